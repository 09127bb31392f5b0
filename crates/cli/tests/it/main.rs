//! The `signorini` command's integration tests, one test binary (each file a
//! module: one link instead of one per file).

mod basins;
mod beam_scheme;
mod cli;
mod contacts;
mod continue_cmd;
mod degree;
mod energy_warn;
mod event_driven;
mod event_estimate;
mod event_sampling;
mod facts;
mod follow;
mod lockstep;
mod new_user;
mod new_user_3;
mod oscillator;
mod reduce;
mod reliability;
mod semidiscrete_rates;
mod sweep;
mod sweep_setup_src;
mod two_stops;
mod vibro;
