//! The event-driven reference at the scales users meet (docs/theory.md
//! §9.1): a harmonic at and near a mode's resonance, weakly damped or not,
//! against the exponential ([`reference`], and [`replay`] for the runs'
//! impacts); a run scaled in length (`s` from 1e-150 to 1e150) or in time
//! against the unscaled one; gaps of 1e-15 to 1e-307 against closed forms;
//! damping of 1e-14 and 1e-10 against the undamped run (the difference is
//! O(damping)); a critically damped mode at `ζ = 1 ± 1e-12` against the
//! closed form of `ζ = 1`; a chain with one spring 1e4 times the others
//! against the exponential.

use crate::events_common as common;
use crate::events_flow::{flow_error, reference};
use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, ModalFlow};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};

/// An oracle's flight `(t, q, v, τ) ↦ (q, v)` after `τ`.
pub(crate) type Flight<'a> = dyn Fn(f64, &[f64], &[f64], f64) -> (Vec<f64>, Vec<f64>) + 'a;

/// A run's impacts replayed on an oracle: each flight from the oracle's own
/// state by `flight(t, q, v, τ)` ([`reference`], the exponential, or
/// events_stiff.rs's modal oracle), Newton's law applied here. Returns
/// the run's outcome, its search steps and the worst event-time error
/// `|gap| / |v|` at the recorded times, the worst relative impact speed and
/// the smallest gap over 49 samples of each flight (no crossing missed).
pub(crate) fn replay(dy: &Dynamics, q0: &[f64], v0: &[f64], e: f64, t_end: f64, flight: &Flight) -> (bool, u64, f64, f64, f64) {
    let n = dy.n();
    let (c, lo) = (dy.contacts[0].dof, dy.contacts[0].bounds.lo);
    let mut run = EventDriven::new(dy, 0.0, q0, v0, e).unwrap();
    let ok = run.run_until(t_end, 100_000).is_ok();
    let minv = common::inverse(&(0..n * n).map(|x| dy.mass.get(x / n, x % n)).collect::<Vec<_>>(), n, &(0..n).collect::<Vec<_>>());
    let (mut t, mut q, mut v) = (0.0, q0.to_vec(), v0.to_vec());
    let (mut wt, mut wv, mut gap) = (0.0f64, 0.0f64, f64::INFINITY);
    for ev in run.events() {
        for j in 1..50 {
            gap = gap.min(flight(t, &q, &v, (ev.t - t) * f64::from(j) / 50.0).0[c] - lo);
        }
        let (qe, ve) = flight(t, &q, &v, ev.t - t);
        wt = wt.max(((qe[c] - lo) / ve[c]).abs());
        wv = wv.max((ve[c] - ev.velocity_before).abs() / ve[c].abs());
        let p = -(1.0 + e) * ve[c] / minv[c * n + c];
        (t, q, v) = (ev.t, qe, (0..n).map(|r| ve[r] + minv[r * n + c] * p).collect());
    }
    (ok && !run.events().is_empty(), run.search_steps(), wt, wv, gap)
}

/// Three masses of a chain tied to a wall, a steady load on the middle one.
fn chain3() -> Dynamics {
    let (m, k) = common::chain_matrices(3, false);
    Dynamics::new(m, k, vec![0.0, 0.1, 0.0], vec![Contact::new(0, Bounds::obstacle(-1e9), false)])
}

/// `x'' + c x' + x = s sin(Ω t)` on an obstacle at `gap`.
fn osc(omega: f64, c: f64, gap: f64, s: f64) -> Dynamics {
    let mut dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(gap), false)]);
    dy.forcing = vec![Forcing { shape: vec![s], time: TimeProfile::Sine { amplitude: 1.0, omega } }];
    if c > 0.0 {
        dy.damping = Some(SymBand::from_diagonal(&[c]));
    }
    dy
}

/// A run's events `(t, v⁻, impulse)` and final `(q, v)`.
type Run = (Vec<(f64, f64, f64)>, Vec<f64>, Vec<f64>);

/// A forced chain of three on an obstacle, lengths scaled by `s` and
/// frequencies by `r` (`K`, loads × `r²`, `C`, `Ω` × `r`, velocities × `s r`),
/// run to `t_end / r`: its events `(t, v⁻, impulse)` and final state, scaled back.
fn run(s: f64, r: f64, e: f64, damp: Option<f64>, t_end: f64) -> Run {
    let (m, k) = common::chain_matrices(3, false);
    let mut dy = Dynamics::new(m, k.lin_comb(r * r, &k, 0.0), vec![0.0, 0.1 * s * r * r, 0.0], vec![Contact::new(0, Bounds::obstacle(-0.2 * s), false)]);
    dy.forcing = vec![Forcing { shape: vec![0.0, 0.0, 0.5 * s * r * r], time: TimeProfile::Sine { amplitude: 1.0, omega: 1.7 * r } }];
    if let Some(a) = damp {
        dy.damping = Some(dy.mass.lin_comb(a * r, &dy.stiffness, 0.0));
    }
    let mut ev = EventDriven::new(&dy, 0.0, &[0.05 * s, 0.0, 0.0], &[-s * r, 0.3 * s * r, 0.0], e).unwrap();
    ev.run_until(t_end / r, 100_000).unwrap();
    let (_, q, v) = ev.state();
    (ev.events().iter().map(|x| (x.t * r, x.velocity_before / (s * r), x.impulse / (s * r))).collect(), q.iter().map(|x| x / s).collect(), v.iter().map(|x| x / (s * r)).collect())
}

/// Four lumped unit masses, unit springs, tied to a wall at dof 3, link 1
/// (dofs 0, 1) `ratio` times stiffer or (`light`) mass 1 `1/ratio` times
/// lighter, a harmonic at dof 3, a contact at `contact`.
pub(crate) fn spread(ratio: f64, light: bool, contact: usize) -> Dynamics {
    let n = 4;
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    // Link `j` joins dofs `j − 1` and `j`.
    let springs = [0.0, if light { 1.0 } else { ratio }, 1.0, 1.0];
    for i in 0..n {
        m.set(i, i, if light && i == 1 { 1.0 / ratio } else { 1.0 });
    }
    for j in 1..n {
        let s = springs[j];
        k.set(j, j, k.get(j, j) + s);
        k.set(j - 1, j - 1, k.get(j - 1, j - 1) + s);
        k.set(j, j - 1, -s);
    }
    k.set(n - 1, n - 1, k.get(n - 1, n - 1) + 1.0);
    let mut dy = Dynamics::new(m, k, vec![0.0; n], vec![Contact::new(contact, Bounds::obstacle(-0.1), false)]);
    dy.forcing = vec![Forcing { shape: vec![0.0, 0.0, 0.0, 0.3], time: TimeProfile::Sine { amplitude: 1.0, omega: 0.9 } }];
    dy
}

/// The steady coefficients `g/(k − Ω² + icΩ)` of a harmonic near a mode's
/// resonance cancelled against the homogeneous part to `ε k/√d` of the
/// motion: before the response from rest (flow.rs, `from_rest`), the flow
/// was off the exponential by 4.6e-4 at `Ω = ω (1 + 2e-13)` (just outside
/// the secular form's old band `|k − Ω²| <= 1e-13 Ω²`), 1.7e-4 at `1e-12`,
/// 5.1e-8 at `1e-9`, 1.3e-10 at `1e-6`, and under `c = 1e-14` by 5.3e-3 at
/// `Ω = ω`; now at most 3.5e-14 (`τ <= 10`; the exponential's own error
/// is 3e-13 at `τ = 100`). `5e-3` is the band's edge (`√d = 1e-2 k`).
#[test]
fn a_mode_forced_near_its_resonance_is_the_exponential() {
    let base = chain3();
    let w = ModalFlow::new(&base).unwrap().omega2()[0].sqrt();
    for c in [0.0, 1e-14, 1e-10] {
        for r in [0.0, 1e-15, 5e-14, -5e-14, 2e-13, 1e-12, -1e-12, 1e-9, 1e-6, -1e-6, 1e-3, 4.9e-3, 5.1e-3, -5.1e-3, 2e-2] {
            let mut dy = base.clone();
            dy.forcing = vec![Forcing { shape: vec![0.0, 0.0, 1.0], time: TimeProfile::Sine { amplitude: 1.0, omega: w * (1.0 + r) } }];
            if c > 0.0 {
                dy.damping = Some(dy.mass.lin_comb(c, &dy.stiffness, 0.0));
            }
            for tau in [1.0, 10.0] {
                let err = flow_error(&dy, 0.3, tau);
                assert!(err <= 1e-13, "c = {c}, Ω = ω (1 + {r}), τ = {tau}: {err:e}");
            }
        }
    }
}

/// An oscillator `x'' + x = 0.1 sin((1 + r) t)` on an obstacle at −0.5:
/// before, at `r = 2e-13` and `1e-12` the runs stopped after 1e7 search
/// steps (the bounds of the steady part `~1/d` held the windows at
/// nothing), at `1e-9` took 7e5 steps, and their impacts were off by 1e-3
/// s; now 82-86 steps and every impact on the exponential's replay.
#[test]
fn impacts_near_resonance_replay_on_the_exponential() {
    for e in [0.8, 1.0] {
        for r in [0.0, 2e-13, 1e-12, 1e-9, 1e-6] {
            let dy = osc(1.0 + r, 0.0, -0.5, 0.1);
            let (ok, steps, dt, dv, gap) = replay(&dy, &[0.0], &[0.0], e, 60.0, &|t, q, v, tau| reference(&dy, t, q, v, tau));
            assert!(ok && steps <= 1000 && dt <= 1e-11 && dv <= 1e-11 && gap > 0.0, "e = {e}, r = {r}: ok {ok}, {steps} steps, t off by {dt:e}, v by {dv:e}, gap {gap:e}");
        }
    }
}

/// Positions × `s` (1e-150 to 1e150, gaps of 1e-151 to 1e149 among them)
/// or times ÷ `r`: the same run, to 2.7e-13 in event times, 2.6e-12 in
/// impact speeds, impulses and the final state (e = 0.8; 1e-13 for e = 0,
/// 1); a power of two, bit for bit.
#[test]
fn a_run_scaled_in_length_or_time_is_the_scaled_run() {
    let worst = |a: &Run, b: &Run| {
        assert_eq!(a.0.len(), b.0.len());
        let events = a.0.iter().zip(&b.0).fold(0.0f64, |m, (x, y)| m.max((x.0 - y.0).abs()).max((x.1 - y.1).abs()).max((x.2 - y.2).abs()));
        a.1.iter().zip(&b.1).chain(a.2.iter().zip(&b.2)).fold(events, |m, (x, y)| m.max((x - y).abs()))
    };
    for e in [0.0, 0.8, 1.0] {
        let base = run(1.0, 1.0, e, None, 20.0);
        assert!(base.0.len() >= 4);
        assert_eq!(worst(&run(2f64.powi(-40), 1.0, e, None, 20.0), &base), 0.0);
        for (s, r) in [(1e-150, 1.0), (1e-12, 1.0), (1e12, 1.0), (1e150, 1.0), (1.0, 1e-3), (1.0, 1e6), (1e-9, 1e4)] {
            let d = worst(&run(s, r, e, None, 20.0), &base);
            assert!(d <= 1e-11, "e = {e}, s = {s}, r = {r}: {d:e}");
        }
    }
}

/// `x'' + x = 0` from `(0, −1)` onto an obstacle at `−g`: the impact at
/// `asin g` at speed `cos(asin g)`, the next at `+ 2π − 2 atan(e cos/g)`.
/// At `g = 1e-300` the first time is within 1e-12 of it (the search's root
/// is taken 1e-12 early, docs/theory.md §9.2: 1e-312 s).
#[test]
fn gaps_down_to_1e_minus_307_meet_their_closed_form() {
    for g in [1e-15, 1e-300, 1e-307] {
        for e in [0.0, 0.8, 1.0] {
            let dy = osc(1.0, 0.0, -g, 0.0);
            let mut run = EventDriven::new(&dy, 0.0, &[0.0], &[-1.0], e).unwrap();
            run.run_until(5.0, 1000).unwrap();
            let ev = run.events();
            let (t1, v1) = (g.asin(), -g.asin().cos());
            assert!((ev[0].t - t1).abs() <= 2e-12 * t1 && (ev[0].velocity_before - v1).abs() <= 1e-15, "g = {g}, e = {e}: {:?}", ev[0]);
            if e > 0.0 {
                let t2 = t1 + 2.0 * std::f64::consts::PI - 2.0 * (-e * v1 / g).atan();
                assert!((ev[1].t - t2).abs() <= 1e-14 && (ev[1].velocity_before - e * v1).abs() <= 1e-15, "g = {g}, e = {e}: {:?}", ev[1]);
            }
        }
    }
}

/// Rayleigh `C = a M` and a dashpot `a` at dof 2 (the first-order form
/// when it is not round-off), `a` = 1e-14 and 1e-10, against the undamped
/// run: the difference is O(a) over the run's own round-off floor (the
/// scaled runs': 2.6e-12 at e = 0.8), not O(1). Measured: Rayleigh 17 a to
/// 65 a, the dashpot 16 a to 414 a at 1e-10 (e = 0.8 the most sensitive),
/// 7.4e-12 at 1e-14.
#[test]
fn weak_damping_moves_a_run_by_the_order_of_the_damping() {
    let mut devs = Vec::new();
    for e in [0.0, 0.8, 1.0] {
        let base = run(1.0, 1.0, e, None, 20.0);
        for a in [1e-14, 1e-10] {
            for dashpot in [false, true] {
                let d = run_damped(e, a, dashpot);
                assert_eq!(d.0.len(), base.0.len(), "e = {e}, a = {a}");
                let dev = d.0.iter().zip(&base.0).fold(0.0f64, |m, (x, y)| m.max((x.0 - y.0).abs()).max((x.1 - y.1).abs()));
                devs.push((e, a, dashpot, d.1.iter().zip(&base.1).chain(d.2.iter().zip(&base.2)).fold(dev, |m, (x, y)| m.max((x - y).abs()))));
            }
        }
    }
    assert!(devs.iter().all(|&(_, a, _, dev)| dev <= 1e3 * a + 1e-11), "(e, a, dashpot, deviation): {devs:?}");
}

/// [`run`] unscaled with a damping `a`: Rayleigh `a M`, or a dashpot at dof 2.
fn run_damped(e: f64, a: f64, dashpot: bool) -> Run {
    if !dashpot {
        return run(1.0, 1.0, e, Some(a), 20.0);
    }
    let (m, k) = common::chain_matrices(3, false);
    let mut dy = Dynamics::new(m, k, vec![0.0, 0.1, 0.0], vec![Contact::new(0, Bounds::obstacle(-0.2), false)]);
    dy.forcing = vec![Forcing { shape: vec![0.0, 0.0, 0.5], time: TimeProfile::Sine { amplitude: 1.0, omega: 1.7 } }];
    let mut c = SymBand::zeros(3, 1);
    c.set(2, 2, a);
    dy.damping = Some(c);
    let mut ev = EventDriven::new(&dy, 0.0, &[0.05, 0.0, 0.0], &[-1.0, 0.3, 0.0], e).unwrap();
    ev.run_until(20.0, 100_000).unwrap();
    let (_, q, v) = ev.state();
    (ev.events().iter().map(|x| (x.t, x.velocity_before, x.impulse)).collect(), q, v)
}

/// `x'' + 2ζ x' + x = 0` at `ζ = 1 ± 1e-12` and 1 (the flow's forms
/// switch there: λ = k − α² changes sign) against `ζ = 1`'s closed form
/// `(x₀ + (v₀ + x₀) t) e^{−t}`: within 1e-11 (their own difference is
/// ~1e-12 t²).
#[test]
fn a_critically_damped_mode_is_continuous_across_its_switch() {
    for d in [-1e-12, 0.0, 1e-12] {
        let dy = osc(1.0, 2.0 * (1.0 + d), -1e9, 0.0);
        let flow = ModalFlow::new(&dy).unwrap();
        for tau in [0.5, 5.0, 50.0] {
            let (x0, v0) = (0.7, -0.4);
            let (mut q, mut v) = ([0.0], [0.0]);
            flow.advance(0.3, &[x0], &[v0], tau, &mut q, &mut v);
            let (x, dx) = ((x0 + (v0 + x0) * tau) * (-tau).exp(), (v0 - (v0 + x0) * tau) * (-tau).exp());
            assert!((q[0] - x).abs() <= 1e-11 && (v[0] - dx).abs() <= 1e-11, "ζ = 1 + {d}, τ = {tau}: ({}, {}) against ({x}, {dx})", q[0], v[0]);
        }
    }
}

/// A chain with one spring 1e4 times the others (ω from 0.36 to 141), or
/// one mass 1e-4 of the others, its contact on the stiff or the soft side:
/// the flow against the exponential (1.4e-10 at τ = 10: the exponential's
/// own scaling and squaring loses `2^s ε`, ~1e-10 here) and every impact
/// of the run on its replay (6e-11 s, 7e-11 in speed).
/// Larger spreads, where the exponential bounds nothing: events_stiff.rs.
#[test]
fn a_chain_with_a_stiffness_spread_of_1e4_replays_on_the_exponential() {
    for light in [false, true] {
        for contact in [0, 2] {
            let dy = spread(1e4, light, contact);
            for tau in [0.01, 1.0, 10.0] {
                let err = flow_error(&dy, 0.3, tau);
                assert!(err <= 1e-9, "light {light}, τ = {tau}: {err:e}");
            }
            for e in [0.8, 1.0] {
                let (ok, _, dt, dv, gap) = replay(&dy, &[0.0; 4], &[-0.3, -0.2, -0.1, 0.0], e, 10.0, &|t, q, v, tau| reference(&dy, t, q, v, tau));
                assert!(ok && dt <= 1e-9 && dv <= 1e-9 && gap > 0.0, "light {light}, contact {contact}, e = {e}: t off by {dt:e}, v by {dv:e}, gap {gap:e}");
            }
        }
    }
}
