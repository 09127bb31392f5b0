//! `signorini continue` end to end: the files and their contract columns,
//! the oscillator's grazing frequency against its closed form (written
//! here), the period-doubled branch, and bad input (exit 2, the option
//! named).

use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

const SCENE: &str =
    "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.8\ndt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = 2.2\n";

fn run(dir: &Path, scene: &str, args: &[&str]) -> std::process::Output {
    let p = dir.join("scene.toml");
    std::fs::write(&p, scene).unwrap();
    bin().arg("continue").arg(&p).args(args).arg("--out").arg(dir.join("out")).output().unwrap()
}

#[test]
fn the_files_their_columns_and_the_grazing_frequency() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(dir.path(), SCENE, &["--param", "forcing.omega", "--from", "2.2", "--to", "3.0"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.path().join("out");
    let branch = std::fs::read_to_string(out.join("branch.csv")).unwrap();
    assert_eq!(branch.lines().next().unwrap(), "param,period,stable,mu_max,impact_velocity,impact_phase,impacts_per_period,releases_per_period,displacement,branch,residual,q0,v0");
    let bif = std::fs::read_to_string(out.join("bifurcations.csv")).unwrap();
    assert_eq!(bif.lines().next().unwrap(), "param,kind,mu_re,mu_im,impacts_before,impacts_after,releases_before,releases_after,displacement,branch");
    let row: Vec<&str> = bif.lines().skip(1).map(|l| l.split(',').collect::<Vec<&str>>()).find(|r| r[1] == "grazing").expect("a grazing");
    // (1 − u)² + 4ζ²u = (F/kg)², u = (Ω/ω)²: the larger root.
    let (zeta, q): (f64, f64) = (0.05, 1.0 / 0.2);
    let want = ((1.0 - 2.0 * zeta * zeta) + (q * q - 4.0 * zeta * zeta * (1.0 - zeta * zeta)).sqrt()).sqrt();
    let got: f64 = row[0].parse().unwrap();
    assert!((got - want).abs() <= 1e-8 * want, "grazing at {got}, closed form {want}");
    assert!(std::fs::read_to_string(out.join("branch.svg")).unwrap().starts_with("<svg"));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("grazing at forcing.omega"), "{text}");
}

#[test]
fn switch_continues_the_period_doubled_branch() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(dir.path(), SCENE, &["--param", "forcing.omega", "--from", "2.2", "--to", "1.03", "--switch"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let branch = std::fs::read_to_string(dir.path().join("out/branch.csv")).unwrap();
    // Rows of branch 1 have period 2; those of the period-doubled orbit
    // (one impact each forcing period, two per orbit) lie between the two
    // period doublings. (Past a grazing of its flight the branch goes on
    // with a third impact: those rows reach beyond.)
    let doubled: Vec<Vec<String>> = branch.lines().skip(1).map(|l| l.split(',').map(String::from).collect()).filter(|r: &Vec<String>| r[9] == "1").collect();
    assert!(doubled.len() > 5, "a doubled branch: {} rows", doubled.len());
    for r in &doubled {
        assert_eq!(r[1], "2");
        let p: f64 = r[0].parse().unwrap();
        if r[6] == "2" {
            assert!((1.0648..=1.1301).contains(&p), "a period-2 orbit at {p}");
        }
    }
    assert!(doubled.iter().filter(|r| r[6] == "2").count() > 5);
    // Its loop of period-2 orbits (through grazings, folds and its mirror
    // image shifted by a period) is run once: the branch ends where it
    // rejoins the period-1 branch through the other period doubling, onto
    // the phase-shifted copies of its own orbits (docs/theory.md §12.3),
    // not at the most points allowed.
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(!text.contains("max points"), "{text}");
}

#[test]
fn bad_input_exits_2_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, args, words) in [
        (SCENE.to_string(), vec!["--param", "oscillator.scheme", "--from", "1", "--to", "2"], "not a number"),
        (SCENE.to_string(), vec!["--param", "forcing.nothing", "--from", "1", "--to", "2"], "not in the scene"),
        (SCENE.to_string(), vec!["--param", "forcing.omega", "--from", "2.2", "--to", "3", "--period", "0"], "period"),
        (SCENE.to_string(), vec!["--param", "forcing.omega", "--from", "2.2", "--to", "2.2"], "from/to"),
        (SCENE.replace("scheme = \"event-driven\"", "scheme = \"ps(0.8, 0.25)\""), vec!["--param", "forcing.omega", "--from", "2.2", "--to", "3"], "event-driven"),
        (SCENE.to_string(), vec!["--param", "oscillator.mass", "--from", "1", "--to", "-1"], "oscillator.mass"),
    ] {
        let o = run(dir.path(), &scene, &args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(words), "{args:?}: {err}");
    }
}

const BAR: &str = "[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"clamped\"\ngap = 0.0\nelements = 80\nmass = \"mod3\"\nscheme = \"event-driven\"\ndt = 0.01\nt_end = 10.0\n";

#[test]
fn modes_writes_the_backbone_against_the_exact_period() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bar.toml");
    std::fs::write(&p, BAR).unwrap();
    let out = dir.path().join("out");
    let o = bin().arg("modes").arg(&p).args(["--from", "0.1", "--to", "10", "--points", "3", "--out"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("backbone.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(lines.next().unwrap().starts_with("energy,period,contact_time,impacts_per_period,exact_period"));
    // g = 0: the continuous bar's period is 3L/c at every energy.
    for l in lines {
        let c: Vec<f64> = l.split(',').take(5).map(|v| v.parse().unwrap()).collect();
        assert!((c[1] - 3.0).abs() < 1e-3 && c[4] == 3.0, "{l}");
    }
    for (args, words) in [(vec!["--from", "-1", "--to", "1"], "from"), (vec!["--from", "1", "--to", "2", "--points", "0"], "points")] {
        let o = bin().arg("modes").arg(&p).args(&args).arg("--out").arg(&out).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(words), "{args:?}: {err}");
    }
}

/// The summary line of a branch: `(S stable, U unstable[, N neutral])`.
fn counts(stdout: &str) -> (usize, usize, usize) {
    let line = stdout.lines().find(|l| l.starts_with("branch 0 ")).unwrap_or_else(|| panic!("no branch line: {stdout}"));
    let inner = &line[line.find("points from").unwrap()..];
    let inner = &inner[inner.find('(').unwrap() + 1..inner.find(')').unwrap()];
    let mut c = (0, 0, 0);
    for part in inner.split(", ") {
        let (n, what) = part.split_once(' ').unwrap();
        let n: usize = n.parse().unwrap();
        match what {
            "stable" => c.0 = n,
            "unstable" => c.1 = n,
            "neutral" => c.2 = n,
            other => panic!("{other} in {line}"),
        }
    }
    c
}

/// Undamped and far from its stop, the oscillator's period-1 orbit is the
/// linear steady state, amplitude `F/(k |1 − s²|)` (0.26 at most over
/// Ω = 2.2 … 3.0, against a stop at 10: no impact), and its multipliers
/// are `e^{±i ω T}`, both of modulus 1: every point is neutral — neither
/// stable nor unstable — as branch.csv (`mu_max` 1) and branch.svg say; a
/// damped branch's summary keeps its two counts alone.
#[test]
fn the_summary_counts_neutral_orbits_apart() {
    let dir = tempfile::tempdir().unwrap();
    let undamped = SCENE.replace("damping_ratio = 0.05", "damping_ratio = 0.0").replace("stop = 0.2", "stop = 10.0");
    let o = run(dir.path(), &undamped, &["--param", "forcing.omega", "--from", "2.2", "--to", "3.0"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    let rows: Vec<Vec<String>> = std::fs::read_to_string(dir.path().join("out/branch.csv")).unwrap().lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect();
    assert!(rows.len() > 3, "{text}");
    for r in &rows {
        let (omega, mu): (f64, f64) = (r[0].parse().unwrap(), r[3].parse().unwrap());
        assert!((mu - 1.0).abs() < 1e-9 && r[6] == "0", "Ω = {omega}: |μ| = {mu}, impacts {}", r[6]);
    }
    assert_eq!(counts(&text), (0, 0, rows.len()), "{text}");
    // Damped (the reference scene): no neutral orbit, and the line as it was.
    let o = run(dir.path(), SCENE, &["--param", "forcing.omega", "--from", "2.2", "--to", "3.0"]);
    let text = String::from_utf8_lossy(&o.stdout);
    let (s, u, n) = counts(&text);
    let rows = std::fs::read_to_string(dir.path().join("out/branch.csv")).unwrap().lines().count() - 1;
    assert!(n == 0 && s > 0 && u > 0 && s + u == rows && !text.contains("neutral"), "{text}");
}
