//! Several runs of the Paoli–Schatzman scheme that share one step matrix,
//! stepped together (a frequency or amplitude sweep of one scene).
//!
//! Every run ("lane") integrates
//!
//! ```text
//! M (U^{n+1} - 2U^n + U^{n-1})/dt² + K (β U^{n+1} + (1-2β) U^n + β U^{n-1}) = F_k + G_k^n - λ_k^n e_c
//! lo_k <= (u_c^{n+1} + e_k u_c^{n-1})/(1+e_k) <= hi_k
//! ```
//!
//! with the same `M`, `K`, `β`, `dt` and contact dof `c` (so the same
//! factor of `A = M + β dt² K` and the same projection column `w = A⁻¹ e_c`),
//! and its own steady load `F_k`, forcing terms `G_k^n = Σ_j shape_{k,j}
//! (β m_{k,j}^{n+1} + (1-2β) m_{k,j}^n + β m_{k,j}^{n-1})` (exact means of its
//! own time profiles), bounds, restitution and initial state.
//!
//! The state is stored structure-of-arrays, `u[i][lane]`, so the two banded
//! products, the forward and backward substitutions and the axpys run with
//! the lanes innermost, `L` at a time (`L` a compile-time constant: the
//! compiler vectorises the lane loops). Each lane performs exactly the
//! floating-point operations of [`PaoliSchatzman::step`](crate::Stepper::step)
//! for one run (single contact, undamped, massive contact node), in the
//! same order, so every lane is bit-identical to the single run of its data
//! (`U^n`, `λ^n`, the active bound, the step at which it turns non-finite).
//! What the single run computes on the side (the works `W_f`, `W_c`, the
//! energy) is not computed here.
//!
//! Supported: half-bandwidth 3 with at least 7 unknowns (the Hermite beam;
//! the paths of [`signorini_fem::SymBand::mul_vec`] and
//! [`signorini_fem::BandLdlt::solve_in_place`] this mirrors). Refused with a
//! [`SchemeError`]: damping, several contacts, a massless contact, lanes
//! that do not share `M`, `K` (bit for bit), the contact dof or the number of
//! forcing terms, other bandwidths, and a lane count outside `1..=L`.
//! Fewer lanes than `L` (the last batch of a sweep) are padded with copies
//! of lane 0, whose results are never reported.
//!
//! Cost (crates/run/benches/lockstep.rs, the paper's beam): the step is
//! compiled for the baseline x86-64 target, with AVX2 and with AVX-512F,
//! the widest the CPU has chosen at run time (no FMA contraction in any, so
//! the same bits). The products, the substitutions and `2U^n - U^{n-1}`
//! are written so that the compiler keeps the lanes in vector registers:
//! the edge rows lane-innermost like the interior ones, the row loops over
//! local slices (no reloads through `self`), and the level combinations
//! `2U^n - U^{n-1}`, `(1-2β) U^n + β U^{n-1}` made row by row just ahead of
//! the forward sweep into a ring of 8 rows (so `U^n`, `U^{n-1}` are read
//! once per step and the two combinations never leave the first-level
//! cache; stored whole, they cost two arrays of `dofs × L` more to stream).
//! Lanes with the same profile
//! share its means; a `Sine` profile's mean is `TimeProfile::mean`'s
//! formula with its factor `sin(ω δ/2)/(ω δ/2)` looked up by the bits of
//! `δ = t_{n+2} - t_{n+1}` (a copy of that formula: the bit-identity tests
//! fail if the two drift apart).

// The lane loops index several per-lane arrays by the lane on purpose:
// that is the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use crate::lanes::{backward, check_count, check_lanes, clamp, column, forward, impl_lockstep, lane_into, lockstep_builds, project_lanes, set_lane, Combine, LaneState, Refusals, TwoProducts};
use crate::{Active, LockstepLane, PaoliSchatzman, Sampler, SchemeError, Stepper};

/// `L` runs of the Paoli–Schatzman scheme sharing one step matrix, stepped
/// together (module docs). Allocates only at construction.
pub struct PaoliSchatzmanLockstep<const L: usize> {
    /// The lanes' shared state (`U^n` in `state.u`, the right-hand side
    /// and then `U^{n+1}` in `state.rhs`; the rings hold `2U^n - U^{n-1}`
    /// and `(1-2β) U^n + β U^{n-1}`), at level `n` (1 after construction:
    /// the start step is taken).
    state: LaneState<L>,
    beta: f64,
    u_prev: Vec<[f64; L]>,
    /// Per forcing term: the means over `[t_{n-1}, t_n]` and `[t_n, t_{n+1}]`.
    means: Vec<[[f64; L]; 2]>,
    /// Per forcing term: `dt² g` with `g = β m^{n+1} + (1-2β) m^n + β m^{n-1}`.
    dt2_gc: Vec<[f64; L]>,
}

/// The Paoli–Schatzman engine's structural refusals.
const REFUSALS: Refusals = Refusals {
    damping: "lockstep Paoli–Schatzman takes undamped problems only (damping: use PaoliSchatzman)",
    contacts: "lockstep Paoli–Schatzman takes exactly one contact (several: use PaoliSchatzman)",
    massless: "lockstep Paoli–Schatzman needs a massive contact node (massless: use PaoliSchatzman)",
    band: "lockstep Paoli–Schatzman supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)",
};

impl<const L: usize> PaoliSchatzmanLockstep<L> {
    /// Sets up `lanes.len()` runs (`1..=L`) of the Paoli–Schatzman scheme
    /// with parameter `β` and step `dt`, and takes each lane's start step
    /// exactly as [`PaoliSchatzman::new`] does (one Newmark(β, 1/2) step;
    /// Newmark(1/4, 1/2) when β = 0), so the batch is at level 1.
    ///
    /// Errors: everything [`PaoliSchatzman::new`] refuses (per lane), and
    /// [`SchemeError::Size`] for a lane count outside `1..=L`,
    /// [`SchemeError::Invalid`] for a restitution outside `[0, 1]`,
    /// [`SchemeError::Structure`] for damping, several contacts, a massless
    /// contact, a half-bandwidth other than 3 (or fewer than 7 unknowns), and
    /// lanes that differ in `M`, `K`, the contact dof or the number of
    /// forcing terms.
    pub fn new(beta: f64, dt: f64, lanes: Vec<LockstepLane>) -> Result<Self, SchemeError> {
        check_count::<L>(lanes.len())?;
        check_lanes(&lanes, &REFUSALS)?;
        let dy0 = &lanes[0].dynamics;
        let a = dy0.step_matrix(0.5 * dt, beta * dt * dt).factor()?;
        // Validates w_c as the single run does.
        let proj = column(&a, dy0.contact().dof)?;
        let terms = dy0.forcing.len();
        let state = LaneState::new(dy0, dt, 1, lanes.len(), &a, &proj);
        let mut s = Self { state, beta, u_prev: vec![[0.0; L]; dy0.n()], means: vec![[[0.0; L]; 2]; terms], dt2_gc: vec![[0.0; L]; terms] };
        for (k, ln) in lanes.into_iter().enumerate() {
            let LockstepLane { dynamics: dy, initial, restitution } = ln;
            let e = dy.contact().restitution.unwrap_or(restitution);
            let single = PaoliSchatzman::new(String::new(), dy.clone(), beta, e, dt, &initial)?;
            // The single run's means over [0, dt], [dt, 2 dt], … (the first two taken).
            s.state.add_lane(k, &dy, e, single.displacement(), |p| Sampler::means(p, 0.0, dt));
            for (j, m) in s.means.iter_mut().enumerate() {
                let sp = &mut s.state.samplers[j][k];
                m[0][k] = sp.next_value();
                m[1][k] = sp.next_value();
            }
            set_lane(&mut s.u_prev, k, single.previous_displacement());
        }
        // Padding lanes copy lane 0 (and its means, every step).
        s.state.finish(&mut [&mut s.u_prev]);
        for k in s.state.lanes..L {
            for m in s.means.iter_mut() {
                (m[0][k], m[1][k]) = (m[0][0], m[1][0]);
            }
        }
        Ok(s)
    }

    /// Lanes in use.
    pub fn lanes(&self) -> usize {
        self.state.lanes
    }

    /// Number of unknowns per lane.
    pub fn dofs(&self) -> usize {
        self.state.dofs
    }

    /// The contact dof (shared).
    pub fn contact_dof(&self) -> usize {
        self.state.c
    }

    /// Time step.
    pub fn dt(&self) -> f64 {
        self.state.dt
    }

    /// β.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Index `n` of the current level `U^n` (every lane's).
    pub fn level(&self) -> usize {
        self.state.n
    }

    /// `t_n = n dt`.
    pub fn time(&self) -> f64 {
        self.state.n as f64 * self.state.dt
    }

    /// The time the contact forces belong to: `t_{n-1}` (massive contact node).
    pub fn lambda_time(&self) -> f64 {
        (self.state.n - 1) as f64 * self.state.dt
    }

    /// Lane `k`'s `U^n` into `out` (length [`dofs`](Self::dofs)).
    #[track_caller]
    pub fn displacement_into(&self, k: usize, out: &mut [f64]) {
        self.state.displacement_into(k, out)
    }

    /// Lane `k`'s `U^{n-1}` into `out`.
    #[track_caller]
    pub fn previous_displacement_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.u_prev, self.state.lanes, k, out)
    }

    /// Lane `k`'s `u_i^n` (for example the tip, `i` = [`contact_dof`](Self::contact_dof)).
    #[track_caller]
    pub fn value(&self, k: usize, i: usize) -> f64 {
        self.state.value(k, i)
    }

    /// Lane `k`'s contact force `λ^{n-1}` of the last step (at
    /// [`lambda_time`](Self::lambda_time); 0 before the first step).
    #[track_caller]
    pub fn contact_force(&self, k: usize) -> f64 {
        self.state.contact_force(k)
    }

    /// Which bound held lane `k`'s contact in the last step.
    #[track_caller]
    pub fn contact_status(&self, k: usize) -> Active {
        self.state.contact_status(k)
    }

    /// The error the single run of lane `k` would have returned
    /// ([`SchemeError::NonFinite`] at the step its state turned non-finite),
    /// if it has; that lane's later values are meaningless, the other lanes
    /// are unaffected.
    #[track_caller]
    pub fn lane_failure(&self, k: usize) -> Option<&SchemeError> {
        self.state.lane_failure(k)
    }

    /// Number of lanes in use that have failed so far.
    pub fn failed_lanes(&self) -> usize {
        self.state.failed_lanes()
    }

    /// Advances every lane one step (module docs); returns the new level.
    /// A lane that turns non-finite is recorded ([`lane_failure`](Self::lane_failure)).
    ///
    /// The same code is compiled three times, for the baseline x86-64 target,
    /// with AVX2 (4 lanes per instruction instead of 2) and with AVX-512F
    /// (8), and the widest the CPU has runs. Rust never contracts
    /// `a * b + c` into an FMA, so every build rounds every operation alike.
    pub fn step(&mut self) -> usize {
        self.step_dispatch()
    }

    lockstep_builds!();

    #[inline(always)]
    fn step_body(&mut self) -> usize {
        let st = &mut self.state;
        let dt2 = st.dt * st.dt;
        let beta = self.beta;
        let a = 1.0 - 2.0 * beta;
        // Forcing coefficients of every term and lane:
        // g = β m_{n+1} + (1-2β) m_n + β m_{n-1}, then dt² g.
        let (dt, nf) = (st.dt, st.n as f64);
        let (t0, t1) = ((nf + 1.0) * dt, (nf + 2.0) * dt);
        st.means(t0, t1);
        for ((m, g), next) in self.means.iter_mut().zip(self.dt2_gc.iter_mut()).zip(&st.next) {
            for k in 0..L {
                let gc = beta * next[k] + a * m[1][k] + beta * m[0][k];
                g[k] = dt2 * gc;
            }
            *m = [m[1], *next];
        }
        // rhs = M t_mass + dt² (F - K t_stiff) + Σ_j dt² g_j shape_j, row by
        // row, each row then eliminated at once (the forward sweep of
        // `BandLdlt::solve_p3`); t_mass = 2U^n - U^{n-1} and t_stiff =
        // (1-2β) U^n + β U^{n-1} are made row by row just ahead of the
        // products that read them (a ring of RING rows: U^n and U^{n-1} are
        // read once, and t stays in L1).
        let n = st.dofs;
        let (u, up) = (&st.u[..n], &self.u_prev[..n]);
        let mut rows = TwoProducts {
            mass: &st.mass[..n],
            stiff: &st.stiff[..n],
            load: &st.load[..n],
            gs: &self.dt2_gc[..],
            shape_rows: &st.shape_rows[..],
            t_mass: &mut st.t_mass,
            t_stiff: &mut st.t_stiff,
            scale: dt2,
            combine: Levels { u, up, a, beta },
        };
        forward::<L, _>(&mut rows, &st.l, &mut st.rhs[..n]);
        backward::<L, _>(&mut st.rhs[..n], &st.lt, &st.inv_d, &mut ());
        self.project();
        // Rotate: U^{n-1} <- U^n <- U^{n+1}.
        let st = &mut self.state;
        std::mem::swap(&mut self.u_prev, &mut st.u);
        std::mem::swap(&mut st.u, &mut st.rhs);
        st.n += 1;
        for k in 0..L {
            st.lams[k] = -st.mu[k] / dt2;
        }
        st.check_finite(None);
        st.n
    }

    /// The projection of every lane (`Projection::project`'s operations),
    /// bounds moved by each lane's restitution; `mu` per lane (0 inside).
    #[inline(always)]
    fn project(&mut self) {
        let st = &mut self.state;
        let c = st.c;
        let (yc, up_c) = (st.rhs[c], self.u_prev[c]);
        let mut xc = [0.0; L];
        for k in 0..L {
            let e = st.e[k];
            let lo = (1.0 + e) * st.lo[k] - e * up_c[k];
            let hi = if st.hi[k].is_finite() { (1.0 + e) * st.hi[k] - e * up_c[k] } else { f64::INFINITY };
            (xc[k], st.acts[k]) = clamp(yc[k], lo, hi);
        }
        project_lanes::<L>(&mut st.rhs, &st.w, st.inv_wc, c, &xc, &st.acts, &mut st.mu);
    }
}

impl_lockstep!(PaoliSchatzmanLockstep);

/// Rows of `2U^n - U^{n-1}` and `(1-2β) U^n + β U^{n-1}` (`a = 1-2β`).
struct Levels<'a, const L: usize> {
    u: &'a [[f64; L]],
    up: &'a [[f64; L]],
    a: f64,
    beta: f64,
}

impl<const L: usize> Combine<L> for Levels<'_, L> {
    #[inline(always)]
    fn combine(&self, j: usize) -> ([f64; L], [f64; L]) {
        let (u, up) = (&self.u[j], &self.up[j]);
        let (mut tm, mut ts) = ([0.0; L], [0.0; L]);
        for k in 0..L {
            tm[k] = 2.0 * u[k] - up[k];
            ts[k] = self.a * u[k] + self.beta * up[k];
        }
        (tm, ts)
    }
}

/// The registry schemes a lockstep engine takes, with their parameters
/// (from a [`SchemeSpec`](crate::SchemeSpec) whose
/// [`Capabilities::lockstep`](crate::Capabilities::lockstep) is set).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LockstepScheme {
    /// `ps(e, β)`: [`PaoliSchatzmanLockstep`].
    PaoliSchatzman {
        /// β.
        beta: f64,
        /// Restitution `e`.
        restitution: f64,
    },
    /// `moreau-jean(θ, e, γ)`: [`MoreauJeanLockstep`](crate::MoreauJeanLockstep).
    MoreauJean {
        /// θ.
        theta: f64,
        /// Restitution `e`.
        restitution: f64,
        /// The activation predictor's γ.
        gamma: f64,
    },
    /// `moreau-jean-projected(θ, e, γ)`: [`MoreauJeanLockstep::projected`](crate::MoreauJeanLockstep::projected).
    MoreauJeanProjected {
        /// θ.
        theta: f64,
        /// Restitution `e`.
        restitution: f64,
        /// The index set's predictor γ.
        gamma: f64,
    },
    /// `nsga(ρ∞, e)`: [`NsgaLockstep`](crate::NsgaLockstep).
    Nsga {
        /// ρ∞.
        rho_inf: f64,
        /// Restitution `e`.
        restitution: f64,
    },
    /// `contact-stabilized` (no parameters, no restitution):
    /// [`ContactStabilizedLockstep`](crate::ContactStabilizedLockstep).
    ContactStabilized,
    /// `cd-lagrange(e)`: [`CdLagrangeLockstep`](crate::CdLagrangeLockstep).
    CdLagrange {
        /// Restitution `e`.
        restitution: f64,
    },
    /// `d1-minus-linear(e)` and `d1-minus-linear-velocity(e)`:
    /// [`D1MinusLinearLockstep`](crate::D1MinusLinearLockstep).
    D1MinusLinear {
        /// The level of the contact forces.
        level: crate::D1Level,
        /// Restitution `e`.
        restitution: f64,
    },
    /// `moreau-jean-combined(θ, e)`: [`MoreauJeanCombinedLockstep`](crate::MoreauJeanCombinedLockstep).
    MoreauJeanCombined {
        /// θ.
        theta: f64,
        /// Restitution `e`.
        restitution: f64,
    },
}

impl LockstepScheme {
    /// The engine and parameters of `spec`, if it can run in lockstep.
    pub fn of(spec: &crate::SchemeSpec) -> Option<Self> {
        if !spec.capabilities().lockstep {
            return None;
        }
        match spec.family().name {
            "ps" => Some(Self::PaoliSchatzman { beta: spec.param("beta")?, restitution: spec.param("e")? }),
            "moreau-jean" => Some(Self::MoreauJean { theta: spec.param("theta")?, restitution: spec.param("e")?, gamma: spec.param("gamma")? }),
            "moreau-jean-projected" => Some(Self::MoreauJeanProjected { theta: spec.param("theta")?, restitution: spec.param("e")?, gamma: spec.param("gamma")? }),
            "nsga" => Some(Self::Nsga { rho_inf: spec.param("rho_inf")?, restitution: spec.param("e")? }),
            "contact-stabilized" => Some(Self::ContactStabilized),
            "cd-lagrange" => Some(Self::CdLagrange { restitution: spec.param("e")? }),
            "d1-minus-linear" => Some(Self::D1MinusLinear { level: crate::D1Level::Acceleration, restitution: spec.param("e")? }),
            "d1-minus-linear-velocity" => Some(Self::D1MinusLinear { level: crate::D1Level::Velocity, restitution: spec.param("e")? }),
            "moreau-jean-combined" => Some(Self::MoreauJeanCombined { theta: spec.param("theta")?, restitution: spec.param("e")? }),
            _ => None,
        }
    }

    /// The restitution of the scheme (a lane's [`LockstepLane::restitution`]).
    pub fn restitution(&self) -> f64 {
        match *self {
            Self::PaoliSchatzman { restitution, .. }
            | Self::MoreauJean { restitution, .. }
            | Self::MoreauJeanProjected { restitution, .. }
            | Self::Nsga { restitution, .. }
            | Self::CdLagrange { restitution }
            | Self::D1MinusLinear { restitution, .. }
            | Self::MoreauJeanCombined { restitution, .. } => restitution,
            Self::ContactStabilized => 0.0,
        }
    }
}
