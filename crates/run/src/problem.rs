//! Bar problems and the built-in benchmarks.

use crate::RunError;
use signorini_exact::{BarDirichlet, BarMirrored, BarNeumannGravity, ExactSolution, FarEnd};
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_norms::VNorm;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Initial};
use std::fmt;
use std::str::FromStr;

/// A point stop at a mesh node: `lo <= u(node) <= hi` (either bound may be
/// infinite), with its own restitution (Paoli–Schatzman, Moreau–Jean) and
/// penalty stiffness when given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop {
    /// The node (bar: `0..=m`; beam: `1..=J`, its displacement dof).
    pub node: usize,
    /// Lower bound (`-∞`: none).
    pub lo: f64,
    /// Upper bound (`+∞`: none).
    pub hi: f64,
    /// Restitution coefficient of this stop (`None`: the scheme's).
    pub restitution: Option<f64>,
    /// Penalty stiffness of this stop (`None`: the law's).
    pub stiffness: Option<f64>,
}

impl Stop {
    /// A stop with the scheme's restitution and stiffness.
    pub fn new(node: usize, lo: f64, hi: f64) -> Self {
        Self { node, lo, hi, restitution: None, stiffness: None }
    }
}

/// Checks a list of stops against the unknowns' displacements `u` at
/// `dof(node)`: bounds ordered and not NaN, distinct nodes, the initial state
/// inside, per-stop parameters in range. Errors name `stop.<i>.<field>`.
pub(crate) fn check_stops(stops: &[Stop], u: &[f64], dof: impl Fn(usize) -> Option<usize>) -> Result<(), RunError> {
    if stops.is_empty() {
        return Err(RunError::Stop { index: 0, field: "node", value: f64::NAN, allowed: "at least one stop".into() });
    }
    for (i, st) in stops.iter().enumerate() {
        let bad = |field: &'static str, value: f64, allowed: String| Err(RunError::Stop { index: i, field, value, allowed });
        let Some(d) = dof(st.node) else {
            return bad("node", st.node as f64, "a node that is an unknown (not a clamped end)".into());
        };
        if st.lo.is_nan() || st.lo == f64::INFINITY {
            return bad("lo", st.lo, "a number or -inf (no lower bound)".into());
        }
        if st.hi.is_nan() || st.hi == f64::NEG_INFINITY {
            return bad("hi", st.hi, "a number or +inf (no upper bound)".into());
        }
        if st.lo > st.hi {
            return bad("lo", st.lo, format!("<= hi = {}", st.hi));
        }
        if let Some(j) = stops[..i].iter().position(|o| o.node == st.node) {
            return bad("node", st.node as f64, format!("a node without another stop (stop.{j} is at node {} already)", st.node));
        }
        if !(st.lo <= u[d] && u[d] <= st.hi) {
            return bad("lo", st.lo, format!("a stop that the initial state satisfies: u = {} at node {} is outside [{}, {}]", u[d], st.node, st.lo, st.hi));
        }
        if let Some(e) = st.restitution {
            if !(0.0..=1.0).contains(&e) {
                return bad("restitution", e, "[0, 1]".into());
            }
        }
        if let Some(k) = st.stiffness {
            if !(k > 0.0 && k.is_finite()) {
                return bad("stiffness", k, "finite and > 0".into());
            }
        }
    }
    Ok(())
}

/// The schemes' contact list for `stops` at `dof(node)`.
pub(crate) fn contacts_of(stops: &[Stop], dof: impl Fn(usize) -> usize, massless: bool) -> Vec<Contact> {
    stops.iter().map(|st| Contact::new(dof(st.node), Bounds { lo: st.lo, hi: st.hi }, massless).with_restitution(st.restitution).with_stiffness(st.stiffness)).collect()
}

/// A Pk bar (P1 unless [`Bar::with_degree`]) with Signorini contact at
/// `x = 0` (docs/theory.md §1.1, §2.1, §2.1.4), or at a list of stops.
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
    /// Stops at nodes replacing the obstacle at `x = 0` when not empty (see
    /// [`BarProblem::with_stops`]); the mass treatment then applies at
    /// every stop's node ([`Bar::mass_with_contacts`]).
    pub stops: Vec<Stop>,
    /// Time-dependent loads `shape · s(t)` on top of the body force (none
    /// by default).
    pub forcing: Vec<Forcing>,
}

impl BarProblem {
    /// Interpolates the initial data `u0(x)`, `v0(x)` at the nodes.
    /// Fails if the initial position at `x = 0` is below the obstacle, or
    /// for a mass treatment not defined at the bar's degree
    /// ([`Bar::check_mass`]).
    pub fn new(bar: Bar, mass: BarMass, gap: f64, body_force: f64, u0: impl Fn(f64) -> f64, v0: impl Fn(f64) -> f64) -> Result<Self, RunError> {
        if !gap.is_finite() {
            return Err(RunError::Invalid { field: "gap", value: gap, allowed: "finite" });
        }
        if !body_force.is_finite() {
            return Err(RunError::Invalid { field: "body_force", value: body_force, allowed: "finite" });
        }
        bar.check_mass(mass)?;
        let n = bar.dofs();
        let u: Vec<f64> = (0..n).map(|i| u0(bar.node(i))).collect();
        let v: Vec<f64> = (0..n).map(|i| v0(bar.node(i))).collect();
        if let Some(bad) = u.iter().chain(&v).find(|x| !x.is_finite()) {
            return Err(RunError::Invalid { field: "initial data", value: *bad, allowed: "finite values at every node" });
        }
        if u[0] < gap {
            return Err(RunError::Invalid {
                field: "initial u(0)",
                value: u[0],
                allowed:
                    "at or above the obstacle position `gap` (set `initial_displacement`, u(x, 0), with u(0) >= gap; `signorini modes` needs it too, though its orbits start from their own states)",
            });
        }
        Ok(Self { bar, mass, gap, body_force, initial: Initial { u, v }, stops: Vec::new(), forcing: Vec::new() })
    }

    /// The same bar with the contact list `stops` (in stop order) instead of
    /// the obstacle at `x = 0` (`gap` is then unused). Refused, naming
    /// `stop.<i>.<field>`: a node that is not an unknown, `lo > hi`, two
    /// stops on one node, an initial state outside a stop, per-stop
    /// parameters out of range; and a mass treatment that does not
    /// generalise to these nodes ([`Bar::mass_all_nodes_with_contacts`]).
    pub fn with_stops(mut self, stops: Vec<Stop>) -> Result<Self, RunError> {
        let n = self.bar.dofs();
        check_stops(&stops, &self.initial.u, |node| (node < n).then_some(node))?;
        let nodes: Vec<usize> = stops.iter().map(|s| s.node).collect();
        self.bar.mass_with_contacts(self.mass, &nodes)?;
        self.stops = stops;
        Ok(self)
    }

    /// The semi-discrete system for the schemes.
    pub fn dynamics(&self) -> Dynamics {
        let f = self.body_force;
        if !self.stops.is_empty() {
            let nodes: Vec<usize> = self.stops.iter().map(|s| s.node).collect();
            return Dynamics::new(
                self.bar.mass_with_contacts(self.mass, &nodes).expect("checked by with_stops"),
                self.bar.stiffness(),
                self.bar.load(|_| f),
                contacts_of(&self.stops, |node| node, self.mass.massless_contact_node()),
            )
            .with_forcing(self.forcing.clone());
        }
        Dynamics::new(self.bar.mass(self.mass), self.bar.stiffness(), self.bar.load(|_| f), vec![Contact::new(0, Bounds::obstacle(self.gap), self.mass.massless_contact_node())])
            .with_forcing(self.forcing.clone())
    }

    /// Adds the load `s(t)` uniform along the bar (`node = None`, per unit
    /// length) or at `node` (a point force), in the bar's scaled units.
    /// Refused, naming `load.x`, for a node that is not an unknown.
    pub fn with_load(mut self, node: Option<usize>, s: signorini_schemes::TimeProfile) -> Result<Self, RunError> {
        let shape = match node {
            None => self.bar.load(|_| 1.0),
            Some(i) if i < self.bar.dofs() => {
                let mut e = vec![0.0; self.bar.dofs()];
                e[i] = 1.0;
                e
            }
            Some(i) => return Err(RunError::Invalid { field: "load.x", value: i as f64, allowed: "a node that is an unknown (not the clamped end)" }),
        };
        self.forcing.push(Forcing { shape, time: s });
        Ok(self)
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
    /// `bar-mirrored`: the Dirichlet bar mirrored onto `[0, 2]`, a free bar
    /// between the stops `u(0) >= 0` and `u(2) <= 0` (docs/theory.md §5.4).
    /// Its level `m` is the number of elements on `[0, 1]`: the problem has
    /// `2m` elements, so `dx = 1/m` as for `bar-dirichlet` at level `m`.
    BarMirrored,
}

impl Benchmark {
    /// Every benchmark.
    pub const ALL: [Benchmark; 4] = [Benchmark::BarDirichlet, Benchmark::BarNeumannGravity, Benchmark::BarNeumannGravityPaper, Benchmark::BarMirrored];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Benchmark::BarDirichlet => "bar-dirichlet",
            Benchmark::BarNeumannGravity => "bar-neumann-gravity",
            Benchmark::BarNeumannGravityPaper => "bar-neumann-gravity-0.11",
            Benchmark::BarMirrored => "bar-mirrored",
        }
    }

    /// The study defaults: (dx/dt, T). The papers' ratios (10 for the
    /// Dirichlet bar and its mirror image, 1 for the falling bar); horizons
    /// of one period (3) and of two impacts (16: one period for g = 1/9;
    /// impacts at 3.02 and 11.08 for g = 0.11).
    pub fn default_ratio_and_horizon(self) -> (f64, f64) {
        match self {
            Benchmark::BarDirichlet | Benchmark::BarMirrored => (10.0, 3.0),
            Benchmark::BarNeumannGravity | Benchmark::BarNeumannGravityPaper => (1.0, 16.0),
        }
    }

    /// The exact solution, valid on `[0, t_end]` (the falling bar is built
    /// event by event up to `t_end`; see [`BarNeumannGravity`] for its limits).
    pub fn exact(self, t_end: f64) -> Result<Box<dyn ExactSolution>, RunError> {
        let neumann =
            |r: Result<BarNeumannGravity, signorini_exact::NeumannError>| -> Result<Box<dyn ExactSolution>, RunError> { r.map(|s| Box::new(s) as Box<dyn ExactSolution>).map_err(RunError::Exact) };
        match self {
            Benchmark::BarDirichlet => Ok(Box::new(BarDirichlet)),
            Benchmark::BarMirrored => Ok(Box::new(BarMirrored)),
            Benchmark::BarNeumannGravity => neumann(BarNeumannGravity::periodic(t_end)),
            Benchmark::BarNeumannGravityPaper => neumann(BarNeumannGravity::paper(t_end)),
        }
    }

    /// The discrete problem at level `m` with a mass treatment, initial
    /// data interpolated from the exact solution at `t = 0`: `m` elements on
    /// `[0, L]`, except `bar-mirrored`, which has `2m` elements on `[0, 2]`
    /// (so `dx = 1/m`, as for `bar-dirichlet` at level `m`) and the stops
    /// `u_0 >= 0` and `u_{2m} <= 0`, in that order, with the mass treatment
    /// at both ([`Bar::mass_with_contacts`]).
    pub fn problem(self, exact: &dyn ExactSolution, m: usize, mass: BarMass) -> Result<BarProblem, RunError> {
        self.problem_with_degree(exact, m, mass, 1)
    }

    /// [`Benchmark::problem`] with Lagrange elements of degree `k` (1, 2, 3;
    /// [`Bar::with_degree`]): level `m` is `m` elements of degree `k`, the
    /// initial data interpolated at all `k m + 1` nodes; bar-mirrored's second
    /// stop is at the last node `2 k m`. Refused, naming `degree`, for another
    /// `k`; naming the mass for a treatment not defined at `k`.
    pub fn problem_with_degree(self, exact: &dyn ExactSolution, m: usize, mass: BarMass, k: usize) -> Result<BarProblem, RunError> {
        let end = match exact.far_end() {
            FarEnd::Clamped => RightEnd::Clamped,
            FarEnd::Free => RightEnd::Free,
        };
        let elements = match self {
            Benchmark::BarMirrored => m.checked_mul(2).ok_or(RunError::Invalid { field: "m", value: m as f64, allowed: "2m elements addressable" })?,
            _ => m,
        };
        let bar = Bar::new(exact.length(), elements, exact.wave_speed(), end)?.with_degree(k)?;
        let p = BarProblem::new(bar, mass, exact.gap(), exact.body_force(), |x| exact.fields(x, 0.0).u, |x| exact.fields(x, 0.0).ut)?;
        match self {
            Benchmark::BarMirrored => p.with_stops(vec![Stop::new(0, exact.gap(), f64::INFINITY), Stop::new(bar.last_node(), f64::NEG_INFINITY, -exact.gap())]),
            _ => Ok(p),
        }
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
