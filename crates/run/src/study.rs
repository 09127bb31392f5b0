//! Convergence studies: sweep the mesh at a fixed `dx/dt`, for each
//! (scheme, mass) pair, in parallel; rates of every norm.
//!
//! The files (per configuration `<scheme>_<mass>.csv` with columns
//! [`LEVEL_COLUMNS`], `rates.csv`, `oscillation.csv`) are written by
//! `signorini_studies::convergence` from these results.

use crate::{run, Benchmark, NormObserver, RunConfig, RunError};
use rayon::prelude::*;
use signorini_exact::ExactSolution;
use signorini_fem::BarMass;
use signorini_norms::{NormKind, NormReport};
use signorini_reduce::Keep;
use signorini_schemes::SchemeSpec;
use std::time::Instant;

/// Columns of a per-configuration CSV.
/// `wall_s` is the whole run (set-up and loop); `setup_s` the set-up alone
/// (problem, exact initial data, the scheme's construction with its CFL
/// check and factorisations, the norm observer) and `step_s` the time loop
/// alone (the runner's own clock), appended later (columns are only ever
/// added at the end).
pub const LEVEL_COLUMNS: [&str; 14] = ["m", "dx", "dt", "steps", "linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "l2_lambda", "linf_energy", "l2_energy", "wall_s", "setup_s", "step_s"];

/// The norms whose rates are reported, in column order.
pub const NORMS: [&str; 7] = ["linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "l2_lambda", "linf_energy", "l2_energy"];

/// Value of a named norm (one of [`NORMS`]).
pub fn norm_value(r: &NormReport, name: &str) -> f64 {
    match name {
        "linf_l2_u" => r.linf_l2_u,
        "l2_l2_u" => r.l2_l2_u,
        "linf_v_u" => r.linf_v_u,
        "l2_v_u" => r.l2_v_u,
        "l2_lambda" => r.l2_lambda,
        "linf_energy" => r.linf_energy,
        "l2_energy" => r.l2_energy,
        _ => f64::NAN,
    }
}

/// What to sweep ([`StudyConfig::new`], then [`with_norms`](StudyConfig::with_norms)
/// and [`with_degree`](StudyConfig::with_degree); the fields stay public).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct StudyConfig {
    /// The benchmark.
    pub benchmark: Benchmark,
    /// Schemes.
    pub schemes: Vec<SchemeSpec>,
    /// Mass treatments.
    pub masses: Vec<BarMass>,
    /// Numbers of elements `m`, increasing.
    pub levels: Vec<usize>,
    /// `dx/dt`.
    pub ratio: f64,
    /// Horizon `T`.
    pub t_end: f64,
    /// Error measure (exact by default; GetFEM-demo style on request).
    pub norms: NormKind,
    /// Element degree `k` (1, 2, 3): level `m` is `m` elements of degree `k`.
    pub degree: usize,
}

impl StudyConfig {
    /// `levels` of `benchmark` for every scheme and mass at `dx/dt = ratio`
    /// up to `t_end`: the exact norms, P1 elements (not validated: see
    /// [`validate`](Self::validate)).
    pub fn new(benchmark: Benchmark, schemes: Vec<SchemeSpec>, masses: Vec<BarMass>, levels: Vec<usize>, ratio: f64, t_end: f64) -> Self {
        Self { benchmark, schemes, masses, levels, ratio, t_end, norms: NormKind::Exact, degree: 1 }
    }

    /// With the error measure `norms`.
    pub fn with_norms(mut self, norms: NormKind) -> Self {
        self.norms = norms;
        self
    }

    /// With Lagrange elements of degree `k` (1, 2, 3).
    pub fn with_degree(mut self, k: usize) -> Self {
        self.degree = k;
        self
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), RunError> {
        if !(1..=3).contains(&self.degree) {
            return Err(RunError::Invalid { field: "degree", value: self.degree as f64, allowed: "1, 2 or 3 (Lagrange P1, P2, P3)" });
        }
        if self.degree > 1 && self.norms != NormKind::Exact {
            return Err(RunError::Invalid { field: "degree", value: self.degree as f64, allowed: "1 with the GetFEM-demo norms (a P1 measure)" });
        }
        if self.degree > 1 {
            if let Some(&mass) = self.masses.iter().find(|v| !matches!(v, BarMass::Std | BarMass::Lumped | BarMass::Mod | BarMass::Mod1)) {
                return Err(signorini_fem::FemError::MassForDegree { mass: mass.name(), degree: self.degree }.into());
            }
        }
        if !(self.ratio > 0.0 && self.ratio.is_finite()) {
            return Err(RunError::Invalid { field: "ratio", value: self.ratio, allowed: "dx/dt finite and > 0" });
        }
        if let Some(&m) = self.levels.iter().find(|&&m| m < 2) {
            return Err(RunError::Invalid { field: "levels", value: m as f64, allowed: "every m >= 2" });
        }
        if self.levels.is_empty() || self.schemes.is_empty() || self.masses.is_empty() {
            return Err(RunError::Invalid { field: "levels/schemes/masses", value: 0.0, allowed: "at least one of each" });
        }
        // A rate needs two distinct levels; a repeated level adds nothing.
        let mut sorted = self.levels.clone();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(RunError::Invalid { field: "levels", value: w[0] as f64, allowed: "distinct values (this one is repeated)" });
        }
        if self.levels.len() < 2 {
            return Err(RunError::Invalid { field: "levels", value: self.levels[0] as f64, allowed: "at least two distinct levels: a rate from one level is meaningless" });
        }
        if let Some(&m) = self.levels.iter().find(|&&m| m > signorini_fem::MAX_ELEMENTS) {
            return Err(RunError::Invalid { field: "levels", value: m as f64, allowed: "every m <= 2^40" });
        }
        // Every level runs a whole number of steps (every benchmark has dx = 1/m).
        for &m in &self.levels {
            RunConfig::new(1.0 / m as f64 / self.ratio, self.t_end)?;
        }
        for s in &self.schemes {
            s.validate().map_err(RunError::Scheme)?;
        }
        Ok(())
    }
}

/// One run of a sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct LevelResult {
    /// Elements.
    pub m: usize,
    /// `dx = L/m`.
    pub dx: f64,
    /// `dt = dx / ratio`.
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// The norms.
    pub norms: NormReport,
    /// Wall time of the run (set-up and loop), seconds.
    pub wall_s: f64,
    /// Wall time of the set-up alone (problem, scheme with its CFL check,
    /// observers), seconds.
    pub setup_s: f64,
    /// Wall time of the time loop alone ([`crate::RunSummary::wall_s`]), seconds.
    pub step_s: f64,
    /// The first level at which the contact is released after having been
    /// active ([`NormObserver::first_release`]).
    pub first_release: Option<f64>,
}

/// All levels of one (scheme, mass) pair.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct ConfigResult {
    /// The scheme.
    pub scheme: SchemeSpec,
    /// The mass treatment.
    pub mass: BarMass,
    /// One entry per level, in the order of [`StudyConfig::levels`].
    pub levels: Vec<LevelResult>,
}

/// One level of a convergence study: what [`run_level`] runs.
///
/// [`Level::new`] takes the required fields; the others have defaults
/// (degree 1, the exact norms, the full model) that the `with_*` setters
/// change:
///
/// ```
/// use signorini_run::study::{run_level, Level};
/// use signorini_run::Benchmark;
/// use signorini_fem::BarMass;
///
/// let b = Benchmark::BarDirichlet;
/// let exact = b.exact(3.0).unwrap();
/// let level = Level::new(b, "newmark-cn".parse().unwrap(), BarMass::Mod, 40, 10.0, 3.0).with_degree(2);
/// let r = run_level(&level, exact.as_ref()).unwrap();
/// println!("L2(L2) error {}", r.norms.l2_l2_u);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Level {
    /// The benchmark ([`Benchmark::problem_with_degree`] builds the level's problem).
    pub benchmark: Benchmark,
    /// The scheme.
    pub scheme: SchemeSpec,
    /// The mass treatment.
    pub mass: BarMass,
    /// Elements `m` of the level.
    pub m: usize,
    /// Element degree `k` (Lagrange P1, P2, P3; default 1); `dx = h`, the element size.
    pub degree: usize,
    /// `dx/dt`.
    pub ratio: f64,
    /// Horizon `T`.
    pub t_end: f64,
    /// Error measure (default [`NormKind::Exact`]).
    pub norms: NormKind,
    /// The massless-boundary reduction of the level's problem
    /// (docs/theory.md §2.5; the norms see the reconstructed full field),
    /// or the full model (`None`, the default).
    pub reduce: Option<Keep>,
}

impl Level {
    /// Level `m` of `benchmark` with `scheme` and `mass` at `dx/dt = ratio`
    /// up to `t_end`: P1 elements, the exact norms, the full model.
    pub fn new(benchmark: Benchmark, scheme: SchemeSpec, mass: BarMass, m: usize, ratio: f64, t_end: f64) -> Self {
        Self { benchmark, scheme, mass, m, degree: 1, ratio, t_end, norms: NormKind::Exact, reduce: None }
    }

    /// With Lagrange elements of degree `k` (1, 2, 3).
    pub fn with_degree(mut self, k: usize) -> Self {
        self.degree = k;
        self
    }

    /// With the error measure `kind`.
    pub fn with_norms(mut self, kind: NormKind) -> Self {
        self.norms = kind;
        self
    }

    /// With the reduced model `keep` (`None`: the full model).
    pub fn with_reduce(mut self, keep: Option<Keep>) -> Self {
        self.reduce = keep;
        self
    }
}

/// Runs one level: builds the problem and scheme, steps to `t_end` with the
/// norm observer (level `m`: see [`Benchmark::problem_with_degree`]; the
/// norms integrate over the whole bar), on the reduced model when
/// [`Level::reduce`] is given.
pub fn run_level(level: &Level, exact: &dyn ExactSolution) -> Result<LevelResult, RunError> {
    let &Level { benchmark, scheme, mass, m, degree: k, ratio, t_end, norms: kind, reduce } = level;
    if k > 1 && kind != NormKind::Exact {
        return Err(RunError::Invalid { field: "degree", value: k as f64, allowed: "1 with the GetFEM-demo norms (a P1 measure)" });
    }
    let start = Instant::now();
    let problem = benchmark.problem_with_degree(exact, m, mass, k)?;
    let dx = problem.bar.h();
    let dt = dx / ratio;
    let cfg = RunConfig::new(dt, t_end)?;
    // Over the whole bar: 2m elements on [0, 2] for bar-mirrored.
    let mut norms = NormObserver::with_degree(exact, problem.bar.elements, k, problem.vnorm(), dt, kind);
    // The same construction as `signorini run` (the CLI's run_bar): the
    // scheme built on the problem's dynamics, with its CFL check.
    let red = reduce.map(|keep| crate::reduced::reduce(&problem.dynamics(), &problem.initial, keep)).transpose()?;
    let mut stepper = match &red {
        None => scheme.build(problem.dynamics(), dt, &problem.initial)?,
        Some(red) => scheme.build(red.dynamics.clone(), dt, &red.initial)?,
    };
    let setup_s = start.elapsed().as_secs_f64();
    let summary = match &red {
        None => run(stepper.as_mut(), &problem.initial.u, &cfg, &mut [&mut norms])?,
        Some(red) => {
            let mut full = crate::reduced::Reconstruct::new(&red.reduction, &mut norms, crate::reduced::Need::Full);
            run(stepper.as_mut(), &red.initial.u, &cfg, &mut [&mut full])?
        }
    };
    Ok(LevelResult { m, dx, dt, steps: summary.steps, norms: norms.report(), wall_s: start.elapsed().as_secs_f64(), setup_s, step_s: summary.wall_s, first_release: norms.first_release() })
}

/// Runs the whole study in parallel (rayon's pool; finest levels first for
/// load balance). `tick` is called after each finished run.
pub fn sweep(cfg: &StudyConfig, tick: &(dyn Fn() + Sync)) -> Result<Vec<ConfigResult>, RunError> {
    sweep_reduced(cfg, None, tick)
}

/// [`sweep`] with every level reduced when `reduce` is given
/// ([`Level::reduce`]).
pub fn sweep_reduced(cfg: &StudyConfig, reduce: Option<Keep>, tick: &(dyn Fn() + Sync)) -> Result<Vec<ConfigResult>, RunError> {
    cfg.validate()?;
    let exact = cfg.benchmark.exact(cfg.t_end)?;
    let mut jobs: Vec<(usize, usize, usize)> = Vec::new();
    for (si, _) in cfg.schemes.iter().enumerate() {
        for (mi, _) in cfg.masses.iter().enumerate() {
            for (li, _) in cfg.levels.iter().enumerate() {
                jobs.push((si, mi, li));
            }
        }
    }
    jobs.sort_by_key(|&(_, _, li)| std::cmp::Reverse(cfg.levels[li]));
    let done: Vec<((usize, usize, usize), LevelResult)> = jobs
        .par_iter()
        .map(|&(si, mi, li)| {
            let level = Level::new(cfg.benchmark, cfg.schemes[si], cfg.masses[mi], cfg.levels[li], cfg.ratio, cfg.t_end).with_degree(cfg.degree).with_norms(cfg.norms).with_reduce(reduce);
            let r = run_level(&level, exact.as_ref());
            tick();
            r.map(|r| ((si, mi, li), r))
        })
        .collect::<Result<_, _>>()?;
    let mut out = Vec::new();
    for (si, scheme) in cfg.schemes.iter().enumerate() {
        for (mi, mass) in cfg.masses.iter().enumerate() {
            let mut levels: Vec<(usize, LevelResult)> = done.iter().filter(|(k, _)| k.0 == si && k.1 == mi).map(|(k, r)| (k.2, *r)).collect();
            levels.sort_by_key(|(li, _)| *li);
            out.push(ConfigResult { scheme: *scheme, mass: *mass, levels: levels.into_iter().map(|(_, r)| r).collect() });
        }
    }
    Ok(out)
}

/// Rates of one norm over a sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rate {
    /// Least-squares slope of `log e` against `log dx` over all levels.
    pub lsq: f64,
    /// `log(e_{k-1}/e_k) / log(dx_{k-1}/dx_k)` for the last two levels.
    pub last: f64,
}

/// Rates of `e(dx)` (pairs `(dx, e)`); levels with a non-positive or
/// non-finite error are skipped; NaN with fewer than two usable levels.
pub fn rate(points: &[(f64, f64)]) -> Rate {
    let pts: Vec<(f64, f64)> = points.iter().filter(|(d, e)| *d > 0.0 && *e > 0.0 && e.is_finite()).map(|(d, e)| (d.ln(), e.ln())).collect();
    if pts.len() < 2 {
        return Rate { lsq: f64::NAN, last: f64::NAN };
    }
    let (a, b) = (pts[pts.len() - 2], pts[pts.len() - 1]);
    Rate { lsq: lsq_slope(&pts), last: (a.1 - b.1) / (a.0 - b.0) }
}

/// The least-squares slope of `y` against `x` through `points` (NaN for
/// fewer than two).
pub fn lsq_slope(points: &[(f64, f64)]) -> f64 {
    if points.len() < 2 {
        return f64::NAN;
    }
    let n = points.len() as f64;
    let (mx, my) = (points.iter().map(|p| p.0).sum::<f64>() / n, points.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

/// File name of the CSV of one (scheme, mass) pair: `<scheme>_<mass>.csv`.
pub fn file_name(scheme: &SchemeSpec, mass: BarMass) -> String {
    format!("{scheme}_{mass}.csv")
}

impl ConfigResult {
    /// File name of its CSV: `<scheme>_<mass>.csv`.
    pub fn file_name(&self) -> String {
        file_name(&self.scheme, self.mass)
    }

    /// Rate of a named norm.
    pub fn rate(&self, norm: &str) -> Rate {
        let pts: Vec<(f64, f64)> = self.levels.iter().map(|l| (l.dx, norm_value(&l.norms, norm))).collect();
        rate(&pts)
    }

    /// The λ oscillation indicator at the finest level.
    pub fn lambda_tv_ratio(&self) -> f64 {
        self.levels.last().map_or(f64::NAN, |l| l.norms.lambda_tv_ratio)
    }
}

/// The rates as a Markdown table: one row per (scheme, mass), the
/// least-squares rate of each norm, and the λ oscillation indicator at the
/// finest level.
pub fn markdown_table(results: &[ConfigResult]) -> String {
    let mut s = String::from("| scheme | mass | L∞(L²) | L²(L²) | L∞(V) | L²(V) | L²(λ) | L∞(E) | L²(E) | λ TV ratio |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|\n");
    for r in results {
        s.push_str(&format!("| {} | {} |", r.scheme, r.mass));
        for n in NORMS {
            s.push_str(&format!(" {:.2} |", r.rate(n).lsq));
        }
        s.push_str(&format!(" {:.1} |\n", r.lambda_tv_ratio()));
    }
    s
}
