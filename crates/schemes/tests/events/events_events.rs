//! Locating the first contact event of a free flight: against closed forms
//! (a harmonic oscillator reaching a level), at grazing incidence, and
//! against a dense sampling of the flow that would expose a missed event.

use crate::events_common as common;
use proptest::prelude::*;

use signorini_fem::SymBand;
use signorini_schemes::events::{Bound, ModalFlow};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};

fn oscillator() -> Dynamics {
    let (m, k) = (SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]));
    Dynamics::new(m, k, vec![0.0], vec![Contact::new(0, Bounds::obstacle(-1.0), false)])
}

/// `x = cos t` reaches `−1/2` at `2π/3` and `1/2` (from below, after the
/// bounce of the cosine) never before it.
#[test]
fn a_harmonic_oscillator_reaches_a_level_at_its_arccos() {
    let f = ModalFlow::new(&oscillator()).unwrap();
    let e = f.first_crossing(0.0, &[1.0], &[0.0], 0, -0.5, 2.0, 10.0).unwrap().unwrap();
    let (t, side, q) = (e.t, e.bound, e.q);
    let want = 2.0 * std::f64::consts::PI / 3.0;
    assert_eq!(side, Bound::Lower);
    assert!((t - want).abs() <= 1e-14 * want, "{t} against {want}");
    assert!((q[0] + 0.5).abs() <= 1e-14);
    // From the bottom (x = −1 at t = π), the upper level 0.9 at 2π − arccos(0.9).
    let e = f.first_crossing(std::f64::consts::PI, &[-1.0], &[0.0], 0, -2.0, 0.9, 10.0).unwrap().unwrap();
    let (t, side) = (e.t, e.bound);
    let want = 2.0 * std::f64::consts::PI - 0.9f64.acos();
    assert_eq!(side, Bound::Upper);
    assert!((t - want).abs() <= 1e-14 * want, "{t} against {want}");
    // Not reached within the horizon.
    assert!(f.first_crossing(0.0, &[1.0], &[0.0], 0, -0.5, 2.0, 2.0).unwrap().is_none());
}

/// Grazing: a level 1e-10 above the minimum is reached (at arccos), one
/// 1e-9 below it is not.
#[test]
fn grazing_levels_are_found_or_not_as_they_are() {
    let f = ModalFlow::new(&oscillator()).unwrap();
    let lo = -1.0 + 1e-10;
    let t = f.first_crossing(0.0, &[1.0], &[0.0], 0, lo, 2.0, 10.0).unwrap().unwrap().t;
    let want = lo.acos();
    assert!((t - want).abs() <= 1e-9 * want, "{t} against {want}");
    assert!(f.first_crossing(0.0, &[1.0], &[0.0], 0, -1.0 - 1e-9, 2.0, 6.0).unwrap().is_none());
}

fn chain(n: usize) -> Dynamics {
    let (m, k) = common::chain_matrices(n, false);
    let mut dy = Dynamics::new(m, k, vec![0.05; n], vec![Contact::new(0, Bounds::obstacle(-1.0), false)]);
    dy.forcing = vec![Forcing {
        shape: (0..n).map(|i| 1.0 / (i as f64 + 1.0)).collect(),
        time: TimeProfile::harmonics(vec![Harmonic { amplitude: 0.3, omega: 1.7, phase: 0.2 }, Harmonic { amplitude: 0.1, omega: 3.1, phase: 0.0 }]).unwrap(),
    }];
    dy
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    /// Many modes, damping, forcing, random levels: the flow sampled at
    /// 20 000 times never leaves the bounds before the reported event, and
    /// is on the bound at it.
    #[test]
    fn no_event_is_missed(t0 in 0.0f64..5.0, lo in -0.6f64..-0.05, hi in 0.05f64..0.6, damped: bool) {
        let n = 5;
        let mut dy = chain(n);
        if damped {
            dy.damping = Some(dy.mass.lin_comb(0.02, &dy.stiffness, 0.01));
        }
        let f = ModalFlow::new(&dy).unwrap();
        let q0 = vec![0.0; n];
        let v0: Vec<f64> = (0..n).map(|i| 0.3 * ((i as f64) + 0.7).sin()).collect();
        let horizon = 30.0;
        let found = f.first_crossing(t0, &q0, &v0, 0, lo, hi, horizon).unwrap();
        let until = found.as_ref().map_or(horizon, |e| e.t - t0);
        let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
        let samples = 20_000;
        for s in 1..samples {
            let tau = until * s as f64 / samples as f64;
            f.advance(t0, &q0, &v0, tau, &mut q, &mut v);
            prop_assert!(q[0] > lo && q[0] < hi, "t = {}: q_c = {} outside [{lo}, {hi}] before the event found at {:?}", t0 + tau, q[0], found.as_ref().map(|e| e.t));
        }
        if let Some(e) = found {
            let level = if e.bound == Bound::Lower { lo } else { hi };
            prop_assert!((e.q[0] - level).abs() <= 1e-12, "at the event q_c = {} against {level}", e.q[0]);
        }
    }
}
