//! An independent reference computation of the `bar-dirichlet` benchmark
//! (`L = 1`, `c = 1`, `f = 0`, `u0 = (1 - x)/2`, `v0 = 0`, clamped at
//! `x = 1`, Signorini contact with the obstacle `g = 0` at `x = 0`), for
//! tests that compare the library's error norms and contact forces with
//! values it did not compute itself.
//!
//! Nothing here calls the library: pure `std`, written from the problem
//! statement and the 2017 mass-redistribution paper, deliberately by other
//! routes than the library takes wherever one exists:
//!
//! * **exact solution** by d'Alembert: `u = φ(x - t) + ψ(x + t)`. The
//!   initial data give `φ' = ψ' = u0'/2 = -1/4` on `[0, 1]`; the clamped end
//!   reflects with a sign change (`ψ'(1 + t) = φ'(1 - t)`); the contact end
//!   reflects the incoming slope `w = ψ'(t)` as `φ'(-t) = -w` while the end
//!   is free (`u_x(0, t) = 0`) and as `φ'(-t) = w` while it touches
//!   (`u(0, t) = 0`, force `λ = u_x(0, t) = 2w <= 0`). Following the waves
//!   round once gives `φ' = ψ' = s` with the 3-periodic slope `s(z) = +1/4`
//!   for `z mod 3 ∈ (2, 3)` and `-1/4` otherwise, so `u_x = s(x-t) + s(x+t)`,
//!   `u = S(x-t) + S(x+t) - S(1-t) - S(1+t)` with `S' = s`, `S(0) = 0`
//!   (so `u(1, t) = 0`), and `λ(t) = s(-t) + s(t)`;
//! * **matrices** dense, assembled from the P1 element matrices, the `mod`
//!   mass by leaving the element `[0, h]` out;
//! * **Newmark** in displacement–velocity–acceleration form (the library
//!   uses the momentum form), **Paoli–Schatzman** with the massless row
//!   written as the equilibrium `(K U^{n+1})_0 = -λ` (the library scales it
//!   by `β dt²`);
//! * **contact** by solving the step twice — free, then with `u_0` fixed on
//!   its bound and the force read from row 0 — with a dense LU (the library
//!   uses the closed-form projection on a banded LDLᵀ factor);
//! * **space norms** by bisection of each element until the error is affine
//!   on every piece, then Gauss–Lobatto: this finds the kinks of the exact
//!   solution without being told where they are (the library splits
//!   elements at the kinks the exact solution reports).
//!
//! Sample sets are those the README documents: displacement at every level
//! `t_0 … t_N`; λ at `t_{n+1}` for Newmark, at `t_n` for Paoli–Schatzman
//! (at `t_{n+1}` with a massless node), none for Paoli–Schatzman's start
//! step; energy at every level for Newmark, at the half levels
//! `t_{1/2} … t_{N-1/2}` for Paoli–Schatzman; `L²` in time is
//! `sqrt(dt Σ e²)` over the samples.

#![allow(dead_code)] // each test target uses a part of it

/// `dx/dt` of the papers' study.
pub const RATIO: usize = 10;
/// The horizon: one period of the exact solution.
pub const T_END: usize = 3;

/// The mass treatment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mass {
    /// Consistent mass.
    Std,
    /// The element `[0, h]` carries no mass (massless contact node).
    Mod,
}

impl Mass {
    /// The library's name.
    pub fn name(self) -> &'static str {
        match self {
            Mass::Std => "std",
            Mass::Mod => "mod",
        }
    }
}

/// The time scheme.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scheme {
    /// Newmark with `β = 1/4`, `γ = 1/2`.
    NewmarkCn,
    /// Newmark with `β = 1/2`, `γ = 1` (first order, dissipative).
    NewmarkI,
    /// Paoli–Schatzman, `β = 1/4`, restitution `e`.
    PaoliSchatzman {
        /// Restitution coefficient.
        e: f64,
    },
}

impl Scheme {
    /// The library's preset name.
    pub fn name(self) -> String {
        match self {
            Scheme::NewmarkCn => "newmark-cn".into(),
            Scheme::NewmarkI => "newmark-i".into(),
            Scheme::PaoliSchatzman { e } => format!("ps-e{e}"),
        }
    }
}

/// Every (scheme, mass) pair the reference covers.
pub const CONFIGS: [(Scheme, Mass); 8] = [
    (Scheme::NewmarkCn, Mass::Std),
    (Scheme::NewmarkCn, Mass::Mod),
    (Scheme::NewmarkI, Mass::Std),
    (Scheme::NewmarkI, Mass::Mod),
    (Scheme::PaoliSchatzman { e: 0.0 }, Mass::Std),
    (Scheme::PaoliSchatzman { e: 0.0 }, Mass::Mod),
    (Scheme::PaoliSchatzman { e: 0.5 }, Mass::Std),
    (Scheme::PaoliSchatzman { e: 0.5 }, Mass::Mod),
];

/// Whether two correct implementations of the pair can be compared only
/// over the first impact: Newmark with `std` mass chatters (the contact node
/// bounces every few steps after the impact), and each bounce multiplies a
/// rounding-level difference by 3 to 10. Measured against the library:
/// `newmark-cn/std` at m = 20, 4e-13 in `U` at the first impact (t = 1),
/// 5e-12 at t = 1.05, 4e-10 at t = 1.15, 5e-2 by t = 3; `newmark-i/std`
/// (dissipative, so the growth stops when the chatter does) 2e-10 in `U` at
/// m = 20, 7e-9 at m = 80, 1e-7 at m = 160, its norms 3e-6 apart at m = 80.
/// Their norms over a period are not reproducible to rounding, so they are
/// neither stored nor compared.
pub fn chaotic(scheme: Scheme, mass: Mass) -> bool {
    mass == Mass::Std && matches!(scheme, Scheme::NewmarkCn | Scheme::NewmarkI)
}

/// The number of steps of `traj` over which its pair is reproducible to
/// rounding: all of them, or for a [`chaotic`] pair its free flight, its
/// first impact and the step after it (then the node bounces every few
/// steps; with the obstacle at `g = 0.1`, m = 20, the rounding difference
/// in λ reaches 2e-8 seven steps after the first impact).
pub fn comparable_steps(scheme: Scheme, mass: Mass, traj: &Trajectory) -> usize {
    if !chaotic(scheme, mass) {
        return traj.steps;
    }
    let first = traj.lambdas.iter().find(|l| l.1 < 0.0).map_or(traj.steps, |l| l.0);
    traj.steps.min(first + 1)
}

// ---------------------------------------------------------------------------
// Exact solution (d'Alembert)

/// Slope `s(z)` of both travelling waves.
pub fn wave_slope(z: f64) -> f64 {
    if z.rem_euclid(3.0) > 2.0 {
        0.25
    } else {
        -0.25
    }
}

/// `S(z) = ∫_0^z s`: `-1/4` per period, `-r/4` on `[0, 2]`, back up on `[2, 3]`.
pub fn wave(z: f64) -> f64 {
    let q = (z / 3.0).floor();
    let r = z - 3.0 * q;
    let inside = if r <= 2.0 { -r / 4.0 } else { -0.5 + (r - 2.0) / 4.0 };
    -q / 4.0 + inside
}

/// `u(x, t)`.
pub fn exact_u(x: f64, t: f64) -> f64 {
    wave(x - t) + wave(x + t) - wave(1.0 - t) - wave(1.0 + t)
}

/// `u_x(x, t)` (one-sided at the kinks).
pub fn exact_ux(x: f64, t: f64) -> f64 {
    wave_slope(x - t) + wave_slope(x + t)
}

/// `u_t(x, t)` (one-sided at the kinks).
pub fn exact_ut(x: f64, t: f64) -> f64 {
    -wave_slope(x - t) + wave_slope(x + t)
}

/// `λ(t) = s(-t) + s(t)`: `-1/2` while the end touches, `0` otherwise.
pub fn exact_lambda(t: f64) -> f64 {
    wave_slope(-t) + wave_slope(t)
}

/// The exact energy `1/2 ∫ (u_t² + u_x²) = ∫ (s(x-t)² + s(x+t)²) = 1/8`.
pub const EXACT_ENERGY: f64 = 0.125;

/// `λ` at time level `k` of a mesh with `m` elements (`t_k = k/(RATIO m)`),
/// from integer arithmetic so that rounding of `k dt` cannot move a sample
/// across a jump: the end touches on `[1, 2)` mod 3 — it reaches the
/// obstacle at `t = 1` (`u(0, 1) = 0`) and leaves it at `t = 2` (the
/// convention at the two jump instants; between them `λ(t)` above decides).
pub fn exact_lambda_at_level(k: usize, m: usize) -> f64 {
    let unit = RATIO * m; // levels per unit time
    let r = k % (3 * unit);
    if (unit..2 * unit).contains(&r) {
        -0.5
    } else {
        0.0
    }
}

// ---------------------------------------------------------------------------
// Dense linear algebra

/// A dense row-major square matrix.
#[derive(Clone, Debug)]
pub struct Dense {
    n: usize,
    a: Vec<f64>,
}

impl Dense {
    /// The zero matrix.
    pub fn zeros(n: usize) -> Self {
        Self { n, a: vec![0.0; n * n] }
    }
    /// Entry `(i, j)`.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.a[i * self.n + j]
    }
    /// Adds `v` to entry `(i, j)`.
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        self.a[i * self.n + j] += v;
    }
    /// Sets entry `(i, j)`.
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        self.a[i * self.n + j] = v;
    }
    /// `a A + b B`.
    pub fn comb(a: f64, x: &Dense, b: f64, y: &Dense) -> Dense {
        Dense { n: x.n, a: x.a.iter().zip(&y.a).map(|(p, q)| a * p + b * q).collect() }
    }
    /// `A x`.
    pub fn mul(&self, x: &[f64]) -> Vec<f64> {
        (0..self.n).map(|i| row_dot(&self.a[i * self.n..(i + 1) * self.n], x)).collect()
    }
    /// `xᵀ A x`.
    pub fn quad(&self, x: &[f64]) -> f64 {
        row_dot(&self.mul(x), x)
    }
    /// The block `rows, cols >= s`.
    pub fn trailing(&self, s: usize) -> Dense {
        let k = self.n - s;
        let mut t = Dense::zeros(k);
        for i in 0..k {
            for j in 0..k {
                t.set(i, j, self.get(i + s, j + s));
            }
        }
        t
    }
}

fn row_dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p * q).sum()
}

/// LU factorisation with partial pivoting.
pub struct Lu {
    n: usize,
    lu: Vec<f64>,
    perm: Vec<usize>,
}

impl Lu {
    /// Factorises `a` (panics if it is singular).
    pub fn new(a: &Dense) -> Self {
        let n = a.n;
        let mut lu = a.a.clone();
        let mut perm: Vec<usize> = (0..n).collect();
        for k in 0..n {
            let p = (k..n).max_by(|&i, &j| lu[i * n + k].abs().total_cmp(&lu[j * n + k].abs())).unwrap();
            assert!(lu[p * n + k] != 0.0, "singular matrix");
            if p != k {
                for j in 0..n {
                    lu.swap(k * n + j, p * n + j);
                }
                perm.swap(k, p);
            }
            for i in k + 1..n {
                let f = lu[i * n + k] / lu[k * n + k];
                lu[i * n + k] = f;
                for j in k + 1..n {
                    lu[i * n + j] -= f * lu[k * n + j];
                }
            }
        }
        Self { n, lu, perm }
    }

    /// `A⁻¹ b`.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut x: Vec<f64> = self.perm.iter().map(|&p| b[p]).collect();
        for i in 0..n {
            let s = row_dot(&self.lu[i * n..i * n + i], &x[..i]);
            x[i] -= s;
        }
        for i in (0..n).rev() {
            let s = row_dot(&self.lu[i * n + i + 1..(i + 1) * n], &x[i + 1..]);
            x[i] = (x[i] - s) / self.lu[i * n + i];
        }
        x
    }
}

/// `S U = r - λ e_0` with `u_0 >= lo`, `λ <= 0`, `(u_0 - lo) λ = 0`, for a
/// fixed matrix `S` whose row 0 carries the force: the free solve, and if it
/// violates the bound, the solve with `u_0 = lo` (the force then read from
/// row 0).
struct ContactSolver {
    s: Dense,
    full: Lu,
    /// The rows and columns `>= 1` (unknowns when `u_0` is fixed).
    reduced: Lu,
}

impl ContactSolver {
    fn new(s: Dense) -> Self {
        Self { full: Lu::new(&s), reduced: Lu::new(&s.trailing(1)), s }
    }

    /// Returns `(U, λ)`.
    fn solve(&self, r: &[f64], lo: f64) -> (Vec<f64>, f64) {
        let free = self.full.solve(r);
        if free[0] >= lo {
            return (free, 0.0);
        }
        let n = r.len();
        let rhs: Vec<f64> = (1..n).map(|i| r[i] - self.s.get(i, 0) * lo).collect();
        let mut u = vec![lo];
        u.extend(self.reduced.solve(&rhs));
        let lambda = r[0] - row_dot(&self.s.a[..n], &u);
        (u, lambda)
    }
}

// ---------------------------------------------------------------------------
// The P1 bar

/// Mass and stiffness on the unknowns `0..m` (node `m` is clamped).
pub struct BarMatrices {
    /// Elements.
    pub m: usize,
    /// `h = 1/m`.
    pub h: f64,
    /// Mass.
    pub mass: Dense,
    /// Stiffness.
    pub stiff: Dense,
}

impl BarMatrices {
    /// Assembled from the element matrices `h/6 [2 1; 1 2]`, `1/h [1 -1; -1 1]`.
    pub fn new(m: usize, mass: Mass) -> Self {
        let h = 1.0 / m as f64;
        let (mut mm, mut kk) = (Dense::zeros(m), Dense::zeros(m));
        for el in 0..m {
            let nodes = [el, el + 1];
            for (a, &i) in nodes.iter().enumerate() {
                for (b, &j) in nodes.iter().enumerate() {
                    if i == m || j == m {
                        continue; // the clamped node is not an unknown
                    }
                    kk.add(i, j, if a == b { 1.0 / h } else { -1.0 / h });
                    if !(mass == Mass::Mod && el == 0) {
                        mm.add(i, j, if a == b { h / 3.0 } else { h / 6.0 });
                    }
                }
            }
        }
        Self { m, h, mass: mm, stiff: kk }
    }

    /// The first dof that carries mass.
    fn massive_start(&self) -> usize {
        usize::from(self.mass.get(0, 0) == 0.0)
    }
}

// ---------------------------------------------------------------------------
// Quadrature of the space errors

/// 4-point Gauss–Lobatto nodes `(1 ∓ 1/√5)/2` (and the ends) on `[0, 1]`, weights (exact to degree 5).
const LOBATTO: [(f64, f64); 4] = [(0.0, 1.0 / 12.0), (0.276_393_202_250_021, 5.0 / 12.0), (0.723_606_797_749_978_9, 5.0 / 12.0), (1.0, 1.0 / 12.0)];

/// A piece is affine when `e` at the two inner Lobatto nodes is within this
/// of its chord. The values are `O(1)` and carry a few ulps (`~1e-16`) of
/// rounding, so an affine piece always passes; a kink at distance `δ` from
/// both ends of a piece of length `ℓ` bends `e` by at least
/// `(1/2)(0.276)·min(δ, ℓ - δ)` (the exact slopes jump by `1/2`), so a piece
/// that passes hides a kink within `1e-12` of its ends at most.
const AFFINE_TOL: f64 = 1e-13;

/// Pieces are not split beyond `2⁻⁴⁵ h` (below `1e-15` for the meshes here;
/// reached only if rounding ever exceeded [`AFFINE_TOL`]).
const MAX_DEPTH: u32 = 45;

/// `[∫ e², ∫ e_x²]` over `[a, b]`: bisected until `e = u_h - u` is affine on
/// each piece (which finds the kinks of the exact solution without being
/// told where they are: the library splits elements at the kinks the exact
/// solution reports), then Gauss–Lobatto for `e²` (exact: degree 2) and
/// `e_x` at the piece's midpoint (constant on an affine piece; the midpoint
/// keeps it away from a kink at an end, where `u_x` is one-sided).
///
/// The criterion bears on `e`, not on the integrals: comparing a rule with
/// its halves to a relative tolerance never stops where `e ≈ 0` (the
/// integrals are then rounding noise), and the recursion doubles at every
/// level — the first version of this reference did that and did not finish.
fn piece_errors(e: &dyn Fn(f64) -> f64, ex: &dyn Fn(f64) -> f64, a: f64, b: f64, depth: u32) -> [f64; 2] {
    let vals = LOBATTO.map(|(x, _)| e(a + (b - a) * x));
    let chord = |x: f64| vals[0] + (vals[3] - vals[0]) * x;
    let affine = (1..3).all(|i| (vals[i] - chord(LOBATTO[i].0)).abs() <= AFFINE_TOL);
    if affine || depth >= MAX_DEPTH {
        let l2: f64 = LOBATTO.iter().zip(&vals).map(|((_, w), v)| w * v * v).sum();
        let d = ex(0.5 * (a + b));
        return [l2 * (b - a), d * d * (b - a)];
    }
    let mid = 0.5 * (a + b);
    let (l, r) = (piece_errors(e, ex, a, mid, depth + 1), piece_errors(e, ex, mid, b, depth + 1));
    [l[0] + r[0], l[1] + r[1]]
}

/// `(‖u_h - u‖_{L²}, |u_h - u|_{H¹})` at time `t` for the P1 function with
/// nodal values `u` at the unknowns (the clamped node `m` is 0).
pub fn space_errors(u: &[f64], t: f64) -> (f64, f64) {
    let m = u.len();
    let h = 1.0 / m as f64;
    let node = |i: usize| if i < m { u[i] } else { 0.0 };
    let (mut l2, mut semi) = (0.0, 0.0);
    for j in 0..m {
        let (a, b) = (j as f64 * h, (j + 1) as f64 * h);
        let (ua, ub) = (node(j), node(j + 1));
        let slope = (ub - ua) / h;
        let e = move |x: f64| ua + slope * (x - a) - exact_u(x, t);
        let ex = move |x: f64| slope - exact_ux(x, t);
        let [p, q] = piece_errors(&e, &ex, a, b, 0);
        l2 += p;
        semi += q;
    }
    (l2.sqrt(), semi.sqrt())
}

// ---------------------------------------------------------------------------
// Time norms

#[derive(Clone, Copy, Debug, Default)]
struct TimeNorm {
    max: f64,
    sum_sq: f64,
}

impl TimeNorm {
    fn push(&mut self, e: f64) {
        self.max = self.max.max(e.abs());
        self.sum_sq += e * e;
    }
    fn l2(&self, dt: f64) -> f64 {
        (dt * self.sum_sq).sqrt()
    }
}

/// The norms of a run, named as the library's study columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Norms {
    /// `L∞(0,T; L²)` of `u_h - u`.
    pub linf_l2_u: f64,
    /// `L²(0,T; L²)`.
    pub l2_l2_u: f64,
    /// `L∞(0,T; H¹₀)` (seminorm).
    pub linf_v_u: f64,
    /// `L²(0,T; H¹₀)`.
    pub l2_v_u: f64,
    /// `L²(0,T)` of `λ_h - λ`.
    pub l2_lambda: f64,
    /// `L∞` of `E_h - E`.
    pub linf_energy: f64,
    /// `L²` of `E_h - E`.
    pub l2_energy: f64,
    /// `TV(λ_h) / TV(λ)` over the λ samples.
    pub lambda_tv_ratio: f64,
}

impl Norms {
    /// The norm columns of the study's CSVs, in order.
    pub const COLUMNS: [&'static str; 7] = ["linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "l2_lambda", "linf_energy", "l2_energy"];

    /// The values in [`Norms::COLUMNS`] order.
    pub fn values(&self) -> [f64; 7] {
        [self.linf_l2_u, self.l2_l2_u, self.linf_v_u, self.l2_v_u, self.l2_lambda, self.linf_energy, self.l2_energy]
    }
}

// ---------------------------------------------------------------------------
// The schemes

/// A trajectory of the reference.
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// Elements.
    pub m: usize,
    /// `dt = (1/m)/RATIO`.
    pub dt: f64,
    /// Steps `N`.
    pub steps: usize,
    /// `U^k` at every level `k = 0..=N`.
    pub u: Vec<Vec<f64>>,
    /// The contact forces in the order the scheme produces them, each with
    /// the level `k` whose time `t_k` it belongs to.
    pub lambdas: Vec<(usize, f64)>,
    /// The discrete energies, each with twice the (possibly half-integer)
    /// level it belongs to: `2k` for `E^k`, `2k + 1` for `E^{k+1/2}`.
    pub energies: Vec<(usize, f64)>,
}

/// A run of the benchmark over `T_END`: its trajectory and error norms.
#[derive(Clone, Debug)]
pub struct Run {
    /// The trajectory (`N = T_END RATIO m` steps).
    pub traj: Trajectory,
    /// The error norms.
    pub norms: Norms,
}

/// Newmark state in displacement, velocity, acceleration (the massless
/// node's velocity and acceleration are unused: its mass column is zero).
struct NewmarkState {
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

/// Newmark(β, γ) in the classical form: predictor `Ũ = U + dt V + dt²(½ - β) A`,
/// `M (U^{n+1} - Ũ)/(β dt²) + K U^{n+1} = -λ e_0` (row 0 of `M` is zero for a
/// massless node, so that row is the equilibrium `(K U)_0 = -λ`), then
/// `A^{n+1} = (U^{n+1} - Ũ)/(β dt²)`, `V^{n+1} = V + dt((1-γ) A + γ A^{n+1})`.
struct Newmark {
    beta: f64,
    gamma: f64,
    dt: f64,
    mass: Dense,
    solver: ContactSolver,
}

impl Newmark {
    fn new(bar: &BarMatrices, beta: f64, gamma: f64, dt: f64) -> Self {
        let s = Dense::comb(1.0 / (beta * dt * dt), &bar.mass, 1.0, &bar.stiff);
        Self { beta, gamma, dt, mass: bar.mass.clone(), solver: ContactSolver::new(s) }
    }

    /// `A^0` from `M A^0 = -K U^0` on the massive dofs (`λ^0 = 0`: the bar
    /// starts off the obstacle).
    fn start(bar: &BarMatrices, u0: Vec<f64>, v0: Vec<f64>) -> NewmarkState {
        let s = bar.massive_start();
        let ku = bar.stiff.mul(&u0);
        let rhs: Vec<f64> = ku[s..].iter().map(|k| -k).collect();
        let mut a = vec![0.0; u0.len()];
        a[s..].copy_from_slice(&Lu::new(&bar.mass.trailing(s)).solve(&rhs));
        NewmarkState { u: u0, v: v0, a }
    }

    /// One step with the obstacle at `gap`; returns `λ^{n+1}`.
    fn step(&self, st: &mut NewmarkState, gap: f64) -> f64 {
        let (b, g, dt) = (self.beta, self.gamma, self.dt);
        let pred: Vec<f64> = (0..st.u.len()).map(|i| st.u[i] + dt * st.v[i] + dt * dt * (0.5 - b) * st.a[i]).collect();
        let r: Vec<f64> = self.mass.mul(&pred).iter().map(|x| x / (b * dt * dt)).collect();
        let (u, lambda) = self.solver.solve(&r, gap);
        for i in 0..u.len() {
            let a_new = (u[i] - pred[i]) / (b * dt * dt);
            st.v[i] += dt * ((1.0 - g) * st.a[i] + g * a_new);
            st.a[i] = a_new;
        }
        st.u = u;
        lambda
    }

    /// `E = ½ VᵀMV + ½ UᵀKU`.
    fn energy(&self, bar: &BarMatrices, st: &NewmarkState) -> f64 {
        0.5 * self.mass.quad(&st.v) + 0.5 * bar.stiff.quad(&st.u)
    }
}

/// Paoli–Schatzman (β = 1/4): `M (U^{n+1} - 2U^n + U^{n-1})/dt² + K (β U^{n+1}
/// + (1-2β) U^n + β U^{n-1}) = -λ^n e_0`, `(u_0^{n+1} + e u_0^{n-1})/(1 + e) >= g`;
/// with a massless node row 0 is `(K U^{n+1})_0 = -λ_{n+1}`.
struct PaoliSchatzman {
    beta: f64,
    e: f64,
    dt: f64,
    massless: bool,
    mass: Dense,
    stiff: Dense,
    solver: ContactSolver,
}

impl PaoliSchatzman {
    fn new(bar: &BarMatrices, beta: f64, e: f64, dt: f64) -> Self {
        let massless = bar.massive_start() == 1;
        let mut s = Dense::comb(1.0 / (dt * dt), &bar.mass, beta, &bar.stiff);
        if massless {
            for j in 0..bar.m {
                s.set(0, j, bar.stiff.get(0, j));
            }
        }
        Self { beta, e, dt, massless, mass: bar.mass.clone(), stiff: bar.stiff.clone(), solver: ContactSolver::new(s) }
    }

    /// `U^{n+1}` and `λ` from `U^n`, `U^{n-1}`, the obstacle at `gap`.
    fn step(&self, u: &[f64], u_prev: &[f64], gap: f64) -> (Vec<f64>, f64) {
        let (b, dt2) = (self.beta, self.dt * self.dt);
        let two_minus: Vec<f64> = u.iter().zip(u_prev).map(|(x, y)| 2.0 * x - y).collect();
        let mix: Vec<f64> = u.iter().zip(u_prev).map(|(x, y)| (1.0 - 2.0 * b) * x + b * y).collect();
        let (mu, kmix) = (self.mass.mul(&two_minus), self.stiff.mul(&mix));
        let mut r: Vec<f64> = mu.iter().zip(&kmix).map(|(p, q)| p / dt2 - q).collect();
        if self.massless {
            r[0] = 0.0;
        }
        // The mean (u_0^{n+1} + e u_0^{n-1})/(1 + e) stays above the obstacle.
        let mean_weight = 1.0 + self.e;
        self.solver.solve(&r, mean_weight * gap - self.e * u_prev[0])
    }

    /// `E^{n+1/2} = ½ VᵀMV + ½ ŪᵀKŪ`, `V = (U^{n+1} - U^n)/dt`, `Ū` the mean (β = 1/4).
    fn energy(&self, u_next: &[f64], u: &[f64]) -> f64 {
        let v: Vec<f64> = u_next.iter().zip(u).map(|(a, b)| (a - b) / self.dt).collect();
        let ubar: Vec<f64> = u_next.iter().zip(u).map(|(a, b)| 0.5 * (a + b)).collect();
        0.5 * self.mass.quad(&v) + 0.5 * self.stiff.quad(&ubar)
    }
}

/// Runs `scheme` with `mass` on `m` elements for `steps` steps of
/// `dt = (1/m)/RATIO`, from the interpolated data of the benchmark, with the
/// obstacle at `gap` (the benchmark's is 0; another value tests the
/// `(1 + e) g` of Paoli–Schatzman's bound, which vanishes at `g = 0`).
pub fn simulate(scheme: Scheme, mass: Mass, m: usize, gap: f64, steps: usize) -> Trajectory {
    let bar = BarMatrices::new(m, mass);
    let dt = bar.h / RATIO as f64;
    let u0: Vec<f64> = (0..m).map(|i| 0.5 * (1.0 - i as f64 / m as f64)).collect();
    let v0 = vec![0.0; m];
    let mut us = vec![u0.clone()];
    let mut lambdas = Vec::new();
    let mut energies = Vec::new();
    let mut st = Newmark::start(&bar, u0, v0);
    match scheme {
        Scheme::NewmarkCn | Scheme::NewmarkI => {
            let (beta, gamma) = if scheme == Scheme::NewmarkCn { (0.25, 0.5) } else { (0.5, 1.0) };
            let nm = Newmark::new(&bar, beta, gamma, dt);
            energies.push((0, nm.energy(&bar, &st)));
            for k in 1..=steps {
                let lambda = nm.step(&mut st, gap);
                lambdas.push((k, lambda));
                energies.push((2 * k, nm.energy(&bar, &st)));
                us.push(st.u.clone());
            }
        }
        Scheme::PaoliSchatzman { e } => {
            // U^1 from one Newmark(β, 1/2) step; its force is not part of the sequence.
            Newmark::new(&bar, 0.25, 0.5, dt).step(&mut st, gap);
            us.push(st.u.clone());
            let ps = PaoliSchatzman::new(&bar, 0.25, e, dt);
            energies.push((1, ps.energy(&us[1], &us[0])));
            for n in 1..steps {
                let (next, lambda) = ps.step(&us[n], &us[n - 1], gap);
                lambdas.push((if ps.massless { n + 1 } else { n }, lambda));
                energies.push((2 * n + 1, ps.energy(&next, &us[n])));
                us.push(next);
            }
        }
    }
    Trajectory { m, dt, steps, u: us, lambdas, energies }
}

/// Runs `scheme` with `mass` on `m` elements, `dx/dt = RATIO`, `T = T_END`,
/// from the interpolated initial data, and measures every norm.
pub fn run(scheme: Scheme, mass: Mass, m: usize) -> Run {
    let traj = simulate(scheme, mass, m, 0.0, T_END * RATIO * m);
    let norms = measure(&traj.u, &traj.lambdas, &traj.energies, m, traj.dt);
    Run { traj, norms }
}

/// `‖λ_h - λ‖_{L²(0,T)}` with every force compared with the exact force
/// `shift` levels away from the level it belongs to: `shift = 0` is the
/// norm of [`Norms`]; `±1` is what a scheme reporting its force one step
/// late or early would be charged (a check that the time level matters).
pub fn l2_lambda_shifted(traj: &Trajectory, shift: isize) -> f64 {
    let sum: f64 = traj.lambdas.iter().map(|&(k, l)| (l - exact_lambda_at_level(k.saturating_add_signed(shift), traj.m)).powi(2)).sum();
    (traj.dt * sum).sqrt()
}

/// The norms of a run's samples.
fn measure(us: &[Vec<f64>], lambdas: &[(usize, f64)], energies: &[(usize, f64)], m: usize, dt: f64) -> Norms {
    let (mut l2, mut v) = (TimeNorm::default(), TimeNorm::default());
    for (k, u) in us.iter().enumerate() {
        let (a, b) = space_errors(u, k as f64 / (RATIO * m) as f64);
        l2.push(a);
        v.push(b);
    }
    let mut lam = TimeNorm::default();
    let (mut tv_h, mut tv_exact) = (0.0, 0.0);
    let mut last: Option<(f64, f64)> = None;
    for &(k, lh) in lambdas {
        let ex = exact_lambda_at_level(k, m);
        lam.push(lh - ex);
        if let Some((a, b)) = last {
            tv_h += (lh - a).abs();
            tv_exact += (ex - b).abs();
        }
        last = Some((lh, ex));
    }
    let mut en = TimeNorm::default();
    for &(_, e) in energies {
        en.push(e - EXACT_ENERGY);
    }
    Norms { linf_l2_u: l2.max, l2_l2_u: l2.l2(dt), linf_v_u: v.max, l2_v_u: v.l2(dt), l2_lambda: lam.l2(dt), linf_energy: en.max, l2_energy: en.l2(dt), lambda_tv_ratio: tv_h / tv_exact }
}

// ---------------------------------------------------------------------------
// The stored values (data/reference/independent/)

/// The level of the shipped scene `data/scenes/bar-dirichlet.toml`.
pub const STORED_LEVEL: usize = 80;

/// Path of the stored values, relative to the workspace root.
pub const STORED_PATH: &str = "data/reference/independent/bar-dirichlet-m80.csv";

/// Columns of the stored CSV.
pub const STORED_COLUMNS: [&str; 13] = ["scheme", "mass", "m", "dx", "dt", "steps", "linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "l2_lambda", "linf_energy", "l2_energy"];

/// The comment lines at the top of the stored CSV.
pub const STORED_HEADER: &str = "\
# Error norms of the bar-dirichlet benchmark (docs/theory.md 5.1; dx/dt = 10,
# T = 3, m = 80: the level of data/scenes/bar-dirichlet.toml), computed by the
# independent reference tests/support/independent_bar.rs, not by the library:
# d'Alembert exact solution, dense matrices and LU with pivoting, Newmark in
# (U, V, A) form, Paoli-Schatzman (beta = 1/4) with the massless row as an
# equilibrium, space norms by bisecting each element until the error is affine
# on every piece, then Gauss-Lobatto. Norms as in docs/theory.md 6.1-6.4;
# lambda compared at the time level the README documents (t_{n+1} Newmark,
# t_n Paoli-Schatzman, t_{n+1} with a massless node). Newmark with std mass is
# left out: it chatters after the impact, which amplifies rounding differences
# (to percents over a period for newmark-cn). The library agrees with these
# values to 9e-10 relative (measured; cancellation in E_h - 1/8 dominates).
# Regenerate: cargo test --release --test independent -- --ignored regenerate_stored_values
# Checked current by: cargo test --release --test independent stored_values_are_current
";

/// One stored row per reproducible configuration (not [`chaotic`]), the
/// norms with 16 significant digits.
pub fn stored_rows() -> Vec<Vec<String>> {
    CONFIGS
        .iter()
        .filter(|&&(scheme, mass)| !chaotic(scheme, mass))
        .map(|&(scheme, mass)| {
            let r = run(scheme, mass, STORED_LEVEL);
            let t = &r.traj;
            let mut row = vec![scheme.name(), mass.name().to_string(), t.m.to_string(), format!("{:.15e}", 1.0 / t.m as f64), format!("{:.15e}", t.dt), t.steps.to_string()];
            row.extend(r.norms.values().iter().map(|v| format!("{v:.15e}")));
            row
        })
        .collect()
}

/// The stored row of `(scheme, mass)` in `text` (the stored CSV), if any.
pub fn stored_norms(text: &str, scheme: &str, mass: &str) -> Option<[f64; 7]> {
    parse_stored(text).into_iter().find(|(k, _)| k.0 == scheme && k.1 == mass).map(|(_, v)| v)
}

/// The stored CSV text for [`stored_rows`].
pub fn stored_text(rows: &[Vec<String>]) -> String {
    let mut s = String::from(STORED_HEADER);
    s.push_str(&STORED_COLUMNS.join(","));
    s.push('\n');
    for r in rows {
        s.push_str(&r.join(","));
        s.push('\n');
    }
    s
}

/// Parses the stored CSV: `(scheme, mass) -> the seven norms`, skipping `#` lines.
pub fn parse_stored(text: &str) -> Vec<((String, String), [f64; 7])> {
    let mut lines = text.lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty());
    let header: Vec<&str> = lines.next().expect("a header line").split(',').collect();
    assert_eq!(header, STORED_COLUMNS, "stored CSV columns");
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), STORED_COLUMNS.len(), "row {l}");
            let norms: [f64; 7] = std::array::from_fn(|i| f[6 + i].parse().expect("a number"));
            ((f[0].to_string(), f[1].to_string()), norms)
        })
        .collect()
}
