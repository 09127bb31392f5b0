//! A forced two-dof chain with a coupled (consistent) mass and Rayleigh
//! damping, its second dof under a stop: the period-1 orbit and its
//! multipliers against an independent shooting written here (classical RK4
//! with the impact located by bisection to 1e-13, Newton's law applied with
//! `M⁻¹`, the map's Jacobian by central differences), and the variational
//! Jacobian against differences of the exact map.

use crate::between::differences;
use crate::continuation;
use signorini_fem::SymBand;
use signorini_orbits::{periodic_orbit, BifurcationKind, BranchPoint, ContinuationOptions, Family, Model, Newton, OrbitError};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};
use std::f64::consts::TAU;

const M: [[f64; 2]; 2] = [[2.0, 0.5], [0.5, 1.0]];
const K: [[f64; 2]; 2] = [[2.0, -1.0], [-1.0, 1.0]];
const A: f64 = 0.05;
const B: f64 = 0.02;
const F: f64 = 1.0;
const W: f64 = 1.3;
const G: f64 = 0.4;
const E: f64 = 0.7;

fn band(a: [[f64; 2]; 2]) -> SymBand {
    let mut b = SymBand::zeros(2, 1);
    for i in 0..2 {
        for j in 0..2 {
            if j >= i {
                b.set(i, j, a[i][j]);
            }
        }
    }
    b
}

fn model() -> Model {
    model_with(E, 0.0)
}

/// With the restitution `e` and a steady load `p` on the second dof
/// toward the stop (its static position `2p`: pressed on the stop for `p > G/2`).
fn model_with(e: f64, p: f64) -> Model {
    model_full(e, p, G)
}

/// With the stop at `g` too.
fn model_full(e: f64, p: f64, g: f64) -> Model {
    let c = [[A * M[0][0] + B * K[0][0], A * M[0][1] + B * K[0][1]], [A * M[1][0] + B * K[1][0], A * M[1][1] + B * K[1][1]]];
    let dy = Dynamics::new(band(M), band(K), vec![0.0, p], vec![Contact::new(1, Bounds { lo: f64::NEG_INFINITY, hi: g }, false)])
        .with_forcing(vec![Forcing { shape: vec![F, 0.0], time: TimeProfile::Sine { amplitude: 1.0, omega: W } }])
        .with_damping(Some(band(c)));
    Model::new(dy, e).unwrap()
}

// ---- The independent integrator.

fn minv() -> [[f64; 2]; 2] {
    let d = M[0][0] * M[1][1] - M[0][1] * M[1][0];
    [[M[1][1] / d, -M[0][1] / d], [-M[1][0] / d, M[0][0] / d]]
}

fn rhs(t: f64, y: [f64; 4]) -> [f64; 4] {
    let mi = minv();
    let f = [F * (W * t).sin(), 0.0];
    let r: Vec<f64> = (0..2).map(|i| f[i] - (0..2).map(|j| K[i][j] * y[j] + (A * M[i][j] + B * K[i][j]) * y[2 + j]).sum::<f64>()).collect();
    [y[2], y[3], mi[0][0] * r[0] + mi[0][1] * r[1], mi[1][0] * r[0] + mi[1][1] * r[1]]
}

fn rk4(t: f64, y: [f64; 4], h: f64) -> [f64; 4] {
    let add = |y: [f64; 4], k: [f64; 4], s: f64| [y[0] + s * k[0], y[1] + s * k[1], y[2] + s * k[2], y[3] + s * k[3]];
    let k1 = rhs(t, y);
    let k2 = rhs(t + h / 2.0, add(y, k1, h / 2.0));
    let k3 = rhs(t + h / 2.0, add(y, k2, h / 2.0));
    let k4 = rhs(t + h, add(y, k3, h));
    [0, 1, 2, 3].map(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// The stroboscopic map by RK4 (steps of T/20000), each impact located by
/// bisection on the step and Newton's law applied.
fn rk_map(y0: [f64; 4]) -> [f64; 4] {
    rk_map_with(y0, G)
}

/// [`rk_map`] with the stop at `g`.
fn rk_map_with(y0: [f64; 4], g: f64) -> [f64; 4] {
    let t_end = TAU / W;
    let n = 20_000;
    let h = t_end / f64::from(n);
    let (mut t, mut y) = (0.0, y0);
    while t < t_end - 1e-14 {
        let step = h.min(t_end - t);
        let z = rk4(t, y, step);
        if z[1] > g {
            // Bisection for the crossing.
            let (mut lo, mut hi) = (0.0, step);
            while hi - lo > 1e-14 {
                let m = 0.5 * (lo + hi);
                if rk4(t, y, m)[1] > g {
                    hi = m;
                } else {
                    lo = m;
                }
            }
            let mut w = rk4(t, y, lo);
            let mi = minv();
            let vn = w[3];
            let p = -(1.0 + E) * vn / mi[1][1];
            w[2] += mi[0][1] * p;
            w[3] += mi[1][1] * p;
            w[1] = w[1].min(g);
            (t, y) = (t + lo, w);
        } else {
            (t, y) = (t + step, z);
        }
    }
    y
}

fn rk_fixed_point(y: [f64; 4]) -> ([f64; 4], [[f64; 4]; 4]) {
    rk_fixed_point_with(y, G)
}

/// [`rk_fixed_point`] with the stop at `g`.
fn rk_fixed_point_with(mut y: [f64; 4], g: f64) -> ([f64; 4], [[f64; 4]; 4]) {
    let rk_map = |y| rk_map_with(y, g);
    let jac = |y: [f64; 4]| differences(y, 1e-6, rk_map);
    for _ in 0..20 {
        let g: Vec<f64> = rk_map(y).iter().zip(&y).map(|(a, b)| a - b).collect();
        if g.iter().all(|x| x.abs() < 1e-12) {
            break;
        }
        let j = jac(y);
        let a = faer::Mat::from_fn(4, 4, |r, c| j[r][c] - if r == c { 1.0 } else { 0.0 });
        let d = faer::linalg::solvers::Solve::solve(&a.partial_piv_lu(), &faer::Mat::from_fn(4, 1, |r, _| -g[r]));
        for i in 0..4 {
            y[i] += d[(i, 0)];
        }
    }
    (y, jac(y))
}

#[test]
fn the_exact_shooting_agrees_with_an_independent_runge_kutta_shooting() {
    let model = model();
    let t = TAU / W;
    // A transient on the exact flow, then Newton.
    let start = model.flow(0.0, &[0.0, 0.0, 0.0, 0.0], 200.0 * t, false).unwrap().x;
    let orbit = periodic_orbit(&model, 0.0, t, &start, &Newton::default()).unwrap();
    assert!(orbit.impacts() >= 1, "an impacting orbit: {} impacts", orbit.impacts());
    // The exact orbit is a fixed point of the RK map to its accuracy...
    let x = [orbit.x[0], orbit.x[1], orbit.x[2], orbit.x[3]];
    let r = rk_map(x).iter().zip(&x).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(r < 1e-9, "RK residual at the exact orbit {r:e}");
    // ...and RK's own Newton from 1e-3 away finds it.
    let (y, j) = rk_fixed_point(x.map(|v| v + 1e-3));
    let err = (0..4).map(|i| (y[i] - orbit.x[i]).abs()).fold(0.0, f64::max);
    assert!(err < 1e-8, "orbit {:?} vs RK {y:?}: {err:e}", orbit.x);
    let mut rk_mu = signorini_orbits::eigenvalues(&faer::Mat::from_fn(4, 4, |r, c| j[r][c])).unwrap();
    rk_mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(a.im.total_cmp(&b.im)));
    let mut mu = orbit.multipliers.clone();
    mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(a.im.total_cmp(&b.im)));
    for (a, b) in mu.iter().zip(&rk_mu) {
        assert!((a - b).norm() < 1e-5 * b.norm().max(1.0), "multiplier {a} vs RK {b}");
    }
    eprintln!("orbit {:?} ({} impacts), multipliers {mu:?}, RK state error {err:e}", orbit.x, orbit.impacts());
}

#[test]
fn the_variational_jacobian_of_the_chain_equals_differences_of_the_exact_map() {
    jacobian_check(E, 0.0, 0);
}

#[test]
fn with_plastic_impacts_the_orbit_sticks_and_its_jacobian_still_equals_differences() {
    jacobian_check(0.0, 0.25, 1);
}

/// The variational Jacobian against central differences on the attractor
/// reached from rest, which has at least `releases` held phases a period.
fn jacobian_check(e: f64, p: f64, releases: usize) {
    let model = model_with(e, p);
    let t = TAU / W;
    let x = model.flow(0.0, &[0.0; 4], 200.0 * t, false).unwrap().x;
    let orbit = periodic_orbit(&model, 0.0, t, &x, &Newton::default()).unwrap();
    assert!(orbit.releases() >= releases, "{} held phases", orbit.releases());
    let x: [f64; 4] = orbit.x.try_into().unwrap();
    let j = model.flow(0.0, &x, t, true).unwrap().jacobian.unwrap();
    let fd = differences(x, 1e-6, |y| model.flow(0.0, &y, t, false).unwrap().x.try_into().unwrap());
    for c in 0..4 {
        for r in 0..4 {
            let fd = fd[r][c];
            assert!((fd - j[(r, c)]).abs() <= 1e-6 * (1.0 + fd.abs()), "J[{r},{c}] = {} vs {fd}", j[(r, c)]);
        }
    }
}

/// The chain in the height of its stop.
struct Stop;

impl Family for Stop {
    fn model(&self, g: f64) -> Result<Model, OrbitError> {
        Ok(model_full(E, 0.0, g))
    }

    fn period(&self, _: f64) -> Result<f64, OrbitError> {
        Ok(TAU / W)
    }
}

/// The chain's linear steady state `Re(U e^{iWt})` (no contact), from
/// `(K − W² M + i W C) U = F e_1` solved by hand (2×2, complex): `U`.
fn steady_state() -> [(f64, f64); 2] {
    let c = |i: usize, j: usize| A * M[i][j] + B * K[i][j];
    // a = K − W² M (real part), b = W C (imaginary part).
    let a = |i: usize, j: usize| K[i][j] - W * W * M[i][j];
    let b = |i: usize, j: usize| W * c(i, j);
    let mul = |x: (f64, f64), y: (f64, f64)| (x.0 * y.0 - x.1 * y.1, x.0 * y.1 + x.1 * y.0);
    let z = |i, j| (a(i, j), b(i, j));
    let det = {
        let (p, q) = (mul(z(0, 0), z(1, 1)), mul(z(0, 1), z(1, 0)));
        (p.0 - q.0, p.1 - q.1)
    };
    let inv = |x: (f64, f64)| {
        let n = x.0 * x.0 + x.1 * x.1;
        (x.0 / n, -x.1 / n)
    };
    // The load is F sin Wt = Re(−i F e^{iWt}): right-hand side (0, −F) in the first row.
    let f = (0.0, -F);
    let u0 = mul(mul(z(1, 1), f), inv(det));
    let u1 = mul(mul((-z(1, 0).0, -z(1, 0).1), f), inv(det));
    [u0, u1]
}

/// The free orbit continued down in the stop's height reaches it where the
/// steady state's amplitude of the second dof equals the height (closed
/// form above); the impacting orbit born there is found and continued, and
/// its points are fixed points of the independent Runge–Kutta map, where
/// RK's own Newton from 1e-4 away lands on them.
#[test]
fn the_impacting_orbit_born_at_the_free_orbits_grazing_agrees_with_the_runge_kutta_shooting() {
    let u = steady_state();
    let want = u[1].0.hypot(u[1].1);
    // The free orbit's section state: q = Re U, v = Re(i W U) = −W Im U.
    let start = [u[0].0, u[1].0, -W * u[0].1, -W * u[1].1];
    let branch = continuation(&Stop, &start, &ContinuationOptions::new(1.5 * want, 0.5 * want)).unwrap();
    eprintln!("{} points, end: {}; grazing height {want}", branch.points.len(), branch.end);
    for b in &branch.bifurcations {
        eprintln!("  {} at {:.15} impacts {:?}", b.kind.name(), b.param, b.impacts);
    }
    for p in &branch.points {
        eprintln!("  {:.9} {} {:.3e} {}", p.param, p.orbit.impacts(), p.orbit.slowest_impact().unwrap_or(0.0), p.stable());
    }
    let g = branch.bifurcations.iter().find(|b| b.kind == BifurcationKind::Grazing).unwrap_or_else(|| panic!("no grazing; end: {}", branch.end));
    assert!((g.param - want).abs() <= 1e-9 * want, "grazing at {} vs the steady state's {want}", g.param);
    assert_eq!(g.impacts, (0, 1));
    let k = g.between.1;
    for p in &branch.points[..k] {
        let err = (0..4).map(|i| (p.orbit.x[i] - start[i]).abs()).fold(0.0, f64::max);
        assert!(p.orbit.impacts() == 0 && err <= 1e-10, "g = {}: the free orbit ({err:e})", p.param);
    }
    let after = &branch.points[k..];
    assert!(after.len() >= 5 && after.iter().all(|p| p.orbit.impacts() == 1), "the impacting branch");
    // Three of its points, away from the grazing (RK4's impact location
    // needs a speed well above its error).
    let picks: Vec<&BranchPoint> = after.iter().filter(|p| p.orbit.slowest_impact().unwrap() > 1e-2).step_by(4).take(3).collect();
    assert_eq!(picks.len(), 3);
    for p in picks {
        let x = [p.orbit.x[0], p.orbit.x[1], p.orbit.x[2], p.orbit.x[3]];
        let r = rk_map_with(x, p.param).iter().zip(&x).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        let (y, _) = rk_fixed_point_with(x.map(|v| v + 1e-4), p.param);
        let err = (0..4).map(|i| (y[i] - x[i]).abs()).fold(0.0, f64::max);
        eprintln!("g = {}: RK residual {r:e}, RK Newton {err:e} away", p.param);
        assert!(r < 1e-9 && err < 1e-8, "g = {}: RK residual {r:e}, RK's orbit {err:e} away", p.param);
    }
}

/// The orbit born at the chain's grazing is found by plain Newton only at
/// the last offset, 1e-3 of the range past the grazing, after the six
/// nearer ones failed: near an orbit (Newton's least residual within 1.5
/// times the offset, relative to the state). The searches on a side give
/// up after two that fail far from any orbit (above `max(1e-4, 100 f)` of
/// the state at the offset `f`: the paper's beam's, docs/orbits.md); a rule
/// that gave up on these would end the branch at the grazing. The first
/// impacting point is the one found there, at the steady state's grazing
/// height less 1e-3 of the range (the range is that height).
#[test]
fn the_searches_that_fail_near_the_chains_grazing_go_on_to_its_impacting_orbit() {
    let u = steady_state();
    let want = u[1].0.hypot(u[1].1);
    let start = [u[0].0, u[1].0, -W * u[0].1, -W * u[1].1];
    let branch = continuation(&Stop, &start, &ContinuationOptions::new(1.5 * want, 0.5 * want)).unwrap();
    let g = branch.bifurcations.iter().find(|b| b.kind == BifurcationKind::Grazing).unwrap_or_else(|| panic!("no grazing; end: {}", branch.end));
    assert_eq!(g.impacts, (0, 1), "end: {}", branch.end);
    let first = &branch.points[g.between.1];
    assert_eq!(first.orbit.impacts(), 1);
    let at = want - 1e-3 * want;
    assert!((first.param - at).abs() <= 1e-9 * want, "the first impacting orbit at {} vs {at}", first.param);
}
