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

/// A tridiagonal right-hand side made row by row, for [`tridiagonal_forward`]:
/// each scheme's own arithmetic for its rows (the plain step's operations
/// in its order), so that the fused pass gives the plain path's bits.
pub(crate) trait TriRows {
    /// Rows `a..a + out.len()` (all interior: `1 <= a`, `a + out.len() <= n − 1`),
    /// branch-free so that the compiler vectorises them across rows.
    fn interior(&self, a: usize, out: &mut [f64]);
    /// The first (`i = 0`) or the last (`i = n − 1`) row.
    fn edge(&self, i: usize) -> f64;
}

/// The P1 bar's fused forward pass, shared by the implicit schemes' fused
/// steps on a tridiagonal step matrix (this file's [`Tridiagonal`],
/// `paoli.rs`, `moreau.rs`, `nitsche.rs`, `hybrid.rs`): `out = L⁻¹ b` with
/// `b` the rows of `rows`, then `Σ_w Σ_j w_j g_j` (each list of `weights`
/// in turn, term by term: `add_terms`' arithmetic), then the rows of `set`
/// overwritten (`(row, value)`), in chunks of [`CHUNK`] rows: a chunk's
/// rows (vectorised across the chunk — AVX2 chosen at run time by the
/// caller, no FMA) are independent of the sweep through the chunk before,
/// so the two overlap. The forward sweep is `BandLdlt::solve_in_place`'s
/// (`y_i = b_i − l_i y_{i−1}`); the caller runs the backward one
/// (`BandLdlt::backward_in_place`). Needs `n = out.len() >= 2`.
#[inline(always)]
pub(crate) fn tridiagonal_forward<R: TriRows>(rows: &R, forcing: &[crate::Forcing], weights: &[&[f64]], set: &[(usize, f64)], l: &[f64], out: &mut [f64]) {
    let n = out.len();
    let l = &l[..n];
    let terms = |out: &mut [f64], a: usize, len: usize| {
        for w in weights {
            for (fc, &wj) in forcing.iter().zip(*w) {
                for (b, g) in out[a..a + len].iter_mut().zip(&fc.shape[a..a + len]) {
                    *b += wj * g;
                }
            }
        }
        for &(c, v) in set {
            if (a..a + len).contains(&c) {
                out[c] = v;
            }
        }
    };
    out[0] = rows.edge(0);
    terms(out, 0, 1);
    let mut prev = out[0];
    let mut a = 1;
    while a < n {
        // Interior rows of the chunk branch-free (vectorised), the last row apart.
        let end = (a + CHUNK).min(n);
        let stop = end.min(n - 1);
        if stop > a {
            rows.interior(a, &mut out[a..stop]);
        }
        if end == n {
            out[n - 1] = rows.edge(n - 1);
        }
        terms(out, a, end - a);
        for (b, li) in out[a..end].iter_mut().zip(&l[a..end]) {
            prev = *b - li * prev;
            *b = prev;
        }
        a = end;
    }
}

/// [`tridiagonal_forward`], compiled with AVX2 where `avx2` says the CPU
/// has it, else for the baseline target.
#[inline]
pub(crate) fn tridiagonal_forward_dispatch<R: TriRows>(avx2: bool, rows: &R, forcing: &[crate::Forcing], weights: &[&[f64]], set: &[(usize, f64)], l: &[f64], out: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: callers set `avx2` only when the CPU reports AVX2.
        return unsafe { tridiagonal_forward_avx2(rows, forcing, weights, set, l, out) };
    }
    let _ = avx2;
    tridiagonal_forward(rows, forcing, weights, set, l, out)
}

/// [`tridiagonal_forward`] compiled with AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn tridiagonal_forward_avx2<R: TriRows>(rows: &R, forcing: &[crate::Forcing], weights: &[&[f64]], set: &[(usize, f64)], l: &[f64], out: &mut [f64]) {
    tridiagonal_forward(rows, forcing, weights, set, l, out)
}

/// A P1 bar's matrix by its two diagonals (`d[i] = A_ii`, `s[i] = A_{i,i−1}`,
/// `s[0]` unused), for the fused steps' rows: `SymBand::mul_vec`'s
/// tridiagonal rows, `s_i x_{i−1} + d_i x_i + s_{i+1} x_{i+1}` in that
/// order (the first row `d_0 x_0 + s_1 x_1`, the last `s_{n−1} x_{n−2} + d_{n−1} x_{n−1}`).
pub(crate) struct TriMatrix {
    pub(crate) d: Vec<f64>,
    pub(crate) s: Vec<f64>,
}

impl TriMatrix {
    /// `a`'s diagonals, if it is tridiagonal.
    pub(crate) fn of(a: &signorini_fem::SymBand) -> Option<Self> {
        (a.half_bandwidth() == 1).then(|| Self { d: a.diagonal(0), s: a.diagonal(1) })
    }

    /// Row `i` of `A x`, `x` given by its values (`x(j)`), any row of `n`.
    #[inline(always)]
    pub(crate) fn row(&self, n: usize, i: usize, x: impl Fn(usize) -> f64) -> f64 {
        let (d, s) = (&self.d, &self.s);
        if i == 0 {
            d[0] * x(0) + s[1] * x(1)
        } else if i == n - 1 {
            s[n - 1] * x(n - 2) + d[n - 1] * x(n - 1)
        } else {
            s[i] * x(i - 1) + d[i] * x(i) + s[i + 1] * x(i + 1)
        }
    }

    /// The coefficients of interior rows `a..a + len`: `(s_i, d_i, s_{i+1})`.
    #[inline(always)]
    pub(crate) fn window(&self, a: usize, len: usize) -> (&[f64], &[f64], &[f64]) {
        (&self.s[a..a + len], &self.d[a..a + len], &self.s[a + 1..a + 1 + len])
    }
}

/// Rows `a − 1`, `a` and `a + 1` onwards of `x`, `len` each: the left,
/// centre and right neighbours a tridiagonal product reads for its rows
/// `a..a + len` (the fused steps' [`TriRows::interior`]).
#[inline(always)]
pub(crate) fn neighbours(x: &[f64], a: usize, len: usize) -> (&[f64], &[f64], &[f64]) {
    (&x[a - 1..a - 1 + len], &x[a..a + len], &x[a + 1..a + 1 + len])
}

/// `M`, `K` and the step matrix's factor tridiagonal (the P1 bar), no
/// damping: the right-hand side `M U_pred − τ²/4 K Uⁿ + τ²/4 (2F + …)` and
/// the forward sweep of the solve in one pass ([`tridiagonal_forward`]),
/// then the solve's backward sweep. Every value is the plain step's
/// operations in the same order (`SymBand::mul_vec`'s tridiagonal rows,
/// the sum, `add_terms` term by term, `BandLdlt::solve_in_place`'s forward
/// sweep), so the same bits (cost: `crates/run/benches/step.rs`,
/// `implicit_scheme_step`).
type Tridiagonal = TriPair;

/// The two tridiagonal matrices a fused P1-bar step reads (`M` and `K`;
/// `nitsche-cn`'s `M` and `K_N`; the reduced schemes' `M*` and `K'`) and
/// whether its kernel runs the AVX2 build ([`tridiagonal_forward_dispatch`]).
pub(crate) struct TriPair {
    pub(crate) m: TriMatrix,
    pub(crate) k: TriMatrix,
    pub(crate) avx2: bool,
}

impl TriPair {
    /// `m` and `k` for a step of at least 2 dofs whose factor `a` is
    /// tridiagonal with a non-zero `L` (a diagonal factor, the lumped mass
    /// with β = 0, solves faster by its own path); `None` otherwise.
    pub(crate) fn beside(m: &signorini_fem::SymBand, k: &signorini_fem::SymBand, a: &BandLdlt) -> Option<Self> {
        let (l, _) = a.tridiagonal_factors()?;
        (m.n() >= 2 && l.iter().any(|x| *x != 0.0)).then_some(())?;
        Some(Self { m: TriMatrix::of(m)?, k: TriMatrix::of(k)?, avx2: avx2_available() })
    }
}

/// Rows per chunk of [`tridiagonal_forward`]'s fused pass.
pub(crate) const CHUNK: usize = 32;

/// [`Tridiagonal`]'s rows for one step: `M p + q (2f − K u)`.
struct StabilizedRows<'a> {
    t: &'a Tridiagonal,
    q: f64,
    p: &'a [f64],
    u: &'a [f64],
    f: &'a [f64],
}

impl TriRows for StabilizedRows<'_> {
    #[inline(always)]
    fn interior(&self, a: usize, o: &mut [f64]) {
        let len = o.len();
        let (p, u, q) = (self.p, self.u, self.q);
        let (pl, pc, pr) = neighbours(p, a, len);
        let (ul, uc, ur) = neighbours(u, a, len);
        let (msl, mdc, msr) = self.t.m.window(a, len);
        let (ksl, kdc, ksr) = self.t.k.window(a, len);
        let fr = &self.f[a..a + len];
        for j in 0..len {
            let mp = msl[j] * pl[j] + mdc[j] * pc[j] + msr[j] * pr[j];
            let ku = ksl[j] * ul[j] + kdc[j] * uc[j] + ksr[j] * ur[j];
            o[j] = mp + q * (2.0 * fr[j] - ku);
        }
    }

    #[inline(always)]
    fn edge(&self, i: usize) -> f64 {
        let n = self.p.len();
        let mp = self.t.m.row(n, i, |j| self.p[j]);
        let ku = self.t.k.row(n, i, |j| self.u[j]);
        mp + self.q * (2.0 * self.f[i] - ku)
    }
}

/// [`Tridiagonal`] of an undamped `dy` (`M`, `K`) beside a tridiagonal
/// factor `a` (a diagonal one too: this scheme's step matrix is never the
/// lumped mass alone).
fn fused_step(dy: &Dynamics, a: &BandLdlt) -> Option<Tridiagonal> {
    (dy.n() >= 2 && dy.damping.is_none() && a.tridiagonal_factors().is_some()).then_some(())?;
    Some(TriPair { m: TriMatrix::of(&dy.mass)?, k: TriMatrix::of(&dy.stiffness)?, avx2: avx2_available() })
}

impl Tridiagonal {
    /// `out = L⁻¹ b`, `b = M p + q (2f − K u) + Σ_j w_old_j g_j + Σ_j w_new_j g_j`.
    #[allow(clippy::too_many_arguments)]
    fn forward(&self, q: f64, p: &[f64], u: &[f64], f: &[f64], forcing: &[crate::Forcing], w_old: &[f64], w_new: &[f64], l: &[f64], out: &mut [f64]) {
        let n = p.len();
        let rows = StabilizedRows { t: self, q, p: &p[..n], u: &u[..n], f: &f[..n] };
        tridiagonal_forward_dispatch(self.avx2, &rows, forcing, &[w_old, w_new], &[], l, &mut out[..n]);
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
        let fused = FusedSwitch::new(fused_step(&dy, &a));
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
