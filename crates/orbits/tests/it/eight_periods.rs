//! The 8-period branch of `signorini continue
//! data/scenes/oscillator-two-stops.toml --param forcing.omega --from 1.5
//! --to 0.6 --switch` (`x'' + 0.1 x' + x = 2 cos Ωt`, `|x| <= 1`, e =
//! 0.8), its 24-impact orbits below Ω = 1.2912, where `‖P'‖` passes 1e6
//! and the slowest impact falls below 1e-2 of the fastest (2.5e-2 against
//! 2.54). There the slow-impact rule held the variational `G_λ` back and
//! the forward difference's, 48 % off it (4.9e5 of 1.0e6 at Ω =
//! 1.2909156), left Newton's residual where it started (8.3e-7 over 12
//! iterations): the branch stopped at 1.2909156. Checked against the
//! transcription of `between.rs` (the closed-form flow between impacts,
//! its own impact search, the restitution by hand; the section a quarter
//! period on: the cosine's phase).

use crate::between::{map_between_from, E};
use crate::continuation;
use signorini_orbits::{ContinuationOptions, SceneFamily};
use std::f64::consts::TAU;

/// Where the branch stopped before.
const STOPPED: f64 = 1.2909156418929;

#[test]
fn the_eight_period_branch_goes_on_past_its_old_stop() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/oscillator-two-stops.toml")).unwrap();
    let fam = SceneFamily::new(text.parse().unwrap(), "forcing.omega", 8).unwrap().0;
    // A point of the `--switch` run's 8-period branch (its `branch.csv`,
    // 13 digits): only the start's guess, corrected by the continuation.
    let from = 1.291277553659;
    let guess = [0.5497662628679, -0.2042036107903];
    // The run's parameter scale (its range 1.5 … 0.6).
    let opts = ContinuationOptions { max_points: 40, scale: Some(0.9), ..ContinuationOptions::new(from, 0.6) };
    let branch = continuation(&fam, &guess, &opts).unwrap();
    let mut past = 0;
    for p in &branch.points {
        let x = [p.orbit.x[0], p.orbit.x[1]];
        let map = |periods| map_between_from(p.param, 0.25 * TAU / p.param, x, periods, (-1.0, 1.0), E, 4000.0);
        let (y, k, _) = map(8);
        let r = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
        // Measured up to 7.6e-9 (|μ| 8e5 … 1.5e6 here).
        assert!(r <= 1e-8 * x[0].abs().max(x[1].abs()).max(1.0), "Ω = {}: |P(x) − x| = {r:e}", p.param);
        assert_eq!(k, 24, "Ω = {}: impacts over 8 periods", p.param);
        // An orbit of 8 periods, not of 4 (measured 2.1e-2 off).
        let (y4, _, _) = map(4);
        let r4 = (y4[0] - x[0]).abs().max((y4[1] - x[1]).abs());
        assert!(r4 > 1e-4, "Ω = {}: a fixed point of 4 periods ({r4:e})", p.param);
        past += usize::from(p.param < STOPPED);
    }
    // Measured: 30 of the 40 points past it, to 1.2903324 (the limit).
    assert!(past >= 20, "{past} points past {STOPPED}: {}", branch.end);
}
