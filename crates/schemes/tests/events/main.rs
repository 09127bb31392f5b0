//! The event-driven reference's integration tests (`events::EventDriven`,
//! its stepper, its flow and its degenerate cases), one test binary beside
//! `tests/it` (the scheme crate's other tests): the two compile side by
//! side. Proptest's regression files for these modules are in
//! `tests/proptest-regressions/` (where proptest looks for a test binary with
//! a `main.rs`).

#[path = "../events_common/mod.rs"]
mod events_common;

mod events_bar;
mod events_chatter;
mod events_condensation;
mod events_dashpot;
mod events_dashpot_chatter;
mod events_dashpot_degenerate;
mod events_degenerate;
mod events_driven;
mod events_energy_balance;
mod events_events;
mod events_flow;
mod events_grazing;
mod events_held_starts;
mod events_let_go;
mod events_massless;
mod events_massless_coupled;
mod events_planted;
mod events_proptest;
mod events_releases;
mod events_restart;
mod events_rk4;
mod events_scales;
mod events_series;
mod events_silent;
mod events_stiff;
mod events_tail;
mod events_tiny_restitution;
mod events_two_stops;
mod events_unresolved;
