//! Scheme names, parameters and their allowed ranges.

use crate::{ContactLaw, Dynamics, Initial, MoreauJean, Nitsche, OneStep, OneStepParams, PaoliSchatzman, Reduced, ReducedLaw, SchemeError, Stepper};
use std::fmt;
use std::str::FromStr;

/// The refusal of a damping matrix by the schemes that do not take one.
pub(crate) const DAMPING_SCHEMES: &str = "this scheme takes no damping matrix: damping needs newmark, theta, ps, penalty-cn or moreau-jean";

/// A time scheme with its parameters (docs/theory.md §4; names: §4.8).
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
    /// (β >= 1/4 is unconditionally stable; β < 1/4 needs a massive contact
    /// node and dt < 2/sqrt((1-4β) κ_h)).
    PaoliSchatzman {
        /// Restitution coefficient e.
        restitution: f64,
        /// β of the two-step average (1/4 by default).
        beta: f64,
    },
    /// A scheme on the reduced formulation of a massless contact node
    /// (`hybrid`, `reduced-cn`); needs a massless-node mass.
    Reduced(ReducedLaw),
    /// Penalised contact `λ = γ_P K_cc min(0, u_c - g)` (for the P1 bar
    /// `K_00 = c²/h`: the GetFEM demo's `(γ_P/h) min(0, u_0 - g)` at c = 1),
    /// with Newmark-CN solved exactly per step (`explicit = false`) or the
    /// explicit central difference (β = 0, γ = 1/2; needs a massive contact
    /// node and dt below the exact CFL limit of `(K + κ e_c e_cᵀ, M)`).
    Penalty {
        /// `γ_P` (> 0).
        gamma_p: f64,
        /// Explicit central difference instead of Newmark-CN.
        explicit: bool,
    },
    /// Nitsche's method with Newmark-CN: γ = γ_0 c²/h (γ_0 > 0), θ ∈ [-1, 1].
    Nitsche {
        /// γ_0.
        gamma0: f64,
        /// θ (1: symmetric, 0: incomplete, -1: skew-symmetric).
        theta: f64,
    },
    /// The explicit central difference started by Taylor's formula
    /// (`cd-taylor`, [`PaoliSchatzman::central_difference_taylor`]): a
    /// diagonal (lumped) mass with a massive contact node, restitution 0,
    /// dt up to and including the CFL limit — with the lumped P1 bar, dt = h/c
    /// exactly (Courant number one, docs/theory.md §4.10): nodally exact until
    /// the first release, then first order with a small constant, the
    /// cheapest configuration of the work–precision study on both bars.
    CentralDifferenceTaylor,
    /// Moreau–Jean (velocity-level θ-scheme, Newton's impact law), θ ∈ [1/2, 1], e ∈ [0, 1].
    MoreauJean {
        /// θ.
        theta: f64,
        /// Newton restitution coefficient e.
        restitution: f64,
    },
}

/// Relative room for round-off in the strict CFL checks (see `check_cfl`).
const STRICT_CFL_ROUNDOFF: f64 = 1e-11;

/// A certified upper bound of `κ_max` of the pencil `(k, m)`, in O(n): the
/// closed form when it is a uniform P1 bar's (std or lumped mass), Lanczos
/// with an inertia test otherwise ([`signorini_fem::max_generalized_eigenvalue_bound`],
/// docs/theory.md §2.3, §2.4). The limit `2/sqrt(κ)` is therefore never
/// above the exact one, and below it by at most a relative 1e-12.
fn kappa_bound(k: &signorini_fem::SymBand, m: &signorini_fem::SymBand) -> Result<f64, signorini_fem::FemError> {
    signorini_fem::max_generalized_eigenvalue_bound(k, m).map(|b| b.upper)
}

impl SchemeSpec {
    /// The presets of docs/theory.md §4.8, in the order of the papers' tables.
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

    /// The schemes users compare against (docs/theory.md §4.6): penalty presets
    /// (γ_P = 10) and Taylor–Flanagan.
    pub const PEERS: [(&'static str, SchemeSpec); 6] = [
        ("penalty-cn", SchemeSpec::Penalty { gamma_p: 10.0, explicit: false }),
        ("penalty-cd", SchemeSpec::Penalty { gamma_p: 10.0, explicit: true }),
        // Taylor–Flanagan: the explicit central difference whose contact
        // force at t_n puts u_c^{n+1} exactly on the obstacle — the two-step
        // Paoli–Schatzman form with β = 0, e = 0 (with lumped mass the
        // correction touches the contact node only, as in the original).
        ("taylor-flanagan", SchemeSpec::PaoliSchatzman { restitution: 0.0, beta: 0.0 }),
        ("moreau-jean", SchemeSpec::MoreauJean { theta: 0.5, restitution: 0.0 }),
        ("cd-massless", SchemeSpec::Reduced(ReducedLaw::CentralDifference)),
        ("nitsche-cn", SchemeSpec::Nitsche { gamma0: 10.0, theta: 1.0 }),
    ];

    /// Named schemes outside [`SchemeSpec::named`] (its loops run every
    /// scheme with every mass; these take one mass only): `cd-taylor`
    /// (lumped mass, Courant number one).
    pub const SINGLE_MASS: [(&'static str, SchemeSpec); 1] = [("cd-taylor", SchemeSpec::CentralDifferenceTaylor)];

    /// Every named scheme: the presets, the reduced ones, the peers.
    pub fn named() -> impl Iterator<Item = (&'static str, SchemeSpec)> {
        Self::PRESETS.into_iter().chain(Self::REDUCED).chain(Self::PEERS)
    }

    /// The exact stability limit of a conditionally stable scheme on `dy`
    /// (`None` for unconditionally stable ones): `2/sqrt(κ_max)` of the
    /// scheme's pencil for the explicit ones (`(K + κ e_c e_cᵀ, M)` for
    /// `penalty-cd`, `(K, M)` for Taylor–Flanagan, the reduced `(K*, M*)` for
    /// `cd-massless`), and `2/sqrt((1 - 4β) κ_max)` of `(K, M)` for the
    /// Paoli–Schatzman β-scheme with 0 < β < 1/4 (0 with a massless node:
    /// always unstable). `κ_max` is a certified upper bound (closed form on
    /// a uniform P1 bar, Lanczos with an inertia test otherwise: O(n), an
    /// iteration count independent of n), so the limit is never
    /// over-estimated and is within a relative 1e-12 of the exact one.
    pub fn cfl_limit(&self, dy: &Dynamics) -> Result<Option<f64>, SchemeError> {
        let c = dy.contact().dof;
        match *self {
            SchemeSpec::Penalty { gamma_p, explicit: true } => {
                let mut k = dy.stiffness.clone();
                for ct in &dy.contacts {
                    let kappa = ct.stiffness.unwrap_or(gamma_p * dy.stiffness.get(ct.dof, ct.dof));
                    k.add(ct.dof, ct.dof, kappa);
                }
                Ok(Some(2.0 / kappa_bound(&k, &dy.mass)?.sqrt()))
            }
            SchemeSpec::CentralDifferenceTaylor => Ok(Some(2.0 / kappa_bound(&dy.stiffness, &dy.mass)?.sqrt())),
            SchemeSpec::PaoliSchatzman { beta, .. } if beta < 0.25 => {
                if dy.massless_contact() {
                    return Ok(Some(0.0));
                }
                let kappa = kappa_bound(&dy.stiffness, &dy.mass)?;
                Ok(Some(crate::beta_scheme_critical_dt(beta, kappa)))
            }
            SchemeSpec::Reduced(ReducedLaw::CentralDifference) if dy.massless_contact() && c == 0 && dy.k() == 1 => {
                // The reduced pencil (K*, M*): in contact the node is fixed and
                // node 1 feels the whole first element.
                let (k, m) = (dy.stiffness.trailing(1), dy.mass.trailing(1));
                Ok(Some(2.0 / kappa_bound(&k, &m)?.sqrt()))
            }
            _ => Ok(None),
        }
    }

    /// How [`cfl_limit`](Self::cfl_limit) is computed for this scheme, in
    /// words (`None` for unconditionally stable schemes).
    pub fn stability_rule(&self) -> Option<&'static str> {
        match *self {
            SchemeSpec::Penalty { explicit: true, .. } => Some("explicit central difference with a penalty spring: 2/sqrt(κ_max) of the pencil (K + κ e_c e_cᵀ, M)"),
            SchemeSpec::PaoliSchatzman { beta: 0.0, .. } => Some("explicit central difference (β = 0): 2/sqrt(κ_max) of the pencil (K, M)"),
            SchemeSpec::CentralDifferenceTaylor => Some("explicit central difference: dt <= 2/sqrt(κ_max) of the pencil (K, M), the limit itself allowed (Courant number one with the lumped P1 bar)"),
            SchemeSpec::PaoliSchatzman { beta, .. } if beta < 0.25 => Some("two-step β-scheme with β < 1/4: 2/sqrt((1 - 4β) κ_max) of the pencil (K, M); β >= 1/4 is unconditionally stable"),
            SchemeSpec::Reduced(ReducedLaw::CentralDifference) => Some("explicit central difference with a quasi-static massless node: 2/sqrt(κ_max) of the reduced pencil (K*, M*) without the contact node"),
            _ => None,
        }
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
                check("beta", beta, (0.0..=0.5).contains(&beta), "[0, 1/2] (β < 1/4 needs a massive contact node and is conditionally stable)")
            }
            SchemeSpec::Reduced(_) | SchemeSpec::CentralDifferenceTaylor => Ok(()),
            SchemeSpec::Penalty { gamma_p, .. } => check("gamma_p", gamma_p, gamma_p > 0.0, "finite and > 0"),
            SchemeSpec::Nitsche { gamma0, theta } => {
                check("gamma0", gamma0, gamma0 > 0.0, "finite and > 0")?;
                check("theta", theta, (-1.0..=1.0).contains(&theta), "[-1, 1]")
            }
            SchemeSpec::MoreauJean { theta, restitution } => {
                check("theta", theta, (0.5..=1.0).contains(&theta), "[1/2, 1]")?;
                check("e", restitution, (0.0..=1.0).contains(&restitution), "[0, 1]")
            }
        }
    }

    /// Whether the scheme can run with a mass treatment whose contact node
    /// is massless (`massless = true`) or massive.
    pub fn accepts_massless_node(&self, massless: bool) -> bool {
        if massless {
            !self.needs_massive_node()
        } else {
            !self.needs_massless_node()
        }
    }

    /// Whether the scheme is explicit (conditionally stable, CFL-limited).
    pub fn is_explicit(&self) -> bool {
        matches!(self, SchemeSpec::Penalty { explicit: true, .. } | SchemeSpec::Reduced(ReducedLaw::CentralDifference) | SchemeSpec::CentralDifferenceTaylor) || matches!(self, SchemeSpec::PaoliSchatzman { beta, .. } if *beta == 0.0)
    }

    /// Whether the scheme needs a massive contact node (explicit schemes,
    /// Moreau–Jean, the β-scheme with β < 1/4).
    pub fn needs_massive_node(&self) -> bool {
        matches!(self, SchemeSpec::Penalty { explicit: true, .. } | SchemeSpec::MoreauJean { .. } | SchemeSpec::CentralDifferenceTaylor) || matches!(self, SchemeSpec::PaoliSchatzman { beta, .. } if *beta < 0.25)
    }

    /// Refuses `dt` at or beyond [`cfl_limit`](Self::cfl_limit); `cd-taylor`,
    /// meant for Courant number one, takes the limit itself (with room for
    /// the round-off of the computed limit: a relative 1e-9, above the
    /// bound's own 1e-12 below the exact limit).
    ///
    /// The other schemes refuse `dt >= limit · (1 + 1e-11)`: the computed
    /// limit is a certified lower bound of the exact one, at most a relative
    /// 1e-12 below it (8 ulps for the closed form), and a step that equals
    /// the exact limit up to the round-off of `dt` itself — `taylor-flanagan`
    /// at `dt = h/c` on the lumped bar with a free far end, whose limit is
    /// exactly `h/c` (the Courant-one study) — is accepted, as the earlier
    /// shift-invert iteration accepted it (its Rayleigh quotient lies below
    /// `κ_max`, so its limit was at or a little above the exact one).
    fn check_cfl(&self, dy: &Dynamics, dt: f64) -> Result<(), SchemeError> {
        if let Some(limit) = self.cfl_limit(dy)? {
            let ok = if *self == SchemeSpec::CentralDifferenceTaylor { dt <= limit * (1.0 + 1e-9) } else { dt < limit * (1.0 + STRICT_CFL_ROUNDOFF) };
            if !ok {
                return Err(SchemeError::Unstable { dt, limit, scheme: self.to_string(), rule: self.stability_rule().unwrap_or("") });
            }
        }
        Ok(())
    }

    /// Whether the scheme needs a diagonal mass (`cd-taylor`'s Taylor start
    /// divides by it): the `lumped` treatment.
    pub fn needs_diagonal_mass(&self) -> bool {
        *self == SchemeSpec::CentralDifferenceTaylor
    }

    /// Whether the scheme needs a massless contact node.
    pub fn needs_massless_node(&self) -> bool {
        matches!(self, SchemeSpec::Reduced(_))
    }

    /// Builds the integrator for a problem, time step and initial state.
    pub fn build(&self, dy: Dynamics, dt: f64, init: &Initial) -> Result<Box<dyn Stepper>, SchemeError> {
        self.validate()?;
        let label = self.to_string();
        // These schemes take the steady load only: refuse a time-dependent
        // one rather than ignore it.
        if !dy.forcing.is_empty() && matches!(self, SchemeSpec::Nitsche { .. } | SchemeSpec::Reduced(_)) {
            return Err(SchemeError::Structure("this scheme takes a steady load only: a time-dependent forcing needs newmark, theta, ps, penalty or moreau-jean"));
        }
        if dy.damping.is_some() {
            if matches!(self, SchemeSpec::Nitsche { .. } | SchemeSpec::Reduced(_)) {
                return Err(SchemeError::Structure(DAMPING_SCHEMES));
            }
            if matches!(self, SchemeSpec::Penalty { explicit: true, .. }) {
                return Err(SchemeError::Structure("penalty-cd is explicit and takes no damping (its step would need a solve with M + dt/2 C): use penalty-cn, newmark, theta, ps or moreau-jean"));
            }
        }
        Ok(match *self {
            SchemeSpec::Newmark { beta, gamma } => Box::new(OneStep::new(label, dy, OneStepParams::newmark(beta, gamma), dt, init)?),
            SchemeSpec::Theta { theta } => Box::new(OneStep::new(label, dy, OneStepParams::theta(theta), dt, init)?),
            SchemeSpec::PaoliSchatzman { restitution, beta } => {
                if beta < 0.25 && dy.massless_contact() {
                    return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped) when β < 1/4 (with a massless node the β-scheme is unstable for every dt)" });
                }
                self.check_cfl(&dy, dt)?;
                Box::new(PaoliSchatzman::new(label, dy, beta, restitution, dt, init)?)
            }
            SchemeSpec::Reduced(law) => {
                if law == ReducedLaw::CentralDifference {
                    self.check_cfl(&dy, dt)?;
                }
                Box::new(Reduced::new(label, dy, law, dt, init)?)
            }
            SchemeSpec::Penalty { gamma_p, explicit } => {
                if explicit && dy.massless_contact() {
                    return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node (mass std or lumped)" });
                }
                let c = dy.contact().dof;
                let kappa = gamma_p * dy.stiffness.get(c, c);
                self.check_cfl(&dy, dt)?;
                let prm = if explicit { OneStepParams::newmark(0.0, 0.5) } else { OneStepParams::newmark(0.25, 0.5) };
                let step = OneStep::new(label, dy, prm, dt, init)?;
                Box::new(step.with_contact_law(ContactLaw::Penalty { stiffness: kappa }).map_err(|e| match e {
                    // In the scheme's own parameter: κ = γ_P K_cc.
                    SchemeError::PenaltyTooStiff { field: "penalty stiffness", value, max } => SchemeError::PenaltyTooStiff { field: "gamma_p", value: gamma_p, max: max * gamma_p / value },
                    e => e,
                })?)
            }
            SchemeSpec::CentralDifferenceTaylor => {
                if dy.massless_contact() {
                    return Err(SchemeError::MassNotSupported { scheme: label, needs: "a massive contact node and a diagonal mass (mass lumped)" });
                }
                self.check_cfl(&dy, dt)?;
                Box::new(PaoliSchatzman::central_difference_taylor(label, dy, 0.0, dt, init)?)
            }
            SchemeSpec::MoreauJean { theta, restitution } => Box::new(MoreauJean::new(label, dy, theta, restitution, dt, init)?),
            SchemeSpec::Nitsche { gamma0, theta } => Box::new(Nitsche::new(label, dy, 0.25, 0.5, gamma0, theta, dt, init)?),
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
            SchemeSpec::Reduced(ReducedLaw::CentralDifference) => f.write_str("cd-massless"),
            SchemeSpec::CentralDifferenceTaylor => f.write_str("cd-taylor"),
            SchemeSpec::Penalty { gamma_p, explicit: false } => write!(f, "penalty({gamma_p})"),
            SchemeSpec::Penalty { gamma_p, explicit: true } => write!(f, "penalty-cd({gamma_p})"),
            SchemeSpec::MoreauJean { theta, restitution } => write!(f, "moreau-jean({theta},{restitution})"),
            SchemeSpec::Nitsche { gamma0, theta } => write!(f, "nitsche({gamma0},{theta})"),
        }
    }
}

impl FromStr for SchemeSpec {
    type Err = SchemeError;
    /// A preset name, or `newmark(BETA,GAMMA)`, `theta(THETA)`, `ps(E)`, `ps(E,BETA)`.
    /// The parameters are validated.
    fn from_str(s: &str) -> Result<Self, SchemeError> {
        let s = s.trim();
        if let Some((_, spec)) = Self::named().chain(Self::SINGLE_MASS).find(|(n, _)| *n == s) {
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
            ("penalty", [g]) => SchemeSpec::Penalty { gamma_p: *g, explicit: false },
            ("penalty-cd", [g]) => SchemeSpec::Penalty { gamma_p: *g, explicit: true },
            ("moreau-jean", [t, e]) => SchemeSpec::MoreauJean { theta: *t, restitution: *e },
            ("nitsche", [g, t]) => SchemeSpec::Nitsche { gamma0: *g, theta: *t },
            _ => return Err(unknown()),
        };
        spec.validate()?;
        Ok(spec)
    }
}
