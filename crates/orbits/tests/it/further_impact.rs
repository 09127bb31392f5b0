//! Grazing of an orbit that already impacts: a further impact appears
//! where a free flight between two impacts reaches a stop. The impact
//! oscillator's period-1 orbit with one impact (closed form:
//! `signorini_exact::ImpactOscillator`) grazes
//!
//! - the same stop, where its flight's interior maximum reaches it (the
//!   classic grazing of the impact oscillator, at low frequency), and
//! - a second, lower stop, where its flight's minimum reaches it.
//!
//! The grazing frequency of each is derived here from the closed-form
//! orbit alone (its free flight `x(t)` between the impacts, the extremum
//! located by bisection of `v`, then bisection in Ω on its distance to the
//! stop) and the continuation must find it to 1e-8, list it as a grazing
//! from 1 to 2 impacts per period, and go on with the two-impact orbit.

use crate::continuation;
use signorini_exact::{ImpactOscillator, OscillatorParams, State};
use signorini_fem::SymBand;
use signorini_orbits::{BifurcationKind, Branch, ContinuationOptions, Family, Model, OrbitError, SceneFamily};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::f64::consts::{FRAC_PI_2, TAU};
use std::sync::Arc;

const GAP: f64 = 0.2;
const R: f64 = 0.8;

fn exact(omega: f64) -> ImpactOscillator {
    ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: omega, gap: GAP, restitution: R }).unwrap()
}

/// The closed form's stable one-impact root at `omega` (admissible or not:
/// past the grazing its flight crosses the stop, and it is still the
/// continuation of the orbit in Ω): impact time and velocity.
fn root(omega: f64) -> (f64, f64) {
    let roots: Vec<_> = exact(omega).period1_roots().into_iter().filter(|o| o.impact_velocity > 0.0 && o.is_stable()).collect();
    assert_eq!(roots.len(), 1, "Ω = {omega}: one stable root with V > 0");
    (roots[0].impact_time, roots[0].impact_velocity)
}

/// The orbit's state on the section t = 0 (mod T).
fn section_state(omega: f64) -> [f64; 2] {
    let (tau, v) = root(omega);
    let t = TAU / omega;
    let z = exact(omega).flow(tau.rem_euclid(t), State { x: GAP, v: -R * v }, t);
    [z.x, z.v]
}

/// The flight's extreme displacement between the impacts: the highest
/// interior maximum (`upper`) or the lowest minimum, each located by
/// bisection of `v` on a grid interval where it changes sign.
fn extremum(omega: f64, upper: bool) -> f64 {
    let osc = exact(omega);
    let (tau, v) = root(omega);
    let t = TAU / omega;
    let z0 = State { x: GAP, v: -R * v };
    let at = |s: f64| osc.flow(tau, z0, s);
    let n = 4000;
    let mut best = if upper { f64::NEG_INFINITY } else { f64::INFINITY };
    for i in 1..n - 1 {
        let (a, b) = (tau + t * f64::from(i) / f64::from(n), tau + t * f64::from(i + 1) / f64::from(n));
        let (va, vb) = (at(a).v, at(b).v);
        if (upper && va > 0.0 && vb <= 0.0) || (!upper && va < 0.0 && vb >= 0.0) {
            let (mut lo, mut hi) = (a, b);
            for _ in 0..80 {
                let m = 0.5 * (lo + hi);
                if (at(m).v > 0.0) == (va > 0.0) {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            let x = at(0.5 * (lo + hi)).x;
            best = if upper { best.max(x) } else { best.min(x) };
        }
    }
    best
}

/// The Ω in `[a, b]` where `f` (the distance of the extremum to its stop,
/// of opposite signs at the ends) vanishes: bisection.
fn zero(mut a: f64, mut b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let fa = f(a);
    assert!(fa * f(b) < 0.0, "a bracket");
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if (f(m) > 0.0) == (fa > 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// The oscillator of the scene with a second stop at `lo` below (forcing
/// `cos Ωt` as the scene's, a harmonic of phase π/2), in Ω.
struct TwoStops {
    lo: f64,
}

impl Family for TwoStops {
    fn model(&self, omega: f64) -> Result<Model, OrbitError> {
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: self.lo, hi: GAP }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: 1.0, omega, phase: FRAC_PI_2 }])) }])
            .with_damping(Some(SymBand::from_diagonal(&[0.1])));
        Model::new(dy, R)
    }

    fn period(&self, omega: f64) -> Result<f64, OrbitError> {
        Ok(TAU / omega)
    }
}

/// The branch's one-impact points up to the grazing are the closed form's
/// orbit; a single grazing, from 1 to 2 impacts, at `want`; the branch goes
/// on with the two-impact orbit, turning back at the grazing (the two
/// orbits meet there: on the far side neither exists).
fn check(branch: &Branch, want: f64, dir: f64) {
    eprintln!("{} points, end: {}", branch.points.len(), branch.end);
    for b in &branch.bifurcations {
        eprintln!("  {} at {:.15} impacts {:?}", b.kind.name(), b.param, b.impacts);
    }
    let grazing: Vec<_> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::Grazing).collect();
    assert_eq!(grazing.len(), 1, "one grazing: {:?}; end: {}", branch.bifurcations, branch.end);
    let g = grazing[0];
    eprintln!("grazing at {} vs closed form {want}: {:e} apart", g.param, (g.param - want).abs());
    assert!((g.param - want).abs() <= 1e-8 * want, "grazing at {} vs closed form {want}", g.param);
    assert_eq!(g.impacts, (1, 2));
    let k = g.between.1;
    for p in &branch.points[..k] {
        assert_eq!(p.orbit.impacts(), 1, "Ω = {}: before the grazing", p.param);
        let x = section_state(p.param);
        let err = (p.orbit.x[0] - x[0]).abs().max((p.orbit.x[1] - x[1]).abs());
        assert!(err <= 1e-8, "Ω = {}: state error {err:e} against the closed form", p.param);
        assert!((p.param - want) * dir < 0.0, "Ω = {}: before the grazing at {want}", p.param);
    }
    let after = &branch.points[k..];
    assert!(after.len() >= 5, "the branch goes on past the grazing: {} points", after.len());
    assert!(after.iter().all(|p| p.orbit.impacts() == 2), "two impacts per period after it");
    assert!((after[0].param - want) * dir < 0.0, "turned back at the grazing: Ω = {} against {want}", after[0].param);
}

#[test]
fn a_second_impact_at_the_same_stop_is_a_grazing_where_the_branch_turns_back() {
    let want = zero(0.89, 0.90, |w| GAP - extremum(w, true));
    let fam = SceneFamily::new(crate::oscillator(0.05, GAP, R, 1.0), "forcing.omega", 1).unwrap().0;
    let branch = continuation(&fam, &section_state(1.0), &ContinuationOptions::new(1.0, 0.8)).unwrap();
    check(&branch, want, -1.0);
    // The two-impact branch folds and comes back stable: at its end (Ω =
    // 0.8) it is the attractor a long run of the map reaches from rest.
    assert!(branch.bifurcations.iter().any(|b| b.kind == BifurcationKind::Fold));
    let last = branch.points.last().unwrap();
    assert_eq!(branch.end, "reached to");
    assert!(last.stable() && last.orbit.impacts() == 2);
    let m = fam.model(0.8).unwrap();
    let t = fam.period(0.8).unwrap();
    let mut x = vec![0.0, 0.0];
    for _ in 0..1000 {
        x = m.flow(0.0, &x, t, false).unwrap().x;
    }
    let err = (x[0] - last.orbit.x[0]).abs().max((x[1] - last.orbit.x[1]).abs());
    assert!(err < 1e-9, "the attractor {x:?} vs the branch's stable two-impact orbit {:?}", last.orbit.x);
}

#[test]
fn the_flight_reaching_the_other_stop_is_a_grazing_where_the_branch_turns_back() {
    let lo = -1.0;
    let want = zero(2.10, 2.15, |w| extremum(w, false) - lo);
    let branch = continuation(&TwoStops { lo }, &section_state(2.2), &ContinuationOptions::new(2.2, 2.0)).unwrap();
    check(&branch, want, -1.0);
    // The orbit after it touches both stops.
    let p = &branch.points[branch.bifurcations[0].between.1 + 3];
    let signs: Vec<f64> = p.orbit.events.iter().filter(|e| e.velocity_before != 0.0).map(|e| e.velocity_before.signum()).collect();
    assert!(signs.contains(&1.0) && signs.contains(&-1.0), "both stops hit: {signs:?}");
}

/// The other way: from the stable two-impact orbit at Ω = 0.8 (the
/// attractor of a run from rest) up, through its fold, back down to where
/// its slow impact vanishes — the same grazing, now 2 → 1 — and on along
/// the one-impact orbit (the closed form's) to Ω = 1.
#[test]
fn from_the_two_impact_orbit_the_branch_reaches_the_same_grazing_and_goes_on_with_one() {
    let want = zero(0.89, 0.90, |w| GAP - extremum(w, true));
    let fam = SceneFamily::new(crate::oscillator(0.05, GAP, R, 1.0), "forcing.omega", 1).unwrap().0;
    let (m, t) = (fam.model(0.8).unwrap(), fam.period(0.8).unwrap());
    let mut x = vec![0.0, 0.0];
    for _ in 0..1000 {
        x = m.flow(0.0, &x, t, false).unwrap().x;
    }
    let branch = continuation(&fam, &x, &ContinuationOptions::new(0.8, 1.0)).unwrap();
    assert_eq!(branch.end, "reached to");
    let grazing: Vec<_> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::Grazing).collect();
    assert_eq!(grazing.len(), 1, "{:?}", branch.bifurcations);
    eprintln!("grazing at {} vs closed form {want}: {:e} apart", grazing[0].param, (grazing[0].param - want).abs());
    assert!((grazing[0].param - want).abs() <= 1e-8 * want, "grazing at {} vs closed form {want}", grazing[0].param);
    assert_eq!(grazing[0].impacts, (2, 1));
    let after = &branch.points[grazing[0].between.1..];
    assert!(after.len() >= 5 && after.iter().all(|p| p.orbit.impacts() == 1));
    for p in after {
        let x = section_state(p.param);
        let err = (p.orbit.x[0] - x[0]).abs().max((p.orbit.x[1] - x[1]).abs());
        assert!(err <= 1e-8, "Ω = {}: state error {err:e} against the closed form", p.param);
    }
}
