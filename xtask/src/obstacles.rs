//! `cargo xtask beam-obstacles`: the beam between obstacles along its whole
//! length (`signorini_studies::obstacles`, which documents its outputs).

use signorini_studies::obstacles;
use std::path::PathBuf;

/// Arguments of `cargo xtask beam-obstacles`.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/beam-obstacles")]
    out: PathBuf,
    /// Obstacles at -g and +g (m) along the whole beam.
    #[arg(long, default_value_t = 0.05, allow_hyphen_values = true)]
    gap: f64,
    /// β of the β-scheme (>= 1/4: unconditionally stable).
    #[arg(long, default_value_t = 0.25, allow_hyphen_values = true)]
    beta: f64,
    /// Horizon (s): long enough for several impacts, short enough that the
    /// vibro-impact motion has not become sensitive to rounding.
    #[arg(long = "t-end", default_value_t = 0.2, allow_hyphen_values = true)]
    t_end: f64,
    /// Time steps of the dt study (s), J fixed at --j; each must divide the
    /// first (coarsest), the reference is the last divided by 4.
    #[arg(long, value_delimiter = ',', default_value = "1e-4,5e-5,2.5e-5,1.25e-5,6.25e-6", allow_hyphen_values = true)]
    dts: Vec<f64>,
    /// Elements of the dt study.
    #[arg(long, default_value_t = 20, allow_hyphen_values = true, value_parser = crate::whole)]
    j: usize,
    /// Meshes of the J study (each a multiple of the first), dt fixed at
    /// --j-dt; the reference is the last times 2.
    #[arg(long, value_delimiter = ',', default_value = "5,10,20,40,80", allow_hyphen_values = true, value_parser = crate::whole)]
    js: Vec<usize>,
    /// Time step of the J study (s).
    #[arg(long = "j-dt", default_value_t = 1e-5, allow_hyphen_values = true)]
    j_dt: f64,
}

/// Runs the study.
pub fn run_obstacles(a: Args) -> Result<(), crate::Failure> {
    let cfg = obstacles::Config { out: a.out, gap: a.gap, beta: a.beta, t_end: a.t_end, dts: a.dts, j: a.j, js: a.js, j_dt: a.j_dt };
    let out = obstacles::run(&cfg, &|_, _| {})?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
