//! # signorini-run
//!
//! The layer between the numerical crates and the command-line tools:
//!
//! * [`problem`]: a P1 bar problem (mesh, mass treatment, obstacle, load,
//!   initial data) and the built-in [`Benchmark`]s with exact solutions;
//! * [`runner`]: the time loop ([`run`]) and the [`Observer`] trait — norms,
//!   CSV series and progress are observers, so nothing is stored unless an
//!   observer stores it; blow-ups stop the run with the step and time;
//! * [`lockstep`]: the time loop of a batch of runs sharing one step
//!   matrix ([`run_lockstep`]), lane by lane the samples of [`run`];
//! * [`observers`]: [`NormObserver`] (exact error norms while stepping) and
//!   [`SeriesWriter`] (CSV time series, flushed as it goes);
//! * [`beam`]: the beam between two stops (the pipe of Dumont & Paoli, its
//!   scenes, the exact stability limit);
//! * [`analysis`]: contact events and phase errors from recorded histories;
//! * [`vibro`]: vibro-impact analysis observers — impacts per contact
//!   ([`ImpactObserver`]: time, forcing phase, pre-impact velocity,
//!   impulse), the stroboscopic Poincaré section ([`PoincareObserver`]) and
//!   the window statistics of a run ([`Summary`]), built together from a
//!   [`VibroConfig`];
//! * [`reduced`]: a problem replaced by its massless-boundary reduction
//!   (docs/theory.md §2.5) and the observer adapter that reconstructs the
//!   full field only where an observer needs it;
//! * [`chaos`]: the largest Lyapunov exponent by Benettin's twin runs
//!   over any [`chaos::Flow`] (a stepper through its state), and the
//!   predictability horizon;
//! * [`cancel`]: the [`Cancel`] token that stops a run or a sweep cleanly;
//! * [`stats`]: batch-means confidence intervals (Student-t quantiles);
//! * [`study`]: convergence sweeps over mesh levels at a fixed `dx/dt`, run
//!   in parallel, and their rates.
//!
//! Architecture invariant: writes only to the `std::io::Write` it is given;
//! opening files and terminals is the CLI's and xtask's job.

pub mod analysis;
pub mod beam;
pub mod cancel;
pub mod chaos;
pub mod energy;
pub mod lockstep;
pub mod observers;
pub mod oscillator;
pub mod problem;
pub mod reduced;
pub mod runner;
pub mod stats;
pub mod study;
pub mod text;
pub mod vibro;

pub use observers::{active_code, History, NormObserver, Record, RowSink, SeriesColumns, SeriesWriter};
pub use cancel::Cancel;
pub use lockstep::{run_lockstep, LaneEnd, LockstepRun};
pub use energy::{EnergyExceeded, EnergyGrowth, EnergyMonitor};
pub use problem::{BarProblem, Benchmark, Stop};
pub use runner::{run, Observer, RunConfig, RunError, RunSummary, Sample};
pub use vibro::{forcing_phase, response_period, Crossing, Impact, ImpactObserver, ImpactStats, Piece, PoincareObserver, PoincarePoint, Summary, Vibro, VibroConfig, WindowObserver};
