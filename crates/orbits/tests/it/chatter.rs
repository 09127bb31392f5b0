//! An orbit that chatters to rest on the stop and is held there until the
//! force lets go (the oscillator with r = 0.5 at Ω = 0.3 and 0.5): every
//! start near it leaves the held phase in the same state, at the same time
//! — the force's zero `F cos Ωt = k g`, the force falling — so the map's
//! Jacobian is 0 and the orbit is superstable. Checked against that
//! release time, against the section state where the section falls in the
//! held phase (at rest on the stop: at t = 0 the force `F = 1` presses it
//! on, `k g = 0.2`), and against central differences of the exact map.

use signorini_fem::SymBand;
use signorini_orbits::{periodic_orbit, Model, Newton};
use signorini_schemes::events::EventKind;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::f64::consts::{FRAC_PI_2, TAU};
use std::sync::Arc;

const G: f64 = 0.2;
const R: f64 = 0.5;

fn model(w: f64) -> Model {
    let one = |v: f64| {
        let mut b = SymBand::zeros(1, 0);
        b.set(0, 0, v);
        b
    };
    let dy = Dynamics::new(one(1.0), one(1.0), vec![0.0], vec![Contact::new(0, Bounds { lo: f64::NEG_INFINITY, hi: G }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: 1.0, omega: w, phase: FRAC_PI_2 }])) }])
        .with_damping(Some(one(0.1)));
    Model::new(dy, R).unwrap()
}

/// The orbit at `w` from the state after 50 periods from rest: released
/// at the force's zero, superstable, its Jacobian 0 as differences; its
/// section state `held` when given.
fn check(w: f64, held: Option<[f64; 2]>) {
    let m = model(w);
    let t = TAU / w;
    let mut x = vec![0.0, 0.0];
    for _ in 0..50 {
        x = m.flow(0.0, &x, t, false).unwrap().x;
    }
    let orbit = periodic_orbit(&m, 0.0, t, &x, &Newton::default()).unwrap_or_else(|e| panic!("Ω = {w}: {e}"));
    assert!(orbit.events.iter().any(|e| e.kind == EventKind::Accumulation) && orbit.releases() == 1, "Ω = {w}: it chatters to rest and is held once");
    let release = G.acos() / w;
    let rel = orbit.events.iter().find(|e| e.kind == EventKind::Release).unwrap();
    assert!((rel.t - release).abs() < 1e-9, "Ω = {w}: released at {} vs the force's zero {release}", rel.t);
    if let Some(z) = held {
        assert!((orbit.x[0] - z[0]).abs() <= 1e-12 && orbit.x[1].abs() <= 1e-12, "Ω = {w}: section state {:?} vs {z:?}", orbit.x);
    }
    assert!(orbit.multipliers.iter().all(|mu| mu.norm() <= 1e-12), "Ω = {w}: {:?}", orbit.multipliers);
    for c in 0..2 {
        for h in [1e-4, 1e-6] {
            let (mut p, mut q) = (orbit.x.clone(), orbit.x.clone());
            p[c] += h;
            q[c] -= h;
            let (fp, fq) = (m.flow(0.0, &p, t, false).unwrap().x, m.flow(0.0, &q, t, false).unwrap().x);
            for r in 0..2 {
                let fd = (fp[r] - fq[r]) / (2.0 * h);
                let j = orbit.monodromy[(r, c)];
                assert!(fd.abs() <= 1e-8 && j == 0.0, "Ω = {w}: J[{r},{c}] = {j} vs differences {fd} (h = {h})");
            }
        }
    }
}

#[test]
fn an_orbit_chattering_to_a_held_phase_is_superstable_with_a_zero_jacobian() {
    // The section in the held phase, and in the free flight after it.
    check(0.3, Some([G, 0.0]));
    check(0.5, None);
}
