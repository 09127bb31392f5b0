//! Benchmark `bar-mirrored` (docs/theory.md §5.4): a free bar on `[0, 2]`,
//! `c = 1`, `f = 0`, `u0 = (1 - x)/2`, `v0 = 0`, between two stops,
//! `u(0, t) >= 0` and `u(2, t) <= 0`.
//!
//! The data are odd about `x = 1` and so is the problem (the map
//! `u(x) ↦ -u(2 - x)` exchanges the stops), so the solution stays odd:
//! `u(1, t) = 0`, and on `[0, 1]` it is the Signorini–Dirichlet bar
//! [`BarDirichlet`](crate::BarDirichlet) (§5.1). Beyond `x = 1` it is its
//! mirror image,
//!
//! ```text
//! u(x, t) = -u_D(2 - x, t),  u_x(x, t) = u_D,x(2 - x, t),  u_t(x, t) = -u_D,t(2 - x, t),
//! ```
//!
//! with the kinks `τ`, `1 - τ` mirrored to `2 - τ`, `1 + τ` (and `x = 1`
//! at integer times, where the lines from both ends meet); the contact
//! force at `x = 0` is `u_D`'s, the one at `x = 2` its opposite, and the
//! energy twice `u_D`'s: `1/4`. Periodic with period 3.

use crate::dirichlet::{eval_zone, phase};
use crate::{on_bar, ExactSolution, FarEnd, Fields, UNDEFINED};

/// The Signorini–Dirichlet bar mirrored antisymmetrically onto `[0, 2]`:
/// two stops, one contact at each end.
#[derive(Clone, Copy, Debug, Default)]
pub struct BarMirrored;

/// The four characteristic lines at `τ` into a phase, as positions in
/// `x`: `τ`, `1 - τ` (those of `u_D`) and their mirror images `2 - τ`,
/// `2 - (1 - τ)`, each rounded once from the one before, so that the zone
/// tests below and [`ExactSolution::kinks`] agree to the bit.
#[inline]
fn lines(tau: f64) -> [f64; 4] {
    let b = 1.0 - tau;
    [tau, b, 2.0 - tau, 2.0 - b]
}

#[inline]
fn eval(p: u8, tau: f64, x: f64) -> Fields {
    let [la, lb, ma, mb] = lines(tau);
    if x < 1.0 {
        eval_zone(p, tau, x, x < la, x < lb)
    } else {
        // u_D's zone of y = 2 - x: "y < τ" is "x > 2 - τ", "y < 1 - τ" is
        // "x > 2 - (1 - τ)"; on a line, the piece towards larger x (none
        // beyond the end x = 2).
        let f = eval_zone(p, tau, 2.0 - x, x >= ma && ma < 2.0, x >= mb);
        Fields { u: -f.u, ux: f.ux, ut: -f.ut }
    }
}

impl ExactSolution for BarMirrored {
    fn name(&self) -> &str {
        "bar-mirrored"
    }
    fn length(&self) -> f64 {
        2.0
    }
    fn far_end(&self) -> FarEnd {
        FarEnd::Free
    }
    fn degree_x(&self) -> usize {
        1
    }
    /// NaN for a non-finite `t` or `x` off `[0, 2]` (see the crate docs).
    fn fields(&self, x: f64, t: f64) -> Fields {
        match (phase(t), on_bar(x, 2.0)) {
            (Some((p, tau)), Some(x)) => eval(p, tau, x),
            _ => UNDEFINED,
        }
    }
    fn u_at(&self, t: f64, xs: &[f64], out: &mut [f64]) {
        let ph = phase(t);
        for (x, o) in xs.iter().zip(out.iter_mut()) {
            *o = match (ph, on_bar(*x, 2.0)) {
                (Some((p, tau)), Some(x)) => eval(p, tau, x).u,
                _ => f64::NAN,
            };
        }
    }
    /// The force at `x = 0` (the one at `x = 2` is its opposite); NaN for a
    /// non-finite `t`.
    fn lambda(&self, t: f64) -> f64 {
        crate::BarDirichlet.lambda(t)
    }
    fn energy(&self) -> f64 {
        0.25
    }
    fn kinks(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        let Some((_, tau)) = phase(t) else { return };
        let [la, lb, ma, mb] = lines(tau);
        // Increasing order (x ↦ 2 - x rounds monotonically). At τ = 0 the
        // lines from both ends meet at x = 1, where u_t then jumps.
        let sorted = if tau <= 0.5 { [la, lb, mb, ma] } else { [lb, la, ma, mb] };
        for k in sorted {
            if k > 0.0 && k < 2.0 && out.last() != Some(&k) {
                out.push(k);
            }
        }
    }
    fn period(&self) -> Option<f64> {
        Some(3.0)
    }
}
