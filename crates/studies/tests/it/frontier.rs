//! The work–precision study's Courant-one rows against a central difference
//! written here: `U^{n+1} = 2U^n − U^{n−1} + dt² M⁻¹(F(t_n) − K U^n)` with
//! the lumped P1 mass at `dt = h/c`, Taylor's start, each contact dof
//! clamped into its bounds (the projection of a diagonal mass with
//! restitution 0) after its free update is shifted by what the clamp took
//! at the step before (the characteristic release, docs/theory.md §4.10),
//! its error measured by the norms observer.

use signorini_fem::BarMass;
use signorini_run::{Benchmark, NormObserver, Observer, Sample};
use signorini_studies::{work_precision, Column};

/// `l2_l2_u` of the hand-written central difference at level `m`.
fn oracle(b: Benchmark, m: usize) -> f64 {
    let (_, t_end) = b.default_ratio_and_horizon();
    let exact = b.exact(t_end).unwrap();
    let p = b.problem(exact.as_ref(), m, BarMass::Lumped).unwrap();
    let dy = p.dynamics();
    let n = dy.n();
    let dt = p.bar.h() / p.bar.wave_speed;
    let mass: Vec<f64> = (0..n).map(|i| dy.mass.get(i, i)).collect();
    let force = |t: f64, u: &[f64]| -> Vec<f64> {
        let mut ku = vec![0.0; n];
        dy.stiffness.mul_vec(u, &mut ku);
        (0..n).map(|i| dy.load[i] + dy.forcing.iter().map(|f| f.shape[i] * f.time.value(t)).sum::<f64>() - ku[i]).collect()
    };
    // What the clamp took from each contact's free update at the last step.
    let mut taken = vec![0.0; dy.contacts.len()];
    let mut clamp = |u: &mut Vec<f64>| {
        for (c, s) in dy.contacts.iter().zip(taken.iter_mut()) {
            u[c.dof] -= *s;
            let free = u[c.dof];
            u[c.dof] = free.clamp(c.bounds.lo, c.bounds.hi);
            *s = free - u[c.dof];
        }
    };
    let mut norms = NormObserver::new(exact.as_ref(), p.bar.elements, p.vnorm(), dt);
    let mut see = |k: usize, u: &[f64]| norms.observe(&Sample::new(k, k as f64 * dt, u)).unwrap();
    let mut prev = p.initial.u.clone();
    let f0 = force(0.0, &prev);
    let mut cur: Vec<f64> = (0..n).map(|i| prev[i] + dt * p.initial.v[i] + 0.5 * dt * dt * f0[i] / mass[i]).collect();
    clamp(&mut cur);
    see(0, &prev);
    see(1, &cur);
    let steps = (t_end / dt).round() as usize;
    for k in 1..steps {
        let f = force(k as f64 * dt, &cur);
        let mut next: Vec<f64> = (0..n).map(|i| 2.0 * cur[i] - prev[i] + dt * dt * f[i] / mass[i]).collect();
        clamp(&mut next);
        prev = std::mem::replace(&mut cur, next);
        see(k + 1, &cur);
    }
    norms.report().l2_l2_u
}

/// The Courant-one rows (levels 10, 20 and their two doublings, 40 and 80)
/// equal the hand-written scheme's error on both bar benchmarks, to 1e-9
/// relative (the two sum in different orders: 3e-12 apart at m = 80), or
/// to 1e-11 where the nodal values are exact up to round-off.
#[test]
fn courant_one_rows_are_a_central_difference_written_here() {
    let out = std::env::temp_dir().join(format!("signorini-studies-frontier-{}", std::process::id()));
    let cfg = work_precision::Config { out: out.clone(), levels: vec![10, 20], degrees: vec![], modes: vec![], beam_dts: vec![], beam_stat_dts: vec![], ..Default::default() };
    let o = work_precision::run(&cfg, &|_, _| {}).unwrap();
    let t = &o.tables[0];
    let (Some(Column::Str(bench)), Some(Column::Str(scheme)), Some(Column::I64(m)), Some(Column::F64(err))) = (t.column("benchmark"), t.column("scheme"), t.column("m"), t.column("l2_l2_u")) else {
        panic!("work_precision.csv's columns")
    };
    let mut seen = 0;
    for i in (0..bench.len()).filter(|&i| scheme[i] == "cd-taylor") {
        let b: Benchmark = bench[i].parse().unwrap();
        let want = oracle(b, m[i] as usize);
        // The Dirichlet bar is nodally exact at Courant number one: both
        // errors are round-off there (1e-15), the falling bar's nodes to round-off
        // (its error is the interpolation error), hence the absolute floor.
        assert!((err[i] - want).abs() <= 1e-9 * want + 1e-11, "{} m = {}: row {:e}, written here {want:e}", bench[i], m[i], err[i]);
        seen += 1;
    }
    assert_eq!(seen, 8, "4 levels on each of the two bars");
    let _ = std::fs::remove_dir_all(out);
}
