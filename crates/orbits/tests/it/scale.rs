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
        let one = |v: f64| {
            let mut b = SymBand::zeros(1, 0);
            b.set(0, 0, v);
            b
        };
        let cosine = TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: crate::between::F, omega: w, phase: FRAC_PI_2 }]));
        let dy = Dynamics::new(one(1.0), one(1.0), vec![0.0], vec![Contact::new(0, Bounds { lo: LO, hi: HI }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: cosine }])
            .with_damping(Some(one(crate::between::C)));
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
