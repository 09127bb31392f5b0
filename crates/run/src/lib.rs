//! # signorini-run
//!
//! The Dirichlet bar benchmark run to one period with `newmark-cn` and the
//! `mod` mass, watched by the exact error norms and by an observer of one's
//! own:
//!
//! ```
//! use signorini_fem::BarMass;
//! use signorini_run::{run, Benchmark, NormObserver, Observer, RunConfig, RunError, Sample};
//! use signorini_schemes::SchemeSpec;
//!
//! /// Records the lowest position of the contact end and counts the levels.
//! struct LowestEnd {
//!     min: f64,
//!     levels: usize,
//! }
//! impl Observer for LowestEnd {
//!     fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
//!         self.min = self.min.min(s.u[0]);
//!         self.levels += 1;
//!         Ok(())
//!     }
//! }
//!
//! let bench = Benchmark::BarDirichlet;
//! let exact = bench.exact(3.0)?;
//! // 10 elements, dx/dt = 10, T = 3 (approach, contact on [1, 2), flight).
//! let (m, dt) = (10, 0.01);
//! let problem = bench.problem(exact.as_ref(), m, BarMass::Mod)?;
//! let mut stepper = "newmark-cn".parse::<SchemeSpec>()?.build(problem.dynamics(), dt, &problem.initial)?;
//! let cfg = RunConfig::new(dt, 3.0)?;
//! let mut norms = NormObserver::new(exact.as_ref(), m, problem.vnorm(), dt);
//! let mut end = LowestEnd { min: f64::INFINITY, levels: 0 };
//! let summary = run(stepper.as_mut(), &problem.initial.u, &cfg, &mut [&mut norms, &mut end])?;
//!
//! assert_eq!(summary.steps, 300);
//! assert_eq!(end.levels, 301); // t_0, then every step
//! assert!(end.min >= 0.0); // never through the obstacle at 0
//! // In contact about the exact solution's 100 steps of [1, 2).
//! assert!((90..=110).contains(&summary.contact_steps), "{}", summary.contact_steps);
//! // The L∞(0,T; L²) error of the displacement: the first row of the
//! // convergence study's data/reference/bar-dirichlet/newmark-cn_mod.csv.
//! let report = norms.report();
//! assert!((report.linf_l2_u - 5.3915971104e-2).abs() < 1e-12, "{}", report.linf_l2_u);
//! # Ok::<(), RunError>(())
//! ```
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

pub use cancel::Cancel;
pub use energy::{EnergyExceeded, EnergyGrowth, EnergyMonitor};
pub use lockstep::{run_lockstep, LaneEnd, LockstepRun};
pub use observers::{active_code, History, NormObserver, Record, RowSink, SeriesColumns, SeriesWriter};
pub use problem::{BarProblem, Benchmark, Stop};
pub use runner::{run, Observer, RunConfig, RunError, RunSummary, Sample};
pub use vibro::{forcing_phase, response_period, Crossing, Impact, ImpactObserver, ImpactStats, Piece, PoincareObserver, PoincarePoint, Summary, Vibro, VibroConfig, WindowObserver};
