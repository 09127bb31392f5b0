//! A branch along orbits with a slow impact: the oscillator between
//! symmetric stops (`x'' + 0.1 x' + x = 2 sin Ωt`, `|x| <= 1`, e = 0.8),
//! its period-3 orbits with two impacts continued from Ω = 3.83 down. At
//! Ω = 3.8240736 a flight reaches a stop and the branch turns back onto
//! orbits with a third, slow impact (its speed growing from 0 as Ω rises).
//! Along them `G_λ` by a forward difference of 1e-7 of the range erred by
//! about `h/v²` of itself (2642 where it is 1490 at v = 8.75e-4): the
//! corrector failed at every step, a natural-parameter Newton fell onto
//! the 2-impact orbits the branch had come down, and the branch named a
//! grazing where no impact vanishes (the slow one at 8.75e-4 and rising)
//! and went back up the 2-impact arc. Checked against a transcription of
//! the oscillator sharing no code with the crate (its closed-form flow
//! between impacts, its own impact search, the restitution by hand): the
//! 3-impact orbits go on past Ω = 3.8265 (a multiple shooting with the
//! impact sequence fixed finds them admissible to Ω = 3.95), every point of
//! the branch is a fixed point of the transcribed map over three periods
//! with the branch's number of impacts, the one grazing is where the
//! transcription's flight touches the stop, and the 3-impact orbits' fold
//! (3.9627076) is where its central differences have a multiplier at +1.

use crate::between::{jacobian, map_between, E};
use crate::continuation;
use signorini_orbits::{periodic_orbit, BifurcationKind, ContinuationOptions, Family, Model, Newton, OrbitError};
use std::f64::consts::TAU;

pub(crate) const P: usize = 3;

pub(crate) struct Between;

impl Family for Between {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        crate::between::model(w)
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(P as f64 * TAU / w)
    }
}

/// The transcription's map over `P` forcing periods between `|x| <= 1`
/// ([`map_between`]: the flow sampled at 1/4000 of a period, split at
/// extrema), with the image, the impacts and the smallest margin of a
/// flight's extremum to a stop.
pub(crate) fn map(w: f64, x: [f64; 2]) -> ([f64; 2], usize, f64) {
    map_between(w, x, P, (-1.0, 1.0), E, 4000.0)
}

#[test]
fn a_branch_follows_its_slow_impact_past_the_grazing() {
    let w0 = 3.83;
    let start = periodic_orbit(&Between.model(w0).unwrap(), 0.0, P as f64 * TAU / w0, &[-0.957, -0.725], &Newton::default()).unwrap();
    assert_eq!(start.impacts(), 2, "the 2-impact orbit at {w0}: {:?}", start.x);
    // Toward 0.83: a range of 3 (the difference step in Ω is 1e-7 of it,
    // 3e-7; over a range of 0.03 the step is 3e-9 and the plain forward
    // difference serves), 50 points (to just past the fold of the 3-impact
    // orbits at 3.9627).
    let branch = continuation(&Between, &start.x, &ContinuationOptions { max_points: 50, ..ContinuationOptions::new(w0, 0.83) }).unwrap();
    eprintln!("{} points to {}: {}", branch.points.len(), branch.points.last().unwrap().param, branch.end);
    for b in &branch.bifurcations {
        eprintln!("  {} at {:.12} (impacts {:?})", b.kind.name(), b.param, b.impacts);
    }
    // Every point is a fixed point of the transcribed map with as many
    // impacts (the transcription's sampling sees a slow impact down to
    // about 1e-3 of the others' speed: below it the points are skipped).
    let mut checked = 0;
    for p in &branch.points {
        if p.orbit.slowest_impact().is_some_and(|v| v < 1e-3) {
            continue;
        }
        let x = [p.orbit.x[0], p.orbit.x[1]];
        let (y, k, _) = map(p.param, x);
        let off = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
        assert!(off <= 1e-9 && k == p.orbit.impacts(), "Ω = {}: {x:?} maps {off:e} away, {k} impacts against {}", p.param, p.orbit.impacts());
        checked += 1;
    }
    // Once on the 3-impact orbits the branch stays on them (no fall back
    // onto the 2-impact arc it came down), and goes past Ω = 3.8265, where
    // their transcribed orbits still have three impacts, to their fold.
    let first = branch.points.iter().position(|p| p.orbit.impacts() == 3).unwrap_or_else(|| panic!("no 3-impact orbit on the branch: {}", branch.end));
    assert!(
        branch.points[first..].iter().all(|p| p.orbit.impacts() == 3),
        "the branch falls back onto the 2-impact orbits: {:?}",
        branch.points[first..].iter().map(|p| (p.param, p.orbit.impacts())).collect::<Vec<_>>()
    );
    assert!(branch.points.iter().any(|p| p.param > 3.96), "the 3-impact orbits end at {}: {}", branch.points.last().unwrap().param, branch.end);
    // The grazing, where a flight of the transcribed 2-impact orbit comes
    // within 1e-6 of the stop, and the fold of the 3-impact orbits, where
    // the transcribed map's central differences have a multiplier at +1
    // (to 1e-3), and the period doubling past it (below); nothing else
    // listed (no grazing where no impact vanishes).
    let kinds: Vec<(&str, f64)> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect();
    let kind = |k: BifurcationKind| branch.bifurcations.iter().filter(|b| b.kind == k).collect::<Vec<_>>();
    let [g, f, pd] = [BifurcationKind::Grazing, BifurcationKind::Fold, BifurcationKind::PeriodDoubling].map(|k| *kind(k).first().unwrap_or_else(|| panic!("no {k:?}: {kinds:?}")));
    assert!(branch.bifurcations.len() == 3, "{kinds:?}");
    let (_, k, margin) = map(g.param, [g.x[0], g.x[1]]);
    assert!(k == 2 && margin < 1e-6, "at the grazing {}: {k} impacts, the flight {margin:e} from the stop", g.param);
    // The transcription's multipliers at `(w, x)` (central differences):
    // half the trace, the discriminant's root and `det(P' + I)`.
    let multipliers = |w: f64, x: [f64; 2]| {
        let j = jacobian(x, |y| map(w, y).0);
        let (tr, det) = (j[0][0] + j[1][1], j[0][0] * j[1][1] - j[0][1] * j[1][0]);
        (0.5 * tr, (0.25 * tr * tr - det).max(0.0).sqrt(), det + tr + 1.0)
    };
    let (half, disc, _) = multipliers(f.param, [f.x[0], f.x[1]]);
    let near_one = (half + disc - 1.0).abs().min((half - disc - 1.0).abs());
    assert!(map(f.param, [f.x[0], f.x[1]]).1 == 3 && near_one < 1e-3, "at the fold {}: the transcription's multipliers {half} ± {disc}", f.param);
    // The period doubling 1.2e-4 past the fold, crossed with it in one
    // step (`det(P' − I)` and `det(P' + I)` both changing sign) and not
    // listed before: the transcription's `det(P' + I)` changes sign between
    // the branch's points around it, and its multiplier there is −1 (to
    // 1e-3).
    let st = |q: &signorini_orbits::BranchPoint| [q.orbit.x[0], q.orbit.x[1]];
    let (a, b) = (&branch.points[pd.between.0], &branch.points[pd.between.1]);
    let (da, db) = (multipliers(a.param, st(a)).2, multipliers(b.param, st(b)).2);
    assert!(da * db < 0.0, "det(P' + I) of the transcription keeps its sign across the period doubling at {}: {da}, {db}", pd.param);
    let (half, disc, _) = multipliers(pd.param, [pd.x[0], pd.x[1]]);
    let near = (half + disc + 1.0).abs().min((half - disc + 1.0).abs());
    assert!(map(pd.param, [pd.x[0], pd.x[1]]).1 == 3 && near < 1e-3, "at the period doubling {}: the transcription's multipliers {half} ± {disc}", pd.param);
    eprintln!("{checked} points checked against the transcription");
    assert!(checked >= 20, "{checked} points checked");
}
