//! Invalid parameters are typed errors naming the field and the allowed
//! range; a run whose state becomes non-finite stops with the step and time
//! and keeps what its observers wrote.

use signorini::fem::{Bar, BarMass, FemError, RightEnd};
use signorini::run::{run, BarProblem, Benchmark, RunConfig, RunError, SeriesColumns, SeriesWriter};
use signorini::schemes::{Dynamics, SchemeError, SchemeSpec, StepReport, Stepper};

fn field_of(e: &SchemeError) -> &'static str {
    match e {
        SchemeError::Invalid { field, .. } => field,
        other => panic!("expected Invalid, got {other:?}"),
    }
}

#[test]
fn scheme_parameters_out_of_range() {
    let cases: [(&str, &str); 9] = [
        ("ps(1.5)", "e"),
        ("ps(-0.1)", "e"),
        ("ps(0.5,0.7)", "beta"),
        ("newmark(0,0.5)", "beta"),
        ("newmark(0.25,0.4)", "gamma"),
        ("newmark(0.2,0.5)", "beta"),
        ("newmark(0.6,0.5)", "beta"),
        ("theta(0.3)", "theta"),
        ("theta(NaN)", "theta"),
    ];
    for (s, field) in cases {
        let e = s.parse::<SchemeSpec>().unwrap_err();
        assert_eq!(field_of(&e), field, "{s}");
        assert!(e.to_string().contains("allowed"), "{e}");
    }
    assert!(matches!("leapfrog".parse::<SchemeSpec>(), Err(SchemeError::UnknownScheme { .. })));
    assert!(matches!("newmark(0.25)".parse::<SchemeSpec>(), Err(SchemeError::UnknownScheme { .. })));
    // Presets round-trip through their names.
    for (name, spec) in SchemeSpec::group(signorini_schemes::Group::Paper) {
        assert_eq!(name.parse::<SchemeSpec>().unwrap(), spec);
        assert_eq!(spec.to_string(), name);
    }
}

#[test]
fn mesh_time_and_problem_parameters_out_of_range() {
    assert!(matches!(Bar::new(1.0, 1, 1.0, RightEnd::Clamped), Err(FemError::Invalid { field: "m", .. })));
    for (dt, t) in [(0.0, 1.0), (-1.0, 1.0), (f64::NAN, 1.0), (f64::INFINITY, 1.0)] {
        assert!(matches!(RunConfig::new(dt, t), Err(RunError::Invalid { field: "dt", .. })), "dt = {dt}");
    }
    for t in [0.0, -2.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(RunConfig::new(0.1, t), Err(RunError::Invalid { field: "T", .. })), "T = {t}");
    }
    let bar = Bar::new(1.0, 4, 1.0, RightEnd::Clamped).unwrap();
    // Initial position below the obstacle.
    let e = BarProblem::new(bar, BarMass::Std, 0.0, 0.0, |_| -0.1, |_| 0.0).unwrap_err();
    assert!(matches!(e, RunError::Invalid { field: "initial u(0)", .. }), "{e}");
    assert!(matches!(BarProblem::new(bar, BarMass::Std, f64::NAN, 0.0, |_| 0.0, |_| 0.0), Err(RunError::Invalid { field: "gap", .. })));
    assert!(matches!("nope".parse::<Benchmark>(), Err(RunError::UnknownBenchmark(_))));
    // A scheme given a dt that is not positive.
    let p = BarProblem::new(bar, BarMass::Mod, 0.0, 0.0, |x| 1.0 - x, |_| 0.0).unwrap();
    let e = SchemeSpec::newmark(0.25, 0.5).build(p.dynamics(), -0.1, &p.initial).err().unwrap();
    assert_eq!(field_of(&e), "dt");
}

/// T must be a whole number of steps: counted exactly (also at 1e9 steps),
/// refused otherwise (dt > T, or T/dt = 2.5) with a typed error.
#[test]
fn steps_cover_the_horizon_exactly() {
    assert_eq!(RunConfig::new(1.0 / 6400.0, 3.0).unwrap().steps(), 19200);
    assert_eq!(RunConfig::new(0.1, 0.3).unwrap().steps(), 3);
    assert_eq!(RunConfig::new(1e-9, 1.0).unwrap().steps(), 1_000_000_000);
    assert_eq!(RunConfig::new(3e-9, 3.0).unwrap().steps(), 1_000_000_000);
    for (dt, t) in [(0.4, 1.0), (2.0, 1.0), (1.0 / 3.0, 1.1)] {
        let e = RunConfig::new(dt, t).unwrap_err();
        assert!(matches!(e, RunError::Horizon { .. }), "{e:?}");
        assert!(e.to_string().contains("whole number of steps"), "{e}");
    }
}

/// A stepper whose state turns NaN at step 5.
struct Failing {
    n: usize,
    u: Vec<f64>,
    dy: Dynamics,
}

impl Stepper for Failing {
    fn label(&self) -> String {
        "failing".into()
    }
    fn dt(&self) -> f64 {
        0.1
    }
    fn level(&self) -> usize {
        self.n
    }
    fn displacement(&self) -> &[f64] {
        &self.u
    }
    fn dynamics(&self) -> &Dynamics {
        &self.dy
    }
    fn step(&mut self) -> Result<StepReport, SchemeError> {
        self.n += 1;
        if self.n == 5 {
            return Err(SchemeError::NonFinite { step: self.n, time: self.time() });
        }
        Ok(StepReport { n: self.n, t: self.time(), lambda: Some((self.time(), -1.0)), active: signorini::contact::Active::Lower })
    }
    fn energy(&mut self) -> Option<(f64, f64)> {
        Some((self.time(), 1.0))
    }
    fn contact_forces(&self) -> &[f64] {
        &[-1.0]
    }
    fn contact_status(&self) -> &[signorini::contact::Active] {
        &[signorini::contact::Active::Lower]
    }
}

#[test]
fn blow_up_stops_with_step_and_time_and_keeps_output() {
    let mut buf = Vec::new();
    let bar = Bar::new(1.0, 3, 1.0, RightEnd::Clamped).unwrap();
    let dy = BarProblem::new(bar, BarMass::Std, 0.0, 0.0, |_| 0.0, |_| 0.0).unwrap().dynamics();
    let mut s = Failing { n: 0, u: vec![0.0; 3], dy };
    {
        let mut w = SeriesWriter::new(&mut buf, 1, 0, SeriesColumns::default()).unwrap();
        let e = run(&mut s, &[0.0; 3], &RunConfig::new(0.1, 10.0).unwrap(), &mut [&mut w]).unwrap_err();
        assert!(matches!(e, RunError::BlowUp { step: 5, time } if (time - 0.5).abs() < 1e-12), "{e:?}");
        assert!(e.to_string().contains("step 5"));
    }
    // Header + levels 0..=4, all complete records.
    let mut rd = csv::Reader::from_reader(buf.as_slice());
    assert_eq!(rd.headers().unwrap().iter().collect::<Vec<_>>(), SeriesWriter::<Vec<u8>>::HEADER.to_vec());
    let rows: Vec<csv::StringRecord> = rd.records().collect::<Result<_, _>>().unwrap();
    assert_eq!(rows.len(), 5);
    assert_eq!(&rows[4][0], "4");
}

#[test]
fn real_scheme_detects_non_finite_state() {
    let bar = Bar::new(1.0, 8, 1.0, RightEnd::Clamped).unwrap();
    let p = BarProblem::new(bar, BarMass::Std, 0.0, 0.0, |x| 1e308 * (1.5 - x), |_| 1e308).unwrap();
    let mut s = SchemeSpec::newmark(0.25, 0.5).build(p.dynamics(), 0.1, &p.initial).unwrap();
    let e = run(s.as_mut(), &p.initial.u, &RunConfig::new(0.1, 1.0).unwrap(), &mut []).unwrap_err();
    assert!(matches!(e, RunError::BlowUp { step: 1, .. }), "{e:?}");
}
