//! Benchmark `bar-neumann-gravity` (docs/theory.md §5.2): an
//! elastic bar `[0, L]` (wave speed `c = 1`, density 1) released from rest
//! at height `u0 > 0` above a rigid floor, falling under gravity `g > 0`,
//! bouncing on the floor at its lower end `x = 0` and free at `x = L`:
//!
//! ```text
//! u_tt − u_xx = −g  on (0, L) × (0, T),
//! 0 ≤ u(0, t)  ⊥  λ(t) = u_x(0, t) ≤ 0,      u_x(L, t) = 0,
//! u(x, 0) = u0,   u_t(x, 0) = 0.
//! ```
//!
//! The body force is `f = −g` (docs/theory.md §5.2.1: the paper's
//! `f = −(g + u_x(0, t))` is the load functional with the Dirac mass of the
//! contact reaction left out).
//!
//! # Closed form (docs/theory.md §5.2.2)
//!
//! ```text
//! u(x, t)   = u0 − g t²/2 + B(t − x) + B(t + x − 2L)
//! u_x(x, t) = β(t + x − 2L) − β(t − x)
//! u_t(x, t) = −g t + β(t + x − 2L) + β(t − x)
//! ```
//!
//! with `B(s) = ∫_{−2L}^{s} β` and `β = 0` on `[−2L, 0)`. The profile `β` of
//! the wave leaving `x = 0` is piecewise linear with slopes `0` or `g` and
//! right-continuous; it is determined by the Signorini condition at `x = 0`.
//! With `z(t) = u(0, t)` and `q(t) = 2β(t − 2L) − g t` (the velocity the end
//! would have if it were free):
//!
//! ```text
//! free    (z > 0, or z = 0 and q > 0):  β(t) = β(t − 2L)        (u_x(0,t) = 0, z' = q)
//! contact (z = 0 and q ≤ 0):            β(t) = g t − β(t − 2L)  (u_t(0,t) = 0, λ = q)
//! ```
//!
//! # Representation used here
//!
//! `B` grows like `g t²/4`, so evaluating the formula above as written loses
//! accuracy as `t` grows (a cancellation of size `g t²`). The implementation
//! stores instead the deviations
//!
//! ```text
//! η(s) = β(s) − g (s + L)/2,         H(s) = B(s) − g s²/4 − g L s/2   (H' = η, H(−2L) = 0),
//! ```
//!
//! which stay bounded for all time, and in which
//!
//! ```text
//! u   = u0 + (g/2) x (x − 2L) + H(t − x) + H(t + x − 2L)
//! u_x = g (x − L) + η(t + x − 2L) − η(t − x)
//! u_t = η(t − x) + η(t + x − 2L)
//! z(t) = u0 + H(t) + H(t − 2L),      q(t) = 2 η(t − 2L) − g L
//! free:    η(t) = η(t − 2L) − g L          contact:  η(t) = −η(t − 2L).
//! ```
//!
//! `η` is piecewise linear with slopes `±g/2`, `H` piecewise quadratic; each
//! piece stores its start `s_k`, `η(s_k)`, `H(s_k)` and its slope.
//!
//! # Event-driven construction (docs/theory.md §5.2.2)
//!
//! The profile is built once, at construction, on `[−2L, t_max + 2L]`, by a
//! march in windows on which the incoming wave `η(· − 2L)` is a single linear
//! piece, so that `q` is linear (slope `±g`) and `z` is quadratic:
//!
//! * an **impact** is the first downward root of `z` in the window, computed
//!   from `z = a₀ + a₁ r + a₂ r²` (`a₀ = z(t)`, `a₁ = q(t)`, `a₂ = q'/2`) by
//!   the cancellation-free formula `r = (−a₁ − √D)/(2a₂)` if `a₁ > 0`, else
//!   `r = 2a₀/(√D − a₁)`, and only when `z(end) ≤ 0` or the vertex value is
//!   negative;
//! * a **take-off** happens where `q` jumps above 0 at a breakpoint of the
//!   incoming wave, or where `q` crosses 0 linearly (a smooth take-off);
//! * events that coincide with a breakpoint of the incoming wave up to
//!   round-off are snapped onto it. This matters in commensurate cases such
//!   as `g = 1/9` (`T1 = 3L`), where events land exactly on breakpoints
//!   (docs/theory.md §5.2.4), and for `T1 = 2L`, where impacts are also
//!   tangential (`z' = 0`), so that their time is only determined to
//!   `O(√ε)`: a root is snapped when `z` stays within round-off of 0 between
//!   it and the breakpoint. A contact of zero length (an impact on a
//!   breakpoint at which `q` jumps above 0) is dropped.
//!
//! Three devices keep round-off from accumulating from bounce to bounce
//! (which would otherwise break the commensurate coincidences after a few
//! hundred `L`): breakpoint times are stored as `origin + k·2L` (an event
//! time carried over `k` windows) and evaluated with one rounding; at a
//! window start that is a carried-over breakpoint the incoming values are
//! taken exactly instead of evaluating the piece at the rounded `t − 2L`;
//! and `z` is tracked on its own (0 in contact, advanced by its quadratic in
//! flight) and used to anchor `H` at each new piece.
//!
//! # Resolution in `f64`: the largest `t_max`
//!
//! Events can come arbitrarily close to earlier breakpoints, and whether an
//! impact lies just before or just after a jump of `q` decides the rest of
//! the motion. Below some scale the solution therefore cannot be built in
//! `f64` at all. The construction snaps an event onto a breakpoint within
//! `1e-11·L`; if the distance was more than round-off (a genuine
//! near-coincidence, not a commensurate one), the events are no longer
//! resolved from that time on, and a `t_max` beyond it is rejected with
//! [`NeumannError::Unresolved`], whose `t_limit` is the largest `t_max` that
//! can be built. This happens:
//!
//! * for the paper's `g = 0.11` (`T1/L = 3.0151`): every contact lasts `2L`
//!   and the flights tend to `6L` (docs/theory.md §5.2.5), so each impact
//!   lands just after a cluster of earlier breakpoints (carried over by
//!   `8L`), with gaps shrinking by about 0.45 per bounce (`1.8e-2`, `6.2e-3`,
//!   …, `2e-11`). The impact near `t = 227.05` is `7e-12` after a breakpoint:
//!   `t_max ≤ 225.04`. (With a fixed snapping tolerance instead, the
//!   computed motion turns chaotic near `t ≈ 430`.)
//! * in the chaotic regimes, e.g. `T1/L = 2.5`: the third contact (at
//!   `t ≈ 14.40 L`) lasts only `0.095 L`, then short contacts and flights
//!   proliferate exponentially (74 events by `t = 50 L`, 15 000 by `200 L`)
//!   and the shortest piece shrinks as fast: `t_max ≤ 198 L`. `T1/L = 1.58`,
//!   `1.9`, `3.5` behave alike (`t_max ≤ 175 L`, `167 L`, `274 L`). The
//!   identities (contact conditions, energy, parallelogram) still hold to
//!   round-off there, and the leapfrog of docs/theory.md §5.2.6 converges to
//!   this solution.
//! * never for `T1 = mL`, `m ≥ 2` an integer (periodic, period `4(m+1)L`,
//!   a fixed number of pieces per period: 5 for `m = 3`, docs/theory.md
//!   §5.2.4), checked to `t_max = 1000 L` for `L = 0.3, 0.7, 1, 3.3`.
//!
//! # Complexity
//!
//! The number of pieces of `β` grows with `t_max`: by a fixed number per
//! period in the commensurate cases, by one per impact in each window of
//! length `2L` for `g = 0.11` (`O((t_max/L)²)`, about 1 650 pieces at
//! `t_max = 225`),
//! and for `T1 ≤ L` quadratically too (about `t_max²/16` for `T1 = 0.05 L`).
//! It is capped at [`BarNeumannGravity::MAX_PIECES`]
//! ([`NeumannError::TooComplex`]).
//!
//! # Special cases (docs/theory.md §5.2.3–§5.2.5)
//!
//! * [`BarNeumannGravity::periodic`]: `u0 = 1/2`, `g = 1/9`, `L = 1`, hence
//!   `T1 = √(2u0/g) = 3L`; exactly periodic with period `16`, impacts at
//!   `3 + 8k`, take-offs at `5 + 8k`.
//! * [`BarNeumannGravity::paper`]: `u0 = 1/2`, `g = 0.11`, `L = 1` (the
//!   paper's data); first impact `T1 = 10/√11`, every contact lasts `2L`, not
//!   periodic; `t_max ≤ 225.04` (see "Resolution").
//!
//! # Domain of evaluation
//!
//! All evaluations ([`ExactSolution::fields`], [`ExactSolution::u_at`],
//! [`ExactSolution::lambda`], [`ExactSolution::kinks`]) are defined for
//! `t ∈ [0, t_max]`, widened by `δ = 1e-9·(t_max + L)` on both sides to absorb
//! round-off in time grids (`n·dt` slightly above `t_max`). Outside, the
//! fields and `λ` are NaN and the kink list is empty; nothing panics. Points
//! `x` within `1e-9·L` of `[0, L]` are clamped onto it; farther off, or NaN,
//! they give NaN fields (the crate docs, "Domain of evaluation").

use std::fmt;

use crate::{on_bar, ExactSolution, FarEnd, Fields, UNDEFINED};

/// Relative distance (in units of `L`) below which an event is snapped onto
/// a breakpoint of the incoming wave (docs/theory.md §5.2.2). A snap by more
/// than round-off ([`ROUNDOFF_T`]) marks the solution unresolved from there.
const SNAP: f64 = 1e-11;

/// Round-off level of times, relative to `|t| + L`: an event snapped onto a
/// breakpoint from farther than this is a genuine near-coincidence, no
/// longer resolved in `f64` (breakpoint times carry one rounding, event
/// times a few).
const ROUNDOFF_T: f64 = 8.0 * f64::EPSILON;

/// Round-off level of the height `z` of the lower end, relative to
/// `u0 + g L²`.
const ROUNDOFF_Z: f64 = 64.0 * f64::EPSILON;

/// Relative slack (in units of `t_max + L`) accepted beyond `[0, t_max]`.
const T_SLACK: f64 = 1e-9;

/// Kinks closer than this (in units of `L`) are reported once.
const KINK_DEDUP: f64 = 1e-14;

/// A parameter rejected by [`BarNeumannGravity::new`]: which one, its value,
/// and the range it must lie in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NeumannError {
    /// The initial height `u0` must be finite and `> 0`.
    InitialHeight(f64),
    /// The gravity `g` must be finite and `> 0`.
    Gravity(f64),
    /// The bar length `L` must be finite and `> 0`.
    Length(f64),
    /// The time horizon `t_max` must be finite and `>= 0`.
    TimeHorizon(f64),
    /// The time horizon `t_max` is too long for these data: the profile `β`
    /// would need more than [`BarNeumannGravity::MAX_PIECES`] linear pieces.
    TooComplex {
        /// The requested horizon.
        t_max: f64,
        /// About the largest `t_max` that fits.
        t_limit: f64,
    },
    /// The time horizon `t_max` is too long for these data: beyond
    /// `t_limit`, events come closer to earlier breakpoints than `f64` can
    /// resolve (they accumulate, as for `g = 0.11` near `t ≈ 227`, or
    /// proliferate; see the module docs, "Resolution"), so the solution can
    /// no longer be built exactly.
    Unresolved {
        /// The requested horizon.
        t_max: f64,
        /// About the largest `t_max` that can be built exactly.
        t_limit: f64,
    },
}

impl NeumannError {
    /// Name of the offending parameter (`"u0"`, `"g"`, `"length"`, `"t_max"`).
    #[must_use]
    pub fn field(&self) -> &'static str {
        match self {
            Self::InitialHeight(_) => "u0",
            Self::Gravity(_) => "g",
            Self::Length(_) => "length",
            Self::TimeHorizon(_) | Self::TooComplex { .. } | Self::Unresolved { .. } => "t_max",
        }
    }

    /// The rejected value.
    #[must_use]
    pub fn value(&self) -> f64 {
        match *self {
            Self::InitialHeight(v) | Self::Gravity(v) | Self::Length(v) | Self::TimeHorizon(v) => v,
            Self::TooComplex { t_max, .. } | Self::Unresolved { t_max, .. } => t_max,
        }
    }

    /// The allowed range, in words.
    #[must_use]
    pub fn allowed(&self) -> &'static str {
        match self {
            Self::TimeHorizon(_) => "finite and >= 0",
            Self::TooComplex { .. } => "short enough for the exact profile to fit in MAX_PIECES = 2^22 pieces",
            Self::Unresolved { .. } => "short enough for the events to be resolved in f64",
            _ => "finite and > 0",
        }
    }
}

impl fmt::Display for NeumannError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Self::TooComplex { t_max, t_limit } | Self::Unresolved { t_max, t_limit } = *self {
            return write!(f, "bar-neumann-gravity: invalid t_max = {t_max} (must be {}: t_max <= {t_limit} for these data)", self.allowed());
        }
        write!(f, "bar-neumann-gravity: invalid {} = {} (must be {})", self.field(), self.value(), self.allowed())
    }
}

impl std::error::Error for NeumannError {}

/// Kind of a contact event at `x = 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventKind {
    /// The lower end reaches the floor; a contact interval starts.
    Impact,
    /// The lower end leaves the floor; the contact interval ends.
    TakeOff,
}

/// A contact event: impacts and take-offs alternate, starting with an
/// impact. The contact intervals are `[impact, take-off)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    /// Time of the event.
    pub time: f64,
    /// Impact or take-off.
    pub kind: EventKind,
}

/// One linear piece of `η` (see the module docs) on `[s, next piece's s)`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Piece {
    /// Start of the piece (`= stamp.time(2L)`).
    s: f64,
    /// How `s` was made: an event time shifted by a number of `2L`.
    stamp: Stamp,
    /// `η(s)`.
    eta: f64,
    /// `H(s)`.
    h: f64,
    /// Slope of `η`: `+g/2` (β has slope `g`) or `−g/2` (β constant).
    slope: f64,
}

/// A breakpoint time written as `origin + k·2L` (an event time, or `−2L`,
/// and the number of windows it has been carried over), evaluated with a
/// single rounding. Summing `2L` window after window would let commensurate
/// coincidences (events exactly on breakpoints, e.g. `T1 = mL`) drift apart
/// by `O(k)` ulps; this keeps them within a few ulps.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Stamp {
    origin: f64,
    k: u32,
}

impl Stamp {
    #[inline]
    fn at(t: f64) -> Self {
        Self { origin: t, k: 0 }
    }

    #[inline]
    fn time(self, two_l: f64) -> f64 {
        f64::from(self.k).mul_add(two_l, self.origin)
    }

    /// The same breakpoint carried over one window.
    #[inline]
    fn next(self) -> Self {
        Self { origin: self.origin, k: self.k.saturating_add(1) }
    }
}

impl Piece {
    #[inline]
    fn eta_at(&self, s: f64) -> f64 {
        self.eta + self.slope * (s - self.s)
    }

    #[inline]
    fn h_at(&self, s: f64) -> f64 {
        let r = s - self.s;
        self.h + r * (self.eta + 0.5 * self.slope * r)
    }
}

/// The two pieces of `β` seen from a point at time `t` (that of `t − x` and
/// that of `t + x − 2L`), in the form used to evaluate `u` on the whole cell
/// they define (one quadratic in `x`).
#[derive(Clone, Copy, Debug)]
struct Cell {
    /// `u0 + H(s_{k1}) + H(s_{k2})`.
    a: f64,
    /// `t − s_{k1}`: `r1 = t − x − s_{k1} = c1 − x`.
    c1: f64,
    e1: f64,
    hs1: f64,
    /// `t − 2L − s_{k2}`: `r2 = t + x − 2L − s_{k2} = c2 + x`.
    c2: f64,
    e2: f64,
    hs2: f64,
}

impl Cell {
    #[inline]
    fn new(p1: &Piece, p2: &Piece, u0: f64, t: f64, two_l: f64) -> Self {
        Self { a: u0 + p1.h + p2.h, c1: t - p1.s, e1: p1.eta, hs1: 0.5 * p1.slope, c2: (t - two_l) - p2.s, e2: p2.eta, hs2: 0.5 * p2.slope }
    }

    /// `u = u0 + (g/2) x (x − 2L) + H(t − x) + H(t + x − 2L)`.
    #[inline]
    fn u(&self, x: f64, half_g: f64, two_l: f64) -> f64 {
        let (r1, r2) = (self.c1 - x, self.c2 + x);
        self.a + half_g * x * (x - two_l) + r1 * (self.e1 + self.hs1 * r1) + r2 * (self.e2 + self.hs2 * r2)
    }
}

/// Index of the piece containing `s`, right-continuous: the last `k` with
/// `s_k <= s` (0 if none).
#[inline]
fn find_right(p: &[Piece], s: f64) -> usize {
    p.partition_point(|q| q.s <= s).saturating_sub(1)
}

/// Index of the piece containing `s`, left-continuous: the last `k` with
/// `s_k < s` (0 if none).
#[inline]
fn find_left(p: &[Piece], s: f64) -> usize {
    p.partition_point(|q| q.s < s).saturating_sub(1)
}

/// Moves `k` (any start) to [`find_right`]`(p, s)` by walking.
#[inline]
fn seek_right(p: &[Piece], mut k: usize, s: f64) -> usize {
    while k > 0 && p[k].s > s {
        k -= 1;
    }
    while k + 1 < p.len() && p[k + 1].s <= s {
        k += 1;
    }
    k
}

/// Moves `k` (any start) to [`find_left`]`(p, s)` by walking.
#[inline]
fn seek_left(p: &[Piece], mut k: usize, s: f64) -> usize {
    while k > 0 && p[k].s >= s {
        k -= 1;
    }
    while k + 1 < p.len() && p[k + 1].s < s {
        k += 1;
    }
    k
}

/// The falling bar under gravity (Signorini–Neumann benchmark of the 2017
/// paper, §4), exact for any `u0 > 0`, `g > 0`, `L > 0` (`c = 1`).
///
/// Built once for `t ∈ [0, t_max]` (the profile is constructed up to
/// `t_max + 2L`); see the module docs for the formulas and the domain of
/// evaluation.
#[derive(Clone, Debug)]
pub struct BarNeumannGravity {
    name: &'static str,
    u0: f64,
    g: f64,
    l: f64,
    t_max: f64,
    /// Evaluation window `[t_lo, t_hi]`.
    t_lo: f64,
    t_hi: f64,
    period: Option<f64>,
    pieces: Vec<Piece>,
    events: Vec<Event>,
}

impl BarNeumannGravity {
    /// Largest number of linear pieces of `β` a solution may hold (`2^22`,
    /// 192 MiB); a longer `t_max` is rejected with
    /// [`NeumannError::TooComplex`].
    pub const MAX_PIECES: usize = 1 << 22;

    /// The bar of length `length`, released from rest at height `u0` under
    /// gravity `g`, for times in `[0, t_max]`.
    ///
    /// # Errors
    /// [`NeumannError`] naming the first parameter out of range: `u0`, `g`,
    /// `length` must be finite and `> 0`, `t_max` finite and `>= 0`;
    /// [`NeumannError::Unresolved`] if the events are not resolved in `f64`
    /// up to `t_max + 2L`, [`NeumannError::TooComplex`] if the profile would
    /// need more than [`Self::MAX_PIECES`] pieces (module docs).
    pub fn new(u0: f64, g: f64, length: f64, t_max: f64) -> Result<Self, NeumannError> {
        Self::build("bar-neumann-gravity-custom", u0, g, length, t_max)
    }

    /// The main benchmark `bar-neumann-gravity`: `u0 = 1/2`, `g = 1/9`,
    /// `L = 1`, exactly periodic with period 16 (docs/theory.md §5.2.4).
    ///
    /// # Errors
    /// [`NeumannError::TimeHorizon`] if `t_max` is not finite or is negative,
    /// [`NeumannError::Unresolved`] or [`NeumannError::TooComplex`] if it is
    /// too long (see [`Self::new`]).
    pub fn periodic(t_max: f64) -> Result<Self, NeumannError> {
        let mut s = Self::build("bar-neumann-gravity", 0.5, 1.0 / 9.0, 1.0, t_max)?;
        s.period = Some(16.0);
        Ok(s)
    }

    /// The paper's data, `bar-neumann-gravity-0.11`: `u0 = 1/2`, `g = 0.11`,
    /// `L = 1`; not periodic (docs/theory.md §5.2.5).
    ///
    /// # Errors
    /// [`NeumannError::TimeHorizon`] if `t_max` is not finite or is negative,
    /// [`NeumannError::Unresolved`] or [`NeumannError::TooComplex`] if it is
    /// too long (see [`Self::new`]).
    pub fn paper(t_max: f64) -> Result<Self, NeumannError> {
        Self::build("bar-neumann-gravity-0.11", 0.5, 0.11, 1.0, t_max)
    }

    fn build(name: &'static str, u0: f64, g: f64, l: f64, t_max: f64) -> Result<Self, NeumannError> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(u0) {
            return Err(NeumannError::InitialHeight(u0));
        }
        if !positive(g) {
            return Err(NeumannError::Gravity(g));
        }
        if !positive(l) {
            return Err(NeumannError::Length(l));
        }
        if !(t_max.is_finite() && t_max >= 0.0) {
            return Err(NeumannError::TimeHorizon(t_max));
        }
        let horizon = t_max + 2.0 * l;
        let Built { pieces, events, reached, unresolved } = march(u0, g, l, horizon);
        // Everything built (up to t_max + 2L) must be exact.
        if unresolved < horizon {
            return Err(NeumannError::Unresolved { t_max, t_limit: (unresolved - 2.0 * l).max(0.0) });
        }
        if pieces.len() > Self::MAX_PIECES {
            return Err(NeumannError::TooComplex { t_max, t_limit: (reached - 2.0 * l).max(0.0) });
        }
        let built = reached;
        let slack = T_SLACK * (t_max + l);
        // Commensurate case T1 = m L, m >= 2 an integer: period 4 (m + 1) L.
        let m = (2.0 * u0 / g).sqrt() / l;
        let period = (m.round() >= 2.0 && (m - m.round()).abs() <= 1e-12 * m).then(|| 4.0 * (m.round() + 1.0) * l);
        Ok(Self { name, u0, g, l, t_max, t_lo: -slack, t_hi: (t_max + slack).min(built), period, pieces, events })
    }

    /// Initial height `u0`.
    #[must_use]
    pub fn u0(&self) -> f64 {
        self.u0
    }

    /// Gravity `g` (the body force is `−g`).
    #[must_use]
    pub fn gravity(&self) -> f64 {
        self.g
    }

    /// End `t_max` of the time interval the solution was built for.
    #[must_use]
    pub fn t_max(&self) -> f64 {
        self.t_max
    }

    /// Time of the first impact, `T1 = √(2 u0 / g)`.
    #[must_use]
    pub fn first_impact(&self) -> f64 {
        (2.0 * self.u0 / self.g).sqrt()
    }

    /// The impacts and take-offs found on `[0, t_max + 2L]`, in time order,
    /// alternating and starting with an impact (a last impact may have no
    /// take-off before `t_max + 2L`).
    #[must_use]
    pub fn events(&self) -> &[Event] {
        &self.events
    }

    /// Impact times (see [`Self::events`]).
    pub fn impacts(&self) -> impl Iterator<Item = f64> + '_ {
        self.events.iter().filter(|e| e.kind == EventKind::Impact).map(|e| e.time)
    }

    /// Take-off times (see [`Self::events`]).
    pub fn takeoffs(&self) -> impl Iterator<Item = f64> + '_ {
        self.events.iter().filter(|e| e.kind == EventKind::TakeOff).map(|e| e.time)
    }

    /// Whether the lower end is in contact at `t`, i.e. `t` lies in a contact
    /// interval `[impact, take-off)` (false outside the evaluation window).
    #[must_use]
    pub fn in_contact(&self, t: f64) -> bool {
        if !self.t_ok(t) {
            return false;
        }
        let i = self.events.partition_point(|e| e.time <= t);
        i > 0 && self.events[i - 1].kind == EventKind::Impact
    }

    /// The breakpoints `s_k` of the profile `β` in `(−2L, t_max + 2L)`,
    /// increasing: `u_x` and `u_t` may jump across the characteristic lines
    /// `x = t − s_k` and `x = s_k − t + 2L`.
    pub fn breakpoints(&self) -> impl Iterator<Item = f64> + '_ {
        self.pieces.iter().skip(1).map(|p| p.s)
    }

    /// Length of the shortest linear piece of `β` (between two consecutive
    /// [`Self::breakpoints`]), or `+∞` if there are none: the finest time
    /// scale of the solution. It can be as small as the snapping scale
    /// `1e-11·L` (module docs, "Resolution").
    #[must_use]
    pub fn shortest_piece(&self) -> f64 {
        self.pieces.windows(2).skip(1).map(|w| w[1].s - w[0].s).fold(f64::INFINITY, f64::min)
    }

    /// Number of linear pieces of `β` on `[−2L, t_max + 2L]` (the cost of the
    /// construction; at most [`Self::MAX_PIECES`]).
    #[must_use]
    pub fn piece_count(&self) -> usize {
        self.pieces.len()
    }

    /// The right-continuous profile `β(s)` of the wave leaving `x = 0`, for
    /// `s ∈ [−2L, t_max]` (0 on `[−2L, 0)`; NaN outside).
    #[must_use]
    pub fn beta(&self, s: f64) -> f64 {
        if !(s >= -2.0 * self.l && s <= self.t_hi) {
            return f64::NAN;
        }
        let p = &self.pieces[find_right(&self.pieces, s)];
        p.eta_at(s) + 0.5 * self.g * (s + self.l)
    }

    /// `q(t) = 2β(t − 2L) − g t`: the velocity of the end `x = 0` if it were
    /// free, equal to the contact force if it is clamped (right-continuous).
    fn q(&self, t: f64) -> f64 {
        let two_l = 2.0 * self.l;
        // The same test as the construction's, so that λ switches exactly at
        // the events.
        let k = self.pieces.partition_point(|p| p.stamp.next().time(two_l) <= t).saturating_sub(1);
        2.0 * self.pieces[k].eta_at(t - two_l) - self.g * self.l
    }

    #[inline]
    fn t_ok(&self, t: f64) -> bool {
        t >= self.t_lo && t <= self.t_hi
    }
}

/// Result of the march.
struct Built {
    pieces: Vec<Piece>,
    events: Vec<Event>,
    /// Time reached (`>= horizon` unless stopped early).
    reached: f64,
    /// First time at which an event had to be snapped onto a breakpoint from
    /// farther than round-off (`+∞` if never): from there on the events are
    /// not resolved in `f64`.
    unresolved: f64,
}

/// Records a snap by `d` at time `t` if it is more than round-off.
#[inline]
fn note_snap(unresolved: &mut f64, d: f64, t: f64, l: f64) {
    if d > ROUNDOFF_T * (t.abs() + l) {
        *unresolved = unresolved.min(t);
    }
}

/// Builds the pieces of `η` on `[−2L, horizon]` and the events
/// (docs/theory.md §5.2.2; see the module docs). Stops early past
/// `BarNeumannGravity::MAX_PIECES` pieces.
fn march(u0: f64, g: f64, l: f64, horizon: f64) -> Built {
    let max_pieces = BarNeumannGravity::MAX_PIECES;
    let two_l = 2.0 * l;
    let gl = g * l;
    let snap = SNAP * l;
    // q has slope ±g: a time snap of `snap` is a q snap of `g·snap`.
    let tol_q = g * snap;
    // Round-off level of z = u0 + H(t) + H(t − 2L) (H is of the size of u).
    let tol_z0 = ROUNDOFF_Z * (u0 + g * l * l);
    // Bound on |q| (the impact speed √(2 u0 g) plus what a window adds).
    let v_max = (2.0 * u0 * g).sqrt() + 2.0 * gl;
    let half_g = 0.5 * g;
    // β = 0 on [−2L, 0): η(s) = −g (s + L)/2, H(−2L) = 0.
    let mut p = vec![Piece { s: -two_l, stamp: Stamp::at(-two_l), eta: half_g * l, h: 0.0, slope: -half_g }];
    let mut ev: Vec<Event> = Vec::new();
    let mut unresolved = f64::INFINITY;
    let mut t = 0.0_f64;
    let mut ts = Stamp::at(0.0); // t = ts.time(2L)
                                 // z(t) = u0 + H(t) + H(t − 2L), tracked on its own (exactly 0 in
                                 // contact, advanced by its local quadratic in flight) and used to anchor
                                 // H at each new piece: round-off then cannot accumulate in z from one
                                 // bounce to the next (it would make tangential impacts, e.g. for
                                 // T1 = 2L, drift by O(√(k ε))).
    let mut z_cur = u0;
    let mut contact = false;
    let mut just_took_off = false;
    let mut j = 0_usize; // incoming piece: the one containing t − 2L
    let mut stall = 0_u32;
    while t < horizon && p.len() <= max_pieces {
        while j + 1 < p.len() && p[j + 1].stamp.next().time(two_l) <= t {
            j += 1;
        }
        let inc = p[j];
        let s_in = t - two_l;
        // At a window start that is the incoming breakpoint carried over
        // (the usual case), take its values exactly: evaluating the piece at
        // the rounded t − 2L would add O(slope · ulp(t)) to η at every
        // window, an error that accumulates from bounce to bounce.
        let (eta_in, h_in) = if ts == inc.stamp.next() { (inc.eta, inc.h) } else { (inc.eta_at(s_in), inc.h_at(s_in)) };
        // Round-off level of z at this time: its size, and the uncertainty
        // of t times the largest speed.
        let tol_z = tol_z0 + ROUNDOFF_T * (t.abs() + l) * v_max;
        let q0 = 2.0 * eta_in - gl;
        let t_start = t;
        if contact {
            // Near-degenerate q at a breakpoint (q ≈ 0 there): snapped to 0.
            if q0.abs() <= tol_q {
                note_snap(&mut unresolved, q0.abs() / g, t, l);
            }
            if q0 > tol_q || (q0 >= -tol_q && inc.slope > 0.0) {
                // Take-off at t (q jumps above 0 at a breakpoint, or is ~0
                // and increasing).
                if ev.last().is_some_and(|e| e.kind == EventKind::Impact && e.time == t) {
                    ev.pop(); // a contact of zero length: a graze
                } else {
                    ev.push(Event { time: t, kind: EventKind::TakeOff });
                }
                contact = false;
                just_took_off = true;
            } else {
                // Anchor H so that z(t) = u0 + H(t) + H(t − 2L) = 0 holds to
                // round-off during the whole contact (instead of inheriting
                // the O(ε t V) error of the impact time).
                push_piece(&mut p, t, ts, -eta_in, -inc.slope, false, Some(-u0 - h_in));
                let (in_end, end_stamp, at_bp) = window_end(&p, j, ts, two_l);
                let snap_end = at_bp && in_end <= horizon;
                let (w_end, w_stamp) = if in_end <= horizon { (in_end, end_stamp) } else { (horizon, Stamp::at(horizon)) };
                let dt = w_end - t;
                if inc.slope > 0.0 && q0 + 2.0 * inc.slope * dt > 0.0 {
                    // Smooth take-off: q crosses 0 linearly inside the window.
                    let r = -q0 / (2.0 * inc.slope);
                    if dt - r <= snap && snap_end {
                        note_snap(&mut unresolved, dt - r, w_end, l);
                        (t, ts) = (w_end, w_stamp); // on the breakpoint: decided at the next step
                    } else {
                        t += r;
                        ts = Stamp::at(t);
                        ev.push(Event { time: t, kind: EventKind::TakeOff });
                        contact = false;
                        just_took_off = true;
                    }
                } else {
                    (t, ts) = (w_end, w_stamp);
                }
            }
        } else {
            // Free fall copies itself: the incoming piece is the current one.
            let self_copy = j + 1 == p.len();
            push_piece(&mut p, t, ts, eta_in - gl, inc.slope, self_copy, Some(z_cur - u0 - h_in));
            let (in_end, end_stamp, at_bp) = window_end(&p, j, ts, two_l);
            let snap_end = at_bp && in_end <= horizon;
            let (w_end, w_stamp) = if in_end <= horizon { (in_end, end_stamp) } else { (horizon, Stamp::at(horizon)) };
            let dt = w_end - t;
            let a0 = z_cur;
            let hit = match impact_root(a0, q0, inc.slope, dt) {
                Some(r) => {
                    let z = |r: f64| a0 + r * (q0 + inc.slope * r);
                    let a2 = inc.slope;
                    let vertex = -q0 / (2.0 * a2);
                    // Largest z on [0, r] and smallest z on [r, dt]: the
                    // crossing is within round-off of the window start (end)
                    // if z stays within tol_z of 0 before (after) it. This
                    // also catches tangential contacts, whose time is only
                    // determined to O(√ε) (e.g. T1 = 2L).
                    let z_max_before = if vertex > 0.0 && vertex < r { z(vertex) } else { a0.max(0.0) };
                    let z_min_after = if vertex > r && vertex < dt { z(vertex) } else { z(dt) };
                    let graze = a2 > 0.0 && vertex > r && vertex < dt && z(vertex) >= -tol_z;
                    if just_took_off && r <= snap {
                        // z rises right after a take-off: a root at ~0 is spurious.
                        None
                    } else if !just_took_off && z_max_before <= tol_z {
                        Some(t)
                    } else if r <= snap {
                        note_snap(&mut unresolved, r, t, l);
                        Some(t)
                    } else if snap_end && z_min_after >= -tol_z && !graze {
                        Some(w_end)
                    } else if snap_end && dt - r <= snap {
                        note_snap(&mut unresolved, dt - r, w_end, l);
                        Some(w_end)
                    } else if graze {
                        None // touches 0 within round-off and rises again
                    } else {
                        Some(t + r)
                    }
                }
                None => None,
            };
            match hit {
                Some(ti) => {
                    ts = if ti == t {
                        ts
                    } else if ti == w_end {
                        w_stamp
                    } else {
                        Stamp::at(ti)
                    };
                    t = ti;
                    ev.push(Event { time: t, kind: EventKind::Impact });
                    contact = true;
                    just_took_off = false;
                    z_cur = 0.0;
                }
                None => {
                    z_cur = a0 + dt * (q0 + inc.slope * dt);
                    (t, ts) = (w_end, w_stamp);
                }
            }
        }
        if t > t_start {
            stall = 0;
            just_took_off = just_took_off && ev.last().is_some_and(|e| e.time == t);
        } else {
            stall += 1;
            if stall > 8 {
                break; // cannot happen; never loop forever
            }
        }
    }
    Built { pieces: p, events: ev, reached: t, unresolved }
}

/// End of the window starting at `t` on which the incoming piece `j` stays
/// the same: its end shifted by `2L` (if `j` is the last piece, it extends
/// at least to `t`, hence the window to `t + 2L`).
///
/// Returns the end, its stamp, and whether it is a breakpoint of the incoming
/// wave (where `q` may jump, so that events may snap onto it).
#[inline]
fn window_end(p: &[Piece], j: usize, t: Stamp, two_l: f64) -> (f64, Stamp, bool) {
    match p.get(j + 1) {
        Some(q) => (q.stamp.next().time(two_l), q.stamp.next(), true),
        None => (t.next().time(two_l), t.next(), false),
    }
}

/// Starts a new piece of `η` at `t` (value `eta`, slope `slope`), replacing a
/// piece that would start at `t` too. With `self_copy` (free mode copying
/// the current piece itself, as in free fall), the piece is merged with the
/// previous one when it is the same linear function up to round-off. Other
/// near-coincidences are kept as breakpoints: merging them would drop the
/// breakpoints onto which later events must snap (the accumulating events of
/// `g = 0.11`). `H(t)` is `h_anchor` if given, else `H` is continued.
fn push_piece(p: &mut Vec<Piece>, t: f64, stamp: Stamp, eta: f64, slope: f64, self_copy: bool, h_anchor: Option<f64>) {
    let mut h = h_anchor;
    if p.len() > 1 && p.last().is_some_and(|c| c.s == t) {
        let popped = p.pop().map(|c| c.h);
        h = h.or(popped);
    }
    let Some(last) = p.last() else { return };
    let tol = 1e-13 * (eta.abs() + 2.0 * slope.abs());
    if self_copy && last.slope == slope && (last.eta_at(t) - eta).abs() <= tol {
        return;
    }
    let h = h.unwrap_or_else(|| last.h_at(t));
    p.push(Piece { s: t, stamp, eta, h, slope });
}

/// First downward root `r ∈ [0, dt]` of `z(r) = a0 + a1 r + a2 r²`
/// (`a2 = ±g/2 ≠ 0`), if any; cancellation-free (docs/theory.md §5.2.2).
#[inline]
fn impact_root(a0: f64, a1: f64, a2: f64, dt: f64) -> Option<f64> {
    if a0 <= 0.0 && a1 <= 0.0 && !(a1 == 0.0 && a2 > 0.0) {
        return Some(0.0);
    }
    let z_end = a0 + dt * (a1 + a2 * dt);
    let vertex_below = a2 > 0.0 && a1 < 0.0 && -a1 < 2.0 * a2 * dt && 4.0 * a2 * a0 < a1 * a1;
    if !(z_end <= 0.0 || vertex_below) {
        return None;
    }
    let d = (a1 * a1 - 4.0 * a2 * a0).max(0.0).sqrt();
    let r = if a1 > 0.0 { (-a1 - d) / (2.0 * a2) } else { 2.0 * a0 / (d - a1) };
    Some(r.clamp(0.0, dt))
}

impl ExactSolution for BarNeumannGravity {
    fn name(&self) -> &str {
        self.name
    }

    fn length(&self) -> f64 {
        self.l
    }

    fn far_end(&self) -> FarEnd {
        FarEnd::Free
    }

    fn body_force(&self) -> f64 {
        -self.g
    }

    fn degree_x(&self) -> usize {
        2
    }

    /// `[0, t_max]` widened by the slack of the module docs.
    fn defined_at(&self, t: f64) -> bool {
        self.t_ok(t)
    }

    /// `u`, `u_x`, `u_t` at `(x, t)`; `x` within round-off of `[0, L]` is
    /// clamped onto it; NaN for `t` outside `[0, t_max]` (± the slack of the
    /// module docs) or `x` off the bar or NaN.
    /// On a kink, the values of the piece on the larger-`x` side; at `x = L`,
    /// the values right-continuous in `t` (`u_x(L, t) = 0` exactly).
    fn fields(&self, x: f64, t: f64) -> Fields {
        let (l, two_l) = (self.l, 2.0 * self.l);
        let Some(x) = on_bar(x, l).filter(|_| self.t_ok(t)) else {
            return UNDEFINED;
        };
        let (s1, s2) = (t - x, t + x - two_l);
        // Ties towards larger x: β(s1⁻) and β(s2⁺). At x = L there is no
        // larger x: both arguments equal t − L and take the same
        // (right-continuous) piece, so that u_x(L, t) = 0 exactly.
        let k1 = if x < l { find_left(&self.pieces, s1) } else { find_right(&self.pieces, s1) };
        let k2 = find_right(&self.pieces, s2);
        let c = Cell::new(&self.pieces[k1], &self.pieces[k2], self.u0, t, two_l);
        let (r1, r2) = (c.c1 - x, c.c2 + x);
        let e1 = c.e1 + 2.0 * c.hs1 * r1;
        // At x = L both arguments are t − L (same piece): same value.
        let e2 = if x < l { c.e2 + 2.0 * c.hs2 * r2 } else { e1 };
        Fields { u: c.u(x, 0.5 * self.g, two_l), ux: self.g * (x - l) + e2 - e1, ut: e1 + e2 }
    }

    /// `u(x_i, t)` for all `i` (up to the shorter of `xs`, `out`), with the
    /// conventions of `fields` (clamping within round-off, NaN). Points are meant to be sorted
    /// increasingly: the points are processed in runs that share one cell
    /// (one pair of pieces of `β`, i.e. one quadratic in `x`), and the pieces
    /// are walked monotonically from one run to the next, so the cost is
    /// `O(n + pieces)`. Unsorted points give the same values, only slower.
    fn u_at(&self, t: f64, xs: &[f64], out: &mut [f64]) {
        if !self.t_ok(t) {
            out.iter_mut().take(xs.len()).for_each(|o| *o = f64::NAN);
            return;
        }
        let (l, two_l, half_g, u0) = (self.l, 2.0 * self.l, 0.5 * self.g, self.u0);
        let p = &self.pieces[..];
        let n = xs.len().min(out.len());
        let first = xs.iter().find_map(|&x| on_bar(x, l)).unwrap_or(0.0);
        let mut k1 = find_left(p, t - first);
        let mut k2 = find_right(p, t + first - two_l);
        let mut i = 0;
        while i < n {
            let Some(x) = on_bar(xs[i], l) else {
                out[i] = f64::NAN;
                i += 1;
                continue;
            };
            // The cell of x, as `fields` finds it.
            let (s1, s2) = (t - x, t + x - two_l);
            k1 = if x < l { seek_left(p, k1, s1) } else { seek_right(p, k1, s1) };
            k2 = seek_right(p, k2, s2);
            let c = Cell::new(&p[k1], &p[k2], u0, t, two_l);
            out[i] = c.u(x, half_g, two_l);
            i += 1;
            // Extend the run while `fields` would pick the same cell: the
            // same tests as `find_left`/`find_right`, so that `u_at` and
            // `fields` agree to the last bit (x = L takes the path above).
            let lo1 = if k1 > 0 { p[k1].s } else { f64::NEG_INFINITY };
            let hi1 = p.get(k1 + 1).map_or(f64::INFINITY, |q| q.s);
            let lo2 = if k2 > 0 { p[k2].s } else { f64::NEG_INFINITY };
            let hi2 = p.get(k2 + 1).map_or(f64::INFINITY, |q| q.s);
            while i < n {
                let Some(x) = on_bar(xs[i], l) else { break };
                let (s1, s2) = (t - x, t + x - two_l);
                if !(x < l && s1 > lo1 && s1 <= hi1 && s2 >= lo2 && s2 < hi2) {
                    break;
                }
                out[i] = c.u(x, half_g, two_l);
                i += 1;
            }
        }
    }

    /// `λ(t) = min(q(t), 0)` on the contact intervals `[impact, take-off)`,
    /// 0 elsewhere (right-continuous); NaN outside the evaluation window.
    fn lambda(&self, t: f64) -> f64 {
        if !self.t_ok(t) {
            return f64::NAN;
        }
        if self.in_contact(t) {
            self.q(t).min(0.0)
        } else {
            0.0
        }
    }

    /// `∫ (u_t² + u_x²)/2 + g u dx = g u0 L` (the initial potential energy).
    fn energy(&self) -> f64 {
        self.g * self.u0 * self.l
    }

    /// The points of `(0, L)` on the characteristic lines `x = t − s_k` and
    /// `x = s_k − t + 2L` through the breakpoints `s_k` of `β`, sorted and
    /// deduplicated; empty outside the evaluation window.
    fn kinks(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        if !self.t_ok(t) {
            return;
        }
        let (l, two_l) = (self.l, 2.0 * self.l);
        let p = &self.pieces[..];
        // Family A: s_k in (t − L, t), x = t − s_k, increasing for k decreasing.
        let a_hi = p.partition_point(|q| q.s < t);
        let a_lo = p.partition_point(|q| q.s <= t - l).max(1);
        // Family B: s_k in (t − 2L, t − L), x = s_k − t + 2L, increasing in k.
        let b_lo = p.partition_point(|q| q.s <= t - two_l).max(1);
        let b_hi = p.partition_point(|q| q.s < t - l);
        let (mut ia, mut ib) = (a_hi, b_lo);
        let tol = KINK_DEDUP * l;
        loop {
            let xa = (ia > a_lo).then(|| t - p[ia - 1].s);
            let xb = (ib < b_hi).then(|| p[ib].s - t + two_l);
            let x = match (xa, xb) {
                (Some(a), Some(b)) if a <= b => {
                    ia -= 1;
                    a
                }
                (Some(_), Some(b)) | (None, Some(b)) => {
                    ib += 1;
                    b
                }
                (Some(a), None) => {
                    ia -= 1;
                    a
                }
                (None, None) => break,
            };
            if x > 0.0 && x < l && out.last().is_none_or(|&last| x - last > tol) {
                out.push(x);
            }
        }
    }

    fn period(&self) -> Option<f64> {
        self.period
    }
}
