//! Event-driven integration with impacts: the exact flow between events
//! ([`ModalFlow`]), each event located without a miss
//! ([`ModalFlow::first_crossing`]), Newton's impact law at each.
//!
//! At an impact of contact `i` (dof `c`, restitution `e_i`, the contact
//! dof massive) the velocity jumps along `M⁻¹ e_c` by the impulse
//! `p = −(1 + e_i) v_c⁻ / (M⁻¹)_cc`, so that `v_c⁺ = −e_i v_c⁻` and the
//! kinetic energy drops by `(1 − e_i²)/2 · (v_c⁻)² / (M⁻¹)_cc` (the
//! effective mass of the contact dof is `1/(M⁻¹)_cc`). `M⁻¹ = Φ Φᵀ` from the
//! M-orthonormal modes.
//!
//! *Not yet here*: `e = 0` (the held phase that follows) and accumulating
//! impacts are refused with [`EventsError::HeldPhase`]; simultaneous impacts
//! of several contacts are resolved one at a time.

use crate::flow::{Bound, EventsError, ModalFlow};
use signorini_schemes::Dynamics;

/// What happened at an event (`events.csv`'s `kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventKind {
    /// An impact (Newton's law).
    Impact,
}

/// One event of an [`EventDriven`] run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventRecord {
    /// Its time.
    pub t: f64,
    /// What happened.
    pub kind: EventKind,
    /// The contact (its index in `Dynamics::contacts`).
    pub contact: usize,
    /// The contact dof's velocity before.
    pub velocity_before: f64,
    /// And after.
    pub velocity_after: f64,
    /// The impulse (the contact force's integral over the instant).
    pub impulse: f64,
}

struct Site {
    dof: usize,
    lo: f64,
    hi: f64,
    restitution: f64,
    /// `M⁻¹ e_c`.
    minv_col: Vec<f64>,
}

/// An event-driven run of a linear structure with unilateral contacts at
/// massive dofs, each with a restitution in (0, 1].
pub struct EventDriven {
    flow: ModalFlow,
    sites: Vec<Site>,
    t: f64,
    q: Vec<f64>,
    v: Vec<f64>,
    events: Vec<EventRecord>,
}

impl EventDriven {
    /// Starts at `(q0, v0)` at time `t0`, inside every contact's bounds;
    /// a contact's restitution is its own (`Contact::restitution`) or `e`.
    pub fn new(dy: &Dynamics, t0: f64, q0: &[f64], v0: &[f64], e: f64) -> Result<Self, EventsError> {
        let flow = ModalFlow::new(dy)?;
        let mut sites = Vec::new();
        for (i, c) in dy.contacts.iter().enumerate() {
            let restitution = c.restitution.unwrap_or(e);
            if !(restitution > 0.0 && restitution <= 1.0) {
                return Err(EventsError::HeldPhase { contact: i, restitution });
            }
            if c.massless {
                return Err(EventsError::MassNotDefinite);
            }
            sites.push(Site { dof: c.dof, lo: c.bounds.lo, hi: c.bounds.hi, restitution, minv_col: flow.minv_column(c.dof) });
        }
        Ok(Self { flow, sites, t: t0, q: q0.to_vec(), v: v0.to_vec(), events: Vec::new() })
    }

    /// Runs to `t_end` exactly; more than `max_events` events on the way
    /// stop it with [`EventsError::TooManyEvents`] (the state is then the
    /// one after the last event taken).
    pub fn run_until(&mut self, t_end: f64, max_events: usize) -> Result<(), EventsError> {
        let mut taken = 0;
        while self.next_event(t_end)?.is_some() {
            taken += 1;
            if taken > max_events {
                return Err(EventsError::TooManyEvents { t: self.t, events: taken });
            }
        }
        Ok(())
    }

    /// Advances to the next event, applies it and returns it, or to `t_end`
    /// if none comes before (then `None`).
    pub fn next_event(&mut self, t_end: f64) -> Result<Option<EventRecord>, EventsError> {
        let horizon = t_end - self.t;
        if horizon <= 0.0 {
            return Ok(None);
        }
        let mut first: Option<(usize, crate::flow::Event)> = None;
        for (i, s) in self.sites.iter().enumerate() {
            let until = first.as_ref().map_or(horizon, |f| f.1.t - self.t);
            if let Some(ev) = self.flow.first_crossing(self.t, &self.q, &self.v, s.dof, s.lo, s.hi, until)? {
                if first.as_ref().is_none_or(|f| ev.t < f.1.t) {
                    first = Some((i, ev));
                }
            }
        }
        let Some((i, ev)) = first else {
            let (mut q, mut v) = (vec![0.0; self.q.len()], vec![0.0; self.v.len()]);
            self.flow.advance(self.t, &self.q, &self.v, horizon, &mut q, &mut v);
            (self.t, self.q, self.v) = (t_end, q, v);
            return Ok(None);
        };
        let s = &self.sites[i];
        let mut q = ev.q;
        let mut v = ev.v;
        // On the bound exactly (the event is within round-off of it).
        q[s.dof] = if ev.bound == Bound::Lower { s.lo } else { s.hi };
        let before = v[s.dof];
        let w = s.minv_col[s.dof];
        let impulse = -(1.0 + s.restitution) * before / w;
        v.iter_mut().zip(&s.minv_col).for_each(|(x, m)| *x += impulse * m);
        // v_c⁺ = −e v_c⁻ exactly.
        v[s.dof] = -s.restitution * before;
        let rec = EventRecord { t: ev.t, kind: EventKind::Impact, contact: i, velocity_before: before, velocity_after: v[s.dof], impulse };
        self.events.push(rec);
        (self.t, self.q, self.v) = (ev.t, q, v);
        Ok(Some(rec))
    }

    /// The time and state `(t, q, v)`.
    pub fn state(&self) -> (f64, &[f64], &[f64]) {
        (self.t, &self.q, &self.v)
    }

    /// The events so far.
    pub fn events(&self) -> &[EventRecord] {
        &self.events
    }
}
