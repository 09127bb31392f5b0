//! The oscillator between symmetric stops, `x'' + 0.1 x' + x = 2 sin Ωt`,
//! `|x| <= 1`, e = 0.8 (section.rs, slow_impact.rs, symmetric.rs): the
//! crate's model of it, and the closed-form flow between impacts that
//! those tests' transcriptions of the map are built on (no code of the
//! crate), with its map between any two stops (slow_impact.rs, isola.rs).

use signorini_fem::SymBand;
use signorini_orbits::{Model, OrbitError};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};

/// The forcing's amplitude.
pub const F: f64 = 2.0;
/// The damping coefficient.
pub const C: f64 = 0.1;
/// The restitution.
pub const E: f64 = 0.8;

/// The crate's model forced at Ω = `w`.
pub fn model(w: f64) -> Result<Model, OrbitError> {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: -1.0, hi: 1.0 }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: F, omega: w } }])
        .with_damping(Some(SymBand::from_diagonal(&[C])));
    Model::new(dy, E)
}

/// The transcription's flow of `x'' + c x' + x = F sin Ωt` from `(x, v)`
/// at `t0` to `t`: the underdamped free motion plus the steady state.
pub fn flow(w: f64, t0: f64, x: f64, v: f64, t: f64) -> (f64, f64) {
    let d = (1.0 - w * w).powi(2) + (C * w).powi(2);
    let (a, b) = (F * (1.0 - w * w) / d, -F * C * w / d);
    let xp = |t: f64| a * (w * t).sin() + b * (w * t).cos();
    let vp = |t: f64| w * (a * (w * t).cos() - b * (w * t).sin());
    let z = 0.5 * C;
    let wd = (1.0 - z * z).sqrt();
    let c1 = x - xp(t0);
    let c2 = (v - vp(t0) + z * c1) / wd;
    let (ex, (sn, cs)) = ((-z * (t - t0)).exp(), (wd * (t - t0)).sin_cos());
    (ex * (c1 * cs + c2 * sn) + xp(t), ex * (-z * (c1 * cs + c2 * sn) + wd * (-c1 * sn + c2 * cs)) + vp(t))
}

/// The last time of `[lo, hi]` where `inside` holds, by bisection.
pub fn bisect(mut lo: f64, mut hi: f64, inside: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if m <= lo || m >= hi {
            break;
        }
        if inside(m) {
            lo = m;
        } else {
            hi = m;
        }
    }
    lo
}

/// The transcription's map over `p` forcing periods between the stops
/// `lo <= x <= hi` with restitution `e`: the flow sampled at `1/samples`
/// of a period, each sample step split at an extremum of `x` (found by
/// bisection on `v`, so that a slow impact inside a step is not stepped
/// over), each crossing of a stop bisected to round-off, the velocity
/// reversed times `e`. Returns the image, the impacts, and the smallest
/// distance to a stop of a flight's extremum that does not reach one.
pub fn map_between(w: f64, x: [f64; 2], p: usize, stops: (f64, f64), e: f64, samples: f64) -> ([f64; 2], usize, f64) {
    map_between_from(w, 0.0, x, p, stops, e, samples)
}

/// [`map_between`] with the section at time `start` (the forcing
/// `F sin Ω(t + start)` seen from `t = 0`: `start` a quarter of the period,
/// `F cos Ωt`).
pub fn map_between_from(w: f64, start: f64, x: [f64; 2], p: usize, stops: (f64, f64), e: f64, samples: f64) -> ([f64; 2], usize, f64) {
    flow_between(w, start, start + p as f64 * std::f64::consts::TAU / w, x, stops, e, samples)
}

/// [`map_between_from`]'s flow from `(x, v)` at `start` to `end` (any
/// span: half a period for an orbit's mirror image `−x(T/2)`).
pub fn flow_between(w: f64, start: f64, end: f64, x: [f64; 2], (lo, hi): (f64, f64), e: f64, samples: f64) -> ([f64; 2], usize, f64) {
    let h = std::f64::consts::TAU / w / samples;
    let (mut t0, mut z, mut t) = (start, (x[0], x[1]), start);
    let (mut impacts, mut margin) = (0, f64::INFINITY);
    let out = |x: f64| !(lo..=hi).contains(&x);
    while t < end {
        let t1 = (t + h).min(end);
        let (v0, v1) = (flow(w, t0, z.0, z.1, t).1, flow(w, t0, z.0, z.1, t1).1);
        let mut ends = vec![t1];
        if v0 * v1 < 0.0 {
            let te = bisect(t, t1, |m| flow(w, t0, z.0, z.1, m).1 * v0 > 0.0);
            let xe = flow(w, t0, z.0, z.1, te).0;
            if !out(xe) {
                margin = margin.min((hi - xe).min(xe - lo));
            }
            ends = vec![te, t1];
        }
        let mut a = t;
        let mut hit = None;
        for &b in &ends {
            if out(flow(w, t0, z.0, z.1, b).0) {
                hit = Some(bisect(a, b, |m| !out(flow(w, t0, z.0, z.1, m).0)));
                break;
            }
            a = b;
        }
        match hit {
            Some(ti) => {
                let y = flow(w, t0, z.0, z.1, ti);
                let stop = if y.0 > 0.5 * (lo + hi) { hi } else { lo };
                (t0, z, t) = (ti, (stop, -e * y.1), ti);
                impacts += 1;
            }
            None => t = t1,
        }
    }
    let y = flow(w, t0, z.0, z.1, end);
    ([y.0, y.1], impacts, margin)
}

/// The Jacobian of a map of the section state by central differences of
/// step 1e-7 ([`differences`]).
pub fn jacobian(x: [f64; 2], map: impl Fn([f64; 2]) -> [f64; 2]) -> [[f64; 2]; 2] {
    differences(x, 1e-7, map)
}

/// The Jacobian of `map` at `x` by central differences of step `h`,
/// `j[r][c] = (map(x + h e_c)[r] − map(x − h e_c)[r]) / 2h` (row `r` of
/// the image, column `c` of the state): the one finite-difference
/// Jacobian of these tests (chain.rs's shootings, the maps here).
pub fn differences<const N: usize>(x: [f64; N], h: f64, map: impl Fn([f64; N]) -> [f64; N]) -> [[f64; N]; N] {
    let mut j = [[0.0; N]; N];
    for c in 0..N {
        let (mut a, mut b) = (x, x);
        a[c] += h;
        b[c] -= h;
        let (ya, yb) = (map(a), map(b));
        for r in 0..N {
            j[r][c] = (ya[r] - yb[r]) / (2.0 * h);
        }
    }
    j
}

/// Newton on a transcribed map of the section state (its `J − I` by
/// [`jacobian`]) from `x`: the fixed point when the residual falls below
/// 1e-10 within `iterations` (near a fold, where `J − I` is nearly
/// singular, it converges slowly); `None` when a step leaves `|x₀| ≤ 2`.
pub fn fixed_point(mut x: [f64; 2], iterations: usize, map: impl Fn([f64; 2]) -> [f64; 2]) -> Option<[f64; 2]> {
    for _ in 0..iterations {
        let g = map(x);
        let r = [g[0] - x[0], g[1] - x[1]];
        if r[0].abs().max(r[1].abs()) <= 1e-10 {
            return Some(x);
        }
        let mut j = jacobian(x, &map);
        j[0][0] -= 1.0;
        j[1][1] -= 1.0;
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        x = [x[0] - (j[1][1] * r[0] - j[0][1] * r[1]) / det, x[1] - (-j[1][0] * r[0] + j[0][0] * r[1]) / det];
        if !(x[0].is_finite() && x[1].is_finite()) || x[0].abs() > 2.0 {
            return None;
        }
    }
    None
}
