//! `bar-dirichlet` against the exact test vectors of exact-neumann.md §1 and
//! its defining properties. The solution is piecewise affine with dyadic
//! data, so test vectors hold to 1e-15 (a few ulps of the products).

use proptest::prelude::*;
use signorini_exact::{BarDirichlet, ExactSolution};

const TOL: f64 = 1e-15;

fn check(x: f64, t: f64, u: f64, ux: f64, ut: f64) {
    let f = BarDirichlet.fields(x, t);
    assert!((f.u - u).abs() <= TOL && (f.ux - ux).abs() <= TOL && (f.ut - ut).abs() <= TOL, "({x},{t}): {f:?} vs ({u},{ux},{ut})");
}

#[test]
fn test_vectors() {
    check(0.25, 0.5, 0.25, 0.0, -0.5);
    check(0.75, 0.5, 0.125, -0.5, 0.0);
    check(0.2, 1.5, -0.1, -0.5, 0.0);
    check(0.3, 1.2, -0.1, 0.0, -0.5);
    check(0.8, 1.5, -0.1, 0.5, 0.0);
    check(0.6, 1.7, -0.15, 0.0, 0.5);
    check(0.2, 2.5, 0.25, 0.0, 0.5);
    check(0.8, 2.5, 0.1, -0.5, 0.0);
    check(0.4, 3.3, 0.3, -0.5, 0.0);
    check(0.9, 7.6, -0.05, 0.5, 0.0);
    for (t, l) in [(0.5, 0.0), (1.25, -0.5), (1.75, -0.5), (2.5, 0.0), (4.5, -0.5)] {
        assert_eq!(BarDirichlet.lambda(t), l, "lambda({t})");
    }
}

#[test]
fn initial_and_boundary_data() {
    for i in 0..=100 {
        let x = i as f64 / 100.0;
        let f = BarDirichlet.fields(x, 0.0);
        assert!((f.u - (1.0 - x) / 2.0).abs() <= TOL);
        assert_eq!(f.ut, 0.0);
        // u(1, t) = 0 for all t.
        let t = i as f64 * 0.0731;
        assert!(BarDirichlet.fields(1.0, t).u.abs() <= TOL, "u(1,{t})");
    }
}

#[test]
fn kinks_are_the_characteristic_lines() {
    let mut k = Vec::new();
    BarDirichlet.kinks(1.3, &mut k);
    assert_eq!(k.len(), 2);
    assert!((k[0] - 0.3).abs() < 1e-15 && (k[1] - 0.7).abs() < 1e-15);
    BarDirichlet.kinks(0.5, &mut k);
    assert_eq!(k, vec![0.5]);
    BarDirichlet.kinks(2.0, &mut k);
    assert!(k.is_empty());
}

proptest! {
    /// Complementarity, sign, continuity, energy density 1/8 and the
    /// parallelogram identity (the weak form of the wave equation).
    #[test]
    fn properties(x in 0.0f64..1.0, t in 0.0f64..12.0, h in 0.0f64..0.2) {
        let s = BarDirichlet;
        let u0 = s.fields(0.0, t).u;
        let l = s.lambda(t);
        prop_assert!(u0 >= -TOL);
        prop_assert!(l <= 0.0);
        prop_assert!((u0 * l).abs() <= TOL);
        // Energy density (u_t² + u_x²)/2 = 1/8 everywhere, so E = 1/8.
        let f = s.fields(x, t);
        prop_assert!(((f.ut * f.ut + f.ux * f.ux) / 2.0 - 0.125).abs() <= TOL);
        // Continuity of u across any line: left/right limits agree.
        let e = 1e-9;
        if x > e && x < 1.0 - e {
            // |u_x| <= 1/2, so a jump-free u moves at most e across [x-e, x+e].
            prop_assert!((s.fields(x - e, t).u - s.fields(x + e, t).u).abs() <= e + 1e-15);
        }
        // Parallelogram identity u(x,t+h)+u(x,t-h)-u(x+h,t)-u(x-h,t) = 0.
        if x >= h && x + h <= 1.0 && t >= h {
            let d = s.fields(x, t + h).u + s.fields(x, t - h).u - s.fields(x + h, t).u - s.fields(x - h, t).u;
            prop_assert!(d.abs() <= 4.0 * TOL, "defect {}", d);
        }
        // Period 3.
        prop_assert!((s.fields(x, t + 3.0).u - f.u).abs() <= 4.0 * TOL);
        // u_at agrees with fields.
        let mut out = [0.0];
        s.u_at(t, &[x], &mut out);
        prop_assert_eq!(out[0], f.u);
    }
}
