//! What the command promises when things go wrong: interrupted and killed
//! runs leave complete rows, reused folders are refused, a scene that
//! validates also starts (and one that does not leaves nothing behind),
//! sizes beyond memory and disk are refused before anything is allocated,
//! keys that would not act are refused, expressions are real-valued,
//! blow-ups are reported as such.

use signorini_cli::scene::{Limits, Scene, SceneError, SceneFile};
use std::path::{Path, PathBuf};
use std::process::{Child, Command};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

fn write_scene(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// Runs `signorini <args>`: (exit code, stdout, stderr).
fn cli(args: &[&str]) -> (Option<i32>, String, String) {
    let o = bin().args(args).output().unwrap();
    (o.status.code(), String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

fn field_error(text: &str, limits: &Limits) -> (String, String) {
    match SceneFile::parse(text).unwrap().validate_with(limits) {
        Err(SceneError::Field { field, message }) => (field, message),
        Err(e) => panic!("{text}: expected a field error, got {e}"),
        Ok(_) => panic!("{text}: accepted"),
    }
}

fn field_error_here(text: &str) -> (String, String) {
    field_error(text, &Limits::machine())
}

/// A beam run long enough not to end before the signal (1e7 steps, ~4 s).
const LONG_BEAM: &str = "[beam]\nscene = \"fig7\"\nt_end = 5.0\n[output]\nevery = 1\nplots = true\n";

/// Starts a long run and waits (polling, no fixed delay) until its series
/// holds at least `bytes`: the signal handlers are installed by then.
fn start_long_run(dir: &Path, bytes: u64) -> (Child, PathBuf) {
    let out = dir.join("run");
    let scene = write_scene(dir, LONG_BEAM);
    let child = bin().args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).stderr(std::process::Stdio::piped()).spawn().unwrap();
    let series = out.join("series.csv");
    while std::fs::metadata(&series).map_or(0, |m| m.len()) < bytes {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    (child, out)
}

fn send(child: &Child, sig: libc::c_int) {
    // SAFETY: kill(2) on our own child's pid.
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
}

/// Every newline-terminated line of a beam series is a complete row
/// (6 cells, the numbers parse, `n` counts up by one); returns the rows and
/// whether a partial last line (no newline) was dropped.
fn complete_rows(text: &str) -> (Vec<Vec<String>>, bool) {
    let (whole, partial) = match text.rfind('\n') {
        Some(i) => (&text[..=i], !text[i + 1..].is_empty()),
        None => ("", !text.is_empty()),
    };
    let mut lines = whole.lines();
    assert_eq!(lines.next(), Some("n,t_s,tip_m,v_tip_m_s,lambda_t,lambda"));
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(String::from).collect()).collect();
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), 6, "row {i}: {r:?}");
        assert_eq!(r[0].parse::<usize>().unwrap(), i, "row {i}");
        for c in [1, 2] {
            r[c].parse::<f64>().unwrap_or_else(|e| panic!("row {i} cell {c} {:?}: {e}", r[c]));
        }
    }
    (rows, partial)
}

/// SIGINT: the run stops at the next step, writes every row it holds and
/// its plot, says where it stopped and exits 130.
#[test]
fn sigint_stops_cleanly_with_complete_rows() {
    let dir = tempfile::tempdir().unwrap();
    let (child, out) = start_long_run(dir.path(), 200_000);
    send(&child, libc::SIGINT);
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    let step: usize = err.split("interrupted at step ").nth(1).and_then(|r| r.split_whitespace().next()).and_then(|n| n.parse().ok()).unwrap_or_else(|| panic!("{err}"));
    let text = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert!(text.ends_with('\n'), "an interrupted run ends its file with a complete row");
    let (rows, partial) = complete_rows(&text);
    assert!(!partial);
    assert_eq!(rows.len(), step + 1, "every level up to the interrupt is written");
    assert!(std::fs::read_to_string(out.join("tip.svg")).unwrap().starts_with("<svg"));
}

/// SIGKILL cannot be handled and can cut the write in flight: what is
/// promised is that every newline-terminated line is a complete row, so a
/// reader that drops a last partial line reads valid data.
#[test]
fn sigkill_leaves_only_complete_lines_and_at_most_one_partial_last_line() {
    let dir = tempfile::tempdir().unwrap();
    let (mut child, out) = start_long_run(dir.path(), 300_000);
    child.kill().unwrap();
    child.wait().unwrap();
    let text = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let (rows, _partial) = complete_rows(&text);
    assert!(rows.len() > 1000, "{} rows", rows.len());
}

/// A folder holding another run's files is refused (exit 2, nothing
/// touched); `--clean` removes exactly those files, never the user's.
#[test]
fn reused_output_folder_is_refused_unless_cleaned() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let a = write_scene(dir.path(), "[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\n");
    let (code, _, err) = cli(&["run", a.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.join("norms.csv").exists());
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let b = dir.path().join("b.toml");
    std::fs::write(&b, "[bar]\nelements = 10\ndt = 0.01\ninitial_displacement = 0.1\n").unwrap();
    let before = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let (code, _, err) = cli(&["run", b.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("earlier run") && err.contains("norms.csv") && err.contains("--clean"), "{err}");
    assert_eq!(std::fs::read_to_string(out.join("series.csv")).unwrap(), before, "a refused run touches nothing");
    let (code, _, err) = cli(&["run", b.to_str().unwrap(), "--out", out.to_str().unwrap(), "--clean"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!out.join("norms.csv").exists(), "the earlier run's norms were removed");
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
    assert!(std::fs::read_to_string(out.join("series.csv")).unwrap().starts_with("n,t,u_contact,v_contact,lambda_t,lambda,energy_t,energy\n"));
}

/// A scheme that cannot be built fails `check` and `run` alike, with exit
/// code 2 and no output folder.
#[test]
fn check_and_run_refuse_the_same_scenes_and_leave_no_folder() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, field) in [
        ("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\nscheme = \"nitsche(0.001,1)\"\n", "bar.scheme"),
        ("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 0.5\nmass = \"lumped\"\nscheme = \"penalty-cd\"\n", "bar.dt"),
        ("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\ndt = 0.07\n", "bar.t_end"),
        ("[beam]\nscene = \"fig8\"\nbeta = 0.1\ndt = 2e-5\n", "beam.dt"),
    ] {
        let p = write_scene(dir.path(), scene);
        let out = dir.path().join("never");
        let (code, _, err) = cli(&["check", p.to_str().unwrap()]);
        assert_eq!(code, Some(2), "check {scene}: {err}");
        assert!(err.contains(field), "{err}");
        let (code, _, err2) = cli(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert_eq!((code, &err2), (Some(2), &err), "run and check agree");
        assert!(!out.exists(), "a refused run leaves no folder");
    }
}

/// Expressions evaluate in floating point: 1/2 is 0.5, not 0.
#[test]
fn expressions_are_real_valued() {
    for (expr, want) in [("1/2", 0.5), ("-1/2", -0.5), ("2^-1", 0.5), ("3/4 + x2", f64::NAN), ("1/2 * (1 - x)", 0.5), ("1e-1 + 1/4", 0.35), ("math::sin(pi/2)", 1.0)] {
        let text = format!("[bar]\nelements = 4\ndt = 0.05\ngap = -1.0\ninitial_displacement = \"{expr}\"\n");
        let got = SceneFile::parse(&text).unwrap().validate().map(|s| match s {
            Scene::Bar(b) => b.problem.initial.u[0],
            Scene::Beam { .. } | Scene::Oscillator { .. } => unreachable!(),
        });
        match got {
            Ok(u) => assert!((u - want).abs() < 1e-15, "{expr}: u(0) = {u}, want {want}"),
            Err(e) => assert!(want.is_nan(), "{expr}: {e}"),
        }
    }
}

/// Every key acts or is refused: β belongs to the projection, the
/// stiffness to the penalty.
#[test]
fn beam_keys_that_would_not_act_are_refused() {
    let (f, m) = field_error_here("[beam]\nscene = \"fig5\"\nbeta = 0.3\n");
    assert_eq!(f, "beam.beta");
    assert!(m.contains("projection"), "{m}");
    let (f, m) = field_error_here("[beam]\ncontact = \"projection\"\npenalty_stiffness = 1e8\n");
    assert_eq!(f, "beam.penalty_stiffness");
    assert!(m.contains("penalty"), "{m}");
    assert!(SceneFile::parse("[beam]\nscene = \"fig5\"\npenalty_stiffness = 2e8\n").unwrap().validate().is_ok());
    assert!(SceneFile::parse("[beam]\nscene = \"fig2\"\nbeta = 0.3\n").unwrap().validate().is_ok());
}

/// Sizes beyond the memory cap are refused before anything is allocated,
/// with the estimate; the largest usize is no exception.
#[test]
fn sizes_beyond_memory_are_refused_with_an_estimate() {
    let cap = Limits { max_memory: 1e9 };
    for (text, field) in [
        ("[bar]\nelements = 1000000000\ndt = 0.01\ninitial_displacement = 0.0\n", "bar.elements"),
        ("[bar]\nelements = 9223372036854775807\ndt = 0.01\ninitial_displacement = 0.0\n", "bar.elements"),
        ("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 1000000000\nratio = 10.0\n", "bar.elements"),
        ("[beam]\nelements = 1000000000\n", "beam.elements"),
        ("[beam]\nelements = 9223372036854775807\n", "beam.elements"),
    ] {
        let (f, m) = field_error(text, &cap);
        assert_eq!(f, field, "{text}");
        assert!(m.contains("memory") && m.contains("GB") && m.contains("fit"), "{m}");
    }
    // 3e6 elements fit in 1 GB (about 1 GB at 320 bytes each); 4e6 do not.
    let bar = |m: usize| format!("[bar]\nelements = {m}\ndt = 0.01\nt_end = 0.01\ninitial_displacement = 0.0\n");
    assert!(SceneFile::parse(&bar(2_000_000)).unwrap().validate_with(&cap).is_ok());
    assert_eq!(field_error(&bar(4_000_000), &cap).0, "bar.elements");
    // The cap is a flag of the command.
    let dir = tempfile::tempdir().unwrap();
    let p = write_scene(dir.path(), &bar(1000));
    let (code, _, err) = cli(&["check", p.to_str().unwrap(), "--max-memory", "1M"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("bar.elements") && err.contains("memory"), "{err}");
}

/// A penalty too stiff for floating point names its parameter and the
/// usable range, for the bar (γ_P) and the beam (N/m).
#[test]
fn penalty_beyond_floating_point_names_its_usable_range() {
    let (f, m) = field_error_here("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\nscheme = \"penalty(1e30)\"\n");
    assert_eq!(f, "bar.scheme");
    assert!(m.contains("gamma_p") && m.contains("usable range"), "{m}");
    let max: f64 = m.rsplit("<= ").next().unwrap().trim().parse().unwrap();
    assert!(SceneFile::parse(&format!("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\nscheme = \"penalty({})\"\n", max * 0.5)).unwrap().validate().is_ok());
    let (f, m) = field_error_here("[beam]\nscene = \"fig5\"\npenalty_stiffness = 1e30\n");
    assert_eq!(f, "beam.penalty_stiffness");
    assert!(m.contains("N/m") && m.contains("usable range"), "{m}");
}

/// A state that overflows is reported as a blow-up with its step and time
/// (exit 1), not as a plotting failure; the rows written are kept.
#[test]
fn overflow_is_reported_as_a_blow_up() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let p = write_scene(dir.path(), "[bar]\nelements = 10\ndt = 0.01\ninitial_displacement = 0.0\ninitial_velocity = 1e300\nbody_force = 1e300\n");
    let (code, _, err) = cli(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.starts_with("error: run blew up") && err.contains("at step"), "{err}");
    assert!(!err.contains("nothing to plot"), "{err}");
    let text = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert!(text.lines().count() >= 2 && text.ends_with('\n'));
}

/// Zero initial energy is not a blow-up: a bar at rest, and a bar resting
/// on the obstacle under gravity, run to the end.
#[test]
fn zero_initial_energy_is_not_a_blow_up() {
    let dir = tempfile::tempdir().unwrap();
    for (i, scene) in [
        "[bar]\nelements = 20\ndt = 0.01\nt_end = 5.0\ninitial_displacement = 0.0\n",
        "[bar]\nelements = 20\ndt = 0.01\nt_end = 5.0\nfar_end = \"free\"\nbody_force = -9.81\ninitial_displacement = 0.0\n",
    ]
    .iter()
    .enumerate()
    {
        let p = write_scene(dir.path(), scene);
        let (code, out, err) = cli(&["run", p.to_str().unwrap(), "--out", dir.path().join(format!("o{i}")).to_str().unwrap()]);
        assert_eq!(code, Some(0), "{scene}: {err}");
        assert!(out.contains("500 steps"), "{out}");
    }
}

/// Output beyond the free space is refused before anything is created;
/// `check` says how much a run writes.
#[test]
fn output_beyond_free_space_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // 1e5 snapshots of 1e6 nodes: about 7 TB.
    let p = write_scene(dir.path(), "[bar]\nelements = 1000000\ndt = 1e-6\nt_end = 0.1\ninitial_displacement = 0.0\n[output]\nsnapshots_every = 1\n");
    let out = dir.path().join("o");
    let (code, stdout, err) = cli(&["check", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    assert!(stdout.contains("output estimate: 7.") && stdout.contains("TB") && stdout.contains("will be refused"), "{stdout}");
    let (code, _, err) = cli(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("free") && err.contains("--no-disk-check"), "{err}");
    assert!(!out.exists());
}

/// Beam snapshots: the absolute displacement ũ = u + h(x) φ(t) at the
/// nodes: the support node moves with φ(t) = 0.2 sin(10 t), the tip is the
/// series' tip.
#[test]
fn beam_snapshots_are_absolute_displacements() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let p = write_scene(dir.path(), "[beam]\nscene = \"fig2\"\nt_end = 0.2\n[output]\nsnapshots_every = 1000\nplots = false\n");
    let (code, _, err) = cli(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    let snaps = std::fs::read_to_string(out.join("snapshots.csv")).unwrap();
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let mut lines = snaps.lines();
    assert_eq!(lines.next(), Some("n,t_s,x_m,u_m"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|c| c.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 5 * 20, "levels 0, 1000, …, 4000; J + 1 = 20 nodes");
    let tip_of = |n: usize| -> f64 { series.lines().nth(n + 1).unwrap().split(',').nth(2).unwrap().parse().unwrap() };
    for snap in rows.chunks(20) {
        let (n, t) = (snap[0][0] as usize, snap[0][1]);
        assert!((snap[0][2]).abs() < 1e-15 && (snap[0][3] - 0.2 * (10.0 * t).sin()).abs() < 1e-12, "support at t = {t}: {:?}", snap[0]);
        assert!((snap[19][2] - 1.501).abs() < 1e-12);
        assert!((snap[19][3] - tip_of(n)).abs() < 1e-12, "tip at n = {n}");
    }
}
