//! The step's contact solve with several contacts (docs/theory.md §3): the
//! influence columns `A⁻¹ e_{c_i}` of the scheme's constant matrix, the
//! exact box-complementarity solve of [`MultiProjection`] and the per-step
//! bound buffers, shared by every scheme that takes several contacts.

use crate::{Contact, Dynamics, SchemeError};
use signorini_contact::{Active, ContactError, MultiProjection, OneDof, PivotRule};
use signorini_fem::{BandLdlt, SymBand};

/// `y ← y + Σ μ_i A⁻¹ e_{c_i}` with `lo_i <= y_{c_i} <= hi_i` (or the spring
/// law, see [`MultiSolve::with_springs`]). Public, hidden from the docs, for
/// the crate's tests only (`tests/it/multi_solve.rs`: the library is not
/// compiled a second time as a test harness); the schemes are its users.
#[doc(hidden)]
pub struct MultiSolve {
    mp: MultiProjection,
    /// Bounds of the current step (filled by the scheme).
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// Solves that pivoted (something violated or held) and their pivots.
    pub pivoting_solves: u64,
    pub pivots: u64,
    /// Large active sets: the reduced banded solve (see [`Banded`]).
    banded: Option<Banded>,
    /// The largest active set the dense Delassus pivots take.
    cap: usize,
    /// Whether the last solve was the banded one.
    last_banded: bool,
}

/// The reduced banded solve for large active sets: with the active dofs
/// fixed at their bounds (or held by their springs) the step's problem is
/// the step matrix with those rows and columns replaced, a banded solve of
/// O(n p²) per pivot, where the Delassus pivot factorises the dense active
/// block in O(s³). Same statuses, same pivoting rule (block pivots, then
/// least-index single pivots), preallocated storage.
struct Banded {
    a: SymBand,
    work: SymBand,
    fac: BandLdlt,
    dofs: Vec<usize>,
    b: Vec<f64>,
    x: Vec<f64>,
    status: Vec<Active>,
    mu: Vec<f64>,
    set: Vec<usize>,
    diag: Vec<f64>,
    compliance: Vec<f64>,
}

impl MultiSolve {
    /// Newton's impact law on the contacts closed in `closed`: the velocity
    /// `v` corrected by impulses so that each closed contact leaves its stop
    /// no slower than `−e` times its velocity before (`before`, or `v`
    /// itself when `None`; `e` the contact's own restitution or
    /// `restitution`), the others unconstrained; the impulses into
    /// `impulses` (zero when none is closed). The explicit velocity-level
    /// schemes' step (cd-lagrange, d1-minus-linear).
    pub(crate) fn newton_law(&mut self, contacts: &[Contact], closed: &[Active], restitution: f64, before: Option<&[f64]>, v: &mut [f64], impulses: &mut [f64]) -> Result<(), SchemeError> {
        if closed.iter().all(|s| *s == Active::None) {
            impulses.iter_mut().for_each(|x| *x = 0.0);
            return Ok(());
        }
        for (i, (ct, s)) in contacts.iter().zip(closed).enumerate() {
            let target = -ct.restitution.unwrap_or(restitution) * before.map_or(v[ct.dof], |b| b[ct.dof]);
            (self.lo[i], self.hi[i]) = match s {
                Active::Lower => (target, f64::INFINITY),
                Active::Upper => (f64::NEG_INFINITY, target),
                Active::None => (f64::NEG_INFINITY, f64::INFINITY),
            };
        }
        let (mu, _) = self.solve(v)?;
        impulses.copy_from_slice(mu);
        Ok(())
    }

    /// For the tests: the largest active set the dense Delassus pivots take
    /// (beyond it the banded solve, when enabled).
    #[doc(hidden)]
    pub fn set_dense_cap(&mut self, cap: usize) {
        self.cap = cap;
    }

    /// For the tests: whether the banded solve is enabled, and whether the
    /// last solve took it.
    #[doc(hidden)]
    pub fn banded_state(&self) -> (bool, bool) {
        (self.banded.is_some(), self.last_banded)
    }

    /// Influence columns of the factor `a` at every contact dof (built once).
    pub fn new(dy: &Dynamics, a: &BandLdlt) -> Result<Self, SchemeError> {
        let n = dy.n();
        let dofs: Vec<usize> = dy.contacts.iter().map(|c| c.dof).collect();
        let columns = dofs
            .iter()
            .map(|&c| {
                let mut w = vec![0.0; n];
                w[c] = 1.0;
                a.solve_in_place(&mut w);
                w
            })
            .collect();
        let k = dofs.len();
        Ok(Self { mp: MultiProjection::new(dofs, columns)?, lo: vec![0.0; k], hi: vec![0.0; k], pivoting_solves: 0, pivots: 0, banded: None, cap: usize::MAX, last_banded: false })
    }

    /// Enables the reduced banded solve of the step matrix `a` for active
    /// sets beyond `s` with `s³ > 24 n (p+1)²` (measured: where one banded
    /// pivot undercuts one dense pivot), when there are more contacts than that.
    pub fn with_banded(mut self, a: SymBand) -> Result<Self, SchemeError> {
        let (n, p, k) = (a.n(), a.half_bandwidth(), self.lo.len());
        let cap = (24.0 * n as f64 * ((p + 1) * (p + 1)) as f64).cbrt().max(8.0) as usize;
        if k <= cap {
            return Ok(self);
        }
        let fac = a.factor()?;
        let dofs: Vec<usize> = self.mp.dofs().to_vec();
        let diag = (0..k).map(|i| self.mp.delassus(i, i)).collect();
        let compliance = (0..k).map(|i| self.mp.compliance(i)).collect();
        self.banded = Some(Banded { work: a.clone(), a, fac, dofs, b: vec![0.0; n], x: vec![0.0; n], status: vec![Active::None; k], mu: vec![0.0; k], set: Vec::with_capacity(k), diag, compliance });
        self.cap = cap;
        Ok(self)
    }

    /// Springs instead of rigid bounds: contact `i` has stiffness `kappa[i]`
    /// and the step's multiplier is `μ_i = scale · N_i` (`scale = a dt²` of
    /// the step), so its compliance is `1/(scale κ_i)`.
    pub fn with_springs(mut self, kappa: &[f64], scale: f64) -> Result<Self, SchemeError> {
        self.mp = self.mp.with_compliance(kappa.iter().map(|k| 1.0 / (scale * k)).collect())?;
        if let Some(bd) = &mut self.banded {
            for (i, c) in bd.compliance.iter_mut().enumerate() {
                *c = self.mp.compliance(i);
            }
        }
        Ok(self)
    }

    /// With one rigid contact: its solve as scalar arithmetic ([`OneDof`],
    /// the same bits as [`solve`](Self::solve)) and its influence column
    /// `A⁻¹ e_c`; `None` otherwise.
    pub(crate) fn one_dof(&self) -> Option<(OneDof, &[f64])> {
        Some((OneDof::of(&self.mp)?, self.mp.column(0)))
    }

    /// `(A⁻¹)_{c_i c_i}`.
    pub fn diagonal(&self, i: usize) -> f64 {
        self.mp.delassus(i, i)
    }

    /// The multipliers of the last solve.
    pub fn multipliers(&self) -> &[f64] {
        match &self.banded {
            Some(bd) if self.last_banded => &bd.mu,
            _ => self.mp.multipliers(),
        }
    }

    /// The contacts with a nonzero multiplier after the last solve.
    pub fn active_set(&self) -> &[usize] {
        match &self.banded {
            Some(bd) if self.last_banded => &bd.set,
            _ => self.mp.active_set(),
        }
    }

    /// The statuses of the last solve.
    pub fn status(&self) -> &[Active] {
        match &self.banded {
            Some(bd) if self.last_banded => &bd.status,
            _ => self.mp.status(),
        }
    }

    /// Solves in place with the bounds in `lo`, `hi`; returns the
    /// multipliers and statuses.
    pub fn solve(&mut self, y: &mut [f64]) -> Result<(&[f64], &[Active]), SchemeError> {
        match self.mp.project_capped(y, &self.lo, &self.hi, self.cap)? {
            Some(r) => {
                self.last_banded = false;
                if r.iterations > 0 {
                    self.pivoting_solves += 1;
                    self.pivots += r.iterations as u64;
                }
            }
            None => {
                let bd = self.banded.as_mut().expect("a cap only with the banded solve");
                bd.status.copy_from_slice(self.mp.status());
                let it = bd.solve(y, &self.lo, &self.hi)?;
                self.mp.set_status(&bd.status);
                self.last_banded = true;
                self.pivoting_solves += 1;
                self.pivots += it as u64;
            }
        }
        Ok((self.multipliers(), self.status()))
    }
}

impl Banded {
    /// From the statuses in `status` (a guess), the exact solution into
    /// `y` (which holds `A⁻¹ b` on entry); returns the pivots made.
    fn solve(&mut self, y: &mut [f64], lo: &[f64], hi: &[f64]) -> Result<usize, SchemeError> {
        let k = self.dofs.len();
        let p = self.a.half_bandwidth();
        let n = self.a.n();
        self.a.mul_vec(y, &mut self.b);
        let mut rule = PivotRule::new((0..k).map(|i| (y[self.dofs[i]], lo[i], hi[i])));
        let max_iter = PivotRule::max_iterations(k);
        for it in 1..=max_iter {
            // The reduced system: rows of active rigid dofs replaced by
            // x_c = bound; active springs add 1/c to the diagonal.
            self.work.copy_from(&self.a);
            self.x.copy_from_slice(&self.b);
            self.set.clear();
            for i in 0..k {
                let bound = match self.status[i] {
                    Active::None => continue,
                    Active::Lower => lo[i],
                    Active::Upper => hi[i],
                };
                self.set.push(i);
                let c = self.dofs[i];
                let ci = self.compliance[i];
                if ci > 0.0 {
                    self.work.add(c, c, 1.0 / ci);
                    self.x[c] += bound / ci;
                } else {
                    for r in c.saturating_sub(p)..(c + p + 1).min(n) {
                        if r != c {
                            self.x[r] -= self.a.get(r, c) * bound;
                        }
                    }
                }
            }
            for &i in &self.set {
                if self.compliance[i] == 0.0 {
                    let c = self.dofs[i];
                    self.work.zero_row_col(c);
                    self.work.set(c, c, 1.0);
                    self.x[c] = if self.status[i] == Active::Lower { lo[i] } else { hi[i] };
                }
            }
            // The fixed dofs' columns went to the right-hand side above;
            // their rows and columns are now those of the identity.
            self.work.factor_into(&mut self.fac).map_err(|_| SchemeError::Contact(ContactError::NotPositiveDefinite))?;
            self.fac.solve_in_place(&mut self.x);
            // Multipliers μ_i = (A x − b)_{c_i} on the active set.
            self.mu.iter_mut().for_each(|m| *m = 0.0);
            for &i in &self.set {
                let c = self.dofs[i];
                let mut r = -self.b[c];
                for j in c.saturating_sub(p)..(c + p + 1).min(n) {
                    r += self.a.get(c, j) * self.x[j];
                }
                self.mu[i] = r;
            }
            // Feasibility and signs: the same pivoting rule as the
            // Delassus pivots.
            let (x, mu, dofs, comp, diag) = (&self.x, &self.mu, &self.dofs, &self.compliance, &self.diag);
            if rule.pass(&mut self.status, lo, hi, |i| (x[dofs[i]] + comp[i] * mu[i], mu[i] * diag[i])) == 0 {
                y.copy_from_slice(&self.x);
                return Ok(it);
            }
        }
        Err(SchemeError::Contact(ContactError::NoConvergence { iterations: max_iter }))
    }
}
