//! The time loop and its observers.

use crate::Cancel;
use signorini_fem::FemError;
use signorini_schemes::{SchemeError, Stepper};
use std::time::Instant;

/// Errors of a run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// A parameter outside its allowed range.
    #[error("invalid {field} = {value}: allowed {allowed}")]
    Invalid {
        /// The parameter's name.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A key or option that this path does not take (it has no value to show).
    #[error("{field} is not allowed here: allowed {allowed}")]
    NotAllowed {
        /// The key or option's name.
        field: &'static str,
        /// What is allowed instead, in words.
        allowed: &'static str,
    },
    /// A stop (or an obstacle at a node) that cannot be used.
    #[error("invalid stop.{index}.{field} = {value}: allowed {allowed}")]
    Stop {
        /// The stop's index in the list.
        index: usize,
        /// Its field.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed, in words.
        allowed: String,
    },
    /// An unknown benchmark name.
    #[error("unknown benchmark {0:?}: allowed bar-dirichlet, bar-neumann-gravity, bar-neumann-gravity-0.11, bar-mirrored")]
    UnknownBenchmark(String),
    /// The exact solution cannot be built for these parameters or horizon.
    #[error("exact solution: {0}")]
    Exact(#[source] signorini_exact::NeumannError),
    /// The mesh or matrices could not be built.
    #[error(transparent)]
    Fem(#[from] FemError),
    /// The scheme could not be built or failed.
    #[error(transparent)]
    Scheme(SchemeError),
    /// The state became non-finite: the run stopped there.
    #[error("run blew up: non-finite state at step {step} (t = {time})")]
    BlowUp {
        /// The step.
        step: usize,
        /// Its time.
        time: f64,
    },
    /// The energy grew beyond the configured bound: the run stopped there.
    #[error("run blew up: energy {energy} exceeds {limit} x the energy scale {scale} (max of |E(0)|, the loads' energy over the horizon and ½ m (max|U⁰|/T)²) at step {step} (t = {time})")]
    EnergyGrowth {
        /// The step.
        step: usize,
        /// Its time.
        time: f64,
        /// The energy reached.
        energy: f64,
        /// The configured growth factor.
        limit: f64,
        /// The energy scale it multiplies.
        scale: f64,
    },
    /// The horizon is not a whole number of steps.
    #[error("t_end = {t_end} is not a whole number of steps of dt = {dt} (T/dt = {}): the run would end at {} instead; choose T = N·dt (e.g. t_end = {} or {}), or dt = T/N (e.g. dt = {})", t_end / dt, sig12((t_end / dt).ceil() * dt), sig12((t_end / dt).floor().max(1.0) * dt), sig12((t_end / dt).ceil() * dt), sig12(t_end / (t_end / dt).ceil()))]
    Horizon {
        /// The horizon asked for.
        t_end: f64,
        /// The time step.
        dt: f64,
    },
    /// The run was interrupted (SIGINT/SIGTERM): what was written is kept.
    #[error("interrupted at step {step} (t = {time})")]
    Interrupted {
        /// The last step completed.
        step: usize,
        /// Its time.
        time: f64,
    },
    /// An observer failed to write its output.
    #[error("output: {0}")]
    Output(#[source] std::io::Error),
    /// A reduced model refused its parameters (`modes`, `cutoff_hz`, …).
    #[error("reduce: {0}")]
    Reduce(#[from] signorini_reduce::ReduceError),
}

/// `x` rounded to 12 significant digits (for messages: `2.94`, not
/// `2.9400000000000004`).
fn sig12(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

impl From<SchemeError> for RunError {
    fn from(e: SchemeError) -> Self {
        match e {
            SchemeError::NonFinite { step, time } => RunError::BlowUp { step, time },
            SchemeError::Interrupted { step, time } => RunError::Interrupted { step, time },
            e => RunError::Scheme(e),
        }
    }
}

/// Time step, horizon and safety limits of a run ([`RunConfig::new`], then
/// the `with_*` setters or the fields).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct RunConfig {
    /// Time step `dt` (> 0, finite).
    pub dt: f64,
    /// Horizon `T` (> 0, finite, a whole number of steps: `T = N dt`).
    pub t_end: f64,
    /// Stop when `|E_h| > limit · S`, with the scale `S = max(|E_h(0)|,
    /// `[`load_energy_scale`](signorini_schemes::Dynamics::load_energy_scale)`(T),
    /// ½ m (max|U⁰|/T)²)` (never zero unless the data and loads are)
    /// (checked only when an observer asks for the energy). `None`: no check.
    pub energy_growth_limit: Option<f64>,
    /// A cancel token (cancelled by a signal handler, another thread, …)
    /// that stops the run cleanly at the next step with
    /// [`RunError::Interrupted`] (inside a step too, for a scheme whose
    /// step is unbounded work: [`Stepper::set_interrupt`]; the run then
    /// ends at the last whole level).
    pub interrupt: Option<Cancel>,
    /// Watch the energy against its budget (`E_ref` + load work −
    /// dissipation, [`crate::energy`]) and record the largest ratio and the
    /// first level past this factor in [`RunSummary::energy`] (`Some`: the
    /// energy is computed at every level). `None` (the default of
    /// [`new`](Self::new)): no monitor. Set it with
    /// [`with_energy_warn`](Self::with_energy_warn).
    pub energy_warn: Option<f64>,
}

/// Relative tolerance (in steps) within which `T/dt` counts as a whole number.
fn whole_steps(t_end: f64, dt: f64) -> Option<usize> {
    let r = t_end / dt;
    let n = r.round();
    (n >= 1.0 && (r - n).abs() <= 1e-9_f64.max(16.0 * f64::EPSILON * r)).then_some(n as usize)
}

impl RunConfig {
    /// A validated configuration (energy growth bound 1e6). `T` must be a
    /// whole number of steps (to a relative 1e-9 or 16 ulps): a run never
    /// goes past `T`, where exact solutions may not be defined, and never
    /// silently stops short of it.
    pub fn new(dt: f64, t_end: f64) -> Result<Self, RunError> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(RunError::Invalid { field: "dt", value: dt, allowed: "finite and > 0" });
        }
        if !(t_end > 0.0 && t_end.is_finite()) {
            return Err(RunError::Invalid { field: "T", value: t_end, allowed: "finite and > 0" });
        }
        if t_end / dt > 1e10 {
            return Err(RunError::Invalid { field: "T/dt", value: t_end / dt, allowed: "at most 1e10 steps" });
        }
        if whole_steps(t_end, dt).is_none() {
            return Err(RunError::Horizon { t_end, dt });
        }
        Ok(Self { dt, t_end, energy_growth_limit: Some(1e6), interrupt: None, energy_warn: None })
    }

    /// With the energy-growth monitor at `factor` (finite and > 1).
    pub fn with_energy_warn(mut self, factor: f64) -> Result<Self, RunError> {
        if !crate::energy::check_factor(factor) {
            return Err(RunError::Invalid { field: "energy_warn", value: factor, allowed: "finite and > 1" });
        }
        self.energy_warn = Some(factor);
        Ok(self)
    }

    /// With a cancel token.
    pub fn with_interrupt(mut self, cancel: Cancel) -> Self {
        self.interrupt = Some(cancel);
        self
    }

    /// Number of steps `N = T/dt` (a whole number, checked by [`new`](Self::new)).
    pub fn steps(&self) -> usize {
        whole_steps(self.t_end, self.dt).unwrap_or_else(|| (self.t_end / self.dt).ceil().max(1.0) as usize)
    }
}

/// What observers see at each time level (the runners build it; a test
/// feeding an observer by hand starts from [`Sample::new`]).
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct Sample<'a> {
    /// Time level `n`.
    pub n: usize,
    /// `t_n`.
    pub t: f64,
    /// Displacement at the unknowns at `t_n`.
    pub u: &'a [f64],
    /// Contact force produced by the step that reached `t_n`, and its time.
    pub lambda: Option<(f64, f64)>,
    /// The scheme's discrete energy and its time (when an observer wants it).
    pub energy: Option<(f64, f64)>,
    /// Whether a constraint was active in that step (any contact).
    pub active: bool,
    /// Every contact's force from that step, in contact order, at the time
    /// of `lambda` (zeros at the start levels).
    pub forces: &'a [f64],
    /// Which bound holds each contact after that step.
    pub status: &'a [signorini_contact::Active],
    /// Work of the time-dependent load and of the contact force so far, when
    /// the scheme tracks it.
    pub work: Option<(f64, f64)>,
}

impl<'a> Sample<'a> {
    /// Level `n` at `t` with the displacement `u`, as a start level is:
    /// no contact force, energy or work, no contact active, no contacts
    /// listed (set the fields, or [`with_contacts`](Self::with_contacts)).
    pub fn new(n: usize, t: f64, u: &'a [f64]) -> Self {
        Self { n, t, u, lambda: None, energy: None, active: false, forces: &[], status: &[], work: None }
    }

    /// With the step's contact force `lambda` (contact 0's, and its time),
    /// whether a constraint was active, every contact's force and status.
    pub fn with_contacts(mut self, lambda: Option<(f64, f64)>, active: bool, forces: &'a [f64], status: &'a [signorini_contact::Active]) -> Self {
        (self.lambda, self.active, self.forces, self.status) = (lambda, active, forces, status);
        self
    }
}

/// Something that watches a run: norms, CSV sinks, progress.
pub trait Observer {
    /// Whether this observer needs the discrete energy (it costs a solve).
    fn wants_energy(&self) -> bool {
        false
    }
    /// Called at `t_0` and after every step.
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError>;
    /// Called once at the end, also when the run stops early.
    fn finish(&mut self) -> Result<(), RunError> {
        Ok(())
    }
}

/// Summary of a finished run.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct RunSummary {
    /// Steps taken.
    pub steps: usize,
    /// Final time.
    pub t_end: f64,
    /// Steps in which the constraint was active.
    pub contact_steps: usize,
    /// Wall-clock time of the loop, seconds.
    pub wall_s: f64,
    /// The energy monitor's findings (with [`RunConfig::energy_warn`]).
    pub energy: Option<crate::energy::EnergyGrowth>,
}

/// Runs `stepper` to `cfg.t_end`, feeding every observer at `t_0` (with the
/// initial displacement `u0`) and after each step. On a blow-up or an
/// observer error, every observer is finished (flushed) before the error is
/// returned.
pub fn run(stepper: &mut dyn Stepper, u0: &[f64], cfg: &RunConfig, observers: &mut [&mut dyn Observer]) -> Result<RunSummary, RunError> {
    let start = Instant::now();
    // An exact flow's last level is read at T itself.
    stepper.set_end(cfg.steps(), cfg.t_end);
    // A step of unbounded work (the event-driven scheme) polls the token too.
    if let Some(cancel) = cfg.interrupt.clone() {
        stepper.set_interrupt(Some(std::sync::Arc::new(move || cancel.is_cancelled())));
    }
    // Energy at every level: a scheme may fuse it with its step.
    let want_energy = observers.iter().any(|o| o.wants_energy()) || cfg.energy_warn.is_some();
    stepper.fuse_energy(want_energy);
    let result = run_inner(stepper, u0, cfg, observers);
    stepper.fuse_energy(false);
    if cfg.interrupt.is_some() {
        stepper.set_interrupt(None);
    }
    let mut fin = Ok(());
    for o in observers.iter_mut() {
        let r = o.finish();
        if fin.is_ok() {
            fin = r;
        }
    }
    let (steps, contact_steps, energy) = result?;
    fin?;
    Ok(RunSummary { steps, t_end: stepper.time(), contact_steps, wall_s: start.elapsed().as_secs_f64(), energy })
}

/// How often (in steps) the runner checks the whole state for non-finite
/// values; the steppers check the contact dof every step.
pub(crate) const FINITE_CHECK_EVERY: usize = 64;

fn run_inner(stepper: &mut dyn Stepper, u0: &[f64], cfg: &RunConfig, observers: &mut [&mut dyn Observer]) -> Result<(usize, usize, Option<crate::energy::EnergyGrowth>), RunError> {
    if (cfg.dt - stepper.dt()).abs() > 1e-15 * cfg.dt {
        return Err(RunError::Invalid { field: "dt", value: cfg.dt, allowed: "the stepper's own dt" });
    }
    let want_energy = observers.iter().any(|o| o.wants_energy()) || cfg.energy_warn.is_some();
    let total = cfg.steps();
    let load_scale = stepper.dynamics().load_energy_scale(cfg.t_end).max(data_energy_scale(stepper.dynamics().mass.total(), u0, cfg.t_end));
    let mut emit = |s: Sample<'_>| -> Result<(), RunError> {
        for o in observers.iter_mut() {
            o.observe(&s)?;
        }
        Ok(())
    };
    let level0_energy = if want_energy && stepper.level() == 0 { stepper.energy() } else { None };
    let k = stepper.dynamics().k();
    let (zero_forces, free) = (vec![0.0; k], vec![signorini_contact::Active::None; k]);
    emit(Sample { n: 0, t: 0.0, u: u0, lambda: None, energy: level0_energy, active: false, work: None, forces: &zero_forces, status: &free })?;
    let mut reference_energy = level0_energy.map(|e| e.1);
    let mut watch = cfg.energy_warn.map(|f| Watch::new(f, stepper, load_scale));
    if let (Some(w), Some(e)) = (watch.as_mut(), level0_energy) {
        w.observe(stepper, 0, e);
    }
    // A two-step scheme arrives at level 1 already (its start step).
    if stepper.level() == 1 {
        let energy = if want_energy { stepper.energy() } else { None };
        reference_energy = reference_energy.or(energy.map(|e| e.1));
        if let (Some(w), Some(e)) = (watch.as_mut(), energy) {
            w.observe(stepper, 1, e);
        }
        check_finite(stepper.displacement(), 1, stepper.time())?;
        emit(Sample { n: 1, t: stepper.time(), u: stepper.displacement(), lambda: None, energy, active: false, work: stepper.work(), forces: &zero_forces, status: &free })?;
    }
    let mut contact_steps = 0;
    while stepper.level() < total {
        if let Some(cancel) = &cfg.interrupt {
            if cancel.is_cancelled() {
                return Err(RunError::Interrupted { step: stepper.level(), time: stepper.time() });
            }
        }
        let rep = stepper.step()?;
        if rep.n % FINITE_CHECK_EVERY == 0 || rep.n == total {
            check_finite(stepper.displacement(), rep.n, rep.t)?;
        }
        let energy = if want_energy { stepper.energy() } else { None };
        if let (Some(limit), Some((_, e))) = (cfg.energy_growth_limit, energy) {
            if !e.is_finite() {
                return Err(RunError::BlowUp { step: rep.n, time: rep.t });
            }
            let scale = reference_energy.get_or_insert(e).abs().max(load_scale);
            if e.abs() > limit * scale {
                return Err(RunError::EnergyGrowth { step: rep.n, time: rep.t, energy: e, limit, scale });
            }
        }
        if let (Some(w), Some(e)) = (watch.as_mut(), energy) {
            w.observe(stepper, rep.n, e);
        }
        let active = if k == 1 { rep.active != signorini_contact::Active::None } else { stepper.contact_status().iter().any(|a| *a != signorini_contact::Active::None) };
        contact_steps += usize::from(active);
        emit(Sample { n: rep.n, t: rep.t, u: stepper.displacement(), lambda: rep.lambda, energy, active, work: stepper.work(), forces: stepper.contact_forces(), status: stepper.contact_status() })?;
    }
    Ok((stepper.level(), contact_steps, watch.and_then(|w| w.monitor.result())))
}

/// The energy monitor with its budget ([`crate::energy`]): the scheme's
/// own load work and dissipation (closed), or the runner's Σ|load work|
/// (open) for a scheme that does not track them.
struct Watch {
    monitor: crate::energy::EnergyMonitor,
    load_scale: f64,
    reference: Option<f64>,
    /// Open budget: Σ|ΔW| so far, the previous displacement and
    /// time-dependent load (empty without forcing).
    open_work: f64,
    u_prev: Vec<f64>,
    f_prev: Vec<f64>,
    f_new: Vec<f64>,
}

impl Watch {
    fn new(factor: f64, stepper: &dyn Stepper, load_scale: f64) -> Self {
        let closed = stepper.work().is_some();
        let dy = stepper.dynamics();
        let mut w = Self { monitor: crate::energy::EnergyMonitor::new(factor, closed), load_scale, reference: None, open_work: 0.0, u_prev: Vec::new(), f_prev: Vec::new(), f_new: Vec::new() };
        if !closed && !dy.forcing.is_empty() {
            w.u_prev = stepper.displacement().to_vec();
            w.f_prev = vec![0.0; dy.n()];
            w.f_new = vec![0.0; dy.n()];
            dy.forcing_at(stepper.time(), &mut w.f_prev);
        }
        w
    }

    fn observe(&mut self, stepper: &dyn Stepper, n: usize, (t, e): (f64, f64)) {
        let reference = match self.reference {
            Some(r) => r,
            None => {
                // The floor of the budget: 1e-12 × the guard's energy scale.
                self.monitor.set_floor(1e-12 * e.abs().max(self.load_scale));
                *self.reference.insert(e)
            }
        };
        let budget = if self.monitor.closed() {
            let wf = stepper.work().map_or(0.0, |w| w.0);
            reference + wf - stepper.dissipation().unwrap_or(0.0)
        } else {
            if !self.u_prev.is_empty() && n > 0 {
                stepper.dynamics().forcing_at(stepper.time(), &mut self.f_new);
                let u = stepper.displacement();
                let dw: f64 = (0..u.len()).map(|i| 0.5 * (self.f_prev[i] + self.f_new[i]) * (u[i] - self.u_prev[i])).sum();
                self.open_work += dw.abs();
                self.u_prev.copy_from_slice(u);
                std::mem::swap(&mut self.f_prev, &mut self.f_new);
            }
            reference + self.open_work
        };
        self.monitor.observe(n, t, e, budget);
    }
}

/// `½ m (max|U⁰| / T)²`: the kinetic energy of moving the total mass `m`
/// by the data's largest displacement over the horizon. It keeps the
/// energy guard's scale positive when `E(0) = 0` without loads (a displaced
/// free bar at rest: a rigid translation has no energy) — rounding then
/// cannot pass for growth.
fn data_energy_scale(mass: f64, u0: &[f64], t_end: f64) -> f64 {
    let umax = u0.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    if !(mass > 0.0) || !umax.is_finite() {
        return 0.0;
    }
    0.5 * mass * (umax / t_end).powi(2)
}

pub(crate) fn check_finite(u: &[f64], step: usize, time: f64) -> Result<(), RunError> {
    if u.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(RunError::BlowUp { step, time })
    }
}
