//! `cargo xtask oscillator`: the impact oscillator scene against its exact
//! period-1 orbits and its grazing frequency (`signorini_studies::oscillator`,
//! which documents its outputs).

use signorini_studies::oscillator;
use std::path::PathBuf;

/// Arguments of `cargo xtask oscillator`.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/oscillator")]
    out: PathBuf,
    /// Forcing frequencies (the scene's stable period-1 range).
    #[arg(long, value_delimiter = ',', default_value = "1.6,1.7,1.8,1.9,2.0,2.1,2.2", allow_hyphen_values = true)]
    omegas: Vec<f64>,
    /// Time steps.
    #[arg(long, value_delimiter = ',', default_value = "2e-3,1e-3,5e-4,2.5e-4,1.25e-4,6.25e-5,3.125e-5,1.5625e-5,7.8125e-6", allow_hyphen_values = true)]
    dts: Vec<f64>,
    /// Forcing periods before the record window.
    #[arg(long, default_value_t = 60.0, allow_hyphen_values = true)]
    transient: f64,
    /// Forcing periods recorded.
    #[arg(long, default_value_t = 10.0, allow_hyphen_values = true)]
    record: f64,
}

/// `cargo xtask oscillator`.
pub fn run_oscillator(a: Args) -> Result<(), crate::Failure> {
    let cfg = oscillator::Config { out: a.out, omegas: a.omegas, dts: a.dts, transient: a.transient, record: a.record };
    let out = oscillator::run(&cfg, &|_, _| {})?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
