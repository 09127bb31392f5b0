//! The finite elements' integration tests, one test binary (each file a
//! module: one link instead of one per file, and the generic code compiled
//! once).

#[path = "../common/mod.rs"]
mod common;

mod beam;
mod contacts;
mod diagonal_solve;
mod kappa_bound;
mod matrices;
mod pk;
