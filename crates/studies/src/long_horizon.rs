//! The long-horizon study (`cargo xtask long-horizon`): the Dirichlet bar
//! over many periods (default T = 30, ten periods), every mass treatment,
//! error against time and the phase of every impact.
//!
//! Each (scheme, mass, m) runs once to `T`; an observer takes the exact
//! `‖u_h − u‖_{L²}` at every time level (docs/theory.md §6.1) and keeps its
//! maximum over each period `[3k, 3k + 3)`, and the times at which the
//! contact node's constraint becomes active (the numerical impacts) against
//! the exact ones, `t = 1 + 3k`. A redistributed mass changes the discrete
//! frequencies, so its error can grow period after period from a phase
//! drift; the table says which treatment keeps the phase.
//!
//! Outputs (`out/long-horizon/`):
//! * `error_vs_time.csv`: `scheme,mass,m,period,t_from,t_to,max_l2_u` — the
//!   largest L² error of u within each period;
//! * `impacts.csv`: `scheme,mass,m,k,t_exact,t_numerical,drift` — impact k:
//!   its exact time `1 + 3k`, the first time within one time unit of it at
//!   which the contact node's constraint becomes active (the time of that
//!   step's force), and the drift, numerical − exact (empty when there is no
//!   onset in that window);
//! * `summary.csv`: `scheme,mass,m,linf_l2_u,l2_l2_u,mean_drift_per_period,final_energy`.

use crate::{create_dir, fe, ff, int, since, txt, Cell, Kind, StudyError, TableOut};
use signorini_fem::BarMass;
use signorini_norms::SpaceIntegrator;
use signorini_run::{run as run_steps, Benchmark, NormObserver, Observer, RunConfig, RunError, Sample};
use signorini_schemes::SchemeSpec;
use std::path::PathBuf;

/// The period of the Dirichlet bar.
const PERIOD: f64 = 3.0;

/// What to run.
#[derive(Clone, Debug)]
pub struct Config {
    /// Output folder (`--out`, default `out/long-horizon`).
    pub out: PathBuf,
    /// (scheme, masses) pairs (`--schemes`/`--masses` are one list of
    /// `scheme:mass` pairs, `--runs`); default `ps-e0` with every mass and
    /// `moreau-jean` with std and lumped.
    pub runs: Vec<(SchemeSpec, BarMass)>,
    /// Levels m (`--levels`).
    pub levels: Vec<usize>,
    /// dx/dt (`--ratio`, default 10, the papers').
    pub ratio: f64,
    /// Horizon (`--t-end`, default 30: ten periods).
    pub t_end: f64,
}

impl Default for Config {
    /// `cargo xtask long-horizon` without options.
    fn default() -> Self {
        let ps: SchemeSpec = "ps-e0".parse().expect("a preset");
        let mj: SchemeSpec = "moreau-jean".parse().expect("a preset");
        let masses = [BarMass::Std, BarMass::Lumped, BarMass::Mod, BarMass::Mod2, BarMass::Mod3, BarMass::Transfer, BarMass::Singular];
        let mut runs: Vec<(SchemeSpec, BarMass)> = masses.iter().map(|&m| (ps, m)).collect();
        runs.extend([(mj, BarMass::Std), (mj, BarMass::Lumped)]);
        Config { out: PathBuf::from("out/long-horizon"), runs, levels: vec![20, 40, 80], ratio: 10.0, t_end: 30.0 }
    }
}

/// Parses `--runs`: `scheme:mass` pairs, comma-separated (a scheme with
/// parameters keeps its commas inside parentheses).
pub fn parse_runs(raw: &[String]) -> Result<Vec<(SchemeSpec, BarMass)>, StudyError> {
    crate::split_schemes(raw)
        .iter()
        .map(|p| {
            let (s, m) = p.rsplit_once(':').ok_or_else(|| StudyError::config("--runs", format!("--runs {p:?}: allowed scheme:mass, e.g. ps-e0:mod3")))?;
            let scheme = s.parse::<SchemeSpec>().map_err(|e| StudyError::config("--runs", format!("--runs {p:?}: {e}")))?;
            let mass = m.parse::<BarMass>().map_err(|e| StudyError::config("--runs", format!("--runs {p:?}: {e}")))?;
            Ok((scheme, mass))
        })
        .collect()
}

impl Config {
    /// Every check, before anything runs.
    pub fn validate(&self) -> Result<(), StudyError> {
        if self.runs.is_empty() {
            return Err(StudyError::config("--runs", "--runs: allowed one or more scheme:mass pairs"));
        }
        for (s, m) in &self.runs {
            if !s.accepts_massless_node(m.massless_contact_node()) {
                return Err(StudyError::config("--runs", format!("--runs {s}:{m}: the scheme does not take this mass (massless contact node: {})", m.massless_contact_node())));
            }
        }
        if self.levels.is_empty() || self.levels.iter().any(|&m| !(2..=20_000).contains(&m)) {
            return Err(StudyError::config("--levels", format!("--levels {:?}: allowed one or more integers in [2, 20000]", self.levels)));
        }
        if !(self.ratio > 0.0 && self.ratio.is_finite()) {
            return Err(StudyError::config("--ratio", format!("--ratio {}: allowed finite and > 0", self.ratio)));
        }
        if !(self.t_end >= PERIOD && self.t_end.is_finite() && self.t_end <= 3000.0) {
            return Err(StudyError::config("--t-end", format!("--t-end {}: allowed finite, in [3, 3000] (one period at least)", self.t_end)));
        }
        let steps = self.levels.iter().map(|&m| m as f64 * self.ratio * self.t_end).fold(0.0, f64::max);
        if steps > 1e9 {
            return Err(StudyError::config("--t-end", format!("--t-end {}: {steps:.2e} steps at the finest level, allowed at most 1e9", self.t_end)));
        }
        Ok(())
    }
}

/// What the study computed and wrote ([`crate::Report`]); its tables:
/// `error_vs_time.csv`, `impacts.csv`, `summary.csv`.
pub type Output = crate::Report;

/// The largest L² error per period and the impact times.
struct Watch<'a> {
    space: SpaceIntegrator<'a>,
    per_period: Vec<f64>,
    impacts: Vec<f64>,
    was_active: bool,
}

impl Observer for Watch<'_> {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let e = self.space.errors(s.t, s.u).l2;
        let k = ((s.t / PERIOD) as usize).min(self.per_period.len() - 1);
        self.per_period[k] = self.per_period[k].max(e);
        if s.active && !self.was_active {
            // The force of the step that reached t_n acts at the level's time.
            self.impacts.push(s.lambda.map_or(s.t, |l| l.0));
        }
        self.was_active = s.active;
        Ok(())
    }
}

/// The last energy of a run.
struct LastEnergy(f64);

impl Observer for LastEnergy {
    fn wants_energy(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if let Some((_, e)) = s.energy {
            self.0 = e;
        }
        Ok(())
    }
}

/// Runs the study.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    a.validate()?;
    let start = std::time::Instant::now();
    create_dir(&a.out)?;
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(a.t_end)?;
    let periods = (a.t_end / PERIOD).ceil() as usize;
    let head = [("scheme", Kind::S), ("mass", Kind::S), ("m", Kind::I)];
    let with = |more: &[(&'static str, Kind)]| -> Vec<(&'static str, Kind)> { head.iter().copied().chain(more.iter().copied()).collect() };
    let mut ev = TableOut::create(&a.out, "error_vs_time.csv", &with(&[("period", Kind::I), ("t_from", Kind::F), ("t_to", Kind::F), ("max_l2_u", Kind::F)]))?;
    let mut im = TableOut::create(&a.out, "impacts.csv", &with(&[("k", Kind::I), ("t_exact", Kind::F), ("t_numerical", Kind::F), ("drift", Kind::F)]))?;
    let mut su = TableOut::create(&a.out, "summary.csv", &with(&[("linf_l2_u", Kind::F), ("l2_l2_u", Kind::F), ("mean_drift_per_period", Kind::F), ("final_energy", Kind::F)]))?;
    let total = (a.runs.len() * a.levels.len()) as u64;
    let mut done = 0;
    let mut md = format!("| scheme | mass | m | max L² error in period 1 | … in period {periods} | L∞(0,T;L²) | impact drift per period | final energy (exact 1/8) |\n|---|---|---|---|---|---|---|---|\n");
    for &(scheme, mass) in &a.runs {
        for &m in &a.levels {
            let p = b.problem(exact.as_ref(), m, mass)?;
            let dt = p.bar.h() / a.ratio;
            let mut stepper = scheme.build(p.dynamics(), dt, &p.initial).map_err(RunError::from)?;
            let cfg = RunConfig::new(dt, a.t_end)?;
            let mut watch = Watch { space: SpaceIntegrator::new(exact.as_ref(), p.bar.elements, p.vnorm()), per_period: vec![0.0; periods], impacts: Vec::new(), was_active: false };
            let mut norms = NormObserver::new(exact.as_ref(), p.bar.elements, p.vnorm(), dt);
            let mut energy = LastEnergy(f64::NAN);
            run_steps(stepper.as_mut(), &p.initial.u, &cfg, &mut [&mut watch, &mut norms, &mut energy])?;
            let (sn, mn) = (scheme.to_string(), mass.to_string());
            for (k, e) in watch.per_period.iter().enumerate() {
                ev.row(vec![txt(&sn), txt(&mn), int(m), int(k + 1), ff(k as f64 * PERIOD, 3), ff(((k + 1) as f64 * PERIOD).min(a.t_end), 3), fe(*e, 6)])?;
            }
            let mut drifts = Vec::new();
            for k in 0..periods {
                let te = 1.0 + PERIOD * k as f64;
                if te > a.t_end {
                    break;
                }
                // The first onset within one time unit of the exact impact (a
                // consistent mass chatters: more onsets follow within the contact phase).
                let tn = watch.impacts.iter().copied().find(|&t| t >= te - 1.0 && t < te + 1.0);
                if let Some(t) = tn {
                    drifts.push((te, t - te));
                }
                im.row(vec![txt(&sn), txt(&mn), int(m), int(k), ff(te, 3), tn.map_or(Cell::E, |t| ff(t, 10)), tn.map_or(Cell::E, |t| fe(t - te, 6))])?;
            }
            // Least-squares slope of the drift against the exact impact time, per period.
            let slope = PERIOD * signorini_run::study::lsq_slope(&drifts);
            let r = norms.report();
            su.row(vec![txt(&sn), txt(&mn), int(m), fe(r.linf_l2_u, 6), fe(r.l2_l2_u, 6), fe(slope, 4), fe(energy.0, 8)])?;
            md.push_str(&format!("| {sn} | {mn} | {m} | {:.3e} | {:.3e} | {:.3e} | {slope:+.2e} | {:.5} |\n", watch.per_period[0], watch.per_period[periods - 1], r.linf_l2_u, energy.0));
            done += 1;
            progress(done, total);
        }
    }
    let tables = vec![ev.finish()?, im.finish()?, su.finish()?];
    let report = format!("# Long horizon: bar-dirichlet over T = {} ({periods} periods), dx/dt = {} (output in {})\n\n{md}", a.t_end, a.ratio, a.out.display());
    Ok(crate::Report { tables, report, wall_s: since(start), notes: Vec::new() })
}
