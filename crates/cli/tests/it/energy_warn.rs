//! `[output] energy_warn` end to end: a run whose energy grows past the
//! factor × its budget prints one warning on stderr with the factor and the
//! time, and the summary the largest E/budget; both are checked against the
//! energies of the run's own `series.csv` (no load, no damping: the budget
//! is E(0)). A conservative run prints no warning; bad factors are refused.

use std::path::Path;
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

fn run(dir: &Path, text: &str) -> Output {
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    bin().args(["run", p.to_str().unwrap(), "--out", dir.join("out").to_str().unwrap(), "--clean"]).output().unwrap()
}

fn scene(mass: &str, extra: &str) -> String {
    format!("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 100\nmass = \"{mass}\"\nscheme = \"newmark-cn\"\nratio = 1.0\nt_end = 3.0\n\n[output]\nplots = false\n{extra}")
}

/// `(t, E)` of every row of series.csv.
fn energies(dir: &Path) -> Vec<(f64, f64)> {
    let mut rd = csv::Reader::from_path(dir.join("out/series.csv")).unwrap();
    let h = rd.headers().unwrap().clone();
    let (it, ie) = (h.iter().position(|c| c == "energy_t").unwrap(), h.iter().position(|c| c == "energy").unwrap());
    rd.records().map(|r| r.unwrap()).filter(|r| !r[ie].is_empty()).map(|r| (r[it].parse().unwrap(), r[ie].parse().unwrap())).collect()
}

/// The number after `key` in `text`.
fn number_after(text: &str, key: &str) -> f64 {
    let i = text.find(key).unwrap_or_else(|| panic!("{key:?} not in {text:?}")) + key.len();
    let s: String = text[i..].chars().take_while(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | '-' | '+')).collect();
    s.parse().unwrap_or_else(|e| panic!("{s:?} after {key:?}: {e}"))
}

#[test]
fn a_growing_run_warns_once_with_the_factor_and_the_time() {
    for factor in [2.0, 3.0] {
        let dir = tempfile::tempdir().unwrap();
        let extra = if factor == 2.0 { String::new() } else { format!("energy_warn = {factor:?}\n") };
        let o = run(dir.path(), &scene("std", &extra));
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (err, out) = (String::from_utf8_lossy(&o.stderr), String::from_utf8_lossy(&o.stdout));
        let e = energies(dir.path());
        let e0 = e[0].1;
        let first = e.iter().find(|(_, x)| *x > factor * e0).expect("newmark-cn std doubles its energy by t = 3");
        let max = e.iter().map(|(_, x)| x / e0).fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(err.matches("warning:").count(), 1, "{err}");
        assert!(err.contains(&format!("exceeds {factor} × its budget from t = ")), "{err}");
        let t = number_after(&err, "its budget from t = ");
        assert!((t - first.0).abs() <= 1e-9, "warned at t = {t}, series says {}", first.0);
        assert!((number_after(&err, "E/budget ") - first.1 / e0).abs() <= 1e-5 * first.1 / e0, "{err}");
        // The summary's largest E/budget (6 digits) against series.csv (13 digits).
        let got = number_after(&out, "largest E/budget ");
        assert!((got - max).abs() <= 1e-5 * max, "summary {got}, series {max}: {out}");
        assert!(out.contains(&format!("warn above {factor})")), "{out}");
    }
}

#[test]
fn a_conservative_run_does_not_warn() {
    // newmark-cn with a massless contact node: the energy never rises above E(0).
    let dir = tempfile::tempdir().unwrap();
    let o = run(dir.path(), &scene("mod", ""));
    assert!(o.status.success());
    let (err, out) = (String::from_utf8_lossy(&o.stderr), String::from_utf8_lossy(&o.stdout));
    assert!(!err.contains("warning"), "{err}");
    let e = energies(dir.path());
    let max = e.iter().map(|(_, x)| x / e[0].1).fold(f64::NEG_INFINITY, f64::max);
    assert!((number_after(&out, "largest E/budget ") - max).abs() <= 1e-5, "{out}");
    assert!(max <= 1.0 + 1e-12);
}

#[test]
fn bad_factors_are_refused_naming_the_key_and_range() {
    for bad in ["1.0", "1", "0.5", "-2.0", "nan", "inf", "-inf"] {
        let dir = tempfile::tempdir().unwrap();
        let o = run(dir.path(), &scene("mod", &format!("energy_warn = {bad}\n")));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{bad}: {err}");
        assert!(err.contains("output.energy_warn") && err.contains("finite and > 1"), "{bad}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}
