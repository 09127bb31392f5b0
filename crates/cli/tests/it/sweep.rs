//! `signorini sweep` and `signorini merge` end to end: shards merged equal
//! the unsharded sweep byte for byte (separate processes), the thread count
//! changes nothing, an interrupted sweep resumes to the same files, and bad
//! options are refused naming the option.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/scenes")
}

/// The shipped oscillator scene at a coarser dt (fast tests).
fn scene(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(scenes().join("oscillator.toml")).unwrap().replace("dt = 1e-3", "dt = 4e-3");
    let p = dir.join("osc.toml");
    std::fs::write(&p, text).unwrap();
    p
}

const FILES: [&str; 6] = ["sweep.csv", "summary.csv", "impacts.csv", "sweep.toml", "bifurcation.svg", "impact_map.svg"];

/// The tests' oscillator sweep (7 runs) into `out`, with `extra` flags.
fn sweep_cmd(scene: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut c = bin();
    c.args(["sweep", scene.to_str().unwrap(), "--param", "forcing.omega", "--from", "1.6", "--to", "2.2", "--count", "7", "--transient", "30", "--record", "6", "--out", out.to_str().unwrap()]);
    c.args(extra);
    c
}

fn sweep(scene: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    sweep_cmd(scene, out, extra).output().unwrap()
}

/// Refused as a bad command (exit 2), the message containing `needle`.
fn refused(o: &std::process::Output, needle: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(needle), "expected {needle:?} in: {err}");
}

fn ok(o: &std::process::Output) {
    assert!(o.status.success(), "{}\n{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
}

fn same_files(a: &Path, b: &Path, files: &[&str]) {
    for f in files {
        let (x, y) = (std::fs::read(a.join(f)).unwrap(), std::fs::read(b.join(f)).unwrap());
        assert!(x == y, "{f} differs between {} and {}", a.display(), b.display());
    }
}

#[test]
fn shards_merged_are_the_unsharded_sweep_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let whole = dir.path().join("whole");
    ok(&sweep(&sc, &whole, &[]));
    // Three shards in three concurrent processes.
    let shards: Vec<PathBuf> = (0..3).map(|i| dir.path().join(format!("shard{i}"))).collect();
    let procs: Vec<std::process::Child> = shards
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let mut c = sweep_cmd(&sc, d, &["--shard", &format!("{i}/3")]);
            c.stdout(std::process::Stdio::null()).stderr(std::process::Stdio::piped()).spawn().unwrap()
        })
        .collect();
    for p in procs {
        let o = p.wait_with_output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let merged = dir.path().join("merged");
    // Given out of order: merge sorts by shard index.
    let o = bin().args(["merge", shards[2].to_str().unwrap(), shards[0].to_str().unwrap(), shards[1].to_str().unwrap(), "--out", merged.to_str().unwrap()]).output().unwrap();
    ok(&o);
    same_files(&whole, &merged, &FILES);
    // The sweep is not trivial: 7 runs, Poincaré rows and impacts in each.
    let summary = std::fs::read_to_string(whole.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 8);
    let rows = std::fs::read_to_string(whole.join("sweep.csv")).unwrap();
    assert!(rows.lines().count() >= 7 * 6, "{rows}");
    assert!(std::fs::read_to_string(whole.join("impacts.csv")).unwrap().lines().count() > 7);
}

#[test]
fn thread_count_changes_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let (a, b) = (dir.path().join("t1"), dir.path().join("t3"));
    ok(&sweep(&sc, &a, &["--threads", "1"]));
    ok(&sweep(&sc, &b, &["--threads", "3"]));
    same_files(&a, &b, &FILES);
}

#[test]
fn an_interrupted_sweep_resumes_to_the_same_files() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let whole = dir.path().join("whole");
    ok(&sweep(&sc, &whole, &[]));
    // What a sweep killed during run 3 leaves: runs 0..3 whole, a cut line.
    let cut = dir.path().join("cut");
    std::fs::create_dir_all(&cut).unwrap();
    std::fs::copy(whole.join("sweep.toml"), cut.join("sweep.toml")).unwrap();
    for f in ["sweep.csv", "impacts.csv", "summary.csv"] {
        let text = std::fs::read_to_string(whole.join(f)).unwrap();
        let mut keep: String = text.lines().filter(|l| l.split(',').nth(1).and_then(|r| r.parse::<usize>().ok()).is_none_or(|r| r < 3)).map(|l| format!("{l}\n")).collect();
        // Rows of run 3 already written to sweep.csv (its summary row is not).
        if f == "sweep.csv" {
            keep.extend(text.lines().filter(|l| l.split(',').nth(1) == Some("3")).take(2).map(|l| format!("{l}\n")));
        }
        keep.push_str("1.9,4,12.5"); // no newline: cut by a kill
        std::fs::write(cut.join(f), keep).unwrap();
    }
    // Only runs 3..7 are computed again: the three whole ones are kept.
    let o = sweep(&sc, &cut, &["--resume"]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("4 runs in"), "{}", String::from_utf8_lossy(&o.stdout));
    same_files(&whole, &cut, &FILES);
    // Resuming a folder of another sweep is refused.
    let o = bin()
        .args([
            "sweep",
            sc.to_str().unwrap(),
            "--param",
            "forcing.omega",
            "--from",
            "1.6",
            "--to",
            "2.3",
            "--count",
            "7",
            "--transient",
            "30",
            "--record",
            "6",
            "--resume",
            "--out",
            cut.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    refused(&o, "another sweep");
}

#[test]
fn merging_shards_of_different_sweeps_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let run = |out: &Path, i: usize, count: &str| {
        let o = bin()
            .args([
                "sweep",
                sc.to_str().unwrap(),
                "--param",
                "forcing.omega",
                "--from",
                "1.6",
                "--to",
                "2.2",
                "--count",
                count,
                "--transient",
                "2",
                "--record",
                "2",
                "--shard",
                &format!("{i}/2"),
                "--out",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        ok(&o);
    };
    run(&a, 0, "4");
    run(&b, 1, "5");
    let o = bin().args(["merge", a.to_str().unwrap(), b.to_str().unwrap(), "--out", dir.path().join("m").to_str().unwrap()]).output().unwrap();
    refused(&o, "different sweeps");
    // A missing shard.
    let o = bin().args(["merge", a.to_str().unwrap(), "--out", dir.path().join("m2").to_str().unwrap()]).output().unwrap();
    refused(&o, "missing");
}

#[test]
fn bad_sweep_options_name_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let out = dir.path().join("o");
    let cases: [(&[&str], &str); 8] = [
        (&["--param", "forcing.omegaa", "--from", "1", "--to", "2", "--count", "3"], "forcing.omegaa"),
        (&["--param", "nothing.omega", "--from", "1", "--to", "2", "--count", "3"], "nothing is not in the scene"),
        (&["--param", "forcing.omega", "--from", "1", "--to", "2", "--count", "0"], "--count"),
        (&["--param", "forcing.omega", "--from", "-1", "--to", "2", "--count", "3", "--log"], "--from"),
        (&["--param", "forcing.omega", "--from", "1", "--to", "0", "--count", "3", "--log"], "--to"),
        (&["--param", "forcing.omega", "--from", "1", "--to", "2", "--count", "3", "--shard", "3/3"], "--shard"),
        (&["--param", "forcing.omega", "--from", "1", "--to", "2", "--count", "3", "--shard", "0/2", "--follow"], "--shard"),
        (&["--param", "oscillator.stop", "--from", "-1", "--to", "0.2", "--count", "3"], "oscillator.initial_displacement"),
    ];
    for (args, needle) in cases {
        let o = bin().args(["sweep", sc.to_str().unwrap(), "--out", out.to_str().unwrap()]).args(args).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!out.join("sweep.csv").exists(), "{args:?}: nothing written");
    }
}

#[test]
fn the_documented_oscillator_sweep_runs() {
    // The command, verbatim but for --out (dt = 1e-3, 210 periods, 7 runs).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("osc");
    let o = bin()
        .args([
            "sweep",
            scenes().join("oscillator.toml").to_str().unwrap(),
            "--param",
            "forcing.omega",
            "--from",
            "1.6",
            "--to",
            "2.2",
            "--count",
            "7",
            "--transient",
            "200",
            "--record",
            "10",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    ok(&o);
    let head = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(head.lines().next(), Some("param,run,t,displacement,velocity,phase"));
    // 10 recorded periods: 10 or 11 section points per run (both window ends).
    let n = head.lines().count() - 1;
    assert!((70..=77).contains(&n), "{n} rows");
    for f in ["summary.csv", "impacts.csv", "bifurcation.svg", "impact_map.svg", "sweep.toml"] {
        assert!(out.join(f).exists(), "{f}");
    }
}

/// SIGINT during a sweep: exit 130 (or 0 if it finished first), whole runs
/// kept; `--resume` then gives exactly the uninterrupted sweep's files. The
/// verdict does not depend on when the signal lands.
#[test]
fn sigint_keeps_whole_runs_and_resume_completes() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let whole = dir.path().join("whole");
    ok(&sweep(&sc, &whole, &["--threads", "1"]));
    let cut = dir.path().join("cut");
    let mut c = sweep_cmd(&sc, &cut, &["--threads", "1"]);
    let child = c.stdout(std::process::Stdio::null()).stderr(std::process::Stdio::piped()).spawn().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(40));
    // SAFETY: kill(2) with a child's pid.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let o = child.wait_with_output().unwrap();
    let code = o.status.code();
    assert!(code == Some(130) || code == Some(0), "{code:?}: {}", String::from_utf8_lossy(&o.stderr));
    if code == Some(130) {
        assert!(String::from_utf8_lossy(&o.stderr).contains("--resume"));
        // Whole runs only: every summary row's run has all its rows.
        let summary = std::fs::read_to_string(cut.join("summary.csv")).unwrap();
        assert!(summary.ends_with('\n'));
        ok(&sweep(&sc, &cut, &["--resume"]));
    }
    same_files(&whole, &cut, &FILES);
}

/// The beam's lockstep groups depend on the batch size, which depends on
/// the thread count: the files do not.
#[test]
fn thread_count_changes_no_output_of_a_lockstep_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let sc = dir.path().join("beam.toml");
    std::fs::write(&sc, "[beam]\nscene = \"fig2\"\n\n[support]\namplitude = 0.2\nomega = 10.0\n").unwrap();
    let run = |out: &Path, threads: &str| {
        ok(&bin()
            .args([
                "sweep",
                sc.to_str().unwrap(),
                "--param",
                "support.omega",
                "--from",
                "8",
                "--to",
                "12",
                "--count",
                "11",
                "--transient",
                "1",
                "--record",
                "2",
                "--threads",
                threads,
                "--out",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap());
    };
    let (a, b) = (dir.path().join("t1"), dir.path().join("t3"));
    run(&a, "1");
    run(&b, "3");
    same_files(&a, &b, &FILES);
}

/// `--no-impacts`: no impacts.csv or impact map, the same statistics, and
/// its shards merge to its unsharded files.
#[test]
fn no_impacts_keeps_the_statistics_and_merges() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let (with, without) = (dir.path().join("with"), dir.path().join("without"));
    ok(&sweep(&sc, &with, &[]));
    ok(&sweep(&sc, &without, &["--no-impacts"]));
    assert!(!without.join("impacts.csv").exists() && !without.join("impact_map.svg").exists());
    same_files(&with, &without, &["sweep.csv", "summary.csv", "bifurcation.svg"]);
    let shards: Vec<PathBuf> = (0..2).map(|i| dir.path().join(format!("s{i}"))).collect();
    for (i, d) in shards.iter().enumerate() {
        ok(&sweep(&sc, d, &["--no-impacts", "--shard", &format!("{i}/2")]));
    }
    let merged = dir.path().join("merged");
    ok(&bin().args(["merge", shards[0].to_str().unwrap(), shards[1].to_str().unwrap(), "--out", merged.to_str().unwrap()]).output().unwrap());
    same_files(&without, &merged, &["sweep.csv", "summary.csv", "bifurcation.svg", "sweep.toml"]);
    assert!(!merged.join("impacts.csv").exists());
}

/// `signorini sweep SCENE --out OUT ARGS…`.
fn sweep_with(scene: &Path, out: &Path, args: &[&str]) -> std::process::Output {
    bin().args(["sweep", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).args(args).output().unwrap()
}

/// The data rows of a CSV file, split at commas.
fn csv_rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path).unwrap().lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect()
}

/// The rows of `sweep.csv` / `impacts.csv` of run `run` without their
/// `param,run` columns.
fn rows_of_run(path: &Path, run: usize) -> Vec<Vec<String>> {
    csv_rows(path).into_iter().filter(|r| r[1] == run.to_string()).map(|r| r[2..].to_vec()).collect()
}

/// A beam scene on the tip's stops moved by `A sin(ω t)`, `extra` lines in `[beam]`.
fn beam_text(extra: &str, omega: f64) -> String {
    format!("[beam]\nscene = \"fig2\"\n{extra}\n[support]\namplitude = 0.2\nomega = {omega:?}\n")
}

/// issue 22, item 1: `reduce` acts in a sweep, and each run of the sweep is
/// `signorini run` of the scene at its value (the sweep's horizon, the same
/// record window): the same statistics, steps and Poincaré samples.
#[test]
fn a_reduced_beam_sweep_is_signorini_run_at_each_value() {
    let dir = tempfile::tempdir().unwrap();
    let reduce = "reduce = { modes = 8 }\n";
    let (red, full) = (dir.path().join("red.toml"), dir.path().join("full.toml"));
    std::fs::write(&red, beam_text(reduce, 10.0)).unwrap();
    std::fs::write(&full, beam_text("", 10.0)).unwrap();
    let args = ["--param", "support.omega", "--from", "9", "--to", "11", "--count", "2", "--transient", "1", "--record", "2"];
    let (sr, sf) = (dir.path().join("sr"), dir.path().join("sf"));
    ok(&sweep_with(&red, &sr, &args));
    ok(&sweep_with(&full, &sf, &args));
    let summary = csv_rows(&sr.join("summary.csv"));
    assert_ne!(summary, csv_rows(&sf.join("summary.csv")), "reduce acts in a sweep");
    let header: Vec<String> = std::fs::read_to_string(sr.join("summary.csv")).unwrap().lines().next().unwrap().split(',').map(String::from).collect();
    let stats = header.len() - 4; // param,run,<stats>,steps,status
    let dt = 5e-5; // fig2's
    for (run, omega) in [(0usize, 9.0f64), (1, 11.0)] {
        // The sweep's horizon, computed here: 3 forcing periods in whole steps.
        let steps = (3.0 * (std::f64::consts::TAU / omega) / dt).round();
        let t_end = steps * dt;
        let text = format!("{}\n[output]\nplots = false\nsummary = true\npoincare = true\nimpacts = true\ntransient = 1.0\n", beam_text(&format!("{reduce}t_end = {t_end:?}\n"), omega));
        let scene = dir.path().join(format!("run{run}.toml"));
        std::fs::write(&scene, text).unwrap();
        let out = dir.path().join(format!("run{run}"));
        ok(&bin().args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap());
        let one = csv_rows(&out.join("summary.csv"));
        let row = &summary[run];
        assert_eq!(row[0], format!("{omega}"));
        assert_eq!(row[2..2 + stats], one[0][..], "run {run}: the sweep's statistics are signorini run's");
        assert_eq!(row[2 + stats], format!("{steps}"), "run {run}: steps");
        assert_eq!(row[3 + stats], "ok");
        // The Poincaré samples, to every printed digit.
        let e12 = |s: &str| format!("{:.12e}", s.parse::<f64>().unwrap());
        let pc = rows_of_run(&sr.join("sweep.csv"), run);
        let one_pc = csv_rows(&out.join("poincare.csv"));
        assert!(!one_pc.is_empty());
        assert_eq!(pc.len(), one_pc.len());
        for (s, r) in pc.iter().zip(&one_pc) {
            for k in 0..3 {
                assert_eq!(e12(&s[k]), r[k], "run {run}: Poincaré column {k}");
            }
        }
    }
}

/// issue 22, item 3: a swept time step takes the sweep's own horizon (the
/// scene's `t_end` is replaced, not checked against the new dt).
#[test]
fn a_swept_time_step_takes_the_sweeps_horizon() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("dt");
    let o = sweep_with(&scenes().join("oscillator.toml"), &out, &["--param", "oscillator.dt", "--from", "1e-3", "--to", "1e-2", "--count", "3", "--transient", "20", "--record", "5"]);
    ok(&o);
    let rows = csv_rows(&out.join("summary.csv"));
    assert_eq!(rows.len(), 3);
    let period = std::f64::consts::TAU / 2.0; // forcing.omega = 2
    for (r, row) in rows.iter().enumerate() {
        let dt = if r == 2 { 1e-2 } else { 1e-3 + (1e-2 - 1e-3) * (r as f64 / 2.0) };
        assert_eq!(row[0].parse::<f64>().unwrap(), dt);
        let n = row.len();
        assert_eq!(row[n - 1], "ok", "run {r}: {row:?}");
        assert_eq!(row[n - 2], format!("{}", (25.0 * period / dt).round()), "run {r}: 25 periods in whole steps");
    }
}

/// issue 22, item 3: an integer field swept over a grid with fractional
/// values is refused before anything runs, naming the field and the value.
#[test]
fn an_integer_field_refuses_a_fractional_grid_before_any_run() {
    let dir = tempfile::tempdir().unwrap();
    let sc = dir.path().join("beam.toml");
    std::fs::write(&sc, beam_text("", 10.0)).unwrap();
    let out = dir.path().join("o");
    let o = sweep_with(&sc, &out, &["--param", "beam.elements", "--from", "10", "--to", "11", "--count", "3", "--transient", "0", "--record", "1"]);
    refused(&o, "beam.elements");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("10.5"), "{err}");
    assert!(!out.join("summary.csv").exists(), "nothing run");
    // The same field given in the scene (an integer key): also refused.
    std::fs::write(&sc, beam_text("elements = 10\n", 10.0)).unwrap();
    let o = sweep_with(&sc, &out, &["--param", "beam.elements", "--from", "10", "--to", "11", "--count", "3", "--transient", "0", "--record", "1"]);
    refused(&o, "beam.elements");
    assert!(!out.join("summary.csv").exists(), "nothing run");
    // Integral values run.
    ok(&sweep_with(&sc, &out, &["--param", "beam.elements", "--from", "10", "--to", "11", "--count", "2", "--transient", "0", "--record", "1"]));
}

/// The oscillator swept over initial velocities whose runs overflow: the
/// first runs, the other two blow up.
fn blow_up_sweep(dir: &Path, out: &Path) -> std::process::Output {
    sweep_with(&scene(dir), out, &["--param", "oscillator.initial_velocity", "--from", "-1e300", "--to", "-1.7e308", "--count", "3", "--transient", "2", "--record", "2"])
}

/// issue 22, item 3: runs that fail at run time keep their rows; the sweep
/// says how many failed and exits 3.
#[test]
fn a_sweep_with_failed_runs_exits_3_and_says_how_many() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = blow_up_sweep(dir.path(), &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("2 of 3 runs failed"), "{err}");
    let rows = csv_rows(&out.join("summary.csv"));
    assert_eq!(rows.len(), 3, "every run's row is kept");
    assert_eq!(rows[0].last().unwrap(), "ok");
    assert!(rows[1].last().unwrap().contains("blew up") && rows[2].last().unwrap().contains("blew up"), "{rows:?}");
    assert!(out.join("bifurcation.svg").exists());
}

/// issue 22, item 11: very large values in the `param` column and in the
/// sweep's messages are written in shortest round-trip form.
#[test]
fn large_values_are_written_in_shortest_form() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    blow_up_sweep(dir.path(), &out);
    let mid = -1e300 + (-1.7e308 - -1e300) * 0.5;
    for f in ["summary.csv", "sweep.csv"] {
        let params: Vec<String> = csv_rows(&out.join(f)).into_iter().map(|r| r[0].clone()).collect();
        for p in &params {
            assert!(["-1e300".to_string(), format!("{mid:e}"), "-1.7e308".to_string()].contains(p), "{f}: {p}");
            assert_eq!(p.parse::<f64>().unwrap().to_bits(), [-1e300f64, mid, -1.7e308].iter().find(|v| format!("{:e}", v) == *p).unwrap().to_bits());
        }
    }
    // Normal values keep their form (data/reference/beam-sweep: 4.012012012012012).
    let sc = scene(dir.path());
    let o = sweep_with(&sc, &dir.path().join("small"), &["--param", "forcing.omega", "--from", "1.6", "--to", "2.2", "--count", "3", "--transient", "1", "--record", "1"]);
    ok(&o);
    let params: Vec<String> = csv_rows(&dir.path().join("small/summary.csv")).into_iter().map(|r| r[0].clone()).collect();
    assert_eq!(params, ["1.6".to_string(), format!("{}", 1.6 + (2.2 - 1.6) * 0.5), "2.2".to_string()]);
    // Messages: --log with a huge negative bound; an integer field at 1e20.
    let o = sweep_with(&sc, &dir.path().join("m1"), &["--param", "forcing.omega", "--from", "-1e300", "--to", "2", "--count", "3", "--log"]);
    refused(&o, "--from: -1e300 is not allowed");
    let bsc = dir.path().join("beam.toml");
    std::fs::write(&bsc, beam_text("elements = 10\n", 10.0)).unwrap();
    let o = sweep_with(&bsc, &dir.path().join("m2"), &["--param", "beam.elements", "--from", "1e20", "--to", "1e20", "--count", "1"]);
    refused(&o, "1e20");
    assert!(!String::from_utf8_lossy(&o.stderr).contains("000000000000000000"), "{}", String::from_utf8_lossy(&o.stderr));
}

/// issue 22, item 4: a shard whose sweep.csv or impacts.csv lost rows (a
/// truncated copy) while its summary.csv is whole is refused by merge,
/// naming the shard, the file and the rows expected and found.
#[test]
fn merge_refuses_a_shard_with_a_truncated_file() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let shards: Vec<PathBuf> = (0..2).map(|i| dir.path().join(format!("s{i}"))).collect();
    for (i, d) in shards.iter().enumerate() {
        ok(&sweep(&sc, d, &["--shard", &format!("{i}/2")]));
    }
    for (k, (file, cut)) in [("sweep.csv", "drop"), ("sweep.csv", "mid-row"), ("impacts.csv", "drop"), ("impacts.csv", "mid-row")].into_iter().enumerate() {
        let bad = dir.path().join(format!("bad{k}"));
        std::fs::create_dir_all(&bad).unwrap();
        for f in ["sweep.toml", "sweep.csv", "summary.csv", "impacts.csv"] {
            std::fs::copy(shards[1].join(f), bad.join(f)).unwrap();
        }
        let text = std::fs::read_to_string(shards[1].join(file)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let rows = lines.len() - 1;
        let (damaged, found) = match cut {
            // The last two rows gone, the file still ending in a newline.
            "drop" => (lines[..lines.len() - 2].iter().map(|l| format!("{l}\n")).collect::<String>(), rows - 2),
            // Cut in the middle of the last row.
            _ => {
                let last = lines[lines.len() - 1];
                (format!("{}{}", lines[..lines.len() - 1].iter().map(|l| format!("{l}\n")).collect::<String>(), &last[..last.len() / 2]), rows - 1)
            }
        };
        std::fs::write(bad.join(file), damaged).unwrap();
        let m = dir.path().join(format!("m{k}"));
        let o = bin().args(["merge", shards[0].to_str().unwrap(), bad.to_str().unwrap(), "--out", m.to_str().unwrap()]).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{file} {cut}: {err}");
        for needle in [bad.display().to_string(), file.to_string(), format!("expected {rows}"), format!("found {found}")] {
            assert!(err.contains(&needle), "{file} {cut}: expected {needle:?} in: {err}");
        }
        assert!(!m.join("sweep.csv").exists(), "{file} {cut}: nothing merged");
    }
    // The intact shards merge.
    ok(&bin().args(["merge", shards[0].to_str().unwrap(), shards[1].to_str().unwrap(), "--out", dir.path().join("good").to_str().unwrap()]).output().unwrap());
}

/// The log grid is `10^(a + k (b − a)/(n − 1))`, `a = log10 from`, `b =
/// log10 to`, computed here; its ends are `--from` and `--to` exactly.
#[test]
fn a_log_grid_is_evenly_spaced_in_the_exponent() {
    use signorini_cli::sweep::SweepOptions;
    let (from, to, n) = (1.0f64, 100.0f64, 5usize);
    let mut o = SweepOptions::new("forcing.omega", from, to, n);
    o.log = true;
    let (a, b) = (from.log10(), to.log10());
    for k in 0..n {
        let want = 10f64.powf(a + k as f64 * (b - a) / (n - 1) as f64);
        let got = o.value(k).0;
        assert!((got / want - 1.0).abs() < 1e-13, "value {k}: {got} against 10^… = {want}");
    }
    assert_eq!((o.value(0).0, o.value(n - 1).0), (from, to), "ends exact");
    // The command's param column holds the same values.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("log");
    ok(&sweep_with(&scene(dir.path()), &out, &["--param", "forcing.omega", "--from", "1", "--to", "100", "--count", "5", "--log", "--transient", "1", "--record", "1"]));
    let params: Vec<f64> = csv_rows(&out.join("summary.csv")).iter().map(|r| r[0].parse().unwrap()).collect();
    assert_eq!(params.len(), n);
    assert_eq!((params[0], params[n - 1]), (from, to));
    for (k, p) in params.iter().enumerate() {
        let want = 10f64.powf(a + k as f64 * (b - a) / (n - 1) as f64);
        assert!((p / want - 1.0).abs() < 1e-13, "run {k}: {p} against {want}");
    }
}

/// `--phase` changes every Poincaré sample: sweeps that differ only in it
/// have different ids, so their shards are not merged together.
#[test]
fn sweeps_differing_only_in_phase_are_different_sweeps() {
    use signorini_cli::scene::Limits;
    use signorini_cli::sweep::{Sweep, SweepOptions};
    let text = std::fs::read_to_string(scenes().join("oscillator.toml")).unwrap();
    let id = |phase: f64| {
        let mut o = SweepOptions::new("forcing.omega", 1.6, 2.2, 4);
        o.phase = phase;
        Sweep::new(&text, "oscillator.toml", None, o, Limits { max_memory: 1e9 }).unwrap().id().to_string()
    };
    assert_ne!(id(0.0), id(1.0));
    assert_eq!(id(1.0), id(1.0));
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let args = |i: usize, phase: &str| -> Vec<String> {
        ["--param", "forcing.omega", "--from", "1.6", "--to", "2.2", "--count", "4", "--transient", "2", "--record", "2", "--phase", phase, "--shard", &format!("{i}/2")]
            .iter()
            .map(|s| s.to_string())
            .collect()
    };
    ok(&sweep_with(&sc, &a, &args(0, "0").iter().map(String::as_str).collect::<Vec<_>>()));
    ok(&sweep_with(&sc, &b, &args(1, "1").iter().map(String::as_str).collect::<Vec<_>>()));
    let o = bin().args(["merge", a.to_str().unwrap(), b.to_str().unwrap(), "--out", dir.path().join("m").to_str().unwrap()]).output().unwrap();
    refused(&o, "different sweeps");
}

/// A 3 × 2 map: run `r` takes value `r mod 3` of `--param` and `r div 3` of
/// `--param2`, both grids computed here, in every file's rows.
#[test]
fn a_map_takes_each_runs_values_from_both_axes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("map");
    ok(&sweep_with(
        &scene(dir.path()),
        &out,
        &[
            "--param",
            "forcing.omega",
            "--from",
            "1.6",
            "--to",
            "2.2",
            "--count",
            "3",
            "--param2",
            "forcing.amplitude",
            "--from2",
            "0.5",
            "--to2",
            "1.0",
            "--count2",
            "2",
            "--transient",
            "1",
            "--record",
            "2",
        ],
    ));
    let p1 = [1.6, 1.6 + (2.2 - 1.6) * 0.5, 2.2];
    let p2 = [0.5, 1.0];
    let want = |r: usize| (p1[r % 3], p2[r / 3]);
    let summary = csv_rows(&out.join("summary.csv"));
    assert_eq!(summary.len(), 6);
    for (r, row) in summary.iter().enumerate() {
        assert_eq!(row[1], r.to_string());
        let got = (row[0].parse::<f64>().unwrap(), row.last().unwrap().parse::<f64>().unwrap());
        assert_eq!(got, want(r), "summary run {r}");
    }
    for f in ["sweep.csv", "impacts.csv"] {
        let rows = csv_rows(&out.join(f));
        assert!(!rows.is_empty());
        for row in rows {
            let r: usize = row[1].parse().unwrap();
            let got = (row[0].parse::<f64>().unwrap(), row.last().unwrap().parse::<f64>().unwrap());
            assert_eq!(got, want(r), "{f} run {r}");
        }
    }
}

/// `--follow` on a map: each row of the second axis starts from the
/// scene's own state, so the first run of each row is the single run at its
/// values (an independent sweep of one run), while the runs that follow do
/// start from their predecessor.
#[test]
fn a_followed_map_restarts_each_row_from_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let out = dir.path().join("follow");
    let axes = |p1: (&str, &str, &str), p2: (&str, &str, &str)| -> Vec<String> {
        [
            "--param",
            "forcing.omega",
            "--from",
            p1.0,
            "--to",
            p1.1,
            "--count",
            p1.2,
            "--param2",
            "forcing.amplitude",
            "--from2",
            p2.0,
            "--to2",
            p2.1,
            "--count2",
            p2.2,
            "--transient",
            "1",
            "--record",
            "3",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let run = |out: &Path, args: Vec<String>, follow: bool| {
        let mut a: Vec<&str> = args.iter().map(String::as_str).collect();
        if follow {
            a.push("--follow");
        }
        ok(&sweep_with(&sc, out, &a));
    };
    run(&out, axes(("1.6", "2.2", "2"), ("0.8", "1.0", "3")), true);
    let summary = csv_rows(&out.join("summary.csv"));
    assert_eq!(summary.len(), 6);
    let p1 = ["1.6", "2.2"];
    let p2 = ["0.8", "0.9", "1"];
    assert_eq!(format!("{}", 0.8 + (1.0 - 0.8) * 0.5), "0.9");
    for r in 0..6 {
        let (v1, v2) = (p1[r % 2], p2[r / 2]);
        let single = dir.path().join(format!("single{r}"));
        run(&single, axes((v1, v1, "1"), (v2, v2, "1")), false);
        let one = csv_rows(&single.join("summary.csv"));
        let same = summary[r][2..] == one[0][2..] && rows_of_run(&out.join("sweep.csv"), r) == rows_of_run(&single.join("sweep.csv"), 0);
        if r % 2 == 0 {
            assert!(same, "run {r} starts a row: it is the single run at ({v1}, {v2})\n{:?}\n{:?}", summary[r], one[0]);
        } else {
            assert!(!same, "run {r} follows run {}: it is not the single run", r - 1);
        }
    }
}

/// A sweep of the beam with `moreau-jean` (its runs stepped in lockstep by
/// `MoreauJeanLockstep`) writes, with 1 and with 3 threads, exactly the
/// files of the same runs one at a time: five shards of one run each (a
/// group of one is run alone, by `run`), in five processes, merged.
#[test]
fn a_moreau_jean_sweep_in_lockstep_is_its_runs_one_at_a_time() {
    lockstep_sweep_is_its_runs_one_at_a_time("moreau-jean(0.5,0.3)");
}

/// The same for `nsga` with a restitution (`NsgaLockstep`).
#[test]
fn an_nsga_sweep_in_lockstep_is_its_runs_one_at_a_time() {
    lockstep_sweep_is_its_runs_one_at_a_time("nsga(0.5,0.3)");
}

/// The same for `moreau-jean-projected` with a restitution and γ
/// (`MoreauJeanLockstep::projected`; θ = 1/2 blows up on fig. 2 within a
/// few periods, one at a time as in lockstep: its projection adds energy).
#[test]
fn a_moreau_jean_projected_sweep_in_lockstep_is_its_runs_one_at_a_time() {
    lockstep_sweep_is_its_runs_one_at_a_time("moreau-jean-projected(0.7,0.5,0.3)");
}

/// The same for `contact-stabilized` (`ContactStabilizedLockstep`).
#[test]
fn a_contact_stabilized_sweep_in_lockstep_is_its_runs_one_at_a_time() {
    lockstep_sweep_is_its_runs_one_at_a_time("contact-stabilized");
}

/// The same for `moreau-jean-combined` with a restitution
/// (`MoreauJeanCombinedLockstep`: lanes that redo their step while the
/// others wait; θ = 0.7, as θ = 1/2 blows up on fig. 2).
#[test]
fn a_moreau_jean_combined_sweep_in_lockstep_is_its_runs_one_at_a_time() {
    lockstep_sweep_is_its_runs_one_at_a_time("moreau-jean-combined(0.7,0.3)");
}

/// The same for `cd-lagrange` with a restitution (`CdLagrangeLockstep`;
/// explicit: dt = 1e-5, below its limit 1.2395e-5 on fig. 2).
#[test]
fn a_cd_lagrange_sweep_in_lockstep_is_its_runs_one_at_a_time() {
    lockstep_sweep_at_dt_is_its_runs_one_at_a_time("cd-lagrange(0.3)", Some(1e-5));
}

/// The same for `d1-minus-linear` with a restitution, on both levels
/// (`D1MinusLinearLockstep`; explicit: dt = 1e-5, below its limit
/// 1.2395e-5 on fig. 2).
#[test]
fn a_d1_minus_linear_sweep_in_lockstep_is_its_runs_one_at_a_time() {
    lockstep_sweep_at_dt_is_its_runs_one_at_a_time("d1-minus-linear(0.3)", Some(1e-5));
    lockstep_sweep_at_dt_is_its_runs_one_at_a_time("d1-minus-linear-velocity(0.3)", Some(1e-5));
}

/// A sweep of the fig. 2 beam with `scheme` over five frequencies, with 1
/// and 3 threads (in lockstep), against its five runs one at a time
/// (five one-run shards, merged): the same files, byte for byte.
fn lockstep_sweep_is_its_runs_one_at_a_time(scheme: &str) {
    lockstep_sweep_at_dt_is_its_runs_one_at_a_time(scheme, None)
}

/// The same, with `[beam] dt` set when given.
fn lockstep_sweep_at_dt_is_its_runs_one_at_a_time(scheme: &str, dt: Option<f64>) {
    let dir = tempfile::tempdir().unwrap();
    let sc = dir.path().join("beam.toml");
    let dt = dt.map_or(String::new(), |dt| format!("dt = {dt:e}\n"));
    std::fs::write(&sc, format!("[beam]\nscene = \"fig2\"\nscheme = \"{scheme}\"\n{dt}\n[support]\namplitude = 0.2\nomega = 10.0\n")).unwrap();
    let run = |out: &Path, extra: &[&str]| {
        let mut c = bin();
        c.args(["sweep", sc.to_str().unwrap(), "--param", "support.omega", "--from", "8", "--to", "12", "--count", "5", "--transient", "1", "--record", "2", "--out", out.to_str().unwrap()]);
        ok(&c.args(extra).output().unwrap());
    };
    let shards: Vec<PathBuf> = (0..5).map(|i| dir.path().join(format!("s{i}"))).collect();
    for (i, s) in shards.iter().enumerate() {
        run(s, &["--shard", &format!("{i}/5"), "--threads", "1"]);
    }
    let merged = dir.path().join("merged");
    let mut m = bin();
    m.arg("merge").args(shards.iter().map(|s| s.to_str().unwrap())).args(["--out", merged.to_str().unwrap()]);
    ok(&m.output().unwrap());
    let impacts = std::fs::read_to_string(merged.join("impacts.csv")).unwrap();
    assert!(impacts.lines().count() > 20, "{scheme}: the runs must reach the stops for the test to mean anything:\n{impacts}");
    for threads in ["1", "3"] {
        let out = dir.path().join(format!("t{threads}"));
        run(&out, &["--threads", threads]);
        same_files(&merged, &out, &FILES);
    }
}
