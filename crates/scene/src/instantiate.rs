//! One way to build a simulation from a validated scene, for every front
//! end (`signorini run`, sweeps, the studies, Python): [`Scene::instantiate`].

use crate::Scene;
use signorini_run::beam::{BeamExcitation, Pipe};
use signorini_run::reduced::{Need, Reconstruct};
use signorini_run::{Observer, RunConfig, RunError, RunSummary};
use signorini_schemes::{Bounds, Initial, Stepper};

/// Why a validated scene could not be instantiated.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    /// The scene (a field's value) is invalid.
    #[error(transparent)]
    Scene(#[from] crate::SceneError),
    /// Building the problem or its integrator failed.
    #[error(transparent)]
    Run(#[from] RunError),
    /// A start state whose size is not the scene's.
    #[error("a start state of {given} unknowns for a scene of {expected}")]
    StartState {
        /// Unknowns of the state given.
        given: usize,
        /// Unknowns of the scene.
        expected: usize,
    },
}

impl From<signorini_schemes::SchemeError> for BuildError {
    fn from(e: signorini_schemes::SchemeError) -> Self {
        BuildError::Run(RunError::from(e))
    }
}

/// A scene's integrator, ready to run: the stepper, its initial
/// displacement, the dof read as "the tip" (the oscillator's dof, the
/// beam's tip, the bar's contact end — contact 0), and how its unknowns
/// map to the scene's (a reduced model's basis, a beam's lifting).
pub struct Simulation {
    /// The integrator.
    pub stepper: Box<dyn Stepper>,
    /// `U⁰` (in the stepper's unknowns: reduced coordinates for a reduced model).
    pub u0: Vec<f64>,
    /// `V⁰` (in the stepper's unknowns).
    pub v0: Vec<f64>,
    /// The tip dof (of the scene's unknowns).
    pub tip: usize,
    /// The beam's lifting `u = ũ − h φ(t)` (`None`: the unknowns are the
    /// absolute state).
    pub lift: Option<Lift>,
    /// A reduced model's basis (`reduce = {…}`): the stepper's unknowns are
    /// then reduced coordinates, and the scene's unknowns (which `tip`,
    /// [`Simulation::contacts`] and `lift` refer to) are their
    /// reconstruction (`signorini_run::reduced::Reconstruct`).
    pub reduction: Option<signorini_reduce::Reduction>,
}

/// A validated scene's simulation, kept for the scene's first
/// [`Scene::instantiate`] from its own initial state: validation builds the
/// integrator to check it (what `check` refuses, `run` refuses), and that
/// build is the run's — `signorini run`, Python and every sweep run pay the
/// set-up once. Later instantiations build anew; a cloned scene starts
/// without one.
#[derive(Default)]
pub struct Ready(std::sync::Mutex<Option<Simulation>>);

impl Clone for Ready {
    fn clone(&self) -> Self {
        Ready::default()
    }
}

impl std::fmt::Debug for Ready {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Ready")
    }
}

impl Ready {
    /// Keeps `sim` for the first instantiation.
    pub(crate) fn keep(sim: Simulation) -> Self {
        Ready(std::sync::Mutex::new(Some(sim)))
    }

    fn take(&self) -> Option<Simulation> {
        self.0.lock().ok().and_then(|mut s| s.take())
    }
}

/// A beam's built integrator as a [`Simulation`] (one conversion for
/// validation and [`Scene::instantiate`]).
pub(crate) fn beam_simulation(built: signorini_run::beam::BuiltBeam, pipe: Pipe, exc: BeamExcitation) -> Simulation {
    let tip = built.beam.tip_dof();
    let (u0, v0, reduction) = match built.reduced {
        None => (built.initial.u, built.initial.v, None),
        Some(r) => (r.initial.u, r.initial.v, Some(r.reduction)),
    };
    Simulation { stepper: built.stepper, u0, v0, tip, lift: Some(Lift { pipe, beam: built.beam, exc }), reduction }
}

/// A beam's lifting, to turn its unknowns into the absolute state.
pub struct Lift {
    pipe: Pipe,
    beam: signorini_fem::Beam,
    exc: BeamExcitation,
}

/// What an observer reads of the scene's unknowns: a reduced model
/// reconstructs only that for it ([`Simulation::run`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reads {
    /// The contact dofs and the tip.
    Contacts,
    /// Every unknown (norms, snapshots, fields, a followed state).
    Full,
    /// Nothing of the state (a progress bar).
    Nothing,
}

impl Simulation {
    /// The number of the scene's unknowns (a reduced model's parent's).
    pub fn unknowns(&self) -> usize {
        self.reduction.as_ref().map_or(self.u0.len(), signorini_reduce::Reduction::parent_dofs)
    }

    /// Runs the time loop with `observers`, each fed the scene's unknowns
    /// it reads: as stepped, or for a reduced model reconstructed (only the
    /// contact and tip rows for [`Reads::Contacts`]). Every front end runs a
    /// scene this way.
    pub fn run(&mut self, cfg: &RunConfig, observers: Vec<(Reads, &mut dyn Observer)>) -> Result<RunSummary, RunError> {
        let rows: Vec<usize> = self.contacts().iter().map(|c| c.0).chain(std::iter::once(self.tip)).collect();
        let Some(r) = &self.reduction else {
            let mut obs: Vec<&mut dyn Observer> = observers.into_iter().map(|o| o.1).collect();
            return signorini_run::run(self.stepper.as_mut(), &self.u0, cfg, &mut obs);
        };
        let mut wrapped: Vec<Result<Reconstruct<'_>, &mut dyn Observer>> = observers
            .into_iter()
            .map(|(reads, o)| match reads {
                Reads::Contacts => Ok(Reconstruct::new(r, o, Need::Dofs(rows.clone()))),
                Reads::Full => Ok(Reconstruct::new(r, o, Need::Full)),
                Reads::Nothing => Err(o),
            })
            .collect();
        let mut obs: Vec<&mut dyn Observer> = wrapped
            .iter_mut()
            .map(|w| match w {
                Ok(rc) => rc as &mut dyn Observer,
                Err(o) => &mut **o,
            })
            .collect();
        signorini_run::run(self.stepper.as_mut(), &self.u0, cfg, &mut obs)
    }

    /// The contacts as dof of the scene's unknowns and bounds, in contact
    /// order (a reduced model's stepper holds them at its dofs `0..nb`).
    pub fn contacts(&self) -> Vec<(usize, Bounds)> {
        let own = &self.stepper.dynamics().contacts;
        match &self.reduction {
            None => own.iter().map(|c| (c.dof, c.bounds)).collect(),
            Some(r) => r.contacts().iter().zip(own).map(|(&dof, c)| (dof, c.bounds)).collect(),
        }
    }

    /// The absolute state `(ũ, ũ_t)` of the scene's unknowns `(u, u_t)` at
    /// `t` (what [`Scene::instantiate`] takes as `start`).
    pub fn absolute(&self, u: &[f64], v: &[f64], t: f64) -> (Vec<f64>, Vec<f64>) {
        match &self.lift {
            None => (u.to_vec(), v.to_vec()),
            Some(l) => l.absolute(u, v, t),
        }
    }
}

impl Lift {
    /// The absolute state `(ũ, ũ_t)` of the beam's unknowns `(u, u_t)` at
    /// `t` ([`Simulation::absolute`] of a beam, without its stepper).
    pub fn absolute(&self, u: &[f64], v: &[f64], t: f64) -> (Vec<f64>, Vec<f64>) {
        self.pipe.absolute_state(&self.beam, &self.exc, u, v, t)
    }
}

impl Scene {
    /// Builds the scene's simulation, from the scene's own initial state or
    /// from `start`, an absolute displacement and velocity at the scene's
    /// unknowns (e.g. the last run's final state in a followed sweep, from
    /// [`Simulation::absolute`]). A reduced model (`reduce = {…}`) steps the
    /// reduction of the scene's problem (`start`, if given, projected onto
    /// it), with [`Simulation::reduction`] set: every front end runs it the
    /// same way, reconstructing the scene's unknowns for its observers.
    pub fn instantiate(&self, start: Option<&(Vec<f64>, Vec<f64>)>) -> Result<Simulation, BuildError> {
        if start.is_none() {
            let ready = match self {
                Scene::Bar(b) => &b.ready,
                Scene::Oscillator { ready, .. } | Scene::Beam { ready, .. } => ready,
            };
            if let Some(sim) = ready.take() {
                return Ok(sim);
            }
        }
        let init = |own: Initial| -> Result<Initial, BuildError> {
            match start {
                None => Ok(own),
                Some((u, v)) if u.len() == own.u.len() && v.len() == own.v.len() => Ok(Initial { u: u.clone(), v: v.clone() }),
                Some((u, _)) => Err(BuildError::StartState { given: u.len(), expected: own.u.len() }),
            }
        };
        match self {
            Scene::Oscillator { osc, scheme, dt, .. } => {
                let (dy, own) = osc.dynamics()?;
                let i = init(own)?;
                let stepper = scheme.build(dy, *dt, &i)?;
                Ok(Simulation { stepper, u0: i.u, v0: i.v, tip: 0, lift: None, reduction: None })
            }
            Scene::Bar(b) => {
                let p = &b.problem;
                let i = init(p.initial.clone())?;
                let dy = p.dynamics();
                let tip = dy.contacts[0].dof;
                match b.reduce {
                    None => {
                        let stepper = b.scheme.build(dy, b.dt, &i)?;
                        Ok(Simulation { stepper, u0: i.u, v0: i.v, tip, lift: None, reduction: None })
                    }
                    Some(keep) => {
                        let r = signorini_run::reduced::reduce(&dy, &i, keep)?;
                        let stepper = b.scheme.build(r.dynamics.clone(), b.dt, &r.initial)?;
                        Ok(Simulation { stepper, u0: r.initial.u, v0: r.initial.v, tip, lift: None, reduction: Some(r.reduction) })
                    }
                }
            }
            Scene::Beam { pipe, excitation, .. } => {
                // `start` is the absolute state (ũ, ũ_t): the lifting is the scene's own.
                let exc = BeamExcitation { start: start.cloned(), ..excitation.clone() };
                let setup = self.beam_setup().expect("a beam scene").with_excitation(exc.clone());
                Ok(beam_simulation(setup.build()?, *pipe, exc))
            }
        }
    }
}
