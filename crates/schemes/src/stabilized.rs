//! The contact-stabilized Newmark scheme of Deuflhard, Krause and Ertel
//! (IJNME 73, 2008; Krause and Walloth, Appl. Numer. Math. 62, 2012;
//! docs/theory.md §4.6.6): the trapezoidal Newmark rule (β = 1/4, γ = 1/2)
//! whose predictor is projected onto the admissible set in the mass norm
//! and whose old contact force is dropped. With `τ = dt`, `K` the set
//! `lo_i <= u_{c_i} <= hi_i`,
//!
//! ```text
//! U_pred   = U^n + τ V^n,
//! U^n_pred = argmin_{W ∈ K} ½ (W − U_pred)ᵀ M (W − U_pred)        (stabilisation),
//! U^{n+1}  = argmin_{W ∈ K} ½ Wᵀ A W − Wᵀ b,   A = M + τ/2 C + τ²/4 K,
//!            b = (M + τ/2 C) U^n_pred − τ²/4 K U^n − τ²/2 C V^n + τ²/4 (F^n + F^{n+1}),
//! V^{n+1}  = V^n + 2/τ (U^{n+1} − U^n_pred).
//! ```
//!
//! Without contact (both projections idle) this is the trapezoidal rule
//! exactly; with `C = 0`, `F = 0` its energy `E = ½VᵀMV + ½UᵀKU` does not
//! grow (docs/theory.md §7.7): the stabilisation only removes kinetic
//! energy, and the implicit contact force does non-positive work over
//! the step; the scheme reports that balance's terms ([`Stepper::work`],
//! [`Stepper::dissipation`]). Both constrained minimisations are solved exactly: the
//! box-constrained QPs of the mass (stabilisation) and of `A` by the
//! workspace's exact contact solve ([`MultiSolve`], influence columns of
//! `M⁻¹` and `A⁻¹`). The contact force reported at `t_{n+1}` is the step's
//! multiplier scaled to a force, `λ = −2 μ/τ²` (the static reaction exactly
//! for a node held at rest); the stabilisation's impulse is not a force
//! of the model and is not reported.
//!
//! The contact nodes must carry mass (the stabilisation projects in the
//! mass norm); the node has no impact law (a restitution is refused).

use crate::loads::{add_terms, Loads};
use crate::multi::MultiSolve;
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::Active;
use signorini_fem::BandLdlt;

/// The contact-stabilized Newmark scheme.
pub struct ContactStabilized {
    label: String,
    dt: f64,
    n: usize,
    dy: Dynamics,
    /// `A = M + τ/2 C + τ²/4 K`, factored.
    a: BandLdlt,
    /// The exact solves of the stabilisation (mass norm) and of the step (`A`).
    mass_solve: MultiSolve,
    step_solve: MultiSolve,
    u: Vec<f64>,
    v: Vec<f64>,
    /// `U^n_pred`.
    pred: Vec<f64>,
    rhs: Vec<f64>,
    tmp: Vec<f64>,
    /// `C (τ/2 U_pred − τ²/2 V)` (damped problems only).
    ctmp: Vec<f64>,
    /// Per forcing term, its values at the levels; the previous level's and this one's.
    loads: Loads,
    s_old: Vec<f64>,
    s_new: Vec<f64>,
    lams: Vec<f64>,
    acts: Vec<Active>,
    /// Since t = 0: the time-dependent load's work `Σ ½(F̃ⁿ + F̃ⁿ⁺¹)·ΔU`,
    /// the contacts' `Σ 2/τ² [μ·Δu_c − ν·(u_cⁿ⁺¹ − p_c)]` (≤ 0) and the
    /// damping's `Σ ½ ΔU·C(Vⁿ + Vⁿ⁺¹)` (docs/theory.md §7.9).
    work_forcing: f64,
    work_contact: f64,
    work_damping: f64,
}

impl ContactStabilized {
    /// Sets up the scheme (massive contact nodes; damping and
    /// time-dependent loads taken).
    pub fn new(label: String, dy: Dynamics, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        if dy.contacts.iter().any(|c| c.massless) {
            return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped): the predictor is projected in the mass norm" });
        }
        let n = dy.n();
        crate::check_start(dt, n, init)?;
        let a_mat = dy.step_matrix(0.5 * dt, 0.25 * dt * dt);
        let a = a_mat.factor()?;
        let m = dy.mass.factor()?;
        let step_solve = MultiSolve::new(&dy, &a)?.with_banded(a_mat)?;
        let mass_solve = MultiSolve::new(&dy, &m)?.with_banded(dy.mass.clone())?;
        let k = dy.k();
        let mut loads = Loads::values(&dy, dt);
        let mut s_old = vec![0.0; dy.forcing.len()];
        loads.next_into(&mut s_old);
        Ok(Self {
            label,
            dt,
            n: 0,
            a,
            mass_solve,
            step_solve,
            u: init.u.clone(),
            v: init.v.clone(),
            pred: vec![0.0; n],
            rhs: vec![0.0; n],
            tmp: vec![0.0; n],
            ctmp: vec![0.0; if dy.damping.is_some() { n } else { 0 }],
            s_new: s_old.clone(),
            s_old,
            loads,
            lams: vec![0.0; k],
            acts: vec![Active::None; k],
            work_forcing: 0.0,
            work_contact: 0.0,
            work_damping: 0.0,
            dy,
        })
    }

    /// Velocity `V^n`.
    pub fn velocity(&self) -> &[f64] {
        &self.v
    }

    /// `U^n_pred` of the last step (the stabilised predictor).
    pub fn predictor(&self) -> &[f64] {
        &self.pred
    }

    /// Each contact's bounds into a solve's buffers.
    fn bounds_into(dy: &Dynamics, ms: &mut MultiSolve) {
        for (i, ct) in dy.contacts.iter().enumerate() {
            ms.lo[i] = ct.bounds.lo;
            ms.hi[i] = ct.bounds.hi;
        }
    }
}

impl Stepper for ContactStabilized {
    stepper_accessors!();

    displacement_velocity_state!();

    fn contact_pivots(&self) -> Option<(u64, u64)> {
        Some((self.mass_solve.pivoting_solves + self.step_solve.pivoting_solves, self.mass_solve.pivots + self.step_solve.pivots))
    }

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let dt = self.dt;
        let q = 0.25 * dt * dt;
        // The stabilised predictor: U + τ V projected onto K in the mass norm.
        for ((p, u), v) in self.pred.iter_mut().zip(&self.u).zip(&self.v) {
            *p = u + dt * v;
        }
        Self::bounds_into(&self.dy, &mut self.mass_solve);
        self.mass_solve.solve(&mut self.pred)?;
        // b = M U_pred − τ²/4 K U + τ²/4 (F^n + F^{n+1}) (+ the damping's terms).
        self.dy.mass.mul_vec(&self.pred, &mut self.rhs);
        self.dy.stiffness.mul_vec(&self.u, &mut self.tmp);
        for ((b, k), f) in self.rhs.iter_mut().zip(&self.tmp).zip(&self.dy.load) {
            *b += q * (2.0 * f - k);
        }
        self.loads.next_into(&mut self.s_new);
        add_terms(&mut self.rhs, &self.dy.forcing, q, &self.s_old);
        add_terms(&mut self.rhs, &self.dy.forcing, q, &self.s_new);
        if let Some(cm) = &self.dy.damping {
            // + τ/2 C U_pred − τ²/2 C V
            for ((t, p), v) in self.tmp.iter_mut().zip(&self.pred).zip(&self.v) {
                *t = 0.5 * dt * p - 2.0 * q * v;
            }
            cm.mul_vec(&self.tmp, &mut self.ctmp);
            self.rhs.iter_mut().zip(&self.ctmp).for_each(|(b, c)| *b += c);
        }
        self.a.solve_in_place(&mut self.rhs);
        Self::bounds_into(&self.dy, &mut self.step_solve);
        let (mu, st) = self.step_solve.solve(&mut self.rhs)?;
        for (i, (&m, &a)) in mu.iter().zip(st).enumerate() {
            self.lams[i] = -2.0 * m / (dt * dt);
            self.acts[i] = a;
        }
        // The step's work (docs/theory.md §7.9), before U and V move on.
        let w = 2.0 / dt;
        for ((f, a), b) in self.dy.forcing.iter().zip(&self.s_old).zip(&self.s_new) {
            let du: f64 = f.shape.iter().zip(&self.rhs).zip(&self.u).map(|((g, un), u)| g * (un - u)).sum();
            self.work_forcing += 0.5 * (a + b) * du;
        }
        self.s_old.copy_from_slice(&self.s_new);
        let nu = self.mass_solve.multipliers();
        for ((ct, m), n) in self.dy.contacts.iter().zip(self.step_solve.multipliers()).zip(nu) {
            let c = ct.dof;
            self.work_contact += w / dt * (m * (self.rhs[c] - self.u[c]) - n * (self.rhs[c] - self.pred[c]));
        }
        if let Some(cm) = &self.dy.damping {
            for (((t, v), un), p) in self.tmp.iter_mut().zip(&self.v).zip(&self.rhs).zip(&self.pred) {
                *t = 2.0 * v + w * (un - p);
            }
            cm.mul_vec(&self.tmp, &mut self.ctmp);
            self.work_damping += 0.5 * self.ctmp.iter().zip(&self.rhs).zip(&self.u).map(|((c, un), u)| c * (un - u)).sum::<f64>();
        }
        // V^{n+1} = V^n + 2/τ (U^{n+1} − U_pred); U^{n+1}.
        for (((u, v), un), p) in self.u.iter_mut().zip(self.v.iter_mut()).zip(&self.rhs).zip(&self.pred) {
            *v += w * (un - p);
            *u = *un;
        }
        self.n += 1;
        crate::contact_step_report(self.n, self.time(), &self.dy.contacts, &self.u, None, &self.lams, &self.acts)
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        Some((self.time(), self.dy.energy(&self.u, &self.v)))
    }

    fn work(&self) -> Option<(f64, f64)> {
        Some((self.work_forcing, self.work_contact))
    }

    fn dissipation(&self) -> Option<f64> {
        Some(self.work_damping)
    }
}

// ---- The registry's row of this file: contact-stabilized.

use crate::family::{Capabilities, Family, Node};

/// Contact-stabilized Newmark (Deuflhard–Krause–Ertel): no parameters.
pub(crate) static CONTACT_STABILIZED: Family = Family {
    name: "contact-stabilized",
    about: "contact-stabilized Newmark (Deuflhard–Krause–Ertel): trapezoidal rule, predictor projected in the mass norm, no old contact force (docs/theory.md §4.6.6)",
    params: &[],
    presets: &[],
    validate: |_| Ok(()),
    capabilities: |_| Capabilities { node: Node::Massive, ..Capabilities::IMPLICIT },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(ContactStabilized::new(s.to_string(), dy, dt, init)?)),
};
