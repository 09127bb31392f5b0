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
use signorini_run::beam::{build_excited, BeamContact, BeamExcitation, BeamScene, PenaltyUnits, Pipe};
use signorini_run::{run, RunConfig};
use signorini_schemes::SchemeSpec;

fn main() {
    divan::main();
}

const CASES: [&str; 2] = ["event-driven", "projection"];

fn scene(name: &str, t_end: f64) -> BeamScene {
    let contact = match name {
        "event-driven" => BeamContact::Scheme("event-driven".parse::<SchemeSpec>().unwrap()),
        _ => BeamContact::Projection { beta: 0.5 },
    };
    BeamScene { dt: 5e-5, t_end, contact, ..BeamScene::PAPER[0] }
}

#[divan::bench(args = CASES, sample_count = 20, sample_size = 1)]
fn setup(bencher: Bencher, name: &str) {
    let sc = scene(name, 1.0);
    bencher.bench_local(|| build_excited(&Pipe::paper(), &sc, false, PenaltyUnits::default(), None, &BeamExcitation::default()).unwrap());
}

#[divan::bench(args = CASES, sample_count = 5, sample_size = 1)]
fn whole_run(bencher: Bencher, name: &str) {
    let sc = scene(name, 1.0);
    bencher.bench_local(|| {
        let (mut s, init, _) = build_excited(&Pipe::paper(), &sc, false, PenaltyUnits::default(), None, &BeamExcitation::default()).unwrap();
        run(s.as_mut(), &init.u, &RunConfig::new(sc.dt, sc.t_end).unwrap(), &mut []).unwrap()
    });
}
