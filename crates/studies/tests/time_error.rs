//! The time-error study (`--reference event-driven`): a reduced model that
//! keeps every interior mode is the parent in other coordinates when the
//! parent's contact is massless (`mod`: `K_r = Tᵀ K T`, `M_r = Tᵀ M T`), so
//! every scheme's time error against the exact semi-discrete solution is
//! the same on both — computed here through two different paths (the
//! reduction and an event-driven run of the reduced model, against the full
//! model's), and the grouped lockstep (one reference run for several
//! schemes) gives the rows of one scheme at a time.

use signorini_fem::BarMass;
use signorini_reduce::Keep;
use signorini_run::Benchmark;
use signorini_schemes::SchemeSpec;
use signorini_studies::time_error::{reference_of, run_case, run_group};

#[test]
fn a_reduced_model_with_every_mode_has_the_full_models_time_error() {
    let bench = Benchmark::BarDirichlet;
    let t_end = 3.0;
    let exact = bench.exact(t_end).unwrap();
    let m = 10;
    let schemes: Vec<SchemeSpec> = ["newmark-cn", "ps-e0", "backward-euler"].iter().map(|s| s.parse().unwrap()).collect();
    let reference = reference_of(&schemes[0], BarMass::Mod).unwrap();
    let full = run_group(bench, exact.as_ref(), &schemes, reference, BarMass::Mod, m, 1, 10.0, t_end, None).unwrap();
    // Clamped at x = 1, contact at node 0: 9 interior dofs, all kept.
    let reduced = run_group(bench, exact.as_ref(), &schemes, reference, BarMass::Mod, m, 1, 10.0, t_end, Some(Keep::Modes(m - 1))).unwrap();
    for (a, b) in full.iter().zip(&reduced) {
        assert!(a.linf_l2_u > 1e-5 && a.events == b.events && a.events >= 2, "{a:?}");
        for (x, y, what) in [(a.linf_l2_u, b.linf_l2_u, "L∞(L²)"), (a.linf_v_u, b.linf_v_u, "L∞(V)"), (a.l2_lambda, b.l2_lambda, "L²(λ)"), (a.linf_energy, b.linf_energy, "L∞(E)")] {
            assert!((x - y).abs() <= 1e-8 * x.abs().max(1e-12), "{}: {what} {x:e} full, {y:e} reduced", a.scheme);
        }
    }
    // Three modes are another semi-discrete problem: `reduce` acts.
    let three = run_group(bench, exact.as_ref(), &schemes, reference, BarMass::Mod, m, 1, 10.0, t_end, Some(Keep::Modes(3))).unwrap();
    for (a, b) in full.iter().zip(&three) {
        assert!((a.linf_l2_u - b.linf_l2_u).abs() > 1e-3 * a.linf_l2_u, "{}: {} with 3 modes, {} full", a.scheme, b.linf_l2_u, a.linf_l2_u);
    }
    // The grouped lockstep gives each scheme's own run, and the L∞(L²)
    // error of a pair of steppers written here (each scheme and its
    // reference built and stepped through the public API, levels paired).
    let problem = bench.problem_with_degree(exact.as_ref(), m, BarMass::Mod, 1).unwrap();
    let dt = problem.bar.h() / 10.0;
    let steps = (t_end / dt).round() as usize;
    for (s, g) in schemes.iter().zip(&full) {
        let one = run_case(bench, exact.as_ref(), *s, BarMass::Mod, m, 1, 10.0, t_end).unwrap();
        assert_eq!([one.linf_l2_u, one.linf_v_u, one.l2_lambda, one.linf_energy].map(f64::to_bits), [g.linf_l2_u, g.linf_v_u, g.l2_lambda, g.linf_energy].map(f64::to_bits), "{s}");
        let dy = problem.dynamics();
        let mut a = s.build(problem.dynamics(), dt, &problem.initial).unwrap();
        let mut b = reference.build(problem.dynamics(), dt, &problem.initial).unwrap();
        let mut worst = 0.0f64;
        loop {
            while b.level() < a.level() {
                b.step().unwrap();
            }
            let e: Vec<f64> = a.displacement().iter().zip(b.displacement()).map(|(x, y)| x - y).collect();
            worst = worst.max(dy.mass.quad_form(&e).sqrt());
            if a.level() >= steps {
                break;
            }
            a.step().unwrap();
        }
        assert!((worst - g.linf_l2_u).abs() <= 1e-13 * worst, "{s}: {worst:e} paired here, {:e} in the study", g.linf_l2_u);
    }
}
