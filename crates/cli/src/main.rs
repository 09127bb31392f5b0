//! `signorini`: run, check and list 1D dynamic contact scenes.

use clap::{Parser, Subcommand};
use signorini_cli::scene::SceneFile;
use signorini_cli::{check, list, run_scene, CliError};
use std::io::IsTerminal;
use std::path::PathBuf;
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
        /// Output folder (default out/<scene file stem>).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Validate a scene and print its stability limit and cost estimate.
    Check {
        /// The scene (TOML).
        scene: PathBuf,
    },
    /// List schemes, masses, benchmarks and beam scenes with their ranges.
    List,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: Result<(), CliError> = (|| match cli.cmd {
        Cmd::List => {
            print!("{}", list());
            Ok(())
        }
        Cmd::Check { scene } => {
            let s = signorini_cli::load(&scene)?;
            println!("{}", check(&s)?);
            Ok(())
        }
        Cmd::Run { scene, out } => {
            let text = std::fs::read_to_string(&scene).map_err(|e| CliError::Io(format!("cannot read {}: {e}", scene.display())))?;
            let file = SceneFile::parse(&text)?;
            let s = file.validate()?;
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(scene.file_stem().unwrap_or_default()));
            let summary = run_scene(&s, &file, &out, std::io::stderr().is_terminal())?;
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
            ExitCode::from(match e {
                CliError::Scene(_) => 2,
                _ => 1,
            })
        }
    }
}
