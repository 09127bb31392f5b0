//! `cargo xtask stress`: long runs at extreme dx/dt with random initial data
//! (`signorini_studies::stress`, which documents its outputs).

use signorini_studies::stress;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/stress")]
    out: PathBuf,
    /// Steps per run.
    #[arg(long, default_value_t = 100_000, allow_hyphen_values = true, value_parser = crate::whole)]
    steps: usize,
    /// Elements.
    #[arg(long, default_value_t = 40, allow_hyphen_values = true, value_parser = crate::whole)]
    elements: usize,
    /// Random seed.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    seed: u64,
}

/// Runs the study.
pub fn run_stress(a: Args) -> Result<(), crate::Failure> {
    let cfg = stress::Config { out: a.out, steps: a.steps, elements: a.elements, seed: a.seed };
    let out = stress::run(&cfg, &|_, _| {})?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
