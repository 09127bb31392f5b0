//! # signorini-exact
//!
//! The Dirichlet bar (`u0 = (1 - x)/2` at rest, clamped at `x = 1`, obstacle
//! at 0 under the end `x = 0`) at points whose values follow by hand:
//!
//! ```
//! use signorini_exact::{BarDirichlet, ExactSolution};
//!
//! let bar = BarDirichlet;
//! // Before the impact (t < 1) the release wave from the free end x = 0 has
//! // reached x = t. Behind it d'Alembert with the even extension of u0 gives
//! // u = (u0(t - x) + u0(x + t))/2 = (1 - t)/2: unstrained, falling at speed 1/2.
//! let f = bar.fields(0.25, 0.5);
//! assert_eq!((f.u, f.ux, f.ut), (0.25, 0.0, -0.5));
//! // Ahead of it the initial state: u = (1 - x)/2, u_x = -1/2, at rest.
//! let f = bar.fields(0.75, 0.5);
//! assert_eq!((f.u, f.ux, f.ut), (0.125, -0.5, 0.0));
//! // The end reaches the obstacle at t = 1 and stays on it until t = 2,
//! // pressed by λ = c² u_x(0, t) = -1/2; no force before.
//! assert_eq!(bar.fields(0.0, 1.5).u, 0.0);
//! assert_eq!((bar.lambda(0.5), bar.lambda(1.5)), (0.0, -0.5));
//! // The energy ∫ (u_t² + c² u_x²)/2 dx of the initial state, 1/8, is kept.
//! assert_eq!(bar.energy(), 0.125);
//! // At t = 1/2 both characteristics x = t and x = 1 - t pass x = 1/2.
//! let mut kinks = Vec::new();
//! bar.kinks(0.5, &mut kinks);
//! assert_eq!(kinks, [0.5]);
//! // Periodic with period 3.
//! assert_eq!(bar.fields(0.25, 3.5), bar.fields(0.25, 0.5));
//! ```
//!
//! Closed-form solutions of the one-dimensional impact benchmarks of docs/theory.md §5,
//! usable on their own (no dependency on any other crate of the workspace).
//!
//! Each benchmark implements [`ExactSolution`]: the displacement `u`, the
//! strain `u_x`, the velocity `u_t`, the contact force `λ(t) = c² u_x(0, t)`
//! (≤ 0), the energy, and — because `u_x`, `u_t` jump across characteristic
//! lines — the positions of those lines at time `t` ([`ExactSolution::kinks`]),
//! so that error integrals can split elements there and stay exact.
//!
//! Benchmarks: [`BarDirichlet`] (`bar-dirichlet`, docs/theory.md §5.1),
//! [`BarNeumannGravity`] (`bar-neumann-gravity`, the falling bar under
//! gravity, docs/theory.md §5.2, built exactly for any data) and
//! [`BarMirrored`] (`bar-mirrored`, the Dirichlet bar mirrored onto `[0, 2]`
//! between two stops, docs/theory.md §5.4).
//!
//! [`Backbone`]: the nonsmooth modes of the bar with a clamped far end
//! (docs/theory.md §11) — for a bar's length, wave speed and gap and an
//! energy, the period, contact time and impacts per period of each family
//! of periodic motions with one contact phase per period, and the motion
//! itself ([`NonsmoothMode`], an [`ExactSolution`]).
//!
//! Besides the bar benchmarks: [`ImpactOscillator`], the forced impact
//! oscillator `m x'' + c x' + k x = F cos Ωt` below a rigid stop with
//! Newton's restitution law — its exact flow between impacts, its period-1
//! orbits with their Floquet multipliers, and its grazing frequencies
//! (see the `oscillator` module docs for the derivations).
//!
//! # Domain of evaluation
//!
//! Every bar benchmark is evaluated on the bar `[0, L]` and at finite times
//! (the falling bar only on `[0, t_max]`, see its docs; the Dirichlet-type
//! bars are periodic, defined at every finite `t`). Outside — a NaN or
//! infinite `t`, a NaN `x`, a point off the bar by more than round-off —
//! the fields and `λ` are NaN, [`ExactSolution::energy_at`] is NaN and the
//! kink list is empty; nothing panics, and no finite value is made up by
//! extrapolating a piece. A point within `1e-9·L` of an end (mesh nodes
//! computed as `i·h`) takes the end's values.
//!
//! Architecture invariant: pure functions of `(x, t)`; no IO, no knowledge of
//! meshes or schemes.

mod backbone;
mod dirichlet;
mod mirrored;
mod neumann;
mod oscillator;

pub use backbone::{Backbone, BackboneError, BackbonePoint, ModeBar, NonsmoothMode};
pub use dirichlet::BarDirichlet;
#[doc(hidden)]
pub use dirichlet::{phase, rem3};
pub use mirrored::BarMirrored;
pub use neumann::{BarNeumannGravity, Event, EventKind, NeumannError};
pub use oscillator::{Admissibility, ImpactOscillator, Multiplier, OscillatorError, OscillatorParams, Period1Orbit, State};

/// Relative slack (in units of `L`) accepted beyond `[0, L]` for a point
/// `x`: within it the point is clamped onto the bar, beyond it the fields
/// are NaN.
pub(crate) const X_SLACK: f64 = 1e-9;

/// `x` on the bar `[0, l]`: clamped onto it if within round-off
/// ([`X_SLACK`]), `None` if farther off or NaN.
#[inline]
pub(crate) fn on_bar(x: f64, l: f64) -> Option<f64> {
    let slack = X_SLACK * l;
    (x >= -slack && x <= l + slack).then(|| x.clamp(0.0, l))
}

/// Fields that are not defined (off the bar, or outside the time domain).
pub(crate) const UNDEFINED: Fields = Fields { u: f64::NAN, ux: f64::NAN, ut: f64::NAN };

/// Point values of an exact solution (one-sided where a kink passes: the
/// values of the piece that contains `x` in its closure, ties broken towards
/// the larger `x`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fields {
    /// Displacement `u(x, t)`.
    pub u: f64,
    /// Strain `u_x(x, t)`.
    pub ux: f64,
    /// Velocity `u_t(x, t)`.
    pub ut: f64,
}

/// The boundary condition at `x = L` of an exact bar solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FarEnd {
    /// `u(L, t) = 0`.
    Clamped,
    /// Not clamped: `u_x(L, t) = 0`, or ([`BarMirrored`]) a stop at `x = L`
    /// that holds it only while in contact. Its `V` norm is the full `H¹` one.
    Free,
}

/// An exact solution of the bar problem `u_tt - c² u_xx = f` on `(0, L)` with
/// Signorini contact at `x = 0` (and, for [`BarMirrored`], a second stop at
/// `x = L`).
pub trait ExactSolution: Send + Sync {
    /// Benchmark name (as used on the command line).
    fn name(&self) -> &str;
    /// Bar length `L`.
    fn length(&self) -> f64;
    /// Wave speed `c`.
    fn wave_speed(&self) -> f64 {
        1.0
    }
    /// Condition at `x = L`.
    fn far_end(&self) -> FarEnd;
    /// Obstacle position `g` (contact when `u(0, t) = g`).
    fn gap(&self) -> f64 {
        0.0
    }
    /// Uniform body force `f` (constant in space and time) of the problem.
    fn body_force(&self) -> f64 {
        0.0
    }
    /// Polynomial degree of `u(·, t)` in `x` between two kinks.
    fn degree_x(&self) -> usize;
    /// Whether `t` is in the time domain of the solution (see the crate
    /// docs, "Domain of evaluation"): every finite `t` unless the solution
    /// says otherwise.
    fn defined_at(&self, t: f64) -> bool {
        t.is_finite()
    }
    /// `u`, `u_x`, `u_t` at `(x, t)`; NaN off the bar or outside the time
    /// domain.
    fn fields(&self, x: f64, t: f64) -> Fields;
    /// `u(x_i, t)` for many points at one time (implementations hoist the
    /// time-dependent work out of the loop).
    fn u_at(&self, t: f64, xs: &[f64], out: &mut [f64]) {
        for (x, o) in xs.iter().zip(out.iter_mut()) {
            *o = self.fields(*x, t).u;
        }
    }
    /// Contact force `λ(t) = c² u_x(0, t) ≤ 0`, right-continuous in `t`.
    fn lambda(&self, t: f64) -> f64;
    /// Energy `∫ (u_t² + c² u_x²)/2 - f u dx`, conserved.
    fn energy(&self) -> f64;
    /// The energy at time `t`: [`Self::energy`] where `t` is in the time
    /// domain ([`Self::defined_at`]), NaN elsewhere.
    fn energy_at(&self, t: f64) -> f64 {
        if self.defined_at(t) {
            self.energy()
        } else {
            f64::NAN
        }
    }
    /// Positions in `(0, L)` where `u_x` or `u_t` may jump at time `t`,
    /// sorted increasingly, appended to `out` after clearing it. Between two
    /// consecutive kinks `u(·, t)` is a polynomial of degree [`Self::degree_x`].
    fn kinks(&self, t: f64, out: &mut Vec<f64>);
    /// Period in time, when the motion is periodic.
    fn period(&self) -> Option<f64> {
        None
    }
}
