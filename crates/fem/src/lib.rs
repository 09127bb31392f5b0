//! # signorini-fem
//!
//! A bar's matrices, assembled and checked against what they must be:
//!
//! ```
//! use signorini_fem::{Bar, BarMass, RightEnd};
//!
//! // A bar of length 1 in 4 P1 elements (h = 1/4), wave speed 1, free at
//! // x = L: 5 unknowns, the contact node 0 first.
//! let bar = Bar::new(1.0, 4, 1.0, RightEnd::Free)?;
//! assert_eq!(bar.dofs(), 5);
//! let close = |a: f64, b: f64| (a - b).abs() <= 1e-14;
//!
//! // The consistent mass carries the whole mass ρL = 1 (ρ = 1); the lumped one
//! // puts h/2 on the end nodes and h on the others.
//! assert!(close(bar.mass(BarMass::Std).total(), 1.0));
//! assert_eq!(bar.mass(BarMass::Lumped).diagonal(0), [0.125, 0.25, 0.25, 0.25, 0.125]);
//! // `mod` takes the mass off the element [0, h]: the contact node is
//! // massless and the bar keeps L - h.
//! let m_mod = bar.mass(BarMass::Mod);
//! assert_eq!(m_mod.get(0, 0), 0.0);
//! assert!(close(m_mod.total(), 0.75));
//!
//! // A free-free bar moves rigidly without strain: K 1 = 0, every row sums to 0.
//! let mut k1 = vec![f64::NAN; 5];
//! bar.stiffness().mul_vec(&[1.0; 5], &mut k1);
//! assert!(k1.iter().all(|r| r.abs() <= 1e-12));
//!
//! // Clamped at x = 1 under the load f = 1: K u = F gives the nodal values of
//! // -u'' = 1, u'(0) = 0, u(1) = 0, i.e. u = (1 - x²)/2 (P1 is nodally exact
//! // in 1D), through the banded LDLᵀ factorisation.
//! let clamped = Bar::new(1.0, 4, 1.0, RightEnd::Clamped)?;
//! let mut u = clamped.load(|_| 1.0);
//! clamped.stiffness().factor()?.solve_in_place(&mut u);
//! for (i, ui) in u.iter().enumerate() {
//!     let x = clamped.node(i);
//!     assert!((ui - (1.0 - x * x) / 2.0).abs() <= 1e-12, "node {i}: {ui}");
//! }
//! # Ok::<(), signorini_fem::FemError>(())
//! ```
//!
//! Finite-element matrices for one-dimensional dynamic contact problems:
//! the P1 bar of docs/theory.md §2.1 with every mass treatment of the
//! mass-redistribution literature ([`BarMass`]), symmetric banded storage
//! ([`SymBand`]) and its LDLᵀ factorisation ([`BandLdlt`]), done once per run
//! and applied in place; the Hermite-cubic beam of docs/theory.md §2.2 ([`Beam`]) and
//! the largest generalized eigenvalue of `(K, M)` that fixes exact
//! stability limits, certified from above in O(n)
//! ([`max_generalized_eigenvalue_bound`]: the closed form of the uniform P1
//! bar, Lanczos with an inertia test otherwise).
//!
//! Architecture invariant: no IO, no time stepping, no contact logic; only
//! matrices, vectors and their algebra. Usable on its own.

mod band;
mod bar;
pub mod beam;
mod eigen;

pub use band::{BandLdlt, SymBand};
pub use bar::{lagrange, Bar, BarMass, RightEnd};
pub use beam::Beam;
pub use eigen::{
    lanczos_top, max_generalized_eigenvalue, max_generalized_eigenvalue_auto, max_generalized_eigenvalue_bound, max_generalized_eigenvalue_lanczos, uniform_p1_max_eigenvalue, KappaBound, Ritz,
    LANCZOS_STEPS,
};

/// The largest number of elements a mesh accepts (2^40): beyond it sizes
/// such as `2 (m + 1)` are no longer safely addressable. Memory runs out
/// long before; the command-line tools refuse sizes beyond the machine's
/// memory with an estimate before building anything.
pub const MAX_ELEMENTS: usize = 1 << 40;

/// Errors of this crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FemError {
    /// A parameter outside its allowed range.
    #[error("invalid {field} = {value}: allowed {allowed}")]
    Invalid {
        /// The parameter's name.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A mass treatment that does not generalise to these contact nodes.
    #[error("mass {mass} with a contact at node {node}: refused, {why}")]
    MassAtContacts {
        /// The mass treatment.
        mass: &'static str,
        /// The node concerned.
        node: usize,
        /// Why, in words.
        why: &'static str,
    },
    /// A mass treatment not defined at this element degree.
    #[error("mass {mass} at degree {degree}: refused, allowed std, lumped, mod or mod1 at degree 2 and 3")]
    MassForDegree {
        /// The mass treatment.
        mass: &'static str,
        /// The element degree.
        degree: usize,
    },
    /// A mass variant name that does not exist.
    #[error("unknown mass variant {0:?}: allowed std, lumped, mod, mod1, mod2, mod3, transfer, singular")]
    UnknownMass(String),
    /// The factorisation met a non-positive pivot.
    #[error("matrix is not positive definite (pivot {pivot} = {value})")]
    NotPositiveDefinite {
        /// Index of the failing pivot.
        pivot: usize,
        /// Its value.
        value: f64,
    },
}
