//! Validation of `[oscillator]`: the impact oscillator and its scheme.

use crate::excitation::Table;
use crate::{contacts_table, field, horizon, positive, OscillatorToml, Scene, SceneError, SceneFile};
use crate::{Ready, Simulation};
use signorini_run::oscillator::Oscillator;
use signorini_run::RunError;
use signorini_schemes::{families_with, SchemeError, SchemeSpec};

impl SceneFile {
    pub(crate) fn validate_oscillator(&self, o: &OscillatorToml, one_step: bool) -> Result<Scene, SceneError> {
        if !self.stop.is_empty() || self.obstacle.is_some() {
            return Err(field(contacts_table(&self.stop), "acts only with [bar] or [beam]: the oscillator's stop is oscillator.stop (two: oscillator.stops)"));
        }
        for (k, t) in [("support", self.support.is_some()), ("load", self.load.is_some())] {
            if t {
                return Err(field(k, "acts only with [bar] or [beam]: the oscillator's load is [forcing]"));
            }
        }
        if self.output.snapshots_every > 0 {
            return Err(field("output.snapshots_every", "acts only with [bar] or [beam] (the oscillator has one dof): remove it"));
        }
        let (lower, stop) = oscillator_stops(o)?;
        let exc = self.forcing.as_ref().map(|f| f.build(Table::Forcing, self.base.as_deref())).transpose()?;
        // The scheme first: its e (when it states one) is the restitution that acts.
        let (scheme, restitution) = oscillator_scheme(o)?;
        let osc = Oscillator {
            mass: o.mass,
            stiffness: o.stiffness,
            damping_ratio: o.damping_ratio.unwrap_or(0.0),
            stop,
            lower,
            restitution,
            x0: o.initial_displacement.unwrap_or(0.0),
            v0: o.initial_velocity.unwrap_or(0.0),
            load: exc.as_ref().map(|e| e.profile.clone()),
        };
        osc.validate().map_err(|e| match e {
            // x(0) outside the stops: the stops' fault when x(0) is the default.
            RunError::Invalid { field: "oscillator.initial_displacement", value, .. } if value.is_finite() && o.initial_displacement.is_none() => match lower {
                None => field("oscillator.stop", format!("{stop} is not allowed: >= initial_displacement (default 0): the initial state must satisfy x <= stop")),
                Some(lo) => field("oscillator.stops", format!("[{lo}, {stop}] is not allowed: lo <= initial_displacement (default 0) <= hi: the initial state must lie between the stops")),
            },
            RunError::Invalid { field: "oscillator.initial_displacement", value, .. } if lower.is_some() => {
                field("oscillator.initial_displacement", format!("{value} is not allowed: finite and between the stops, in [{}, {stop}] (oscillator.stops)", lower.unwrap_or(f64::NEG_INFINITY)))
            }
            RunError::Invalid { field: "oscillator.lower", value, allowed } => field("oscillator.stops", format!("lo = {value} is not allowed: {allowed}")),
            RunError::Invalid { field: f, value, allowed } => field(f, format!("{value} is not allowed: {allowed}")),
            e => field("oscillator", e),
        })?;
        let scheme = scheme.unwrap_or_else(|| osc.default_scheme());
        let dt = positive("oscillator.dt", o.dt)?;
        let t_end = if one_step { dt } else { positive("oscillator.t_end", o.t_end)? };
        if t_end / dt > 1e10 {
            return Err(field("oscillator.dt", format!("{dt} gives {:.3e} steps: at most 1e10", t_end / dt)));
        }
        horizon("oscillator", dt, t_end)?;
        let omega = exc.and_then(|e| e.omega);
        // The clock alone (a sweep's first look): no integrator.
        if one_step {
            return Ok(Scene::Oscillator { omega, osc, scheme, dt, t_end, ready: Ready::default() });
        }
        // Validation is the instantiation (Scene::instantiate's build), kept for the run.
        let built = osc.dynamics().and_then(|(dy, own)| Ok((scheme.build(dy, dt, &own)?, own)));
        let (stepper, own) = built.map_err(|e| match e {
            RunError::Scheme(e @ SchemeError::Unstable { .. }) => field("oscillator.dt", e),
            RunError::Scheme(e @ (SchemeError::Factor(_) | SchemeError::NonFinite { .. })) => field("oscillator", format!("{e}: allowed: data whose step matrix is finite and positive definite")),
            RunError::Scheme(e) => field("oscillator.scheme", e),
            e @ RunError::BlowUp { .. } => field("oscillator", format!("{e}: the data overflow in the first step; allowed: data whose first step is finite")),
            e => field("oscillator", e),
        })?;
        let ready = Ready::keep(Simulation { stepper, u0: own.u, v0: own.v, tip: 0, lift: None, reduction: None });
        Ok(Scene::Oscillator { omega, osc, scheme, dt, t_end, ready })
    }
}

/// The oscillator's bounds `(lower, upper)` from `stop` (one side: `x <=
/// stop`) or `stops = [lo, hi]` (`lo <= x <= hi`, as `beam.stops`): exactly
/// one of them, finite, lo < hi.
fn oscillator_stops(o: &OscillatorToml) -> Result<(Option<f64>, f64), SceneError> {
    match (o.stop, o.stops) {
        (Some(_), Some(_)) => Err(field(
            "oscillator.stops",
            "and oscillator.stop are both given; one acts: stop = g is one stop (x <= g), stops = [lo, hi] two (lo <= x <= hi): remove oscillator.stop, or oscillator.stops",
        )),
        (None, None) => Err(field("oscillator.stop", "missing: give the stop, stop = g (x <= g), or two, stops = [lo, hi] (lo <= x <= hi)")),
        (Some(g), None) => Ok((None, g)),
        (None, Some([lo, hi])) => {
            if !(lo.is_finite() && hi.is_finite()) {
                return Err(field("oscillator.stops", format!("[{lo}, {hi}] is not allowed: finite numbers [lo, hi], lo < hi")));
            }
            if lo >= hi {
                return Err(field("oscillator.stops", format!("[{lo}, {hi}] is not allowed: lo < hi (lo <= x <= hi)")));
            }
            Ok((Some(lo), hi))
        }
    }
}

/// The oscillator's scheme (`None`: the default, [`Oscillator::default_scheme`])
/// and the restitution that acts (docs/vibro-impact.md, "Which restitution
/// acts"): a scheme with an impact law whose text states its e (`ps(0.5)`,
/// `ps-e0.5`, `event-driven(0.8)`) takes that e, and `oscillator.restitution`
/// may only repeat it; a scheme written by its family's name alone
/// (`event-driven`, `moreau-jean`) or without its e takes
/// `oscillator.restitution` (default 0), and is printed with it.
fn oscillator_scheme(o: &OscillatorToml) -> Result<(Option<SchemeSpec>, f64), SceneError> {
    let r = o.restitution.unwrap_or(0.0);
    let Some(text) = &o.scheme else {
        return Ok((None, r));
    };
    let spec: SchemeSpec = text.parse().map_err(|e| field("oscillator.scheme", e))?;
    if spec.needs_massless_node() {
        return Err(field("oscillator.scheme", format!("{spec} needs a massless contact node; the oscillator's mass sits at its contact: {}", families_with(|c| c.accepts_massless_node(false)))));
    }
    let Some(at) = spec.family().params.iter().position(|p| p.name == "e").filter(|_| spec.capabilities().restitution) else {
        if r != 0.0 {
            return Err(field(
                "oscillator.restitution",
                format!("acts only with a scheme that has an impact law ({}); {spec} has none: remove it or set it to 0, or choose ps", families_with(|c| c.restitution)),
            ));
        }
        return Ok((Some(spec), 0.0));
    };
    let t = text.trim();
    let states_e = match t.split_once('(') {
        Some((_, args)) => args.trim_end_matches(')').split(',').filter(|a| !a.trim().is_empty()).count() > at,
        None => t != spec.family().name,
    };
    let e = spec.args()[at];
    // The scheme with the e `r`.
    let with_e = |r: f64| {
        let mut args = spec.args().to_vec();
        args[at] = r;
        spec.family().with(&args)
    };
    match o.restitution {
        Some(r) if states_e && r != e => Err(field(
            "oscillator.restitution",
            format!(
                "{r} conflicts with oscillator.scheme = \"{t}\", whose e = {e} acts: give the restitution once (remove oscillator.restitution, or write it in the scheme: \"{}\")",
                with_e(r).call()
            ),
        )),
        Some(r) if !states_e => {
            let spec = with_e(r);
            spec.validate().map_err(|e| field("oscillator.restitution", e))?;
            Ok((Some(spec), r))
        }
        _ => Ok((Some(spec), e)),
    }
}

/// What `signorini check` states of a valid oscillator scene: the text (the
/// cost line replaced by an event-driven run's `probe_cost`), its steps and
/// stability limit.
pub(crate) fn check_text(osc: &Oscillator, scheme: SchemeSpec, dt: f64, t_end: f64, omega: Option<f64>, probe_cost: Option<&str>) -> Result<(String, usize, Option<f64>), crate::BuildError> {
    let steps = signorini_run::RunConfig::new(dt, t_end)?.steps();
    let (dy, _) = osc.dynamics()?;
    let limit = scheme.cfl_limit(&dy)?;
    let stability = match limit {
        None => "unconditionally stable".to_string(),
        Some(limit) => format!("conditionally stable: exact limit dt < {limit:.6e}; dt = {dt:e} is below it"),
    };
    let wn = (osc.stiffness / osc.mass).sqrt();
    let text = format!(
        "valid oscillator scene: m = {}, k = {}, ζ = {}, ω_n = {wn:.6}, {}, r = {}, scheme {scheme}, dt = {dt:e}, T = {t_end}: {steps} steps{}\nstability: {stability}",
        osc.mass,
        osc.stiffness,
        osc.damping_ratio,
        match osc.lower {
            None => format!("stop {}", osc.stop),
            Some(lo) => format!("stops [{lo}, {}]", osc.stop),
        },
        signorini_run::text::num(osc.restitution),
        omega.map_or(String::new(), |w| format!("; forcing Ω = {w} ({:.3} forcing periods)", t_end * w / std::f64::consts::TAU))
    );
    let text = match probe_cost {
        Some(c) => format!("{text}\n{c}"),
        None => text,
    };
    Ok((text, steps, limit))
}
