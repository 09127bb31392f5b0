//! Event-driven cases chosen to fail on specific wrong versions of the
//! events code that every other test lets pass, each against an oracle
//! written here (closed forms evaluated densely, bisection, geometric
//! series), never against the code's own accessors:
//!
//! - the resonant term `m |U| Ω^{m−1}` of the particular solution's bounds
//!   (`ModalFlow::bounds`): resonant forcing, near-grazing levels, against
//!   the closed-form secular solution searched by brute force;
//! - the accumulation's relative 1e-9 (`driven.rs`): a ball chattering late
//!   in time (`t ≈ 1000`, where a looser relative filter stops it early),
//!   against the closed-form impact sequence and free flights;
//! - the sign of the held displacements in a free massless contact's
//!   condensed position (`massless.rs`): two coupled massless contacts,
//!   one held at a nonzero bound, against the hand-derived flow.

use signorini_fem::SymBand;
use signorini_schemes::events::{Bound, EventDriven, EventKind, ModalFlow};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};

/// A deterministic xorshift generator (the cases are fixed, not random).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, a: f64, b: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        a + (b - a) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// `x'' + w² x = A sin(w t + p)` (at resonance) from `(x0, v0)` at `t0`, in
/// closed form: the secular `P = −A/(2w) (t − t0) cos(w t + p)` (`P'' + w² P
/// = A sin(w t + p)`, `P(t0) = 0`) plus the free oscillation that matches the
/// start. Returns `(x, x')` at `t`.
struct Resonant {
    w: f64,
    a: f64,
    p: f64,
    t0: f64,
    c1: f64,
    c2: f64,
}

impl Resonant {
    fn new(w: f64, a: f64, p: f64, t0: f64, x0: f64, v0: f64) -> Self {
        let u = -a / (2.0 * w);
        Self { w, a, p, t0, c1: x0, c2: (v0 - u * (w * t0 + p).cos()) / w }
    }

    fn at(&self, t: f64) -> (f64, f64) {
        let (w, tau) = (self.w, t - self.t0);
        let u = -self.a / (2.0 * w);
        let th = w * t + self.p;
        let (s, c) = (w * tau).sin_cos();
        let x = tau * u * th.cos() + self.c1 * c + self.c2 * s;
        let v = u * th.cos() - tau * u * w * th.sin() - self.c1 * w * s + self.c2 * w * c;
        (x, v)
    }

    /// The first time in `(t0, t0 + horizon]` where `x` reaches `lo` from
    /// above or `hi` from below, by brute force: samples `dt` apart, each
    /// interval also searched for an interior extremum (a zero of `x'` by
    /// bisection) so that a dip narrower than `dt` is not missed, then the
    /// crossing by bisection. Also returns the smallest `|g'|` at a crossing
    /// or `|g|` at a non-crossing extremum (how well posed the case is).
    fn first_crossing(&self, lo: f64, hi: f64, horizon: f64) -> (Option<(f64, Bound)>, f64) {
        let gap = |t: f64| {
            let x = self.at(t).0;
            (x - lo).min(hi - x)
        };
        let side = |t: f64| if self.at(t).0 - lo < hi - self.at(t).0 { Bound::Lower } else { Bound::Upper };
        let bisect_root = |mut a: f64, mut b: f64| {
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if m <= a || m >= b {
                    break;
                }
                if gap(m) > 0.0 {
                    a = m;
                } else {
                    b = m;
                }
            }
            b
        };
        let dt = 1e-3 / self.w;
        let end = self.t0 + horizon;
        let mut near = f64::INFINITY;
        let mut t = self.t0;
        while t < end {
            let t1 = (t + dt).min(end);
            if gap(t1) <= 0.0 {
                let r = bisect_root(t, t1);
                near = near.min(self.at(r).1.abs());
                return (Some((r, side(r))), near);
            }
            // An extremum of x inside the interval: x' changes sign.
            let (d0, d1) = (self.at(t).1, self.at(t1).1);
            if d0 * d1 < 0.0 {
                let (mut a, mut b) = (t, t1);
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    if m <= a || m >= b {
                        break;
                    }
                    if self.at(m).1 * d0 > 0.0 {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                let g = gap(a);
                if g <= 0.0 {
                    let r = bisect_root(t, a);
                    near = near.min(self.at(r).1.abs());
                    return (Some((r, side(r))), near);
                }
                near = near.min(g);
            }
            t = t1;
        }
        (None, near)
    }

    /// The first local minimum (`lower`) or maximum of `x` after `t0`.
    fn first_extremum(&self, lower: bool, horizon: f64) -> Option<(f64, f64)> {
        let dt = 1e-3 / self.w;
        let mut t = self.t0;
        while t < self.t0 + horizon {
            let (d0, d1) = (self.at(t).1, self.at(t + dt).1);
            if (lower && d0 < 0.0 && d1 >= 0.0) || (!lower && d0 > 0.0 && d1 <= 0.0) {
                let (mut a, mut b) = (t, t + dt);
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    if self.at(m).1 * d0 > 0.0 {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                return Some((a, self.at(a).0));
            }
            t += dt;
        }
        None
    }
}

/// A harmonic force at the oscillator's own frequency: the particular
/// solution grows (`t cos`), and the bound of its derivatives over a window
/// `h` must keep the term `m |U| Ω^{m−1}` (the derivative of the secular
/// factor) besides `h |U| Ω^m`. Without it the curvature bound of a short
/// window is too small, the "safe" step passes the level: the crossing comes
/// late, or a brief dip below a level near a turning point (a near-graze)
/// is stepped over and missed. 400 fixed cases (`t0` near 100, where the
/// time resolution is 1e-13), half of them with the level put just inside
/// the trajectory's first turning point (a dip of depth 3e-5 to 3e-2 of
/// the turning point's size), horizons from `0.3/ω` to `20/ω`: each first
/// crossing (or none) as the closed form's, found by brute force. Cases
/// whose crossing is slower than `|x'| = 1e-2` (or that pass a level closer
/// than 1e-2) are left out: the current search can stall on those (a
/// separate defect).
#[test]
fn resonant_forcing_crossings_and_brief_dips_match_the_closed_form() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let (mut checked, mut dips, mut hits) = (0, 0, 0);
    let mut failures: Vec<(&str, String)> = Vec::new();
    for case in 0..400 {
        let w = rng.uniform(0.5, 3.0);
        let (a, p) = (rng.uniform(0.1, 3.0), rng.uniform(-3.1, 3.1));
        let t0 = rng.uniform(100.0, 103.0);
        let (x0, v0) = (rng.uniform(-0.05, 0.05), rng.uniform(-1.0, 1.0));
        let horizon = [0.3, 1.0, 2.0, 5.0, 20.0][case % 5] / w;
        let exact = Resonant::new(w, a, p, t0, x0, v0);
        let (mut lo, mut hi) = (rng.uniform(-1.0, -0.06), rng.uniform(0.06, 1.0));
        let depth = 10f64.powf(rng.uniform(-4.5, -1.5));
        if case % 2 == 1 {
            // A level just inside the first turning point: a brief dip.
            let lower = rng.uniform(0.0, 1.0) < 0.5;
            let Some((_, xe)) = exact.first_extremum(lower, horizon) else { continue };
            let scale = xe.abs().max(0.05);
            if lower && xe < -0.06 {
                lo = xe + depth * scale;
            } else if !lower && xe > 0.06 {
                hi = xe - depth * scale;
            } else {
                continue;
            }
            dips += 1;
        }
        let (want, near) = exact.first_crossing(lo, hi, horizon);
        // Well posed: no crossing slower (or extremum closer) than 1e-2.
        // (On slower crossings the current search can stall: its modal state
        // stops moving once a step changes x by less than its rounding, t
        // goes on; a separate defect.)
        if near < 1e-2 {
            continue;
        }
        checked += 1;
        let h = TimeProfile::harmonics(vec![Harmonic { amplitude: a, omega: w, phase: p }]).unwrap();
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[w * w]), vec![0.0], vec![Contact::new(0, Bounds { lo, hi }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0], time: h }]);
        let flow = ModalFlow::new(&dy).unwrap();
        let ctx = format!("case {case}: w = {w}, A = {a}, p = {p}, t0 = {t0}, x0 = {x0}, v0 = {v0}, [{lo}, {hi}], horizon {horizon}");
        let got = match flow.first_crossing(t0, &[x0], &[v0], 0, lo, hi, horizon) {
            Ok(got) => got,
            Err(e) => {
                failures.push(("error", format!("{ctx}: {e} (closed form: {want:?}, |x'| or |gap| {near:e})")));
                continue;
            }
        };
        match (got, want) {
            (None, None) => {}
            (Some(e), Some((t, side))) => {
                hits += 1;
                // The root to its conditioning: round-off of x (its size
                // grows with the secular term) over |x'|.
                let size = 1.0 + a * (t - t0 + 1.0) / w;
                let tol = 1e-12 * t.abs().max(1.0) + 1e-15 * size / near;
                if (e.t - t).abs() > tol || e.bound != side {
                    failures.push(("located wrongly", format!("{ctx}: the crossing at t = {} ({:?}) against the closed form's {t} ({side:?}), off by {:e}", e.t, e.bound, e.t - t)));
                }
            }
            (None, Some(w)) => failures.push(("missed", format!("{ctx}: the event search found nothing, the closed form a crossing at {w:?}"))),
            (Some(e), None) => failures.push(("spurious", format!("{ctx}: the event search found a crossing at {} ({:?}), the closed form none", e.t, e.bound))),
        }
    }
    let count = |kind: &str| failures.iter().filter(|f| f.0 == kind).count();
    let shown: Vec<&str> = ["missed", "spurious", "error", "located wrongly"].iter().flat_map(|k| failures.iter().filter(move |f| f.0 == *k).take(3)).map(|f| f.1.as_str()).collect();
    assert!(
        failures.is_empty(),
        "{} of {checked} cases wrong ({} missed, {} spurious, {} errors, {} located wrongly), e.g.:\n{}",
        failures.len(),
        count("missed"),
        count("spurious"),
        count("error"),
        count("located wrongly"),
        shown.join("\n")
    );
    // The cases are fixed: enough of each kind are checked.
    assert!(checked >= 250 && dips >= 60 && hits >= 150, "{checked} cases checked, {dips} dips, {hits} crossings");
}

/// A ball `x'' = −g` on a floor `x >= 0` with `0 < e < 1`, leaving it at
/// `t0 = 1000` with speed `u`: impacts at `t_k = t0 + (2u/g)(1 − e^k)/(1 − e)`
/// with speed `u e^{k−1}`, accumulating at `t∞ = t0 + 2u/(g (1 − e))`. The
/// accumulation may be declared only once `t∞ − t_k` is below a relative
/// 1e-9 of the time, or at a micro-impact (slower than 1e-6 of the first),
/// so every impact before both is taken, and between two of them the ball
/// flies. Late in time a looser relative filter (1e-6 · 1000 s = 1 ms)
/// declares it after a dozen impacts and holds the ball while it still
/// bounces: the state in the middle of a later flight (closed form) shows it.
#[test]
fn a_late_chatter_takes_every_impact_until_the_accumulation_is_due() {
    let (g, u, t0) = (1.0, 1.0, 1000.0);
    for e in [0.5, 0.9] {
        let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[0.0]), vec![-g], vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
        let mut r = EventDriven::new(&dy, t0, &[0.0], &[u], e).unwrap();
        let t_inf = t0 + 2.0 * u / (g * (1.0 - e));
        let t_k = |k: i32| t0 + 2.0 * u / g * (1.0 - e.powi(k)) / (1.0 - e);
        // The impacts the rules must take: faster than 1e-6 of the first,
        // and t∞ − t_k above 1e-9 t_k (both from the closed form).
        let due = (1..).find(|&k| u * e.powi(k - 1) <= 1e-6 * u || t_inf - t_k(k) <= 1e-9 * t_k(k)).unwrap();
        let must = due - 1;
        // Mid-flight after impact `k`: a quarter of the flight in, `x = 3 v²/(8g)`, `x' = v/2`.
        for k in [must / 2, must - 2] {
            let v = u * e.powi(k);
            let tm = t_k(k) + 0.5 * v / g;
            r.run_until(tm, 100_000).unwrap();
            let (_, q, qd) = r.state();
            let (xw, vw) = (3.0 * v * v / (8.0 * g), 0.5 * v);
            assert!(
                (q[0] - xw).abs() <= 1e-3 * xw && (qd[0] - vw).abs() <= 1e-3 * vw,
                "e = {e}: a quarter into the flight after impact {k} (t = {tm}) the state is ({}, {}), the closed form's ({xw}, {vw}); events: {} impacts, then {:?}",
                q[0],
                qd[0],
                r.events().iter().filter(|x| x.kind == EventKind::Impact).count(),
                r.events().iter().find(|x| x.kind == EventKind::Accumulation)
            );
        }
        r.run_until(t_inf + 1.0, 100_000).unwrap();
        let ev = r.events();
        let acc = ev.iter().position(|x| x.kind == EventKind::Accumulation).expect("an accumulation");
        assert!(acc as i32 >= must, "e = {e}: the accumulation after {acc} impacts; impacts 1..={must} are due first (t∞ − t_k = {:e} at the last taken)", t_inf - ev[acc - 1].t);
        for (i, x) in ev[..acc].iter().enumerate() {
            let k = i as i32 + 1;
            assert_eq!(x.kind, EventKind::Impact);
            assert!((x.t - t_k(k)).abs() <= 1e-12 * t0, "e = {e}: impact {k} at {} against {}", x.t, t_k(k));
            assert!((x.velocity_before + u * e.powi(k - 1)).abs() <= 1e-9 * u, "e = {e}: impact {k}: v⁻ = {}", x.velocity_before);
        }
        assert!((ev[acc].t - t_inf).abs() <= 1e-12 * t_inf, "e = {e}: accumulation at {} against {t_inf}", ev[acc].t);
        assert_eq!(acc, ev.len() - 1);
        let (_, q, qd) = r.state();
        assert_eq!((q[0], qd[0]), (0.0, 0.0));
    }
}

/// Two massless contact dofs coupled by a spring, and one mass: dofs
/// `[z1, z2, x]`, springs `z1–z2`, `z2–x`, `x–ground` (all 1), `M =
/// diag(0, 0, 1)`, the load `−1` on `z1`. `z1` is held at `lo1 = −0.1`
/// (its force `1 − 0.1 − z2 > 0`); `z2` is free at its static position
/// `z2 = (lo1 + x)/2` — the held displacement `lo1` enters it through the
/// spring, a nonzero constant term. Then `x'' = −2x + z2 = −1.5 x − 0.05`,
/// `x = x* + (x0 − x*) cos ωt + (v0/ω) sin ωt` (`x* = −1/30`, `ω² = 1.5`),
/// and `z2` lands on `lo2 = −0.3` when `x = 2 lo2 − lo1 = −0.5`. Held there
/// too, `x'' = −2x + lo2` until `z2`'s force `−lo1 + 2 lo2 − x` vanishes,
/// at `x = −0.5` again: its release. Both times by bisection on the closed
/// forms.
#[test]
fn a_free_massless_contact_sees_its_held_neighbour_at_a_nonzero_bound() {
    let (lo1, lo2) = (-0.1, -0.3);
    let (mut m, mut k) = (SymBand::zeros(3, 1), SymBand::zeros(3, 1));
    m.set(2, 2, 1.0);
    for (i, j, v) in [(0, 0, 1.0), (1, 0, -1.0), (1, 1, 2.0), (2, 1, -1.0), (2, 2, 2.0)] {
        k.set(i, j, v);
    }
    let contacts = vec![Contact::new(0, Bounds::obstacle(lo1), true), Contact::new(1, Bounds::obstacle(lo2), true)];
    let dy = Dynamics::new(m, k, vec![-1.0, 0.0, 0.0], contacts);
    let (x0, v0) = (0.0, -1.0);
    // The static start with z1 held: z2 = (lo1 + x0)/2.
    let q0 = [lo1, 0.5 * (lo1 + x0), x0];
    let mut r = EventDriven::new(&dy, 0.0, &q0, &[0.0, 0.0, v0], 0.0).unwrap();
    assert_eq!(r.held(), vec![(0, false)]);
    let bisect = |f: &dyn Fn(f64) -> f64, mut a: f64, mut b: f64| {
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            if f(mid) > 0.0 {
                a = mid;
            } else {
                b = mid;
            }
        }
        0.5 * (a + b)
    };
    // Phase 1: x'' + 1.5 x = −0.05.
    let (w1, xs1) = (1.5f64.sqrt(), -0.05 / 1.5);
    let x1 = |t: f64| xs1 + (x0 - xs1) * (w1 * t).cos() + v0 / w1 * (w1 * t).sin();
    let dx1 = |t: f64| -(x0 - xs1) * w1 * (w1 * t).sin() + v0 * (w1 * t).cos();
    let land = 2.0 * lo2 - lo1;
    // x decreases from 0 to its minimum (≈ −0.85) before t = 2: one crossing.
    let t_land = bisect(&|t| x1(t) - land, 0.0, 2.0);
    assert!(x1(2.0) < land && dx1(t_land) < -0.1);
    let ev = r.next_event(10.0).unwrap().expect("z2's landing");
    assert!(ev.kind == EventKind::Impact && ev.contact == 1, "{ev:?}");
    assert!((ev.t - t_land).abs() <= 1e-12, "z2 lands at {} against the closed form's {t_land}", ev.t);
    let (_, q, v) = r.state();
    assert!((q[2] - land).abs() <= 1e-12 && (v[2] - dx1(t_land)).abs() <= 1e-12, "x = {}, x' = {} against {land}, {}", q[2], v[2], dx1(t_land));
    assert_eq!((q[0], q[1]), (lo1, lo2));
    // Phase 2: x'' + 2x = lo2 from (land, dx1(t_land)); z2's force vanishes at x = land.
    let (w2, xs2, va) = (2f64.sqrt(), 0.5 * lo2, dx1(t_land));
    let x2 = |t: f64| xs2 + (land - xs2) * (w2 * (t - t_land)).cos() + va / w2 * (w2 * (t - t_land)).sin();
    // Below `land` (moving down, away from x* = lo2/2 = −0.15) it comes back
    // to it within half a period, where x = −lo2/2 ... above it.
    let half = std::f64::consts::PI / w2;
    assert!(x2(t_land + half) > land);
    let t_rel = bisect(&|t| land - x2(t), t_land + 1e-9, t_land + half);
    let ev = r.next_event(10.0).unwrap().expect("z2's release");
    assert!(ev.kind == EventKind::Release && ev.contact == 1, "{ev:?}");
    assert!((ev.t - t_rel).abs() <= 1e-12, "z2 leaves at {} against the closed form's {t_rel}", ev.t);
}

/// One case of the family above, run by `EventDriven` with impacts
/// (`e = 0.8`): the resonant oscillator reaches the upper stop 0.1 s before
/// the end of the first search's window. Its event list — each impact
/// where the closed-form flight from the previous one reaches a stop
/// (brute force), the velocity after it `−e v⁻` — starts with that impact;
/// a search whose window bound is too small steps to the window's end over
/// it (no event by then), and the whole list changes.
#[test]
fn a_resonant_crossing_near_the_window_end_starts_the_event_list() {
    let (w, a, p) = (0.5253433526886846, 2.7077873301212425, -2.8569905190090816);
    let (t0, x0, v0) = (101.28026692286602, -0.022729091608001486, -0.7450105632362398);
    let (lo, hi, e) = (-0.5335901577133362, 0.4205337389424564, 0.8);
    let t_end = t0 + 1.9035169948987518;
    let h = TimeProfile::harmonics(vec![Harmonic { amplitude: a, omega: w, phase: p }]).unwrap();
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[w * w]), vec![0.0], vec![Contact::new(0, Bounds { lo, hi }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: h }]);
    // The closed-form flight from the start, and how briefly it is above hi.
    let first = Resonant::new(w, a, p, t0, x0, v0);
    let (Some((t1, Bound::Upper)), near) = first.first_crossing(lo, hi, t_end - t0) else { panic!("the closed form reaches the upper stop") };
    assert!(near > 1e-2 && t_end - t1 > 0.09, "{near}, {t1}");
    // The oracle's event list: impacts chained through closed-form flights.
    let mut want = Vec::new();
    let (mut ts, mut xs, mut vs) = (t0, x0, v0);
    let stop = t0 + 30.0;
    while want.len() < 4 {
        let flight = Resonant::new(w, a, p, ts, xs, vs);
        let (Some((tc, side)), near) = flight.first_crossing(lo, hi, stop - ts) else { break };
        assert!(near > 1e-3, "impact {}: a near-graze of {near}", want.len());
        let vc = flight.at(tc).1;
        want.push((tc, side, vc));
        (ts, xs, vs) = (tc, if side == Bound::Upper { hi } else { lo }, -e * vc);
    }
    assert!(want.len() == 4 && (want[0].0 - t1).abs() < 1e-15 * t1);
    let mut run = EventDriven::new(&dy, t0, &[x0], &[v0], e).unwrap();
    // The first search's window ends at t_end, as the family's horizon.
    let ev = run.next_event(t_end).unwrap();
    assert!(ev.is_some_and(|x| x.kind == EventKind::Impact), "no impact by t = {t_end}: the closed form's crossing at {t1} was stepped over; {ev:?}");
    run.run_until(want[3].0 + 1e-6, 100).unwrap();
    let got = run.events();
    assert!(got.len() >= 4, "{got:?}");
    for (k, (g, &(tc, side, vc))) in got.iter().zip(&want).enumerate() {
        // An impact at the upper stop comes in upward.
        let at_upper = g.velocity_before > 0.0;
        assert!((g.t - tc).abs() <= 1e-9 && at_upper == (side == Bound::Upper), "impact {k}: at {} against the closed form's {tc} ({side:?})", g.t);
        assert!((g.velocity_before - vc).abs() <= 1e-9 && (g.velocity_after + e * vc).abs() <= 1e-9, "impact {k}: v⁻ = {}, v⁺ = {} against {vc}, {}", g.velocity_before, g.velocity_after, -e * vc);
    }
}

/// The safe step's root `(g' + sqrt(g'² + 2 B g))/B` cancelled when
/// `g' < 0` and `2 B g ≪ g'²`: once `2 B g < ε g'²` it rounded to 0 and the
/// event was declared with the gap still open (now `2g/(sqrt(…) − g')`).
/// A mass at `x = 1` moving at `−1` under the load `−1e-9` reaches `x = 0`
/// at `2/(1 + sqrt(1 + 2e-9))`; the search stopped 1.4e-7 earlier with the
/// gap 1.4e-7 (the event-driven run then clamped it).
#[test]
fn a_fast_approach_with_a_tiny_curvature_is_located_at_its_root() {
    let a = 1e-9;
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[0.0]), vec![-a], vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
    let flow = ModalFlow::new(&dy).unwrap();
    let ev = flow.first_crossing(0.0, &[1.0], &[-1.0], 0, 0.0, f64::INFINITY, 10.0).unwrap().unwrap();
    let want = 2.0 / (1.0 + (1.0 + 2.0 * a).sqrt());
    assert!((ev.t - want).abs() <= 1e-15 && ev.q[0].abs() <= 1e-15, "t = {} against {want}, the gap there {}", ev.t, ev.q[0]);
}

/// Under resonance, a crossing at `|x'| = 3e-3` (not a graze) stalled the
/// search: one ulp above the level the root step `ulp/|x'|` exceeded the
/// time resolution, but advancing the modal state by it changed nothing
/// (the secular and free parts rounded separately), so `t` walked on with
/// the state frozen, past the crossing, until `NoConvergence` after 10⁷
/// steps (about 5 s). Every state is now evaluated from the phase's base
/// as an increment (docs/theory.md §9.1, §9.2).
#[test]
fn a_slow_resonant_crossing_is_found() {
    let (w, a, p) = (1.353745749890675, 1.7977823469710135, -0.1327268124243326);
    let (t0, x0, v0) = (1.2174549929118172, 0.04740652809306735, -0.85334387000829);
    let (lo, hi) = (-0.2130014468821061, 0.4012172540726203);
    // The search's first window (its steps, so whether it stalls, depend on it).
    let horizon = 14.773822929169047;
    let h = TimeProfile::harmonics(vec![Harmonic { amplitude: a, omega: w, phase: p }]).unwrap();
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[w * w]), vec![0.0], vec![Contact::new(0, Bounds { lo, hi }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: h }]);
    let flow = ModalFlow::new(&dy).unwrap();
    let (Some((want, Bound::Upper)), near) = Resonant::new(w, a, p, t0, x0, v0).first_crossing(lo, hi, horizon) else { panic!("a crossing") };
    assert!(near > 2e-3);
    let ev = flow.first_crossing(t0, &[x0], &[v0], 0, lo, hi, horizon);
    assert!(matches!(&ev, Ok(Some(e)) if (e.t - want).abs() <= 1e-12), "{ev:?} against the closed form's crossing at {want}");
}
