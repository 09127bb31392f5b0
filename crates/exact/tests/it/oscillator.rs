//! The forced impact oscillator against oracles independent of its closed
//! forms: finite differences of the ODE, the semigroup property, a Taylor
//! series for short steps, a classical RK4 integration (free, and with
//! Newton's impact law and event location) written here, a dense scan of the
//! period-1 residual computed by that RK4, a finite-difference Jacobian of
//! the RK4 impact map, and the steady-state amplitude solved here.

use signorini_exact::{Admissibility, ImpactOscillator, OscillatorError, OscillatorParams, Period1Orbit, State};
use std::f64::consts::TAU;

/// The product's reference scene: `m = k = 1`, `ζ = 0.05`, `F = 1`,
/// `g = 0.2`, `r = 0.8`.
fn reference(omega: f64) -> OscillatorParams {
    OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: omega, gap: 0.2, restitution: 0.8 }
}

/// A scene with non-unit `m`, `k` (catches `k` vs `k/m` mix-ups).
fn odd() -> OscillatorParams {
    OscillatorParams { mass: 2.5, stiffness: 7.0, damping_ratio: 0.13, force: 1.7, forcing_frequency: 1.3, gap: 0.35, restitution: 0.6 }
}

fn osc(p: OscillatorParams) -> ImpactOscillator {
    ImpactOscillator::new(p).unwrap()
}

/// Deterministic uniform numbers in `[0, 1)` (64-bit LCG).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

/// The acceleration of the ODE, written from the parameters.
fn accel(p: &OscillatorParams, t: f64, x: f64, v: f64, forced: bool) -> f64 {
    let c = 2.0 * p.damping_ratio * (p.stiffness * p.mass).sqrt();
    let f = if forced { p.force * (p.forcing_frequency * t).cos() } else { 0.0 };
    (f - c * v - p.stiffness * x) / p.mass
}

/// One classical RK4 step of length `h` of the free motion.
fn rk4(p: &OscillatorParams, t: f64, x: f64, v: f64, h: f64, forced: bool) -> (f64, f64) {
    let a = |t, x, v| accel(p, t, x, v, forced);
    let (k1x, k1v) = (v, a(t, x, v));
    let (k2x, k2v) = (v + 0.5 * h * k1v, a(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v));
    let (k3x, k3v) = (v + 0.5 * h * k2v, a(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v));
    let (k4x, k4v) = (v + h * k3v, a(t + h, x + h * k3x, v + h * k3v));
    (x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x), v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v))
}

/// RK4 of the free motion from `(x, v)` at `t0` to `t1` with about `n` steps.
fn rk4_to(p: &OscillatorParams, t0: f64, x: f64, v: f64, t1: f64, n: usize, forced: bool) -> (f64, f64) {
    let h = (t1 - t0) / n as f64;
    let (mut x, mut v) = (x, v);
    for i in 0..n {
        (x, v) = rk4(p, t0 + i as f64 * h, x, v, h, forced);
    }
    (x, v)
}

/// RK4 with the stop: from `(x, v)` (below the stop) at `t0`, the next time
/// `x` reaches `g` and the velocity there, located by bisection of the
/// length of a single RK4 sub-step from the step's start.
fn next_impact(p: &OscillatorParams, t0: f64, x: f64, v: f64, h: f64, t_max: f64) -> (f64, f64) {
    let g = p.gap;
    let (mut t, mut x, mut v) = (t0, x, v);
    while t < t_max {
        let (xn, vn) = rk4(p, t, x, v, h, true);
        if xn >= g {
            let (mut lo, mut hi) = (0.0, h);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if rk4(p, t, x, v, mid, true).0 >= g {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let s = 0.5 * (lo + hi);
            return (t + s, rk4(p, t, x, v, s, true).1);
        }
        (t, x, v) = (t + h, xn, vn);
    }
    panic!("no impact before t = {t_max}");
}

fn assert_close(what: &str, a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b} (diff {:e}, tol {tol:e})", (a - b).abs());
}

// ---------------------------------------------------------------------------
// (a) The flow solves the ODE, is a semigroup, and is accurate for short steps.

#[test]
fn flow_satisfies_the_ode() {
    // 8th-order central differences of t ↦ x(t).
    const D1: [f64; 4] = [4.0 / 5.0, -1.0 / 5.0, 4.0 / 105.0, -1.0 / 280.0];
    const D2: [f64; 5] = [-205.0 / 72.0, 8.0 / 5.0, -1.0 / 5.0, 8.0 / 315.0, -1.0 / 560.0];
    let mut rng = Lcg(7);
    for p in [reference(1.6), reference(2.2), odd()] {
        let o = osc(p);
        let c = 2.0 * p.damping_ratio * (p.stiffness * p.mass).sqrt();
        for _ in 0..200 {
            let t0 = rng.range(-10.0, 10.0);
            let z0 = random_state(&mut rng, (-1.0, 0.3), (-2.0, 2.0));
            let t = t0 + rng.range(-8.0, 8.0);
            let h = 0.02;
            let x = |s: f64| o.flow(t0, z0, t + s).x;
            let x0 = x(0.0);
            let mut d1 = 0.0;
            let mut d2 = D2[0] * x0;
            for j in 1..5 {
                let (xp, xm) = (x(j as f64 * h), x(-(j as f64) * h));
                d1 += D1[j - 1] * (xp - xm);
                d2 += D2[j] * (xp + xm);
            }
            let (d1, d2) = (d1 / h, d2 / (h * h));
            let fc = p.force * (p.forcing_frequency * t).cos();
            let scale = (p.mass * d2).abs() + (c * d1).abs() + (p.stiffness * x0).abs() + fc.abs();
            let res = p.mass * d2 + c * d1 + p.stiffness * x0 - fc;
            assert!(res.abs() <= 1e-8 * scale, "ODE residual {res:e} (scale {scale}) at t = {t}");
            // And the returned velocity is x'.
            let v = o.flow(t0, z0, t).v;
            assert_close("v = x'", v, d1, 1e-8 * (1.0 + v.abs()));
            // Initial condition.
            let z = o.flow(t0, z0, t0);
            assert_eq!((z.x, z.v), (z0.x, z0.v));
        }
    }
}

#[test]
fn flow_is_a_semigroup() {
    let mut rng = Lcg(11);
    for p in [reference(1.9), odd()] {
        let o = osc(p);
        for _ in 0..500 {
            let t0 = rng.range(-20.0, 20.0);
            let z0 = random_state(&mut rng, (-2.0, 1.0), (-3.0, 3.0));
            let t1 = t0 + rng.range(-5.0, 5.0);
            let t2 = t1 + rng.range(-5.0, 5.0);
            let two = o.flow(t1, o.flow(t0, z0, t1), t2);
            let one = o.flow(t0, z0, t2);
            let s = 1.0 + z0.x.abs() + z0.v.abs();
            assert_close("semigroup x", two.x, one.x, 1e-13 * s);
            assert_close("semigroup v", two.v, one.v, 1e-13 * s);
        }
    }
}

#[test]
fn increment_is_accurate_for_short_steps() {
    // Taylor series of the ODE solution, derivatives from the ODE itself.
    let mut rng = Lcg(3);
    for p in [reference(1.7), odd()] {
        let o = osc(p);
        let (m, k, w) = (p.mass, p.stiffness, p.forcing_frequency);
        let c = 2.0 * p.damping_ratio * (k * m).sqrt();
        for _ in 0..100 {
            let t0 = rng.range(0.0, 50.0);
            let z0 = random_state(&mut rng, (-1.0, 0.2), (0.5, 2.0));
            let (s, co) = (w * t0).sin_cos();
            let d2 = (p.force * co - c * z0.v - k * z0.x) / m;
            let d3 = (-p.force * w * s - c * d2 - k * z0.v) / m;
            let d4 = (-p.force * w * w * co - c * d3 - k * d2) / m;
            let d5 = (p.force * w * w * w * s - c * d4 - k * d3) / m;
            for h in [1e-4, 1e-6, 1e-8, 1e-10, -1e-7] {
                // The step actually represented (t0 + h is rounded).
                let h = (t0 + h) - t0;
                let d = o.increment(t0, z0, t0 + h);
                let dx = z0.v * h + d2 * h * h / 2.0 + d3 * h.powi(3) / 6.0 + d4 * h.powi(4) / 24.0;
                let dv = d2 * h + d3 * h * h / 2.0 + d4 * h.powi(3) / 6.0 + d5 * h.powi(4) / 24.0;
                assert_close("dx", d.x, dx, 1e-12 * dx.abs());
                assert_close("dv", d.v, dv, 1e-12 * dv.abs() + 1e-14 * (z0.v * h).abs());
            }
        }
    }
}

// ---------------------------------------------------------------------------
// (b) The flow against RK4.

#[test]
fn flow_matches_rk4() {
    let mut rng = Lcg(5);
    for p in [reference(1.6), reference(2.2), odd()] {
        let o = osc(p);
        for _ in 0..3 {
            let t0 = rng.range(-3.0, 3.0);
            let z0 = random_state(&mut rng, (-1.0, 0.2), (-2.0, 2.0));
            let (mut t, mut x, mut v) = (t0, z0.x, z0.v);
            for _ in 0..8 {
                (x, v) = rk4_to(&p, t, x, v, t + 1.0, 2000, true);
                t += 1.0;
                let z = o.flow(t0, z0, t);
                assert_close("x vs RK4", z.x, x, 1e-10);
                assert_close("v vs RK4", z.v, v, 1e-10);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Period-1 orbits.

/// The period-1 residual by RK4 superposition: the free motion over `T`
/// from `(g, -rV)` at `τ` is `z_a(τ) + V z_b` (`z_a` forced from `(g, 0)`,
/// `z_b` unforced from `(0, -r)`); it ends at `(g, V)` for some `V` iff
/// `H(τ) = (g - x_a)(v_b - 1) + x_b v_a = 0`, and then `V = v_a/(1 - v_b)`.
struct Rk4Residual {
    p: OscillatorParams,
    zb: (f64, f64),
    n: usize,
}

impl Rk4Residual {
    fn new(p: OscillatorParams) -> Self {
        let t = TAU / p.forcing_frequency;
        let n = 3000;
        let zb = rk4_to(&p, 0.0, 0.0, -p.restitution, t, n, false);
        Self { p, zb, n }
    }
    fn eval(&self, tau: f64) -> (f64, f64) {
        let t = TAU / self.p.forcing_frequency;
        let (xa, va) = rk4_to(&self.p, tau, self.p.gap, 0.0, tau + t, self.n, true);
        let (xb, vb) = self.zb;
        ((self.p.gap - xa) * (vb - 1.0) + xb * va, va / (1.0 - vb))
    }
}

#[test]
fn period1_roots_are_all_the_roots_of_the_rk4_residual() {
    let mut cases: Vec<OscillatorParams> = (0..=6).map(|i| reference(1.6 + 0.1 * f64::from(i))).collect();
    cases.push(odd());
    cases.push(OscillatorParams { restitution: 0.0, ..reference(1.3) });
    cases.push(OscillatorParams { restitution: 1.0, damping_ratio: 0.02, ..reference(0.7) });
    for p in cases {
        let o = osc(p);
        let t = TAU / p.forcing_frequency;
        let res = Rk4Residual::new(p);
        let n = 200;
        let mut roots = Vec::new();
        let mut prev = res.eval(0.0).0;
        for i in 1..=n {
            let (a, b) = ((i - 1) as f64 * t / n as f64, i as f64 * t / n as f64);
            let cur = res.eval(b).0;
            if prev == 0.0 || prev.signum() != cur.signum() {
                let (mut lo, mut hi, flo) = (a, b, prev);
                for _ in 0..45 {
                    let mid = 0.5 * (lo + hi);
                    if res.eval(mid).0.signum() == flo.signum() {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let tau = 0.5 * (lo + hi);
                roots.push((tau, res.eval(tau).1));
            }
            prev = cur;
        }
        let got = o.period1_roots();
        assert_eq!(got.len(), roots.len(), "number of roots at {p:?}: {got:?} vs {roots:?}");
        for (g, (tau, v)) in got.iter().zip(&roots) {
            assert_close("impact time", g.impact_time, *tau, 1e-8);
            assert_close("phase", g.phase, (p.forcing_frequency * tau).rem_euclid(TAU), 1e-8);
            assert_close("V", g.impact_velocity, *v, 1e-8 * (1.0 + v.abs()));
        }
    }
}

/// The orbits used below: all admissible roots of the reference scene, one
/// unstable one near grazing (Ω = 2.3) and one of the odd scene.
fn orbit_cases() -> Vec<(OscillatorParams, Period1Orbit)> {
    let mut v = Vec::new();
    for w in [1.6, 1.8, 2.0, 2.2, 2.3, 1.1] {
        let p = reference(w);
        for o in osc(p).period1_orbits() {
            v.push((p, o));
        }
    }
    for o in osc(odd()).period1_orbits() {
        v.push((odd(), o));
    }
    v
}

#[test]
fn period1_orbits_are_periodic_under_rk4_with_impacts() {
    let cases = orbit_cases();
    assert!(cases.len() >= 7, "expected an orbit per scene");
    for (p, o) in cases {
        let t = TAU / p.forcing_frequency;
        let h = t / 4000.0;
        let (mut t0, mut v) = (o.impact_time, o.impact_velocity);
        for n in 1..=4 {
            let (ti, vi) = next_impact(&p, t0, p.gap, -p.restitution * v, h, t0 + 2.0 * t);
            assert_close("impact time", ti, o.impact_time + n as f64 * t, 1e-8);
            assert_close("impact velocity", vi, o.impact_velocity, 1e-8);
            (t0, v) = (ti, vi);
        }
    }
}

#[test]
fn inadmissible_roots_are_rejected_for_the_right_reason() {
    let mut seen_penetration = false;
    for w in [0.3, 0.5, 0.7, 0.9, 1.6, 2.0, 2.3, 2.6] {
        let p = reference(w);
        let t = TAU / w;
        for o in osc(p).period1_roots() {
            let v = o.impact_velocity;
            if v.is_nan() || v <= 0.0 {
                assert_eq!(o.admissibility, Admissibility::NonPositiveVelocity);
                continue;
            }
            // Highest point of the free RK4 motion strictly between the impacts.
            let (mut x, mut u) = (p.gap, -p.restitution * v);
            let n = 20000;
            let hh = t / n as f64;
            let mut top = f64::NEG_INFINITY;
            for i in 0..n - 1 {
                (x, u) = rk4(&p, o.impact_time + i as f64 * hh, x, u, hh, true);
                if i > 2 {
                    top = top.max(x);
                }
            }
            if top > p.gap + 1e-9 {
                seen_penetration = true;
                assert!(matches!(o.admissibility, Admissibility::Penetrates { .. }), "Ω = {w}: RK4 reaches {top} > g but {:?}", o.admissibility);
            } else {
                assert!(top < p.gap - 1e-9, "Ω = {w}: too close to call ({top})");
                assert!(o.is_admissible(), "Ω = {w}: {:?} but RK4 stays below g", o.admissibility);
            }
        }
    }
    assert!(seen_penetration, "the sweep must contain a penetrating root");
}

/// The impact map `(τ, V) ↦ (τ' - T, V')` by RK4.
fn rk4_impact_map(p: &OscillatorParams, tau: f64, v: f64) -> (f64, f64) {
    let t = TAU / p.forcing_frequency;
    let (ti, vi) = next_impact(p, tau, p.gap, -p.restitution * v, t / 4000.0, tau + 2.0 * t);
    (ti - t, vi)
}

#[test]
fn multipliers_match_the_rk4_impact_map_jacobian() {
    let mut seen = (false, false);
    for (p, o) in orbit_cases() {
        let (tau, v) = (o.impact_time, o.impact_velocity);
        let (et, ev) = (1e-5, 1e-5 * v.max(0.1));
        let (a, b) = (rk4_impact_map(&p, tau + et, v), rk4_impact_map(&p, tau - et, v));
        let (c, d) = (rk4_impact_map(&p, tau, v + ev), rk4_impact_map(&p, tau, v - ev));
        let j = [[(a.0 - b.0) / (2.0 * et), (c.0 - d.0) / (2.0 * ev)], [(a.1 - b.1) / (2.0 * et), (c.1 - d.1) / (2.0 * ev)]];
        let tr = j[0][0] + j[1][1];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let [m1, m2] = o.multipliers;
        // μ1 + μ2 and μ1 μ2 (real for a complex pair).
        let sum = m1.re + m2.re;
        let prod = m1.re * m2.re - m1.im * m2.im;
        assert_close("trace", sum, tr, 1e-5 * (1.0 + tr.abs()));
        assert_close("det", prod, det, 1e-5 * (1.0 + det.abs()));
        // The determinant is r² e^{-2ζω T} (independent closed form).
        let wn = (p.stiffness / p.mass).sqrt();
        let t = TAU / p.forcing_frequency;
        let det_exact = p.restitution.powi(2) * (-2.0 * p.damping_ratio * wn * t).exp();
        assert_close("det closed form", prod, det_exact, 1e-12);
        if o.is_stable() {
            seen.0 = true;
        } else {
            seen.1 = true;
        }
    }
    assert!(seen.0 && seen.1, "need stable and unstable orbits: {seen:?}");
}

#[test]
fn stability_agrees_with_rk4_perturbation_growth() {
    for (p, o) in orbit_cases() {
        let t = TAU / p.forcing_frequency;
        let dev = |tau: f64, v: f64, n: usize| ((tau - o.impact_time - n as f64 * t) * p.forcing_frequency).abs() + (v - o.impact_velocity).abs() / o.impact_velocity;
        let mu = o.multipliers[0].abs();
        let eps = 1e-7;
        let (mut tau, mut v) = (o.impact_time, o.impact_velocity * (1.0 + eps));
        let d0 = dev(tau, v, 0);
        // Enough impacts for a factor 1e3 either way (at most 300).
        let n = ((3.0 * std::f64::consts::LN_10 / mu.ln().abs().max(1e-3)).ceil() as usize).clamp(2, 300);
        for _ in 0..n {
            let (ti, vi) = next_impact(&p, tau, p.gap, -p.restitution * v, t / 4000.0, tau + 2.0 * t);
            (tau, v) = (ti, vi);
        }
        let ratio = dev(tau, v, n) / d0;
        if o.is_stable() {
            assert!(ratio < 0.1, "stable orbit {o:?}: perturbation ratio {ratio} after {n}");
        } else {
            assert!(ratio > 10.0, "unstable orbit {o:?}: perturbation ratio {ratio} after {n}");
        }
    }
}

// ---------------------------------------------------------------------------
// (d) Grazing.

/// Steady-state amplitude at `Ω`, from the 2×2 system for `A cos + B sin`.
fn amplitude(p: &OscillatorParams, w: f64) -> f64 {
    let c = 2.0 * p.damping_ratio * (p.stiffness * p.mass).sqrt();
    // (k - m w²) A + c w B = F;  -c w A + (k - m w²) B = 0.
    let d = p.stiffness - p.mass * w * w;
    let det = d * d + c * c * w * w;
    let a = p.force * d / det;
    let b = p.force * c * w / det;
    a.hypot(b)
}

#[test]
fn grazing_frequencies_are_where_the_amplitude_equals_the_gap() {
    let cases = [
        (reference(2.0), 1),
        (OscillatorParams { force: 0.5, gap: 1.0, ..reference(2.0) }, 2),
        (OscillatorParams { force: 0.5, gap: 1.0, damping_ratio: 0.5, ..reference(2.0) }, 0),
        (OscillatorParams { mass: 3.0, stiffness: 12.0, force: 2.0, gap: 0.5, ..reference(2.0) }, 2),
        (OscillatorParams { gap: -0.1, ..reference(2.0) }, 0),
        (OscillatorParams { force: -1.0, ..reference(2.0) }, 1),
    ];
    for (p, count) in cases {
        let got = osc(p).grazing_frequencies();
        // Dense scan of amplitude - g.
        let wn = (p.stiffness / p.mass).sqrt();
        let n = 20000;
        let mut scan = Vec::new();
        if p.gap > 0.0 {
            let f = |w: f64| amplitude(&p, w) - p.gap;
            for i in 0..n {
                let (a, b) = (5.0 * wn * i as f64 / n as f64 + 1e-9, 5.0 * wn * (i + 1) as f64 / n as f64);
                if f(a).signum() != f(b).signum() {
                    let (mut lo, mut hi) = (a, b);
                    for _ in 0..100 {
                        let mid = 0.5 * (lo + hi);
                        if f(mid).signum() == f(lo).signum() {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    scan.push(0.5 * (lo + hi));
                }
            }
        }
        assert_eq!(got.len(), count, "{p:?}: {got:?}");
        assert_eq!(scan.len(), count, "{p:?}: scan {scan:?}");
        for (g, s) in got.iter().zip(&scan) {
            assert_close("grazing Ω", *g, *s, 1e-12 * s);
            assert_close("amplitude at grazing", amplitude(&p, *g), p.gap, 1e-13 * p.gap);
        }
    }
}

#[test]
fn impact_velocity_vanishes_at_grazing() {
    let wg = osc(reference(2.0)).grazing_frequencies()[0];
    // Independent check of the grazing frequency itself.
    assert_close("amplitude", amplitude(&reference(wg), wg), 0.2, 1e-14);
    let mut last = f64::INFINITY;
    for eps in [1e-2, 1e-3, 1e-4, 1e-5] {
        let orbits = osc(reference(wg - eps)).period1_orbits();
        let v = orbits.iter().map(|o| o.impact_velocity).fold(f64::INFINITY, f64::min);
        assert!(v < last && v < 2.0 * eps && v > 0.1 * eps, "Ω = Ωg - {eps}: V = {v}");
        last = v;
        // Beyond grazing the small-V root has V < 0 (no impacting orbit there).
        let beyond = osc(reference(wg + eps)).period1_roots();
        assert!(beyond.iter().all(|o| !o.is_admissible()), "Ω = Ωg + {eps}: {beyond:?}");
        let vneg = beyond.iter().map(|o| o.impact_velocity).fold(f64::NEG_INFINITY, f64::max);
        assert!(vneg < 0.0 && vneg > -2.0 * eps, "Ω = Ωg + {eps}: V = {vneg}");
    }
    // At Ω = Ωg - 1e-3 the tiny-V orbit is periodic under RK4 with impacts.
    let p = reference(wg - 1e-3);
    let o = osc(p).period1_orbits().into_iter().min_by(|a, b| a.impact_velocity.total_cmp(&b.impact_velocity)).unwrap();
    let t = TAU / p.forcing_frequency;
    let (ti, vi) = next_impact(&p, o.impact_time, p.gap, -p.restitution * o.impact_velocity, t / 4000.0, o.impact_time + 2.0 * t);
    assert_close("impact time", ti, o.impact_time + t, 1e-8);
    assert_close("impact velocity", vi, o.impact_velocity, 1e-8);
}

// ---------------------------------------------------------------------------
// (e) Bad input.

#[test]
fn bad_parameters_are_refused_with_the_field_named() {
    let good = reference(1.8);
    assert!(ImpactOscillator::new(good).is_ok());
    type Case = (fn(&mut OscillatorParams, f64), &'static str, &'static [f64]);
    let cases: [Case; 7] = [
        (|p, v| p.mass = v, "mass", &[0.0, -1.0, f64::NAN, f64::INFINITY]),
        (|p, v| p.stiffness = v, "stiffness", &[0.0, -2.0, f64::NAN, f64::INFINITY]),
        (|p, v| p.damping_ratio = v, "damping_ratio", &[-0.1, 1.0, 1.5, f64::NAN]),
        (|p, v| p.force = v, "force", &[f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
        (|p, v| p.forcing_frequency = v, "forcing_frequency", &[0.0, -1.0, f64::NAN, f64::INFINITY]),
        (|p, v| p.gap = v, "gap", &[f64::NAN, f64::INFINITY]),
        (|p, v| p.restitution = v, "restitution", &[-0.01, 1.01, f64::NAN]),
    ];
    for (set, field, values) in cases {
        for &v in values {
            let mut p = good;
            set(&mut p, v);
            let e = ImpactOscillator::new(p).unwrap_err();
            assert_eq!(e.field(), field, "{e}");
            assert!(e.value().to_bits() == v.to_bits(), "{e}");
            let msg = e.to_string();
            assert!(msg.contains(field) && msg.contains(e.allowed()), "{msg}");
        }
    }
    // Exact undamped resonance: no steady state.
    let p = OscillatorParams { mass: 4.0, stiffness: 4.0, damping_ratio: 0.0, forcing_frequency: 1.0, ..good };
    assert_eq!(ImpactOscillator::new(p), Err(OscillatorError::Resonance(1.0)));
    // The ends of the allowed ranges are accepted.
    for p in [
        OscillatorParams { damping_ratio: 0.0, ..good },
        OscillatorParams { restitution: 0.0, ..good },
        OscillatorParams { restitution: 1.0, ..good },
        OscillatorParams { force: 0.0, gap: 0.0, ..good },
        OscillatorParams { damping_ratio: 0.999, ..good },
    ] {
        assert!(ImpactOscillator::new(p).is_ok(), "{p:?}");
    }
}

/// Highest point of the free RK4 motion strictly inside `(τ, τ + T)` from
/// `(g, -rV)`: the largest sample, refined by the parabola through it and
/// its neighbours.
fn rk4_interior_max(p: &OscillatorParams, tau: f64, v: f64) -> f64 {
    let t = TAU / p.forcing_frequency;
    let n = 20000;
    let h = t / n as f64;
    let (mut x, mut u) = (p.gap, -p.restitution * v);
    let mut xs = Vec::with_capacity(n);
    for i in 0..n {
        (x, u) = rk4(p, tau + i as f64 * h, x, u, h, true);
        xs.push(x);
    }
    let mut best = f64::NEG_INFINITY;
    for i in 1..n - 2 {
        let (a, b, c) = (xs[i - 1], xs[i], xs[i + 1]);
        if b >= a && b >= c {
            let den = a - 2.0 * b + c;
            let top = if den < 0.0 { b - (c - a) * (c - a) / (8.0 * den) } else { b };
            best = best.max(top);
        }
    }
    best
}

#[test]
fn a_penetration_between_samples_is_found() {
    // Between Ω = 0.8 (the V > 0 root crosses the stop) and Ω = 0.9
    // (admissible), the interior maximum of that root's motion passes
    // through g. Bisect Ω (RK4 maxima) until it exceeds g by < 1e-7, far
    // less than the gap between the dense samples can show.
    let root = |w: f64| {
        let o = osc(reference(w)).period1_roots().into_iter().find(|o| o.impact_velocity > 0.0).unwrap();
        (o, rk4_interior_max(&reference(w), o.impact_time, o.impact_velocity) - 0.2)
    };
    let (mut lo, mut hi) = (0.8, 0.9);
    assert!(root(lo).1 > 0.0 && root(hi).1 < 0.0);
    let mut excess = root(lo).1;
    while excess > 1e-7 {
        let mid = 0.5 * (lo + hi);
        let e = root(mid).1;
        if e > 0.0 {
            (lo, excess) = (mid, e);
        } else {
            hi = mid;
        }
        assert!(hi - lo > 1e-14, "bisection stalled");
    }
    let (o, e) = root(lo);
    assert!(e > 0.0 && e <= 1e-7);
    assert!(matches!(o.admissibility, Admissibility::Penetrates { height, .. } if height >= 0.2), "Ω = {lo}: RK4 exceeds g by {e:e} but {:?}", o.admissibility);
}

/// A state with `x` and `v` drawn uniformly from the given ranges.
fn random_state(rng: &mut Lcg, x: (f64, f64), v: (f64, f64)) -> State {
    State { x: rng.range(x.0, x.1), v: rng.range(v.0, v.1) }
}
