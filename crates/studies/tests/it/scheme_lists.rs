//! The `schemes` option of the studies that loop over every scheme and mass
//! (stress, beam statistics, work–precision): the given schemes run, each
//! with the masses it takes, and nothing else; schemes without a time step
//! or with one mass treatment only are refused naming the option.

use signorini_studies::{beam_statistics, stress, work_precision, Column, StudyError};
use std::path::PathBuf;

fn temp_out(name: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("signorini-scheme-lists-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    p
}

fn strs(t: &signorini_studies::Table, name: &str) -> Vec<String> {
    match t.column(name) {
        Some(Column::Str(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

fn floats(t: &signorini_studies::Table, name: &str) -> Vec<f64> {
    match t.column(name) {
        Some(Column::F64(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

/// The rows are the given schemes' and only theirs: contact-stabilized with
/// the two masses whose contact node has mass (std, lumped), newmark-cn with
/// all seven, verlet-nitsche(10,0) with the lumped one only (θ ≠ 1), seven
/// dx/dt each, in that order. And contact-stabilized
/// dissipates (theory §7.9: without load or damping ΔE ≤ 0 at every step),
/// so its energy never exceeds the initial one.
#[test]
fn stress_runs_the_given_schemes_with_the_masses_they_take() {
    let out = temp_out("stress");
    let schemes = Some(vec!["contact-stabilized".parse().unwrap(), "newmark-cn".parse().unwrap(), "verlet-nitsche(10,0)".parse().unwrap()]);
    let cfg = stress::Config { out: out.clone(), steps: 400, elements: 8, seed: 3, schemes };
    let o = stress::run(&cfg, &|_, _| {}).expect("the study runs");
    let t = &o.tables[0];
    let (scheme, mass) = (strs(t, "scheme"), strs(t, "mass"));
    let mut want = Vec::new();
    // verlet-nitsche with θ ≠ 1 takes the lumped mass only.
    for (s, masses) in
        [("contact-stabilized", &["std", "lumped"][..]), ("newmark-cn", &["std", "lumped", "mod", "mod2", "mod3", "transfer", "singular"][..]), ("verlet-nitsche(10,0)", &["lumped"][..])]
    {
        for m in masses {
            want.extend(std::iter::repeat_n((s.to_string(), m.to_string()), stress::RATIOS.len()));
        }
    }
    let got: Vec<(String, String)> = scheme.into_iter().zip(mass).collect();
    assert_eq!(got, want);
    let growth = floats(t, "max_growth");
    for (i, g) in growth.iter().enumerate().take(2 * stress::RATIOS.len()) {
        assert!(*g <= 1.0 + 1e-6, "contact-stabilized row {i}: E/E0 up to {g}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// The reference (no time step) and a scheme of one mass treatment are
/// refused before anything is written, naming the option.
#[test]
fn stress_refuses_schemes_without_a_time_step_or_with_one_mass() {
    for bad in ["event-driven", "cd-taylor"] {
        let out = temp_out(&format!("stress-{bad}"));
        let cfg = stress::Config { out: out.clone(), schemes: Some(vec![bad.parse().unwrap()]), ..Default::default() };
        match stress::run(&cfg, &|_, _| {}) {
            Err(StudyError::Config { field, message }) => {
                let message = message.render(signorini_studies::options::Spelling::Flag);
                assert_eq!(field, "schemes", "{message}");
                assert!(message.starts_with(&format!("--schemes {bad}:")), "{message}");
            }
            other => panic!("{bad}: expected a refusal naming schemes, got {:?}", other.map(|o| o.report)),
        }
        assert!(!out.exists(), "{bad}: nothing is written");
    }
}

/// Beam statistics with `schemes`: the paper's scheme named by its call
/// (`ps(0,0.5)`) gives the default run's numbers (the scene's own
/// `contact = "projection"` is that scheme), a second scheme's rows are
/// compared with the first's finest level, and the `scheme` column names
/// each run's scheme.
#[test]
fn beam_statistics_compares_every_scheme_with_the_first_schemes_finest() {
    let base = |out: PathBuf, schemes| beam_statistics::Config { out, dts: vec![5e-5, 2.5e-5], elements: vec![19], transient: 2.0, window: 10.0, batches: 10, schemes, ..Default::default() };
    let (d, g) = (temp_out("bs-default"), temp_out("bs-given"));
    let own = beam_statistics::run(&base(d.clone(), None), &|_, _| {}).expect("the default runs");
    let given = Some(vec!["ps(0,0.5)".parse().unwrap(), "contact-stabilized".parse().unwrap()]);
    let two = beam_statistics::run(&base(g.clone(), given), &|_, _| {}).expect("the given schemes run");
    let (t1, t2) = (&own.tables[0], &two.tables[0]);
    let n = strs(t1, "statistic").len();
    assert_eq!(strs(t2, "statistic").len(), 2 * n);
    assert!(strs(t1, "scheme").iter().all(|s| s == "ps(0,0.5)"), "{:?}", strs(t1, "scheme"));
    let scheme = strs(t2, "scheme");
    assert!(scheme[..n].iter().all(|s| s == "ps(0,0.5)") && scheme[n..].iter().all(|s| s == "contact-stabilized"), "{scheme:?}");
    for col in ["mean", "ci_low", "ci_high", "finest_mean", "rel_diff"] {
        let (a, b) = (floats(t1, col), floats(t2, col));
        assert_eq!(a[..], b[..n], "{col}: the paper's scheme by name is the scene's own");
    }
    // The second scheme's finest_mean is the first's finest level (dt = 2.5e-5),
    // and its rel_diff is measured against it.
    let (mean, finest, rel, dt) = (floats(t2, "mean"), floats(t2, "finest_mean"), floats(t2, "rel_diff"), floats(t2, "dt"));
    let stat = strs(t2, "statistic");
    for i in n..2 * n {
        let first = (0..n).find(|&k| stat[k] == stat[i] && dt[k] == 2.5e-5).expect("the first scheme's finest row");
        assert_eq!(finest[i], mean[first], "row {i} ({})", stat[i]);
        let want = mean[i] / mean[first] - 1.0;
        assert!((rel[i] - want).abs() <= 1e-3 * want.abs().max(1e-9), "row {i}: rel_diff {} against {want}", rel[i]);
    }
    // A scheme that does not take the beam is refused naming the option.
    let h = temp_out("bs-hybrid");
    match beam_statistics::run(&base(h.clone(), Some(vec!["hybrid".parse().unwrap()])), &|_, _| {}) {
        Err(StudyError::Config { field, .. }) => assert_eq!(field, "schemes"),
        other => panic!("expected a refusal naming schemes, got {:?}", other.map(|o| o.report)),
    }
    assert!(!h.exists());
    for p in [d, g] {
        let _ = std::fs::remove_dir_all(p);
    }
}

/// Work–precision with `schemes`: the bar rows are the given schemes' (each
/// with the masses it takes) beside the Courant-one frontier rows, which
/// every run has; the reference is refused naming the option.
#[test]
fn work_precision_runs_the_given_schemes() {
    let out = temp_out("wp");
    let cfg = work_precision::Config {
        out: out.clone(),
        levels: vec![10, 20],
        degrees: vec![],
        modes: vec![],
        beam_dts: vec![],
        beam_stat_dts: vec![],
        repeats: 1,
        schemes: Some(vec!["contact-stabilized".parse().unwrap()]),
        ..Default::default()
    };
    let o = work_precision::run(&cfg, &|_, _| {}).expect("the study runs");
    let t = o.tables.iter().find(|t| t.file == "work_precision.csv").expect("work_precision.csv");
    let mut pairs: Vec<(String, String)> = strs(t, "scheme").into_iter().zip(strs(t, "mass")).collect();
    pairs.sort();
    pairs.dedup();
    let want: Vec<(String, String)> = [("cd-taylor", "lumped"), ("contact-stabilized", "lumped"), ("contact-stabilized", "std")].iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    assert_eq!(pairs, want);
    let cfg = work_precision::Config { out: out.clone(), schemes: Some(vec!["event-driven".parse().unwrap()]), ..Default::default() };
    match work_precision::run(&cfg, &|_, _| {}) {
        Err(StudyError::Config { field, .. }) => assert_eq!(field, "schemes"),
        other => panic!("expected a refusal naming schemes, got {:?}", other.map(|o| o.report)),
    }
    let _ = std::fs::remove_dir_all(&out);
}
