//! The `signorini` command end to end: scenes run in a temporary folder, CSV
//! checked; bad inputs give the right exit code and a message naming the
//! field (the scene reader's fuzzing is crates/fuzz/tests/fuzz.rs).

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/scenes")
}

fn write_scene(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn bar_scene_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = bin().args(["run", scenes().join("bar-dirichlet.toml").to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut rd = csv::Reader::from_path(out.join("series.csv")).unwrap();
    let header: Vec<String> = rd.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(header, ["n", "t", "u_contact", "v_contact", "lambda_t", "lambda", "energy_t", "energy", "u_contact_exact", "lambda_exact", "energy_exact"]);
    let rows: Vec<csv::StringRecord> = rd.records().collect::<Result<_, _>>().unwrap();
    assert_eq!(rows.len(), 2401); // levels 0..=2400 (T = 3, dt = 1/800)
                                  // Exact columns: u(0, 0) = 1/2, E = 1/8; the node never goes below the obstacle.
    assert_eq!(&rows[0][8], "5.000000000000e-1");
    for r in &rows {
        assert!(r[2].parse::<f64>().unwrap() >= 0.0);
        assert_eq!(r[10].parse::<f64>().unwrap(), 0.125);
    }
    // The velocity column is the backward difference of u_contact.
    let (u1, u2, t1, t2): (f64, f64, f64, f64) = (rows[99][2].parse().unwrap(), rows[100][2].parse().unwrap(), rows[99][1].parse().unwrap(), rows[100][1].parse().unwrap());
    let v: f64 = rows[100][3].parse().unwrap();
    assert!((v - (u2 - u1) / (t2 - t1)).abs() <= 1e-9 * (1.0 + v.abs()), "{v}");
    assert_eq!(&rows[0][3], "");
    // The norms equal the stored values of the independent reference
    // (tests/support/independent_bar.rs, not the library; it agrees with the
    // library to 9e-10 relative, and norms.csv has 11 significant digits):
    // every norm column, to 1e-8 relative.
    let stored = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/reference/independent/bar-dirichlet-m80.csv");
    let mut sr = csv::ReaderBuilder::new().comment(Some(b'#')).from_path(stored).unwrap();
    let sh = sr.headers().unwrap().clone();
    let want = sr.records().map(Result::unwrap).find(|r| &r[0] == "newmark-cn" && &r[1] == "mod").expect("newmark-cn/mod in the stored values");
    let mut nr = csv::Reader::from_path(out.join("norms.csv")).unwrap();
    let nh = nr.headers().unwrap().clone();
    let got = nr.records().next().unwrap().unwrap();
    for (i, col) in sh.iter().enumerate().skip(6) {
        let j = nh.iter().position(|c| c == col).unwrap_or_else(|| panic!("norms.csv has no column {col}"));
        let (g, w): (f64, f64) = (got[j].parse().unwrap(), want[i].parse().unwrap());
        assert!((g - w).abs() <= 1e-8 * w.abs(), "{col}: CLI {g:e}, independent reference {w:e}");
    }
    // Snapshots every 400 steps: levels 0, 400, …, 2400, 81 nodes each.
    let snaps = csv::Reader::from_path(out.join("snapshots.csv")).unwrap().records().count();
    assert_eq!(snaps, 7 * 81);
    for svg in ["u_contact.svg", "lambda.svg", "energy.svg"] {
        assert!(std::fs::read_to_string(out.join(svg)).unwrap().starts_with("<svg"), "{svg}");
    }
}

#[test]
fn beam_scene_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("beam");
    let o = bin().args(["run", scenes().join("beam-fig2.toml").to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows: Vec<csv::StringRecord> = csv::Reader::from_path(out.join("series.csv")).unwrap().records().collect::<Result<_, _>>().unwrap();
    assert_eq!(rows.len(), 4001); // every 10th of 40 000 steps, plus level 0
    assert!(rows.iter().all(|r| r[2].parse::<f64>().unwrap().abs() <= 0.1));
    assert!(out.join("tip.svg").exists());
}

#[test]
fn every_shipped_scene_is_valid() {
    for e in std::fs::read_dir(scenes()).unwrap() {
        let p = e.unwrap().path();
        let o = bin().args(["check", p.to_str().unwrap()]).output().unwrap();
        assert!(o.status.success(), "{}: {}", p.display(), String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stdout).contains("stability"));
    }
}

/// (scene text, exit code, words the message must contain)
fn check_rejects(text: &str, code: i32, words: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let p = write_scene(dir.path(), text);
    let o = bin().args(["run", p.to_str().unwrap(), "--out", dir.path().join("o").to_str().unwrap()]).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{text}\n{err}");
    for w in words {
        assert!(err.contains(w), "message {err:?} lacks {w:?}");
    }
}

#[test]
fn bad_inputs_name_the_field_and_range() {
    let ok = "[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\n";
    check_rejects("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\ncolour = 3\n", 2, &["unknown field", "colour", "line 5"]);
    check_rejects("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\ndt = -0.1\n", 2, &["bar.dt", "> 0"]);
    check_rejects("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 1\nratio = 10.0\n", 2, &["bar.elements", ">= 2"]);
    check_rejects("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\nscheme = \"hybrid\"\n", 2, &["bar.mass", "massless"]);
    // cd-taylor takes the lumped mass only (std: not diagonal; mod: massless contact node).
    check_rejects("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 1.0\nscheme = \"cd-taylor\"\n", 2, &["bar.mass", "lumped", "got std"]);
    check_rejects("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 1.0\nscheme = \"cd-taylor\"\nmass = \"mod\"\n", 2, &["bar.mass", "lumped", "got mod"]);
    check_rejects("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\nscheme = \"ps(1.5)\"\n", 2, &["bar.scheme", "[0, 1]"]);
    check_rejects("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\nlength = 2.0\n", 2, &["bar.length", "benchmark"]);
    check_rejects("[bar]\nelements = 10\ndt = 0.01\ninitial_displacement = \"1 - \"\n", 2, &["bar.initial_displacement"]);
    check_rejects("[bar]\nelements = 10\ndt = 0.01\ninitial_displacement = -1.0\n", 2, &["initial u(0)", "obstacle"]);
    check_rejects("[beam]\nscene = \"fig8\"\nbeta = 0.1\ndt = 2e-5\n", 2, &["beam.dt", "stability limit", "1.600196e-5", "β = 0.1 < 1/4"]);
    check_rejects("[beam]\ncontact = \"glue\"\n", 2, &["beam.contact", "projection"]);
    check_rejects("[output]\nevery = 1\n", 2, &["[bar]", "[beam]"]);
    check_rejects(&format!("{ok}[output]\nevery = 0\n"), 2, &["output.every", ">= 1"]);
    check_rejects("[bar\n", 2, &["scene file", "line 1"]);
    // A missing scene file is bad input too (issue 22 §11; it was exit 1).
    let o = bin().args(["run", "/nonexistent/scene.toml"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn list_and_check_print_ranges_and_limits() {
    let o = bin().arg("list").output().unwrap();
    let s = String::from_utf8_lossy(&o.stdout);
    for w in ["newmark-cn", "hybrid", "mod3", "bar-neumann-gravity", "fig8", "θ ∈ [1/2, 1]"] {
        assert!(s.contains(w), "list lacks {w}");
    }
    // A family without presets says what it takes under its call, as the
    // presets do (the beam line points at "a family marked beam above"):
    // contact-stabilized Newmark projects in the mass norm (a massive node),
    // has no impact law, takes damping and the beam (theory §4.6.6).
    let block: Vec<&str> = s.lines().skip_while(|l| l.trim() != "contact-stabilized").take(3).collect();
    assert_eq!(block.len(), 3, "{s}");
    assert_eq!(block[2].trim(), "[implicit, std or lumped only, damping, time-dependent load, several contacts, beam]", "{s}");
    let o = bin().args(["check", scenes().join("beam-fig8.toml").to_str().unwrap()]).output().unwrap();
    let s = String::from_utf8_lossy(&o.stdout);
    // β = 1/4: no limit; the paper's sufficient condition is reported as what it is.
    assert!(s.contains("unconditionally stable (β = 0.25 >= 1/4)") && s.contains("1.752926e-5 s: not a limit"), "{s}");
    // An explicit bar scheme: the exact CFL limit (lumped P1 bar, m = 10, spring 10 c²/h).
    let dir = tempfile::tempdir().unwrap();
    let p = write_scene(dir.path(), "[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 0.5\nmass = \"lumped\"\nscheme = \"penalty-cd\"\n");
    let o = bin().args(["check", p.to_str().unwrap()]).output().unwrap();
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(2), "beyond the limit: refused by check as by run");
    assert!(e.contains("bar.dt") && e.contains("4.254380e-2") && e.contains("penalty spring"), "{e}");
    // Below it, check reports the limit.
    let p = write_scene(dir.path(), "[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 3.0\nmass = \"lumped\"\nscheme = \"penalty-cd\"\n");
    let s = String::from_utf8_lossy(&bin().args(["check", p.to_str().unwrap()]).output().unwrap().stdout).to_string();
    assert!(s.contains("exact limit dt < 4.254380e-2") && s.contains("below it"), "{s}");
}

// Interrupted and killed runs: tests/it/reliability.rs; the reader's fuzzing: crates/fuzz/tests/fuzz.rs.

/// `bar-mirrored` through the CLI: norms.csv's `m` is the study's level (m
/// elements per half-bar, 2m in all), and its L²-type norms are √2 times
/// the single-contact bar's stored study values at the same level
/// (data/reference/bar-dirichlet, written by the convergence study on one
/// contact: not this code path).
#[test]
fn bar_mirrored_scene_reports_the_study_level_and_the_mirror_norms() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = write_scene(dir.path(), "[bar]\nbenchmark = \"bar-mirrored\"\nelements = 20\nmass = \"mod\"\nscheme = \"newmark-cn\"\nratio = 10.0\nt_end = 3.0\n");
    let o = bin().args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut nr = csv::Reader::from_path(out.join("norms.csv")).unwrap();
    let nh = nr.headers().unwrap().clone();
    let got = nr.records().next().unwrap().unwrap();
    assert_eq!(&got[0], "20", "norms.csv m");
    let stored = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/reference/bar-dirichlet/newmark-cn_mod.csv");
    let mut sr = csv::Reader::from_path(stored).unwrap();
    let sh = sr.headers().unwrap().clone();
    let want = sr.records().map(Result::unwrap).find(|r| &r[0] == "20").expect("level 20");
    for col in ["linf_l2_u", "l2_l2_u"] {
        let (i, j) = (sh.iter().position(|c| c == col).unwrap(), nh.iter().position(|c| c == col).unwrap());
        let (w, g): (f64, f64) = (want[i].parse().unwrap(), got[j].parse().unwrap());
        assert!((g / (std::f64::consts::SQRT_2 * w) - 1.0).abs() <= 1e-8, "{col}: mirrored {g:e}, √2 × single {:e}", std::f64::consts::SQRT_2 * w);
    }
}
