//! A turn in the parameter where a multiplier touches +1 without passing
//! it: the oscillator between symmetric stops (`x'' + 0.1 x' + x = 2 sin
//! Ωt`, `|x| <= 1`, e = 0.8), its asymmetric period-3 orbits with two
//! impacts, continued from Ω = 5 up, turn at Ω = 5.0609 onto their mirror
//! images, where they meet the symmetric orbit (its pitchfork). Traced
//! over a range of 3 (the hunt's) the turn was listed on one pass and not
//! on another, the bisection's multiplier farther than 1e-2 from +1 at
//! one of them. A turn is a fold only where a multiplier passes through
//! +1 (the orbits on one side of it stable, on the other unstable);
//! checked against a transcription of the map sharing no code with the
//! crate (`slow_impact.rs`'s: the closed-form flow between impacts, its
//! own impact search): at the branch's points on either side of the turn
//! its central differences put both multipliers inside the unit circle
//! and `det(J − I)` of one sign, so the turn is no fold. From either
//! start (the orbit at Ω = 5 and its mirror image) the branch lists it
//! once, a branch point, at the same Ω.

use crate::between::jacobian;
use crate::continuation;
use crate::slow_impact::{map, Between, P};
use signorini_orbits::{periodic_orbit, BifurcationKind, ContinuationOptions, Family, Newton};
use std::f64::consts::TAU;

/// The transcription's multipliers at `x` (central differences, step
/// 1e-7): the largest modulus and `det(J − I)`.
fn multipliers(w: f64, x: [f64; 2]) -> (f64, f64) {
    let j = jacobian(x, |y| map(w, y).0);
    let (tr, det) = (j[0][0] + j[1][1], j[0][0] * j[1][1] - j[0][1] * j[1][0]);
    let disc = 0.25 * tr * tr - det;
    let largest = if disc >= 0.0 { (0.5 * tr).abs() + disc.sqrt() } else { det.sqrt() };
    (largest, (j[0][0] - 1.0) * (j[1][1] - 1.0) - j[0][1] * j[1][0])
}

#[test]
fn a_turn_onto_the_mirror_image_is_a_branch_point_from_either_side() {
    let w0 = 5.0;
    let mut at = Vec::new();
    for (guess, to) in [([-0.851, 0.644], 8.0), ([-0.894, 0.729], 6.0)] {
        let start = periodic_orbit(&Between.model(w0).unwrap(), 0.0, P as f64 * TAU / w0, &guess, &Newton::default()).unwrap();
        let branch = continuation(&Between, &start.x, &ContinuationOptions { max_points: 12, ..ContinuationOptions::new(w0, to) }).unwrap();
        let kinds: Vec<(&str, f64)> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect();
        eprintln!("from {:?} to {to}: {} points to {}: {kinds:?}", start.x, branch.points.len(), branch.points.last().unwrap().param);
        let turns: Vec<_> = branch.bifurcations.iter().filter(|b| b.param > 5.05).collect();
        assert!(turns.len() == 1 && turns[0].kind == BifurcationKind::BranchPoint, "from {:?}: {kinds:?}", start.x);
        let b = turns[0];
        // Either side of the turn: no multiplier of the transcription
        // outside the unit circle, det(J − I) of one sign.
        let (p, q) = (&branch.points[b.between.0], &branch.points[b.between.1]);
        let (mp, dp) = multipliers(p.param, [p.orbit.x[0], p.orbit.x[1]]);
        let (mq, dq) = multipliers(q.param, [q.orbit.x[0], q.orbit.x[1]]);
        assert!(mp < 1.0 && mq < 1.0 && dp * dq > 0.0, "at {} and {}: |μ| {mp}, {mq}, det(J − I) {dp:e}, {dq:e}", p.param, q.param);
        assert!((p.param - b.param) * (q.param - b.param) >= 0.0 && p.param.min(q.param) < b.param, "the turn at {} between {} and {}", b.param, p.param, q.param);
        at.push(b.param);
    }
    assert!((at[0] - at[1]).abs() <= 1e-4, "the turn at {} and at {}", at[0], at[1]);
}

/// The same orbits continued from Ω = 5 to 5.5 (a range of 0.5) do not
/// turn: at the pitchfork they pass onto the symmetric orbits, the
/// multiplier touching +1 with no test changing sign, and the branch
/// listed nothing there. It now names a branch point where the
/// asymmetry (the least distance of the mirror images `−x((k + ½)T)`
/// from the state) reaches 0. Checked against the transcription
/// (`between.rs`'s flow, no code of the crate): the branch's points on
/// either side of it are fixed points of its map, the one before
/// asymmetric (by its own half-period flows, above 1e-3), the one after
/// symmetric (below 1e-8), `det(J − I)` of one sign at both (no
/// multiplier through +1: no fold, nothing for the determinant's test).
#[test]
fn a_pass_onto_the_symmetric_orbits_is_a_branch_point() {
    use crate::between::{flow_between, E};
    let w0 = 5.0;
    let start = periodic_orbit(&Between.model(w0).unwrap(), 0.0, P as f64 * TAU / w0, &[-0.851, 0.644], &Newton::default()).unwrap();
    let branch = continuation(&Between, &start.x, &ContinuationOptions::new(w0, 5.5)).unwrap();
    let kinds: Vec<(&str, f64)> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect();
    eprintln!("{} points to {}: {}: {kinds:?}", branch.points.len(), branch.points.last().unwrap().param, branch.end);
    assert_eq!(branch.end, "reached to");
    let near: Vec<_> = branch.bifurcations.iter().filter(|b| (b.param - 5.0609).abs() < 2e-3).collect();
    assert!(near.len() == 1 && near[0].kind == BifurcationKind::BranchPoint, "{kinds:?}");
    let b = near[0];
    let asymmetry = |w: f64, x: [f64; 2]| {
        (0..P)
            .map(|k| {
                let y = flow_between(w, 0.0, (k as f64 + 0.5) * TAU / w, x, (-1.0, 1.0), E, 4000.0).0;
                (y[0] + x[0]).abs().max((y[1] + x[1]).abs())
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (p, q) = (&branch.points[b.between.0], &branch.points[b.between.1]);
    let (xp, xq) = ([p.orbit.x[0], p.orbit.x[1]], [q.orbit.x[0], q.orbit.x[1]]);
    for (w, x) in [(p.param, xp), (q.param, xq)] {
        let (y, _, _) = map(w, x);
        let off = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
        assert!(off <= 1e-9, "Ω = {w}: {x:?} is no fixed point of the transcription ({off:e})");
    }
    let (ap, aq) = (asymmetry(p.param, xp), asymmetry(q.param, xq));
    let ((mp, dp), (mq, dq)) = (multipliers(p.param, xp), multipliers(q.param, xq));
    eprintln!("branch point at {}: Ω = {} asymmetry {ap:e}, |μ| {mp}, det(J − I) {dp:e}; Ω = {} asymmetry {aq:e}, |μ| {mq}, det(J − I) {dq:e}", b.param, p.param, q.param);
    assert!(ap > 1e-3 && aq < 1e-8, "asymmetry {ap:e} at {} and {aq:e} at {}", p.param, q.param);
    assert!((b.param - p.param) * (b.param - q.param) <= 0.0, "the branch point at {} outside its step {} … {}", b.param, p.param, q.param);
    assert!(dp * dq > 0.0 && mp < 1.0 && mq < 1.0, "det(J − I) {dp:e}, {dq:e}; |μ| {mp}, {mq}");
}
