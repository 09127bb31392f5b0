//! The Lyapunov study (`cargo xtask lyapunov`): the largest Lyapunov
//! exponent of the paper's beam scenes, beam-obstacles and the impact
//! oscillator's sweep range, by Benettin's twin runs
//! (`signorini_run::chaos`), and the predictability horizon it implies.
//!
//! Each case builds its scene twice (`Scene::instantiate`), runs the
//! reference for `transient` forcing periods, perturbs a twin by a relative
//! `perturbation` (default 1e-10) of the state's energy norm
//! `√(uᵀ K u + vᵀ M v)` in a seeded random direction, and renormalises the
//! twin every τ = one `1/intervals_per_period` of a forcing period (whole
//! steps) over `window` forcing periods. `λ_max` is the mean log growth per
//! unit time, its 95 % interval from `batches` batch means (Student t).
//! The horizon is the time for a round-off of 1e-16 relative to the largest
//! displacement of a contact dof over the window to grow to 1 mm at
//! `λ_max`: `ln(1e-3 / (1e-16 · scale)) / λ_max` (empty when λ_max <= 0).
//! The report states a horizon only when the whole interval is above 0:
//! when it contains 0 the sign of λ is undecided, and the report says so
//! ([`horizon_cells`]).
//!
//! Cases: every scene of `scenes` at its own dt and J; the scenes of
//! `refine` again at every `dts` × `elements` (what λ_max does under
//! refinement; a scene's own dt and J once); the oscillator at every Ω of `omegas` (its scene's
//! dt = 1e-3), whose period-1 orbits are stable: there λ_max is known, the
//! Floquet exponent `ln|μ₁| Ω / 2π` of signorini-exact's closed form.
//!
//! Outputs (`--out`, default `out/lyapunov`):
//! * `lyapunov.csv`: `scene,dt,elements,lambda_max,ci_low,ci_high,horizon_s`
//!   (λ in 1/s; `elements` 1 for the oscillator);
//! * `oscillator.csv`: `omega,lambda_max,ci_low,ci_high,lambda_exact,multiplier`.

use crate::{create_dir, fd, fde, fe, ff, int, opt, since, txt, Kind, StudyError, TableOut};
use signorini_exact::{ImpactOscillator, OscillatorParams};
use signorini_run::chaos::{energy_norm, lyapunov, predictability_horizon, Benettin, Flow, StepperFlow};
use signorini_scene::presets::{self, Preset};
use signorini_scene::{Limits, Scene, SceneError, SceneFile};
use signorini_schemes::SchemeSpec;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The beam scenes this study knows: the paper's figures, fig. 2 driven by
/// `[support]` (data/scenes/beam-fig2-support.toml) and the obstacles along
/// the whole pipe (data/scenes/beam-obstacles.toml).
pub const BEAM_SCENES: [&str; 9] = ["fig2-support", "fig2", "fig3", "fig4", "fig5", "fig6", "fig7", "fig8", "beam-obstacles"];

crate::options::study_config! {
    /// Largest Lyapunov exponents by Benettin's twin runs: the twin perturbed
    /// by a relative ⟨perturbation⟩ of the state's energy norm, renormalised
    /// ⟨per_period⟩ times a forcing period over ⟨window⟩ forcing periods after
    /// ⟨transient⟩, a 95 % interval from ⟨batches⟩ batch means. Cases: the beam
    /// ⟨scenes⟩ at their own dt and J, the ⟨refine⟩ scenes at every ⟨dts⟩ ×
    /// ⟨elements⟩, the impact oscillator at every Ω of ⟨omegas⟩.
    /// lyapunov.csv: scene, dt, elements, lambda_max, ci_low, ci_high, horizon_s
    /// (the time for a 1e-16 relative round-off to grow to 1 mm; NaN for
    /// λ <= 0); oscillator.csv: omega, lambda_max, ci_low, ci_high,
    /// lambda_exact, multiplier (the exact Floquet exponent of the period-1
    /// orbit).
    study "lyapunov";
    pub struct Config {
        /// Beam scenes at their own dt and J, comma-separated (fig2-support,
        /// fig2 … fig8, beam-obstacles; default every one;
        /// none: no such case).
        pub scenes: Vec<String> = BEAM_SCENES.iter().map(|s| s.to_string()).collect(),
        /// Beam scenes run again at every ⟨dts⟩ × ⟨elements⟩.
        pub refine: Vec<String> = vec!["fig2-support".into()],
        /// Time steps of the refinement (s), comma-separated.
        pub dts: Vec<f64> = vec![5e-5, 2.5e-5, 1e-5],
        /// Elements J of the refinement, comma-separated.
        pub elements: Vec<usize> = vec![19, 38],
        /// Forcing frequencies of the impact oscillator, comma-separated
        /// (default its sweep range 1.6 … 2.2; none or empty: no oscillator).
        pub omegas: Vec<f64> = vec![1.6, 1.7, 1.8, 1.9, 2.0, 2.1, 2.2],
        /// Relative perturbation of the twin (0 < ε < 1e-3).
        pub perturbation: f64 = 1e-10,
        /// Forcing periods before the twin starts.
        pub transient: f64 = 10.0,
        /// Forcing periods measured.
        pub window: f64 = 20.0,
        /// Renormalisations per forcing period.
        pub per_period: usize = 64,
        /// Batches of the 95 % confidence interval.
        pub batches: usize = 10,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/lyapunov"),
    }
}

impl Config {
    /// Every check, before anything runs.
    pub fn validate(&self) -> Result<(), StudyError> {
        for (flag, list) in [("scenes", &self.scenes), ("refine", &self.refine)] {
            if let Some(s) = list.iter().find(|s| !BEAM_SCENES.contains(&s.as_str())) {
                return Err(StudyError::config(flag, format!("{} {s:?}: allowed {}", crate::options::at(flag), BEAM_SCENES.join(", "))));
            }
        }
        if self.scenes.is_empty() && self.refine.is_empty() && self.omegas.is_empty() {
            return Err(StudyError::config("scenes", "⟨scenes⟩, ⟨refine⟩ and ⟨omegas⟩ are all empty: allowed at least one case"));
        }
        if !self.refine.is_empty() {
            if self.dts.is_empty() || self.dts.iter().any(|d| !(d.is_finite() && *d > 0.0 && *d <= 1e-3)) {
                return Err(StudyError::config("dts", format!("⟨dts⟩ {:?}: allowed at least one, each finite and in (0, 1e-3]", self.dts)));
            }
            if self.elements.is_empty() || self.elements.iter().any(|&j| !(2..=1000).contains(&j)) {
                return Err(StudyError::config("elements", format!("⟨elements⟩ {:?}: allowed at least one, each in [2, 1000]", self.elements)));
            }
        }
        if self.omegas.iter().any(|w| !(w.is_finite() && *w > 0.0 && *w <= 100.0)) {
            return Err(StudyError::config("omegas", format!("⟨omegas⟩ {:?}: allowed each finite and in (0, 100]", self.omegas)));
        }
        if !(self.perturbation > 0.0 && self.perturbation < 1e-3) {
            return Err(StudyError::config(
                "perturbation",
                format!("⟨perturbation⟩ {}: allowed 0 < perturbation < 1e-3 (relative to the state's energy norm)", signorini_run::text::num(self.perturbation)),
            ));
        }
        if !(self.transient.is_finite() && (0.0..=1e4).contains(&self.transient)) {
            return Err(StudyError::config("transient", format!("⟨transient⟩ {}: allowed finite, in [0, 10000] forcing periods", self.transient)));
        }
        if !(1..=10_000).contains(&self.per_period) {
            return Err(StudyError::config("per_period", format!("⟨per_period⟩ {}: allowed an integer in [1, 10000]", self.per_period)));
        }
        if !(2..=1000).contains(&self.batches) {
            return Err(StudyError::config("batches", format!("⟨batches⟩ {}: allowed an integer in [2, 1000]", self.batches)));
        }
        let most = 1e4;
        if !(self.window.is_finite() && self.window <= most && self.window * self.per_period as f64 >= (10 * self.batches) as f64) {
            return Err(StudyError::config(
                "window",
                format!(
                    "⟨window⟩ {}: allowed finite, at most {most} forcing periods, and at least 10 renormalisations per batch (window · per-period >= 10 · batches = {})",
                    self.window,
                    10 * self.batches
                ),
            ));
        }
        Ok(())
    }

    /// The cases: (scene, dt, elements; `None` = the scene's own) then the oscillator's Ω.
    fn cases(&self) -> Vec<Case> {
        let mut v: Vec<Case> = self.scenes.iter().map(|s| Case::Beam { name: s.clone(), dt: None, elements: None, scheme: None }).collect();
        for s in &self.refine {
            for &j in &self.elements {
                for &dt in &self.dts {
                    v.push(Case::Beam { name: s.clone(), dt: Some(dt), elements: Some(j), scheme: None });
                }
            }
        }
        v.extend(self.omegas.iter().map(|&w| Case::Oscillator { omega: w }));
        v
    }
}

/// What the study computed and wrote ([`crate::Report`]); its tables:
/// `lyapunov.csv`, `oscillator.csv` (when Ω are given).
pub type Output = crate::Report;

#[derive(Clone, Debug)]
#[doc(hidden)]
pub enum Case {
    Beam { name: String, dt: Option<f64>, elements: Option<usize>, scheme: Option<SchemeSpec> },
    Oscillator { omega: f64 },
}

/// The scene of a case with horizon `t_end` (s) (the beam statistics'
/// scenes too): a preset of the scene crate with its horizon, and the beam
/// scenes' dt, J and scheme (the beam statistics' `schemes`) or the
/// oscillator's Ω, set by path (an edit of a key
/// the scene does not have fails, [`presets::set_path`]).
#[doc(hidden)]
pub fn scene_file(case: &Case, t_end: f64) -> Result<SceneFile, SceneError> {
    match case {
        Case::Beam { name, dt, elements, scheme } => {
            let doc = match name.as_str() {
                "fig2-support" => Preset::Fig2Support.document()?,
                "beam-obstacles" => Preset::BeamObstacles.document()?,
                fig => {
                    let mut beam = toml::Table::new();
                    beam.insert("scene".into(), fig.into());
                    toml::Table::from_iter([("beam".to_string(), toml::Value::Table(beam))])
                }
            };
            let mut edits = vec![("beam.t_end", t_end.into())];
            if let Some(dt) = dt {
                edits.push(("beam.dt", (*dt).into()));
            }
            if let Some(j) = elements {
                edits.push(("beam.elements", toml::Value::Integer(*j as i64)));
            }
            if let Some(s) = scheme {
                edits.push(("beam.scheme", s.call().into()));
            }
            presets::edit(doc, &edits)
        }
        Case::Oscillator { omega } => Preset::Oscillator.edited(&[("oscillator.t_end", t_end.into()), ("forcing.omega", (*omega).into())]),
    }
}

/// One case's result.
struct Row {
    scene: String,
    dt: f64,
    elements: usize,
    omega: Option<f64>,
    lambda: f64,
    ci: (f64, f64),
    horizon: f64,
}

/// The scene of a case (for its clock): validated, not built.
fn scene_of(case: &Case, t_end: f64) -> Result<Scene, StudyError> {
    let file = scene_file(case, t_end).map_err(|e| StudyError::failed(label(case), e))?;
    file.validate_with(&Limits::machine()).map_err(|e| StudyError::failed(label(case), e))
}

#[doc(hidden)]
pub fn label(case: &Case) -> String {
    match case {
        Case::Beam { name, .. } => name.clone(),
        Case::Oscillator { omega } => format!("oscillator-{omega}"),
    }
}

/// Runs one case.
fn run_case(a: &Config, case: &Case) -> Result<Row, StudyError> {
    let name = label(case);
    let fail = |e: String| StudyError::Run(format!("{name}: {e}"));
    // The clock first (Ω, dt), at a placeholder horizon.
    let probe = scene_of(case, 1.0)?;
    let (omega, dt, _) = probe.sweep_clock().ok_or_else(|| fail("no periodic forcing".into()))?;
    let period = std::f64::consts::TAU / omega;
    let t_end = ((a.transient + a.window + 1.0) * period / dt).ceil() * dt;
    let scene = scene_of(case, t_end)?;
    let build = || scene.instantiate(None).map_err(|e| StudyError::failed(&name, e));
    let (mut ra, mut rb) = (StepperFlow(build()?.stepper), StepperFlow(build()?.stepper));
    let elements = match (&scene, case) {
        (Scene::Beam { scene, .. }, _) => scene.elements,
        _ => 1,
    };
    let contact_dofs: Vec<usize> = ra.0.dynamics().contacts.iter().map(|c| c.dof).collect();
    let norm = energy_norm(ra.0.as_ref());
    let interval_steps = ((period / a.per_period as f64 / dt).round() as usize).max(1);
    let transient_steps = (a.transient * period / dt).round() as usize;
    // Both through the transient: the twin must be at the reference's time
    // level (its forcing's phase), set_state keeps the level.
    ra.advance(transient_steps).map_err(|e| StudyError::failed(&name, e))?;
    rb.advance(transient_steps).map_err(|e| StudyError::failed(&name, e))?;
    let intervals = ((a.window * period / dt) / interval_steps as f64).round() as usize;
    // Not counted: the first forcing period (the direction aligning).
    let cfg = Benettin { perturbation: a.perturbation, interval_steps, discard: a.per_period, intervals: intervals.max(a.batches), batches: a.batches, seed: 23 };
    // The displacement scale of the horizon: the largest |u| of a contact dof, sampled per interval.
    let mut scale = 0.0_f64;
    let mut scaled = ScaleWatch { inner: &mut ra, dofs: &contact_dofs, scale: &mut scale };
    let r = lyapunov(&mut scaled, &mut rb, &norm, &cfg).map_err(|e| StudyError::failed(&name, e))?;
    let horizon = predictability_horizon(r.lambda, scale, 1e-16, 1e-3);
    Ok(Row { scene: name, dt, elements, omega: matches!(case, Case::Oscillator { .. }).then_some(omega), lambda: r.lambda, ci: (r.ci.low, r.ci.high), horizon })
}

/// A flow that records the largest |u| of some dofs at every read.
struct ScaleWatch<'a> {
    inner: &'a mut StepperFlow,
    dofs: &'a [usize],
    scale: &'a mut f64,
}

impl Flow for ScaleWatch<'_> {
    fn dt(&self) -> f64 {
        self.inner.dt()
    }
    fn state(&self) -> Result<Vec<f64>, signorini_run::RunError> {
        self.inner.state()
    }
    fn set_state(&mut self, s: &[f64]) -> Result<(), signorini_run::RunError> {
        self.inner.set_state(s)
    }
    fn advance(&mut self, steps: usize) -> Result<(), signorini_run::RunError> {
        self.inner.advance(steps)?;
        let u = self.inner.0.displacement();
        *self.scale = self.dofs.iter().map(|&d| u[d].abs()).fold(*self.scale, f64::max);
        Ok(())
    }
}

/// The report's e-folding time and horizon of an exponent `lambda` with
/// 95 % interval `ci` and horizon `horizon` (s, at `lambda`): both only
/// when the whole interval is above 0; `∞` when it is below 0; when it
/// contains 0 the sign of λ is undecided, and so is the horizon.
pub fn horizon_cells(lambda: f64, ci: (f64, f64), horizon: f64) -> (String, String) {
    if ci.0 <= 0.0 && 0.0 <= ci.1 {
        ("—".into(), "undecided (the interval contains 0)".into())
    } else if ci.1 < 0.0 {
        ("—".into(), "∞ (λ < 0)".into())
    } else if lambda > 0.0 && horizon.is_finite() {
        (format!("{:.1} ms", 1e3 / lambda), format!("{horizon:.2}"))
    } else {
        // An interval of NaNs (a failed estimate): nothing to say.
        ("—".into(), "—".into())
    }
}

/// The exact λ_max of the oscillator's period-1 orbit at Ω and its largest |μ|.
fn oscillator_exact(omega: f64) -> Option<(f64, f64)> {
    let o = ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: omega, gap: 0.2, restitution: 0.8 }).ok()?;
    let orbits = o.period1_orbits();
    let [orbit] = orbits.as_slice() else { return None };
    let mu = orbit.multipliers.iter().map(|m| m.abs()).fold(0.0, f64::max);
    Some((mu.ln() * omega / std::f64::consts::TAU, mu))
}

/// Runs the study; `progress` after every case.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    a.validate()?;
    create_dir(&a.out)?;
    let start = std::time::Instant::now();
    // Every scene validated before any run (bad dt or J fails at once); a
    // refinement case that is a scene's own (dt, J) is run once.
    let mut cases: Vec<Case> = Vec::new();
    let mut seen: Vec<(String, f64, usize)> = Vec::new();
    for c in a.cases() {
        if let (Scene::Beam { scene, .. }, Case::Beam { name, .. }) = (scene_of(&c, 1.0)?, &c) {
            let key = (name.clone(), scene.dt, scene.elements);
            if seen.contains(&key) {
                continue;
            }
            seen.push(key);
        }
        cases.push(c);
    }
    let rows = crate::run_cases(&cases, progress, &|c| run_case(a, c));
    let (f_, i_, s_) = (Kind::F, Kind::I, Kind::S);
    let mut ly = TableOut::create(&a.out, "lyapunov.csv", &[("scene", s_), ("dt", f_), ("elements", i_), ("lambda_max", f_), ("ci_low", f_), ("ci_high", f_), ("horizon_s", f_)])?;
    let mut osc = (!a.omegas.is_empty())
        .then(|| TableOut::create(&a.out, "oscillator.csv", &[("omega", f_), ("lambda_max", f_), ("ci_low", f_), ("ci_high", f_), ("lambda_exact", f_), ("multiplier", f_)]))
        .transpose()?;
    let mut md = format!(
        "# Largest Lyapunov exponents (Benettin, perturbation {:e}, τ = T/{}, {} periods after {}, 95 % batch means over {} batches; output in {})\n\n| scene | dt (s) | J | λ_max (1/s) | 95 % interval | e-folding time | horizon to 1 mm (s) |\n|---|---|---|---|---|---|---|\n",
        a.perturbation,
        a.per_period,
        a.window,
        a.transient,
        a.batches,
        a.out.display()
    );
    let w_ = |r: std::fmt::Result| r.expect("writing to a String");
    for r in rows {
        let r = r?;
        let horizon = r.horizon.is_finite().then(|| fe(r.horizon, 4));
        ly.row(vec![txt(&r.scene), fde(r.dt), int(r.elements), fe(r.lambda, 6), fe(r.ci.0, 6), fe(r.ci.1, 6), opt(horizon)])?;
        let (efold, hz) = horizon_cells(r.lambda, r.ci, r.horizon);
        w_(writeln!(md, "| {} | {:e} | {} | {:+.3} | [{:+.3}, {:+.3}] | {efold} | {hz} |", r.scene, r.dt, r.elements, r.lambda, r.ci.0, r.ci.1));
        if let (Some(w), Some(t)) = (r.omega, osc.as_mut()) {
            let ex = oscillator_exact(w);
            t.row(vec![fd(w), fe(r.lambda, 6), fe(r.ci.0, 6), fe(r.ci.1, 6), opt(ex.map(|e| fe(e.0, 6))), opt(ex.map(|e| ff(e.1, 6)))])?;
        }
    }
    let mut tables = vec![ly.finish()?];
    if let Some(t) = osc {
        tables.push(t.finish()?);
        w_(writeln!(md, "\nOscillator (stable period-1 orbits): λ_max against the exact Floquet exponent ln|μ₁| Ω/2π in `oscillator.csv`."));
    }
    let wall_s = since(start);
    w_(writeln!(md, "\nwrote {} in {wall_s:.1} s", a.out.display()));
    Ok(Output { tables, report: md, wall_s, notes: Vec::new() })
}
