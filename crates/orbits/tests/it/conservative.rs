//! A conservative impact oscillator (no damping, elastic impacts: the
//! Poincaré map preserves area, its multipliers a pair `μ, 1/μ`). Its
//! period-1 orbit's pair of multipliers goes round the unit circle, meets
//! at −1 and leaves it along the negative real axis: a period doubling of
//! the area-preserving map, where no single multiplier passes through −1
//! (of the pair `−1 − ε`, `−1 + ε/(1 + ε)` the one nearer −1 stays inside
//! the circle). It was named nothing. Checked against the closed form of
//! `signorini_exact::oscillator` (the orbit's monodromy written out by
//! hand: the trace of an area-preserving 2×2 map is −2 there), and the
//! doubled orbit against a transcription of the map from the exact crate's
//! free flow with the impacts found here. Below Ω = 2 its orbit impacts
//! on the section: a branch stalled there names no grazing it never
//! reached.

use crate::{continuation, doubled_branch};
use signorini_exact::{ImpactOscillator, OscillatorParams, State};
use signorini_orbits::{BifurcationKind, ContinuationOptions, SceneFamily};
use std::f64::consts::TAU;

const GAP: f64 = 0.2;

fn exact(omega: f64) -> ImpactOscillator {
    ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.0, force: 1.0, forcing_frequency: omega, gap: GAP, restitution: 1.0 }).unwrap()
}

/// The admissible closed-form period-1 orbit at `omega` (one between 2.1
/// and 2.4: its impact at phase π) and its monodromy's trace.
fn closed(omega: f64) -> ([f64; 2], f64) {
    let osc = exact(omega);
    let orbits = osc.period1_orbits();
    assert_eq!(orbits.len(), 1, "Ω = {omega}: one admissible period-1 orbit");
    let o = &orbits[0];
    let t = TAU / omega;
    let z = osc.flow(o.impact_time.rem_euclid(t), State { x: GAP, v: -o.impact_velocity }, t);
    ([z.x, z.v], o.monodromy[0][0] + o.monodromy[1][1])
}

/// Where the closed-form trace is −2, by bisection between 2.2 and 2.3.
fn closed_pd() -> f64 {
    let (mut lo, mut hi) = (2.2, 2.3);
    let f = |w: f64| closed(w).1 + 2.0;
    assert!(f(lo) > 0.0 && f(hi) < 0.0);
    for _ in 0..100 {
        let m = 0.5 * (lo + hi);
        if f(m) > 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    0.5 * (lo + hi)
}

/// The map over `periods` forcing periods, transcribed: the exact crate's
/// free flow, each impact (the first crossing of the stop, sampled at 1e-3
/// of the period and bisected) reflecting the velocity.
fn map(omega: f64, x: [f64; 2], periods: usize) -> [f64; 2] {
    let osc = exact(omega);
    let end = periods as f64 * TAU / omega;
    let (mut t0, mut z0) = (0.0, State { x: x[0], v: x[1] });
    let h = 1e-3 * TAU / omega;
    let mut t = t0;
    while t < end {
        let t1 = (t + h).min(end);
        let z1 = osc.flow(t0, z0, t1);
        if z1.x > GAP {
            let (mut a, mut b) = (t, t1);
            for _ in 0..100 {
                let m = 0.5 * (a + b);
                if osc.flow(t0, z0, m).x > GAP {
                    b = m;
                } else {
                    a = m;
                }
            }
            let hit = osc.flow(t0, z0, b);
            (t0, z0) = (b, State { x: GAP, v: -hit.v });
            t = b;
            continue;
        }
        t = t1;
    }
    let z = osc.flow(t0, z0, end);
    [z.x, z.v]
}

#[test]
fn a_pair_meeting_at_minus_one_on_the_conservative_map_is_a_period_doubling() {
    let fam = SceneFamily::new(crate::oscillator(0.0, GAP, 1.0, 2.2), "forcing.omega", 1).unwrap().0;
    let want = closed_pd();
    // From the elliptic side (the pair on the circle) and from the
    // hyperbolic one (a real negative pair).
    for (from, to) in [(2.1, 2.4), (2.4, 2.1)] {
        let start = closed(from).0;
        let opts = ContinuationOptions::new(from, to);
        let branch = continuation(&fam, &start, &opts).unwrap();
        let bifs: Vec<_> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect();
        eprintln!("{from} -> {to}: {bifs:?}, {}", branch.end);
        assert_eq!(branch.bifurcations.len(), 1, "{from} -> {to}: {bifs:?}");
        let pd = &branch.bifurcations[0];
        assert_eq!(pd.kind, BifurcationKind::PeriodDoubling, "{bifs:?}");
        assert!((pd.param - want).abs() <= 1e-9, "{from} -> {to}: at {} vs closed form {want}", pd.param);
        assert!((pd.mu.re + 1.0).abs() <= 1e-5 && pd.mu.im.abs() <= 1e-5, "multiplier {:?}", pd.mu);
        // The doubled branch from it: its first orbit a fixed point of
        // the transcribed map over two periods, not over one.
        if from < to {
            let d = doubled_branch(&fam, &fam.with_periods(2), pd, (from, to), &opts).unwrap();
            let p = &d.points[0];
            let x = [p.orbit.x[0], p.orbit.x[1]];
            let (one, two) = (map(p.param, x, 1), map(p.param, x, 2));
            let off = |y: [f64; 2]| (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
            eprintln!("doubled orbit at {}: {x:?}, P(x) − x {:e}, P²(x) − x {:e}", p.param, off(one), off(two));
            assert!(off(two) <= 1e-8 && off(one) >= 1e-3, "at {}: P(x) − x {:e}, P²(x) − x {:e}", p.param, off(one), off(two));
        }
    }
}

/// Below Ω = 2 the admissible period-1 orbit impacts at phase 0: its
/// impact sits on the section `t = 0` along the whole branch, where the
/// map jumps (docs/orbits.md's limits), and the corrector stalls within
/// 1e-5 of the start. The grazing of its flight (where the closed-form
/// orbit stops being admissible: between 0.880 and 0.885) is far below;
/// the distance to it, barely changing over the stalled steps, was
/// extrapolated and named a grazing at 0.8687, 0.53 beyond the branch's
/// last point, the branch said to end there. Every bifurcation listed must
/// lie among the branch's points, a grazing at the closed form's. The
/// least step is 1e-4 of the range, not the default 1e-7: the branch
/// stalls at the same point (1.399999965) and, with the guard against that
/// extrapolation taken out, still names the grazing at 0.8696; the halvings
/// below 1e-4 only cost time (8.9 CPU-s instead of 14.0, medians of 3
/// paired runs).
#[test]
fn a_branch_stalled_on_its_section_names_no_grazing_it_never_reached() {
    let fam = SceneFamily::new(crate::oscillator(0.0, GAP, 1.0, 2.2), "forcing.omega", 1).unwrap().0;
    let admissible = |w: f64| exact(w).period1_roots().iter().any(|o| o.phase.abs() < 1e-9 && o.is_admissible());
    let (mut lo, mut hi) = (0.86, 0.9);
    assert!(!admissible(lo) && admissible(hi));
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if admissible(m) {
            hi = m;
        } else {
            lo = m;
        }
    }
    let grazing = 0.5 * (lo + hi);
    // The closed-form orbit at 1.4: on the stop at t = 0, moving in.
    let osc = exact(1.4);
    let o = osc.period1_orbits().into_iter().find(|o| o.phase.abs() < 1e-9).unwrap();
    let t = TAU / 1.4;
    let z = osc.flow(o.impact_time.rem_euclid(t), State { x: GAP, v: -o.impact_velocity }, t);
    let branch = continuation(&fam, &[z.x, z.v], &ContinuationOptions { min_step: 1e-4, ..ContinuationOptions::new(1.4, 1.05) }).unwrap();
    let (a, b) = branch.points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.param), b.max(p.param)));
    let bifs: Vec<_> = branch.bifurcations.iter().map(|f| (f.kind.name(), f.param)).collect();
    eprintln!("points {a} … {b}; {bifs:?}; closed-form grazing {grazing}; {}", branch.end);
    for f in &branch.bifurcations {
        let near = if f.kind == BifurcationKind::Grazing { (f.param - grazing).abs() <= 1e-6 } else { true };
        assert!(
            near && f.param >= a - 1e-3 * (b - a).max(1e-3) && f.param <= b + 1e-3 * (b - a).max(1e-3),
            "{} at {} (branch from {a} to {b}; the closed form's grazing at {grazing})",
            f.kind.name(),
            f.param
        );
    }
}

/// The same between stops at ±1 (forced `1.5 sin Ωt`, undamped, elastic).
struct Between;

impl signorini_orbits::Family for Between {
    fn model(&self, w: f64) -> Result<signorini_orbits::Model, signorini_orbits::OrbitError> {
        use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};
        let dy = Dynamics::new(signorini_fem::SymBand::from_diagonal(&[1.0]), signorini_fem::SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: -1.0, hi: 1.0 }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: 1.5, omega: w } }]);
        signorini_orbits::Model::new(dy, 1.0)
    }
    fn period(&self, w: f64) -> Result<f64, signorini_orbits::OrbitError> {
        Ok(TAU / w)
    }
}

/// From the 4-impact orbit at Ω = 2 down: a trial step's corrector ran
/// from the orbit at 1.634 along its hyperplane onto the free orbit at
/// 2.207 (0.37 of the range for a step of 1e-2 or so; the multipliers,
/// on the unit circle at both ends, did not flag it), the step was taken
/// and the change of impacts between them bisected to a grazing at 0.796,
/// where no free orbit exists (its closed-form amplitude `1.5/|1 − Ω²|`
/// reaches the stops at Ω = √2.5 and is 4.1 there). A free orbit on the
/// branch must be the closed form's steady state, above √2.5, and every
/// bifurcation must lie between the two points it is listed between.
/// The branch as the code now steps it no longer makes that trial: with
/// the trial's acceptance guard off altogether this passes too (checked
/// 2026-12-01 with first steps 1e-2 and 3e-2, 40 and 400 points: no free
/// orbit below √2.5, no bifurcation outside its points, but at 3e-2 and
/// 400 points the run ends in an error); it stands as a regression check,
/// not as that guard's test.
#[test]
fn a_trial_that_runs_onto_another_arc_is_no_step() {
    // The 4-impact orbit through (0, 2.9719779338): a fixed point of the
    // transcribed map at Ω = 2 (the closed-form flow of x'' + x = 1.5 sin 2t
    // between elastic stops at ±1, Newton on it: one of four 4-impact orbits
    // there). A 400-period transient from rest also reaches it, but which
    // orbit an undamped system's transient lands on is decided by its
    // round-off: a last-bit change of the event search landed it on a
    // 0-impact orbit.
    let start = signorini_orbits::Family::model(&Between, 2.0).unwrap();
    let orbit = signorini_orbits::periodic_orbit(&start, 0.0, TAU / 2.0, &[0.0, 2.9719779338], &signorini_orbits::Newton::default()).unwrap();
    assert_eq!(orbit.impacts(), 4);
    assert!(orbit.x[0].abs() <= 1e-9 && (orbit.x[1] - 2.9719779338).abs() <= 1e-9, "{:?}", orbit.x);
    let mut opts = ContinuationOptions::new(2.0, 0.45);
    opts.max_points = 40;
    let branch = continuation(&Between, &orbit.x, &opts).unwrap();
    let bifs: Vec<_> = branch.bifurcations.iter().map(|f| (f.kind.name(), f.param, f.between)).collect();
    eprintln!("{bifs:?}; {}", branch.end);
    for p in branch.points.iter().filter(|p| p.orbit.impacts() == 0) {
        let w = p.param;
        let v = 1.5 * w / (1.0 - w * w);
        assert!(w >= 2.5f64.sqrt() && p.orbit.x[0].abs() <= 1e-9 && (p.orbit.x[1] - v).abs() <= 1e-9, "free orbit at {w}: {:?} vs the steady state (0, {v})", p.orbit.x);
    }
    for f in &branch.bifurcations {
        let (a, b) = (branch.points[f.between.0].param, branch.points[f.between.1].param);
        assert!((f.param - a) * (f.param - b) <= 1e-12, "{} at {} listed between points at {a} and {b}", f.kind.name(), f.param);
    }
}
