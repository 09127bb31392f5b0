//! Bad input to every study's `Config`: a typed `StudyError::Config` naming
//! the option as `cargo xtask` spells it, from `validate` and from `run`,
//! before anything is written (the output folder is not even created).

use signorini_studies::{beam, convergence, obstacles, oscillator, stress, weighted, work_precision, StudyError};
use std::path::PathBuf;

/// A folder that does not exist (and must still not exist after the refusal).
fn nowhere(name: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("signorini-studies-bad-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    p
}

#[track_caller]
fn assert_field<T: std::fmt::Debug>(r: Result<T, StudyError>, want: &str, out: &std::path::Path) {
    match r {
        Err(StudyError::Config { field, message }) => {
            let (field, message) = (signorini_studies::options::Spelling::Flag.spell(&field), message.render(signorini_studies::options::Spelling::Flag));
            assert_eq!(field, want, "{message}");
            // Today's messages: `--t-end 3: allowed ...`, or the sweep's own
            // `invalid levels = 0: allowed ...` (convergence keeps it).
            assert!(message.contains(want.trim_start_matches("--")), "the message names the option: {message}");
        }
        other => panic!("expected a Config error on {want}, got {other:?}"),
    }
    assert!(!out.exists(), "{} was created", out.display());
}

const NO_PROGRESS: &(dyn Fn(u64, u64) + Sync) = &|_, _| {};

#[test]
fn convergence_refuses_empty_levels_and_a_zero_ratio() {
    let out = nowhere("convergence");
    let cfg = convergence::Config { levels: vec![], out: Some(out.clone()), ..Default::default() };
    assert_field(cfg.validate(), "--levels", &out);
    assert_field(convergence::run(&cfg, NO_PROGRESS).map(|_| ()), "--levels", &out);
    // Issue 22 §11: the message starts with the flag as typed.
    let cfg = convergence::Config { levels: vec![1, 2], out: Some(out.clone()), ..Default::default() };
    match convergence::run(&cfg, NO_PROGRESS) {
        Err(StudyError::Config { message, .. }) => assert!(message.render(signorini_studies::options::Spelling::Flag).starts_with("--levels 1: allowed every m >= 2"), "{message}"),
        other => panic!("levels 1 accepted: {:?}", other.map(|o| o.out)),
    }
    let cfg = convergence::Config { ratio: Some(0.0), out: Some(out.clone()), ..Default::default() };
    assert_field(convergence::run(&cfg, NO_PROGRESS).map(|_| ()), "--ratio", &out);
    assert_field(convergence::parse_norms("l2"), "--norms", &out);
    assert_field(signorini_studies::parse_schemes(&["newmark(0.25".to_string()]), "--schemes", &out);
    assert_field(signorini_studies::parse_masses(&["heavy".to_string()]), "--masses", &out);
}

#[test]
fn weighted_refuses_a_horizon_before_the_second_impact() {
    let out = nowhere("weighted");
    let cfg = weighted::Config { out: out.clone(), t_end: 3.0 };
    assert_field(weighted::run(&cfg, NO_PROGRESS).map(|_| ()), "--t-end", &out);
    assert_field(weighted::Config { out: out.clone(), t_end: f64::NAN }.validate(), "--t-end", &out);
}

#[test]
fn beam_refuses_an_unknown_scene_and_a_zero_penalty_dt() {
    let out = nowhere("beam");
    let cfg = beam::Config { out: out.clone(), scenes: vec!["fig9".into()], ..Default::default() };
    assert_field(beam::run(&cfg, NO_PROGRESS).map(|_| ()), "--scenes", &out);
    let cfg = beam::Config { out: out.clone(), penalty_dts: vec![5e-6, 0.0], ..Default::default() };
    assert_field(beam::run(&cfg, NO_PROGRESS).map(|_| ()), "--penalty-dts", &out);
}

#[test]
fn obstacles_refuses_a_zero_gap_and_one_dt() {
    let out = nowhere("obstacles");
    let cfg = obstacles::Config { out: out.clone(), gap: 0.0, ..Default::default() };
    assert_field(obstacles::run(&cfg, NO_PROGRESS).map(|_| ()), "--gap", &out);
    let cfg = obstacles::Config { out: out.clone(), dts: vec![1e-4], ..Default::default() };
    assert_field(cfg.validate(), "--dts", &out);
}

#[test]
fn oscillator_refuses_empty_dts_and_a_negative_frequency() {
    let out = nowhere("oscillator");
    let cfg = oscillator::Config { out: out.clone(), dts: vec![], ..Default::default() };
    assert_field(oscillator::run(&cfg, NO_PROGRESS).map(|_| ()), "--dts", &out);
    let cfg = oscillator::Config { out: out.clone(), omegas: vec![2.0, -1.0], ..Default::default() };
    assert_field(cfg.validate(), "--omegas", &out);
    // Issue 31 §3: Ω = 3 has no admissible period-1 orbit, which the study
    // found only after every run (then failed, its folder written); now
    // refused before any.
    let cfg = oscillator::Config { out: out.clone(), omegas: vec![2.0, 3.0], dts: vec![1e-3], ..Default::default() };
    assert_field(oscillator::run(&cfg, NO_PROGRESS).map(|_| ()), "--omegas", &out);
}

#[test]
fn work_precision_refuses_a_level_below_two() {
    let out = nowhere("wp");
    let cfg = work_precision::Config { out: out.clone(), levels: vec![1, 10], ..Default::default() };
    assert_field(work_precision::run(&cfg, NO_PROGRESS).map(|_| ()), "--levels", &out);
}

/// The frontier's options: a degree other than 2 or 3, zero modes, a beam
/// step below twice the reference's or beyond the window, a window beyond
/// the horizon, a reference step with too many steps, a horizon of zero.
#[test]
fn work_precision_refuses_bad_frontier_options() {
    let out = nowhere("wp-frontier");
    let base = work_precision::Config { out: out.clone(), ..Default::default() };
    let cases: Vec<(work_precision::Config, &str)> = vec![
        (work_precision::Config { degrees: vec![2, 4], ..base.clone() }, "--degrees"),
        (work_precision::Config { degrees: vec![1], ..base.clone() }, "--degrees"),
        (work_precision::Config { modes: vec![0], ..base.clone() }, "--modes"),
        (work_precision::Config { beam_dts: vec![4e-7], ..base.clone() }, "--beam-dts"),
        (work_precision::Config { beam_dts: vec![0.2], ..base.clone() }, "--beam-dts"),
        (work_precision::Config { beam_dts: vec![], reference: work_precision::BeamReference::EventDriven, ..base.clone() }, "--reference"),
        (work_precision::Config { beam_dts: vec![f64::NAN], ..base.clone() }, "--beam-dts"),
        (work_precision::Config { beam_window: 2.0, ..base.clone() }, "--beam-window"),
        (work_precision::Config { beam_ref_dt: 1e-9, ..base.clone() }, "--beam-ref-dt"),
        (work_precision::Config { beam_ref_dt: -1.0, ..base.clone() }, "--beam-ref-dt"),
        (work_precision::Config { beam_t_end: 0.0, ..base.clone() }, "--beam-t-end"),
        (work_precision::Config { beam_t_end: f64::INFINITY, ..base.clone() }, "--beam-t-end"),
        // The beam's impact-power rows (issue 23 §5): a step beyond 1e-3 s,
        // a window under ten periods, a reference not below the steps.
        (work_precision::Config { beam_stat_dts: vec![2e-3], ..base.clone() }, "--beam-stat-dts"),
        (work_precision::Config { beam_stat_window: 9.0, ..base.clone() }, "--beam-stat-window"),
        (work_precision::Config { beam_stat_ref_dt: 5e-5, ..base.clone() }, "--beam-stat-ref-dt"),
        (work_precision::Config { beam_stat_ref_dt: f64::NAN, ..base.clone() }, "--beam-stat-ref-dt"),
    ];
    for (cfg, flag) in cases {
        assert_field(work_precision::run(&cfg, NO_PROGRESS).map(|_| ()), flag, &out);
    }
}

#[test]
fn stress_refuses_zero_steps_and_one_element() {
    let out = nowhere("stress");
    let cfg = stress::Config { out: out.clone(), steps: 0, ..Default::default() };
    assert_field(stress::run(&cfg, NO_PROGRESS).map(|_| ()), "--steps", &out);
    let cfg = stress::Config { out: out.clone(), elements: 1, ..Default::default() };
    assert_field(cfg.validate(), "--elements", &out);
}
