//! The degenerate classes a user meets first, under a dashpot (a
//! non-classical damping: the first-order flow of docs/theory.md §9.1):
//! a chain that starts held and is released, lands, chatters and is held
//! again; two contacts reached at the same instant (a symmetric dashpot,
//! and a slightly asymmetric one); and a two-sided stop run of §9.3's hunt
//! (run 686). The held-start and two-stop suites run Rayleigh damping or
//! none; these run the contact rules on the first-order flow.
//!
//! Oracle: the event-located RK4 of `events_rk4.rs`. Its tolerance is its
//! own error: each case is run by the oracle at `h` and at `h/2`, whose
//! difference `Δ` is the error of the `h` run to `O(h⁵)` (RK4: the `h/2`
//! run's error is `Δ/15`); the run must agree with the `h/2` oracle within
//! `4 Δ` plus a round-off floor (`1e-12` in time and speed, `1e-12` of the
//! state's scale), measured per quantity (event times, impact speeds, the
//! accumulation time) and, for the state at fixed times, with `Δ` the
//! largest over the state's entries. Per entry `Δ` can cancel: the oracle's
//! error is its RK4 truncation (`O(h⁴)`) plus a part that grows as its
//! step count (`1/h`; taken for round-off), of either sign. Run 686 at `t = 6`, `h = 1e-3`:
//! from `h/2` to `h/16` the oracle's successive differences double, of
//! alternating sign, on every entry (velocity 2: 9.6e-12, −1.8e-11,
//! 3.7e-11), the run within 1.1e-12 of the `h/2` oracle and 2.7e-11 of
//! the `h/16` one; at `h` against `h/2` that entry's difference is 1.8e-13
//! (truncation and round-off of opposite signs), the state's largest
//! 9.8e-12.

use crate::events_common::{chain_matrices, cut_chain_matrices};
use crate::events_rk4::{Output, Rk4, Stop};
use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind, EventRecord};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::sync::Arc;

/// A state `(q, v)`.
type State = (Vec<f64>, Vec<f64>);

/// A problem for both: `Dynamics` and the oracle, from the same data.
struct Case {
    name: &'static str,
    m: SymBand,
    k: SymBand,
    /// Dashpots `(dof, c)` on the diagonal of `C`.
    dashpots: Vec<(usize, f64)>,
    f0: Vec<f64>,
    shape: Vec<f64>,
    wave: (f64, f64, f64),
    stops: Vec<Stop>,
    e: f64,
    q0: Vec<f64>,
    v0: Vec<f64>,
    t_end: f64,
    samples: Vec<f64>,
}

impl Case {
    fn n(&self) -> usize {
        self.m.n()
    }

    fn dynamics(&self) -> Dynamics {
        let n = self.n();
        let mut c = SymBand::zeros(n, 1);
        for &(d, x) in &self.dashpots {
            c.set(d, d, c.get(d, d) + x);
        }
        let contacts = self.stops.iter().map(|s| Contact::new(s.dof, Bounds { lo: s.lo, hi: s.hi }, false)).collect();
        let forcing = vec![Forcing { shape: self.shape.clone(), time: TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: self.wave.0, omega: self.wave.1, phase: self.wave.2 }])) }];
        Dynamics::new(self.m.clone(), self.k.clone(), self.f0.clone(), contacts).with_forcing(forcing).with_damping(Some(c))
    }

    fn oracle(&self, h: f64) -> Output {
        let n = self.n();
        let dense = |b: &SymBand| (0..n * n).map(|x| b.get(x / n, x % n)).collect::<Vec<f64>>();
        let mut c = vec![0.0; n * n];
        for &(d, x) in &self.dashpots {
            c[d * n + d] += x;
        }
        let rk = Rk4 { n, m: dense(&self.m), k: dense(&self.k), c, f0: self.f0.clone(), shape: self.shape.clone(), wave: self.wave, stops: self.stops.clone(), e: self.e };
        rk.run(&self.q0, &self.v0, self.t_end, h, &self.samples)
    }

    /// The run's events and its state at the sample times.
    fn run(&self) -> (Vec<EventRecord>, Vec<State>) {
        let mut run = EventDriven::new(&self.dynamics(), 0.0, &self.q0, &self.v0, self.e).unwrap_or_else(|e| panic!("{}: {e}", self.name));
        let mut states = Vec::new();
        for &t in &self.samples {
            run.run_until(t, 20_000).unwrap_or_else(|e| panic!("{}: {e}", self.name));
            let (_, q, v) = run.state();
            states.push((q, v));
        }
        run.run_until(self.t_end, 20_000).unwrap_or_else(|e| panic!("{}: {e}", self.name));
        (run.events().to_vec(), states)
    }
}

/// The held chain of (a): `n` consistent masses tied at the far end, the
/// stop `q₀ >= 0`, at rest on it, pressed by `−A sin(Ω t + p)` at dof 0.
fn held_chain(name: &'static str, dashpots: Vec<(usize, f64)>) -> Case {
    let n = 4;
    let (m, k) = chain_matrices(n, false);
    let mut shape = vec![0.0; n];
    shape[0] = -1.0;
    shape[2] = 0.3;
    Case {
        name,
        m,
        k,
        dashpots,
        f0: vec![0.0; n],
        shape,
        wave: (1.0, 1.0, 0.3),
        stops: vec![Stop { dof: 0, lo: 0.0, hi: f64::INFINITY }],
        e: 0.5,
        q0: vec![0.0; n],
        v0: vec![0.0; n],
        t_end: 20.0,
        samples: vec![2.0, 5.0, 8.0, 12.0, 16.0, 20.0],
    }
}

/// (b) The free P1 bar of three elements (`L = 1`, consistent mass) moving
/// at `−0.5` onto equal stops at both ends (`u₀, u₃ >= −0.05`, `e = 0.5`:
/// `events_two_stops.rs`), with a dashpot at each end: `c` at dof 0 and
/// `c (1 + asym)` at dof 3.
fn two_stops(name: &'static str, c: f64, asym: f64) -> Case {
    let (n, h) = (4, 1.0 / 3.0);
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        let w = if i == 0 || i == n - 1 { 1.0 } else { 2.0 };
        m.set(i, i, h * w / 3.0);
        k.set(i, i, w / h);
        if i > 0 {
            m.set(i, i - 1, h / 6.0);
            k.set(i, i - 1, -1.0 / h);
        }
    }
    Case {
        name,
        m,
        k,
        dashpots: vec![(0, c), (3, c * (1.0 + asym))],
        f0: vec![0.0; n],
        shape: vec![0.0; n],
        wave: (0.0, 1.0, 0.0),
        stops: vec![Stop { dof: 0, lo: -0.05, hi: f64::INFINITY }, Stop { dof: 3, lo: -0.05, hi: f64::INFINITY }],
        e: 0.5,
        q0: vec![0.0; n],
        v0: vec![-0.5; n],
        t_end: 3.0,
        samples: vec![0.3, 0.6, 1.0, 2.0, 3.0],
    }
}

/// (c) Run 686 of §9.3's hunt (seed 1 of its random class): a free chain
/// of four consistent masses, a dashpot of 0.0219 at dof 0, the two-sided
/// stop `−0.2 <= q₂ <= 0.2` with `e = 0.941`, loaded and forced at dof 0:
/// 26 impacts at both sides, then a chatter on the lower side whose 164
/// impacts accumulate at `t = 11.26`, held to `t = 12`.
fn run_686() -> Case {
    let (m, k) = chain_matrices(4, true);
    Case {
        name: "hunt run 686",
        m,
        k,
        dashpots: vec![(0, 0.021916625949891223)],
        f0: vec![-0.31028162402209625, 0.027246476919682155, -0.038518087598953255, -0.01096576073491165],
        shape: vec![0.662996128121426, 0.0, 0.0, 0.0],
        wave: (0.8919609889550084, 1.3673234405779466, 3.476044735249661),
        stops: vec![Stop { dof: 2, lo: -0.2, hi: 0.2 }],
        e: 0.9410501940709735,
        q0: vec![0.0; 4],
        v0: vec![0.11040765100023853, -0.8117979129938917, -0.9453847184462103, 0.20034262732234498],
        t_end: 12.0,
        samples: vec![3.0, 6.0, 9.0, 11.0, 12.0],
    }
}

/// The events compared: every release, accumulation and impact except the
/// impacts slower than 1e-3 of their contact's fastest since its last
/// release or accumulation, a held contact's impulses, and the
/// accumulation of a contact with no impacts of its own (a chatter's tail: both end it by the
/// micro-impact rule, a few impacts apart: docs/theory.md §9.3), as `(t,
/// kind, contact, v_c before)`.
fn items(rows: impl Iterator<Item = (f64, EventKind, usize, f64)>) -> Vec<(f64, EventKind, usize, f64)> {
    let mut vmax = [0.0f64; 4];
    let mut out = Vec::new();
    for r in rows {
        match r.1 {
            EventKind::Impact => {
                vmax[r.2] = vmax[r.2].max(r.3.abs());
                if r.3.abs() > 1e-3 * vmax[r.2] {
                    out.push(r);
                }
            }
            // A contact lifted within its band by another's impulse and
            // put at rest (the run's rule for rebounds it cannot resolve:
            // docs/theory.md §9.3; the oracle keeps it held): no run of
            // impacts of its own ends there.
            EventKind::Accumulation if vmax[r.2] == 0.0 => {}
            _ => {
                vmax[r.2] = 0.0;
                out.push(r);
            }
        }
    }
    // Two contacts' events of one kind at one instant (to 1e-9 s: two
    // releases located one after the other), in contact order.
    for i in 1..out.len() {
        if out[i].0 - out[i - 1].0 <= 1e-9 && out[i].1 == out[i - 1].1 && out[i].2 < out[i - 1].2 {
            out.swap(i, i - 1);
        }
    }
    out
}

/// The run against the oracle at `h/2`, within `4 Δ` (`Δ`: the oracle at
/// `h` against `h/2`, per quantity) plus the round-off floor (module
/// docs). An accumulation time within `4 Δ + 1e-7` s: the run may end a
/// chatter a few impacts before the oracle (its micro-impact rule, or a
/// joint rest when its impulse lifts a held contact within the band), its
/// limit then `t_k + 2w/(|a| (1 − e))` to first order, within a fraction
/// of that tail (4e-7 s at `w = 1e-6`, two stops asymmetric: measured
/// 1.5e-8 s) of the oracle's geometric one. Returns the worst `|error| /
/// tolerance` of times, speeds, accumulations and states.
fn check(case: &Case, h: f64) -> [f64; 4] {
    let (got, states) = case.run();
    let (coarse, fine) = (case.oracle(h), case.oracle(h / 2.0));
    let g = items(got.iter().map(|r| (r.t, r.kind, r.contact, r.velocity_before)));
    let (w, c) = (items(fine.rows.iter().copied()), items(coarse.rows.iter().copied()));
    let name = case.name;
    assert!(w.len() == c.len() && w.iter().zip(&c).all(|(a, b)| a.1 == b.1 && a.2 == b.2), "{name}: the oracle at h and h/2 differ: {w:?}\n{c:?}");
    assert!(g.len() == w.len(), "{name}: {} events against the oracle's {}:\n{g:?}\n{w:?}", g.len(), w.len());
    let mut worst = [0.0f64; 4];
    for ((gr, wr), cr) in g.iter().zip(&w).zip(&c) {
        assert!(gr.1 == wr.1 && gr.2 == wr.2, "{name}: {gr:?} against {wr:?}");
        let floor = if gr.1 == EventKind::Accumulation { 1e-7 } else { 1e-12 * wr.0.max(1.0) };
        let tol_t = 4.0 * (cr.0 - wr.0).abs() + floor;
        let slot = if gr.1 == EventKind::Accumulation { 2 } else { 0 };
        assert!((gr.0 - wr.0).abs() <= tol_t, "{name}: {gr:?} against {wr:?} (tolerance {tol_t:.1e} s)");
        worst[slot] = worst[slot].max((gr.0 - wr.0).abs() / tol_t);
        if gr.1 == EventKind::Impact {
            let tol_v = 4.0 * (cr.3 - wr.3).abs() + 1e-12 * wr.3.abs().max(1.0);
            assert!((gr.3 - wr.3).abs() <= tol_v, "{name}: {gr:?} against {wr:?} (tolerance {tol_v:.1e} m/s)");
            worst[1] = worst[1].max((gr.3 - wr.3).abs() / tol_v);
        }
    }
    for (i, (q, v)) in states.iter().enumerate() {
        let ((qw, vw), (qc, vc)) = (&fine.samples[i], &coarse.samples[i]);
        let scale = qw.iter().chain(vw).fold(1.0f64, |m, x| m.max(x.abs()));
        // Δ over the whole state, not per entry: an entry's own Δ can
        // cancel (module docs).
        let delta = qw.iter().chain(vw).zip(qc.iter().chain(vc)).fold(0.0f64, |m, (y, z)| m.max((z - y).abs()));
        let tol = 4.0 * delta + 1e-12 * scale;
        for (j, (x, y)) in q.iter().chain(v).zip(qw.iter().chain(vw)).enumerate() {
            assert!((x - y).abs() <= tol, "{name}: at t = {}, entry {j} of (q, v): {x} against {y} (tolerance {tol:.1e})", case.samples[i]);
            worst[3] = worst[3].max((x - y).abs() / tol);
        }
    }
    println!("{name}: {} events compared, worst error/tolerance: times {:.2}, speeds {:.2}, accumulations {:.2}, states {:.2}", g.len(), worst[0], worst[1], worst[2], worst[3]);
    worst
}

/// (a) A chain held on its stop at the start under a load that reverses
/// (at dof 0, and at dof 2 against it), with a dashpot at the contact dof,
/// and with one there and one away from it: released where the held force
/// turns (the load at dof 2 moves the chain while held, so the force is not
/// the load's alone), flight, landing, chatter accumulating, held, and
/// released again.
#[test]
fn a_held_start_under_a_dashpot_is_released_lands_chatters_and_holds_as_the_oracle() {
    for case in [held_chain("held, dashpot at the contact", vec![(0, 0.4)]), held_chain("held, dashpots at the contact and away", vec![(0, 0.4), (2, 0.4)])] {
        let (got, _) = case.run();
        let kinds: Vec<EventKind> = got.iter().map(|r| r.kind).collect();
        assert!(kinds[0] == EventKind::Release && kinds.contains(&EventKind::Accumulation) && kinds.iter().filter(|&&k| k == EventKind::Release).count() >= 2, "{}: {got:?}", case.name);
        check(&case, 1e-3);
    }
}

/// (b) Two equal stops reached at the same instant under a symmetric
/// dashpot (both ends' impacts and their accumulation at one instant,
/// Newton's law on both at once), and under a slightly asymmetric one (1 %:
/// the ends 2e-4 s apart, then one end held while the other chatters into
/// it through the consistent mass).
#[test]
fn two_stops_reached_together_under_a_dashpot_match_the_oracle() {
    let sym = two_stops("two stops, symmetric", 0.3, 0.0);
    let (got, _) = sym.run();
    assert!(got.len() >= 2 && got[0].t == got[1].t && got[0].contact != got[1].contact, "{got:?}");
    check(&sym, 1e-3);
    check(&two_stops("two stops, asymmetric", 0.3, 0.01), 1e-3);
}

/// (c) Run 686 of the hunt: a two-sided stop under a dashpot, impacts on
/// both sides, then a chatter of 164 impacts (`e = 0.94`) accumulating.
/// Before each plane of the first-order flow took its best-conditioned
/// vector (flow.rs, `pair_vector`) it hit the hunt's 2·10⁵-event cap.
#[test]
fn hunt_run_686_a_two_sided_stop_under_a_dashpot_matches_the_oracle() {
    check(&run_686(), 1e-3);
}

/// (d) A free chain of eight consistent masses cut into three free parts
/// (`{0, 1, 2}`, `{3, 4, 5}`, `{6, 7}`: three rigid modes), a dashpot at
/// each end of the chain (the middle part's rigid mode undamped), falling
/// under a steady load onto stops under the interior dofs 1 and 4 (the
/// oracle's impacts take two contacts at most; the last part falls
/// freely): the first two parts land, chatter and are held in turn, so
/// the flights and held phases have three, two and one rigid modes at once
/// (the first-order form: six, four and two eigenvalues near 0; flow.rs,
/// `rigid_block`).
fn three_parts() -> Case {
    let (m, k) = cut_chain_matrices(8, &[3, 6]);
    Case {
        name: "three free parts",
        m,
        k,
        dashpots: vec![(0, 0.05), (7, 0.03)],
        f0: vec![-0.3; 8],
        shape: vec![0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 0.0, 0.1],
        wave: (0.5, 1.3, 0.4),
        stops: vec![Stop { dof: 1, lo: -0.1, hi: f64::INFINITY }, Stop { dof: 4, lo: -0.15, hi: f64::INFINITY }],
        e: 0.5,
        q0: vec![0.0; 8],
        v0: vec![-0.3, -0.3, -0.3, -0.1, -0.1, -0.1, 0.2, 0.2],
        t_end: 8.0,
        samples: vec![1.0, 2.0, 4.0, 6.0, 8.0],
    }
}

/// (d) Three free parts landing in turn, through flights and held phases
/// with three, two and one rigid modes (flow.rs, `rigid_block`), against
/// the oracle: 53 events, the worst error 0.14 of its tolerance. Plant:
/// the eigenvalue path (no block, as before) refuses the run (the
/// first-order basis' condition 6.1e11).
#[test]
fn three_free_parts_landing_in_turn_match_the_oracle() {
    let case = three_parts();
    let (got, _) = case.run();
    let kinds = |k: EventKind| got.iter().filter(|r| r.kind == k).map(|r| r.contact).collect::<Vec<usize>>();
    let held = kinds(EventKind::Accumulation);
    assert!((0..2).all(|c| held.contains(&c)), "each stopped part lands and is held: {got:?}");
    check(&case, 1e-3);
}
