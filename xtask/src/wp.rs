//! `cargo xtask work-precision`: error reached against wall time, per scheme
//! and mass, and the accuracy–cost frontier (Courant one, P2/P3, reduced
//! models, the beam) (`signorini_studies::work_precision`, which documents
//! its outputs).

use signorini_studies::work_precision;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/work-precision")]
    out: PathBuf,
    /// Levels m.
    #[arg(long, value_delimiter = ',', default_value = "10,20,40,80,160,320,640", allow_hyphen_values = true, value_parser = crate::whole)]
    levels: Vec<usize>,
    /// Element degrees beyond P1 (2, 3); `--degrees ''` for none.
    #[arg(long, default_value = "2,3", allow_hyphen_values = true)]
    degrees: String,
    /// Kept modes of the reduced bar and beam models; `--modes ''` for none.
    #[arg(long, default_value = "2,4,8,16", allow_hyphen_values = true)]
    modes: String,
    /// Time steps of the beam rows (s); `--beam-dts ''` for no beam rows.
    #[arg(long, default_value = "1e-5,2.5e-5,5e-5,1e-4,2.5e-4,5e-4", allow_hyphen_values = true)]
    beam_dts: String,
    /// The beam reference's time step (s).
    #[arg(long, default_value_t = 2.5e-7, allow_hyphen_values = true)]
    beam_ref_dt: f64,
    /// The beam's error window [0, w] (s).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true)]
    beam_window: f64,
    /// The beam's horizon (s).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    beam_t_end: f64,
    /// Time steps of the beam's impact-power rows (s); `--beam-stat-dts ''` for none.
    #[arg(long, default_value = "5e-5,2.5e-5,1e-5", allow_hyphen_values = true)]
    beam_stat_dts: String,
    /// The impact power's reference step (s).
    #[arg(long, default_value_t = 5e-6, allow_hyphen_values = true)]
    beam_stat_ref_dt: f64,
    /// The impact power's window (forcing periods).
    #[arg(long, default_value_t = 320.0, allow_hyphen_values = true)]
    beam_stat_window: f64,
    /// The beam rows' reference: fine-step (the projection scheme at
    /// --beam-ref-dt) or event-driven (the exact semi-discrete solution,
    /// sampled at the largest step dividing every --beam-dts). The bar rows
    /// are always measured against their closed forms (what `convergence
    /// --reference exact` means); the beam has none, hence fine-step where
    /// convergence says exact, and `exact` is refused.
    #[arg(long, default_value = "fine-step")]
    reference: String,
    /// Timed runs per configuration, in [1, 100]: the cost is their median,
    /// and two configurations whose ranges [min, max] overlap are a tie.
    #[arg(long, default_value_t = 5, allow_hyphen_values = true, value_parser = crate::whole)]
    repeats: usize,
}

/// A comma-separated list of `flag`, empty for none (`--degrees ''`).
fn list<T: std::str::FromStr>(flag: &str, s: &str) -> Result<Vec<T>, crate::Failure> {
    s.split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|p| p.parse().map_err(|_| crate::Failure::Input(format!("{flag} {p:?}: allowed a comma-separated list of numbers, or '' for none"))))
        .collect()
}

/// Runs the study.
pub fn run_wp(a: Args) -> Result<(), crate::Failure> {
    let cfg = work_precision::Config {
        out: a.out,
        levels: a.levels,
        degrees: list("--degrees", &a.degrees)?,
        modes: list("--modes", &a.modes)?,
        beam_dts: list("--beam-dts", &a.beam_dts)?,
        beam_ref_dt: a.beam_ref_dt,
        beam_window: a.beam_window,
        beam_t_end: a.beam_t_end,
        beam_stat_dts: list("--beam-stat-dts", &a.beam_stat_dts)?,
        beam_stat_ref_dt: a.beam_stat_ref_dt,
        beam_stat_window: a.beam_stat_window,
        reference: a.reference.parse::<work_precision::BeamReference>()?,
        repeats: a.repeats,
    };
    let out = work_precision::run(&cfg, &|_, _| {})?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
