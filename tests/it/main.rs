//! The facade's cross-crate integration tests, one test binary (each file a
//! module: one link instead of one per file, and the generic code compiled
//! once). `independent.rs` is still a test binary of its own (`independent`
//! is named in the files it regenerates).

#[path = "../../crates/schemes/tests/common/mod.rs"]
mod common;
#[path = "../support/independent_bar.rs"]
mod independent_bar;

mod bad_input;
mod beam;
mod convergence;
mod mirrored;
mod readme;
mod several_contacts;
mod stability;
mod weighted;
