//! The nonsmooth generalized-α scheme (docs/theory.md §4.6.5; Chen,
//! Acary, Virlez, Brüls, IJNME 96 (2013) 487–511; the constraints at
//! position and velocity level together: Brüls, Acary, Cardona, CMAME 281
//! (2014) 131–161): the smooth motion by the generalized-α scheme of
//! Chung and Hulbert (in Arnold and Brüls's form, with the
//! acceleration-like variable `a`), the impacts at velocity level by
//! Newton's law on the index set, the positions corrected onto the
//! admissible set,
//!
//! ```text
//! M q̈^{n+1} + K U^{n+1} = F(t_{n+1})                    (smooth part, at the corrected U)
//! (1−α_m) a^{n+1} + α_m a^n = (1−α_f) q̈^{n+1} + α_f q̈^n
//! U^{n+1} = U^n + dt V^n + dt²(½−β) a^n + dt² β a^{n+1} + Y,     M Y = Σ_i ν_i e_{c_i}
//! V^{n+1} = V^n + dt(1−γ) a^n + dt γ a^{n+1} + W,                 M W = Σ_i Λ_i e_{c_i}
//! lo_i <= u_{c_i}^{n+1} <= hi_i, ν_i complementary (every contact: the position correction)
//! i in the index set (u_{c_i}^{n+1} <= lo_i):  0 <= v_{c_i}^{n+1} + e_i v_{c_i}^n ⊥ Λ_i >= 0
//! (at an upper stop the mirror image), Λ_i = 0 elsewhere,
//! ```
//!
//! with Chung and Hulbert's coefficients from the spectral radius at
//! infinity ρ∞ ∈ [0, 1]: `α_m = (2ρ∞−1)/(ρ∞+1)`, `α_f = ρ∞/(ρ∞+1)`,
//! `γ = ½ − α_m + α_f`, `β = ¼(1 − α_m + α_f)²` (second order; ρ∞ = 1 is
//! the trapezoidal rule, energy-conserving off contact). `Y` and `W` are
//! the paper's position correction `U_{n+1}` and velocity jump `W_{n+1}`
//! (renamed: `U` is the displacement here).
//!
//! For a linear, undamped system the papers' monolithic problem is
//! triangular and is solved exactly, without Newton iterations: with
//! `c = (1−α_f)/(1−α_m)`, `S = M + c β dt² K` (factorised once) and the
//! free step `U_f` (the generalized-α step without contact), the smooth
//! equation at the corrected positions gives `U^{n+1} = U_f + S⁻¹ Σ ν_i
//! e_{c_i}`, so the position law is the projection of `U_f` with the
//! influence columns of `S` (the closed form for one contact, the exact
//! box solve for several). The correction changes the smooth acceleration,
//! `q̈^{n+1} = q̈_f − (z_M − z_S)/(c β dt²)` with `z_M = M⁻¹ Σ ν_i e_{c_i}`,
//! `z_S = S⁻¹ Σ ν_i e_{c_i}`, hence `a` and the velocity; then Newton's law on
//! the contacts on their bound is the projection of the velocity with the
//! influence columns of `M`. `W` does not enter the positions (no damping).
//! `λ_i = −Λ_i/dt` is reported at `t_{n+1}`. The constraint holds at every
//! level at the position level, the impact law at the velocity level.
//!
//! A time-dependent load enters at `t_{n+1}` (the smooth equation is
//! enforced at the levels). The initial `q̈^0 = a^0 = M⁻¹(F(0) − K U^0)`.
//! Needs a massive contact node (`M⁻¹`) and no damping matrix.

use crate::family::{not_taken, Refused};
use crate::fused::{fused_switches, FusedSwitch};
use crate::lanes::avx2_available;
use crate::loads::{add_terms, Loads};
use crate::multi::MultiSolve;
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::{Active, Projection};
use signorini_fem::BandLdlt;

/// Chung and Hulbert's coefficients `(α_m, α_f, β, γ)` for the spectral
/// radius at infinity `rho_inf` (Chung, Hulbert, J. Appl. Mech. 60 (1993)
/// 371–375; in Arnold and Brüls's convention, as Siconos's
/// `NewMarkAlphaOSI::setParametersFromRho_infty`).
pub fn chung_hulbert(rho_inf: f64) -> (f64, f64, f64, f64) {
    let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
    let alpha_f = rho_inf / (rho_inf + 1.0);
    let gamma = 0.5 - alpha_m + alpha_f;
    let beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
    (alpha_m, alpha_f, beta, gamma)
}

/// The nonsmooth generalized-α scheme.
pub struct Nsga {
    label: String,
    restitution: f64,
    alpha_m: f64,
    alpha_f: f64,
    beta: f64,
    gamma: f64,
    dt: f64,
    n: usize,
    dy: Dynamics,
    /// `S = M + c β dt² K`, factorised.
    s: BandLdlt,
    /// `M`, factorised (the velocity jump and `M⁻¹` of the correction).
    mf: BandLdlt,
    /// One contact: the position projection with `S⁻¹ e_c`, the velocity
    /// projection with `M⁻¹ e_c`, and `M⁻¹ e_c − S⁻¹ e_c`.
    proj_u: Option<Projection>,
    proj_v: Option<Projection>,
    dz: Vec<f64>,
    /// Several contacts: the exact solves with `S` and with `M`.
    multi_u: Option<MultiSolve>,
    multi_v: Option<MultiSolve>,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    qdd: Vec<f64>,
    rhs: Vec<f64>,
    zm: Vec<f64>,
    /// Per contact, `v_c^n` (the impact law's pre-step velocity).
    vc0: Vec<f64>,
    lams: Vec<f64>,
    acts: Vec<Active>,
    /// The free step fused into `S`'s sweeps ([`Tridiagonal`]) where `K`
    /// and `S` are tridiagonal, and its switches (tests, benchmarks).
    fused: FusedSwitch<Tridiagonal>,
    /// Per forcing term, its values at the levels; the latest (`t_n`).
    loads: Loads,
    svals: Vec<f64>,
}

impl Nsga {
    /// Sets up the scheme (ρ∞ ∈ [0, 1], e ∈ [0, 1]; a massive contact
    /// node; no damping matrix).
    pub fn new(label: String, dy: Dynamics, rho_inf: f64, restitution: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        crate::family::check("rho_inf", rho_inf, (0.0..=1.0).contains(&rho_inf), "[0, 1]")?;
        crate::family::check("e", restitution, (0.0..=1.0).contains(&restitution), "[0, 1]")?;
        if dy.massless_contact() {
            return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped): the impact law acts on its velocity" });
        }
        if dy.damping.is_some() {
            return Err(not_taken(label, Refused::Damping, " (the monolithic step is triangular only without damping: C W would couple the velocity jump to the positions)"));
        }
        let n = dy.n();
        crate::check_start(dt, n, init)?;
        let (alpha_m, alpha_f, beta, gamma) = chung_hulbert(rho_inf);
        let c = (1.0 - alpha_f) / (1.0 - alpha_m);
        let s_mat = dy.step_matrix(0.0, c * beta * dt * dt);
        let s = s_mat.factor()?;
        let mf = dy.massive_factor()?;
        let k = dy.k();
        let column = |f: &BandLdlt, dof: usize| {
            let mut w = vec![0.0; n];
            w[dof] = 1.0;
            f.solve_in_place(&mut w);
            w
        };
        let (mut proj_u, mut proj_v, mut dz, mut multi_u, mut multi_v) = (None, None, Vec::new(), None, None);
        if k == 1 {
            let dof = dy.contact().dof;
            let (ws, wm) = (column(&s, dof), column(&mf, dof));
            dz = wm.iter().zip(&ws).map(|(m, s)| m - s).collect();
            proj_u = Some(Projection::new(dof, ws)?);
            proj_v = Some(Projection::new(dof, wm)?);
        } else {
            multi_u = Some(MultiSolve::new(&dy, &s)?.with_banded(s_mat)?);
            multi_v = Some(MultiSolve::new(&dy, &mf)?.with_banded(dy.mass.clone())?);
        }
        let mut loads = Loads::values(&dy, dt);
        let mut svals = vec![0.0; dy.forcing.len()];
        loads.next_into(&mut svals);
        let fused = FusedSwitch::new(Tridiagonal::new(&dy, &s));
        let mut me = Self {
            label,
            restitution,
            alpha_m,
            alpha_f,
            beta,
            gamma,
            dt,
            n: 0,
            s,
            mf,
            proj_u,
            proj_v,
            dz,
            multi_u,
            multi_v,
            u: init.u.clone(),
            v: init.v.clone(),
            a: vec![0.0; n],
            qdd: vec![0.0; n],
            rhs: vec![0.0; n],
            zm: vec![0.0; n],
            vc0: vec![0.0; k],
            lams: vec![0.0; k],
            acts: vec![Active::None; k],
            fused,
            loads,
            svals,
            dy,
        };
        me.consistent_acceleration();
        me.a.copy_from_slice(&me.qdd);
        Ok(me)
    }

    /// `q̈ = M⁻¹(F(t_n) − K U)` (the smooth equation at the current level).
    fn consistent_acceleration(&mut self) {
        self.dy.stiffness.mul_vec(&self.u, &mut self.qdd);
        for (x, f) in self.qdd.iter_mut().zip(&self.dy.load) {
            *x = f - *x;
        }
        add_terms(&mut self.qdd, &self.dy.forcing, 1.0, &self.svals);
        self.mf.solve_in_place(&mut self.qdd);
    }

    /// Velocity `V^n`.
    pub fn velocity(&self) -> &[f64] {
        &self.v
    }

    /// The acceleration-like variable `a^n`.
    pub fn acceleration_like(&self) -> &[f64] {
        &self.a
    }

    /// The coefficients `(α_m, α_f, β, γ)` in use.
    pub fn coefficients(&self) -> (f64, f64, f64, f64) {
        (self.alpha_m, self.alpha_f, self.beta, self.gamma)
    }

    /// What [`NsgaLockstep`](crate::NsgaLockstep) takes of a single run
    /// (one contact, after [`new`](Self::new)): the factor of `S`, the
    /// position and velocity projections (`S⁻¹ e_c`, `M⁻¹ e_c`),
    /// `M⁻¹ e_c − S⁻¹ e_c`, and `a^0`, `q̈^0`; `None` with several contacts.
    pub(crate) fn lockstep_parts(&self) -> Option<NsgaParts<'_>> {
        let (proj_u, proj_v) = (self.proj_u.as_ref()?, self.proj_v.as_ref()?);
        Some(NsgaParts { s: &self.s, proj_u, proj_v, dz: &self.dz, a: &self.a, qdd: &self.qdd })
    }

    /// The free generalized-α step: `U, V, a, q̈` become the step's values
    /// without contact (fused into `S`'s sweeps by [`Tridiagonal`] for a
    /// tridiagonal `K` and `S`, the same bits).
    fn free_step(&mut self) {
        self.loads.next_into(&mut self.svals);
        let p = Predictor::new(self);
        if let Some(tri) = self.fused.active() {
            let (l, inv_d) = self.s.tridiagonal_factors().expect("tridiagonal");
            let st = Sweep { u: &mut self.u, v: &mut self.v, a: &mut self.a, q: &mut self.qdd };
            tri.step(&p, st, &self.dy.load, &self.dy.forcing, &self.svals, l, inv_d);
            return;
        }
        for (((u, v), a), q) in self.u.iter_mut().zip(self.v.iter_mut()).zip(self.a.iter_mut()).zip(&self.qdd) {
            p.apply(u, v, a, *q);
        }
        // S q̈ = F(t_{n+1}) − K Û.
        self.dy.stiffness.mul_vec(&self.u, &mut self.rhs);
        for (x, f) in self.rhs.iter_mut().zip(&self.dy.load) {
            *x = f - *x;
        }
        add_terms(&mut self.rhs, &self.dy.forcing, 1.0, &self.svals);
        self.s.solve_in_place(&mut self.rhs);
        std::mem::swap(&mut self.qdd, &mut self.rhs);
        for (((u, v), a), q) in self.u.iter_mut().zip(self.v.iter_mut()).zip(self.a.iter_mut()).zip(&self.qdd) {
            p.update(u, v, a, *q);
        }
    }

    fused_switches!(fused);

    /// The position correction's effect on the smooth part: `q̈ −= d/(c β dt²)`,
    /// `a −= d/(β dt²)`, `V −= γ d/(β dt)`, `d = z_M − z_S`, scaled by `s`.
    fn correct_smooth(v: &mut [f64], a: &mut [f64], qdd: &mut [f64], d: &[f64], s: f64, coefs: (f64, f64, f64, f64)) {
        let (h, b, g, c) = coefs;
        let (kq, ka, kv) = (s / (c * b * h * h), s / (b * h * h), s * g / (b * h));
        for (((v, a), q), d) in v.iter_mut().zip(a.iter_mut()).zip(qdd.iter_mut()).zip(d) {
            *q -= kq * d;
            *a -= ka * d;
            *v -= kv * d;
        }
    }
}

/// A single run's parts the lockstep engine shares ([`Nsga::lockstep_parts`]).
pub(crate) struct NsgaParts<'a> {
    pub(crate) s: &'a BandLdlt,
    pub(crate) proj_u: &'a Projection,
    pub(crate) proj_v: &'a Projection,
    pub(crate) dz: &'a [f64],
    pub(crate) a: &'a [f64],
    pub(crate) qdd: &'a [f64],
}

/// The generalized-α predictor and update of one entry: `â = (α_f q̈ −
/// α_m a)/(1 − α_m)`, `Û = U + dt V + dt²((½−β) a + β â)`, `V̂ = V +
/// dt((1−γ) a + γ â)`; after the solve, `U += c β dt² q̈`, `V += c γ dt q̈`,
/// `a = â + c q̈`.
/// (The lockstep engine's rows use the same coefficients.)
#[derive(Clone, Copy)]
pub(crate) struct Predictor {
    pub(crate) af: f64,
    pub(crate) am: f64,
    pub(crate) inv: f64,
    pub(crate) h: f64,
    pub(crate) hh_a: f64,
    pub(crate) hh_b: f64,
    pub(crate) h_a: f64,
    pub(crate) h_g: f64,
    pub(crate) cu: f64,
    pub(crate) cv: f64,
    pub(crate) c: f64,
}

impl Predictor {
    fn new(s: &Nsga) -> Self {
        Self::of(s.dt, s.alpha_m, s.alpha_f, s.beta, s.gamma)
    }

    /// The coefficients for the step `h` and `α_m, α_f, β, γ`.
    pub(crate) fn of(h: f64, am: f64, af: f64, b: f64, g: f64) -> Self {
        let c = (1.0 - af) / (1.0 - am);
        Self { af, am, inv: 1.0 / (1.0 - am), h, hh_a: h * h * (0.5 - b), hh_b: h * h * b, h_a: h * (1.0 - g), h_g: h * g, cu: c * b * h * h, cv: c * g * h, c }
    }

    #[inline(always)]
    fn apply(&self, u: &mut f64, v: &mut f64, a: &mut f64, q: f64) {
        let ah = (self.af * q - self.am * *a) * self.inv;
        *u += self.h * *v + self.hh_a * *a + self.hh_b * ah;
        *v += self.h_a * *a + self.h_g * ah;
        *a = ah;
    }

    #[inline(always)]
    fn update(&self, u: &mut f64, v: &mut f64, a: &mut f64, q: f64) {
        *u += self.cu * q;
        *v += self.cv * q;
        *a += self.c * q;
    }
}

/// The state a free step updates: `U, V, a` and `q̈` (in: `q̈ⁿ`; out: `q̈ⁿ⁺¹`).
struct Sweep<'a> {
    u: &'a mut [f64],
    v: &'a mut [f64],
    a: &'a mut [f64],
    q: &'a mut [f64],
}

/// `K` and `S`'s factor tridiagonal (the P1 bar; no damping, as always
/// here): the free step in two passes over the rows, in chunks of
/// [`CHUNK`] rows. Forward: a chunk's predictor (one row ahead, for
/// `K Û`'s upper neighbour), its right-hand sides `F − K Û + Σ s_j g_j`,
/// both vectorised across the chunk's rows (AVX2 chosen at run time, no
/// FMA) and independent of the forward sweep's chain through the chunk
/// before, so the two overlap; then the chain through the chunk. Backward:
/// the chain through a chunk, then the chunk's updates of `U, V, a`,
/// vectorised, overlapping the chain through the next chunk. Every value is
/// the plain step's operations in the same order ([`Predictor`]'s, the
/// rows of `SymBand::mul_vec` for a tridiagonal matrix, `F − ·`,
/// `add_terms` term by term, `BandLdlt::solve_in_place`'s two sweeps), so
/// the same bits (cost: `crates/run/benches/step.rs`,
/// `implicit_scheme_step`).
struct Tridiagonal {
    /// `K`'s diagonal and sub-diagonal (`k_s[i] = K[i][i−1]`, `k_s[0] = 0`).
    k_d: Vec<f64>,
    k_s: Vec<f64>,
    avx2: bool,
}

/// Rows per chunk of [`Tridiagonal`]'s passes.
const CHUNK: usize = 32;

impl Tridiagonal {
    fn new(dy: &Dynamics, s: &BandLdlt) -> Option<Self> {
        let applies = dy.n() >= 2 && dy.stiffness.half_bandwidth() == 1 && s.tridiagonal_factors().is_some();
        let avx2 = avx2_available();
        applies.then(|| Self { k_d: dy.stiffness.diagonal(0), k_s: dy.stiffness.diagonal(1), avx2 })
    }

    /// The free step: predictor, `S q̈ = F − K Û + Σ s_j g_j`, update.
    #[allow(clippy::too_many_arguments)]
    fn step(&self, p: &Predictor, st: Sweep<'_>, f: &[f64], forcing: &[crate::Forcing], s: &[f64], l: &[f64], inv_d: &[f64]) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only when the CPU reports AVX2.
            return unsafe { self.step_avx2(p, st, f, forcing, s, l, inv_d) };
        }
        self.step_body(p, st, f, forcing, s, l, inv_d)
    }

    /// [`step_body`](Self::step_body) compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    unsafe fn step_avx2(&self, p: &Predictor, st: Sweep<'_>, f: &[f64], forcing: &[crate::Forcing], s: &[f64], l: &[f64], inv_d: &[f64]) {
        self.step_body(p, st, f, forcing, s, l, inv_d)
    }

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn step_body(&self, p: &Predictor, st: Sweep<'_>, f: &[f64], forcing: &[crate::Forcing], s: &[f64], l: &[f64], inv_d: &[f64]) {
        let n = st.u.len();
        let (u, v, a, q) = (&mut st.u[..n], &mut st.v[..n], &mut st.a[..n], &mut st.q[..n]);
        let (kd, ks, f, l, inv_d) = (&self.k_d[..n], &self.k_s[..n], &f[..n], &l[..n], &inv_d[..n]);
        // The predictor on entries [lo, hi) (functions, not closures: a
        // closure is compiled apart, for the baseline target, and was not
        // inlined into the AVX2 build).
        #[inline(always)]
        fn predict(p: &Predictor, u: &mut [f64], v: &mut [f64], a: &mut [f64], q: &[f64], lo: usize, hi: usize) {
            for (((u, v), a), q) in u[lo..hi].iter_mut().zip(&mut v[lo..hi]).zip(&mut a[lo..hi]).zip(&q[lo..hi]) {
                p.apply(u, v, a, *q);
            }
        }
        // + Σ_j s_j g_j on rows [lo, hi), term by term.
        #[inline(always)]
        fn terms(forcing: &[crate::Forcing], s: &[f64], q: &mut [f64], lo: usize, hi: usize) {
            for (fc, &sj) in forcing.iter().zip(s) {
                for (b, g) in q[lo..hi].iter_mut().zip(&fc.shape[lo..hi]) {
                    *b += sj * g;
                }
            }
        }
        // Row 0 (`mul_vec`'s first row), its predictor and its neighbour's first.
        predict(p, u, v, a, q, 0, 2);
        q[0] = f[0] - (kd[0] * u[0] + ks[1] * u[1]);
        terms(forcing, s, q, 0, 1);
        let mut prev = q[0];
        let mut lo = 1;
        while lo < n {
            let hi = (lo + CHUNK).min(n);
            // The predictor one row ahead; the interior rows branch-free, the last apart.
            predict(p, u, v, a, q, lo + 1, (hi + 1).min(n));
            let stop = hi.min(n - 1);
            if stop > lo {
                let r = lo..stop;
                let (ul, uc, ur) = (&u[lo - 1..stop - 1], &u[r.clone()], &u[lo + 1..stop + 1]);
                let (ksl, kdc, ksr) = (&ks[r.clone()], &kd[r.clone()], &ks[lo + 1..stop + 1]);
                let (fr, o) = (&f[r.clone()], &mut q[r]);
                for j in 0..o.len() {
                    o[j] = fr[j] - (ksl[j] * ul[j] + kdc[j] * uc[j] + ksr[j] * ur[j]);
                }
            }
            if hi == n {
                q[n - 1] = f[n - 1] - (ks[n - 1] * u[n - 2] + kd[n - 1] * u[n - 1]);
            }
            terms(forcing, s, q, lo, hi);
            for (b, li) in q[lo..hi].iter_mut().zip(&l[lo..hi]) {
                prev = *b - li * prev;
                *b = prev;
            }
            lo = hi;
        }
        // The backward sweep, a chunk at a time, each chunk's updates after its chain.
        let last = n - 1;
        let mut next = q[last] * inv_d[last];
        q[last] = next;
        p.update(&mut u[last], &mut v[last], &mut a[last], next);
        let mut hi = last;
        while hi > 0 {
            let lo = hi.saturating_sub(CHUNK);
            for i in (lo..hi).rev() {
                next = q[i] * inv_d[i] - l[i + 1] * next;
                q[i] = next;
            }
            for (((u, v), a), q) in u[lo..hi].iter_mut().zip(&mut v[lo..hi]).zip(&mut a[lo..hi]).zip(&q[lo..hi]) {
                p.update(u, v, a, *q);
            }
            hi = lo;
        }
    }
}

impl Stepper for Nsga {
    stepper_accessors!();

    fn state(&self) -> Option<Vec<f64>> {
        Some(self.u.iter().chain(&self.v).chain(&self.a).copied().collect())
    }

    /// `U^n, V^n, a^n`; `q̈^n` is recomputed from `U^n` (the smooth
    /// equation at the level).
    fn set_state(&mut self, s: &[f64]) -> Result<(), SchemeError> {
        let n = self.u.len();
        crate::check_state_len(s, 3 * n)?;
        self.u.copy_from_slice(&s[..n]);
        self.v.copy_from_slice(&s[n..2 * n]);
        self.a.copy_from_slice(&s[2 * n..]);
        self.consistent_acceleration();
        Ok(())
    }

    fn contact_pivots(&self) -> Option<(u64, u64)> {
        match (&self.multi_u, &self.multi_v) {
            (Some(p), Some(q)) => Some((p.pivoting_solves + q.pivoting_solves, p.pivots + q.pivots)),
            _ => None,
        }
    }

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let (h, af, am) = (self.dt, self.alpha_f, self.alpha_m);
        let coefs = (h, self.beta, self.gamma, (1.0 - af) / (1.0 - am));
        for (v0, ct) in self.vc0.iter_mut().zip(&self.dy.contacts) {
            *v0 = self.v[ct.dof];
        }
        self.free_step();
        if let (Some(pu), Some(pv)) = (&self.proj_u, &self.proj_v) {
            let ct = &self.dy.contacts[0];
            let (lo, hi) = (ct.bounds.lo, ct.bounds.hi);
            let pr = pu.project(&mut self.u, lo, hi);
            if pr.mu != 0.0 {
                Self::correct_smooth(&mut self.v, &mut self.a, &mut self.qdd, &self.dz, pr.mu, coefs);
            }
            let uc = self.u[ct.dof];
            let (at_lo, at_hi) = (uc <= lo, uc >= hi);
            let e = ct.restitution.unwrap_or(self.restitution);
            let target = -e * self.vc0[0];
            let big = if at_lo || at_hi {
                let (vlo, vhi) = (if at_lo { target } else { f64::NEG_INFINITY }, if at_hi && !at_lo { target } else { f64::INFINITY });
                pv.project(&mut self.v, vlo, vhi).mu
            } else {
                0.0
            };
            self.lams[0] = -big / h;
            self.acts[0] = pr.active;
        } else {
            let mu_ok = {
                let ms = self.multi_u.as_mut().expect("several contacts");
                for (i, ct) in self.dy.contacts.iter().enumerate() {
                    ms.lo[i] = ct.bounds.lo;
                    ms.hi[i] = ct.bounds.hi;
                }
                let (mu, st) = ms.solve(&mut self.u)?;
                self.acts.copy_from_slice(st);
                // Σ ν_i e_{c_i}, then z_M − z_S (two solves, only when a contact acted).
                self.rhs.iter_mut().for_each(|x| *x = 0.0);
                let mut any = false;
                for (ct, &m) in self.dy.contacts.iter().zip(mu) {
                    self.rhs[ct.dof] = m;
                    any |= m != 0.0;
                }
                any
            };
            if mu_ok {
                self.zm.copy_from_slice(&self.rhs);
                self.mf.solve_in_place(&mut self.zm);
                self.s.solve_in_place(&mut self.rhs);
                for (z, s) in self.zm.iter_mut().zip(&self.rhs) {
                    *z -= s;
                }
                Self::correct_smooth(&mut self.v, &mut self.a, &mut self.qdd, &self.zm, 1.0, coefs);
            }
            let mv = self.multi_v.as_mut().expect("several contacts");
            for (i, ct) in self.dy.contacts.iter().enumerate() {
                let uc = self.u[ct.dof];
                let (at_lo, at_hi) = (uc <= ct.bounds.lo, uc >= ct.bounds.hi);
                let target = -ct.restitution.unwrap_or(self.restitution) * self.vc0[i];
                mv.lo[i] = if at_lo { target } else { f64::NEG_INFINITY };
                mv.hi[i] = if at_hi && !at_lo { target } else { f64::INFINITY };
            }
            let (big, _) = mv.solve(&mut self.v)?;
            for (l, b) in self.lams.iter_mut().zip(big) {
                *l = -b / h;
            }
        }
        self.n += 1;
        crate::contact_step_report(self.n, self.time(), &self.dy.contacts, &self.u, Some(&self.v), &self.lams, &self.acts)
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        Some((self.time(), self.dy.energy(&self.u, &self.v)))
    }
}

// ---- The registry's row of this file: nsga.

use crate::family::{check, Capabilities, Family, Node, Param, SchemeSpec};

/// The spectral radius at infinity ρ∞.
const RHO_INF: Param = Param { name: "rho_inf", symbol: "ρ∞", syntax: "RHO_INF", allowed: "∈ [0, 1]", default: None };
/// The restitution `e` (default 0).
const E: Param = Param { name: "e", symbol: "e", syntax: "E", allowed: "∈ [0, 1]", default: Some(0.0) };

/// The nonsmooth generalized-α scheme, ρ∞ ∈ [0, 1], e ∈ [0, 1] (default 0).
pub(crate) static NSGA: Family = Family {
    name: "nsga",
    about: "nonsmooth generalized-α (Chen–Acary–Virlez–Brüls 2013, Brüls–Acary–Cardona 2014): generalized-α smooth part with spectral radius ρ∞ at infinity, Newton's impact law at velocity level on the index set, positions corrected onto the bounds (docs/theory.md §4.6.5)",
    params: &[RHO_INF, E],
    presets: &[],
    validate: |a| {
        check("rho_inf", a[0], (0.0..=1.0).contains(&a[0]), "[0, 1]")?;
        check("e", a[1], (0.0..=1.0).contains(&a[1]), "[0, 1]")
    },
    capabilities: |_| Capabilities { node: Node::Massive, damping: false, restitution: true, lockstep: true, ..Capabilities::IMPLICIT },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(Nsga::new(s.to_string(), dy, s.args()[0], s.args()[1], dt, init)?)),
};

impl SchemeSpec {
    /// The nonsmooth generalized-α scheme with ρ∞ and restitution `e`
    /// (not validated until built).
    pub fn nsga(rho_inf: f64, restitution: f64) -> Self {
        NSGA.with(&[rho_inf, restitution])
    }
}
