//! An applied event that logs nothing — a contact landing on its bound at
//! zero speed, no impact (docs/theory.md §9.3) — does not end the run. It
//! used to: `next_event` returned `None`, which its callers read as "the
//! time asked is reached", so `run_until(21)` returned with the clock at
//! 1.78 and a sampled run read a stale state (found by the orbits' tests on
//! the chain below).

use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind, Reached};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

fn band(a: [[f64; 2]; 2]) -> SymBand {
    let mut b = SymBand::zeros(2, 1);
    for i in 0..2 {
        for j in i..2 {
            b.set(i, j, a[i][j]);
        }
    }
    b
}

/// Two dofs, a consistent (full) mass, Rayleigh damping, the second dof
/// forced by `cos(0.3 t)` onto a stop at 0.2: with a small restitution it
/// chatters to rest, is held, leaves, and lands again.
fn chain() -> Dynamics {
    let m = [[2.0, 0.5], [0.5, 1.0]];
    let k = [[2.0, -1.0], [-1.0, 1.0]];
    let c = [[0.05 * m[0][0] + 0.02 * k[0][0], 0.05 * m[0][1] + 0.02 * k[0][1]], [0.05 * m[1][0] + 0.02 * k[1][0], 0.05 * m[1][1] + 0.02 * k[1][1]]];
    Dynamics::new(band(m), band(k), vec![0.0, 0.0], vec![Contact::new(1, Bounds { lo: f64::NEG_INFINITY, hi: 0.2 }, false)])
        .with_forcing(vec![Forcing { shape: vec![0.0, 1.0], time: TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: 1.0, omega: 0.3, phase: FRAC_PI_2 }])) }])
        .with_damping(Some(band(c)))
}

const Q0: [f64; 2] = [-0.49194903938110957, 0.19323241113402123];
const V0: [f64; 2] = [0.18367946682133252, -0.024464410042742635];

/// Every horizon asked is reached, and the state at t = 21 is the same
/// bits whether the run goes there at once or stops at 2, 3 and 6 on the
/// way (a run never re-bases on a sample), for the restitutions the
/// orbits' tests met it with (1e-6, 1e-12) and the plastic `e = 0`.
#[test]
fn a_landing_that_logs_nothing_does_not_end_the_run() {
    let dy = chain();
    for e in [1e-6, 1e-12, 0.0] {
        let mut sampled = EventDriven::new(&dy, 1.0, &Q0, &V0, e).unwrap();
        for t_end in [2.0, 3.0, 6.0, 21.0] {
            let mut direct = EventDriven::new(&dy, 1.0, &Q0, &V0, e).unwrap();
            direct.run_until(t_end, 1_000_000).unwrap();
            sampled.run_until(t_end, 1_000_000).unwrap();
            for run in [&direct, &sampled] {
                assert_eq!(run.time(), t_end, "e = {e}: run_until({t_end}) stopped at {}", run.time());
            }
            let ((_, qd, vd), (_, qs, vs)) = (direct.state(), sampled.state());
            for i in 0..2 {
                assert_eq!((qd[i].to_bits(), vd[i].to_bits()), (qs[i].to_bits(), vs[i].to_bits()), "e = {e}, t = {t_end}, dof {i}: ({}, {}) at once, ({}, {}) sampled", qd[i], vd[i], qs[i], vs[i]);
            }
        }
        // The case is the one meant: the contact is held at some point.
        assert!(sampled.events().iter().any(|r| r.kind == EventKind::Release), "e = {e}: {:?}", sampled.events());
    }
}

/// `next_change` reports each applied event, the silent ones as
/// `Event(None)`, and `End` only at the time asked.
#[test]
fn next_change_reports_the_silent_landings_and_ends_at_the_time_asked() {
    let dy = chain();
    let mut run = EventDriven::new(&dy, 1.0, &Q0, &V0, 1e-6).unwrap();
    let (mut silent, mut logged) = (0, 0);
    loop {
        match run.next_change(21.0).unwrap() {
            Reached::End => break,
            Reached::Event(None) => silent += 1,
            Reached::Event(Some(_)) => logged += 1,
        }
    }
    assert_eq!(run.time(), 21.0);
    assert!(silent >= 1 && logged >= 1, "silent {silent}, logged {logged}");
}
