//! Two contacts chattering together through a consistent mass: free chains
//! (`events_common::chain_matrices`) on two stops, `0 < e < 1`, found by a
//! sampling hunt over random chains, loads and dampings. Each contact's
//! accumulation puts it at rest with an impulse that lifts the other on its
//! stop through `M⁻¹`; the lifted one landed again at a speed 1/3 to 1/100
//! of the last, accumulated, lifted the first: case 21 stopped with
//! `NoProgress` (25 events at t = 3.8267), cases 50 and 59 chattered at
//! 1e-10 and 1e-8 m/s to the event limit, and an accumulation logged at its
//! limit `t∞` was followed by the lifted contact's landing before `t∞`
//! (docs/theory.md §9.3, "Contacts lifted by an accumulation").
//!
//! Oracles, none of them the run's own accessors: the momentum of the free
//! chain, `Σ_c ∫ r_c = ΔP − ∫ 1ᵀ f` over every output step (the load
//! integrated in closed form here; `1ᵀ K = 0` and `C = b K`), the same run
//! sampled at `dt` and `dt/8` giving the same bits at the common levels,
//! `events` in time order, and the run reaching its end.

use crate::events_common as common;
use signorini_schemes::events::EventStepper;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, Initial, Stepper, TimeProfile};
use std::sync::Arc;

/// A hunt case: the chain, its restitution, start speed, sampling step and
/// the load `f0 + shape A sin(ω t + p) + ramp s(t)` (`s` piecewise linear).
struct Case {
    name: &'static str,
    dy: Dynamics,
    e: f64,
    v0: Vec<f64>,
    dt: f64,
    f0: Vec<f64>,
    shape: Vec<f64>,
    wave: (f64, f64, f64),
    ramp: Vec<f64>,
    points: Vec<(f64, f64)>,
}

/// The load `f0 + shape A sin(ω t + p) + e_0 s(t)` (`wave = (A, ω, p)`,
/// `s` through `points`; none when empty).
struct Load {
    f0: Vec<f64>,
    shape: Vec<f64>,
    wave: (f64, f64, f64),
    points: Vec<(f64, f64)>,
}

/// The free chain of `n` dofs with `C = b K` (none for `b = 0`), the load
/// and the stops; `(e, b, dt)`.
fn case(name: &'static str, n: usize, (e, b, dt): (f64, f64, f64), load: Load, contacts: Vec<Contact>, v0: Vec<f64>) -> Case {
    let Load { f0, shape, wave, points } = load;
    let (m, k) = common::chain_matrices(n, true);
    let mut ramp = vec![0.0; n];
    let mut forcing = vec![Forcing { shape: shape.clone(), time: TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: wave.0, omega: wave.1, phase: wave.2 }])) }];
    if !points.is_empty() {
        ramp[0] = 1.0;
        forcing.push(Forcing { shape: ramp.clone(), time: TimeProfile::series(points.iter().map(|p| p.0).collect(), points.iter().map(|p| p.1).collect()).unwrap() });
    }
    let c = (b > 0.0).then(|| common::rayleigh(&m, &k, 0.0, b));
    let dy = Dynamics::new(m, k, f0.clone(), contacts).with_forcing(forcing).with_damping(c);
    Case { name, dy, e, v0, dt, f0, shape, wave, ramp, points }
}

/// Case 21: two dofs, both on stops, `e = 0.3`, `C = b K`, a series load.
fn case21() -> Case {
    let stops = vec![Contact::new(0, Bounds::obstacle(-0.09377068176889612), false), Contact::new(1, Bounds::obstacle(-0.06690561297803942), false)];
    let points = vec![(0.0, 0.7024837418324346), (2.2111284901956703, -0.7187731324213928), (3.6015949960037514, 0.5634052489239183), (5.155510463120724, -0.7233836201562922)];
    let wave = (1.3618297551776433, 2.196378626992472, 0.04971267316725447);
    let load = Load { f0: vec![-0.5869867401755063, -0.0978311233625844], shape: vec![0.0282197585661208, 0.0], wave, points };
    case("21", 2, (0.3, 0.0006478246894306983, 0.25), load, stops, vec![-0.2928573799866331, -0.30733565853352696])
}

/// Case 50: six dofs, `e = 0.3`, stops under both ends and a middle dof
/// between two, `C = b K`, a series load.
fn case50() -> Case {
    let stops =
        vec![Contact::new(0, Bounds::obstacle(-0.0879467229932296), false), Contact::new(5, Bounds::obstacle(-0.01642370481311479), false), Contact::new(3, Bounds { lo: -0.2, hi: 0.2 }, false)];
    let points = vec![(0.0, -0.21350443406167718), (2.4711153243003787, 0.27980004653604484), (3.6761101788092074, 0.883191591534529), (5.782115247986557, -0.5665358038798836)];
    let mut f0 = vec![0.05222057482822576; 6];
    f0[0] = 0.3133234489693545;
    let v0 = vec![-0.7341906891348271, -0.6277186424446133, -0.8409506884523281, -1.0101434413602557, -0.5228219423566973, -0.570376259077463];
    let load = Load { f0, shape: vec![-0.09288485373865041, 0.0, 0.0, 0.0, 1.0, 0.0], wave: (0.7933783421173015, 3.9858379048888235, 3.847003668321374), points };
    case("50", 6, (0.3, 0.0066355880619624165, 1.0), load, stops, v0)
}

/// Case 59: six dofs, `e = 0.5`, undamped, a stop under the left end and
/// the middle dof between two.
fn case59() -> Case {
    let stops = vec![Contact::new(0, Bounds::obstacle(-0.015689027742896967), false), Contact::new(3, Bounds { lo: -0.2, hi: 0.2 }, false)];
    let mut f0 = vec![-0.06368128381361904; 6];
    f0[0] = -0.38208770288171423;
    let v0 = vec![0.0767763515460392, 0.3702463462271379, 0.3730889074736721, 0.12378262604565116, 0.21737087905433777, -0.033057285434338834];
    let load = Load { f0, shape: vec![1.9508915331262615, 0.0, 0.0, 0.0, 0.0, 0.0], wave: (0.15375657964521583, 0.30925784794682043, 4.590722603273395), points: Vec::new() };
    case("59", 6, (0.5, 0.0, 0.125), load, stops, v0)
}

/// `∫_a^b s`, `s` linear between its points and held beyond them.
fn series_integral(p: &[(f64, f64)], a: f64, b: f64) -> f64 {
    let val = |t: f64| match p.iter().position(|x| x.0 > t) {
        None => p[p.len() - 1].1,
        Some(0) => p[0].1,
        Some(k) => p[k - 1].1 + (p[k].1 - p[k - 1].1) / (p[k].0 - p[k - 1].0) * (t - p[k - 1].0),
    };
    let mut knots = vec![a];
    knots.extend(p.iter().map(|x| x.0).filter(|&t| t > a && t < b));
    knots.push(b);
    knots.windows(2).map(|w| 0.5 * (val(w[0]) + val(w[1])) * (w[1] - w[0])).sum()
}

/// `∫_a^b 1ᵀ f`, in closed form.
fn load_integral(c: &Case, a: f64, b: f64) -> f64 {
    let (amp, w, p) = c.wave;
    let mut x = c.f0.iter().sum::<f64>() * (b - a) + c.shape.iter().sum::<f64>() * amp * ((w * a + p).cos() - (w * b + p).cos()) / w;
    if !c.points.is_empty() {
        x += c.ramp.iter().sum::<f64>() * series_integral(&c.points, a, b);
    }
    x
}

/// `1ᵀ M v` of the consistent chain (2/3, 1/6; 1/3 at the ends), written here.
fn momentum(v: &[f64]) -> f64 {
    let n = v.len();
    (0..n).map(|i| v[i] * (if i == 0 || i == n - 1 { 1.0 / 3.0 } else { 2.0 / 3.0 } + if i > 0 { 1.0 / 6.0 } else { 0.0 } + if i + 1 < n { 1.0 / 6.0 } else { 0.0 })).sum()
}

/// Each case over [0, 12] through the registry's stepper, sampled every
/// `dt` and every `dt/8`: no error (before: `NoProgress` or the event
/// limit), the same state bits at every common level, the same events, in
/// time order; over every step the contacts' impulses (`−λ dt`) balance the
/// chain's momentum, `Σ_c p_c = ΔP − ∫ 1ᵀ f`, to 1e-11 (relative to the
/// momenta and impulses: measured ≤ 5.1e-15). Each case is checked to take
/// accumulations of both contacts of a pair, the joint rest this test is for.
#[test]
fn contacts_chattering_together_through_a_consistent_mass_reach_their_end() {
    for c in [case21(), case50(), case59()] {
        let n = c.v0.len();
        let init = Initial { u: vec![0.0; n], v: c.v0.clone() };
        let mut coarse = EventStepper::new("c".into(), c.dy.clone(), c.e, c.dt, &init).unwrap().with_max_events(20_000);
        let mut fine = EventStepper::new("f".into(), c.dy.clone(), c.e, c.dt / 8.0, &init).unwrap().with_max_events(20_000);
        let levels = (12.0 / c.dt) as usize;
        let mut p_prev = momentum(&c.v0);
        for lv in 1..=levels {
            for _ in 0..8 {
                fine.step().unwrap_or_else(|e| panic!("case {}, dt/8, to t = {}: {e}", c.name, lv as f64 * c.dt));
            }
            coarse.step().unwrap_or_else(|e| panic!("case {}, dt, to t = {}: {e}", c.name, lv as f64 * c.dt));
            let (sc, sf) = (coarse.state().unwrap(), fine.state().unwrap());
            assert!(sc.iter().zip(&sf).all(|(a, b)| a.to_bits() == b.to_bits()), "case {}, t = {}: {sc:?} sampled at dt, {sf:?} at dt/8", c.name, coarse.time());
            let t1 = lv as f64 * c.dt;
            let p = momentum(&sc[n..]);
            let got: f64 = coarse.contact_forces().iter().map(|l| -l * c.dt).sum();
            let want = p - p_prev - load_integral(&c, t1 - c.dt, t1);
            assert!((got - want).abs() <= 1e-11 * (1.0 + p.abs() + p_prev.abs() + got.abs()), "case {}, step to t = {t1}: impulses {got}, momentum balance {want}", c.name);
            p_prev = p;
        }
        assert_eq!(coarse.time(), 12.0, "case {}", c.name);
        let ev = coarse.events();
        assert!(ev == fine.events(), "case {}: the events differ at dt and dt/8 ({} against {})", c.name, ev.len(), fine.events().len());
        if let Some(w) = ev.windows(2).find(|w| w[1].t < w[0].t) {
            panic!("case {}: events out of time order: {:?} then {:?}", c.name, w[0], w[1]);
        }
        // A joint rest: accumulations of two contacts at one located instant.
        let acc: Vec<_> = ev.iter().filter(|x| x.kind == signorini_schemes::events::EventKind::Accumulation).collect();
        assert!(acc.windows(2).any(|w| w[0].contact != w[1].contact && (w[1].t - w[0].t).abs() <= 1e-5), "case {}: no joint accumulation: {acc:?}", c.name);
        assert!(ev.len() <= 1000, "case {}: {} events", c.name, ev.len());
    }
}
