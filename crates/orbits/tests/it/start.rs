//! A continuation whose start finds no orbit says what the transient
//! settled on. The oscillator of `oscillator.rs` at Ω = 1.1 lies between
//! the period doublings at 1.0648 and 1.1300: its period-1 orbit exists
//! (the closed form's, unstable) and the motion from rest settles on an
//! orbit of 2 periods. `signorini continue --from 1.1` failed with
//! "no periodic orbit near the start (residual 0.73)"; it now names the
//! attractor's period and the option that continues it. Checked against
//! the closed form (a period-1 orbit at 1.1, unstable) and a transcription
//! of the flow sharing no code with the crate (from rest, 400 periods:
//! the state returns after 2 periods, not after 1).

use crate::oscillator::closed_orbits;
use signorini_orbits::front::{continue_scene, ContinueOptions};
use signorini_orbits::OrbitError;
use std::f64::consts::TAU;

/// The transcription's flow of `x'' + 0.1 x' + x = cos Ωt` from `(x, v)`
/// at `t0` to `t` (no stop).
fn flow(w: f64, t0: f64, x: f64, v: f64, t: f64) -> (f64, f64) {
    let d = (1.0 - w * w).powi(2) + (0.1 * w).powi(2);
    let (a, b) = ((1.0 - w * w) / d, 0.1 * w / d);
    let xp = |t: f64| a * (w * t).cos() + b * (w * t).sin();
    let vp = |t: f64| w * (b * (w * t).cos() - a * (w * t).sin());
    let (z, wd) = (0.05, (1.0f64 - 0.0025).sqrt());
    let c1 = x - xp(t0);
    let c2 = (v - vp(t0) + z * c1) / wd;
    let (ex, (sn, cs)) = ((-z * (t - t0)).exp(), (wd * (t - t0)).sin_cos());
    (ex * (c1 * cs + c2 * sn) + xp(t), ex * (-z * (c1 * cs + c2 * sn) + wd * (-c1 * sn + c2 * cs)) + vp(t))
}

/// The transcription's map over one forcing period with the stop at 0.2
/// (sampled at 1/2000 of the period, each crossing bisected, e = 0.8).
fn map(w: f64, x: (f64, f64)) -> (f64, f64) {
    let end = TAU / w;
    let h = end / 2000.0;
    let (mut t0, mut z, mut t) = (0.0, x, 0.0);
    while t < end {
        let t1 = (t + h).min(end);
        if flow(w, t0, z.0, z.1, t1).0 > 0.2 {
            let (mut lo, mut hi) = (t, t1);
            for _ in 0..100 {
                let m = 0.5 * (lo + hi);
                if flow(w, t0, z.0, z.1, m).0 > 0.2 {
                    hi = m;
                } else {
                    lo = m;
                }
            }
            let y = flow(w, t0, z.0, z.1, lo);
            (t0, z, t) = (lo, (0.2, -0.8 * y.1), lo);
            continue;
        }
        t = t1;
    }
    flow(w, t0, z.0, z.1, end)
}

#[test]
fn a_start_on_a_period_two_attractor_says_so() {
    let w = 1.1;
    // The closed form: a period-1 orbit exists at 1.1, unstable.
    let orbits = closed_orbits(w);
    assert!(!orbits.is_empty() && orbits.iter().all(|o| !o.2), "the closed form's period-1 orbits at 1.1: {orbits:?}");
    // The transcription: from rest, 400 periods; then the state comes back
    // after 2 periods and not after 1.
    let mut x = (0.0, 0.0);
    for _ in 0..400 {
        x = map(w, x);
    }
    let (one, two) = (map(w, x), map(w, map(w, x)));
    let gap = |a: (f64, f64)| (a.0 - x.0).abs().max((a.1 - x.1).abs());
    assert!(gap(two) <= 1e-6 && gap(one) > 1e-2, "the transcription's attractor: {:e} after 1 period, {:e} after 2", gap(one), gap(two));
    let scene =
        "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.8\ndt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = 1.1\n";
    let opts = ContinueOptions { param: "forcing.omega".into(), from: 1.1, to: 4.0, period: 1, transient: 100.0, max_points: 400, switch: false, sweep: Vec::new(), param_scale: None };
    match continue_scene(scene.parse().unwrap(), &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true) {
        Err(e @ OrbitError::NoConvergence { residual, .. }) => {
            let m = e.to_string();
            eprintln!("{m}");
            assert!(residual.is_finite() && m.contains(&format!("{residual:e}")), "{m}");
            assert!(m.contains("returns to itself after 2 forcing periods") && m.contains("--period 2"), "{m}");
        }
        Err(e) => panic!("{e}"),
        Ok(c) => panic!("a branch from 1.1: {:?}", c.lines),
    }
}
