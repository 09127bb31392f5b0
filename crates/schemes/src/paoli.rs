//! Paoli–Schatzman two-step scheme with restitution (SPEC §4.3, 2017 paper
//! eq. (34)); with `e = 0` and two-sided bounds it is the β-scheme of the
//! beam between stops (SPEC §4.4).
//!
//! ```text
//! M (U^{n+1} - 2U^n + U^{n-1})/dt² + K (β U^{n+1} + (1-2β) U^n + β U^{n-1}) = F - λ^n e_c
//! lo <= (u_c^{n+1} + e u_c^{n-1})/(1+e) <= hi       (complementary to λ^n)
//! ```
//!
//! i.e. `u_c^{n+1} ∈ [(1+e) lo - e u_c^{n-1}, (1+e) hi - e u_c^{n-1}]`, one
//! projection per step with the same matrix `A = M + β dt² K` as Newmark(β, ·),
//! `μ = -dt² λ^n`. `U^1` comes from one Newmark(β, 1/2) step (same matrix).
//!
//! Massless contact node: row `c` of `M` vanishes and the papers project
//! `K U^n`, `K U^{n-1}` on the orthogonal of `ker M`; row `c` is then the
//! quasi-static equilibrium at `t_{n+1}`, `(K U^{n+1})_c = F_c - λ_{n+1}`,
//! and the reported force belongs to `t_{n+1}` (`μ = -β dt² λ_{n+1}`).
//!
//! Energy at half steps (for any β; SPEC §4.3 is the case β = 1/4):
//! `E^{n+1/2} = ½ VᵀMV + ½ (β - 1/4) dt² VᵀKV + ½ ŪᵀKŪ - FᵀŪ`,
//! `V = (U^{n+1} - U^n)/dt`, `Ū = (U^n + U^{n+1})/2`.

use crate::onestep::{OneStep, OneStepParams};
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::Projection;
use signorini_fem::BandLdlt;

/// The Paoli–Schatzman scheme.
pub struct PaoliSchatzman {
    label: String,
    beta: f64,
    restitution: f64,
    dt: f64,
    n: usize,
    dy: Dynamics,
    a: BandLdlt,
    proj: Projection,
    u_prev: Vec<f64>,
    u: Vec<f64>,
    rhs: Vec<f64>,
    tmp: Vec<f64>,
    ktmp: Vec<f64>,
}

impl PaoliSchatzman {
    /// Sets up the scheme and takes the start step (one Newmark(β, 1/2)
    /// step, so the returned scheme is at level 1).
    pub fn new(label: String, dy: Dynamics, beta: f64, restitution: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        let mut start = OneStep::new(label.clone(), dy, OneStepParams::newmark(beta, 0.5), dt, init)?;
        let n = start.dynamics().n();
        let u_prev = init.u.clone();
        let first = start.step()?;
        debug_assert_eq!(first.n, 1);
        let u = start.displacement().to_vec();
        let (dy, a, proj, _) = start.into_parts();
        Ok(Self { label, beta, restitution, dt, n: 1, dy, a, proj, u_prev, u, rhs: vec![0.0; n], tmp: vec![0.0; n], ktmp: vec![0.0; n] })
    }

    /// `U^{n-1}`.
    pub fn previous_displacement(&self) -> &[f64] {
        &self.u_prev
    }

    /// The problem.
    pub fn dynamics(&self) -> &Dynamics {
        &self.dy
    }

    /// β.
    pub fn beta(&self) -> f64 {
        self.beta
    }
}

impl Stepper for PaoliSchatzman {
    fn label(&self) -> String {
        self.label.clone()
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn level(&self) -> usize {
        self.n
    }

    fn displacement(&self) -> &[f64] {
        &self.u
    }

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let dt2 = self.dt * self.dt;
        let beta = self.beta;
        let e = self.restitution;
        let c = self.dy.contact_dof;
        // rhs = M (2U^n - U^{n-1}) - dt² K ((1-2β) U^n + β U^{n-1}) + dt² F
        for ((t, u), up) in self.tmp.iter_mut().zip(&self.u).zip(&self.u_prev) {
            *t = 2.0 * u - up;
        }
        self.dy.mass.mul_vec(&self.tmp, &mut self.rhs);
        for ((t, u), up) in self.tmp.iter_mut().zip(&self.u).zip(&self.u_prev) {
            *t = (1.0 - 2.0 * beta) * u + beta * up;
        }
        self.dy.stiffness.mul_vec(&self.tmp, &mut self.ktmp);
        for ((b, f), k) in self.rhs.iter_mut().zip(&self.dy.load).zip(&self.ktmp) {
            *b += dt2 * (f - k);
        }
        if self.dy.massless_contact {
            // Row c projected on the orthogonal of ker M: equilibrium at t_{n+1}.
            self.rhs[c] = beta * dt2 * self.dy.load[c];
        }
        self.a.solve_in_place(&mut self.rhs);
        let up_c = self.u_prev[c];
        let lo = (1.0 + e) * self.dy.bounds.lo - e * up_c;
        let hi = if self.dy.bounds.hi.is_finite() { (1.0 + e) * self.dy.bounds.hi - e * up_c } else { f64::INFINITY };
        let pr = self.proj.project(&mut self.rhs, lo, hi);
        // Rotate: U^{n-1} <- U^n <- U^{n+1}.
        std::mem::swap(&mut self.u_prev, &mut self.u);
        std::mem::swap(&mut self.u, &mut self.rhs);
        self.n += 1;
        let t = self.time();
        let (lambda, t_lambda) = if self.dy.massless_contact {
            (-pr.mu / (beta * dt2), t)
        } else {
            (-pr.mu / dt2, t - self.dt)
        };
        if !(self.u[c].is_finite() && lambda.is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        Ok(StepReport { n: self.n, t, lambda: Some((t_lambda, lambda)), active: pr.active })
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        let dt = self.dt;
        // tmp = V^{n-1/2}, ktmp = Ū^{n-1/2} (scratch between steps).
        for (((v, ub), u), up) in self.tmp.iter_mut().zip(self.ktmp.iter_mut()).zip(&self.u).zip(&self.u_prev) {
            *v = (u - up) / dt;
            *ub = 0.5 * (u + up);
        }
        let kin = self.dy.mass.quad_form(&self.tmp);
        let stiff_v = self.dy.stiffness.quad_form(&self.tmp);
        let pot = self.dy.stiffness.quad_form(&self.ktmp);
        let load: f64 = self.dy.load.iter().zip(&self.ktmp).map(|(f, u)| f * u).sum();
        let e = 0.5 * kin + 0.5 * (self.beta - 0.25) * dt * dt * stiff_v + 0.5 * pot - load;
        Some((self.time() - 0.5 * dt, e))
    }
}
