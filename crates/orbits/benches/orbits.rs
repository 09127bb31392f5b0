//! The speed targets for periodic orbits: a period-1 orbit of the
//! impact oscillator to 1e-12 (Newton from 1 % off, the scene built once;
//! target < 1 ms), and a branch of the oscillator from Ω = 2.2 to 3.0
//! through its grazing (scene rebuilt at every parameter value, as
//! `signorini continue` does; target < 0.2 s for 200 points), and the
//! paper's beam (J = 19, A = 0.07 m) continued in the support frequency
//! over 4 … 16 rad/s to its grazing, with the searches for an impacting
//! orbit there that fail (target < 1 min on 2 cores; one run).
//!
//! `cargo bench -p signorini-orbits --bench orbits`.

use divan::Bencher;
use signorini_orbits::{continuation, periodic_orbit, ContinuationOptions, Family, Newton, SceneFamily};

fn main() {
    divan::main();
}

const SCENE: &str =
    "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.8\ndt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = 2.2\n";

fn family() -> SceneFamily {
    SceneFamily::new(SCENE.parse().unwrap(), "forcing.omega", 1).unwrap().0
}

/// The orbit at Ω = 2.2 (found once), to start 1 % off it.
fn orbit_state(fam: &SceneFamily) -> Vec<f64> {
    let model = fam.model(2.2).unwrap();
    let t = fam.period(2.2).unwrap();
    let x = model.flow(0.0, &[0.0, 0.0], 200.0 * t, false).unwrap().x;
    periodic_orbit(&model, 0.0, t, &x, &Newton::default()).unwrap().x
}

#[divan::bench]
fn period_one_orbit_to_1e_12(b: Bencher) {
    let fam = family();
    let model = fam.model(2.2).unwrap();
    let t = fam.period(2.2).unwrap();
    let guess: Vec<f64> = orbit_state(&fam).iter().map(|v| v * 1.01).collect();
    b.bench_local(|| periodic_orbit(&model, 0.0, t, &guess, &Newton::default()).unwrap().residual);
}

#[divan::bench(sample_count = 10)]
fn branch_through_grazing(b: Bencher) {
    let fam = family();
    let start = orbit_state(&fam);
    let mut opts = ContinuationOptions::new(2.2, 3.0);
    // 200 points: steps of at most 1/200 of the range.
    (opts.step, opts.max_step) = (0.005, 0.005);
    opts.max_points = 400;
    b.bench_local(|| continuation(&fam, &start, &opts).unwrap().points.len());
}

#[divan::bench]
fn scene_build(b: Bencher) {
    let fam = family();
    b.bench_local(|| fam.build(2.3).unwrap().horizon);
}

#[divan::bench]
fn one_period_map_with_jacobian(b: Bencher) {
    let fam = family();
    let model = fam.model(2.2).unwrap();
    let x = orbit_state(&fam);
    b.bench_local(|| model.flow(0.0, &x, fam.period(2.2).unwrap(), true).unwrap().x[0]);
}

/// `signorini continue beam-07-exact.toml --param support.omega --from 4
/// --to 16 --transient 0` without the files: the free branch to the
/// grazing at 12.216 rad/s and the Newton searches on both sides of it.
#[divan::bench(sample_count = 1, sample_size = 1)]
fn beam_frequency_branch_to_its_grazing(b: Bencher) {
    let doc = "[beam]\nscene = \"fig2\"\nscheme = \"event-driven\"\n[support]\namplitude = 0.07\nomega = 4.0\n";
    let fam = SceneFamily::new(doc.parse().unwrap(), "support.omega", 1).unwrap().0;
    let start = fam.build(4.0).unwrap().start;
    b.bench_local(|| continuation(&fam, &start, &ContinuationOptions::new(4.0, 16.0)).unwrap().points.len());
}
