//! Nonsmooth modes of the bar (docs/theory.md §11): the exact families of
//! periodic motions of the unforced, undamped bar `u_tt = c² u_xx` on
//! `(0, L)`, clamped at `x = L`, with the Signorini condition
//! `u(0, t) ≥ g ⊥ λ = c² u_x(0, t) ≤ 0` at `x = 0`, one contact phase per
//! period, and their backbone `period(E)`.
//!
//! # The closed form
//!
//! Every solution with the far end clamped is `u(x, t) = −½ ∫_{t+x/c}^{t+τ−x/c} q`,
//! `τ = 2L/c`, where `q(t)` is the velocity the end `x = 0` would have at `t` if it
//! were free (the wave arriving there, doubled). The end's boundary
//! condition acts on `q` by a round trip: `q(t + τ) = −q(t)` while the end is free,
//! `q(t + τ) = q(t)` while it is held, and the energy is `E = (c/4) ∫_t^{t+τ} q²`.
//! When the period `T` and `τ` are incommensurate `|q|` is a constant `Q`, and
//! the periodic motions with one contact phase per period form the families
//! `k = 1, 2, …` (the `k`-th continues the `k`-th linear period `4L/((2k−1)c)`):
//!
//! ```text
//! Q = √(2E/L),   flight t_f = (τ − 2g/Q)/k,   period T = (t_f/2 + τ)/k,   contact t_c = T − t_f,
//! ```
//!
//! while `t_c > 0` and `t_f > 0`. With a clearance (`g < 0`) the family is the
//! linear motion (period `4L/((2k−1)c)`, no contact) up to the threshold
//! `E_k = (2k−1)² c² g²/(2L)`; with `g = 0` the period is `(2k+1)L/(k²c)` at
//! every energy; with `g > 0` (the obstacle prestresses the bar) the family
//! starts at the static state, `E = c² g²/(2L)`, the least energy of any
//! admissible state. The end hits the obstacle at speed `Q` and is held by
//! the constant force `λ = −cQ`. The family `k = 1` is the bar stretched
//! linearly, `u = (Q/c)(L − x)`, released from rest; `bar-dirichlet` is its
//! point `g = 0`, `E = 1/8` (period 3, contact 1).
//!
//! With the far end free the obstacle's impulse `−∫λ dt ≥ 0` is the change of
//! the bar's momentum over a period, so no periodic motion has any contact
//! force: [`BackboneError::FreeFarEnd`].

use std::fmt;

use crate::{on_bar, ExactSolution, FarEnd, Fields, UNDEFINED};

/// The bar of a nonsmooth mode: the `[bar]` scene's geometry (density 1, no
/// body force). `Copy`, plain data; checked by [`Backbone::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeBar {
    /// Length `L` (> 0; default 1).
    pub length: f64,
    /// Wave speed `c = √(E/ρ)` (> 0; default 1).
    pub wave_speed: f64,
    /// Obstacle position `g` at `x = 0` (contact when `u(0, t) = g`; any
    /// finite value, default 0): `g < 0` is a clearance, `g > 0` a prestress.
    pub gap: f64,
    /// Condition at `x = L` (default clamped; free has no mode with contact).
    pub far_end: FarEnd,
}

impl Default for ModeBar {
    fn default() -> Self {
        Self { length: 1.0, wave_speed: 1.0, gap: 0.0, far_end: FarEnd::Clamped }
    }
}

/// Bad input to [`Backbone`]: names the field, the value and the allowed range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BackboneError {
    /// The length must be finite and `> 0`.
    Length(f64),
    /// The wave speed must be finite and `> 0`.
    WaveSpeed(f64),
    /// The gap must be finite.
    Gap(f64),
    /// The family index must be `>= 1`.
    Family(u32),
    /// With the far end free no periodic motion has a contact force.
    FreeFarEnd,
    /// The energy must be finite and `>= 0`.
    Energy(f64),
    /// With `g > 0` no admissible state has less energy than the static one.
    BelowStatic {
        /// The requested energy.
        energy: f64,
        /// The static state's energy `c² g²/(2L)`.
        minimum: f64,
    },
}

impl BackboneError {
    /// Name of the offending parameter.
    #[must_use]
    pub fn field(&self) -> &'static str {
        match self {
            Self::Length(_) => "length",
            Self::WaveSpeed(_) => "wave_speed",
            Self::Gap(_) => "gap",
            Self::Family(_) => "family",
            Self::FreeFarEnd => "far_end",
            Self::Energy(_) | Self::BelowStatic { .. } => "energy",
        }
    }

    /// The allowed range, in words.
    #[must_use]
    pub fn allowed(&self) -> String {
        match self {
            Self::Length(_) | Self::WaveSpeed(_) => "finite and > 0".into(),
            Self::Gap(_) => "finite".into(),
            Self::Family(_) => ">= 1".into(),
            Self::FreeFarEnd => "\"clamped\" (with a free far end the obstacle's impulse changes the momentum: no periodic motion has contact)".into(),
            Self::Energy(_) => "finite and >= 0".into(),
            Self::BelowStatic { minimum, .. } => format!(">= {minimum}, the static state's energy c² g²/(2L) (gap > 0)"),
        }
    }

    /// The rejected value, as written in messages.
    #[must_use]
    pub fn value(&self) -> String {
        match *self {
            Self::Length(v) | Self::WaveSpeed(v) | Self::Gap(v) | Self::Energy(v) => format!("{v}"),
            Self::BelowStatic { energy, .. } => format!("{energy}"),
            Self::Family(k) => format!("{k}"),
            Self::FreeFarEnd => "\"free\"".into(),
        }
    }
}

impl fmt::Display for BackboneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "nonsmooth mode: invalid {} = {} (must be {})", self.field(), self.value(), self.allowed())
    }
}

impl std::error::Error for BackboneError {}

/// One point of a backbone: the periodic motion of family `k` at energy `E`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BackbonePoint {
    /// Energy `E = ∫ (u_t² + c² u_x²)/2 dx`.
    pub energy: f64,
    /// Period `T`.
    pub period: f64,
    /// Time per period with the end on the obstacle (`0` below the threshold).
    pub contact_time: f64,
    /// Time per period with the end free, `T − contact_time`.
    pub flight_time: f64,
    /// Contact phases (impacts) per period: 1 when both phases last, else 0
    /// (the linear motion below the threshold; the static state for `g > 0`).
    pub impacts_per_period: u32,
    /// Speed `Q = √(2E/L)` of the end: it moves at `±Q` in flight and hits
    /// the obstacle at speed `Q`.
    pub impact_velocity: f64,
    /// The contact force during contact, `λ = −cQ` (0 without contact).
    pub contact_force: f64,
}

/// The backbone of the family `k` of nonsmooth modes of a bar (see the
/// module docs and docs/theory.md §11).
///
/// ```
/// use signorini_exact::{Backbone, ExactSolution, FarEnd, ModeBar};
///
/// // L = c = 1 with a clearance 1/4 (the obstacle at g = -1/4).
/// let bar = ModeBar { length: 1.0, wave_speed: 1.0, gap: -0.25, far_end: FarEnd::Clamped };
/// let first = Backbone::new(bar, 1).unwrap();
/// // Contact starts at c² g²/(2L) = 1/32; below it the linear period 4L/c.
/// assert_eq!((first.threshold(), first.point(0.01).unwrap().period), (1.0 / 32.0, 4.0));
/// // At E = 1/2 the end hits at Q = √(2E/L) = 1: T = 3L/c − g/Q, t_c = L/c + g/Q.
/// let p = first.point(0.5).unwrap();
/// assert_eq!((p.period, p.contact_time, p.impacts_per_period), (3.25, 0.75, 1));
/// // The motion: the bar stretched linearly, u = (Q/c)(L − x), at rest at t = 0.
/// let mode = first.mode(0.5).unwrap();
/// assert_eq!((mode.fields(0.25, 0.0).u, mode.fields(0.25, 0.0).ut), (0.75, 0.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Backbone {
    bar: ModeBar,
    family: u32,
}

impl Backbone {
    /// The family `k >= 1` of `bar` (`k = 1`: the one through the first
    /// linear period `4L/c`); typed errors for bad data and a free far end.
    pub fn new(bar: ModeBar, family: u32) -> Result<Self, BackboneError> {
        if !(bar.length.is_finite() && bar.length > 0.0) {
            return Err(BackboneError::Length(bar.length));
        }
        if !(bar.wave_speed.is_finite() && bar.wave_speed > 0.0) {
            return Err(BackboneError::WaveSpeed(bar.wave_speed));
        }
        if !bar.gap.is_finite() {
            return Err(BackboneError::Gap(bar.gap));
        }
        if family == 0 {
            return Err(BackboneError::Family(family));
        }
        if bar.far_end == FarEnd::Free {
            return Err(BackboneError::FreeFarEnd);
        }
        Ok(Self { bar, family })
    }

    /// The bar.
    #[must_use]
    pub fn bar(&self) -> ModeBar {
        self.bar
    }

    /// The family index `k`.
    #[must_use]
    pub fn family(&self) -> u32 {
        self.family
    }

    fn k(&self) -> f64 {
        f64::from(self.family)
    }

    /// Round-trip time `τ = 2L/c`.
    fn tau(&self) -> f64 {
        2.0 * self.bar.length / self.bar.wave_speed
    }

    /// The linear period `4L/((2k−1)c)` (the family below its threshold).
    #[must_use]
    pub fn linear_period(&self) -> f64 {
        2.0 * self.tau() / (2.0 * self.k() - 1.0)
    }

    /// The period at `g = 0` (every energy) and the limit `E → ∞` for any
    /// gap: `(2k+1)L/(k²c)` (`3L/c` for `k = 1`).
    #[must_use]
    pub fn limit_period(&self) -> f64 {
        let k = self.k();
        self.tau() * (2.0 * k + 1.0) / (2.0 * k * k)
    }

    /// The least energy of the family's motions with contact: for `g < 0`
    /// the threshold `(2k−1)² c² g²/(2L)` where the linear motion first
    /// touches the obstacle; for `g > 0` the static state's energy
    /// `c² g²/(2L)` (below it no admissible state exists); 0 for `g = 0`.
    #[must_use]
    pub fn threshold(&self) -> f64 {
        let ModeBar { length, wave_speed: c, gap: g, .. } = self.bar;
        let n = if g < 0.0 { 2.0 * self.k() - 1.0 } else { 1.0 };
        (n * c * g).powi(2) / (2.0 * length)
    }

    fn check_energy(&self, energy: f64) -> Result<(), BackboneError> {
        if !(energy.is_finite() && energy >= 0.0) {
            return Err(BackboneError::Energy(energy));
        }
        if self.bar.gap > 0.0 && energy < self.threshold() {
            return Err(BackboneError::BelowStatic { energy, minimum: self.threshold() });
        }
        Ok(())
    }

    /// The family's periodic motion at energy `E`: period, contact time,
    /// impacts per period, the end's speed and the contact force.
    pub fn point(&self, energy: f64) -> Result<BackbonePoint, BackboneError> {
        self.check_energy(energy)?;
        let ModeBar { length, wave_speed: c, gap: g, .. } = self.bar;
        let (k, tau) = (self.k(), self.tau());
        let q = (2.0 * energy / length).sqrt();
        let (period, flight) = if g == 0.0 {
            // Positively homogeneous: the same times at every energy.
            (self.limit_period(), tau / k)
        } else if g < 0.0 && energy <= self.threshold() {
            // The linear motion: the end's velocity a square wave ±Q.
            (self.linear_period(), self.linear_period())
        } else if g > 0.0 && energy <= self.threshold() {
            // The static state (held, no flight), the limit 2L/(kc) of the family.
            (tau / k, 0.0)
        } else {
            let flight = ((tau - 2.0 * g / q) / k).max(0.0);
            ((0.5 * flight + tau) / k, flight)
        };
        let contact = (period - flight).max(0.0);
        let impacts = u32::from(contact > 0.0 && flight > 0.0);
        Ok(BackbonePoint {
            energy,
            period,
            contact_time: contact,
            flight_time: period - contact,
            impacts_per_period: impacts,
            impact_velocity: q,
            contact_force: if contact > 0.0 { -c * q } else { 0.0 },
        })
    }

    /// The motion itself at energy `E`, as an [`ExactSolution`] (time origin
    /// at the top of the flight, where the end is highest and starts down).
    pub fn mode(&self, energy: f64) -> Result<NonsmoothMode, BackboneError> {
        let p = self.point(energy)?;
        Ok(NonsmoothMode { bar: self.bar, point: p, tau: self.tau(), descent: 0.5 * p.flight_time + p.contact_time })
    }
}

/// A nonsmooth mode at one energy (see [`Backbone::mode`]): `u`, `u_x`,
/// `u_t`, `λ` in closed form, piecewise affine, periodic.
///
/// With `t = 0` at the top of the flight, the free-end velocity `q(s)` is
/// `−Q` on `[0, t_f/2 + t_c)` (descent, then contact) and `+Q` on the rest
/// of the period (ascent), and `u(x, t) = −½ ∫_{t+x/c}^{t+τ−x/c} q`,
/// `u_t = ½ (q(t + x/c) − q(t + τ − x/c))`,
/// `u_x = (q(t + x/c) + q(t + τ − x/c))/(2c)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonsmoothMode {
    bar: ModeBar,
    point: BackbonePoint,
    tau: f64,
    /// `t_f/2 + t_c`: where `q` turns from `−Q` to `+Q`.
    descent: f64,
}

impl NonsmoothMode {
    /// The backbone point this motion is.
    #[must_use]
    pub fn point(&self) -> BackbonePoint {
        self.point
    }

    /// `s` folded into `[0, T)`.
    fn fold(&self, s: f64) -> f64 {
        let r = s.rem_euclid(self.point.period);
        if r >= self.point.period {
            0.0
        } else {
            r
        }
    }

    /// `q(s)`, right-continuous (`left`: the left limit).
    fn q(&self, s: f64, left: bool) -> f64 {
        let r = self.fold(s);
        let qv = self.point.impact_velocity;
        let down = if left { r > 0.0 && r <= self.descent } else { r < self.descent };
        if down {
            -qv
        } else {
            qv
        }
    }

    /// `∫_0^s q` for `s ∈ [0, 2T + τ]` (no folding: exact pieces).
    fn integral(&self, s: f64) -> f64 {
        let (t, a, qv) = (self.point.period, self.descent, self.point.impact_velocity);
        let one = |r: f64| -qv * r.min(a) + qv * (r - a).max(0.0);
        let mut n = 0.0;
        let mut r = s;
        while r >= t {
            r -= t;
            n += 1.0;
        }
        n * one(t) + one(r)
    }
}

impl ExactSolution for NonsmoothMode {
    fn name(&self) -> &str {
        "nonsmooth-mode"
    }
    fn length(&self) -> f64 {
        self.bar.length
    }
    fn wave_speed(&self) -> f64 {
        self.bar.wave_speed
    }
    fn far_end(&self) -> FarEnd {
        FarEnd::Clamped
    }
    fn gap(&self) -> f64 {
        self.bar.gap
    }
    fn degree_x(&self) -> usize {
        1
    }
    fn fields(&self, x: f64, t: f64) -> Fields {
        let (Some(x), true) = (on_bar(x, self.bar.length), t.is_finite()) else {
            return UNDEFINED;
        };
        let c = self.bar.wave_speed;
        let t = self.fold(t);
        let (a, b) = (t + x / c, t + self.tau - x / c);
        // u = −½ ∫_a^b q (a <= b); both ends in [0, T + τ].
        let u = -0.5 * (self.integral(b) - self.integral(a));
        // A larger x moves a right and b left: one-sided values of that piece.
        let (qa, qb) = (self.q(a, false), self.q(b, true));
        Fields { u, ux: (qa + qb) / (2.0 * c), ut: 0.5 * (qa - qb) }
    }
    fn lambda(&self, t: f64) -> f64 {
        if !t.is_finite() {
            return f64::NAN;
        }
        let r = self.fold(t);
        let start = 0.5 * self.point.flight_time;
        if self.point.contact_time > 0.0 && r >= start && r < self.descent {
            self.point.contact_force
        } else {
            0.0
        }
    }
    fn energy(&self) -> f64 {
        self.point.energy
    }
    fn kinks(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        if !t.is_finite() || self.point.impact_velocity == 0.0 {
            return;
        }
        let (c, l, period) = (self.bar.wave_speed, self.bar.length, self.point.period);
        let t = self.fold(t);
        // q jumps at s ≡ 0 and s ≡ descent (mod T); the kinks are where
        // t + x/c or t + τ − x/c reaches one.
        let mut n = -1.0;
        while n * period <= t + self.tau + period {
            for s in [0.0, self.descent] {
                let s = s + n * period;
                for x in [c * (s - t), c * (t + self.tau - s)] {
                    if x > 0.0 && x < l {
                        out.push(x);
                    }
                }
            }
            n += 1.0;
        }
        out.sort_by(f64::total_cmp);
        out.dedup();
    }
    fn period(&self) -> Option<f64> {
        Some(self.point.period)
    }
}
