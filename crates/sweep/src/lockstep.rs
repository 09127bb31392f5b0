//! Runs that share a step matrix stepped together ([`simulate_lockstep`],
//! up to [`LANES`] lanes), each lane bit for bit its single run.

use crate::error::Error;
use crate::simulate::{observers, rows_of, text_cell, Plan, RunRows, ScenePlan};
use signorini_run::reduced::Need;
use signorini_run::{run_lockstep, Cancel, LockstepRun, Observer, RunConfig, RunError};
use signorini_scene::Scene;
use signorini_schemes::{Bounds, Initial, Lockstep, LockstepBatch, LockstepLane, LockstepScheme};

/// Runs per lockstep group at most: the paper beam's sweeps step up to this
/// many runs together (crates/run/benches/lockstep.rs: per run-step, 16
/// lanes cost less than 8, 8 less than 4, and all far less than one run
/// alone); a smaller group takes the narrowest engine that holds it (2, 4,
/// 8 or 16 lanes). A batch's runs are split into groups of equal size so
/// that every thread gets one.
pub const LANES: usize = 16;

/// A run the lockstep engine takes: a beam (full model) on its tip's two
/// stops, not continued from another run, whose scheme can run in lockstep
/// (`Capabilities::lockstep`: `ps(e, β)`, the paper's projection among
/// them, `moreau-jean(θ, e, γ)`, `moreau-jean-projected(θ, e, γ)`,
/// `nsga(ρ∞, e)`, `contact-stabilized`, `cd-lagrange(e)` and
/// `d1-minus-linear(e)` on both levels, `moreau-jean-combined(θ, e)`;
/// [`LockstepScheme`]), within its
/// stability limit or forced past it as its single run.
/// The lane is the run's [`Simulation`](signorini_scene::Simulation) (the
/// one its validation built): its problem and initial state.
pub(crate) fn lane_of(scene: &Scene) -> Option<(LockstepLane, LockstepScheme, f64, usize)> {
    let scheme = lockstep_params(scene)?;
    let Scene::Beam { scene: bs, .. } = scene else { return None };
    let sim = scene.instantiate(None).ok()?;
    let lane = LockstepLane { dynamics: sim.stepper.dynamics().clone(), initial: Initial { u: sim.u0, v: sim.v0 }, restitution: scheme.restitution() };
    Some((lane, scheme, bs.dt, sim.tip))
}

/// The engine and parameters of a scene the lockstep engines take (see
/// [`lane_of`]), or `None`.
pub(crate) fn lockstep_params(scene: &Scene) -> Option<LockstepScheme> {
    match scene {
        // A reduced model steps other matrices: one run at a time.
        Scene::Beam { scene: bs, contacts: None, excitation, reduce: None, .. } if excitation.start.is_none() && bs.spring.is_none() => LockstepScheme::of(&bs.scheme),
        _ => None,
    }
}

/// The batch's runs as jobs: consecutive lockstep-able runs in groups of up
/// to [`LANES`], every other run alone (indices into `prepared`). The groups
/// hold `⌈R / threads⌉` runs (at most [`LANES`]), `R` the batch's
/// lockstep-able runs, so that `threads` threads all have a group.
pub(crate) fn lockstep_jobs<T>(prepared: &[(usize, T, Result<ScenePlan, Error>)], threads: usize) -> Vec<Vec<usize>> {
    let ok: Vec<bool> = prepared.iter().map(|p| p.2.as_ref().is_ok_and(|(scene, _)| lockstep_params(scene).is_some())).collect();
    let group = ok.iter().filter(|&&o| o).count().div_ceil(threads.max(1)).clamp(1, LANES);
    let mut jobs: Vec<Vec<usize>> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    for (k, ok) in ok.into_iter().enumerate() {
        if ok {
            open.push(k);
            if open.len() == group {
                jobs.push(std::mem::take(&mut open));
            }
        } else {
            jobs.push(vec![k]);
        }
    }
    if !open.is_empty() {
        jobs.push(open);
    }
    jobs
}

/// Runs `group` (beam runs sharing a step matrix) in lockstep on one
/// [`LockstepBatch`] (the engine of their scheme, of the narrowest width
/// that holds them: 2, 4, 8 or 16 lanes) stepped by
/// [`signorini_run::run_lockstep`]:
/// each lane performs the single run's arithmetic and feeds its observers
/// the samples [`signorini_run::run`] would, so its rows are the ones
/// [`simulate`](fn@crate::simulate) writes, bit for bit.
/// `None` when the runs cannot share the engine (then run them one by one).
pub fn simulate_lockstep(group: &[(&Scene, &Plan)], interrupt: Option<&Cancel>) -> Option<Vec<RunRows>> {
    if !(2..=LANES).contains(&group.len()) {
        return None;
    }
    let mut lanes = Vec::with_capacity(group.len());
    let mut tips = Vec::with_capacity(group.len());
    let mut first: Option<(LockstepScheme, f64)> = None;
    for (scene, plan) in group {
        let (lane, scheme, d, tip) = lane_of(scene)?;
        // One engine: the same scheme, parameters and step (the
        // restitution may differ from lane to lane).
        let same = |s: LockstepScheme| match (s, scheme) {
            (LockstepScheme::PaoliSchatzman { beta: a, .. }, LockstepScheme::PaoliSchatzman { beta: b, .. }) => a == b,
            (LockstepScheme::MoreauJean { theta: a, gamma: g, .. }, LockstepScheme::MoreauJean { theta: b, gamma: h, .. }) => a == b && g == h,
            (LockstepScheme::MoreauJeanProjected { theta: a, gamma: g, .. }, LockstepScheme::MoreauJeanProjected { theta: b, gamma: h, .. }) => a == b && g == h,
            (LockstepScheme::Nsga { rho_inf: a, .. }, LockstepScheme::Nsga { rho_inf: b, .. }) => a == b,
            (LockstepScheme::ContactStabilized, LockstepScheme::ContactStabilized) => true,
            (LockstepScheme::CdLagrange { .. }, LockstepScheme::CdLagrange { .. }) => true,
            (LockstepScheme::D1MinusLinear { level: a, .. }, LockstepScheme::D1MinusLinear { level: b, .. }) => a == b,
            (LockstepScheme::MoreauJeanCombined { theta: a, .. }, LockstepScheme::MoreauJeanCombined { theta: b, .. }) => a == b,
            _ => false,
        };
        if first.is_some_and(|(s, dt)| !same(s) || dt != d) || plan.dt != d {
            return None;
        }
        first = first.or(Some((scheme, d)));
        tips.push(tip);
        lanes.push(lane);
    }
    let (scheme, dt) = first?;
    let inits: Vec<Vec<f64>> = lanes.iter().map(|l| l.initial.u.clone()).collect();
    let contacts: Vec<Vec<(usize, Bounds)>> = lanes.iter().map(|l| l.dynamics.contacts.iter().map(|c| (c.dof, c.bounds)).collect()).collect();
    let lanes_of = Lanes { group, tips: &tips, inits: &inits, contacts: &contacts };
    run_group(LockstepBatch::new(scheme, dt, lanes).ok()?, &lanes_of, interrupt)
}

/// What a group's lanes bring besides their problems: scene and plan, tip,
/// initial displacement and contacts.
struct Lanes<'g, 's> {
    group: &'g [(&'s Scene, &'s Plan)],
    tips: &'g [usize],
    inits: &'g [Vec<f64>],
    contacts: &'g [Vec<(usize, Bounds)>],
}

/// Steps `eng` (built on the lanes of `lanes`) with each lane's observers,
/// and gives each lane's rows.
fn run_group(mut eng: LockstepBatch, lanes: &Lanes<'_, '_>, interrupt: Option<&Cancel>) -> Option<Vec<RunRows>> {
    let Lanes { group, tips, inits, contacts } = *lanes;
    // The vibro observers read the tip and the contact only.
    let mut need: Vec<usize> = tips.iter().copied().chain(std::iter::once(eng.contact_dof())).collect();
    need.sort_unstable();
    need.dedup();
    let mut vibs = Vec::with_capacity(group.len());
    let mut cfgs = Vec::with_capacity(group.len());
    for (k, (_, plan)) in group.iter().enumerate() {
        vibs.push(observers(plan, tips[k], contacts[k].clone()).ok()?);
        let mut rc = RunConfig::new(plan.dt, plan.t_end).ok()?;
        rc.interrupt = interrupt.cloned();
        cfgs.push(rc);
    }
    let ends = {
        let mut runs: Vec<LockstepRun<'_>> = vibs.iter_mut().zip(&cfgs).zip(inits).map(|((v, rc), u0)| LockstepRun::new(u0, rc, vec![v as &mut dyn Observer])).collect();
        run_lockstep(&mut eng, &mut runs, &Need::Dofs(need)).ok()?
    };
    Some(
        vibs.iter()
            .zip(ends)
            .zip(group)
            .map(|((vib, end), (_, plan))| {
                // What `simulate` makes of `run`'s result.
                let (steps, status) = match &end.result {
                    Ok(s) => (s.steps, "ok".to_string()),
                    Err(RunError::Interrupted { .. }) => (0, "interrupted".to_string()),
                    Err(e) => (end.level, text_cell(&e.to_string())),
                };
                rows_of(vib, plan, steps, status, None)
            })
            .collect(),
    )
}
