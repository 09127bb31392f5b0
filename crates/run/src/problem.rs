//! Bar problems and the built-in benchmarks.

use crate::RunError;
use signorini_exact::{BarDirichlet, BarNeumannGravity, ExactSolution, FarEnd};
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_norms::VNorm;
use signorini_schemes::{Bounds, Contact, Dynamics, Initial};
use std::fmt;
use std::str::FromStr;

/// A P1 bar with Signorini contact at `x = 0` (docs/theory.md §1.1, §2.1).
#[derive(Clone, Debug)]
pub struct BarProblem {
    /// Geometry, wave speed, far end.
    pub bar: Bar,
    /// Mass treatment.
    pub mass: BarMass,
    /// Obstacle position `g` (contact when `u(0, t) = g`).
    pub gap: f64,
    /// Uniform body force `f` (e.g. `-g` for gravity).
    pub body_force: f64,
    /// Initial displacement and velocity at the unknowns.
    pub initial: Initial,
}

impl BarProblem {
    /// Interpolates the initial data `u0(x)`, `v0(x)` at the nodes.
    /// Fails if the initial position at `x = 0` is below the obstacle.
    pub fn new(bar: Bar, mass: BarMass, gap: f64, body_force: f64, u0: impl Fn(f64) -> f64, v0: impl Fn(f64) -> f64) -> Result<Self, RunError> {
        if !gap.is_finite() {
            return Err(RunError::Invalid { field: "gap", value: gap, allowed: "finite" });
        }
        if !body_force.is_finite() {
            return Err(RunError::Invalid { field: "body_force", value: body_force, allowed: "finite" });
        }
        let n = bar.dofs();
        let u: Vec<f64> = (0..n).map(|i| u0(bar.node(i))).collect();
        let v: Vec<f64> = (0..n).map(|i| v0(bar.node(i))).collect();
        if let Some(bad) = u.iter().chain(&v).find(|x| !x.is_finite()) {
            return Err(RunError::Invalid { field: "initial data", value: *bad, allowed: "finite values at every node" });
        }
        if u[0] < gap {
            return Err(RunError::Invalid { field: "initial u(0)", value: u[0], allowed: "at or above the obstacle position gap" });
        }
        Ok(Self { bar, mass, gap, body_force, initial: Initial { u, v } })
    }

    /// The semi-discrete system for the schemes.
    pub fn dynamics(&self) -> Dynamics {
        let f = self.body_force;
        Dynamics {
            mass: self.bar.mass(self.mass),
            stiffness: self.bar.stiffness(),
            load: self.bar.load(|_| f),
            contacts: vec![Contact::new(0, Bounds::obstacle(self.gap), self.mass.massless_contact_node())],
            forcing: None,
        }
    }

    /// The `V` norm of docs/theory.md §6.1 for this far end.
    pub fn vnorm(&self) -> VNorm {
        match self.bar.right_end {
            RightEnd::Clamped => VNorm::H1Seminorm,
            RightEnd::Free => VNorm::H1Full,
        }
    }
}

/// The built-in benchmarks with exact solutions (docs/theory.md §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Benchmark {
    /// `bar-dirichlet`: docs/theory.md §5.1.
    BarDirichlet,
    /// `bar-neumann-gravity`: the falling bar, `u0 = 1/2`, `g = 1/9`, `L = 1`
    /// (exactly periodic, period 16; docs/theory.md §5.2.4).
    BarNeumannGravity,
    /// `bar-neumann-gravity-0.11`: the paper's data `g = 0.11` (not periodic;
    /// exact closed form up to `t ≈ 225`).
    BarNeumannGravityPaper,
}

impl Benchmark {
    /// Every benchmark.
    pub const ALL: [Benchmark; 3] = [Benchmark::BarDirichlet, Benchmark::BarNeumannGravity, Benchmark::BarNeumannGravityPaper];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Benchmark::BarDirichlet => "bar-dirichlet",
            Benchmark::BarNeumannGravity => "bar-neumann-gravity",
            Benchmark::BarNeumannGravityPaper => "bar-neumann-gravity-0.11",
        }
    }

    /// The study defaults: (dx/dt, T). The papers' ratios (10 for the
    /// Dirichlet bar, 1 for the falling bar); horizons of one period (3) and
    /// of two impacts (16: one period for g = 1/9; impacts at 3.02 and 11.08
    /// for g = 0.11).
    pub fn default_ratio_and_horizon(self) -> (f64, f64) {
        match self {
            Benchmark::BarDirichlet => (10.0, 3.0),
            Benchmark::BarNeumannGravity | Benchmark::BarNeumannGravityPaper => (1.0, 16.0),
        }
    }

    /// The exact solution, valid on `[0, t_end]` (the falling bar is built
    /// event by event up to `t_end`; see [`BarNeumannGravity`] for its limits).
    pub fn exact(self, t_end: f64) -> Result<Box<dyn ExactSolution>, RunError> {
        let neumann = |r: Result<BarNeumannGravity, signorini_exact::NeumannError>| -> Result<Box<dyn ExactSolution>, RunError> {
            r.map(|s| Box::new(s) as Box<dyn ExactSolution>).map_err(|e| RunError::Exact(e.to_string()))
        };
        match self {
            Benchmark::BarDirichlet => Ok(Box::new(BarDirichlet)),
            Benchmark::BarNeumannGravity => neumann(BarNeumannGravity::periodic(t_end)),
            Benchmark::BarNeumannGravityPaper => neumann(BarNeumannGravity::paper(t_end)),
        }
    }

    /// The discrete problem on `m` elements with a mass treatment, initial
    /// data interpolated from the exact solution at `t = 0`.
    pub fn problem(self, exact: &dyn ExactSolution, m: usize, mass: BarMass) -> Result<BarProblem, RunError> {
        let end = match exact.far_end() {
            FarEnd::Clamped => RightEnd::Clamped,
            FarEnd::Free => RightEnd::Free,
        };
        let bar = Bar::new(exact.length(), m, exact.wave_speed(), end)?;
        BarProblem::new(bar, mass, exact.gap(), exact.body_force(), |x| exact.fields(x, 0.0).u, |x| exact.fields(x, 0.0).ut)
    }
}

impl fmt::Display for Benchmark {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Benchmark {
    type Err = RunError;
    fn from_str(s: &str) -> Result<Self, RunError> {
        Benchmark::ALL.into_iter().find(|b| b.name() == s).ok_or_else(|| RunError::UnknownBenchmark(s.to_string()))
    }
}
