//! A scheme family's description: its parameters, presets, capabilities
//! and builder ([`Family`]), and the helpers the scheme files define their
//! families with. The scheme files import this module; the registry
//! (`registry.rs`: [`FAMILIES`](crate::FAMILIES), `SchemeSpec` and its
//! parsing) imports them, so the types live here and not in the registry.

use crate::{Dynamics, Initial, SchemeError, Stepper};
use std::fmt;

/// The most parameters a family takes.
pub const MAX_PARAMS: usize = 3;

/// One parameter of a scheme family.
#[derive(Clone, Copy, Debug)]
pub struct Param {
    /// Its name in errors (`beta`, `e`, `gamma_p`).
    pub name: &'static str,
    /// Its symbol in the docs (`β`, `γ_P`).
    pub symbol: &'static str,
    /// Its placeholder in the syntax (`BETA`, `E`).
    pub syntax: &'static str,
    /// Its allowed range, in words (`[0, 1]`).
    pub allowed: &'static str,
    /// The value taken when the call leaves it out (trailing parameters only).
    pub default: Option<f64>,
}

/// Which contact node a scheme needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Node {
    /// Either a massive or a massless contact node.
    Any,
    /// A massive contact node (mass `std` or `lumped`; explicit schemes,
    /// Moreau–Jean, the β-scheme with β < 1/4).
    Massive,
    /// A massless contact node (the reduced formulations).
    Massless,
}

/// What a scheme (a family with its parameter values) can be combined with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct Capabilities {
    /// Explicit (conditionally stable, CFL-limited).
    pub explicit: bool,
    /// The contact node it needs.
    pub node: Node,
    /// It needs a diagonal mass (`lumped`).
    pub diagonal_mass: bool,
    /// It takes a damping matrix `C`.
    pub damping: bool,
    /// It takes a time-dependent load.
    pub forcing: bool,
    /// It has an impact law: a per-contact restitution acts.
    pub restitution: bool,
    /// It is a penalty method: a per-contact stiffness acts.
    pub stiffness: bool,
    /// It takes several contacts.
    pub several_contacts: bool,
    /// It takes the beam's structure (Hermite cubics: consistent, non-diagonal
    /// mass, massive contact dofs that are not dof 0, a support motion's load).
    pub beam: bool,
    /// Runs that share a step matrix can be stepped together by the
    /// lockstep engine ([`crate::PaoliSchatzmanLockstep`],
    /// [`crate::MoreauJeanLockstep`], [`crate::NsgaLockstep`],
    /// [`crate::ContactStabilizedLockstep`], [`crate::CdLagrangeLockstep`],
    /// [`crate::D1MinusLinearLockstep`],
    /// [`crate::MoreauJeanCombinedLockstep`]; [`crate::LockstepScheme`]: one contact,
    /// undamped, a massive contact node, half-bandwidth 3), each lane bit
    /// for bit its single run; a sweep batches such runs.
    pub lockstep: bool,
}

impl Capabilities {
    /// An implicit scheme for any node that takes everything but impact
    /// laws and penalty stiffness (the Newmark/θ family's).
    pub const IMPLICIT: Capabilities = Capabilities {
        explicit: false,
        node: Node::Any,
        diagonal_mass: false,
        damping: true,
        forcing: true,
        restitution: false,
        stiffness: false,
        several_contacts: true,
        beam: true,
        lockstep: false,
    };

    /// Whether a mass treatment whose contact node is massless (`true`) or
    /// massive (`false`) suits the scheme.
    pub fn accepts_massless_node(&self, massless: bool) -> bool {
        match self.node {
            Node::Any => true,
            Node::Massive => !massless,
            Node::Massless => massless,
        }
    }
}

/// The group a preset is listed in (the studies loop over them in this order).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Group {
    /// The papers' presets (docs/theory.md §4.8), in the order of their tables.
    Paper,
    /// The schemes on the reduced formulation (massless contact node only).
    Reduced,
    /// The schemes users compare against (docs/theory.md §4.6).
    Peer,
    /// Schemes that take one mass only (left out of the loops over every
    /// scheme and mass).
    SingleMass,
    /// The exact event-driven reference (not a time-stepping scheme: left
    /// out of the loops over schemes).
    Reference,
}

/// A named preset of a family.
#[derive(Clone, Copy, Debug)]
pub struct Preset {
    /// Its name (`newmark-cn`).
    pub name: &'static str,
    /// The family's parameter values.
    pub args: &'static [f64],
    /// The list it belongs to.
    pub group: Group,
    /// Its place in the group (the papers' table order).
    pub rank: u8,
}

/// How a family builds its stepper: the scheme (with its values), the
/// problem, the time step and the initial state.
pub type BuildFn = fn(&SchemeSpec, Dynamics, f64, &Initial) -> Result<Box<dyn Stepper>, SchemeError>;

/// A scheme family: everything the workspace knows of a scheme comes from here.
pub struct Family {
    /// The name (`newmark`, `ps`, `cd-taylor`).
    pub name: &'static str,
    /// One line for `signorini list`.
    pub about: &'static str,
    /// Its parameters (at most [`MAX_PARAMS`]).
    pub params: &'static [Param],
    /// Its named presets.
    pub presets: &'static [Preset],
    /// Checks the parameter values (ranges and their relations).
    pub validate: fn(&[f64]) -> Result<(), SchemeError>,
    /// What the scheme with these values can be combined with.
    pub capabilities: fn(&[f64]) -> Capabilities,
    /// The exact stability limit on a problem (`None`: unconditionally stable).
    pub cfl_limit: fn(&[f64], &Dynamics) -> Result<Option<f64>, SchemeError>,
    /// How the limit is computed, in words (`None`: unconditionally stable).
    pub stability_rule: fn(&[f64]) -> Option<&'static str>,
    /// Builds the integrator (the parameters are validated and the
    /// capabilities checked before).
    pub build: BuildFn,
}

impl fmt::Debug for Family {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Family").field("name", &self.name).finish_non_exhaustive()
    }
}

impl Family {
    /// The call syntax: `newmark(BETA,GAMMA)`, `ps(E[,BETA])`; the bare name
    /// for a family without parameters.
    pub fn syntax(&self) -> String {
        if self.params.is_empty() {
            return self.name.to_string();
        }
        let mut s = format!("{}(", self.name);
        for (i, p) in self.params.iter().enumerate() {
            let sep = if i == 0 { "" } else { "," };
            if p.default.is_some() {
                s += &format!("[{sep}{}]", p.syntax);
            } else {
                s += &format!("{sep}{}", p.syntax);
            }
        }
        s + ")"
    }

    /// The ranges of the parameters, in words (`β ∈ (0, 1/2], γ ∈ [1/2, 2β]`).
    pub fn ranges(&self) -> String {
        self.params.iter().map(|p| format!("{} {}", p.symbol, p.allowed)).collect::<Vec<_>>().join(", ")
    }
}

/// A certified upper bound of `κ_max` of the pencil `(k, m)`, in O(n): the
/// closed form when it is a uniform P1 bar's (std or lumped mass), Lanczos
/// with an inertia test otherwise ([`signorini_fem::max_generalized_eigenvalue_bound`],
/// docs/theory.md §2.3, §2.4). The limit `2/sqrt(κ)` is therefore never
/// above the exact one, and below it by at most a relative 1e-12.
pub(crate) fn kappa_bound(k: &signorini_fem::SymBand, m: &signorini_fem::SymBand) -> Result<f64, signorini_fem::FemError> {
    signorini_fem::max_generalized_eigenvalue_bound(k, m).map(|b| b.upper)
}

/// A check of one parameter: `Ok` if `ok` and `v` is finite.
pub(crate) fn check(field: &'static str, v: f64, ok: bool, allowed: &'static str) -> Result<(), SchemeError> {
    if ok && v.is_finite() {
        Ok(())
    } else {
        Err(SchemeError::Invalid { field, value: v, allowed })
    }
}

/// A part of the problem that a scheme's constructor may refuse
/// ([`not_taken`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Refused {
    /// A damping matrix `C`.
    Damping,
    /// More than one contact.
    SeveralContacts,
}

impl Refused {
    /// Every part a constructor may refuse.
    pub(crate) const ALL: [Refused; 2] = [Refused::Damping, Refused::SeveralContacts];

    /// In words, as [`SchemeError::NotTaken`]'s `what`.
    pub(crate) fn what(self) -> &'static str {
        match self {
            Refused::Damping => "damping matrix",
            Refused::SeveralContacts => "several contacts",
        }
    }

    /// Whether a scheme with these capabilities takes it.
    pub(crate) fn taken_by(self, c: &Capabilities) -> bool {
        match self {
            Refused::Damping => c.damping,
            Refused::SeveralContacts => c.several_contacts,
        }
    }
}

/// The `by` of a constructor's refusal: a scheme file names no other
/// scheme (it is below the registry), so [`SchemeSpec::build`] puts the
/// registry's list of the schemes that take the part in its place; a
/// constructor called directly (`Nitsche::new`) keeps these words.
pub(crate) const TAKERS_UNNAMED: &str = "a scheme whose capabilities take it (signorini_schemes::families_with names them)";

/// A constructor's refusal of a part of the problem its scheme does not
/// take; `why` may be empty or start with a space.
pub(crate) fn not_taken(scheme: String, refused: Refused, why: &'static str) -> SchemeError {
    SchemeError::NotTaken { scheme, what: refused.what(), why, by: TAKERS_UNNAMED.to_string() }
}

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
}

/// Relative room for round-off in the strict CFL checks (see `check_cfl`).
pub(crate) const STRICT_CFL_ROUNDOFF: f64 = 1e-11;

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
