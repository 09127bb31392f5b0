//! The compiled half of the `signorini` Python package (`signorini._signorini`):
//! thin bindings over the workspace crates. The Python half (`python/signorini/`)
//! broadcasts arrays and documents the API; every entry point here turns a
//! Rust panic into `signorini.InternalError` instead of aborting.

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use signorini_exact::{Backbone, BackboneError, BarDirichlet, BarMirrored, BarNeumannGravity, ExactSolution, FarEnd, ModeBar, NeumannError};

mod fem;
mod orbits;
mod run;
mod studies;
mod sweep;

create_exception!(signorini, SceneError, PyValueError, "Bad input: names the field and the allowed range.");
create_exception!(signorini, BlowUp, PyException, "A run became non-finite or its energy grew beyond bounds (step and time in the message).");
create_exception!(signorini, InternalError, PyRuntimeError, "A bug in signorini (a Rust panic), reported instead of aborting the interpreter.");

/// Runs `f`, turning a panic into `InternalError`.
pub(crate) fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(p) => {
            let msg = p.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| p.downcast_ref::<String>().cloned()).unwrap_or_else(|| "unknown panic".to_owned());
            Err(InternalError::new_err(format!("internal error (Rust panic): {msg}")))
        }
    }
}

/// Runs `work` on a worker thread with the GIL released while this thread
/// polls Python's signal handlers every 50 ms; on the first pending signal
/// (Ctrl-C) it cancels `cancel`, which the run or sweep checks, and keeps
/// the exception. Returns the work's result (a panic on the worker is an
/// `InternalError`) and that exception, if any.
pub(crate) fn interruptible<T: Send>(py: Python<'_>, cancel: &signorini_run::Cancel, work: impl FnOnce() -> PyResult<T> + Send) -> (PyResult<T>, Option<PyErr>) {
    py.detach(|| {
        std::thread::scope(|sc| {
            let worker = sc.spawn(|| guarded(work));
            let mut signal = None;
            while !worker.is_finished() {
                std::thread::sleep(std::time::Duration::from_millis(50));
                if signal.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        signal = Some(e);
                        cancel.cancel();
                    }
                }
            }
            (worker.join().unwrap_or_else(|_| Err(InternalError::new_err("the worker thread panicked"))), signal)
        })
    })
}

/// An exact benchmark solution (see `signorini.exact.solution`).
#[pyclass(module = "signorini._signorini", frozen)]
struct Exact {
    inner: Box<dyn ExactSolution>,
}

impl Exact {
    fn map2<'py>(&self, py: Python<'py>, x: PyReadonlyArray1<'py, f64>, t: PyReadonlyArray1<'py, f64>, f: impl Fn(&dyn ExactSolution, f64, f64) -> f64) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guarded(|| {
            let (x, t) = (x.as_slice()?, t.as_slice()?);
            if x.len() != t.len() {
                return Err(SceneError::new_err(format!("x and t: {} and {} values; allowed: arrays of one shape (the Python wrapper broadcasts)", x.len(), t.len())));
            }
            let out: Vec<f64> = x.iter().zip(t).map(|(&x, &t)| f(self.inner.as_ref(), x, t)).collect();
            Ok(out.into_pyarray(py))
        })
    }
}

#[pymethods]
impl Exact {
    /// The benchmark's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name().to_string()
    }
    /// The bar's length L.
    #[getter]
    fn length(&self) -> f64 {
        self.inner.length()
    }
    /// u(x, t) at paired points.
    fn u<'py>(&self, py: Python<'py>, x: PyReadonlyArray1<'py, f64>, t: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.map2(py, x, t, |s, x, t| s.fields(x, t).u)
    }
    /// u_x(x, t) at paired points.
    fn u_x<'py>(&self, py: Python<'py>, x: PyReadonlyArray1<'py, f64>, t: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.map2(py, x, t, |s, x, t| s.fields(x, t).ux)
    }
    /// u_t(x, t) at paired points.
    fn u_t<'py>(&self, py: Python<'py>, x: PyReadonlyArray1<'py, f64>, t: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.map2(py, x, t, |s, x, t| s.fields(x, t).ut)
    }
    /// The contact force λ(t).
    fn lam<'py>(&self, py: Python<'py>, t: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guarded(|| Ok(t.as_slice()?.iter().map(|&t| self.inner.lambda(t)).collect::<Vec<f64>>().into_pyarray(py)))
    }
    /// The (conserved) energy.
    fn energy(&self) -> f64 {
        self.inner.energy()
    }
    /// The energy at each time: the conserved value where the solution is
    /// defined, NaN elsewhere (a NaN or infinite t, beyond t_max).
    fn energy_at<'py>(&self, py: Python<'py>, t: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guarded(|| Ok(t.as_slice()?.iter().map(|&t| self.inner.energy_at(t)).collect::<Vec<f64>>().into_pyarray(py)))
    }
}

/// A backbone error as the SceneError naming its field and range.
fn backbone_error(e: BackboneError) -> PyErr {
    SceneError::new_err(format!("{}: {} is not allowed: {}", e.field(), e.value(), e.allowed()))
}

/// The `[bar]` data of a nonsmooth mode (defaults: L = 1, c = 1, g = 0,
/// clamped, the family 1), checked by the exact crate.
fn mode_backbone(length: Option<f64>, wave_speed: Option<f64>, gap: Option<f64>, far_end: Option<&str>, family: Option<i64>) -> PyResult<Backbone> {
    let far_end = match far_end.unwrap_or("clamped") {
        "clamped" => FarEnd::Clamped,
        "free" => FarEnd::Free,
        other => return Err(SceneError::new_err(format!("far_end: {other:?} is not allowed: \"clamped\" or \"free\""))),
    };
    let family = family.unwrap_or(1);
    let family = u32::try_from(family).map_err(|_| SceneError::new_err(format!("family: {family} is not allowed: >= 1")))?;
    Backbone::new(ModeBar { length: length.unwrap_or(1.0), wave_speed: wave_speed.unwrap_or(1.0), gap: gap.unwrap_or(0.0), far_end }, family).map_err(backbone_error)
}

/// The backbone of a family of nonsmooth modes (see `signorini.exact.backbone`).
#[pyclass(module = "signorini._signorini", frozen)]
struct ExactBackbone {
    inner: Backbone,
}

#[pymethods]
impl ExactBackbone {
    /// The family index k.
    #[getter]
    fn family(&self) -> u32 {
        self.inner.family()
    }
    /// The least energy with contact (g < 0: where the linear motion first
    /// touches; g > 0: the static state's energy; 0 for g = 0).
    #[getter]
    fn threshold(&self) -> f64 {
        self.inner.threshold()
    }
    /// The linear period 4L/((2k-1)c).
    #[getter]
    fn linear_period(&self) -> f64 {
        self.inner.linear_period()
    }
    /// The period at g = 0, and the limit E -> inf: (2k+1)L/(k^2 c).
    #[getter]
    fn limit_period(&self) -> f64 {
        self.inner.limit_period()
    }
    /// The backbone at each energy: a dict of arrays (period, contact_time,
    /// flight_time, impacts_per_period, impact_velocity, contact_force).
    fn at<'py>(&self, py: Python<'py>, energy: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let points = guarded(|| energy.as_slice()?.iter().map(|&e| self.inner.point(e).map_err(backbone_error)).collect::<PyResult<Vec<_>>>())?;
        let d = pyo3::types::PyDict::new(py);
        let col = |f: fn(&signorini_exact::BackbonePoint) -> f64| points.iter().map(f).collect::<Vec<f64>>().into_pyarray(py);
        d.set_item("period", col(|p| p.period))?;
        d.set_item("contact_time", col(|p| p.contact_time))?;
        d.set_item("flight_time", col(|p| p.flight_time))?;
        d.set_item("impacts_per_period", points.iter().map(|p| i64::from(p.impacts_per_period)).collect::<Vec<i64>>().into_pyarray(py))?;
        d.set_item("impact_velocity", col(|p| p.impact_velocity))?;
        d.set_item("contact_force", col(|p| p.contact_force))?;
        Ok(d)
    }
}

/// The backbone of the family `family` of nonsmooth modes of the bar
/// (docs/theory.md §11).
#[pyfunction]
#[pyo3(signature = (length=None, wave_speed=None, gap=None, far_end=None, family=None))]
fn exact_backbone(length: Option<f64>, wave_speed: Option<f64>, gap: Option<f64>, far_end: Option<&str>, family: Option<i64>) -> PyResult<ExactBackbone> {
    guarded(|| Ok(ExactBackbone { inner: mode_backbone(length, wave_speed, gap, far_end, family)? }))
}

/// The exact solution `name` ("bar-dirichlet", "bar-mirrored",
/// "bar-neumann-gravity"; the falling bar takes g, u0, length, t_max;
/// "nonsmooth-mode" takes energy, length, wave_speed, gap, family).
#[pyfunction]
#[pyo3(signature = (name, g=None, u0=None, length=None, t_max=None, energy=None, wave_speed=None, gap=None, family=None))]
#[allow(clippy::too_many_arguments)]
fn exact_solution(
    name: &str,
    g: Option<f64>,
    u0: Option<f64>,
    length: Option<f64>,
    t_max: Option<f64>,
    energy: Option<f64>,
    wave_speed: Option<f64>,
    gap: Option<f64>,
    family: Option<f64>,
) -> PyResult<Exact> {
    guarded(|| {
        let mode_only = [("energy", energy), ("wave_speed", wave_speed), ("gap", gap), ("family", family)];
        let no_params = |bench: &str| -> PyResult<()> {
            for (k, v) in [("g", g), ("u0", u0), ("length", length), ("t_max", t_max)].into_iter().chain(mode_only) {
                if v.is_some() {
                    return Err(SceneError::new_err(format!("{k}: {bench} takes no parameters (its data are fixed); allowed: none")));
                }
            }
            Ok(())
        };
        let inner: Box<dyn ExactSolution> = match name {
            "bar-dirichlet" => {
                no_params(name)?;
                Box::new(BarDirichlet)
            }
            "bar-mirrored" => {
                no_params(name)?;
                Box::new(BarMirrored)
            }
            "nonsmooth-mode" => {
                for (k, v) in [("g", g), ("u0", u0), ("t_max", t_max)] {
                    if v.is_some() {
                        return Err(SceneError::new_err(format!("{k}: not a parameter of nonsmooth-mode; allowed: energy, length, wave_speed, gap, family")));
                    }
                }
                let energy = energy.ok_or_else(|| SceneError::new_err("energy: required by nonsmooth-mode; allowed: finite and >= 0"))?;
                let family = match family {
                    None => None,
                    Some(k) if k.is_finite() && k.fract() == 0.0 && k >= 1.0 && k <= f64::from(u32::MAX) => Some(k as i64),
                    Some(k) => return Err(SceneError::new_err(format!("family: {k} is not allowed: an integer >= 1"))),
                };
                Box::new(mode_backbone(length, wave_speed, gap, None, family)?.mode(energy).map_err(backbone_error)?)
            }
            "bar-neumann-gravity" | "bar-neumann-gravity-0.11" => {
                for (k, v) in mode_only {
                    if v.is_some() {
                        return Err(SceneError::new_err(format!("{k}: not a parameter of {name}; allowed: g, u0, length, t_max")));
                    }
                }
                let paper = name.ends_with("0.11");
                let t_max = t_max.unwrap_or(16.0);
                let s = match (g, u0, length) {
                    // The benchmarks' own data keep their names.
                    (None, None, None) if paper => BarNeumannGravity::paper(t_max),
                    (None, None, None) => BarNeumannGravity::periodic(t_max),
                    _ => BarNeumannGravity::new(u0.unwrap_or(0.5), g.unwrap_or(if paper { 0.11 } else { 1.0 / 9.0 }), length.unwrap_or(1.0), t_max),
                };
                // The parameter first, then its range (the exact crate's words).
                Box::new(s.map_err(|e| match e {
                    NeumannError::TooComplex { t_limit, .. } | NeumannError::Unresolved { t_limit, .. } => {
                        SceneError::new_err(format!("{}: {} is not allowed: at most about {t_limit} for these data ({})", e.field(), e.value(), e.allowed()))
                    }
                    _ => SceneError::new_err(format!("{}: {} is not allowed: {}", e.field(), e.value(), e.allowed())),
                })?)
            }
            other => return Err(SceneError::new_err(format!("name: {other:?} is not allowed: bar-dirichlet, bar-mirrored, bar-neumann-gravity, bar-neumann-gravity-0.11, nonsmooth-mode"))),
        };
        Ok(Exact { inner })
    })
}

/// A Python value as TOML (`path` names it in errors): dicts are tables,
/// lists arrays, and numbers, strings and booleans themselves.
fn to_toml(v: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
    // numpy: a scalar or 0-d array is the Python value it holds (a numpy
    // bool stays a bool, an integer an integer), an array a list.
    if let Some(plain) = numpy_plain(v)? {
        return to_toml(&plain, path);
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return v.extract::<i64>().map(toml::Value::Integer).map_err(|_| SceneError::new_err(format!("{path}: an integer beyond 64 bits is not allowed")));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, val) in d.iter() {
            let k: String = k.extract().map_err(|_| SceneError::new_err(format!("{path}: keys must be strings")))?;
            let sub = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
            t.insert(k, to_toml(&val, &sub)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut a = Vec::new();
        for (i, item) in v.try_iter()?.enumerate() {
            a.push(to_toml(&item?, &format!("{path}.{i}"))?);
        }
        return Ok(toml::Value::Array(a));
    }
    // numpy scalars and other numbers.
    if let Ok(x) = v.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    Err(SceneError::new_err(format!("{}: {} is not allowed: a number (int or float), a str, a bool, a list or a dict", if path.is_empty() { "scene" } else { path }, type_words(v))))
}

/// A numpy scalar or 0-d array as the Python value it holds (`.item()`), a
/// numpy array of any other shape as nested lists (`.tolist()`); `None` for
/// anything that is not numpy's.
pub(crate) fn numpy_plain<'py>(v: &Bound<'py, PyAny>) -> PyResult<Option<Bound<'py, PyAny>>> {
    if !v.hasattr("dtype")? {
        return Ok(None);
    }
    let Ok(ndim) = v.getattr("ndim").and_then(|n| n.extract::<usize>()) else { return Ok(None) };
    let method = if ndim == 0 { "item" } else { "tolist" };
    if !v.hasattr(method)? {
        return Ok(None);
    }
    Ok(Some(v.call_method0(method)?))
}

/// `repr(v) (a T)`, T the Python type's name.
fn type_words(v: &Bound<'_, PyAny>) -> String {
    let ty = v.get_type().name().map(|n| n.to_string()).unwrap_or_default();
    let r = v.repr().map(|r| r.to_string()).unwrap_or_default();
    let r = if r.chars().count() > 60 { format!("{}...", r.chars().take(57).collect::<String>()) } else { r };
    format!("{r} (a {ty})")
}

/// serde's words for a value or a type, in Python's.
fn py_words(serde: &str) -> String {
    let quoted = |s: &str| s.split('`').nth(1).unwrap_or("").to_string();
    let t = serde.trim();
    match t {
        "sequence" | "a sequence" => "a list".into(),
        "map" | "a map" => "a dict".into(),
        "a string" => "a str".into(),
        "a boolean" => "a bool (True or False)".into(),
        "usize" | "u64" | "u32" | "u16" | "u8" => "an int >= 0".into(),
        "i64" | "i32" | "isize" => "an int".into(),
        "f64" | "f32" => "a number (int or float)".into(),
        _ if t.starts_with("struct ") => "a dict".into(),
        _ if t.starts_with("floating point `") => format!("{} (a float)", quoted(t)),
        _ if t.starts_with("integer `") => format!("{} (an int)", quoted(t)),
        _ if t.starts_with("boolean `") => (if quoted(t) == "true" { "True (a bool)" } else { "False (a bool)" }).into(),
        _ if t.starts_with("string \"") => format!("'{}' (a str)", t.trim_start_matches("string \"").trim_end_matches('"')),
        _ => t.replace('`', ""),
    }
}

/// The segments of a dotted path (`stop.0.node`, `stop[0].node`).
fn path_segments(path: &str) -> Vec<String> {
    path.replace('[', ".").replace(']', "").split('.').filter(|s| !s.is_empty()).map(str::to_string).collect()
}

/// `doc` with the value at `path` replaced by `v`; None if the path is not
/// in the document.
fn with_value(doc: &toml::Table, path: &str, v: toml::Value) -> Option<toml::Table> {
    fn put(at: &mut toml::Value, segs: &[String], v: toml::Value) -> Option<()> {
        let Some((first, rest)) = segs.split_first() else {
            *at = v;
            return Some(());
        };
        let next = match at {
            toml::Value::Table(t) => t.get_mut(first)?,
            toml::Value::Array(a) => a.get_mut(first.parse::<usize>().ok()?)?,
            _ => return None,
        };
        put(next, rest, v)
    }
    let mut d = toml::Value::Table(doc.clone());
    put(&mut d, &path_segments(path), v)?;
    match d {
        toml::Value::Table(t) => Some(t),
        _ => None,
    }
}

/// What the scene's validation allows at `path` (a number the document
/// holds with the wrong type), in its own words: the document is validated
/// with an out-of-range stand-in there (0, then the largest int, for an
/// integer key; NaN for a real one), and the part after "is not allowed:"
/// (or "allowed") of its error about that key is the range. The scene
/// crate's validation is thus the one place the ranges are written. None
/// when no stand-in is refused naming the key (another key is wrong too, or
/// every value of the type is allowed).
fn scene_range(doc: &toml::Table, path: &str, int: bool) -> Option<String> {
    use signorini_scene::{Limits, SceneError as E, SceneFile};
    let stand_ins = if int { vec![toml::Value::Integer(0), toml::Value::Integer(i64::MAX)] } else { vec![toml::Value::Float(f64::NAN)] };
    let want = path_segments(path);
    for v in stand_ins {
        let d = with_value(doc, path, v)?;
        let Ok(file) = SceneFile::from_table(d) else { continue };
        let r = guarded(|| Ok(file.validate_with(&Limits::machine()).err())).ok().flatten();
        if let Some(E::Field { field, message }) = r {
            if path_segments(&field) == want {
                let rest = match message.find("is not allowed:") {
                    Some(at) => &message[at + "is not allowed:".len()..],
                    None => message.find("allowed").map_or(message.as_str(), |at| &message[at + "allowed".len()..]),
                };
                let rest = rest.trim_start_matches(':').trim();
                return (!rest.is_empty()).then(|| rest.to_string());
            }
        }
    }
    None
}

/// A scene error in Python's words: serde's type errors of the TOML
/// document ("invalid type: string \"80\", expected usize in
/// `bar.elements`") become "bar.elements: '80' (a str) is not allowed: an
/// integer >= 2" — for a number, the range is the scene validation's
/// ([`scene_range`], given the document `doc`), else the type in Python's
/// words; other messages keep theirs, a dict's "scene file:" being
/// "scene:".
pub(crate) fn py_scene_error(e: signorini_scene::SceneError, dict: bool) -> PyErr {
    py_scene_error_in(e, dict, None)
}

fn py_scene_error_in(e: signorini_scene::SceneError, dict: bool, doc: Option<&toml::Table>) -> PyErr {
    use signorini_scene::SceneError as E;
    let E::Toml(err) = &e else { return SceneError::new_err(e.to_string()) };
    let msg = err.to_string();
    let (first, path) = match msg.split_once("\nin `") {
        Some((f, rest)) => (f.trim(), rest.split('`').next().unwrap_or("").to_string()),
        None => (msg.trim(), String::new()),
    };
    let join = |key: &str| if path.is_empty() { key.to_string() } else { format!("{path}.{key}") };
    let at = if path.is_empty() { "scene".to_string() } else { path.clone() };
    let text = if let Some(rest) = first.strip_prefix("invalid type: ").or_else(|| first.strip_prefix("invalid value: ")) {
        match rest.split_once(", expected ") {
            Some((got, want)) => {
                let int = matches!(want.trim(), "usize" | "u64" | "u32" | "u16" | "u8" | "i64" | "i32" | "isize");
                let real = matches!(want.trim(), "f64" | "f32");
                let range = if int || real { doc.and_then(|d| scene_range(d, &path, int)) } else { None };
                format!("{at}: {} is not allowed: {}", py_words(got), range.unwrap_or_else(|| py_words(want)))
            }
            None => format!("{at}: {rest}"),
        }
    } else if let Some(rest) = first.strip_prefix("unknown field `") {
        let (key, allowed) = rest.split_once('`').unwrap_or((rest, ""));
        let allowed = allowed.trim_start_matches(", expected one of ").trim_start_matches(", expected ").replace('`', "");
        format!("{}: not a key of {} (allowed: {allowed})", join(key), if path.is_empty() { "the scene" } else { &path })
    } else if let Some(rest) = first.strip_prefix("missing field `") {
        format!("{}: missing: a required key", join(rest.trim_end_matches('`')))
    } else if dict {
        format!("scene: {first}{}", if path.is_empty() { String::new() } else { format!(" (in {path})") })
    } else {
        e.to_string()
    };
    SceneError::new_err(text)
}

/// The scene of `scene`: a dict (the TOML schema as Python values), a path
/// to a TOML file, or TOML text.
pub(crate) fn scene_of(scene: &Bound<'_, PyAny>) -> PyResult<(signorini_scene::SceneFile, signorini_scene::Scene)> {
    use signorini_scene::{Limits, SceneFile};
    let is_dict = scene.is_instance_of::<pyo3::types::PyDict>();
    let bad = |e: signorini_scene::SceneError| py_scene_error(e, is_dict);
    // A type error of a text names the range its validation states (the
    // document parsed as a plain table for the stand-ins).
    let parse = |text: &str| SceneFile::parse(text).map_err(|e| py_scene_error_in(e, is_dict, toml::from_str::<toml::Table>(text).ok().as_ref()));
    let file = if let Ok(text) = scene.extract::<String>() {
        let path = std::path::Path::new(&text);
        if !text.contains('\n') && !text.contains('=') && path.exists() {
            let body = std::fs::read_to_string(path).map_err(|e| SceneError::new_err(format!("scene: cannot read {text}: {e}")))?;
            let mut f = parse(&body)?;
            f.base = path.parent().map(std::path::Path::to_path_buf);
            f
        } else {
            parse(&text)?
        }
    } else if let Ok(p) = scene.extract::<std::path::PathBuf>() {
        let body = std::fs::read_to_string(&p).map_err(|e| {
            let m = format!("scene: cannot read {}: {e}", p.display());
            if e.kind() == std::io::ErrorKind::NotFound {
                pyo3::exceptions::PyFileNotFoundError::new_err(m)
            } else {
                pyo3::exceptions::PyOSError::new_err(m)
            }
        })?;
        let mut f = parse(&body)?;
        f.base = p.parent().map(std::path::Path::to_path_buf);
        f
    } else {
        if !is_dict {
            return Err(SceneError::new_err(format!("scene: {} is not allowed: a dict, a path (str or os.PathLike) or TOML text (str)", type_words(scene))));
        }
        match to_toml(scene, "")? {
            toml::Value::Table(t) => SceneFile::from_table(t.clone()).map_err(|e| py_scene_error_in(e, true, Some(&t)))?,
            _ => return Err(SceneError::new_err("scene: a dict, a path (str or os.PathLike) or TOML text (str)")),
        }
    };
    let s = file.validate_with(&Limits::machine()).map_err(bad)?;
    Ok((file, s))
}

/// The TOML text of a scene given as a dict (keys checked as `run` does).
#[pyfunction]
fn scene_text(scene: &Bound<'_, PyAny>) -> PyResult<String> {
    if !scene.is_instance_of::<pyo3::types::PyDict>() {
        return Err(SceneError::new_err(format!("scene: {} is not allowed: a dict, a path (str or os.PathLike) or TOML text (str)", type_words(scene))));
    }
    match to_toml(scene, "")? {
        toml::Value::Table(t) => toml::to_string(&t).map_err(|e| SceneError::new_err(format!("scene: {e}"))),
        _ => Err(SceneError::new_err("scene: a dict, a path or TOML text")),
    }
}

/// What a run of the scene would do (the text of `signorini check`):
/// validated, the integrator built, stability, memory, cost. Nothing runs
/// but an event-driven scene's probe of its events (at most 1 s).
#[pyfunction]
fn check_scene(py: Python<'_>, scene: &Bound<'_, PyAny>) -> PyResult<String> {
    let (file, s) = scene_of(scene)?;
    let here = std::env::current_dir().unwrap_or_else(|_| std::env::temp_dir());
    py.detach(|| guarded(|| signorini_scene::check_report(&s, &file, &here).map(|r| r.text).map_err(|e| SceneError::new_err(e.to_string()))))
}

/// `signorini check` as a dict: its text and the numbers it states, from
/// the same library calls — `steps`, `stability_limit` (the exact limit of
/// dt for a conditionally stable scheme, None for an unconditionally stable
/// one), `memory_bytes` and `output_bytes` (the estimates).
#[pyfunction]
fn check_scene_numbers<'py>(py: Python<'py>, scene: &Bound<'py, PyAny>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let (file, s) = scene_of(scene)?;
    let here = std::env::current_dir().unwrap_or_else(|_| std::env::temp_dir());
    // The command's own report: the text and the numbers it states.
    let r = py.detach(|| guarded(|| signorini_scene::check_report(&s, &file, &here).map_err(|e| SceneError::new_err(e.to_string()))))?;
    let (text, steps, limit, memory, output) = (r.text, r.steps, r.stability_limit, r.memory_bytes, r.output_bytes);
    let d = pyo3::types::PyDict::new(py);
    d.set_item("text", text)?;
    d.set_item("steps", steps)?;
    d.set_item("stability_limit", limit)?;
    d.set_item("memory_bytes", memory.round() as u64)?;
    d.set_item("output_bytes", output.round() as u64)?;
    Ok(d)
}

/// A deliberate panic, for the tests of the panic guard.
#[pyfunction]
fn _panic_for_tests() -> PyResult<()> {
    guarded(|| panic!("planted"))
}

#[pymodule]
fn _signorini(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("BlowUp", py.get_type::<BlowUp>())?;
    m.add("InternalError", py.get_type::<InternalError>())?;
    m.add_class::<Exact>()?;
    m.add_function(wrap_pyfunction!(exact_solution, m)?)?;
    m.add_function(wrap_pyfunction!(exact_backbone, m)?)?;
    m.add_class::<ExactBackbone>()?;
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)?;
    m.add_function(wrap_pyfunction!(run::run_scene, m)?)?;
    m.add_class::<run::RunArrays>()?;
    m.add_class::<fem::Matrices>()?;
    m.add_function(wrap_pyfunction!(studies::study, m)?)?;
    m.add_function(wrap_pyfunction!(studies::study_check, m)?)?;
    m.add_function(wrap_pyfunction!(studies::study_fields, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::run_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(orbits::run_continuation, m)?)?;
    m.add_function(wrap_pyfunction!(orbits::run_modes, m)?)?;
    m.add_function(wrap_pyfunction!(orbits::run_basins, m)?)?;
    m.add_function(wrap_pyfunction!(scene_text, m)?)?;
    m.add_function(wrap_pyfunction!(check_scene, m)?)?;
    m.add_function(wrap_pyfunction!(check_scene_numbers, m)?)?;
    m.add_function(wrap_pyfunction!(fem::bar_matrices, m)?)?;
    m.add_function(wrap_pyfunction!(fem::beam_matrices, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
