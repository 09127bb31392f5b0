//! Shared by the event tests: the chain of masses they run, and the
//! oracles' dense inverse.

use signorini_fem::SymBand;

/// `(M, K)` of `n` masses in a chain: a P1-like consistent mass, unit
/// springs, tied to a wall at the far end unless `free` (then both ends
/// are half elements).
#[allow(dead_code)]
pub fn chain_matrices(n: usize, free: bool) -> (SymBand, SymBand) {
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        let end = i == 0 || (free && i == n - 1);
        m.set(i, i, if end { 1.0 / 3.0 } else { 2.0 / 3.0 });
        k.set(i, i, if end { 1.0 } else { 2.0 });
        if i > 0 {
            m.set(i, i - 1, 1.0 / 6.0);
            k.set(i, i - 1, -1.0);
        }
    }
    (m, k)
}

/// The inverse of the dense `a` restricted to the dofs `keep` (Gauss–Jordan
/// with partial pivoting), embedded in `n × n` with zeros elsewhere.
#[allow(dead_code)]
pub fn inverse(a: &[f64], n: usize, keep: &[usize]) -> Vec<f64> {
    let p = keep.len();
    let mut w: Vec<Vec<f64>> = (0..p).map(|i| (0..p).map(|j| a[keep[i] * n + keep[j]]).chain((0..p).map(|j| if i == j { 1.0 } else { 0.0 })).collect()).collect();
    for col in 0..p {
        let piv = (col..p).max_by(|&x, &y| w[x][col].abs().total_cmp(&w[y][col].abs())).unwrap();
        w.swap(col, piv);
        let d = w[col][col];
        assert!(d.abs() > 1e-300, "singular");
        w[col].iter_mut().for_each(|x| *x /= d);
        for r in 0..p {
            if r != col {
                let f = w[r][col];
                if f != 0.0 {
                    let row = w[col].clone();
                    w[r].iter_mut().zip(&row).for_each(|(x, y)| *x -= f * y);
                }
            }
        }
    }
    let mut out = vec![0.0; n * n];
    for i in 0..p {
        for j in 0..p {
            out[keep[i] * n + keep[j]] = w[i][p + j];
        }
    }
    out
}
