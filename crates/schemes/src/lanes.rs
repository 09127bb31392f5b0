//! What every lockstep engine ([`PaoliSchatzmanLockstep`](crate::PaoliSchatzmanLockstep),
//! [`MoreauJeanLockstep`](crate::MoreauJeanLockstep), [`NsgaLockstep`](crate::NsgaLockstep),
//! [`ContactStabilizedLockstep`](crate::ContactStabilizedLockstep),
//! [`CdLagrangeLockstep`](crate::CdLagrangeLockstep),
//! [`D1MinusLinearLockstep`](crate::D1MinusLinearLockstep),
//! [`MoreauJeanCombinedLockstep`](crate::MoreauJeanCombinedLockstep))
//! shares: the lane of a batch ([`LockstepLane`]), the time loop's view of
//! an engine ([`Lockstep`]), and one lane state ([`LaneState`]: the shared
//! matrices' rows, the factor's rows and projection column, the loads and
//! forcing terms lane-innermost, the contact's bounds and results, the
//! failures) with the pieces of a step every engine runs on it: the lane
//! checks, the forcing's samples, the forward sweep (the right-hand side's
//! rows made just ahead of their elimination, [`Rows`]), the backward
//! sweep (with a per-row hook), the projection of a contact on every lane,
//! the failure check and the builds for the widest vector unit.
//!
//! Each piece performs the operations of the single run it mirrors, per
//! lane and in the same order (the half-bandwidth-3 paths of
//! [`signorini_fem::SymBand::mul_vec`], [`signorini_fem::BandLdlt::solve_in_place`],
//! `signorini_contact::Projection::project`), so an engine built from them
//! is its single runs bit for bit when its own vectors are.

// The lane loops index several per-lane arrays by the lane on purpose:
// that is the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use crate::{Active, Dynamics, Initial, Sampler, SchemeError, TimeProfile};
use signorini_contact::Projection;
use signorini_fem::{BandLdlt, SymBand};

/// One run of a lockstep batch: its problem, initial state and restitution
/// (the scheme's `e`, overridden by the contact's own
/// [`Contact::restitution`](crate::Contact::restitution) as in the single
/// run).
#[derive(Clone, Debug)]
pub struct LockstepLane {
    /// The problem (shares `M`, `K`, the contact dof and the number of
    /// forcing terms with every other lane).
    pub dynamics: Dynamics,
    /// `U^0`, `V^0`.
    pub initial: Initial,
    /// Restitution coefficient `e ∈ [0, 1]`.
    pub restitution: f64,
}

/// What a time loop needs of a lockstep engine ([`PaoliSchatzmanLockstep`](crate::PaoliSchatzmanLockstep),
/// [`MoreauJeanLockstep`](crate::MoreauJeanLockstep), [`NsgaLockstep`](crate::NsgaLockstep),
/// [`ContactStabilizedLockstep`](crate::ContactStabilizedLockstep),
/// [`CdLagrangeLockstep`](crate::CdLagrangeLockstep),
/// [`D1MinusLinearLockstep`](crate::D1MinusLinearLockstep)):
/// `L` runs sharing one step matrix, stepped together, each lane bit for
/// bit its single run. Every lane-indexed method asserts `k < lanes()`.
pub trait Lockstep {
    /// Lanes in use.
    fn lanes(&self) -> usize;
    /// Number of unknowns per lane.
    fn dofs(&self) -> usize;
    /// The contact dof (shared).
    fn contact_dof(&self) -> usize;
    /// Time step.
    fn dt(&self) -> f64;
    /// Index `n` of the current level (every lane's): 1 after construction
    /// for a two-step scheme (its start step taken), else 0.
    fn level(&self) -> usize;
    /// `t_n = n dt`.
    fn time(&self) -> f64;
    /// The time the contact forces of the last step belong to (what the
    /// single run's report gives).
    fn lambda_time(&self) -> f64;
    /// Advances every lane one step; returns the new level.
    fn step(&mut self) -> usize;
    /// Lane `k`'s `U^n` into `out` (length [`dofs`](Self::dofs)).
    fn displacement_into(&self, k: usize, out: &mut [f64]);
    /// Lane `k`'s `u_i^n`.
    fn value(&self, k: usize, i: usize) -> f64;
    /// Lane `k`'s contact force of the last step (the single run's report).
    fn contact_force(&self, k: usize) -> f64;
    /// Which bound held lane `k`'s contact in the last step.
    fn contact_status(&self, k: usize) -> Active;
    /// The error lane `k`'s single run would have returned, if it has.
    fn lane_failure(&self, k: usize) -> Option<&SchemeError>;
    /// Every lane's results of the last step at once (`U^n`, the contact
    /// force and status, the failure): what a time loop reads after each
    /// step, without a call per lane.
    fn results(&self) -> LaneResults<'_>;
}

/// Every lane's results of a lockstep engine's last step ([`Lockstep::results`]),
/// read in place: the same values as the engine's lane-indexed methods.
/// Every lane-indexed method asserts `k < lanes()`.
#[derive(Clone, Copy, Debug)]
pub struct LaneResults<'a> {
    lanes: usize,
    /// The engine's width `L` (row `i` of `U^n` is `u[i L..(i + 1) L]`).
    width: usize,
    u: &'a [f64],
    forces: &'a [f64],
    status: &'a [Active],
    failures: &'a [Option<SchemeError>],
}

impl<'a> LaneResults<'a> {
    /// Lanes in use.
    #[inline]
    pub fn lanes(&self) -> usize {
        self.lanes
    }

    /// Lane `k`'s `u_i^n`.
    #[inline]
    #[track_caller]
    pub fn value(&self, k: usize, i: usize) -> f64 {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.u[i * self.width + k]
    }

    /// Lane `k`'s `U^n` into `out` (one value per unknown).
    #[inline]
    #[track_caller]
    pub fn displacement_into(&self, k: usize, out: &mut [f64]) {
        assert!(k < self.lanes && out.len() * self.width == self.u.len(), "lane {k} of {}, out of length {} (expected {})", self.lanes, out.len(), self.u.len() / self.width);
        for (o, row) in out.iter_mut().zip(self.u.chunks_exact(self.width)) {
            *o = row[k];
        }
    }

    /// Lane `k`'s contact force of the last step.
    #[inline]
    #[track_caller]
    pub fn contact_force(&self, k: usize) -> f64 {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.forces[k]
    }

    /// Which bound held lane `k`'s contact in the last step.
    #[inline]
    #[track_caller]
    pub fn contact_status(&self, k: usize) -> Active {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.status[k]
    }

    /// The error lane `k`'s single run would have returned, if it has.
    #[inline]
    #[track_caller]
    pub fn failure(&self, k: usize) -> Option<&'a SchemeError> {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.failures[k].as_ref()
    }
}

/// A band row of half-bandwidth 3: `[A_ii, A_i,i-1, A_i,i-2, A_i,i-3,
/// A_i+1,i, A_i+2,i, A_i+3,i]` (zeros outside the matrix).
pub(crate) type Row7 = [f64; 7];

/// Rows of a ring ([`Rows::prepare`]) kept at once (a product's row reads
/// seven): a power of two, at least 7.
pub(crate) const RING: usize = 8;

/// Step lengths `δ` remembered by [`SincTable`] (the rounding of
/// `(n+2) dt - (n+1) dt` gives a handful of values; four catch > 99.99%).
pub(crate) const SINC_SLOTS: usize = 4;

/// The messages of an engine's structural refusals (each names the engine
/// and the single run to use instead).
pub(crate) struct Refusals {
    pub(crate) damping: &'static str,
    pub(crate) contacts: &'static str,
    pub(crate) massless: &'static str,
    pub(crate) band: &'static str,
}

/// The lane state every lockstep engine keeps, lane-innermost (`x[i][lane]`),
/// and the shared factor: an engine adds its own vectors and parameters.
/// Allocates only at construction.
pub(crate) struct LaneState<const L: usize> {
    pub(crate) dt: f64,
    /// Level `n` of `U^n`.
    pub(crate) n: usize,
    /// Lanes in use (`1..=L`); the rest copy lane 0.
    pub(crate) lanes: usize,
    pub(crate) dofs: usize,
    pub(crate) c: usize,
    pub(crate) mass: Vec<Row7>,
    pub(crate) stiff: Vec<Row7>,
    /// Rows of the step matrix's factor `L` (`l[i] = [L_i,i-1, L_i,i-2,
    /// L_i,i-3]`), of `Lᵀ` (`lt[i] = [L_i+1,i, L_i+2,i, L_i+3,i]`) and `1/D`.
    pub(crate) l: Vec<[f64; 3]>,
    pub(crate) lt: Vec<[f64; 3]>,
    pub(crate) inv_d: Vec<f64>,
    /// The projection column `A⁻¹ e_c` and `1/w_c` (as `Projection` has them).
    pub(crate) w: Vec<f64>,
    pub(crate) inv_wc: f64,
    /// `U^n`.
    pub(crate) u: Vec<[f64; L]>,
    /// The right-hand side, then the solve's result.
    pub(crate) rhs: Vec<[f64; L]>,
    /// Two rings of rows made just ahead of the forward sweep (row `j` in
    /// slot `j % RING`): the arguments of the two banded products.
    pub(crate) t_mass: [[f64; L]; RING],
    pub(crate) t_stiff: [[f64; L]; RING],
    pub(crate) load: Vec<[f64; L]>,
    /// The forcing terms' shapes, row by row: entry `i·terms + j` is term
    /// `j`'s shape at row `i`, per lane.
    pub(crate) shape_rows: Vec<[f64; L]>,
    /// Per forcing term, its shape per row (during construction only).
    shapes: Vec<Vec<[f64; L]>>,
    /// Per forcing term: the profile of each lane in use.
    pub(crate) profiles: Vec<Vec<TimeProfile>>,
    /// Per forcing term and lane, its samples step after step as the single
    /// run takes them ([`Sampler`]; advanced only on lanes that own their
    /// samples, and for the means of a `Sine` only where the engine does not
    /// take them from the [`SincTable`]).
    pub(crate) samplers: Vec<Vec<Sampler>>,
    /// Per forcing term and lane: the first lane with the same profile
    /// (its samples are computed once and copied).
    pub(crate) mean_src: Vec<[usize; L]>,
    /// Per forcing term: its latest samples ([`means`](Self::means),
    /// [`samples`](Self::samples)).
    pub(crate) next: Vec<[f64; L]>,
    pub(crate) lo: [f64; L],
    pub(crate) hi: [f64; L],
    pub(crate) e: [f64; L],
    /// The projection's multiplier per lane (0 when free).
    pub(crate) mu: [f64; L],
    pub(crate) lams: [f64; L],
    pub(crate) acts: [Active; L],
    pub(crate) failed: [Option<SchemeError>; L],
    /// Run the AVX2 build of the step.
    pub(crate) avx2: bool,
    /// Run the AVX-512 build of the step (implies `avx2`).
    pub(crate) avx512: bool,
    /// A Sine profile's `sin(ω δ/2)/(ω δ/2)` per step length `δ`.
    pub(crate) sinc: SincTable<L>,
}

/// [`SchemeError::Size`] unless `1 <= lanes <= L`.
pub(crate) fn check_count<const L: usize>(lanes: usize) -> Result<(), SchemeError> {
    if lanes == 0 || lanes > L {
        return Err(SchemeError::Size { what: "lockstep lanes (1..=L)", got: lanes, expected: L });
    }
    Ok(())
}

/// What every engine refuses of its lanes (in this order, lane by lane): a
/// restitution outside `[0, 1]`, damping, other than one contact, a
/// massless contact, lanes that differ from the first in `M`, `K` (bit for
/// bit), the contact dof or the number of forcing terms; then a
/// half-bandwidth other than 3 or fewer than 7 unknowns.
pub(crate) fn check_lanes(lanes: &[LockstepLane], why: &Refusals) -> Result<(), SchemeError> {
    let dy0 = &lanes[0].dynamics;
    for ln in lanes {
        let dy = &ln.dynamics;
        if !(0.0..=1.0).contains(&ln.restitution) {
            return Err(SchemeError::Invalid { field: "restitution", value: ln.restitution, allowed: "[0, 1]" });
        }
        if dy.damping.is_some() {
            return Err(SchemeError::Structure(why.damping));
        }
        if dy.k() != 1 {
            return Err(SchemeError::Structure(why.contacts));
        }
        if dy.massless_contact() {
            return Err(SchemeError::Structure(why.massless));
        }
        if !same_band(&dy.mass, &dy0.mass) || !same_band(&dy.stiffness, &dy0.stiffness) {
            return Err(SchemeError::Structure("lockstep lanes must share the mass and stiffness matrices bit for bit"));
        }
        if dy.contact().dof != dy0.contact().dof {
            return Err(SchemeError::Structure("lockstep lanes must share the contact dof"));
        }
        if dy.forcing.len() != dy0.forcing.len() {
            return Err(SchemeError::Structure("lockstep lanes must have the same number of forcing terms"));
        }
    }
    if dy0.mass.half_bandwidth() != 3 || dy0.stiffness.half_bandwidth() != 3 || dy0.n() < 7 {
        return Err(SchemeError::Structure(why.band));
    }
    Ok(())
}

/// The projection column `A⁻¹ e_c` of a factor, validated as the single
/// runs validate it (`Projection::new`).
pub(crate) fn column(a: &BandLdlt, c: usize) -> Result<Projection, SchemeError> {
    let mut w = vec![0.0; a.n()];
    w[c] = 1.0;
    a.solve_in_place(&mut w);
    Ok(Projection::new(c, w)?)
}

impl<const L: usize> LaneState<L> {
    /// The state of `used` lanes of the problem `dy0` (every lane's `M`,
    /// `K`, contact dof and number of forcing terms), with the step
    /// matrix's factor `a` and its projection column `proj`; lanes are
    /// then added by [`add_lane`](Self::add_lane) and the batch closed by
    /// [`finish`](Self::finish).
    pub(crate) fn new(dy0: &Dynamics, dt: f64, n: usize, used: usize, a: &BandLdlt, proj: &Projection) -> Self {
        let dofs = dy0.n();
        let (lf, ltf, inv_d) = a.band_factors();
        let terms = dy0.forcing.len();
        let zeros = vec![[0.0; L]; dofs];
        Self {
            dt,
            n,
            lanes: used,
            dofs,
            c: dy0.contact().dof,
            mass: rows7(&dy0.mass),
            stiff: rows7(&dy0.stiffness),
            l: lf.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect(),
            lt: ltf.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect(),
            inv_d: inv_d.to_vec(),
            w: proj.influence().to_vec(),
            // 1/w_c as Projection computes it.
            inv_wc: 1.0 / proj.wc(),
            u: zeros.clone(),
            rhs: zeros.clone(),
            t_mass: [[0.0; L]; RING],
            t_stiff: [[0.0; L]; RING],
            load: zeros.clone(),
            shape_rows: Vec::new(),
            shapes: vec![zeros; terms],
            profiles: vec![Vec::with_capacity(used); terms],
            samplers: (0..terms).map(|_| Vec::with_capacity(used)).collect(),
            mean_src: vec![[0; L]; terms],
            next: vec![[0.0; L]; terms],
            lo: [0.0; L],
            hi: [0.0; L],
            e: [0.0; L],
            mu: [0.0; L],
            lams: [0.0; L],
            acts: [Active::None; L],
            failed: std::array::from_fn(|_| None),
            avx2: avx2_available(),
            avx512: avx512_available(),
            sinc: SincTable::new(terms),
        }
    }

    /// Lane `k`'s profiles (each with the sampler `sampler` makes of it),
    /// shapes, load, bounds, restitution `e` and `U` (`u`).
    pub(crate) fn add_lane(&mut self, k: usize, dy: &Dynamics, e: f64, u: &[f64], sampler: impl Fn(&TimeProfile) -> Sampler) {
        let ct = *dy.contact();
        for (j, f) in dy.forcing.iter().enumerate() {
            self.profiles[j].push(f.time.clone());
            self.samplers[j].push(sampler(&f.time));
            self.mean_src[j][k] = self.profiles[j].iter().position(|q| same_profile(q, &f.time)).unwrap_or(k);
            for (row, g) in self.shapes[j].iter_mut().zip(&f.shape) {
                row[k] = *g;
            }
        }
        for (row, f) in self.load.iter_mut().zip(&dy.load) {
            row[k] = *f;
        }
        (self.lo[k], self.hi[k], self.e[k]) = (ct.bounds.lo, ct.bounds.hi, e);
        set_lane(&mut self.u, k, u);
    }

    /// Pads the lanes after the ones in use with copies of lane 0 (in `U`,
    /// the loads, the shapes, the samples' sources, the bounds, and in the
    /// engine's own vectors `extra`), and lays the shapes out row by row.
    pub(crate) fn finish(&mut self, extra: &mut [&mut Vec<[f64; L]>]) {
        for k in self.lanes..L {
            for v in [&mut self.u, &mut self.load].into_iter().chain(self.shapes.iter_mut()).chain(extra.iter_mut().map(|v| &mut **v)) {
                for row in v.iter_mut() {
                    row[k] = row[0];
                }
            }
            for src in self.mean_src.iter_mut() {
                src[k] = 0;
            }
            (self.lo[k], self.hi[k], self.e[k]) = (self.lo[0], self.hi[0], self.e[0]);
        }
        let shapes = std::mem::take(&mut self.shapes);
        self.shape_rows = (0..self.dofs).flat_map(|i| shapes.iter().map(move |sh| sh[i])).collect();
    }

    /// Each forcing term's means over `[t0, t1]` on every lane, into
    /// [`next`](Self::next) term by term: a `Sine`'s by `TimeProfile::mean`'s
    /// formula with its factor `sin(ω δ/2)/(ω δ/2)` looked up by the bits of
    /// `δ = t1 - t0` (one `sin` per lane and step instead of two), any other
    /// profile's from its sampler (which must give the means over
    /// `[t0, t1]`); lanes with the same profile share them.
    #[inline(always)]
    pub(crate) fn means(&mut self, t0: f64, t1: f64) {
        let slot = self.sinc.slot(&self.profiles, t1 - t0);
        for ((((prof, src), sc), sps), next) in self.profiles.iter().zip(&self.mean_src).zip(&self.sinc.table).zip(self.samplers.iter_mut()).zip(self.next.iter_mut()) {
            for k in 0..L {
                next[k] = if src[k] != k {
                    next[src[k]]
                } else if let &TimeProfile::Sine { amplitude, omega } = &prof[k] {
                    amplitude * (omega * 0.5 * (t0 + t1)).sin() * sc[slot][k]
                } else {
                    sps[k].next_value()
                };
            }
        }
    }

    /// Each forcing term's next sample from its sampler on every lane,
    /// into [`next`](Self::next) term by term; lanes with the same profile
    /// share them.
    #[inline(always)]
    pub(crate) fn samples(&mut self) {
        for ((src, sps), next) in self.mean_src.iter().zip(self.samplers.iter_mut()).zip(self.next.iter_mut()) {
            for k in 0..L {
                next[k] = if src[k] != k { next[src[k]] } else { sps[k].next_value() };
            }
        }
    }

    /// After a step to level `n`: records, on each lane in use that has not
    /// failed yet, a [`SchemeError::NonFinite`] at `(n, n dt)` if `u_c`, the
    /// contact force or (for a scheme that checks it) `v_c` is not finite,
    /// as the single run's report does.
    #[inline(always)]
    pub(crate) fn check_finite(&mut self, vc: Option<&[f64; L]>) {
        let t = self.n as f64 * self.dt;
        let uc = self.u[self.c];
        for k in 0..self.lanes {
            let v_ok = match vc {
                Some(v) => v[k].is_finite(),
                None => true,
            };
            if self.failed[k].is_none() && !(uc[k].is_finite() && v_ok && self.lams[k].is_finite()) {
                self.failed[k] = Some(SchemeError::NonFinite { step: self.n, time: t });
            }
        }
    }

    /// Lane `k`'s `U^n` into `out` (length `dofs`).
    #[track_caller]
    pub(crate) fn displacement_into(&self, k: usize, out: &mut [f64]) {
        lane_into(&self.u, self.lanes, k, out);
    }

    #[track_caller]
    pub(crate) fn value(&self, k: usize, i: usize) -> f64 {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.u[i][k]
    }

    #[track_caller]
    pub(crate) fn contact_force(&self, k: usize) -> f64 {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.lams[k]
    }

    #[track_caller]
    pub(crate) fn contact_status(&self, k: usize) -> Active {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.acts[k]
    }

    #[track_caller]
    pub(crate) fn lane_failure(&self, k: usize) -> Option<&SchemeError> {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.failed[k].as_ref()
    }

    /// Every lane's results ([`Lockstep::results`]).
    pub(crate) fn results(&self) -> LaneResults<'_> {
        LaneResults { lanes: self.lanes, width: L, u: self.u.as_flattened(), forces: &self.lams, status: &self.acts, failures: &self.failed }
    }

    pub(crate) fn failed_lanes(&self) -> usize {
        self.failed[..self.lanes].iter().filter(|f| f.is_some()).count()
    }
}

/// Lane `k` (of `lanes` in use) of a lane-innermost vector into `out`.
#[track_caller]
pub(crate) fn lane_into<const L: usize>(x: &[[f64; L]], lanes: usize, k: usize, out: &mut [f64]) {
    assert!(k < lanes && out.len() == x.len(), "lane {k} of {lanes}, out of length {} (expected {})", out.len(), x.len());
    for (o, row) in out.iter_mut().zip(x) {
        *o = row[k];
    }
}

/// Sets lane `k` of a lane-innermost vector to `x`.
pub(crate) fn set_lane<const L: usize>(v: &mut [[f64; L]], k: usize, x: &[f64]) {
    for (row, x) in v.iter_mut().zip(x) {
        row[k] = *x;
    }
}

/// The methods every engine has about its builds, and its step's dispatch
/// to the widest (`step_body` compiled for the baseline x86-64 target,
/// with AVX2 and with AVX-512F; Rust never contracts `a * b + c` into an
/// FMA, so every build rounds every operation alike). Inside the engine's
/// `impl` block; the engine has a `state: LaneState<L>` and a `step_body`.
macro_rules! lockstep_builds {
    () => {
        /// Uses the baseline x86-64 (SSE2) code even where the CPU has AVX2
        /// (the results are the same bits; for tests and measurements).
        pub fn portable(mut self) -> Self {
            self.state.avx2 = false;
            self.state.avx512 = false;
            self
        }

        /// Uses at most the AVX2 build, even where the CPU has AVX-512 (the
        /// results are the same bits; for tests and measurements).
        pub fn without_avx512(mut self) -> Self {
            self.state.avx512 = false;
            self
        }

        /// Keeps the AVX2 build only if `avx2`, the AVX-512 one only if
        /// `avx512` and `avx2` (the same bits; for [`LockstepBatch`](crate::LockstepBatch)).
        pub(crate) fn restrict_builds(&mut self, avx2: bool, avx512: bool) {
            self.state.avx2 &= avx2;
            self.state.avx512 &= avx512 && avx2;
        }

        /// Whether the step runs the AVX-512 build (chosen at construction
        /// from the running CPU; never FMA).
        pub fn uses_avx512(&self) -> bool {
            self.state.avx512
        }

        /// Whether the step runs the AVX2 build (chosen at construction
        /// from the running CPU; never FMA, so the same bits).
        pub fn uses_avx2(&self) -> bool {
            self.state.avx2
        }

        /// Advances every lane one step with the build for the widest
        /// vector unit the CPU has; returns the new level.
        fn step_dispatch(&mut self) -> usize {
            #[cfg(target_arch = "x86_64")]
            if self.state.avx512 {
                // SAFETY: `avx512` is true only if `is_x86_feature_detected!`
                // reported AVX-512F and AVX2 on the running CPU (set in `new`).
                return unsafe { self.step_avx512() };
            }
            #[cfg(target_arch = "x86_64")]
            if self.state.avx2 {
                // SAFETY: `avx2` is true only if `is_x86_feature_detected!("avx2")`
                // reported AVX2 on the running CPU (set in `new`).
                return unsafe { self.step_avx2() };
            }
            self.step_body()
        }

        /// `step_body` compiled with AVX2 (4 lanes per instruction).
        ///
        /// # Safety
        /// The CPU must support AVX2.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        unsafe fn step_avx2(&mut self) -> usize {
            self.step_body()
        }

        /// `step_body` compiled with AVX-512F (8 lanes per instruction).
        /// `avx512f` brings `fma` along as a target feature, but Rust never
        /// contracts `a * b + c` into an FMA: the same bits.
        ///
        /// # Safety
        /// The CPU must support AVX-512F and AVX2.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,avx2")]
        unsafe fn step_avx512(&mut self) -> usize {
            self.step_body()
        }
    };
}
pub(crate) use lockstep_builds;

/// [`Lockstep`] for an engine with a `state: LaneState<L>`, a
/// `step_dispatch` ([`lockstep_builds`]) and a `lambda_time(&self)`.
macro_rules! impl_lockstep {
    ($engine:ident) => {
        impl<const L: usize> $crate::lanes::Lockstep for $engine<L> {
            fn lanes(&self) -> usize {
                self.state.lanes
            }
            fn dofs(&self) -> usize {
                self.state.dofs
            }
            fn contact_dof(&self) -> usize {
                self.state.c
            }
            fn dt(&self) -> f64 {
                self.state.dt
            }
            fn level(&self) -> usize {
                self.state.n
            }
            fn time(&self) -> f64 {
                self.state.n as f64 * self.state.dt
            }
            fn lambda_time(&self) -> f64 {
                $engine::lambda_time(self)
            }
            fn step(&mut self) -> usize {
                self.step_dispatch()
            }
            fn displacement_into(&self, k: usize, out: &mut [f64]) {
                self.state.displacement_into(k, out)
            }
            fn value(&self, k: usize, i: usize) -> f64 {
                self.state.value(k, i)
            }
            fn contact_force(&self, k: usize) -> f64 {
                self.state.contact_force(k)
            }
            fn contact_status(&self, k: usize) -> $crate::Active {
                self.state.contact_status(k)
            }
            fn lane_failure(&self, k: usize) -> Option<&$crate::SchemeError> {
                self.state.lane_failure(k)
            }
            fn results(&self) -> $crate::LaneResults<'_> {
                self.state.results()
            }
        }
    };
}
pub(crate) use impl_lockstep;

/// The lockstep engines' forcing means of Sine profiles: for the last few
/// step lengths `δ = t1 - t0` (their bits), per forcing term, slot and lane,
/// `sin(ω δ/2)/(ω δ/2)` (as `TimeProfile::mean` computes it).
pub(crate) struct SincTable<const L: usize> {
    keys: [Option<u64>; SINC_SLOTS],
    /// The slot replaced next.
    next: usize,
    pub(crate) table: Vec<[[f64; L]; SINC_SLOTS]>,
}

impl<const L: usize> SincTable<L> {
    pub(crate) fn new(terms: usize) -> Self {
        Self { keys: [None; SINC_SLOTS], next: 0, table: vec![[[0.0; L]; SINC_SLOTS]; terms] }
    }

    /// The slot holding the factors for `δ`, filled (for every Sine
    /// profile of `profiles`, per forcing term and lane) if `δ` is new.
    #[inline(always)]
    pub(crate) fn slot(&mut self, profiles: &[Vec<TimeProfile>], delta: f64) -> usize {
        let key = delta.to_bits();
        if let Some(s) = self.keys.iter().position(|&d| d == Some(key)) {
            return s;
        }
        let s = self.next;
        self.next = (s + 1) % SINC_SLOTS;
        self.keys[s] = Some(key);
        for (prof, sc) in profiles.iter().zip(self.table.iter_mut()) {
            for (k, p) in prof.iter().enumerate() {
                if let &TimeProfile::Sine { omega, .. } = p {
                    let half = 0.5 * omega * delta;
                    sc[s][k] = if half.abs() < 1e-8 { 1.0 - half * half / 6.0 } else { half.sin() / half };
                }
            }
        }
        s
    }
}

pub(crate) fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

pub(crate) fn avx512_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Bitwise equality of two band matrices (`-0.0 ≠ 0.0`: the products differ in sign).
pub(crate) fn same_band(a: &SymBand, b: &SymBand) -> bool {
    let (n, p) = (a.n(), a.half_bandwidth());
    if (n, p) != (b.n(), b.half_bandwidth()) {
        return false;
    }
    (0..=p).all(|k| a.diagonal(k).iter().zip(b.diagonal(k)).all(|(x, y)| x.to_bits() == y.to_bits()))
}

/// Bitwise equality of two profiles (then their means are the same bits).
pub(crate) fn same_profile(a: &TimeProfile, b: &TimeProfile) -> bool {
    let bits = |x: &[f64], y: &[f64]| x.len() == y.len() && x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits());
    match (a, b) {
        (TimeProfile::Sine { amplitude: a0, omega: w0 }, TimeProfile::Sine { amplitude: a1, omega: w1 }) => bits(&[*a0, *w0], &[*a1, *w1]),
        (TimeProfile::Harmonics(x), TimeProfile::Harmonics(y)) => x.len() == y.len() && x.iter().zip(y.iter()).all(|(p, q)| bits(&[p.amplitude, p.omega, p.phase], &[q.amplitude, q.omega, q.phase])),
        (TimeProfile::Series(x), TimeProfile::Series(y)) => bits(x.times(), y.times()) && bits(x.values(), y.values()),
        _ => false,
    }
}

pub(crate) fn rows7(a: &SymBand) -> Vec<Row7> {
    let n = a.n();
    let d: Vec<Vec<f64>> = (0..=3).map(|k| a.diagonal(k)).collect();
    (0..n)
        .map(|i| {
            let right = |k: usize| if i + k < n { d[k][i + k] } else { 0.0 };
            [d[0][i], d[1][i], d[2][i], d[3][i], right(1), right(2), right(3)]
        })
        .collect()
}

/// The right-hand side of a step, row by row, for [`forward`]: `prepare(j)`
/// makes row `j` of the rings the products read (called for row `i + 3`
/// before row `i` is asked for), `row(i, interior)` gives row `i` of the
/// right-hand side (`interior`: rows `3..n-3`, whose products read seven
/// rows; the others are [`edge`] rows).
pub(crate) trait Rows<const L: usize> {
    fn prepare(&mut self, j: usize);
    fn row(&self, i: usize, interior: bool) -> [f64; L];
}

/// The forward sweep of `BandLdlt::solve_p3` on every lane, each row of the
/// right-hand side made (by `src`) just before it is eliminated; the
/// eliminated rows into `rhs` (length `dofs`).
#[inline(always)]
pub(crate) fn forward<const L: usize, R: Rows<L>>(src: &mut R, l: &[[f64; 3]], rhs: &mut [[f64; L]]) {
    let n = rhs.len();
    let l = &l[..n];
    // Rows 0, 1, 2: fewer predecessors (each needs the rings up to row i + 3).
    for j in 0..4 {
        src.prepare(j);
    }
    let r0 = src.row(0, false);
    src.prepare(4);
    let mut r1 = src.row(1, false);
    for k in 0..L {
        r1[k] -= l[1][0] * r0[k];
    }
    src.prepare(5);
    let mut r2 = src.row(2, false);
    for k in 0..L {
        r2[k] -= l[2][1] * r0[k] + l[2][0] * r1[k];
    }
    (rhs[0], rhs[1], rhs[2]) = (r0, r1, r2);
    let (mut w1, mut w2, mut w3) = (r2, r1, r0);
    // Every further row: the rings' row i + 3, the row, then eliminated at once.
    for ((i, li), out) in (3..n - 3).zip(&l[3..n - 3]).zip(rhs[3..n - 3].iter_mut()) {
        src.prepare(i + 3);
        *out = eliminate::<L>(li, src.row(i, true), &mut w1, &mut w2, &mut w3);
    }
    for i in n - 3..n {
        rhs[i] = eliminate::<L>(&l[i], src.row(i, false), &mut w1, &mut w2, &mut w3);
    }
}

/// Work on each row of the backward sweep's result as soon as it is known
/// (it fills the row-to-row recurrence's latency); `()` does none.
pub(crate) trait Done<const L: usize> {
    fn done(&mut self, i: usize, x: &[f64; L]);
}

impl<const L: usize> Done<L> for () {
    #[inline(always)]
    fn done(&mut self, _: usize, _: &[f64; L]) {}
}

/// The backward sweep of `BandLdlt::solve_p3` on every lane, in place;
/// `done.done(i, x_i)` is called with each row's result as soon as it is
/// known (rows `n-3..n` in that order, then `n-4` down to 0).
#[inline(always)]
pub(crate) fn backward<const L: usize, D: Done<L>>(b: &mut [[f64; L]], lt: &[[f64; 3]], inv_d: &[f64], done: &mut D) {
    let n = b.len();
    let (lt, inv_d) = (&lt[..n], &inv_d[..n]);
    // Rows n-3..n have fewer successors.
    let (c2, c3) = (lt[n - 2], lt[n - 3]);
    for k in 0..L {
        b[n - 1][k] *= inv_d[n - 1];
        b[n - 2][k] = b[n - 2][k] * inv_d[n - 2] - c2[0] * b[n - 1][k];
        b[n - 3][k] = b[n - 3][k] * inv_d[n - 3] - c3[1] * b[n - 1][k] - c3[0] * b[n - 2][k];
    }
    for i in n - 3..n {
        done.done(i, &b[i]);
    }
    let (mut x1, mut x2, mut x3) = (b[n - 3], b[n - 2], b[n - 1]);
    for (i, ((bi, col), di)) in (0..n - 3).rev().zip(b[..n - 3].iter_mut().rev().zip(lt[..n - 3].iter().rev()).zip(inv_d[..n - 3].iter().rev())) {
        let mut s = [0.0; L];
        for k in 0..L {
            s[k] = (bi[k] * di - col[2] * x3[k] - col[1] * x2[k]) - col[0] * x1[k];
        }
        x3 = x2;
        x2 = x1;
        x1 = s;
        *bi = s;
        done.done(i, &s);
    }
}

/// `Projection::project`'s choice for one lane: `y` clamped to `[lo, hi]`
/// and the bound that holds it.
#[inline(always)]
pub(crate) fn clamp(y: f64, lo: f64, hi: f64) -> (f64, Active) {
    if y < lo {
        (lo, Active::Lower)
    } else if y > hi {
        (hi, Active::Upper)
    } else {
        (y, Active::None)
    }
}

/// The rest of `Projection::project` on every lane, given each lane's
/// clamped `x_c` and bound held (`acts`): `mu = (x_c - y_c)/w_c` (0 where
/// free), `y += mu w` and `y_c = x_c` on the lanes held.
#[inline(always)]
pub(crate) fn project_lanes<const L: usize>(y: &mut [[f64; L]], w: &[f64], inv_wc: f64, c: usize, xc: &[f64; L], acts: &[Active; L], mu: &mut [f64; L]) {
    let yc = y[c];
    let mut act = [false; L];
    for k in 0..L {
        act[k] = acts[k] != Active::None;
        mu[k] = if act[k] { (xc[k] - yc[k]) * inv_wc } else { 0.0 };
    }
    if !act.iter().any(|&a| a) {
        return;
    }
    let m = *mu;
    for (y, wi) in y.iter_mut().zip(w) {
        for k in 0..L {
            y[k] = if act[k] { y[k] + m[k] * wi } else { y[k] };
        }
    }
    for k in 0..L {
        if act[k] {
            y[c][k] = xc[k];
        }
    }
}

/// Rows `j` of the two products' arguments `(t_mass, t_stiff)` from an
/// engine's vectors ([`TwoProducts`]).
pub(crate) trait Combine<const L: usize> {
    fn combine(&self, j: usize) -> ([f64; L], [f64; L]);
}

/// [`Rows`] of `M t_mass + s (F - K t_stiff) + Σ_j g_j shape_j` (`s` = `dt²`
/// for Paoli–Schatzman, `dt` for Moreau–Jean), the rings' rows made by
/// `combine` from the engine's vectors.
pub(crate) struct TwoProducts<'a, const L: usize, C: Combine<L>> {
    pub(crate) mass: &'a [Row7],
    pub(crate) stiff: &'a [Row7],
    pub(crate) load: &'a [[f64; L]],
    pub(crate) gs: &'a [[f64; L]],
    pub(crate) shape_rows: &'a [[f64; L]],
    pub(crate) t_mass: &'a mut [[f64; L]; RING],
    pub(crate) t_stiff: &'a mut [[f64; L]; RING],
    pub(crate) scale: f64,
    pub(crate) combine: C,
}

impl<const L: usize, C: Combine<L>> Rows<L> for TwoProducts<'_, L, C> {
    #[inline(always)]
    fn prepare(&mut self, j: usize) {
        (self.t_mass[j % RING], self.t_stiff[j % RING]) = self.combine.combine(j);
    }

    #[inline(always)]
    fn row(&self, i: usize, interior_row: bool) -> [f64; L] {
        let (mv, kv) = two_products::<L>((self.mass, self.t_mass), (self.stiff, self.t_stiff), i, interior_row);
        let terms = self.gs.len();
        rhs_row::<L>(self.scale, mv, kv, &self.load[i], self.gs, chunk(self.shape_rows, i, terms))
    }
}

/// Row `i` of the products `A t_a` and `B t_b` of two band matrices
/// (7-wide rows) with their ring-buffered arguments: an interior row
/// without bound checks, or a row at the band's edges.
#[inline(always)]
pub(crate) fn two_products<const L: usize>((a, ta): (&[Row7], &[[f64; L]; RING]), (b, tb): (&[Row7], &[[f64; L]; RING]), i: usize, interior_row: bool) -> ([f64; L], [f64; L]) {
    if interior_row {
        (interior::<L>(&a[i], ta, i), interior::<L>(&b[i], tb, i))
    } else {
        (edge::<L>(a, ta, i), edge::<L>(b, tb, i))
    }
}

/// Entries `i·w .. (i+1)·w` of `v`: row `i` of a table of width `w`.
#[inline(always)]
pub(crate) fn chunk<T>(v: &[T], i: usize, w: usize) -> &[T] {
    &v[i * w..(i + 1) * w]
}

/// Row `r` of `M t_mass + s (F - K t_stiff) + Σ_j g_j shape_j` from its
/// products `mv`, `kv`, its load `f` and the terms' `g_j`, `shape_j`.
#[inline(always)]
pub(crate) fn rhs_row<const L: usize>(s: f64, mv: [f64; L], kv: [f64; L], f: &[f64; L], gs: &[[f64; L]], shapes: &[[f64; L]]) -> [f64; L] {
    let mut r = [0.0; L];
    for k in 0..L {
        r[k] = mv[k] + s * (f[k] - kv[k]);
    }
    add_shapes(r, gs, shapes)
}

/// `r + Σ_j g_j shape_j`, term by term (`add_terms`' order).
#[inline(always)]
pub(crate) fn add_shapes<const L: usize>(mut r: [f64; L], gs: &[[f64; L]], shapes: &[[f64; L]]) -> [f64; L] {
    for (g, sh) in gs.iter().zip(shapes) {
        for k in 0..L {
            r[k] += g[k] * sh[k];
        }
    }
    r
}

/// The forward elimination of a row `r` with three predecessors (`w1` the
/// last), `BandLdlt::solve_p3`'s order; the window moves on by one.
#[inline(always)]
pub(crate) fn eliminate<const L: usize>(lr: &[f64; 3], mut r: [f64; L], w1: &mut [f64; L], w2: &mut [f64; L], w3: &mut [f64; L]) -> [f64; L] {
    for k in 0..L {
        r[k] = (r[k] - lr[2] * w3[k] - lr[1] * w2[k]) - lr[0] * w1[k];
    }
    *w3 = *w2;
    *w2 = *w1;
    *w1 = r;
    r
}

/// An interior row `i` of a half-bandwidth-3 product (`SymBand::mul_vec_p3`'s
/// order): `(r0 x_i + r1 x_{i-1} + r2 x_{i-2} + r3 x_{i-3}) + (c1 x_{i+1} + c2 x_{i+2} + c3 x_{i+3})`,
/// `x` a ring holding rows `i-3..=i+3` (row `j` in slot `j % RING`).
#[inline(always)]
pub(crate) fn interior<const L: usize>(r: &Row7, x: &[[f64; L]; RING], i: usize) -> [f64; L] {
    let at = |d: usize| &x[(i + d - 3) % RING];
    let (x0, x1, x2, x3, x4, x5, x6) = (at(0), at(1), at(2), at(3), at(4), at(5), at(6));
    let mut y = [0.0; L];
    for k in 0..L {
        y[k] = (r[0] * x3[k] + r[1] * x2[k] + r[2] * x1[k] + r[3] * x0[k]) + (r[4] * x4[k] + r[5] * x5[k] + r[6] * x6[k]);
    }
    y
}

/// A first or last row (`SymBand::mul_vec_p3`'s `row` closure): the
/// diagonal term, then for `k = 1..=3` the left and the right neighbour;
/// `x` a ring holding rows `i-3..=i+3` that exist (row `j` in slot `j % RING`).
#[inline(always)]
pub(crate) fn edge<const L: usize>(a: &[Row7], x: &[[f64; L]; RING], i: usize) -> [f64; L] {
    let (n, r) = (a.len(), &a[i]);
    let mut y = [0.0; L];
    let xi = &x[i % RING];
    for lane in 0..L {
        y[lane] = r[0] * xi[lane];
    }
    for k in 1..=3 {
        if i >= k {
            let (c, xs) = (r[k], &x[(i - k) % RING]);
            for lane in 0..L {
                y[lane] += c * xs[lane];
            }
        }
        if i + k < n {
            let (c, xs) = (r[3 + k], &x[(i + k) % RING]);
            for lane in 0..L {
                y[lane] += c * xs[lane];
            }
        }
    }
    y
}
