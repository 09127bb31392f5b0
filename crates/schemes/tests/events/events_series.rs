//! Piecewise-linear loads in the event-driven run against closed forms:
//! the response of one mass to a load that is a sum of ramps
//! `Σ_k Δs_k (t − t_k)₊` (`Δs_k` the change of slope at the series' point
//! `t_k`) is the same sum of ramp responses, written here for the four
//! kinds of mode the flow distinguishes: a spring with and without damping,
//! a free mass with and without damping.

use signorini_fem::SymBand;
use signorini_schemes::events::EventDriven;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};

/// The response `(x, x')` of `m x'' + c x' + k x = τ₊` from rest.
fn ramp_response(m: f64, c: f64, k: f64, tau: f64) -> (f64, f64) {
    if tau <= 0.0 {
        return (0.0, 0.0);
    }
    if k > 0.0 {
        let wn = (k / m).sqrt();
        let z = c / (2.0 * (k * m).sqrt());
        let wd = wn * (1.0 - z * z).sqrt();
        let (a, b) = (2.0 * z / wn, (2.0 * z * z - 1.0) / wd);
        let ex = (-z * wn * tau).exp();
        let (s, co) = (wd * tau).sin_cos();
        let x = (tau - a + ex * (a * co + b * s)) / k;
        let dx = (1.0 + ex * ((-z * wn * a + b * wd) * co + (-z * wn * b - a * wd) * s)) / k;
        (x, dx)
    } else if c > 0.0 {
        let g = c / m;
        let x = (1.0 - (-g * tau).exp()) / (m * g * g * g) + tau * tau / (2.0 * m * g) - tau / (m * g * g);
        let dx = (-g * tau).exp() / (m * g * g) + tau / (m * g) - 1.0 / (m * g * g);
        (x, dx)
    } else {
        (tau * tau * tau / (6.0 * m), tau * tau / (2.0 * m))
    }
}

#[test]
fn one_mass_under_a_piecewise_linear_load_is_the_sum_of_its_ramp_responses() {
    let (times, values) = (vec![0.3, 1.1, 2.0, 3.7, 4.5], vec![0.0, 0.8, 0.8, -0.5, -0.5]);
    // The changes of slope at each point (0 before the first, 0 after the last).
    let mut kinks = Vec::new();
    let mut before = 0.0;
    for k in 0..times.len() {
        let after = if k + 1 < times.len() { (values[k + 1] - values[k]) / (times[k + 1] - times[k]) } else { 0.0 };
        kinks.push((times[k], after - before));
        before = after;
    }
    for (m, c, k) in [(2.0, 0.0, 8.0), (2.0, 0.6, 8.0), (1.5, 0.0, 0.0), (1.5, 0.9, 0.0)] {
        let series = TimeProfile::series(times.clone(), values.clone()).unwrap();
        let dy = Dynamics::new(SymBand::from_diagonal(&[m]), SymBand::from_diagonal(&[k]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(-1e3), false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: series }])
            .with_damping((c > 0.0).then(|| SymBand::from_diagonal(&[c])));
        let mut run = EventDriven::new(&dy, 0.0, &[0.0], &[0.0], 0.0).unwrap();
        for j in 1..=130 {
            let t = 0.05 * j as f64;
            run.run_until(t, 0).unwrap();
            let (_, q, v) = run.state();
            let (x, dx) = kinks.iter().fold((0.0, 0.0), |(x, dx), &(tk, ds)| {
                let (r, dr) = ramp_response(m, c, k, t - tk);
                (x + ds * r, dx + ds * dr)
            });
            let scale = x.abs().max(dx.abs()).max(1.0);
            assert!((q[0] - x).abs() <= 1e-12 * scale && (v[0] - dx).abs() <= 1e-12 * scale, "m = {m}, c = {c}, k = {k}, t = {t}: (q, v) = ({}, {}) against ({x}, {dx})", q[0], v[0]);
        }
    }
}

/// A mass resting on a floor under the load through `(0, −1), (2, −3),
/// (5, 1.5)`: held while the load presses (force `r = −F`), released at
/// `t = 4` where the third piece's ramp reaches 0, the impulse over the
/// held phase `∫₀⁴ −F = 7`; then `m x'' = 1.5 (t − 4)`: at `t = 5`,
/// `x = 0.25/m`, `x' = 0.75/m`.
#[test]
fn a_pressed_mass_is_released_where_the_ramp_crosses_zero() {
    use signorini_schemes::events::EventKind;
    let m = 2.0;
    let series = TimeProfile::series(vec![0.0, 2.0, 5.0], vec![-1.0, -3.0, 1.5]).unwrap();
    let dy = Dynamics::new(SymBand::from_diagonal(&[m]), SymBand::from_diagonal(&[0.0]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(0.0), false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: series }]);
    let mut run = EventDriven::new(&dy, 0.0, &[0.0], &[0.0], 0.0).unwrap();
    assert_eq!(run.held(), vec![(0, false)]);
    run.run_until(5.0, 10).unwrap();
    let ev = run.events();
    assert_eq!(ev.len(), 1, "{ev:?}");
    assert_eq!(ev[0].kind, EventKind::Release);
    assert!((ev[0].t - 4.0).abs() <= 1e-14 * 4.0, "released at {}", ev[0].t);
    let impulse = run.take_impulses()[0];
    assert!((impulse - 7.0).abs() <= 1e-13 * 7.0, "impulse {impulse}");
    let (_, q, v) = run.state();
    assert!((q[0] - 0.25 / m).abs() <= 1e-13 && (v[0] - 0.75 / m).abs() <= 1e-13, "(q, v) = ({}, {})", q[0], v[0]);
}
