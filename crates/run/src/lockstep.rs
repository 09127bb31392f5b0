//! The time loop of a lockstep batch: `L` runs of one scheme that share
//! one step matrix (a [`Lockstep`] engine: [`PaoliSchatzmanLockstep`],
//! [`MoreauJeanLockstep`]), each lane feeding its own observers exactly the
//! [`Sample`]s that [`run`] would feed them for that lane's single run.
//!
//! The contract of [`run`], lane by lane: level 0 (the lane's `u0`), level 1
//! when the engine arrives there (a two-step scheme's start step, the whole
//! state checked for finite values), then every
//! step up to the lane's own horizon ([`RunConfig::t_end`]), the whole state
//! checked every 64 steps and at the horizon; a lane stops on its own at a
//! blow-up (the step its single run stops at, with the same
//! [`RunError::BlowUp`]), an observer error, or when its
//! [`RunConfig::interrupt`] is cancelled (checked before each step, as
//! [`run`] does), while the other lanes go on; its observers are finished
//! when it stops. The engine computes neither the energy nor the works: a
//! lane's observers must not want the energy ([`Observer::wants_energy`];
//! refused, as is [`RunConfig::energy_warn`]), and [`Sample::work`] is
//! `None` (where [`run`] gives the single stepper's works).
//!
//! [`run`]: crate::run

use crate::reduced::Need;
use crate::runner::{check_finite, FINITE_CHECK_EVERY};
use crate::{Cancel, Observer, RunConfig, RunError, RunSummary, Sample};
use signorini_contact::Active;
use signorini_schemes::Lockstep;
#[cfg(doc)]
use signorini_schemes::{MoreauJeanLockstep, PaoliSchatzmanLockstep};
use std::time::Instant;

/// One lane of [`run_lockstep`]: what [`run`](crate::run) takes for one run
/// besides the stepper ([`LockstepRun::new`]).
#[non_exhaustive]
pub struct LockstepRun<'a> {
    /// The lane's initial displacement `U^0` (level 0's sample).
    pub u0: &'a [f64],
    /// Its time step (the engine's) and horizon, interrupt and limits.
    pub cfg: &'a RunConfig,
    /// Its observers.
    pub observers: Vec<&'a mut dyn Observer>,
}

impl<'a> LockstepRun<'a> {
    /// A lane starting from `u0` with `cfg`, feeding `observers`.
    pub fn new(u0: &'a [f64], cfg: &'a RunConfig, observers: Vec<&'a mut dyn Observer>) -> Self {
        Self { u0, cfg, observers }
    }
}

/// How one lane of [`run_lockstep`] ended.
#[derive(Debug)]
#[non_exhaustive]
pub struct LaneEnd {
    /// What [`run`](crate::run) returns for the lane's single run
    /// ([`RunSummary::wall_s`] is the whole batch's loop).
    pub result: Result<RunSummary, RunError>,
    /// The level the lane reached (what the single run's
    /// [`Stepper::level`](signorini_schemes::Stepper::level) gives after
    /// [`run`](crate::run) returns, also when it stopped early).
    pub level: usize,
}

/// A lane being stepped.
struct Lane<'r, 'a> {
    run: &'r mut LockstepRun<'a>,
    /// The displacement its observers see.
    u: Vec<f64>,
    /// Its horizon in steps.
    total: usize,
    contact_steps: usize,
    end: Option<Result<(), RunError>>,
    level: usize,
    /// Its interrupt (the config's, held here: read before every step).
    interrupt: Option<Cancel>,
    /// Its observers' places in the batch's one array of observers (held
    /// there, lane after lane, while the batch runs: one short array read
    /// per step instead of each lane's own list).
    obs: std::ops::Range<usize>,
}

impl Lane<'_, '_> {
    /// Stops the lane at `level` with `result`, finishing every observer
    /// (also after an error; the run's error first, then the first
    /// observer's, as `run` reports them).
    fn stop(&mut self, all: &mut [&mut dyn Observer], level: usize, result: Result<(), RunError>) {
        let mut fin = Ok(());
        for o in all[self.obs.clone()].iter_mut() {
            let r = o.finish();
            if fin.is_ok() {
                fin = r;
            }
        }
        self.level = level;
        self.end = Some(result.and(fin));
    }
}

/// Runs every lane of `engine` (built on the lanes' problems, at level 0 or 1)
/// to its own horizon, feeding each lane's observers the samples [`run`]
/// would (module docs). `need` says which unknowns the observers read:
/// with [`Need::Full`] the whole displacement is copied out of the engine
/// at every step (the samples of [`run`], entry for entry); with
/// [`Need::Dofs`] only those unknowns are, and the others hold the values
/// of the last whole-state check (every 64 steps) — for observers that read
/// a few dofs, as a sweep's do.
///
/// Errors (before any step): a lane count other than the engine's, a lane
/// whose `dt` is not the engine's or whose `u0` has another length, an
/// observer that wants the energy, an energy monitor. Each lane's own end
/// is in its [`LaneEnd`], in lane order.
///
/// [`run`]: crate::run
pub fn run_lockstep(engine: &mut dyn Lockstep, runs: &mut [LockstepRun<'_>], need: &Need) -> Result<Vec<LaneEnd>, RunError> {
    let start = Instant::now();
    if runs.len() != engine.lanes() {
        return Err(RunError::Invalid { field: "lanes", value: runs.len() as f64, allowed: "as many runs as the engine has lanes" });
    }
    let dofs = engine.dofs();
    for r in runs.iter() {
        if (r.cfg.dt - engine.dt()).abs() > 1e-15 * r.cfg.dt {
            return Err(RunError::Invalid { field: "dt", value: r.cfg.dt, allowed: "the lockstep engine's own dt" });
        }
        if r.u0.len() != dofs {
            return Err(RunError::Invalid { field: "u0", value: r.u0.len() as f64, allowed: "one value per unknown of the engine's lanes" });
        }
        if r.cfg.energy_warn.is_some() || r.observers.iter().any(|o| o.wants_energy()) {
            return Err(RunError::NotAllowed { field: "energy", allowed: "observers that do not want the energy, and no energy monitor, in a lockstep run (the engine does not compute it)" });
        }
    }
    let dt = engine.dt();
    let level0 = engine.level();
    if level0 > 1 {
        return Err(RunError::Invalid { field: "level", value: level0 as f64, allowed: "an engine at level 0 or 1 (not stepped yet)" });
    }
    let some: Vec<usize> = match need {
        Need::Full => Vec::new(),
        Need::Dofs(d) => d.iter().copied().filter(|&i| i < dofs).collect(),
    };
    let (zero, free) = ([0.0], [Active::None]);
    // Every lane's observers in one array, lane after lane (given back at the end).
    let mut all: Vec<&mut dyn Observer> = Vec::with_capacity(runs.iter().map(|r| r.observers.len()).sum());
    let mut lanes: Vec<Lane<'_, '_>> = runs
        .iter_mut()
        .map(|run| {
            let first = all.len();
            all.append(&mut run.observers);
            Lane { u: run.u0.to_vec(), total: run.cfg.steps(), interrupt: run.cfg.interrupt.clone(), obs: first..all.len(), run, contact_steps: 0, end: None, level: level0 }
        })
        .collect();
    // Level 0 (the initial displacement) and, for a two-step scheme, level
    // 1 (the start step).
    for (k, l) in lanes.iter_mut().enumerate() {
        let s0 = Sample { n: 0, t: 0.0, u: l.run.u0, lambda: None, energy: None, active: false, work: None, forces: &zero, status: &free };
        if let Err(e) = all[l.obs.clone()].iter_mut().try_for_each(|o| o.observe(&s0)) {
            l.stop(&mut all, level0, Err(e));
            continue;
        }
        if level0 == 0 {
            if l.total == 0 {
                l.stop(&mut all, 0, Ok(()));
            }
            continue;
        }
        engine.displacement_into(k, &mut l.u);
        if let Err(e) = check_finite(&l.u, 1, engine.time()) {
            l.stop(&mut all, 1, Err(e));
            continue;
        }
        let s1 = Sample { n: 1, t: engine.time(), u: &l.u, lambda: None, energy: None, active: false, work: None, forces: &zero, status: &free };
        let r = all[l.obs.clone()].iter_mut().try_for_each(|o| o.observe(&s1));
        if let Err(e) = r {
            l.stop(&mut all, 1, Err(e));
        } else if l.total <= 1 {
            l.stop(&mut all, 1, Ok(()));
        }
    }
    loop {
        // Every lane still going checks its interrupt before the step.
        let level = engine.level();
        for l in lanes.iter_mut().filter(|l| l.end.is_none()) {
            if l.interrupt.as_ref().is_some_and(Cancel::is_cancelled) {
                l.stop(&mut all, level, Err(RunError::Interrupted { step: level, time: engine.time() }));
            }
        }
        if lanes.iter().all(|l| l.end.is_some()) {
            break;
        }
        let level = engine.step();
        let t = engine.time();
        let tl = engine.lambda_time();
        // Every lane's results in one view (no call into the engine per lane).
        let res = engine.results();
        for (k, l) in lanes.iter_mut().enumerate() {
            if l.end.is_some() {
                continue;
            }
            if let Some(e) = res.failure(k) {
                l.stop(&mut all, level, Err(RunError::from(e.clone())));
                continue;
            }
            // The runner's whole-state check; between checks, with
            // `Need::Dofs`, only the unknowns the observers read are copied.
            if level % FINITE_CHECK_EVERY == 0 || level == l.total {
                res.displacement_into(k, &mut l.u);
                if let Err(e) = check_finite(&l.u, level, t) {
                    l.stop(&mut all, level, Err(e));
                    continue;
                }
            } else if matches!(need, Need::Full) {
                res.displacement_into(k, &mut l.u);
            } else {
                for &i in &some {
                    l.u[i] = res.value(k, i);
                }
            }
            let (lam, st) = ([res.contact_force(k)], [res.contact_status(k)]);
            let active = st[0] != Active::None;
            l.contact_steps += usize::from(active);
            let s = Sample { n: level, t, u: &l.u, lambda: Some((tl, lam[0])), energy: None, active, work: None, forces: &lam, status: &st };
            if let Err(e) = all[l.obs.clone()].iter_mut().try_for_each(|o| o.observe(&s)) {
                l.stop(&mut all, level, Err(e));
                continue;
            }
            if level >= l.total {
                l.stop(&mut all, level, Ok(()));
            }
        }
    }
    let wall_s = start.elapsed().as_secs_f64();
    let mut all = all.into_iter();
    Ok(lanes
        .into_iter()
        .map(|l| {
            l.run.observers.extend(all.by_ref().take(l.obs.len()));
            // Every lane has stopped (and finished its observers).
            let result = l.end.unwrap_or(Ok(())).map(|()| RunSummary { steps: l.level, t_end: l.level as f64 * dt, contact_steps: l.contact_steps, wall_s, energy: None });
            LaneEnd { result, level: l.level }
        })
        .collect())
}
