//! `signorini`: run, check and list 1D dynamic contact scenes.

use clap::{Parser, Subcommand};
use signorini_cli::scene::Limits;
use signorini_cli::sweep::{Axis, Sweep, SweepOptions};
use signorini_cli::{check, list, run_scene, CliError, RunOptions};
use signorini_run::Cancel;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "signorini", version, about = "1D dynamic contact: bar on an obstacle, beam between stops")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a scene file and write its CSV series and SVG plots.
    Run {
        /// The scene (TOML).
        scene: PathBuf,
        /// Output folder (default out/SCENE, SCENE the scene file stem, relative to the current directory).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Remove an earlier run's files from the output folder first (otherwise such a folder is refused).
        #[arg(long)]
        clean: bool,
        /// Run even if the estimated output exceeds the free disk space.
        #[arg(long)]
        no_disk_check: bool,
        /// Memory cap for the run, e.g. 4G, 512M or bytes (default: the machine's available memory).
        #[arg(long, value_parser = parse_bytes)]
        max_memory: Option<f64>,
    },
    /// Validate a scene and print its stability limit, memory, output size and cost estimates.
    Check {
        /// The scene (TOML).
        scene: PathBuf,
        /// Output folder the run would use (for the free-space check).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Memory cap, as for `run`.
        #[arg(long, value_parser = parse_bytes)]
        max_memory: Option<f64>,
    },
    /// List schemes, masses, benchmarks and beam scenes with their ranges.
    List,
    /// Sweep one numeric scene field over a grid: Poincaré samples, impacts, statistics and a bifurcation diagram.
    Sweep {
        /// The scene (TOML).
        scene: PathBuf,
        /// Dotted path of the swept field, e.g. forcing.omega, support.amplitude, stop.0.hi.
        #[arg(long)]
        param: String,
        /// First value.
        #[arg(long, allow_hyphen_values = true)]
        from: f64,
        /// Last value (may be below --from: a downward sweep).
        #[arg(long, allow_hyphen_values = true)]
        to: f64,
        /// Number of runs (>= 1).
        #[arg(long)]
        count: usize,
        /// Logarithmic spacing (both bounds > 0).
        #[arg(long)]
        log: bool,
        /// A second swept field, for a two-parameter map (run r: value r mod count of --param, r div count of --param2).
        #[arg(long, requires_all = ["from2", "to2", "count2"])]
        param2: Option<String>,
        /// First value of --param2.
        #[arg(long, allow_hyphen_values = true, requires = "param2")]
        from2: Option<f64>,
        /// Last value of --param2.
        #[arg(long, allow_hyphen_values = true, requires = "param2")]
        to2: Option<f64>,
        /// Number of values of --param2.
        #[arg(long, requires = "param2")]
        count2: Option<usize>,
        /// Logarithmic spacing of --param2.
        #[arg(long, requires = "param2")]
        log2: bool,
        /// Forcing periods before the record window.
        #[arg(long, default_value_t = 100.0)]
        transient: f64,
        /// Forcing periods recorded.
        #[arg(long, default_value_t = 10.0)]
        record: f64,
        /// Forcing phase of the Poincaré section, in [0, 2π).
        #[arg(long, default_value_t = 0.0)]
        phase: f64,
        /// Relative tolerance of the response-period test, in (0, 1): a first-order scheme's impacts jitter by O(dt).
        #[arg(long, default_value_t = 1e-3)]
        period_tol: f64,
        /// Do not write impacts.csv and impact_map.svg (a chattering beam makes hundreds of impacts per period); summary.csv keeps the statistics.
        #[arg(long)]
        no_impacts: bool,
        /// Start each run from the previous run's final state (continuation: hysteresis).
        #[arg(long)]
        follow: bool,
        /// Run only the I-th of N blocks of runs (I from 0), for `signorini merge`.
        #[arg(long, value_parser = parse_shard)]
        shard: Option<(usize, usize)>,
        /// Continue an interrupted sweep in --out without recomputing its runs.
        #[arg(long)]
        resume: bool,
        /// Threads (default: all cores); the output does not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Output folder (default out/SCENE-sweep, SCENE the scene file stem).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Memory cap per run, as for `run`.
        #[arg(long, value_parser = parse_bytes)]
        max_memory: Option<f64>,
    },
    /// The branch of periodic orbits of an event-driven scene in a numeric
    /// key, with stability and bifurcations: branch.csv, bifurcations.csv,
    /// branch.svg.
    /// The nonsmooth modes of an unforced bar (scheme = "event-driven"): its
    /// periodic motions continued in the energy, backbone.csv and backbone.svg.
    Modes {
        /// The scene (an unforced [bar], far end clamped).
        scene: PathBuf,
        /// The lowest energy.
        #[arg(long, allow_hyphen_values = true)]
        from: f64,
        /// The highest energy.
        #[arg(long, allow_hyphen_values = true)]
        to: f64,
        /// Energies on the backbone (geometric steps; linear from 0).
        #[arg(long, default_value_t = 40)]
        points: usize,
        /// Output folder (default out/<scene>-modes).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    Continue {
        /// The scene (TOML; scheme = "event-driven(e)", a periodic forcing).
        scene: PathBuf,
        /// The parameter's dotted path in the scene (e.g. forcing.omega), written in the scene.
        #[arg(long)]
        param: String,
        /// The start of the range (the first orbit is found there).
        #[arg(long, allow_hyphen_values = true)]
        from: f64,
        /// The end of the range.
        #[arg(long, allow_hyphen_values = true)]
        to: f64,
        /// Forcing periods per orbit (1: period-1 orbits).
        #[arg(long, default_value_t = 1)]
        period: usize,
        /// Forcing periods run from the scene's initial state before Newton.
        #[arg(long, default_value_t = 100.0)]
        transient: f64,
        /// Most points per branch.
        #[arg(long, default_value_t = 400)]
        max_points: usize,
        /// The parameter's scale for the steps (scaled arclength) and the searches' offsets, which are fractions of it; default: the range |to - from|. Given, runs from one start to different ends take the same steps where they overlap.
        #[arg(long)]
        param_scale: Option<f64>,
        /// At each period doubling, continue the period-doubled branch too (and theirs, a cascade of up to 3 doublings); at each branch point, the branch crossing there.
        #[arg(long)]
        switch: bool,
        /// A sweep folder (signorini sweep --out) whose bifurcation diagram the plot draws under the branch.
        #[arg(long)]
        sweep: Option<PathBuf>,
        /// Output folder (default out/<scene>-continue).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Memory a scene may use (e.g. 4G); default: the machine's available memory.
        #[arg(long, value_parser = parse_bytes)]
        max_memory: Option<f64>,
    },
    /// Basins of attraction of an event-driven scene over a grid of initial
    /// states: basins.csv (each cell's attractor), basins.svg.
    Basins {
        /// The scene (TOML; scheme = "event-driven(e)", a periodic forcing).
        scene: PathBuf,
        /// Dotted path of the initial displacement key (e.g. oscillator.initial_displacement), written in the scene.
        #[arg(long)]
        x: String,
        /// Dotted path of the initial velocity key (e.g. oscillator.initial_velocity), written in the scene.
        #[arg(long)]
        v: String,
        /// Cells along x and along v (each >= 1).
        #[arg(long, num_args = 2, value_names = ["NX", "NY"], required = true)]
        grid: Vec<usize>,
        /// First and last value of --x (cell centres).
        #[arg(long, num_args = 2, value_names = ["A", "B"], allow_negative_numbers = true, required = true)]
        x_range: Vec<f64>,
        /// First and last value of --v (cell centres).
        #[arg(long, num_args = 2, value_names = ["C", "D"], allow_negative_numbers = true, required = true)]
        v_range: Vec<f64>,
        /// Forcing periods run before the attractor is read.
        #[arg(long, default_value_t = 200)]
        transient: usize,
        /// Longest period looked for, in forcing periods.
        #[arg(long, default_value_t = 16)]
        max_period: usize,
        /// Period test: |P^k(x) - x|_inf <= tol * max(1, |x|_inf), P the stroboscopic map.
        #[arg(long, default_value_t = 1e-6)]
        tol: f64,
        /// Tolerance (relative, as --tol) of grouping cells into attractors and matching --orbits.
        #[arg(long, default_value_t = 1e-3)]
        match_tol: f64,
        /// A continuation's branch.csv (signorini continue): label cells by the known orbits they reach.
        #[arg(long)]
        orbits: Option<PathBuf>,
        /// Run only the I-th of N blocks of cells (I from 0), for `signorini merge`.
        #[arg(long, value_parser = parse_shard)]
        shard: Option<(usize, usize)>,
        /// Threads (default: all cores); the output does not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Output folder (default out/SCENE-basins).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Memory a scene may use (e.g. 4G); default: the machine's available memory.
        #[arg(long, value_parser = parse_bytes)]
        max_memory: Option<f64>,
    },
    /// Merge the shard folders of a sharded sweep (or basins) into the files of the unsharded one.
    Merge {
        /// The shard folders.
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
    },
}

/// `I/N`.
fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (i, n) = s.split_once('/').ok_or_else(|| format!("{s:?}: I/N, e.g. 3/16 (I from 0 to N - 1)"))?;
    match (i.trim().parse::<usize>(), n.trim().parse::<usize>()) {
        (Ok(i), Ok(n)) if n >= 1 && i < n => Ok((i, n)),
        _ => Err(format!("{s:?}: I/N with N >= 1 and 0 <= I < N, e.g. 3/16")),
    }
}

/// `4G`, `512M`, `100k` (powers of 1024) or a plain number of bytes.
fn parse_bytes(s: &str) -> Result<f64, String> {
    let t = s.trim();
    let (num, mult) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => {
            let m = match c.to_ascii_uppercase() {
                'K' => 1024.0,
                'M' => 1024.0 * 1024.0,
                'G' => 1024.0 * 1024.0 * 1024.0,
                'T' => 1024.0_f64.powi(4),
                _ => return Err(format!("{s:?}: a size such as 4G, 512M, 100K or a number of bytes")),
            };
            (&t[..i], m)
        }
        _ => (t, 1.0),
    };
    match num.parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v * mult),
        _ => Err(format!("{s:?}: a size > 0 such as 4G, 512M, 100K or a number of bytes")),
    }
}

fn limits(max_memory: Option<f64>) -> Limits {
    max_memory.map_or_else(Limits::machine, |m| Limits { max_memory: m })
}

fn default_out(scene: &Path) -> PathBuf {
    PathBuf::from("out").join(scene.file_stem().unwrap_or_default())
}

/// SIGINT and SIGTERM cancel a token the time loop checks at every step, and
/// an event-driven step inside its event search (the run then stops cleanly
/// and keeps its output); a second signal while the
/// token is cancelled exits at once with 130. The handlers hold clones of
/// the token's flag.
fn interrupt_token() -> Option<Cancel> {
    let cancel = Cancel::new();
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register_conditional_shutdown(sig, 130, cancel.flag()).ok()?;
        signal_hook::flag::register(sig, cancel.flag()).ok()?;
    }
    Some(cancel)
}

/// Writes to stdout; a closed pipe (`signorini … | head`) is not an error
/// worth a panic: what could not be printed is dropped.
fn say(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().write_all(text.as_bytes());
}

// The closure's error is the command's `CliError`, returned once.
#[allow(clippy::result_large_err)]
fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: Result<(), CliError> = (|| match cli.cmd {
        Cmd::List => {
            say(&list());
            Ok(())
        }
        Cmd::Check { scene, out, max_memory } => {
            let (file, s) = signorini_cli::load(&scene, &limits(max_memory))?;
            let out = out.unwrap_or_else(|| default_out(&scene));
            say(&format!("{}\n", check(&s, &file, &out)?));
            Ok(())
        }
        Cmd::Sweep { scene, param, from, to, count, log, param2, from2, to2, count2, log2, transient, record, phase, period_tol, no_impacts, follow, shard, resume, threads, out, max_memory } => {
            let text = signorini_cli::read_scene_file(&scene)?;
            let second = match (param2, from2, to2, count2) {
                (Some(param), Some(from), Some(to), Some(count)) => Some(Axis { param, from, to, count, log: log2 }),
                _ => None,
            };
            let mut opts = SweepOptions::new(&param, from, to, count);
            (opts.log, opts.second, opts.transient, opts.record, opts.phase, opts.period_tol) = (log, second, transient, record, phase, period_tol);
            (opts.impacts, opts.follow, opts.shard, opts.resume, opts.threads, opts.interrupt) = (!no_impacts, follow, shard, resume, threads, interrupt_token());
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-sweep", scene.file_stem().unwrap_or_default().to_string_lossy())));
            let sweep = Sweep::from_file(&scene, &text, opts, limits(max_memory))?;
            let bar = signorini_cli::RunsBar::new(std::io::stderr().is_terminal());
            let report = signorini_cli::sweep::run(&sweep, &out, &bar)?;
            for l in &report.lines {
                say(&format!("{l}\n"));
            }
            if report.failed > 0 {
                return Err(CliError::SweepFailed { failed: report.failed, total: report.runs, dir: out.display().to_string() });
            }
            Ok(())
        }
        Cmd::Modes { scene, from, to, points, out } => {
            let text = signorini_cli::read_scene_file(&scene)?;
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-modes", scene.file_stem().unwrap_or_default().to_string_lossy())));
            for l in signorini_cli::orbits::modes_scene(&text, from, to, points, &out)? {
                say(&format!("{l}\n"));
            }
            Ok(())
        }
        Cmd::Continue { scene, param, from, to, period, transient, max_points, param_scale, switch, sweep, out, max_memory } => {
            let text = signorini_cli::read_scene_file(&scene)?;
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-continue", scene.file_stem().unwrap_or_default().to_string_lossy())));
            let sweep = sweep.as_deref().map(signorini_cli::orbits::sweep_points).transpose()?.unwrap_or_default();
            let opts = signorini_orbits::front::ContinueOptions { param, from, to, period, transient, max_points, switch, sweep, param_scale };
            for l in signorini_cli::orbits::continue_scene(&text, &opts, &out, limits(max_memory), std::io::stderr().is_terminal(), interrupt_token())? {
                say(&format!("{l}\n"));
            }
            Ok(())
        }
        Cmd::Basins { scene, x, v, grid, x_range, v_range, transient, max_period, tol, match_tol, orbits, shard, threads, out, max_memory } => {
            let text = signorini_cli::read_scene_file(&scene)?;
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-basins", scene.file_stem().unwrap_or_default().to_string_lossy())));
            use signorini_orbits::basins::{Axis, BasinOptions};
            let opts = signorini_cli::basins::BasinsOptions {
                x: Axis { path: x, from: x_range[0], to: x_range[1], count: grid[0] },
                v: Axis { path: v, from: v_range[0], to: v_range[1], count: grid[1] },
                classify: BasinOptions { transient, max_period, tol, match_tol },
                orbits,
                shard,
                threads,
                interrupt: interrupt_token(),
                progress: std::io::stderr().is_terminal(),
            };
            for l in signorini_cli::basins::basins(&text, &opts, &out, limits(max_memory))?.lines {
                say(&format!("{l}\n"));
            }
            Ok(())
        }
        Cmd::Merge { shards, out } if shards.first().is_some_and(|d| signorini_cli::basins::is_basins_folder(d)) => {
            for l in signorini_cli::basins::merge(&shards, &out)? {
                say(&format!("{l}\n"));
            }
            Ok(())
        }
        Cmd::Merge { shards, out } => {
            for l in signorini_cli::sweep::merge(&shards, &out)? {
                say(&format!("{l}\n"));
            }
            Ok(())
        }
        Cmd::Run { scene, out, clean, no_disk_check, max_memory } => {
            let (file, s) = signorini_cli::load(&scene, &limits(max_memory))?;
            let out = out.unwrap_or_else(|| default_out(&scene));
            let mut opts = RunOptions::default();
            (opts.progress, opts.clean, opts.no_disk_check, opts.interrupt) = (std::io::stderr().is_terminal(), clean, no_disk_check, interrupt_token());
            let summary = run_scene(&s, &file, &out, &opts)?;
            for w in &summary.warnings {
                eprintln!("{w}");
            }
            for l in summary.lines {
                say(&format!("{l}\n"));
            }
            Ok(())
        }
    })();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", signorini_run::text::tidy_numbers(&e.to_string()));
            ExitCode::from(e.exit_code())
        }
    }
}
