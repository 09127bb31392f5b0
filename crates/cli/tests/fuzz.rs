//! Fuzzing of the scene reader and validator (issue 11 §3): generated scene
//! documents and byte-level mutations of the shipped scenes never make
//! `parse` or `validate` panic, every rejection is a typed error naming a
//! field of the document and what is allowed, and the generator's valid and
//! invalid values are accepted and refused (see `signorini_cli::fuzz`).
//! The long run is `cargo xtask fuzz`.

use signorini_cli::fuzz::{self, Config};
use std::path::Path;

/// The shipped scenes (data/scenes/*.toml), sorted by name.
fn shipped_scenes() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "toml")).collect();
    paths.sort();
    paths.iter().map(|p| std::fs::read_to_string(p).unwrap()).collect()
}

/// A short run from a fixed seed (the same inputs every time).
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
