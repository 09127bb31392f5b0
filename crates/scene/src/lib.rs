//! Scene files: TOML descriptions of a bar or beam run.
//!
//! A scene read, validated and instantiated, then stepped: the impact
//! oscillator (restitution 0: Paoli–Schatzman projects the position onto
//! the stop) never passes it.
//!
//! ```
//! use signorini_scene::{Limits, SceneFile};
//!
//! let text = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.0\ndt = 1e-3\nt_end = 10.0\n[forcing]\namplitude = 1.0\nomega = 2.0\n";
//! let scene = SceneFile::parse(text)?.validate_with(&Limits::machine())?;
//! let mut sim = scene.instantiate(None)?;
//! for _ in 0..10_000 {
//!     sim.stepper.step()?;
//!     assert!(sim.stepper.displacement()[sim.tip] <= 0.2 + 1e-12);
//! }
//! // A bad value is refused naming its field and the allowed range.
//! let refused = SceneFile::parse(&text.replace("stop = 0.2", "stop = -1.0"))?.validate_with(&Limits::machine());
//! let Err(e) = refused else { panic!("a stop below the start was accepted") };
//! assert!(e.to_string().starts_with("oscillator.stop"), "{e}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ```toml
//! [bar]                        # or [beam]
//! benchmark = "bar-dirichlet"  # initial data, geometry and exact solution from a benchmark
//! elements = 80
//! mass = "mod"
//! scheme = "newmark-cn"
//! ratio = 10.0                 # dx/dt (or dt = ...)
//! t_end = 3.0
//!
//! [output]
//! every = 1                    # a series row every k steps
//! snapshots_every = 0          # u(x) every k steps (0: none)
//! plots = true
//! ```
//!
//! Without a benchmark a bar gives `length`, `wave_speed`, `far_end`
//! ("clamped" or "free"), `gap`, `body_force`, and `initial_displacement` /
//! `initial_velocity` as a number, an expression in `x` (evalexpr syntax:
//! `0.5 * (1 - x)`, `math::sin(pi * x)`; evaluated in floating point: `1/2`
//! is 0.5) or a table `[[x0, u0], [x1, u1], …]` (piecewise linear, covering
//! the whole `[0, length]`; an `[obstacle]` table the nodes it bounds). Every
//! key is checked: unknown keys are rejected, each value is range-checked
//! with the allowed range in the message, a key that would not act in this
//! scene is refused, and the integrator is built once (so a scene that
//! validates also starts).
//!
//! Several contacts (bar or beam): a list of point stops and/or bounds at
//! every node replace the default contact (the bar's obstacle at x = 0 with
//! `gap`, the beam's tip stops `stops = [g1, g2]`, which are then refused):
//!
//! ```toml
//! [[stop]]            # one table per stop, in contact order
//! x = 0.0             # a mesh node (to 1e-9·L)
//! lo = 0.0            # lower bound (optional; -inf: none)
//! hi = 0.05           # upper bound (optional; at least one finite bound)
//! restitution = 0.5   # ps / moreau-jean (bar), projection (beam) only
//! stiffness = 1e3     # penalty only (bar: scaled units; beam: N/m)
//!
//! [obstacle]          # lo(x) <= u(x) <= hi(x) at every unknown node
//! lo = "-0.1"         # number, expression in x or table (-inf: none)
//! hi = 0.1
//! ```
//!
//! A node with both a stop and the obstacle gets the intersection of their
//! bounds. Contact order (the series' `u_c<i>` columns): the stops as
//! listed, then the obstacle's other nodes by increasing x.
//!
//! A reduced model (docs/theory.md §2.5) in `[bar]` or `[beam]`:
//! `reduce = { modes = 8 }` keeps the 8 lowest fixed-interface modes,
//! `reduce = { cutoff_hz = 200.0 }` every mode up to 200 Hz; the contacts
//! stay physical and massless (the bar needs a massless-node mass: mod,
//! mod1-3, transfer, singular; the beam's are made massless by the method).
//! The full field is reconstructed for the outputs.
//!
//! The impact oscillator is a third kind of scene, with its load:
//!
//! ```toml
//! [oscillator]        # m x'' + c x' + k x = F(t), x <= stop, c = 2 ζ sqrt(k m)
//! mass = 1.0
//! stiffness = 1.0
//! damping_ratio = 0.05
//! stop = 0.2
//! restitution = 0.8
//! dt = 1e-3
//! t_end = 100.0
//! [forcing]           # F cos(Ω t) by default
//! amplitude = 1.0
//! omega = 2.0
//! ```
//!
//! Excitations (`[forcing]`, the beam's `[support]`, a `[load]` on a bar or a
//! beam) take any time profile: [`crate::excitation`]. `[output]` may ask for
//! `impacts`, `poincare`, `summary` after a `transient` (forcing periods).
//!
//! A validated [`Scene`] is turned into a running simulation one way for
//! every front end: [`Scene::instantiate`].

mod bar;
mod beam;
mod contacts;
mod error;
pub mod excitation;
mod facts;
mod field;
mod instantiate;
mod limits;
mod oscillator;
pub mod presets;
mod report;
mod scene;
mod schema;
mod validate;

pub(crate) use contacts::{contact_error, contact_set, contacts_table, softest_stop, stiff_stop, too_soft, KeyRules, NodeMesh};
pub use contacts::{ContactSet, Site, NODE_TOLERANCE};
pub use error::{field, SceneError};
pub(crate) use error::{finite, positive};
pub use facts::{ExactCurve, Facts, Kind, Norms, Plot, SnapshotNodes};
pub use field::{real_literals, InitialField, MAX_EXPRESSION_CHARS};
pub use instantiate::{BuildError, Lift, Reads, Ready, Simulation};
pub use limits::{bytes, contact_memory, memory_estimate, Limits};
pub(crate) use limits::{contacts_fit, fits};
pub use report::{
    check_report, energy_warning, event_probe, free_space, io_reason, output_estimate, output_estimate_note, plot_every, sig12, sig6, CheckReport, EventProbe, ProbeEnd, EXACT_CURVE_SEGMENTS,
    FORCE_MAP_BINS, MAX_FORCE_LINES, SCATTER_POINTS,
};
pub use scene::{BarRun, Scene};
pub(crate) use schema::reduce_error;
pub use schema::{BarToml, BeamToml, FieldToml, ObstacleToml, OscillatorToml, OutputToml, ReduceToml, SceneFile, StopToml, DEFAULT_ENERGY_WARN};
pub(crate) use validate::{extreme_key, horizon, scheme_error};

pub(crate) use bar::validate_bar;
pub(crate) use beam::validate_beam;
