//! The time-dependent load of a stepper, shared by the one-step schemes,
//! Paoli–Schatzman and Moreau–Jean: one [`Sampler`] per forcing term (its
//! values at the levels, or its exact means over the steps) and the
//! application `out += Σ_j (scale · s_j) shape_j`, term by term in the
//! order of `Dynamics::forcing` (the arithmetic each stepper did alone).
//! The lockstep kernel keeps its own lanes-innermost loop.

use crate::{Dynamics, Forcing, Sampler};

/// One sampler per forcing term.
pub(crate) struct Loads {
    samplers: Vec<Sampler>,
}

impl Loads {
    /// The values `s_j(n dt)`, n = 0, 1, … (the one-step schemes).
    pub(crate) fn values(dy: &Dynamics, dt: f64) -> Self {
        Self { samplers: dy.forcing.iter().map(|f| Sampler::values(&f.time, 0.0, dt)).collect() }
    }

    /// The exact means of `s_j` over `[n dt, (n+1) dt]`, n = 0, 1, …
    /// (Paoli–Schatzman, Moreau–Jean).
    pub(crate) fn means(dy: &Dynamics, dt: f64) -> Self {
        Self { samplers: dy.forcing.iter().map(|f| Sampler::means(&f.time, 0.0, dt)).collect() }
    }

    /// No loads (before a stepper sets its own).
    pub(crate) fn none() -> Self {
        Self { samplers: Vec::new() }
    }

    /// Each term's next sample into `out` (one per term).
    pub(crate) fn next_into(&mut self, out: &mut [f64]) {
        for (s, sp) in out.iter_mut().zip(self.samplers.iter_mut()) {
            *s = sp.next_value();
        }
    }
}

/// `out += Σ_j (scale · values_j) shape_j`, term by term.
pub(crate) fn add_terms(out: &mut [f64], forcing: &[Forcing], scale: f64, values: &[f64]) {
    for (f, &s) in forcing.iter().zip(values) {
        let w = scale * s;
        out.iter_mut().zip(&f.shape).for_each(|(b, g)| *b += w * g);
    }
}
