//! `cargo xtask courant1`: the central difference with the lumped mass at
//! dx/dt = c against the exact solutions, node by node
//! (`signorini_studies::courant1`, which documents its outputs).

use signorini_studies::courant1;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/courant1")]
    out: PathBuf,
    /// Benchmarks, comma-separated (default: all four).
    #[arg(long, value_delimiter = ',')]
    benchmarks: Vec<String>,
    /// Numbers of elements m, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "10,20,40,80", allow_hyphen_values = true, value_parser = crate::whole)]
    levels: Vec<usize>,
    /// Horizon (default: 6 for the Dirichlet and mirrored bars, 16 for the falling bars).
    #[arg(long = "t-end", allow_hyphen_values = true)]
    t_end: Option<f64>,
}

/// Runs the study.
pub fn run_courant1(a: Args) -> Result<(), crate::Failure> {
    let mut cfg = courant1::Config { out: a.out, levels: a.levels, t_end: a.t_end, ..Default::default() };
    if !a.benchmarks.is_empty() {
        cfg.benchmarks = a.benchmarks.iter().map(|b| signorini_studies::convergence::parse_benchmark(b.trim())).collect::<Result<Vec<_>, _>>()?;
    }
    let out = courant1::run(&cfg, &|_, _| {})?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
