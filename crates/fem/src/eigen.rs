//! The largest generalized eigenvalue `κ_h` of a symmetric-definite pencil
//! `(K, M)` (docs/theory.md §2.3, §4.4, §4.7): it fixes the exact stability limit of the
//! conditionally stable schemes.
//!
//! Method: shift-invert iteration `x ← (σM − K)⁻¹ M x` with a shift `σ`
//! strictly above `κ_h` (the element-by-element bound: the largest
//! eigenvalue of each element pair bounds that of the assembly), so that
//! `σM − K` is positive definite and the banded LDLᵀ factor applies; the
//! iteration converges to the eigenvalue closest to `σ`, i.e. `κ_h`, and the
//! Rayleigh quotient `xᵀKx / xᵀMx` converges twice as fast.

use crate::{FemError, SymBand};

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

/// `κ_h` without a known bound: a power-iteration estimate (200 steps on
/// `M⁻¹K`) times 1.05 as the shift, raised by half until `σM − K` factorises
/// (which certifies `σ > κ_h`), then [`max_generalized_eigenvalue`]. `M`
/// must be positive definite.
pub fn max_generalized_eigenvalue_auto(k: &SymBand, m: &SymBand) -> Result<f64, FemError> {
    m.factor()?;
    let mut sigma = 1.05 * power_max(k, m, 200).abs().max(f64::MIN_POSITIVE);
    for _ in 0..200 {
        if m.lin_comb(sigma, k, -1.0).factor().is_ok() {
            return max_generalized_eigenvalue(k, m, sigma, 1_000_000).map(|r| r.0);
        }
        sigma *= 1.5;
    }
    Err(FemError::Invalid { field: "sigma", value: sigma, allowed: "a finite upper bound of the spectrum (none found)" })
}
