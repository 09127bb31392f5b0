//! Moreau–Jean with the combined projection (docs/theory.md §4.6.4; Acary,
//! CMAME 2013; Siconos's `MoreauJeanCombinedProjectionOSI` with
//! `TimeSteppingCombinedProjection` and `MLCPProjectOnConstraints`): the
//! index set is decided on the step's own positions, the step redone until
//! it stops growing, and the positions of its contacts projected on their
//! bounds as equalities,
//!
//! ```text
//! I = ∅ (every step starts empty)
//! loop:
//!     (Ũ, V^{n+1}) = the Moreau–Jean step from U^n, V^n with Newton's law on I
//!     if max_{i ∈ I} |y_i(Ũ)| >= tol:  U^{n+1} = argmin ½|U − Ũ|²  s.t.  y_i(U) = 0, i ∈ I
//!     else U^{n+1} = Ũ
//!     J = { sides not in I with y_i(U^{n+1}) <= 0 }
//!     if J = ∅: done;  else I = I ∪ J and redo the step
//! ```
//!
//! `y_i` the gap of a contact's side (`u_c − lo`, `hi − u_c`). The metric is
//! the identity (`MLCPProjectOnConstraints` without mass normalisation);
//! each contact holds its own dof, so the projection puts each side of `I`
//! on its bound, open or not (Siconos's `doCombinedProjOnEquality`, on by
//! default). `tol = 1e-8` (`constraintTolUnilateral`); the set only grows
//! within a step, so the passes end (at most `2k + 1`; Siconos allows 50).
//! No γ: the constructor of Siconos's integrator takes θ only. Velocities
//! are those of the last pass (the projection keeps them).

use crate::moreau::MoreauJean;
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};

/// Siconos's `TimeSteppingCombinedProjection::_constraintTolUnilateral`:
/// the projection acts when a side of the index set is off its bound by
/// this much or more.
pub const COMBINED_TOLERANCE: f64 = 1e-8;

/// Moreau–Jean with the combined projection. Its state
/// ([`Stepper::state`]) is `U^n, V^n` as Moreau–Jean's (the index set is
/// decided afresh each step).
pub struct MoreauJeanCombined {
    mj: MoreauJean,
    /// `dt` and θ, for [`Self::first_pass_may_grow`].
    dt: f64,
    theta: f64,
    /// The step's start `U^n, V^n` and its unconstrained `V^{n+1}`.
    u0: Vec<f64>,
    v0: Vec<f64>,
    free: Vec<f64>,
    /// The steps whose projection acted, the passes of all steps.
    projections: u64,
    passes: u64,
    /// The change of the discrete energy made by the projections so far.
    projection_energy: f64,
}

impl MoreauJeanCombined {
    /// Sets up the scheme (as [`MoreauJean::new`], without γ).
    pub fn new(label: String, dy: Dynamics, theta: f64, restitution: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        let mj = MoreauJean::new(label, dy, theta, restitution, 0.0, dt, init)?.with_given_index_set();
        let n = init.u.len();
        Ok(Self { mj, dt, theta, u0: vec![0.0; n], v0: vec![0.0; n], free: vec![0.0; n], projections: 0, passes: 0, projection_energy: 0.0 })
    }

    /// Velocity `V^n`.
    pub fn velocity(&self) -> &[f64] {
        self.mj.velocity()
    }

    /// The steps whose projection acted so far.
    pub fn projections(&self) -> u64 {
        self.projections
    }

    /// The passes (Moreau–Jean steps) taken so far: one a step, one more
    /// each time the index set grew.
    pub fn passes(&self) -> u64 {
        self.passes
    }

    /// The change of the discrete energy `½ VᵀMV + ½ UᵀKU − FᵀU` made by
    /// the projections so far (potential energy: the velocities are kept).
    pub fn projection_energy(&self) -> f64 {
        self.projection_energy
    }

    /// One pass's projection: the sides of the set put on their bounds if
    /// one is off by `tol` or more. Returns the energy it added, if it acted.
    fn project(&mut self) -> Option<f64> {
        let (u, contacts, set) = self.mj.index_set_parts()?;
        let mut worst = 0.0f64;
        for (ct, &(lo, hi)) in contacts.iter().zip(&set.sides) {
            if lo {
                worst = worst.max((u[ct.dof] - ct.bounds.lo).abs());
            }
            if hi {
                worst = worst.max((ct.bounds.hi - u[ct.dof]).abs());
            }
        }
        if worst < COMBINED_TOLERANCE {
            return None;
        }
        let before = self.mj.energy_now();
        let (u, contacts, set) = self.mj.index_set_parts()?;
        for (ct, &(lo, hi)) in contacts.iter().zip(&set.sides) {
            // Both sides in the set (a gap closed from both): the lower wins.
            if lo {
                u[ct.dof] = ct.bounds.lo;
            } else if hi {
                u[ct.dof] = ct.bounds.hi;
            }
        }
        Some(self.mj.energy_now() - before)
    }

    /// Whether the first pass (an empty set: no Newton's law, no
    /// projection) can end with a side to add, so that the step's start
    /// must be kept for a redo: with several contacts always (their solve
    /// decides), with one whether its `u_c + dt ((1−θ) v_c + θ v_c^{n+1})`
    /// (the unconstrained `V^{n+1}` in `free_mut`: `finish_step`'s own
    /// arithmetic, so its value) reaches a bound as [`Self::grow`] asks.
    fn first_pass_may_grow(&mut self) -> bool {
        let (dt, th) = (self.dt, self.theta);
        let Some((_, contacts, _)) = self.mj.index_set_parts() else { return true };
        let [ct] = contacts else { return true };
        let (c, bounds) = (ct.dof, ct.bounds);
        let (u, v, _) = self.mj.step_start_mut();
        let (uc, vc) = (u[c], v[c]);
        let u1 = uc + dt * ((1.0 - th) * vc + th * self.mj.free_mut()[c]);
        u1 - bounds.lo <= 0.0 || bounds.hi - u1 <= 0.0
    }

    /// Adds to the set the sides out of it whose gap is `<= 0`; whether
    /// one was added.
    fn grow(&mut self) -> bool {
        let Some((u, contacts, set)) = self.mj.index_set_parts() else { return false };
        let mut grew = false;
        for (ct, (lo, hi)) in contacts.iter().zip(set.sides.iter_mut()) {
            if !*lo && u[ct.dof] - ct.bounds.lo <= 0.0 {
                (*lo, grew) = (true, true);
            }
            if !*hi && ct.bounds.hi - u[ct.dof] <= 0.0 {
                (*hi, grew) = (true, true);
            }
        }
        grew
    }
}

impl Stepper for MoreauJeanCombined {
    delegate_stepper!(mj);
    fn step(&mut self) -> Result<StepReport, SchemeError> {
        if let Some((_, _, set)) = self.mj.index_set_parts() {
            set.sides.iter_mut().for_each(|s| *s = (false, false));
        }
        self.mj.free_velocity();
        // The step's start is kept for a redo only where the first pass can
        // end with a side to add: most steps of one contact cannot, and
        // skip the three copies.
        let keep = self.first_pass_may_grow();
        if keep {
            self.free.copy_from_slice(self.mj.free_mut());
            let (u, v, _) = self.mj.step_start_mut();
            self.u0.copy_from_slice(u);
            self.v0.copy_from_slice(v);
        }
        let n0 = *self.mj.step_start_mut().2;
        loop {
            self.passes += 1;
            let rep = self.mj.finish_step()?;
            let projected = self.project();
            let grew = self.grow();
            if grew && !keep {
                // Unreachable: `first_pass_may_grow` is the first pass's own test.
                return Err(SchemeError::Structure("moreau-jean-combined: a redo without the step's start"));
            }
            if !grew {
                if let Some(de) = projected {
                    self.projections += 1;
                    self.projection_energy += de;
                }
                return Ok(rep);
            }
            // Redo the step from its start with the larger set.
            let (u, v, n) = self.mj.step_start_mut();
            u.copy_from_slice(&self.u0);
            v.copy_from_slice(&self.v0);
            *n = n0;
            self.mj.free_mut().copy_from_slice(&self.free);
        }
    }
    fn energy(&mut self) -> Option<(f64, f64)> {
        self.mj.energy()
    }
}

// ---- The registry's row of this file: moreau-jean-combined.

use crate::family::{Capabilities, Family, Node, SchemeSpec};
use crate::moreau;

/// Moreau–Jean with the combined projection (Siconos's
/// `MoreauJeanCombinedProjectionOSI`), θ ∈ [1/2, 1], e ∈ [0, 1].
pub(crate) static MOREAU_JEAN_COMBINED: Family = Family {
    name: "moreau-jean-combined",
    about: "Moreau–Jean with the combined projection: the index set decided on the step's positions (the step redone while it grows), its contacts' positions projected on their bounds (Siconos's MoreauJeanCombinedProjectionOSI; docs/theory.md §4.6.4)",
    params: &[moreau::THETA, moreau::E],
    presets: &[],
    validate: moreau::check_params,
    capabilities: |_| Capabilities { node: Node::Massive, restitution: true, lockstep: true, ..Capabilities::IMPLICIT },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(MoreauJeanCombined::new(s.to_string(), dy, s.args()[0], s.args()[1], dt, init)?)),
};

impl SchemeSpec {
    /// Moreau–Jean with the combined projection, θ and restitution `e`
    /// (not validated until built).
    pub fn moreau_jean_combined(theta: f64, restitution: f64) -> Self {
        MOREAU_JEAN_COMBINED.with(&[theta, restitution])
    }
}
