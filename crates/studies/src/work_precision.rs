//! The work–precision study (`cargo xtask work-precision`): error reached
//! against wall time, per scheme and mass, on `bar-dirichlet` (dx/dt = 10,
//! T = 3) and `bar-neumann-gravity` (dx/dt = 1, T = 16; 10 for the explicit
//! schemes, whose CFL limit is below h), then the accuracy–cost frontier on
//! the same axes (docs/theory.md §2.5, §4.10):
//!
//! * `cd-taylor` with the lumped P1 mass at Courant number one (`dt = h/c`,
//!   Taylor's start), on the levels and two doublings beyond the finest;
//! * P2 and P3 elements (`--degrees`): `newmark-cn` and `newmark-ii` with the
//!   `std` and `mod` masses, dx/dt as for P1 (`dx` the element size);
//! * reduced models (`--modes`): the massless-boundary reduction of the
//!   `mod` bar to r fixed-interface modes, `newmark-cn`, levels with at least
//!   r interior modes;
//! * the beam of the paper's figure 2 (`beam-fig2`: J = 19, β = 1/2, the
//!   projection, `--beam-dts`), full model and its massless-tip reductions to
//!   `--modes` modes, against a full-model reference at `--beam-ref-dt`
//!   (or, with `--reference event-driven`, the exact semi-discrete solution
//!   of docs/theory.md §9, `event-driven(0)`, the projection scheme's limit
//!   as dt → 0): largest tip error over `[0, --beam-window]` (the window in
//!   which the reference is converged in dt, reported), over
//!   `[0, --beam-t-end]`, and the error of the first impact time.
//!
//! Outputs (`out/work-precision/`): `work_precision.csv` with columns
//! `benchmark,scheme,mass,m,dt,steps,l2_l2_u,linf_energy,wall_s` then
//! `degree,modes,tip_err,tip_err_end,impact_err` then
//! `linf_l2_u,linf_v_u,l2_v_u,l2_lambda,l2_energy,release_err` then
//! `impact_power,impact_power_low,impact_power_high,impact_power_rel_err`
//! then `setup_s,step_s` (`wall_s` and `step_s`: the stepping alone, best
//! of 3, runs one at a time; `setup_s`: the set-up of the same runs, best
//! of 3 — the problem and the scheme built as `signorini run` builds them,
//! CFL check and factorisations included; `modes` 0 for a full model; the
//! bar rows leave the three beam columns empty, the beam rows the norm
//! columns; `m` is J and `degree` 3, Hermite cubics, for the beam;
//! `release_err` is |first discrete − first exact release time|; the
//! impact-power rows are the beam with its support motion, `wall_s` and
//! `step_s` the whole run, `setup_s` empty), `<benchmark>.svg` per benchmark (log-log, L²(0,T;L²) error —
//! the beam's tip error — against wall time) and for the bars
//! `<benchmark>-strain.svg` (L∞(0,T;V)) and `<benchmark>-force.svg` (λ in
//! L²(0,T)), and on stdout the cheapest configuration reaching each
//! accuracy band in each of the three quantities, a configuration whose
//! error does not fall with m in a quantity (least-squares rate below 0.1,
//! unless it is round-off) marked so wherever it is named.

use crate::{create_dir, fe, int, opt, since, txt, Kind, StudyError, TableOut};
use rayon::prelude::*;
use signorini_fem::BarMass;
use signorini_norms::NormReport;
use signorini_plot::{line_chart, Chart, Scale, Series};
use signorini_reduce::Keep;
use signorini_run::beam::{build_excited, build_reduced, BeamContact, BeamExcitation, BeamScene, PenaltyUnits, Pipe};
use signorini_run::stats::{batch_means, Interval};
use signorini_run::study::{self, StudyConfig};
use signorini_run::{run as run_steps, Benchmark, NormObserver, Observer, RunConfig, RunError, Sample};
use signorini_schemes::{SchemeSpec, Stepper};
use std::fmt::Write as _;
use std::path::PathBuf;

/// What to run.
#[derive(Clone, Debug)]
pub struct Config {
    /// Output folder (`--out`, default `out/work-precision`).
    pub out: PathBuf,
    /// Levels m (`--levels`, default 10, 20, …, 640).
    pub levels: Vec<usize>,
    /// Element degrees beyond P1 (`--degrees`, default 2, 3; empty: none).
    pub degrees: Vec<usize>,
    /// Kept modes of the reduced models, bar and beam (`--modes`, default
    /// 2, 4, 8, 16; empty: none).
    pub modes: Vec<usize>,
    /// Time steps of the beam rows (`--beam-dts`, default 1e-5 … 5e-4 s;
    /// empty: no beam rows).
    pub beam_dts: Vec<f64>,
    /// The beam reference's time step (`--beam-ref-dt`, default 2.5e-7 s).
    pub beam_ref_dt: f64,
    /// The beam's error window `[0, w]` (`--beam-window`, default 0.1 s).
    pub beam_window: f64,
    /// The beam's horizon (`--beam-t-end`, default 1 s).
    pub beam_t_end: f64,
    /// Time steps of the beam-statistics rows (`--beam-stat-dts`, default
    /// 5e-5, 2.5e-5, 1e-5 s; empty: none): fig. 2 with `[support]`, its
    /// impact power over a long window against the run at `beam_stat_ref_dt`.
    pub beam_stat_dts: Vec<f64>,
    /// The impact power's reference step (`--beam-stat-ref-dt`, default 5e-6 s).
    pub beam_stat_ref_dt: f64,
    /// The statistics window in forcing periods (`--beam-stat-window`,
    /// default 320: 201 s at ω = 10; 20 batches, after 10 periods).
    pub beam_stat_window: f64,
    /// The beam rows' reference (`--reference`, default the fine step).
    pub reference: BeamReference,
}

/// The reference of the beam rows' tip errors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BeamReference {
    /// The same scheme at `--beam-ref-dt` (`fine-step`).
    #[default]
    FineStep,
    /// The exact semi-discrete solution (`event-driven`: the scheme
    /// `event-driven(0)`, the limit of the projection scheme as dt → 0;
    /// docs/theory.md §9), sampled at the largest step that divides every
    /// `--beam-dts` (no interpolation), its first impact from its event log.
    EventDriven,
}

impl std::str::FromStr for BeamReference {
    type Err = StudyError;
    fn from_str(s: &str) -> Result<Self, StudyError> {
        match s {
            "fine-step" => Ok(Self::FineStep),
            "event-driven" => Ok(Self::EventDriven),
            _ => Err(StudyError::config("--reference", format!("--reference {s:?}: allowed fine-step, event-driven"))),
        }
    }
}

impl Default for Config {
    /// `cargo xtask work-precision` without options.
    fn default() -> Self {
        Config {
            out: PathBuf::from("out/work-precision"),
            levels: vec![10, 20, 40, 80, 160, 320, 640],
            degrees: vec![2, 3],
            modes: vec![2, 4, 8, 16],
            beam_dts: vec![1e-5, 2.5e-5, 5e-5, 1e-4, 2.5e-4, 5e-4],
            beam_ref_dt: 2.5e-7,
            beam_window: 0.1,
            beam_t_end: 1.0,
            beam_stat_dts: vec![5e-5, 2.5e-5, 1e-5],
            beam_stat_ref_dt: 5e-6,
            beam_stat_window: 320.0,
            reference: BeamReference::FineStep,
        }
    }
}

/// The Courant-one levels: the configured ones and two doublings beyond the finest.
fn courant1_levels(levels: &[usize]) -> Vec<usize> {
    let mut l = levels.to_vec();
    let top = levels.iter().copied().max().unwrap_or(0);
    l.extend([2 * top, 4 * top]);
    l.sort_unstable();
    l.dedup();
    l
}

impl Config {
    /// Every check done before a file is created; an error names the flag.
    pub fn validate(&self) -> Result<(), StudyError> {
        let schemes: Vec<SchemeSpec> = SchemeSpec::named().map(|(_, s)| s).collect();
        for benchmark in BARS {
            let (ratio, t_end) = benchmark.default_ratio_and_horizon();
            for r in [ratio, ratio.max(10.0)] {
                StudyConfig::new(benchmark, schemes.clone(), vec![BarMass::Std], self.levels.clone(), r, t_end).validate().map_err(|e| StudyError::config("--levels", format!("--levels: {e}")))?;
            }
        }
        if let Some(&k) = self.degrees.iter().find(|&&k| !(2..=3).contains(&k)) {
            return Err(StudyError::config("--degrees", format!("--degrees {k}: allowed 2 and 3 (P1 is always run)")));
        }
        if let Some(&r) = self.modes.iter().find(|&&r| !(1..=10_000).contains(&r)) {
            return Err(StudyError::config("--modes", format!("--modes {r}: allowed integers in [1, 10000] (levels with fewer interior modes are skipped)")));
        }
        if self.reference == BeamReference::EventDriven && self.beam_dts.is_empty() {
            return Err(StudyError::config("--reference", "--reference event-driven: it is the beam rows' reference, and --beam-dts '' asks for none; allowed with beam rows"));
        }
        let (w, te, rdt) = (self.beam_window, self.beam_t_end, self.beam_ref_dt);
        if !(te > 0.0 && te <= 10.0) {
            return Err(StudyError::config("--beam-t-end", format!("--beam-t-end {te}: allowed in (0, 10] s")));
        }
        if !(w > 0.0 && w <= te) {
            return Err(StudyError::config("--beam-window", format!("--beam-window {w}: allowed in (0, --beam-t-end = {te}] s")));
        }
        if !(rdt > 0.0 && rdt.is_finite() && te / rdt <= 4e7) {
            return Err(StudyError::config("--beam-ref-dt", format!("--beam-ref-dt {rdt}: allowed > 0 with at most 4e7 steps to --beam-t-end = {te} s")));
        }
        if let Some(&dt) = self.beam_dts.iter().find(|&&dt| !(dt >= 2.0 * rdt && dt <= w)) {
            return Err(StudyError::config("--beam-dts", format!("--beam-dts {dt}: allowed in [2 × --beam-ref-dt, --beam-window] = [{}, {w}] s", 2.0 * rdt)));
        }
        let stats = self.stat_config(&self.beam_stat_dts);
        stats.validate().map_err(|e| match e {
            StudyError::Config { field, message } => {
                let flag = match field.as_str() {
                    "--dts" => "--beam-stat-dts",
                    _ => "--beam-stat-window",
                };
                StudyError::config(flag, message.replacen(&field, flag, 1))
            }
            other => other,
        })?;
        let r = self.beam_stat_ref_dt;
        if !(r.is_finite() && r > 0.0 && self.beam_stat_dts.iter().all(|&d| d >= 2.0 * r)) {
            return Err(StudyError::config("--beam-stat-ref-dt", format!("--beam-stat-ref-dt {r}: allowed > 0 and at most half of every --beam-stat-dts")));
        }
        self.stat_config(&[r]).validate().map_err(|e| StudyError::config("--beam-stat-ref-dt", format!("--beam-stat-ref-dt {r}: {e}")))?;
        let top = self.levels.iter().copied().max().unwrap_or(0);
        crate::fits_memory("--levels", 4 * top, 1)?;
        crate::fits_memory("--degrees", 3 * top, 1)
    }
}

impl Config {
    /// The beam-statistics configuration of the impact-power rows at `dts`
    /// (fig. 2 with `[support]`, J = 19, 10 periods of transient, 20 batches).
    fn stat_config(&self, dts: &[f64]) -> crate::beam_statistics::Config {
        crate::beam_statistics::Config { dts: if dts.is_empty() { vec![self.beam_stat_ref_dt] } else { dts.to_vec() }, elements: vec![19], window: self.beam_stat_window, ..Default::default() }
    }
}

/// The beam-statistics rows' benchmark name.
pub const BEAM_STATS: &str = "beam-fig2-support";

/// The impact power of fig. 2 with `[support]` at `dt` (J = 19) with its
/// 95 % batch-means interval, the steps and the wall time of the run (the
/// scene's own path, `signorini run`'s, observers included).
fn impact_power(a: &Config, dt: f64) -> Result<(Interval, usize, f64), StudyError> {
    let sc = a.stat_config(&[dt]);
    let start = std::time::Instant::now();
    let (values, steps) = crate::beam_statistics::run_case("fig2-support", dt, 19, &sc)?;
    let wall = since(start);
    let power = batch_means(&values[0], sc.batches, 0.95).ok_or_else(|| StudyError::Run(format!("{BEAM_STATS}, dt = {dt:e}: no interval")))?;
    Ok((power, steps, wall))
}

/// What the study computed and wrote ([`crate::Report`]); its tables: `work_precision.csv`.
pub type Output = crate::Report;

const BARS: [Benchmark; 2] = [Benchmark::BarDirichlet, Benchmark::BarNeumannGravity];

/// The beam benchmark's name in the table.
pub const BEAM: &str = "beam-fig2";

struct Point {
    benchmark: String,
    scheme: String,
    mass: String,
    m: usize,
    dt: f64,
    steps: usize,
    /// Bar rows: every norm of the run.
    norms: Option<NormReport>,
    /// Bar rows: |first discrete release − first exact release| (NaN if
    /// either is missing).
    release_err: Option<f64>,
    wall: f64,
    /// Set-up time (best of 3), seconds.
    setup: f64,
    degree: usize,
    modes: usize,
    /// Beam: tip error over the window, over the horizon, first impact time error.
    beam: Option<(f64, f64, f64)>,
    /// Beam statistics: the impact power with its interval, and its relative
    /// error against the reference run's.
    power: Option<(Interval, f64)>,
}

impl Point {
    /// The configuration's name in the report and the plots.
    fn label(&self) -> String {
        let mut s = format!("{} {}", self.scheme, self.mass);
        if self.degree > 1 && self.benchmark != BEAM {
            write!(s, " P{}", self.degree).expect("writing to a String");
        }
        if self.modes > 0 {
            write!(s, " r={}", self.modes).expect("writing to a String");
        }
        s
    }
    /// The error this benchmark is judged by in quantity `q` (the beam: its
    /// tip over the window, whatever `q`).
    fn error(&self, q: Quantity) -> f64 {
        match (self.beam, self.norms.as_ref()) {
            (Some((w, _, _)), _) => w,
            (None, Some(n)) => q.of(n),
            (None, None) => f64::NAN,
        }
    }
}

/// A quantity the cheapest-per-target tables are given in.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Quantity {
    /// Displacement, L²(0,T;L²).
    U,
    /// Strain: the displacement in V, L∞(0,T;V).
    Strain,
    /// Contact force, L²(0,T).
    Force,
}

impl Quantity {
    const ALL: [Quantity; 3] = [Quantity::U, Quantity::Strain, Quantity::Force];
    fn of(self, n: &NormReport) -> f64 {
        match self {
            Quantity::U => n.l2_l2_u,
            Quantity::Strain => n.linf_v_u,
            Quantity::Force => n.l2_lambda,
        }
    }
    /// Its name in tables and notes.
    fn name(self) -> &'static str {
        match self {
            Quantity::U => "u in L²(0,T;L²)",
            Quantity::Strain => "strain: u in L∞(0,T;V)",
            Quantity::Force => "contact force λ in L²(0,T)",
        }
    }
    /// The column it is read from.
    fn column(self) -> &'static str {
        match self {
            Quantity::U => "l2_l2_u",
            Quantity::Strain => "linf_v_u",
            Quantity::Force => "l2_lambda",
        }
    }
    /// The SVG's file name suffix (`<benchmark><suffix>.svg`).
    fn suffix(self) -> &'static str {
        match self {
            Quantity::U => "",
            Quantity::Strain => "-strain",
            Quantity::Force => "-force",
        }
    }
    fn targets(self) -> &'static [f64] {
        match self {
            Quantity::U => &[3e-2, 1e-2, 3e-3, 1e-3, 3e-4],
            Quantity::Strain | Quantity::Force => &[3e-1, 1e-1, 3e-2, 1e-2, 3e-3],
        }
    }
}

/// Below this every error of a configuration is round-off: exact, not
/// non-convergent (a V norm of nodally exact values is ~1e-8: the square
/// root of a round-off sum).
const ROUND_OFF: f64 = 1e-7;

/// The least-squares rate below which a configuration's error does not fall
/// with m: it is named non-convergent in that quantity.
const NON_CONVERGENT_RATE: f64 = 0.1;

/// The quantities in which the configuration `label` of `pts` does not
/// converge: the least-squares rate of its error against dx over its levels
/// (at least two) below [`NON_CONVERGENT_RATE`], unless every error is
/// round-off.
fn non_convergent(pts: &[&Point], label: &str) -> Vec<Quantity> {
    let mine: Vec<&&Point> = pts.iter().filter(|p| p.label() == label && p.norms.is_some()).collect();
    Quantity::ALL
        .into_iter()
        .filter(|&q| {
            let e: Vec<(f64, f64)> = mine.iter().map(|p| (1.0 / p.m as f64, p.error(q))).collect();
            let rate = study::rate(&e).lsq;
            e.len() >= 2 && e.iter().any(|x| x.1 > ROUND_OFF) && !(rate >= NON_CONVERGENT_RATE)
        })
        .collect()
}

/// The first time the exact contact force goes from nonzero to zero (the
/// first release), to 1e-12: a scan at 1e-3, then bisection.
fn exact_release(exact: &dyn signorini_exact::ExactSolution, t_end: f64) -> Option<f64> {
    let on = |t: f64| exact.lambda(t) != 0.0;
    let step = 1e-3;
    let n = (t_end / step) as usize;
    let first_on = (0..=n).map(|k| k as f64 * step).position(on)?;
    let off = (first_on..=n).map(|k| k as f64 * step).find(|&t| !on(t))?;
    let (mut a, mut b) = (off - step, off);
    while b - a > 1e-12 {
        let mid = 0.5 * (a + b);
        if on(mid) {
            a = mid;
        } else {
            b = mid;
        }
    }
    Some(b)
}

/// Wall times `(set-up, stepping)` of the runs of a stepper that `build`
/// makes (the set-up is `build` itself), no observers, each the best of 3.
/// A stepper ready to run and its initial displacement.
type Built = (Box<dyn Stepper>, Vec<f64>);
/// The same and the beam's unknowns.
type BuiltBeam = (Box<dyn Stepper>, Vec<f64>, usize);

fn best_of_3(build: &dyn Fn() -> Result<Built, StudyError>, dt: f64, t_end: f64) -> Result<(f64, f64), StudyError> {
    let (mut setup, mut step) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..3 {
        let start = std::time::Instant::now();
        let (mut s, u0) = build()?;
        setup = setup.min(start.elapsed().as_secs_f64());
        let start = std::time::Instant::now();
        run_steps(s.as_mut(), &u0, &RunConfig::new(dt, t_end)?, &mut [])?;
        step = step.min(start.elapsed().as_secs_f64());
    }
    Ok((setup, step))
}

fn run_err(e: impl std::error::Error + Send + Sync + 'static) -> StudyError {
    StudyError::failed("", e)
}

/// Wall times `(set-up, stepping)` of a bar level (degree `k`, the
/// reduction `keep` when given), each the best of 3. The set-up is that of
/// `signorini run` on the benchmark's scene: the problem (matrices, exact
/// initial data), the reduction if any, and the scheme with its CFL check.
#[allow(clippy::too_many_arguments)]
fn time_stepping(b: Benchmark, scheme: SchemeSpec, mass: BarMass, m: usize, k: usize, ratio: f64, t_end: f64, keep: Option<Keep>) -> Result<(f64, f64), StudyError> {
    let exact = b.exact(t_end)?;
    let dt = b.problem_with_degree(exact.as_ref(), m, mass, k)?.bar.h() / ratio;
    let build = || -> Result<(Box<dyn Stepper>, Vec<f64>), StudyError> {
        let p = b.problem_with_degree(exact.as_ref(), m, mass, k)?;
        match keep {
            None => Ok((scheme.build(p.dynamics(), dt, &p.initial).map_err(run_err)?, p.initial.u.clone())),
            Some(keep) => {
                let red = signorini_run::reduced::reduce(&p.dynamics(), &p.initial, keep)?;
                Ok((scheme.build(red.dynamics.clone(), dt, &red.initial).map_err(run_err)?, red.initial.u.clone()))
            }
        }
    };
    best_of_3(&build, dt, t_end)
}

/// The Courant-one rows: `cd-taylor`, lumped P1 mass, `dt = h/c`, built as
/// `signorini run` builds `scheme = "cd-taylor"` (through [`SchemeSpec`],
/// CFL check included; this used to call the constructor directly and
/// skip the check).
fn courant1(b: Benchmark, m: usize) -> Result<Point, StudyError> {
    let (_, t_end) = b.default_ratio_and_horizon();
    let exact = b.exact(t_end)?;
    let p = b.problem(exact.as_ref(), m, BarMass::Lumped)?;
    let dt = p.bar.h() / p.bar.wave_speed;
    let build = || -> Result<(Box<dyn Stepper>, Vec<f64>), StudyError> {
        let p = b.problem(exact.as_ref(), m, BarMass::Lumped)?;
        Ok((SchemeSpec::cd_taylor().build(p.dynamics(), dt, &p.initial).map_err(RunError::from)?, p.initial.u.clone()))
    };
    let (mut s, u0) = build()?;
    let mut norms = NormObserver::new(exact.as_ref(), p.bar.elements, p.vnorm(), dt);
    let sum = run_steps(s.as_mut(), &u0, &RunConfig::new(dt, t_end)?, &mut [&mut norms])?;
    let r = norms.report();
    let (setup, wall) = best_of_3(&build, dt, t_end)?;
    let release_err = Some(release_error(norms.first_release(), exact_release(exact.as_ref(), t_end)));
    Ok(Point {
        benchmark: b.to_string(),
        scheme: "cd-taylor".into(),
        mass: BarMass::Lumped.to_string(),
        m,
        dt,
        steps: sum.steps,
        norms: Some(r),
        release_err,
        wall,
        setup,
        degree: 1,
        modes: 0,
        beam: None,
        power: None,
    })
}

/// |discrete − exact| first release time, NaN where either is missing.
fn release_error(discrete: Option<f64>, exact: Option<f64>) -> f64 {
    discrete.zip(exact).map_or(f64::NAN, |(d, e)| (d - e).abs())
}

/// The tip of a beam run at every level, and whether a stop was active.
struct Tip {
    dof: usize,
    u: Vec<f64>,
    active: Vec<bool>,
}

impl Observer for Tip {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        self.u.push(s.u[self.dof]);
        self.active.push(s.active);
        Ok(())
    }
}

impl Tip {
    /// Linear interpolation at `t` of levels `n dt`.
    fn at(&self, t: f64, dt: f64) -> f64 {
        let x = t / dt;
        let n = (x.floor() as usize).min(self.u.len().saturating_sub(2));
        let f = x - n as f64;
        self.u[n] + f * (self.u[n + 1] - self.u[n])
    }
    /// The first level at which a stop is active, as a time.
    fn first_impact(&self, dt: f64) -> Option<f64> {
        self.active.iter().position(|&a| a).map(|n| n as f64 * dt)
    }
    /// Largest difference from `reference` (levels of `ref_dt`) over `[0, t]`.
    fn error(&self, dt: f64, reference: &Tip, ref_dt: f64, t: f64) -> f64 {
        let last = ((t / dt).round() as usize).min(self.u.len() - 1);
        (0..=last).fold(0.0_f64, |e, n| e.max((self.u[n] - reference.at(n as f64 * dt, ref_dt)).abs()))
    }
}

/// A beam configuration: `modes` 0 for the full model.
fn beam_build(dt: f64, t_end: f64, modes: usize) -> Result<BuiltBeam, StudyError> {
    beam_build_with(dt, t_end, modes, BeamContact::Projection { beta: 0.5 })
}

/// [`beam_build`] with another contact treatment.
fn beam_build_with(dt: f64, t_end: f64, modes: usize, contact: BeamContact) -> Result<BuiltBeam, StudyError> {
    let scene = BeamScene { dt, t_end, contact, ..BeamScene::PAPER[0] };
    let (pipe, exc) = (Pipe::paper(), BeamExcitation::default());
    if modes == 0 {
        let (s, init, beam) = build_excited(&pipe, &scene, false, PenaltyUnits::default(), None, &exc)?;
        Ok((s, init.u, beam.tip_dof()))
    } else {
        let (s, red, _) = build_reduced(&pipe, &scene, PenaltyUnits::default(), None, &exc, Keep::Modes(modes))?;
        Ok((s, red.initial.u.clone(), 0))
    }
}

fn beam_tip(dt: f64, t_end: f64, modes: usize) -> Result<(Tip, usize), StudyError> {
    let (mut s, u0, dof) = beam_build(dt, t_end, modes)?;
    let levels = (t_end / dt).round() as usize + 1;
    let mut tip = Tip { dof, u: Vec::with_capacity(levels), active: Vec::with_capacity(levels) };
    let sum = run_steps(s.as_mut(), &u0, &RunConfig::new(dt, t_end)?, &mut [&mut tip])?;
    Ok((tip, sum.steps))
}

/// The exact semi-discrete tip ([`BeamReference::EventDriven`]) sampled
/// every `dt`, and its first impact time (from the event log).
fn beam_tip_exact(dt: f64, t_end: f64) -> Result<(Tip, f64), StudyError> {
    let spec: SchemeSpec = "event-driven(0)".parse().map_err(|e: signorini_schemes::SchemeError| StudyError::Run(e.to_string()))?;
    let (mut s, u0, dof) = beam_build_with(dt, t_end, 0, BeamContact::Scheme(spec))?;
    let levels = (t_end / dt).round() as usize + 1;
    let mut tip = Tip { dof, u: Vec::with_capacity(levels), active: Vec::with_capacity(levels) };
    run_steps(s.as_mut(), &u0, &RunConfig::new(dt, t_end)?, &mut [&mut tip])?;
    let first = s.events().and_then(|e| e.first()).map_or(f64::NAN, |e| e.t);
    Ok((tip, first))
}

/// The largest step that divides every one of `dts` (to 1e-9), at most
/// their smallest: `dt_min / k` for the least `k <= 1000` that works.
fn common_step(dts: &[f64]) -> Option<f64> {
    let min = dts.iter().copied().fold(f64::INFINITY, f64::min);
    (1..=1000).map(|k| min / k as f64).find(|d| dts.iter().all(|dt| ((dt / d) - (dt / d).round()).abs() <= 1e-9 * (dt / d)))
}

/// The beam rows and the reference's own convergence: its difference from
/// the run at twice its step over the window and over the horizon — or,
/// for the event-driven reference, the fine-step reference's difference
/// from the exact solution (how converged the fine step is).
fn beam_points(a: &Config) -> Result<(Vec<Point>, (f64, f64)), StudyError> {
    let (te, w) = (a.beam_t_end, a.beam_window);
    let (reference, rdt, self_conv, t_ref) = match a.reference {
        BeamReference::FineStep => {
            let rdt = a.beam_ref_dt;
            let (reference, _) = beam_tip(rdt, te, 0)?;
            let (check, _) = beam_tip(2.0 * rdt, te, 0)?;
            let self_conv = (check.error(2.0 * rdt, &reference, rdt, w), check.error(2.0 * rdt, &reference, rdt, te));
            let t_ref = reference.first_impact(rdt).unwrap_or(f64::NAN);
            (reference, rdt, self_conv, t_ref)
        }
        BeamReference::EventDriven => {
            let rdt = common_step(&a.beam_dts).unwrap_or(a.beam_ref_dt);
            let (reference, t_ref) = beam_tip_exact(rdt, te)?;
            let (fine, _) = beam_tip(a.beam_ref_dt, te, 0)?;
            let fine_err = (fine.error(a.beam_ref_dt, &reference, rdt, w), fine.error(a.beam_ref_dt, &reference, rdt, te));
            (reference, rdt, fine_err, t_ref)
        }
    };
    let j = BeamScene::PAPER[0].elements;
    let mut points = Vec::new();
    for modes in std::iter::once(0).chain(a.modes.iter().copied().filter(|&r| r < 2 * j)) {
        for &dt in &a.beam_dts {
            let (tip, steps) = beam_tip(dt, te, modes)?;
            let imp = tip.first_impact(dt).map_or(f64::NAN, |t| (t - t_ref).abs());
            let errs = (tip.error(dt, &reference, rdt, w), tip.error(dt, &reference, rdt, te), imp);
            let (setup, wall) = best_of_3(
                &|| {
                    let (s, u0, _) = beam_build(dt, te, modes)?;
                    Ok((s, u0))
                },
                dt,
                te,
            )?;
            let mass = if modes == 0 { "consistent" } else { "massless-tip" };
            points.push(Point {
                benchmark: BEAM.into(),
                scheme: "beta-scheme(0.5)".into(),
                mass: mass.into(),
                m: j,
                dt,
                steps,
                norms: None,
                release_err: None,
                wall,
                setup,
                degree: 3,
                modes,
                beam: Some(errs),
                power: None,
            });
        }
    }
    Ok((points, self_conv))
}

/// Runs the study; `progress` after every (benchmark, scheme) sweep and its
/// timings, then after each block of the frontier rows.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    let schemes: Vec<SchemeSpec> = SchemeSpec::named().map(|(_, s)| s).collect();
    // Everything is checked before a file is created.
    a.validate()?;
    let start = std::time::Instant::now();
    create_dir(&a.out)?;
    let frontier = 2 * (1 + a.degrees.len() + a.modes.len()) as u64 + u64::from(!a.beam_dts.is_empty()) + u64::from(!a.beam_stat_dts.is_empty());
    let total = 2 * schemes.len() as u64 + frontier;
    let mut done = 0;
    let mut tick = || {
        done += 1;
        progress(done, total);
    };
    let mut notes = Vec::new();
    // Every mass treatment (mod1 is mod under another name).
    let masses: Vec<BarMass> = BarMass::ALL.into_iter().filter(|m| *m != BarMass::Mod1).collect();
    let mut points = Vec::new();
    // The exact first release of each bar's horizon.
    let releases: Vec<(String, Option<f64>)> = BARS
        .iter()
        .map(|b| {
            let (_, t_end) = b.default_ratio_and_horizon();
            Ok((b.to_string(), exact_release(b.exact(t_end)?.as_ref(), t_end)))
        })
        .collect::<Result<_, StudyError>>()?;
    let release_of = |b: Benchmark| releases.iter().find(|r| r.0 == b.to_string()).and_then(|r| r.1);
    let full = |b: Benchmark, scheme: SchemeSpec, mass: BarMass, l: &study::LevelResult, k: usize, modes: usize, (setup, wall): (f64, f64)| Point {
        benchmark: b.to_string(),
        scheme: scheme.to_string(),
        mass: mass.to_string(),
        m: l.m,
        dt: l.dt,
        steps: l.steps,
        norms: Some(l.norms),
        release_err: Some(release_error(l.first_release, release_of(b))),
        wall,
        setup,
        degree: k,
        modes,
        beam: None,
        power: None,
    };
    for benchmark in BARS {
        let (ratio, t_end) = benchmark.default_ratio_and_horizon();
        for scheme in &schemes {
            let ok: Vec<BarMass> = masses.iter().copied().filter(|m| scheme.accepts_massless_node(m.massless_contact_node())).collect();
            // Explicit schemes cannot take dt = h (their CFL limit is below it):
            // they run at dx/dt = 10 on every benchmark.
            let ratio = if scheme.is_explicit() { ratio.max(10.0) } else { ratio };
            let cfg = StudyConfig::new(benchmark, vec![*scheme], ok, a.levels.clone(), ratio, t_end);
            for r in study::sweep(&cfg, &|| {})? {
                for l in &r.levels {
                    let wall = time_stepping(benchmark, r.scheme, r.mass, l.m, 1, ratio, t_end, None)?;
                    points.push(full(benchmark, r.scheme, r.mass, l, 1, 0, wall));
                }
            }
            tick();
        }
    }
    // The frontier: Courant one, Pk, reduced models, the beam.
    for benchmark in BARS {
        let (ratio, t_end) = benchmark.default_ratio_and_horizon();
        for m in courant1_levels(&a.levels) {
            points.push(courant1(benchmark, m)?);
        }
        tick();
        let pk: Vec<SchemeSpec> = ["newmark-cn", "newmark-ii"].iter().map(|n| n.parse().map_err(run_err)).collect::<Result<_, _>>()?;
        for &k in &a.degrees {
            let cfg = StudyConfig::new(benchmark, pk.clone(), vec![BarMass::Std, BarMass::Mod], a.levels.clone(), ratio, t_end).with_degree(k);
            for r in study::sweep(&cfg, &|| {})? {
                for l in &r.levels {
                    let wall = time_stepping(benchmark, r.scheme, r.mass, l.m, k, ratio, t_end, None)?;
                    points.push(full(benchmark, r.scheme, r.mass, l, k, 0, wall));
                }
            }
            tick();
        }
        let cn: SchemeSpec = "newmark-cn".parse().map_err(run_err)?;
        let exact = benchmark.exact(t_end)?;
        for &r in &a.modes {
            // A level has as many interior modes as unknowns less the contact.
            let mut levels = Vec::new();
            for &m in &a.levels {
                let dofs = benchmark.problem(exact.as_ref(), m, BarMass::Mod)?.bar.dofs();
                if r < dofs {
                    levels.push(m);
                } else {
                    notes.push(format!("{benchmark}: r = {r} skipped at m = {m} (only {} interior modes)", dofs - 1));
                }
            }
            // One level at a time (a sweep wants two levels for its rates).
            let runs: Vec<Result<(usize, study::LevelResult), StudyError>> =
                levels.par_iter().map(|&m| Ok((m, study::run_level(&study::Level::new(benchmark, cn, BarMass::Mod, m, ratio, t_end).with_reduce(Some(Keep::Modes(r))), exact.as_ref())?))).collect();
            for run in runs {
                let (m, l) = run?;
                let wall = time_stepping(benchmark, cn, BarMass::Mod, m, 1, ratio, t_end, Some(Keep::Modes(r)))?;
                points.push(full(benchmark, cn, BarMass::Mod, &l, 1, r, wall));
            }
            tick();
        }
    }
    let beam_check = if a.beam_dts.is_empty() {
        None
    } else {
        let (p, check) = beam_points(a)?;
        points.extend(p);
        if let Some(r) = a.modes.iter().find(|&&r| r >= 2 * BeamScene::PAPER[0].elements) {
            notes.push(format!("{BEAM}: r = {r} skipped (the beam has {} interior modes)", 2 * BeamScene::PAPER[0].elements - 1));
        }
        tick();
        Some(check)
    };
    // The beam's impact power over a long window against the reference step.
    if !a.beam_stat_dts.is_empty() {
        let (reference, ref_steps, ref_wall) = impact_power(a, a.beam_stat_ref_dt)?;
        let row = |dt: f64, power: Interval, steps: usize, wall: f64| Point {
            benchmark: BEAM_STATS.into(),
            scheme: "beta-scheme(0.5)".into(),
            mass: "consistent".into(),
            m: 19,
            dt,
            steps,
            norms: None,
            release_err: None,
            wall,
            // The whole run is timed (`wall_s`, `step_s`): no set-up apart.
            setup: f64::NAN,
            degree: 3,
            modes: 0,
            beam: None,
            power: Some((power, power.mean / reference.mean - 1.0)),
        };
        for &dt in &a.beam_stat_dts {
            let (power, steps, wall) = impact_power(a, dt)?;
            points.push(row(dt, power, steps, wall));
        }
        points.push(row(a.beam_stat_ref_dt, reference, ref_steps, ref_wall));
        tick();
    }
    let (s_, f_, i_) = (Kind::S, Kind::F, Kind::I);
    let mut w = TableOut::create(
        &a.out,
        "work_precision.csv",
        &[
            ("benchmark", s_),
            ("scheme", s_),
            ("mass", s_),
            ("m", i_),
            ("dt", f_),
            ("steps", i_),
            ("l2_l2_u", f_),
            ("linf_energy", f_),
            ("wall_s", f_),
            ("degree", i_),
            ("modes", i_),
            ("tip_err", f_),
            ("tip_err_end", f_),
            ("impact_err", f_),
            ("linf_l2_u", f_),
            ("linf_v_u", f_),
            ("l2_v_u", f_),
            ("l2_lambda", f_),
            ("l2_energy", f_),
            ("release_err", f_),
            ("impact_power", f_),
            ("impact_power_low", f_),
            ("impact_power_high", f_),
            ("impact_power_rel_err", f_),
            ("setup_s", f_),
            ("step_s", f_),
        ],
    )?;
    let e6 = |x: Option<f64>| opt(x.map(|x| fe(x, 6)));
    for p in &points {
        let b = |f: fn(&(f64, f64, f64)) -> f64| e6(p.beam.as_ref().map(f));
        let n = |f: fn(&NormReport) -> f64| e6(p.norms.as_ref().map(f));
        w.row(vec![
            txt(p.benchmark.clone()),
            txt(p.scheme.clone()),
            txt(p.mass.clone()),
            int(p.m),
            fe(p.dt, 6),
            int(p.steps),
            n(|r| r.l2_l2_u),
            n(|r| r.linf_energy),
            fe(p.wall, 6),
            int(p.degree),
            int(p.modes),
            b(|e| e.0),
            b(|e| e.1),
            b(|e| e.2),
            n(|r| r.linf_l2_u),
            n(|r| r.linf_v_u),
            n(|r| r.l2_v_u),
            n(|r| r.l2_lambda),
            n(|r| r.l2_energy),
            e6(p.release_err.filter(|e| e.is_finite())),
            e6(p.power.map(|(i, _)| i.mean)),
            e6(p.power.map(|(i, _)| i.low)),
            e6(p.power.map(|(i, _)| i.high)),
            e6(p.power.map(|(_, r)| r)),
            e6(Some(p.setup).filter(|s| s.is_finite())),
            fe(p.wall, 6),
        ])?;
    }
    let table = w.finish()?;
    let mut report = String::from("# Work–precision (error against stepping wall time)\n\n");
    let mut benchmarks: Vec<String> = BARS.iter().map(|b| b.to_string()).collect();
    if beam_check.is_some() {
        benchmarks.push(BEAM.into());
    }
    for benchmark in &benchmarks {
        let pts: Vec<&Point> = points.iter().filter(|p| &p.benchmark == benchmark).collect();
        let mut keys: Vec<String> = pts.iter().map(|p| p.label()).collect();
        keys.dedup();
        let is_beam = benchmark == BEAM;
        // The beam is judged by its tip; a bar in each quantity, with its own SVG.
        let quantities: &[Quantity] = if is_beam { &[Quantity::U] } else { &Quantity::ALL };
        // Per configuration, the quantities whose error does not fall with m.
        let failing: Vec<(String, Vec<Quantity>)> = if is_beam { Vec::new() } else { keys.iter().map(|k| (k.clone(), non_convergent(&pts, k))).collect() };
        let flagged = |label: &str| -> String {
            match failing.iter().find(|f| f.0 == label).map(|f| &f.1) {
                Some(qs) if !qs.is_empty() => format!(" (does not converge in {})", qs.iter().map(|q| q.name()).collect::<Vec<_>>().join(", ")),
                _ => String::new(),
            }
        };
        writeln!(report, "## {benchmark}\n").expect("writing to a String");
        if let (true, Some((cw, ct))) = (is_beam, beam_check) {
            match a.reference {
                BeamReference::FineStep => writeln!(
                    report,
                    "Tip error against the full model at dt = {:e} s over [0, {}] s (that reference differs from the run at twice its step by {cw:.2e} m there, by {ct:.2e} m over [0, {}] s).\n",
                    a.beam_ref_dt, a.beam_window, a.beam_t_end
                ),
                BeamReference::EventDriven => writeln!(
                    report,
                    "Tip error against the exact semi-discrete solution (`event-driven(0)`, sampled every {:e} s) over [0, {}] s; the first impact time from its event log. The full model at dt = {:e} s (the fine-step reference) differs from it by {cw:.2e} m there, by {ct:.2e} m over [0, {}] s.\n",
                    common_step(&a.beam_dts).unwrap_or(a.beam_ref_dt),
                    a.beam_window,
                    a.beam_ref_dt,
                    a.beam_t_end
                ),
            }
            .expect("writing to a String");
        }
        for &q in quantities {
            let (y_label, file) =
                if is_beam { ("largest tip error over the window (m)".to_string(), format!("{benchmark}.svg")) } else { (format!("{} error", q.name()), format!("{benchmark}{}.svg", q.suffix())) };
            let series: Vec<Series> = keys
                .iter()
                .map(|k| Series { label: k.clone(), points: pts.iter().filter(|p| &p.label() == k).map(|p| (p.wall, p.error(q))).collect(), reference: false, style: Default::default() })
                .collect();
            let title = if is_beam { format!("{benchmark}: error against wall time") } else { format!("{benchmark}: {} error against wall time", q.name()) };
            let svg = line_chart(&Chart { title: &title, x_label: "wall time (s)", y_label: &y_label, scale: Scale::LogLog, size: (1000, 650) }, &series).map_err(StudyError::Plot)?;
            crate::write_file(&a.out.join(file), &svg)?;
            if !is_beam {
                writeln!(report, "### {} (column `{}`)\n", q.name(), q.column()).expect("writing to a String");
            }
            writeln!(report, "| target error | cheapest (scheme, mass, {}) | wall (s) | error | runner-up | wall (s) |\n|---|---|---|---|---|---|", if is_beam { "dt" } else { "m" })
                .expect("writing to a String");
            let targets: &[f64] = if is_beam { &[3e-2, 1e-2, 3e-3, 1e-3, 3e-4] } else { q.targets() };
            for &target in targets {
                // Per configuration, the cheapest level that reaches the target.
                let mut best: Vec<&Point> = keys.iter().filter_map(|k| pts.iter().filter(|p| &p.label() == k && p.error(q) <= target).min_by(|a, b| a.wall.total_cmp(&b.wall)).copied()).collect();
                best.sort_by(|a, b| a.wall.total_cmp(&b.wall));
                let at = |p: &Point| if is_beam { format!("{} dt={:e}", p.label(), p.dt) } else { format!("{} m={}{}", p.label(), p.m, flagged(&p.label())) };
                match (best.first(), best.get(1)) {
                    (Some(b0), r) => writeln!(
                        report,
                        "| {target:.0e} | {} | {:.2e} | {:.2e} | {} | {} |",
                        at(b0),
                        b0.wall,
                        b0.error(q),
                        r.map_or("-".into(), |r| at(r)),
                        r.map_or("-".into(), |r| format!("{:.2e}", r.wall))
                    ),
                    (None, _) => writeln!(report, "| {target:.0e} | not reached at these levels | | | | |"),
                }
                .expect("writing to a String");
            }
            report.push('\n');
        }
        if !is_beam {
            let mut listed: Vec<String> = failing.iter().filter(|f| !f.1.is_empty()).map(|f| format!("{}{}", f.0, flagged(&f.0))).collect();
            listed.sort();
            if !listed.is_empty() {
                writeln!(report, "Configurations whose error does not fall with m in some quantity (least-squares rate below {NON_CONVERGENT_RATE}): {}.\n", listed.join("; "))
                    .expect("writing to a String");
            }
        }
        if is_beam {
            // The question: today's full model at the paper's step,
            // and the cheapest reduced model at least as accurate.
            let paper_dt = BeamScene::PAPER[0].dt;
            let q = Quantity::U;
            if let Some(today) = pts.iter().find(|p| p.modes == 0 && (p.dt - paper_dt).abs() < 1e-12) {
                let reduced = pts.iter().filter(|p| p.modes > 0 && p.error(q) <= today.error(q)).min_by(|a, b| a.wall.total_cmp(&b.wall));
                writeln!(report, "The full model at the paper's dt = {paper_dt:e} s: tip error {:.2e} m, {:.2e} s. ", today.error(q), today.wall).expect("writing to a String");
                match reduced {
                    Some(r) => writeln!(
                        report,
                        "Cheapest reduced model at least as accurate: {} dt={:e}, {:.2e} m, {:.2e} s ({:.1}x less wall time).",
                        r.label(),
                        r.dt,
                        r.error(q),
                        r.wall,
                        today.wall / r.wall
                    ),
                    None => writeln!(
                        report,
                        "No reduced model reaches that error at these steps and modes (best: {}).",
                        pts.iter().filter(|p| p.modes > 0).min_by(|a, b| a.error(q).total_cmp(&b.error(q))).map_or("-".into(), |p| format!("{} dt={:e}, {:.2e} m", p.label(), p.dt, p.error(q)))
                    ),
                }
                .expect("writing to a String");
            }
            report.push('\n');
        }
    }
    if !a.beam_stat_dts.is_empty() {
        impact_power_report(a, &points, &mut report);
    }
    Ok(Output { tables: vec![table], report, wall_s: since(start), notes })
}

/// The impact-power section: every step with its interval and error against
/// the reference, and the target — within 1 % of the reference with both
/// intervals within ±1 %, at least 10x cheaper — reached or not (then the
/// window it would take, intervals shrinking as 1/√window).
fn impact_power_report(a: &Config, points: &[Point], report: &mut String) {
    let rows: Vec<(&Point, Interval, f64)> = points.iter().filter_map(|p| p.power.map(|(i, r)| (p, i, r))).collect();
    let Some(&(ref_p, ref_i, _)) = rows.iter().find(|(p, _, _)| p.dt == a.beam_stat_ref_dt) else { return };
    let half = |i: &Interval| (i.high - i.low) / 2.0 / i.mean.abs();
    let period = std::f64::consts::TAU / 10.0;
    writeln!(
        report,
        "## {BEAM_STATS}: impact power (a statistic that converges; docs in `cargo xtask beam-statistics`)\n\nJ = 19, window {} forcing periods ({:.0} s) after 10, 20 batches; reference dt = {:e} s: {:.4} [{:.4}, {:.4}] (±{:.1} %), {:.2} s.\n\n| dt (s) | impact power [95 % interval] | ± | error against the reference | wall (s) |\n|---|---|---|---|---|",
        a.beam_stat_window,
        a.beam_stat_window * period,
        a.beam_stat_ref_dt,
        ref_i.mean,
        ref_i.low,
        ref_i.high,
        100.0 * half(&ref_i),
        ref_p.wall
    )
    .expect("writing to a String");
    for (p, i, r) in &rows {
        writeln!(report, "| {:e} | {:.4} [{:.4}, {:.4}] | {:.1} % | {:+.2} % | {:.2} |", p.dt, i.mean, i.low, i.high, 100.0 * half(i), 100.0 * r, p.wall).expect("writing to a String");
    }
    let ok = rows
        .iter()
        .filter(|(p, i, r)| p.dt != a.beam_stat_ref_dt && r.abs() <= 0.01 && half(i) <= 0.01 && half(&ref_i) <= 0.01 && p.wall * 10.0 <= ref_p.wall)
        .min_by(|x, y| x.0.wall.total_cmp(&y.0.wall));
    match ok {
        Some((p, _, r)) => writeln!(report, "\nTarget reached: dt = {:e} s is within {:.2} % of the reference with both intervals within ±1 %, {:.1}x cheaper.\n", p.dt, 100.0 * r.abs(), ref_p.wall / p.wall),
        None => {
            let worst = rows.iter().map(|(_, i, _)| half(i)).fold(0.0_f64, f64::max);
            writeln!(
                report,
                "\nTarget (within 1 % of the reference, both intervals within ±1 %, 10x cheaper) not reached: the intervals over this window are up to ±{:.1} %; ±1 % needs about {:.0} forcing periods ({:.0} s) of window, intervals shrinking as 1/√window.\n",
                100.0 * worst,
                a.beam_stat_window * (worst / 0.01).powi(2),
                a.beam_stat_window * (worst / 0.01).powi(2) * period
            )
        }
    }
    .expect("writing to a String");
}
