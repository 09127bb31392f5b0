//! The Lyapunov study: the twin-run divergence of the paper's beam (fig. 2
//! with `[support]`, ω and ω(1 + 1e-10)), Benettin's λ_max on it and on the
//! impact oscillator against its exact Floquet exponent, the CSV, and bad
//! input.

use signorini_run::chaos::{Flow, StepperFlow};
use signorini_scene::{Limits, SceneFile};
use signorini_studies::{lyapunov, Column, StudyError};
use std::path::PathBuf;

const FIG2_SUPPORT: &str = include_str!("../../../../data/scenes/beam-fig2-support.toml");

fn col_f(t: &signorini_studies::Table, name: &str) -> Vec<f64> {
    match t.column(name) {
        Some(Column::F64(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

fn fig2(omega: &str) -> StepperFlow {
    let text = FIG2_SUPPORT.replace("omega = 10.0", &format!("omega = {omega}")).replace("[beam]\n", "[beam]\nt_end = 2.0\n");
    let scene = SceneFile::parse(&text).unwrap().validate_with(&Limits::machine()).unwrap();
    StepperFlow(scene.instantiate(None).unwrap().stepper)
}

#[test]
fn twin_runs_of_the_beam_separate_exponentially_then_saturate() {
    // ω = 10 and ω (1 + 1e-10): the tips' distance every 0.05 s to 2 s.
    let (mut a, mut b) = (fig2("10.0"), fig2("10.000000001"));
    let tip = a.0.dynamics().contacts[0].dof;
    let every = 1000; // 0.05 s at dt = 5e-5
    let mut sep = Vec::new();
    for _ in 0..40 {
        a.advance(every).unwrap();
        b.advance(every).unwrap();
        sep.push((a.0.displacement()[tip] - b.0.displacement()[tip]).abs());
    }
    // t = 0.15 s is sample 2, t = 0.65 s sample 12.
    let (d15, d65) = (sep[2], sep[12]);
    assert!((1e-11..1e-8).contains(&d15), "separation at 0.15 s: {d15:e}");
    assert!((1e-5..1e-3).contains(&d65), "separation at 0.65 s: {d65:e}");
    let efold = 0.5 / (d65 / d15).ln();
    assert!((0.02..0.06).contains(&efold), "e-folding time {efold} s (about 40 ms)");
    // Saturated at the size of the attractor (stops at ±0.1 m).
    let late = sep[20..].iter().copied().fold(0.0, f64::max);
    assert!((3e-3..0.2).contains(&late), "largest separation after 1 s: {late:e}");
}

#[test]
fn study_on_the_beam_and_the_oscillator() {
    let out = std::env::temp_dir().join(format!("signorini-studies-lyapunov-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let cfg = lyapunov::Config { out: out.clone(), scenes: vec!["fig2-support".into()], refine: vec![], omegas: vec![2.0], transient: 10.0, window: 10.0, batches: 5, ..Default::default() };
    let o = lyapunov::run(&cfg, &|_, _| {}).unwrap();
    let t = &o.tables[0];
    assert_eq!(t.file, "lyapunov.csv");
    let head: Vec<&str> = t.columns.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(head, ["scene", "dt", "elements", "lambda_max", "ci_low", "ci_high", "horizon_s"]);
    let text = std::fs::read_to_string(out.join("lyapunov.csv")).unwrap();
    assert!(text.starts_with("scene,dt,elements,lambda_max,ci_low,ci_high,horizon_s\n"), "{text}");
    let (l, lo, hi, hz) = (col_f(t, "lambda_max"), col_f(t, "ci_low"), col_f(t, "ci_high"), col_f(t, "horizon_s"));
    // The beam: chaotic, e-folding time 20–60 ms; the horizon ln(1e-3/(1e-16·0.1))/λ.
    assert!((1.0 / 0.06..1.0 / 0.02).contains(&l[0]), "beam λ_max = {}", l[0]);
    assert!(lo[0] < l[0] && l[0] < hi[0] && lo[0] > 0.0, "{} [{}, {}]", l[0], lo[0], hi[0]);
    let expect = (1e-3 / (1e-16 * 0.1_f64)).ln() / l[0];
    assert!((hz[0] / expect - 1.0).abs() < 0.05, "horizon {} against {expect}", hz[0]);
    // The oscillator at Ω = 2: a stable period-1 orbit, λ_max = ln|μ₁| Ω/2π < 0, no horizon.
    let osc = &o.tables[1];
    let (lam, exact) = (col_f(osc, "lambda_max")[0], col_f(osc, "lambda_exact")[0]);
    assert!(exact < 0.0 && (lam / exact - 1.0).abs() < 0.03, "oscillator λ_max {lam} against the exact {exact}");
    assert!(hz[1].is_nan(), "no horizon for λ <= 0: {}", hz[1]);
    let _ = std::fs::remove_dir_all(&out);
}

fn nowhere(name: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("signorini-studies-bad-lyapunov-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    p
}

#[track_caller]
fn refused(cfg: lyapunov::Config, want: &str, range: &str) {
    let out = cfg.out.clone();
    match lyapunov::run(&cfg, &|_, _| {}) {
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
fn bad_input_is_refused_naming_the_option() {
    let base = || lyapunov::Config { out: nowhere("x"), ..Default::default() };
    for eps in [0.0, -1e-10, 1e-3, 0.5, f64::NAN, f64::INFINITY] {
        refused(lyapunov::Config { perturbation: eps, ..base() }, "--perturbation", "0 < perturbation < 1e-3");
    }
    refused(lyapunov::Config { scenes: vec!["fig9".into()], ..base() }, "--scenes", "fig2-support");
    refused(lyapunov::Config { refine: vec!["nope".into()], ..base() }, "--refine", "beam-obstacles");
    refused(lyapunov::Config { batches: 1, ..base() }, "--batches", "[2, 1000]");
    refused(lyapunov::Config { window: 0.5, ..base() }, "--window", "at least 10 renormalisations per batch");
    refused(lyapunov::Config { window: f64::NAN, ..base() }, "--window", "finite");
    refused(lyapunov::Config { dts: vec![0.0], ..base() }, "--dts", "(0, 1e-3]");
    refused(lyapunov::Config { elements: vec![1], ..base() }, "--elements", "[2, 1000]");
    refused(lyapunov::Config { omegas: vec![-2.0], ..base() }, "--omegas", "(0, 100]");
    refused(lyapunov::Config { transient: -1.0, ..base() }, "--transient", "[0, 10000]");
    refused(lyapunov::Config { per_period: 0, ..base() }, "--per-period", "[1, 10000]");
    refused(lyapunov::Config { scenes: vec![], refine: vec![], omegas: vec![], ..base() }, "--scenes", "at least one case");
}

/// Issue 31 §9: an interval that contains 0 leaves the sign of λ, and so the
/// horizon, undecided (it printed "∞ (λ ≤ 0)" for −0.117 [−0.369, +0.134]).
#[test]
fn an_interval_containing_zero_gives_no_horizon() {
    use lyapunov::horizon_cells;
    let undecided = ("—".to_string(), "undecided (the interval contains 0)".to_string());
    assert_eq!(horizon_cells(-0.117, (-0.369, 0.134), f64::NAN), undecided);
    // λ > 0 with an interval reaching below 0: no finite horizon either.
    assert_eq!(horizon_cells(0.05, (-0.01, 0.11), 644.0), undecided);
    assert_eq!(horizon_cells(-0.12, (-0.124, -0.117), f64::NAN), ("—".to_string(), "∞ (λ < 0)".to_string()));
    // fig. 2: 29.4 [27.7, 31.2] /s, 1/29.4 = 34.0 ms, 32.2/29.4 = 1.10 s.
    let h = (1e-3 / (1e-16 * 0.1_f64)).ln() / 29.4;
    assert_eq!(horizon_cells(29.4, (27.7, 31.2), h), ("34.0 ms".to_string(), "1.10".to_string()));
}
