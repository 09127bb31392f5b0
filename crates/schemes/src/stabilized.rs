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

use crate::fused::{fused_switches, FusedSwitch};
use crate::lanes::avx2_available;
use crate::loads::{add_terms, Loads};
use crate::multi::MultiSolve;
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::{Active, OneDof};
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
    /// The P1 bar's tridiagonal step, fused ([`Tridiagonal`]), if it
    /// applies, and its switches (tests, benchmarks).
    fused: FusedSwitch<Tridiagonal>,
    /// Per forcing term, `τ²/4 s^n` and `τ²/4 s^{n+1}` (`add_terms`' weights).
    w_old: Vec<f64>,
    w_new: Vec<f64>,
}

/// A single run's parts the lockstep engine shares ([`ContactStabilized::lockstep_parts`]).
pub(crate) struct StabilizedParts<'a> {
    pub(crate) a: &'a BandLdlt,
    pub(crate) mass: (OneDof, &'a [f64]),
    pub(crate) step: (OneDof, &'a [f64]),
}

/// `M`, `K` and the step matrix's factor tridiagonal (the P1 bar), no
/// damping: the right-hand side `M U_pred − τ²/4 K Uⁿ + τ²/4 (2F + …)` and
/// the forward sweep of the solve in one pass, in chunks of [`CHUNK`] rows
/// (a chunk's right-hand side, vectorised across its rows — AVX2 chosen at
/// run time, no FMA —, is independent of the sweep through the chunk
/// before, so the two overlap), then the solve's backward sweep. Every
/// value is the plain step's operations in the same order
/// (`SymBand::mul_vec`'s tridiagonal rows, the sum, `add_terms` term by
/// term, `BandLdlt::solve_in_place`'s forward sweep), so the same bits
/// (cost: `crates/run/benches/step.rs`, `implicit_scheme_step`).
struct Tridiagonal {
    m_d: Vec<f64>,
    m_s: Vec<f64>,
    k_d: Vec<f64>,
    k_s: Vec<f64>,
    avx2: bool,
}

/// Rows per chunk of [`Tridiagonal`]'s fused pass.
const CHUNK: usize = 32;

impl Tridiagonal {
    fn new(dy: &Dynamics, a: &BandLdlt) -> Option<Self> {
        let n = dy.n();
        let applies = n >= 2 && dy.damping.is_none() && dy.mass.half_bandwidth() == 1 && dy.stiffness.half_bandwidth() == 1 && a.tridiagonal_factors().is_some();
        let avx2 = avx2_available();
        applies.then(|| Self { m_d: dy.mass.diagonal(0), m_s: dy.mass.diagonal(1), k_d: dy.stiffness.diagonal(0), k_s: dy.stiffness.diagonal(1), avx2 })
    }

    /// `out = L⁻¹ b`, `b = M p + q (2f − K u) + Σ_j w_old_j g_j + Σ_j w_new_j g_j`.
    #[allow(clippy::too_many_arguments)]
    fn forward(&self, q: f64, p: &[f64], u: &[f64], f: &[f64], forcing: &[crate::Forcing], w_old: &[f64], w_new: &[f64], l: &[f64], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only when the CPU reports AVX2.
            return unsafe { self.forward_avx2(q, p, u, f, forcing, w_old, w_new, l, out) };
        }
        self.forward_body(q, p, u, f, forcing, w_old, w_new, l, out)
    }

    /// [`forward_body`](Self::forward_body) compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    unsafe fn forward_avx2(&self, q: f64, p: &[f64], u: &[f64], f: &[f64], forcing: &[crate::Forcing], w_old: &[f64], w_new: &[f64], l: &[f64], out: &mut [f64]) {
        self.forward_body(q, p, u, f, forcing, w_old, w_new, l, out)
    }

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn forward_body(&self, q: f64, p: &[f64], u: &[f64], f: &[f64], forcing: &[crate::Forcing], w_old: &[f64], w_new: &[f64], l: &[f64], out: &mut [f64]) {
        let n = p.len();
        let (md, ms, kd, ks) = (&self.m_d[..n], &self.m_s[..n], &self.k_d[..n], &self.k_s[..n]);
        let (p, u, f, l, out) = (&p[..n], &u[..n], &f[..n], &l[..n], &mut out[..n]);
        // `mul_vec_tridiag`'s rows: the first, the interior, the last.
        let row = |i: usize| -> f64 {
            let (mp, ku) = if i == 0 {
                (md[0] * p[0] + ms[1] * p[1], kd[0] * u[0] + ks[1] * u[1])
            } else if i == n - 1 {
                (ms[n - 1] * p[n - 2] + md[n - 1] * p[n - 1], ks[n - 1] * u[n - 2] + kd[n - 1] * u[n - 1])
            } else {
                (ms[i] * p[i - 1] + md[i] * p[i] + ms[i + 1] * p[i + 1], ks[i] * u[i - 1] + kd[i] * u[i] + ks[i + 1] * u[i + 1])
            };
            mp + q * (2.0 * f[i] - ku)
        };
        let terms = |out: &mut [f64], a: usize, len: usize| {
            for w in [w_old, w_new] {
                for (fc, &wj) in forcing.iter().zip(w) {
                    for (b, g) in out[a..a + len].iter_mut().zip(&fc.shape[a..a + len]) {
                        *b += wj * g;
                    }
                }
            }
        };
        out[0] = row(0);
        terms(out, 0, 1);
        let mut prev = out[0];
        let mut a = 1;
        while a < n {
            // Interior rows of the chunk branch-free (vectorised), the last row apart.
            let end = (a + CHUNK).min(n);
            let stop = end.min(n - 1);
            if stop > a {
                let (o, r) = (&mut out[a..stop], a..stop);
                let (pl, pc, pr) = (&p[a - 1..stop - 1], &p[r.clone()], &p[a + 1..stop + 1]);
                let (ul, uc, ur) = (&u[a - 1..stop - 1], &u[r.clone()], &u[a + 1..stop + 1]);
                let (msl, mdc, msr) = (&ms[r.clone()], &md[r.clone()], &ms[a + 1..stop + 1]);
                let (ksl, kdc, ksr) = (&ks[r.clone()], &kd[r.clone()], &ks[a + 1..stop + 1]);
                let fr = &f[r];
                for j in 0..o.len() {
                    let mp = msl[j] * pl[j] + mdc[j] * pc[j] + msr[j] * pr[j];
                    let ku = ksl[j] * ul[j] + kdc[j] * uc[j] + ksr[j] * ur[j];
                    o[j] = mp + q * (2.0 * fr[j] - ku);
                }
            }
            if end == n {
                out[n - 1] = row(n - 1);
            }
            terms(out, a, end - a);
            for (b, li) in out[a..end].iter_mut().zip(&l[a..end]) {
                prev = *b - li * prev;
                *b = prev;
            }
            a = end;
        }
    }
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
        let fused = FusedSwitch::new(Tridiagonal::new(&dy, &a));
        Ok(Self {
            fused,
            w_old: vec![0.0; dy.forcing.len()],
            w_new: vec![0.0; dy.forcing.len()],
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

    /// What [`ContactStabilizedLockstep`](crate::ContactStabilizedLockstep)
    /// takes of a single run (one rigid contact, after [`new`](Self::new)):
    /// the factor of `A`, and the stabilisation's and the step's contact
    /// solves as scalar arithmetic with their columns `M⁻¹ e_c`, `A⁻¹ e_c`;
    /// `None` with several contacts.
    pub(crate) fn lockstep_parts(&self) -> Option<StabilizedParts<'_>> {
        Some(StabilizedParts { a: &self.a, mass: self.mass_solve.one_dof()?, step: self.step_solve.one_dof()? })
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
        if let Some(tri) = self.fused.active() {
            // The same right-hand side and solve, fused ([`Tridiagonal`]).
            self.loads.next_into(&mut self.s_new);
            for ((wo, wn), (a, b)) in self.w_old.iter_mut().zip(self.w_new.iter_mut()).zip(self.s_old.iter().zip(&self.s_new)) {
                (*wo, *wn) = (q * a, q * b);
            }
            let (l, _) = self.a.tridiagonal_factors().expect("tridiagonal");
            tri.forward(q, &self.pred, &self.u, &self.dy.load, &self.dy.forcing, &self.w_old, &self.w_new, l, &mut self.rhs);
            self.a.backward_in_place(&mut self.rhs);
            return self.finish();
        }
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
        self.finish()
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

impl ContactStabilized {
    fused_switches!(fused);

    /// The rest of a step from `A⁻¹ b` in `rhs`: the contact solve, the
    /// works, `V` and `U`.
    fn finish(&mut self) -> Result<StepReport, SchemeError> {
        let dt = self.dt;
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
    capabilities: |_| Capabilities { node: Node::Massive, lockstep: true, ..Capabilities::IMPLICIT },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(ContactStabilized::new(s.to_string(), dy, dt, init)?)),
};
