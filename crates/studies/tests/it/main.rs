//! The studies' integration tests, one test binary (each file a module: one link
//! instead of one per file, and the crates' generic code compiled once).

mod bad_input;
mod beam_statistics;
mod convergence_src;
mod courant1;
mod frontier;
mod long_horizon;
mod lyapunov;
mod lyapunov_src;
mod options;
mod oscillator_src;
mod scheme_lists;
mod tables;
mod time_error;
mod work_precision_src;
mod wp_quantities;
mod wp_report;
