//! Several runs of Schindler and Acary's time-discontinuous Galerkin
//! scheme that share one mass matrix, stepped together (a frequency or
//! amplitude sweep of one scene): the lockstep engine of
//! `d1-minus-linear(e)` and `d1-minus-linear-velocity(e)`, built on the
//! lockstep engines' lane state ([`LaneState`]).
//!
//! Every run ("lane") takes [`D1MinusLinear`]'s half-explicit step
//! (docs/theory.md §4.6.7) on its level ([`D1Level`]): with
//! `a(t, U) = M⁻¹(F_k − K U + Σ_j s_{k,j}(t) shape_{k,j})`,
//!
//! ```text
//! acceleration level: a⁺ = a(t_n, Uⁿ) + λ⁺ M⁻¹e_c on I₂ⁿ,  V₁ = Vⁿ + dt a⁺
//! velocity level:     V₁ = Vⁿ + dt a(t_n, Uⁿ) + μ⁺ M⁻¹e_c on I₁ⁿ
//! Uⁿ⁺¹ = Uⁿ + dt/2 (Vⁿ + V₁);  I₁, I₂, I₃ from u_c of Uⁿ⁺¹ and Uⁿ, v_c of V₁
//! V_f from a(t_{n+1}, Uⁿ⁺¹) and the end's force problem (none if I₃ ≠ ∅)
//! Vⁿ⁺¹ = V_f + Λ M⁻¹e_c,  Newton's law on I₁ with the lane's restitution
//! ```
//!
//! with the same `M`, `K`, `dt`, level and contact dof `c` (so the same
//! factor of `M` and the same column `M⁻¹ e_c`), and its own steady load,
//! forcing terms (their values at the levels), bounds, restitution and
//! initial state. The single run solves its force problems and Newton's
//! law with the several-contacts solve ([`MultiSolve`](crate::MultiSolve));
//! for its one contact each lane solves them with [`OneDof`], that solve's
//! arithmetic for one dof, with two warm-start statuses per lane as the
//! single run has two solves: the force solve's (shared by the start's and
//! the end's force problems) and the impact solve's; a lane whose index set
//! is empty makes no solve (its status is kept), as the single run.
//!
//! The state is stored lane-innermost (`u[i][lane]`, `V`, `a(t_n, Uⁿ)` and
//! the predictor `a⁺` or `V₁`). Undamped, `a(t_n, Uⁿ)` is the last step's
//! `a(t_{n+1}, Uⁿ⁺¹)`, so a step is one banded product and one solve with
//! `M`'s factor. The start's force problem needs only the contact row, so
//! it comes first, and with it the index sets of the step's end (`u_c` of
//! `Uⁿ⁺¹`, `v_c` of `V₁`); the predictor and `Uⁿ⁺¹` are then made row by
//! row just ahead of the forward sweep (`Uⁿ⁺¹`'s rows into the ring
//! `K Uⁿ⁺¹` reads), each right-hand side row `F − K Uⁿ⁺¹ + Σ_j s_j shape_j`
//! eliminated as it is made. When no lane's contact is closed at the end
//! (`I₁ = ∅`: no end force, no impact), `Vⁿ⁺¹` is made row by row inside
//! the backward sweep; else the end's force problem and Newton's law are
//! solved on the contact row of every lane, then `Vⁿ⁺¹` made in one pass.
//! All with the lanes innermost, `L` at a time, compiled for the baseline
//! x86-64 target, AVX2 and AVX-512F (chosen at run time; never FMA). Each
//! lane performs exactly the floating-point operations of
//! [`D1MinusLinear::step`](crate::Stepper::step) for one run (single
//! contact, undamped, massive contact node), in the same order, so every
//! lane is bit-identical to the single run of its data (`Uⁿ`, `Vⁿ`, `λ`
//! and its parts, the closed side, the step at which it fails). The
//! energy is not computed.
//!
//! Supported and refused as for the other engines: half-bandwidth 3 with
//! at least 7 unknowns (the Hermite beam's consistent mass); damping,
//! several contacts, a massless contact, lanes that do not share `M`, `K`
//! (bit for bit), the contact dof or the number of forcing terms, and a
//! lane count outside `1..=L` are refused with a [`SchemeError`]. The
//! step's stability limit is not checked here (the single run does not
//! check it either; the registry's build does). Fewer lanes than `L` are
//! padded with copies of lane 0, whose results are never reported.

// The lane loops index several per-lane arrays by the lane on purpose:
// that is the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use crate::d1minus::{side, INDEX_SET_TOLERANCE};
use crate::lanes::{add_shapes, backward, check_count, check_lanes, chunk, edge, forward, impl_lockstep, interior, lane_into, lockstep_builds, set_lane, Done, LaneState, Refusals, Row7, Rows, RING};
use crate::{Active, D1Level, D1MinusLinear, LockstepLane, Sampler, SchemeError};
use signorini_contact::{ContactError, OneDof, Projection};

/// `L` runs of Schindler and Acary's scheme on one level sharing one mass
/// matrix, stepped together (module docs). Allocates only at construction.
pub struct D1MinusLinearLockstep<const L: usize> {
    /// The lanes' shared state (`Uⁿ` in `state.u`; the factor is `M`'s;
    /// the right-hand side, then `a(t_{n+1}, Uⁿ⁺¹)`, in `state.rhs`; the
    /// ring `t_stiff` holds `Uⁿ⁺¹`'s rows; `state.next` the forcing terms'
    /// values at `t_{n+1}`; `state.acts` the side closed at the step's end,
    /// `I₁`), at level `n` (0 after construction).
    state: LaneState<L>,
    level: D1Level,
    /// `Vⁿ`.
    v: Vec<[f64; L]>,
    /// `a(t_n, Uⁿ)`.
    a: Vec<[f64; L]>,
    /// The last step's predictor: `a⁺` (acceleration level) or `V₁`
    /// (velocity level).
    p: Vec<[f64; L]>,
    /// The contact solve as scalar arithmetic and its column `M⁻¹ e_c`.
    law: OneDof,
    w: Vec<f64>,
    /// Per lane, the side of the start's force problem (`I₂ⁿ` or `I₁ⁿ`)
    /// and of the end's (`I₂` or `I₁`).
    start: [Active; L],
    end: [Active; L],
    /// Per lane, the force solve's status (shared by the start's and the
    /// end's problems) and the impact solve's: their warm starts.
    force_status: [Active; L],
    impact_status: [Active; L],
    /// Per lane, the last step's `Λ`, `λ⁺`, `λ⁻` (`μ⁺`, `μ⁻` on the
    /// velocity level), and whether a contact closed in it (`I₃ ≠ ∅`).
    impulses: [f64; L],
    f_plus: [f64; L],
    f_minus: [f64; L],
    impact: [bool; L],
}

/// The D1MinusLinear engine's structural refusals.
const REFUSALS: Refusals = Refusals {
    damping: "lockstep d1-minus-linear takes undamped problems only (damping: use D1MinusLinear)",
    contacts: "lockstep d1-minus-linear takes exactly one contact (several: use D1MinusLinear)",
    massless: "lockstep d1-minus-linear needs a massive contact node (massless: no D1MinusLinear run takes it)",
    band: "lockstep d1-minus-linear supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)",
};

/// The bounds of a force problem on the closed side `s` (`H a >= 0` or
/// `H V >= 0`, `D1MinusLinear::force_problem`'s).
#[inline(always)]
fn force_bounds(s: Active) -> (f64, f64) {
    if s == Active::Lower {
        (0.0, f64::INFINITY)
    } else {
        (f64::NEG_INFINITY, 0.0)
    }
}

/// One lane's contact solve from its status (updated): the multiplier,
/// and the value `y_c` takes (the bound held, else `y`); an error is
/// recorded as lane `k`'s failure (the single run's) if it has none yet.
#[inline(always)]
fn solve<const L: usize>(law: &OneDof, status: &mut Active, y: f64, (lo, hi): (f64, f64), st: &mut LaneState<L>, k: usize) -> (f64, bool, f64) {
    let mu = match law.solve(status, y, lo, hi) {
        Ok(m) => m,
        Err(e) => {
            fail(st, k, e);
            0.0
        }
    };
    match *status {
        Active::Lower => (mu, true, lo),
        Active::Upper => (mu, true, hi),
        Active::None => (mu, false, y),
    }
}

fn fail<const L: usize>(st: &mut LaneState<L>, k: usize, e: ContactError) {
    if k < st.lanes && st.failed[k].is_none() {
        st.failed[k] = Some(e.into());
    }
}

impl<const L: usize> D1MinusLinearLockstep<L> {
    /// Sets up `lanes.len()` runs (`1..=L`) of the scheme on `level` with
    /// step `dt`, each lane's restitution its own (a contact's own
    /// restitution overriding it, as in [`D1MinusLinear`]); the batch is at
    /// level 0, each lane in its initial state.
    ///
    /// Errors: everything [`D1MinusLinear::at_level`] refuses (per lane),
    /// and [`SchemeError::Size`] for a lane count outside `1..=L`,
    /// [`SchemeError::Invalid`] for a restitution outside `[0, 1]`,
    /// [`SchemeError::Structure`] for damping, several contacts, a massless
    /// contact, a half-bandwidth other than 3 (or fewer than 7 unknowns),
    /// and lanes that differ in `M`, `K`, the contact dof or the number of
    /// forcing terms.
    pub fn new(level: D1Level, dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        check_count::<L>(lanes.len())?;
        check_lanes(&lanes, &REFUSALS)?;
        let single = |ln: &LockstepLane| D1MinusLinear::at_level(level, String::new(), ln.dynamics.clone(), ln.restitution, dt, &ln.initial);
        let first = single(&lanes[0])?;
        let (mf, (law, w)) = first.lockstep_parts().expect("one rigid contact");
        let dy0 = &lanes[0].dynamics;
        // The state's own projection column, as the law's (validated as
        // `Projection` validates it).
        let proj = Projection::new(dy0.contact().dof, w.to_vec())?;
        let state = LaneState::new(dy0, dt, 0, lanes.len(), mf, &proj);
        let zeros = vec![[0.0; L]; dy0.n()];
        let none = [Active::None; L];
        let mut s = Self {
            state,
            level,
            v: zeros.clone(),
            a: zeros.clone(),
            p: zeros,
            law,
            w: w.to_vec(),
            start: none,
            end: none,
            force_status: none,
            impact_status: none,
            impulses: [0.0; L],
            f_plus: [0.0; L],
            f_minus: [0.0; L],
            impact: [false; L],
        };
        for (k, ln) in lanes.iter().enumerate() {
            // What the single run refuses, this lane refuses too; its
            // a(t_0, U⁰) is the lane's.
            let one = single(ln)?;
            let e = ln.dynamics.contact().restitution.unwrap_or(ln.restitution);
            // The single run's values at n dt, n = 0, 1, …
            s.state.add_lane(k, &ln.dynamics, e, &ln.initial.u, |prof| Sampler::values(prof, 0.0, dt));
            set_lane(&mut s.v, k, &ln.initial.v);
            set_lane(&mut s.a, k, one.free_acceleration());
        }
        // Padding lanes copy lane 0 (and its samples, every step).
        s.state.finish(&mut [&mut s.v, &mut s.a]);
        // The values at t = 0 (the single run's first `next_into`, which
        // its a(t_0, U⁰) above took).
        s.state.samples();
        s.start_sets();
        Ok(s)
    }

    /// The level the contact forces are computed on.
    pub fn contact_level(&self) -> D1Level {
        self.level
    }

    /// Lane `k`'s `Vⁿ` into `out` (length [`dofs`](crate::Lockstep::dofs)).
    #[track_caller]
    pub fn velocity_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.v, self.state.lanes, k, out)
    }

    /// Lane `k`'s last impulse `Λ` ([`D1MinusLinear::impulses`]).
    #[track_caller]
    pub fn impulse(&self, k: usize) -> f64 {
        assert!(k < self.state.lanes, "lane {k} of {}", self.state.lanes);
        self.impulses[k]
    }

    /// Lane `k`'s last forces `(λ⁺, λ⁻)` (`(μ⁺, μ⁻)` on the velocity level;
    /// [`D1MinusLinear::forces`]).
    #[track_caller]
    pub fn forces(&self, k: usize) -> (f64, f64) {
        assert!(k < self.state.lanes, "lane {k} of {}", self.state.lanes);
        (self.f_plus[k], self.f_minus[k])
    }

    /// Whether a contact of lane `k` closed in the last step
    /// ([`D1MinusLinear::impact`]).
    #[track_caller]
    pub fn impact(&self, k: usize) -> bool {
        assert!(k < self.state.lanes, "lane {k} of {}", self.state.lanes);
        self.impact[k]
    }

    /// `t_n`: the single run reports the step's mean force at its end.
    fn lambda_time(&self) -> f64 {
        self.state.n as f64 * self.state.dt
    }

    /// The start's index sets from `Uⁿ`, `Vⁿ` (`D1MinusLinear::start_set`):
    /// the closed contacts with `ẏ <= ε` (acceleration level) or all closed
    /// ones (velocity level).
    #[inline(always)]
    fn start_sets(&mut self) {
        let st = &self.state;
        let velocity = self.level == D1Level::Velocity;
        let (uc, vc) = (st.u[st.c], self.v[st.c]);
        for k in 0..L {
            self.start[k] = match side(st.lo[k], st.hi[k], uc[k]) {
                Active::Lower if velocity || vc[k] <= INDEX_SET_TOLERANCE => Active::Lower,
                Active::Upper if velocity || -vc[k] <= INDEX_SET_TOLERANCE => Active::Upper,
                _ => Active::None,
            };
        }
    }

    lockstep_builds!();

    #[inline(always)]
    fn step_body(&mut self) -> usize {
        match self.level {
            D1Level::Acceleration => self.step_at::<false>(),
            D1Level::Velocity => self.step_at::<true>(),
        }
    }

    /// The step on the acceleration level (`VEL` false) or the velocity
    /// level (module docs).
    #[inline(always)]
    fn step_at<const VEL: bool>(&mut self) -> usize {
        let st = &mut self.state;
        let h = st.dt;
        let (c, n) = (st.c, st.dofs);
        // The forcing terms' values at t_{n+1}.
        st.samples();
        // The start's force problem on every lane's contact row: on a⁺ =
        // a(t_n) + λ⁺ M⁻¹e_c, or on V₁ = Vⁿ + h a(t_n) + μ⁺ M⁻¹e_c.
        let (ac, vc, uc) = (self.a[c], self.v[c], st.u[c]);
        let mut held = [false; L];
        let mut pc = [0.0; L];
        for k in 0..L {
            let y = if VEL { vc[k] + h * ac[k] } else { ac[k] };
            (self.f_plus[k], pc[k]) = (0.0, y);
            if self.start[k] != Active::None {
                (self.f_plus[k], held[k], pc[k]) = solve(&self.law, &mut self.force_status[k], y, force_bounds(self.start[k]), st, k);
            }
        }
        // The index sets at the step's end: I₁ from u_c of Uⁿ⁺¹, I₃ from
        // Uⁿ's, the end's force problem's from V₁'s rate.
        let mut any_closed = false;
        for k in 0..L {
            let v1 = if VEL { pc[k] } else { vc[k] + h * pc[k] };
            let x1 = uc[k] + 0.5 * h * (vc[k] + v1);
            let s = side(st.lo[k], st.hi[k], x1);
            st.acts[k] = s;
            let (old_gap, rate) = match s {
                Active::Lower => (uc[k] - st.lo[k], v1),
                Active::Upper => (st.hi[k] - uc[k], -v1),
                Active::None => (0.0, 0.0),
            };
            self.impact[k] = s != Active::None && old_gap > INDEX_SET_TOLERANCE;
            self.end[k] = if s != Active::None && (VEL || rate <= INDEX_SET_TOLERANCE) { s } else { Active::None };
            any_closed |= s != Active::None;
        }
        // The predictor and Uⁿ⁺¹ row by row, each row of
        // M a(t_{n+1}) = F − K Uⁿ⁺¹ + Σ_j s_j shape_j made just ahead of its
        // elimination (the forward sweep of `BandLdlt::solve_p3` with M's factor).
        let mut rows = Predict::<L, VEL> {
            stiff: &st.stiff[..n],
            load: &st.load[..n],
            gs: &st.next[..],
            shape_rows: &st.shape_rows[..],
            t_stiff: &mut st.t_stiff,
            u: &mut st.u[..n],
            v: &self.v[..n],
            a: &self.a[..n],
            p: &mut self.p[..n],
            w: &self.w[..n],
            mu: self.f_plus,
            held,
            pc,
            c,
            h,
        };
        forward::<L, _>(&mut rows, &st.l, &mut st.rhs[..n]);
        if any_closed {
            backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut ());
            self.finish_closed::<VEL>();
        } else {
            // No contact closed at the end on any lane: no end force, no
            // impact; Vⁿ⁺¹ row by row in the backward sweep.
            let mut rows = Finish::<L, VEL> { v: &mut self.v[..n], p: &self.p[..n], h };
            backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut rows);
            self.f_minus = [0.0; L];
            self.impulses = [0.0; L];
        }
        // The next step's a(t_n, Uⁿ): a(t_{n+1}, Uⁿ⁺¹) itself.
        let st = &mut self.state;
        std::mem::swap(&mut self.a, &mut st.rhs);
        st.n += 1;
        for k in 0..L {
            let smooth = if self.impact[k] {
                0.0
            } else if VEL {
                0.5 * self.f_plus[k] + self.f_minus[k]
            } else {
                0.5 * h * (self.f_plus[k] + self.f_minus[k])
            };
            st.lams[k] = -(self.impulses[k] + smooth) / h;
        }
        st.check_finite(Some(&self.v[c]));
        self.start_sets();
        self.state.n
    }

    /// `Vⁿ⁺¹` when some lane's contact is closed at the step's end: on the
    /// contact row of every lane the end's force problem (not where a
    /// contact closed in the step) and Newton's law, then every row.
    #[inline(always)]
    fn finish_closed<const VEL: bool>(&mut self) {
        let st = &mut self.state;
        let (h, c, n) = (st.dt, st.c, st.dofs);
        let (ec, ac, vc, pc) = (st.rhs[c], self.a[c], self.v[c], self.p[c]);
        let (mut held_m, mut held_i) = ([false; L], [false; L]);
        let mut xc = [0.0; L];
        for k in 0..L {
            self.f_minus[k] = 0.0;
            let vf = if self.impact[k] {
                // No contact force: V_f = Vⁿ + h/2 (a(t_n) + a(t_{n+1})).
                self.f_plus[k] = 0.0;
                vc[k] + 0.5 * h * (ac[k] + ec[k])
            } else {
                // a⁻ = a(t_{n+1}) + λ⁻ M⁻¹e_c, or V_f = ½(Vⁿ + V₁) + h/2 a(t_{n+1}) + μ⁻ M⁻¹e_c.
                let mut y = if VEL { 0.5 * (vc[k] + pc[k]) + 0.5 * h * ec[k] } else { ec[k] };
                if self.end[k] != Active::None {
                    (self.f_minus[k], held_m[k], y) = solve(&self.law, &mut self.force_status[k], y, force_bounds(self.end[k]), st, k);
                }
                if VEL {
                    y
                } else {
                    vc[k] + 0.5 * h * (pc[k] + y)
                }
            };
            // Newton's law on I₁: Vⁿ⁺¹ = V_f + Λ M⁻¹e_c.
            (self.impulses[k], xc[k]) = (0.0, vf);
            if st.acts[k] != Active::None {
                let target = -st.e[k] * vf;
                let bounds = if st.acts[k] == Active::Lower { (target, f64::INFINITY) } else { (f64::NEG_INFINITY, target) };
                (self.impulses[k], held_i[k], xc[k]) = solve(&self.law, &mut self.impact_status[k], vf, bounds, st, k);
            }
        }
        let (mu, lam, imp) = (self.f_minus, self.impulses, self.impact);
        for (i, ((vr, (ar, pr)), (er, wi))) in self.v[..n].iter_mut().zip(self.a[..n].iter().zip(&self.p[..n])).zip(st.rhs[..n].iter().zip(&self.w[..n])).enumerate() {
            // Whole rows in, whole row out.
            let (v, a, p, e, wi) = (*vr, *ar, *pr, *er, *wi);
            let mut out = [0.0; L];
            for k in 0..L {
                let vf = if VEL {
                    let t = 0.5 * (v[k] + p[k]) + 0.5 * h * e[k];
                    let t = if held_m[k] { t + mu[k] * wi } else { t };
                    if imp[k] {
                        v[k] + 0.5 * h * (a[k] + e[k])
                    } else {
                        t
                    }
                } else {
                    let am = if held_m[k] { e[k] + mu[k] * wi } else { e[k] };
                    let (b0, b1) = if imp[k] { (a[k], e[k]) } else { (p[k], am) };
                    v[k] + 0.5 * h * (b0 + b1)
                };
                out[k] = if held_i[k] { vf + lam[k] * wi } else { vf };
            }
            // The contact row as solved above (the bounds held).
            *vr = if i == c { xc } else { out };
        }
    }
}

impl_lockstep!(D1MinusLinearLockstep);

/// [`Rows`] of `F − K Uⁿ⁺¹ + Σ_j s_j shape_j` (`accel`'s order: `K U`,
/// `F −` it, then `add_terms` term by term), row `j` of the predictor
/// (`a⁺`, or `V₁` when `VEL`) and of `Uⁿ⁺¹ = Uⁿ + h/2 (Vⁿ + V₁)` made in
/// `prepare` (into `p`, `u` and the ring `K Uⁿ⁺¹` reads).
struct Predict<'a, const L: usize, const VEL: bool> {
    stiff: &'a [Row7],
    load: &'a [[f64; L]],
    gs: &'a [[f64; L]],
    shape_rows: &'a [[f64; L]],
    t_stiff: &'a mut [[f64; L]; RING],
    u: &'a mut [[f64; L]],
    v: &'a [[f64; L]],
    a: &'a [[f64; L]],
    p: &'a mut [[f64; L]],
    w: &'a [f64],
    /// The start's multipliers, the lanes whose problem held, and the
    /// predictor's contact row.
    mu: [f64; L],
    held: [bool; L],
    pc: [f64; L],
    c: usize,
    h: f64,
}

impl<const L: usize, const VEL: bool> Rows<L> for Predict<'_, L, VEL> {
    #[inline(always)]
    fn prepare(&mut self, j: usize) {
        let (a, v, wj, h) = (self.a[j], self.v[j], self.w[j], self.h);
        // `MultiProjection`'s apply: y += μ w on the lanes held, y_c on the bound.
        let mut p = [0.0; L];
        for k in 0..L {
            let y = if VEL { v[k] + h * a[k] } else { a[k] };
            p[k] = if self.held[k] { y + self.mu[k] * wj } else { y };
        }
        if j == self.c {
            p = self.pc;
        }
        let mut u = self.u[j];
        for k in 0..L {
            let v1 = if VEL { p[k] } else { v[k] + h * p[k] };
            u[k] += 0.5 * h * (v[k] + v1);
        }
        self.p[j] = p;
        self.u[j] = u;
        self.t_stiff[j % RING] = u;
    }

    #[inline(always)]
    fn row(&self, i: usize, interior_row: bool) -> [f64; L] {
        let kv = if interior_row { interior::<L>(&self.stiff[i], self.t_stiff, i) } else { edge::<L>(self.stiff, self.t_stiff, i) };
        let f = &self.load[i];
        let mut r = [0.0; L];
        for k in 0..L {
            r[k] = f[k] - kv[k];
        }
        add_shapes(r, self.gs, chunk(self.shape_rows, i, self.gs.len()))
    }
}

/// Each row of `a(t_{n+1})` as the backward sweep gives it, when no lane's
/// contact is closed at the end: `Vⁿ⁺¹ = Vⁿ + h/2 (a⁺ + a(t_{n+1}))`, or
/// `½(Vⁿ + V₁) + h/2 a(t_{n+1})` when `VEL`.
struct Finish<'a, const L: usize, const VEL: bool> {
    v: &'a mut [[f64; L]],
    p: &'a [[f64; L]],
    h: f64,
}

impl<const L: usize, const VEL: bool> Done<L> for Finish<'_, L, VEL> {
    #[inline(always)]
    fn done(&mut self, i: usize, x: &[f64; L]) {
        // Whole rows in, whole row out: no store can alias a load.
        let (mut v, p) = (self.v[i], self.p[i]);
        for k in 0..L {
            v[k] = if VEL { 0.5 * (v[k] + p[k]) + 0.5 * self.h * x[k] } else { v[k] + 0.5 * self.h * (p[k] + x[k]) };
        }
        self.v[i] = v;
    }
}
