//! `cargo xtask <study>`: the reproducible studies of signorini. Each study
//! lives in `signorini_studies::<study>` (Config, run, Output with one table
//! per CSV); this binary only turns the flags into its `Config`, draws a
//! progress bar where the study has one, and prints the report and notes.
//!
//! * `convergence`: sweep dx at a fixed dx/dt for each (scheme, mass) pair;
//!   write one CSV error curve per pair, `rates.csv`, `oscillation.csv`,
//!   log-log plots, and print the rates as a Markdown table. Defaults: the
//!   papers' study.
//! * `weighted`: the weighted-mass-redistribution study (mod1/mod2/mod3 ×
//!   newmark-cn, backward-euler, ps-e1, hybrid): figure runs, phase errors,
//!   energy loss and convergence.
//! * `work-precision`: error against wall time; `stress`: long runs at
//!   extreme dx/dt with random data.
//! * `beam`: the beam between two stops — the paper's figures 2–8, wall
//!   times against the paper's, the exact stability limit, self-convergence.
//! * `lyapunov`: the largest Lyapunov exponent of the beam scenes and the
//!   impact oscillator (Benettin's twin runs), the predictability horizon.
//! * `beam-statistics`: statistics of the beam over long windows with
//!   batch-means intervals against dt and J (which converge).
//! * `fuzz`: the scene reader and validator on generated and mutated scenes.
//! * `docs`: the user guide's generated tables, from `data/reference`,
//!   and ARCHITECTURE.md's crate graph, from `cargo tree` (`--check`: fail
//!   when a committed one is out of date).
//! * `test`: every test, and the guide's strict build.

mod beam;
mod beam_statistics;
mod courant1;
mod crate_graph;
mod docs;
mod fuzz;
mod long_horizon;
mod lyapunov;
mod obstacles;
mod oscillator;
mod pytest;
mod scene_keys;
mod stress;
mod weighted;
mod wp;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use signorini_studies::{convergence, StudyError};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "cargo xtask", about = "Reproducible studies of signorini")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Convergence study: error norms against dx at fixed dx/dt, and their rates.
    Convergence(ConvergenceArgs),
    /// Weighted mass redistribution and the hybrid scheme: figure runs, phase shift, energy, rates.
    Weighted(weighted::Args),
    /// The beam between two stops: the paper's seven scenes, timings, stability limit, self-convergence.
    Beam(beam::Args),
    /// The beam between obstacles along its whole length (problem (P)): feasibility, self-convergence in dt and J, energy balance.
    #[command(name = "beam-obstacles")]
    BeamObstacles(obstacles::Args),
    /// The impact oscillator scene against its exact period-1 orbits (rates in dt) and its grazing frequency.
    Oscillator(oscillator::Args),
    /// Every test: the Rust workspace's, then the Python package (built with maturin into target/py-venv) with pytest, then the user guide (generated tables checked, mkdocs build --strict).
    Test(pytest::Args),
    /// Work–precision: error reached against wall time per scheme and mass.
    #[command(name = "work-precision")]
    WorkPrecision(wp::Args),
    /// Stability stress: long runs, extreme dx/dt, random data; energy drift and blow-ups.
    Stress(stress::Args),
    /// Courant number one: the lumped central difference at dx/dt = c, node by node against the exact solutions.
    Courant1(courant1::Args),
    /// The Dirichlet bar over many periods (T = 30): error against time and impact phase for every mass.
    #[command(name = "long-horizon")]
    LongHorizon(long_horizon::Args),
    /// The largest Lyapunov exponent (Benettin's twin runs) of the paper's beam scenes, beam-obstacles and the impact oscillator, and the predictability horizon.
    Lyapunov(lyapunov::Args),
    /// Statistics of the beam scenes over a long window with 95 % batch-means intervals, against dt and J: which converge.
    #[command(name = "beam-statistics")]
    BeamStatistics(beam_statistics::Args),
    /// Fuzz the scene reader and validator: no panic, typed errors naming a field.
    Fuzz(fuzz::Args),
    /// The user guide's generated tables (docs/generated/, the README's headline) from data/reference, the scene key reference from the scene schema (crates/scene), and ARCHITECTURE.md's crate graph from `cargo tree`; --check compares instead of writing.
    Docs(docs::Args),
}

// The field docs are the `--help` text (clap), where `<benchmark>` is a
// placeholder and `[,B]` an optional part, not HTML or a link; writing them
// for rustdoc would change the help.
#[allow(rustdoc::invalid_html_tags, rustdoc::broken_intra_doc_links)]
#[derive(clap::Args)]
struct ConvergenceArgs {
    /// Benchmark with an exact solution (bar-dirichlet, bar-neumann-gravity,
    /// bar-neumann-gravity-0.11, bar-mirrored: level m is m elements on
    /// [0, 1], 2m on its [0, 2]).
    #[arg(long, default_value = "bar-dirichlet")]
    benchmark: String,
    /// Schemes, comma-separated: presets or newmark(B,G), theta(T), ps(E[,B]).
    #[arg(long, default_value = "newmark-cn,newmark-i,newmark-ii,backward-euler,ps-e0,ps-e0.5,ps-e1")]
    schemes: Vec<String>,
    /// Mass treatments, comma-separated (std, lumped, mod, mod1, mod2, mod3, transfer, singular).
    #[arg(long, value_delimiter = ',', default_value = "std,mod")]
    masses: Vec<String>,
    /// Numbers of elements m, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "10,20,40,80,160,320,640", allow_hyphen_values = true, value_parser = whole)]
    levels: Vec<usize>,
    /// dx/dt (default: the benchmark's, 10 for bar-dirichlet).
    #[arg(long, allow_hyphen_values = true)]
    ratio: Option<f64>,
    /// Horizon T (default: the benchmark's, 3 for bar-dirichlet).
    #[arg(long = "t-end", allow_hyphen_values = true)]
    t_end: Option<f64>,
    /// Output folder (default out/convergence/<benchmark>, or
    /// out/convergence/<benchmark>-getfem-norms with --norms getfem).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Error measure: exact (kink-split, docs/theory.md §6.1) or getfem (errors of the
    /// nodal interpolant, relative to the reference's norms, as GetFEM's
    /// 1D dynamic-contact demo computes them).
    #[arg(long, default_value = "exact")]
    norms: String,
    /// A reduced model at every level (docs/theory.md §2.5): modes=R keeps
    /// the R lowest fixed-interface modes, cutoff_hz=F every mode up to F Hz
    /// (needs a massless-contact mass and a scheme that takes one). Default: none.
    #[arg(long)]
    reduce: Option<String>,
    /// Element degree k (1, 2, 3: Lagrange P1, P2, P3); level m is m elements
    /// of degree k (default folder out/convergence/<benchmark>-p<k> for k > 1).
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = whole)]
    degree: usize,
    /// Remove the CSV and SVG files of another study or configuration from
    /// the output folder first (without it such a folder is refused).
    #[arg(long)]
    clean: bool,
    /// What the errors are measured against: exact (the benchmark's closed
    /// form) or event-driven (the exact semi-discrete solution on the same
    /// mesh: the time error alone, with the space error beside it; every
    /// mass, massless contact nodes against event-driven(0); with --reduce,
    /// the reduced model's; default folder
    /// out/convergence/<benchmark>-event-driven[-reduce-…]).
    #[arg(long, default_value = "exact")]
    reference: String,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.cmd {
        Cmd::Convergence(a) => convergence(a),
        Cmd::Weighted(a) => weighted::run(a),
        Cmd::Beam(a) => beam::run_beam(a),
        Cmd::BeamObstacles(a) => obstacles::run_obstacles(a),
        Cmd::Oscillator(a) => oscillator::run_oscillator(a),
        Cmd::Test(a) => pytest::run_tests(a),
        Cmd::WorkPrecision(a) => wp::run_wp(a),
        Cmd::Stress(a) => stress::run_stress(a),
        Cmd::Courant1(a) => courant1::run_courant1(a),
        Cmd::LongHorizon(a) => long_horizon::run_long_horizon(a),
        Cmd::Lyapunov(a) => lyapunov::run_lyapunov(a),
        Cmd::BeamStatistics(a) => beam_statistics::run_beam_statistics(a),
        Cmd::Fuzz(a) => fuzz::run_fuzz(a).map_err(Failure::from),
        Cmd::Docs(a) => docs::run_docs(a).map_err(Failure::from),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // Bad input exits 2, as clap's own errors and `signorini` do.
        Err(Failure::Input(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        Err(Failure::Failed(e)) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
        Err(Failure::Reported) => ExitCode::FAILURE,
    }
}

/// Why a `cargo xtask` command stopped: bad input (a flag out of its range,
/// exit status 2, as clap's own errors and the `signorini` command) or a
/// failure of the work itself (exit status 1).
#[derive(Debug)]
pub(crate) enum Failure {
    /// Bad input; the message names the flag and what is allowed.
    Input(String),
    /// A run, a file or a tool failed.
    Failed(String),
    /// A failure already reported on the terminal (`cargo xtask test`,
    /// whose verdict must stay its last line).
    Reported,
}

impl From<StudyError> for Failure {
    /// A study's [`StudyError::Config`] is bad input; anything else a failure.
    fn from(e: StudyError) -> Self {
        match e {
            StudyError::Config { message, .. } => Failure::Input(message),
            other => Failure::Failed(other.to_string()),
        }
    }
}

impl From<String> for Failure {
    /// The commands that are not studies (test, fuzz, docs) fail with text.
    fn from(e: String) -> Self {
        Failure::Failed(e)
    }
}

/// A whole-number flag (elements, levels, batches, …): a negative number
/// or a fraction is refused by clap naming the flag (exit 2); the flag's
/// range is checked by its study.
pub(crate) fn whole(s: &str) -> Result<usize, String> {
    s.trim().parse::<usize>().map_err(|_| format!("allowed a whole number >= 0 ({s:?} is not one); the study checks the flag's range"))
}

fn convergence(a: ConvergenceArgs) -> Result<(), Failure> {
    let benchmark = convergence::parse_benchmark(&a.benchmark)?;
    // Schemes may contain commas inside parentheses: split on ',' outside them.
    let schemes = signorini_studies::parse_schemes(&a.schemes)?;
    let masses = signorini_studies::parse_masses(&a.masses)?;
    let norms = convergence::parse_norms(&a.norms)?;
    let reduce = a.reduce.as_deref().map(convergence::parse_reduce).transpose()?;
    let reference = convergence::parse_reference(&a.reference)?;
    let cfg = convergence::Config { benchmark, schemes, masses, levels: a.levels, ratio: a.ratio, t_end: a.t_end, out: a.out, norms, reduce, degree: a.degree, clean: a.clean, reference };
    let out = with_progress_bar(|p| convergence::run(&cfg, p))?;
    notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}

/// Prints a study's notes and warnings on stderr.
pub(crate) fn notes(notes: &[String]) {
    for n in notes {
        eprintln!("{n}");
    }
}

/// Runs `f` with a progress bar on a terminal (hidden otherwise) driven by
/// its `progress(done, total)` callback.
pub(crate) fn with_progress_bar<T>(f: impl FnOnce(&(dyn Fn(u64, u64) + Sync)) -> T) -> T {
    let bar = ProgressBar::with_draw_target(Some(0), if std::io::stderr().is_terminal() { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() });
    bar.set_style(ProgressStyle::with_template("{bar:40} {pos}/{len} runs  {elapsed}").unwrap_or_else(|_| ProgressStyle::default_bar()));
    let r = f(&|done, total| {
        bar.set_length(total);
        bar.set_position(done);
    });
    bar.finish_and_clear();
    r
}
