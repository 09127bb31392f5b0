//! The classes a user meets first (issue 32): a structure that starts
//! held on its stop under a load that reverses, plastic impacts into held
//! phases. Before the fix, every such run cycled release → zero-speed
//! impact → release at one instant until `max_events` (a release is
//! located to the time resolution, where the held force is `r' δt`, not 0,
//! and the free phase's `g'' ∝ r` read that as an approach).
//!
//! Oracles: closed forms written here. A chain at rest on its stop, loaded
//! only at its contact dof, does not move while held (the load goes into
//! the reaction), so it is released exactly where the load changes sign;
//! the held plastic oscillator `x'' + x = cos t`, `x <= 0.2`, is released
//! at `acos 0.2 + 2πk` and its free flight is the resonant closed form.

use crate::events_common as common;

use proptest::prelude::*;
use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::sync::Arc;

fn sine(amplitude: f64, omega: f64, phase: f64) -> TimeProfile {
    TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude, omega, phase }]))
}

/// `x'' + x = cos t` from `(x, x') = (x0, v0)` at `t0`: the resonant closed form.
fn resonant(t0: f64, x0: f64, v0: f64) -> impl Fn(f64) -> (f64, f64) {
    // x = A cos t + B sin t + (t/2) sin t.
    let (s, c) = t0.sin_cos();
    let (px, pv) = (0.5 * t0 * s, 0.5 * s + 0.5 * t0 * c);
    let (rx, rv) = (x0 - px, v0 - pv);
    // A c + B s = rx, −A s + B c = rv.
    let (a, b) = (rx * c - rv * s, rx * s + rv * c);
    move |t: f64| {
        let (s, c) = t.sin_cos();
        (a * c + b * s + 0.5 * t * s, -a * s + b * c + 0.5 * s + 0.5 * t * c)
    }
}

/// The held plastic oscillator: released at `acos 0.2 + 2πk`, lands at the
/// root of the closed-form flight (bisection here) with its speed, held
/// again (plastic), for 15 periods.
#[test]
fn a_held_plastic_oscillator_is_released_once_per_forcing_period() {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: f64::NEG_INFINITY, hi: 0.2 }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: sine(1.0, 1.0, FRAC_PI_2) }]);
    let mut r = EventDriven::new(&dy, 0.0, &[0.2], &[0.0], 0.0).expect("starts");
    let periods = 15;
    r.run_until(periods as f64 * TAU, 1000).expect("completes");
    let ev = r.events();
    common::check_order(ev).unwrap();
    assert_eq!(ev.len(), 2 * periods, "{ev:?}");
    let t_r = 0.2f64.acos();
    // The flight after a release at t_r: x(t) = 0.2 again at the landing.
    let flight = resonant(t_r, 0.2, 0.0);
    let (mut lo, mut hi) = (t_r + 1.0, t_r + TAU);
    assert!(flight(lo).0 < 0.2 && flight(hi).0 > 0.2);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if flight(mid).0 < 0.2 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (t_land, v_land) = (lo, flight(lo).1);
    for k in 0..periods {
        let shift = k as f64 * TAU;
        let (rel, imp) = (ev[2 * k], ev[2 * k + 1]);
        assert_eq!((rel.kind, imp.kind), (EventKind::Release, EventKind::Impact), "period {k}");
        let tol = 1e-12 * (1.0 + shift);
        assert!((rel.t - (t_r + shift)).abs() <= tol, "release {k} at {} against {}", rel.t, t_r + shift);
        assert!((imp.t - (t_land + shift)).abs() <= tol, "landing {k} at {} against {}", imp.t, t_land + shift);
        assert!((imp.velocity_before - v_land).abs() <= 1e-11, "landing {k} at speed {} against {v_land}", imp.velocity_before);
    }
}

/// A chain of `n` masses (consistent or lumped mass), free or tied at its
/// far end, with a stop at dof 0 (`lo = 0`, or `hi = 0`), at rest on it,
/// loaded at dof 0 by `∓A sin(ω t + p)` (into the stop at t = 0), optional
/// Rayleigh damping.
fn held_chain(n: usize, free: bool, lumped: bool, upper: bool, load: (f64, f64, f64), damping: Option<(f64, f64)>) -> Dynamics {
    let (mut m, k) = common::chain_matrices(n, free);
    if lumped {
        let mut l = SymBand::zeros(n, 1);
        for i in 0..n {
            let row = m.get(i, i) + if i > 0 { m.get(i, i - 1) } else { 0.0 } + if i + 1 < n { m.get(i + 1, i) } else { 0.0 };
            l.set(i, i, row);
        }
        m = l;
    }
    let bounds = if upper { Bounds { lo: f64::NEG_INFINITY, hi: 0.0 } } else { Bounds::obstacle(0.0) };
    let mut shape = vec![0.0; n];
    shape[0] = if upper { 1.0 } else { -1.0 };
    let (a, w, p) = load;
    let c = damping.map(|(alpha, beta)| common::rayleigh(&m, &k, alpha, beta));
    Dynamics::new(m, k, vec![0.0; n], vec![Contact::new(0, bounds, false)]).with_forcing(vec![Forcing { shape, time: sine(a, w, p) }]).with_damping(c)
}

/// The case: a clamped two-element bar (here the chains of 2, 3 and
/// 5 dofs, std and lumped, clamped and free) pressed by `−sin t` is held
/// until t = π exactly, then released; the run goes on to t = 20.
#[test]
fn held_bars_under_minus_sin_t_are_released_at_pi() {
    for n in [2, 3, 5] {
        for free in [false, true] {
            for lumped in [false, true] {
                let dy = held_chain(n, free, lumped, false, (1.0, 1.0, 0.0), None);
                let mut r = EventDriven::new(&dy, 0.0, &vec![0.0; n], &vec![0.0; n], 0.0).expect("starts");
                r.run_until(20.0, 10_000).unwrap_or_else(|e| panic!("n = {n}, free = {free}, lumped = {lumped}: {e}"));
                let ev = r.events();
                common::check_order(ev).unwrap_or_else(|e| panic!("n = {n}, free = {free}, lumped = {lumped}: {e}"));
                assert_eq!(ev[0].kind, EventKind::Release);
                assert!((ev[0].t - PI).abs() <= 4.0 * f64::EPSILON * PI, "released at {}", ev[0].t);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]
    /// Held starts under random reversing loads: chains of 2–6 dofs, every
    /// mass, both far ends, either side of the stop, with and without
    /// damping. The first event is the release where the load changes
    /// sign, `t_r = (π − p)/ω`, to 1e-12; the run completes over three
    /// load periods with every event in time order.
    #[test]
    fn held_starts_under_reversing_loads_are_released_where_the_load_changes_sign(
        n in 2usize..=6, free: bool, lumped: bool, upper: bool,
        amplitude in 0.1f64..3.0, omega in 0.2f64..4.0, phase in 0.05f64..(PI - 0.05),
        damped: bool, alpha in 0.0f64..0.3, beta in 0.0f64..0.1,
    ) {
        let dy = held_chain(n, free, lumped, upper, (amplitude, omega, phase), damped.then_some((alpha, beta)));
        let mut r = EventDriven::new(&dy, 0.0, &vec![0.0; n], &vec![0.0; n], 0.0).expect("starts");
        let t_end = 3.0 * TAU / omega;
        r.run_until(t_end, 100_000).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let ev = r.events();
        common::check_order(ev).map_err(TestCaseError::fail)?;
        let t_r = (PI - phase) / omega;
        prop_assert_eq!(ev[0].kind, EventKind::Release);
        prop_assert!((ev[0].t - t_r).abs() <= 1e-12 * t_r.max(1.0), "released at {} against {}", ev[0].t, t_r);
    }

    /// Plastic impacts into held phases from a free start (the oscillator
    /// `x'' + 2ζx' + x = cos(Ω t)`, `x <= 0.2`, e = 0; the Ω = 0.5,
    /// 1.0, 1.1 among them): every run completes over 30 forcing periods,
    /// in time order.
    #[test]
    fn plastic_impacts_into_held_phases_complete(omega in prop_oneof![Just(0.5), Just(1.0), Just(1.1), 0.3f64..3.0], zeta in prop_oneof![Just(0.0), 0.0f64..0.2]) {
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: f64::NEG_INFINITY, hi: 0.2 }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: sine(1.0, omega, FRAC_PI_2) }])
            .with_damping((zeta > 0.0).then(|| SymBand::from_diagonal(&[2.0 * zeta])));
        let mut r = EventDriven::new(&dy, 0.0, &[0.0], &[0.0], 0.0).expect("starts");
        r.run_until(30.0 * TAU / omega, 100_000).map_err(|e| TestCaseError::fail(e.to_string()))?;
        common::check_order(r.events()).map_err(TestCaseError::fail)?;
    }
}

/// Held starts where the load is tangent to 0 at t = 0 (`x'' + x = f`,
/// `x >= 0`, at rest on the stop). `f = cos t − 1` presses, its force
/// `1 − cos t` touching 0 at t = 0 (a wave's rate read as 6e-17 there was
/// a release: release → landing → release at t = 0 until `NoProgress`):
/// held, `x ≡ 0`. `f = 1 − cos t` pulls from a double zero: the contact
/// leaves as `x = 1 − cos t − (t/2) sin t ≈ t⁴/24` (read up to the third
/// derivative the gap's start was an approach: the same cycle), lands at
/// t = 2π at the speed −π, leaves at `e π`, and from the double zero there
/// as before: `x = 1 − cos t − ((t − 2π)/2 − e π) sin t` (closed forms).
#[test]
fn held_starts_under_loads_tangent_to_zero_press_or_leave_as_the_closed_form() {
    for (sign, e) in [(-1.0, 0.0), (-1.0, 1.0), (1.0, 0.0), (1.0, 0.5), (1.0, 1.0)] {
        // f = sign (1 − cos t).
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![sign], vec![Contact::new(0, Bounds::obstacle(0.0), false)])
            .with_forcing(vec![Forcing { shape: vec![-sign], time: sine(1.0, 1.0, FRAC_PI_2) }]);
        let mut r = EventDriven::new(&dy, 0.0, &[0.0], &[0.0], e).expect("starts");
        for k in 1..=30 {
            let t = 0.25 * k as f64;
            r.run_until(t, 1000).unwrap_or_else(|err| panic!("f = {sign} (1 − cos t), e = {e}: {err}"));
            let (_, q, v) = r.state();
            let (s, c) = t.sin_cos();
            let b = if t < TAU { 0.5 * t } else { 0.5 * (t - TAU) - e * PI };
            let (qx, vx) = if sign > 0.0 { (1.0 - c - b * s, 0.5 * s - b * c) } else { (0.0, 0.0) };
            assert!((q[0] - qx).abs() <= 1e-13 && (v[0] - vx).abs() <= 1e-13, "f = {sign} (1 − cos t), e = {e}, t = {t}: ({}, {}) against ({qx}, {vx})", q[0], v[0]);
        }
        let ev = r.events();
        common::check_order(ev).unwrap();
        if sign > 0.0 {
            // Released at 0; one impact, at 2π, at the speed −π.
            assert!(ev.iter().all(|x| x.kind == EventKind::Release && (x.t == 0.0 || (x.t - TAU).abs() <= 1e-14) || x.kind == EventKind::Impact), "{ev:?}");
            let imp: Vec<_> = ev.iter().filter(|x| x.kind == EventKind::Impact).collect();
            assert!(imp.len() == 1 && (imp[0].t - TAU).abs() <= 1e-13 && (imp[0].velocity_before + PI).abs() <= 1e-13, "{ev:?}");
        }
    }
}
