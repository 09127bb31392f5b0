//! The work–precision study in every quantity (issue 23 §1): the columns
//! `linf_l2_u, linf_v_u, l2_v_u, l2_lambda, l2_energy, release_err` of a few
//! rows against values computed here from the run's own levels and the
//! exact solutions, independently of the norms crate: the space integrals by
//! a composite 3-point Gauss rule on 200 pieces per element (not split at
//! the kinks: 1e-3 relative), the time norms and the release as
//! docs/theory.md §6.2–6.4 define them, the exact release time from the
//! falling bar's own event list.

use signorini_exact::{BarNeumannGravity, ExactSolution};
use signorini_fem::BarMass;
use signorini_run::Benchmark;
use signorini_schemes::{SchemeSpec, Stepper};
use signorini_studies::{work_precision, Column};

/// What a run's levels give, computed here.
struct Independent {
    linf_l2_u: f64,
    linf_v_u: f64,
    l2_v_u: f64,
    l2_lambda: f64,
    l2_energy: f64,
    first_release: Option<f64>,
}

/// `‖u_h − u‖` in L² and in V at time `t` (V: the H¹ seminorm for a
/// clamped far end, the full H¹ norm for a free one), by composite Gauss.
fn space_errors(exact: &dyn ExactSolution, u: &[f64], h: f64, elements: usize, full_h1: bool, t: f64) -> (f64, f64) {
    let (gx, gw) = ([-(0.6f64).sqrt(), 0.0, (0.6f64).sqrt()], [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0]);
    let pieces = 200;
    let (mut l2, mut h1) = (0.0, 0.0);
    let nodal = |i: usize| if i < u.len() { u[i] } else { 0.0 }; // a clamped far node is not an unknown
    for e in 0..elements {
        let (a, b) = (nodal(e), nodal(e + 1));
        let slope = (b - a) / h;
        for p in 0..pieces {
            let (x0, x1) = (e as f64 * h + p as f64 * h / pieces as f64, e as f64 * h + (p + 1) as f64 * h / pieces as f64);
            for (g, w) in gx.iter().zip(gw) {
                let x = 0.5 * (x0 + x1) + 0.5 * (x1 - x0) * g;
                let uh = a + slope * (x - e as f64 * h);
                let f = exact.fields(x, t);
                l2 += 0.5 * (x1 - x0) * w * (uh - f.u).powi(2);
                h1 += 0.5 * (x1 - x0) * w * (slope - f.ux).powi(2);
            }
        }
    }
    (l2.sqrt(), if full_h1 { (l2 + h1).sqrt() } else { h1.sqrt() })
}

/// Runs `scheme` on `bench` at level `m` (dx/dt = `ratio`) through the
/// scheme's own constructor and computes every quantity from its levels.
fn independent(bench: Benchmark, scheme: &str, mass: BarMass, m: usize, ratio: f64, t_end: f64) -> Independent {
    let exact = bench.exact(t_end).unwrap();
    let p = bench.problem(exact.as_ref(), m, mass).unwrap();
    let (h, full_h1) = (p.bar.h(), bench == Benchmark::BarNeumannGravity);
    let dt = h / ratio;
    let mut s: Box<dyn Stepper> = scheme.parse::<SchemeSpec>().unwrap().build(p.dynamics(), dt, &p.initial).unwrap();
    let steps = (t_end / dt).round() as usize;
    let e_exact = exact.energy();
    let (mut linf_l2, mut linf_v, mut sum_v, mut sum_l, mut sum_e) = (0.0f64, 0.0f64, 0.0, 0.0, 0.0);
    let level = |u: &[f64], t: f64, linf_l2: &mut f64, linf_v: &mut f64, sum_v: &mut f64| {
        let (el2, ev) = space_errors(exact.as_ref(), u, h, p.bar.elements, full_h1, t);
        *linf_l2 = linf_l2.max(el2);
        *linf_v = linf_v.max(ev);
        *sum_v += dt * ev * ev;
    };
    level(&p.initial.u, 0.0, &mut linf_l2, &mut linf_v, &mut sum_v);
    if s.level() == 0 {
        if let Some((_, e)) = s.energy() {
            sum_e += dt * (e - e_exact).powi(2);
        }
    } else {
        // A two-step scheme starts at level 1.
        let t = s.time();
        level(s.displacement(), t, &mut linf_l2, &mut linf_v, &mut sum_v);
        if let Some((_, e)) = s.energy() {
            sum_e += dt * (e - e_exact).powi(2);
        }
    }
    let (mut was_active, mut first_release) = (false, None);
    while s.level() < steps {
        let r = s.step().unwrap();
        let active = r.active != signorini_schemes::Active::None;
        if was_active && !active && first_release.is_none() {
            first_release = Some(r.t);
        }
        was_active = active;
        if let Some((tl, lam)) = r.lambda {
            sum_l += dt * (lam - exact.lambda(tl)).powi(2);
        }
        if let Some((_, e)) = s.energy() {
            sum_e += dt * (e - e_exact).powi(2);
        }
        level(s.displacement(), r.t, &mut linf_l2, &mut linf_v, &mut sum_v);
    }
    Independent { linf_l2_u: linf_l2, linf_v_u: linf_v, l2_v_u: sum_v.sqrt(), l2_lambda: sum_l.sqrt(), l2_energy: sum_e.sqrt(), first_release }
}

#[track_caller]
fn close(what: &str, row: f64, here: f64, rel: f64) {
    assert!((row - here).abs() <= rel * here.abs() + 1e-12, "{what}: row {row:e}, computed here {here:e}");
}

/// The new columns of three bar rows (a one-step scheme with a massless
/// contact node, the two-step Courant-one scheme with a massive one, on both
/// bars) equal what their levels give.
#[test]
fn the_new_columns_are_the_runs_own_errors() {
    let out = std::env::temp_dir().join(format!("signorini-studies-wp-quantities-{}", std::process::id()));
    let cfg = work_precision::Config { out: out.clone(), levels: vec![10, 20], degrees: vec![], modes: vec![], beam_dts: vec![], beam_stat_dts: vec![], ..Default::default() };
    let o = work_precision::run(&cfg, &|_, _| {}).unwrap();
    let t = &o.tables[0];
    let s = |c: &str| match t.column(c) {
        Some(Column::Str(v)) => v.clone(),
        other => panic!("{c}: {other:?}"),
    };
    let f = |c: &str| match t.column(c) {
        Some(Column::F64(v)) => v.clone(),
        other => panic!("{c}: {other:?}"),
    };
    let Some(Column::I64(m)) = t.column("m") else { panic!("m") };
    let (bench, scheme, mass) = (s("benchmark"), s("scheme"), s("mass"));
    // The falling bar's first take-off, from its own event list.
    let takeoff = BarNeumannGravity::periodic(16.0).unwrap().takeoffs().next().unwrap();
    for (b, sc, ms, level, ratio, t_end, release) in [
        (Benchmark::BarNeumannGravity, "newmark-cn", BarMass::Mod, 10, 1.0, 16.0, takeoff),
        (Benchmark::BarNeumannGravity, "cd-taylor", BarMass::Lumped, 20, 1.0, 16.0, takeoff),
        (Benchmark::BarDirichlet, "newmark-cn", BarMass::Mod, 20, 10.0, 3.0, 2.0),
    ] {
        let i = (0..bench.len()).find(|&i| bench[i] == b.to_string() && scheme[i] == sc && mass[i] == ms.to_string() && m[i] == level).unwrap_or_else(|| panic!("no row {b} {sc} {ms} m = {level}"));
        let here = independent(b, sc, ms, level as usize, ratio, t_end);
        let what = |c: &str| format!("{b} {sc} {ms} m = {level}: {c}");
        close(&what("linf_l2_u"), f("linf_l2_u")[i], here.linf_l2_u, 1e-3);
        close(&what("linf_v_u"), f("linf_v_u")[i], here.linf_v_u, 1e-3);
        close(&what("l2_v_u"), f("l2_v_u")[i], here.l2_v_u, 1e-3);
        close(&what("l2_lambda"), f("l2_lambda")[i], here.l2_lambda, 1e-5);
        close(&what("l2_energy"), f("l2_energy")[i], here.l2_energy, 1e-5);
        let rel = (here.first_release.expect("a release") - release).abs();
        close(&what("release_err"), f("release_err")[i], rel, 1e-5);
    }
    let _ = std::fs::remove_dir_all(out);
}
