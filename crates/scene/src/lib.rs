//! Scene files: TOML descriptions of a bar or beam run.
//!
//! A scene read, validated and instantiated, then stepped: the impact
//! oscillator (restitution 0: Paoli–Schatzman projects the position onto
//! the stop) never passes it.
//!
//! ```
//! use signorini_scene::{Limits, SceneFile};
//!
//! let text = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.0\ndt = 1e-3\nt_end = 10.0\n[forcing]\namplitude = 1.0\nomega = 2.0\n";
//! let scene = SceneFile::parse(text)?.validate_with(&Limits::machine())?;
//! let mut sim = scene.instantiate(None)?;
//! for _ in 0..10_000 {
//!     sim.stepper.step()?;
//!     assert!(sim.stepper.displacement()[sim.tip] <= 0.2 + 1e-12);
//! }
//! // A bad value is refused naming its field and the allowed range.
//! let refused = SceneFile::parse(&text.replace("stop = 0.2", "stop = -1.0"))?.validate_with(&Limits::machine());
//! let Err(e) = refused else { panic!("a stop below the start was accepted") };
//! assert!(e.to_string().starts_with("oscillator.stop"), "{e}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ```toml
//! [bar]                        # or [beam]
//! benchmark = "bar-dirichlet"  # initial data, geometry and exact solution from a benchmark
//! elements = 80
//! mass = "mod"
//! scheme = "newmark-cn"
//! ratio = 10.0                 # dx/dt (or dt = ...)
//! t_end = 3.0
//!
//! [output]
//! every = 1                    # a series row every k steps
//! snapshots_every = 0          # u(x) every k steps (0: none)
//! plots = true
//! ```
//!
//! Without a benchmark a bar gives `length`, `wave_speed`, `far_end`
//! ("clamped" or "free"), `gap`, `body_force`, and `initial_displacement` /
//! `initial_velocity` as a number, an expression in `x` (evalexpr syntax:
//! `0.5 * (1 - x)`, `math::sin(pi * x)`; evaluated in floating point: `1/2`
//! is 0.5) or a table `[[x0, u0], [x1, u1], …]` (piecewise linear, covering
//! the whole `[0, length]`; an `[obstacle]` table the nodes it bounds). Every
//! key is checked: unknown keys are rejected, each value is range-checked
//! with the allowed range in the message, a key that would not act in this
//! scene is refused, and the integrator is built once (so a scene that
//! validates also starts).
//!
//! Several contacts (bar or beam): a list of point stops and/or bounds at
//! every node replace the default contact (the bar's obstacle at x = 0 with
//! `gap`, the beam's tip stops `stops = [g1, g2]`, which are then refused):
//!
//! ```toml
//! [[stop]]            # one table per stop, in contact order
//! x = 0.0             # a mesh node (to 1e-9·L)
//! lo = 0.0            # lower bound (optional; -inf: none)
//! hi = 0.05           # upper bound (optional; at least one finite bound)
//! restitution = 0.5   # ps / moreau-jean (bar), projection (beam) only
//! stiffness = 1e3     # penalty only (bar: scaled units; beam: N/m)
//!
//! [obstacle]          # lo(x) <= u(x) <= hi(x) at every unknown node
//! lo = "-0.1"         # number, expression in x or table (-inf: none)
//! hi = 0.1
//! ```
//!
//! A node with both a stop and the obstacle gets the intersection of their
//! bounds. Contact order (the series' `u_c<i>` columns): the stops as
//! listed, then the obstacle's other nodes by increasing x.
//!
//! A reduced model (docs/theory.md §2.5) in `[bar]` or `[beam]`:
//! `reduce = { modes = 8 }` keeps the 8 lowest fixed-interface modes,
//! `reduce = { cutoff_hz = 200.0 }` every mode up to 200 Hz; the contacts
//! stay physical and massless (the bar needs a massless-node mass: mod,
//! mod1-3, transfer, singular; the beam's are made massless by the method).
//! The full field is reconstructed for the outputs.
//!
//! The impact oscillator is a third kind of scene, with its load:
//!
//! ```toml
//! [oscillator]        # m x'' + c x' + k x = F(t), x <= stop, c = 2 ζ sqrt(k m)
//! mass = 1.0
//! stiffness = 1.0
//! damping_ratio = 0.05
//! stop = 0.2
//! restitution = 0.8
//! dt = 1e-3
//! t_end = 100.0
//! [forcing]           # F cos(Ω t) by default
//! amplitude = 1.0
//! omega = 2.0
//! ```
//!
//! Excitations (`[forcing]`, the beam's `[support]`, a `[load]` on a bar or a
//! beam) take any time profile: [`crate::excitation`]. `[output]` may ask for
//! `impacts`, `poincare`, `summary` after a `transient` (forcing periods).
//!
//! A validated [`Scene`] is turned into a running simulation one way for
//! every front end: [`Scene::instantiate`].

pub mod excitation;
mod facts;
mod instantiate;
pub mod presets;
mod report;

pub use facts::{ExactCurve, Facts, Kind, Norms, Plot, SnapshotNodes};
pub use instantiate::{BuildError, Lift, Reads, Ready, Simulation};
pub use report::{check_report, energy_warning, event_probe, free_space, io_reason, output_estimate, sig12, sig6, CheckReport, EventProbe, ProbeEnd};

use crate::excitation::Excitation;
use crate::excitation::{ExcitationToml, Table};
use serde::Deserialize;
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_reduce::{Keep, ReduceError};
use signorini_run::beam::{BeamExcitation, BeamScene, BeamSetup, PenaltyUnits, Pipe};
use signorini_run::oscillator::Oscillator;
use signorini_run::text::{num, tidy_numbers};
use signorini_run::{BarProblem, Benchmark, RunConfig, RunError, Stop};
use signorini_schemes::TimeProfile;
use signorini_schemes::{families_with, SchemeError, SchemeSpec};
use std::fmt;

/// A scene error: which field, what is wrong, what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The TOML itself (message includes line and column when the error
    /// comes from the scene's text).
    #[error("scene file: {0}")]
    Toml(#[source] toml::de::Error),
    /// A value out of its range or inconsistent with others.
    #[error("{field}: {message}")]
    Field {
        /// Dotted path of the field (`bar.dt`).
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

/// A field's error; very large and very small numbers in the message get
/// an exponent ([`tidy_numbers`]).
pub fn field(f: &str, m: impl fmt::Display) -> SceneError {
    SceneError::Field { field: f.to_string(), message: tidy_numbers(&m.to_string()) }
}

/// The whole scene file: one of `[bar]`, `[beam]` or `[oscillator]`, and
/// the tables that go with it.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// A P1/P2/P3 bar hitting an obstacle.
    pub bar: Option<BarToml>,
    /// The pipe between two stops of the beam paper.
    pub beam: Option<BeamToml>,
    /// What a run writes.
    #[serde(default)]
    pub output: OutputToml,
    /// `[[stop]]`: point stops at mesh nodes (replace the default contact).
    #[serde(default)]
    pub stop: Vec<StopToml>,
    /// `[obstacle]`: bounds at every unknown node's displacement.
    pub obstacle: Option<ObstacleToml>,
    /// A one-degree-of-freedom impact oscillator.
    pub oscillator: Option<OscillatorToml>,
    /// `[forcing]`: the oscillator's load `F cos(Ω t)` (or another profile).
    pub forcing: Option<ExcitationToml>,
    /// `[support]`: the beam's support motion φ(t).
    pub support: Option<ExcitationToml>,
    /// `[load]`: a time-dependent distributed or nodal load (bar, beam).
    pub load: Option<ExcitationToml>,
    /// The scene file's folder (for files the scene names); not a key.
    #[serde(skip)]
    pub base: Option<std::path::PathBuf>,
}

/// `[oscillator]`: `m x'' + c x' + k x = F(t)`, `x <= stop`, `c = 2 ζ sqrt(k m)`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OscillatorToml {
    /// Mass m (> 0).
    pub mass: f64,
    /// Stiffness k (>= 0).
    pub stiffness: f64,
    /// Damping ratio ζ (>= 0; default 0).
    pub damping_ratio: Option<f64>,
    /// The stop: x <= stop.
    pub stop: f64,
    /// Restitution r in [0, 1] (default 0): the e of the default scheme, and
    /// of a scheme written without its e (`event-driven`); with a scheme
    /// that states its e (`ps(0.5)`) it may only repeat it.
    pub restitution: Option<f64>,
    /// x(0) (default 0).
    pub initial_displacement: Option<f64>,
    /// x'(0) (default 0).
    pub initial_velocity: Option<f64>,
    /// Time step.
    pub dt: f64,
    /// Horizon.
    pub t_end: f64,
    /// Scheme: any scheme with a massive contact node and damping (default
    /// `ps(r, 0.25)`: Paoli–Schatzman with e = restitution).
    pub scheme: Option<String>,
}

/// `[[stop]]`: a point stop `lo <= u(x) <= hi` at a mesh node.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StopToml {
    /// Position: a mesh node, to a relative 1e-9 of the length.
    pub x: f64,
    /// Lower bound (`-inf`: none; default -inf). At least one of `lo`, `hi`
    /// is finite, and lo <= hi.
    pub lo: Option<f64>,
    /// Upper bound (`+inf`: none; default +inf).
    pub hi: Option<f64>,
    /// Restitution coefficient of this stop, in [0, 1] (schemes with a
    /// restitution law only; default: the scheme's e).
    pub restitution: Option<f64>,
    /// Penalty stiffness of this stop, > 0 (penalty contact only; default:
    /// the scheme's). Bar: in the scaled equation's units; beam: N/m.
    pub stiffness: Option<f64>,
}

/// `[obstacle]`: `lo(x) <= u(x) <= hi(x)` at every unknown node.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObstacleToml {
    /// Lower bound: a number (`-inf`: none), an expression in `x` or a table
    /// `[[x, v], …]` covering every bounded node (absent: no lower bound).
    pub lo: Option<FieldToml>,
    /// Upper bound: a number (`+inf`: none), an expression in `x` or a table
    /// `[[x, v], …]` covering every bounded node (absent: no upper bound).
    pub hi: Option<FieldToml>,
}

/// `[bar]`: a P1/P2/P3 bar hitting an obstacle (one of `[bar]`, `[beam]`,
/// `[oscillator]` per scene).
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BarToml {
    /// A built-in problem with an exact solution: `bar-dirichlet`,
    /// `bar-neumann-gravity`, `bar-neumann-gravity-0.11` or `bar-mirrored`
    /// (the geometry and initial-data keys are then refused). Absent: a user
    /// bar.
    pub benchmark: Option<String>,
    /// Length L (> 0; default 1).
    pub length: Option<f64>,
    /// Wave speed c (> 0; default 1).
    pub wave_speed: Option<f64>,
    /// `"clamped"` or `"free"` (default `"clamped"`).
    pub far_end: Option<String>,
    /// Obstacle position g at x = 0 (default 0; refused with `[[stop]]` /
    /// `[obstacle]`).
    pub gap: Option<f64>,
    /// Uniform body force f (default 0).
    pub body_force: Option<f64>,
    /// u0(x): a number, an expression in `x`, or a table `[[x, u], …]`
    /// (piecewise linear, covering [0, L]); default 0.
    pub initial_displacement: Option<FieldToml>,
    /// v0(x): a number, an expression in `x`, or a table `[[x, v], …]`
    /// (piecewise linear, covering [0, L]); default 0.
    pub initial_velocity: Option<FieldToml>,
    /// Elements m (>= 2).
    pub elements: usize,
    /// Element degree k (1, 2, 3: Lagrange P1, P2, P3; default 1); the
    /// `k m + 1` nodes are at `x = i L/(k m)`. Degrees 2 and 3 take the
    /// masses std, lumped and mod.
    pub degree: Option<usize>,
    /// Mass treatment: `std`, `lumped`, `mod`, `mod1`, `mod2`, `mod3`,
    /// `transfer` or `singular` (docs/schemes.md, "Mass treatments").
    #[serde(default = "default_mass")]
    pub mass: String,
    /// Scheme: a preset, `hybrid`, `reduced-cn`, `newmark(B,G)`, `theta(T)`,
    /// `ps(E[,B])`, … (`signorini list`; docs/schemes.md).
    #[serde(default = "default_scheme")]
    pub scheme: String,
    /// Time step (give `dt` or `ratio`, one of them).
    pub dt: Option<f64>,
    /// dx/dt, the alternative to `dt`.
    pub ratio: Option<f64>,
    /// Horizon T, a whole number of steps of dt.
    pub t_end: Option<f64>,
    /// A reduced model (docs/theory.md §2.5): `{ modes = r }` or
    /// `{ cutoff_hz = f }`, with massless contacts (mod-type masses).
    pub reduce: Option<ReduceToml>,
}

/// `reduce = { modes = r }` or `reduce = { cutoff_hz = f }` in `[bar]` or
/// `[beam]`: the massless-boundary reduction (docs/theory.md §2.5), keeping
/// the `r` lowest fixed-interface modes or every mode up to `f` Hz.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ReduceToml {
    /// The number of modes kept (1 ..= the unknowns less the contacts).
    pub modes: Option<usize>,
    /// The frequency cutoff in Hz (at or above the first mode's).
    pub cutoff_hz: Option<f64>,
}

impl ReduceToml {
    /// Which modes to keep; `table` is `bar` or `beam` (for the field names).
    fn keep(&self, table: &str) -> Result<Keep, SceneError> {
        match (self.modes, self.cutoff_hz) {
            (Some(r), None) => Ok(Keep::Modes(r)),
            (None, Some(f)) => Ok(Keep::CutoffHz(f)),
            (None, None) => Err(field(&format!("{table}.reduce"), "give modes = r or cutoff_hz = f")),
            (Some(_), Some(_)) => Err(field(&format!("{table}.reduce.cutoff_hz"), "give modes or cutoff_hz, not both")),
        }
    }
}

/// A reduction's error, named `<table>.reduce.<field>`.
fn reduce_error(e: RunError, table: &str) -> SceneError {
    match e {
        RunError::Reduce(ReduceError::Invalid { field: f, value, allowed }) => field(&format!("{table}.reduce.{f}"), format!("{value} is not allowed: {allowed}")),
        RunError::Reduce(e @ ReduceError::NotDefinite { .. }) => field(&format!("{table}.reduce"), e),
        e => field(table, e),
    }
}

fn default_mass() -> String {
    "std".into()
}
fn default_scheme() -> String {
    "newmark-cn".into()
}

/// An initial field: a number, an expression in `x`, or a table.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum FieldToml {
    /// Constant.
    Number(f64),
    /// Expression in `x`.
    Expr(String),
    /// Piecewise-linear table of `[x, value]` pairs, x increasing.
    Table(#[serde(deserialize_with = "pairs")] Vec<[f64; 2]>),
}

/// Exactly two numbers (serde's fixed-size arrays would drop extra items).
fn exact_pair<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let v: Vec<f64> = Deserialize::deserialize(d)?;
    <[f64; 2]>::try_from(v.as_slice()).map_err(|_| serde::de::Error::custom(format!("{} numbers are not allowed: exactly two, [a, b]", v.len())))
}

/// `[[x, u], …]`, each pair exactly two numbers.
fn pairs<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
    #[derive(Deserialize)]
    struct Pair(#[serde(deserialize_with = "exact_pair")] [f64; 2]);
    let v: Vec<Pair> = Deserialize::deserialize(d)?;
    Ok(v.into_iter().map(|p| p.0).collect())
}

/// An optional pair of exactly two numbers.
fn optional_pair<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
    exact_pair(d).map(Some)
}

/// `[beam]`: the pipe between two stops of the beam paper.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BeamToml {
    /// A paper scene (`"fig2"` … `"fig8"`) to start from; the other keys
    /// override it. Absent: J = 19, dt = 1e-5 s, T = 2 s, projection with
    /// β = 1/2.
    pub scene: Option<String>,
    /// Elements J (>= 1; default: the scene's, 19).
    pub elements: Option<usize>,
    /// Time step (s; default: the scene's).
    pub dt: Option<f64>,
    /// Horizon (s; default: the scene's).
    pub t_end: Option<f64>,
    /// `"projection"` (the registry's `ps(0,β)`: the β-scheme with the
    /// exact projection) or `"penalty"` (`penalty-cn`, Newmark β = 1/4, with
    /// a spring of `penalty_stiffness` N/m) (default: the scene's).
    pub contact: Option<String>,
    /// β of the β-scheme, in [0, 1/2] (projection only; default: the
    /// scene's).
    pub beta: Option<f64>,
    /// Penalty spring stiffness (N/m, > 0; penalty only; default: the
    /// scene's, 1e8 in fig5–fig7).
    pub penalty_stiffness: Option<f64>,
    /// A scheme of the registry instead of `contact` (any that takes the
    /// beam's structure: `signorini list`); replaces `contact`, `beta` and
    /// `penalty_stiffness`.
    pub scheme: Option<String>,
    /// Lower and upper stops `[g1, g2]` (m), g1 < g2 (default: the paper's
    /// ±0.1 m; refused with `[[stop]]` / `[obstacle]`).
    #[serde(default, deserialize_with = "optional_pair")]
    pub stops: Option<[f64; 2]>,
    /// Support amplitude (m) and angular frequency (rad/s), `[amplitude,
    /// omega]`; or a `[support]` table with any profile (default: the
    /// paper's 0.2 sin(10 t) m).
    #[serde(default, deserialize_with = "optional_pair")]
    pub support: Option<[f64; 2]>,
    /// `true`: run a conditionally stable scheme (the β-scheme with β < 1/4,
    /// or a `scheme` with a stability limit) beyond its exact stability
    /// limit anyway (refused with an unconditionally stable `scheme`).
    #[serde(default)]
    pub force: bool,
    /// A reduced model (docs/theory.md §2.5): `{ modes = r }` or
    /// `{ cutoff_hz = f }` (β >= 1/4).
    pub reduce: Option<ReduceToml>,
}

/// `[output]`: what a run writes.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OutputToml {
    /// A series row every `every` steps (>= 1).
    #[serde(default = "one")]
    pub every: usize,
    /// A snapshot of u(x) every k steps (0: none).
    #[serde(default)]
    pub snapshots_every: usize,
    /// Write SVG plots.
    #[serde(default = "yes")]
    pub plots: bool,
    /// `impacts.csv` (every impact) and `impact_map.svg`.
    #[serde(default)]
    pub impacts: bool,
    /// `poincare.csv`: stroboscopic samples at the forcing period after the
    /// transient, and `poincare.svg` (needs a periodic forcing).
    #[serde(default)]
    pub poincare: bool,
    /// `summary.csv`: impact statistics, RMS contact force, max |tip|, the
    /// response period (over the record window).
    #[serde(default)]
    pub summary: bool,
    /// Forcing periods before the record window of poincare / summary
    /// (default 0; without a periodic forcing: seconds).
    #[serde(default)]
    pub transient: f64,
    /// Relative tolerance of the response-period test in `summary.csv`, in
    /// (0, 1) (default 1e-3).
    pub period_tol: Option<f64>,
    /// Warn (once, on stderr) when the discrete energy exceeds its budget
    /// (initial energy + work of the loads and supports − dissipation, as
    /// the scheme's identity defines it) by more than this factor; finite
    /// and > 1 (default 2). The summary prints the largest E/budget.
    /// Refused in sweeps, which do not watch the energy.
    pub energy_warn: Option<f64>,
}

/// The default of `[output] energy_warn`.
pub const DEFAULT_ENERGY_WARN: f64 = 2.0;

fn one() -> usize {
    1
}
fn yes() -> bool {
    true
}

impl Default for OutputToml {
    fn default() -> Self {
        Self { every: 1, snapshots_every: 0, plots: true, impacts: false, poincare: false, summary: false, transient: 0.0, period_tol: None, energy_warn: None }
    }
}

/// A validated bar scene.
pub struct BarRun {
    /// The problem.
    pub problem: BarProblem,
    /// The benchmark, if the scene uses one (exact solution available).
    pub benchmark: Option<Benchmark>,
    /// The scheme.
    pub scheme: SchemeSpec,
    /// Time step.
    pub dt: f64,
    /// Horizon.
    pub t_end: f64,
    /// The contacts of `[[stop]]` / `[obstacle]` (`None`: the obstacle at
    /// x = 0); the problem holds them as its stops.
    pub contacts: Option<ContactSet>,
    /// The frequency of a periodic `[load]` (Poincaré section, phases).
    pub omega: Option<f64>,
    /// The reduced model's modes, if `reduce` is given.
    pub reduce: Option<Keep>,
    /// The validated simulation, for the first instantiation.
    pub ready: Ready,
}

/// One contact of a scene with `[[stop]]` / `[obstacle]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Site {
    /// The mesh node (bar: `0..=m`; beam: `1..=J`).
    pub node: usize,
    /// The node's position.
    pub x: f64,
    /// The `[[stop]]` entry it comes from (its index and `x` as written).
    pub stop: Option<(usize, f64)>,
    /// The obstacle's `(lo, hi)` at the node, where `[obstacle]` applies.
    pub obstacle: Option<(f64, f64)>,
    /// Whether the stop gave its own `stiffness`.
    pub own_stiffness: bool,
}

/// The contacts of a scene with `[[stop]]` / `[obstacle]`, in contact
/// order (the series' `u_c<i>` order): the stops as listed, then the
/// obstacle's other nodes by increasing x.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSet {
    /// The stops as the problem takes them (bounds intersected with the
    /// obstacle's where both apply).
    pub stops: Vec<Stop>,
    /// Where each comes from, in the same order.
    pub sites: Vec<Site>,
}

impl ContactSet {
    /// The field a library error on contact `index` belongs to:
    /// `stop.<i>.<field>`, or `obstacle.lo` / `obstacle.hi` with the node's x.
    fn field_of(&self, index: usize, what: &str) -> (String, String) {
        let Some(site) = self.sites.get(index) else {
            return ("stop".into(), String::new());
        };
        match site.stop {
            Some((i, _)) => (format!("stop.{i}.{}", if what == "node" { "x" } else { what }), String::new()),
            None => (format!("obstacle.{}", if what == "hi" { "hi" } else { "lo" }), format!(" (at the node x = {})", site.x)),
        }
    }

    /// One line per stop and a summary of the obstacle's nodes, for `check`.
    pub fn describe(&self) -> String {
        let bound = |v: f64| {
            if v.is_finite() {
                format!("{v}")
            } else {
                "none".into()
            }
        };
        let mut s = format!("contacts: {} (series columns u_c<i>, lambda_<i>, active_<i> in this order)", self.sites.len());
        let mut obstacle_only = Vec::new();
        for (i, (site, st)) in self.sites.iter().zip(&self.stops).enumerate() {
            match site.stop {
                Some((j, x)) => {
                    s += &format!(
                        "\n  {i}: stop.{j} x = {x} snapped to node {} (x = {}): lo = {}, hi = {}{}",
                        site.node,
                        site.x,
                        bound(st.lo),
                        bound(st.hi),
                        if site.obstacle.is_some() { " (intersected with [obstacle])" } else { "" }
                    )
                }
                None => obstacle_only.push((i, site, st)),
            }
        }
        if let (Some(first), Some(last)) = (obstacle_only.first(), obstacle_only.last()) {
            let (lo_min, lo_max) = obstacle_only.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.2.lo), b.max(p.2.lo)));
            let (hi_min, hi_max) = obstacle_only.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.2.hi), b.max(p.2.hi)));
            s += &format!(
                "\n  {}..={}: [obstacle] at {} nodes, x = {} … {}: lo in [{}, {}], hi in [{}, {}]",
                first.0,
                last.0,
                obstacle_only.len(),
                first.1.x,
                last.1.x,
                bound(lo_min),
                bound(lo_max),
                bound(hi_min),
                bound(hi_max)
            );
        }
        s
    }
}

/// A validated scene.
// One scene per run or sweep value: the size of the beam's variant does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Scene {
    /// A bar.
    Bar(Box<BarRun>),
    /// The one-degree-of-freedom impact oscillator.
    Oscillator {
        /// Its data (load included).
        osc: Oscillator,
        /// The scheme.
        scheme: SchemeSpec,
        /// Time step.
        dt: f64,
        /// Horizon.
        t_end: f64,
        /// The forcing frequency (Poincaré section, impact phases).
        omega: Option<f64>,
        /// The validated simulation, for the first instantiation.
        ready: Ready,
    },
    /// A beam between stops.
    Beam {
        /// The pipe.
        pipe: Pipe,
        /// The run.
        scene: BeamScene,
        /// Forced beyond the stability limit.
        force: bool,
        /// The contacts of `[[stop]]` / `[obstacle]` (`None`: the tip's
        /// two stops).
        contacts: Option<ContactSet>,
        /// `[support]` beyond a sine, `[load]`.
        excitation: BeamExcitation,
        /// The reduced model's modes, if `reduce` is given.
        reduce: Option<Keep>,
        /// The forcing frequency (the support's, or `omega` of `[support]` /
        /// `[load]`): Poincaré section and impact phases.
        omega: Option<f64>,
        /// The validated simulation, for the first instantiation.
        ready: Ready,
    },
}

impl Scene {
    /// A beam scene's [`BeamSetup`] (pipe, run, contacts, excitation, force,
    /// reduction): what every front end builds the beam from; `None` for
    /// other scenes.
    pub fn beam_setup(&self) -> Option<BeamSetup> {
        let Scene::Beam { pipe, scene, force, contacts, excitation, reduce, .. } = self else { return None };
        let mut s = BeamSetup::new(*pipe, *scene).with_excitation(excitation.clone()).forced(*force);
        s.stops = contacts.as_ref().map(|c| c.stops.clone());
        s.reduce = *reduce;
        Some(s)
    }
}

impl OutputToml {
    /// Where the record window starts (s): the `transient` is in forcing
    /// periods of `omega`, in seconds without a forcing.
    pub fn record_from(&self, omega: Option<f64>) -> f64 {
        omega.map_or(self.transient, |w| self.transient * std::f64::consts::TAU / w)
    }

    /// The analysis window against the scene's clock: `poincare` needs a
    /// periodic forcing, and the record window after the `transient` must
    /// not be empty (it starts before the horizon).
    fn check_window(&self, scene: &Scene) -> Result<(), SceneError> {
        let (omega, t_end) = scene.forcing_and_horizon();
        if self.poincare && omega.is_none() {
            return Err(field("output.poincare", "needs a periodic forcing (the oscillator's [forcing], a beam's support): remove it"));
        }
        if !(self.poincare || self.summary || self.impacts) {
            return Ok(());
        }
        let from = self.record_from(omega);
        if from >= t_end {
            let (unit, most) = omega.map_or(("s", t_end), |w| ("forcing periods", t_end * w / std::f64::consts::TAU));
            return Err(field(
                "output.transient",
                format!("{} {unit} ({from} s) is not allowed: it reaches the horizon t_end = {t_end} s, so nothing would be recorded; allowed: [0, {most}) {unit}", self.transient),
            ));
        }
        Ok(())
    }
}

impl Scene {
    /// The forcing frequency `Ω` (`None` without a periodic forcing) and
    /// the horizon `t_end`.
    pub fn forcing_and_horizon(&self) -> (Option<f64>, f64) {
        let f = self.facts();
        (f.omega, f.t_end)
    }

    /// What a sweep needs of the scene's clock: the forcing frequency `Ω`
    /// (the Poincaré section and impact phases), the time step, and the key
    /// of its horizon (which a sweep sets to `transient + record` forcing
    /// periods). `None` without a periodic forcing.
    pub fn sweep_clock(&self) -> Option<(f64, f64, &'static str)> {
        let f = self.facts();
        f.omega.map(|w| (w, f.dt, f.t_end_key))
    }
}

/// What a scene must fit in, checked before anything large is allocated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Memory a run may use (bytes). Default: the machine's available
    /// memory (`MemAvailable` of /proc/meminfo; 8 GiB where unknown).
    pub max_memory: f64,
}

impl Limits {
    /// The machine's available memory.
    pub fn machine() -> Self {
        Self { max_memory: mem_available().unwrap_or(8.0 * GIB) }
    }
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

fn mem_available() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// Bytes a run needs per element, measured (peak resident set of
/// `signorini run` at m = 2e6 and J = 1e6: 228 and 582 bytes per element)
/// with a margin for the schemes that keep more vectors.
const BYTES_PER_BAR_ELEMENT: f64 = 320.0;
const BYTES_PER_BEAM_ELEMENT: f64 = 800.0;
/// What any run needs besides its mesh (plot buffers, the exact solution).
const BYTES_BASE: f64 = 32.0 * 1024.0 * 1024.0;

/// The memory (bytes) a bar (`beam = false`) or beam run on `elements`
/// elements needs, estimated before allocating it.
pub fn memory_estimate(elements: usize, beam: bool) -> f64 {
    BYTES_BASE + elements as f64 * if beam { BYTES_PER_BEAM_ELEMENT } else { BYTES_PER_BAR_ELEMENT }
}

/// The memory (bytes) the multi-contact solve holds for `k > 1` contacts
/// on `unknowns` unknowns: the influence columns `A⁻¹ e_c` (`8 k n`) and
/// the Delassus matrix with its Cholesky storage (`16 k²`); 0 for one
/// contact (its column is in the per-element estimate).
pub fn contact_memory(k: usize, unknowns: usize) -> f64 {
    if k <= 1 {
        return 0.0;
    }
    let k = k as f64;
    8.0 * k * unknowns as f64 + 16.0 * k * k
}

/// Refuses `k` contacts on `unknowns` unknowns whose solve would not fit
/// beside the mesh, naming `name`.
fn contacts_fit(name: &str, k: usize, unknowns: usize, elements: usize, beam: bool, limits: &Limits) -> Result<(), SceneError> {
    let mesh = memory_estimate(elements, beam);
    let solve = contact_memory(k, unknowns);
    if mesh + solve > limits.max_memory {
        let room = (limits.max_memory - mesh).max(0.0);
        let n = unknowns as f64;
        // The largest k with 8 k n + 16 k² <= room.
        let most = ((-8.0 * n + (64.0 * n * n + 64.0 * room).sqrt()) / 32.0).floor().max(0.0);
        return Err(field(
            name,
            format!(
                "{k} contacts on {unknowns} unknowns need about {} for the multi-contact solve (8·k·n bytes of influence columns A⁻¹e_c, 16·k² of the Delassus matrix and its factor) besides {} for the mesh, beyond the cap of {} (the machine's available memory unless --max-memory is given): at most {most:.0} contacts fit at this mesh; allowed: fewer contacts or elements",
                bytes(solve),
                bytes(mesh),
                bytes(limits.max_memory)
            ),
        ));
    }
    Ok(())
}

/// Human-readable bytes.
pub fn bytes(b: f64) -> String {
    match b {
        b if b >= 1e12 => format!("{:.1} TB", b / 1e12),
        b if b >= 1e9 => format!("{:.1} GB", b / 1e9),
        b if b >= 1e6 => format!("{:.1} MB", b / 1e6),
        b if b >= 1e3 => format!("{:.1} kB", b / 1e3),
        b => format!("{b:.0} B"),
    }
}

fn fits(name: &str, elements: usize, beam: bool, limits: &Limits) -> Result<(), SceneError> {
    let need = memory_estimate(elements, beam);
    if need > limits.max_memory {
        let most = ((limits.max_memory - BYTES_BASE) / (need - BYTES_BASE) * elements as f64).max(0.0).floor();
        return Err(field(
            name,
            format!(
                "{elements} elements need about {} of memory, beyond the cap of {} (the machine's available memory unless --max-memory is given): at most {most:.0} elements fit",
                bytes(need),
                bytes(limits.max_memory)
            ),
        ));
    }
    Ok(())
}

pub(crate) fn positive(name: &str, v: f64) -> Result<f64, SceneError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(field(name, format!("{v} is not allowed: finite and > 0")))
    }
}

pub(crate) fn finite(name: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(field(name, format!("{v} is not allowed: a finite number")))
    }
}

/// The expression with every integer literal written as a real (`1` →
/// `1.0`), so that it evaluates in floating point: `1/2` is 0.5, not the
/// integer division's 0 (evalexpr types a literal without a dot or an
/// exponent as an integer). Digits inside identifiers (`x2`) are left alone.
pub fn real_literals(expr: &str) -> String {
    let b = expr.as_bytes();
    let mut out = String::with_capacity(expr.len() + 8);
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let in_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.');
        if c.is_ascii_digit() && !in_word {
            let start = i;
            let mut real = false;
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            if i < b.len() && b[i] == b'.' {
                real = true;
                i += 1;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
            }
            if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                let mut j = i + 1;
                if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                    j += 1;
                }
                if j < b.len() && b[j].is_ascii_digit() {
                    real = true;
                    i = j;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            out.push_str(&expr[start..i]);
            if !real {
                out.push_str(".0");
            }
        } else {
            // Copy one whole UTF-8 character.
            let len = expr[i..].chars().next().map_or(1, char::len_utf8);
            out.push_str(&expr[i..i + len]);
            i += len;
        }
    }
    out
}

/// The longest expression accepted (characters).
pub const MAX_EXPRESSION_CHARS: usize = 1000;

/// An initial field as a function of x.
pub enum InitialField {
    /// Constant.
    Number(f64),
    /// Compiled expression.
    Expr(evalexpr::Node<evalexpr::DefaultNumericTypes>),
    /// Table.
    Table(Vec<[f64; 2]>),
}

impl InitialField {
    fn compile(name: &str, f: &FieldToml) -> Result<Self, SceneError> {
        Ok(match f {
            FieldToml::Number(v) => InitialField::Number(finite(name, *v)?),
            FieldToml::Expr(s) => {
                // evalexpr parses and evaluates recursively: a cap on the
                // length keeps the nesting far from the stack's limit.
                if s.chars().count() > MAX_EXPRESSION_CHARS {
                    return Err(field(name, format!("an expression of {} characters is not allowed: at most {MAX_EXPRESSION_CHARS} (use a table [[x, u], …] for long data)", s.chars().count())));
                }
                let s = &real_literals(s);
                let tree = evalexpr::build_operator_tree(s).map_err(|e| field(name, format!("expression {s:?}: {e} (allowed: a number in x, e.g. \"0.5 * (1 - x)\" or \"math::sin(pi * x)\")")))?;
                // Evaluate once so that errors surface here with the field's name.
                let mut ctx = evalexpr::HashMapContext::<evalexpr::DefaultNumericTypes>::new();
                use evalexpr::ContextWithMutableVariables;
                for (k, v) in [("x", 0.0), ("pi", std::f64::consts::PI)] {
                    ctx.set_value(k.into(), evalexpr::Value::Float(v)).map_err(|e| field(name, e))?;
                }
                tree.eval_number_with_context(&ctx).map_err(|e| field(name, format!("expression {s:?} (a number in x, e.g. \"0.5 * (1 - x)\" or \"math::sin(pi * x)\"): {e}")))?;
                InitialField::Expr(tree)
            }
            FieldToml::Table(t) => {
                if t.is_empty() || t.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) || t.windows(2).any(|w| w[1][0] <= w[0][0]) {
                    return Err(field(name, "a table needs at least one [x, value] pair, finite values and strictly increasing x"));
                }
                InitialField::Table(t.clone())
            }
        })
    }

    /// Refuses a table whose x range does not cover `[a, b]` (to within
    /// [`NODE_TOLERANCE`] of the span's end): outside its range a table would
    /// otherwise be extended by its end values without a word.
    fn check_covers(&self, name: &str, a: f64, b: f64) -> Result<(), SceneError> {
        let InitialField::Table(t) = self else { return Ok(()) };
        let tol = NODE_TOLERANCE * b.abs().max(a.abs());
        let (first, last) = (t[0][0], t[t.len() - 1][0]);
        if first > a + tol || last < b - tol {
            return Err(field(
                name,
                format!("a table on [{}, {}] is not allowed: its x must cover the whole [{}, {}] (first x <= {}, last x >= {})", num(first), num(last), num(a), num(b), num(a), num(b)),
            ));
        }
        Ok(())
    }

    /// The value at x (NaN if an expression fails to evaluate, caught by the problem's finiteness check).
    pub fn eval(&self, x: f64) -> f64 {
        match self {
            InitialField::Number(v) => *v,
            InitialField::Expr(tree) => {
                let mut ctx = evalexpr::HashMapContext::<evalexpr::DefaultNumericTypes>::new();
                use evalexpr::ContextWithMutableVariables;
                if ctx.set_value("x".into(), evalexpr::Value::Float(x)).is_err() || ctx.set_value("pi".into(), evalexpr::Value::Float(std::f64::consts::PI)).is_err() {
                    return f64::NAN;
                }
                tree.eval_number_with_context(&ctx).unwrap_or(f64::NAN)
            }
            InitialField::Table(t) => {
                if x <= t[0][0] {
                    return t[0][1];
                }
                for w in t.windows(2) {
                    if x <= w[1][0] {
                        let s = (x - w[0][0]) / (w[1][0] - w[0][0]);
                        return w[0][1] + s * (w[1][1] - w[0][1]);
                    }
                }
                t[t.len() - 1][1]
            }
        }
    }
}

/// The relative tolerance (of the length) within which a stop's `x` is a node.
pub const NODE_TOLERANCE: f64 = 1e-9;

/// The nodes a scene's contacts may use.
struct NodeMesh<'a> {
    /// Length of the bar or beam.
    length: f64,
    /// Elements (nodes `0..=elements`, at `x(i)`; for a P`k` bar, `k m`:
    /// its nodes are those of a P1 bar of `k m` elements).
    elements: usize,
    /// The nodes that are unknowns (a clamped node cannot be a contact).
    unknown: std::ops::RangeInclusive<usize>,
    /// Node positions.
    x: &'a dyn Fn(usize) -> f64,
}

impl NodeMesh<'_> {
    /// The node at `x` (within `NODE_TOLERANCE·L`) that is an unknown;
    /// errors name `name` and give the nearest nodes or the allowed ones.
    fn node(&self, name: &str, x: f64) -> Result<usize, SceneError> {
        let (l, m) = (self.length, self.elements);
        let tol = NODE_TOLERANCE * l;
        let h = l / m as f64;
        if !x.is_finite() || x < -tol || x > l + tol {
            return Err(field(name, format!("{x} is not allowed: the position of a mesh node, in [0, {l}]")));
        }
        let node = ((x / h).round().max(0.0) as usize).min(m);
        if (x - (self.x)(node)).abs() > tol {
            let below = ((x / h).floor().max(0.0) as usize).min(m);
            let above = (below + 1).min(m);
            return Err(field(
                name,
                format!(
                    "{x} is not allowed: a mesh node, within {NODE_TOLERANCE:e}·L = {tol:e} (nodes x = i L/{m}); the nearest nodes are x = {} (node {below}) and x = {} (node {above})",
                    (self.x)(below),
                    (self.x)(above)
                ),
            ));
        }
        let (first, last) = (*self.unknown.start(), *self.unknown.end());
        if !self.unknown.contains(&node) {
            return Err(field(
                name,
                format!("{x} is not allowed: node {node} is clamped (no displacement to bound); allowed: the nodes {first}..={last}, x = {} to {}", (self.x)(first), (self.x)(last)),
            ));
        }
        Ok(node)
    }
}

/// Which per-stop keys act with the scene's scheme: `Err(why)` refuses the key.
struct KeyRules {
    restitution: Result<(), String>,
    stiffness: Result<(), String>,
}

/// One bound of `[obstacle]`, `None` where it is absent or is the number
/// `none` (`-inf` for lo, `+inf` for hi).
fn obstacle_bound(name: &str, f: Option<&FieldToml>, none: f64) -> Result<Option<InitialField>, SceneError> {
    match f {
        None => Ok(None),
        Some(FieldToml::Number(v)) if *v == none => Ok(None),
        Some(FieldToml::Number(v)) if !v.is_finite() => Err(field(name, format!("{v} is not allowed: a finite number, an expression or table in x, or {none} (no bound)"))),
        Some(f) => InitialField::compile(name, f).map(Some),
    }
}

/// The contacts of `[[stop]]` and `[obstacle]` on `mesh`, checked against
/// the initial displacement `u0(node)`: every error names its field
/// (`stop.<i>.<key>`, `obstacle.lo`/`obstacle.hi` with the node's x).
fn contact_set(stops: &[StopToml], obstacle: Option<&ObstacleToml>, mesh: &NodeMesh<'_>, u0: &dyn Fn(usize) -> f64, rules: &KeyRules) -> Result<ContactSet, SceneError> {
    let (first, last) = (*mesh.unknown.start(), *mesh.unknown.end());
    let mut sites: Vec<Site> = Vec::with_capacity(stops.len());
    let mut list: Vec<Stop> = Vec::with_capacity(stops.len());
    for (i, st) in stops.iter().enumerate() {
        let key = |k: &str| format!("stop.{i}.{k}");
        let x = st.x;
        let node = mesh.node(&key("x"), x)?;
        if let Some(p) = sites.iter().position(|s| s.node == node) {
            return Err(field(&key("x"), format!("{x} is not allowed: it snaps to node {node}, where stop.{p} is already; allowed: one stop per node (give lo and hi in one stop)")));
        }
        let lo = match st.lo {
            None => f64::NEG_INFINITY,
            Some(v) if v.is_nan() || v == f64::INFINITY => return Err(field(&key("lo"), format!("{v} is not allowed: a number, or -inf (no lower bound)"))),
            Some(v) => v,
        };
        let hi = match st.hi {
            None => f64::INFINITY,
            Some(v) if v.is_nan() || v == f64::NEG_INFINITY => return Err(field(&key("hi"), format!("{v} is not allowed: a number, or +inf (no upper bound)"))),
            Some(v) => v,
        };
        if !lo.is_finite() && !hi.is_finite() {
            return match (st.lo, st.hi) {
                (Some(v), _) => Err(field(&key("lo"), format!("{v} without a finite hi is not allowed: at least one finite bound (a finite lo, or a finite hi)"))),
                (None, Some(v)) => Err(field(&key("hi"), format!("{v} without a finite lo is not allowed: at least one finite bound (a finite hi, or a finite lo)"))),
                (None, None) => Err(field(&key("lo"), "give lo and/or hi: a stop needs at least one finite bound")),
            };
        }
        if lo > hi {
            return Err(field(&key("lo"), format!("{lo} is not allowed: lo <= hi = {hi}")));
        }
        if let Some(e) = st.restitution {
            if let Err(why) = &rules.restitution {
                return Err(field(&key("restitution"), why));
            }
            if !(0.0..=1.0).contains(&e) {
                return Err(field(&key("restitution"), format!("{e} is not allowed: [0, 1]")));
            }
        }
        if let Some(k) = st.stiffness {
            if let Err(why) = &rules.stiffness {
                return Err(field(&key("stiffness"), why));
            }
            if !(k > 0.0 && k.is_finite()) {
                return Err(field(&key("stiffness"), format!("{k} is not allowed: finite and > 0")));
            }
        }
        sites.push(Site { node, x: (mesh.x)(node), stop: Some((i, x)), obstacle: None, own_stiffness: st.stiffness.is_some() });
        list.push(Stop { node, lo, hi, restitution: st.restitution, stiffness: st.stiffness });
    }
    if let Some(ob) = obstacle {
        if ob.lo.is_none() && ob.hi.is_none() {
            return Err(field("obstacle", "give lo and/or hi (a number, an expression in x or a table)"));
        }
        let lo_f = obstacle_bound("obstacle.lo", ob.lo.as_ref(), f64::NEG_INFINITY)?;
        let hi_f = obstacle_bound("obstacle.hi", ob.hi.as_ref(), f64::INFINITY)?;
        // A table must cover the nodes the obstacle bounds.
        for (name, f) in [("obstacle.lo", &lo_f), ("obstacle.hi", &hi_f)] {
            if let Some(f) = f {
                f.check_covers(name, (mesh.x)(first), (mesh.x)(last))?;
            }
        }
        if lo_f.is_none() && hi_f.is_none() {
            let name = if ob.lo.is_some() { "obstacle.lo" } else { "obstacle.hi" };
            return Err(field(name, "-inf / +inf alone is not a bound: give at least one finite bound (lo or hi)"));
        }
        let at = |name: &str, f: &Option<InitialField>, x: f64, none: f64| -> Result<f64, SceneError> {
            match f {
                None => Ok(none),
                Some(f) => {
                    let v = f.eval(x);
                    if v.is_finite() {
                        Ok(v)
                    } else {
                        Err(field(name, format!("{v} at the node x = {x} is not allowed: a value finite at every node (for no bound give the number {none}, not an expression)")))
                    }
                }
            }
        };
        for node in first..=last {
            let x = (mesh.x)(node);
            let lo = at("obstacle.lo", &lo_f, x, f64::NEG_INFINITY)?;
            let hi = at("obstacle.hi", &hi_f, x, f64::INFINITY)?;
            if lo > hi {
                return Err(field("obstacle.lo", format!("lo({x}) = {lo} is not allowed: lo(x) <= hi(x) = {hi} at every node")));
            }
            match sites.iter().position(|s| s.node == node) {
                Some(p) => {
                    // A stop there: the intersection of both.
                    let (st, i) = (&mut list[p], sites[p].stop.map_or(p, |s| s.0));
                    if st.lo > hi {
                        return Err(field(
                            &format!("stop.{i}.lo"),
                            format!("{} is not allowed: above obstacle.hi = {hi} at its node x = {x}; allowed: bounds that meet the obstacle's (the two are intersected)", st.lo),
                        ));
                    }
                    if st.hi < lo {
                        return Err(field(
                            &format!("stop.{i}.hi"),
                            format!("{} is not allowed: below obstacle.lo = {lo} at its node x = {x}; allowed: bounds that meet the obstacle's (the two are intersected)", st.hi),
                        ));
                    }
                    st.lo = st.lo.max(lo);
                    st.hi = st.hi.min(hi);
                    sites[p].obstacle = Some((lo, hi));
                }
                None => {
                    sites.push(Site { node, x, stop: None, obstacle: Some((lo, hi)), own_stiffness: false });
                    list.push(Stop::new(node, lo, hi));
                }
            }
        }
    }
    // The initial state inside every contact's bounds, the violated bound named.
    for (site, st) in sites.iter().zip(&list) {
        let u = u0(site.node);
        if !(st.lo <= u && u <= st.hi) {
            let (which, bound, side) = if u < st.lo { ("lo", st.lo, "below") } else { ("hi", st.hi, "above") };
            // The stop's own bound if it is the one violated, else the obstacle's.
            let own = site.stop.filter(|(i, _)| (if which == "lo" { stops[*i].lo } else { stops[*i].hi }) == Some(bound));
            let name = match own {
                Some((i, _)) => format!("stop.{i}.{which}"),
                None => format!("obstacle.{which}"),
            };
            return Err(field(
                &name,
                format!(
                    "{bound} at x = {} (node {}) is not allowed: the initial displacement u0 = {u} is {side} it; allowed: bounds the initial state satisfies, lo <= u0(x) <= hi",
                    site.x, site.node
                ),
            ));
        }
    }
    Ok(ContactSet { stops: list, sites })
}

impl SceneFile {
    /// The energy monitor's factor (`[output] energy_warn`, default
    /// [`DEFAULT_ENERGY_WARN`]).
    pub fn energy_warn(&self) -> f64 {
        self.output.energy_warn.unwrap_or(DEFAULT_ENERGY_WARN)
    }
}

impl SceneFile {
    /// Parses a scene (TOML syntax, unknown keys, types).
    pub fn parse(text: &str) -> Result<Self, SceneError> {
        toml::from_str(text).map_err(SceneError::Toml)
    }

    /// A scene from a parsed TOML document (unknown keys, types).
    pub fn from_table(doc: toml::Table) -> Result<Self, SceneError> {
        toml::Value::Table(doc).try_into().map_err(SceneError::Toml)
    }

    /// Checks every value and builds the scene, within the machine's
    /// available memory.
    pub fn validate(&self) -> Result<Scene, SceneError> {
        self.validate_with(&Limits::machine())
    }

    /// Checks every value and builds the scene: sizes against `limits`
    /// before anything large is allocated, then the integrator itself (so
    /// that a scene that validates also starts: `check` and `run` refuse
    /// the same things).
    pub fn validate_with(&self, limits: &Limits) -> Result<Scene, SceneError> {
        self.validate_horizon(limits, false)
    }

    /// As [`validate_with`](Self::validate_with) with the horizon replaced
    /// by one step of the scene's `dt`, whatever `t_end` says: what a sweep
    /// reads first (its forcing and `dt`), before it sets its own horizon
    /// and validates again.
    pub fn validate_clock(&self, limits: &Limits) -> Result<Scene, SceneError> {
        self.validate_horizon(limits, true)
    }

    fn validate_horizon(&self, limits: &Limits, one_step: bool) -> Result<Scene, SceneError> {
        if self.output.every == 0 {
            return Err(field("output.every", "0 is not allowed: an integer >= 1"));
        }
        if !(self.output.transient >= 0.0 && self.output.transient.is_finite()) {
            return Err(field("output.transient", format!("{} is not allowed: finite and >= 0 (forcing periods)", self.output.transient)));
        }
        if let Some(tol) = self.output.period_tol {
            if !(tol > 0.0 && tol < 1.0) {
                return Err(field("output.period_tol", format!("{tol} is not allowed: in (0, 1)")));
            }
            if !self.output.summary {
                return Err(field("output.period_tol", "acts only with output.summary (the response period is a summary column): remove it, or set summary = true"));
            }
        }
        if let Some(f) = self.output.energy_warn {
            if !signorini_run::energy::check_factor(f) {
                return Err(field(
                    "output.energy_warn",
                    format!("{f} is not allowed: finite and > 1 (the factor by which the energy may exceed its budget before a warning; default {DEFAULT_ENERGY_WARN})"),
                ));
            }
        }
        if self.output.transient > 0.0 && !(self.output.poincare || self.output.summary || self.output.impacts) {
            return Err(field("output.transient", "acts only with output.poincare, output.summary or output.impacts: remove it, or ask for one"));
        }
        let scene = self.validate_tables(limits, one_step)?;
        if !one_step {
            self.output.check_window(&scene)?;
        }
        Ok(scene)
    }

    fn validate_tables(&self, limits: &Limits, one_step: bool) -> Result<Scene, SceneError> {
        if let Some(o) = &self.oscillator {
            if self.bar.is_some() || self.beam.is_some() {
                return Err(field("oscillator", "give exactly one of the tables [bar], [beam] and [oscillator]"));
            }
            return self.validate_oscillator(o, one_step);
        }
        if self.forcing.is_some() {
            return Err(field("forcing", "acts only with [oscillator] (a bar or a beam takes [load], a beam also [support])"));
        }
        match (&self.bar, &self.beam) {
            (Some(b), None) => {
                if self.support.is_some() {
                    return Err(field("support", "acts only with [beam] (the bar has no moving support): give the excitation as a [load]"));
                }
                let load = self.load.as_ref().map(|e| e.build(Table::Load, self.base.as_deref())).transpose()?;
                Ok(Scene::Bar(Box::new(validate_bar(b, &self.stop, self.obstacle.as_ref(), load, limits, one_step)?)))
            }
            (None, Some(b)) => {
                let support = self.support.as_ref().map(|e| e.build(Table::Support, self.base.as_deref())).transpose()?;
                let load = self.load.as_ref().map(|e| e.build(Table::Load, self.base.as_deref())).transpose()?;
                validate_beam(b, &self.stop, self.obstacle.as_ref(), support, load, limits, one_step)
            }
            _ => Err(field("bar/beam", "give exactly one of the tables [bar], [beam] and [oscillator]")),
        }
    }

    fn validate_oscillator(&self, o: &OscillatorToml, one_step: bool) -> Result<Scene, SceneError> {
        if !self.stop.is_empty() || self.obstacle.is_some() {
            return Err(field(contacts_table(&self.stop), "acts only with [bar] or [beam]: the oscillator's stop is oscillator.stop"));
        }
        for (k, t) in [("support", self.support.is_some()), ("load", self.load.is_some())] {
            if t {
                return Err(field(k, "acts only with [bar] or [beam]: the oscillator's load is [forcing]"));
            }
        }
        if self.output.snapshots_every > 0 {
            return Err(field("output.snapshots_every", "acts only with [bar] or [beam] (the oscillator has one dof): remove it"));
        }
        let exc = self.forcing.as_ref().map(|f| f.build(Table::Forcing, self.base.as_deref())).transpose()?;
        // The scheme first: its e (when it states one) is the restitution that acts.
        let (scheme, restitution) = oscillator_scheme(o)?;
        let osc = Oscillator {
            mass: o.mass,
            stiffness: o.stiffness,
            damping_ratio: o.damping_ratio.unwrap_or(0.0),
            stop: o.stop,
            restitution,
            x0: o.initial_displacement.unwrap_or(0.0),
            v0: o.initial_velocity.unwrap_or(0.0),
            load: exc.as_ref().map(|e| e.profile.clone()),
        };
        osc.validate().map_err(|e| match e {
            // x(0) above the stop: the stop's fault when x(0) is the default.
            RunError::Invalid { field: "oscillator.initial_displacement", value, .. } if value.is_finite() && o.initial_displacement.is_none() => {
                field("oscillator.stop", format!("{} is not allowed: >= initial_displacement (default 0): the initial state must satisfy x <= stop", o.stop))
            }
            RunError::Invalid { field: f, value, allowed } => field(f, format!("{value} is not allowed: {allowed}")),
            e => field("oscillator", e),
        })?;
        let scheme = scheme.unwrap_or_else(|| osc.default_scheme());
        let dt = positive("oscillator.dt", o.dt)?;
        let t_end = if one_step { dt } else { positive("oscillator.t_end", o.t_end)? };
        if t_end / dt > 1e10 {
            return Err(field("oscillator.dt", format!("{dt} gives {:.3e} steps: at most 1e10", t_end / dt)));
        }
        horizon("oscillator", dt, t_end)?;
        let omega = exc.and_then(|e| e.omega);
        // The clock alone (a sweep's first look): no integrator.
        if one_step {
            return Ok(Scene::Oscillator { omega, osc, scheme, dt, t_end, ready: Ready::default() });
        }
        // Validation is the instantiation (Scene::instantiate's build), kept for the run.
        let built = osc.dynamics().and_then(|(dy, own)| Ok((scheme.build(dy, dt, &own)?, own)));
        let (stepper, own) = built.map_err(|e| match e {
            RunError::Scheme(e @ SchemeError::Unstable { .. }) => field("oscillator.dt", e),
            RunError::Scheme(e @ (SchemeError::Factor(_) | SchemeError::NonFinite { .. })) => field("oscillator", format!("{e}: allowed: data whose step matrix is finite and positive definite")),
            RunError::Scheme(e) => field("oscillator.scheme", e),
            e @ RunError::BlowUp { .. } => field("oscillator", format!("{e}: the data overflow in the first step; allowed: data whose first step is finite")),
            e => field("oscillator", e),
        })?;
        let ready = Ready::keep(Simulation { stepper, u0: own.u, v0: own.v, tip: 0, lift: None, reduction: None });
        Ok(Scene::Oscillator { omega, osc, scheme, dt, t_end, ready })
    }
}

/// The oscillator's scheme (`None`: the default, [`Oscillator::default_scheme`])
/// and the restitution that acts (docs/vibro-impact.md, "Which restitution
/// acts"): a scheme with an impact law whose text states its e (`ps(0.5)`,
/// `ps-e0.5`, `event-driven(0.8)`) takes that e, and `oscillator.restitution`
/// may only repeat it; a scheme written by its family's name alone
/// (`event-driven`, `moreau-jean`) or without its e takes
/// `oscillator.restitution` (default 0), and is printed with it.
fn oscillator_scheme(o: &OscillatorToml) -> Result<(Option<SchemeSpec>, f64), SceneError> {
    let r = o.restitution.unwrap_or(0.0);
    let Some(text) = &o.scheme else {
        return Ok((None, r));
    };
    let spec: SchemeSpec = text.parse().map_err(|e| field("oscillator.scheme", e))?;
    if spec.needs_massless_node() {
        return Err(field("oscillator.scheme", format!("{spec} needs a massless contact node; the oscillator's mass sits at its contact: {}", families_with(|c| c.accepts_massless_node(false)))));
    }
    let Some(at) = spec.family().params.iter().position(|p| p.name == "e").filter(|_| spec.capabilities().restitution) else {
        if r != 0.0 {
            return Err(field(
                "oscillator.restitution",
                format!("acts only with a scheme that has an impact law ({}); {spec} has none: remove it or set it to 0, or choose ps", families_with(|c| c.restitution)),
            ));
        }
        return Ok((Some(spec), 0.0));
    };
    let t = text.trim();
    let states_e = match t.split_once('(') {
        Some((_, args)) => args.trim_end_matches(')').split(',').filter(|a| !a.trim().is_empty()).count() > at,
        None => t != spec.family().name,
    };
    let e = spec.args()[at];
    // The scheme with the e `r`.
    let with_e = |r: f64| {
        let mut args = spec.args().to_vec();
        args[at] = r;
        spec.family().with(&args)
    };
    match o.restitution {
        Some(r) if states_e && r != e => Err(field(
            "oscillator.restitution",
            format!(
                "{r} conflicts with oscillator.scheme = \"{t}\", whose e = {e} acts: give the restitution once (remove oscillator.restitution, or write it in the scheme: \"{}\")",
                with_e(r).call()
            ),
        )),
        Some(r) if !states_e => {
            let spec = with_e(r);
            spec.validate().map_err(|e| field("oscillator.restitution", e))?;
            Ok((Some(spec), r))
        }
        _ => Ok((Some(spec), e)),
    }
}

/// Of the keys a document gives, the one whose value is furthest from 1 in
/// scale (the likeliest cause of an overflow in a product of them).
/// Returns the key and that distance, `|log10 |v||`.
fn extreme_key(given: &[(&'static str, Option<f64>)]) -> Option<(&'static str, f64)> {
    given.iter().filter_map(|(k, v)| v.map(|v| (*k, v.abs().log10().abs()))).filter(|(_, s)| s.is_finite()).max_by(|a, b| a.1.total_cmp(&b.1))
}

/// A run configuration for `dt` and `t_end`, the horizon's error on `t_end`.
fn horizon(prefix: &str, dt: f64, t_end: f64) -> Result<(), SceneError> {
    match RunConfig::new(dt, t_end) {
        Ok(_) => Ok(()),
        Err(e @ RunError::Horizon { .. }) => Err(field(&format!("{prefix}.t_end"), e)),
        Err(e) => Err(field(&format!("{prefix}.dt"), e)),
    }
}

/// Which field a scheme's construction error belongs to; an overflow is
/// put on `overflow_key`.
fn scheme_error(e: SchemeError, overflow_key: &str) -> SceneError {
    match e {
        SchemeError::Unstable { .. } => field("bar.dt", e),
        SchemeError::MassNotSupported { .. } => field("bar.mass", e),
        e @ SchemeError::Factor(_) => field("bar", format!("{e}: the step matrix of these data is not usable; allowed: data whose matrices are finite and positive definite")),
        e @ SchemeError::NonFinite { .. } => field(overflow_key, format!("{e}: the data overflow in the scheme's start; allowed: data whose first step is finite")),
        e => field("bar.scheme", e),
    }
}

/// The table a scene-level contact error names: `stop` when `[[stop]]` is
/// given, else `obstacle`.
fn contacts_table(stops: &[StopToml]) -> &'static str {
    if stops.is_empty() {
        "obstacle"
    } else {
        "stop"
    }
}

/// A library error on a scene's contacts, named by the contact's field.
fn contact_error(e: RunError, set: &ContactSet, table: &str) -> SceneError {
    match e {
        RunError::Stop { index, field: f, value, allowed } => {
            let (name, at) = set.field_of(index, f);
            field(&name, format!("{value}{at}: allowed {allowed}"))
        }
        RunError::Fem(e @ signorini_fem::FemError::MassAtContacts { .. }) => field(
            &format!("{table}.mass"),
            format!("{e}; allowed: std or lumped (any contact nodes), or contact nodes this treatment supports (docs/scenes.md, \"Several contacts: [[stop]] and [obstacle]\")"),
        ),
        e => field(table, e),
    }
}

/// The stop a "stop stiffness" error is about: the first contact whose
/// stiffness is `value` (in the scheme's units `kappa(stiffness)`).
fn stiff_stop(set: &ContactSet, value: f64, kappa: impl Fn(f64) -> f64) -> Option<&Site> {
    set.stops.iter().zip(&set.sites).find(|(st, _)| st.stiffness.is_some_and(|k| kappa(k) == value)).map(|(_, site)| site)
}

/// The softest own stop stiffness of `set` (its stop index and value).
fn softest_stop(set: &ContactSet) -> Option<(usize, f64)> {
    set.stops.iter().zip(&set.sites).filter(|(_, site)| site.own_stiffness).filter_map(|(st, site)| Some((site.stop?.0, st.stiffness?))).min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The message of a spring too soft for floating point.
fn too_soft(e: impl fmt::Display) -> String {
    format!("{e}: a spring this soft has a compliance 1/(β dt² κ) beyond the floating-point range; allowed: stiffness with β dt² κ >= 2.2e-308 (κ in the scaled equation)")
}

fn validate_bar(b: &BarToml, stops: &[StopToml], obstacle: Option<&ObstacleToml>, load: Option<Excitation>, limits: &Limits, one_step: bool) -> Result<BarRun, SceneError> {
    let mass: BarMass = b.mass.parse().map_err(|e| field("bar.mass", e))?;
    let scheme: SchemeSpec = b.scheme.parse().map_err(|e| field("bar.scheme", e))?;
    if scheme.needs_massless_node() && !mass.massless_contact_node() {
        return Err(field("bar.mass", format!("scheme {scheme} needs a massless contact node: mod, mod1, mod2, mod3, transfer or singular (got {mass})")));
    }
    if scheme.needs_diagonal_mass() && mass != BarMass::Lumped {
        return Err(field("bar.mass", format!("scheme {scheme} needs a diagonal mass with a massive contact node: lumped (got {mass})")));
    }
    if scheme.needs_massive_node() && mass.massless_contact_node() {
        return Err(field("bar.mass", format!("scheme {scheme} needs a massive contact node: std or lumped (got {mass})")));
    }
    if b.elements < 2 {
        return Err(field("bar.elements", format!("{} is not allowed: an integer >= 2", b.elements)));
    }
    let degree = b.degree.unwrap_or(1);
    if !(1..=3).contains(&degree) {
        return Err(field("bar.degree", format!("{degree} is not allowed: 1, 2 or 3 (Lagrange P1, P2, P3)")));
    }
    if degree > 1 && !matches!(mass, BarMass::Std | BarMass::Lumped | BarMass::Mod | BarMass::Mod1) {
        return Err(field("bar.mass", format!("{mass} is not defined at degree {degree}: allowed std, lumped, mod or mod1")));
    }
    let reduce = b.reduce.as_ref().map(|r| r.keep("bar")).transpose()?;
    if reduce.is_some() {
        if !scheme.accepts_massless_node(true) {
            return Err(field(
                "bar.scheme",
                format!(
                    "{scheme} needs a massive contact node, and a reduced model's contacts are massless (reduce): allowed a scheme that takes a massless node ({}; ps with β >= 1/4)",
                    families_with(|c| c.accepts_massless_node(true))
                ),
            ));
        }
        if !mass.massless_contact_node() {
            return Err(field(
                "bar.mass",
                format!("{mass} with reduce: the reduction keeps the contacts massless, exact for a parent whose contact nodes carry no mass; allowed mod, mod1, mod2, mod3, transfer or singular"),
            ));
        }
    }
    // A P`k` bar of m elements has the unknowns of a P1 bar of k m.
    fits("bar.elements", b.elements.saturating_mul(degree), false, limits)?;
    // Several contacts: [[stop]] / [obstacle] replace the obstacle at x = 0.
    let multi = !stops.is_empty() || obstacle.is_some();
    if multi {
        if b.benchmark.is_some() {
            return Err(field(contacts_table(stops), "a benchmark brings its own obstacle and exact solution: remove [[stop]] and [obstacle], or remove benchmark"));
        }
        if b.gap.is_some() {
            return Err(field("bar.gap", "acts only without [[stop]] and [obstacle], which replace the obstacle at x = 0: remove it (that obstacle is the stop x = 0, lo = gap)"));
        }
        if obstacle.is_some() && mass.massless_contact_node() {
            return Err(field("bar.mass", format!("{mass} takes the mass off every contact node, and [obstacle] makes every node one: allowed std or lumped with [obstacle]")));
        }
        // Every unknown node with [obstacle] (m + 1 at most), else one per stop.
        let unknowns = b.elements.saturating_mul(degree).saturating_add(1);
        let k = if obstacle.is_some() { unknowns } else { stops.len() };
        contacts_fit(contacts_table(stops), k, unknowns, b.elements.saturating_mul(degree), false, limits)?;
    }
    let (mut problem, benchmark, default_t) = match &b.benchmark {
        Some(name) => {
            for (k, given) in [
                ("length", b.length.is_some()),
                ("wave_speed", b.wave_speed.is_some()),
                ("far_end", b.far_end.is_some()),
                ("gap", b.gap.is_some()),
                ("body_force", b.body_force.is_some()),
                ("initial_displacement", b.initial_displacement.is_some()),
                ("initial_velocity", b.initial_velocity.is_some()),
            ] {
                if given {
                    return Err(field(&format!("bar.{k}"), "comes from the benchmark: remove it, or remove `benchmark`"));
                }
            }
            let bench: Benchmark = name.parse().map_err(|e| field("bar.benchmark", e))?;
            let t = bench.default_ratio_and_horizon().1;
            let t_end = b.t_end.unwrap_or(t);
            let exact = bench.exact(positive("bar.t_end", t_end)?).map_err(|e| field("bar.t_end", e))?;
            let p = bench.problem_with_degree(exact.as_ref(), b.elements, mass, degree).map_err(|e| field("bar", e))?;
            (p, Some(bench), t)
        }
        None => {
            let length = positive("bar.length", b.length.unwrap_or(1.0))?;
            if length > 1e150 {
                return Err(field("bar.length", format!("{length:e} is not allowed: at most 1e150 (products of lengths must stay finite)")));
            }
            let c = positive("bar.wave_speed", b.wave_speed.unwrap_or(1.0))?;
            let end = match b.far_end.as_deref().unwrap_or("clamped") {
                "clamped" => RightEnd::Clamped,
                "free" => RightEnd::Free,
                other => return Err(field("bar.far_end", format!("{other:?} is not allowed: \"clamped\" or \"free\""))),
            };
            // With stops the obstacle at x = 0 is unused: a gap no state is below.
            let gap = if multi { -f64::MAX } else { finite("bar.gap", b.gap.unwrap_or(0.0))? };
            let f = finite("bar.body_force", b.body_force.unwrap_or(0.0))?;
            let u0 = InitialField::compile("bar.initial_displacement", b.initial_displacement.as_ref().unwrap_or(&FieldToml::Number(0.0)))?;
            let v0 = InitialField::compile("bar.initial_velocity", b.initial_velocity.as_ref().unwrap_or(&FieldToml::Number(0.0)))?;
            u0.check_covers("bar.initial_displacement", 0.0, length)?;
            v0.check_covers("bar.initial_velocity", 0.0, length)?;
            // The stiffness entries are c² m / L.
            let k = c * c * b.elements as f64 / length;
            if !(k.is_finite() && k >= f64::MIN_POSITIVE && (length / b.elements as f64) >= f64::MIN_POSITIVE) {
                let key = extreme_key(&[("bar.wave_speed", b.wave_speed), ("bar.length", b.length)]).map_or("bar.elements", |(k, _)| k);
                return Err(field(
                    key,
                    format!(
                        "wave_speed = {c:e}, length = {length:e}, elements = {}: the stiffness c² m / L or the element size L / m leaves the floating-point range; allowed: 2.2e-308 <= c² m / L < 1.8e308 and L / m >= 2.2e-308",
                        b.elements
                    ),
                ));
            }
            let bar = Bar::new(length, b.elements, c, end).and_then(|bar| bar.with_degree(degree)).map_err(|e| field("bar", e))?;
            // The first node where a field is not finite, to name its key.
            let bad = std::cell::Cell::new(None);
            let at = |key: &'static str, fld: &InitialField, x: f64| {
                let v = fld.eval(x);
                if !v.is_finite() && bad.get().is_none() {
                    bad.set(Some((key, x, v)));
                }
                v
            };
            let p = BarProblem::new(bar, mass, gap, f, |x| at("bar.initial_displacement", &u0, x), |x| at("bar.initial_velocity", &v0, x)).map_err(|e| match bad.get() {
                Some((key, x, v)) => field(key, format!("{v} at the node x = {x} is not allowed: a value finite at every node")),
                None => field("bar", e),
            })?;
            (p, None, 1.0)
        }
    };
    let contacts = if multi {
        let bar = problem.bar;
        let mesh = NodeMesh { length: bar.length, elements: bar.last_node(), unknown: 0..=bar.dofs() - 1, x: &|i| bar.node(i) };
        let rules = KeyRules {
            restitution: if scheme.capabilities().restitution {
                Ok(())
            } else {
                Err(format!("acts only with a scheme that has a restitution law ({}), not {scheme}: remove it, or choose such a scheme", families_with(|c| c.restitution)))
            },
            stiffness: if scheme.capabilities().stiffness {
                Ok(())
            } else {
                Err(format!("acts only with a penalty scheme ({}), not {scheme}: remove it, or choose one", families_with(|c| c.stiffness)))
            },
        };
        let u0 = problem.initial.u.clone();
        let set = contact_set(stops, obstacle, &mesh, &|i| u0[i], &rules)?;
        if set.stops.len() == 1 && mass.massless_contact_node() && set.stops[0].node != 0 {
            return Err(field("bar.mass", format!("{mass} with one contact needs it at node 0 (x = 0), not node {}: allowed std or lumped, or the stop at x = 0", set.stops[0].node)));
        }
        problem = problem.with_stops(set.stops.clone()).map_err(|e| contact_error(e, &set, "bar"))?;
        Some(set)
    } else {
        None
    };
    let mut omega = None;
    if let Some(e) = load {
        if b.benchmark.is_some() {
            return Err(field("load", "a benchmark is its own problem with its exact solution: remove [load], or remove benchmark"));
        }
        let bar = problem.bar;
        let mesh = NodeMesh { length: bar.length, elements: bar.last_node(), unknown: 0..=bar.dofs() - 1, x: &|i| bar.node(i) };
        let node = e.x.map(|x| mesh.node("load.x", x)).transpose()?;
        omega = e.omega;
        problem = problem.with_load(node, e.profile).map_err(|e| field("load.x", e))?;
    }
    let dt = match (b.dt, b.ratio) {
        (Some(dt), None) => positive("bar.dt", dt)?,
        (None, Some(r)) => problem.bar.h() / positive("bar.ratio", r)?,
        (None, None) => return Err(field("bar.dt", "give dt or ratio (= dx/dt)")),
        (Some(_), Some(_)) => return Err(field("bar.ratio", "give dt or ratio, not both")),
    };
    let t_end = if one_step { dt } else { positive("bar.t_end", b.t_end.unwrap_or(default_t))? };
    if t_end / dt > 1e9 {
        return Err(field("bar.dt", format!("{dt} gives {:.3e} steps: at most 1e9", t_end / dt)));
    }
    horizon("bar", dt, t_end)?;
    // M + β dt² K must keep M's digits: (c dt / h)² below 1e15.
    let r = problem.bar.wave_speed * dt / problem.bar.h();
    if !(r * r <= 1e15) {
        let key = extreme_key(&[("bar.wave_speed", b.wave_speed), ("bar.ratio", b.ratio), ("bar.dt", b.dt), ("bar.length", b.length)]).map_or("bar.dt", |(k, _)| k);
        return Err(field(key, format!("c dt / h = {r:e}: the step matrix M + β dt² K loses the mass to rounding; allowed: c dt / h <= 3.2e7")));
    }
    // An overflow comes from an extreme number (beyond 1e100) if one is given
    // — of the data, or of the initial fields at the nodes. (The gap only
    // enters comparisons: it overflows nothing.)
    let largest = |v: &[f64], given: bool| given.then(|| v.iter().fold(0.0_f64, |a, x| a.max(x.abs()))).filter(|m| *m > 1.0);
    let numbers = [
        ("bar.body_force", b.body_force),
        ("bar.length", b.length),
        ("bar.wave_speed", b.wave_speed),
        ("bar.dt", b.dt),
        ("bar.ratio", b.ratio),
        ("bar.initial_displacement", largest(&problem.initial.u, b.initial_displacement.is_some())),
        ("bar.initial_velocity", largest(&problem.initial.v, b.initial_velocity.is_some())),
    ];
    let overflow_key = extreme_key(&numbers).filter(|(_, scale)| *scale > 100.0).map_or("bar", |(k, _)| k);
    // The clock alone (a sweep's first look): no integrator.
    if one_step {
        return Ok(BarRun { problem, benchmark, scheme, dt, t_end, contacts, omega, reduce, ready: Ready::default() });
    }
    // Validation is the instantiation (Scene::instantiate's build), kept for the run.
    let full = problem.dynamics();
    let tip = full.contacts[0].dof;
    let (dy, init, reduction) = match reduce {
        None => (full, problem.initial.clone(), None),
        Some(keep) => {
            let red = signorini_run::reduced::reduce(&full, &problem.initial, keep).map_err(|e| reduce_error(e, "bar"))?;
            (red.dynamics, red.initial, Some(red.reduction))
        }
    };
    let stepper = scheme.build(dy, dt, &init).map_err(|e| match (e, &contacts) {
        (SchemeError::PenaltyTooStiff { field: "stop stiffness", value, max }, Some(set)) => {
            let name = stiff_stop(set, value, |k| k).and_then(|s| s.stop).map_or("stop".to_string(), |(i, _)| format!("stop.{i}.stiffness"));
            field(&name, format!("{value:e} makes the contact law ill-posed in floating point at this mesh and dt (the spring is more than 1e12 times stiffer than the step matrix at its node); usable range: 0 < stiffness <= {max:.3e}"))
        }
        (e @ SchemeError::Structure(_), Some(_)) => field("bar.scheme", format!("{e}; allowed: a scheme that takes this contact set")),
        (e @ SchemeError::Contact(signorini_contact::ContactError::Compliance(_)), Some(set)) => {
            // The softest spring: a stop's own, or the scheme's γ_P K_cc.
            let name = softest_stop(set).filter(|&(_, k)| k < 1e-100).map_or("bar.scheme".to_string(), |(i, _)| format!("stop.{i}.stiffness"));
            field(&name, too_soft(e))
        }
        (SchemeError::Events(signorini_schemes::events::EventsError::MasslessRestitution { contact, restitution }), set) => {
            // A stop's own restitution, else the scheme's e.
            let key = set.as_ref().filter(|s| s.stops.get(contact).is_some_and(|st| st.restitution.is_some())).map_or("bar.scheme".to_string(), |s| s.field_of(contact, "restitution").0);
            field(
                &key,
                format!("e = {restitution} at a massless contact node (this mass treatment or reduced model gives the contact node no mass): it lands on its bound without an impact (its force is statically condensed), so no restitution acts there; allowed: 0 (event-driven(0)), or a massive contact node (mass std or lumped)"),
            )
        }
        (e, _) => scheme_error(e, overflow_key),
    })?;
    let ready = Ready::keep(Simulation { stepper, u0: init.u, v0: init.v, tip, lift: None, reduction });
    Ok(BarRun { problem, benchmark, scheme, dt, t_end, contacts, omega, reduce, ready })
}

/// The beam's scheme and spring (N/m) from `beam.scheme`, or from the
/// paper's spelling: `contact = "projection"` is `ps(0, β)` (`beta`,
/// default 1/2), `contact = "penalty"` is `penalty-cn` (Newmark β = 1/4)
/// with a spring of `penalty_stiffness` N/m (default 10⁸) at every contact
/// without its own; neither: the paper scene's (or the custom scene's
/// projection) with `beta` / `penalty_stiffness` applied. Every key acts or
/// is refused: `beta` with the penalty, `penalty_stiffness` with the
/// projection, and `contact`, `beta`, `penalty_stiffness` with `scheme`.
fn beam_scheme(b: &BeamToml, base: &BeamScene) -> Result<(SchemeSpec, Option<f64>), SceneError> {
    if let Some(name) = b.scheme.as_deref() {
        for (key, given) in [("beam.contact", b.contact.is_some()), ("beam.beta", b.beta.is_some()), ("beam.penalty_stiffness", b.penalty_stiffness.is_some())] {
            if given {
                return Err(field(key, "acts only without beam.scheme, which replaces contact, beta and penalty_stiffness (contact = \"projection\" is ps(0,β), \"penalty\" is penalty-cn with a spring): remove one of them"));
            }
        }
        let spec: SchemeSpec = name.parse().map_err(|e| field("beam.scheme", e))?;
        if !spec.capabilities().beam {
            return Err(field(
                "beam.scheme",
                format!(
                    "{spec} does not take the beam's structure (Hermite cubics: a consistent mass, massive contact dofs away from dof 0, the support's load): allowed {}",
                    families_with(|c| c.beam)
                ),
            ));
        }
        if b.force && spec.stability_rule().is_none() {
            return Err(field("beam.force", format!("acts only with a conditionally stable scheme (its stability limit is what force lifts); {spec} is unconditionally stable: remove it")));
        }
        return Ok((spec, None));
    }
    let penalty = match b.contact.as_deref() {
        None => base.spring.is_some(),
        Some("projection") => false,
        Some("penalty") => true,
        Some(other) => return Err(field("beam.contact", format!("{other:?} is not allowed: \"projection\" or \"penalty\" (or beam.scheme = a registry scheme)"))),
    };
    if penalty {
        let stiffness = b.penalty_stiffness.or(base.spring).unwrap_or(1e8);
        positive("beam.penalty_stiffness", stiffness)?;
        if b.beta.is_some() {
            return Err(field(
                "beam.beta",
                "acts only with contact = \"projection\" (the β-scheme); the penalty contact integrates with Newmark β = 1/4: remove beta, or set contact = \"projection\"",
            ));
        }
        Ok((SchemeSpec::penalty(10.0, false), Some(stiffness)))
    } else {
        // An explicit contact = "projection" starts from β = 1/2; without it, the scene's β.
        let base_beta = if b.contact.is_none() { base.scheme.param("beta").unwrap_or(0.5) } else { 0.5 };
        let beta = b.beta.unwrap_or(base_beta);
        if !(0.0..=0.5).contains(&beta) {
            return Err(field("beam.beta", format!("{beta} is not allowed: [0, 1/2]")));
        }
        if b.penalty_stiffness.is_some() {
            return Err(field("beam.penalty_stiffness", "acts only with contact = \"penalty\": remove it, or set contact = \"penalty\""));
        }
        Ok((SchemeSpec::ps(0.0, beta), None))
    }
}

fn validate_beam(
    b: &BeamToml,
    stops: &[StopToml],
    obstacle: Option<&ObstacleToml>,
    support: Option<Excitation>,
    load: Option<Excitation>,
    limits: &Limits,
    one_step: bool,
) -> Result<Scene, SceneError> {
    let base = match &b.scene {
        Some(name) => *BeamScene::PAPER.iter().find(|s| s.name == name).ok_or_else(|| field("beam.scene", format!("{name:?} is not allowed: fig2, fig3, fig4, fig5, fig6, fig7 or fig8")))?,
        None => BeamScene::new("custom", 19, 1e-5, 2.0, SchemeSpec::ps(0.0, 0.5)),
    };
    let elements = b.elements.unwrap_or(base.elements);
    if elements < 1 {
        return Err(field("beam.elements", "0 is not allowed: an integer >= 1"));
    }
    fits("beam.elements", elements, true, limits)?;
    let dt = positive("beam.dt", b.dt.unwrap_or(base.dt))?;
    let t_end = if one_step { dt } else { positive("beam.t_end", b.t_end.unwrap_or(base.t_end))? };
    if t_end / dt > 1e9 {
        return Err(field("beam.dt", format!("{dt} gives {:.3e} steps: at most 1e9", t_end / dt)));
    }
    horizon("beam", dt, t_end)?;
    if dt > 1e100 {
        return Err(field("beam.dt", format!("{dt:e} is not allowed: at most 1e100 (dt² enters the step matrix)")));
    }
    let (scheme, spring) = beam_scheme(b, &base)?;
    // The paper's spelling (contact = "projection" / "penalty"), named in messages.
    let legacy = b.scheme.is_none();
    // Several contacts: [[stop]] / [obstacle] replace the tip's two stops.
    let multi = !stops.is_empty() || obstacle.is_some();
    if multi {
        if b.stops.is_some() {
            return Err(field("beam.stops", "acts only without [[stop]] and [obstacle], which replace the tip's stops: remove it (the tip's stops are the stop x = L, lo = g1, hi = g2)"));
        }
        let k = if obstacle.is_some() { elements } else { stops.len() };
        contacts_fit(contacts_table(stops), k, elements.saturating_mul(2), elements, true, limits)?;
    }
    let mut pipe = Pipe::paper();
    if let Some([g1, g2]) = b.stops {
        if !(g1.is_finite() && g2.is_finite() && g1 < g2) {
            return Err(field("beam.stops", format!("[{g1}, {g2}] is not allowed: finite, g1 < g2")));
        }
        if !(g1 <= 0.0 && g2 >= 0.0) {
            return Err(field("beam.stops", format!("[{g1}, {g2}] is not allowed: the tip starts at 0, so g1 <= 0 <= g2")));
        }
        pipe.stops = (g1, g2);
    }
    if support.is_some() && b.support.is_some() {
        return Err(field("beam.support", "not both [support] and beam.support = [A, ω]: remove beam.support (it is [support] with amplitude = A, omega = ω)"));
    }
    // [support]: the paper's sine A sin(ω t) takes the pipe's own path (bit for
    // bit the beam.support scenes); any other profile the general lifting.
    let mut excitation = BeamExcitation::default();
    let mut omega = Some(pipe.support.1);
    if let Some(e) = support {
        match e.profile {
            TimeProfile::Sine { amplitude, omega: w } => pipe.support = (amplitude, w),
            ref other => {
                if other.second_derivative().is_none() {
                    return Err(field("support.profile", "\"series\" is not allowed for a support motion: φ'' of a piecewise-linear φ is a train of impulses; give the load itself in [load]"));
                }
                excitation.support = Some(other.clone());
                omega = e.omega;
            }
        }
    }
    if let Some(e) = load {
        let l = pipe.length;
        let mesh = NodeMesh { length: l, elements, unknown: 1..=elements, x: &|i| l * i as f64 / elements as f64 };
        let node = e.x.map(|x| mesh.node("load.x", x)).transpose()?;
        excitation.load = Some((node, e.profile));
        omega = omega.or(e.omega);
    }
    if let Some([a, w]) = b.support {
        pipe.support = (finite("beam.support", a)?, positive("beam.support", w)?);
        // The lifted load is A ω² h(x) + 8 A k²/L⁴, its velocity A ω h(x).
        if !(a * w * w).is_finite() {
            return Err(field("beam.support", format!("[{a}, {w}] is not allowed: A ω² must be finite (< 1.8e308)")));
        }
    }
    let scene = BeamScene { name: "scene", elements, dt, t_end, scheme, spring, paper_seconds: base.paper_seconds };
    let contacts = if multi {
        let l = pipe.length;
        let mesh = NodeMesh { length: l, elements, unknown: 1..=elements, x: &|i| l * i as f64 / elements as f64 };
        let rules = KeyRules {
            restitution: match scheme {
                spec if spec.capabilities().restitution => Ok(()),
                _ if legacy => Err("acts only with contact = \"projection\" (the β-scheme's impact law); the penalty contact has none: remove it, or set contact = \"projection\"".to_string()),
                spec => Err(format!("acts only with a scheme that has a restitution law ({}), not {spec}: remove it, or choose such a scheme", families_with(|c| c.restitution && c.beam))),
            },
            stiffness: match scheme {
                spec if spec.capabilities().stiffness => Ok(()),
                _ if legacy => Err("acts only with contact = \"penalty\" (N/m, like penalty_stiffness): remove it, or set contact = \"penalty\"".to_string()),
                spec => Err(format!("acts only with a penalty scheme ({}), not {spec}: remove it, or choose one", families_with(|c| c.stiffness && c.beam))),
            },
        };
        // The lifted displacement u = ũ - hφ starts at 0.
        let mut set = contact_set(stops, obstacle, &mesh, &|_| 0.0, &rules)?;
        // beam.penalty_stiffness is every stop's spring (N/m) unless it gives its own.
        if let Some(stiffness) = spring {
            for st in &mut set.stops {
                st.stiffness = st.stiffness.or(Some(stiffness));
            }
        }
        Some(set)
    } else {
        None
    };
    let rho_s = pipe.rho_s;
    let reduce = b.reduce.as_ref().map(|r| r.keep("beam")).transpose()?;
    let mut setup = BeamSetup::new(pipe, scene).with_excitation(excitation.clone()).forced(b.force);
    setup.stops = contacts.as_ref().map(|c| c.stops.clone());
    setup.reduce = reduce;
    if reduce.is_some() {
        if let Some(beta) = scheme.param("beta").filter(|_| legacy && spring.is_none()) {
            if beta < 0.25 {
                return Err(field(
                    "beam.beta",
                    format!("{beta} is not allowed with reduce: the reduced model's contacts are massless, and the β-scheme with a massless node is unstable for every β < 1/4; allowed [1/4, 1/2]"),
                ));
            }
        }
    }
    if excitation.support.is_none() {
        omega = Some(pipe.support.1);
    }
    // The clock alone (a sweep's first look): no integrator.
    if one_step {
        return Ok(Scene::Beam { pipe, scene, force: b.force, contacts, excitation, omega, reduce, ready: Ready::default() });
    }
    // Validation is the instantiation (Scene::instantiate's build), kept for the run.
    let built = setup.build().map_err(|e| match e {
        e @ RunError::Reduce(_) => reduce_error(e, "beam"),
        // The paper's β-scheme: its limit with the paper's sufficient condition (3.1).
        RunError::Scheme(SchemeError::Unstable { dt, limit, .. }) if legacy && spring.is_none() => {
            let beta = scheme.param("beta").unwrap_or(f64::NAN);
            let paper = pipe.dynamics(elements).and_then(|(beam, _, _)| signorini_run::beam::stability_limit(&beam, beta)).map_or(f64::NAN, |l| l.dt_sufficient);
            field(
                "beam.dt",
                format!("dt = {dt} is at or beyond the exact stability limit {limit:.6e} of the β-scheme with β = {beta} < 1/4 (2/sqrt((1-4β) κ_h); the paper's sufficient condition (3.1) gives {paper:.6e}); use a smaller dt or β >= 1/4 (unconditionally stable), or force = true to run past it"),
            )
        }
        RunError::Scheme(SchemeError::Unstable { .. }) => field("beam.dt", format!("{e} (or force = true to run past it)")),
        RunError::NotAllowed { field: f, allowed } => field(f, format!("not allowed here: allowed {allowed}")),
        RunError::Scheme(SchemeError::PenaltyTooStiff { field: "stop stiffness", value, max }) if contacts.is_some() => {
            let own = contacts.as_ref().and_then(|set| stiff_stop(set, value, |k| PenaltyUnits::NewtonPerMetre.kappa(k, rho_s))).filter(|s| s.own_stiffness).and_then(|s| s.stop);
            let (name, k) = match own {
                Some((i, _)) => (format!("stop.{i}.stiffness"), value * rho_s),
                None => ("beam.penalty_stiffness".to_string(), value * rho_s),
            };
            field(&name, format!("{k:e} N/m makes the contact law ill-posed in floating point at this mesh and dt (the spring is more than 1e12 times stiffer than the beam at its node); usable range: 0 < stiffness <= {:.3e} N/m", max * rho_s))
        }
        e @ RunError::Stop { .. } if contacts.is_some() => contacts.as_ref().map_or_else(|| field("beam", "unreachable"), |set| contact_error(e, set, "beam")),
        // A registry scheme that does not take this beam's contacts: its key.
        e @ RunError::Scheme(SchemeError::Structure(_) | SchemeError::NotTaken { .. }) if !legacy => field("beam.scheme", format!("{e}; allowed: a scheme that takes this beam's contacts")),
        e @ RunError::Scheme(SchemeError::Structure(_)) if contacts.is_some() => field("beam", format!("{e}; allowed: a contact set the beam's scheme takes")),
        e @ RunError::Scheme(SchemeError::Contact(signorini_contact::ContactError::Compliance(_))) if contacts.is_some() => {
            // The softest spring: a stop's own, or penalty_stiffness.
            let default = match spring {
                Some(stiffness) if contacts.as_ref().is_some_and(|c| c.sites.iter().any(|s| !s.own_stiffness)) => stiffness,
                _ => f64::INFINITY,
            };
            let name = contacts.as_ref().and_then(softest_stop).filter(|&(_, k)| k < default).map_or("beam.penalty_stiffness".to_string(), |(i, _)| format!("stop.{i}.stiffness"));
            field(&name, too_soft(e))
        }
        RunError::Scheme(SchemeError::PenaltyTooStiff { max, .. }) => {
            let k = spring.unwrap_or(f64::NAN);
            // The scheme sees κ = k/(ρS): back to N/m.
            field("beam.penalty_stiffness", format!("{k:e} N/m makes the contact law ill-posed in floating point at this mesh and dt (the spring is more than 1e12 times stiffer than the beam at its tip); usable range: 0 < penalty_stiffness <= {:.3e} N/m", max * pipe.rho_s))
        }
        e @ RunError::BlowUp { .. } => field("beam", format!("{e}: the data overflow in the first step; allowed: data whose first step is finite")),
        e => field("beam", e),
    })?;
    let ready = Ready::keep(instantiate::beam_simulation(built, pipe, excitation.clone()));
    Ok(Scene::Beam { pipe, scene, force: b.force, contacts, excitation, omega, reduce, ready })
}
