//! Grazing of an orbit without impacts: the impacting orbit born where the
//! free orbit touches a stop exists on one side of the grazing — past it,
//! or on the near side, where the free orbit exists too (the branch turns
//! back there: a nonsmooth fold, hysteresis). Which side is that of the
//! square-root map's fixed point (theory §12.3); for the impact
//! oscillator the closed form (`signorini_exact::ImpactOscillator`) says
//! it: past the grazing for Ω > 2ω (`oscillator.rs`), on the near side for
//! ω < Ω < 2ω (here).

use crate::continuation;
use signorini_exact::{ImpactOscillator, OscillatorParams, State};
use signorini_orbits::{BifurcationKind, Branch, ContinuationOptions, SceneFamily};
use std::f64::consts::TAU;

/// The stop at 0.8: the free orbit's amplitude reaches it at Ω = 1.497
/// (between ω = 1 and 2ω).
const GAP: f64 = 0.8;

fn exact(omega: f64) -> ImpactOscillator {
    ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: omega, gap: GAP, restitution: 0.8 }).unwrap()
}

/// The closed form's admissible period-1 orbits at `omega`: section state
/// (t = 0), multipliers, impact speed.
fn closed_orbits(omega: f64) -> Vec<([f64; 2], [[f64; 2]; 2], f64)> {
    let osc = exact(omega);
    let t = TAU / omega;
    osc.period1_orbits()
        .into_iter()
        .map(|o| {
            let z = osc.flow(o.impact_time.rem_euclid(t), State { x: GAP, v: -0.8 * o.impact_velocity }, t);
            ([z.x, z.v], [[o.multipliers[0].re, o.multipliers[0].im], [o.multipliers[1].re, o.multipliers[1].im]], o.impact_velocity)
        })
        .collect()
}

/// Every point against the closed forms: without impacts the linear
/// steady state (1e-10), with one the nearest admissible closed-form orbit
/// (state 1e-8; multipliers 1e-8 relative, plus `1e-11/V`: the
/// multiplier grows as `1/V` near the grazing, `V` the impact speed, known
/// to Newton's tolerance of the state, 1e-11).
fn check_points(branch: &Branch) {
    for p in &branch.points {
        let osc = exact(p.param);
        match p.orbit.impacts() {
            0 => {
                let z = osc.steady_state(0.0);
                let err = (p.orbit.x[0] - z.x).abs().max((p.orbit.x[1] - z.v).abs());
                assert!(err <= 1e-10, "Ω = {}: steady state error {err:e}", p.param);
            }
            1 => {
                let (err, mu, v) = closed_orbits(p.param)
                    .into_iter()
                    .map(|(x, mu, v)| ((p.orbit.x[0] - x[0]).abs().max((p.orbit.x[1] - x[1]).abs()), mu, v))
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .unwrap_or_else(|| panic!("Ω = {}: no admissible closed-form orbit", p.param));
                assert!(err <= 1e-8, "Ω = {}: state error {err:e}", p.param);
                let mut got: Vec<[f64; 2]> = p.orbit.multipliers.iter().map(|m| [m.re, m.im]).collect();
                let mut want = mu.to_vec();
                for m in [&mut got, &mut want] {
                    m.sort_by(|a, b| (b[0].hypot(b[1]), b[1]).partial_cmp(&(a[0].hypot(a[1]), a[1])).unwrap());
                }
                for (a, b) in got.iter().zip(&want) {
                    let e = (a[0] - b[0]).hypot(a[1] - b[1]);
                    assert!(e <= (1e-8 + 1e-11 / v) * a[0].hypot(a[1]).max(1.0), "Ω = {}: multiplier {a:?} vs closed form {b:?}", p.param);
                }
            }
            k => panic!("Ω = {}: {k} impacts on the period-1 branch", p.param),
        }
    }
}

#[test]
fn between_omega_and_twice_omega_the_impacting_orbit_born_at_the_free_grazing_turns_back() {
    let fam = SceneFamily::new(crate::oscillator(0.05, GAP, 0.8, 2.0), "forcing.omega", 1).unwrap().0;
    let want = exact(2.0).grazing_frequencies();
    assert_eq!(want.len(), 1, "{want:?}");
    let want = want[0];
    assert!(want > 1.0 && want < 2.0, "{want}");
    // The closed form itself: just above the grazing (where the free orbit
    // exists) an admissible impacting orbit with a slow impact; just below
    // it none slow.
    let slow = |omega: f64| closed_orbits(omega).into_iter().map(|o| o.2).fold(f64::INFINITY, f64::min);
    assert!(slow(want + 1e-4) < 1e-2, "a slow impact on the near side: {}", slow(want + 1e-4));
    assert!(slow(want - 1e-4) > 1e-1, "none past it: {}", slow(want - 1e-4));
    let z = exact(2.0).steady_state(0.0);
    let branch = continuation(&fam, &[z.x, z.v], &ContinuationOptions::new(2.0, 1.2)).unwrap();
    eprintln!("{} points, end: {}", branch.points.len(), branch.end);
    for b in &branch.bifurcations {
        eprintln!("  {} at {:.15} impacts {:?}", b.kind.name(), b.param, b.impacts);
    }
    for p in &branch.points {
        eprintln!("  {:.9} {} {:.3e} {}", p.param, p.orbit.impacts(), p.orbit.slowest_impact().unwrap_or(0.0), p.stable());
    }
    check_points(&branch);
    let g = branch.bifurcations.iter().find(|b| b.kind == BifurcationKind::Grazing).unwrap_or_else(|| panic!("no grazing; end: {}", branch.end));
    eprintln!("grazing at {} vs closed form {want}: {:e} apart", g.param, (g.param - want).abs());
    assert!((g.param - want).abs() <= 1e-8 * want, "grazing at {} vs closed form {want}", g.param);
    assert_eq!(g.impacts, (0, 1));
    let k = g.between.1;
    assert!(branch.points[..k].iter().all(|p| p.orbit.impacts() == 0 && p.param > want), "the free orbit, above the grazing");
    let after = &branch.points[k..];
    assert!(after.len() >= 5, "the impacting branch is continued: {} points", after.len());
    assert!(after.iter().all(|p| p.orbit.impacts() == 1));
    // Turned back: the first impacting orbit is on the free orbit's side,
    // slow and unstable (a saddle).
    assert!(after[0].param > want, "turned back: Ω = {} against the grazing {want}", after[0].param);
    assert!(after[0].orbit.slowest_impact().unwrap() < 1e-2 && !after[0].stable());
    // It folds where the closed form's two admissible roots merge (their
    // count, bisected in Ω) and comes back stable, past the grazing.
    let fold = branch.bifurcations.iter().find(|b| b.kind == BifurcationKind::Fold).expect("a fold");
    let (mut lo, mut hi) = (want + 0.1, 1.9);
    assert!(closed_orbits(lo).len() == 2 && closed_orbits(hi).is_empty());
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if closed_orbits(m).len() == 2 {
            lo = m;
        } else {
            hi = m;
        }
    }
    eprintln!("fold at {} vs closed form {lo}: {:e} apart", fold.param, (fold.param - lo).abs());
    assert!((fold.param - lo).abs() <= 1e-8, "fold at {} vs closed form {lo}", fold.param);
    let last = branch.points.last().unwrap();
    assert!(branch.end == "reached to" && last.stable() && last.param < want);
}
