//! `reduce = { modes = r }` / `{ cutoff_hz = f }` in `[bar]` and `[beam]`
//! (docs/theory.md §2.5): bad input refused naming the field; a valid
//! reduced bar scene runs through `run_scene` to the full model's norms.

use signorini_cli::scene::{SceneError, SceneFile};

fn refused(text: &str) -> (String, String) {
    match SceneFile::parse(text).and_then(|f| f.validate().map(|_| ())) {
        Err(SceneError::Field { field, message }) => (field, message),
        Err(SceneError::Toml(e)) => ("toml".into(), e.to_string()),
        Ok(()) => panic!("accepted:\n{text}"),
        Err(e) => panic!("neither a field nor a TOML error: {e:?}"),
    }
}

fn bar(mass: &str, scheme: &str, reduce: &str) -> String {
    format!("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 20\nmass = \"{mass}\"\nscheme = \"{scheme}\"\nratio = 10.0\nreduce = {reduce}\n")
}

#[test]
fn bad_reduce_input_names_the_field() {
    assert_eq!(refused(&bar("mod", "newmark-cn", "{ modes = 0 }")).0, "bar.reduce.modes");
    // 20 elements, clamped end: 20 unknowns, 1 contact, 19 interior modes.
    assert_eq!(refused(&bar("mod", "newmark-cn", "{ modes = 20 }")).0, "bar.reduce.modes");
    assert!(SceneFile::parse(&bar("mod", "newmark-cn", "{ modes = 19 }")).unwrap().validate().is_ok());
    // The first fixed-interface mode of the mod bar at m = 20 is near
    // c/(2L) = 0.5 Hz (the clamped–clamped bar): 0.1 Hz is below it.
    let (f, m) = refused(&bar("mod", "newmark-cn", "{ cutoff_hz = 0.1 }"));
    assert_eq!(f, "bar.reduce.cutoff_hz", "{m}");
    assert!(SceneFile::parse(&bar("mod", "newmark-cn", "{ cutoff_hz = 2.0 }")).unwrap().validate().is_ok());
    assert_eq!(refused(&bar("mod", "newmark-cn", "{ modes = 2, cutoff_hz = 2.0 }")).0, "bar.reduce.cutoff_hz");
    assert_eq!(refused(&bar("mod", "newmark-cn", "{ }")).0, "bar.reduce");
    let (f, m) = refused(&bar("mod", "newmark-cn", "{ modes = 2, mode = 3 }"));
    assert!(f == "toml" && m.contains("mode"), "{f}: {m}");
    // A massive parent mass, and a scheme that needs a massive node.
    assert_eq!(refused(&bar("std", "newmark-cn", "{ modes = 4 }")).0, "bar.mass");
    assert_eq!(refused(&bar("std", "moreau-jean", "{ modes = 4 }")).0, "bar.scheme");
    assert_eq!(refused(&bar("lumped", "ps(0,0.1)", "{ modes = 4 }")).0, "bar.scheme");
    // The beam: 38 unknowns, 1 contact, 37 modes; β < 1/4 is unstable with a massless tip.
    let beam = |extra: &str| format!("[beam]\nscene = \"fig2\"\n{extra}\n");
    assert_eq!(refused(&beam("reduce = { modes = 38 }")).0, "beam.reduce.modes");
    assert_eq!(refused(&beam("reduce = { modes = 4 }\nbeta = 0.0")).0, "beam.beta");
    assert!(SceneFile::parse(&beam("reduce = { modes = 37 }")).unwrap().validate().is_ok());
}
