//! Damping (`Dynamics::damping`) and several forcing terms, checked against
//! what the test computes itself: closed-form recurrences of the schemes'
//! defining equations (characteristic roots), the schemes' equations and
//! energy identities re-evaluated from the recorded displacements with dense
//! matrices built here, the exact solution of the damped forced oscillator,
//! and right-hand sides assembled here term by term.

use crate::common;

use common::*;
use signorini_contact::Active;
use signorini_fem::{BarMass, Beam, SymBand};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Initial, MoreauJean, Nitsche, OneStep, OneStepParams, PaoliSchatzman, Reduced, ReducedLaw, SchemeError, SchemeSpec, Stepper, TimeProfile};

// ---------------------------------------------------------------- 1 dof

/// The 1-dof oscillator `m u'' + c u' + k u = amp sin(Ω t)` with a stop far
/// below (never reached).
fn oscillator(m: f64, c: f64, k: f64, forcing: Option<Sine>) -> Dynamics {
    Dynamics::new(SymBand::from_diagonal(&[m]), SymBand::from_diagonal(&[k]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(-1e6), false)])
        .with_forcing(forcing.map(|s| Forcing { shape: vec![1.0], time: s.profile() }).into_iter().collect())
        .with_damping(Some(SymBand::from_diagonal(&[c])))
}

/// `A^n x` for a real 2×2 `A` with complex characteristic roots `r e^{±iφ}`,
/// in closed form: `A^n = r^{n-1} (sin(nφ)/sin φ · A − r sin((n−1)φ)/sin φ · I)`.
fn power_apply(a: [[f64; 2]; 2], n: usize, x: [f64; 2]) -> [f64; 2] {
    let tr = a[0][0] + a[1][1];
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let disc = tr * tr - 4.0 * det;
    assert!(disc < 0.0, "the test wants complex roots (an underdamped step): trace {tr}, det {det}");
    let r = det.sqrt();
    let phi = (tr / (2.0 * r)).acos();
    let nf = n as f64;
    let (p, q) = if n == 0 { (0.0, 1.0) } else { (r.powi(n as i32 - 1) * (nf * phi).sin() / phi.sin(), -r.powi(n as i32) * ((nf - 1.0) * phi).sin() / phi.sin()) };
    let ax = [a[0][0] * x[0] + a[0][1] * x[1], a[1][0] * x[0] + a[1][1] * x[1]];
    [p * ax[0] + q * x[0], p * ax[1] + q * x[1]]
}

/// The one-step map `(u, v) → (u', v')` of Newmark's defining equations
/// (standard form, not the code's momentum form):
/// `m a' + c v' + k u' = 0`, `u' = u + dt v + dt² (b a + a_n a')`,
/// `v' = v + dt ((1 − γ) a + γ a')`, `a = −(c v + k u)/m`.
fn newmark_map(m: f64, c: f64, k: f64, an: f64, b: f64, g: f64, dt: f64) -> [[f64; 2]; 2] {
    let step = |u: f64, v: f64| {
        let a0 = -(c * v + k * u) / m;
        let a1 = -(c * (v + dt * (1.0 - g) * a0) + k * (u + dt * v + b * dt * dt * a0)) / (m + g * dt * c + an * dt * dt * k);
        (u + dt * v + dt * dt * (b * a0 + an * a1), v + dt * ((1.0 - g) * a0 + g * a1))
    };
    let (e1, e2) = (step(1.0, 0.0), step(0.0, 1.0));
    [[e1.0, e2.0], [e1.1, e2.1]]
}

/// The Moreau–Jean map (no impact): `(m + θ dt c + θ² dt² k) v' = m v − dt k (u + θ(1−θ) dt v) − (1−θ) dt c v`,
/// `u' = u + dt ((1−θ) v + θ v')`.
fn moreau_map(m: f64, c: f64, k: f64, th: f64, dt: f64) -> [[f64; 2]; 2] {
    let step = |u: f64, v: f64| {
        let v1 = (m * v - dt * k * (u + th * (1.0 - th) * dt * v) - (1.0 - th) * dt * c * v) / (m + th * dt * c + th * th * dt * dt * k);
        (u + dt * ((1.0 - th) * v + th * v1), v1)
    };
    let (e1, e2) = (step(1.0, 0.0), step(0.0, 1.0));
    [[e1.0, e2.0], [e1.1, e2.1]]
}

/// Largest `|u_n − want_n| / max|want|` over `steps` steps.
fn compare(s: &mut dyn Stepper, steps: usize, want: impl Fn(usize) -> f64) -> f64 {
    let (mut err, mut scale) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        s.step().unwrap();
        let n = s.level();
        let w = want(n);
        err = err.max((s.displacement()[0] - w).abs());
        scale = scale.max(w.abs());
    }
    err / scale
}

const M1: f64 = 1.3;
const C1: f64 = 0.4;
const K1: f64 = 50.0;

/// (a) The one-step schemes' displacements against `A^n x_0` in closed form
/// (characteristic roots of the 2×2 step map): Newmark-CN, the θ-method with
/// θ = 1 (backward Euler), Newmark(0.3, 0.6), Moreau–Jean θ = 1/2, 0.7.
#[test]
fn one_dof_one_step_schemes_follow_their_recurrence() {
    let (u0, v0, dt, steps) = (0.7, -1.1, 0.02, 1000);
    let init = Initial { u: vec![u0], v: vec![v0] };
    let cases: [(&str, OneStepParams, [[f64; 2]; 2]); 3] = [
        ("newmark-cn", OneStepParams::newmark(0.25, 0.5), newmark_map(M1, C1, K1, 0.25, 0.25, 0.5, dt)),
        ("theta(1)", OneStepParams::theta(1.0), newmark_map(M1, C1, K1, 1.0, 0.0, 1.0, dt)),
        ("newmark(0.3,0.6)", OneStepParams::newmark(0.3, 0.6), newmark_map(M1, C1, K1, 0.3, 0.2, 0.6, dt)),
    ];
    for (name, prm, a) in cases {
        let mut s = OneStep::new(name.into(), oscillator(M1, C1, K1, None), prm, dt, &init).unwrap();
        let err = compare(&mut s, steps, |n| power_apply(a, n, [u0, v0])[0]);
        println!("{name}: relative error vs the closed-form recurrence {err:.2e}");
        assert!(err < 1e-12, "{name}: {err:e}");
    }
    for th in [0.5, 0.7] {
        let a = moreau_map(M1, C1, K1, th, dt);
        let mut s = MoreauJean::new("mj".into(), oscillator(M1, C1, K1, None), th, 0.0, 0.5, dt, &init).unwrap();
        let err = compare(&mut s, steps, |n| power_apply(a, n, [u0, v0])[0]);
        println!("moreau-jean({th}): relative error vs the closed-form recurrence {err:.2e}");
        assert!(err < 1e-12, "moreau-jean({th}): {err:e}");
    }
}

/// (a) Paoli–Schatzman β = 0 and 1/4: `(m + c dt/2 + β dt² k) z² − (2m − (1−2β) dt² k) z + (m − c dt/2 + β dt² k) = 0`
/// has roots `r e^{±iφ}`, so `u_n = r^n (u_0 cos nφ + Q sin nφ)` with `Q`
/// from `u_1`, which is the start step's (Newmark(β, 1/2), or (1/4, 1/2) at β = 0,
/// computed here by [`newmark_map`]).
#[test]
fn one_dof_paoli_schatzman_follows_its_recurrence() {
    let (u0, v0, dt, steps) = (0.7, -1.1, 0.02, 1000);
    let init = Initial { u: vec![u0], v: vec![v0] };
    for beta in [0.0, 0.25, 0.4] {
        let sb = if beta > 0.0 { beta } else { 0.25 };
        let u1 = power_apply(newmark_map(M1, C1, K1, sb, 0.5 - sb, 0.5, dt), 1, [u0, v0])[0];
        let (a2, a1, a0) = (M1 + 0.5 * C1 * dt + beta * dt * dt * K1, -(2.0 * M1 - (1.0 - 2.0 * beta) * dt * dt * K1), M1 - 0.5 * C1 * dt + beta * dt * dt * K1);
        let r = (a0 / a2).sqrt();
        let phi = (-a1 / (2.0 * a2 * r)).acos();
        let q = (u1 / r - u0 * phi.cos()) / phi.sin();
        let want = |n: usize| r.powi(n as i32) * (u0 * (n as f64 * phi).cos() + q * (n as f64 * phi).sin());
        let spec = SchemeSpec::ps(0.0, beta);
        let mut s = spec.build(oscillator(M1, C1, K1, None), dt, &init).unwrap();
        assert_eq!(s.level(), 1);
        assert!((s.displacement()[0] - u1).abs() <= 1e-14, "start step");
        let err = compare(s.as_mut(), steps, want);
        println!("ps(0,{beta}): relative error vs the closed-form recurrence {err:.2e}");
        assert!(err < 1e-12, "ps β = {beta}: {err:e}");
    }
}

/// (c) The damped forced oscillator's exact solution: particular
/// `P sin Ωt + Q cos Ωt` plus the free decay `e^{−ζωt}(A cos ω_d t + B sin ω_d t)`;
/// the largest nodal error over `[0, 4]` falls by 4 per halving of dt
/// (observed rates within [1.95, 2.05]) for Newmark-CN (load `F(t_{n+1})`),
/// at first order for θ = 1 ([0.95, 1.05] on the two finest pairs) and for PS β = 1/4 whose
/// time-averaged load `Gⁿ` is centred at `t_{n+½}` (docs/theory.md §4.3:
/// first order with a time-dependent load by design; [0.9, 1.1] on the finest
/// pairs). PS β = 1/4 with a steady load `F` (exact solution `F/k` plus the
/// free decay) is second order ([1.95, 2.05]), and so is Moreau–Jean θ = 1/2
/// with the sine load (its exact impulse per step).
#[test]
fn damped_forced_oscillator_converges_at_the_schemes_order() {
    let (m, c, k, f, om): (f64, f64, f64, f64, f64) = (1.3, 0.9, 50.0, 2.5, 4.0);
    let (u0, v0, t_end) = (0.3, -0.5, 4.0);
    // Particular solution.
    let (kk, co) = (k - m * om * om, c * om);
    let det = kk * kk + co * co;
    let (p, q) = (f * kk / det, -f * co / det);
    // Free decay with u(0) = u0 - q, u'(0) = v0 - p Ω.
    let w0 = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let a = u0 - q;
    let b = (v0 - p * om + zeta * w0 * a) / wd;
    let exact = |t: f64| p * (om * t).sin() + q * (om * t).cos() + (-zeta * w0 * t).exp() * (a * (wd * t).cos() + b * (wd * t).sin());
    let init = Initial { u: vec![u0], v: vec![v0] };
    let sine = Sine { amp: f, omega: om };
    // The steady load F: u = F/k + e^{−ζωt}(A' cos ω_d t + B' sin ω_d t).
    let a_s = u0 - f / k;
    let b_s = (v0 + zeta * w0 * a_s) / wd;
    let exact_steady = |t: f64| f / k + (-zeta * w0 * t).exp() * (a_s * (wd * t).cos() + b_s * (wd * t).sin());
    let ps = SchemeSpec::ps(0.0, 0.25);
    let cases: [(SchemeSpec, bool, f64, f64, usize); 5] = [
        (SchemeSpec::newmark(0.25, 0.5), true, 1.95, 2.05, 0),
        (SchemeSpec::theta(1.0), true, 0.95, 1.05, 2),
        (ps, true, 0.9, 1.1, 1),
        (ps, false, 1.95, 2.05, 0),
        (SchemeSpec::moreau_jean(0.5, 0.0), true, 1.95, 2.05, 0),
    ];
    for (spec, forced, lo, hi, skip) in cases {
        let mut errs = Vec::new();
        for steps in [400usize, 800, 1600, 3200, 6400] {
            let dt = t_end / steps as f64;
            let mut dy = oscillator(m, c, k, forced.then_some(sine));
            if !forced {
                dy.load = vec![f];
            }
            let mut s = spec.build(dy, dt, &init).unwrap();
            let mut err = 0.0f64;
            while s.level() < steps {
                s.step().unwrap();
                let t = s.level() as f64 * dt;
                err = err.max((s.displacement()[0] - if forced { exact(t) } else { exact_steady(t) }).abs());
            }
            errs.push(err);
        }
        let rates: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        println!("{spec} ({}): errors {errs:.3?}, rates {rates:.3?}", if forced { "sine load" } else { "steady load" });
        for r in &rates[skip..] {
            assert!((lo..=hi).contains(r), "{spec}: rate {r} outside [{lo}, {hi}] (errors {errs:?})");
        }
    }
}

// ---------------------------------------------------------------- bars with contacts

/// Rayleigh damping `C = α M + β_K K` for a scene: the band (from the
/// scene's own `M`, `K`) and the dense oracle copy.
fn rayleigh(dy: &mut Dynamics, o: &Oracle, alpha: f64, beta_k: f64) -> Dense {
    dy.damping = Some(dy.mass.lin_comb(alpha, &dy.stiffness, beta_k));
    (0..o.n()).map(|i| (0..o.n()).map(|j| alpha * o.m[i][j] + beta_k * o.k[i][j]).collect()).collect()
}

/// What the checkers measured.
#[derive(Debug, Default)]
struct Balance {
    residual: Worst,
    energy: Worst,
    wf: f64,
    wc: f64,
    d: f64,
}

/// Newmark-CN with damping, from the trajectory alone (massive dofs only):
/// `V^{n+1} = 2ΔU/dt − V^n`, the momentum equation
/// `M (V^{n+1} − V^n) = dt/2 (R^n + R^{n+1})` with `R = F(t) − K U − C V − Σ λ_i e_{c_i}`
/// (`λ^0 = 0`), and `E^n − E^0 = W_f + W_c − D` with
/// `E = ½ VᵀMV + ½ UᵀKU − F_sᵀU`, `W_f = Σ ½ (F_t^n + F_t^{n+1})ᵀΔU`,
/// `W_c = −Σ ½ (C^n + C^{n+1})ᵀΔU`, `D = Σ dt V̄ᵀ C V̄`, `V̄ = ΔU/dt`.
fn check_cn(o: &Oracle, c: &Dense, timed: &dyn Fn(f64) -> Vec<f64>, init: &Initial, traj: &Traj, tol: f64) -> Balance {
    let dt = traj.dt;
    let n = o.n();
    let forces = traj.all_forces(0);
    let fvec = |l: usize| if l == 0 { vec![0.0; n] } else { o.force_vector(forces[l].as_ref().unwrap()) };
    let energy = |u: &[f64], v: &[f64]| 0.5 * quad(&o.m, v) + 0.5 * quad(&o.k, u) - dot(&o.load, u);
    let r = |l: usize, v: &[f64]| -> Vec<f64> {
        let (ft, ku, cv, fc) = (timed(l as f64 * dt), mul(&o.k, traj.at(l)), mul(c, v), fvec(l));
        (0..n).map(|i| o.load[i] + ft[i] - ku[i] - cv[i] - fc[i]).collect()
    };
    let (nm, nk, nc) = (norm_inf(&o.m), norm_inf(&o.k), norm_inf(c));
    let mut b = Balance::default();
    let mut v = init.v.clone();
    let e0 = energy(traj.at(0), &v);
    for l in 0..traj.last() {
        let (u0, u1) = (traj.at(l), traj.at(l + 1));
        let du = sub(u1, u0);
        let v1: Vec<f64> = (0..n).map(|i| 2.0 * du[i] / dt - v[i]).collect();
        let (r0, r1) = (r(l, &v), r(l + 1, &v1));
        let lhs = mul(&o.m, &sub(&v1, &v));
        let res: Vec<f64> = (0..n).map(|i| lhs[i] - 0.5 * dt * (r0[i] + r1[i])).collect();
        let scale = nm * (max_abs(&v) + max_abs(&v1)) + dt * (max_abs(&r0) + max_abs(&r1) + nk * max_abs(u1) + nc * max_abs(&v1));
        b.residual.check(&format!("CN momentum residual at step {l}"), max_abs(&res), scale, tol);
        let (ft0, ft1) = (timed(l as f64 * dt), timed((l + 1) as f64 * dt));
        b.wf += 0.5 * dot(&du, &lin(&[(1.0, &ft0), (1.0, &ft1)]));
        b.wc -= 0.5 * dot(&du, &lin(&[(1.0, &fvec(l)), (1.0, &fvec(l + 1))]));
        b.d += quad(c, &du) / dt;
        let e1 = energy(u1, &v1);
        let scale = e0.abs().max(e1.abs()).max(b.wf.abs()).max(b.wc.abs()).max(b.d).max(nm * max_abs(&v1).powi(2)).max(nk * max_abs(u1).powi(2));
        b.energy.check(&format!("CN balance at step {l}→{}", l + 1), (e1 - e0) - (b.wf + b.wc - b.d), scale, tol);
        v = v1;
    }
    b
}

/// Paoli–Schatzman with damping (massive contact nodes, forces at `t_n`):
/// `M (U^{n+1} − 2U^n + U^{n−1})/dt² + C (U^{n+1} − U^{n−1})/(2dt) + K (β U^{n+1} + (1−2β) U^n + β U^{n−1}) = F_s + G^n − Σ λ_i^n e_{c_i}`
/// with `G^n = β g^{n+1} + (1−2β) g^n + β g^{n−1}` from the exact means
/// `g^k = mean(t_k, t_{k+1})` of the timed load, and
/// `E^{n+1/2} − E^{1/2} = W_f + W_c − D`.
fn check_ps(o: &Oracle, c: &Dense, beta: f64, mean: &dyn Fn(f64, f64) -> Vec<f64>, init: &Initial, traj: &Traj, tol: f64) -> Balance {
    let dt = traj.dt;
    let n = o.n();
    let forces = traj.all_forces(1);
    let g = |l: usize| mean(l as f64 * dt, (l + 1) as f64 * dt);
    let energy = |u0: &[f64], u1: &[f64]| {
        let v: Vec<f64> = (0..n).map(|i| (u1[i] - u0[i]) / dt).collect();
        let ub: Vec<f64> = (0..n).map(|i| 0.5 * (u0[i] + u1[i])).collect();
        0.5 * quad(&o.m, &v) + 0.5 * (beta - 0.25) * dt * dt * quad(&o.k, &v) + 0.5 * quad(&o.k, &ub) - dot(&o.load, &ub)
    };
    let (nm, nk, nc) = (norm_inf(&o.m), norm_inf(&o.k), norm_inf(c));
    let mut b = Balance::default();
    assert_eq!(traj.first, 1, "PS starts at level 1");
    let at = |l: usize| if l == 0 { &init.u[..] } else { traj.at(l) };
    let e0 = energy(at(0), at(1));
    for l in 1..traj.last() {
        let (um, u, up) = (at(l - 1), at(l), at(l + 1));
        let gn = lin(&[(beta, &g(l + 1)), (1.0 - 2.0 * beta, &g(l)), (beta, &g(l - 1))]);
        let fc = o.force_vector(forces[l].as_ref().unwrap());
        let acc = mul(&o.m, &lin(&[(1.0 / (dt * dt), up), (-2.0 / (dt * dt), u), (1.0 / (dt * dt), um)]));
        let damp = mul(c, &lin(&[(0.5 / dt, up), (-0.5 / dt, um)]));
        let kav = mul(&o.k, &lin(&[(beta, up), (1.0 - 2.0 * beta, u), (beta, um)]));
        let res: Vec<f64> = (0..n).map(|i| acc[i] + damp[i] + kav[i] - o.load[i] - gn[i] + fc[i]).collect();
        let scale = nm * (max_abs(up) + max_abs(u) + max_abs(um)) / (dt * dt) + nc * (max_abs(up) + max_abs(um)) / dt + nk * max_abs(u) + max_abs(&gn) + max_abs(&fc) + max_abs(&o.load);
        b.residual.check(&format!("PS residual at level {l}"), max_abs(&res), scale, tol);
        let d2 = sub(up, um);
        b.wf += 0.5 * dot(&gn, &d2);
        b.wc -= 0.5 * dot(&fc, &d2);
        b.d += quad(c, &d2) / (4.0 * dt);
        let e1 = energy(u, up);
        let scale = e0.abs().max(e1.abs()).max(b.wf.abs()).max(b.wc.abs()).max(b.d).max(nm * (max_abs(&d2) / dt).powi(2)).max(nk * max_abs(up).powi(2));
        b.energy.check(&format!("PS balance at level {l}"), (e1 - e0) - (b.wf + b.wc - b.d), scale, tol);
    }
    b
}

fn bar_forcing(n: usize) -> (Vec<f64>, Sine) {
    let h = 1.0 / 20.0;
    ((0..n).map(|i| h * (1.0 + 0.5 * (i as f64 * 0.4).sin())).collect(), Sine { amp: 3.0, omega: 9.0 })
}

/// The code's reported work and dissipation against the test's.
fn assert_reports(name: &str, s: &dyn Stepper, b: &Balance) {
    let (wf, wc) = s.work().expect("the scheme reports its work");
    let d = s.dissipation().expect("the scheme reports its dissipation");
    let scale = b.wf.abs().max(b.wc.abs()).max(b.d).max(1e-12);
    for (what, got, want) in [("W_f", wf, b.wf), ("W_c", wc, b.wc), ("D", d, b.d)] {
        assert!((got - want).abs() <= 1e-10 * scale, "{name}: reported {what} = {got:e}, the test's {want:e}");
    }
    assert!(b.d > 0.0 && b.wc.abs() > 0.0, "{name}: the damping and the contact must both work (D = {:e}, W_c = {:e})", b.d, b.wc);
}

/// (b) The discrete energy balance with Rayleigh damping `C = α M + β_K K`
/// on the P1 bar (std mass, massive contact node), one obstacle and several
/// stops, a forcing, the contacts active: Newmark-CN and Paoli–Schatzman
/// (β = 1/4 and 0.3, e = 0 and 1/2): the schemes' equations hold to
/// round-off, `ΔE = W_f + W_c − D` to round-off, and the reported
/// `work()`/`dissipation()` are the test's.
#[test]
fn damped_energy_balance_with_contacts() {
    let m = 20;
    let single = |free: bool| bar_scene(m, BarMass::Std, free, -0.05, -0.5, Some(bar_forcing(if free { m + 1 } else { m })));
    let stops = [OStop::new(0, -0.02, f64::INFINITY), OStop::new(8, -0.006, 0.004), OStop::new(14, -0.01, 0.008)];
    let several = || {
        let n = m + 1;
        bar_stops_scene(m, BarMass::Std, true, &stops, -0.5, Some(bar_forcing(n)))
    };
    let scenes: Vec<(&str, Dynamics, Oracle)> = {
        let (d1, o1) = single(false);
        let (d2, o2) = several();
        vec![("one obstacle", d1, o1), ("three stops", d2, o2)]
    };
    for (sname, mut dy, o) in scenes {
        let c = rayleigh(&mut dy, &o, 0.8, 2e-3);
        let n = o.n();
        let init = Initial { u: vec![0.0; n], v: (0..n).map(|i| -0.8 + 0.2 * (i as f64 * 0.3).sin()).collect() };
        let (shape, sine) = o.forcing.clone().unwrap();
        let timed = |t: f64| shape.iter().map(|g| g * sine.at(t)).collect::<Vec<f64>>();
        let mean = |t0: f64, t1: f64| shape.iter().map(|g| g * sine.mean(t0, t1)).collect::<Vec<f64>>();
        let dt = 0.01;
        let steps = 150;
        // Newmark-CN.
        let mut s = SchemeSpec::newmark(0.25, 0.5).build(dy.clone(), dt, &init).unwrap();
        let traj = record(s.as_mut(), steps);
        assert!(traj.active_steps() > 5, "{sname}: contact must be active");
        let b = check_cn(&o, &c, &timed, &init, &traj, 1e-11);
        println!("{sname} newmark-cn: residual {:.1e}, balance {:.1e}, W_f {:.4e}, W_c {:.4e}, D {:.4e}", b.residual.ratio, b.energy.ratio, b.wf, b.wc, b.d);
        assert_reports(&format!("{sname} newmark-cn"), s.as_ref(), &b);
        // Paoli–Schatzman.
        for (beta, e) in [(0.25, 0.0), (0.3, 0.5)] {
            let mut s = SchemeSpec::ps(e, beta).build(dy.clone(), dt, &init).unwrap();
            let traj = record(s.as_mut(), steps);
            assert!(traj.active_steps() > 5, "{sname}: contact must be active");
            let b = check_ps(&o, &c, beta, &mean, &init, &traj, 1e-11);
            println!("{sname} ps({e},{beta}): residual {:.1e}, balance {:.1e}, W_f {:.4e}, W_c {:.4e}, D {:.4e}", b.residual.ratio, b.energy.ratio, b.wf, b.wc, b.d);
            assert_reports(&format!("{sname} ps({e},{beta})"), s.as_ref(), &b);
        }
    }
}

/// Moreau–Jean with damping, a forcing and several stops: its velocity-level equation
/// `M (V^{n+1} − V^n) + dt K (U^n + U^{n+1})/2 + dt C (V^n + V^{n+1})/2 = dt F_s + ∫_{t_n}^{t_{n+1}} F_t + Σ p_i e_{c_i}`
/// (θ = 1/2, velocities rebuilt from the displacements, the forcing's
/// integral from the antiderivative) holds to round-off.
#[test]
fn moreau_jean_damped_momentum_equation() {
    let m = 20;
    let stops = [OStop::new(0, -0.02, f64::INFINITY), OStop::new(8, -0.006, 0.004)];
    let (mut dy, o) = bar_stops_scene(m, BarMass::Lumped, true, &stops, -0.5, Some(bar_forcing(m + 1)));
    let (shape, sine) = o.forcing.clone().unwrap();
    let c = rayleigh(&mut dy, &o, 0.8, 2e-3);
    let n = o.n();
    let init = Initial { u: vec![0.0; n], v: (0..n).map(|i| -0.8 + 0.2 * (i as f64 * 0.3).sin()).collect() };
    let dt = 0.01;
    let mut s = SchemeSpec::moreau_jean(0.5, 0.3).build(dy, dt, &init).unwrap();
    let traj = record(s.as_mut(), 150);
    let forces = traj.all_forces(0);
    let mut v = init.v.clone();
    let mut w = Worst::default();
    let mut impulses = 0;
    for l in 0..traj.last() {
        let (u0, u1) = (traj.at(l), traj.at(l + 1));
        let v1: Vec<f64> = (0..n).map(|i| 2.0 * (u1[i] - u0[i]) / dt - v[i]).collect();
        let p: Vec<f64> = forces[l + 1].as_ref().unwrap().iter().map(|lam| -lam * dt).collect();
        impulses += p.iter().filter(|x| **x != 0.0).count();
        let mdv = mul(&o.m, &sub(&v1, &v));
        let kmid = mul(&o.k, &lin(&[(0.5, u0), (0.5, u1)]));
        let cmid = mul(&c, &lin(&[(0.5, &v), (0.5, &v1)]));
        let pv = o.force_vector(&p);
        let mean = sine.mean(l as f64 * dt, (l + 1) as f64 * dt);
        let res: Vec<f64> = (0..n).map(|i| mdv[i] + dt * (kmid[i] + cmid[i] - o.load[i] - shape[i] * mean) - pv[i]).collect();
        let scale = norm_inf(&o.m) * (max_abs(&v1) + max_abs(&v)) + dt * (norm_inf(&o.k) * max_abs(u1) + norm_inf(&c) * max_abs(&v1) + max_abs(&o.load)) + max_abs(&p);
        w.check(&format!("MJ residual at step {l}"), max_abs(&res), scale, 1e-11);
        v = v1;
    }
    println!("moreau-jean damped: residual {:.1e}, {impulses} impulses", w.ratio);
    assert!(impulses > 3);
}

// ---------------------------------------------------------------- refusals

/// (d) Damping is refused with a typed error where it cannot be taken, and
/// bad damping matrices or forcing terms are refused by validation.
#[test]
fn damping_refusals_are_typed() {
    let m = 10;
    let (dy_mod, o_mod) = bar_scene(m, BarMass::Mod, false, -0.05, -0.5, None);
    let n = o_mod.n();
    let init = Initial { u: vec![0.0; n], v: vec![-0.5; n] };
    // A damping matrix with a zero contact row (allowed for a massless node).
    let mut c_massless = dy_mod.stiffness.lin_comb(1e-3, &dy_mod.stiffness, 0.0);
    c_massless.zero_row_col(0);
    let mut dy = dy_mod.clone();
    dy.damping = Some(c_massless.clone());
    for spec in ["hybrid", "reduced-cn", "cd-massless"] {
        let e = spec.parse::<SchemeSpec>().unwrap().build(dy.clone(), 1e-3, &init).err().expect("refused");
        assert!(matches!(&e, SchemeError::NotTaken { what: "damping matrix", .. }), "{spec}: {e}");
    }
    // The constructors refuse it too (not only SchemeSpec::build).
    let e = Reduced::new("hybrid".into(), dy.clone(), ReducedLaw::Hybrid, 1e-3, &init).err().expect("refused");
    assert!(matches!(&e, SchemeError::NotTaken { what: "damping matrix", .. }), "Reduced::new: {e}");
    // ... while the momentum-form schemes take it.
    for spec in ["newmark-cn", "backward-euler", "ps-e0", "penalty-cn"] {
        let mut s = spec.parse::<SchemeSpec>().unwrap().build(dy.clone(), 1e-2, &init).unwrap_or_else(|e| panic!("{spec}: {e}"));
        let traj = record(s.as_mut(), 100);
        assert!(traj.active_steps() > 0 && traj.u.iter().flatten().all(|x| x.is_finite()), "{spec}: the massless node must meet the obstacle, finitely");
    }
    let (dy_std, o_std) = bar_scene(m, BarMass::Std, false, -0.05, -0.5, None);
    let mut dy = dy_std.clone();
    dy.damping = Some(dy_std.stiffness.lin_comb(1e-3, &dy_std.stiffness, 0.0));
    let init = Initial { u: vec![0.0; o_std.n()], v: vec![-0.5; o_std.n()] };
    for spec in ["nitsche-cn", "penalty-cd"] {
        let e = spec.parse::<SchemeSpec>().unwrap().build(dy.clone(), 1e-5, &init).err().expect("refused");
        assert!(matches!(&e, SchemeError::NotTaken { what: "damping matrix", .. }), "{spec}: {e}");
    }
    let e = Nitsche::new("nitsche".into(), dy.clone(), 0.25, 0.5, 10.0, 1.0, 1e-3, &init).err().expect("refused");
    assert!(matches!(&e, SchemeError::NotTaken { what: "damping matrix", .. }), "Nitsche::new: {e}");
    let e = OneStep::new("cd".into(), dy.clone(), OneStepParams::newmark(0.0, 0.5), 1e-5, &init).err().expect("refused");
    assert!(matches!(&e, SchemeError::NotTaken { what: "damping matrix", .. }), "{e}");
    for spec in ["moreau-jean", "ps(0,0)", "theta(0.7)"] {
        spec.parse::<SchemeSpec>().unwrap().build(dy.clone(), 1e-4, &init).unwrap_or_else(|e| panic!("{spec}: {e}"));
    }
    // Validation.
    let bad = |c: SymBand| {
        let mut d = dy_std.clone();
        d.damping = Some(c);
        d.validate().expect_err("invalid damping")
    };
    assert!(matches!(bad(SymBand::zeros(n + 1, 1)), SchemeError::Size { what: "damping matrix", got, expected } if got == n + 1 && expected == n));
    assert!(matches!(bad(SymBand::zeros(n, 2)), SchemeError::Size { got: 2, expected: 1, .. }));
    let mut c = SymBand::zeros(n, 1);
    c.set(3, 2, f64::NAN);
    assert!(matches!(bad(c), SchemeError::Invalid { field: "damping entry", .. }));
    let mut c = SymBand::zeros(n, 1);
    c.set(4, 4, -1.0);
    assert!(matches!(bad(c), SchemeError::Invalid { field: "damping diagonal", value, .. } if value == -1.0));
    let mut d = dy_mod.clone();
    d.damping = Some(dy_mod.stiffness.lin_comb(1e-3, &dy_mod.stiffness, 0.0));
    assert!(matches!(d.validate(), Err(SchemeError::Structure(msg)) if msg.contains("massless")));
    // A narrower band is widened: a diagonal C on the tridiagonal bar.
    let mut d = dy_std.clone();
    let mut c = SymBand::zeros(n, 0);
    (0..n).for_each(|i| c.set(i, i, 0.3));
    d.damping = Some(c);
    SchemeSpec::newmark(0.25, 0.5).build(d, 1e-3, &init).unwrap();
    // Forcing terms: every shape is checked; the steady-load schemes refuse any.
    let mut d = dy_std.clone();
    d.forcing =
        vec![Forcing { shape: vec![0.0; n], time: TimeProfile::Sine { amplitude: 1.0, omega: 1.0 } }, Forcing { shape: vec![0.0; n - 1], time: TimeProfile::Sine { amplitude: 1.0, omega: 1.0 } }];
    assert!(matches!(d.validate(), Err(SchemeError::Size { what: "forcing shape", got, .. }) if got == n - 1));
    d.forcing.pop();
    let e = SchemeSpec::nitsche(10.0, 1.0).build(d.clone(), 1e-3, &init).err().expect("refused");
    assert!(matches!(&e, SchemeError::NotTaken { what: "time-dependent load", .. }), "{e}");
    SchemeSpec::moreau_jean(0.5, 0.0).build(d, 1e-3, &init).expect("Moreau–Jean takes a forcing");
}

// ---------------------------------------------------------------- several forcing terms

/// (e) Two terms with the same profile equal one term whose shape is their
/// sum (to round-off: 1e-10 of max|U| after 200 steps with contact; measured
/// 1.3e-11 for Newmark-CN, 1e-14 for PS and penalty-cn), and so does W_f.
#[test]
fn two_terms_with_one_profile_equal_their_sum() {
    let m = 20;
    let n = m;
    let g1: Vec<f64> = (0..n).map(|i| 0.05 * (1.0 + (i as f64 * 0.5).sin())).collect();
    let g2: Vec<f64> = (0..n).map(|i| -0.03 * (i as f64 * 0.2).cos()).collect();
    let sum: Vec<f64> = g1.iter().zip(&g2).map(|(a, b)| a + b).collect();
    let s = Sine { amp: 4.0, omega: 7.0 };
    let (base, _) = bar_scene(m, BarMass::Std, false, -0.03, -0.5, None);
    let init = Initial { u: vec![0.0; n], v: vec![-0.6; n] };
    let term = |g: &Vec<f64>| Forcing { shape: g.clone(), time: s.profile() };
    // (θ = 0.6 is left out: in persistent contact it amplifies a round-off
    // perturbation of the load to 1e-6 of max|U| within 100 steps.)
    for spec in ["newmark-cn", "ps-e0.5", "penalty-cn"] {
        let spec: SchemeSpec = spec.parse().unwrap();
        let (mut one, mut two) = (base.clone(), base.clone());
        one.forcing = vec![term(&sum)];
        two.forcing = vec![term(&g1), term(&g2)];
        let (mut a, mut b) = (spec.build(one, 0.01, &init).unwrap(), spec.build(two, 0.01, &init).unwrap());
        let (ta, tb) = (record(a.as_mut(), 200), record(b.as_mut(), 200));
        let scale = ta.u.iter().map(|u| max_abs(u)).fold(0.0, f64::max);
        let err = ta.u.iter().zip(&tb.u).map(|(x, y)| max_abs(&sub(x, y))).fold(0.0, f64::max);
        let (wa, wb) = (a.work().unwrap(), b.work().unwrap());
        println!("{spec}: one term vs two: {:.1e} of max|U|; W_f {:e} vs {:e}", err / scale, wa.0, wb.0);
        assert!(err <= 1e-10 * scale, "{spec}: {err:e}");
        assert!((wa.0 - wb.0).abs() <= 1e-10 * wa.0.abs(), "{spec}: W_f {} vs {}", wa.0, wb.0);
    }
}

/// (e) A beam-like support motion with two terms, `−h φ''(t)` and
/// `−k² h'''' φ(t)`-like: two shapes, two profiles of different frequencies
/// on the Hermite beam between stops, with damping; the test assembles
/// `F(t) = Σ_j shape_j s_j(t)` (and its exact means) itself and checks the
/// schemes' equations, balances and reported work (Newmark-CN, PS β = 1/4).
#[test]
fn two_term_beam_forcing_against_an_assembled_load() {
    let (j, k2) = (10, 3.0);
    let beam = Beam::new(1.0, j, k2).unwrap();
    let h1 = beam.load(|x| x * x * (3.0 - 2.0 * x));
    let h2 = beam.load(|_| 12.0);
    let (s1, s2) = (Sine { amp: -8.0, omega: 12.0 }, Sine { amp: 0.5, omega: 5.0 });
    let (mut dy, o) = beam_scene(j, k2, -0.004, 0.003, h1.clone(), s1);
    dy.forcing.push(Forcing { shape: h2.clone(), time: s2.profile() });
    let c = rayleigh(&mut dy, &o, 0.5, 1e-4);
    let n = o.n();
    let timed = |t: f64| (0..n).map(|i| h1[i] * s1.at(t) + h2[i] * s2.at(t)).collect::<Vec<f64>>();
    let mean = |t0: f64, t1: f64| (0..n).map(|i| h1[i] * s1.mean(t0, t1) + h2[i] * s2.mean(t0, t1)).collect::<Vec<f64>>();
    let init = Initial { u: vec![0.0; n], v: vec![0.0; n] };
    let dt = 2e-3;
    let mut s = SchemeSpec::newmark(0.25, 0.5).build(dy.clone(), dt, &init).unwrap();
    let traj = record(s.as_mut(), 400);
    assert!(traj.reports.iter().any(|r| r.active == Active::Lower) && traj.reports.iter().any(|r| r.active == Active::Upper), "both stops must be hit");
    let b = check_cn(&o, &c, &timed, &init, &traj, 1e-11);
    println!("beam newmark-cn, two terms: residual {:.1e}, balance {:.1e}, W_f {:.4e}, W_c {:.4e}, D {:.4e}", b.residual.ratio, b.energy.ratio, b.wf, b.wc, b.d);
    assert_reports("beam newmark-cn", s.as_ref(), &b);
    let mut s = SchemeSpec::ps(0.0, 0.25).build(dy, dt, &init).unwrap();
    let traj = record(s.as_mut(), 400);
    let b = check_ps(&o, &c, 0.25, &mean, &init, &traj, 1e-11);
    println!("beam ps, two terms: residual {:.1e}, balance {:.1e}, W_f {:.4e}, W_c {:.4e}, D {:.4e}", b.residual.ratio, b.energy.ratio, b.wf, b.wc, b.d);
    assert_reports("beam ps", s.as_ref(), &b);
}

/// Without damping the reported dissipation stays exactly 0 (nothing is
/// accumulated on the undamped path).
#[test]
fn undamped_dissipation_is_zero() {
    let (dy, o) = bar_scene(10, BarMass::Std, false, -0.05, -0.5, None);
    let init = Initial { u: vec![0.0; o.n()], v: vec![-0.5; o.n()] };
    let mut s = PaoliSchatzman::new("ps".into(), dy, 0.25, 0.0, 0.01, &init).unwrap();
    s.step().unwrap();
    assert_eq!(s.dissipation(), Some(0.0));
}
