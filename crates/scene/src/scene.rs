//! A validated scene: [`Scene`] and the bar's [`BarRun`].

use crate::ContactSet;
use crate::Ready;
use signorini_reduce::Keep;
use signorini_run::beam::{BeamExcitation, BeamScene, BeamSetup, Pipe};
use signorini_run::oscillator::Oscillator;
use signorini_run::{BarProblem, Benchmark};
use signorini_schemes::SchemeSpec;

/// A validated bar scene.
pub struct BarRun {
    /// The problem.
    pub problem: BarProblem,
    /// The benchmark, if the scene uses one (exact solution available).
    pub benchmark: Option<Benchmark>,
    /// The scheme.
    pub scheme: SchemeSpec,
    /// Time step.
    pub dt: f64,
    /// Horizon.
    pub t_end: f64,
    /// The contacts of `[[stop]]` / `[obstacle]` (`None`: the obstacle at
    /// x = 0); the problem holds them as its stops.
    pub contacts: Option<ContactSet>,
    /// The frequency of a periodic `[load]` (Poincaré section, phases).
    pub omega: Option<f64>,
    /// The reduced model's modes, if `reduce` is given.
    pub reduce: Option<Keep>,
    /// The validated simulation, for the first instantiation.
    pub ready: Ready,
}

/// A validated scene.
// One scene per run or sweep value: the size of the beam's variant does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Scene {
    /// A bar.
    Bar(Box<BarRun>),
    /// The one-degree-of-freedom impact oscillator.
    Oscillator {
        /// Its data (load included).
        osc: Oscillator,
        /// The scheme.
        scheme: SchemeSpec,
        /// Time step.
        dt: f64,
        /// Horizon.
        t_end: f64,
        /// The forcing frequency (Poincaré section, impact phases).
        omega: Option<f64>,
        /// The validated simulation, for the first instantiation.
        ready: Ready,
    },
    /// A beam between stops.
    Beam {
        /// The pipe.
        pipe: Pipe,
        /// The run.
        scene: BeamScene,
        /// Forced beyond the stability limit.
        force: bool,
        /// The contacts of `[[stop]]` / `[obstacle]` (`None`: the tip's
        /// two stops).
        contacts: Option<ContactSet>,
        /// `[support]` beyond a sine, `[load]`.
        excitation: BeamExcitation,
        /// The reduced model's modes, if `reduce` is given.
        reduce: Option<Keep>,
        /// The forcing frequency (the support's, or `omega` of `[support]` /
        /// `[load]`): Poincaré section and impact phases.
        omega: Option<f64>,
        /// The validated simulation, for the first instantiation.
        ready: Ready,
    },
}

impl Scene {
    /// A beam scene's [`BeamSetup`] (pipe, run, contacts, excitation, force,
    /// reduction): what every front end builds the beam from; `None` for
    /// other scenes.
    pub fn beam_setup(&self) -> Option<BeamSetup> {
        let Scene::Beam { pipe, scene, force, contacts, excitation, reduce, .. } = self else { return None };
        let mut s = BeamSetup::new(*pipe, *scene).with_excitation(excitation.clone()).forced(*force);
        s.stops = contacts.as_ref().map(|c| c.stops.clone());
        s.reduce = *reduce;
        Some(s)
    }
}

impl Scene {
    /// The forcing frequency `Ω` (`None` without a periodic forcing) and
    /// the horizon `t_end`.
    pub fn forcing_and_horizon(&self) -> (Option<f64>, f64) {
        let f = self.facts();
        (f.omega, f.t_end)
    }

    /// What a sweep needs of the scene's clock: the forcing frequency `Ω`
    /// (the Poincaré section and impact phases), the time step, and the key
    /// of its horizon (which a sweep sets to `transient + record` forcing
    /// periods). `None` without a periodic forcing.
    pub fn sweep_clock(&self) -> Option<(f64, f64, &'static str)> {
        let f = self.facts();
        f.omega.map(|w| (w, f.dt, f.t_end_key))
    }
}
