//! Fuzzing of the scene reader and validator (issue 11 §3): generated scene
//! documents and byte-level mutations of the shipped scenes never make
//! `parse` or `validate` panic, every rejection is a typed error naming a
//! field of the document and what is allowed, and the generator's valid and
//! invalid values are accepted and refused (see `signorini_fuzz`).
//! The long run is `cargo xtask fuzz`.

use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::TestRunner;
use signorini_fuzz::{self as fuzz, Config, Outcome};
use signorini_scene::{Scene, SceneError};
use std::collections::BTreeMap;
use std::path::Path;

/// The shipped scenes (data/scenes/*.toml), sorted by name.
fn shipped_scenes() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "toml")).collect();
    paths.sort();
    paths.iter().map(|p| std::fs::read_to_string(p).unwrap()).collect()
}

/// A short run from a fixed seed (the same inputs every time; the variable
/// SCENE_FUZZ_CASES sets the number of cases per generator).
#[test]
fn scene_reader_fuzz() {
    let scenes = shipped_scenes();
    assert!(scenes.len() >= 10, "only {} shipped scenes found", scenes.len());
    let cases: u32 = std::env::var("SCENE_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(20_000);
    match fuzz::fuzz(Config::TODAY, cases, 11, scenes, &|_| {}) {
        Ok(stats) => assert_eq!((stats.documents, stats.mutations), (cases, cases)),
        Err(f) => panic!("{} generator: {}\n--- input ---\n{}\n---", f.generator, f.reason, f.input),
    }
}

/// The generator is not vacuous: from a fixed seed, documents are accepted,
/// fail to parse, and are refused naming each table and many keys.
#[test]
fn generator_reaches_every_answer() {
    let mut runner = TestRunner::deterministic();
    let docs = fuzz::documents(Config::TODAY);
    let mut answers: BTreeMap<String, u32> = BTreeMap::new();
    // Documents with [[stop]] or [obstacle]: (with the bar, with the beam) accepted.
    let mut contacts_accepted = (0, 0);
    // `[oscillator]` scenes accepted (each then run by `check_doc`).
    let mut oscillators_accepted = 0;
    let n = 4000;
    for _ in 0..n {
        let doc = docs.new_tree(&mut runner).unwrap().current();
        let text = doc.render();
        let with_contacts = doc.tables.iter().any(|t| t.name == "stop" || t.name == "obstacle");
        let answer = match fuzz::run_reader(&text, Config::TODAY).unwrap() {
            Outcome::Parsed(_, Some(Ok(scene))) if with_contacts => {
                match scene {
                    Scene::Bar(_) => contacts_accepted.0 += 1,
                    Scene::Beam { .. } => contacts_accepted.1 += 1,
                    Scene::Oscillator { .. } => unreachable!("contacts are refused with [oscillator]"),
                }
                "accepted".to_string()
            }
            Outcome::ParseError(_) => "parse error".to_string(),
            Outcome::Parsed(_, None) => "not validated".to_string(),
            Outcome::Parsed(_, Some(Ok(Scene::Oscillator { .. }))) => {
                oscillators_accepted += 1;
                "accepted".to_string()
            }
            Outcome::Parsed(_, Some(Ok(_))) => "accepted".to_string(),
            Outcome::Parsed(_, Some(Err(SceneError::Field { field, .. }))) => field,
            Outcome::Parsed(_, Some(Err(e))) => format!("{e:?}"),
        };
        *answers.entry(answer).or_default() += 1;
    }
    let share = |k: &str| f64::from(answers.get(k).copied().unwrap_or(0)) / f64::from(n);
    // Validation builds the integrator and wants whole-step horizons, so
    // fewer random documents pass than parse errors (measured 8.7 %).
    assert!(share("accepted") > 0.05 && share("parse error") > 0.1 && share("parse error") < 0.5, "{answers:?}");
    for field in [
        "bar/beam",
        "output.every",
        "bar",
        "bar.benchmark",
        "bar.length",
        "bar.wave_speed",
        "bar.far_end",
        "bar.gap",
        "bar.body_force",
        "bar.initial_displacement",
        "bar.initial_velocity",
        "bar.elements",
        "bar.mass",
        "bar.scheme",
        "bar.dt",
        "bar.ratio",
        "bar.t_end",
        "beam.scene",
        "beam.elements",
        "beam.dt",
        "beam.t_end",
        "beam.contact",
        "beam.beta",
        "beam.penalty_stiffness",
        "beam.stops",
        "beam.support",
        "stop",
        "stop.0.x",
        "stop.0.lo",
        "stop.0.hi",
        "stop.0.restitution",
        "stop.0.stiffness",
        "stop.1.x",
        "obstacle",
        "obstacle.lo",
        "obstacle.hi",
        "oscillator.mass",
        "oscillator.stiffness",
        "oscillator.damping_ratio",
        "oscillator.stop",
        "oscillator.stops",
        "oscillator.restitution",
        "oscillator.initial_displacement",
        "oscillator.initial_velocity",
        "oscillator.scheme",
        "oscillator.dt",
        "oscillator.t_end",
        "forcing.amplitude",
        "forcing.omega",
        "support",
        "load",
    ] {
        assert!(answers.contains_key(field), "no document refused naming {field}: {answers:?}");
    }
    // Valid stops and obstacles are accepted, with the bar and with the beam.
    assert!(contacts_accepted.0 >= 10 && contacts_accepted.1 >= 10, "documents with contacts accepted (bar, beam): {contacts_accepted:?}");
    assert!(oscillators_accepted >= 20, "oscillator scenes accepted: {oscillators_accepted}");
}
