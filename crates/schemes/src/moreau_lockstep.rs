//! Several runs of the Moreau–Jean scheme that share one step matrix,
//! stepped together (a frequency or amplitude sweep of one scene): the
//! lockstep engine of `moreau-jean(θ, e, γ)`, built like
//! [`PaoliSchatzmanLockstep`](crate::PaoliSchatzmanLockstep).
//!
//! Every run ("lane") integrates [`MoreauJean`]'s step
//!
//! ```text
//! (M + θ²dt²K) V^{n+1} = M V^n - dt K (U^n + θ(1-θ) dt V^n) + dt F_k + Σ_j dt s_{k,j}^n shape_{k,j} + p e_c,
//! U^{n+1} = U^n + dt ((1-θ) V^n + θ V^{n+1}),
//! if u_c^n + γ dt v_c^n <= lo_k:  v_c^{n+1} >= -e_k v_c^n (p >= 0, complementary);
//! else if it is >= hi_k:          v_c^{n+1} <= -e_k v_c^n;    else p = 0,
//! ```
//!
//! with the same `M`, `K`, `θ`, `γ`, `dt` and contact dof `c` (so the same
//! factor of `M + θ²dt²K` and the same projection column `w = A⁻¹ e_c`),
//! and its own steady load `F_k`, forcing terms (`s_{k,j}^n` the exact mean
//! of its profile over `[t_n, t_{n+1}]`), bounds, restitution and initial
//! state `U^0, V^0`.
//!
//! The state is stored lane-innermost, `u[i][lane]`, `v[i][lane]`, and the
//! step is [`PaoliSchatzmanLockstep`](crate::PaoliSchatzmanLockstep)'s
//! machinery with Moreau–Jean's vectors: the two banded products (`M V^n`
//! and `K (U^n + θ(1-θ) dt V^n)`, the latter's argument made row by row
//! into a ring just ahead of the forward sweep), the forward and backward
//! substitutions of the shared factor, the velocity-level impact law on
//! every lane, and the update of `U`, all with the lanes innermost, `L` at a
//! time, compiled for the baseline x86-64 target, AVX2 and AVX-512F (the
//! widest the CPU has, chosen at run time; never FMA). Each lane performs
//! exactly the floating-point operations of [`MoreauJean::step`](crate::Stepper::step)
//! for one run (single contact, undamped, massive contact node, no index
//! set), in the same order, so every lane is bit-identical to the single
//! run of its data (`U^n`, `λ`, the active bound, the step at which it turns
//! non-finite). The energy is not computed.
//!
//! Supported and refused as for the Paoli–Schatzman engine: half-bandwidth
//! 3 with at least 7 unknowns; damping, several contacts, a massless
//! contact, lanes that do not share `M`, `K` (bit for bit), the contact
//! dof or the number of forcing terms, and a lane count outside `1..=L` are
//! refused with a [`SchemeError`]. Fewer lanes than `L` are padded with
//! copies of lane 0, whose results are never reported.
//!
//! [`MoreauJeanLockstep::projected`] is the engine of
//! `moreau-jean-projected(θ, e, γ)` ([`MoreauJeanProjected`](crate::MoreauJeanProjected)):
//! the same step with the single run's index set kept per lane (a side
//! joins when `u_c + γ dt v_c − lo <= 1e-7`, or `hi − (u_c + γ dt v_c)`,
//! leaves when that is `> 1e-7` with a non-negative rate) in place of the
//! plain prediction, and after it, on the lanes whose sides in the set are
//! violated by more than `1e-8`, `u_c` clamped on their bounds (the
//! positions' projection; a lane's failure is checked before it, as the
//! single run's report is made before it). Each lane is the single
//! `MoreauJeanProjected` run bit for bit.

// The lane loops index several per-lane arrays by the lane on purpose:
// that is the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use crate::lanes::{backward, check_count, check_lanes, column, forward, impl_lockstep, lane_into, lockstep_builds, project_lanes, set_lane, Combine, Done, LaneState, Refusals, TwoProducts};
use crate::moreau_projected::{INDEX_SET_THRESHOLD, PROJECTION_TOLERANCE};
use crate::{Active, LockstepLane, MoreauJean, Sampler, SchemeError};

/// `L` runs of the Moreau–Jean scheme sharing one step matrix, stepped
/// together (module docs). Allocates only at construction.
pub struct MoreauJeanLockstep<const L: usize> {
    /// The lanes' shared state (`U^n` in `state.u`, the right-hand side and
    /// then `V^{n+1}` in `state.rhs`; the rings hold `V^n` and
    /// `U^n + θ(1-θ) dt V^n`), at level `n` (0 after construction).
    state: LaneState<L>,
    theta: f64,
    gamma: f64,
    v: Vec<[f64; L]>,
    /// Per forcing term: `dt s` with `s` the mean over `[t_n, t_{n+1}]`.
    dt_s: Vec<[f64; L]>,
    /// The contacts predicted active at their lower, upper stop this step.
    at_lo: [bool; L],
    at_hi: [bool; L],
    /// `moreau-jean-projected`'s index set (per lane, its lower and its
    /// upper side in the set), kept from step to step; `None` for
    /// `moreau-jean`.
    sides: Option<([bool; L], [bool; L])>,
}

/// The Moreau–Jean engine's structural refusals.
const REFUSALS: Refusals = Refusals {
    damping: "lockstep Moreau–Jean takes undamped problems only (damping: use MoreauJean)",
    contacts: "lockstep Moreau–Jean takes exactly one contact (several: use MoreauJean)",
    massless: "lockstep Moreau–Jean needs a massive contact node (massless: use MoreauJean)",
    band: "lockstep Moreau–Jean supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)",
};

impl<const L: usize> MoreauJeanLockstep<L> {
    /// Sets up `lanes.len()` runs (`1..=L`) of the Moreau–Jean scheme with
    /// parameters `θ`, the activation predictor's `γ` and step `dt`, each
    /// lane's restitution its own (a contact's own restitution overriding
    /// it, as in [`MoreauJean`]); the batch is at level 0.
    ///
    /// Errors: everything [`MoreauJean::new`] refuses (per lane), and
    /// [`SchemeError::Size`] for a lane count outside `1..=L`,
    /// [`SchemeError::Invalid`] for θ outside `[1/2, 1]`, γ or a restitution
    /// outside `[0, 1]`, [`SchemeError::Structure`] for damping, several
    /// contacts, a massless contact, a half-bandwidth other than 3 (or fewer
    /// than 7 unknowns), and lanes that differ in `M`, `K`, the contact dof
    /// or the number of forcing terms.
    pub fn new(theta: f64, gamma: f64, dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        check_count::<L>(lanes.len())?;
        if !(0.5..=1.0).contains(&theta) {
            return Err(SchemeError::Invalid { field: "theta", value: theta, allowed: "[1/2, 1]" });
        }
        if !(0.0..=1.0).contains(&gamma) {
            return Err(SchemeError::Invalid { field: "gamma", value: gamma, allowed: "[0, 1]" });
        }
        check_lanes(&lanes, &REFUSALS)?;
        let dy0 = &lanes[0].dynamics;
        // MoreauJean::new's factor and projection column.
        let a = dy0.step_matrix(theta * dt, theta * theta * dt * dt).factor()?;
        let proj = column(&a, dy0.contact().dof)?;
        let terms = dy0.forcing.len();
        let state = LaneState::new(dy0, dt, 0, lanes.len(), &a, &proj);
        let mut s = Self { state, theta, gamma, v: vec![[0.0; L]; dy0.n()], dt_s: vec![[0.0; L]; terms], at_lo: [false; L], at_hi: [false; L], sides: None };
        for (k, ln) in lanes.into_iter().enumerate() {
            let LockstepLane { dynamics: dy, initial, restitution } = ln;
            let e = dy.contact().restitution.unwrap_or(restitution);
            // The single run's means over [n dt, (n+1) dt], n = 0, 1, …
            s.state.add_lane(k, &dy, e, &initial.u, |p| Sampler::means(p, 0.0, dt));
            set_lane(&mut s.v, k, &initial.v);
            // What the single run refuses, this lane refuses too.
            MoreauJean::new(String::new(), dy, theta, restitution, gamma, dt, &initial)?;
        }
        // Padding lanes copy lane 0 (and its means, every step).
        s.state.finish(&mut [&mut s.v]);
        Ok(s)
    }

    /// Sets up `lanes.len()` runs (`1..=L`) of `moreau-jean-projected(θ,
    /// e, γ)` ([`MoreauJeanProjected`](crate::MoreauJeanProjected): Moreau–Jean with an index set kept
    /// with thresholds and the positions of its sides projected on their
    /// bounds; module docs) with step `dt`; the batch is at level 0.
    ///
    /// Errors: those of [`new`](Self::new) (what [`MoreauJeanProjected::new`](crate::MoreauJeanProjected::new)
    /// refuses is what [`MoreauJean::new`] refuses).
    pub fn projected(theta: f64, gamma: f64, dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        let mut s = Self::new(theta, gamma, dt, lanes)?;
        s.sides = Some(([false; L], [false; L]));
        Ok(s)
    }

    /// θ.
    pub fn theta(&self) -> f64 {
        self.theta
    }

    /// Lane `k`'s `V^n` into `out` (length [`dofs`](crate::Lockstep::dofs)).
    #[track_caller]
    pub fn velocity_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.v, self.state.lanes, k, out)
    }

    /// `t_{n}`: the single run reports the impulse's mean force at the end of its step.
    fn lambda_time(&self) -> f64 {
        self.state.n as f64 * self.state.dt
    }

    lockstep_builds!();

    #[inline(always)]
    fn step_body(&mut self) -> usize {
        let (dt, th) = (self.state.dt, self.theta);
        // Which lanes' contacts are predicted active (from U^n, V^n: known
        // before the solve). None: V^{n+1} is the solve's result, and
        // U^{n+1} = U^n + dt ((1-θ) V^n + θ V^{n+1}) is made row by row in
        // the backward sweep (work that fills the recurrence's latency);
        // else after the impact law, in a pass of its own. The same
        // operations either way.
        let any = self.predict();
        free_forward::<L>(&mut self.state, &self.v, &mut self.dt_s, th);
        let st = &mut self.state;
        let n = st.dofs;
        // Backward (`BandLdlt::solve_p3`'s order).
        let a = 1.0 - th;
        if any {
            backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut ());
        } else {
            let mut adv = Advance { u: &mut st.u[..n], v: &self.v[..n], dt, a, th };
            backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut adv);
        }
        if any {
            self.impact();
            let st = &mut self.state;
            for ((ur, vr), vnr) in st.u.iter_mut().zip(&self.v).zip(&st.rhs) {
                advance::<L>(ur, vr, vnr, dt, a, th);
            }
        } else {
            self.state.mu = [0.0; L];
            self.state.acts = [Active::None; L];
        }
        let st = &mut self.state;
        std::mem::swap(&mut self.v, &mut st.rhs);
        st.n += 1;
        for k in 0..L {
            st.lams[k] = -st.mu[k] / dt;
        }
        st.check_finite(None);
        let n = st.n;
        if any {
            self.project_positions();
        }
        n
    }

    /// `moreau-jean-projected`'s projection of the positions
    /// (`MoreauJeanProjected::project` on each lane): where a side in the
    /// set is violated by more than the tolerance, `u_c` is put back on the
    /// bounds of the sides in the set.
    #[inline(always)]
    fn project_positions(&mut self) {
        let Some((in_lo, in_hi)) = &self.sides else { return };
        let st = &mut self.state;
        let c = st.c;
        let uc = &mut st.u[c];
        for k in 0..L {
            let mut x = uc[k];
            let mut worst = 0.0f64;
            if in_lo[k] {
                worst = worst.max(st.lo[k] - x);
            }
            if in_hi[k] {
                worst = worst.max(x - st.hi[k]);
            }
            if worst > PROJECTION_TOLERANCE {
                if in_lo[k] && x < st.lo[k] {
                    x = st.lo[k];
                }
                if in_hi[k] && x > st.hi[k] {
                    x = st.hi[k];
                }
                uc[k] = x;
            }
        }
    }

    /// Each lane's contact predicted active at its lower stop
    /// (`u_c + γ dt v_c <= lo`) or upper stop (`>= hi`), as
    /// `MoreauJean::predict` computes it, into `at_lo`, `at_hi`; whether any is.
    #[inline(always)]
    fn predict(&mut self) -> bool {
        let st = &self.state;
        let gdt = self.gamma * st.dt;
        let (uc, vc) = (&st.u[st.c], &self.v[st.c]);
        let mut any = false;
        if let Some((in_lo, in_hi)) = &mut self.sides {
            // The index set (`MoreauJean::predict` with `IndexSet::keep`,
            // enter = leave = INDEX_SET_THRESHOLD).
            let keep = |member: bool, y: f64, ydot: f64| if member { !(y > INDEX_SET_THRESHOLD && ydot >= 0.0) } else { y <= INDEX_SET_THRESHOLD };
            for k in 0..L {
                let pred = uc[k] + gdt * vc[k];
                in_lo[k] = keep(in_lo[k], pred - st.lo[k], vc[k]);
                in_hi[k] = keep(in_hi[k], st.hi[k] - pred, -vc[k]);
                (self.at_lo[k], self.at_hi[k]) = (in_lo[k], in_hi[k]);
                any |= in_lo[k] | in_hi[k];
            }
            return any;
        }
        for k in 0..L {
            let pred = uc[k] + gdt * vc[k];
            self.at_lo[k] = pred <= st.lo[k];
            self.at_hi[k] = pred >= st.hi[k];
            any |= self.at_lo[k] | self.at_hi[k];
        }
        any
    }

    /// Newton's impact law on every lane (`MoreauJean::finish_step` with
    /// `Projection::project`'s operations): a contact predicted active at
    /// its lower stop gets `v_c^{n+1} >= -e v_c^n`, else one predicted at
    /// its upper stop `v_c^{n+1} <= -e v_c^n`; `mu` per lane (0 when free).
    #[inline(always)]
    fn impact(&mut self) {
        let st = &mut self.state;
        let c = st.c;
        let (yc, vc) = (st.rhs[c], self.v[c]);
        let mut xc = [0.0; L];
        for k in 0..L {
            let bound = -st.e[k] * vc[k];
            let y = yc[k];
            (xc[k], st.acts[k]) = if self.at_lo[k] {
                if y < bound {
                    (bound, Active::Lower)
                } else {
                    (y, Active::None)
                }
            } else if self.at_hi[k] {
                if y > bound {
                    (bound, Active::Upper)
                } else {
                    (y, Active::None)
                }
            } else {
                (y, Active::None)
            };
        }
        project_lanes::<L>(&mut st.rhs, &st.w, st.inv_wc, c, &xc, &st.acts, &mut st.mu);
    }
}

impl_lockstep!(MoreauJeanLockstep);

/// The forward half of the free solve of a Moreau–Jean step, shared with
/// [`crate::MoreauJeanCombinedLockstep`]: the forcing terms' means over
/// `[t_n, t_{n+1}]` (`Sampler::means`: a = 0 + n dt, b = 0 + (n+1) dt),
/// times dt (`add_terms`' scale) into `dt_s`; then
/// `rhs = M V + dt (F - K (U + θ(1-θ) dt V)) + Σ_j (dt s_j) shape_j`, row by
/// row, each row eliminated at once (the forward sweep of
/// `BandLdlt::solve_p3`), `V` and `U + θ(1-θ) dt V` made row by row into a
/// ring just ahead of the products that read them. The backward sweep is
/// the caller's.
#[inline(always)]
pub(crate) fn free_forward<const L: usize>(st: &mut LaneState<L>, v: &[[f64; L]], dt_s: &mut [[f64; L]], th: f64) {
    let dt = st.dt;
    let nf = st.n as f64;
    let (t0, t1) = (nf * dt, (nf + 1.0) * dt);
    st.means(t0, t1);
    for (g, next) in dt_s.iter_mut().zip(&st.next) {
        for k in 0..L {
            g[k] = dt * next[k];
        }
    }
    let cv = th * (1.0 - th) * dt;
    let n = st.dofs;
    let (u, v) = (&st.u[..n], &v[..n]);
    let mut rows = TwoProducts {
        mass: &st.mass[..n],
        stiff: &st.stiff[..n],
        load: &st.load[..n],
        gs: &dt_s[..],
        shape_rows: &st.shape_rows[..],
        t_mass: &mut st.t_mass,
        t_stiff: &mut st.t_stiff,
        scale: dt,
        combine: Velocities { u, v, cv },
    };
    forward::<L, _>(&mut rows, &st.l, &mut st.rhs[..n]);
}

/// Rows of `V^n` and `U^n + θ(1-θ) dt V^n` (`cv = θ(1-θ) dt`).
struct Velocities<'a, const L: usize> {
    u: &'a [[f64; L]],
    v: &'a [[f64; L]],
    cv: f64,
}

impl<const L: usize> Combine<L> for Velocities<'_, L> {
    #[inline(always)]
    fn combine(&self, j: usize) -> ([f64; L], [f64; L]) {
        let (u, v) = (&self.u[j], &self.v[j]);
        let (tm, mut ts) = (*v, [0.0; L]);
        for k in 0..L {
            ts[k] = u[k] + self.cv * v[k];
        }
        (tm, ts)
    }
}

/// [`advance`] on each row of `V^{n+1}` as the backward sweep makes it
/// (when no contact is predicted active).
struct Advance<'a, const L: usize> {
    u: &'a mut [[f64; L]],
    v: &'a [[f64; L]],
    dt: f64,
    a: f64,
    th: f64,
}

impl<const L: usize> Done<L> for Advance<'_, L> {
    #[inline(always)]
    fn done(&mut self, i: usize, x: &[f64; L]) {
        advance::<L>(&mut self.u[i], &self.v[i], x, self.dt, self.a, self.th);
    }
}

/// Row `i` of `U^{n+1} = U^n + dt ((1-θ) V^n + θ V^{n+1})` (`a = 1-θ`):
/// `MoreauJean::finish_step`'s update.
#[inline(always)]
fn advance<const L: usize>(u: &mut [f64; L], v: &[f64; L], vn: &[f64; L], dt: f64, a: f64, th: f64) {
    // Whole rows in, whole row out: no store can alias a load, so the lane
    // loop is vectorised wherever it is inlined.
    let (mut r, v, vn) = (*u, *v, *vn);
    for k in 0..L {
        r[k] += dt * (a * v[k] + th * vn[k]);
    }
    *u = r;
}
