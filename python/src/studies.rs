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
            let m = py_flags(&message);
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

/// Which out-of-range value stands in for a wrongly typed number while the
/// study's own `validate` is asked for the allowed range ([`study`]).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Sentinel {
    /// 0 for an int (below every minimum but 0), NaN for a float.
    Low,
    /// The largest int (above every maximum), NaN for a float.
    High,
}

/// The first keyword argument whose value has the wrong type for a number:
/// its name (`levels[1]` for an item), the study's option it sets, the
/// value in Python's words and the type wanted.
struct WrongType {
    key: String,
    option: String,
    value: String,
    int: bool,
}

/// Takes the keyword arguments one by one, naming the argument in every
/// error; anything left over is an unknown argument. A number of the wrong
/// type (a str, a bool, a float with a fraction where an int is wanted) is
/// not refused on the spot: it is recorded, and a [`Sentinel`] stands in,
/// so that the study's `validate` — the one place that knows the ranges —
/// states what is allowed.
struct Args<'a, 'py> {
    study: &'a str,
    d: &'a Bound<'py, PyDict>,
    /// Every argument asked for, for the error on one left over.
    asked: std::cell::RefCell<Vec<String>>,
    sentinel: Sentinel,
    wrong: std::cell::RefCell<Option<WrongType>>,
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
    fn words(v: &Bound<'py, PyAny>) -> String {
        let ty = v.get_type().name().map(|n| n.to_string()).unwrap_or_default();
        format!("{} (a {ty})", v.repr().map(|r| r.to_string()).unwrap_or_default())
    }
    fn bad(&self, key: &str, v: &Bound<'py, PyAny>, want: &str) -> PyErr {
        SceneError::new_err(format!("{key}: {} is not allowed: {want}", Self::words(v)))
    }
    /// Records `key`'s wrong type (the first one only) for [`study`].
    fn wrong(&self, key: &str, option: &str, v: &Bound<'py, PyAny>, int: bool) {
        let mut w = self.wrong.borrow_mut();
        if w.is_none() {
            *w = Some(WrongType { key: key.to_string(), option: option.to_string(), value: Self::words(v), int });
        }
    }
    /// `v`, or the Python value a numpy scalar or 0-d array holds.
    fn plain(v: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match crate::numpy_plain(v)? {
            Some(p) if !p.is_instance_of::<pyo3::types::PyList>() => Ok(p),
            _ => Ok(v.clone()),
        }
    }
    fn float(&self, key: &str, option: &str, v: &Bound<'py, PyAny>) -> PyResult<f64> {
        let x = Self::plain(v)?;
        let ok = !(x.is_instance_of::<pyo3::types::PyBool>() || x.is_instance_of::<pyo3::types::PyString>());
        match x.extract::<f64>() {
            Ok(f) if ok => Ok(f),
            _ => {
                self.wrong(key, option, v, false);
                Ok(f64::NAN)
            }
        }
    }
    fn int(&self, key: &str, option: &str, v: &Bound<'py, PyAny>) -> PyResult<usize> {
        let x = Self::plain(v)?;
        let got = if x.is_instance_of::<pyo3::types::PyBool>() {
            None
        } else if x.is_instance_of::<pyo3::types::PyFloat>() {
            // A float with a whole value is that int (80.0); 80.5 is not.
            let f: f64 = x.extract()?;
            (f.fract() == 0.0 && f >= 0.0 && f < 2f64.powi(53)).then_some(f as usize)
        } else {
            x.extract::<usize>().ok()
        };
        Ok(got.unwrap_or_else(|| {
            self.wrong(key, option, v, true);
            match self.sentinel {
                Sentinel::Low => 0,
                Sentinel::High => usize::MAX,
            }
        }))
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
        self.take(key)?.map(|v| self.float(key, key, &v)).transpose()
    }
    fn usize(&self, key: &str) -> PyResult<Option<usize>> {
        self.take(key)?.map(|v| self.int(key, key, &v)).transpose()
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
        self.take(key)?.map(|v| self.list(key, &v)?.iter().enumerate().map(|(i, x)| self.int(&format!("{key}[{i}]"), key, x)).collect()).transpose()
    }
    fn f64s(&self, key: &str) -> PyResult<Option<Vec<f64>>> {
        self.take(key)?.map(|v| self.list(key, &v)?.iter().enumerate().map(|(i, x)| self.float(&format!("{key}[{i}]"), key, x)).collect()).transpose()
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
    let c = configured(name, kwargs, &out)?;
    c.run(py, &out)
}

/// What [`study`] would run, validated and not run: `None`, or the
/// SceneError `study` would raise before running (the tests check each
/// option's stated range against what the study accepts).
#[pyfunction]
pub fn study_check(name: &str, kwargs: &Bound<'_, PyDict>) -> PyResult<()> {
    let out = std::env::temp_dir().join("signorini-study-check-unused");
    configured(name, kwargs, &out)?.validate().map_err(study_err)
}

/// The configuration of the study `name`, or the SceneError of a wrongly
/// typed argument with the range the study's `validate` states for it
/// (found by handing `validate` an out-of-range stand-in, [`Sentinel`]).
fn configured(name: &str, kwargs: &Bound<'_, PyDict>, out: &std::path::Path) -> PyResult<Cfg> {
    let (c, wrong) = configure(name, kwargs, out, Sentinel::Low)?;
    let Some(w) = wrong else { return Ok(c) };
    let mut allowed = range_of(&c, &w);
    if allowed.is_none() && w.int {
        allowed = range_of(&configure(name, kwargs, out, Sentinel::High)?.0, &w);
    }
    let want = allowed.unwrap_or_else(|| if w.int { "an int >= 0".into() } else { "a number (int or float)".into() });
    Err(SceneError::new_err(format!("{}: {} is not allowed: {want}", w.key, w.value)))
}

/// What `c.validate()` says is allowed for `w`'s option, when it refuses
/// the stand-in value naming that option.
fn range_of(c: &Cfg, w: &WrongType) -> Option<String> {
    // A panic on the stand-in would be a bug of `validate`: no range then.
    guarded(|| Ok(c.validate().err().and_then(|e| allowed_of(e, &w.option)))).ok().flatten()
}

/// The allowed part of a study's error about the Python argument `option`:
/// the text after "allowed" (`--batches 0: allowed an integer in [10,
/// 1000]` → `an integer in [10, 1000]`); None for an error about another
/// option or without that word.
fn allowed_of(e: StudyError, option: &str) -> Option<String> {
    let StudyError::Config { field, message } = e else { return None };
    // The error names the option, or (a check of two options together:
    // `--js … / --j …`) mentions its flag.
    let flag = format!("--{}", option.replace('_', "-"));
    let mentions = message.match_indices(&flag).any(|(at, _)| !message[at + flag.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '-'));
    if py_name(&field) != option && !mentions {
        return None;
    }
    // The text after "allowed", else after the option and its value
    // (`--j-dt NaN: must divide …`).
    let rest = match message.find("allowed") {
        Some(at) => &message[at + "allowed".len()..],
        None => message.split_once(": ").map_or("", |(_, r)| r),
    };
    let rest = py_flags(rest.trim_start_matches(':').trim());
    (!rest.is_empty()).then_some(rest)
}

/// `text` with each `--flag-name` as the Python argument `flag_name`.
fn py_flags(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let name: String = rest[at + 2..].chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '-').collect();
        if name.starts_with(|c: char| c.is_ascii_alphabetic()) {
            out.push_str(&name.replace('-', "_"));
        } else {
            out.push_str("--");
            out.push_str(&name);
        }
        rest = &rest[at + 2 + name.len()..];
    }
    out.push_str(rest);
    out
}

/// A study's configuration.
enum Cfg {
    Convergence(signorini_studies::convergence::Config),
    Weighted(signorini_studies::weighted::Config),
    Stress(signorini_studies::stress::Config),
    WorkPrecision(signorini_studies::work_precision::Config),
    Beam(signorini_studies::beam::Config),
    Obstacles(signorini_studies::obstacles::Config),
    Oscillator(signorini_studies::oscillator::Config),
    Courant1(signorini_studies::courant1::Config),
    LongHorizon(signorini_studies::long_horizon::Config),
    Lyapunov(signorini_studies::lyapunov::Config),
    BeamStatistics(signorini_studies::beam_statistics::Config),
}

impl Cfg {
    fn validate(&self) -> Result<(), StudyError> {
        match self {
            Cfg::Convergence(c) => c.validate(),
            Cfg::Weighted(c) => c.validate(),
            Cfg::Stress(c) => c.validate(),
            Cfg::WorkPrecision(c) => c.validate(),
            Cfg::Beam(c) => c.validate(),
            Cfg::Obstacles(c) => c.validate(),
            Cfg::Oscillator(c) => c.validate(),
            Cfg::Courant1(c) => c.validate(),
            Cfg::LongHorizon(c) => c.validate(),
            Cfg::Lyapunov(c) => c.validate(),
            Cfg::BeamStatistics(c) => c.validate(),
        }
    }

    fn run<'py>(&self, py: Python<'py>, out: &std::path::Path) -> PyResult<Bound<'py, PyDict>> {
        use signorini_studies as st;
        let none = |_: u64, _: u64| {};
        macro_rules! plain {
            ($m:ident, $c:expr) => {{
                let o = detached(py, || st::$m::run($c, &none))?;
                output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, out)
            }};
        }
        match self {
            Cfg::Convergence(c) => {
                let o = detached(py, || st::convergence::run(c, &none))?;
                let d = output_py(py, &o.tables, &o.report, o.wall_s, &o.notes, &o.out)?;
                let configs: Vec<(String, String, String)> = o.results.iter().map(|r| (r.scheme.to_string(), r.mass.to_string(), r.file_name())).collect();
                d.set_item("configs", configs)?;
                d.set_item("ratio", o.config.ratio)?;
                d.set_item("t_end", o.config.t_end)?;
                Ok(d)
            }
            Cfg::Weighted(c) => plain!(weighted, c),
            Cfg::Stress(c) => plain!(stress, c),
            Cfg::WorkPrecision(c) => plain!(work_precision, c),
            Cfg::Beam(c) => plain!(beam, c),
            Cfg::Obstacles(c) => plain!(obstacles, c),
            Cfg::Oscillator(c) => plain!(oscillator, c),
            Cfg::Courant1(c) => plain!(courant1, c),
            Cfg::LongHorizon(c) => plain!(long_horizon, c),
            Cfg::Lyapunov(c) => plain!(lyapunov, c),
            Cfg::BeamStatistics(c) => plain!(beam_statistics, c),
        }
    }
}

/// The configuration of the study `name` from the keyword arguments, and
/// the first argument of a wrong type (its value replaced by `sentinel`).
fn configure(name: &str, kwargs: &Bound<'_, PyDict>, out: &std::path::Path, sentinel: Sentinel) -> PyResult<(Cfg, Option<WrongType>)> {
    use signorini_studies as st;
    let out = out.to_path_buf();
    let kw = kwargs.copy()?;
    let a = Args { study: name, d: &kw, asked: Default::default(), sentinel, wrong: Default::default() };
    let c = match name {
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
            Cfg::Convergence(c)
        }
        "weighted" => {
            let mut c = st::weighted::Config { out: out.clone(), ..Default::default() };
            c.t_end = a.f64("t_end")?.unwrap_or(c.t_end);
            a.done()?;
            Cfg::Weighted(c)
        }
        "stress" => {
            let mut c = st::stress::Config { out: out.clone(), ..Default::default() };
            c.steps = a.usize("steps")?.unwrap_or(c.steps);
            c.elements = a.usize("elements")?.unwrap_or(c.elements);
            c.seed = a.usize("seed")?.map_or(c.seed, |s| s as u64);
            a.done()?;
            Cfg::Stress(c)
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
            Cfg::WorkPrecision(c)
        }
        "beam" => {
            let mut c = st::beam::Config { out: out.clone(), ..Default::default() };
            c.scenes = a.strs("scenes")?.unwrap_or(c.scenes);
            c.force = a.bool("force")?.unwrap_or(c.force);
            c.penalty_dts = a.f64s("penalty_dts")?.unwrap_or(c.penalty_dts);
            a.done()?;
            Cfg::Beam(c)
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
            Cfg::Obstacles(c)
        }
        "oscillator" => {
            let mut c = st::oscillator::Config { out: out.clone(), ..Default::default() };
            c.omegas = a.f64s("omegas")?.unwrap_or(c.omegas);
            c.dts = a.f64s("dts")?.unwrap_or(c.dts);
            c.transient = a.f64("transient")?.unwrap_or(c.transient);
            c.record = a.f64("record")?.unwrap_or(c.record);
            a.done()?;
            Cfg::Oscillator(c)
        }
        "courant1" => {
            let mut c = st::courant1::Config { out: out.clone(), ..Default::default() };
            if let Some(bs) = a.strs("benchmarks")? {
                c.benchmarks = bs.iter().map(|b| st::convergence::parse_benchmark(b)).collect::<Result<_, _>>().map_err(study_err)?;
            }
            c.levels = a.usizes("levels")?.unwrap_or(c.levels);
            c.t_end = a.f64("t_end")?.or(c.t_end);
            a.done()?;
            Cfg::Courant1(c)
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
            Cfg::LongHorizon(c)
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
            Cfg::Lyapunov(c)
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
            Cfg::BeamStatistics(c)
        }
        other => {
            return Err(SceneError::new_err(format!(
                "study: {other:?} is not one of convergence, weighted, beam, beam_obstacles, oscillator, work_precision, stress, courant1, long_horizon, lyapunov, beam_statistics"
            )))
        }
    };
    Ok((c, a.wrong.into_inner()))
}
