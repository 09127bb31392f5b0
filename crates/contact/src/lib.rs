//! # signorini-contact
//!
//! The crate alone, with a step matrix and a solver of the user's own: a
//! predictor projected onto the obstacle, then complementarity and
//! equilibrium checked:
//!
//! ```
//! use signorini_contact::{Active, Projection};
//!
//! // The user's SPD matrix A (3 unknowns, contact dof c = 0) ...
//! let a = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]];
//! let mul = |x: &[f64]| -> Vec<f64> { a.iter().map(|row| row.iter().zip(x).map(|(r, x)| r * x).sum()).collect() };
//! // ... and its influence column w = A⁻¹ e_0 (A⁻¹ = [[3, 2, 1], [2, 4, 2], [1, 2, 3]] / 4).
//! let w = vec![0.75, 0.5, 0.25];
//! assert_eq!(mul(&w), [1.0, 0.0, 0.0]);
//! let proj = Projection::new(0, w)?;
//!
//! // The unconstrained solution y = A⁻¹ b of b = (-2, 0, 1) goes below the
//! // obstacle lo = 0 (y = (-5/4, -1/2, 1/4)).
//! let (lo, hi) = (0.0, f64::INFINITY);
//! let b = [-2.0, 0.0, 1.0];
//! let mut x = vec![-1.25, -0.5, 0.25];
//! assert_eq!(mul(&x), b);
//! let r = proj.project(&mut x, lo, hi);
//!
//! // On the bound, pushed up by μ = (lo - y_0)/w_0 = 5/3:
//! assert_eq!(r.active, Active::Lower);
//! assert_eq!(x[0], lo);
//! assert!((r.mu - 5.0 / 3.0).abs() < 1e-14);
//! // complementarity: μ >= 0, x_0 >= lo, μ (x_0 - lo) = 0 ...
//! assert!(r.mu >= 0.0 && x[0] >= lo && r.mu * (x[0] - lo) == 0.0);
//! // ... and equilibrium A x = b + μ e_0 (x = (0, 1/3, 2/3)).
//! for (i, (ax, bi)) in mul(&x).into_iter().zip(b).enumerate() {
//!     let rhs = if i == 0 { bi + r.mu } else { bi };
//!     assert!((ax - rhs).abs() < 1e-14, "row {i}: {ax} != {rhs}");
//! }
//!
//! // A predictor inside the bounds is left as it is, with μ = 0.
//! let mut y = vec![0.25, 1.5, 2.75];
//! let r = proj.project(&mut y, lo, hi);
//! assert_eq!((r.mu, r.active, y), (0.0, Active::None, vec![0.25, 1.5, 2.75]));
//! # Ok::<(), signorini_contact::ContactError>(())
//! ```
//!
//! One implicit step of every scheme with a single contact dof `c` reduces to
//! (docs/theory.md §3, Dumont–Paoli Lemma 4.1):
//!
//! ```text
//! find x, μ:  A x = b + μ e_c,   lo <= x_c <= hi,
//!             μ = 0 if lo < x_c < hi,  μ >= 0 if x_c = lo,  μ <= 0 if x_c = hi,
//! ```
//!
//! with `A` symmetric positive definite. With `y = A⁻¹ b` and `w = A⁻¹ e_c`
//! (computed once per run by the caller, who owns the factorisation),
//! `x_c = clamp(y_c, lo, hi)`, `μ = (x_c - y_c)/w_c` and `x = y + μ w`.
//! [`Projection`] applies this in place: one axpy per step, no allocation.
//!
//! Laws that are piecewise linear in `x_c` (penalty, normal compliance, the
//! hybrid scheme's midpoint law) are solved just as exactly by
//! [`solve_piecewise_linear`]: `x_c = y_c + w_c N(x_c)` is tested branch by
//! branch, no Newton iterations.
//!
//! With several constrained dofs, [`MultiProjection`] solves the same
//! problem exactly (box-constrained complementarity on the Delassus matrix
//! `C A⁻¹ Cᵀ`, principal pivoting with finite termination).
//!
//! Architecture invariant: works on slices; knows nothing of meshes,
//! matrices or time. Usable on its own with any linear solver.

/// Errors of this crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContactError {
    /// `w_c = (A⁻¹)_cc` must be positive and finite (A SPD).
    #[error("influence coefficient w_c = {0} must be positive and finite (is A positive definite?)")]
    BadInfluence(f64),
    /// The contact dof is outside the vector.
    #[error("contact dof {dof} outside 0..{n}")]
    DofOutOfRange {
        /// The dof given.
        dof: usize,
        /// The vector length.
        n: usize,
    },
    /// Bounds with `lo > hi` or NaN.
    #[error("invalid bounds [{lo}, {hi}]: need lo <= hi, neither NaN")]
    BadBounds {
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// The scalar law has no solution (not monotone).
    #[error("the piecewise-linear contact law has no solution on any branch (law not monotone, or w_c too large)")]
    NoBranch,
    /// Several contacts: the number of influence columns (or a column's
    /// length) does not match.
    #[error("{dofs} constrained dofs need as many influence columns A⁻¹ e_c of equal length (got {columns})")]
    Columns {
        /// Constrained dofs.
        dofs: usize,
        /// Columns (or the offending length).
        columns: usize,
    },
    /// Several contacts: a dof constrained twice.
    #[error("dof {0} is constrained twice: give each dof one pair of bounds")]
    DuplicateDof(usize),
    /// Several contacts: the Delassus matrix (or a block of it) is not
    /// positive definite (A is not, or the columns are not A⁻¹ e_c).
    #[error("the Delassus matrix C A⁻¹ Cᵀ is not positive definite (is A positive definite, and are the columns A⁻¹ e_c?)")]
    NotPositiveDefinite,
    /// Several contacts: pivoting did not terminate (only rounding on a
    /// nearly singular Delassus matrix can cause it).
    #[error("the multi-contact solve did not terminate in {iterations} pivots (Delassus matrix nearly singular?)")]
    NoConvergence {
        /// Pivots made.
        iterations: usize,
    },
    /// A compliance that is negative or not finite.
    #[error("invalid compliance {0}: allowed finite and >= 0")]
    Compliance(f64),
}

/// The result of one projection: the multiplier and which bound is active.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projected {
    /// The multiplier `μ` (≥ 0 on the lower bound, ≤ 0 on the upper, 0 inside).
    pub mu: f64,
    /// Which bound, if any, holds `x_c`.
    pub active: Active,
}

mod multi;
pub use multi::{MultiProjected, MultiProjection, OneDof, PivotRule};

/// Which bound is active after a projection.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Active {
    /// `lo < x_c < hi`.
    None,
    /// `x_c = lo`.
    Lower,
    /// `x_c = hi`.
    Upper,
}

/// The closed-form projection for contact dof `c`, holding `w = A⁻¹ e_c`.
#[derive(Clone, Debug)]
pub struct Projection {
    c: usize,
    w: Vec<f64>,
    inv_wc: f64,
}

impl Projection {
    /// `w` must be `A⁻¹ e_c` for the SPD matrix `A` of the step.
    pub fn new(c: usize, w: Vec<f64>) -> Result<Self, ContactError> {
        if c >= w.len() {
            return Err(ContactError::DofOutOfRange { dof: c, n: w.len() });
        }
        let wc = w[c];
        if !(wc > 0.0 && wc.is_finite()) {
            return Err(ContactError::BadInfluence(wc));
        }
        Ok(Self { c, w, inv_wc: 1.0 / wc })
    }

    /// The contact dof.
    pub fn dof(&self) -> usize {
        self.c
    }

    /// `w = A⁻¹ e_c`.
    pub fn influence(&self) -> &[f64] {
        &self.w
    }

    /// `w_c = (A⁻¹)_cc`.
    pub fn wc(&self) -> f64 {
        self.w[self.c]
    }

    /// Turns the unconstrained solution `y = A⁻¹ b` (in place) into the
    /// constrained one and returns the multiplier. `lo = -∞` or `hi = +∞`
    /// give one-sided bounds. Bounds are the caller's responsibility
    /// (checked in debug builds).
    #[inline]
    #[track_caller]
    pub fn project(&self, y: &mut [f64], lo: f64, hi: f64) -> Projected {
        debug_assert!(lo <= hi, "bounds [{lo}, {hi}]");
        debug_assert_eq!(y.len(), self.w.len());
        let yc = y[self.c];
        let (xc, active) = if yc < lo {
            (lo, Active::Lower)
        } else if yc > hi {
            (hi, Active::Upper)
        } else {
            (yc, Active::None)
        };
        if active == Active::None {
            return Projected { mu: 0.0, active };
        }
        let mu = (xc - yc) * self.inv_wc;
        for (yi, wi) in y.iter_mut().zip(&self.w) {
            *yi += mu * wi;
        }
        // Exact bound, free of the rounding of the axpy.
        y[self.c] = xc;
        Projected { mu, active }
    }

    /// Applies `x += μ w` for a multiplier found otherwise (for example by
    /// [`solve_piecewise_linear`]), setting `x_c` to `xc` exactly.
    #[inline]
    pub fn apply(&self, y: &mut [f64], mu: f64, xc: f64) {
        for (yi, wi) in y.iter_mut().zip(&self.w) {
            *yi += mu * wi;
        }
        y[self.c] = xc;
    }
}

/// Checks bounds given by a user: `lo <= hi`, neither NaN.
pub fn check_bounds(lo: f64, hi: f64) -> Result<(), ContactError> {
    if lo.is_nan() || hi.is_nan() || lo > hi {
        return Err(ContactError::BadBounds { lo, hi });
    }
    Ok(())
}

/// A piecewise-linear law `N(x) = a_k + b_k x` on branch `k`, the branches
/// separated by increasing breakpoints (`branches.len() == breaks.len() + 1`;
/// branch `k` covers `[breaks[k-1], breaks[k]]`).
#[derive(Clone, Copy, Debug)]
pub struct PiecewiseLinear<'a> {
    /// Increasing breakpoints.
    pub breaks: &'a [f64],
    /// `(a_k, b_k)` per branch.
    pub branches: &'a [(f64, f64)],
}

impl PiecewiseLinear<'_> {
    /// `N(x)`.
    pub fn eval(&self, x: f64) -> f64 {
        let k = self.breaks.iter().take_while(|b| x > **b).count();
        let (a, b) = self.branches[k];
        a + b * x
    }
}

/// Solves `x = y_c + w_c N(x)` exactly for a piecewise-linear `N` by testing
/// each branch: on branch `k`, `x = (y_c + w_c a_k)/(1 - w_c b_k)`, accepted if
/// it lies in the branch (closed interval). For a continuous non-increasing
/// `N` (every contact law of docs/theory.md §3, §4.5, §4.6) the solution exists and is unique;
/// returns `(x, N(x))`.
pub fn solve_piecewise_linear(yc: f64, wc: f64, law: PiecewiseLinear<'_>) -> Result<(f64, f64), ContactError> {
    debug_assert_eq!(law.branches.len(), law.breaks.len() + 1);
    for (k, &(a, b)) in law.branches.iter().enumerate() {
        let den = 1.0 - wc * b;
        if den <= 0.0 {
            continue;
        }
        let x = (yc + wc * a) / den;
        let lo = if k == 0 { f64::NEG_INFINITY } else { law.breaks[k - 1] };
        let hi = law.breaks.get(k).copied().unwrap_or(f64::INFINITY);
        if x >= lo && x <= hi {
            return Ok((x, a + b * x));
        }
    }
    Err(ContactError::NoBranch)
}
