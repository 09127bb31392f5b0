//! A transient stopped on a continuation's orbit: on the oscillator of
//! `basins.rs` (stop 0.5, Ω = 1.85), the known orbits of a `branch.csv`
//! written here from the closed forms — the free response and the stable
//! impacting period-1 orbit (stable), the unstable impacting ones, and the
//! stable impacting orbit at Ω = 1.80 (another value of the continued
//! parameter) — give the targets of the stable orbits at the scene's value
//! alone, and each cell whose transient stops on one of them (no seed
//! targets) is classified and labelled as an independent event-driven run
//! (closed-form flights, impacts bisected) ends after 260 forcing periods,
//! and as the full transient classifies it (class and label), the
//! targets in both orders. Two starts beside the unstable orbit (1e-2
//! along its stable direction, ±1e-5 along its unstable one) come close
//! to it and leave: made a target, it stopped the first after 3 periods.

use crate::basins::{independent, OMEGA, SCENE};
use signorini_exact::{ImpactOscillator, OscillatorParams, State};
use signorini_orbits::basins::{classify, match_known, parse_branch, Axis, BasinOptions, BasinScene, KnownOrbit, Outcome};
use signorini_scene::Limits;
use std::f64::consts::TAU;
use std::fmt::Write as _;

/// The admissible impacting period-1 orbits at `omega` on the section
/// (forcing phase 0), in closed form, each with its stability.
fn impacting(omega: f64) -> Vec<([f64; 2], bool)> {
    let osc = ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: omega, gap: 0.5, restitution: 0.8 }).unwrap();
    let t = TAU / omega;
    osc.period1_orbits()
        .into_iter()
        .filter(|o| o.is_admissible())
        .map(|o| {
            let z = osc.flow(o.impact_time.rem_euclid(t), State { x: 0.5, v: -0.8 * o.impact_velocity }, t);
            ([z.x, z.v], o.is_stable())
        })
        .collect()
}

/// The free response's point on the section (the linear steady state).
fn free(omega: f64) -> [f64; 2] {
    let (c, k) = (2.0 * 0.05, 1.0 - omega * omega);
    let (amp, phi) = (1.0 / (k * k + (c * omega).powi(2)).sqrt(), (c * omega).atan2(k));
    [amp * phi.cos(), amp * omega * phi.sin()]
}

#[test]
fn a_transient_stopped_on_a_branch_orbit_ends_where_an_independent_run_ends() {
    // branch.csv: branch 0 the impacting orbits at 1.80 then 1.85 (stable
    // and unstable), branch 1 the free response at 1.85.
    let mut text = String::from("param,period,stable,branch,q0,v0\n");
    let (here, there) = (impacting(OMEGA), impacting(1.80));
    assert!(here.iter().filter(|o| o.1).count() == 1 && here.iter().any(|o| !o.1), "a stable and an unstable impacting orbit at 1.85: {here:?}");
    for (omega, orbits) in [(1.80, &there), (OMEGA, &here)] {
        for (s, stable) in orbits {
            let _ = writeln!(text, "{omega},1,{},0,{:e},{:e}", u8::from(*stable), s[0], s[1]);
        }
    }
    let f = free(OMEGA);
    let _ = writeln!(text, "{OMEGA},1,1,1,{:e},{:e}", f[0], f[1]);
    let known = parse_branch(&text).unwrap();
    let doc: toml::Table = SCENE.parse().unwrap();
    let x = Axis { path: "oscillator.initial_displacement".into(), from: -2.0, to: 0.4, count: 12 };
    let v = Axis { path: "oscillator.initial_velocity".into(), from: -1.5, to: 1.5, count: 10 };
    let scene = BasinScene::new(doc, x.clone(), v.clone(), Limits::machine()).unwrap();
    let opts = BasinOptions::default();
    let targets = scene.known_targets(&known, &[], &opts).unwrap();
    // The two stable orbits at 1.85, at their closed forms; not the
    // unstable ones, not the orbit at 1.80.
    let stable: Vec<[f64; 2]> = here.iter().filter(|o| o.1).map(|o| o.0).chain([f]).collect();
    assert_eq!(targets.len(), 2, "{targets:?}");
    let at = |t: &signorini_orbits::basins::Target, s: [f64; 2]| (t.point[0] - s[0]).abs() < 1e-7 && (t.point[1] - s[1]).abs() < 1e-7;
    for s in &stable {
        assert_eq!(targets.iter().filter(|t| at(t, *s)).count(), 1, "{s:?} among the targets {targets:?}");
    }
    // The label a state ends with: the nearest known orbit of period 1
    // within match_tol (written here, not the crate's match_known).
    let label_of = |s: [f64; 2]| -> Option<String> {
        let tol = opts.match_tol * s[0].abs().max(s[1].abs()).max(1.0);
        let (mut best, mut name) = (f64::INFINITY, None);
        let mut index = [0usize; 2];
        for line in text.lines().skip(1) {
            let c: Vec<f64> = line.split(',').map(|w| w.parse().unwrap()).collect();
            let b = c[3] as usize;
            let d = (c[4] - s[0]).abs().max((c[5] - s[1]).abs());
            if d <= tol && d < best {
                (best, name) = (d, Some(format!("branch{b}:{}", index[b])));
            }
            index[b] += 1;
        }
        name
    };
    let label = |a: &signorini_orbits::basins::Attractor, known: &[KnownOrbit]| match_known(a, known, opts.match_tol).map(|o| o.label.clone());
    let t = TAU / OMEGA;
    let hit = stable[0];
    // The targets in both orders: a cell is tried against each in turn
    // at each forcing period.
    let reversed: Vec<_> = targets.iter().rev().cloned().collect();
    let mut stopped = [0usize; 2];
    for (cell, targets) in (0..scene.cells()).flat_map(|c| [(c, &targets), (c, &reversed)]) {
        let (i, j) = scene.ij(cell);
        let (Outcome::Attractor(a), Some(k)) = scene.classify_near(cell, &opts, targets) else { continue };
        assert!(k < opts.transient, "cell {cell}: stopped at {k}");
        let (x0, v0) = (x.value(i), v.value(j));
        let end = independent(x0, v0, 260.0 * t);
        let on_hit = (end[0] - hit[0]).abs().max((end[1] - hit[1]).abs()) < 1e-3;
        assert_eq!((a.period, a.impacts, a.sticking), (1, usize::from(on_hit), false), "cell {cell} ({x0}, {v0}) stopped at period {k}: the independent run ends at {end:?}");
        assert_eq!(label(&a, &known), label_of(end), "cell {cell} ({x0}, {v0}) stopped at period {k}: the independent run ends at {end:?}");
        // And as the cell's whole transient classifies it.
        let built = scene.build(i, j).unwrap();
        let full = classify(&built.model, built.omega, &built.start, &opts).unwrap();
        assert_eq!((a.period, a.impacts, a.sticking, label(&a, &known)), (full.period, full.impacts, full.sticking, label(&full, &known)), "cell {cell}");
        assert!(a.state.iter().zip(&full.state).all(|(p, q)| (p - q).abs() < 1e-10), "cell {cell}: {:?} against {:?}", a.state, full.state);
        stopped[usize::from(on_hit)] += 1;
    }
    // Cells started near the unstable orbit at 1.85: 1e-2 from it along
    // its stable direction and ±1e-5 along its unstable one (the map's
    // Jacobian there by central differences of the independent run), so
    // that they come closer to it for a few periods before they leave it
    // for a stable orbit, on the side the offset says. None may stop on
    // it: each is classified as the independent run ends.
    for saddle in here.iter().filter(|o| !o.1).map(|o| o.0) {
        let h = 1e-6;
        let column = |k: usize| {
            let (mut p, mut m) = (saddle, saddle);
            p[k] += h;
            m[k] -= h;
            let (a, b) = (independent(p[0], p[1], t), independent(m[0], m[1], t));
            [(a[0] - b[0]) / (2.0 * h), (a[1] - b[1]) / (2.0 * h)]
        };
        let (c0, c1) = (column(0), column(1));
        let (tr, det) = (c0[0] + c1[1], c0[0] * c1[1] - c1[0] * c0[1]);
        let disc = tr * tr / 4.0 - det;
        assert!(disc > 0.0, "real multipliers at the unstable orbit: {c0:?} {c1:?}");
        let (l1, l2) = (tr / 2.0 - disc.sqrt(), tr / 2.0 + disc.sqrt());
        let (ls, lu) = if l1.abs() < l2.abs() { (l1, l2) } else { (l2, l1) };
        assert!(ls.abs() < 1.0 && lu.abs() > 1.0, "a saddle: {ls}, {lu}");
        // (J − λ) w = 0: w = (J01, λ − J00), scaled to ‖w‖∞ = 1.
        let dir = |l: f64| {
            let w = [c1[0], l - c0[0]];
            let n = w[0].abs().max(w[1].abs());
            [w[0] / n, w[1] / n]
        };
        let (ws, wu) = (dir(ls), dir(lu));
        for side in [1.0, -1.0] {
            let (x0, v0) = (saddle[0] + 1e-2 * ws[0] + side * 1e-5 * wu[0], saddle[1] + 1e-2 * ws[1] + side * 1e-5 * wu[1]);
            let doc: toml::Table = SCENE.parse().unwrap();
            let one = |path: &str, at: f64| Axis { path: path.into(), from: at, to: at, count: 1 };
            let near = BasinScene::new(doc, one("oscillator.initial_displacement", x0), one("oscillator.initial_velocity", v0), Limits::machine()).unwrap();
            let (Outcome::Attractor(a), k) = near.classify_near(0, &opts, &targets) else { panic!("({x0}, {v0}) failed") };
            let end = independent(x0, v0, 260.0 * t);
            let on_hit = (end[0] - hit[0]).abs().max((end[1] - hit[1]).abs()) < 1e-3;
            assert_eq!((a.period, a.impacts, label(&a, &known)), (1, usize::from(on_hit), label_of(end)), "({x0}, {v0}) by the unstable orbit, stopped at {k:?}: the independent run ends at {end:?}");
        }
    }
    assert!(stopped[0] >= 5 && stopped[1] >= 5 && stopped[0] + stopped[1] > scene.cells(), "cells stopped on each branch orbit: {stopped:?}");
}
