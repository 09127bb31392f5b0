//! xtask's tests, one test binary (each file the tests of one module of the
//! library, which is not compiled a second time as a test harness).

mod crate_graph;
mod docs;
mod module_graph;
mod pytest;
mod scene_keys;
mod studies;
mod unit_tests;
