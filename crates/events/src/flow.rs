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
//! `cΩ A + (k − Ω²) B = 0`; at resonance, `c = 0` and `k = Ω²`, the secular
//! `−G a t cos θ / (2Ω)`; a free mode `k = 0` integrates the constant)
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

use faer::{Mat, Side};
use signorini_fem::SymBand;
use signorini_schemes::{Dynamics, TimeProfile};

/// Why a problem has no exact modal flow here.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EventsError {
    /// The mass matrix is not positive definite (a massless dof: its static
    /// condensation is not implemented yet).
    #[error("mass: not positive definite (a massless dof is not taken yet by the exact flow)")]
    MassNotDefinite,
    /// The damping matrix is not diagonalised by the undamped modes.
    #[error("damping: the undamped modes do not diagonalise C (largest off-diagonal {off:e} against the largest modal damping {diag:e}); allowed: classical damping, e.g. Rayleigh C = a M + b K")]
    NotClassical {
        /// Largest |off-diagonal| of Φᵀ C Φ.
        off: f64,
        /// Largest |diagonal| of Φᵀ C Φ.
        diag: f64,
    },
    /// A load profile without a closed-form particular solution here.
    #[error("forcing term {index}: a piecewise-linear series is not taken yet by the exact flow; allowed: sine or harmonics")]
    Profile {
        /// The forcing term.
        index: usize,
    },
    /// The symmetric eigensolver failed.
    #[error("the modal decomposition of (K, M) failed")]
    Eigen,
    /// A contact without rebound (`e = 0`) would start a held phase, not
    /// implemented yet.
    #[error("contact {contact}: restitution {restitution} is not taken yet by the event-driven integrator (e = 0 starts a held phase); allowed (0, 1]")]
    HeldPhase {
        /// The contact.
        contact: usize,
        /// Its restitution.
        restitution: f64,
    },
    /// More events than allowed (impacts accumulating toward a held phase).
    #[error("{events} events by t = {t}: impacts accumulate (the held phase they lead to is not implemented yet), or raise the limit")]
    TooManyEvents {
        /// Where it stopped.
        t: f64,
        /// Events taken.
        events: usize,
    },
    /// The event search took too many steps (a contact grazing its bound).
    #[error("the event search stopped at t = {t} after {steps} steps (a contact grazing its bound without reaching it)")]
    NoConvergence {
        /// Where it stopped.
        t: f64,
        /// Steps taken.
        steps: usize,
    },
}

/// One harmonic load term in modal coordinates: `G_i a sin(Ω t + p)` for every mode `i`.
#[derive(Clone, Debug)]
struct Harmonic {
    modal: Vec<f64>,
    amplitude: f64,
    omega: f64,
    phase: f64,
}

/// The exact flow of a linear problem between events (see the module docs).
#[derive(Clone, Debug)]
pub struct ModalFlow {
    n: usize,
    /// Φ (columns: the modes), n × n.
    phi: Mat<f64>,
    /// `M Φ`: `η = (M Φ)ᵀ q`.
    m_phi: Mat<f64>,
    /// ω_i² (ascending).
    k: Vec<f64>,
    /// Modal damping `c_i = φ_iᵀ C φ_i`.
    c: Vec<f64>,
    /// The steady load in modal coordinates.
    g0: Vec<f64>,
    harmonics: Vec<Harmonic>,
}

fn dense(a: &SymBand) -> Mat<f64> {
    Mat::from_fn(a.n(), a.n(), |i, j| a.get(i, j))
}

/// `C(τ)` and `S(τ)` of the module docs for `λ = k − α²`.
fn cs(lambda: f64, tau: f64) -> (f64, f64) {
    if lambda > 0.0 {
        let w = lambda.sqrt();
        ((w * tau).cos(), (w * tau).sin() / w)
    } else if lambda < 0.0 {
        let w = (-lambda).sqrt();
        ((w * tau).cosh(), (w * tau).sinh() / w)
    } else {
        (1.0, tau)
    }
}

impl ModalFlow {
    /// The flow of `dy`'s free motion (its contacts ignored): `M` positive
    /// definite, `C` classical, each forcing profile a sine or a sum of harmonics.
    pub fn new(dy: &Dynamics) -> Result<Self, EventsError> {
        let n = dy.n();
        let m = dense(&dy.mass);
        let llt = m.llt(Side::Lower).map_err(|_| EventsError::MassNotDefinite)?;
        let l = llt.L().to_owned();
        let mut linv = Mat::<f64>::identity(n, n);
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), faer::Par::Seq);
        let a = &linv * dense(&dy.stiffness) * linv.transpose();
        let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
        let evd = a.self_adjoint_eigen(Side::Lower).map_err(|_| EventsError::Eigen)?;
        // A rigid mode's ω² is round-off (±1e-16 of the largest): exactly 0,
        // so that its particular solution integrates the load instead of
        // dividing by the round-off.
        let kmax = (0..n).map(|i| evd.S().column_vector()[i].abs()).fold(0.0, f64::max);
        let k: Vec<f64> = (0..n).map(|i| evd.S().column_vector()[i]).map(|w2| if w2.abs() <= 1e-12 * kmax { 0.0 } else { w2 }).collect();
        let phi = linv.transpose() * evd.U();
        let m_phi = &m * &phi;
        let c = match &dy.damping {
            None => vec![0.0; n],
            Some(cm) => {
                let modal = phi.transpose() * dense(cm) * &phi;
                let diag = (0..n).map(|i| modal[(i, i)].abs()).fold(0.0, f64::max);
                let off = (0..n).flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j))).map(|(i, j)| modal[(i, j)].abs()).fold(0.0, f64::max);
                if off > 1e-10 * diag.max(f64::MIN_POSITIVE) {
                    return Err(EventsError::NotClassical { off, diag });
                }
                (0..n).map(|i| modal[(i, i)]).collect()
            }
        };
        let project = |g: &[f64]| -> Vec<f64> { (0..n).map(|i| (0..n).map(|r| phi[(r, i)] * g[r]).sum()).collect() };
        let mut g0 = project(&dy.load);
        let mut harmonics = Vec::new();
        for (index, f) in dy.forcing.iter().enumerate() {
            let modal = project(&f.shape);
            match &f.time {
                &TimeProfile::Sine { amplitude, omega } => harmonics.push(Harmonic { modal, amplitude, omega, phase: 0.0 }),
                TimeProfile::Harmonics(h) => {
                    for t in h.iter() {
                        if t.omega == 0.0 {
                            // A constant: a sin(p).
                            let s = t.amplitude * t.phase.sin();
                            g0.iter_mut().zip(&modal).for_each(|(g, m)| *g += s * m);
                        } else {
                            harmonics.push(Harmonic { modal: modal.clone(), amplitude: t.amplitude, omega: t.omega, phase: t.phase });
                        }
                    }
                }
                TimeProfile::Series(_) => return Err(EventsError::Profile { index }),
            }
        }
        Ok(Self { n, phi, m_phi, k, c, g0, harmonics })
    }

    /// `M⁻¹ e_dof = Φ Φᵀ e_dof` (the modes are M-orthonormal).
    pub fn minv_column(&self, dof: usize) -> Vec<f64> {
        (0..self.n).map(|r| (0..self.n).map(|i| self.phi[(r, i)] * self.phi[(dof, i)]).sum()).collect()
    }

    /// The squared natural frequencies `ω_i²`, ascending.
    pub fn omega2(&self) -> &[f64] {
        &self.k
    }

    /// The particular solution of mode `i` and its derivative at `t`.
    fn particular(&self, i: usize, t: f64) -> (f64, f64) {
        let (k, c) = (self.k[i], self.c[i]);
        let g0 = self.g0[i];
        let (mut p, mut dp) = if k > 0.0 {
            (g0 / k, 0.0)
        } else if c > 0.0 {
            (g0 * t / c, g0 / c)
        } else {
            (0.5 * g0 * t * t, g0 * t)
        };
        for h in &self.harmonics {
            let g = h.modal[i] * h.amplitude;
            if g == 0.0 {
                continue;
            }
            let w = h.omega;
            let th = w * t + h.phase;
            let (s, co) = th.sin_cos();
            let detune = k - w * w;
            if c == 0.0 && detune.abs() <= 1e-13 * w * w {
                // Resonance: the secular solution.
                p += -g * t * co / (2.0 * w);
                dp += -g * co / (2.0 * w) + 0.5 * g * t * s;
            } else {
                let d = detune * detune + (c * w) * (c * w);
                let (a, b) = (g * detune / d, -g * c * w / d);
                p += a * s + b * co;
                dp += w * (a * co - b * s);
            }
        }
        (p, dp)
    }

    /// Mode `i`'s remainder `e = η − P` and `e'` at `t0` from the state
    /// `(q0, v0)` (`η = φ_iᵀ M q`).
    fn homogeneous_start(&self, i: usize, t0: f64, q0: &[f64], v0: &[f64]) -> (f64, f64) {
        let (eta, deta) = (0..self.n).fold((0.0, 0.0), |(a, b), r| (a + self.m_phi[(r, i)] * q0[r], b + self.m_phi[(r, i)] * v0[r]));
        let (p0, dp0) = self.particular(i, t0);
        (eta - p0, deta - dp0)
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
        let mut eta = vec![0.0; n];
        let mut deta = vec![0.0; n];
        for i in 0..n {
            let (e0, de0) = self.homogeneous_start(i, t0, q0, v0);
            let (k, alpha) = (self.k[i], 0.5 * self.c[i]);
            let (cc, ss) = cs(k - alpha * alpha, tau);
            let decay = (-alpha * tau).exp();
            let (p1, dp1) = self.particular(i, t0 + tau);
            eta[i] = decay * (e0 * cc + (de0 + alpha * e0) * ss) + p1;
            deta[i] = decay * (de0 * cc - (alpha * de0 + k * e0) * ss) + dp1;
        }
        for r in 0..n {
            q[r] = (0..n).map(|i| self.phi[(r, i)] * eta[i]).sum();
            v[r] = (0..n).map(|i| self.phi[(r, i)] * deta[i]).sum();
        }
    }
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

/// Which bound of a contact dof a trajectory reaches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bound {
    /// `q_c = lo`, approached from above.
    Lower,
    /// `q_c = hi`, approached from below.
    Upper,
}

impl ModalFlow {
    /// An upper bound of `|q_c''|` on `[t0, t0 + h]` for the trajectory from
    /// `(q0, v0)` at `t0` (docs/theory.md §9.2): per mode,
    /// `|e''| <= c |e'|max + k |e|max` with `|e| <= |e₀| + |e₀' + α e₀| S̄`,
    /// `|e'| <= |e₀'| + |α e₀' + k e₀| S̄`, `S̄ = min(h, 1/√λ)` (λ > 0) or `h`,
    /// plus the particular solution's `|P''|` (`Ω² (|A| + |B|)` per harmonic,
    /// `|g|(1 + Ω (t0 + h)/2)` at resonance, `|g₀|` for a free undamped mode).
    fn curvature_bound(&self, dof: usize, t0: f64, q0: &[f64], v0: &[f64], h: f64) -> f64 {
        let n = self.n;
        let mut b = 0.0;
        for i in 0..n {
            let w = self.phi[(dof, i)].abs();
            if w == 0.0 {
                continue;
            }
            let (e0, de0) = self.homogeneous_start(i, t0, q0, v0);
            let (k, c) = (self.k[i], self.c[i]);
            let alpha = 0.5 * c;
            let lambda = k - alpha * alpha;
            let sbar = if lambda > 0.0 { h.min(1.0 / lambda.sqrt()) } else { h };
            let emax = e0.abs() + (de0 + alpha * e0).abs() * sbar;
            let demax = de0.abs() + (alpha * de0 + k * e0).abs() * sbar;
            let mut pp = if k == 0.0 && c == 0.0 { self.g0[i].abs() } else { 0.0 };
            for hm in &self.harmonics {
                let g = hm.modal[i] * hm.amplitude;
                let om = hm.omega;
                let detune = k - om * om;
                if c == 0.0 && detune.abs() <= 1e-13 * om * om {
                    pp += g.abs() * (1.0 + om * (t0 + h).abs() / 2.0);
                } else {
                    let d = detune * detune + (c * om) * (c * om);
                    pp += om * om * (g * detune / d).abs() + om * om * (g * c * om / d).abs();
                }
            }
            b += w * (c * demax + k * emax + pp);
        }
        // Round-off of the bound itself.
        b * (1.0 + 1e-12) + f64::MIN_POSITIVE
    }

    /// The first time in `(t0, t0 + horizon]` at which the contact dof `dof`
    /// of the trajectory from `(q0, v0)` reaches `lo` (from above) or `hi`
    /// (from below), with the state there; `None` if it stays strictly
    /// inside. The state must start inside (`lo < q_c < hi`, or on a bound
    /// and leaving it).
    ///
    /// No event is missed: each step goes no further than where the
    /// parabola `g + g' s − B s²/2` (g the distance to the bound, B a bound
    /// of `|g''|` over the window) reaches 0, and that parabola lies below
    /// the distance (Taylor's formula with remainder), so the distance
    /// stays positive on every step taken. Near a root the steps shrink
    /// quadratically; the search stops when a step is below 1e-15 of the
    /// time (a relative 1e-15 event time) or after `max_steps` steps.
    #[allow(clippy::too_many_arguments)]
    pub fn first_crossing(&self, t0: f64, q0: &[f64], v0: &[f64], dof: usize, lo: f64, hi: f64, horizon: f64) -> Result<Option<Event>, EventsError> {
        let n = self.n;
        let end = t0 + horizon;
        let (mut t, mut q, mut v) = (t0, q0.to_vec(), v0.to_vec());
        let (mut qn, mut vn) = (vec![0.0; n], vec![0.0; n]);
        // The window over which the curvature bound is taken: a fraction
        // of the shortest period keeps it tight without many windows.
        let kmax = self.k.iter().fold(0.0f64, |a, &k| a.max(k));
        let window = if kmax > 0.0 { 0.25 / kmax.sqrt() } else { horizon };
        for _ in 0..MAX_STEPS {
            let h = window.min(end - t);
            if h <= 0.0 {
                return Ok(None);
            }
            let b = self.curvature_bound(dof, t, &q, &v, h);
            let mut step = h;
            let mut side = None;
            for (s, g, dg) in [(Bound::Lower, q[dof] - lo, v[dof]), (Bound::Upper, hi - q[dof], -v[dof])] {
                if !g.is_finite() {
                    continue;
                }
                // The root of g + dg s − b s²/2 (b > 0): where the lower bound reaches 0.
                let g = g.max(0.0);
                let reach = (dg + (dg * dg + 2.0 * b * g).sqrt()) / b;
                if reach < step {
                    step = reach;
                    side = Some(s);
                }
            }
            if let Some(s) = side {
                if step <= 1e-15 * t.abs().max(1e-300) || (step <= f64::EPSILON * t.abs().max(1.0)) {
                    let te = t + step;
                    self.advance(t, &q, &v, step, &mut qn, &mut vn);
                    return Ok(Some(Event { t: te, bound: s, q: qn, v: vn }));
                }
            }
            self.advance(t, &q, &v, step, &mut qn, &mut vn);
            t += step;
            std::mem::swap(&mut q, &mut qn);
            std::mem::swap(&mut v, &mut vn);
            if side.is_none() && t >= end {
                return Ok(None);
            }
        }
        Err(EventsError::NoConvergence { t, steps: MAX_STEPS })
    }
}

/// Steps of [`ModalFlow::first_crossing`] before it gives up (a grazing
/// contact that never quite touches can take many).
const MAX_STEPS: usize = 1_000_000;
