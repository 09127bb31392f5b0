//! `cargo xtask work-precision`: error reached against wall time, per scheme
//! and mass (`signorini_studies::work_precision`, which documents its outputs).

use signorini_studies::work_precision;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/work-precision")]
    out: PathBuf,
    /// Levels m.
    #[arg(long, value_delimiter = ',', default_value = "10,20,40,80,160,320,640")]
    levels: Vec<usize>,
}

/// Runs the study.
pub fn run_wp(a: Args) -> Result<(), String> {
    let cfg = work_precision::Config { out: a.out, levels: a.levels };
    let out = work_precision::run(&cfg, &|_, _| {}).map_err(|e| e.to_string())?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
