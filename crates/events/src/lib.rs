//! # signorini-events
//!
//! Exact dynamics of `M q'' + C q' + K q = f(t)` between contact events: the
//! first piece of the event-driven reference (issue 25). Between events every
//! model of the workspace is linear, so its flow has a closed form:
//! [`ModalFlow`] advances a state `(q, v)` over any interval exactly (to
//! round-off) by the modal decomposition of the pencil `(K, M)` with
//! Rayleigh damping `C = a M + b K`, and the exact particular solution of
//! each load term (a constant, sums of harmonics `A sin(Ω t + p)`, the
//! resonant case included).
//!
//! A mass-spring pair `m q'' + k q = 0` released from `q = 1` is `cos(t)`:
//!
//! ```
//! use signorini_fem::SymBand;
//! use signorini_events::ModalFlow;
//! use signorini_schemes::{Bounds, Contact, Dynamics};
//!
//! let (mut m, mut k) = (SymBand::zeros(1, 0), SymBand::zeros(1, 0));
//! m.set(0, 0, 2.0);
//! k.set(0, 0, 2.0);
//! let dy = Dynamics::new(m, k, vec![0.0], vec![Contact::new(0, Bounds::obstacle(-10.0), false)]);
//! let flow = ModalFlow::new(&dy)?;
//! let (mut q, mut v) = (vec![0.0], vec![0.0]);
//! flow.advance(0.0, &[1.0], &[0.0], 1.0, &mut q, &mut v);
//! assert!((q[0] - 1f64.cos()).abs() < 1e-15 && (v[0] + 1f64.sin()).abs() < 1e-15);
//! # Ok::<(), signorini_events::EventsError>(())
//! ```
//!
//! [`ModalFlow::first_crossing`] locates the first time a contact dof
//! reaches a bound, with a step rule that cannot miss an event
//! (docs/theory.md §9.2).
//!
//! [`EventDriven`] runs a structure with contacts event by event: the exact
//! flow, each impact located, Newton's law with restitution in (0, 1].
//!
//! *Not yet here* (the rest of issue 25): simultaneous impacts as one LCP, held
//! phases, accumulation, massless contact dofs, non-proportional damping and
//! piecewise-linear loads.

mod driven;
mod flow;

pub use driven::{EventDriven, EventKind, EventRecord};
pub use flow::{Bound, Event, EventsError, ModalFlow};
