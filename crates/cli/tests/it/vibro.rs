//! Vibro-impact scenes end to end: the paper's fig. 2 beam read by the
//! impact observer against the impact times stored by `cargo xtask beam`
//! (data/reference/beam/scenes.csv), the paper's scene as one run of a
//! support-frequency sweep with identical numbers, general support motions
//! against the sine path, and loads on the bar against closed forms.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn ok(o: &std::process::Output) {
    assert!(o.status.success(), "{}\n{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
}

fn run(dir: &Path, name: &str, text: &str) -> PathBuf {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join(name);
    ok(&bin().args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap());
    out
}

fn rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path).unwrap().lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect()
}

/// The stored fig. 2 row: contact onsets and the first eight onset times.
fn reference_fig2() -> (usize, Vec<f64>) {
    let text = std::fs::read_to_string(root().join("data/reference/beam/scenes.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.find(|l| l.starts_with("fig2,projection,")).unwrap().split(',').collect();
    let col = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
    (col("impacts").parse().unwrap(), col("first_impacts_s").split(' ').map(|t| t.parse().unwrap()).collect())
}

const FIG2: &str = "[beam]\nscene = \"fig2\"\n\n[output]\nevery = 10\nplots = false\nimpacts = true\n";

#[test]
fn fig2_impacts_are_the_stored_contact_onsets() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), "fig2", FIG2);
    let imp = rows(&out.join("impacts.csv"));
    let (count, first) = reference_fig2();
    assert_eq!(imp.len(), count, "one impact per contact onset");
    let dt = 5e-5;
    for (r, t_ref) in imp.iter().zip(&first) {
        // The onset level t_ref (5 decimals) is the first level whose step was
        // active; the crossing estimate lies in the step before it.
        let t: f64 = r[1].parse().unwrap();
        assert!(t <= t_ref + 5e-6 && t > t_ref - dt - 5e-6, "impact at {t}, onset level {t_ref}");
        // The forcing phase is 10 t mod 2π.
        let phase: f64 = r[2].parse().unwrap();
        assert!((phase - (10.0 * t).rem_euclid(std::f64::consts::TAU)).abs() < 1e-9);
    }
}

#[test]
fn the_paper_scene_is_one_run_of_a_support_frequency_sweep() {
    let dir = tempfile::tempdir().unwrap();
    // [support] with the paper's sine is the same problem, bit for bit.
    let with_support = format!("{FIG2}poincare = true\n\n[support]\namplitude = 0.2\nomega = 10.0\n");
    let a = run(dir.path(), "plain", &format!("{FIG2}poincare = true\n"));
    let b = run(dir.path(), "support", &with_support);
    for f in ["series.csv", "impacts.csv", "poincare.csv"] {
        assert_eq!(std::fs::read(a.join(f)).unwrap(), std::fs::read(b.join(f)).unwrap(), "{f}");
    }
    // A sweep over support.omega through 10 rad/s; its horizon is 2 s at
    // ω = 10 when it records 2·10/(2π) periods (40 000 steps of 5e-5 s).
    let scene = dir.path().join("sweep.toml");
    std::fs::write(&scene, &with_support).unwrap();
    let out = dir.path().join("sw");
    let record = format!("{:.15}", 20.0 / std::f64::consts::TAU);
    ok(&bin()
        .args(["sweep", scene.to_str().unwrap(), "--param", "support.omega", "--from", "9.0", "--to", "11.0", "--count", "3", "--transient", "0", "--record", &record, "--out", out.to_str().unwrap()])
        .output()
        .unwrap());
    let summary = rows(&out.join("summary.csv"));
    assert_eq!(summary[1][0], "10");
    assert_eq!(summary[1][summary[1].len() - 2], "40000", "steps of the ω = 10 run");
    // Its impacts and Poincaré samples are the run's, to every printed digit.
    let e12 = |s: &str| format!("{:.12e}", s.parse::<f64>().unwrap());
    let sweep_imp: Vec<Vec<String>> = rows(&out.join("impacts.csv")).into_iter().filter(|r| r[1] == "1").collect();
    let run_imp = rows(&b.join("impacts.csv"));
    assert_eq!(sweep_imp.len(), run_imp.len());
    for (s, r) in sweep_imp.iter().zip(&run_imp) {
        assert_eq!(s[2], r[0], "stop");
        for k in 0..5 {
            assert_eq!(e12(&s[3 + k]), r[1 + k], "impact column {k}");
        }
    }
    let sweep_pc: Vec<Vec<String>> = rows(&out.join("sweep.csv")).into_iter().filter(|r| r[1] == "1").collect();
    let run_pc = rows(&b.join("poincare.csv"));
    assert!(!run_pc.is_empty());
    assert_eq!(sweep_pc.len(), run_pc.len());
    for (s, r) in sweep_pc.iter().zip(&run_pc) {
        for k in 0..3 {
            assert_eq!(e12(&s[2 + k]), r[k]);
        }
    }
}

#[test]
fn a_general_support_motion_is_the_sine_when_it_is_one() {
    // φ = 0.2 sin(10 t) as one harmonic takes the general lifting (two load
    // terms, −h φ'' and 8 k²/L⁴ φ): the same tip to round-off before impacts.
    let dir = tempfile::tempdir().unwrap();
    let head = "[beam]\nscene = \"fig2\"\nt_end = 0.08\n\n[output]\nplots = false\n";
    let a = run(dir.path(), "sine", &format!("{head}\n[support]\namplitude = 0.2\nomega = 10.0\n"));
    let b = run(dir.path(), "harm", &format!("{head}\n[support]\nprofile = \"harmonics\"\nharmonics = [[0.2, 10.0, 0.0]]\nomega = 10.0\n"));
    let (ra, rb) = (rows(&a.join("series.csv")), rows(&b.join("series.csv")));
    assert_eq!(ra.len(), rb.len());
    let mut worst: f64 = 0.0;
    for (x, y) in ra.iter().zip(&rb) {
        let (u, v): (f64, f64) = (x[2].parse().unwrap(), y[2].parse().unwrap());
        worst = worst.max((u - v).abs());
    }
    assert!(worst < 1e-12 && worst.is_finite(), "tip differs by {worst:e} m");
    // A phase-shifted motion φ(0) ≠ 0 starts the beam undeformed: the tip of
    // u = ũ − hφ starts at 0 (h(L) = 0) and the run goes.
    run(dir.path(), "cos", &format!("{head}\n[support]\nprofile = \"cosine\"\namplitude = 0.05\nomega = 10.0\n"));
}

#[test]
fn bad_excitations_name_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("[beam]\nscene = \"fig2\"\n[support]\nprofile = \"series\"\nseries = [[0.0, 0.0], [1.0, 0.1]]\n", "support.profile"),
        ("[beam]\nscene = \"fig2\"\n[support]\nprofile = \"random\"\nf_lo = 5.0\nf_hi = 2.0\npsd = 1e-4\n", "support.f_hi"),
        ("[beam]\nscene = \"fig2\"\n[support]\namplitude = 0.2\n", "support.omega"),
        ("[beam]\nscene = \"fig2\"\nsupport = [0.2, 10.0]\n[support]\namplitude = 0.2\nomega = 10.0\n", "beam.support"),
        ("[beam]\nscene = \"fig2\"\n[load]\nprofile = \"series\"\nseries = [[0.0, 0.0], [0.0, 0.1]]\n", "load.series.t"),
        ("[beam]\nscene = \"fig2\"\n[load]\namplitude = 1.0\nomega = 3.0\nx = 0.3\n", "load.x"),
        ("[beam]\nscene = \"fig2\"\n[load]\namplitude = 1.0\nomega = 3.0\nharmonics = [[1.0, 2.0, 0.0]]\n", "load.harmonics"),
        ("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 1.0\n[load]\namplitude = 1.0\nomega = 3.0\n", "load"),
        ("[bar]\nelements = 10\ndt = 0.1\n[support]\namplitude = 1.0\nomega = 3.0\n", "support"),
        ("[bar]\nelements = 10\ndt = 0.1\n[load]\nprofile = \"random\"\nf_lo = 0.0\nf_hi = 2.0\npsd = -1.0\n", "load.psd"),
    ];
    for (i, (text, field)) in cases.iter().enumerate() {
        let scene = dir.path().join(format!("bad{i}.toml"));
        std::fs::write(&scene, text).unwrap();
        let o = bin().args(["check", scene.to_str().unwrap()]).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{text}: {err}");
        assert!(err.contains(field), "{text}: {err}");
    }
}

#[test]
fn a_uniform_load_moves_a_free_bar_as_a_rigid_body() {
    // A free–free bar far from its obstacle under f(t) = A sin(ω t) per unit
    // length: every node follows u = A/ω² (ω t − sin ω t) (from rest), and
    // Crank–Nicolson converges to it at second order.
    let (a, w) = (0.3, 2.0);
    let exact = |t: f64| a / (w * w) * (w * t - (w * t).sin());
    let dir = tempfile::tempdir().unwrap();
    let err = |dt: f64| {
        let text = format!("[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"free\"\ngap = -10.0\ninitial_displacement = 0.0\ninitial_velocity = 0.0\nelements = 8\nscheme = \"newmark-cn\"\ndt = {dt}\nt_end = 2.0\n\n[output]\nplots = false\n\n[load]\namplitude = {a}\nomega = {w}\n");
        let out = run(dir.path(), &format!("bar{dt}"), &text);
        rows(&out.join("series.csv")).iter().map(|r| (r[2].parse::<f64>().unwrap() - exact(r[1].parse().unwrap())).abs()).fold(0.0, f64::max)
    };
    let (e1, e2) = (err(0.02), err(0.01));
    let rate = (e1 / e2).log2();
    assert!((1.9..2.1).contains(&rate) && e2 < 1e-4, "errors {e1:e}, {e2:e}, rate {rate}");
}

#[test]
fn random_support_motion_is_reproducible_from_its_seed() {
    let dir = tempfile::tempdir().unwrap();
    let scene =
        |seed: u64| format!("[beam]\nscene = \"fig2\"\nt_end = 0.2\n\n[output]\nplots = false\n\n[support]\nprofile = \"random\"\nf_lo = 0.5\nf_hi = 5.0\npsd = 1e-4\ncount = 50\nseed = {seed}\n");
    let a = std::fs::read(run(dir.path(), "r1", &scene(1)).join("series.csv")).unwrap();
    let b = std::fs::read(run(dir.path(), "r1b", &scene(1)).join("series.csv")).unwrap();
    let c = std::fs::read(run(dir.path(), "r2", &scene(2)).join("series.csv")).unwrap();
    assert_eq!(a, b, "same seed, same run");
    assert_ne!(a, c, "another seed, another signal");
}

/// `output.period_tol`: at dt = 1e-3 the oscillator's period-1 orbit at
/// Ω = 2.2 jitters by O(dt) on its section; 1e-3 calls it not periodic
/// (0), 5e-3 period-1. Out of range, or without `summary`, it is refused.
#[test]
fn the_period_tolerance_is_the_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(root().join("data/scenes/oscillator.toml")).unwrap().replace("omega = 2.0", "omega = 2.2").replace("t_end = 100.0", "t_end = 300.0");
    let period = |extra: &str| {
        let out = run(dir.path(), &format!("p{}", extra.len()), &format!("{base}\n[output]\nplots = false\nsummary = true\npoincare = true\ntransient = 80\n{extra}"));
        rows(&out.join("summary.csv"))[0][7].clone()
    };
    assert_eq!(period(""), "0");
    assert_eq!(period("period_tol = 5e-3\n"), "1");
    for (extra, field) in [("summary = true\nperiod_tol = 2.0\n", "output.period_tol"), ("period_tol = 5e-3\n", "output.period_tol")] {
        let scene = dir.path().join("bad.toml");
        std::fs::write(&scene, format!("{base}\n[output]\n{extra}")).unwrap();
        let o = bin().args(["check", scene.to_str().unwrap()]).output().unwrap();
        assert_eq!(o.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&o.stderr).contains(field));
    }
}
