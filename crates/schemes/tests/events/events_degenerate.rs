//! Degenerate cases a user meets first that no other events test covers
//! (found by a campaign over masses, restitutions, damping, forcing and
//! starts), each against an independent value:
//!
//! - a landing at zero speed *and* zero acceleration (a cubic tangency:
//!   `x'' = sin t` reaching its stop at `t = π`), held until the load lets
//!   go at `2π`, then the closed-form flight;
//! - held phases, releases and accumulations of multi-dof bars (consistent,
//!   lumped, P2) give the same bits whether the run goes to `T` at once,
//!   stops at many sample times, or is stepped by [`EventStepper`] as
//!   `signorini run` steps it;
//! - an elastic (`e = 1`) bar pressed onto its stop keeps its energy over
//!   10⁴ impacts, each one elastic;
//! - a bar between two stops reached at the same instant (an antisymmetric
//!   start) keeps its mirror symmetry through every impact, held phase and
//!   release.
//! - the event limit counts records on both paths (`run_until` and the
//!   stepper), two per instant where two contacts are hit together.

use signorini_fem::{Bar, BarMass, RightEnd, SymBand};
use signorini_schemes::events::{EventDriven, EventKind, EventRecord, EventStepper};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, Initial, Stepper, TimeProfile};
use std::f64::consts::{PI, TAU};
use std::sync::Arc;

fn harmonics(terms: &[(f64, f64, f64)]) -> TimeProfile {
    TimeProfile::Harmonics(Arc::from(terms.iter().map(|&(amplitude, omega, phase)| Harmonic { amplitude, omega, phase }).collect::<Vec<_>>()))
}

/// A free mass `x'' = sin t` above its stop `x >= lo`, from `x = lo + π`,
/// `x' = −2` at `t = 0`: `x = lo + π − t − sin t` reaches the stop at `t = π`
/// with `x' = −1 − cos π = 0` and `x'' = sin π = 0` (the gap is `−(t − π)³/6`
/// there: a cubic tangency, crossing), then is pressed (`sin t < 0`) and held
/// until `2π`, where the load turns; from rest there `x = lo + t − 2π − sin t`,
/// `x' = 1 − cos t >= 0`: it never returns. The search locates the landing
/// within the cube root of round-off of `π` (1e-5) at a speed of 1e-10, so
/// a few impacts of that speed may come first; with `e = 0.5` they
/// accumulate, and with `e = 1` — whose rebounds never shrank (10⁷ events
/// by t = 3.8) — they end too, too low to be told from rest (docs/theory.md
/// §9.3). The release and the state after it are exact.
#[test]
fn a_cubic_tangency_lands_at_zero_speed_and_is_released_where_the_load_turns() {
    for e in [0.0, 0.5, 1.0] {
        for lo in [0.0, 1.0, -3.0] {
            let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[0.0]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(lo), false)])
                .with_forcing(vec![Forcing { shape: vec![1.0], time: harmonics(&[(1.0, 1.0, 0.0)]) }]);
            let mut r = EventDriven::new(&dy, 0.0, &[lo + PI], &[-2.0], e).unwrap();
            let t_end = 10.0;
            r.run_until(t_end, 1000).unwrap_or_else(|err| panic!("e = {e}, lo = {lo}: {err}"));
            let ev = r.events();
            let releases: Vec<&EventRecord> = ev.iter().filter(|x| x.kind == EventKind::Release).collect();
            assert_eq!(releases.len(), 1, "e = {e}, lo = {lo}: {ev:?}");
            assert!((releases[0].t - TAU).abs() <= 1e-12, "e = {e}, lo = {lo}: released at {}", releases[0].t);
            for x in ev.iter().filter(|x| x.kind != EventKind::Release) {
                assert!((x.t - PI).abs() <= 1e-4 && x.velocity_before.abs() <= 1e-8, "e = {e}, lo = {lo}: {x:?}");
            }
            let (t, q, v) = r.state();
            assert_eq!(t, t_end);
            let (xw, vw) = (lo + t_end - TAU - t_end.sin(), 1.0 - t_end.cos());
            assert!((q[0] - xw).abs() <= 1e-12 * (1.0 + lo.abs()) && (v[0] - vw).abs() <= 1e-12, "e = {e}, lo = {lo}: ({}, {}) against ({xw}, {vw})", q[0], v[0]);
        }
    }
}

/// A clamped P1 bar of 4 elements (`L = c = 1`), or P2 of 2, with its stop at
/// node 0 (`u_0 >= 0`), pressed there by `−a sin(1.3 t) − b sin(3.7 t + 0.5)`.
fn bar(mass: BarMass, degree: usize, two: bool, damped: bool) -> Dynamics {
    let elements = if degree == 1 { 4 } else { 2 };
    let bar = Bar::new(1.0, elements, 1.0, RightEnd::Clamped).unwrap().with_degree(degree).unwrap();
    let (m, k) = (bar.mass(mass), bar.stiffness());
    let n = m.n();
    let mut shape = vec![0.0; n];
    shape[0] = -1.0;
    let load = if two { harmonics(&[(0.6, 1.3, 0.0), (0.4, 3.7, 0.5)]) } else { harmonics(&[(0.8, 1.3, 0.0)]) };
    let c = damped.then(|| m.lin_comb(0.05, &k, 0.02));
    Dynamics::new(m, k, vec![0.0; n], vec![Contact::new(0, Bounds::obstacle(0.0), false)]).with_forcing(vec![Forcing { shape, time: load }]).with_damping(c)
}

fn bits(q: &[f64], v: &[f64]) -> Vec<u64> {
    q.iter().chain(v).map(|x| x.to_bits()).collect()
}

fn event_bits(ev: &[EventRecord]) -> Vec<(u64, u64, u64, u64, usize)> {
    ev.iter().map(|e| (e.t.to_bits(), e.velocity_before.to_bits(), e.velocity_after.to_bits(), e.impulse.to_bits(), e.contact)).collect()
}

/// Runs with held phases, releases and accumulations (every mass, one and
/// two harmonics, damped or not, from held starts and from speeds into and
/// out of the stop): the state at `T = 20` and every event are the same
/// bits whether the run goes there at once, stops every 0.37 on the way,
/// or is stepped by the registry's stepper every 0.25 (`advance_to`, as
/// `signorini run` steps it) — a sample reads the phase from its base and
/// never re-bases it (docs/theory.md §9.2). Each case is checked to take
/// releases, and the `e = 0.5` ones accumulations, so that the sampling
/// meets them.
#[test]
fn held_phases_releases_and_accumulations_are_the_same_bits_at_any_sampling() {
    let cases = [
        (BarMass::Std, 1, false, false, 0.5, 0.0),
        (BarMass::Std, 1, true, true, 0.5, -0.3),
        (BarMass::Lumped, 1, true, false, 0.5, 0.3),
        (BarMass::Std, 2, true, true, 0.5, 0.0),
        (BarMass::Std, 1, true, false, 0.0, -0.3),
        (BarMass::Lumped, 1, false, true, 0.0, 0.3),
    ];
    for (mass, degree, two, damped, e, v_c) in cases {
        let name = format!("{mass:?} P{degree} two = {two} damped = {damped} e = {e} v_c = {v_c}");
        let dy = bar(mass, degree, two, damped);
        let n = dy.n();
        let q0 = vec![0.0; n];
        let mut v0 = vec![0.0; n];
        v0[0] = v_c;
        let t_end = 20.0;
        let mut direct = EventDriven::new(&dy, 0.0, &q0, &v0, e).unwrap();
        direct.run_until(t_end, 100_000).unwrap_or_else(|err| panic!("{name}: {err}"));
        let (_, q, v) = direct.state();
        let ev = direct.events().to_vec();
        assert!(ev.iter().any(|x| x.kind == EventKind::Release), "{name}: no release");
        if e > 0.0 {
            assert!(ev.iter().any(|x| x.kind == EventKind::Accumulation), "{name}: no accumulation");
        }
        let mut sampled = EventDriven::new(&dy, 0.0, &q0, &v0, e).unwrap();
        let mut k = 1;
        loop {
            let t = (k as f64 * 0.37).min(t_end);
            sampled.run_until(t, 100_000).unwrap_or_else(|err| panic!("{name}, sampled: {err}"));
            assert_eq!(sampled.time(), t, "{name}");
            if t == t_end {
                break;
            }
            k += 1;
        }
        let (_, qs, vs) = sampled.state();
        assert!(bits(&q, &v) == bits(&qs, &vs), "{name}: sampled every 0.37 {qs:?} {vs:?} against {q:?} {v:?}");
        assert!(event_bits(&ev) == event_bits(sampled.events()), "{name}: the events differ sampled every 0.37 ({} against {})", sampled.events().len(), ev.len());
        let mut stepper = EventStepper::new("event-driven".into(), dy.clone(), e, 0.25, &Initial { u: q0.clone(), v: v0.clone() }).unwrap();
        for _ in 0..80 {
            stepper.step().unwrap_or_else(|err| panic!("{name}, stepped: {err}"));
        }
        assert_eq!(stepper.time(), t_end, "{name}");
        assert!(bits(&q, &v) == stepper.state().unwrap().iter().map(|x| x.to_bits()).collect::<Vec<_>>(), "{name}: stepped every 0.25");
        assert!(event_bits(&ev) == event_bits(stepper.events()), "{name}: the events differ stepped every 0.25");
    }
}

/// `½ vᵀ M v + ½ qᵀ K q − fᵀ q`, by the fem crate's band products.
fn energy(m: &SymBand, k: &SymBand, f: &[f64], q: &[f64], v: &[f64]) -> f64 {
    let n = q.len();
    let (mut mv, mut kq) = (vec![0.0; n], vec![0.0; n]);
    m.mul_vec(v, &mut mv);
    k.mul_vec(q, &mut kq);
    (0..n).map(|i| 0.5 * v[i] * mv[i] + 0.5 * q[i] * kq[i] - f[i] * q[i]).sum()
}

/// Elastic impacts (`e = 1`) of the clamped consistent-mass P1 and P2 bars
/// pressed onto their stop by a steady load at the contact node, from a
/// speed into the stop, over `t = 10³`: more than 10⁴ impacts, each one
/// elastic (`v⁺ = −v⁻`), and the energy `½ vᵀMv + ½ qᵀKq − fᵀq` kept to
/// a relative 1e-10 (measured: 5.6e-12 and 1.7e-11).
#[test]
fn an_elastic_bar_pressed_on_its_stop_keeps_its_energy_over_ten_thousand_impacts() {
    for degree in [1, 2] {
        let elements = if degree == 1 { 4 } else { 2 };
        let bar = Bar::new(1.0, elements, 1.0, RightEnd::Clamped).unwrap().with_degree(degree).unwrap();
        let (m, k) = (bar.mass(BarMass::Std), bar.stiffness());
        let n = m.n();
        let mut f = vec![0.0; n];
        f[0] = -0.5;
        let dy = Dynamics::new(m.clone(), k.clone(), f.clone(), vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
        let (q0, mut v0) = (vec![0.0; n], vec![0.0; n]);
        v0[0] = -0.3;
        let e0 = energy(&m, &k, &f, &q0, &v0);
        let mut r = EventDriven::new(&dy, 0.0, &q0, &v0, 1.0).unwrap();
        r.run_until(1000.0, 1_000_000).unwrap();
        let ev = r.events();
        assert!(ev.len() > 10_000 && ev.iter().all(|x| x.kind == EventKind::Impact && x.velocity_after == -x.velocity_before), "P{degree}: {} events", ev.len());
        let (_, q, v) = r.state();
        let drift = energy(&m, &k, &f, &q, &v) - e0;
        assert!(drift.abs() <= 1e-10 * e0, "P{degree}: the energy {e0} drifted by {drift:e} over {} impacts", ev.len());
    }
}

/// A free P1 bar of 3 elements between a stop below its left end
/// (`u_0 >= −0.05`) and one above its right end (`u_3 <= 0.05`), stretched
/// from rest by `v = (−0.5, −1/6, 1/6, 0.5)` and pulled outward by a steady
/// load at both ends (`∓0.2`): both ends reach their stops at the same
/// instant, every time. The motion is mirror-antisymmetric (`u_i = −u_{3−i}`),
/// X, with opposite
/// impulses, and the state stays antisymmetric to round-off — through
/// plastic holds and releases (e = 0), chatter and accumulations (0.5) and
/// elastic bounces (1), for the consistent and the lumped mass. Newton's
/// law on both contacts at once keeps it; impacts taken one contact at a
/// time (the second at its bound `10⁻¹⁶` later) do not.
#[test]
fn a_bar_between_two_stops_reached_together_stays_antisymmetric() {
    for mass in [BarMass::Std, BarMass::Lumped] {
        for e in [0.0, 0.5, 1.0] {
            let bar = Bar::new(1.0, 3, 1.0, RightEnd::Free).unwrap();
            let stops = vec![Contact::new(0, Bounds::obstacle(-0.05), false), Contact::new(3, Bounds { lo: f64::NEG_INFINITY, hi: 0.05 }, false)];
            let dy = Dynamics::new(bar.mass(mass), bar.stiffness(), vec![-0.2, 0.0, 0.0, 0.2], stops);
            let mut r = EventDriven::new(&dy, 0.0, &[0.0; 4], &[-0.5, -1.0 / 6.0, 1.0 / 6.0, 0.5], e).unwrap();
            let mut t = 0.0;
            while t < 6.0 {
                t += 0.1;
                r.run_until(t, 100_000).unwrap_or_else(|err| panic!("{mass:?}, e = {e}: {err}"));
                let (_, q, v) = r.state();
                for i in 0..2 {
                    assert!((q[i] + q[3 - i]).abs() <= 1e-12 && (v[i] + v[3 - i]).abs() <= 1e-12, "{mass:?}, e = {e}, t = {t}: q = {q:?}, v = {v:?}");
                }
            }
            let ev = r.events();
            assert!(ev.len() >= 2 && ev.len() % 2 == 0, "{mass:?}, e = {e}: {ev:?}");
            for p in ev.chunks(2) {
                let (a, b) = (p[0], p[1]);
                assert!((a.t - b.t).abs() <= 1e-12 && a.kind == b.kind && a.contact != b.contact, "{mass:?}, e = {e}: not a pair {a:?} {b:?}");
                assert!((a.impulse + b.impulse).abs() <= 1e-12 && (a.velocity_before + b.velocity_before).abs() <= 1e-12, "{mass:?}, e = {e}: {a:?} {b:?}");
            }
        }
    }
}

/// The event limit counts the same thing on both paths: `run_until(t,
/// max)` (the library's) and the stepper's `max_events` (`signorini run`'s
/// `event-driven(E,MAX_EVENTS)`) each allow exactly `max` records, however
/// many of them one located instant logs. On the bar between two stops
/// reached together (above), every located impact logs two records (one
/// per end, in pairs: checked), so a limit of one less than the records
/// must stop both paths, and the records themselves pass both. `run_until`
/// counted located instants, half the records, and let 2·max through.
#[test]
fn the_event_limit_counts_records_on_every_path() {
    for e in [0.0, 1.0] {
        let bar = Bar::new(1.0, 3, 1.0, RightEnd::Free).unwrap();
        let stops = vec![Contact::new(0, Bounds::obstacle(-0.05), false), Contact::new(3, Bounds { lo: f64::NEG_INFINITY, hi: 0.05 }, false)];
        let dy = Dynamics::new(bar.mass(BarMass::Std), bar.stiffness(), vec![-0.2, 0.0, 0.0, 0.2], stops);
        let (q0, v0) = ([0.0; 4], [-0.5, -1.0 / 6.0, 1.0 / 6.0, 0.5]);
        let t_end = 3.0;
        let mut free = EventDriven::new(&dy, 0.0, &q0, &v0, e).unwrap();
        free.run_until(t_end, usize::MAX).unwrap();
        let records = free.events().len();
        assert!(records >= 4 && free.events().chunks(2).all(|p| p[0].t == p[1].t && p[0].contact != p[1].contact), "e = {e}: not in pairs: {:?}", free.events());
        for (max, passes) in [(records, true), (records - 1, false)] {
            let mut r = EventDriven::new(&dy, 0.0, &q0, &v0, e).unwrap();
            assert_eq!(r.run_until(t_end, max).is_ok(), passes, "e = {e}: run_until with max = {max} of {records} records");
            let mut stepper = EventStepper::new("event-driven".into(), dy.clone(), e, 0.5, &Initial { u: q0.to_vec(), v: v0.to_vec() }).unwrap().with_max_events(max);
            let stepped = (0..6).try_for_each(|_| stepper.step().map(|_| ()));
            assert_eq!(stepped.is_ok(), passes, "e = {e}: the stepper with max_events = {max} of {records} records");
        }
    }
}

/// Tiny nudges of a held state: the clamped bars (consistent and lumped P1
/// of 4 elements, consistent P2 of 2) start at rest on their stop
/// (`u_0 >= 0`) under a steady load `−0.5` at every node: the contact is
/// held while the other nodes oscillate. At `t = 1, 2, 3` each dof's
/// displacement (the contact's off its stop only) or velocity is nudged by
/// `±10⁻¹⁵ … ±10⁻⁶`. Every nudged run goes on to 2 later (the contact falls
/// back, lands plastically or chatters to rest, and is held again), stays
/// inside its bound, and never gains energy: `½ vᵀMv + ½ qᵀKq − fᵀq` at the
/// end is at most the nudged start's (undamped, a steady load, one
/// contact, `e <= 1`; gains measured below 5e-16 of an energy of 1e-2).
/// The consistent P1 bar with `e = 0.5` chattered to the event limit from a
/// contact-dof nudge of 1e-15 (rebounds below the position's round-off,
/// docs/theory.md §9.3) before they ended as an accumulation.
#[test]
fn tiny_nudges_of_a_held_bar_settle_without_gaining_energy() {
    for (mass, degree, e) in [(BarMass::Std, 1, 0.0), (BarMass::Std, 1, 0.5), (BarMass::Lumped, 1, 0.0), (BarMass::Lumped, 1, 0.5), (BarMass::Std, 2, 0.0), (BarMass::Std, 2, 0.5)] {
        let elements = if degree == 1 { 4 } else { 2 };
        let bar = Bar::new(1.0, elements, 1.0, RightEnd::Clamped).unwrap().with_degree(degree).unwrap();
        let (m, k) = (bar.mass(mass), bar.stiffness());
        let n = m.n();
        let f = vec![-0.5; n];
        let dy = Dynamics::new(m.clone(), k.clone(), f.clone(), vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
        let mut r = EventDriven::new(&dy, 0.0, &vec![0.0; n], &vec![0.0; n], e).unwrap();
        for t_h in [1.0, 2.0, 3.0] {
            r.run_until(t_h, 1000).unwrap();
            assert_eq!(r.held(), vec![(0, false)], "{mass:?} P{degree}, e = {e}, t = {t_h}");
            let (_, qh, vh) = r.state();
            for dof in 0..n {
                for position in [true, false] {
                    for d in [1e-15, 1e-12, 1e-9, 1e-6] {
                        for d in [d, -d] {
                            if position && dof == 0 && d < 0.0 {
                                continue;
                            }
                            let name = format!("{mass:?} P{degree}, e = {e}, t = {t_h}: {} of dof {dof} by {d:e}", if position { "u" } else { "v" });
                            let (mut q, mut v) = (qh.clone(), vh.clone());
                            if position {
                                q[dof] += d;
                            } else {
                                v[dof] += d;
                            }
                            let before = energy(&m, &k, &f, &q, &v);
                            let mut x = EventDriven::new(&dy, t_h, &q, &v, e).unwrap();
                            x.run_until(t_h + 2.0, 10_000).unwrap_or_else(|err| panic!("{name}: {err}"));
                            let (t, q, v) = x.state();
                            assert!(t == t_h + 2.0 && q[0] >= 0.0, "{name}: t = {t}, u_0 = {}", q[0]);
                            let after = energy(&m, &k, &f, &q, &v);
                            assert!(after <= before + 1e-14, "{name}: the energy went from {before} to {after}");
                        }
                    }
                }
            }
        }
    }
}

/// Three masses in a row (consistent: 2/3 on the diagonal, 1/6 beside;
/// springs 2, −1), stops under the end dofs (at `lo`), a steady load −0.5 on
/// each end pressing them on.
fn chain3(lo: f64, damped: bool) -> Dynamics {
    let (mut m, mut k) = (SymBand::zeros(3, 1), SymBand::zeros(3, 1));
    for i in 0..3 {
        m.set(i, i, 2.0 / 3.0);
        k.set(i, i, 2.0);
        if i > 0 {
            m.set(i, i - 1, 1.0 / 6.0);
            k.set(i, i - 1, -1.0);
        }
    }
    let stops = vec![Contact::new(0, Bounds::obstacle(lo), false), Contact::new(2, Bounds::obstacle(lo), false)];
    let c = damped.then(|| m.lin_comb(0.05, &k, 0.02));
    Dynamics::new(m, k, vec![-0.5, 0.0, -0.5], stops).with_damping(c)
}

/// The chain, plastic (`e = 0`), its ends landing at different times: each
/// end's plastic impact lifts the other through the consistent mass, which
/// lands again 1/15 as fast (0.45, 0.48, 0.032, 2.1e-3, …): a geometric run
/// of alternating impacts. It used to go on at 2.7e-9 m/s every 4.8e-9 s
/// (rebounds of 3e-18, below the position's round-off) to the event limit.
/// Now the run of impacts ends where the lifted end's rebound is too low to
/// be told from rest (a height of 1.6e-15 here, after 8 impacts), both ends
/// at rest, logged at the time its rebounds would take (`2w/|a|` for
/// `e = 0`), 1.3e-7 after its impact and 2.0e-8 before the limit of the
/// impact times (Aitken's, from their last three, computed here apart from
/// the run's rules; asserted within 4e-8): the landings after it are
/// neglected, as the band neglects their heights; the run ends
/// in a few dozen events, and the energy
/// `½ vᵀMv + ½ qᵀKq − fᵀq` (undamped, steady load) never rises.
#[test]
fn two_ends_lifting_each_other_through_the_mass_come_to_rest_together() {
    let dy = chain3(0.0, false);
    let mut r = EventDriven::new(&dy, 0.0, &[0.1, 0.0, 0.13], &[0.0; 3], 0.0).unwrap();
    let mut last = energy(&dy.mass, &dy.stiffness, &dy.load, &[0.1, 0.0, 0.13], &[0.0; 3]);
    for i in 1..=40 {
        r.run_until(0.5 * i as f64, 200).unwrap_or_else(|err| panic!("to t = {}: {err}", 0.5 * i as f64));
        let (_, q, v) = r.state();
        let now = energy(&dy.mass, &dy.stiffness, &dy.load, &q, &v);
        assert!(now <= last + 1e-15 && q[0] >= 0.0 && q[2] >= 0.0, "t = {}: energy {last} -> {now}, q = {q:?}", 0.5 * i as f64);
        last = now;
    }
    let ev = r.events();
    let impacts: Vec<f64> = ev.iter().filter(|x| x.kind == EventKind::Impact && x.t < 0.6).map(|x| x.t).collect();
    assert!(impacts.len() >= 6 && ev.len() <= 60, "{} events: {ev:?}", ev.len());
    // Aitken's limit of the impact times.
    let [a, b, c] = [impacts[impacts.len() - 3], impacts[impacts.len() - 2], impacts[impacts.len() - 1]];
    let t_inf = c - (c - b) * (c - b) / ((c - b) - (b - a));
    let rest: Vec<&EventRecord> = ev.iter().filter(|x| x.kind == EventKind::Accumulation).collect();
    assert!(!rest.is_empty() && rest.iter().all(|x| (x.t - t_inf).abs() <= 4e-8), "the limit {t_inf}: {rest:?}");
}

/// The same chain, damped, both ends starting on stops at 0 with the same
/// speed up (`v = (0.3, 0, 0.3)`): mirror-symmetric, so both ends land
/// together every time. With stops and start all at 0 the contacts had no
/// length of their own, their at-bound band shrank to equality, and the two
/// landings were located 1.1e-16 s apart and taken one by one: the mirror
/// symmetry broke and the ends lifted each other to the event limit
/// (t = 0.69). Now the motion stays symmetric to round-off, each event a
/// pair at one instant.
#[test]
fn two_ends_on_stops_at_zero_land_together() {
    let dy = chain3(0.0, true);
    let mut r = EventDriven::new(&dy, 0.0, &[0.0; 3], &[0.3, 0.0, 0.3], 0.0).unwrap();
    for i in 1..=20 {
        r.run_until(i as f64, 1000).unwrap_or_else(|err| panic!("to t = {i}: {err}"));
        let (_, q, v) = r.state();
        assert!((q[0] - q[2]).abs() <= 1e-12 && (v[0] - v[2]).abs() <= 1e-12, "t = {i}: q = {q:?}, v = {v:?}");
    }
    let ev = r.events();
    assert!(ev.len() >= 2 && ev.len() <= 100, "{} events", ev.len());
    for pair in ev.chunks(2) {
        assert!(pair.len() == 2 && pair[0].t == pair[1].t && pair[0].kind == pair[1].kind && pair[0].contact != pair[1].contact, "not in pairs: {pair:?}");
    }
}

/// A free P1 bar of 3 elements squeezed between a stop at 0 under its left
/// end and one at 0 over its right end, pushed onto both by
/// `0.6 sin 1.3t + 0.4 sin(3.7t + 0.5)`, damped, nearly plastic
/// (`e = 10⁻¹²`), from rest at 0 with its ends moving into the stops at 0.3:
/// mirror-antisymmetric (`u_i = −u_{3−i}`). Its stops and start give no
/// length, and the first displacements met at an event were round-off
/// (1e-26): taken as the band's length, they left the ends chattering in
/// turn at 2e-9 m/s to the event limit (t = 17). The band's length is now
/// the largest displacement met so far: the run ends at t = 20 in a few
/// dozen events (76), inside its stops, antisymmetric to 1e-14.
#[test]
fn a_bar_squeezed_between_stops_at_zero_runs_to_its_end_antisymmetric() {
    let bar = Bar::new(1.0, 3, 1.0, RightEnd::Free).unwrap();
    let (m, k) = (bar.mass(BarMass::Std), bar.stiffness());
    let c = m.lin_comb(0.05, &k, 0.02);
    let stops = vec![Contact::new(0, Bounds { lo: 0.0, hi: f64::INFINITY }, false), Contact::new(3, Bounds { lo: f64::NEG_INFINITY, hi: 0.0 }, false)];
    let dy = Dynamics::new(m, k, vec![0.0; 4], stops).with_forcing(vec![Forcing { shape: vec![-1.0, 0.0, 0.0, 1.0], time: harmonics(&[(0.6, 1.3, 0.0), (0.4, 3.7, 0.5)]) }]).with_damping(Some(c));
    let mut r = EventDriven::new(&dy, 0.0, &[0.0; 4], &[-0.3, 0.0, 0.0, 0.3], 1e-12).unwrap();
    for i in 1..=20 {
        r.run_until(i as f64, 1000).unwrap_or_else(|err| panic!("to t = {i}: {err}"));
        let (_, q, v) = r.state();
        assert!(q[0] >= 0.0 && q[3] <= 0.0, "t = {i}: q = {q:?}");
        for j in 0..2 {
            assert!((q[j] + q[3 - j]).abs() <= 1e-12 && (v[j] + v[3 - j]).abs() <= 1e-12, "t = {i}: q = {q:?}, v = {v:?}");
        }
    }
    assert!(r.events().len() <= 200, "{} events", r.events().len());
}
