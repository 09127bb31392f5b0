//! A nonsmooth fold met from its unstable side: the oscillator of
//! `oscillator.rs` (ζ = 0.05, e = 0.8, stop 0.2, `cos Ωt`) has, above
//! Ω_g ≈ 0.8930926, a stable 1-impact orbit and an unstable 2-impact one
//! (from the fold at 0.9335 down); at Ω_g the 1-impact orbit's flight
//! grazes the stop, the 2-impact orbit's slow impact vanishes there, and
//! below it neither exists. `signorini continue --from 0.5 --to 5` came
//! down the 2-impact arc, its corrector stalling at the map's round-off
//! (residual 1.5e-11 … 4e-11 against 2e-11, the slow impact at 1.6e-3)
//! 1.3e-4 above Ω_g; the corner search then took the coexisting 1-impact
//! orbit, 4.5e-6 below, as the orbit "beyond a corner", listed a grazing
//! at 0.893221 (1.3e-4 off), went down the 1-impact arc to Ω_g, turned
//! back onto the 2-impact arc and traced it and everything before it a
//! second time (400 points, the fold at 0.9335 and the grazing at 0.608
//! listed twice). From Ω = 0.905 down (a shorter range: longer steps in
//! Ω) the extrapolated grazing fell 1.5e-5 short and the orbit "across"
//! it was that 1-impact orbit 3e-6 above the grazing, followed down to
//! the grazing and back up the 2-impact arc the same way. Now the two arcs
//! are recognised as the nonsmooth fold they are: the grazing is located
//! on the 1-impact arc and the branch turns back along it. Checked against the closed forms of
//! `signorini_exact` (the 1-impact orbit, its flight's maximum reaching
//! the stop found by bisection here).

use crate::continuation;
use crate::oscillator::closed_orbits;
use signorini_exact::{ImpactOscillator, OscillatorParams, State};
use signorini_orbits::{periodic_orbit, BifurcationKind, Branch, ContinuationOptions, Family, Newton, SceneFamily};
use std::f64::consts::TAU;

/// The largest interior maximum of the closed-form 1-impact orbit's flight
/// at Ω, less the stop (negative: the flight stays below it). `None`
/// where the closed form has no such orbit.
fn flight_top(w: f64) -> Option<f64> {
    let osc = ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: w, gap: 0.2, restitution: 0.8 }).unwrap();
    let t = TAU / w;
    // Every root, admissible or not (past the grazing the flight crosses
    // the stop: the closed form calls it inadmissible): the stable one.
    let o = osc.period1_roots().into_iter().filter(|o| o.impact_velocity > 0.0).max_by(|a, b| a.impact_velocity.total_cmp(&b.impact_velocity))?;
    let z0 = State { x: 0.2, v: -0.8 * o.impact_velocity };
    let at = |s: f64| osc.flow(o.impact_time, z0, o.impact_time + s);
    let n = 4000;
    let mut top = f64::NEG_INFINITY;
    for k in 1..n {
        let (a, b) = (f64::from(k - 1) * t / f64::from(n), f64::from(k) * t / f64::from(n));
        // v from + to −: a maximum, bisected to round-off.
        if at(a).v > 0.0 && at(b).v <= 0.0 {
            let (mut lo, mut hi) = (a, b);
            for _ in 0..100 {
                let m = 0.5 * (lo + hi);
                if at(m).v > 0.0 {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            top = top.max(at(lo).x);
        }
    }
    Some(top - 0.2)
}

/// The grazing: where the closed form's flight reaches the stop.
fn grazing() -> f64 {
    let (mut lo, mut hi) = (0.8925, 0.8935);
    assert!(flight_top(lo).unwrap() > 0.0 && flight_top(hi).unwrap() < 0.0);
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if flight_top(m).unwrap() > 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    0.5 * (lo + hi)
}

/// The branch's grazings, each once, the one at `wg` (2 -> 1 impacts)
/// among them to 1e-9, and no other bifurcation listed twice (a branch
/// that traces an arc again lists its bifurcations again).
fn listed_once(branch: &Branch, wg: f64) {
    let said: Vec<_> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param, b.impacts)).collect();
    eprintln!("{} points to {}: {}; Ω_g = {wg}; {said:?}", branch.points.len(), branch.points.last().unwrap().param, branch.end);
    let at: Vec<_> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::Grazing && (b.param - wg).abs() <= 1e-3).collect();
    assert!(at.len() == 1 && at[0].impacts == (2, 1), "one grazing near Ω_g, 2 -> 1 impacts: {said:?}");
    assert!((at[0].param - wg).abs() <= 1e-9, "the grazing at {} against the closed form's {wg}", at[0].param);
    for (i, a) in branch.bifurcations.iter().enumerate() {
        assert!(!branch.bifurcations[i + 1..].iter().any(|b| b.kind == a.kind && (b.param - a.param).abs() <= 1e-6), "listed twice: {said:?}");
    }
}

/// The run that showed it: `signorini continue osc.toml --from 0.5 --to
/// 5`, from the state after 100 forcing periods (from rest): up the
/// 3-impact arc, through the fold at 0.632 and the grazing at 0.608 onto
/// the 2-impact arc, its fold at 0.9335 and down to Ω_g, then up the
/// 1-impact arc to 5.
#[test]
fn the_branch_from_half_the_frequency_passes_the_nonsmooth_fold_once() {
    let wg = grazing();
    let fam = SceneFamily::new(crate::oscillator(0.05, 0.2, 0.8, 0.9), "forcing.omega", 1).unwrap().0;
    let (m, t) = (fam.model(0.5).unwrap(), fam.period(0.5).unwrap());
    let x0 = m.flow(0.0, &[0.0, 0.0], 100.0 * t, false).unwrap().x;
    let branch = continuation(&fam, &x0, &ContinuationOptions::new(0.5, 5.0)).unwrap();
    listed_once(&branch, wg);
    assert_eq!(branch.end, "reached to");
    // Past Ω_g the 1-impact orbits of the closed form.
    let k = branch.bifurcations.iter().find(|b| (b.param - wg).abs() <= 1e-9).unwrap().between.1;
    for p in branch.points[k..].iter().filter(|p| p.param < 1.0) {
        let err = closed_orbits(p.param).iter().map(|o| (o.0[0] - p.orbit.x[0]).abs().max((o.0[1] - p.orbit.x[1]).abs())).fold(f64::INFINITY, f64::min);
        assert!(p.orbit.impacts() == 1 && err <= 1e-8, "Ω = {}: {} impacts, {err:e} from the closed form", p.param, p.orbit.impacts());
    }
}

#[test]
fn a_nonsmooth_fold_met_from_the_unstable_arc_turns_back_at_the_grazing() {
    let wg = grazing();
    let fam = SceneFamily::new(crate::oscillator(0.05, 0.2, 0.8, 0.9), "forcing.omega", 1).unwrap().0;
    // The unstable 2-impact orbit at 0.9048735 (from its branch).
    let w0 = 0.9048735164774;
    let start = periodic_orbit(&fam.model(w0).unwrap(), 0.0, TAU / w0, &[-2.215954665578e-2, -1.520075255640], &Newton::default()).unwrap();
    assert_eq!((start.impacts(), start.mu_max() > 1.0), (2, true), "the start is the unstable 2-impact orbit");
    let branch = continuation(&fam, &start.x, &ContinuationOptions::new(w0, 0.85)).unwrap();
    listed_once(&branch, wg);
    assert_eq!(branch.bifurcations.len(), 1, "the grazing alone");
    // No point below the grazing; past it the branch goes back up along
    // the stable 1-impact orbits of the closed form.
    let k = branch.points.iter().position(|p| p.orbit.impacts() == 1).expect("the branch reaches the 1-impact orbits");
    assert!(branch.points.iter().all(|p| p.param >= wg - 1e-12), "a point below the grazing");
    assert!(branch.points[..k].iter().all(|p| p.orbit.impacts() == 2) && branch.points[k..].iter().all(|p| p.orbit.impacts() == 1), "the arcs in order");
    let ones = &branch.points[k..];
    assert!(ones.len() >= 3 && ones.windows(2).all(|w| w[1].param > w[0].param), "the 1-impact arc goes up in Ω: {}", branch.end);
    for p in ones {
        let (x, _, stable) = closed_orbits(p.param).into_iter().find(|o| o.2).unwrap_or_else(|| panic!("Ω = {}: no stable closed-form orbit", p.param));
        let err = (x[0] - p.orbit.x[0]).abs().max((x[1] - p.orbit.x[1]).abs());
        assert!(stable && p.stable() && err <= 1e-8, "Ω = {}: {:?} against the closed form's {x:?}", p.param, p.orbit.x);
    }
}
