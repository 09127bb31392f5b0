//! The scheme registry: one table of every time scheme, from which parsing,
//! printing, validation, capabilities (what a scene may combine with a
//! scheme), stability rules, `signorini list`, the messages that name
//! schemes, the fuzzer's pools and the studies' loops are derived.
//!
//! A scheme family (`newmark`, `ps`, `moreau-jean`, …) is a [`Family`]: its
//! name, its parameters with their ranges and syntax, its named presets,
//! its [`Capabilities`], its stability limit and how to build its
//! [`Stepper`] (the types are in `family.rs`, which the scheme files
//! import). Each family is defined in the file of its integrator; the
//! registry is the list [`FAMILIES`]. A new scheme is its file (the stepper
//! and its `Family`), one row in [`FAMILIES`], and its documentation.
//!
//! A [`SchemeSpec`] is a family with its parameter values: `newmark-cn` is
//! the preset `newmark(0.25,0.5)`; `ps(0.5)` takes `ps`'s default `β = 1/4`.

use crate::family::{Capabilities, Family, Group, Refused, SchemeSpec, TAKERS_UNNAMED};
use crate::{Dynamics, Initial, SchemeError, Stepper};
use std::fmt;
use std::str::FromStr;

/// The registry: every scheme family, in the order `signorini list` shows them.
pub static FAMILIES: &[&Family] = &[
    &crate::onestep::NEWMARK,
    &crate::onestep::THETA,
    &crate::paoli::PS,
    &crate::hybrid::HYBRID,
    &crate::hybrid::REDUCED_CN,
    &crate::onestep::PENALTY,
    &crate::onestep::PENALTY_CD,
    &crate::moreau::MOREAU_JEAN,
    &crate::moreau_projected::MOREAU_JEAN_PROJECTED,
    &crate::moreau_combined::MOREAU_JEAN_COMBINED,
    &crate::nsga::NSGA,
    &crate::stabilized::CONTACT_STABILIZED,
    &crate::d1minus::D1_MINUS_LINEAR,
    &crate::d1minus::D1_MINUS_LINEAR_VELOCITY,
    &crate::cd_lagrange::CD_LAGRANGE,
    &crate::hybrid::CD_MASSLESS,
    &crate::nitsche::NITSCHE,
    &crate::verlet_nitsche::VERLET_NITSCHE,
    &crate::paoli::CD_TAYLOR,
    &crate::events::EVENT_DRIVEN,
];

/// The families whose capabilities satisfy `pred`, in words (`newmark,
/// theta, ps or moreau-jean`): the schemes a message offers instead.
pub fn families_with(pred: impl Fn(&Capabilities) -> bool) -> String {
    let names: Vec<&str> = FAMILIES
        .iter()
        .filter(|f| {
            // A family qualifies if its default values (or any preset) do.
            let defaults: Vec<f64> = f.params.iter().map(|p| p.default.unwrap_or(f64::NAN)).collect();
            f.presets.iter().any(|p| pred(&(f.capabilities)(p.args))) || (f.presets.is_empty() && pred(&(f.capabilities)(&defaults)))
        })
        .map(|f| f.name)
        .collect();
    match names.split_last() {
        None => String::new(),
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    }
}

/// Every way to write a scheme, in words: the presets, then each family's
/// call syntax (`newmark(BETA,GAMMA)`, `ps(E[,BETA])`).
pub fn syntax_list() -> String {
    let mut all: Vec<String> = SchemeSpec::presets().map(|p| p.0.to_string()).collect();
    for f in FAMILIES.iter().filter(|f| !f.params.is_empty()) {
        all.push(f.syntax());
    }
    all.join(", ")
}

impl SchemeSpec {
    /// Every named preset with its scheme, grouped ([`Group`]) and in each
    /// group in the papers' order.
    pub fn presets() -> impl Iterator<Item = (&'static str, SchemeSpec, Group)> {
        let mut all: Vec<(&'static str, SchemeSpec, Group, u8)> = FAMILIES.iter().flat_map(|f| f.presets.iter().map(move |p| (p.name, f.with(p.args), p.group, p.rank))).collect();
        all.sort_by_key(|p| (p.2, p.3));
        all.into_iter().map(|p| (p.0, p.1, p.2))
    }

    /// The presets of one group.
    pub fn group(g: Group) -> impl Iterator<Item = (&'static str, SchemeSpec)> {
        Self::presets().filter(move |p| p.2 == g).map(|p| (p.0, p.1))
    }

    /// Every named scheme run with every mass (the papers' presets, the
    /// reduced ones, the peers; not [`Group::SingleMass`] nor the
    /// event-driven [`Group::Reference`]).
    pub fn named() -> impl Iterator<Item = (&'static str, SchemeSpec)> {
        Self::presets().filter(|p| p.2 != Group::SingleMass && p.2 != Group::Reference).map(|p| (p.0, p.1))
    }

    /// Builds the integrator for a problem, time step and initial state:
    /// the parameters are validated, a time-dependent load and a damping
    /// matrix refused by the schemes that do not take them.
    pub fn build(&self, dy: Dynamics, dt: f64, init: &Initial) -> Result<Box<dyn Stepper>, SchemeError> {
        self.validate()?;
        let caps = self.capabilities();
        if !dy.forcing.is_empty() && !caps.forcing {
            return Err(SchemeError::NotTaken { scheme: self.to_string(), what: "time-dependent load", why: "", by: families_with(|c| c.forcing) });
        }
        if dy.damping.is_some() && !caps.damping {
            return Err(SchemeError::NotTaken {
                scheme: self.to_string(),
                what: "damping matrix",
                why: if caps.explicit { " (an explicit step would need a solve with M + dt/2 C)" } else { "" },
                by: families_with(|c| c.damping),
            });
        }
        (self.family().build)(self, dy, dt, init).map_err(name_takers)
    }
}

/// A constructor's refusal ([`crate::family::not_taken`]) with the
/// registry's list of the schemes that take the part refused.
fn name_takers(e: SchemeError) -> SchemeError {
    match e {
        SchemeError::NotTaken { scheme, what, why, by } if by == TAKERS_UNNAMED => {
            let by = Refused::ALL.into_iter().find(|r| r.what() == what).map_or(by, |r| families_with(|c| r.taken_by(c)));
            SchemeError::NotTaken { scheme, what, why, by }
        }
        e => e,
    }
}

impl fmt::Display for SchemeSpec {
    /// The preset name when it is one, else the call form `newmark(β,γ)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The first preset equal to it in [`SchemeSpec::presets`]'s order
        // (the least group and rank, ties in the families' order), found
        // without building and sorting the whole list: every integrator's
        // label is written so (a scene family builds one at every
        // parameter value).
        if let Some((_, p)) = FAMILIES.iter().flat_map(|fam| fam.presets.iter().map(move |p| (fam, p))).filter(|(fam, p)| fam.with(p.args) == *self).min_by_key(|(_, p)| (p.group, p.rank)) {
            return f.write_str(p.name);
        }
        f.write_str(&self.call())
    }
}

impl FromStr for SchemeSpec {
    type Err = SchemeError;
    /// A preset name, or a family's call `name(A[,B])` (trailing parameters
    /// with a default may be left out). The parameters are validated.
    fn from_str(s: &str) -> Result<Self, SchemeError> {
        let s = s.trim();
        // The first preset of that name in [`SchemeSpec::presets`]'s order
        // (the least group and rank, ties in the families' order), found
        // without building and sorting the whole list: a scene family
        // parses its scheme at every parameter value.
        if let Some((f, p)) = FAMILIES.iter().flat_map(|f| f.presets.iter().map(move |p| (f, p))).filter(|(_, p)| p.name == s).min_by_key(|(_, p)| (p.group, p.rank)) {
            return Ok(f.with(p.args));
        }
        let unknown = || SchemeError::UnknownScheme { name: s.to_string(), allowed: syntax_list() };
        if let Some(f) = FAMILIES.iter().find(|f| f.params.is_empty() && f.name == s) {
            return Ok(f.with(&[]));
        }
        let (head, rest) = s.split_once('(').ok_or_else(unknown)?;
        let args = rest.strip_suffix(')').ok_or_else(unknown)?;
        // `name()`: every parameter at its default (a family whose parameters all have one).
        let nums: Vec<f64> = if args.trim().is_empty() { Vec::new() } else { args.split(',').map(|a| a.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| unknown())? };
        let family = FAMILIES.iter().find(|f| f.name == head.trim() && !f.params.is_empty()).ok_or_else(unknown)?;
        let required = family.params.iter().filter(|p| p.default.is_none()).count();
        if nums.len() < required || nums.len() > family.params.len() {
            return Err(unknown());
        }
        let full: Vec<f64> = family.params.iter().enumerate().map(|(i, p)| nums.get(i).copied().or(p.default).unwrap_or(f64::NAN)).collect();
        let spec = family.with(&full);
        spec.validate()?;
        Ok(spec)
    }
}
