//! Post-processing of recorded histories: contact events and phase errors.

use crate::observers::Record;

/// The first contact events of a history.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Events {
    /// First level at which the constraint is active (time of the first impact).
    pub first_impact: Option<f64>,
    /// First level after that at which it is inactive again (take-off).
    pub first_takeoff: Option<f64>,
    /// First level after the take-off at which it is active again.
    pub second_impact: Option<f64>,
}

/// Contact events from the `active` flags, to the resolution `dt` of the
/// levels (an impact is dated by the first level whose step was active, a
/// take-off by the first inactive one).
pub fn events(records: &[Record]) -> Events {
    let mut it = records.iter().skip(1);
    let first_impact = it.by_ref().find(|r| r.active).map(|r| r.t);
    let first_takeoff = it.by_ref().find(|r| !r.active).map(|r| r.t);
    let second_impact = it.find(|r| r.active).map(|r| r.t);
    Events { first_impact, first_takeoff, second_impact }
}

/// `max_n |u_c(t_n) - exact(t_n)|` over the records with `t_n <= t_end`.
pub fn linf_error(records: &[Record], t_end: f64, exact: impl Fn(f64) -> f64) -> f64 {
    records.iter().filter(|r| r.t <= t_end * (1.0 + 1e-12)).map(|r| (r.u_contact - exact(r.t)).abs()).fold(0.0, f64::max)
}
