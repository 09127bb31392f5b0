//! What a family overrides reaches the continuation through the tests'
//! shim ([`crate::AnyFamily`]) and is used there: a family of scenes marks
//! each branch point with its scene's forcing frequency and tip
//! ([`Family::model_period_marker`]), and says the forcing periods its map
//! spans ([`Family::periods`]). Without the shim forwarding them the
//! defaults (no marks, one period) would be tested instead, and no other
//! test would see it.

use crate::continuation;
use signorini_orbits::{periodic_orbit, ContinuationOptions, Family, Newton, SceneFamily};
use std::f64::consts::TAU;

/// The oscillator `x'' + 0.1x' + x = A sin 1.3t` against a stop at 0.2
/// (e = 0.8), continued in its amplitude `A` from 1 to 1.2: every point is
/// marked, with the scene's Ω (1.3, which the parameter does not move) and
/// the displacement of the point's own state (the oscillator's tip; no
/// support motion). A family of 2 periods reports 2, and its map's horizon
/// is two forcing periods.
#[test]
fn a_family_of_scenes_marks_its_points_and_says_its_periods() {
    let doc = crate::oscillator(0.05, 0.2, 0.8, 1.3);
    let (fam, a0) = SceneFamily::new(doc.clone(), "forcing.amplitude", 1).unwrap();
    assert_eq!(a0, 1.0);
    let start = periodic_orbit(&fam.model(a0).unwrap(), 0.0, TAU / 1.3, &[0.1, 0.5], &Newton::default()).unwrap();
    let branch = continuation(&fam, &start.x, &ContinuationOptions::new(a0, 1.2)).unwrap();
    assert!(branch.points.len() >= 3, "{} points: {}", branch.points.len(), branch.end);
    for p in &branch.points {
        let mark = p.mark.as_ref().unwrap_or_else(|| panic!("the point at A = {} is not marked", p.param));
        assert_eq!(mark.omega, 1.3, "A = {}", p.param);
        assert_eq!(mark.tip, p.orbit.x[0], "A = {}", p.param);
    }
    let (two, _) = SceneFamily::new(doc, "forcing.amplitude", 2).unwrap();
    assert_eq!(crate::AnyFamily(&two).periods(), 2);
    let horizon = crate::AnyFamily(&two).period(a0).unwrap();
    assert!((horizon - 2.0 * TAU / 1.3).abs() <= 1e-15 * horizon, "{horizon}");
}
