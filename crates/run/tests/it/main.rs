//! The run layer's integration tests, one test binary (each file a module: one
//! link instead of one per file, and the generic code compiled once).

mod beam_src;
mod chaos;
mod energy_growth;
mod event_interrupt;
mod event_long;
mod lockstep;
mod pk;
mod reduced;
mod runner;
mod stats_src;
mod text_src;
mod vibro;
