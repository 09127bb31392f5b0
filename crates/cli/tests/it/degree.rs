//! The scene key `bar.degree` (docs/theory.md §2.1.4): out of range or with a
//! mass treatment P2/P3 do not define, a typed error naming the key; in
//! range, it reaches the problem — a P2 benchmark scene's norms.csv holds
//! the norms of the run library's P2 level (signorini-run's own tests check
//! those against closed forms and rates), not the P1 ones, and its
//! snapshots have the `2m + 1` nodes.

use signorini_fem::BarMass;
use signorini_run::study::{run_level, Level};
use signorini_run::Benchmark;
use std::process::Command;

fn scene(extra: &str, mass: &str) -> String {
    format!("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nmass = \"{mass}\"\nscheme = \"newmark-cn\"\nratio = 10.0\nt_end = 1.0\n{extra}\n[output]\nevery = 1\nsnapshots_every = 100\nplots = false\n")
}

fn run_scene(text: &str) -> (std::process::Output, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("scene.toml");
    std::fs::write(&p, text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_signorini")).args(["run", p.to_str().unwrap(), "--out", dir.path().join("o").to_str().unwrap()]).output().unwrap();
    (o, dir)
}

#[test]
fn bad_degree_names_bar_degree() {
    for (extra, mass, words) in [
        ("degree = 0", "std", vec!["bar.degree", "1, 2 or 3"]),
        ("degree = 4", "mod", vec!["bar.degree", "1, 2 or 3"]),
        ("degree = 2", "transfer", vec!["bar.mass", "degree 2", "std, lumped, mod or mod1"]),
    ] {
        let (o, _dir) = run_scene(&scene(extra, mass));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra} {mass}: {err}");
        for w in words {
            assert!(err.contains(w), "{extra} {mass}: message {err:?} lacks {w:?}");
        }
    }
}

#[test]
fn degree_reaches_the_problem() {
    let (o, dir) = run_scene(&scene("degree = 2", "mod"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut nr = csv::Reader::from_path(dir.path().join("o/norms.csv")).unwrap();
    let h = nr.headers().unwrap().clone();
    let row = nr.records().next().unwrap().unwrap();
    let got: f64 = row[h.iter().position(|c| c == "l2_l2_u").unwrap()].parse().unwrap();
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(1.0).unwrap();
    let level = |k| run_level(&Level::new(b, "newmark-cn".parse().unwrap(), BarMass::Mod, 10, 10.0, 1.0).with_degree(k), exact.as_ref()).unwrap().norms.l2_l2_u;
    let (p2, p1) = (level(2), level(1));
    assert!((got - p2).abs() <= 1e-9 * p2, "norms.csv {got:e}, P2 level {p2:e} (P1: {p1:e})");
    assert!((p1 - p2).abs() > 1e-3 * p2, "P1 and P2 must differ for this test to see the key: {p1:e} {p2:e}");
    // Snapshots: 21 nodes (clamped end included) per snapshot.
    let snaps = std::fs::read_to_string(dir.path().join("o/snapshots.csv")).unwrap();
    let first: Vec<&str> = snaps.lines().skip(1).filter(|l| l.starts_with("0,")).collect();
    assert_eq!(first.len(), 21, "{}", &snaps[..snaps.len().min(400)]);
}
