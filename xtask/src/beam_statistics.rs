//! `cargo xtask beam-statistics`: statistics of the beam scenes over a long
//! window with 95 % batch-means intervals, against dt and J
//! (`signorini_studies::beam_statistics`, which documents its outputs).

use signorini_studies::beam_statistics;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/beam-statistics")]
    out: PathBuf,
    /// Scenes, comma-separated (fig2-support, beam-obstacles).
    #[arg(long, value_delimiter = ',', default_value = "fig2-support")]
    scenes: Vec<String>,
    /// Time steps (s), comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "5e-5,2.5e-5,1e-5", allow_hyphen_values = true)]
    dts: Vec<f64>,
    /// Elements J, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "19,38", allow_hyphen_values = true, value_parser = crate::whole)]
    elements: Vec<usize>,
    /// Forcing periods before the window.
    #[arg(long, default_value_t = 10.0, allow_hyphen_values = true)]
    transient: f64,
    /// Forcing periods of the window (at least 10).
    #[arg(long, default_value_t = 320.0, allow_hyphen_values = true)]
    window: f64,
    /// Batches of the 95 % intervals (at least 10).
    #[arg(long, default_value_t = 20, allow_hyphen_values = true, value_parser = crate::whole)]
    batches: usize,
    /// Active runs closer than this (s) form one contact episode.
    #[arg(long = "episode-gap", default_value_t = 5e-3, allow_hyphen_values = true)]
    episode_gap: f64,
}

/// Runs the study.
pub fn run_beam_statistics(a: Args) -> Result<(), crate::Failure> {
    let cfg = beam_statistics::Config { out: a.out, scenes: a.scenes, dts: a.dts, elements: a.elements, transient: a.transient, window: a.window, batches: a.batches, episode_gap: a.episode_gap };
    let out = crate::with_progress_bar(|p| beam_statistics::run(&cfg, p))?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
