//! Validation of `[bar]`: the mesh, the benchmark or the custom data, the
//! contacts, the scheme, the reduced model.

use crate::excitation::Excitation;
use crate::{
    contact_error, contact_set, contacts_fit, contacts_table, extreme_key, field, finite, fits, horizon, positive, reduce_error, scheme_error, softest_stop, stiff_stop, too_soft, BarRun, BarToml,
    FieldToml, InitialField, KeyRules, Limits, NodeMesh, ObstacleToml, SceneError, StopToml,
};
use crate::{Ready, Simulation};
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_run::{BarProblem, Benchmark};
use signorini_schemes::{families_with, SchemeError, SchemeSpec};

pub(crate) fn validate_bar(b: &BarToml, stops: &[StopToml], obstacle: Option<&ObstacleToml>, load: Option<Excitation>, limits: &Limits, one_step: bool) -> Result<BarRun, SceneError> {
    let mass: BarMass = b.mass.parse().map_err(|e| field("bar.mass", e))?;
    let scheme: SchemeSpec = b.scheme.parse().map_err(|e| field("bar.scheme", e))?;
    if scheme.needs_massless_node() && !mass.massless_contact_node() {
        return Err(field("bar.mass", format!("scheme {scheme} needs a massless contact node: mod, mod1, mod2, mod3, transfer or singular (got {mass})")));
    }
    if scheme.needs_diagonal_mass() && mass != BarMass::Lumped {
        return Err(field("bar.mass", format!("scheme {scheme} needs a diagonal mass with a massive contact node: lumped (got {mass})")));
    }
    if scheme.needs_massive_node() && mass.massless_contact_node() {
        return Err(field("bar.mass", format!("scheme {scheme} needs a massive contact node: std or lumped (got {mass})")));
    }
    if b.elements < 2 {
        return Err(field("bar.elements", format!("{} is not allowed: an integer >= 2", b.elements)));
    }
    let degree = b.degree.unwrap_or(1);
    if !(1..=3).contains(&degree) {
        return Err(field("bar.degree", format!("{degree} is not allowed: 1, 2 or 3 (Lagrange P1, P2, P3)")));
    }
    if degree > 1 && !matches!(mass, BarMass::Std | BarMass::Lumped | BarMass::Mod | BarMass::Mod1) {
        return Err(field("bar.mass", format!("{mass} is not defined at degree {degree}: allowed std, lumped, mod or mod1")));
    }
    let reduce = b.reduce.as_ref().map(|r| r.keep("bar")).transpose()?;
    if reduce.is_some() {
        if !scheme.accepts_massless_node(true) {
            return Err(field(
                "bar.scheme",
                format!(
                    "{scheme} needs a massive contact node, and a reduced model's contacts are massless (reduce): allowed a scheme that takes a massless node ({}; ps with β >= 1/4)",
                    families_with(|c| c.accepts_massless_node(true))
                ),
            ));
        }
        if !mass.massless_contact_node() {
            return Err(field(
                "bar.mass",
                format!("{mass} with reduce: the reduction keeps the contacts massless, exact for a parent whose contact nodes carry no mass; allowed mod, mod1, mod2, mod3, transfer or singular"),
            ));
        }
    }
    // A P`k` bar of m elements has the unknowns of a P1 bar of k m.
    fits("bar.elements", b.elements.saturating_mul(degree), false, limits)?;
    // Several contacts: [[stop]] / [obstacle] replace the obstacle at x = 0.
    let multi = !stops.is_empty() || obstacle.is_some();
    if multi {
        if b.benchmark.is_some() {
            return Err(field(contacts_table(stops), "a benchmark brings its own obstacle and exact solution: remove [[stop]] and [obstacle], or remove benchmark"));
        }
        if b.gap.is_some() {
            return Err(field("bar.gap", "acts only without [[stop]] and [obstacle], which replace the obstacle at x = 0: remove it (that obstacle is the stop x = 0, lo = gap)"));
        }
        if obstacle.is_some() && mass.massless_contact_node() {
            return Err(field("bar.mass", format!("{mass} takes the mass off every contact node, and [obstacle] makes every node one: allowed std or lumped with [obstacle]")));
        }
        // Every unknown node with [obstacle] (m + 1 at most), else one per stop.
        let unknowns = b.elements.saturating_mul(degree).saturating_add(1);
        let k = if obstacle.is_some() { unknowns } else { stops.len() };
        contacts_fit(contacts_table(stops), k, unknowns, b.elements.saturating_mul(degree), false, limits)?;
    }
    let (mut problem, benchmark, default_t) = match &b.benchmark {
        Some(name) => {
            for (k, given) in [
                ("length", b.length.is_some()),
                ("wave_speed", b.wave_speed.is_some()),
                ("far_end", b.far_end.is_some()),
                ("gap", b.gap.is_some()),
                ("body_force", b.body_force.is_some()),
                ("initial_displacement", b.initial_displacement.is_some()),
                ("initial_velocity", b.initial_velocity.is_some()),
            ] {
                if given {
                    return Err(field(&format!("bar.{k}"), "comes from the benchmark: remove it, or remove `benchmark`"));
                }
            }
            let bench: Benchmark = name.parse().map_err(|e| field("bar.benchmark", e))?;
            let t = bench.default_ratio_and_horizon().1;
            let t_end = b.t_end.unwrap_or(t);
            let exact = bench.exact(positive("bar.t_end", t_end)?).map_err(|e| field("bar.t_end", e))?;
            let p = bench.problem_with_degree(exact.as_ref(), b.elements, mass, degree).map_err(|e| field("bar", e))?;
            (p, Some(bench), t)
        }
        None => {
            let length = positive("bar.length", b.length.unwrap_or(1.0))?;
            if length > 1e150 {
                return Err(field("bar.length", format!("{length:e} is not allowed: at most 1e150 (products of lengths must stay finite)")));
            }
            let c = positive("bar.wave_speed", b.wave_speed.unwrap_or(1.0))?;
            let end = match b.far_end.as_deref().unwrap_or("clamped") {
                "clamped" => RightEnd::Clamped,
                "free" => RightEnd::Free,
                other => return Err(field("bar.far_end", format!("{other:?} is not allowed: \"clamped\" or \"free\""))),
            };
            // With stops the obstacle at x = 0 is unused: a gap no state is below.
            let gap = if multi { -f64::MAX } else { finite("bar.gap", b.gap.unwrap_or(0.0))? };
            let f = finite("bar.body_force", b.body_force.unwrap_or(0.0))?;
            let u0 = InitialField::compile("bar.initial_displacement", b.initial_displacement.as_ref().unwrap_or(&FieldToml::Number(0.0)))?;
            let v0 = InitialField::compile("bar.initial_velocity", b.initial_velocity.as_ref().unwrap_or(&FieldToml::Number(0.0)))?;
            u0.check_covers("bar.initial_displacement", 0.0, length)?;
            v0.check_covers("bar.initial_velocity", 0.0, length)?;
            // The stiffness entries are c² m / L.
            let k = c * c * b.elements as f64 / length;
            if !(k.is_finite() && k >= f64::MIN_POSITIVE && (length / b.elements as f64) >= f64::MIN_POSITIVE) {
                let key = extreme_key(&[("bar.wave_speed", b.wave_speed), ("bar.length", b.length)]).map_or("bar.elements", |(k, _)| k);
                return Err(field(
                    key,
                    format!(
                        "wave_speed = {c:e}, length = {length:e}, elements = {}: the stiffness c² m / L or the element size L / m leaves the floating-point range; allowed: 2.2e-308 <= c² m / L < 1.8e308 and L / m >= 2.2e-308",
                        b.elements
                    ),
                ));
            }
            let bar = Bar::new(length, b.elements, c, end).and_then(|bar| bar.with_degree(degree)).map_err(|e| field("bar", e))?;
            // The first node where a field is not finite, to name its key.
            let bad = std::cell::Cell::new(None);
            let at = |key: &'static str, fld: &InitialField, x: f64| {
                let v = fld.eval(x);
                if !v.is_finite() && bad.get().is_none() {
                    bad.set(Some((key, x, v)));
                }
                v
            };
            let p = BarProblem::new(bar, mass, gap, f, |x| at("bar.initial_displacement", &u0, x), |x| at("bar.initial_velocity", &v0, x)).map_err(|e| match bad.get() {
                Some((key, x, v)) => field(key, format!("{v} at the node x = {x} is not allowed: a value finite at every node")),
                None => field("bar", e),
            })?;
            (p, None, 1.0)
        }
    };
    let contacts = if multi {
        let bar = problem.bar;
        let mesh = NodeMesh { length: bar.length, elements: bar.last_node(), unknown: 0..=bar.dofs() - 1, x: &|i| bar.node(i) };
        let rules = KeyRules {
            restitution: if scheme.capabilities().restitution {
                Ok(())
            } else {
                Err(format!("acts only with a scheme that has a restitution law ({}), not {scheme}: remove it, or choose such a scheme", families_with(|c| c.restitution)))
            },
            stiffness: if scheme.capabilities().stiffness {
                Ok(())
            } else {
                Err(format!("acts only with a penalty scheme ({}), not {scheme}: remove it, or choose one", families_with(|c| c.stiffness)))
            },
        };
        let u0 = problem.initial.u.clone();
        let set = contact_set(stops, obstacle, &mesh, &|i| u0[i], &rules)?;
        if set.stops.len() == 1 && mass.massless_contact_node() && set.stops[0].node != 0 {
            return Err(field("bar.mass", format!("{mass} with one contact needs it at node 0 (x = 0), not node {}: allowed std or lumped, or the stop at x = 0", set.stops[0].node)));
        }
        problem = problem.with_stops(set.stops.clone()).map_err(|e| contact_error(e, &set, "bar"))?;
        Some(set)
    } else {
        None
    };
    let mut omega = None;
    if let Some(e) = load {
        if b.benchmark.is_some() {
            return Err(field("load", "a benchmark is its own problem with its exact solution: remove [load], or remove benchmark"));
        }
        let bar = problem.bar;
        let mesh = NodeMesh { length: bar.length, elements: bar.last_node(), unknown: 0..=bar.dofs() - 1, x: &|i| bar.node(i) };
        let node = e.x.map(|x| mesh.node("load.x", x)).transpose()?;
        omega = e.omega;
        problem = problem.with_load(node, e.profile).map_err(|e| field("load.x", e))?;
    }
    let dt = match (b.dt, b.ratio) {
        (Some(dt), None) => positive("bar.dt", dt)?,
        (None, Some(r)) => problem.bar.h() / positive("bar.ratio", r)?,
        (None, None) => return Err(field("bar.dt", "give dt or ratio (= dx/dt)")),
        (Some(_), Some(_)) => return Err(field("bar.ratio", "give dt or ratio, not both")),
    };
    let t_end = if one_step { dt } else { positive("bar.t_end", b.t_end.unwrap_or(default_t))? };
    if t_end / dt > 1e9 {
        return Err(field("bar.dt", format!("{dt} gives {:.3e} steps: at most 1e9", t_end / dt)));
    }
    horizon("bar", dt, t_end)?;
    // M + β dt² K must keep M's digits: (c dt / h)² below 1e15.
    let r = problem.bar.wave_speed * dt / problem.bar.h();
    if !(r * r <= 1e15) {
        let key = extreme_key(&[("bar.wave_speed", b.wave_speed), ("bar.ratio", b.ratio), ("bar.dt", b.dt), ("bar.length", b.length)]).map_or("bar.dt", |(k, _)| k);
        return Err(field(key, format!("c dt / h = {r:e}: the step matrix M + β dt² K loses the mass to rounding; allowed: c dt / h <= 3.2e7")));
    }
    // An overflow comes from an extreme number (beyond 1e100) if one is given
    // — of the data, or of the initial fields at the nodes. (The gap only
    // enters comparisons: it overflows nothing.)
    let largest = |v: &[f64], given: bool| given.then(|| v.iter().fold(0.0_f64, |a, x| a.max(x.abs()))).filter(|m| *m > 1.0);
    let numbers = [
        ("bar.body_force", b.body_force),
        ("bar.length", b.length),
        ("bar.wave_speed", b.wave_speed),
        ("bar.dt", b.dt),
        ("bar.ratio", b.ratio),
        ("bar.initial_displacement", largest(&problem.initial.u, b.initial_displacement.is_some())),
        ("bar.initial_velocity", largest(&problem.initial.v, b.initial_velocity.is_some())),
    ];
    let overflow_key = extreme_key(&numbers).filter(|(_, scale)| *scale > 100.0).map_or("bar", |(k, _)| k);
    // The clock alone (a sweep's first look): no integrator.
    if one_step {
        return Ok(BarRun { problem, benchmark, scheme, dt, t_end, contacts, omega, reduce, ready: Ready::default() });
    }
    // Validation is the instantiation (Scene::instantiate's build), kept for the run.
    let full = problem.dynamics();
    let tip = full.contacts[0].dof;
    let (dy, init, reduction) = match reduce {
        None => (full, problem.initial.clone(), None),
        Some(keep) => {
            let red = signorini_run::reduced::reduce(&full, &problem.initial, keep).map_err(|e| reduce_error(e, "bar"))?;
            (red.dynamics, red.initial, Some(red.reduction))
        }
    };
    let stepper = scheme.build(dy, dt, &init).map_err(|e| match (e, &contacts) {
        (SchemeError::PenaltyTooStiff { field: "stop stiffness", value, max }, Some(set)) => {
            let name = stiff_stop(set, value, |k| k).and_then(|s| s.stop).map_or("stop".to_string(), |(i, _)| format!("stop.{i}.stiffness"));
            field(&name, format!("{value:e} makes the contact law ill-posed in floating point at this mesh and dt (the spring is more than 1e12 times stiffer than the step matrix at its node); usable range: 0 < stiffness <= {max:.3e}"))
        }
        (e @ SchemeError::Structure(_), Some(_)) => field("bar.scheme", format!("{e}; allowed: a scheme that takes this contact set")),
        (e @ SchemeError::Contact(signorini_contact::ContactError::Compliance(_)), Some(set)) => {
            // The softest spring: a stop's own, or the scheme's γ_P K_cc.
            let name = softest_stop(set).filter(|&(_, k)| k < 1e-100).map_or("bar.scheme".to_string(), |(i, _)| format!("stop.{i}.stiffness"));
            field(&name, too_soft(e))
        }
        (SchemeError::Events(signorini_schemes::events::EventsError::MasslessRestitution { contact, restitution }), set) => {
            // A stop's own restitution, else the scheme's e.
            let key = set.as_ref().filter(|s| s.stops.get(contact).is_some_and(|st| st.restitution.is_some())).map_or("bar.scheme".to_string(), |s| s.field_of(contact, "restitution").0);
            field(
                &key,
                format!("e = {restitution} at a massless contact node (this mass treatment or reduced model gives the contact node no mass): it lands on its bound without an impact (its force is statically condensed), so no restitution acts there; allowed: 0 (event-driven(0)), or a massive contact node (mass std or lumped)"),
            )
        }
        (e, _) => scheme_error(e, overflow_key),
    })?;
    let ready = Ready::keep(Simulation { stepper, u0: init.u, v0: init.v, tip, lift: None, reduction });
    Ok(BarRun { problem, benchmark, scheme, dt, t_end, contacts, omega, reduce, ready })
}

/// What `signorini check` states of a valid bar scene: the text (the
/// cost line replaced by an event-driven run's `probe_cost`), its steps and
/// stability limit.
pub(crate) fn check_text(b: &BarRun, probe_cost: Option<&str>) -> Result<(String, usize, Option<f64>), crate::BuildError> {
    let steps = signorini_run::RunConfig::new(b.dt, b.t_end)?.steps();
    let dofs = b.problem.bar.dofs();
    let limit = b.scheme.cfl_limit(&b.problem.dynamics())?;
    let stability = match limit {
        None => "unconditionally stable".to_string(),
        // Validation refuses a dt at or beyond the limit.
        Some(limit) => format!("conditionally stable: exact limit dt < {limit:.6e} ({}); dt = {:e} is below it", b.scheme.stability_rule().unwrap_or(""), b.dt),
    };
    let text = format!(
        "valid bar scene: {} elements ({} unknowns), mass {}, scheme {}, dt = {:e}, T = {}: {} steps, {:.3e} dof-steps\n\
             stability: {stability}\n\
             cost estimate: {:.2} s stepping with all norms (10 ns per dof-step, measured on 2 cores)",
        b.problem.bar.elements,
        dofs,
        b.problem.mass,
        b.scheme,
        b.dt,
        b.t_end,
        steps,
        (dofs * steps) as f64,
        1e-8 * (dofs * steps) as f64
    );
    let text = match probe_cost {
        Some(c) => text.lines().filter(|l| !l.starts_with("cost estimate")).chain([c]).collect::<Vec<_>>().join("\n"),
        None => text,
    };
    Ok((text, steps, limit))
}
