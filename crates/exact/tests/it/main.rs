//! The exact solutions' integration tests, one test binary (each file a
//! module: one link instead of one per file). Proptest's regression files for
//! these modules are in `tests/proptest-regressions/` (where proptest looks
//! for a test binary with a `main.rs`).

#[path = "../common/mod.rs"]
mod common;

mod backbone;
mod dirichlet;
mod dirichlet_src;
mod domain;
mod mirrored;
mod neumann;
mod oscillator;
