//! Scene files: TOML descriptions of a bar or beam run.
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
//! is 0.5) or a table `[[x0, u0], [x1, u1], …]` (piecewise linear). Every
//! key is checked: unknown keys are rejected, each value is range-checked
//! with the allowed range in the message, a key that would not act in this
//! scene is refused, and the integrator is built once (so a scene that
//! validates also starts).

use serde::Deserialize;
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_run::beam::{build as build_beam, BeamContact, BeamScene, Pipe};
use signorini_run::{BarProblem, Benchmark, RunConfig, RunError};
use signorini_schemes::{SchemeError, SchemeSpec};
use std::fmt;

/// A scene error: which field, what is wrong, what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The TOML itself (message includes line and column).
    #[error("scene file: {0}")]
    Toml(String),
    /// A value out of its range or inconsistent with others.
    #[error("{field}: {message}")]
    Field {
        /// Dotted path of the field (`bar.dt`).
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

fn field(f: &str, m: impl fmt::Display) -> SceneError {
    SceneError::Field { field: f.to_string(), message: m.to_string() }
}

/// The whole scene file.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// A bar problem.
    pub bar: Option<BarToml>,
    /// A beam between two stops.
    pub beam: Option<BeamToml>,
    /// Outputs.
    #[serde(default)]
    pub output: OutputToml,
}

/// `[bar]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BarToml {
    /// Built-in benchmark.
    pub benchmark: Option<String>,
    /// Length L (> 0).
    pub length: Option<f64>,
    /// Wave speed c (> 0).
    pub wave_speed: Option<f64>,
    /// "clamped" or "free".
    pub far_end: Option<String>,
    /// Obstacle position g.
    pub gap: Option<f64>,
    /// Uniform body force f.
    pub body_force: Option<f64>,
    /// u0(x).
    pub initial_displacement: Option<FieldToml>,
    /// v0(x).
    pub initial_velocity: Option<FieldToml>,
    /// Elements m (>= 2).
    pub elements: usize,
    /// Mass treatment.
    #[serde(default = "default_mass")]
    pub mass: String,
    /// Scheme.
    #[serde(default = "default_scheme")]
    pub scheme: String,
    /// Time step.
    pub dt: Option<f64>,
    /// dx/dt (alternative to dt).
    pub ratio: Option<f64>,
    /// Horizon.
    pub t_end: Option<f64>,
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

/// `[beam]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BeamToml {
    /// A paper scene (fig2 … fig8) to start from; the other keys override it.
    pub scene: Option<String>,
    /// Elements J (>= 1).
    pub elements: Option<usize>,
    /// Time step (s).
    pub dt: Option<f64>,
    /// Horizon (s).
    pub t_end: Option<f64>,
    /// "projection" or "penalty".
    pub contact: Option<String>,
    /// β of the β-scheme, in [0, 1/2].
    pub beta: Option<f64>,
    /// Penalty spring stiffness (N/m, > 0).
    pub penalty_stiffness: Option<f64>,
    /// Lower and upper stops (m), g1 < g2.
    #[serde(default, deserialize_with = "optional_pair")]
    pub stops: Option<[f64; 2]>,
    /// Support amplitude (m) and angular frequency (rad/s).
    #[serde(default, deserialize_with = "optional_pair")]
    pub support: Option<[f64; 2]>,
    /// Run a conditionally stable β-scheme beyond its limit anyway.
    #[serde(default)]
    pub force: bool,
}

/// `[output]`.
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
}

fn one() -> usize {
    1
}
fn yes() -> bool {
    true
}

impl Default for OutputToml {
    fn default() -> Self {
        Self { every: 1, snapshots_every: 0, plots: true }
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
}

/// A validated scene.
pub enum Scene {
    /// A bar.
    Bar(Box<BarRun>),
    /// A beam between stops.
    Beam {
        /// The pipe.
        pipe: Pipe,
        /// The run.
        scene: BeamScene,
        /// Forced beyond the stability limit.
        force: bool,
    },
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

fn positive(name: &str, v: f64) -> Result<f64, SceneError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(field(name, format!("{v} is not allowed: finite and > 0")))
    }
}

fn finite(name: &str, v: f64) -> Result<f64, SceneError> {
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

impl SceneFile {
    /// Parses a scene (TOML syntax, unknown keys, types).
    pub fn parse(text: &str) -> Result<Self, SceneError> {
        toml::from_str(text).map_err(|e| SceneError::Toml(e.to_string()))
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
        if self.output.every == 0 {
            return Err(field("output.every", "0 is not allowed: an integer >= 1"));
        }
        match (&self.bar, &self.beam) {
            (Some(b), None) => Ok(Scene::Bar(Box::new(validate_bar(b, limits)?))),
            (None, Some(b)) => validate_beam(b, limits),
            _ => Err(field("bar/beam", "give exactly one of the tables [bar] and [beam]")),
        }
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

fn validate_bar(b: &BarToml, limits: &Limits) -> Result<BarRun, SceneError> {
    let mass: BarMass = b.mass.parse().map_err(|e| field("bar.mass", e))?;
    let scheme: SchemeSpec = b.scheme.parse().map_err(|e| field("bar.scheme", e))?;
    if scheme.needs_massless_node() && !mass.massless_contact_node() {
        return Err(field("bar.mass", format!("scheme {scheme} needs a massless contact node: mod, mod1, mod2, mod3, transfer or singular (got {mass})")));
    }
    if scheme.needs_massive_node() && mass.massless_contact_node() {
        return Err(field("bar.mass", format!("scheme {scheme} needs a massive contact node: std or lumped (got {mass})")));
    }
    if b.elements < 2 {
        return Err(field("bar.elements", format!("{} is not allowed: an integer >= 2", b.elements)));
    }
    fits("bar.elements", b.elements, false, limits)?;
    let (problem, benchmark, default_t) = match &b.benchmark {
        Some(name) => {
            for (k, given) in [("length", b.length.is_some()), ("wave_speed", b.wave_speed.is_some()), ("far_end", b.far_end.is_some()), ("gap", b.gap.is_some()), ("body_force", b.body_force.is_some()), ("initial_displacement", b.initial_displacement.is_some()), ("initial_velocity", b.initial_velocity.is_some())] {
                if given {
                    return Err(field(&format!("bar.{k}"), "comes from the benchmark: remove it, or remove `benchmark`"));
                }
            }
            let bench: Benchmark = name.parse().map_err(|e| field("bar.benchmark", e))?;
            let t = bench.default_ratio_and_horizon().1;
            let t_end = b.t_end.unwrap_or(t);
            let exact = bench.exact(positive("bar.t_end", t_end)?).map_err(|e| field("bar.t_end", e))?;
            let p = bench.problem(exact.as_ref(), b.elements, mass).map_err(|e| field("bar", e))?;
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
            let gap = finite("bar.gap", b.gap.unwrap_or(0.0))?;
            let f = finite("bar.body_force", b.body_force.unwrap_or(0.0))?;
            let u0 = InitialField::compile("bar.initial_displacement", b.initial_displacement.as_ref().ok_or_else(|| field("bar.initial_displacement", "required without a benchmark"))?)?;
            let v0 = InitialField::compile("bar.initial_velocity", b.initial_velocity.as_ref().unwrap_or(&FieldToml::Number(0.0)))?;
            // The stiffness entries are c² m / L.
            let k = c * c * b.elements as f64 / length;
            if !(k.is_finite() && k >= f64::MIN_POSITIVE && (length / b.elements as f64) >= f64::MIN_POSITIVE) {
                let key = extreme_key(&[("bar.wave_speed", b.wave_speed), ("bar.length", b.length)]).map_or("bar.elements", |(k, _)| k);
                return Err(field(key, format!("wave_speed = {c:e}, length = {length:e}, elements = {}: the stiffness c² m / L or the element size L / m leaves the floating-point range; allowed: 2.2e-308 <= c² m / L < 1.8e308 and L / m >= 2.2e-308", b.elements)));
            }
            let bar = Bar::new(length, b.elements, c, end).map_err(|e| field("bar", e))?;
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
    let dt = match (b.dt, b.ratio) {
        (Some(dt), None) => positive("bar.dt", dt)?,
        (None, Some(r)) => problem.bar.h() / positive("bar.ratio", r)?,
        (None, None) => return Err(field("bar.dt", "give dt or ratio (= dx/dt)")),
        (Some(_), Some(_)) => return Err(field("bar.ratio", "give dt or ratio, not both")),
    };
    let t_end = positive("bar.t_end", b.t_end.unwrap_or(default_t))?;
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
    // An overflow comes from an extreme number (beyond 1e100) if one is given.
    let numbers = [("bar.body_force", b.body_force), ("bar.gap", b.gap), ("bar.length", b.length), ("bar.wave_speed", b.wave_speed), ("bar.dt", b.dt), ("bar.ratio", b.ratio)];
    let overflow_key = extreme_key(&numbers).filter(|(_, scale)| *scale > 100.0).map_or("bar", |(k, _)| k);
    scheme.build(problem.dynamics(), dt, &problem.initial).map_err(|e| scheme_error(e, overflow_key))?;
    Ok(BarRun { problem, benchmark, scheme, dt, t_end })
}

fn validate_beam(b: &BeamToml, limits: &Limits) -> Result<Scene, SceneError> {
    let base = match &b.scene {
        Some(name) => *BeamScene::PAPER.iter().find(|s| s.name == name).ok_or_else(|| field("beam.scene", format!("{name:?} is not allowed: fig2, fig3, fig4, fig5, fig6, fig7 or fig8")))?,
        None => BeamScene { name: "custom", elements: 19, dt: 1e-5, t_end: 2.0, contact: BeamContact::Projection { beta: 0.5 }, paper_seconds: None },
    };
    let elements = b.elements.unwrap_or(base.elements);
    if elements < 1 {
        return Err(field("beam.elements", "0 is not allowed: an integer >= 1"));
    }
    fits("beam.elements", elements, true, limits)?;
    let dt = positive("beam.dt", b.dt.unwrap_or(base.dt))?;
    let t_end = positive("beam.t_end", b.t_end.unwrap_or(base.t_end))?;
    if t_end / dt > 1e9 {
        return Err(field("beam.dt", format!("{dt} gives {:.3e} steps: at most 1e9", t_end / dt)));
    }
    horizon("beam", dt, t_end)?;
    if dt > 1e100 {
        return Err(field("beam.dt", format!("{dt:e} is not allowed: at most 1e100 (dt² enters the step matrix)")));
    }
    let contact = match b.contact.as_deref() {
        None => match base.contact {
            BeamContact::Projection { beta } => BeamContact::Projection { beta: b.beta.unwrap_or(beta) },
            BeamContact::Penalty { stiffness } => BeamContact::Penalty { stiffness: b.penalty_stiffness.unwrap_or(stiffness) },
        },
        Some("projection") => BeamContact::Projection { beta: b.beta.unwrap_or(0.5) },
        Some("penalty") => BeamContact::Penalty { stiffness: b.penalty_stiffness.unwrap_or(1e8) },
        Some(other) => return Err(field("beam.contact", format!("{other:?} is not allowed: \"projection\" or \"penalty\""))),
    };
    match contact {
        BeamContact::Projection { beta } if !(0.0..=0.5).contains(&beta) => return Err(field("beam.beta", format!("{beta} is not allowed: [0, 1/2]"))),
        BeamContact::Penalty { stiffness } => {
            positive("beam.penalty_stiffness", stiffness)?;
        }
        _ => {}
    }
    // Every key acts or is refused: β belongs to the projection's β-scheme,
    // the stiffness to the penalty (whose Newmark scheme has β = 1/4).
    match contact {
        BeamContact::Penalty { .. } if b.beta.is_some() => {
            return Err(field("beam.beta", "acts only with contact = \"projection\" (the β-scheme); the penalty contact integrates with Newmark β = 1/4: remove beta, or set contact = \"projection\""));
        }
        BeamContact::Projection { .. } if b.penalty_stiffness.is_some() => {
            return Err(field("beam.penalty_stiffness", "acts only with contact = \"penalty\": remove it, or set contact = \"penalty\""));
        }
        _ => {}
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
    if let Some([a, w]) = b.support {
        pipe.support = (finite("beam.support", a)?, positive("beam.support", w)?);
        // The lifted load is A ω² h(x) + 8 A k²/L⁴, its velocity A ω h(x).
        if !(a * w * w).is_finite() {
            return Err(field("beam.support", format!("[{a}, {w}] is not allowed: A ω² must be finite (< 1.8e308)")));
        }
    }
    let scene = BeamScene { name: "scene", elements, dt, t_end, contact, paper_seconds: base.paper_seconds };
    build_beam(&pipe, &scene, b.force).map_err(|e| match e {
        RunError::Unstable { .. } => field("beam.dt", e),
        RunError::Scheme(SchemeError::PenaltyTooStiff { max, .. }) => {
            let k = match contact {
                BeamContact::Penalty { stiffness } => stiffness,
                BeamContact::Projection { .. } => f64::NAN,
            };
            // The scheme sees κ = k/(ρS): back to N/m.
            field("beam.penalty_stiffness", format!("{k:e} N/m makes the contact law ill-posed in floating point at this mesh and dt (the spring is more than 1e12 times stiffer than the beam at its tip); usable range: 0 < penalty_stiffness <= {:.3e} N/m", max * pipe.rho_s))
        }
        e @ RunError::BlowUp { .. } => field("beam", format!("{e}: the data overflow in the first step; allowed: data whose first step is finite")),
        e => field("beam", e),
    })?;
    Ok(Scene::Beam { pipe, scene, force: b.force })
}
