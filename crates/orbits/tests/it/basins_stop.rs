//! A transient stopped on a known attractor: on the oscillator of
//! `basins.rs` (stop 0.5, Ω = 1.85: the free response and an impacting
//! period-1 orbit, both stable), each cell whose transient stops early on
//! a seed's target is classified as an independent event-driven run
//! (closed-form flights, impacts bisected) ends after 260 forcing periods
//! (all 120 cells stop, after 9 to 34 periods; a radius made infinite
//! stops cell 49 on the wrong attractor after 3); and with a transient of
//! 16 periods, too short for most cells to stop, every cell not stopped is
//! `classify`'s result bit for bit (the same run, read at each period on
//! the way; a run started again at each reading differs in the last bits).

use crate::basins::{impacting, independent, OMEGA, SCENE};
use signorini_orbits::basins::{classify, Axis, BasinOptions, BasinScene, Outcome};
use signorini_scene::Limits;
use std::f64::consts::TAU;

#[test]
fn a_stopped_transient_ends_where_an_independent_run_ends() {
    let doc: toml::Table = SCENE.parse().unwrap();
    let x = Axis { path: "oscillator.initial_displacement".into(), from: -2.0, to: 0.4, count: 12 };
    let v = Axis { path: "oscillator.initial_velocity".into(), from: -1.5, to: 1.5, count: 10 };
    let scene = BasinScene::new(doc, x.clone(), v.clone(), Limits::machine()).unwrap();
    let opts = BasinOptions::default();
    let seeds = scene.seeds();
    assert_eq!(seeds.len(), 64);
    let outcomes: Vec<Outcome> = seeds.iter().map(|&c| scene.classify(c, &opts)).collect();
    let targets = scene.targets(&seeds, &outcomes, &opts).unwrap();
    assert_eq!(targets.len(), 2, "both attractors are targets");
    let hit = impacting();
    let t = TAU / OMEGA;
    let (mut stopped, mut whole) = (0, 0);
    for cell in 0..scene.cells() {
        let (i, j) = scene.ij(cell);
        let (Outcome::Attractor(a), k) = scene.classify_near(cell, &opts, &targets) else { panic!("cell {cell} failed") };
        match k {
            Some(k) => {
                assert!(k < opts.transient, "cell {cell}: stopped at {k}");
                // Where an independent run from the cell's start ends.
                let (x0, v0) = (x.value(i), v.value(j));
                let end = independent(x0, v0, 260.0 * t);
                let on_hit = (end[0] - hit[0]).abs().max((end[1] - hit[1]).abs()) < 1e-3;
                assert_eq!((a.period, a.impacts, a.sticking), (1, usize::from(on_hit), false), "cell {cell} ({x0}, {v0}) stopped at period {k}: the independent run ends at {end:?}");
                stopped += 1;
            }
            None => {
                let built = scene.build(i, j).unwrap();
                assert_eq!(a, classify(&built.model, built.omega, &built.start, &opts).unwrap(), "cell {cell}");
                whole += 1;
            }
        }
    }
    assert!(stopped > scene.cells() / 2, "{stopped} cells stopped early, {whole} ran their whole transient");
    // A transient too short for most cells to stop: those that run it
    // whole are `classify`'s cells, bit for bit.
    let short = BasinOptions { transient: 16, ..BasinOptions::default() };
    let mut whole = 0;
    for cell in 0..scene.cells() {
        let (i, j) = scene.ij(cell);
        if let (Outcome::Attractor(a), None) = scene.classify_near(cell, &short, &targets) {
            let built = scene.build(i, j).unwrap();
            assert_eq!(a, classify(&built.model, built.omega, &built.start, &short).unwrap(), "cell {cell}, a transient of 16 periods");
            whole += 1;
        }
    }
    assert!(whole > 20, "{whole} cells ran the short transient whole");
}
