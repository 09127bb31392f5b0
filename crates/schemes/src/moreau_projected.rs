//! Moreau–Jean with a direct projection of the positions (docs/theory.md
//! §4.6.4; Acary, CMAME 2013; Siconos's `MoreauJeanDirectProjectionOSI`
//! with `TimeSteppingDirectProjection` and `MLCPProjectOnConstraints`):
//! the step of [`MoreauJean`], then the positions of the contacts in the
//! index set put back on their bounds,
//!
//! ```text
//! Ũ^{n+1} from the Moreau–Jean step (the index set I: its Newton laws),
//! if max_{i ∈ I} max(0, −y_i(Ũ^{n+1})) > tol:
//!     U^{n+1} = argmin ½|U − Ũ^{n+1}|²  subject to  y_i(U) >= 0, i ∈ I,
//! V^{n+1} unchanged,
//! ```
//!
//! `y_i` the gap of a contact's side (`u_c − lo`, `hi − u_c`). The metric is
//! the identity (Siconos's default: `MLCPProjectOnConstraints` without mass
//! normalisation, the LCP matrix `H Hᵀ`); each contact holds its own dof,
//! so `H Hᵀ` is the identity and the exact projection is the clamp of each
//! violated side in `I` on its bound. The index set `I` is kept from step
//! to step with Siconos's thresholds ([`crate::moreau::IndexSet`]): a side
//! joins when `y + γ dt ẏ <= 1e-7`, leaves when `y + γ dt ẏ > 1e-7` and
//! `ẏ >= 0`; `tol = 1e-8` (Siconos's `constraintTolUnilateral`). A side
//! not in `I` is not projected: its penetration stays. The projection
//! changes positions only, so it changes the discrete energy by the
//! potential energy of the shift.

use crate::moreau::MoreauJean;
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};

/// Siconos's thresholds (`MoreauJeanDirectProjectionOSI`'s
/// `SICONOS_MPC_DEFAULT_ACTIVATION_POS_THRESHOLD` and its deactivation
/// twin): a side joins the index set at a predicted gap `<= 1e-7`, leaves
/// above it (with a non-negative rate).
pub const INDEX_SET_THRESHOLD: f64 = 1e-7;
/// Siconos's `TimeSteppingDirectProjection::_constraintTolUnilateral`: the
/// projection acts when a side of the index set is violated by more.
pub const PROJECTION_TOLERANCE: f64 = 1e-8;

/// Moreau–Jean followed by the direct projection of the positions. Its
/// state ([`Stepper::state`]) is `U^n, V^n` as Moreau–Jean's; the index
/// set is kept across [`Stepper::set_state`] (it is decided again, with
/// its thresholds, at the next step).
pub struct MoreauJeanProjected {
    mj: MoreauJean,
    /// The steps whose projection acted.
    projections: u64,
    /// The change of the discrete energy made by the projections so far.
    projection_energy: f64,
}

impl MoreauJeanProjected {
    /// Sets up the scheme (as [`MoreauJean::new`]).
    pub fn new(label: String, dy: Dynamics, theta: f64, restitution: f64, gamma: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        let mj = MoreauJean::new(label, dy, theta, restitution, gamma, dt, init)?.with_index_set(INDEX_SET_THRESHOLD, INDEX_SET_THRESHOLD);
        Ok(Self { mj, projections: 0, projection_energy: 0.0 })
    }

    /// Velocity `V^n`.
    pub fn velocity(&self) -> &[f64] {
        self.mj.velocity()
    }

    /// The steps whose projection acted so far.
    pub fn projections(&self) -> u64 {
        self.projections
    }

    /// The change of the discrete energy `½ VᵀMV + ½ UᵀKU − FᵀU` made by
    /// the projections so far (their potential energy: the velocities are
    /// kept).
    pub fn projection_energy(&self) -> f64 {
        self.projection_energy
    }

    /// The projection after the step: the sides in the index set put back
    /// on their bounds if one is violated by more than the tolerance.
    fn project(&mut self) {
        let Some((u, contacts, set)) = self.mj.index_set_parts() else { return };
        // Siconos's criterion: the largest violation max(0, −y) over the set.
        let mut worst = 0.0f64;
        for (ct, &(lo, hi)) in contacts.iter().zip(&set.sides) {
            if lo {
                worst = worst.max(ct.bounds.lo - u[ct.dof]);
            }
            if hi {
                worst = worst.max(u[ct.dof] - ct.bounds.hi);
            }
        }
        if worst <= PROJECTION_TOLERANCE {
            return;
        }
        let before = self.mj.energy_now();
        let Some((u, contacts, set)) = self.mj.index_set_parts() else { return };
        for (ct, &(lo, hi)) in contacts.iter().zip(&set.sides) {
            let (b, x) = (ct.bounds, &mut u[ct.dof]);
            if lo && *x < b.lo {
                *x = b.lo;
            }
            if hi && *x > b.hi {
                *x = b.hi;
            }
        }
        self.projections += 1;
        self.projection_energy += self.mj.energy_now() - before;
    }
}

impl Stepper for MoreauJeanProjected {
    delegate_stepper!(mj);
    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let rep = self.mj.step()?;
        self.project();
        Ok(rep)
    }
    fn energy(&mut self) -> Option<(f64, f64)> {
        self.mj.energy()
    }
}

// ---- The registry's row of this file: moreau-jean-projected.

use crate::family::{Capabilities, Family, Node, SchemeSpec};
use crate::moreau;

/// Moreau–Jean with the direct projection of the positions (Siconos's
/// `MoreauJeanDirectProjectionOSI`), θ ∈ [1/2, 1], e ∈ [0, 1], γ ∈ [0, 1].
pub(crate) static MOREAU_JEAN_PROJECTED: Family = Family {
    name: "moreau-jean-projected",
    about: "Moreau–Jean followed by the projection of the positions of the contacts in its index set on their bounds (Siconos's MoreauJeanDirectProjectionOSI; docs/theory.md §4.6.4)",
    params: &[moreau::THETA, moreau::E, moreau::GAMMA],
    presets: &[],
    validate: moreau::check_params,
    capabilities: |_| Capabilities { node: Node::Massive, restitution: true, lockstep: true, ..Capabilities::IMPLICIT },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(MoreauJeanProjected::new(s.to_string(), dy, s.args()[0], s.args()[1], s.args()[2], dt, init)?)),
};

impl SchemeSpec {
    /// Moreau–Jean with the direct projection of the positions, θ,
    /// restitution `e` and the predictor's γ (not validated until built).
    pub fn moreau_jean_projected(theta: f64, restitution: f64, gamma: f64) -> Self {
        MOREAU_JEAN_PROJECTED.with(&[theta, restitution, gamma])
    }
}
