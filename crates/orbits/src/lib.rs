//! Periodic motions of signorini's models on the exact event-driven flow
//! (docs/theory.md §12): the flow map and its Jacobian from the
//! variational equations with a saltation matrix at each impact
//! ([`Model`]), periodic orbits by shooting with their Floquet multipliers
//! ([`periodic_orbit`], [`autonomous_orbit`]), and pseudo-arclength
//! continuation in a scene parameter with its bifurcations
//! ([`continuation`]), the nonsmooth modes of the bar, continued in the
//! energy ([`modes::backbone`]), and basins of attraction on a grid of
//! initial states ([`basins`]).
//!
//! The numerical parts do no IO; the scene side ([`SceneFamily`]) builds a
//! [`Model`] from a scene document at each parameter value, the way
//! `signorini sweep` does.

pub mod basins;
mod continuation;
pub mod front;
mod map;
pub mod modes;
pub mod output;
mod scene;
mod shoot;
mod variational;

pub use continuation::{continuation, continuation_watched, crossing_branch, doubled_branch, Bifurcation, BifurcationKind, Branch, BranchPoint, ContinuationOptions, Family, Mark, Marker};
#[doc(hidden)]
pub use continuation::{corrected, param_derivative};
pub use map::{Image, Model};
pub use scene::{Built, SceneFamily};
pub use shoot::{autonomous_orbit, eigenvalues, periodic_orbit, Newton, Orbit};

/// Why an orbit or a branch could not be computed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OrbitError {
    /// The exact run failed.
    #[error("the exact run: {0}")]
    Events(signorini_schemes::events::EventsError),
    /// Interrupted (a front end's SIGINT, Python's Ctrl-C).
    #[error("interrupted")]
    Interrupted,
    /// The model has no linearisation here.
    #[error("{0}")]
    Model(String),
    /// A state of the wrong size.
    #[error("a state of {given} unknowns for a model of {expected}")]
    Size {
        /// Given.
        given: usize,
        /// The model's.
        expected: usize,
    },
    /// The flow has no derivative at an event of the orbit.
    #[error("no derivative at t = {t}: {why}")]
    NoDerivative {
        /// The event's time.
        t: f64,
        /// What happened there.
        why: String,
    },
    /// Newton did not converge.
    #[error("Newton did not converge: residual {residual:e} after {iterations} iterations ({why})")]
    NoConvergence {
        /// `‖P(x) − x‖∞` at the last iterate.
        residual: f64,
        /// Iterations taken.
        iterations: usize,
        /// Why, in words.
        why: String,
    },
    /// No branch starts beside a bifurcation: what its guesses came to.
    #[error("{0}")]
    NoBranch(String),
    /// An option's value is not allowed.
    #[error("{option}: {message}")]
    Option {
        /// The option (a CLI flag or Python keyword's name).
        option: &'static str,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The scene at a parameter value.
    #[error("{0}")]
    Scene(String),
    /// More events in one evaluation of the map than the model allows
    /// ([`Model::with_max_events`], [`MAX_EVENTS_PER_MAP`] by default): the
    /// exact run's own limit, a scheme parameter, does not act here.
    #[error("{events} events by t = {t} within one evaluation of the map, more than the orbit layer allows there (10⁶ unless the model sets another limit): the motion chatters without end there, or the state is far from a periodic orbit")]
    TooManyEvents {
        /// Where the run stopped.
        t: f64,
        /// Events taken.
        events: usize,
    },
}

/// The most events one evaluation of the map may take, unless
/// [`Model::with_max_events`] says otherwise.
pub const MAX_EVENTS_PER_MAP: usize = 1_000_000;

impl From<signorini_schemes::events::EventsError> for OrbitError {
    fn from(e: signorini_schemes::events::EventsError) -> Self {
        match e {
            signorini_schemes::events::EventsError::Interrupted { .. } => OrbitError::Interrupted,
            // Every exact run of this crate runs under the model's limit;
            // the run's own message would point at a scheme parameter.
            signorini_schemes::events::EventsError::TooManyEvents { t, events } => OrbitError::TooManyEvents { t, events },
            other => OrbitError::Events(other),
        }
    }
}
