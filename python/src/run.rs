//! `signorini.run`: a scene stepped on a worker thread (the GIL released),
//! recorded into preallocated vectors and handed to numpy without copies
//! per element.

use crate::{guarded, scene_of, BlowUp, InternalError, SceneError};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use signorini_run::{Observer, RunError, Sample};

/// Everything a run records, in flat vectors reserved for every level.
struct Recorder {
    tip: usize,
    dofs: Vec<usize>,
    energy: bool,
    /// Record the whole unknown vector every `every` levels (0: never).
    every: usize,
    t: Vec<f64>,
    tip_u: Vec<f64>,
    lam_t: Vec<f64>,
    lam: Vec<f64>,
    energy_t: Vec<f64>,
    energy_v: Vec<f64>,
    contact_u: Vec<f64>,
    forces: Vec<f64>,
    active: Vec<bool>,
    fields_t: Vec<f64>,
    fields: Vec<f64>,
}

impl Recorder {
    fn new(tip: usize, dofs: Vec<usize>, energy: bool, every: usize, levels: usize, unknowns: usize) -> Self {
        let c = dofs.len();
        let f = levels.checked_div(every).map_or(0, |q| q + 1);
        Self {
            tip,
            energy,
            every,
            t: Vec::with_capacity(levels),
            tip_u: Vec::with_capacity(levels),
            lam_t: Vec::with_capacity(levels),
            lam: Vec::with_capacity(levels),
            energy_t: Vec::with_capacity(if energy { levels } else { 0 }),
            energy_v: Vec::with_capacity(if energy { levels } else { 0 }),
            contact_u: Vec::with_capacity(levels * c),
            forces: Vec::with_capacity(levels * c),
            active: Vec::with_capacity(levels),
            fields_t: Vec::with_capacity(f),
            fields: Vec::with_capacity(f * unknowns),
            dofs,
        }
    }
}

impl Observer for Recorder {
    fn wants_energy(&self) -> bool {
        self.energy
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        self.t.push(s.t);
        self.tip_u.push(s.u[self.tip]);
        if let Some((t, l)) = s.lambda {
            self.lam_t.push(t);
            self.lam.push(l);
        }
        // The runner computes energies for its monitor too: record them only when asked.
        if let (true, Some((t, e))) = (self.energy, s.energy) {
            self.energy_t.push(t);
            self.energy_v.push(e);
        }
        self.contact_u.extend(self.dofs.iter().map(|&d| s.u[d]));
        if s.forces.len() == self.dofs.len() {
            self.forces.extend_from_slice(s.forces);
        } else {
            self.forces.extend(std::iter::repeat_n(0.0, self.dofs.len()));
        }
        self.active.push(s.active);
        if self.every > 0 && s.n % self.every == 0 {
            self.fields_t.push(s.t);
            self.fields.extend_from_slice(s.u);
        }
        Ok(())
    }
}

/// What a run recorded (see `signorini.run`).
#[pyclass(module = "signorini._signorini", frozen, get_all)]
pub struct RunArrays {
    t: Py<PyArray1<f64>>,
    tip: Py<PyArray1<f64>>,
    lam_t: Py<PyArray1<f64>>,
    lam: Py<PyArray1<f64>>,
    energy_t: Py<PyArray1<f64>>,
    energy: Py<PyArray1<f64>>,
    contact_dofs: Vec<usize>,
    contact_lo: Py<PyArray1<f64>>,
    contact_hi: Py<PyArray1<f64>>,
    contact_u: Py<PyArray2<f64>>,
    forces: Py<PyArray2<f64>>,
    active: Py<PyArray1<bool>>,
    fields_t: Py<PyArray1<f64>>,
    fields: Py<PyArray2<f64>>,
    norms: Option<Py<PyDict>>,
    steps: usize,
    contact_steps: usize,
    dt: f64,
    status: String,
    /// The largest E/budget (NaN when the run stopped early).
    energy_max_ratio: f64,
    /// The first level past the factor: `step, t, ratio, energy, budget`.
    energy_exceeded: Option<Py<PyDict>>,
    /// The warning's text (Python emits it as `EnergyGrowthWarning`).
    energy_warning: Option<String>,
    /// An event-driven run's events (`events.csv`'s columns as arrays;
    /// `kind` a list of str); `None` for a time-stepping scheme.
    events: Option<Py<PyDict>>,
}

fn matrix(py: Python<'_>, v: Vec<f64>, cols: usize) -> PyResult<Py<PyArray2<f64>>> {
    let rows = v.len().checked_div(cols).unwrap_or(0);
    let a = Array2::from_shape_vec((rows, cols), v).map_err(|e| InternalError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py).unbind())
}

/// A run's error as Python sees it: no file was written; a run that stopped
/// on the way keeps its levels as the exception's `partial`. Very large and
/// small numbers get an exponent.
fn python_status(e: &RunError) -> String {
    let m = signorini_run::text::tidy_numbers(&e.to_string());
    match e {
        RunError::BlowUp { .. } | RunError::EnergyGrowth { .. } | RunError::Interrupted { .. } => format!("{m}; the levels so far are kept (the exception's partial)"),
        _ => m,
    }
}

/// Runs a scene (see `signorini.run`). The stepping releases the GIL and
/// checks for Ctrl-C every 50 ms; a KeyboardInterrupt or a blow-up carries
/// the partial result as its `partial` attribute.
#[pyfunction]
#[pyo3(signature = (scene, energy=None, fields_every=0, energy_warn=None))]
pub fn run_scene(py: Python<'_>, scene: &Bound<'_, PyAny>, energy: Option<bool>, fields_every: i64, energy_warn: Option<f64>) -> PyResult<RunArrays> {
    use signorini_run::{Cancel, RunConfig};
    use signorini_scene::Reads;
    if fields_every < 0 {
        return Err(SceneError::new_err(format!("fields_every: {fields_every} is not allowed: an int >= 0 (0: no fields, k: every k steps)")));
    }
    let bad_factor = |factor: f64| SceneError::new_err(format!("energy_warn: {factor} is out of range: finite and > 1"));
    // The arguments are checked before the scene (Python asks this function
    // for their ranges with any scene).
    if let Some(f) = energy_warn.filter(|f| !signorini_run::energy::check_factor(*f)) {
        return Err(bad_factor(f));
    }
    let (file, s) = scene_of(scene)?;
    // The argument, else the scene's `[output] energy_warn`, else 2.
    let factor = energy_warn.unwrap_or_else(|| file.energy_warn());
    if !signorini_run::energy::check_factor(factor) {
        return Err(bad_factor(factor));
    }
    // The scene's facts: its clock, whether its series has energies, its norms.
    let facts = s.facts();
    let (dt, t_end, energy_default) = (facts.dt, facts.t_end, facts.columns.energy);
    let exact = s.exact().map_err(|e| SceneError::new_err(e.to_string()))?;
    // One instantiation for every front end: a reduced model (`reduce = {…}`)
    // steps in reduced coordinates, and the recorder and the norms see the
    // scene's unknowns, reconstructed, as `signorini run` does.
    let mut built = guarded(|| s.instantiate(None).map_err(|e| SceneError::new_err(e.to_string())))?;
    let mut cfg = RunConfig::new(dt, t_end).and_then(|c| c.with_energy_warn(factor)).map_err(|e| SceneError::new_err(e.to_string()))?;
    // One token per run, cancelled from this thread when Python has a pending signal.
    let cancel = Cancel::new();
    cfg.interrupt = Some(cancel.clone());
    let levels = cfg.steps() + 1;
    let unknowns = built.unknowns();
    let contacts = built.contacts();
    let dofs: Vec<usize> = contacts.iter().map(|c| c.0).collect();
    let (lo, hi): (Vec<f64>, Vec<f64>) = contacts.iter().map(|c| (c.1.lo, c.1.hi)).unzip();
    let mut rec = Recorder::new(built.tip, dofs.clone(), energy.unwrap_or(energy_default), fields_every as usize, levels, unknowns);
    let mut norms = facts.norms.zip(exact.as_deref()).map(|(n, e)| n.observer(e, dt));
    let (res, signal) = crate::interruptible(py, &cancel, || {
        // The recorder reads the fields when asked, else the contacts and the tip.
        let mut obs: Vec<(Reads, &mut dyn Observer)> = vec![(if fields_every > 0 { Reads::Full } else { Reads::Contacts }, &mut rec)];
        if let Some(n) = norms.as_mut() {
            obs.push((Reads::Full, n));
        }
        let res = built.run(&cfg, obs);
        Ok(res)
    });
    let res = res?;
    // Fields: the absolute state (the beam's lifting added back).
    if built.lift.is_some() && unknowns > 0 {
        let zero = vec![0.0; unknowns];
        for (row, &t) in rec.fields.chunks_mut(unknowns).zip(&rec.fields_t) {
            let (abs, _) = built.absolute(row, &zero, t);
            row.copy_from_slice(&abs);
        }
    }
    let norms = match (&res, norms) {
        (Ok(_), Some(n)) => {
            let r = n.report();
            let d = PyDict::new(py);
            for k in signorini_run::study::NORMS {
                d.set_item(k, signorini_run::study::norm_value(&r, k))?;
            }
            d.set_item("lambda_tv_ratio", r.lambda_tv_ratio)?;
            Some(d.unbind())
        }
        _ => None,
    };
    let status = match &res {
        Ok(_) => "ok".to_string(),
        Err(e) => python_status(e),
    };
    let growth = res.as_ref().ok().and_then(|s| s.energy);
    let energy_exceeded = match growth.and_then(|g| g.exceeded) {
        Some(x) => {
            let d = PyDict::new(py);
            d.set_item("step", x.step)?;
            d.set_item("t", x.time)?;
            d.set_item("ratio", x.ratio)?;
            d.set_item("energy", x.energy)?;
            d.set_item("budget", x.budget)?;
            Some(d.unbind())
        }
        None => None,
    };
    let events = match built.stepper.events() {
        Some(ev) => {
            let d = PyDict::new(py);
            d.set_item("t", ev.iter().map(|e| e.t).collect::<Vec<f64>>().into_pyarray(py))?;
            d.set_item("kind", ev.iter().map(|e| e.kind.name()).collect::<Vec<&str>>())?;
            d.set_item("contact", ev.iter().map(|e| e.contact as i64).collect::<Vec<i64>>().into_pyarray(py))?;
            d.set_item("velocity_before", ev.iter().map(|e| e.velocity_before).collect::<Vec<f64>>().into_pyarray(py))?;
            d.set_item("velocity_after", ev.iter().map(|e| e.velocity_after).collect::<Vec<f64>>().into_pyarray(py))?;
            d.set_item("impulse", ev.iter().map(|e| e.impulse).collect::<Vec<f64>>().into_pyarray(py))?;
            Some(d.unbind())
        }
        None => None,
    };
    let c = dofs.len();
    let out = RunArrays {
        events,
        energy_max_ratio: growth.map_or(f64::NAN, |g| g.max_ratio),
        energy_exceeded,
        energy_warning: growth.as_ref().and_then(signorini_scene::energy_warning),
        steps: res.as_ref().map_or(rec.t.len().saturating_sub(1), |s| s.steps),
        contact_steps: res.as_ref().map_or_else(|_| rec.active.iter().filter(|a| **a).count(), |s| s.contact_steps),
        t: rec.t.into_pyarray(py).unbind(),
        tip: rec.tip_u.into_pyarray(py).unbind(),
        lam_t: rec.lam_t.into_pyarray(py).unbind(),
        lam: rec.lam.into_pyarray(py).unbind(),
        energy_t: rec.energy_t.into_pyarray(py).unbind(),
        energy: rec.energy_v.into_pyarray(py).unbind(),
        contact_dofs: dofs,
        contact_lo: lo.into_pyarray(py).unbind(),
        contact_hi: hi.into_pyarray(py).unbind(),
        contact_u: matrix(py, rec.contact_u, c)?,
        forces: matrix(py, rec.forces, c)?,
        active: rec.active.into_pyarray(py).unbind(),
        fields_t: rec.fields_t.into_pyarray(py).unbind(),
        fields: matrix(py, rec.fields, unknowns)?,
        norms,
        dt,
        status,
    };
    let err = match (signal, res) {
        (Some(e), _) => e,
        (None, Ok(_)) => return Ok(out),
        (None, Err(e @ (RunError::BlowUp { .. } | RunError::EnergyGrowth { .. }))) => BlowUp::new_err(python_status(&e)),
        (None, Err(e)) => SceneError::new_err(python_status(&e)),
    };
    err.value(py).setattr("partial", Py::new(py, out)?)?;
    Err(err)
}
