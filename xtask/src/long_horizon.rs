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
    #[arg(long, value_delimiter = ',', default_value = "20,40,80", allow_hyphen_values = true, value_parser = crate::whole)]
    levels: Vec<usize>,
    /// dx/dt.
    #[arg(long, default_value_t = 10.0, allow_hyphen_values = true)]
    ratio: f64,
    /// Horizon (three time units a period).
    #[arg(long = "t-end", default_value_t = 30.0, allow_hyphen_values = true)]
    t_end: f64,
    /// Leave out the energy-growth table.
    #[arg(long)]
    no_energy: bool,
    /// Energy-growth table: scheme:mass pairs, comma-separated (default: newmark-cn and ps-e0 with std, lumped, mod, mod3; ps-e1 with std, mod3; moreau-jean with std, lumped; hybrid with mod, mod3).
    #[arg(long)]
    energy_runs: Vec<String>,
    /// Energy-growth table: every named scheme with every mass it accepts (instead of the default runs).
    #[arg(long, conflicts_with = "energy_runs")]
    energy_all: bool,
    /// Energy-growth table: dx/dt values, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1,2,10", allow_hyphen_values = true)]
    energy_ratios: Vec<f64>,
    /// Energy-growth table: number of elements.
    #[arg(long, default_value_t = 100, allow_hyphen_values = true, value_parser = crate::whole)]
    energy_m: usize,
    /// Energy-growth table: horizon.
    #[arg(long = "energy-t-end", default_value_t = 1e4, allow_hyphen_values = true)]
    energy_t_end: f64,
}

/// Runs the study.
pub fn run_long_horizon(a: Args) -> Result<(), crate::Failure> {
    let mut cfg = long_horizon::Config { out: a.out, levels: a.levels, ratio: a.ratio, t_end: a.t_end, ..Default::default() };
    if !a.runs.is_empty() {
        cfg.runs = long_horizon::parse_runs(&a.runs)?;
    }
    cfg.energy = if a.no_energy {
        None
    } else {
        let mut e = long_horizon::EnergyTable { ratios: a.energy_ratios, m: a.energy_m, t_end: a.energy_t_end, ..Default::default() };
        if a.energy_all {
            e.runs = long_horizon::EnergyTable::all_runs();
        } else if !a.energy_runs.is_empty() {
            e.runs = long_horizon::parse_runs(&a.energy_runs).map_err(|e| crate::Failure::Input(e.to_string().replace("--runs", "--energy-runs")))?;
        }
        Some(e)
    };
    let out = crate::with_progress_bar(|p| long_horizon::run(&cfg, p))?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
