//! The exact flow of `M q'' + C q' + K q = F + Σ_j g_j s_j(t)` between events.
//!
//! With `M = L Lᵀ` and `L⁻¹ K L⁻ᵀ = V Λ Vᵀ`, the modes `Φ = L⁻ᵀ V` are
//! M-orthonormal (`Φᵀ M Φ = I`, `Φᵀ K Φ = Λ`); a damping matrix that `Φ`
//! diagonalises (classical damping: Rayleigh `C = a M + b K` among them)
//! gives `Φᵀ C Φ = diag(c_i)`. Each modal coordinate `η_i = φ_iᵀ M q` then
//! obeys the scalar equation
//!
//! ```text
//! η'' + c η' + k η = g₀ + Σ_j G_j a_j sin(Ω_j t + p_j),   k = ω_i², G_j = φ_iᵀ g_j
//! ```
//!
//! whose solution is a particular solution `P(t)` (one per load term:
//! `g₀/k`; `A sin θ + B cos θ` with `(k − Ω²) A − cΩ B = G a`,
//! `cΩ A + (k − Ω²) B = 0`; near resonance, `|k − Ω² + icΩ| <= 1e-2 k`,
//! the response from rest at the step's start, the secular `−G a t cos θ /
//! (2Ω)` at `c = 0`, `k = Ω²`; a free mode `k = 0` integrates the constant)
//! plus the homogeneous flow of `e = η − P` over `τ`:
//!
//! ```text
//! e(τ)  = e^{−ατ} [ e₀ C(τ) + (e₀' + α e₀) S(τ) ]
//! e'(τ) = e^{−ατ} [ e₀' C(τ) − (α e₀' + k e₀) S(τ) ],   α = c/2, λ = k − α²
//! ```
//!
//! with `C, S = cos(√λ τ), sin(√λ τ)/√λ` (λ > 0), `cosh, sinh(√−λ τ)/√−λ`
//! (λ < 0), `1, τ` (λ = 0). Every step is closed form: the flow is exact to
//! round-off over any interval, however long.
//!
//! The event search needs more than the state: the derivatives of every
//! modal coordinate at a time (its *jet*) and bounds of
//! each derivative over a window ([`ModalFlow::jet_and_bounds`]). Both follow from
//! the scalar equation: `e^{(m)} = −c e^{(m−1)} − k e^{(m−2)}`, and the
//! particular solutions' derivatives in closed form.
//!
//! **Non-classical damping** (`Φᵀ C Φ` not diagonal) takes the first-order
//! form ([`General`], docs/theory.md §9.1): per mode a real invariant plane
//! of `[0 I; −M⁻¹K −M⁻¹C]` in which `η = a` obeys the same scalar equation
//! with the load `r + c p + p'`, and `η' = b + p(t)`.
//!
//! **Piecewise-linear loads.** A load `g s(t)` with `s` a piecewise-linear
//! series is, on each piece, a constant plus a ramp: `a + b (t − t_p)`. Its
//! particular solution is exact on the piece (`k > 0`: `(a + b τ)/k −
//! c b/k²`; `k = 0`: the integrals of the load, vanishing at the interval's
//! start), and the flow is set to each piece in turn
//! ([`ModalFlow::set_piece`]): [`super::EventDriven`] stops its searches at
//! the series' breakpoints, where only the slope changes (the load is
//! continuous, so is the state).

use super::record::EventsError;
use super::Bound;
use crate::{Dynamics, Series, TimeProfile};
use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, Side};
use signorini_fem::SymBand;

/// Orders of a mode's jet: `η, η', …, η⁽⁵⁾`.
pub(crate) const JET: usize = 6;

/// A load on the full problem: `F₀ + Σ_j g_j a_j sin(Ω_j t + p_j) + Σ_l h_l s_l(t)`.
#[derive(Clone, Debug)]
pub(crate) struct Loads {
    pub constant: Vec<f64>,
    /// `(g_j, a_j, Ω_j, p_j)`, Ω_j ≠ 0.
    pub waves: Vec<(Vec<f64>, f64, f64, f64)>,
    /// `(h_l, s_l)`: piecewise-linear series (with the index of their forcing term).
    pub ramps: Vec<(Vec<f64>, Series, usize)>,
}

/// The piece of every series at a time: `s_l(t) = values_l + slopes_l (t − t_p)`
/// up to `next` (the first breakpoint after `t_p`).
#[derive(Clone, Debug, Default)]
pub(crate) struct Piece {
    pub t_p: f64,
    pub values: Vec<f64>,
    pub slopes: Vec<f64>,
    pub next: f64,
}

impl Loads {
    /// Whether a load depends on time (a harmonic, a series): a flow from
    /// a state then depends on the absolute time, not only on the elapsed
    /// one (docs/theory.md §9.2).
    pub fn time_dependent(&self) -> bool {
        !self.waves.is_empty() || !self.ramps.is_empty()
    }

    /// The loads of `dy`: its steady load, its sines and harmonics (a
    /// harmonic of frequency 0 is the constant `a sin p`).
    pub fn of(dy: &Dynamics) -> Result<Self, EventsError> {
        let mut constant = dy.load.clone();
        let mut waves = Vec::new();
        let mut ramps = Vec::new();
        for (index, f) in dy.forcing.iter().enumerate() {
            match &f.time {
                &TimeProfile::Sine { amplitude, omega } => waves.push((f.shape.clone(), amplitude, omega, 0.0)),
                TimeProfile::Harmonics(h) => {
                    for t in h.iter() {
                        if t.omega == 0.0 {
                            let s = t.amplitude * t.phase.sin();
                            constant.iter_mut().zip(&f.shape).for_each(|(c, g)| *c += s * g);
                        } else {
                            waves.push((f.shape.clone(), t.amplitude, t.omega, t.phase));
                        }
                    }
                }
                TimeProfile::Series(s) => ramps.push((f.shape.clone(), s.clone(), index)),
            }
        }
        Ok(Self { constant, waves, ramps })
    }

    /// [`of`](Self::of), a piecewise-linear series refused (a flow that
    /// takes no piece: [`EventsError::Profile`]).
    pub fn without_series(dy: &Dynamics) -> Result<Self, EventsError> {
        let loads = Self::of(dy)?;
        if let Some((_, _, index)) = loads.ramps.first() {
            return Err(EventsError::Profile { index: *index });
        }
        Ok(loads)
    }

    /// The loads of a phase's flow: `f − K_·A q_A` (the `held` dofs'
    /// displacements, `K`'s entries `k(i, j)`, load the others), the waves
    /// and the series, each mapped onto the flow's dofs by `reduce` (the
    /// free dofs' entries; with massless dofs, the static condensation's).
    pub fn held(&self, k: impl Fn(usize, usize) -> f64, held: &[(usize, f64)], reduce: impl Fn(&[f64]) -> Vec<f64>) -> Self {
        let mut steady = self.constant.clone();
        for (d, x) in steady.iter_mut().enumerate() {
            for &(a, xa) in held {
                *x -= k(d, a) * xa;
            }
        }
        Self {
            constant: reduce(&steady),
            waves: self.waves.iter().map(|(g, a, w, p)| (reduce(g), *a, *w, *p)).collect(),
            ramps: self.ramps.iter().map(|(h, s, index)| (reduce(h), s.clone(), *index)).collect(),
        }
    }

    /// `F'(t)_r` on `piece` (the series' slopes there).
    pub fn rate(&self, r: usize, t: f64, piece: &Piece) -> f64 {
        self.waves.iter().map(|(g, a, w, p)| g[r] * a * w * (w * t + p).cos()).sum::<f64>() + self.ramps.iter().enumerate().map(|(l, (h, _, _))| h[r] * piece.slopes[l]).sum::<f64>()
    }

    /// `F(t)_r`.
    pub fn value(&self, r: usize, t: f64) -> f64 {
        self.constant[r] + self.waves.iter().map(|(g, a, w, p)| g[r] * a * (w * t + p).sin()).sum::<f64>() + self.ramps.iter().map(|(h, s, _)| h[r] * s.value(t)).sum::<f64>()
    }

    /// The piece of every series at `t` (right-continuous: at a breakpoint,
    /// the piece that starts there), into `out`.
    pub fn piece_into(&self, t: f64, out: &mut Piece) {
        out.t_p = t;
        out.next = f64::INFINITY;
        out.values.clear();
        out.slopes.clear();
        for (_, s, _) in &self.ramps {
            let (value, slope, next) = s.piece(t);
            out.values.push(value);
            out.slopes.push(slope);
            out.next = out.next.min(next.unwrap_or(f64::INFINITY));
        }
    }
}

/// The first-order form of a problem with non-classical damping
/// (docs/theory.md §9.1): `z = (q, v) = T ζ` with `ζ = (a_1, b_1, a_2, b_2, …)`
/// and, per mode, `a' = b + p(t)`, `b' = −k a − c b + r(t)` (`p = P F`,
/// `r = R F` the load's projections). The mode's coordinate `η = a` then
/// obeys `η'' + c η' + k η = r + c p + p'` and `η' = b + p(t)`.
#[derive(Clone, Debug)]
struct General {
    /// `T` (2n × 2n): columns `2i, 2i + 1` are mode `i`'s `x_a, x_b`.
    t: Mat<f64>,
    /// `T⁻¹`.
    tinv: Mat<f64>,
    /// `M⁻¹`.
    minv: Mat<f64>,
    /// `p_i(t) = pf0_i + Σ_j ph_j,i a_j sin(Ω_j t + p_j) + Σ_l pr_l,i s_l(t)`.
    pf0: Vec<f64>,
    ph: Vec<Vec<f64>>,
    /// `(a_j, Ω_j, p_j)` of each load wave.
    waves: Vec<(f64, f64, f64)>,
    pr: Vec<Vec<f64>>,
    /// [`GeneralBasis::drive`].
    drive: Vec<f64>,
}

/// One harmonic load term in modal coordinates: `G_i a sin(Ω t + p)` for every mode `i`.
#[derive(Clone, Debug)]
pub(crate) struct Harmonic {
    pub modal: Vec<f64>,
    pub amplitude: f64,
    pub omega: f64,
    pub phase: f64,
    /// Per mode, the coefficients of its particular solution, computed
    /// once (a flow's `k_i`, `c_i` and loads are fixed): the search and
    /// every sample read them, the same bits as computed in place.
    pub coef: Vec<Coef>,
}

/// Mode `i`'s particular solution of a harmonic `g sin θ` (`g = G_i a`):
/// none (`g = 0`), near resonance (`√d <= NEAR k`, [`near`]) the response
/// from rest at `t_ref` ([`from_rest`]; `g` kept), or steady `a sin θ + b
/// cos θ` with `a = g δ/d`, `b = −g c Ω/d` (`δ = k − Ω²`, `d = δ² + (cΩ)²`).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Coef {
    Zero,
    Near(f64),
    Steady(f64, f64),
}

/// The steady coefficients `(g δ/d, −g c Ω/d)` of [`Coef::Steady`].
fn steady_coef(k: f64, c: f64, g: f64, w: f64) -> Coef {
    let detune = k - w * w;
    let d = detune * detune + (c * w) * (c * w);
    Coef::Steady(g * detune / d, -g * c * w / d)
}

impl Harmonic {
    fn new(modal: Vec<f64>, amplitude: f64, omega: f64, phase: f64, k: &[f64], c: &[f64]) -> Self {
        let coef = (0..modal.len())
            .map(|i| {
                let (k, c, g, w) = (k[i], c[i], modal[i] * amplitude, omega);
                if g == 0.0 {
                    Coef::Zero
                } else if near(k, c, w) {
                    Coef::Near(g)
                } else {
                    steady_coef(k, c, g, w)
                }
            })
            .collect();
        Self { modal, amplitude, omega, phase, coef }
    }

    /// The coefficients of each driven mode `i` (a defective chain's,
    /// `drive[i] = s ≠ 0`) for its load `g sin θ` plus `s` times its
    /// driver's particular solution `a₂ sin θ + b₂ cos θ`, i.e. `G sin θ + H
    /// cos θ`: `(G p − H q) sin θ + (G q + H p) cos θ`, with `p sin θ + q cos
    /// θ` the response to `sin θ` (`p = δ/d`, `q = −cΩ/d`) and `cos θ =
    /// sin(θ + π/2)`. A chain's modes are damped (`c > 0`): their steady
    /// coefficients are finite, taken even near resonance.
    fn driven(mut self, k: &[f64], c: &[f64], drive: &[f64]) -> Self {
        for (i, &s) in drive.iter().enumerate() {
            if s == 0.0 {
                continue;
            }
            for j in [i, i + 1] {
                if let Coef::Near(g) = self.coef[j] {
                    self.coef[j] = steady_coef(k[j], c[j], g, self.omega);
                }
            }
            let Coef::Steady(a2, b2) = self.coef[i + 1] else { continue };
            let (g, h) = (self.modal[i] * self.amplitude + s * a2, s * b2);
            let (k, c, w) = (k[i], c[i], self.omega);
            let detune = k - w * w;
            let d = detune * detune + (c * w) * (c * w);
            let (p, q) = (detune / d, -c * w / d);
            self.coef[i] = Coef::Steady(g * p - h * q, g * q + h * p);
        }
        self
    }
}

/// The exact flow of a linear problem between events (see the module docs).
#[derive(Clone, Debug)]
pub struct ModalFlow {
    n: usize,
    /// Φ (columns: the modes), n × n.
    pub(crate) phi: Mat<f64>,
    /// `M Φ`: `η = (M Φ)ᵀ q`.
    m_phi: Mat<f64>,
    /// ω_i² (ascending).
    pub(crate) k: Vec<f64>,
    /// Modal damping `c_i = φ_iᵀ C φ_i`.
    pub(crate) c: Vec<f64>,
    /// The steady load in modal coordinates.
    pub(crate) g0: Vec<f64>,
    pub(crate) harmonics: Vec<Harmonic>,
    /// Each series' load shape in modal coordinates.
    pub(crate) ramp_modal: Vec<Vec<f64>>,
    /// Non-classical damping: the first-order form (module docs), `None`
    /// for classical damping.
    general: Option<Box<General>>,
    /// The series' values and slopes on the current piece.
    piece: Vec<(f64, f64)>,
    /// The constant and ramp loads on the current piece:
    /// `ga_i + gb_i (t − tp)` (`g0` and 0 without series).
    ga: Vec<f64>,
    gb: Vec<f64>,
    tp: f64,
    /// [`Loads::time_dependent`] of its loads (a flow without modes, every
    /// dof held, still sees them in its held forces).
    time_dependent: bool,
}

pub(crate) fn dense(a: &signorini_fem::SymBand) -> Mat<f64> {
    Mat::from_fn(a.n(), a.n(), |i, j| a.get(i, j))
}

/// `cos(ωτ) − 1` and `sin(ωτ)/ω` (`ω = √λ`; `cosh`, `sinh` for `λ < 0`; `0, τ`
/// for `λ = 0`), the first accurate for small `τ`:
/// `cos(ωτ) − 1 = −2 sin²(ωτ/2)`, `cosh(ωτ) − 1 = 2 sinh²(ωτ/2)`.
fn cs_m1(lambda: f64, tau: f64) -> (f64, f64) {
    // One `sin_cos` of the half angle: `sin ωτ = 2 sin(ωτ/2) cos(ωτ/2)`.
    if lambda > 0.0 {
        let w = lambda.sqrt();
        let (h, c) = (0.5 * w * tau).sin_cos();
        (-2.0 * h * h, 2.0 * h * c / w)
    } else if lambda < 0.0 {
        let w = (-lambda).sqrt();
        let h = (0.5 * w * tau).sinh();
        (2.0 * h * h, 2.0 * h * (1.0 + h * h).sqrt() / w)
    } else {
        (0.0, tau)
    }
}

/// The particular solution of the steady load `a + b τ` (`τ = t − t_ref`)
/// of a mode `(k, c)` and its derivatives (orders 0..4), each as its terms,
/// every term a constant times a power of `τ`: order `m` is the sum of
/// `terms[m]`, and the sum of their magnitudes at `τ = h` bounds it over
/// `[0, h]`. `k > 0`: `(a + b τ)/k − c b/k²`; `k = 0 < c`:
/// `a τ/c − b τ/c² + b τ²/(2c)`; `k = c = 0`: `a τ²/2 + b τ³/6` (the ones
/// that grow vanish at `τ = 0`).
fn steady_terms(k: f64, c: f64, a: f64, b: f64, tau: f64) -> [[f64; 3]; 4] {
    let mut t = [[0.0; 3]; 4];
    if k > 0.0 && b == 0.0 && k * k > 0.0 {
        // No ramp (`b = ±0`, the usual case): each term with `b` is a
        // signed zero (or NaN), which a division by `k` or `k² > 0` leaves
        // as it is: the same bits as the general form, without its
        // divisions (they are most of a step's arithmetic besides `sin_cos`).
        t[0] = [a / k, b * tau, -c * b];
        t[1][0] = b;
    } else if k > 0.0 {
        t[0] = [a / k, b * tau / k, -c * b / (k * k)];
        t[1][0] = b / k;
    } else if c > 0.0 {
        t[0] = [a * tau / c, -b * tau / (c * c), 0.5 * b * tau * tau / c];
        t[1] = [a / c, -b / (c * c), b * tau / c];
        t[2][0] = b / c;
    } else {
        t[0] = [0.5 * a * tau * tau, b * tau * tau * tau / 6.0, 0.0];
        t[1] = [a * tau, 0.5 * b * tau * tau, 0.0];
        t[2] = [a, b * tau, 0.0];
        t[3][0] = b;
    }
    t
}

/// `φ_1 … φ_4` of `z <= 0`: `φ_k(z) = (e^z − Σ_{j<k} z^j/j!)/z^k` (`φ_k(0)
/// = 1/k!`), each to a few ulps: the series `Σ_j z^j/(j + k)!` for `|z| <=
/// 1` (its 20th term below 1e-19 of `φ_k`), else `φ_1 = expm1(z)/z` and
/// `φ_{k+1} = (φ_k − 1/k!)/z`, which lose at most a few ulps once `|z| >= 1`.
/// A damped free mode (`k = 0 < c`, a free chain's rigid pair) responds to
/// a load `a + b τ` with `η' = η₀' e^z + a τ φ_1 + b τ² φ_2`, `η = η₀ +
/// η₀' τ φ_1 + a τ² φ_2 + b τ³ φ_3` (`z = −c τ`): no `1/c` (docs/theory.md §9.1).
fn phis(z: f64) -> [f64; 4] {
    if z.abs() <= 1.0 {
        // φ_4 by its series, then φ_k = 1/k! + z φ_{k+1} downwards.
        let mut term = 1.0 / 24.0;
        let mut p4 = term;
        for j in 1..=20 {
            term *= z / f64::from(j + 4);
            p4 += term;
        }
        let p3 = 1.0 / 6.0 + z * p4;
        let p2 = 0.5 + z * p3;
        let p1 = 1.0 + z * p2;
        [p1, p2, p3, p4]
    } else {
        let p1 = z.exp_m1() / z;
        let p2 = (p1 - 1.0) / z;
        let p3 = (p2 - 0.5) / z;
        [p1, p2, p3, (p3 - 1.0 / 6.0) / z]
    }
}

/// Bounds of a free mode's `|e|` and `|e'|` over `[0, h]` from `(e₀, e₀')`
/// ([`ModalFlow::jet_and_bounds`], docs/theory.md §9.2), and `S̄`.
fn free_bounds(k: f64, c: f64, e0: f64, de0: f64, h: f64) -> (f64, f64, f64) {
    let alpha = 0.5 * c;
    let lambda = k - alpha * alpha;
    let sbar = if lambda > 0.0 { h.min(1.0 / lambda.sqrt()) } else { h };
    let b1 = de0 + alpha * e0;
    let mut d0 = e0.abs() + b1.abs() * sbar;
    if lambda > 0.0 {
        d0 = d0.min((e0 * e0 + b1 * b1 / lambda).sqrt());
    }
    (d0, de0.abs() + (alpha * de0 + k * e0).abs() * sbar, sbar)
}

/// `(e^{yτ} − e^{xτ})/(y − x)` (`τ e^{xτ}` for `y = x`) without
/// cancellation however close `x` and `y` are: `τ e^{xτ} φ₁((y − x)τ)`
/// with `φ₁(z) = Σ z^j/(j + 1)!` for `|(y − x)τ| <= 1` (its 20th term below
/// 1e-19), the quotient beyond (where it loses at most a few ulps).
fn divided(x: faer::c64, y: faer::c64, tau: f64) -> faer::c64 {
    let z = (y - x) * tau;
    if z.norm() <= 1.0 {
        let (mut term, mut sum) = (faer::c64::new(1.0, 0.0), faer::c64::new(1.0, 0.0));
        for j in 1..=20 {
            term = term * z / f64::from(j + 1);
            sum += term;
        }
        (x * tau).exp() * sum * tau
    } else {
        ((y * tau).exp() - (x * tau).exp()) / (y - x)
    }
}

/// `e^{−ατ} cosh(βτ)` and `e^{−ατ} sinh(βτ)/β` for `0 < β <= α`, without
/// overflow or cancellation.
fn overdamped(alpha: f64, beta: f64, tau: f64) -> (f64, f64) {
    let (slow, fast) = ((-(alpha - beta) * tau).exp(), (-(alpha + beta) * tau).exp());
    let ds = if 2.0 * beta * tau < 1.0 { 0.5 * fast * (2.0 * beta * tau).exp_m1() / beta } else { 0.5 * (slow - fast) / beta };
    (0.5 * (slow + fast), ds)
}

/// A harmonic of frequency `w` within this of a mode's resonance (`√d =
/// |k − w² + i c w| <= NEAR k`) takes the response from rest ([`from_rest`]):
/// the steady coefficients `g/√d` cancel against the homogeneous part to
/// `ε k/√d` of the motion (docs/theory.md §9.1). Measured on a chain's
/// mode, forced at `ω (1 + r)`: the state off the exponential by 4.6e-4
/// at `r = 2e-13` (1e-13 above the secular form's old band), 1.7e-4 at
/// `r = 1e-12`, 5e-8 at `1e-9`, 1.3e-10 at `1e-6`; with `c = 1e-14` at
/// `r = 0`, 5.3e-3; event runs stalled (1e7 search steps). Here the
/// steady form loses at most `100 ε`.
const NEAR: f64 = 1e-2;

/// Whether a harmonic of frequency `w` is near the resonance of the mode `(k, c)` ([`NEAR`]).
fn near(k: f64, c: f64, w: f64) -> bool {
    k > 0.0 && (k - w * w).hypot(c * w) <= NEAR * k
}

/// The response of a mode `(k, c)` (underdamped: [`near`] implies it) from
/// rest at `τ = 0` to `g sin(θ₀ + Ω τ)` (`(sin θ₀, cos θ₀)`), and its
/// derivative, at `τ`: with `G(u) = Im e^{μu}/β` the impulse response (`μ =
/// −α + iβ`), `∫₀^τ G(τ − u) g sin(θ₀ + Ω u) du = g/(2β) Re[e^{−iθ₀} I(μ,
/// −iΩ) − e^{iθ₀} I(μ, iΩ)]` and `μ` inside the bracket for the derivative,
/// `I(x, y) = ∫₀^τ e^{x(τ − u)} e^{yu} du` ([`divided`]): the secular `τ
/// e^{iωτ}` at `μ = iΩ`, to round-off however small the detuning.
fn from_rest(k: f64, c: f64, g: f64, w: f64, (s0, c0): (f64, f64), tau: f64) -> (f64, f64) {
    let mu = faer::c64::new(-0.5 * c, (k - 0.25 * c * c).sqrt());
    let turn = faer::c64::new(c0, s0);
    let z = turn.conj() * divided(mu, faer::c64::new(0.0, -w), tau) - turn * divided(mu, faer::c64::new(0.0, w), tau);
    let f = g / (2.0 * mu.im);
    (f * z.re, f * (mu * z).re)
}

/// [`from_rest`] at `st` from `t_ref = t − st` (`(s, co)`: `sin, cos θ` at
/// `t`) and its derivatives up to order `N − 1` into `p` (added): `P⁽ᵐ⁾ =
/// f⁽ᵐ⁻²⁾ − c P⁽ᵐ⁻¹⁾ − k P⁽ᵐ⁻²⁾`, `f = g sin θ`.
fn add_from_rest<const N: usize>(k: f64, c: f64, g: f64, w: f64, (s, co): (f64, f64), st: f64, p: &mut [f64; N]) {
    let mut q = [0.0; N];
    if st != 0.0 {
        let (sw, cw) = (w * st).sin_cos();
        let (x, dx) = from_rest(k, c, g, w, (s * cw - co * sw, co * cw + s * sw), st);
        q[0] = x;
        if N > 1 {
            q[1] = dx;
        }
    }
    let mut wm = 1.0;
    for m in 2..N {
        let f = g * wm * [s, co, -s, -co][(m - 2) % 4];
        q[m] = f - c * q[m - 1] - k * q[m - 2];
        wm *= w;
    }
    p.iter_mut().zip(q).for_each(|(a, b)| *a += b);
}

/// Eigenvalues of the first-order form (complex or real) within this
/// fraction of its spectral radius are one repeated eigenvalue (round-off
/// splits a repeated one by ~1e-16 of the radius, a Jordan block by ~1e-8:
/// the latter stays split, a nearly critically damped mode
/// ([`NEAR_CRITICAL`]); one that lands within this is a cluster whose
/// eigenspace is a line, its plane from `(A − λ)²` ([`critical_plane`])).
const REPEATED: f64 = 1e-12;

/// A damping matrix whose modal entries `|φ_iᵀ C φ_j|` are all within
/// this fraction of the fastest mode's `ω` is round-off (docs/theory.md
/// §9.1): none. Its effect over a time `τ` is `c τ`, at most `1e-15 ω τ`:
/// below the flow's own round-off over a thousand of the fastest periods.
const ROUND_OFF_DAMPING: f64 = 1e-15;

/// Real eigenvalues of the first-order form closer than this fraction of
/// its spectral radius are not paired with each other (docs/theory.md
/// §9.1): the plane of `λ₁, λ₂` has a basis of condition ~`|λ|²/|λ₁ − λ₂|`,
/// which reaches the 1e8 that [`ModalFlow::general`] refuses about here.
const CLOSE: f64 = 1e-8;

/// `a x` (dense, each entry summed from the first column on).
fn times(a: &Mat<f64>, x: &[f64]) -> Vec<f64> {
    (0..a.nrows()).map(|r| (0..a.ncols()).map(|t| a[(r, t)] * x[t]).sum()).collect()
}

/// The sine of the angle between `x_a = (a + c) x` and `x` (1: the plane's
/// columns orthogonal; 0: parallel), and `|x_a| / |x|`.
fn pair_sine(a: &Mat<f64>, c: f64, x: &[f64]) -> (f64, f64) {
    let ax: Vec<f64> = times(a, x).iter().zip(x).map(|(p, q)| p + c * q).collect();
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(p, q)| p * q).sum::<f64>();
    let (aa, xx, ax_x) = (dot(&ax, &ax), dot(x, x), dot(&ax, x));
    if !(aa > 0.0 && xx > 0.0) {
        return (0.0, 0.0);
    }
    ((1.0 - (ax_x * ax_x) / (aa * xx)).max(0.0).sqrt(), (aa / xx).sqrt())
}

/// How well the columns `x_a = (a + c) x`, `x` condition their block of
/// `T`: `sin θ · r / (1 + r²)` with `r = |x_a| / |x|` (at most ½, for
/// orthogonal columns of one length; 0 for parallel ones or a vanishing
/// `x_a`). Near an eigenvector of `λ₂` in a pair with `λ₁ ≈ 0`, `x_a =
/// −λ₁ x` is round-off whose direction, and so its sine, means nothing:
/// the sine alone chose such a vector once (a free chain, a dashpot of
/// 1.17 at dof 1: `T`'s condition 3e16, the run refused).
fn pair_score(a: &Mat<f64>, c: f64, x: &[f64]) -> f64 {
    let (sine, r) = pair_sine(a, c, x);
    sine * r / (1.0 + r * r)
}

/// The vector `x_b` of a mode's invariant plane (spanned by `u₁`, `u₂`: a
/// real pair's eigenvectors, or a complex one's real and imaginary parts),
/// `x_a = (a + c) x_b` the plane's other column of `T`: `first` (the
/// vector taken before) if the two columns are at least 30° apart (sine
/// 1/2), else of it and 64 directions of the half turn the one whose
/// columns condition `T` best ([`pair_score`]) (docs/theory.md §9.1). A
/// free chain's rigid pair (`λ₁ = 0` and the slow decay `λ₂ = −c` of its
/// translation under a weak dashpot) has nearly parallel eigenvectors: from
/// `x_b = u₁ + u₂`, `x_a = c u₁` was parallel to it within `~c`, `T`'s
/// condition 6e4 at `c = 0.025`, the flow off the exponential by 3.9e-11
/// of the state (events_flow.rs); orthogonal to `u₁`, `x_a ∥ u₁ ⟂ x_b`.
/// The score's exact maximiser over the plane (a 2 × 2 generalized
/// eigenproblem) conditions `T` no better than the scan, within 1 %
/// either way: not taken (docs/theory.md §9.1).
fn pair_vector(a: &Mat<f64>, c: f64, u1: &[f64], u2: &[f64], first: Vec<f64>) -> Vec<f64> {
    // An orthonormal basis `(p₁, p₂)` of the plane (Gram–Schmidt, twice).
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(p, q)| p * q).sum::<f64>();
    let n1 = dot(u1, u1).sqrt();
    let p1: Vec<f64> = u1.iter().map(|x| x / n1).collect();
    let mut p2 = u2.to_vec();
    for _ in 0..2 {
        let d = dot(&p1, &p2);
        p2.iter_mut().zip(&p1).for_each(|(x, y)| *x -= d * y);
    }
    let n2 = dot(&p2, &p2).sqrt();
    if !(n2 > 0.0) {
        return first;
    }
    p2.iter_mut().for_each(|x| *x /= n2);
    // `cos θ p₁ + sin θ p₂` over 64 angles of the half turn: the best.
    if pair_sine(a, c, &first).0 >= 0.5 {
        return first;
    }
    let (mut best, mut best_score) = (first.clone(), pair_score(a, c, &first));
    for i in 0..64 {
        let th = std::f64::consts::PI * f64::from(i) / 64.0;
        let (s, co) = th.sin_cos();
        let x: Vec<f64> = p1.iter().zip(&p2).map(|(x, y)| co * x + s * y).collect();
        let score = pair_score(a, c, &x);
        if score > best_score {
            (best, best_score) = (x, score);
        }
    }
    let size = best.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    best.into_iter().map(|v| v / size).collect()
}

/// The eigenvectors of a real eigenvalue `λ` of `a` repeated `m` times: an
/// orthonormal basis of the null space of `a − λ I` (its right singular
/// vectors of singular value ≤ 1e-10 of the largest), whatever basis of
/// it the eigen-decomposition gave (possibly nearly parallel vectors). Of
/// dimension `m` when the eigenvalue is semisimple, below when defective
/// (a real Jordan block): refused.
pub fn repeated_line(a: &Mat<f64>, lambda: f64, m: usize) -> Result<Vec<Vec<f64>>, EventsError> {
    let nn = a.nrows();
    let shifted = Mat::from_fn(nn, nn, |i, j| a[(i, j)] - if i == j { lambda } else { 0.0 });
    let svd = shifted.svd().map_err(|_| EventsError::Eigen)?;
    let s = svd.S().column_vector();
    let smax = (0..nn).fold(0.0f64, |x, i| x.max(s[i]));
    let null: Vec<usize> = (0..nn).filter(|&i| s[i] <= 1e-10 * smax).collect();
    if null.len() != m {
        return Err(EventsError::Defective { condition: f64::INFINITY });
    }
    let v = svd.V();
    Ok(null.iter().map(|&i| (0..nn).map(|r| v[(r, i)]).collect()).collect())
}

/// The planes of a complex eigenvalue `σ ± iω` of `a` repeated `m` times
/// (`k = σ² + ω²`, `c = −2σ`): one real vector `x` per plane `{x, a x}`.
/// The real invariant subspace is the null space of
/// `Q = a² + c a + k I = (a − λ)(a − λ̄)` (its right singular vectors of
/// singular value ≤ 1e-10 of the largest); of dimension `2m` when the
/// eigenvalue is semisimple, below when defective (a Jordan block):
/// refused. Each `x` is the subspace's vector farthest from the planes
/// taken so far (orthogonal to them); an invariant plane meeting another
/// in a line would meet it in an invariant line, which a pair without
/// real eigenvalues has not: the planes are independent.
pub fn repeated_planes(a: &Mat<f64>, k: f64, c: f64, m: usize) -> Result<Vec<Vec<f64>>, EventsError> {
    let nn = a.nrows();
    let q = a * a + Mat::from_fn(nn, nn, |i, j| c * a[(i, j)] + if i == j { k } else { 0.0 });
    let svd = q.svd().map_err(|_| EventsError::Eigen)?;
    let s = svd.S().column_vector();
    let smax = (0..nn).fold(0.0f64, |x, i| x.max(s[i]));
    let null: Vec<usize> = (0..nn).filter(|&i| s[i] <= 1e-10 * smax).collect();
    if null.len() != 2 * m {
        return Err(EventsError::Defective { condition: f64::INFINITY });
    }
    let v = svd.V();
    let mut z: Vec<Vec<f64>> = null.iter().map(|&i| (0..nn).map(|r| v[(r, i)]).collect()).collect();
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(2 * m);
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    // Gram–Schmidt, twice, against the basis; the result and its norm.
    let orth = |basis: &[Vec<f64>], mut x: Vec<f64>| -> (Vec<f64>, f64) {
        for _ in 0..2 {
            for b in basis {
                let d = dot(b, &x);
                x.iter_mut().zip(b).for_each(|(p, q)| *p -= d * q);
            }
        }
        let norm = dot(&x, &x).sqrt();
        (x.into_iter().map(|p| p / norm).collect(), norm)
    };
    let mut xs = Vec::with_capacity(m);
    for _ in 0..m {
        let (best, _) = z.iter().enumerate().map(|(i, zi)| (i, orth(&basis, zi.clone()).1)).fold((0, -1.0), |b, c| if c.1 > b.1 { c } else { b });
        let (x, norm) = orth(&basis, z.swap_remove(best));
        if !(norm > 1e-8) {
            return Err(EventsError::Defective { condition: f64::INFINITY });
        }
        let ax = times(a, &x);
        let size = dot(&ax, &ax).sqrt();
        basis.push(x.clone());
        let (y, norm) = orth(&basis, ax);
        if !(norm > 1e-8 * size) {
            return Err(EventsError::Defective { condition: f64::INFINITY });
        }
        basis.push(y);
        xs.push(x);
    }
    Ok(xs)
}

/// A pair of eigenvalues of the first-order form (two reals or a complex
/// pair) whose moduli are within this fraction of every other eigenvalue's
/// is a slow pair well apart from the rest: a free structure's rigid pair
/// `λ = 0, −c` under a weak damping (docs/theory.md §9.1). Its plane is
/// taken from `(A − λ₁)(A − λ₂)` ([`slow_plane`]), not from its
/// eigenvectors. At `c/|λ₃|` of 3e-3 the eigenvectors' plane is within
/// 8e-13 of the exponential, the slow plane within 7e-14; hunt run 686
/// (6.7e-3) takes it, its flow 1.6e-13 → 1.6e-14 off the exponential
/// (docs/theory.md §9.1). Above 1e-2 the eigenvectors' plane stays.
const SLOW: f64 = 1e-2;

/// Two real eigenvalues of the first-order form split by at most this
/// fraction of its spectral radius, or a complex pair `σ ± iω` with `2ω`
/// within it, are one nearly critically damped mode when their plane's
/// columns are apart ([`critical_plane`]; docs/theory.md §9.1). A
/// critically damped mode of a non-classical `C` is a Jordan block of `A`,
/// which round-off splits by ~`√ε` of the radius (measured: 1.3e-8 to
/// 9.3e-8 on three exact ones) into two reals or a complex pair with
/// eigenvectors parallel within that: their plane known to ε over their
/// angle, `T` refused. The eigenvectors' plane of a genuinely split pair
/// was off the exponential by 1.1e-12 at a split of 1.7e-4 of the radius,
/// 3.3e-13 at 6e-4, 1.3e-13 at 1.7e-3, 2e-14 at 6e-3; the plane of
/// `(A − λ₁)(A − λ₂)` by at most 6e-14 from 1.3e-8 to 2e-2.
const NEAR_CRITICAL: f64 = 1e-2;

/// The plane of a nearly critically damped mode `λ₁, λ₂` of `a` split by
/// `split` (`k = λ₁λ₂`, or `σ² + ω²` for `σ ± iω`; `c = −λ₁ − λ₂`;
/// docs/theory.md §9.1): [`slow_plane`]'s null space of `(a − λ₁)(a − λ₂)`,
/// known to round-off however close `λ₁` and `λ₂` are (for a Jordan block
/// it is `(a + c/2)²`'s), and of it the vector whose columns condition `T`
/// best. Kept when those columns are apart: the sine of their angle above
/// `10 split/|λ̄|` (`λ̄ = −c/2`) and 1e-6. A nearly repeated eigenvalue
/// with two eigenvectors apart (two identical blocks, one detuned) has on
/// that plane `a ≈ λ̄`, every `x_a` within `split/(2|λ̄|)` of its `x_b`:
/// `None`, its eigenvectors stay.
pub fn critical_plane(a: &Mat<f64>, k: f64, c: f64, split: f64) -> Option<Vec<f64>> {
    let x = slow_plane(a, k, c)?;
    let (sine, _) = pair_sine(a, c, &x);
    (sine > (10.0 * split / (0.5 * c).abs()).max(1e-6)).then_some(x)
}

/// The chain of a (nearly) defective complex pair: `σ₁ ± iω₁` and `σ₂ ±
/// iω₂` of `a` split by `split` (`k_j = σ_j² + ω_j²`, `c_j = −2σ_j`; the
/// same twice for a pair repeated to round-off) whose two planes are nearly
/// one (docs/theory.md §9.1). A defective pair (a Jordan block of the
/// first-order form) has one eigenvector each: round-off splits it by
/// ~`√ε` of the radius into two pairs with eigenvectors parallel within
/// that, and their planes' basis is refused (the example of
/// events_flow.rs: condition 4.9e8). Its real invariant subspace is the
/// null space of `Q₁ Q₂` (`Q_j = a² + c_j a + k_j`; right singular vectors
/// of singular value ≤ 1e-10 of `‖Q₁‖_F ‖Q₂‖_F`), four-dimensional and known
/// to round-off however close the pairs are; on it `Q₁ Q₂ = 0`. Of it,
/// `x_b2` is the vector that `Q₂` stretches most, `x_b1 = Q₂ x_b2 / s` (`s`
/// the stretch's largest entry) and `x_a_j = (a + c_j) x_b_j`: then `a x_a1
/// = −k₁ x_b1` and `a x_a2 = s x_b1 − k₂ x_b2`, two companion blocks of
/// which the first is driven by the second, `η₁'' + c₁ η₁' + k₁ η₁ = s η₂`
/// ([`ModalFlow`]'s drive). Returns `(x_b1, x_b2, s)`, or `None` (the
/// planes stay) unless the subspace is four-dimensional and `Q₂`'s stretch
/// there, over `2ω₂ √k₂`, exceeds `10 split/√k₂` and 1e-6: a nearly
/// repeated pair with two eigenvectors apart (two identical blocks, one
/// detuned) has `Q₂` of `~split · 2ω₂` on the subspace.
pub fn defective_chain(a: &Mat<f64>, (k1, c1): (f64, f64), (k2, c2): (f64, f64), split: f64) -> Option<(Vec<f64>, Vec<f64>, f64)> {
    // Two damped oscillating pairs only (`c > 0`: a driven mode's
    // particular solution is never resonant).
    if !(c1 > 0.0 && c2 > 0.0 && k1 > 0.25 * c1 * c1 && k2 > 0.25 * c2 * c2) {
        return None;
    }
    let nn = a.nrows();
    let quad = |k: f64, c: f64| a * a + Mat::from_fn(nn, nn, |i, j| c * a[(i, j)] + if i == j { k } else { 0.0 });
    let (q1, q2) = (quad(k1, c1), quad(k2, c2));
    // Relative to its factors' sizes: where the subspace is the whole
    // space (two dofs), `Q₁ Q₂` is round-off, its largest singular value too.
    let frobenius = |q: &Mat<f64>| (0..nn).flat_map(|i| (0..nn).map(move |j| (i, j))).map(|(i, j)| q[(i, j)] * q[(i, j)]).sum::<f64>().sqrt();
    let scale = frobenius(&q1) * frobenius(&q2);
    let svd = (&q1 * &q2).svd().ok()?;
    let s = svd.S().column_vector();
    let null: Vec<usize> = (0..nn).filter(|&i| s[i] <= 1e-10 * scale).collect();
    if null.len() != 4 {
        return None;
    }
    let basis = Mat::from_fn(nn, 4, |r, j| svd.V()[(r, null[j])]);
    let stretch = (&q2 * &basis).svd().ok()?;
    let sv = stretch.S().column_vector();
    let top = (0..4).fold(0, |b, j| if sv[j] > sv[b] { j } else { b });
    let w2 = (k2 - 0.25 * c2 * c2).max(0.0).sqrt();
    if !(sv[top] > (2.0 * w2 * k2.sqrt()) * (10.0 * split / k2.sqrt()).max(1e-6)) {
        return None;
    }
    let xb2: Vec<f64> = (0..nn).map(|r| (0..4).map(|j| basis[(r, j)] * stretch.V()[(j, top)]).sum()).collect();
    let size = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let xb2: Vec<f64> = {
        let s = size(&xb2);
        xb2.into_iter().map(|v| v / s).collect()
    };
    let xb1 = times(&q2, &xb2);
    let drive = size(&xb1);
    Some((xb1.into_iter().map(|v| v / drive).collect(), xb2, drive))
}

/// The invariant plane of a slow pair `λ₁, λ₂` of `a` (`k = λ₁λ₂`, `c = −λ₁
/// − λ₂`; docs/theory.md §9.1), without its eigenvectors: the null space of
/// `Q = a² + c a + k I = (a − λ₁)(a − λ₂)` (its right singular vectors of
/// singular value ≤ 1e-10 of the largest), known to round-off over the
/// pair's distance from the rest of the spectrum however close `λ₁` and
/// `λ₂` are. A free chain's rigid pair under a weak dashpot (`λ = 0` and
/// `−c`, `c` of 1e-13 to 1e-3 of the spectral radius) has two eigenvectors
/// parallel within `~c`: the plane they span was known to `ε/c` only
/// (refused, or 6e-11 off the exponential). Of that plane, `x_b`
/// orthogonal to `(a + c) g` (`g` the plane's basis vector it is largest
/// for): for `k = 0`, `(a + c) x` is the line of the eigenvector of 0
/// whatever `x`, so `x_a ⟂ x_b` (`pair_vector` keeps it, or scans the
/// plane if its columns are within 30°). `None` when the null space is not
/// two-dimensional (the pair not apart from the rest).
pub fn slow_plane(a: &Mat<f64>, k: f64, c: f64) -> Option<Vec<f64>> {
    let nn = a.nrows();
    let q = a * a + Mat::from_fn(nn, nn, |i, j| c * a[(i, j)] + if i == j { k } else { 0.0 });
    let svd = q.svd().ok()?;
    let s = svd.S().column_vector();
    let smax = (0..nn).fold(0.0f64, |x, i| x.max(s[i]));
    let null: Vec<usize> = (0..nn).filter(|&i| s[i] <= 1e-10 * smax).collect();
    if null.len() != 2 {
        return None;
    }
    let v = svd.V();
    let (g1, g2): (Vec<f64>, Vec<f64>) = (0..nn).map(|r| (v[(r, null[0])], v[(r, null[1])])).unzip();
    let shifted = |x: &[f64]| -> Vec<f64> { times(a, x).iter().zip(x).map(|(p, q)| p + c * q).collect() };
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(p, q)| p * q).sum::<f64>();
    let (w1, w2) = (shifted(&g1), shifted(&g2));
    let w = if dot(&w1, &w1) >= dot(&w2, &w2) { w1 } else { w2 };
    // `w`'s components on the plane's pair, turned a quarter: the plane's
    // vector orthogonal to it.
    let (p1, p2) = (dot(&g1, &w), dot(&g2, &w));
    if !(p1.hypot(p2) > 0.0) {
        return None;
    }
    let x: Vec<f64> = g1.iter().zip(&g2).map(|(a, b)| -p2 * a + p1 * b).collect();
    let size = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let x: Vec<f64> = x.into_iter().map(|v| v / size).collect();
    Some(pair_vector(a, c, &g1, &g2, x))
}

/// The rigid modes of a free structure with two or more of them (parts
/// without a spring to the ground or to each other: `K`'s null space of
/// dimension `r >= 2`), under a damping that the modes of `(K, M)` do not
/// diagonalise (docs/theory.md §9.1): one plane `{x_b, x_a}` per rigid
/// mode, `k = 0` and its decay `c_j` (`A x_a = 0`, `A x_b = x_a − c_j
/// x_b`), from the structure, not from the first-order form's `2r`
/// eigenvalues near 0 (an undamped one defective, a weakly damped one's
/// eigenvectors parallel within `~c`). With `Z` the rigid modes (the
/// M-orthonormal null space of `K`, from the symmetric pencil), `Φ_e` the
/// elastic ones (`ω²`) and `D = Φᵀ C Φ`, the slow invariant subspace is
/// `{y, s; x = P s, x' = R s}` (`q = Z y + Φ_e x`, `s = y'`): the rigid
/// velocities `s` obey `s' = −G s`, `G = D_yy + D_yx R`, with `R = −P G`
/// and `ω² P = R G − D_xx R − D_xy` (the elastic part slaved to them),
/// solved by that fixed point (a contraction while the rigid decays are
/// slow against the elastic frequencies; `P = R = 0` when the damping
/// leaves the rigid modes alone). Each eigenpair `G g_j = c_j g_j` gives
/// `x_b = (Φ_e P g_j, Z g_j + Φ_e R g_j)` (the state `y = 0, s = g_j`),
/// whose `(A + c_j) x_b = (Z g_j, 0)` is a rigid displacement, `A`'s null
/// vector. `None` (the eigenvalue path) with fewer than two rigid modes, a
/// fixed point that does not converge, or `G` without a well-conditioned
/// real eigenbasis.
fn rigid_block(m: &Mat<f64>, k: &Mat<f64>, c: &Mat<f64>) -> Option<Vec<(f64, Vec<f64>)>> {
    let n = m.nrows();
    let llt = m.llt(Side::Lower).ok()?;
    let mut linv = Mat::<f64>::identity(n, n);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(llt.L(), linv.as_mut(), faer::Par::Seq);
    let s = &linv * k * linv.transpose();
    let s = Mat::from_fn(n, n, |i, j| 0.5 * (s[(i, j)] + s[(j, i)]));
    let evd = s.self_adjoint_eigen(Side::Lower).ok()?;
    let w2: Vec<f64> = (0..n).map(|i| evd.S().column_vector()[i]).collect();
    let kmax = w2.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let (rigid, elastic): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| w2[i].abs() <= 1e-12 * kmax);
    let (r, ne) = (rigid.len(), elastic.len());
    if r < 2 || elastic.iter().any(|&i| !(w2[i] > 0.0)) {
        return None;
    }
    let phi = linv.transpose() * evd.U();
    let d = phi.transpose() * c * &phi;
    let dyy = Mat::from_fn(r, r, |i, j| d[(rigid[i], rigid[j])]);
    let dyx = Mat::from_fn(r, ne, |i, j| d[(rigid[i], elastic[j])]);
    let dxy = Mat::from_fn(ne, r, |i, j| d[(elastic[i], rigid[j])]);
    let dxx = Mat::from_fn(ne, ne, |i, j| d[(elastic[i], elastic[j])]);
    let big = |x: &Mat<f64>| (0..x.nrows()).flat_map(|i| (0..x.ncols()).map(move |j| (i, j))).fold(0.0f64, |a, (i, j)| a.max(x[(i, j)].abs()));
    let (mut p, mut rr) = (Mat::<f64>::zeros(ne, r), Mat::<f64>::zeros(ne, r));
    let mut settled = None;
    for it in 0..400 {
        let g = &dyy + &dyx * &rr;
        rr = Mat::from_fn(ne, r, |i, j| -(0..r).map(|l| p[(i, l)] * g[(l, j)]).sum::<f64>());
        let rhs = &rr * &g - &dxx * &rr - &dxy;
        let next = Mat::from_fn(ne, r, |i, j| rhs[(i, j)] / w2[elastic[i]]);
        let change = big(&(&next - &p));
        let size = big(&next);
        p = next;
        if !change.is_finite() {
            return None;
        }
        match settled {
            // Two more sweeps once the change is at round-off.
            Some(at) if it >= at + 2 => break,
            None if change <= 1e-14 * size => settled = Some(it),
            _ => {}
        }
    }
    settled?;
    let g = &dyy + &dyx * &rr;
    rr = Mat::from_fn(ne, r, |i, j| -(0..r).map(|l| p[(i, l)] * g[(l, j)]).sum::<f64>());
    // G's eigenpairs: real (G is nearly D_yy, symmetric semidefinite).
    let gscale = big(&g);
    let evg = g.eigen().ok()?;
    let lam: Vec<f64> = (0..r).map(|j| evg.S().column_vector()[j].re).collect();
    if (0..r).any(|j| evg.S().column_vector()[j].im.abs() > 1e-10 * gscale) {
        return None;
    }
    let mut vecs: Vec<Vec<f64>> = (0..r).map(|j| (0..r).map(|i| evg.U()[(i, j)].re).collect()).collect();
    let v = Mat::from_fn(r, r, |i, j| vecs[j][i]);
    let norm1 = |x: &Mat<f64>| (0..x.ncols()).map(|j| (0..x.nrows()).map(|i| x[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max);
    let cond = norm1(&v) * norm1(&v.full_piv_lu().inverse());
    let mut lam = lam;
    if !(cond <= 1e6) {
        // A repeated decay (identical parts): its eigenspace from the null
        // space of `G − λ̄`, an orthonormal basis.
        let mut order: Vec<usize> = (0..r).collect();
        order.sort_by(|&a, &b| lam[a].total_cmp(&lam[b]));
        let (mut l2, mut v2) = (Vec::with_capacity(r), Vec::with_capacity(r));
        let mut i = 0;
        while i < r {
            let end = (i..r).take_while(|&j| lam[order[j]] - lam[order[i]] <= 1e-12 * gscale.max(f64::MIN_POSITIVE)).last().map_or(i + 1, |j| j + 1);
            let mean = order[i..end].iter().map(|&j| lam[j]).sum::<f64>() / (end - i) as f64;
            let shifted = Mat::from_fn(r, r, |a, b| g[(a, b)] - if a == b { mean } else { 0.0 });
            let svd = shifted.svd().ok()?;
            let sv = svd.S().column_vector();
            let smax = (0..r).fold(0.0f64, |x, q| x.max(sv[q]));
            let null: Vec<usize> = (0..r).filter(|&q| sv[q] <= 1e-10 * smax.max(gscale)).collect();
            if null.len() != end - i {
                return None;
            }
            for &q in &null {
                l2.push(mean);
                v2.push((0..r).map(|a| svd.V()[(a, q)]).collect());
            }
            i = end;
        }
        (lam, vecs) = (l2, v2);
    }
    let zc = Mat::from_fn(n, r, |i, j| phi[(i, rigid[j])]);
    let ec = Mat::from_fn(n, ne, |i, j| phi[(i, elastic[j])]);
    Some(
        lam.iter()
            .zip(&vecs)
            .map(|(&cj, gj)| {
                let gm = Mat::from_fn(r, 1, |i, _| gj[i]);
                let (pq, zv, rv) = (&ec * (&p * &gm), &zc * &gm, &ec * (&rr * &gm));
                let x: Vec<f64> = (0..n).map(|i| pq[(i, 0)]).chain((0..n).map(|i| zv[(i, 0)] + rv[(i, 0)])).collect();
                (cj.max(0.0), x)
            })
            .collect(),
    )
}

/// The load-free part of a [`ModalFlow`]: the modes of `(K, M)` (`Φ`,
/// `M Φ`) or the first-order form's planes (`T`, `T⁻¹`, `M⁻¹`), and each
/// mode's `k_i`, `c_i`. It depends on the matrices only: flows of the same
/// matrices with other loads are made from it
/// ([`ModalFlow::with_loads`], [`super::FlowBases`]).
#[derive(Clone, Debug)]
pub(crate) struct Basis {
    n: usize,
    phi: Mat<f64>,
    m_phi: Mat<f64>,
    k: Vec<f64>,
    c: Vec<f64>,
    general: Option<GeneralBasis>,
}

/// The first-order form's basis (non-classical damping).
#[derive(Clone, Debug)]
struct GeneralBasis {
    t: Mat<f64>,
    tinv: Mat<f64>,
    minv: Mat<f64>,
    /// Per mode `i`, the drive `s_i` of a defective chain
    /// ([`defective_chain`]): `η_i'' + c_i η_i' + k_i η_i = … + s_i η_{i+1}`
    /// (empty: no chain; 0: none for that mode).
    drive: Vec<f64>,
}

impl Basis {
    /// The basis of `M q'' + C q' + K q` (dense, any size, 0 included).
    pub(crate) fn new(m: Mat<f64>, k: Mat<f64>, c: Option<Mat<f64>>) -> Result<Self, EventsError> {
        let n = m.nrows();
        // A NaN would pass the Cholesky factor and the eigensolver and be
        // dropped by the largest-entry folds below: refused by name here.
        for (matrix, a) in [("mass", Some(&m)), ("stiffness", Some(&k)), ("damping", c.as_ref())] {
            let Some(a) = a else { continue };
            if let Some((row, col)) = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).find(|&(i, j)| !a[(i, j)].is_finite()) {
                return Err(EventsError::NotFinite { matrix, row, col, value: a[(row, col)] });
            }
        }
        if n == 0 {
            return Ok(Self { n, phi: Mat::zeros(0, 0), m_phi: Mat::zeros(0, 0), k: vec![], c: vec![], general: None });
        }
        let llt = m.llt(Side::Lower).map_err(|_| EventsError::MassNotDefinite)?;
        let l = llt.L().to_owned();
        let mut linv = Mat::<f64>::identity(n, n);
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), faer::Par::Seq);
        let a = &linv * &k * linv.transpose();
        let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
        let evd = a.self_adjoint_eigen(Side::Lower).map_err(|_| EventsError::Eigen)?;
        let w2 = evd.S().column_vector();
        let wmax = (0..n).map(|i| w2[i].abs()).fold(0.0, f64::max);
        let wmin = (0..n).map(|i| w2[i].abs()).filter(|&w| w > 1e-12 * wmax).fold(f64::INFINITY, f64::min);
        // Below a spread of 1e3 the eigensolver's ω² are already to a few
        // ulps (the oscillators, two equal dofs whose simultaneous events
        // need the solver's symmetric modes bit for bit): left as they are.
        let mb = band(&m);
        let (phi, w2) = if wmax > 1e3 * wmin { refine(&m, &k, mb.as_ref().zip(band(&k).as_ref()), linv.transpose() * evd.U()) } else { (linv.transpose() * evd.U(), (0..n).map(|i| w2[i]).collect()) };
        // A rigid mode's ω² is round-off (±1e-16 of the largest): exactly 0,
        // so that its particular solution integrates the load instead of
        // dividing by the round-off.
        let kmax = w2.iter().fold(0.0, |a: f64, w| a.max(w.abs()));
        let kv: Vec<f64> = w2.iter().map(|&w2| if w2.abs() <= 1e-12 * kmax { 0.0 } else { w2 }).collect();
        let m_phi = product(&m, mb.as_ref(), &phi);
        let cv = match &c {
            None => vec![0.0; n],
            Some(cm) => {
                let modal = phi.transpose() * cm * &phi;
                let diag = (0..n).map(|i| modal[(i, i)].abs()).fold(0.0, f64::max);
                let off = (0..n).flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j))).map(|(i, j)| modal[(i, j)].abs()).fold(0.0, f64::max);
                if diag.max(off) <= ROUND_OFF_DAMPING * kmax.sqrt() {
                    // A damping of round-off size against the stiffness (a
                    // 1e-17 dashpot) is none: the first-order form refused a
                    // free chain's (its rigid pair defective to round-off,
                    // condition 2e16), and a modal damping that small makes
                    // a rigid mode's particular solution `g₀ t/c` (docs/theory.md §9.1).
                    vec![0.0; n]
                } else if off > 1e-10 * diag.max(f64::MIN_POSITIVE) {
                    let minv = linv.transpose() * &linv;
                    return ModalFlow::general(&m, &k, cm, minv);
                } else {
                    // A modal damping of round-off size is 0, as a rigid
                    // mode's ω² is: a free chain with `C = b K` gave its rigid
                    // mode c = 1e-17, and the steady load's particular
                    // solution `f t / c` put the chain at 9e15.
                    (0..n).map(|i| modal[(i, i)]).map(|c| if c <= 1e-12 * diag { 0.0 } else { c }).collect()
                }
            }
        };
        Ok(Self { n, phi, m_phi, k: kv, c: cv, general: None })
    }
}

/// `a`'s symmetric band when a product with it by band is the cheaper:
/// `a` exactly symmetric and its `2p + 1` diagonals at most an eighth of
/// `n` (a bar's `p = 1`, a beam's 3). The set-up's products with `M` and
/// `K` then cost `O(n² p)` where the dense ones cost `2n³` (the scalar
/// band loop is ~8 times slower per flop than faer's product).
fn band(a: &Mat<f64>) -> Option<SymBand> {
    let n = a.nrows();
    let p = (0..n).flat_map(|j| (0..n).map(move |i| (i, j))).filter(|&(i, j)| a[(i, j)] != 0.0).map(|(i, j)| i.abs_diff(j)).max()?;
    if 8 * (2 * p + 1) > n || (0..n).any(|i| (i.saturating_sub(p)..i).any(|j| a[(i, j)] != a[(j, i)])) {
        return None;
    }
    let mut b = SymBand::zeros(n, p);
    for i in 0..n {
        for j in i.saturating_sub(p)..=i {
            b.set(i, j, a[(i, j)]);
        }
    }
    Some(b)
}

/// `a x`, by `a`'s band when it has one ([`band`]).
fn product(a: &Mat<f64>, band: Option<&SymBand>, x: &Mat<f64>) -> Mat<f64> {
    let Some(b) = band else { return a * x };
    let mut y = Mat::<f64>::zeros(x.nrows(), x.ncols());
    for j in 0..x.ncols() {
        let xj = x.col(j).try_as_col_major().expect("a dense matrix's column").as_slice();
        b.mul_vec(xj, y.col_mut(j).try_as_col_major_mut().expect("a dense matrix's column").as_slice_mut());
    }
    y
}

/// The lower triangle (diagonal included) of `xᵀ y` (`xᵀ y` symmetric):
/// half the dense product's cost.
fn gram_lower(x: &Mat<f64>, y: &Mat<f64>) -> Mat<f64> {
    use faer::linalg::matmul::triangular::{matmul, BlockStructure};
    let mut g = Mat::<f64>::zeros(x.ncols(), y.ncols());
    matmul(g.as_mut(), BlockStructure::TriangularLower, faer::Accum::Replace, x.transpose(), BlockStructure::Rectangular, y, BlockStructure::Rectangular, 1.0, faer::Par::Seq);
    g
}

/// One step of Ogita and Aishima's refinement of the modes `phi` of
/// `(K, M)` (Numer. Algorithms 2018, RefSyEv, here with `M`'s inner
/// product), in the original matrices: with `S = ΦᵀKΦ`, `G = ΦᵀMΦ`
/// (symmetric), `R = I − G`, `ω_i² = s_ii / g_ii` and `Φ ← Φ (I + E)`,
/// `e_ij = (s_ij + ω_j² r_ij) / (ω_j² − ω_i²)`, `e_ii = r_ii / 2`, or
/// `r_ij / 2` for a pair closer than `δ = 2 (‖S − diag S‖_F + max ω² ‖R‖_F)`.
/// The eigensolver of `L⁻¹KL⁻ᵀ` is accurate to round-off of its largest
/// eigenvalue only: on the bar at m = 200 the slow modes' residuals
/// `‖Kφ − ω²Mφ‖ / (ω² ‖Mφ‖)` were 3e-10 and their `ω²` off by 1e-11
/// (relative), which the flow turned into velocities off the Taylor
/// oracle's by 10–20 times its own round-off (docs/theory.md §9). One step
/// brings both to the round-off of the products with `K` and `M`
/// (5e-12 and 1e-13). The modes stay ascending (a pair within `δ`
/// reordered by the step is put back). With `bands` (`M`'s, `K`'s:
/// [`band`]) `KΦ`, `MΦ` go by band and only the lower triangles of `S`,
/// `G` are formed ([`gram_lower`]), 4n³ flops where the dense step takes
/// 10n³; without (a system too small or too wide for a band to pay: the
/// beams, the chains) the products are dense and `S`, `G` symmetrised,
/// their bits those of the step before the bands.
fn refine(m: &Mat<f64>, k: &Mat<f64>, bands: Option<(&SymBand, &SymBand)>, phi: Mat<f64>) -> (Mat<f64>, Vec<f64>) {
    let n = phi.nrows();
    let (s, g) = match bands {
        Some((mb, kb)) => (gram_lower(&phi, &product(k, Some(kb), &phi)), gram_lower(&phi, &product(m, Some(mb), &phi))),
        None => (phi.transpose() * (k * &phi), phi.transpose() * (m * &phi)),
    };
    let sym = |a: &Mat<f64>, i: usize, j: usize| if bands.is_some() { a[(i.max(j), i.min(j))] } else { 0.5 * (a[(i, j)] + a[(j, i)]) };
    let r = |i: usize, j: usize| f64::from(u8::from(i == j)) - sym(&g, i, j);
    let w2: Vec<f64> = (0..n).map(|i| s[(i, i)] / g[(i, i)]).collect();
    let frobenius = |f: &dyn Fn(usize, usize) -> f64| (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| f(i, j).powi(2)).sum::<f64>().sqrt();
    let kmax = w2.iter().fold(0.0, |a: f64, w| a.max(w.abs()));
    let delta = 2.0 * (frobenius(&|i, j| if i == j { 0.0 } else { sym(&s, i, j) }) + kmax * frobenius(&r));
    let e = Mat::from_fn(n, n, |i, j| if i == j || (w2[j] - w2[i]).abs() <= delta { 0.5 * r(i, j) } else { (sym(&s, i, j) + w2[j] * r(i, j)) / (w2[j] - w2[i]) });
    let phi = &phi + &phi * &e;
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| w2[a].total_cmp(&w2[b]));
    (Mat::from_fn(n, n, |r, i| phi[(r, order[i])]), order.iter().map(|&i| w2[i]).collect())
}

impl ModalFlow {
    /// The flow of `dy`'s free motion (its contacts ignored): `M` positive
    /// definite, `C` classical or not (the first-order form), each forcing profile a sine or a sum of
    /// harmonics (a piecewise-linear series is [`super::EventDriven`]'s:
    /// [`EventsError::Profile`] here).
    pub fn new(dy: &Dynamics) -> Result<Self, EventsError> {
        let loads = Loads::without_series(dy)?;
        Self::from_parts(dense(&dy.mass), dense(&dy.stiffness), dy.damping.as_ref().map(dense), &loads)
    }

    /// The flow of `M q'' + C q' + K q = loads` (dense, any size, 0 included).
    pub(crate) fn from_parts(m: Mat<f64>, k: Mat<f64>, c: Option<Mat<f64>>, loads: &Loads) -> Result<Self, EventsError> {
        Ok(Self::with_loads(&Basis::new(m, k, c)?, loads))
    }

    /// The flow of `basis`'s matrices with `loads`: the loads' projections
    /// and particular parts on the basis' modes (the same bits as
    /// [`from_parts`](Self::from_parts) of the matrices `basis` was built from).
    pub(crate) fn with_loads(basis: &Basis, loads: &Loads) -> Self {
        let n = basis.n;
        if n == 0 {
            let ramp_modal = vec![Vec::new(); loads.ramps.len()];
            let piece = vec![(0.0, 0.0); loads.ramps.len()];
            return Self {
                n,
                phi: Mat::zeros(0, 0),
                m_phi: Mat::zeros(0, 0),
                k: vec![],
                c: vec![],
                g0: vec![],
                harmonics: vec![],
                ramp_modal,
                general: None,
                piece,
                ga: vec![],
                gb: vec![],
                tp: 0.0,
                time_dependent: loads.time_dependent(),
            };
        }
        if let Some(gb) = &basis.general {
            return Self::general_loads(basis, gb, loads);
        }
        let (phi, kv, cv) = (&basis.phi, &basis.k, &basis.c);
        let project = |g: &[f64]| -> Vec<f64> { (0..n).map(|i| (0..n).map(|r| phi[(r, i)] * g[r]).sum()).collect() };
        let g0 = project(&loads.constant);
        let harmonics = loads.waves.iter().map(|(g, a, w, p)| Harmonic::new(project(g), *a, *w, *p, kv, cv)).collect();
        let ramp_modal = loads.ramps.iter().map(|(h, _, _)| project(h)).collect();
        let (ga, gb) = (g0.clone(), vec![0.0; n]);
        let piece = vec![(0.0, 0.0); loads.ramps.len()];
        Self { n, phi: phi.clone(), m_phi: basis.m_phi.clone(), k: kv.clone(), c: cv.clone(), g0, harmonics, ramp_modal, general: None, piece, ga, gb, tp: 0.0, time_dependent: loads.time_dependent() }
    }

    /// The basis of a non-classical damping `c` (docs/theory.md §9.1): the
    /// real eigenvectors of the first-order matrix `A = [0 I; −M⁻¹K −M⁻¹C]`
    /// give, per complex pair `σ ± iω` with eigenvector `u + iy`, the basis
    /// `x_b = u`, `x_a = (A + c) x_b` of its invariant plane (`c = −2σ`,
    /// `k = σ² + ω²`); two real eigenvalues `λ₁ ≠ λ₂` (taken in ascending
    /// order, pairwise) give `x_b = u₁ + u₂` (`c = −λ₁ − λ₂`, `k = λ₁λ₂`);
    /// either `x_b` replaced by a better-conditioned vector of its plane
    /// when `x_a` is within 30° of it ([`pair_vector`]). On each plane `A x_a = −k x_b`, `A x_b = x_a − c x_b`: the
    /// companion block of `η'' + c η' + k η`. A complex eigenvalue repeated
    /// to round-off ([`REPEATED`]) gives its planes from the real invariant
    /// subspace ([`repeated_planes`]; a defective one is refused); a real
    /// one (a pair `λ ± iε`, `ε` within [`REPEATED`], counts as `λ` twice)
    /// its eigenvectors from the eigenspace ([`repeated_line`]), and with
    /// two real eigenvalues within [`CLOSE`] the `R` reals pair the `i`-th
    /// with the `(i + R/2)`-th, so that no plane holds one eigenvalue twice.
    /// Two reals split by at most [`NEAR_CRITICAL`] of the radius, or a
    /// complex pair as close, with their plane's columns apart (a
    /// critically damped mode, a Jordan block that round-off split, or a
    /// nearly critical one) take their plane from `(A − λ₁)(A − λ₂)`
    /// ([`critical_plane`]), not from their nearly parallel eigenvectors.
    /// A slow pair (the two eigenvalues of smallest modulus within
    /// [`SLOW`] of every other's: a free structure's rigid pair under a
    /// weak damping) takes its plane from `(A − λ₁)(A − λ₂)`
    /// ([`slow_plane`]), not from its nearly parallel eigenvectors; two or
    /// more rigid modes (free parts) take theirs from `K`'s null space
    /// ([`rigid_block`]).
    fn general(m: &Mat<f64>, k: &Mat<f64>, c: &Mat<f64>, minv: Mat<f64>) -> Result<Basis, EventsError> {
        let n = m.nrows();
        let nn = 2 * n;
        let mk = &minv * k;
        let mc = &minv * c;
        let a = Mat::from_fn(nn, nn, |i, j| match (i < n, j < n) {
            (true, true) => 0.0,
            (true, false) => f64::from(u8::from(j - n == i)),
            (false, true) => -mk[(i - n, j)],
            (false, false) => -mc[(i - n, j - n)],
        });
        let evd = a.eigen().map_err(|_| EventsError::Eigen)?;
        let (u, sv) = (evd.U(), evd.S().column_vector());
        // (k, c, x_b) per mode.
        let mut modes: Vec<(f64, f64, Vec<f64>)> = Vec::with_capacity(n);
        // Per defective chain, its pairs `(k₁, c₁)`, `(k₂, c₂)` and
        // [`defective_chain`]'s `(x_b1, x_b2, s)`.
        type Chain = ((f64, f64), (f64, f64), (Vec<f64>, Vec<f64>, f64));
        let mut chains: Vec<Chain> = Vec::new();
        let mut reals: Vec<(f64, Vec<f64>)> = Vec::new();
        let size = |x: &[f64]| x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let unit = |x: Vec<f64>| -> Vec<f64> {
            let s = size(&x);
            x.into_iter().map(|v| v / s).collect()
        };
        // A complex eigenvalue repeated to round-off (docs/theory.md §9.1):
        // one cluster, its planes from the real invariant subspace.
        let radius = (0..nn).fold(0.0f64, |r, j| r.max(sv[j].re.hypot(sv[j].im)));
        let mut done = vec![false; nn];
        // A slow pair well apart from the rest (a free structure's rigid
        // pair under a weak damping, docs/theory.md §9.1): its plane from
        // `(A − λ₁)(A − λ₂)`, not from its nearly parallel eigenvectors.
        let modulus = |j: usize| sv[j].re.hypot(sv[j].im);
        let mut order: Vec<usize> = (0..nn).collect();
        order.sort_by(|&x, &y| modulus(x).total_cmp(&modulus(y)));
        // Two or more rigid modes (free parts): one block from `K`'s null
        // space ([`rigid_block`]); its `2r` eigenvalues (0 and each `−c_j`)
        // are the nearest ones, taken off the list.
        let block = rigid_block(m, k, c);
        if let Some(block) = &block {
            let want = block.iter().map(|_| 0.0).chain(block.iter().map(|b| -b.0));
            for w in want.collect::<Vec<f64>>() {
                let near = (0..nn).filter(|&j| !done[j]).min_by(|&x, &y| (sv[x].re - w).hypot(sv[x].im).total_cmp(&(sv[y].re - w).hypot(sv[y].im)));
                if let Some(j) = near {
                    done[j] = true;
                }
            }
            modes.extend(block.iter().map(|(cj, x)| (0.0, *cj, unit(x.clone()))));
        }
        if block.is_none() && nn >= 4 && modulus(order[1]) <= SLOW * modulus(order[2]) {
            let (l1, l2) = (sv[order[0]], sv[order[1]]);
            let pair = if l1.im == 0.0 && l2.im == 0.0 {
                Some((l1.re * l2.re, -(l1.re + l2.re)))
            } else if l1.im != 0.0 && l1.im == -l2.im && l1.re == l2.re {
                Some((l1.re * l1.re + l1.im * l1.im, -2.0 * l1.re))
            } else {
                None
            };
            if let Some((ks, cs)) = pair {
                if let Some(x) = slow_plane(&a, ks, cs) {
                    modes.push((ks, cs, unit(x)));
                    done[order[0]] = true;
                    done[order[1]] = true;
                }
            }
        }
        for j in 0..nn {
            let l = sv[j];
            if done[j] {
                continue;
            }
            // A pair `λ ± iε` with `ε` within [`REPEATED`] of the radius:
            // a real eigenvalue repeated, split by round-off into a complex
            // pair (two identical overdamped blocks do); its cluster
            // (below) gives both their vectors.
            let split = l.im != 0.0 && l.im.abs() <= REPEATED * radius;
            if split {
                reals.push((l.re, vec![0.0; nn]));
            } else if l.im > 0.0 && !done[j] {
                let near: Vec<usize> = (j..nn).filter(|&i| sv[i].im > REPEATED * radius && !done[i] && (sv[i].re - l.re).hypot(sv[i].im - l.im) <= REPEATED * radius).collect();
                if near.len() > 1 {
                    let m = near.len() as f64;
                    let (re, im) = near.iter().fold((0.0, 0.0), |(a, b), &i| (a + sv[i].re / m, b + sv[i].im / m));
                    let (ki, ci) = (re * re + im * im, -2.0 * re);
                    match repeated_planes(&a, ki, ci, near.len()) {
                        Ok(xs) => modes.extend(xs.into_iter().map(|x| (ki, ci, unit(x)))),
                        // A defective pair repeated to round-off: its chain.
                        Err(e) => match (near.len() == 2).then(|| defective_chain(&a, (ki, ci), (ki, ci), 0.0)).flatten() {
                            Some(chain) => chains.push(((ki, ci), (ki, ci), chain)),
                            None => return Err(e),
                        },
                    }
                    for i in near {
                        done[i] = true;
                    }
                    continue;
                }
                // A (nearly) defective pair (docs/theory.md §9.1): another
                // pair within NEAR_CRITICAL whose eigenvector is nearly
                // this one's (the cosine of their angle above ½: a cheap
                // test before the chain's SVD), its chain from `Q₁ Q₂`.
                if 2.0 * l.im > NEAR_CRITICAL * radius {
                    let cosine = |p: usize| {
                        let (mut d, mut n1, mut n2) = (faer::c64::new(0.0, 0.0), 0.0, 0.0);
                        for r in 0..nn {
                            d += u[(r, j)].conj() * u[(r, p)];
                            (n1, n2) = (n1 + u[(r, j)].norm_sqr(), n2 + u[(r, p)].norm_sqr());
                        }
                        d.norm() / (n1 * n2).sqrt()
                    };
                    let partner = (0..nn)
                        .filter(|&p| p > j && !done[p] && 2.0 * sv[p].im > NEAR_CRITICAL * radius)
                        .map(|p| (p, (sv[p].re - l.re).hypot(sv[p].im - l.im)))
                        .filter(|&(p, d)| d <= NEAR_CRITICAL * radius && cosine(p) >= 0.5)
                        .min_by(|x, y| x.1.total_cmp(&y.1));
                    if let Some((p, split)) = partner {
                        let pair = |x: faer::c64| (x.re * x.re + x.im * x.im, -2.0 * x.re);
                        if let Some(chain) = defective_chain(&a, pair(l), pair(sv[p]), split) {
                            chains.push((pair(l), pair(sv[p]), chain));
                            (done[j], done[p]) = (true, true);
                            continue;
                        }
                    }
                }
                // A nearly critically damped mode split into `σ ± iω`
                // (docs/theory.md §9.1): its plane from `(A − λ)(A − λ̄)`.
                if 2.0 * l.im <= NEAR_CRITICAL * radius {
                    let (ki, ci) = (l.re * l.re + l.im * l.im, -2.0 * l.re);
                    if let Some(x) = critical_plane(&a, ki, ci, 2.0 * l.im) {
                        modes.push((ki, ci, unit(x)));
                        done[j] = true;
                        continue;
                    }
                }
                // A real vector of the plane: the real or the imaginary
                // part of the eigenvector, the larger, unless another
                // direction of the plane conditions `T` better.
                let (re, im): (Vec<f64>, Vec<f64>) = (0..nn).map(|r| (u[(r, j)].re, u[(r, j)].im)).unzip();
                let x = unit(if size(&re) >= size(&im) { re.clone() } else { im.clone() });
                let x = pair_vector(&a, -2.0 * l.re, &re, &im, x);
                modes.push((l.re * l.re + l.im * l.im, -2.0 * l.re, x));
            } else if l.im == 0.0 {
                reals.push((l.re, unit((0..nn).map(|r| u[(r, j)].re).collect())));
            }
        }
        reals.sort_by(|x, y| x.0.total_cmp(&y.0));
        // Two reals split by more than round-off of a repeated one and at
        // most NEAR_CRITICAL: a nearly critically damped mode when their
        // plane's columns are apart (docs/theory.md §9.1), its plane from
        // `(A − λ₁)(A − λ₂)`.
        if reals.windows(2).any(|w| w[1].0 - w[0].0 > REPEATED * radius && w[1].0 - w[0].0 <= NEAR_CRITICAL * radius) {
            let mut kept = Vec::with_capacity(reals.len());
            let mut i = 0;
            while i < reals.len() {
                if i + 1 < reals.len() {
                    let (l1, l2) = (reals[i].0, reals[i + 1].0);
                    let split = l2 - l1;
                    if split > REPEATED * radius && split <= NEAR_CRITICAL * radius {
                        if let Some(x) = critical_plane(&a, l1 * l2, -(l1 + l2), split) {
                            modes.push((l1 * l2, -(l1 + l2), unit(x)));
                            i += 2;
                            continue;
                        }
                    }
                }
                kept.push(reals[i].clone());
                i += 1;
            }
            reals = kept;
        }
        // A real eigenvalue repeated to round-off (docs/theory.md §9.1):
        // one cluster, its mean and an orthonormal basis of its eigenspace;
        // a pair whose eigenspace is a line is a Jordan block (a critically
        // damped mode), its plane from `(A − λ)²`.
        if reals.windows(2).any(|w| w[1].0 - w[0].0 <= REPEATED * radius) {
            let mut grouped = Vec::with_capacity(reals.len());
            let mut i = 0;
            while i < reals.len() {
                let end = (i..reals.len()).take_while(|&j| reals[j].0 - reals[i].0 <= REPEATED * radius).last().map_or(i + 1, |j| j + 1);
                if end - i == 1 {
                    grouped.push(reals[i].clone());
                } else {
                    let l = reals[i..end].iter().map(|r| r.0).sum::<f64>() / (end - i) as f64;
                    match repeated_line(&a, l, end - i) {
                        Ok(xs) => grouped.extend(xs.into_iter().map(|x| (l, unit(x)))),
                        // A pair only: a block of three or more stays refused (no plane's SVD for it).
                        Err(e) => match (end - i == 2).then(|| critical_plane(&a, l * l, -2.0 * l, reals[end - 1].0 - reals[i].0)).flatten() {
                            Some(x) => modes.push((l * l, -2.0 * l, unit(x))),
                            None => return Err(e),
                        },
                    }
                }
                i = end;
            }
            reals = grouped;
        }
        // Adjacent in ascending order; with two eigenvalues closer than
        // CLOSE (a repeated one among them), the i-th with the (i + R/2)-th
        // of the R: no pair is from one cluster unless a cluster holds more
        // than half of them (then no pairing avoids it; refused below).
        let half = reals.len() / 2;
        let close = reals.windows(2).any(|w| w[1].0 - w[0].0 <= CLOSE * radius);
        if reals.len() % 2 == 1 {
            return Err(EventsError::Defective { condition: f64::INFINITY });
        }
        for p in 0..half {
            let ((l1, u1), (l2, u2)) = if close { (&reals[p], &reals[p + half]) } else { (&reals[2 * p], &reals[2 * p + 1]) };
            let c = -(l1 + l2);
            let x = unit(u1.iter().zip(u2).map(|(a, b)| a + b).collect());
            let x = pair_vector(&a, c, u1, u2, x);
            modes.push((l1 * l2, c, x));
        }
        modes.sort_by(|x, y| x.0.total_cmp(&y.0));
        // Each chain's two modes side by side, the driven one first, in
        // the order of its `k`.
        let mut drive = Vec::new();
        if !chains.is_empty() {
            chains.sort_by(|x, y| x.0 .0.total_cmp(&y.0 .0));
            let mut singles = std::mem::take(&mut modes).into_iter().peekable();
            for ((k1, c1), (k2, c2), (xb1, xb2, s)) in chains {
                modes.extend(std::iter::from_fn(|| singles.next_if(|m| m.0 <= k1)));
                drive.resize(modes.len() + 2, 0.0);
                drive[modes.len()] = s;
                modes.push((k1, c1, xb1));
                modes.push((k2, c2, xb2));
            }
            modes.extend(singles);
            drive.resize(modes.len(), 0.0);
        }
        if modes.len() != n {
            return Err(EventsError::Defective { condition: f64::INFINITY });
        }
        // A damping of round-off sign is 0 (as the classical path does),
        // in the basis as in the equation.
        for m in &mut modes {
            m.1 = m.1.max(0.0);
        }
        let kmax = modes.iter().fold(0.0f64, |a, m| a.max(m.0.abs()));
        let mut t = Mat::<f64>::zeros(nn, nn);
        for (i, (_, ci, xb)) in modes.iter().enumerate() {
            let ax = &a * Mat::from_fn(nn, 1, |r, _| xb[r]);
            for r in 0..nn {
                t[(r, 2 * i)] = ax[(r, 0)] + ci * xb[r];
                t[(r, 2 * i + 1)] = xb[r];
            }
        }
        let tinv = t.full_piv_lu().inverse();
        // The basis' condition: round-off is amplified by it in every step.
        let norm = |x: &Mat<f64>| (0..nn).map(|i| (0..nn).map(|j| x[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max);
        let condition = norm(&t) * norm(&tinv);
        if !(condition <= 1e8) {
            return Err(EventsError::Defective { condition });
        }
        // Each plane invariant: `A x_a = −k x_b` (`A x_b = x_a − c x_b`
        // holds by construction). A nearly defective real pair (a rigid
        // mode of a free structure that the damping leaves undamped: ±1.5e-8
        // for ±0) gives `x_b = u₁ + u₂` from two nearly parallel
        // eigenvectors: the sum cancels, its error out of the plane grows
        // to 1e-8 while `T` stays well conditioned (15), and the flow was
        // off the exponential by 3e-10 to 0.93 (events_flow.rs); such a
        // pair now takes its slow or critical plane. No basis: refused
        // (docs/schemes.md).
        let an = norm(&a);
        for (i, (ki, ..)) in modes.iter().enumerate() {
            let size = |col: usize| (0..nn).fold(0.0f64, |m, r| m.max(t[(r, col)].abs()));
            let scale = an * size(2 * i) + ki.abs() * size(2 * i + 1);
            let xa: Vec<f64> = (0..nn).map(|r| t[(r, 2 * i)]).collect();
            // A chain's driving mode: `A x_a = s x_b' − k x_b` (`x_b'` the driven one's).
            let s = if i > 0 { drive.get(i - 1).copied().unwrap_or(0.0) } else { 0.0 };
            let res = if s == 0.0 {
                times(&a, &xa).iter().enumerate().map(|(r, ax)| (ax + ki * t[(r, 2 * i + 1)]).abs()).fold(0.0, f64::max)
            } else {
                times(&a, &xa).iter().enumerate().map(|(r, ax)| (ax + ki * t[(r, 2 * i + 1)] - s * t[(r, 2 * i - 1)]).abs()).fold(0.0, f64::max)
            };
            if !(res <= 1e-11 * scale) {
                return Err(EventsError::Defective { condition: f64::INFINITY });
            }
        }
        let kv: Vec<f64> = modes.iter().map(|m| if m.0.abs() <= 1e-12 * kmax { 0.0 } else { m.0 }).collect();
        let cv: Vec<f64> = modes.iter().map(|m| m.1).collect();
        Ok(Basis { n, phi: Mat::zeros(0, 0), m_phi: Mat::zeros(0, 0), k: kv, c: cv, general: Some(GeneralBasis { t, tinv, minv, drive }) })
    }
}

impl ModalFlow {
    /// [`with_loads`](Self::with_loads) on a first-order basis `gb`.
    fn general_loads(basis: &Basis, gb: &GeneralBasis, loads: &Loads) -> Self {
        let n = basis.n;
        let (kv, cv) = (&basis.k, &basis.c);
        let (t, tinv, minv) = (&gb.t, &gb.tinv, &gb.minv);
        // P and R: the rows of T⁻¹ on the velocity part, times M⁻¹.
        let proj = |row: usize, g: &[f64]| -> f64 {
            let mut s = 0.0;
            for x in 0..n {
                let w: f64 = (0..n).map(|y| minv[(x, y)] * g[y]).sum();
                s += tinv[(row, n + x)] * w;
            }
            s
        };
        let p_of = |g: &[f64]| -> Vec<f64> { (0..n).map(|i| proj(2 * i, g)).collect() };
        // r + c p: the load of η'' + c η' + k η.
        let load_of = |g: &[f64]| -> Vec<f64> { (0..n).map(|i| proj(2 * i + 1, g) + cv[i] * proj(2 * i, g)).collect() };
        let g0 = load_of(&loads.constant);
        let mut harmonics = Vec::new();
        let (mut ph, mut waves) = (Vec::new(), Vec::new());
        for (g, amp, w, ph0) in &loads.waves {
            harmonics.push(Harmonic::new(load_of(g), *amp, *w, *ph0, kv, cv).driven(kv, cv, &gb.drive));
            // p' of a p ∝ a sin θ: a Ω cos θ = a Ω sin(θ + π/2).
            let pg = p_of(g);
            harmonics.push(Harmonic::new(pg.clone(), amp * w, *w, ph0 + std::f64::consts::FRAC_PI_2, kv, cv).driven(kv, cv, &gb.drive));
            ph.push(pg);
            waves.push((*amp, *w, *ph0));
        }
        let ramp_modal = loads.ramps.iter().map(|(h, _, _)| load_of(h)).collect();
        let pr = loads.ramps.iter().map(|(h, _, _)| p_of(h)).collect();
        let pf0 = p_of(&loads.constant);
        let general = General { t: t.clone(), tinv: tinv.clone(), minv: minv.clone(), pf0, ph, waves, pr, drive: gb.drive.clone() };
        let (ga, gb) = (g0.clone(), vec![0.0; n]);
        let piece = vec![(0.0, 0.0); loads.ramps.len()];
        let mut flow = Self {
            n,
            phi: Mat::zeros(0, 0),
            m_phi: Mat::zeros(0, 0),
            k: kv.clone(),
            c: cv.clone(),
            g0,
            harmonics,
            ramp_modal,
            general: Some(Box::new(general)),
            piece,
            ga,
            gb,
            tp: 0.0,
            time_dependent: loads.time_dependent(),
        };
        flow.drive_steady();
        flow
    }

    /// The drive `s_i` of mode `i` by mode `i + 1` (a defective chain,
    /// [`defective_chain`]: `η_i'' + c_i η_i' + k_i η_i = … + s_i η_{i+1}`;
    /// 0: none).
    #[inline]
    fn drive(&self, i: usize) -> f64 {
        self.general.as_ref().and_then(|g| g.drive.get(i).copied()).unwrap_or(0.0)
    }

    /// A driven mode's steady load (`ga`, `gb`) plus `s` times its driver's
    /// particular solution of its own, `(a + b τ)/k − c b/k²` (docs/theory.md
    /// §9.1): the driven mode's particular solution is then that of its
    /// load, and its remainder obeys `e'' + c e' + k e = s e₂` (`e₂` the
    /// driver's remainder). A driver's `k > 0` ([`defective_chain`]).
    fn drive_steady(&mut self) {
        let Some(g) = &self.general else { return };
        for (i, &s) in g.drive.iter().enumerate() {
            if s != 0.0 {
                let (k, c, a, b) = (self.k[i + 1], self.c[i + 1], self.ga[i + 1], self.gb[i + 1]);
                self.ga[i] += s * (a / k - c * b / (k * k));
                self.gb[i] += s * b / k;
            }
        }
    }

    /// Whether the damping is classical (the modes `Φ` of `(K, M)`), else
    /// the first-order form.
    pub fn classical(&self) -> bool {
        self.general.is_none()
    }

    /// `p_i(t)` of the first-order form (`η_i' = b_i + p_i`; 0 when classical).
    fn shift(&self, i: usize, t: f64) -> f64 {
        let Some(g) = &self.general else { return 0.0 };
        let mut s = g.pf0[i];
        for (j, &(a, w, p)) in g.waves.iter().enumerate() {
            let x = g.ph[j][i];
            if x != 0.0 {
                s += x * a * (w * t + p).sin();
            }
        }
        for (l, pr) in g.pr.iter().enumerate() {
            let (v, d) = self.piece[l];
            s += pr[i] * (v + d * (t - self.tp));
        }
        s
    }

    /// The functional `row_q · q + row_v · v` of the state (rows over this
    /// flow's dofs) on the modal state, as the search takes it: `Σ β_i η_i +
    /// α_i η_i'` plus, with the first-order form, the load terms `−Σ α_i p_i(t)`.
    /// `ramps` has one entry per series of the loads. A classical flow and
    /// a zero `row_v` (a position) leave `α` empty: the search then skips
    /// the `η'` terms.
    pub(crate) fn linear(&self, row_q: &[f64], row_v: &[f64]) -> Functional {
        let n = self.n;
        let mut f = Functional { beta: vec![0.0; n], alpha: vec![0.0; n], ramps: vec![0.0; self.ramp_modal.len()], ..Default::default() };
        match &self.general {
            None => {
                for i in 0..n {
                    f.beta[i] = (0..n).map(|r| row_q[r] * self.phi[(r, i)]).sum();
                    f.alpha[i] = (0..n).map(|r| row_v[r] * self.phi[(r, i)]).sum();
                }
                if row_v.iter().all(|&x| x == 0.0) {
                    f.alpha.clear();
                }
            }
            Some(g) => {
                for i in 0..n {
                    f.beta[i] = (0..n).map(|r| row_q[r] * g.t[(r, 2 * i)] + row_v[r] * g.t[(n + r, 2 * i)]).sum();
                    f.alpha[i] = (0..n).map(|r| row_q[r] * g.t[(r, 2 * i + 1)] + row_v[r] * g.t[(n + r, 2 * i + 1)]).sum();
                }
                f.constant = -(0..n).map(|i| f.alpha[i] * g.pf0[i]).sum::<f64>();
                for (j, &(a, w, p)) in g.waves.iter().enumerate() {
                    f.waves.push((-(0..n).map(|i| f.alpha[i] * g.ph[j][i]).sum::<f64>() * a, w, p));
                }
                for (l, pr) in g.pr.iter().enumerate() {
                    f.ramps[l] = -(0..n).map(|i| f.alpha[i] * pr[i]).sum::<f64>();
                }
            }
        }
        // The constant alone until the caller sets the piece (the series'
        // values are the caller's).
        f.now = (f.constant, 0.0, 0.0);
        f
    }

    /// Sets the series' loads to their piece `piece` (module docs): the
    /// flow is exact up to `piece.next`.
    pub(crate) fn set_piece(&mut self, piece: &Piece) {
        self.tp = piece.t_p;
        for (l, x) in self.piece.iter_mut().enumerate() {
            *x = (piece.values[l], piece.slopes[l]);
        }
        for i in 0..self.n {
            let (mut a, mut b) = (self.g0[i], 0.0);
            for (l, h) in self.ramp_modal.iter().enumerate() {
                a += h[i] * piece.values[l];
                b += h[i] * piece.slopes[l];
            }
            if let Some(g) = &self.general {
                // p' of the ramps: their slopes.
                for (l, pr) in g.pr.iter().enumerate() {
                    a += pr[i] * piece.slopes[l];
                }
            }
            (self.ga[i], self.gb[i]) = (a, b);
        }
        self.drive_steady();
    }

    /// Mode `i`'s constant and ramp load at `t_ref`: `a + b (t − t_ref)`.
    #[inline]
    fn steady(&self, i: usize, t_ref: f64) -> (f64, f64) {
        let b = self.gb[i];
        (if b == 0.0 { self.ga[i] } else { self.ga[i] + b * (t_ref - self.tp) }, b)
    }

    /// The number of modes.
    pub fn n(&self) -> usize {
        self.n
    }

    /// `M⁻¹ e_dof = Φ Φᵀ e_dof` (the modes are M-orthonormal).
    pub fn minv_column(&self, dof: usize) -> Vec<f64> {
        if let Some(g) = &self.general {
            return (0..self.n).map(|r| g.minv[(r, dof)]).collect();
        }
        (0..self.n).map(|r| (0..self.n).map(|i| self.phi[(r, i)] * self.phi[(dof, i)]).sum()).collect()
    }

    /// `M⁻¹ x`.
    pub(crate) fn minv(&self, x: &[f64]) -> Vec<f64> {
        let (mut y, mut out) = (Vec::new(), Vec::new());
        self.minv_into(x, &mut y, &mut out);
        out
    }

    /// [`minv`](Self::minv) into `out` (`y`: work storage; no allocation
    /// once both have the capacity).
    pub(crate) fn minv_into(&self, x: &[f64], y: &mut Vec<f64>, out: &mut Vec<f64>) {
        out.clear();
        if let Some(g) = &self.general {
            out.extend((0..self.n).map(|r| (0..self.n).map(|s| g.minv[(r, s)] * x[s]).sum::<f64>()));
            return;
        }
        y.clear();
        y.extend((0..self.n).map(|i| (0..self.n).map(|r| self.phi[(r, i)] * x[r]).sum::<f64>()));
        out.extend((0..self.n).map(|r| (0..self.n).map(|i| self.phi[(r, i)] * y[i]).sum::<f64>()));
    }

    /// Whether its loads depend on time ([`Loads::time_dependent`]).
    pub(crate) fn time_dependent(&self) -> bool {
        self.time_dependent
    }

    /// The squared natural frequencies `ω_i²`, ascending.
    pub fn omega2(&self) -> &[f64] {
        &self.k
    }

    /// The modal coordinates at `t`: `η = Φᵀ M q`, `η' = Φᵀ M v` (the
    /// first-order form: `(a, b) = T⁻¹ (q, v)`, `η = a`, `η' = b + p(t)`).
    pub(crate) fn to_modal(&self, t: f64, q: &[f64], v: &[f64], eta: &mut [f64], deta: &mut [f64]) {
        if let Some(g) = &self.general {
            let n = self.n;
            for i in 0..n {
                let (mut a, mut b) = (0.0, 0.0);
                for r in 0..n {
                    a += g.tinv[(2 * i, r)] * q[r] + g.tinv[(2 * i, n + r)] * v[r];
                    b += g.tinv[(2 * i + 1, r)] * q[r] + g.tinv[(2 * i + 1, n + r)] * v[r];
                }
                (eta[i], deta[i]) = (a, b + self.shift(i, t));
            }
            return;
        }
        for i in 0..self.n {
            (eta[i], deta[i]) = (0..self.n).fold((0.0, 0.0), |(a, b), r| (a + self.m_phi[(r, i)] * q[r], b + self.m_phi[(r, i)] * v[r]));
        }
    }

    /// Adds to `(eta, deta)` the modal coordinates of a change `(dq, dv)`
    /// of the state (`η += Φᵀ M dq`, `η' += Φᵀ M dv`; the first-order
    /// form: `(η, η') += T⁻¹ (dq, dv)`, its load shift unchanged): the modal
    /// state of `(q + dq, v + dv)` from that of `(q, v)` without the round
    /// trip through the state, whose map `Φ Φᵀ M` differs from the identity
    /// by the basis' round-off ([`super::EventDriven`]'s impacts,
    /// docs/theory.md §9.3).
    pub(crate) fn add_change(&self, dq: &[f64], dv: &[f64], eta: &mut [f64], deta: &mut [f64]) {
        let n = self.n;
        if let Some(g) = &self.general {
            for i in 0..n {
                let (mut a, mut b) = (0.0, 0.0);
                for r in 0..n {
                    a += g.tinv[(2 * i, r)] * dq[r] + g.tinv[(2 * i, n + r)] * dv[r];
                    b += g.tinv[(2 * i + 1, r)] * dq[r] + g.tinv[(2 * i + 1, n + r)] * dv[r];
                }
                (eta[i], deta[i]) = (eta[i] + a, deta[i] + b);
            }
            return;
        }
        for i in 0..n {
            let (a, b) = (0..n).fold((0.0, 0.0), |(a, b), r| (a + self.m_phi[(r, i)] * dq[r], b + self.m_phi[(r, i)] * dv[r]));
            (eta[i], deta[i]) = (eta[i] + a, deta[i] + b);
        }
    }

    /// `q = Φ η`, `v = Φ η'` at `t` (the first-order form: `T (η, η' − p(t))`).
    pub(crate) fn to_physical(&self, t: f64, eta: &[f64], deta: &[f64], q: &mut [f64], v: &mut [f64]) {
        let free: Vec<usize> = (0..self.n).collect();
        self.physical_into(t, eta, deta, &free, q, v);
    }

    /// [`to_physical`](Self::to_physical) into the entries `free` of `q`
    /// and `v` (no allocation).
    pub(crate) fn physical_into(&self, t: f64, eta: &[f64], deta: &[f64], free: &[usize], q: &mut [f64], v: &mut [f64]) {
        let n = self.n;
        let Some(g) = &self.general else {
            // Column by column (Φ is stored by columns): each entry still
            // sums its terms from 0 in the order of the modes, the same
            // bits as the row-by-row dot products.
            for &d in free {
                (q[d], v[d]) = (0.0, 0.0);
            }
            for i in 0..n {
                let (e, de) = (eta[i], deta[i]);
                let col = self.phi.col(i).try_as_col_major().expect("a dense matrix's column").as_slice();
                for (&x, &d) in col.iter().zip(free) {
                    q[d] += x * e;
                    v[d] += x * de;
                }
            }
            return;
        };
        for &d in free {
            (q[d], v[d]) = (0.0, 0.0);
        }
        for i in 0..n {
            let (a, b) = (eta[i], deta[i] - self.shift(i, t));
            for (r, &d) in free.iter().enumerate() {
                q[d] += g.t[(r, 2 * i)] * a + g.t[(r, 2 * i + 1)] * b;
                v[d] += g.t[(n + r, 2 * i)] * a + g.t[(n + r, 2 * i + 1)] * b;
            }
        }
    }

    /// The particular solution of mode `i` and its derivatives (orders
    /// `0..JET`) at `t`. Where it grows with time (a free mode's constant
    /// load, a harmonic near resonance) it is the one that vanishes at
    /// `t_ref` with its growth (`g₀ (t − t_ref)²/2`, the response from rest: they
    /// differ from the others by homogeneous solutions), so that no
    /// absolute time multiplies it: round-off stays relative to the motion
    /// since `t_ref`, not to the time elapsed since 0.
    fn particular_jet(&self, i: usize, t: f64, t_ref: f64, tr: &[(f64, f64)]) -> [f64; JET] {
        self.particular::<JET>(i, t, t_ref, tr)
    }

    /// The first `N` orders of [`particular_jet`](Self::particular_jet).
    fn particular<const N: usize>(&self, i: usize, t: f64, t_ref: f64, tr: &[(f64, f64)]) -> [f64; N] {
        let (k, c) = (self.k[i], self.c[i]);
        let (g0, b) = self.steady(i, t_ref);
        let mut p = [0.0; N];
        let st = t - t_ref;
        for (pm, terms) in p.iter_mut().zip(steady_terms(k, c, g0, b, st)) {
            *pm = terms[0] + terms[1] + terms[2];
        }
        self.add_harmonic_particular(i, st, tr, &mut p);
        p
    }

    /// Adds the harmonics' part of [`particular`](Self::particular) (`st = t − t_ref`) to `p`.
    fn add_harmonic_particular<const N: usize>(&self, i: usize, st: f64, tr: &[(f64, f64)], p: &mut [f64; N]) {
        for (h, &(s, co)) in self.harmonics.iter().zip(tr) {
            let w = h.omega;
            // d^m/dt^m of (a sin θ + b cos θ): Ω^m times the quarter-turns.
            let turn = |a: f64, b: f64, m: usize| -> f64 {
                match m % 4 {
                    0 => a * s + b * co,
                    1 => a * co - b * s,
                    2 => -a * s - b * co,
                    _ => -a * co + b * s,
                }
            };
            match h.coef[i] {
                Coef::Zero => {}
                Coef::Near(g) => add_from_rest(self.k[i], self.c[i], g, w, (s, co), st, p),
                Coef::Steady(a, b) => {
                    let mut wm = 1.0;
                    for (m, pm) in p.iter_mut().enumerate() {
                        *pm += wm * turn(a, b, m);
                        wm *= w;
                    }
                }
            }
        }
    }

    /// Bounds of `|P⁽ᵐ⁾|` (orders `0..=JET`) over `[t0, t0 + h]`, `P` the
    /// particular solution with `t_ref = t0`.
    fn particular_bounds(&self, i: usize, t0: f64, h: f64) -> [f64; JET + 1] {
        let (k, c) = (self.k[i], self.c[i]);
        let (g0, r) = self.steady(i, t0);
        let tt = h;
        let mut b = [0.0; JET + 1];
        // Each term is a power of τ: its magnitude at τ = h bounds it on [0, h].
        for (bm, terms) in b.iter_mut().zip(steady_terms(k, c, g0, r, tt)) {
            *bm = terms[0].abs() + terms[1].abs() + terms[2].abs();
        }
        for hm in &self.harmonics {
            let w = hm.omega;
            // From the coefficients: `|g| δ/d` is `g δ/d` up to its sign
            // (rounding is symmetric), and so on.
            match hm.coef[i] {
                Coef::Zero => {}
                Coef::Near(g) => {
                    // The response from rest over `[0, h]`: `|G| <= S̄ =
                    // min(h, 1/β)`, `|G'| <= 1 + α S̄` (the impulse
                    // response's), then the equation's recursion.
                    let (g, alpha) = (g.abs(), 0.5 * c);
                    let sbar = tt.min(1.0 / (k - alpha * alpha).sqrt());
                    let mut q = [0.0; JET + 1];
                    (q[0], q[1]) = (g * tt * sbar, g * tt * (1.0 + alpha * sbar));
                    let mut wm = 1.0;
                    for m in 2..=JET {
                        q[m] = g * wm + c * q[m - 1] + k * q[m - 2];
                        wm *= w.abs();
                    }
                    b.iter_mut().zip(q).for_each(|(x, y)| *x += y);
                }
                Coef::Steady(a, bb) => {
                    let amp = a.abs() + bb.abs();
                    let mut wm = 1.0;
                    for bm in b.iter_mut() {
                        *bm += wm * amp;
                        wm *= w;
                    }
                }
            }
        }
        b
    }

    /// Mode `i`'s remainder `e = η − P` and `e'` at `t` from `(η_i, η_i')`
    /// (`P` vanishing at `t_ref` where it grows).
    fn remainder(&self, i: usize, t: f64, t_ref: f64, eta: f64, deta: f64, tr: &[(f64, f64)]) -> (f64, f64) {
        let p = self.particular_jet(i, t, t_ref, tr);
        (eta - p[0], deta - p[1])
    }

    /// Mode `i`'s jet at `t` ([`jet_with`](Self::jet_with)) and the
    /// bounds of its derivatives over `[t, t + h]`
    /// ([`bounds_with`](Self::bounds_with)), from `(η_i, η_i')` at `t`: one
    /// evaluation of the particular solution for both (a search step's).
    pub(crate) fn jet_and_bounds(&self, i: usize, t: f64, eta: &[f64], deta: &[f64], h: f64, tr: &[(f64, f64)]) -> ([f64; JET], [f64; JET + 1]) {
        let p = self.particular_jet(i, t, t, tr);
        let s = self.drive(i);
        if s == 0.0 {
            return (self.jet_with(i, eta[i], deta[i], &p), self.bounds_with(i, t, eta[i], deta[i], h, &p));
        }
        // A driven mode (a defective chain, docs/theory.md §9.2): `e'' + c
        // e' + k e = s e₂`, `e₂` its driver's remainder, whose jet and
        // bounds (without its particular part) enter the recursions; its
        // response `s ∫ G(τ − u) e₂(u) du` (`G` the impulse response, `|G|
        // <= S̄`, `|G'| <= 1 + α S̄`) adds `s |e₂| h S̄` and `s |e₂| h (1 + α
        // S̄)` to the free bounds of orders 0 and 1.
        let p2 = self.particular_jet(i + 1, t, t, tr);
        let (k2, c2) = (self.k[i + 1], self.c[i + 1]);
        let mut e2 = [0.0; JET];
        (e2[0], e2[1]) = (eta[i + 1] - p2[0], deta[i + 1] - p2[1]);
        for m in 2..JET {
            e2[m] = -c2 * e2[m - 1] - k2 * e2[m - 2];
        }
        let (b0, b1, _) = free_bounds(k2, c2, e2[0], e2[1], h);
        let mut d2 = [0.0; JET + 1];
        (d2[0], d2[1]) = (b0, b1);
        for m in 2..=JET {
            d2[m] = c2 * d2[m - 1] + k2 * d2[m - 2];
        }
        let (k, c) = (self.k[i], self.c[i]);
        let mut e = [0.0; JET];
        (e[0], e[1]) = (eta[i] - p[0], deta[i] - p[1]);
        for m in 2..JET {
            e[m] = -c * e[m - 1] - k * e[m - 2] + s * e2[m - 2];
        }
        let mut jet = [0.0; JET];
        for m in 0..JET {
            jet[m] = e[m] + p[m];
        }
        (jet[0], jet[1]) = (eta[i], deta[i]);
        let (b0, b1, sbar) = free_bounds(k, c, e[0], e[1], h);
        let mut d = [0.0; JET + 1];
        (d[0], d[1]) = (b0 + s * d2[0] * h * sbar, b1 + s * d2[0] * h * (1.0 + 0.5 * c * sbar));
        for m in 2..=JET {
            d[m] = c * d[m - 1] + k * d[m - 2] + s * d2[m - 2];
        }
        let pb = self.particular_bounds(i, t, h);
        for m in 0..=JET {
            d[m] = (d[m] + pb[m]) * (1.0 + 1e-12);
        }
        (jet, d)
    }

    /// The derivatives `η_i⁽ᵐ⁾(t)`, `m = 0..JET`, from `(η_i, η_i')` at `t`
    /// (`p`: the particular solution's jet at `t`, `t_ref = t`).
    fn jet_with(&self, i: usize, eta: f64, deta: f64, p: &[f64; JET]) -> [f64; JET] {
        let (k, c) = (self.k[i], self.c[i]);
        let mut e = [0.0; JET];
        (e[0], e[1]) = (eta - p[0], deta - p[1]);
        for m in 2..JET {
            e[m] = -c * e[m - 1] - k * e[m - 2];
        }
        let mut out = [0.0; JET];
        for m in 0..JET {
            out[m] = e[m] + p[m];
        }
        (out[0], out[1]) = (eta, deta);
        out
    }

    /// Bounds of `|η_i⁽ᵐ⁾|`, `m = 0..=JET`, over `[t, t + h]` for the
    /// trajectory from `(η_i, η_i')` at `t` (docs/theory.md §9.2): `|e| <=
    /// |e₀| + |e₀' + α e₀| S̄`, `|e'| <= |e₀'| + |α e₀' + k e₀| S̄` with `S̄ =
    /// min(h, 1/√λ)` (λ > 0) or `h`, the first also at most the amplitude
    /// `√(e₀² + (e₀' + α e₀)²/λ)`; then `|e⁽ᵐ⁾| <= c |e⁽ᵐ⁻¹⁾| + k |e⁽ᵐ⁻²⁾|`;
    /// plus the particular solution's bounds (`p`: its jet at `t`).
    fn bounds_with(&self, i: usize, t: f64, eta: f64, deta: f64, h: f64, p: &[f64; JET]) -> [f64; JET + 1] {
        let (e0, de0) = (eta - p[0], deta - p[1]);
        let (k, c) = (self.k[i], self.c[i]);
        let mut d = [0.0; JET + 1];
        (d[0], d[1], _) = free_bounds(k, c, e0, de0, h);
        for m in 2..=JET {
            d[m] = c * d[m - 1] + k * d[m - 2];
        }
        let p = self.particular_bounds(i, t, h);
        for m in 0..=JET {
            // Round-off of the bound itself.
            d[m] = (d[m] + p[m]) * (1.0 + 1e-12);
        }
        d
    }

    /// The increments `(η(t0 + τ) − η, η'(t0 + τ) − η')` of mode `i` from
    /// `(η, η')` at `t0` (`dtr`: the harmonics'
    /// [`increments`](Self::trig_increments) over the step).
    #[inline]
    pub(crate) fn advance_mode(&self, i: usize, t0: f64, (eta, deta): (f64, f64), tau: f64, tr0: &[(f64, f64)], dtr: &[(f64, f64)]) -> (f64, f64) {
        let (k, alpha) = (self.k[i], 0.5 * self.c[i]);
        if k == 0.0 && alpha > 0.0 {
            // A damped free mode (`λ = 0, −c`): the steady load's response
            // from rest by the φ-functions, whose form has no `1/c` to
            // cancel (`a τ/c` against `a (1 − e^{−cτ})/c²` lost `ε/(cτ)` of
            // the motion: 1e-3 of the state at c = 1e-13, docs/theory.md §9.1),
            // plus the free decay of the rest (the harmonics' particular
            // solution taken off as before).
            let mut ph = [0.0; 2];
            self.add_harmonic_particular(i, 0.0, tr0, &mut ph);
            let mut dph = [0.0; 2];
            self.add_harmonic_delta(i, tau, tr0, dtr, &mut dph);
            let de0 = deta - ph[1];
            let z = -self.c[i] * tau;
            let [p1, p2, p3, _] = phis(z);
            let (g0, b) = self.steady(i, t0);
            return (de0 * tau * p1 + tau * tau * (g0 * p2 + b * tau * p3) + dph[0], de0 * z.exp_m1() + tau * (g0 * p1 + b * tau * p2) + dph[1]);
        }
        let p0 = self.particular::<2>(i, t0, t0, tr0);
        let (e0, de0) = (eta - p0[0], deta - p0[1]);
        let dp = self.particular_delta(i, t0, tau, tr0, dtr);
        let p1 = [p0[0] + dp[0], p0[1] + dp[1]];
        let lambda = k - alpha * alpha;
        if lambda < 0.0 && (-lambda).sqrt() * tau > 700.0 {
            // Overdamped over a long step: e^{−ατ} cosh(βτ) and
            // e^{−ατ} sinh(βτ)/β as sums of decaying exponentials (cosh
            // alone overflows for βτ > 710; below, the product is accurate
            // and kept as it was).
            let (dc, ds) = overdamped(alpha, (-lambda).sqrt(), tau);
            return (e0 * dc + (de0 + alpha * e0) * ds + p1[0] - eta, de0 * dc - (alpha * de0 + k * e0) * ds + p1[1] - deta);
        }
        // As increments of the state (docs/theory.md §9.1): over a short
        // step `e₀ (cos ωτ − 1)` is `−2 e₀ sin²(ωτ/2)`, not the difference
        // of two near-equal numbers, so a chatter flight's `η(τ) − η(0)`
        // (of size `v τ`) keeps its relative precision.
        let (cc1, ss) = cs_m1(lambda, tau);
        let (decay, dm1) = if alpha == 0.0 { (1.0, 0.0) } else { ((-alpha * tau).exp(), (-alpha * tau).exp_m1()) };
        // e^{−ατ} cos − 1.
        let a = decay * cc1 + dm1;
        let b = decay * ss;
        (e0 * a + (de0 + alpha * e0) * b + dp[0], de0 * a - (alpha * de0 + k * e0) * b + dp[1])
    }

    /// What a driven mode `i`'s driver adds to its increments over `τ` from
    /// `t0` (docs/theory.md §9.1), the driver at `(η₂, η₂')`: the response
    /// `s ∫₀^τ G(τ − u) e₂(u) du` and its derivative, `G(u) = Im e^{μu}/ω₁`
    /// the driven mode's impulse response (`μ = −α₁ + iω₁`) and `e₂(u) =
    /// Re κ e^{νu}` the driver's remainder (`ν = −α₂ + iω₂`, `κ = e₂ −
    /// i (e₂' + α₂ e₂)/ω₂`): `s/ω₁ Im[(κ I(μ, ν) + κ̄ I(μ, ν̄))/2]`, and with `μ`
    /// inside the bracket for the derivative, `I(x, y) = ∫₀^τ e^{x(τ − u)}
    /// e^{yu} du` ([`divided`]). At a defective pair `ν = μ`, `I(μ, μ) = τ
    /// e^{μτ}`: the secular terms `τ e^{στ} (cos, sin)`; split, the same
    /// formula to round-off however small the split.
    fn driven_delta(&self, i: usize, t0: f64, (eta, deta): (f64, f64), tau: f64, tr0: &[(f64, f64)]) -> (f64, f64) {
        let p = self.particular::<2>(i + 1, t0, t0, tr0);
        let (e, de) = (eta - p[0], deta - p[1]);
        let root = |k: f64, c: f64| faer::c64::new(-0.5 * c, (k - 0.25 * c * c).sqrt());
        let (mu, nu) = (root(self.k[i], self.c[i]), root(self.k[i + 1], self.c[i + 1]));
        let kappa = faer::c64::new(e, -(de + 0.5 * self.c[i + 1] * e) / nu.im);
        let z = (kappa * divided(mu, nu, tau) + kappa.conj() * divided(mu, nu.conj(), tau)) * 0.5;
        let f = self.drive(i) / mu.im;
        (f * z.im, f * (mu * z).im)
    }

    /// `sin θ₁ − sin θ₀, cos θ₁ − cos θ₀` of every harmonic over `[t0, t0 + τ]`
    /// (`θ = Ω_j t + p_j`; `tr0` at `t0`), accurate for small `τ`:
    /// `sin θ₀ (cos Ωτ − 1) + cos θ₀ sin Ωτ`, `cos Ωτ − 1 = −2 sin²(Ωτ/2)`.
    fn trig_increments(&self, tau: f64, tr0: &[(f64, f64)], out: &mut Vec<(f64, f64)>) {
        out.clear();
        out.extend(self.harmonics.iter().zip(tr0).map(|(h, &(s0, c0))| {
            let (half, ch) = (0.5 * h.omega * tau).sin_cos();
            let (sw, cm1) = (2.0 * half * ch, -2.0 * half * half);
            (s0 * cm1 + c0 * sw, c0 * cm1 - s0 * sw)
        }));
    }

    /// `P(t0 + τ) − P(t0)` and the same of `P'` (`P` the particular
    /// solution with `t_ref = t0`), from the harmonics' increments `dtr`:
    /// the steady terms' constants cancel exactly, and a chatter flight's
    /// short step keeps its relative precision (docs/theory.md §9.1).
    fn particular_delta(&self, i: usize, t0: f64, tau: f64, tr0: &[(f64, f64)], dtr: &[(f64, f64)]) -> [f64; 2] {
        let (k, c) = (self.k[i], self.c[i]);
        let (g0, b) = self.steady(i, t0);
        let (at1, at0) = (steady_terms(k, c, g0, b, tau), steady_terms(k, c, g0, b, 0.0));
        let mut d = [0.0; 2];
        for m in 0..2 {
            d[m] = (at1[m][0] - at0[m][0]) + (at1[m][1] - at0[m][1]) + (at1[m][2] - at0[m][2]);
        }
        self.add_harmonic_delta(i, tau, tr0, dtr, &mut d);
        d
    }

    /// Adds the harmonics' part of [`particular_delta`](Self::particular_delta) to `d`.
    fn add_harmonic_delta(&self, i: usize, tau: f64, tr0: &[(f64, f64)], dtr: &[(f64, f64)], d: &mut [f64; 2]) {
        for ((h, &(s0, c0)), &(ds, dc)) in self.harmonics.iter().zip(tr0).zip(dtr) {
            let w = h.omega;
            match h.coef[i] {
                Coef::Zero => {}
                Coef::Near(g) => {
                    // From rest at t0: the increments are the response.
                    let (x, dx) = from_rest(self.k[i], self.c[i], g, w, (s0, c0), tau);
                    d[0] += x;
                    d[1] += dx;
                }
                Coef::Steady(a, bb) => {
                    d[0] += a * ds + bb * dc;
                    d[1] += w * (a * dc - bb * ds);
                }
            }
        }
    }

    /// `sin, cos (Ω_j t + p_j)` of every harmonic into `out` (shared by
    /// every mode: one `sin_cos` per harmonic and time).
    pub(crate) fn trig(&self, t: f64, out: &mut Vec<(f64, f64)>) {
        out.clear();
        out.extend(self.harmonics.iter().map(|h| (h.omega * t + h.phase).sin_cos()));
    }

    /// Advances the modal state in place by `tau` from `t0` (`tr`: work storage).
    pub(crate) fn advance_modal(&self, t0: f64, eta: &mut [f64], deta: &mut [f64], tau: f64, tr: &mut [Vec<(f64, f64)>; 2]) {
        let [tr0, dtr] = tr;
        self.trig(t0, tr0);
        self.trig_increments(tau, tr0, dtr);
        for i in 0..self.n {
            let (mut d, mut dd) = self.advance_mode(i, t0, (eta[i], deta[i]), tau, tr0, dtr);
            // A driven mode's driver `i + 1` is still at `t0`.
            if self.drive(i) != 0.0 {
                let (x, y) = self.driven_delta(i, t0, (eta[i + 1], deta[i + 1]), tau, tr0);
                (d, dd) = (d + x, dd + y);
            }
            (eta[i], deta[i]) = (eta[i] + d, deta[i] + dd);
        }
    }

    /// [`advance_modal`](Self::advance_modal) from `(eta0, deta0)` into
    /// `(eta, deta)`, keeping the increments in `(d, dd)` (their full
    /// precision: the search evaluates its functionals from them).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn advance_modal_from(
        &self,
        t0: f64,
        (eta0, deta0): (&[f64], &[f64]),
        tau: f64,
        (eta, deta): (&mut [f64], &mut [f64]),
        (d, dd): (&mut [f64], &mut [f64]),
        tr: &mut [Vec<(f64, f64)>; 2],
    ) {
        let [tr0, dtr] = tr;
        self.trig(t0, tr0);
        self.trig_increments(tau, tr0, dtr);
        for i in 0..self.n {
            (d[i], dd[i]) = self.advance_mode(i, t0, (eta0[i], deta0[i]), tau, tr0, dtr);
            if self.drive(i) != 0.0 {
                let (x, y) = self.driven_delta(i, t0, (eta0[i + 1], deta0[i + 1]), tau, tr0);
                (d[i], dd[i]) = (d[i] + x, dd[i] + y);
            }
            (eta[i], deta[i]) = (eta0[i] + d[i], deta0[i] + dd[i]);
        }
    }

    /// `∫ η_i` over `[t0, t0 + tau]`, mode `i` from `(η, η')` at `t0` to `(η₁, η₁')`.
    pub(crate) fn integral(&self, i: usize, t0: f64, start: (&[f64], &[f64]), end: (&[f64], &[f64]), tau: f64, tr: &[Vec<(f64, f64)>; 2]) -> f64 {
        let ((eta, deta), (eta1, deta1)) = ((start.0[i], start.1[i]), (end.0[i], end.1[i]));
        let (k, c) = (self.k[i], self.c[i]);
        let (g0, b) = self.steady(i, t0);
        let t1 = t0 + tau;
        let mut s = if k == 0.0 && c > 0.0 {
            // A damped free mode (`λ = 0, −c`): `advance_mode`'s φ-form
            // integrated, `∫₀^τ s^j φ_j(−cs) ds = τ^{j+1} φ_{j+1}(−cτ)`:
            // `e₀ τ + e₀' τ² φ₂ + g₀ τ³ φ₃ + b τ⁴ φ₄` (`e₀, e₀'` less the
            // harmonics' particular part, whose integral is added below).
            // The `1/c` form, `e₀ τ + e₀' (τ + expm1(−cτ)/c)/c + g₀ τ²/(2c)`
            // with `e₀' = η₀' − g₀/c`, cancelled to `~ε/(cτ)` of its terms:
            // 1e10 of the integral at `c = 1e-13` (docs/theory.md §9.1).
            let mut ph = [0.0; 2];
            self.add_harmonic_particular(i, 0.0, &tr[0], &mut ph);
            let (e0, de0) = (eta - ph[0], deta - ph[1]);
            let [_, p2, p3, p4] = phis(-c * tau);
            e0 * tau + tau * tau * (de0 * p2 + tau * (g0 * p3 + b * tau * p4))
        } else if k > 0.0 {
            let (e0, de0) = self.remainder(i, t0, t0, eta, deta, &tr[0]);
            let (e1, de1) = self.remainder(i, t1, t0, eta1, deta1, &tr[1]);
            // The remainder: e'' + c e' + k e = 0 (a driven mode's: `s e₂`,
            // its driver's remainder, whose integral is the same form's).
            let s = self.drive(i);
            if s == 0.0 {
                -((de1 - de0) + c * (e1 - e0)) / k + g0 * tau / k
            } else {
                let (k2, c2) = (self.k[i + 1], self.c[i + 1]);
                let (f0, df0) = self.remainder(i + 1, t0, t0, start.0[i + 1], start.1[i + 1], &tr[0]);
                let (f1, df1) = self.remainder(i + 1, t1, t0, end.0[i + 1], end.1[i + 1], &tr[1]);
                let driver = -((df1 - df0) + c2 * (f1 - f0)) / k2;
                -((de1 - de0) + c * (e1 - e0) - s * driver) / k + g0 * tau / k
            }
        } else {
            let (e0, de0) = self.remainder(i, t0, t0, eta, deta, &tr[0]);
            e0 * tau + 0.5 * de0 * tau * tau + g0 * tau * tau * tau / 6.0
        };
        if b != 0.0 && !(k == 0.0 && c > 0.0) {
            s += if k > 0.0 { b * tau * tau / (2.0 * k) - c * b * tau / (k * k) } else { b * tau * tau * tau * tau / 24.0 };
        }
        // From the particular solutions' coefficients (a driven mode's take
        // its driver's in).
        for h in &self.harmonics {
            let w = h.omega;
            let at = |t: f64| (w * t + h.phase).sin_cos();
            match h.coef[i] {
                Coef::Zero => {}
                Coef::Near(g) => {
                    // The response from rest `x` obeys its equation: `k ∫ x
                    // = ∫ g sin θ − x'(τ) − c x(τ)`.
                    let ((s0, c0), (_, c1)) = (at(t0), at(t1));
                    let (x, dx) = from_rest(k, c, g, w, (s0, c0), tau);
                    s += (g * (c0 - c1) / w - dx - c * x) / k;
                }
                Coef::Steady(a, b) => {
                    let ((s0, c0), (s1, c1)) = (at(t0), at(t1));
                    s += (-a * (c1 - c0) + b * (s1 - s0)) / w;
                }
            }
        }
        s
    }

    /// `∫ q_dof` over `[t0, t0 + tau]` along the flow from `(q0, v0)` at
    /// `t0`, taken as a held force's impulse is (the position's functional,
    /// [`linear`](Self::linear), integrated from the modal states at both
    /// ends, docs/theory.md §9.3): for the tests, which check it against
    /// an independent oracle.
    ///
    /// # Panics
    /// If a slice's length is not the problem's or `dof` is not one of its
    /// dofs (a programmer error).
    #[doc(hidden)]
    #[track_caller]
    pub fn position_integral(&self, t0: f64, q0: &[f64], v0: &[f64], tau: f64, dof: usize) -> f64 {
        let n = self.n;
        assert!(q0.len() == n && v0.len() == n && dof < n, "state slices of {n} entries, a dof below {n}");
        let (mut eta0, mut deta0) = (vec![0.0; n], vec![0.0; n]);
        self.to_modal(t0, q0, v0, &mut eta0, &mut deta0);
        let (mut eta, mut deta, mut d, mut dd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        self.advance_modal_from(t0, (&eta0, &deta0), tau, (&mut eta, &mut deta), (&mut d, &mut dd), &mut [Vec::new(), Vec::new()]);
        let mut unit = vec![0.0; n];
        unit[dof] = 1.0;
        self.linear(&unit, &vec![0.0; n]).integral(self, t0, (&eta0, &deta0), (&eta, &deta), tau, &mut [Vec::new(), Vec::new()])
    }

    /// Advances the state `(q0, v0)` at time `t0` by `tau` exactly into
    /// `(q, v)` (see the module docs).
    ///
    /// # Panics
    /// If a slice's length is not the problem's (a programmer error).
    #[track_caller]
    pub fn advance(&self, t0: f64, q0: &[f64], v0: &[f64], tau: f64, q: &mut [f64], v: &mut [f64]) {
        let n = self.n;
        assert!(q0.len() == n && v0.len() == n && q.len() == n && v.len() == n, "state slices of {n} entries");
        let (mut eta, mut deta) = (vec![0.0; n], vec![0.0; n]);
        self.to_modal(t0, q0, v0, &mut eta, &mut deta);
        self.advance_modal(t0, &mut eta, &mut deta, tau, &mut [Vec::new(), Vec::new()]);
        self.to_physical(t0 + tau, &eta, &deta, q, v);
    }
}

/// `g(t) = Σ β_i η_i + α_i η_i' + c₀ + c₁ (t − t_p) + Σ_j c_j sin(Ω_j t + p_j)`: a quantity
/// whose sign change is an event, on the modal state ([`ModalFlow::linear`]
/// builds one; the event search, `search.rs`, owns its methods and its
/// module docs the details).
#[derive(Clone, Debug, Default)]
pub(crate) struct Functional {
    pub beta: Vec<f64>,
    /// Empty: no `η'` terms.
    pub alpha: Vec<f64>,
    /// `c₀` without the series (`c₀` is `constant` plus the series' values).
    pub constant: f64,
    /// `(c_j, Ω_j, p_j)`.
    pub waves: Vec<(f64, f64, f64)>,
    /// The coefficient of each piecewise-linear series `s_l(t)`.
    pub ramps: Vec<f64>,
    /// `c₀` and `c₁` on the current piece, and `t_p`.
    pub now: (f64, f64, f64),
}

/// The first event of a free flight ([`ModalFlow::first_crossing`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Its time.
    pub t: f64,
    /// The bound reached.
    pub bound: Bound,
    /// The displacement there.
    pub q: Vec<f64>,
    /// The velocity there.
    pub v: Vec<f64>,
}
