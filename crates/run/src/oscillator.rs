//! The one-degree-of-freedom impact oscillator, the reference problem of
//! vibro-impact studies:
//!
//! `m x'' + c x' + k x = F cos(Ω t)` (or any [`TimeProfile`] times `F`),
//! `x <= stop` (between two stops: `lower <= x <= stop`), `c = 2 ζ sqrt(k m)`,
//! Newton's impact law `x'⁺ = −r x'⁻` at the stop (at each, with one `r`),
//! `x(0) = x₀`, `x'(0) = v₀`.
//!
//! It is one dof of the same [`Dynamics`] the bar and the beam use, so every
//! scheme that takes a massive contact node and a damping runs it; the
//! default is Paoli–Schatzman (β = 1/4) with `e = r`.

use crate::RunError;
use signorini_fem::SymBand;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, Initial, SchemeSpec, Stepper, TimeProfile};
use std::sync::Arc;

/// The oscillator's data.
#[derive(Clone, Debug, PartialEq)]
pub struct Oscillator {
    /// Mass `m` (> 0).
    pub mass: f64,
    /// Stiffness `k` (>= 0).
    pub stiffness: f64,
    /// Damping ratio `ζ` (>= 0): `c = 2 ζ sqrt(k m)`.
    pub damping_ratio: f64,
    /// The stop: `x <= stop` (the upper bound).
    pub stop: f64,
    /// A second stop below it, `lower <= x` (`None`: one stop). One
    /// contact with the two bounds, as the beam's tip between its stops.
    pub lower: Option<f64>,
    /// Restitution coefficient `r` in [0, 1].
    pub restitution: f64,
    /// `x(0)`.
    pub x0: f64,
    /// `x'(0)`.
    pub v0: f64,
    /// The load's time profile `s(t)`: the load is `s(t)` itself (its
    /// amplitude is in the profile). [`Oscillator::cosine`] builds
    /// `F cos(Ω t)`.
    pub load: Option<TimeProfile>,
}

impl Oscillator {
    /// `F cos(Ω t) = F sin(Ω t + π/2)`.
    pub fn cosine(amplitude: f64, omega: f64) -> TimeProfile {
        TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude, omega, phase: std::f64::consts::FRAC_PI_2 }]))
    }

    /// The damping coefficient `c = 2 ζ sqrt(k m)`.
    pub fn damping(&self) -> f64 {
        2.0 * self.damping_ratio * (self.stiffness * self.mass).sqrt()
    }

    /// Checks the data; errors name `oscillator.<field>`.
    pub fn validate(&self) -> Result<(), RunError> {
        let bad = |field: &'static str, value: f64, allowed: &'static str| Err(RunError::Invalid { field, value, allowed });
        if !(self.mass > 0.0 && self.mass.is_finite()) {
            return bad("oscillator.mass", self.mass, "finite and > 0");
        }
        if !(self.stiffness >= 0.0 && self.stiffness.is_finite()) {
            return bad("oscillator.stiffness", self.stiffness, "finite and >= 0");
        }
        if !(self.damping_ratio >= 0.0 && self.damping_ratio.is_finite()) {
            return bad("oscillator.damping_ratio", self.damping_ratio, "finite and >= 0");
        }
        if !self.damping().is_finite() {
            return bad("oscillator.damping_ratio", self.damping_ratio, "a damping 2 ζ sqrt(k m) that is finite");
        }
        if !self.stop.is_finite() {
            return bad("oscillator.stop", self.stop, "a finite number");
        }
        if let Some(lo) = self.lower {
            if !lo.is_finite() {
                return bad("oscillator.lower", lo, "a finite number");
            }
            if lo >= self.stop {
                return bad("oscillator.lower", lo, "< stop (the lower stop below the upper one)");
            }
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return bad("oscillator.restitution", self.restitution, "[0, 1]");
        }
        if !self.x0.is_finite() || self.x0 > self.stop {
            return bad("oscillator.initial_displacement", self.x0, "finite and <= stop (the initial state satisfies the constraint)");
        }
        if self.lower.is_some_and(|lo| self.x0 < lo) {
            return bad("oscillator.initial_displacement", self.x0, "finite and >= the lower stop (the initial state satisfies the constraint)");
        }
        if !self.v0.is_finite() {
            return bad("oscillator.initial_velocity", self.v0, "a finite number");
        }
        Ok(())
    }

    /// The one-dof problem and its initial state.
    pub fn dynamics(&self) -> Result<(Dynamics, Initial), RunError> {
        self.validate()?;
        let c = self.damping();
        let contact = Contact::new(0, Bounds { lo: self.lower.unwrap_or(f64::NEG_INFINITY), hi: self.stop }, false).with_restitution(Some(self.restitution));
        let dy = Dynamics::new(SymBand::from_diagonal(&[self.mass]), SymBand::from_diagonal(&[self.stiffness]), vec![0.0], vec![contact])
            .with_forcing(self.load.iter().map(|p| Forcing { shape: vec![1.0], time: p.clone() }).collect())
            .with_damping((c > 0.0).then(|| SymBand::from_diagonal(&[c])));
        Ok((dy, Initial { u: vec![self.x0], v: vec![self.v0] }))
    }

    /// The default scheme: Paoli–Schatzman, β = 1/4, `e = r`.
    pub fn default_scheme(&self) -> SchemeSpec {
        SchemeSpec::ps(self.restitution, 0.25)
    }

    /// The stepper of `scheme` (default: [`Self::default_scheme`]) at `dt`.
    pub fn stepper(&self, scheme: Option<SchemeSpec>, dt: f64) -> Result<(Box<dyn Stepper>, Initial), RunError> {
        let (dy, init) = self.dynamics()?;
        let spec = scheme.unwrap_or_else(|| self.default_scheme());
        let s = spec.build(dy, dt, &init)?;
        Ok((s, init))
    }
}
