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

use crate::family::{Capabilities, Family, Group, Node, MAX_PARAMS};
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
    &crate::hybrid::CD_MASSLESS,
    &crate::nitsche::NITSCHE,
    &crate::paoli::CD_TAYLOR,
    &crate::events::EVENT_DRIVEN,
];

/// A time scheme with its parameters (docs/theory.md §4; names: §4.8): a
/// [`Family`] of the registry and its parameter values.
#[derive(Clone, Copy)]
pub struct SchemeSpec {
    family: &'static Family,
    args: [f64; MAX_PARAMS],
    /// The stability limit is not enforced ([`SchemeSpec::beyond_limit`]):
    /// not part of the scheme's identity (equality, text).
    waived: bool,
}

impl PartialEq for SchemeSpec {
    fn eq(&self, other: &Self) -> bool {
        self.family.name == other.family.name && self.args() == other.args()
    }
}

impl fmt::Debug for SchemeSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.call())
    }
}

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

impl Family {
    /// The family's scheme with `args` (not validated: [`SchemeSpec::validate`]).
    ///
    /// # Panics
    /// If `args` is not one value per parameter (a programmer error).
    #[track_caller]
    pub const fn with(&'static self, args: &[f64]) -> SchemeSpec {
        assert!(args.len() == self.params.len(), "a scheme family takes one value per parameter");
        let mut a = [0.0; MAX_PARAMS];
        let mut i = 0;
        while i < args.len() {
            a[i] = args[i];
            i += 1;
        }
        SchemeSpec { family: self, args: a, waived: false }
    }
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

    /// The family.
    pub fn family(&self) -> &'static Family {
        self.family
    }

    /// The parameter values, one per [`Family::params`].
    pub fn args(&self) -> &[f64] {
        &self.args[..self.family.params.len()]
    }

    /// The value of the parameter `name`, if the family has one.
    pub fn param(&self, name: &str) -> Option<f64> {
        self.family.params.iter().position(|p| p.name == name).map(|i| self.args[i])
    }

    /// The call form, `newmark(0.25,0.5)` (the bare name without parameters).
    /// Trailing parameters at their default are left out
    /// (`event-driven(0.8)`, not `event-driven(0.8,10000000)`), and very
    /// small or large values take an exponent (`1e-10`); the text parses
    /// back to the same scheme.
    pub fn call(&self) -> String {
        if self.family.params.is_empty() {
            return self.family.name.to_string();
        }
        let params = self.family.params;
        let shown = params.iter().zip(self.args()).rposition(|(p, &a)| p.default != Some(a)).map_or(0, |i| i + 1);
        let args: Vec<String> = self.args()[..shown].iter().map(|&a| number(a)).collect();
        format!("{}({})", self.family.name, args.join(","))
    }

    /// The same scheme built without enforcing its stability limit (a
    /// scene's `force = true`: a run past the limit, to see it blow up);
    /// everything else is checked as by [`SchemeSpec::build`]. Equality and
    /// the text form do not see it.
    pub fn beyond_limit(mut self) -> Self {
        self.waived = true;
        self
    }

    /// Whether the stability limit is waived ([`SchemeSpec::beyond_limit`]).
    pub fn limit_waived(&self) -> bool {
        self.waived
    }

    /// What the scheme can be combined with.
    pub fn capabilities(&self) -> Capabilities {
        (self.family.capabilities)(self.args())
    }

    /// Checks every parameter against its allowed range.
    pub fn validate(&self) -> Result<(), SchemeError> {
        (self.family.validate)(self.args())
    }

    /// The exact stability limit of a conditionally stable scheme on `dy`
    /// (`None` for unconditionally stable ones). `κ_max` is a certified
    /// upper bound (closed form on a uniform P1 bar, Lanczos with an inertia
    /// test otherwise), so the limit is never over-estimated and is within
    /// a relative 1e-12 of the exact one.
    pub fn cfl_limit(&self, dy: &Dynamics) -> Result<Option<f64>, SchemeError> {
        (self.family.cfl_limit)(self.args(), dy)
    }

    /// How [`cfl_limit`](Self::cfl_limit) is computed, in words (`None` for
    /// unconditionally stable schemes).
    pub fn stability_rule(&self) -> Option<&'static str> {
        (self.family.stability_rule)(self.args())
    }

    /// Whether the scheme can run with a mass treatment whose contact node
    /// is massless (`massless = true`) or massive.
    pub fn accepts_massless_node(&self, massless: bool) -> bool {
        self.capabilities().accepts_massless_node(massless)
    }

    /// Whether the scheme is explicit (conditionally stable, CFL-limited).
    pub fn is_explicit(&self) -> bool {
        self.capabilities().explicit
    }

    /// Whether the scheme needs a massive contact node.
    pub fn needs_massive_node(&self) -> bool {
        self.capabilities().node == Node::Massive
    }

    /// Whether the scheme needs a massless contact node.
    pub fn needs_massless_node(&self) -> bool {
        self.capabilities().node == Node::Massless
    }

    /// Whether the scheme needs a diagonal mass (the `lumped` treatment).
    pub fn needs_diagonal_mass(&self) -> bool {
        self.capabilities().diagonal_mass
    }

    /// Refuses `dt` at or beyond [`cfl_limit`](Self::cfl_limit), with room
    /// `roundoff` (relative) for the round-off of the computed limit.
    ///
    /// The computed limit is a certified lower bound of the exact one, at
    /// most a relative 1e-12 below it (8 ulps for the closed form): with
    /// [`STRICT_CFL_ROUNDOFF`] a step that equals the exact limit up to the
    /// round-off of `dt` itself — `taylor-flanagan` at `dt = h/c` on the
    /// lumped bar with a free far end, whose limit is exactly `h/c` (the
    /// Courant-one study) — is accepted.
    pub(crate) fn check_cfl(&self, dy: &Dynamics, dt: f64, inclusive: bool) -> Result<(), SchemeError> {
        if self.waived {
            return Ok(());
        }
        if let Some(limit) = self.cfl_limit(dy)? {
            let ok = if inclusive { dt <= limit * (1.0 + 1e-9) } else { dt < limit * (1.0 + STRICT_CFL_ROUNDOFF) };
            if !ok {
                return Err(SchemeError::Unstable { dt, limit, scheme: self.to_string(), rule: self.stability_rule().unwrap_or("") });
            }
        }
        Ok(())
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
        (self.family.build)(self, dy, dt, init)
    }
}

/// Relative room for round-off in the strict CFL checks (see `check_cfl`).
pub(crate) const STRICT_CFL_ROUNDOFF: f64 = 1e-11;

impl fmt::Display for SchemeSpec {
    /// The preset name when it is one, else the call form `newmark(β,γ)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some((name, _, _)) = Self::presets().find(|(_, s, _)| s == self) {
            return f.write_str(name);
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
        if let Some((_, spec, _)) = Self::presets().find(|(n, _, _)| *n == s) {
            return Ok(spec);
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

/// A parameter's value as the call form prints it: plain, or with an
/// exponent below 1e-5 and from 1e16 on in magnitude, as messages print
/// numbers (`signorini_run::text::num`); both parse back exactly (Rust
/// prints the shortest text that does).
fn number(a: f64) -> String {
    if a != 0.0 && (a.abs() < 1e-5 || a.abs() >= 1e16) {
        format!("{a:e}")
    } else {
        a.to_string()
    }
}
