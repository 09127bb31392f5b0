//! Time profiles `s(t)` of separable loads `F(t) = shape · s(t)`: their
//! values and exact means over a step (docs/theory.md §4.3).

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
}

impl TimeProfile {
    /// `s(t)`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            &TimeProfile::Sine { amplitude, omega } => amplitude * (omega * t).sin(),
        }
    }

    /// `max_t |s(t)|`.
    pub fn max_abs(&self) -> f64 {
        match self {
            TimeProfile::Sine { amplitude, .. } => amplitude.abs(),
        }
    }

    /// The exact mean `1/(t1 - t0) ∫ s` over `[t0, t1]` (docs/theory.md §4.3's `f^n`),
    /// written without cancellation: `A sin(ω t_mid) sin(ω δ/2) / (ω δ/2)`.
    pub fn mean(&self, t0: f64, t1: f64) -> f64 {
        match self {
            &TimeProfile::Sine { amplitude, omega } => {
                let half = 0.5 * omega * (t1 - t0);
                let sinc = if half.abs() < 1e-8 { 1.0 - half * half / 6.0 } else { half.sin() / half };
                amplitude * (omega * 0.5 * (t0 + t1)).sin() * sinc
            }
        }
    }
}

