//! Paoli–Schatzman two-step scheme with restitution (docs/theory.md §4.3, 2017 paper
//! eq. (34)); with `e = 0` and two-sided bounds it is the β-scheme of the
//! beam between stops (docs/theory.md §4.4).
//!
//! ```text
//! M (U^{n+1} - 2U^n + U^{n-1})/dt² + K (β U^{n+1} + (1-2β) U^n + β U^{n-1}) = F - λ^n e_c
//! lo <= (u_c^{n+1} + e u_c^{n-1})/(1+e) <= hi       (complementary to λ^n)
//! ```
//!
//! i.e. `u_c^{n+1} ∈ [(1+e) lo - e u_c^{n-1}, (1+e) hi - e u_c^{n-1}]`, one
//! projection per step with the same matrix `A = M + β dt² K` as Newmark(β, ·),
//! `μ = -dt² λ^n`. `U^1` comes from one Newmark(β, 1/2) step (Newmark(1/4,
//! 1/2) when β = 0, which the β-scheme allows with a massive contact node:
//! then `A = M`).
//!
//! A time-dependent load enters through exact time averages (docs/theory.md §4.3):
//! `G^n = β f^{n+1} + (1-2β) f^n + β f^{n-1}`, `f^k = 1/dt ∫_{t_k}^{t_{k+1}} F`.
//! The scheme accumulates the work of that load, `W_f = Σ ½ G^nᵀ(U^{n+1} - U^{n-1})`,
//! and of the contact force, `W_c = Σ -½ λ^n (u_c^{n+1} - u_c^{n-1})`, so that
//! (massive contact node) `E^{n+1/2} - E^{1/2} = W_f + W_c` exactly — the
//! discrete energy balance of the beam driven by its support.
//!
//! Massless contact node: row `c` of `M` vanishes and the papers project
//! `K U^n`, `K U^{n-1}` on the orthogonal of `ker M`; row `c` is then the
//! quasi-static equilibrium at `t_{n+1}`, `(K U^{n+1})_c = F_c - λ_{n+1}`,
//! and the reported force belongs to `t_{n+1}` (`μ = -β dt² λ_{n+1}`).
//!
//! Energy at half steps (for any β; docs/theory.md §4.3, balance §7.3):
//! `E^{n+1/2} = ½ VᵀMV + ½ (β - 1/4) dt² VᵀKV + ½ ŪᵀKŪ - FᵀŪ`,
//! `V = (U^{n+1} - U^n)/dt`, `Ū = (U^n + U^{n+1})/2`.
//!
//! Several forcing terms (`F(t) = load + Σ_j shape_j s_j(t)`) each enter
//! with their own exact means, `G^n = Σ_j shape_j (β m_j^{n+1} + (1-2β) m_j^n + β m_j^{n-1})`.
//!
//! Damping ([`crate::Dynamics::damping`]) enters centred,
//!
//! ```text
//! M (U^{n+1} - 2U^n + U^{n-1})/dt² + C (U^{n+1} - U^{n-1})/(2 dt) + K (β U^{n+1} + (1-2β) U^n + β U^{n-1}) = G^n - λ^n e_c
//! ```
//!
//! so the step matrix is `M + dt/2 C + β dt² K` (the contact solve and the
//! restitution law unchanged), and the balance becomes
//! `E^{n+1/2} - E^{1/2} = W_f + W_c - D` with
//! `D = Σ (U^{n+1} - U^{n-1})ᵀ C (U^{n+1} - U^{n-1}) / (4 dt) >= 0`.

use crate::lanes::avx2_available;
use crate::loads::{add_terms, Loads};
use crate::multi::MultiSolve;
use crate::onestep::{same_bits, uniform_interior, with_avx2, Col, OneStep, OneStepParams, Same};
use crate::stabilized::{neighbours, tridiagonal_forward_dispatch, TriRows};
use crate::{Bounds, Dynamics, Forcing, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::{Active, Projection};
use signorini_fem::BandLdlt;
use std::cell::Cell;

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
    /// Work of the forcing since `t_{1/2}` (a `Cell`: [`Stepper::work`]
    /// settles the fused step's pending sum).
    work_forcing: Cell<f64>,
    work_contact: f64,
    /// Work of the damping force since `t_{1/2}` (module docs).
    work_damping: f64,
    /// Per forcing term, the means of its time profile over [t_{n-1}, t_n],
    /// [t_n, t_{n+1}] (rolled each step, so one new mean per step).
    means: Vec<[f64; 2]>,
    /// Per forcing term, its exact means step after step ([`Sampler`]: a
    /// rotation for harmonics, the profile's own `mean` otherwise).
    loads: Loads,
    /// Per forcing term, its coefficient `β m^{n+1} + (1-2β) m^n + β m^{n-1}` of the step.
    g_coefs: Vec<f64>,
    lams: Vec<f64>,
    acts: Vec<Active>,
    /// Several contacts: the exact solve, the contacts whose bounds move
    /// (restitution > 0), those with a force after the last step.
    multi: Option<MultiSolve>,
    moving: Vec<usize>,
    touched: Vec<usize>,
    marked: Vec<bool>,
    /// The characteristic release of `cd-taylor` at Courant number one
    /// (docs/theory.md §4.10): per contact, whether it applies and what the
    /// projection removed from the node's free update at the last step.
    release: Option<Release>,
    /// The explicit step with a diagonal mass, fused (see [`ExplicitDiagonal`]).
    explicit: Option<ExplicitDiagonal>,
    /// Half-bandwidth 3 (the beam): `M` and `K` by diagonals, for the
    /// right-hand side in one vectorised pass (see [`Bands3`]).
    bands: Option<Bands3>,
    /// The beam's fused step ([`FusedStep`]): whether it applies, and whether it is on.
    fused: FusedStep,
    /// The bar's fused step ([`TriStep`]), if it applies, and whether it is on.
    tri: Option<TriStep>,
    tri_on: bool,
    /// [`TriStep`]'s rows set after the sums: a massless contact's
    /// quasi-static row (`β dt² F_c(t_{n+1})`), per contact.
    tri_set: Vec<(usize, f64)>,
    /// Per forcing term, `dt² × g_coefs` (the fused step's weights).
    g_w: Vec<f64>,
    /// The fused step's scratch: the step's new coefficients, and the
    /// last step's work sums, one per forcing term.
    g_next: Vec<f64>,
    /// The next step's coefficients, found by the fused step between its
    /// sweeps (its scratch; rotated into `g_next` at the end of the step).
    g_ahead: Vec<f64>,
    work_acc: Vec<f64>,
    /// The fused step's fourth level: `U^{n−1}` of the step just taken, kept
    /// through the next step so its forcing work is summed beside the sweeps.
    old: Vec<f64>,
    /// The fused step leaves the forcing's work of the step just taken to
    /// the next step, which sums it from `old` beside its backward sweep
    /// (the first term inside it, the others just before it), unless
    /// [`Stepper::work`] is asked first:
    /// then `work` adds it.
    work_pending: Cell<bool>,
    /// `g_next` holds the next step's coefficients already (the fused step
    /// finds them between its two sweeps).
    coefs_ahead: bool,
}

/// The beam's β-step fused (half-bandwidth 3, one massive contact, no
/// damping, no characteristic release): the right-hand side is assembled
/// chunk by chunk inside the forward sweep of the solve
/// ([`Bands3::forward_body`]), then the backward sweep ([`backward_p3`]),
/// all in one function ([`Bands3::unconstrained`]) compiled for AVX2 where
/// the CPU has it — every value the same operations in the same order as
/// the plain path ([`Bands3::rhs`], `add_terms`,
/// [`BandLdlt::solve_in_place`]), so the same bits; the right-hand side's
/// work overlaps the sweep's latency instead of preceding it, and the next
/// step's forcing means (a `sin`) are found between the two sweeps, in the
/// backward sweep's shadow (cost: `crates/run/benches/step.rs`, `beam_beta_scheme_step`
/// against `beam_band_solve`).
#[derive(Clone, Copy, Debug)]
struct FusedStep {
    applies: bool,
    on: bool,
}

/// `M` and `K` of half-bandwidth 3 stored by diagonals (`m[k][i] =
/// M[i][i-k]`), so that the right-hand side's two banded products
/// `M (2U^n − U^{n−1})` and `K ((1−2β) U^n + β U^{n−1})` and the sum
/// `M x + dt² (F − K y)` are one pass over contiguous slices that the
/// compiler vectorises across rows (the row-major product of
/// `SymBand::mul_vec_p3` gathers each row's window). Every row is summed
/// in `mul_vec_p3`'s order — interior rows as
/// `(r₀x_i + r₁x_{i−1} + r₂x_{i−2} + r₃x_{i−3}) + (c₁x_{i+1} + c₂x_{i+2} + c₃x_{i+3})`,
/// the three first and last rows the diagonal term then each neighbour
/// left and right — so the same bits (the lockstep tests compare it with
/// the lockstep kernel's own copy of that arithmetic; cost:
/// `crates/run/benches/step.rs`, `beam_beta_scheme_step`).
/// Compiled for the baseline target and with AVX2, chosen at run time
/// (no FMA in either).
struct Bands3 {
    m: [Vec<f64>; 4],
    k: [Vec<f64>; 4],
    avx2: bool,
}

impl Bands3 {
    fn new(dy: &Dynamics) -> Option<Self> {
        let n = dy.n();
        let applies = n > 6 && dy.mass.half_bandwidth() == 3 && dy.stiffness.half_bandwidth() == 3;
        let avx2 = avx2_available();
        applies.then(|| Self { m: std::array::from_fn(|k| dy.mass.diagonal(k)), k: std::array::from_fn(|k| dy.stiffness.diagonal(k)), avx2 })
    }

    /// `out = M x + dt² (f − K y)`.
    fn rhs(&self, dt2: f64, x: &[f64], y: &[f64], f: &[f64], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only when the CPU reports AVX2.
            return unsafe { self.rhs_avx2(dt2, x, y, f, out) };
        }
        self.rhs_body(dt2, x, y, f, out)
    }

    /// [`rhs_body`](Self::rhs_body) compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn rhs_avx2(&self, dt2: f64, x: &[f64], y: &[f64], f: &[f64], out: &mut [f64]) {
        self.rhs_body(dt2, x, y, f, out)
    }

    /// The whole right-hand side: the three edge rows at each end
    /// ([`edge_row`](Self::edge_row)) and the interior rows
    /// ([`interior`](Self::interior)), the fused step's two pieces.
    #[inline(always)]
    fn rhs_body(&self, dt2: f64, x: &[f64], y: &[f64], f: &[f64], out: &mut [f64]) {
        let n = x.len();
        for i in (0..3).chain(n - 3..n) {
            out[i] = self.edge_row(dt2, x, y, f, i);
        }
        self.interior(dt2, x, y, f, out, 3, n - 6);
    }

    /// Interior rows `a..a + len` of [`rhs_body`](Self::rhs_body)'s
    /// right-hand side (`3 <= a`, `a + len <= n − 3`), the same
    /// arithmetic row by row.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn interior(&self, dt2: f64, x: &[f64], y: &[f64], f: &[f64], out: &mut [f64], a: usize, len: usize) {
        let r = a..a + len;
        let (m0, m1, m2, m3) = (&self.m[0][r.clone()], &self.m[1][r.clone()], &self.m[2][r.clone()], &self.m[3][r.clone()]);
        let (mc1, mc2, mc3) = (&self.m[1][a + 1..a + 1 + len], &self.m[2][a + 2..a + 2 + len], &self.m[3][a + 3..a + 3 + len]);
        let (k0, k1, k2, k3) = (&self.k[0][r.clone()], &self.k[1][r.clone()], &self.k[2][r.clone()], &self.k[3][r.clone()]);
        let (kc1, kc2, kc3) = (&self.k[1][a + 1..a + 1 + len], &self.k[2][a + 2..a + 2 + len], &self.k[3][a + 3..a + 3 + len]);
        let (x0, x1, x2, x3, x4, x5, x6) =
            (&x[a - 3..a - 3 + len], &x[a - 2..a - 2 + len], &x[a - 1..a - 1 + len], &x[a..a + len], &x[a + 1..a + 1 + len], &x[a + 2..a + 2 + len], &x[a + 3..a + 3 + len]);
        let (y0, y1, y2, y3, y4, y5, y6) =
            (&y[a - 3..a - 3 + len], &y[a - 2..a - 2 + len], &y[a - 1..a - 1 + len], &y[a..a + len], &y[a + 1..a + 1 + len], &y[a + 2..a + 2 + len], &y[a + 3..a + 3 + len]);
        let (f, out) = (&f[r.clone()], &mut out[r]);
        for j in 0..len {
            let mx = (m0[j] * x3[j] + m1[j] * x2[j] + m2[j] * x1[j] + m3[j] * x0[j]) + (mc1[j] * x4[j] + mc2[j] * x5[j] + mc3[j] * x6[j]);
            let ky = (k0[j] * y3[j] + k1[j] * y2[j] + k2[j] * y1[j] + k3[j] * y0[j]) + (kc1[j] * y4[j] + kc2[j] * y5[j] + kc3[j] * y6[j]);
            out[j] = mx + dt2 * (f[j] - ky);
        }
    }

    /// An edge row (`i < 3` or `i >= n − 3`) of `M x + dt² (f − K y)`:
    /// `mul_vec_p3`'s `row` closure.
    #[inline(always)]
    fn edge_row(&self, dt2: f64, x: &[f64], y: &[f64], f: &[f64], i: usize) -> f64 {
        #[inline(always)]
        fn row(d: &[Vec<f64>; 4], v: &[f64], i: usize) -> f64 {
            let n = v.len();
            let mut s = d[0][i] * v[i];
            for k in 1..=3 {
                if i >= k {
                    s += d[k][i] * v[i - k];
                }
                if i + k < n {
                    s += d[k][i + k] * v[i + k];
                }
            }
            s
        }
        row(&self.m, x, i) + dt2 * (f[i] - row(&self.k, y, i))
    }

    /// The beam's right-hand side and the forward sweep of its solve in one
    /// pass (see [`FusedStep`]): `out = L⁻¹ (M x + dt² (f − K y) + Σ_j w_j g_j)`
    /// with `A = L D Lᵀ` of half-bandwidth 3.
    /// The fused step's unconstrained `U^{n+1}` into `out`: `x = 2U^n − U^{n−1}`,
    /// `y = (1−2β) U^n + β U^{n−1}` ([`Levels`]), then [`forward_body`](Self::forward_body)
    /// and the factor's backward sweep, in one function compiled for AVX2
    /// where the CPU has it.
    fn unconstrained(&self, fa: Forward<'_>, xy: Levels<'_>, a: &BandLdlt, out: &mut [f64], work: Option<WorkSum<'_>>, between: impl FnOnce()) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only when the CPU reports AVX2.
            return unsafe { self.unconstrained_avx2(fa, xy, a, out, work, between) };
        }
        self.unconstrained_body(fa, xy, a, out, work, between)
    }

    /// [`unconstrained_body`](Self::unconstrained_body) compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn unconstrained_avx2(&self, fa: Forward<'_>, xy: Levels<'_>, a: &BandLdlt, out: &mut [f64], work: Option<WorkSum<'_>>, between: impl FnOnce()) {
        self.unconstrained_body(fa, xy, a, out, work, between)
    }

    /// `between` runs after the forward pass, before the backward sweep:
    /// work independent of the sweeps (the next step's forcing means),
    /// which there runs in the shadow of the sweep's chain instead of
    /// between one step's backward sweep and the next step's forward one;
    /// `work`, a forcing term's work sum, runs inside the backward sweep
    /// ([`backward_p3`]).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn unconstrained_body(&self, fa: Forward<'_>, xy: Levels<'_>, a: &BandLdlt, out: &mut [f64], work: Option<WorkSum<'_>>, between: impl FnOnce()) {
        let Levels { beta, u, up, x, y } = xy;
        for (((t, k), u), up) in x.iter_mut().zip(y.iter_mut()).zip(u).zip(up) {
            *t = 2.0 * u - up;
            *k = (1.0 - 2.0 * beta) * u + beta * up;
        }
        self.forward_body(fa, x, y, out);
        between();
        let (_, lt, inv_d) = a.band_factors();
        backward_p3(lt, inv_d, out, work);
    }

    /// [`edge_row`](Self::edge_row) on the three first rows (`TAIL =
    /// false`) or the three last (`TAIL = true`; `n > 6`), read from windows
    /// of six rows whose bounds the compiler knows ([`row6`]): the same terms
    /// in the same order, with no bounds check and no test per term (the
    /// fused step's; the plain path keeps `edge_row`).
    #[inline(always)]
    fn edge_rows<const TAIL: bool>(&self, dt2: f64, x: &[f64], y: &[f64], f: &[f64]) -> [f64; 3] {
        let a = if TAIL { x.len() - 6 } else { 0 };
        let (m, k) = (&self.m, &self.k);
        let (m, k) = ([six(&m[0], a), six(&m[1], a), six(&m[2], a), six(&m[3], a)], [six(&k[0], a), six(&k[1], a), six(&k[2], a), six(&k[3], a)]);
        let (x, y, f) = (six(x, a), six(y, a), six(f, a));
        let o = if TAIL { 3 } else { 0 };
        [edge6(&m, &k, dt2, x, y, f, o), edge6(&m, &k, dt2, x, y, f, o + 1), edge6(&m, &k, dt2, x, y, f, o + 2)]
    }

    #[inline(always)]
    fn forward_body(&self, fa: Forward<'_>, x: &[f64], y: &[f64], out: &mut [f64]) {
        let Forward { dt2, f, forcing, w, l } = fa;
        let n = x.len();
        let (x, y, f, out, l) = (&x[..n], &y[..n], &f[..n], &mut out[..n], &l[..3 * n]);
        // Each block of rows: the right-hand side, the forcing, the sweep.
        // Rows 0..3: the edge rows, then `solve_p3`'s first rows.
        out[..3].copy_from_slice(&self.edge_rows::<false>(dt2, x, y, f));
        add_forcing(forcing, w, out, 0, 3);
        out[1] -= l[3] * out[0];
        out[2] -= l[7] * out[0] + l[6] * out[1];
        let mut win = (out[2], out[1], out[0]);
        // Interior rows in chunks: a chunk's right-hand side (vectorised
        // across its rows) is independent of the sweep through the chunk
        // before, so the two overlap. Their operands sliced once
        // ([`InteriorRows`]), so a chunk's slices share one bounds check.
        let rows = InteriorRows::new(self, x, y, f);
        let len = n - 6;
        let mut c = 0;
        while c + FUSED_CHUNK <= len {
            let a = 3 + c;
            rows.chunk(dt2, &mut out[a..a + FUSED_CHUNK], c);
            add_forcing(forcing, w, out, a, FUSED_CHUNK);
            sweep_p3(l, out, a, FUSED_CHUNK, &mut win);
            c += FUSED_CHUNK;
        }
        if c < len {
            let (a, rest) = (3 + c, len - c);
            rows.chunk(dt2, &mut out[a..a + rest], c);
            add_forcing(forcing, w, out, a, rest);
            sweep_p3(l, out, a, rest, &mut win);
        }
        out[n - 3..].copy_from_slice(&self.edge_rows::<true>(dt2, x, y, f));
        add_forcing(forcing, w, out, n - 3, 3);
        sweep_p3(l, out, n - 3, 3, &mut win);
    }
}

/// Six rows of `v` from `a` (`a + 6 <= v.len()`).
#[inline(always)]
fn six(v: &[f64], a: usize) -> &[f64; 6] {
    v[a..a + 6].try_into().expect("a window of six rows")
}

/// `edge_row` on row `i` of a window of six rows ([`row6`]).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn edge6(m: &[&[f64; 6]; 4], k: &[&[f64; 6]; 4], dt2: f64, x: &[f64; 6], y: &[f64; 6], f: &[f64; 6], i: usize) -> f64 {
    row6(m, x, i) + dt2 * (f[i] - row6(k, y, i))
}

/// `edge_row`'s `row` on row `i` of a window of six rows (`d[k]` the
/// window of diagonal `k`): its terms are those of the whole matrix when
/// the window is the first six rows (`i < 3`) or the last six (`i >= 3`).
#[inline(always)]
fn row6(d: &[&[f64; 6]; 4], v: &[f64; 6], i: usize) -> f64 {
    let mut s = d[0][i] * v[i];
    for k in 1..=3 {
        if i >= k {
            s += d[k][i] * v[i - k];
        }
        if i + k < 6 {
            s += d[k][i + k] * v[i + k];
        }
    }
    s
}

/// [`InteriorRows`]' bands: a row's diagonal and left neighbours, then its right ones.
#[inline(always)]
fn bands7(d: &[Vec<f64>; 4], len: usize) -> [&[f64]; 7] {
    [&d[0][3..3 + len], &d[1][3..3 + len], &d[2][3..3 + len], &d[3][3..3 + len], &d[1][4..4 + len], &d[2][5..5 + len], &d[3][6..6 + len]]
}

/// [`InteriorRows`]' levels: `v` at `i − 3..=i + 3`.
#[inline(always)]
fn levels7(v: &[f64], len: usize) -> [&[f64]; 7] {
    [&v[..len], &v[1..1 + len], &v[2..2 + len], &v[3..3 + len], &v[4..4 + len], &v[5..5 + len], &v[6..6 + len]]
}

/// [`Bands3::interior`]'s operands on all the interior rows `3..n − 3`,
/// each sliced once a step to their number, `n − 6`: `m[0..4]`, `k[0..4]`
/// the row's diagonal and left neighbours, `m[4..7]`, `k[4..7]` its right
/// neighbours; `x[d]`, `y[d]` the levels at `i + d − 3`.
struct InteriorRows<'a> {
    m: [&'a [f64]; 7],
    k: [&'a [f64]; 7],
    x: [&'a [f64]; 7],
    y: [&'a [f64]; 7],
    f: &'a [f64],
}

impl<'a> InteriorRows<'a> {
    #[inline(always)]
    fn new(b: &'a Bands3, x: &'a [f64], y: &'a [f64], f: &'a [f64]) -> Self {
        let len = x.len() - 6;
        Self { m: bands7(&b.m, len), k: bands7(&b.k, len), x: levels7(x, len), y: levels7(y, len), f: &f[3..3 + len] }
    }

    /// Interior rows `3 + c..3 + c + out.len()` into `out`: [`Bands3::interior`]'s arithmetic.
    #[inline(always)]
    fn chunk(&self, dt2: f64, out: &mut [f64], c: usize) {
        let e = c + out.len();
        let [m0, m1, m2, m3, mc1, mc2, mc3] = self.m;
        let (m0, m1, m2, m3, mc1, mc2, mc3) = (&m0[c..e], &m1[c..e], &m2[c..e], &m3[c..e], &mc1[c..e], &mc2[c..e], &mc3[c..e]);
        let [k0, k1, k2, k3, kc1, kc2, kc3] = self.k;
        let (k0, k1, k2, k3, kc1, kc2, kc3) = (&k0[c..e], &k1[c..e], &k2[c..e], &k3[c..e], &kc1[c..e], &kc2[c..e], &kc3[c..e]);
        let [x0, x1, x2, x3, x4, x5, x6] = self.x;
        let (x0, x1, x2, x3, x4, x5, x6) = (&x0[c..e], &x1[c..e], &x2[c..e], &x3[c..e], &x4[c..e], &x5[c..e], &x6[c..e]);
        let [y0, y1, y2, y3, y4, y5, y6] = self.y;
        let (y0, y1, y2, y3, y4, y5, y6) = (&y0[c..e], &y1[c..e], &y2[c..e], &y3[c..e], &y4[c..e], &y5[c..e], &y6[c..e]);
        let f = &self.f[c..e];
        for j in 0..out.len() {
            let mx = (m0[j] * x3[j] + m1[j] * x2[j] + m2[j] * x1[j] + m3[j] * x0[j]) + (mc1[j] * x4[j] + mc2[j] * x5[j] + mc3[j] * x6[j]);
            let ky = (k0[j] * y3[j] + k1[j] * y2[j] + k2[j] * y1[j] + k3[j] * y0[j]) + (kc1[j] * y4[j] + kc2[j] * y5[j] + kc3[j] * y6[j]);
            out[j] = mx + dt2 * (f[j] - ky);
        }
    }
}

/// What [`Bands3::forward_body`] reads besides the two levels: `M x + dt² (f − K y) + Σ_j w_j g_j`
/// and the factor's `l` ([`BandLdlt::band_factors`]). (The last step's
/// forcing work is summed beside the backward sweep, from a buffer the
/// forward pass does not write: [`WorkSum`] and [`Bands3::unconstrained`]'s `between`.)
struct Forward<'a> {
    dt2: f64,
    f: &'a [f64],
    forcing: &'a [Forcing],
    w: &'a [f64],
    l: &'a [f64],
}

/// The two levels the fused step's right-hand side is made of, and where
/// [`Bands3::unconstrained`] puts `x = 2U^n − U^{n−1}` and `y = (1−2β) U^n + β U^{n−1}`.
struct Levels<'a> {
    beta: f64,
    u: &'a [f64],
    up: &'a [f64],
    x: &'a mut [f64],
    y: &'a mut [f64],
}

/// `add_step_work`'s sums, continued: term by term, `acc_j += g_j[i] (u[i]
/// − old[i])`, rows in order (the fused step's `between`).
#[inline(always)]
fn work_terms(forcing: &[Forcing], u: &[f64], old: &[f64], acc: &mut [f64]) {
    for (fc, s) in forcing.iter().zip(acc.iter_mut()) {
        let mut sum = *s;
        for ((g, x), y) in fc.shape.iter().zip(u).zip(old) {
            sum += g * (x - y);
        }
        *s = sum;
    }
}

/// `add_terms`' arithmetic on rows `a..a + len`: term by term, `out += w_j g_j`.
#[inline(always)]
fn add_forcing(forcing: &[Forcing], w: &[f64], out: &mut [f64], a: usize, len: usize) {
    let out = &mut out[a..a + len];
    for (fc, &wj) in forcing.iter().zip(w) {
        for (b, g) in out.iter_mut().zip(&fc.shape[a..a + len]) {
            *b += wj * g;
        }
    }
}

/// `solve_p3`'s forward rows `a..a + len` (`a >= 3`), the last three
/// results in `win` (`(y_{i−1}, y_{i−2}, y_{i−3})`).
#[inline(always)]
fn sweep_p3(l: &[f64], out: &mut [f64], a: usize, len: usize, win: &mut (f64, f64, f64)) {
    let (mut w1, mut w2, mut w3) = *win;
    for (bi, row) in out[a..a + len].iter_mut().zip(l[3 * a..3 * (a + len)].chunks_exact(3)) {
        let s = (*bi - row[2] * w3 - row[1] * w2) - row[0] * w1;
        w3 = w2;
        w2 = w1;
        w1 = s;
        *bi = s;
    }
    *win = (w1, w2, w3);
}

/// `BandLdlt::backward_in_place`'s sweep at half-bandwidth 3 (`n > 3`),
/// the same operations in the same order, inlined into the fused step (so
/// compiled with it, for AVX2 where the CPU has it). With `work`, one
/// forcing term's work sum ([`work_terms`]' operations, rows in order) is
/// carried in the same loop, a row of it beside each row of the sweep:
/// two independent chains, the sum's in the sweep's shadow, where before
/// the sweep it held the sweep back (its 38 additions in a row, in the
/// out-of-order window ahead of the sweep's first rows).
#[inline(always)]
fn backward_p3(lt: &[f64], inv_d: &[f64], b: &mut [f64], work: Option<WorkSum<'_>>) {
    let n = b.len();
    let (lt, inv_d) = (&lt[..n * 3], &inv_d[..n]);
    // Rows n-3..n have fewer successors.
    b[n - 1] *= inv_d[n - 1];
    b[n - 2] = b[n - 2] * inv_d[n - 2] - lt[(n - 2) * 3] * b[n - 1];
    b[n - 3] = b[n - 3] * inv_d[n - 3] - lt[(n - 3) * 3 + 1] * b[n - 1] - lt[(n - 3) * 3] * b[n - 2];
    let mut x = (b[n - 3], b[n - 2], b[n - 1]);
    let rows = b[..n - 3].iter_mut().rev().zip(lt[..(n - 3) * 3].chunks_exact(3).rev()).zip(inv_d[..n - 3].iter().rev());
    let Some(WorkSum { g, u, old, acc }) = work else {
        for ((bi, col), di) in rows {
            *bi = backward_row(*bi, col, *di, &mut x);
        }
        return;
    };
    // The sum's rows 0..3 here, rows 3..n beside the sweep's rows n−4..=0.
    let (g, u, old) = (&g[..n], &u[..n], &old[..n]);
    let mut sum = *acc;
    for ((gi, ui), oi) in g[..3].iter().zip(&u[..3]).zip(&old[..3]) {
        sum += gi * (ui - oi);
    }
    for ((((bi, col), di), gi), (ui, oi)) in rows.zip(&g[3..]).zip(u[3..].iter().zip(&old[3..])) {
        *bi = backward_row(*bi, col, *di, &mut x);
        sum += gi * (ui - oi);
    }
    *acc = sum;
}

/// A row of [`backward_p3`]'s loop: `(b_i d_i⁻¹ − l₂ x₃ − l₁ x₂) − l₀ x₁`, the
/// window `x = (x₁, x₂, x₃)` moved on by one row.
#[inline(always)]
fn backward_row(bi: f64, col: &[f64], di: f64, x: &mut (f64, f64, f64)) -> f64 {
    let s = (bi * di - col[2] * x.2 - col[1] * x.1) - col[0] * x.0;
    *x = (s, x.0, x.1);
    s
}

/// One forcing term's work sum for [`backward_p3`]: `acc += g[i] (u[i] − old[i])`,
/// rows in order ([`work_terms`] on one term).
struct WorkSum<'a> {
    g: &'a [f64],
    u: &'a [f64],
    old: &'a [f64],
    acc: &'a mut f64,
}

/// The bar's β-step fused (`M`, `K` and the factor of `A` tridiagonal,
/// `L` not the identity, no damping, no characteristic release): the right-hand
/// side `M (2U^n − U^{n−1}) + dt² (F − K ((1−2β) U^n + β U^{n−1})) + Σ_j dt² G_j g_j`
/// made row by row inside the forward sweep of the solve (the shared
/// [`tridiagonal_forward`](crate::stabilized::tridiagonal_forward), as
/// `contact-stabilized`'s), `2U^n − U^{n−1}` and `(1−2β) U^n + β U^{n−1}`
/// computed where a row needs them instead of in two passes of their own,
/// a massless contact's quasi-static row set after the sums, then the
/// factor's backward sweep. Every value is the general path's operations
/// in the same order (its two passes, `SymBand::mul_vec`'s tridiagonal
/// rows, the sum, `add_terms`, the row set,
/// `BandLdlt::solve_in_place`'s sweeps), so the same bits (cost:
/// `crates/run/benches/step.rs`, `implicit_scheme_step`).
type TriStep = crate::stabilized::TriPair;

/// [`TriStep`] of an undamped `dy` (`M`, `K`) beside the factor `a`.
fn tri_step(dy: &Dynamics, a: &BandLdlt) -> Option<TriStep> {
    dy.damping.is_none().then_some(())?;
    TriStep::beside(&dy.mass, &dy.stiffness, a)
}

/// [`TriStep`]'s rows for one step: `M x + dt² (f − K y)`, `x = 2u − up`,
/// `y = (1−2β) u + β up`.
struct PsRows<'a> {
    t: &'a TriStep,
    dt2: f64,
    /// `1 − 2β` and β.
    c: f64,
    beta: f64,
    u: &'a [f64],
    up: &'a [f64],
    f: &'a [f64],
}

impl TriRows for PsRows<'_> {
    #[inline(always)]
    fn interior(&self, a: usize, o: &mut [f64]) {
        let len = o.len();
        let (u, up, c, beta, dt2) = (self.u, self.up, self.c, self.beta, self.dt2);
        let (ul, uc, ur) = neighbours(u, a, len);
        let (pl, pc, pr) = neighbours(up, a, len);
        let (msl, mdc, msr) = self.t.m.window(a, len);
        let (ksl, kdc, ksr) = self.t.k.window(a, len);
        let fr = &self.f[a..a + len];
        for j in 0..len {
            let (xl, xc, xr) = (2.0 * ul[j] - pl[j], 2.0 * uc[j] - pc[j], 2.0 * ur[j] - pr[j]);
            let (yl, yc, yr) = (c * ul[j] + beta * pl[j], c * uc[j] + beta * pc[j], c * ur[j] + beta * pr[j]);
            let mx = msl[j] * xl + mdc[j] * xc + msr[j] * xr;
            let ky = ksl[j] * yl + kdc[j] * yc + ksr[j] * yr;
            o[j] = mx + dt2 * (fr[j] - ky);
        }
    }

    #[inline(always)]
    fn edge(&self, i: usize) -> f64 {
        let (u, up, n) = (self.u, self.up, self.u.len());
        let mx = self.t.m.row(n, i, |j| 2.0 * u[j] - up[j]);
        let ky = self.t.k.row(n, i, |j| self.c * u[j] + self.beta * up[j]);
        mx + self.dt2 * (self.f[i] - ky)
    }
}

/// Rows per chunk of the fused forward pass ([`Bands3::forward_body`]).
const FUSED_CHUNK: usize = 8;

/// The characteristic release rule (docs/theory.md §4.10): at Courant number
/// one the free update of a contact node held at its bound must continue
/// the incoming wave from where it would be had the node been free, so the
/// next free update subtracts what the projection removed at this step.
struct Release {
    /// Per contact: the rule applies (the node and its neighbour are on
    /// d'Alembert's grid, restitution 0).
    on: Vec<bool>,
    /// Per contact: free update minus projected value at the last step.
    shift: Vec<f64>,
    /// Per contact: this step's free update (scratch).
    free: Vec<f64>,
    /// Per contact: the shift applied at this step, `M_cc s / dt²` (the
    /// part of the node's contact force that the shifted free update hides).
    force: Vec<f64>,
}

impl Release {
    /// The rule for `dy` at step `dt`, if some contact qualifies: restitution
    /// 0, no damping, a diagonal mass, and the contact node with its single
    /// neighbour on d'Alembert's grid (`dt² K_cc / M_cc = 2`,
    /// `K_nc = −K_cc`, `dt² K_nn / M_nn = 2`, `dt² K_nc / M_nn = −1`, each to
    /// 1e-9 relative).
    fn for_courant_one(dy: &Dynamics, restitution: f64, dt: f64) -> Option<Self> {
        if dy.damping.is_some() {
            return None;
        }
        let (n, dt2) = (dy.n(), dt * dt);
        let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
        let k = |i: usize, j: usize| if i.abs_diff(j) <= dy.stiffness.half_bandwidth() { dy.stiffness.get(i.max(j), i.min(j)) } else { 0.0 };
        let on: Vec<bool> = dy
            .contacts
            .iter()
            .map(|ct| {
                let c = ct.dof;
                let neighbours: Vec<usize> = (c.saturating_sub(dy.stiffness.half_bandwidth())..n.min(c + dy.stiffness.half_bandwidth() + 1)).filter(|&j| j != c && k(c, j) != 0.0).collect();
                let [nb] = neighbours[..] else { return false };
                let (mc, mn) = (dy.mass.get(c, c), dy.mass.get(nb, nb));
                ct.restitution.unwrap_or(restitution) == 0.0
                    && mc > 0.0
                    && mn > 0.0
                    && near(dt2 * k(c, c) / mc, 2.0)
                    && near(k(nb, c), -k(c, c))
                    && near(dt2 * k(nb, nb) / mn, 2.0)
                    && near(dt2 * k(nb, c) / mn, -1.0)
            })
            .collect();
        let m = on.len();
        on.iter().any(|&b| b).then(|| Release { on, shift: vec![0.0; m], free: vec![0.0; m], force: vec![0.0; m] })
    }
}

/// The central difference (β = 0) with a diagonal mass and a tridiagonal
/// stiffness, one massive contact, no damping and no time-dependent load
/// (`cd-taylor` and `taylor-flanagan` on the lumped bar): the right-hand
/// side and the solve with the diagonal step matrix `A = M` in one pass,
/// `U^{n+1}_i = (M_ii (2U^n_i − U^{n−1}_i) + dt² (F_i − (K U^n)_i)) / M_ii`
/// with `1/M_ii` the factor's own inverse pivot — the general path's
/// operations in the same order (its products with the zero off-diagonals
/// of `M` and of `L` add exact zeros), so the same numbers. On a uniform
/// mesh the interior rows' coefficients are scalars ([`Same`]: the same
/// values in the same operations, the same bits), and the pass is
/// compiled with AVX2 where the CPU has it (no FMA).
struct ExplicitDiagonal {
    m: Vec<f64>,
    /// The sub-diagonal of `M` (zeros), kept so that the energy's sums are
    /// the general path's term for term.
    m_sub: Vec<f64>,
    k_diag: Vec<f64>,
    k_sub: Vec<f64>,
    inv_d: Vec<f64>,
    avx2: bool,
    /// The step's interior rows' `(M_ii, K_{i,i−1}, K_ii, K_{i,i+1},
    /// 1/D_i)`, `i = 1..n−1`, when each is one value on every such row.
    uniform: Option<[Same; 5]>,
    /// The energy's rows `1..n−1`' `(M_ii, M_{i,i−1}, K_ii, K_{i,i−1})`,
    /// likewise.
    uniform_energy: Option<[Same; 4]>,
}

/// The interior rows `1..n−1` of [`ExplicitDiagonal`]'s step, coefficients
/// `(M_ii, K_{i,i−1}, K_ii, K_{i,i+1}, 1/D_i)` as slices or [`Same`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn explicit_interior<C: Col>([mc, ksl, kdc, ksr, dc]: [C; 5], dt2: f64, u: &[f64], up: &[f64], f: &[f64], out: &mut [f64]) {
    let n = u.len();
    let (ul, uc, ur) = (&u[..n - 2], &u[1..n - 1], &u[2..n]);
    let (pc, fc, oc) = (&up[1..n - 1], &f[1..n - 1], &mut out[1..n - 1]);
    for j in 0..n - 2 {
        let ku = (ksl.at(j) * ul[j] + kdc.at(j) * uc[j]) + ksr.at(j) * ur[j];
        oc[j] = (mc.at(j) * (2.0 * uc[j] - pc[j]) + dt2 * (fc[j] - ku)) * dc.at(j);
    }
}

/// The four sums of [`ExplicitDiagonal::energy_sums`] over rows `1..n−1`,
/// coefficients `(M_ii, M_{i,i−1}, K_ii, K_{i,i−1})` as slices or
/// [`Same`], carried in `acc` (`kin`, `stiff_v`, `pot`, `load`) with the
/// previous row's `(V, Ū)` in `prev`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn explicit_energy_rows<C: Col>([mc, msc, kdc, ksc]: [C; 4], dt: f64, u: &[f64], up: &[f64], f: &[f64], acc: &mut [f64; 4], prev: &mut (f64, f64)) {
    let n = u.len();
    let [mut kin, mut stiff_v, mut pot, mut load] = *acc;
    let (mut pv, mut pu) = *prev;
    let (uc, pc, fc) = (&u[1..n - 1], &up[1..n - 1], &f[1..n - 1]);
    for j in 0..n - 2 {
        let v = (uc[j] - pc[j]) / dt;
        let ub = 0.5 * (uc[j] + pc[j]);
        kin += v * (mc.at(j) * v + 2.0 * (0.0 + msc.at(j) * pv));
        stiff_v += v * (kdc.at(j) * v + 2.0 * (0.0 + ksc.at(j) * pv));
        pot += ub * (kdc.at(j) * ub + 2.0 * (0.0 + ksc.at(j) * pu));
        load += fc[j] * ub;
        (pv, pu) = (v, ub);
    }
    *acc = [kin, stiff_v, pot, load];
    *prev = (pv, pu);
}

impl ExplicitDiagonal {
    /// The fused step when it applies.
    fn new(dy: &Dynamics, beta: f64, a: &BandLdlt) -> Option<Self> {
        let n = dy.n();
        let applies = beta == 0.0
            && n >= 3
            && dy.k() == 1
            && !dy.massless_contact()
            && dy.damping.is_none()
            && dy.forcing.is_empty()
            && dy.mass.half_bandwidth() == 1
            && dy.stiffness.half_bandwidth() == 1
            && dy.mass.diagonal(1).iter().all(|x| *x == 0.0);
        let (l, inv_d) = a.tridiagonal_factors()?;
        (applies && l.iter().all(|x| *x == 0.0)).then(|| {
            let (m, m_sub, k_diag, k_sub) = (dy.mass.diagonal(0), dy.mass.diagonal(1), dy.stiffness.diagonal(0), dy.stiffness.diagonal(1));
            let inner = 1..n - 1;
            let uniform = uniform_interior(&k_diag, &k_sub, inv_d, 1).and_then(|[sl, d, sr, e]| Some([same_bits(&m[inner.clone()])?, sl, d, sr, e]));
            let uniform_energy = (|| Some([same_bits(&m[inner.clone()])?, same_bits(&m_sub[inner.clone()])?, same_bits(&k_diag[inner.clone()])?, same_bits(&k_sub[inner.clone()])?]))();
            ExplicitDiagonal { m, m_sub, k_diag, k_sub, inv_d: inv_d.to_vec(), avx2: avx2_available(), uniform, uniform_energy }
        })
    }

    /// `out = U^{n+1}` before the contact projection.
    fn unconstrained(&self, dt2: f64, u: &[f64], up: &[f64], f: &[f64], out: &mut [f64]) {
        let n = u.len();
        let (m, kd, ks, inv_d) = (&self.m[..n], &self.k_diag[..n], &self.k_sub[..n], &self.inv_d[..n]);
        let (up, f, out) = (&up[..n], &f[..n], &mut out[..n]);
        let at = |i: usize, ku: f64| (m[i] * (2.0 * u[i] - up[i]) + dt2 * (f[i] - ku)) * inv_d[i];
        out[0] = at(0, kd[0] * u[0] + ks[1] * u[1]);
        out[n - 1] = at(n - 1, ks[n - 1] * u[n - 2] + kd[n - 1] * u[n - 1]);
        let e = self;
        with_avx2!(self.avx2, fn(e: &ExplicitDiagonal, dt2: f64, u: &[f64], up: &[f64], f: &[f64], out: &mut [f64]) -> () {
            // A uniform mesh's coefficients as scalars (the same values: the same bits).
            match e.uniform {
                Some(cols) => explicit_interior(cols, dt2, u, up, f, out),
                None => {
                    let n = u.len();
                    let cols = [&e.m[1..n - 1], &e.k_sub[1..n - 1], &e.k_diag[1..n - 1], &e.k_sub[2..n], &e.inv_d[1..n - 1]];
                    explicit_interior(cols, dt2, u, up, f, out)
                }
            }
        });
    }

    /// The energy's four sums `(VᵀMV, VᵀKV, ŪᵀKŪ, FᵀŪ)` in one pass, each
    /// accumulated in the order of `SymBand::quad_form` and of the dot
    /// product of the general path (`V = (U^n − U^{n−1})/dt`, `Ū` their
    /// mean): row 0, the rows `1..n−1` ([`explicit_energy_rows`]), row `n−1`.
    fn energy_sums(&self, dt: f64, u: &[f64], up: &[f64], f: &[f64]) -> (f64, f64, f64, f64) {
        let n = u.len();
        let (m, ms, kd, ks, up, f) = (&self.m[..n], &self.m_sub[..n], &self.k_diag[..n], &self.k_sub[..n], &up[..n], &f[..n]);
        let (v, ub) = ((u[0] - up[0]) / dt, 0.5 * (u[0] + up[0]));
        let (mut kin, mut stiff_v, mut pot, mut load) = (0.0, 0.0, 0.0, -0.0);
        kin += v * (m[0] * v + 2.0 * 0.0);
        stiff_v += v * (kd[0] * v + 2.0 * 0.0);
        pot += ub * (kd[0] * ub + 2.0 * 0.0);
        load += f[0] * ub;
        let mut acc = [kin, stiff_v, pot, load];
        let mut prev = (v, ub);
        // A uniform mesh's coefficients as scalars (the same values: the same bits).
        match self.uniform_energy {
            Some(cols) => explicit_energy_rows(cols, dt, u, up, f, &mut acc, &mut prev),
            None => explicit_energy_rows([&m[1..n - 1], &ms[1..n - 1], &kd[1..n - 1], &ks[1..n - 1]], dt, u, up, f, &mut acc, &mut prev),
        }
        let [mut kin, mut stiff_v, mut pot, mut load] = acc;
        let ((pv, pu), l) = (prev, n - 1);
        let (v, ub) = ((u[l] - up[l]) / dt, 0.5 * (u[l] + up[l]));
        kin += v * (m[l] * v + 2.0 * (0.0 + ms[l] * pv));
        stiff_v += v * (kd[l] * v + 2.0 * (0.0 + ks[l] * pv));
        pot += ub * (kd[l] * ub + 2.0 * (0.0 + ks[l] * pu));
        load += f[l] * ub;
        (kin, stiff_v, pot, load)
    }
}

impl PaoliSchatzman {
    /// Sets up the scheme and takes the start step (one Newmark(β, 1/2)
    /// step, so the returned scheme is at level 1). `β = 0` needs a massive
    /// contact node.
    pub fn new(label: String, dy: Dynamics, beta: f64, restitution: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        if beta == 0.0 && dy.massless_contact() {
            return Err(SchemeError::Invalid { field: "beta", value: beta, allowed: "(0, 1/2] with a massless contact node (β = 0 makes the step matrix M singular)" });
        }
        let start_beta = if beta > 0.0 { beta } else { 0.25 };
        let mut start = OneStep::new(label.clone(), dy, OneStepParams::newmark(start_beta, 0.5), dt, init)?;
        let first = start.step()?;
        debug_assert_eq!(first.n, 1);
        let u = start.displacement().to_vec();
        let dy = start.into_dynamics();
        Self::from_levels(label, dy, beta, restitution, dt, init, u)
    }

    /// The central difference (β = 0) started by Taylor's formula instead of
    /// a Newmark step: `U¹ = U⁰ + dt V⁰ + dt²/2 M⁻¹(F(0) − K U⁰ − C V⁰)`,
    /// each contact dof then clamped into its bounds. With the lumped P1
    /// mass at `dx/dt = c` this start is the exact nodal value of
    /// d'Alembert's solution whenever `V⁰` is affine on every pair of
    /// elements around a node (docs/theory.md §4.10). Needs a diagonal mass
    /// matrix with every diagonal entry positive.
    pub fn central_difference_taylor(label: String, dy: Dynamics, restitution: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        let n = dy.n();
        let diagonal = dy.mass.half_bandwidth() == 0 || (1..n).all(|i| (1..=dy.mass.half_bandwidth().min(i)).all(|k| dy.mass.get(i, i - k) == 0.0));
        if !diagonal || (0..n).any(|i| !(dy.mass.get(i, i) > 0.0)) {
            return Err(SchemeError::Structure("the Taylor start needs a diagonal mass matrix with no massless node (mass lumped)"));
        }
        if init.u.len() != n || init.v.len() != n {
            return Err(SchemeError::Invalid { field: "initial state length", value: init.u.len() as f64, allowed: "the number of unknowns" });
        }
        let mut f = dy.load.clone();
        for fc in &dy.forcing {
            let s0 = fc.time.value(0.0);
            f.iter_mut().zip(&fc.shape).for_each(|(a, g)| *a += g * s0);
        }
        let mut ku = vec![0.0; n];
        dy.stiffness.mul_vec(&init.u, &mut ku);
        f.iter_mut().zip(&ku).for_each(|(a, k)| *a -= k);
        if let Some(c) = &dy.damping {
            c.mul_vec(&init.v, &mut ku);
            f.iter_mut().zip(&ku).for_each(|(a, k)| *a -= k);
        }
        let mut u: Vec<f64> = (0..n).map(|i| init.u[i] + dt * init.v[i] + 0.5 * dt * dt * f[i] / dy.mass.get(i, i)).collect();
        let mut release = Release::for_courant_one(&dy, restitution, dt);
        for (i, ct) in dy.contacts.iter().enumerate() {
            let free = u[ct.dof];
            u[ct.dof] = u[ct.dof].clamp(ct.bounds.lo, ct.bounds.hi);
            if let Some(r) = release.as_mut() {
                r.shift[i] = free - u[ct.dof];
            }
        }
        let mut s = Self::from_levels(label, dy, 0.0, restitution, dt, init, u)?;
        s.fused.applies &= release.is_none();
        s.fused.on &= release.is_none();
        if release.is_some() {
            (s.tri, s.tri_on) = (None, false);
        }
        s.release = release;
        Ok(s)
    }

    /// The scheme at level 1 from `U⁰` (`init.u`) and `U¹` (`u`).
    fn from_levels(label: String, dy: Dynamics, beta: f64, restitution: f64, dt: f64, init: &Initial, u: Vec<f64>) -> Result<Self, SchemeError> {
        let n = dy.n();
        let a_mat = dy.step_matrix(0.5 * dt, beta * dt * dt);
        let a = a_mat.factor()?;
        let c = dy.contact().dof;
        let k = dy.k();
        let multi = if k > 1 {
            let mut ms = MultiSolve::new(&dy, &a)?.with_banded(a_mat)?;
            for (i, ct) in dy.contacts.iter().enumerate() {
                (ms.lo[i], ms.hi[i]) = (ct.bounds.lo, ct.bounds.hi);
            }
            Some(ms)
        } else {
            None
        };
        let moving: Vec<usize> = if k > 1 { (0..k).filter(|&i| dy.contacts[i].restitution.unwrap_or(restitution) != 0.0).collect() } else { Vec::new() };
        let mut w = vec![0.0; n];
        w[c] = 1.0;
        a.solve_in_place(&mut w);
        let proj = Projection::new(c, w)?;
        let terms = dy.forcing.len();
        let explicit = ExplicitDiagonal::new(&dy, beta, &a);
        let bands = Bands3::new(&dy);
        let applies = bands.is_some() && k == 1 && !dy.massless_contact() && dy.damping.is_none() && a.half_bandwidth() == 3 && n > 6;
        let tri = if explicit.is_none() { tri_step(&dy, &a) } else { None };
        let tri_set = if dy.massless_contact() { dy.contacts.iter().map(|ct| (ct.dof, 0.0)).collect() } else { Vec::new() };
        Ok(Self {
            label,
            beta,
            restitution,
            dt,
            n: 1,
            dy,
            a,
            proj,
            u_prev: init.u.clone(),
            u,
            rhs: vec![0.0; n],
            tmp: vec![0.0; n],
            ktmp: vec![0.0; n],
            work_forcing: Cell::new(0.0),
            work_contact: 0.0,
            work_damping: 0.0,
            means: vec![[0.0; 2]; terms],
            loads: Loads::none(),
            g_coefs: vec![0.0; terms],
            lams: vec![0.0; k],
            acts: vec![Active::None; k],
            multi,
            moving,
            touched: Vec::with_capacity(k),
            marked: vec![false; k],
            release: None,
            explicit,
            bands,
            fused: FusedStep { applies, on: applies },
            tri_on: tri.is_some(),
            tri,
            tri_set,
            g_w: vec![0.0; terms],
            g_next: vec![0.0; terms],
            g_ahead: vec![0.0; terms],
            work_acc: vec![0.0; terms],
            old: vec![0.0; n],
            work_pending: Cell::new(false),
            coefs_ahead: false,
        }
        .with_means())
    }

    fn with_means(mut self) -> Self {
        let dt = self.dt;
        // Means over [n dt, (n+1) dt], n = 0, 1, …: the first two now, then one
        // per step ([(n+1) dt, (n+2) dt] at level n).
        self.loads = Loads::means(&self.dy, dt);
        let terms = self.dy.forcing.len();
        let (mut first, mut second) = (vec![0.0; terms], vec![0.0; terms]);
        self.loads.next_into(&mut first);
        self.loads.next_into(&mut second);
        for ((m, a), b) in self.means.iter_mut().zip(first).zip(second) {
            *m = [a, b];
        }
        self
    }

    /// After the contact solve (`U^{n+1}` in `rhs`): what the projection
    /// removed from each contact's free update, for the next step.
    fn record_release(&mut self) {
        if let Some(r) = self.release.as_mut() {
            for (i, ct) in self.dy.contacts.iter().enumerate() {
                r.shift[i] = r.free[i] - self.rhs[ct.dof];
            }
        }
    }

    /// Each forcing term's work over the step just taken, `½ g_j G_jᵀ(U^{n+1} - U^{n-1})`,
    /// to `add` in the order of the terms.
    fn step_work_forcing(&self, mut add: impl FnMut(f64)) {
        for (f, gc) in self.dy.forcing.iter().zip(&self.g_coefs) {
            add(0.5 * gc * f.shape.iter().zip(&self.u).zip(&self.rhs).map(|((g, a), b)| g * (a - b)).sum::<f64>());
        }
    }

    /// [`add_step_work`](Self::add_step_work)'s forcing part (all of it
    /// without damping, so on the fused step's path).
    fn add_forcing_work(&self) {
        let mut wf = self.work_forcing.get();
        self.step_work_forcing(|w| wf += w);
        self.work_forcing.set(wf);
    }

    /// Work of the forcing terms over the step just taken, `½ G^nᵀ(U^{n+1} - U^{n-1})`
    /// (`U^{n+1}` in `u`, `U^{n-1}` in `rhs`), and of the damping.
    fn add_step_work(&mut self) {
        self.add_forcing_work();
        if let Some(cm) = &self.dy.damping {
            for ((t, a), b) in self.tmp.iter_mut().zip(&self.u).zip(&self.rhs) {
                *t = a - b;
            }
            self.work_damping += cm.quad_form(&self.tmp) / (4.0 * self.dt);
        }
    }

    /// The rest of a step with several contacts (each with its own
    /// restitution), from the unconstrained `U^{n+1}` in `rhs`. Bounds move
    /// only for contacts with `e > 0`; only contacts with a force now or at
    /// the step before are visited.
    fn finish_multi(&mut self) -> Result<StepReport, SchemeError> {
        let dt2 = self.dt * self.dt;
        let ms = self.multi.as_mut().expect("several contacts");
        for &i in &self.moving {
            let ct = &self.dy.contacts[i];
            let e = ct.restitution.unwrap_or(self.restitution);
            let up = self.u_prev[ct.dof];
            ms.lo[i] = if ct.bounds.lo.is_finite() { (1.0 + e) * ct.bounds.lo - e * up } else { f64::NEG_INFINITY };
            ms.hi[i] = if ct.bounds.hi.is_finite() { (1.0 + e) * ct.bounds.hi - e * up } else { f64::INFINITY };
        }
        ms.solve(&mut self.rhs)?;
        self.record_release();
        std::mem::swap(&mut self.u_prev, &mut self.u);
        std::mem::swap(&mut self.u, &mut self.rhs);
        self.n += 1;
        let t = self.time();
        let ms = self.multi.as_ref().expect("several contacts");
        let (mu, st) = (ms.multipliers(), ms.status());
        for &i in ms.active_set() {
            if !self.marked[i] {
                self.marked[i] = true;
                self.touched.push(i);
            }
        }
        let (scale, t_lambda) = if self.dy.massless_contact() { (self.beta * dt2, t) } else { (dt2, (self.n - 1) as f64 * self.dt) };
        let c0 = self.dy.contacts[0].dof;
        if !self.u[c0].is_finite() {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        let mut work = 0.0;
        for &i in &self.touched {
            let c = self.dy.contacts[i].dof;
            let lam = self.release.as_ref().map_or(-mu[i] / scale, |r| -mu[i] / scale + r.force[i]);
            if !(self.u[c].is_finite() && lam.is_finite()) {
                return Err(SchemeError::NonFinite { step: self.n, time: t });
            }
            work += -0.5 * lam * (self.u[c] - self.rhs[c]);
            self.lams[i] = lam;
            self.acts[i] = st[i];
        }
        self.work_contact += work;
        let (lams, acts, marked) = (&self.lams, &self.acts, &mut self.marked);
        self.touched.retain(|&i| {
            let keep = lams[i] != 0.0 || acts[i] != Active::None;
            marked[i] = keep;
            keep
        });
        self.add_step_work();
        Ok(StepReport { n: self.n, t, lambda: Some((t_lambda, self.lams[0])), active: self.acts[0] })
    }

    /// [`general_unconstrained`](Self::general_unconstrained) on the beam
    /// ([`FusedStep`]).
    fn fused_unconstrained(&mut self) {
        let dt2 = self.dt * self.dt;
        let beta = self.beta;
        // This step's coefficients in `g_next` (found during the last step):
        // `g_coefs` still holds the last step's, for its pending work.
        if !self.coefs_ahead {
            self.advance_coefs();
        }
        // `add_terms`' weights.
        for (w, g) in self.g_w.iter_mut().zip(&self.g_next) {
            *w = dt2 * g;
        }
        // `add_step_work`'s sums start as `Iterator::sum` starts.
        let zero: f64 = std::iter::empty::<f64>().sum();
        self.work_acc.iter_mut().for_each(|s| *s = zero);
        let pending = self.work_pending.take();
        if pending {
            // `rhs` holds the last step's `U^{n−1}`: kept in `old` for its work sum.
            std::mem::swap(&mut self.rhs, &mut self.old);
        }
        let b3 = self.bands.as_ref().expect("the fused step has the bands");
        let (l, _, _) = self.a.band_factors();
        let fa = Forward { dt2, f: &self.dy.load, forcing: &self.dy.forcing, w: &self.g_w, l };
        let xy = Levels { beta, u: &self.u, up: &self.u_prev, x: &mut self.tmp, y: &mut self.ktmp };
        // The next step's coefficients (a `sin` or a rotation per term) into
        // `g_ahead`: independent of the sweeps, found between them, where
        // they overlap the backward sweep's chain.
        // The last step's work: the first term's sum inside the backward
        // sweep, the others' before it.
        let (loads, means, ahead) = (&mut self.loads, &mut self.means, &mut self.g_ahead);
        let (forcing, u, old) = (&self.dy.forcing, &self.u, &self.old);
        let (first, rest) = self.work_acc.split_first_mut().map_or((None, &mut [][..]), |(a, r)| (Some(a), r));
        let work = first.filter(|_| pending).map(|acc| WorkSum { g: &forcing[0].shape, u, old, acc });
        b3.unconstrained(fa, xy, &self.a, &mut self.rhs, work, || {
            if pending {
                work_terms(forcing.get(1..).unwrap_or_default(), u, old, rest);
            }
            Self::roll_coefs(beta, loads, means, ahead)
        });
        if pending {
            let mut wf = self.work_forcing.get();
            for (gc, s) in self.g_coefs.iter().zip(&self.work_acc) {
                wf += 0.5 * gc * s;
            }
            self.work_forcing.set(wf);
        }
        std::mem::swap(&mut self.g_coefs, &mut self.g_next);
        std::mem::swap(&mut self.g_next, &mut self.g_ahead);
        self.coefs_ahead = true;
    }

    /// `out` = the next step's coefficients `β m^{n+1} + (1−2β) m^n + β m^{n−1}`
    /// per forcing term, the means rolled: `general_unconstrained`'s arithmetic.
    fn roll_coefs(beta: f64, loads: &mut Loads, means: &mut [[f64; 2]], out: &mut [f64]) {
        loads.next_into(out);
        for (m, gc) in means.iter_mut().zip(out.iter_mut()) {
            let next = *gc;
            *gc = beta * next + (1.0 - 2.0 * beta) * m[1] + beta * m[0];
            *m = [m[1], next];
        }
    }

    /// The next step's forcing coefficients into `g_next` (the means over the
    /// next step rolled in), `general_unconstrained`'s arithmetic.
    fn advance_coefs(&mut self) {
        Self::roll_coefs(self.beta, &mut self.loads, &mut self.means, &mut self.g_next);
        self.coefs_ahead = true;
    }

    /// The last step's work of the forcing terms, if the fused step left it
    /// to the next one: added now (before `u` or `rhs` change).
    fn settle_work(&mut self) {
        if self.work_pending.take() {
            self.add_forcing_work();
        }
    }

    /// Switches the beam's fused step (`FusedStep`) off or back on (where
    /// it applies; on by default): for tests comparing it with the plain
    /// step, and benchmarks. Changes no result.
    #[doc(hidden)]
    pub fn set_fused(&mut self, on: bool) {
        self.settle_work();
        self.fused.on = on && self.fused.applies;
        self.tri_on = on && self.tri.is_some();
    }

    /// Whether a fused step (the beam's or the bar's) is in use.
    #[doc(hidden)]
    pub fn fused(&self) -> bool {
        self.fused.on || self.tri_on
    }

    /// The beam's kernels (`Bands3`) and the bar's ([`TriStep`]) in their
    /// baseline x86-64 build, AVX2 or not: for tests. Changes no result.
    #[doc(hidden)]
    pub fn portable(mut self) -> Self {
        if let Some(b) = self.bands.as_mut() {
            b.avx2 = false;
        }
        if let Some(t) = self.tri.as_mut() {
            t.avx2 = false;
        }
        self
    }

    /// This step's forcing coefficients into `g_coefs`
    /// (`general_unconstrained`'s and the bar's fused step's).
    fn step_coefs(&mut self) {
        // (found ahead by the fused step if it ran before).
        if std::mem::take(&mut self.coefs_ahead) {
            std::mem::swap(&mut self.g_coefs, &mut self.g_next);
        } else {
            let beta = self.beta;
            self.loads.next_into(&mut self.g_coefs);
            for (m, gc) in self.means.iter_mut().zip(self.g_coefs.iter_mut()) {
                let next = *gc;
                *gc = beta * next + (1.0 - 2.0 * beta) * m[1] + beta * m[0];
                *m = [m[1], next];
            }
        }
    }

    /// A massless contact's quasi-static row at `t_{n+1}`, `β dt² F_c(t_{n+1})`.
    fn massless_row(&self, c: usize) -> f64 {
        let t1 = (self.n + 1) as f64 * self.dt;
        // `load + 0.0` without forcing, `load + term_0` with one: as before.
        let mut fc = self.dy.load[c] + self.dy.forcing.first().map_or(0.0, |f| f.shape[c] * f.time.value(t1));
        for f in self.dy.forcing.iter().skip(1) {
            fc += f.shape[c] * f.time.value(t1);
        }
        self.beta * (self.dt * self.dt) * fc
    }

    /// [`general_unconstrained`](Self::general_unconstrained) on the bar
    /// ([`TriStep`]).
    fn tri_unconstrained(&mut self) {
        let dt2 = self.dt * self.dt;
        let beta = self.beta;
        self.step_coefs();
        // `add_terms`' weights.
        for (w, g) in self.g_w.iter_mut().zip(&self.g_coefs) {
            *w = dt2 * g;
        }
        for i in 0..self.tri_set.len() {
            let c = self.tri_set[i].0;
            self.tri_set[i].1 = self.massless_row(c);
        }
        let tri = self.tri.as_ref().expect("the bar's fused step applies");
        let (l, _) = self.a.tridiagonal_factors().expect("tridiagonal");
        let rows = PsRows { t: tri, dt2, c: 1.0 - 2.0 * beta, beta, u: &self.u, up: &self.u_prev, f: &self.dy.load };
        tridiagonal_forward_dispatch(tri.avx2, &rows, &self.dy.forcing, &[&self.g_w], &self.tri_set, l, &mut self.rhs);
        self.a.backward_in_place(&mut self.rhs);
    }

    /// `rhs = U^{n+1}` before the contact projection, in general: the
    /// right-hand side `M (2U^n − U^{n−1}) − dt² K ((1−2β) U^n + β U^{n−1}) + dt² G^n`
    /// (damping, forcing means, a massless node's quasi-static row), then
    /// the solve with `A`.
    fn general_unconstrained(&mut self) {
        let dt2 = self.dt * self.dt;
        let beta = self.beta;
        if let Some(b3) = &self.bands {
            for (((t, k), u), up) in self.tmp.iter_mut().zip(self.ktmp.iter_mut()).zip(&self.u).zip(&self.u_prev) {
                *t = 2.0 * u - up;
                *k = (1.0 - 2.0 * beta) * u + beta * up;
            }
            b3.rhs(dt2, &self.tmp, &self.ktmp, &self.dy.load, &mut self.rhs);
        } else {
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
        }
        // + dt/2 C U^{n-1} (damping, centred).
        if let Some(cm) = &self.dy.damping {
            cm.mul_vec(&self.u_prev, &mut self.ktmp);
            let half = 0.5 * self.dt;
            self.rhs.iter_mut().zip(&self.ktmp).for_each(|(b, k)| *b += half * k);
        }
        // Time-dependent load: G^n = Σ_j shape_j (β m_{n+1} + (1-2β) m_n + β m_{n-1}).
        // (the means over [t_{n+1}, t_{n+2}] first, into g_coefs).
        self.step_coefs();
        add_terms(&mut self.rhs, &self.dy.forcing, dt2, &self.g_coefs);
        if self.dy.massless_contact() {
            // Row c projected on the orthogonal of ker M: equilibrium at t_{n+1}.
            for ct in &self.dy.contacts {
                self.rhs[ct.dof] = self.massless_row(ct.dof);
            }
        }
        self.a.solve_in_place(&mut self.rhs);
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
    stepper_accessors!();

    /// `(U^n, (U^n − U^{n−1})/dt)`, then with the characteristic release
    /// (`cd-taylor` at Courant number one) the contacts' shifts.
    fn state(&self) -> Option<Vec<f64>> {
        let mut s = self.u.clone();
        s.extend(self.u.iter().zip(&self.u_prev).map(|(u, up)| (u - up) / self.dt));
        if let Some(r) = &self.release {
            s.extend_from_slice(&r.shift);
        }
        Some(s)
    }

    fn set_state(&mut self, s: &[f64]) -> Result<(), SchemeError> {
        let n = self.u.len();
        let shifts = self.release.as_ref().map_or(0, |r| r.shift.len());
        crate::check_state_len(s, 2 * n + shifts)?;
        self.settle_work();
        let (u, rest) = s.split_at(n);
        let (v, shift) = rest.split_at(n);
        self.u.copy_from_slice(u);
        for ((up, u), v) in self.u_prev.iter_mut().zip(u).zip(v) {
            *up = u - self.dt * v;
        }
        if let Some(r) = self.release.as_mut() {
            r.shift.copy_from_slice(shift);
        }
        Ok(())
    }

    fn contact_pivots(&self) -> Option<(u64, u64)> {
        self.multi.as_ref().map(|m| (m.pivoting_solves, m.pivots))
    }

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let dt2 = self.dt * self.dt;
        let beta = self.beta;
        let e = self.dy.contact().restitution.unwrap_or(self.restitution);
        let c = self.dy.contact().dof;
        if let Some(ex) = &self.explicit {
            ex.unconstrained(dt2, &self.u, &self.u_prev, &self.dy.load, &mut self.rhs);
        } else if self.fused.on {
            self.fused_unconstrained();
        } else if self.tri_on {
            self.tri_unconstrained();
        } else {
            self.general_unconstrained();
        }
        if let Some(r) = self.release.as_mut() {
            for (i, ct) in self.dy.contacts.iter().enumerate() {
                let s = if r.on[i] { r.shift[i] } else { 0.0 };
                self.rhs[ct.dof] -= s;
                r.free[i] = self.rhs[ct.dof];
                r.force[i] = self.dy.mass.get(ct.dof, ct.dof) * s / dt2;
            }
        }
        if self.multi.is_some() {
            return self.finish_multi();
        }
        let up_c = self.u_prev[c];
        let Bounds { lo, hi } = self.dy.contact().bounds;
        let lo = (1.0 + e) * lo - e * up_c;
        let hi = if hi.is_finite() { (1.0 + e) * hi - e * up_c } else { f64::INFINITY };
        let pr = self.proj.project(&mut self.rhs, lo, hi);
        self.record_release();
        // Rotate: U^{n-1} <- U^n <- U^{n+1}.
        std::mem::swap(&mut self.u_prev, &mut self.u);
        std::mem::swap(&mut self.u, &mut self.rhs);
        self.n += 1;
        let t = self.time();
        let (lambda, t_lambda) = if self.dy.massless_contact() {
            (-pr.mu / (beta * dt2), t)
        } else {
            // t_{n} computed from its index, as every time level is: `t - dt`
            // can round below an exact level (1.9999999999999998 for 2).
            // The node's contact force: what its shifted free update hides too.
            (self.release.as_ref().map_or(-pr.mu / dt2, |r| -pr.mu / dt2 + r.force[0]), (self.n - 1) as f64 * self.dt)
        };
        if !(self.u[c].is_finite() && lambda.is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        // Work since t_{1/2}: U^{n+1} is now `u`, U^{n-1} is in `rhs` (the
        // fused step adds the forcing's in the next step, beside its backward sweep).
        if self.fused.on {
            self.work_pending.set(true);
        } else {
            self.add_step_work();
        }
        self.work_contact += -0.5 * lambda * (self.u[c] - self.rhs[c]);
        (self.lams[0], self.acts[0]) = (lambda, pr.active);
        Ok(StepReport { n: self.n, t, lambda: Some((t_lambda, lambda)), active: pr.active })
    }

    /// Work of the time-dependent load and of the contact force since
    /// `t_{1/2}` (see the module docs).
    fn work(&self) -> Option<(f64, f64)> {
        if self.work_pending.take() {
            self.add_forcing_work();
        }
        Some((self.work_forcing.get(), self.work_contact))
    }

    /// `D = Σ (U^{n+1} - U^{n-1})ᵀ C (U^{n+1} - U^{n-1}) / (4 dt)` since
    /// `t_{1/2}` (0 undamped): `E^{n+1/2} - E^{1/2} = W_f + W_c - D`.
    fn dissipation(&self) -> Option<f64> {
        Some(self.work_damping)
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        let dt = self.dt;
        if let Some(ex) = &self.explicit {
            let (kin, stiff_v, pot, load) = ex.energy_sums(dt, &self.u, &self.u_prev, &self.dy.load);
            let e = 0.5 * kin + 0.5 * (self.beta - 0.25) * dt * dt * stiff_v + 0.5 * pot - load;
            return Some((self.time() - 0.5 * dt, e));
        }
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

// ---- The registry's rows of this file: ps (the β-scheme, taylor-flanagan) and cd-taylor.

use crate::family::{check, kappa_bound, Capabilities, Family, Group, Node, Param, Preset, SchemeSpec};

/// Paoli–Schatzman / the β-scheme, restitution e ∈ [0, 1], β ∈ [0, 1/2]
/// (β >= 1/4 is unconditionally stable; β < 1/4 needs a massive contact
/// node and dt < 2/sqrt((1-4β) κ_h)).
pub(crate) static PS: Family = Family {
    name: "ps",
    about: "Paoli–Schatzman two-step β-scheme with restitution e (docs/theory.md §4.3); β = 0 is Taylor–Flanagan's central difference",
    params: &[
        Param { name: "e", symbol: "e", syntax: "E", allowed: "∈ [0, 1]", default: None },
        Param { name: "beta", symbol: "β", syntax: "BETA", allowed: "∈ [0, 1/2] (default 1/4; β < 1/4 needs a massive contact node)", default: Some(0.25) },
    ],
    presets: &[
        Preset { name: "ps-e0", args: &[0.0, 0.25], group: Group::Paper, rank: 4 },
        Preset { name: "ps-e0.5", args: &[0.5, 0.25], group: Group::Paper, rank: 5 },
        Preset { name: "ps-e1", args: &[1.0, 0.25], group: Group::Paper, rank: 6 },
        // Taylor–Flanagan: the explicit central difference whose contact
        // force at t_n puts u_c^{n+1} exactly on the obstacle — the two-step
        // Paoli–Schatzman form with β = 0, e = 0 (with lumped mass the
        // correction touches the contact node only, as in the original).
        Preset { name: "taylor-flanagan", args: &[0.0, 0.0], group: Group::Peer, rank: 2 },
    ],
    validate: |a| {
        check("e", a[0], (0.0..=1.0).contains(&a[0]), "[0, 1]")?;
        check("beta", a[1], (0.0..=0.5).contains(&a[1]), "[0, 1/2] (β < 1/4 needs a massive contact node and is conditionally stable)")
    },
    capabilities: |a| Capabilities { explicit: a[1] == 0.0, node: if a[1] < 0.25 { Node::Massive } else { Node::Any }, restitution: true, lockstep: true, ..Capabilities::IMPLICIT },
    cfl_limit: |a, dy| {
        let beta = a[1];
        if beta >= 0.25 {
            return Ok(None);
        }
        if dy.massless_contact() {
            return Ok(Some(0.0));
        }
        let kappa = kappa_bound(&dy.stiffness, &dy.mass)?;
        Ok(Some(crate::beta_scheme_critical_dt(beta, kappa)))
    },
    stability_rule: |a| {
        if a[1] == 0.0 {
            Some("explicit central difference (β = 0): 2/sqrt(κ_max) of the pencil (K, M)")
        } else if a[1] < 0.25 {
            Some("two-step β-scheme with β < 1/4: 2/sqrt((1 - 4β) κ_max) of the pencil (K, M); β >= 1/4 is unconditionally stable")
        } else {
            None
        }
    },
    build: |s, dy, dt, init| {
        let (restitution, beta) = (s.args()[0], s.args()[1]);
        if beta < 0.25 && dy.massless_contact() {
            return Err(SchemeError::MassNotSupported {
                scheme: s.to_string(),
                needs: "a massive contact node (mass std or lumped) when β < 1/4 (with a massless node the β-scheme is unstable for every dt)",
            });
        }
        s.check_cfl(&dy, dt, false)?;
        Ok(Box::new(PaoliSchatzman::new(s.to_string(), dy, beta, restitution, dt, init)?))
    },
};

/// The explicit central difference started by Taylor's formula
/// ([`PaoliSchatzman::central_difference_taylor`]): a diagonal (lumped)
/// mass with a massive contact node, restitution 0, dt up to and including
/// the CFL limit — with the lumped P1 bar, dt = h/c exactly (Courant number
/// one, docs/theory.md §4.10).
pub(crate) static CD_TAYLOR: Family = Family {
    name: "cd-taylor",
    about: "explicit central difference with Taylor's start, dt up to the CFL limit itself (Courant number one; docs/theory.md §4.10)",
    params: &[],
    presets: &[Preset { name: "cd-taylor", args: &[], group: Group::SingleMass, rank: 0 }],
    validate: |_| Ok(()),
    capabilities: |_| Capabilities { explicit: true, node: Node::Massive, diagonal_mass: true, beam: false, ..Capabilities::IMPLICIT },
    cfl_limit: |_, dy| Ok(Some(2.0 / kappa_bound(&dy.stiffness, &dy.mass)?.sqrt())),
    stability_rule: |_| Some("explicit central difference: dt <= 2/sqrt(κ_max) of the pencil (K, M), the limit itself allowed (Courant number one with the lumped P1 bar)"),
    build: |s, dy, dt, init| {
        if dy.massless_contact() {
            return Err(SchemeError::MassNotSupported { scheme: s.to_string(), needs: "a massive contact node and a diagonal mass (mass lumped)" });
        }
        s.check_cfl(&dy, dt, true)?;
        Ok(Box::new(PaoliSchatzman::central_difference_taylor(s.to_string(), dy, 0.0, dt, init)?))
    },
};

impl SchemeSpec {
    /// Paoli–Schatzman with restitution `e` and β (not validated until built).
    pub const fn ps(restitution: f64, beta: f64) -> Self {
        PS.with(&[restitution, beta])
    }
    /// `cd-taylor`: the central difference with Taylor's start.
    pub fn cd_taylor() -> Self {
        CD_TAYLOR.with(&[])
    }
}
