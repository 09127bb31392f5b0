//! Costs on the user's path (issue 23, item 3): the set-up of a run and
//! whole runs, built exactly as `signorini run`, the convergence study and
//! Python build them (`Benchmark::problem`, then `SchemeSpec::build` with
//! its CFL check and factorisations).
//!
//! * `setup`: problem (matrices, exact initial data) and integrator of the
//!   falling bar (`bar-neumann-gravity`) at m = 1280 and 10 240: `cd-taylor`
//!   with the lumped mass at dt = h/c (its CFL check: the closed form of
//!   the uniform P1 bar), `newmark-cn` with `mod` (no CFL check),
//!   `penalty-cd` with the lumped mass at dx/dt = 10 (its pencil
//!   `(K + κ e₀e₀ᵀ, M)` has no closed form: Lanczos and the inertia test).
//! * `cfl_check`: `SchemeSpec::cfl_limit` alone on those pencils.
//! * `whole_run`: set-up, stepping and every error norm
//!   (`study::run_level`, one level of `cargo xtask convergence`) at
//!   m = 1280 and dx/dt = 1 for both schemes, so the same step count:
//!   3 840 steps on `bar-dirichlet` (T = 3), 20 480 on the falling bar (T = 16).
//!
//! `cargo bench -p signorini-run --bench setup`; the README ("Performance",
//! costs on the user's path) records the medians.

use divan::Bencher;
use signorini_fem::BarMass;
use signorini_run::{study, Benchmark};
use signorini_schemes::SchemeSpec;

fn main() {
    divan::main();
}

/// `(scheme, mass, dx/dt)` of a case name.
fn case(name: &str) -> (SchemeSpec, BarMass, f64) {
    match name {
        "cd-taylor" => (SchemeSpec::cd_taylor(), BarMass::Lumped, 1.0),
        "newmark-cn" => (SchemeSpec::newmark(0.25, 0.5), BarMass::Mod, 1.0),
        "penalty-cd" => (SchemeSpec::penalty(10.0, true), BarMass::Lumped, 10.0),
        _ => unreachable!("unknown case {name}"),
    }
}

const SETUP_CASES: [&str; 3] = ["cd-taylor", "newmark-cn", "penalty-cd"];

#[divan::bench(args = SETUP_CASES, consts = [1280, 10240], sample_count = 20, sample_size = 1)]
fn setup<const M: usize>(bencher: Bencher, name: &str) {
    let b = Benchmark::BarNeumannGravity;
    let (_, t_end) = b.default_ratio_and_horizon();
    let exact = b.exact(t_end).unwrap();
    let (spec, mass, ratio) = case(name);
    bencher.bench_local(|| {
        let p = b.problem(exact.as_ref(), M, mass).unwrap();
        let dt = p.bar.h() / ratio;
        spec.build(p.dynamics(), dt, &p.initial).unwrap()
    });
}

#[divan::bench(args = SETUP_CASES, consts = [1280, 10240], sample_count = 20, sample_size = 1)]
fn cfl_check<const M: usize>(bencher: Bencher, name: &str) {
    let b = Benchmark::BarNeumannGravity;
    let (_, t_end) = b.default_ratio_and_horizon();
    let exact = b.exact(t_end).unwrap();
    let (spec, mass, _) = case(name);
    let dy = b.problem(exact.as_ref(), M, mass).unwrap().dynamics();
    bencher.bench_local(|| spec.cfl_limit(&dy).unwrap());
}

#[divan::bench(args = ["bar-dirichlet/cd-taylor", "bar-dirichlet/newmark-cn", "bar-neumann-gravity/cd-taylor", "bar-neumann-gravity/newmark-cn"], sample_count = 5, sample_size = 1)]
fn whole_run(bencher: Bencher, name: &str) {
    let (bench, scheme) = name.split_once('/').unwrap();
    let b: Benchmark = bench.parse().unwrap();
    let (_, t_end) = b.default_ratio_and_horizon();
    let exact = b.exact(t_end).unwrap();
    let (spec, mass, ratio) = case(scheme);
    bencher.bench_local(|| study::run_level(&study::Level::new(b, spec, mass, 1280, ratio, t_end), exact.as_ref()).unwrap());
}
