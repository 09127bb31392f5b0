//! # Event-driven reference (docs/theory.md §9)
//!
//! Exact dynamics of `M q'' + C q' + K q = f(t)` with unilateral contacts
//! `lo_i <= q_{c_i} <= hi_i`. Between events every model of the workspace is
//! linear, so its flow has a closed form: [`ModalFlow`] advances a state
//! `(q, v)` over any interval exactly (to round-off) by the modal
//! decomposition of the pencil `(K, M)` with classical damping (Rayleigh
//! `C = a M + b K` among them), and the exact particular solution of each
//! load term (a constant, sums of harmonics `A sin(Ω t + p)`, the resonant
//! case included; a piecewise-linear series is a constant plus a ramp on
//! each piece, which [`EventDriven`] takes piece by piece).
//!
//! A mass-spring pair `m q'' + k q = 0` released from `q = 1` is `cos(t)`:
//!
//! ```
//! use signorini_fem::SymBand;
//! use signorini_schemes::events::ModalFlow;
//! use signorini_schemes::{Bounds, Contact, Dynamics};
//!
//! let (m, k) = (SymBand::from_diagonal(&[2.0]), SymBand::from_diagonal(&[2.0]));
//! let dy = Dynamics::new(m, k, vec![0.0], vec![Contact::new(0, Bounds::obstacle(-10.0), false)]);
//! let flow = ModalFlow::new(&dy)?;
//! let (mut q, mut v) = (vec![0.0], vec![0.0]);
//! flow.advance(0.0, &[1.0], &[0.0], 1.0, &mut q, &mut v);
//! assert!((q[0] - 1f64.cos()).abs() < 1e-15 && (v[0] + 1f64.sin()).abs() < 1e-15);
//! # Ok::<(), signorini_schemes::events::EventsError>(())
//! ```
//!
//! Every event — a contact reaching a bound, a held contact's force
//! reaching zero — is located by a step rule that cannot miss it
//! (docs/theory.md §9.2). [`EventDriven`] runs a structure event by event:
//! impacts by Newton's law on every contact at once (the velocity LCP on the
//! Delassus matrix), held phases on the pencil with the held dofs removed,
//! releases, and accumulations of impacts (chattering) passed to the held
//! phase at their limit. [`EventStepper`] is the registry's `event-driven`
//! scheme: the same run sampled at the output times.
//!
//! A damping that the modes of `(K, M)` do not diagonalise takes the
//! first-order form (docs/theory.md §9.1): a real basis of invariant planes
//! of `[0 I; −M⁻¹K −M⁻¹C]` in which each mode obeys the same scalar
//! equation. Massless contact dofs (mass redistribution, reduced models)
//! are statically condensed: they land and leave without impacts. *Not
//! here*: a defective first-order form (refused), a restitution above 0
//! at a massless contact (refused).

mod driven;
mod flow;
mod record;
mod search;
mod stepper;

pub use driven::{bases_built, Condensation, EventDriven, FlowBases, Reached, MAX_EVENTS};
#[doc(hidden)]
pub use flow::{critical_plane, defective_chain, repeated_line, repeated_planes, slow_plane};
pub use flow::{Event, ModalFlow};
pub use record::{EventKind, EventRecord, EventsError};
pub use stepper::EventStepper;
pub(crate) use stepper::EVENT_DRIVEN;

/// Which bound of a contact dof a trajectory reaches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bound {
    /// `q_c = lo`, approached from above.
    Lower,
    /// `q_c = hi`, approached from below.
    Upper,
}
