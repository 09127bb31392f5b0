//! The library against an independent reference on `bar-dirichlet`
//! (`tests/support/independent_bar.rs`: d'Alembert exact solution, dense
//! matrices and LU, Newmark in (U, V, A) form, Paoli–Schatzman with the
//! massless row as an equilibrium, norms by bisection to affine pieces).
//!
//! * the reference's exact solution against the problem statement and the
//!   table of docs/theory.md §5.1 (so the reference is checked on its own);
//! * step by step, for newmark-cn, newmark-i, ps-e0, ps-e0.5 with std and mod mass:
//!   the displacement, the contact force **and the time level it belongs
//!   to** (README: `t_{n+1}` for Newmark, `t_n` for Paoli–Schatzman,
//!   `t_{n+1}` with a massless node), the discrete energy and its time;
//!   once on the benchmark and once with the obstacle at `g = 0.1`, where
//!   Paoli–Schatzman's bound `(1 + e) g - e u_0^{n-1}` has its `g` term;
//! * the stored values of `data/reference/independent/` are what the
//!   reference computes today (the CLI's test compares its output with them).
//!
//! Tolerances: both sides compute the same finite-dimensional trajectory by
//! different arithmetic (LU with pivoting vs banded LDLᵀ, (U, V, A) vs
//! momentum form, a second solve vs the closed-form projection), so they
//! differ by rounding, amplified at each impact; λ inherits the difference
//! in `U` times `M/(β dt²)`, about `4 RATIO² m |ΔU|`. Measured at m = 20
//! over the comparable levels (`reference::comparable_steps`), both gaps:
//! at most 1.1e-12 in `U`, 9.4e-10 in `|Δλ|/(1 + |λ|)` (newmark-cn/std at
//! its first impact with g = 0.1; 3.1e-11 for every other pair), 3.8e-11
//! relative in the energy. The bounds below leave 9–26x margin over the
//! worst and are far below what a wrong coefficient, mass entry or bound
//! produces (planted: a 0.1 % error in one `mod` mass entry, 2.4e-7 in
//! `U^1`; Paoli–Schatzman's bound without its `(1 + e)` on `g`, 2e-3 in
//! `U`); a wrong time level is caught exactly.

#[path = "support/independent_bar.rs"]
mod reference;

use reference::{exact_lambda, exact_u, exact_ut, exact_ux, Mass, Scheme, CONFIGS};
use signorini::fem::{Bar, BarMass, RightEnd};
use signorini::run::{BarProblem, Benchmark};
use signorini::schemes::{SchemeSpec, Stepper};
use std::path::Path;

/// The mesh of the step-by-step comparison (600 steps over a period).
const M: usize = 20;

/// Bounds of the step-by-step comparison (see the module docs).
const TOL_U: f64 = 1e-11;
const TOL_LAMBDA: f64 = 1e-8;
const TOL_ENERGY: f64 = 1e-9;

fn library_mass(m: Mass) -> BarMass {
    m.name().parse().unwrap()
}

/// The library's scheme on `m` elements: the library's own benchmark
/// problem when `gap = 0`, the same bar and data with the obstacle at `gap`
/// otherwise.
fn library_stepper(scheme: Scheme, mass: Mass, m: usize, gap: f64) -> Box<dyn Stepper> {
    let problem = if gap == 0.0 {
        let exact = Benchmark::BarDirichlet.exact(3.0).unwrap();
        Benchmark::BarDirichlet.problem(exact.as_ref(), m, library_mass(mass)).unwrap()
    } else {
        let bar = Bar::new(1.0, m, 1.0, RightEnd::Clamped).unwrap();
        BarProblem::new(bar, library_mass(mass), gap, 0.0, |x| 0.5 * (1.0 - x), |_| 0.0).unwrap()
    };
    let spec: SchemeSpec = scheme.name().parse().unwrap();
    let dt = problem.bar.h() / reference::RATIO as f64;
    spec.build(problem.dynamics(), dt, &problem.initial).unwrap()
}

/// The exact solution of the reference reproduces the data, the boundary
/// conditions, Signorini's conditions, the energy 1/8 and the table of
/// docs/theory.md §5.1 (the paper's zones, with its sign typo corrected).
#[test]
fn reference_exact_solution_is_the_benchmark() {
    for i in 0..=100 {
        let x = i as f64 / 100.0;
        assert!((exact_u(x, 0.0) - 0.5 * (1.0 - x)).abs() < 1e-15, "u0 at {x}");
        if i > 0 && i < 100 {
            assert_eq!(exact_ut(x, 0.0), 0.0, "v0 at {x}");
        }
    }
    for i in 0..=3000 {
        let t = i as f64 * 1e-3 + 1e-4; // off the jump instants
        assert!(exact_u(1.0, t).abs() < 1e-15, "clamped end at {t}");
        let (gap, lambda) = (exact_u(0.0, t), exact_lambda(t));
        assert!(gap >= -1e-15 && lambda <= 0.0 && (gap * lambda).abs() < 1e-15, "Signorini at {t}: u(0) = {gap}, λ = {lambda}");
        assert_eq!(lambda, exact_ux(0.0, t));
        let touching = (1.0..2.0).contains(&t.rem_euclid(3.0));
        assert_eq!(lambda, if touching { -0.5 } else { 0.0 }, "λ({t})");
    }
    // The level version agrees with λ(t) off the jumps and is right-continuous at them.
    for m in [20, 80] {
        for k in 0..=3 * reference::RATIO * m {
            let t = k as f64 / (reference::RATIO * m) as f64;
            assert_eq!(reference::exact_lambda_at_level(k, m), exact_lambda(t + 1e-9), "λ at level {k} of m = {m}");
        }
    }
    // Energy 1/2 ∫ (u_t² + u_x²) = 1/8 by a midpoint sum (piecewise constant integrand).
    for t in [0.3, 1.1, 1.9, 2.45, 2.99] {
        let n = 100_000;
        let e: f64 = (0..n).map(|i| (i as f64 + 0.5) / n as f64).map(|x| 0.5 * (exact_ut(x, t).powi(2) + exact_ux(x, t).powi(2))).sum::<f64>() / n as f64;
        assert!((e - reference::EXACT_ENERGY).abs() < 1e-12, "E({t}) = {e}");
    }
    // The exact test values of docs/theory.md §5.1 (away from the kinks; the
    // paper's §5.1 eqs. (38)–(39) zone by zone, the last two a period later).
    // (An earlier version of this table expected u(0.25, 0.5) = 0.375, the
    // zone-I value (1 - x)/2; but x = 0.25 < t = 0.5 lies in zone II, behind
    // the characteristic from x = 0, where the paper's (38b) gives
    // (1 - t)/2 = 0.25: the expectation was wrong, not the reference.)
    let table = [
        // x, t, u, u_x, u_t
        (0.25, 0.5, 0.25, 0.0, -0.5),
        (0.75, 0.5, 0.125, -0.5, 0.0),
        (0.2, 1.5, -0.1, -0.5, 0.0),
        (0.3, 1.2, -0.1, 0.0, -0.5),
        (0.8, 1.5, -0.1, 0.5, 0.0),
        (0.6, 1.7, -0.15, 0.0, 0.5),
        (0.2, 2.5, 0.25, 0.0, 0.5),
        (0.8, 2.5, 0.1, -0.5, 0.0),
        (0.4, 3.3, 0.3, -0.5, 0.0),
        (0.9, 7.6, -0.05, 0.5, 0.0),
    ];
    for (x, t, u, ux, ut) in table {
        assert!((exact_u(x, t) - u).abs() < 1e-15, "u({x}, {t}) = {} instead of {u}", exact_u(x, t));
        assert_eq!((exact_ux(x, t), exact_ut(x, t)), (ux, ut), "(u_x, u_t)({x}, {t})");
    }
}

/// The reference's space norms on known cases: the interpolant of `u(·, 0)`
/// (affine, so exact: zero error), and a P1 function whose error against
/// the exact solution is worked out by hand at `t = 0.5` (zero nodal
/// values: `∫ u² = ∫₀^½ 1/16 + ∫_½^1 (1 - x)²/4 = 1/32 + 1/96`,
/// `∫ u_x² = ½ · 1/4`).
#[test]
fn reference_space_norms_on_known_cases() {
    let m = 20;
    let u0: Vec<f64> = (0..m).map(|i| 0.5 * (1.0 - i as f64 / m as f64)).collect();
    let (l2, semi) = reference::space_errors(&u0, 0.0);
    assert!(l2 < 1e-15 && semi < 1e-14, "interpolant of the initial data: {l2:e}, {semi:e}");
    let (l2, semi) = reference::space_errors(&vec![0.0; m], 0.5);
    assert!((l2 - (1.0f64 / 32.0 + 1.0 / 96.0).sqrt()).abs() < 1e-14, "{l2}");
    assert!((semi - 0.125f64.sqrt()).abs() < 1e-14, "{semi}");
    // A kink inside an element (x = 0.5 + 1/(3m) at t = 0.5 + 1/(3m)) is found.
    let t = 0.5 + 1.0 / (3.0 * m as f64);
    let (l2, semi) = reference::space_errors(&vec![0.0; m], t);
    let tau = t;
    let exact_l2 = (tau * (1.0 - tau).powi(2) / 4.0 + (1.0 - tau).powi(3) / 12.0).sqrt();
    assert!((l2 - exact_l2).abs() < 1e-13, "{l2} vs {exact_l2}");
    assert!((semi - ((1.0 - tau) / 4.0).sqrt()).abs() < 1e-13, "{semi}");
}

/// The largest deviations of the library from the reference over the
/// comparable steps of (scheme, mass) on `m` elements, obstacle at `gap`
/// (a period, or the first impact of the chaotic pair); panics with
/// the step named at the first deviation beyond the bounds or at a force
/// reported at another time than the README's.
fn compare_steps(scheme: Scheme, mass: Mass, m: usize, gap: f64) -> [f64; 3] {
    let name = format!("{}/{} (g = {gap})", scheme.name(), mass.name());
    let r = reference::simulate(scheme, mass, m, gap, reference::T_END * reference::RATIO * m);
    let steps = reference::comparable_steps(scheme, mass, &r);
    let mut s = library_stepper(scheme, mass, m, gap);
    let dt = r.dt;
    assert!((s.dt() - dt).abs() <= 1e-15 * dt, "{name}: dt");
    let mut worst = [0.0f64; 3];
    let check_u = |level: usize, u: &[f64]| {
        let d = u.iter().zip(&r.u[level]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(d <= TOL_U, "{name}: U^{level} differs from the reference by {d:e}");
        d
    };
    // Two-step schemes arrive at level 1 (their start step) and report no force for it.
    worst[0] = check_u(s.level(), s.displacement());
    let mut energies = r.energies.iter();
    let check_e = |te: f64, e: f64, (half, er): (usize, f64), what: &str| {
        let expected = half as f64 * 0.5 * dt;
        assert!((te - expected).abs() <= 1e-9 * dt, "{name}: {what} at t = {te}, expected {expected}");
        let d = (e - er).abs() / er.abs();
        assert!(d <= TOL_ENERGY, "{name}: {what} = {e} vs reference {er}");
        d
    };
    let (te, e) = s.energy().expect("E^0 or E^{1/2}");
    worst[2] = check_e(te, e, *energies.next().unwrap(), "start energy");
    let mut forces = r.lambdas.iter();
    let mut contact = 0;
    while s.level() < steps {
        let rep = s.step().unwrap();
        worst[0] = worst[0].max(check_u(rep.n, s.displacement()));
        let (t, lambda) = rep.lambda.unwrap_or_else(|| panic!("{name}: step to level {} reports no force", rep.n));
        let &(k, lr) = forces.next().expect("as many forces as the reference");
        let documented = k as f64 * dt;
        assert!(
            (t - documented).abs() <= 1e-9 * dt,
            "{name}: the force of the step to level {} is reported at t = {t}; the README's level is t_{k} = {documented} ({})",
            rep.n,
            if k == rep.n { "t_{n+1}" } else { "t_n" }
        );
        let d = (lambda - lr).abs() / (1.0 + lr.abs());
        assert!(d <= TOL_LAMBDA, "{name}: λ at t_{k} = {lambda} vs reference {lr}");
        worst[1] = worst[1].max(d);
        contact += usize::from(lr < -0.1);
        let (te, e) = s.energy().unwrap();
        worst[2] = worst[2].max(check_e(te, e, *energies.next().unwrap(), &format!("energy of level {}", rep.n)));
    }
    if steps == r.steps {
        assert!(forces.next().is_none() && energies.next().is_none(), "{name}: the reference has more samples than the library produced");
    }
    // The comparison is not vacuous: the bar touched and the force was felt.
    let needed = if reference::chaotic(scheme, mass) { 1 } else { 50 };
    assert!(contact >= needed, "{name}: {contact} contact steps");
    eprintln!("{name}: {steps} steps, max |ΔU| = {:.1e}, |Δλ|/(1+|λ|) = {:.1e}, |ΔE|/E = {:.1e}", worst[0], worst[1], worst[2]);
    worst
}

/// Step by step against the reference on the benchmark: `U^n`, `λ` with its
/// time level, the energy with its time level, over the levels where the
/// pair is reproducible (a period; the first impact for std-mass Newmark,
/// which chatters: `reference::chaotic`). A force reported one step early or
/// late fails here with the step named.
#[test]
fn steps_forces_and_their_time_levels_match_the_reference() {
    for (scheme, mass) in CONFIGS {
        compare_steps(scheme, mass, M, 0.0);
    }
}

/// The same with the obstacle at `g = 0.1`: Paoli–Schatzman's bound
/// `u_0^{n+1} >= (1 + e) g - e u_0^{n-1}` has a `g` term (at `g = 0` a wrong
/// factor on it is invisible).
#[test]
fn steps_match_the_reference_with_a_nonzero_gap() {
    for (scheme, mass) in CONFIGS {
        compare_steps(scheme, mass, M, 0.1);
    }
}

fn stored_path() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(reference::STORED_PATH)
}

/// The stored values (read by the CLI's tests) are what the independent
/// reference computes: regenerated here and compared to 1e-12 (they are
/// written with 16 significant digits; the reference uses only `+ - * /`,
/// `floor` and `rem_euclid`, all exact or correctly rounded, in a fixed
/// order, so it is deterministic on any IEEE platform).
#[test]
fn stored_values_are_current() {
    let text = std::fs::read_to_string(stored_path()).expect("data/reference/independent/bar-dirichlet-m80.csv: run the ignored test regenerate_stored_values");
    assert!(text.starts_with(reference::STORED_HEADER), "the stored file's header says how it was produced");
    let stored = reference::parse_stored(&text);
    let fresh = reference::parse_stored(&reference::stored_text(&reference::stored_rows()));
    assert_eq!(stored.len(), fresh.len(), "configurations");
    assert_eq!(stored.len(), 6, "every configuration but the chaotic std-mass Newmark");
    for ((key, s), (fkey, f)) in stored.iter().zip(&fresh) {
        assert_eq!(key, fkey);
        for (i, (a, b)) in s.iter().zip(f).enumerate() {
            assert!((a - b).abs() <= 1e-12 * b.abs(), "{key:?} {}: stored {a:e}, reference now {b:e}", reference::Norms::COLUMNS[i]);
        }
    }
}

/// Writes the stored values from the reference (run by hand after a
/// deliberate change of the reference or of the benchmark).
#[test]
#[ignore = "writes data/reference/independent/; run by hand"]
fn regenerate_stored_values() {
    let p = stored_path();
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, reference::stored_text(&reference::stored_rows())).unwrap();
}

/// Paoli–Schatzman reports its force at the level `t_n = n·dt` computed
/// from the index, like every other time level — not as `t_{n+1} − dt`,
/// which rounds below exact levels (1.9999999999999998 for t = 2 at
/// m = 160) and there evaluated the exact force just before take-off
/// (an l2_lambda error of 8e-3 at m = 160 before the fix).
#[test]
fn ps_force_times_are_exact_levels() {
    for scheme in [Scheme::PaoliSchatzman { e: 0.0 }, Scheme::PaoliSchatzman { e: 0.5 }] {
        let mut s = library_stepper(scheme, Mass::Std, 160, 0.0);
        let dt = s.dt();
        let mut off = 0;
        while s.time() < 3.0 - 0.5 * dt {
            let rep = s.step().unwrap();
            if let Some((t, _)) = rep.lambda {
                let want = (rep.n - 1) as f64 * dt;
                off += usize::from(t.to_bits() != want.to_bits());
            }
        }
        assert_eq!(off, 0, "{}: {off} force times are not n·dt", scheme.name());
    }
}
