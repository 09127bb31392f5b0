//! The Pk space norms (docs/theory.md §6) against closed-form integrals of
//! polynomials: `u_h` interpolates a known polynomial at the Lagrange nodes
//! (so it *is* that polynomial when its degree is <= k), the "exact
//! solution" is a test double with a kink inside an element, and
//! `∫ (u_h - u)²`, `∫ (u_h - u)'²` are integrated by hand from monomial
//! coefficients (antiderivatives on each side of the kink). Agreement to
//! rounding: 1e-13 relative.

use signorini_exact::{ExactSolution, FarEnd, Fields};
use signorini_norms::{SpaceIntegrator, VNorm};

/// `u(x) = (x - a)|x - a|` (kink in u_x at a) or `|x - a|`, or `x²` (no kink).
struct Double {
    a: f64,
    quadratic: bool,
    kink: bool,
}

impl Double {
    /// Monomial coefficients of `u` left and right of `a`.
    fn sides(&self) -> (Vec<f64>, Vec<f64>) {
        let a = self.a;
        if !self.kink {
            return (vec![0.0, 0.0, 1.0], vec![0.0, 0.0, 1.0]);
        }
        if self.quadratic {
            // ±(x - a)²
            let sq = vec![a * a, -2.0 * a, 1.0];
            (sq.iter().map(|c| -c).collect(), sq)
        } else {
            (vec![a, -1.0], vec![-a, 1.0])
        }
    }
}

impl ExactSolution for Double {
    fn name(&self) -> &str {
        "double"
    }
    fn length(&self) -> f64 {
        1.0
    }
    fn far_end(&self) -> FarEnd {
        FarEnd::Free
    }
    fn degree_x(&self) -> usize {
        if self.quadratic || !self.kink {
            2
        } else {
            1
        }
    }
    fn fields(&self, x: f64, _t: f64) -> Fields {
        let d = x - self.a;
        let u = if !self.kink {
            x * x
        } else if self.quadratic {
            d * d.abs()
        } else {
            d.abs()
        };
        Fields { u, ux: f64::NAN, ut: 0.0 }
    }
    fn lambda(&self, _t: f64) -> f64 {
        0.0
    }
    fn energy(&self) -> f64 {
        0.0
    }
    fn kinks(&self, _t: f64, out: &mut Vec<f64>) {
        out.clear();
        if self.kink {
            out.push(self.a);
        }
    }
}

fn sub(p: &[f64], q: &[f64]) -> Vec<f64> {
    (0..p.len().max(q.len())).map(|i| p.get(i).unwrap_or(&0.0) - q.get(i).unwrap_or(&0.0)).collect()
}
fn mul(p: &[f64], q: &[f64]) -> Vec<f64> {
    let mut r = vec![0.0; p.len() + q.len() - 1];
    for (i, x) in p.iter().enumerate() {
        for (j, y) in q.iter().enumerate() {
            r[i + j] += x * y;
        }
    }
    r
}
fn der(p: &[f64]) -> Vec<f64> {
    if p.len() < 2 {
        return vec![0.0];
    }
    p.iter().enumerate().skip(1).map(|(i, c)| i as f64 * c).collect()
}
/// `∫_lo^hi p` from the antiderivative.
fn integral(p: &[f64], lo: f64, hi: f64) -> f64 {
    p.iter().enumerate().map(|(i, c)| c * (hi.powi(i as i32 + 1) - lo.powi(i as i32 + 1)) / (i as f64 + 1.0)).sum()
}
fn eval(p: &[f64], x: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, c| acc * x + c)
}

/// (L², H¹-seminorm²) of `P - u` on [0, 1], by hand.
fn by_hand(p: &[f64], u: &Double) -> (f64, f64) {
    let (left, right) = u.sides();
    let a = if u.kink { u.a } else { 1.0 };
    let (el, er) = (sub(p, &left), sub(p, &right));
    let l2 = integral(&mul(&el, &el), 0.0, a) + integral(&mul(&er, &er), a, 1.0);
    let (dl, dr) = (der(&el), der(&er));
    let semi = integral(&mul(&dl, &dl), 0.0, a) + integral(&mul(&dr, &dr), a, 1.0);
    (l2, semi)
}

fn check(k: usize, m: usize, p: &[f64], u: &Double, clamped: bool) {
    let n = k * m;
    // Clamped convention: k m values, the last node's taken as 0 (so P(1) must be 0).
    let values: Vec<f64> = (0..if clamped { n } else { n + 1 }).map(|i| eval(p, i as f64 / n as f64)).collect();
    let (l2, semi) = by_hand(p, u);
    for vnorm in [VNorm::H1Seminorm, VNorm::H1Full] {
        let mut s = SpaceIntegrator::with_degree(u, m, k, vnorm);
        let e = s.errors(0.0, &values);
        let v2 = if vnorm == VNorm::H1Full { semi + l2 } else { semi };
        assert!((e.l2 - l2.sqrt()).abs() <= 1e-13 * l2.sqrt(), "P{k} m={m} a={}: L2 {} vs {}", u.a, e.l2, l2.sqrt());
        assert!((e.v - v2.sqrt()).abs() <= 1e-13 * v2.sqrt(), "P{k} m={m} a={}: V {} vs {}", u.a, e.v, v2.sqrt());
    }
}

#[test]
fn pk_norms_are_closed_form_integrals_of_polynomials() {
    // u_h = P of degree k (interpolated exactly), u with a kink inside an
    // element (a = 0.37 in [0.2, 0.4] of m = 5, between Lagrange nodes),
    // on a Lagrange node (a = 0.4 + 1/15 for P3 is a node of element 2), and without a kink.
    let cubic = [0.3, -1.1, 0.7, 0.9];
    let quad = [0.3, -1.1, 2.7];
    for a in [0.37, 0.4 + 1.0 / 15.0, 0.05] {
        for quadratic in [true, false] {
            let u = Double { a, quadratic, kink: true };
            check(3, 5, &cubic, &u, false);
            check(2, 5, &quad, &u, false);
            check(3, 7, &quad, &u, false);
            check(2, 1, &quad, &u, false);
        }
    }
    let u = Double { a: 0.0, quadratic: true, kink: false };
    check(3, 4, &cubic, &u, false);
    check(2, 4, &quad, &u, false);
    // Clamped: P(1) = 0.
    check(3, 6, &[0.2, -0.5, 0.1, 0.2], &Double { a: 0.37, quadratic: true, kink: true }, true);
    check(2, 6, &[0.2, -0.5, 0.3], &Double { a: 0.37, quadratic: false, kink: true }, true);
}

#[test]
fn pk_interpolant_of_the_exact_solution_has_zero_error_without_kinks() {
    // u = x², u_h its P2 interpolant: identical, so both norms vanish.
    let u = Double { a: 0.0, quadratic: true, kink: false };
    let values: Vec<f64> = (0..=10).map(|i| (i as f64 / 10.0).powi(2)).collect();
    let e = SpaceIntegrator::with_degree(&u, 5, 2, VNorm::H1Full).errors(0.0, &values);
    assert!(e.l2 <= 1e-15 && e.v <= 1e-14, "{e:?}");
}
