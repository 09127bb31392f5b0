//! One run of a sweep: [`simulate`] steps a scene over its [`Plan`] and
//! returns its rows ([`RunRows`]).

use signorini_run::vibro::{Piece, Summary, VibroConfig};
use signorini_run::{Cancel, Observer, RunConfig, RunError, Sample};
use signorini_scene::{Reads, Scene};
use signorini_schemes::Bounds;

/// A validated scene at a value and its clock.
pub(crate) type ScenePlan = (Scene, Plan);

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

/// Keeps the last two displacement vectors (for a followed sweep's final
/// velocity, their backward difference).
pub(crate) struct LastTwo {
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
pub(crate) fn failed(e: &dyn std::fmt::Display) -> RunRows {
    let mut buf = Vec::new();
    let _ = Summary { impacts: None, rms_force: None, max_abs_tip: None, poincare: None }.write_row(&mut buf);
    RunRows { summary: String::from_utf8_lossy(&buf).into_owned(), status: text_cell(&e.to_string()), ..RunRows::default() }
}

/// A cell of free text for a CSV row: quoted, quotes doubled, one line.
pub(crate) fn text_cell(s: &str) -> String {
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
pub(crate) fn observers(plan: &Plan, tip: usize, contacts: Vec<(usize, Bounds)>) -> Result<signorini_run::vibro::Vibro, RunError> {
    let mut c = VibroConfig::new(plan.dt, Some(plan.omega), plan.record_from, tip, contacts)?;
    c.t_end = Some(plan.t_end);
    c.phase = plan.phase;
    c.period_tol = plan.period_tol;
    c.build(Piece::Memory, Piece::Memory, true)
}

/// A sweep run's rows from its observers (the record window's impacts).
pub(crate) fn rows_of(vib: &signorini_run::vibro::Vibro, plan: &Plan, steps: usize, status: String, state: Option<(Vec<f64>, Vec<f64>)>) -> RunRows {
    let poincare = vib.poincare.as_ref().map_or_else(Vec::new, |p| p.points().iter().map(|q| [q.t, q.displacement, q.velocity, plan.phase]).collect());
    let impacts = vib.impacts.as_ref().map_or_else(Vec::new, |o| o.impacts().iter().filter(|i| i.t >= plan.record_from).map(|i| (i.stop, [i.t, i.phase, i.velocity, i.impulse, i.duration])).collect());
    let mut buf = Vec::new();
    let _ = vib.summary().write_row(&mut buf);
    RunRows { poincare, impacts, summary: String::from_utf8_lossy(&buf).into_owned(), steps, status, state }
}
