//! Discrete energy identities of docs/theory.md §7 as property tests over random
//! initial data, meshes, time steps and obstacle positions, with the standard
//! mass and with massless contact nodes.
//!
//! Tolerance: each identity is an algebraic consequence of the scheme, so it
//! holds up to rounding of the quantities involved. The check is
//! `|lhs - rhs| <= 1e-11 * scale`, with `scale` the largest absolute energy
//! (or term) involved: sums of ~100 products of O(scale) numbers, each with
//! relative error 1e-16, plus the solve's backward error (κ(A) < 1e4 here).

use proptest::prelude::*;
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_schemes::{Bounds, Dynamics, Initial, OneStep, OneStepParams, PaoliSchatzman, Reduced, ReducedLaw, Stepper};

const MASSES: [BarMass; 6] = [BarMass::Std, BarMass::Lumped, BarMass::Mod, BarMass::Mod3, BarMass::Transfer, BarMass::Singular];

fn dynamics(m: usize, mass: BarMass, gap: f64, end: RightEnd, force: f64) -> Dynamics {
    let bar = Bar::new(1.0, m, 1.0, end).unwrap();
    Dynamics {
        mass: bar.mass(mass),
        stiffness: bar.stiffness(),
        load: bar.load(|_| force),
        contact_dof: 0,
        massless_contact: mass.massless_contact_node(),
        bounds: Bounds::obstacle(gap),
        forcing: None,
    }
}

/// Random smooth-ish initial data above the obstacle `gap` at node 0.
fn initial(n: usize, amp: f64, seed: f64, gap: f64) -> Initial {
    let u: Vec<f64> = (0..n).map(|i| amp * ((i as f64 + 1.0) * seed).sin() + if i == 0 { gap.abs() + 0.1 } else { 0.0 }).collect();
    let v = (0..n).map(|i| -amp * ((i as f64 + 2.0) * seed * 1.7).cos()).collect();
    Initial { u, v }
}

/// Rounding scale of the energies: besides |E|, the quadratic forms UᵀKU and
/// VᵀMV are computed with absolute error ~ eps ‖K‖ ‖U‖² (a free bar can
/// drift rigidly far from the origin while E stays small).
fn rounding_scale(k: &signorini_fem::SymBand, m: &signorini_fem::SymBand, us: &[&[f64]], vs: &[&[f64]], energies: &[f64]) -> f64 {
    let norm = |a: &signorini_fem::SymBand| (0..a.n()).map(|i| (0..a.n()).map(|j| a.get(i, j).abs()).sum::<f64>()).fold(0.0, f64::max);
    let sq = |x: &[f64]| dot(x, x);
    let mut s = energies.iter().fold(1e-3f64, |s, e| s.max(e.abs()));
    for u in us {
        s = s.max(norm(k) * sq(u));
    }
    for v in vs {
        s = s.max(norm(m) * sq(v));
    }
    s
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn diff(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// Runs a one-step scheme and checks, at every step, the identity of docs/theory.md §7.1
/// for Newmark(β, γ) (θ-method through its Newmark-like coefficients, with
/// its own identity when `theta` is given).
fn check_one_step(dy: Dynamics, prm: OneStepParams, theta: Option<f64>, dt: f64, init: &Initial, steps: usize) -> Result<usize, TestCaseError> {
    check_one_step_with(dy, prm, theta, dt, init, steps, None)
}

/// As [`check_one_step`], with a contact law other than the projection; for
/// a penalty law also checks the force law at every step.
fn check_one_step_with(dy: Dynamics, prm: OneStepParams, theta: Option<f64>, dt: f64, init: &Initial, steps: usize, law: Option<signorini_schemes::ContactLaw>) -> Result<usize, TestCaseError> {
    let (k, mm) = (dy.stiffness.clone(), dy.mass.clone());
    let f = dy.load.clone();
    let n = dy.n();
    let gap = dy.bounds.lo;
    let mut s = OneStep::new("t".into(), dy, prm, dt, init).unwrap();
    if let Some(l) = law {
        s = s.with_contact_law(l).unwrap();
    }
    let (mut v0, mut v1) = (vec![0.0; n], vec![0.0; n]);
    let mut contacts = 0;
    // A massless node's initial value need not be its equilibrium: the first
    // step projects it there (an O(h) energy change the identity does not
    // describe). The identities hold exactly from then on.
    let first = usize::from(s.dynamics().massless_contact);
    for _ in 0..first {
        s.step().unwrap();
    }
    for _ in first..steps {
        let u0 = s.displacement().to_vec();
        s.velocity(&mut v0);
        let l0 = s.lambda();
        let e0 = s.energy().unwrap().1;
        let rep = s.step().unwrap();
        contacts += usize::from(rep.active != signorini_contact::Active::None);
        let u1 = s.displacement().to_vec();
        s.velocity(&mut v1);
        let l1 = s.lambda();
        let e1 = s.energy().unwrap().1;
        // The identities are for the mechanical energy: remove the spring's.
        let spring = |u: f64| match law {
            Some(signorini_schemes::ContactLaw::Penalty { stiffness }) => 0.5 * stiffness * (gap - u).max(0.0).powi(2),
            _ => 0.0,
        };
        let (e0, e1) = (e0 - spring(u0[0]), e1 - spring(u1[0]));
        let (du, dv) = (diff(&u1, &u0), diff(&v1, &v0));
        let mut kdu = vec![0.0; n];
        k.mul_vec(&du, &mut kdu);
        let mut kdv = vec![0.0; n];
        k.mul_vec(&dv, &mut kdv);
        let g = prm.gamma;
        // A steady load enters the total energy as -FᵀU; KU - F replaces KU in
        // the derivation and F cancels from every difference term, so the
        // identities hold unchanged for the total energy.
        let _ = &f;
        let rhs = match theta {
            None => {
                let beta = prm.a_new;
                (0.5 - g) * dot(&du, &kdu) - du[0] * ((1.0 - g) * l0 + g * l1)
                    + dt * (beta - g / 2.0) * dot(&dv, &kdu)
                    + dt * (beta - g / 2.0) * dv[0] * (l1 - l0)
            }
            Some(th) => (0.5 - th) * (mm.quad_form(&dv) + dot(&du, &kdu)) - du[0] * ((1.0 - th) * l0 + th * l1),
        };
        let scale = rounding_scale(&k, &mm, &[&u0, &u1], &[&v0, &v1], &[e0, e1]);
        prop_assert!(((e1 - e0) - rhs).abs() <= 1e-11 * scale, "ΔE = {} but identity gives {} (scale {})", e1 - e0, rhs, scale);
        match law {
            // The constraint holds exactly.
            None => prop_assert!(u1[0] >= s.dynamics().bounds.lo),
            // The penalty force is the spring law of the new displacement
            // (rounding: κ(g - u) cancels, a few ulps of κ|u|).
            Some(signorini_schemes::ContactLaw::Penalty { stiffness }) => {
                let want = stiffness * (u1[0] - gap).min(0.0);
                prop_assert!((l1 - want).abs() <= 1e-14 * stiffness * (1.0 + u1[0].abs() + gap.abs()), "λ {} vs law {}", l1, want);
            }
            Some(_) => {}
        }
    }
    Ok(contacts)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn newmark_energy_identity(m in 2usize..30, mass_i in 0usize..6, beta_gamma in prop_oneof![Just((0.25, 0.5)), Just((0.5, 1.0)), Just((0.5, 0.5)), (0.3f64..0.5, 0.5f64..0.6)],
                               cfl in 0.05f64..20.0, amp in 0.01f64..1.0, seed in 0.1f64..3.0, gap in -0.5f64..0.0, free in proptest::bool::ANY, force in -0.5f64..0.5) {
        let end = if free { RightEnd::Free } else { RightEnd::Clamped };
        let dy = dynamics(m, MASSES[mass_i], gap, end, force);
        let n = dy.n();
        let dt = cfl / m as f64;
        check_one_step(dy, OneStepParams::newmark(beta_gamma.0, beta_gamma.1), None, dt, &initial(n, amp, seed, gap), 40)?;
    }

    #[test]
    fn theta_energy_identity(m in 2usize..30, mass_i in 0usize..6, theta in 0.5f64..=1.0, cfl in 0.05f64..20.0, amp in 0.01f64..1.0, seed in 0.1f64..3.0, gap in -0.5f64..0.0, force in -0.5f64..0.5) {
        let dy = dynamics(m, MASSES[mass_i], gap, RightEnd::Free, force);
        let n = dy.n();
        check_one_step(dy, OneStepParams::theta(theta), Some(theta), cfl / m as f64, &initial(n, amp, seed, gap), 40)?;
    }

    /// Paoli–Schatzman: with a massive contact node,
    /// E^{n+1/2} - E^{n-1/2} = -λ^n (u_0^{n+1} - u_0^{n-1})/2, which with the
    /// complementarity and g = 0 is (1+e)/2 λ^n u_0^{n-1} (2017 paper (35)).
    /// With a massless node, row 0 is replaced by the equilibrium at t_{n+1};
    /// what holds then is ΔE = d_0 (u_0^{n+1} - u_0^{n-1})/2 with
    /// d_0 = (K(βU^{n+1} + (1-2β)U^n + βU^{n-1}))_0 - F_0, the residual of the
    /// dropped averaged row (checked here; it is not sign-definite).
    #[test]
    fn paoli_schatzman_energy_identity(m in 2usize..30, mass_i in 0usize..6, e in 0.0f64..=1.0, beta in 0.25f64..0.5,
                                       cfl in 0.05f64..20.0, amp in 0.01f64..1.0, seed in 0.1f64..3.0, force in -0.5f64..0.5, free in proptest::bool::ANY,
                                       explicit in proptest::bool::ANY) {
        let mass = MASSES[mass_i];
        let end = if free { RightEnd::Free } else { RightEnd::Clamped };
        let dy = dynamics(m, mass, 0.0, end, force);
        let (k, mm, f, n) = (dy.stiffness.clone(), dy.mass.clone(), dy.load.clone(), dy.n());
        // β = 0 (Taylor–Flanagan) with a massive node, below its exact CFL limit.
        let explicit = explicit && !mass.massless_contact_node();
        let (beta, dt) = if explicit {
            let limit = 2.0 / signorini_fem::max_generalized_eigenvalue_auto(&k, &mm).unwrap().sqrt();
            (0.0, (cfl / 20.0).min(0.95) * limit)
        } else {
            (beta, cfl / m as f64)
        };
        let mut s = PaoliSchatzman::new("ps".into(), dy, beta, e, dt, &initial(n, amp, seed, 0.0)).unwrap();
        let mut e_prev = s.energy().unwrap().1;
        for _ in 0..40 {
            let (um, u0) = (s.previous_displacement().to_vec(), s.displacement().to_vec());
            let rep = s.step().unwrap();
            let u1 = s.displacement().to_vec();
            let e_new = s.energy().unwrap().1;
            let (_, lam) = rep.lambda.unwrap();
            let rhs = if mass.massless_contact_node() {
                let avg: Vec<f64> = (0..n).map(|i| beta * u1[i] + (1.0 - 2.0 * beta) * u0[i] + beta * um[i]).collect();
                let mut ka = vec![0.0; n];
                k.mul_vec(&avg, &mut ka);
                0.5 * (ka[0] - f[0]) * (u1[0] - um[0])
            } else {
                let general = -0.5 * lam * (u1[0] - um[0]);
                // (35): the complementarity turns it into (1+e)/2 λ^n u_0^{n-1}.
                let paper = 0.5 * (1.0 + e) * lam * um[0];
                prop_assert!((general - paper).abs() <= 1e-12 * (1.0 + general.abs() + paper.abs()));
                general
            };
            let v: Vec<f64> = diff(&u1, &u0).iter().map(|x| x / dt).collect();
            let scale = rounding_scale(&k, &mm, &[&um, &u0, &u1], &[&v], &[e_prev, e_new]);
            prop_assert!(((e_new - e_prev) - rhs).abs() <= 1e-11 * scale, "ΔE = {} vs {}", e_new - e_prev, rhs);
            // The restitution constraint holds.
            prop_assert!(u1[0] + e * um[0] >= -1e-15 * (1.0 + um[0].abs()));
            e_prev = e_new;
        }
    }
}

#[test]
fn crank_nicolson_and_midpoint_conserve_energy_without_contact() {
    for mass in MASSES {
        for (prm, theta) in [(OneStepParams::newmark(0.25, 0.5), None), (OneStepParams::theta(0.5), Some(0.5))] {
            let dy = dynamics(17, mass, -1e6, RightEnd::Clamped, 0.0);
            let init = initial(dy.n(), 0.3, 1.3, 0.0);
            let massless = dy.massless_contact;
            let mut s = OneStep::new("cn".into(), dy, prm, 0.37, &init).unwrap();
            if massless {
                s.step().unwrap(); // equilibrate the massless node first
            }
            let e0 = s.energy().unwrap().1;
            for _ in 0..2000 {
                s.step().unwrap();
            }
            let e1 = s.energy().unwrap().1;
            assert!((e1 - e0).abs() <= 1e-12 * e0, "{mass} {theta:?}: {e0} -> {e1}");
        }
    }
}

#[test]
fn newmark_with_contact_really_exercises_contact() {
    // The proptests above must see active contact: check one typical case.
    let dy = dynamics(10, BarMass::Std, 0.0, RightEnd::Clamped, 0.0);
    let init = Initial { u: (0..10).map(|i| 0.5 - 0.05 * i as f64).collect(), v: vec![-1.0; 10] };
    let contacts = check_one_step(dy, OneStepParams::newmark(0.25, 0.5), None, 0.05, &init, 60).unwrap();
    assert!(contacts > 5, "only {contacts} contact steps");
}

const MASSLESS: [BarMass; 6] = [BarMass::Mod, BarMass::Mod1, BarMass::Mod2, BarMass::Mod3, BarMass::Transfer, BarMass::Singular];

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Weighted-mass paper, Lemma 5.1: the hybrid scheme's energy never
    /// increases (steady load, any massless-node mass, any dt, with and
    /// without contact). Checked to rounding: E^{n+1} <= E^n + 1e-12·scale.
    #[test]
    fn hybrid_energy_never_increases(m in 2usize..30, mass_i in 0usize..6, cfl in 0.05f64..20.0, amp in 0.01f64..1.0,
                                     seed in 0.1f64..3.0, gap in -0.3f64..0.0, force in -0.5f64..0.5, free in proptest::bool::ANY) {
        let end = if free { RightEnd::Free } else { RightEnd::Clamped };
        let dy = dynamics(m, MASSLESS[mass_i], gap, end, force);
        let (k, mm) = (dy.stiffness.clone(), dy.mass.clone());
        let init = initial(dy.n(), amp, seed, gap);
        let mut s = Reduced::new("hybrid".into(), dy, ReducedLaw::Hybrid, cfl / m as f64, &init).unwrap();
        let mut e = s.energy().unwrap().1;
        let mut contacts = 0;
        for _ in 0..60 {
            let r = s.step().unwrap();
            contacts += usize::from(r.active != signorini_contact::Active::None);
            let e1 = s.energy().unwrap().1;
            let mut v = vec![0.0; s.displacement().len()];
            v[1..].copy_from_slice(s.velocity());
            let scale = rounding_scale(&k, &mm, &[s.displacement()], &[&v], &[e, e1]);
            prop_assert!(e1 <= e + 1e-12 * scale, "energy grew: {} -> {} (+{:e})", e, e1, e1 - e);
            // The reduced energy of the paper differs by a constant only.
            e = e1;
        }
        let _ = contacts;
    }
}

#[test]
fn hybrid_conserves_energy_without_contact_and_dissipates_with_it() {
    for mass in MASSLESS {
        // Far obstacle: midpoint rule on a linear system, energy conserved.
        let dy = dynamics(17, mass, -1e6, RightEnd::Clamped, 0.1);
        let init = initial(dy.n(), 0.3, 1.3, 0.0);
        let mut s = Reduced::new("hybrid".into(), dy, ReducedLaw::Hybrid, 0.37, &init).unwrap();
        let e0 = s.energy().unwrap().1;
        let r0 = s.reduced_energy();
        for _ in 0..2000 {
            s.step().unwrap();
        }
        let e1 = s.energy().unwrap().1;
        assert!((e1 - e0).abs() <= 1e-12 * e0.abs(), "{mass}: {e0} -> {e1}");
        // The paper's reduced energy and the physical one differ by a constant.
        assert!(((s.reduced_energy() - r0) - (e1 - e0)).abs() <= 1e-12 * e0.abs());
    }
    // With contact (the Dirichlet benchmark's data), it loses energy, a little.
    let dy = dynamics(40, BarMass::Mod3, 0.0, RightEnd::Clamped, 0.0);
    let n = dy.n();
    let init = Initial { u: (0..n).map(|i| 0.5 - 0.5 * i as f64 / 40.0).collect(), v: vec![0.0; n] };
    let mut s = Reduced::new("hybrid".into(), dy, ReducedLaw::Hybrid, 0.0025, &init).unwrap();
    let e0 = s.energy().unwrap().1;
    let mut contact_steps = 0;
    for _ in 0..1200 {
        contact_steps += usize::from(s.step().unwrap().active != signorini_contact::Active::None);
    }
    let e1 = s.energy().unwrap().1;
    assert!(contact_steps > 300, "{contact_steps}");
    assert!(e1 < e0 && e1 > 0.9 * e0, "{e0} -> {e1}");
}

/// The paper's Lemma 3.1 scheme (Crank–Nicolson on the reduced ODE) is
/// `newmark-cn` with a massless node once the node starts in equilibrium:
/// the trajectories agree to rounding through impacts.
#[test]
fn reduced_crank_nicolson_is_newmark_cn_with_a_massless_node() {
    for mass in MASSLESS {
        for (gap, force) in [(0.0, 0.0), (-0.05, -0.3)] {
            let dy = dynamics(20, mass, gap, RightEnd::Free, force);
            let n = dy.n();
            let k = -dy.stiffness.get(0, 1);
            let mut u: Vec<f64> = (0..n).map(|i| 0.3 - 0.4 * (i as f64 / 20.0)).collect();
            u[0] = (u[1] + dy.load[0] / k).max(gap);
            let init = Initial { u, v: vec![-0.7; n] };
            let mut a = Reduced::new("reduced-cn".into(), dy.clone(), ReducedLaw::CrankNicolson, 0.013, &init).unwrap();
            let mut b = OneStep::new("newmark-cn".into(), dy, OneStepParams::newmark(0.25, 0.5), 0.013, &init).unwrap();
            let mut contacts = 0;
            for _ in 0..400 {
                let ra = a.step().unwrap();
                let rb = b.step().unwrap();
                contacts += usize::from(rb.active != signorini_contact::Active::None);
                let d = a.displacement().iter().zip(b.displacement()).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
                assert!(d <= 1e-11, "{mass}: trajectories differ by {d}");
                let (la, lb) = (ra.lambda.unwrap().1, rb.lambda.unwrap().1);
                assert!((la - lb).abs() <= 1e-9 * (1.0 + lb.abs()), "{mass}: λ {la} vs {lb}");
            }
            assert!(contacts > 20, "{mass}: {contacts} contact steps");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Penalised contact (Newmark-CN solved exactly per step, or the explicit
    /// central difference below its exact CFL limit): the Newmark identity
    /// of docs/theory.md §7.5 holds with λ the penalty force, and the force is the law
    /// λ = γ_P K_00 min(0, u_0 - g) of the new displacement.
    #[test]
    fn penalty_energy_identity_and_law(m in 2usize..25, massive in proptest::bool::ANY, gamma_p in 0.1f64..100.0, explicit in proptest::bool::ANY,
                                       cfl in 0.05f64..0.95, amp in 0.01f64..1.0, seed in 0.1f64..3.0, gap in -0.3f64..0.0) {
        let mass = if massive { BarMass::Std } else { BarMass::Lumped };
        let dy = dynamics(m, mass, gap, RightEnd::Clamped, 0.0);
        let kappa = gamma_p * dy.stiffness.get(0, 0);
        let (prm, dt) = if explicit {
            let mut k = dy.stiffness.clone();
            k.add(0, 0, kappa);
            let kmax = signorini_fem::max_generalized_eigenvalue_auto(&k, &dy.mass).unwrap();
            (OneStepParams::newmark(0.0, 0.5), cfl * 2.0 / kmax.sqrt())
        } else {
            (OneStepParams::newmark(0.25, 0.5), cfl * 20.0 / m as f64)
        };
        let init = initial(dy.n(), amp, seed, gap);
        check_one_step_with(dy, prm, None, dt, &init, 60, Some(signorini_schemes::ContactLaw::Penalty { stiffness: kappa }))?;
    }
}

#[test]
fn explicit_penalty_refuses_steps_beyond_its_cfl_limit() {
    use signorini_schemes::{SchemeError, SchemeSpec};
    let dy = dynamics(20, BarMass::Lumped, 0.0, RightEnd::Clamped, 0.0);
    let init = initial(dy.n(), 0.3, 1.0, 0.0);
    let spec: SchemeSpec = "penalty-cd(10)".parse().unwrap();
    // Lumped P1 bar with a spring 10 c²/h at node 0: κ_max from the eigen solver.
    let mut k = dy.stiffness.clone();
    k.add(0, 0, 10.0 * dy.stiffness.get(0, 0));
    let limit = 2.0 / signorini_fem::max_generalized_eigenvalue_auto(&k, &dy.mass).unwrap().sqrt();
    assert!(limit > 0.01 && limit < 0.05, "{limit}");
    match spec.build(dy.clone(), limit * 1.001, &init) {
        Err(SchemeError::Unstable { dt, limit: l, .. }) => assert!((l - limit).abs() < 1e-12 && dt > l),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted beyond the CFL limit"),
    }
    assert!(spec.build(dy, limit * 0.999, &init).is_ok());
    let massless = dynamics(20, BarMass::Mod, 0.0, RightEnd::Clamped, 0.0);
    assert!(matches!(spec.build(massless, 1e-4, &init), Err(SchemeError::MassNotSupported { .. })));
    assert!(matches!("penalty(0)".parse::<SchemeSpec>(), Err(SchemeError::Invalid { field: "gamma_p", .. })));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Moreau–Jean, θ = 1/2: ΔE = p (v_c^n + v_c^{n+1})/2 exactly (steady
    /// load in E); by the complementarity p (v_c^{n+1} + e v_c^n) = 0 this is
    /// (1-e)/2 p v_c^n: zero for e = 1, ≤ 0 when the node approaches
    /// (v_c^n ≤ 0) — but positive when the predicted-active node already
    /// separates (v_c^n > 0) and the impulse stops it: a measured gain.
    #[test]
    fn moreau_jean_energy_identity(m in 2usize..25, massive in proptest::bool::ANY, e in 0.0f64..=1.0, cfl in 0.05f64..20.0,
                                   amp in 0.01f64..1.0, seed in 0.1f64..3.0, gap in -0.3f64..0.0, force in -0.5f64..0.5, free in proptest::bool::ANY) {
        let mass = if massive { BarMass::Std } else { BarMass::Lumped };
        let end = if free { RightEnd::Free } else { RightEnd::Clamped };
        let dy = dynamics(m, mass, gap, end, force);
        let (k, mm) = (dy.stiffness.clone(), dy.mass.clone());
        let mut s = signorini_schemes::MoreauJean::new("mj".into(), dy, 0.5, e, cfl / m as f64, &initial(m + usize::from(free), amp, seed, gap)).unwrap();
        let mut e0 = s.energy().unwrap().1;
        for _ in 0..60 {
            let v0 = s.velocity()[0];
            s.step().unwrap();
            let (v1, p) = (s.velocity()[0], s.impulse());
            let e1 = s.energy().unwrap().1;
            let rhs = p * (v0 + v1) / 2.0;
            let scale = rounding_scale(&k, &mm, &[s.displacement()], &[s.velocity()], &[e0, e1]);
            prop_assert!(((e1 - e0) - rhs).abs() <= 1e-11 * scale, "ΔE {} vs {}", e1 - e0, rhs);
            prop_assert!((rhs - 0.5 * (1.0 - e) * p * v0).abs() <= 1e-12 * scale, "complementarity: {} vs {}", rhs, 0.5 * (1.0 - e) * p * v0);
            if v0 <= 0.0 {
                prop_assert!(rhs <= 1e-12 * scale, "an approaching impact gained energy {}", rhs);
            }
            e0 = e1;
        }
    }
}

/// Taylor–Flanagan (`ps(0, 0)`, lumped mass, dt below the exact CFL limit):
/// the contact correction moves the contact node only, puts it exactly on
/// the obstacle, and the central-difference energy
/// E^{n+1/2} = ½VᵀMV + ½ U^nᵀ K U^{n+1} obeys ΔE = -λ^n (u_0^{n+1} - u_0^{n-1})/2 ≤ 0.
#[test]
fn taylor_flanagan_corrects_the_contact_node_only_and_dissipates() {
    use signorini_schemes::SchemeSpec;
    let dy = dynamics(30, BarMass::Lumped, 0.0, RightEnd::Clamped, 0.0);
    let (k, n) = (dy.stiffness.clone(), dy.n());
    let spec: SchemeSpec = "taylor-flanagan".parse().unwrap();
    let limit = spec.cfl_limit(&dy).unwrap().unwrap();
    // Lumped P1 bar: κ_max → 4c²/h² as m grows, so dt_c ≈ h/c.
    assert!((limit * 30.0 - 1.0).abs() < 0.01, "CFL limit {limit}");
    let init = Initial { u: (0..n).map(|i| 0.5 * (1.0 - i as f64 / 30.0)).collect(), v: vec![-0.3; n] };
    let mut s = PaoliSchatzman::new("tf".into(), dy, 0.0, 0.0, 0.9 * limit, &init).unwrap();
    let mut e_prev = s.energy().unwrap().1;
    let mut contacts = 0;
    for _ in 0..600 {
        let um = s.previous_displacement().to_vec();
        let u0 = s.displacement().to_vec();
        let rep = s.step().unwrap();
        let u1 = s.displacement().to_vec();
        let (_, lam) = rep.lambda.unwrap();
        if lam != 0.0 {
            contacts += 1;
            assert_eq!(u1[0], 0.0);
            // Nodes 1.. follow the free central-difference update exactly.
            let mut ku = vec![0.0; n];
            k.mul_vec(&u0, &mut ku);
            let mm = s.dynamics().mass.get(1, 1);
            let dt2 = (0.9 * limit) * (0.9 * limit);
            let free1 = 2.0 * u0[1] - um[1] - dt2 * ku[1] / mm;
            assert!((u1[1] - free1).abs() <= 1e-14, "node 1 moved by the correction: {} vs {}", u1[1], free1);
        }
        let e = s.energy().unwrap().1;
        let rhs = -0.5 * lam * (u1[0] - um[0]);
        assert!(((e - e_prev) - rhs).abs() <= 1e-13, "ΔE {} vs {}", e - e_prev, rhs);
        assert!(rhs <= 1e-15);
        e_prev = e;
    }
    assert!(contacts > 10, "{contacts}");
    assert!(matches!("taylor-flanagan".parse::<SchemeSpec>().unwrap().build(dynamics(10, BarMass::Mod, 0.0, RightEnd::Clamped, 0.0), 1e-3, &initial(10, 0.1, 1.0, 0.0)), Err(signorini_schemes::SchemeError::MassNotSupported { .. })));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Explicit central difference with a quasi-static massless contact node
    /// (`cd-massless`, below its exact CFL limit): on the reduced system the
    /// Newmark identity with β = 0, γ = 1/2 holds for E = ½VᵀM*V + ½UᵀK'U - F'ᵀU
    /// with λ = -k(-w)⁺ the contact force on node 1.
    #[test]
    fn central_difference_massless_identity(m in 3usize..25, mass_i in 0usize..6, cfl in 0.05f64..0.95, amp in 0.01f64..1.0,
                                            seed in 0.1f64..3.0, gap in -0.3f64..0.0, force in -0.5f64..0.5) {
        use signorini_schemes::SchemeSpec;
        let dy = dynamics(m, MASSLESS[mass_i], gap, RightEnd::Clamped, force);
        let spec: SchemeSpec = "cd-massless".parse().unwrap();
        let dt = cfl * spec.cfl_limit(&dy).unwrap().unwrap();
        let init = initial(dy.n(), amp, seed, gap);
        let mut s = Reduced::new("cd".into(), dy, ReducedLaw::CentralDifference, dt, &init).unwrap();
        let (kf, ms, f) = (s.free_stiffness().clone(), s.reduced_mass().clone(), s.reduced_load().to_vec());
        let energy = |s: &Reduced| {
            let u = &s.displacement()[1..];
            0.5 * ms.quad_form(s.velocity()) + 0.5 * kf.quad_form(u) - dot(&f, u)
        };
        let lam = |r: &signorini_schemes::StepReport| r.lambda.map_or(0.0, |l| l.1);
        let mut l0 = s.lambda_now();
        for _ in 0..60 {
            let (u0, v0, e0) = (s.displacement()[1..].to_vec(), s.velocity().to_vec(), energy(&s));
            let r = s.step().unwrap();
            let (u1, v1, e1) = (s.displacement()[1..].to_vec(), s.velocity().to_vec(), energy(&s));
            let l1 = lam(&r);
            let (du, dv) = (diff(&u1, &u0), diff(&v1, &v0));
            let mut kdu = vec![0.0; du.len()];
            kf.mul_vec(&du, &mut kdu);
            let rhs = -du[0] * 0.5 * (l0 + l1) - 0.25 * dt * dot(&dv, &kdu) - 0.25 * dt * dv[0] * (l1 - l0);
            let scale = rounding_scale(&kf, &ms, &[&u0, &u1], &[&v0, &v1], &[e0, e1]);
            prop_assert!(((e1 - e0) - rhs).abs() <= 1e-11 * scale, "ΔE {} vs {}", e1 - e0, rhs);
            l0 = l1;
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Nitsche + Crank–Nicolson: ΔE = -ΔUᵀ(N^n + N^{n+1})/2 for
    /// E = ½VᵀMV + ½UᵀK_N U - FᵀU, N the Nitsche force vector (any θ, any
    /// mass; a massless node from its second step, as for Newmark).
    #[test]
    fn nitsche_energy_identity(m in 2usize..25, mass_i in 0usize..6, gamma0 in 2.0f64..1000.0, theta in prop_oneof![Just(1.0), Just(0.0), Just(-1.0)],
                               cfl in 0.05f64..20.0, amp in 0.01f64..1.0, seed in 0.1f64..3.0, gap in -0.3f64..0.0, force in -0.5f64..0.5) {
        let dy = dynamics(m, MASSES[mass_i], gap, RightEnd::Clamped, force);
        let mm = dy.mass.clone();
        let init = initial(dy.n(), amp, seed, gap);
        let Ok(mut s) = signorini_schemes::Nitsche::new("n".into(), dy, 0.25, 0.5, gamma0, theta, cfl / m as f64, &init) else {
            // Parameters for which the step matrix is not definite: a typed error, tested elsewhere.
            return Ok(());
        };
        let kn = s.nitsche_stiffness().clone();
        let n = m;
        if MASSES[mass_i].massless_contact_node() {
            s.step().unwrap();
        }
        let mut v = vec![0.0; n];
        for _ in 0..50 {
            let (u0, n0) = (s.displacement().to_vec(), s.force_vector());
            let e0 = s.energy().unwrap().1;
            s.step().unwrap();
            let (u1, n1) = (s.displacement().to_vec(), s.force_vector());
            let e1 = s.energy().unwrap().1;
            let rhs = -0.5 * ((u1[0] - u0[0]) * (n0[0] + n1[0]) + (u1[1] - u0[1]) * (n0[1] + n1[1]));
            s.velocity(&mut v);
            // The Nitsche force carries γ = γ_0 k (k = c²/h = m), and the
            // contact step amplifies the rounding of s_y - γg by 1 + W ≈ γ_0
            // (measured: the mismatch grows like γ_0·γ·eps·|u|², 3e-9 at
            // γ_0 = 973, m = 10, dt = 1.9; 4e-12 at γ_0 = 10).
            let umax = u0.iter().chain(&u1).fold(0.0f64, |a, b| a.max(b.abs()));
            let scale = rounding_scale(&kn, &mm, &[&u0, &u1], &[&v], &[e0, e1]).max(gamma0 * gamma0 * n as f64 * umax * umax);
            prop_assert!(((e1 - e0) - rhs).abs() <= 1e-11 * scale, "ΔE {} vs {}", e1 - e0, rhs);
        }
    }
}

/// As γ_0 grows, Nitsche's solution tends to the exactly projected one
/// (with a massless contact node, where Crank–Nicolson does not chatter and
/// the comparison is not blurred by chaos).
#[test]
fn nitsche_tends_to_the_projection() {
    let dy = dynamics(20, BarMass::Mod, 0.0, RightEnd::Clamped, 0.0);
    let n = dy.n();
    let init = Initial { u: (0..n).map(|i| 0.5 * (1.0 - i as f64 / 20.0)).collect(), v: vec![0.0; n] };
    let mut proj = OneStep::new("cn".into(), dy.clone(), OneStepParams::newmark(0.25, 0.5), 0.005, &init).unwrap();
    for _ in 0..300 {
        proj.step().unwrap();
    }
    let mut last = f64::INFINITY;
    for g0 in [1e2, 1e4, 1e6] {
        let mut s = signorini_schemes::Nitsche::new("n".into(), dy.clone(), 0.25, 0.5, g0, 1.0, 0.005, &init).unwrap();
        for _ in 0..300 {
            s.step().unwrap();
        }
        let d = s.displacement().iter().zip(proj.displacement()).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(d < last, "γ0 = {g0}: {d} not below {last}");
        last = d;
    }
    assert!(last < 1e-4, "{last}");
}
