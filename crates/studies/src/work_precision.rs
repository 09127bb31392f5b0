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
//! then `setup_s,step_s` then `step_s_min,step_s_max,repeats` (`wall_s`
//! and `step_s`: the stepping alone, the median of `--repeats` runs, one at
//! a time, taken in `--repeats` rounds over every configuration so that a
//! burst of load on a shared machine falls on all of them alike;
//! `step_s_min`, `step_s_max`: the range of those runs; `setup_s`: the
//! median set-up of the same runs — the problem and the scheme built as
//! `signorini run` builds them, CFL check and factorisations included;
//! `modes` 0 for a full model; the
//! bar rows leave the three beam columns empty, the beam rows the norm
//! columns; `m` is J and `degree` 3, Hermite cubics, for the beam;
//! `release_err` is |first discrete − first exact release time|; the
//! impact-power rows are the beam with its support motion, `wall_s` and
//! `step_s` the whole run, timed once (`repeats` 1), `setup_s` empty),
//! `<benchmark>.svg` per benchmark (log-log, L²(0,T;L²) error — the beam's
//! tip error — against wall time) and for the bars `<benchmark>-strain.svg`
//! (L∞(0,T;V)) and `<benchmark>-force.svg` (λ in L²(0,T)): each the
//! frontier (the cheapest configuration per error level, a staircase) and
//! the few configurations the table names, not every curve; and on stdout
//! per quantity the configurations reaching each accuracy band ranked by
//! median cost — two whose cost ranges overlap are a tie and printed as one
//! (`tie: … / …`) — with the conditions under which each cheapest one
//! holds, a configuration whose error does not fall with m in a quantity
//! (least-squares rate below 0.1, unless it is round-off) marked so
//! wherever it is named. Only the timing columns, the SVGs and the report
//! depend on the timings; every other column is deterministic.

use crate::{create_dir, fe, int, opt, since, txt, Kind, StudyError, TableOut};
use rayon::prelude::*;
use signorini_fem::BarMass;
use signorini_norms::NormReport;
use signorini_plot::{line_chart, Chart, Scale, Series, Style};
use signorini_reduce::Keep;
use signorini_run::beam::{BeamScene, BeamSetup, Pipe};
use signorini_run::stats::{batch_means, Interval};
use signorini_run::study::{self, StudyConfig};
use signorini_run::{run as run_steps, Benchmark, NormObserver, Observer, RunConfig, RunError, Sample};
use signorini_schemes::{SchemeSpec, Stepper};
use std::fmt::Write as _;
use std::path::PathBuf;

crate::options::study_config! {
    /// Work–precision: error against wall time for every scheme and mass, then
    /// the frontier on the same axes: Courant-one central difference, P2/P3
    /// (⟨degrees⟩), reduced bar and beam models (⟨modes⟩), and the beam of
    /// figure 2 at ⟨beam_dts⟩ against a reference at ⟨beam_ref_dt⟩ (tip error
    /// over [0, ⟨beam_window⟩] and [0, ⟨beam_t_end⟩], first-impact error). The
    /// beam with its support motion (fig. 2 with `[support]`) at ⟨beam_stat_dts⟩
    /// gives its impact power over ⟨beam_stat_window⟩ forcing periods with a
    /// 95 % interval, against ⟨beam_stat_ref_dt⟩. Empty ⟨degrees⟩, ⟨modes⟩,
    /// ⟨beam_dts⟩ or ⟨beam_stat_dts⟩ leave those rows out.
    study "work_precision";
    pub struct Config {
        /// Levels m, comma-separated.
        pub levels: Vec<usize> = vec![10, 20, 40, 80, 160, 320, 640],
        /// Element degrees beyond P1 (2, 3), comma-separated; empty: none.
        pub degrees: Vec<usize> = vec![2, 3],
        /// Kept modes of the reduced bar and beam models, comma-separated;
        /// empty: none.
        pub modes: Vec<usize> = vec![2, 4, 8, 16],
        /// Time steps of the beam rows (s), comma-separated; empty: no beam
        /// rows.
        pub beam_dts: Vec<f64> = vec![1e-5, 2.5e-5, 5e-5, 1e-4, 2.5e-4, 5e-4],
        /// The beam reference's time step (s).
        pub beam_ref_dt: f64 = 2.5e-7,
        /// The beam's error window [0, w] (s).
        pub beam_window: f64 = 0.1,
        /// The beam's horizon (s).
        pub beam_t_end: f64 = 1.0,
        /// Time steps of the beam's impact-power rows (s), comma-separated;
        /// empty: none. Fig. 2 with `[support]`, its impact power over a
        /// long window against the run at ⟨beam_stat_ref_dt⟩.
        pub beam_stat_dts: Vec<f64> = vec![5e-5, 2.5e-5, 1e-5],
        /// The impact power's reference step (s).
        pub beam_stat_ref_dt: f64 = 5e-6,
        /// The impact power's window (forcing periods; 320 is 201 s at
        /// ω = 10; 20 batches, after 10 periods).
        pub beam_stat_window: f64 = 320.0,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/work-precision"),
        /// The beam rows' reference: fine-step (the projection scheme at
        /// ⟨beam_ref_dt⟩) or event-driven (the exact semi-discrete solution,
        /// sampled at the largest step dividing every ⟨beam_dts⟩). The bar
        /// rows are always measured against their closed forms (what the
        /// convergence study's reference exact means); the beam has none,
        /// hence fine-step where convergence says exact, and exact is
        /// refused.
        #[serde(deserialize_with = "de_reference")]
        pub reference: BeamReference = BeamReference::FineStep,
        /// Timed runs per configuration, in [1, 100]: the cost is their
        /// median, and two configurations whose ranges [min, max] overlap
        /// are a tie.
        pub repeats: usize = 5,
        /// The bar rows' schemes, comma-separated (default: every named
        /// scheme of `signorini list`, by name); a family without presets by
        /// its call (`contact-stabilized`, `nsga(0.5)`). Each runs with
        /// every mass it accepts.
        #[serde(deserialize_with = "crate::options::with::some_schemes")]
        pub schemes: Option<Vec<SchemeSpec>> = None,
    }
}

fn de_reference<'de, D: serde::Deserializer<'de>>(d: D) -> Result<BeamReference, D::Error> {
    crate::options::with::text(d, |s| s.parse())
}

impl crate::options::FieldType for BeamReference {
    const KIND: crate::options::Kind = crate::options::Kind::Text;
    fn show(&self) -> Option<String> {
        Some(if *self == BeamReference::FineStep { "fine-step" } else { "event-driven" }.to_string())
    }
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
    /// `fine-step` or `event-driven`. `cargo xtask convergence --reference`
    /// takes `exact` (the closed form) where this takes `fine-step`: the
    /// bar rows here are always measured against their closed forms, and
    /// the flag chooses only the beam's reference, which has none, so
    /// `exact` is refused with that reason rather than read as one of them.
    fn from_str(s: &str) -> Result<Self, StudyError> {
        match s {
            "fine-step" => Ok(Self::FineStep),
            "event-driven" => Ok(Self::EventDriven),
            "exact" => Err(StudyError::config(
                "reference",
                "⟨reference⟩ \"exact\": the beam has no closed form (the bar rows are always measured against theirs, which is what the convergence study's reference exact means); ⟨reference⟩ chooses the beam rows' reference: allowed fine-step (the projection scheme at ⟨beam_ref_dt⟩), event-driven (the exact semi-discrete solution)",
            )),
            _ => Err(StudyError::config("reference", format!("⟨reference⟩ {s:?}: allowed fine-step, event-driven"))),
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
        let schemes: Vec<SchemeSpec> = crate::time_stepping_schemes("schemes", self.schemes.as_deref())?.into_iter().map(|(_, s)| s).collect();
        for benchmark in BARS {
            let (ratio, t_end) = benchmark.default_ratio_and_horizon();
            for r in [ratio, ratio.max(10.0)] {
                StudyConfig::new(benchmark, schemes.clone(), vec![BarMass::Std], self.levels.clone(), r, t_end).validate().map_err(|e| StudyError::config("levels", format!("⟨levels⟩: {e}")))?;
            }
        }
        if let Some(&k) = self.degrees.iter().find(|&&k| !(2..=3).contains(&k)) {
            return Err(StudyError::config("degrees", format!("⟨degrees⟩ {k}: allowed 2 and 3 (P1 is always run)")));
        }
        if let Some(&r) = self.modes.iter().find(|&&r| !(1..=10_000).contains(&r)) {
            return Err(StudyError::config("modes", format!("⟨modes⟩ {r}: allowed integers in [1, 10000] (levels with fewer interior modes are skipped)")));
        }
        if !(1..=100).contains(&self.repeats) {
            return Err(StudyError::config("repeats", format!("⟨repeats⟩ {}: allowed integers in [1, 100]", self.repeats)));
        }
        if self.reference == BeamReference::EventDriven && self.beam_dts.is_empty() {
            return Err(StudyError::config("reference", "⟨reference⟩ event-driven: it is the beam rows' reference, and ⟨beam_dts⟩ '' asks for none; allowed with beam rows"));
        }
        let (w, te, rdt) = (self.beam_window, self.beam_t_end, self.beam_ref_dt);
        if !(te > 0.0 && te <= 10.0) {
            return Err(StudyError::config("beam_t_end", format!("⟨beam_t_end⟩ {te}: allowed in (0, 10] s")));
        }
        if !(w > 0.0 && w <= te) {
            return Err(StudyError::config("beam_window", format!("⟨beam_window⟩ {w}: allowed in (0, ⟨beam_t_end⟩ = {te}] s")));
        }
        if !(rdt > 0.0 && rdt.is_finite() && te / rdt <= 4e7) {
            return Err(StudyError::config("beam_ref_dt", format!("⟨beam_ref_dt⟩ {rdt}: allowed > 0 with at most 4e7 steps to ⟨beam_t_end⟩ = {te} s")));
        }
        if let Some(&dt) = self.beam_dts.iter().find(|&&dt| !(dt >= 2.0 * rdt && dt <= w)) {
            return Err(StudyError::config("beam_dts", format!("⟨beam_dts⟩ {dt}: allowed in [2 × ⟨beam_ref_dt⟩, ⟨beam_window⟩] = [{}, {w}] s", 2.0 * rdt)));
        }
        let stats = self.stat_config(&self.beam_stat_dts);
        stats.validate().map_err(|e| match e {
            StudyError::Config { field, message } => {
                let flag = match field.as_str() {
                    "dts" => "beam_stat_dts",
                    _ => "beam_stat_window",
                };
                StudyError::Config { field: flag.to_string(), message: message.rename(&field, flag) }
            }
            other => other,
        })?;
        let r = self.beam_stat_ref_dt;
        if !(r.is_finite() && r > 0.0 && self.beam_stat_dts.iter().all(|&d| d >= 2.0 * r)) {
            return Err(StudyError::config("beam_stat_ref_dt", format!("⟨beam_stat_ref_dt⟩ {r}: allowed > 0 and at most half of every ⟨beam_stat_dts⟩")));
        }
        self.stat_config(&[r]).validate().map_err(|e| StudyError::config("beam_stat_ref_dt", format!("⟨beam_stat_ref_dt⟩ {r}: {e}")))?;
        let top = self.levels.iter().copied().max().unwrap_or(0);
        crate::fits_memory("levels", 4 * top, 1)?;
        crate::fits_memory("degrees", 3 * top, 1)
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
    let (values, steps) = crate::beam_statistics::run_case("fig2-support", dt, 19, None, &sc)?;
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
    /// The stepping's cost: the median of the timed runs and their range
    /// (filled in by the timing rounds for the rows that have `timing`).
    cost: Cost,
    /// Set-up time (median of the timed runs), seconds.
    setup: f64,
    /// How to time one run of this row (`None`: timed where it ran).
    timing: Option<Timed>,
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
    /// Where in its sweep: `m=20`, or `dt=5e-4` for the beam.
    fn at(&self) -> String {
        if self.benchmark == BEAM {
            format!("dt={:e}", self.dt)
        } else {
            format!("m={}", self.m)
        }
    }
    /// The row as the cheapest-per-target tables see it, in quantity `q`.
    fn entry(&self, q: Quantity) -> Entry {
        Entry { label: self.label(), at: self.at(), cost: self.cost, error: self.error(q) }
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

/// The beam's target tip errors (m).
const BEAM_TARGETS: [f64; 5] = [3e-2, 1e-2, 3e-3, 1e-3, 3e-4];

// ---------------------------------------------------------------------------
// Ranking by cost with its spread, the frontier, the conditions

/// A configuration's cost, timed `n` times: the median and the range of
/// the runs (seconds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cost {
    /// The median run (for an even count, the mean of the middle two).
    pub median: f64,
    /// The fastest run.
    pub min: f64,
    /// The slowest run.
    pub max: f64,
    /// Runs timed.
    pub n: usize,
}

impl Cost {
    /// Not timed yet (NaN; the timing rounds fill it in).
    const UNTIMED: Cost = Cost { median: f64::NAN, min: f64::NAN, max: f64::NAN, n: 0 };

    /// The cost of the runs `samples`; `None` if there is none or one is not finite.
    pub fn of(samples: &[f64]) -> Option<Cost> {
        if samples.is_empty() || samples.iter().any(|s| !s.is_finite()) {
            return None;
        }
        let mut s = samples.to_vec();
        s.sort_by(f64::total_cmp);
        let n = s.len();
        let median = if n % 2 == 1 { s[n / 2] } else { 0.5 * (s[n / 2 - 1] + s[n / 2]) };
        Some(Cost { median, min: s[0], max: s[n - 1], n })
    }

    /// A single run.
    pub fn once(t: f64) -> Cost {
        Cost { median: t, min: t, max: t, n: 1 }
    }

    /// Cheaper beyond the timing spread: this whole range lies below `other`'s.
    pub fn clearly_below(&self, other: &Cost) -> bool {
        self.max < other.min
    }

    /// A tie: the ranges overlap (neither lies wholly below the other).
    pub fn ties(&self, other: &Cost) -> bool {
        !self.clearly_below(other) && !other.clearly_below(self)
    }
}

/// The tier of each of `costs`: 0 for every cost that no other lies wholly
/// below (the cheapest by median and whatever ties with it), 1 for the same
/// among the rest, and so on. Two costs of one tier need not overlap each
/// other, but neither is clearly cheaper than the other given the rest.
pub fn tiers(costs: &[Cost]) -> Vec<usize> {
    const OPEN: usize = usize::MAX;
    let mut tier = vec![OPEN; costs.len()];
    let mut t = 0;
    loop {
        let open: Vec<usize> = (0..costs.len()).filter(|&i| tier[i] == OPEN).collect();
        if open.is_empty() {
            return tier;
        }
        let now: Vec<usize> = open.iter().copied().filter(|&i| !open.iter().any(|&j| j != i && costs[j].clearly_below(&costs[i]))).collect();
        // Never empty for well-formed ranges (min <= max: "clearly below" is
        // a strict order); malformed ones all land in this tier.
        for i in if now.is_empty() { open } else { now } {
            tier[i] = t;
        }
        t += 1;
    }
}

/// The accuracy–cost frontier of `(cost, error)` points: the indices of the
/// points that no other point matches or beats in both (as cheap or cheaper
/// and as accurate or more, better in one), by increasing cost and so
/// decreasing error — the cheapest point per error level. Points with a
/// negative or non-finite cost or error are left out.
pub fn frontier(points: &[(f64, f64)]) -> Vec<usize> {
    let ok = |&(c, e): &(f64, f64)| c.is_finite() && e.is_finite() && c >= 0.0 && e >= 0.0;
    let mut idx: Vec<usize> = (0..points.len()).filter(|&i| ok(&points[i])).collect();
    idx.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0).then(points[a].1.total_cmp(&points[b].1)));
    let mut best = f64::INFINITY;
    let mut out = Vec::new();
    for i in idx {
        if points[i].1 < best {
            best = points[i].1;
            out.push(i);
        }
    }
    out
}

/// One configuration at one level in a cheapest-per-target table.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The configuration: `scheme mass`, then `P2`/`P3` and `r=` when not
    /// P1 or not the full model.
    pub label: String,
    /// Where in its sweep: `m=20`, or `dt=5e-4` for the beam.
    pub at: String,
    /// Its cost.
    pub cost: Cost,
    /// Its error in the table's quantity.
    pub error: f64,
}

/// The configurations of `entries` that reach `target`, each at its
/// cheapest level (by median) with error at or below it, ranked:
/// `(index into entries, tier of [`tiers`])`, by tier, then median, then label.
pub fn ranking(entries: &[Entry], target: f64) -> Vec<(usize, usize)> {
    let mut best: Vec<usize> = Vec::new();
    for (i, e) in entries.iter().enumerate().filter(|(_, e)| e.error <= target) {
        match best.iter_mut().find(|b| entries[**b].label == e.label) {
            Some(b) if e.cost.median < entries[*b].cost.median => *b = i,
            Some(_) => {}
            None => best.push(i),
        }
    }
    let t = tiers(&best.iter().map(|&i| entries[i].cost).collect::<Vec<_>>());
    let mut r: Vec<(usize, usize)> = best.into_iter().zip(t).collect();
    r.sort_by(|a, b| a.1.cmp(&b.1).then(entries[a.0].cost.median.total_cmp(&entries[b.0].cost.median)).then(entries[a.0].label.cmp(&entries[b.0].label)));
    r
}

/// At most this many configurations are named in one cell of a table.
const MAX_NAMED: usize = 4;

/// `1.31e-6 [1.20e-6, 1.52e-6]`; a single run without its range.
pub fn cost_text(c: &Cost) -> String {
    if c.n > 1 {
        format!("{:.2e} [{:.2e}, {:.2e}]", c.median, c.min, c.max)
    } else {
        format!("{:.2e}", c.median)
    }
}

/// The table of the cheapest configurations per target error, as the
/// study's report and the user guide give it: per target the cheapest tier
/// (`tie: A / B` when several) and the next one, with their costs (median
/// [min, max]) and errors; then where each cheapest configuration named
/// in it holds.
/// `flag(label)` is appended to a configuration's name (the non-convergence
/// mark).
pub fn cheapest_table(benchmark: &str, entries: &[Entry], targets: &[f64], flag: &dyn Fn(&str) -> String) -> String {
    let mut s = String::from("| target error | cheapest (ties: ranges overlap) | wall (s): median [min, max] | error | next | wall (s): median [min, max] |\n|---|---|---|---|---|---|\n");
    let mut winners: Vec<&str> = Vec::new();
    let group = |idx: &[usize]| -> [String; 3] {
        if idx.is_empty() {
            return ["-".into(), "-".into(), "-".into()];
        }
        let shown = &idx[..idx.len().min(MAX_NAMED)];
        let more = if idx.len() > MAX_NAMED { format!(" / … (+{} tied)", idx.len() - MAX_NAMED) } else { String::new() };
        let join = |f: &dyn Fn(&Entry) -> String| shown.iter().map(|&i| f(&entries[i])).collect::<Vec<_>>().join(" / ");
        let tie = if idx.len() > 1 { "tie: " } else { "" };
        [format!("{tie}{}{more}", join(&|e| format!("{} {}{}", e.label, e.at, flag(&e.label)))), join(&|e| cost_text(&e.cost)), join(&|e| format!("{:.2e}", e.error))]
    };
    for &target in targets {
        let r = ranking(entries, target);
        if r.is_empty() {
            s.push_str(&format!("| {target:.0e} | not reached at these levels | | | | |\n"));
            continue;
        }
        let tier = |t: usize| r.iter().filter(|x| x.1 == t).map(|x| x.0).collect::<Vec<_>>();
        let (first, next) = (tier(0), tier(1));
        // The named ones (a cell lists at most MAX_NAMED).
        for &i in first.iter().take(MAX_NAMED) {
            if !winners.contains(&entries[i].label.as_str()) {
                winners.push(&entries[i].label);
            }
        }
        let ([a, b, c], [d, e, _]) = (group(&first), group(&next));
        s.push_str(&format!("| {target:.0e} | {a} | {b} | {c} | {d} | {e} |\n"));
    }
    // Where each cheapest configuration holds, those sharing a reason together.
    let mut reasons: Vec<(String, Vec<&str>)> = Vec::new();
    for w in winners {
        let why = condition(benchmark, w);
        match reasons.iter_mut().find(|r| r.0 == why) {
            Some(r) => r.1.push(w),
            None => reasons.push((why, vec![w])),
        }
    }
    if !reasons.is_empty() {
        s.push_str("\nWhere the cheapest hold: ");
        let parts: Vec<String> = reasons.iter().map(|(why, who)| format!("{}: {why}", who.iter().map(|w| format!("`{w}`")).collect::<Vec<_>>().join(", "))).collect();
        s.push_str(&parts.join(". "));
        s.push_str(".\n");
    }
    s
}

/// Under which conditions the ranking of configuration `label` on
/// `benchmark` holds: what of the benchmark it rests on, and what it does
/// not carry to.
pub fn condition(benchmark: &str, label: &str) -> String {
    let mut words = label.split(' ');
    let (scheme, mass) = (words.next().unwrap_or(""), words.next().unwrap_or(""));
    let rest: Vec<&str> = words.collect();
    let reduced = rest.iter().find_map(|w| w.strip_prefix("r="));
    let degree = rest.iter().find_map(|w| w.strip_prefix('P'));
    if benchmark.starts_with("beam") {
        return match reduced {
            Some(_) => "a massless-tip reduced model: dropping the tip's mass is a model error no step removes, so its error has a floor; measured on the tip over the error window only".into(),
            None => "measured on the tip over the error window only: past the first impacts the beam's trajectory does not converge in dt (it is chaotic, `cargo xtask lyapunov`), so no pointwise ranking holds beyond it".into(),
        };
    }
    if reduced.is_some() {
        return "a reduced model: its error stops at the truncation error of its r modes (a bar hitting a stop has a square-wave velocity), so it ranks only at coarse targets, and finer ones need more modes".into();
    }
    if scheme == "cd-taylor" && mass == "lumped" && degree.is_none() {
        let what = if benchmark == "bar-dirichlet" { "its error is round-off" } else { "its error is the interpolation of exact nodal values" };
        return format!(
            "Courant number one — exact at the nodes ({what}) because dx/dt = c on a uniform mesh makes each step d'Alembert's rule, with the stop at a node, restitution 0 and the releases on time levels; does not carry to other meshes, loads or obstacles (a release between time levels, g = 0.11: first order; `cargo xtask courant1`)"
        );
    }
    if let Some(k) = degree {
        return format!("P{k} elements: they pay where the solution is smooth between impacts; the impact's kink sets the rate otherwise");
    }
    let explicit = scheme.parse::<SchemeSpec>().map(|s| s.is_explicit()).unwrap_or(false);
    if explicit {
        return "an explicit scheme at dx/dt = 10, below its CFL limit: a measured ranking on this benchmark, no exactness property behind it; its step limit shrinks with the smallest element".into();
    }
    "a measured ranking on this benchmark at these levels, no exactness property behind it".into()
}

/// At most this many configurations are drawn besides the frontier.
#[doc(hidden)]
pub const MAX_CURVES: usize = 6;

/// The curves of a work–precision chart: the frontier (the cheapest entry
/// per error level, as a staircase: the least error reached within each
/// cost, run on to the largest cost drawn) and the configurations the table
/// names, at most [`MAX_CURVES`], in this order of priority: the cheapest
/// (by median) at each target, the configurations owning frontier points,
/// the cheapest of the next tier at each target, then the rest of the
/// first tiers and of the next; and how many configurations are drawn.
#[doc(hidden)]
pub fn wp_series(entries: &[Entry], targets: &[f64]) -> (Vec<Series>, usize) {
    let mut chosen: Vec<&str> = Vec::new();
    fn add<'e>(l: &'e str, chosen: &mut Vec<&'e str>) {
        if chosen.len() < MAX_CURVES && !chosen.contains(&l) {
            chosen.push(l);
        }
    }
    let ranked: Vec<Vec<(usize, usize)>> = targets.iter().map(|&t| ranking(entries, t)).collect();
    // A ranking is sorted by tier, then median: a tier's first is its cheapest.
    let first_of = |tier: usize| ranked.iter().filter_map(move |r| r.iter().find(|x| x.1 == tier).map(|x| x.0));
    for i in first_of(0) {
        add(&entries[i].label, &mut chosen);
    }
    let pts: Vec<(f64, f64)> = entries.iter().map(|e| (e.cost.median, e.error)).collect();
    let front = frontier(&pts);
    for &i in &front {
        add(&entries[i].label, &mut chosen);
    }
    for i in first_of(1) {
        add(&entries[i].label, &mut chosen);
    }
    for tier in [0, 1] {
        for r in &ranked {
            for &(i, _) in r.iter().filter(|x| x.1 == tier) {
                add(&entries[i].label, &mut chosen);
            }
        }
    }
    let mut series = Vec::new();
    let x_end =
        entries.iter().filter(|e| chosen.contains(&e.label.as_str()) || front.iter().any(|&i| entries[i].label == e.label)).map(|e| e.cost.median).filter(|c| c.is_finite()).fold(0.0_f64, f64::max);
    let mut stair = Vec::new();
    for (k, &i) in front.iter().enumerate() {
        let (c, e) = pts[i];
        if k > 0 {
            stair.push((c, stair.last().map_or(e, |p: &(f64, f64)| p.1)));
        }
        stair.push((c, e));
    }
    if let Some(&(c, e)) = stair.last() {
        if x_end > c {
            stair.push((x_end, e));
        }
    }
    series.push(Series { label: "frontier: the cheapest per error level".into(), points: stair, reference: false, style: Style { group: Some(6), variant: None } });
    // Colours skip black (the frontier's).
    for (k, l) in chosen.iter().enumerate() {
        let points = entries.iter().filter(|e| e.label == *l).map(|e| (e.cost.median, e.error)).collect();
        series.push(Series { label: (*l).to_string(), points, reference: false, style: Style { group: Some(if k >= 6 { k + 1 } else { k }), variant: Some(k) } });
    }
    (series, chosen.len())
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

/// A stepper ready to run and its initial displacement.
type Built = (Box<dyn Stepper>, Vec<f64>);
/// The same and the beam's unknowns.
type BuiltBeam = (Box<dyn Stepper>, Vec<f64>, usize);

/// Wall times `(set-up, stepping)` of one run of the stepper that `build`
/// makes (the set-up is `build` itself), no observers.
fn one_run(build: &dyn Fn() -> Result<Built, StudyError>, dt: f64, t_end: f64) -> Result<(f64, f64), StudyError> {
    let start = std::time::Instant::now();
    let (mut s, u0) = build()?;
    let setup = start.elapsed().as_secs_f64();
    let start = std::time::Instant::now();
    run_steps(s.as_mut(), &u0, &RunConfig::new(dt, t_end)?, &mut [])?;
    Ok((setup, start.elapsed().as_secs_f64()))
}

fn run_err(e: impl std::error::Error + Send + Sync + 'static) -> StudyError {
    StudyError::failed("", e)
}

/// How to time one run of a row: the set-up of `signorini run` on the
/// row's scene (the problem — matrices, exact initial data —, the
/// reduction if any, the scheme with its CFL check and factorisations),
/// then the stepping without observers. The rows are timed after every
/// error is computed, in `--repeats` rounds over all of them, one run at a
/// time.
#[derive(Clone, Copy)]
enum Timed {
    /// A bar level (degree `k`, the reduction `keep` when given, dt = h/ratio).
    Bar { b: Benchmark, scheme: SchemeSpec, mass: BarMass, m: usize, k: usize, ratio: f64, t_end: f64, keep: Option<Keep> },
    /// The Courant-one row at level `m`.
    Courant1 { b: Benchmark, m: usize },
    /// A beam row (`modes` 0: the full model).
    Beam { dt: f64, t_end: f64, modes: usize },
}

impl Timed {
    /// Wall times `(set-up, stepping)` of one run.
    fn sample(&self) -> Result<(f64, f64), StudyError> {
        match *self {
            Timed::Bar { b, scheme, mass, m, k, ratio, t_end, keep } => {
                let exact = b.exact(t_end)?;
                let dt = b.problem_with_degree(exact.as_ref(), m, mass, k)?.bar.h() / ratio;
                let build = || -> Result<Built, StudyError> {
                    let p = b.problem_with_degree(exact.as_ref(), m, mass, k)?;
                    match keep {
                        None => Ok((scheme.build(p.dynamics(), dt, &p.initial).map_err(run_err)?, p.initial.u.clone())),
                        Some(keep) => {
                            let red = signorini_run::reduced::reduce(&p.dynamics(), &p.initial, keep)?;
                            Ok((scheme.build(red.dynamics.clone(), dt, &red.initial).map_err(run_err)?, red.initial.u.clone()))
                        }
                    }
                };
                one_run(&build, dt, t_end)
            }
            Timed::Courant1 { b, m } => {
                let (_, t_end) = b.default_ratio_and_horizon();
                let exact = b.exact(t_end)?;
                let p = b.problem(exact.as_ref(), m, BarMass::Lumped)?;
                let dt = p.bar.h() / p.bar.wave_speed;
                let build = || -> Result<Built, StudyError> {
                    let p = b.problem(exact.as_ref(), m, BarMass::Lumped)?;
                    Ok((SchemeSpec::cd_taylor().build(p.dynamics(), dt, &p.initial).map_err(RunError::from)?, p.initial.u.clone()))
                };
                one_run(&build, dt, t_end)
            }
            Timed::Beam { dt, t_end, modes } => one_run(
                &|| {
                    let (s, u0, _) = beam_build(dt, t_end, modes)?;
                    Ok((s, u0))
                },
                dt,
                t_end,
            ),
        }
    }
}

/// Times every row that has a [`Timed`] in `repeats` rounds over all of
/// them (one run at a time), then sets its cost (median and range of the
/// stepping) and its set-up (median); `tick` after each round.
fn time_rows(points: &mut [Point], repeats: usize, tick: &mut dyn FnMut()) -> Result<(), StudyError> {
    let mut samples: Vec<(Vec<f64>, Vec<f64>)> = points.iter().map(|_| (Vec::with_capacity(repeats), Vec::with_capacity(repeats))).collect();
    for _ in 0..repeats {
        for (p, s) in points.iter().zip(samples.iter_mut()) {
            if let Some(t) = &p.timing {
                let (setup, step) = t.sample()?;
                s.0.push(setup);
                s.1.push(step);
            }
        }
        tick();
    }
    for (p, (setup, step)) in points.iter_mut().zip(samples) {
        if p.timing.is_some() {
            let what = format!("{} {} {}: no finite timing", p.benchmark, p.label(), p.at());
            let (Some(cost), Some(setup)) = (Cost::of(&step), Cost::of(&setup)) else { return Err(StudyError::Run(what)) };
            p.cost = cost;
            p.setup = setup.median;
        }
    }
    Ok(())
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
    let mut s = SchemeSpec::cd_taylor().build(p.dynamics(), dt, &p.initial).map_err(RunError::from)?;
    let mut norms = NormObserver::new(exact.as_ref(), p.bar.elements, p.vnorm(), dt);
    let sum = run_steps(s.as_mut(), &p.initial.u, &RunConfig::new(dt, t_end)?, &mut [&mut norms])?;
    let r = norms.report();
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
        cost: Cost::UNTIMED,
        setup: f64::NAN,
        timing: Some(Timed::Courant1 { b, m }),
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
    beam_build_with(dt, t_end, modes, SchemeSpec::ps(0.0, 0.5))
}

/// [`beam_build`] with another scheme.
fn beam_build_with(dt: f64, t_end: f64, modes: usize, scheme: SchemeSpec) -> Result<BuiltBeam, StudyError> {
    let scene = BeamScene { dt, t_end, scheme, ..BeamScene::PAPER[0] };
    let setup = BeamSetup::new(Pipe::paper(), scene);
    if modes == 0 {
        let b = setup.build()?;
        Ok((b.stepper, b.initial.u, b.beam.tip_dof()))
    } else {
        let b = setup.reduced(Keep::Modes(modes)).build()?;
        let u0 = b.reduced.map(|r| r.initial.u).unwrap_or_default();
        Ok((b.stepper, u0, 0))
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
    let (mut s, u0, dof) = beam_build_with(dt, t_end, 0, spec)?;
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
                cost: Cost::UNTIMED,
                setup: f64::NAN,
                timing: Some(Timed::Beam { dt, t_end: te, modes }),
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
    // Everything is checked before a file is created.
    a.validate()?;
    let schemes: Vec<SchemeSpec> = crate::time_stepping_schemes("schemes", a.schemes.as_deref())?.into_iter().map(|(_, s)| s).collect();
    let start = std::time::Instant::now();
    create_dir(&a.out)?;
    let frontier = 2 * (1 + a.degrees.len() + a.modes.len()) as u64 + u64::from(!a.beam_dts.is_empty()) + u64::from(!a.beam_stat_dts.is_empty());
    let total = 2 * schemes.len() as u64 + frontier + a.repeats as u64;
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
    let full = |b: Benchmark, scheme: SchemeSpec, mass: BarMass, l: &study::LevelResult, k: usize, modes: usize, ratio: f64, t_end: f64| Point {
        benchmark: b.to_string(),
        scheme: scheme.to_string(),
        mass: mass.to_string(),
        m: l.m,
        dt: l.dt,
        steps: l.steps,
        norms: Some(l.norms),
        release_err: Some(release_error(l.first_release, release_of(b))),
        cost: Cost::UNTIMED,
        setup: f64::NAN,
        timing: Some(Timed::Bar { b, scheme, mass, m: l.m, k, ratio, t_end, keep: (modes > 0).then_some(Keep::Modes(modes)) }),
        degree: k,
        modes,
        beam: None,
        power: None,
    };
    for benchmark in BARS {
        let (ratio, t_end) = benchmark.default_ratio_and_horizon();
        for scheme in &schemes {
            let ok: Vec<BarMass> = masses.iter().copied().filter(|&m| crate::takes_mass(scheme, m)).collect();
            // Explicit schemes cannot take dt = h (their CFL limit is below it):
            // they run at dx/dt = 10 on every benchmark.
            let ratio = if scheme.is_explicit() { ratio.max(10.0) } else { ratio };
            let cfg = StudyConfig::new(benchmark, vec![*scheme], ok, a.levels.clone(), ratio, t_end);
            for r in study::sweep(&cfg, &|| {})? {
                for l in &r.levels {
                    points.push(full(benchmark, r.scheme, r.mass, l, 1, 0, ratio, t_end));
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
                    points.push(full(benchmark, r.scheme, r.mass, l, k, 0, ratio, t_end));
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
                let (_, l) = run?;
                points.push(full(benchmark, cn, BarMass::Mod, &l, 1, r, ratio, t_end));
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
            // The whole run, timed once (`wall_s`, `step_s`): no set-up apart.
            cost: Cost::once(wall),
            setup: f64::NAN,
            timing: None,
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
    // Every error is known: the timing rounds, one run at a time.
    time_rows(&mut points, a.repeats, &mut tick)?;
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
            ("step_s_min", f_),
            ("step_s_max", f_),
            ("repeats", i_),
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
            fe(p.cost.median, 6),
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
            fe(p.cost.median, 6),
            fe(p.cost.min, 6),
            fe(p.cost.max, 6),
            int(p.cost.n),
        ])?;
    }
    let table = w.finish()?;
    let mut report = String::from("# Work–precision (error against stepping wall time)\n\n");
    writeln!(
        report,
        "Timings on this machine: the stepping's wall time, the median of {} runs taken in {} rounds over every configuration, with its range [min, max]. Two configurations whose ranges overlap are a tie and are printed together (`tie: … / …`, by median). The errors are deterministic; the costs, the order of tied configurations and the plots' x axis are not (µs to s on a shared machine). A ranking is that of these benchmarks: the conditions under which each cheapest configuration holds follow each table.\n",
        a.repeats, a.repeats
    )
    .expect("writing to a String");
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
            let entries: Vec<Entry> = pts.iter().map(|p| p.entry(q)).collect();
            let targets: &[f64] = if is_beam { &BEAM_TARGETS } else { q.targets() };
            let what = if is_beam { format!("{benchmark}: tip error") } else { format!("{benchmark}: {} error", q.name()) };
            let (series, drawn) = wp_series(&entries, targets);
            let title = format!("{what} against wall time: the frontier and {drawn} of {} configurations", keys.len());
            let svg = line_chart(&Chart { title: &title, x_label: "wall time of the stepping, median (s)", y_label: &y_label, scale: Scale::LogLog, size: (1000, 650) }, &series)
                .map_err(StudyError::Plot)?;
            crate::write_file(&a.out.join(&file), &svg)?;
            if !is_beam {
                writeln!(report, "### {} (column `{}`)\n", q.name(), q.column()).expect("writing to a String");
            }
            report.push_str(&cheapest_table(benchmark, &entries, targets, &flagged));
            writeln!(report, "\n`{file}`: the frontier (the cheapest configuration per error level) and the {drawn} configurations named above; all {} are in `work_precision.csv`.\n", keys.len())
                .expect("writing to a String");
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
            // and the cheapest reduced model at least as accurate (nothing
            // said when no reduced model was run).
            let paper_dt = BeamScene::PAPER[0].dt;
            let q = Quantity::U;
            let any_reduced = pts.iter().any(|p| p.modes > 0);
            if let Some(today) = pts.iter().find(|p| p.modes == 0 && (p.dt - paper_dt).abs() < 1e-12) {
                let reduced = pts.iter().filter(|p| p.modes > 0 && p.error(q) <= today.error(q)).min_by(|a, b| a.cost.median.total_cmp(&b.cost.median));
                write!(report, "The full model at the paper's dt = {paper_dt:e} s: tip error {:.2e} m, {} s.", today.error(q), cost_text(&today.cost)).expect("writing to a String");
                match reduced {
                    Some(r) if r.cost.ties(&today.cost) => {
                        write!(report, " Cheapest reduced model at least as accurate: {} dt={:e}, {:.2e} m, {} s: a tie in cost (the ranges overlap).", r.label(), r.dt, r.error(q), cost_text(&r.cost))
                    }
                    Some(r) => write!(
                        report,
                        " Cheapest reduced model at least as accurate: {} dt={:e}, {:.2e} m, {} s ({:.1}x {} wall time, medians).",
                        r.label(),
                        r.dt,
                        r.error(q),
                        cost_text(&r.cost),
                        if r.cost.median <= today.cost.median { today.cost.median / r.cost.median } else { r.cost.median / today.cost.median },
                        if r.cost.median <= today.cost.median { "less" } else { "more" }
                    ),
                    None if any_reduced => write!(
                        report,
                        " No reduced model reaches that error at these steps and modes (best: {}).",
                        pts.iter().filter(|p| p.modes > 0).min_by(|a, b| a.error(q).total_cmp(&b.error(q))).map_or(String::new(), |p| format!("{} dt={:e}, {:.2e} m", p.label(), p.dt, p.error(q)))
                    ),
                    None => Ok(()),
                }
                .expect("writing to a String");
                report.push('\n');
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
        ref_p.cost.median
    )
    .expect("writing to a String");
    for (p, i, r) in &rows {
        writeln!(report, "| {:e} | {:.4} [{:.4}, {:.4}] | {:.1} % | {:+.2} % | {:.2} |", p.dt, i.mean, i.low, i.high, 100.0 * half(i), 100.0 * r, p.cost.median).expect("writing to a String");
    }
    let ok = rows
        .iter()
        .filter(|(p, i, r)| p.dt != a.beam_stat_ref_dt && r.abs() <= 0.01 && half(i) <= 0.01 && half(&ref_i) <= 0.01 && p.cost.median * 10.0 <= ref_p.cost.median)
        .min_by(|x, y| x.0.cost.median.total_cmp(&y.0.cost.median));
    match ok {
        Some((p, _, r)) => writeln!(report, "\nTarget reached: dt = {:e} s is within {:.2} % of the reference with both intervals within ±1 %, {:.1}x cheaper (single runs).\n", p.dt, 100.0 * r.abs(), ref_p.cost.median / p.cost.median),
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
