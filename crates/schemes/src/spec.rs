//! Scheme names, parameters and their allowed ranges.

use crate::{Dynamics, Initial, OneStep, OneStepParams, PaoliSchatzman, Reduced, ReducedLaw, SchemeError, Stepper};
use std::fmt;
use std::str::FromStr;

/// A time scheme with its parameters (SPEC §4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SchemeSpec {
    /// Newmark(β, γ), contact at `t_{n+1}`; β ∈ (0, 1/2], γ ∈ [1/2, 2β].
    Newmark {
        /// β.
        beta: f64,
        /// γ.
        gamma: f64,
    },
    /// θ-method, θ ∈ [1/2, 1].
    Theta {
        /// θ.
        theta: f64,
    },
    /// Paoli–Schatzman / β-scheme, restitution e ∈ [0, 1], β ∈ [0, 1/2]
    /// (β = 0 only with a massive contact node; β < 1/2 is conditionally
    /// stable: dt < 2/sqrt((1-2β) κ_h)).
    PaoliSchatzman {
        /// Restitution coefficient e.
        restitution: f64,
        /// β of the two-step average (1/4 by default).
        beta: f64,
    },
    /// A scheme on the reduced formulation of a massless contact node
    /// (`hybrid`, `reduced-cn`); needs a massless-node mass.
    Reduced(ReducedLaw),
}

impl SchemeSpec {
    /// The presets of SPEC §4, in the order of the papers' tables.
    pub const PRESETS: [(&'static str, SchemeSpec); 7] = [
        ("newmark-cn", SchemeSpec::Newmark { beta: 0.25, gamma: 0.5 }),
        ("newmark-i", SchemeSpec::Newmark { beta: 0.5, gamma: 1.0 }),
        ("newmark-ii", SchemeSpec::Newmark { beta: 0.5, gamma: 0.5 }),
        ("backward-euler", SchemeSpec::Theta { theta: 1.0 }),
        ("ps-e0", SchemeSpec::PaoliSchatzman { restitution: 0.0, beta: 0.25 }),
        ("ps-e0.5", SchemeSpec::PaoliSchatzman { restitution: 0.5, beta: 0.25 }),
        ("ps-e1", SchemeSpec::PaoliSchatzman { restitution: 1.0, beta: 0.25 }),
    ];

    /// The schemes on the reduced formulation (massless contact node only).
    pub const REDUCED: [(&'static str, SchemeSpec); 2] =
        [("hybrid", SchemeSpec::Reduced(ReducedLaw::Hybrid)), ("reduced-cn", SchemeSpec::Reduced(ReducedLaw::CrankNicolson))];

    /// Every named scheme: the presets, then the reduced ones.
    pub fn named() -> impl Iterator<Item = (&'static str, SchemeSpec)> {
        Self::PRESETS.into_iter().chain(Self::REDUCED)
    }

    /// Checks every parameter against its allowed range.
    pub fn validate(&self) -> Result<(), SchemeError> {
        let check = |field, v: f64, ok: bool, allowed| if ok && v.is_finite() { Ok(()) } else { Err(SchemeError::Invalid { field, value: v, allowed }) };
        match *self {
            SchemeSpec::Newmark { beta, gamma } => {
                check("gamma", gamma, (0.5..=1.0).contains(&gamma), "[1/2, 1]")?;
                check("beta", beta, beta > 0.0 && beta <= 0.5, "(0, 1/2] (β = 0 is explicit: not an implicit Newmark preset)")?;
                check("beta", beta, 2.0 * beta >= gamma, "[γ/2, 1/2] (unconditional stability; conditionally stable implicit Newmark is not offered)")
            }
            SchemeSpec::Theta { theta } => check("theta", theta, (0.5..=1.0).contains(&theta), "[1/2, 1]"),
            SchemeSpec::PaoliSchatzman { restitution, beta } => {
                check("e", restitution, (0.0..=1.0).contains(&restitution), "[0, 1]")?;
                check("beta", beta, (0.0..=0.5).contains(&beta), "[0, 1/2] (β = 0 needs a massive contact node)")
            }
            SchemeSpec::Reduced(_) => Ok(()),
        }
    }

    /// Whether the scheme needs a massless contact node.
    pub fn needs_massless_node(&self) -> bool {
        matches!(self, SchemeSpec::Reduced(_))
    }

    /// Whether the scheme is a two-step scheme (started by one one-step step).
    pub fn is_two_step(&self) -> bool {
        matches!(self, SchemeSpec::PaoliSchatzman { .. })
    }

    /// Builds the integrator for a problem, time step and initial state.
    pub fn build(&self, dy: Dynamics, dt: f64, init: &Initial) -> Result<Box<dyn Stepper>, SchemeError> {
        self.validate()?;
        let label = self.to_string();
        Ok(match *self {
            SchemeSpec::Newmark { beta, gamma } => Box::new(OneStep::new(label, dy, OneStepParams::newmark(beta, gamma), dt, init)?),
            SchemeSpec::Theta { theta } => Box::new(OneStep::new(label, dy, OneStepParams::theta(theta), dt, init)?),
            SchemeSpec::PaoliSchatzman { restitution, beta } => Box::new(PaoliSchatzman::new(label, dy, beta, restitution, dt, init)?),
            SchemeSpec::Reduced(law) => Box::new(Reduced::new(label, dy, law, dt, init)?),
        })
    }
}

impl fmt::Display for SchemeSpec {
    /// The preset name when it is one, else `newmark(β,γ)`, `theta(θ)`, `ps(e,β)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some((name, _)) = Self::named().find(|(_, s)| s == self) {
            return f.write_str(name);
        }
        match self {
            SchemeSpec::Newmark { beta, gamma } => write!(f, "newmark({beta},{gamma})"),
            SchemeSpec::Theta { theta } => write!(f, "theta({theta})"),
            SchemeSpec::PaoliSchatzman { restitution, beta } => write!(f, "ps({restitution},{beta})"),
            SchemeSpec::Reduced(ReducedLaw::Hybrid) => f.write_str("hybrid"),
            SchemeSpec::Reduced(ReducedLaw::CrankNicolson) => f.write_str("reduced-cn"),
        }
    }
}

impl FromStr for SchemeSpec {
    type Err = SchemeError;
    /// A preset name, or `newmark(BETA,GAMMA)`, `theta(THETA)`, `ps(E)`, `ps(E,BETA)`.
    /// The parameters are validated.
    fn from_str(s: &str) -> Result<Self, SchemeError> {
        let s = s.trim();
        if let Some((_, spec)) = Self::named().find(|(n, _)| *n == s) {
            return Ok(spec);
        }
        let unknown = || SchemeError::UnknownScheme(s.to_string());
        let (head, rest) = s.split_once('(').ok_or_else(unknown)?;
        let args = rest.strip_suffix(')').ok_or_else(unknown)?;
        let nums: Vec<f64> = args.split(',').map(|a| a.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| unknown())?;
        let spec = match (head.trim(), nums.as_slice()) {
            ("newmark", [beta, gamma]) => SchemeSpec::Newmark { beta: *beta, gamma: *gamma },
            ("theta", [theta]) => SchemeSpec::Theta { theta: *theta },
            ("ps", [e]) => SchemeSpec::PaoliSchatzman { restitution: *e, beta: 0.25 },
            ("ps", [e, beta]) => SchemeSpec::PaoliSchatzman { restitution: *e, beta: *beta },
            _ => return Err(unknown()),
        };
        spec.validate()?;
        Ok(spec)
    }
}
