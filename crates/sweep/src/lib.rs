//! Parameter sweeps of a scene (`signorini sweep`) and the merge of their
//! shards (`signorini merge`).
//!
//! Three forcing frequencies of the impact oscillator, each run sampled at
//! the forcing period:
//!
//! ```
//! use signorini_scene::Limits;
//! use signorini_sweep::{run, NoProgress, Sweep, SweepOptions};
//!
//! let scene = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.8\ndt = 1e-3\nt_end = 1.0\n[forcing]\namplitude = 1.0\nomega = 2.0\n";
//! let mut opts = SweepOptions::new("forcing.omega", 1.5, 2.5, 3);
//! (opts.transient, opts.record) = (5.0, 5.0);
//! let sweep = Sweep::new(scene, "oscillator.toml", None, opts, Limits::machine())?;
//! let dir = std::env::temp_dir().join(format!("signorini-doctest-sweep-{}", std::process::id()));
//! let _ = std::fs::remove_dir_all(&dir);
//! let report = run(&sweep, &dir, &NoProgress)?;
//! assert_eq!((report.runs, report.failed), (3, 0));
//! // One summary row per run, and its Poincaré samples at t = 5T, 6T, …, 10T.
//! let summary = std::fs::read_to_string(dir.join("summary.csv"))?;
//! assert_eq!(summary.lines().count(), 1 + 3);
//! assert_eq!(std::fs::read_to_string(dir.join("sweep.csv"))?.lines().count(), 1 + 3 * 6);
//! std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A sweep runs one scene many times, each with one numeric field — named by
//! its dotted path in the scene document, `forcing.omega`, `support.amplitude`,
//! `stop.0.hi` — set to a value of a linear or logarithmic grid, and reads
//! each run as vibro-impact papers do: stroboscopic (Poincaré) samples at the
//! forcing period after a transient, the impacts, and summary statistics.
//! The horizon of every run is `transient + record` forcing periods (rounded
//! to whole steps), replacing the scene's `t_end`.
//!
//! Output folder (a contract; columns only ever added):
//! * `sweep.csv` — `param,run,t,displacement,velocity,phase`: one row per
//!   Poincaré sample at `t = (k + phase/2π)·2π/Ω` (k integer, time from the
//!   run's start, `phase` the section's forcing phase, `--phase`, default 0)
//!   in the record window: the oscillator's displacement, the beam's tip,
//!   the bar's contact end;
//! * `summary.csv` — one row per run: `param,run,` then the statistics of
//!   [`signorini_run::vibro`] (`impacts,impacts_per_period,…,period`), then
//!   `steps,status` (`ok`, or why the run stopped: a blow-up keeps the rows
//!   of the sweep going);
//! * `impacts.csv` — `param,run,stop,t,phase,velocity,impulse,duration`: the
//!   impacts of the record window (the data of the impact map);
//! * `bifurcation.svg` (Poincaré displacement against the parameter) and
//!   `impact_map.svg` (pre-impact velocity against forcing phase);
//! * `sweep.toml` — the manifest (written and read with the toml crate): the sweep's id (a hash of the scene text
//!   and every option that changes a number), its options, and with
//!   `--shard I/N` the shard.
//!
//! Rows are written in run order, whatever the number of threads: runs go
//! in batches, each batch in parallel, and a batch's rows are written in
//! order when all of it is done, so the files always hold a whole prefix
//! of runs (`--resume` continues after it). `--shard I/N` runs the I-th of
//! N contiguous blocks of runs; [`merge`] concatenates the shards' files in
//! order into exactly the files of the unsharded sweep.

mod error;
mod lockstep;
mod options;
mod output;
mod run;
mod setup;
mod simulate;

pub use error::{Error, SweepError};
pub use lockstep::{simulate_lockstep, LANES};
pub use options::{grid, set_path, Axis, SweepOptions};
pub use output::{merge, summary_header, IMPACT_COLUMNS, SWEEP_COLUMNS, SWEEP_FILES};
pub use run::{run, NoProgress, Progress, SweepReport};
#[doc(hidden)]
pub use setup::Manifest;
pub use setup::Sweep;
pub use signorini_run::text::num;
pub use simulate::{simulate, Plan, RunRows};
