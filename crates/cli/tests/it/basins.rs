//! `signorini basins` end to end: sampled cells against independent
//! `signorini run`s of the same initial states (their Poincaré samples and
//! impacts classified here, by this file's own period test), two coexisting
//! period-1 attractors of the oscillator, shards merged equal to the
//! unsharded grid byte for byte, the thread count changes nothing, an
//! interrupt keeps whole rows, and bad input is refused naming the option.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

/// The oscillator with a stop at 0.5, forced at Ω = 1.85: the free
/// (non-impacting) period-1 response, of amplitude 1/|1 − Ω²| ≈ 0.41 < 0.5,
/// coexists with a stable impacting period-1 orbit.
const OMEGA: f64 = 1.85;
fn scene_text(x0: f64, v0: f64, t_end: f64, output: &str) -> String {
    format!(
        "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.5\nrestitution = 0.8\ninitial_displacement = {x0:?}\ninitial_velocity = {v0:?}\ndt = 1e-2\nt_end = {t_end:?}\nscheme = \"event-driven(0.8)\"\n[forcing]\namplitude = 1.0\nomega = {OMEGA:?}\n{output}"
    )
}

fn write_scene(dir: &Path) -> PathBuf {
    let p = dir.join("osc.toml");
    std::fs::write(&p, scene_text(0.0, 0.0, 10.0, "")).unwrap();
    p
}

const TRANSIENT: usize = 200;
const GRID: (usize, usize) = (9, 7);
const XR: (f64, f64) = (-2.0, 0.4);
const VR: (f64, f64) = (-1.5, 1.5);

fn basins(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut c = bin();
    c.args(["basins", scene.to_str().unwrap(), "--x", "oscillator.initial_displacement", "--v", "oscillator.initial_velocity"]);
    c.args(["--grid", &GRID.0.to_string(), &GRID.1.to_string(), "--x-range", &XR.0.to_string(), &XR.1.to_string(), "--v-range", &VR.0.to_string(), &VR.1.to_string()]);
    c.args(["--transient", &TRANSIENT.to_string(), "--out", out.to_str().unwrap()]);
    c.args(extra);
    c.output().unwrap()
}

fn rows(out: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(out.join("basins.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "i,j,x,v,attractor,period,impacts_per_period,sticking,label,q0,v0");
    lines.map(|l| l.split(',').map(str::to_string).collect()).collect()
}

/// What an independent `signorini run` of the initial state `(x0, v0)`
/// says: its Poincaré samples after the transient, classified here — the
/// smallest k with |s_k − s_0|∞ <= 1e-5 — its impacts over those k periods,
/// and the cycle's points.
fn independent(dir: &Path, x0: f64, v0: f64) -> (usize, usize, Vec<[f64; 2]>) {
    let t = TAU / OMEGA;
    let scene = dir.join(format!("run_{x0}_{v0}.toml"));
    let output = format!("[output]\npoincare = true\nimpacts = true\ntransient = {TRANSIENT}\nplots = false\n");
    // t_end a whole number of steps (dt = 0.01) past 216 T.
    let t_end = (((TRANSIENT as f64 + 16.0) * t + 0.05) * 100.0).ceil() / 100.0;
    std::fs::write(&scene, scene_text(x0, v0, t_end, &output).replace(&format!("t_end = {t_end:?}"), &format!("t_end = {t_end:.2}"))).unwrap();
    let out = dir.join(format!("run_{x0}_{v0}"));
    let o = bin().args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let samples: Vec<[f64; 3]> = std::fs::read_to_string(out.join("poincare.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
            [c[0], c[1], c[2]]
        })
        .collect();
    assert_eq!(samples.len(), 17, "the run's Poincaré samples at 200T..216T");
    assert!((samples[0][0] - TRANSIENT as f64 * t).abs() < 1e-9);
    let s0 = samples[0];
    let k = (1..17).find(|&k| (samples[k][1] - s0[1]).abs().max((samples[k][2] - s0[2]).abs()) <= 1e-5).unwrap_or(0);
    let impacts: Vec<f64> = std::fs::read_to_string(out.join("impacts.csv")).unwrap().lines().skip(1).map(|l| l.split(',').nth(1).unwrap().parse().unwrap()).collect();
    let n = if k > 0 { impacts.iter().filter(|&&ti| ti > s0[0] && ti <= samples[k][0]).count() } else { 0 };
    (k, n, samples[..k.max(1)].iter().map(|s| [s[1], s[2]]).collect())
}

fn axis(from: f64, to: f64, n: usize, i: usize) -> f64 {
    from + (to - from) * i as f64 / (n - 1) as f64
}

#[test]
fn sampled_cells_match_independent_runs_and_two_attractors_coexist() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let out = dir.path().join("b");
    let o = basins(&scene, &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = rows(&out);
    assert_eq!(rows.len(), GRID.0 * GRID.1);
    // Two period-1 attractors, one with an impact a period and the free one.
    let mut labels: Vec<&str> = rows.iter().map(|r| r[8].as_str()).collect();
    labels.sort_unstable();
    labels.dedup();
    assert_eq!(labels, ["p1-i0", "p1-i1"]);
    // The free response in closed form: X cos(Ωt − φ).
    let (c, k) = (2.0 * 0.05, 1.0 - OMEGA * OMEGA);
    let (amp, phi) = (1.0 / (k * k + (c * OMEGA).powi(2)).sqrt(), (c * OMEGA).atan2(k));
    let free = [amp * phi.cos(), amp * OMEGA * phi.sin()];
    for r in rows.iter().filter(|r| r[8] == "p1-i0") {
        let s: Vec<f64> = r[9..].iter().map(|x| x.parse().unwrap()).collect();
        assert!((s[0] - free[0]).abs() < 1e-7 && (s[1] - free[1]).abs() < 1e-7, "{r:?} against {free:?}");
    }
    // Sampled cells: the first of each attractor, the corners, and a few.
    let mut sample: Vec<usize> = vec![0, GRID.0 - 1, GRID.0 * GRID.1 - GRID.0, GRID.0 * GRID.1 - 1, 23, 40];
    for l in labels {
        sample.push(rows.iter().position(|r| r[8] == l).unwrap());
    }
    sample.sort_unstable();
    sample.dedup();
    for c in sample {
        let r = &rows[c];
        let (i, j) = (c % GRID.0, c / GRID.0);
        assert_eq!((r[0].parse::<usize>().unwrap(), r[1].parse::<usize>().unwrap()), (i, j));
        let (x0, v0) = (axis(XR.0, XR.1, GRID.0, i), axis(VR.0, VR.1, GRID.1, j));
        assert!((r[2].parse::<f64>().unwrap() - x0).abs() < 1e-12 && (r[3].parse::<f64>().unwrap() - v0).abs() < 1e-12, "{r:?}");
        let (period, impacts, cycle) = independent(dir.path(), x0, v0);
        assert_eq!(r[5].parse::<usize>().unwrap(), period, "cell {c} ({x0}, {v0}): period {r:?}");
        assert_eq!(r[6].parse::<usize>().unwrap(), impacts, "cell {c} ({x0}, {v0}): impacts {r:?}");
        assert_eq!(r[7], "0");
        let s: Vec<f64> = r[9..].iter().map(|x| x.parse().unwrap()).collect();
        let d = cycle.iter().map(|p| (p[0] - s[0]).abs().max((p[1] - s[1]).abs())).fold(f64::INFINITY, f64::min);
        assert!(d < 1e-5, "cell {c}: the attractor's state {s:?} against the run's cycle {cycle:?}");
    }
}

#[test]
fn shards_merge_to_the_unsharded_grid_and_threads_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let whole = dir.path().join("whole");
    assert!(basins(&scene, &whole, &["--threads", "1"]).status.success());
    let two = dir.path().join("two");
    assert!(basins(&scene, &two, &["--threads", "2"]).status.success());
    for f in ["basins.csv", "basins.svg", "basins.toml"] {
        assert!(std::fs::read(whole.join(f)).unwrap() == std::fs::read(two.join(f)).unwrap(), "{f} differs between 1 and 2 threads");
    }
    let shards: Vec<PathBuf> = (0..4).map(|i| dir.path().join(format!("s{i}"))).collect();
    // The ids each shard gives are its own (shard 2, cells 31..47, starts on
    // the free orbit, id 1 of the whole grid); merge renumbers.
    for i in [2, 0, 3, 1] {
        let o = basins(&scene, &shards[i], &["--shard", &format!("{i}/4")]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(!shards[i].join("basins.svg").exists());
    }
    let merged = dir.path().join("merged");
    let o =
        bin().args(["merge", shards[2].to_str().unwrap(), shards[0].to_str().unwrap(), shards[3].to_str().unwrap(), shards[1].to_str().unwrap(), "--out", merged.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["basins.csv", "basins.svg", "basins.toml"] {
        assert!(std::fs::read(whole.join(f)).unwrap() == std::fs::read(merged.join(f)).unwrap(), "{f} merged differs from the unsharded grid's");
    }
    // A missing shard, and shards of another grid, are refused.
    let o = bin().args(["merge", shards[0].to_str().unwrap(), shards[2].to_str().unwrap(), shards[3].to_str().unwrap(), "--out", dir.path().join("m2").to_str().unwrap()]).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("shard 1 of 4 is missing"), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn an_interrupt_keeps_whole_rows() {
    let dir = tempfile::tempdir().unwrap();
    let text = scene_text(0.0, 0.0, 10.0, "");
    let cancel = signorini_run::Cancel::new();
    cancel.cancel();
    use signorini_orbits::basins::{Axis, BasinOptions};
    let opts = signorini_cli::basins::BasinsOptions {
        x: Axis { path: "oscillator.initial_displacement".into(), from: XR.0, to: XR.1, count: 4 },
        v: Axis { path: "oscillator.initial_velocity".into(), from: VR.0, to: VR.1, count: 3 },
        classify: BasinOptions { transient: 20, ..BasinOptions::default() },
        orbits: None,
        shard: None,
        threads: Some(2),
        interrupt: Some(cancel),
        progress: false,
    };
    let out = dir.path().join("b");
    let e = signorini_cli::basins::basins(&text, &opts, &out, signorini_scene::Limits::machine()).unwrap_err();
    assert_eq!(e.exit_code(), 130);
    assert!(e.to_string().contains("interrupted after 0 of 12 cells"), "{e}");
    assert_eq!(std::fs::read_to_string(out.join("basins.csv")).unwrap(), "i,j,x,v,attractor,period,impacts_per_period,sticking,label,q0,v0\n");
}

/// Bad input: a typed error naming the option, exit 2.
#[test]
fn bad_input_names_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let run = |scene: &Path, args: &[&str]| -> (Option<i32>, String) {
        let mut c = bin();
        c.args(["basins", scene.to_str().unwrap(), "--out", dir.path().join("bad").to_str().unwrap()]);
        c.args(args);
        let o = c.output().unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let base = ["--x", "oscillator.initial_displacement", "--v", "oscillator.initial_velocity", "--x-range", "-1", "0", "--v-range", "-1", "1"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> { base.iter().copied().chain(extra.iter().copied()).collect() };
    // A path that is no number of the scene.
    let mut a = with(&["--grid", "2", "2"]);
    a[1] = "oscillator.scheme";
    let (code, err) = run(&scene, &a);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("error: x: oscillator.scheme: is a string, not a number"), "{err}");
    let mut a = with(&["--grid", "2", "2"]);
    a[3] = "oscillator.nothing";
    let (code, err) = run(&scene, &a);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("error: v: oscillator.nothing: is not in the scene"), "{err}");
    // Grid 0.
    let (code, err) = run(&scene, &with(&["--grid", "0", "3"]));
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("error: grid: 0 is not allowed"), "{err}");
    // Not a number at all (clap).
    let (code, err) = run(&scene, &with(&["--grid", "a", "3"]));
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--grid"), "{err}");
    // A scheme other than the exact one.
    let other = dir.path().join("ps.toml");
    std::fs::write(&other, scene_text(0.0, 0.0, 10.0, "").replace("event-driven(0.8)", "ps(0.8)")).unwrap();
    let (code, err) = run(&other, &with(&["--grid", "2", "2"]));
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("error: scheme: ps(") && err.contains("allowed: event-driven(e)"), "{err}");
    // A corner outside the scene's ranges (beyond the stop).
    let mut a = with(&["--grid", "2", "2"]);
    a[6] = "0.9";
    let (code, err) = run(&scene, &a);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("error: x-range:"), "{err}");
    // A corner where only the second axis leaves its range (a negative
    // damping ratio) names that axis.
    let mut a = with(&["--grid", "2", "2"]);
    (a[3], a[8], a[9]) = ("oscillator.damping_ratio", "0.05", "-0.05");
    let (code, err) = run(&scene, &a);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("error: v-range:") && err.contains("damping_ratio: -0.05 is not allowed"), "{err}");
    // Equal ends with more than one cell on that axis; one cell takes them.
    let mut a = with(&["--grid", "3", "2"]);
    a[6] = "-1";
    let (code, err) = run(&scene, &a);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("error: x-range: -1 -1 is not allowed: two different numbers"), "{err}");
    a[11] = "1";
    let (code, err) = run(&scene, &a);
    assert_eq!(code, Some(0), "{err}");
    // Tolerances.
    let (code, err) = run(&scene, &with(&["--grid", "2", "2", "--tol", "0"]));
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("error: tol: 0 is not allowed"), "{err}");
}

/// `--orbits`: a continuation's branch through the impacting orbit (from
/// the scene's start (−2, −2), which the grid shows on it) labels exactly
/// the cells the unlabelled grid puts on `p1-i1`, by the branch's point at
/// the scene's Ω (`branch0:0`, the first); the free orbit's cells keep
/// their description.
#[test]
fn known_orbits_label_their_basins() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let start = dir.path().join("start.toml");
    std::fs::write(&start, scene_text(-2.0, -2.0, 10.0, "")).unwrap();
    let cont = dir.path().join("c");
    let o = bin().args(["continue", start.to_str().unwrap(), "--param", "forcing.omega", "--from", "1.85", "--to", "1.87", "--out", cont.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let branch = std::fs::read_to_string(cont.join("branch.csv")).unwrap();
    let first: Vec<&str> = branch.lines().nth(1).unwrap().split(',').collect();
    assert_eq!((first[0], first[6]), ("1.850000000000e0", "1"), "the branch starts at Ω = 1.85 on the impacting orbit");
    let plain = dir.path().join("plain");
    assert!(basins(&scene, &plain, &[]).status.success());
    let labelled = dir.path().join("labelled");
    let o = basins(&scene, &labelled, &["--orbits", cont.join("branch.csv").to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (rows(&plain), rows(&labelled));
    for (p, l) in a.iter().zip(&b) {
        let want = if p[8] == "p1-i1" { "branch0:0" } else { p[8].as_str() };
        assert_eq!(l[8], want, "{p:?} / {l:?}");
        assert_eq!(p[..8], l[..8]);
    }
    // A file that is no branch.csv is refused naming the option.
    let o = basins(&scene, &dir.path().join("bad"), &["--orbits", scene.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("error: orbits: no param column"), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `--orbits` with orbits of two forcing periods, from two branches in one
/// file: the oscillator with its stop at 0.2 at Ω = 1.11 has two period-2
/// attractors (2 and 3 impacts over the period); a continuation from a
/// state in each basin (`--period 2`, from the scene's Ω) and the two
/// `branch.csv` joined (the second renumbered branch 1) label exactly the
/// cells the unlabelled grid puts on `p2-i2` and `p2-i3`, each by the
/// first point of its own branch (at the scene's Ω), whose period and
/// impacts per period are the cells' (a known orbit of period p labels a
/// cycle whose period divides p: its impacts scale with it).
#[test]
fn labels_of_period_two_orbits_agree_with_their_branch_rows() {
    let dir = tempfile::tempdir().unwrap();
    let text = |x0: f64, v0: f64| {
        format!(
            "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.8\ninitial_displacement = {x0:?}\ninitial_velocity = {v0:?}\ndt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = 1.11\n"
        )
    };
    let scene = dir.path().join("osc.toml");
    std::fs::write(&scene, text(0.0, 0.0)).unwrap();
    let grid = |out: &Path, extra: &[&str]| {
        let mut c = bin();
        c.args(["basins", scene.to_str().unwrap(), "--x", "oscillator.initial_displacement", "--v", "oscillator.initial_velocity"]);
        c.args(["--grid", "12", "12", "--x-range", "-2", "0.15", "--v-range", "-2", "2", "--out", out.to_str().unwrap()]).args(extra);
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        rows(out)
    };
    let plain = grid(&dir.path().join("plain"), &[]);
    // One continuation from a cell of each attractor.
    let mut joined = String::new();
    for (b, want) in ["p2-i2", "p2-i3"].into_iter().enumerate() {
        let cell = plain.iter().find(|r| r[8] == want).unwrap_or_else(|| panic!("no {want} cell"));
        let start = dir.path().join(format!("start{b}.toml"));
        std::fs::write(&start, text(cell[2].parse().unwrap(), cell[3].parse().unwrap())).unwrap();
        let out = dir.path().join(format!("c{b}"));
        let o = bin().args(["continue", start.to_str().unwrap(), "--param", "forcing.omega", "--from", "1.11", "--to", "1.115", "--period", "2", "--out", out.to_str().unwrap()]).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let csv = std::fs::read_to_string(out.join("branch.csv")).unwrap();
        let mut lines = csv.lines();
        let head = lines.next().unwrap();
        if b == 0 {
            joined = format!("{head}\n");
        }
        let cb = head.split(',').position(|h| h == "branch").unwrap();
        for l in lines {
            let mut f: Vec<&str> = l.split(',').collect();
            let n = b.to_string();
            f[cb] = &n;
            joined += &(f.join(",") + "\n");
        }
    }
    let file = dir.path().join("both.csv");
    std::fs::write(&file, &joined).unwrap();
    let labelled = grid(&dir.path().join("labelled"), &["--orbits", file.to_str().unwrap()]);
    let mut lines = joined.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let branch_rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let c = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let mut seen = [0usize; 2];
    for (p, l) in plain.iter().zip(&labelled) {
        assert_eq!(p[..8], l[..8]);
        let Some((b, n)) = l[8].strip_prefix("branch").and_then(|s| s.split_once(':')) else {
            assert_eq!(l[8], p[8], "a cell off the two attractors keeps its description");
            assert!(p[8] != "p2-i2" && p[8] != "p2-i3", "{p:?} not labelled");
            continue;
        };
        let (b, n): (usize, usize) = (b.parse().unwrap(), n.parse().unwrap());
        let row = branch_rows.iter().filter(|r| r[c("branch")] == b.to_string()).nth(n).unwrap_or_else(|| panic!("{} names no row", l[8]));
        assert_eq!(row[c("param")].parse::<f64>().unwrap(), 1.11, "{} is not the branch's point at the scene's Ω", l[8]);
        let (bp, bi): (usize, usize) = (row[c("period")].parse().unwrap(), row[c("impacts_per_period")].parse().unwrap());
        let (cp, ci): (usize, usize) = (l[5].parse().unwrap(), l[6].parse().unwrap());
        assert!(bp % cp == 0 && ci * (bp / cp) == bi, "cell {:?} (period {cp}, {ci} impacts) labelled {} (period {bp}, {bi} impacts)", &l[..4], l[8]);
        assert_eq!(p[8], ["p2-i2", "p2-i3"][b], "{} labels a {} cell", l[8], p[8]);
        seen[b] += 1;
    }
    assert!(seen[0] > 0 && seen[1] > 0, "cells labelled per branch: {seen:?}");
}
