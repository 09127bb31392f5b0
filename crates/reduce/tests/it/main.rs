//! signorini-reduce's integration tests (one binary, one module per concern).
mod event_driven;
mod reduction;
