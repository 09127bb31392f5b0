//! Periodic orbits of the impact oscillator against the closed forms of
//! `signorini_exact::oscillator` (an independent derivation: the period-1
//! orbit's impact phase from a sinusoid's roots, its monodromy `S Φ(T)`
//! written out by hand).

use signorini_exact::{ImpactOscillator, OscillatorParams, State};
use signorini_orbits::{periodic_orbit, Family, Newton, SceneFamily};
use std::f64::consts::TAU;

fn exact(omega: f64) -> ImpactOscillator {
    exact_at(1.0, 0.05, 0.2, omega)
}

fn exact_at(k: f64, zeta: f64, gap: f64, omega: f64) -> ImpactOscillator {
    ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: k, damping_ratio: zeta, force: 1.0, forcing_frequency: omega, gap, restitution: 0.8 }).unwrap()
}

/// The closed-form period-1 orbits at `omega`: the state at t = 0 (the
/// stroboscopic section), the multipliers and whether the orbit is stable.
pub(crate) fn closed_orbits(omega: f64) -> Vec<([f64; 2], [[f64; 2]; 2], bool)> {
    closed_orbits_at(1.0, 0.05, 0.2, omega)
}

/// [`closed_orbits`] of the oscillator with stiffness `k`, damping ratio
/// `zeta` and the stop at `gap` (unit mass and force, e = 0.8).
pub(crate) fn closed_orbits_at(k: f64, zeta: f64, gap: f64, omega: f64) -> Vec<([f64; 2], [[f64; 2]; 2], bool)> {
    let osc = exact_at(k, zeta, gap, omega);
    let t = TAU / omega;
    osc.period1_orbits()
        .into_iter()
        .filter(|o| o.is_admissible())
        .map(|o| {
            // Post-impact state at τ, flowed (no impact in between) to T.
            let tau = o.impact_time.rem_euclid(t);
            let z = osc.flow(tau, State { x: gap, v: -0.8 * o.impact_velocity }, t);
            let mu = [[o.multipliers[0].re, o.multipliers[0].im], [o.multipliers[1].re, o.multipliers[1].im]];
            ([z.x, z.v], mu, o.is_stable())
        })
        .collect()
}

fn family() -> SceneFamily {
    let doc = crate::oscillator(0.05, 0.2, 0.8, 2.0);
    SceneFamily::new(doc, "forcing.omega", 1).unwrap().0
}

pub(crate) fn sorted(mut m: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    m.sort_by(|a, b| (b[0].hypot(b[1]), b[1]).partial_cmp(&(a[0].hypot(a[1]), a[1])).unwrap());
    m
}

fn assert_multipliers(got: &[faer::c64], want: [[f64; 2]; 2], tol: f64, what: &str) {
    let g = sorted(got.iter().map(|m| [m.re, m.im]).collect());
    let w = sorted(want.to_vec());
    for (a, b) in g.iter().zip(&w) {
        let err = (a[0] - b[0]).hypot(a[1] - b[1]);
        assert!(err <= tol * a[0].hypot(a[1]).max(1.0), "{what}: multiplier {a:?} vs closed form {b:?} (error {err:e})");
    }
}

#[test]
fn shooting_finds_every_closed_form_period_one_orbit_with_its_multipliers() {
    let fam = family();
    let mut checked = (0, 0);
    for omega in (8..=40).map(|i| f64::from(i) / 10.0) {
        let model = fam.model(omega).unwrap();
        let t = fam.period(omega).unwrap();
        assert!((t - TAU / omega).abs() < 1e-15);
        for (x, mu, stable) in closed_orbits(omega) {
            // Start 1 % off the orbit.
            let guess = [x[0] * 1.01 + 1e-3, x[1] * 0.99];
            let orbit = periodic_orbit(&model, 0.0, t, &guess, &Newton::default()).unwrap_or_else(|e| panic!("Ω = {omega}: {e}"));
            let err = (orbit.x[0] - x[0]).abs().max((orbit.x[1] - x[1]).abs());
            assert!(err <= 1e-10, "Ω = {omega}: state {:?} vs closed form {x:?} (error {err:e})", orbit.x);
            assert_multipliers(&orbit.multipliers, mu, 1e-8, &format!("Ω = {omega}"));
            assert_eq!(orbit.impacts(), 1, "Ω = {omega}: one impact per period");
            if stable {
                checked.0 += 1;
            } else {
                checked.1 += 1;
            }
        }
    }
    eprintln!("checked (stable, unstable) = {checked:?}");
    assert!(checked.0 >= 3 && checked.1 >= 3, "stable and unstable orbits both checked: {checked:?}");
}

#[test]
fn the_variational_jacobian_equals_central_differences_of_the_map() {
    let fam = family();
    for omega in [1.7, 2.3] {
        let model = fam.model(omega).unwrap();
        let t = fam.period(omega).unwrap();
        for (x, _, _) in closed_orbits(omega) {
            let img = model.flow(0.0, &x, t, true).unwrap();
            let j = img.jacobian.unwrap();
            for c in 0..2 {
                let h = 1e-6;
                let (mut xp, mut xm) = (x, x);
                xp[c] += h;
                xm[c] -= h;
                let (p, m) = (model.flow(0.0, &xp, t, false).unwrap().x, model.flow(0.0, &xm, t, false).unwrap().x);
                for r in 0..2 {
                    let fd = (p[r] - m[r]) / (2.0 * h);
                    assert!((fd - j[(r, c)]).abs() <= 1e-6 * (1.0 + fd.abs()), "Ω = {omega}: J[{r},{c}] = {} vs differences {fd}", j[(r, c)]);
                }
            }
        }
    }
}

/// Checks every point of a branch against the closed forms: impacting
/// orbits against `period1_orbits`, orbits without impacts against the
/// linear steady state.
fn check_branch(branch: &signorini_orbits::Branch) {
    for p in &branch.points {
        let osc = exact(p.param);
        match p.orbit.impacts() {
            0 => {
                let z = osc.steady_state(0.0);
                let err = (p.orbit.x[0] - z.x).abs().max((p.orbit.x[1] - z.v).abs());
                assert!(err <= 1e-10, "Ω = {}: steady state error {err:e}", p.param);
            }
            1 => {
                let best = closed_orbits(p.param).into_iter().map(|(x, mu, _)| ((p.orbit.x[0] - x[0]).abs().max((p.orbit.x[1] - x[1]).abs()), mu)).min_by(|a, b| a.0.total_cmp(&b.0));
                let (err, mu) = best.unwrap_or_else(|| panic!("Ω = {}: no closed-form orbit", p.param));
                assert!(err <= 1e-8, "Ω = {}: state error {err:e}", p.param);
                assert_multipliers(&p.orbit.multipliers, mu, 1e-8, &format!("Ω = {}", p.param));
            }
            k => panic!("Ω = {}: {k} impacts on the period-1 branch", p.param),
        }
    }
}

#[test]
fn a_branch_through_grazing_matches_the_closed_forms_and_the_grazing_frequency() {
    use crate::continuation;
    use signorini_orbits::{BifurcationKind, ContinuationOptions};
    let fam = family();
    let start = closed_orbits(2.2).into_iter().find(|o| o.2).expect("a stable orbit at the start").0;
    let branch = continuation(&fam, &start, &ContinuationOptions::new(2.2, 3.0)).unwrap();
    assert_eq!(branch.end, "reached to");
    check_branch(&branch);
    let grazing: Vec<_> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::Grazing).collect();
    assert_eq!(grazing.len(), 1, "{:?}", branch.bifurcations);
    let want = exact(2.0).grazing_frequencies()[0];
    assert!((grazing[0].param - want).abs() <= 1e-8 * want, "grazing at {} vs closed form {want}", grazing[0].param);
    assert_eq!(grazing[0].impacts, (1, 0));
    assert!(branch.points.iter().any(|p| p.orbit.impacts() == 0 && p.param > want), "the branch goes on without impacts");
    // The period doubling is the closed form's, the jump of the test
    // function at 2.278 (where the multiplier nearest −1 passes from −1.72
    // to −0.28) is not one.
    assert_period_doublings(&branch, 2.2, 2.44);
}

/// The branch's period doublings in `[lo, hi]` are the closed form's, to 1e-8.
fn assert_period_doublings(branch: &signorini_orbits::Branch, lo: f64, hi: f64) {
    let mut got: Vec<f64> = branch.bifurcations.iter().filter(|b| b.kind == signorini_orbits::BifurcationKind::PeriodDoubling && (lo..=hi).contains(&b.param)).map(|b| b.param).collect();
    got.sort_by(f64::total_cmp);
    let want = closed_pd(lo, hi);
    assert_eq!(got.len(), want.len(), "period doublings {got:?} vs closed form {want:?}");
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() <= 1e-8 * w, "period doubling at {g} vs closed form {w}");
    }
}

/// The closed form's period-doubling frequencies in `[lo, hi]`: where a
/// real multiplier of its orbits crosses −1 (bisection).
pub(crate) fn closed_pd(lo: f64, hi: f64) -> Vec<f64> {
    let test = |w: f64| -> Option<f64> {
        closed_orbits(w)
            .into_iter()
            .filter_map(|(_, mu, _)| mu.iter().filter(|m| m[1] == 0.0 && m[0] < 0.0).map(|m| -m[0] - 1.0).min_by(|a, b| a.abs().total_cmp(&b.abs())))
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
    };
    let n = 400;
    let mut out = Vec::new();
    for i in 0..n {
        let (a, b) = (lo + (hi - lo) * f64::from(i) / f64::from(n), lo + (hi - lo) * f64::from(i + 1) / f64::from(n));
        let (Some(fa), Some(fb)) = (test(a), test(b)) else { continue };
        if fa * fb < 0.0 {
            let (mut a, mut b, mut fa) = (a, b, fa);
            for _ in 0..80 {
                let m = 0.5 * (a + b);
                let fm = test(m).unwrap();
                if fm * fa > 0.0 {
                    (a, fa) = (m, fm);
                } else {
                    b = m;
                }
            }
            // A crossing of −1, not the jump where the multiplier nearest
            // −1 passes from one negative multiplier to the other (both
            // equally far from −1 there).
            if test(0.5 * (a + b)).is_some_and(|f| f.abs() < 1e-6) {
                out.push(0.5 * (a + b));
            }
        }
    }
    out
}

#[test]
fn period_doublings_on_the_branch_are_where_the_closed_form_multiplier_is_minus_one() {
    use crate::continuation;
    use signorini_orbits::{BifurcationKind, ContinuationOptions};
    let fam = family();
    let start = closed_orbits(2.2).into_iter().find(|o| o.2).expect("a stable orbit at the start").0;
    let branch = continuation(&fam, &start, &ContinuationOptions::new(2.2, 1.03)).unwrap();
    assert_eq!(branch.end, "reached to");
    check_branch(&branch);
    let got: Vec<f64> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::PeriodDoubling).map(|b| b.param).collect();
    let mut want = closed_pd(1.03, 2.2);
    want.reverse();
    assert_eq!(got.len(), want.len(), "period doublings {got:?} vs closed form {want:?}");
    assert!(!want.is_empty());
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() <= 1e-8 * w, "period doubling at {g} vs closed form {w}");
    }
    // Unstable between the two, stable outside.
    for p in &branch.points {
        let inside = p.param < want[0] && p.param > want[want.len() - 1];
        if (p.param - want[0]).abs() > 1e-6 && (p.param - want[want.len() - 1]).abs() > 1e-6 {
            assert_eq!(p.stable(), !inside || want.len() % 2 == 1, "Ω = {}: stable = {}", p.param, p.stable());
        }
    }
}

/// The closed form's saddle-node in `[lo, hi]` (its two period-1 roots
/// there, none beyond): bisection on the number of roots, which the closed
/// form gets from `|α| <= R` (docs of `signorini_exact::ImpactOscillator`).
fn closed_fold(gap: f64, lo: f64, hi: f64) -> f64 {
    let roots =
        |w: f64| ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: w, gap, restitution: 0.8 }).unwrap().period1_roots().len();
    let (mut a, mut b) = (lo, hi);
    assert!(roots(a) == 2 && roots(b) == 0);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if roots(m) == 2 {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

#[test]
fn a_fold_is_located_at_the_closed_form_saddle_node_and_the_branch_turns_back_unstable() {
    use crate::continuation;
    use signorini_orbits::{BifurcationKind, ContinuationOptions};
    let doc = crate::oscillator(0.05, 0.5, 0.8, 2.0);
    let fam = SceneFamily::new(doc, "forcing.omega", 1).unwrap().0;
    let osc = |w: f64| ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: w, gap: 0.5, restitution: 0.8 }).unwrap();
    let t = TAU / 1.6;
    let o = osc(1.6).period1_orbits().into_iter().find(|o| o.is_admissible() && o.is_stable()).unwrap();
    let z = osc(1.6).flow(o.impact_time.rem_euclid(t), State { x: 0.5, v: -0.8 * o.impact_velocity }, t);
    let branch = continuation(&fam, &[z.x, z.v], &ContinuationOptions::new(1.6, 1.95)).unwrap();
    let folds: Vec<_> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::Fold).collect();
    assert_eq!(folds.len(), 1, "{:?}", branch.bifurcations);
    let want = closed_fold(0.5, 1.85, 1.95);
    eprintln!("fold at {} vs closed form {want}; branch end: {}", folds[0].param, branch.end);
    assert!((folds[0].param - want).abs() <= 1e-8 * want, "fold at {} vs closed form {want}", folds[0].param);
    assert!((folds[0].mu.re - 1.0).abs() < 1e-6, "the critical multiplier {:?}", folds[0].mu);
    // Before the fold stable, after it (the other orbit of the pair) unstable;
    // every one-impact point equal to a closed-form orbit.
    let k = folds[0].between.1;
    assert!(branch.points[..k].iter().all(|p| p.stable() || (p.param - want).abs() < 1e-4));
    assert!(branch.points[k..].iter().filter(|p| p.orbit.impacts() == 1 && (p.param - want).abs() > 1e-4).all(|p| !p.stable()));
    for p in branch.points.iter().filter(|p| p.orbit.impacts() == 1) {
        let t = TAU / p.param;
        let best = osc(p.param)
            .period1_orbits()
            .into_iter()
            .filter(|o| o.is_admissible())
            .map(|o| {
                let z = osc(p.param).flow(o.impact_time.rem_euclid(t), State { x: 0.5, v: -0.8 * o.impact_velocity }, t);
                (p.orbit.x[0] - z.x).abs().max((p.orbit.x[1] - z.v).abs())
            })
            .fold(f64::INFINITY, f64::min);
        // Near the fold the closed form's roots carry √ε errors.
        let tol = if (p.param - want).abs() < 1e-3 { 1e-6 } else { 1e-8 };
        assert!(best <= tol, "Ω = {}: state error {best:e}", p.param);
    }
}

#[test]
fn from_the_free_orbit_into_grazing_the_branch_goes_on_with_the_impact() {
    use crate::continuation;
    use signorini_orbits::{BifurcationKind, ContinuationOptions};
    let fam = family();
    // The linear steady state at Ω = 3 (no impact), continued down.
    let z = exact(3.0).steady_state(0.0);
    let branch = continuation(&fam, &[z.x, z.v], &ContinuationOptions::new(3.0, 2.2)).unwrap();
    assert_eq!(branch.end, "reached to");
    check_branch(&branch);
    let want = exact(2.0).grazing_frequencies()[0];
    let grazing: Vec<_> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::Grazing).collect();
    assert_eq!(grazing.len(), 1, "{:?}", branch.bifurcations);
    assert!((grazing[0].param - want).abs() <= 1e-8 * want, "grazing at {} vs closed form {want}", grazing[0].param);
    assert_eq!(grazing[0].impacts, (0, 1));
    assert_period_doublings(&branch, 2.2, 2.44);
}

/// The front end labels each branch point with what the point carries (its
/// scene's Ω and tip, not built again): for the oscillator the tip is the
/// displacement itself, so `branch.csv`'s `displacement` is its `q0`, on
/// the period-1 branch and the period-doubled ones alike; and a period-1
/// point's impact phase is Ω·t of its impact with Ω its own parameter
/// (the closed-form orbit's phase there).
#[test]
fn every_point_carries_its_own_omega_and_tip() {
    use signorini_orbits::front::{continue_scene, ContinueOptions};
    let doc = crate::oscillator(0.05, 0.2, 0.8, 2.2);
    let opts = ContinueOptions { param: "forcing.omega".into(), from: 2.2, to: 1.03, period: 1, transient: 100.0, max_points: 400, switch: true, sweep: Vec::new(), param_scale: None };
    let done = continue_scene(doc, &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true).unwrap();
    let csv = &done.files.iter().find(|f| f.0 == "branch.csv").unwrap().1;
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (cd, cq, cp, cb, cph, cper) = (col("displacement"), col("q0"), col("param"), col("branch"), col("impact_phase"), col("period"));
    let mut doubled = 0;
    for l in lines {
        let c: Vec<&str> = l.split(',').collect();
        assert_eq!(c[cd], c[cq], "{l}");
        doubled += usize::from(c[cb] != "0");
        if c[cper] == "1" && !c[cph].is_empty() {
            let omega: f64 = c[cp].parse().unwrap();
            let phase: f64 = c[cph].parse().unwrap();
            let want: Vec<f64> = exact(omega).period1_orbits().into_iter().filter(|o| o.is_admissible()).map(|o| o.phase.rem_euclid(TAU)).collect();
            assert!(want.iter().any(|w| (w - phase).abs() < 1e-6 || (TAU - (w - phase).abs()) < 1e-6), "Ω = {omega}: phase {phase} vs closed form {want:?}");
        }
    }
    assert!(doubled > 10, "the period-doubled branches are there: {doubled} rows");
}

/// Each period doubling listed, in both directions along the branch,
/// carries the multiplier of the orbit where it is located: within 1e-6 of
/// −1, and the closed form's multiplier nearest −1 at that Ω (an
/// interpolated point keeps the multipliers of the bracket's end nearer
/// `a`; a jump of the test function between two negative multipliers
/// equally far from −1 — −1.717 and −0.283 at Ω = 2.2784 — listed its
/// end's multiplier as a "period doubling").
#[test]
fn a_period_doublings_multiplier_is_minus_one_at_the_closed_forms_frequency() {
    use crate::continuation;
    use signorini_orbits::{BifurcationKind, ContinuationOptions};
    let fam = family();
    let want = closed_pd(2.2, 2.44);
    assert_eq!(want.len(), 1, "{want:?}");
    for (from, to) in [(2.2, 3.0), (2.44, 2.2)] {
        let start = closed_orbits(from).into_iter().find(|o| o.2 || from > 2.3).expect("an orbit at the start").0;
        let branch = continuation(&fam, &start, &ContinuationOptions::new(from, to)).unwrap();
        let pds: Vec<_> = branch.bifurcations.iter().filter(|b| b.kind == BifurcationKind::PeriodDoubling && (2.2..=2.44).contains(&b.param)).collect();
        assert_eq!(pds.len(), 1, "{from} -> {to}: {pds:?}");
        let b = pds[0];
        assert!((b.param - want[0]).abs() <= 1e-8 * want[0], "{from} -> {to}: at {} vs closed form {}", b.param, want[0]);
        let closed = closed_orbits(b.param).into_iter().flat_map(|(_, mu, _)| mu).filter(|m| m[1] == 0.0).map(|m| m[0]).min_by(|x, y| (x + 1.0).abs().total_cmp(&(y + 1.0).abs())).unwrap();
        assert!((b.mu.re + 1.0).abs() < 1e-6 && b.mu.im == 0.0, "{from} -> {to}: multiplier {}", b.mu);
        assert!((b.mu.re - closed).abs() < 1e-6, "{from} -> {to}: multiplier {} vs closed form {closed}", b.mu.re);
    }
}
