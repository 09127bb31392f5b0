//! What a new user hit (issue 22): tables that do not cover the domain,
//! exit codes of bad input, messages with numbers in shortest form.

use signorini_cli::scene::{SceneError, SceneFile};

fn validate(text: &str) -> Result<(), (String, String)> {
    match SceneFile::parse(text).expect("parses").validate() {
        Ok(_) => Ok(()),
        Err(SceneError::Field { field, message }) => Err((field, message)),
        Err(e) => panic!("{text}: expected a field error, got {e}"),
    }
}

fn bar(u0: &str, v0: &str) -> String {
    format!("[bar]\nlength = 1.0\nfar_end = \"free\"\ngap = -0.5\ninitial_displacement = {u0}\ninitial_velocity = {v0}\nelements = 20\nmass = \"mod\"\nscheme = \"newmark-cn\"\ndt = 0.05\nt_end = 1.0\n")
}

/// §6: a table outside the bar (or covering part of it) is refused naming
/// its key and the span it must cover; one that covers [0, L] is accepted,
/// to within the node tolerance.
#[test]
fn initial_tables_must_cover_the_bar() {
    for (u0, v0, key) in [
        ("[[5.0, 0.1], [6.0, 0.2]]", "0.0", "bar.initial_displacement"),
        ("[[0.0, 0.1], [0.5, 0.2]]", "0.0", "bar.initial_displacement"),
        ("[[0.1, 0.1], [1.0, 0.2]]", "0.0", "bar.initial_displacement"),
        ("0.0", "[[0.0, -1.0], [0.999, -1.0]]", "bar.initial_velocity"),
        ("[[0.5, 0.0]]", "0.0", "bar.initial_displacement"),
    ] {
        let (field, message) = validate(&bar(u0, v0)).expect_err(u0);
        assert_eq!(field, key, "{message}");
        assert!(message.contains("cover the whole [0, 1]"), "{message}");
    }
    for (u0, v0) in [("[[0.0, 0.1], [1.0, 0.2]]", "[[-1.0, 0.0], [2.0, -1.0]]"), ("[[1e-12, 0.1], [0.9999999999, 0.2]]", "0.0")] {
        validate(&bar(u0, v0)).unwrap_or_else(|e| panic!("{u0} {v0}: {e:?}"));
    }
}

/// §6 for `[obstacle]`: a table must cover the nodes it bounds (the beam's
/// unknown nodes, x = L/J … L).
#[test]
fn obstacle_tables_must_cover_the_bounded_nodes() {
    let scene = |lo: &str| format!("[beam]\nscene = \"fig2\"\n[obstacle]\nlo = {lo}\nhi = 0.1\n");
    let (field, message) = validate(&scene("[[0.5, -0.1], [1.0, -0.1]]")).expect_err("half the beam");
    assert_eq!(field, "obstacle.lo", "{message}");
    assert!(message.contains("is not allowed") && message.contains("cover"), "{message}");
    validate(&scene("[[0.0, -0.1], [1.501, -0.1]]")).expect("the whole beam (L = 1.501 m)");
}
