//! A restitution so small that the rebound cannot be resolved in time
//! (docs/theory.md §9.3, "Rebounds below the time resolution").
//!
//! A mass `m = 1` without spring, pushed by `F = 1` from rest at `x = 0`
//! into its stop `x <= 1/2`: `x = t²/2` up to the impact at `t = 1` with
//! speed 1; after it, rebounds of total duration `2 e/(1 − e)` (the
//! velocity `e` against the acceleration 1) and then rest, held by the
//! force `r = −1`. For `e = 1e-20` or `1e-300` that duration is below the
//! time resolution: the run must end like `e = 0` (held at `1/2` from
//! `t = 1`), not search for a rebound it cannot resolve.

use signorini_fem::SymBand;
use signorini_schemes::events::{EventKind, EventStepper};
use signorini_schemes::{Bounds, Contact, Dynamics, Initial, Stepper};

const DT: f64 = 0.25;
const STEPS: usize = 16;

/// Levels `(x, v, λ)` of the run with restitution `e`, and its events.
fn run(e: f64) -> (Vec<(f64, f64, f64)>, Vec<signorini_schemes::events::EventRecord>) {
    let (m, k) = (SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[0.0]));
    let dy = Dynamics::new(m, k, vec![1.0], vec![Contact::new(0, Bounds { lo: f64::NEG_INFINITY, hi: 0.5 }, false)]);
    // At most 100 events: the run must not chatter either.
    let mut s = EventStepper::new(format!("event-driven({e})"), dy, e, DT, &Initial { u: vec![0.0], v: vec![0.0] }).unwrap().with_max_events(100);
    let mut levels = Vec::new();
    for _ in 0..STEPS {
        s.step().unwrap_or_else(|err| panic!("e = {e}: {err}"));
        let st = s.state().unwrap();
        levels.push((st[0], st[1], s.contact_forces()[0]));
    }
    (levels, s.events().to_vec())
}

#[test]
fn a_tiny_restitution_holds_the_mass_as_e_0_does() {
    let (plastic, _) = run(0.0);
    for e in [1e-20, 1e-300, 1e-10] {
        let (levels, events) = run(e);
        for (n, &(x, v, lambda)) in levels.iter().enumerate() {
            let t = (n + 1) as f64 * DT;
            // The closed form: free fall t²/2 up to t = 1, then held (at
            // t = 1 itself the velocity is 1 before the impact, 0 after).
            let (xe, ve) = if t < 1.0 { (0.5 * t * t, t) } else { (0.5, 0.0) };
            let dv = if t == 1.0 { v.min((v - 1.0).abs()) } else { (v - ve).abs() };
            assert!((x - xe).abs() <= 1e-12 && dv <= 1e-12, "e = {e}, t = {t}: (x, v) = ({x}, {v}), expected ({xe}, {ve})");
            // The mean contact force over a held step is F = 1; the steps
            // that end and start at t = 1 share the impulse 1.
            if n <= 2 || n >= 5 {
                let le = if n <= 2 { 0.0 } else { 1.0 };
                assert!((lambda - le).abs() <= 1e-9, "e = {e}, t = {t}: λ = {lambda}, expected {le}");
            }
            // As e = 0, to round-off and the rebound's speed e (e = 1e-10:
            // resolved, mid-rebound at t = 1).
            let (p, tol) = (plastic[n], 1e-15 + 2.0 * e);
            assert!((x - p.0).abs() <= tol && (v - p.1).abs() <= tol, "e = {e}, t = {t}: ({x}, {v}) vs e = 0: ({}, {})", p.0, p.1);
        }
        assert!(((levels[3].2 + levels[4].2) * DT - (1.0 + DT)).abs() <= 1e-9, "e = {e}: λ at t = 1 and 1.25: {} and {}", levels[3].2, levels[4].2);
        // The impact at t = 1 with speed 1, the rest at once; nothing after.
        assert_eq!(events[0].kind, EventKind::Impact);
        assert!((events[0].t - 1.0).abs() <= 1e-12 && (events[0].velocity_before - 1.0).abs() <= 1e-12);
        let last = events.last().unwrap();
        assert_eq!(last.kind, EventKind::Accumulation, "e = {e}: {events:?}");
        assert!((last.t - 1.0).abs() <= 1e-9 && last.velocity_after == 0.0, "e = {e}: {last:?}");
        assert!(events.len() <= 3, "e = {e}: {} events", events.len());
        // The impulses add up to the momentum taken, −1 (at the upper stop),
        // less F times the rebounds' duration 2e/(1 − e).
        let total: f64 = events.iter().map(|r| r.impulse).sum();
        assert!((total + 1.0).abs() <= 1e-9, "e = {e}: impulses {total}");
    }
}
