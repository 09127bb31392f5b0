//! Parameter sweeps of a scene (`signorini sweep`) and the merge of their
//! shards (`signorini merge`).
//!
//! Three forcing frequencies of the impact oscillator, each run sampled at
//! the forcing period:
//!
//! ```
//! use signorini_scene::Limits;
//! use signorini_sweep::{run, NoProgress, Sweep, SweepOptions};
//!
//! let scene = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.8\ndt = 1e-3\nt_end = 1.0\n[forcing]\namplitude = 1.0\nomega = 2.0\n";
//! let mut opts = SweepOptions::new("forcing.omega", 1.5, 2.5, 3);
//! (opts.transient, opts.record) = (5.0, 5.0);
//! let sweep = Sweep::new(scene, "oscillator.toml", None, opts, Limits::machine())?;
//! let dir = std::env::temp_dir().join(format!("signorini-doctest-sweep-{}", std::process::id()));
//! let _ = std::fs::remove_dir_all(&dir);
//! let report = run(&sweep, &dir, &NoProgress)?;
//! assert_eq!((report.runs, report.failed), (3, 0));
//! // One summary row per run, and its Poincaré samples at t = 5T, 6T, …, 10T.
//! let summary = std::fs::read_to_string(dir.join("summary.csv"))?;
//! assert_eq!(summary.lines().count(), 1 + 3);
//! assert_eq!(std::fs::read_to_string(dir.join("sweep.csv"))?.lines().count(), 1 + 3 * 6);
//! std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A sweep runs one scene many times, each with one numeric field — named by
//! its dotted path in the scene document, `forcing.omega`, `support.amplitude`,
//! `stop.0.hi` — set to a value of a linear or logarithmic grid, and reads
//! each run as vibro-impact papers do: stroboscopic (Poincaré) samples at the
//! forcing period after a transient, the impacts, and summary statistics.
//! The horizon of every run is `transient + record` forcing periods (rounded
//! to whole steps), replacing the scene's `t_end`.
//!
//! Output folder (a contract; columns only ever added):
//! * `sweep.csv` — `param,run,t,displacement,velocity,phase`: one row per
//!   Poincaré sample at `t = (k + phase/2π)·2π/Ω` (k integer, time from the
//!   run's start, `phase` the section's forcing phase, `--phase`, default 0)
//!   in the record window: the oscillator's displacement, the beam's tip,
//!   the bar's contact end;
//! * `summary.csv` — one row per run: `param,run,` then the statistics of
//!   [`signorini_run::vibro`] (`impacts,impacts_per_period,…,period`), then
//!   `steps,status` (`ok`, or why the run stopped: a blow-up keeps the rows
//!   of the sweep going);
//! * `impacts.csv` — `param,run,stop,t,phase,velocity,impulse,duration`: the
//!   impacts of the record window (the data of the impact map);
//! * `bifurcation.svg` (Poincaré displacement against the parameter) and
//!   `impact_map.svg` (pre-impact velocity against forcing phase);
//! * `sweep.toml` — the manifest (written and read with the toml crate): the sweep's id (a hash of the scene text
//!   and every option that changes a number), its options, and with
//!   `--shard I/N` the shard.
//!
//! Rows are written in run order, whatever the number of threads: runs go
//! in batches, each batch in parallel, and a batch's rows are written in
//! order when all of it is done, so the files always hold a whole prefix
//! of runs (`--resume` continues after it). `--shard I/N` runs the I-th of
//! N contiguous blocks of runs; [`merge`] concatenates the shards' files in
//! order into exactly the files of the unsharded sweep.

use rayon::prelude::*;
use signorini_plot::{impact_map, scatter, thin, Chart, Scale, Series, Style};
use signorini_run::reduced::Need;
use signorini_run::vibro::{Piece, Summary, VibroConfig};
use signorini_run::{run_lockstep, Cancel, LockstepRun, Observer, RunConfig, RunError, Sample};
use signorini_scene::{io_reason, BuildError, Limits, Reads, Scene, SceneError, SceneFile};
use signorini_schemes::{Bounds, Initial, LockstepLane, PaoliSchatzmanLockstep};
use std::fmt::Write as _;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

/// A run's value(s): the first axis's, and the second's on a map.
type Values = (f64, Option<f64>);
/// A validated scene at a value and its clock.
type ScenePlan = (Scene, Plan);
/// A run of a batch: its index, value(s) and scene (or why it has none).
type Prepared = (usize, Values, Result<ScenePlan, Error>);
/// A displacement and velocity to start a run from (a followed sweep).
type StartState = (Vec<f64>, Vec<f64>);

/// Header of `sweep.csv`.
pub const SWEEP_COLUMNS: &str = "param,run,t,displacement,velocity,phase";
/// Header of `impacts.csv` in a sweep folder.
pub const IMPACT_COLUMNS: &str = "param,run,stop,t,phase,velocity,impulse,duration";
/// The files a sweep writes.
pub const SWEEP_FILES: [&str; 6] = ["sweep.csv", "summary.csv", "impacts.csv", "bifurcation.svg", "impact_map.svg", "sweep.toml"];

/// What a sweep's command line gave that is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SweepError {
    /// An option out of range.
    #[error("--{option}: {message}")]
    Option {
        /// The option (`count`, `from`, `shard`, …).
        option: &'static str,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The parameter path names no numeric field of the scene.
    #[error("--param {path}: {message}")]
    Param {
        /// The path given.
        path: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The scene with a swept value is invalid.
    #[error("--param {path} = {}: {error}", num(*value))]
    Value {
        /// The path.
        path: String,
        /// The value.
        value: f64,
        /// The scene's error.
        error: SceneError,
    },
    /// The scene cannot be swept (no periodic forcing to sample at).
    #[error("{0}")]
    Scene(String),
    /// Shards that do not make one sweep, or a folder to resume that is not this sweep's.
    #[error("{0}")]
    Folder(String),
}

pub use signorini_run::text::num;

/// Why a sweep or a merge stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The sweep's options, parameter path, values, shards or folder.
    #[error(transparent)]
    Options(#[from] SweepError),
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A scene could not be instantiated.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A file of the sweep's folder could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The output folder cannot be created.
    #[error("--out {}: {source}", path.display())]
    OutFolder {
        /// The folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The sweep was cancelled between runs: whole runs are kept.
    #[error("interrupted after {done} of {total} runs (whole runs kept in {dir}); continue with --resume")]
    Interrupted {
        /// Runs written.
        done: usize,
        /// Runs of the sweep (or shard).
        total: usize,
        /// The folder.
        dir: String,
    },
    /// The thread pool could not be built.
    #[error("thread pool: {0}")]
    ThreadPool(#[source] rayon::ThreadPoolBuildError),
    /// A run's rows went missing in a batch (a bug).
    #[error("a run went missing")]
    MissingRun,
}

impl Error {
    /// Whether the input was bad (options, scene, values, folder: nothing
    /// or not all was run), as opposed to a failure while running or
    /// writing. `signorini sweep` exits 2 for these.
    pub fn is_bad_input(&self) -> bool {
        matches!(self, Error::Options(_) | Error::Scene(_) | Error::OutFolder { .. } | Error::Build(BuildError::Scene(_)))
    }
}

/// How far a sweep is: the engine calls it as runs finish (from several
/// threads). The CLI draws a progress bar with it; a caller that does not
/// watch passes [`NoProgress`].
pub trait Progress: Sync {
    /// The sweep starts: `total` runs, of which `done` are already in the
    /// folder (a resumed sweep).
    fn start(&self, _total: u64, _done: u64) {}
    /// `runs` more runs are done.
    fn advance(&self, _runs: u64) {}
    /// The sweep stopped (finished, interrupted or failed).
    fn finish(&self) {}
}

/// A [`Progress`] that shows nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}

/// A second axis of a two-parameter map.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// Dotted path of the field.
    pub param: String,
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Number of values (>= 1).
    pub count: usize,
    /// Logarithmic spacing.
    pub log: bool,
}

/// The value `i` of `count` on `[from, to]`, linear or logarithmic, the
/// ends exact.
fn grid(from: f64, to: f64, count: usize, log: bool, i: usize) -> f64 {
    if count == 1 || i == 0 {
        return from;
    }
    if i + 1 == count {
        return to;
    }
    let s = i as f64 / (count - 1) as f64;
    if log {
        from * (to / from).powf(s)
    } else {
        from + (to - from) * s
    }
}

/// Checks one axis' range.
fn check_axis(suffix: &'static str, from: f64, to: f64, count: usize, log: bool) -> Result<(), SweepError> {
    let name = |o: &'static str| -> &'static str {
        match (o, suffix) {
            ("count", "") => "count",
            ("from", "") => "from",
            ("to", "") => "to",
            ("count", _) => "count2",
            ("from", _) => "from2",
            _ => "to2",
        }
    };
    let opt = |option, message: String| Err(SweepError::Option { option, message });
    if count == 0 {
        return opt(name("count"), "0 is not allowed: an integer >= 1".into());
    }
    if !from.is_finite() {
        return opt(name("from"), format!("{} is not allowed: a finite number", num(from)));
    }
    if !to.is_finite() {
        return opt(name("to"), format!("{} is not allowed: a finite number", num(to)));
    }
    if log && !(from > 0.0) {
        return opt(name("from"), format!("{} is not allowed with --log: > 0", num(from)));
    }
    if log && !(to > 0.0) {
        return opt(name("to"), format!("{} is not allowed with --log: > 0", num(to)));
    }
    Ok(())
}

/// The options of a sweep ([`SweepOptions::new`], then the fields).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct SweepOptions {
    /// Dotted path of the swept field.
    pub param: String,
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Number of runs (>= 1).
    pub count: usize,
    /// Logarithmic spacing (both bounds > 0).
    pub log: bool,
    /// A second swept field (a two-parameter map): run `r` takes value
    /// `r mod count` of the first axis and `r div count` of this one.
    pub second: Option<Axis>,
    /// Forcing periods before the record window (>= 0).
    pub transient: f64,
    /// Forcing periods recorded (> 0).
    pub record: f64,
    /// Forcing phase of the Poincaré section, in [0, 2π).
    pub phase: f64,
    /// Relative tolerance of the response-period test (in (0, 1); default
    /// 1e-3 of the tip's displacement and velocity ranges).
    pub period_tol: f64,
    /// Write `impacts.csv` and `impact_map.svg` (the statistics in
    /// `summary.csv` are computed either way). A chattering beam makes
    /// hundreds of impacts per period: `--no-impacts` keeps the folder small.
    pub impacts: bool,
    /// Start each run from the previous run's final state.
    pub follow: bool,
    /// Run only the `I`-th (0-based) of `N` blocks: `(I, N)`.
    pub shard: Option<(usize, usize)>,
    /// Continue a folder that holds a prefix of this sweep's runs.
    pub resume: bool,
    /// Threads (None: rayon's default, all cores).
    pub threads: Option<usize>,
    /// Stop cleanly when cancelled (keeps whole runs written).
    pub interrupt: Option<Cancel>,
}

impl SweepOptions {
    /// A sweep of `param` over `[from, to]` with `count` runs and the
    /// defaults: linear, 100 transient periods, 10 recorded, phase 0.
    pub fn new(param: &str, from: f64, to: f64, count: usize) -> Self {
        Self {
            param: param.into(),
            from,
            to,
            count,
            log: false,
            second: None,
            transient: 100.0,
            record: 10.0,
            phase: 0.0,
            period_tol: 1e-3,
            impacts: true,
            follow: false,
            shard: None,
            resume: false,
            threads: None,
            interrupt: None,
        }
    }

    /// Checks the options (not the path: [`Sweep::new`] does, on the scene).
    pub fn validate(&self) -> Result<(), SweepError> {
        let opt = |option, message: String| Err(SweepError::Option { option, message });
        check_axis("", self.from, self.to, self.count, self.log)?;
        if let Some(a) = &self.second {
            check_axis("2", a.from, a.to, a.count, a.log)?;
            if a.param == self.param {
                return Err(SweepError::Param { path: a.param.clone(), message: "--param2 names the same field as --param: a map needs two fields".into() });
            }
        }
        let total = self.total();
        if total > 100_000_000 {
            return opt("count", format!("{total} runs are not allowed: at most 1e8 per sweep"));
        }
        if !(self.transient >= 0.0 && self.transient.is_finite()) {
            return opt("transient", format!("{} is not allowed: forcing periods, finite and >= 0", num(self.transient)));
        }
        if !(self.record > 0.0 && self.record.is_finite()) {
            return opt("record", format!("{} is not allowed: forcing periods, finite and > 0", num(self.record)));
        }
        if !(self.phase >= 0.0 && self.phase < std::f64::consts::TAU) {
            return opt("phase", format!("{} is not allowed: a forcing phase in [0, 2π)", num(self.phase)));
        }
        if !(self.period_tol > 0.0 && self.period_tol < 1.0) {
            return opt("period-tol", format!("{} is not allowed: in (0, 1)", num(self.period_tol)));
        }
        if let Some((i, n)) = self.shard {
            if n == 0 || i >= n {
                return opt("shard", format!("{i}/{n} is not allowed: I/N with N >= 1 and 0 <= I < N"));
            }
            if n > total {
                return opt("shard", format!("{i}/{n} is not allowed: at most as many shards as runs ({total})"));
            }
            if self.follow {
                return opt("shard", "is not allowed with --follow: a followed sweep is one sequence of runs, each starting from the last one's state".into());
            }
        }
        if self.threads == Some(0) {
            return opt("threads", "0 is not allowed: an integer >= 1".into());
        }
        Ok(())
    }

    /// Number of runs: `count`, times `count2` for a map.
    pub fn total(&self) -> usize {
        self.count.saturating_mul(self.second.as_ref().map_or(1, |a| a.count))
    }

    /// The values of run `r`: on the first axis `from + (to − from)
    /// i/(count − 1)` (or `from (to/from)^(i/(count − 1))` with `--log`; the
    /// last value is `to` exactly) with `i = r mod count`, and on the
    /// second axis likewise with `r div count`.
    pub fn value(&self, r: usize) -> (f64, Option<f64>) {
        let i = r % self.count;
        let p = grid(self.from, self.to, self.count, self.log, i);
        (p, self.second.as_ref().map(|a| grid(a.from, a.to, a.count, a.log, r / self.count)))
    }

    /// The runs of this shard (all runs without one): block `I` of `N`
    /// contiguous blocks, `[I·total/N, (I+1)·total/N)`.
    pub fn runs(&self) -> std::ops::Range<usize> {
        let total = self.total();
        match self.shard {
            None => 0..total,
            Some((i, n)) => (i * total / n)..((i + 1) * total / n),
        }
    }
}

/// FNV-1a (64 bit): a stable, portable hash for sweep ids.
fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Sets the numeric field at `path` in a scene document to `value`.
/// Segments are keys, or array indices (`stop.0.hi`). The parent must
/// exist; an existing value must be a number. An integral value goes in as
/// an integer, another as a float: the scene's parse refuses a fraction in
/// an integer field (and [`Sweep::new`] refuses a grid that gives one).
pub fn set_path(doc: &mut toml::Table, path: &str, value: f64) -> Result<(), SweepError> {
    let err = |m: String| SweepError::Param { path: path.into(), message: m };
    let segs: Vec<&str> = path.split('.').collect();
    if segs.iter().any(|s| s.is_empty()) {
        return Err(err("a dotted path of keys and array indices, e.g. forcing.omega, support.amplitude, stop.0.hi".into()));
    }
    let (last, parents) = segs.split_last().ok_or_else(|| err("empty".into()))?;
    let mut here = toml::Value::Table(std::mem::take(doc));
    let result = (|| {
        let mut cur = &mut here;
        let mut walked = String::new();
        for s in parents {
            let name = if walked.is_empty() { s.to_string() } else { format!("{walked}.{s}") };
            let hint = keys_hint(cur, &walked);
            cur = step(cur, s).ok_or_else(|| err(format!("{name} is not in the scene{hint}")))?;
            walked = name;
        }
        let table = match cur {
            toml::Value::Table(t) => t,
            toml::Value::Array(a) => {
                let i: usize = last.parse().map_err(|_| err(format!("{walked} is a list: the next segment is an index 0..{}", a.len())))?;
                let len = a.len();
                let slot = a.get_mut(i).ok_or_else(|| err(format!("{walked} has {len} entries: index {i} is out of range")))?;
                return put(slot, value, path);
            }
            _ => return Err(err(format!("{walked} is a value, not a table"))),
        };
        match table.get_mut(*last) {
            Some(slot) => put(slot, value, path),
            None => {
                // A key the scene leaves at its default: validation decides.
                // An integral value goes in as an integer, which integer
                // fields need and real fields take.
                let v = if value.fract() == 0.0 && value.abs() <= 9.0e15 { toml::Value::Integer(value as i64) } else { toml::Value::Float(value) };
                table.insert(last.to_string(), v);
                Ok(())
            }
        }
    })();
    if let toml::Value::Table(t) = here {
        *doc = t;
    }
    result
}

/// Whether `path` names an integer field of the scene: the document parses
/// with an integer there and not with a fraction.
fn integer_field(doc: &toml::Table, path: &str) -> bool {
    let parses = |v: f64| {
        let mut d = doc.clone();
        set_path(&mut d, path, v).is_ok() && SceneFile::from_table(d).is_ok()
    };
    parses(1.0) && !parses(0.5)
}

/// Refuses the grid of an axis over an integer field that gives a value
/// that is not an integer (or beyond 9e15), naming the value, its index
/// and a count that would do.
fn integral_grid(doc: &toml::Table, path: &str, suffix: &str, from: f64, to: f64, count: usize, log: bool) -> Result<(), SweepError> {
    let bad = |i: usize, v: f64| -> Option<String> {
        if v.fract() == 0.0 && v.abs() <= 9.0e15 {
            return None;
        }
        let grid = format!("--from{suffix} {} --to{suffix} {} --count{suffix} {count}{}", num(from), num(to), if log { format!(" --log{suffix}") } else { String::new() });
        let d = (to - from).abs();
        let hint = if v.abs() > 9.0e15 {
            String::new()
        } else if log {
            format!(" (a --log{suffix} grid gives integers only at its ends: sweep linearly)")
        } else if from.fract() == 0.0 && to.fract() == 0.0 && d <= 9.0e15 && count <= 1_000_000 {
            // The largest count up to this one whose step divides to − from.
            let c = (2..=count).rev().find(|c| d % (*c as f64 - 1.0) == 0.0).unwrap_or(1);
            format!(" (e.g. --count{suffix} {c}: (count − 1) must divide |to − from| = {})", num(d))
        } else {
            format!(" (--from{suffix} and --to{suffix} integral, (count − 1) dividing their difference)")
        };
        Some(format!("an integer field: {grid} gives {} (value {i} of 0..{count}): allowed integral values of magnitude at most 9e15 only{hint}", num(v)))
    };
    match (0..count).find_map(|i| bad(i, grid(from, to, count, log, i))) {
        Some(message) if integer_field(doc, path) => Err(SweepError::Param { path: path.into(), message }),
        _ => Ok(()),
    }
}

fn step<'a>(v: &'a mut toml::Value, seg: &str) -> Option<&'a mut toml::Value> {
    match v {
        toml::Value::Table(t) => t.get_mut(seg),
        toml::Value::Array(a) => seg.parse::<usize>().ok().and_then(move |i| a.get_mut(i)),
        _ => None,
    }
}

fn keys_hint(v: &toml::Value, walked: &str) -> String {
    match v {
        toml::Value::Table(t) if !t.is_empty() => {
            let keys: Vec<&str> = t.keys().map(String::as_str).collect();
            format!(" ({} has: {})", if walked.is_empty() { "the scene" } else { walked }, keys.join(", "))
        }
        _ => String::new(),
    }
}

fn put(slot: &mut toml::Value, value: f64, path: &str) -> Result<(), SweepError> {
    let err = |m: String| SweepError::Param { path: path.into(), message: m };
    match slot {
        toml::Value::Float(_) => *slot = toml::Value::Float(value),
        // An integer literal: an integral value stays one; another goes in
        // as a float, which a real field written `omega = 10` takes and an
        // integer field refuses ([`Sweep::new`] checks the grid of one).
        toml::Value::Integer(_) if value.fract() == 0.0 && value.abs() <= 9.0e15 => *slot = toml::Value::Integer(value as i64),
        toml::Value::Integer(_) => *slot = toml::Value::Float(value),
        other => return Err(err(format!("names a {} value, not a number", other.type_str()))),
    }
    Ok(())
}

/// One run's results, as rows.
#[derive(Clone, Debug, Default)]
pub struct RunRows {
    /// `sweep.csv` rows (without `param,run,`): `t,displacement,velocity,phase`.
    pub poincare: Vec<[f64; 4]>,
    /// `impacts.csv` rows (without `param,run,`): stop, then `t,phase,velocity,impulse,duration`.
    pub impacts: Vec<(usize, [f64; 5])>,
    /// The statistics columns of `summary.csv`, already formatted.
    pub summary: String,
    /// Steps taken.
    pub steps: usize,
    /// `ok` or why the run stopped.
    pub status: String,
    /// The final state (for `--follow`): displacement and velocity.
    pub state: Option<(Vec<f64>, Vec<f64>)>,
}

/// A validated sweep of a scene.
pub struct Sweep {
    opts: SweepOptions,
    doc: toml::Table,
    id: String,
    limits: Limits,
    scene_name: String,
    base: Option<PathBuf>,
}

impl Sweep {
    /// Checks the options and the path, that an integer field's grid gives
    /// integral values only, and the scene at the first and last values (so
    /// a sweep fails at once; [`run`] checks every value before it runs).
    pub fn new(scene_text: &str, scene_name: &str, base: Option<PathBuf>, opts: SweepOptions, limits: Limits) -> Result<Self, Error> {
        opts.validate()?;
        let doc: toml::Table = toml::from_str(scene_text).map_err(SceneError::Toml)?;
        let mut h = fnv1a(scene_text.as_bytes(), 0xcbf2_9ce4_8422_2325);
        let mut key = format!(
            "|{}|{:016x}|{:016x}|{}|{}|{:016x}|{:016x}|{:016x}|{}|{:016x}",
            opts.param,
            opts.from.to_bits(),
            opts.to.to_bits(),
            opts.count,
            opts.log,
            opts.transient.to_bits(),
            opts.record.to_bits(),
            opts.phase.to_bits(),
            opts.follow,
            opts.period_tol.to_bits()
        );
        if !opts.impacts {
            key += "|no-impacts";
        }
        if let Some(a) = &opts.second {
            key += &format!("|{}|{:016x}|{:016x}|{}|{}", a.param, a.from.to_bits(), a.to.to_bits(), a.count, a.log);
        }
        h = fnv1a(key.as_bytes(), h);
        // A key that would not act is refused: the sweep's runs are not
        // watched by the energy monitor of `signorini run`.
        if doc.get("output").and_then(|o| o.get("energy_warn")).is_some() {
            return Err(signorini_scene::field(
                "output.energy_warn",
                "is not allowed in a sweep: its runs are not watched against their energy budget (run one value with `signorini run` for the warning); allowed: no energy_warn",
            )
            .into());
        }
        let sweep = Self { id: format!("{h:016x}"), opts, doc, limits, scene_name: scene_name.into(), base };
        let o = &sweep.opts;
        integral_grid(&sweep.doc, &o.param, "", o.from, o.to, o.count, o.log)?;
        if let Some(a) = &o.second {
            integral_grid(&sweep.doc, &a.param, "2", a.from, a.to, a.count, a.log)?;
        }
        let last = sweep.opts.total() - 1;
        for r in [0, last] {
            sweep.scene(sweep.opts.value(r))?;
        }
        Ok(sweep)
    }

    /// A sweep of the scene file `path` (its text `text`): files the scene
    /// names are found next to it.
    pub fn from_file(path: &Path, text: &str, opts: SweepOptions, limits: Limits) -> Result<Self, Error> {
        let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned());
        Self::new(text, &name, path.parent().map(Path::to_path_buf), opts, limits)
    }

    /// The sweep's id (hash of the scene text and the options that change numbers).
    pub fn id(&self) -> &str {
        &self.id
    }

    /// The options.
    pub fn options(&self) -> &SweepOptions {
        &self.opts
    }

    /// The scene document with the swept field(s) at `value`.
    pub fn document(&self, value: (f64, Option<f64>)) -> Result<toml::Table, SweepError> {
        let mut doc = self.doc.clone();
        set_path(&mut doc, &self.opts.param, value.0)?;
        if let (Some(a), Some(v)) = (&self.opts.second, value.1) {
            set_path(&mut doc, &a.param, v)?;
        }
        Ok(doc)
    }

    /// The validated scene at `value`, its horizon set to the sweep's.
    pub fn scene(&self, value: (f64, Option<f64>)) -> Result<(SceneFile, Scene, Plan), Error> {
        // A map's error names both values: `--param P = v, --param2 Q = w`.
        let (path, shown) = match (&self.opts.second, value.1) {
            (Some(a), Some(v)) => (format!("{} = {}, --param2 {}", self.opts.param, num(value.0), a.param), v),
            _ => (self.opts.param.clone(), value.0),
        };
        let bad = |e: SceneError| SweepError::Value { path: path.clone(), value: shown, error: e };
        let doc = self.document(value)?;
        let parse = |doc: toml::Table| -> Result<SceneFile, SweepError> {
            let mut f = SceneFile::from_table(doc).map_err(bad)?;
            f.base = self.base.clone();
            Ok(f)
        };
        // The forcing and dt first, the scene's own horizon left aside: the
        // sweep's replaces it (a swept dt need not divide the scene's t_end).
        let file = parse(doc.clone())?;
        let scene = file.validate_clock(&self.limits).map_err(bad)?;
        let (omega, dt, key) = scene.sweep_clock().ok_or_else(|| {
            SweepError::Scene(format!(
                "{}: a sweep samples the response at the forcing period, and this scene has no periodic forcing (an oscillator's [forcing], a beam's support motion)",
                self.scene_name
            ))
        })?;
        let period = std::f64::consts::TAU / omega;
        let total = self.opts.transient + self.opts.record;
        let steps = (total * period / dt).round().max(1.0);
        let t_end = steps * dt;
        let mut doc = doc;
        set_path(&mut doc, key, t_end).map_err(|e| SweepError::Scene(format!("cannot set the horizon {key}: {e}")))?;
        let file = parse(doc)?;
        let scene = file.validate_with(&self.limits).map_err(bad)?;
        Ok((file, scene, Plan { omega, dt, t_end, record_from: self.opts.transient * period, phase: self.opts.phase, period_tol: self.opts.period_tol }))
    }

    /// The manifest of this sweep (of `shard` of it).
    fn manifest(&self, shard: Option<(usize, usize)>) -> Manifest {
        let o = &self.opts;
        let a = o.second.as_ref();
        Manifest {
            id: self.id.clone(),
            scene: self.scene_name.clone(),
            param: o.param.clone(),
            from: o.from,
            to: o.to,
            count: o.count,
            log: o.log,
            param2: a.map(|a| a.param.clone()),
            from2: a.map(|a| a.from),
            to2: a.map(|a| a.to),
            count2: a.map(|a| a.count),
            log2: a.map(|a| a.log),
            transient: o.transient,
            record: o.record,
            phase: o.phase,
            period_tol: o.period_tol,
            follow: o.follow,
            impacts: (!o.impacts).then_some(false),
            shard: shard.map(|(i, n)| [i, n]),
            runs: shard.map(|_| [o.runs().start, o.runs().end]),
        }
    }
}

/// The first line of `sweep.toml`.
const MANIFEST_HEADER: &str = "# signorini sweep manifest: merge checks that shards share the id\n";

/// `sweep.toml`: the sweep's id, scene and options (the second axis of a
/// map, `impacts = false` with `--no-impacts`, and a shard's `shard` and
/// `runs` only when they apply), written with the toml crate in this
/// field order after [`MANIFEST_HEADER`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    id: String,
    scene: String,
    param: String,
    from: f64,
    to: f64,
    count: usize,
    log: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    param2: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    from2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    to2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    count2: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    log2: Option<bool>,
    transient: f64,
    record: f64,
    phase: f64,
    period_tol: f64,
    follow: bool,
    /// `Some(false)` with `--no-impacts`; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    impacts: Option<bool>,
    /// `[I, N]` of a shard.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    shard: Option<[usize; 2]>,
    /// The shard's runs `[start, end)`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    runs: Option<[usize; 2]>,
}

impl Manifest {
    /// The text of `sweep.toml`.
    fn text(&self) -> String {
        // Serialising a struct of numbers, strings, booleans and arrays of
        // integers cannot fail.
        format!("{MANIFEST_HEADER}{}", toml::to_string(self).unwrap_or_default())
    }

    /// Reads a `sweep.toml`.
    fn parse(text: &str) -> Result<Self, toml::de::Error> {
        toml::from_str(text)
    }

    /// Whether the runs have a second parameter (a map).
    fn is_map(&self) -> bool {
        self.param2.is_some()
    }
}

/// What a run needs to know of the sweep's clock.
#[derive(Clone, Copy, Debug)]
pub struct Plan {
    /// Forcing angular frequency Ω.
    pub omega: f64,
    /// Time step.
    pub dt: f64,
    /// Horizon (whole steps).
    pub t_end: f64,
    /// Start of the record window.
    pub record_from: f64,
    /// Poincaré section phase.
    pub phase: f64,
    /// Tolerance of the response-period test.
    pub period_tol: f64,
}

fn io(p: &Path, e: std::io::Error) -> Error {
    Error::Io { path: p.to_path_buf(), source: e }
}

/// The rows of one run, formatted: `param,run,<values>[,param2]`.
fn rows_text(value: (f64, Option<f64>), run: usize, r: &RunRows) -> (String, String, String) {
    let (p, p2) = value;
    let tail = p2.map_or(String::new(), |v| format!(",{}", num(v)));
    let p = num(p);
    let mut sw = String::new();
    for row in &r.poincare {
        let _ = writeln!(sw, "{p},{run},{},{},{},{}{tail}", row[0], row[1], row[2], row[3]);
    }
    let mut im = String::new();
    for (stop, v) in &r.impacts {
        let _ = writeln!(im, "{p},{run},{stop},{},{},{},{},{}{tail}", v[0], v[1], v[2], v[3], v[4]);
    }
    let su = format!("{p},{run},{},{},{}{tail}\n", r.summary, r.steps, r.status);
    (sw, im, su)
}

/// The headers of `sweep.csv`, `impacts.csv` (unless `--no-impacts`),
/// `summary.csv` (`,param2` last for a map).
fn headers(map: bool, impacts: bool) -> Vec<(&'static str, String)> {
    let tail = if map { ",param2" } else { "" };
    let mut h = vec![("sweep.csv", format!("{SWEEP_COLUMNS}{tail}")), ("summary.csv", format!("{}{tail}", summary_header()))];
    if impacts {
        h.insert(1, ("impacts.csv", format!("{IMPACT_COLUMNS}{tail}")));
    }
    h
}

/// Reads the complete lines of a file (a last line without its newline,
/// cut by a kill, is dropped).
fn complete_lines(p: &Path) -> Result<Vec<String>, Error> {
    let text = std::fs::read_to_string(p).map_err(|e| io(p, e))?;
    Ok(text.split_inclusive('\n').filter(|l| l.ends_with('\n')).map(|l| l.trim_end_matches('\n').to_string()).collect())
}

/// The run index (second column) of a data row.
fn run_of(line: &str) -> Option<usize> {
    line.split(',').nth(1)?.parse().ok()
}

/// The open output files of a sweep.
struct Outputs {
    sweep: File,
    impacts: Option<File>,
    summary: File,
}

impl Outputs {
    fn append(dir: &Path, name: &str) -> Result<File, Error> {
        let p = dir.join(name);
        OpenOptions::new().append(true).open(&p).map_err(|e| io(&p, e))
    }
}

/// What a finished sweep (or shard) did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SweepReport {
    /// Lines for the terminal.
    pub lines: Vec<String>,
    /// Runs of the sweep (of the shard).
    pub runs: usize,
    /// Runs whose status is not `ok` (blow-ups, …), resumed ones included.
    pub failed: usize,
}

/// Whether a `summary.csv` data row is of a run that failed (its status
/// is not `ok`; a map's row ends with `param2` after it).
fn failed_row(line: &str, map: bool) -> bool {
    let line = if map { line.rsplit_once(',').map_or(line, |(a, _)| a) } else { line };
    !line.ends_with(",ok")
}

/// The engine of [`run`], with `simulate(scene, plan, start state)` doing
/// each run that the lockstep engine does not take. Every value of the
/// sweep's (shard's) runs is checked before anything is written: a value
/// that makes the scene invalid is refused ([`SweepError::Value`]).
fn sweep_report<F>(sweep: &Sweep, dir: &Path, simulate: F, progress: &dyn Progress) -> Result<SweepReport, Error>
where
    F: Fn(&Scene, &Plan, Option<&(Vec<f64>, Vec<f64>)>) -> RunRows + Sync,
{
    let o = &sweep.opts;
    let interrupt = o.interrupt.as_ref();
    let runs = o.runs();
    let pool = {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(t) = o.threads {
            b = b.num_threads(t);
        }
        b.build().map_err(Error::ThreadPool)?
    };
    // Every value before the first run (the first invalid one in run order).
    if let Some(r) = pool.install(|| runs.clone().into_par_iter().find_first(|&r| sweep.scene(o.value(r)).is_err())) {
        sweep.scene(o.value(r))?;
    }
    std::fs::create_dir_all(dir).map_err(|source| Error::OutFolder { path: dir.to_path_buf(), source })?;
    let manifest = sweep.manifest(o.shard);
    let mpath = dir.join("sweep.toml");
    let mut first = runs.start;
    let mut state: Option<(Vec<f64>, Vec<f64>)> = None;
    let mut stopped = 0usize;
    if o.resume {
        let old = std::fs::read_to_string(&mpath).map_err(|e| io(&mpath, e))?;
        // The manifests compared as values (a different key, or a file that
        // is not a manifest, is another sweep).
        if Manifest::parse(&old).ok().as_ref() != Some(&manifest) {
            return Err(SweepError::Folder(format!(
                "--resume: {} holds another sweep (its sweep.toml differs: id {} here, {} asked); use a new --out",
                dir.display(),
                manifest_id(&old).as_deref().unwrap_or("?"),
                sweep.id
            ))
            .into());
        }
        let summary = complete_lines(&dir.join("summary.csv"))?;
        let done: Vec<usize> = summary.iter().skip(1).filter_map(|l| run_of(l)).collect();
        // The prefix of runs whose summary row is complete.
        let mut next = runs.start;
        for r in &done {
            if *r == next {
                next += 1;
            }
        }
        first = next;
        // The kept runs' failures count in the sweep's.
        stopped = summary.iter().skip(1).filter(|l| run_of(l).is_some_and(|r| r < first) && failed_row(l, o.second.is_some())).count();
        for (name, header) in headers(o.second.is_some(), o.impacts) {
            let p = dir.join(name);
            let lines = complete_lines(&p)?;
            let mut text = header + "\n";
            for l in lines.iter().skip(1).filter(|l| run_of(l).is_some_and(|r| r < first)) {
                text.push_str(l);
                text.push('\n');
            }
            std::fs::write(&p, text).map_err(|e| io(&p, e))?;
        }
        if o.follow && first > runs.start {
            state = read_state(&dir.join("follow_state.txt"))?;
        }
    } else {
        if let Some(f) = SWEEP_FILES.iter().find(|f| dir.join(f).exists()) {
            return Err(SweepError::Folder(format!("{} holds a sweep's files ({f}): pass --resume to continue that sweep, or choose another --out", dir.display())).into());
        }
        std::fs::write(&mpath, manifest.text()).map_err(|e| io(&mpath, e))?;
        for (name, header) in headers(o.second.is_some(), o.impacts) {
            let p = dir.join(name);
            std::fs::write(&p, header + "\n").map_err(|e| io(&p, e))?;
        }
    }
    let mut out =
        Outputs { sweep: Outputs::append(dir, "sweep.csv")?, impacts: if o.impacts { Some(Outputs::append(dir, "impacts.csv")?) } else { None }, summary: Outputs::append(dir, "summary.csv")? };
    let batch = if o.follow { 1 } else { (2 * LANES * pool.current_num_threads()).max(1) };
    let bar = progress;
    bar.start(runs.len() as u64, (first - runs.start) as u64);
    let start = std::time::Instant::now();
    let mut next = first;
    let mut interrupted = false;
    while next < runs.end {
        if interrupt.is_some_and(Cancel::is_cancelled) {
            interrupted = true;
            break;
        }
        let end = (next + batch).min(runs.end);
        let results: Vec<(usize, Values, Result<RunRows, Error>)> = if o.follow {
            // One run at a time, each from the last one's state.
            let i = next;
            let v = o.value(i);
            // A followed map restarts from the scene's own state on each row.
            let start = if i % o.count == 0 { None } else { state.as_ref() };
            let r = sweep.scene(v).map(|(_, scene, plan)| simulate(&scene, &plan, start));
            bar.advance(1);
            vec![(i, v, r)]
        } else {
            pool.install(|| {
                let prepared: Vec<Prepared> = (next..end).into_par_iter().map(|i| (i, o.value(i), sweep.scene(o.value(i)).map(|(_, s, p)| (s, p)))).collect();
                let jobs = lockstep_jobs(&prepared);
                let done: Vec<Vec<(usize, RunRows)>> = jobs
                    .into_par_iter()
                    .map(|job| {
                        let out = match job.as_slice() {
                            [k] => match &prepared[*k].2 {
                                Ok((scene, plan)) => vec![(*k, simulate(scene, plan, None))],
                                Err(_) => Vec::new(),
                            },
                            ks => {
                                let group: Vec<(&Scene, &Plan)> = ks.iter().filter_map(|k| prepared[*k].2.as_ref().ok().map(|(s, p)| (s, p))).collect();
                                match simulate_lockstep(&group, interrupt) {
                                    Some(rows) => ks.iter().copied().zip(rows).collect(),
                                    None => ks.iter().filter_map(|k| prepared[*k].2.as_ref().ok().map(|(s, p)| (*k, simulate(s, p, None)))).collect(),
                                }
                            }
                        };
                        bar.advance(job.len() as u64);
                        out
                    })
                    .collect();
                let mut rows: Vec<Option<RunRows>> = (0..prepared.len()).map(|_| None).collect();
                for (k, r) in done.into_iter().flatten() {
                    rows[k] = Some(r);
                }
                prepared.into_iter().zip(rows).map(|((i, v, p), r)| (i, v, p.and_then(|_| r.ok_or(Error::MissingRun)))).collect()
            })
        };
        let (mut sw, mut im, mut su) = (String::new(), String::new(), String::new());
        for (i, v, r) in results {
            // A value whose scene is invalid (every value was checked before
            // the first run: only if building it fails now) is a failed run,
            // like a blow-up: the sweep goes on.
            let rows = r.unwrap_or_else(|e| failed(&e));
            if rows.status == "interrupted" {
                interrupted = true;
                break;
            }
            stopped += usize::from(rows.status != "ok");
            let (a, b, c) = rows_text(v, i, &rows);
            sw.push_str(&a);
            im.push_str(&b);
            su.push_str(&c);
            next = i + 1;
            if o.follow {
                state = rows.state.clone();
            }
        }
        out.sweep.write_all(sw.as_bytes()).map_err(|e| io(&dir.join("sweep.csv"), e))?;
        if let Some(f) = out.impacts.as_mut() {
            f.write_all(im.as_bytes()).map_err(|e| io(&dir.join("impacts.csv"), e))?;
        }
        if o.follow {
            write_state(&dir.join("follow_state.txt"), state.as_ref())?;
        }
        out.summary.write_all(su.as_bytes()).map_err(|e| io(&dir.join("summary.csv"), e))?;
        if interrupted {
            break;
        }
    }
    bar.finish();
    let wall = start.elapsed().as_secs_f64();
    if interrupted {
        return Err(Error::Interrupted { done: next - runs.start, total: runs.len(), dir: dir.display().to_string() });
    }
    let mut lines = vec![format!("{} runs in {wall:.3} s ({} of them stopped early: see summary.csv's status)", runs.len() - (first - runs.start), stopped)];
    if o.shard.is_none() {
        lines.extend(plots(dir)?);
    }
    lines.push(format!("wrote {}", dir.display()));
    Ok(SweepReport { lines, runs: runs.len(), failed: stopped })
}

/// The `id` of a manifest's text, also of one that is not this version's.
fn manifest_id(text: &str) -> Option<String> {
    text.parse::<toml::Table>().ok()?.get("id")?.as_str().map(str::to_string)
}

fn write_state(p: &Path, state: Option<&(Vec<f64>, Vec<f64>)>) -> Result<(), Error> {
    let mut s = String::new();
    if let Some((u, v)) = state {
        let join = |x: &[f64]| x.iter().map(|a| format!("{a:?}")).collect::<Vec<_>>().join(",");
        let _ = writeln!(s, "{}\n{}", join(u), join(v));
    }
    std::fs::write(p, s).map_err(|e| io(p, e))
}

fn read_state(p: &Path) -> Result<Option<StartState>, Error> {
    let text = std::fs::read_to_string(p).map_err(|e| io(p, e))?;
    let mut lines = text.lines();
    let parse = |l: Option<&str>| -> Option<Vec<f64>> { l.map(|l| l.split(',').filter_map(|x| x.parse().ok()).collect()) };
    Ok(match (parse(lines.next()), parse(lines.next())) {
        (Some(u), Some(v)) if !u.is_empty() && u.len() == v.len() => Some((u, v)),
        _ => None,
    })
}

/// `summary.csv`'s header.
pub fn summary_header() -> String {
    format!("param,run,{},steps,status", signorini_run::vibro::Summary::csv_header())
}

/// Draws `bifurcation.svg` and `impact_map.svg` from the folder's CSVs.
fn plots(dir: &Path) -> Result<Vec<String>, Error> {
    let mut notes = Vec::new();
    let col = |l: &str, i: usize| l.split(',').nth(i).and_then(|x| x.parse::<f64>().ok()).unwrap_or(f64::NAN);
    let sweep = complete_lines(&dir.join("sweep.csv"))?;
    let (pts, title) = thin(sweep.iter().skip(1).map(|l| (col(l, 0), col(l, 3))).collect(), "bifurcation diagram: Poincaré displacement", "samples");
    // The x axis names the swept parameter, as the manifest records it.
    let param = std::fs::read_to_string(dir.join("sweep.toml"))
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|m| m.get("param").and_then(|p| p.as_str()).map(str::to_string))
        .unwrap_or_else(|| "parameter".into());
    let chart = Chart { title: &title, x_label: &param, y_label: "displacement", scale: Scale::Linear, size: (900, 600) };
    let radius = if pts.len() > 20_000 { 1 } else { 2 };
    match scatter(&chart, &[Series { label: "Poincaré samples".into(), points: pts, reference: false, style: Style::default() }], radius) {
        Ok(svg) => std::fs::write(dir.join("bifurcation.svg"), svg).map_err(|e| io(&dir.join("bifurcation.svg"), e))?,
        Err(e) => notes.push(format!("note: bifurcation.svg not written: {e}")),
    }
    if !dir.join("impacts.csv").exists() {
        return Ok(notes);
    }
    let impacts = complete_lines(&dir.join("impacts.csv"))?;
    let points = impacts.iter().skip(1).map(|l| {
        let stop = col(l, 2);
        (if stop.is_finite() && stop >= 0.0 { stop as usize } else { 0 }, col(l, 4), col(l, 5))
    });
    match impact_map(points, |n| if n > 20_000 { 1 } else { 2 }) {
        Ok(svg) => std::fs::write(dir.join("impact_map.svg"), svg).map_err(|e| io(&dir.join("impact_map.svg"), e))?,
        Err(e) => notes.push(format!("note: impact_map.svg not written: {e} (no impacts in the record windows)")),
    }
    Ok(notes)
}

/// Merges shard folders into `out`: the files an unsharded sweep writes,
/// byte for byte. Refuses shards of different sweeps (ids), missing or
/// repeated shards, and incomplete ones.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<Vec<String>, Error> {
    let bad = |m: String| Error::from(SweepError::Folder(m));
    if shards.is_empty() {
        return Err(bad("merge: give the shard folders".into()));
    }
    let mut found: Vec<(usize, usize, usize, usize, &PathBuf, String, Manifest)> = Vec::new();
    for d in shards {
        let p = d.join("sweep.toml");
        let text = std::fs::read_to_string(&p)
            .map_err(|e| bad(format!("{} is not a shard folder ({}: {}): give the folders `signorini sweep --shard I/N` wrote", d.display(), p.display(), io_reason(&e))))?;
        let m = Manifest::parse(&text).map_err(|e| bad(format!("{}: not a sweep manifest ({})", p.display(), e.message().trim_end())))?;
        let [i, n] = m.shard.ok_or_else(|| bad(format!("{} is not a shard (no shard = [I, N] in its sweep.toml)", d.display())))?;
        let [r0, r1] = m.runs.ok_or_else(|| bad(format!("{}: no runs range", p.display())))?;
        found.push((i, n, r0, r1, d, m.id.clone(), m));
    }
    let (id0, n0) = (found[0].5.clone(), found[0].1);
    if let Some(f) = found.iter().find(|f| f.5 != id0) {
        return Err(bad(format!("{} belongs to sweep {}, {} to sweep {}: shards of different sweeps are not merged", f.4.display(), f.5, found[0].4.display(), id0)));
    }
    if let Some(f) = found.iter().find(|f| f.1 != n0) {
        return Err(bad(format!("{} is a shard of {} and {} of {}: not one sharding", f.4.display(), f.1, found[0].4.display(), n0)));
    }
    found.sort_by_key(|f| f.0);
    for (k, f) in found.iter().enumerate() {
        if f.0 != k {
            let what = if k > 0 && found[k - 1].0 == f.0 { format!("shard {} is given twice", f.0) } else { format!("shard {k} of {n0} is missing") };
            return Err(bad(format!("merge: {what}")));
        }
    }
    if found.len() != n0 {
        return Err(bad(format!("merge: shard {} of {n0} is missing ({} given)", found.len(), found.len())));
    }
    std::fs::create_dir_all(out).map_err(|source| Error::OutFolder { path: out.to_path_buf(), source })?;
    if let Some(f) = SWEEP_FILES.iter().find(|f| out.join(f).exists()) {
        return Err(bad(format!("{} holds a sweep's files ({f}): choose another --out", out.display())));
    }
    let manifest0 = &found[0].6;
    let (map, impacts) = (manifest0.is_map(), manifest0.impacts != Some(false));
    // Every shard's files are read and checked before anything is written:
    // the summary against the manifest's runs, the other files' rows of
    // each run against the counts its summary row gives.
    let files = headers(map, impacts);
    let mut texts: Vec<String> = files.iter().map(|(_, h)| format!("{h}\n")).collect();
    for f in &found {
        let dir = f.4;
        let lines: Vec<Vec<String>> = files.iter().map(|(name, _)| complete_lines(&dir.join(name))).collect::<Result<_, _>>()?;
        for ((name, header), l) in files.iter().zip(&lines) {
            if l.first() != Some(header) {
                return Err(bad(format!("{}: its first line is not the header {header:?}: a damaged shard; run it again", dir.join(name).display())));
            }
        }
        let summary = &lines[files.iter().position(|(n, _)| *n == "summary.csv").unwrap_or(0)];
        let runs: Vec<usize> = summary.iter().skip(1).filter_map(|l| run_of(l)).collect();
        if runs != (f.2..f.3).collect::<Vec<_>>() {
            return Err(bad(format!(
                "{}: expected {} rows (runs {}..{} of the manifest), found {} (runs {}..{}): finish the shard (--resume) or run it again before merging",
                dir.join("summary.csv").display(),
                f.3 - f.2,
                f.2,
                f.3,
                summary.len() - 1,
                runs.first().copied().unwrap_or(f.2),
                runs.last().map_or(f.2, |r| r + 1)
            )));
        }
        // Rows per run that summary.csv counts: `poincare_points` for
        // sweep.csv, `impacts` (the record window's) for impacts.csv.
        let column = |c: &str| summary[0].split(',').position(|h| h == c);
        let expected = |c: Option<usize>| -> Vec<usize> { summary.iter().skip(1).map(|l| c.and_then(|c| l.split(',').nth(c)).and_then(|x| x.parse().ok()).unwrap_or(0)).collect() };
        for (k, (name, _)) in files.iter().enumerate() {
            let want = match *name {
                "sweep.csv" => expected(column("poincare_points")),
                "impacts.csv" => expected(column("impacts")),
                _ => continue,
            };
            let mut got = vec![0usize; want.len()];
            let mut stray = 0usize;
            for l in lines[k].iter().skip(1) {
                match run_of(l).and_then(|r| r.checked_sub(f.2)).filter(|r| *r < got.len()) {
                    Some(r) => got[r] += 1,
                    None => stray += 1,
                }
            }
            let (e, g): (usize, usize) = (want.iter().sum(), got.iter().sum::<usize>() + stray);
            if want != got || stray > 0 {
                let first = want.iter().zip(&got).position(|(a, b)| a != b).map_or(String::new(), |r| format!("; run {} has {} of its {}", f.2 + r, got[r], want[r]));
                return Err(bad(format!(
                    "{}: expected {e} rows (runs {}..{} as the manifest and summary.csv count them), found {g}{first}: a damaged shard; run it again (--shard {}/{})",
                    dir.join(name).display(),
                    f.2,
                    f.3,
                    f.0,
                    f.1
                )));
            }
        }
        for (t, l) in texts.iter_mut().zip(&lines) {
            for row in l.iter().skip(1) {
                t.push_str(row);
                t.push('\n');
            }
        }
    }
    for ((name, _), text) in files.iter().zip(texts) {
        std::fs::write(out.join(name), text).map_err(|e| io(&out.join(name), e))?;
    }
    // The unsharded manifest: the shard's without its shard and runs.
    let unsharded = Manifest { shard: None, runs: None, ..found[0].6.clone() };
    std::fs::write(out.join("sweep.toml"), unsharded.text()).map_err(|e| io(&out.join("sweep.toml"), e))?;
    let mut lines = vec![format!("merged {n0} shards of sweep {id0}")];
    lines.extend(plots(out)?);
    lines.push(format!("wrote {}", out.display()));
    Ok(lines)
}

/// Runs a sweep into `dir` (see the module docs), telling `progress` as
/// runs finish: its lines for the terminal and the count of failed runs (a
/// sweep whose runs failed is still a sweep; `signorini sweep` exits 3
/// when there are any).
pub fn run(sweep: &Sweep, dir: &Path, progress: &dyn Progress) -> Result<SweepReport, Error> {
    let interrupt = sweep.opts.interrupt.as_ref();
    let follow = sweep.opts.follow;
    sweep_report(sweep, dir, |scene, plan, start| simulate(scene, plan, start, follow, interrupt), progress)
}

/// Keeps the last two displacement vectors (for a followed sweep's final
/// velocity, their backward difference).
struct LastTwo {
    prev: Vec<f64>,
    last: Vec<f64>,
    t: f64,
}

impl Observer for LastTwo {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        std::mem::swap(&mut self.prev, &mut self.last);
        self.last.copy_from_slice(s.u);
        self.t = s.t;
        Ok(())
    }
}

/// The rows of a run that could not run or stopped at once: empty
/// statistics and why, as its status.
fn failed(e: &dyn std::fmt::Display) -> RunRows {
    let mut buf = Vec::new();
    let _ = Summary { impacts: None, rms_force: None, max_abs_tip: None, poincare: None }.write_row(&mut buf);
    RunRows { summary: String::from_utf8_lossy(&buf).into_owned(), status: text_cell(&e.to_string()), ..RunRows::default() }
}

/// A cell of free text for a CSV row: quoted, quotes doubled, one line.
fn text_cell(s: &str) -> String {
    format!("\"{}\"", s.replace('"', "\"\"").replace('\n', " "))
}

/// One run of a sweep: the Poincaré samples and impacts of the record
/// window, the statistics, and (with `follow`) the final state, its
/// velocity the backward difference over the last step. A run that cannot
/// be built or stops early gives its reason as the status, and what it
/// recorded before.
pub fn simulate(scene: &Scene, plan: &Plan, start: Option<&(Vec<f64>, Vec<f64>)>, follow: bool, interrupt: Option<&Cancel>) -> RunRows {
    // A reduced model (`reduce = {…}`) runs as `signorini run` runs it: the
    // observers see the scene's unknowns, reconstructed.
    let mut built = match scene.instantiate(start) {
        Ok(b) => b,
        Err(e) => return failed(&e),
    };
    let mut vib = match observers(plan, built.tip, built.contacts()) {
        Ok(v) => v,
        Err(e) => return failed(&e),
    };
    let n = built.unknowns();
    let mut last = LastTwo { prev: vec![0.0; if follow { n } else { 0 }], last: vec![0.0; if follow { n } else { 0 }], t: 0.0 };
    let mut rc = match RunConfig::new(plan.dt, plan.t_end) {
        Ok(c) => c,
        Err(e) => return failed(&e),
    };
    rc.interrupt = interrupt.cloned();
    let mut obs: Vec<(Reads, &mut dyn Observer)> = vec![(Reads::Contacts, &mut vib)];
    if follow {
        obs.push((Reads::Full, &mut last));
    }
    let res = built.run(&rc, obs);
    let (steps, status) = match &res {
        Ok(s) => (s.steps, "ok".to_string()),
        Err(RunError::Interrupted { .. }) => (0, "interrupted".to_string()),
        Err(e) => (built.stepper.level(), text_cell(&e.to_string())),
    };
    let state = (follow && res.is_ok()).then(|| {
        let v: Vec<f64> = last.last.iter().zip(&last.prev).map(|(a, b)| (a - b) / plan.dt).collect();
        built.absolute(&last.last, &v, last.t)
    });
    rows_of(&vib, plan, steps, status, state)
}

/// A sweep run's observers: the impacts, the Poincaré section at the
/// plan's phase and the window statistics, kept in memory.
fn observers(plan: &Plan, tip: usize, contacts: Vec<(usize, Bounds)>) -> Result<signorini_run::vibro::Vibro, RunError> {
    let mut c = VibroConfig::new(plan.dt, Some(plan.omega), plan.record_from, tip, contacts)?;
    c.t_end = Some(plan.t_end);
    c.phase = plan.phase;
    c.period_tol = plan.period_tol;
    c.build(Piece::Memory, Piece::Memory, true)
}

/// A sweep run's rows from its observers (the record window's impacts).
fn rows_of(vib: &signorini_run::vibro::Vibro, plan: &Plan, steps: usize, status: String, state: Option<(Vec<f64>, Vec<f64>)>) -> RunRows {
    let poincare = vib.poincare.as_ref().map_or_else(Vec::new, |p| p.points().iter().map(|q| [q.t, q.displacement, q.velocity, plan.phase]).collect());
    let impacts = vib.impacts.as_ref().map_or_else(Vec::new, |o| o.impacts().iter().filter(|i| i.t >= plan.record_from).map(|i| (i.stop, [i.t, i.phase, i.velocity, i.impulse, i.duration])).collect());
    let mut buf = Vec::new();
    let _ = vib.summary().write_row(&mut buf);
    RunRows { poincare, impacts, summary: String::from_utf8_lossy(&buf).into_owned(), steps, status, state }
}

/// Runs per lockstep group: the paper beam's sweeps step up to this many
/// runs together (crates/run/benches/lockstep.rs: 112 ns per run-step at 8
/// lanes, 125 at 4, 417 for one run alone); a smaller group takes the
/// narrowest engine that holds it (2, 4 or 8 lanes).
pub const LANES: usize = 8;

/// A run the lockstep engine takes: a beam (full model) on its tip's two
/// stops, not continued from another run, whose scheme can run in lockstep
/// (`Capabilities::lockstep`: `ps(e, β)`, the paper's projection among
/// them), within its stability limit or forced past it as its single run.
/// The lane is the run's [`Simulation`](signorini_scene::Simulation) (the
/// one its validation built): its problem and initial state.
fn lane_of(scene: &Scene) -> Option<(LockstepLane, f64, f64, usize)> {
    let (beta, e) = lockstep_params(scene)?;
    let Scene::Beam { scene: bs, .. } = scene else { return None };
    let sim = scene.instantiate(None).ok()?;
    let lane = LockstepLane { dynamics: sim.stepper.dynamics().clone(), initial: Initial { u: sim.u0, v: sim.v0 }, restitution: e };
    Some((lane, beta, bs.dt, sim.tip))
}

/// The β and restitution of a scene the lockstep engine takes (see
/// [`lane_of`]), or `None`.
fn lockstep_params(scene: &Scene) -> Option<(f64, f64)> {
    match scene {
        // A reduced model steps other matrices: one run at a time.
        Scene::Beam { scene: bs, contacts: None, excitation, reduce: None, .. } if excitation.start.is_none() && bs.spring.is_none() && bs.scheme.capabilities().lockstep => {
            Some((bs.scheme.param("beta")?, bs.scheme.param("e")?))
        }
        _ => None,
    }
}

/// The batch's runs as jobs: consecutive lockstep-able runs in groups of up
/// to [`LANES`], every other run alone (indices into `prepared`).
fn lockstep_jobs<T>(prepared: &[(usize, T, Result<ScenePlan, Error>)]) -> Vec<Vec<usize>> {
    let mut jobs: Vec<Vec<usize>> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    for (k, p) in prepared.iter().enumerate() {
        let ok = p.2.as_ref().is_ok_and(|(scene, _)| lockstep_params(scene).is_some());
        if ok {
            open.push(k);
            if open.len() == LANES {
                jobs.push(std::mem::take(&mut open));
            }
        } else {
            jobs.push(vec![k]);
        }
    }
    if !open.is_empty() {
        jobs.push(open);
    }
    jobs
}

/// Runs `group` (beam runs sharing a step matrix) in lockstep
/// ([`PaoliSchatzmanLockstep`] stepped by [`signorini_run::run_lockstep`]):
/// each lane performs the single run's arithmetic and feeds its observers
/// the samples [`signorini_run::run`] would, so its rows are the ones
/// [`simulate`] writes, bit for bit.
/// `None` when the runs cannot share the engine (then run them one by one).
pub fn simulate_lockstep(group: &[(&Scene, &Plan)], interrupt: Option<&Cancel>) -> Option<Vec<RunRows>> {
    match group.len() {
        2 => lockstep_width::<2>(group, interrupt),
        3..=4 => lockstep_width::<4>(group, interrupt),
        5..=8 => lockstep_width::<8>(group, interrupt),
        _ => None,
    }
}

/// [`simulate_lockstep`] on an engine of `L` lanes.
fn lockstep_width<const L: usize>(group: &[(&Scene, &Plan)], interrupt: Option<&Cancel>) -> Option<Vec<RunRows>> {
    let mut lanes = Vec::with_capacity(group.len());
    let mut tips = Vec::with_capacity(group.len());
    let (mut beta, mut dt) = (f64::NAN, f64::NAN);
    for (k, (scene, plan)) in group.iter().enumerate() {
        let (lane, b, d, tip) = lane_of(scene)?;
        if k > 0 && (b != beta || d != dt) || plan.dt != d {
            return None;
        }
        (beta, dt) = (b, d);
        tips.push(tip);
        lanes.push(lane);
    }
    let inits: Vec<Vec<f64>> = lanes.iter().map(|l| l.initial.u.clone()).collect();
    let contacts: Vec<Vec<(usize, Bounds)>> = lanes.iter().map(|l| l.dynamics.contacts.iter().map(|c| (c.dof, c.bounds)).collect()).collect();
    let mut eng = PaoliSchatzmanLockstep::<L>::new(beta, dt, lanes).ok()?;
    // The vibro observers read the tip and the contact only.
    let mut need: Vec<usize> = tips.iter().copied().chain(std::iter::once(eng.contact_dof())).collect();
    need.sort_unstable();
    need.dedup();
    let mut vibs = Vec::with_capacity(group.len());
    let mut cfgs = Vec::with_capacity(group.len());
    for (k, (_, plan)) in group.iter().enumerate() {
        vibs.push(observers(plan, tips[k], contacts[k].clone()).ok()?);
        let mut rc = RunConfig::new(plan.dt, plan.t_end).ok()?;
        rc.interrupt = interrupt.cloned();
        cfgs.push(rc);
    }
    let ends = {
        let mut runs: Vec<LockstepRun<'_>> = vibs.iter_mut().zip(&cfgs).zip(&inits).map(|((v, rc), u0)| LockstepRun::new(u0, rc, vec![v as &mut dyn Observer])).collect();
        run_lockstep(&mut eng, &mut runs, &Need::Dofs(need)).ok()?
    };
    Some(
        vibs.iter()
            .zip(ends)
            .zip(group)
            .map(|((vib, end), (_, plan))| {
                // What `simulate` makes of `run`'s result.
                let (steps, status) = match &end.result {
                    Ok(s) => (s.steps, "ok".to_string()),
                    Err(RunError::Interrupted { .. }) => (0, "interrupted".to_string()),
                    Err(e) => (end.level, text_cell(&e.to_string())),
                };
                rows_of(vib, plan, steps, status, None)
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The manifest as it was written by hand before the toml crate wrote
    /// it (`writeln!` with `{:?}` for strings and floats).
    fn by_hand(m: &Manifest) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "# signorini sweep manifest: merge checks that shards share the id");
        let _ = writeln!(s, "id = \"{}\"", m.id);
        let _ = writeln!(s, "scene = {:?}", m.scene);
        let _ = writeln!(s, "param = {:?}", m.param);
        let _ = writeln!(s, "from = {:?}\nto = {:?}\ncount = {}\nlog = {}", m.from, m.to, m.count, m.log);
        if let Some(p) = &m.param2 {
            let _ = writeln!(s, "param2 = {:?}\nfrom2 = {:?}\nto2 = {:?}\ncount2 = {}\nlog2 = {}", p, m.from2.unwrap(), m.to2.unwrap(), m.count2.unwrap(), m.log2.unwrap());
        }
        let _ = writeln!(s, "transient = {:?}\nrecord = {:?}\nphase = {:?}\nperiod_tol = {:?}\nfollow = {}", m.transient, m.record, m.phase, m.period_tol, m.follow);
        if m.impacts == Some(false) {
            let _ = writeln!(s, "impacts = false");
        }
        if let (Some([i, n]), Some([a, b])) = (m.shard, m.runs) {
            let _ = writeln!(s, "shard = [{i}, {n}]\nruns = [{a}, {b}]");
        }
        s
    }

    fn manifest(from: f64, to: f64, scene: &str, map: bool, shard: bool) -> Manifest {
        Manifest {
            id: "a60189f356524119".into(),
            scene: scene.into(),
            param: "support.omega".into(),
            from,
            to,
            count: 1000,
            log: false,
            param2: map.then(|| "stop.0.hi".into()),
            from2: map.then_some(to),
            to2: map.then_some(from),
            count2: map.then_some(7),
            log2: map.then_some(true),
            transient: 20.0,
            record: 2.5,
            phase: from.abs().min(6.0),
            period_tol: 0.001,
            follow: !map,
            impacts: map.then_some(false),
            shard: shard.then_some([1, 4]),
            runs: shard.then_some([250, 500]),
        }
    }

    /// The toml crate writes what the hand-written manifest was, byte for
    /// byte, for numbers in `[1e-4, 1e16)` in magnitude (or 0) and names
    /// without `"` or `\` (the reference sweep's among them), and reads it
    /// back to the same values.
    #[test]
    fn the_toml_manifest_is_the_hand_written_one() {
        let floats = [4.0, 16.0, 0.0, 0.001, 0.1, 1e-4, 123456789.125, 1e15, 9.999e15, -3.5, 1.0 / 3.0, 9.5, 2.0 * std::f64::consts::PI];
        for (k, &from) in floats.iter().enumerate() {
            let to = floats[(k + 3) % floats.len()];
            for scene in ["beam-fig2-support.toml", "my scene (2).toml", "é.toml", "t\tab.toml", "it's.toml"] {
                for (map, shard) in [(false, false), (true, false), (false, true), (true, true)] {
                    let m = manifest(from, to, scene, map, shard);
                    assert_eq!(m.text(), by_hand(&m), "from {from:?} to {to:?} scene {scene:?} map {map} shard {shard}");
                    assert_eq!(Manifest::parse(&m.text()).unwrap(), m);
                }
            }
        }
    }

    /// Where the two differ, both are TOML for the same values: the toml
    /// crate writes floats below 1e-4 or from 1e16 in magnitude in
    /// positional notation (`0.00001`, `10000000000000000.0`: Rust's
    /// `Display`, where `{:?}` wrote `1e-5`, `1e16`), and a name with `"`
    /// or `\` as a literal string (`'a"b.toml'`) or a multi-line one,
    /// where `{:?}` wrote Rust escapes. A folder written by hand (an older
    /// version) still resumes and merges: it reads to the same manifest.
    #[test]
    fn where_the_texts_differ_the_values_do_not() {
        let floats = [1e-5, 2.5e-7, 3e-300, f64::MIN_POSITIVE, 1e16, 1e20, 6.02e23, -1e300, f64::MAX];
        for (k, &from) in floats.iter().enumerate() {
            let to = floats[(k + 1) % floats.len()];
            for scene in ["beam.toml", "a\"b.toml", "c:\\x\\s.toml", "it's \"x\".toml"] {
                for (map, shard) in [(false, false), (true, true)] {
                    let m = manifest(from, to, scene, map, shard);
                    assert_ne!(m.text(), by_hand(&m));
                    for text in [m.text(), by_hand(&m)] {
                        let back = Manifest::parse(&text).unwrap();
                        assert_eq!(back, m, "{text}");
                        assert_eq!((back.from.to_bits(), back.to.to_bits()), (m.from.to_bits(), m.to.to_bits()));
                    }
                }
            }
        }
    }
}
