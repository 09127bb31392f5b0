//! The norms' integration tests, one test binary (each file a module: one link
//! instead of one per file).

mod norms;
mod pk;
