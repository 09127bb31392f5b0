//! The forced impact oscillator, the reference problem of vibro-impact
//! dynamics: its exact flow between impacts, its period-1 orbits with their
//! Floquet multipliers, and its grazing frequencies.
//!
//! # Problem
//!
//! ```text
//! m x'' + c x' + k x = F cos(Ω t),   c = 2 ζ √(k m),   x <= g,
//! at x = g:  v⁺ = -r v⁻   (Newton's impact law, v⁻ > 0, r ∈ [0, 1]).
//! ```
//!
//! Divided by `m`: `x'' + 2ζω x' + ω² x = f cos(Ω t)` with `ω = √(k/m)`
//! (`ω_n`), `f = F/m`; damped frequency `ω_d = ω √(1 - ζ²)` (only
//! `0 <= ζ < 1` is accepted); forcing period `T = 2π/Ω`.
//!
//! # Flow between impacts (the free motion)
//!
//! The `T`-periodic particular solution is `x_p(t) = A cos Ωt + B sin Ωt`,
//! `v_p = x_p'`, with
//!
//! ```text
//! D = (ω² - Ω²)² + (2ζωΩ)²,   A = f (ω² - Ω²)/D,   B = f 2ζωΩ/D,
//! amplitude √(A² + B²) = (F/k) / √((1 - s²)² + (2ζ s)²),   s = Ω/ω.
//! ```
//!
//! (`D = 0` only for `ζ = 0`, `Ω = ω`: refused.) The rest `y = z - z_p`,
//! `z = (x, v)`, is free and damped: `y(t0 + h) = Φ(h) y(t0)` with
//!
//! ```text
//! Φ(h) = e^{-ζωh} [ cos ω_d h + ζω S      S                 ]
//!                 [ -ω² S                 cos ω_d h - ζω S  ],   S = sin(ω_d h)/ω_d,
//! det Φ(h) = e^{-2ζωh}.
//! ```
//!
//! [`ImpactOscillator::increment`] returns `z(t) - z(t0)` computed as
//! `(z_p(t) - z_p(t0)) + (Φ(h) - I)(z0 - z_p(t0))`, each difference in a form
//! without cancellation: `cos a - cos b = -2 sin((a+b)/2) sin((a-b)/2)`,
//! `sin a - sin b = 2 cos((a+b)/2) sin((a-b)/2)`, `e^{-ζωh} - 1 = expm1(-ζωh)`,
//! `cos ω_d h - 1 = -2 sin²(ω_d h/2)`. So the increment is accurate to
//! round-off relative to its own size even for `h = t - t0 → 0`, and
//! [`ImpactOscillator::flow`] is `z0 + increment`.
//!
//! # Period-1 orbits
//!
//! One impact per forcing period: leaving `(g, -rV)` at `τ`, the free motion
//! reaches `(g, V)` at `τ + T`, `V > 0`, and stays below the stop in between.
//! `z_p` is `T`-periodic, so with `p = z_p(τ)`, `a = g - p_x`, `b = p_v`,
//! `Φ = Φ(T)`:
//!
//! ```text
//! p + Φ ((g, -rV) - p) = (g, V)   ⟺   Φ11 a - Φ12 (rV + b) = a,
//!                                     Φ21 a - Φ22 (rV + b) = V - b.
//! ```
//!
//! Two equations, affine in `V`: `r Φ12 V = (Φ11 - 1) a - Φ12 b` and
//! `(1 + r Φ22) V = Φ21 a + (1 - Φ22) b`. They are consistent iff
//!
//! ```text
//! G(τ) = K1 a + K2 b = 0,    K1 = 1 - Φ11 + r Φ22 - r det Φ,    K2 = (1 + r) Φ12,
//! ```
//!
//! and `V` is then their least-squares solution (exact at a root, and never
//! divided by a vanishing `Φ12` or `1 + rΦ22` alone). Because `a` and `b`
//! are affine in `cos Ωτ`, `sin Ωτ`, the scalar equation is a sinusoid in
//! the forcing phase `θ = Ωτ`:
//!
//! ```text
//! G = K1 g + (K2 Ω B - K1 A) cos θ - (K1 B + K2 Ω A) sin θ = α + R cos(θ - φ),
//! ```
//!
//! so ALL its roots in `[0, 2π)` are `θ = φ ± arccos(-α/R)` (two, one double
//! root at a saddle-node `|α| = R`, or none): no bracketing is needed and
//! none can be missed. (The tests check this against a dense scan of the
//! residual computed by an independent Runge–Kutta integration.)
//!
//! A root is admissible iff `V > 0` and `x(t) < g` for all `t ∈ (τ, τ+T)`:
//! checked on a dense grid (at least 64 samples per period of the faster of
//! `ω` and `Ω`, and at least 256) and at every local maximum of `x`,
//! located by bisection of `v` on each grid interval where `v` turns from
//! `> 0` to `<= 0`. (The grid check is only an early exit: a crossing of the
//! stop implies an interior maximum above it.) Cost: `O(ω T + Ω T)` flow
//! evaluations per root.
//!
//! Conditioning: at a saddle-node (`|α| = R`, a double root) `arccos` is
//! ill-conditioned, so the two roots there carry errors of order `√ε`, and a
//! double root pushed to `|α| > R` by round-off is reported as no root.
//! Elsewhere `τ` and `V` are accurate to a few ulps (checked against a
//! 40-digit matrix-exponential solution on the reference scene).
//!
//! # Stability: monodromy with the saltation matrix
//!
//! Linearise the one-period map of the state just after impact. A
//! perturbation `δz` of the post-impact state at `τ` is carried by the free
//! flow to `Φ δz` at `τ + T`. The perturbed orbit hits the stop at
//! `τ + T + δt` with `x = g` there: `(Φ δz)_x + V δt = 0`, i.e.
//! `δt = -e1ᵀ Φ δz / V`. Its pre-impact state at its own impact time is
//! `z⁻ + Φ δz + f⁻ δt` (`f⁻ = (V, a⁻)` the pre-impact vector field); the
//! impact law `R(x, v) = (x, -r v)`, `DR = diag(1, -r)`, maps it to
//! `R(z⁻) + DR (Φ δz + f⁻ δt)`; flowing back by `δt` to the fixed time
//! `τ + T` with the post-impact field `f⁺ = (-rV, a⁺)` subtracts `f⁺ δt`:
//!
//! ```text
//! δz⁺ = [DR + (f⁺ - DR f⁻) e1ᵀ / V] Φ δz = S Φ δz,
//! S = [ -r                    0  ]     (saltation matrix; e1ᵀ f⁻ = V),
//!     [ (a⁺ + r a⁻)/V        -r  ]
//! a± = f cos Ωτ - ω² g - 2ζω v±,   v⁻ = V, v⁺ = -rV
//!   ⇒ a⁺ + r a⁻ = (1 + r)(f cos Ωτ - ω² g)   (the damping cancels).
//! ```
//!
//! The monodromy matrix is `M = S Φ(T)`; its eigenvalues `μ1, μ2` are the
//! Floquet multipliers (the Jacobian of the impact map `(τ_n, V_n) ↦
//! (τ_{n+1}, V_{n+1})` is similar to `M` for `rV ≠ 0`, so it has the same
//! eigenvalues). `det M = r² e^{-2ζωT}`, `tr M = -r (Φ11 + Φ22) + S21 Φ12`.
//! The orbit is (linearly) stable iff `|μ1| < 1` and `|μ2| < 1`.
//!
//! # Grazing
//!
//! The impacting period-1 branch ends at grazing (`V → 0`) where the
//! non-impacting steady state `x_p` just touches the stop: amplitude `= g`
//! (`g > 0`). With `u = s²`, `q = |F|/(k g)`:
//!
//! ```text
//! (1 - u)² + 4ζ² u = q²   ⟺   u² - 2(1 - 2ζ²) u + 1 - q² = 0,
//! u± = (1 - 2ζ²) ± √(q² - 4ζ²(1 - ζ²)),
//! ```
//!
//! the smaller root taken as `(1 - q²)/u₊` (no cancellation); each root
//! `u > 0` gives `Ω = ω √u` ([`ImpactOscillator::grazing_frequencies`]).
//! For `g <= 0` the steady state (mean 0) always reaches the stop: no
//! grazing frequency.

use std::f64::consts::TAU;
use std::fmt;

/// Parameters of the forced impact oscillator, as a scene gives them
/// (dimensional); validated by [`ImpactOscillator::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OscillatorParams {
    /// Mass `m` (finite, `> 0`).
    pub mass: f64,
    /// Stiffness `k` (finite, `> 0`).
    pub stiffness: f64,
    /// Damping ratio `ζ` (`0 <= ζ < 1`), `c = 2ζ√(km)`.
    pub damping_ratio: f64,
    /// Forcing amplitude `F` (finite) of `F cos(Ω t)`.
    pub force: f64,
    /// Forcing (angular) frequency `Ω` (finite, `> 0`).
    pub forcing_frequency: f64,
    /// Position `g` of the rigid stop above: `x <= g` (finite).
    pub gap: f64,
    /// Coefficient of restitution `r` (`0 <= r <= 1`): `v⁺ = -r v⁻`.
    pub restitution: f64,
}

/// A parameter rejected by [`ImpactOscillator::new`]: which one, its value,
/// and the range it must lie in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OscillatorError {
    /// The mass `m` must be finite and `> 0`.
    Mass(f64),
    /// The stiffness `k` must be finite and `> 0`.
    Stiffness(f64),
    /// The damping ratio `ζ` must lie in `[0, 1)` (underdamped).
    DampingRatio(f64),
    /// The force amplitude `F` must be finite.
    Force(f64),
    /// The forcing frequency `Ω` must be finite and `> 0`.
    ForcingFrequency(f64),
    /// The forcing frequency `Ω` equals `ω_n = √(k/m)` with `ζ = 0`: exact
    /// resonance, no periodic steady state.
    Resonance(f64),
    /// The gap `g` must be finite.
    Gap(f64),
    /// The restitution `r` must lie in `[0, 1]`.
    Restitution(f64),
}

impl OscillatorError {
    /// Name of the offending field of [`OscillatorParams`].
    #[must_use]
    pub fn field(&self) -> &'static str {
        match self {
            Self::Mass(_) => "mass",
            Self::Stiffness(_) => "stiffness",
            Self::DampingRatio(_) => "damping_ratio",
            Self::Force(_) => "force",
            Self::ForcingFrequency(_) | Self::Resonance(_) => "forcing_frequency",
            Self::Gap(_) => "gap",
            Self::Restitution(_) => "restitution",
        }
    }

    /// The rejected value.
    #[must_use]
    pub fn value(&self) -> f64 {
        match *self {
            Self::Mass(v) | Self::Stiffness(v) | Self::DampingRatio(v) | Self::Force(v) | Self::ForcingFrequency(v) | Self::Resonance(v) | Self::Gap(v) | Self::Restitution(v) => v,
        }
    }

    /// The allowed range, in words.
    #[must_use]
    pub fn allowed(&self) -> &'static str {
        match self {
            Self::Mass(_) | Self::Stiffness(_) | Self::ForcingFrequency(_) => "finite and > 0",
            Self::DampingRatio(_) => "in [0, 1)",
            Self::Force(_) | Self::Gap(_) => "finite",
            Self::Resonance(_) => "!= sqrt(k/m) when damping_ratio = 0",
            Self::Restitution(_) => "in [0, 1]",
        }
    }
}

impl fmt::Display for OscillatorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "impact oscillator: invalid {} = {} (must be {})", self.field(), self.value(), self.allowed())
    }
}

impl std::error::Error for OscillatorError {}

/// State `(x, v)` of the oscillator.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct State {
    /// Position `x`.
    pub x: f64,
    /// Velocity `v = x'`.
    pub v: f64,
}

/// A complex number `re + i im` (a Floquet multiplier).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Multiplier {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

impl Multiplier {
    /// Modulus `|μ|`.
    #[must_use]
    pub fn abs(&self) -> f64 {
        self.re.hypot(self.im)
    }
}

/// Why a root of the period-1 equation is not a physical orbit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Admissibility {
    /// `V > 0` and `x < g` on `(τ, τ + T)`: a period-1 impacting orbit.
    Admissible,
    /// `V <= 0`: the motion would arrive at the stop from above.
    NonPositiveVelocity,
    /// The free motion crosses the stop between the impacts: `x(time) =
    /// height >= g` for `time ∈ (τ, τ + T)`.
    Penetrates {
        /// A time at which `x >= g`.
        time: f64,
        /// `x` there.
        height: f64,
    },
}

/// A solution of the period-1 equations (one impact per forcing period),
/// admissible or not (see [`Period1Orbit::admissibility`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Period1Orbit {
    /// Impact time `τ ∈ [0, T)`.
    pub impact_time: f64,
    /// Forcing phase at impact, `Ωτ mod 2π ∈ [0, 2π)`.
    pub phase: f64,
    /// Pre-impact velocity `V` (`> 0` when admissible); the post-impact one
    /// is `-rV`.
    pub impact_velocity: f64,
    /// Monodromy matrix `M = S Φ(T)` of the post-impact state over one
    /// period (row-major), saltation matrix included (module docs).
    pub monodromy: [[f64; 2]; 2],
    /// Eigenvalues of `M` (the Floquet multipliers), the larger modulus first.
    pub multipliers: [Multiplier; 2],
    /// Admissibility of this root.
    pub admissibility: Admissibility,
}

impl Period1Orbit {
    /// `true` iff both multipliers have modulus `< 1`.
    #[must_use]
    pub fn is_stable(&self) -> bool {
        self.multipliers.iter().all(|m| m.abs() < 1.0)
    }

    /// `true` iff this root is a physical orbit ([`Admissibility::Admissible`]).
    #[must_use]
    pub fn is_admissible(&self) -> bool {
        self.admissibility == Admissibility::Admissible
    }
}

/// The forced impact oscillator `m x'' + c x' + k x = F cos Ωt`, `x <= g`,
/// Newton's law `v⁺ = -r v⁻` (module docs): exact flow, period-1 orbits,
/// grazing frequencies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactOscillator {
    p: OscillatorParams,
    /// `ω = √(k/m)`.
    wn: f64,
    /// `ω_d = ω √(1 - ζ²)`.
    wd: f64,
    /// `ζω`.
    sigma: f64,
    /// `f = F/m`.
    f: f64,
    /// Particular solution coefficients.
    a: f64,
    b: f64,
}

impl ImpactOscillator {
    /// Validates the parameters (each field finite and in its range, see
    /// [`OscillatorParams`]; `ζ = 0` with `Ω = √(k/m)` is refused).
    ///
    /// # Errors
    /// [`OscillatorError`] naming the first offending field.
    pub fn new(p: OscillatorParams) -> Result<Self, OscillatorError> {
        use OscillatorError as E;
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(p.mass) {
            return Err(E::Mass(p.mass));
        }
        if !pos(p.stiffness) {
            return Err(E::Stiffness(p.stiffness));
        }
        if !(0.0..1.0).contains(&p.damping_ratio) {
            return Err(E::DampingRatio(p.damping_ratio));
        }
        if !p.force.is_finite() {
            return Err(E::Force(p.force));
        }
        if !pos(p.forcing_frequency) {
            return Err(E::ForcingFrequency(p.forcing_frequency));
        }
        if !p.gap.is_finite() {
            return Err(E::Gap(p.gap));
        }
        if !(0.0..=1.0).contains(&p.restitution) {
            return Err(E::Restitution(p.restitution));
        }
        let wn = (p.stiffness / p.mass).sqrt();
        let z = p.damping_ratio;
        let wd = wn * ((1.0 - z) * (1.0 + z)).sqrt();
        let w = p.forcing_frequency;
        let det = (wn - w) * (wn + w);
        let cross = 2.0 * z * wn * w;
        let d = det * det + cross * cross;
        if d == 0.0 || !d.is_finite() {
            return Err(E::Resonance(w));
        }
        let f = p.force / p.mass;
        Ok(Self { p, wn, wd, sigma: z * wn, f, a: f * det / d, b: f * cross / d })
    }

    /// The validated parameters.
    #[must_use]
    pub fn params(&self) -> &OscillatorParams {
        &self.p
    }

    /// Natural frequency `ω_n = √(k/m)`.
    #[must_use]
    pub fn natural_frequency(&self) -> f64 {
        self.wn
    }

    /// Forcing period `T = 2π/Ω`.
    #[must_use]
    pub fn period(&self) -> f64 {
        TAU / self.p.forcing_frequency
    }

    /// Amplitude of the non-impacting steady state,
    /// `(F/k) / √((1 - s²)² + (2ζ s)²)`, `s = Ω/ω_n`.
    #[must_use]
    pub fn steady_amplitude(&self) -> f64 {
        self.a.hypot(self.b)
    }

    /// The `T`-periodic particular solution `z_p(t) = (A cos Ωt + B sin Ωt,
    /// Ω(B cos Ωt - A sin Ωt))` (the non-impacting steady state).
    #[must_use]
    pub fn steady_state(&self, t: f64) -> State {
        let w = self.p.forcing_frequency;
        let (s, c) = (w * t).sin_cos();
        State { x: self.a * c + self.b * s, v: w * (self.b * c - self.a * s) }
    }

    /// Transition matrix `Φ(h)` of the free damped motion (row-major), see
    /// the module docs.
    #[must_use]
    pub fn transition(&self, h: f64) -> [[f64; 2]; 2] {
        let (e, _, c, _, s) = self.homogeneous_parts(h);
        let w2 = self.wn * self.wn;
        [[e * (c + self.sigma * s), e * s], [-e * w2 * s, e * (c - self.sigma * s)]]
    }

    /// `(e^{-ζωh}, expm1(-ζωh), cos ω_d h, cos ω_d h - 1, sin(ω_d h)/ω_d)`.
    #[inline]
    fn homogeneous_parts(&self, h: f64) -> (f64, f64, f64, f64, f64) {
        let em1 = (-self.sigma * h).exp_m1();
        let (sn, c) = (self.wd * h).sin_cos();
        let half = (0.5 * self.wd * h).sin();
        (1.0 + em1, em1, c, -2.0 * half * half, sn / self.wd)
    }

    /// `z(t) - z0` for the free motion (no stop) leaving `z0` at `t0`,
    /// accurate relative to its own size for small `t - t0` (module docs).
    #[must_use]
    pub fn increment(&self, t0: f64, z0: State, t: f64) -> State {
        let h = t - t0;
        let w = self.p.forcing_frequency;
        // Particular part: z_p(t) - z_p(t0).
        let sh = (0.5 * w * h).sin();
        let (sm, cm) = (0.5 * w * (t + t0)).sin_cos();
        let dcos = -2.0 * sm * sh;
        let dsin = 2.0 * cm * sh;
        let dxp = self.a * dcos + self.b * dsin;
        let dvp = w * (self.b * dcos - self.a * dsin);
        // Homogeneous part: (Φ(h) - I) y0.
        let p0 = self.steady_state(t0);
        let (y, yv) = (z0.x - p0.x, z0.v - p0.v);
        let (e, em1, _, cm1, s) = self.homogeneous_parts(h);
        let w2 = self.wn * self.wn;
        let base = e * cm1 + em1; // e cos - 1
        let p11 = base + e * self.sigma * s;
        let p12 = e * s;
        let p21 = -e * w2 * s;
        let p22 = base - e * self.sigma * s;
        State { x: dxp + p11 * y + p12 * yv, v: dvp + p21 * y + p22 * yv }
    }

    /// The state at `t` of the free motion (no stop) leaving `z0` at `t0`:
    /// `z0 + increment(t0, z0, t)`. Any `t` (also `t < t0`).
    #[must_use]
    pub fn flow(&self, t0: f64, z0: State, t: f64) -> State {
        let d = self.increment(t0, z0, t);
        State { x: z0.x + d.x, v: z0.v + d.v }
    }

    /// The forcing frequencies `Ω > 0` at which the steady-state amplitude
    /// equals the gap (grazing of the non-impacting orbit), increasing;
    /// empty for `g <= 0` or when the amplitude never reaches `g` (module
    /// docs, "Grazing"). Uses `m`, `k`, `ζ`, `F`, `g` (not `Ω` or `r`).
    #[must_use]
    pub fn grazing_frequencies(&self) -> Vec<f64> {
        let g = self.p.gap;
        if g <= 0.0 {
            return Vec::new();
        }
        let z = self.p.damping_ratio;
        let q = self.p.force.abs() / (self.p.stiffness * g);
        let q2 = q * q;
        let disc = q2 - 4.0 * z * z * (1.0 - z * z);
        if disc < 0.0 {
            return Vec::new();
        }
        let mid = 1.0 - 2.0 * z * z;
        let up = mid + disc.sqrt();
        let mut out = Vec::with_capacity(2);
        if up > 0.0 {
            let um = (1.0 - q2) / up;
            if um > 0.0 && um < up {
                out.push(self.wn * um.sqrt());
            }
            out.push(self.wn * up.sqrt());
        }
        out
    }

    /// All roots of the period-1 equation `G(τ) = 0` in `[0, T)` (module
    /// docs), admissible or not, by increasing phase, each with its
    /// pre-impact velocity, monodromy, multipliers and admissibility. At
    /// most two; none when the equation degenerates (`G ≡ 0` up to
    /// round-off, e.g. `ζ = 0` with `ω T` a multiple of `2π`).
    #[must_use]
    pub fn period1_roots(&self) -> Vec<Period1Orbit> {
        let t_per = self.period();
        let w = self.p.forcing_frequency;
        let r = self.p.restitution;
        let g = self.p.gap;
        let phi = self.transition(t_per);
        let det = phi[0][0] * phi[1][1] - phi[0][1] * phi[1][0];
        let k1 = 1.0 - phi[0][0] + r * phi[1][1] - r * det;
        let k2 = (1.0 + r) * phi[0][1];
        // G = α + β cos θ + γ sin θ.
        let alpha = k1 * g;
        let beta = k2 * w * self.b - k1 * self.a;
        let gamma = -(k1 * self.b + k2 * w * self.a);
        let rr = beta.hypot(gamma);
        let scale = (k1.abs() + k2.abs() / self.wn) * (g.abs() + self.steady_amplitude());
        if rr <= 1e-13 * scale || rr == 0.0 {
            return Vec::new();
        }
        let c = -alpha / rr;
        if c.abs() > 1.0 {
            return Vec::new();
        }
        let ph = gamma.atan2(beta);
        let d = c.acos();
        let mut thetas = [wrap(ph - d), wrap(ph + d)];
        thetas.sort_by(f64::total_cmp);
        let n = if d == 0.0 { 1 } else { 2 };
        thetas[..n].iter().map(|&th| self.orbit_at(th, &phi)).collect()
    }

    /// The admissible period-1 orbits ([`Self::period1_roots`] filtered).
    #[must_use]
    pub fn period1_orbits(&self) -> Vec<Period1Orbit> {
        self.period1_roots().into_iter().filter(Period1Orbit::is_admissible).collect()
    }

    /// The orbit data at a root `θ` of the period-1 equation.
    fn orbit_at(&self, theta: f64, phi: &[[f64; 2]; 2]) -> Period1Orbit {
        let w = self.p.forcing_frequency;
        let r = self.p.restitution;
        let g = self.p.gap;
        let tau = theta / w;
        let (s, c) = theta.sin_cos();
        let px = self.a * c + self.b * s;
        let pv = w * (self.b * c - self.a * s);
        let (a, b) = (g - px, pv);
        // r Φ12 V = (Φ11 - 1) a - Φ12 b;  (1 + r Φ22) V = Φ21 a + (1 - Φ22) b.
        let (c1, d1) = (r * phi[0][1], (phi[0][0] - 1.0) * a - phi[0][1] * b);
        let (c2, d2) = (1.0 + r * phi[1][1], phi[1][0] * a + (1.0 - phi[1][1]) * b);
        let v = (c1 * d1 + c2 * d2) / (c1 * c1 + c2 * c2);
        // Saltation S = [[-r, 0], [(1 + r)(f cos θ - ω² g)/V, -r]], M = S Φ.
        let s21 = (1.0 + r) * (self.f * c - self.wn * self.wn * g) / v;
        let m = [[-r * phi[0][0], -r * phi[0][1]], [s21 * phi[0][0] - r * phi[1][0], s21 * phi[0][1] - r * phi[1][1]]];
        Period1Orbit { impact_time: tau, phase: theta, impact_velocity: v, monodromy: m, multipliers: eigenvalues(&m), admissibility: self.admissibility(tau, v) }
    }

    /// Checks `V > 0` and `x < g` on `(τ, τ + T)` (module docs).
    fn admissibility(&self, tau: f64, v: f64) -> Admissibility {
        if v.is_nan() || v <= 0.0 {
            return Admissibility::NonPositiveVelocity;
        }
        let g = self.p.gap;
        let t_per = self.period();
        let z0 = State { x: g, v: -self.p.restitution * v };
        let fastest = self.wn.max(self.p.forcing_frequency);
        let n = ((64.0 * fastest * t_per / TAU).ceil() as usize).max(256);
        let dt = t_per / n as f64;
        let at = |t: f64| self.flow(tau, z0, t);
        let mut prev = z0;
        let mut t_prev = tau;
        for j in 1..=n {
            let t = if j == n { tau + t_per } else { tau + j as f64 * dt };
            let z = at(t);
            if j < n && z.x >= g {
                return Admissibility::Penetrates { time: t, height: z.x };
            }
            if prev.v > 0.0 && z.v <= 0.0 {
                // A local maximum of x in (t_prev, t]: bisect v.
                let (mut lo, mut hi) = (t_prev, t);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    if at(mid).v > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let tm = 0.5 * (lo + hi);
                let xm = at(tm).x;
                if xm >= g {
                    return Admissibility::Penetrates { time: tm, height: xm };
                }
            }
            prev = z;
            t_prev = t;
        }
        Admissibility::Admissible
    }
}

/// `θ` folded into `[0, 2π)`.
fn wrap(theta: f64) -> f64 {
    let t = theta.rem_euclid(TAU);
    if t >= TAU {
        0.0
    } else {
        t
    }
}

/// Eigenvalues of a real 2×2 matrix, the larger modulus first.
fn eigenvalues(m: &[[f64; 2]; 2]) -> [Multiplier; 2] {
    let tr = m[0][0] + m[1][1];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let half = 0.5 * tr;
    // tr²/4 - det, with the off-diagonal product kept apart to limit cancellation.
    let diff = 0.5 * (m[0][0] - m[1][1]);
    let disc = diff * diff + m[0][1] * m[1][0];
    if disc >= 0.0 {
        let big = half + half.signum() * disc.sqrt();
        let small = if big == 0.0 { 0.0 } else { det / big };
        let (x, y) = if big.abs() >= small.abs() { (big, small) } else { (small, big) };
        [Multiplier { re: x, im: 0.0 }, Multiplier { re: y, im: 0.0 }]
    } else {
        let im = (-disc).sqrt();
        [Multiplier { re: half, im }, Multiplier { re: half, im: -im }]
    }
}
