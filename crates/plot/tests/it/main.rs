//! The crate's tests, one test binary (each file a module).

mod lib_src;
