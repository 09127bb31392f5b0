//! `signorini.continuation`, `modes` and `basins`: `signorini continue`,
//! `modes` and `basins` from Python (the same `signorini_orbits` functions:
//! `front::continue_scene`, `modes::backbone`, `basins::Grid`); their files
//! come back as columns of numpy arrays and as text.

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
/// columns}, "files": {file: text}, "svg": str or None, "lines": [...]}`
/// and writes the files to `out` if given.
#[pyfunction]
#[pyo3(signature = (scene_text, param, start, stop, period, transient, max_points, switch, sweep, out, param_scale))]
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
    param_scale: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let doc: toml::Table = guarded(|| scene_text.parse().map_err(|e: toml::de::Error| SceneError::new_err(e.to_string())))?;
    guarded(|| signorini_scene::SceneFile::from_table(doc.clone()).map(|_| ()).map_err(|e| crate::py_scene_error(e, false)))?;
    let opts = ContinueOptions { param: param.to_string(), from: start, to: stop, period, transient, max_points, switch, sweep, param_scale };
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
    let files = PyDict::new(py);
    let mut svg = None;
    for (name, body) in &done.files {
        files.set_item(*name, body)?;
        if name.ends_with(".csv") {
            tables.set_item(*name, columns(py, body, COUNTS)?)?;
        } else {
            svg = Some(body.clone());
        }
    }
    let d = PyDict::new(py);
    d.set_item("tables", tables)?;
    d.set_item("files", files)?;
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

/// Runs `signorini basins` on `scene_text` (the same
/// `signorini_orbits::basins::Grid`); returns each cell's columns, the
/// attractors, the files' text (`basins.csv`, `basins.toml`, and
/// `basins.svg` for a whole grid) and the lines to print. Ctrl-C stops
/// between cells and raises KeyboardInterrupt whose `partial` is that dict
/// for the whole rows so far.
#[pyfunction]
#[pyo3(signature = (scene_text, x, v, grid, x_range, v_range, transient, max_period, tol, match_tol, orbits, shard, threads))]
#[allow(clippy::too_many_arguments)]
pub fn run_basins<'py>(
    py: Python<'py>,
    scene_text: &str,
    x: String,
    v: String,
    grid: (usize, usize),
    x_range: (f64, f64),
    v_range: (f64, f64),
    transient: usize,
    max_period: usize,
    tol: f64,
    match_tol: f64,
    orbits: Option<String>,
    shard: Option<(usize, usize)>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    use signorini_orbits::basins::{basins_csv, basins_svg, basins_toml, Axis, BasinOptions, Grid, GridOptions};
    let started = std::time::Instant::now();
    let doc: toml::Table = guarded(|| scene_text.parse().map_err(|e: toml::de::Error| SceneError::new_err(e.to_string())))?;
    guarded(|| signorini_scene::SceneFile::from_table(doc).map(|_| ()).map_err(|e| crate::py_scene_error(e, false)))?;
    let mut o = GridOptions::new(Axis { path: x, from: x_range.0, to: x_range.1, count: grid.0 }, Axis { path: v, from: v_range.0, to: v_range.1, count: grid.1 });
    (o.classify, o.orbits, o.shard, o.threads, o.keep) = (BasinOptions { transient, max_period, tol, match_tol }, orbits, shard, threads, true);
    let g = guarded(|| Grid::new(scene_text, o, signorini_scene::Limits::machine()).map_err(python_error))?;
    let cancel = signorini_run::Cancel::new();
    let (b, signal) = interruptible(py, &cancel, || g.run(&|| {}, &|| cancel.is_cancelled(), &mut |_| true).map_err(python_error));
    let b = b?;
    let d = PyDict::new(py);
    let n = b.attractor.len();
    let w = 2 * b.state_dofs.len();
    let cells: Vec<usize> = (b.cells.start..b.cells.start + n).collect();
    let ints = |v: &[usize]| v.iter().map(|&k| k as i64).collect::<Vec<i64>>();
    d.set_item("i", cells.iter().map(|c| (c % b.x.count) as i64).collect::<Vec<_>>().into_pyarray(py))?;
    d.set_item("j", cells.iter().map(|c| (c / b.x.count) as i64).collect::<Vec<_>>().into_pyarray(py))?;
    d.set_item("x", cells.iter().map(|c| b.x.value(c % b.x.count)).collect::<Vec<_>>().into_pyarray(py))?;
    d.set_item("v", cells.iter().map(|c| b.v.value(c / b.x.count)).collect::<Vec<_>>().into_pyarray(py))?;
    d.set_item("attractor", b.attractor.clone().into_pyarray(py))?;
    d.set_item("period", ints(&b.period).into_pyarray(py))?;
    d.set_item("impacts_per_period", ints(&b.impacts).into_pyarray(py))?;
    d.set_item("sticking", b.sticking.clone().into_pyarray(py))?;
    d.set_item("label", PyList::new(py, &b.label)?)?;
    d.set_item("state", b.state.clone().into_pyarray(py))?;
    d.set_item("width", w)?;
    let names: Vec<String> = ["q", "v"].iter().flat_map(|p| b.state_dofs.iter().map(move |k| format!("{p}{k}"))).collect();
    d.set_item("state_columns", PyList::new(py, &names)?)?;
    let a = PyDict::new(py);
    a.set_item("id", (0..b.attractors.len() as i64).collect::<Vec<_>>().into_pyarray(py))?;
    a.set_item("period", b.attractors.iter().map(|e| e.period as i64).collect::<Vec<_>>().into_pyarray(py))?;
    a.set_item("label", PyList::new(py, b.attractors.iter().map(|e| e.label.as_str()))?)?;
    a.set_item("state", b.attractors.iter().flat_map(|e| e.state.iter().copied()).collect::<Vec<_>>().into_pyarray(py))?;
    a.set_item("cells", b.attractors.iter().map(|e| e.cells as i64).collect::<Vec<_>>().into_pyarray(py))?;
    a.set_item("first_cell", b.attractors.iter().map(|e| e.first_cell as i64).collect::<Vec<_>>().into_pyarray(py))?;
    d.set_item("attractors", a)?;
    d.set_item("grid", (b.manifest.nx, b.manifest.ny))?;
    d.set_item("cells", (b.cells.start, b.cells.end))?;
    d.set_item("complete", b.complete())?;
    d.set_item("id", &b.manifest.id)?;
    let files = PyDict::new(py);
    files.set_item("basins.toml", basins_toml(&b))?;
    files.set_item("basins.csv", basins_csv(&b))?;
    let mut lines = vec![b.summary(started.elapsed().as_secs_f64())];
    if b.complete() && shard.is_none() {
        match basins_svg(&b) {
            Ok(svg) => files.set_item("basins.svg", svg)?,
            Err(e) => lines.push(format!("note: basins.svg not written: {e}")),
        }
    }
    d.set_item("files", files)?;
    d.set_item("lines", PyList::new(py, &lines)?)?;
    if let Some(e) = signal {
        e.value(py).setattr("partial", &d)?;
        return Err(e);
    }
    Ok(d)
}
