//! Output never changes the event-driven reference (`scheme =
//! "event-driven"`, docs/theory.md §9.4): a sample at an impact's time, a
//! `dt` of 1e-12 or beyond the events' spacing, a horizon that is not
//! `N dt` in floating point, `t_end = 0` and an interrupted run. In each the
//! events and the final state are the same bits whatever `dt`, and
//! `signorini run` writes the text of the library's own run (the scene's
//! `Scene::instantiate`, the runner, the series writer and the event log).

use signorini_cli::scene::{Reads, SceneError, SceneFile};
use signorini_run::observers::{write_events, SeriesWriter};
use signorini_run::{Observer, RunConfig, RunError, Sample};
use std::path::Path;
use std::process::Command;

/// A level as the observers see it, in bits.
struct Level {
    t: u64,
    u: Vec<u64>,
    energy: Option<u64>,
    forces: Vec<u64>,
    status: Vec<i8>,
}

/// Every level.
#[derive(Default)]
struct Levels(Vec<Level>);

impl Observer for Levels {
    fn wants_energy(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let bits = |x: &[f64]| x.iter().map(|x| x.to_bits()).collect();
        self.0.push(Level {
            t: s.t.to_bits(),
            u: bits(s.u),
            energy: s.energy.map(|e| e.1.to_bits()),
            forces: bits(s.forces),
            status: s.status.iter().map(|a| signorini_run::observers::active_code(*a)).collect(),
        });
        Ok(())
    }
}

/// The library's run of a scene text: `series.csv`'s and `events.csv`'s
/// text, every level, the final state `(t, U ++ V)` in bits and the
/// run's result.
struct Library {
    series: String,
    events: String,
    levels: Levels,
    end: (u64, Vec<u64>),
    result: Result<usize, String>,
}

fn library(text: &str) -> Library {
    library_with(text, None)
}

/// [`library`], its cancel token cancelled at level `stop` (the runner
/// then stops before the next step).
fn library_with(text: &str, stop: Option<usize>) -> Library {
    let file = SceneFile::parse(text).unwrap();
    let scene = file.validate().unwrap();
    let facts = scene.facts();
    let exact = scene.exact().unwrap();
    let mut sim = scene.instantiate(None).unwrap();
    let mut cfg = RunConfig::new(facts.dt, facts.t_end).unwrap().with_energy_warn(file.energy_warn()).unwrap();
    let cancel = signorini_run::Cancel::new();
    cfg.interrupt = stop.map(|_| cancel.clone());
    let mut stopper = StopAt(stop.unwrap_or(usize::MAX), cancel);
    let dofs: Option<Vec<usize>> = facts.contacts.map(|_| sim.contacts().iter().map(|c| c.0).collect());
    let mut buf = Vec::new();
    let mut levels = Levels::default();
    let result = {
        let mut series = SeriesWriter::new(&mut buf, file.output.every, sim.tip, facts.series_columns(exact.as_deref(), dofs.as_deref())).unwrap();
        sim.run(&cfg, vec![(Reads::Contacts, &mut series), (Reads::Full, &mut levels), (Reads::Nothing, &mut stopper)]).map(|s| s.steps).map_err(|e| e.to_string())
    };
    let mut events = Vec::new();
    write_events(&mut events, sim.stepper.events().expect("an event-driven run")).unwrap();
    let state = sim.stepper.state().unwrap().iter().map(|x| x.to_bits()).collect();
    Library { series: String::from_utf8(buf).unwrap(), events: String::from_utf8(events).unwrap(), levels, end: (sim.stepper.time().to_bits(), state), result }
}

/// `signorini run` of a scene text into `dir/name`: (exit code, stderr,
/// `series.csv`, `events.csv`; empty when absent).
fn cli(dir: &Path, name: &str, text: &str) -> (Option<i32>, String, String, String) {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join(name);
    let o = Command::new(env!("CARGO_BIN_EXE_signorini")).args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    let read = |f: &str| std::fs::read_to_string(out.join(f)).unwrap_or_default();
    (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned(), read("series.csv"), read("events.csv"))
}

/// The CLI's files are the library's text, and the run succeeded.
fn cli_is_library(dir: &Path, name: &str, text: &str, lib: &Library) {
    let (code, err, series, events) = cli(dir, name, text);
    assert_eq!(code, Some(0), "{name}: {err}");
    assert!(lib.result.is_ok(), "{name}: {:?}", lib.result);
    assert!(series == lib.series, "{name}: series.csv differs from the library's run");
    assert!(events == lib.events, "{name}: events.csv differs from the library's run");
}

/// The undamped oscillator `x'' + x = 0` from `x = 0`, `x' = 1`, its stop
/// at 0.5 (restitution 0.8): `x = sin t` until the first impact at π/6.
fn free_oscillator(dt: f64, t_end: f64) -> String {
    format!("[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.0\nstop = 0.5\nrestitution = 0.8\ninitial_displacement = 0.0\ninitial_velocity = 1.0\ndt = {dt:e}\nt_end = {t_end:e}\nscheme = \"event-driven\"\n")
}

/// The same oscillator forced by `cos 2t` from rest, stop at 0.2.
fn forced_oscillator(dt: f64, t_end: f64) -> String {
    format!("[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.0\nstop = 0.2\nrestitution = 0.8\ninitial_displacement = 0.0\ninitial_velocity = 0.0\ndt = {dt:e}\nt_end = {t_end:e}\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = 2.0\n")
}

/// The first event's time in an `events.csv` text.
fn event_times(events: &str) -> Vec<f64> {
    events.lines().skip(1).map(|l| l.split(',').next().unwrap().parse().unwrap()).collect()
}

/// A sample exactly at an impact's time shows the state after it. First
/// the free oscillator: its first impact is located at π/6 (the closed
/// form, to 1e-15 relative); sampled at `dt = t₁/1024` (so `1024 dt` is
/// the located `t₁` exactly), the row at `t₁` holds the impact's impulse
/// as the step's mean force `(1 + e) cos t₁ / dt`, contact 0 active, and
/// the energy after it, `½ e² cos² t₁ + ½ sin² t₁` (closed forms); the
/// level before it the energy ½. Then every event of the forced oscillator
/// over [0, 20] s (7 impacts): a run ending exactly at the event (`dt =
/// t_k / 64`) ends on the velocity after the impact (the sign of
/// `velocity_after`), and a run with `dt = t_k` (one step) ends on the same
/// bits. Each run's files from the CLI are the library's text.
#[test]
fn a_sample_at_an_impact_shows_the_state_after_it() {
    let dir = tempfile::tempdir().unwrap();
    let coarse = library(&free_oscillator(1e-3, 1.0));
    let t1 = event_times(&coarse.events)[0];
    let pi6 = std::f64::consts::FRAC_PI_6;
    assert!((t1 - pi6).abs() <= 1e-15 * pi6, "first impact at {t1:e}, closed form {pi6:e}");
    let dt = t1 / 1024.0;
    let text = free_oscillator(dt, 2048.0 * dt);
    let lib = library(&text);
    cli_is_library(dir.path(), "aligned", &text, &lib);
    assert_eq!(lib.events.lines().nth(1), coarse.events.lines().nth(1), "the first impact's row");
    let at = &lib.levels.0[1024];
    assert_eq!(f64::from_bits(at.t), t1);
    let (e, c) = (0.8, t1.cos());
    let lambda = f64::from_bits(at.forces[0]);
    assert!((lambda - (1.0 + e) * c / dt).abs() <= 1e-9 * lambda.abs(), "the row at t₁: mean force {lambda:e}, closed form {:e}", (1.0 + e) * c / dt);
    assert_eq!(at.status, [1], "contact 0 at its upper bound in the step ending at t₁");
    let energy = f64::from_bits(at.energy.unwrap());
    let after = 0.5 * e * e * c * c + 0.5 * t1.sin().powi(2);
    assert!((energy - after).abs() <= 1e-14, "the energy at t₁: {energy}, after the impact {after}, before 0.5");
    let before = f64::from_bits(lib.levels.0[1023].energy.unwrap());
    assert!((before - 0.5).abs() <= 1e-14, "{before}");

    let forced = library(&forced_oscillator(1e-3, 20.0));
    let times = event_times(&forced.events);
    assert!(times.len() >= 6, "{} events", times.len());
    let rows: Vec<Vec<&str>> = forced.events.lines().skip(1).map(|l| l.split(',').collect()).collect();
    for (k, (&tk, row)) in times.iter().zip(&rows).enumerate() {
        let fine = library(&forced_oscillator(tk / 64.0, tk));
        let one = library(&forced_oscillator(tk, tk));
        assert_eq!(fine.end, one.end, "event {k}: the state at t = {tk:e} depends on dt");
        assert_eq!(f64::from_bits(fine.end.0), tk);
        let v = f64::from_bits(fine.end.1[1]);
        let after: f64 = row[4].parse().unwrap();
        assert_eq!(v.signum(), after.signum(), "event {k} ({row:?}): the run ending at it ends on v = {v:e}, not the velocity after it");
        assert!((v - after).abs() <= 1e-12 * after.abs(), "event {k}: {v:e} against {after:e}");
        // Each run's log is the full run's first k + 1 rows.
        assert_eq!(fine.events, one.events);
        assert_eq!(fine.events.lines().count(), k + 2, "event {k}: {}", fine.events);
        if k % 5 == 0 {
            cli_is_library(dir.path(), &format!("forced{k}"), &forced_oscillator(tk / 64.0, tk), &fine);
        }
    }
}

/// The oscillator pushed onto its stop by `10⁵ cos t` from 1e-9 below it
/// (restitution 0.5): impacts every 1.4e-7 s halving down to 4.4e-9 s,
/// then an accumulation at 4.24e-7 s, all within `t_end = 5e-7`.
fn chatter(dt: f64, every: usize) -> String {
    format!("[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.0\nstop = 0.2\nrestitution = 0.5\ninitial_displacement = 0.199999999\ninitial_velocity = 0.0\ndt = {dt:e}\nt_end = 5e-7\nscheme = \"event-driven\"\n[forcing]\namplitude = 1e5\nomega = 1.0\n[output]\nevery = {every}\n")
}

/// `dt = 1e-12` (500 000 levels, every 5th written) and `dt = 5e-7` (one
/// step holding every event, 100 times the shortest spacing) write the
/// same `events.csv` as `dt = 1e-8`, end on the same state bits, and read
/// the same state bits at every time two samplings share (42 of them);
/// the CLI's files
/// are the library's text in each.
#[test]
fn a_tiny_dt_and_a_dt_beyond_the_events_spacing_give_the_same_run() {
    let dir = tempfile::tempdir().unwrap();
    let runs: Vec<Library> = [(1e-12, 5), (1e-8, 1), (5e-7, 1)]
        .into_iter()
        .enumerate()
        .map(|(i, (dt, every))| {
            let text = chatter(dt, every);
            let lib = library(&text);
            cli_is_library(dir.path(), &format!("chatter{i}"), &text, &lib);
            lib
        })
        .collect();
    let times = event_times(&runs[1].events);
    assert!(runs[1].events.contains("accumulation") && times.len() >= 6, "{}", runs[1].events);
    let spacing = times.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
    assert!(spacing < 5e-7 / 100.0, "the shortest spacing {spacing:e}");
    assert_eq!(runs[0].levels.0.len(), 500_001);
    assert_eq!(runs[0].series.lines().count(), 100_002);
    for r in &runs[1..] {
        assert!(r.events == runs[0].events, "events.csv depends on dt");
        assert_eq!(r.end, runs[0].end, "the final state depends on dt");
        assert_eq!(f64::from_bits(r.end.0), 5e-7);
    }
    // The state (u and the energy: v) at the times the samplings share.
    let mut shared = 0;
    for (i, a) in runs.iter().enumerate() {
        let at: std::collections::HashMap<u64, _> = a.levels.0.iter().map(|l| (l.t, (&l.u, l.energy))).collect();
        for b in &runs[i + 1..] {
            for l in &b.levels.0 {
                if let Some(&(u, e)) = at.get(&l.t) {
                    assert_eq!((u, e), (&l.u, l.energy), "the state at t = {:e}", f64::from_bits(l.t));
                    shared += 1;
                }
            }
        }
    }
    assert!(shared > 30, "{shared} shared levels");
}

/// `t_end = 0.7` with `dt = 0.1` (7 × 0.1 = 0.7000000000000001), 0.07,
/// 1e-3 and 0.7: the last level is read at 0.7 itself, once (levels
/// `0..=N`), on the same state bits and after the same events whatever
/// `dt`; the CLI's last row is level N at 7.000000000000e-1. A horizon
/// that is not a whole number of steps (0.75 with dt = 0.1) is refused
/// naming `oscillator.t_end`.
#[test]
fn the_last_level_is_at_t_end_once_whatever_dt() {
    let dir = tempfile::tempdir().unwrap();
    let mut off_grid = 0;
    let mut ends = Vec::new();
    for (i, (dt, n)) in [(0.1, 7usize), (0.07, 10), (1e-3, 700), (0.7, 1)].into_iter().enumerate() {
        off_grid += usize::from(n as f64 * dt != 0.7);
        let text = free_oscillator(dt, 0.7);
        let lib = library(&text);
        cli_is_library(dir.path(), &format!("h{i}"), &text, &lib);
        assert_eq!(lib.result, Ok(n));
        assert_eq!(lib.levels.0.len(), n + 1, "dt = {dt}: levels 0..={n}");
        assert_eq!(f64::from_bits(lib.levels.0[n].t), 0.7, "dt = {dt}: the last level's time");
        let last = lib.series.lines().last().unwrap();
        assert!(last.starts_with(&format!("{n},7.000000000000e-1,")), "dt = {dt}: {last}");
        assert_eq!(lib.series.lines().filter(|l| l.split(',').nth(1) == Some("7.000000000000e-1")).count(), 1);
        assert_eq!(lib.events.lines().count(), 2, "dt = {dt}: the impact at π/6: {}", lib.events);
        ends.push((lib.end, lib.events));
    }
    assert!(off_grid >= 2, "{off_grid} of the dt's miss 0.7 by N dt");
    assert!(ends.iter().all(|e| *e == ends[0]), "the final state or the events depend on dt");
    let (code, err, ..) = cli(dir.path(), "off", &free_oscillator(0.1, 0.75));
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("oscillator.t_end") && err.contains("not a whole number of steps"), "{err}");
}

/// `t_end = 0` is refused naming the field and its range by the scene
/// (`oscillator.t_end`, `bar.t_end`, `beam.t_end`: "finite and > 0"), so by
/// `signorini run` (exit 2, no series written), `check` and by the runner's own
/// configuration (`T`).
#[test]
fn t_end_zero_is_refused_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let bar = "[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nscheme = \"event-driven\"\nratio = 10.0\nt_end = 0.0\n";
    let beam = "[beam]\nscene = \"fig2\"\nscheme = \"event-driven\"\nt_end = 0.0\n";
    for (kind, text) in [("oscillator", free_oscillator(1e-3, 0.0)), ("bar", bar.to_string()), ("beam", beam.to_string())] {
        match SceneFile::parse(&text).unwrap().validate() {
            Err(SceneError::Field { field, message }) => assert!(field == format!("{kind}.t_end") && message.contains("finite and > 0"), "{field}: {message}"),
            Err(e) => panic!("{kind}: {e}"),
            Ok(_) => panic!("{kind}: t_end = 0 accepted"),
        }
        let (code, err, series, _) = cli(dir.path(), kind, &text);
        assert_eq!(code, Some(2), "{kind}: {err}");
        assert!(err.contains(&format!("{kind}.t_end")) && err.contains("finite and > 0"), "{kind}: {err}");
        assert!(series.is_empty(), "{kind}: a refused run wrote {series}");
        let o = Command::new(env!("CARGO_BIN_EXE_signorini")).args(["check", dir.path().join(format!("{kind}.toml")).to_str().unwrap()]).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.code() == Some(2) && err.contains(&format!("{kind}.t_end")), "check {kind}: {err}");
    }
    assert!(matches!(RunConfig::new(1e-3, 0.0), Err(RunError::Invalid { field: "T", .. })));
}

/// An interrupted run keeps whole rows, and they are the uninterrupted
/// run's: the library's run stopped by its cancel token after level 300
/// writes the first 301 rows of the run to 1000 levels byte for byte;
/// `signorini run` stopped by SIGINT (exit 130, "interrupted at step N")
/// writes the text of the library's run to `N dt`, and an `events.csv`
/// that holds that run's events and is a prefix of the run's to `(N + 1)
/// dt` (events inside the interrupted step are kept).
#[test]
fn an_interrupted_run_writes_the_uninterrupted_runs_prefix() {
    let dt = 1e-3;
    let full = library(&forced_oscillator(dt, 1.0));
    let cut = library_with(&forced_oscillator(dt, 1.0), Some(300));
    assert!(cut.result.as_ref().is_err_and(|e| e.contains("interrupted at step 300")), "{:?}", cut.result);
    let prefix: String = full.series.lines().take(302).map(|l| format!("{l}\n")).collect();
    assert!(cut.series == prefix, "the cancelled run's rows are not the full run's first 301");

    let dir = tempfile::tempdir().unwrap();
    let long = forced_oscillator(1e-5, 20.0);
    let scene = dir.path().join("long.toml");
    std::fs::write(&scene, &long).unwrap();
    let out = dir.path().join("long");
    let mut child = Command::new(env!("CARGO_BIN_EXE_signorini")).args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).stderr(std::process::Stdio::piped()).spawn().unwrap();
    while std::fs::metadata(out.join("series.csv")).map_or(0, |m| m.len()) < 300_000 {
        assert!(child.try_wait().unwrap().is_none(), "the run ended before the signal: {:?}", child.wait_with_output());
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    // SAFETY: kill(2) on our own child's pid.
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) }, 0);
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    let step: usize = err.split("interrupted at step ").nth(1).and_then(|r| r.split_whitespace().next()).and_then(|n| n.parse().ok()).unwrap_or_else(|| panic!("{err}"));
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let events = std::fs::read_to_string(out.join("events.csv")).unwrap();
    let upto = |n: usize| library(&forced_oscillator(1e-5, n as f64 * 1e-5));
    let (at, next) = (upto(step), upto(step + 1));
    assert!(series == at.series, "the interrupted run's {} rows are not the run to step {step}", series.lines().count() - 1);
    assert!(events.starts_with(&at.events) && next.events.starts_with(&events), "events.csv is not the uninterrupted run's prefix");
}

/// Cancels its token at level `.0` (the runner stops before the next step).
struct StopAt(usize, signorini_run::Cancel);

impl Observer for StopAt {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if s.n == self.0 {
            self.1.cancel();
        }
        Ok(())
    }
}
