//! The step's contact solve with several contacts (docs/theory.md §3): the
//! influence columns `A⁻¹ e_{c_i}` of the scheme's constant matrix, the
//! exact box-complementarity solve of [`MultiProjection`] and the per-step
//! bound buffers, shared by every scheme that takes several contacts.

use crate::{Dynamics, SchemeError};
use signorini_contact::{Active, MultiProjection};
use signorini_fem::BandLdlt;

/// `y ← y + Σ μ_i A⁻¹ e_{c_i}` with `lo_i <= y_{c_i} <= hi_i` (or the spring
/// law, see [`MultiSolve::with_springs`]).
pub(crate) struct MultiSolve {
    mp: MultiProjection,
    /// Bounds of the current step (filled by the scheme).
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// Solves that pivoted (something violated or held) and their pivots.
    pub pivoting_solves: u64,
    pub pivots: u64,
}

impl MultiSolve {
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
        Ok(Self { mp: MultiProjection::new(dofs, columns)?, lo: vec![0.0; k], hi: vec![0.0; k], pivoting_solves: 0, pivots: 0 })
    }

    /// Springs instead of rigid bounds: contact `i` has stiffness `kappa[i]`
    /// and the step's multiplier is `μ_i = scale · N_i` (`scale = a dt²` of
    /// the step), so its compliance is `1/(scale κ_i)`.
    pub fn with_springs(mut self, kappa: &[f64], scale: f64) -> Result<Self, SchemeError> {
        self.mp = self.mp.with_compliance(kappa.iter().map(|k| 1.0 / (scale * k)).collect())?;
        Ok(self)
    }

    /// `(A⁻¹)_{c_i c_i}`.
    pub fn diagonal(&self, i: usize) -> f64 {
        self.mp.delassus(i, i)
    }

    /// The multipliers of the last solve.
    pub fn multipliers(&self) -> &[f64] {
        self.mp.multipliers()
    }

    /// The contacts with a nonzero multiplier after the last solve.
    pub fn active_set(&self) -> &[usize] {
        self.mp.active_set()
    }

    /// The statuses of the last solve.
    pub fn status(&self) -> &[Active] {
        self.mp.status()
    }

    /// Solves in place with the bounds in `lo`, `hi`; returns the
    /// multipliers and statuses.
    pub fn solve(&mut self, y: &mut [f64]) -> Result<(&[f64], &[Active]), SchemeError> {
        let r = self.mp.project(y, &self.lo, &self.hi)?;
        if r.iterations > 0 {
            self.pivoting_solves += 1;
            self.pivots += r.iterations as u64;
        }
        Ok((self.mp.multipliers(), self.mp.status()))
    }
}
