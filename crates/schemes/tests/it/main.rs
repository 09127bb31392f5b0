//! The scheme crate's integration tests but the event-driven reference's
//! (`tests/events`), one test binary (each file a module: one link instead
//! of one per file, and the generic code compiled once). Two binaries, not
//! one: the crate's tests are the largest of the workspace and compile last,
//! and on two cores two halves compile side by side.
//! Proptest's regression files for these modules are in
//! `tests/proptest-regressions/` (where proptest looks for a test binary with
//! a `main.rs`).

#[path = "../common/mod.rs"]
mod common;

mod carpenter;
mod cd_lagrange;
mod cd_lagrange_lockstep;
mod combined_lockstep;
mod conformance;
mod d1_minus_linear_lockstep;
mod d1minus;
mod damping;
mod diagonal_mass;
mod energy;
mod fused_bar;
mod lockstep;
mod moreau_lockstep;
mod moreau_projected_lockstep;
mod multi_solve;
mod nsga;
mod nsga_lockstep;
mod peers;
mod profile;
mod ps_massless;
mod several_contacts;
mod siconos;
mod stabilized;
mod stabilized_lockstep;
mod verlet_nitsche;
