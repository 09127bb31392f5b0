//! A grazing where the branch turns back, met from far: the sine-forced
//! period-3 loop of `isola.rs` (`x'' + 0.1 x' + x = 2 sin Ωt`, stops −1
//! and 0.5, e = 0.3) from Ω = 4 down with the parameter's scale 4. Its
//! 2-impact orbits lose their slow impact where the 1-impact orbits'
//! flight reaches a stop, and turn back into them (a nonsmooth fold).
//! The branch crawls near Ω = 3.139 (the corrector's residual at its
//! floor, docs/orbits.md) and meets the 1-impact orbits from two points
//! 2.2e-7 apart at Ω = 3.1387640, 1.5e-2 above the grazing: the 2-impact
//! arc extrapolated linearly from them missed the 1-impact orbit at the
//! grazing by 0.83 in the state, the turn was refused, and the branch
//! listed a grazing at 3.1387178, where the transcription has none, and
//! ended without closing. Now the turn is confirmed from the 1-impact
//! side where the extrapolation is that long (`continuation.rs`,
//! `meets_by_speed`).

use crate::between::{fixed_point, map_between};
use crate::continuation;
use crate::isola::{Isola, E, HI, LO};
use signorini_orbits::{periodic_orbit, BifurcationKind, ContinuationOptions, Family, Newton};
use std::f64::consts::TAU;

/// The transcription's map over three forcing periods: the image, its
/// impacts and the least distance of a flight's extremum to a stop.
fn map(w: f64, x: [f64; 2]) -> ([f64; 2], usize, f64) {
    map_between(w, x, 3, (LO, HI), E, 1000.0)
}

/// The transcription's grazing of the 1-impact orbits from `(w, x)` on
/// them: the zero in Ω of their flight's margin to the stop, by secant
/// steps on their fixed points (Newton on the transcribed map, each from
/// the last) from `w` and a fortieth of the way toward 3.1239 (`isola.rs`
/// puts the grazing at 3.1238). Past the grazing there is no 1-impact
/// orbit (the arc turns back): a step landing there marks the bracket's
/// far end, and the next is the secant's clipped to the bracket's nearer
/// half (a bisection at worst), so that each step past it costs one
/// failed Newton, not a run of halvings.
fn grazing(w: f64, x: [f64; 2]) -> f64 {
    let orbit = |w: f64, x: [f64; 2]| -> Option<([f64; 2], f64)> {
        let y = fixed_point(x, 60, |z| map(w, z).0)?;
        let (_, k, margin) = map(w, y);
        (k == 1 && margin > 0.0).then_some((y, margin))
    };
    let (mut x1, mut m1) = orbit(w, x).expect("a 1-impact orbit at the start");
    let (mut w0, mut m0, mut w1) = (w, m1, w - (w - 3.1239) / 40.0);
    (x1, m1) = orbit(w1, x1).expect("a 1-impact orbit a fortieth of the way on");
    // The nearest Ω known past the grazing (none yet).
    let mut past = f64::NEG_INFINITY;
    for _ in 0..200 {
        let secant = w1 - m1 * (w1 - w0) / (m1 - m0);
        let next = if secant > past + 0.5 * (w1 - past) || past == f64::NEG_INFINITY { secant } else { past + 0.5 * (w1 - past) };
        if (next - w1).abs() <= 1e-14 {
            return next;
        }
        match orbit(next, x1) {
            Some((y, m)) => (w0, m0, w1, x1, m1) = (w1, m1, next, y, m),
            None => past = next,
        }
    }
    w1
}

/// The branch lists the 2 → 1 grazing once, at the transcription's (to
/// 1e-9), goes on from a 1-impact orbit of the transcription, and closes
/// the loop.
#[test]
fn a_turn_at_a_grazing_met_from_far_is_located_on_the_turning_arc() {
    let (w0, p) = (4.0, 3);
    let start = periodic_orbit(&Isola(p).model(w0).unwrap(), 0.0, 3.0 * TAU / w0, &[-0.78, -0.30], &Newton::default()).unwrap();
    let branch = continuation(&Isola(p), &start.x, &ContinuationOptions { scale: Some(4.0), max_points: 600, ..ContinuationOptions::new(w0, 2.0) }).unwrap();
    eprintln!("{} points to {}: {}", branch.points.len(), branch.points.last().unwrap().param, branch.end);
    for b in &branch.bifurcations {
        eprintln!("  {} at {:.13} {:?}", b.kind.name(), b.param, b.impacts);
    }
    let turns: Vec<_> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::Grazing && b.impacts == (2, 1)).collect();
    assert_eq!(turns.len(), 1, "the 2 → 1 grazings: {:?}", turns.iter().map(|b| b.param).collect::<Vec<_>>());
    let b = turns[0];
    let after = &branch.points[b.between.1];
    let x = [after.orbit.x[0], after.orbit.x[1]];
    let (y, k, _) = map(after.param, x);
    let d = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
    assert!(d <= 1e-9 && k == 1, "the point after the turn (Ω = {}): {d:e} from a fixed point, {k} impacts", after.param);
    let want = grazing(after.param, x);
    eprintln!("the transcription's grazing {want:.13}, listed {:.13} ({:e})", b.param, (b.param - want).abs());
    assert!((b.param - want).abs() <= 1e-9, "the grazing listed at {}, the transcription's at {want}", b.param);
    assert!(branch.end.starts_with("closed"), "{}", branch.end);
}
