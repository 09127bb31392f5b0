//! The impact oscillator between two stops, `stops = [lo, hi]`, through
//! every front end of the binary: `check`, `run`, `sweep`, `continue` and
//! `basins` each give a result that differs from the one-stop scene's
//! (`stop = hi`), checked against closed forms written here where there is
//! one; and the refusals (exit 2, the key named).

use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

/// The free elastic oscillator `x'' + x = 0` from `x = 0`, `x' = 1`.
const FREE: &str = "[oscillator]\nmass = 1.0\nstiffness = 1.0\nstops = [-0.5, 0.8]\nrestitution = 1.0\ninitial_velocity = 1.0\ndt = 1e-2\nt_end = 4.0\nscheme = \"event-driven\"\n";

/// `x'' + 0.1 x' + x = cos Ωt` between −0.5 and 0.8, e = 0.8.
const FORCED: &str = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstops = [-0.5, 0.8]\nrestitution = 0.8\ninitial_displacement = 0.0\ninitial_velocity = 0.0\ndt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = 3.0\n";

/// The same scene with the upper stop alone.
fn one_stop(scene: &str) -> String {
    scene.replace("stops = [-0.5, 0.8]", "stop = 0.8")
}

fn write(dir: &Path, name: &str, scene: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, scene).unwrap();
    p
}

fn ok(o: &std::process::Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The rows of a CSV file, split at commas, without the header.
fn rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path).unwrap().lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect()
}

/// `x = sin t` reaches the upper stop 0.8 at `t1 = asin 0.8` at speed 0.6;
/// reflected (e = 1) it is `x = sin(2 t1 − t)`, which reaches the lower
/// stop −0.5 at `t2 = 2 t1 + π/6` at speed −√3/2, and the upper again at
/// `t3 = t2 + t1 + π/6` at 0.6 (the energy `x² + x'² = 1` kept). With the
/// upper stop alone it never meets −0.5: its second impact is at the upper
/// stop again.
#[test]
fn run_meets_the_far_stop_at_the_closed_form_time_and_speed() {
    let dir = tempfile::tempdir().unwrap();
    let t1 = 0.8f64.asin();
    let t2 = 2.0 * t1 + std::f64::consts::FRAC_PI_6;
    let want = [(t1, 0.6), (t2, -(3.0f64.sqrt()) / 2.0), (t2 + t1 + std::f64::consts::FRAC_PI_6, 0.6)];
    let o = bin().arg("run").arg(write(dir.path(), "two.toml", FREE)).arg("--out").arg(dir.path().join("two")).output().unwrap();
    ok(&o);
    let ev = rows(&dir.path().join("two/events.csv"));
    assert_eq!(ev.len(), want.len(), "{ev:?}");
    for (r, (t, v)) in ev.iter().zip(want) {
        let (gt, gv): (f64, f64) = (r[0].parse().unwrap(), r[3].parse().unwrap());
        assert_eq!(r[1], "impact");
        assert!((gt - t).abs() <= 1e-12 && (gv - v).abs() <= 1e-12, "impact at t = {gt}, v = {gv}; closed form t = {t}, v = {v}");
    }
    // series.csv: x within the stops at every level.
    let series = rows(&dir.path().join("two/series.csv"));
    assert!(series.iter().all(|r| r[2].parse::<f64>().unwrap() >= -0.5 - 1e-12), "x below the lower stop");
    let o = bin().arg("run").arg(write(dir.path(), "one.toml", &one_stop(FREE))).arg("--out").arg(dir.path().join("one")).output().unwrap();
    ok(&o);
    let ev = rows(&dir.path().join("one/events.csv"));
    assert!(ev.len() == 1 && ev[0][3].parse::<f64>().unwrap() > 0.0, "one stop: the upper stop's impact alone before t = 4 ({ev:?})");
}

#[test]
fn check_states_both_stops() {
    let dir = tempfile::tempdir().unwrap();
    let o = bin().arg("check").arg(write(dir.path(), "two.toml", FORCED)).output().unwrap();
    ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("stops [-0.5, 0.8], r = 0.8"), "{text}");
    let o = bin().arg("check").arg(write(dir.path(), "one.toml", &one_stop(FORCED))).output().unwrap();
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("stop 0.8, r = 0.8"));
}

/// At Ω = 1.6 from rest the sweep's record has impacts on the lower stop
/// (velocity < 0) between the stops, none with the upper stop alone.
#[test]
fn sweep_records_impacts_on_the_lower_stop() {
    let dir = tempfile::tempdir().unwrap();
    let lower = |name: &str, scene: &str| {
        let out = dir.path().join(name);
        let o = bin()
            .arg("sweep")
            .arg(write(dir.path(), &format!("{name}.toml"), scene))
            .args(["--param", "forcing.omega", "--from", "1.6", "--to", "1.7", "--count", "2", "--transient", "20", "--record", "5", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        ok(&o);
        rows(&out.join("impacts.csv")).iter().filter(|r| r[5].parse::<f64>().unwrap() < 0.0).count()
    };
    assert!(lower("two", FORCED) > 0, "no impact on the lower stop");
    assert_eq!(lower("one", &one_stop(FORCED)), 0);
}

/// The free period-1 orbit `x = a cos Ωt + b sin Ωt` (a = (1 − Ω²)/d,
/// b = 2ζΩ/d, d = (1 − Ω²)² + (2ζΩ)²) continued from Ω = 3 down grazes
/// the nearer stop, the lower one at 0.5: `(1 − u)² + 4ζ²u = (1/0.5)²`,
/// u = Ω², the larger root. With the upper stop alone (0.8) the orbit
/// reaches Ω = 1.5 without a grazing.
#[test]
fn continue_grazes_the_lower_stop_at_the_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("two");
    let o = bin().arg("continue").arg(write(dir.path(), "two.toml", FORCED)).args(["--param", "forcing.omega", "--from", "3", "--to", "1.5", "--out"]).arg(&out).output().unwrap();
    ok(&o);
    let zeta: f64 = 0.05;
    let want = ((1.0 - 2.0 * zeta * zeta) + (4.0 - 4.0 * zeta * zeta * (1.0 - zeta * zeta)).sqrt()).sqrt();
    let bif = rows(&out.join("bifurcations.csv"));
    let g: f64 = bif.iter().find(|r| r[1] == "grazing").expect("a grazing")[0].parse().unwrap();
    assert!((g - want).abs() <= 1e-9 * want, "grazing at {g}, closed form {want}");
    // Every point above the grazing without impacts is the free orbit.
    let mut free = 0;
    for r in rows(&out.join("branch.csv")) {
        let w: f64 = r[0].parse().unwrap();
        if r[6] != "0" || w < g {
            continue;
        }
        let u = w * w;
        let d = (1.0 - u).powi(2) + (2.0 * zeta * w).powi(2);
        let (q, v): (f64, f64) = (r[11].parse().unwrap(), r[12].parse().unwrap());
        assert!((q - (1.0 - u) / d).abs() <= 1e-9 && (v - w * 2.0 * zeta * w / d).abs() <= 1e-9, "Ω = {w}: ({q}, {v})");
        free += 1;
    }
    assert!(free >= 10, "{free} free points");
    let out = dir.path().join("one");
    let o = bin().arg("continue").arg(write(dir.path(), "one.toml", &one_stop(FORCED))).args(["--param", "forcing.omega", "--from", "3", "--to", "1.5", "--out"]).arg(&out).output().unwrap();
    ok(&o);
    assert!(rows(&out.join("bifurcations.csv")).is_empty(), "one stop at 0.8: no bifurcation down to 1.5");
}

/// At Ω = 1.6 the free orbit's amplitude, 1/√d = 0.63, passes −0.5: every
/// cell goes to an orbit with two impacts a period between the stops, while
/// with the upper stop alone the free orbit (no impact) attracts a cell.
#[test]
fn basins_differ_with_the_lower_stop() {
    let dir = tempfile::tempdir().unwrap();
    let cells = |name: &str, scene: &str| {
        let out = dir.path().join(name);
        let o = bin()
            .arg("basins")
            .arg(write(dir.path(), &format!("{name}.toml"), &scene.replace("omega = 3.0", "omega = 1.6")))
            .args(["--x", "oscillator.initial_displacement", "--v", "oscillator.initial_velocity", "--grid", "2", "2", "--x-range", "-0.4", "0.4", "--v-range", "-0.1", "0.1", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        ok(&o);
        rows(&out.join("basins.csv")).iter().map(|r| (r[5].clone(), r[6].clone())).collect::<Vec<_>>()
    };
    let two = cells("two", FORCED);
    assert!(two.iter().all(|c| c == &("1".to_string(), "2".to_string())), "{two:?}");
    let one = cells("one", &one_stop(FORCED));
    assert!(one.iter().any(|c| c.1 == "0"), "{one:?}");
}

/// Bad stops: exit 2, nothing run, the key named with what is allowed.
#[test]
fn bad_stops_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(String, &[&str]); 6] = [
        (FORCED.replace("stops = [-0.5, 0.8]", "stop = 0.8\nstops = [-0.5, 0.8]"), &["oscillator.stops", "oscillator.stop ", "one acts"]),
        (FORCED.replace("stops = [-0.5, 0.8]", "stops = [0.8, -0.5]"), &["oscillator.stops", "lo < hi"]),
        (FORCED.replace("stops = [-0.5, 0.8]", "stops = [-inf, 0.8]"), &["oscillator.stops", "finite"]),
        (FREE.replace("stops = [-0.5, 0.8]", "stops = [0.1, 0.8]"), &["oscillator.stops", "lo <= initial_displacement (default 0) <= hi"]),
        (FORCED.replace("initial_displacement = 0.0", "initial_displacement = -0.6"), &["oscillator.initial_displacement", "[-0.5, 0.8]"]),
        (FORCED.replace("stops = [-0.5, 0.8]\n", ""), &["oscillator.stop", "stops = [lo, hi]"]),
    ];
    for (scene, needles) in cases {
        let p = write(dir.path(), "bad.toml", &scene);
        for cmd in [&["check"][..], &["run", "--out", "bad"][..]] {
            let o = bin().current_dir(dir.path()).args(cmd).arg(&p).output().unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{cmd:?}: {err}");
            for n in needles {
                assert!(err.contains(n), "{cmd:?}: {n:?} not in {err}");
            }
        }
        assert!(!dir.path().join("bad").exists());
    }
}
