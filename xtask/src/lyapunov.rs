//! `cargo xtask lyapunov`: the largest Lyapunov exponent of the beam scenes
//! and the impact oscillator by Benettin's twin runs, and the
//! predictability horizon (`signorini_studies::lyapunov`, which documents
//! its outputs).

use signorini_studies::lyapunov;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/lyapunov")]
    out: PathBuf,
    /// Beam scenes at their own dt and J, comma-separated (fig2-support, fig2 … fig8, beam-obstacles; default every one).
    #[arg(long, value_delimiter = ',')]
    scenes: Option<Vec<String>>,
    /// Beam scenes run again at every --dts × --elements (default fig2-support).
    #[arg(long, value_delimiter = ',')]
    refine: Option<Vec<String>>,
    /// Time steps of the refinement (s), comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "5e-5,2.5e-5,1e-5", allow_hyphen_values = true)]
    dts: Vec<f64>,
    /// Elements J of the refinement, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "19,38", allow_hyphen_values = true, value_parser = crate::whole)]
    elements: Vec<usize>,
    /// Forcing frequencies of the impact oscillator, comma-separated (default its sweep range 1.6 … 2.2; "none": no oscillator).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    omegas: Option<Vec<String>>,
    /// Relative perturbation of the twin (0 < ε < 1e-3).
    #[arg(long, default_value_t = 1e-10, allow_hyphen_values = true)]
    perturbation: f64,
    /// Forcing periods before the twin starts.
    #[arg(long, default_value_t = 10.0, allow_hyphen_values = true)]
    transient: f64,
    /// Forcing periods measured.
    #[arg(long, default_value_t = 20.0, allow_hyphen_values = true)]
    window: f64,
    /// Renormalisations per forcing period.
    #[arg(long = "per-period", default_value_t = 64, allow_hyphen_values = true, value_parser = crate::whole)]
    per_period: usize,
    /// Batches of the 95 % confidence interval.
    #[arg(long, default_value_t = 10, allow_hyphen_values = true, value_parser = crate::whole)]
    batches: usize,
}

fn list(v: Option<Vec<String>>, default: Vec<String>) -> Vec<String> {
    match v {
        None => default,
        Some(v) if v.iter().all(|s| s.trim() == "none" || s.trim().is_empty()) => Vec::new(),
        Some(v) => v.into_iter().map(|s| s.trim().to_string()).collect(),
    }
}

/// Runs the study.
pub fn run_lyapunov(a: Args) -> Result<(), crate::Failure> {
    let d = lyapunov::Config::default();
    let omegas = match a.omegas {
        None => d.omegas.clone(),
        Some(v) => list(Some(v), Vec::new())
            .iter()
            .map(|s| s.parse::<f64>().map_err(|e| crate::Failure::Input(format!("--omegas {s:?}: {e}; allowed numbers in (0, 100] or none"))))
            .collect::<Result<_, _>>()?,
    };
    let cfg = lyapunov::Config {
        out: a.out,
        scenes: list(a.scenes, d.scenes.clone()),
        refine: list(a.refine, d.refine.clone()),
        dts: a.dts,
        elements: a.elements,
        omegas,
        perturbation: a.perturbation,
        transient: a.transient,
        window: a.window,
        per_period: a.per_period,
        batches: a.batches,
    };
    let out = crate::with_progress_bar(|p| lyapunov::run(&cfg, p))?;
    crate::notes(&out.notes);
    print!("{}", out.report);
    Ok(())
}
