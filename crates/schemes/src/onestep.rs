//! One-step schemes in momentum form (docs/theory.md §4.1, §4.2).
//!
//! With `P = M V`, `R = M A` and a contact force `λ^{n+1}` at `t_{n+1}`:
//!
//! ```text
//! (M + a dt² K) U^{n+1} = M U^n + dt P^n + b dt² R^n + a dt² (F - λ^{n+1} e_c)
//! R^{n+1} = F - K U^{n+1} - λ^{n+1} e_c            (R_c := 0 for a massless node)
//! P^{n+1} = P^n + dt ((1-γ) R^n + γ R^{n+1})
//! ```
//!
//! * Newmark(β, γ) (2017 paper eq. (30)): `a = β`, `b = 1/2 - β`.
//! * θ-method (eq. (32)): `a = θ²`, `b = θ(1-θ)`, `γ = θ`.
//!
//! The contact condition `lo <= u_c^{n+1} <= hi` is solved by the closed-form
//! projection with `μ = -a dt² λ^{n+1}`. A massless contact node needs no
//! special case: its row of `M` is zero, so its row of the step is the
//! quasi-static equilibrium `(K U^{n+1})_c = F_c - λ^{n+1}`.
//!
//! Energy `E^n = ½ Pᵀ M⁺ P + ½ Uᵀ K U - Fᵀ U` (`M⁺P` on the massive dofs;
//! `F` the steady load; plus the spring energy with a penalty law).
//!
//! With [`ContactLaw::Penalty`] the contact force is a spring outside
//! `[lo, hi]`, `N(u_c) = κ (lo - u_c)⁺ - κ (u_c - hi)⁺`: `u_c^{n+1} = y_c + a dt² w_c N(u_c^{n+1})`
//! is solved exactly branch by branch (docs/theory.md §3), `λ = -N`. A time-dependent
//! load (the terms of [`crate::Dynamics::forcing`]) enters as its value `F(t_{n+1})`.
//!
//! ## Damping
//!
//! With a damping matrix `C` ([`crate::Dynamics::damping`]) the step solves
//! Newmark's `M A^{n+1} + C V^{n+1} + K U^{n+1} = F^{n+1} - λ^{n+1} e_c` with
//! `U^{n+1} = Ũ + a dt² A^{n+1}`, `V^{n+1} = Ṽ + γ dt A^{n+1}` and the
//! predictors `Ũ = U^n + dt V^n + b dt² A^n`, `Ṽ = V^n + (1-γ) dt A^n`:
//!
//! ```text
//! (M + γ dt C + a dt² K) U^{n+1} = M U^n + dt P^n + b dt² R^n + C (γ dt Ũ - a dt² Ṽ) + a dt² (F - λ^{n+1} e_c)
//! A^{n+1} = (U^{n+1} - Ũ)/(a dt²),   V^{n+1} = Ṽ + γ dt A^{n+1}
//! R^{n+1} = F - K U^{n+1} - C V^{n+1} - λ^{n+1} e_c,   P^{n+1} as above
//! ```
//!
//! (`M Ũ` in its momentum form; the velocity and acceleration vectors are
//! kept besides `P`, `R` because `C` acts on `V`, not on `M V`; they are 0
//! on massless contact dofs, whose rows of `C` must vanish). The contact
//! solve is unchanged (`μ = -a dt² λ`). The damping does the work
//! `D = Σ ½ (C V^n + C V^{n+1})ᵀ (U^{n+1} - U^n)` (trapezoid, like the
//! forcing's), so that for Newmark-CN `ΔE = W_f + W_c - D` exactly: `D =
//! Σ dt V̄ᵀ C V̄ >= 0` with `V̄ = (U^{n+1} - U^n)/dt`. An explicit step
//! (`a = 0`) refuses damping (its step would need a solve with `M + γ dt C`);
//! undamped problems take exactly the arithmetic they took before damping
//! existed (and the fused tridiagonal path, which damped ones do not).

use crate::lanes::avx2_available;
use crate::loads::{add_terms, Loads};
use crate::multi::MultiSolve;
use crate::{ContactLaw, Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::{solve_piecewise_linear, Active, PiecewiseLinear, Projection};
use signorini_fem::BandLdlt;

/// Coefficients of a one-step scheme (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneStepParams {
    /// Weight `a` of the new acceleration in the displacement update (`β`, or `θ²`).
    pub a_new: f64,
    /// Weight `b` of the old acceleration (`1/2 - β`, or `θ(1-θ)`).
    pub a_old: f64,
    /// Weight `γ` of the new acceleration in the velocity update (`γ`, or `θ`).
    pub gamma: f64,
}

impl OneStepParams {
    /// Newmark(β, γ).
    pub fn newmark(beta: f64, gamma: f64) -> Self {
        Self { a_new: beta, a_old: 0.5 - beta, gamma }
    }
    /// θ-method.
    pub fn theta(theta: f64) -> Self {
        Self { a_new: theta * theta, a_old: theta * (1.0 - theta), gamma: theta }
    }
}

/// Newmark / θ-method integrator with exact contact projection.
pub struct OneStep {
    label: String,
    prm: OneStepParams,
    dt: f64,
    n: usize,
    dy: Dynamics,
    a: BandLdlt,
    proj: Projection,
    /// Factor of the mass matrix on the massive dofs (energy, velocity).
    m_massive: BandLdlt,
    u: Vec<f64>,
    mom: Vec<f64>,
    r: Vec<f64>,
    rhs: Vec<f64>,
    ku: Vec<f64>,
    u_c_prev: f64,
    lambda: f64,
    law: ContactLaw,
    /// `F(t_n)` (the steady load when there is no forcing).
    f: Vec<f64>,
    /// `U^n` before the step (kept only with a forcing, for its work).
    u_prev: Vec<f64>,
    work_f: f64,
    work_c: f64,
    /// Work of the damping force so far (see the module docs).
    work_d: f64,
    /// Each forcing term's time profile at t_n (so one evaluation per step)
    /// and at t_{n+1} (filled by the step).
    s_now: Vec<f64>,
    s_next: Vec<f64>,
    /// Per forcing term, its values at `n dt` step after step (a [`Sampler`] each).
    loads: Loads,
    /// With damping: the velocity and acceleration vectors and scratch.
    damp: Option<Damped>,
    /// Diagonals of M and K for the fused tridiagonal path (bar).
    tri: Option<Tridiagonals>,
    /// Per-contact force and status of the last step.
    lams: Vec<f64>,
    acts: Vec<Active>,
    /// The forces of the step before (several contacts: for the work).
    prev_lams: Vec<f64>,
    /// Several contacts: those with a nonzero force after the last step
    /// (capacity k: no allocation while stepping).
    touched: Vec<usize>,
    /// `marked[i]`: contact `i` is in `touched`.
    marked: Vec<bool>,
    /// Several contacts: the exact solve (None with one contact, or for an
    /// explicit step, which needs none), the contact displacements before
    /// the step, the penalty stiffness of each stop.
    multi: Option<MultiSolve>,
    kappas: Vec<f64>,
    /// The caller asks for the energy after every step
    /// ([`Stepper::fuse_energy`]): on the bar's tridiagonal path the step
    /// then ends by assembling and forward-sweeping the next step's
    /// right-hand side in one loop with this level's energy sums.
    fuse_energy: bool,
    /// `rhs` holds the next step's right-hand side, forward-swept (the
    /// step starts with its backward sweep).
    ahead: bool,
    /// The energy sums `(Pᵀ M⁺ P, Uᵀ K U, Fᵀ U)` of the current level,
    /// when the step computed them.
    sums: Option<(f64, f64, f64)>,
}

/// The state a damped step needs besides `P`, `R` (module docs, "Damping").
struct Damped {
    /// `V^n`, `A^n` (zero on massless contact dofs).
    vel: Vec<f64>,
    acc: Vec<f64>,
    /// The predictors `Ũ`, `Ṽ` of the step.
    ut: Vec<f64>,
    vt: Vec<f64>,
    /// `C V^n`, and scratch for `C x`.
    cv: Vec<f64>,
    cx: Vec<f64>,
}

/// `M` and `K` as (diagonal, sub-diagonal) pairs; `sub[i] = A[i][i-1]`.
struct Tridiagonals {
    md: Vec<f64>,
    ms: Vec<f64>,
    kd: Vec<f64>,
    ks: Vec<f64>,
    /// The CPU has AVX2: [`update_forward_energy`] is compiled with it too
    /// (chosen at run time; no FMA, so the same bits).
    avx2: bool,
    /// The step matrix's factor has `L = I` (`A = M` lumped, an explicit
    /// step): the step takes [`diagonal_step_dispatch`] and
    /// [`update_momentum_dispatch`] (the same bits as the sweeps).
    diagonal: bool,
    /// With `diagonal`: the interior rows' `(M_{i,i−1}, M_ii, M_{i,i+1},
    /// 1/D_i)` and `(K_{i,i−1}, K_ii, K_{i,i+1}, ·)` when each is one value
    /// on every interior row (a uniform mesh): those passes' [`Same`]
    /// columns.
    uniform_m: Option<[Same; 4]>,
    uniform_k: Option<[Same; 4]>,
    /// The energy's rows `s+1..n−1` (`s` the massive start; the fused
    /// forward sweep's too): `(L_A, L_M, 1/D_M, K_ii, K_{i,i−1})` — the step
    /// matrix's and the massive block's factors, `K` — as [`Same`] when each
    /// is one value there.
    uniform_energy: Option<[Same; 5]>,
}

/// Rows per block of the fused end of a step ([`update_forward_energy`]):
/// the 12 arrays a block touches (96 bytes a row, 3 kB) stay in the core's L1
/// between the update pass and the forward sweep that reads them again,
/// and a block's update (throughput) can overlap the sweep's chains
/// (latency) of the block before (an explanation consistent with the
/// timings). Measured fastest of 16 to 1024 rows and one block
/// (docs/performance.md).
const FUSED_BLOCK: usize = 32;

/// The contact row's fix after the update pass: `R_c −= λ`,
/// `P_c −= γ dt λ` (or, massless, `R_c = P_c = 0`), the operations of the
/// plain step.
#[derive(Clone, Copy)]
struct ContactFix {
    dof: usize,
    massless: bool,
    lambda: f64,
}

/// The factors the fused end of a step sweeps with: the step matrix's
/// `l_a` (forward sweep) and the massive block's `(l_m, inv_d_m)` from
/// dof `s` (the kinetic energy's forward sweep).
#[derive(Clone, Copy)]
struct FusedFactors<'a> {
    l_a: &'a [f64],
    l_m: &'a [f64],
    inv_d_m: &'a [f64],
    s: usize,
}

/// [`update_forward_energy`], compiled with AVX2 when the CPU has it.
#[allow(clippy::too_many_arguments)]
fn update_forward_energy_dispatch(
    t: &Tridiagonals,
    fa: FusedFactors<'_>,
    fix: ContactFix,
    u: &[f64],
    f: &[f64],
    mom: &mut [f64],
    r: &mut [f64],
    rhs: &mut [f64],
    dt: f64,
    g: f64,
    c: [f64; 3],
) -> (f64, f64, f64) {
    #[cfg(target_arch = "x86_64")]
    if t.avx2 {
        // SAFETY: `avx2` is set only when the CPU reports AVX2.
        return unsafe { update_forward_energy_avx2(t, fa, fix, u, f, mom, r, rhs, dt, g, c) };
    }
    update_forward_energy(t, fa, fix, u, f, mom, r, rhs, dt, g, c)
}

/// [`update_forward_energy`] compiled with AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn update_forward_energy_avx2(
    t: &Tridiagonals,
    fa: FusedFactors<'_>,
    fix: ContactFix,
    u: &[f64],
    f: &[f64],
    mom: &mut [f64],
    r: &mut [f64],
    rhs: &mut [f64],
    dt: f64,
    g: f64,
    c: [f64; 3],
) -> (f64, f64, f64) {
    update_forward_energy(t, fa, fix, u, f, mom, r, rhs, dt, g, c)
}

/// The end of a step on the bar's tridiagonal path when the energy is
/// wanted at every level, in blocks of [`FUSED_BLOCK`] rows: for each
/// block, [`update_rows`] (`R`, `P` and the next step's right-hand side),
/// the contact row's fix if the block holds it (and its `rhs` row again,
/// [`rhs_row`]), then [`ForwardEnergy::rows`] (the next step's forward
/// sweep and this level's energy sums, carried from block to block). A
/// block's rows are updated from `U` alone, so the blocks are independent
/// of each other in the first pass, and each chain of the second runs in
/// row order: the operations of the whole first pass and then the whole
/// second, in their order, so the same bits — with the arrays the two
/// passes share read from L1 the second time (at m = 10 000 they stream
/// from L2 otherwise).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn update_forward_energy(
    t: &Tridiagonals,
    fa: FusedFactors<'_>,
    fix: ContactFix,
    u: &[f64],
    f: &[f64],
    mom: &mut [f64],
    r: &mut [f64],
    rhs: &mut [f64],
    dt: f64,
    g: f64,
    c: [f64; 3],
) -> (f64, f64, f64) {
    let n = u.len();
    let mut fe = ForwardEnergy { prev_a: 0.0, prev: 0.0, kin: 0.0, pot: 0.0, lw: -0.0 };
    let mut lo = 0;
    while lo < n {
        // The first block holds rows 0..=s (s ≤ 1 < FUSED_BLOCK − 1).
        let hi = (lo + FUSED_BLOCK).min(n);
        update_rows(t, u, f, mom, r, rhs, dt, g, c, lo, hi);
        if (lo..hi).contains(&fix.dof) {
            let k = fix.dof;
            if fix.massless {
                r[k] = 0.0;
                mom[k] = 0.0;
            } else {
                r[k] -= fix.lambda;
                mom[k] -= dt * g * fix.lambda;
            }
            rhs[k] = rhs_row(&t.md, &t.ms, u, mom, r, f, c, k);
        }
        let from = if lo == 0 {
            fe.head(fa, rhs, mom, &t.kd, &t.ks, u, f);
            fa.s + 1
        } else {
            lo
        };
        fe.rows(fa, t.uniform_energy, rhs, mom, &t.kd, &t.ks, u, f, from, hi);
        lo = hi;
    }
    (fe.kin, fe.pot, fe.lw)
}

/// Second pass of the fused end of a step, carried from block to block:
/// the forward sweep of the step matrix's factor `l_a` on `b` in place (as
/// [`forward_backward_fused`] does it, the last row included, unscaled;
/// running value `prev_a`) and, in the same loop, the energy sums
/// `(Pᵀ M⁺ P, Uᵀ K U, Fᵀ U)` of [`energy_sums_tri`] (the kinetic form's
/// forward sweep with the massive block's factor from dof `s`, `prev`,
/// `kin`; the potential's with `K`'s diagonal and sub-diagonal, `pot`; the
/// load's dot product from `-0.0`, `lw`): independent ordered chains side
/// by side, each with its own operations in its own order, so the same
/// bits as the separate loops.
struct ForwardEnergy {
    prev_a: f64,
    prev: f64,
    kin: f64,
    pot: f64,
    lw: f64,
}

impl ForwardEnergy {
    /// Rows `0..=s` (before the rows the two forward sweeps share).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn head(&mut self, fa: FusedFactors<'_>, b: &mut [f64], p: &[f64], kd: &[f64], ks: &[f64], u: &[f64], load: &[f64]) {
        let s = fa.s;
        let (mut pot, mut lw) = (0.0, -0.0);
        for i in 0..=s {
            let off = if i == 0 { 0.0 } else { 0.0 + ks[i] * u[i - 1] };
            pot += u[i] * (kd[i] * u[i] + 2.0 * off);
            lw += load[i] * u[i];
        }
        let mut prev_a = b[0];
        for i in 1..=s {
            prev_a = b[i] - fa.l_a[i] * prev_a;
            b[i] = prev_a;
        }
        let prev = p[s];
        *self = ForwardEnergy { prev_a, prev, kin: prev * prev * fa.inv_d_m[0], pot, lw };
    }

    /// Rows `lo..hi` (`lo > s`): those before `n − 1` from the columns
    /// (`cols`, a uniform mesh's coefficients as scalars: the same values,
    /// the same bits; else the slices), row `n − 1` from the slices.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn rows(&mut self, fa: FusedFactors<'_>, cols: Option<[Same; 5]>, b: &mut [f64], p: &[f64], kd: &[f64], ks: &[f64], u: &[f64], load: &[f64], lo: usize, hi: usize) {
        let (n, s) = (u.len(), fa.s);
        let mid = hi.min(n - 1);
        if lo < mid {
            match cols {
                Some(c) => self.rows_from(c, b, p, u, load, s, lo, mid),
                None => {
                    let c = [&fa.l_a[s + 1..n - 1], &fa.l_m[1..n - 1 - s], &fa.inv_d_m[1..n - 1 - s], &kd[s + 1..n - 1], &ks[s + 1..n - 1]];
                    self.rows_from(c, b, p, u, load, s, lo, mid)
                }
            }
        }
        if hi == n && lo < n {
            let i = n - 1;
            let ForwardEnergy { mut prev_a, mut prev, mut kin, mut pot, mut lw } = *self;
            prev_a = b[i] - fa.l_a[i] * prev_a;
            b[i] = prev_a;
            prev = p[i] - fa.l_m[i - s] * prev;
            kin += prev * prev * fa.inv_d_m[i - s];
            let off = 0.0 + ks[i] * u[i - 1];
            pot += u[i] * (kd[i] * u[i] + 2.0 * off);
            lw += load[i] * u[i];
            *self = ForwardEnergy { prev_a, prev, kin, pot, lw };
        }
    }

    /// Rows `lo..hi` (`s < lo < hi <= n − 1`), coefficients `(L_A, L_M,
    /// 1/D_M, K_ii, K_{i,i−1})` as slices or [`Same`] (row `i` at
    /// `i − s − 1`).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn rows_from<C: Col>(&mut self, cols: [C; 5], b: &mut [f64], p: &[f64], u: &[f64], load: &[f64], s: usize, lo: usize, hi: usize) {
        let [lac, lmc, ldc, kdc, ksc] = cols.map(|c| c.from(lo - s - 1));
        let ForwardEnergy { mut prev_a, mut prev, mut kin, mut pot, mut lw } = *self;
        let (bc, pc, ul, uc, fc) = (&mut b[lo..hi], &p[lo..hi], &u[lo - 1..hi - 1], &u[lo..hi], &load[lo..hi]);
        for j in 0..bc.len() {
            prev_a = bc[j] - lac.at(j) * prev_a;
            bc[j] = prev_a;
            prev = pc[j] - lmc.at(j) * prev;
            kin += prev * prev * ldc.at(j);
            let off = 0.0 + ksc.at(j) * ul[j];
            pot += uc[j] * (kdc.at(j) * uc[j] + 2.0 * off);
            lw += fc[j] * uc[j];
        }
        *self = ForwardEnergy { prev_a, prev, kin, pot, lw };
    }
}

/// `y_i = (A x)_i + c_i` for a tridiagonal `A` given by its diagonal `d` and
/// sub-diagonal `s` (`s[i] = A[i][i-1]`), with `c_i` from a closure; the
/// interior loop is branch-free over equal-length slices so it vectorises.
#[inline(always)]
fn tri_apply(d: &[f64], s: &[f64], x: &[f64], mut c: impl FnMut(usize, f64)) {
    let n = x.len();
    let (d, s) = (&d[..n], &s[..n]);
    c(0, d[0] * x[0] + s[1] * x[1]);
    let it = x[..n - 2].iter().zip(&x[1..n - 1]).zip(&x[2..]).zip(&s[1..n - 1]).zip(&d[1..n - 1]).zip(&s[2..]);
    for (k, (((((xl, xc), xr), sl), dc), sr)) in it.enumerate() {
        c(k + 1, sl * xl + dc * xc + sr * xr);
    }
    c(n - 1, s[n - 1] * x[n - 2] + d[n - 1] * x[n - 1]);
}

/// Solves `(M + a dt² K) x = M u + c0 p + c1 r + c2 f` with the tridiagonal
/// factor `(l, inv_d)` of the matrix, the right-hand side computed inside the
/// forward sweep (`m_d`, `m_s`: diagonal and sub-diagonal of `M`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn forward_backward_fused(l: &[f64], inv_d: &[f64], m_d: &[f64], m_s: &[f64], u: &[f64], p: &[f64], r: &[f64], f: &[f64], c: [f64; 3], out: &mut [f64]) {
    let n = u.len();
    let (l, inv_d, m_d, m_s, p, r, f, out) = (&l[..n], &inv_d[..n], &m_d[..n], &m_s[..n], &p[..n], &r[..n], &f[..n], &mut out[..n]);
    let extra = |i: usize| c[0] * p[i] + c[1] * r[i] + c[2] * f[i];
    let mut prev = m_d[0] * u[0] + m_s[1] * u[1] + extra(0);
    out[0] = prev;
    let it = u[..n - 2].iter().zip(&u[1..n - 1]).zip(&u[2..]).zip(&m_s[1..n - 1]).zip(&m_d[1..n - 1]).zip(&m_s[2..]);
    let it = it.zip(p[1..n - 1].iter().zip(&r[1..n - 1]).zip(&f[1..n - 1])).zip(l[1..n - 1].iter().zip(out[1..n - 1].iter_mut()));
    for (((((((ul, uc), ur), sl), dc), sr), ((pi, ri), fi)), (li, oi)) in it {
        let b = sl * ul + dc * uc + sr * ur + c[0] * pi + c[1] * ri + c[2] * fi;
        prev = b - li * prev;
        *oi = prev;
    }
    let b_last = m_s[n - 1] * u[n - 2] + m_d[n - 1] * u[n - 1] + extra(n - 1);
    out[n - 1] = b_last - l[n - 1] * prev;
    backward_sweep(l, inv_d, out);
}

/// `x` is infinite, NaN or `−0`, as 0 or 1: where a sweep's step over a
/// zero entry of `L`, `b − (±0)·y`, may not be `b` (the check of
/// `BandLdlt::solve_in_place`'s diagonal path; with `1/D_i > 0`, possibly
/// `+∞`, a `b_i` that is infinite, NaN or `−0` makes `b_i (1/D_i)` so).
#[inline(always)]
pub(crate) fn not_plain(x: f64) -> u64 {
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    let b = x.to_bits();
    u64::from(b & EXP == EXP) | u64::from(b == 1 << 63)
}

/// A lumped mass and a tridiagonal stiffness (the P1 bar's lumped
/// explicit schemes: `cd-lagrange`, `d1-minus-linear`, `verlet-nitsche`):
/// `K`'s diagonal and sub-diagonal by themselves and the inverse pivots of
/// `M`'s factor (whose `L` is the identity), for steps fused into one or two
/// vectorised passes (AVX2 when the CPU has it, no FMA) with the operations,
/// in their order, of `SymBand::mul_vec` and `BandLdlt::solve_in_place`
/// (the products `b_i (1/D_i)`, checked with [`not_plain`]).
pub(crate) struct LumpedTri {
    pub(crate) kd: Vec<f64>,
    pub(crate) ks: Vec<f64>,
    pub(crate) inv_d: Vec<f64>,
    pub(crate) avx2: bool,
    /// The interior rows' `(K_{i,i−1}, K_ii, K_{i,i+1}, 1/D_i)` when each is
    /// one value on every interior row (bit for bit: a uniform mesh), for
    /// the passes' [`Same`] columns.
    pub(crate) uniform: Option<[Same; 4]>,
}

/// A column of per-row coefficients of a fused pass's interior rows: a
/// slice, or [`Same`] (one value on every row). A pass generic over it
/// does the same operations on the same values either way, so the same
/// bits; the scalar form streams no array (on a uniform mesh the lumped
/// explicit steps' coefficient arrays, four of their seven to ten, are
/// what keeps their arrays out of the L1 cache at m = 1000,
/// docs/performance.md).
pub(crate) trait Col: Copy {
    /// Row `j`'s coefficient.
    fn at(self, j: usize) -> f64;
    /// The column from row `k` on.
    fn from(self, k: usize) -> Self;
}

impl Col for &[f64] {
    #[inline(always)]
    fn at(self, j: usize) -> f64 {
        self[j]
    }
    #[inline(always)]
    fn from(self, k: usize) -> Self {
        &self[k..]
    }
}

/// One coefficient on every row (a [`Col`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Same(pub(crate) f64);

impl Col for Same {
    #[inline(always)]
    fn at(self, _: usize) -> f64 {
        self.0
    }
    #[inline(always)]
    fn from(self, _: usize) -> Self {
        self
    }
}

/// `Some(x[0])` if every entry of `x` has the bits of `x[0]` (a nonempty `x`).
pub(crate) fn same_bits(x: &[f64]) -> Option<Same> {
    let first = *x.first()?;
    x.iter().all(|v| v.to_bits() == first.to_bits()).then_some(Same(first))
}

/// The columns `(s_i, d_i, s_{i+1}, e_i)`, `i = first..n−1`, of a
/// tridiagonal matrix `(d, s)` (`s[i] = A[i][i−1]`) and a diagonal `e`, as
/// [`Same`] when each is one value (bit for bit) on every one of these
/// rows (`first >= 1`; at least one row).
pub(crate) fn uniform_interior(d: &[f64], s: &[f64], e: &[f64], first: usize) -> Option<[Same; 4]> {
    let n = d.len();
    if first == 0 || n < first + 2 || s.len() != n || e.len() != n {
        return None;
    }
    let sides = same_bits(&s[first..])?;
    Some([sides, same_bits(&d[first..n - 1])?, sides, same_bits(&e[first..n - 1])?])
}

impl LumpedTri {
    /// `Some` when `mf` is a tridiagonal factor with `L = I` and `k` is
    /// tridiagonal, of size 2 or more.
    pub(crate) fn new(mf: &BandLdlt, k: &signorini_fem::SymBand) -> Option<Self> {
        Self::uniform_from(mf, k, 1)
    }

    /// [`new`](Self::new), [`uniform`](Self::uniform) judged on the rows
    /// `first..n−1` (those the scheme's pass takes from the columns).
    pub(crate) fn uniform_from(mf: &BandLdlt, k: &signorini_fem::SymBand, first: usize) -> Option<Self> {
        let (l, inv_d) = mf.tridiagonal_factors()?;
        (k.half_bandwidth() == 1 && k.n() == l.len() && l.len() >= 2 && l.iter().all(|x| *x == 0.0)).then(|| {
            let (kd, ks) = (k.diagonal(0), k.diagonal(1));
            let uniform = uniform_interior(&kd, &ks, inv_d, first);
            LumpedTri { kd, ks, inv_d: inv_d.to_vec(), avx2: avx2_available(), uniform }
        })
    }

    /// Rows 0 and `n − 1` of `K u` with `SymBand::mul_vec`'s operations.
    #[inline(always)]
    pub(crate) fn ku_ends(&self, u: &[f64]) -> (f64, f64) {
        let (kd, ks, l) = (&self.kd, &self.ks, u.len() - 1);
        (kd[0] * u[0] + ks[1] * u[1], ks[l] * u[l - 1] + kd[l] * u[l])
    }

    /// The interior rows' slices, `1..n−1`: `(K_{i,i−1}, K_ii, K_{i,i+1},
    /// u_{i−1}, u_i, u_{i+1}, 1/D_i)`, row `i` of `K u` being
    /// `ksl·ul + kdc·uc + ksr·ur` in that order.
    #[allow(clippy::type_complexity)]
    #[inline(always)]
    pub(crate) fn interior<'a>(&'a self, u: &'a [f64]) -> ([&'a [f64]; 3], [&'a [f64]; 3], &'a [f64]) {
        let n = u.len();
        let (kd, ks, inv_d) = (&self.kd[..n], &self.ks[..n], &self.inv_d[..n]);
        ([&ks[1..n - 1], &kd[1..n - 1], &ks[2..]], [&u[..n - 2], &u[1..n - 1], &u[2..]], &inv_d[1..n - 1])
    }

    /// [`interior`](Self::interior)'s coefficient columns `(K_{i,i−1},
    /// K_ii, K_{i,i+1}, 1/D_i)` as slices, for `n` rows.
    #[inline(always)]
    pub(crate) fn columns(&self, n: usize) -> [&[f64]; 4] {
        let (kd, ks, inv_d) = (&self.kd[..n], &self.ks[..n], &self.inv_d[..n]);
        [&ks[1..n - 1], &kd[1..n - 1], &ks[2..], &inv_d[1..n - 1]]
    }
}

/// A lumped explicit scheme's energy sums ([`sums`](Self::sums)): `M`'s
/// diagonal and sub-diagonal beside a [`LumpedTri`]'s `K`, and the rows
/// `1..n−1`' `(M_{i,i−1}, M_ii, K_{i,i−1}, K_ii, K_{i,i+1})` as [`Same`]
/// when each is one value there (a uniform mesh).
pub(crate) struct LumpedEnergy {
    md: Vec<f64>,
    ms: Vec<f64>,
    uniform: Option<[Same; 5]>,
}

impl LumpedEnergy {
    /// `Some` when `mass` is tridiagonal (of `lt`'s size).
    pub(crate) fn new(mass: &signorini_fem::SymBand, lt: &LumpedTri) -> Option<Self> {
        let n = mass.n();
        (mass.half_bandwidth() == 1 && n == lt.kd.len()).then(|| {
            let (md, ms) = (mass.diagonal(0), mass.diagonal(1));
            let inner = 1..n.max(2) - 1;
            let uniform = (|| {
                let ksides = same_bits(&lt.ks[1..])?;
                Some([same_bits(&ms[inner.clone()])?, same_bits(&md[inner.clone()])?, ksides, same_bits(&lt.kd[inner.clone()])?, ksides])
            })();
            LumpedEnergy { md, ms, uniform: uniform.filter(|_| n >= 3) }
        })
    }

    /// `(Vᵀ M V, Uᵀ K W, Σ F_i c (U_i + W_i))` (or `c F_i U_i` with `W =
    /// None`) with `lt`'s `K` (`n >= 2`) in one pass: the sums of
    /// `SymBand::quad_form` (`V`), of `SymBand::mul_vec`'s rows dotted with
    /// `U` (an iterator sum: from `−0.0`) — `SymBand::quad_form(U)` instead
    /// with `W = None` — and of the load's iterator sum, each with its own
    /// operations in its own order (so the same bits as the separate
    /// calls), their three loop-carried additions side by side instead of
    /// one pass (and a product) after another. The lumped explicit schemes'
    /// energy after every step.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn sums(&self, lt: &LumpedTri, v: &[f64], u: &[f64], w: Option<&[f64]>, load: &[f64], c: f64) -> (f64, f64, f64) {
        let n = u.len();
        let (md, ms, kd, ks) = (&self.md[..n], &self.ms[..n], &lt.kd[..n], &lt.ks[..n]);
        // A uniform mesh's coefficients as scalars (the same values: the same bits).
        match self.uniform {
            Some(cols) => energy_sums_lumped(cols, md, ms, kd, ks, v, u, w, load, c),
            None if n >= 3 => energy_sums_lumped([&ms[1..n - 1], &md[1..n - 1], &ks[1..n - 1], &kd[1..n - 1], &ks[2..n]], md, ms, kd, ks, v, u, w, load, c),
            None => energy_sums_lumped([Same(0.0); 5], md, ms, kd, ks, v, u, w, load, c),
        }
    }
}

/// [`LumpedEnergy::sums`]: rows 0 and `n − 1` from the slices, the rows
/// between from the columns `(M_{i,i−1}, M_ii, K_{i,i−1}, K_ii,
/// K_{i,i+1})` (row `i` at `i − 1`; none when `n = 2`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn energy_sums_lumped<C: Col>([msl, mdc, ksl, kdc, ksr]: [C; 5], md: &[f64], ms: &[f64], kd: &[f64], ks: &[f64], v: &[f64], u: &[f64], w: Option<&[f64]>, load: &[f64], c: f64) -> (f64, f64, f64) {
    let n = u.len();
    let (v, load, l) = (&v[..n], &load[..n], n - 1);
    // `quad_form`'s row i: `off = 0.0 + s_i x_{i−1}` (row 0: 0.0), `x_i (d_i x_i + 2 off)`.
    let quad = |d: &[f64], s: &[f64], x: &[f64], i: usize| {
        let off = if i == 0 { 0.0 } else { 0.0 + s[i] * x[i - 1] };
        x[i] * (d[i] * x[i] + 2.0 * off)
    };
    let (mut kin, mut lw) = (0.0, -0.0);
    kin += quad(md, ms, v, 0);
    let (vl, vc) = (&v[..l.saturating_sub(1)], &v[1..l.max(1)]);
    match w {
        Some(w) => {
            let w = &w[..n];
            // `mul_vec_tridiag`'s rows.
            let mut pot = -0.0;
            pot += u[0] * (kd[0] * w[0] + ks[1] * w[1]);
            lw += load[0] * c * (u[0] + w[0]);
            let (wl, wc, wr) = (&w[..l.saturating_sub(1)], &w[1..l.max(1)], &w[2.min(n)..]);
            let (uc, fc) = (&u[1..l.max(1)], &load[1..l.max(1)]);
            for j in 0..l.saturating_sub(1) {
                kin += vc[j] * (mdc.at(j) * vc[j] + 2.0 * (0.0 + msl.at(j) * vl[j]));
                pot += uc[j] * (ksl.at(j) * wl[j] + kdc.at(j) * wc[j] + ksr.at(j) * wr[j]);
                lw += fc[j] * c * (uc[j] + wc[j]);
            }
            kin += quad(md, ms, v, l);
            pot += u[l] * (ks[l] * w[l - 1] + kd[l] * w[l]);
            lw += load[l] * c * (u[l] + w[l]);
            (kin, pot, lw)
        }
        None => {
            let mut pot = 0.0;
            pot += quad(kd, ks, u, 0);
            lw += load[0] * u[0];
            let (ul, uc, fc) = (&u[..l.saturating_sub(1)], &u[1..l.max(1)], &load[1..l.max(1)]);
            for j in 0..l.saturating_sub(1) {
                kin += vc[j] * (mdc.at(j) * vc[j] + 2.0 * (0.0 + msl.at(j) * vl[j]));
                pot += uc[j] * (kdc.at(j) * uc[j] + 2.0 * (0.0 + ksl.at(j) * ul[j]));
                lw += fc[j] * uc[j];
            }
            kin += quad(md, ms, v, l);
            pot += quad(kd, ks, u, l);
            lw += load[l] * u[l];
            (kin, pot, lw)
        }
    }
}

/// Runs `$body` (an expression) compiled with AVX2 when `$avx2` (the CPU
/// has it; no FMA, so the same bits), in a nested function of the given
/// arguments.
macro_rules! with_avx2 {
    ($avx2:expr, fn($($a:ident: $t:ty),* $(,)?) -> $r:ty $body:block) => {{
        #[inline(always)]
        #[allow(clippy::too_many_arguments)]
        fn plain($($a: $t),*) -> $r $body
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        #[allow(clippy::too_many_arguments)]
        unsafe fn avx2($($a: $t),*) -> $r {
            plain($($a),*)
        }
        // SAFETY: the flag is set only when the CPU reports AVX2.
        #[cfg(target_arch = "x86_64")]
        let r = if $avx2 { unsafe { avx2($($a),*) } } else { plain($($a),*) };
        #[cfg(not(target_arch = "x86_64"))]
        let r = {
            let _ = $avx2;
            plain($($a),*)
        };
        r
    }};
}
pub(crate) use with_avx2;

/// [`forward_backward_fused`] when the factor's `L` is the identity (`A =
/// M` lumped: `penalty-cd`): row `i` of the right-hand side with the
/// operations of the sweep's row `i`, times `1/D_i`, in one vectorised
/// pass. With every `l_i = ±0` the sweeps' values are these products
/// unless one is infinite, NaN or `−0` ([`not_plain`]): then false, and
/// the caller runs the sweeps (its inputs are untouched: `out` only is
/// written).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn diagonal_step<C: Col>([msl, mdc, msr, dc]: [C; 4], inv_d: &[f64], m_d: &[f64], m_s: &[f64], u: &[f64], p: &[f64], r: &[f64], f: &[f64], c: [f64; 3], out: &mut [f64]) -> bool {
    let n = u.len();
    let (inv_d, m_d, m_s, p, r, f, out) = (&inv_d[..n], &m_d[..n], &m_s[..n], &p[..n], &r[..n], &f[..n], &mut out[..n]);
    let extra = |i: usize| c[0] * p[i] + c[1] * r[i] + c[2] * f[i];
    let first = (m_d[0] * u[0] + m_s[1] * u[1] + extra(0)) * inv_d[0];
    let last = (m_s[n - 1] * u[n - 2] + m_d[n - 1] * u[n - 1] + extra(n - 1)) * inv_d[n - 1];
    let mut odd = not_plain(first) | not_plain(last);
    out[0] = first;
    out[n - 1] = last;
    // The interior's `(M_{i,i−1}, M_ii, M_{i,i+1}, 1/D_i)`: slices or `Same`.
    let (ul, uc, ur) = (&u[..n - 2], &u[1..n - 1], &u[2..]);
    let (pc, rc, fc) = (&p[1..n - 1], &r[1..n - 1], &f[1..n - 1]);
    let oc = &mut out[1..n - 1];
    for j in 0..n - 2 {
        let b = msl.at(j) * ul[j] + mdc.at(j) * uc[j] + msr.at(j) * ur[j] + c[0] * pc[j] + c[1] * rc[j] + c[2] * fc[j];
        let x = b * dc.at(j);
        odd |= not_plain(x);
        oc[j] = x;
    }
    odd == 0
}

/// [`diagonal_step`] compiled with AVX2 when the CPU has it (no FMA: the
/// same bits).
#[allow(clippy::too_many_arguments)]
fn diagonal_step_dispatch(has_avx2: bool, uniform: Option<[Same; 4]>, inv_d: &[f64], m_d: &[f64], m_s: &[f64], u: &[f64], p: &[f64], r: &[f64], f: &[f64], c: [f64; 3], out: &mut [f64]) -> bool {
    with_avx2!(has_avx2, fn(uniform: Option<[Same; 4]>, inv_d: &[f64], m_d: &[f64], m_s: &[f64], u: &[f64], p: &[f64], r: &[f64], f: &[f64], c: [f64; 3], out: &mut [f64]) -> bool {
        // A uniform mesh's coefficients as scalars (the same values: the same bits).
        match uniform {
            Some(cols) => diagonal_step(cols, inv_d, m_d, m_s, u, p, r, f, c, out),
            None => {
                let n = u.len();
                let cols = [&m_s[1..n - 1], &m_d[1..n - 1], &m_s[2..n], &inv_d[1..n - 1]];
                diagonal_step(cols, inv_d, m_d, m_s, u, p, r, f, c, out)
            }
        }
    })
}

/// `R ← F − K U`, `P ← P + dt((1−γ) R_old + γ R)` on the tridiagonal
/// path in one vectorised pass: the operations of
/// [`OneStep::update_acceleration_and_momentum`]'s ([`tri_apply`]'s rows),
/// row by row in the same order, so the same bits.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn update_momentum<C: Col>([ksl, kdc, ksr, _]: [C; 4], kd: &[f64], ks: &[f64], u: &[f64], f: &[f64], mom: &mut [f64], r: &mut [f64], dt: f64, g: f64) {
    let n = u.len();
    let (kd, ks, f, mom, r) = (&kd[..n], &ks[..n], &f[..n], &mut mom[..n], &mut r[..n]);
    let row = |ku: f64, f: f64, p: &mut f64, r: &mut f64| {
        let rn = f - ku;
        *p += dt * ((1.0 - g) * *r + g * rn);
        *r = rn;
    };
    row(kd[0] * u[0] + ks[1] * u[1], f[0], &mut mom[0], &mut r[0]);
    let l = n - 1;
    row(ks[l] * u[l - 1] + kd[l] * u[l], f[l], &mut mom[l], &mut r[l]);
    // The interior's `(K_{i,i−1}, K_ii, K_{i,i+1})`: slices or `Same`.
    let (ul, uc, ur) = (&u[..n - 2], &u[1..n - 1], &u[2..]);
    let fc = &f[1..n - 1];
    let (pc, rc) = (&mut mom[1..n - 1], &mut r[1..n - 1]);
    for j in 0..n - 2 {
        let rn = fc[j] - (ksl.at(j) * ul[j] + kdc.at(j) * uc[j] + ksr.at(j) * ur[j]);
        pc[j] += dt * ((1.0 - g) * rc[j] + g * rn);
        rc[j] = rn;
    }
}

/// [`update_momentum`] compiled with AVX2 when the CPU has it.
#[allow(clippy::too_many_arguments)]
fn update_momentum_dispatch(has_avx2: bool, uniform: Option<[Same; 4]>, kd: &[f64], ks: &[f64], u: &[f64], f: &[f64], mom: &mut [f64], r: &mut [f64], dt: f64, g: f64) {
    with_avx2!(has_avx2, fn(uniform: Option<[Same; 4]>, kd: &[f64], ks: &[f64], u: &[f64], f: &[f64], mom: &mut [f64], r: &mut [f64], dt: f64, g: f64) -> () {
        // A uniform mesh's coefficients as scalars (the same values: the same bits).
        match uniform {
            Some(cols) => update_momentum(cols, kd, ks, u, f, mom, r, dt, g),
            None => {
                let n = u.len();
                let cols = [&ks[1..n - 1], &kd[1..n - 1], &ks[2..n], &kd[1..n - 1]];
                update_momentum(cols, kd, ks, u, f, mom, r, dt, g)
            }
        }
    })
}

/// The backward sweep of the tridiagonal factor `(l, inv_d)` on a
/// forward-swept right-hand side `out` (the second half of
/// [`forward_backward_fused`]).
#[inline(always)]
fn backward_sweep(l: &[f64], inv_d: &[f64], out: &mut [f64]) {
    let n = out.len();
    let (l, inv_d) = (&l[..n], &inv_d[..n]);
    let mut next = out[n - 1] * inv_d[n - 1];
    out[n - 1] = next;
    for ((o, li1), di) in out[..n - 1].iter_mut().rev().zip(l[1..].iter().rev()).zip(inv_d[..n - 1].iter().rev()) {
        next = *o * di - li1 * next;
        *o = next;
    }
}

/// Row `i` of the right-hand side `M U + c₀ P + c₁ R + c₂ F` with the
/// operations, in their order, of [`forward_backward_fused`]'s row `i`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn rhs_row(m_d: &[f64], m_s: &[f64], u: &[f64], p: &[f64], r: &[f64], f: &[f64], c: [f64; 3], i: usize) -> f64 {
    let n = u.len();
    let extra = c[0] * p[i] + c[1] * r[i] + c[2] * f[i];
    if i == 0 {
        m_d[0] * u[0] + m_s[1] * u[1] + extra
    } else if i == n - 1 {
        m_s[n - 1] * u[n - 2] + m_d[n - 1] * u[n - 1] + extra
    } else {
        m_s[i] * u[i - 1] + m_d[i] * u[i] + m_s[i + 1] * u[i + 1] + c[0] * p[i] + c[1] * r[i] + c[2] * f[i]
    }
}

/// First pass of the fused end of a step, rows `lo..hi` (branch-free,
/// vectorised across the interior rows): `R ← F − K U`,
/// `P ← P + dt((1−γ) R_old + γ R)` (the operations of
/// [`OneStep::update_acceleration_and_momentum`]), the next step's
/// right-hand side `M U + c₀ P + c₁ R + c₂ F` into `rhs` (those of
/// [`forward_backward_fused`], [`rhs_row`]). The caller then fixes the
/// contact row's `P`, `R` and its `rhs` row.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn update_rows(t: &Tridiagonals, u: &[f64], f: &[f64], mom: &mut [f64], r: &mut [f64], rhs: &mut [f64], dt: f64, g: f64, c: [f64; 3], lo: usize, hi: usize) {
    let n = u.len();
    let (kd, ks, md, ms) = (&t.kd[..n], &t.ks[..n], &t.md[..n], &t.ms[..n]);
    let (f, mom, r, rhs) = (&f[..n], &mut mom[..n], &mut r[..n], &mut rhs[..n]);
    let mut a = lo;
    if a == 0 {
        let rn = f[0] - (kd[0] * u[0] + ks[1] * u[1]);
        mom[0] += dt * ((1.0 - g) * r[0] + g * rn);
        r[0] = rn;
        rhs[0] = md[0] * u[0] + ms[1] * u[1] + (c[0] * mom[0] + c[1] * r[0] + c[2] * f[0]);
        a = 1;
    }
    let b = if hi == n { n - 1 } else { hi };
    if b > a {
        // The interior's `(K_{i,i−1}, K_ii, K_{i,i+1})`, `(M_{i,i−1}, M_ii,
        // M_{i,i+1})` from row 1: a uniform mesh's as scalars (the same
        // values: the same bits), else the slices.
        match (t.uniform_k, t.uniform_m) {
            (Some([ksl, kdc, ksr, _]), Some([msl, mdc, msr, _])) => update_interior([ksl, kdc, ksr, msl, mdc, msr], u, f, mom, r, rhs, dt, g, c, a, b),
            _ => update_interior([&ks[1..n - 1], &kd[1..n - 1], &ks[2..n], &ms[1..n - 1], &md[1..n - 1], &ms[2..n]], u, f, mom, r, rhs, dt, g, c, a, b),
        }
    }
    if hi == n {
        let l = n - 1;
        let rn = f[l] - (ks[l] * u[l - 1] + kd[l] * u[l]);
        mom[l] += dt * ((1.0 - g) * r[l] + g * rn);
        r[l] = rn;
        rhs[l] = ms[l] * u[l - 1] + md[l] * u[l] + (c[0] * mom[l] + c[1] * r[l] + c[2] * f[l]);
    }
}

/// [`update_rows`]' interior rows `a..b` (`1 <= a < b <= n − 1`),
/// coefficients `(K_{i,i−1}, K_ii, K_{i,i+1}, M_{i,i−1}, M_ii, M_{i,i+1})`
/// as slices or [`Same`] (row `i` at `i − 1`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn update_interior<C: Col>(cols: [C; 6], u: &[f64], f: &[f64], mom: &mut [f64], r: &mut [f64], rhs: &mut [f64], dt: f64, g: f64, c: [f64; 3], a: usize, b: usize) {
    let [ksl, kdc, ksr, msl, mdc, msr] = cols.map(|x| x.from(a - 1));
    let (ul, uc, ur) = (&u[a - 1..b - 1], &u[a..b], &u[a + 1..b + 1]);
    let (fc, pc, rc, bc) = (&f[a..b], &mut mom[a..b], &mut r[a..b], &mut rhs[a..b]);
    for j in 0..b - a {
        let rn = fc[j] - (ksl.at(j) * ul[j] + kdc.at(j) * uc[j] + ksr.at(j) * ur[j]);
        let p = pc[j] + dt * ((1.0 - g) * rc[j] + g * rn);
        pc[j] = p;
        rc[j] = rn;
        bc[j] = msl.at(j) * ul[j] + mdc.at(j) * uc[j] + msr.at(j) * ur[j] + c[0] * p + c[1] * rn + c[2] * fc[j];
    }
}

/// `(Pᵀ M⁺ P, Uᵀ K U, Fᵀ U)` on the tridiagonal path in one pass: the
/// sums of [`BandLdlt::inverse_quad_form`] over `p[s..]` with the factor
/// `(l, inv_d)` of the massive block, of `SymBand::quad_form` with `K`'s
/// diagonal `kd` and sub-diagonal `ks`, and of the load's dot product (an
/// iterator sum: from `-0.0`), each with its own operations in its own
/// order — so the same bits as the three calls — but their loop-carried
/// dependencies side by side instead of one after another
/// (`benches/step.rs`, `parts_energy`).
#[allow(clippy::too_many_arguments)]
fn energy_sums_tri(cols: Option<[Same; 5]>, l: &[f64], inv_d: &[f64], s: usize, p: &[f64], kd: &[f64], ks: &[f64], u: &[f64], load: &[f64]) -> (f64, f64, f64) {
    let n = u.len();
    let (p, kd, ks, load) = (&p[..n], &kd[..n], &ks[..n], &load[..n]);
    let (l, inv_d) = (&l[..n - s], &inv_d[..n - s]);
    let (mut pot, mut lw) = (0.0, -0.0);
    // Rows 0..=s; `quad_form`'s off-diagonal sum starts at 0.0.
    for i in 0..=s {
        let off = if i == 0 { 0.0 } else { 0.0 + ks[i] * u[i - 1] };
        pot += u[i] * (kd[i] * u[i] + 2.0 * off);
        lw += load[i] * u[i];
    }
    let mut prev = p[s];
    let mut acc = [prev * prev * inv_d[0], pot, lw];
    if n - 1 > s {
        // Rows s+1..n−1 (a uniform mesh's coefficients as scalars: the same
        // values, the same bits), then row n−1.
        match cols {
            Some([_, lc, dc, kdc, ksc]) => energy_rows_tri([lc, dc, kdc, ksc], p, u, load, s, &mut prev, &mut acc),
            None => energy_rows_tri([&l[1..n - 1 - s], &inv_d[1..n - 1 - s], &kd[s + 1..n - 1], &ks[s + 1..n - 1]], p, u, load, s, &mut prev, &mut acc),
        }
        let i = n - 1;
        prev = p[i] - l[i - s] * prev;
        acc[0] += prev * prev * inv_d[i - s];
        let off = 0.0 + ks[i] * u[i - 1];
        acc[1] += u[i] * (kd[i] * u[i] + 2.0 * off);
        acc[2] += load[i] * u[i];
    }
    (acc[0], acc[1], acc[2])
}

/// [`energy_sums_tri`]'s rows `s+1..n−1`, coefficients `(L_M, 1/D_M,
/// K_ii, K_{i,i−1})` as slices or [`Same`] (row `i` at `i − s − 1`), the
/// sums `(kin, pot, lw)` and the sweep's value carried.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn energy_rows_tri<C: Col>([lc, dc, kdc, ksc]: [C; 4], p: &[f64], u: &[f64], load: &[f64], s: usize, prev: &mut f64, acc: &mut [f64; 3]) {
    let n = u.len();
    let (pc, ul, uc, fc) = (&p[s + 1..n - 1], &u[s..n - 2], &u[s + 1..n - 1], &load[s + 1..n - 1]);
    let [mut kin, mut pot, mut lw] = *acc;
    let mut pr = *prev;
    for j in 0..pc.len() {
        pr = pc[j] - lc.at(j) * pr;
        kin += pr * pr * dc.at(j);
        let off = 0.0 + ksc.at(j) * ul[j];
        pot += uc[j] * (kdc.at(j) * uc[j] + 2.0 * off);
        lw += fc[j] * uc[j];
    }
    *acc = [kin, pot, lw];
    *prev = pr;
}

impl OneStep {
    /// Sets up the scheme: factorises `M + a dt² K` and the massive block of
    /// `M`, and computes `P^0 = M V^0`, `R^0 = F - K U^0` (`λ^0 = 0`).
    pub fn new(label: String, dy: Dynamics, prm: OneStepParams, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        let n = dy.n();
        for (what, v) in [("initial displacement", &init.u), ("initial velocity", &init.v)] {
            if v.len() != n {
                return Err(SchemeError::Size { what, got: v.len(), expected: n });
            }
        }
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SchemeError::Invalid { field: "dt", value: dt, allowed: "finite and > 0" });
        }
        if dy.damping.is_some() && prm.a_new == 0.0 {
            return Err(not_taken(label, Refused::Damping, " (an explicit step, β = 0: it would need a solve with M + γ dt C)"));
        }
        let a_mat = dy.step_matrix(prm.gamma * dt, prm.a_new * dt * dt);
        let a = a_mat.factor()?;
        let c = dy.contact().dof;
        let k = dy.k();
        let multi = if k > 1 && prm.a_new > 0.0 {
            let mut ms = MultiSolve::new(&dy, &a)?.with_banded(a_mat.clone())?;
            for (i, ct) in dy.contacts.iter().enumerate() {
                (ms.lo[i], ms.hi[i]) = (ct.bounds.lo, ct.bounds.hi);
            }
            Some(ms)
        } else {
            None
        };
        let mut w = vec![0.0; n];
        w[c] = 1.0;
        a.solve_in_place(&mut w);
        let proj = Projection::new(c, w)?;
        let m_massive = dy.massive_factor()?;
        let mut mom = vec![0.0; n];
        dy.mass.mul_vec(&init.v, &mut mom);
        let mut ku = vec![0.0; n];
        dy.stiffness.mul_vec(&init.u, &mut ku);
        let mut f = vec![0.0; n];
        dy.load_at(0.0, &mut f);
        let mut damp = None;
        let mut r: Vec<f64> = if let Some(cm) = &dy.damping {
            let mut cv = vec![0.0; n];
            cm.mul_vec(&init.v, &mut cv);
            let r = f.iter().zip(&ku).zip(&cv).map(|((f, k), c)| f - k - c).collect();
            damp = Some(Damped { vel: init.v.clone(), acc: vec![0.0; n], ut: vec![0.0; n], vt: vec![0.0; n], cv, cx: vec![0.0; n] });
            r
        } else {
            f.iter().zip(&ku).map(|(f, k)| f - k).collect()
        };
        for ct in dy.contacts.iter().filter(|ct| ct.massless) {
            r[ct.dof] = 0.0;
            mom[ct.dof] = 0.0;
        }
        if let Some(d) = &mut damp {
            // A^0 = M⁻¹ R^0 on the massive dofs (zero on massless contact rows).
            let s = dy.massive_start();
            d.acc[s..].copy_from_slice(&r[s..]);
            m_massive.solve_in_place(&mut d.acc[s..]);
            for ct in dy.contacts.iter().filter(|ct| ct.massless) {
                (d.acc[ct.dof], d.vel[ct.dof]) = (0.0, 0.0);
            }
        }
        let tri = (a.half_bandwidth() == 1 && n >= 2 && damp.is_none()).then(|| {
            let (md, ms, kd, ks) = (dy.mass.diagonal(0), dy.mass.diagonal(1), dy.stiffness.diagonal(0), dy.stiffness.diagonal(1));
            let inv_d = a.tridiagonal_factors().filter(|(l, _)| l.iter().all(|x| *x == 0.0)).map(|(_, inv_d)| inv_d);
            let (uniform_m, uniform_k) = match inv_d {
                Some(inv_d) => (uniform_interior(&md, &ms, inv_d, 1), uniform_interior(&kd, &ks, inv_d, 1)),
                None => (None, None),
            };
            let s = dy.massive_start();
            let uniform_energy = (|| {
                let ((l_a, _), (l_m, inv_d_m)) = (a.tridiagonal_factors()?, m_massive.tridiagonal_factors()?);
                // No rows between the massive start and the last (two dofs, a massless first).
                (n >= s + 2).then_some(())?;
                let (rows, block) = (s + 1..n - 1, 1..n - 1 - s);
                Some([same_bits(&l_a[rows.clone()])?, same_bits(&l_m[block.clone()])?, same_bits(&inv_d_m[block])?, same_bits(&kd[rows.clone()])?, same_bits(&ks[rows])?])
            })();
            Tridiagonals { md, ms, kd, ks, avx2: avx2_available(), diagonal: inv_d.is_some(), uniform_m, uniform_k, uniform_energy }
        });
        // Each forcing term's values at n dt, n = 0, 1, …: s(0) now, then one per step.
        let mut loads = Loads::values(&dy, dt);
        let mut s_now = vec![0.0; dy.forcing.len()];
        loads.next_into(&mut s_now);
        Ok(Self {
            lams: vec![0.0; k],
            prev_lams: vec![0.0; k],
            touched: Vec::with_capacity(k),
            marked: vec![false; k],
            acts: vec![Active::None; k],
            multi,
            kappas: Vec::new(),
            fuse_energy: false,
            ahead: false,
            sums: None,
            tri,
            law: ContactLaw::Projection,
            u_prev: if dy.forcing.is_empty() { Vec::new() } else { init.u.clone() },
            work_f: 0.0,
            work_c: 0.0,
            work_d: 0.0,
            s_now,
            loads,
            s_next: vec![0.0; dy.forcing.len()],
            damp,
            f,
            label,
            prm,
            dt,
            n: 0,
            u: init.u.clone(),
            mom,
            r,
            rhs: vec![0.0; n],
            ku,
            u_c_prev: init.u[c],
            lambda: 0.0,
            a,
            proj,
            m_massive,
            dy,
        })
    }

    /// Uses `law` for the contacts instead of the projection. A penalty
    /// law's stiffness is contact 0's; another stop without its own
    /// ([`crate::Contact::stiffness`]) gets it scaled by `K_cc / K_00` (so
    /// `penalty(γ_P)` puts `γ_P K_cc` at every stop).
    pub fn with_contact_law(mut self, law: ContactLaw) -> Result<Self, SchemeError> {
        let mut law = law;
        if let ContactLaw::Penalty { stiffness } = law {
            if !(stiffness > 0.0 && stiffness.is_finite()) {
                return Err(SchemeError::Invalid { field: "penalty stiffness", value: stiffness, allowed: "finite and > 0" });
            }
            let an = self.prm.a_new * self.dt * self.dt;
            // A stop without its own stiffness: the law's, scaled by its
            // stiffness diagonal relative to contact 0's (γ_P K_cc per stop).
            let k0 = self.dy.stiffness.get(self.dy.contacts[0].dof, self.dy.contacts[0].dof);
            let n_contacts = self.dy.k();
            self.kappas =
                self.dy.contacts.iter().map(|c| c.stiffness.unwrap_or(if n_contacts == 1 || !(k0 > 0.0) { stiffness } else { stiffness * self.dy.stiffness.get(c.dof, c.dof) / k0 })).collect();
            // The step solves x = y_c + W κ (lo - x)⁺ with W = a dt² w_c:
            // beyond κ W = 1e12 the branch tests are decided by rounding.
            for (i, &kappa) in self.kappas.iter().enumerate() {
                let wc = match &self.multi {
                    Some(m) => m.diagonal(i),
                    None => self.proj.influence()[self.dy.contacts[i].dof],
                };
                let w = an * wc;
                let max = PENALTY_CONDITION_MAX / w;
                if w > 0.0 && kappa > max {
                    let field = if self.dy.contacts[i].stiffness.is_some() { "stop stiffness" } else { "penalty stiffness" };
                    return Err(SchemeError::PenaltyTooStiff { field, value: kappa, max });
                }
            }
            law = ContactLaw::Penalty { stiffness: self.kappas[0] };
            if let Some(m) = self.multi.take() {
                self.multi = Some(m.with_springs(&self.kappas, an)?);
            }
        }
        self.law = law;
        Ok(self)
    }

    /// Momentum `P^n = M V^n`.
    pub fn momentum(&self) -> &[f64] {
        &self.mom
    }

    /// `R^n = M A^n`.
    pub fn mass_acceleration(&self) -> &[f64] {
        &self.r
    }

    /// The contact force `λ^n` of the last step.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// The parameters.
    pub fn params(&self) -> OneStepParams {
        self.prm
    }

    /// The problem.
    pub fn dynamics(&self) -> &Dynamics {
        &self.dy
    }

    /// Velocity `V^n`: `M⁻¹ P` on the massive dofs; a massless contact node
    /// reports `(u_c^n - u_c^{n-1})/dt` (0 before the first step).
    pub fn velocity(&mut self, out: &mut [f64]) {
        let s = self.dy.massive_start();
        out[s..].copy_from_slice(&self.mom[s..]);
        self.m_massive.solve_in_place(&mut out[s..]);
        if s == 1 {
            out[0] = if self.n == 0 { 0.0 } else { (self.u[0] - self.u_c_prev) / self.dt };
        } else if self.dy.k() > 1 && self.dy.massless_contact() {
            // `rhs` holds U^{n-1} between steps (see `finish_multi`).
            for ct in &self.dy.contacts {
                out[ct.dof] = if self.n == 0 { 0.0 } else { (self.u[ct.dof] - self.rhs[ct.dof]) / self.dt };
            }
        }
    }

    /// The rest of a step with several contacts, from the unconstrained
    /// `y` in `rhs`: the contact solve, then the update of `R` and `P`.
    /// Only the contacts with a force now or at the step before are
    /// visited (an inactive obstacle costs the solver's bound check).
    fn finish_multi(&mut self, an: f64, dt: f64, g: f64) -> Result<StepReport, SchemeError> {
        // `touched`: contacts whose force was nonzero at the step before.
        let mut touched = std::mem::take(&mut self.touched);
        match self.law {
            ContactLaw::Projection if an == 0.0 => {
                self.touched = touched;
                return Err(SchemeError::Structure("an explicit step (β = 0) cannot use the projection: use a penalty law"));
            }
            ContactLaw::Projection | ContactLaw::Penalty { .. } if an > 0.0 => {
                let ms = self.multi.as_mut().expect("built for an implicit step");
                ms.solve(&mut self.rhs)?;
                let (mu, st) = (ms.multipliers(), ms.status());
                for &i in ms.active_set() {
                    if !self.marked[i] {
                        self.marked[i] = true;
                        touched.push(i);
                    }
                }
                for &i in &touched {
                    self.lams[i] = -mu[i] / an;
                    self.acts[i] = st[i];
                }
            }
            _ => {
                // Explicit penalty: the springs act at the new positions.
                for (i, ct) in self.dy.contacts.iter().enumerate() {
                    let (x, kappa) = (self.rhs[ct.dof], self.kappas[i]);
                    let force = kappa * (ct.bounds.lo - x).max(0.0) - kappa * (x - ct.bounds.hi).max(0.0);
                    if force != 0.0 && !self.marked[i] {
                        self.marked[i] = true;
                        touched.push(i);
                    }
                }
                for &i in &touched {
                    let ct = &self.dy.contacts[i];
                    let (x, kappa) = (self.rhs[ct.dof], self.kappas[i]);
                    let force = kappa * (ct.bounds.lo - x).max(0.0) - kappa * (x - ct.bounds.hi).max(0.0);
                    self.lams[i] = -force;
                    self.acts[i] = if force > 0.0 {
                        Active::Lower
                    } else if force < 0.0 {
                        Active::Upper
                    } else {
                        Active::None
                    };
                }
            }
        }
        // After the swap `rhs` holds U^n until the next step (the previous
        // contact displacements, for the work and a massless velocity).
        std::mem::swap(&mut self.u, &mut self.rhs);
        self.n += 1;
        let t = self.time();
        let mut work = 0.0;
        let c0 = self.dy.contacts[0].dof;
        if !(self.u[c0].is_finite() && self.lams[0].is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        for &i in &touched {
            let c = self.dy.contacts[i].dof;
            let (lam, x) = (self.lams[i], self.u[c]);
            if !(x.is_finite() && lam.is_finite()) {
                return Err(SchemeError::NonFinite { step: self.n, time: t });
            }
            work += -0.5 * (self.prev_lams[i] + lam) * (x - self.rhs[c]);
        }
        self.work_c += work;
        self.add_forcing_work();
        self.damped_kinematics(an, dt, g);
        self.update_acceleration_and_momentum(dt, g);
        if self.dy.massless_contact() {
            for ct in &self.dy.contacts {
                self.r[ct.dof] = 0.0;
                self.mom[ct.dof] = 0.0;
            }
        } else {
            for &i in &touched {
                let (c, lam) = (self.dy.contacts[i].dof, self.lams[i]);
                self.r[c] -= lam;
                self.mom[c] -= dt * g * lam;
            }
        }
        // Keep for the next step only the contacts that now carry a force.
        for &i in &touched {
            self.prev_lams[i] = self.lams[i];
        }
        let (lams, acts, marked) = (&self.lams, &self.acts, &mut self.marked);
        touched.retain(|&i| {
            let keep = lams[i] != 0.0 || acts[i] != Active::None;
            marked[i] = keep;
            keep
        });
        self.touched = touched;
        Ok(StepReport { n: self.n, t, lambda: Some((t, self.lams[0])), active: self.acts[0] })
    }

    /// Work of the forcing over the step just taken, `½ (F^n + F^{n+1})ᵀ(U^{n+1} - U^n)`
    /// (the form of the Newmark-CN energy identity), term by term; `s_next`
    /// holds each profile at `t_{n+1}`.
    #[inline]
    fn add_forcing_work(&mut self) {
        for (j, fo) in self.dy.forcing.iter().enumerate() {
            let gdu: f64 = fo.shape.iter().zip(&self.u).zip(&self.u_prev).map(|((g, u1), u0)| g * (u1 - u0)).sum();
            self.work_f += 0.5 * (self.s_now[j] + self.s_next[j]) * gdu;
            self.s_now[j] = self.s_next[j];
        }
    }

    /// With damping, once `U^{n+1}` is in `u` (and `U^n` in `rhs`):
    /// `A^{n+1} = (U^{n+1} - Ũ)/(a dt²)`, `V^{n+1} = Ṽ + γ dt A^{n+1}`,
    /// `C V^{n+1}`, and the damping work `½ (C V^n + C V^{n+1})ᵀ (U^{n+1} - U^n)`.
    #[inline]
    fn damped_kinematics(&mut self, an: f64, dt: f64, g: f64) {
        let (Some(d), Some(cm)) = (&mut self.damp, &self.dy.damping) else { return };
        for ((((a, v), u1), ut), vt) in d.acc.iter_mut().zip(d.vel.iter_mut()).zip(&self.u).zip(&d.ut).zip(&d.vt) {
            *a = (u1 - ut) / an;
            *v = vt + g * dt * *a;
        }
        for ct in self.dy.contacts.iter().filter(|ct| ct.massless) {
            (d.acc[ct.dof], d.vel[ct.dof]) = (0.0, 0.0);
        }
        cm.mul_vec(&d.vel, &mut d.cx);
        let w: f64 = d.cv.iter().zip(&d.cx).zip(&self.u).zip(&self.rhs).map(|(((c0, c1), u1), u0)| (c0 + c1) * (u1 - u0)).sum();
        self.work_d += 0.5 * w;
        std::mem::swap(&mut d.cv, &mut d.cx);
    }

    /// `R^{n+1} = F - K U^{n+1}` and `P^{n+1} = P^n + dt((1-γ) R^n + γ R^{n+1})`
    /// before the contact forces are applied (fused on the bar's
    /// tridiagonal path).
    #[inline(always)]
    fn update_acceleration_and_momentum(&mut self, dt: f64, g: f64) {
        if let Some(d) = &self.damp {
            // R^{n+1} = F - K U^{n+1} - C V^{n+1} (`cv` holds C V^{n+1}).
            self.dy.stiffness.mul_vec(&self.u, &mut self.ku);
            for ((((p, r), f), k), cv) in self.mom.iter_mut().zip(self.r.iter_mut()).zip(&self.f).zip(&self.ku).zip(&d.cv) {
                let rn = f - k - cv;
                *p += dt * ((1.0 - g) * *r + g * rn);
                *r = rn;
            }
        } else if let Some(t) = self.tri.as_ref().filter(|t| t.diagonal) {
            update_momentum_dispatch(t.avx2, t.uniform_k, &t.kd, &t.ks, &self.u, &self.f, &mut self.mom, &mut self.r, dt, g);
        } else if let Some(t) = &self.tri {
            let (mom, r, f) = (&mut self.mom[..], &mut self.r[..], &self.f[..]);
            tri_apply(&t.kd, &t.ks, &self.u, |i, ku| {
                let rn = f[i] - ku;
                mom[i] += dt * ((1.0 - g) * r[i] + g * rn);
                r[i] = rn;
            });
        } else {
            self.dy.stiffness.mul_vec(&self.u, &mut self.ku);
            for (((p, r), f), k) in self.mom.iter_mut().zip(self.r.iter_mut()).zip(&self.f).zip(&self.ku) {
                let rn = f - k;
                *p += dt * ((1.0 - g) * *r + g * rn);
                *r = rn;
            }
        }
    }

    /// The end of a fused step ([`update_forward_energy`]): `R`, `P` with
    /// the contact row's fix, the next step's `b` forward-swept, this
    /// level's energy sums. False (nothing done) off the tridiagonal path.
    fn finish_fused(&mut self, fix: ContactFix, coef: [f64; 3]) -> bool {
        let (Some(t), Some((l_a, _)), Some((l_m, inv_d_m))) = (&self.tri, self.a.tridiagonal_factors(), self.m_massive.tridiagonal_factors()) else { return false };
        let fa = FusedFactors { l_a, l_m, inv_d_m, s: self.dy.massive_start() };
        // `f` is the steady load here (no forcing: `fuse_energy`), the same
        // values as `dy.load`, one stream fewer.
        let (dt, g) = (self.dt, self.prm.gamma);
        self.sums = Some(update_forward_energy_dispatch(t, fa, fix, &self.u, &self.f, &mut self.mom, &mut self.r, &mut self.rhs, dt, g, coef));
        self.ahead = true;
        true
    }

    /// Gives back the problem (to start a two-step scheme).
    pub(crate) fn into_dynamics(self) -> Dynamics {
        self.dy
    }
}

impl Stepper for OneStep {
    stepper_accessors!();

    /// Offered undamped with massive contacts: `U`, `M⁻¹ P`, `R`.
    fn state(&self) -> Option<Vec<f64>> {
        if self.damp.is_some() || self.dy.massless_contact() {
            return None;
        }
        let mut v = self.mom.clone();
        self.m_massive.solve_in_place(&mut v);
        Some(self.u.iter().chain(&v).chain(&self.r).copied().collect())
    }

    fn set_state(&mut self, s: &[f64]) -> Result<(), SchemeError> {
        if self.damp.is_some() || self.dy.massless_contact() {
            return Err(SchemeError::Structure("a damped Newmark/θ scheme or one with a massless contact does not offer its state (set_state)"));
        }
        let n = self.u.len();
        crate::check_state_len(s, 3 * n)?;
        self.u.copy_from_slice(&s[..n]);
        self.dy.mass.mul_vec(&s[n..2 * n], &mut self.mom);
        self.r.copy_from_slice(&s[2 * n..]);
        (self.ahead, self.sums) = (false, None);
        Ok(())
    }

    /// On the bar's tridiagonal path (one contact, no forcing): each step
    /// ends by assembling and forward-sweeping the next step's right-hand
    /// side in one loop with the new level's energy sums (two independent
    /// ordered chains side by side); [`energy`](Stepper::energy) then
    /// returns them. The same bits as without (tested).
    fn fuse_energy(&mut self, on: bool) {
        let tri = self.tri.is_some() && self.a.tridiagonal_factors().is_some() && self.m_massive.tridiagonal_factors().is_some();
        self.fuse_energy = on && tri && self.dy.k() == 1 && self.dy.forcing.is_empty() && self.damp.is_none();
    }

    fn contact_pivots(&self) -> Option<(u64, u64)> {
        self.multi.as_ref().map(|m| (m.pivoting_solves, m.pivots))
    }

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let dt = self.dt;
        let dt2 = dt * dt;
        let (an, ao, g) = (self.prm.a_new * dt2, self.prm.a_old * dt2, self.prm.gamma);
        let c = self.dy.contact().dof;
        if !self.dy.forcing.is_empty() {
            // F = load + s_0 shape_0 + s_1 shape_1 + ..., s_j(t_{n+1}).
            self.u_prev.copy_from_slice(&self.u);
            self.loads.next_into(&mut self.s_next);
            self.f.copy_from_slice(&self.dy.load);
            add_terms(&mut self.f, &self.dy.forcing, 1.0, &self.s_next);
        }
        self.sums = None;
        // b = M U^n + dt P^n + b dt² R^n + a dt² F
        if let (Some(t), Some((l, inv_d))) = (&self.tri, self.a.tridiagonal_factors()) {
            if std::mem::take(&mut self.ahead) {
                // The step before assembled and forward-swept b (`fuse_energy`).
                backward_sweep(l, inv_d, &mut self.rhs);
            } else if !(t.diagonal && diagonal_step_dispatch(t.avx2, t.uniform_m, inv_d, &t.md, &t.ms, &self.u, &self.mom, &self.r, &self.f, [dt, ao, an], &mut self.rhs)) {
                // Bar: b is assembled inside the forward sweep, whose loop-carried
                // dependency leaves the core idle enough to do it for free.
                // (A lumped `A = M` takes one pass instead, but where a
                // product is infinite, NaN or `−0`.)
                forward_backward_fused(l, inv_d, &t.md, &t.ms, &self.u, &self.mom, &self.r, &self.f, [dt, ao, an], &mut self.rhs);
            }
        } else {
            self.dy.mass.mul_vec(&self.u, &mut self.rhs);
            for (((b, p), r), f) in self.rhs.iter_mut().zip(&self.mom).zip(&self.r).zip(&self.f) {
                *b += dt * p + ao * r + an * f;
            }
            if let (Some(d), Some(cm)) = (&mut self.damp, &self.dy.damping) {
                // + C (γ dt Ũ - a dt² Ṽ), Ũ = U + dt V + b dt² A, Ṽ = V + (1-γ) dt A.
                for (((((ut, vt), x), u), v), a) in d.ut.iter_mut().zip(d.vt.iter_mut()).zip(d.cx.iter_mut()).zip(&self.u).zip(&d.vel).zip(&d.acc) {
                    *ut = u + dt * v + ao * a;
                    *vt = v + (1.0 - g) * dt * a;
                    *x = g * dt * *ut - an * *vt;
                }
                cm.mul_vec(&d.cx, &mut self.ku);
                self.rhs.iter_mut().zip(&self.ku).for_each(|(b, k)| *b += k);
            }
            self.a.solve_in_place(&mut self.rhs);
        }
        if self.dy.k() > 1 {
            return self.finish_multi(an, dt, g);
        }
        let (lambda, active) = match self.law {
            ContactLaw::Projection if an == 0.0 => {
                return Err(SchemeError::Structure("an explicit step (β = 0) cannot use the projection: use a penalty law"));
            }
            ContactLaw::Projection => {
                let pr = self.proj.project(&mut self.rhs, self.dy.contacts[0].bounds.lo, self.dy.contacts[0].bounds.hi);
                (-pr.mu / an, pr.active)
            }
            ContactLaw::Penalty { stiffness } => {
                let (force, active) = penalty_solve(&self.proj, &mut self.rhs, self.dy.contacts[0].bounds.lo, self.dy.contacts[0].bounds.hi, stiffness, an)?;
                (-force, active)
            }
        };
        self.u_c_prev = self.u[c];
        std::mem::swap(&mut self.u, &mut self.rhs);
        self.n += 1;
        let t = self.time();
        if !(self.u[c].is_finite() && lambda.is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        self.work_c += -0.5 * (self.lambda + lambda) * (self.u[c] - self.u_c_prev);
        self.add_forcing_work();
        self.lambda = lambda;
        self.damped_kinematics(an, dt, g);
        // `fuse_energy` (the bar's tridiagonal path, one contact, no
        // forcing, no damping): R, P, the contact row, the next step's b,
        // its forward sweep and the energy sums, block by block.
        if !(self.fuse_energy && self.finish_fused(ContactFix { dof: c, massless: self.dy.contacts[0].massless, lambda }, [dt, ao, an])) {
            self.update_acceleration_and_momentum(dt, g);
            // The contact row: the force term (or, massless, R_c = P_c = 0).
            if self.dy.contacts[0].massless {
                self.r[c] = 0.0;
                self.mom[c] = 0.0;
            } else {
                self.r[c] -= lambda;
                self.mom[c] -= dt * g * lambda;
            }
        }
        self.lams[0] = lambda;
        self.acts[0] = active;
        Ok(StepReport { n: self.n, t, lambda: Some((t, lambda)), active })
    }

    /// Work of the time-dependent load and of the contact force, by the
    /// trapezoid rule (for Newmark-CN with the projection, `ΔE = W_f + W_c`
    /// exactly; with a penalty law, `E` includes the spring energy and the
    /// balance shows what the scheme does not conserve).
    fn work(&self) -> Option<(f64, f64)> {
        Some((self.work_f, self.work_c))
    }

    /// `D = Σ ½ (C V^n + C V^{n+1})ᵀ (U^{n+1} - U^n)` (0 undamped): for
    /// Newmark-CN with the projection, `ΔE = W_f + W_c - D` exactly.
    fn dissipation(&self) -> Option<f64> {
        Some(self.work_d)
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        let s = self.dy.massive_start();
        let (kin, pot, load) = match (self.sums, &self.tri, self.m_massive.tridiagonal_factors()) {
            (Some(sums), _, _) => sums,
            (None, Some(t), Some((l, inv_d))) => energy_sums_tri(t.uniform_energy, l, inv_d, s, &self.mom, &t.kd, &t.ks, &self.u, &self.dy.load),
            _ => (self.m_massive.inverse_quad_form(&self.mom[s..]), self.dy.stiffness.quad_form(&self.u), self.dy.load.iter().zip(&self.u).map(|(f, u)| f * u).sum()),
        };
        let spring = match self.law {
            ContactLaw::Projection => 0.0,
            // `kappas` is set with the penalty law (`with_contact_law`).
            ContactLaw::Penalty { .. } => {
                let mut e = 0.0;
                for (i, ct) in self.dy.contacts.iter().enumerate() {
                    let uc = self.u[ct.dof];
                    let (a, b) = ((ct.bounds.lo - uc).max(0.0), (uc - ct.bounds.hi).max(0.0));
                    e += 0.5 * self.kappas[i] * (a * a + b * b);
                }
                e
            }
        };
        Some((self.time(), 0.5 * kin + 0.5 * pot - load + spring))
    }
}

/// The largest `κ W` of a penalty step (see [`OneStep::with_contact_law`]).
const PENALTY_CONDITION_MAX: f64 = 1e12;

/// The penalty step: `x = y_c + W N(x)` with `N(x) = κ(lo - x)⁺ - κ(x - hi)⁺`
/// and `W = a dt² w_c`, solved exactly; then `U = y + a dt² N w`. Returns `N`.
fn penalty_solve(proj: &Projection, y: &mut [f64], lo: f64, hi: f64, kappa: f64, an: f64) -> Result<(f64, Active), SchemeError> {
    let c = proj.dof();
    let mut breaks = [0.0; 2];
    let mut branches = [(0.0, 0.0); 3];
    let mut nb = 0;
    if lo.is_finite() {
        breaks[nb] = lo;
        branches[nb] = (kappa * lo, -kappa);
        nb += 1;
    }
    branches[nb] = (0.0, 0.0);
    if hi.is_finite() {
        breaks[nb] = hi;
        branches[nb + 1] = (kappa * hi, -kappa);
        nb += 1;
    }
    let law = PiecewiseLinear { breaks: &breaks[..nb], branches: &branches[..=nb] };
    let (x, force) = solve_piecewise_linear(y[c], an * proj.wc(), law)?;
    if force == 0.0 {
        return Ok((0.0, Active::None));
    }
    proj.apply(y, an * force, x);
    Ok((force, if force > 0.0 { Active::Lower } else { Active::Upper }))
}

// ---- The registry's rows of this file: newmark, theta, penalty, penalty-cd.

use crate::family::{check, kappa_bound, not_taken, Capabilities, Family, Group, Node, Param, Preset, Refused, SchemeSpec};

/// Newmark(β, γ), contact at `t_{n+1}`; β ∈ (0, 1/2], γ ∈ [1/2, 2β].
pub(crate) static NEWMARK: Family = Family {
    name: "newmark",
    about: "Newmark(β, γ) in momentum form, contact at t_{n+1} (docs/theory.md §4.1)",
    params: &[Param { name: "beta", symbol: "β", syntax: "BETA", allowed: "∈ (0, 1/2]", default: None }, Param { name: "gamma", symbol: "γ", syntax: "GAMMA", allowed: "∈ [1/2, 2β]", default: None }],
    presets: &[
        Preset { name: "newmark-cn", args: &[0.25, 0.5], group: Group::Paper, rank: 0 },
        Preset { name: "newmark-i", args: &[0.5, 1.0], group: Group::Paper, rank: 1 },
        Preset { name: "newmark-ii", args: &[0.5, 0.5], group: Group::Paper, rank: 2 },
    ],
    validate: |a| {
        let (beta, gamma) = (a[0], a[1]);
        check("gamma", gamma, (0.5..=1.0).contains(&gamma), "[1/2, 1]")?;
        check("beta", beta, beta > 0.0 && beta <= 0.5, "(0, 1/2] (β = 0 is explicit: not an implicit Newmark preset)")?;
        check("beta", beta, 2.0 * beta >= gamma, "[γ/2, 1/2] (unconditional stability; conditionally stable implicit Newmark is not offered)")
    },
    capabilities: |_| Capabilities::IMPLICIT,
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(OneStep::new(s.to_string(), dy, OneStepParams::newmark(s.args()[0], s.args()[1]), dt, init)?)),
};

/// The θ-method, θ ∈ [1/2, 1].
pub(crate) static THETA: Family = Family {
    name: "theta",
    about: "θ-method in momentum form (docs/theory.md §4.2)",
    params: &[Param { name: "theta", symbol: "θ", syntax: "THETA", allowed: "∈ [1/2, 1]", default: None }],
    presets: &[Preset { name: "backward-euler", args: &[1.0], group: Group::Paper, rank: 3 }],
    validate: |a| check("theta", a[0], (0.5..=1.0).contains(&a[0]), "[1/2, 1]"),
    capabilities: |_| Capabilities::IMPLICIT,
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(OneStep::new(s.to_string(), dy, OneStepParams::theta(s.args()[0]), dt, init)?)),
};

const GAMMA_P: [Param; 1] = [Param { name: "gamma_p", symbol: "γ_P", syntax: "GAMMA_P", allowed: "> 0", default: None }];

/// Penalised contact `λ = γ_P K_cc min(0, u_c - g)` (for the P1 bar
/// `K_00 = c²/h`: the GetFEM demo's `(γ_P/h) min(0, u_0 - g)` at c = 1) with
/// Newmark-CN solved exactly per step.
pub(crate) static PENALTY: Family = Family {
    name: "penalty",
    about: "penalty spring γ_P K_cc (or a contact's stiffness) with Newmark-CN, solved exactly per step (docs/theory.md §4.6)",
    params: &GAMMA_P,
    presets: &[Preset { name: "penalty-cn", args: &[10.0], group: Group::Peer, rank: 0 }],
    validate: |a| check("gamma_p", a[0], a[0] > 0.0, "finite and > 0"),
    capabilities: |_| Capabilities { stiffness: true, ..Capabilities::IMPLICIT },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| build_penalty(s, dy, dt, init, false),
};

/// The penalty spring with the explicit central difference (β = 0,
/// γ = 1/2): a massive contact node and dt below the exact CFL limit of
/// `(K + κ e_c e_cᵀ, M)`.
pub(crate) static PENALTY_CD: Family = Family {
    name: "penalty-cd",
    about: "penalty spring with the explicit central difference (docs/theory.md §4.6)",
    params: &GAMMA_P,
    presets: &[Preset { name: "penalty-cd", args: &[10.0], group: Group::Peer, rank: 1 }],
    validate: |a| check("gamma_p", a[0], a[0] > 0.0, "finite and > 0"),
    capabilities: |_| Capabilities { explicit: true, node: Node::Massive, damping: false, stiffness: true, ..Capabilities::IMPLICIT },
    cfl_limit: |a, dy| {
        let mut k = dy.stiffness.clone();
        for ct in &dy.contacts {
            let kappa = ct.stiffness.unwrap_or(a[0] * dy.stiffness.get(ct.dof, ct.dof));
            k.add(ct.dof, ct.dof, kappa);
        }
        Ok(Some(2.0 / kappa_bound(&k, &dy.mass)?.sqrt()))
    },
    stability_rule: |_| Some("explicit central difference with a penalty spring: 2/sqrt(κ_max) of the pencil (K + κ e_c e_cᵀ, M)"),
    build: |s, dy, dt, init| build_penalty(s, dy, dt, init, true),
};

fn build_penalty(s: &SchemeSpec, dy: Dynamics, dt: f64, init: &Initial, explicit: bool) -> Result<Box<dyn crate::Stepper>, SchemeError> {
    let gamma_p = s.args()[0];
    let label = s.to_string();
    if explicit && dy.massless_contact() {
        return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped)" });
    }
    let c = dy.contact().dof;
    let kappa = gamma_p * dy.stiffness.get(c, c);
    s.check_cfl(&dy, dt, false)?;
    let prm = if explicit { OneStepParams::newmark(0.0, 0.5) } else { OneStepParams::newmark(0.25, 0.5) };
    let step = OneStep::new(label, dy, prm, dt, init)?;
    Ok(Box::new(step.with_contact_law(ContactLaw::Penalty { stiffness: kappa }).map_err(|e| match e {
        // In the scheme's own parameter: κ = γ_P K_cc.
        SchemeError::PenaltyTooStiff { field: "penalty stiffness", value, max } => SchemeError::PenaltyTooStiff { field: "gamma_p", value: gamma_p, max: max * gamma_p / value },
        e => e,
    })?))
}

impl SchemeSpec {
    /// Newmark(β, γ) (not validated until built).
    pub fn newmark(beta: f64, gamma: f64) -> Self {
        NEWMARK.with(&[beta, gamma])
    }
    /// The θ-method.
    pub fn theta(theta: f64) -> Self {
        THETA.with(&[theta])
    }
    /// The penalty spring `γ_P K_cc` with Newmark-CN (`explicit = false`,
    /// `penalty(G)`) or the explicit central difference (`penalty-cd(G)`).
    pub const fn penalty(gamma_p: f64, explicit: bool) -> Self {
        if explicit {
            PENALTY_CD.with(&[gamma_p])
        } else {
            PENALTY.with(&[gamma_p])
        }
    }
}

/// The damping refusal of the constructors whose schemes take none.
pub(crate) fn no_damping(label: &str) -> SchemeError {
    not_taken(label.to_string(), Refused::Damping, "")
}
