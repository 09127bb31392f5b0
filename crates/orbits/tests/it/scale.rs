//! What a branch lists does not depend on its range. The period-3 orbits
//! of `x'' + 0.1 x' + x = 2 cos Ωt` between the stops −1 and 0.5 (e = 0.3),
//! from their orbit at Ω = 4 down, graze at Ω = 3.4277, where the branch
//! turns back onto 2-impact orbits with a fold at 3.5022392 and a period
//! doubling at 3.5019175. The searches past the grazing were at fractions
//! of the range: from 4 to 1 the one at 1e-3 of it (3e-3 in Ω) found an
//! orbit of another arc, 0.022 away, and the branch went on along it,
//! listing neither (from 4 to 3 and to 2 both were listed). Their offsets
//! are now fractions of the problem's scale. Each range's fold and period
//! doubling are checked against a transcription sharing no code with the
//! crate (`between.rs`'s closed-form flow, the section a quarter period
//! on): `det(P' − I)` changes sign across the fold, with an orbit of the
//! transcription 1e-6 inside it and none within 1e-2 of it 1e-6 outside; `det(P' + I)`
//! changes sign across the period doubling.

use crate::between::{jacobian, map_between_from};
use crate::continuation;
use signorini_fem::SymBand;
use signorini_orbits::{BifurcationKind, ContinuationOptions, Family, Model, OrbitError};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::f64::consts::{FRAC_PI_2, TAU};
use std::sync::Arc;

const LO: f64 = -1.0;
const HI: f64 = 0.5;
const E: f64 = 0.3;

/// The crate's family: orbits of 3 forcing periods, the forcing a cosine.
struct Cosine;

impl Family for Cosine {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        let cosine = TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: crate::between::F, omega: w, phase: FRAC_PI_2 }]));
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: LO, hi: HI }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: cosine }])
            .with_damping(Some(SymBand::from_diagonal(&[crate::between::C])));
        Model::new(dy, E)
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(3.0 * TAU / w)
    }
    fn periods(&self) -> usize {
        3
    }
}

/// The transcription's map over 3 periods of `2 cos Ωt`: the sine-forced
/// flow from a quarter period on.
fn map(w: f64, x: [f64; 2]) -> ([f64; 2], usize) {
    let (y, k, _) = map_between_from(w, 0.25 * TAU / w, x, 3, (LO, HI), E, 1000.0);
    (y, k)
}

/// Newton on the transcription from `x` (between.rs's `fixed_point`,
/// within 40 iterations): the fixed point and its impacts.
fn fixed_point(w: f64, x: [f64; 2]) -> Option<([f64; 2], usize)> {
    crate::between::fixed_point(x, 40, |y| map(w, y).0).map(|y| (y, map(w, y).1))
}

/// `det(P' + s I)` of the transcription at its fixed point near `x`.
fn det(w: f64, x: [f64; 2], s: f64) -> f64 {
    let (y, _) = fixed_point(w, x).expect("the transcription's orbit at a branch point");
    let mut j = jacobian(y, |z| map(w, z).0);
    j[0][0] += s;
    j[1][1] += s;
    j[0][0] * j[1][1] - j[0][1] * j[1][0]
}

#[test]
fn the_fold_and_period_doubling_past_the_grazing_are_listed_whatever_the_range() {
    let mut listed = Vec::new();
    for to in [3.0, 2.0, 1.0] {
        let opts = ContinuationOptions { max_points: 70, ..ContinuationOptions::new(4.0, to) };
        let branch = continuation(&Cosine, &[-0.78, -0.30], &opts).unwrap();
        let pts = &branch.points;
        let find = |kind: BifurcationKind| branch.bifurcations.iter().find(|b| b.kind == kind && (3.45..3.55).contains(&b.param));
        let (Some(fold), Some(pd)) = (find(BifurcationKind::Fold), find(BifurcationKind::PeriodDoubling)) else {
            panic!("4 → {to}: no fold or period doubling near 3.50 listed: {:?}", branch.bifurcations.iter().map(|b| (b.kind, b.param)).collect::<Vec<_>>());
        };
        // The fold: det(P' − I) of the transcription changes sign between
        // the branch's points around it; an orbit 1e-6 inside (below), none
        // 1e-6 outside.
        let (a, b) = (&pts[fold.between.0], &pts[fold.between.1]);
        let st = |p: &signorini_orbits::BranchPoint| [p.orbit.x[0], p.orbit.x[1]];
        assert!(det(a.param, st(a), -1.0) * det(b.param, st(b), -1.0) < 0.0, "4 → {to}: det(P' − I) keeps its sign across the fold at {}", fold.param);
        let x = [fold.x[0], fold.x[1]];
        let inside = fixed_point(fold.param - 1e-6, x);
        assert!(inside.is_some_and(|(_, k)| k == 2), "4 → {to}: no 2-impact orbit 1e-6 inside the fold at {}", fold.param);
        let outside = fixed_point(fold.param + 1e-6, x).filter(|(y, _)| (y[0] - x[0]).abs().max((y[1] - x[1]).abs()) <= 1e-2);
        assert!(outside.is_none(), "4 → {to}: an orbit 1e-6 outside the fold at {}", fold.param);
        let (a, b) = (&pts[pd.between.0], &pts[pd.between.1]);
        assert!(det(a.param, st(a), 1.0) * det(b.param, st(b), 1.0) < 0.0, "4 → {to}: det(P' + I) keeps its sign across the period doubling at {}", pd.param);
        listed.push((fold.param, pd.param));
    }
    // The same bifurcations, wherever the range ends.
    for (f, p) in &listed[1..] {
        assert!((f - listed[0].0).abs() <= 1e-9 && (p - listed[0].1).abs() <= 1e-9, "{listed:?}");
    }
}

/// Given the parameter's scale (`scale`: Λ = 4, the start's magnitude),
/// the runs from 4 to 1 and to 2 take the same steps: the arclength's
/// parameter scale, the searches' offsets at a grazing and the steps'
/// bounds are fractions of Λ, not of the range. Over their common part, [2, 4],
/// the two branches are the same points, every one a fixed point of the
/// transcription's map (1e-9 of the state, as many impacts), and list the
/// same bifurcations: the period doubling and fold of the 1-impact orbits
/// and the fold and period doubling past the grazing, each against the
/// transcription (`det(P' ∓ I)` changing sign between the points around
/// it). With offsets and steps of the range (no `scale`) the two runs'
/// points differ (200 and 355 of them before each closes its loop).
#[test]
fn the_runs_to_1_and_to_2_take_the_same_steps_and_list_the_same_bifurcations() {
    let run = |to: f64| continuation(&Cosine, &[-0.78, -0.30], &ContinuationOptions { scale: Some(4.0), ..ContinuationOptions::new(4.0, to) }).unwrap();
    let (one, two) = (run(1.0), run(2.0));
    let common = |b: &signorini_orbits::Branch| b.points.iter().take_while(|p| p.param >= 2.0).count();
    let (n1, n2) = (common(&one), common(&two));
    assert_eq!(n1, n2, "points over [2, 4]: {n1} to 1, {n2} to 2 ({} and {} in all; ends: {} / {})", one.points.len(), two.points.len(), one.end, two.end);
    for (k, (a, b)) in one.points.iter().zip(&two.points).take(n1).enumerate() {
        let d = a.orbit.x.iter().zip(&b.orbit.x).fold((a.param - b.param).abs(), |m, (u, v)| m.max((u - v).abs()));
        assert!(d <= 1e-12, "point {k}: 4 → 1 at {} {:?}, 4 → 2 at {} {:?}", a.param, a.orbit.x, b.param, b.orbit.x);
        let x = [a.orbit.x[0], a.orbit.x[1]];
        let (y, impacts) = map(a.param, x);
        let r = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
        assert!(r <= 1e-9 && impacts == a.orbit.impacts(), "point {k} at {}: the transcription's residual {r:e}, {impacts} impacts (the branch's {})", a.param, a.orbit.impacts());
    }
    let within = |b: &signorini_orbits::Branch| b.bifurcations.iter().filter(|f| f.between.1 < n1).map(|f| (f.kind, f.param)).collect::<Vec<_>>();
    let (l1, l2) = (within(&one), within(&two));
    assert_eq!(l1.len(), l2.len(), "{l1:?} / {l2:?}");
    for ((k1, p1), (k2, p2)) in l1.iter().zip(&l2) {
        assert!(k1 == k2 && (p1 - p2).abs() <= 1e-12, "{l1:?} / {l2:?}");
    }
    // The fold and period doubling past the grazing at 3.4277 and those of
    // the 1-impact orbits (3.837, 4.2609), against the transcription.
    let st = |p: &signorini_orbits::BranchPoint| [p.orbit.x[0], p.orbit.x[1]];
    let mut seen = (0, 0);
    for f in one.bifurcations.iter().filter(|f| f.between.1 < n1) {
        let s = match f.kind {
            BifurcationKind::Fold => -1.0,
            BifurcationKind::PeriodDoubling => 1.0,
            _ => continue,
        };
        let (a, b) = (&one.points[f.between.0], &one.points[f.between.1]);
        assert!(det(a.param, st(a), s) * det(b.param, st(b), s) < 0.0, "det(P' + {s} I) keeps its sign across the {:?} at {}", f.kind, f.param);
        if s < 0.0 {
            seen.0 += 1;
        } else {
            seen.1 += 1;
        }
    }
    assert_eq!(seen, (2, 2), "folds and period doublings over [2, 4]: {l1:?}");
    for (want, kind) in [(3.502239242907, BifurcationKind::Fold), (3.501917507165, BifurcationKind::PeriodDoubling)] {
        assert!(l1.iter().any(|(k, p)| *k == kind && (p - want).abs() <= 1e-9), "no {kind:?} at {want}: {l1:?}");
    }
}
