//! The beam statistics study: on fig. 2 with `[support]` the impact power
//! agrees across time steps within its interval while the impacts per
//! period (chatter counted as separate impacts) and the RMS contact force
//! change with dt; the CSV marks them; bad windows and batch counts are
//! refused naming the option.

use signorini_studies::{beam_statistics, Column, StudyError};

fn col_f(t: &signorini_studies::Table, name: &str) -> Vec<f64> {
    match t.column(name) {
        Some(Column::F64(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

fn col_s(t: &signorini_studies::Table, name: &str) -> Vec<String> {
    match t.column(name) {
        Some(Column::Str(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

#[test]
fn converging_and_step_dependent_statistics_of_fig2() {
    let out = std::env::temp_dir().join(format!("signorini-studies-beam-stats-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let cfg = beam_statistics::Config { out: out.clone(), dts: vec![5e-5, 1e-5], elements: vec![19], transient: 5.0, window: 40.0, batches: 10, ..Default::default() };
    let o = beam_statistics::run(&cfg, &|_, _| {}).unwrap();
    let t = &o.tables[0];
    let head: Vec<&str> = t.columns.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(head, ["scene", "dt", "elements", "statistic", "mean", "ci_low", "ci_high", "finest_mean", "rel_diff", "within_ci", "kind", "scheme", "wall_s"]);
    assert!(out.join("statistics.svg").exists());
    let (stat, kind, dt) = (col_s(t, "statistic"), col_s(t, "kind"), col_f(t, "dt"));
    let (mean, lo, hi, rel) = (col_f(t, "mean"), col_f(t, "ci_low"), col_f(t, "ci_high"), col_f(t, "rel_diff"));
    let row = |s: &str, d: f64| (0..stat.len()).find(|&i| stat[i] == s && dt[i] == d).unwrap_or_else(|| panic!("{s} at {d}"));
    for (s, dep) in beam_statistics::STATISTICS {
        let i = row(s, 5e-5);
        assert_eq!(kind[i], if dep { "step-dependent" } else { "converges" }, "{s}");
        assert!(lo[i] <= mean[i] && mean[i] <= hi[i], "{s}: {} [{}, {}]", mean[i], lo[i], hi[i]);
    }
    // Impact power: within a few per cent and within the intervals.
    let (p5, p1) = (row("impact_power", 5e-5), row("impact_power", 1e-5));
    assert!(rel[p5].abs() < 0.1 && lo[p5] <= hi[p1] && lo[p1] <= hi[p5], "impact power {} against {}", mean[p5], mean[p1]);
    assert!((25.0..45.0).contains(&mean[p1]), "impact power {}", mean[p1]);
    // Impacts per period: about 140 against 313, far outside the intervals.
    let (n5, n1) = (row("impacts_per_period", 5e-5), row("impacts_per_period", 1e-5));
    assert!(hi[n5] < lo[n1] && mean[n1] / mean[n5] > 1.8, "impacts per period {} against {}", mean[n5], mean[n1]);
    let (f5, f1) = (row("rms_force", 5e-5), row("rms_force", 1e-5));
    assert!(hi[f5] < lo[f1], "rms force {} against {}", mean[f5], mean[f1]);
    let _ = std::fs::remove_dir_all(&out);
}

#[track_caller]
fn refused(cfg: beam_statistics::Config, want: &str, range: &str) {
    let out = cfg.out.clone();
    match beam_statistics::run(&cfg, &|_, _| {}) {
        Err(StudyError::Config { field, message }) => {
            let (field, message) = (signorini_studies::options::Spelling::Flag.spell(&field), message.render(signorini_studies::options::Spelling::Flag));
            assert_eq!(field, want, "{message}");
            assert!(message.starts_with(want) && message.contains(range), "{message}");
        }
        other => panic!("expected a Config error on {want}, got {:?}", other.map(|o| o.report)),
    }
    assert!(!out.exists(), "{} was created", out.display());
}

#[test]
fn short_windows_and_few_batches_are_refused() {
    let out = std::env::temp_dir().join(format!("signorini-studies-bad-beam-stats-{}", std::process::id()));
    let base = || beam_statistics::Config { out: out.clone(), ..Default::default() };
    for w in [9.99, 0.0, -5.0, f64::NAN, f64::INFINITY] {
        refused(beam_statistics::Config { window: w, ..base() }, "--window", "[10, 100000] forcing periods");
    }
    for b in [0, 1, 9] {
        refused(beam_statistics::Config { batches: b, ..base() }, "--batches", "[10, 1000]");
    }
    refused(beam_statistics::Config { scenes: vec!["fig9".into()], ..base() }, "--scenes", "fig2-support");
    refused(beam_statistics::Config { dts: vec![-1e-5], ..base() }, "--dts", "(0, 1e-3]");
    refused(beam_statistics::Config { episode_gap: -1.0, ..base() }, "--episode-gap", "[0, 1]");
}

/// Issue 31 §3: one time step (nothing to compare against dt) computed
/// everything, then failed on the plot ("nothing to plot") without a report.
/// Now the study finishes: the report and the CSV, no `statistics.svg`
/// (an earlier run's is removed), and a note saying why.
#[test]
fn one_time_step_gives_the_report_and_skips_the_plot() {
    let out = std::env::temp_dir().join(format!("signorini-studies-beam-stats-one-dt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("statistics.svg"), "<svg>an earlier run's</svg>").unwrap();
    let cfg = beam_statistics::Config { out: out.clone(), dts: vec![5e-5], elements: vec![19], transient: 1.0, window: 10.0, batches: 10, ..Default::default() };
    let o = beam_statistics::run(&cfg, &|_, _| {}).expect("one dt is a complete study");
    // Every statistic once, each its own finest level.
    assert_eq!(col_s(&o.tables[0], "statistic").len(), beam_statistics::STATISTICS.len());
    assert!(o.report.contains("| impact_power | converges | 5e-5 | 19 |") && o.report.contains("| finest |"), "{}", o.report);
    assert!(out.join("statistics.csv").exists());
    assert!(!out.join("statistics.svg").exists(), "a stale statistics.svg was left");
    assert!(o.notes.iter().any(|n| n.contains("statistics.svg not drawn")), "{:?}", o.notes);
    let _ = std::fs::remove_dir_all(&out);
}

/// Issue 31 §9: a level whose interval does not overlap the finest's is no
/// evidence of convergence. Intervals written here by hand.
#[test]
fn a_verdict_needs_overlapping_intervals() {
    use signorini_run::stats::Interval;
    let iv = |mean: f64, half: f64| Interval { mean, low: mean - half, high: mean + half, std_err: half / 2.09, batches: 20 };
    // The reference's impact power: 36.04 ± 1.07 at dt = 5e-5, J = 38
    // against the finest 33.03 ± 1.08: apart.
    let (coarse, finest) = (iv(36.04, 1.07), iv(33.03, 1.08));
    assert_eq!(beam_statistics::verdict(&coarse, &finest, false, false), "undecided (intervals apart)");
    assert_eq!(beam_statistics::verdict(&coarse, &finest, true, false), "differs (intervals apart; step-dependent)");
    // 34.47 ± 1.13 overlaps 33.03 ± 1.08 (34.11 > 33.34).
    assert_eq!(beam_statistics::verdict(&iv(34.47, 1.13), &finest, false, false), "agrees (intervals overlap)");
    // Touching intervals overlap; the finest is itself.
    assert_eq!(beam_statistics::verdict(&iv(35.0, 0.5), &iv(34.0, 0.5), false, false), "agrees (intervals overlap)");
    assert_eq!(beam_statistics::verdict(&finest, &finest, false, true), "finest");
}
