//! Nonsmooth modes of a discretised bar (docs/theory.md §11.7): the family
//! of periodic motions of the unforced, undamped `[bar]` scene on its
//! exact event-driven flow, continued in the energy, next to the continuous
//! bar's closed form ([`signorini_exact::Backbone`], family `k = 1`).
//!
//! Each point is an [`autonomous_orbit`]: Gauss–Newton on
//! `(P_T(x) − x, phase, E(x) − E) = 0` with the period unknown. The first
//! start is the exact mode sampled at the nodes (the bar stretched linearly,
//! at rest, at the top of its flight) — below the exact threshold of a
//! clearance, the discrete bar's first linear mode —, each next one the secant predictor
//! through the last two points (natural-parameter continuation in the
//! energy, geometric steps). A point where Newton fails ends the family:
//! [`Modes::stopped`] says at which energy and why.

use crate::map::Model;
use crate::shoot::{autonomous_orbit, Newton, Orbit};
use crate::OrbitError;
use faer::c64;
use signorini_exact::{Backbone, BackbonePoint, ExactSolution, FarEnd, ModeBar};
use signorini_scene::{Scene, SceneFile};
use signorini_schemes::events::EventKind;
use signorini_schemes::SchemeSpec;

/// One periodic motion of the discrete bar at one energy.
#[derive(Clone, Debug)]
pub struct ModePoint {
    /// The energy `½ vᵀMv + ½ qᵀKq`.
    pub energy: f64,
    /// The period (s).
    pub period: f64,
    /// Time per period with the contact node on the obstacle (s).
    pub contact_time: f64,
    /// Impacts per period (landings at a non-zero speed).
    pub impacts_per_period: usize,
    /// Floquet multipliers, by decreasing modulus, the two trivial ones at
    /// +1 (the flow's direction, the energy) left out.
    pub multipliers: Vec<c64>,
    /// `‖P_T(x) − x‖∞` at the solution.
    pub residual: f64,
    /// The continuous bar's mode at this energy (family `k = 1`), if the
    /// closed form applies (far end clamped).
    pub exact: Option<BackbonePoint>,
    /// The orbit (its state on the section `x`: the state dofs' `(q, v)`).
    pub orbit: Orbit,
}

impl ModePoint {
    /// The largest multiplier's modulus (1 for a neutrally stable motion
    /// of the conservative bar).
    pub fn mu_max(&self) -> f64 {
        self.multipliers.first().map_or(1.0, |m| m.norm())
    }
}

/// A backbone of a discrete bar: the points found, and where and why the
/// continuation stopped before the end of the range (if it did).
#[derive(Debug)]
pub struct Modes {
    /// Points by increasing energy.
    pub points: Vec<ModePoint>,
    /// The energy at which no orbit was found, and Newton's report.
    pub stopped: Option<(f64, OrbitError)>,
    /// Elements of the bar.
    pub elements: usize,
    /// The dofs whose `(q, v)` make the state (`ModePoint::orbit.x`).
    pub state_dofs: Vec<usize>,
}

/// A `[bar]` scene as the shooting of its modes needs it.
pub struct ModeScene {
    /// The exact flow of the bar.
    pub model: Model,
    /// The continuous bar's data (gap, length, wave speed, far end).
    pub bar: ModeBar,
    /// Node coordinates of the scene's unknowns.
    pub nodes: Vec<f64>,
    /// Elements.
    pub elements: usize,
    /// The restitution of the contact (`event-driven(e)`).
    pub restitution: f64,
}

impl ModeScene {
    /// The bar of `doc`: a `[bar]` scene without forcing, body force,
    /// stops or reduction, whose scheme is `event-driven(e)`.
    pub fn new(doc: &toml::Table) -> Result<Self, OrbitError> {
        let file = SceneFile::from_table(doc.clone()).map_err(|e| OrbitError::Scene(e.to_string()))?;
        let scene = file.validate().map_err(|e| OrbitError::Scene(e.to_string()))?;
        let Scene::Bar(b) = &scene else {
            return Err(OrbitError::Option { option: "scene", message: "nonsmooth modes are computed for a [bar] scene (an unforced bar with its gap)".into() });
        };
        let p = &b.problem;
        if !p.forcing.is_empty() || b.omega.is_some() {
            return Err(OrbitError::Option { option: "load", message: "nonsmooth modes are motions of the unforced bar: remove the scene's [load]/[[forcing]]".into() });
        }
        if p.body_force != 0.0 {
            return Err(OrbitError::Option { option: "bar.body_force", message: format!("{} is not allowed: 0 (nonsmooth modes are motions of the unforced bar)", p.body_force) });
        }
        if b.contacts.is_some() || !p.stops.is_empty() {
            return Err(OrbitError::Option { option: "stop", message: "nonsmooth modes are computed with the obstacle at x = 0 (the bar's gap), not [[stop]]/[obstacle]".into() });
        }
        if b.reduce.is_some() {
            return Err(OrbitError::Option { option: "bar.reduce", message: "not allowed for nonsmooth modes: the full bar".into() });
        }
        if p.bar.right_end != signorini_fem::RightEnd::Clamped {
            return Err(OrbitError::Option {
                option: "bar.far_end",
                message: "\"free\" is not allowed: \"clamped\" (with a free far end the obstacle's impulse changes the momentum: no periodic motion has contact, docs/theory.md §11.5)".into(),
            });
        }
        let spec: &SchemeSpec = &b.scheme;
        if spec.family().name != "event-driven" {
            return Err(OrbitError::Option {
                option: "scheme",
                message: format!("{spec} is not allowed: nonsmooth modes are computed on the exact flow; allowed: event-driven(e) (set the scene's scheme = \"event-driven(e)\")"),
            });
        }
        let model = Model::new(p.dynamics(), spec.args()[0])?;
        let bar = ModeBar { length: p.bar.length, wave_speed: p.bar.wave_speed, gap: p.gap, far_end: FarEnd::Clamped };
        let nodes = (0..p.bar.dofs()).map(|i| p.bar.node(i)).collect();
        Ok(Self { model, bar, nodes, elements: p.bar.elements, restitution: spec.args()[0] })
    }

    /// The continuous bar's mode `k = 1` at `energy`, sampled at the nodes
    /// at the top of its flight (t = 0), as a state of the model.
    pub fn exact_state(&self, energy: f64) -> Result<Vec<f64>, OrbitError> {
        let mode = Backbone::new(self.bar, 1).and_then(|b| b.mode(energy)).map_err(|e| OrbitError::Option { option: "energy", message: e.to_string() })?;
        let q: Vec<f64> = self.nodes.iter().map(|&x| mode.fields(x, 0.0).u).collect();
        let v: Vec<f64> = self.nodes.iter().map(|&x| mode.fields(x, 0.0).ut).collect();
        Ok(self.model.pack(&q, &v))
    }

    /// The discrete bar's lowest linear mode at `energy`, at rest with the
    /// contact end at its highest, as a state of the model, and its period
    /// `2π/ω`: the start below the exact threshold, where the continuous
    /// family is a linear motion whose square-wave end velocity the
    /// discrete bar does not carry.
    pub fn linear_state(&self, energy: f64) -> Result<(Vec<f64>, f64), OrbitError> {
        let (omega, shape) = self.model.lowest_mode()?;
        if !(omega > 0.0) {
            return Err(OrbitError::Model("the bar's lowest mode has no frequency".into()));
        }
        let a = (2.0 * energy).sqrt() / omega;
        // The first state dof is the one next to the contact (dof 0 or 1).
        let sign = if shape.first().copied().unwrap_or(1.0) < 0.0 { -1.0 } else { 1.0 };
        let mut x: Vec<f64> = shape.iter().map(|p| sign * a * p).collect();
        x.extend(std::iter::repeat_n(0.0, shape.len()));
        Ok((x, std::f64::consts::TAU / omega))
    }

    /// The continuous bar's backbone point at `energy` (family 1).
    pub fn exact_point(&self, energy: f64) -> Option<BackbonePoint> {
        Backbone::new(self.bar, 1).and_then(|b| b.point(energy)).ok()
    }
}

/// The energies of a backbone: `points` geometric steps from `from` to
/// `to` (linear if `from` is 0). Checked: `from >= 0`, `to >= from`, both
/// finite, `points >= 1` (`points = 1` needs `from = to`).
pub fn energies(from: f64, to: f64, points: usize) -> Result<Vec<f64>, OrbitError> {
    if !(from.is_finite() && from >= 0.0) {
        return Err(OrbitError::Option { option: "from", message: format!("{from} is not allowed: an energy, finite and >= 0") });
    }
    if !(to.is_finite() && to >= from) {
        return Err(OrbitError::Option { option: "to", message: format!("{to} is not allowed: an energy, finite and >= from ({from})") });
    }
    if points == 0 || (points == 1 && to != from) {
        return Err(OrbitError::Option { option: "points", message: format!("{points} is not allowed: >= 2 (1 when from = to)") });
    }
    if points == 1 {
        return Ok(vec![from]);
    }
    let s = |i: usize| i as f64 / (points - 1) as f64;
    Ok((0..points).map(|i| if from > 0.0 { from * (to / from).powf(s(i)) } else { from + (to - from) * s(i) }).collect())
}

/// The backbone of the `[bar]` scene `scene_doc` (an unforced bar, far end
/// clamped, `scheme = "event-driven(e)"`) from the energy `from` to `to`
/// in `points` geometric steps. Bad input: typed errors naming the option
/// or the scene's key. A point where no periodic orbit is found ends the
/// backbone ([`Modes::stopped`]); none at the first energy is an error.
pub fn backbone(scene_doc: &toml::Table, from: f64, to: f64, points: usize) -> Result<Modes, OrbitError> {
    let scene = ModeScene::new(scene_doc)?;
    backbone_of(&scene, &energies(from, to, points)?, &Newton { tol: 1e-11, scale: 1e-300, max_iter: 30, stall: 0 })
}

/// The backbone of `scene` at `energies` (increasing), Newton's settings
/// `newton`.
pub fn backbone_of(scene: &ModeScene, energies: &[f64], newton: &Newton) -> Result<Modes, OrbitError> {
    let model = &scene.model;
    let mut points: Vec<ModePoint> = Vec::new();
    let mut stopped = None;
    for (i, &energy) in energies.iter().enumerate() {
        let (guess, period) = match points.len() {
            0 => match scene.exact_point(energy) {
                // Below the threshold: the discrete bar's first linear mode.
                Some(p) if p.impacts_per_period == 0 && scene.bar.gap < 0.0 => scene.linear_state(energy)?,
                p => (scene.exact_state(energy)?, p.map_or(4.0 * scene.bar.length / scene.bar.wave_speed, |p| p.period)),
            },
            1 => {
                // The homogeneity of the bar without gap, a scaling of the
                // state by √(E/E₀) otherwise as good a start.
                let p = &points[0];
                let s = (energy / p.energy).sqrt();
                (p.orbit.x.iter().map(|x| x * s).collect(), p.period)
            }
            n => {
                let (a, b) = (&points[n - 2], &points[n - 1]);
                let r = (energy - b.energy) / (b.energy - a.energy);
                (b.orbit.x.iter().zip(&a.orbit.x).map(|(xb, xa)| xb + r * (xb - xa)).collect(), b.period + r * (b.period - a.period))
            }
        };
        // A step long beside the last two (the energies' ratio far from
        // 1) extrapolates the state and the period far off (a period
        // below 0): then the last point scaled by √(E/E_b), as for the
        // second point.
        let found = autonomous_orbit(model, &guess, period, energy, newton).or_else(|e| match points.last() {
            Some(b) if points.len() >= 2 => {
                let s = (energy / b.energy).sqrt();
                autonomous_orbit(model, &b.orbit.x.iter().map(|x| x * s).collect::<Vec<_>>(), b.period, energy, newton).map_err(|_| e)
            }
            _ => Err(e),
        });
        match found.map_err(|e| held_for_good(scene, energy, e)) {
            Ok(orbit) => points.push(point(scene, energy, orbit)),
            Err(e) if i == 0 => return Err(e),
            Err(e) => {
                stopped = Some((energy, e));
                break;
            }
        }
    }
    Ok(Modes { points, stopped, elements: scene.elements, state_dofs: model.state_dofs().to_vec() })
}

/// Newton's failure `e` at `energy`, with the reason there is no orbit to
/// find said where the scene gives it: a restitution of 0, a contact node
/// with mass, an energy at which the continuous mode touches the obstacle.
/// Each landing at a speed then takes the node's kinetic energy out of the
/// undamped bar, so a periodic motion can touch only at zero speed: from
/// the mode's start the node lands once and stays held, never released,
/// and no periodic orbit with a flight exists near the mode (theory §11.7;
/// the lumped bar, m = 10, gap 0.1, at E = 0.006 said only that Newton
/// failed).
fn held_for_good(scene: &ModeScene, energy: f64, e: OrbitError) -> OrbitError {
    let touches = scene.exact_point(energy).is_some_and(|p| p.impacts_per_period > 0);
    let massive = scene.model.state_dofs().first() == Some(&0);
    match e {
        OrbitError::NoConvergence { residual, iterations, why } if scene.restitution == 0.0 && touches && massive => OrbitError::NoConvergence {
            residual,
            iterations,
            why: format!(
                "{why}; with restitution 0 there is none to find at E = {energy}: each landing at a speed takes the contact node's kinetic energy out of the undamped bar, so the node lands once and stays held, never released — no periodic orbit with a flight exists near the mode (docs/theory.md §11.7)"
            ),
        },
        e => e,
    }
}

fn point(scene: &ModeScene, energy: f64, orbit: Orbit) -> ModePoint {
    let (contact_time, impacts) = contact_of(&orbit);
    ModePoint { energy, period: orbit.period, contact_time, impacts_per_period: impacts, multipliers: orbit.multipliers.clone(), residual: orbit.residual, exact: scene.exact_point(energy), orbit }
}

/// The time the contact is held over one period of `orbit` (from its
/// events: a landing or an accumulation starts a held phase, a release
/// ends it; a period that starts held is recognised by a release before
/// any landing), and its impacts.
pub fn contact_of(orbit: &Orbit) -> (f64, usize) {
    let (t0, t1) = (orbit.t0, orbit.t0 + orbit.period);
    let mut evs: Vec<_> = orbit.events.iter().filter(|e| e.t >= t0 && e.t <= t1).collect();
    evs.sort_by(|a, b| a.t.total_cmp(&b.t));
    let lands = |k: EventKind, after: f64| k == EventKind::Accumulation || (k == EventKind::Impact && after == 0.0);
    let first_land = evs.iter().position(|e| lands(e.kind, e.velocity_after));
    let first_release = evs.iter().position(|e| e.kind == EventKind::Release);
    let mut held_since = match (first_land, first_release) {
        (_, Some(r)) if first_land.is_none_or(|l| r < l) => Some(t0),
        _ => None,
    };
    let mut total = 0.0;
    for e in &evs {
        if e.kind == EventKind::Release {
            if let Some(s) = held_since.take() {
                total += e.t - s;
            }
        } else if lands(e.kind, e.velocity_after) && held_since.is_none() {
            held_since = Some(e.t);
        }
    }
    if let Some(s) = held_since {
        total += t1 - s;
    }
    (total, orbit.impacts())
}

/// Where the flow from `x0` comes back closest to it: the time `t` in
/// `[(1 − w) T, (1 + w) T]` (`T` = `period`, `w` = `window`) minimising
/// `‖x(t) − x0‖₂ / ‖x0‖₂`, sampled at 200 instants and refined by golden
/// section, with that distance and the contact time and impacts over
/// `(0, t]`. A periodic motion returns at distance 0 (to round-off); a
/// motion that is not periodic says how far from it it is.
pub fn closest_return(model: &Model, x0: &[f64], period: f64, window: f64) -> Result<Return, OrbitError> {
    if !(window > 0.0 && window < 1.0) {
        return Err(OrbitError::Option { option: "window", message: format!("{window} is not allowed: in (0, 1)") });
    }
    let norm = x0.iter().map(|v| v * v).sum::<f64>().sqrt();
    let dist = |x: &[f64]| x.iter().zip(x0).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt() / norm;
    let (a, b) = ((1.0 - window) * period, (1.0 + window) * period);
    let samples = 200;
    let h = (b - a) / samples as f64;
    let mut x = model.flow(0.0, x0, a, false)?.x;
    let mut best = (dist(&x), a);
    for i in 1..=samples {
        x = model.flow(0.0, &x, h, false)?.x;
        let d = dist(&x);
        if d < best.0 {
            best = (d, a + h * i as f64);
        }
    }
    let at = |t: f64| -> Result<f64, OrbitError> { Ok(dist(&model.flow(0.0, x0, t, false)?.x)) };
    let (lo, hi) = ((best.1 - h).max(a), (best.1 + h).min(b));
    let (fc, c) = crate::map::golden_min(lo, hi, 1e-13 * period, at)?;
    let (distance, time) = [(best.0, best.1), (fc, c)].into_iter().min_by(|p, q| p.0.total_cmp(&q.0)).expect("three");
    let img = model.flow(0.0, x0, time, false)?;
    let orbit = Orbit { x: x0.to_vec(), t0: 0.0, period: time, events: img.events, monodromy: faer::Mat::zeros(0, 0), multipliers: Vec::new(), residual: distance, iterations: 0 };
    let (contact_time, impacts) = contact_of(&orbit);
    Ok(Return { time, distance, contact_time, impacts })
}

/// What [`closest_return`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Return {
    /// The time of the closest return.
    pub time: f64,
    /// `‖x(time) − x0‖₂ / ‖x0‖₂`.
    pub distance: f64,
    /// The contact time over `(0, time]`.
    pub contact_time: f64,
    /// Impacts over `(0, time]`.
    pub impacts: usize,
}
