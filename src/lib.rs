//! # signorini
//!
//! Facade of the signorini workspace: re-exports the crates so a user can
//! depend on one name. Each crate is also usable alone:
//!
//! * [`fem`]: P1–P3 bar and Hermite beam matrices with every mass treatment, banded LDLᵀ;
//! * [`contact`]: the closed-form contact projection;
//! * [`exact`]: exact benchmark solutions;
//! * [`norms`]: exact error norms accumulated while stepping;
//! * [`reduce`]: reduced models with a massless contact boundary;
//! * [`schemes`]: the time integrators;
//! * [`run`]: problems, the time loop, observers and convergence studies;
//! * [`plot`]: SVG line charts and heat maps;
//! * [`scene`]: the TOML scene format, its validation and one instantiation;
//! * [`sweep`]: parameter sweeps (grid, manifest, lockstep batches, merge);
//! * [`orbits`]: periodic orbits on the exact flow (shooting, Floquet multipliers, continuation, bifurcations);
//! * [`studies`]: every study as a library function.
//!
//! Every library crate of the workspace is here; the `signorini` command
//! (`signorini-cli`) is a front end on them, not a library of the facade.
//!
//! The Dirichlet bar's exact solution and a run of Newmark-CN against it:
//!
//! ```
//! use signorini::exact::ExactSolution;
//! use signorini::run::Benchmark;
//!
//! let exact = Benchmark::BarDirichlet.exact(3.0)?;
//! // Free at t = 0.5, in contact at t = 1.5 with the force −1/2 (docs/theory.md §5.1).
//! assert_eq!((exact.lambda(0.5), exact.lambda(1.5)), (0.0, -0.5));
//! let scheme: signorini::schemes::SchemeSpec = "newmark-cn".parse()?;
//! assert_eq!(scheme.to_string(), "newmark-cn");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub use signorini_contact as contact;
pub use signorini_exact as exact;
pub use signorini_fem as fem;
pub use signorini_norms as norms;
pub use signorini_orbits as orbits;
pub use signorini_plot as plot;
pub use signorini_reduce as reduce;
pub use signorini_run as run;
pub use signorini_scene as scene;
pub use signorini_schemes as schemes;
pub use signorini_studies as studies;
pub use signorini_sweep as sweep;
