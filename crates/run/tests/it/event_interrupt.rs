//! An interrupt stops an event-driven run inside an output step (the event
//! search polls the run's cancel token every 256 of its steps), and leaves
//! complete rows and a whole state.
//!
//! The problem: a free mass (`k = 0`) bouncing elastically (`e = 1`)
//! between walls at `±g`, `g = 1e-3`, from `x = 0` at speed 1: the sawtooth
//! of period `4g`, an impact every `2g` — 500 impacts per output step of
//! `dt = 1`, at `t = g (1 + 2k)`, and `x(1) = 0`, `x'(1) = 1` (250 whole
//! periods). No test here depends on timing: the interrupt comes from a
//! poll that counts its calls.

use signorini_contact::Active;
use signorini_fem::SymBand;
use signorini_run::{run, Cancel, Observer, RunConfig, RunError, SeriesColumns, SeriesWriter};
use signorini_schemes::events::{EventKind, EventStepper};
use signorini_schemes::{Bounds, Contact, Dynamics, Initial, Interrupt, SchemeError, StepReport, Stepper};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

const GAP: f64 = 1e-3;

fn bouncing() -> EventStepper {
    let (m, k) = (SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[0.0]));
    let dy = Dynamics::new(m, k, vec![0.0], vec![Contact::new(0, Bounds { lo: -GAP, hi: GAP }, false)]);
    EventStepper::new("event-driven(1)".into(), dy, 1.0, 1.0, &Initial { u: vec![0.0], v: vec![1.0] }).expect("a valid problem")
}

/// The impacts of `[0, t]` in closed form: those at `g (1 + 2k) <= t`.
fn impacts_by(t: f64) -> usize {
    ((t / GAP + 1.0) / 2.0).floor() as usize
}

/// A poll that says "stop" from its `from`-th call on (1-based), counting its calls.
fn poll_from(from: usize) -> (Interrupt, Arc<AtomicUsize>) {
    let calls = Arc::new(AtomicUsize::new(0));
    let c = Arc::clone(&calls);
    (Arc::new(move || c.fetch_add(1, Ordering::Relaxed) + 1 >= from), calls)
}

/// The stepper alone: a poll that stops from its second call stops the
/// first step after at most 256 search steps — fewer events than the
/// step's 500 — at level 0 with level 0's state; once the poll is removed,
/// the same step ends where an uninterrupted run does (the closed form).
#[test]
fn a_poll_stops_the_step_inside_and_the_run_resumes_whole() {
    assert_eq!(impacts_by(1.0), 500);
    let mut s = bouncing();
    let (poll, calls) = poll_from(2);
    s.set_interrupt(Some(poll));
    let err = s.step().unwrap_err();
    assert_eq!(err, SchemeError::Interrupted { step: 0, time: 0.0 });
    assert_eq!(calls.load(Ordering::Relaxed), 2, "polled at search step 0 and 256");
    // Every event costs a search step: at most 256 before the second poll.
    let done = s.events().len();
    assert!(done > 0 && done <= 256 && done < impacts_by(1.0), "{done} events before the interrupt");
    let last = s.events()[done - 1].t;
    assert!(last < 1.0, "the events so far lie inside the first step: {last}");
    // Level 0 and its state are kept.
    assert_eq!((s.level(), s.time(), s.displacement()), (0, 0.0, &[0.0][..]));
    // A pre-set poll (true at once) stops the resumed step too, with no event.
    let (stop, _) = poll_from(1);
    s.set_interrupt(Some(stop));
    assert!(matches!(s.step(), Err(SchemeError::Interrupted { step: 0, .. })));
    assert_eq!(s.events().len(), done);
    // Resumed without the poll: the exact sawtooth at t = 1.
    s.set_interrupt(None);
    s.step().expect("the step resumes");
    assert_eq!(s.level(), 1);
    assert!(s.displacement()[0].abs() <= 1e-9, "x(1) = {}", s.displacement()[0]);
    assert_eq!(s.events().len(), impacts_by(1.0));
    for (k, e) in s.events().iter().enumerate() {
        assert_eq!(e.kind, EventKind::Impact);
        assert!((e.t - GAP * (1.0 + 2.0 * k as f64)).abs() <= 1e-12, "impact {k} at {}", e.t);
    }
}

/// The stepper under the runner, cancelling the run's token at the second
/// poll of the second step.
struct CancelInside {
    inner: EventStepper,
    token: Cancel,
    polls: Arc<AtomicUsize>,
    armed: Arc<AtomicBool>,
}

impl Stepper for CancelInside {
    fn label(&self) -> String {
        self.inner.label()
    }
    fn dt(&self) -> f64 {
        self.inner.dt()
    }
    fn level(&self) -> usize {
        self.inner.level()
    }
    fn displacement(&self) -> &[f64] {
        self.inner.displacement()
    }
    fn dynamics(&self) -> &Dynamics {
        self.inner.dynamics()
    }
    fn step(&mut self) -> Result<StepReport, SchemeError> {
        self.armed.store(self.inner.level() == 1, Ordering::Relaxed);
        self.polls.store(0, Ordering::Relaxed);
        self.inner.step()
    }
    fn contact_forces(&self) -> &[f64] {
        self.inner.contact_forces()
    }
    fn contact_status(&self) -> &[Active] {
        self.inner.contact_status()
    }
    fn energy(&mut self) -> Option<(f64, f64)> {
        self.inner.energy()
    }
    fn set_interrupt(&mut self, poll: Option<Interrupt>) {
        // The runner's poll, wrapped: cancels the token at the second call
        // of an armed step, then asks the runner's poll.
        let poll = poll.map(|runner| {
            let (token, polls, armed) = (self.token.clone(), Arc::clone(&self.polls), Arc::clone(&self.armed));
            Arc::new(move || {
                if armed.load(Ordering::Relaxed) && polls.fetch_add(1, Ordering::Relaxed) + 1 >= 2 {
                    token.cancel();
                }
                runner()
            }) as Interrupt
        });
        self.inner.set_interrupt(poll);
    }
}

/// The runner hands its token to the stepper: cancelled inside step 2, the
/// run stops there with `Interrupted` at level 1 (t = 1), the series holds
/// levels 0 and 1, whole rows, and the events stop well short of step 2's
/// 500; without a token the same run reaches t = 3.
#[test]
fn the_runner_polls_its_token_inside_an_event_driven_step() {
    let token = Cancel::new();
    let mut s = CancelInside { inner: bouncing(), token: token.clone(), polls: Arc::default(), armed: Arc::default() };
    let cfg = RunConfig::new(1.0, 3.0).unwrap().with_interrupt(token.clone());
    let mut buf: Vec<u8> = Vec::new();
    {
        let mut w = SeriesWriter::new(&mut buf, 1, 0, SeriesColumns::default()).unwrap();
        let err = run(&mut s, &[0.0], &cfg, &mut [&mut w as &mut dyn Observer]).unwrap_err();
        assert!(matches!(err, RunError::Interrupted { step: 1, time } if time == 1.0), "{err}");
    }
    assert!(token.is_cancelled());
    let text = String::from_utf8(buf).unwrap();
    assert!(text.ends_with('\n'), "whole rows only");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "the header and levels 0 and 1:\n{text}");
    let width = lines[0].split(',').count();
    for (n, row) in lines[1..].iter().enumerate() {
        let cells: Vec<&str> = row.split(',').collect();
        assert_eq!((cells.len(), cells[0]), (width, n.to_string().as_str()), "row {n}: {row}");
        let x: f64 = cells[2].parse().unwrap();
        assert!(x.abs() <= 1e-9, "x({n}) = {x}: the sawtooth is 0 at whole times");
    }
    let done = s.inner.events().len();
    assert!(done >= impacts_by(1.0) && done < impacts_by(2.0), "{done} events: step 2 cut short");
    // The runner removes its poll when it returns: a second run of the
    // stepper without a token goes on (the cancelled token no longer acts).
    let cfg = RunConfig::new(1.0, 3.0).unwrap();
    let summary = run(&mut s, &[0.0], &cfg, &mut []).expect("runs to the end");
    assert_eq!(summary.steps, 3);
    assert_eq!(s.inner.events().len(), impacts_by(3.0));
}
