//! Several runs of Moreau–Jean with the combined projection that share one
//! step matrix, stepped together (a frequency or amplitude sweep of one
//! scene): the lockstep engine of `moreau-jean-combined(θ, e)`, built on
//! the lockstep engines' lane state ([`LaneState`]) like
//! [`MoreauJeanLockstep`](crate::MoreauJeanLockstep).
//!
//! Every run ("lane") takes [`MoreauJeanCombined`]'s step: the index set
//! starts empty, the Moreau–Jean step is taken with Newton's law on its
//! sides, the sides of the set are put on their bounds when one is off by
//! [`COMBINED_TOLERANCE`] or more, the sides whose gap is `<= 0` at the
//! new positions join the set, and while it grows the step is redone from
//! `U^n, V^n` and the step's unconstrained `V^{n+1}` (module docs of
//! [`MoreauJeanCombined`]).
//!
//! The unconstrained `V^{n+1}` is the same on every pass, so it is solved
//! once for all lanes (the Moreau–Jean engine's forward and backward
//! sweeps, with the same `M`, `K`, `θ`, `dt` and contact dof), and the
//! first pass (an empty set: no impact) makes `U^{n+1}` row by row inside
//! the backward sweep. Then, while some lane's set grew, every lane whose
//! set grew redoes its step (`V^{n+1}` from the saved unconstrained one,
//! Newton's law on its set's side, `U^{n+1}`, its projection and growth)
//! while the others wait: their `U^{n+1}`, `V^{n+1}`, multiplier and
//! status are kept by a per-lane select, so each lane takes exactly as many
//! passes as its single run (at most 3 for one contact: each pass but the
//! last adds a side) and the batch as many as its slowest lane. A lane's
//! failure is checked after each of its passes, before its projection, as
//! the single run's report is made there; a failed lane takes no more
//! passes.
//!
//! Each lane performs exactly the floating-point operations of
//! [`MoreauJeanCombined::step`](crate::Stepper::step) for one run (single
//! contact, undamped, massive contact node), in the same order, so every
//! lane is bit-identical to the single run of its data (`U^n`, `V^n`, `λ`,
//! the active bound, the step at which it turns non-finite). The energy
//! and the projections' bookkeeping are not computed.
//!
//! Supported and refused as for the Moreau–Jean engine: half-bandwidth 3
//! with at least 7 unknowns; damping, several contacts, a massless contact,
//! lanes that do not share `M`, `K` (bit for bit), the contact dof or the
//! number of forcing terms, and a lane count outside `1..=L` are refused
//! with a [`SchemeError`]. Fewer lanes than `L` are padded with copies of
//! lane 0, whose results are never reported.

// The lane loops index several per-lane arrays by the lane on purpose:
// that is the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use crate::lanes::{backward, check_count, check_lanes, column, impl_lockstep, lane_into, lockstep_builds, project_lanes, set_lane, Done, LaneState, Refusals};
use crate::moreau_lockstep::free_forward;
use crate::{Active, LockstepLane, MoreauJeanCombined, Sampler, SchemeError, COMBINED_TOLERANCE};

/// `L` runs of Moreau–Jean with the combined projection sharing one step
/// matrix, stepped together (module docs). Allocates only at construction.
pub struct MoreauJeanCombinedLockstep<const L: usize> {
    /// The lanes' shared state (`U^n` in `state.u`, the right-hand side and
    /// then the pass's `V^{n+1}` in `state.rhs`; the rings hold `V^n` and
    /// `U^n + θ(1-θ) dt V^n`), at level `n` (0 after construction).
    state: LaneState<L>,
    theta: f64,
    /// `V^n`.
    v: Vec<[f64; L]>,
    /// The pass's `U^{n+1}`.
    un: Vec<[f64; L]>,
    /// The step's unconstrained `V^{n+1}` (saved when a lane redoes its step).
    free: Vec<[f64; L]>,
    /// Per forcing term: `dt s` with `s` the mean over `[t_n, t_{n+1}]`.
    dt_s: Vec<[f64; L]>,
    /// The index set per lane: its lower and its upper side.
    in_lo: [bool; L],
    in_hi: [bool; L],
    /// The passes taken so far, all lanes together (a batch's pass counts
    /// once however many lanes take it).
    passes: u64,
}

/// The engine's structural refusals.
const REFUSALS: Refusals = Refusals {
    damping: "lockstep Moreau–Jean (combined projection) takes undamped problems only (damping: use MoreauJeanCombined)",
    contacts: "lockstep Moreau–Jean (combined projection) takes exactly one contact (several: use MoreauJeanCombined)",
    massless: "lockstep Moreau–Jean (combined projection) needs a massive contact node (massless: use MoreauJeanCombined)",
    band: "lockstep Moreau–Jean (combined projection) supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)",
};

impl<const L: usize> MoreauJeanCombinedLockstep<L> {
    /// Sets up `lanes.len()` runs (`1..=L`) of `moreau-jean-combined(θ, e)`
    /// with step `dt`, each lane's restitution its own (a contact's own
    /// restitution overriding it, as in [`MoreauJeanCombined`]); the batch
    /// is at level 0.
    ///
    /// Errors: everything [`MoreauJeanCombined::new`] refuses (per lane),
    /// and [`SchemeError::Size`] for a lane count outside `1..=L`,
    /// [`SchemeError::Invalid`] for θ outside `[1/2, 1]` or a restitution
    /// outside `[0, 1]`, [`SchemeError::Structure`] for damping, several
    /// contacts, a massless contact, a half-bandwidth other than 3 (or
    /// fewer than 7 unknowns), and lanes that differ in `M`, `K`, the
    /// contact dof or the number of forcing terms.
    pub fn new(theta: f64, dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        check_count::<L>(lanes.len())?;
        if !(0.5..=1.0).contains(&theta) {
            return Err(SchemeError::Invalid { field: "theta", value: theta, allowed: "[1/2, 1]" });
        }
        check_lanes(&lanes, &REFUSALS)?;
        let dy0 = &lanes[0].dynamics;
        // MoreauJean::new's factor and projection column.
        let a = dy0.step_matrix(theta * dt, theta * theta * dt * dt).factor()?;
        let proj = column(&a, dy0.contact().dof)?;
        let (n, terms) = (dy0.n(), dy0.forcing.len());
        let state = LaneState::new(dy0, dt, 0, lanes.len(), &a, &proj);
        let zeros = vec![[0.0; L]; n];
        let mut s = Self { state, theta, v: zeros.clone(), un: zeros.clone(), free: zeros, dt_s: vec![[0.0; L]; terms], in_lo: [false; L], in_hi: [false; L], passes: 0 };
        for (k, ln) in lanes.into_iter().enumerate() {
            let LockstepLane { dynamics: dy, initial, restitution } = ln;
            let e = dy.contact().restitution.unwrap_or(restitution);
            // The single run's means over [n dt, (n+1) dt], n = 0, 1, …
            s.state.add_lane(k, &dy, e, &initial.u, |p| Sampler::means(p, 0.0, dt));
            set_lane(&mut s.v, k, &initial.v);
            // What the single run refuses, this lane refuses too.
            MoreauJeanCombined::new(String::new(), dy, theta, restitution, dt, &initial)?;
        }
        // Padding lanes copy lane 0 (and its means, every step).
        s.state.finish(&mut [&mut s.v]);
        Ok(s)
    }

    /// θ.
    pub fn theta(&self) -> f64 {
        self.theta
    }

    /// The passes the batch has taken so far: one a step, one more each
    /// time some lane's index set grew (the single runs count theirs in
    /// [`MoreauJeanCombined::passes`]).
    pub fn passes(&self) -> u64 {
        self.passes
    }

    /// Lane `k`'s `V^n` into `out` (length [`dofs`](crate::Lockstep::dofs)).
    #[track_caller]
    pub fn velocity_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.v, self.state.lanes, k, out)
    }

    /// `t_n`: the single run reports the impulse's mean force at the end of its step.
    fn lambda_time(&self) -> f64 {
        self.state.n as f64 * self.state.dt
    }

    lockstep_builds!();

    #[inline(always)]
    fn step_body(&mut self) -> usize {
        let (dt, th) = (self.state.dt, self.theta);
        // The unconstrained V^{n+1} (`MoreauJean::free_velocity`): the
        // Moreau–Jean engine's forward sweep, and the first pass's
        // U^{n+1} = U^n + dt ((1-θ) V^n + θ V^{n+1}) row by row in the
        // backward sweep (the set is empty: no impact).
        free_forward::<L>(&mut self.state, &self.v, &mut self.dt_s, th);
        let a = 1.0 - th;
        let st = &mut self.state;
        let n = st.dofs;
        let mut adv = Advance { un: &mut self.un[..n], u: &st.u[..n], v: &self.v[..n], dt, a, th };
        backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut adv);
        st.mu = [0.0; L];
        st.acts = [Active::None; L];
        (self.in_lo, self.in_hi) = ([false; L], [false; L]);
        self.passes += 1;
        let mut live = [true; L];
        if self.settle(&mut live) {
            // Some lane's set grew: keep the unconstrained V^{n+1} (the
            // first pass left it as it was) and redo those lanes' step
            // until no set grows (each pass but the last adds a side).
            self.free.copy_from_slice(&self.state.rhs);
            loop {
                self.redo(&live);
                self.passes += 1;
                if !self.settle(&mut live) {
                    break;
                }
            }
        }
        let st = &mut self.state;
        std::mem::swap(&mut st.u, &mut self.un);
        std::mem::swap(&mut self.v, &mut st.rhs);
        st.n += 1;
        for k in 0..L {
            st.lams[k] = -st.mu[k] / dt;
        }
        st.n
    }

    /// After a pass, on its lanes (`live`): the failure check of the single
    /// run's report (`u_c^{n+1}` and `λ` finite; a failed lane takes no more
    /// passes), the projection of `u_c` on the set's bounds
    /// (`MoreauJeanCombined::project`), and the set's growth
    /// (`MoreauJeanCombined::grow`); `live` becomes the lanes whose set
    /// grew. Whether any did.
    #[inline(always)]
    fn settle(&mut self, live: &mut [bool; L]) -> bool {
        let st = &mut self.state;
        let (c, dt) = (st.c, st.dt);
        let next = st.n + 1;
        let mut any = false;
        let uc = &mut self.un[c];
        for k in 0..L {
            if !live[k] {
                continue;
            }
            let mut x = uc[k];
            if !(x.is_finite() && (-st.mu[k] / dt).is_finite()) {
                if k < st.lanes && st.failed[k].is_none() {
                    st.failed[k] = Some(SchemeError::NonFinite { step: next, time: next as f64 * dt });
                }
                live[k] = false;
                continue;
            }
            let (lo, hi) = (st.lo[k], st.hi[k]);
            let mut worst = 0.0f64;
            if self.in_lo[k] {
                worst = worst.max((x - lo).abs());
            }
            if self.in_hi[k] {
                worst = worst.max((hi - x).abs());
            }
            if worst >= COMBINED_TOLERANCE {
                // Both sides in the set: the lower wins.
                if self.in_lo[k] {
                    x = lo;
                } else if self.in_hi[k] {
                    x = hi;
                }
                uc[k] = x;
            }
            let mut grew = false;
            if !self.in_lo[k] && x - lo <= 0.0 {
                (self.in_lo[k], grew) = (true, true);
            }
            if !self.in_hi[k] && hi - x <= 0.0 {
                (self.in_hi[k], grew) = (true, true);
            }
            live[k] = grew;
            any |= grew;
        }
        any
    }

    /// The step redone on the lanes `live` from `U^n`, `V^n` and the
    /// unconstrained `V^{n+1}` with Newton's law on their set's side (the
    /// lower if both: `MoreauJean::finish_step` with a given set); the
    /// other lanes keep their `U^{n+1}`, `V^{n+1}`, multiplier and status.
    #[inline(always)]
    fn redo(&mut self, live: &[bool; L]) {
        let st = &mut self.state;
        let (c, n, dt, th) = (st.c, st.dofs, st.dt, self.theta);
        let a = 1.0 - th;
        for (r, f) in st.rhs[..n].iter_mut().zip(&self.free[..n]) {
            let (mut x, f) = (*r, *f);
            for k in 0..L {
                x[k] = if live[k] { f[k] } else { x[k] };
            }
            *r = x;
        }
        let (yc, vc) = (st.rhs[c], self.v[c]);
        let (mut xc, mut acts, mut mu) = ([0.0; L], [Active::None; L], [0.0; L]);
        for k in 0..L {
            let bound = -st.e[k] * vc[k];
            let y = yc[k];
            (xc[k], acts[k]) = if !live[k] {
                (y, Active::None)
            } else if self.in_lo[k] {
                if y < bound {
                    (bound, Active::Lower)
                } else {
                    (y, Active::None)
                }
            } else if self.in_hi[k] {
                if y > bound {
                    (bound, Active::Upper)
                } else {
                    (y, Active::None)
                }
            } else {
                (y, Active::None)
            };
        }
        project_lanes::<L>(&mut st.rhs, &st.w, st.inv_wc, c, &xc, &acts, &mut mu);
        for k in 0..L {
            if live[k] {
                (st.mu[k], st.acts[k]) = (mu[k], acts[k]);
            }
        }
        for ((unr, ur), (vr, vnr)) in self.un[..n].iter_mut().zip(&st.u[..n]).zip(self.v[..n].iter().zip(&st.rhs[..n])) {
            let (mut r, u, v, vn) = (*unr, *ur, *vr, *vnr);
            for k in 0..L {
                r[k] = if live[k] { u[k] + dt * (a * v[k] + th * vn[k]) } else { r[k] };
            }
            *unr = r;
        }
    }
}

impl_lockstep!(MoreauJeanCombinedLockstep);

/// The first pass's `U^{n+1} = U^n + dt ((1-θ) V^n + θ V^{n+1})` (`a = 1-θ`)
/// row by row as the backward sweep makes `V^{n+1}`.
struct Advance<'a, const L: usize> {
    un: &'a mut [[f64; L]],
    u: &'a [[f64; L]],
    v: &'a [[f64; L]],
    dt: f64,
    a: f64,
    th: f64,
}

impl<const L: usize> Done<L> for Advance<'_, L> {
    #[inline(always)]
    fn done(&mut self, i: usize, x: &[f64; L]) {
        let (u, v, mut r) = (self.u[i], self.v[i], [0.0; L]);
        for k in 0..L {
            r[k] = u[k] + self.dt * (self.a * v[k] + self.th * x[k]);
        }
        self.un[i] = r;
    }
}
