//! A scene document as a family of models in one of its numeric keys (the
//! dotted paths of `signorini sweep --param`).

use crate::continuation::Family;
use crate::map::{Model, Shared};
use crate::OrbitError;
use signorini_scene::{Lift, Limits, Scene, SceneFile, Simulation};
use signorini_schemes::events::{EventDriven, FlowBases};
use signorini_schemes::{Dynamics, SchemeSpec};
use std::sync::{Arc, Mutex};

/// A scene in a parameter: its document, the parameter's dotted path, and
/// the orbit's period in forcing periods.
#[derive(Clone)]
pub struct SceneFamily {
    doc: toml::Table,
    path: String,
    periods: usize,
    limits: Limits,
    interrupt: Option<signorini_schemes::Interrupt>,
    /// What the models built so far share ([`Shared`]: the linearisation's
    /// core and the flows' bases, each eigen-decomposition computed once):
    /// a model whose structure is the last one's (the same matrices and
    /// contact dofs, bit for bit: a parameter that moves only a load, a
    /// bound, a restitution or the start) is built on it; another
    /// structure (a stiffness, a mass) starts a new one. The clones of the
    /// family (its period-doubled families, a basin's threads) share it.
    shared: Arc<Mutex<Option<Shared>>>,
    /// The last models built for a model alone ([`SceneFamily::model_only`]:
    /// a map's image, `G_λ`'s shifted run, a margin): their parameter's
    /// bits, dynamics, restitution, forcing frequency and tip. A value built again (a
    /// converged point's margins and grazing searches at its own
    /// parameter) is a model of the same structure, not a scene parsed,
    /// validated and instantiated again.
    memo: Arc<Mutex<Vec<Memo>>>,
}

/// A model built for a parameter value ([`SceneFamily::memo`]).
#[derive(Clone)]
struct Memo {
    param: u64,
    dy: Dynamics,
    e: f64,
    /// The forcing frequency (the horizon is the family's periods of it:
    /// a period-doubled family shares the memo).
    omega: f64,
    /// The tip dof (the oscillator's, a bar's contact end).
    tip: usize,
}

/// The most models [`SceneFamily::memo`] keeps.
const MEMO: usize = 4;

impl std::fmt::Debug for SceneFamily {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SceneFamily({} in {} periods)", self.path, self.periods)
    }
}

/// One scene of the family, built: its model, the map's horizon, and the
/// scene's own start state (as a state of the model).
pub struct Built {
    /// The model.
    pub model: Model,
    /// The map's horizon: `periods` forcing periods (s).
    pub horizon: f64,
    /// The scene's initial state.
    pub start: Vec<f64>,
    /// The forcing frequency Ω (rad/s).
    pub omega: f64,
    tip: Tip,
}

/// What the tip's displacement needs of a built scene's simulation (its
/// stepper's run went to the model).
struct Tip {
    tip: usize,
    lift: Option<Lift>,
    reduction: Option<signorini_reduce::Reduction>,
}

impl Built {
    /// The tip's absolute displacement (the scene's tip dof: the
    /// oscillator's, the beam's tip, a bar's contact end) in the state `x`
    /// at the section (t = 0): the quantity a sweep's bifurcation diagram
    /// shows. A reduced model's state is reconstructed, a beam's lifted.
    pub fn tip(&self, x: &[f64]) -> Result<f64, OrbitError> {
        tip(&self.model, &self.tip, x)
    }
}

/// The tip's displacement on the section of the orbit through `x` of
/// `model`, the model of the scene `sim` was built from.
fn tip(model: &Model, sim: &Tip, x: &[f64]) -> Result<f64, OrbitError> {
    let (q, v) = model.settle(0.0, x)?;
    let (q, v) = match &sim.reduction {
        None => (q, v),
        Some(r) => {
            let (mut qf, mut vf) = (vec![0.0; r.parent_dofs()], vec![0.0; r.parent_dofs()]);
            r.reconstruct(&q, &mut qf);
            r.reconstruct(&v, &mut vf);
            (qf, vf)
        }
    };
    // As `Simulation::absolute` at t = 0.
    let q = match &sim.lift {
        None => q,
        Some(l) => l.absolute(&q, &v, 0.0).0,
    };
    Ok(q[sim.tip])
}

impl SceneFamily {
    /// The family of `doc` in `path`, for orbits of `periods` forcing
    /// periods. The path must name a number of the scene (checked here at
    /// its own value); the scene's scheme must be the exact event-driven
    /// reference, and it must have a periodic forcing.
    pub fn new(doc: toml::Table, path: &str, periods: usize) -> Result<(Self, f64), OrbitError> {
        Self::with_limits(doc, path, periods, Limits::machine())
    }

    /// [`SceneFamily::new`] within `limits` (a front end's `--max-memory`).
    pub fn with_limits(doc: toml::Table, path: &str, periods: usize, limits: Limits) -> Result<(Self, f64), OrbitError> {
        if periods == 0 {
            return Err(OrbitError::Option { option: "period", message: "0 is not allowed: forcing periods per orbit, an integer >= 1".into() });
        }
        let value = lookup(&doc, path)?;
        let family = Self { doc, path: path.to_string(), periods, limits, interrupt: None, shared: Arc::default(), memo: Arc::default() };
        family.build(value)?;
        Ok((family, value))
    }

    /// The same scene and parameter for orbits of `periods` forcing periods
    /// (a period-doubled branch's family).
    pub fn with_periods(&self, periods: usize) -> Self {
        Self { periods: periods.max(1), ..self.clone() }
    }

    /// Every model built with the poll `interrupt` ([`Model::with_interrupt`]).
    pub fn with_interrupt(mut self, interrupt: Option<signorini_schemes::Interrupt>) -> Self {
        self.interrupt = interrupt;
        self
    }

    /// Forcing periods per orbit.
    pub fn periods(&self) -> usize {
        self.periods
    }

    /// The scene at `param`, built.
    pub fn build(&self, param: f64) -> Result<Built, OrbitError> {
        self.build_with(&[("param", &self.path, param)])
    }

    /// The model, horizon, forcing frequency and tip at `param`, as
    /// [`SceneFamily::build`] makes them (the same model, bit for bit),
    /// without the start state and without the scene's own
    /// validated run where the model does not need it: once the family
    /// knows its structure (the first build), an oscillator's or an
    /// unreduced bar's scene at another value is parsed and validated (its
    /// refusals are the same: an invalid value is refused as by `build`),
    /// and its model made from the dynamics the scene defines on the
    /// family's structure, its first flow's run made by the model itself
    /// (`EventDriven::restart` of the scene's run and a new run from the
    /// same state are the same run). A value among the last [`MEMO`] built
    /// this way is not parsed again. Another structure, a reduced bar, a
    /// beam (whose lifting the instantiation builds with its run), or a
    /// scheme other than the exact one: [`SceneFamily::build`].
    fn model_only(&self, param: f64) -> Result<(Model, f64, f64, Tip), OrbitError> {
        let full = |b: Built| (b.model, b.horizon, b.omega, b.tip);
        let shared = self.shared.lock().ok().and_then(|s| s.clone());
        let Some(shared) = shared else {
            return self.build(param).map(full);
        };
        // A value kept is taken where its structure is the store's (a
        // parameter that changes the structure moves the store on).
        let hit = self.memo.lock().ok().and_then(|m| m.iter().find(|m| m.param == param.to_bits()).cloned()).filter(|m| shared.bases().fits(&m.dy));
        let memo = match hit {
            Some(m) => m,
            None => {
                let mut doc = self.doc.clone();
                signorini_sweep::set_path(&mut doc, &self.path, param).map_err(|e| OrbitError::Option { option: "param", message: e.to_string() })?;
                let at = |e: String| OrbitError::Scene(format!("{} = {param}: {e}", self.path));
                let file = SceneFile::from_table(doc).map_err(|e| at(e.to_string()))?;
                let scene = file.validate_clock(&self.limits).map_err(|e| at(e.to_string()))?;
                // As `Scene::instantiate` builds them: the same dynamics,
                // the same tip.
                let direct = match &scene {
                    Scene::Oscillator { osc, scheme, .. } => Some((osc.dynamics().map_err(|e| at(e.to_string()))?.0, scheme)),
                    Scene::Bar(b) if b.reduce.is_none() => Some((b.problem.dynamics(), &b.scheme)),
                    _ => None,
                };
                let (Some((dy, scheme)), Some((omega, _, _))) = (direct, scene.sweep_clock()) else {
                    return self.build(param).map(full);
                };
                let Some(tip) = dy.contacts.first().map(|c| c.dof) else {
                    return self.build(param).map(full);
                };
                if scheme.family().name != "event-driven" || !shared.bases().fits(&dy) {
                    return self.build(param).map(full);
                }
                let m = Memo { param: param.to_bits(), dy, e: scheme.args()[0], omega, tip };
                if let Ok(mut memo) = self.memo.lock() {
                    if memo.len() == MEMO {
                        memo.remove(0);
                    }
                    memo.push(m.clone());
                }
                m
            }
        };
        let model = Model::new_shared(memo.dy, memo.e, Some(&shared), None, None)?.with_interrupt(self.interrupt.clone());
        let horizon = self.periods as f64 * std::f64::consts::TAU / memo.omega;
        Ok((model, horizon, memo.omega, Tip { tip: memo.tip, lift: None, reduction: None }))
    }

    /// The scene with each `(option, path, value)` of `sets` set, built
    /// (an option names the flag whose path it is, for errors).
    pub(crate) fn build_with(&self, sets: &[(&'static str, &str, f64)]) -> Result<Built, OrbitError> {
        let mut doc = self.doc.clone();
        for (option, path, value) in sets {
            signorini_sweep::set_path(&mut doc, path, *value).map_err(|e| OrbitError::Option { option, message: e.to_string() })?;
        }
        let at = |e: String| OrbitError::Scene(format!("{}: {e}", sets.iter().map(|(_, p, v)| format!("{p} = {v}")).collect::<Vec<_>>().join(", ")));
        let file = SceneFile::from_table(doc).map_err(|e| at(e.to_string()))?;
        let scene = file.validate_clock(&self.limits).map_err(|e| at(e.to_string()))?;
        let Some((omega, _, _)) = scene.sweep_clock() else {
            return Err(OrbitError::Option { option: "scene", message: "periodic orbits of the forcing period need a periodic forcing (an oscillator's [forcing], a beam's support or load, a bar's [[forcing]]); an unforced bar's periodic motions are its nonsmooth modes (signorini modes)".into() });
        };
        // The scene's validated run builds its flows' bases through the
        // family's store (lent: the store of the structure built last; a
        // new structure's run starts its own, found in `lent` after).
        let shared = self.shared.lock().ok().and_then(|s| s.clone());
        let mut lent = shared.as_ref().map(Shared::bases);
        let sim = FlowBases::lend(&mut lent, || scene.instantiate(None));
        let Simulation { stepper, u0, v0, tip, lift, reduction } = sim.map_err(|e| at(e.to_string()))?;
        let label = stepper.label();
        let spec: SchemeSpec = label.parse().map_err(|_| at(format!("scheme {label}: not a registry scheme")))?;
        if spec.family().name != "event-driven" {
            return Err(OrbitError::Option {
                option: "scheme",
                message: format!("{label} is not allowed: periodic orbits are computed on the exact flow; allowed: event-driven(e) (set the scene's scheme = \"event-driven(e)\")"),
            });
        }
        // The scene's validated run (event-driven(e) of its dynamics from
        // its start) is the model's first: no second set-up of the same run.
        let dy = stepper.dynamics().clone();
        let first = stepper.into_event_run().and_then(|run| run.downcast::<EventDriven>().ok()).map(|run| *run);
        // The run kept the family's store only if it is its structure
        // (checked there, `FlowBases::fits`): the same store, the same
        // structure, not compared again.
        let shared = shared.filter(|s| lent.as_ref().is_some_and(|l| Arc::ptr_eq(l, &s.bases())));
        let fits = shared.is_some();
        let model = Model::new_shared(dy, spec.args()[0], shared.as_ref(), lent, first)?.with_interrupt(self.interrupt.clone());
        if !fits {
            if let Ok(mut s) = self.shared.lock() {
                *s = Some(model.shared());
            }
        }
        let start = model.pack(&u0, &v0);
        Ok(Built { model, horizon: self.periods as f64 * std::f64::consts::TAU / omega, start, omega, tip: Tip { tip, lift, reduction } })
    }
}

impl Family for SceneFamily {
    fn model(&self, param: f64) -> Result<Model, OrbitError> {
        Ok(self.model_only(param)?.0)
    }

    fn period(&self, param: f64) -> Result<f64, OrbitError> {
        Ok(self.model_only(param)?.1)
    }

    fn model_and_period(&self, param: f64) -> Result<(Model, f64), OrbitError> {
        let (model, horizon, ..) = self.model_only(param)?;
        Ok((model, horizon))
    }

    fn periods(&self) -> usize {
        self.periods
    }

    /// Each point marked with its scene's Ω and tip ([`Built::tip`]), from
    /// the scene built for its model (without a second build).
    fn model_period_marker(&self, param: f64) -> Result<(Model, f64, Option<crate::continuation::Marker>), OrbitError> {
        let (model, horizon, omega, at) = self.model_only(param)?;
        let marker: crate::continuation::Marker = Box::new(move |model, x| tip(model, &at, x).ok().map(|tip| crate::continuation::Mark { omega, tip }));
        Ok((model, horizon, Some(marker)))
    }
}

/// The number at `path` in `doc` (a missing key: the scene's default is
/// not known here, so the path must be written in the scene).
fn lookup(doc: &toml::Table, path: &str) -> Result<f64, OrbitError> {
    lookup_as(doc, path, "param")
}

/// [`lookup`] for the option `option`.
pub(crate) fn lookup_as(doc: &toml::Table, path: &str, option: &'static str) -> Result<f64, OrbitError> {
    let err = |m: String| OrbitError::Option { option, message: format!("{path}: {m}") };
    let cur = signorini_scene::presets::get_path(doc, path).ok_or_else(|| err("is not in the scene (write the key in the scene file with its start value)".into()))?;
    match cur {
        toml::Value::Float(x) => Ok(*x),
        toml::Value::Integer(i) => Ok(*i as f64),
        other => Err(err(format!("is a {}, not a number", other.type_str()))),
    }
}
