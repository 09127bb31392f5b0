//! What a validated scene states of itself for the front ends
//! ([`Scene::facts`]): its clock, scheme, contacts, the series' column
//! names, its exact solution and norms, its plots with titles and units,
//! the nodes of its snapshots, the estimates `check` states. `signorini
//! run`, Python's `run()`/`check()` and the check report read these and
//! never switch on the kind of scene: the knowledge of each kind lives
//! here, one arm per kind.

use crate::{ContactSet, Scene, SceneFile};
use signorini_exact::ExactSolution;
use signorini_run::{BarProblem, Benchmark, NormObserver, RunError, SeriesColumns};
use signorini_schemes::{SchemeSpec, TimeProfile};

/// The kind of a scene: its table (`[bar]`, `[beam]`, `[oscillator]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Kind {
    /// `[bar]`.
    Bar,
    /// `[beam]`.
    Beam,
    /// `[oscillator]`.
    Oscillator,
}

/// The exact curve a plot draws against the numerical one.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum ExactCurve {
    /// The displacement `u(x, t)` at this `x`.
    U(f64),
    /// The contact force `λ(t)`.
    Lambda,
    /// The energy.
    Energy,
}

/// One line plot of a run (numerical, and the exact curve where the scene
/// has an exact solution).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Plot {
    /// The file (`u_contact.svg`, …).
    pub file: &'static str,
    /// The title.
    pub title: String,
    /// The axes' labels (time, value), with units where the scene has them.
    pub axes: (&'static str, &'static str),
    /// The exact curve drawn with it, if the scene has an exact solution.
    pub exact: Option<ExactCurve>,
}

impl Plot {
    fn new(file: &'static str, title: impl Into<String>, axes: (&'static str, &'static str), exact: Option<ExactCurve>) -> Self {
        Self { file, title: title.into(), axes, exact }
    }
}

/// The displacement at the mesh nodes for `snapshots.csv`.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SnapshotNodes {
    /// The file's header (`n,t,x,u`, or with units `n,t_s,x_m,u_m`).
    pub header: &'static str,
    /// `(x, the unknown holding u(x) or None where u = 0, lifting h(x))`
    /// per node, in order of x.
    pub nodes: Vec<(f64, Option<usize>, f64)>,
    /// The support motion `φ(t)` added as `h(x) φ(t)` (the beam's
    /// absolute displacement), `None` without a lifting.
    pub support: Option<TimeProfile>,
}

/// The norms of a scene with an exact solution (a bar benchmark): what
/// `norms.csv` and Python's `norms` report.
#[derive(Clone, Copy)]
pub struct Norms<'a> {
    problem: &'a BarProblem,
    benchmark: Benchmark,
}

impl<'a> Norms<'a> {
    /// The observer accumulating every norm against `exact` (the exact
    /// norms of docs/theory.md §6.1).
    pub fn observer<'e>(&self, exact: &'e dyn ExactSolution, dt: f64) -> NormObserver<'e> {
        let p = self.problem;
        NormObserver::with_degree(exact, p.bar.elements, p.bar.degree, p.vnorm(), dt, Default::default())
    }

    /// The convergence study's level `m` (`bar-mirrored`: elements per
    /// half-bar) and `dx`, for `norms.csv`.
    pub fn level(&self) -> (usize, f64) {
        let p = self.problem;
        let level = if self.benchmark == Benchmark::BarMirrored { p.bar.elements / 2 } else { p.bar.elements };
        (level, p.bar.h())
    }
}

/// A scene's facts, for every front end ([`Scene::facts`]).
#[non_exhaustive]
pub struct Facts<'a> {
    /// The kind of scene.
    pub kind: Kind,
    /// The scheme.
    pub scheme: SchemeSpec,
    /// Time step.
    pub dt: f64,
    /// Horizon.
    pub t_end: f64,
    /// The forcing frequency `Ω` (`None` without a periodic forcing): the
    /// Poincaré section, impact phases, a sweep's clock.
    pub omega: Option<f64>,
    /// The contacts of `[[stop]]` / `[obstacle]` (`None`: the scene's
    /// default contact), which add the series' `u_c<i>,lambda_<i>,active_<i>`.
    pub contacts: Option<&'a ContactSet>,
    /// The series' column names and whether it writes energies
    /// (`exact` and `contacts` left for the front end: [`Facts::series_columns`]).
    pub columns: SeriesColumns<'static>,
    /// The plot of the tip (the contact dof, the oscillator's `x`, the beam's tip).
    pub tip_plot: Plot,
    /// The plot of the one contact force, without a contact set (with one:
    /// every contact's force in `lambda.svg`, in [`Facts::force_unit`]).
    pub lambda_plot: Option<Plot>,
    /// The plot of the discrete energy.
    pub energy_plot: Option<Plot>,
    /// The unit of the contact forces in `lambda.svg` with a contact set
    /// (empty: scaled units, time axis `t`; else the time axis is `t (s)`).
    pub force_unit: &'static str,
    /// The mesh's nodes (1 for the oscillator), for the output estimate.
    pub nodes: usize,
    /// The memory estimate (bytes).
    pub memory_bytes: f64,
    /// The key of the horizon (`bar.t_end`, …), which a sweep sets.
    pub t_end_key: &'static str,
    /// The norms, where the scene has an exact solution.
    pub norms: Option<Norms<'a>>,
    /// The reduced model's modes, if `reduce` is given.
    pub reduce: Option<signorini_reduce::Keep>,
    /// The first words of the run's summary line.
    headline: Headline,
}

/// The first line of a run's summary, per kind.
enum Headline {
    /// `<benchmark or "bar"> (m elements, mass …, scheme …, dt = …): …`.
    Bar { elements: usize, mass: String },
    /// `oscillator (scheme, dt = …): …; max |x| = …`.
    Oscillator,
    /// `… steps in … s; …; max |tip| = … m (<stops>)`.
    Beam { stops: String },
}

impl Facts<'_> {
    /// The series' columns with the exact solution's and the contacts'
    /// (`contacts`: the dofs of [`Facts::contacts`], in contact order).
    pub fn series_columns<'e>(&self, exact: Option<&'e dyn ExactSolution>, contacts: Option<&'e [usize]>) -> SeriesColumns<'e> {
        SeriesColumns { exact, contacts, ..self.columns }
    }

    /// The series' numeric columns after the step counter (for the output
    /// estimate): `t`, the tip and its velocity, `lambda_t,lambda`, the
    /// energies, the exact solution's three, three per contact.
    pub fn series_width(&self) -> usize {
        5 + if self.columns.energy { 2 } else { 0 } + if self.norms.is_some() { 3 } else { 0 } + 3 * self.contacts.map_or(0, |c| c.sites.len())
    }

    /// The first line of the run's summary for the terminal: `steps`,
    /// `contact_steps`, the loop's `wall` time (s) and the largest |tip|.
    pub fn run_line(&self, file: &SceneFile, steps: usize, contact_steps: usize, wall: f64, max_abs: f64) -> String {
        match &self.headline {
            Headline::Bar { elements, mass } => format!(
                "{} ({elements} elements, mass {mass}, scheme {}, dt = {:e}): {steps} steps in {wall:.3} s, {contact_steps} contact steps",
                file.bar.as_ref().and_then(|b| b.benchmark.clone()).unwrap_or_else(|| "bar".into()),
                self.scheme,
                self.dt,
            ),
            Headline::Oscillator => format!("oscillator ({}, dt = {:e}): {steps} steps in {wall:.3} s, {contact_steps} contact steps; max |x| = {max_abs:.6}", self.scheme, self.dt),
            Headline::Beam { stops } => format!("{steps} steps in {wall:.3} s; {contact_steps} contact steps; max |tip| = {max_abs:.6} m ({stops})"),
        }
    }
}

impl Scene {
    /// The scene's facts: what a front end needs to run and present it
    /// without knowing its kind.
    pub fn facts(&self) -> Facts<'_> {
        let per_contact = |c: Option<&ContactSet>, unknowns: usize| crate::contact_memory(c.map_or(1, |c| c.sites.len()), unknowns);
        match self {
            Scene::Bar(b) => {
                let p = &b.problem;
                let contacts = b.contacts.as_ref();
                let (tip_plot, lambda_plot) = match contacts {
                    Some(set) => (Plot::new("u_contact.svg", format!("u at contact 0 (x = {})", set.sites[0].x), ("t", "u"), None), None),
                    None => {
                        (Plot::new("u_contact.svg", "u(0,t)", ("t", "u(0,t)"), Some(ExactCurve::U(0.0))), Some(Plot::new("lambda.svg", "contact force λ(t)", ("t", "λ"), Some(ExactCurve::Lambda))))
                    }
                };
                Facts {
                    kind: Kind::Bar,
                    scheme: b.scheme,
                    dt: b.dt,
                    t_end: b.t_end,
                    omega: b.omega,
                    contacts,
                    columns: SeriesColumns::default(),
                    tip_plot,
                    lambda_plot,
                    energy_plot: Some(Plot::new("energy.svg", "discrete energy", ("t", "E"), Some(ExactCurve::Energy))),
                    force_unit: "",
                    nodes: p.bar.last_node() + 1,
                    memory_bytes: crate::memory_estimate(p.bar.last_node(), false) + per_contact(contacts, p.bar.dofs()),
                    t_end_key: "bar.t_end",
                    norms: b.benchmark.map(|benchmark| Norms { problem: p, benchmark }),
                    reduce: b.reduce,
                    headline: Headline::Bar { elements: p.bar.elements, mass: p.mass.to_string() },
                }
            }
            Scene::Oscillator { scheme, dt, t_end, omega, .. } => Facts {
                kind: Kind::Oscillator,
                scheme: *scheme,
                dt: *dt,
                t_end: *t_end,
                omega: *omega,
                contacts: None,
                columns: SeriesColumns { t: "t", u: "x", v: "v", energy: true, exact: None, contacts: None },
                tip_plot: Plot::new("x.svg", "oscillator displacement x(t)", ("t", "x"), None),
                lambda_plot: None,
                energy_plot: None,
                force_unit: "",
                nodes: 1,
                memory_bytes: crate::memory_estimate(1, false) + per_contact(None, 1),
                t_end_key: "oscillator.t_end",
                norms: None,
                reduce: None,
                headline: Headline::Oscillator,
            },
            Scene::Beam { pipe, scene, contacts, omega, reduce, .. } => Facts {
                kind: Kind::Beam,
                scheme: scene.scheme,
                dt: scene.dt,
                t_end: scene.t_end,
                omega: *omega,
                contacts: contacts.as_ref(),
                columns: SeriesColumns { t: "t_s", u: "tip_m", v: "v_tip_m_s", energy: false, exact: None, contacts: None },
                tip_plot: Plot::new("tip.svg", "tip of the beam ũ(L,t)", ("t (s)", "ũ(L,t) (m)"), None),
                lambda_plot: None,
                energy_plot: None,
                force_unit: " (scaled equation: force / ρS, m² s⁻²)",
                nodes: scene.elements + 1,
                memory_bytes: crate::memory_estimate(scene.elements, true) + per_contact(contacts.as_ref(), 2 * scene.elements),
                t_end_key: "beam.t_end",
                norms: None,
                reduce: *reduce,
                headline: Headline::Beam {
                    stops: match contacts {
                        Some(c) => format!("{} contacts", c.sites.len()),
                        None => format!("stops {:?}", pipe.stops),
                    },
                },
            },
        }
    }

    /// The exact solution, where the scene has one (a bar benchmark).
    pub fn exact(&self) -> Result<Option<Box<dyn ExactSolution>>, RunError> {
        match self {
            Scene::Bar(b) => b.benchmark.map(|bench| bench.exact(b.t_end)).transpose(),
            Scene::Oscillator { .. } | Scene::Beam { .. } => Ok(None),
        }
    }

    /// What `signorini check` states of the scene's kind: the text (with
    /// `probe_cost`, an event-driven run's cost line, in place of the
    /// estimate), the steps and the stability limit.
    pub(crate) fn check_text(&self, probe_cost: Option<&str>) -> Result<(String, usize, Option<f64>), crate::BuildError> {
        match self {
            Scene::Bar(b) => crate::bar::check_text(b, probe_cost),
            Scene::Beam { pipe, scene, force, .. } => crate::beam::check_text(&self.beam_setup().expect("a beam scene"), pipe, scene, *force, probe_cost),
            Scene::Oscillator { osc, scheme, dt, t_end, omega, .. } => crate::oscillator::check_text(osc, *scheme, *dt, *t_end, *omega, probe_cost),
        }
    }

    /// The nodes of `snapshots.csv` (`None`: the scene has no mesh, and
    /// validation refuses `snapshots_every`).
    pub fn snapshot_nodes(&self) -> Option<SnapshotNodes> {
        match self {
            Scene::Bar(b) => {
                let bar = &b.problem.bar;
                let nodes = (0..=bar.last_node()).map(|i| (bar.node(i), (i < bar.dofs()).then_some(i), 0.0)).collect();
                Some(SnapshotNodes { header: "n,t,x,u", nodes, support: None })
            }
            Scene::Beam { pipe, scene, excitation, .. } => {
                // Node i at x = i h; its value unknown is 2(i - 1); node 0 is clamped to the support.
                let h = pipe.length / scene.elements as f64;
                let nodes = (0..=scene.elements).map(|i| (i as f64 * h, i.checked_sub(1).map(|k| 2 * k), pipe.lifting(i as f64 * h).0)).collect();
                Some(SnapshotNodes { header: "n,t_s,x_m,u_m", nodes, support: Some(excitation.support_motion(pipe)) })
            }
            Scene::Oscillator { .. } => None,
        }
    }
}
