//! Validation of a scene file: the `[output]` table, the choice of
//! table, and what every kind shares (the horizon, a scheme's error).

use crate::excitation::Table;
use crate::{field, validate_bar, validate_beam, Limits, OutputToml, Scene, SceneError, SceneFile, DEFAULT_ENERGY_WARN};
use signorini_run::{RunConfig, RunError};
use signorini_schemes::SchemeError;

impl OutputToml {
    /// Where the record window starts (s): the `transient` is in forcing
    /// periods of `omega`, in seconds without a forcing.
    pub fn record_from(&self, omega: Option<f64>) -> f64 {
        omega.map_or(self.transient, |w| self.transient * std::f64::consts::TAU / w)
    }

    /// The analysis window against the scene's clock: `poincare` needs a
    /// periodic forcing, and the record window after the `transient` must
    /// not be empty (it starts before the horizon).
    fn check_window(&self, scene: &Scene) -> Result<(), SceneError> {
        let (omega, t_end) = scene.forcing_and_horizon();
        if self.poincare && omega.is_none() {
            return Err(field("output.poincare", "needs a periodic forcing (the oscillator's [forcing], a beam's support): remove it"));
        }
        if !(self.poincare || self.summary || self.impacts) {
            return Ok(());
        }
        let from = self.record_from(omega);
        if from >= t_end {
            let (unit, most) = omega.map_or(("s", t_end), |w| ("forcing periods", t_end * w / std::f64::consts::TAU));
            return Err(field(
                "output.transient",
                format!("{} {unit} ({from} s) is not allowed: it reaches the horizon t_end = {t_end} s, so nothing would be recorded; allowed: [0, {most}) {unit}", self.transient),
            ));
        }
        Ok(())
    }
}

impl SceneFile {
    /// Parses a scene (TOML syntax, unknown keys, types).
    pub fn parse(text: &str) -> Result<Self, SceneError> {
        toml::from_str(text).map_err(SceneError::Toml)
    }

    /// A scene from a parsed TOML document (unknown keys, types).
    pub fn from_table(doc: toml::Table) -> Result<Self, SceneError> {
        toml::Value::Table(doc).try_into().map_err(SceneError::Toml)
    }

    /// Checks every value and builds the scene, within the machine's
    /// available memory.
    pub fn validate(&self) -> Result<Scene, SceneError> {
        self.validate_with(&Limits::machine())
    }

    /// Checks every value and builds the scene: sizes against `limits`
    /// before anything large is allocated, then the integrator itself (so
    /// that a scene that validates also starts: `check` and `run` refuse
    /// the same things).
    pub fn validate_with(&self, limits: &Limits) -> Result<Scene, SceneError> {
        self.validate_horizon(limits, false)
    }

    /// As [`validate_with`](Self::validate_with) with the horizon replaced
    /// by one step of the scene's `dt`, whatever `t_end` says: what a sweep
    /// reads first (its forcing and `dt`), before it sets its own horizon
    /// and validates again.
    pub fn validate_clock(&self, limits: &Limits) -> Result<Scene, SceneError> {
        self.validate_horizon(limits, true)
    }

    pub(crate) fn validate_horizon(&self, limits: &Limits, one_step: bool) -> Result<Scene, SceneError> {
        if self.output.every == 0 {
            return Err(field("output.every", "0 is not allowed: an integer >= 1"));
        }
        if !(self.output.transient >= 0.0 && self.output.transient.is_finite()) {
            return Err(field("output.transient", format!("{} is not allowed: finite and >= 0 (forcing periods)", self.output.transient)));
        }
        if let Some(tol) = self.output.period_tol {
            if !(tol > 0.0 && tol < 1.0) {
                return Err(field("output.period_tol", format!("{tol} is not allowed: in (0, 1)")));
            }
            if !self.output.summary {
                return Err(field("output.period_tol", "acts only with output.summary (the response period is a summary column): remove it, or set summary = true"));
            }
        }
        if let Some(f) = self.output.energy_warn {
            if !signorini_run::energy::check_factor(f) {
                return Err(field(
                    "output.energy_warn",
                    format!("{f} is not allowed: finite and > 1 (the factor by which the energy may exceed its budget before a warning; default {DEFAULT_ENERGY_WARN})"),
                ));
            }
        }
        if self.output.transient > 0.0 && !(self.output.poincare || self.output.summary || self.output.impacts) {
            return Err(field("output.transient", "acts only with output.poincare, output.summary or output.impacts: remove it, or ask for one"));
        }
        let scene = self.validate_tables(limits, one_step)?;
        if !one_step {
            self.output.check_window(&scene)?;
        }
        Ok(scene)
    }

    fn validate_tables(&self, limits: &Limits, one_step: bool) -> Result<Scene, SceneError> {
        if let Some(o) = &self.oscillator {
            if self.bar.is_some() || self.beam.is_some() {
                return Err(field("oscillator", "give exactly one of the tables [bar], [beam] and [oscillator]"));
            }
            return self.validate_oscillator(o, one_step);
        }
        if self.forcing.is_some() {
            return Err(field("forcing", "acts only with [oscillator] (a bar or a beam takes [load], a beam also [support])"));
        }
        match (&self.bar, &self.beam) {
            (Some(b), None) => {
                if self.support.is_some() {
                    return Err(field("support", "acts only with [beam] (the bar has no moving support): give the excitation as a [load]"));
                }
                let load = self.load.as_ref().map(|e| e.build(Table::Load, self.base.as_deref())).transpose()?;
                Ok(Scene::Bar(Box::new(validate_bar(b, &self.stop, self.obstacle.as_ref(), load, limits, one_step)?)))
            }
            (None, Some(b)) => {
                let support = self.support.as_ref().map(|e| e.build(Table::Support, self.base.as_deref())).transpose()?;
                let load = self.load.as_ref().map(|e| e.build(Table::Load, self.base.as_deref())).transpose()?;
                validate_beam(b, &self.stop, self.obstacle.as_ref(), support, load, limits, one_step)
            }
            _ => Err(field("bar/beam", "give exactly one of the tables [bar], [beam] and [oscillator]")),
        }
    }
}

/// Of the keys a document gives, the one whose value is furthest from 1 in
/// scale (the likeliest cause of an overflow in a product of them).
/// Returns the key and that distance, `|log10 |v||`.
pub(crate) fn extreme_key(given: &[(&'static str, Option<f64>)]) -> Option<(&'static str, f64)> {
    given.iter().filter_map(|(k, v)| v.map(|v| (*k, v.abs().log10().abs()))).filter(|(_, s)| s.is_finite()).max_by(|a, b| a.1.total_cmp(&b.1))
}

/// A run configuration for `dt` and `t_end`, the horizon's error on `t_end`.
pub(crate) fn horizon(prefix: &str, dt: f64, t_end: f64) -> Result<(), SceneError> {
    match RunConfig::new(dt, t_end) {
        Ok(_) => Ok(()),
        Err(e @ RunError::Horizon { .. }) => Err(field(&format!("{prefix}.t_end"), e)),
        Err(e) => Err(field(&format!("{prefix}.dt"), e)),
    }
}

/// Which field a scheme's construction error belongs to; an overflow is
/// put on `overflow_key`.
pub(crate) fn scheme_error(e: SchemeError, overflow_key: &str) -> SceneError {
    match e {
        SchemeError::Unstable { .. } => field("bar.dt", e),
        SchemeError::MassNotSupported { .. } => field("bar.mass", e),
        e @ SchemeError::Factor(_) => field("bar", format!("{e}: the step matrix of these data is not usable; allowed: data whose matrices are finite and positive definite")),
        e @ SchemeError::NonFinite { .. } => field(overflow_key, format!("{e}: the data overflow in the scheme's start; allowed: data whose first step is finite")),
        e => field("bar.scheme", e),
    }
}
