//! Symmetric stops: the impact oscillator between `−g` and `g`, forced
//! `2 sin Ωt`. Its symmetric orbit (`x(t + T/2) = −x(t)`) loses stability
//! by symmetry-breaking pitchforks — a multiplier through +1 where the
//! branch goes on in Ω — and the asymmetric pair born there meets it
//! again. Checked against oracles the continuation knows nothing of: the
//! symmetry itself (the state half a period on, by the flow), runs of the
//! flow from either side of the symmetric orbit (which leave it for a
//! mirror pair of attractors where it is unstable and return to it where
//! it is stable), and Liouville's formula for every multiplier product
//! (`det P' = e^{2N} e^{−cT/m}`: each impact's saltation has determinant
//! `e²`, the damping contracts areas by `e^{−cT/m}`).
//! Also two starts at the edge of a scene's domain: a restitution of 1
//! (the corrector's difference in the parameter stepped out of it) and a
//! forcing amplitude of 0 (the orbit at rest gave the state no scale).

use crate::between::{flow, C, E};
use crate::continuation;
use signorini_fem::SymBand;
use signorini_orbits::{periodic_orbit, BifurcationKind, Branch, ContinuationOptions, Family, Model, Newton, OrbitError, SceneFamily};
use signorini_scene::presets::set_path;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};
use std::f64::consts::TAU;

struct Between;

/// The same between its stops without damping and with elastic impacts
/// (a conservative structure: every multiplier product is 1).
struct Elastic;

impl Family for Elastic {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: -1.0, hi: 1.0 }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: 1.5, omega: w } }]);
        Model::new(dy, 1.0)
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(TAU / w)
    }
}

impl Between {
    fn at(&self, w: f64) -> Model {
        crate::between::model(w).unwrap()
    }
}

impl Family for Between {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        Ok(self.at(w))
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(TAU / w)
    }
}

/// `x(0) + x(T/2)` along the orbit through `x` at Ω = `w`: 0 on a
/// symmetric orbit, of opposite signs on the two mirror images.
fn asymmetry(w: f64, x: &[f64]) -> f64 {
    let half = Between.at(w).flow(0.0, x, TAU / w / 2.0, false).unwrap().x;
    x[0] + half[0]
}

/// Where the flow from `x` is after `k` periods at Ω = `w`.
fn settle(w: f64, x: &[f64], k: f64) -> Vec<f64> {
    Between.at(w).flow(0.0, x, k * TAU / w, false).unwrap().x
}

fn liouville(branch: &Branch) {
    for p in &branch.points {
        let j = &p.orbit.monodromy;
        let det = j[(0, 0)] * j[(1, 1)] - j[(0, 1)] * j[(1, 0)];
        let want = E.powi(2 * p.orbit.impacts() as i32) * (-C * TAU / p.param).exp();
        let prod = p.orbit.multipliers[0] * p.orbit.multipliers[1];
        assert!((det - want).abs() <= 1e-9 * want && (prod.re - want).abs() <= 1e-8 * want && prod.im.abs() <= 1e-8, "Ω = {}: det {det}, μ₁μ₂ {prod} vs e^2N e^-cT {want}", p.param);
    }
}

/// The symmetric branch from Ω = 2 down to 0.9: two branch points, where
/// the runs of the flow leave the symmetric orbit for two mirror-image
/// attractors between them and return to it outside; no fold.
fn symmetric_branch() -> Branch {
    let w0 = 2.0;
    let x0 = settle(w0, &[0.0, 0.0], 400.0);
    let start = periodic_orbit(&Between.at(w0), 0.0, TAU / w0, &x0, &Newton::default()).unwrap();
    assert!(asymmetry(w0, &start.x).abs() < 1e-10);
    continuation(&Between, &start.x, &ContinuationOptions::new(w0, 0.9)).unwrap()
}

/// `det(J − I)` of the map's Jacobian by central differences of the flow
/// at the orbit through `x` (Ω = `w`).
fn det_fd(w: f64, x: &[f64]) -> f64 {
    let m = Between.at(w);
    let mut j = [[0.0; 2]; 2];
    for c in 0..2 {
        let h = 1e-7;
        let (mut p, mut q) = (x.to_vec(), x.to_vec());
        p[c] += h;
        q[c] -= h;
        let (fp, fq) = (m.flow(0.0, &p, TAU / w, false).unwrap().x, m.flow(0.0, &q, TAU / w, false).unwrap().x);
        for r in 0..2 {
            j[r][c] = (fp[r] - fq[r]) / (2.0 * h);
        }
    }
    (j[0][0] - 1.0) * (j[1][1] - 1.0) - j[0][1] * j[1][0]
}

#[test]
fn the_symmetric_orbit_loses_stability_at_two_branch_points_not_folds() {
    let branch = symmetric_branch();
    assert_eq!(branch.end, "reached to");
    liouville(&branch);
    for p in &branch.points {
        assert!(asymmetry(p.param, &p.orbit.x).abs() < 1e-9, "Ω = {}: the branch left the symmetric orbit", p.param);
    }
    let kinds: Vec<&str> = branch.bifurcations.iter().map(|b| b.kind.name()).collect();
    assert_eq!(kinds, ["branch-point", "branch-point"], "{:?}", branch.bifurcations);
    let (hi, lo) = (branch.bifurcations[0].param, branch.bifurcations[1].param);
    // The oracle: runs of the flow from the symmetric orbit nudged either
    // way, 400 periods, just inside and just outside each branch point.
    for (k, w, unstable) in [(0, hi - 0.02, true), (0, hi + 0.02, false), (1, lo + 0.02, true), (1, lo - 0.02, false)] {
        let sym = periodic_orbit(&Between.at(w), 0.0, TAU / w, &branch.bifurcations[k].x, &Newton::default()).unwrap();
        assert!(asymmetry(w, &sym.x).abs() < 1e-10);
        let ends: Vec<Vec<f64>> = [1e-6, -1e-6].iter().map(|d| settle(w, &[sym.x[0] + d, sym.x[1]], 400.0)).collect();
        let (a, b) = (asymmetry(w, &ends[0]), asymmetry(w, &ends[1]));
        if unstable {
            assert!(a.abs() > 1e-2 && b.abs() > 1e-2, "Ω = {w}: the runs should leave the symmetric orbit: {a}, {b}");
            if k == 1 {
                // Below the upper branch point the two runs end on
                // attractors that are no mirror pair (the pair born at the
                // lower one is not what they settle on).
                continue;
            }
            assert!((a + b).abs() < 1e-8 * a.abs().max(1.0), "Ω = {w}: the runs should leave for a mirror pair: {a}, {b}");
            // Mirror images: the one's section state is minus the other's half a period on.
            let half = Between.at(w).flow(0.0, &ends[0], TAU / w / 2.0, false).unwrap().x;
            assert!((half[0] + ends[1][0]).abs() < 1e-8 && (half[1] + ends[1][1]).abs() < 1e-8, "Ω = {w}: {half:?} vs −{:?}", ends[1]);
        } else {
            assert!(a.abs() < 1e-8 && b.abs() < 1e-8, "Ω = {w}: the runs should return to the symmetric orbit: {a}, {b}");
        }
    }
    // A multiplier of the map's differences passes +1 within 1e-6 of each.
    for b in &branch.bifurcations {
        let d: Vec<f64> = [b.param - 1e-6, b.param + 1e-6].iter().map(|&w| det_fd(w, &periodic_orbit(&Between.at(w), 0.0, TAU / w, &b.x, &Newton::default()).unwrap().x)).collect();
        assert!(d[0] * d[1] < 0.0, "Ω = {}: det(J − I) {d:?}", b.param);
    }
}

/// The asymmetric orbit continued up to the branch point where it meets
/// the symmetric one: the branch turns in Ω there onto the mirror image
/// (the asymmetry changes sign), a branch point where the symmetric
/// branch has its own, not a fold.
#[test]
fn the_asymmetric_orbit_turns_onto_its_mirror_image_at_a_branch_point() {
    let w0 = 1.5;
    let x0 = settle(w0, &[0.0, 0.0], 400.0);
    let start = periodic_orbit(&Between.at(w0), 0.0, TAU / w0, &x0, &Newton::default()).unwrap();
    let a0 = asymmetry(w0, &start.x);
    assert!(a0.abs() > 0.1, "an asymmetric orbit: {a0}");
    let mut opts = ContinuationOptions::new(w0, 3.0);
    opts.max_points = 14;
    let branch = continuation(&Between, &start.x, &opts).unwrap();
    liouville(&branch);
    let first = &branch.bifurcations[0];
    assert_eq!(first.kind, BifurcationKind::BranchPoint, "{:?}", branch.bifurcations);
    assert!(!branch.bifurcations.iter().any(|b| b.kind == BifurcationKind::Fold), "{:?}", branch.bifurcations);
    let (before, after) = branch.points.split_at(first.between.1);
    assert!(before.iter().all(|p| asymmetry(p.param, &p.orbit.x) * a0 > 0.0));
    assert!(after.iter().all(|p| asymmetry(p.param, &p.orbit.x) * a0 < 0.0), "the branch goes on onto the mirror image");
    // Where the symmetric branch has its upper branch point.
    let sym = symmetric_branch().bifurcations[0].param;
    assert!((first.param - sym).abs() < 1e-7, "{} vs the symmetric branch's {sym}", first.param);
}

/// A range from a restitution of 1 (the end of its domain): every point
/// obeys Liouville's formula with its own restitution.
#[test]
fn a_range_from_the_end_of_the_parameters_domain_starts() {
    let doc = crate::oscillator(0.05, 0.2, 1.0, 2.0);
    let (fam, _) = SceneFamily::new(doc, "oscillator.restitution", 1).unwrap();
    let built = fam.build(1.0).unwrap();
    let x0 = built.model.flow(0.0, &built.start, 200.0 * built.horizon, false).unwrap().x;
    let branch = continuation(&fam, &x0, &ContinuationOptions::new(1.0, 0.5)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(branch.end, "reached to");
    let t = TAU / 2.0;
    for p in &branch.points {
        let j = &p.orbit.monodromy;
        let det = j[(0, 0)] * j[(1, 1)] - j[(0, 1)] * j[(1, 0)];
        let want = p.param.powi(2 * p.orbit.impacts() as i32) * (-0.1 * t).exp();
        assert!(p.orbit.impacts() > 0 && (det - want).abs() <= 1e-9 * want, "e = {}: det {det} vs {want}", p.param);
    }
}

/// A range from a forcing amplitude of 0 (the orbit at rest): the free
/// orbit grows with the amplitude and grazes the stop where the linear
/// steady state's amplitude `A / √((k − mΩ²)² + (cΩ)²)` reaches it.
#[test]
fn a_range_from_rest_reaches_the_grazing() {
    let mut doc = crate::oscillator(0.05, 0.2, 1.0, 2.0);
    set_path(&mut doc, "forcing.amplitude", 0.0.into()).unwrap();
    let (fam, _) = SceneFamily::new(doc, "forcing.amplitude", 1).unwrap();
    let branch = continuation(&fam, &[0.0, 0.0], &ContinuationOptions::new(0.0, 1.0)).unwrap();
    let g = branch.bifurcations.iter().find(|b| b.kind == BifurcationKind::Grazing).unwrap_or_else(|| panic!("no grazing; end: {}", branch.end));
    let want = 0.2 * ((1.0f64 - 4.0).powi(2) + (0.1f64 * 2.0).powi(2)).sqrt();
    assert!((g.param - want).abs() <= 1e-9, "grazing at {} vs {want}", g.param);
}

/// The symmetric four-impact orbit from Ω = 0.6 up: its own turning point
/// (symmetric on both sides, `det(J − I)` of the map's differences
/// changing sign across it) stays a fold, and the grazing met where the
/// corrector takes a corner step is listed once.
#[test]
fn a_fold_of_the_symmetric_orbit_stays_a_fold_and_each_grazing_is_listed_once() {
    let w0 = 0.6;
    let x0 = settle(w0, &[0.0, 0.0], 400.0);
    let start = periodic_orbit(&Between.at(w0), 0.0, TAU / w0, &x0, &Newton::default()).unwrap();
    assert!(asymmetry(w0, &start.x).abs() < 1e-10);
    let branch = continuation(&Between, &start.x, &ContinuationOptions::new(w0, 3.5)).unwrap();
    liouville(&branch);
    let fold = branch.bifurcations.iter().find(|b| b.kind == BifurcationKind::Fold).unwrap_or_else(|| panic!("{:?}", branch.bifurcations));
    for p in &branch.points[..=fold.between.1] {
        assert!(asymmetry(p.param, &p.orbit.x).abs() < 1e-9, "Ω = {}", p.param);
    }
    let (a, b) = (&branch.points[fold.between.0], &branch.points[fold.between.1]);
    assert!(det_fd(a.param, &a.orbit.x) * det_fd(b.param, &b.orbit.x) < 0.0);
    assert!(a.param < fold.param + 1e-12 && b.param < fold.param + 1e-12, "a turning point in Ω");
    for (i, x) in branch.bifurcations.iter().enumerate() {
        for y in &branch.bifurcations[i + 1..] {
            assert!(!(x.kind == y.kind && x.param == y.param), "{} at {} listed twice", x.kind.name(), x.param);
        }
    }
}

/// Conservative: the free orbit of the undamped oscillator between its
/// stops, `x = 1.5 sin Ωt / (1 − Ω²)` (closed form), from Ω = 3.47 down
/// to its grazing (`|1.5 / (1 − Ω²)| = 1`: Ω² = 2.5). Its multipliers
/// are `e^{±2πi/Ω}`, on the unit circle at every Ω: no Neimark–Sacker
/// point anywhere (the round-off of `|μ| − 1` changed sign twice).
#[test]
fn a_conservative_orbit_has_no_neimark_sacker_point() {
    let w0 = 3.47;
    let v = |w: f64| 1.5 * w / (1.0 - w * w);
    // From the state 200 periods after rest (the free vibration rides on
    // the orbit: Newton takes it off).
    let m = Elastic.model(w0).unwrap();
    let x0 = m.flow(0.0, &[0.0, 0.0], 200.0 * TAU / w0, false).unwrap().x;
    let start = periodic_orbit(&m, 0.0, TAU / w0, &x0, &Newton::default()).unwrap();
    let branch = continuation(&Elastic, &start.x, &ContinuationOptions::new(w0, 0.45)).unwrap();
    assert!(branch.points.len() > 10);
    for p in &branch.points {
        assert_eq!(p.orbit.impacts(), 0);
        assert!(p.orbit.x[0].abs() < 1e-9 && (p.orbit.x[1] - v(p.param)).abs() < 1e-9 * v(p.param).abs(), "Ω = {}: {:?}", p.param, p.orbit.x);
        let th = TAU / p.param;
        let want = [faer::c64::new(th.cos(), th.sin()), faer::c64::new(th.cos(), -th.sin())];
        for m in &p.orbit.multipliers {
            assert!(want.iter().any(|w| (m - w).norm() < 1e-9), "Ω = {}: {m} vs e^±2πi/Ω", p.param);
        }
    }
    // It ends at its grazing, the only bifurcation named.
    let kinds: Vec<(&str, f64)> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect();
    assert!(kinds.len() == 1 && kinds[0].0 == "grazing" && (kinds[0].1 - 2.5f64.sqrt()).abs() < 1e-9, "{kinds:?}");
}

/// The elastic oscillator's map over one period, transcribed: the
/// closed-form flow of `x'' + x = 1.5 sin Ωt` between impacts, each
/// crossing of a stop `±1` (sampled at 1/4000 of the period, bisected to
/// round-off) reflecting the velocity.
fn elastic_map(w: f64, x: [f64; 2]) -> [f64; 2] {
    let a = 1.5 / (1.0 - w * w);
    let flow = |t0: f64, z: (f64, f64), t: f64| {
        let (c1, c2) = (z.0 - a * (w * t0).sin(), z.1 - a * w * (w * t0).cos());
        let (sn, cs) = (t - t0).sin_cos();
        (c1 * cs + c2 * sn + a * (w * t).sin(), -c1 * sn + c2 * cs + a * w * (w * t).cos())
    };
    let (end, h) = (TAU / w, TAU / w / 4000.0);
    let (mut t0, mut z, mut t) = (0.0, (x[0], x[1]), 0.0);
    while t < end {
        let t1 = (t + h).min(end);
        if flow(t0, z, t1).0.abs() > 1.0 {
            let (mut lo, mut hi) = (t, t1);
            for _ in 0..200 {
                let m = 0.5 * (lo + hi);
                if m <= lo || m >= hi {
                    break;
                }
                if flow(t0, z, m).0.abs() > 1.0 {
                    hi = m;
                } else {
                    lo = m;
                }
            }
            let y = flow(t0, z, lo);
            (t0, z, t) = (lo, (y.0.signum(), -y.1), lo);
            continue;
        }
        t = t1;
    }
    let y = flow(t0, z, end);
    [y.0, y.1]
}

/// The elastic oscillator between its stops from Ω = 1.2 down: its
/// two-impact orbit turns in Ω where a flight between its impacts grazes a
/// stop (1.0817624, named a grazing): a corner, where no multiplier is at
/// +1 (the transcription's: 0.73 ± 0.68i). The turn was also named a
/// branch point. Every branch point named must have a multiplier of the
/// transcribed map (central differences at the listed state) at +1: within
/// 0.15 of it (the pair of this area-preserving map meets +1 on the circle
/// and leaves it as the square root of the distance from the point).
#[test]
fn a_turn_at_a_grazing_is_no_branch_point() {
    let w0 = 1.2;
    let m = Elastic.model(w0).unwrap();
    let x0 = m.flow(0.0, &[0.0, 0.0], 400.0 * TAU / w0, false).unwrap().x;
    let start = periodic_orbit(&m, 0.0, TAU / w0, &x0, &Newton::default()).unwrap();
    let mut opts = ContinuationOptions::new(w0, 0.45);
    opts.max_points = 40;
    let branch = continuation(&Elastic, &start.x, &opts).unwrap();
    let bifs: Vec<_> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param, b.mu)).collect();
    eprintln!("{bifs:?}; {}", branch.end);
    let grazing = branch.bifurcations.iter().find(|b| b.kind == BifurcationKind::Grazing && (b.param - 1.0817624).abs() < 1e-6).expect("the grazing at 1.0817624");
    for b in branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::BranchPoint) {
        let x = [b.x[0], b.x[1]];
        let mut j = [[0.0; 2]; 2];
        for c in 0..2 {
            let (mut p, mut q) = (x, x);
            p[c] += 1e-7;
            q[c] -= 1e-7;
            let (fp, fq) = (elastic_map(b.param, p), elastic_map(b.param, q));
            for r in 0..2 {
                j[r][c] = (fp[r] - fq[r]) / 2e-7;
            }
        }
        // The multiplier nearest +1 from the trace and determinant.
        let (tr, det) = (j[0][0] + j[1][1], j[0][0] * j[1][1] - j[0][1] * j[1][0]);
        let disc = tr * tr / 4.0 - det;
        let near = if disc >= 0.0 { [tr / 2.0 + disc.sqrt(), tr / 2.0 - disc.sqrt()].iter().map(|m| (m - 1.0).abs()).fold(f64::INFINITY, f64::min) } else { (tr / 2.0 - 1.0).hypot((-disc).sqrt()) };
        eprintln!("branch point at {}: the transcription's multiplier nearest +1 is {near:e} from it", b.param);
        assert!(near <= 0.15 && (b.param - grazing.param).abs() > 1e-6, "branch point at {} (grazing at {}): the transcription's multipliers are {near:e} from +1", b.param, grazing.param);
    }
}

/// `--switch` at the symmetric orbit's upper branch point
/// ([`signorini_orbits::crossing_branch`]): the branch crossing there is
/// the asymmetric one. Its orbits are no symmetric ones (`x(0) + x(T/2)`
/// by the flow is off 0), the mirror image of each (`−x(T/2)`) is a
/// periodic orbit too (a run of the flow over a period returns to it),
/// and where a point is listed stable (`|μ|max < 0.95`; not within 1e-2
/// of a grazing, where a run may cross it) a run from 1e-4
/// beside it returns to it, where unstable (`|μ|max > 1.05`), leaves it.
#[test]
fn the_switch_at_a_branch_point_follows_the_asymmetric_branch() {
    let sym = symmetric_branch();
    let upper = &sym.bifurcations[0];
    assert_eq!(upper.kind, BifurcationKind::BranchPoint);
    let opts = ContinuationOptions::new(2.0, 0.9);
    let br = crate::crossing_branch(&Between, &sym, upper, (2.0, 0.9), &opts).unwrap();
    eprintln!("{} points from {} to {}: {}", br.points.len(), br.points[0].param, br.points.last().unwrap().param, br.end);
    for b in &br.bifurcations {
        eprintln!("  {} at {}", b.kind.name(), b.param);
    }
    // Every bifurcation at a parameter (a grazing located from an orbit
    // whose flights have no interior extremum was listed at NaN: an empty
    // cell of bifurcations.csv), within the branch's range.
    let (lo, hi) = br.points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.param), b.max(p.param)));
    for b in &br.bifurcations {
        assert!(b.param.is_finite() && b.param >= lo - 1e-2 && b.param <= hi + 1e-2, "{} at {} (the branch from {lo} to {hi})", b.kind.name(), b.param);
    }
    assert!(br.points.len() >= 5, "{} points", br.points.len());
    // It ends where it meets the symmetric branch again: at its lower
    // branch point (the asymmetric orbit turning onto its mirror image).
    let lower = sym.bifurcations[1].param;
    assert!(br.rejoins.is_some_and(|at| (at - lower).abs() <= 1e-6), "ends at {:?}, the lower branch point at {lower}: {}", br.rejoins, br.end);
    let (mut stable, mut unstable) = (0, 0);
    for p in br.points.iter().step_by(3) {
        let w = p.param;
        let a = asymmetry(w, &p.orbit.x);
        // Past the branch point where it meets the symmetric orbit again
        // the asymmetry is small: checked away from it.
        if (w - upper.param).abs() < 1e-3 {
            continue;
        }
        assert!(a.abs() > 1e-3, "Ω = {w}: a symmetric orbit ({a})");
        let half = Between.at(w).flow(0.0, &p.orbit.x, TAU / w / 2.0, false).unwrap().x;
        let mirror = [-half[0], -half[1]];
        let back = settle(w, &mirror, 1.0);
        let d = (back[0] - mirror[0]).abs().max((back[1] - mirror[1]).abs());
        assert!(d <= 1e-9 && (mirror[0] - p.orbit.x[0]).abs() > 1e-4, "Ω = {w}: the mirror image is {d:e} from periodic");
        // Not beside a grazing (a run from beside may cross it).
        if br.bifurcations.iter().any(|b| b.kind == BifurcationKind::Grazing && (b.param - w).abs() <= 1e-2) {
            continue;
        }
        let end = settle(w, &[p.orbit.x[0] + 1e-4, p.orbit.x[1]], 400.0);
        let gone = (end[0] - p.orbit.x[0]).abs().max((end[1] - p.orbit.x[1]).abs());
        // Away from +1 (near it the run closes in too slowly to tell).
        if p.stable() && p.orbit.mu_max() < 0.95 {
            stable += 1;
            assert!(gone <= 1e-8, "Ω = {w}: stable, but the run ends {gone:e} from it");
        } else if p.orbit.mu_max() > 1.05 {
            unstable += 1;
            assert!(gone >= 1e-4, "Ω = {w}: unstable, but the run ends {gone:e} from it");
        }
    }
    eprintln!("{stable} stable, {unstable} unstable checked");
    assert!(stable >= 2, "{stable} stable points checked");
}

/// Bisection on `[lo, hi]` for the sign change of `f` (`f(lo) <= 0 < f(hi)`
/// or the reverse) to round-off.
fn bisect_time(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> bool) -> f64 {
    let at_lo = f(lo);
    loop {
        let m = 0.5 * (lo + hi);
        if m <= lo || m >= hi {
            return lo;
        }
        if f(m) == at_lo {
            lo = m;
        } else {
            hi = m;
        }
    }
}

/// The transcription's map over a period with the stop `s` (±1) left out
/// for `t` in `skip`: every other crossing of a stop, and every excursion
/// past one between samples (its interior extremum found by bisection on
/// the velocity), is bisected to round-off and the velocity reversed
/// times e. Returns the state after a period, the impacts (time, stop,
/// speed), and the largest `s x - 1` over `skip` (the flight's distance
/// past the left-out stop at its extremum there).
fn virtual_map(w: f64, x: [f64; 2], s: f64, skip: (f64, f64)) -> ([f64; 2], Vec<(f64, f64, f64)>, f64) {
    let end = TAU / w;
    let h = end / 4000.0;
    let (mut t0, mut z, mut t, mut impacts, mut reach) = (0.0, (x[0], x[1]), 0.0, Vec::new(), f64::NEG_INFINITY);
    while t < end {
        let t1 = (t + h).min(end);
        let at = |u: f64| flow(w, t0, z.0, z.1, u);
        let mut hit: Option<(f64, f64)> = None;
        for stop in [-1.0, 1.0] {
            let left_out = |u: f64| stop == s && u >= skip.0 && u <= skip.1;
            let past = |u: f64| stop * at(u).0 > 1.0 && !left_out(u);
            // An extremum toward this stop inside the interval.
            let top = if stop * at(t).1 > 0.0 && stop * at(t1).1 <= 0.0 { Some(bisect_time(t, t1, |u| stop * at(u).1 <= 0.0)) } else { None };
            if let Some(m) = top {
                if left_out(m) {
                    reach = reach.max(stop * at(m).0 - 1.0);
                }
            }
            let cross = if past(t1) { Some(t1) } else { top.filter(|&m| past(m)) };
            if let Some(c) = cross {
                let tc = bisect_time(t, c, past);
                if hit.is_none_or(|(u, _)| tc < u) {
                    hit = Some((tc, stop));
                }
            }
        }
        if let Some((tc, stop)) = hit {
            let y = at(tc);
            impacts.push((tc, stop, y.1.abs()));
            (t0, z, t) = (tc, (stop, -E * y.1), tc);
            continue;
        }
        t = t1;
    }
    let y = flow(w, t0, z.0, z.1, end);
    ([y.0, y.1], impacts, reach)
}

/// The fixed point of [`virtual_map`] at `w` from `x` (Newton on central
/// differences) and its reach past the left-out stop.
fn virtual_orbit(w: f64, mut x: [f64; 2], s: f64, skip: (f64, f64)) -> ([f64; 2], Vec<(f64, f64, f64)>, f64) {
    for _ in 0..30 {
        let (y, _, _) = virtual_map(w, x, s, skip);
        let r = [y[0] - x[0], y[1] - x[1]];
        if r[0].abs().max(r[1].abs()) <= 1e-13 {
            break;
        }
        let mut j = [[0.0; 2]; 2];
        for c in 0..2 {
            let (mut p, mut q) = (x, x);
            p[c] += 1e-7;
            q[c] -= 1e-7;
            let (fp, fq) = (virtual_map(w, p, s, skip).0, virtual_map(w, q, s, skip).0);
            for (k, row) in j.iter_mut().enumerate() {
                row[c] = (fp[k] - p[k] - fq[k] + q[k]) / 2e-7;
            }
        }
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        x[0] -= (j[1][1] * r[0] - j[0][1] * r[1]) / det;
        x[1] -= (j[0][0] * r[1] - j[1][0] * r[0]) / det;
    }
    let (_, k, reach) = virtual_map(w, x, s, skip);
    (x, k, reach)
}

/// The grazing the switched (asymmetric) branch lists near Ω = 1.0383,
/// where the slow impact of its 3-impact orbits vanishes and its 2-impact
/// orbits begin: located independently as where the 2-impact orbit's
/// flight reaches the stop (the transcription's map with that stop left
/// out around the flight's extremum, its fixed point by Newton, the
/// extremum's distance past the stop by bisection on Ω to 1e-10). A
/// trial of the location that landed on an orbit of another arc (its
/// flight margin NaN) made every later secant NaN, and the linear
/// extrapolation of the slow impact's speed was listed, 2.9e-5 off.
#[test]
fn the_switched_branch_lists_its_grazing_where_the_flight_reaches_the_stop() {
    let sym = symmetric_branch();
    let upper = &sym.bifurcations[0];
    let br = crate::crossing_branch(&Between, &sym, upper, (2.0, 0.9), &ContinuationOptions::new(2.0, 0.9)).unwrap();
    let g = br
        .bifurcations
        .iter()
        .find(|b| b.kind == BifurcationKind::Grazing && b.param < 1.05)
        .unwrap_or_else(|| panic!("no grazing listed below 1.05: {:?}", br.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect::<Vec<_>>()));
    // The point on the side without the slow impact (its smooth side).
    let (b, c) = (&br.points[g.between.0], &br.points[g.between.1]);
    let smooth = if b.orbit.impacts() < c.orbit.impacts() { b } else { c };
    let beyond = if smooth.param == b.param { c } else { b };
    eprintln!("grazing listed at {}: {} impacts at {}, {} at {}", g.param, smooth.orbit.impacts(), smooth.param, beyond.orbit.impacts(), beyond.param);
    // The slow impact of the orbit beyond, by the transcription: its stop
    // `s` and time `tg`; that stop is left out within 0.3 of `tg`, where
    // no other impact falls.
    let (_, seen, _) = virtual_map(beyond.param, [beyond.orbit.x[0], beyond.orbit.x[1]], 0.0, (0.0, 0.0));
    assert_eq!(seen.len(), beyond.orbit.impacts(), "{seen:?}");
    let &(tg, s, slow) = seen.iter().min_by(|p, q| p.2.total_cmp(&q.2)).unwrap();
    let skip = (tg - 0.3, tg + 0.3);
    assert!(skip.0 > 0.0 && skip.1 < TAU / beyond.param && seen.iter().all(|i| i.0 == tg || (i.0 - tg).abs() > 0.5), "{seen:?}");
    eprintln!("slow impact at {s}, t = {tg}, speed {slow:e} at {}: {seen:?}", beyond.param);
    let x0 = [smooth.orbit.x[0], smooth.orbit.x[1]];
    let reach = |w: f64, x: [f64; 2]| {
        let (y, k, r) = virtual_orbit(w, x, s, skip);
        assert_eq!(k.len(), smooth.orbit.impacts(), "Ω = {w}: the left-out orbit's impacts {k:?}");
        (y, r)
    };
    // From the smooth side toward the other, in steps of 1e-5 (each
    // Newton from the last orbit), to the first past the stop; then
    // bisection.
    let (mut lo, mut xlo, step) = (smooth.param, x0, 1e-5 * (beyond.param - smooth.param).signum());
    let (_, r0) = reach(lo, x0);
    assert!(r0 < 0.0, "Ω = {lo}: the flight is {r0:e} past the stop");
    let mut hi = lo;
    for _ in 0..1000 {
        hi = lo + step;
        let (x, r) = reach(hi, xlo);
        if r >= 0.0 {
            break;
        }
        (lo, xlo) = (hi, x);
    }
    eprintln!("the flight reaches the stop between {lo} and {hi}");
    assert!((hi - smooth.param) * (beyond.param - hi) > 0.0, "no grazing between {} and {}", smooth.param, beyond.param);
    while (hi - lo).abs() > 1e-10 {
        let m = 0.5 * (lo + hi);
        let (xm, rm) = reach(m, xlo);
        if rm < 0.0 {
            (lo, xlo) = (m, xm);
        } else {
            hi = m;
        }
    }
    let want = 0.5 * (lo + hi);
    eprintln!("grazing: listed {}, the transcription's {want} ({:e} apart)", g.param, g.param - want);
    assert!((g.param - want).abs() <= 1e-8, "the grazing listed at {} is {:e} from the transcription's {want}", g.param, g.param - want);
}

/// The transcription's pitchfork near `w`: the symmetric orbit is the
/// fixed point of the half-period map mirrored, `R(x) = −φ(x, T/2)`
/// (`between.rs`'s closed-form flow; Newton on `R` stays regular where
/// the full map's `P' − I` is singular), and a multiplier of the full
/// map `P` (its central differences at that orbit, steps 1e-4 and 5e-5
/// Richardson-extrapolated: truncation and round-off both below 1e-12)
/// passes +1 where `det(P' − I)` changes sign: bisected in Ω from
/// `w ∓ 1e-5` to round-off.
fn transcribed_pitchfork(w: f64, x: [f64; 2]) -> f64 {
    let map = |w: f64, x: [f64; 2], span: f64| crate::between::flow_between(w, 0.0, span * TAU / w, x, (-1.0, 1.0), E, 1000.0).0;
    let orbit = |w: f64| {
        let mut y = x;
        for _ in 0..60 {
            let r = map(w, y, 0.5);
            let f = [y[0] + r[0], y[1] + r[1]];
            let mut j = crate::between::differences(y, 1e-6, |z| map(w, z, 0.5));
            j[0][0] += 1.0;
            j[1][1] += 1.0;
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            let step = [(j[1][1] * f[0] - j[0][1] * f[1]) / det, (-j[1][0] * f[0] + j[0][0] * f[1]) / det];
            y = [y[0] - step[0], y[1] - step[1]];
            if step[0].abs().max(step[1].abs()) <= 1e-15 {
                break;
            }
        }
        y
    };
    let det = |w: f64| {
        let y = orbit(w);
        let (j1, j2) = (crate::between::differences(y, 1e-4, |z| map(w, z, 1.0)), crate::between::differences(y, 5e-5, |z| map(w, z, 1.0)));
        let j: Vec<Vec<f64>> = (0..2).map(|r| (0..2).map(|c| (4.0 * j2[r][c] - j1[r][c]) / 3.0).collect()).collect();
        (j[0][0] - 1.0) * (j[1][1] - 1.0) - j[0][1] * j[1][0]
    };
    let (lo, hi) = (w - 1e-5, w + 1e-5);
    assert!(det(lo) * det(hi) < 0.0, "no multiplier of the transcription through +1 within 1e-5 of {w}");
    bisect_time(lo, hi, |m| det(m) > 0.0)
}

/// The symmetric branch's two pitchforks, where the corrector's extended
/// system is singular (two branches cross): listed at the transcription's
/// `det(P' − I)` zero to 1e-10 (the bisection on the arclength that
/// located them ended where the corrector failed, 4.4e-9 and 1.3e-8 off).
#[test]
fn the_symmetric_branch_points_are_at_the_transcriptions_pitchforks() {
    let branch = symmetric_branch();
    let off: Vec<(f64, f64)> = branch.bifurcations.iter().map(|b| (b.param, transcribed_pitchfork(b.param, [b.x[0], b.x[1]]))).collect();
    assert_eq!(off.len(), 2, "{off:?}");
    eprintln!("(listed, transcription): {off:?}");
    for (at, want) in off {
        assert!((at - want).abs() <= 1e-10, "branch point at {at}: the transcription's pitchfork at {want}, {:e} off", at - want);
    }
}
