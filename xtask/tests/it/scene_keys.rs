//! The tests of `xtask::scene_keys` (xtask/src/scene_keys.rs).

use std::collections::BTreeSet;
use xtask::scene_keys::*;

fn root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The keys a table of the reader accepts, from serde's refusal of an
/// unknown key in it (`unknown field `zz`, expected one of `a`, `b`` /
/// `expected `a` or `b`` / `expected `a``).
fn accepted(doc: &str) -> BTreeSet<String> {
    let e = signorini_scene::SceneFile::parse(doc).expect_err("an unknown key must be refused").to_string();
    let (_, tail) = e.split_once("unknown field `zz_not_a_key`, expected").unwrap_or_else(|| panic!("not serde's unknown-field message for\n{doc}\n{e}"));
    let tail = tail.lines().next().unwrap_or("");
    tail.split('`').skip(1).step_by(2).map(String::from).collect()
}

/// The keys of the generated section whose title names `table`.
fn generated(secs: &[Section], table: &str) -> BTreeSet<String> {
    let found: Vec<&Section> = secs.iter().filter(|s| s.titles.iter().any(|t| t.starts_with(table) || t == table)).collect();
    assert_eq!(found.len(), 1, "one generated table for {table}; titles: {:?}", secs.iter().map(|s| &s.titles).collect::<Vec<_>>());
    found[0].rows.iter().map(|r| r[0].trim_matches('`').to_string()).collect()
}

#[test]
fn generated_keys_are_the_readers() {
    let secs = sections(&root()).unwrap();
    // (the generated table's title, a document with an unknown key in
    // that table). Written out here, independently of the generator.
    let probes: [(&str, &str); 12] = [
        ("Top level", "zz_not_a_key = 1\n"),
        ("`[bar]`", "[bar]\nzz_not_a_key = 1\n"),
        ("`[beam]`", "[beam]\nzz_not_a_key = 1\n"),
        ("`[oscillator]`", "[oscillator]\nzz_not_a_key = 1\n"),
        ("`[[stop]]`", "[[stop]]\nzz_not_a_key = 1\n"),
        ("`[obstacle]`", "[obstacle]\nzz_not_a_key = 1\n"),
        ("`[output]`", "[output]\nzz_not_a_key = 1\n"),
        ("`[forcing]`", "[forcing]\nzz_not_a_key = 1\n"),
        ("`[support]`", "[support]\nzz_not_a_key = 1\n"),
        ("`[load]`", "[load]\nzz_not_a_key = 1\n"),
        ("`reduce = { … }`", "[bar]\nreduce = { zz_not_a_key = 1 }\n"),
        ("`reduce = { … }`", "[beam]\nreduce = { zz_not_a_key = 1 }\n"),
    ];
    for (table, doc) in probes {
        assert_eq!(generated(&secs, table), accepted(doc), "the generated keys of {table} differ from what the reader accepts ({doc:?})");
    }
    // Every generated table is probed: a new table needs a probe here.
    for s in &secs {
        assert!(s.titles.iter().any(|t| probes.iter().any(|(p, _)| t.starts_with(p))), "no probe for the generated table {:?}: add one", s.titles);
    }
}

#[test]
fn every_key_is_documented_and_typed() {
    for s in sections(&root()).unwrap() {
        assert!(!s.doc.is_empty(), "{:?} has no doc comment", s.titles);
        for r in &s.rows {
            assert!(!r[3].is_empty(), "{:?} {}: no `///` doc comment", s.titles, r[0]);
        }
    }
    let md = render(&root()).unwrap();
    assert!(md.contains("| `mass` | string | default `\"std\"` |"), "{md}");
    assert!(md.contains("| `initial_displacement` | number, string or `[[a, b], …]` | optional |"), "{md}");
    assert!(md.contains("| `stops` | `[a, b]` pair | optional |"), "{md}");
    assert!(md.contains("| `plots` | bool | default `true` |"), "{md}");
}

#[test]
fn an_attribute_it_does_not_know_is_refused() {
    let dir = std::env::temp_dir().join(format!("scene-keys-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("crates/scene/src")).unwrap();
    std::fs::write(dir.join(SOURCES[0]), "#[derive(Deserialize)]\n#[serde(deny_unknown_fields)]\npub struct SceneFile {\n    /// A.\n    #[serde(rename = \"b\")]\n    pub a: f64,\n}\n").unwrap();
    std::fs::write(dir.join(SOURCES[1]), "").unwrap();
    let e = render(&dir).err().unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(e.contains("rename") && e.contains("SceneFile.a"), "{e}");
}
