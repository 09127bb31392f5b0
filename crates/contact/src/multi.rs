//! The step's contact problem with several constrained dofs (docs/theory.md
//! §3): find `x`, `μ` with
//!
//! ```text
//! A x = b + Σ_i μ_i e_{c_i},   lo_i <= x_{c_i} <= hi_i,
//! μ_i = 0 inside,  μ_i >= 0 at lo_i,  μ_i <= 0 at hi_i     (i = 1..k)
//! ```
//!
//! for `A` symmetric positive definite: the minimiser of `½ xᵀAx − bᵀx` over
//! the box. With `y = A⁻¹ b` and the influence columns `W_j = A⁻¹ e_{c_j}`
//! (computed once by the caller, who owns the factorisation), the contact
//! values are `z = y_c + D μ` with the constant Delassus matrix
//! `D_ij = (W_j)_{c_i}` (k × k, SPD), and the problem is a box-constrained
//! linear complementarity problem in `μ`. It is solved exactly, with finite
//! termination, by principal pivoting on the status of each dof (free, at
//! its lower or at its upper bound): block pivots (every infeasible dof
//! changes status at once, the primal–dual active-set step) while they
//! reduce the number of infeasible dofs, then Murty's least-index single
//! pivots, which terminate for every P-matrix — `D` is SPD. Each pivot
//! solves `D_SS μ_S = bound_S − y_S` on the active set `S` by a dense
//! Cholesky factorisation in preallocated storage: no allocation per step.
//! Then `x = y + Σ μ_j W_j` and `x_{c_i}` is set to its bound exactly.

use crate::{Active, ContactError};

/// The outcome of one multi-contact solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultiProjected {
    /// Pivoting iterations (linear solves on the active set).
    pub iterations: usize,
    /// Dofs at a bound.
    pub active: usize,
    /// The complementarity residual: the largest bound violation of a free
    /// dof and the largest wrong-signed multiplier times its `D_ii`
    /// (both in units of displacement; zero up to rounding).
    pub residual: f64,
    /// Of the `iterations`, the passes made by Murty's least-index single
    /// pivots after block pivoting stalled (0: block pivots alone solved it).
    pub single_pivots: usize,
}

/// The exact solver for `k` constrained dofs, holding the influence columns
/// and the Delassus matrix.
#[derive(Clone, Debug)]
pub struct MultiProjection {
    dofs: Vec<usize>,
    /// `W_j = A⁻¹ e_{c_j}`, column after column (`k · n`).
    columns: Vec<f64>,
    n: usize,
    /// `D` (k × k, row-major), plus the compliance on its diagonal.
    delassus: Vec<f64>,
    /// Per-dof compliance `c_i >= 0` (0: a rigid bound; see
    /// [`MultiProjection::with_compliance`]).
    compliance: Vec<f64>,
    // Work storage (no allocation per solve).
    status: Vec<Active>,
    /// Statuses that are not `Active::None`.
    held: usize,
    /// Whether `mu` may hold nonzeros.
    dirty: bool,
    mu: Vec<f64>,
    z: Vec<f64>,
    set: Vec<usize>,
    chol: Vec<f64>,
    rhs: Vec<f64>,
}

/// Iterations of block pivoting without progress before single pivots.
const BLOCK_TRIES: usize = 3;

/// The pivoting rule of the exact box-complementarity solvers, shared by
/// [`MultiProjection`] (pivots on the Delassus matrix) and any other solve
/// of the same problem on the same statuses (e.g. a reduced banded one):
/// block pivots — every infeasible dof changes status at once — while they
/// reduce the number of infeasible dofs, then, after three
/// passes without progress, Murty's least-index single pivots, which
/// terminate for every P-matrix.
#[derive(Clone, Copy, Debug)]
pub struct PivotRule {
    best: usize,
    fails: usize,
    single: bool,
    tol: f64,
}

impl PivotRule {
    /// A rule for one solve, its tolerance `64 ε` times the largest
    /// `|y_c|`, `|lo|`, `|hi|` (finite bounds) of `(y_c, lo, hi)`.
    pub fn new(values: impl Iterator<Item = (f64, f64, f64)>) -> Self {
        let scale = values.map(|(y, l, h)| y.abs().max(finite_or_zero(l).abs()).max(finite_or_zero(h).abs())).fold(0.0_f64, f64::max).max(f64::MIN_POSITIVE);
        Self { best: usize::MAX, fails: 0, single: false, tol: 64.0 * f64::EPSILON * scale }
    }

    /// Whether block pivoting has stalled and the next passes are Murty's
    /// least-index single pivots.
    pub fn single(&self) -> bool {
        self.single
    }

    /// The pivots allowed before a solve gives up, for `k` dofs.
    pub fn max_iterations(k: usize) -> usize {
        4 * k * k + 64
    }

    /// One pass over the dofs after a solve on the current statuses:
    /// `zm(i)` gives dof `i`'s contact value `z_i` (what the bounds hold)
    /// and its multiplier scaled to a displacement (`μ_i D_ii`). Changes
    /// the statuses of the infeasible dofs (all of them, or the first
    /// one) and returns how many were infeasible (0: solved).
    pub fn pass(&mut self, status: &mut [Active], lo: &[f64], hi: &[f64], zm: impl Fn(usize) -> (f64, f64)) -> usize {
        let tol = self.tol;
        let mut count = 0;
        for i in 0..status.len() {
            let (z, md) = zm(i);
            let next = match status[i] {
                Active::None if z < lo[i] - tol => Some(Active::Lower),
                Active::None if z > hi[i] + tol => Some(Active::Upper),
                Active::Lower if md < -tol => Some(Active::None),
                Active::Upper if md > tol => Some(Active::None),
                _ => None,
            };
            if let Some(st) = next {
                if !self.single || count == 0 {
                    status[i] = st;
                }
                count += 1;
            }
        }
        if count > 0 && !self.single {
            if count < self.best {
                self.best = count;
                self.fails = 0;
            } else {
                self.fails += 1;
                if self.fails >= BLOCK_TRIES {
                    self.single = true;
                }
            }
        }
        count
    }
}

impl MultiProjection {
    /// `columns[j]` must be `A⁻¹ e_{dofs[j]}` for the SPD matrix `A` of the
    /// step; dofs distinct and in range.
    pub fn new(dofs: Vec<usize>, columns: Vec<Vec<f64>>) -> Result<Self, ContactError> {
        let k = dofs.len();
        if k == 0 || columns.len() != k {
            return Err(ContactError::Columns { dofs: k, columns: columns.len() });
        }
        let n = columns[0].len();
        for (j, &c) in dofs.iter().enumerate() {
            if c >= n {
                return Err(ContactError::DofOutOfRange { dof: c, n });
            }
            if columns[j].len() != n {
                return Err(ContactError::Columns { dofs: k, columns: columns[j].len() });
            }
            if dofs[..j].contains(&c) {
                return Err(ContactError::DuplicateDof(c));
            }
        }
        let mut delassus = vec![0.0; k * k];
        for i in 0..k {
            for j in 0..k {
                // Symmetrised: (A⁻¹)_{c_i c_j} computed twice by the caller.
                delassus[i * k + j] = 0.5 * (columns[j][dofs[i]] + columns[i][dofs[j]]);
            }
        }
        let mut chol = delassus.clone();
        if !cholesky(&mut chol, k) {
            return Err(ContactError::NotPositiveDefinite);
        }
        let flat = columns.into_iter().flatten().collect();
        Ok(Self {
            dofs,
            columns: flat,
            n,
            delassus,
            compliance: vec![0.0; k],
            status: vec![Active::None; k],
            held: 0,
            dirty: false,
            mu: vec![0.0; k],
            z: vec![0.0; k],
            set: Vec::with_capacity(k),
            chol,
            rhs: vec![0.0; k],
        })
    }

    /// Makes the bounds compliant: dof `i` may pass its bound by `c_i μ_i`,
    ///
    /// ```text
    /// lo_i <= x_{c_i} + c_i μ_i <= hi_i   (complementary to μ_i),
    /// ```
    ///
    /// which is a spring law: outside `[lo_i, hi_i]` the multiplier is
    /// `μ_i = (lo_i − x_{c_i})/c_i` (or `(hi_i − x_{c_i})/c_i`), a spring of
    /// stiffness `1/c_i` in the units of `μ` (a penalty step with force
    /// `N = κ (lo − x)⁺ − κ (x − hi)⁺` and `μ = a N` has `c = 1/(a κ)`).
    /// The problem stays a box LCP, on `D + diag(c)` (SPD), solved by the
    /// same pivoting. `c_i = 0` keeps dof `i` rigid.
    pub fn with_compliance(mut self, compliance: Vec<f64>) -> Result<Self, ContactError> {
        let k = self.dofs.len();
        if compliance.len() != k {
            return Err(ContactError::Columns { dofs: k, columns: compliance.len() });
        }
        if let Some(&bad) = compliance.iter().find(|c| !(c.is_finite() && **c >= 0.0)) {
            return Err(ContactError::Compliance(bad));
        }
        for (i, c) in compliance.iter().enumerate() {
            self.delassus[i * k + i] += c - self.compliance[i];
        }
        self.compliance = compliance;
        Ok(self)
    }

    /// The influence column `W_j = A⁻¹ e_{c_j}` of dof `j` (as given to
    /// [`new`](Self::new)).
    #[track_caller]
    pub fn column(&self, j: usize) -> &[f64] {
        &self.columns[j * self.n..(j + 1) * self.n]
    }

    /// The constrained dofs, in the order of the bounds and multipliers.
    pub fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    /// `D_ij = (A⁻¹)_{c_i c_j}` (without the compliance).
    pub fn delassus(&self, i: usize, j: usize) -> f64 {
        let d = self.delassus[i * self.dofs.len() + j];
        if i == j {
            d - self.compliance[i]
        } else {
            d
        }
    }

    /// The multipliers of the last solve, in dof order.
    pub fn multipliers(&self) -> &[f64] {
        &self.mu
    }

    /// The dofs (indices into [`dofs`](Self::dofs)) with a nonzero
    /// multiplier after the last solve, in increasing order (empty when
    /// nothing was violated or held).
    pub fn active_set(&self) -> &[usize] {
        &self.set
    }

    /// Which bound holds each dof after the last solve.
    pub fn status(&self) -> &[Active] {
        &self.status
    }

    /// Turns the unconstrained solution `y = A⁻¹ b` (in place) into the
    /// constrained one. `lo[i] = -∞` or `hi[i] = +∞` give one-sided bounds;
    /// bounds must satisfy `lo <= hi` (checked in debug builds). The
    /// multipliers and statuses are then in [`multipliers`](Self::multipliers)
    /// and [`status`](Self::status).
    #[track_caller]
    pub fn project(&mut self, y: &mut [f64], lo: &[f64], hi: &[f64]) -> Result<MultiProjected, ContactError> {
        Ok(self.project_capped(y, lo, hi, usize::MAX)?.expect("no cap"))
    }

    /// [`project`](Self::project), giving up (`Ok(None)`, `y` untouched) as
    /// soon as a pivot would hold more than `cap` dofs at their bounds — for
    /// callers that solve large active sets another way (a reduced banded
    /// solve costs O(n) per pivot where the dense active block costs
    /// O(s³)). The statuses reached are then in [`status`](Self::status), a
    /// starting guess for that other solve.
    #[track_caller]
    pub fn project_capped(&mut self, y: &mut [f64], lo: &[f64], hi: &[f64], cap: usize) -> Result<Option<MultiProjected>, ContactError> {
        let k = self.dofs.len();
        assert_eq!(y.len(), self.n, "y");
        assert!(lo.len() == k && hi.len() == k, "bounds");
        debug_assert!(lo.iter().zip(hi).all(|(l, h)| l <= h), "bounds");
        // Nothing held from the last solve: one branch-free pass of bound
        // checks decides whether anything is violated (an inactive obstacle
        // costs that check and nothing else).
        if self.held == 0 {
            let mut violated = false;
            for (&c, (l, h)) in self.dofs.iter().zip(lo.iter().zip(hi)) {
                let yc = y[c];
                violated |= (yc < *l) | (yc > *h);
            }
            if !violated {
                if self.dirty {
                    self.mu.iter_mut().for_each(|m| *m = 0.0);
                    self.dirty = false;
                }
                self.set.clear();
                return Ok(Some(MultiProjected { iterations: 0, active: 0, residual: 0.0, single_pivots: 0 }));
            }
        }
        // Start from the previous statuses (warm start: contact sets change
        // little from step to step) but only where still meaningful.
        for i in 0..k {
            let yc = y[self.dofs[i]];
            if (self.status[i] == Active::Lower && !lo[i].is_finite()) || (self.status[i] == Active::Upper && !hi[i].is_finite()) {
                self.status[i] = Active::None;
            }
            if self.status[i] == Active::None {
                if yc < lo[i] {
                    self.status[i] = Active::Lower;
                } else if yc > hi[i] {
                    self.status[i] = Active::Upper;
                }
            }
        }
        self.held = self.status.iter().filter(|s| **s != Active::None).count();
        if self.held == 0 {
            if self.dirty {
                self.mu.iter_mut().for_each(|m| *m = 0.0);
                self.dirty = false;
            }
            self.set.clear();
            return Ok(Some(MultiProjected { iterations: 0, active: 0, residual: 0.0, single_pivots: 0 }));
        }
        self.dirty = true;
        let mut rule = PivotRule::new((0..k).map(|i| (y[self.dofs[i]], lo[i], hi[i])));
        let max_iter = PivotRule::max_iterations(k);
        let mut single_pivots = 0;
        for it in 1..=max_iter {
            if !self.solve_on_status(y, lo, hi, cap)? {
                return Ok(None);
            }
            let (z, mu, delassus) = (&self.z, &self.mu, &self.delassus);
            let single = rule.single();
            if rule.pass(&mut self.status, lo, hi, |i| (z[i], mu[i] * delassus[i * k + i])) == 0 {
                let residual = self.apply(y, lo, hi);
                self.held = self.set.len();
                return Ok(Some(MultiProjected { iterations: it, active: self.held, residual, single_pivots }));
            }
            single_pivots += usize::from(single);
        }
        Err(ContactError::NoConvergence { iterations: max_iter })
    }

    /// `μ_S` from `D_SS μ_S = bound_S − y_S`, `μ = 0` off `S`; then `z`.
    /// `false` (nothing solved) when `S` holds more than `cap` dofs.
    fn solve_on_status(&mut self, y: &[f64], lo: &[f64], hi: &[f64], cap: usize) -> Result<bool, ContactError> {
        let k = self.dofs.len();
        self.set.clear();
        self.set.extend((0..k).filter(|&i| self.status[i] != Active::None));
        let s = self.set.len();
        if s > cap {
            return Ok(false);
        }
        for (a, &i) in self.set.iter().enumerate() {
            let bound = if self.status[i] == Active::Lower { lo[i] } else { hi[i] };
            self.rhs[a] = bound - y[self.dofs[i]];
            for (b, &j) in self.set.iter().enumerate() {
                self.chol[a * s + b] = self.delassus[i * k + j];
            }
        }
        if !cholesky(&mut self.chol[..s * s], s) {
            return Err(ContactError::NotPositiveDefinite);
        }
        cholesky_solve(&self.chol[..s * s], s, &mut self.rhs[..s]);
        self.mu.iter_mut().for_each(|m| *m = 0.0);
        for (a, &i) in self.set.iter().enumerate() {
            self.mu[i] = self.rhs[a];
        }
        for i in 0..k {
            let mut zi = y[self.dofs[i]];
            for &j in &self.set {
                zi += self.delassus[i * k + j] * self.mu[j];
            }
            self.z[i] = zi;
        }
        Ok(true)
    }

    /// Sets the statuses (the warm start of the next solve) after a solve
    /// made elsewhere (see [`project_capped`](Self::project_capped)); the
    /// multipliers are zeroed.
    #[track_caller]
    pub fn set_status(&mut self, status: &[Active]) {
        assert_eq!(status.len(), self.dofs.len(), "status");
        self.status.copy_from_slice(status);
        self.held = status.iter().filter(|s| **s != Active::None).count();
        self.mu.iter_mut().for_each(|m| *m = 0.0);
        self.dirty = false;
        self.set.clear();
    }

    /// The compliance of dof `i` (0: rigid).
    pub fn compliance(&self, i: usize) -> f64 {
        self.compliance[i]
    }

    /// `x = y + Σ μ_j W_j`, rigid bounds set exactly; returns the residual.
    fn apply(&mut self, y: &mut [f64], lo: &[f64], hi: &[f64]) -> f64 {
        let k = self.dofs.len();
        for &j in &self.set {
            let mu = self.mu[j];
            let col = &self.columns[j * self.n..(j + 1) * self.n];
            for (yi, wi) in y.iter_mut().zip(col) {
                *yi += mu * wi;
            }
        }
        let mut residual = 0.0_f64;
        for i in 0..k {
            let d = self.delassus[i * k + i];
            let ci = self.compliance[i];
            if ci > 0.0 {
                // A spring: x_c + c μ is what the bounds hold.
                let zi = y[self.dofs[i]] + ci * self.mu[i];
                residual = residual.max(match self.status[i] {
                    Active::Lower => (-self.mu[i] * d).max(0.0).max((zi - lo[i]).abs()),
                    Active::Upper => (self.mu[i] * d).max(0.0).max((zi - hi[i]).abs()),
                    Active::None => (lo[i] - zi).max(zi - hi[i]).max(0.0),
                });
                continue;
            }
            match self.status[i] {
                Active::Lower => {
                    y[self.dofs[i]] = lo[i];
                    residual = residual.max((-self.mu[i] * d).max(0.0));
                }
                Active::Upper => {
                    y[self.dofs[i]] = hi[i];
                    residual = residual.max((self.mu[i] * d).max(0.0));
                }
                Active::None => {
                    let zi = y[self.dofs[i]];
                    residual = residual.max((lo[i] - zi).max(zi - hi[i]).max(0.0));
                }
            }
        }
        residual
    }
}

/// [`MultiProjection`]'s solve for one rigid dof, as scalar arithmetic: the
/// same operations in the same order (the bound checks, the warm start
/// from the last status, [`PivotRule`]'s tolerance and passes, the
/// Cholesky solve of the 1 × 1 Delassus system `μ = ((bound − y_c)/√D)/√D`,
/// `z = y_c + D μ`), so the same bits — for callers that solve one contact
/// on many problems at once (the lockstep engines), lane by lane. The
/// caller keeps each problem's status (the warm start) and applies the
/// result as [`MultiProjection::project`] does: where the status returned
/// is not [`Active::None`], `y += μ W` and `y_c` set to the bound held.
#[derive(Clone, Copy, Debug)]
pub struct OneDof {
    /// `D = (A⁻¹)_cc` (symmetrised as [`MultiProjection::new`] does) and `√D`.
    d: f64,
    sq: f64,
}

impl OneDof {
    /// The scalar solve of a one-dof, rigid `mp`; `None` for several dofs
    /// or a compliant one.
    pub fn of(mp: &MultiProjection) -> Option<Self> {
        (mp.dofs.len() == 1 && mp.compliance[0] == 0.0).then(|| Self { d: mp.delassus[0], sq: mp.delassus[0].sqrt() })
    }

    /// The solve of `y_c` (`yc`) on `[lo, hi]` from the last `status` (the
    /// warm start; updated): the multiplier `μ` (0 when the status returned
    /// is [`Active::None`], and then `y` is left as it is). Errors as
    /// [`MultiProjection::project`] (which for one dof ends in at most
    /// three passes).
    #[inline]
    pub fn solve(&self, status: &mut Active, yc: f64, lo: f64, hi: f64) -> Result<f64, ContactError> {
        // Nothing held: the bound checks (`project_capped`'s first pass).
        if *status == Active::None && !((yc < lo) | (yc > hi)) {
            return Ok(0.0);
        }
        // The warm start.
        if (*status == Active::Lower && !lo.is_finite()) || (*status == Active::Upper && !hi.is_finite()) {
            *status = Active::None;
        }
        if *status == Active::None {
            if yc < lo {
                *status = Active::Lower;
            } else if yc > hi {
                *status = Active::Upper;
            }
        }
        if *status == Active::None {
            return Ok(0.0);
        }
        // `PivotRule::new`'s tolerance and `pass` (one dof: every pass
        // changes at most the one status, so block and single pivots agree).
        let scale = 0.0_f64.max(yc.abs().max(finite_or_zero(lo).abs()).max(finite_or_zero(hi).abs())).max(f64::MIN_POSITIVE);
        let tol = 64.0 * f64::EPSILON * scale;
        for _ in 0..PivotRule::max_iterations(1) {
            // `solve_on_status`: D μ = bound − y_c by Cholesky, then z.
            let (mu, z) = match *status {
                Active::None => (0.0, yc),
                s => {
                    let bound = if s == Active::Lower { lo } else { hi };
                    let mu = ((bound - yc) / self.sq) / self.sq;
                    (mu, yc + self.d * mu)
                }
            };
            let md = mu * self.d;
            let next = match *status {
                Active::None if z < lo - tol => Some(Active::Lower),
                Active::None if z > hi + tol => Some(Active::Upper),
                Active::Lower if md < -tol => Some(Active::None),
                Active::Upper if md > tol => Some(Active::None),
                _ => None,
            };
            match next {
                Some(s) => *status = s,
                None => return Ok(mu),
            }
        }
        Err(ContactError::NoConvergence { iterations: PivotRule::max_iterations(1) })
    }
}

fn finite_or_zero(x: f64) -> f64 {
    if x.is_finite() {
        x
    } else {
        0.0
    }
}

/// In-place dense Cholesky `L Lᵀ` of an `s × s` row-major SPD matrix (the
/// lower triangle holds `L`); false if a pivot is not positive.
fn cholesky(a: &mut [f64], s: usize) -> bool {
    for j in 0..s {
        let mut d = a[j * s + j];
        for p in 0..j {
            d -= a[j * s + p] * a[j * s + p];
        }
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        let d = d.sqrt();
        a[j * s + j] = d;
        for i in j + 1..s {
            let mut v = a[i * s + j];
            for p in 0..j {
                v -= a[i * s + p] * a[j * s + p];
            }
            a[i * s + j] = v / d;
        }
    }
    true
}

/// Solves `L Lᵀ x = b` in place with the factor of [`cholesky`].
fn cholesky_solve(l: &[f64], s: usize, b: &mut [f64]) {
    for i in 0..s {
        let mut v = b[i];
        for p in 0..i {
            v -= l[i * s + p] * b[p];
        }
        b[i] = v / l[i * s + i];
    }
    for i in (0..s).rev() {
        let mut v = b[i];
        for p in i + 1..s {
            v -= l[p * s + i] * b[p];
        }
        b[i] = v / l[i * s + i];
    }
}
