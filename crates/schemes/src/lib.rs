//! # signorini-schemes
//!
//! A 3-dof spring–mass chain thrown at a stop, stepped by Paoli–Schatzman
//! with restitution 0: the bound holds at every level and the energy never
//! rises above its start:
//!
//! ```
//! use signorini_fem::SymBand;
//! use signorini_schemes::{Active, Bounds, Contact, Dynamics, Initial, SchemeSpec};
//!
//! // Unit masses 0 - 1 - 2 in a chain of unit springs, mass 2 tied to a wall,
//! // a stop 0.1 below mass 0 (u_0 >= -0.1).
//! let (mut m, mut k) = (SymBand::zeros(3, 1), SymBand::zeros(3, 1));
//! for i in 0..3 {
//!     m.set(i, i, 1.0);
//! }
//! for (i, j, v) in [(0, 0, 1.0), (1, 0, -1.0), (1, 1, 2.0), (2, 1, -1.0), (2, 2, 2.0)] {
//!     k.set(i, j, v);
//! }
//! let lo = -0.1;
//! let dy = Dynamics::new(m, k, vec![0.0; 3], vec![Contact::new(0, Bounds::obstacle(lo), false)]);
//! // Mass 0 thrown down at speed 1: energy ½ · 1² = 0.5.
//! let init = Initial { u: vec![0.0; 3], v: vec![-1.0, 0.0, 0.0] };
//! let mut s = "ps-e0".parse::<SchemeSpec>()?.build(dy, 0.01, &init)?;
//! let (mut e_start, mut e_end, mut contact_steps) = (None, f64::NAN, 0);
//! for _ in 0..1000 {
//!     let r = s.step()?;
//!     // The bound holds exactly (the projection puts u_0 on it).
//!     assert!(s.displacement()[0] >= lo);
//!     contact_steps += usize::from(r.active == Active::Lower);
//!     if let Some((_, e)) = s.energy() {
//!         let e0 = *e_start.get_or_insert(e);
//!         assert!(e <= e0 * (1.0 + 1e-12), "energy {e} above its start {e0}");
//!         e_end = e;
//!     }
//! }
//! let e_start = e_start.unwrap();
//! assert!((e_start - 0.5).abs() < 1e-3);
//! // The stop was hit, and the inelastic impacts took energy away.
//! assert!(contact_steps > 0);
//! assert!(e_end < 0.9 * e_start);
//! # Ok::<(), signorini_schemes::SchemeError>(())
//! ```
//!
//! Time integrators for the semi-discrete contact problem
//!
//! ```text
//! M U'' + K U = F - λ e_c,    lo <= u_c <= hi,   λ >= 0 ⊥ ... (docs/theory.md §3, §4)
//! ```
//!
//! optionally with a viscous damping `C U'` on the left ([`Dynamics::damping`];
//! [`OneStep`], [`PaoliSchatzman`], [`MoreauJean`]) and `F(t)` a steady load
//! plus any number of separable terms `shape_j s_j(t)` ([`Dynamics::forcing`]).
//!
//! (bar notation: `λ = c² u_x(0, t) <= 0` enters as `-λ e_0`; a lower bound is
//! pushed up by `-λ >= 0`). Every scheme solves, each step, `A x = b + μ e_c`
//! with one matrix `A` factorised once ([`signorini_fem::BandLdlt`]) and the
//! closed-form projection of [`signorini_contact::Projection`]; the hot loop
//! allocates nothing.
//!
//! * [`OneStep`]: Newmark(β, γ) (2017 paper eq. (30)) and the θ-method
//!   (eq. (32)) in momentum form `P = M V`, `R = M A`, so a massless contact
//!   node (the MOD mass family) needs no special case.
//! * [`PaoliSchatzman`]: the two-step scheme with restitution `e` (eq. (34)),
//!   started by one [`OneStep`] Newmark(β, 1/2) step.
//!   [`PaoliSchatzmanLockstep`] steps `L` runs that share its step matrix
//!   together (a sweep), each lane bit-identical to its single run;
//!   [`MoreauJeanLockstep`], [`NsgaLockstep`], [`ContactStabilizedLockstep`],
//!   [`CdLagrangeLockstep`] and [`MoreauJeanCombinedLockstep`] do the same
//!   for [`MoreauJean`], [`Nsga`], [`ContactStabilized`], [`CdLagrange`]
//!   and [`MoreauJeanCombined`] (all six behind the [`Lockstep`] trait, on
//!   one lane state; [`LockstepScheme`] says which engine a registry
//!   scheme takes). [`LockstepBatch`] is their one non-generic entry (the
//!   scheme and the width chosen at run time, every engine compiled once
//!   here), the one the sweep and the tests take.
//!
//! * [`Reduced`]: the massless contact node eliminated (`u_0 = max(u_1, g)`),
//!   with the hybrid Crank–Nicolson/midpoint scheme of the weighted-mass paper
//!   (energy never increases) or Crank–Nicolson on the reduced ODE.
//!
//! [`SchemeSpec`] names the presets of docs/theory.md §4.8 and builds a boxed
//! [`Stepper`]; the time loop itself lives in `signorini-run`.
//!
//! Architecture invariant: no IO, no exact solutions; depends on
//! `signorini-fem` (matrices, factorisation) and `signorini-contact`.

/// The accessors every stepper implements the same way, from its fields
/// `label`, `dt`, `n` (level), `u` (displacement), `dy` (the problem),
/// `lams` and `acts` (per-contact force and status of the last step).
macro_rules! stepper_accessors {
    () => {
        fn label(&self) -> String {
            self.label.clone()
        }
        fn dt(&self) -> f64 {
            self.dt
        }
        fn level(&self) -> usize {
            self.n
        }
        fn displacement(&self) -> &[f64] {
            &self.u
        }
        fn dynamics(&self) -> &crate::Dynamics {
            &self.dy
        }
        fn contact_forces(&self) -> &[f64] {
            &self.lams
        }
        fn contact_status(&self) -> &[signorini_contact::Active] {
            &self.acts
        }
    };
}

/// [`Stepper::state`] and [`Stepper::set_state`] of a scheme whose state is
/// its displacement and velocity, `U ++ V` (fields `u`, `v`); with a method
/// name, `set_state` then calls it to rebuild what the scheme derives from
/// them.
macro_rules! displacement_velocity_state {
    ($($then:ident)?) => {
        fn state(&self) -> Option<Vec<f64>> {
            Some(self.u.iter().chain(&self.v).copied().collect())
        }
        fn set_state(&mut self, s: &[f64]) -> Result<(), crate::SchemeError> {
            let n = self.u.len();
            crate::check_state_len(s, 2 * n)?;
            self.u.copy_from_slice(&s[..n]);
            self.v.copy_from_slice(&s[n..]);
            $(self.$then();)?
            Ok(())
        }
    };
}

/// The [`Stepper`] methods of a scheme that wraps another in its field
/// `$inner` (a Moreau–Jean variant around [`MoreauJean`]): everything but
/// `step` and `energy`, which the wrapper writes.
macro_rules! delegate_stepper {
    ($inner:ident) => {
        fn label(&self) -> String {
            self.$inner.label()
        }
        fn dt(&self) -> f64 {
            self.$inner.dt()
        }
        fn level(&self) -> usize {
            self.$inner.level()
        }
        fn displacement(&self) -> &[f64] {
            self.$inner.displacement()
        }
        fn dynamics(&self) -> &crate::Dynamics {
            self.$inner.dynamics()
        }
        fn contact_forces(&self) -> &[f64] {
            self.$inner.contact_forces()
        }
        fn contact_status(&self) -> &[signorini_contact::Active] {
            self.$inner.contact_status()
        }
        fn contact_pivots(&self) -> Option<(u64, u64)> {
            self.$inner.contact_pivots()
        }
        fn state(&self) -> Option<Vec<f64>> {
            self.$inner.state()
        }
        fn set_state(&mut self, s: &[f64]) -> Result<(), crate::SchemeError> {
            self.$inner.set_state(s)
        }
    };
}

mod batch;
mod cd_lagrange;
mod cd_lockstep;
mod combined_lockstep;
mod d1_lockstep;
mod d1minus;
pub mod events;
mod family;
mod fused;
mod hybrid;
mod lanes;
mod loads;
mod lockstep;
mod moreau;
mod moreau_combined;
mod moreau_lockstep;
mod moreau_projected;
mod multi;
mod nitsche;
mod nsga;
mod nsga_lockstep;
mod onestep;
mod paoli;
mod profile;
mod registry;
mod stabilized;
mod stabilized_lockstep;
mod verlet_nitsche;

pub use batch::{ImpactParts, LaneVector, LockstepBatch, LOCKSTEP_WIDTHS};
pub use cd_lagrange::CdLagrange;
pub use cd_lockstep::CdLagrangeLockstep;
pub use combined_lockstep::MoreauJeanCombinedLockstep;
pub use d1_lockstep::D1MinusLinearLockstep;
pub use d1minus::{D1Level, D1MinusLinear, INDEX_SET_TOLERANCE as D1_INDEX_SET_TOLERANCE};
pub use family::{BuildFn, Capabilities, Family, Group, Node, Param, Preset, SchemeSpec, MAX_PARAMS};
pub use hybrid::{Reduced, ReducedLaw};
pub use lanes::{LaneResults, Lockstep, LockstepLane};
pub use lockstep::{LockstepScheme, PaoliSchatzmanLockstep};
pub use moreau::MoreauJean;
pub use moreau_combined::{MoreauJeanCombined, COMBINED_TOLERANCE};
pub use moreau_lockstep::MoreauJeanLockstep;
pub use moreau_projected::{MoreauJeanProjected, INDEX_SET_THRESHOLD, PROJECTION_TOLERANCE};
#[doc(hidden)]
pub use multi::MultiSolve;
pub use nitsche::Nitsche;
pub use nsga::{chung_hulbert, Nsga};
pub use nsga_lockstep::NsgaLockstep;
pub use onestep::{OneStep, OneStepParams};
pub use paoli::PaoliSchatzman;
pub use profile::{Harmonic, ProfileError, Psd, RandomSpec, Sampler, Series, SplitMix64, TimeProfile, MAX_RANDOM_COUNT};
pub use registry::{families_with, syntax_list, FAMILIES};
/// The status of a contact (re-exported from signorini-contact).
pub use signorini_contact::Active;
pub use stabilized::ContactStabilized;
pub use stabilized_lockstep::ContactStabilizedLockstep;
pub use verlet_nitsche::VerletNitsche;

use signorini_contact::ContactError;
use signorini_fem::{FemError, SymBand};

/// Errors of this crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SchemeError {
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
    /// An unknown scheme name.
    #[error("unknown scheme {name:?}: allowed {allowed}")]
    UnknownScheme {
        /// The name given.
        name: String,
        /// Every way to write a scheme (from the registry).
        allowed: String,
    },
    /// The scheme does not take this part of the problem; `by` names the
    /// schemes that do (from the registry).
    #[error("unsupported structure: {scheme} takes no {what}{why}: allowed {by}")]
    NotTaken {
        /// The scheme.
        scheme: String,
        /// What it does not take (`damping matrix`, `several contacts`).
        what: &'static str,
        /// Why, in words (may be empty; starts with a space).
        why: &'static str,
        /// The schemes that take it.
        by: String,
    },
    /// Vectors or matrices of inconsistent sizes.
    #[error("size mismatch: {what} has {got} entries, expected {expected}")]
    Size {
        /// Which input.
        what: &'static str,
        /// Its size.
        got: usize,
        /// The expected size.
        expected: usize,
    },
    /// The scheme cannot use this mass treatment.
    #[error("scheme {scheme} needs {needs}")]
    MassNotSupported {
        /// The scheme.
        scheme: String,
        /// What it needs, in words.
        needs: &'static str,
    },
    /// A massless node that is not the contact dof 0, or similar structure errors.
    #[error("unsupported structure: {0}")]
    Structure(&'static str),
    /// The scheme's matrix could not be factorised.
    #[error("factorisation failed: {0}")]
    Factor(#[from] FemError),
    /// The contact projection could not be set up.
    #[error("contact: {0}")]
    Contact(#[from] ContactError),
    /// An explicit scheme asked to run at or beyond its stability limit.
    #[error("dt = {dt} is at or beyond the exact stability limit {limit:.6e} of {scheme} ({rule}): allowed dt < {limit:.6e}")]
    Unstable {
        /// The time step asked for.
        dt: f64,
        /// The exact critical time step.
        limit: f64,
        /// The scheme.
        scheme: String,
        /// How the limit is computed for this scheme, in words.
        rule: &'static str,
    },
    /// A penalty so stiff that the step's scalar contact equation loses
    /// every digit in floating point (its spring dwarfs the structure's own
    /// compliance at the contact dof by more than 1e12).
    #[error("{field} = {value:e} makes the contact law ill-posed in floating point at this mesh and dt (the spring is more than 1e12 times stiffer than the structure at the contact dof, so the step's contact equation has no digits left); usable range: 0 < {field} <= {max:.3e}")]
    PenaltyTooStiff {
        /// The parameter (`gamma_p`, `penalty stiffness`).
        field: &'static str,
        /// Its value.
        value: f64,
        /// The largest usable value for this mesh and dt.
        max: f64,
    },
    /// The state became non-finite (NaN or infinity).
    #[error("state became non-finite at step {step} (t = {time})")]
    NonFinite {
        /// The step that produced it.
        step: usize,
        /// Its time.
        time: f64,
    },
    /// A step stopped early by the poll of [`Stepper::set_interrupt`]: the
    /// stepper is still at level `step` (its state that level's).
    #[error("interrupted at step {step} (t = {time})")]
    Interrupted {
        /// The level kept.
        step: usize,
        /// Its time.
        time: f64,
    },
    /// The event-driven reference refused the problem or stopped.
    #[error("event-driven: {0}")]
    Events(#[from] events::EventsError),
}

/// The exact critical time step of the two-step β-scheme (Paoli–Schatzman's
/// linear part) on a pencil whose largest generalized eigenvalue is `kappa`:
/// `2 / sqrt((1 - 4β) κ)` for β < 1/4 (`2/sqrt(κ)` at β = 0, the central
/// difference), `∞` for β >= 1/4 (unconditionally stable: the discrete
/// energy splits into a nonnegative quadratic form, and the projection only
/// removes energy). With a massless node (`κ = ∞`) every β < 1/4 is unstable
/// (limit 0): the massless row's recurrence has a root of modulus > 1.
pub fn beta_scheme_critical_dt(beta: f64, kappa: f64) -> f64 {
    if beta >= 0.25 {
        f64::INFINITY
    } else {
        2.0 / ((1.0 - 4.0 * beta) * kappa).sqrt()
    }
}

/// Bounds on the contact dof: `lo <= u_c <= hi` (`hi = +∞` for a one-sided
/// obstacle at gap `lo`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Lower bound (obstacle position `g`, or the lower stop `g1`).
    pub lo: f64,
    /// Upper bound (`+∞`, or the upper stop `g2`).
    pub hi: f64,
}

impl Bounds {
    /// A one-sided obstacle at `gap`.
    pub fn obstacle(gap: f64) -> Self {
        Self { lo: gap, hi: f64::INFINITY }
    }
}

/// A separable time-dependent load term `shape · s(t)` (on top of the steady
/// load; [`Dynamics::forcing`] sums several).
#[derive(Clone, Debug, PartialEq)]
pub struct Forcing {
    /// The spatial load vector.
    pub shape: Vec<f64>,
    /// Its time profile.
    pub time: TimeProfile,
}

/// How the contact condition on `u_c` is enforced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactLaw {
    /// Exactly, by the projection of docs/theory.md §3 (`lo <= u_c <= hi`).
    Projection,
    /// Penalty / normal compliance: a spring of stiffness `stiffness` (per
    /// unit `ρS`) acts outside `[lo, hi]`: force `κ (lo - u)⁺ - κ (u - hi)⁺`,
    /// solved exactly each step as a piecewise-linear scalar equation.
    Penalty {
        /// Spring stiffness `κ` (> 0), in the scaled equation's units.
        stiffness: f64,
    },
}

/// One constrained dof: `lo <= u_dof <= hi`, with the contact law's
/// per-contact parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Contact {
    /// The constrained dof.
    pub dof: usize,
    /// Its bounds.
    pub bounds: Bounds,
    /// Whether the dof carries no mass (its rows of `M` are zero; it then
    /// evolves quasi-statically: `(K U)_c = F_c - λ`).
    pub massless: bool,
    /// The restitution coefficient of this contact, overriding the scheme's
    /// (Paoli–Schatzman, Moreau–Jean); `None`: the scheme's.
    pub restitution: Option<f64>,
    /// The penalty stiffness of this stop, overriding the law's; `None`:
    /// the law's.
    pub stiffness: Option<f64>,
}

impl Contact {
    /// A contact with the scheme's restitution and stiffness.
    pub fn new(dof: usize, bounds: Bounds, massless: bool) -> Self {
        Self { dof, bounds, massless, restitution: None, stiffness: None }
    }

    /// With its own restitution coefficient (`None`: the scheme's; [`Contact::restitution`]).
    pub fn with_restitution(mut self, restitution: Option<f64>) -> Self {
        self.restitution = restitution;
        self
    }

    /// With its own penalty stiffness (`None`: the scheme's; [`Contact::stiffness`]).
    pub fn with_stiffness(mut self, stiffness: Option<f64>) -> Self {
        self.stiffness = stiffness;
        self
    }
}

/// The semi-discrete problem a scheme integrates (scheme-agnostic):
/// [`Dynamics::new`], then [`with_forcing`](Dynamics::with_forcing) and
/// [`with_damping`](Dynamics::with_damping) (the fields stay public).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Dynamics {
    /// Mass matrix `M` (rows/columns of massless contacts zero).
    pub mass: SymBand,
    /// Stiffness matrix `K`.
    pub stiffness: SymBand,
    /// Steady load vector `F` (time-independent).
    pub load: Vec<f64>,
    /// The constrained dofs (at least one), in stop order. With one, every
    /// scheme uses the closed-form projection; with several, the exact
    /// multi-contact solve ([`signorini_contact::MultiProjection`]).
    pub contacts: Vec<Contact>,
    /// Time-dependent loads added to `load`: `F(t) = load + Σ_j shape_j s_j(t)`
    /// (empty: the steady load only).
    pub forcing: Vec<Forcing>,
    /// Viscous damping matrix `C` (symmetric, positive semi-definite, half-bandwidth
    /// at most `M`'s; rows of massless contacts zero): `M U'' + C U' + K U = F - Σ λ_i e_{c_i}`.
    /// `None`: undamped. Taken by [`OneStep`] (implicit steps), [`PaoliSchatzman`]
    /// and [`MoreauJean`]; [`Reduced`] and [`Nitsche`] refuse it.
    pub damping: Option<SymBand>,
}

impl Dynamics {
    /// `M U'' + K U = load - Σ λ_i e_{c_i}` with `contacts`: no
    /// time-dependent load, undamped.
    pub fn new(mass: SymBand, stiffness: SymBand, load: Vec<f64>, contacts: Vec<Contact>) -> Self {
        Self { mass, stiffness, load, contacts, forcing: Vec::new(), damping: None }
    }

    /// With the time-dependent loads `forcing` ([`Dynamics::forcing`]).
    pub fn with_forcing(mut self, forcing: Vec<Forcing>) -> Self {
        self.forcing = forcing;
        self
    }

    /// With the viscous damping matrix `C` (`None`: undamped; [`Dynamics::damping`]).
    pub fn with_damping(mut self, damping: Option<SymBand>) -> Self {
        self.damping = damping;
        self
    }

    /// The mechanical energy `½ vᵀ M v + ½ uᵀ K u − Fᵀ u` of the state
    /// `(u, v)` (the steady load's potential; the schemes that carry their
    /// own velocity report it).
    pub fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        let load: f64 = self.load.iter().zip(u).map(|(f, u)| f * u).sum();
        0.5 * self.mass.quad_form(v) + 0.5 * self.stiffness.quad_form(u) - load
    }

    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.mass.n()
    }

    /// The first contact (the only one of a single-contact problem).
    pub fn contact(&self) -> &Contact {
        &self.contacts[0]
    }

    /// Number of contacts.
    pub fn k(&self) -> usize {
        self.contacts.len()
    }

    /// Whether the contacts are massless (all of them; see [`validate`](Self::validate)).
    pub fn massless_contact(&self) -> bool {
        self.contacts.first().is_some_and(|c| c.massless)
    }

    /// Checks sizes and structure: at least one contact, distinct dofs in
    /// range, valid bounds, every contact massless or every one massive,
    /// and a massless contact's rows of `M` zero.
    pub fn validate(&self) -> Result<(), SchemeError> {
        let n = self.n();
        for (what, got) in [("stiffness", self.stiffness.n()), ("load", self.load.len())] {
            if got != n {
                return Err(SchemeError::Size { what, got, expected: n });
            }
        }
        if self.contacts.is_empty() {
            return Err(SchemeError::Structure("at least one contact is needed"));
        }
        let massless = self.contacts[0].massless;
        for (i, c) in self.contacts.iter().enumerate() {
            if c.dof >= n {
                return Err(SchemeError::Size { what: "contact dof", got: c.dof, expected: n });
            }
            if self.contacts[..i].iter().any(|d| d.dof == c.dof) {
                return Err(SchemeError::Contact(signorini_contact::ContactError::DuplicateDof(c.dof)));
            }
            if c.massless != massless {
                return Err(SchemeError::Structure("every contact must be massless, or every one massive (one mass treatment for all contact nodes)"));
            }
            if c.massless {
                let p = self.mass.half_bandwidth();
                if (c.dof.saturating_sub(p)..(c.dof + p + 1).min(n)).any(|j| self.mass.get(c.dof, j) != 0.0) {
                    return Err(SchemeError::Structure("a massless contact's row of M must be zero"));
                }
            }
            signorini_contact::check_bounds(c.bounds.lo, c.bounds.hi)?;
            if let Some(e) = c.restitution {
                if !(0.0..=1.0).contains(&e) {
                    return Err(SchemeError::Invalid { field: "restitution", value: e, allowed: "[0, 1]" });
                }
            }
            if let Some(k) = c.stiffness {
                if !(k > 0.0 && k.is_finite()) {
                    return Err(SchemeError::Invalid { field: "penalty stiffness", value: k, allowed: "finite and > 0" });
                }
            }
        }
        if self.contacts.len() == 1 && massless && self.contacts[0].dof != 0 {
            return Err(SchemeError::Structure("a single massless contact node must be dof 0"));
        }
        for f in &self.forcing {
            if f.shape.len() != n {
                return Err(SchemeError::Size { what: "forcing shape", got: f.shape.len(), expected: n });
            }
        }
        if let Some(c) = &self.damping {
            if c.n() != n {
                return Err(SchemeError::Size { what: "damping matrix", got: c.n(), expected: n });
            }
            let (p, pm) = (c.half_bandwidth(), self.mass.half_bandwidth());
            if p > pm {
                return Err(SchemeError::Size { what: "damping half-bandwidth (at most the mass matrix's, so the step matrix keeps its band)", got: p, expected: pm });
            }
            for i in 0..n {
                for j in i.saturating_sub(p)..=i {
                    let v = c.get(i, j);
                    if !v.is_finite() {
                        return Err(SchemeError::Invalid { field: "damping entry", value: v, allowed: "finite" });
                    }
                }
                let d = c.get(i, i);
                if d < 0.0 {
                    return Err(SchemeError::Invalid { field: "damping diagonal", value: d, allowed: ">= 0 (C positive semi-definite)" });
                }
            }
            for ct in self.contacts.iter().filter(|ct| ct.massless) {
                if (ct.dof.saturating_sub(p)..(ct.dof + p + 1).min(n)).any(|j| c.get(ct.dof, j) != 0.0) {
                    return Err(SchemeError::Structure("a massless contact's row of the damping matrix C must be zero (the node has no velocity of its own)"));
                }
            }
        }
        Ok(())
    }

    /// The step matrix `M + c_coef C + k_coef K` (`M + k_coef K` exactly as
    /// before when undamped; `C` widened to `M`'s band).
    pub(crate) fn step_matrix(&self, c_coef: f64, k_coef: f64) -> SymBand {
        let a = self.mass.lin_comb(1.0, &self.stiffness, k_coef);
        match &self.damping {
            None => a,
            Some(c) => {
                let (n, p) = (a.n(), a.half_bandwidth());
                let mut w = SymBand::zeros(n, p);
                for i in 0..n {
                    for j in i.saturating_sub(c.half_bandwidth())..=i {
                        w.set(i, j, c.get(i, j));
                    }
                }
                a.lin_comb(1.0, &w, c_coef)
            }
        }
    }

    /// `F(t)` = steady load + forcing at `t`, into `out`.
    pub fn load_at(&self, t: f64, out: &mut [f64]) {
        out.copy_from_slice(&self.load);
        self.add_forcing(t, out);
    }

    /// The time-dependent part of the load alone, `Σ_j shape_j s_j(t)`, into `out`.
    pub fn forcing_at(&self, t: f64, out: &mut [f64]) {
        out.iter_mut().for_each(|o| *o = 0.0);
        self.add_forcing(t, out);
    }

    fn add_forcing(&self, t: f64, out: &mut [f64]) {
        for f in &self.forcing {
            let s = f.time.value(t);
            out.iter_mut().zip(&f.shape).for_each(|(o, g)| *o += s * g);
        }
    }

    /// An energy scale of the loads over a horizon `T`, never zero when a
    /// load is: the kinetic energy `(f T)² / (2 m)` that the largest total
    /// load `f = Σ|F_i| + Σ_j max|s_j|·Σ_i|shape_{j,i}|` gives the total mass
    /// `m = Σ_ij M_ij` in free flight over `T`. The runner's energy-growth
    /// guard uses `max(|E(0)|, this)`, so a system that starts at rest
    /// (E(0) = 0) under a load is not reported as a blow-up.
    pub fn load_energy_scale(&self, t_end: f64) -> f64 {
        let mut f: f64 = self.load.iter().map(|x| x.abs()).sum();
        for fo in &self.forcing {
            f += fo.time.max_abs() * fo.shape.iter().map(|x| x.abs()).sum::<f64>();
        }
        let m = self.mass.total();
        if f == 0.0 || !(m > 0.0) {
            return 0.0;
        }
        (f * t_end).powi(2) / (2.0 * m)
    }

    /// First massive dof of a single-contact problem (its massless contact
    /// node, if any, is dof 0).
    pub(crate) fn massive_start(&self) -> usize {
        usize::from(self.massless_contact() && self.k() == 1)
    }

    /// The factor of `M` on the massive dofs, for kinetic energies and
    /// velocities: the trailing block past a massless dof 0 (one contact),
    /// or `M` with a unit diagonal on every massless contact row (several:
    /// those rows and columns are zero, so the unit entries decouple).
    pub(crate) fn massive_factor(&self) -> Result<signorini_fem::BandLdlt, SchemeError> {
        if self.k() == 1 || !self.massless_contact() {
            return Ok(self.mass.trailing(self.massive_start()).factor()?);
        }
        let mut m = self.mass.clone();
        for c in &self.contacts {
            m.set(c.dof, c.dof, 1.0);
        }
        Ok(m.factor()?)
    }
}

/// The initial state `U^0`, `V^0`.
#[derive(Clone, Debug, PartialEq)]
pub struct Initial {
    /// Displacement.
    pub u: Vec<f64>,
    /// Velocity.
    pub v: Vec<f64>,
}

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepReport {
    /// Index of the new time level.
    pub n: usize,
    /// Its time `t_n = n dt`.
    pub t: f64,
    /// Contact 0's force (every contact's: [`Stepper::contact_forces`]):
    /// the contact force the step produced and the time it belongs to
    /// (`t_{n}` for Newmark/θ; `t_{n-1}` for Paoli–Schatzman with a massive
    /// contact node, `t_n` with a massless one), or `None` for a start step
    /// whose force is not part of the scheme's sequence.
    pub lambda: Option<(f64, f64)>,
    /// Whether the constraint of contact 0 was active (every contact's
    /// status: [`Stepper::contact_status`]).
    pub active: signorini_contact::Active,
}

/// A poll a long step calls to learn whether it should stop early (the
/// runner hands one over [`Stepper::set_interrupt`]: its cancel token's
/// flag). It must be cheap; a step calls it at bounded intervals of its own
/// work (the event-driven scheme: every 256 steps of its event searches).
pub type Interrupt = std::sync::Arc<dyn Fn() -> bool + Send + Sync>;

/// A time integrator: one step at a time (the loop lives in the runner).
pub trait Stepper: Send {
    /// Human-readable name with parameters.
    fn label(&self) -> String;
    /// Time step.
    fn dt(&self) -> f64;
    /// Index `n` of the current time level.
    fn level(&self) -> usize;
    /// Current time `n dt`.
    fn time(&self) -> f64 {
        self.level() as f64 * self.dt()
    }
    /// Current displacement `U^n`.
    fn displacement(&self) -> &[f64];
    /// The semi-discrete problem being integrated.
    fn dynamics(&self) -> &Dynamics;
    /// Advances one step.
    fn step(&mut self) -> Result<StepReport, SchemeError>;
    /// The force `λ_i` of every contact after the last step, in contact
    /// order, at the time of the report's `lambda` (the report holds
    /// contact 0's); zeros before the first step.
    fn contact_forces(&self) -> &[f64];
    /// Which bound holds each contact after the last step.
    fn contact_status(&self) -> &[signorini_contact::Active];
    /// Several contacts: the steps whose contact solve pivoted (something
    /// violated or held) and their pivots (linear solves on the active
    /// set) so far; `None` for a single contact (closed form).
    fn contact_pivots(&self) -> Option<(u64, u64)> {
        None
    }
    /// The scheme's natural discrete energy and the time it belongs to
    /// (`t_n` for one-step schemes, `t_{n-1/2}` for Paoli–Schatzman), with
    /// the load potential `-Fᵀ U`. `None` before the first step of a
    /// two-step scheme.
    fn energy(&mut self) -> Option<(f64, f64)>;
    /// Work done so far by the time-dependent load and by the contact force
    /// (schemes that keep the discrete energy balance `ΔE = W_f + W_c`), if
    /// the scheme tracks it.
    fn work(&self) -> Option<(f64, f64)> {
        None
    }
    /// Energy dissipated so far by the damping force `C U'` (in the form
    /// that closes the scheme's discrete balance `ΔE = W_f + W_c - D`;
    /// 0 without damping), if the scheme tracks it (those that report
    /// [`work`](Self::work)).
    fn dissipation(&self) -> Option<f64> {
        None
    }
    /// The state the next steps depend on besides the time level, flat:
    /// `U^n` (`n` entries), then a velocity `V^n` (`n` entries: Moreau–Jean's
    /// own, Newmark's `M⁻¹ P^n`, Paoli–Schatzman's backward difference
    /// `(U^n − U^{n−1})/dt`), then any further internal state (Newmark:
    /// `R^n = M A^n`). For twin runs (Lyapunov exponents, `signorini-run`'s
    /// `chaos`). `None`: the scheme does not offer it (the default; also a
    /// damped Newmark and the reduced and Nitsche schemes).
    fn state(&self) -> Option<Vec<f64>> {
        None
    }
    /// Replaces the state by `s`, laid out as [`state`](Self::state)
    /// returns it (the time level is kept). Refused by schemes without a
    /// `state`, or for a wrong length.
    fn set_state(&mut self, s: &[f64]) -> Result<(), SchemeError> {
        let _ = s;
        Err(SchemeError::Structure("this scheme does not offer its state (set_state)"))
    }
    /// The caller will ask for [`energy`](Self::energy) after every step
    /// (`on`; the runner does while an observer wants it): a scheme may
    /// then compute it inside the step, where its loops overlap with the
    /// step's, and must give the same bits as without. Ignored by
    /// default (and by every scheme but the bar's Newmark/θ path).
    fn fuse_energy(&mut self, on: bool) {
        let _ = on;
    }
    /// The events so far of an event-driven scheme (`events.csv`);
    /// `None` for time-stepping schemes.
    fn events(&self) -> Option<&[events::EventRecord]> {
        None
    }
    /// The exact run an event-driven scheme samples, taken out of it (an
    /// [`events::EventDriven`] behind `Any`, so that the crate root does not
    /// name the events' driver, which depends on it; the orbits' map starts
    /// its own runs from it: `EventDriven::restart`); `None` for
    /// time-stepping schemes.
    fn into_event_run(self: Box<Self>) -> Option<Box<dyn std::any::Any>> {
        None
    }
    /// A poll for a step whose work is unbounded (the event-driven scheme:
    /// any number of events in one output step): while it returns `true`
    /// the step stops within a bounded amount of work with
    /// [`SchemeError::Interrupted`], the level and its state kept (the
    /// runner checks its token between steps as well). `None` removes it.
    /// Time-stepping schemes, whose step is bounded work, ignore it (the
    /// default).
    fn set_interrupt(&mut self, poll: Option<Interrupt>) {
        let _ = poll;
    }
    /// The run ends at level `n`, at the horizon `t_end` (the runner's,
    /// within 1e-9 of `n dt`): a scheme that samples an exact flow (the
    /// event-driven scheme) reads its level `n` at `t_end` itself, so that
    /// the final state is the flow's at `t_end` whatever `dt` (0.1 × 3 is
    /// 0.30000000000000004). Time-stepping schemes, whose level `n` is
    /// `n dt` by construction, ignore it (the default).
    fn set_end(&mut self, n: usize, t_end: f64) {
        let _ = (n, t_end);
    }
}

/// Checks a stepper's time step (finite, > 0) and its start: the initial
/// displacement and velocity have the problem's `n` entries.
pub(crate) fn check_start(dt: f64, n: usize, init: &Initial) -> Result<(), SchemeError> {
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(SchemeError::Invalid { field: "dt", value: dt, allowed: "finite and > 0" });
    }
    for (what, v) in [("initial displacement", &init.u), ("initial velocity", &init.v)] {
        if v.len() != n {
            return Err(SchemeError::Size { what, got: v.len(), expected: n });
        }
    }
    Ok(())
}

/// The end of a contact scheme's step at level `n`, time `t`: every
/// contact's position `u[dof]` (with `v`, its velocity too) and force
/// `lams[i]` checked finite ([`SchemeError::NonFinite`] otherwise), then
/// the report with contact 0's force `lams[0]` at `t` and status `acts[0]`.
pub(crate) fn contact_step_report(n: usize, t: f64, contacts: &[Contact], u: &[f64], v: Option<&[f64]>, lams: &[f64], acts: &[signorini_contact::Active]) -> Result<StepReport, SchemeError> {
    for (ct, lam) in contacts.iter().zip(lams) {
        let c = ct.dof;
        if !(u[c].is_finite() && v.is_none_or(|v| v[c].is_finite()) && lam.is_finite()) {
            return Err(SchemeError::NonFinite { step: n, time: t });
        }
    }
    Ok(StepReport { n, t, lambda: Some((t, lams[0])), active: acts[0] })
}

/// Checks a state's length for [`Stepper::set_state`].
pub(crate) fn check_state_len(s: &[f64], expected: usize) -> Result<(), SchemeError> {
    if s.len() != expected {
        return Err(SchemeError::Size { what: "state", got: s.len(), expected });
    }
    Ok(())
}
