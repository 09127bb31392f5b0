//! The event-driven run allocates nothing per event once it has started
//! (the developers' guide: "the hot loop allocates nothing"; issue 34):
//! its per-event vectors are work storage of the run, reused. A test
//! binary of its own, whose global allocator counts the allocations of
//! each thread (no timing): after a warm-up that meets every active set
//! of the run (their flows are built once and cached), the next events —
//! impacts, releases, held phases, accumulations, through the run and
//! through its stepper — make no new allocation. Growing the event log
//! (and a contact's run of impact times) reallocates a buffer that
//! already exists, a doubling now and then: counted apart, bounded.

use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind, EventStepper};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Initial, Stepper, TimeProfile};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    /// This thread's fresh allocations and its reallocations.
    static COUNT: Cell<(u64, u64)> = const { Cell::new((0, 0)) };
}

fn bump(fresh: u64, re: u64) {
    // `try_with`: nothing counted while the thread's storage is torn down.
    let _ = COUNT.try_with(|c| {
        let (a, r) = c.get();
        c.set((a + fresh, r + re));
    });
}

// SAFETY: every call is passed to the system allocator unchanged; the
// counter is a `const` thread-local `Cell` (no allocation, no drop).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump(1, 0);
        // SAFETY: the caller's contract, passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        bump(1, 0);
        // SAFETY: the caller's contract, passed on unchanged.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump(0, 1);
        // SAFETY: the caller's contract, passed on unchanged.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract, passed on unchanged.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// `(fresh allocations, reallocations)` of this thread during `f`.
fn counted<R>(f: impl FnOnce() -> R) -> (R, u64, u64) {
    let (a0, r0) = COUNT.with(Cell::get);
    let out = f();
    let (a1, r1) = COUNT.with(Cell::get);
    (out, a1 - a0, r1 - r0)
}

fn band(d: &[f64], off: &[f64]) -> SymBand {
    let mut b = SymBand::zeros(d.len(), usize::from(!off.is_empty()));
    for (i, &x) in d.iter().enumerate() {
        b.set(i, i, x);
    }
    for (i, &x) in off.iter().enumerate() {
        b.set(i + 1, i, x);
    }
    b
}

/// The events of the kinds in `window`: `(impacts, releases, accumulations)`.
fn kinds(window: &[signorini_schemes::events::EventRecord]) -> (usize, usize, usize) {
    let n = |k: EventKind| window.iter().filter(|e| e.kind == k).count();
    (n(EventKind::Impact), n(EventKind::Release), n(EventKind::Accumulation))
}

/// Runs `warm` events, then `count` more; the allocations of the second
/// part, and its events' kinds.
fn after_warm_up(run: &mut EventDriven, warm: usize, count: usize) -> (u64, u64, (usize, usize, usize)) {
    for _ in 0..warm {
        run.next_event(f64::INFINITY).expect("the warm-up's events").expect("an event");
    }
    let start = run.events().len();
    let ((), fresh, re) = counted(|| {
        for _ in 0..count {
            run.next_event(f64::INFINITY).expect("the counted events").expect("an event");
        }
    });
    (fresh, re, kinds(&run.events()[start..]))
}

/// A bound on the reallocations of `count` events: the log's doublings
/// and a few of the impact times' (not one per event).
const FEW: u64 = 16;

#[test]
fn the_two_stop_oscillator_impacts_without_allocating() {
    // m x'' + c x' + k x = 2 sin(1.325 t), −1 <= x <= 1, e = 0.8 (the
    // basins' grid of docs/orbits.md): impacts at both stops, free flights.
    let c = band(&[0.1], &[]);
    let forcing = vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: 2.0, omega: 1.325 } }];
    let dy = Dynamics::new(band(&[1.0], &[]), band(&[1.0], &[]), vec![0.0], vec![Contact::new(0, Bounds { lo: -1.0, hi: 1.0 }, false)]).with_forcing(forcing).with_damping(Some(c));
    let mut run = EventDriven::new(&dy, 0.0, &[0.3], &[0.5], 0.8).unwrap();
    let (fresh, re, (impacts, ..)) = after_warm_up(&mut run, 200, 2000);
    assert_eq!(impacts, 2000, "every event an impact");
    assert_eq!(fresh, 0, "{fresh} fresh allocations over 2000 impacts (and {re} reallocations)");
    assert!(re <= FEW, "{re} reallocations over 2000 impacts");
}

#[test]
fn a_plastic_oscillator_lands_holds_and_releases_without_allocating() {
    // e = 0 on a stop at 0 under −0.5 + 2 sin(2t): each landing is an
    // impact then a held phase (no free dof: an empty flow), each release
    // a flight.
    let forcing = vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: 2.0, omega: 2.0 } }];
    let dy = Dynamics::new(band(&[1.0], &[]), band(&[1.0], &[]), vec![-0.5], vec![Contact::new(0, Bounds::obstacle(0.0), false)]).with_forcing(forcing);
    let mut run = EventDriven::new(&dy, 0.0, &[0.5], &[0.0], 0.0).unwrap();
    let (fresh, re, (impacts, releases, _)) = after_warm_up(&mut run, 100, 1000);
    assert!(impacts >= 400 && releases >= 400, "{impacts} impacts, {releases} releases");
    assert_eq!(fresh, 0, "{fresh} fresh allocations over 1000 landings and releases (and {re} reallocations)");
    assert!(re <= FEW, "{re} reallocations");
}

/// A damped P1 chain of three masses on a stop at its first dof, pressed
/// onto it by a steady load and lifted off by a harmonic one.
fn chain(e: f64) -> (Dynamics, Vec<f64>) {
    let (h, n) = (1.0 / 3.0, 3);
    let m = band(&[2.0 * h / 3.0, 2.0 * h / 3.0, h / 3.0], &[h / 6.0, h / 6.0]);
    let k = band(&[2.0 / h, 2.0 / h, 1.0 / h], &[-1.0 / h, -1.0 / h]);
    let c = band(&[0.02 / h, 0.02 / h, 0.01 / h], &[-0.01 / h, -0.01 / h]);
    let forcing = vec![Forcing { shape: vec![1.0, 1.0, 0.5], time: TimeProfile::Sine { amplitude: 1.5, omega: 3.0 } }];
    let stop = Contact::new(0, Bounds::obstacle(0.0), false).with_restitution(Some(e));
    let dy = Dynamics::new(m, k, vec![-1.0, -1.0, -0.5], vec![stop]).with_forcing(forcing).with_damping(Some(c));
    (dy, vec![0.2; n])
}

#[test]
fn a_chattering_chain_accumulates_holds_and_releases_without_allocating() {
    let (dy, q0) = chain(0.5);
    let mut run = EventDriven::new(&dy, 0.0, &q0, &[0.0; 3], 0.5).unwrap();
    let (fresh, re, (impacts, releases, accumulations)) = after_warm_up(&mut run, 500, 3000);
    assert!(impacts > 0 && releases > 0 && accumulations > 0, "{impacts} impacts, {releases} releases, {accumulations} accumulations");
    assert_eq!(fresh, 0, "{fresh} fresh allocations over 3000 events (and {re} reallocations)");
    assert!(re <= FEW, "{re} reallocations");
}

#[test]
fn the_stepper_samples_a_held_phase_without_allocating() {
    // The registry's event-driven scheme: each output step reads the
    // state, the held force's integral and the impulses.
    let (dy, q0) = chain(0.5);
    let init = Initial { u: q0, v: vec![0.0; 3] };
    let mut stepper = EventStepper::new("event-driven".into(), dy, 0.5, 1e-2, &init).unwrap();
    for _ in 0..2000 {
        stepper.step().unwrap();
    }
    let start = Stepper::events(&stepper).unwrap().len();
    let ((), fresh, re) = counted(|| {
        for _ in 0..4000 {
            stepper.step().unwrap();
        }
    });
    let (impacts, releases, accumulations) = kinds(&Stepper::events(&stepper).unwrap()[start..]);
    assert!(impacts > 0 && releases > 0 && accumulations > 0, "{impacts} impacts, {releases} releases, {accumulations} accumulations");
    assert_eq!(fresh, 0, "{fresh} fresh allocations over 4000 steps (and {re} reallocations)");
    assert!(re <= FEW, "{re} reallocations");
}

#[test]
fn a_massless_contact_lands_and_leaves_without_allocating() {
    // A P1 chain of five dofs whose contact dof 0 is massless (its mass
    // moved to dof 1: mass redistribution), between two stops, conservative:
    // landings (held phases, statically condensed) and releases.
    let (masses, springs) = ([1.0, 0.7, 1.2, 0.9], [2.0, 1.0, 1.5, 0.8]);
    let n = 5;
    let (mut md, mut mo, mut kd, mut ko) = (vec![0.0; n], vec![0.0; n - 1], vec![0.0; n], vec![0.0; n - 1]);
    for i in 0..n - 1 {
        md[i] += masses[i] / 3.0;
        md[i + 1] += masses[i] / 3.0;
        mo[i] = masses[i] / 6.0;
        kd[i] += springs[i];
        kd[i + 1] += springs[i];
        ko[i] = -springs[i];
    }
    kd[n - 1] += 0.3;
    md[1] += md[0] + mo[0];
    (md[0], mo[0]) = (0.0, 0.0);
    let dy = Dynamics::new(band(&md, &mo), band(&kd, &ko), vec![0.0, -0.05, 0.02, 0.0, -0.03], vec![Contact::new(0, Bounds { lo: -0.05, hi: 0.08 }, true)]);
    let mut run = EventDriven::new(&dy, 0.0, &[0.0, 0.02, -0.01, 0.03, 0.0], &[0.0, -0.6, 0.4, 0.3, -0.5], 0.0).unwrap();
    let (fresh, re, (impacts, releases, _)) = after_warm_up(&mut run, 200, 1000);
    assert!(impacts > 0 && releases > 0, "{impacts} landings, {releases} releases");
    assert_eq!(fresh, 0, "{fresh} fresh allocations over 1000 landings and releases (and {re} reallocations)");
    assert!(re <= FEW, "{re} reallocations");
}
