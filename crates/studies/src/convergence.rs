//! The convergence study (`cargo xtask convergence`): sweep dx at a fixed
//! dx/dt for each (scheme, mass) pair; one CSV error curve per pair
//! (`<scheme>_<mass>.csv`, columns [`LEVEL_COLUMNS`]: `wall_s` the whole
//! run, then `setup_s` and `step_s` its set-up and its time loop), `rates.csv`
//! (`scheme,mass,norm,lsq_rate,last_rate`: least-squares and last-two
//! slopes of `log e` against `log dx`), `oscillation.csv`
//! (`scheme,mass,m,lambda_tv_ratio`), log-log plots `plot_<norm>.svg`, and
//! the rates as a Markdown table. Defaults: the papers' study.

use crate::{fe, ff, fits_memory, int, parse_schemes, prepare_dir, since, txt, Kind, StudyError, Table, TableOut};
use signorini_fem::BarMass;
use signorini_norms::NormKind;
use signorini_plot::{line_chart, stack_vertically, Chart, Scale, Series, Style};
use signorini_reduce::Keep;
use signorini_run::study::{self, ConfigResult, StudyConfig, LEVEL_COLUMNS, NORMS};
use signorini_run::Benchmark;
use signorini_schemes::SchemeSpec;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The default scheme list of `--schemes`.
pub const DEFAULT_SCHEMES: &str = "newmark-cn,newmark-i,newmark-ii,backward-euler,ps-e0,ps-e0.5,ps-e1";

crate::options::study_config! {
    /// The convergence study: for each (scheme, mass), the benchmark at each
    /// level m (m elements; bar-mirrored 2m on its [0, 2]) with dt = dx/⟨ratio⟩
    /// up to ⟨t_end⟩, and every error norm. An output folder holding CSV or SVG
    /// files this study would not write (another study's or configuration's) is
    /// refused unless ⟨clean⟩ removes them.
    study "convergence";
    pub struct Config {
        /// Benchmark with an exact solution (bar-dirichlet,
        /// bar-neumann-gravity, bar-neumann-gravity-0.11, bar-mirrored:
        /// level m is m elements on [0, 1], 2m on its [0, 2]).
        #[serde(deserialize_with = "de_benchmark")]
        pub benchmark: Benchmark = Benchmark::BarDirichlet,
        /// Schemes, comma-separated: presets or newmark(B,G), theta(T),
        /// ps(E) or ps(E,B) (commas inside parentheses do not split).
        #[serde(deserialize_with = "crate::options::with::schemes")]
        pub schemes: Vec<SchemeSpec> = parse_schemes(&[DEFAULT_SCHEMES.to_string()]).expect("the default schemes parse"),
        /// Mass treatments, comma-separated (std, lumped, mod, mod1, mod2,
        /// mod3, transfer, singular).
        #[serde(deserialize_with = "crate::options::with::masses")]
        pub masses: Vec<BarMass> = vec![BarMass::Std, BarMass::Mod],
        /// Numbers of elements m, comma-separated.
        pub levels: Vec<usize> = vec![10, 20, 40, 80, 160, 320, 640],
        /// dx/dt (default: the benchmark's, 10 for bar-dirichlet).
        pub ratio: Option<f64> = None,
        /// Horizon T (default: the benchmark's, 3 for bar-dirichlet).
        pub t_end: Option<f64> = None,
        /// Error measure: exact (kink-split, docs/theory.md §6.1) or getfem
        /// (errors of the nodal interpolant, relative to the reference's
        /// norms, as GetFEM's 1D dynamic-contact demo computes them).
        #[serde(deserialize_with = "de_norms")]
        pub norms: NormKind = NormKind::Exact,
        /// Output folder (default `out/convergence/<benchmark>`, or
        /// `out/convergence/<benchmark>-getfem-norms` with the GetFEM norms).
        pub out: Option<PathBuf> = None,
        /// Remove the CSV and SVG files of another study or configuration
        /// from the output folder first (without it such a folder is
        /// refused).
        pub clean: bool = false,
        /// A reduced model at every level (docs/theory.md §2.5): modes=R
        /// keeps the R lowest fixed-interface modes, cutoff_hz=F every mode
        /// up to F Hz (needs a massless-contact mass and a scheme that takes
        /// one). Default: none, the full model.
        #[serde(deserialize_with = "de_reduce")]
        pub reduce: Option<Keep> = None,
        /// Element degree k (1, 2, 3: Lagrange P1, P2, P3); level m is m
        /// elements of degree k (default folder
        /// `out/convergence/<benchmark>-p<k>` for k > 1); the files of degree
        /// 1 are those of P1, byte for byte.
        pub degree: usize = 1,
        /// What the errors are measured against: exact (the benchmark's
        /// closed form) or event-driven (the exact semi-discrete solution on
        /// the same mesh: the time error alone, with the space error beside
        /// it; every mass, massless contact nodes
        /// against event-driven(0); with ⟨reduce⟩, the reduced model's;
        /// default folder `out/convergence/<benchmark>-event-driven[-reduce-…]`).
        #[serde(deserialize_with = "de_reference")]
        pub reference: Reference = Reference::Exact,
    }
}

fn de_benchmark<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Benchmark, D::Error> {
    crate::options::with::text(d, parse_benchmark)
}
fn de_norms<'de, D: serde::Deserializer<'de>>(d: D) -> Result<NormKind, D::Error> {
    crate::options::with::text(d, parse_norms)
}
fn de_reduce<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<Keep>, D::Error> {
    crate::options::with::text(d, parse_reduce).map(Some)
}
fn de_reference<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Reference, D::Error> {
    crate::options::with::text(d, parse_reference)
}

impl crate::options::FieldType for Benchmark {
    const KIND: crate::options::Kind = crate::options::Kind::Text;
    fn show(&self) -> Option<String> {
        Some(self.name().to_string())
    }
}
impl crate::options::FieldType for NormKind {
    const KIND: crate::options::Kind = crate::options::Kind::Text;
    fn show(&self) -> Option<String> {
        Some(if *self == NormKind::Exact { "exact" } else { "getfem" }.to_string())
    }
}
impl crate::options::FieldType for Keep {
    const KIND: crate::options::Kind = crate::options::Kind::Text;
    fn show(&self) -> Option<String> {
        Some(match self {
            Keep::Modes(r) => format!("modes={r}"),
            Keep::CutoffHz(f) => format!("cutoff_hz={f}"),
        })
    }
}
impl crate::options::FieldType for Reference {
    const KIND: crate::options::Kind = crate::options::Kind::Text;
    fn show(&self) -> Option<String> {
        Some(if *self == Reference::Exact { "exact" } else { "event-driven" }.to_string())
    }
}

/// What the convergence study measures errors against.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Reference {
    /// The benchmark's closed form (space and time error together).
    #[default]
    Exact,
    /// `event-driven(e)` on the same mesh: the time error ([`crate::time_error`]).
    EventDriven,
}

/// Parses `--reference`.
pub fn parse_reference(s: &str) -> Result<Reference, StudyError> {
    match s {
        "exact" => Ok(Reference::Exact),
        "event-driven" => Ok(Reference::EventDriven),
        _ => Err(StudyError::config("reference", format!("⟨reference⟩ {s:?}: allowed exact, event-driven"))),
    }
}

/// Parses `--benchmark`.
pub fn parse_benchmark(s: &str) -> Result<Benchmark, StudyError> {
    s.parse().map_err(|e| StudyError::config("benchmark", format!("⟨benchmark⟩: {e}")))
}

/// Parses `--reduce`: `modes=R` (R >= 1) or `cutoff_hz=F` (F > 0).
pub fn parse_reduce(s: &str) -> Result<Keep, StudyError> {
    let bad = || StudyError::config("reduce", format!("⟨reduce⟩ {s:?}: allowed modes=R (an integer >= 1) or cutoff_hz=F (a frequency > 0)"));
    match s.split_once('=') {
        Some(("modes", r)) => r.trim().parse::<usize>().ok().filter(|r| *r >= 1).map(Keep::Modes).ok_or_else(bad),
        Some(("cutoff_hz", f)) => f.trim().parse::<f64>().ok().filter(|f| f.is_finite() && *f > 0.0).map(Keep::CutoffHz).ok_or_else(bad),
        _ => Err(bad()),
    }
}

/// Parses `--norms`: `exact` or `getfem`.
pub fn parse_norms(s: &str) -> Result<NormKind, StudyError> {
    match s {
        "exact" => Ok(NormKind::Exact),
        "getfem" => Ok(NormKind::GetfemInterpolated),
        other => Err(StudyError::config("norms", format!("⟨norms⟩ {other:?}: allowed exact or getfem"))),
    }
}

/// Maps a sweep-validation error to the option it names.
fn study_error(e: signorini_run::RunError) -> StudyError {
    let field = match &e {
        signorini_run::RunError::Invalid { field: "ratio", .. } => "ratio",
        signorini_run::RunError::Invalid { field: "levels" | "levels/schemes/masses", .. } => "levels",
        signorini_run::RunError::Invalid { field: "T" | "dt" | "T/dt", .. } => "t_end",
        signorini_run::RunError::Scheme(_) => "schemes",
        signorini_run::RunError::Invalid { field: "degree", .. } => "degree",
        signorini_run::RunError::Fem(signorini_fem::FemError::MassForDegree { .. }) => "masses",
        _ => "levels",
    };
    // The message starts with the option, as every Config error's does.
    let message = match &e {
        signorini_run::RunError::Invalid { value, allowed, .. } => format!("{} {}: allowed {allowed}", crate::options::at(field), signorini_run::text::num(*value)),
        _ => format!("{}: {e}", crate::options::at(field)),
    };
    StudyError::config(field, message)
}

impl Config {
    /// The sweep this configuration runs: the benchmark's dx/dt and horizon
    /// where none is given, and on bar-mirrored only the schemes that take
    /// its two stops (the others are listed in the returned notes); the
    /// output folder. Every check is done here, before anything is run.
    pub fn resolve(&self) -> Result<(StudyConfig, PathBuf, Vec<String>), StudyError> {
        let (ratio0, t0) = self.benchmark.default_ratio_and_horizon();
        let mut cfg = StudyConfig::new(self.benchmark, self.schemes.clone(), self.masses.clone(), self.levels.clone(), self.ratio.unwrap_or(ratio0), self.t_end.unwrap_or(t0))
            .with_norms(self.norms)
            .with_degree(self.degree);
        cfg.validate().map_err(study_error)?;
        if let Some(keep) = self.reduce {
            if let Some(m) = cfg.masses.iter().find(|m| !m.massless_contact_node()) {
                return Err(StudyError::config(
                    "masses",
                    format!(
                        "⟨masses⟩ {m} with ⟨reduce⟩: the reduction keeps the contacts massless, exact for a parent without mass at its contacts; allowed mod, mod1, mod2, mod3, transfer, singular"
                    ),
                ));
            }
            if let Some(s) = cfg.schemes.iter().find(|s| !s.accepts_massless_node(true)) {
                return Err(StudyError::config("schemes", format!("⟨schemes⟩ {s} with ⟨reduce⟩: it needs a massive contact node, and a reduced model's contacts are massless")));
            }
            // Each level's reduction, built before anything runs.
            let exact = cfg.benchmark.exact(cfg.t_end).map_err(|e| StudyError::config("t_end", e.to_string()))?;
            for &m in &cfg.levels {
                for &mass in &cfg.masses {
                    let p = cfg.benchmark.problem_with_degree(exact.as_ref(), m, mass, self.degree).map_err(|e| StudyError::config("masses", format!("⟨masses⟩ {mass}: {e}")))?;
                    signorini_run::reduced::reduce(&p.dynamics(), &p.initial, keep).map_err(|e| StudyError::config("reduce", format!("⟨reduce⟩ at m = {m}: {e}")))?;
                }
            }
        }
        let mut notes = Vec::new();
        if self.benchmark == Benchmark::BarMirrored {
            cfg.schemes = several_contact_schemes(&cfg, &mut notes)?;
        }
        // The sweep runs as many levels at once as there are cores.
        fits_memory("levels", cfg.levels.iter().copied().max().unwrap_or(0).saturating_mul(cfg.degree), std::thread::available_parallelism().map_or(1, |n| n.get()))?;
        let mut folder = if self.norms == NormKind::Exact { self.benchmark.name().to_string() } else { format!("{}-getfem-norms", self.benchmark.name()) };
        if self.degree > 1 {
            folder = format!("{folder}-p{}", self.degree);
        }
        if self.reference == Reference::EventDriven {
            if self.norms != NormKind::Exact {
                return Err(StudyError::config("reference", "⟨reference⟩ event-driven: the exact norms only (no ⟨norms⟩ getfem)"));
            }
            folder += "-event-driven";
        }
        match self.reduce {
            None => {}
            Some(Keep::Modes(r)) => folder += &format!("-reduce-modes-{r}"),
            Some(Keep::CutoffHz(f)) => folder += &format!("-reduce-cutoff-{f}hz"),
        }
        let out = self.out.clone().unwrap_or_else(|| PathBuf::from("out/convergence").join(folder));
        Ok((cfg, out, notes))
    }

    /// Every check `cargo xtask convergence` does before it runs; an error names the option.
    pub fn validate(&self) -> Result<(), StudyError> {
        self.resolve().map(|_| ())
    }
}

/// What the study computed and wrote.
#[derive(Clone, Debug)]
pub struct Output {
    /// The sweep that ran (on bar-mirrored, only the schemes that take two stops).
    pub config: StudyConfig,
    /// The output folder.
    pub out: PathBuf,
    /// Per (scheme, mass), the levels' norms.
    pub results: Vec<ConfigResult>,
    /// One table per CSV written: `<scheme>_<mass>.csv` in result order, `rates.csv`, `oscillation.csv`.
    pub tables: Vec<Table>,
    /// The Markdown report `cargo xtask convergence` prints.
    pub report: String,
    /// Wall time of the sweep (s).
    pub wall_s: f64,
    /// Notes and warnings for stderr (schemes skipped, plots skipped).
    pub notes: Vec<String>,
}

/// Runs the study (see the module documentation).
pub fn run(cfg: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    let (study_cfg, out, mut notes) = cfg.resolve()?;
    if cfg.reference == Reference::EventDriven {
        let start = std::time::Instant::now();
        crate::prepare_dir(&out, &["time_error.csv".to_string(), "space_error.csv".to_string()], cfg.clean)?;
        let (tables, mut report) = crate::time_error::run(&study_cfg, cfg.reduce, &out, progress)?;
        let wall_s = crate::since(start);
        report.push_str(&format!("\nin {wall_s:.1} s\n"));
        return Ok(Output { config: study_cfg, out, results: Vec::new(), tables, report, wall_s, notes });
    }
    let (results, wall_s, tables) = sweep_into_reduced(&study_cfg, cfg.reduce, &out, "", cfg.clean, progress, &mut notes)?;
    let mut report = format!(
        "# Convergence: {}, dx/dt = {}, T = {}, m = {:?}, P{} elements{}{}\n\nLeast-squares rates of the error against dx (CSV: {}).\n\n",
        study_cfg.benchmark,
        study_cfg.ratio,
        study_cfg.t_end,
        study_cfg.levels,
        study_cfg.degree,
        if study_cfg.norms == NormKind::Exact { "" } else { " — GetFEM-demo norms: errors of the nodal interpolant, relative" },
        match cfg.reduce {
            None => String::new(),
            Some(Keep::Modes(r)) => format!(" — reduced model (docs/theory.md §2.5), {r} modes"),
            Some(Keep::CutoffHz(f)) => format!(" — reduced model (docs/theory.md §2.5), modes up to {f} Hz"),
        },
        out.display()
    );
    if study_cfg.degree > 1 {
        report.push_str(&format!("Lagrange P{} elements: level m is m elements of degree {} (k m + 1 nodes), dx = L/m.\n\n", study_cfg.degree, study_cfg.degree));
    }
    report.push_str(&study::markdown_table(&results));
    report.push_str(&format!("\n{} runs in {:.1} s\n", results.iter().map(|r| r.levels.len()).sum::<usize>(), wall_s));
    Ok(Output { config: study_cfg, out, results, tables, report, wall_s, notes })
}

/// The schemes of `cfg` that take several contacts (bar-mirrored has two
/// stops): each is built on the smallest level with each mass, and one that
/// refuses the structure (the reduced schemes, Nitsche) is left out with a
/// note. Nothing left is an error.
fn several_contact_schemes(cfg: &StudyConfig, notes: &mut Vec<String>) -> Result<Vec<SchemeSpec>, StudyError> {
    let exact = cfg.benchmark.exact(cfg.t_end).map_err(|e| StudyError::config("t_end", e.to_string()))?;
    let m = cfg.levels.iter().copied().min().unwrap_or(2);
    let mut keep = Vec::new();
    'schemes: for s in &cfg.schemes {
        for &mass in &cfg.masses {
            let p = cfg.benchmark.problem_with_degree(exact.as_ref(), m, mass, cfg.degree).map_err(|e| StudyError::config("masses", format!("⟨masses⟩ {mass}: {e}")))?;
            // The registry refuses a structure a family does not take with
            // `NotTaken` (naming the schemes that do); a builder's own check
            // with `Structure`.
            match s.build(p.dynamics(), p.bar.h() / cfg.ratio, &p.initial) {
                Err(signorini_schemes::SchemeError::Structure(why)) => {
                    notes.push(format!("note: {s} skipped on {}: {why}", cfg.benchmark));
                    continue 'schemes;
                }
                Err(e @ signorini_schemes::SchemeError::NotTaken { .. }) => {
                    notes.push(format!("note: {s} skipped on {}: {e}", cfg.benchmark));
                    continue 'schemes;
                }
                _ => {}
            }
        }
        keep.push(*s);
    }
    if keep.is_empty() {
        return Err(StudyError::config("schemes", format!("⟨schemes⟩: none of them takes the two stops of {}: use {}", cfg.benchmark, signorini_schemes::families_with(|c| c.several_contacts))));
    }
    Ok(keep)
}

/// Runs a sweep (progress after every run) and writes its CSVs and log-log
/// plots into `out`; the tables are named `prefix` + file name. Returns the
/// results, the sweep's wall time and the tables.
pub(crate) fn sweep_into(cfg: &StudyConfig, out: &Path, prefix: &str, progress: &(dyn Fn(u64, u64) + Sync), notes: &mut Vec<String>) -> Result<(Vec<ConfigResult>, f64, Vec<Table>), StudyError> {
    sweep_into_reduced(cfg, None, out, prefix, false, progress, notes)
}

/// [`sweep_into`] with every level reduced when `reduce` is given.
/// The folder may hold only files this sweep writes, unless `clean`.
fn sweep_into_reduced(
    cfg: &StudyConfig,
    reduce: Option<Keep>,
    out: &Path,
    prefix: &str,
    clean: bool,
    progress: &(dyn Fn(u64, u64) + Sync),
    notes: &mut Vec<String>,
) -> Result<(Vec<ConfigResult>, f64, Vec<Table>), StudyError> {
    prepare_dir(out, &output_files(cfg), clean)?;
    let total = (cfg.schemes.len() * cfg.masses.len() * cfg.levels.len()) as u64;
    let done = AtomicU64::new(0);
    let start = std::time::Instant::now();
    let results = study::sweep_reduced(cfg, reduce, &|| progress(done.fetch_add(1, Ordering::Relaxed) + 1, total))?;
    let wall = since(start);
    let mut tables = Vec::new();
    let level_kinds: Vec<(&str, Kind)> = LEVEL_COLUMNS.iter().map(|&c| (c, if c == "m" || c == "steps" { Kind::I } else { Kind::F })).collect();
    for r in &results {
        let mut t = TableOut::create_in(out, prefix, &r.file_name(), &level_kinds)?;
        for l in &r.levels {
            let mut row = vec![int(l.m), fe(l.dx, 10), fe(l.dt, 10), int(l.steps)];
            row.extend(NORMS.iter().map(|n| fe(study::norm_value(&l.norms, n), 10)));
            row.extend([ff(l.wall_s, 6), ff(l.setup_s, 6), ff(l.step_s, 6)]);
            t.row(row)?;
        }
        tables.push(t.finish()?);
    }
    let mut rates = TableOut::create_in(out, prefix, "rates.csv", &[("scheme", Kind::S), ("mass", Kind::S), ("norm", Kind::S), ("lsq_rate", Kind::F), ("last_rate", Kind::F)])?;
    for r in &results {
        for n in NORMS {
            let rt = r.rate(n);
            rates.row(vec![txt(r.scheme.to_string()), txt(r.mass.to_string()), txt(n), ff(rt.lsq, 4), ff(rt.last, 4)])?;
        }
    }
    tables.push(rates.finish()?);
    let mut osc = TableOut::create_in(out, prefix, "oscillation.csv", &[("scheme", Kind::S), ("mass", Kind::S), ("m", Kind::I), ("lambda_tv_ratio", Kind::F)])?;
    for r in &results {
        for l in &r.levels {
            osc.row(vec![txt(r.scheme.to_string()), txt(r.mass.to_string()), int(l.m), ff(l.norms.lambda_tv_ratio, 4)])?;
        }
    }
    tables.push(osc.finish()?);
    for norm in PLOTTED_NORMS {
        // One panel per mass, so that the schemes' curves stay apart (14
        // curves in one chart were unreadable); colour, marker and dash
        // pattern by scheme: the second-order schemes' curves with a
        // massless node lie on one another (the same errors to 2–3 digits),
        // and colour alone let the last one drawn hide the others.
        let panels: Result<Vec<String>, signorini_plot::PlotError> = cfg
            .masses
            .iter()
            .map(|&mass| {
                let series: Vec<Series> = results
                    .iter()
                    .filter(|r| r.mass == mass)
                    .map(|r| {
                        let k = cfg.schemes.iter().position(|s| *s == r.scheme);
                        let style = Style { group: k, variant: k };
                        Series { label: format!("{} {}", r.scheme, r.mass), points: r.levels.iter().map(|l| (l.dx, study::norm_value(&l.norms, norm))).collect(), reference: false, style }
                    })
                    .collect();
                let title = format!("{}, mass {mass}: {} against dx (dx/dt = {})", cfg.benchmark, norm_words(norm), cfg.ratio);
                line_chart(&Chart { title: &title, x_label: "dx", y_label: &norm_words(norm), scale: Scale::LogLog, size: (900, 500) }, &series)
            })
            .collect();
        match panels.and_then(|p| stack_vertically(&p)) {
            Ok(svg) => crate::write_file(&out.join(format!("plot_{norm}.svg")), &svg)?,
            Err(e) => notes.push(format!("warning: plot of {norm} skipped: {e}")),
        }
    }
    Ok((results, wall, tables))
}

/// The files a sweep of `cfg` writes into its folder: one CSV per (scheme,
/// mass), the rates, the oscillation indicator and the plots.
fn output_files(cfg: &StudyConfig) -> Vec<String> {
    let mut files: Vec<String> = cfg.schemes.iter().flat_map(|s| cfg.masses.iter().map(move |&m| study::file_name(s, m))).collect();
    files.extend(["rates.csv", "oscillation.csv"].map(String::from));
    files.extend(PLOTTED_NORMS.iter().map(|n| format!("plot_{n}.svg")));
    files
}

/// A norm's column name in words, for axes and titles.
fn norm_words(norm: &str) -> String {
    let words = match norm {
        "linf_l2_u" => "max in time of the L² error of u (L∞(0,T;L²))",
        "l2_l2_u" => "L² in time of the L² error of u (L²(0,T;L²))",
        "linf_v_u" => "max in time of the strain error (L∞(0,T;V))",
        "l2_energy" => "L² in time of the energy error",
        other => other,
    };
    words.to_string()
}

/// The norms drawn against dx, one SVG each (a panel per mass).
const PLOTTED_NORMS: [&str; 4] = ["linf_l2_u", "l2_l2_u", "linf_v_u", "l2_energy"];
