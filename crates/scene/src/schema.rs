//! The TOML schema of a scene file (serde structs, unknown keys rejected):
//! `[bar]`, `[beam]`, `[oscillator]`, `[[stop]]`, `[obstacle]`, `[output]`.

use crate::excitation::ExcitationToml;
use crate::{field, SceneError};
use serde::Deserialize;
use signorini_reduce::{Keep, ReduceError};
use signorini_run::RunError;

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

/// `[oscillator]`: `m x'' + c x' + k x = F(t)`, `x <= stop` (or `lo <= x <= hi`
/// with `stops = [lo, hi]`), `c = 2 ζ sqrt(k m)`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OscillatorToml {
    /// Mass m (> 0).
    pub mass: f64,
    /// Stiffness k (>= 0).
    pub stiffness: f64,
    /// Damping ratio ζ (>= 0; default 0).
    pub damping_ratio: Option<f64>,
    /// The stop: x <= stop (one of `stop`, `stops`).
    pub stop: Option<f64>,
    /// Two stops `[lo, hi]`: lo <= x <= hi, finite, lo < hi, the start
    /// between them (as `beam.stops`; one of `stop`, `stops`). Exactly
    /// two numbers: `[lo, hi, x]` is refused, as `beam.stops` refuses it.
    #[serde(default, deserialize_with = "optional_pair")]
    pub stops: Option<[f64; 2]>,
    /// Restitution r in [0, 1] (default 0), at both stops: the e of the default scheme, and
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
    pub(crate) fn keep(&self, table: &str) -> Result<Keep, SceneError> {
        match (self.modes, self.cutoff_hz) {
            (Some(r), None) => Ok(Keep::Modes(r)),
            (None, Some(f)) => Ok(Keep::CutoffHz(f)),
            (None, None) => Err(field(&format!("{table}.reduce"), "give modes = r or cutoff_hz = f")),
            (Some(_), Some(_)) => Err(field(&format!("{table}.reduce.cutoff_hz"), "give modes or cutoff_hz, not both")),
        }
    }
}

/// A reduction's error, named `<table>.reduce.<field>`.
pub(crate) fn reduce_error(e: RunError, table: &str) -> SceneError {
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

impl SceneFile {
    /// The energy monitor's factor (`[output] energy_warn`, default
    /// [`DEFAULT_ENERGY_WARN`]).
    pub fn energy_warn(&self) -> f64 {
        self.output.energy_warn.unwrap_or(DEFAULT_ENERGY_WARN)
    }
}
