//! The grid of a sweep and its options: [`Axis`], [`SweepOptions`], and
//! [`set_path`], the edit of the scene document by dotted path.

use crate::error::SweepError;
use signorini_run::text::num;
use signorini_run::Cancel;
use signorini_scene::{presets, SceneError, SceneFile};

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
/// ends exact (a range that ends on a bound, a stop, gives the bound
/// itself). The sweeps' axes and the basins' grid.
pub fn grid(from: f64, to: f64, count: usize, log: bool, i: usize) -> f64 {
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
pub(crate) fn check_axis(suffix: &'static str, from: f64, to: f64, count: usize, log: bool) -> Result<(), SweepError> {
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

    /// Checks the options (not the path: [`Sweep::new`](crate::Sweep::new) does, on the scene).
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

/// Sets the numeric field at `path` in a scene document to `value`.
/// Segments are keys, or array indices (`stop.0.hi`). The parent must
/// exist; an existing value must be a number. An integral value goes in as
/// an integer, another as a float: the scene's parse refuses a fraction in
/// an integer field (and [`Sweep::new`](crate::Sweep::new) refuses a grid that gives one).
pub fn set_path(doc: &mut toml::Table, path: &str, value: f64) -> Result<(), SweepError> {
    let err = |m: String| SweepError::Param { path: path.into(), message: m };
    let integral = value.fract() == 0.0 && value.abs() <= 9.0e15;
    let v = match presets::get_path(doc, path) {
        Some(toml::Value::Float(_)) => toml::Value::Float(value),
        // An integer literal: an integral value stays one; another goes in
        // as a float, which a real field written `omega = 10` takes and an
        // integer field refuses ([`Sweep::new`] checks the grid of one).
        Some(toml::Value::Integer(_)) if integral => toml::Value::Integer(value as i64),
        Some(toml::Value::Integer(_)) => toml::Value::Float(value),
        Some(other) => return Err(err(format!("names a {} value, not a number", other.type_str()))),
        // A key the scene leaves at its default (validation decides), or a
        // path the editor refuses. An integral value goes in as an integer,
        // which integer fields need and real fields take.
        None if integral => toml::Value::Integer(value as i64),
        None => toml::Value::Float(value),
    };
    presets::set_path(doc, path, v).map_err(|e| match e {
        SceneError::Field { message, .. } => err(message),
        other => err(other.to_string()),
    })
}

/// Whether `path` names an integer field of the scene: the document parses
/// with an integer there and not with a fraction.
pub(crate) fn integer_field(doc: &toml::Table, path: &str) -> bool {
    let parses = |v: f64| {
        let mut d = doc.clone();
        set_path(&mut d, path, v).is_ok() && SceneFile::from_table(d).is_ok()
    };
    parses(1.0) && !parses(0.5)
}

/// Refuses the grid of an axis over an integer field that gives a value
/// that is not an integer (or beyond 9e15), naming the value, its index
/// and a count that would do.
pub(crate) fn integral_grid(doc: &toml::Table, path: &str, suffix: &str, from: f64, to: f64, count: usize, log: bool) -> Result<(), SweepError> {
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
