//! The tests of `signorini_studies::lyapunov` that were unit tests in src/lyapunov.rs (the
//! library is not compiled a second time as a test harness).

use signorini_scene::presets::Preset;
use signorini_scene::SceneFile;
use signorini_studies::lyapunov::*;

/// The scene as the study built it before the presets: the data file's
/// text with keys inserted after `[beam]`, or two values replaced.
fn old_text(case: &Case, t_end: f64) -> String {
    let file = |name: &str| std::fs::read_to_string(format!("{}/../../data/scenes/{name}", env!("CARGO_MANIFEST_DIR"))).expect("the data file");
    match case {
        Case::Beam { name, dt, elements, .. } => {
            let mut keys = format!("t_end = {t_end:e}\n");
            if let Some(dt) = dt {
                keys.push_str(&format!("dt = {dt:e}\n"));
            }
            if let Some(j) = elements {
                keys.push_str(&format!("elements = {j}\n"));
            }
            let base = match name.as_str() {
                "fig2-support" => file("beam-fig2-support.toml"),
                "beam-obstacles" => file("beam-obstacles.toml"),
                fig => format!("[beam]\nscene = \"{fig}\"\n"),
            };
            let (head, tail) = base.split_once("[beam]\n").expect("a beam scene");
            format!("{head}[beam]\n{keys}{tail}")
        }
        Case::Oscillator { omega } => file("oscillator.toml").replace("t_end = 100.0", &format!("t_end = {t_end:e}")).replace("omega = 2.0", &format!("omega = {omega:e}")),
    }
}

#[test]
fn the_edited_presets_are_the_scenes_the_text_edits_gave() {
    let cases = [
        Case::Beam { name: "fig2-support".into(), dt: None, elements: None, scheme: None },
        Case::Beam { name: "fig2-support".into(), dt: Some(2.5e-5), elements: Some(38), scheme: None },
        Case::Beam { name: "beam-obstacles".into(), dt: None, elements: None, scheme: None },
        Case::Beam { name: "fig5".into(), dt: Some(1e-5), elements: Some(19), scheme: None },
        Case::Oscillator { omega: 1.7 },
    ];
    for case in &cases {
        let t_end = 1.0_f64 / 3.0 + 2.0;
        let old = SceneFile::parse(&old_text(case, t_end)).expect("the old text parses");
        let new = scene_file(case, t_end).expect("the preset edits");
        assert_eq!(new, old, "{}", label(case));
        // And each edit took: the values are the ones asked for, not the file's.
        match (case, &new) {
            (Case::Oscillator { omega }, f) => {
                assert_eq!(f.oscillator.as_ref().map(|o| o.t_end), Some(t_end));
                assert!(format!("{:?}", f.forcing).contains(&format!("{omega:?}")), "{:?}", f.forcing);
            }
            (Case::Beam { dt, elements, .. }, f) => {
                let b = f.beam.as_ref().expect("a beam");
                assert_eq!(b.t_end, Some(t_end));
                assert_eq!(b.dt, *dt);
                assert_eq!(b.elements, *elements);
            }
        }
    }
}

#[test]
fn an_edit_of_a_key_the_preset_does_not_have_fails() {
    // A table that is not there: set_path itself refuses, naming the path.
    let e = Preset::Oscillator.edited(&[("forcing2.omega", 1.8.into())]).expect_err("forcing2 is not a table of the scene");
    assert!(e.to_string().starts_with("forcing2.omega: forcing2 is not in the scene"), "{e}");
    // A key the scene does not have: the scene reader refuses it.
    assert!(Preset::Oscillator.edited(&[("forcing.omga", 1.8.into())]).is_err());
    assert!(Preset::Fig2Support.edited(&[("beam.t_ned", 1.0.into())]).is_err());
    // A value where a table is: refused.
    assert!(Preset::Oscillator.edited(&[("oscillator.mass.x", 1.0.into())]).is_err());
}

#[test]
fn one_path_editor_walks_keys_and_list_entries_for_presets_and_sweeps() {
    // The studies' edits (any value) and the sweeps' and orbit families'
    // (numbers) walk a document the same way: keys, then list indices.
    let text = "[a]\nn = 3\nx = 1.5\nname = \"s\"\n[[stop]]\nhi = 0.1\n";
    let mut doc: toml::Table = text.parse().unwrap();
    signorini_scene::presets::set_path(&mut doc, "stop.0.hi", 0.25.into()).unwrap();
    assert_eq!(doc["stop"].as_array().unwrap()[0]["hi"].as_float(), Some(0.25));
    assert_eq!(signorini_scene::presets::get_path(&doc, "stop.0.hi").and_then(|v| v.as_float()), Some(0.25));
    assert_eq!(signorini_scene::presets::get_path(&doc, "stop.1.hi"), None);
    // The sweep's numeric edit keeps an integer literal integral where it can.
    signorini_sweep::set_path(&mut doc, "a.n", 4.0).unwrap();
    assert_eq!(doc["a"]["n"].as_integer(), Some(4));
    signorini_sweep::set_path(&mut doc, "a.n", 4.5).unwrap();
    assert_eq!(doc["a"]["n"].as_float(), Some(4.5));
    signorini_sweep::set_path(&mut doc, "stop.0.hi", 2.0).unwrap();
    assert_eq!(doc["stop"].as_array().unwrap()[0]["hi"].as_float(), Some(2.0));
    signorini_sweep::set_path(&mut doc, "a.new", 7.0).unwrap();
    assert_eq!(doc["a"]["new"].as_integer(), Some(7));
    // Refusals, each naming where the walk stopped.
    let sweep_err = |doc: &mut toml::Table, path: &str| signorini_sweep::set_path(doc, path, 1.0).unwrap_err().to_string();
    for (path, needle) in [
        ("stop.1", "stop has 1 entries: index 1 is out of range"),
        ("stop.1.hi", "stop.1 is not in the scene"),
        ("stop.x", "stop is a list: the next segment is an index 0..1"),
        ("a.x.y", "a.x is a value, not a table"),
        ("b.x", "b is not in the scene (the scene has: a, stop)"),
        ("a.name", "names a string value, not a number"),
        ("a..x", "a dotted path of keys and array indices"),
    ] {
        let e = sweep_err(&mut doc, path);
        assert!(e.contains(needle), "{path}: {e}");
    }
    let e = signorini_scene::presets::set_path(&mut doc, "stop.x", 1.0.into()).unwrap_err().to_string();
    assert!(e.starts_with("stop.x: stop is a list"), "{e}");
    // A refused edit leaves the document as it was.
    assert_eq!(doc["stop"].as_array().unwrap()[0]["hi"].as_float(), Some(2.0));
    assert_eq!(doc["a"]["x"].as_float(), Some(1.5));
}
