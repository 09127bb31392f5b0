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
//!
//! **Energy growth** ([`EnergyTable`], on by default; `--no-energy` leaves
//! it out): each (scheme, mass) of `--energy-runs` at every dx/dt of
//! `--energy-ratios` (default 1, 2, 10) on `m = 100` elements to
//! `T = 10⁴` (`--energy-m`, `--energy-t-end`), with the run crate's energy
//! monitor (`signorini_run::energy`: bar-dirichlet has no load and no
//! damping, so the budget is the first energy the scheme reports, `E(0)` or
//! `E^{1/2}`). `--energy-benchmark` starts the runs from another benchmark
//! instead: `bar-neumann-gravity`, Doyen–Ern–Piperno's bouncing bar (two
//! impacts every 16 time units; its steady load is in the energy, so the
//! budget is again the first energy the scheme reports, `g u0 L = 1/18` or
//! within a relative 1e-7 of it), the 0.11 bar, or the mirrored bar. The default runs are the schemes and masses the long-run
//! question is about; `--energy-all` takes every named scheme with every
//! mass it accepts (explicit schemes at a dx/dt beyond their stability
//! limit are left out, with a note).
//! * `energy_growth.csv`: `scheme,mass,m,dx_dt,dt,steps,e_ref,final_energy,max_ratio,t_max_ratio,t_ratio_2,final_ratio,t_stopped`
//!   — `t_ratio_2` the first time E/budget exceeds 2 (empty: never);
//!   `t_stopped` the time at which the run's energy guard (|E| > 10⁶ × its
//!   scale, `RunConfig::energy_growth_limit`) stopped the run (empty: it
//!   reached T; the other columns then stop there);
//! * `energy_vs_time.csv`: `scheme,mass,m,dx_dt,window,t_to,max_ratio` —
//!   the largest E/budget within each of 100 equal windows of `[0, T]`;
//! * `energy_growth.svg`: those curves, one panel per dx/dt (log-log).

use crate::{create_dir, fd, fe, ff, int, since, txt, Cell, Kind, StudyError, TableOut};
use signorini_fem::BarMass;
use signorini_norms::SpaceIntegrator;
use signorini_plot::{line_chart, stack_vertically, Chart, Scale, Series, Style};
use signorini_run::{run as run_steps, Benchmark, NormObserver, Observer, RunConfig, RunError, Sample};
use signorini_schemes::SchemeSpec;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

/// The period of the Dirichlet bar.
const PERIOD: f64 = 3.0;

crate::options::study_config! {
    /// Long horizons: the Dirichlet bar over ⟨t_end⟩ (ten periods by default)
    /// for ⟨runs⟩: the largest L² error in each period, every impact time
    /// against the exact one, the drift per period. Then (unless ⟨energy⟩ is off)
    /// the energy-growth table: ⟨energy_runs⟩ (or ⟨energy_all⟩: every named
    /// scheme with every mass it accepts) at each dx/dt of ⟨energy_ratios⟩ on
    /// ⟨energy_m⟩ elements to ⟨energy_t_end⟩: the largest E/budget and when it
    /// first exceeds 2 (energy_growth.csv, energy_vs_time.csv,
    /// energy_growth.svg), from bar-dirichlet's initial data or
    /// ⟨energy_benchmark⟩'s. The default table takes minutes; a shorter
    /// ⟨energy_t_end⟩ shortens it.
    study "long_horizon";
    pub struct Config {
        /// scheme:mass pairs, comma-separated (default: ps-e0 with every
        /// mass, moreau-jean with std and lumped).
        #[serde(deserialize_with = "de_runs")]
        pub runs: Vec<(SchemeSpec, BarMass)> = default_runs(),
        /// Numbers of elements m, comma-separated.
        pub levels: Vec<usize> = vec![20, 40, 80],
        /// dx/dt (the papers').
        pub ratio: f64 = 10.0,
        /// Horizon (three time units a period: 30 is ten periods).
        pub t_end: f64 = 30.0,
        /// The energy-growth table (energy_growth.csv, energy_vs_time.csv,
        /// energy_growth.svg; off: left out).
        pub energy: bool = true,
        /// Energy-growth table: scheme:mass pairs, comma-separated (default:
        /// newmark-cn and ps-e0 with std, lumped, mod, mod3; ps-e1 with std,
        /// mod3; moreau-jean with std, lumped; hybrid with mod, mod3).
        #[serde(deserialize_with = "de_energy_runs")]
        pub energy_runs: Option<Vec<(SchemeSpec, BarMass)>> = None,
        /// Energy-growth table: every named scheme with every mass it
        /// accepts (instead of the default runs; not with ⟨energy_runs⟩).
        pub energy_all: bool = false,
        /// Energy-growth table: dx/dt values, comma-separated.
        pub energy_ratios: Vec<f64> = EnergyTable::default().ratios,
        /// Energy-growth table: number of elements.
        pub energy_m: usize = EnergyTable::default().m,
        /// Energy-growth table: horizon.
        pub energy_t_end: f64 = EnergyTable::default().t_end,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/long-horizon"),
        /// Energy-growth table: the benchmark whose initial data, load and
        /// far end the runs start from (bar-dirichlet; bar-neumann-gravity:
        /// Doyen–Ern–Piperno's bouncing bar, two impacts every 16 time
        /// units; bar-neumann-gravity-0.11 to ⟨energy_t_end⟩ ≤ 225;
        /// bar-mirrored).
        #[serde(deserialize_with = "de_energy_benchmark")]
        pub energy_benchmark: Benchmark = Benchmark::BarDirichlet,
    }
}

fn de_runs<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<(SchemeSpec, BarMass)>, D::Error> {
    crate::options::with::list(d, |r| parse_runs_of("runs", r))
}
fn de_energy_benchmark<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Benchmark, D::Error> {
    crate::options::with::text(d, |s| s.parse::<Benchmark>().map_err(|e| StudyError::config("energy_benchmark", format!("⟨energy_benchmark⟩: {e}"))))
}
fn de_energy_runs<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<Vec<(SchemeSpec, BarMass)>>, D::Error> {
    crate::options::with::list(d, |r| parse_runs_of("energy_runs", r)).map(Some)
}

/// ps-e0 with every mass, moreau-jean with std and lumped.
fn default_runs() -> Vec<(SchemeSpec, BarMass)> {
    let ps: SchemeSpec = "ps-e0".parse().expect("a preset");
    let mj: SchemeSpec = "moreau-jean".parse().expect("a preset");
    let masses = [BarMass::Std, BarMass::Lumped, BarMass::Mod, BarMass::Mod2, BarMass::Mod3, BarMass::Transfer, BarMass::Singular];
    let mut runs: Vec<(SchemeSpec, BarMass)> = masses.iter().map(|&m| (ps, m)).collect();
    runs.extend([(mj, BarMass::Std), (mj, BarMass::Lumped)]);
    runs
}

impl Config {
    /// The energy-growth table the configuration asks for (`None`: off).
    pub fn energy_table(&self) -> Option<EnergyTable> {
        self.energy.then(|| {
            let runs = if self.energy_all { EnergyTable::all_runs() } else { self.energy_runs.clone().unwrap_or_else(|| EnergyTable::default().runs) };
            EnergyTable { runs, ratios: self.energy_ratios.clone(), m: self.energy_m, t_end: self.energy_t_end, benchmark: self.energy_benchmark }
        })
    }
}

/// The energy-growth table's runs (module docs).
#[derive(Clone, Debug)]
pub struct EnergyTable {
    /// (scheme, mass) pairs (`--energy-runs`; `--energy-all`: [`EnergyTable::all_runs`]).
    pub runs: Vec<(SchemeSpec, BarMass)>,
    /// dx/dt values (`--energy-ratios`, default 1, 2, 10).
    pub ratios: Vec<f64>,
    /// Elements (`--energy-m`, default 100).
    pub m: usize,
    /// Horizon (`--energy-t-end`, default 10⁴).
    pub t_end: f64,
    /// The benchmark the runs start from (`--energy-benchmark`, default
    /// bar-dirichlet).
    pub benchmark: Benchmark,
}

/// Windows of `energy_vs_time.csv`.
const ENERGY_WINDOWS: usize = 100;

impl Default for EnergyTable {
    /// newmark-cn and ps-e0 with std, lumped, mod and mod3; ps-e1 with std
    /// and mod3; moreau-jean with std and lumped; hybrid with mod and mod3.
    fn default() -> Self {
        let p = |s: &str| -> SchemeSpec { s.parse().expect("a preset") };
        let (cn, ps0, ps1, mj, hy) = (p("newmark-cn"), p("ps-e0"), p("ps-e1"), p("moreau-jean"), p("hybrid"));
        let four = [BarMass::Std, BarMass::Lumped, BarMass::Mod, BarMass::Mod3];
        let mut runs: Vec<(SchemeSpec, BarMass)> = four.iter().map(|&m| (cn, m)).chain(four.iter().map(|&m| (ps0, m))).collect();
        runs.extend([(ps1, BarMass::Std), (ps1, BarMass::Mod3), (mj, BarMass::Std), (mj, BarMass::Lumped), (hy, BarMass::Mod), (hy, BarMass::Mod3)]);
        Self { runs, ratios: vec![1.0, 2.0, 10.0], m: 100, t_end: 1e4, benchmark: Benchmark::BarDirichlet }
    }
}

impl EnergyTable {
    /// `--energy-all`: every named scheme (presets, reduced, peers, and
    /// cd-taylor with its lumped mass) with every mass it accepts (mod1 is
    /// mod: left out).
    pub fn all_runs() -> Vec<(SchemeSpec, BarMass)> {
        let masses = [BarMass::Std, BarMass::Lumped, BarMass::Mod, BarMass::Mod2, BarMass::Mod3, BarMass::Transfer, BarMass::Singular];
        let mut runs: Vec<(SchemeSpec, BarMass)> =
            SchemeSpec::named().flat_map(|(_, s)| masses.iter().filter(move |m| s.accepts_massless_node(m.massless_contact_node())).map(move |&m| (s, m))).collect();
        runs.extend(SchemeSpec::group(signorini_schemes::Group::SingleMass).map(|(_, s)| (s, BarMass::Lumped)));
        runs
    }

    fn validate(&self) -> Result<(), StudyError> {
        if self.runs.is_empty() {
            return Err(StudyError::config("energy_runs", "⟨energy_runs⟩: allowed one or more scheme:mass pairs"));
        }
        for (s, m) in &self.runs {
            if !s.accepts_massless_node(m.massless_contact_node()) {
                return Err(StudyError::config("energy_runs", format!("⟨energy_runs⟩ {s}:{m}: the scheme does not take this mass (massless contact node: {})", m.massless_contact_node())));
            }
        }
        if self.ratios.is_empty() || self.ratios.iter().any(|r| !(*r > 0.0 && r.is_finite())) {
            return Err(StudyError::config("energy_ratios", format!("⟨energy_ratios⟩ {:?}: allowed one or more finite values > 0", self.ratios)));
        }
        if !(2..=20_000).contains(&self.m) {
            return Err(StudyError::config("energy_m", format!("⟨energy_m⟩ {}: allowed an integer in [2, 20000]", self.m)));
        }
        if !(self.t_end >= PERIOD && self.t_end.is_finite() && self.t_end <= 1e6) {
            return Err(StudyError::config("energy_t_end", format!("⟨energy_t_end⟩ {}: allowed finite, in [3, 1e6]", self.t_end)));
        }
        let steps = self.m as f64 * self.ratios.iter().fold(0.0, |a: f64, &r| a.max(r)) * self.t_end;
        if steps > 1e9 {
            return Err(StudyError::config("energy_t_end", format!("⟨energy_t_end⟩ {}: {steps:.2e} steps at the largest dx/dt, allowed at most 1e9", self.t_end)));
        }
        // bar-neumann-gravity-0.11 has its closed form only up to t ≈ 225.
        self.benchmark.exact(self.t_end).map_err(|e| StudyError::config("energy_t_end", format!("⟨energy_t_end⟩ {} with ⟨energy_benchmark⟩ {}: {e}", self.t_end, self.benchmark)))?;
        Ok(())
    }
}

/// Parses `runs`: `scheme:mass` pairs, comma-separated (a scheme with
/// parameters keeps its commas inside parentheses).
pub fn parse_runs(raw: &[String]) -> Result<Vec<(SchemeSpec, BarMass)>, StudyError> {
    parse_runs_of("runs", raw)
}

/// [`parse_runs`] for the field `field` (`runs`, `energy_runs`), which an error names.
pub fn parse_runs_of(field: &str, raw: &[String]) -> Result<Vec<(SchemeSpec, BarMass)>, StudyError> {
    let f = crate::options::at(field);
    crate::split_schemes(raw)
        .iter()
        .map(|p| {
            let (s, m) = p.rsplit_once(':').ok_or_else(|| StudyError::config(field, format!("{f} {p:?}: allowed scheme:mass, e.g. ps-e0:mod3")))?;
            let scheme = s.parse::<SchemeSpec>().map_err(|e| StudyError::config(field, format!("{f} {p:?}: {e}")))?;
            let mass = m.parse::<BarMass>().map_err(|e| StudyError::config(field, format!("{f} {p:?}: {e}")))?;
            Ok((scheme, mass))
        })
        .collect()
}

impl Config {
    /// Every check, before anything runs.
    pub fn validate(&self) -> Result<(), StudyError> {
        if self.runs.is_empty() {
            return Err(StudyError::config("runs", "⟨runs⟩: allowed one or more scheme:mass pairs"));
        }
        for (s, m) in &self.runs {
            if !s.accepts_massless_node(m.massless_contact_node()) {
                return Err(StudyError::config("runs", format!("⟨runs⟩ {s}:{m}: the scheme does not take this mass (massless contact node: {})", m.massless_contact_node())));
            }
        }
        if self.levels.is_empty() || self.levels.iter().any(|&m| !(2..=20_000).contains(&m)) {
            return Err(StudyError::config("levels", format!("⟨levels⟩ {:?}: allowed one or more integers in [2, 20000]", self.levels)));
        }
        if !(self.ratio > 0.0 && self.ratio.is_finite()) {
            return Err(StudyError::config("ratio", format!("⟨ratio⟩ {}: allowed finite and > 0", self.ratio)));
        }
        if !(self.t_end >= PERIOD && self.t_end.is_finite() && self.t_end <= 3000.0) {
            return Err(StudyError::config("t_end", format!("⟨t_end⟩ {}: allowed finite, in [3, 3000] (one period at least)", self.t_end)));
        }
        let steps = self.levels.iter().map(|&m| m as f64 * self.ratio * self.t_end).fold(0.0, f64::max);
        if steps > 1e9 {
            return Err(StudyError::config("t_end", format!("⟨t_end⟩ {}: {steps:.2e} steps at the finest level, allowed at most 1e9", self.t_end)));
        }
        let d = Config::default();
        if !self.energy
            && (self.energy_runs.is_some()
                || self.energy_all
                || self.energy_ratios != d.energy_ratios
                || self.energy_m != d.energy_m
                || self.energy_t_end != d.energy_t_end
                || self.energy_benchmark != d.energy_benchmark)
        {
            return Err(StudyError::config(
                "energy",
                "⟨energy⟩ off: ⟨energy_runs⟩, ⟨energy_all⟩, ⟨energy_ratios⟩, ⟨energy_m⟩, ⟨energy_t_end⟩ and ⟨energy_benchmark⟩ act only with the energy table: remove them, or turn it on",
            ));
        }
        if self.energy_all && self.energy_runs.is_some() {
            return Err(StudyError::config("energy_runs", "⟨energy_runs⟩: not both ⟨energy_runs⟩ and ⟨energy_all⟩"));
        }
        if let Some(e) = self.energy_table() {
            e.validate()?;
        }
        Ok(())
    }
}

/// What the study computed and wrote ([`crate::Report`]); its tables:
/// `error_vs_time.csv`, `impacts.csv`, `summary.csv`, then (with the
/// energy table) `energy_growth.csv`, `energy_vs_time.csv`.
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
    let energy = a.energy_table();
    let energy_jobs = energy.as_ref().map_or(0, |e| e.runs.len() * e.ratios.len());
    let total = (a.runs.len() * a.levels.len() + energy_jobs) as u64;
    let mut done = 0;
    let mut md =
        format!("| scheme | mass | m | max L² error in period 1 | … in period {periods} | L∞(0,T;L²) | impact drift per period | final energy (exact 1/8) |\n|---|---|---|---|---|---|---|---|\n");
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
            // A drift needs two impacts (a horizon of one period has one).
            let drift = if slope.is_finite() { format!("{slope:+.2e}") } else { "—".to_string() };
            md.push_str(&format!("| {sn} | {mn} | {m} | {:.3e} | {:.3e} | {:.3e} | {drift} | {:.5} |\n", watch.per_period[0], watch.per_period[periods - 1], r.linf_l2_u, energy.0));
            done += 1;
            progress(done, total);
        }
    }
    let mut tables = vec![ev.finish()?, im.finish()?, su.finish()?];
    let mut report = format!("# Long horizon: bar-dirichlet over T = {} ({periods} periods), dx/dt = {} (output in {})\n\n{md}", a.t_end, a.ratio, a.out.display());
    let mut notes = Vec::new();
    if let Some(e) = &energy {
        energy_growth(a, e, done, total, progress, &mut tables, &mut report, &mut notes)?;
    }
    Ok(crate::Report { tables, report, wall_s: since(start), notes })
}

/// One energy-growth run's results.
struct Growth {
    scheme: SchemeSpec,
    mass: BarMass,
    ratio: f64,
    dt: f64,
    w: Windows,
    /// The time at which the run's 1e6 energy guard (or its non-finite
    /// guard) stopped it, if it did.
    stopped: Option<f64>,
}

/// E/E_ref at every level (no damping, and a steady load at most, whose
/// potential is in the energy, so the first energy E_ref is the budget of
/// every scheme, closed or open): its
/// largest value per window of `[0, T]` and over the run, the first time it
/// exceeds 2, the last energy and level.
struct Windows {
    t_end: f64,
    e_ref: Option<f64>,
    last: f64,
    steps: usize,
    max: Vec<f64>,
    max_ratio: f64,
    t_max: f64,
    first2: Option<f64>,
}

impl Windows {
    fn new(t_end: f64) -> Self {
        Self { t_end, e_ref: None, last: f64::NAN, steps: 0, max: vec![f64::NAN; ENERGY_WINDOWS], max_ratio: f64::NEG_INFINITY, t_max: 0.0, first2: None }
    }
}

impl Observer for Windows {
    fn wants_energy(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        self.steps = s.n;
        if let Some((t, e)) = s.energy {
            let r = e / *self.e_ref.get_or_insert(e);
            let k = ((t / self.t_end * ENERGY_WINDOWS as f64) as usize).min(ENERGY_WINDOWS - 1);
            // NaN.max(r) = r: an empty window takes its first value.
            self.max[k] = self.max[k].max(r);
            if r > self.max_ratio {
                (self.max_ratio, self.t_max) = (r, t);
            }
            if self.first2.is_none() && r > 2.0 {
                self.first2 = Some(t);
            }
            self.last = e;
        }
        Ok(())
    }
}

/// The energy-growth table: every (scheme, mass, dx/dt) in parallel.
#[allow(clippy::too_many_arguments)]
fn energy_growth(
    a: &Config,
    e: &EnergyTable,
    done0: u64,
    total: u64,
    progress: &(dyn Fn(u64, u64) + Sync),
    tables: &mut Vec<crate::Table>,
    report: &mut String,
    notes: &mut Vec<String>,
) -> Result<(), StudyError> {
    use rayon::prelude::*;
    let b = e.benchmark;
    let exact = b.exact(e.t_end)?;
    let jobs: Vec<(SchemeSpec, BarMass, f64)> = e.runs.iter().flat_map(|&(s, m)| e.ratios.iter().map(move |&r| (s, m, r))).collect();
    let done = AtomicU64::new(done0);
    let results: Vec<Result<Option<Growth>, StudyError>> = jobs
        .par_iter()
        .map(|&(scheme, mass, ratio)| {
            let p = b.problem(exact.as_ref(), e.m, mass)?;
            let dt = p.bar.h() / ratio;
            let mut stepper = match scheme.build(p.dynamics(), dt, &p.initial) {
                Ok(s) => s,
                // --energy-all: an explicit scheme beyond its stability limit is left out.
                Err(signorini_schemes::SchemeError::Unstable { .. }) => {
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                    return Ok(None);
                }
                Err(err) => return Err(RunError::from(err).into()),
            };
            let cfg = RunConfig::new(dt, e.t_end)?;
            let mut w = Windows::new(e.t_end);
            let stopped = match run_steps(stepper.as_mut(), &p.initial.u, &cfg, &mut [&mut w]) {
                Ok(_) => None,
                // Growth past the run's 1e6 guard (or to non-finite values) stops the run: a row all the same.
                Err(RunError::EnergyGrowth { time, .. } | RunError::BlowUp { time, .. }) => Some(time),
                Err(err) => return Err(err.into()),
            };
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            Ok(Some(Growth { scheme, mass, ratio, dt, w, stopped }))
        })
        .collect();
    let head = [("scheme", Kind::S), ("mass", Kind::S), ("m", Kind::I), ("dx_dt", Kind::F)];
    let with = |more: &[(&'static str, Kind)]| -> Vec<(&'static str, Kind)> { head.iter().copied().chain(more.iter().copied()).collect() };
    let mut gt = TableOut::create(
        &a.out,
        "energy_growth.csv",
        &with(&[
            ("dt", Kind::F),
            ("steps", Kind::I),
            ("e_ref", Kind::F),
            ("final_energy", Kind::F),
            ("max_ratio", Kind::F),
            ("t_max_ratio", Kind::F),
            ("t_ratio_2", Kind::F),
            ("final_ratio", Kind::F),
            ("t_stopped", Kind::F),
        ]),
    )?;
    let mut vt = TableOut::create(&a.out, "energy_vs_time.csv", &with(&[("window", Kind::I), ("t_to", Kind::F), ("max_ratio", Kind::F)]))?;
    let budget = if exact.body_force() == 0.0 { "no load, no damping" } else { "a steady load, in the energy; no damping" };
    let mut md = format!("\n# Energy growth: {b}, m = {}, to T = {} (E/budget; budget = the first energy, {budget})\n\n| scheme | mass | dx/dt | max E/budget | at t | first t with E/budget > 2 | final E/budget (or where the run's 1e6 energy guard stopped it) |\n|---|---|---|---|---|---|---|\n", e.m, e.t_end);
    let mut kept = Vec::new();
    for (r, &(scheme, mass, ratio)) in results.into_iter().zip(&jobs) {
        let Some(g) = r? else {
            notes.push(format!("energy growth: {scheme}:{mass} at dx/dt = {ratio} left out (beyond the scheme's stability limit)"));
            continue;
        };
        let (sn, mn) = (scheme.to_string(), mass.to_string());
        let w = &g.w;
        let e_ref = w.e_ref.unwrap_or(f64::NAN);
        gt.row(vec![
            txt(&sn),
            txt(&mn),
            int(e.m),
            fd(g.ratio),
            fe(g.dt, 6),
            int(w.steps),
            fe(e_ref, 10),
            fe(w.last, 10),
            fe(w.max_ratio, 6),
            ff(w.t_max, 4),
            w.first2.map_or(Cell::E, |t| ff(t, 4)),
            fe(w.last / e_ref, 6),
            g.stopped.map_or(Cell::E, |t| ff(t, 4)),
        ])?;
        for (k, x) in w.max.iter().enumerate() {
            vt.row(vec![txt(&sn), txt(&mn), int(e.m), fd(g.ratio), int(k + 1), ff(e.t_end * (k + 1) as f64 / ENERGY_WINDOWS as f64, 3), if x.is_nan() { Cell::E } else { fe(*x, 6) }])?;
        }
        let fate = match g.stopped {
            Some(t) => format!("stopped by the 1e6 guard at t = {t:.1}"),
            None => format!("{:.4}", w.last / e_ref),
        };
        md.push_str(&format!("| {sn} | {mn} | {} | {:.4e} | {:.1} | {} | {fate} |\n", g.ratio, w.max_ratio, w.t_max, w.first2.map_or("—".to_string(), |t| format!("{t:.2}"))));
        kept.push(g);
    }
    tables.push(gt.finish()?);
    tables.push(vt.finish()?);
    report.push_str(&md);
    // One panel per dx/dt: the largest E/budget per window against t.
    let panels: Result<Vec<String>, signorini_plot::PlotError> = e
        .ratios
        .iter()
        .map(|&r| {
            let series: Vec<Series> = kept
                .iter()
                .filter(|g| g.ratio == r)
                .map(|g| {
                    let style = Style { group: e.runs.iter().map(|x| x.0).position(|s| s == g.scheme), variant: e.runs.iter().filter(|x| x.0 == g.scheme).position(|x| x.1 == g.mass) };
                    let points = g.w.max.iter().enumerate().map(|(k, w)| (e.t_end * (k + 1) as f64 / ENERGY_WINDOWS as f64, *w)).collect();
                    Series { label: format!("{} {}", g.scheme, g.mass), points, reference: false, style }
                })
                .collect();
            let title = format!("{b}, m = {}, dx/dt = {r}: largest E/budget per window of T/{ENERGY_WINDOWS}", e.m);
            line_chart(&Chart { title: &title, x_label: "t", y_label: "E / budget", scale: Scale::LogLog, size: (900, 500) }, &series)
        })
        .collect();
    match panels.and_then(|p| stack_vertically(&p)) {
        Ok(svg) => crate::write_file(&a.out.join("energy_growth.svg"), &svg)?,
        Err(err) => notes.push(format!("warning: energy_growth.svg skipped: {err}")),
    }
    Ok(())
}
