//! `cargo xtask <study>`: the reproducible studies of signorini.
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
//! * `fuzz`: the scene reader and validator on generated and mutated scenes.

mod beam;
mod fuzz;
mod obstacles;
mod oscillator;
mod pytest;
mod stress;
mod weighted;
mod wp;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use signorini_fem::BarMass;
use signorini_norms::NormKind;
use signorini_run::study::{self, StudyConfig};
use signorini_run::Benchmark;
use signorini_schemes::SchemeSpec;
use std::fs::File;
use std::io::{BufWriter, IsTerminal};
use signorini_plot::{line_chart, Chart, Scale, Series, Style};
use std::path::{Path, PathBuf};
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
    /// Every test: the Rust workspace's, then the Python package (built with maturin into target/py-venv) with pytest.
    Test(pytest::Args),
    /// Work–precision: error reached against wall time per scheme and mass.
    #[command(name = "work-precision")]
    WorkPrecision(wp::Args),
    /// Stability stress: long runs, extreme dx/dt, random data; energy drift and blow-ups.
    Stress(stress::Args),
    /// Fuzz the scene reader and validator: no panic, typed errors naming a field.
    Fuzz(fuzz::Args),
}

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
    #[arg(long, value_delimiter = ',', default_value = "10,20,40,80,160,320,640")]
    levels: Vec<usize>,
    /// dx/dt (default: the benchmark's, 10 for bar-dirichlet).
    #[arg(long, allow_negative_numbers = true)]
    ratio: Option<f64>,
    /// Horizon T (default: the benchmark's, 3 for bar-dirichlet).
    #[arg(long = "t-end", allow_negative_numbers = true)]
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
        Cmd::Fuzz(a) => fuzz::run_fuzz(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn convergence(a: ConvergenceArgs) -> Result<(), String> {
    let benchmark: Benchmark = a.benchmark.parse().map_err(|e| format!("--benchmark: {e}"))?;
    // Schemes may contain commas inside parentheses: split on ',' outside them.
    let schemes = split_schemes(&a.schemes).iter().map(|s| s.parse::<SchemeSpec>().map_err(|e| format!("--schemes: {e}"))).collect::<Result<Vec<_>, _>>()?;
    let masses = a.masses.iter().map(|s| s.trim().parse::<BarMass>().map_err(|e| format!("--masses: {e}"))).collect::<Result<Vec<_>, _>>()?;
    let (ratio0, t0) = benchmark.default_ratio_and_horizon();
    let norms = match a.norms.as_str() {
        "exact" => NormKind::Exact,
        "getfem" => NormKind::GetfemInterpolated,
        other => return Err(format!("--norms {other:?}: allowed exact or getfem")),
    };
    let mut cfg = StudyConfig { benchmark, schemes, masses, levels: a.levels, ratio: a.ratio.unwrap_or(ratio0), t_end: a.t_end.unwrap_or(t0), norms };
    cfg.validate().map_err(|e| e.to_string())?;
    if benchmark == Benchmark::BarMirrored {
        cfg.schemes = several_contact_schemes(&cfg)?;
    }
    // The sweep runs as many levels at once as there are cores.
    fits_memory("--levels", cfg.levels.iter().copied().max().unwrap_or(0), std::thread::available_parallelism().map_or(1, |n| n.get()))?;
    let folder = if norms == NormKind::Exact { benchmark.name().to_string() } else { format!("{}-getfem-norms", benchmark.name()) };
    let out = a.out.unwrap_or_else(|| PathBuf::from("out/convergence").join(folder));

    let results = run_study(&cfg, &out)?;
    println!(
        "# Convergence: {}, dx/dt = {}, T = {}, m = {:?}{}\n\nLeast-squares rates of the error against dx (CSV: {}).\n",
        cfg.benchmark,
        cfg.ratio,
        cfg.t_end,
        cfg.levels,
        if cfg.norms == NormKind::Exact { "" } else { " — GetFEM-demo norms: errors of the nodal interpolant, relative" },
        out.display()
    );
    print!("{}", study::markdown_table(&results.0));
    println!("\n{} runs in {:.1} s", results.0.iter().map(|r| r.levels.len()).sum::<usize>(), results.1);
    Ok(())
}

/// The schemes of `cfg` that take several contacts (bar-mirrored has two
/// stops): each is built on the smallest level with each mass, and one that
/// refuses the structure (the reduced schemes, Nitsche) is left out with a
/// printed note. Nothing left is an error.
fn several_contact_schemes(cfg: &StudyConfig) -> Result<Vec<SchemeSpec>, String> {
    let exact = cfg.benchmark.exact(cfg.t_end).map_err(|e| e.to_string())?;
    let m = cfg.levels.iter().copied().min().unwrap_or(2);
    let mut keep = Vec::new();
    'schemes: for s in &cfg.schemes {
        for &mass in &cfg.masses {
            let p = cfg.benchmark.problem(exact.as_ref(), m, mass).map_err(|e| format!("--masses {mass}: {e}"))?;
            if let Err(signorini_schemes::SchemeError::Structure(why)) = s.build(p.dynamics(), p.bar.h() / cfg.ratio, &p.initial) {
                eprintln!("note: {s} skipped on {}: {why}", cfg.benchmark);
                continue 'schemes;
            }
        }
        keep.push(*s);
    }
    if keep.is_empty() {
        return Err(format!("--schemes: none of them takes the two stops of {}: use newmark, theta, ps, penalty or moreau-jean", cfg.benchmark));
    }
    Ok(keep)
}

/// Refuses `copies` runs of `elements` elements at once beyond the
/// machine's available memory (the estimate of `signorini check`).
pub(crate) fn fits_memory(flag: &str, elements: usize, copies: usize) -> Result<(), String> {
    let need = signorini_cli::scene::memory_estimate(elements, false) * copies.max(1) as f64;
    let have = signorini_cli::scene::Limits::machine().max_memory;
    if need > have {
        return Err(format!("{flag}: {elements} elements need about {} of memory ({copies} at once), beyond the {} available", signorini_cli::scene::bytes(need), signorini_cli::scene::bytes(have)));
    }
    Ok(())
}

/// Creates a file in `dir` for writing.
pub(crate) fn create(dir: &Path, name: &str) -> Result<BufWriter<File>, String> {
    let p = dir.join(name);
    File::create(&p).map(BufWriter::new).map_err(|e| format!("cannot write {}: {e}", p.display()))
}

/// Runs a sweep with a progress bar on a terminal and writes its CSVs and
/// log-log plots into `out`; returns the results and the wall time.
pub(crate) fn run_study(cfg: &StudyConfig, out: &Path) -> Result<(Vec<study::ConfigResult>, f64), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let total = (cfg.schemes.len() * cfg.masses.len() * cfg.levels.len()) as u64;
    let bar = ProgressBar::with_draw_target(Some(total), if std::io::stderr().is_terminal() { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() });
    bar.set_style(ProgressStyle::with_template("{bar:40} {pos}/{len} runs  {elapsed}").unwrap_or_else(|_| ProgressStyle::default_bar()));
    let start = std::time::Instant::now();
    let results = study::sweep(cfg, &|| bar.inc(1)).map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    for r in &results {
        r.write_csv(create(out, &r.file_name())?).map_err(|e| e.to_string())?;
    }
    study::write_rates(create(out, "rates.csv")?, &results).map_err(|e| e.to_string())?;
    study::write_oscillation(create(out, "oscillation.csv")?, &results).map_err(|e| e.to_string())?;
    for norm in ["linf_l2_u", "l2_l2_u", "linf_v_u", "l2_energy"] {
        let series: Vec<Series> = results
            .iter()
            .map(|r| {
                // Colour by scheme, marker and dash by mass.
                let style = Style { group: cfg.schemes.iter().position(|s| *s == r.scheme), variant: cfg.masses.iter().position(|m| *m == r.mass) };
                Series { label: format!("{} {}", r.scheme, r.mass), points: r.levels.iter().map(|l| (l.dx, study::norm_value(&l.norms, norm))).collect(), reference: false, style }
            })
            .collect();
        let chart = Chart { title: &format!("{}: {norm} against dx (dx/dt = {})", cfg.benchmark, cfg.ratio), x_label: "dx", y_label: norm, scale: Scale::LogLog, size: (900, 600) };
        match line_chart(&chart, &series) {
            Ok(svg) => std::fs::write(out.join(format!("plot_{norm}.svg")), svg).map_err(|e| e.to_string())?,
            Err(e) => eprintln!("warning: plot of {norm} skipped: {e}"),
        }
    }
    Ok((results, wall))
}

/// Joins pieces that clap split inside parentheses, e.g. `newmark(0.25` + `0.5)`.
fn split_schemes(raw: &[String]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for piece in raw.iter().flat_map(|s| s.split(',')) {
        match out.last_mut() {
            Some(last) if last.matches('(').count() > last.matches(')').count() => {
                last.push(',');
                last.push_str(piece.trim());
            }
            _ => out.push(piece.trim().to_string()),
        }
    }
    out.retain(|s| !s.is_empty());
    out
}
