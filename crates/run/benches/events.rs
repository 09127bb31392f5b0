//! The exact event-driven reference on the user's path (issue 25, item 4):
//! the paper's beam of fig. 2 (J = 19, 38 dofs, stops at ±0.1 m) built as
//! `signorini run` builds a beam scene with `scheme = "event-driven"`
//! (`build_excited` with the registry's scheme), then run over [0, T]
//! sampled at the paper's dt = 5e-5 s, against the paper's projection
//! scheme (β = 1/2) at the same dt on the same path.
//!
//! * `setup`: the problem and the integrator (the modal decomposition of
//!   the pencil; the projection scheme's factorisation);
//! * `whole_run`: set-up and stepping over T = 1 s.
//!
//! `cargo bench -p signorini-run --bench events`; the README ("The exact
//! reference") records the medians.

use divan::Bencher;
use signorini_run::beam::{BeamScene, BeamSetup, Pipe};
use signorini_run::{run, RunConfig};
use signorini_schemes::SchemeSpec;

fn main() {
    divan::main();
}

const CASES: [&str; 2] = ["event-driven", "projection"];

fn scene(name: &str, t_end: f64) -> BeamScene {
    let scheme = match name {
        "event-driven" => "event-driven".parse::<SchemeSpec>().unwrap(),
        _ => SchemeSpec::ps(0.0, 0.5),
    };
    BeamScene { dt: 5e-5, t_end, scheme, ..BeamScene::PAPER[0] }
}

#[divan::bench(args = CASES, sample_count = 20, sample_size = 1)]
fn setup(bencher: Bencher, name: &str) {
    let sc = scene(name, 1.0);
    bencher.bench_local(|| BeamSetup::new(Pipe::paper(), sc).build().unwrap());
}

#[divan::bench(args = CASES, sample_count = 5, sample_size = 1)]
fn whole_run(bencher: Bencher, name: &str) {
    let sc = scene(name, 1.0);
    bencher.bench_local(|| {
        let mut b = BeamSetup::new(Pipe::paper(), sc).build().unwrap();
        run(b.stepper.as_mut(), &b.initial.u, &RunConfig::new(sc.dt, sc.t_end).unwrap(), &mut []).unwrap()
    });
}
