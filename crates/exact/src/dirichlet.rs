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
#[doc(hidden)]
pub fn phase(t: f64) -> Option<(u8, f64)> {
    if !t.is_finite() {
        return None;
    }
    let tp = rem3(t);
    // ⌊tp⌋ by truncation where that is the same value (tp > 0; `floor` is
    // a library call on the baseline x86-64 target).
    let p = if tp > 0.0 { f64::from(tp as u8) } else { tp.floor() };
    // rem_euclid can return 3.0 for tiny negative t; fold it back.
    if p >= 3.0 {
        return Some((0, 0.0));
    }
    Some((p as u8, tp - p))
}

/// `t.rem_euclid(3.0)`, the same bits, without the library `fmod` call
/// (tens of ns; the norms ask for the phase several times per step), for
/// `0 < t < 2⁴⁸`. Let `j = ⌊t/3⌋` (exact quotient). Rounding is monotone and
/// `3j/3` rounds to `j`, so the rounded `t/3` gives `k = j` or `j + 1`; `3k`
/// is exact (`k < 2⁴⁸`), and so is `t − 3k`: `0` for `k = 0`, otherwise
/// Sterbenz's lemma (`t/2 <= 3k <= 2t`, as `t >= 3/2` when `k >= 1`). The
/// true remainder `t − 3j ∈ [0, 3)` is a multiple of `t`'s ulp no larger
/// than `t`, hence representable: `r` itself, or `r + 3` rounded exactly.
/// That is what `fmod` returns. Elsewhere (`t <= 0`, huge, non-finite):
/// `rem_euclid` itself.
#[inline]
#[doc(hidden)]
pub fn rem3(t: f64) -> f64 {
    if !(t > 0.0 && t < 281_474_976_710_656.0) {
        return t.rem_euclid(3.0);
    }
    // ⌊t/3⌋ by truncation (t/3 in (0, 2⁴⁸): the same value as `floor`).
    let k = ((t / 3.0) as u64) as f64;
    let r = t - 3.0 * k;
    if r < 0.0 {
        r + 3.0
    } else {
        r
    }
}

/// `out[i] = zone(x_i)` with `x_i` clamped onto `[0, 1]` (`on_bar`), NaN off the bar.
#[inline(always)]
fn each_on_bar(xs: &[f64], out: &mut [f64], zone: impl Fn(f64) -> f64) {
    let (lo, hi) = (-crate::X_SLACK, 1.0 + crate::X_SLACK);
    for (x, o) in xs.iter().zip(out.iter_mut()) {
        *o = select(*x >= lo && *x <= hi, zone(x.clamp(0.0, 1.0)), f64::NAN);
    }
}

/// `if c { a } else { b }`, both computed (a select, not a branch).
#[inline(always)]
fn select(c: bool, a: f64, b: f64) -> f64 {
    if c {
        a
    } else {
        b
    }
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

/// [`BarDirichlet`]'s `u_at` compiled with AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn u_at_avx2(t: f64, xs: &[f64], out: &mut [f64]) {
    u_at_body(t, xs, out)
}

/// The body of [`BarDirichlet`]'s `u_at`.
#[inline(always)]
fn u_at_body(t: f64, xs: &[f64], out: &mut [f64]) {
    let Some((p, tau)) = phase(t) else {
        out.iter_mut().take(xs.len()).for_each(|o| *o = f64::NAN);
        return;
    };
    // `eval_zone`'s values that depend on τ alone.
    let (approach, contact_left, contact_right, flight) = ((1.0 - tau) / 2.0, -tau / 2.0, (tau - 1.0) / 2.0, tau / 2.0);
    // One loop per phase (a `match` inside would keep it scalar).
    match p {
        0 => each_on_bar(xs, out, |x| select(x < tau, approach, (1.0 - x) / 2.0)),
        1 => each_on_bar(xs, out, |x| select(x + tau < 1.0, select(x < tau, -x / 2.0, contact_left), select(x < tau, contact_right, (x - 1.0) / 2.0))),
        _ => each_on_bar(xs, out, |x| select(x + tau < 1.0, flight, (1.0 - x) / 2.0)),
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
    /// [`fields`](Self::fields)' `u` at every point, the phase found once
    /// and each zone's value chosen without a branch (so the loop
    /// vectorises): the same operations on the same clamped `x`, the same bits.
    /// Compiled for the baseline target and with AVX2, chosen at run time
    /// (no FMA: the same bits either way).
    fn u_at(&self, t: f64, xs: &[f64], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU reports AVX2.
            return unsafe { u_at_avx2(t, xs, out) };
        }
        u_at_body(t, xs, out)
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
