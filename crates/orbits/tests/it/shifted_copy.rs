//! A branch of orbits of two forcing periods that returns onto its copy
//! one forcing period on: the oscillator between symmetric stops
//! (`between.rs`: `x'' + 0.1 x' + x = 2 sin Ωt`, `|x| <= 1`, e = 0.8) has
//! stable period-2 orbits at Ω = 1.3, born at the period doubling of its
//! period-1 orbits near 1.31805. Continued up in Ω as orbits of two
//! periods they shrink onto the period-1 orbit there, where they meet
//! their own states after one forcing period (a pitchfork of the 2-period
//! map), and turn onto that copy: the branch ends `returned onto itself …
//! shifted by 1 forcing period` (`Returns::check` on the states after one
//! period the corrector's flow read). Checked against the transcription
//! of `between.rs` (no code of the crate): the last point and its state
//! after one forcing period (the transcription's flow) are both fixed
//! points of its 2-period map, distinct, with the same impacts; the
//! period-1 orbit Newton finds on its 1-period map from the last point
//! lies between them; the turn, inside the last step, is listed as a
//! branch point of the 2-period map where its `det(P₁' + I)` changes sign
//! (the branch ends at 1.3178233, 25 points, the last the step's end on
//! the copy: the copy 4.3e-2 from it, the period-1 orbit 2.0e-2 from it;
//! the turn at 1.3180499, 1.0e-6 below the transcription's period
//! doubling). Planted: the locator skipped on the return's step — the
//! last bifurcation listed is the period doubling at 1.3132; before the
//! step's end was kept (the branch ended at 1.3179901, 24 points): the
//! states after one period read as the state itself (`k` shifted by one)
//! — the branch leaves the range at 1.195 (78 points); the return onto a
//! traced segment left out — it goes back down its copy and closes on its
//! first orbit shifted by one period (48 points).

use crate::between::{fixed_point, flow_between, jacobian, map_between, model, E};
use crate::continuation;
use signorini_orbits::{periodic_orbit, BifurcationKind, ContinuationOptions, Family, Model, Newton, OrbitError};
use std::f64::consts::TAU;

/// The oscillator's orbits of two forcing periods.
struct Two;

impl Family for Two {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        model(w)
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(2.0 * TAU / w)
    }
    fn periods(&self) -> usize {
        2
    }
}

#[test]
fn a_period_two_branch_ends_where_it_returns_onto_its_copy_one_period_on() {
    let w0 = 1.3;
    let m = model(w0).unwrap();
    // The stable 6-impact orbit of `signorini continue
    // data/scenes/oscillator-two-stops.toml --period 2` at Ω = 1.3 (forced
    // by 2 cos Ωt: its state at t = 0 is the sine-forced one's at T/4),
    // flowed on to the section of the sine.
    let t = TAU / w0;
    let x0 = m.flow(0.25 * t, &[0.7734981963863, -0.3290463060712], 0.75 * t, false).unwrap().x;
    let start = periodic_orbit(&m, 0.0, 2.0 * t, &x0, &Newton::default()).unwrap();
    assert_eq!(start.impacts(), 6, "the period-2 orbit at {w0}: {:?}", start.x);
    let branch = continuation(&Two, &start.x, &ContinuationOptions::new(w0, 1.5)).unwrap();
    let last = branch.points.last().unwrap();
    eprintln!("{} points to {}: {}", branch.points.len(), last.param, branch.end);
    assert!(branch.end.starts_with("returned onto itself") && branch.end.contains("shifted by 1 forcing period,"), "{}", branch.end);
    let w = last.param;
    let x = [last.orbit.x[0], last.orbit.x[1]];
    // The last point and its copy one period on: orbits of the 2-period map.
    let (y, _, _) = flow_between(w, 0.0, TAU / w, x, (-1.0, 1.0), E, 4000.0);
    let copy_gap = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
    for z in [x, y] {
        let (pz, k, _) = map_between(w, z, 2, (-1.0, 1.0), E, 4000.0);
        let off = (pz[0] - z[0]).abs().max((pz[1] - z[1]).abs());
        assert!(off <= 1e-9 && k == last.orbit.impacts(), "Ω = {w}: {z:?} maps {off:e} away, {k} impacts against {}", last.orbit.impacts());
    }
    // The period-1 orbit between them.
    let z = fixed_point([0.5 * (x[0] + y[0]), 0.5 * (x[1] + y[1])], 60, |s| map_between(w, s, 1, (-1.0, 1.0), E, 4000.0).0).expect("the period-1 orbit");
    let between = (z[0] - x[0]).abs().max((z[1] - x[1]).abs());
    eprintln!("Ω = {w}: the copy {copy_gap:e} from the last point, the period-1 orbit {between:e} from it");
    assert!(copy_gap > 1e-6, "the last point is the period-1 orbit itself ({copy_gap:e} from its copy)");
    assert!(between < copy_gap, "the period-1 orbit {z:?}: {between:e} from the last point");
    // The turn onto the copy, inside the last step, is located as any
    // step's bifurcations are: a branch point of the 2-period map (the
    // branch turns there, a multiplier at +1) at the period doubling of the
    // period-1 orbits, where the transcription's `det(P₁' + I)` changes
    // sign. Within 1e-5: the corrector fails near the pitchfork (two
    // branches cross there), and the bracket's two ends, on either side of
    // the turn, interpolate to a parameter short of it (1.0e-6 here).
    let n = branch.points.len();
    let turn = branch.bifurcations.last().expect("the turn listed");
    assert!(turn.kind == BifurcationKind::BranchPoint && turn.between == (n - 2, n - 1), "the last bifurcation {:?} at {} between {:?} ({n} points)", turn.kind, turn.param, turn.between);
    let det_plus = |w: f64| {
        let z = fixed_point(z, 60, |s| map_between(w, s, 1, (-1.0, 1.0), E, 4000.0).0).expect("the period-1 orbit");
        let j = jacobian(z, |s| map_between(w, s, 1, (-1.0, 1.0), E, 4000.0).0);
        (j[0][0] + 1.0) * (j[1][1] + 1.0) - j[0][1] * j[1][0]
    };
    let (below, above) = (det_plus(turn.param - 1e-5), det_plus(turn.param + 1e-5));
    eprintln!("the turn at {}: det(P₁' + I) {below:e} at −1e-5, {above:e} at +1e-5", turn.param);
    assert!(below * above < 0.0, "no period doubling of the period-1 orbits within 1e-5 of the turn at {}: det(P₁' + I) {below:e}, {above:e}", turn.param);
}
