//! Courant number one: the lumped central difference at dx/dt = c against
//! an independent model written here (nodal recurrences of the lumped P1
//! chain with the characteristic release, docs/theory.md §4.10) and against
//! the exact solutions — exact to round-off at every node and level,
//! releases included, where every release falls on a time level; the
//! falling bar with g = 0.11 releases between levels, where no scheme that
//! holds nodal values can be exact.

use signorini_fem::BarMass;
use signorini_run::Benchmark;
use signorini_schemes::{PaoliSchatzman, SchemeError, SchemeSpec, Stepper};
use signorini_studies::{courant1, Column};

/// The lumped chain on [0, 1] clamped at x = 1, obstacle u_0 >= 0, c = 1,
/// dt = h: interior u_i^{n+1} = u_{i+1}^n + u_{i-1}^n − u_i^{n-1}, the end
/// node (mass h/2) u_0^{n+1} = max(0, w) with its free update
/// w = 2 u_1^n − u_0^{n-1} − s^n, where s^n = w^n − u_0^n is what the
/// obstacle took from the last free update (0 in free flight: the mirror
/// rule); Taylor start.
fn chain(m: usize, steps: usize) -> Vec<Vec<f64>> {
    let h = 1.0 / m as f64;
    let u0: Vec<f64> = (0..=m).map(|i| (1.0 - i as f64 * h) / 2.0).collect();
    // Taylor: u1 = u0 + dt²/2 a0 with a0 = 0 inside (u0 affine), −1/h at node 0.
    let mut u1 = u0.clone();
    u1[0] = u0[0] - 0.5 * h;
    let mut levels = vec![u0, u1];
    let mut taken = 0.0;
    for n in 1..steps {
        let (up, u) = (&levels[n - 1], &levels[n]);
        let mut next = vec![0.0; m + 1];
        let w = 2.0 * u[1] - up[0] - taken;
        next[0] = w.max(0.0);
        taken = w - next[0];
        for i in 1..m {
            next[i] = u[i + 1] + u[i - 1] - up[i];
        }
        levels.push(next);
    }
    levels
}

#[test]
fn the_scheme_is_the_independent_chain_and_exact_through_the_release() {
    let exact = Benchmark::BarDirichlet.exact(6.0).unwrap();
    for m in [10, 20, 40] {
        let p = Benchmark::BarDirichlet.problem(exact.as_ref(), m, BarMass::Lumped).unwrap();
        let dt = p.bar.h();
        let mut s = PaoliSchatzman::central_difference_taylor("cd".into(), p.dynamics(), 0.0, dt, &p.initial).unwrap();
        let steps = 6 * m;
        let want = chain(m, steps + 1);
        let h = dt;
        for n in 1..=steps {
            if n > 1 {
                s.step().unwrap();
            }
            let u = s.displacement();
            for i in 0..m {
                assert!((u[i] - want[n][i]).abs() < 1e-13, "m = {m}, level {n}, node {i}: {} vs the chain's {}", u[i], want[n][i]);
            }
            let t = n as f64 * dt;
            let err = (0..m).map(|i| (u[i] - exact.fields(i as f64 * h, t).u).abs()).fold(0.0, f64::max);
            // Free flight, the impact at t = 1, the contact phase and the
            // release at t = 2: every node exact (the old two-level rule held
            // the node one step too long: dt/2 at t = 2 + dt).
            assert!(err < 1e-13, "m = {m}, t = {t}: nodal error {err:e}");
        }
    }
}

/// Every node at every level against the exact solutions where every
/// release falls on a time level (bar-dirichlet, bar-mirrored, the falling
/// bar with g = 1/9), to round-off relative to the solution's size; with
/// g = 0.11 the release (t = 5.0151…) falls between levels and the error is
/// first order, as docs/theory.md §4.10 proves it must be. The contact force
/// the scheme reports equals the exact one away from its jumps.
#[test]
fn cd_taylor_is_nodally_exact_where_releases_are_on_the_grid() {
    for (bench, t_end, exact_expected) in
        [(Benchmark::BarDirichlet, 6.0, true), (Benchmark::BarMirrored, 6.0, true), (Benchmark::BarNeumannGravity, 16.0, true), (Benchmark::BarNeumannGravityPaper, 16.0, false)]
    {
        let exact = bench.exact(t_end).unwrap();
        for m in [10, 20, 40, 80] {
            let p = bench.problem(exact.as_ref(), m, BarMass::Lumped).unwrap();
            let h = p.bar.h();
            let mut s: Box<dyn Stepper> = "cd-taylor".parse::<SchemeSpec>().unwrap().build(p.dynamics(), h, &p.initial).unwrap();
            let steps = (t_end / h).round() as usize;
            let nodes = p.initial.u.len();
            let (mut worst, mut scale) = (0.0f64, 0.0f64);
            for n in 1..=steps {
                if n > 1 {
                    let r = s.step().unwrap();
                    // The contact force too, away from its jumps (one level each side).
                    let (tl, lam) = r.lambda.unwrap();
                    let jump = |t: f64| (exact.lambda(t - 1.01 * h) - exact.lambda(t + 1.01 * h)).abs() > 1e-12;
                    if exact_expected && !jump(tl) {
                        assert!((lam - exact.lambda(tl)).abs() <= 1e-9, "{bench} m = {m}, t = {tl}: λ {lam} vs {}", exact.lambda(tl));
                    }
                }
                let t = n as f64 * h;
                for (i, u) in s.displacement().iter().enumerate().take(nodes) {
                    let want = exact.fields(i as f64 * h, t).u;
                    worst = worst.max((u - want).abs());
                    scale = scale.max(want.abs());
                }
            }
            if exact_expected {
                assert!(worst <= 1e-12 * scale.max(1.0) * m as f64, "{bench} m = {m}: nodal error {worst:e}");
            } else {
                assert!(worst > 1e-4, "{bench} m = {m}: exact to {worst:e}, but the release is between levels");
            }
        }
    }
}

/// The named scheme `cd-taylor` (a scene's `scheme = "cd-taylor"`) is the
/// chain on the Dirichlet bar; it takes the falling bar's lumped mass at its
/// exact limit dt = h (closed form: the half-mass end nodes make `κ_max`
/// exactly 4c²/h²) and refuses dt = 1.001 h, the consistent mass (not
/// diagonal) and a massless contact node, each with a typed error.
#[test]
fn the_named_scheme_is_the_chain_and_runs_at_its_limit() {
    let spec: SchemeSpec = "cd-taylor".parse().unwrap();
    assert_eq!(spec.to_string(), "cd-taylor");
    assert!(spec.is_explicit() && spec.needs_massive_node());
    let exact = Benchmark::BarDirichlet.exact(6.0).unwrap();
    let m = 20;
    let p = Benchmark::BarDirichlet.problem(exact.as_ref(), m, BarMass::Lumped).unwrap();
    let mut s = spec.build(p.dynamics(), p.bar.h(), &p.initial).unwrap();
    let want = chain(m, 6 * m + 1);
    for (n, level) in want.iter().enumerate().take(6 * m + 1).skip(1) {
        if n > 1 {
            s.step().unwrap();
        }
        for (i, w) in level.iter().enumerate().take(m) {
            assert!((s.displacement()[i] - w).abs() < 1e-13, "level {n}, node {i}");
        }
    }
    let exact = Benchmark::BarNeumannGravity.exact(16.0).unwrap();
    for m in [10, 40, 160] {
        let p = Benchmark::BarNeumannGravity.problem(exact.as_ref(), m, BarMass::Lumped).unwrap();
        let h = p.bar.h();
        assert!(spec.build(p.dynamics(), h, &p.initial).is_ok(), "m = {m}: dt = h refused");
        assert!(matches!(spec.build(p.dynamics(), 1.001 * h, &p.initial), Err(SchemeError::Unstable { .. })), "m = {m}");
    }
    let h = 1.0 / 40.0;
    let std = Benchmark::BarNeumannGravity.problem(exact.as_ref(), 40, BarMass::Std).unwrap();
    assert!(matches!(spec.build(std.dynamics(), 0.5 * h, &std.initial), Err(SchemeError::Structure(_))));
    let mass_less = Benchmark::BarNeumannGravity.problem(exact.as_ref(), 40, BarMass::Mod).unwrap();
    assert!(matches!(spec.build(mass_less.dynamics(), 0.5 * h, &mass_less.initial), Err(SchemeError::MassNotSupported { .. })));
}

#[test]
fn the_study_reports_no_error_where_releases_are_on_the_grid() {
    let out = std::env::temp_dir().join(format!("signorini-studies-courant1-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let cfg = courant1::Config { out: out.clone(), benchmarks: vec![Benchmark::BarDirichlet, Benchmark::BarNeumannGravity], levels: vec![10, 20], t_end: None };
    let o = courant1::run(&cfg, &|_, _| {}).unwrap();
    let t = &o.tables[0];
    let f = |name: &str| match t.column(name) {
        Some(Column::F64(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    };
    let s = |name: &str| match t.column(name) {
        Some(Column::Str(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    };
    let (bench, start, dt, first_t, first, release) = (s("benchmark"), s("start"), f("dt"), f("first_error_t"), f("first_error"), f("exact_release_t"));
    for r in 0..bench.len() {
        match (bench[r].as_str(), start[r].as_str()) {
            (_, "taylor") => {
                // Releases on the grid (t = 2; t = 5 for g = 1/9): exact throughout.
                assert!(first_t[r].is_nan() && first[r].is_nan(), "row {r}: first error {} at {}", first[r], first_t[r]);
            }
            ("bar-dirichlet", "newmark") => {
                // taylor-flanagan's Newmark(1/4, 1/2) start is not the nodal recurrence.
                assert!((first_t[r] - dt[r]).abs() < 1e-12, "row {r}");
            }
            (_, _) => {
                // The falling bar (g = 1/9, from rest) with the Newmark start:
                // exact through the impact at t = 3 until the step across the release.
                assert!(first_t[r] >= release[r] - 1e-12 && first_t[r] <= release[r] + dt[r] + 1e-12, "row {r}: {} vs {}", first_t[r], release[r]);
            }
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_input_is_refused_before_the_folder_exists() {
    let out = std::env::temp_dir().join(format!("signorini-studies-courant1-bad-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    for (cfg, field) in [
        (courant1::Config { out: out.clone(), levels: vec![], ..Default::default() }, "--levels"),
        (courant1::Config { out: out.clone(), levels: vec![1], ..Default::default() }, "--levels"),
        (courant1::Config { out: out.clone(), benchmarks: vec![], ..Default::default() }, "--benchmarks"),
        (courant1::Config { out: out.clone(), t_end: Some(f64::NAN), ..Default::default() }, "--t-end"),
    ] {
        match courant1::run(&cfg, &|_, _| {}) {
            Err(signorini_studies::StudyError::Config { field: f, .. }) => assert_eq!(signorini_studies::options::Spelling::Flag.spell(&f), field),
            other => panic!("{field}: {other:?}"),
        }
        assert!(!out.exists());
    }
}

#[test]
fn the_taylor_start_refuses_a_consistent_mass() {
    let exact = Benchmark::BarDirichlet.exact(3.0).unwrap();
    let p = Benchmark::BarDirichlet.problem(exact.as_ref(), 10, BarMass::Std).unwrap();
    assert!(PaoliSchatzman::central_difference_taylor("cd".into(), p.dynamics(), 0.0, 0.1, &p.initial).is_err());
}
