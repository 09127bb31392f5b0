//! An impact crossing the section's time along a branch: the oscillator
//! between symmetric stops (`x'' + 0.1 x' + x = 2 sin Ωt`, `|x| <= 1`,
//! e = 0.8), its asymmetric orbit continued from Ω = 1.5 down. Past the
//! fold at 1.3311 its stable 3-impact orbit's impact at −1 reaches the
//! section (`x(0) = −1`) at Ω = 1.32838440, and again, back, at
//! 1.08871925. At the first the branch took the stable 2-impact orbit
//! that coexists there, 0.3 away in the state (Newton from the state with
//! the impulse applied, 2.3e-9 further on, landed on it), went back along
//! the 2-impact arc it had traced, and listed nothing at the jump; at the
//! second the corrector stalled (its difference in Ω put the impact into
//! the period's end: `G_λ` 1.8e8). Checked against a transcription of the
//! oscillator sharing no code with the crate (its closed-form flow between
//! impacts, its own impact search, the restitution by hand): every point
//! is a fixed point of the transcribed map with the crate's number of
//! impacts, and the period doubling is where `det(P' + I)` of the
//! transcribed map changes sign.

use crate::between::{jacobian, map_between, E};
use crate::continuation;
use signorini_orbits::{periodic_orbit, BifurcationKind, ContinuationOptions, Family, Model, Newton, OrbitError};
use std::f64::consts::TAU;

struct Between;

impl Family for Between {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        crate::between::model(w)
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(TAU / w)
    }
}

/// The transcription's map over a forcing period and its impacts
/// (between.rs's `map_between` at 1/4000 of the period between the stops
/// ±1).
fn map(w: f64, x: [f64; 2]) -> ([f64; 2], usize) {
    let (y, impacts, _) = map_between(w, x, 1, (-1.0, 1.0), E, 4000.0);
    (y, impacts)
}

/// `det(J + I)` of the transcribed map's central differences at `x`.
fn det_plus_i(w: f64, x: [f64; 2]) -> f64 {
    let j = jacobian(x, |y| map(w, y).0);
    (j[0][0] + 1.0) * (j[1][1] + 1.0) - j[0][1] * j[1][0]
}

#[test]
fn an_impact_crossing_the_section_keeps_the_branch_on_its_orbits() {
    let w0 = 1.5;
    let m = Between.model(w0).unwrap();
    let x0 = m.flow(0.0, &[0.0, 0.0], 400.0 * TAU / w0, false).unwrap().x;
    let start = periodic_orbit(&m, 0.0, TAU / w0, &x0, &Newton::default()).unwrap();
    let branch = continuation(&Between, &start.x, &ContinuationOptions::new(w0, 0.9)).unwrap();
    eprintln!("{} points to {}: {}", branch.points.len(), branch.points.last().unwrap().param, branch.end);
    for b in &branch.bifurcations {
        eprintln!("  {} at {:.12} (impacts {:?})", b.kind.name(), b.param, b.impacts);
    }
    // Every point whose slowest impact the transcription's sampling sees
    // (speed 1e-2 and more) is a fixed point of the transcribed map, with
    // as many impacts.
    let mut checked = 0;
    for p in &branch.points {
        if p.orbit.slowest_impact().is_some_and(|v| v < 1e-2) {
            continue;
        }
        let x = [p.orbit.x[0], p.orbit.x[1]];
        let (y, k) = map(p.param, x);
        let off = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
        assert!(off <= 1e-9 && k == p.orbit.impacts(), "Ω = {}: {x:?} maps {off:e} away, {k} impacts against {}", p.param, p.orbit.impacts());
        checked += 1;
    }
    // Past both crossings of the section (1.32838440 and 1.08871925) the
    // branch goes on along the 3-impact orbits, its state near −1 on the
    // section there (within 1e-2: the impact just before or after it),
    // not on another arc.
    for at in [1.3283844, 1.0887193] {
        let i = branch
            .points
            .iter()
            .position(|p| (p.param - at).abs() < 1e-6 && (p.orbit.x[0] + 1.0).abs() < 1e-6)
            .unwrap_or_else(|| panic!("the branch never reaches the section crossing at {at}: {}", branch.end));
        let next: Vec<_> = branch.points[i + 1..].iter().take(4).map(|p| (p.param, p.orbit.impacts(), p.orbit.x[0])).collect();
        assert!(next.len() == 4 && next.iter().all(|&(w, k, x)| k == 3 && (x + 1.0).abs() < 1e-2 && w < at + 1e-6), "past Ω = {at}: {next:?} ({})", branch.end);
    }
    assert!(branch.points.iter().any(|p| p.param < 1.06 && p.orbit.impacts() == 3), "the branch ends at {}", branch.end);
    // The period doubling of the 3-impact orbits, where the transcribed
    // map's det(P' + I) changes sign (its orbits from the crate's nearest
    // points, refined by Newton on the transcription's differences: here
    // the map's own points bracket it to 1e-6).
    let pd = branch
        .bifurcations
        .iter()
        .find(|b| b.kind == BifurcationKind::PeriodDoubling)
        .unwrap_or_else(|| panic!("no period doubling listed: {:?}", branch.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect::<Vec<_>>()));
    let orbit_at = |w: f64| periodic_orbit(&Between.model(w).unwrap(), 0.0, TAU / w, &pd.x, &Newton { tol: 1e-11, ..Newton::default() }).unwrap().x;
    let (lo, hi) = (pd.param - 1e-6, pd.param + 1e-6);
    let (a, b) = (orbit_at(lo), orbit_at(hi));
    for (w, x) in [(lo, &a), (hi, &b)] {
        let (y, _) = map(w, [x[0], x[1]]);
        assert!((y[0] - x[0]).abs().max((y[1] - x[1]).abs()) <= 1e-9, "Ω = {w}: not a fixed point of the transcription");
    }
    let (da, db) = (det_plus_i(lo, [a[0], a[1]]), det_plus_i(hi, [b[0], b[1]]));
    assert!(da * db < 0.0, "det(P' + I) keeps its sign across the period doubling at {}: {da} {db}", pd.param);
    eprintln!("{checked} points checked against the transcription");
    assert!(checked >= 100, "{checked} points checked");
}
