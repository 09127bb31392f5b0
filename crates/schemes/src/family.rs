//! A scheme family's description: its parameters, presets, capabilities
//! and builder ([`Family`]), and the helpers the scheme files define their
//! families with. The scheme files import this module; the registry
//! (`registry.rs`: [`FAMILIES`](crate::FAMILIES), `SchemeSpec` and its
//! parsing) imports them, so the types live here and not in the registry.

use crate::{Dynamics, Initial, SchemeError, SchemeSpec, Stepper};
use std::fmt;

/// The most parameters a family takes.
pub const MAX_PARAMS: usize = 2;

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
    /// lockstep engine ([`crate::PaoliSchatzmanLockstep`]: one contact,
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
