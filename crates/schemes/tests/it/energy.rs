//! The discrete equations and energy identities of docs/theory.md §4 and §7
//! for the one-step schemes (Newmark presets and any Newmark(β, γ), the
//! θ-method, penalty) and the two-step Paoli–Schatzman / β-scheme (every
//! restitution, β = ¼ and other β, Taylor–Flanagan), on the P1 bar with
//! every mass treatment and on the Hermite beam between two stops.
//!
//! Nothing checked here comes from the scheme under test but its recorded
//! displacements and reported contact forces: `M`, `K` and the loads are
//! assembled in `common` from the element matrices, momenta are rebuilt from
//! the displacements by the scheme's documented update, energies and the
//! work of the time-dependent load are recomputed from them, and the
//! reported force is placed at the time level docs/theory.md §4 documents.
//! Every run has a nonzero gap, a body force and a time-dependent load, and
//! the initial data drive the contact node onto the obstacle.
//!
//! Tolerance: each checked quantity is an algebraic consequence of the
//! scheme's equations, so it holds up to rounding of the terms involved; the
//! check is `|lhs − rhs| <= 1e-11 · scale` with `scale` the largest term
//! (quadratic forms counted as `‖K‖ ‖U‖²`, `‖M‖ ‖V‖²`, products as
//! `‖A‖ ‖x‖`). Measured worst ratios over repeated runs: 1e-13 (penalty,
//! κ up to 3000), 2e-14 (Newmark/θ), 2e-15 (Paoli–Schatzman), 6e-16 (beam);
//! the bugs these tests were checked against (a wrong coefficient, load
//! average, bound or time level) give 1e-7 to 1e-3.

use crate::common;

use common::*;
use proptest::prelude::*;
use signorini_fem::BarMass;
use signorini_schemes::{Initial, SchemeError, SchemeSpec};

const TOL: f64 = 1e-11;

/// The eight mass treatments of docs/theory.md §2.1.2.
const MASSES: [BarMass; 8] = BarMass::ALL;
const MASSIVE: [BarMass; 2] = [BarMass::Std, BarMass::Lumped];

/// A forcing on the bar: shape `h (1 + x_i)` (any vector would do; its sum
/// is below 2) times `A sin(ω t)`. The proptests take `A < |body|/2` with a
/// downward body force, so the total load always pushes the bar onto the
/// obstacle and every run sees contact.
fn bar_forcing(n: usize, m: usize, amp: f64, omega: f64) -> Option<(Vec<f64>, Sine)> {
    let h = 1.0 / m as f64;
    Some(((0..n).map(|i| h * (1.0 + i as f64 * h)).collect(), Sine { amp, omega }))
}

/// The one-step schemes under test, by name (presets) or as their spec, and
/// their momentum-form coefficients from docs/theory.md §4.1–§4.2.
fn one_step_scheme(i: usize, beta: f64, gamma: f64, theta: f64) -> (SchemeSpec, Coefs) {
    match i {
        0 => ("newmark-cn".parse().unwrap(), Coefs::newmark(0.25, 0.5)),
        1 => ("newmark-i".parse().unwrap(), Coefs::newmark(0.5, 1.0)),
        2 => ("newmark-ii".parse().unwrap(), Coefs::newmark(0.5, 0.5)),
        3 => ("backward-euler".parse().unwrap(), Coefs::theta(1.0)),
        4 => (SchemeSpec::theta(theta), Coefs::theta(theta)),
        _ => {
            let beta = beta.max(gamma / 2.0);
            (SchemeSpec::newmark(beta, gamma), Coefs::newmark(beta, gamma))
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Newmark (every preset, any β, γ) and the θ-method with the projection:
    /// the update in momentum form, the contact conditions and the energy
    /// identity of §7.1/§7.2 with the work of the forcing, every step.
    #[test]
    fn one_step_equations_and_energy_identity(m in 2usize..30, mass_i in 0usize..8, scheme in 0usize..6, beta in 0.25f64..0.5, gamma in 0.5f64..0.8,
                                              theta in 0.5f64..=1.0, cfl in 0.05f64..10.0, phi in gap_strategy(), body in -0.5f64..-0.1,
                                              amp in 0.1f64..1.0, omega in 1.0f64..20.0, offset in 0.0f64..0.02, speed in 0.5f64..2.0,
                                              wiggle in 0.0f64..0.5, seed in 0.1f64..3.0, free in proptest::bool::ANY) {
        let gap = gap_of(phi, body);
        let n = if free { m + 1 } else { m };
        let (dy, o) = bar_scene(m, MASSES[mass_i], free, gap, body, bar_forcing(n, m, 0.5 * amp * body.abs(), omega));
        let (spec, cf) = one_step_scheme(scheme, beta, gamma, theta);
        let init = approaching(n, m, gap, offset, speed, wiggle, seed);
        let dt = cfl / m as f64;
        let mut s = spec.build(dy, dt, &init).unwrap();
        let traj = record(s.as_mut(), steps_for(dt, 40));
        check_one_step(&o, &o.k, cf, &init, &traj, point_force(o.n(), 0), TOL);
        let active = check_projection(&o, &traj);
        prop_assert!(active > 0, "{spec}: the run never touched the obstacle");
    }

    /// Penalty (Newmark-CN solved exactly per step, or the explicit central
    /// difference below the CFL limit of the dense pencil (K + κ e₀e₀ᵀ, M)):
    /// the Newmark update and identity with λ the spring force, and the
    /// force is the law λ = κ min(0, u₀ − g), κ = γ_P K₀₀ = γ_P/h.
    #[test]
    fn penalty_equations_identity_and_law(m in 2usize..25, lumped in proptest::bool::ANY, gamma_p in 0.1f64..100.0, explicit in proptest::bool::ANY,
                                          frac in 0.05f64..0.95, phi in gap_strategy(), body in -0.5f64..-0.1, amp in 0.1f64..1.0, omega in 1.0f64..20.0,
                                          offset in 0.0f64..0.02, speed in 0.5f64..2.0, wiggle in 0.0f64..0.5, seed in 0.1f64..3.0) {
        let gap = gap_of(phi, body);
        let mass = if lumped { BarMass::Lumped } else { BarMass::Std };
        let (dy, o) = bar_scene(m, mass, false, gap, body, bar_forcing(m, m, 0.5 * amp * body.abs(), omega));
        let kappa = gamma_p * m as f64;
        let (spec, cf, dt) = if explicit {
            let mut kp = o.k.clone();
            kp[0][0] += kappa;
            let limit = 2.0 / kappa_max(&kp, &o.m).sqrt();
            (SchemeSpec::penalty(gamma_p, true), Coefs::newmark(0.0, 0.5), frac * limit)
        } else {
            (SchemeSpec::penalty(gamma_p, false), Coefs::newmark(0.25, 0.5), frac * 20.0 / m as f64)
        };
        let init = approaching(m, m, gap, offset, speed, wiggle, seed);
        let mut s = spec.build(dy, dt, &init).unwrap();
        let traj = record(s.as_mut(), steps_for(dt, 60));
        check_one_step(&o, &o.k, cf, &init, &traj, point_force(o.n(), 0), TOL);
        let lambdas = traj.lambdas(0);
        let mut engaged = 0;
        for l in 1..=traj.last() {
            let (u, lam) = (traj.at(l)[0], lambdas[l].unwrap());
            let want = kappa * (u - gap).min(0.0);
            engaged += usize::from(want != 0.0);
            prop_assert!((lam - want).abs() <= 1e-13 * kappa * (u.abs() + gap.abs()), "level {}: λ = {} but the spring law gives {}", l, lam, want);
        }
        prop_assert!(engaged > 0, "the spring never engaged");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Paoli–Schatzman with e ∈ {0, ½, 1} or any e, β = ¼ or any β ∈ [¼, ½],
    /// and (massive contact node, dt below the β-scheme's limit from the
    /// dense pencil) β ∈ (0, ¼) and β = 0 (Taylor–Flanagan): the start step,
    /// the two-step equation with the exact forcing means, the restitution
    /// constraint with the gap, and the half-step energy balance.
    #[test]
    fn paoli_schatzman_equations_and_energy_balance(m in 2usize..30, mass_i in 0usize..8, e_i in 0usize..4, e_any in 0.0f64..=1.0, beta_i in 0usize..4,
                                                    beta_hi in 0.25f64..=0.5, beta_lo in 0.01f64..0.25, frac in 0.3f64..0.95, cfl in 0.05f64..10.0,
                                                    phi in gap_strategy(), body in -0.5f64..-0.1, amp in 0.1f64..1.0, omega in 1.0f64..20.0,
                                                    offset in 0.0f64..0.02, speed in 0.5f64..2.0, wiggle in 0.0f64..0.5, seed in 0.1f64..3.0, free in proptest::bool::ANY) {
        let gap = gap_of(phi, body);
        let e = [0.0, 0.5, 1.0, e_any][e_i];
        // β < ¼ needs a massive contact node: use std/lumped for those.
        let mass = if beta_i >= 2 { MASSIVE[mass_i % 2] } else { MASSES[mass_i] };
        let n = if free { m + 1 } else { m };
        let (dy, o) = bar_scene(m, mass, free, gap, body, bar_forcing(n, m, 0.5 * amp * body.abs(), omega));
        let (beta, dt) = match beta_i {
            0 => (0.25, cfl / m as f64),
            1 => (beta_hi, cfl / m as f64),
            2 => (beta_lo, frac * 2.0 / ((1.0 - 4.0 * beta_lo) * kappa_max(&o.k, &o.m)).sqrt()),
            _ => (0.0, frac * 2.0 / kappa_max(&o.k, &o.m).sqrt()),
        };
        let spec = SchemeSpec::ps(e, beta);
        let init = approaching(n, m, gap, offset, speed, wiggle, seed);
        let mut s = spec.build(dy, dt, &init).unwrap();
        let traj = record(s.as_mut(), steps_for(dt, 40));
        let st = check_ps(&o, beta, e, &init, &traj);
        prop_assert!(st.active > 0, "{}: the run never touched the obstacle", spec);
    }
}

/// The Hermite beam between two stops, driven by a sine load: Newmark (every
/// preset; the banded, non-tridiagonal update path) and the θ-method with
/// the two-sided projection, and the β-scheme (β = ¼, 0.3, and 0.1 below
/// its limit from the dense pencil), each checked step by step with the
/// beam matrices multiplied here. Both stops must be hit.
#[test]
fn beam_between_stops_one_step_and_beta_scheme() {
    let j = 8;
    let n = 2 * j;
    let shape: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 1.0 / j as f64 } else { 0.0 }).collect();
    let (lo, hi) = (-0.05, 0.04);
    let (dy, o) = beam_scene(j, 1.0, lo, hi, shape, Sine { amp: 12.0, omega: 9.0 });
    let init = Initial { u: vec![0.0; n], v: (0..n).map(|i| if i % 2 == 0 { 0.1 * (i / 2 + 1) as f64 / j as f64 } else { 0.0 }).collect() };
    let dt = 2e-3;
    let counts = |traj: &Traj, lag: usize| {
        let l = traj.lambdas(lag);
        (l.iter().flatten().filter(|x| **x < 0.0).count(), l.iter().flatten().filter(|x| **x > 0.0).count())
    };
    for i in 0..5 {
        let (spec, cf) = one_step_scheme(i, 0.3, 0.6, 0.7);
        let mut s = spec.build(dy.clone(), dt, &init).unwrap();
        let traj = record(s.as_mut(), 500);
        let st = check_one_step(&o, &o.k, cf, &init, &traj, point_force(n, o.c), TOL);
        check_projection(&o, &traj);
        let (down, up) = counts(&traj, 0);
        assert!(down > 3 && up > 3, "{spec}: contact levels on the lower stop {down}, upper {up}");
        println!("beam {spec}: worst update residual {:.1e}, energy identity {:.1e}; contact levels {down}/{up}", st.residual.ratio, st.energy.ratio);
    }
    let kappa = kappa_max(&o.k, &o.m);
    for (beta, dt) in [(0.25, dt), (0.3, dt), (0.1, 0.9 * 2.0 / ((1.0 - 0.4) * kappa).sqrt())] {
        let spec = SchemeSpec::ps(0.0, beta);
        let mut s = spec.build(dy.clone(), dt, &init).unwrap();
        let steps = (1.0 / dt) as usize;
        let traj = record(s.as_mut(), steps);
        let st = check_ps(&o, beta, 0.0, &init, &traj);
        let (down, up) = counts(&traj, 1);
        assert!(down > 3 && up > 3, "{spec}: contact levels on the lower stop {down}, upper {up}");
        println!("beam {spec} (dt {dt:.3e}): worst residual {:.1e}, energy balance {:.1e}; contact levels {down}/{up}", st.residual.ratio, st.energy.ratio);
    }
}

/// Crank–Nicolson and the midpoint rule conserve the energy recomputed from
/// the trajectory when the obstacle is out of reach and the load is steady
/// (every mass treatment, 2000 steps, dt far beyond any CFL limit).
#[test]
fn crank_nicolson_and_midpoint_conserve_energy_without_contact() {
    for mass in MASSES {
        for (spec, cf) in [("newmark-cn", Coefs::newmark(0.25, 0.5)), ("theta(0.5)", Coefs::theta(0.5))] {
            let (dy, o) = bar_scene(17, mass, false, -1e6, 0.3, None);
            let init = approaching(17, 17, 0.0, 0.1, 0.7, 0.3, 1.3);
            let spec: SchemeSpec = spec.parse().unwrap();
            let mut s = spec.build(dy, 0.37, &init).unwrap();
            let traj = record(s.as_mut(), 2000);
            assert_eq!(traj.active_steps(), 0);
            // The identity says ΔE = 0 here, step by step, to rounding.
            let st = check_one_step(&o, &o.k, cf, &init, &traj, |_, _, _| vec![0.0; 17], TOL);
            assert!(st.energy.ratio < 1e-12, "{mass} {spec}: {:e}", st.energy.ratio);
        }
    }
}

/// One deterministic contact-heavy case per family, so the checks above are
/// known to see many impacts: Newmark-CN and ps-e0.5 with a gap of 0.1 and a
/// downward body force (the bar settles on the obstacle and bounces).
#[test]
fn contact_heavy_runs_satisfy_the_same_checks() {
    for mass in [BarMass::Std, BarMass::Mod] {
        let (dy, o) = bar_scene(10, mass, false, 0.1, -2.0, bar_forcing(10, 10, 1.0, 6.0));
        let init = approaching(10, 10, 0.1, 0.3, 1.0, 0.0, 1.0);
        let mut s = "newmark-cn".parse::<SchemeSpec>().unwrap().build(dy.clone(), 0.05, &init).unwrap();
        let traj = record(s.as_mut(), 200);
        let st = check_one_step(&o, &o.k, Coefs::newmark(0.25, 0.5), &init, &traj, point_force(10, 0), TOL);
        let active = check_projection(&o, &traj);
        assert!(active > 10, "{mass} newmark-cn: {active} contact levels");
        println!("{mass} newmark-cn: residual {:.1e}, energy {:.1e}, {active} contact levels", st.residual.ratio, st.energy.ratio);
        let mut s = "ps-e0.5".parse::<SchemeSpec>().unwrap().build(dy, 0.05, &init).unwrap();
        let traj = record(s.as_mut(), 200);
        let st = check_ps(&o, 0.25, 0.5, &init, &traj);
        assert!(st.active > 10, "{mass} ps-e0.5: {} contact levels", st.active);
        println!("{mass} ps-e0.5: residual {:.1e}, energy {:.1e}, {} contact levels", st.residual.ratio, st.energy.ratio, st.active);
    }
}

/// Taylor–Flanagan (`ps(0, 0)`, lumped mass, dt at 0.9 of the limit computed
/// here from the dense pencil): the correction moves the contact node only
/// (node 1 follows the free central-difference update), puts it exactly on
/// the obstacle, and contact never adds energy.
#[test]
fn taylor_flanagan_corrects_the_contact_node_only_and_dissipates() {
    let m = 30;
    let (dy, o) = bar_scene(m, BarMass::Lumped, false, 0.05, -1.0, None);
    let limit = 2.0 / kappa_max(&o.k, &o.m).sqrt();
    // Lumped P1 bar: κ_max → 4/h² as m grows, so dt_c ≈ h.
    assert!((limit * m as f64 - 1.0).abs() < 0.01, "CFL limit {limit}");
    let dt = 0.9 * limit;
    let init = approaching(m, m, 0.05, 0.2, 0.5, 0.1, 1.0);
    let spec: SchemeSpec = "taylor-flanagan".parse().unwrap();
    let mut s = spec.build(dy, dt, &init).unwrap();
    let traj = record(s.as_mut(), 600);
    let st = check_ps(&o, 0.0, 0.0, &init, &traj);
    assert!(st.active > 10, "{} contact steps", st.active);
    let lambdas = traj.lambdas(1);
    for l in 2..traj.last() {
        let (um, u0, u1) = (traj.at(l - 1), traj.at(l), traj.at(l + 1));
        let lam = lambdas[l].unwrap();
        assert!(lam <= 0.0);
        if lam != 0.0 {
            assert_eq!(u1[0], 0.05);
            let ku = mul(&o.k, u0);
            let free1 = 2.0 * u0[1] - um[1] + dt * dt * (o.load[1] - ku[1]) / o.m[1][1];
            assert!((u1[1] - free1).abs() <= 1e-14, "node 1 moved by the correction: {} vs {}", u1[1], free1);
            // Contact work −½ λ (u₀ⁿ⁺¹ − u₀ⁿ⁻¹) = ½ λ (u₀ⁿ⁻¹ − g) <= 0.
            assert!(0.5 * lam * (um[0] - 0.05) <= 0.0);
        }
    }
    assert!(matches!(spec.build(bar_scene(10, BarMass::Mod, false, 0.0, 0.0, None).0, 1e-3, &approaching(10, 10, 0.0, 0.1, 0.1, 0.0, 1.0)), Err(SchemeError::MassNotSupported { .. })));
}

/// The explicit penalty scheme refuses a step just beyond the CFL limit of
/// the dense pencil `(K + κ e₀e₀ᵀ, M)` computed here, reports that limit,
/// and accepts a step just below it.
#[test]
fn explicit_penalty_refuses_steps_beyond_its_cfl_limit() {
    let (dy, o) = bar_scene(20, BarMass::Lumped, false, 0.0, 0.0, None);
    let init = approaching(20, 20, 0.0, 0.1, 0.3, 0.0, 1.0);
    let spec: SchemeSpec = "penalty-cd(10)".parse().unwrap();
    let mut kp = o.k.clone();
    kp[0][0] += 10.0 * 20.0;
    let limit = 2.0 / kappa_max(&kp, &o.m).sqrt();
    assert!(limit > 0.01 && limit < 0.05, "{limit}");
    match spec.build(dy.clone(), limit * 1.001, &init) {
        Err(SchemeError::Unstable { dt, limit: l, .. }) => assert!((l - limit).abs() < 1e-10 * limit && dt > l, "limit {l} vs {limit}"),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted beyond the CFL limit"),
    }
    assert!(spec.build(dy, limit * 0.999, &init).is_ok());
    let massless = bar_scene(20, BarMass::Mod, false, 0.0, 0.0, None).0;
    assert!(matches!(spec.build(massless, 1e-4, &init), Err(SchemeError::MassNotSupported { .. })));
    assert!(matches!("penalty(0)".parse::<SchemeSpec>(), Err(SchemeError::Invalid { field: "gamma_p", .. })));
}

/// The fused explicit step of `PaoliSchatzman` (β = 0, diagonal mass,
/// tridiagonal stiffness, one massive contact, no damping, no
/// time-dependent load) is the general path's arithmetic: the same problem
/// with a zero damping matrix (which takes the general path and only adds
/// exact zeros) gives equal displacements, forces and energies at every
/// step (`==`), for `cd-taylor`, both far ends, through impacts and
/// releases. (`taylor-flanagan` steps through the same code, but its
/// Newmark start step takes another path with a damping matrix.)
#[test]
fn fused_explicit_step_is_the_general_path_number_for_number() {
    for name in ["cd-taylor"] {
        let spec: SchemeSpec = name.parse().unwrap();
        for free in [true, false] {
            let m = 40;
            let (dy, _) = bar_scene(m, BarMass::Lumped, free, 0.05, -1.0, None);
            let n = dy.n();
            let init = approaching(n, m, 0.05, 0.2, 0.5, 0.1, 1.0);
            let dt = 0.9 / m as f64;
            let mut general = dy.clone();
            general.damping = Some(signorini_fem::SymBand::zeros(n, 1));
            let (mut a, mut b) = (spec.build(dy, dt, &init).unwrap(), spec.build(general, dt, &init).unwrap());
            let mut contacts = 0;
            for step in 0..3000 {
                let (ra, rb) = (a.step().unwrap(), b.step().unwrap());
                assert_eq!(ra.lambda, rb.lambda, "{name} free {free}: λ at step {step}");
                assert!(a.displacement().iter().zip(b.displacement()).all(|(x, y)| x == y), "{name} free {free}: U at step {step}");
                assert_eq!(a.energy(), b.energy(), "{name} free {free}: energy at step {step}");
                contacts += usize::from(ra.lambda.is_some_and(|l| l.1 != 0.0));
            }
            assert!(contacts > 10, "{name} free {free}: {contacts} contact steps");
        }
    }
}

/// The strict explicit schemes (`taylor-flanagan` = `ps(0,0)`) refuse
/// `dt >= limit · (1 + 1e-11)`: on the lumped bar with a free far end the
/// exact limit is `h` (closed form, docs/theory.md §2.4); the reported
/// limit (a certified bound) is never above it by more than the rounding of
/// `h` itself and within 1e-14 below it; `dt = h` is accepted (the
/// Courant-one study runs it, as it did when the limit came from a Rayleigh
/// quotient) and `1 + 1e-10` times it refused.
#[test]
fn strict_explicit_schemes_leave_only_round_off_at_the_limit() {
    let spec: SchemeSpec = "taylor-flanagan".parse().unwrap();
    for m in [5usize, 10, 80, 1000] {
        let h = 1.0 / m as f64;
        let dy = bar_scene(m, BarMass::Lumped, true, 0.0, 0.0, None).0;
        let init = approaching(m + 1, m, 0.0, 0.1, 0.3, 0.0, 1.0);
        let reported = spec.cfl_limit(&dy).unwrap().unwrap();
        assert!(reported <= h * (1.0 + 4.0 * f64::EPSILON) && reported >= h * (1.0 - 1e-14), "m = {m}: reported {reported:e}, exact h = {h:e}");
        assert!(spec.build(dy.clone(), h, &init).is_ok(), "m = {m}: dt = h refused");
        match spec.build(dy, h * (1.0 + 1e-10), &init) {
            Err(SchemeError::Unstable { limit, .. }) => assert_eq!(limit, reported),
            Err(e) => panic!("m = {m}: {e}"),
            Ok(_) => panic!("m = {m}: accepted 1 + 1e-10 times the exact limit"),
        }
    }
}

/// `cd-taylor` takes dt up to and including its CFL limit `2/ω_max` and
/// refuses beyond it, the limit from the closed-form spectrum of the lumped
/// P1 bar (c = 1, h = 1/m): `(h/2) ü₀ = (u₁ − u₀)/h` at node 0 is the
/// interior equation `h ü_i = (u_{i−1} − 2u_i + u_{i+1})/h` with the mirror
/// `u_{−1} = u₁`, so the modes are `u_i = cos(θ i)` with
/// `ω² = (4/h²) sin²(θ/2)`. A free far end mirrors too: `θ = jπ/m`,
/// `j = 0..=m`, `ω_max = 2/h` and the limit is `h` (Courant number one);
/// a clamped one needs `cos(θ m) = 0`: `θ = (2j − 1)π/(2m)`, `j = 1..=m`,
/// `ω_max = (2/h) cos(π/(4m))` and the limit `h / cos(π/(4m))`. The
/// computed limit equals the closed form to 1e-10; the step equal to the
/// closed form is accepted, and so is 1 + 1e-10 times it (the room the
/// crate leaves for the round-off of its computed limit: measured, that
/// limit is one ulp below `h` at m = 5 with a free end, up to 6e-14 above
/// it for m < 80); 1.001 and 1 + 1e-6 times it are refused, naming the
/// limit — room for round-off, not for a step beyond the limit.
#[test]
fn cd_taylor_takes_its_cfl_limit_and_refuses_beyond() {
    let spec: SchemeSpec = "cd-taylor".parse().unwrap();
    for free in [true, false] {
        for m in [5usize, 10, 25] {
            let h = 1.0 / m as f64;
            let limit = if free { h } else { h / (std::f64::consts::PI / (4.0 * m as f64)).cos() };
            let (dy, _) = bar_scene(m, BarMass::Lumped, free, 0.0, 0.0, None);
            let n = if free { m + 1 } else { m };
            let init = approaching(n, m, 0.0, 0.1, 0.3, 0.0, 1.0);
            let reported = spec.cfl_limit(&dy).unwrap().unwrap();
            assert!((reported - limit).abs() <= 1e-10 * limit, "free {free} m = {m}: computed limit {reported:e}, closed form {limit:e}");
            for factor in [1.0, 1.0 + 1e-10] {
                assert!(spec.build(dy.clone(), factor * limit, &init).is_ok(), "free {free} m = {m}: refused dt = {factor} × the limit {limit:e}");
            }
            for factor in [1.001, 1.0 + 1e-6] {
                match spec.build(dy.clone(), factor * limit, &init) {
                    Err(SchemeError::Unstable { dt, limit: l, .. }) => {
                        assert!(dt == factor * limit && (l - limit).abs() <= 1e-10 * limit, "free {free} m = {m}: refusal names {l:e}, closed form {limit:e}")
                    }
                    Err(e) => panic!("free {free} m = {m}: {e}"),
                    Ok(_) => panic!("free {free} m = {m}: accepted {factor} × the limit {limit:e}"),
                }
            }
        }
    }
}

/// The bar's energy `½ Pᵀ M⁺ P + ½ Uᵀ K U − Fᵀ U` (summed in one fused pass on the
/// tridiagonal path) is, bit for bit, the sum of the three separate forms of
/// `signorini-fem` (`BandLdlt::inverse_quad_form` of `M`'s massive block,
/// `SymBand::quad_form`, the load's dot product) evaluated on the scheme's
/// own `P` and `U` — every mass treatment (massless contact node or not),
/// free and clamped ends, after steps with and without contact. The energy
/// is written to `data/reference` (the convergence CSVs' energy errors), so
/// a faster form must not move its last bit.
#[test]
fn bar_energy_is_the_three_separate_forms_bit_for_bit() {
    use signorini_schemes::{OneStep, OneStepParams, Stepper};
    for mass in MASSES {
        for free in [false, true] {
            for m in [2usize, 3, 17] {
                let (dy, _) = bar_scene(m, mass, free, 0.0, -0.2, bar_forcing(if free { m + 1 } else { m }, m, 0.05, 7.0));
                let n = dy.n();
                let init = approaching(n, m, 0.0, 0.01, 0.6, 0.3, 2.0);
                let s = usize::from(mass.massless_contact_node());
                let m_massive = dy.mass.trailing(s).factor().unwrap();
                let (k, load) = (dy.stiffness.clone(), dy.load.clone());
                let mut st = OneStep::new("cn".into(), dy, OneStepParams::newmark(0.25, 0.5), 0.01, &init).unwrap();
                for step in 0..40 {
                    let (u, p) = (st.displacement().to_vec(), st.momentum().to_vec());
                    let lw: f64 = load.iter().zip(&u).map(|(f, u)| f * u).sum();
                    let expected = 0.5 * m_massive.inverse_quad_form(&p[s..]) + 0.5 * k.quad_form(&u) - lw;
                    let got = st.energy().unwrap().1;
                    assert!(got.to_bits() == expected.to_bits(), "{mass:?} free {free} m = {m}, step {step}: {got:e} vs {expected:e}");
                    st.step().unwrap();
                }
            }
        }
    }
}

/// With [`Stepper::fuse_energy`] on, the bar's Newmark/θ step ends by
/// assembling and forward-sweeping the next step's right-hand side in one
/// loop with the new level's energy sums. That changes no bit: against the
/// same scheme with it off, `U`, `P`, `R`, the contact force and status are
/// equal (`to_bits`) at every step, and the fused energy equals, bit for
/// bit, the three separate forms of `signorini-fem` on the scheme's own `P`
/// and `U` — every mass treatment, free and clamped ends, Newmark-CN, θ,
/// the penalty law, through impacts and releases, across a `set_state`
/// (which drops the step assembled ahead) and with the hint switched off
/// and on again mid-run; on bars of one block of the fused step's rows and
/// of several.
#[test]
fn fused_energy_step_is_the_plain_step_bit_for_bit() {
    use signorini_schemes::{ContactLaw, OneStep, OneStepParams, Stepper};
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
    for mass in MASSES {
        for free in [false, true] {
            // The fused step works in blocks of 32 rows: 64 is two blocks
            // (clamped, n = m) or two and one row (free, n = m + 1); 700
            // many, the last one partial.
            for m in [2usize, 3, 17, 64, 700] {
                for (prm, law) in [
                    (OneStepParams::newmark(0.25, 0.5), ContactLaw::Projection),
                    (OneStepParams::theta(0.7), ContactLaw::Projection),
                    (OneStepParams::newmark(0.3, 0.6), ContactLaw::Penalty { stiffness: 50.0 }),
                ] {
                    let (dy, _) = bar_scene(m, mass, free, 0.0, -0.2, None);
                    let n = dy.n();
                    let init = approaching(n, m, 0.0, 0.01, 0.6, 0.3, 2.0);
                    let s = usize::from(mass.massless_contact_node());
                    let m_massive = dy.mass.trailing(s).factor().unwrap();
                    let (k, load) = (dy.stiffness.clone(), dy.load.clone());
                    let build = || OneStep::new("cn".into(), dy.clone(), prm, 0.01, &init).unwrap().with_contact_law(law).unwrap();
                    let (mut plain, mut fused) = (build(), build());
                    fused.fuse_energy(true);
                    let mut contacts = 0;
                    for step in 0..120 {
                        // A perturbed state through `set_state` on both
                        // (offered with a massive contact node).
                        if let (50, Some(mut st)) = (step, plain.state()) {
                            st.iter_mut().enumerate().for_each(|(i, x)| *x += 1e-3 * (i as f64).sin());
                            plain.set_state(&st).unwrap();
                            fused.set_state(&st).unwrap();
                        }
                        if step == 80 || step == 83 {
                            fused.fuse_energy(step == 83);
                        }
                        let (ra, rb) = (plain.step().unwrap(), fused.step().unwrap());
                        assert_eq!(ra, rb, "{mass:?} free {free} m = {m} {prm:?}: report at step {step}");
                        for (what, a, b) in [("U", plain.displacement(), fused.displacement()), ("P", plain.momentum(), fused.momentum()), ("R", plain.mass_acceleration(), fused.mass_acceleration())]
                        {
                            assert!(bits(a) == bits(b), "{mass:?} free {free} m = {m} {prm:?}: {what} at step {step}");
                        }
                        let (u, p) = (fused.displacement().to_vec(), fused.momentum().to_vec());
                        let lw: f64 = load.iter().zip(&u).map(|(f, u)| f * u).sum();
                        let spring = match law {
                            ContactLaw::Penalty { stiffness } => 0.5 * stiffness * (0.0 - u[0]).max(0.0).powi(2),
                            ContactLaw::Projection => 0.0,
                        };
                        let expected = 0.5 * m_massive.inverse_quad_form(&p[s..]) + 0.5 * k.quad_form(&u) - lw + spring;
                        let (ea, eb) = (plain.energy().unwrap(), fused.energy().unwrap());
                        assert!(eb.1.to_bits() == expected.to_bits() && ea == eb, "{mass:?} free {free} m = {m} {prm:?}, step {step}: {:e} vs {expected:e}", eb.1);
                        contacts += usize::from(rb.lambda.is_some_and(|l| l.1 != 0.0));
                    }
                    assert!(contacts > 3, "{mass:?} free {free} m = {m} {prm:?}: {contacts} contact steps");
                }
            }
        }
    }
}
