//! Hermite-cubic beam matrices and the exact stability eigenvalue.
//! Polynomials of degree <= 3 are represented exactly by the Hermite space,
//! so quadratic forms of interpolants equal the integrals to rounding (1e-12
//! relative). The assembled matrices are compared entry by entry with dense
//! matrices assembled here from the element matrices of docs/theory.md §2.2;
//! the eigenvalues with a dense faer solve (κ_h to 1e-10) and the smallest
//! with the continuous cantilever's first eigenvalue.

use crate::common;

use common::{assert_matrix_eq, close, generalized_eigenvalues};
use faer::Mat;
use signorini_fem::beam::{element_mass, element_stiffness};
use signorini_fem::{max_generalized_eigenvalue, Beam};

/// `M_e` of docs/theory.md §2.2 (unit ρS), written out.
fn hand_element_mass(h: f64) -> [[f64; 4]; 4] {
    let (a, b) = (h, h * h);
    let m = [[156.0, 22.0 * a, 54.0, -13.0 * a], [22.0 * a, 4.0 * b, 13.0 * a, -3.0 * b], [54.0, 13.0 * a, 156.0, -22.0 * a], [-13.0 * a, -3.0 * b, -22.0 * a, 4.0 * b]];
    m.map(|row| row.map(|v| v * h / 420.0))
}

/// `K_e` of docs/theory.md §2.2, written out.
fn hand_element_stiffness(h: f64, k2: f64) -> [[f64; 4]; 4] {
    let (a, b) = (h, h * h);
    let k = [[12.0, 6.0 * a, -12.0, 6.0 * a], [6.0 * a, 4.0 * b, -6.0 * a, 2.0 * b], [-12.0, -6.0 * a, 12.0, -6.0 * a], [6.0 * a, 2.0 * b, -6.0 * a, 4.0 * b]];
    k.map(|row| row.map(|v| v * k2 / (h * h * h)))
}

/// Dense assembly over `J` elements: element `e` joins nodes `e` and
/// `e + 1`; node `j >= 1` owns unknowns `2(j-1)` (value) and `2(j-1)+1`
/// (slope); node 0 is clamped (its two local dofs are dropped).
fn hand_assemble(j_elems: usize, elem: [[f64; 4]; 4]) -> Mat<f64> {
    let n = 2 * j_elems;
    let mut out = Mat::<f64>::zeros(n, n);
    let dof = |e: usize, a: usize| -> Option<usize> {
        let node = if a < 2 { e } else { e + 1 };
        (node >= 1).then(|| 2 * (node - 1) + (a % 2))
    };
    for e in 0..j_elems {
        for (a, row) in elem.iter().enumerate() {
            for (b, v) in row.iter().enumerate() {
                if let (Some(i), Some(j)) = (dof(e, a), dof(e, b)) {
                    out[(i, j)] += v;
                }
            }
        }
    }
    out
}

fn hand_matrices(b: &Beam) -> (Mat<f64>, Mat<f64>) {
    let h = b.length / b.elements as f64;
    (hand_assemble(b.elements, hand_element_stiffness(h, b.k2)), hand_assemble(b.elements, hand_element_mass(h)))
}

#[test]
fn element_and_assembled_matrices_equal_hand_built_ones() {
    for h in [0.3, 1.501 / 19.0] {
        let (m, k) = (element_mass(h), element_stiffness(h, 282.84));
        let (hm, hk) = (hand_element_mass(h), hand_element_stiffness(h, 282.84));
        for i in 0..4 {
            for j in 0..4 {
                assert!(close(m[i][j], hm[i][j], 1e-15) || m[i][j] == hm[i][j], "M_e[{i}][{j}] = {} vs {}", m[i][j], hm[i][j]);
                assert!(close(k[i][j], hk[i][j], 1e-15), "K_e[{i}][{j}] = {} vs {}", k[i][j], hk[i][j]);
            }
        }
    }
    for j in [1usize, 2, 3, 7, 19] {
        let b = Beam::new(1.501, j, 282.84).unwrap();
        let (k, m) = hand_matrices(&b);
        assert_matrix_eq(&b.mass(), &m, 1e-14, &format!("beam M, J = {j}"));
        assert_matrix_eq(&b.stiffness(), &k, 1e-14, &format!("beam K, J = {j}"));
        assert_eq!(b.tip_dof(), 2 * j - 2);
    }
    // Two entries written out (J = 2, h = L/2): the tip value's mass is one
    // element's 156 h/420, node 1's value couples to the tip by 54 h/420.
    let b = Beam::new(2.0, 2, 3.0).unwrap();
    assert!(close(b.mass().get(2, 2), 156.0 / 420.0, 1e-15));
    assert!(close(b.mass().get(0, 2), 54.0 / 420.0, 1e-15));
    assert!(close(b.stiffness().get(0, 0), 2.0 * 12.0 * 3.0, 1e-15));
    assert!(close(b.stiffness().get(1, 3), 2.0 * 3.0, 1e-15));
}

#[test]
fn quadratic_forms_of_polynomials_are_exact() {
    let b = Beam::new(1.501, 19, 282.84).unwrap();
    let l = b.length;
    // u = x² and x³ satisfy the clamping u(0) = u'(0) = 0.
    let u2 = b.interpolate(|x| x * x, |x| 2.0 * x);
    let u3 = b.interpolate(|x| x * x * x, |x| 3.0 * x * x);
    assert!(close(b.mass().quad_form(&u2), l.powi(5) / 5.0, 1e-12));
    assert!(close(b.mass().bilinear(&u2, &u3), l.powi(6) / 6.0, 1e-12));
    // UᵀKU of a smooth u cancels terms of size ‖K‖‖u‖² ≈ 1e6 times the
    // result (K ~ k²/h³): relative rounding up to ~1e-10.
    assert!(close(b.stiffness().quad_form(&u2), b.k2 * 4.0 * l, 1e-9));
    assert!(close(b.stiffness().quad_form(&u3), b.k2 * 12.0 * l.powi(3), 1e-9));
    // Load of a quartic against x²: ∫ (1 + x⁴) x² dx, exact with 4 Gauss points.
    let f = b.load(|x| 1.0 + x.powi(4));
    let got: f64 = f.iter().zip(&u2).map(|(a, c)| a * c).sum();
    assert!(close(got, l.powi(3) / 3.0 + l.powi(7) / 7.0, 1e-12));
}

#[test]
fn total_mass_and_rigid_modes_per_element() {
    let h = 0.3;
    let (m, k) = (element_mass(h), element_stiffness(h, 7.0));
    let quad = |a: &[[f64; 4]; 4], v: [f64; 4]| -> f64 { (0..4).map(|i| (0..4).map(|j| v[i] * a[i][j] * v[j]).sum::<f64>()).sum() };
    // Constant 1: values 1, slopes 0: mass ρS h per element, so ρS L in all.
    assert!(close(quad(&m, [1.0, 0.0, 1.0, 0.0]), h, 1e-14));
    // Constants and linear functions are in the kernel of the free beam's stiffness.
    for v in [[1.0, 0.0, 1.0, 0.0], [0.0, 1.0, h, 1.0]] {
        for i in 0..4 {
            let r: f64 = (0..4).map(|j| k[i][j] * v[j]).sum();
            assert!(r.abs() < 1e-12 * 7.0 / h.powi(3), "{r}");
        }
    }
}

/// `β₁ L` of the clamped-free (cantilever) beam: the first root of
/// `cos(x) cosh(x) = -1`, found here by bisection.
fn cantilever_root() -> f64 {
    let f = |x: f64| x.cos() * x.cosh() + 1.0;
    let (mut a, mut b) = (1.5, 2.5);
    for _ in 0..200 {
        let c = 0.5 * (a + b);
        if f(a) * f(c) <= 0.0 {
            b = c;
        } else {
            a = c;
        }
    }
    0.5 * (a + b)
}

#[test]
fn smallest_eigenvalue_approaches_the_cantilever_from_above() {
    let root = cantilever_root();
    assert!((root - 1.875_104_068_711_961).abs() < 1e-12, "{root}");
    let (l, k2): (f64, f64) = (1.501, 282.84);
    let exact = k2 * root.powi(4) / l.powi(4);
    let mut prev_err = f64::INFINITY;
    for j in [1usize, 2, 4, 8, 16] {
        let b = Beam::new(l, j, k2).unwrap();
        let (k, m) = hand_matrices(&b);
        let eig = generalized_eigenvalues(&k, &m);
        let lo = eig[0];
        // Conforming Galerkin with the consistent mass: eigenvalues are upper
        // bounds of the continuous ones, converging as h⁴ (halving h divides
        // the error by 16 asymptotically; by 9.9 from J = 1 to 2).
        let err = (lo - exact) / exact;
        assert!(err >= -1e-12, "J = {j}: smallest {lo} below the continuous {exact}");
        assert!(err < prev_err / 8.0 || err < 1e-10, "J = {j}: relative error {err:e} after {prev_err:e}");
        prev_err = err;
        eprintln!("J = {j}: smallest eigenvalue {lo:.12e}, cantilever {exact:.12e}, rel. error {err:.3e}");
        // The banded matrices have the same spectrum (through their own factorisation: positive definite).
        assert!(b.mass().factor().is_ok() && b.stiffness().factor().is_ok());
    }
    assert!(prev_err < 1e-6, "J = 16: relative error {prev_err:e}");
}

/// κ_h against a dense faer solve of the hand-assembled pencil.
fn dense_kappa(b: &Beam) -> f64 {
    let (k, m) = hand_matrices(b);
    *generalized_eigenvalues(&k, &m).last().unwrap()
}

#[test]
fn kappa_matches_dense_eigensolver_and_bounds() {
    for j in [1usize, 2, 5, 19, 40] {
        let b = Beam::new(1.501, j, 282.84).unwrap();
        let bound = b.element_kappa_bound();
        let (kappa, iters) = max_generalized_eigenvalue(&b.stiffness(), &b.mass(), bound * (1.0 + 1e-3), 200_000).unwrap();
        let want = dense_kappa(&b);
        assert!(close(kappa, want, 1e-10), "J = {j}: {kappa} vs {want} ({iters} iterations)");
        eprintln!("J = {j}: κ_h = {kappa:.10e} in {iters} iterations; element bound {bound:.4e}");
        assert!(bound >= kappa * (1.0 - 1e-12), "J = {j}: element bound {bound} < κ {kappa}");
        // The paper's appendix bound (5.2): 24·420·19²/37 · k²/h⁴.
        let paper = 24.0 * 420.0 * 361.0 / 37.0 * b.k2 / b.h().powi(4);
        assert!(paper > bound, "J = {j}: paper bound {paper} vs element bound {bound}");
    }
}
