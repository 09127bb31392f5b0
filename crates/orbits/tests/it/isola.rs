//! A closed branch: the oscillator `x'' + 0.1 x' + x = 2 sin Ωt` between
//! the stops −1 and 0.5 (e = 0.3) has an isola of period-5 orbits with one
//! impact, from Ω = 5.54 to 6.01, through the stable orbit at Ω = 5.6.
//! Continued from there it was traced round and round until the point
//! budget (400 points), each of its two folds listed ten times. The branch
//! now ends where it returns to its first orbit, each fold listed once.
//! Checked against a transcription sharing no code with the crate (the
//! closed-form flow between impacts of `between.rs`, its own impact search,
//! the restitution by hand): every point a fixed point of the transcribed
//! map over five periods, and each fold where Newton on that map (central
//! differences) finds an orbit just before it and none just past it.

use crate::between::map_between;
use crate::continuation;
use signorini_fem::SymBand;
use signorini_orbits::{periodic_orbit, BifurcationKind, ContinuationOptions, Family, Model, Newton, OrbitError};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};
use std::f64::consts::TAU;

pub(crate) const LO: f64 = -1.0;
pub(crate) const HI: f64 = 0.5;
pub(crate) const E: f64 = 0.3;

/// The family of orbits of `p` forcing periods.
pub(crate) struct Isola(pub(crate) usize);

impl Family for Isola {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: LO, hi: HI }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: crate::between::F, omega: w } }])
            .with_damping(Some(SymBand::from_diagonal(&[crate::between::C])));
        Model::new(dy, E)
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(self.0 as f64 * TAU / w)
    }
    fn periods(&self) -> usize {
        self.0
    }
}

/// The transcription's map over `p` forcing periods between the stops
/// ([`map_between`], the flow sampled at 1/1000 of a period): the image
/// and the impacts.
fn map_over(p: usize, w: f64, x: [f64; 2]) -> ([f64; 2], usize) {
    let (y, impacts, _) = map_between(w, x, p, (LO, HI), E, 1000.0);
    (y, impacts)
}

/// The transcription's map over 5 forcing periods.
fn map(w: f64, x: [f64; 2]) -> ([f64; 2], usize) {
    map_over(5, w, x)
}

/// Newton on the transcribed map from `x` (between.rs's `fixed_point`,
/// within 60 iterations).
fn fixed_point(w: f64, x: [f64; 2]) -> Option<[f64; 2]> {
    crate::between::fixed_point(x, 60, |y| map(w, y).0)
}

#[test]
fn an_isola_is_traced_once_and_closed() {
    let w0 = 5.6;
    let start = periodic_orbit(&Isola(5).model(w0).unwrap(), 0.0, 5.0 * TAU / w0, &[-0.5385, -0.1181], &Newton::default()).unwrap();
    assert_eq!(start.impacts(), 1, "the 1-impact orbit at {w0}: {:?}", start.x);
    let branch = continuation(&Isola(5), &start.x, &ContinuationOptions::new(w0, 6.5)).unwrap();
    eprintln!("{} points to {}: {}", branch.points.len(), branch.points.last().unwrap().param, branch.end);
    for b in &branch.bifurcations {
        eprintln!("  {} at {:.12} {:?}", b.kind.name(), b.param, b.x);
    }
    // Closed where it started: the last point is the first orbit.
    assert!(branch.end.starts_with("closed"), "{}", branch.end);
    let (first, last) = (&branch.points[0], branch.points.last().unwrap());
    let off = first.orbit.x.iter().zip(&last.orbit.x).fold((first.param - last.param).abs(), |a, (u, v)| a.max((u - v).abs()));
    assert!(off <= 1e-9, "the last point is {off:e} from the first");
    // Every point a fixed point of the transcribed map, one impact.
    for p in &branch.points {
        let x = [p.orbit.x[0], p.orbit.x[1]];
        let (y, k) = map(p.param, x);
        let d = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
        assert!(d <= 1e-9 && k == 1 && p.orbit.impacts() == 1, "Ω = {}: {x:?} maps {d:e} away, {k} impacts", p.param);
    }
    // Both ends of the isola in Ω, each fold once.
    let (lo, hi) = branch.points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.param), b.max(p.param)));
    assert!(lo < 5.545 && hi > 6.005, "the branch spans {lo} to {hi}");
    let kinds: Vec<(&str, f64)> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect();
    assert!(branch.bifurcations.len() == 2 && branch.bifurcations.iter().all(|b| b.kind == BifurcationKind::Fold), "{kinds:?}");
    // Each fold where the transcription's orbits end: Newton from the
    // fold's state and from the branch's points on either side of it finds
    // one 1e-6 inside the isola and none 1e-6 outside (within 0.05 of it).
    for b in &branch.bifurcations {
        let inside = if b.param > 5.8 { -1.0 } else { 1.0 };
        let x = [b.x[0], b.x[1]];
        let seeds = [x, [branch.points[b.between.0].orbit.x[0], branch.points[b.between.0].orbit.x[1]], [branch.points[b.between.1].orbit.x[0], branch.points[b.between.1].orbit.x[1]]];
        let near = |w: f64| seeds.iter().filter_map(|s| fixed_point(w, *s)).any(|y| (y[0] - x[0]).abs().max((y[1] - x[1]).abs()) <= 0.05);
        assert!(near(b.param + inside * 1e-6), "no transcribed orbit inside the fold at {}", b.param);
        assert!(!near(b.param - inside * 1e-6), "a transcribed orbit past the fold at {}", b.param);
    }
}

/// The period-3 orbits of the same oscillator from Ω = 4 down (a range of
/// 2) form a loop: the branch was traced three times over, its period
/// doubling, grazings and fold listed once a lap, each lap at another
/// section state of the same orbits. Now it ends where it reaches its
/// first orbit again. It used to close on that orbit one forcing period
/// on: at the grazing at 3.1238 (a slow impact vanishing) a trial fell
/// onto the 1-impact orbit's state after one forcing period, 1.06 of the
/// state's scale from the branch's arc, and the branch turned onto it
/// there; it now turns onto the 1-impact orbits that meet its arc at the
/// grazing (3e-5 of the scale from it), the same orbits in their own
/// phase, and closes on the first orbit itself (81 points, not 75; the
/// same bifurcations, each once).
#[test]
fn a_loop_closes_on_its_first_orbit_without_a_phase_jump() {
    let (w0, p) = (4.0, 3);
    let start = periodic_orbit(&Isola(p).model(w0).unwrap(), 0.0, 3.0 * TAU / w0, &[-0.78, -0.30], &Newton::default()).unwrap();
    assert_eq!(start.impacts(), 1, "the 1-impact orbit at {w0}: {:?}", start.x);
    let branch = continuation(&Isola(p), &start.x, &ContinuationOptions::new(w0, 2.0)).unwrap();
    eprintln!("{} points to {}: {}", branch.points.len(), branch.points.last().unwrap().param, branch.end);
    for b in &branch.bifurcations {
        eprintln!("  {} at {:.12} {:?}", b.kind.name(), b.param, b.x);
    }
    assert!(branch.end.starts_with("closed"), "{}", branch.end);
    // The last point is the first orbit itself, not its state after 1 or
    // 2 forcing periods (by the transcription's flow): no phase jump.
    let (first, last) = (&branch.points[0], branch.points.last().unwrap());
    let x0 = [first.orbit.x[0], first.orbit.x[1]];
    let shifted = [x0, map_over(1, w0, x0).0, map_over(2, w0, x0).0];
    let off: Vec<f64> = shifted.iter().map(|y| (y[0] - last.orbit.x[0]).abs().max((y[1] - last.orbit.x[1]).abs())).collect();
    assert!(last.param == w0 && off[0] <= 1e-9, "the last point at {} is {:e}, {:e}, {:e} from the first orbit's states after 0, 1, 2 periods", last.param, off[0], off[1], off[2]);
    // Every point (its slowest impact above 1e-3) a fixed point of the
    // transcribed map over three periods with as many impacts.
    let mut checked = 0;
    for q in &branch.points {
        if q.orbit.slowest_impact().is_some_and(|v| v < 1e-3) {
            continue;
        }
        let x = [q.orbit.x[0], q.orbit.x[1]];
        let (y, k) = map_over(p, q.param, x);
        let d = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
        assert!(d <= 1e-9 && k == q.orbit.impacts(), "Ω = {}: {x:?} maps {d:e} away, {k} impacts against {}", q.param, q.orbit.impacts());
        checked += 1;
    }
    assert!(checked >= 40, "{checked} points checked");
    // No bifurcation listed twice (a second lap lists each again, at a
    // shifted state: the same parameter to 1e-8).
    for (i, a) in branch.bifurcations.iter().enumerate() {
        for b in &branch.bifurcations[..i] {
            assert!(!(a.kind == b.kind && (a.param - b.param).abs() <= 1e-8), "{} at {} listed twice", a.kind.name(), a.param);
        }
    }
}
