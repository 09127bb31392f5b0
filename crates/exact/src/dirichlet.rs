//! Benchmark `bar-dirichlet` (docs/theory.md §5.1): `L = 1`,
//! `c = 1`, `f = 0`, `u0 = (1 - x)/2`, `v0 = 0`, `u(1, t) = 0`. Periodic with
//! period 3: approach on `[0, 1)`, contact on `[1, 2)`, flight on `[2, 3)`.
//! Piecewise affine in `(x, t)`; kinks on `x = τ` and `x = 1 - τ`.
//!
//! The 2017 paper prints zone I of phase 1 as `-(t1 - t)/2`: a sign typo;
//! `-τ/2` is right (continuity with zones II and III).

use crate::{on_bar, ExactSolution, FarEnd, Fields, UNDEFINED};

/// The Signorini–Dirichlet bar of Dabaghi–Petrov–Pousin–Renard §5.
#[derive(Clone, Copy, Debug, Default)]
pub struct BarDirichlet;

/// Phase (0 approach, 1 contact, 2 flight) and time inside it; `t` must be
/// finite (`None` otherwise: a NaN phase would be cast to phase 0).
#[inline]
pub(crate) fn phase(t: f64) -> Option<(u8, f64)> {
    if !t.is_finite() {
        return None;
    }
    let tp = t.rem_euclid(3.0);
    let p = tp.floor();
    // rem_euclid can return 3.0 for tiny negative t; fold it back.
    if p >= 3.0 {
        return Some((0, 0.0));
    }
    Some((p as u8, tp - p))
}

#[inline]
fn eval(p: u8, tau: f64, x: f64) -> Fields {
    // a: reached by the line leaving x = 0 at the phase start;
    // b: not yet reached by the line leaving x = 1.
    eval_zone(p, tau, x, x < tau, x + tau < 1.0)
}

/// The fields at `x` in the zone `(a, b)` of phase `p`, `tau` into it
/// (`a`: left of the line `x = τ`; `b`: left of the line `x = 1 - τ`).
#[inline]
pub(crate) fn eval_zone(p: u8, tau: f64, x: f64, a: bool, b: bool) -> Fields {
    let f = |u: f64, ux: f64, ut: f64| Fields { u, ux, ut };
    match (p, a, b) {
        (0, false, _) => f((1.0 - x) / 2.0, -0.5, 0.0),
        (0, true, _) => f((1.0 - tau) / 2.0, 0.0, -0.5),
        (1, false, true) => f(-tau / 2.0, 0.0, -0.5),
        (1, true, true) => f(-x / 2.0, -0.5, 0.0),
        (1, false, false) => f((x - 1.0) / 2.0, 0.5, 0.0),
        (1, true, false) => f((tau - 1.0) / 2.0, 0.0, 0.5),
        (_, _, true) => f(tau / 2.0, 0.0, 0.5),
        (_, _, false) => f((1.0 - x) / 2.0, -0.5, 0.0),
    }
}

impl ExactSolution for BarDirichlet {
    fn name(&self) -> &str {
        "bar-dirichlet"
    }
    fn length(&self) -> f64 {
        1.0
    }
    fn far_end(&self) -> FarEnd {
        FarEnd::Clamped
    }
    fn degree_x(&self) -> usize {
        1
    }
    /// NaN for a non-finite `t` or `x` off `[0, 1]` (see the crate docs).
    fn fields(&self, x: f64, t: f64) -> Fields {
        match (phase(t), on_bar(x, 1.0)) {
            (Some((p, tau)), Some(x)) => eval(p, tau, x),
            _ => UNDEFINED,
        }
    }
    fn u_at(&self, t: f64, xs: &[f64], out: &mut [f64]) {
        let ph = phase(t);
        for (x, o) in xs.iter().zip(out.iter_mut()) {
            *o = match (ph, on_bar(*x, 1.0)) {
                (Some((p, tau)), Some(x)) => eval(p, tau, x).u,
                _ => f64::NAN,
            };
        }
    }
    /// NaN for a non-finite `t`.
    fn lambda(&self, t: f64) -> f64 {
        match phase(t) {
            Some((1, _)) => -0.5,
            Some(_) => 0.0,
            None => f64::NAN,
        }
    }
    fn energy(&self) -> f64 {
        0.125
    }
    fn kinks(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        let Some((_, tau)) = phase(t) else { return };
        let (a, b) = if tau <= 0.5 { (tau, 1.0 - tau) } else { (1.0 - tau, tau) };
        for k in [a, b] {
            if k > 0.0 && k < 1.0 && out.last() != Some(&k) {
                out.push(k);
            }
        }
    }
    fn period(&self) -> Option<f64> {
        Some(3.0)
    }
}
