//! The run layer's integration tests, one test binary (each file a module: one
//! link instead of one per file, and the generic code compiled once).

mod chaos;
mod energy_growth;
mod event_interrupt;
mod lockstep;
mod pk;
mod reduced;
mod runner;
mod vibro;
