//! The energy-growth monitor: the discrete energy against its budget.
//!
//! A scheme's energy identity (docs/theory.md §7) reads
//! `E_n − E_ref = W_f + W_c − D`: the work of the time-dependent loads
//! (which is also how support motion enters: the beam's support is a load
//! in the moving frame), the work of the contact forces, and the energy the
//! damping dissipates. The **budget** is what the energy would be if
//! contact did no work:
//!
//! ```text
//! B_n = E_ref + W_f − D                      (closed budget)
//! ```
//!
//! with `W_f` and `D` as the scheme accumulates them
//! ([`Stepper::work`](signorini_schemes::Stepper::work),
//! [`Stepper::dissipation`](signorini_schemes::Stepper::dissipation)) and
//! `E_ref` the first energy the scheme reports (`E⁰`, or `E^{1/2}` for the
//! two-step schemes, whose work starts there). A scheme that does not track
//! its work (Moreau–Jean, the reduced schemes, Nitsche) gets an **open
//! budget**: `B_n = E_ref + Σ_k |½ (F̃_k + F̃_{k+1})ᵀ (U^{k+1} − U^k)|`, the
//! runner's own trapezoidal load work step by step in absolute value (`F̃`
//! the time-dependent part of the load; the steady load is in `E`), and no
//! dissipation — an upper bound of what the energy may reach.
//!
//! The monitor records the largest `E_n / B_n` and the first level at which
//! it exceeds the factor (strictly). A budget at or below
//! `1e-12 ×` the run's energy scale (a negative energy from a load
//! potential) is taken as that floor, so the ratio stays finite. No IO: the
//! CLI and Python say it.

/// The first level at which `E / budget` exceeded the factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyExceeded {
    /// The time level.
    pub step: usize,
    /// The energy's time (`t_n`, or `t_{n−1/2}` for the two-step schemes).
    pub time: f64,
    /// `E / budget` there.
    pub ratio: f64,
    /// The energy.
    pub energy: f64,
    /// The budget.
    pub budget: f64,
}

/// What the monitor found over a run (in [`RunSummary::energy`](crate::RunSummary::energy)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyGrowth {
    /// The factor (`[output] energy_warn`, default 2).
    pub factor: f64,
    /// The largest `E / budget` over the levels (1 for a run whose energy
    /// never rose above its budget and started there).
    pub max_ratio: f64,
    /// The energy's time at the largest ratio.
    pub max_ratio_time: f64,
    /// The first level at which the ratio exceeded the factor, if any.
    pub exceeded: Option<EnergyExceeded>,
    /// Whether the budget is the scheme's closed identity (`true`) or the
    /// open one (`E_ref` + Σ|load work|; module docs).
    pub closed: bool,
}

/// The monitor itself (the runner feeds it).
#[derive(Clone, Debug)]
pub struct EnergyMonitor {
    floor: f64,
    state: EnergyGrowth,
    seen: bool,
}

/// Whether `factor` is a usable factor: finite and > 1.
pub fn check_factor(factor: f64) -> bool {
    factor > 1.0 && factor.is_finite()
}

impl EnergyMonitor {
    /// A monitor for `factor` (> 1, finite: [`check_factor`]); `closed`:
    /// whether the budget is the scheme's closed identity.
    pub fn new(factor: f64, closed: bool) -> Self {
        Self { floor: f64::MIN_POSITIVE, state: EnergyGrowth { factor, max_ratio: f64::NEG_INFINITY, max_ratio_time: 0.0, exceeded: None, closed }, seen: false }
    }

    /// Whether the budget is the scheme's closed identity.
    pub fn closed(&self) -> bool {
        self.state.closed
    }

    /// Floors the budget at `floor` (a value that is not finite and > 0
    /// leaves the smallest positive number).
    pub fn set_floor(&mut self, floor: f64) {
        self.floor = if floor > 0.0 && floor.is_finite() { floor } else { f64::MIN_POSITIVE };
    }

    /// One level: its step, the energy's time, the energy and the budget.
    /// Returns the ratio.
    pub fn observe(&mut self, step: usize, time: f64, energy: f64, budget: f64) -> f64 {
        let ratio = energy / budget.max(self.floor);
        if !self.seen || ratio > self.state.max_ratio {
            self.state.max_ratio = ratio;
            self.state.max_ratio_time = time;
            self.seen = true;
        }
        if self.state.exceeded.is_none() && ratio > self.state.factor {
            self.state.exceeded = Some(EnergyExceeded { step, time, ratio, energy, budget });
        }
        ratio
    }

    /// What it found (`None` if it saw no energy).
    pub fn result(&self) -> Option<EnergyGrowth> {
        self.seen.then_some(self.state)
    }
}
