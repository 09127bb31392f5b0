//! Event-driven runs against closed forms: an oscillator bouncing on a
//! stop (event times, energy over 10⁴ impacts), the loss of each impact on
//! a chain, and the period-1 orbits of the forced impact oscillator that
//! `signorini-exact` computes in closed form.

mod common;

use signorini_events::{EventDriven, EventKind};
use signorini_exact::{ImpactOscillator, OscillatorParams};
use signorini_fem::SymBand;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::f64::consts::PI;

fn one(v: f64) -> SymBand {
    let mut b = SymBand::zeros(1, 0);
    b.set(0, 0, v);
    b
}

/// `x'' + x = 0` from `x = 1` onto a stop at `−1/2` with `e = 1`: impacts at
/// `2π/3 + k 4π/3` (the bounce mirrors the fall), the energy `1/2` kept.
#[test]
fn an_elastic_bounce_keeps_its_energy_over_ten_thousand_impacts() {
    let dy = Dynamics::new(one(1.0), one(1.0), vec![0.0], vec![Contact::new(0, Bounds::obstacle(-0.5), false)]);
    let mut r = EventDriven::new(&dy, 0.0, &[1.0], &[0.0], 1.0).unwrap();
    let impacts = 10_000;
    let t_end = 2.0 * PI / 3.0 + (impacts as f64 - 0.5) * 4.0 * PI / 3.0;
    r.run_until(t_end, impacts).unwrap();
    let ev = r.events();
    assert_eq!(ev.len(), impacts);
    for (k, e) in ev.iter().enumerate() {
        let want = 2.0 * PI / 3.0 + k as f64 * 4.0 * PI / 3.0;
        assert!((e.t - want).abs() <= 1e-12 * want, "impact {k} at {} against {want}", e.t);
        assert_eq!(e.kind, EventKind::Impact);
        assert!((e.velocity_before + 3f64.sqrt() / 2.0).abs() <= 1e-12, "{e:?}");
    }
    let (_, q, v) = r.state();
    let energy = 0.5 * v[0] * v[0] + 0.5 * q[0] * q[0];
    assert!((energy - 0.5).abs() <= 1e-12, "energy {energy}");
}

/// A chain with a stop under its first mass: each impact removes exactly
/// `(1 − e²)/2 (v_c⁻)² / (M⁻¹)_cc` (the effective mass of the contact dof),
/// the flow between impacts none (undamped, steady load).
#[test]
fn each_impact_loses_the_newton_energy() {
    let n = 4;
    let (m, k) = common::chain_matrices(n, false);
    let load = vec![-0.05; n];
    let dy = Dynamics::new(m.clone(), k.clone(), load.clone(), vec![Contact::new(0, Bounds::obstacle(-0.1), false)]);
    let e = 0.6;
    let q0 = vec![0.0; n];
    let v0 = vec![-0.4, -0.1, 0.2, 0.0];
    let energy = |q: &[f64], v: &[f64]| {
        let (mut mv, mut kq) = (vec![0.0; n], vec![0.0; n]);
        m.mul_vec(v, &mut mv);
        k.mul_vec(q, &mut kq);
        (0..n).map(|i| 0.5 * v[i] * mv[i] + 0.5 * q[i] * kq[i] - load[i] * q[i]).sum::<f64>()
    };
    // (M⁻¹)_00 by the fem crate's banded LDLᵀ (the events crate inverts M
    // through its faer modes): M x = e_0.
    let w = {
        let mut x = vec![0.0; n];
        x[0] = 1.0;
        m.factor().unwrap().solve_in_place(&mut x);
        x[0]
    };
    let mut r = EventDriven::new(&dy, 0.0, &q0, &v0, e).unwrap();
    let mut before = energy(&q0, &v0);
    let mut impacts = 0;
    // The first impacts: later ones accumulate toward rest on the stop
    // (chattering), whose held phase is not implemented yet.
    while let Some(ev) = r.next_event(40.0).unwrap() {
        let (_, q, v) = r.state();
        let after = energy(q, v);
        let loss = 0.5 * (1.0 - e * e) * ev.velocity_before * ev.velocity_before / w;
        // The flow between impacts keeps the energy to a relative 1e-12 or so.
        assert!((before - after - loss).abs() <= 1e-11 * before.abs(), "impact at {}: lost {} against {loss}", ev.t, before - after);
        assert!(loss > 1e-6 * before.abs(), "impact at {}: a loss of {loss} is too small to check", ev.t);
        assert!(ev.velocity_before < 0.0 && (ev.velocity_after + e * ev.velocity_before).abs() <= 1e-15);
        before = after;
        impacts += 1;
        if impacts == 6 {
            break;
        }
    }
    assert_eq!(impacts, 6);
}

/// The forced impact oscillator `m x'' + c x' + k x = F cos Ω t`, `x <= g`,
/// `v⁺ = −r v⁻`: from the post-impact state of a stable period-1 orbit of
/// `signorini-exact`, the next impact comes one forcing period later with
/// the same velocity.
#[test]
fn period_one_orbits_of_the_impact_oscillator_close() {
    let p = OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: 2.3, gap: 0.1, restitution: 0.8 };
    let osc = ImpactOscillator::new(p).unwrap();
    let orbits: Vec<_> = osc.period1_orbits().into_iter().filter(|o| o.is_admissible()).collect();
    assert!(!orbits.is_empty());
    let c = 2.0 * p.damping_ratio * (p.stiffness * p.mass).sqrt();
    let cosine = TimeProfile::harmonics(vec![Harmonic { amplitude: p.force, omega: p.forcing_frequency, phase: PI / 2.0 }]).unwrap();
    let stop = Contact::new(0, Bounds { lo: f64::NEG_INFINITY, hi: p.gap }, false).with_restitution(Some(p.restitution));
    let dy = Dynamics::new(one(p.mass), one(p.stiffness), vec![0.0], vec![stop]).with_forcing(vec![Forcing { shape: vec![1.0], time: cosine }]).with_damping(Some(one(c)));
    let period = 2.0 * PI / p.forcing_frequency;
    for o in orbits {
        let tau = o.impact_time;
        let mut r = EventDriven::new(&dy, tau, &[p.gap], &[-p.restitution * o.impact_velocity], p.restitution).unwrap();
        let ev = r.next_event(tau + 1.5 * period).unwrap().expect("the next impact");
        assert!((ev.t - (tau + period)).abs() <= 1e-12 * period, "impact at {} against {}", ev.t, tau + period);
        assert!((ev.velocity_before - o.impact_velocity).abs() <= 1e-12 * o.impact_velocity.abs(), "{} against {}", ev.velocity_before, o.impact_velocity);
    }
}
