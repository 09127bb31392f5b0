//! The scheme crate's integration tests, one test binary (each file a module:
//! one link instead of one per file, and the generic code compiled once).
//! Proptest's regression files for these modules are in
//! `tests/proptest-regressions/` (where proptest looks for a test binary with
//! a `main.rs`).

#[path = "../common/mod.rs"]
mod common;
#[path = "../events_common/mod.rs"]
mod events_common;

mod carpenter;
mod cd_lagrange;
mod cd_lagrange_lockstep;
mod conformance;
mod d1minus;
mod damping;
mod energy;
mod events_degenerate;
mod events_driven;
mod events_events;
mod events_flow;
mod events_held_starts;
mod events_massless;
mod events_planted;
mod events_proptest;
mod events_series;
mod events_silent;
mod events_tiny_restitution;
mod events_two_stops;
mod lockstep;
mod moreau_lockstep;
mod moreau_projected_lockstep;
mod multi_solve;
mod nsga;
mod nsga_lockstep;
mod peers;
mod profile;
mod several_contacts;
mod siconos;
mod stabilized;
mod stabilized_lockstep;
mod verlet_nitsche;
