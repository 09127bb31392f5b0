//! Cost per step against the number of obstacles and of active contacts
//! (issue 12), bar and beam. Every case integrates the same physical run
//! over a whole period, so the average mixes free and contact steps as a
//! real run does:
//!
//! * bar: `bar-dirichlet`, m = 1000, `newmark-cn`, std mass, dx/dt = 10,
//!   T = 3 (30 000 steps; the end x = 0 is in contact during part of it).
//!   `k1` is today's single-contact path; `k2`, `k8`, `every` add 1, 7 or
//!   every other node as obstacles that never act (`lo = -10`), so at most
//!   one contact is active; `floor-every` puts an obstacle `u >= 0` at every
//!   node (many active: the bar lands on a floor along its length).
//! * beam: the paper's pipe (J = 19, β = 1/2, dt = 5e-5 s, T = 2 s: 40 000
//!   steps). `k1` is the tip's two stops (today's path); `k2`, `k8`,
//!   `every` add inactive obstacles (±10 m); `obstacles-every` is the
//!   paper's general problem: ±0.1 m at every node (beam-obstacles).
//!
//! `cargo bench -p signorini-run --bench contacts`; the README
//! ("Performance", several contacts) records the medians and, from
//! `print_pivots`, the pivots per pivoting solve.

use divan::Bencher;
use signorini_fem::BarMass;
use signorini_run::beam::{BeamScene, BeamSetup, Pipe};
use signorini_run::{BarProblem, Benchmark, Stop};
use signorini_schemes::{SchemeSpec, Stepper};

fn main() {
    divan::main();
}

const BAR_M: usize = 1000;
const BAR_STEPS: usize = 30_000;
const BEAM_STEPS: usize = 40_000;

fn bar(case: &str) -> Box<dyn Stepper> {
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(3.0).unwrap();
    let p: BarProblem = b.problem(exact.as_ref(), BAR_M, BarMass::Std).unwrap();
    let inactive = |nodes: &mut dyn Iterator<Item = usize>| -> Vec<Stop> { std::iter::once(Stop::new(0, 0.0, f64::INFINITY)).chain(nodes.map(|i| Stop::new(i, -10.0, f64::INFINITY))).collect() };
    let p = match case {
        "k1" => p,
        "k2" => p.with_stops(inactive(&mut std::iter::once(BAR_M / 2))).unwrap(),
        "k8" => p.with_stops(inactive(&mut (1..8).map(|j| j * BAR_M / 8))).unwrap(),
        "every" => p.with_stops(inactive(&mut (1..BAR_M))).unwrap(),
        "floor-every" => p.with_stops((0..BAR_M).map(|i| Stop::new(i, 0.0, f64::INFINITY)).collect()).unwrap(),
        _ => unreachable!(),
    };
    let dt = p.bar.h() / 10.0;
    SchemeSpec::newmark(0.25, 0.5).build(p.dynamics(), dt, &p.initial).unwrap()
}

fn beam(case: &str) -> Box<dyn Stepper> {
    let pipe = Pipe::paper();
    let j = 19;
    let scene = BeamScene::new("bench", j, 5e-5, 2.0, SchemeSpec::ps(0.0, 0.5));
    let tip = |extra: &mut dyn Iterator<Item = usize>| -> Vec<Stop> { std::iter::once(Stop::new(j, -0.1, 0.1)).chain(extra.map(|i| Stop::new(i, -10.0, 10.0))).collect() };
    let stops = match case {
        "k1" => None,
        "k2" => Some(tip(&mut std::iter::once(10))),
        "k8" => Some(tip(&mut (1..8).map(|i| 2 * i + 3))),
        "every" => Some(tip(&mut (1..j))),
        "obstacles-every" => Some((1..=j).map(|i| Stop::new(i, -0.1, 0.1)).collect()),
        _ => unreachable!(),
    };
    let mut setup = BeamSetup::new(pipe, scene);
    setup.stops = stops;
    setup.build().unwrap().stepper
}

fn steps(s: &mut dyn Stepper, n: usize) {
    while s.level() < n {
        divan::black_box(s.step().unwrap());
    }
}

#[divan::bench(args = ["k1", "k2", "k8", "every", "floor-every"], sample_count = 10, sample_size = 1)]
fn bar_per_period(bencher: Bencher, case: &str) {
    bencher.with_inputs(|| bar(case)).bench_local_values(|mut s| {
        steps(s.as_mut(), BAR_STEPS);
        s
    });
}

#[divan::bench(args = ["k1", "k2", "k8", "every", "obstacles-every"], sample_count = 10, sample_size = 1)]
fn beam_per_run(bencher: Bencher, case: &str) {
    bencher.with_inputs(|| beam(case)).bench_local_values(|mut s| {
        steps(s.as_mut(), BEAM_STEPS);
        s
    });
}

/// Not a timing: prints the contact statistics of each case once.
#[divan::bench(sample_count = 1, sample_size = 1)]
fn print_pivots() {
    for case in ["k2", "k8", "every", "floor-every"] {
        let mut s = bar(case);
        steps(s.as_mut(), BAR_STEPS);
        let (solves, pivots) = s.contact_pivots().unwrap();
        eprintln!("bar {case}: k = {}, {solves} of {BAR_STEPS} steps pivoted, {:.2} pivots per pivoting step", s.dynamics().k(), pivots as f64 / solves.max(1) as f64);
    }
    for case in ["k2", "k8", "every", "obstacles-every"] {
        let mut s = beam(case);
        steps(s.as_mut(), BEAM_STEPS);
        let (solves, pivots) = s.contact_pivots().unwrap();
        eprintln!("beam {case}: k = {}, {solves} of {BEAM_STEPS} steps pivoted, {:.2} pivots per pivoting step", s.dynamics().k(), pivots as f64 / solves.max(1) as f64);
    }
}
