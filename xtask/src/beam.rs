//! `cargo xtask beam`: the beam between two stops (Dumont & Paoli;
//! `signorini_studies::beam`, which documents its outputs).

use signorini_studies::beam;
use std::path::PathBuf;

/// Arguments of `cargo xtask beam`.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/beam")]
    out: PathBuf,
    /// Scenes to run, comma-separated (fig2 … fig8).
    #[arg(long, value_delimiter = ',', default_value = "fig2,fig3,fig4,fig5,fig6,fig7,fig8")]
    scenes: Vec<String>,
    /// Run conditionally stable scenes even beyond their stability limit.
    #[arg(long)]
    force: bool,
    /// Time steps (s) of the penalty study (`penalty.csv`), comma-separated;
    /// the paper's are 5e-6, 1e-6, 5e-7 (runs the figures already made are
    /// reused).
    #[arg(long = "penalty-dts", value_delimiter = ',', default_value = "5e-6,1e-6,5e-7", allow_hyphen_values = true)]
    penalty_dts: Vec<f64>,
}

/// Runs the study.
pub fn run_beam(a: Args) -> Result<(), crate::Failure> {
    let cfg = beam::Config { out: a.out, scenes: a.scenes, force: a.force, penalty_dts: a.penalty_dts };
    let out = beam::run(&cfg, &|_, _| {})?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
