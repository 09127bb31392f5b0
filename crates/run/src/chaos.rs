//! The largest Lyapunov exponent by twin runs with renormalisation
//! (Benettin et al. 1980), and the predictability horizon it implies.
//!
//! A reference run `a` and a twin `b = a + δ₀`, `‖δ₀‖ = d₀ = ε ‖a‖`
//! (relative perturbation `ε`, a seeded pseudo-random direction), advance
//! `τ` at a time; after each interval `k` the separation `d_k = ‖b − a‖` gives
//! the log growth `g_k = ln(d_k / d₀)` and the twin is put back at distance
//! `d₀` along the separation, `b ← a + (b − a) d₀/d_k`. Then
//! `λ_max = (Σ g_k)/(K τ)`, and a confidence interval from the batch means
//! of the `g_k / τ` ([`crate::stats::batch_means`]): successive growths are
//! correlated (the separation's direction is carried over), batches of many
//! intervals are nearly independent.
//!
//! The separation is measured in a norm of the state given as a closure: for
//! a [`Stepper`] the energy norm `√(δuᵀ K δu + δvᵀ M δv)` of its `(U, V)`
//! ([`energy_norm`]), any further internal state (Newmark's `R`) carried
//! along and rescaled with the rest. Any two norms give the same `λ_max` in
//! the limit; a finite run's estimate differs by O(1/(K τ)).
//!
//! No IO.

use crate::stats::{batch_means, Interval};
use crate::RunError;
use signorini_schemes::{SplitMix64, Stepper};

/// A system advanced in fixed steps whose whole state can be read and set.
pub trait Flow {
    /// The time of one step (1 for a map).
    fn dt(&self) -> f64;
    /// The whole state, flat.
    fn state(&self) -> Result<Vec<f64>, RunError>;
    /// Replaces the whole state.
    fn set_state(&mut self, s: &[f64]) -> Result<(), RunError>;
    /// Advances `steps` steps.
    fn advance(&mut self, steps: usize) -> Result<(), RunError>;
}

/// A [`Stepper`] as a [`Flow`] (through [`Stepper::state`] and
/// [`Stepper::set_state`]; a scheme without them is refused, naming `scheme`).
pub struct StepperFlow(pub Box<dyn Stepper>);

const NO_STATE: RunError =
    RunError::NotAllowed { field: "scheme", allowed: "a scheme that offers its state for twin runs (Paoli–Schatzman and the β-schemes, Moreau–Jean, undamped Newmark/θ with massive contacts)" };

impl Flow for StepperFlow {
    fn dt(&self) -> f64 {
        self.0.dt()
    }
    fn state(&self) -> Result<Vec<f64>, RunError> {
        self.0.state().ok_or(NO_STATE)
    }
    fn set_state(&mut self, s: &[f64]) -> Result<(), RunError> {
        self.0.set_state(s).map_err(RunError::Scheme)
    }
    fn advance(&mut self, steps: usize) -> Result<(), RunError> {
        for _ in 0..steps {
            let r = self.0.step().map_err(RunError::Scheme)?;
            if !self.0.displacement().iter().all(|x| x.is_finite()) {
                return Err(RunError::BlowUp { step: r.n, time: r.t });
            }
        }
        Ok(())
    }
}

/// The energy norm `√(δuᵀ K δu + δvᵀ M δv)` on the first `2n` entries of a
/// [`Stepper::state`] of the problem `stepper` integrates (further entries
/// are not measured).
pub fn energy_norm(stepper: &dyn Stepper) -> impl Fn(&[f64]) -> f64 + Send + Sync {
    let dy = stepper.dynamics();
    let (k, m) = (dy.stiffness.clone(), dy.mass.clone());
    let n = dy.n();
    move |s: &[f64]| {
        let mut w = vec![0.0; n];
        k.mul_vec(&s[..n], &mut w);
        let eu: f64 = w.iter().zip(&s[..n]).map(|(a, b)| a * b).sum();
        m.mul_vec(&s[n..2 * n], &mut w);
        let ev: f64 = w.iter().zip(&s[n..2 * n]).map(|(a, b)| a * b).sum();
        (eu.max(0.0) + ev.max(0.0)).sqrt()
    }
}

/// How to run [`lyapunov`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Benettin {
    /// The perturbation relative to the reference state's norm, `0 < ε < 1e-3`.
    pub perturbation: f64,
    /// Steps between renormalisations (τ = `interval_steps` dt).
    pub interval_steps: usize,
    /// Intervals run first and not counted (the random direction aligning
    /// with the most unstable one).
    pub discard: usize,
    /// Number of intervals `K` counted.
    pub intervals: usize,
    /// Batches for the confidence interval (>= 2, at most `K`).
    pub batches: usize,
    /// The perturbation direction's seed.
    pub seed: u64,
}

impl Benettin {
    /// Checks the ranges, naming the field.
    pub fn validate(&self) -> Result<(), RunError> {
        if !(self.perturbation > 0.0 && self.perturbation < 1e-3) {
            return Err(RunError::Invalid { field: "perturbation", value: self.perturbation, allowed: "0 < perturbation < 1e-3 (relative)" });
        }
        if self.interval_steps == 0 {
            return Err(RunError::Invalid { field: "interval_steps", value: 0.0, allowed: ">= 1" });
        }
        if self.batches < 2 || self.intervals < self.batches {
            return Err(RunError::Invalid { field: "batches", value: self.batches as f64, allowed: "2 <= batches <= intervals" });
        }
        Ok(())
    }
}

/// What [`lyapunov`] measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Lyapunov {
    /// `λ_max` (per unit time of the flow).
    pub lambda: f64,
    /// Its 95 % batch-means interval.
    pub ci: Interval,
    /// The interval τ (time).
    pub tau: f64,
    /// The log growth `g_k` of every interval (the discarded ones first).
    pub growths: Vec<f64>,
    /// The perturbation's size `d₀` in the norm.
    pub d0: f64,
}

/// The largest Lyapunov exponent of `a` by Benettin's twin runs: `b` is the
/// twin (same system at the same time level — a forced system's phase —, any
/// state: it is overwritten), `norm` measures a
/// state difference. `a` starts from its current state (run a transient
/// first). Errors: a bad [`Benettin`], a reference state of zero norm, twins
/// that merge exactly (`d_k = 0`) or separate to a non-finite distance.
pub fn lyapunov<A: Flow + ?Sized, B: Flow + ?Sized>(a: &mut A, b: &mut B, norm: &dyn Fn(&[f64]) -> f64, cfg: &Benettin) -> Result<Lyapunov, RunError> {
    cfg.validate()?;
    let xa = a.state()?;
    let scale = norm(&xa);
    if !(scale > 0.0 && scale.is_finite()) {
        return Err(RunError::Invalid { field: "state", value: scale, allowed: "a reference state of finite, nonzero norm (run a transient first)" });
    }
    let d0 = cfg.perturbation * scale;
    let mut rng = SplitMix64::new(cfg.seed);
    let mut dir: Vec<f64> = xa.iter().map(|_| 2.0 * rng.next_f64() - 1.0).collect();
    let nd = norm(&dir);
    if !(nd > 0.0) {
        return Err(RunError::Invalid { field: "state", value: nd, allowed: "a norm that measures the perturbation's direction" });
    }
    dir.iter_mut().for_each(|d| *d *= d0 / nd);
    let mut xb: Vec<f64> = xa.iter().zip(&dir).map(|(x, d)| x + d).collect();
    b.set_state(&xb)?;
    let tau = cfg.interval_steps as f64 * a.dt();
    let mut growths = Vec::with_capacity(cfg.discard + cfg.intervals);
    let mut delta = vec![0.0; xa.len()];
    for _ in 0..cfg.discard + cfg.intervals {
        a.advance(cfg.interval_steps)?;
        b.advance(cfg.interval_steps)?;
        let xa = a.state()?;
        xb = b.state()?;
        delta.iter_mut().zip(xb.iter().zip(&xa)).for_each(|(d, (y, x))| *d = y - x);
        let d = norm(&delta);
        if d == 0.0 {
            return Err(RunError::Invalid {
                field: "separation",
                value: d,
                allowed: "> 0: the twins merged exactly (a perturbation lost in round-off, below about 1e-15 relative, or a state every neighbour collapses onto)",
            });
        }
        if !d.is_finite() {
            return Err(RunError::Invalid { field: "separation", value: d, allowed: "finite (the twin blew up)" });
        }
        growths.push((d / d0).ln());
        let r = d0 / d;
        xb.iter_mut().zip(xa.iter().zip(&delta)).for_each(|(y, (x, dl))| *y = x + dl * r);
        b.set_state(&xb)?;
    }
    let rates: Vec<f64> = growths[cfg.discard..].iter().map(|g| g / tau).collect();
    let ci = batch_means(&rates, cfg.batches, 0.95).expect("validated: 2 <= batches <= intervals");
    let lambda = rates.iter().sum::<f64>() / rates.len() as f64;
    Ok(Lyapunov { lambda, ci, tau, growths, d0 })
}

/// The separation `‖b − a‖` of two runs without renormalisation, every
/// `every` steps for `samples` samples (the twin-run divergence).
pub fn separation<A: Flow + ?Sized, B: Flow + ?Sized>(a: &mut A, b: &mut B, norm: &dyn Fn(&[f64]) -> f64, every: usize, samples: usize) -> Result<Vec<f64>, RunError> {
    let mut out = Vec::with_capacity(samples);
    for _ in 0..samples {
        a.advance(every)?;
        b.advance(every)?;
        let (xa, xb) = (a.state()?, b.state()?);
        let d: Vec<f64> = xb.iter().zip(&xa).map(|(y, x)| y - x).collect();
        out.push(norm(&d));
    }
    Ok(out)
}

/// The predictability horizon: the time for a relative round-off
/// `roundoff` of a state of size `scale` to grow to `tolerance` at the rate
/// `λ`, `ln(tolerance / (roundoff · scale)) / λ` (∞ for λ <= 0; 0 when the
/// round-off is already beyond the tolerance).
pub fn predictability_horizon(lambda: f64, scale: f64, roundoff: f64, tolerance: f64) -> f64 {
    if !(lambda > 0.0) {
        return f64::INFINITY;
    }
    (tolerance / (roundoff * scale)).ln().max(0.0) / lambda
}
