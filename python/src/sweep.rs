//! `signorini.sweep`: the `signorini sweep` engine (rayon batches, the
//! lockstep beam engine, shards) from Python; its CSV files come back as
//! columns of numpy arrays, parsed in Rust.

use crate::{guarded, InternalError, SceneError};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use signorini_sweep::{Axis, Sweep, SweepOptions};
use std::path::{Path, PathBuf};

/// The columns that count (runs, impacts, forcing periods, points, steps,
/// stop indices): int64 when every cell is an integer.
const COUNTS: &[&str] = &["run", "stop", "impacts", "period", "poincare_points", "steps"];

/// A CSV file as `{column: array}`: a counting column ([`COUNTS`]) whose
/// every cell is an integer becomes int64, another column whose every cell
/// is a number (an empty cell is NaN) float64, any other a list of str.
fn read_csv<'py>(py: Python<'py>, path: &Path) -> PyResult<Option<Bound<'py, PyDict>>> {
    if !path.exists() {
        return Ok(None);
    }
    let mut r = csv::Reader::from_path(path).map_err(|e| InternalError::new_err(format!("{}: {e}", path.display())))?;
    let header: Vec<String> = r.headers().map_err(|e| InternalError::new_err(e.to_string()))?.iter().map(String::from).collect();
    let mut cols: Vec<Vec<String>> = vec![Vec::new(); header.len()];
    for rec in r.records() {
        let rec = rec.map_err(|e| InternalError::new_err(format!("{}: {e}", path.display())))?;
        for (c, v) in cols.iter_mut().zip(rec.iter()) {
            c.push(v.to_string());
        }
    }
    let d = PyDict::new(py);
    for (name, c) in header.iter().zip(cols) {
        if COUNTS.contains(&name.as_str()) {
            if let Some(v) = c.iter().map(|v| v.parse::<i64>().ok()).collect::<Option<Vec<i64>>>() {
                d.set_item(name, v.into_pyarray(py))?;
                continue;
            }
        }
        let nums: Option<Vec<f64>> = c.iter().map(|v| if v.is_empty() { Some(f64::NAN) } else { v.parse::<f64>().ok() }).collect();
        match nums {
            Some(v) => d.set_item(name, v.into_pyarray(py))?,
            None => d.set_item(name, PyList::new(py, c)?)?,
        }
    }
    Ok(Some(d))
}

/// A sweep's error with the options named as the Python arguments
/// (`--from` is `start`, `--period-tol` is `period_tol`, …).
fn python_message(e: &signorini_sweep::Error) -> String {
    use signorini_sweep::SweepError;
    match e {
        signorini_sweep::Error::Options(SweepError::Option { option, message }) => {
            let name = match *option {
                "from" => "start",
                "to" => "stop",
                "from2" => "start2",
                "to2" => "stop2",
                other => other,
            };
            format!("{}: {message}", name.replace('-', "_"))
        }
        signorini_sweep::Error::Options(SweepError::Param { path, message }) => format!("param {path}: {message}"),
        signorini_sweep::Error::Options(SweepError::Value { path, value, error }) => format!("param {path} = {value}: {error}"),
        other => other.to_string(),
    }
}

/// Runs a sweep of `scene_text` (named `scene_name`, files it names found
/// in `base`) into `out`; returns `{"tables": {file: columns}, "lines":
/// [...], "id": str}`. Ctrl-C stops after the current batch (whole runs
/// kept) and raises KeyboardInterrupt with the tables so far as `partial`.
#[pyfunction]
#[pyo3(signature = (scene_text, scene_name, base, out, param, start, stop, count, log, second, transient, record, phase, period_tol, impacts, follow, shard, resume, threads))]
#[allow(clippy::too_many_arguments)]
pub fn run_sweep<'py>(
    py: Python<'py>,
    scene_text: &str,
    scene_name: &str,
    base: Option<PathBuf>,
    out: PathBuf,
    param: String,
    start: f64,
    stop: f64,
    count: usize,
    log: bool,
    second: Option<(String, f64, f64, usize, bool)>,
    transient: f64,
    record: f64,
    phase: f64,
    period_tol: f64,
    impacts: bool,
    follow: bool,
    shard: Option<(usize, usize)>,
    resume: bool,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let cancel = signorini_run::Cancel::new();
    let second = second.map(|(param, from, to, count, log)| Axis { param, from, to, count, log });
    let mut opts = SweepOptions::new(&param, start, stop, count);
    (opts.log, opts.second, opts.transient, opts.record, opts.phase, opts.period_tol) = (log, second, transient, record, phase, period_tol);
    (opts.impacts, opts.follow, opts.shard, opts.resume, opts.threads, opts.interrupt) = (impacts, follow, shard, resume, threads, Some(cancel.clone()));
    let limits = signorini_scene::Limits::machine();
    let sweep = guarded(|| Sweep::new(scene_text, scene_name, base, opts, limits).map_err(|e| SceneError::new_err(python_message(&e))))?;
    let (res, signal) = crate::interruptible(py, &cancel, || Ok(signorini_sweep::run(&sweep, &out, &signorini_sweep::NoProgress).map(|r| r.lines)));
    let res = res?;
    let tables = PyDict::new(py);
    for f in ["sweep.csv", "summary.csv", "impacts.csv"] {
        if let Some(t) = read_csv(py, &out.join(f))? {
            tables.set_item(f, t)?;
        }
    }
    let d = PyDict::new(py);
    d.set_item("tables", &tables)?;
    d.set_item("id", sweep.id())?;
    d.set_item("out", &out)?;
    d.set_item("lines", Vec::<String>::new())?;
    match (signal, res) {
        (Some(e), _) => {
            e.value(py).setattr("partial", &d)?;
            Err(e)
        }
        (None, Ok(lines)) => {
            d.set_item("lines", lines)?;
            Ok(d)
        }
        (None, Err(e)) => {
            // Bad input (exit 2 from the command) is a SceneError; IO is an OSError.
            let err = if e.is_bad_input() { SceneError::new_err(e.to_string()) } else { pyo3::exceptions::PyOSError::new_err(e.to_string()) };
            err.value(py).setattr("partial", &d)?;
            Err(err)
        }
    }
}
