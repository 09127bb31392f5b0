//! Several runs of the CD-Lagrange scheme that share one mass matrix,
//! stepped together (a frequency or amplitude sweep of one scene): the
//! lockstep engine of `cd-lagrange(e)`, built on the lockstep engines'
//! lane state ([`LaneState`]).
//!
//! Every run ("lane") takes [`CdLagrange`]'s step (docs/theory.md §4.6.9):
//!
//! ```text
//! a      = M⁻¹(F_k − K Uⁿ + Σ_j s_{k,j}(t_n) shape_{k,j})
//! V_free = V^{n−½} + κ a                    (κ = dt, dt/2 on the first step)
//! V^{n+½} = V_free + Λ M⁻¹e_c,  0 <= Λ ⊥ v_c^{n+½} + e_k v_c^{n−½} >= 0   if u_cⁿ <= lo_k
//!                               (the mirror image if u_cⁿ >= hi_k; else Λ = 0)
//! U^{n+1} = Uⁿ + dt V^{n+½}
//! ```
//!
//! with the same `M`, `K`, `dt` and contact dof `c` (so the same factor of
//! `M` and the same column `M⁻¹ e_c`), and its own steady load, forcing
//! terms (their values at the levels), bounds, restitution and initial
//! state. The single run makes Newton's law with the several-contacts
//! solve ([`MultiSolve`](crate::MultiSolve)); for its one contact each lane
//! makes it with [`OneDof`], that solve's arithmetic for one dof (its bound
//! checks, its warm start from the last status kept per lane, its pivoting
//! tolerance, `Λ = ((bound − v_c)/√D)/√D`), and applies it as it does
//! (`V += Λ w` on every row, `v_c` set to the bound held). A lane whose
//! contact is open at `Uⁿ` makes no solve (its status is kept), as the
//! single run.
//!
//! The state is stored lane-innermost (`u[i][lane]`, `v[i][lane]`). Which
//! lanes are closed needs only `u_cⁿ`, so it comes first; the right-hand
//! side `F − K Uⁿ + Σ_j s_j shape_j` is made row by row just ahead of the
//! forward sweep of `M`'s factor (`Uⁿ`'s rows into the ring `K Uⁿ` reads),
//! each row eliminated as it is made. When no lane is closed, `V^{n+½}` and
//! `U^{n+1}` are made row by row inside the backward sweep (whose
//! row-to-row recurrence leaves the vector units waiting); else `V_free`
//! is made there, and the law, `V` and `U` in a pass after it. All with the
//! lanes innermost, `L` at a time, compiled for the baseline x86-64 target,
//! AVX2 and AVX-512F (chosen at run time; never FMA). Each lane performs
//! exactly the floating-point operations of [`CdLagrange::step`](crate::Stepper::step)
//! for one run (single contact, undamped, massive contact node), in the
//! same order, so every lane is bit-identical to the single run of its
//! data (`Uⁿ`, `V^{n−½}`, `λ`, the closed side, the step at which it turns
//! non-finite). `U^{n−1}` and the energy are not kept.
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

use crate::lanes::{add_shapes, backward, check_count, check_lanes, chunk, edge, forward, impl_lockstep, interior, lane_into, lockstep_builds, set_lane, Done, LaneState, Refusals, Row7, Rows, RING};
use crate::{Active, CdLagrange, LockstepLane, Sampler, SchemeError};
use signorini_contact::{OneDof, Projection};

/// `L` runs of the CD-Lagrange scheme sharing one mass matrix, stepped
/// together (module docs). Allocates only at construction.
pub struct CdLagrangeLockstep<const L: usize> {
    /// The lanes' shared state (`Uⁿ` in `state.u`; the factor is `M`'s;
    /// the right-hand side, then `a`, in `state.rhs`; the ring `t_stiff`
    /// holds `Uⁿ`'s rows; `state.next` the forcing terms' values at `t_n`;
    /// `state.acts` the side closed at `Uⁿ`), at level `n` (0 after
    /// construction).
    state: LaneState<L>,
    /// `V^{n−½}` (`V⁰` before the first step).
    v: Vec<[f64; L]>,
    /// Newton's law as scalar arithmetic, the column `M⁻¹ e_c`, and each
    /// lane's status (the law's warm start).
    law: OneDof,
    w: Vec<f64>,
    status: [Active; L],
}

/// The CD-Lagrange engine's structural refusals.
const REFUSALS: Refusals = Refusals {
    damping: "lockstep CD-Lagrange takes undamped problems only (damping: no CD-Lagrange run takes it)",
    contacts: "lockstep CD-Lagrange takes exactly one contact (several: use CdLagrange)",
    massless: "lockstep CD-Lagrange needs a massive contact node (massless: no CD-Lagrange run takes it)",
    band: "lockstep CD-Lagrange supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)",
};

impl<const L: usize> CdLagrangeLockstep<L> {
    /// Sets up `lanes.len()` runs (`1..=L`) of the CD-Lagrange scheme with
    /// step `dt`, each lane's restitution its own (a contact's own
    /// restitution overriding it, as in [`CdLagrange`]); the batch is at
    /// level 0, each lane in its initial state.
    ///
    /// Errors: everything [`CdLagrange::new`] refuses (per lane), and
    /// [`SchemeError::Size`] for a lane count outside `1..=L`,
    /// [`SchemeError::Invalid`] for a restitution outside `[0, 1]`,
    /// [`SchemeError::Structure`] for damping, several contacts, a massless
    /// contact, a half-bandwidth other than 3 (or fewer than 7 unknowns),
    /// and lanes that differ in `M`, `K`, the contact dof or the number of
    /// forcing terms.
    pub fn new(dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        check_count::<L>(lanes.len())?;
        check_lanes(&lanes, &REFUSALS)?;
        let single = |ln: &LockstepLane| CdLagrange::new(String::new(), ln.dynamics.clone(), ln.restitution, dt, &ln.initial);
        let first = single(&lanes[0])?;
        let (mf, (law, w)) = first.lockstep_parts().expect("one rigid contact");
        let dy0 = &lanes[0].dynamics;
        // The state's own projection column, as the law's (validated as
        // `Projection` validates it).
        let proj = Projection::new(dy0.contact().dof, w.to_vec())?;
        let state = LaneState::new(dy0, dt, 0, lanes.len(), mf, &proj);
        let mut s = Self { state, v: vec![[0.0; L]; dy0.n()], law, w: w.to_vec(), status: [Active::None; L] };
        for (k, ln) in lanes.iter().enumerate() {
            // What the single run refuses, this lane refuses too.
            single(ln)?;
            let e = ln.dynamics.contact().restitution.unwrap_or(ln.restitution);
            // The single run's values at n dt, n = 0, 1, …
            s.state.add_lane(k, &ln.dynamics, e, &ln.initial.u, |prof| Sampler::values(prof, 0.0, dt));
            set_lane(&mut s.v, k, &ln.initial.v);
        }
        // Padding lanes copy lane 0 (and its samples, every step).
        s.state.finish(&mut [&mut s.v]);
        // The values at t = 0 (the single run's first `next_into`).
        s.state.samples();
        Ok(s)
    }

    /// Lane `k`'s `V^{n−½}` (`V⁰` before the first step) into `out`
    /// (length [`dofs`](crate::Lockstep::dofs)).
    #[track_caller]
    pub fn half_step_velocity_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.v, self.state.lanes, k, out)
    }

    /// `t_{n−1}`: the single run reports the impulse of the step's start.
    fn lambda_time(&self) -> f64 {
        self.state.n.saturating_sub(1) as f64 * self.state.dt
    }

    lockstep_builds!();

    #[inline(always)]
    fn step_body(&mut self) -> usize {
        let st = &mut self.state;
        let h = st.dt;
        // The first step is the start's half step.
        let kick = if st.n == 0 { 0.5 * h } else { h };
        let (c, n) = (st.c, st.dofs);
        // Iⁿ from the gaps at Uⁿ (`side` of the single run), and the
        // velocity the law compares with, v_c^{n−½}.
        let uc = st.u[c];
        let mut any = false;
        for k in 0..L {
            st.acts[k] = if uc[k] <= st.lo[k] {
                Active::Lower
            } else if uc[k] >= st.hi[k] {
                Active::Upper
            } else {
                Active::None
            };
            any |= st.acts[k] != Active::None;
        }
        let vc_old = self.v[c];
        // M a = F − K Uⁿ + Σ_j s_j shape_j: each row made just ahead of its
        // elimination (the forward sweep of `BandLdlt::solve_p3` with M's factor).
        let mut rows = Accel { stiff: &st.stiff[..n], load: &st.load[..n], gs: &st.next[..], shape_rows: &st.shape_rows[..], t_stiff: &mut st.t_stiff, u: &st.u[..n] };
        forward::<L, _>(&mut rows, &st.l, &mut st.rhs[..n]);
        let mut mu = [0.0; L];
        if any {
            // V_free = V^{n−½} + κ a row by row in the backward sweep, then
            // the law on the closed lanes, V^{n+½} and U^{n+1} in a pass.
            let mut kicked = Kick { u: None, v: &mut self.v[..n], kick, h };
            backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut kicked);
            let vc = self.v[c];
            let mut held = [false; L];
            let mut xc = vc;
            for k in 0..L {
                if st.acts[k] == Active::None {
                    continue;
                }
                // `MultiSolve::newton_law`: the bound −e v_c^{n−½} on the closed side.
                let target = -st.e[k] * vc_old[k];
                let (lo, hi) = if st.acts[k] == Active::Lower { (target, f64::INFINITY) } else { (f64::NEG_INFINITY, target) };
                match self.law.solve(&mut self.status[k], vc[k], lo, hi) {
                    Ok(m) => mu[k] = m,
                    Err(e) => {
                        if k < st.lanes && st.failed[k].is_none() {
                            st.failed[k] = Some(e.into());
                        }
                    }
                }
                match self.status[k] {
                    Active::Lower => (held[k], xc[k]) = (true, lo),
                    Active::Upper => (held[k], xc[k]) = (true, hi),
                    Active::None => {}
                }
            }
            for (i, (ur, vr)) in st.u[..n].iter_mut().zip(self.v[..n].iter_mut()).enumerate() {
                // `MultiProjection`'s apply: V += Λ w on the lanes held, then
                // v_c on the bound; then U^{n+1} = Uⁿ + dt V^{n+½}.
                let (mut vn, wi) = (*vr, self.w[i]);
                for k in 0..L {
                    vn[k] = if held[k] { vn[k] + mu[k] * wi } else { vn[k] };
                }
                if i == c {
                    for k in 0..L {
                        vn[k] = if held[k] { xc[k] } else { vn[k] };
                    }
                }
                *vr = vn;
                advance::<L>(ur, &vn, h);
            }
        } else {
            let mut kicked = Kick { u: Some(&mut st.u[..n]), v: &mut self.v[..n], kick, h };
            backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut kicked);
        }
        // The values at t_{n+1}.
        st.samples();
        st.n += 1;
        for k in 0..L {
            // The force over the kick the impulse completes (dt/2 at the start).
            st.lams[k] = -mu[k] / kick;
        }
        st.check_finite(Some(&self.v[c]));
        st.n
    }
}

impl_lockstep!(CdLagrangeLockstep);

/// [`Rows`] of `F − K Uⁿ + Σ_j s_j shape_j` (`CdLagrange::step`'s order:
/// `K Uⁿ`, `F −` it, then `add_terms` term by term), `Uⁿ`'s row `j` copied
/// into the ring `K Uⁿ` reads.
struct Accel<'a, const L: usize> {
    stiff: &'a [Row7],
    load: &'a [[f64; L]],
    gs: &'a [[f64; L]],
    shape_rows: &'a [[f64; L]],
    t_stiff: &'a mut [[f64; L]; RING],
    u: &'a [[f64; L]],
}

impl<const L: usize> Rows<L> for Accel<'_, L> {
    #[inline(always)]
    fn prepare(&mut self, j: usize) {
        self.t_stiff[j % RING] = self.u[j];
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

/// Each row of `a` as the backward sweep gives it: `V += κ a`, and where no
/// lane is closed (`u` given) `U^{n+1} = Uⁿ + dt V^{n+½}` at once.
struct Kick<'a, const L: usize> {
    u: Option<&'a mut [[f64; L]]>,
    v: &'a mut [[f64; L]],
    kick: f64,
    h: f64,
}

impl<const L: usize> Done<L> for Kick<'_, L> {
    #[inline(always)]
    fn done(&mut self, i: usize, a: &[f64; L]) {
        // Whole rows in, whole row out: no store can alias a load.
        let mut vn = self.v[i];
        for k in 0..L {
            vn[k] += self.kick * a[k];
        }
        self.v[i] = vn;
        if let Some(u) = &mut self.u {
            advance::<L>(&mut u[i], &vn, self.h);
        }
    }
}

/// Row `i` of `U^{n+1} = Uⁿ + dt V^{n+½}`.
#[inline(always)]
fn advance<const L: usize>(u: &mut [f64; L], v: &[f64; L], h: f64) {
    let mut r = *u;
    for k in 0..L {
        r[k] += h * v[k];
    }
    *u = r;
}
