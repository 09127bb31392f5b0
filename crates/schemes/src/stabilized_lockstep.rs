//! Several runs of the contact-stabilized Newmark scheme that share one
//! step matrix, stepped together (a frequency or amplitude sweep of one
//! scene): the lockstep engine of `contact-stabilized`, built on the
//! lockstep engines' lane state ([`LaneState`]).
//!
//! Every run ("lane") takes [`ContactStabilized`]'s step (docs/theory.md
//! §4.6.6): the predictor `U^n + τ V^n` projected onto `[lo, hi]` at the
//! contact dof in the mass norm (the column `M⁻¹ e_c`), the right-hand side
//! `b = M U^n_pred − τ²/4 K U^n + τ²/4 (2F + Σ_j s_j(t_n) g_j + Σ_j s_j(t_{n+1}) g_j)`,
//! `A⁻¹ b` with `A = M + τ²/4 K`, its projection with the column `A⁻¹ e_c`
//! (multiplier `μ`, `λ = −2μ/τ²` at `t_{n+1}`), then
//! `V^{n+1} = V^n + 2/τ (U^{n+1} − U^n_pred)`. The single run makes both
//! projections with the several-contacts solve ([`MultiSolve`](crate::MultiSolve));
//! for its one contact each lane makes them with
//! [`OneDof`](signorini_contact::OneDof), that solve's arithmetic for one
//! dof (its bound checks, its warm start from the last status kept per
//! lane, its pivoting tolerance, `μ = ((bound − y_c)/√D)/√D`), and applies
//! them as it does (`y += μ W` on every row, `y_c` set to the bound held).
//! The lanes share `M`, `K`, `dt` and the contact dof (so the factor of `A`
//! and both columns); each has its own steady load, forcing terms (their
//! values at the levels), bounds and initial state.
//!
//! The state is stored lane-innermost (`u[i][lane]`, also `V` and the
//! predictor). The stabilisation's multiplier needs only `u_c + τ v_c`, so
//! it comes first; the projected predictor is then made row by row just
//! ahead of the forward sweep (into the ring `M U^n_pred` reads, `U^n`'s
//! rows into the ring `K U^n` reads), each right-hand side row eliminated
//! as it is made; after the backward sweep the step's projection, `V` and
//! `U` are made in one pass. All with the lanes innermost, `L` at a time,
//! compiled for the baseline x86-64 target, AVX2 and AVX-512F (chosen at
//! run time; never FMA). Each lane performs exactly the floating-point
//! operations of [`ContactStabilized::step`](crate::Stepper::step) for one
//! run (single contact, undamped, massive contact node; the plain step, as
//! the single run takes it on the beam), in the same order, so every lane
//! is bit-identical to the single run of its data (`U^n`, `V^n`, the
//! predictor, `λ`, the active bound, the step at which it turns
//! non-finite). The works and the energy are not computed.
//!
//! Supported and refused as for the other engines: half-bandwidth 3 with
//! at least 7 unknowns; damping, several contacts, a massless contact,
//! lanes that do not share `M`, `K` (bit for bit), the contact dof or the
//! number of forcing terms, a lane count outside `1..=L` and a nonzero
//! restitution (the scheme has no impact law) are refused with a
//! [`SchemeError`]. Fewer lanes than `L` are padded with copies of lane 0,
//! whose results are never reported.

// The lane loops index several per-lane arrays by the lane on purpose:
// that is the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use crate::lanes::{
    add_shapes, backward, check_count, check_lanes, chunk, column, forward, impl_lockstep, lane_into, lockstep_builds, set_lane, two_products, Done, LaneState, Refusals, Row7, Rows, RING,
};
use crate::{Active, ContactStabilized, LockstepLane, Sampler, SchemeError};
use signorini_contact::OneDof;

/// `L` runs of the contact-stabilized Newmark scheme sharing one step
/// matrix, stepped together (module docs). Allocates only at construction.
pub struct ContactStabilizedLockstep<const L: usize> {
    /// The lanes' shared state (`U^n` in `state.u`; the factor is `A`'s;
    /// the right-hand side, then `A⁻¹ b`, in `state.rhs`; the rings hold
    /// `U^n_pred` and `U^n`; `state.acts` the step solve's statuses, its
    /// warm start), at level `n` (0 after construction).
    state: LaneState<L>,
    v: Vec<[f64; L]>,
    /// `U^n_pred` of the last step.
    pred: Vec<[f64; L]>,
    /// Per forcing term, its value at `t_n`.
    s_old: Vec<[f64; L]>,
    /// Per forcing term `τ²/4 s_j(t_n)`, then per term `τ²/4 s_j(t_{n+1})`.
    gs: Vec<[f64; L]>,
    /// The stabilisation's solve (mass norm) and column `M⁻¹ e_c`, and its
    /// statuses per lane (its warm start).
    mass: OneDof,
    wm: Vec<f64>,
    mass_status: [Active; L],
    /// The step's solve and column `A⁻¹ e_c`.
    step: OneDof,
    wa: Vec<f64>,
}

/// The contact-stabilized engine's structural refusals.
const REFUSALS: Refusals = Refusals {
    damping: "lockstep contact-stabilized Newmark takes undamped problems only (damping: use ContactStabilized)",
    contacts: "lockstep contact-stabilized Newmark takes exactly one contact (several: use ContactStabilized)",
    massless: "lockstep contact-stabilized Newmark needs a massive contact node (massless: no contact-stabilized run takes it)",
    band: "lockstep contact-stabilized Newmark supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)",
};

impl<const L: usize> ContactStabilizedLockstep<L> {
    /// Sets up `lanes.len()` runs (`1..=L`) of the contact-stabilized
    /// Newmark scheme with step `dt`; the batch is at level 0, each lane in
    /// its initial state (as [`ContactStabilized::new`] starts).
    ///
    /// Errors: everything [`ContactStabilized::new`] refuses (per lane),
    /// and [`SchemeError::Size`] for a lane count outside `1..=L`,
    /// [`SchemeError::Invalid`] for a restitution other than 0,
    /// [`SchemeError::Structure`] for damping, several contacts, a massless
    /// contact, a half-bandwidth other than 3 (or fewer than 7 unknowns),
    /// and lanes that differ in `M`, `K`, the contact dof or the number of
    /// forcing terms.
    pub fn new(dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        check_count::<L>(lanes.len())?;
        check_lanes(&lanes, &REFUSALS)?;
        if let Some(ln) = lanes.iter().find(|ln| ln.restitution != 0.0) {
            return Err(SchemeError::Invalid { field: "restitution", value: ln.restitution, allowed: "0 (contact-stabilized has no impact law)" });
        }
        let single = |ln: &LockstepLane| ContactStabilized::new(String::new(), ln.dynamics.clone(), dt, &ln.initial);
        let first = single(&lanes[0])?;
        let parts = first.lockstep_parts().expect("one rigid contact");
        let dy0 = &lanes[0].dynamics;
        let n = dy0.n();
        // The state's own projection column (unused here) as the other engines validate it.
        let proj = column(parts.a, dy0.contact().dof)?;
        let state = LaneState::new(dy0, dt, 0, lanes.len(), parts.a, &proj);
        let terms = dy0.forcing.len();
        let zeros = vec![[0.0; L]; n];
        let mut s = Self {
            state,
            v: zeros.clone(),
            pred: zeros,
            s_old: vec![[0.0; L]; terms],
            gs: vec![[0.0; L]; 2 * terms],
            mass: parts.mass.0,
            wm: parts.mass.1.to_vec(),
            mass_status: [Active::None; L],
            step: parts.step.0,
            wa: parts.step.1.to_vec(),
        };
        for (k, ln) in lanes.iter().enumerate() {
            // What the single run refuses, this lane refuses too.
            single(ln)?;
            // The single run's values at n dt, n = 0, 1, … (the first, at
            // t = 0, its `s_old` at the start).
            s.state.add_lane(k, &ln.dynamics, 0.0, &ln.initial.u, |prof| Sampler::values(prof, 0.0, dt));
            for (j, s0) in s.s_old.iter_mut().enumerate() {
                s0[k] = s.state.samplers[j][k].next_value();
            }
            set_lane(&mut s.v, k, &ln.initial.v);
        }
        // Padding lanes copy lane 0 (and its samples, every step).
        s.state.finish(&mut [&mut s.v, &mut s.s_old]);
        Ok(s)
    }

    /// Lane `k`'s `V^n` into `out` (length [`dofs`](crate::Lockstep::dofs)).
    #[track_caller]
    pub fn velocity_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.v, self.state.lanes, k, out)
    }

    /// Lane `k`'s `U^n_pred` of the last step (the stabilised predictor)
    /// into `out`.
    #[track_caller]
    pub fn predictor_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.pred, self.state.lanes, k, out)
    }

    /// `t_n`: the single run reports `λ` at the end of its step.
    fn lambda_time(&self) -> f64 {
        self.state.n as f64 * self.state.dt
    }

    lockstep_builds!();

    #[inline(always)]
    fn step_body(&mut self) -> usize {
        let st = &mut self.state;
        let dt = st.dt;
        let q = 0.25 * dt * dt;
        let c = st.c;
        let n = st.dofs;
        // The stabilisation: u_c + τ v_c solved on [lo, hi] in the mass
        // norm, lane by lane (`MultiSolve::solve` of the single run).
        let (uc, vc) = (st.u[c], self.v[c]);
        let mut pc = [0.0; L];
        for k in 0..L {
            pc[k] = uc[k] + dt * vc[k];
        }
        let pm = solve_lanes(&self.mass, &mut self.mass_status, &pc, &st.lo, &st.hi, &mut st.failed, st.lanes);
        // The forcing terms' values at t_{n+1}, and the weights τ²/4 s.
        st.samples();
        let terms = st.next.len();
        for j in 0..terms {
            for k in 0..L {
                self.gs[j][k] = q * self.s_old[j][k];
                self.gs[terms + j][k] = q * st.next[j][k];
            }
        }
        // A⁻¹ b: the projected predictor made row by row just ahead of the
        // forward sweep, each right-hand side row eliminated as it is made.
        let mut rows = Predicted {
            mass: &st.mass[..n],
            stiff: &st.stiff[..n],
            load: &st.load[..n],
            gs: &self.gs[..],
            shape_rows: &st.shape_rows[..],
            t_mass: &mut st.t_mass,
            t_stiff: &mut st.t_stiff,
            u: &st.u[..n],
            v: &self.v[..n],
            pred: &mut self.pred[..n],
            w: &self.wm[..n],
            p: pm,
            c,
            dt,
            q,
        };
        forward::<L, _>(&mut rows, &st.l, &mut st.rhs[..n]);
        // The step's projection with A⁻¹ e_c, lane by lane, λ = −2μ/τ², then
        // U^{n+1} (the projection applied) and V^{n+1} = V^n + 2/τ (U^{n+1} − U^n_pred).
        let w = 2.0 / dt;
        let pa = if c + 3 >= n {
            // The contact row is among the first three the backward sweep
            // gives: the rest of the step is made row by row inside it
            // (whose row-to-row recurrence leaves the vector units waiting).
            let mut fin = Finish {
                u: &mut st.u[..n],
                v: &mut self.v[..n],
                pred: &self.pred[..n],
                wa: &self.wa[..n],
                last: [[0.0; L]; 3],
                c,
                w,
                solve: &self.step,
                status: &mut st.acts,
                lo: &st.lo,
                hi: &st.hi,
                failed: &mut st.failed,
                used: st.lanes,
                p: Projected { mu: [0.0; L], held: [false; L], xc: [0.0; L] },
            };
            backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut fin);
            fin.p
        } else {
            backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut ());
            let pa = solve_lanes(&self.step, &mut st.acts, &st.rhs[c], &st.lo, &st.hi, &mut st.failed, st.lanes);
            for (i, (((u, v), r), (p, wa))) in st.u[..n].iter_mut().zip(self.v[..n].iter_mut()).zip(&st.rhs[..n]).zip(self.pred[..n].iter().zip(&self.wa[..n])).enumerate() {
                let x = pa.apply(r, *wa, i == c);
                finish_row::<L>(u, v, &x, p, w);
            }
            pa
        };
        for k in 0..L {
            st.lams[k] = -2.0 * pa.mu[k] / (dt * dt);
        }
        self.s_old.copy_from_slice(&st.next);
        st.n += 1;
        st.check_finite(None);
        st.n
    }
}

impl_lockstep!(ContactStabilizedLockstep);

/// One contact solve on every lane: each lane's multiplier, whether it
/// holds a bound, and the contact value it sets.
#[derive(Clone, Copy)]
struct Projected<const L: usize> {
    mu: [f64; L],
    held: [bool; L],
    /// The bound held (the value itself where free).
    xc: [f64; L],
}

impl<const L: usize> Projected<L> {
    /// Row `i` of `y` with the projection applied (`MultiProjection`'s
    /// `apply`): `y_i + μ w_i` on the lanes held, then the bound at the
    /// contact row.
    #[inline(always)]
    fn apply(&self, y: &[f64; L], w: f64, contact_row: bool) -> [f64; L] {
        let mut x = [0.0; L];
        for k in 0..L {
            x[k] = if self.held[k] { y[k] + self.mu[k] * w } else { y[k] };
        }
        if contact_row {
            for k in 0..L {
                x[k] = if self.held[k] { self.xc[k] } else { x[k] };
            }
        }
        x
    }
}

/// `solve`'s one-dof solve of `yc` on every lane (statuses in `status`, the
/// warm start); an error (which a single run would return from its step)
/// is recorded as lane `k`'s failure, if it has none yet (lanes in use only).
#[inline(always)]
fn solve_lanes<const L: usize>(solve: &OneDof, status: &mut [Active; L], yc: &[f64; L], lo: &[f64; L], hi: &[f64; L], failed: &mut [Option<SchemeError>; L], used: usize) -> Projected<L> {
    let mut p = Projected { mu: [0.0; L], held: [false; L], xc: *yc };
    for k in 0..L {
        match solve.solve(&mut status[k], yc[k], lo[k], hi[k]) {
            Ok(mu) => p.mu[k] = mu,
            Err(e) => {
                if k < used && failed[k].is_none() {
                    failed[k] = Some(e.into());
                }
            }
        }
        p.held[k] = status[k] != Active::None;
        p.xc[k] = match status[k] {
            Active::Lower => lo[k],
            Active::Upper => hi[k],
            Active::None => yc[k],
        };
    }
    p
}

/// The end of the step row by row as the backward sweep gives `A⁻¹ b`
/// (for a contact row among the last three): the last three rows kept
/// until the last of them, then the step's solve on the contact row
/// ([`solve_lanes`]) and those rows finished; every further row finished
/// at once (the projection applied, `V` and `U`, [`finish_row`]).
struct Finish<'a, const L: usize> {
    u: &'a mut [[f64; L]],
    v: &'a mut [[f64; L]],
    pred: &'a [[f64; L]],
    wa: &'a [f64],
    last: [[f64; L]; 3],
    c: usize,
    w: f64,
    solve: &'a OneDof,
    status: &'a mut [Active; L],
    lo: &'a [f64; L],
    hi: &'a [f64; L],
    failed: &'a mut [Option<SchemeError>; L],
    used: usize,
    p: Projected<L>,
}

impl<const L: usize> Finish<'_, L> {
    #[inline(always)]
    fn row(&mut self, i: usize, y: &[f64; L]) {
        let x = self.p.apply(y, self.wa[i], i == self.c);
        finish_row::<L>(&mut self.u[i], &mut self.v[i], &x, &self.pred[i], self.w);
    }
}

impl<const L: usize> Done<L> for Finish<'_, L> {
    #[inline(always)]
    fn done(&mut self, i: usize, x: &[f64; L]) {
        let n = self.u.len();
        if i + 3 < n {
            return self.row(i, x);
        }
        // Rows n-3, n-2, n-1, in that order (`backward`).
        self.last[i + 3 - n] = *x;
        if i == n - 1 {
            self.p = solve_lanes(self.solve, self.status, &self.last[self.c + 3 - n], self.lo, self.hi, self.failed, self.used);
            for r in n - 3..n {
                let y = self.last[r + 3 - n];
                self.row(r, &y);
            }
        }
    }
}

/// `V += w (x − p)`, `U = x` on one row.
#[inline(always)]
fn finish_row<const L: usize>(u: &mut [f64; L], v: &mut [f64; L], x: &[f64; L], p: &[f64; L], w: f64) {
    let mut vn = *v;
    for k in 0..L {
        vn[k] += w * (x[k] - p[k]);
    }
    (*u, *v) = (*x, vn);
}

/// [`Rows`] of `M U^n_pred + τ²/4 (2F − K U^n) + Σ_j τ²/4 s_j(t_n) g_j +
/// Σ_j τ²/4 s_j(t_{n+1}) g_j` (`ContactStabilized::step`'s order), the
/// projected predictor's row `j` made (`U + τ V`, the stabilisation
/// applied) into `pred` and the ring `M U^n_pred` reads, `U^n`'s row into
/// the ring `K U^n` reads.
struct Predicted<'a, const L: usize> {
    mass: &'a [Row7],
    stiff: &'a [Row7],
    load: &'a [[f64; L]],
    gs: &'a [[f64; L]],
    shape_rows: &'a [[f64; L]],
    t_mass: &'a mut [[f64; L]; RING],
    t_stiff: &'a mut [[f64; L]; RING],
    u: &'a [[f64; L]],
    v: &'a [[f64; L]],
    pred: &'a mut [[f64; L]],
    /// `M⁻¹ e_c` and the stabilisation's solve.
    w: &'a [f64],
    p: Projected<L>,
    c: usize,
    dt: f64,
    q: f64,
}

impl<const L: usize> Rows<L> for Predicted<'_, L> {
    #[inline(always)]
    fn prepare(&mut self, j: usize) {
        let (u, v) = (&self.u[j], &self.v[j]);
        let mut y = [0.0; L];
        for k in 0..L {
            y[k] = u[k] + self.dt * v[k];
        }
        let p = self.p.apply(&y, self.w[j], j == self.c);
        (self.pred[j], self.t_mass[j % RING], self.t_stiff[j % RING]) = (p, p, *u);
    }

    #[inline(always)]
    fn row(&self, i: usize, interior_row: bool) -> [f64; L] {
        let (mv, kv) = two_products::<L>((self.mass, self.t_mass), (self.stiff, self.t_stiff), i, interior_row);
        let f = &self.load[i];
        let mut r = [0.0; L];
        for k in 0..L {
            r[k] = mv[k] + self.q * (2.0 * f[k] - kv[k]);
        }
        let terms = self.gs.len() / 2;
        let shapes = chunk(self.shape_rows, i, terms);
        add_shapes(add_shapes(r, &self.gs[..terms], shapes), &self.gs[terms..], shapes)
    }
}
