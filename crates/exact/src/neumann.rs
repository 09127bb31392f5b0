//! Benchmark `bar-neumann-gravity` (SPEC §5.2; exact-neumann.md §2): an
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
//! The body force is `f = −g` (exact-neumann.md §2.1: the paper's
//! `f = −(g + u_x(0, t))` is the load functional with the Dirac mass of the
//! contact reaction left out).
//!
//! # Closed form (exact-neumann.md §2.2)
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
//! # Event-driven construction (exact-neumann.md §2.2)
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
//! * events within `1e-11·L` of a breakpoint are snapped onto it (this matters
//!   in commensurate cases such as `g = 1/9`, where events land exactly on
//!   breakpoints; exact-neumann.md §2.4). A contact of zero length (an impact
//!   snapped onto a breakpoint at which `q` jumps above 0) is dropped.
//!
//! The number of pieces grows with time (for `g = 0.11`, by one per impact in
//! each window of length `2L`; exact-neumann.md §2.5), so construction costs
//! `O((t_max/L)²)` in the worst case — a few milliseconds for `t_max = 1000 L`.
//!
//! # Special cases (exact-neumann.md §2.3–§2.5)
//!
//! * [`BarNeumannGravity::periodic`]: `u0 = 1/2`, `g = 1/9`, `L = 1`, hence
//!   `T1 = √(2u0/g) = 3L`; exactly periodic with period `16`, impacts at
//!   `3 + 8k`, take-offs at `5 + 8k`.
//! * [`BarNeumannGravity::paper`]: `u0 = 1/2`, `g = 0.11`, `L = 1` (the
//!   paper's data); first impact `T1 = 10/√11`, every contact lasts `2L`, not
//!   periodic.
//!
//! # Domain of evaluation
//!
//! All evaluations ([`ExactSolution::fields`], [`ExactSolution::u_at`],
//! [`ExactSolution::lambda`], [`ExactSolution::kinks`]) are defined for
//! `t ∈ [0, t_max]`, widened by `δ = 1e-9·(t_max + L)` on both sides to absorb
//! round-off in time grids (`n·dt` slightly above `t_max`). Outside, the
//! fields and `λ` are NaN and the kink list is empty; nothing panics. Points
//! `x` outside `[0, L]` are clamped to `[0, L]`; a NaN `x` gives NaN fields.

use std::fmt;

use crate::{ExactSolution, FarEnd, Fields};

/// Relative distance (in units of `L`) below which an event is snapped onto
/// a breakpoint of the incoming wave (exact-neumann.md §2.2).
const SNAP: f64 = 1e-11;

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
}

impl NeumannError {
    /// Name of the offending parameter (`"u0"`, `"g"`, `"length"`, `"t_max"`).
    pub fn field(&self) -> &'static str {
        match self {
            Self::InitialHeight(_) => "u0",
            Self::Gravity(_) => "g",
            Self::Length(_) => "length",
            Self::TimeHorizon(_) => "t_max",
        }
    }

    /// The rejected value.
    pub fn value(&self) -> f64 {
        match *self {
            Self::InitialHeight(v) | Self::Gravity(v) | Self::Length(v) | Self::TimeHorizon(v) => v,
        }
    }

    /// The allowed range, in words.
    pub fn allowed(&self) -> &'static str {
        match self {
            Self::TimeHorizon(_) => "finite and >= 0",
            _ => "finite and > 0",
        }
    }
}

impl fmt::Display for NeumannError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "bar-neumann-gravity: invalid {} = {} (must be {})",
            self.field(),
            self.value(),
            self.allowed()
        )
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
    /// Start of the piece.
    s: f64,
    /// `η(s)`.
    eta: f64,
    /// `H(s)`.
    h: f64,
    /// Slope of `η`: `+g/2` (β has slope `g`) or `−g/2` (β constant).
    slope: f64,
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
    /// The bar of length `length`, released from rest at height `u0` under
    /// gravity `g`, for times in `[0, t_max]`.
    ///
    /// # Errors
    /// [`NeumannError`] naming the first parameter out of range: `u0`, `g`,
    /// `length` must be finite and `> 0`, `t_max` finite and `>= 0`.
    pub fn new(u0: f64, g: f64, length: f64, t_max: f64) -> Result<Self, NeumannError> {
        Self::build("bar-neumann-gravity-custom", u0, g, length, t_max)
    }

    /// The main benchmark `bar-neumann-gravity`: `u0 = 1/2`, `g = 1/9`,
    /// `L = 1`, exactly periodic with period 16 (exact-neumann.md §2.4).
    ///
    /// # Errors
    /// [`NeumannError::TimeHorizon`] if `t_max` is not finite or is negative.
    pub fn periodic(t_max: f64) -> Result<Self, NeumannError> {
        let mut s = Self::build("bar-neumann-gravity", 0.5, 1.0 / 9.0, 1.0, t_max)?;
        s.period = Some(16.0);
        Ok(s)
    }

    /// The paper's data, `bar-neumann-gravity-0.11`: `u0 = 1/2`, `g = 0.11`,
    /// `L = 1`; not periodic (exact-neumann.md §2.5).
    ///
    /// # Errors
    /// [`NeumannError::TimeHorizon`] if `t_max` is not finite or is negative.
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
        let (pieces, events, built) = march(u0, g, l, horizon);
        let slack = T_SLACK * (t_max + l);
        // Commensurate case T1 = m L, m >= 2 an integer: period 4 (m + 1) L.
        let m = (2.0 * u0 / g).sqrt() / l;
        let period = (m.round() >= 2.0 && (m - m.round()).abs() <= 1e-12 * m).then(|| 4.0 * (m.round() + 1.0) * l);
        Ok(Self {
            name,
            u0,
            g,
            l,
            t_max,
            t_lo: -slack,
            t_hi: (t_max + slack).min(built),
            period,
            pieces,
            events,
        })
    }

    /// Initial height `u0`.
    pub fn u0(&self) -> f64 {
        self.u0
    }

    /// Gravity `g` (the body force is `−g`).
    pub fn gravity(&self) -> f64 {
        self.g
    }

    /// End `t_max` of the time interval the solution was built for.
    pub fn t_max(&self) -> f64 {
        self.t_max
    }

    /// Time of the first impact, `T1 = √(2 u0 / g)`.
    pub fn first_impact(&self) -> f64 {
        (2.0 * self.u0 / self.g).sqrt()
    }

    /// The impacts and take-offs found on `[0, t_max + 2L]`, in time order,
    /// alternating and starting with an impact (a last impact may have no
    /// take-off before `t_max + 2L`).
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

    /// The right-continuous profile `β(s)` of the wave leaving `x = 0`, for
    /// `s ∈ [−2L, t_max]` (0 on `[−2L, 0)`; NaN outside).
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
        let k = self.pieces.partition_point(|p| p.s + two_l <= t).saturating_sub(1);
        2.0 * self.pieces[k].eta_at(t - two_l) - self.g * self.l
    }

    #[inline]
    fn t_ok(&self, t: f64) -> bool {
        t >= self.t_lo && t <= self.t_hi
    }
}

/// Builds the pieces of `η` on `[−2L, horizon]` and the events; returns also
/// the time reached (`>= horizon` unless the march stalled, which does not
/// happen in practice).
fn march(u0: f64, g: f64, l: f64, horizon: f64) -> (Vec<Piece>, Vec<Event>, f64) {
    let two_l = 2.0 * l;
    let gl = g * l;
    let snap = SNAP * l;
    // q has slope ±g: a time snap of `snap` is a q snap of `g·snap`.
    let tol_q = g * snap;
    let half_g = 0.5 * g;
    // β = 0 on [−2L, 0): η(s) = −g (s + L)/2, H(−2L) = 0.
    let mut p = vec![Piece { s: -two_l, eta: half_g * l, h: 0.0, slope: -half_g }];
    let mut ev: Vec<Event> = Vec::new();
    let mut t = 0.0_f64;
    let mut contact = false;
    let mut just_took_off = false;
    let mut j = 0_usize; // incoming piece: the one containing t − 2L
    let mut stall = 0_u32;
    while t < horizon {
        while j + 1 < p.len() && p[j + 1].s + two_l <= t {
            j += 1;
        }
        let inc = p[j];
        let s_in = t - two_l;
        let eta_in = inc.eta_at(s_in);
        let q0 = 2.0 * eta_in - gl;
        let t_start = t;
        if contact {
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
                push_piece(&mut p, t, -eta_in, -inc.slope, gl, Some(-u0 - inc.h_at(s_in)));
                let w_end = window_end(&p, j, t, two_l).min(horizon);
                let dt = w_end - t;
                if inc.slope > 0.0 && q0 + 2.0 * inc.slope * dt > 0.0 {
                    // Smooth take-off: q crosses 0 linearly inside the window.
                    let r = -q0 / (2.0 * inc.slope);
                    if dt - r <= snap {
                        t = w_end; // on the breakpoint: decided at the next step
                    } else {
                        t += r;
                        ev.push(Event { time: t, kind: EventKind::TakeOff });
                        contact = false;
                        just_took_off = true;
                    }
                } else {
                    t = w_end;
                }
            }
        } else {
            push_piece(&mut p, t, eta_in - gl, inc.slope, gl, None);
            let w_end = window_end(&p, j, t, two_l).min(horizon);
            let dt = w_end - t;
            let a0 = p.last().map_or(0.0, |c| c.h_at(t)) + inc.h_at(s_in) + u0;
            let hit = impact_root(a0, q0, inc.slope, dt).and_then(|r| {
                if r <= snap {
                    // Right after a take-off z rises: a root at 0 is spurious.
                    (!just_took_off).then_some(t)
                } else if dt - r <= snap {
                    Some(w_end)
                } else {
                    Some(t + r)
                }
            });
            match hit {
                Some(ti) => {
                    t = ti;
                    ev.push(Event { time: t, kind: EventKind::Impact });
                    contact = true;
                    just_took_off = false;
                }
                None => t = w_end,
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
    (p, ev, t)
}

/// End of the window starting at `t` on which the incoming piece `j` stays
/// the same: its end shifted by `2L` (if `j` is the last piece, it extends
/// at least to `t`, hence the window to `t + 2L`).
#[inline]
fn window_end(p: &[Piece], j: usize, t: f64, two_l: f64) -> f64 {
    if j + 1 < p.len() {
        p[j + 1].s + two_l
    } else {
        t + two_l
    }
}

/// Starts a new piece of `η` at `t` (value `eta`, slope `slope`), replacing a
/// piece that would start at `t` too, and merging with the previous piece if
/// it is the same linear function (free fall copies itself). `H(t)` is
/// `h_anchor` if given, else `H` is continued continuously.
fn push_piece(p: &mut Vec<Piece>, t: f64, eta: f64, slope: f64, gl: f64, h_anchor: Option<f64>) {
    let mut h = h_anchor;
    if p.len() > 1 && p.last().is_some_and(|c| c.s == t) {
        let popped = p.pop().map(|c| c.h);
        h = h.or(popped);
    }
    let Some(last) = p.last() else { return };
    let tol = 1e-13 * (eta.abs() + gl);
    if last.slope == slope && (last.eta_at(t) - eta).abs() <= tol {
        return;
    }
    let h = h.unwrap_or_else(|| last.h_at(t));
    p.push(Piece { s: t, eta, h, slope });
}

/// First downward root `r ∈ [0, dt]` of `z(r) = a0 + a1 r + a2 r²`
/// (`a2 = ±g/2 ≠ 0`), if any; cancellation-free (exact-neumann.md §2.2).
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

    /// `u`, `u_x`, `u_t` at `(x, t)`; `x` is clamped to `[0, L]`; NaN for
    /// `t` outside `[0, t_max]` (± the slack of the module docs) or NaN `x`.
    /// On a kink, the values of the piece on the larger-`x` side; at `x = L`,
    /// the values right-continuous in `t` (`u_x(L, t) = 0` exactly).
    fn fields(&self, x: f64, t: f64) -> Fields {
        if !self.t_ok(t) || x.is_nan() {
            return Fields { u: f64::NAN, ux: f64::NAN, ut: f64::NAN };
        }
        let x = x.clamp(0.0, self.l);
        let (s1, s2) = (t - x, t + x - 2.0 * self.l);
        // Ties towards larger x: β(s1⁻) and β(s2⁺). At x = L there is no
        // larger x: both arguments equal t − L and take the same
        // (right-continuous) piece, so that u_x(L, t) = 0 exactly.
        let k1 = if x < self.l { find_left(&self.pieces, s1) } else { find_right(&self.pieces, s1) };
        let p1 = &self.pieces[k1];
        let p2 = &self.pieces[find_right(&self.pieces, s2)];
        let (e1, e2) = (p1.eta_at(s1), p2.eta_at(s2));
        Fields {
            u: self.u0 + 0.5 * self.g * x * (x - 2.0 * self.l) + p1.h_at(s1) + p2.h_at(s2),
            ux: self.g * (x - self.l) + e2 - e1,
            ut: e1 + e2,
        }
    }

    /// `u(x_i, t)` for all `i`, in `O(n + pieces)` when the points are sorted
    /// increasingly (the pieces are walked monotonically from one point to
    /// the next; unsorted points are still handled correctly, only slower).
    /// Same conventions as `fields` (clamping, NaN).
    fn u_at(&self, t: f64, xs: &[f64], out: &mut [f64]) {
        if !self.t_ok(t) {
            out.iter_mut().take(xs.len()).for_each(|o| *o = f64::NAN);
            return;
        }
        let (l, two_l, half_g, u0) = (self.l, 2.0 * self.l, 0.5 * self.g, self.u0);
        let p = &self.pieces[..];
        let x0 = xs.first().map_or(0.0, |x| x.clamp(0.0, l));
        let mut k1 = find_left(p, t - x0);
        let mut k2 = find_right(p, t + x0 - two_l);
        for (&x, o) in xs.iter().zip(out.iter_mut()) {
            if x.is_nan() {
                *o = f64::NAN;
                continue;
            }
            let x = x.clamp(0.0, l);
            let (s1, s2) = (t - x, t + x - two_l);
            k1 = if x < l { seek_left(p, k1, s1) } else { seek_right(p, k1, s1) };
            k2 = seek_right(p, k2, s2);
            *o = u0 + half_g * x * (x - two_l) + p[k1].h_at(s1) + p[k2].h_at(s2);
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
