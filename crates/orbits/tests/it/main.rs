//! signorini-orbits' integration tests (one binary, one module per concern).
mod autonomous;
mod basins;
mod basins_branch;
mod basins_stop;
mod beam;
mod between;
mod bubble;
mod cascade;
mod chain;
mod chatter;
mod conservative;
mod corrector;
mod floor;
mod free_grazing;
mod further_impact;
mod graze_approach;
mod isola;
mod marks;
mod mirror;
mod nonsmooth_fold;
mod oscillator;
mod param_derivative;
mod period_two;
mod reach;
mod readings;
mod rebuilt;
mod reuse;
mod scale;
mod section;
mod shared;
mod shifted_copy;
mod slow_impact;
mod start;
mod store;
mod switch;
mod symmetric;
mod turn;
mod turned_back;
mod two_stops;

use signorini_orbits::{Bifurcation, Branch, ContinuationOptions, Family, Marker, Model, OrbitError};

/// Every family of these tests (a dozen types: scenes, transcribed maps,
/// counting wrappers) reaches the continuation through this one type, so
/// that this crate compiles the continuation's generic code once, not once
/// per family (13 copies: 57 CPU-s to compile this crate). Each method
/// is the family's own, the defaults it overrides included.
struct AnyFamily<'a>(&'a dyn Family);

impl Family for AnyFamily<'_> {
    fn model(&self, param: f64) -> Result<Model, OrbitError> {
        self.0.model(param)
    }

    fn period(&self, param: f64) -> Result<f64, OrbitError> {
        self.0.period(param)
    }

    fn model_and_period(&self, param: f64) -> Result<(Model, f64), OrbitError> {
        self.0.model_and_period(param)
    }

    fn model_period_marker(&self, param: f64) -> Result<(Model, f64, Option<Marker>), OrbitError> {
        self.0.model_period_marker(param)
    }

    fn periods(&self) -> usize {
        self.0.periods()
    }
}

/// [`signorini_orbits::continuation`] through [`AnyFamily`].
pub fn continuation(family: &dyn Family, guess: &[f64], opts: &ContinuationOptions) -> Result<Branch, OrbitError> {
    signorini_orbits::continuation(&AnyFamily(family), guess, opts)
}

/// [`signorini_orbits::doubled_branch`] through [`AnyFamily`].
pub fn doubled_branch(single: &dyn Family, double: &dyn Family, bif: &Bifurcation, range: (f64, f64), opts: &ContinuationOptions) -> Result<Branch, OrbitError> {
    signorini_orbits::doubled_branch(&AnyFamily(single), &AnyFamily(double), bif, range, opts)
}

/// [`signorini_orbits::crossing_branch`] through [`AnyFamily`].
pub fn crossing_branch(family: &dyn Family, parent: &Branch, bif: &Bifurcation, range: (f64, f64), opts: &ContinuationOptions) -> Result<Branch, OrbitError> {
    signorini_orbits::crossing_branch(&AnyFamily(family), parent, bif, range, opts)
}

/// The impact oscillator most modules trace: `x'' + 2ζx' + x = sin Ωt`
/// against one stop at `stop` (mass, stiffness and forcing amplitude 1),
/// run event-driven with restitution `e`, as a scene's TOML table.
pub fn oscillator(zeta: f64, stop: f64, e: f64, omega: f64) -> toml::Table {
    let text = format!(
        "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = {zeta:?}\nstop = {stop:?}\nrestitution = {e:?}\n\
         dt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = {omega:?}\n"
    );
    text.parse().expect("the oscillator's scene text")
}
