//! The oscillator between symmetric stops, `x'' + 0.1 x' + x = 2 sin Ωt`,
//! `|x| <= 1`, e = 0.8 (section.rs, slow_impact.rs, symmetric.rs): the
//! crate's model of it, and the closed-form flow between impacts that
//! those tests' transcriptions of the map are built on (no code of the
//! crate).

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
    let one = |v: f64| {
        let mut b = SymBand::zeros(1, 0);
        b.set(0, 0, v);
        b
    };
    let dy = Dynamics::new(one(1.0), one(1.0), vec![0.0], vec![Contact::new(0, Bounds { lo: -1.0, hi: 1.0 }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: F, omega: w } }])
        .with_damping(Some(one(C)));
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
