//! `signorini`: run, check and list 1D dynamic contact scenes.

use clap::{Parser, Subcommand};
use signorini_cli::scene::Limits;
use signorini_cli::{check, list, run_scene, CliError, RunOptions};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

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
        /// Output folder (default out/<scene file stem>, relative to the current directory).
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

/// SIGINT and SIGTERM set a flag the time loop checks at every step (the run
/// then stops cleanly and keeps its output); a second signal while the flag
/// is set exits at once with 130.
fn interrupt_flag() -> Option<&'static AtomicBool> {
    let flag: &'static Arc<AtomicBool> = Box::leak(Box::new(Arc::new(AtomicBool::new(false))));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register_conditional_shutdown(sig, 130, Arc::clone(flag)).ok()?;
        signal_hook::flag::register(sig, Arc::clone(flag)).ok()?;
    }
    Some(&**flag)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: Result<(), CliError> = (|| match cli.cmd {
        Cmd::List => {
            print!("{}", list());
            Ok(())
        }
        Cmd::Check { scene, out, max_memory } => {
            let (file, s) = signorini_cli::load(&scene, &limits(max_memory))?;
            let out = out.unwrap_or_else(|| default_out(&scene));
            println!("{}", check(&s, &file, &out)?);
            Ok(())
        }
        Cmd::Run { scene, out, clean, no_disk_check, max_memory } => {
            let (file, s) = signorini_cli::load(&scene, &limits(max_memory))?;
            let out = out.unwrap_or_else(|| default_out(&scene));
            let opts = RunOptions { progress: std::io::stderr().is_terminal(), clean, no_disk_check, interrupt: interrupt_flag() };
            let summary = run_scene(&s, &file, &out, &opts)?;
            for l in summary.lines {
                println!("{l}");
            }
            Ok(())
        }
    })();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
