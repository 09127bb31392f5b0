//! The studies from Python: the same `signorini_studies` functions as
//! `cargo xtask <study>`, configured from keyword arguments through the
//! studies' one reader (`signorini_studies::options::read`: every keyword is
//! a field of the study's `Config`, by its Rust name), run with the GIL
//! released; every CSV they write comes back as a table of numpy arrays.

use crate::{guarded, SceneError};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString};
use signorini_studies::options::{self, Input, Spelling, Study, Value};
use signorini_studies::{Column, StudyError, Table};
use std::path::PathBuf;

fn study_err(e: StudyError) -> PyErr {
    match &e {
        StudyError::Config { field, .. } => {
            // The message names the field as a keyword argument; it is put first.
            let m = e.render(Spelling::Neutral);
            SceneError::new_err(if m.starts_with(field.as_str()) { m } else { format!("{field}: {m}") })
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

/// `repr(v) (a T)`: a value in the words of an error.
fn words(v: &Bound<'_, PyAny>) -> String {
    let ty = v.get_type().name().map(|n| n.to_string()).unwrap_or_default();
    format!("{} (a {ty})", v.repr().map(|r| r.to_string()).unwrap_or_default())
}

/// A keyword argument's value as the studies' reader takes it (a numpy
/// scalar or array as the Python value it holds; an iterable other than a
/// str as a list).
fn input(v: &Bound<'_, PyAny>) -> PyResult<Input> {
    let w = words(v);
    let x = match crate::numpy_plain(v)? {
        Some(p) => p,
        None => v.clone(),
    };
    let value = if x.is_instance_of::<PyBool>() {
        Value::Bool(x.extract()?)
    } else if x.is_instance_of::<PyInt>() {
        x.extract::<i128>().map_or(Value::Other, Value::Int)
    } else if x.is_instance_of::<PyFloat>() {
        Value::Float(x.extract()?)
    } else if x.is_instance_of::<PyString>() {
        Value::Str(x.extract()?)
    } else if let Ok(it) = x.try_iter() {
        Value::List(it.map(|i| i.and_then(|i| input(&i))).collect::<PyResult<_>>()?)
    } else {
        Value::Other
    };
    Ok(Input { value, words: w })
}

/// The keyword arguments as (field, value) pairs.
fn given(kwargs: &Bound<'_, PyDict>, out: &std::path::Path) -> PyResult<Vec<(String, Input)>> {
    let mut v: Vec<(String, Input)> = kwargs.iter().map(|(k, x)| Ok((k.extract::<String>()?, input(&x)?))).collect::<PyResult<_>>()?;
    v.push(("out".into(), Input { value: Value::Str(out.display().to_string()), words: format!("{:?}", out.display().to_string()) }));
    Ok(v)
}

/// One field for Python: `(name, kind, doc, default)`.
type FieldRow = (String, String, String, Option<String>);

/// A study's fields for the Python functions: `(name, kind, doc, default)`,
/// `kind` one of switch, number, text, numbers, texts; `default` the value's
/// text (None: computed by the study).
fn fields<C: Study>() -> Vec<FieldRow> {
    let d = C::default();
    C::FIELDS
        .iter()
        .map(|f| {
            let kind = match f.kind {
                options::Kind::Switch => "switch",
                options::Kind::Number => "number",
                options::Kind::Text => "text",
                options::Kind::Numbers => "numbers",
                options::Kind::Texts => "texts",
            };
            (f.name.to_string(), kind.to_string(), f.doc(Spelling::Neutral), d.show(f.name).filter(|s| !s.is_empty() || f.kind.is_list()))
        })
        .collect()
}

/// Runs `f` with the GIL released, a panic turned into `InternalError`.
fn detached<T: Send>(py: Python<'_>, f: impl FnOnce() -> Result<T, StudyError> + Send) -> PyResult<T> {
    py.detach(|| guarded(|| f().map_err(study_err)))
}

/// Runs the study `name` with the keyword arguments `kwargs` (the fields
/// of its `Config`, the options of `cargo xtask <name>` as Python names)
/// writing into `out`; returns the tables, the report, the wall time, the
/// notes and (convergence) the configurations in order.
#[pyfunction]
pub fn study<'py>(py: Python<'py>, name: &str, kwargs: &Bound<'py, PyDict>, out: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let c = configure(name, &given(kwargs, &out)?)?;
    c.run(py, &out)
}

/// What [`study`] would run, validated and not run: `None`, or the
/// SceneError `study` would raise before running (the tests check each
/// option's stated range against what the study accepts).
#[pyfunction]
pub fn study_check(name: &str, kwargs: &Bound<'_, PyDict>) -> PyResult<()> {
    let out = std::env::temp_dir().join("signorini-study-check-unused");
    configure(name, &given(kwargs, &out)?)?.validate().map_err(study_err)
}

/// The fields of study `name` (its keyword arguments, in order):
/// `(name, kind, doc, default)` ([`fields`]).
#[pyfunction]
pub fn study_fields(name: &str) -> PyResult<Vec<FieldRow>> {
    use signorini_studies as st;
    Ok(match name {
        "convergence" => fields::<st::convergence::Config>(),
        "weighted" => fields::<st::weighted::Config>(),
        "stress" => fields::<st::stress::Config>(),
        "work_precision" => fields::<st::work_precision::Config>(),
        "beam" => fields::<st::beam::Config>(),
        "beam_obstacles" => fields::<st::obstacles::Config>(),
        "oscillator" => fields::<st::oscillator::Config>(),
        "courant1" => fields::<st::courant1::Config>(),
        "long_horizon" => fields::<st::long_horizon::Config>(),
        "lyapunov" => fields::<st::lyapunov::Config>(),
        "beam_statistics" => fields::<st::beam_statistics::Config>(),
        other => return Err(unknown(other)),
    })
}

fn unknown(name: &str) -> PyErr {
    SceneError::new_err(format!("study: {name:?} is not one of convergence, weighted, beam, beam_obstacles, oscillator, work_precision, stress, courant1, long_horizon, lyapunov, beam_statistics"))
}

/// The configuration of the study `name` from its fields, read by the
/// studies' one reader (not yet validated).
fn configure(name: &str, given: &[(String, Input)]) -> PyResult<Cfg> {
    use signorini_studies as st;
    let r = |e| study_err(e);
    Ok(match name {
        "convergence" => Cfg::Convergence(options::read(given).map_err(r)?),
        "weighted" => Cfg::Weighted(options::read(given).map_err(r)?),
        "stress" => Cfg::Stress(options::read(given).map_err(r)?),
        "work_precision" => Cfg::WorkPrecision(options::read::<st::work_precision::Config>(given).map_err(r)?),
        "beam" => Cfg::Beam(options::read(given).map_err(r)?),
        "beam_obstacles" => Cfg::Obstacles(options::read(given).map_err(r)?),
        "oscillator" => Cfg::Oscillator(options::read(given).map_err(r)?),
        "courant1" => Cfg::Courant1(options::read(given).map_err(r)?),
        "long_horizon" => Cfg::LongHorizon(options::read(given).map_err(r)?),
        "lyapunov" => Cfg::Lyapunov(options::read(given).map_err(r)?),
        "beam_statistics" => Cfg::BeamStatistics(options::read(given).map_err(r)?),
        other => return Err(unknown(other)),
    })
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
