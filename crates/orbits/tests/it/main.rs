//! signorini-orbits' integration tests (one binary, one module per concern).
mod basins;
mod chain;
mod oscillator;
mod reach;
