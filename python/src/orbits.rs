//! `signorini.continuation`: `signorini continue` from Python (the same
//! `signorini_orbits::front::continue_scene`); its CSV files come back as
//! columns of numpy arrays.

use crate::{guarded, interruptible, SceneError};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use signorini_orbits::front::{continue_scene, ContinueOptions};
use signorini_orbits::OrbitError;

/// The columns that count: int64.
const COUNTS: &[&str] = &["period", "stable", "impacts_per_period", "releases_per_period", "branch", "impacts_before", "impacts_after", "releases_before", "releases_after"];

/// A CSV text as `{column: array}` (a counting column int64, a numeric one
/// float64 with an empty cell NaN, any other a list of str).
fn columns<'py>(py: Python<'py>, text: &str, counts: &[&str]) -> PyResult<Bound<'py, PyDict>> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let mut cols: Vec<Vec<&str>> = vec![Vec::new(); header.len()];
    for l in lines {
        for (c, v) in cols.iter_mut().zip(l.split(',')) {
            c.push(v);
        }
    }
    let d = PyDict::new(py);
    for (name, c) in header.iter().zip(cols) {
        if counts.contains(name) {
            if let Some(v) = c.iter().map(|v| v.parse::<i64>().ok()).collect::<Option<Vec<i64>>>() {
                d.set_item(name, v.into_pyarray(py))?;
                continue;
            }
        }
        match c.iter().map(|v| if v.is_empty() { Some(f64::NAN) } else { v.parse::<f64>().ok() }).collect::<Option<Vec<f64>>>() {
            Some(v) => d.set_item(name, v.into_pyarray(py))?,
            None => d.set_item(name, PyList::new(py, c)?)?,
        }
    }
    Ok(d)
}

/// An error with the options named as the Python arguments.
fn python_error(e: OrbitError) -> PyErr {
    match e {
        OrbitError::Option { option, message } => {
            let name = match option {
                "from" => "start",
                "to" => "stop",
                "from/to" => "start/stop",
                other => other,
            };
            SceneError::new_err(format!("{}: {message}", name.replace('-', "_")))
        }
        OrbitError::Scene(m) => SceneError::new_err(m),
        OrbitError::Interrupted => pyo3::exceptions::PyKeyboardInterrupt::new_err("interrupted"),
        other => pyo3::exceptions::PyRuntimeError::new_err(other.to_string()),
    }
}

/// Runs a continuation of `scene_text`; returns `{"tables": {file:
/// columns}, "svg": str or None, "lines": [...]}` and writes the files to
/// `out` if given.
#[pyfunction]
#[pyo3(signature = (scene_text, param, start, stop, period, transient, max_points, switch, sweep, out))]
#[allow(clippy::too_many_arguments)]
pub fn run_continuation<'py>(
    py: Python<'py>,
    scene_text: &str,
    param: &str,
    start: f64,
    stop: f64,
    period: usize,
    transient: f64,
    max_points: usize,
    switch: bool,
    sweep: Vec<(f64, f64)>,
    out: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let doc: toml::Table = guarded(|| scene_text.parse().map_err(|e: toml::de::Error| SceneError::new_err(e.to_string())))?;
    guarded(|| signorini_scene::SceneFile::from_table(doc.clone()).map(|_| ()).map_err(|e| crate::py_scene_error(e, false)))?;
    let opts = ContinueOptions { param: param.to_string(), from: start, to: stop, period, transient, max_points, switch, sweep };
    let cancel = signorini_run::Cancel::new();
    let c = cancel.clone();
    let poll: std::sync::Arc<dyn Fn() -> bool + Send + Sync> = std::sync::Arc::new(move || c.is_cancelled());
    let (done, signal) = interruptible(py, &cancel, || continue_scene(doc, &opts, signorini_scene::Limits::machine(), Some(poll.clone()), &mut |_, _, _| !cancel.is_cancelled()).map_err(python_error));
    if let Some(e) = signal {
        return Err(e);
    }
    let done = done?;
    if let Some(dir) = &out {
        std::fs::create_dir_all(dir).map_err(|e| SceneError::new_err(format!("out {dir}: {e}")))?;
        for (name, body) in &done.files {
            std::fs::write(std::path::Path::new(dir).join(name), body).map_err(|e| SceneError::new_err(format!("out {dir}/{name}: {e}")))?;
        }
    }
    let tables = PyDict::new(py);
    let mut svg = None;
    for (name, body) in &done.files {
        if name.ends_with(".csv") {
            tables.set_item(*name, columns(py, body, COUNTS)?)?;
        } else {
            svg = Some(body.clone());
        }
    }
    let d = PyDict::new(py);
    d.set_item("tables", tables)?;
    d.set_item("svg", svg)?;
    d.set_item("lines", PyList::new(py, &done.lines)?)?;
    Ok(d)
}

/// The backbone of `scene_text`'s nonsmooth modes from energy `start` to
/// `stop`; returns `{"tables": {"backbone.csv": columns}, "svg": str or
/// None, "lines": [...]}` and writes the files to `out` if given.
#[pyfunction]
#[pyo3(signature = (scene_text, start, stop, points, out))]
pub fn run_modes<'py>(py: Python<'py>, scene_text: &str, start: f64, stop: f64, points: usize, out: Option<String>) -> PyResult<Bound<'py, PyDict>> {
    let doc: toml::Table = guarded(|| scene_text.parse().map_err(|e: toml::de::Error| SceneError::new_err(e.to_string())))?;
    guarded(|| signorini_scene::SceneFile::from_table(doc.clone()).map(|_| ()).map_err(|e| crate::py_scene_error(e, false)))?;
    let cancel = signorini_run::Cancel::new();
    let (modes, signal) = interruptible(py, &cancel, || signorini_orbits::modes::backbone(&doc, start, stop, points).map_err(python_error));
    if let Some(e) = signal {
        return Err(e);
    }
    let modes = modes?;
    let csv = signorini_orbits::output::backbone_csv(&modes);
    let svg = signorini_orbits::output::backbone_svg(&modes).ok();
    if let Some(dir) = &out {
        std::fs::create_dir_all(dir).map_err(|e| SceneError::new_err(format!("out {dir}: {e}")))?;
        std::fs::write(std::path::Path::new(dir).join("backbone.csv"), &csv).map_err(|e| SceneError::new_err(format!("out {dir}/backbone.csv: {e}")))?;
        if let Some(s) = &svg {
            std::fs::write(std::path::Path::new(dir).join("backbone.svg"), s).map_err(|e| SceneError::new_err(format!("out {dir}/backbone.svg: {e}")))?;
        }
    }
    let tables = PyDict::new(py);
    tables.set_item("backbone.csv", columns(py, &csv, &["impacts_per_period"])?)?;
    let mut lines = vec![format!("{} of {points} energies on the backbone ({} elements)", modes.points.len(), modes.elements)];
    if let Some((e, why)) = &modes.stopped {
        lines.push(format!("the family ended at energy {e}: {why}"));
    }
    let d = PyDict::new(py);
    d.set_item("tables", tables)?;
    d.set_item("svg", svg)?;
    d.set_item("lines", PyList::new(py, &lines)?)?;
    Ok(d)
}
