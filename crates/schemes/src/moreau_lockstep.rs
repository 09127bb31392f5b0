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

// The lane loops index several per-lane arrays by the lane on purpose:
// that is the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use crate::lockstep::{avx2_available, avx512_available, chunk, edge, eliminate, interior, rhs_row, rows7, same_band, same_profile, Lockstep, Row7, SincTable, RING};
use crate::{Active, LockstepLane, MoreauJean, Sampler, SchemeError, TimeProfile};

/// `L` runs of the Moreau–Jean scheme sharing one step matrix, stepped
/// together (module docs). Allocates only at construction.
pub struct MoreauJeanLockstep<const L: usize> {
    theta: f64,
    gamma: f64,
    dt: f64,
    /// Level `n` of `U^n`, `V^n` (0 after construction).
    n: usize,
    /// Lanes in use (`1..=L`); the rest copy lane 0.
    lanes: usize,
    dofs: usize,
    c: usize,
    mass: Vec<Row7>,
    stiff: Vec<Row7>,
    /// Rows of the factor (as in `PaoliSchatzmanLockstep`).
    l: Vec<[f64; 3]>,
    lt: Vec<[f64; 3]>,
    inv_d: Vec<f64>,
    w: Vec<f64>,
    inv_wc: f64,
    u: Vec<[f64; L]>,
    v: Vec<[f64; L]>,
    /// The right-hand side, then the new velocity `V^{n+1}`.
    rhs: Vec<[f64; L]>,
    /// `V^n` and `U^n + θ(1-θ) dt V^n`, made row by row as the forward
    /// sweep reaches them: row `j` in slot `j % RING`.
    t_mass: [[f64; L]; RING],
    t_stiff: [[f64; L]; RING],
    load: Vec<[f64; L]>,
    /// The forcing terms' shapes, row by row: entry `i·terms + j` is term
    /// `j`'s shape at row `i`, per lane.
    shape_rows: Vec<[f64; L]>,
    /// Per forcing term: the profile of each lane in use.
    profiles: Vec<Vec<TimeProfile>>,
    /// Per forcing term and lane, its means step after step as the single
    /// run takes them (advanced only for profiles other than `Sine`, and only
    /// on lanes that own their means).
    samplers: Vec<Vec<Sampler>>,
    /// Per forcing term and lane: the first lane with the same profile.
    mean_src: Vec<[usize; L]>,
    /// Per forcing term: `dt s` with `s` the mean over `[t_n, t_{n+1}]`.
    dt_s: Vec<[f64; L]>,
    lo: [f64; L],
    hi: [f64; L],
    e: [f64; L],
    mu: [f64; L],
    /// The contacts predicted active at their lower, upper stop this step.
    at_lo: [bool; L],
    at_hi: [bool; L],
    lams: [f64; L],
    acts: [Active; L],
    failed: [Option<SchemeError>; L],
    avx2: bool,
    avx512: bool,
    /// A Sine profile's `sin(ω δ/2)/(ω δ/2)` per step length `δ`.
    sinc: SincTable<L>,
}

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
        if lanes.is_empty() || lanes.len() > L {
            return Err(SchemeError::Size { what: "lockstep lanes (1..=L)", got: lanes.len(), expected: L });
        }
        if !(0.5..=1.0).contains(&theta) {
            return Err(SchemeError::Invalid { field: "theta", value: theta, allowed: "[1/2, 1]" });
        }
        if !(0.0..=1.0).contains(&gamma) {
            return Err(SchemeError::Invalid { field: "gamma", value: gamma, allowed: "[0, 1]" });
        }
        let dy0 = &lanes[0].dynamics;
        for ln in &lanes {
            let dy = &ln.dynamics;
            if !(0.0..=1.0).contains(&ln.restitution) {
                return Err(SchemeError::Invalid { field: "restitution", value: ln.restitution, allowed: "[0, 1]" });
            }
            if dy.damping.is_some() {
                return Err(SchemeError::Structure("lockstep Moreau–Jean takes undamped problems only (damping: use MoreauJean)"));
            }
            if dy.k() != 1 {
                return Err(SchemeError::Structure("lockstep Moreau–Jean takes exactly one contact (several: use MoreauJean)"));
            }
            if dy.massless_contact() {
                return Err(SchemeError::Structure("lockstep Moreau–Jean needs a massive contact node (massless: use MoreauJean)"));
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
        let (dofs, p) = (dy0.n(), dy0.mass.half_bandwidth());
        if p != 3 || dy0.stiffness.half_bandwidth() != 3 || dofs < 7 {
            return Err(SchemeError::Structure("lockstep Moreau–Jean supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)"));
        }
        // MoreauJean::new's factor and projection column.
        let a = dy0.step_matrix(theta * dt, theta * theta * dt * dt).factor()?;
        let c = dy0.contact().dof;
        let mut w = vec![0.0; dofs];
        w[c] = 1.0;
        a.solve_in_place(&mut w);
        let proj = signorini_contact::Projection::new(c, w)?;
        let inv_wc = 1.0 / proj.wc();
        let (lf, ltf, inv_d) = a.band_factors();
        let terms = dy0.forcing.len();
        let zeros = vec![[0.0; L]; dofs];
        let mut s = Self {
            theta,
            gamma,
            dt,
            n: 0,
            lanes: lanes.len(),
            dofs,
            c,
            mass: rows7(&dy0.mass),
            stiff: rows7(&dy0.stiffness),
            l: lf.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect(),
            lt: ltf.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect(),
            inv_d: inv_d.to_vec(),
            w: proj.influence().to_vec(),
            inv_wc,
            u: zeros.clone(),
            v: zeros.clone(),
            rhs: zeros.clone(),
            t_mass: [[0.0; L]; RING],
            t_stiff: [[0.0; L]; RING],
            load: zeros.clone(),
            shape_rows: Vec::new(),
            profiles: vec![Vec::with_capacity(lanes.len()); terms],
            samplers: (0..terms).map(|_| Vec::with_capacity(lanes.len())).collect(),
            mean_src: vec![[0; L]; terms],
            dt_s: vec![[0.0; L]; terms],
            lo: [0.0; L],
            hi: [0.0; L],
            e: [0.0; L],
            mu: [0.0; L],
            at_lo: [false; L],
            at_hi: [false; L],
            lams: [0.0; L],
            acts: [Active::None; L],
            failed: std::array::from_fn(|_| None),
            avx2: avx2_available(),
            avx512: avx512_available(),
            sinc: SincTable::new(terms),
        };
        let used = lanes.len();
        let mut shapes = vec![zeros; terms];
        for (k, ln) in lanes.into_iter().enumerate() {
            let LockstepLane { dynamics: dy, initial, restitution } = ln;
            let ct = *dy.contact();
            for (j, f) in dy.forcing.iter().enumerate() {
                s.profiles[j].push(f.time.clone());
                // The single run's means over [n dt, (n+1) dt], n = 0, 1, …
                s.samplers[j].push(Sampler::means(&f.time, 0.0, dt));
                s.mean_src[j][k] = s.profiles[j].iter().position(|q| same_profile(q, &f.time)).unwrap_or(k);
                for (row, g) in shapes[j].iter_mut().zip(&f.shape) {
                    row[k] = *g;
                }
            }
            for (row, f) in s.load.iter_mut().zip(&dy.load) {
                row[k] = *f;
            }
            (s.lo[k], s.hi[k], s.e[k]) = (ct.bounds.lo, ct.bounds.hi, ct.restitution.unwrap_or(restitution));
            // What the single run refuses, this lane refuses too.
            MoreauJean::new(String::new(), dy, theta, restitution, gamma, dt, &initial)?;
            for ((row, rowv), (x, xv)) in s.u.iter_mut().zip(s.v.iter_mut()).zip(initial.u.iter().zip(&initial.v)) {
                (row[k], rowv[k]) = (*x, *xv);
            }
        }
        // Padding lanes copy lane 0 (and its means, every step).
        for k in used..L {
            for v in [&mut s.u, &mut s.v, &mut s.load].into_iter().chain(shapes.iter_mut()) {
                for row in v.iter_mut() {
                    row[k] = row[0];
                }
            }
            for src in s.mean_src.iter_mut() {
                src[k] = 0;
            }
            (s.lo[k], s.hi[k], s.e[k]) = (s.lo[0], s.hi[0], s.e[0]);
        }
        s.shape_rows = (0..dofs).flat_map(|i| shapes.iter().map(move |sh| sh[i])).collect();
        Ok(s)
    }

    /// θ.
    pub fn theta(&self) -> f64 {
        self.theta
    }

    /// Lane `k`'s `V^n` into `out` (length [`dofs`](Lockstep::dofs)).
    #[track_caller]
    pub fn velocity_into(&self, k: usize, out: &mut [f64]) {
        assert!(k < self.lanes && out.len() == self.dofs, "lane {k} of {}, out of length {} (expected {})", self.lanes, out.len(), self.dofs);
        for (o, row) in out.iter_mut().zip(&self.v) {
            *o = row[k];
        }
    }

    /// Uses the baseline x86-64 (SSE2) code even where the CPU has AVX2
    /// (the same bits; for tests and measurements).
    pub fn portable(mut self) -> Self {
        self.avx2 = false;
        self.avx512 = false;
        self
    }

    /// Uses at most the AVX2 build (the same bits; for tests and measurements).
    pub fn without_avx512(mut self) -> Self {
        self.avx512 = false;
        self
    }

    /// Whether [`step`](Lockstep::step) runs the AVX-512 build.
    pub fn uses_avx512(&self) -> bool {
        self.avx512
    }

    /// Whether [`step`](Lockstep::step) runs the AVX2 build.
    pub fn uses_avx2(&self) -> bool {
        self.avx2
    }

    /// [`step_body`](Self::step_body) compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn step_avx2(&mut self) -> usize {
        self.step_body()
    }

    /// [`step_body`](Self::step_body) compiled with AVX-512F (Rust never
    /// contracts `a * b + c` into an FMA: the same bits).
    ///
    /// # Safety
    /// The CPU must support AVX-512F and AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx2")]
    unsafe fn step_avx512(&mut self) -> usize {
        self.step_body()
    }

    #[inline(always)]
    fn step_body(&mut self) -> usize {
        let (dt, th) = (self.dt, self.theta);
        // The forcing terms' means over [t_n, t_{n+1}] (`Sampler::means`:
        // a = 0 + n dt, b = 0 + (n+1) dt), times dt (`add_terms`' scale).
        let nf = self.n as f64;
        let (t0, t1) = (nf * dt, (nf + 1.0) * dt);
        let slot = self.sinc.slot(&self.profiles, t1 - t0);
        for ((((prof, src), g), sc), sps) in self.profiles.iter().zip(&self.mean_src).zip(self.dt_s.iter_mut()).zip(&self.sinc.table).zip(self.samplers.iter_mut()) {
            let mut next = [0.0; L];
            for k in 0..L {
                next[k] = if src[k] != k {
                    next[src[k]]
                } else if let &TimeProfile::Sine { amplitude, omega } = &prof[k] {
                    amplitude * (omega * 0.5 * (t0 + t1)).sin() * sc[slot][k]
                } else {
                    sps[k].next_value()
                };
            }
            for k in 0..L {
                g[k] = dt * next[k];
            }
        }
        // rhs = M V + dt (F - K (U + θ(1-θ) dt V)) + Σ_j (dt s_j) shape_j,
        // row by row, each row eliminated at once (the forward sweep of
        // `BandLdlt::solve_p3`); V and U + θ(1-θ) dt V are made row by row
        // into a ring just ahead of the products that read them.
        // Which lanes' contacts are predicted active (from U^n, V^n: known
        // before the solve). None: V^{n+1} is the solve's result, and
        // U^{n+1} = U^n + dt ((1-θ) V^n + θ V^{n+1}) is made row by row in
        // the backward sweep (work that fills the recurrence's latency);
        // else after the impact law, in a pass of its own. The same
        // operations either way.
        let any = self.predict();
        let cv = th * (1.0 - th) * dt;
        let n = self.dofs;
        let terms = self.dt_s.len();
        let (l, lt, inv_d) = (&self.l[..n], &self.lt[..n], &self.inv_d[..n]);
        let (mass, stiff, load) = (&self.mass[..n], &self.stiff[..n], &self.load[..n]);
        let (u, v) = (&self.u[..n], &self.v[..n]);
        let (tm, ts) = (&mut self.t_mass, &mut self.t_stiff);
        let (gs, shape_rows) = (&self.dt_s[..terms], &self.shape_rows[..n * terms]);
        let rhs = &mut self.rhs[..n];
        for j in 0..4 {
            combine_row::<L>(tm, ts, &u[j], &v[j], j, cv);
        }
        let r0 = rhs_row::<L>(dt, edge::<L>(mass, tm, 0), edge::<L>(stiff, ts, 0), &load[0], gs, chunk(shape_rows, 0, terms));
        combine_row::<L>(tm, ts, &u[4], &v[4], 4, cv);
        let mut r1 = rhs_row::<L>(dt, edge::<L>(mass, tm, 1), edge::<L>(stiff, ts, 1), &load[1], gs, chunk(shape_rows, 1, terms));
        for k in 0..L {
            r1[k] -= l[1][0] * r0[k];
        }
        combine_row::<L>(tm, ts, &u[5], &v[5], 5, cv);
        let mut r2 = rhs_row::<L>(dt, edge::<L>(mass, tm, 2), edge::<L>(stiff, ts, 2), &load[2], gs, chunk(shape_rows, 2, terms));
        for k in 0..L {
            r2[k] -= l[2][1] * r0[k] + l[2][0] * r1[k];
        }
        (rhs[0], rhs[1], rhs[2]) = (r0, r1, r2);
        let (mut w1, mut w2, mut w3) = (r2, r1, r0);
        for (((i, (rm, rk)), (un, vn)), out) in (3..n - 3).zip(mass[3..n - 3].iter().zip(&stiff[3..n - 3])).zip(u[6..].iter().zip(&v[6..])).zip(rhs[3..n - 3].iter_mut()) {
            combine_row::<L>(tm, ts, un, vn, i + 3, cv);
            *out = eliminate::<L>(&l[i], rhs_row::<L>(dt, interior::<L>(rm, tm, i), interior::<L>(rk, ts, i), &load[i], gs, chunk(shape_rows, i, terms)), &mut w1, &mut w2, &mut w3);
        }
        for i in n - 3..n {
            rhs[i] = eliminate::<L>(&l[i], rhs_row::<L>(dt, edge::<L>(mass, tm, i), edge::<L>(stiff, ts, i), &load[i], gs, chunk(shape_rows, i, terms)), &mut w1, &mut w2, &mut w3);
        }
        // Backward (`BandLdlt::solve_p3`'s order).
        let a = 1.0 - th;
        let b = &mut self.rhs[..n];
        let (uw, vr) = (&mut self.u[..n], &self.v[..n]);
        let (c2, c3) = (lt[n - 2], lt[n - 3]);
        for k in 0..L {
            b[n - 1][k] *= inv_d[n - 1];
            b[n - 2][k] = b[n - 2][k] * inv_d[n - 2] - c2[0] * b[n - 1][k];
            b[n - 3][k] = b[n - 3][k] * inv_d[n - 3] - c3[1] * b[n - 1][k] - c3[0] * b[n - 2][k];
        }
        if !any {
            for i in n - 3..n {
                advance::<L>(&mut uw[i], &vr[i], &b[i], dt, a, th);
            }
        }
        let (mut x1, mut x2, mut x3) = (b[n - 3], b[n - 2], b[n - 1]);
        for (((bi, col), di), (ui, vi)) in b[..n - 3].iter_mut().rev().zip(lt[..n - 3].iter().rev()).zip(inv_d[..n - 3].iter().rev()).zip(uw[..n - 3].iter_mut().rev().zip(vr[..n - 3].iter().rev())) {
            let mut s = [0.0; L];
            for k in 0..L {
                s[k] = (bi[k] * di - col[2] * x3[k] - col[1] * x2[k]) - col[0] * x1[k];
            }
            x3 = x2;
            x2 = x1;
            x1 = s;
            *bi = s;
            if !any {
                advance::<L>(ui, vi, &s, dt, a, th);
            }
        }
        if any {
            self.impact();
            for ((ur, vr), vnr) in self.u.iter_mut().zip(&self.v).zip(&self.rhs) {
                advance::<L>(ur, vr, vnr, dt, a, th);
            }
        } else {
            self.mu = [0.0; L];
            self.acts = [Active::None; L];
        }
        std::mem::swap(&mut self.v, &mut self.rhs);
        self.n += 1;
        let t = self.n as f64 * dt;
        let uc = self.u[self.c];
        for k in 0..L {
            self.lams[k] = -self.mu[k] / dt;
        }
        for k in 0..self.lanes {
            if self.failed[k].is_none() && !(uc[k].is_finite() && self.lams[k].is_finite()) {
                self.failed[k] = Some(SchemeError::NonFinite { step: self.n, time: t });
            }
        }
        self.n
    }

    /// Each lane's contact predicted active at its lower stop
    /// (`u_c + γ dt v_c <= lo`) or upper stop (`>= hi`), as
    /// `MoreauJean::predict` computes it, into `at_lo`, `at_hi`; whether any is.
    #[inline(always)]
    fn predict(&mut self) -> bool {
        let gdt = self.gamma * self.dt;
        let (uc, vc) = (&self.u[self.c], &self.v[self.c]);
        let mut any = false;
        for k in 0..L {
            let pred = uc[k] + gdt * vc[k];
            self.at_lo[k] = pred <= self.lo[k];
            self.at_hi[k] = pred >= self.hi[k];
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
        let c = self.c;
        let (yc, vc) = (self.rhs[c], self.v[c]);
        let mut xc = [0.0; L];
        let mut act = [false; L];
        for k in 0..L {
            let bound = -self.e[k] * vc[k];
            let y = yc[k];
            (xc[k], self.acts[k]) = if self.at_lo[k] {
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
            act[k] = self.acts[k] != Active::None;
            self.mu[k] = if act[k] { (xc[k] - y) * self.inv_wc } else { 0.0 };
        }
        if !act.iter().any(|&a| a) {
            return;
        }
        let mu = self.mu;
        for (y, wi) in self.rhs.iter_mut().zip(&self.w) {
            for k in 0..L {
                y[k] = if act[k] { y[k] + mu[k] * wi } else { y[k] };
            }
        }
        for k in 0..L {
            if act[k] {
                self.rhs[c][k] = xc[k];
            }
        }
    }
}

/// Row `i` of `U^{n+1} = U^n + dt ((1-θ) V^n + θ V^{n+1})` (`a = 1-θ`):
/// `MoreauJean::finish_step`'s update.
#[inline(always)]
fn advance<const L: usize>(u: &mut [f64; L], v: &[f64; L], vn: &[f64; L], dt: f64, a: f64, th: f64) {
    for k in 0..L {
        u[k] += dt * (a * v[k] + th * vn[k]);
    }
}

/// Row `j` of `t_mass = V^n` and `t_stiff = U^n + θ(1-θ) dt V^n`
/// (`cv = θ(1-θ) dt`), into slot `j % RING`.
#[inline(always)]
fn combine_row<const L: usize>(t_mass: &mut [[f64; L]; RING], t_stiff: &mut [[f64; L]; RING], u: &[f64; L], v: &[f64; L], j: usize, cv: f64) {
    let (tm, ts) = (&mut t_mass[j % RING], &mut t_stiff[j % RING]);
    for k in 0..L {
        tm[k] = v[k];
        ts[k] = u[k] + cv * v[k];
    }
}

impl<const L: usize> Lockstep for MoreauJeanLockstep<L> {
    fn lanes(&self) -> usize {
        self.lanes
    }

    fn dofs(&self) -> usize {
        self.dofs
    }

    fn contact_dof(&self) -> usize {
        self.c
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn level(&self) -> usize {
        self.n
    }

    fn time(&self) -> f64 {
        self.n as f64 * self.dt
    }

    /// `t_{n}`: the single run reports the impulse's mean force at the end of its step.
    fn lambda_time(&self) -> f64 {
        self.time()
    }

    /// Advances every lane one step (the build for the widest vector unit
    /// the CPU has; the same bits in every build).
    fn step(&mut self) -> usize {
        #[cfg(target_arch = "x86_64")]
        if self.avx512 {
            // SAFETY: `avx512` is true only if `is_x86_feature_detected!`
            // reported AVX-512F and AVX2 on the running CPU (set in `new`).
            return unsafe { self.step_avx512() };
        }
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is true only if `is_x86_feature_detected!("avx2")`
            // reported AVX2 on the running CPU (set in `new`).
            return unsafe { self.step_avx2() };
        }
        self.step_body()
    }

    #[track_caller]
    fn displacement_into(&self, k: usize, out: &mut [f64]) {
        assert!(k < self.lanes && out.len() == self.dofs, "lane {k} of {}, out of length {} (expected {})", self.lanes, out.len(), self.dofs);
        for (o, row) in out.iter_mut().zip(&self.u) {
            *o = row[k];
        }
    }

    #[track_caller]
    fn value(&self, k: usize, i: usize) -> f64 {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.u[i][k]
    }

    #[track_caller]
    fn contact_force(&self, k: usize) -> f64 {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.lams[k]
    }

    #[track_caller]
    fn contact_status(&self, k: usize) -> Active {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.acts[k]
    }

    #[track_caller]
    fn lane_failure(&self, k: usize) -> Option<&SchemeError> {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.failed[k].as_ref()
    }
}
