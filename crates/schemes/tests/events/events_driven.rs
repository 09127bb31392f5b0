//! Event-driven runs against closed forms: an oscillator bouncing on a
//! stop (event times, energy over 10⁴ impacts), the loss of each impact on
//! a chain, and the period-1 orbits of the forced impact oscillator that
//! `signorini-exact` computes in closed form.

use crate::events_common as common;

use signorini_exact::{ImpactOscillator, OscillatorParams};
use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::f64::consts::PI;

/// `x'' + x = 0` from `x = 1` onto a stop at `−1/2` with `e = 1`: impacts at
/// `2π/3 + k 4π/3` (the bounce mirrors the fall), the energy `1/2` kept.
#[test]
fn an_elastic_bounce_keeps_its_energy_over_ten_thousand_impacts() {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(-0.5), false)]);
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

/// The same bounce from `x = 0, v = −1` onto a stop at `−1/2` over
/// `2·10⁴` (4 775 impacts), read every `10⁻²`, every 1 and only at the end:
/// the impacts at `t₁ + k (π + 2 t₁)`, `t₁ = asin ½` (the free arc above the
/// stop is `π + 2 t₁` long), to `10⁻⁸` however long the run; the events
/// and the states at common sample times bit-identical whatever the
/// sampling (a sample reads the flow, it never re-bases it).
#[test]
fn an_elastic_bounce_does_not_drift_over_long_runs_at_any_sampling() {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(-0.5), false)]);
    let t_end = 2e4;
    let run = |dt: f64| {
        let mut r = EventDriven::new(&dy, 0.0, &[0.0], &[-1.0], 1.0).unwrap();
        let samples = (t_end / dt).round() as usize;
        let mut every_unit = Vec::new();
        for k in 1..=samples {
            let t = k as f64 * dt;
            r.run_until(t, 10_000).unwrap();
            let (tr, q, v) = r.state();
            assert_eq!(tr, t);
            if (t - t.round()).abs() < 1e-9 * dt && t.round() as usize % 1000 == 0 {
                every_unit.push((q[0].to_bits(), v[0].to_bits()));
            }
        }
        (r.events().to_vec(), every_unit, r.state())
    };
    let (t1, period) = (0.5f64.asin(), std::f64::consts::PI + 2.0 * 0.5f64.asin());
    let (events, samples, end) = run(1e-2);
    assert_eq!(events.len(), ((t_end - t1) / period).floor() as usize + 1);
    let mut drift = 0.0f64;
    for (k, e) in events.iter().enumerate() {
        drift = drift.max((e.t - (t1 + k as f64 * period)).abs());
        assert!((e.velocity_before + 3f64.sqrt() / 2.0).abs() <= 1e-12, "impact {k}: {e:?}");
    }
    assert!(drift <= 1e-8, "impact times drift {drift:e} from the closed form");
    let energy = 0.5 * end.1[0] * end.1[0] + 0.5 * end.2[0] * end.2[0];
    assert!((energy - 0.5).abs() <= 1e-12, "energy {energy}");
    for dt in [1.0, t_end] {
        let (other, other_samples, other_end) = run(dt);
        assert_eq!(other.len(), events.len(), "dt = {dt}");
        for (a, b) in events.iter().zip(&other) {
            assert!(a.t.to_bits() == b.t.to_bits() && a.velocity_before.to_bits() == b.velocity_before.to_bits(), "dt = {dt}: {a:?} against {b:?}");
        }
        assert!(other_end.1[0].to_bits() == end.1[0].to_bits() && other_end.2[0].to_bits() == end.2[0].to_bits(), "dt = {dt}: the end state differs");
        if dt == 1.0 {
            assert_eq!(other_samples, samples, "the state at t = 1000 k");
        }
    }
}

/// Chatter: `x'' + x = −F` leaving its stop at `x = 0` with speed `v₀`
/// and restitution `r` flies `2 atan(v/F)` (the flight from the stop back
/// to it at the same speed), so the impacts are at `t_k = Σ_{j<k} 2
/// atan(r^j v₀/F)` with speeds `r^k v₀`, and accumulate at the sum of the
/// series; then the contact is held for good (its force `F`). Every impact
/// down to a speed of 1e-6 of the first to 1e-12 in time and in relative
/// speed, the accumulation to 1e-12 (before the flight was advanced as
/// increments, `−F + F cos τ` lost the short flights' precision: 5e-12 s
/// and 2e-8 in speed).
#[test]
fn chatter_under_a_steady_force_matches_its_closed_form() {
    for (f, r, v0) in [(1.0, 0.5, 1.0), (1.0, 0.8, 1.0), (0.3, 0.5, 2.0), (2.0, 0.3, 0.7)] {
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![-f], vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
        let mut run = EventDriven::new(&dy, 0.0, &[0.0], &[v0], r).unwrap();
        run.run_until(30.0, 10_000).unwrap();
        let ev = run.events();
        let (mut t, mut v, mut k) = (0.0f64, v0, 0);
        let mut t_inf = 0.0;
        let mut vv = v0;
        for _ in 0..4000 {
            t_inf += 2.0 * (vv / f).atan();
            vv *= r;
        }
        while v > 1e-6 * v0 {
            t += 2.0 * (v / f).atan();
            let e = &ev[k];
            assert_eq!(e.kind, EventKind::Impact, "(F, r) = ({f}, {r}): event {k} {e:?}");
            assert!((e.t - t).abs() <= 1e-12, "(F, r) = ({f}, {r}): impact {k} at {} against {t}", e.t);
            assert!((-e.velocity_before - v).abs() <= 1e-12 * v, "(F, r) = ({f}, {r}): impact {k} at speed {} against {v}", -e.velocity_before);
            v *= r;
            k += 1;
        }
        let last = ev.last().unwrap();
        assert_eq!(last.kind, EventKind::Accumulation, "(F, r) = ({f}, {r}): {last:?}");
        assert!((last.t - t_inf).abs() <= 1e-12, "(F, r) = ({f}, {r}): accumulation at {} against {t_inf}", last.t);
        let (_, q, vel) = run.state();
        assert!(q[0] == 0.0 && vel[0] == 0.0, "held at the stop: {q:?} {vel:?}");
    }
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
        let after = energy(&q, &v);
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
    let dy = Dynamics::new(SymBand::from_diagonal(&[p.mass]), SymBand::from_diagonal(&[p.stiffness]), vec![0.0], vec![stop])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: cosine }])
        .with_damping(Some(SymBand::from_diagonal(&[c])));
    let period = 2.0 * PI / p.forcing_frequency;
    for o in orbits {
        let tau = o.impact_time;
        let mut r = EventDriven::new(&dy, tau, &[p.gap], &[-p.restitution * o.impact_velocity], p.restitution).unwrap();
        let ev = r.next_event(tau + 1.5 * period).unwrap().expect("the next impact");
        assert!((ev.t - (tau + period)).abs() <= 1e-12 * period, "impact at {} against {}", ev.t, tau + period);
        assert!((ev.velocity_before - o.impact_velocity).abs() <= 1e-12 * o.impact_velocity.abs(), "{} against {}", ev.velocity_before, o.impact_velocity);
    }
}

/// A ball `x'' = −g` dropped from `h` onto `x >= 0` with `0 < e < 1`: the
/// impacts at `t₁ = √(2h/g)`, `t_{k+1} = t_k + 2 eᵏ v₁/g` (`v₁ = √(2gh)`)
/// accumulate at `t∞ = t₁ + 2 e v₁ / (g (1 − e))`; after it the ball rests,
/// held with the force `m g`.
#[test]
fn a_bouncing_ball_accumulates_at_its_closed_form_time_and_rests() {
    let (g, h, m) = (9.81, 1.3, 2.0);
    for e in [0.3, 0.5, 0.8] {
        let dy = Dynamics::new(SymBand::from_diagonal(&[m]), SymBand::from_diagonal(&[0.0]), vec![-m * g], vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
        let mut r = EventDriven::new(&dy, 0.0, &[h], &[0.0], e).unwrap();
        let v1 = (2.0 * g * h).sqrt();
        let t1 = (2.0 * h / g).sqrt();
        let t_inf = t1 + 2.0 * e * v1 / (g * (1.0 - e));
        r.run_until(t_inf + 1.0, 100_000).unwrap();
        let ev = r.events();
        let acc = ev.iter().position(|x| x.kind == EventKind::Accumulation).expect("an accumulation");
        assert_eq!(acc, ev.len() - 1, "nothing after the accumulation: {:?}", &ev[acc..]);
        let mut want = t1;
        for (k, x) in ev[..acc].iter().enumerate() {
            assert_eq!(x.kind, EventKind::Impact);
            assert!((x.t - want).abs() <= 1e-12 * want, "e = {e}: impact {k} at {} against {want}", x.t);
            let vk = v1 * e.powi(k as i32);
            assert!((x.velocity_before + vk).abs() <= 1e-9 * v1, "e = {e}: impact {k} velocity {} against {}", x.velocity_before, -vk);
            assert!((x.impulse - m * (1.0 + e) * vk).abs() <= 1e-9 * m * v1);
            want += 2.0 * e.powi(k as i32 + 1) * v1 / g;
        }
        assert!((ev[acc].t - t_inf).abs() <= 1e-12 * t_inf, "e = {e}: accumulation at {} against {t_inf}", ev[acc].t);
        let (t, q, v) = r.state();
        assert_eq!((t, q[0], v[0]), (t_inf + 1.0, 0.0, 0.0));
        assert_eq!(r.held(), vec![(0, false)]);
        assert!((r.forces()[0] - m * g).abs() <= 1e-12 * m * g);
    }
}

/// `x'' + x = −1 + 2 sin 2t` held on `x >= 0` from rest (`e = 0`): the
/// force `r = −F(t)` reaches 0 at `t = π/12`; then the free flight is
/// `x = −1 + C₁ cos t + C₂ sin t − (2/3) sin 2t` from `x = x' = 0` there.
#[test]
fn a_held_oscillator_is_released_when_its_force_vanishes() {
    let sine2 = TimeProfile::Sine { amplitude: 2.0, omega: 2.0 };
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![-1.0], vec![Contact::new(0, Bounds::obstacle(0.0), false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: sine2 }]);
    let mut r = EventDriven::new(&dy, 0.0, &[0.0], &[0.0], 0.0).unwrap();
    assert_eq!(r.held(), vec![(0, false)]);
    let tr = PI / 12.0;
    // The force while held: r = 1 − 2 sin 2t.
    r.run_until(0.1, 10).unwrap();
    assert!((r.forces()[0] - (1.0 - 2.0 * (0.2f64).sin())).abs() <= 1e-14);
    // Its integral over [0, 0.1]: t + (cos 2t − 1).
    let imp = r.take_impulses()[0];
    assert!((imp - (0.1 + ((0.2f64).cos() - 1.0))).abs() <= 1e-14, "{imp}");
    let ev = r.next_event(1.0).unwrap().expect("the release");
    assert_eq!(ev.kind, EventKind::Release);
    assert!((ev.t - tr).abs() <= 1e-14 * tr, "release at {} against {tr}", ev.t);
    // x(tr) = x'(tr) = 0: C₁ cos + C₂ sin = 1 + (2/3) sin 2tr, −C₁ sin + C₂ cos = (4/3) cos 2tr.
    let (a, b) = (1.0 + 2.0 / 3.0 * (2.0 * tr).sin(), 4.0 / 3.0 * (2.0 * tr).cos());
    let (c1, c2) = (a * tr.cos() - b * tr.sin(), a * tr.sin() + b * tr.cos());
    let x = |t: f64| -1.0 + c1 * t.cos() + c2 * t.sin() - 2.0 / 3.0 * (2.0 * t).sin();
    let dx = |t: f64| -c1 * t.sin() + c2 * t.cos() - 4.0 / 3.0 * (2.0 * t).cos();
    // It lifts off (x > 0 just after) and flies until it lands again.
    let t_probe = tr + 0.3;
    assert!(x(t_probe) > 0.0);
    let next = r.next_event(t_probe).unwrap();
    assert!(next.is_none(), "{next:?}");
    let (_, q, v) = r.state();
    assert!((q[0] - x(t_probe)).abs() <= 1e-13 && (v[0] - dx(t_probe)).abs() <= 1e-13, "{} {} against {} {}", q[0], v[0], x(t_probe), dx(t_probe));
}

/// A free chain of three masses (consistent mass) falling flat onto two
/// stops under its ends: both impacts are simultaneous and solved as one
/// LCP on the Delassus matrix `W = (M⁻¹)_{cc}`: with both active,
/// `W p = −(1 + e) v_c⁻`, `v⁺ = v⁻ + M⁻¹ E p` — computed here by a dense
/// inverse written in the test, against the events' impulses.
#[test]
fn simultaneous_impacts_are_one_lcp() {
    let (m, k) = common::chain_matrices(3, true);
    let contacts = vec![Contact::new(0, Bounds::obstacle(0.0), false), Contact::new(2, Bounds::obstacle(0.0), false)];
    let dy = Dynamics::new(m.clone(), k, vec![0.0; 3], contacts);
    let e = 0.7;
    let v0 = [-1.0, -1.0, -1.0];
    let mut r = EventDriven::new(&dy, 0.0, &[0.5, 0.5, 0.5], &v0, e).unwrap();
    let first = r.next_event(1.0).unwrap().expect("the impacts");
    assert!((first.t - 0.5).abs() <= 1e-15);
    let ev = r.events().to_vec();
    assert_eq!(ev.len(), 2, "{ev:?}");
    // Dense M⁻¹ by Gauss–Jordan.
    let mut a: Vec<Vec<f64>> = (0..3).map(|i| (0..3).map(|j| m.get(i, j)).chain((0..3).map(move |j| if i == j { 1.0 } else { 0.0 })).collect()).collect();
    for p in 0..3 {
        let piv = a[p][p];
        a[p].iter_mut().for_each(|x| *x /= piv);
        for r in 0..3 {
            if r != p {
                let f = a[r][p];
                let row = a[p].clone();
                a[r].iter_mut().zip(&row).for_each(|(x, y)| *x -= f * y);
            }
        }
    }
    let minv = |i: usize, j: usize| a[i][3 + j];
    let (w00, w02, w22) = (minv(0, 0), minv(0, 2), minv(2, 2));
    let (b0, b2) = (-(1.0 + e) * v0[0], -(1.0 + e) * v0[2]);
    let det = w00 * w22 - w02 * w02;
    let (p0, p2) = ((w22 * b0 - w02 * b2) / det, (w00 * b2 - w02 * b0) / det);
    assert!(p0 > 0.0 && p2 > 0.0);
    for x in &ev {
        let want = if x.contact == 0 { p0 } else { p2 };
        assert!((x.impulse - want).abs() <= 1e-12 * want, "contact {}: {} against {want}", x.contact, x.impulse);
        assert!((x.velocity_after - e).abs() <= 1e-12);
    }
    let (_, _, v) = r.state();
    let v1 = v0[1] + minv(1, 0) * p0 + minv(1, 2) * p2;
    assert!((v[1] - v1).abs() <= 1e-12, "{} against {v1}", v[1]);
}

/// A mass resting on its stop with no load (its contact force identically
/// zero, every derivative zero) stays held: no release, no impact — a
/// held force that stays at zero is no event (the release's `quiet` rule;
/// without it the run would release and re-impact at the same time until
/// its event limit).
#[test]
fn a_mass_resting_on_its_stop_without_load_makes_no_event() {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
    let mut r = EventDriven::new(&dy, 0.0, &[0.0], &[0.0], 0.0).unwrap().with_max_events(100);
    r.run_until(10.0, 100).unwrap();
    assert!(r.events().is_empty(), "{:?}", &r.events()[..r.events().len().min(3)]);
    let (t, q, v) = r.state();
    assert_eq!((t, q[0], v[0]), (10.0, 0.0, 0.0));
}

/// Equal bounds `lo = hi` make a bilateral constraint: the dof is stopped
/// at once and held for good, its force taking both signs (a harmonic load
/// pushes and pulls it), with no release — for a massive dof and for a
/// massless one (then the chain's dof 0 is massless). The other dofs follow
/// the flow of the chain with dof 0 removed (a Dirichlet condition;
/// `ModalFlow`, itself tested against the matrix exponential).
#[test]
fn equal_bounds_hold_the_dof_for_good() {
    use signorini_schemes::events::ModalFlow;
    let n = 4;
    for massless in [false, true] {
        let (mut m, k) = common::chain_matrices(n, false);
        if massless {
            m.set(1, 1, m.get(1, 1) + m.get(0, 0));
            m.set(0, 0, 0.0);
            m.set(1, 0, 0.0);
        }
        let forcing = vec![Forcing { shape: vec![1.0, 0.3, 0.0, 0.0], time: TimeProfile::Sine { amplitude: 0.8, omega: 1.1 } }];
        let dy = Dynamics::new(m.clone(), k.clone(), vec![0.0; n], vec![Contact::new(0, Bounds { lo: 0.0, hi: 0.0 }, massless)]).with_forcing(forcing.clone());
        let (q0, v0) = ([0.0, 0.1, -0.05, 0.02], [if massless { 0.0 } else { 0.3 }, -0.2, 0.1, 0.0]);
        let mut run = EventDriven::new(&dy, 0.0, &q0, &v0, if massless { 0.0 } else { 0.5 }).unwrap_or_else(|e| panic!("massless {massless}: {e}"));
        // The chain without dof 0.
        let sub = |a: &SymBand| {
            let mut b = SymBand::zeros(n - 1, 1);
            for i in 1..n {
                for j in i.saturating_sub(1).max(1)..=i {
                    b.set(i - 1, j - 1, a.get(i, j));
                }
            }
            b
        };
        let pinned = Dynamics::new(sub(&m), sub(&k), vec![0.0; n - 1], vec![Contact::new(0, Bounds::obstacle(-1e9), false)])
            .with_forcing(vec![Forcing { shape: vec![0.3, 0.0, 0.0], time: TimeProfile::Sine { amplitude: 0.8, omega: 1.1 } }]);
        let flow = ModalFlow::new(&pinned).unwrap();
        // The post-impact velocities: M-projection with v_0 = 0, i.e. the
        // chain's momentum kept on the others (massive case); massless: as given.
        let (_, _, v_start) = run.state();
        let (mut signs, mut t) = ([false; 2], 0.0);
        while t < 20.0 {
            t += 0.25;
            run.run_until(t, 10).unwrap();
            let imp = run.take_impulses()[0];
            signs[usize::from(imp > 0.0)] |= imp != 0.0;
            let (_, q, v) = run.state();
            assert!(q[0] == 0.0 && v[0] == 0.0, "massless {massless}, t = {t}: q_0 = {}, v_0 = {}", q[0], v[0]);
            let (mut qr, mut vr) = (vec![0.0; n - 1], vec![0.0; n - 1]);
            flow.advance(0.0, &q0[1..], &v_start[1..], t, &mut qr, &mut vr);
            for i in 1..n {
                assert!((q[i] - qr[i - 1]).abs() <= 1e-11 && (v[i] - vr[i - 1]).abs() <= 1e-11, "massless {massless}, t = {t}, dof {i}: ({}, {}) against ({}, {})", q[i], v[i], qr[i - 1], vr[i - 1]);
            }
        }
        assert!(signs[0] && signs[1], "massless {massless}: the force took one sign only");
        let ev = run.events();
        assert!(ev.iter().all(|e| e.kind == EventKind::Impact && e.t == 0.0), "massless {massless}: {ev:?}");
    }
}
