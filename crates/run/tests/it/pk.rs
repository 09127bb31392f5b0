//! P2/P3 bars through the run layer (docs/theory.md §2.1.4):
//!
//! * degree 1 through the Pk path (`run_level` at degree 1, `problem_with_degree`,
//!   `NormObserver::with_degree`) gives the norms the P1 code gave before the
//!   Pk generalisation, bit for bit (the bits below were printed by that code,
//!   commit bb6338b);
//! * P2 and P3 converge at their theoretical rates on a smooth problem: the
//!   first free mode of the bar free at 0 (far from the obstacle), clamped at
//!   1, `u = cos(πt/2) cos(πx/2)`, with Newmark-CN at `dt = h^{(k+1)/2}/10` so
//!   the time error `O(dt²)` scales like the space error `O(h^{k+1})` in
//!   L²; rates `k + 1` (L²) and `k` (H¹) within ±0.3. The errors are
//!   integrated here with an 8-point Gauss rule per element, not by
//!   signorini-norms (whose exactness needs a polynomial `u`: for a cosine
//!   it would measure `u_h` against the degree-`k` interpolant of `u`);
//! * a degree other than 1, 2, 3 is a typed error naming `degree`.

use signorini_fem::{Bar, BarMass, FemError, RightEnd};
use signorini_norms::NormKind;
use signorini_run::study::{rate, run_level, Level, StudyConfig};
use signorini_run::{run, Benchmark, Observer, RunConfig, RunError, Sample};
use signorini_schemes::{Bounds, Contact, Dynamics, Initial, SchemeSpec};
use std::f64::consts::PI;

fn bits(n: &signorini_norms::NormReport) -> [u64; 8] {
    [n.linf_l2_u, n.l2_l2_u, n.linf_v_u, n.l2_v_u, n.l2_lambda, n.linf_energy, n.l2_energy, n.lambda_tv_ratio].map(f64::to_bits)
}

#[test]
fn p1_levels_through_the_pk_path_are_bit_identical_to_the_p1_code() {
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(3.0).unwrap();
    let r = run_level(&Level::new(b, "newmark-cn".parse().unwrap(), BarMass::Mod, 20, 10.0, 3.0).with_degree(1).with_norms(NormKind::Exact), exact.as_ref()).unwrap();
    assert_eq!(
        bits(&r.norms),
        [0x3f9a77c1b2814529, 0x3f9f88cd737d161e, 0x3fca762a1f7c9bac, 0x3fcf4d9d1bbbcab4, 0x3fc8f66c01bd78df, 0x3f79e50f2d54fa80, 0x3f866748341fdd20, 0x400844cb3d074108],
        "{:?}",
        r.norms
    );
    let b = Benchmark::BarNeumannGravity;
    let exact = b.exact(16.0).unwrap();
    let r = run_level(&Level::new(b, "ps-e0".parse().unwrap(), BarMass::Std, 20, 1.0, 16.0).with_degree(1).with_norms(NormKind::Exact), exact.as_ref()).unwrap();
    assert_eq!(
        bits(&r.norms),
        // The V norms since the degree-2 seminorm is computed from its
        // differences (a kink at round-off distance from a node had added
        // the cancellation error of a sliver: l2_v_u 0.2372...4399 before).
        [0x3fb113ea80ff035f, 0x3fb1a2e7e267ab86, 0x3fbaf09c94117e03, 0x3fce5d7a4f157223, 0x3fc47f529fb85068, 0x3f654d369ee3b3a0, 0x3f7e5c6ff49839cd, 0x3ff8d60b37b3bd5f],
        "{:?}",
        r.norms
    );
}

/// The first free mode `cos(πt/2) cos(πx/2)` of the bar on [0, 1], free at 0, clamped at 1.
fn mode(x: f64, t: f64) -> (f64, f64) {
    let w = PI / 2.0;
    ((w * t).cos() * (w * x).cos(), -w * (w * t).cos() * (w * x).sin())
}

/// Gauss–Legendre nodes and weights on [0, 1] (Newton on the Legendre polynomial).
fn gauss(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for j in 2..=n {
                    let p2 = ((2 * j - 1) as f64 * x * p1 - (j - 1) as f64 * p0) / j as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                x -= p1 / dp;
            }
            (0.5 * (x + 1.0), 1.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Lagrange basis of degree `k` on the nodes `r/k` of [0, 1]: value and derivative at `s`.
fn basis(k: usize, i: usize, s: f64) -> (f64, f64) {
    let node = |r: usize| r as f64 / k as f64;
    let others: Vec<usize> = (0..=k).filter(|&r| r != i).collect();
    let v = others.iter().map(|&r| (s - node(r)) / (node(i) - node(r))).product();
    let d = others.iter().map(|&r| others.iter().filter(|&&p| p != r).map(|&p| (s - node(p)) / (node(i) - node(p))).product::<f64>() / (node(i) - node(r))).sum();
    (v, d)
}

/// `L²(0,T;L²)` and `L²(0,T;H¹)` of `u_h - u` for the mode, from its own
/// 8-point Gauss rule per element (independent of signorini-norms).
struct ModeErrors {
    k: usize,
    m: usize,
    dt: f64,
    g: Vec<(f64, f64)>,
    /// `basis(k, i, s_g)` per Gauss point `g`, per `i`.
    table: Vec<Vec<(f64, f64)>>,
    l2: f64,
    h1: f64,
}

impl Observer for ModeErrors {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let (k, m) = (self.k, self.m);
        let h = 1.0 / m as f64;
        let nodal = |i: usize| if i < s.u.len() { s.u[i] } else { 0.0 };
        let (mut a, mut b) = (0.0, 0.0);
        for j in 0..m {
            for (&(sg, w), table) in self.g.iter().zip(&self.table) {
                let (mut uh, mut duh) = (0.0, 0.0);
                for (i, &(v, d)) in table.iter().enumerate() {
                    uh += nodal(k * j + i) * v;
                    duh += nodal(k * j + i) * d / h;
                }
                let (u, ux) = mode((j as f64 + sg) * h, s.t);
                a += w * h * (uh - u).powi(2);
                b += w * h * (duh - ux).powi(2);
            }
        }
        self.l2 += self.dt * a;
        self.h1 += self.dt * b;
        Ok(())
    }
}

/// `(dx, L²(0,T;L²), L²(0,T;H¹))` of the free mode with P`k` elements, `m` of them.
fn mode_errors(k: usize, m: usize, t_end: f64) -> (f64, f64, f64) {
    let bar = Bar::new(1.0, m, 1.0, RightEnd::Clamped).unwrap().with_degree(k).unwrap();
    let h = bar.h();
    let steps = (t_end / (0.1 * h.powf((k as f64 + 1.0) / 2.0))).ceil();
    let dt = t_end / steps;
    let n = bar.dofs();
    let init = Initial { u: (0..n).map(|i| mode(i as f64 * h / k as f64, 0.0).0).collect(), v: vec![0.0; n] };
    let dy = Dynamics::new(bar.mass(BarMass::Std), bar.stiffness(), vec![0.0; n], vec![Contact::new(0, Bounds::obstacle(-10.0), false)]);
    let mut stepper = "newmark-cn".parse::<SchemeSpec>().unwrap().build(dy, dt, &init).unwrap();
    let g = gauss(8);
    let table = g.iter().map(|&(sg, _)| (0..=k).map(|i| basis(k, i, sg)).collect()).collect();
    let mut errs = ModeErrors { k, m, dt, g, table, l2: 0.0, h1: 0.0 };
    run(stepper.as_mut(), &init.u, &RunConfig::new(dt, t_end).unwrap(), &mut [&mut errs]).unwrap();
    (h, errs.l2.sqrt(), errs.h1.sqrt())
}

#[test]
fn p2_and_p3_converge_at_their_rates_on_a_smooth_mode() {
    for (k, levels) in [(2, [4, 8, 16, 32]), (3, [4, 8, 16, 24])] {
        let e: Vec<(f64, f64, f64)> = levels.iter().map(|&m| mode_errors(k, m, 2.0)).collect();
        let l2 = rate(&e.iter().map(|x| (x.0, x.1)).collect::<Vec<_>>()).lsq;
        let h1 = rate(&e.iter().map(|x| (x.0, x.2)).collect::<Vec<_>>()).lsq;
        eprintln!("P{k}: rates L2 {l2:.3}, H1 {h1:.3}; errors {e:?}");
        assert!((l2 - (k as f64 + 1.0)).abs() <= 0.3, "P{k}: L2 rate {l2} (errors {e:?})");
        assert!((h1 - k as f64).abs() <= 0.3, "P{k}: H1 rate {h1} (errors {e:?})");
    }
}

#[test]
fn a_degree_other_than_1_2_3_is_refused_by_name() {
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(3.0).unwrap();
    for k in [0, 4] {
        match b.problem_with_degree(exact.as_ref(), 10, BarMass::Std, k) {
            Err(RunError::Fem(FemError::Invalid { field: "degree", .. })) => {}
            other => panic!("degree {k}: {other:?}"),
        }
        let cfg = StudyConfig::new(b, vec!["newmark-cn".parse().unwrap()], vec![BarMass::Std], vec![10, 20], 10.0, 3.0).with_degree(k);
        assert!(matches!(cfg.validate(), Err(RunError::Invalid { field: "degree", .. })), "degree {k}");
    }
    // A mass treatment P2 does not define, and the P1-only GetFEM norms.
    assert!(matches!(b.problem_with_degree(exact.as_ref(), 10, BarMass::Transfer, 2), Err(RunError::Fem(FemError::MassForDegree { .. }))));
    let cfg = StudyConfig::new(b, vec!["newmark-cn".parse().unwrap()], vec![BarMass::Std], vec![10, 20], 10.0, 3.0).with_norms(NormKind::GetfemInterpolated).with_degree(2);
    assert!(matches!(cfg.validate(), Err(RunError::Invalid { field: "degree", .. })));
    assert!(cfg.with_norms(NormKind::Exact).validate().is_ok());
}
