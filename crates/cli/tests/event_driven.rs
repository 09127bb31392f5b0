//! `scheme = "event-driven"` through `signorini run` (issue 25): its event
//! log, its refusals, and the event limit.

use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

/// Runs a scene text into `dir/name`: (exit code, stderr).
fn run(dir: &Path, name: &str, text: &str) -> (Option<i32>, String) {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join(name);
    let o = bin().args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
}

const OSC: &str = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.0\nstop = 0.2\nrestitution = 0.8\ninitial_displacement = 0.0\ninitial_velocity = 0.0\ndt = 1e-3\nt_end = 20.0\n";

/// `max_events` (the second parameter) stops the run with a typed error
/// naming it, and the events so far are in `events.csv`, whole rows.
#[test]
fn the_event_limit_stops_the_run_and_keeps_the_events() {
    let dir = tempfile::tempdir().unwrap();
    let full = format!("{OSC}scheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = 2.0\n");
    assert_eq!(run(dir.path(), "full", &full).0, Some(0));
    let all = std::fs::read_to_string(dir.path().join("full/events.csv")).unwrap();
    let n = all.lines().count() - 1;
    assert!(n > 6, "{n} events over 20 s");
    let capped = format!("{OSC}scheme = \"event-driven(0.8,5)\"\n[forcing]\namplitude = 1.0\nomega = 2.0\n");
    let (code, err) = run(dir.path(), "capped", &capped);
    assert_ne!(code, Some(0), "{err}");
    assert!(err.contains("max_events") && err.contains("events by t ="), "{err}");
    let kept = std::fs::read_to_string(dir.path().join("capped/events.csv")).unwrap();
    // The first six events (the sixth made the count exceed 5), as in the full run.
    let want: Vec<&str> = all.lines().take(7).collect();
    assert_eq!(kept.lines().collect::<Vec<_>>(), want);
    assert!(kept.ends_with('\n'));
}

/// Refusals name the field and the allowed range, before anything runs.
#[test]
fn refusals_name_the_field() {
    let dir = tempfile::tempdir().unwrap();
    for (scheme, want) in [("event-driven(1.5)", "e = 1.5"), ("event-driven(0,0.5)", "max_events"), ("event-driven(0,-1)", "max_events")] {
        let (code, err) = run(dir.path(), "bad", &format!("{OSC}scheme = \"{scheme}\"\n"));
        assert_eq!(code, Some(2), "{scheme}: {err}");
        assert!(err.contains("oscillator.scheme") && err.contains(want), "{scheme}: {err}");
    }
    // A massless contact node (mass redistribution) is refused naming the scheme.
    let bar = "[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nmass = \"mod\"\nscheme = \"event-driven\"\nratio = 10.0\nt_end = 0.5\n";
    let (code, err) = run(dir.path(), "massless", bar);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("bar.scheme") || err.contains("bar.mass"), "{err}");
}
