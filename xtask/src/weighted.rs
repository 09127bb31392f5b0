//! `cargo xtask weighted`: the weighted-mass-redistribution study
//! (`signorini_studies::weighted`, which documents its outputs).

use signorini_studies::weighted;
use std::path::PathBuf;

/// Arguments of `cargo xtask weighted`.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/weighted")]
    out: PathBuf,
    /// Horizon of the figure runs (the paper's figures show [0, 3]; the
    /// phase and energy tables use 3 and 30).
    #[arg(long = "t-end", default_value_t = 30.0, allow_hyphen_values = true)]
    t_end: f64,
}

/// Runs the study.
pub fn run(a: Args) -> Result<(), crate::Failure> {
    let cfg = weighted::Config { out: a.out, t_end: a.t_end };
    let out = crate::with_progress_bar(|p| weighted::run(&cfg, p))?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
