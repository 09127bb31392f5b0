//! [`EventDriven::restart`]: a run started again at another state is the
//! run [`EventDriven::new`] makes from that state, bit for bit — its events
//! (times, speeds, impulses), its states at sampled times and its active
//! set — after the restarted run has met other phases (held sets, a
//! chatter to rest, the contact solver's warm start) from another start.
//! The orbits' shooting starts one run again at every map evaluation.

use crate::events_common as common;
use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventsError};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};

/// A chain of `n` unit masses and springs (the last grounded), `C = 0.02 K`.
fn chain(n: usize) -> (SymBand, SymBand, SymBand) {
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        m.set(i, i, 1.0);
        k.set(i, i, if i + 1 < n { 2.0 } else { 1.0 });
        if i > 0 {
            k.set(i, i - 1, -1.0);
        }
    }
    let c = common::rayleigh(&m, &k, 0.0, 0.02);
    (m, k, c)
}

/// Events and states of `run` sampled up to `t_end`, as bits.
fn trace(run: &mut EventDriven, t_end: f64) -> Vec<u64> {
    let mut out = Vec::new();
    for i in 1..=40 {
        run.run_until(t_end * i as f64 / 40.0, 100_000).unwrap();
        let (t, q, v) = run.state();
        out.push(t.to_bits());
        out.extend(q.iter().chain(&v).map(|x| x.to_bits()));
        out.extend(run.held_iter().map(|(c, up)| 2 * c as u64 + up as u64));
        out.push(u64::MAX);
    }
    for e in run.events() {
        out.extend([e.t, e.velocity_before, e.velocity_after, e.impulse].map(f64::to_bits));
        out.extend([e.kind as u64, e.contact as u64]);
    }
    out
}

/// `dy` from `(q, v)` at `t0` by a new run and by a run first taken from
/// `other` to `t_other`, then started again: the same bits.
fn same_as_new(dy: &Dynamics, e: f64, start: (f64, &[f64], &[f64]), other: (f64, &[f64], &[f64], f64), t_end: f64) -> usize {
    let mut fresh = EventDriven::new(dy, start.0, start.1, start.2, e).unwrap();
    let want = trace(&mut fresh, t_end);
    let mut run = EventDriven::new(dy, other.0, other.1, other.2, e).unwrap();
    run.run_until(other.3, 100_000).unwrap();
    assert!(!run.events().is_empty(), "the other start meets events");
    run.restart(start.0, start.1, start.2).unwrap();
    let got = trace(&mut run, t_end);
    assert_eq!(got, want, "a restarted run differs from a new one");
    fresh.events().len()
}

#[test]
fn a_restarted_run_is_a_new_run_bit_for_bit() {
    let n = 4;
    let (m, k, c) = chain(n);
    // Two stops (dof 0 below, dof 3 above), a steady load pressing dof 0
    // onto its stop (e = 0.5 chatters to rest there), a harmonic and a
    // series load.
    let contacts = vec![Contact::new(0, Bounds::obstacle(-0.2), false), Contact::new(3, Bounds { lo: f64::NEG_INFINITY, hi: 0.3 }, false)];
    let series = TimeProfile::series(vec![0.0, 3.0, 7.0], vec![0.0, -0.5, 0.2]).unwrap();
    let dy = Dynamics::new(m, k, vec![-0.6, 0.0, 0.0, 0.0], contacts)
        .with_damping(Some(c))
        .with_forcing(vec![Forcing { shape: vec![1.0, 0.0, 0.0, 0.5], time: TimeProfile::Sine { amplitude: 0.8, omega: 1.7 } }, Forcing { shape: vec![0.0, 1.0, 0.0, 0.0], time: series }]);
    let q0 = [0.0, 0.1, -0.1, 0.0];
    for e in [0.0, 0.5, 1.0] {
        // Plastic impacts hold the contacts; e = 0.5 chatters to rest.
        let events = same_as_new(&dy, e, (0.5, &q0, &[-1.0, 0.0, 0.3, 0.8]), (0.0, &[0.0; 4], &[0.9, -0.5, 0.0, -0.7], 6.0), 12.0);
        assert!(events > 5, "e = {e}: {events} events");
    }
    // After a run with impacts 1e4 times faster (the micro-impact rule
    // compares each impact with the contact's fastest so far).
    let events = same_as_new(&dy, 0.5, (0.5, &q0, &[-1.0, 0.0, 0.3, 0.8]), (0.0, &[0.0; 4], &[-1e4, 0.0, 0.0, 0.0], 0.01), 12.0);
    assert!(events > 5, "{events} events");
}

#[test]
fn a_restart_outside_a_bound_fails_as_new_does_and_the_run_starts_again_after() {
    let (m, k, _) = chain(2);
    let dy = Dynamics::new(m, k, vec![-0.3, 0.0], vec![Contact::new(0, Bounds::obstacle(-0.1), false)]);
    let mut run = EventDriven::new(&dy, 0.0, &[0.0, 0.0], &[-1.0, 0.0], 0.7).unwrap();
    run.run_until(3.0, 1000).unwrap();
    let outside = [-0.5, 0.0];
    let want = match EventDriven::new(&dy, 0.0, &outside, &[0.0; 2], 0.7) {
        Err(e @ EventsError::Outside { .. }) => e.to_string(),
        other => panic!("new: {:?}", other.err()),
    };
    assert_eq!(run.restart(0.0, &outside, &[0.0; 2]).unwrap_err().to_string(), want);
    let mut fresh = EventDriven::new(&dy, 1.0, &[0.05, -0.02], &[-0.4, 0.2], 0.7).unwrap();
    run.restart(1.0, &[0.05, -0.02], &[-0.4, 0.2]).unwrap();
    assert_eq!(trace(&mut run, 9.0), trace(&mut fresh, 9.0));
}
