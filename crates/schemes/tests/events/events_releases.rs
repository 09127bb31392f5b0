//! Releases a user meets first (docs/theory.md §9.3, "Touches, releases
//! together, rebounds without length"): a held force that touches 0
//! without changing sign, two contacts released at one instant, and a free
//! mass (no stiffness) pushed onto its stop.
//!
//! Oracles, written here: the touch `x'' + x = −(1 + cos t) + δ` held on 0
//! (reaction `1 − δ + cos t`: never negative for `δ <= 0`; for `δ > 0`
//! negative on `|t − π| < 2 asin √(δ/2)`, the flight `x(u) = ∫₀ᵘ sin(u − w)
//! F(w) dw` by Simpson's rule, without cancellation); two equal masses
//! coupled by a spring, each on its stop under `−cos t`, released at π/2
//! into the symmetric mode `x'' + x = −cos t`; the free mass `x'' = −1`
//! rebounding `v₀²/2` every `2v₀` (`e = 1`), its flights shrinking by `e`
//! to `τ∞ = 2v₀/(1 − e)`.

use crate::events_common as common;
use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::sync::Arc;

fn cosine(amplitude: f64, phase: f64) -> TimeProfile {
    TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude, omega: 1.0, phase: FRAC_PI_2 + phase }]))
}

fn band(n: usize, entries: &[(usize, usize, f64)]) -> SymBand {
    let mut b = SymBand::zeros(n, 1);
    for &(i, j, v) in entries {
        b.set(i, j, v);
    }
    b
}

/// The search's time resolution at `t` (docs/theory.md §9.2).
fn resolution(t: f64) -> f64 {
    (1e-15 * t.abs()).max(f64::EPSILON * t.abs().max(1.0))
}

fn touch(delta: f64) -> Dynamics {
    Dynamics::new(band(1, &[(0, 0, 1.0)]), band(1, &[(0, 0, 1.0)]), vec![-1.0 + delta], vec![Contact::new(0, Bounds::obstacle(0.0), false)])
        .with_forcing(vec![Forcing { shape: vec![-1.0], time: cosine(1.0, 0.0) }])
}

/// A held force that touches 0 (or dips by 1e-15, within its round-off)
/// is no release: no row, the mass stays at 0.
#[test]
fn a_held_force_touching_zero_releases_nothing() {
    for delta in [0.0, 1e-15, -1e-15, -1e-12, -1e-8] {
        let mut r = EventDriven::new(&touch(delta), 0.0, &[0.0], &[0.0], 0.0).expect("starts");
        for k in 1..=8 {
            r.run_until(k as f64 * PI, 100).unwrap_or_else(|e| panic!("δ = {delta}: {e}"));
            let (_, q, v) = r.state();
            assert!(q[0] == 0.0 && v[0] == 0.0, "δ = {delta} at {k}π: ({}, {})", q[0], v[0]);
        }
        assert!(r.events().is_empty(), "δ = {delta}: {:?}", r.events());
    }
}

/// `δ = 1e-8`: the force is negative for `|t − π| < a = 2 asin √(δ/2)`:
/// one release at `π − a` and one landing (the flight's root) per period
/// (measured: releases within 6e-13 s, landings 1e-11 s, their speed
/// 7.5e-12 within 1e-7 of it).
#[test]
fn a_held_force_dipping_below_zero_releases_and_lands_once() {
    let delta = 1e-8f64;
    let a = 2.0 * (0.5 * delta).sqrt().asin();
    let (flight, _) = dip_flight(delta);
    let (u_land, v_land) = landing(flight, (3.0 * a, 5.0 * a));
    let mut r = EventDriven::new(&touch(delta), 0.0, &[0.0], &[0.0], 0.0).expect("starts");
    r.run_until(8.0 * PI, 100).expect("completes");
    let ev = r.events();
    assert_eq!(ev.len(), 8, "{ev:?}");
    for k in 0..4 {
        let t_r = (2 * k + 1) as f64 * PI - a;
        let (rel, imp) = (ev[2 * k], ev[2 * k + 1]);
        assert_eq!((rel.kind, imp.kind), (EventKind::Release, EventKind::Impact), "period {k}");
        // The force's round-off (2ε on terms of 1) over its rate `a`.
        assert!((rel.t - t_r).abs() <= 8.0 * f64::EPSILON / a + 4.0 * resolution(t_r), "release {k}: {} against {t_r}", rel.t);
        assert!((imp.t - (t_r + u_land)).abs() <= 5e-11, "landing {k}: {} against {}", imp.t, t_r + u_land);
        assert!((imp.velocity_before - v_land).abs() <= 5e-7 * v_land.abs(), "landing {k}: {} against {v_land}", imp.velocity_before);
    }
}

/// Two unit masses, each on a unit spring to the ground and a unit spring
/// to the other, each on its own stop at 0, dof 1 loaded by `−cos(t + φ)`.
fn twins(phi: f64) -> Dynamics {
    let m = band(2, &[(0, 0, 1.0), (1, 1, 1.0)]);
    let k = band(2, &[(0, 0, 2.0), (1, 1, 2.0), (1, 0, -1.0)]);
    let stop = |d| Contact::new(d, Bounds::obstacle(0.0), false);
    Dynamics::new(m, k, vec![0.0; 2], vec![stop(0), stop(1)]).with_forcing(vec![Forcing { shape: vec![-1.0, 0.0], time: cosine(1.0, 0.0) }, Forcing { shape: vec![0.0, -1.0], time: cosine(1.0, phi) }])
}

/// `x'' + x = −cos t` from `(t0, x0, v0)`: the symmetric mode's flight.
fn symmetric(t0: f64, x0: f64, v0: f64) -> impl Fn(f64) -> (f64, f64) {
    // x = A cos t + B sin t − (t/2) sin t.
    let (s, c) = t0.sin_cos();
    let (rx, rv) = (x0 + 0.5 * t0 * s, v0 + 0.5 * s + 0.5 * t0 * c);
    let (a, b) = (rx * c - rv * s, rx * s + rv * c);
    move |t: f64| {
        let (s, c) = t.sin_cos();
        (a * c + b * s - 0.5 * t * s, -a * s + b * c - 0.5 * s - 0.5 * t * c)
    }
}

/// The first root of a flight's position in `(lo, hi)` (bisection),
/// positive at `lo`, negative at `hi`.
fn landing(x: impl Fn(f64) -> (f64, f64), (mut lo, mut hi): (f64, f64)) -> (f64, f64) {
    assert!(x(lo).0 > 0.0 && x(hi).0 < 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if x(mid).0 > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo, x(lo).1)
}

/// Both released at π/2, together, then the symmetric mode: landings of
/// both at once at its roots; with `e = 0` held and released again at
/// 5π/2 (before: `NoProgress` there, each release re-landing the other).
#[test]
fn two_contacts_released_at_one_instant_leave_together() {
    for e in [0.0, 0.5, 1.0] {
        let mut r = EventDriven::new(&twins(0.0), 0.0, &[0.0; 2], &[0.0; 2], e).expect("starts");
        let first = symmetric(FRAC_PI_2, 0.0, 0.0);
        r.run_until(6.0, 100).unwrap_or_else(|err| panic!("e = {e}: {err}"));
        let (_, q, v) = r.state();
        let (x, dx) = first(6.0);
        assert!(q.iter().all(|q| (q - x).abs() <= 1e-13) && v.iter().all(|v| (v - dx).abs() <= 1e-13), "e = {e} at 6: {q:?} {v:?} against ({x}, {dx})");
        r.run_until(4.0 * PI, 100).unwrap_or_else(|err| panic!("e = {e}: {err}"));
        let ev = r.events();
        common::check_order(ev).unwrap();
        // Rows in pairs at one time, both contacts named.
        assert!(ev.len() % 2 == 0 && ev.chunks(2).all(|p| p[0].t == p[1].t && p[0].kind == p[1].kind && p[0].contact + p[1].contact == 1), "e = {e}: {ev:?}");
        assert!(ev[..2].iter().all(|r| r.kind == EventKind::Release && (r.t - FRAC_PI_2).abs() <= 4.0 * resolution(FRAC_PI_2)), "e = {e}: {ev:?}");
        let (t1, v1) = landing(&first, (PI, TAU));
        assert!(ev[2..4].iter().all(|r| r.kind == EventKind::Impact && (r.t - t1).abs() <= 1e-12 && (r.velocity_before - v1).abs() <= 1e-12), "e = {e}: {:?} against {t1}, {v1}", &ev[2..4]);
        if e == 0.0 {
            // Held from t1 (the reaction cos t >= 0) to 5π/2, the same flight again.
            assert_eq!(ev.len(), 8, "{ev:?}");
            assert!(ev[4..6].iter().all(|r| r.kind == EventKind::Release && (r.t - 5.0 * FRAC_PI_2).abs() <= 4.0 * resolution(5.0 * FRAC_PI_2)), "{ev:?}");
            assert!(ev[6..].iter().all(|r| r.kind == EventKind::Impact && (r.t - t1 - TAU).abs() <= 1e-11 && (r.velocity_before - v1).abs() <= 1e-11), "{ev:?}");
            let (_, q, v) = r.state();
            assert!(q.iter().chain(&v).all(|x| *x == 0.0), "{q:?} {v:?}");
        } else {
            let (t2, v2) = landing(symmetric(t1, 0.0, -e * v1), (t1 + 0.5, t1 + PI));
            assert!(ev[4..6].iter().all(|r| r.kind == EventKind::Impact && (r.t - t2).abs() <= 1e-11 && (r.velocity_before - v2).abs() <= 1e-11), "e = {e}: {:?} against {t2}, {v2}", &ev[4..6]);
        }
    }
}

/// Loads `φ` apart (1e-15 … 1e-9): dof 1 released at `π/2 − φ`, dof 0 at
/// π/2 (within the resolution: 1e-15 apart they leave together), then on
/// to 4π without error, in time order.
#[test]
fn releases_a_hair_apart_keep_their_times_and_order() {
    for phi in [1e-15, 1e-13, 1e-12, 1e-9] {
        let mut r = EventDriven::new(&twins(phi), 0.0, &[0.0; 2], &[0.0; 2], 0.0).expect("starts");
        r.run_until(4.0 * PI, 100).unwrap_or_else(|err| panic!("φ = {phi}: {err}"));
        let ev = r.events();
        common::check_order(ev).unwrap();
        let tol = 4.0 * resolution(FRAC_PI_2);
        for c in 0..2 {
            let t_c = FRAC_PI_2 - if c == 1 { phi } else { 0.0 };
            let rel = ev.iter().find(|r| r.contact == c).expect("released");
            assert!(rel.kind == EventKind::Release && (rel.t - t_c).abs() <= tol, "φ = {phi}, contact {c}: {rel:?} against {t_c}");
        }
        assert_eq!(ev.iter().filter(|r| r.kind == EventKind::Release).count(), 4, "φ = {phi}: {ev:?}");
    }
}

/// A free chain of three masses, a stop under each end, both ends pressed
/// by `−cos t`: released together at π/2, mirror-symmetric after.
#[test]
fn a_chain_released_at_both_ends_by_symmetry_stays_symmetric() {
    let m = band(3, &[(0, 0, 1.0), (1, 1, 2.0), (2, 2, 1.0)]);
    let k = band(3, &[(0, 0, 1.0), (1, 1, 2.0), (2, 2, 1.0), (1, 0, -1.0), (2, 1, -1.0)]);
    let stop = |d| Contact::new(d, Bounds::obstacle(0.0), false);
    let dy = Dynamics::new(m, k, vec![0.0; 3], vec![stop(0), stop(2)]).with_forcing(vec![Forcing { shape: vec![-1.0, 0.0, -1.0], time: cosine(1.0, 0.0) }]);
    for e in [0.0, 0.5, 1.0] {
        let mut r = EventDriven::new(&dy, 0.0, &[0.0; 3], &[0.0; 3], e).expect("starts");
        r.run_until(4.0 * PI, 100).unwrap_or_else(|err| panic!("e = {e}: {err}"));
        let ev = r.events();
        common::check_order(ev).unwrap();
        assert!(ev.len() >= 2 && ev[0].t == ev[1].t && ev[0].contact + ev[1].contact == 1, "e = {e}: {ev:?}");
        assert!(ev[..2].iter().all(|r| r.kind == EventKind::Release && (r.t - FRAC_PI_2).abs() <= 4.0 * resolution(FRAC_PI_2)), "e = {e}: {ev:?}");
        let (_, q, v) = r.state();
        let size = q.iter().chain(&v).fold(1.0f64, |m, x| m.max(x.abs()));
        assert!((q[0] - q[2]).abs() <= 1e-12 * size && (v[0] - v[2]).abs() <= 1e-12 * size, "e = {e}: {q:?} {v:?}");
    }
}

fn free_mass() -> Dynamics {
    Dynamics::new(band(1, &[(0, 0, 1.0)]), band(1, &[(0, 0, 0.0)]), vec![-1.0], vec![Contact::new(0, Bounds::obstacle(0.0), false)])
}

/// `x'' = −1` on a stop at 0 from `(0, v₀)`: no stiffness, no length.
/// Flights of `2v₀` below the time resolution (1e-17, 1e-300) are at rest
/// (an accumulation row at the first impact, 0 or `2v₀`); resolvable ones
/// land as the closed form: every `2v₀` for `e = 1`; for `e < 1` at
/// `2v₀ (1 + e + … + e^{k−1})`, accumulating at `2v₀/(1 − e)`.
#[test]
fn a_free_mass_pushed_onto_its_stop_rebounds_as_the_closed_form() {
    for e in [0.0, 0.5, 1.0] {
        for v0 in [0.0, 1e-300, -1e-300, 1e-17, -1e-17, 1e-9, -1e-9, 1e-6] {
            let mut r = EventDriven::new(&free_mass(), 0.0, &[0.0], &[v0], e).expect("starts");
            let w = v0.abs();
            // Its first landing (at once for v₀ < 0), then flights of 2w eᵏ.
            let t1 = if v0 > 0.0 { 2.0 * w } else { 0.0 };
            let resolved = 2.0 * w > 4.0 * resolution(t1);
            let end = if e == 1.0 && resolved { t1 + 40.5 * 2.0 * w } else { 1e-4 };
            r.run_until(end, 1000).unwrap_or_else(|err| panic!("e = {e}, v₀ = {v0}: {err}"));
            let ev = r.events();
            common::check_order(ev).unwrap();
            let (_, q, v) = r.state();
            let case = format!("e = {e}, v₀ = {v0}: {:?}", &ev[..ev.len().min(4)]);
            if v0 == 0.0 {
                assert!(ev.is_empty() && q[0] == 0.0 && v[0] == 0.0, "{case}");
                continue;
            }
            if e == 1.0 && resolved {
                assert_eq!(ev.len(), 41, "{case}");
                for (k, x) in ev.iter().enumerate() {
                    let t = t1 + 2.0 * w * k as f64;
                    assert!(x.kind == EventKind::Impact && (x.t - t).abs() <= 1e-13 * t, "{case}: landing {k} at {} against {t}", x.t);
                    assert!((x.velocity_before + w).abs() <= 1e-13 * w && (x.velocity_after - w).abs() <= 1e-13 * w, "{case}: landing {k}: {x:?}");
                }
                // Half a flight after the last: at its top, w²/2.
                assert!((q[0] - 0.5 * w * w).abs() <= 1e-12 * w * w && v[0].abs() <= 1e-12 * w, "{case}: ({}, {})", q[0], v[0]);
                continue;
            }
            // At rest from the limit on.
            assert!(q[0] == 0.0 && v[0] == 0.0, "{case}: ({}, {})", q[0], v[0]);
            let last = ev.last().expect("an event");
            let t_inf = t1 + if e < 1.0 { 2.0 * e * w / (1.0 - e) } else { 0.0 };
            if e == 0.0 {
                // One landing, an impact (or at rest at once below the resolution).
                assert!(ev.len() == 1 && (last.t - t1).abs() <= 1e-14 * t1, "{case}");
            } else if !resolved {
                // Logged at the limit, within the one flight it neglects.
                assert!(ev.len() <= 2 && last.kind == EventKind::Accumulation && (last.t - t_inf).abs() <= 2.0 * w + 1e-15 * t_inf, "{case}");
            } else {
                // 0 < e < 1: the landings at t1 + 2ew(1 + … + e^{k−1}) at speed w eᵏ, then the limit.
                for (k, x) in ev[..ev.len() - 1].iter().enumerate() {
                    let t = t1 + 2.0 * e * w * (1.0 - e.powi(k as i32)) / (1.0 - e);
                    assert!(x.kind == EventKind::Impact && (x.t - t).abs() <= 1e-14 * t && (x.velocity_before + w * e.powi(k as i32)).abs() <= 1e-14 * w, "{case}: landing {k}: {x:?} against {t}");
                }
                assert!(last.kind == EventKind::Accumulation && (last.t - t_inf).abs() <= 1e-13 * t_inf, "{case}: {last:?} against {t_inf}");
            }
        }
    }
}

/// The flight of `touch(δ)` from its release, `u` after it: the load
/// `F(w) = δ − 2 sin²((w − a)/2)` (0 at w = 0) against the spring,
/// Duhamel's integral by Simpson's rule; and `F` itself.
fn dip_flight(delta: f64) -> (impl Fn(f64) -> (f64, f64), impl Fn(f64) -> f64) {
    let a = 2.0 * (0.5 * delta).sqrt().asin();
    let load = move |w: f64| delta - 2.0 * (0.5 * (w - a)).sin().powi(2);
    let flight = move |u: f64| -> (f64, f64) {
        let n = 4000;
        let h = u / n as f64;
        let (mut x, mut v) = (0.0, 0.0);
        for i in 0..=n {
            let w = i as f64 * h;
            let c = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            x += c * (u - w).sin() * load(w);
            v += c * (u - w).cos() * load(w);
        }
        (x * h / 3.0, v * h / 3.0)
    };
    (flight, load)
}

/// `δ` on a log grid from 1e-16 to 1e-6, both signs: one release at
/// `(2k+1)π − a` (within the force's round-off over its rate, `8ε/a`) and
/// one landing per period at the flight's root, every change logged (no
/// landing at zero speed: before, `δ = 1e-12` and `1e-10` logged two
/// releases 7.9e-11 and 7.8e-12 s apart, the first one early by its
/// round-off and landed at once); dips within the band (`δ <= 1e-14`) and
/// `δ <= 0`: nothing, `x ≡ 0`.
#[test]
fn a_dip_of_any_depth_releases_once_per_period() {
    let mut worst: (f64, f64) = (0.0, 0.0);
    for k in 12..=32 {
        for sign in [1.0, -1.0] {
            let delta = sign * 10f64.powf(-0.5 * k as f64);
            let mut r = EventDriven::new(&touch(delta), 0.0, &[0.0], &[0.0], 0.0).expect("starts");
            let mut changes = 0;
            while let signorini_schemes::events::Reached::Event(e) = r.next_change(4.0 * PI).unwrap_or_else(|e| panic!("δ = {delta:e}: {e}")) {
                assert!(e.is_some(), "δ = {delta:e}: a change without a row at {}", r.time());
                changes += 1;
            }
            let ev = r.events();
            common::check_order(ev).unwrap();
            assert_eq!(changes, ev.len());
            if ev.is_empty() {
                assert!(delta < 1e-12, "δ = {delta:e}: no release");
                let (_, q, v) = r.state();
                assert!(q[0] == 0.0 && v[0] == 0.0, "δ = {delta:e}: ({}, {})", q[0], v[0]);
                continue;
            }
            assert!(delta > 1e-14, "δ = {delta:e}: {ev:?}");
            let a = 2.0 * (0.5 * delta).sqrt().asin();
            let (flight, load) = dip_flight(delta);
            let (u_land, v_land) = landing(&flight, (3.0 * a, 5.0 * a));
            // The landing's speed `~8a³/3` against the flight's round-off:
            // its time within `64ε/a` (measured: up to 1.4e-9 s at a = 1.4e-6).
            let tol_land = 64.0 * f64::EPSILON / a;
            let tol_v = 2.0 * load(u_land).abs() * tol_land + 5e-7 * v_land.abs();
            assert_eq!(ev.len(), 4, "δ = {delta:e}: {ev:?}");
            for p in 0..2 {
                let t_r = (2 * p + 1) as f64 * PI - a;
                let (rel, imp) = (ev[2 * p], ev[2 * p + 1]);
                assert_eq!((rel.kind, imp.kind, rel.contact, imp.contact), (EventKind::Release, EventKind::Impact, 0, 0), "δ = {delta:e}, period {p}");
                assert!((rel.t - t_r).abs() <= 8.0 * f64::EPSILON / a + 4.0 * resolution(t_r), "δ = {delta:e}, release {p}: {} against {t_r}", rel.t);
                assert!((imp.t - (t_r + u_land)).abs() <= tol_land, "δ = {delta:e}, landing {p}: {} against {}", imp.t, t_r + u_land);
                assert!((imp.velocity_before - v_land).abs() <= tol_v, "δ = {delta:e}, landing {p}: {} against {v_land}", imp.velocity_before);
                worst.0 = worst.0.max((rel.t - t_r).abs() * a / f64::EPSILON);
                worst.1 = worst.1.max((imp.t - t_r - u_land).abs() * a / f64::EPSILON);
            }
            let (_, q, v) = r.state();
            assert!(q[0] == 0.0 && v[0] == 0.0, "δ = {delta:e}: ({}, {})", q[0], v[0]);
        }
    }
    println!("worst release, landing errors in ε/a: {worst:?}");
}

/// Three unit oscillators on stops at 0, uncoupled: dofs 0 and 1 held
/// under `−cos t` and `−cos(t − φ)` (released at π/2 and π/2 + φ), dof 2
/// free, `x₂ = sin(t_g − t)`, arriving at `t_g` at speed −1; `φ` one ulp,
/// `t_g` one to six ulps after π/2 (within the resolution 4δ = 28 ulps):
/// the releases, then the impact, nothing else (before: the impact's LCP
/// took the contacts just released, at rest on their stops with speeds of
/// round-off, as impacts, held and released them again: rows `impact` of
/// contacts 0 and 1, and with e = 1 an accumulation).
#[test]
fn an_impact_just_after_a_release_leaves_the_released_alone() {
    let ulp = f64::EPSILON;
    let cosine = |phase: f64| TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: 1.0, omega: 1.0, phase: FRAC_PI_2 - phase }]));
    let stop = |d| Contact::new(d, Bounds::obstacle(0.0), false);
    let dy = Dynamics::new(band(3, &[(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0)]), band(3, &[(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0)]), vec![0.0; 3], vec![stop(0), stop(1), stop(2)])
        .with_forcing(vec![Forcing { shape: vec![-1.0, 0.0, 0.0], time: cosine(0.0) }, Forcing { shape: vec![0.0, -1.0, 0.0], time: cosine(ulp) }]);
    let flight = symmetric(FRAC_PI_2, 0.0, 0.0);
    for e in [0.0, 1.0] {
        for k in [1.0, 2.0, 4.0, 6.0] {
            let tg = FRAC_PI_2 + k * ulp;
            let mut r = EventDriven::new(&dy, 0.0, &[0.0, 0.0, tg.sin()], &[0.0, 0.0, -tg.cos()], e).expect("starts");
            r.run_until(3.0, 100).unwrap_or_else(|err| panic!("e = {e}, t_g = π/2 + {k} ulp: {err}"));
            let ev = r.events();
            let case = format!("e = {e}, t_g = π/2 + {k} ulp: {ev:?}");
            common::check_order(ev).unwrap();
            assert_eq!(ev.len(), 3, "{case}");
            let tol = 4.0 * resolution(FRAC_PI_2);
            for (row, c) in ev[..2].iter().zip([0, 1]) {
                assert!(row.kind == EventKind::Release && row.contact == c && (row.t - FRAC_PI_2).abs() <= tol, "{case}");
            }
            let imp = ev[2];
            assert!(imp.kind == EventKind::Impact && imp.contact == 2 && (imp.t - tg).abs() <= tol, "{case}");
            assert!((imp.velocity_before + 1.0).abs() <= 1e-15 && (imp.velocity_after - e).abs() <= 1e-15, "{case}");
            let (_, q, v) = r.state();
            let (x, dx) = flight(3.0);
            let (x2, v2) = (e * (3.0 - tg).sin(), e * (3.0 - tg).cos());
            for (d, (xe, ve)) in [(x, dx), (x, dx), (x2, v2)].into_iter().enumerate() {
                assert!((q[d] - xe).abs() <= 1e-13 && (v[d] - ve).abs() <= 1e-13, "{case}: dof {d} at 3: ({}, {}) against ({xe}, {ve})", q[d], v[d]);
            }
        }
    }
}

/// The dip's flight, `δ a²` high (1e-20 at δ = 1e-10) while the gap's
/// modal terms are O(1) (the static part, the resonant `t sin t`, the
/// homogeneous part): the search's steps per 4π run, against the flight's
/// own scale. The flight lasts `~4a` and is resolved by steps of a
/// fraction of `a`; a search bounding the curvature by its O(1) terms
/// steps `~√(δ a²)` instead and took 1.0e4 to 9.9e6 steps per run (δ =
/// 1e-6 … 1e-12). Each run: its two releases and landings, located as
/// [`a_dip_of_any_depth_releases_once_per_period`] checks.
#[test]
fn a_dip_is_searched_at_the_flights_own_scale() {
    for k in [12, 16, 20, 24] {
        let delta = 10f64.powf(-0.5 * k as f64);
        let mut r = EventDriven::new(&touch(delta), 0.0, &[0.0], &[0.0], 0.0).expect("starts");
        r.run_until(4.0 * PI, 100).unwrap_or_else(|e| panic!("δ = {delta:e}: {e}"));
        let ev = r.events();
        assert_eq!(ev.len(), 4, "δ = {delta:e}: {ev:?}");
        let steps = r.search_steps();
        println!("δ = {delta:e}: {steps} search steps");
        assert!(steps <= 1000, "δ = {delta:e}: {steps} search steps");
    }
}

/// The case above with dof 1's load `φ` = 2 to 6 ulps later (released at
/// `π/2 + φ`) and the impact at `t_g` from 3 ulps before π/2 to 9 after
/// (before, between and after the releases): each contact named once, a
/// release of 0 and of 1 and an impact of 2, in time order, the state at
/// 3 as the closed forms (before: with the impact between the releases,
/// a fourth row, contact 0 released again at contact 1's release, its gap
/// 1e-48 there located by a root step of 2e-24 s).
#[test]
fn releases_ulps_apart_around_an_impact_log_each_contact_once() {
    let ulp = f64::EPSILON;
    let cosine = |phase: f64| TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: 1.0, omega: 1.0, phase: FRAC_PI_2 - phase }]));
    let stop = |d| Contact::new(d, Bounds::obstacle(0.0), false);
    let flight = symmetric(FRAC_PI_2, 0.0, 0.0);
    let tol = 4.0 * resolution(FRAC_PI_2);
    for phi in [2.0, 3.0, 4.0, 6.0] {
        let dy = Dynamics::new(band(3, &[(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0)]), band(3, &[(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0)]), vec![0.0; 3], vec![stop(0), stop(1), stop(2)])
            .with_forcing(vec![Forcing { shape: vec![-1.0, 0.0, 0.0], time: cosine(0.0) }, Forcing { shape: vec![0.0, -1.0, 0.0], time: cosine(phi * ulp) }]);
        for e in [0.0, 1.0] {
            for k in [-3.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 9.0] {
                let tg = FRAC_PI_2 + k * ulp;
                let mut r = EventDriven::new(&dy, 0.0, &[0.0, 0.0, tg.sin()], &[0.0, 0.0, -tg.cos()], e).expect("starts");
                r.run_until(3.0, 100).unwrap_or_else(|err| panic!("φ = {phi} ulp, e = {e}, t_g = π/2 + {k} ulp: {err}"));
                let ev = r.events();
                let case = format!("φ = {phi} ulp, e = {e}, t_g = π/2 + {k} ulp: {ev:?}");
                common::check_order(ev).unwrap();
                assert_eq!(ev.len(), 3, "{case}");
                for (c, kind, t_c) in [(0, EventKind::Release, FRAC_PI_2), (1, EventKind::Release, FRAC_PI_2 + phi * ulp), (2, EventKind::Impact, tg)] {
                    let rows: Vec<_> = ev.iter().filter(|x| x.contact == c).collect();
                    assert!(rows.len() == 1 && rows[0].kind == kind && (rows[0].t - t_c).abs() <= tol, "{case}: contact {c}");
                }
                let imp = ev.iter().find(|x| x.contact == 2).expect("the impact");
                assert!((imp.velocity_before + 1.0).abs() <= 1e-15 && (imp.velocity_after - e).abs() <= 1e-15, "{case}");
                let (_, q, v) = r.state();
                let (x, dx) = flight(3.0);
                let (x1, dx1) = flight(3.0 - phi * ulp);
                let (x2, v2) = (e * (3.0 - tg).sin(), e * (3.0 - tg).cos());
                for (d, (xe, ve)) in [(x, dx), (x1, dx1), (x2, v2)].into_iter().enumerate() {
                    assert!((q[d] - xe).abs() <= 1e-13 && (v[d] - ve).abs() <= 1e-13, "{case}: dof {d} at 3: ({}, {}) against ({xe}, {ve})", q[d], v[d]);
                }
            }
        }
    }
}

/// `x'' + x = 0` from `(1, 0)` on a stop at 0, `e = 1/2`: the impact at
/// π/2 (`v⁻ = −1`), asked for at its own located time `t_e` from a
/// sample at 1.5 before it (the search's root step ends there, inside a
/// step). Without events at the pause (the orbits' section) the run
/// stands at `t_e` before it, `(cos t_e, −sin t_e)`, and takes it on the
/// next call; with them (the sampler) after it, `(0, e sin t_e)`; the
/// same row either way (before: applied in both modes, as a zero at a
/// step's start is only with them).
#[test]
fn an_impact_at_the_pause_located_inside_a_step_follows_the_pause_rule() {
    let e = 0.5;
    let dy = Dynamics::new(band(1, &[(0, 0, 1.0)]), band(1, &[(0, 0, 1.0)]), vec![0.0], vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
    let mut whole = EventDriven::new(&dy, 0.0, &[1.0], &[0.0], e).expect("starts");
    whole.run_until(3.0, 10).expect("runs");
    let te = whole.events()[0].t;
    assert!((te - FRAC_PI_2).abs() <= 4.0 * resolution(FRAC_PI_2), "{te}");
    for at_pause in [false, true] {
        let mut r = EventDriven::new(&dy, 0.0, &[1.0], &[0.0], e).expect("starts");
        r.take_events_at_pause(at_pause);
        r.run_until(1.5, 10).expect("runs");
        r.run_until(te, 10).expect("runs");
        let (t, q, v) = r.state();
        let (xe, ve) = if at_pause { (0.0, e * te.sin()) } else { (te.cos(), -te.sin()) };
        assert!(t == te && r.events().len() == usize::from(at_pause), "at pause {at_pause}: {:?}", r.events());
        assert!((q[0] - xe).abs() <= 1e-15 && (v[0] - ve).abs() <= 1e-15, "at pause {at_pause}: ({}, {}) against ({xe}, {ve})", q[0], v[0]);
        r.run_until(3.0, 10).expect("runs");
        assert_eq!(r.events(), whole.events(), "at pause {at_pause}");
        let (_, q, v) = r.state();
        let (xe, ve) = (e * te.sin() * (3.0 - te).sin(), e * te.sin() * (3.0 - te).cos());
        assert!((q[0] - xe).abs() <= 1e-14 && (v[0] - ve).abs() <= 1e-14, "at pause {at_pause}: ({}, {}) against ({xe}, {ve})", q[0], v[0]);
    }
}
