//! Dense oracles shared by the fem tests: matrices as dense faer matrices
//! and generalized eigenvalues of a symmetric-definite pencil computed by
//! faer's dense solvers (independent of the crate's banded code).

#![allow(dead_code)]

use faer::{Mat, Side};
use signorini_fem::SymBand;

/// The dense matrix of a `SymBand` read from its storage (`get`), the
/// oracle the factorisation, the products and the eigenvalue bounds are
/// checked against (matrices.rs, kappa_bound.rs); [`dense_operator`] reads
/// the same matrix through `mul_vec` instead, and [`assert_matrix_eq`]
/// checks both readings.
pub fn dense(a: &SymBand) -> Mat<f64> {
    Mat::from_fn(a.n(), a.n(), |i, j| a.get(i, j))
}

/// The dense matrix of a `SymBand`, read column by column through
/// `mul_vec` on unit vectors (the operator, not the storage).
pub fn dense_operator(a: &SymBand) -> Mat<f64> {
    let n = a.n();
    let mut out = Mat::<f64>::zeros(n, n);
    let mut e = vec![0.0; n];
    let mut y = vec![0.0; n];
    for j in 0..n {
        e[j] = 1.0;
        a.mul_vec(&e, &mut y);
        for i in 0..n {
            out[(i, j)] = y[i];
        }
        e[j] = 0.0;
    }
    out
}

/// Asserts `a` equals the hand-built dense `want`, entry by entry, both
/// through `get` and through the operator (`mul_vec`), to `tol` times the
/// largest entry of `want`.
pub fn assert_matrix_eq(a: &SymBand, want: &Mat<f64>, tol: f64, what: &str) {
    let n = want.nrows();
    assert_eq!(a.n(), n, "{what}: size");
    let scale = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).fold(0.0f64, |s, (i, j)| s.max(want[(i, j)].abs()));
    let op = dense_operator(a);
    for i in 0..n {
        for j in 0..n {
            let w = want[(i, j)];
            let (g, o) = (a.get(i, j), op[(i, j)]);
            assert!((g - w).abs() <= tol * scale, "{what}: entry ({i},{j}) = {g}, hand-assembled {w}");
            assert!((o - w).abs() <= tol * scale, "{what}: operator entry ({i},{j}) = {o}, hand-assembled {w}");
        }
    }
}

/// All generalized eigenvalues of `(K, M)`, `M` SPD, ascending: the
/// eigenvalues of `L⁻¹ K L⁻ᵀ` with `M = L Lᵀ` (dense faer Cholesky, two
/// triangular solves and a symmetric eigensolver).
pub fn generalized_eigenvalues(k: &Mat<f64>, m: &Mat<f64>) -> Vec<f64> {
    let n = m.nrows();
    let l = m.llt(Side::Lower).expect("M must be SPD").L().to_owned();
    let mut linv = Mat::<f64>::identity(n, n);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), faer::Par::Seq);
    let c = &linv * k * linv.transpose();
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let mut e = c.self_adjoint_eigenvalues(Side::Lower).unwrap();
    e.sort_by(|a, b| a.partial_cmp(b).unwrap());
    e
}

/// The trailing principal submatrix on `start..n`.
pub fn trailing(a: &Mat<f64>, start: usize) -> Mat<f64> {
    let n = a.nrows() - start;
    Mat::from_fn(n, n, |i, j| a[(i + start, j + start)])
}

/// `|a - b| <= tol |b|`.
pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1e-300)
}
