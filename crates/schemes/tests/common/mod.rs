//! Oracles shared by the scheme tests, independent of the code under test.
//!
//! * The P1 bar (every mass treatment) and the Hermite beam matrices are
//!   assembled here, dense (`Vec<Vec<f64>>`), from the element matrices of
//!   docs/theory.md §2.1–§2.2; the schemes are fed the `signorini-fem`
//!   matrices, and every quantity a test checks (residuals of the scheme's
//!   equations, energies, work of the loads) is recomputed from the recorded
//!   displacements with the matrices built here, never read from a scheme's
//!   `energy()` or `work()`.
//! * Solves on the massive block and the largest generalized eigenvalue of a
//!   pencil go through faer's dense Cholesky and symmetric eigensolver (not
//!   the banded LDLᵀ nor the shift-invert iteration of `signorini-fem`).
//! * The sine profile's value and exact mean over a step are written here from
//!   the antiderivative (`A (cos ωt₀ − cos ωt₁)/(ω (t₁ − t₀))`), not in the
//!   code's cancellation-free sinc form.

#![allow(dead_code)]

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use signorini_fem::{Bar, BarMass, Beam, RightEnd, SymBand};
use signorini_schemes::{
    Active, Bounds, Contact, Dynamics, Forcing, Harmonic, Initial, LaneVector, Lockstep, LockstepBatch, LockstepLane, LockstepScheme, SchemeError, StepReport, Stepper, TimeProfile,
};

/// A dense square matrix, row by row.
pub type Dense = Vec<Vec<f64>>;

/// The `n × n` zero matrix.
pub fn zeros(n: usize) -> Dense {
    vec![vec![0.0; n]; n]
}

/// `a x`.
pub fn mul(a: &Dense, x: &[f64]) -> Vec<f64> {
    a.iter().map(|row| dot(row, x)).collect()
}

/// `xᵀ a x`.
pub fn quad(a: &Dense, x: &[f64]) -> f64 {
    dot(x, &mul(a, x))
}

/// `xᵀ a y`.
pub fn bilin(a: &Dense, x: &[f64], y: &[f64]) -> f64 {
    dot(x, &mul(a, y))
}

/// `xᵀ y`.
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len(), "length mismatch");
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// `x − y`.
pub fn sub(x: &[f64], y: &[f64]) -> Vec<f64> {
    x.iter().zip(y).map(|(a, b)| a - b).collect()
}

/// `Σ cᵢ xᵢ` over equal-length vectors.
pub fn lin(terms: &[(f64, &[f64])]) -> Vec<f64> {
    let n = terms[0].1.len();
    (0..n).map(|i| terms.iter().map(|(c, x)| c * x[i]).sum()).collect()
}

/// Largest absolute entry.
pub fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The infinity norm (largest absolute row sum).
pub fn norm_inf(a: &Dense) -> f64 {
    a.iter().map(|r| r.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max)
}

/// `a + s b`.
pub fn mat_add(a: &Dense, s: f64, b: &Dense) -> Dense {
    a.iter().zip(b).map(|(ra, rb)| ra.iter().zip(rb).map(|(x, y)| x + s * y).collect()).collect()
}

/// The trailing block from row/column `s` on.
pub fn trailing(a: &Dense, s: usize) -> Dense {
    a[s..].iter().map(|r| r[s..].to_vec()).collect()
}

/// The unit vector `e_i` of length `n`.
pub fn unit(n: usize, i: usize) -> Vec<f64> {
    let mut e = vec![0.0; n];
    e[i] = 1.0;
    e
}

fn to_faer(a: &Dense) -> Mat<f64> {
    Mat::from_fn(a.len(), a.len(), |i, j| a[i][j])
}

/// A dense Cholesky factor (faer) of a symmetric positive definite matrix.
pub struct Chol(faer::linalg::solvers::Llt<f64>);

impl Chol {
    /// Factorises `a` (panics if it is not positive definite).
    pub fn new(a: &Dense) -> Self {
        Chol(to_faer(a).llt(Side::Lower).expect("SPD matrix"))
    }

    /// `a⁻¹ b`.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let x = self.0.solve(Mat::from_fn(b.len(), 1, |i, _| b[i]));
        (0..b.len()).map(|i| x[(i, 0)]).collect()
    }
}

/// The largest eigenvalue of the symmetric pencil `(k, m)` (`m` SPD): that
/// of `L⁻¹ k L⁻ᵀ` with `m = L Lᵀ`, by faer's dense symmetric eigensolver.
pub fn kappa_max(k: &Dense, m: &Dense) -> f64 {
    let n = m.len();
    let l = to_faer(m).llt(Side::Lower).expect("M is SPD").L().to_owned();
    let mut linv = Mat::<f64>::identity(n, n);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), faer::Par::Seq);
    let c = &linv * to_faer(k) * linv.transpose();
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    *c.self_adjoint_eigenvalues(Side::Lower).expect("symmetric eigenvalues").last().unwrap()
}

/// The smallest eigenvalue of a symmetric matrix.
pub fn min_eigenvalue(a: &Dense) -> f64 {
    to_faer(a).self_adjoint_eigenvalues(Side::Lower).expect("symmetric eigenvalues")[0]
}

/// Asserts that a `SymBand` given to a scheme holds the matrix built here
/// (to rounding), so a failure below points at the scheme, not the input.
pub fn assert_same(what: &str, band: &SymBand, dense: &Dense) {
    let n = dense.len();
    assert_eq!(band.n(), n, "{what}: size");
    let scale = norm_inf(dense).max(1e-300);
    for i in 0..n {
        for j in 0..n {
            assert!((band.get(i, j) - dense[i][j]).abs() <= 1e-14 * scale, "{what}[{i}][{j}] = {} but the test assembles {}", band.get(i, j), dense[i][j]);
        }
    }
}

/// P1 bar on `[0, 1]`, wave speed 1, `m` elements (docs/theory.md §2.1):
/// `(M, K)` on the unknowns (nodes `0..=m`, node `m` dropped when clamped).
/// Element mass `w_j (h/6)[2 1; 1 2]` (consistent) or `w_j (h/2) I`
/// (lumped), element stiffness `(1/h)[1 −1; −1 1]`; the density weights and
/// the node-level changes of §2.1.2's table.
pub fn bar_matrices(m: usize, mass: BarMass, free: bool) -> (Dense, Dense) {
    let h = 1.0 / m as f64;
    let mf = m as f64;
    let w = |j: usize| -> f64 {
        match mass {
            BarMass::Std | BarMass::Lumped | BarMass::Transfer | BarMass::Singular => 1.0,
            BarMass::Mod | BarMass::Mod1 => {
                if j == 0 {
                    0.0
                } else {
                    1.0
                }
            }
            BarMass::Mod2 => {
                if j == 0 {
                    0.0
                } else {
                    mf / (mf - 1.0)
                }
            }
            BarMass::Mod3 => match j {
                0 => 0.0,
                1 => 2.0,
                _ => 1.0,
            },
        }
    };
    let nodes = m + 1;
    let (mut mm, mut kk) = (zeros(nodes), zeros(nodes));
    for j in 0..m {
        let me = if mass == BarMass::Lumped { [[h / 2.0, 0.0], [0.0, h / 2.0]] } else { [[2.0 * h / 6.0, h / 6.0], [h / 6.0, 2.0 * h / 6.0]] };
        let ke = [[1.0 / h, -1.0 / h], [-1.0 / h, 1.0 / h]];
        for a in 0..2 {
            for b in 0..2 {
                mm[j + a][j + b] += w(j) * me[a][b];
                kk[j + a][j + b] += ke[a][b];
            }
        }
    }
    match mass {
        BarMass::Transfer => {
            let moved = mm[0][0] + mm[0][1];
            mm[1][1] += moved;
            zero_row_col(&mut mm, 0);
        }
        BarMass::Singular => {
            zero_row_col(&mut mm, 0);
            mm[1][1] = 7.0 * h / 12.0;
        }
        _ => {}
    }
    let n = if free { nodes } else { m };
    let cut = |a: Dense| -> Dense { a[..n].iter().map(|r| r[..n].to_vec()).collect() };
    (cut(mm), cut(kk))
}

fn zero_row_col(a: &mut Dense, i: usize) {
    for k in 0..a.len() {
        a[i][k] = 0.0;
        a[k][i] = 0.0;
    }
}

/// The load of a uniform body force `f` on the P1 bar (`∫ f φ_i`, exact):
/// `f h` at interior nodes, `f h/2` at nodes 0 and `m`.
pub fn bar_uniform_load(m: usize, free: bool, f: f64) -> Vec<f64> {
    let h = 1.0 / m as f64;
    let n = if free { m + 1 } else { m };
    (0..n).map(|i| if i == 0 || i == m { 0.5 * f * h } else { f * h }).collect()
}

/// The Hermite-cubic beam on `[0, length]`, `j` elements, `k² = k2`, unit
/// `ρS`, clamped at 0 (docs/theory.md §2.2): `(M, K)` on the `2j` unknowns.
pub fn beam_matrices(j: usize, length: f64, k2: f64) -> (Dense, Dense) {
    let h = length / j as f64;
    let h2 = h * h;
    let me = [[156.0, 22.0 * h, 54.0, -13.0 * h], [22.0 * h, 4.0 * h2, 13.0 * h, -3.0 * h2], [54.0, 13.0 * h, 156.0, -22.0 * h], [-13.0 * h, -3.0 * h2, -22.0 * h, 4.0 * h2]];
    let ke = [[12.0, 6.0 * h, -12.0, 6.0 * h], [6.0 * h, 4.0 * h2, -6.0 * h, 2.0 * h2], [-12.0, -6.0 * h, 12.0, -6.0 * h], [6.0 * h, 2.0 * h2, -6.0 * h, 4.0 * h2]];
    let all = 2 * (j + 1);
    let (mut mm, mut kk) = (zeros(all), zeros(all));
    for e in 0..j {
        for a in 0..4 {
            for b in 0..4 {
                mm[2 * e + a][2 * e + b] += h / 420.0 * me[a][b];
                kk[2 * e + a][2 * e + b] += k2 / (h * h2) * ke[a][b];
            }
        }
    }
    (trailing(&mm, 2), trailing(&kk, 2))
}

/// The sine profile `A sin(ω t)` of a forcing, written independently.
#[derive(Clone, Copy, Debug)]
pub struct Sine {
    /// Amplitude `A`.
    pub amp: f64,
    /// Angular frequency `ω`.
    pub omega: f64,
}

impl Sine {
    /// `A sin(ω t)`.
    pub fn at(&self, t: f64) -> f64 {
        self.amp * (self.omega * t).sin()
    }

    /// The exact mean over `[t0, t1]`, from the antiderivative.
    pub fn mean(&self, t0: f64, t1: f64) -> f64 {
        self.amp * ((self.omega * t0).cos() - (self.omega * t1).cos()) / (self.omega * (t1 - t0))
    }

    /// The profile as the library's type.
    pub fn profile(&self) -> TimeProfile {
        TimeProfile::Sine { amplitude: self.amp, omega: self.omega }
    }
}

/// What a test knows of the semi-discrete problem, built independently of
/// the `Dynamics` the scheme is given: `M U'' + K U = F_s + shape·s(t) − λ e_c`.
#[derive(Clone, Debug)]
pub struct Oracle {
    /// Mass matrix.
    pub m: Dense,
    /// Stiffness matrix.
    pub k: Dense,
    /// Steady load `F_s`.
    pub load: Vec<f64>,
    /// Time-dependent load `shape · s(t)`, if any.
    pub forcing: Option<(Vec<f64>, Sine)>,
    /// Contact dof.
    pub c: usize,
    /// Whether the contact dof carries no mass.
    pub massless: bool,
    /// Bounds on `u_c`.
    pub lo: f64,
    /// Upper bound (`+∞` for one obstacle).
    pub hi: f64,
    /// Every constrained dof, in contact order (the first is `c`, `lo`,
    /// `hi`); every one massless when `massless`.
    pub stops: Vec<OStop>,
}

/// One constrained dof as the test knows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OStop {
    /// The dof.
    pub dof: usize,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Its own restitution, if any.
    pub e: Option<f64>,
    /// Its own penalty stiffness, if any.
    pub kappa: Option<f64>,
}

impl OStop {
    /// A stop with the scheme's restitution and stiffness.
    pub fn new(dof: usize, lo: f64, hi: f64) -> Self {
        Self { dof, lo, hi, e: None, kappa: None }
    }
}

impl Oracle {
    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.m.len()
    }

    /// The time-dependent part `shape · s(t)` (zero without forcing).
    pub fn forcing_at(&self, t: f64) -> Vec<f64> {
        match &self.forcing {
            Some((shape, s)) => shape.iter().map(|g| g * s.at(t)).collect(),
            None => vec![0.0; self.n()],
        }
    }

    /// `F(t) = F_s + shape · s(t)`.
    pub fn load_at(&self, t: f64) -> Vec<f64> {
        self.load.iter().zip(self.forcing_at(t)).map(|(a, b)| a + b).collect()
    }

    /// The forcing's exact mean over `[t0, t1]` (zero without forcing).
    pub fn forcing_mean(&self, t0: f64, t1: f64) -> Vec<f64> {
        match &self.forcing {
            Some((shape, s)) => shape.iter().map(|g| g * s.mean(t0, t1)).collect(),
            None => vec![0.0; self.n()],
        }
    }

    /// The dofs that carry mass: all but the massless contacts.
    pub fn massive_dofs(&self) -> Vec<usize> {
        (0..self.n()).filter(|i| !(self.massless && self.stops.iter().any(|st| st.dof == *i))).collect()
    }

    /// `(M_ss)⁻¹ P` on the massive dofs, `V_c = 0` on a massless node (whose
    /// velocity terms cancel from the identities once it is in equilibrium,
    /// docs/theory.md §7.7).
    pub fn velocity(&self, chol: &Chol, p: &[f64]) -> Vec<f64> {
        let s = self.massive_dofs();
        let ps: Vec<f64> = s.iter().map(|&i| p[i]).collect();
        let mut v = vec![0.0; self.n()];
        for (&i, x) in s.iter().zip(chol.solve(&ps)) {
            v[i] = x;
        }
        v
    }

    /// The Cholesky factor of the massive block of `M`.
    pub fn mass_chol(&self) -> Chol {
        let s = self.massive_dofs();
        Chol::new(&s.iter().map(|&i| s.iter().map(|&j| self.m[i][j]).collect()).collect())
    }

    /// The contact force vector `Σ λ_i e_{c_i}` for the forces `lams` in
    /// contact order.
    pub fn force_vector(&self, lams: &[f64]) -> Vec<f64> {
        assert_eq!(lams.len(), self.stops.len(), "one force per contact");
        let mut f = vec![0.0; self.n()];
        for (st, l) in self.stops.iter().zip(lams) {
            f[st.dof] += l;
        }
        f
    }
}

/// A bar scene: `m` elements, a mass treatment, the far end, an obstacle at
/// `gap`, a uniform body force and an optional forcing. Returns the
/// `Dynamics` built from `signorini-fem` (what the schemes run on) and the
/// test's own `Oracle` (checked equal to rounding).
pub fn bar_scene(m: usize, mass: BarMass, free: bool, gap: f64, body: f64, forcing: Option<(Vec<f64>, Sine)>) -> (Dynamics, Oracle) {
    let bar = Bar::new(1.0, m, 1.0, if free { RightEnd::Free } else { RightEnd::Clamped }).unwrap();
    let (mm, kk) = bar_matrices(m, mass, free);
    let load = bar_uniform_load(m, free, body);
    let dy = Dynamics::new(bar.mass(mass), bar.stiffness(), bar.load(|_| body), vec![Contact::new(0, Bounds::obstacle(gap), mass.massless_contact_node())])
        .with_forcing(forcing.as_ref().map(|(shape, s)| Forcing { shape: shape.clone(), time: s.profile() }).into_iter().collect());
    assert_same("bar mass", &dy.mass, &mm);
    assert_same("bar stiffness", &dy.stiffness, &kk);
    for (a, b) in dy.load.iter().zip(&load) {
        assert!((a - b).abs() <= 1e-15 * (1.0 + b.abs()), "bar load {a} vs {b}");
    }
    let o = Oracle { m: mm, k: kk, load, forcing, c: 0, massless: mass.massless_contact_node(), lo: gap, hi: f64::INFINITY, stops: vec![OStop::new(0, gap, f64::INFINITY)] };
    (dy, o)
}

/// A beam scene: `j` Hermite elements on `[0, 1]`, `k² = k2`, the tip
/// between stops `[lo, hi]`, no steady load, forcing `shape · s(t)`.
pub fn beam_scene(j: usize, k2: f64, lo: f64, hi: f64, shape: Vec<f64>, s: Sine) -> (Dynamics, Oracle) {
    let beam = Beam::new(1.0, j, k2).unwrap();
    let (mm, kk) = beam_matrices(j, 1.0, k2);
    let n = 2 * j;
    let dy =
        Dynamics::new(beam.mass(), beam.stiffness(), vec![0.0; n], vec![Contact::new(2 * j - 2, Bounds { lo, hi }, false)]).with_forcing(vec![Forcing { shape: shape.clone(), time: s.profile() }]);
    assert_eq!(dy.stiffness.half_bandwidth(), 3, "the beam must take the banded (non-tridiagonal) path");
    assert_same("beam mass", &dy.mass, &mm);
    assert_same("beam stiffness", &dy.stiffness, &kk);
    let o = Oracle { m: mm, k: kk, load: vec![0.0; n], forcing: Some((shape, s)), c: 2 * j - 2, massless: false, lo, hi, stops: vec![OStop::new(2 * j - 2, lo, hi)] };
    (dy, o)
}

/// Smooth initial data for a bar whose contact node starts `offset` above
/// the obstacle `gap` and moves towards it at speed `speed`, with a smooth
/// perturbation `(amp/seed²)(1 − cos(seed x))` of the displacement (its
/// curvature, hence the elastic force near node 0, is at most `amp`) and
/// `amp sin(seed x)` of the velocity. With `speed >= 0.5`, `amp <= 0.5`,
/// `offset <= 0.02` and loads below 0.25 the node reaches the obstacle
/// before `t = 0.1` (see [`steps_for`]).
pub fn approaching(n: usize, m: usize, gap: f64, offset: f64, speed: f64, amp: f64, seed: f64) -> Initial {
    let x = |i: usize| i as f64 / m as f64;
    let u = (0..n).map(|i| gap + offset + amp / (seed * seed) * (1.0 - (seed * x(i)).cos())).collect();
    let v = (0..n).map(|i| -speed + amp * (seed * x(i)).sin()).collect();
    Initial { u, v }
}

/// The number of steps of size `dt` to run: at least `min`, and enough to
/// reach `t = 0.1`, by which [`approaching`] data have met the obstacle.
pub fn steps_for(dt: f64, min: usize) -> usize {
    min.max((0.1 / dt).ceil() as usize)
}

/// A nonzero gap of either sign, as a fraction `φ ∈ ±[0.1, 0.9]` for [`gap_of`].
pub fn gap_strategy() -> impl proptest::strategy::Strategy<Value = f64> {
    proptest::prop_oneof![-0.9f64..-0.1, 0.1f64..0.9]
}

/// The gap for a fraction `φ`: `g = 0.3 φ` above the origin, `g = φ |f|/2`
/// below it, so that a clamped bar at rest under the body force `f < 0`
/// (tip at `f/2`) would press on the obstacle: even a dissipative scheme
/// with a huge step meets it.
pub fn gap_of(phi: f64, body: f64) -> f64 {
    if phi > 0.0 {
        0.3 * phi
    } else {
        0.5 * phi * body.abs()
    }
}

/// The contact force vector `λ e_c` of the one-step schemes with a point
/// contact (for [`check_one_step`]).
pub fn point_force(n: usize, c: usize) -> impl Fn(usize, &[f64], f64) -> Vec<f64> {
    move |_, _, lambda| {
        let mut f = vec![0.0; n];
        f[c] = lambda;
        f
    }
}

/// A recorded run: the displacement at every level from `first` on, and
/// each step's report.
pub struct Traj {
    /// Time step.
    pub dt: f64,
    /// Level of `u[0]`.
    pub first: usize,
    /// `U` at levels `first, first + 1, …`.
    pub u: Vec<Vec<f64>>,
    /// `reports[i]` produced level `first + i + 1`.
    pub reports: Vec<StepReport>,
    /// Every contact's force after each step (`forces[i]` with `reports[i]`).
    pub forces: Vec<Vec<f64>>,
}

impl Traj {
    /// `U` at level `n`.
    pub fn at(&self, n: usize) -> &[f64] {
        &self.u[n - self.first]
    }

    /// The last level.
    pub fn last(&self) -> usize {
        self.first + self.u.len() - 1
    }

    /// The contact force by level: the step producing level `n` must report
    /// its force at time `t_{n − lag}` (docs/theory.md §4: lag 0 for the
    /// one-step schemes, 1 for Paoli–Schatzman with a massive contact node),
    /// which is where it is placed. Levels no step reports are `None`.
    pub fn lambdas(&self, lag: usize) -> Vec<Option<f64>> {
        let mut out = vec![None; self.last() + 1];
        for (i, r) in self.reports.iter().enumerate() {
            let n = self.first + i + 1;
            assert_eq!(r.n, n, "report level");
            let (t, l) = r.lambda.expect("every step reports its contact force");
            let want = (n - lag) as f64 * self.dt;
            assert!((t - want).abs() <= 1e-9 * self.dt, "step to level {n}: λ reported at t = {t}, the documented level is t_{} = {want}", n - lag);
            out[n - lag] = Some(l);
        }
        out
    }

    /// Every contact's force by level, placed like [`Traj::lambdas`]
    /// (`None` where no step reports one).
    pub fn all_forces(&self, lag: usize) -> Vec<Option<Vec<f64>>> {
        let mut out = vec![None; self.last() + 1];
        for (i, (r, f)) in self.reports.iter().zip(&self.forces).enumerate() {
            let n = self.first + i + 1;
            assert_eq!(r.lambda.map(|l| l.1), Some(f[0]), "step to level {n}: the report's λ is contact 0's force");
            out[n - lag] = Some(f.clone());
        }
        out
    }

    /// Number of steps whose report says a bound was active.
    pub fn active_steps(&self) -> usize {
        self.reports.iter().filter(|r| r.active != signorini_contact::Active::None).count()
    }
}

/// Runs `steps` steps and records the trajectory (panics on a scheme error).
pub fn record(s: &mut dyn Stepper, steps: usize) -> Traj {
    let first = s.level();
    let mut u = vec![s.displacement().to_vec()];
    let mut reports = Vec::with_capacity(steps);
    let mut forces = Vec::with_capacity(steps);
    for _ in 0..steps {
        let r = s.step().unwrap_or_else(|e| panic!("{}: {e}", s.label()));
        reports.push(r);
        forces.push(s.contact_forces().to_vec());
        u.push(s.displacement().to_vec());
    }
    Traj { dt: s.dt(), first, u, reports, forces }
}

/// The largest `|lhs − rhs| / scale` seen, to quote and to assert on.
#[derive(Clone, Copy, Debug, Default)]
pub struct Worst {
    /// Largest ratio.
    pub ratio: f64,
}

impl Worst {
    /// Records `|err| / scale` and asserts it is at most `tol`.
    #[track_caller]
    pub fn check(&mut self, what: &str, err: f64, scale: f64, tol: f64) {
        let r = err.abs() / scale.max(1e-300);
        assert!(r <= tol, "{what}: mismatch {err:e} is {r:e} of the scale {scale:e} (tolerance {tol:e})");
        self.ratio = self.ratio.max(r);
    }
}

/// Coefficients of a one-step scheme in momentum form (docs/theory.md §4.1,
/// §4.2): `M ΔU = dt Pⁿ + dt² (b Rⁿ + a R̃ⁿ⁺¹)`, `Pⁿ⁺¹ = Pⁿ + dt ((1 − γ) Rⁿ + γ Rⁿ⁺¹)`.
#[derive(Clone, Copy, Debug)]
pub struct Coefs {
    /// `a` (β, or θ²).
    pub a: f64,
    /// `b` (½ − β, or θ(1 − θ)).
    pub b: f64,
    /// `γ` (or θ).
    pub gamma: f64,
    /// The energy identity: Newmark's (§7.1) or the θ-method's (§7.2).
    pub theta_identity: bool,
}

impl Coefs {
    /// Newmark(β, γ).
    pub fn newmark(beta: f64, gamma: f64) -> Self {
        Self { a: beta, b: 0.5 - beta, gamma, theta_identity: false }
    }

    /// θ-method.
    pub fn theta(theta: f64) -> Self {
        Self { a: theta * theta, b: theta * (1.0 - theta), gamma: theta, theta_identity: true }
    }
}

/// What [`check_one_step`] measured.
#[derive(Clone, Debug, Default)]
pub struct OneStepStats {
    /// Worst residual of the displacement update.
    pub residual: Worst,
    /// Worst mismatch of the energy identity.
    pub energy: Worst,
    /// At every level: the energy `E` recomputed here, and the work of the
    /// time-dependent load and of the contact forces accumulated from level
    /// 0 (trapezoid, `Σ ½ ΔUᵀ(Gⁿ + Gⁿ⁺¹)` split by origin).
    pub path: Vec<(f64, f64, f64)>,
}

/// Checks a one-step run (Newmark, θ-method, penalty, Nitsche) against the
/// scheme's equations in momentum form with the test's matrices: `k` is the
/// stiffness the scheme uses (`K`, or Nitsche's `K_N`), `force(n, Uⁿ, λⁿ)`
/// the contact force vector `Cⁿ` at level `n` (`λ⁰ = 0`). With
/// `Rⁿ = F(tₙ) − K Uⁿ − Cⁿ` (`R_c := 0` for a massless node) and
/// `P⁰ = M V⁰`, at every step
///
/// * the update residual `M ΔU − dt Pⁿ − dt² (b Rⁿ + a R̃ⁿ⁺¹)` vanishes
///   (`R̃` without the massless zeroing: that row is the node's equilibrium);
/// * the energy `E = ½ VᵀMV + ½ UᵀKU − F_sᵀU`, `V = M⁺P`, obeys Newmark's
///   identity (§7.1, written for a general load `G = F_f − C`)
///   `ΔE = (½−γ) ΔUᵀKΔU + dt(β−γ/2) ΔVᵀKΔU + ΔUᵀ((1−γ)Gⁿ + γGⁿ⁺¹) − dt(β−γ/2) ΔVᵀ[G]`,
///   or the θ-method's `ΔE = (½−θ)(ΔVᵀMΔV + ΔUᵀKΔU) + ΔUᵀ((1−θ)Gⁿ + θGⁿ⁺¹)`
///   (from the first step on with a massless node, §7.7).
pub fn check_one_step(o: &Oracle, k: &Dense, cf: Coefs, init: &Initial, traj: &Traj, force: impl Fn(usize, &[f64], f64) -> Vec<f64>, tol: f64) -> OneStepStats {
    assert_eq!(traj.first, 0);
    let (dt, n) = (traj.dt, o.n());
    let lambdas = traj.lambdas(0);
    let chol = o.mass_chol();
    let (nm, nk) = (norm_inf(&o.m), norm_inf(k));
    let lam = |l: usize| if l == 0 { 0.0 } else { lambdas[l].unwrap() };
    let cvec = |l: usize| force(l, traj.at(l), lam(l));
    // R̃ (unzeroed) and R (massless row zeroed) at level l.
    let r_full = |l: usize| -> Vec<f64> {
        let (f, ku, cv) = (o.load_at(l as f64 * dt), mul(k, traj.at(l)), cvec(l));
        (0..n).map(|i| f[i] - ku[i] - cv[i]).collect()
    };
    let zero_c = |mut r: Vec<f64>| {
        if o.massless {
            for st in &o.stops {
                r[st.dof] = 0.0;
            }
        }
        r
    };
    let energy = |u: &[f64], v: &[f64]| 0.5 * quad(&o.m, v) + 0.5 * quad(k, u) - dot(&o.load, u);
    let g_vec = |l: usize| sub(&o.forcing_at(l as f64 * dt), &cvec(l));
    let mut st = OneStepStats::default();
    let mut p = mul(&o.m, &init.v);
    let mut r = zero_c(r_full(0));
    let (mut wf, mut wc) = (0.0, 0.0);
    st.path.push((energy(traj.at(0), &o.velocity(&chol, &p)), 0.0, 0.0));
    for l in 0..traj.last() {
        let (u0, u1) = (traj.at(l), traj.at(l + 1));
        let du = sub(u1, u0);
        let r1_full = r_full(l + 1);
        // The displacement update.
        let lhs = mul(&o.m, &du);
        let res: Vec<f64> = (0..n).map(|i| lhs[i] - dt * p[i] - dt * dt * (cf.b * r[i] + cf.a * r1_full[i])).collect();
        let scale = nm * (max_abs(u0) + max_abs(u1)) + dt * max_abs(&p) + dt * dt * (cf.b.abs() * max_abs(&r) + cf.a * (max_abs(&r1_full) + nk * max_abs(u1)));
        st.residual.check(&format!("update residual at step {l}→{}", l + 1), max_abs(&res), scale, tol);
        // The momentum update, and the energy identity.
        let r1 = zero_c(r1_full);
        let p1: Vec<f64> = (0..n).map(|i| p[i] + dt * ((1.0 - cf.gamma) * r[i] + cf.gamma * r1[i])).collect();
        let (v0, v1) = (o.velocity(&chol, &p), o.velocity(&chol, &p1));
        let t = |l: usize| l as f64 * dt;
        wf += 0.5 * dot(&du, &lin(&[(1.0, &o.forcing_at(t(l))), (1.0, &o.forcing_at(t(l + 1)))]));
        wc -= 0.5 * dot(&du, &lin(&[(1.0, &cvec(l)), (1.0, &cvec(l + 1))]));
        st.path.push((energy(u1, &v1), wf, wc));
        if l >= usize::from(o.massless) {
            let (e0, e1) = (energy(u0, &v0), energy(u1, &v1));
            let dv = sub(&v1, &v0);
            let kdu = mul(k, &du);
            let (g0, g1) = (g_vec(l), g_vec(l + 1));
            let g = cf.gamma;
            let terms = if cf.theta_identity {
                let th = g;
                vec![(0.5 - th) * (quad(&o.m, &dv) + dot(&du, &kdu)), dot(&du, &lin(&[(1.0 - th, &g0), (th, &g1)]))]
            } else {
                let beta = cf.a;
                vec![(0.5 - g) * dot(&du, &kdu), dt * (beta - g / 2.0) * dot(&dv, &kdu), dot(&du, &lin(&[(1.0 - g, &g0), (g, &g1)])), -dt * (beta - g / 2.0) * dot(&dv, &sub(&g1, &g0))]
            };
            let rhs: f64 = terms.iter().sum();
            let scale = terms.iter().fold(e0.abs().max(e1.abs()), |s, t| s.max(t.abs())).max(nk * max_abs(u0).max(max_abs(u1)).powi(2)).max(nm * max_abs(&v0).max(max_abs(&v1)).powi(2));
            st.energy.check(&format!("energy identity at step {l}→{} (ΔE = {:e}, identity {:e})", l + 1, e1 - e0, rhs), (e1 - e0) - rhs, scale, tol);
        }
        p = p1;
        r = r1;
    }
    st
}

/// Checks the projection's contact conditions at every level of a one-step
/// run, for every contact: `lo <= u_c <= hi`, `λ <= 0` on `lo`, `λ >= 0` on
/// `hi`, `λ = 0` strictly inside (the bound itself, not a rounding of it).
/// Returns the number of levels with some `λ ≠ 0`.
pub fn check_projection(o: &Oracle, traj: &Traj) -> usize {
    let _ = traj.lambdas(0);
    let forces = traj.all_forces(0);
    let mut active = 0;
    for l in 1..=traj.last() {
        let f = forces[l].as_ref().unwrap();
        for (st, &lam) in o.stops.iter().zip(f) {
            let u = traj.at(l)[st.dof];
            assert!(u >= st.lo && u <= st.hi, "level {l}: u_{} = {u} outside [{}, {}]", st.dof, st.lo, st.hi);
            if lam != 0.0 {
                let on = if lam < 0.0 { st.lo } else { st.hi };
                assert_eq!(u, on, "level {l}: λ = {lam} at dof {} but u = {u} is not on the bound {on}", st.dof);
            }
        }
        active += usize::from(f.iter().any(|x| *x != 0.0));
    }
    active
}

/// What [`check_ps`] measured.
#[derive(Default, Debug)]
pub struct PsStats {
    /// Worst residual of the two-step equation (and the start step).
    pub residual: Worst,
    /// Worst mismatch of the half-step energy balance.
    pub energy: Worst,
    /// Levels where some force is nonzero.
    pub active: usize,
    /// Levels with a nonzero force, per contact.
    pub active_per_contact: Vec<usize>,
}

/// Checks a Paoli–Schatzman run (docs/theory.md §4.3–§4.4, §7.3) with the
/// test's matrices, from the recorded displacements (`U⁰` = the initial
/// data, the run starting at level 1) and reported forces, for every
/// contact `i` (dof `c_i`, bounds `[lo_i, hi_i]`, restitution `e_i` = its
/// own or the scheme's `e`):
///
/// * the start step: rows off the contacts of one Newmark(β, ½) step (β = ¼
///   when β = 0) with the load `F(t₁)`; each contact row a force of the
///   right sign;
/// * every step: `M(Uⁿ⁺¹ − 2Uⁿ + Uⁿ⁻¹) + dt² K(βUⁿ⁺¹ + (1−2β)Uⁿ + βUⁿ⁻¹) = dt² (F_s + Gⁿ − Σ λ_iⁿ e_{c_i})`,
///   `Gⁿ = shape·(β fⁿ⁺¹ + (1−2β) fⁿ + β fⁿ⁻¹)`, `fᵏ` the exact mean over
///   `[t_k, t_{k+1}]` (massless nodes: row `c_i` is `(K Uⁿ⁺¹)_{c_i} = F_{c_i}(t_{n+1}) − λ_{i,n+1}`);
/// * the constraint `lo_i <= (u_{c_i}ⁿ⁺¹ + e_i u_{c_i}ⁿ⁻¹)/(1+e_i) <= hi_i`,
///   complementary to `λ_i` (`u_{c_i}ⁿ⁺¹ = (1+e_i) lo_i − e_i u_{c_i}ⁿ⁻¹` when `λ_i < 0`);
/// * the half-step energy balance
///   `E^{n+½} − E^{n−½} = ½ Gⁿᵀ(Uⁿ⁺¹ − Uⁿ⁻¹) − Σ ½ λ_iⁿ (u_{c_i}ⁿ⁺¹ − u_{c_i}ⁿ⁻¹)`, each
///   contact term being the paper's (35) with a gap, `(1+e_i)/2 λ_iⁿ (u_{c_i}ⁿ⁻¹ − bound)`
///   (massless nodes: `+ ½ ρ_{c_i} (u_{c_i}ⁿ⁺¹ − u_{c_i}ⁿ⁻¹)` with `ρ_{c_i}` the dropped row's residual).
pub fn check_ps(o: &Oracle, beta: f64, e: f64, init: &Initial, traj: &Traj) -> PsStats {
    const TOL: f64 = 1e-11;
    assert_eq!(traj.first, 1, "Paoli–Schatzman starts at level 1");
    let (dt, n) = (traj.dt, o.n());
    let dt2 = dt * dt;
    let is_contact = |i: usize| o.stops.iter().any(|st| st.dof == i);
    let u = |l: usize| -> &[f64] {
        if l == 0 {
            &init.u
        } else {
            traj.at(l)
        }
    };
    let lag = if o.massless { 0 } else { 1 };
    let _ = traj.lambdas(lag);
    let forces = traj.all_forces(lag);
    let (nm, nk) = (norm_inf(&o.m), norm_inf(&o.k));
    let mut st = PsStats { active_per_contact: vec![0; o.stops.len()], ..PsStats::default() };
    // The start step.
    {
        let bs = if beta > 0.0 { beta } else { 0.25 };
        let mut r0 = sub(&o.load_at(0.0), &mul(&o.k, u(0)));
        if o.massless {
            for s in &o.stops {
                r0[s.dof] = 0.0;
            }
        }
        let mv0 = mul(&o.m, &init.v);
        let lhs = mul(&mat_add(&o.m, bs * dt2, &o.k), u(1));
        let rhs = lin(&[(1.0, &mul(&o.m, u(0))), (dt, &mv0), ((0.5 - bs) * dt2, &r0), (bs * dt2, &o.load_at(dt))]);
        let res = sub(&lhs, &rhs);
        let scale = (nm + bs * dt2 * nk) * max_abs(u(1)) + nm * max_abs(u(0)) + dt * max_abs(&mv0) + dt2 * (max_abs(&r0) + max_abs(&o.load_at(dt)));
        for i in (0..n).filter(|&i| !is_contact(i)) {
            st.residual.check(&format!("start step, row {i}"), res[i], scale, TOL);
        }
        // Row c_i: μ = res >= 0 pushes up from lo, <= 0 down from hi.
        for s in &o.stops {
            let uc = u(1)[s.dof];
            assert!(uc >= s.lo && uc <= s.hi, "start step: u_{} = {uc} outside the bounds", s.dof);
            if res[s.dof].abs() > TOL * scale {
                assert_eq!(uc, if res[s.dof] > 0.0 { s.lo } else { s.hi }, "start step: a force {} off the bound at dof {}", res[s.dof], s.dof);
            }
        }
    }
    let mean = |k: usize| o.forcing_mean(k as f64 * dt, (k + 1) as f64 * dt);
    let energy = |l: usize| -> (f64, f64) {
        // E^{l+½} and a rounding scale for it.
        let v: Vec<f64> = sub(u(l + 1), u(l)).iter().map(|x| x / dt).collect();
        let ub = lin(&[(0.5, u(l)), (0.5, u(l + 1))]);
        let terms = [0.5 * quad(&o.m, &v), 0.5 * (beta - 0.25) * dt2 * quad(&o.k, &v), 0.5 * quad(&o.k, &ub), -dot(&o.load, &ub)];
        let scale = nm * max_abs(&v).powi(2) + nk * (max_abs(&ub).powi(2) + dt2 * max_abs(&v).powi(2)) + max_abs(&o.load) * max_abs(&ub) * n as f64;
        (terms.iter().sum(), scale)
    };
    for l in 1..traj.last() {
        let (um, u0, u1) = (u(l - 1), u(l), u(l + 1));
        let g = lin(&[(beta, &mean(l + 1)), (1.0 - 2.0 * beta, &mean(l)), (beta, &mean(l - 1))]);
        let avg = lin(&[(beta, u1), (1.0 - 2.0 * beta, u0), (beta, um)]);
        let kavg = mul(&o.k, &avg);
        let macc = mul(&o.m, &lin(&[(1.0, u1), (-2.0, u0), (1.0, um)]));
        // The forces of this step and the level they belong to.
        let lam_level = if o.massless { l + 1 } else { l };
        let lams = forces[lam_level].clone().unwrap_or_else(|| panic!("no force reported for level {lam_level}"));
        let lam_max = max_abs(&lams);
        let mut res: Vec<f64> = (0..n).map(|i| macc[i] + dt2 * (kavg[i] - o.load[i] - g[i])).collect();
        let scale = nm * (max_abs(u1) + 2.0 * max_abs(u0) + max_abs(um)) + dt2 * (nk * (max_abs(u1) + max_abs(u0) + max_abs(um)) + max_abs(&o.load) + max_abs(&g) + lam_max);
        let f1 = o.load_at((l + 1) as f64 * dt);
        let ku1 = mul(&o.k, u1);
        for (s, &lam) in o.stops.iter().zip(&lams) {
            if o.massless {
                res[s.dof] = dt2 * (ku1[s.dof] - f1[s.dof] + lam);
            } else {
                res[s.dof] += dt2 * lam;
            }
        }
        st.residual.check(&format!("two-step residual at step {l}→{}", l + 1), max_abs(&res), scale, TOL);
        let ((e0, s0), (e1, s1)) = (energy(l - 1), energy(l));
        let d2u = sub(u1, um);
        let work = 0.5 * dot(&g, &d2u);
        let mut contact = 0.0;
        let mut cscale = 0.0f64;
        for (i, (s, &lam)) in o.stops.iter().zip(&lams).enumerate() {
            // The restitution constraint and its complementarity.
            let ei = s.e.unwrap_or(e);
            let (ucm, uc1) = (um[s.dof], u1[s.dof]);
            let lo_e = if s.lo.is_finite() { (1.0 + ei) * s.lo - ei * ucm } else { f64::NEG_INFINITY };
            let hi_e = if s.hi.is_finite() { (1.0 + ei) * s.hi - ei * ucm } else { f64::INFINITY };
            let fin = |x: f64| if x.is_finite() { x.abs() } else { 0.0 };
            let tol_c = 1e-14 * (fin(s.lo) + ucm.abs() + uc1.abs() + fin(s.hi));
            assert!(uc1 >= lo_e - tol_c && uc1 <= hi_e + tol_c, "step {l}, dof {}: u^(n+1) = {uc1} outside [{lo_e}, {hi_e}] (e = {ei})", s.dof);
            if lam != 0.0 {
                st.active_per_contact[i] += 1;
                let (on, sign_ok) = if lam < 0.0 { (lo_e, s.lo.is_finite()) } else { (hi_e, s.hi.is_finite()) };
                assert!(sign_ok, "step {l}, dof {}: λ = {lam} pushes towards a missing bound", s.dof);
                assert!((uc1 - on).abs() <= tol_c, "step {l}, dof {}: λ = {lam} but u^(n+1) = {uc1} is not (1+e)·bound − e·u^(n−1) = {on} (e = {ei})", s.dof);
            }
            // Its term of the half-step energy balance.
            contact += if o.massless {
                let rho_c = kavg[s.dof] - o.load[s.dof] - g[s.dof];
                0.5 * rho_c * d2u[s.dof]
            } else {
                let general = -0.5 * lam * d2u[s.dof];
                if lam != 0.0 {
                    let bound = if lam < 0.0 { s.lo } else { s.hi };
                    let paper = 0.5 * (1.0 + ei) * lam * (ucm - bound);
                    st.energy.check(&format!("step {l}, dof {}: contact work vs (1+e)/2 λ (u^(n−1) − bound)", s.dof), general - paper, s0.max(s1).max(general.abs()), TOL);
                }
                general
            };
            cscale = cscale.max(contact.abs());
        }
        st.active += usize::from(lams.iter().any(|x| *x != 0.0));
        let scale = s0.max(s1).max(work.abs()).max(cscale);
        st.energy.check(&format!("half-step energy balance at step {l}→{} (ΔE = {:e}, work {work:e}, contact {contact:e})", l + 1, e1 - e0), (e1 - e0) - work - contact, scale, TOL);
    }
    st
}

/// A bar scene with several stops (`stops[i].dof` is a node; the mass
/// treatment at every stop's node): `std`, `lumped` (unchanged matrices) or
/// `mod` (every element next to a stop's node carries no mass), assembled
/// here from the element matrices, and checked equal to what
/// `Bar::mass_with_contacts` gives the scheme.
pub fn bar_stops_scene(m: usize, mass: BarMass, free: bool, stops: &[OStop], body: f64, forcing: Option<(Vec<f64>, Sine)>) -> (Dynamics, Oracle) {
    assert!(matches!(mass, BarMass::Std | BarMass::Lumped | BarMass::Mod), "the oracle builds std, lumped and mod at several nodes");
    let bar = Bar::new(1.0, m, 1.0, if free { RightEnd::Free } else { RightEnd::Clamped }).unwrap();
    let nodes: Vec<usize> = stops.iter().map(|s| s.dof).collect();
    let (mut mm, kk) = bar_matrices(m, if mass == BarMass::Mod { BarMass::Std } else { mass }, free);
    if mass == BarMass::Mod {
        let h = 1.0 / m as f64;
        for j in (0..m).filter(|&j| nodes.contains(&j) || nodes.contains(&(j + 1))) {
            // Remove element j's consistent mass.
            for (a, b, v) in [(j, j, h / 3.0), (j + 1, j + 1, h / 3.0), (j, j + 1, h / 6.0), (j + 1, j, h / 6.0)] {
                if a < mm.len() && b < mm.len() {
                    mm[a][b] -= v;
                }
            }
        }
        for &i in &nodes {
            for k in 0..mm.len() {
                assert!(mm[i][k].abs() < 1e-15 && mm[k][i].abs() < 1e-15, "node {i} keeps mass");
                mm[i][k] = 0.0;
                mm[k][i] = 0.0;
            }
        }
    }
    let load = bar_uniform_load(m, free, body);
    let massless = mass.massless_contact_node();
    let dy = Dynamics::new(
        bar.mass_with_contacts(mass, &nodes).unwrap(),
        bar.stiffness(),
        bar.load(|_| body),
        stops.iter().map(|s| Contact::new(s.dof, Bounds { lo: s.lo, hi: s.hi }, massless).with_restitution(s.e).with_stiffness(s.kappa)).collect(),
    )
    .with_forcing(forcing.as_ref().map(|(shape, s)| Forcing { shape: shape.clone(), time: s.profile() }).into_iter().collect());
    assert_same("bar mass at the stops", &dy.mass, &mm);
    assert_same("bar stiffness", &dy.stiffness, &kk);
    let s0 = stops[0];
    let o = Oracle { m: mm, k: kk, load, forcing, c: s0.dof, massless, lo: s0.lo, hi: s0.hi, stops: stops.to_vec() };
    (dy, o)
}

/// Checks a Moreau–Jean run (θ = ½, steady load; docs/theory.md §4.6.4)
/// with several contacts from the recorded displacements and forces, the
/// velocities rebuilt here (`V^{n+1} = 2ΔU/dt − Vⁿ` from `V⁰`): the
/// momentum equation `M(Vⁿ⁺¹ − Vⁿ) + dt K(Uⁿ + Uⁿ⁺¹)/2 = dt F + Σ p_i e_{c_i}`
/// (`p_i = −λ_i dt`), Newton's law at every predicted-active stop
/// (`u + dt/2 v <= lo`: `v⁺ + e v >= 0`, `p >= 0`, complementary; at `hi`
/// the mirror image), `p_i = 0` elsewhere, and `ΔE = Σ p_i (v_iⁿ + v_iⁿ⁺¹)/2`.
/// Returns the worst residual and energy ratios and the impulses per stop.
pub fn check_moreau_jean(o: &Oracle, e: f64, init: &Initial, traj: &Traj) -> (Worst, Worst, Vec<usize>) {
    const TOL: f64 = 1e-11;
    let dt = traj.dt;
    let all = traj.all_forces(0);
    let (nm, nk) = (norm_inf(&o.m), norm_inf(&o.k));
    let energy = |u: &[f64], v: &[f64]| 0.5 * quad(&o.m, v) + 0.5 * quad(&o.k, u) - dot(&o.load, u);
    let (mut res_w, mut en_w, mut active) = (Worst::default(), Worst::default(), vec![0usize; o.stops.len()]);
    let mut v = init.v.clone();
    for l in 0..traj.last() {
        let (u0, u1) = (traj.at(l), traj.at(l + 1));
        // θ = ½: U^{n+1} = U^n + dt (Vⁿ + Vⁿ⁺¹)/2.
        let v1: Vec<f64> = (0..o.n()).map(|i| 2.0 * (u1[i] - u0[i]) / dt - v[i]).collect();
        let f = all[l + 1].as_ref().unwrap();
        let p: Vec<f64> = f.iter().map(|lam| -lam * dt).collect();
        // M (V^{n+1} − Vⁿ) + dt K (Uⁿ + U^{n+1})/2 = dt F + Σ p_i e_i.
        let mdv = mul(&o.m, &sub(&v1, &v));
        let kmid = mul(&o.k, &lin(&[(0.5, u0), (0.5, u1)]));
        let pv = o.force_vector(&p);
        let res: Vec<f64> = (0..o.n()).map(|i| mdv[i] + dt * (kmid[i] - o.load[i]) - pv[i]).collect();
        let scale = nm * (max_abs(&v1) + max_abs(&v)) + dt * (nk * (max_abs(u0) + max_abs(u1)) + max_abs(&o.load)) + max_abs(&p);
        res_w.check(&format!("e = {e}: momentum residual at step {l}"), max_abs(&res), scale, TOL);
        for (i, s) in o.stops.iter().enumerate() {
            let ei = s.e.unwrap_or(e);
            let (uc, vc, vc1, pi) = (u0[s.dof], v[s.dof], v1[s.dof], p[i]);
            let pred = uc + 0.5 * dt * vc;
            let vtol = 1e-9 * (vc.abs() + vc1.abs() + 1.0);
            let (down, up) = (pred <= s.lo, pred >= s.hi && !(pred <= s.lo));
            if down {
                assert!(vc1 + ei * vc >= -vtol && pi >= 0.0, "step {l}, stop {i}: v^(n+1) = {vc1}, −e vⁿ = {}, p = {pi}", -ei * vc);
                assert!((pi * (vc1 + ei * vc)).abs() <= vtol * (pi.abs() + 1e-300), "step {l}, stop {i}: p = {pi} with v^(n+1) + e vⁿ = {}", vc1 + ei * vc);
            } else if up {
                assert!(vc1 + ei * vc <= vtol && pi <= 0.0, "step {l}, stop {i}: v^(n+1) = {vc1}, p = {pi} at the upper bound");
                assert!((pi * (vc1 + ei * vc)).abs() <= vtol * (pi.abs() + 1e-300));
            } else {
                assert_eq!(pi, 0.0, "step {l}, stop {i}: an impulse while not predicted active");
            }
            active[i] += usize::from(pi != 0.0);
        }
        // ΔE = Σ p_i (v_iⁿ + v_iⁿ⁺¹)/2.
        let (e0, e1) = (energy(u0, &v), energy(u1, &v1));
        let rhs: f64 = o.stops.iter().zip(&p).map(|(s, pi)| pi * 0.5 * (v[s.dof] + v1[s.dof])).sum();
        let escale = e0.abs().max(e1.abs()).max(rhs.abs()).max(nm * max_abs(&v1).powi(2)).max(nk * max_abs(u1).powi(2));
        en_w.check(&format!("e = {e}: energy identity at step {l}"), (e1 - e0) - rhs, escale, TOL);
        v = v1;
    }
    (res_w, en_w, active)
}

// ---- The lockstep engines' oracle: their single runs.
//
// Every engine is reached through the one non-generic entry,
// `LockstepBatch` (compiled once in the library): the tests build no
// engine of their own width, so this crate compiles none of their code.

/// A vector of an engine's lanes beyond `U^n` (`V^n`, a predictor, …),
/// compared with its single run's bit for bit from level `from` on.
pub struct Extra<S> {
    pub name: &'static str,
    /// The lane's vector ([`LockstepBatch::vector_into`]).
    pub vector: LaneVector,
    /// The single run's.
    pub single: fn(&S) -> &[f64],
    /// The first step after which it is compared (0: from the start).
    pub from: usize,
}

/// Bit patterns of `x`.
pub fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// Panics at the first entry of `got` whose bits differ from `want`'s.
#[track_caller]
fn same_bits(at: &str, name: &str, got: &[f64], want: &[f64]) {
    if bits(got) != bits(want) {
        let i = (0..got.len()).find(|&i| got[i].to_bits() != want[i].to_bits()).unwrap_or(got.len().min(want.len()));
        panic!("{at}: {name}[{i}] = {:e}, single run {:e}", got.get(i).copied().unwrap_or(f64::NAN), want.get(i).copied().unwrap_or(f64::NAN));
    }
}

/// Steps three builds of a lockstep batch (`make()` as the CPU selects,
/// its AVX2 build and its baseline x86-64 build) and each lane's single
/// run (`singles`, lane `k` the `k`-th) `steps` times, and compares, for
/// every build, lane and step, bit for bit: the level, `t_n`, the time of
/// the contact force, `U^n` (and `u_c` through `value`, and the whole view
/// of [`Lockstep::results`]), every `extras` vector, the contact force and
/// status of the single run's report, and no failure; a lane whose single
/// run fails must report that error at that step in every build (and is
/// no longer compared). Returns per lane the number of steps held at the
/// lower and upper bound.
#[track_caller]
pub fn check_lockstep<S: Stepper>(make: impl Fn() -> LockstepBatch, singles: &mut [S], extras: &[Extra<S>], steps: usize) -> Vec<(usize, usize)> {
    let mut builds = [("selected", make()), ("baseline", make().portable()), ("AVX2", make().without_avx512())];
    assert!(!builds[1].1.uses_avx2() && !builds[1].1.uses_avx512() && !builds[2].1.uses_avx512());
    assert_eq!(builds[0].1.lanes(), singles.len(), "a single run per lane");
    let n = builds[0].1.dofs();
    let mut buf = vec![0.0; n];
    let mut counts = vec![(0, 0); singles.len()];
    let mut done = vec![false; singles.len()];
    for step in 0..=steps {
        if step > 0 {
            for (_, b) in builds.iter_mut() {
                b.step();
            }
        }
        for (k, s) in singles.iter_mut().enumerate() {
            if done[k] {
                continue;
            }
            let report = if step > 0 {
                match s.step() {
                    Ok(r) => Some(r),
                    Err(e) => {
                        // The single run stops here: the lane must report the same error.
                        for (what, b) in &builds {
                            assert_eq!(b.lane_failure(k), Some(&e), "lane {k} step {step}: {what} build");
                            assert_eq!(b.results().failure(k), Some(&e), "lane {k} step {step}: {what} build's results");
                        }
                        done[k] = true;
                        continue;
                    }
                }
            } else {
                None
            };
            if let Some(r) = &report {
                match r.active {
                    Active::Lower => counts[k].0 += 1,
                    Active::Upper => counts[k].1 += 1,
                    Active::None => {}
                }
            }
            let want = s.displacement();
            for (what, b) in &builds {
                let at = format!("lane {k} level {} ({what} build)", s.level());
                assert_eq!(b.level(), s.level(), "{at}: level");
                assert_eq!(b.time().to_bits(), s.time().to_bits(), "{at}: time");
                let res = b.results();
                b.displacement_into(k, &mut buf);
                same_bits(&at, "u", &buf, want);
                res.displacement_into(k, &mut buf);
                same_bits(&at, "the results' u", &buf, want);
                let c = b.contact_dof();
                assert_eq!(b.value(k, c).to_bits(), want[c].to_bits(), "{at}: u_c");
                assert_eq!(res.value(k, c).to_bits(), want[c].to_bits(), "{at}: the results' u_c");
                for x in extras.iter().filter(|x| step >= x.from) {
                    assert!(b.vector_into(x.vector, k, &mut buf), "{at}: the engine keeps no {}", x.name);
                    same_bits(&at, x.name, &buf, (x.single)(s));
                }
                if let Some(r) = &report {
                    let (tl, lam) = r.lambda.expect("a contact force");
                    assert_eq!(tl.to_bits(), b.lambda_time().to_bits(), "{at}: the contact force's time");
                    assert_eq!(lam.to_bits(), b.contact_force(k).to_bits(), "{at}: λ {lam} vs {}", b.contact_force(k));
                    assert_eq!(lam.to_bits(), res.contact_force(k).to_bits(), "{at}: the results' λ");
                    assert_eq!(r.active, b.contact_status(k), "{at}: status");
                    assert_eq!(r.active, res.contact_status(k), "{at}: the results' status");
                    assert!(b.lane_failure(k).is_none() && res.failure(k).is_none(), "{at}: {:?}", b.lane_failure(k));
                }
            }
        }
    }
    counts
}

/// The refusals every lockstep engine makes of its lanes (`new` an
/// engine of 4 lanes, `base` a lane it takes): no lane, 5 lanes,
/// damping, two contacts, a massless contact, a mass matrix off by an ulp,
/// another contact dof, another number of forcing terms.
pub fn check_lane_refusals(new: impl Fn(Vec<LockstepLane>) -> Option<SchemeError>, base: impl Fn() -> LockstepLane) {
    let new = |lanes| new(lanes).expect("refused");
    assert!(matches!(new(vec![]), SchemeError::Size { got: 0, expected: 4, .. }));
    assert!(matches!(new(vec![base(), base(), base(), base(), base()]), SchemeError::Size { got: 5, expected: 4, .. }));
    let mut d = base();
    d.dynamics.damping = Some(d.dynamics.mass.clone());
    assert!(matches!(new(vec![base(), d]), SchemeError::Structure(m) if m.contains("undamped")));
    let mut d = base();
    d.dynamics.contacts.push(Contact::new(0, Bounds { lo: -1.0, hi: 1.0 }, false));
    assert!(matches!(new(vec![d]), SchemeError::Structure(m) if m.contains("one contact")));
    let mut d = base();
    d.dynamics.contacts[0].massless = true;
    assert!(matches!(new(vec![d]), SchemeError::Structure(m) if m.contains("massive")));
    let mut d = base();
    let m = d.dynamics.mass.get(5, 5);
    d.dynamics.mass.set(5, 5, m * (1.0 + 1e-15));
    assert!(matches!(new(vec![base(), d]), SchemeError::Structure(m) if m.contains("mass and stiffness")));
    let mut d = base();
    d.dynamics.contacts[0].dof = 10;
    assert!(matches!(new(vec![base(), d]), SchemeError::Structure(m) if m.contains("contact dof")));
    let mut d = base();
    d.dynamics.forcing.clear();
    assert!(matches!(new(vec![base(), d]), SchemeError::Structure(m) if m.contains("forcing terms")));
}

/// An engine under test: its scheme (the batch's: the restitution is each
/// lane's), each lane's single run (`single(lane, dt)`, the oracle), the
/// vectors compared besides `U^n`, and what else a comparison checks
/// (`also(width, dt, lanes, steps)`, after [`check_lockstep`]).
pub struct Engine<S> {
    pub scheme: LockstepScheme,
    pub single: SingleRun<S>,
    pub extras: Vec<Extra<S>>,
    pub also: Option<AlsoCheck>,
}

/// A lane's single run with step `dt` ([`Engine::single`]).
pub type SingleRun<S> = Box<dyn Fn(&LockstepLane, f64) -> S>;

/// What a comparison also checks ([`Engine::also`]): `(width, dt, lanes, steps)`.
pub type AlsoCheck = Box<dyn Fn(usize, f64, &[LockstepLane], usize)>;

/// What a comparison saw: per lane the steps held at the lower and upper
/// bound, and the single runs at its end.
pub struct Seen<S> {
    pub counts: Vec<(usize, usize)>,
    pub singles: Vec<S>,
}

impl<S: Stepper> Engine<S> {
    pub fn new(scheme: LockstepScheme, single: impl Fn(&LockstepLane, f64) -> S + 'static, extras: Vec<Extra<S>>) -> Self {
        Self { scheme, single: Box::new(single), extras, also: None }
    }

    /// The batch of `width` lanes on `lanes`, or its refusal.
    pub fn batch(&self, width: usize, dt: f64, lanes: Vec<LockstepLane>) -> Result<LockstepBatch, SchemeError> {
        LockstepBatch::with_width(self.scheme, width, dt, lanes)
    }

    /// Steps a batch of `width` lanes (every build) and each lane's single
    /// run `steps` times and compares them bit for bit at every step
    /// ([`check_lockstep`], then `also`).
    #[track_caller]
    pub fn compare(&self, width: usize, dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Seen<S> {
        let mut singles: Vec<S> = lanes.iter().map(|l| (self.single)(l, dt)).collect();
        let counts = check_lockstep(|| self.batch(width, dt, lanes.clone()).unwrap(), &mut singles, &self.extras, steps);
        if let Some(also) = &self.also {
            also(width, dt, &lanes, steps);
        }
        Seen { counts, singles }
    }

    /// [`compare`](Self::compare)'s counts.
    #[track_caller]
    pub fn counts(&self, width: usize, dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Vec<(usize, usize)> {
        self.compare(width, dt, lanes, steps).counts
    }

    /// Four lanes of the paper beam ([`rattling_lanes`]), `steps` steps: the
    /// first three rattle between both stops (more than 20 steps on each).
    #[track_caller]
    pub fn rattles(&self, dt: f64, steps: usize) -> Seen<S> {
        let seen = self.compare(4, dt, rattling_lanes(), steps);
        for (k, &(lo, hi)) in seen.counts.iter().enumerate().take(3) {
            assert!(lo > 20 && hi > 20, "{:?}: lane {k} should rattle between both stops: {lo} lower, {hi} upper steps", self.scheme);
        }
        seen
    }

    /// An amplitude sweep on 8 lanes ([`amplitude_lanes`], step `dt`) and
    /// two forcing terms per lane on 4 ([`two_term_lanes`], step `dt_two`),
    /// `steps` steps each: every lane in contact (more than 10 steps).
    /// Returns what the amplitude sweep saw.
    #[track_caller]
    pub fn amplitude_and_two_terms(&self, dt: f64, dt_two: f64, steps: usize) -> Seen<S> {
        let seen = self.compare(8, dt, amplitude_lanes(), steps);
        assert_contacts(&seen.counts, "amplitude sweep");
        assert_contacts(&self.counts(4, dt_two, two_term_lanes(), steps), "two forcing terms");
        seen
    }

    /// Partial batches: 4 lanes in a batch of 8 ([`partial_lanes`] with the
    /// fast forcing `fast`, `steps.0` steps) and 1 lane in a batch of 2
    /// (`pipe(19, 0.25, 44)`, `steps.1` steps); returns the lone lane's counts.
    #[track_caller]
    pub fn partial_batches(&self, dt: f64, fast: f64, steps: (usize, usize)) -> (usize, usize) {
        self.compare(8, dt, partial_lanes(fast), steps.0);
        self.counts(2, dt, vec![lane(pipe(19, 0.25, 44.0, (-0.01, 0.01)), 0.0)], steps.1)[0]
    }

    /// 16 lanes, 11 in use ([`sixteen_lanes`]): the two at rest (lanes 7
    /// and 8) stay at rest, the others are in contact.
    #[track_caller]
    pub fn sixteen(&self, dt: f64, steps: usize) -> Seen<S> {
        let seen = self.compare(16, dt, sixteen_lanes(), steps);
        assert_eq!(&seen.counts[7..9], &[(0, 0), (0, 0)], "{:?}: the lanes at rest stay at rest", self.scheme);
        assert_contacts(&seen.counts[..7], "sixteen lanes");
        assert_contacts(&seen.counts[9..], "sixteen lanes");
        seen
    }

    /// Short beams, J = 4, 5, 6, 8, with restitutions and a one-sided
    /// obstacle ([`short_beam_lanes`]), `steps` steps: every lane in contact.
    #[track_caller]
    pub fn short_beams(&self, dt: f64, steps: usize) {
        for j in [4, 5, 6, 8] {
            assert_contacts(&self.counts(4, dt, short_beam_lanes(j), steps), &format!("J = {j}"));
        }
    }

    /// The contact at each `(dof, gap)` of `at` ([`off_tip_lanes`]), 4
    /// lanes, `steps` steps: every lane in contact.
    #[track_caller]
    pub fn off_the_tip(&self, dt: f64, at: &[(usize, f64)], steps: usize) {
        for &(dof, gap) in at {
            assert_contacts(&self.counts(4, dt, off_tip_lanes(dof, gap), steps), &format!("dof {dof}"));
        }
    }

    /// Lanes whose forcing overflows ([`failing_lanes`], checked on this
    /// engine's single runs over `steps` steps) report the single run's
    /// `NonFinite` error at that step; the other lanes carry on bit for bit.
    #[track_caller]
    pub fn failing_lane(&self, dt: f64, steps: usize) {
        let lanes = failing_lanes(|l| {
            let mut s = (self.single)(l, dt);
            (0..steps).find_map(|_| s.step().err())
        });
        self.compare(4, dt, lanes, steps);
    }

    /// [`check_lane_refusals`] on a batch of 4 lanes, and a restitution
    /// of 1.5 refused as [`SchemeError::Invalid`].
    pub fn refusals(&self, dt: f64) {
        let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
        check_lane_refusals(|lanes| self.batch(4, dt, lanes).err(), base);
        let mut d = base();
        d.restitution = 1.5;
        assert!(matches!(self.batch(4, dt, vec![d]).err(), Some(SchemeError::Invalid { field: "restitution", .. })), "{:?}", self.scheme);
    }
}

/// Every lane held at a bound more than 10 steps.
#[track_caller]
pub fn assert_contacts(counts: &[(usize, usize)], what: &str) {
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{what}: {counts:?}");
}

// ---- The lockstep tests' problems: the paper's pipe with its support motion.

const LENGTH: f64 = 1.501;
const K2: f64 = 282.84;

/// `h(x)` of the lifting (crates/run/src/beam.rs, `Pipe::lifting`) and `h'`.
fn lifting(x: f64) -> (f64, f64) {
    let y = x / LENGTH;
    (1.0 - 2.0 * y * y + 4.0 / 3.0 * y.powi(3) - y.powi(4) / 3.0, (-4.0 * y + 4.0 * y * y - 4.0 / 3.0 * y.powi(3)) / LENGTH)
}

/// The paper's pipe (`Pipe::dynamics`, copied) with support `A sin(ω t)`
/// and stops `stops` at the tip: forcing `(A ω² h + 8 A k²/L⁴) sin(ω t)`,
/// `u = 0`, `u_t = -A ω h`.
pub fn pipe(j: usize, amp: f64, omega: f64, stops: (f64, f64)) -> (Dynamics, Initial) {
    let beam = Beam::new(LENGTH, j, K2).unwrap();
    let l4 = LENGTH.powi(4);
    let shape = beam.load(|x| amp * omega * omega * lifting(x).0 + 8.0 * amp * K2 / l4);
    let n = beam.dofs();
    let dy = Dynamics::new(beam.mass(), beam.stiffness(), vec![0.0; n], vec![Contact::new(beam.tip_dof(), Bounds { lo: stops.0, hi: stops.1 }, false)])
        .with_forcing(vec![Forcing { shape, time: TimeProfile::Sine { amplitude: 1.0, omega } }]);
    let v = beam.interpolate(|x| -amp * omega * lifting(x).0, |x| -amp * omega * lifting(x).1);
    (dy, Initial { u: vec![0.0; n], v })
}

/// The pipe driven by a support motion `φ` of two harmonics (`Pipe::excite`'s
/// two lifting terms, `-h φ''` and `8 k²/L⁴ φ`), starting at rest.
pub fn pipe_harmonics(j: usize, terms: Vec<Harmonic>, stops: (f64, f64)) -> (Dynamics, Initial) {
    let (beam, mut dy, _) = {
        let (dy, init) = pipe(j, 0.0, 1.0, stops);
        (Beam::new(LENGTH, j, K2).unwrap(), dy, init)
    };
    let phi = TimeProfile::harmonics(terms).unwrap();
    let acc = phi.second_derivative().unwrap();
    let l4 = LENGTH.powi(4);
    dy.forcing = vec![Forcing { shape: beam.load(|x| -lifting(x).0), time: acc }, Forcing { shape: beam.load(|_| 8.0 * K2 / l4), time: phi.clone() }];
    let (p0, dp0) = (phi.value(0.0), phi.derivative_at(0.0).unwrap());
    let u = beam.interpolate(|x| -p0 * lifting(x).0, |x| -p0 * lifting(x).1);
    let v = beam.interpolate(|x| -dp0 * lifting(x).0, |x| -dp0 * lifting(x).1);
    (dy, Initial { u, v })
}

pub fn lane(d: (Dynamics, Initial), e: f64) -> LockstepLane {
    LockstepLane { dynamics: d.0, initial: d.1, restitution: e }
}

/// Four lanes of the paper beam (J = 19, e = 0) with different ω and A,
/// narrow stops (±0.01) so the tip rattles, the last on stops at ±0.1.
pub fn rattling_lanes() -> Vec<LockstepLane> {
    let stops = (-0.01, 0.01);
    vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.2, 37.0, stops), 0.0), lane(pipe(19, 0.35, 23.5, stops), 0.0), lane(pipe(19, 0.05, 61.0, (-0.1, 0.1)), 0.0)]
}

/// An amplitude sweep: 5 lanes of one profile (ω = 30: means shared),
/// A = 0.1 … 0.38, stops (-0.01, 0.02).
pub fn amplitude_lanes() -> Vec<LockstepLane> {
    (0..5).map(|i| lane(pipe(19, 0.1 + 0.07 * i as f64, 30.0, (-0.01, 0.02)), 0.0)).collect()
}

/// Three lanes with two forcing terms each (a support motion of two
/// harmonics: `Sampler`'s phasors), stops (-0.01, 0.02).
pub fn two_term_lanes() -> Vec<LockstepLane> {
    [(0.01, 40.0), (0.012, 70.0), (0.02, 25.0)]
        .iter()
        .map(|&(a, w)| lane(pipe_harmonics(19, vec![Harmonic { amplitude: a, omega: w, phase: 0.3 }, Harmonic { amplitude: 0.5 * a, omega: 2.7 * w, phase: -1.0 }], (-0.01, 0.02)), 0.0))
        .collect()
}

/// Four lanes for a partial batch, one of them with the fast forcing
/// `fast` (A = 1e-4; ω dt = 1 at ω = 2·10⁴ and dt = 5e-5: its factor
/// sin(ω δ/2)/(ω δ/2) changes with the rounding of δ, so a stale δ shows).
pub fn partial_lanes(fast: f64) -> Vec<LockstepLane> {
    let stops = (-0.01, 0.01);
    vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 31.0, stops), 0.0), lane(pipe(19, 0.1, 55.0, stops), 0.0), lane(pipe(19, 1e-4, fast, stops), 0.0)]
}

/// 11 lanes for an engine of 16: frequencies and amplitudes, two lanes at
/// rest with zero forcing (A = 0 and A = -0: zeros of both signs in the
/// data; lanes 7 and 8), restitutions 1/2 and 1.
pub fn sixteen_lanes() -> Vec<LockstepLane> {
    let stops = (-0.01, 0.01);
    let mut lanes: Vec<LockstepLane> = (0..7).map(|i| lane(pipe(19, 0.1 + 0.05 * i as f64, 9.5 + 7.0 * i as f64, stops), 0.0)).collect();
    lanes.push(lane(pipe(19, 0.0, 10.0, stops), 0.0));
    lanes.push(lane(pipe(19, -0.0, 12.0, stops), 0.0));
    lanes.push(lane(pipe(19, 0.2, 37.0, stops), 0.5));
    lanes.push(lane(pipe(19, 0.2, 37.0, stops), 1.0));
    lanes
}

/// A short beam of `j` elements (J = 4 … 8: 8 to 16 unknowns, about as
/// many as the ring of 8 rows, whose first and last rows overlap): a
/// contact's own restitution (0.8), restitutions 1/2 and 0.7, a one-sided
/// obstacle.
pub fn short_beam_lanes(j: usize) -> Vec<LockstepLane> {
    let stops = (-0.01, 0.01);
    let mut own = pipe(j, 0.2, 37.0, stops);
    own.0.contacts[0].restitution = Some(0.8);
    vec![lane(pipe(j, 0.2, 10.0, stops), 0.0), lane(own, 0.0), lane(pipe(j, 0.35, 23.5, stops), 0.5), lane(pipe(j, 0.3, 20.0, (-0.01, f64::INFINITY)), 0.7)]
}

/// Four lanes of J = 19 with the contact at `dof` (off the tip's
/// displacement, row n-2) on stops at ±`gap`.
pub fn off_tip_lanes(dof: usize, gap: f64) -> Vec<LockstepLane> {
    let at = |amp: f64, omega: f64| {
        let (mut dy, init) = pipe(19, amp, omega, (-gap, gap));
        dy.contacts[0].dof = dof;
        lane((dy, init), 0.0)
    };
    vec![at(0.2, 10.0), at(0.3, 31.0), at(0.35, 23.5), at(0.1, 55.0)]
}

/// A lane at rest on a stop at 0 (the lower one for `p > 0`, the upper one
/// for `p < 0`; the other at ±0.01) pressed onto it by the steady load
/// `-p` times the forcing's shape (`U = 0`, `V = 0`, no forcing).
pub fn pressed(p: f64) -> LockstepLane {
    let stops = if p > 0.0 { (0.0, 0.01) } else { (-0.01, 0.0) };
    let (mut dy, mut init) = pipe(19, 0.0, 10.0, stops);
    let shape = pipe(19, 1.0, 10.0, (0.0, 0.0)).0.forcing[0].shape.clone();
    dy.load = shape.iter().map(|g| -p * g).collect();
    init.v.iter_mut().for_each(|v| *v = 0.0);
    lane((dy, init), 0.0)
}

/// A vibrating lane (stops ±0.01) with a steady load `p` times its forcing's shape.
pub fn loaded(amp: f64, omega: f64, p: f64) -> LockstepLane {
    let (mut dy, init) = pipe(19, amp, omega, (-0.01, 0.01));
    dy.load = dy.forcing[0].shape.iter().map(|g| p * g).collect();
    lane((dy, init), 0.0)
}

/// Three lanes pressed on a stop (lanes 0, 2, 4: loads 0.1, 1e-3 and
/// `last`) beside two vibrating lanes with steady loads.
pub fn pressed_lanes(last: f64) -> Vec<LockstepLane> {
    vec![pressed(0.1), loaded(0.2, 10.0, 0.05), pressed(1e-3), loaded(0.3, 31.0, -0.02), pressed(last)]
}

/// The four lanes of every engine's failing-lane test: the pipe between
/// stops at ±0.01, lanes 1 and 3 forced with amplitudes 1e306 and 1e304
/// (their single runs turn non-finite at some step), lanes 0 and 2
/// ordinary. The oracle is checked here, on the scheme's own single runs:
/// `single_fails` (a lane's single run stepped as long as the test steps
/// the batch, its first error) fails on lanes 1 and 3 and on no other.
pub fn failing_lanes(single_fails: impl Fn(&LockstepLane) -> Option<SchemeError>) -> Vec<LockstepLane> {
    let stops = (-0.01, 0.01);
    let huge = |amp: f64| {
        let (mut dy, init) = pipe(19, 0.2, 37.0, stops);
        dy.forcing[0].time = TimeProfile::Sine { amplitude: amp, omega: 37.0 };
        lane((dy, init), 0.0)
    };
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), huge(1e306), lane(pipe(19, 0.3, 31.0, stops), 0.0), huge(1e304)];
    let fails: Vec<Option<SchemeError>> = lanes.iter().map(single_fails).collect();
    assert!(fails[0].is_none() && fails[2].is_none() && fails[1].is_some() && fails[3].is_some(), "the single runs' failures: {fails:?}");
    lanes
}
