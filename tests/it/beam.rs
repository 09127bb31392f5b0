//! The beam between two stops: exact constraint, discrete energy balance
//! recomputed from the trajectory (support load and works summed here), the
//! lifted data, penalty law, and the paper's first impact.

use proptest::prelude::*;
use signorini::fem::SymBand;
use signorini::run::beam::{BeamScene, BeamSetup, BuiltBeam, Pipe};
use signorini::schemes::{Bounds, ContactLaw, Forcing, OneStep, OneStepParams, PaoliSchatzman, SchemeSpec, Stepper, TimeProfile};

fn scene(dt: f64, t_end: f64, scheme: SchemeSpec) -> BeamScene {
    BeamScene::new("test", 19, dt, t_end, scheme)
}

/// The lifting `h(x) = 1 - 2y² + (4/3)y³ - (1/3)y⁴`, `y = x/L`, and `h'`
/// (docs/theory.md §1.2), written out here.
fn lifting(x: f64, l: f64) -> (f64, f64) {
    let y = x / l;
    (1.0 - 2.0 * y * y + 4.0 / 3.0 * y.powi(3) - y.powi(4) / 3.0, (-4.0 * y + 4.0 * y * y - 4.0 / 3.0 * y.powi(3)) / l)
}

/// The support load's shape `S_i = ∫ (A ω² h(x) + 8 A k²/L⁴) φ_i dx` over
/// the Hermite basis (unknown `2(j-1)` the value at node `j`, `2(j-1)+1` its
/// slope), by 5-point Gauss–Legendre per element (exact: degree 4 + 3).
fn support_shape(pipe: &Pipe, j_elems: usize) -> Vec<f64> {
    const X: [f64; 5] = [0.0, -0.538_469_310_105_683_1, 0.538_469_310_105_683_1, -0.906_179_845_938_664, 0.906_179_845_938_664];
    const W: [f64; 5] = [128.0 / 225.0, 0.478_628_670_499_366_5, 0.478_628_670_499_366_5, 0.236_926_885_056_189_1, 0.236_926_885_056_189_1];
    let (l, (a, w)) = (pipe.length, pipe.support);
    let h = l / j_elems as f64;
    let f = |x: f64| a * w * w * lifting(x, l).0 + 8.0 * a * pipe.k2 / l.powi(4);
    let mut out = vec![0.0; 2 * j_elems];
    for e in 0..j_elems {
        for (xi, wi) in X.iter().zip(&W) {
            let s = 0.5 * (xi + 1.0);
            let (s2, s3) = (s * s, s * s * s);
            let phi = [1.0 - 3.0 * s2 + 2.0 * s3, h * (s - 2.0 * s2 + s3), 3.0 * s2 - 2.0 * s3, h * (s3 - s2)];
            let fx = f((e as f64 + s) * h) * wi * 0.5 * h;
            for (k, p) in phi.iter().enumerate() {
                let node = e + k / 2;
                if node >= 1 {
                    out[2 * (node - 1) + k % 2] += fx * p;
                }
            }
        }
    }
    out
}

/// `1/dt ∫_{t0}^{t0+dt} sin(ω t) dt = (cos ω t0 - cos ω t1)/(ω dt)`, written
/// as `2 sin(ω t_mid) sin(ω dt/2)/(ω dt)` (no cancellation).
fn sine_mean(omega: f64, t0: f64, dt: f64) -> f64 {
    2.0 * (omega * (t0 + 0.5 * dt)).sin() * (0.5 * omega * dt).sin() / (omega * dt)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `E^{n+1/2}` of docs/theory.md §4.3 from two consecutive levels (no steady load).
fn half_step_energy(m: &SymBand, k: &SymBand, beta: f64, dt: f64, u0: &[f64], u1: &[f64]) -> f64 {
    let v: Vec<f64> = u0.iter().zip(u1).map(|(a, b)| (b - a) / dt).collect();
    let ub: Vec<f64> = u0.iter().zip(u1).map(|(a, b)| 0.5 * (a + b)).collect();
    0.5 * m.quad_form(&v) + 0.5 * (beta - 0.25) * dt * dt * k.quad_form(&v) + 0.5 * k.quad_form(&ub)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// β-scheme with the projection (β ∈ [1/4, 1/2]: unconditionally
    /// stable, so any dt) over 0.3 s, long enough for the tip to reach a stop.
    /// From the trajectory alone, with the support load `Gⁿ` recomputed here
    /// from the lifting (shape and exact time means): the scheme's equation
    /// holds off the tip, its tip residual is the reported `λⁿ`, the tip
    /// stays in [g1, g2], contact never adds energy (e = 0), and
    /// `E^{n+1/2} - E^{1/2} = W_support + W_contact` (docs/theory.md §7.3)
    /// with both works summed here; the scheme's own work accounting agrees.
    #[test]
    fn beta_scheme_constraint_and_energy_balance(j in 2usize..10, beta in 0.25f64..=0.5, amp in 0.1f64..0.4, omega in 5.0f64..40.0,
                                                 gap in 0.01f64..0.05, dt in 5e-5f64..2e-4) {
        let pipe = Pipe { stops: (-gap, 0.8 * gap), support: (amp, omega), ..Pipe::paper() };
        let (beam, dy, init) = pipe.dynamics(j).unwrap();
        let (mm, kk) = (dy.mass.clone(), dy.stiffness.clone());
        let shape = support_shape(&pipe, j);
        let tip = beam.tip_dof();
        let n_dofs = beam.dofs();
        let mut s = PaoliSchatzman::new("beta".into(), dy, beta, 0.0, dt, &init).unwrap();
        let (mut u_prev, mut u) = (init.u.clone(), s.displacement().to_vec());
        // The start step is one Newmark(β, ½) step from rest (U⁰ = 0, so
        // M A⁰ = F(0) - K U⁰ = 0, and the tip, at 0 with velocity 0, is free):
        // (M + β dt² K) U¹ = dt M V⁰ + β dt² sin(ω dt) S.
        {
            let (mut mu, mut ku1, mut mv) = (vec![0.0; n_dofs], vec![0.0; n_dofs], vec![0.0; n_dofs]);
            mm.mul_vec(&u, &mut mu);
            kk.mul_vec(&u, &mut ku1);
            mm.mul_vec(&init.v, &mut mv);
            let f1 = (omega * dt).sin();
            let lhs: Vec<f64> = (0..n_dofs).map(|i| mu[i] + beta * dt * dt * ku1[i]).collect();
            let rhs: Vec<f64> = (0..n_dofs).map(|i| dt * mv[i] + beta * dt * dt * f1 * shape[i]).collect();
            let scale = lhs.iter().chain(&rhs).fold(1e-300f64, |a, b| a.max(b.abs()));
            for i in 0..n_dofs {
                prop_assert!((lhs[i] - rhs[i]).abs() <= 1e-12 * scale, "start step, dof {}: {} vs {}", i, lhs[i], rhs[i]);
            }
        }
        let e_half = half_step_energy(&mm, &kk, beta, dt, &u_prev, &u);
        prop_assert!((s.energy().unwrap().1 - e_half).abs() <= 1e-12 * e_half.abs());
        let (mut w_support, mut w_contact) = (0.0, 0.0);
        let mut contacts = 0;
        let (mut acc, mut ku, mut tmp) = (vec![0.0; n_dofs], vec![0.0; n_dofs], vec![0.0; n_dofs]);
        let steps = (0.3 / dt).ceil() as usize;
        for _ in 1..steps {
            let n = s.level(); // the step goes t_{n-1}, t_n -> t_{n+1}
            let r = s.step().unwrap();
            let u_next = s.displacement().to_vec();
            // Gⁿ = β f^{n+1} + (1-2β) fⁿ + β f^{n-1}, fᵏ the mean over [t_k, t_{k+1}].
            let t = |k: usize| k as f64 * dt;
            let g = beta * sine_mean(omega, t(n + 1), dt) + (1.0 - 2.0 * beta) * sine_mean(omega, t(n), dt) + beta * sine_mean(omega, t(n - 1), dt);
            // Residual Gⁿ S - M δ²U/dt² - K(β U^{n+1} + (1-2β) Uⁿ + β U^{n-1}) = λⁿ e_tip.
            for i in 0..n_dofs {
                tmp[i] = (u_next[i] - 2.0 * u[i] + u_prev[i]) / (dt * dt);
            }
            mm.mul_vec(&tmp, &mut acc);
            for i in 0..n_dofs {
                tmp[i] = beta * u_next[i] + (1.0 - 2.0 * beta) * u[i] + beta * u_prev[i];
            }
            kk.mul_vec(&tmp, &mut ku);
            let scale = (0..n_dofs).map(|i| acc[i].abs().max(ku[i].abs()).max((g * shape[i]).abs())).fold(1e-300, f64::max);
            for i in (0..n_dofs).filter(|&i| i != tip) {
                let res = g * shape[i] - acc[i] - ku[i];
                prop_assert!(res.abs() <= 1e-9 * scale, "step {}: residual {} at dof {} (scale {})", n, res, i, scale);
            }
            let lambda = g * shape[tip] - acc[tip] - ku[tip];
            let (t_l, l_rep) = r.lambda.unwrap();
            prop_assert!((t_l - t(n)).abs() <= 1e-12, "λ of the step from t_{} belongs to {}", n, t_l);
            prop_assert!((l_rep - lambda).abs() <= 1e-9 * scale, "step {}: reported λ {} vs residual {}", n, l_rep, lambda);
            let active = r.active != signorini::contact::Active::None;
            contacts += usize::from(active);
            if !active {
                prop_assert!(lambda.abs() <= 1e-9 * scale, "step {}: force {} without contact", n, lambda);
            }
            let ut = u_next[tip];
            prop_assert!(ut >= -gap && ut <= 0.8 * gap, "tip {} outside [{}, {}]", ut, -gap, 0.8 * gap);
            // Works of the step, from the trajectory.
            let dw_c = -0.5 * lambda * (u_next[tip] - u_prev[tip]);
            prop_assert!(dw_c <= 1e-9 * scale * gap, "step {}: contact work {} > 0", n, dw_c);
            w_contact += dw_c;
            let du: Vec<f64> = u_next.iter().zip(&u_prev).map(|(a, b)| a - b).collect();
            w_support += 0.5 * g * dot(&shape, &du);
            u_prev = std::mem::replace(&mut u, u_next);
            let e = half_step_energy(&mm, &kk, beta, dt, &u_prev, &u);
            let escale = e.abs().max(e_half.abs()).max(w_support.abs()).max(1e-12);
            prop_assert!(((e - e_half) - (w_support + w_contact)).abs() <= 1e-10 * escale,
                "step {}: ΔE = {} vs W_support + W_contact = {} + {}", n, e - e_half, w_support, w_contact);
            let (wf, wc) = s.work().unwrap();
            prop_assert!((wf - w_support).abs() <= 1e-10 * escale && (wc - w_contact).abs() <= 1e-10 * escale,
                "step {}: scheme's works ({}, {}) vs recomputed ({}, {})", n, wf, wc, w_support, w_contact);
        }
        // The run must have exercised the contact terms.
        prop_assert!(contacts > 0, "no contact in {} steps", steps);
        prop_assert!(w_contact < 0.0, "contact work {}", w_contact);
    }
}

/// The lifted problem of docs/theory.md §1.2 for the paper's pipe: rest
/// initial position, initial velocity the Hermite interpolant of `-A ω h`,
/// and the forcing `(A ω² h + 8 A k²/L⁴) sin(ω t)`, against the formulas
/// written out here (the paper's `20 h + 89.1534… `).
#[test]
fn lifted_data_of_the_paper_pipe() {
    let pipe = Pipe::paper();
    let (a, w) = pipe.support;
    assert_eq!((a, w), (0.2, 10.0));
    let c = 8.0 * a * pipe.k2 / pipe.length.powi(4);
    assert!((c - 89.1534).abs() < 1e-4, "8 A k²/L⁴ = {c}");
    for j in [1usize, 4, 19] {
        let (beam, dy, init) = pipe.dynamics(j).unwrap();
        let h = pipe.length / j as f64;
        assert!(init.u.iter().all(|&x| x == 0.0));
        for node in 1..=j {
            let (hv, hd) = lifting(node as f64 * h, pipe.length);
            let (v, s) = (init.v[2 * (node - 1)], init.v[2 * (node - 1) + 1]);
            assert!((v + a * w * hv).abs() <= 1e-14, "J = {j}, node {node}: v = {v}, -Aωh = {}", -a * w * hv);
            assert!((s + a * w * hd).abs() <= 1e-13, "J = {j}, node {node}: slope {s}, -Aωh' = {}", -a * w * hd);
        }
        // The tip value's initial velocity is 0 (h(L) = 0): the tip starts at rest.
        assert!(init.v[beam.tip_dof()].abs() <= 1e-14);
        assert_eq!(dy.forcing.len(), 1, "J = {j}: one forcing term");
        let Forcing { shape, time } = dy.forcing[0].clone();
        assert_eq!(time, TimeProfile::Sine { amplitude: 1.0, omega: w });
        let want = support_shape(&pipe, j);
        for (i, (g, x)) in shape.iter().zip(&want).enumerate() {
            assert!((g - x).abs() <= 1e-12 * x.abs().max(1e-3), "J = {j}: shape[{i}] = {g}, by hand {x}");
        }
        assert!(dy.load.iter().all(|&x| x == 0.0));
        assert_eq!(dy.contact().bounds, Bounds { lo: -0.1, hi: 0.1 });
    }
}

/// Normal compliance: the reported force is the spring law of the tip
/// displacement, exactly (to rounding), and the stops are violated.
#[test]
fn penalty_force_law() {
    let pipe = Pipe::paper();
    let (_, dy, init) = pipe.dynamics(19).unwrap();
    let tip = dy.contact().dof;
    let Bounds { lo, hi } = dy.contact().bounds;
    let kappa = 1e8 / pipe.rho_s;
    let mut s = OneStep::new("pen".into(), dy, OneStepParams::newmark(0.25, 0.5), 5e-6, &init).unwrap().with_contact_law(ContactLaw::Penalty { stiffness: kappa }).unwrap();
    let mut max_excess: f64 = 0.0;
    let mut active = 0;
    for _ in 0..40_000 {
        let r = s.step().unwrap();
        let u = s.displacement()[tip];
        let law = kappa * (lo - u).max(0.0) - kappa * (u - hi).max(0.0);
        let lambda = r.lambda.unwrap().1;
        // κ(hi − u) cancels: rounding of a few ulps of κ·|u| (κ = 8.4e8).
        assert!((lambda + law).abs() <= 4e-16 * kappa * (u.abs() + hi), "λ = {lambda}, spring {law} at u = {u}");
        active += usize::from(law != 0.0);
        max_excess = max_excess.max(u.abs() - 0.1);
    }
    assert!(active > 100 && max_excess > 1e-5, "{active} penalty steps, max excess {max_excess}");
    assert!(matches!(
        OneStep::new("pen".into(), Pipe::paper().dynamics(3).unwrap().1, OneStepParams::newmark(0.25, 0.5), 1e-5, &Pipe::paper().dynamics(3).unwrap().2)
            .unwrap()
            .with_contact_law(ContactLaw::Penalty { stiffness: -1.0 }),
        Err(signorini::schemes::SchemeError::Invalid { field: "penalty stiffness", .. })
    ));
}

// The β-scheme's stability limit and its refusal: tests/it/stability.rs.

/// Fig. 2 data (β = 1/2, dt = 5e-5): the tip never leaves [-0.1, 0.1] and
/// first touches the upper stop at t = 0.0878 s, as every finer run does.
#[test]
fn first_impact_of_the_paper_scene() {
    let pipe = Pipe::paper();
    let BuiltBeam { stepper: mut s, initial: init, beam, .. } = BeamSetup::new(pipe, scene(5e-5, 0.2, SchemeSpec::ps(0.0, 0.5))).build().unwrap();
    // The scene starts from the lifted data: at rest, tip velocity 0.
    assert!(init.u.iter().all(|&x| x == 0.0) && init.v[beam.tip_dof()].abs() <= 1e-14);
    assert_eq!(init.v, pipe.dynamics(19).unwrap().2.v);
    let mut first = None;
    for _ in 0..4000 {
        let r = s.step().unwrap();
        let u = s.displacement()[beam.tip_dof()];
        assert!(u.abs() <= 0.1);
        if first.is_none() && r.active != signorini::contact::Active::None {
            first = Some((r.t, u));
        }
    }
    let (t, u) = first.unwrap();
    assert!((t - 0.08785).abs() < 1e-4 && u == 0.1, "first impact at {t} (tip {u})");
    // The support forcing's time averages are exact.
    let p = TimeProfile::Sine { amplitude: 2.0, omega: 10.0 };
    let (t0, t1): (f64, f64) = (0.3, 0.3 + 1e-3);
    let exact = 2.0 * ((10.0 * t0).cos() - (10.0 * t1).cos()) / (10.0 * 1e-3);
    assert!((p.mean(t0, t1) - exact).abs() < 1e-12);
    assert!((p.mean(t0, t1) - 2.0 * sine_mean(10.0, t0, 1e-3)).abs() < 1e-12);
    // and stay accurate where the difference of cosines cancels (dt = 1e-9).
    assert!((p.mean(t0, t0 + 1e-9) - 2.0 * (10.0 * (t0 + 0.5e-9)).sin()).abs() < 1e-12);
}
