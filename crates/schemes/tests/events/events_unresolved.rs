//! Elastic rebounds with no length but the model's own (a stop at 0, a
//! start at 0): `x'' + x = −1` from `(0, v₀)`, `e = 1`. Oracle: the closed
//! form `x = −1 + cos t + v₀ sin t` of each flight, landing at
//! `t = 2 atan v₀` (`tan(t/2) = v₀`) at the speed `−v₀`, rising `≈ v₀²/2`.
//! A rise within the position's round-off (`ε` of the length `|f|/k = 1`)
//! is taken at rest (docs/theory.md §9.3); one above it is resolved,
//! landing by landing.

use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind};
use signorini_schemes::{Bounds, Contact, Dynamics};

fn pressed_oscillator() -> Dynamics {
    Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![-1.0], vec![Contact::new(0, Bounds::obstacle(0.0), false)])
}

#[test]
fn elastic_rebounds_below_the_band_of_the_models_own_length_are_at_rest() {
    let dy = pressed_oscillator();
    for v0 in [1e-17, 1e-9, 2e-8, -1e-17, -1e-9, -2e-8] {
        let rise = 0.5 * v0 * v0;
        assert!(rise <= f64::EPSILON, "the case's rise {rise} is below the band");
        let mut r = EventDriven::new(&dy, 0.0, &[0.0], &[v0], 1.0).expect("starts");
        r.run_until(1.0, 100).unwrap_or_else(|e| panic!("v₀ = {v0}: {e}"));
        let (_, q, v) = r.state();
        // The exact motion stays within [0, rise] at speeds up to |v₀|.
        assert!(q[0] >= 0.0 && q[0] <= rise && v[0].abs() <= v0.abs(), "v₀ = {v0}: ({}, {})", q[0], v[0]);
        let ev = r.events();
        assert!(ev.len() <= 2 && ev.iter().all(|e| e.t == 0.0) && ev.last().is_some_and(|e| e.kind == EventKind::Accumulation), "v₀ = {v0}: {ev:?}");
    }
}

#[test]
fn elastic_rebounds_above_the_band_land_as_the_closed_form() {
    let dy = pressed_oscillator();
    // Rise 5e-13, 2250 round-offs; 50 landings to t = 1e-4.
    let v0 = 1e-6f64;
    let period = 2.0 * v0.atan();
    let mut r = EventDriven::new(&dy, 0.0, &[0.0], &[v0], 1.0).expect("starts");
    r.run_until(50.5 * period, 1000).expect("completes");
    let ev = r.events();
    assert_eq!(ev.len(), 50, "{ev:?}");
    for (k, e) in ev.iter().enumerate() {
        let t = (k + 1) as f64 * period;
        assert!(e.kind == EventKind::Impact && (e.t - t).abs() <= 1e-15 * (k + 1) as f64, "landing {k} at {} against {t}", e.t);
        assert!((e.velocity_before + v0).abs() <= 1e-15 * v0 && (e.velocity_after - v0).abs() <= 1e-15 * v0, "landing {k}: {e:?}");
    }
}
