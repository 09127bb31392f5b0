//! The beam between two stops (docs/theory.md §1.2, §8; Dumont & Paoli): a steel pipe
//! clamped to a support vibrating as `φ(t) = A sin(ω t)`, its tip rattling
//! between stops at `g1 <= ũ(L, t) <= g2`.
//!
//! Lifting `u = ũ - h(x) φ(t)`, `h(x) = 1 - 2y² + 4/3 y³ - 1/3 y⁴`, `y = x/L`,
//! makes the clamping homogeneous; then `u_tt + k² u_xxxx = f` with
//! `f = -h φ'' - k² h'''' φ = (A ω² h(x) + 8 A k²/L⁴) sin(ω t)` (the paper's
//! `(20 h + 1.6 k²/L⁴) sin(10 t)` for `A = 0.2`, `ω = 10`), `u(·,0) = 0`,
//! `u_t(·,0) = -A ω h`. Since `h(L) = 0`, the tip of `u` is the physical tip.

use crate::problem::{check_stops, contacts_of, Stop};
use crate::RunError;
use signorini_fem::{max_generalized_eigenvalue, Beam};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Initial, SchemeSpec, Stepper, TimeProfile};

/// The pipe of the paper and its support motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pipe {
    /// Length `L` (m).
    pub length: f64,
    /// `k² = EI/(ρS)` (m⁴ s⁻²).
    pub k2: f64,
    /// Mass per unit length `ρS` (kg/m), to convert a spring in N/m.
    pub rho_s: f64,
    /// Lower and upper stops `g1 < 0 < g2` (m).
    pub stops: (f64, f64),
    /// Support amplitude `A` (m) and angular frequency `ω` (rad/s).
    pub support: (f64, f64),
}

impl Pipe {
    /// docs/theory.md §1.2: L = 1.501 m, k² = 282.84, stops ±0.1 m, φ = 0.2 sin(10 t);
    /// tube of 1 cm outer diameter, 0.5 mm wall, ρ = 8000 kg/m³.
    pub fn paper() -> Self {
        let (d, e) = (0.01_f64, 0.0005_f64);
        let area = std::f64::consts::PI / 4.0 * (d * d - (d - 2.0 * e).powi(2));
        Self { length: 1.501, k2: 282.84, rho_s: 8000.0 * area, stops: (-0.1, 0.1), support: (0.2, 10.0) }
    }

    /// The lifting function `h(x)` and its derivative.
    pub fn lifting(&self, x: f64) -> (f64, f64) {
        let l = self.length;
        let y = x / l;
        (1.0 - 2.0 * y * y + 4.0 / 3.0 * y.powi(3) - y.powi(4) / 3.0, (-4.0 * y + 4.0 * y * y - 4.0 / 3.0 * y.powi(3)) / l)
    }

    /// The semi-discrete problem on `j` elements and its initial state.
    pub fn dynamics(&self, j: usize) -> Result<(Beam, Dynamics, Initial), RunError> {
        let beam = Beam::new(self.length, j, self.k2)?;
        let (a, w) = self.support;
        let l4 = self.length.powi(4);
        let shape = beam.load(|x| a * w * w * self.lifting(x).0 + 8.0 * a * self.k2 / l4);
        let n = beam.dofs();
        let dy = Dynamics::new(beam.mass(), beam.stiffness(), vec![0.0; n], vec![Contact::new(beam.tip_dof(), Bounds { lo: self.stops.0, hi: self.stops.1 }, false)])
            .with_forcing(vec![Forcing { shape, time: TimeProfile::Sine { amplitude: 1.0, omega: w } }]);
        let v = beam.interpolate(|x| -a * w * self.lifting(x).0, |x| -a * w * self.lifting(x).1);
        Ok((beam, dy, Initial { u: vec![0.0; n], v }))
    }
}

/// A beam's excitation beyond the paper's sine support motion: any support
/// motion `φ(t)` whose `φ''` is a profile (sine, harmonics, random), and a
/// time-dependent load.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BeamExcitation {
    /// The support motion `φ(t)` (`None`: the pipe's `A sin(ω t)`).
    pub support: Option<TimeProfile>,
    /// A load `q(t)`: at a node (`Some(node)`, a force in N) or, with
    /// `None`, uniform along the beam (N/m); its time profile.
    pub load: Option<(Option<usize>, TimeProfile)>,
    /// The absolute state `(ũ, ũ_t)` at the unknowns to start from (`None`:
    /// at rest and undeformed), e.g. another run's final state
    /// ([`Pipe::absolute_state`]): the lifted start is `ũ − h φ(0)`,
    /// `ũ_t − h φ'(0)`.
    pub start: Option<(Vec<f64>, Vec<f64>)>,
}

impl BeamExcitation {
    /// The support motion: the given profile, or the pipe's sine.
    pub fn support_motion(&self, pipe: &Pipe) -> TimeProfile {
        self.support.clone().unwrap_or(TimeProfile::Sine { amplitude: pipe.support.0, omega: pipe.support.1 })
    }
}

impl Pipe {
    /// Applies `exc` to the semi-discrete problem of [`Pipe::dynamics`]:
    /// a support motion `φ` replaces the sine's load by the two terms of
    /// the lifting, `−h φ''(t)` and `−k² h^(4) φ(t) = 8 k²/L⁴ φ(t)` (exact for
    /// any `φ` with a `φ''`), and the initial state by `u = −h φ(0)`,
    /// `u_t = −h φ'(0)` (the beam starts at rest and undeformed); a load adds
    /// `q(t)/ρS` (the scaled equation's units). A support motion without
    /// `φ''` (a piecewise-linear series: impulses) is refused, naming
    /// `support.profile`.
    pub fn excite(&self, beam: &Beam, dy: &mut Dynamics, init: &mut Initial, exc: &BeamExcitation) -> Result<(), RunError> {
        if let Some(phi) = &exc.support {
            let Some(acc) = phi.second_derivative() else {
                return Err(RunError::Invalid {
                    field: "support.profile",
                    value: f64::NAN,
                    allowed: "a support motion with a second derivative (sine, cosine, harmonics, random); a series' φ'' is a train of impulses: give it as a [load]",
                });
            };
            let l4 = self.length.powi(4);
            dy.forcing = vec![Forcing { shape: beam.load(|x| -self.lifting(x).0), time: acc }, Forcing { shape: beam.load(|_| 8.0 * self.k2 / l4), time: phi.clone() }];
            let (p0, dp0) = (phi.value(0.0), phi.derivative_at(0.0).unwrap_or(0.0));
            init.u = beam.interpolate(|x| -p0 * self.lifting(x).0, |x| -p0 * self.lifting(x).1);
            init.v = beam.interpolate(|x| -dp0 * self.lifting(x).0, |x| -dp0 * self.lifting(x).1);
        }
        if let Some((u, v)) = &exc.start {
            if u.len() != init.u.len() || v.len() != init.v.len() {
                return Err(RunError::Invalid { field: "start", value: u.len() as f64, allowed: "a state of the beam's number of unknowns" });
            }
            let phi = exc.support_motion(self);
            let h = beam.interpolate(|x| self.lifting(x).0, |x| self.lifting(x).1);
            let (p0, dp0) = (phi.value(0.0), phi.derivative_at(0.0).unwrap_or(0.0));
            init.u = u.iter().zip(&h).map(|(a, b)| a - p0 * b).collect();
            init.v = v.iter().zip(&h).map(|(a, b)| a - dp0 * b).collect();
        }
        if let Some((node, q)) = &exc.load {
            let shape = match node {
                Some(i) => {
                    let d = node_dof(beam, *i).ok_or(RunError::Invalid { field: "load.x", value: *i as f64, allowed: "a node that is an unknown (not the clamped support)" })?;
                    let mut e = vec![0.0; beam.dofs()];
                    e[d] = 1.0 / self.rho_s;
                    e
                }
                None => beam.load(|_| 1.0 / self.rho_s),
            };
            dy.forcing.push(Forcing { shape, time: q.clone() });
        }
        Ok(())
    }
}

impl Pipe {
    /// The absolute state `(ũ, ũ_t) = (u + h φ(t), u_t + h φ'(t))` at the
    /// unknowns of the lifted state `(u, u_t)` at time `t` under `exc`'s
    /// support motion.
    pub fn absolute_state(&self, beam: &Beam, exc: &BeamExcitation, u: &[f64], v: &[f64], t: f64) -> (Vec<f64>, Vec<f64>) {
        let phi = exc.support_motion(self);
        let h = beam.interpolate(|x| self.lifting(x).0, |x| self.lifting(x).1);
        let (p, dp) = (phi.value(t), phi.derivative_at(t).unwrap_or(0.0));
        (u.iter().zip(&h).map(|(a, b)| a + p * b).collect(), v.iter().zip(&h).map(|(a, b)| a + dp * b).collect())
    }
}

/// The displacement unknown of beam node `node` (`1..=J`; node 0 is
/// clamped): `2 (node - 1)`.
pub fn node_dof(beam: &Beam, node: usize) -> Option<usize> {
    (1..=beam.elements).contains(&node).then(|| 2 * (node - 1))
}

impl Pipe {
    /// The semi-discrete problem with the contact list `stops` (on the
    /// displacement `u = ũ − hφ` at each stop's node, as the paper's
    /// problem (P) constrains it; `h(L) = 0`, so at the tip it is the
    /// physical displacement) instead of the tip's two stops. Refused,
    /// naming `stop.<i>.<field>`: nodes outside `1..=J`, `lo > hi`, two
    /// stops on one node, an initial state (`u = 0`) outside a stop.
    pub fn dynamics_with_stops(&self, j: usize, stops: &[Stop]) -> Result<(Beam, Dynamics, Initial), RunError> {
        let (beam, mut dy, init) = self.dynamics(j)?;
        check_stops(stops, &init.u, |node| node_dof(&beam, node))?;
        dy.contacts = contacts_of(stops, |node| 2 * (node - 1), false);
        Ok((beam, dy, init))
    }
}

/// How a beam's penalty spring ([`BeamScene::spring`], a stop's own
/// stiffness) enters the scaled
/// equation `u_tt + k² u_xxxx = f` (unit `ρS`, docs/theory.md §1.2, §4.6.1).
///
/// The paper gives its spring as `1/ε = 10⁸ N/m` without saying how it was
/// scaled; its reported violation (2.25e-4 m at dt = 5e-7 s) is close to what
/// the number gives when used unscaled, not to what the physical spring gives
/// (docs/theory.md §8.1). Both readings are offered so that both can be run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PenaltyUnits {
    /// A physical spring in N/m: the scaled equation uses `κ = stiffness/ρS`
    /// (s⁻²). The default.
    #[default]
    NewtonPerMetre,
    /// The number used as is in the scaled equation, `κ = stiffness` (s⁻²):
    /// a spring `ρS` times the physical one (8.4× softer for the pipe).
    Unscaled,
}

impl PenaltyUnits {
    /// Both readings, the default first.
    pub const ALL: [PenaltyUnits; 2] = [PenaltyUnits::NewtonPerMetre, PenaltyUnits::Unscaled];

    /// The stiffness `κ` (s⁻²) of the scaled equation for `stiffness` read in
    /// these units, for a pipe of mass per length `rho_s` (kg/m).
    pub fn kappa(self, stiffness: f64, rho_s: f64) -> f64 {
        match self {
            PenaltyUnits::NewtonPerMetre => stiffness / rho_s,
            PenaltyUnits::Unscaled => stiffness,
        }
    }

    /// A short name for tables and file columns: `N/m` or `unscaled`.
    pub fn label(self) -> &'static str {
        match self {
            PenaltyUnits::NewtonPerMetre => "N/m",
            PenaltyUnits::Unscaled => "unscaled",
        }
    }
}

/// A run of the beam between stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamScene {
    /// Name (`fig2` … `fig8` for the paper's figures).
    pub name: &'static str,
    /// Elements `J`.
    pub elements: usize,
    /// Time step (s).
    pub dt: f64,
    /// Horizon (s).
    pub t_end: f64,
    /// The time scheme: any of the registry that takes the beam's structure
    /// (`Capabilities::beam`). The paper's projection is `ps(0, β)` (the
    /// β-scheme with the exact projection, e = 0), its normal compliance
    /// `penalty-cn` (Newmark β = 1/4) with a [`spring`](Self::spring).
    pub scheme: SchemeSpec,
    /// The spring (N/m, read in the build's [`PenaltyUnits`]) of every
    /// contact without its own stiffness, for a penalty scheme
    /// (`Capabilities::stiffness`); `None`: the scheme's own rule (`γ_P K_cc`).
    /// Refused with a scheme that has no spring.
    pub spring: Option<f64>,
    /// The paper's Scilab run time (s, 1.1 GHz machine, 2003), if any.
    pub paper_seconds: Option<f64>,
}

impl BeamScene {
    /// The paper's figures 2–8 (docs/theory.md §8.1), J = 19, T = 2 s: the
    /// projection (`ps(0, β)`) or the penalty spring of 10⁸ N/m (`penalty-cn`).
    pub const PAPER: [BeamScene; 7] = [
        BeamScene::paper("fig2", 5e-5, SchemeSpec::ps(0.0, 0.5), None, 18.24),
        BeamScene::paper("fig3", 5e-6, SchemeSpec::ps(0.0, 0.5), None, 173.71),
        BeamScene::paper("fig4", 1e-6, SchemeSpec::ps(0.0, 0.5), None, 870.45),
        BeamScene::paper("fig5", 5e-6, SchemeSpec::penalty(10.0, false), Some(1e8), 241.17),
        BeamScene::paper("fig6", 1e-6, SchemeSpec::penalty(10.0, false), Some(1e8), 1187.9),
        BeamScene::paper("fig7", 5e-7, SchemeSpec::penalty(10.0, false), Some(1e8), 2426.4),
        BeamScene::paper("fig8", 1e-6, SchemeSpec::ps(0.0, 0.25), None, 859.38),
    ];

    const fn paper(name: &'static str, dt: f64, scheme: SchemeSpec, spring: Option<f64>, seconds: f64) -> Self {
        BeamScene { name, elements: 19, dt, t_end: 2.0, scheme, spring, paper_seconds: Some(seconds) }
    }

    /// A scene of `elements` elements with `scheme` (no spring, no paper time).
    pub fn new(name: &'static str, elements: usize, dt: f64, t_end: f64, scheme: SchemeSpec) -> Self {
        BeamScene { name, elements, dt, t_end, scheme, spring: None, paper_seconds: None }
    }

    /// β when the scheme is the paper's projection — `ps(0, β)`, no spring —
    /// else `None` (what the reports word with the paper's β-scheme).
    pub fn projection_beta(&self) -> Option<f64> {
        self.scheme.param("beta").filter(|&b| self.scheme == SchemeSpec::ps(0.0, b) && self.spring.is_none())
    }

    /// The same scene with the spring `stiffness` (N/m) on every contact
    /// without its own ([`BeamScene::spring`]).
    pub fn with_spring(mut self, stiffness: f64) -> Self {
        self.spring = Some(stiffness);
        self
    }
}

/// The stability limit of the β-scheme on a beam (docs/theory.md, "Stability").
///
/// Splitting the two-step scheme's discrete energy exactly shows it is
/// unconditionally stable for β >= 1/4 (the projection only removes energy)
/// and, for β < 1/4, stable iff `dt < 2 / sqrt((1 - 4β) κ_h)`. The paper's
/// condition (3.1), `dt < 2 sqrt((1 - α)/(κ_h (1 - 2β)))` (α → 0), is a
/// sufficient condition of its proof, not a limit: it is reported, never
/// enforced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilityLimit {
    /// `κ_h`, the largest generalized eigenvalue of `(K, M)`.
    pub kappa: f64,
    /// The exact critical time step: `2 / sqrt((1 - 4β) κ_h)` for β < 1/4,
    /// `∞` for β >= 1/4.
    pub dt_critical: f64,
    /// The paper's sufficient condition (3.1) with α → 0 and the exact
    /// `κ_h`: `2 / sqrt((1 - 2β) κ_h)` (∞ for β = 1/2).
    pub dt_sufficient: f64,
    /// The paper's sufficient condition (3.1) with its appendix upper bound
    /// (5.2) of `κ_h`, `κ̄ = 24·420·19²/37 · k²/h⁴` (the paper's
    /// 3.3469e-6 s for J = 19, β = 1/4).
    pub dt_paper: f64,
}

/// The exact critical time step of the two-step β-scheme on a pencil whose
/// largest generalized eigenvalue is `kappa`: `2 / sqrt((1 - 4β) κ)` for
/// β < 1/4, `∞` otherwise.
pub fn beta_scheme_critical_dt(beta: f64, kappa: f64) -> f64 {
    signorini_schemes::beta_scheme_critical_dt(beta, kappa)
}

/// `κ_h` and the critical time steps for β.
pub fn stability_limit(beam: &Beam, beta: f64) -> Result<StabilityLimit, RunError> {
    let (k, m) = (beam.stiffness(), beam.mass());
    let (kappa, _) = max_generalized_eigenvalue(&k, &m, beam.element_kappa_bound() * (1.0 + 1e-3), 1_000_000)?;
    let paper = 24.0 * 420.0 * 361.0 / 37.0 * beam.k2 / beam.h().powi(4);
    let sufficient = |kap: f64| if beta >= 0.5 { f64::INFINITY } else { 2.0 / ((1.0 - 2.0 * beta) * kap).sqrt() };
    Ok(StabilityLimit { kappa, dt_critical: beta_scheme_critical_dt(beta, kappa), dt_sufficient: sufficient(kappa), dt_paper: sufficient(paper) })
}

/// Everything a beam run is built from, in one place: the pipe, the scene
/// (elements, dt, scheme, spring), the units of its springs, the contact
/// list (`None`: the tip's two stops), the excitation, whether a
/// conditionally stable scheme may run past its limit, and a reduction.
/// [`BeamSetup::problem`] is the semi-discrete problem, [`BeamSetup::build`]
/// the integrator on it (or on its reduction).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct BeamSetup {
    /// The pipe and its support motion.
    pub pipe: Pipe,
    /// Elements, time step, horizon, scheme and spring.
    pub scene: BeamScene,
    /// How the scene's spring and each stop's own stiffness are read.
    pub units: PenaltyUnits,
    /// The contact list instead of the tip's two stops
    /// ([`Pipe::dynamics_with_stops`]).
    pub stops: Option<Vec<Stop>>,
    /// The support motion beyond the pipe's sine, a load, a start state.
    pub excitation: BeamExcitation,
    /// Run a conditionally stable scheme at or beyond its stability limit
    /// ([`SchemeSpec::beyond_limit`]).
    pub force: bool,
    /// Integrate the massless-boundary reduction (docs/theory.md §2.5)
    /// keeping these modes.
    pub reduce: Option<signorini_reduce::Keep>,
}

/// A beam run's integrator and what it stands on.
pub struct BuiltBeam {
    /// The integrator (on the reduced coordinates when reduced).
    pub stepper: Box<dyn Stepper>,
    /// The full problem's initial state.
    pub initial: Initial,
    /// The beam.
    pub beam: Beam,
    /// The reduction, when [`BeamSetup::reduce`] was given (its basis and
    /// the initial state in reduced coordinates).
    pub reduced: Option<crate::reduced::Reduced>,
}

impl BeamSetup {
    /// The scene on the pipe: springs in N/m, the tip's two stops, the
    /// pipe's sine support, the limit enforced, the full model.
    pub fn new(pipe: Pipe, scene: BeamScene) -> Self {
        BeamSetup { pipe, scene, units: PenaltyUnits::NewtonPerMetre, stops: None, excitation: BeamExcitation::default(), force: false, reduce: None }
    }

    /// Reads the springs in `units`.
    pub fn with_units(mut self, units: PenaltyUnits) -> Self {
        self.units = units;
        self
    }

    /// The contact list `stops` instead of the tip's two stops.
    pub fn with_stops(mut self, stops: Vec<Stop>) -> Self {
        self.stops = Some(stops);
        self
    }

    /// The excitation `excitation` ([`Pipe::excite`]).
    pub fn with_excitation(mut self, excitation: BeamExcitation) -> Self {
        self.excitation = excitation;
        self
    }

    /// Whether a conditionally stable scheme may run beyond its limit.
    pub fn forced(mut self, force: bool) -> Self {
        self.force = force;
        self
    }

    /// Integrates the reduction keeping `keep`'s modes.
    pub fn reduced(mut self, keep: signorini_reduce::Keep) -> Self {
        self.reduce = Some(keep);
        self
    }

    /// The semi-discrete problem: the beam, its stops (or the tip's two),
    /// the excitation; every contact's spring — its own, else the scene's —
    /// read in [`BeamSetup::units`] (the scaled equation's `κ`).
    pub fn problem(&self) -> Result<(Beam, Dynamics, Initial), RunError> {
        let (pipe, scene) = (&self.pipe, &self.scene);
        if !(scene.dt > 0.0 && scene.dt.is_finite()) {
            return Err(RunError::Invalid { field: "dt", value: scene.dt, allowed: "finite and > 0" });
        }
        let (beam, mut dy, mut init) = match &self.stops {
            None => pipe.dynamics(scene.elements)?,
            Some(stops) => pipe.dynamics_with_stops(scene.elements, stops)?,
        };
        pipe.excite(&beam, &mut dy, &mut init, &self.excitation)?;
        // A stop's own spring is read in `units`; a contact without one gets
        // the scene's spring as is (a physical N/m spring, not scaled by K_cc).
        let scene_kappa = scene.spring.map(|k| self.units.kappa(k, pipe.rho_s));
        for c in &mut dy.contacts {
            c.stiffness = c.stiffness.map(|k| self.units.kappa(k, pipe.rho_s)).or(scene_kappa);
        }
        Ok((beam, dy, init))
    }

    /// The integrator: the scene's registry scheme on [`BeamSetup::problem`]
    /// (or its reduction). Refused, naming `beam.scheme`, a scheme that does
    /// not take the beam's structure (or, reduced, a massless contact
    /// node); naming `beam.penalty_stiffness`, a spring with a scheme that
    /// has none; a conditionally stable scheme at or beyond its limit
    /// unless [`BeamSetup::force`] (the scheme's `Unstable` error).
    pub fn build(&self) -> Result<BuiltBeam, RunError> {
        let (beam, dy, initial) = self.problem()?;
        let spec = if self.force { self.scene.scheme.beyond_limit() } else { self.scene.scheme };
        let caps = spec.capabilities();
        if !caps.beam {
            return Err(RunError::NotAllowed { field: "beam.scheme", allowed: "a scheme that takes the beam's structure (signorini list: the presets marked beam)" });
        }
        if self.scene.spring.is_some() && !caps.stiffness {
            return Err(RunError::NotAllowed { field: "beam.penalty_stiffness", allowed: "with a penalty scheme (a spring), not with this scheme" });
        }
        let dt = self.scene.dt;
        match self.reduce {
            None => Ok(BuiltBeam { stepper: spec.build(dy, dt, &initial)?, initial, beam, reduced: None }),
            Some(keep) => {
                if !caps.accepts_massless_node(true) {
                    return Err(RunError::NotAllowed { field: "beam.scheme", allowed: "with reduce, a scheme that takes a massless contact node (the reduced model's contacts are massless)" });
                }
                let red = crate::reduced::reduce(&dy, &initial, keep)?;
                let stepper = spec.build(red.dynamics.clone(), dt, &red.initial)?;
                Ok(BuiltBeam { stepper, initial, beam, reduced: Some(red) })
            }
        }
    }
}
