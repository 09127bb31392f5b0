//! Hermite-cubic beam matrices and the exact stability eigenvalue.
//! Polynomials of degree <= 3 are represented exactly by the Hermite space,
//! so quadratic forms of interpolants equal the integrals to rounding (1e-12
//! relative); the eigenvalue is checked against a dense faer solve to 1e-10.

use faer::{Mat, Side};
use signorini_fem::beam::{element_mass, element_stiffness};
use signorini_fem::{max_generalized_eigenvalue, Beam, SymBand};

fn dense(a: &SymBand) -> Mat<f64> {
    Mat::from_fn(a.n(), a.n(), |i, j| a.get(i, j))
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1e-300)
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
    // Symmetry.
    for i in 0..4 {
        for j in 0..4 {
            assert_eq!(m[i][j], m[j][i]);
            assert_eq!(k[i][j], k[j][i]);
        }
    }
}

#[test]
fn clamped_matrices_are_positive_definite() {
    let b = Beam::new(1.0, 6, 2.0).unwrap();
    for a in [b.mass(), b.stiffness()] {
        let e = dense(&a).self_adjoint_eigenvalues(Side::Lower).unwrap();
        assert!(e[0] > 0.0, "{e:?}");
        assert!(a.factor().is_ok());
    }
}

/// κ_h against a dense solve: eigenvalues of L⁻¹ K L⁻ᵀ with M = L Lᵀ.
fn dense_kappa(b: &Beam) -> f64 {
    let (m, k) = (dense(&b.mass()), dense(&b.stiffness()));
    let l = m.llt(Side::Lower).unwrap().L().to_owned();
    let n = m.nrows();
    // C = L⁻¹ K L⁻ᵀ via two triangular solves on dense columns.
    let linv = {
        let mut id = Mat::<f64>::identity(n, n);
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), id.as_mut(), faer::Par::Seq);
        id
    };
    let c = &linv * &k * linv.transpose();
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    *c.self_adjoint_eigenvalues(Side::Lower).unwrap().last().unwrap()
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
