//! `signorini check` on an event-driven scene estimates `events.csv` from a
//! bounded probe of the run's events (their rate, the bytes of their rows)
//! and counts it in the output estimate of the disk check; compared here
//! with the `events.csv` the run writes (sizes, not times).

use signorini_cli::check_report;
use signorini_cli::scene::{Limits, ProbeEnd, SceneFile};
use std::path::Path;
use std::process::Command;

/// The `check_report` of a scene text, and the size of the `events.csv`
/// that `signorini run` writes for it.
fn estimate_and_actual(dir: &Path, name: &str, text: &str) -> (signorini_cli::CheckReport, u64) {
    let file = SceneFile::parse(text).unwrap();
    let scene = file.validate_with(&Limits::machine()).unwrap();
    let out = dir.join(name);
    let report = check_report(&scene, &file, &out).unwrap();
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_signorini")).args(["run", path.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let actual = std::fs::metadata(out.join("events.csv")).unwrap().len();
    (report, actual)
}

/// An impact oscillator driven near resonance (`k = 400`, `Ω = 20`, stop
/// at 0, e = 0.8): an impact or a release about every 0.16 s, 12 700
/// events over `T = 2000`. The probe covers 1 % of `T` and 1000 events
/// (about 8 %): the extrapolated `events.csv` is within a factor 3 of the
/// written one (here within 5 %), and is part of the output estimate.
#[test]
fn the_probe_estimates_events_csv_of_a_dense_run() {
    let dir = tempfile::tempdir().unwrap();
    let text = "[oscillator]\nmass = 1.0\nstiffness = 400.0\ndamping_ratio = 0.05\nstop = 0.0\nscheme = \"event-driven(0.8)\"\ndt = 0.1\nt_end = 2000.0\n[forcing]\namplitude = 10.0\nomega = 20.0\n[output]\nevery = 10\nplots = false\n";
    let (report, actual) = estimate_and_actual(dir.path(), "dense", text);
    let probe = report.events.as_ref().expect("an event-driven scene is probed");
    assert!(probe.covered < 0.5 * probe.horizon, "the probe extrapolates: it covered [0, {}] of {}", probe.covered, probe.horizon);
    assert!(matches!(probe.end, ProbeEnd::Share | ProbeEnd::Budget), "{:?}", probe.end);
    let est = probe.bytes_estimate();
    let ratio = est / actual as f64;
    assert!((1.0 / 3.0..=3.0).contains(&ratio), "events.csv estimated {est} B, written {actual} B");
    // The written events.csv alone is 1.2 MB: the output estimate holds it.
    assert!(actual > 1_000_000 && report.output_bytes >= est, "output estimate {} B", report.output_bytes);
    // The text says it is an estimate from a probe, and what it covered.
    assert!(report.text.contains("estimated from a probe of the run") && report.text.contains("events in [0, ") && report.text.contains("events.csv included"), "{}", report.text);
}

/// A probe that reaches the horizon counts the run's events: its
/// `events.csv` is the written one to the byte.
#[test]
fn a_probe_of_the_whole_horizon_is_exact() {
    let dir = tempfile::tempdir().unwrap();
    let text = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nscheme = \"event-driven(0.8)\"\ndt = 0.01\nt_end = 100.0\n[forcing]\namplitude = 1.0\nomega = 2.0\n[output]\nplots = false\n";
    let (report, actual) = estimate_and_actual(dir.path(), "whole", text);
    let probe = report.events.as_ref().unwrap();
    assert_eq!(probe.end, ProbeEnd::Horizon);
    assert!(probe.events > 10, "{} events", probe.events);
    assert_eq!(probe.bytes_estimate(), actual as f64);
    assert!(report.text.contains("the probe ran the whole horizon"), "{}", report.text);
}

/// `run`'s disk check skips the probe where `events.csv`'s bound at
/// `max_events` fits (`EventProbe::bytes_bound_unprobed`): sound only if no
/// row can be longer than the bound's row and no probe estimates more.
/// The longest row there is — every number negative with a three-digit
/// exponent, the longest kind, the largest contact index — fits the bound
/// at one event, and the dense run's probe estimates less than its bound.
#[test]
fn the_unprobed_bound_holds_the_longest_row_and_every_estimate() {
    use signorini_cli::scene::EventProbe;
    use signorini_schemes::events::{EventKind, EventRecord};
    let x = -f64::MIN_POSITIVE;
    let worst = EventRecord { t: x, kind: EventKind::Accumulation, contact: usize::MAX, velocity_before: x, velocity_after: x, impulse: x };
    let mut csv = Vec::new();
    signorini_run::observers::write_events(&mut csv, &[worst]).unwrap();
    let scene = |text: &str| SceneFile::parse(text).unwrap().validate_with(&Limits::machine()).unwrap();
    let one = scene("[oscillator]\nmass = 1.0\nstiffness = 1.0\nstop = 0.2\nscheme = \"event-driven(0.8,1)\"\ndt = 0.01\nt_end = 1.0\n");
    let bound = EventProbe::bytes_bound_unprobed(&one).expect("an event-driven scene");
    assert!(csv.len() as f64 <= bound, "the longest row: {} bytes, the bound at one event {bound}", csv.len());
    let text =
        "[oscillator]\nmass = 1.0\nstiffness = 400.0\ndamping_ratio = 0.05\nstop = 0.0\nscheme = \"event-driven(0.8,2000)\"\ndt = 0.1\nt_end = 2000.0\n[forcing]\namplitude = 10.0\nomega = 20.0\n";
    let (file, dense) = (SceneFile::parse(text).unwrap(), scene(text));
    let probe = check_report(&dense, &file, Path::new("o")).unwrap().events.expect("probed");
    let bound = EventProbe::bytes_bound_unprobed(&dense).unwrap();
    assert!(probe.bytes_estimate() <= bound && probe.bytes_bound() <= bound, "estimate {}, bound {bound}", probe.bytes_estimate());
    assert!(EventProbe::bytes_bound_unprobed(&scene("[oscillator]\nmass = 1.0\nstiffness = 1.0\nstop = 0.2\ndt = 0.01\nt_end = 1.0\n")).is_none());
}
