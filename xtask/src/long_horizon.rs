//! `cargo xtask long-horizon`: the Dirichlet bar over many periods, every
//! mass, error against time and impact phase (`signorini_studies::long_horizon`,
//! which documents its outputs).

use signorini_studies::long_horizon;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/long-horizon")]
    out: PathBuf,
    /// scheme:mass pairs, comma-separated (default: ps-e0 with every mass, moreau-jean with std and lumped).
    #[arg(long)]
    runs: Vec<String>,
    /// Numbers of elements m, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "20,40,80")]
    levels: Vec<usize>,
    /// dx/dt.
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    ratio: f64,
    /// Horizon (three time units a period).
    #[arg(long = "t-end", default_value_t = 30.0, allow_negative_numbers = true)]
    t_end: f64,
}

/// Runs the study.
pub fn run_long_horizon(a: Args) -> Result<(), String> {
    let mut cfg = long_horizon::Config { out: a.out, levels: a.levels, ratio: a.ratio, t_end: a.t_end, ..Default::default() };
    if !a.runs.is_empty() {
        cfg.runs = long_horizon::parse_runs(&a.runs).map_err(|e| e.to_string())?;
    }
    let out = long_horizon::run(&cfg, &|_, _| {}).map_err(|e| e.to_string())?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
