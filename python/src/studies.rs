//! The studies from Python: the same `signorini_studies` functions as
//! `cargo xtask <study>`, configured from keyword arguments, run with the
//! GIL released; every CSV they write comes back as a table of numpy
//! arrays.

use crate::{guarded, SceneError};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use signorini_studies::{Column, StudyError, Table};
use std::path::PathBuf;

/// `--t-end` → `t_end`: the study's option as the Python argument.
fn py_name(flag: &str) -> String {
    flag.trim_start_matches('-').replace('-', "_")
}

fn study_err(e: StudyError) -> PyErr {
    match e {
        StudyError::Config { field, message } => {
            // The message names the option as `cargo xtask` spells it: name
            // the Python argument, first.
            let name = py_name(&field);
            let m = message.replacen(&field, &name, 1);
            SceneError::new_err(if m.starts_with(&name) { m } else { format!("{name}: {m}") })
        }
        other => SceneError::new_err(other.to_string()),
    }
}

/// `{file: {column: array}}`: float64 and int64 arrays, lists of str.
fn tables_py<'py>(py: Python<'py>, tables: &[Table]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for t in tables {
        let cols = PyDict::new(py);
        for (name, c) in &t.columns {
            match c {
                Column::F64(v) => cols.set_item(name, v.clone().into_pyarray(py))?,
                Column::I64(v) => cols.set_item(name, v.clone().into_pyarray(py))?,
                Column::Str(v) => cols.set_item(name, PyList::new(py, v)?)?,
            }
        }
        d.set_item(&t.file, cols)?;
    }
    Ok(d)
}

/// The common part of every study's output, as a dict.
fn output_py<'py>(py: Python<'py>, tables: &[Table], report: &str, wall_s: f64, notes: &[String], out: &std::path::Path) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("tables", tables_py(py, tables)?)?;
    d.set_item("report", report)?;
    d.set_item("wall_s", wall_s)?;
    d.set_item("notes", notes.to_vec())?;
    d.set_item("out", out.to_path_buf())?;
    Ok(d)
}

/// Takes the keyword arguments one by one, naming the argument in every
/// error; anything left over is an unknown argument.
struct Args<'a, 'py> {
    study: &'a str,
    d: &'a Bound<'py, PyDict>,
    /// Every argument asked for, for the error on one left over.
    asked: std::cell::RefCell<Vec<String>>,
}

impl<'py> Args<'_, 'py> {
    fn take(&self, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.asked.borrow_mut().push(key.to_string());
        let v = self.d.get_item(key)?;
        if v.is_some() {
            self.d.del_item(key)?;
        }
        Ok(v.filter(|v| !v.is_none()))
    }
    fn bad(&self, key: &str, v: &Bound<'py, PyAny>, want: &str) -> PyErr {
        let ty = v.get_type().name().map(|n| n.to_string()).unwrap_or_default();
        SceneError::new_err(format!("{key}: a {ty} ({}) is not allowed: {want}", v.repr().map(|r| r.to_string()).unwrap_or_default()))
    }
    /// `v`, or the Python value a numpy scalar or 0-d array holds.
    fn plain(v: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match crate::numpy_plain(v)? {
            Some(p) if !p.is_instance_of::<pyo3::types::PyList>() => Ok(p),
            _ => Ok(v.clone()),
        }
    }
    fn float(&self, key: &str, v: &Bound<'py, PyAny>) -> PyResult<f64> {
        let x = Self::plain(v)?;
        if x.is_instance_of::<pyo3::types::PyBool>() || x.is_instance_of::<pyo3::types::PyString>() {
            return Err(self.bad(key, v, "a number (int or float)"));
        }
        x.extract::<f64>().map_err(|_| self.bad(key, v, "a number (int or float)"))
    }
    fn int(&self, key: &str, v: &Bound<'py, PyAny>) -> PyResult<usize> {
        let x = Self::plain(v)?;
        if x.is_instance_of::<pyo3::types::PyBool>() {
            return Err(self.bad(key, v, "an int >= 0"));
        }
        if x.is_instance_of::<pyo3::types::PyFloat>() {
            // A float with a whole value is that int (80.0); 80.5 is not.
            let f: f64 = x.extract()?;
            if f.fract() == 0.0 && f >= 0.0 && f < 2f64.powi(53) {
                return Ok(f as usize);
            }
            return Err(self.bad(key, v, "an int >= 0 (a whole number)"));
        }
        x.extract::<usize>().map_err(|_| self.bad(key, v, "an int >= 0"))
    }
    fn list(&self, key: &str, v: &Bound<'py, PyAny>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        if v.is_instance_of::<pyo3::types::PyString>() {
            return Ok(vec![v.clone()]);
        }
        match v.try_iter() {
            Ok(it) => it.collect(),
            Err(_) => Ok(vec![v.clone()]),
        }
        .map_err(|_: PyErr| self.bad(key, v, "a list"))
    }
    fn f64(&self, key: &str) -> PyResult<Option<f64>> {
        self.take(key)?.map(|v| self.float(key, &v)).transpose()
    }
    fn usize(&self, key: &str) -> PyResult<Option<usize>> {
        self.take(key)?.map(|v| self.int(key, &v)).transpose()
    }
    fn bool(&self, key: &str) -> PyResult<Option<bool>> {
        self.take(key)?
            .map(|v| {
                let x = Self::plain(&v)?;
                if x.is_instance_of::<pyo3::types::PyBool>() {
                    x.extract::<bool>()
                } else {
                    Err(self.bad(key, &v, "True or False"))
                }
            })
            .transpose()
    }
    fn usizes(&self, key: &str) -> PyResult<Option<Vec<usize>>> {
        self.take(key)?.map(|v| self.list(key, &v)?.iter().enumerate().map(|(i, x)| self.int(&format!("{key}[{i}]"), x)).collect()).transpose()
    }
    fn f64s(&self, key: &str) -> PyResult<Option<Vec<f64>>> {
        self.take(key)?.map(|v| self.list(key, &v)?.iter().enumerate().map(|(i, x)| self.float(&format!("{key}[{i}]"), x)).collect()).transpose()
    }
    fn strs(&self, key: &str) -> PyResult<Option<Vec<String>>> {
        self.take(key)?.map(|v| self.list(key, &v)?.iter().enumerate().map(|(i, x)| x.extract::<String>().map_err(|_| self.bad(&format!("{key}[{i}]"), x, "a string"))).collect()).transpose()
    }
    fn str(&self, key: &str) -> PyResult<Option<String>> {
        self.take(key)?.map(|v| v.extract::<String>().map_err(|_| self.bad(key, &v, "a string"))).transpose()
    }
    /// Errors if an argument is left that the study does not take (the
    /// allowed ones are those asked for).
    fn done(&self) -> PyResult<()> {
        if let Some((k, _)) = self.d.iter().next() {
            return Err(SceneError::new_err(format!("{k}: not an argument of the {} study (allowed: {})", self.study, self.asked.borrow().join(", "))));
        }
        Ok(())
    }
}

/// Runs `f` with the GIL released, a panic turned into `InternalError`.
fn detached<T: Send>(py: Python<'_>, f: impl FnOnce() -> Result<T, StudyError> + Send) -> PyResult<T> {
    py.detach(|| guarded(|| f().map_err(study_err)))
}

/// Runs the study `name` with the keyword arguments `kwargs` (the options of
/// `cargo xtask <name>`, as Python names) writing into `out`; returns the
/// tables, the report, the wall time, the notes and (convergence) the
/// configurations in order.
#[pyfunction]
pub fn study<'py>(py: Python<'py>, name: &str, kwargs: &Bound<'py, PyDict>, out: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    use signorini_studies as st;
    let kw = kwargs.copy()?;
    let a = Args { study: name, d: &kw, asked: Default::default() };
    let none = |_: u64, _: u64| {};
    match name {
        "convergence" => {
            let mut c = st::convergence::Config { out: Some(out.clone()), ..Default::default() };
            if let Some(b) = a.str("benchmark")? {
                c.benchmark = st::convergence::parse_benchmark(&b).map_err(study_err)?;
            }
            if let Some(s) = a.strs("schemes")? {
                c.schemes = st::parse_schemes(&s).map_err(study_err)?;
            }
            if let Some(m) = a.strs("masses")? {
                c.masses = st::parse_masses(&m).map_err(study_err)?;
            }
            if let Some(l) = a.usizes("levels")? {
                c.levels = l;
            }
            c.ratio = a.f64("ratio")?.or(c.ratio);
            c.t_end = a.f64("t_end")?.or(c.t_end);
            if let Some(n) = a.str("norms")? {
                c.norms = st::convergence::parse_norms(&n).map_err(study_err)?;
            }
            c.clean = a.bool("clean")?.unwrap_or(c.clean);
            a.done()?;
            let o = detached(py, || st::convergence::run(&c, &none))?;
            let d = output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &o.out)?;
            let configs: Vec<(String, String, String)> = o.results.iter().map(|r| (r.scheme.to_string(), r.mass.to_string(), r.file_name())).collect();
            d.set_item("configs", configs)?;
            d.set_item("ratio", o.config.ratio)?;
            d.set_item("t_end", o.config.t_end)?;
            Ok(d)
        }
        "weighted" => {
            let mut c = st::weighted::Config { out: out.clone(), ..Default::default() };
            c.t_end = a.f64("t_end")?.unwrap_or(c.t_end);
            a.done()?;
            let o = detached(py, || st::weighted::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "stress" => {
            let mut c = st::stress::Config { out: out.clone(), ..Default::default() };
            c.steps = a.usize("steps")?.unwrap_or(c.steps);
            c.elements = a.usize("elements")?.unwrap_or(c.elements);
            c.seed = a.usize("seed")?.map_or(c.seed, |s| s as u64);
            a.done()?;
            let o = detached(py, || st::stress::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "work_precision" => {
            let mut c = st::work_precision::Config { out: out.clone(), ..Default::default() };
            c.levels = a.usizes("levels")?.unwrap_or(c.levels);
            c.degrees = a.usizes("degrees")?.unwrap_or(c.degrees);
            c.modes = a.usizes("modes")?.unwrap_or(c.modes);
            c.beam_dts = a.f64s("beam_dts")?.unwrap_or(c.beam_dts);
            c.beam_ref_dt = a.f64("beam_ref_dt")?.unwrap_or(c.beam_ref_dt);
            c.beam_window = a.f64("beam_window")?.unwrap_or(c.beam_window);
            c.beam_t_end = a.f64("beam_t_end")?.unwrap_or(c.beam_t_end);
            c.beam_stat_dts = a.f64s("beam_stat_dts")?.unwrap_or(c.beam_stat_dts);
            c.beam_stat_ref_dt = a.f64("beam_stat_ref_dt")?.unwrap_or(c.beam_stat_ref_dt);
            c.beam_stat_window = a.f64("beam_stat_window")?.unwrap_or(c.beam_stat_window);
            a.done()?;
            let o = detached(py, || st::work_precision::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "beam" => {
            let mut c = st::beam::Config { out: out.clone(), ..Default::default() };
            c.scenes = a.strs("scenes")?.unwrap_or(c.scenes);
            c.force = a.bool("force")?.unwrap_or(c.force);
            c.penalty_dts = a.f64s("penalty_dts")?.unwrap_or(c.penalty_dts);
            a.done()?;
            let o = detached(py, || st::beam::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "beam_obstacles" => {
            let mut c = st::obstacles::Config { out: out.clone(), ..Default::default() };
            c.gap = a.f64("gap")?.unwrap_or(c.gap);
            c.beta = a.f64("beta")?.unwrap_or(c.beta);
            c.t_end = a.f64("t_end")?.unwrap_or(c.t_end);
            c.dts = a.f64s("dts")?.unwrap_or(c.dts);
            c.j = a.usize("j")?.unwrap_or(c.j);
            c.js = a.usizes("js")?.unwrap_or(c.js);
            c.j_dt = a.f64("j_dt")?.unwrap_or(c.j_dt);
            a.done()?;
            let o = detached(py, || st::obstacles::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "oscillator" => {
            let mut c = st::oscillator::Config { out: out.clone(), ..Default::default() };
            c.omegas = a.f64s("omegas")?.unwrap_or(c.omegas);
            c.dts = a.f64s("dts")?.unwrap_or(c.dts);
            c.transient = a.f64("transient")?.unwrap_or(c.transient);
            c.record = a.f64("record")?.unwrap_or(c.record);
            a.done()?;
            let o = detached(py, || st::oscillator::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "courant1" => {
            let mut c = st::courant1::Config { out: out.clone(), ..Default::default() };
            if let Some(bs) = a.strs("benchmarks")? {
                c.benchmarks = bs.iter().map(|b| st::convergence::parse_benchmark(b)).collect::<Result<_, _>>().map_err(study_err)?;
            }
            c.levels = a.usizes("levels")?.unwrap_or(c.levels);
            c.t_end = a.f64("t_end")?.or(c.t_end);
            a.done()?;
            let o = detached(py, || st::courant1::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "long_horizon" => {
            let mut c = st::long_horizon::Config { out: out.clone(), ..Default::default() };
            if let Some(r) = a.strs("runs")? {
                c.runs = st::long_horizon::parse_runs(&r).map_err(study_err)?;
            }
            c.levels = a.usizes("levels")?.unwrap_or(c.levels);
            c.ratio = a.f64("ratio")?.unwrap_or(c.ratio);
            c.t_end = a.f64("t_end")?.unwrap_or(c.t_end);
            // The energy-growth table (energy=False: --no-energy).
            let (energy, runs, all) = (a.bool("energy")?, a.strs("energy_runs")?, a.bool("energy_all")?.unwrap_or(false));
            let (ratios, m, te) = (a.f64s("energy_ratios")?, a.usize("energy_m")?, a.f64("energy_t_end")?);
            if energy == Some(false) {
                if runs.is_some() || all || ratios.is_some() || m.is_some() || te.is_some() {
                    return Err(SceneError::new_err("energy: the energy_* arguments act only with energy=True: remove them, or energy=False"));
                }
                c.energy = None;
            }
            if let Some(e) = c.energy.as_mut() {
                if all && runs.is_some() {
                    return Err(SceneError::new_err("energy_runs: not both energy_runs and energy_all"));
                }
                if all {
                    e.runs = st::long_horizon::EnergyTable::all_runs();
                }
                if let Some(r) = runs {
                    e.runs = st::long_horizon::parse_runs(&r).map_err(|err| SceneError::new_err(err.to_string().replace("--runs", "energy_runs")))?;
                }
                e.ratios = ratios.unwrap_or(std::mem::take(&mut e.ratios));
                e.m = m.unwrap_or(e.m);
                e.t_end = te.unwrap_or(e.t_end);
            }
            a.done()?;
            let o = detached(py, || st::long_horizon::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "lyapunov" => {
            let mut c = st::lyapunov::Config { out: out.clone(), ..Default::default() };
            c.scenes = a.strs("scenes")?.unwrap_or(c.scenes);
            c.refine = a.strs("refine")?.unwrap_or(c.refine);
            c.dts = a.f64s("dts")?.unwrap_or(c.dts);
            c.elements = a.usizes("elements")?.unwrap_or(c.elements);
            c.omegas = a.f64s("omegas")?.unwrap_or(c.omegas);
            c.perturbation = a.f64("perturbation")?.unwrap_or(c.perturbation);
            c.transient = a.f64("transient")?.unwrap_or(c.transient);
            c.window = a.f64("window")?.unwrap_or(c.window);
            c.per_period = a.usize("per_period")?.unwrap_or(c.per_period);
            c.batches = a.usize("batches")?.unwrap_or(c.batches);
            a.done()?;
            let o = detached(py, || st::lyapunov::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        "beam_statistics" => {
            let mut c = st::beam_statistics::Config { out: out.clone(), ..Default::default() };
            c.scenes = a.strs("scenes")?.unwrap_or(c.scenes);
            c.dts = a.f64s("dts")?.unwrap_or(c.dts);
            c.elements = a.usizes("elements")?.unwrap_or(c.elements);
            c.transient = a.f64("transient")?.unwrap_or(c.transient);
            c.window = a.f64("window")?.unwrap_or(c.window);
            c.batches = a.usize("batches")?.unwrap_or(c.batches);
            c.episode_gap = a.f64("episode_gap")?.unwrap_or(c.episode_gap);
            a.done()?;
            let o = detached(py, || st::beam_statistics::run(&c, &none))?;
            output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &out)
        }
        other => Err(SceneError::new_err(format!(
            "study: {other:?} is not one of convergence, weighted, beam, beam_obstacles, oscillator, work_precision, stress, courant1, long_horizon, lyapunov, beam_statistics"
        ))),
    }
}
