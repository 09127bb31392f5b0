//! The largest generalized eigenvalue `κ_h` of a symmetric-definite pencil
//! `(K, M)` (docs/theory.md §2.3, §2.4, §4.4, §4.7): it fixes the exact stability limit of the
//! conditionally stable schemes.
//!
//! Two ways, both certified from above (the stability limit `2/sqrt(κ_h)`
//! is never over-estimated) and both O(n):
//!
//! * [`uniform_p1_max_eigenvalue`]: the closed form of the uniform P1 bar
//!   with lumped or consistent mass (docs/theory.md §2.4), recognised from
//!   the matrices themselves, whichever path built them;
//! * [`max_generalized_eigenvalue_lanczos`], for every other pencil: a fixed
//!   number of Lanczos steps on `M⁻¹K` in the `M` inner product (banded
//!   solves with `M`) gives a Ritz value `θ <= κ_h` and its residual bound
//!   `r` (an eigenvalue lies in `[θ − r, θ + r]`); `σ = θ + r` is then
//!   certified above *every* eigenvalue by Sylvester's law of inertia
//!   (`σM − K` has a banded LDLᵀ factor with positive pivots), and
//!   bisection on that test between `θ` and `σ` tightens it to a relative
//!   1e-12. The number of steps depends on `r/θ`, not on `n`.
//!
//! [`max_generalized_eigenvalue`] is the older shift-invert iteration
//! `x ← (σM − K)⁻¹ M x` from a known bound `σ > κ_h` (the beam's element
//! bound); its iteration count grows like `n²` when the top of the
//! spectrum clusters, as on every uniform mesh.

use crate::{BandLdlt, FemError, SymBand};
use std::f64::consts::PI;

fn normalize(x: &mut [f64], m: &SymBand) {
    let n = m.quad_form(x).sqrt();
    x.iter_mut().for_each(|v| *v /= n);
}

/// Power iteration on `M⁻¹K` (for small pencils with a clear spectral gap).
pub(crate) fn power_max(k: &SymBand, m: &SymBand, iters: usize) -> f64 {
    let Ok(f) = m.factor() else { return f64::NAN };
    let n = k.n();
    let mut x: Vec<f64> = (0..n).map(|i| 1.0 + 0.37 * i as f64 - 0.11 * (i * i) as f64).collect();
    let mut y = vec![0.0; n];
    let mut rq = 0.0;
    for _ in 0..iters {
        normalize(&mut x, m);
        k.mul_vec(&x, &mut y);
        rq = x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>();
        f.solve_in_place(&mut y);
        std::mem::swap(&mut x, &mut y);
    }
    rq
}

/// `κ_h = max xᵀKx / xᵀMx` for SPD `M` and symmetric positive semi-definite
/// `K`, given a strict upper bound `sigma > κ_h` (e.g. the element bound
/// times `1 + 1e-3`). Converges to a relative change below 1e-15 of the
/// Rayleigh quotient (at most `max_iter` iterations; returns the last
/// quotient and the iteration count).
pub fn max_generalized_eigenvalue(k: &SymBand, m: &SymBand, sigma: f64, max_iter: usize) -> Result<(f64, usize), FemError> {
    let shifted = m.lin_comb(sigma, k, -1.0);
    let f = shifted.factor().map_err(|_| FemError::Invalid { field: "sigma", value: sigma, allowed: "strictly above the largest generalized eigenvalue" })?;
    let n = k.n();
    let mut x: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 1.0 } else { -1.0 } * (1.0 + 0.1 * i as f64)).collect();
    let mut y = vec![0.0; n];
    let mut kx = vec![0.0; n];
    let mut prev = f64::NAN;
    for it in 0..max_iter {
        normalize(&mut x, m);
        k.mul_vec(&x, &mut kx);
        let rq: f64 = x.iter().zip(&kx).map(|(a, b)| a * b).sum();
        if (rq - prev).abs() <= 1e-15 * rq.abs() {
            return Ok((rq, it));
        }
        prev = rq;
        m.mul_vec(&x, &mut y);
        f.solve_in_place(&mut y);
        std::mem::swap(&mut x, &mut y);
    }
    Ok((prev, max_iter))
}

/// `κ_h` without a known bound: the certified upper bound of
/// [`max_generalized_eigenvalue_bound`] (the closed form on a uniform P1
/// bar, Lanczos and an inertia test otherwise), within a relative 1e-12 of
/// `κ_h`. `M` must be positive definite.
pub fn max_generalized_eigenvalue_auto(k: &SymBand, m: &SymBand) -> Result<f64, FemError> {
    max_generalized_eigenvalue_bound(k, m).map(|b| b.upper)
}

/// The closed-form `κ_h` of the uniform P1 bar (docs/theory.md §2.4),
/// recognised from the pencil itself: `K = a T` with `T` the stiffness
/// pattern of a bar free at node 0 (`K_00 = a`, interior diagonal `2a`,
/// off-diagonal `−a`; last diagonal `a` for a free far end, `2a` for a
/// clamped one, whose node `m` is not an unknown), and `M` either lumped
/// (diagonal, `e` at the free ends and `2e` inside) or consistent (`e` at
/// the free ends, `2e` inside, `e/2` off the diagonal), `e = M_00`. These
/// relations hold exactly, bit for bit, for the matrices [`crate::Bar`]
/// assembles (sums of equal terms and halvings are exact), so the pencil is
/// exactly `(a/e)` times an integer one and the closed form is its top
/// eigenvalue up to the rounding of the formula. With `C = cos(π/(2m))`
/// (clamped, `m = n`) or `C = 1` (free, `m = n − 1`):
///
/// * lumped: `κ_h = (a/e)(1 + C)`, i.e. `(4c²/h²) cos²(π/(4m))` clamped,
///   `4c²/h²` free;
/// * consistent: `κ_h = (2a/e)(1 + C)/(2 − C)`, i.e. `12c²/h²` free.
///
/// `None` for any other pencil (other masses, massless nodes, P2/P3, the
/// beam, a penalty spring, a non-uniform mesh, `n < 2`).
pub fn uniform_p1_max_eigenvalue(k: &SymBand, m: &SymBand) -> Option<f64> {
    let n = k.n();
    if n < 2 || m.n() != n || k.half_bandwidth() != 1 || m.half_bandwidth() != 1 {
        return None;
    }
    let a = -k.get(1, 0);
    if !(a > 0.0 && a.is_finite()) || k.get(0, 0) != a {
        return None;
    }
    if (1..n).any(|i| k.get(i, i - 1) != -a) || (1..n - 1).any(|i| k.get(i, i) != 2.0 * a) {
        return None;
    }
    let free = match k.get(n - 1, n - 1) {
        x if x == a => true,
        x if x == 2.0 * a => false,
        _ => return None,
    };
    let e = m.get(0, 0);
    if !(e > 0.0 && e.is_finite()) {
        return None;
    }
    let off = m.get(1, 0);
    let lumped = match off {
        0.0 => true,
        x if x == 0.5 * e => false,
        _ => return None,
    };
    if (1..n).any(|i| m.get(i, i - 1) != off) || (1..n - 1).any(|i| m.get(i, i) != 2.0 * e) {
        return None;
    }
    if m.get(n - 1, n - 1) != if free { e } else { 2.0 * e } {
        return None;
    }
    let elements = if free { n - 1 } else { n };
    Some(p1_closed_form(a / e, elements, free, lumped))
}

/// `κ_h` of the uniform P1 bar from `a/e` (`K_01 = −a`, `M_00 = e`), the
/// number of elements, the far end and the mass (see [`uniform_p1_max_eigenvalue`]).
pub(crate) fn p1_closed_form(a_over_e: f64, elements: usize, free: bool, lumped: bool) -> f64 {
    // θ_max = π − π/(2m) (clamped) or π (free): cos θ_max = −C.
    let c = if free { 1.0 } else { (PI / (2.0 * elements as f64)).cos() };
    if lumped {
        a_over_e * (1.0 + c)
    } else {
        2.0 * a_over_e * (1.0 + c) / (2.0 - c)
    }
}

/// A Ritz value at the top of the spectrum of `(K, M)` and its residual bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ritz {
    /// The largest Ritz value `θ` (a Rayleigh quotient: `θ <= κ_h` up to round-off).
    pub value: f64,
    /// `‖K y − θ M y‖_{M⁻¹}` for its `M`-normalised Ritz vector `y`: some
    /// generalized eigenvalue lies in `[θ − r, θ + r]` (not necessarily the largest).
    pub residual: f64,
    /// Lanczos steps taken (fewer than asked when the Krylov space is invariant).
    pub steps: usize,
}

/// `steps` Lanczos steps (at most `n`) on `M⁻¹K`, self-adjoint in the `M`
/// inner product, from a fixed pseudo-random start, with full
/// reorthogonalisation: the largest Ritz value and its residual bound
/// `β_s |z_s|` (`z` the unit eigenvector of the tridiagonal `T_s`, `β_s`
/// the next off-diagonal). Each step is one product with `K`, one banded
/// solve and one product with `M`, plus `O(n s)` for the
/// reorthogonalisation. `M` must be positive definite.
pub fn lanczos_top(k: &SymBand, m: &SymBand, steps: usize) -> Result<Ritz, FemError> {
    let fm = m.factor()?;
    Ok(lanczos_with(k, m, &fm, steps))
}

fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

#[track_caller]
fn lanczos_with(k: &SymBand, m: &SymBand, fm: &BandLdlt, steps: usize) -> Ritz {
    let n = k.n();
    assert!(m.n() == n && fm.n() == n, "size mismatch");
    let s_max = steps.clamp(1, n.max(1));
    // A fixed pseudo-random start (xorshift64): every mode present.
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut v: Vec<f64> = (0..n)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect();
    let mut mv = vec![0.0; n];
    m.mul_vec(&v, &mut mv);
    let norm = dot(&v, &mv).sqrt();
    v.iter_mut().for_each(|x| *x /= norm);
    mv.iter_mut().for_each(|x| *x /= norm);
    let (mut basis, mut mbasis) = (vec![v], vec![mv]);
    let (mut alpha, mut beta) = (Vec::with_capacity(s_max), Vec::with_capacity(s_max));
    let (mut w, mut mw) = (vec![0.0; n], vec![0.0; n]);
    let mut last_beta = 0.0;
    for j in 0..s_max {
        k.mul_vec(&basis[j], &mut w);
        let a = dot(&basis[j], &w);
        fm.solve_in_place(&mut w);
        alpha.push(a);
        // Full reorthogonalisation in the M inner product, twice ("twice is enough").
        for _ in 0..2 {
            for i in 0..=j {
                let c = dot(&w, &mbasis[i]);
                w.iter_mut().zip(&basis[i]).for_each(|(x, b)| *x -= c * b);
            }
        }
        m.mul_vec(&w, &mut mw);
        let b = dot(&w, &mw).max(0.0).sqrt();
        last_beta = b;
        let scale = alpha.iter().fold(0.0_f64, |s, x| s.max(x.abs())).max(beta.iter().fold(0.0_f64, |s: f64, x: &f64| s.max(*x)));
        if j + 1 == s_max || !(b > 1e-14 * scale) {
            break;
        }
        beta.push(b);
        basis.push(w.iter().map(|x| x / b).collect());
        mbasis.push(mw.iter().map(|x| x / b).collect());
    }
    let s = alpha.len();
    let mut t = vec![0.0; s * s];
    for i in 0..s {
        t[i * s + i] = alpha[i];
        if i + 1 < s {
            t[i * s + i + 1] = beta[i];
            t[(i + 1) * s + i] = beta[i];
        }
    }
    let (values, vectors) = jacobi(&mut t, s);
    let top = (0..s).max_by(|&x, &y| values[x].total_cmp(&values[y])).unwrap_or(0);
    Ritz { value: values[top], residual: last_beta * vectors[(s - 1) * s + top].abs(), steps: s }
}

/// Eigenvalues and unit eigenvectors of a small symmetric matrix (row-major
/// `s × s`, overwritten) by cyclic Jacobi rotations: `(values, V)` with
/// `V[i * s + j]` component `i` of eigenvector `j`.
fn jacobi(a: &mut [f64], s: usize) -> (Vec<f64>, Vec<f64>) {
    let mut v = vec![0.0; s * s];
    for i in 0..s {
        v[i * s + i] = 1.0;
    }
    for _sweep in 0..100 {
        let off: f64 = (0..s).map(|p| (p + 1..s).map(|q| a[p * s + q] * a[p * s + q]).sum::<f64>()).sum();
        let diag: f64 = (0..s).map(|p| a[p * s + p] * a[p * s + p]).sum();
        if !(off > 1e-36 * diag) {
            break;
        }
        for p in 0..s {
            for q in p + 1..s {
                let apq = a[p * s + q];
                if apq == 0.0 {
                    continue;
                }
                // Zero a_pq: t = tan φ, the smaller root of t² + 2ϑ t − 1 = 0.
                let th = (a[q * s + q] - a[p * s + p]) / (2.0 * apq);
                let t = if th.abs() < 1e150 { th.signum() / (th.abs() + (th * th + 1.0).sqrt()) } else { 0.5 / th };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let sn = t * c;
                for r in 0..s {
                    let (x, y) = (a[r * s + p], a[r * s + q]);
                    a[r * s + p] = c * x - sn * y;
                    a[r * s + q] = sn * x + c * y;
                }
                for r in 0..s {
                    let (x, y) = (a[p * s + r], a[q * s + r]);
                    a[p * s + r] = c * x - sn * y;
                    a[q * s + r] = sn * x + c * y;
                }
                for r in 0..s {
                    let (x, y) = (v[r * s + p], v[r * s + q]);
                    v[r * s + p] = c * x - sn * y;
                    v[r * s + q] = sn * x + c * y;
                }
            }
        }
    }
    ((0..s).map(|i| a[i * s + i]).collect(), v)
}

/// A certified upper bound of `κ_h` and how it was found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KappaBound {
    /// Every generalized eigenvalue of `(K, M)` is at most `upper` (within a
    /// relative 1e-12 of `κ_h` for the Lanczos path, a few ulps for the closed form).
    pub upper: f64,
    /// A lower estimate: the closed form itself, or the largest of the Ritz
    /// value and the shifts the inertia test refused.
    pub lower: f64,
    /// The Ritz value's residual bound (0 for the closed form).
    pub residual: f64,
    /// Lanczos steps (0 for the closed form).
    pub lanczos_steps: usize,
    /// Inertia tests (banded LDLᵀ of `σM − K`; 0 for the closed form).
    pub factorizations: usize,
    /// Whether the closed form of the uniform P1 bar was used.
    pub closed_form: bool,
}

impl KappaBound {
    /// Lanczos steps and inertia tests together: the iteration count, which
    /// does not grow with `n`.
    pub fn iterations(&self) -> usize {
        self.lanczos_steps + self.factorizations
    }
}

/// Lanczos steps of [`max_generalized_eigenvalue_lanczos`].
pub const LANCZOS_STEPS: usize = 16;
/// Relative width at which the bisection on the inertia test stops.
const BISECTION_TOL: f64 = 1e-12;
/// Relative room added to the certified shift for the round-off of the
/// factorisation that certified it (its backward error is a few ulps of
/// `‖σM − K‖` times the band width).
const ROUNDING_MARGIN: f64 = 1e-13;
/// Cap on the inertia tests (growth and bisection; about 40 are needed).
const MAX_FACTORIZATIONS: usize = 200;

/// A certified upper bound of `κ_h`: the closed form when the pencil is a
/// uniform P1 bar's ([`uniform_p1_max_eigenvalue`], times `1 + 16ε` for
/// the rounding of the formula), else [`max_generalized_eigenvalue_lanczos`].
/// `M` must be positive definite.
pub fn max_generalized_eigenvalue_bound(k: &SymBand, m: &SymBand) -> Result<KappaBound, FemError> {
    if let Some(kappa) = uniform_p1_max_eigenvalue(k, m) {
        return Ok(KappaBound { upper: kappa * (1.0 + 16.0 * f64::EPSILON), lower: kappa, residual: 0.0, lanczos_steps: 0, factorizations: 0, closed_form: true });
    }
    max_generalized_eigenvalue_lanczos(k, m)
}

/// The inertia test `σM − K ≻ 0` (all pivots of its banded LDLᵀ positive,
/// which by Sylvester's law of inertia means `σ > κ_h`), without allocating
/// once built: a pivot recurrence on the diagonals for tridiagonal pencils,
/// a factorisation into fixed storage otherwise.
struct InertiaTest<'a> {
    k: &'a SymBand,
    m: &'a SymBand,
    tri: Option<[Vec<f64>; 4]>,
    shifted: SymBand,
    factor: BandLdlt,
    count: usize,
}

impl<'a> InertiaTest<'a> {
    fn new(k: &'a SymBand, m: &'a SymBand) -> Self {
        let (n, p) = (k.n(), k.half_bandwidth());
        let tri = (p == 1 && m.half_bandwidth() == 1).then(|| [k.diagonal(0), k.diagonal(1), m.diagonal(0), m.diagonal(1)]);
        let (shifted, factor) = if tri.is_some() { (SymBand::zeros(0, 1), BandLdlt::zeros(0, 1)) } else { (SymBand::zeros(n, p), BandLdlt::zeros(n, p)) };
        InertiaTest { k, m, tri, shifted, factor, count: 0 }
    }

    fn positive_definite(&mut self, sigma: f64) -> bool {
        self.count += 1;
        match &self.tri {
            Some([kd, ks, md, ms]) => {
                let n = kd.len();
                let mut d = sigma * md[0] - kd[0];
                if !(d > 0.0 && d.is_finite()) {
                    return false;
                }
                for i in 1..n {
                    let e = sigma * ms[i] - ks[i];
                    d = (sigma * md[i] - kd[i]) - e * e / d;
                    if !(d > 0.0 && d.is_finite()) {
                        return false;
                    }
                }
                true
            }
            None => {
                self.m.lin_comb_into(sigma, self.k, -1.0, &mut self.shifted);
                self.shifted.factor_into(&mut self.factor).is_ok()
            }
        }
    }
}

/// A certified upper bound of `κ_h` for any symmetric-definite pencil
/// (docs/theory.md §2.3): [`LANCZOS_STEPS`] Lanczos steps give the Ritz value
/// `θ` and its residual bound `r`; `σ = (θ + r)(1 + 1e-13)` is tested by
/// the inertia of `σM − K` (raised by doubling increments if refused: the
/// Ritz value was not the top one), then bisection between the refused
/// shifts (and `θ`) and the accepted ones stops at a relative width 1e-12.
/// The returned `upper` is an accepted shift times `1 + 1e-13`. `K`
/// symmetric positive semi-definite with `M`'s half-bandwidth, `M`
/// positive definite (else [`FemError::NotPositiveDefinite`]).
pub fn max_generalized_eigenvalue_lanczos(k: &SymBand, m: &SymBand) -> Result<KappaBound, FemError> {
    let fm = m.factor()?;
    let ritz = lanczos_with(k, m, &fm, LANCZOS_STEPS);
    let n = k.n();
    let bound = |upper: f64, lower: f64, factorizations: usize| KappaBound { upper, lower, residual: ritz.residual, lanczos_steps: ritz.steps, factorizations, closed_form: false };
    let theta = ritz.value.max(0.0);
    if theta + ritz.residual <= 0.0 && (0..n).all(|i| k.get(i, i) == 0.0) {
        // A positive semi-definite K with a zero diagonal is zero.
        return Ok(bound(0.0, 0.0, 0));
    }
    let mut test = InertiaTest::new(k, m);
    let mut lo = theta;
    let mut hi = (theta + ritz.residual) * (1.0 + ROUNDING_MARGIN);
    if !(hi > 0.0) {
        hi = (0..n).map(|i| k.get(i, i) / m.get(i, i)).fold(0.0_f64, f64::max).max(f64::MIN_POSITIVE);
    }
    // Raise σ until the inertia test accepts it.
    let mut step = ritz.residual.max(1e-6 * hi);
    while !test.positive_definite(hi) {
        if test.count >= MAX_FACTORIZATIONS || !hi.is_finite() {
            return Err(FemError::Invalid { field: "sigma", value: hi, allowed: "a finite upper bound of the spectrum (none found)" });
        }
        lo = lo.max(hi);
        hi += step;
        step *= 2.0;
    }
    // Bisection: hi stays certified, lo refused (or the Ritz value).
    while hi - lo > BISECTION_TOL * hi && test.count < MAX_FACTORIZATIONS {
        let mid = lo + 0.5 * (hi - lo);
        if !(mid > lo && mid < hi) {
            break;
        }
        if test.positive_definite(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(bound(hi * (1.0 + ROUNDING_MARGIN), lo, test.count))
}
