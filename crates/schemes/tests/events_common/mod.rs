//! Shared by the event tests: the chain of masses they run.

use signorini_fem::SymBand;

/// `(M, K)` of `n` masses in a chain: a P1-like consistent mass, unit
/// springs, tied to a wall at the far end unless `free` (then both ends
/// are half elements).
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
