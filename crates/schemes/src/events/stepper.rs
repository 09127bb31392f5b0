//! The registry's `event-driven` scheme: an [`EventDriven`] run sampled at
//! the levels `n dt` of the runner, so that every output of `signorini run`
//! (series, snapshots, norms, energies) reads the exact semi-discrete
//! solution. `dt` is only the sampling step: no error depends on it. The
//! level `n` is read at `n dt`, the last one at the horizon itself
//! ([`Stepper::set_end`]); an event located at a level's time is taken
//! before that level is read (its row shows the state after the event).
//!
//! At each level the contact force reported is the mean force over the
//! step, `λ = −(Σ impulses + ∫ r)/dt` with the held force's integral in
//! closed form — the same quantity a time-stepping scheme's `λ` estimates;
//! a contact is active in a step if it is held at its end or took an
//! impulse during it.

use super::driven::{EventDriven, MAX_EVENTS};
use super::record::EventRecord;
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::Active;

/// An event-driven run as a [`Stepper`] (module docs).
pub struct EventStepper {
    label: String,
    dt: f64,
    n: usize,
    dy: Dynamics,
    run: EventDriven,
    u: Vec<f64>,
    v: Vec<f64>,
    lams: Vec<f64>,
    acts: Vec<Active>,
    /// The last level and its time ([`Stepper::set_end`]).
    end: Option<(usize, f64)>,
}

impl EventStepper {
    /// Starts at `init` at `t = 0`, sampled every `dt`; `e` is the
    /// restitution of every contact without its own.
    pub fn new(label: String, dy: Dynamics, e: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        let n = dy.n();
        for (what, len) in [("initial displacement", init.u.len()), ("initial velocity", init.v.len())] {
            if len != n {
                return Err(SchemeError::Size { what, got: len, expected: n });
            }
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(SchemeError::Invalid { field: "dt", value: dt, allowed: "> 0 and finite" });
        }
        let mut run = EventDriven::new(&dy, 0.0, &init.u, &init.v, e)?;
        run.take_events_at_pause(true);
        let k = dy.contacts.len();
        let (_, u, v) = run.state();
        let mut s = Self { label, dt, n: 0, dy, run, u, v, lams: vec![0.0; k], acts: vec![Active::None; k], end: None };
        s.read();
        // The impulses at t = 0 (an approaching contact on its bound) are
        // not part of the first step's mean force.
        s.run.take_impulses();
        Ok(s)
    }

    fn read(&mut self) {
        self.run.state_into(&mut self.u, &mut self.v);
        self.acts.iter_mut().for_each(|a| *a = Active::None);
        for (c, upper) in self.run.held_iter() {
            self.acts[c] = if upper { Active::Upper } else { Active::Lower };
        }
    }

    /// At most `max_events` events in the run (default [`MAX_EVENTS`]):
    /// beyond, a step stops with [`super::EventsError::TooManyEvents`].
    pub fn with_max_events(mut self, max_events: usize) -> Self {
        self.run.set_max_events(max_events);
        self
    }

    /// The time of level `n`: `n dt`, the horizon at the last level.
    fn level_time(&self, n: usize) -> f64 {
        match self.end {
            Some((last, t_end)) if last == n => t_end,
            _ => n as f64 * self.dt,
        }
    }

    /// The events so far.
    pub fn events(&self) -> &[EventRecord] {
        self.run.events()
    }

    /// The underlying run.
    pub fn run(&self) -> &EventDriven {
        &self.run
    }
}

impl Stepper for EventStepper {
    stepper_accessors!();

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let t_next = self.level_time(self.n + 1);
        let result = self.run.advance_to(t_next);
        if let Err(super::EventsError::Interrupted { .. }) = result {
            // The level and its state stay; the run resumes inside the step.
            return Err(SchemeError::Interrupted { step: self.n, time: self.time() });
        }
        self.read();
        result?;
        self.n += 1;
        let t = self.time();
        // The impulses into `lams`, then the mean forces. A contact that
        // took an impulse in the step is active in it, as a time stepper's
        // contact is in the step that projects it (the vibro-impact
        // analysis counts an impact per run of active steps).
        self.run.take_impulses_into(&mut self.lams);
        for (l, a) in self.lams.iter_mut().zip(self.acts.iter_mut()) {
            if *a == Active::None && *l != 0.0 {
                *a = if *l > 0.0 { Active::Lower } else { Active::Upper };
            }
            *l = if *l == 0.0 { 0.0 } else { -*l / self.dt };
        }
        if !self.u.iter().chain(&self.v).all(|x| x.is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        Ok(StepReport { n: self.n, t, lambda: Some((t, self.lams[0])), active: self.acts[0] })
    }

    fn time(&self) -> f64 {
        self.level_time(self.n)
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        Some((self.time(), self.dy.energy(&self.u, &self.v)))
    }

    fn state(&self) -> Option<Vec<f64>> {
        Some(self.u.iter().chain(&self.v).copied().collect())
    }

    fn set_state(&mut self, s: &[f64]) -> Result<(), SchemeError> {
        let n = self.u.len();
        crate::check_state_len(s, 2 * n)?;
        self.run.reset(&s[..n], &s[n..])?;
        self.run.take_impulses();
        self.read();
        Ok(())
    }

    fn events(&self) -> Option<&[EventRecord]> {
        Some(self.run.events())
    }

    fn into_event_run(self: Box<Self>) -> Option<Box<dyn std::any::Any>> {
        Some(Box::new(self.run))
    }

    fn set_interrupt(&mut self, poll: Option<crate::Interrupt>) {
        self.run.set_interrupt(poll);
    }

    fn set_end(&mut self, n: usize, t_end: f64) {
        self.end = Some((n, t_end));
    }
}

// ---- The registry's row of this file: event-driven.

use crate::family::{check, Capabilities, Family, Group, Node, Param, Preset};

/// The exact event-driven reference, restitution `e ∈ [0, 1]` (default 0),
/// at most `max_events` events (default 10⁷).
pub(crate) static EVENT_DRIVEN: Family = Family {
    name: "event-driven",
    about: "exact event-driven reference: closed-form flow between events, every event located, Newton's law with restitution E (docs/theory.md §9)",
    params: &[
        Param { name: "e", symbol: "e", syntax: "E", allowed: "∈ [0, 1]", default: Some(0.0) },
        Param { name: "max_events", symbol: "max_events", syntax: "MAX_EVENTS", allowed: "an integer in [1, 1e12]", default: Some(MAX_EVENTS as f64) },
    ],
    presets: &[Preset { name: "event-driven", args: &[0.0, MAX_EVENTS as f64], group: Group::Reference, rank: 0 }],
    validate: |a| {
        check("e", a[0], (0.0..=1.0).contains(&a[0]), "[0, 1]")?;
        check("max_events", a[1], a[1] >= 1.0 && a[1] <= 1e12 && a[1].fract() == 0.0, "an integer in [1, 1e12]")
    },
    capabilities: |_| Capabilities {
        explicit: false,
        node: Node::Any,
        diagonal_mass: false,
        damping: true,
        forcing: true,
        restitution: true,
        stiffness: false,
        several_contacts: true,
        beam: true,
        lockstep: false,
    },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(EventStepper::new(s.to_string(), dy, s.args()[0], dt, init)?.with_max_events(s.args()[1] as usize))),
};
