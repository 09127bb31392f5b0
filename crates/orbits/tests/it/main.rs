//! signorini-orbits' integration tests (one binary, one module per concern).
mod autonomous;
mod basins;
mod beam;
mod cascade;
mod chain;
mod chatter;
mod conservative;
mod corrector;
mod free_grazing;
mod further_impact;
mod oscillator;
mod period_two;
mod reach;
mod reuse;
mod switch;
mod symmetric;
mod two_stops;
