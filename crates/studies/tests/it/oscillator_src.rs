//! The tests of `signorini_studies::oscillator` that were unit tests in src/oscillator.rs (the
//! library is not compiled a second time as a test harness).

/// The scene as the study built it before the presets: the data file's
/// text with three values replaced.
fn old_text(dt: f64, x0: f64, v0: f64) -> String {
    std::fs::read_to_string(format!("{}/../../data/scenes/oscillator.toml", env!("CARGO_MANIFEST_DIR")))
        .expect("the data file")
        .replace("dt = 1e-3", &format!("dt = {dt:e}"))
        .replace("initial_displacement = 0.0", &format!("initial_displacement = {x0:e}"))
        .replace("initial_velocity = 0.0", &format!("initial_velocity = {v0:e}"))
}

#[test]
fn the_edited_preset_is_the_scene_the_text_edits_gave() {
    for (dt, x0, v0) in [(1e-4, 0.0, 0.0), (7.8125e-6, -0.123_456_789_012_345_67, 1.0 / 3.0), (2e-3, 0.2, -0.9)] {
        let old = signorini_scene::SceneFile::parse(&old_text(dt, x0, v0)).unwrap();
        let new = signorini_scene::SceneFile::parse(&signorini_studies::oscillator::scene_text(dt, x0, v0).unwrap()).unwrap();
        assert_eq!(new, old, "dt {dt}, x0 {x0}, v0 {v0}");
        let o = new.oscillator.as_ref().expect("an oscillator");
        assert_eq!((o.dt, o.initial_displacement, o.initial_velocity), (dt, Some(x0), Some(v0)));
    }
}
