//! Vibro-impact analysis observers: impact maps, Poincaré sections and impact
//! statistics, the quantities read in studies of tubes rattling in their
//! supports, gear rattle and impact dampers.
//!
//! * [`ImpactObserver`]: one [`Impact`] per maximal run of levels in which a
//!   contact is active (time, forcing phase, pre-impact velocity, impulse,
//!   duration), optionally a CSV row per impact;
//! * [`PoincarePoint`]s from [`PoincareObserver`]: the tip's displacement and
//!   velocity at the stroboscopic times `t_k = k·2π/Ω`;
//! * [`WindowObserver`]: RMS contact force and largest tip excursion;
//! * [`Summary`]: the statistics of all three over the record window
//!   `t >= record_from`, one CSV row per run ([`Summary::csv_header`]).
//!
//! [`VibroConfig`] builds all of them in one call ([`VibroConfig::build`],
//! each piece optional: a piece not requested costs nothing). Every observer
//! allocates at construction only, except that the in-memory lists of
//! impacts and Poincaré points grow (amortised doubling) past the capacity
//! reserved at construction ([`VibroConfig::impact_capacity`]; the Poincaré
//! list reserves its exact size when [`VibroConfig::t_end`] is given).
//!
//! ## Contact forces and impulses
//!
//! A contact's force `λ` enters the equations as `−λ e_c` ([`crate::active_code`]:
//! `λ <= 0` at a lower bound, `>= 0` at an upper one), and [`Sample::forces`]
//! holds every contact's `λ` from the step that reached the level. For both
//! families of schemes the momentum the contact gives the structure over a
//! run of levels is exactly `J = −dt Σ λ` over that run:
//!
//! * Paoli–Schatzman, `M (U^{n+1} − 2U^n + U^{n−1})/dt² + … = F − λ^n e_c`:
//!   `M (V^{n+1/2} − V^{n−1/2}) = dt (F − K Ū^n) − dt λ^n e_c`, so the step
//!   that reaches `t_{n+1}` (whose sample carries `λ^n`) receives the contact
//!   momentum `−dt λ^n` exactly;
//! * Newmark / θ (momentum form), `P^{n+1} = P^n + dt ((1−γ) R^n + γ R^{n+1})`,
//!   `R^k ∋ −λ^k e_c`: `λ^k` enters two consecutive momentum updates with
//!   weights `γ dt` and `(1−γ) dt`, so by the end of the step after a run the
//!   momentum received is `−dt Σ λ^k` exactly.
//!
//! `J` therefore has the sign of the force on the structure: `> 0` (upwards)
//! at a lower stop, `< 0` at an upper one. For a point mass `m` hitting a
//! rigid stop at speed `|V|` with restitution `r`, `J = (1 + r) m |V|`.

use crate::{Observer, RowSink, RunError, Sample};
use signorini_contact::Active;
use signorini_schemes::{Bounds, Dynamics};
use std::f64::consts::TAU;
use std::io::Write;

/// A row sink on `w` with `header` written (and flushed) at once.
fn header_sink<W: Write>(w: W, header: &str) -> Result<RowSink<W>, RunError> {
    let mut s = RowSink::new(w);
    s.row(|b| b.write_all(header.as_bytes()))?;
    s.flush()?;
    Ok(s)
}

/// Writes `,x` as `{:.12e}`, or `,` (an empty cell) when `x` is not finite.
fn cell(buf: &mut Vec<u8>, x: f64) -> std::io::Result<()> {
    buf.push(b',');
    if x.is_finite() {
        write!(buf, "{x:.12e}")
    } else {
        Ok(())
    }
}

/// The forcing phase `Ω t mod 2π`, in `[0, 2π)`; NaN without `Ω`.
pub fn forcing_phase(omega: Option<f64>, t: f64) -> f64 {
    match omega {
        Some(w) => {
            let p = (w * t).rem_euclid(TAU);
            // rem_euclid can round up to 2π itself for a tiny negative argument.
            if p >= TAU {
                0.0
            } else {
                p
            }
        }
        None => f64::NAN,
    }
}

/// Which estimate gave an impact's time and velocity (see [`ImpactObserver`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossing {
    /// The quadratic through the last three free levels (second order).
    Quadratic,
    /// The line through the last two levels before the impact (first order:
    /// fewer than three free levels).
    Linear,
    /// No level before the impact: the time of its first active level and a
    /// NaN velocity.
    None,
}

/// One impact: a maximal run of consecutive levels in which a contact's
/// status is not [`Active::None`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// The contact's index (contact order, as in [`Sample::forces`]).
    pub stop: usize,
    /// Estimated impact time `t*` (the crossing of the bound, see
    /// [`ImpactObserver`]).
    pub t: f64,
    /// Forcing phase `Ω t* mod 2π` in `[0, 2π)`; NaN without `Ω`.
    pub phase: f64,
    /// Pre-impact velocity at `t*`, signed (`< 0` hitting a lower stop).
    pub velocity: f64,
    /// Impulse `J = −dt Σ λ` over the run (the momentum given to the
    /// structure: `> 0` at a lower stop; see the module docs). A sustained
    /// contact is one long impact: its `J` includes the reaction to the
    /// steady loads over its duration.
    pub impulse: f64,
    /// Contact duration: the number of active levels times `dt` (a
    /// rebound resolved in one step lasts `dt`).
    pub duration: f64,
    /// The first active level.
    pub first_level: usize,
    /// Which bound was hit.
    pub side: Active,
    /// How `t` and `velocity` were estimated.
    pub crossing: Crossing,
}

/// An impact in progress.
#[derive(Clone, Copy, Debug)]
struct Open {
    t: f64,
    velocity: f64,
    crossing: Crossing,
    first_level: usize,
    side: Active,
    sum_lambda: f64,
    levels: usize,
}

/// Per-contact state of an [`ImpactObserver`].
#[derive(Clone, Copy, Debug)]
struct Track {
    dof: usize,
    bounds: Bounds,
    /// `(t, u)` of the last three levels, newest first.
    hist: [(f64, f64); 3],
    /// Levels held in `hist` (at most 3).
    seen: usize,
    /// Consecutive free levels ending at the newest one (at most 3).
    free: usize,
    open: Option<Open>,
}

/// The [`Track`]s of an [`ImpactObserver`]: up to two held in the observer
/// itself (a beam on its tip's stops has one contact), so that a step reads
/// no other memory for them; more in a `Vec`.
#[derive(Clone, Debug)]
// Inline on purpose: the point is not to read elsewhere at every step.
#[allow(clippy::large_enum_variant)]
enum Tracks {
    Few([Track; 2], usize),
    Many(Vec<Track>),
}

impl Tracks {
    fn new(contacts: &[(usize, Bounds)]) -> Self {
        let track = |&(dof, bounds): &(usize, Bounds)| Track { dof, bounds, hist: [(f64::NAN, f64::NAN); 3], seen: 0, free: 0, open: None };
        if contacts.len() <= 2 {
            let blank = track(&(0, Bounds { lo: 0.0, hi: 0.0 }));
            let mut few = [blank; 2];
            for (f, c) in few.iter_mut().zip(contacts) {
                *f = track(c);
            }
            Tracks::Few(few, contacts.len())
        } else {
            Tracks::Many(contacts.iter().map(track).collect())
        }
    }
}

impl std::ops::Deref for Tracks {
    type Target = [Track];
    #[inline]
    fn deref(&self) -> &[Track] {
        match self {
            Tracks::Few(t, n) => &t[..*n],
            Tracks::Many(v) => v,
        }
    }
}

impl std::ops::DerefMut for Tracks {
    #[inline]
    fn deref_mut(&mut self) -> &mut [Track] {
        match self {
            Tracks::Few(t, n) => &mut t[..*n],
            Tracks::Many(v) => v,
        }
    }
}

/// The crossing of `bound` by the quadratic through `u(−2), u(−1), u(0)`
/// (levels in units of `dt`, `s = 0` the last free level): the root of
/// `a₂ s² + a₁ s + (u₀ − b)`, `a₁ = (3u₀ − 4u₋₁ + u₋₂)/2`, `a₂ = (u₀ − 2u₋₁
/// + u₋₂)/2`, at which the fit moves into the obstacle (slope of the sign of
/// `inward`: `−1` at a lower bound, `+1` at an upper one; of the two roots
/// exactly one does, unless they coincide), clamped to `[−2, 1]` (the
/// fitted levels and the step to the first active level). Without a real
/// root (the fit turns before the bound: a grazing contact) the fit's
/// closest approach, its vertex, clamped likewise. Returns `(s, du/ds at s)`.
fn quadratic_crossing(u2: f64, u1: f64, u0: f64, bound: f64, inward: f64) -> (f64, f64) {
    let a1 = 0.5 * (3.0 * u0 - 4.0 * u1 + u2);
    let a2 = 0.5 * (u0 - 2.0 * u1 + u2);
    let c = u0 - bound;
    let slope = |s: f64| a1 + 2.0 * a2 * s;
    let fin = |s: f64| {
        let s = if s.is_nan() { 0.0 } else { s.clamp(-2.0, 1.0) };
        (s, slope(s))
    };
    if a2 == 0.0 {
        return fin(if a1 * inward > 0.0 { -c / a1 } else { 0.0 });
    }
    let d = a1 * a1 - 4.0 * a2 * c;
    if d < 0.0 {
        return fin(-a1 / (2.0 * a2));
    }
    // The two roots without cancellation: q/a₂ and c/q.
    let q = -0.5 * (a1 + a1.signum() * d.sqrt());
    if q == 0.0 {
        return fin(0.0);
    }
    let (r1, r2) = (q / a2, c / q);
    fin(if slope(r2) * inward > 0.0 { r2 } else { r1 })
}

/// The crossing of `bound` by the line through `(0, u_a)` and `(1, u_b)`
/// (levels in units of `dt`): `s = (b − u_a)/(u_b − u_a)` clamped to
/// `[0, hi]` when the line moves into the obstacle (`inward` as in
/// [`quadratic_crossing`]), else `away`. Returns `(s, u_b − u_a)`.
fn linear_crossing(ua: f64, ub: f64, bound: f64, inward: f64, hi: f64, away: f64) -> (f64, f64) {
    let slope = ub - ua;
    let s = if slope * inward > 0.0 { (bound - ua) / slope } else { away };
    (if s.is_nan() { away } else { s.clamp(0.0, hi) }, slope)
}

/// Detects impacts at every contact (see [`Impact`]) and writes one CSV row
/// per impact as it completes, `stop,t,phase,velocity,impulse,duration`
/// (`{:.12e}`; an empty cell for a NaN phase or velocity), through a
/// [`RowSink`]. Every impact goes to the CSV; those with `t* >= record_from`
/// are also kept in memory ([`impacts`](Self::impacts)) for the
/// statistics ([`stats`](Self::stats)). An impact still in progress when the
/// run ends is closed at the last level.
///
/// **Impact time and velocity**, from displacements alone. With `m` the
/// first active level and `b` the bound of the side that became active:
///
/// * at least three free levels before `m` (`m−3, m−2, m−1`): the quadratic
///   through them and its crossing of `b` into the obstacle (of its two
///   crossings, the one where it moves towards the obstacle), clamped to
///   `[t_{m−3}, t_m]`; `t* = t_{m−1} + s dt` and the velocity is its
///   derivative there. The local error is `O(dt³)` in the displacement, so
///   `t*` and the velocity are second-order accurate (exact for a
///   parabola). The crossing can precede `t_{m−1}`: Paoli–Schatzman with
///   restitution `e > 0` constrains `(u^{n+1} + e u^{n−1})/(1+e)`, so a
///   free level may already lie beyond the bound. A fit that turns before
///   reaching `b` (grazing) gives its vertex (closest approach), clamped
///   likewise, and the (small) slope there;
/// * fewer free levels (chatter, or an impact at the very start): the line
///   through the two levels before `m` (one of them may be the last level of
///   the previous impact), its crossing clamped to `[t_{m−2}, t_m]`, or, with
///   only one level before `m`, the line through it and level `m`, its
///   crossing clamped to `[t_{m−1}, t_m]`; a line moving away from the
///   obstacle gives `t* = t_{m−1}`; the secant is the velocity (first
///   order);
/// * no level before `m`: `t* = t_m`, velocity NaN.
///
/// **Duration**: (number of active levels)·`dt`. **Phase**: `Ω t* mod 2π`.
pub struct ImpactObserver<W: Write> {
    tracks: Tracks,
    dt: f64,
    omega: Option<f64>,
    record_from: f64,
    out: Option<RowSink<W>>,
    kept: Vec<Impact>,
    total: usize,
    t_last: f64,
}

impl<W: Write> ImpactObserver<W> {
    /// The CSV columns, in order.
    pub const HEADER: &'static str = "stop,t,phase,velocity,impulse,duration";

    /// An observer of the contacts `(dof, bounds)` (in contact order), time
    /// step `dt`, forcing frequency `omega` (phases NaN without), keeping the
    /// impacts from `record_from` on (room for `capacity` reserved), writing
    /// to `csv` when given (header at once).
    pub fn new(contacts: &[(usize, Bounds)], dt: f64, omega: Option<f64>, record_from: f64, capacity: usize, csv: Option<W>) -> Result<Self, RunError> {
        let tracks = Tracks::new(contacts);
        let out = csv.map(|w| header_sink(w, Self::HEADER)).transpose()?;
        Ok(Self { tracks, dt, omega, record_from, out, kept: Vec::with_capacity(capacity), total: 0, t_last: f64::NAN })
    }

    /// The impacts with `t >= record_from`, in order of completion.
    pub fn impacts(&self) -> &[Impact] {
        &self.kept
    }

    /// Every impact completed so far (transient included).
    pub fn total(&self) -> usize {
        self.total
    }

    /// The statistics of the kept impacts over the window `[record_from,
    /// t_last]` (see [`ImpactStats`]).
    pub fn stats(&self) -> ImpactStats {
        ImpactStats::of(&self.kept, self.t_last - self.record_from, self.omega)
    }

    fn close(&mut self, i: usize) -> Result<(), RunError> {
        let Some(o) = self.tracks[i].open.take() else { return Ok(()) };
        let imp = Impact {
            stop: i,
            t: o.t,
            phase: forcing_phase(self.omega, o.t),
            velocity: o.velocity,
            impulse: -self.dt * o.sum_lambda,
            duration: o.levels as f64 * self.dt,
            first_level: o.first_level,
            side: o.side,
            crossing: o.crossing,
        };
        self.total += 1;
        if imp.t >= self.record_from {
            self.kept.push(imp);
        }
        if let Some(out) = &mut self.out {
            out.row(|b| {
                write!(b, "{}", imp.stop)?;
                for x in [imp.t, imp.phase, imp.velocity, imp.impulse, imp.duration] {
                    cell(b, x)?;
                }
                Ok(())
            })?;
        }
        Ok(())
    }

    /// The impact time and velocity of an impact whose first active level is
    /// `(t_m, u_m)` (see the type's docs).
    fn estimate(tr: &Track, tm: f64, um: f64, side: Active, dt: f64) -> (f64, f64, Crossing) {
        let (bound, inward) = if side == Active::Upper { (tr.bounds.hi, 1.0) } else { (tr.bounds.lo, -1.0) };
        let [(t0, u0), (_, u1), (_, u2)] = tr.hist;
        if tr.free >= 3 {
            let (s, d) = quadratic_crossing(u2, u1, u0, bound, inward);
            (t0 + s * dt, d / dt, Crossing::Quadratic)
        } else if tr.seen >= 2 {
            // s measured from level m−2: t* = t_{m−2} + s dt.
            let (s, d) = linear_crossing(u1, u0, bound, inward, 2.0, 1.0);
            (t0 + (s - 1.0) * dt, d / dt, Crossing::Linear)
        } else if tr.seen == 1 {
            let (s, d) = linear_crossing(u0, um, bound, inward, 1.0, 0.0);
            (t0 + s * (tm - t0), d / (tm - t0), Crossing::Linear)
        } else {
            (tm, f64::NAN, Crossing::None)
        }
    }
}

impl<W: Write> Observer for ImpactObserver<W> {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if s.forces.len() != self.tracks.len() || s.status.len() != self.tracks.len() {
            return Err(RunError::Invalid { field: "vibro.contacts", value: self.tracks.len() as f64, allowed: "one entry per contact of the run, in contact order" });
        }
        self.t_last = s.t;
        for i in 0..self.tracks.len() {
            let dof = self.tracks[i].dof;
            let Some(&u) = s.u.get(dof) else {
                return Err(RunError::Invalid { field: "vibro.contacts.dof", value: dof as f64, allowed: "a dof of the problem" });
            };
            let st = s.status[i];
            if st != Active::None {
                let tr = &self.tracks[i];
                let mut o = match tr.open {
                    Some(o) => o,
                    None => {
                        let (t, velocity, crossing) = Self::estimate(tr, s.t, u, st, self.dt);
                        Open { t, velocity, crossing, first_level: s.n, side: st, sum_lambda: 0.0, levels: 0 }
                    }
                };
                o.sum_lambda += s.forces[i];
                o.levels += 1;
                let tr = &mut self.tracks[i];
                tr.open = Some(o);
                tr.free = 0;
            } else {
                if self.tracks[i].open.is_some() {
                    self.close(i)?;
                }
                let tr = &mut self.tracks[i];
                tr.free = (tr.free + 1).min(3);
            }
            let tr = &mut self.tracks[i];
            tr.hist = [(s.t, u), tr.hist[0], tr.hist[1]];
            tr.seen = (tr.seen + 1).min(3);
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), RunError> {
        for i in 0..self.tracks.len() {
            self.close(i)?;
        }
        match &mut self.out {
            Some(out) => out.flush(),
            None => Ok(()),
        }
    }
}

/// Impact statistics over a window of length `W` (from [`ImpactObserver::stats`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactStats {
    /// Number of impacts.
    pub count: usize,
    /// Impacts per forcing period, `count / (W Ω / 2π)` (NaN without `Ω`
    /// or for `W <= 0`).
    pub per_period: f64,
    /// Mean of `|J_i|` (0 without impacts).
    pub mean_impulse: f64,
    /// Largest `|J_i|` (0 without impacts).
    pub max_impulse: f64,
    /// Impact power `P = Σ |J_i| |v_i| / W` (impacts with a NaN velocity
    /// left out; NaN for `W <= 0`): the impact work rate of wear laws. For a
    /// point mass and restitution `r`, `J = (1+r) m |v|`, and the kinetic
    /// energy an impact dissipates is `½ m v² (1 − r²) = (1−r)/2 · |J| |v|`:
    /// `(1−r)/2 · P` is the power the impacts dissipate.
    pub power: f64,
    /// The window length `W`.
    pub window: f64,
}

impl ImpactStats {
    /// The statistics of `impacts` over a window of length `window`.
    pub fn of(impacts: &[Impact], window: f64, omega: Option<f64>) -> Self {
        let count = impacts.len();
        let (mut sum, mut max, mut work) = (0.0_f64, 0.0_f64, 0.0_f64);
        for imp in impacts {
            let j = imp.impulse.abs();
            sum += j;
            max = max.max(j);
            if imp.velocity.is_finite() {
                work += j * imp.velocity.abs();
            }
        }
        let defined = window > 0.0;
        let per_period = match omega {
            Some(w) if defined => count as f64 / (window * w / TAU),
            _ => f64::NAN,
        };
        Self { count, per_period, mean_impulse: if count > 0 { sum / count as f64 } else { 0.0 }, max_impulse: max, power: if defined { work / window } else { f64::NAN }, window }
    }
}

/// A point of the stroboscopic Poincaré section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoincarePoint {
    /// The period index `k`.
    pub k: u64,
    /// `t_k = k · (2π/Ω)`, computed from `k` (no accumulation); the forcing
    /// phase is 0 there by construction.
    pub t: f64,
    /// The tip displacement at `t_k`.
    pub displacement: f64,
    /// The tip velocity at `t_k`.
    pub velocity: f64,
}

/// The cubic through `u` at the nodes `x = −1, 0, 1, 2` and its derivative,
/// at `x`.
fn cubic4(u: [f64; 4], x: f64) -> (f64, f64) {
    const NODES: [f64; 4] = [-1.0, 0.0, 1.0, 2.0];
    let (mut val, mut der) = (0.0, 0.0);
    for (i, (&xi, &ui)) in NODES.iter().zip(&u).enumerate() {
        let (mut denom, mut prod, mut dprod) = (1.0, 1.0, 0.0);
        for (_, &xj) in NODES.iter().enumerate().filter(|&(j, _)| j != i) {
            denom *= xi - xj;
            // (prod · (x − x_j))' = dprod · (x − x_j) + prod.
            dprod = dprod * (x - xj) + prod;
            prod *= x - xj;
        }
        val += ui * prod / denom;
        der += ui * dprod / denom;
    }
    (val, der)
}

/// Samples one dof (the tip) at the stroboscopic times `t_k = k·2π/Ω`,
/// `t_k >= record_from`: displacement and velocity from the cubic through
/// the four levels `t_{j−1}, t_j, t_{j+1}, t_{j+2}` with `t_j <= t_k <
/// t_{j+1}` and its derivative (Lagrange, levels evenly spaced by `dt`):
/// errors `O(dt⁴)` and `O(dt³)` on smooth stretches; at the first levels and
/// at the end of the run the stencil is the first or last four levels (an
/// extrapolation-free one-sided cubic, same orders). A point whose stencil
/// contains an impact (a kink of the displacement) is only `O(dt)` in the
/// velocity and `O(dt²)` in the displacement there: it is kept as computed
/// (the section of a vibro-impact orbit is usually taken away from impacts;
/// choose the phase of `Ω t` accordingly). Rows `t,displacement,velocity`
/// (`{:.12e}`) go through a [`RowSink`] when a writer is given; the points
/// are kept in memory ([`points`](Self::points)). Fewer than four levels in
/// the whole run give no point.
///
/// It also tracks, over the levels with `t_n >= record_from`, the range of
/// the tip displacement and of its difference velocity `(u_n − u_{n−1})/dt`:
/// the scales of the period test ([`period`](Self::period)).
pub struct PoincareObserver<W: Write> {
    tip: usize,
    dt: f64,
    period: f64,
    /// `θ/Ω`: the section's time offset within a period.
    offset: f64,
    record_from: f64,
    next_k: u64,
    /// `(t, u)` of the last four levels, oldest first.
    win: [(f64, f64); 4],
    seen: usize,
    out: Option<RowSink<W>>,
    points: Vec<PoincarePoint>,
    range_u: (f64, f64),
    range_v: (f64, f64),
}

impl<W: Write> PoincareObserver<W> {
    /// The CSV columns, in order.
    pub const HEADER: &'static str = "t,displacement,velocity";

    /// An observer of dof `tip` for forcing frequency `omega > 0`, from
    /// `record_from >= 0` on, time step `dt`; `capacity` points reserved;
    /// writing to `csv` when given (header at once).
    pub fn new(tip: usize, dt: f64, omega: f64, record_from: f64, capacity: usize, csv: Option<W>) -> Result<Self, RunError> {
        if !(omega > 0.0 && omega.is_finite()) {
            return Err(RunError::Invalid { field: "vibro.omega", value: omega, allowed: "finite and > 0 (a Poincaré section needs the forcing frequency)" });
        }
        let period = TAU / omega;
        // The first k with k·T >= record_from.
        let mut k = (record_from / period).ceil().max(0.0);
        if k >= 1.0 && (k - 1.0) * period >= record_from {
            k -= 1.0;
        }
        let out = csv.map(|w| header_sink(w, Self::HEADER)).transpose()?;
        let empty = (f64::INFINITY, f64::NEG_INFINITY);
        Ok(Self { tip, dt, period, offset: 0.0, record_from, next_k: k as u64, win: [(f64::NAN, f64::NAN); 4], seen: 0, out, points: Vec::with_capacity(capacity), range_u: empty, range_v: empty })
    }

    /// The points so far.
    pub fn points(&self) -> &[PoincarePoint] {
        &self.points
    }

    /// `t_k = k · 2π/Ω + θ/Ω` (θ the section's phase, 0 by default).
    fn t_of(&self, k: u64) -> f64 {
        k as f64 * self.period + self.offset
    }

    /// The section at forcing phase `theta ∈ [0, 2π)` instead of 0: samples
    /// at `t_k = (k + θ/2π)·2π/Ω`, the first with `t_k >= record_from`.
    /// Refused (naming `vibro.phase`) outside `[0, 2π)`; call before the run.
    pub fn with_phase(mut self, theta: f64) -> Result<Self, RunError> {
        if !(0.0..TAU).contains(&theta) {
            return Err(RunError::Invalid { field: "vibro.phase", value: theta, allowed: "[0, 2π)" });
        }
        self.offset = theta / TAU * self.period;
        let mut k = ((self.record_from - self.offset) / self.period).ceil().max(0.0);
        if k >= 1.0 && (k - 1.0) * self.period + self.offset >= self.record_from {
            k -= 1.0;
        }
        self.next_k = k as u64;
        Ok(self)
    }

    /// The scales of the period test: the ranges `(max − min)` of the tip
    /// displacement and of its difference velocity over the window (0 before
    /// any level of the window).
    pub fn scales(&self) -> (f64, f64) {
        let r = |(lo, hi): (f64, f64)| if hi >= lo { hi - lo } else { 0.0 };
        (r(self.range_u), r(self.range_v))
    }

    /// The response period of the points (see [`response_period`]) with
    /// the scales of [`scales`](Self::scales).
    pub fn period(&self, p_max: usize, tol: f64) -> Option<usize> {
        let (sx, sv) = self.scales();
        response_period(&self.points, p_max, tol, sx, sv)
    }

    /// Emits the point `k` from the current four levels.
    fn emit(&mut self, k: u64) -> Result<(), RunError> {
        let t = self.t_of(k);
        let (t1, _) = self.win[1];
        let x = (t - t1) / self.dt;
        let (d, v) = cubic4(self.win.map(|w| w.1), x);
        let p = PoincarePoint { k, t, displacement: d, velocity: v / self.dt };
        self.points.push(p);
        if let Some(out) = &mut self.out {
            out.row(|b| {
                write!(b, "{:.12e}", p.t)?;
                cell(b, p.displacement)?;
                cell(b, p.velocity)
            })?;
        }
        Ok(())
    }
}

impl<W: Write> Observer for PoincareObserver<W> {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let Some(&u) = s.u.get(self.tip) else {
            return Err(RunError::Invalid { field: "vibro.tip", value: self.tip as f64, allowed: "a dof of the problem" });
        };
        if s.t >= self.record_from {
            self.range_u = (self.range_u.0.min(u), self.range_u.1.max(u));
            if self.seen > 0 {
                let (tp, up) = self.win[3];
                let v = (u - up) / (s.t - tp);
                self.range_v = (self.range_v.0.min(v), self.range_v.1.max(v));
            }
        }
        self.win = [self.win[1], self.win[2], self.win[3], (s.t, u)];
        self.seen = (self.seen + 1).min(4);
        if self.seen == 4 {
            // Points before t_{n−1}: the centred stencil (or, at the start,
            // the first four levels).
            while self.t_of(self.next_k) < self.win[2].0 {
                self.emit(self.next_k)?;
                self.next_k += 1;
            }
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), RunError> {
        if self.seen == 4 {
            while self.t_of(self.next_k) <= self.win[3].0 {
                self.emit(self.next_k)?;
                self.next_k += 1;
            }
        }
        match &mut self.out {
            Some(out) => out.flush(),
            None => Ok(()),
        }
    }
}

/// The response period of a sequence of Poincaré points: the smallest `p`
/// in `1..=p_max` such that the last `L = min(N, 2 p_max)` points repeat
/// with period `p`, i.e. every pair `j, j+p` in them satisfies
/// `|x_{j+p} − x_j| <= tol · scale_x` and `|v_{j+p} − v_j| <= tol ·
/// scale_v`; `p` is tried only when `2p <= L` (at least two full periods).
/// `None`: not periodic (within `p_max`), or too few points.
///
/// The scales are the spread of the orbit, not of the points: the spread of
/// the points themselves vanishes for a period-1 response.
/// [`PoincareObserver::period`] passes the ranges of the tip displacement
/// and velocity over the whole window (which contain the points' spread).
pub fn response_period(points: &[PoincarePoint], p_max: usize, tol: f64, scale_x: f64, scale_v: f64) -> Option<usize> {
    let l = points.len().min(2 * p_max);
    let tail = &points[points.len() - l..];
    (1..=p_max)
        .filter(|&p| 2 * p <= l)
        .find(|&p| tail.iter().zip(&tail[p..]).all(|(a, b)| (b.displacement - a.displacement).abs() <= tol * scale_x && (b.velocity - a.velocity).abs() <= tol * scale_v))
}

/// Contact-force and tip statistics over the levels with `t_n >=
/// record_from`: the RMS total contact force `sqrt(mean_n Σ_i λ_i²)` over
/// the stepped levels (those with [`Sample::lambda`]; each carries one
/// step's forces, so the mean over levels is the time mean), and the
/// largest `|u_tip|`.
#[derive(Clone, Debug)]
pub struct WindowObserver {
    tip: usize,
    record_from: f64,
    sum_sq: f64,
    levels: usize,
    max_abs_tip: f64,
}

impl WindowObserver {
    /// For dof `tip`, from `record_from` on.
    pub fn new(tip: usize, record_from: f64) -> Self {
        Self { tip, record_from, sum_sq: 0.0, levels: 0, max_abs_tip: 0.0 }
    }

    /// RMS total contact force over the window (0 before any stepped level).
    pub fn rms_force(&self) -> f64 {
        if self.levels == 0 {
            0.0
        } else {
            (self.sum_sq / self.levels as f64).sqrt()
        }
    }

    /// Largest `|u_tip|` over the window.
    pub fn max_abs_tip(&self) -> f64 {
        self.max_abs_tip
    }
}

impl Observer for WindowObserver {
    #[inline]
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let Some(&u) = s.u.get(self.tip) else {
            return Err(RunError::Invalid { field: "vibro.tip", value: self.tip as f64, allowed: "a dof of the problem" });
        };
        if s.t < self.record_from {
            return Ok(());
        }
        self.max_abs_tip = self.max_abs_tip.max(u.abs());
        if s.lambda.is_some() {
            self.sum_sq += s.forces.iter().map(|l| l * l).sum::<f64>();
            self.levels += 1;
        }
        Ok(())
    }
}

/// The statistics of a run over its record window, one CSV row per run.
/// `None` marks a piece that was not requested.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    /// Impact statistics (impact observer).
    pub impacts: Option<ImpactStats>,
    /// RMS total contact force (window observer).
    pub rms_force: Option<f64>,
    /// Largest `|u_tip|` (window observer).
    pub max_abs_tip: Option<f64>,
    /// Poincaré section: `(points in the window, response period)`, the
    /// period `None` when not periodic (see [`response_period`]).
    pub poincare: Option<(usize, Option<usize>)>,
}

impl Summary {
    /// The CSV columns, in order.
    pub const COLUMNS: [&'static str; 10] = ["impacts", "impacts_per_period", "mean_impulse", "max_impulse", "impact_power", "rms_force", "max_abs_tip", "period", "window", "poincare_points"];

    /// The columns whose values depend on the time step on a chattering
    /// contact (the beam between rigid stops: `cargo xtask beam-statistics`):
    /// they count or average over *active runs* (chatter counted as separate
    /// impacts: 140 and 313 per period at dt = 5e-5 and 1e-5 on fig. 2), or
    /// sample an impulsive force per step (`rms_force`: 92 and 137). Read
    /// `impact_power` (and, from `impacts.csv`, impulses per unit time)
    /// instead; they converge in dt.
    pub const STEP_DEPENDENT: [&'static str; 4] = ["impacts", "impacts_per_period", "mean_impulse", "rms_force"];

    /// The header line (no newline):
    /// `impacts,impacts_per_period,mean_impulse,max_impulse,impact_power,rms_force,max_abs_tip,period,window,poincare_points`.
    /// A sweep prefixes its own columns (`param,run,`).
    pub fn csv_header() -> String {
        Self::COLUMNS.join(",")
    }

    /// Writes the row (no leading comma, no newline) in the order of
    /// [`COLUMNS`](Self::COLUMNS): `impacts` an integer; `period` the
    /// integer `p`, or `0` when not periodic; `window` the impact window
    /// length `W`; `poincare_points` an integer; floats `{:.12e}`; an empty
    /// cell for a piece not requested or a value not defined (NaN).
    pub fn write_row(&self, buf: &mut Vec<u8>) -> std::io::Result<()> {
        let im = self.impacts;
        if let Some(s) = im {
            write!(buf, "{}", s.count)?;
        }
        for x in [im.map(|s| s.per_period), im.map(|s| s.mean_impulse), im.map(|s| s.max_impulse), im.map(|s| s.power), self.rms_force, self.max_abs_tip] {
            cell(buf, x.unwrap_or(f64::NAN))?;
        }
        buf.push(b',');
        if let Some((_, p)) = self.poincare {
            write!(buf, "{}", p.unwrap_or(0))?;
        }
        cell(buf, im.map_or(f64::NAN, |s| s.window))?;
        buf.push(b',');
        if let Some((n, _)) = self.poincare {
            write!(buf, "{n}")?;
        }
        Ok(())
    }
}

/// Whether and where a piece of [`VibroConfig::build`] writes.
#[derive(Debug)]
pub enum Piece<W> {
    /// Not computed.
    Off,
    /// Computed, kept in memory.
    Memory,
    /// Computed, kept in memory and written as CSV to `W`.
    Csv(W),
}

impl<W> Piece<W> {
    fn parts(self) -> Option<Option<W>> {
        match self {
            Piece::Off => None,
            Piece::Memory => Some(None),
            Piece::Csv(w) => Some(Some(w)),
        }
    }
}

/// What the vibro-impact observers need, so a CLI builds them in one call
/// ([`VibroConfig::new`], then the fields).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct VibroConfig {
    /// Time step (`> 0`, finite; the run's).
    pub dt: f64,
    /// Forcing angular frequency `Ω` (`> 0`, finite), if the load is periodic.
    pub omega: Option<f64>,
    /// Start of the record window (`>= 0`, finite): the transient before it
    /// is left out of the statistics and the Poincaré section.
    pub record_from: f64,
    /// The dof of the tip (Poincaré section, largest excursion).
    pub tip: usize,
    /// The contacts `(dof, bounds)`, in contact order.
    pub contacts: Vec<(usize, Bounds)>,
    /// Largest period tried by the period test (`1..=1000`).
    pub p_max: usize,
    /// Relative tolerance of the period test (`(0, 1)`; see [`response_period`]).
    pub period_tol: f64,
    /// The horizon, if known: the Poincaré list then reserves its exact size.
    pub t_end: Option<f64>,
    /// Impacts reserved in memory at construction.
    pub impact_capacity: usize,
    /// The forcing phase `θ ∈ [0, 2π)` of the Poincaré section (default 0).
    pub phase: f64,
}

impl VibroConfig {
    /// A validated configuration with `p_max = 8`, `period_tol = 1e-3`, no
    /// horizon and room for 1024 impacts.
    pub fn new(dt: f64, omega: Option<f64>, record_from: f64, tip: usize, contacts: Vec<(usize, Bounds)>) -> Result<Self, RunError> {
        let cfg = Self { dt, omega, record_from, tip, contacts, p_max: 8, period_tol: 1e-3, t_end: None, impact_capacity: 1024, phase: 0.0 };
        cfg.validate()?;
        Ok(cfg)
    }

    /// The contacts of `dy` (dofs and bounds, in contact order).
    pub fn for_dynamics(dy: &Dynamics, dt: f64, omega: Option<f64>, record_from: f64, tip: usize) -> Result<Self, RunError> {
        if tip >= dy.n() {
            return Err(RunError::Invalid { field: "vibro.tip", value: tip as f64, allowed: "a dof of the problem (< its number of unknowns)" });
        }
        Self::new(dt, omega, record_from, tip, dy.contacts.iter().map(|c| (c.dof, c.bounds)).collect())
    }

    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), RunError> {
        let bad = |field, value, allowed| Err(RunError::Invalid { field, value, allowed });
        if !(self.dt > 0.0 && self.dt.is_finite()) {
            return bad("vibro.dt", self.dt, "finite and > 0");
        }
        if let Some(w) = self.omega {
            if !(w > 0.0 && w.is_finite()) {
                return bad("vibro.omega", w, "finite and > 0");
            }
        }
        if !(self.record_from >= 0.0 && self.record_from.is_finite()) {
            return bad("vibro.record_from", self.record_from, "finite and >= 0");
        }
        if !(1..=1000).contains(&self.p_max) {
            return bad("vibro.p_max", self.p_max as f64, "1..=1000");
        }
        if !(self.period_tol > 0.0 && self.period_tol < 1.0) {
            return bad("vibro.period_tol", self.period_tol, "(0, 1)");
        }
        if let Some(t) = self.t_end {
            if !(t > 0.0 && t.is_finite()) {
                return bad("vibro.t_end", t, "finite and > 0");
            }
        }
        if self.contacts.is_empty() {
            return bad("vibro.contacts", 0.0, "at least one contact");
        }
        for &(_, b) in &self.contacts {
            if b.lo.is_nan() || b.hi.is_nan() || b.lo > b.hi {
                return bad("vibro.contacts.bounds", b.lo, "lo <= hi, not NaN");
            }
        }
        Ok(())
    }

    /// The impact observer.
    pub fn impacts<W: Write>(&self, csv: Option<W>) -> Result<ImpactObserver<W>, RunError> {
        self.validate()?;
        ImpactObserver::new(&self.contacts, self.dt, self.omega, self.record_from, self.impact_capacity, csv)
    }

    /// The Poincaré observer (needs `omega`).
    pub fn poincare<W: Write>(&self, csv: Option<W>) -> Result<PoincareObserver<W>, RunError> {
        self.validate()?;
        let omega = self.omega.ok_or(RunError::Invalid { field: "vibro.omega", value: f64::NAN, allowed: "given (a Poincaré section needs the forcing frequency)" })?;
        let cap = self.t_end.map_or(0, |t| ((t - self.record_from).max(0.0) * omega / TAU).floor() as usize + 2);
        PoincareObserver::new(self.tip, self.dt, omega, self.record_from, cap, csv)?.with_phase(self.phase)
    }

    /// The window observer.
    pub fn window(&self) -> WindowObserver {
        WindowObserver::new(self.tip, self.record_from)
    }

    /// The pieces asked for, as one observer.
    pub fn build<WI: Write, WP: Write>(&self, impacts: Piece<WI>, poincare: Piece<WP>, window: bool) -> Result<Vibro<WI, WP>, RunError> {
        self.validate()?;
        Ok(Vibro {
            impacts: impacts.parts().map(|w| self.impacts(w)).transpose()?,
            poincare: poincare.parts().map(|w| self.poincare(w)).transpose()?,
            window: window.then(|| self.window()),
            p_max: self.p_max,
            period_tol: self.period_tol,
        })
    }
}

/// The vibro-impact observers of one run (each optional), fed together.
pub struct Vibro<WI: Write = std::io::Sink, WP: Write = std::io::Sink> {
    /// Impacts.
    pub impacts: Option<ImpactObserver<WI>>,
    /// Poincaré section.
    pub poincare: Option<PoincareObserver<WP>>,
    /// Force and tip statistics.
    pub window: Option<WindowObserver>,
    p_max: usize,
    period_tol: f64,
}

impl<WI: Write, WP: Write> Vibro<WI, WP> {
    /// The statistics of the pieces present.
    pub fn summary(&self) -> Summary {
        Summary {
            impacts: self.impacts.as_ref().map(ImpactObserver::stats),
            rms_force: self.window.as_ref().map(WindowObserver::rms_force),
            max_abs_tip: self.window.as_ref().map(WindowObserver::max_abs_tip),
            poincare: self.poincare.as_ref().map(|p| (p.points().len(), p.period(self.p_max, self.period_tol))),
        }
    }
}

impl<WI: Write, WP: Write> Observer for Vibro<WI, WP> {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if let Some(o) = &mut self.impacts {
            o.observe(s)?;
        }
        if let Some(o) = &mut self.poincare {
            o.observe(s)?;
        }
        if let Some(o) = &mut self.window {
            o.observe(s)?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), RunError> {
        let a = self.impacts.as_mut().map_or(Ok(()), Observer::finish);
        let b = self.poincare.as_mut().map_or(Ok(()), Observer::finish);
        a.and(b)
    }
}
