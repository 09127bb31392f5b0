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

use crate::{Active, Dynamics, Initial, PaoliSchatzman, Sampler, SchemeError, Stepper, TimeProfile};
use signorini_contact::Projection;
use signorini_fem::SymBand;

/// One run of a lockstep batch: its problem, initial state and restitution
/// (the scheme's `e`, overridden by the contact's own
/// [`Contact::restitution`](crate::Contact::restitution) as in
/// [`PaoliSchatzman`]).
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

/// A band row of half-bandwidth 3: `[A_ii, A_i,i-1, A_i,i-2, A_i,i-3,
/// A_i+1,i, A_i+2,i, A_i+3,i]` (zeros outside the matrix).
pub(crate) type Row7 = [f64; 7];

/// `L` runs of the Paoli–Schatzman scheme sharing one step matrix, stepped
/// together (module docs). Allocates only at construction.
pub struct PaoliSchatzmanLockstep<const L: usize> {
    beta: f64,
    dt: f64,
    /// Level `n` of `U^n` (1 after construction: the start step is taken).
    n: usize,
    /// Lanes in use (`1..=L`); the rest copy lane 0.
    lanes: usize,
    dofs: usize,
    c: usize,
    mass: Vec<Row7>,
    stiff: Vec<Row7>,
    /// Rows of `L` (`l[i] = [L_i,i-1, L_i,i-2, L_i,i-3]`), of `Lᵀ`
    /// (`lt[i] = [L_i+1,i, L_i+2,i, L_i+3,i]`) and `1/D`.
    l: Vec<[f64; 3]>,
    lt: Vec<[f64; 3]>,
    inv_d: Vec<f64>,
    w: Vec<f64>,
    inv_wc: f64,
    u_prev: Vec<[f64; L]>,
    u: Vec<[f64; L]>,
    rhs: Vec<[f64; L]>,
    /// `2U^n - U^{n-1}` and `(1-2β) U^n + β U^{n-1}`, made row by row
    /// as the forward sweep reaches them: row `j` in slot `j % RING`.
    t_mass: [[f64; L]; RING],
    t_stiff: [[f64; L]; RING],
    load: Vec<[f64; L]>,
    /// The forcing terms' shapes, row by row: entry `i·terms + j` is term
    /// `j`'s shape at row `i`, per lane.
    shape_rows: Vec<[f64; L]>,
    /// Per forcing term: the profile of each lane in use.
    profiles: Vec<Vec<TimeProfile>>,
    /// Per forcing term and lane, its means step after step as the single
    /// run takes them ([`Sampler`]; advanced only for profiles other than
    /// `Sine`, whose means come from the sinc table, and only on lanes that
    /// own their means).
    samplers: Vec<Vec<Sampler>>,
    /// Per forcing term and lane: the first lane with the same profile
    /// (its means are computed once and copied).
    mean_src: Vec<[usize; L]>,
    /// Per forcing term: the means over `[t_{n-1}, t_n]` and `[t_n, t_{n+1}]`.
    means: Vec<[[f64; L]; 2]>,
    /// Per forcing term: `dt² g` with `g = β m^{n+1} + (1-2β) m^n + β m^{n-1}`.
    dt2_gc: Vec<[f64; L]>,
    lo: [f64; L],
    hi: [f64; L],
    e: [f64; L],
    mu: [f64; L],
    lams: [f64; L],
    acts: [Active; L],
    failed: [Option<SchemeError>; L],
    /// Run the AVX2 build of the step.
    avx2: bool,
    /// Run the AVX-512 build of the step (implies `avx2`).
    avx512: bool,
    /// A Sine profile's `sin(ω δ/2)/(ω δ/2)` per step length `δ`.
    sinc: SincTable<L>,
}

/// Rows of `2U^n - U^{n-1}` and `(1-2β) U^n + β U^{n-1}` kept at once
/// (a product's row reads seven): a power of two, at least 7.
pub(crate) const RING: usize = 8;

/// Step lengths `δ` remembered by [`PaoliSchatzmanLockstep`] (the rounding
/// of `(n+2) dt - (n+1) dt` gives a handful of values; four catch > 99.99%).
pub(crate) const SINC_SLOTS: usize = 4;

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
        if lanes.is_empty() || lanes.len() > L {
            return Err(SchemeError::Size { what: "lockstep lanes (1..=L)", got: lanes.len(), expected: L });
        }
        let dy0 = &lanes[0].dynamics;
        for ln in &lanes {
            let dy = &ln.dynamics;
            if !(0.0..=1.0).contains(&ln.restitution) {
                return Err(SchemeError::Invalid { field: "restitution", value: ln.restitution, allowed: "[0, 1]" });
            }
            if dy.damping.is_some() {
                return Err(SchemeError::Structure("lockstep Paoli–Schatzman takes undamped problems only (damping: use PaoliSchatzman)"));
            }
            if dy.k() != 1 {
                return Err(SchemeError::Structure("lockstep Paoli–Schatzman takes exactly one contact (several: use PaoliSchatzman)"));
            }
            if dy.massless_contact() {
                return Err(SchemeError::Structure("lockstep Paoli–Schatzman needs a massive contact node (massless: use PaoliSchatzman)"));
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
            return Err(SchemeError::Structure("lockstep Paoli–Schatzman supports half-bandwidth 3 with at least 7 unknowns (the Hermite beam)"));
        }
        let a = dy0.step_matrix(0.5 * dt, beta * dt * dt).factor()?;
        let c = dy0.contact().dof;
        let mut w = vec![0.0; dofs];
        w[c] = 1.0;
        a.solve_in_place(&mut w);
        // Validates w_c as the single run does; 1/w_c as Projection computes it.
        let proj = Projection::new(c, w)?;
        let inv_wc = 1.0 / proj.wc();
        let (lf, ltf, inv_d) = a.band_factors();
        let l = lf.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect();
        let lt = ltf.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect();
        let terms = dy0.forcing.len();
        let zeros = vec![[0.0; L]; dofs];
        let mut s = Self {
            beta,
            dt,
            n: 1,
            lanes: lanes.len(),
            dofs,
            c,
            mass: rows7(&dy0.mass),
            stiff: rows7(&dy0.stiffness),
            l,
            lt,
            inv_d: inv_d.to_vec(),
            w: proj.influence().to_vec(),
            inv_wc,
            u_prev: zeros.clone(),
            u: zeros.clone(),
            rhs: zeros.clone(),
            t_mass: [[0.0; L]; RING],
            t_stiff: [[0.0; L]; RING],
            load: zeros.clone(),
            shape_rows: Vec::new(),
            profiles: vec![Vec::with_capacity(lanes.len()); terms],
            samplers: (0..terms).map(|_| Vec::with_capacity(lanes.len())).collect(),
            mean_src: vec![[0; L]; terms],
            means: vec![[[0.0; L]; 2]; terms],
            dt2_gc: vec![[0.0; L]; terms],
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
        };
        let used = lanes.len();
        let mut shapes = vec![zeros; terms];
        for (k, ln) in lanes.into_iter().enumerate() {
            let LockstepLane { dynamics: dy, initial, restitution } = ln;
            let ct = *dy.contact();
            let e = ct.restitution.unwrap_or(restitution);
            for (j, f) in dy.forcing.iter().enumerate() {
                s.profiles[j].push(f.time.clone());
                // The single run's first two means, [0, dt] and [dt, 2 dt].
                let mut sp = Sampler::means(&f.time, 0.0, dt);
                s.means[j][0][k] = sp.next_value();
                s.means[j][1][k] = sp.next_value();
                s.samplers[j].push(sp);
                s.mean_src[j][k] = s.profiles[j].iter().position(|q| same_profile(q, &f.time)).unwrap_or(k);
                for (row, g) in shapes[j].iter_mut().zip(&f.shape) {
                    row[k] = *g;
                }
            }
            for (row, f) in s.load.iter_mut().zip(&dy.load) {
                row[k] = *f;
            }
            (s.lo[k], s.hi[k], s.e[k]) = (ct.bounds.lo, ct.bounds.hi, e);
            let single = PaoliSchatzman::new(String::new(), dy, beta, e, dt, &initial)?;
            for ((row, rowp), (x, xp)) in s.u.iter_mut().zip(s.u_prev.iter_mut()).zip(single.displacement().iter().zip(single.previous_displacement())) {
                (row[k], rowp[k]) = (*x, *xp);
            }
        }
        // Padding lanes copy lane 0 (and its means, every step).
        for k in used..L {
            for v in [&mut s.u, &mut s.u_prev, &mut s.load].into_iter().chain(shapes.iter_mut()) {
                for row in v.iter_mut() {
                    row[k] = row[0];
                }
            }
            for (m, src) in s.means.iter_mut().zip(s.mean_src.iter_mut()) {
                (m[0][k], m[1][k], src[k]) = (m[0][0], m[1][0], 0);
            }
            (s.lo[k], s.hi[k], s.e[k]) = (s.lo[0], s.hi[0], s.e[0]);
        }
        s.shape_rows = (0..dofs).flat_map(|i| shapes.iter().map(move |sh| sh[i])).collect();
        Ok(s)
    }

    /// Lanes in use.
    pub fn lanes(&self) -> usize {
        self.lanes
    }

    /// Number of unknowns per lane.
    pub fn dofs(&self) -> usize {
        self.dofs
    }

    /// The contact dof (shared).
    pub fn contact_dof(&self) -> usize {
        self.c
    }

    /// Time step.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// β.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Index `n` of the current level `U^n` (every lane's).
    pub fn level(&self) -> usize {
        self.n
    }

    /// `t_n = n dt`.
    pub fn time(&self) -> f64 {
        self.n as f64 * self.dt
    }

    /// The time the contact forces belong to: `t_{n-1}` (massive contact node).
    pub fn lambda_time(&self) -> f64 {
        (self.n - 1) as f64 * self.dt
    }

    /// Lane `k`'s `U^n` into `out` (length [`dofs`](Self::dofs)).
    #[track_caller]
    pub fn displacement_into(&self, k: usize, out: &mut [f64]) {
        assert!(k < self.lanes && out.len() == self.dofs, "lane {k} of {}, out of length {} (expected {})", self.lanes, out.len(), self.dofs);
        for (o, row) in out.iter_mut().zip(&self.u) {
            *o = row[k];
        }
    }

    /// Lane `k`'s `U^{n-1}` into `out`.
    #[track_caller]
    pub fn previous_displacement_into(&self, k: usize, out: &mut [f64]) {
        assert!(k < self.lanes && out.len() == self.dofs, "lane {k} of {}, out of length {} (expected {})", self.lanes, out.len(), self.dofs);
        for (o, row) in out.iter_mut().zip(&self.u_prev) {
            *o = row[k];
        }
    }

    /// Lane `k`'s `u_i^n` (for example the tip, `i` = [`contact_dof`](Self::contact_dof)).
    #[track_caller]
    pub fn value(&self, k: usize, i: usize) -> f64 {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.u[i][k]
    }

    /// Lane `k`'s contact force `λ^{n-1}` of the last step (at
    /// [`lambda_time`](Self::lambda_time); 0 before the first step).
    #[track_caller]
    pub fn contact_force(&self, k: usize) -> f64 {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.lams[k]
    }

    /// Which bound held lane `k`'s contact in the last step.
    #[track_caller]
    pub fn contact_status(&self, k: usize) -> Active {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.acts[k]
    }

    /// The error the single run of lane `k` would have returned
    /// ([`SchemeError::NonFinite`] at the step its state turned non-finite),
    /// if it has; that lane's later values are meaningless, the other lanes
    /// are unaffected.
    #[track_caller]
    pub fn lane_failure(&self, k: usize) -> Option<&SchemeError> {
        assert!(k < self.lanes, "lane {k} of {}", self.lanes);
        self.failed[k].as_ref()
    }

    /// Number of lanes in use that have failed so far.
    pub fn failed_lanes(&self) -> usize {
        self.failed[..self.lanes].iter().filter(|f| f.is_some()).count()
    }

    /// Uses the baseline x86-64 (SSE2) code even where the CPU has AVX2
    /// (the results are the same bits; for tests and measurements).
    pub fn portable(mut self) -> Self {
        self.avx2 = false;
        self.avx512 = false;
        self
    }

    /// Uses at most the AVX2 build, even where the CPU has AVX-512 (the
    /// results are the same bits; for tests and measurements).
    pub fn without_avx512(mut self) -> Self {
        self.avx512 = false;
        self
    }

    /// Whether [`step`](Self::step) runs the AVX-512 build of the step
    /// (chosen at construction from the running CPU; never FMA).
    pub fn uses_avx512(&self) -> bool {
        self.avx512
    }

    /// Whether [`step`](Self::step) runs the AVX2 build of the step (chosen
    /// at construction from the running CPU; never FMA, so the same bits).
    pub fn uses_avx2(&self) -> bool {
        self.avx2
    }

    /// Advances every lane one step (module docs); returns the new level.
    /// A lane that turns non-finite is recorded ([`lane_failure`](Self::lane_failure)).
    ///
    /// The same code is compiled three times, for the baseline x86-64 target,
    /// with AVX2 (4 lanes per instruction instead of 2) and with AVX-512F
    /// (8), and the widest the CPU has runs. Rust never contracts
    /// `a * b + c` into an FMA, so every build rounds every operation alike.
    pub fn step(&mut self) -> usize {
        #[cfg(target_arch = "x86_64")]
        if self.avx512 {
            // SAFETY: `avx512` is true only if `is_x86_feature_detected!`
            // reported AVX-512F and AVX2 on the running CPU (set in `new`).
            return unsafe { self.step_avx512() };
        }
        if self.avx2 {
            // SAFETY: `avx2` is true only if `is_x86_feature_detected!("avx2")`
            // reported AVX2 on the running CPU (set in `new`).
            return unsafe { self.step_avx2() };
        }
        self.step_body()
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

    /// [`step_body`](Self::step_body) compiled with AVX-512F (8 lanes per
    /// instruction). `avx512f` brings `fma` along as a target feature, but
    /// Rust never contracts `a * b + c` into an FMA: the same bits.
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
        let dt2 = self.dt * self.dt;
        let beta = self.beta;
        let a = 1.0 - 2.0 * beta;
        // Forcing coefficients of every term and lane:
        // g = β m_{n+1} + (1-2β) m_n + β m_{n-1}, then dt² g.
        let (dt, nf) = (self.dt, self.n as f64);
        let (t0, t1) = ((nf + 1.0) * dt, (nf + 2.0) * dt);
        // Sine profiles: `TimeProfile::mean`'s formula, its factor
        // sin(ω δ/2)/(ω δ/2) looked up by δ = t1 - t0 (which takes a few
        // values only, by rounding): one `sin` per lane and step instead of two.
        let slot = self.sinc.slot(&self.profiles, t1 - t0);
        for (((((prof, src), m), g), sc), sps) in self.profiles.iter().zip(&self.mean_src).zip(self.means.iter_mut()).zip(self.dt2_gc.iter_mut()).zip(&self.sinc.table).zip(self.samplers.iter_mut()) {
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
                let gc = beta * next[k] + a * m[1][k] + beta * m[0][k];
                g[k] = dt2 * gc;
            }
            *m = [m[1], next];
        }
        // rhs = M t_mass + dt² (F - K t_stiff) + Σ_j dt² g_j shape_j, row by
        // row, each row then eliminated at once (the forward sweep of
        // `BandLdlt::solve_p3`, its last three results kept in w1, w2, w3);
        // t_mass = 2U^n - U^{n-1} and t_stiff = (1-2β) U^n + β U^{n-1} are
        // made row by row just ahead of the products that read them (a ring
        // of RING rows: U^n and U^{n-1} are read once, and t stays in L1).
        let n = self.dofs;
        let terms = self.dt2_gc.len();
        let (l, lt, inv_d) = (&self.l[..n], &self.lt[..n], &self.inv_d[..n]);
        let (mass, stiff, load) = (&self.mass[..n], &self.stiff[..n], &self.load[..n]);
        let (u, up) = (&self.u[..n], &self.u_prev[..n]);
        let (tm, ts) = (&mut self.t_mass, &mut self.t_stiff);
        let (gs, shape_rows) = (&self.dt2_gc[..terms], &self.shape_rows[..n * terms]);
        let rhs = &mut self.rhs[..n];
        // Row i of M t_mass + dt² (F - K t_stiff) + Σ_j dt² g_j shape_j,
        // from its two products.
        // Rows 0, 1, 2: fewer predecessors (each needs t up to row i + 3).
        for j in 0..4 {
            combine_row::<L>(tm, ts, &u[j], &up[j], j, a, beta);
        }
        let r0 = rhs_row::<L>(dt2, edge::<L>(mass, tm, 0), edge::<L>(stiff, ts, 0), &load[0], gs, chunk(shape_rows, 0, terms));
        combine_row::<L>(tm, ts, &u[4], &up[4], 4, a, beta);
        let mut r1 = rhs_row::<L>(dt2, edge::<L>(mass, tm, 1), edge::<L>(stiff, ts, 1), &load[1], gs, chunk(shape_rows, 1, terms));
        for k in 0..L {
            r1[k] -= l[1][0] * r0[k];
        }
        combine_row::<L>(tm, ts, &u[5], &up[5], 5, a, beta);
        let mut r2 = rhs_row::<L>(dt2, edge::<L>(mass, tm, 2), edge::<L>(stiff, ts, 2), &load[2], gs, chunk(shape_rows, 2, terms));
        for k in 0..L {
            r2[k] -= l[2][1] * r0[k] + l[2][0] * r1[k];
        }
        (rhs[0], rhs[1], rhs[2]) = (r0, r1, r2);
        let (mut w1, mut w2, mut w3) = (r2, r1, r0);
        // Every further row: t's row i + 3, the products, then eliminated at once.
        for (((i, (rm, rk)), (un, upn)), out) in (3..n - 3).zip(mass[3..n - 3].iter().zip(&stiff[3..n - 3])).zip(u[6..].iter().zip(&up[6..])).zip(rhs[3..n - 3].iter_mut()) {
            combine_row::<L>(tm, ts, un, upn, i + 3, a, beta);
            *out = eliminate::<L>(&l[i], rhs_row::<L>(dt2, interior::<L>(rm, tm, i), interior::<L>(rk, ts, i), &load[i], gs, chunk(shape_rows, i, terms)), &mut w1, &mut w2, &mut w3);
        }
        for i in n - 3..n {
            rhs[i] = eliminate::<L>(&l[i], rhs_row::<L>(dt2, edge::<L>(mass, tm, i), edge::<L>(stiff, ts, i), &load[i], gs, chunk(shape_rows, i, terms)), &mut w1, &mut w2, &mut w3);
        }
        // Backward: rows n-3..n have fewer successors.
        let b = &mut self.rhs[..n];
        let (c2, c3) = (lt[n - 2], lt[n - 3]);
        for k in 0..L {
            b[n - 1][k] *= inv_d[n - 1];
            b[n - 2][k] = b[n - 2][k] * inv_d[n - 2] - c2[0] * b[n - 1][k];
            b[n - 3][k] = b[n - 3][k] * inv_d[n - 3] - c3[1] * b[n - 1][k] - c3[0] * b[n - 2][k];
        }
        let (mut x1, mut x2, mut x3) = (b[n - 3], b[n - 2], b[n - 1]);
        for ((bi, col), di) in b[..n - 3].iter_mut().rev().zip(lt[..n - 3].iter().rev()).zip(inv_d[..n - 3].iter().rev()) {
            let mut s = [0.0; L];
            for k in 0..L {
                s[k] = (bi[k] * di - col[2] * x3[k] - col[1] * x2[k]) - col[0] * x1[k];
            }
            x3 = x2;
            x2 = x1;
            x1 = s;
            *bi = s;
        }
        self.project();
        // Rotate: U^{n-1} <- U^n <- U^{n+1}.
        std::mem::swap(&mut self.u_prev, &mut self.u);
        std::mem::swap(&mut self.u, &mut self.rhs);
        self.n += 1;
        let t = self.time();
        let uc = self.u[self.c];
        for k in 0..L {
            self.lams[k] = -self.mu[k] / dt2;
        }
        for k in 0..self.lanes {
            if self.failed[k].is_none() && !(uc[k].is_finite() && self.lams[k].is_finite()) {
                self.failed[k] = Some(SchemeError::NonFinite { step: self.n, time: t });
            }
        }
        self.n
    }

    /// The projection of every lane (`Projection::project`'s operations),
    /// bounds moved by each lane's restitution; `mu` per lane (0 inside).
    #[inline(always)]
    fn project(&mut self) {
        let c = self.c;
        let (yc, up_c) = (self.rhs[c], self.u_prev[c]);
        let mut xc = [0.0; L];
        let mut act = [false; L];
        for k in 0..L {
            let e = self.e[k];
            let lo = (1.0 + e) * self.lo[k] - e * up_c[k];
            let hi = if self.hi[k].is_finite() { (1.0 + e) * self.hi[k] - e * up_c[k] } else { f64::INFINITY };
            let y = yc[k];
            (xc[k], self.acts[k]) = if y < lo {
                (lo, Active::Lower)
            } else if y > hi {
                (hi, Active::Upper)
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

/// What a time loop needs of a lockstep engine ([`PaoliSchatzmanLockstep`],
/// [`MoreauJeanLockstep`](crate::MoreauJeanLockstep)): `L` runs sharing one
/// step matrix, stepped together, each lane bit for bit its single run.
/// Every lane-indexed method asserts `k < lanes()`.
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
}

impl<const L: usize> Lockstep for PaoliSchatzmanLockstep<L> {
    fn lanes(&self) -> usize {
        PaoliSchatzmanLockstep::lanes(self)
    }
    fn dofs(&self) -> usize {
        PaoliSchatzmanLockstep::dofs(self)
    }
    fn contact_dof(&self) -> usize {
        PaoliSchatzmanLockstep::contact_dof(self)
    }
    fn dt(&self) -> f64 {
        PaoliSchatzmanLockstep::dt(self)
    }
    fn level(&self) -> usize {
        PaoliSchatzmanLockstep::level(self)
    }
    fn time(&self) -> f64 {
        PaoliSchatzmanLockstep::time(self)
    }
    fn lambda_time(&self) -> f64 {
        PaoliSchatzmanLockstep::lambda_time(self)
    }
    fn step(&mut self) -> usize {
        PaoliSchatzmanLockstep::step(self)
    }
    fn displacement_into(&self, k: usize, out: &mut [f64]) {
        PaoliSchatzmanLockstep::displacement_into(self, k, out)
    }
    fn value(&self, k: usize, i: usize) -> f64 {
        PaoliSchatzmanLockstep::value(self, k, i)
    }
    fn contact_force(&self, k: usize) -> f64 {
        PaoliSchatzmanLockstep::contact_force(self, k)
    }
    fn contact_status(&self, k: usize) -> Active {
        PaoliSchatzmanLockstep::contact_status(self, k)
    }
    fn lane_failure(&self, k: usize) -> Option<&SchemeError> {
        PaoliSchatzmanLockstep::lane_failure(self, k)
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
            _ => None,
        }
    }

    /// The restitution of the scheme (a lane's [`LockstepLane::restitution`]).
    pub fn restitution(&self) -> f64 {
        match *self {
            Self::PaoliSchatzman { restitution, .. } | Self::MoreauJean { restitution, .. } => restitution,
        }
    }
}

/// Row `j` of `t_mass = 2U^n - U^{n-1}` and `t_stiff = (1-2β) U^n + β U^{n-1}`
/// (`a = 1-2β`) from `u = U^n_j`, `up = U^{n-1}_j`, into slot `j % RING`.
#[inline(always)]
fn combine_row<const L: usize>(t_mass: &mut [[f64; L]; RING], t_stiff: &mut [[f64; L]; RING], u: &[f64; L], up: &[f64; L], j: usize, a: f64, beta: f64) {
    let (tm, ts) = (&mut t_mass[j % RING], &mut t_stiff[j % RING]);
    for k in 0..L {
        tm[k] = 2.0 * u[k] - up[k];
        ts[k] = a * u[k] + beta * up[k];
    }
}

/// Entries `i·w .. (i+1)·w` of `v`: row `i` of a table of width `w`.
#[inline(always)]
pub(crate) fn chunk<T>(v: &[T], i: usize, w: usize) -> &[T] {
    &v[i * w..(i + 1) * w]
}

/// Row `r` of `M t_mass + dt² (F - K t_stiff) + Σ_j dt² g_j shape_j` from
/// its products `mv`, `kv`, its load `f` and the terms' `dt² g_j`, `shape_j`.
#[inline(always)]
pub(crate) fn rhs_row<const L: usize>(dt2: f64, mv: [f64; L], kv: [f64; L], f: &[f64; L], gs: &[[f64; L]], shapes: &[[f64; L]]) -> [f64; L] {
    let mut r = [0.0; L];
    for k in 0..L {
        r[k] = mv[k] + dt2 * (f[k] - kv[k]);
    }
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
