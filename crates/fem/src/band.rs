//! Symmetric banded matrices and their LDLᵀ factorisation.
//!
//! Storage is the lower band, row by row: entry `(i, i-k)` for `k = 0..=p`
//! lives at `data[i * (p + 1) + k]` (entries with `i - k < 0` are unused and
//! kept at zero). The factorisation is the textbook banded LDLᵀ without
//! pivoting, valid for symmetric positive definite matrices; it is computed
//! once per run and then applied in place, allocating nothing.
//!
//! The solve is specialised for the half-bandwidths that occur (1: P1 bar,
//! 3: Hermite beam) so the inner loops have compile-time trip counts; the
//! benchmark `benches/step.rs` of `signorini-schemes` measures it against a
//! bare hand-written tridiagonal solve. A tridiagonal factor whose `L` is
//! the identity (a lumped mass) is solved by a product per row, with the
//! sweeps' bits (`BandLdlt::solve_diagonal`).

use crate::FemError;

/// A real symmetric matrix with half-bandwidth `p` (`A[i][j] = 0` for `|i-j| > p`).
#[derive(Clone, Debug)]
pub struct SymBand {
    n: usize,
    p: usize,
    data: Vec<f64>,
    /// Half-bandwidth 3 (the beam): the band by diagonals for
    /// [`mul_vec`](Self::mul_vec), made at the first product after the
    /// last change (every `&mut` method resets it).
    diagonals: std::sync::OnceLock<Diagonals3>,
}

impl PartialEq for SymBand {
    fn eq(&self, other: &Self) -> bool {
        (self.n, self.p) == (other.n, other.p) && self.data == other.data
    }
}

impl SymBand {
    /// The zero `n × n` matrix with half-bandwidth `p`.
    pub fn zeros(n: usize, p: usize) -> Self {
        Self { n, p, data: vec![0.0; n * (p + 1)], diagonals: std::sync::OnceLock::new() }
    }

    /// The diagonal matrix with `d` on its diagonal (half-bandwidth 0): a
    /// lumped mass, or a one-dof structure's mass, stiffness or damping.
    pub fn from_diagonal(d: &[f64]) -> Self {
        Self { n: d.len(), p: 0, data: d.to_vec(), diagonals: std::sync::OnceLock::new() }
    }

    /// The product by diagonals is stale after a change.
    fn changed(&mut self) {
        self.diagonals = std::sync::OnceLock::new();
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Half-bandwidth.
    pub fn half_bandwidth(&self) -> usize {
        self.p
    }

    /// The sum of all entries `Σ_ij A_ij` (`1ᵀ A 1`; for a mass matrix of
    /// translational dofs, the total mass carried by them).
    pub fn total(&self) -> f64 {
        let mut s = 0.0;
        for i in 0..self.n {
            for k in 0..=self.p.min(i) {
                let v = self.data[i * (self.p + 1) + k];
                s += if k == 0 { v } else { 2.0 * v };
            }
        }
        s
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> Option<usize> {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        (i < self.n && i - j <= self.p).then(|| i * (self.p + 1) + (i - j))
    }

    /// Entry `(i, j)` (zero outside the band).
    #[track_caller]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        assert!(i < self.n && j < self.n, "index ({i},{j}) out of {}x{}", self.n, self.n);
        self.idx(i, j).map_or(0.0, |k| self.data[k])
    }

    /// Sets entry `(i, j)` and its mirror. Panics outside the band (programmer error).
    #[track_caller]
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        let k = self.idx(i, j).unwrap_or_else(|| panic!("({i},{j}) outside the band"));
        self.data[k] = v;
        self.changed();
    }

    /// Adds `v` to entry `(i, j)` (and so to its mirror).
    #[track_caller]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let k = self.idx(i, j).unwrap_or_else(|| panic!("({i},{j}) outside the band"));
        self.data[k] += v;
        self.changed();
    }

    /// `a * self + b * other` (same shape).
    #[track_caller]
    pub fn lin_comb(&self, a: f64, other: &SymBand, b: f64) -> SymBand {
        assert_eq!((self.n, self.p), (other.n, other.p), "shape mismatch");
        let data = self.data.iter().zip(&other.data).map(|(x, y)| a * x + b * y).collect();
        SymBand { n: self.n, p: self.p, data, diagonals: std::sync::OnceLock::new() }
    }

    /// `out = a * self + b * other` (same shape), without allocating: the
    /// shifted matrices `σM − K` of an inertia test repeated in a loop.
    #[track_caller]
    pub fn lin_comb_into(&self, a: f64, other: &SymBand, b: f64, out: &mut SymBand) {
        assert!((self.n, self.p) == (other.n, other.p) && (self.n, self.p) == (out.n, out.p), "shape mismatch");
        for ((o, x), y) in out.data.iter_mut().zip(&self.data).zip(&other.data) {
            *o = a * x + b * y;
        }
        out.changed();
    }

    /// The trailing principal submatrix on indices `start..n`.
    pub fn trailing(&self, start: usize) -> SymBand {
        let mut out = SymBand::zeros(self.n - start, self.p);
        for i in start..self.n {
            for j in i.saturating_sub(self.p).max(start)..=i {
                out.set(i - start, j - start, self.get(i, j));
            }
        }
        out
    }

    /// Zeroes row and column `i`.
    pub fn zero_row_col(&mut self, i: usize) {
        for j in i.saturating_sub(self.p)..(i + self.p + 1).min(self.n) {
            self.set(i, j, 0.0);
        }
    }

    /// The `k`-th sub-diagonal as a vector of length `n`: entry `i` is
    /// `A[i][i-k]` (zero for `i < k`). `k = 0` is the diagonal.
    pub fn diagonal(&self, k: usize) -> Vec<f64> {
        (0..self.n).map(|i| if i >= k && k <= self.p { self.data[i * (self.p + 1) + k] } else { 0.0 }).collect()
    }

    /// `y = A x`.
    #[track_caller]
    #[inline]
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert!(x.len() == self.n && y.len() == self.n, "length mismatch");
        match self.p {
            1 if self.n >= 2 => self.mul_vec_tridiag(x, y),
            3 if self.n > 6 => self.diagonals.get_or_init(|| Diagonals3::new(self)).mul_vec(x, y),
            3 => self.mul_vec_p::<3>(x, y),
            _ => self.mul_vec_generic(x, y),
        }
    }

    /// `x^T A x`.
    pub fn quad_form(&self, x: &[f64]) -> f64 {
        assert_eq!(x.len(), self.n, "length mismatch");
        let p1 = self.p + 1;
        let mut s = 0.0;
        for i in 0..self.n {
            let row = &self.data[i * p1..(i + 1) * p1];
            let mut off = 0.0;
            for k in 1..=self.p.min(i) {
                off += row[k] * x[i - k];
            }
            s += x[i] * (row[0] * x[i] + 2.0 * off);
        }
        s
    }

    /// `x^T A y`.
    pub fn bilinear(&self, x: &[f64], y: &[f64]) -> f64 {
        assert!(x.len() == self.n && y.len() == self.n, "length mismatch");
        let p1 = self.p + 1;
        let mut s = 0.0;
        for i in 0..self.n {
            let row = &self.data[i * p1..(i + 1) * p1];
            s += row[0] * x[i] * y[i];
            for k in 1..=self.p.min(i) {
                s += row[k] * (x[i] * y[i - k] + x[i - k] * y[i]);
            }
        }
        s
    }

    fn mul_vec_generic(&self, x: &[f64], y: &mut [f64]) {
        let p1 = self.p + 1;
        y.fill(0.0);
        for i in 0..self.n {
            let row = &self.data[i * p1..(i + 1) * p1];
            let mut s = row[0] * x[i];
            for k in 1..=self.p.min(i) {
                s += row[k] * x[i - k];
                y[i - k] += row[k] * x[i];
            }
            y[i] += s;
        }
    }

    fn mul_vec_tridiag(&self, x: &[f64], y: &mut [f64]) {
        let n = self.n;
        let d = &self.data[..2 * n];
        let (x, y) = (&x[..n], &mut y[..n]);
        y[0] = d[0] * x[0] + d[3] * x[1];
        for i in 1..n - 1 {
            y[i] = d[2 * i + 1] * x[i - 1] + d[2 * i] * x[i] + d[2 * i + 3] * x[i + 1];
        }
        y[n - 1] = d[2 * n - 1] * x[n - 2] + d[2 * n - 2] * x[n - 1];
    }

    /// Half-bandwidth 3, row by row: interior rows read a fixed window of 7
    /// entries of x (bounds checked once per row) and the row's 7
    /// coefficients. [`Diagonals3::mul_vec`] is the same arithmetic by
    /// diagonals (what [`mul_vec`](Self::mul_vec) uses); this is its
    /// reference in the tests.
    #[doc(hidden)]
    pub fn mul_vec_p3(&self, x: &[f64], y: &mut [f64]) {
        let n = self.n;
        let d = &self.data[..n * 4];
        let row = |i: usize| -> f64 {
            let mut s = d[i * 4] * x[i];
            for k in 1..=3 {
                if i >= k {
                    s += d[i * 4 + k] * x[i - k];
                }
                if i + k < n {
                    s += d[(i + k) * 4 + k] * x[i + k];
                }
            }
            s
        };
        for i in (0..3).chain(n - 3..n) {
            y[i] = row(i);
        }
        for i in 3..n - 3 {
            let xw: &[f64; 7] = x[i - 3..i + 4].try_into().expect("window of 7");
            let r: &[f64; 4] = d[i * 4..i * 4 + 4].try_into().expect("row of 4");
            let (c1, c2, c3) = (d[(i + 1) * 4 + 1], d[(i + 2) * 4 + 2], d[(i + 3) * 4 + 3]);
            y[i] = (r[0] * xw[3] + r[1] * xw[2] + r[2] * xw[1] + r[3] * xw[0]) + (c1 * xw[4] + c2 * xw[5] + c3 * xw[6]);
        }
    }

    fn mul_vec_p<const P: usize>(&self, x: &[f64], y: &mut [f64]) {
        let n = self.n;
        if n <= 2 * P {
            return self.mul_vec_generic(x, y);
        }
        // Row i: sum_k A[i][i-k] x[i-k] + sum_k A[i+k][i] x[i+k]; the rows
        // P..n-P have every neighbour, so their loop is branch-free.
        let d = &self.data[..n * (P + 1)];
        let row = |i: usize| -> f64 {
            let mut s = d[i * (P + 1)] * x[i];
            for k in 1..=P {
                if i >= k {
                    s += d[i * (P + 1) + k] * x[i - k];
                }
                if i + k < n {
                    s += d[(i + k) * (P + 1) + k] * x[i + k];
                }
            }
            s
        };
        for i in (0..P).chain(n - P..n) {
            y[i] = row(i);
        }
        let x = &x[..n];
        for i in P..n - P {
            let xs = &x[i - P..=i + P];
            let dr = &d[i * (P + 1)..(i + P + 1) * (P + 1)];
            let mut s = dr[0] * xs[P];
            for k in 1..=P {
                s += dr[k] * xs[P - k] + dr[k * (P + 1) + k] * xs[P + k];
            }
            y[i] = s;
        }
    }

    /// Copies `other` (same size and bandwidth) into `self` without
    /// allocating (the product by diagonals is made again at the next
    /// product).
    #[track_caller]
    pub fn copy_from(&mut self, other: &SymBand) {
        assert!(self.n == other.n && self.p == other.p, "size mismatch");
        self.data.copy_from_slice(&other.data);
        self.changed();
    }

    /// Banded LDLᵀ factorisation (no pivoting). Fails with
    /// [`FemError::NotPositiveDefinite`] if a pivot is not positive and finite.
    pub fn factor(&self) -> Result<BandLdlt, FemError> {
        let (n, p) = (self.n, self.p);
        let mut out = BandLdlt::zeros(n, p);
        self.factor_into(&mut out)?;
        Ok(out)
    }

    /// [`factor`](Self::factor) into the storage of an existing factor of
    /// the same size and bandwidth: no allocation (for factorisations
    /// repeated in a loop).
    #[track_caller]
    pub fn factor_into(&self, out: &mut BandLdlt) -> Result<(), FemError> {
        let (n, p) = (self.n, self.p);
        assert!(out.n == n && out.p == p, "size mismatch");
        out.diagonal = None;
        let (l, d) = (&mut out.l, &mut out.d);
        l.iter_mut().for_each(|x| *x = 0.0);
        // l[i*p + k-1] = L[i][i-k], k = 1..=p.
        for j in 0..n {
            let mut dj = self.get(j, j);
            for k in 1..=p.min(j) {
                let ljk = l[j * p + k - 1];
                dj -= ljk * ljk * d[j - k];
            }
            if !(dj > 0.0 && dj.is_finite()) {
                return Err(FemError::NotPositiveDefinite { pivot: j, value: dj });
            }
            d[j] = dj;
            for i in j + 1..(j + p + 1).min(n) {
                // L[i][j] = (A[i][j] - sum_{q<j} L[i][q] L[j][q] d[q]) / d[j]
                let mut s = self.get(i, j);
                for q in i.saturating_sub(p)..j {
                    if j - q <= p {
                        s -= l[i * p + (i - q) - 1] * l[j * p + (j - q) - 1] * d[q];
                    }
                }
                l[i * p + (i - j) - 1] = s / dj;
            }
        }
        for (inv, x) in out.inv_d.iter_mut().zip(d.iter()) {
            *inv = 1.0 / x;
        }
        // Transposed copy for the backward sweep: lt[i*p + k-1] = L[i+k][i].
        for i in 0..n {
            for k in 1..=p {
                out.lt[i * p + k - 1] = if i + k < n { l[(i + k) * p + k - 1] } else { 0.0 };
            }
        }
        out.diagonal = (p == 1 && n >= 1 && out.l.iter().all(|x| *x == 0.0)).then(avx2_available);
        Ok(())
    }
}

/// Whether the CPU has AVX2 (false off x86-64).
fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// The factor `L D Lᵀ` of a [`SymBand`] (unit lower triangular `L` with the
/// same bandwidth).
#[derive(Clone, Debug)]
pub struct BandLdlt {
    n: usize,
    p: usize,
    l: Vec<f64>,
    lt: Vec<f64>,
    d: Vec<f64>,
    inv_d: Vec<f64>,
    /// A tridiagonal factor whose `L` is the identity (every sub-diagonal
    /// entry zero: a lumped mass): [`solve_in_place`](Self::solve_in_place)
    /// takes the diagonal path ([`solve_diagonal`](Self::solve_diagonal));
    /// `Some(avx2)`, whether the CPU has AVX2 (chosen at run time, no FMA,
    /// so the same bits).
    diagonal: Option<bool>,
}

/// `x` is infinite, NaN or `−0`: where `b − 0·y` is not `b` (a sweep's
/// step over a zero entry of `L`), as 0 or 1.
#[inline(always)]
fn not_plain(x: f64) -> u64 {
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    let b = x.to_bits();
    u64::from(b & EXP == EXP) | u64::from(b == 1 << 63)
}

/// The diagonal path's body: if no `b_i · (1/D_i)` is infinite, NaN or
/// `−0`, `b_i ← b_i · (1/D_i)` and true; otherwise false and `b`
/// untouched. (With `1/D_i > 0`, possibly `+∞`, a `b_i` that is infinite,
/// NaN or `−0` makes its product so: `b` needs no check of its own.)
#[inline(always)]
fn diagonal_body(inv_d: &[f64], b: &mut [f64]) -> bool {
    let n = b.len();
    let inv_d = &inv_d[..n];
    let mut odd = 0;
    for (x, s) in b.iter().zip(inv_d) {
        odd |= not_plain(x * s);
    }
    if odd != 0 {
        return false;
    }
    for (x, s) in b.iter_mut().zip(inv_d) {
        *x *= s;
    }
    true
}

/// [`diagonal_body`] compiled with AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn diagonal_body_avx2(inv_d: &[f64], b: &mut [f64]) -> bool {
    diagonal_body(inv_d, b)
}

impl BandLdlt {
    /// Storage for the factor of an `n × n` matrix of half-bandwidth `p`,
    /// to be filled by [`SymBand::factor_into`].
    pub fn zeros(n: usize, p: usize) -> Self {
        BandLdlt { n, p, l: vec![0.0; n * p.max(1)], lt: vec![0.0; n * p.max(1)], d: vec![0.0; n], inv_d: vec![0.0; n], diagonal: None }
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The pivots `D`.
    pub fn pivots(&self) -> &[f64] {
        &self.d
    }

    /// Half-bandwidth.
    pub fn half_bandwidth(&self) -> usize {
        self.p
    }

    /// For a tridiagonal factor (`p = 1`): the sub-diagonal of `L`
    /// (`l[i] = L[i][i-1]`, `l[0] = 0`) and the inverse pivots `1/D`, for
    /// callers that fuse their own work into the sweeps. `None` otherwise.
    pub fn tridiagonal_factors(&self) -> Option<(&[f64], &[f64])> {
        (self.p == 1).then(|| (&self.l[..self.n], &self.inv_d[..]))
    }

    /// The factor's storage, for callers that run their own sweeps with the
    /// same arithmetic (several right-hand sides in lockstep): `(l, lt, inv_d)`
    /// with `l[i p + k - 1] = L[i][i-k]` (zero for `i < k`),
    /// `lt[i p + k - 1] = L[i+k][i]` (zero for `i + k >= n`), `k = 1..=p`,
    /// and `inv_d[i] = 1 / D[i]`.
    pub fn band_factors(&self) -> (&[f64], &[f64], &[f64]) {
        (&self.l, &self.lt, &self.inv_d)
    }

    /// `bᵀ A⁻¹ b = ‖L⁻¹ b‖²_{D⁻¹}`: one forward sweep, no scratch, `b` untouched.
    pub fn inverse_quad_form(&self, b: &[f64]) -> f64 {
        assert_eq!(b.len(), self.n, "length mismatch");
        let n = self.n;
        if n == 0 {
            return 0.0;
        }
        if self.p == 1 {
            let (l, inv_d, b) = (&self.l[..n], &self.inv_d[..n], &b[..n]);
            let mut prev = b[0];
            let mut s = prev * prev * inv_d[0];
            for i in 1..n {
                prev = b[i] - l[i] * prev;
                s += prev * prev * inv_d[i];
            }
            return s;
        }
        let mut y = b.to_vec();
        let p = self.p;
        let mut s = 0.0;
        for i in 0..n {
            let mut v = y[i];
            for k in 1..=p.min(i) {
                v -= self.l[i * p + k - 1] * y[i - k];
            }
            y[i] = v;
            s += v * v * self.inv_d[i];
        }
        s
    }

    /// Solves `A x = b` in place (`b` becomes `x`). Allocates nothing.
    #[track_caller]
    #[inline]
    pub fn solve_in_place(&self, b: &mut [f64]) {
        assert_eq!(b.len(), self.n, "length mismatch");
        match self.p {
            0 => b.iter_mut().zip(&self.inv_d).for_each(|(x, s)| *x *= s),
            1 if self.diagonal.is_some() => self.solve_diagonal(b),
            1 => self.solve_tridiag(b),
            2 => self.solve_p::<2>(b),
            3 if self.n > 3 => self.solve_p3(b),
            3 => self.solve_p::<3>(b),
            _ => self.solve_generic(b),
        }
    }

    /// The second half of [`solve_in_place`](Self::solve_in_place): from
    /// `y = L⁻¹ b` (a forward sweep the caller ran itself, with
    /// [`band_factors`](Self::band_factors), fused with other work),
    /// `b` becomes `x = L⁻ᵀ D⁻¹ y` — the backward sweep of `solve_in_place`,
    /// the same operations in the same order, so the same bits. Allocates nothing.
    #[track_caller]
    #[inline]
    pub fn backward_in_place(&self, b: &mut [f64]) {
        assert_eq!(b.len(), self.n, "length mismatch");
        match self.p {
            0 => b.iter_mut().zip(&self.inv_d).for_each(|(x, s)| *x *= s),
            1 => self.backward_tridiag(b),
            2 if self.n > 2 => self.backward_p::<2>(b),
            3 if self.n > 3 => self.backward_p3(b),
            _ => self.backward_generic(b),
        }
    }

    /// The tridiagonal solve when `L` is the identity (a lumped mass),
    /// the same bits as the sweeps ([`solve_tridiag`](Self::solve_tridiag)):
    /// with every `l_i = ±0`, the forward sweep's `y_i = b_i − l_i y_{i−1}`
    /// is `b_i` while every `b_i` is finite and not `−0`, and the backward
    /// sweep's `x_i = y_i/D_i − l_{i+1} x_{i+1}` is `y_i (1/D_i)` while every
    /// such product is finite and not `−0` (`b − (±0)` is `b` for any other
    /// finite `b`). So one check pass and one product pass (vectorised;
    /// AVX2 chosen at run time, no FMA) where the sweeps' two dependency
    /// chains cost a multiplication and a subtraction's latency a row
    /// each; if any value is infinite, NaN or `−0` (a zero's sign or a
    /// NaN that the sweeps would carry to the other rows), the sweeps.
    fn solve_diagonal(&self, b: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if self.diagonal == Some(true) {
            // SAFETY: `Some(true)` is set only when the CPU reports AVX2.
            if unsafe { diagonal_body_avx2(&self.inv_d, b) } {
                return;
            }
            return self.solve_tridiag(b);
        }
        if !diagonal_body(&self.inv_d, b) {
            self.solve_tridiag(b);
        }
    }

    fn solve_tridiag(&self, b: &mut [f64]) {
        let n = self.n;
        let l = &self.l[..n];
        let inv_d = &self.inv_d[..n];
        let b = &mut b[..n];
        // The running value stays in a register: the loop-carried dependency
        // is one fused multiply-add, not a store/load round trip.
        let mut prev = b[0];
        for i in 1..n {
            prev = b[i] - l[i] * prev;
            b[i] = prev;
        }
        Self::backward_tridiag_body(l, inv_d, b);
    }

    fn backward_tridiag(&self, b: &mut [f64]) {
        let n = self.n;
        Self::backward_tridiag_body(&self.l[..n], &self.inv_d[..n], &mut b[..n]);
    }

    #[inline(always)]
    fn backward_tridiag_body(l: &[f64], inv_d: &[f64], b: &mut [f64]) {
        let n = b.len();
        let mut next = b[n - 1] * inv_d[n - 1];
        b[n - 1] = next;
        for i in (0..n - 1).rev() {
            next = b[i] * inv_d[i] - l[i + 1] * next;
            b[i] = next;
        }
    }

    fn solve_p<const P: usize>(&self, b: &mut [f64]) {
        let n = self.n;
        if n <= P {
            return self.solve_generic(b);
        }
        let (l, b) = (&self.l[..n * P], &mut b[..n]);
        for i in 1..P {
            let mut s = b[i];
            for k in 1..=i {
                s -= l[i * P + k - 1] * b[i - k];
            }
            b[i] = s;
        }
        // Rows with P predecessors: fixed trip count, contiguous row of L.
        // The last P results stay in registers (`win[k-1]` = y[i-k]), the
        // farthest terms are subtracted first, so the loop-carried dependency
        // is a single fused multiply-add, with no store-to-load round trip.
        let mut win = [0.0; P];
        for k in 1..=P {
            win[k - 1] = b[P - k];
        }
        for i in P..n {
            let row = &l[i * P..i * P + P];
            let mut s = b[i];
            for k in (1..=P).rev() {
                s -= row[k - 1] * win[k - 1];
            }
            for k in (1..P).rev() {
                win[k] = win[k - 1];
            }
            win[0] = s;
            b[i] = s;
        }
        self.backward_p::<P>(b);
    }

    #[inline(always)]
    fn backward_p<const P: usize>(&self, b: &mut [f64]) {
        let n = self.n;
        let (lt, inv_d, b) = (&self.lt[..n * P], &self.inv_d[..n], &mut b[..n]);
        for i in (n - P..n).rev() {
            let mut s = b[i] * inv_d[i];
            for k in 1..n - i {
                s -= lt[i * P + k - 1] * b[i + k];
            }
            b[i] = s;
        }
        // Rows with P successors: the transposed copy keeps the column
        // contiguous; the window holds x[i+k] in registers.
        let mut win = [0.0; P];
        for k in 1..=P {
            win[k - 1] = b[n - P - 1 + k];
        }
        for i in (0..n - P).rev() {
            let col = &lt[i * P..i * P + P];
            let mut s = b[i] * inv_d[i];
            for k in (1..=P).rev() {
                s -= col[k - 1] * win[k - 1];
            }
            for k in (1..P).rev() {
                win[k] = win[k - 1];
            }
            win[0] = s;
            b[i] = s;
        }
    }

    /// Half-bandwidth 3 (the Hermite beam): the last three results are kept
    /// in named scalars, which the compiler keeps in registers (an array
    /// window was measured 4× slower), and the farthest terms come first so
    /// the loop-carried dependency is one fused multiply-add.
    fn solve_p3(&self, b: &mut [f64]) {
        let n = self.n;
        let (l, b) = (&self.l[..n * 3], &mut b[..n]);
        // Forward: rows 0..3 have fewer predecessors.
        b[1] -= l[3] * b[0];
        b[2] -= l[7] * b[0] + l[6] * b[1];
        let (mut w1, mut w2, mut w3) = (b[2], b[1], b[0]);
        for (bi, row) in b[3..].iter_mut().zip(l[9..].chunks_exact(3)) {
            let s = (*bi - row[2] * w3 - row[1] * w2) - row[0] * w1;
            w3 = w2;
            w2 = w1;
            w1 = s;
            *bi = s;
        }
        self.backward_p3(b);
    }

    /// The backward sweep of [`solve_p3`](Self::solve_p3).
    #[inline(always)]
    fn backward_p3(&self, b: &mut [f64]) {
        let n = self.n;
        let (lt, inv_d, b) = (&self.lt[..n * 3], &self.inv_d[..n], &mut b[..n]);
        // Backward: rows n-3..n have fewer successors.
        b[n - 1] *= inv_d[n - 1];
        b[n - 2] = b[n - 2] * inv_d[n - 2] - lt[(n - 2) * 3] * b[n - 1];
        b[n - 3] = b[n - 3] * inv_d[n - 3] - lt[(n - 3) * 3 + 1] * b[n - 1] - lt[(n - 3) * 3] * b[n - 2];
        let (mut x1, mut x2, mut x3) = (b[n - 3], b[n - 2], b[n - 1]);
        for ((bi, col), di) in b[..n - 3].iter_mut().rev().zip(lt[..(n - 3) * 3].chunks_exact(3).rev()).zip(inv_d[..n - 3].iter().rev()) {
            let s = (*bi * di - col[2] * x3 - col[1] * x2) - col[0] * x1;
            x3 = x2;
            x2 = x1;
            x1 = s;
            *bi = s;
        }
    }

    fn solve_generic(&self, b: &mut [f64]) {
        let (n, p) = (self.n, self.p);
        for i in 0..n {
            let mut s = b[i];
            for k in 1..=p.min(i) {
                s -= self.l[i * p + k - 1] * b[i - k];
            }
            b[i] = s;
        }
        self.backward_generic(b);
    }

    fn backward_generic(&self, b: &mut [f64]) {
        let (n, p) = (self.n, self.p);
        for i in (0..n).rev() {
            let mut s = b[i] * self.inv_d[i];
            for k in 1..=p {
                if i + k < n {
                    s -= self.l[(i + k) * p + k - 1] * b[i + k];
                }
            }
            b[i] = s;
        }
    }
}

/// A symmetric matrix of half-bandwidth 3 (`n > 6`) by diagonals
/// (`d[k][i] = A[i][i−k]`), for [`SymBand::mul_vec`]: one pass over
/// contiguous slices that the compiler vectorises across rows, where the
/// row-major [`SymBand::mul_vec_p3`] gathers each row's window: 48 against
/// 67 ns a product on the beam's 38 unknowns (`signorini-run`'s
/// `benches/step.rs`, `beam_band_product`). Every row is
/// summed in `mul_vec_p3`'s order — interior rows as
/// `(r₀x_i + r₁x_{i−1} + r₂x_{i−2} + r₃x_{i−3}) + (c₁x_{i+1} + c₂x_{i+2} + c₃x_{i+3})`,
/// the three first and last rows the diagonal term then each neighbour
/// left and right — so the same bits (tested against it). Compiled for the
/// baseline target and with AVX2, chosen at run time (no FMA in either).
#[derive(Clone, Debug)]
struct Diagonals3 {
    d: [Vec<f64>; 4],
    avx2: bool,
}

impl Diagonals3 {
    fn new(a: &SymBand) -> Self {
        #[cfg(target_arch = "x86_64")]
        let avx2 = std::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = false;
        Self { d: std::array::from_fn(|k| a.diagonal(k)), avx2 }
    }

    fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only when the CPU reports AVX2.
            return unsafe { self.mul_vec_avx2(x, y) };
        }
        self.mul_vec_body(x, y)
    }

    /// [`mul_vec_body`](Self::mul_vec_body) compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn mul_vec_avx2(&self, x: &[f64], y: &mut [f64]) {
        self.mul_vec_body(x, y)
    }

    #[inline(always)]
    fn mul_vec_body(&self, x: &[f64], y: &mut [f64]) {
        let n = x.len();
        let d = &self.d;
        for i in (0..3).chain(n - 3..n) {
            let mut s = d[0][i] * x[i];
            for k in 1..=3 {
                if i >= k {
                    s += d[k][i] * x[i - k];
                }
                if i + k < n {
                    s += d[k][i + k] * x[i + k];
                }
            }
            y[i] = s;
        }
        let (a, len) = (3, n - 6);
        let r = a..a + len;
        let (r0, r1, r2, r3) = (&d[0][r.clone()], &d[1][r.clone()], &d[2][r.clone()], &d[3][r.clone()]);
        let (c1, c2, c3) = (&d[1][a + 1..a + 1 + len], &d[2][a + 2..a + 2 + len], &d[3][a + 3..a + 3 + len]);
        let (x0, x1, x2, x3, x4, x5, x6) =
            (&x[a - 3..a - 3 + len], &x[a - 2..a - 2 + len], &x[a - 1..a - 1 + len], &x[a..a + len], &x[a + 1..a + 1 + len], &x[a + 2..a + 2 + len], &x[a + 3..a + 3 + len]);
        let y = &mut y[r];
        for j in 0..len {
            y[j] = (r0[j] * x3[j] + r1[j] * x2[j] + r2[j] * x1[j] + r3[j] * x0[j]) + (c1[j] * x4[j] + c2[j] * x5[j] + c3[j] * x6[j]);
        }
    }
}
