//! One way to build a simulation from a validated scene, for every front
//! end (`signorini run`, sweeps, the studies, Python): [`Scene::instantiate`].

use crate::Scene;
use signorini_run::beam::{build_excited, BeamExcitation, PenaltyUnits, Pipe};
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
            Some(l) => l.pipe.absolute_state(&l.beam, &l.exc, u, v, t),
        }
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
                Ok(Simulation { stepper, u0: i.u, tip: 0, lift: None, reduction: None })
            }
            Scene::Bar(b) => {
                let p = &b.problem;
                let i = init(p.initial.clone())?;
                let dy = p.dynamics();
                let tip = dy.contacts[0].dof;
                match b.reduce {
                    None => {
                        let stepper = b.scheme.build(dy, b.dt, &i)?;
                        Ok(Simulation { stepper, u0: i.u, tip, lift: None, reduction: None })
                    }
                    Some(keep) => {
                        let r = signorini_run::reduced::reduce(&dy, &i, keep)?;
                        let stepper = b.scheme.build(r.dynamics.clone(), b.dt, &r.initial)?;
                        Ok(Simulation { stepper, u0: r.initial.u, tip, lift: None, reduction: Some(r.reduction) })
                    }
                }
            }
            Scene::Beam { pipe, scene, force, contacts, excitation, reduce, .. } => {
                // `start` is the absolute state (ũ, ũ_t): the lifting is the scene's own.
                let exc = BeamExcitation { start: start.cloned(), ..excitation.clone() };
                let stops = contacts.as_ref().map(|c| c.stops.as_slice());
                let (stepper, u0, beam, reduction) = match reduce {
                    None => {
                        let (stepper, i, beam) = build_excited(pipe, scene, *force, PenaltyUnits::NewtonPerMetre, stops, &exc)?;
                        (stepper, i.u, beam, None)
                    }
                    Some(keep) => {
                        let (stepper, r, beam) = signorini_run::beam::build_reduced(pipe, scene, PenaltyUnits::NewtonPerMetre, stops, &exc, *keep)?;
                        (stepper, r.initial.u, beam, Some(r.reduction))
                    }
                };
                let tip = beam.tip_dof();
                Ok(Simulation { stepper, u0, tip, lift: Some(Lift { pipe: *pipe, beam, exc }), reduction })
            }
        }
    }
}
