//! `cargo xtask <study>`: the reproducible studies of signorini. Each study
//! lives in `signorini_studies::<study>` (Config, run, Output with one table
//! per CSV); this binary only turns the flags into its `Config`, draws a
//! progress bar where the study has one, and prints the report and notes.
//!
//! * `convergence`: sweep dx at a fixed dx/dt for each (scheme, mass) pair;
//!   write one CSV error curve per pair, `rates.csv`, `oscillation.csv`,
//!   log-log plots, and print the rates as a Markdown table. Defaults: the
//!   papers' study.
//! * `weighted`: the weighted-mass-redistribution study (mod1/mod2/mod3 ×
//!   newmark-cn, backward-euler, ps-e1, hybrid): figure runs, phase errors,
//!   energy loss and convergence.
//! * `work-precision`: error against wall time; `stress`: long runs at
//!   extreme dx/dt with random data.
//! * `beam`: the beam between two stops — the paper's figures 2–8, wall
//!   times against the paper's, the exact stability limit, self-convergence.
//! * `lyapunov`: the largest Lyapunov exponent of the beam scenes and the
//!   impact oscillator (Benettin's twin runs), the predictability horizon.
//! * `beam-statistics`: statistics of the beam over long windows with
//!   batch-means intervals against dt and J (which converge).
//! * `fuzz`: the scene reader and validator on generated and mutated scenes.
//! * `docs`: the user guide's generated tables, from `data/reference`,
//!   and ARCHITECTURE.md's crate graph, from `cargo tree` (`--check`: fail
//!   when a committed one is out of date, or when the modules of
//!   signorini-schemes, -sweep or -fuzz name each other in a circle).
//! * `test`: every test, and the guide's strict build.

#[doc(hidden)]
pub mod crate_graph;
#[doc(hidden)]
pub mod docs;
#[doc(hidden)]
pub mod fuzz;
#[doc(hidden)]
pub mod module_graph;
#[doc(hidden)]
pub mod py_studies;
#[doc(hidden)]
pub mod pytest;
#[doc(hidden)]
pub mod scene_keys;
#[doc(hidden)]
pub mod studies;
#[doc(hidden)]
pub mod unit_tests;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "cargo xtask", about = "Reproducible studies of signorini")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

/// The commands that are not studies (the studies' commands are built
/// from their `Config`s, [`studies`]).
#[derive(Subcommand)]
enum Cmd {
    /// Every test: the Rust workspace's, then the Python package (built with maturin into target/py-venv) with pytest, then the user guide (generated tables checked, mkdocs build --strict).
    Test(pytest::Args),
    /// Fuzz the scene reader and validator: no panic, typed errors naming a field.
    Fuzz(fuzz::Args),
    /// The user guide's generated tables (docs/generated/, the README's headline) from data/reference, the scene key reference from the scene schema (crates/scene), and ARCHITECTURE.md's crate graph from `cargo tree`; --check compares instead of writing.
    Docs(docs::Args),
}

/// `cargo xtask`: the commands, their flags, the exit status (src/main.rs
/// calls it; the library exists so that the tests do not compile this code
/// a second time as a test harness).
pub fn main() -> ExitCode {
    let entries = studies::entries();
    let mut cmd = Cli::command();
    for e in &entries {
        cmd = cmd.subcommand(e.command());
    }
    let m = cmd.get_matches();
    let result = match m.subcommand() {
        Some((name, sub)) if entries.iter().any(|e| e.name() == name) => entries.iter().find(|e| e.name() == name).map_or(Err(Failure::Reported), |e| e.run(sub)),
        _ => match Cli::from_arg_matches(&m) {
            Ok(cli) => match cli.cmd {
                Cmd::Test(a) => pytest::run_tests(a),
                Cmd::Fuzz(a) => fuzz::run_fuzz(a).map_err(Failure::from),
                Cmd::Docs(a) => docs::run_docs(a).map_err(Failure::from),
            },
            Err(e) => e.exit(),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // Bad input exits 2, as clap's own errors and `signorini` do.
        Err(Failure::Input(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        Err(Failure::Failed(e)) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
        Err(Failure::Reported) => ExitCode::FAILURE,
    }
}

/// Why a `cargo xtask` command stopped: bad input (a flag out of its range,
/// exit status 2, as clap's own errors and the `signorini` command) or a
/// failure of the work itself (exit status 1).
#[derive(Debug)]
pub enum Failure {
    /// Bad input; the message names the flag and what is allowed.
    Input(String),
    /// A run, a file or a tool failed.
    Failed(String),
    /// A failure already reported on the terminal (`cargo xtask test`,
    /// whose verdict must stay its last line).
    Reported,
}

impl From<String> for Failure {
    /// The commands that are not studies (test, fuzz, docs) fail with text.
    fn from(e: String) -> Self {
        Failure::Failed(e)
    }
}

/// Prints a study's notes and warnings on stderr.
pub fn notes(notes: &[String]) {
    for n in notes {
        eprintln!("{n}");
    }
}

/// Runs `f` with a progress bar on a terminal (hidden otherwise) driven by
/// its `progress(done, total)` callback.
pub fn with_progress_bar<T>(f: impl FnOnce(&(dyn Fn(u64, u64) + Sync)) -> T) -> T {
    let bar = ProgressBar::with_draw_target(Some(0), if std::io::stderr().is_terminal() { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() });
    bar.set_style(ProgressStyle::with_template("{bar:40} {pos}/{len} runs  {elapsed}").unwrap_or_else(|_| ProgressStyle::default_bar()));
    let r = f(&|done, total| {
        bar.set_length(total);
        bar.set_position(done);
    });
    bar.finish_and_clear();
    r
}
