//! The work–precision report (issue 31 §9–§11): no verdict about reduced
//! models when none was run, the timing columns (median and range of
//! `--repeats` runs) beside deterministic ones, and the flags `--repeats`
//! and `--reference` refused with the reason.

use signorini_studies::{work_precision, Column, StudyError};

/// A small study: the bars at m = 10, 20, the beam at the paper's step
/// against a reference at 1e-5 s over 0.1 s, no reduced model.
fn small(name: &str, repeats: usize) -> work_precision::Config {
    let out = std::env::temp_dir().join(format!("signorini-studies-wp-report-{name}-{}", std::process::id()));
    work_precision::Config {
        out,
        levels: vec![10, 20],
        degrees: vec![],
        modes: vec![],
        beam_dts: vec![5e-5],
        beam_ref_dt: 1e-5,
        beam_window: 0.05,
        beam_t_end: 0.1,
        beam_stat_dts: vec![],
        repeats,
        ..Default::default()
    }
}

/// Every column but the timing ones, as text.
fn non_timing(t: &signorini_studies::Table) -> Vec<(String, String)> {
    let timing = ["wall_s", "setup_s", "step_s", "step_s_min", "step_s_max", "repeats"];
    t.columns.iter().filter(|(name, _)| !timing.contains(&name.as_str())).map(|(name, c)| (name.clone(), format!("{c:?}"))).collect()
}

#[test]
fn no_reduced_model_no_verdict_and_timings_apart() {
    let (a, b) = (small("a", 1), small("b", 3));
    let oa = work_precision::run(&a, &|_, _| {}).unwrap();
    let ob = work_precision::run(&b, &|_, _| {}).unwrap();
    // §9: the paragraph on the paper's step is there, without a reduced-model verdict.
    for o in [&oa, &ob] {
        assert!(o.report.contains("The full model at the paper's dt = 5e-5 s"), "{}", o.report);
        assert!(!o.report.contains("No reduced model") && !o.report.contains("best: -"), "{}", o.report);
        assert!(o.report.contains("Timings on this machine"), "{}", o.report);
    }
    // The timing columns: every timed row's median within its range, its
    // count the configured one; the rest identical between the runs.
    let t = &ob.tables[0];
    let f = |c: &str| match t.column(c) {
        Some(Column::F64(v)) => v.clone(),
        other => panic!("{c}: {other:?}"),
    };
    let n = match t.column("repeats") {
        Some(Column::I64(v)) => v.clone(),
        other => panic!("repeats: {other:?}"),
    };
    let (med, lo, hi, wall) = (f("step_s"), f("step_s_min"), f("step_s_max"), f("wall_s"));
    assert!(!med.is_empty());
    for i in 0..med.len() {
        assert!(lo[i] <= med[i] && med[i] <= hi[i] && wall[i] == med[i] && n[i] == 3, "row {i}: {} [{}, {}] x{}", med[i], lo[i], hi[i], n[i]);
    }
    assert_eq!(non_timing(&oa.tables[0]), non_timing(t), "a column other than the timings depends on the timings");
    for c in [&a, &b] {
        let _ = std::fs::remove_dir_all(&c.out);
    }
}

#[track_caller]
fn refused(r: Result<work_precision::Output, StudyError>, flag: &str, says: &str) {
    match r {
        Err(StudyError::Config { field, message }) => {
            let (field, message) = (signorini_studies::options::Spelling::Flag.spell(&field), message.render(signorini_studies::options::Spelling::Flag));
            assert_eq!(field, flag, "{message}");
            assert!(message.contains(says), "{message}");
        }
        other => panic!("expected a refusal of {flag}, got {:?}", other.map(|o| o.report)),
    }
}

#[test]
fn repeats_and_reference_are_refused_with_the_reason() {
    for r in [0, 101] {
        let c = small("bad", r);
        refused(work_precision::run(&c, &|_, _| {}), "--repeats", "allowed integers in [1, 100]");
        assert!(!c.out.exists());
    }
    match "exact".parse::<work_precision::BeamReference>() {
        Err(StudyError::Config { field, message }) => {
            let (field, message) = (signorini_studies::options::Spelling::Flag.spell(&field), message.render(signorini_studies::options::Spelling::Flag));
            assert_eq!(field, "--reference");
            assert!(message.contains("the beam has no closed form") && message.contains("allowed fine-step") && message.contains("event-driven"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!("fine-step".parse::<work_precision::BeamReference>().ok(), Some(work_precision::BeamReference::FineStep));
    assert_eq!("event-driven".parse::<work_precision::BeamReference>().ok(), Some(work_precision::BeamReference::EventDriven));
}
