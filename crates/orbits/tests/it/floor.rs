//! The corrector at the map's round-off floor: the oscillator between
//! symmetric stops of `data/scenes/oscillator-two-stops.toml`
//! (`x'' + 0.1 x' + x = 2 cos Ωt`, `|x| <= 1`, e = 0.8), its 4-impact
//! orbits between Ω = 0.7024 and their 4 → 2 grazing at 0.7010020. Their
//! map has `‖P'‖∞` from 6e4 to 5e7 there (two slow impacts), and
//! `|P(x) − x|` cannot be computed below about `ε (‖x‖ + ‖P(x)‖)(1 +
//! ‖P'‖)`, 4e-11 … 5e-8, above the tolerance (1e-11 of the state): with
//! the variational `G_λ` at every iteration the continuation from 0.6
//! stopped at 0.7018238, its corrector's residual wandering between
//! 1.8e-11 and 2.6e-10 on a correct orbit. Checked against the
//! transcription of `between.rs` (the closed-form flow between impacts,
//! its own impact search, the restitution by hand; the section a quarter
//! period on: the cosine's phase).

use crate::between::{map_between_from, E};
use signorini_orbits::{corrected, Family, SceneFamily};
use std::f64::consts::TAU;

/// The transcription's map over one forcing period: image and impacts.
fn map(w: f64, x: [f64; 2]) -> ([f64; 2], usize) {
    let (y, k, _) = map_between_from(w, 0.25 * TAU / w, x, 1, (-1.0, 1.0), E, 4000.0);
    (y, k)
}

/// The transcription's `|P(x) − x|∞` at `(w, x)`, with its impacts.
fn residual(w: f64, x: &[f64]) -> (f64, usize) {
    let (y, k) = map(w, [x[0], x[1]]);
    ((y[0] - x[0]).abs().max((y[1] - x[1]).abs()), k)
}

fn family() -> SceneFamily {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/oscillator-two-stops.toml")).unwrap();
    SceneFamily::new(text.parse().unwrap(), "forcing.omega", 1).unwrap().0
}

/// States near the 4-impact orbits between Ω = 0.7023 and the grazing
/// (a run of the continuation with the variational `G_λ` at every
/// iteration, its `branch.csv` to 13 digits): only the corrector's
/// starting guesses, each checked below against the transcription.
const NEAR: [(f64, [f64; 2]); 6] = [
    (0.7023467396230, [0.6240224263415, -1.702975847044]),
    (0.7015011619829, [0.6268335239863, -1.706955999691]),
    (0.7012454334523, [0.6276844143383, -1.708157540890]),
    (0.7011273334521, [0.6280774837458, -1.708712093596]),
    (0.7010775030706, [0.6282433543667, -1.708946013663]),
    (0.7010506799471, [0.6283326458597, -1.709071914323]),
];

/// The transcription's round-off bound at an orbit of multiplier `mu`
/// (as `period_two.rs`'s): its own map, as the crate's, is computed to
/// about `ε |μ|` of the state.
fn bound(mu: f64) -> f64 {
    1e-12 * mu.max(1.0) + 1e-10
}

/// The crate's map at `(w, x)`: its Jacobian's largest eigenvalue's
/// modulus and the eigenvector of its smaller one (only to choose where
/// to plant a point and how near to ask it).
fn monodromy(fam: &SceneFamily, w: f64, x: &[f64]) -> (f64, [f64; 2]) {
    let img = fam.model(w).unwrap().flow(0.0, x, fam.period(w).unwrap(), true).unwrap();
    let j = img.jacobian.unwrap();
    let (a, b, c, d) = (j[(0, 0)], j[(0, 1)], j[(1, 0)], j[(1, 1)]);
    let (tr, det) = (a + d, a * d - b * c);
    let disc = (0.25 * tr * tr - det).max(0.0).sqrt();
    let big = 0.5 * tr + tr.signum() * disc;
    let small = det / big;
    let v = if b.abs() >= c.abs() { [b, small - a] } else { [small - d, c] };
    let n = v[0].hypot(v[1]);
    (big.abs(), [v[0] / n, v[1] / n])
}

/// At each Ω the corrector (the parameter held) accepts a fixed point of
/// the transcription with the 4 impacts, where `|P(x) − x|` cannot reach
/// the tolerance 1.7e-11 (the map's floor 4e-11 … 5e-8 there).
#[test]
fn the_corrector_converges_at_the_maps_round_off_floor() {
    let fam = family();
    for (w, x) in NEAR {
        let y = corrected(&fam, &x, w).unwrap_or_else(|e| panic!("Ω = {w}: {e}"));
        let (mu, _) = monodromy(&fam, w, &y);
        let (d, k) = residual(w, &y);
        eprintln!("Ω = {w}: |μ| {mu:.3e}, transcription residual {d:.2e}");
        assert!(d <= bound(mu) && k == 4, "Ω = {w}: |P(x) − x| = {d:e} (bound {:e}), {k} impacts", bound(mu));
    }
}

/// A point 1e-8 off the orbit along the smaller multiplier's direction
/// (where `|P(x) − x|` grows least: by 1e-8 |μ₂ − 1|, below 4 times the
/// floor where ‖P'‖ passes 1e7) is not accepted: the corrector moves it
/// to a fixed point of the transcription.
#[test]
fn a_point_off_the_branch_by_1e_8_is_not_accepted_at_the_floor() {
    let fam = family();
    for (w, x) in NEAR {
        let y = corrected(&fam, &x, w).unwrap();
        let (mu, v) = monodromy(&fam, w, &y);
        let planted = [y[0] + 1e-8 * v[0], y[1] + 1e-8 * v[1]];
        let (dp, _) = residual(w, &planted);
        let z = corrected(&fam, &planted, w).unwrap_or_else(|e| panic!("Ω = {w}: {e}"));
        let moved = (z[0] - planted[0]).abs().max((z[1] - planted[1]).abs());
        let (dz, k) = residual(w, &z);
        eprintln!("Ω = {w}: |μ| {mu:.2e}, planted residual {dp:.2e}, corrected {dz:.2e}, moved {moved:.2e}");
        assert!(moved >= 5e-9, "Ω = {w}: the planted point taken (moved {moved:e})");
        assert!(dz <= bound(mu) && k == 4, "Ω = {w}: |P(z) − z| = {dz:e}, {k} impacts");
    }
}
