//! The long-horizon study: its per-period errors agree with the standard
//! norms of an independent run over one period, impacts are found at the
//! exact times' neighbourhood, and the redistributed mass's phase drift is
//! linear in time and first order in h.

use signorini_fem::BarMass;
use signorini_run::{run, Benchmark, NormObserver, RunConfig};
use signorini_schemes::SchemeSpec;
use signorini_studies::{long_horizon, Column, StudyError};

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
fn periods_impacts_and_drift() {
    let out = std::env::temp_dir().join(format!("signorini-studies-long-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let ps: SchemeSpec = "ps-e0".parse().unwrap();
    let cfg = long_horizon::Config { out: out.clone(), runs: vec![(ps, BarMass::Mod), (ps, BarMass::Mod3)], levels: vec![20, 40], ratio: 10.0, t_end: 30.0 };
    let o = long_horizon::run(&cfg, &|_, _| {}).unwrap();
    let (ev, im, su) = (&o.tables[0], &o.tables[1], &o.tables[2]);
    assert_eq!((ev.file.as_str(), im.file.as_str(), su.file.as_str()), ("error_vs_time.csv", "impacts.csv", "summary.csv"));

    // Period 1's largest L² error is L∞(0, 3; L²) of an independent run to t = 3.
    let exact = Benchmark::BarDirichlet.exact(3.0).unwrap();
    let p = Benchmark::BarDirichlet.problem(exact.as_ref(), 20, BarMass::Mod).unwrap();
    let dt = p.bar.h() / 10.0;
    let mut s = ps.build(p.dynamics(), dt, &p.initial).unwrap();
    let mut norms = NormObserver::new(exact.as_ref(), 20, p.vnorm(), dt);
    run(s.as_mut(), &p.initial.u, &RunConfig::new(dt, 3.0).unwrap(), &mut [&mut norms]).unwrap();
    let first = col_f(ev, "max_l2_u")[0];
    assert!((first - norms.report().linf_l2_u).abs() <= 1e-12 * first, "{first} vs {}", norms.report().linf_l2_u);

    // Impacts: the first within one element's transit time h/c of t = 1; mod's drift grows linearly
    // (impact 9 ≈ 9 × the per-period slope) and halves with h.
    let (mass, m, k, drift) = (col_s(im, "mass"), match im.column("m") {
        Some(Column::I64(v)) => v.clone(),
        other => panic!("{other:?}"),
    }, match im.column("k") {
        Some(Column::I64(v)) => v.clone(),
        other => panic!("{other:?}"),
    }, col_f(im, "drift"));
    let d = |ms: &str, mm: i64, kk: i64| (0..mass.len()).find(|&r| mass[r] == ms && m[r] == mm && k[r] == kk).map(|r| drift[r]).unwrap();
    for (ms, mm) in [("mod", 20), ("mod", 40), ("mod3", 20), ("mod3", 40)] {
        assert!(d(ms, mm, 0).abs() <= 1.0 / mm as f64 + 1e-12, "{ms} m={mm}: first impact drift {}", d(ms, mm, 0));
    }
    let slope = |mm: i64| (d("mod", mm, 9) - d("mod", mm, 0)) / 9.0;
    assert!(slope(20) < 0.0 && (d("mod", 20, 5) - d("mod", 20, 0) - 5.0 * slope(20)).abs() < 0.2 * (5.0 * slope(20)).abs(), "not linear: {}", slope(20));
    let ratio = slope(20) / slope(40);
    assert!((1.6..2.4).contains(&ratio), "drift per period not first order in h: {ratio}");
    // mod3 keeps the phase far better than mod.
    assert!(d("mod3", 20, 9).abs() < 0.1 * d("mod", 20, 9).abs());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_input_names_the_option() {
    let out = std::env::temp_dir().join(format!("signorini-studies-long-bad-{}", std::process::id()));
    let mj: SchemeSpec = "moreau-jean".parse().unwrap();
    for (cfg, field) in [
        (long_horizon::Config { out: out.clone(), runs: vec![], ..Default::default() }, "--runs"),
        (long_horizon::Config { out: out.clone(), runs: vec![(mj, BarMass::Mod)], ..Default::default() }, "--runs"),
        (long_horizon::Config { out: out.clone(), levels: vec![1], ..Default::default() }, "--levels"),
        (long_horizon::Config { out: out.clone(), ratio: 0.0, ..Default::default() }, "--ratio"),
        (long_horizon::Config { out: out.clone(), t_end: 1.0, ..Default::default() }, "--t-end"),
        (long_horizon::Config { out: out.clone(), levels: vec![20000], ratio: 100.0, t_end: 3000.0, ..Default::default() }, "--t-end"),
    ] {
        match long_horizon::run(&cfg, &|_, _| {}) {
            Err(StudyError::Config { field: f, .. }) => assert_eq!(f, field),
            other => panic!("{field}: {other:?}"),
        }
        assert!(!out.exists());
    }
    assert!(long_horizon::parse_runs(&["ps-e0:heavy".into()]).is_err());
    assert_eq!(long_horizon::parse_runs(&["ps(0.5,0.25):mod3,newmark-cn:std".into()]).unwrap().len(), 2);
}
