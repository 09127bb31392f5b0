//! Time profiles `s(t)` of separable loads `F(t) = shape · s(t)`: their
//! values and exact means over a step (docs/theory.md §4.3), their exact
//! derivatives (for the lifting `u = ũ − h(x) φ(t)` of a support motion `φ`),
//! and band-limited random realisations built from a seed.
//!
//! * [`TimeProfile::Sine`]: `A sin(ω t)`.
//! * [`TimeProfile::Harmonics`]: `Σ_i a_i sin(ω_i t + p_i)`, data shared on clone.
//! * [`TimeProfile::Series`]: piecewise-linear interpolation of `(t_k, v_k)`
//!   points, end values held outside the data.
//! * [`TimeProfile::random`]: a [`TimeProfile::Harmonics`] realisation of a
//!   one-sided PSD over a frequency band ([`RandomSpec`]), reproducible from
//!   its seed on every platform ([`SplitMix64`]).
//!
//! The two-step schemes use the exact mean `fⁿ = 1/dt ∫ s` over a step
//! ([`TimeProfile::mean`]), the one-step schemes the values
//! ([`TimeProfile::value`]). [`Sampler`] evaluates a profile on equally spaced
//! times (a step loop) at a few multiplications per harmonic instead of one
//! `sin` per harmonic. Construction validates user data and returns a
//! [`ProfileError`] naming the offending field; nothing here allocates after
//! construction.

use std::f64::consts::{FRAC_PI_2, TAU};
use std::sync::Arc;

/// The largest `count` of [`RandomSpec`] (each harmonic costs one `sin` per
/// [`TimeProfile::value`]; a million is already far beyond any step loop).
pub const MAX_RANDOM_COUNT: usize = 1_000_000;

/// Bad input to a profile constructor: the field (with its index for lists,
/// e.g. `series.t[3]`) and the allowed range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// A value outside its allowed range (NaN, infinite, negative, not increasing, ...).
    #[error("invalid {field} = {value}: allowed {allowed}")]
    Invalid {
        /// The field, e.g. `series.t[3]` or `random.f_hi`.
        field: String,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: String,
    },
    /// A list or count of the wrong size.
    #[error("{field} has {got} entries: allowed {allowed}")]
    Count {
        /// The field, e.g. `series` or `random.count`.
        field: String,
        /// Its size.
        got: usize,
        /// The allowed sizes, in words.
        allowed: String,
    },
}

impl ProfileError {
    /// The offending field's name (e.g. `series.t[3]`).
    pub fn field(&self) -> &str {
        match self {
            ProfileError::Invalid { field, .. } | ProfileError::Count { field, .. } => field,
        }
    }
}

fn invalid(field: impl Into<String>, value: f64, allowed: impl Into<String>) -> ProfileError {
    ProfileError::Invalid { field: field.into(), value, allowed: allowed.into() }
}

/// One term `a sin(ω t + p)` of [`TimeProfile::Harmonics`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Harmonic {
    /// Amplitude `a` (any sign).
    pub amplitude: f64,
    /// Angular frequency `ω` (rad/s).
    pub omega: f64,
    /// Phase `p` (rad).
    pub phase: f64,
}

/// A piecewise-linear function through the points `(t_k, v_k)`,
/// `k = 0..K` (`K >= 2`, `t` strictly increasing, everything finite),
/// holding its end values outside `[t_0, t_{K-1}]`:
///
/// ```text
/// s(t) = v_0                                          t <= t_0
///        v_k + (t − t_k)(v_{k+1} − v_k)/(t_{k+1} − t_k)   t_k <= t < t_{k+1}
///        v_{K-1}                                      t >= t_{K-1}
/// ```
///
/// Built only by [`Series::new`] (validated); the points are shared on clone.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    t: Arc<[f64]>,
    v: Arc<[f64]>,
}

impl Series {
    /// Validates and stores the points: `t` and `v` of the same length
    /// `>= 2`, every entry finite, `t` strictly increasing. Errors name the
    /// entry: `series.t[3]`, `series.v[0]`, `series` (the count).
    pub fn new(t: Vec<f64>, v: Vec<f64>) -> Result<Self, ProfileError> {
        Self::checked("series", "series.t", "series.v", t, v)
    }

    fn checked(name: &str, tname: &str, vname: &str, t: Vec<f64>, v: Vec<f64>) -> Result<Self, ProfileError> {
        if t.len() != v.len() {
            return Err(ProfileError::Count { field: vname.to_string(), got: v.len(), allowed: format!("as many as {tname} ({})", t.len()) });
        }
        if t.len() < 2 {
            return Err(ProfileError::Count { field: name.to_string(), got: t.len(), allowed: "at least 2 points".to_string() });
        }
        for (k, (&tk, &vk)) in t.iter().zip(&v).enumerate() {
            if !tk.is_finite() {
                return Err(invalid(format!("{tname}[{k}]"), tk, "finite"));
            }
            if k > 0 && tk <= t[k - 1] {
                return Err(invalid(format!("{tname}[{k}]"), tk, format!("> {tname}[{}] = {} (strictly increasing)", k - 1, t[k - 1])));
            }
            if !vk.is_finite() {
                return Err(invalid(format!("{vname}[{k}]"), vk, "finite"));
            }
        }
        Ok(Self { t: t.into(), v: v.into() })
    }

    /// The abscissae `t_k`.
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// The values `v_k`.
    pub fn values(&self) -> &[f64] {
        &self.v
    }

    /// `s` on piece `j` (`[t_j, t_{j+1}]`) at `x`.
    #[inline]
    fn on_piece(&self, j: usize, x: f64) -> f64 {
        let (t, v) = (&self.t, &self.v);
        v[j] + (x - t[j]) * (v[j + 1] - v[j]) / (t[j + 1] - t[j])
    }

    /// `s(t)` (binary search, `O(log K)`); NaN for a NaN `t`.
    pub fn value(&self, t: f64) -> f64 {
        let k = self.t.len();
        // Number of points <= t: 0 before the data (or NaN), k after it.
        match self.t.partition_point(|&x| x <= t) {
            0 if t.is_nan() => f64::NAN,
            0 => self.v[0],
            n if n == k => self.v[k - 1],
            n => self.on_piece(n - 1, t),
        }
    }

    /// The piece at `t`, right-continuous (at a point, the piece that
    /// starts there): `s(t)`, the slope there (0 outside the data, where the
    /// end values are held) and the next point after `t` (`None` past the
    /// last).
    pub fn piece(&self, t: f64) -> (f64, f64, Option<f64>) {
        let (tk, vk) = (&self.t, &self.v);
        let n = tk.partition_point(|&x| x <= t);
        let slope = if n == 0 || n == tk.len() { 0.0 } else { (vk[n] - vk[n - 1]) / (tk[n] - tk[n - 1]) };
        (self.value(t), slope, tk.get(n).copied())
    }

    /// `∫_a^b s`, exactly (trapezoids on the pieces `[a, b]` meets, held
    /// ends outside the data; `−∫_b^a s` when `a > b`):
    /// `O(log K + pieces spanned)`.
    pub fn integral(&self, a: f64, b: f64) -> f64 {
        if a > b {
            return -self.integral(b, a);
        }
        let (t, v) = (&self.t, &self.v);
        let k = t.len();
        let (first, last) = (t[0], t[k - 1]);
        let mut sum = 0.0;
        if a < first {
            sum += v[0] * (b.min(first) - a);
        }
        if b > last {
            sum += v[k - 1] * (b - a.max(last));
        }
        let (lo, hi) = (a.max(first), b.min(last));
        if lo < hi {
            // The piece holding lo: [t_j, t_{j+1}] with t_j <= lo < t_{j+1}.
            let mut j = (t.partition_point(|&x| x <= lo) - 1).min(k - 2);
            let (mut x0, mut s0) = (lo, self.on_piece(j, lo));
            loop {
                let (x1, s1) = if hi < t[j + 1] { (hi, self.on_piece(j, hi)) } else { (t[j + 1], v[j + 1]) };
                sum += 0.5 * (x1 - x0) * (s0 + s1);
                if x1 >= hi {
                    break;
                }
                j += 1;
                (x0, s0) = (x1, s1);
            }
        }
        sum
    }

    /// The mean `1/(t1 − t0) ∫ s` over `[t0, t1]` (either order), exactly;
    /// `s(t0)` when `t0 = t1`.
    pub fn mean(&self, t0: f64, t1: f64) -> f64 {
        let (a, b) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        if a == b {
            return self.value(a);
        }
        self.integral(a, b) / (b - a)
    }

    /// `max_t |s(t)| = max_k |v_k|` (exact: a piecewise-linear function
    /// takes its extrema at its points).
    pub fn max_abs(&self) -> f64 {
        self.v.iter().fold(0.0, |m, x| m.max(x.abs()))
    }
}

/// `sin(x)/x`, even, without the `0/0` at `x = 0`.
#[inline]
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-8 {
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}

/// A time profile `s(t)` of a separable load `F(t) = shape · s(t)`.
#[derive(Clone, Debug, PartialEq)]
pub enum TimeProfile {
    /// `s(t) = amplitude · sin(omega t)`.
    Sine {
        /// Amplitude.
        amplitude: f64,
        /// Angular frequency (rad/s).
        omega: f64,
    },
    /// `s(t) = Σ_i a_i sin(ω_i t + p_i)` (the terms are shared, not copied,
    /// on clone). Build it with [`TimeProfile::harmonics`] (validated) or
    /// [`TimeProfile::random`]; each term costs one `sin` per
    /// [`value`](Self::value) (see [`Sampler`] for step loops).
    Harmonics(Arc<[Harmonic]>),
    /// Piecewise-linear interpolation of points, end values held outside the
    /// data ([`Series`]; build it with [`TimeProfile::series`]).
    Series(Series),
}

impl TimeProfile {
    /// `Σ_i a_i sin(ω_i t + p_i)` from its terms: at least one, every field
    /// finite (errors name `harmonics[i].amplitude`, `.omega`, `.phase`).
    pub fn harmonics(terms: Vec<Harmonic>) -> Result<Self, ProfileError> {
        if terms.is_empty() {
            return Err(ProfileError::Count { field: "harmonics".to_string(), got: 0, allowed: "at least 1 term".to_string() });
        }
        for (i, h) in terms.iter().enumerate() {
            for (name, x) in [("amplitude", h.amplitude), ("omega", h.omega), ("phase", h.phase)] {
                if !x.is_finite() {
                    return Err(invalid(format!("harmonics[{i}].{name}"), x, "finite"));
                }
            }
        }
        Ok(TimeProfile::Harmonics(terms.into()))
    }

    /// The piecewise-linear profile through `(t[k], v[k])` ([`Series::new`]:
    /// `>= 2` points, finite, `t` strictly increasing; end values held
    /// outside `[t[0], t[K-1]]`).
    pub fn series(t: Vec<f64>, v: Vec<f64>) -> Result<Self, ProfileError> {
        Ok(TimeProfile::Series(Series::new(t, v)?))
    }

    /// `s(t)`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            &TimeProfile::Sine { amplitude, omega } => amplitude * (omega * t).sin(),
            TimeProfile::Harmonics(h) => h.iter().map(|h| h.amplitude * (h.omega * t + h.phase).sin()).sum(),
            TimeProfile::Series(s) => s.value(t),
        }
    }

    /// `max_t |s(t)|` for `Sine` and `Series` (exact); for `Harmonics` the
    /// upper bound `Σ_i |a_i|` (attained only if the peaks line up).
    pub fn max_abs(&self) -> f64 {
        match self {
            TimeProfile::Sine { amplitude, .. } => amplitude.abs(),
            TimeProfile::Harmonics(h) => h.iter().map(|h| h.amplitude.abs()).sum(),
            TimeProfile::Series(s) => s.max_abs(),
        }
    }

    /// The exact mean `1/(t1 - t0) ∫ s` over `[t0, t1]` (docs/theory.md §4.3's `f^n`),
    /// written without cancellation: `A sin(ω t_mid) sin(ω δ/2) / (ω δ/2)`
    /// for `Sine`, `Σ_i a_i sin(ω_i t_mid + p_i) sin(ω_i δ/2) / (ω_i δ/2)`
    /// for `Harmonics` (`t_mid = (t0 + t1)/2`, `δ = t1 − t0`), the exact
    /// integral of the piecewise-linear function (held ends included) for
    /// `Series` ([`Series::mean`], `O(log K + pieces spanned)`). At `t0 = t1`
    /// it is `s(t0)`.
    pub fn mean(&self, t0: f64, t1: f64) -> f64 {
        match self {
            &TimeProfile::Sine { amplitude, omega } => {
                let half = 0.5 * omega * (t1 - t0);
                let sinc = if half.abs() < 1e-8 { 1.0 - half * half / 6.0 } else { half.sin() / half };
                amplitude * (omega * 0.5 * (t0 + t1)).sin() * sinc
            }
            TimeProfile::Harmonics(h) => {
                let (mid, delta) = (0.5 * (t0 + t1), t1 - t0);
                h.iter().map(|h| h.amplitude * (h.omega * mid + h.phase).sin() * sinc(0.5 * h.omega * delta)).sum()
            }
            TimeProfile::Series(s) => s.mean(t0, t1),
        }
    }

    /// The exact derivative `s'`: `A ω sin(ω t + π/2)` for `Sine`,
    /// `Σ a_i ω_i sin(ω_i t + p_i + π/2)` for `Harmonics` (both as
    /// `Harmonics`); `None` for `Series` (its derivative is piecewise
    /// constant, and the second derivative a train of impulses: a support
    /// motion must then be given as a load instead).
    pub fn derivative(&self) -> Option<TimeProfile> {
        match self {
            &TimeProfile::Sine { amplitude, omega } => Some(TimeProfile::Harmonics(Arc::new([Harmonic { amplitude: amplitude * omega, omega, phase: FRAC_PI_2 }]))),
            TimeProfile::Harmonics(h) => Some(TimeProfile::Harmonics(h.iter().map(|h| Harmonic { amplitude: h.amplitude * h.omega, omega: h.omega, phase: h.phase + FRAC_PI_2 }).collect())),
            TimeProfile::Series(_) => None,
        }
    }

    /// The exact second derivative `s''`: `Sine { −A ω², ω }` for `Sine`,
    /// `Σ (−a_i ω_i²) sin(ω_i t + p_i)` for `Harmonics` (phases unchanged);
    /// `None` for `Series` (see [`derivative`](Self::derivative)).
    pub fn second_derivative(&self) -> Option<TimeProfile> {
        match self {
            &TimeProfile::Sine { amplitude, omega } => Some(TimeProfile::Sine { amplitude: -amplitude * omega * omega, omega }),
            TimeProfile::Harmonics(h) => Some(TimeProfile::Harmonics(h.iter().map(|h| Harmonic { amplitude: -h.amplitude * h.omega * h.omega, omega: h.omega, phase: h.phase }).collect())),
            TimeProfile::Series(_) => None,
        }
    }

    /// `s'(t)` without building the derivative: `A ω cos(ω t)`,
    /// `Σ a_i ω_i cos(ω_i t + p_i)`; `None` for `Series`. At `t = 0` it is
    /// the initial rate `φ'(0)` of a support motion (the lifting's initial
    /// velocity).
    pub fn derivative_at(&self, t: f64) -> Option<f64> {
        match self {
            &TimeProfile::Sine { amplitude, omega } => Some(amplitude * omega * (omega * t).cos()),
            TimeProfile::Harmonics(h) => Some(h.iter().map(|h| h.amplitude * h.omega * (h.omega * t + h.phase).cos()).sum()),
            TimeProfile::Series(_) => None,
        }
    }

    /// A band-limited random realisation of a one-sided PSD: a
    /// [`TimeProfile::Harmonics`] with `spec.count` terms. The band
    /// `[f_lo, f_hi]` is cut into equal bins `Δf = (f_hi − f_lo)/count`;
    /// bin `i` gives the term
    ///
    /// ```text
    /// f_i = f_lo + (i + u_i) Δf       (u_i uniform in [0, 1): jitter)
    /// a_i = sqrt(2 ∫_{bin i} S df) = sqrt(2 S̄_i Δf)   (S̄_i the exact mean of S over the bin)
    /// p_i = 2π r_i                    (r_i uniform in [0, 1))
    /// ω_i = 2π f_i
    /// ```
    ///
    /// so the variance `Σ a_i²/2 = ∫_{f_lo}^{f_hi} S df` exactly (up to
    /// rounding), and the expected periodogram is `S`. The jitter keeps the
    /// realisation from being periodic with period `1/Δf` (equally spaced
    /// frequencies would repeat it exactly).
    ///
    /// **Contract**: the realisation is a function of the spec alone. `u_i`
    /// and `r_i` are, in that order for `i = 0, 1, ...`, the outputs of
    /// [`SplitMix64::new(seed)`](SplitMix64) through
    /// [`SplitMix64::next_f64`]; every parameter is then computed with
    /// correctly rounded IEEE operations (`+ − × ÷ sqrt`), so the same seed
    /// and spec give bit-identical `(a_i, ω_i, p_i)` on every platform and
    /// Rust version (the signal's values are as portable as the platform's
    /// `sin`). Changing this is a breaking change.
    ///
    /// Errors: `random.f_lo` (finite, >= 0), `random.f_hi` (finite, > f_lo),
    /// `random.count` (1 ..= [`MAX_RANDOM_COUNT`]), `random.psd` (flat level
    /// finite and >= 0), `random.psd.f[k]` / `random.psd.s[k]` (a table as
    /// [`Series::new`], `s >= 0`, covering the band).
    pub fn random(spec: &RandomSpec) -> Result<TimeProfile, ProfileError> {
        let RandomSpec { f_lo, f_hi, ref psd, count, seed } = *spec;
        if !(f_lo.is_finite() && f_lo >= 0.0) {
            return Err(invalid("random.f_lo", f_lo, "finite and >= 0"));
        }
        if !(f_hi.is_finite() && f_hi > f_lo) {
            return Err(invalid("random.f_hi", f_hi, format!("finite and > random.f_lo = {f_lo}")));
        }
        if !(1..=MAX_RANDOM_COUNT).contains(&count) {
            return Err(ProfileError::Count { field: "random.count".to_string(), got: count, allowed: format!("1 ..= {MAX_RANDOM_COUNT}") });
        }
        // The PSD as a piecewise-linear function of f (flat: constant).
        let table = match psd {
            &Psd::Flat(s) => {
                if !(s.is_finite() && s >= 0.0) {
                    return Err(invalid("random.psd", s, "finite and >= 0"));
                }
                Series { t: Arc::new([f_lo, f_hi]), v: Arc::new([s, s]) }
            }
            Psd::Table { f, s } => {
                let table = Series::checked("random.psd", "random.psd.f", "random.psd.s", f.clone(), s.clone())?;
                if let Some(k) = s.iter().position(|&x| x < 0.0) {
                    return Err(invalid(format!("random.psd.s[{k}]"), s[k], "finite and >= 0"));
                }
                let last = f.len() - 1;
                if f[0] > f_lo {
                    return Err(invalid("random.psd.f[0]", f[0], format!("<= random.f_lo = {f_lo} (the table must cover the band)")));
                }
                if f[last] < f_hi {
                    return Err(invalid(format!("random.psd.f[{last}]"), f[last], format!(">= random.f_hi = {f_hi} (the table must cover the band)")));
                }
                table
            }
        };
        let df = (f_hi - f_lo) / count as f64;
        let mut rng = SplitMix64::new(seed);
        let terms: Arc<[Harmonic]> = (0..count)
            .map(|i| {
                let lo = f_lo + i as f64 * df;
                let hi = if i + 1 == count { f_hi } else { f_lo + (i + 1) as f64 * df };
                let u = rng.next_f64();
                let r = rng.next_f64();
                let f = f_lo + (i as f64 + u) * df;
                Harmonic { amplitude: (2.0 * table.integral(lo, hi)).sqrt(), omega: TAU * f, phase: TAU * r }
            })
            .collect();
        Ok(TimeProfile::Harmonics(terms))
    }
}

/// A one-sided power spectral density `S(f)` (units² / Hz, `f` in Hz):
/// `∫_0^∞ S df` is the signal's variance.
#[derive(Clone, Debug, PartialEq)]
pub enum Psd {
    /// `S(f) = level` over the band.
    Flat(f64),
    /// `S` piecewise linear through the points `(f[k], s[k])` (as
    /// [`Series`]: `>= 2` points, `f` strictly increasing, all finite), every
    /// `s[k] >= 0`, covering the band: `f[0] <= f_lo`, `f[K-1] >= f_hi`.
    Table {
        /// Frequencies (Hz), strictly increasing.
        f: Vec<f64>,
        /// PSD values (units²/Hz), >= 0.
        s: Vec<f64>,
    },
}

/// A band-limited random profile ([`TimeProfile::random`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RandomSpec {
    /// Lower band edge (Hz), finite and >= 0.
    pub f_lo: f64,
    /// Upper band edge (Hz), finite and > `f_lo`.
    pub f_hi: f64,
    /// The one-sided PSD over the band.
    pub psd: Psd,
    /// Number of harmonics (equal frequency bins), 1 ..= [`MAX_RANDOM_COUNT`].
    pub count: usize,
    /// The generator's seed: the same seed and spec give the same signal.
    pub seed: u64,
}

/// SplitMix64 (G. L. Steele, D. Lea, C. H. Flood, "Fast splittable
/// pseudorandom number generators", OOPSLA 2014; the reference C code is
/// S. Vigna's `splitmix64.c`, prng.di.unimi.it): a Weyl sequence
/// `state += 0x9e3779b97f4a7c15` followed by the mix
///
/// ```text
/// z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9
/// z = (z ^ (z >> 27)) * 0x94d049bb133111eb
/// z ^ (z >> 31)
/// ```
///
/// (wrapping `u64` arithmetic). Period `2⁶⁴`; plain integer operations, so
/// identical on every platform. Its first outputs for seed 1234567 are
/// 6457827717110365317, 3203168211198807973, 9817491932198370423, ...
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// The generator with state `seed`.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform number in `[0, 1)`: the top 53 bits of
    /// [`next_u64`](Self::next_u64) times `2⁻⁵³` (exact).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// How often [`Sampler`] recomputes its rotating phasors with `sin_cos`
/// (every this many steps), bounding the drift of the recurrence to about
/// `RESYNC · 2ε` relative to `Σ|a_i|`.
const RESYNC: u64 = 64;

/// One harmonic's rotating phasor `(cos θ, sin θ)`, `θ = ω t + p`, and its
/// per-step rotation `(cos ω dt, sin ω dt)`.
#[derive(Clone, Debug)]
struct Phasor {
    amp: f64,
    omega: f64,
    phase: f64,
    c: f64,
    s: f64,
    rc: f64,
    rs: f64,
}

/// A profile evaluated on equally spaced times, one call per step: the
/// values `s(t_n)`, `t_n = t0 + n dt` ([`Sampler::values`]), or the means
/// over `[t_n, t_{n+1}]` ([`Sampler::means`]), for `n = 0, 1, 2, ...`.
///
/// For `Harmonics` each term's phasor `e^{i θ_n}` is advanced by the exact
/// rotation `e^{i ω dt}` (four multiplications instead of a `sin`), and
/// recomputed from `θ_n = ω t_n + p` with `sin_cos` every 64 steps, so the
/// results agree with [`TimeProfile::value`] / [`TimeProfile::mean`] to
/// about `1e-14 Σ|a_i|`; the mean uses the amplitudes `a_i sinc(ω_i dt/2)`
/// at the midpoints. `Sine` and `Series` are evaluated directly (`Sine`
/// bit-identical to [`TimeProfile::value`] / [`TimeProfile::mean`]).
/// Allocation only at construction.
#[derive(Clone, Debug)]
pub struct Sampler {
    profile: TimeProfile,
    means: bool,
    t0: f64,
    dt: f64,
    n: u64,
    phasors: Vec<Phasor>,
}

impl Sampler {
    /// The values `s(t0 + n dt)`, `n = 0, 1, ...`.
    pub fn values(profile: &TimeProfile, t0: f64, dt: f64) -> Self {
        Self::new(profile, t0, dt, false)
    }

    /// The exact means over `[t0 + n dt, t0 + (n + 1) dt]`, `n = 0, 1, ...`
    /// (docs/theory.md §4.3's `fⁿ` for `t0 = 0`).
    pub fn means(profile: &TimeProfile, t0: f64, dt: f64) -> Self {
        Self::new(profile, t0, dt, true)
    }

    fn new(profile: &TimeProfile, t0: f64, dt: f64, means: bool) -> Self {
        let phasors = match profile {
            TimeProfile::Harmonics(h) => h
                .iter()
                .map(|h| {
                    let amp = if means { h.amplitude * sinc(0.5 * h.omega * dt) } else { h.amplitude };
                    let (rs, rc) = (h.omega * dt).sin_cos();
                    Phasor { amp, omega: h.omega, phase: h.phase, c: 1.0, s: 0.0, rc, rs }
                })
                .collect(),
            _ => Vec::new(),
        };
        Self { profile: profile.clone(), means, t0, dt, n: 0, phasors }
    }

    /// The index `n` of the next result.
    pub fn step(&self) -> u64 {
        self.n
    }

    /// The result for step `n` (the value at `t_n`, or the mean over
    /// `[t_n, t_{n+1}]`), then advances to `n + 1`.
    pub fn next_value(&mut self) -> f64 {
        let a = self.t0 + self.n as f64 * self.dt;
        let out = if self.phasors.is_empty() {
            let b = self.t0 + (self.n + 1) as f64 * self.dt;
            if self.means {
                self.profile.mean(a, b)
            } else {
                self.profile.value(a)
            }
        } else {
            if self.n % RESYNC == 0 {
                let t = if self.means { 0.5 * (a + (self.t0 + (self.n + 1) as f64 * self.dt)) } else { a };
                for p in &mut self.phasors {
                    (p.s, p.c) = (p.omega * t + p.phase).sin_cos();
                }
            }
            let mut sum = 0.0;
            for p in &mut self.phasors {
                sum += p.amp * p.s;
                (p.s, p.c) = (p.s * p.rc + p.c * p.rs, p.c * p.rc - p.s * p.rs);
            }
            sum
        };
        self.n += 1;
        out
    }
}
