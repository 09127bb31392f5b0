//! Validation of `[beam]`: the pipe's scene, its contacts, scheme and
//! excitation, the reduced model.

use crate::excitation::Excitation;
use crate::{
    contact_error, contact_set, contacts_fit, contacts_table, field, finite, fits, horizon, positive, reduce_error, softest_stop, stiff_stop, too_soft, BeamToml, KeyRules, Limits, NodeMesh,
    ObstacleToml, Scene, SceneError, StopToml,
};
use crate::{instantiate, Ready};
use signorini_run::beam::{BeamExcitation, BeamScene, BeamSetup, PenaltyUnits, Pipe};
use signorini_run::RunError;
use signorini_schemes::TimeProfile;
use signorini_schemes::{families_with, SchemeError, SchemeSpec};

/// The beam's scheme and spring (N/m) from `beam.scheme`, or from the
/// paper's spelling: `contact = "projection"` is `ps(0, β)` (`beta`,
/// default 1/2), `contact = "penalty"` is `penalty-cn` (Newmark β = 1/4)
/// with a spring of `penalty_stiffness` N/m (default 10⁸) at every contact
/// without its own; neither: the paper scene's (or the custom scene's
/// projection) with `beta` / `penalty_stiffness` applied. Every key acts or
/// is refused: `beta` with the penalty, `penalty_stiffness` with the
/// projection, and `contact`, `beta`, `penalty_stiffness` with `scheme`.
fn beam_scheme(b: &BeamToml, base: &BeamScene) -> Result<(SchemeSpec, Option<f64>), SceneError> {
    if let Some(name) = b.scheme.as_deref() {
        for (key, given) in [("beam.contact", b.contact.is_some()), ("beam.beta", b.beta.is_some()), ("beam.penalty_stiffness", b.penalty_stiffness.is_some())] {
            if given {
                return Err(field(key, "acts only without beam.scheme, which replaces contact, beta and penalty_stiffness (contact = \"projection\" is ps(0,β), \"penalty\" is penalty-cn with a spring): remove one of them"));
            }
        }
        let spec: SchemeSpec = name.parse().map_err(|e| field("beam.scheme", e))?;
        if !spec.capabilities().beam {
            return Err(field(
                "beam.scheme",
                format!(
                    "{spec} does not take the beam's structure (Hermite cubics: a consistent mass, massive contact dofs away from dof 0, the support's load): allowed {}",
                    families_with(|c| c.beam)
                ),
            ));
        }
        if b.force && spec.stability_rule().is_none() {
            return Err(field("beam.force", format!("acts only with a conditionally stable scheme (its stability limit is what force lifts); {spec} is unconditionally stable: remove it")));
        }
        return Ok((spec, None));
    }
    let penalty = match b.contact.as_deref() {
        None => base.spring.is_some(),
        Some("projection") => false,
        Some("penalty") => true,
        Some(other) => return Err(field("beam.contact", format!("{other:?} is not allowed: \"projection\" or \"penalty\" (or beam.scheme = a registry scheme)"))),
    };
    if penalty {
        let stiffness = b.penalty_stiffness.or(base.spring).unwrap_or(1e8);
        positive("beam.penalty_stiffness", stiffness)?;
        if b.beta.is_some() {
            return Err(field(
                "beam.beta",
                "acts only with contact = \"projection\" (the β-scheme); the penalty contact integrates with Newmark β = 1/4: remove beta, or set contact = \"projection\"",
            ));
        }
        Ok((SchemeSpec::penalty(10.0, false), Some(stiffness)))
    } else {
        // An explicit contact = "projection" starts from β = 1/2; without it, the scene's β.
        let base_beta = if b.contact.is_none() { base.scheme.param("beta").unwrap_or(0.5) } else { 0.5 };
        let beta = b.beta.unwrap_or(base_beta);
        if !(0.0..=0.5).contains(&beta) {
            return Err(field("beam.beta", format!("{beta} is not allowed: [0, 1/2]")));
        }
        if b.penalty_stiffness.is_some() {
            return Err(field("beam.penalty_stiffness", "acts only with contact = \"penalty\": remove it, or set contact = \"penalty\""));
        }
        Ok((SchemeSpec::ps(0.0, beta), None))
    }
}

pub(crate) fn validate_beam(
    b: &BeamToml,
    stops: &[StopToml],
    obstacle: Option<&ObstacleToml>,
    support: Option<Excitation>,
    load: Option<Excitation>,
    limits: &Limits,
    one_step: bool,
) -> Result<Scene, SceneError> {
    let base = match &b.scene {
        Some(name) => *BeamScene::PAPER.iter().find(|s| s.name == name).ok_or_else(|| field("beam.scene", format!("{name:?} is not allowed: fig2, fig3, fig4, fig5, fig6, fig7 or fig8")))?,
        None => BeamScene::new("custom", 19, 1e-5, 2.0, SchemeSpec::ps(0.0, 0.5)),
    };
    let elements = b.elements.unwrap_or(base.elements);
    if elements < 1 {
        return Err(field("beam.elements", "0 is not allowed: an integer >= 1"));
    }
    fits("beam.elements", elements, true, limits)?;
    let dt = positive("beam.dt", b.dt.unwrap_or(base.dt))?;
    let t_end = if one_step { dt } else { positive("beam.t_end", b.t_end.unwrap_or(base.t_end))? };
    if t_end / dt > 1e9 {
        return Err(field("beam.dt", format!("{dt} gives {:.3e} steps: at most 1e9", t_end / dt)));
    }
    horizon("beam", dt, t_end)?;
    if dt > 1e100 {
        return Err(field("beam.dt", format!("{dt:e} is not allowed: at most 1e100 (dt² enters the step matrix)")));
    }
    let (scheme, spring) = beam_scheme(b, &base)?;
    // The paper's spelling (contact = "projection" / "penalty"), named in messages.
    let legacy = b.scheme.is_none();
    // Several contacts: [[stop]] / [obstacle] replace the tip's two stops.
    let multi = !stops.is_empty() || obstacle.is_some();
    if multi {
        if b.stops.is_some() {
            return Err(field("beam.stops", "acts only without [[stop]] and [obstacle], which replace the tip's stops: remove it (the tip's stops are the stop x = L, lo = g1, hi = g2)"));
        }
        let k = if obstacle.is_some() { elements } else { stops.len() };
        contacts_fit(contacts_table(stops), k, elements.saturating_mul(2), elements, true, limits)?;
    }
    let mut pipe = Pipe::paper();
    if let Some([g1, g2]) = b.stops {
        if !(g1.is_finite() && g2.is_finite() && g1 < g2) {
            return Err(field("beam.stops", format!("[{g1}, {g2}] is not allowed: finite, g1 < g2")));
        }
        if !(g1 <= 0.0 && g2 >= 0.0) {
            return Err(field("beam.stops", format!("[{g1}, {g2}] is not allowed: the tip starts at 0, so g1 <= 0 <= g2")));
        }
        pipe.stops = (g1, g2);
    }
    if support.is_some() && b.support.is_some() {
        return Err(field("beam.support", "not both [support] and beam.support = [A, ω]: remove beam.support (it is [support] with amplitude = A, omega = ω)"));
    }
    // [support]: the paper's sine A sin(ω t) takes the pipe's own path (bit for
    // bit the beam.support scenes); any other profile the general lifting.
    let mut excitation = BeamExcitation::default();
    let mut omega = Some(pipe.support.1);
    if let Some(e) = support {
        match e.profile {
            TimeProfile::Sine { amplitude, omega: w } => pipe.support = (amplitude, w),
            ref other => {
                if other.second_derivative().is_none() {
                    return Err(field("support.profile", "\"series\" is not allowed for a support motion: φ'' of a piecewise-linear φ is a train of impulses; give the load itself in [load]"));
                }
                excitation.support = Some(other.clone());
                omega = e.omega;
            }
        }
    }
    if let Some(e) = load {
        let l = pipe.length;
        let mesh = NodeMesh { length: l, elements, unknown: 1..=elements, x: &|i| l * i as f64 / elements as f64 };
        let node = e.x.map(|x| mesh.node("load.x", x)).transpose()?;
        excitation.load = Some((node, e.profile));
        omega = omega.or(e.omega);
    }
    if let Some([a, w]) = b.support {
        pipe.support = (finite("beam.support", a)?, positive("beam.support", w)?);
        // The lifted load is A ω² h(x) + 8 A k²/L⁴, its velocity A ω h(x).
        if !(a * w * w).is_finite() {
            return Err(field("beam.support", format!("[{a}, {w}] is not allowed: A ω² must be finite (< 1.8e308)")));
        }
    }
    let scene = BeamScene { name: "scene", elements, dt, t_end, scheme, spring, paper_seconds: base.paper_seconds };
    let contacts = if multi {
        let l = pipe.length;
        let mesh = NodeMesh { length: l, elements, unknown: 1..=elements, x: &|i| l * i as f64 / elements as f64 };
        let rules = KeyRules {
            restitution: match scheme {
                spec if spec.capabilities().restitution => Ok(()),
                _ if legacy => Err("acts only with contact = \"projection\" (the β-scheme's impact law); the penalty contact has none: remove it, or set contact = \"projection\"".to_string()),
                spec => Err(format!("acts only with a scheme that has a restitution law ({}), not {spec}: remove it, or choose such a scheme", families_with(|c| c.restitution && c.beam))),
            },
            stiffness: match scheme {
                spec if spec.capabilities().stiffness => Ok(()),
                _ if legacy => Err("acts only with contact = \"penalty\" (N/m, like penalty_stiffness): remove it, or set contact = \"penalty\"".to_string()),
                spec => Err(format!("acts only with a penalty scheme ({}), not {spec}: remove it, or choose one", families_with(|c| c.stiffness && c.beam))),
            },
        };
        // The lifted displacement u = ũ - hφ starts at 0.
        let mut set = contact_set(stops, obstacle, &mesh, &|_| 0.0, &rules)?;
        // beam.penalty_stiffness is every stop's spring (N/m) unless it gives its own.
        if let Some(stiffness) = spring {
            for st in &mut set.stops {
                st.stiffness = st.stiffness.or(Some(stiffness));
            }
        }
        Some(set)
    } else {
        None
    };
    let rho_s = pipe.rho_s;
    let reduce = b.reduce.as_ref().map(|r| r.keep("beam")).transpose()?;
    let mut setup = BeamSetup::new(pipe, scene).with_excitation(excitation.clone()).forced(b.force);
    setup.stops = contacts.as_ref().map(|c| c.stops.clone());
    setup.reduce = reduce;
    if reduce.is_some() {
        if let Some(beta) = scheme.param("beta").filter(|_| legacy && spring.is_none()) {
            if beta < 0.25 {
                return Err(field(
                    "beam.beta",
                    format!("{beta} is not allowed with reduce: the reduced model's contacts are massless, and the β-scheme with a massless node is unstable for every β < 1/4; allowed [1/4, 1/2]"),
                ));
            }
        }
    }
    if excitation.support.is_none() {
        omega = Some(pipe.support.1);
    }
    // The clock alone (a sweep's first look): no integrator.
    if one_step {
        return Ok(Scene::Beam { pipe, scene, force: b.force, contacts, excitation, omega, reduce, ready: Ready::default() });
    }
    // Validation is the instantiation (Scene::instantiate's build), kept for the run.
    let built = setup.build().map_err(|e| match e {
        e @ RunError::Reduce(_) => reduce_error(e, "beam"),
        // The paper's β-scheme: its limit with the paper's sufficient condition (3.1).
        RunError::Scheme(SchemeError::Unstable { dt, limit, .. }) if legacy && spring.is_none() => {
            let beta = scheme.param("beta").unwrap_or(f64::NAN);
            let paper = pipe.dynamics(elements).and_then(|(beam, _, _)| signorini_run::beam::stability_limit(&beam, beta)).map_or(f64::NAN, |l| l.dt_sufficient);
            field(
                "beam.dt",
                format!("dt = {dt} is at or beyond the exact stability limit {limit:.6e} of the β-scheme with β = {beta} < 1/4 (2/sqrt((1-4β) κ_h); the paper's sufficient condition (3.1) gives {paper:.6e}); use a smaller dt or β >= 1/4 (unconditionally stable), or force = true to run past it"),
            )
        }
        RunError::Scheme(SchemeError::Unstable { .. }) => field("beam.dt", format!("{e} (or force = true to run past it)")),
        RunError::NotAllowed { field: f, allowed } => field(f, format!("not allowed here: allowed {allowed}")),
        RunError::Scheme(SchemeError::PenaltyTooStiff { field: "stop stiffness", value, max }) if contacts.is_some() => {
            let own = contacts.as_ref().and_then(|set| stiff_stop(set, value, |k| PenaltyUnits::NewtonPerMetre.kappa(k, rho_s))).filter(|s| s.own_stiffness).and_then(|s| s.stop);
            let (name, k) = match own {
                Some((i, _)) => (format!("stop.{i}.stiffness"), value * rho_s),
                None => ("beam.penalty_stiffness".to_string(), value * rho_s),
            };
            field(&name, format!("{k:e} N/m makes the contact law ill-posed in floating point at this mesh and dt (the spring is more than 1e12 times stiffer than the beam at its node); usable range: 0 < stiffness <= {:.3e} N/m", max * rho_s))
        }
        e @ RunError::Stop { .. } if contacts.is_some() => contacts.as_ref().map_or_else(|| field("beam", "unreachable"), |set| contact_error(e, set, "beam")),
        // A registry scheme that does not take this beam's contacts: its key.
        e @ RunError::Scheme(SchemeError::Structure(_) | SchemeError::NotTaken { .. }) if !legacy => field("beam.scheme", format!("{e}; allowed: a scheme that takes this beam's contacts")),
        e @ RunError::Scheme(SchemeError::Structure(_)) if contacts.is_some() => field("beam", format!("{e}; allowed: a contact set the beam's scheme takes")),
        e @ RunError::Scheme(SchemeError::Contact(signorini_contact::ContactError::Compliance(_))) if contacts.is_some() => {
            // The softest spring: a stop's own, or penalty_stiffness.
            let default = match spring {
                Some(stiffness) if contacts.as_ref().is_some_and(|c| c.sites.iter().any(|s| !s.own_stiffness)) => stiffness,
                _ => f64::INFINITY,
            };
            let name = contacts.as_ref().and_then(softest_stop).filter(|&(_, k)| k < default).map_or("beam.penalty_stiffness".to_string(), |(i, _)| format!("stop.{i}.stiffness"));
            field(&name, too_soft(e))
        }
        RunError::Scheme(SchemeError::PenaltyTooStiff { max, .. }) => {
            let k = spring.unwrap_or(f64::NAN);
            // The scheme sees κ = k/(ρS): back to N/m.
            field("beam.penalty_stiffness", format!("{k:e} N/m makes the contact law ill-posed in floating point at this mesh and dt (the spring is more than 1e12 times stiffer than the beam at its tip); usable range: 0 < penalty_stiffness <= {:.3e} N/m", max * pipe.rho_s))
        }
        e @ RunError::BlowUp { .. } => field("beam", format!("{e}: the data overflow in the first step; allowed: data whose first step is finite")),
        e => field("beam", e),
    })?;
    let ready = Ready::keep(instantiate::beam_simulation(built, pipe, excitation.clone()));
    Ok(Scene::Beam { pipe, scene, force: b.force, contacts, excitation, omega, reduce, ready })
}

/// What `signorini check` states of a valid beam scene: the text (the
/// cost line replaced by an event-driven run's `probe_cost`), its steps and
/// stability limit.
pub(crate) fn check_text(setup: &BeamSetup, pipe: &Pipe, scene: &BeamScene, force: bool, probe_cost: Option<&str>) -> Result<(String, usize, Option<f64>), crate::BuildError> {
    let scene_setup = setup;
    let (_, _, beam_) = pipe.dynamics(scene.elements).map(|(b, d, i)| (d, i, b))?;
    let steps = signorini_run::RunConfig::new(scene.dt, scene.t_end)?.steps();
    let spec = scene.scheme;
    // The paper's β-scheme (the projection, ps(0, β)) is reported with
    // the paper's sufficient condition (3.1); a penalty spring with
    // Newmark β = 1/4; any other scheme by its registry limit.
    let paper_beta = scene.projection_beta();
    let registry = match paper_beta {
        None => {
            let (_, dy, _) = scene_setup.problem()?;
            Some(spec.cfl_limit(&dy).map_err(signorini_run::RunError::from)?)
        }
        Some(_) => None,
    };
    let lim = signorini_run::beam::stability_limit(&beam_, paper_beta.unwrap_or(0.25))?;
    let stab = match paper_beta {
            Some(beta) if beta < 0.25 => format!(
                "conditionally stable (β = {beta} < 1/4): κ_h = {:.6e}, exact critical dt = 2/sqrt((1-4β) κ_h) = {:.6e} s (the paper's sufficient condition (3.1) gives {:.6e} s; with its κ bound {:.6e} s); dt = {:e} is {}",
                lim.kappa,
                lim.dt_critical,
                lim.dt_sufficient,
                lim.dt_paper,
                scene.dt,
                if scene.dt < lim.dt_critical {
                    "below it"
                } else if force {
                    "BEYOND it (forced)"
                } else {
                    "BEYOND it: the run will be refused"
                }
            ),
            Some(beta) => {
                format!("unconditionally stable (β = {beta} >= 1/4); κ_h = {:.6e} (the paper's sufficient condition (3.1) would ask dt < {:.6e} s: not a limit)", lim.kappa, lim.dt_sufficient)
            }
            None if scene.spring.is_some() => format!("Newmark β = 1/4 with a penalty spring: unconditionally stable; κ_h = {:.6e}", lim.kappa),
            None => match registry.flatten() {
                None => format!("{spec}: unconditionally stable; κ_h = {:.6e}", lim.kappa),
                Some(l) => format!("{spec}: conditionally stable: exact limit dt < {l:.6e} s ({}); dt = {:e} is below it", spec.stability_rule().unwrap_or(""), scene.dt),
            },
        };
    let text = format!(
        "valid beam scene: J = {} ({} unknowns), dt = {:e} s, T = {} s: {} steps\nstability: {stab}\ncost estimate: {:.2} s (0.42 µs per step at J = 19, measured)",
        scene.elements,
        beam_.dofs(),
        scene.dt,
        scene.t_end,
        steps,
        4.2e-7 * steps as f64 * (scene.elements as f64 / 19.0)
    );
    let text = match probe_cost {
        Some(c) => text.lines().filter(|l| !l.starts_with("cost estimate")).chain([c]).collect::<Vec<_>>().join("\n"),
        None => text,
    };
    let limit = match registry {
        Some(l) => l,
        None => paper_beta.filter(|&b| b < 0.25).map(|_| lim.dt_critical),
    };
    Ok((text, steps, limit))
}
