//! Tests of the vibro-impact observers (`signorini_run::vibro`) against
//! closed forms written here: synthetic samples of a parabola hitting a stop
//! at a known time and speed (the quadratic crossing estimate is exact to
//! rounding), a cubic and a sine sampled at the stroboscopic times (the
//! Poincaré interpolation is exact for the cubic and falls at O(dt⁴) /
//! O(dt³) for the sine), hand-summed impulses and statistics, period-3 and
//! non-periodic sequences for the period test, and a real Paoli–Schatzman
//! run of a mass falling on a stop (impact time and velocity of free fall,
//! impulse `(1+r) m |V|`, and the discrete momentum balance).

use signorini_contact::Active;
use signorini_fem::SymBand;
use signorini_run::{response_period, run, Crossing, ImpactObserver, Observer, Piece, PoincareObserver, PoincarePoint, RunConfig, RunError, Sample, Summary, VibroConfig, WindowObserver};
use signorini_schemes::{Bounds, Contact, Dynamics, Initial, PaoliSchatzman};
use std::f64::consts::TAU;

/// One synthetic level: displacement vector, per-contact forces and status.
struct Level {
    u: Vec<f64>,
    forces: Vec<f64>,
    status: Vec<Active>,
}

/// Feeds `levels` (at `t_n = n dt`) to `obs`, then finishes it.
fn feed(obs: &mut dyn Observer, dt: f64, levels: &[Level]) -> Result<(), RunError> {
    for (n, l) in levels.iter().enumerate() {
        let t = n as f64 * dt;
        let lambda = (n > 0).then_some((t, l.forces[0]));
        let active = l.status.iter().any(|a| *a != Active::None);
        obs.observe(&Sample::new(n, t, &l.u).with_contacts(lambda, active, &l.forces, &l.status))?;
    }
    obs.finish()
}

/// A single-contact level.
fn one(u: f64, force: f64, status: Active) -> Level {
    Level { u: vec![u], forces: vec![force], status: vec![status] }
}

/// Parses a CSV text into its header and rows of cells (empty cells NaN).
fn parse_csv(bytes: &[u8]) -> (String, Vec<Vec<f64>>) {
    let text = std::str::from_utf8(bytes).expect("utf8");
    let mut lines = text.lines();
    let header = lines.next().expect("header").to_string();
    let rows = lines.map(|l| l.split(',').map(|c| if c.is_empty() { f64::NAN } else { c.parse().expect("number") }).collect()).collect();
    (header, rows)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// A parabola `u(t) = h − g t²/2` falls onto the stop `lo = 0`: impact at
/// `t_c = sqrt(2h/g)` with `V = −g t_c`. The levels after the crossing sit
/// on the stop for three levels with forces `−2, −3, −1.5`, then rebound.
/// The quadratic through the last three free levels is the parabola itself:
/// `t*`, `V` exact to rounding; `J = dt·6.5`, duration `3 dt`; the phase is
/// `Ω t_c − 2π ⌊Ω t_c / 2π⌋` with `Ω t_c ≈ 24.7` (three wraps, a phase above π); the CSV row
/// holds the same numbers.
#[test]
fn parabola_impact_time_velocity_phase_exact() {
    let (h, g, dt, omega): (f64, f64, f64, f64) = (4.1, 0.97, 0.0137, 8.5);
    let tc = (2.0 * h / g).sqrt();
    let v = -g * tc;
    let first = (tc / dt).ceil() as usize;
    assert!(first as f64 * dt > tc && first >= 3);
    let mut levels: Vec<Level> = (0..first).map(|n| one(h - 0.5 * g * (n as f64 * dt).powi(2), 0.0, Active::None)).collect();
    for f in [-2.0, -3.0, -1.5] {
        levels.push(one(0.0, f, Active::Lower));
    }
    for j in 1..6 {
        levels.push(one(0.01 * j as f64, 0.0, Active::None));
    }
    let mut csv = Vec::new();
    let mut obs = ImpactObserver::new(&[(0, Bounds::obstacle(0.0))], dt, Some(omega), 0.0, 4, Some(&mut csv)).unwrap();
    feed(&mut obs, dt, &levels).unwrap();
    let imps = obs.impacts().to_vec();
    assert_eq!(imps.len(), 1);
    let imp = imps[0];
    assert_eq!(imp.crossing, Crossing::Quadratic);
    assert_eq!(imp.first_level, first);
    assert!(rel(imp.t, tc) < 1e-12, "t* = {} vs {tc}", imp.t);
    assert!(rel(imp.velocity, v) < 1e-10, "v = {} vs {v}", imp.velocity);
    assert!(rel(imp.impulse, 6.5 * dt) < 1e-14, "J = {}", imp.impulse);
    assert!(rel(imp.duration, 3.0 * dt) < 1e-14);
    let wraps = (omega * tc / TAU).floor();
    assert_eq!(wraps, 3.0);
    assert!(omega * tc - TAU * wraps > std::f64::consts::PI, "a phase in (π, 2π) tells a 2π wrap from a π one");
    let phase = omega * tc - TAU * wraps;
    assert!((imp.phase - phase).abs() < 1e-10, "phase {} vs {phase}", imp.phase);
    drop(obs);
    let (header, rows) = parse_csv(&csv);
    assert_eq!(header, "stop,t,phase,velocity,impulse,duration");
    assert_eq!(rows.len(), 1);
    let r = &rows[0];
    assert_eq!(r[0], 0.0);
    assert!(rel(r[1], tc) < 1e-11 && (r[2] - phase).abs() < 1e-10 && rel(r[3], v) < 1e-10 && rel(r[4], 6.5 * dt) < 1e-11 && rel(r[5], 3.0 * dt) < 1e-11, "{r:?}");
}

/// The mirror image at an upper stop `hi = 1` (with a lower stop at −5 that
/// is never reached): `u(t) = 1 − 0.3 + a (t − 0)²/2` rising, crossing `hi`
/// at `t_c = sqrt(0.6/a)` with `V = a t_c > 0`; the bound used must be `hi`.
/// A single active level (a rebound) with force `+4`: `J = −4 dt`. Without
/// `Ω` the phase is NaN (an empty CSV cell).
#[test]
fn upper_stop_single_level_rebound() {
    let (a, dt) = (2.3, 0.021);
    let tc = (0.6_f64 / a).sqrt();
    let first = (tc / dt).ceil() as usize;
    let mut levels: Vec<Level> = (0..first).map(|n| one(0.7 + 0.5 * a * (n as f64 * dt).powi(2), 0.0, Active::None)).collect();
    levels.push(one(0.98, 4.0, Active::Upper));
    levels.push(one(0.9, 0.0, Active::None));
    let mut csv = Vec::new();
    let mut obs = ImpactObserver::new(&[(0, Bounds { lo: -5.0, hi: 1.0 })], dt, None, 0.0, 4, Some(&mut csv)).unwrap();
    feed(&mut obs, dt, &levels).unwrap();
    let imp = obs.impacts()[0];
    assert_eq!(imp.side, Active::Upper);
    assert!(rel(imp.t, tc) < 1e-12 && rel(imp.velocity, a * tc) < 1e-10, "{imp:?}");
    assert!(rel(imp.impulse, -4.0 * dt) < 1e-14 && rel(imp.duration, dt) < 1e-14);
    assert!(imp.phase.is_nan());
    drop(obs);
    let (_, rows) = parse_csv(&csv);
    assert!(rows[0][2].is_nan() && rel(rows[0][1], tc) < 1e-11);
}

/// Fewer than three free levels before an impact: the line through the two
/// levels before it (here the previous impact's last level `u = 0` and the
/// one free level `u = 0.2`); it moves away from the stop, so `t* =
/// t_{m−1}` and `v = 0.2/dt`. The first
/// impact (level 1, one level before it) uses the line through levels 0 and
/// 1: `u: 1 → −1` crosses 0 at `t = dt/2` with `v = −2/dt`.
#[test]
fn fallbacks_with_few_free_levels() {
    let dt = 0.1;
    let levels =
        vec![one(1.0, 0.0, Active::None), one(-1.0, -1.0, Active::Lower), one(0.0, -1.0, Active::Lower), one(0.2, 0.0, Active::None), one(0.1, -2.0, Active::Lower), one(0.3, 0.0, Active::None)];
    let mut obs = ImpactObserver::<std::io::Sink>::new(&[(0, Bounds::obstacle(0.0))], dt, None, 0.0, 4, None).unwrap();
    feed(&mut obs, dt, &levels).unwrap();
    let imps = obs.impacts();
    assert_eq!(imps.len(), 2);
    assert_eq!(imps[0].crossing, Crossing::Linear);
    assert!(rel(imps[0].t, 0.05) < 1e-14 && rel(imps[0].velocity, -20.0) < 1e-14, "{:?}", imps[0]);
    assert!(rel(imps[0].impulse, 0.2) < 1e-14 && rel(imps[0].duration, 0.2) < 1e-14);
    assert_eq!(imps[1].crossing, Crossing::Linear);
    assert!(rel(imps[1].t, 0.3) < 1e-14 && rel(imps[1].velocity, 2.0) < 1e-14, "{:?}", imps[1]);
    assert!(rel(imps[1].impulse, 0.2) < 1e-14);
}

/// Two contacts with hand-chosen levels and forces: contact 0 (lower stop
/// 0) hits at levels 4–5 (forces −1, −2) and 12 (force −4), contact 1
/// (upper stop 1) at levels 8–10 (forces 1, 1, 0.5); the free levels before
/// each impact lie on lines, so the crossing is the line's. `record_from`
/// drops the first impact (`t* = 1.75`) from memory, not from the CSV. Checks
/// impulses, durations, times, velocities, the count, mean and max `|J|`,
/// the impact power `Σ|J||v|/W` and impacts per period, from hand values;
/// with one and three more contacts that never touch (wide stops, never
/// active): the same impacts (the observer holds up to two contacts in
/// itself and more elsewhere).
#[test]
fn impulses_and_statistics_by_hand() {
    for idle in [0, 1, 3] {
        impulses_and_statistics_by_hand_with(idle);
    }
}

fn impulses_and_statistics_by_hand_with(idle: usize) {
    let dt = 0.5;
    let omega = TAU / 3.5; // period 3.5
    let mut levels = Vec::new();
    for n in 0..16usize {
        // Contact 0: 1.75 − 0.5 n (crosses 0 at n = 3.5: t* = 1.75, v = −1).
        let (mut u0, mut f0, mut s0) = (1.75 - 0.5 * n as f64, 0.0, Active::None);
        if n == 4 || n == 5 {
            (u0, f0, s0) = (0.0, if n == 4 { -1.0 } else { -2.0 }, Active::Lower);
        }
        // Then 0.1 (12 − n) − 0.05: 0.25, 0.15, 0.05 at levels 9–11,
        // crossing 0 at level 11.5: t* = 5.75, v = −0.1/dt = −0.2.
        if (6..12).contains(&n) {
            u0 = 0.1 * (12 - n) as f64 - 0.05;
        }
        if n == 12 {
            (u0, f0, s0) = (0.0, -4.0, Active::Lower);
        }
        if n > 12 {
            u0 = 0.3 * (n - 12) as f64;
        }
        // Contact 1: 0.25 + 0.1 n crosses 1 at level 7.5: t* = 3.75, v = 0.2.
        let (mut u1, mut f1, mut s1) = (0.25 + 0.1 * n as f64, 0.0, Active::None);
        if (8..=10).contains(&n) {
            (u1, f1, s1) = (1.0, [1.0, 1.0, 0.5][n - 8], Active::Upper);
        }
        if n > 10 {
            u1 = 0.9;
        }
        let (mut u, mut forces, mut status) = (vec![u0, u1], vec![f0, f1], vec![s0, s1]);
        for _ in 0..idle {
            u.push(0.5);
            forces.push(0.0);
            status.push(Active::None);
        }
        levels.push(Level { u, forces, status });
    }
    let mut csv = Vec::new();
    let record_from = 3.5;
    let mut contacts = vec![(0, Bounds::obstacle(0.0)), (1, Bounds { lo: f64::NEG_INFINITY, hi: 1.0 })];
    contacts.extend((0..idle).map(|k| (2 + k, Bounds { lo: -100.0, hi: 100.0 })));
    let mut obs = ImpactObserver::new(&contacts, dt, Some(omega), record_from, 1, Some(&mut csv)).unwrap();
    feed(&mut obs, dt, &levels).unwrap();
    assert_eq!(obs.total(), 3);
    let imps = obs.impacts().to_vec();
    assert_eq!(imps.len(), 2, "{imps:?}");
    // In order of completion: contact 1 at level 11, contact 0 at level 13.
    let (c1, c0) = (imps[0], imps[1]);
    assert_eq!((c1.stop, c0.stop), (1, 0));
    assert!(rel(c1.t, 3.75) < 1e-13 && rel(c1.velocity, 0.2) < 1e-12, "{c1:?}");
    assert!(rel(c1.impulse, -1.25) < 1e-14 && rel(c1.duration, 1.5) < 1e-14);
    assert!(rel(c0.t, 5.75) < 1e-13 && rel(c0.velocity, -0.2) < 1e-12, "{c0:?}");
    assert!(rel(c0.impulse, 2.0) < 1e-14 && rel(c0.duration, 0.5) < 1e-14);
    assert!(rel(c0.phase, TAU * 2.25 / 3.5) < 1e-13, "phase of t = 5.75 (period 3.5): 2π·2.25/3.5 > π, got {}", c0.phase);
    let st = obs.stats();
    let w = 15.0 * dt - record_from;
    assert_eq!(w, 4.0);
    assert_eq!(st.count, 2);
    assert!(rel(st.mean_impulse, (1.25 + 2.0) / 2.0) < 1e-14 && rel(st.max_impulse, 2.0) < 1e-14);
    assert!(rel(st.power, (1.25 * 0.2 + 2.0 * 0.2) / w) < 1e-12, "{}", st.power);
    assert!(rel(st.per_period, 2.0 / (w / 3.5)) < 1e-13, "{}", st.per_period);
    drop(obs);
    let (_, rows) = parse_csv(&csv);
    assert_eq!(rows.len(), 3);
    // The transient impact: levels 4–5 of contact 0, t* = 1.75, J = 1.5.
    assert_eq!(rows[0][0], 0.0);
    assert!(rel(rows[0][1], 1.75) < 1e-11 && rel(rows[0][3], -1.0) < 1e-11 && rel(rows[0][4], 1.5) < 1e-11 && rel(rows[0][5], 1.0) < 1e-11, "{:?}", rows[0]);
}

/// A cubic `u(t)` sampled at levels: the Poincaré points (displacement and
/// velocity) are the cubic and its derivative at `t_k = k·2π/Ω` to rounding,
/// for every `k` with `record_from <= t_k <= T` (counted by hand; also when
/// the last one falls in the last step), with `t_k` bitwise `k·(2π/Ω)`; the
/// CSV holds the same rows.
#[test]
fn poincare_exact_for_a_cubic() {
    let (dt, omega, record_from) = (0.01, 2.9, 0.5);
    let period = TAU / omega;
    let u = |t: f64| 0.3 - 1.1 * t + 0.45 * t * t - 0.07 * t * t * t;
    let du = |t: f64| -1.1 + 0.9 * t - 0.21 * t * t;
    // Horizons: 10, and the level just past t_4 (so t_4 falls in the last
    // step and is emitted only at `finish`).
    let last = (4.0 * period / dt).ceil() as usize;
    assert!(((last - 1) as f64) * dt < 4.0 * period);
    for steps in [1000usize, last] {
        let levels: Vec<Level> = (0..=steps).map(|n| Level { u: vec![7.0, u(n as f64 * dt)], forces: vec![0.0], status: vec![Active::None] }).collect();
        let mut csv = Vec::new();
        let mut obs = PoincareObserver::new(1, dt, omega, record_from, 0, Some(&mut csv)).unwrap();
        feed(&mut obs, dt, &levels).unwrap();
        let t_end = steps as f64 * dt;
        let expect: Vec<u64> = (0..100).filter(|&k| k as f64 * period >= record_from && k as f64 * period <= t_end).collect();
        assert_eq!(expect, vec![1, 2, 3, 4]);
        let pts = obs.points().to_vec();
        assert_eq!(pts.iter().map(|p| p.k).collect::<Vec<_>>(), expect, "horizon {t_end}");
        for p in &pts {
            assert_eq!(p.t, p.k as f64 * (TAU / omega));
            assert!((p.displacement - u(p.t)).abs() < 1e-12, "{p:?} vs {}", u(p.t));
            assert!((p.velocity - du(p.t)).abs() < 1e-10, "{p:?} vs {}", du(p.t));
        }
        drop(obs);
        let (header, rows) = parse_csv(&csv);
        assert_eq!(header, "t,displacement,velocity");
        assert_eq!(rows.len(), 4);
        for (r, p) in rows.iter().zip(&pts) {
            assert!(rel(r[0], p.t) < 1e-11 && rel(r[1], u(p.t)) < 1e-11 && rel(r[2], du(p.t)) < 1e-9);
        }
    }
}

/// A section at forcing phase θ samples at `t_k = (k + θ/2π)·2π/Ω`, from
/// the first such time in the record window; θ outside `[0, 2π)` is refused.
#[test]
fn poincare_section_at_a_phase() {
    let (dt, omega, record_from, theta) = (0.01, 2.9, 0.5, 2.0);
    let period = TAU / omega;
    let u = |t: f64| 0.3 - 1.1 * t + 0.45 * t * t - 0.07 * t * t * t;
    let levels: Vec<Level> = (0..=1000).map(|n| Level { u: vec![u(n as f64 * dt)], forces: vec![0.0], status: vec![Active::None] }).collect();
    let mut obs = PoincareObserver::new(0, dt, omega, record_from, 0, None::<Vec<u8>>).unwrap().with_phase(theta).unwrap();
    feed(&mut obs, dt, &levels).unwrap();
    // Independently: the times k T + θ/Ω in [0.5, 10].
    let expect: Vec<f64> = (0..100).map(|k| k as f64 * period + theta / omega).filter(|&t| t >= record_from && t <= 10.0).collect();
    assert_eq!(expect.len(), 5);
    let pts = obs.points();
    assert_eq!(pts.len(), expect.len());
    for (p, t) in pts.iter().zip(&expect) {
        assert!((p.t - t).abs() < 1e-12 && (p.displacement - u(*t)).abs() < 1e-12, "{p:?} vs t = {t}");
        // The forcing phase of the sample is θ.
        assert!(((omega * p.t) % TAU - theta).abs() < 1e-12);
    }
    for bad in [-0.1, TAU, f64::NAN] {
        assert!(PoincareObserver::new(0, dt, omega, 0.0, 0, None::<Vec<u8>>).unwrap().with_phase(bad).is_err(), "{bad}");
    }
}

/// `u = sin(w t + 0.4)`: the largest errors of the Poincaré points over
/// `[0, 20]` fall by ≈ 16 (displacement, O(dt⁴)) and ≈ 8 (velocity,
/// O(dt³)) when `dt` halves.
#[test]
fn poincare_sine_orders() {
    let (w, omega) = (1.7, 1.3);
    let errs = |dt: f64| {
        let steps = (20.0 / dt).round() as usize;
        let levels: Vec<Level> = (0..=steps).map(|n| one((w * n as f64 * dt + 0.4).sin(), 0.0, Active::None)).collect();
        let mut obs = PoincareObserver::<std::io::Sink>::new(0, dt, omega, 0.0, 0, None).unwrap();
        feed(&mut obs, dt, &levels).unwrap();
        assert_eq!(obs.points().len(), 5);
        obs.points().iter().fold((0.0_f64, 0.0_f64), |(a, b), p| (a.max((p.displacement - (w * p.t + 0.4).sin()).abs()), b.max((p.velocity - w * (w * p.t + 0.4).cos()).abs())))
    };
    let (e1, e2) = (errs(0.04), errs(0.02));
    let (ru, rv) = (e1.0 / e2.0, e1.1 / e2.1);
    eprintln!("sine: dt 0.04 errors {e1:?}, dt 0.02 errors {e2:?}, ratios {ru:.2} {rv:.2}");
    assert!(ru > 12.0 && ru < 20.0, "displacement ratio {ru}");
    assert!(rv > 6.0 && rv < 10.0, "velocity ratio {rv}");
}

fn pt(k: u64, x: f64, v: f64) -> PoincarePoint {
    PoincarePoint { k, t: k as f64, displacement: x, velocity: v }
}

/// A period-3 sequence (values of spread ≈ 2·S, offset by 1000 S, noise
/// 1e-6·S) is period 3 for `tol = 1e-4` relative to the scales `S`, for
/// S = 1 and S = 1e3 (an absolute tolerance fails one of them); repeats
/// drifting by 0.3 tolerances stay period 3, by 3 tolerances they are not
/// (a tolerance off by 10 either way fails one of them); a quasi-periodic
/// sequence is not periodic; a constant one is period 1; five period-3
/// points are too few (2p = 6).
#[test]
fn period_detection() {
    let base = [(0.3, -1.0), (1.2, 0.5), (-0.8, 0.9)];
    for s in [1.0, 1e3] {
        let seq: Vec<PoincarePoint> = (0..20)
            .map(|j| {
                let (x, v) = base[j % 3];
                let noise = 1e-6 * ((j * 7919 % 13) as f64 / 13.0 - 0.5);
                pt(j as u64, s * (1000.0 + x + noise), s * (v - noise))
            })
            .collect();
        assert_eq!(response_period(&seq, 8, 1e-4, 2.0 * s, 1.9 * s), Some(3), "scale {s}");
        // Repeats differing by 0.3 and by 3 tolerances (tol · scale_x = 2e-4 s).
        let drift = |d: f64| -> Vec<PoincarePoint> { seq.iter().enumerate().map(|(j, p)| pt(p.k, p.displacement + d * 2e-4 * s * (j / 3) as f64, p.velocity)).collect() };
        assert_eq!(response_period(&drift(0.3), 8, 1e-4, 2.0 * s, 1.9 * s), Some(3), "small drift, scale {s}");
        assert_eq!(response_period(&drift(3.0), 8, 1e-4, 2.0 * s, 1.9 * s), None, "drift, scale {s}");
    }
    let phi = (5.0_f64.sqrt() - 1.0) / 2.0;
    let quasi: Vec<PoincarePoint> = (0..40).map(|j| pt(j, (TAU * phi * j as f64).cos(), (TAU * phi * j as f64).sin())).collect();
    assert_eq!(response_period(&quasi, 8, 1e-3, 2.0, 2.0), None);
    let period1: Vec<PoincarePoint> = (0..10).map(|j| pt(j, 0.25, -0.5)).collect();
    assert_eq!(response_period(&period1, 8, 1e-3, 1.0, 1.0), Some(1));
    let short: Vec<PoincarePoint> = (0..5).map(|j| pt(j, base[j as usize % 3].0, base[j as usize % 3].1)).collect();
    assert_eq!(response_period(&short, 8, 1e-3, 2.0, 2.0), None);
}

/// Window statistics: constant forces `(−3, 4)` at every stepped level from
/// `record_from` on give RMS `sqrt(9 + 16) = 5`; the largest `|u_tip|` is the
/// window's (a larger value before `record_from` is left out).
#[test]
fn window_rms_and_max_tip() {
    let dt = 0.1;
    let levels: Vec<Level> = (0..50)
        .map(|n| {
            let t = n as f64 * dt;
            let f = if t >= 2.0 { vec![-3.0, 4.0] } else { vec![-100.0, 0.0] };
            Level { u: vec![0.0, if n == 5 { -9.0 } else { (t).sin() * 0.5 }], forces: f, status: vec![Active::None; 2] }
        })
        .collect();
    let mut obs = WindowObserver::new(1, 2.0);
    feed(&mut obs, dt, &levels).unwrap();
    assert!(rel(obs.rms_force(), 5.0) < 1e-14, "{}", obs.rms_force());
    let max = (20..50).map(|n| ((n as f64 * dt).sin() * 0.5).abs()).fold(0.0, f64::max);
    assert_eq!(obs.max_abs_tip(), max);
}

/// The summary row: its header and the cells of a hand-made summary
/// (period written as `p`, `0` when not periodic, empty cells for pieces not
/// requested).
#[test]
fn summary_csv() {
    assert_eq!(Summary::csv_header(), "impacts,impacts_per_period,mean_impulse,max_impulse,impact_power,rms_force,max_abs_tip,period,window,poincare_points");
    let cfg = VibroConfig::new(0.1, Some(1.0), 0.0, 0, vec![(0, Bounds::obstacle(0.0))]).unwrap();
    let v = cfg.build::<std::io::Sink, std::io::Sink>(Piece::Off, Piece::Memory, true).unwrap();
    let s = v.summary();
    assert!(s.impacts.is_none() && s.poincare == Some((0, None)) && s.rms_force == Some(0.0));
    let mut buf = Vec::new();
    s.write_row(&mut buf).unwrap();
    assert_eq!(String::from_utf8(buf).unwrap(), ",,,,,0.000000000000e0,0.000000000000e0,0,,0");
}

/// Bad configurations are typed errors naming the field.
#[test]
fn bad_config() {
    let c = vec![(0, Bounds::obstacle(0.0))];
    let field = |r: Result<VibroConfig, RunError>| match r {
        Err(RunError::Invalid { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    assert_eq!(field(VibroConfig::new(0.0, None, 0.0, 0, c.clone())), "vibro.dt");
    assert_eq!(field(VibroConfig::new(0.1, Some(-1.0), 0.0, 0, c.clone())), "vibro.omega");
    assert_eq!(field(VibroConfig::new(0.1, None, f64::NAN, 0, c.clone())), "vibro.record_from");
    assert_eq!(field(VibroConfig::new(0.1, None, 0.0, 0, vec![])), "vibro.contacts");
    assert_eq!(field(VibroConfig::new(0.1, None, 0.0, 0, vec![(0, Bounds { lo: 1.0, hi: 0.0 })])), "vibro.contacts.bounds");
    let cfg = VibroConfig::new(0.1, None, 0.0, 0, c.clone()).unwrap();
    assert!(matches!(cfg.poincare::<std::io::Sink>(None), Err(RunError::Invalid { field: "vibro.omega", .. })));
    let mut bad = cfg.clone();
    bad.p_max = 0;
    assert!(matches!(bad.validate(), Err(RunError::Invalid { field: "vibro.p_max", .. })));
    // Two contacts configured, one in the run.
    let mut two = cfg.clone();
    two.contacts.push((1, Bounds::obstacle(0.0)));
    let mut obs = two.impacts::<std::io::Sink>(None).unwrap();
    assert!(matches!(feed(&mut obs, 0.1, &[one(1.0, 0.0, Active::None)]), Err(RunError::Invalid { field: "vibro.contacts", .. })));
    // A tip dof outside the problem.
    let mut w = WindowObserver::new(3, 0.0);
    assert!(matches!(feed(&mut w, 0.1, &[one(1.0, 0.0, Active::None)]), Err(RunError::Invalid { field: "vibro.tip", .. })));
}

/// One mass `m` on a spring `k` (possibly 0) under the weight `−m g`,
/// released at rest at `h` above a stop at 0 with restitution `r`, run by
/// Paoli–Schatzman (β = 1/4) through `run` up to just after the first
/// impact. Returns the impact, the recorded displacements and dt.
fn falling_mass(k: f64, r: f64, dt: f64, t_end: f64) -> (signorini_run::Impact, Vec<f64>) {
    let (m, g, h) = (2.0, 9.81, 0.5);
    let (mass, stiffness) = (SymBand::from_diagonal(&[m]), SymBand::from_diagonal(&[k]));
    let dy = Dynamics::new(mass, stiffness, vec![-m * g], vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
    let init = Initial { u: vec![h], v: vec![0.0] };
    let mut ps = PaoliSchatzman::new("ps".into(), dy.clone(), 0.25, r, dt, &init).unwrap();
    let cfg = VibroConfig::for_dynamics(ps.dynamics(), dt, None, 0.0, 0).unwrap();
    let mut vib = cfg.build::<std::io::Sink, std::io::Sink>(Piece::Memory, Piece::Off, false).unwrap();
    struct Rec(Vec<f64>);
    impl Observer for Rec {
        fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
            self.0.push(s.u[0]);
            Ok(())
        }
    }
    let mut rec = Rec(Vec::new());
    let steps = (t_end / dt).round();
    run(&mut ps, &init.u, &RunConfig::new(dt, steps * dt).unwrap(), &mut [&mut vib, &mut rec]).unwrap();
    let imps = vib.impacts.as_ref().unwrap().impacts().to_vec();
    assert!(!imps.is_empty());
    (imps[0], rec.0)
}

/// Free fall (`k = 0`, the scheme exact for a constant acceleration): the
/// impact time `sqrt(2h/g)` and velocity `−sqrt(2gh)` to rounding; the
/// impulse is `(1+r) m |V|` to O(dt) and equals the discrete momentum
/// balance `m (V^{l−1/2} − V^{m−3/2}) − (l−m+1) F dt` of the recorded levels
/// to rounding (`m..l` the active levels). With a spring (`k = 3`, exact
/// `u = −mg/k + (h + mg/k) cos(ω t)`) the time and velocity errors are
/// O(dt²): they fall by ≈ 4 when dt halves.
#[test]
fn real_run_mass_on_a_stop() {
    let (m, g, h, r): (f64, f64, f64, f64) = (2.0, 9.81, 0.5, 0.6);
    let tc = (2.0 * h / g).sqrt();
    let vc = -(2.0 * g * h).sqrt();
    for dt in [1e-3, 7e-4] {
        let (imp, u) = falling_mass(0.0, r, dt, tc + 0.05);
        assert_eq!(imp.crossing, Crossing::Quadratic);
        assert!(rel(imp.t, tc) < 1e-9, "t* {} vs {tc}", imp.t);
        assert!(rel(imp.velocity, vc) < 1e-7, "v {} vs {vc}", imp.velocity);
        let jexp = (1.0 + r) * m * vc.abs();
        assert!(rel(imp.impulse, jexp) < 3.0 * dt / tc, "J {} vs {jexp} (dt {dt})", imp.impulse);
        let (a, levels) = (imp.first_level, (imp.duration / dt).round() as usize);
        let l = a + levels - 1;
        let balance = m * ((u[l] - u[l - 1]) / dt - (u[a - 1] - u[a - 2]) / dt) - levels as f64 * (-m * g) * dt;
        assert!((imp.impulse - balance).abs() < 1e-9 * jexp, "J {} vs balance {balance}", imp.impulse);
        eprintln!("free fall dt {dt}: t* err {:.2e}, v err {:.2e}, J/((1+r)m|V|) − 1 = {:.2e}, levels {levels}", imp.t - tc, imp.velocity - vc, imp.impulse / jexp - 1.0);
    }
    let k = 3.0;
    let (w, u_eq) = ((k / m).sqrt(), -m * g / k);
    let tc = ((u_eq.abs()) / (h - u_eq)).acos() / w;
    let vc = -(h - u_eq) * w * (w * tc).sin();
    let dts = [4e-3, 2e-3, 1e-3, 5e-4];
    let errs: Vec<(f64, f64)> = dts
        .iter()
        .map(|&dt| {
            let (imp, _) = falling_mass(k, r, dt, tc + 0.05);
            assert_eq!(imp.crossing, Crossing::Quadratic);
            ((imp.t - tc) / (dt * dt), (imp.velocity - vc) / (dt * dt))
        })
        .collect();
    eprintln!("spring: (t* error, v error)/dt² for dt = {dts:?}: {errs:?}");
    // The time error is smooth in dt (the scheme's phase error): ratio 4.
    let rt = errs[1].0 / errs[2].0;
    assert!(rt > 0.8 && rt < 1.25, "time error/dt² {} vs {}", errs[1].0, errs[2].0);
    // The velocity error mixes the scheme's O(dt²) error with the
    // extrapolation's, whose constant depends on where the crossing falls in
    // its step: it stays bounded by C dt², the extrapolation's part by
    // max|u'''|/6 · max_{s∈[−2,1]} |3s² + 6s + 2| = (h + mg/k) ω³ · 11/6
    // ≈ 23.7 (a first-order estimate would give ≈ g dt / 2, ≥ 1000 dt² here).
    let c3 = (h - u_eq) * w.powi(3) * 11.0 / 6.0;
    for (dt, e) in dts.iter().zip(&errs) {
        assert!(e.0.abs() < 0.1 && e.1.abs() < c3, "dt {dt}: errors/dt² {e:?} (bound {c3})");
    }
}

/// The period test on a sampled trajectory, through [`VibroConfig::build`]
/// and [`Summary`]: `u = cos(Ω t/3 + 0.3) + 0.5 cos(Ω t + 1)` is period 3 at
/// the stroboscopic times, `0.5 cos(Ω t + 1)` period 1 (its Poincaré points
/// coincide up to the interpolation error, so the tolerance must scale with
/// the orbit's range, not the points'), `cos(φ Ω t)` (φ the golden ratio)
/// not periodic. The number of points is counted by hand, and the summary
/// row writes the period (0 when not periodic).
#[test]
fn period_of_sampled_trajectories() {
    let (dt, omega, record_from, t_end): (f64, f64, f64, f64) = (0.01, 2.0, 10.0, 200.0);
    let steps = (t_end / dt).round() as usize;
    let npts = (0..1000).filter(|&k| k as f64 * TAU / omega >= record_from && k as f64 * TAU / omega <= steps as f64 * dt).count();
    let phi = (1.0 + 5.0_f64.sqrt()) / 2.0;
    type Signal = fn(f64, f64, f64) -> f64;
    let cases: [(Signal, usize); 3] = [(|w, t, _| (w * t / 3.0 + 0.3).cos() + 0.5 * (w * t + 1.0).cos(), 3), (|w, t, _| 0.5 * (w * t + 1.0).cos(), 1), (|w, t, phi| (phi * w * t).cos(), 0)];
    for (u, p) in cases {
        let levels: Vec<Level> = (0..=steps).map(|n| one(u(omega, n as f64 * dt, phi), 0.0, Active::None)).collect();
        let mut cfg = VibroConfig::new(dt, Some(omega), record_from, 0, vec![(0, Bounds::obstacle(-10.0))]).unwrap();
        cfg.t_end = Some(t_end);
        let mut csv = Vec::new();
        let mut v = cfg.build(Piece::<std::io::Sink>::Memory, Piece::Csv(&mut csv), true).unwrap();
        feed(&mut v, dt, &levels).unwrap();
        let s = v.summary();
        assert_eq!(s.poincare, Some((npts, (p > 0).then_some(p))), "case period {p}");
        assert_eq!(s.impacts.map(|i| i.count), Some(0));
        let mut row = Vec::new();
        s.write_row(&mut row).unwrap();
        let row = String::from_utf8(row).unwrap();
        assert_eq!(row.split(',').nth(7), Some(p.to_string().as_str()), "{row}");
        drop(v);
        assert_eq!(parse_csv(&csv).1.len(), npts);
    }
}

/// Feeds `levels` (at `t_n = n dt`) to `obs` as a run whose first `start`
/// levels are start levels (no step reached them: no `lambda`, zero
/// forces, as `run` emits them), then finishes it.
fn feed_started(obs: &mut dyn Observer, dt: f64, start: usize, levels: &[Level]) -> Result<(), RunError> {
    for (n, l) in levels.iter().enumerate() {
        let t = n as f64 * dt;
        let lambda = (n >= start).then_some((t, l.forces[0]));
        obs.observe(&Sample::new(n, t, &l.u).with_contacts(lambda, false, &l.forces, &l.status))?;
    }
    obs.finish()
}

/// The RMS force is over the stepped levels only, by hand: forces
/// `(0, 0), (0, 0), (3, 4), (0, 0), (1, −2)` at levels 0..=4 from
/// `record_from = 0`, `Σ_n Σ_i λ_i² = 25 + 0 + 5 = 30`. A two-step start
/// (levels 0 and 1 without a step) averages over 3 levels: `sqrt(10)`; a
/// one-step start (level 0 only) over 4, the zero forces of level 1 counted:
/// `sqrt(7.5)`. Counting the start levels too would give `sqrt(6)`.
#[test]
fn window_rms_over_stepped_levels_by_hand() {
    let forces = [[0.0, 0.0], [0.0, 0.0], [3.0, 4.0], [0.0, 0.0], [1.0, -2.0]];
    let levels: Vec<Level> = forces.iter().map(|f| Level { u: vec![0.5], forces: f.to_vec(), status: vec![Active::None; 2] }).collect();
    for (start, want) in [(2, 10.0_f64.sqrt()), (1, 7.5_f64.sqrt())] {
        let mut obs = WindowObserver::new(0, 0.0);
        feed_started(&mut obs, 0.1, start, &levels).unwrap();
        assert!(rel(obs.rms_force(), want) < 1e-15, "start {start}: {} vs {want}", obs.rms_force());
    }
}

/// The period test at its boundary `2p = L` (exactly two periods in the
/// last `L = min(N, 2 p_max)` points), by hand with the period-3 values
/// `a, b, c` of `period_detection`: `a b c a b c` (N = 6 = 2·3) is period 3
/// with `p_max = 8` (L = 6) and with `p_max = 3`; `a b a b` is period 2 with
/// `p_max = 2`; two equal points are period 1 with `p_max = 1`; a
/// transient `c c` before `a b c a b c` is left out with `p_max = 3` (L = 6:
/// period 3) but not with `p_max = 4` (L = 8: `c c a b c a b c` has no
/// period <= 4: `p = 1, 2, 4` pair `c` with `a`, `p = 3` pairs `c` with `b`).
#[test]
fn period_at_exactly_two_periods() {
    let [a, b, c] = [(0.3, -1.0), (1.2, 0.5), (-0.8, 0.9)];
    let seq = |vals: &[(f64, f64)]| -> Vec<PoincarePoint> { vals.iter().enumerate().map(|(j, &(x, v))| pt(j as u64, x, v)).collect() };
    let period = |vals: &[(f64, f64)], p_max: usize| response_period(&seq(vals), p_max, 1e-3, 2.0, 2.0);
    assert_eq!(period(&[a, b, c, a, b, c], 8), Some(3));
    assert_eq!(period(&[a, b, c, a, b, c], 3), Some(3));
    assert_eq!(period(&[a, b, a, b], 2), Some(2));
    assert_eq!(period(&[a, a], 1), Some(1));
    assert_eq!(period(&[c, c, a, b, c, a, b, c], 3), Some(3));
    assert_eq!(period(&[c, c, a, b, c, a, b, c], 4), None);
    assert_eq!(period(&[a, b, c, a, b], 8), None);
}

/// A Poincaré time on the last level: `Ω = 2π` (period `2π/2π = 1`
/// exactly), `dt = 1/4`, levels `t_n = n/4`, `n = 0..=8`, of the cubic
/// `u = t³ − t` (every `t_n` and `u(t_n)` exact in binary). The section
/// times are `t_k = k`, `k = 0, 1, 2`, the last one the last level `t_8 =
/// 2`, emitted at `finish`. By hand: `(u, u') = (0, −1), (0, 2), (6, 11)`;
/// the cubic stencils reproduce `u` (errors a few ulps).
#[test]
fn poincare_point_on_the_last_level() {
    let dt = 0.25;
    let levels: Vec<Level> = (0..=8).map(|n| n as f64 * dt).map(|t| one(t * t * t - t, 0.0, Active::None)).collect();
    let mut obs = PoincareObserver::<std::io::Sink>::new(0, dt, TAU, 0.0, 0, None).unwrap();
    feed(&mut obs, dt, &levels).unwrap();
    let got: Vec<(u64, f64, f64, f64)> = obs.points().iter().map(|p| (p.k, p.t, p.displacement, p.velocity)).collect();
    let want = [(0, 0.0, 0.0, -1.0), (1, 1.0, 0.0, 2.0), (2, 2.0, 6.0, 11.0)];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert_eq!((g.0, g.1), (w.0, w.1));
        assert!((g.2 - w.2).abs() <= 1e-14 && (g.3 - w.3).abs() <= 1e-13, "{g:?} vs {w:?}");
    }
}
