//! Several runs of the nonsmooth generalized-α scheme that share one step
//! matrix, stepped together (a frequency or amplitude sweep of one scene):
//! the lockstep engine of `nsga(ρ∞, e)`, built on the lockstep engines'
//! lane state ([`LaneState`]).
//!
//! Every run ("lane") takes [`Nsga`]'s step (docs/theory.md §4.6.5): the
//! generalized-α predictor `â = (α_f q̈^n − α_m a^n)/(1 − α_m)`,
//! `Û = U^n + dt V^n + dt²((½−β) a^n + β â)`, `V̂ = V^n + dt((1−γ) a^n + γ â)`;
//! the smooth equation `S q̈ = F + Σ_j s_j(t_{n+1}) shape_j − K Û` with
//! `S = M + c β dt² K`, `c = (1−α_f)/(1−α_m)`; the update `U = Û + c β dt² q̈`,
//! `V = V̂ + c γ dt q̈`, `a = â + c q̈`; the position projection onto
//! `[lo, hi]` with the column `S⁻¹ e_c` (multiplier `ν`) and its effect on
//! the smooth part (`q̈ −= ν d/(c β dt²)`, `a −= ν d/(β dt²)`,
//! `V −= ν γ d/(β dt)`, `d = M⁻¹ e_c − S⁻¹ e_c`); then Newton's law on a
//! contact at its bound, `v_c ≥ −e v_c^n` (or `≤` at an upper stop), by the
//! projection of `V` with the column `M⁻¹ e_c`, and `λ = −Λ/dt` at
//! `t_{n+1}`. The lanes share `M`, `K`, ρ∞, `dt` and the contact dof (so
//! the factor of `S` and both columns); each has its own steady load,
//! forcing terms (their values at the levels), bounds, restitution and
//! initial state.
//!
//! The state is stored lane-innermost (`u[i][lane]`, also `V`, `a`, `q̈`):
//! the predictor is made row by row just ahead of the forward sweep (into
//! the ring `K Û` reads), the right-hand side's rows are eliminated as they
//! are made, and the update of `U`, `V`, `a` is done row by row in the
//! backward sweep, all with the lanes innermost, `L` at a time, compiled
//! for the baseline x86-64 target, AVX2 and AVX-512F (chosen at run time;
//! never FMA). Each lane performs exactly the floating-point operations of
//! [`Nsga::step`](crate::Stepper::step) for one run (single contact,
//! undamped, massive contact node; the plain free step, as the single run
//! takes it on the beam), in the same order, so every lane is bit-identical
//! to the single run of its data (`U^n`, `V^n`, `λ`, the active bound, the
//! step at which it turns non-finite). The energy is not computed.
//!
//! Supported and refused as for the other engines: half-bandwidth 3 with
//! at least 7 unknowns; damping, several contacts, a massless contact,
//! lanes that do not share `M`, `K` (bit for bit), the contact dof or the
//! number of forcing terms, and a lane count outside `1..=L` are refused
//! with a [`SchemeError`]. Fewer lanes than `L` are padded with copies of
//! lane 0, whose results are never reported.

// The lane loops index several per-lane arrays by the lane on purpose:
// that is the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use crate::lanes::{
    add_shapes, backward, check_count, check_lanes, chunk, clamp, edge, forward, impl_lockstep, interior, lane_into, lockstep_builds, project_lanes, set_lane, Done, LaneState, Refusals, Row7, Rows,
    RING,
};
use crate::nsga::{chung_hulbert, Predictor};
use crate::{Active, LockstepLane, Nsga, Sampler, SchemeError};

/// `L` runs of the nonsmooth generalized-α scheme sharing one step matrix,
/// stepped together (module docs). Allocates only at construction.
pub struct NsgaLockstep<const L: usize> {
    /// The lanes' shared state (`U^n` in `state.u`; the factor and column
    /// are `S`'s; the right-hand side, then `q̈^{n+1}`, in `state.rhs`; the
    /// ring `t_stiff` holds `Û`; `state.mu` the position multiplier), at
    /// level `n` (0 after construction).
    state: LaneState<L>,
    rho_inf: f64,
    k: Coefficients,
    v: Vec<[f64; L]>,
    a: Vec<[f64; L]>,
    qdd: Vec<[f64; L]>,
    /// `M⁻¹ e_c` and `1/(M⁻¹ e_c)_c` (the velocity projection), and
    /// `d = M⁻¹ e_c − S⁻¹ e_c`.
    wm: Vec<f64>,
    inv_wmc: f64,
    dz: Vec<f64>,
}

/// The step's coefficients, as [`Nsga`] computes them: its `Predictor`'s
/// (one constructor), and `correct_smooth`'s.
#[derive(Clone, Copy)]
struct Coefficients {
    p: Predictor,
    gamma: f64,
    /// `c β dt²`, `β dt²`, `β dt` (the correction's denominators).
    den_q: f64,
    den_a: f64,
    den_v: f64,
}

impl Coefficients {
    fn new(rho_inf: f64, h: f64) -> Self {
        let (am, af, b, g) = chung_hulbert(rho_inf);
        let p = Predictor::of(h, am, af, b, g);
        Self { p, gamma: g, den_q: p.c * b * h * h, den_a: b * h * h, den_v: b * h }
    }
}

/// The nonsmooth generalized-α engine's structural refusals.
const REFUSALS: Refusals = Refusals {
    damping: "lockstep nonsmooth generalized-α takes undamped problems only (damping: no nsga run takes it)",
    contacts: "lockstep nonsmooth generalized-α takes exactly one contact (several: use Nsga)",
    massless: "lockstep nonsmooth generalized-α needs a massive contact node (massless: no nsga run takes it)",
    band: "lockstep nonsmooth generalized-α supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)",
};

impl<const L: usize> NsgaLockstep<L> {
    /// Sets up `lanes.len()` runs (`1..=L`) of the nonsmooth
    /// generalized-α scheme with spectral radius `ρ∞` and step `dt`, each
    /// lane's restitution its own (a contact's own restitution overriding
    /// it, as in [`Nsga`]); the batch is at level 0, each lane in the state
    /// [`Nsga::new`] starts from (`a^0 = q̈^0 = M⁻¹(F(0) − K U^0)`).
    ///
    /// Errors: everything [`Nsga::new`] refuses (per lane), and
    /// [`SchemeError::Size`] for a lane count outside `1..=L`,
    /// [`SchemeError::Invalid`] for ρ∞ or a restitution outside `[0, 1]`,
    /// [`SchemeError::Structure`] for damping, several contacts, a massless
    /// contact, a half-bandwidth other than 3 (or fewer than 7 unknowns),
    /// and lanes that differ in `M`, `K`, the contact dof or the number of
    /// forcing terms.
    pub fn new(rho_inf: f64, dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        check_count::<L>(lanes.len())?;
        if !(0.0..=1.0).contains(&rho_inf) {
            return Err(SchemeError::Invalid { field: "rho_inf", value: rho_inf, allowed: "[0, 1]" });
        }
        check_lanes(&lanes, &REFUSALS)?;
        let single = |ln: &LockstepLane| Nsga::new(String::new(), ln.dynamics.clone(), rho_inf, ln.restitution, dt, &ln.initial);
        let first = single(&lanes[0])?;
        let parts = first.lockstep_parts().expect("one contact");
        let dy0 = &lanes[0].dynamics;
        let n = dy0.n();
        let state = LaneState::new(dy0, dt, 0, lanes.len(), parts.s, parts.proj_u);
        let zeros = vec![[0.0; L]; n];
        let mut s = Self {
            state,
            rho_inf,
            k: Coefficients::new(rho_inf, dt),
            v: zeros.clone(),
            a: zeros.clone(),
            qdd: zeros,
            wm: parts.proj_v.influence().to_vec(),
            // 1/w_c as Projection computes it.
            inv_wmc: 1.0 / parts.proj_v.wc(),
            dz: parts.dz.to_vec(),
        };
        for (k, ln) in lanes.iter().enumerate() {
            // What the single run refuses, this lane refuses too; its
            // initial acceleration is the lane's.
            let one = single(ln)?;
            let p = one.lockstep_parts().expect("one contact");
            let e = ln.dynamics.contact().restitution.unwrap_or(ln.restitution);
            // The single run's values at n dt, n = 0, 1, … (the first, at
            // t = 0, taken by its start).
            s.state.add_lane(k, &ln.dynamics, e, &ln.initial.u, |prof| {
                let mut sp = Sampler::values(prof, 0.0, dt);
                sp.next_value();
                sp
            });
            set_lane(&mut s.v, k, &ln.initial.v);
            set_lane(&mut s.a, k, p.a);
            set_lane(&mut s.qdd, k, p.qdd);
        }
        // Padding lanes copy lane 0 (and its samples, every step).
        s.state.finish(&mut [&mut s.v, &mut s.a, &mut s.qdd]);
        Ok(s)
    }

    /// ρ∞.
    pub fn rho_inf(&self) -> f64 {
        self.rho_inf
    }

    /// Lane `k`'s `V^n` into `out` (length [`dofs`](crate::Lockstep::dofs)).
    #[track_caller]
    pub fn velocity_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.v, self.state.lanes, k, out)
    }

    /// Lane `k`'s acceleration-like variable `a^n` into `out`.
    #[track_caller]
    pub fn acceleration_like_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.a, self.state.lanes, k, out)
    }

    /// `t_n`: the single run reports `λ` at the end of its step.
    fn lambda_time(&self) -> f64 {
        self.state.n as f64 * self.state.dt
    }

    lockstep_builds!();

    #[inline(always)]
    fn step_body(&mut self) -> usize {
        let kc = self.k;
        let st = &mut self.state;
        let c = st.c;
        // v_c^n, the impact law's pre-step velocity.
        let vc0 = self.v[c];
        // The forcing terms' values at t_{n+1} (`add_terms`' scale is 1.0,
        // whose product changes no bit: the values themselves).
        st.samples();
        // S q̈ = F(t_{n+1}) − K Û: the predictor made row by row just ahead
        // of the forward sweep (Û into the ring K Û reads), each row of the
        // right-hand side eliminated as it is made; the update of U, V, a
        // row by row in the backward sweep, as each q̈ row is known.
        let n = st.dofs;
        let mut rows = Predicted {
            stiff: &st.stiff[..n],
            load: &st.load[..n],
            gs: &st.next[..],
            shape_rows: &st.shape_rows[..],
            ring: &mut st.t_stiff,
            u: &mut st.u[..n],
            v: &mut self.v[..n],
            a: &mut self.a[..n],
            q: &self.qdd[..n],
            k: kc,
        };
        forward::<L, _>(&mut rows, &st.l, &mut st.rhs[..n]);
        let mut upd = Update { u: &mut st.u[..n], v: &mut self.v[..n], a: &mut self.a[..n], k: kc };
        backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut upd);
        std::mem::swap(&mut self.qdd, &mut st.rhs);
        // The position projection with S⁻¹ e_c (`Projection::project`).
        let mut xc = [0.0; L];
        for k in 0..L {
            (xc[k], st.acts[k]) = clamp(st.u[c][k], st.lo[k], st.hi[k]);
        }
        project_lanes::<L>(&mut st.u, &st.w, st.inv_wc, c, &xc, &st.acts, &mut st.mu);
        // Its effect on the smooth part (`Nsga::correct_smooth`), on the
        // lanes whose multiplier is not 0.
        let mu = st.mu;
        let mut moved = [false; L];
        for k in 0..L {
            moved[k] = mu[k] != 0.0;
        }
        if moved.iter().any(|&m| m) {
            let (mut kq, mut ka, mut kv) = ([0.0; L], [0.0; L], [0.0; L]);
            for k in 0..L {
                (kq[k], ka[k], kv[k]) = (mu[k] / kc.den_q, mu[k] / kc.den_a, mu[k] * kc.gamma / kc.den_v);
            }
            for (((v, a), q), d) in self.v.iter_mut().zip(self.a.iter_mut()).zip(self.qdd.iter_mut()).zip(&self.dz) {
                correct_row::<L>(v, a, q, *d, &moved, &kq, &ka, &kv);
            }
        }
        // Newton's law on a contact at its bound: the velocity projection
        // with M⁻¹ e_c onto v_c >= -e v_c^n (lower) or <= (upper).
        let mut xv = [0.0; L];
        let mut held = [Active::None; L];
        for k in 0..L {
            let uc = st.u[c][k];
            let (at_lo, at_hi) = (uc <= st.lo[k], uc >= st.hi[k]);
            let target = -st.e[k] * vc0[k];
            let (vlo, vhi) = if at_lo || at_hi { (if at_lo { target } else { f64::NEG_INFINITY }, if at_hi && !at_lo { target } else { f64::INFINITY }) } else { (f64::NEG_INFINITY, f64::INFINITY) };
            (xv[k], held[k]) = clamp(self.v[c][k], vlo, vhi);
        }
        let mut big = [0.0; L];
        project_lanes::<L>(&mut self.v, &self.wm, self.inv_wmc, c, &xv, &held, &mut big);
        for k in 0..L {
            st.lams[k] = -big[k] / kc.p.h;
        }
        st.n += 1;
        st.check_finite(Some(&self.v[c]));
        st.n
    }
}

impl_lockstep!(NsgaLockstep);

/// `Nsga`'s `Predictor::update` on each row of `q̈^{n+1}` as the backward
/// sweep makes it: `U += c β dt² q̈`, `V += c γ dt q̈`, `a += c q̈`.
struct Update<'a, const L: usize> {
    u: &'a mut [[f64; L]],
    v: &'a mut [[f64; L]],
    a: &'a mut [[f64; L]],
    k: Coefficients,
}

impl<const L: usize> Done<L> for Update<'_, L> {
    #[inline(always)]
    fn done(&mut self, i: usize, q: &[f64; L]) {
        update_row::<L>(&mut self.u[i], &mut self.v[i], &mut self.a[i], q, &self.k.p);
    }
}

/// [`Rows`] of `F + Σ_j s_j shape_j − K Û`, the predictor of row `j`
/// (`Nsga`'s `Predictor::apply`: `U`, `V`, `a` become `Û`, `V̂`, `â`) made
/// in place and `Û`'s row copied into the ring.
struct Predicted<'a, const L: usize> {
    stiff: &'a [Row7],
    load: &'a [[f64; L]],
    gs: &'a [[f64; L]],
    shape_rows: &'a [[f64; L]],
    ring: &'a mut [[f64; L]; RING],
    u: &'a mut [[f64; L]],
    v: &'a mut [[f64; L]],
    a: &'a mut [[f64; L]],
    q: &'a [[f64; L]],
    k: Coefficients,
}

impl<const L: usize> Rows<L> for Predicted<'_, L> {
    #[inline(always)]
    fn prepare(&mut self, j: usize) {
        predict_row::<L>(&mut self.u[j], &mut self.v[j], &mut self.a[j], &self.q[j], &mut self.ring[j % RING], &self.k.p);
    }

    #[inline(always)]
    fn row(&self, i: usize, interior_row: bool) -> [f64; L] {
        let kv = if interior_row { interior::<L>(&self.stiff[i], self.ring, i) } else { edge::<L>(self.stiff, self.ring, i) };
        let f = &self.load[i];
        let mut r = [0.0; L];
        for k in 0..L {
            r[k] = f[k] - kv[k];
        }
        add_shapes(r, self.gs, chunk(self.shape_rows, i, self.gs.len()))
    }
}

/// `Nsga`'s `Predictor::apply` on row `j` (`Û`, `V̂`, `â` in place of `U`,
/// `V`, `a`), `Û`'s row also into `ring`. (Whole rows in, whole rows out:
/// no store can alias a load, so the lane loop is vectorised.)
#[inline(always)]
fn predict_row<const L: usize>(u: &mut [f64; L], v: &mut [f64; L], a: &mut [f64; L], q: &[f64; L], ring: &mut [f64; L], p: &Predictor) {
    let (mut un, mut vn, mut an, q) = (*u, *v, *a, *q);
    for k in 0..L {
        let ah = (p.af * q[k] - p.am * an[k]) * p.inv;
        un[k] += p.h * vn[k] + p.hh_a * an[k] + p.hh_b * ah;
        vn[k] += p.h_a * an[k] + p.h_g * ah;
        an[k] = ah;
    }
    (*u, *v, *a, *ring) = (un, vn, an, un);
}

/// `Nsga`'s `Predictor::update` on one row: `U += c β dt² q̈`,
/// `V += c γ dt q̈`, `a += c q̈`.
#[inline(always)]
fn update_row<const L: usize>(u: &mut [f64; L], v: &mut [f64; L], a: &mut [f64; L], q: &[f64; L], p: &Predictor) {
    let (mut un, mut vn, mut an, q) = (*u, *v, *a, *q);
    for k in 0..L {
        un[k] += p.cu * q[k];
        vn[k] += p.cv * q[k];
        an[k] += p.c * q[k];
    }
    (*u, *v, *a) = (un, vn, an);
}

/// `Nsga::correct_smooth` on one row, on the lanes `moved`: `q̈ −= kq d`,
/// `a −= ka d`, `V −= kv d`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn correct_row<const L: usize>(v: &mut [f64; L], a: &mut [f64; L], q: &mut [f64; L], d: f64, moved: &[bool; L], kq: &[f64; L], ka: &[f64; L], kv: &[f64; L]) {
    for k in 0..L {
        q[k] = if moved[k] { q[k] - kq[k] * d } else { q[k] };
        a[k] = if moved[k] { a[k] - ka[k] * d } else { a[k] };
        v[k] = if moved[k] { v[k] - kv[k] * d } else { v[k] };
    }
}
