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
    format!(
        "[bar]\nlength = 1.0\nfar_end = \"free\"\ngap = -0.5\ninitial_displacement = {u0}\ninitial_velocity = {v0}\nelements = 20\nmass = \"mod\"\nscheme = \"newmark-cn\"\ndt = 0.05\nt_end = 1.0\n"
    )
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

/// Runs `signorini <args>`: (exit code, stderr).
fn cli(args: &[&str]) -> (Option<i32>, String) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_signorini")).args(args).output().expect("the binary starts");
    (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// §11: a missing scene file and an `--out` that is a file are bad input:
/// exit 2 with words, not "os error 17"; nothing is run.
#[test]
fn missing_scene_and_out_on_a_file_exit_2() {
    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("nowhere/x.toml");
    for cmd in ["run", "check", "sweep"] {
        let mut args = vec![cmd, missing.to_str().expect("utf-8")];
        if cmd == "sweep" {
            args.extend(["--param", "oscillator.omega", "--from", "1", "--to", "2", "--count", "2"]);
        }
        let (code, err) = cli(&args);
        assert_eq!(code, Some(2), "{cmd}: {err}");
        assert!(err.contains("cannot read the scene file") && err.contains("no such file") && !err.contains("os error"), "{cmd}: {err}");
    }
    let file = dir.path().join("afile");
    std::fs::write(&file, "x").expect("write");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/oscillator.toml");
    let (code, err) = cli(&["run", scene, "--out", file.to_str().expect("utf-8")]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--out") && err.contains("not a folder") && !err.contains("os error"), "{err}");
}

/// §11: very large and very small numbers reach the user in exponent form,
/// never as 300-digit decimals.
#[test]
fn huge_and_tiny_numbers_in_messages_have_an_exponent() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (dt, want) in [("1e300", "dt = 1e300"), ("1e-300", "1e-300 gives")] {
        let p = dir.path().join("s.toml");
        std::fs::write(&p, format!("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 20\nmass = \"mod\"\nscheme = \"newmark-cn\"\ndt = {dt}\n")).expect("write");
        let (code, err) = cli(&["check", p.to_str().expect("utf-8")]);
        assert_eq!(code, Some(2), "{err}");
        assert!(err.contains(want), "{err}");
        assert!(!err.contains("0000000000000000000"), "a long decimal: {err}");
    }
}

/// §11: a run that stops early says that its rows are kept, naming the folder.
#[test]
fn a_stopped_run_names_where_its_rows_are_kept() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("o");
    let p = dir.path().join("s.toml");
    std::fs::write(&p, "[bar]\nelements = 10\ndt = 0.01\ninitial_displacement = 0.0\ninitial_velocity = 1e300\nbody_force = 1e300\n").expect("write");
    let (code, err) = cli(&["run", p.to_str().expect("utf-8"), "--out", out.to_str().expect("utf-8")]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains(&format!("the rows written so far are kept in {}", out.display())), "{err}");
}

/// §12: the beam's time axis has its unit.
#[test]
fn the_beam_plots_have_a_time_unit() {
    let dir = tempfile::tempdir().expect("temp dir");
    let p = dir.path().join("s.toml");
    std::fs::write(&p, "[beam]\nscene = \"fig2\"\nt_end = 0.01\n[output]\nplots = true\n").expect("write");
    let out = dir.path().join("o");
    let (code, err) = cli(&["run", p.to_str().expect("utf-8"), "--out", out.to_str().expect("utf-8")]);
    assert_eq!(code, Some(0), "{err}");
    let svg = std::fs::read_to_string(out.join("tip.svg")).expect("tip.svg");
    assert!(svg.contains(">\nt (s)\n<") || svg.contains(">t (s)<"), "no 't (s)' axis label in tip.svg");
}

/// §12: the bifurcation diagram's x axis names the swept parameter.
#[test]
fn the_bifurcation_axis_names_the_parameter() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("o");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/oscillator.toml");
    let (code, err) = cli(&["sweep", scene, "--param", "forcing.omega", "--from", "1.6", "--to", "2.2", "--count", "3", "--transient", "5", "--record", "3", "--out", out.to_str().expect("utf-8")]);
    assert_eq!(code, Some(0), "{err}");
    let svg = std::fs::read_to_string(out.join("bifurcation.svg")).expect("bifurcation.svg");
    assert!(svg.contains("\nforcing.omega\n") || svg.contains(">forcing.omega<"), "the x axis does not name forcing.omega");
}

/// §11 for sweeps: an `--out` that is a file and a merge of a folder that is
/// not a shard are bad input (exit 2), in words.
#[test]
fn sweep_and_merge_bad_folders_exit_2() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("afile");
    std::fs::write(&file, "x").expect("write");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/oscillator.toml");
    let (code, err) = cli(&["sweep", scene, "--param", "forcing.omega", "--from", "1.6", "--to", "2.2", "--count", "2", "--transient", "2", "--record", "2", "--out", file.to_str().expect("utf-8")]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--out") && err.contains("not a folder") && !err.contains("os error"), "{err}");
    let nowhere = dir.path().join("nope");
    let (code, err) = cli(&["merge", nowhere.to_str().expect("utf-8"), "--out", dir.path().join("m").to_str().expect("utf-8")]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("is not a shard folder") && !err.contains("os error"), "{err}");
}

/// A key that does nothing is refused: `[output] energy_warn` in a swept
/// scene (the sweep's runs are not watched against their energy budget),
/// naming the key, before any run (exit 2, nothing written).
#[test]
fn a_sweep_refuses_energy_warn() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/oscillator.toml")).expect("scene");
    let p = dir.path().join("s.toml");
    std::fs::write(&p, format!("{text}\n[output]\nenergy_warn = 3.0\n")).expect("write");
    let out = dir.path().join("o");
    let (code, err) = cli(&[
        "sweep",
        p.to_str().expect("utf-8"),
        "--param",
        "forcing.omega",
        "--from",
        "1.6",
        "--to",
        "2.2",
        "--count",
        "2",
        "--transient",
        "2",
        "--record",
        "2",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("output.energy_warn") && err.contains("not allowed in a sweep"), "{err}");
    assert!(!out.exists(), "nothing is written");
}
