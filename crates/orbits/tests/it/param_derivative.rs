//! `G_λ`, the derivative of the shooting map in the parameter that steers
//! the continuation's corrector and tangent (`continuation.rs`,
//! `param_derivative`), against the transcription of `between.rs` (the
//! closed-form flow between impacts, its own impact search, the
//! restitution by hand: no code of the crate) differentiated in Ω by
//! central differences at two steps, which agree with each other first.
//! The oscillator between symmetric stops, `x'' + 0.1 x' + x = 2 sin Ωt`,
//! `|x| <= 1`, e = 0.8, its map over `p` forcing periods `2πp/Ω`: the
//! horizon moves with Ω.

use crate::between::{map_between, E};
use signorini_orbits::{param_derivative, Family, Model, OrbitError};
use std::f64::consts::TAU;

/// The map over `p` forcing periods.
struct Between(usize);

impl Family for Between {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        crate::between::model(w)
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(self.0 as f64 * TAU / w)
    }
}

/// The transcription's map and its impacts (4000 samples a period).
fn map(p: usize, w: f64, x: [f64; 2]) -> ([f64; 2], usize) {
    let (y, k, _) = map_between(w, x, p, (-1.0, 1.0), E, 4000.0);
    (y, k)
}

/// `∂P/∂Ω` of the transcription by the central difference of step `d`.
fn central(p: usize, w: f64, x: [f64; 2], d: f64) -> [f64; 2] {
    let (a, b) = (map(p, w + d, x).0, map(p, w - d, x).0);
    [(a[0] - b[0]) / (2.0 * d), (a[1] - b[1]) / (2.0 * d)]
}

/// At two states whose runs have two impacts, none slow (the map smooth in Ω
/// there), with the parameter's scale 1 and 3: `G_λ` within 3e-6 of its
/// size of the transcription's, whose differences of step 1e-4 and 1e-5
/// agree to 1e-6 (the finer's truncation, a hundredth of the coarser's,
/// about 1e-8). `G_λ` is a forward difference of step `h` = 1e-7 Λ,
/// which errs by `h P''/2`: at Ω = 1.4 by 4.6e-7 and 1.5e-6 of its size
/// with Λ = 1 and 3 (in proportion to the step), 2.5e-8 at Ω = 2.5.
/// Dropping the period's dependence on Ω from the
/// crate's difference (the map at `Ω + h` over the horizon at `Ω`) leaves
/// out `ẋ(T) dT/dΩ` and fails.
#[test]
fn the_parameter_derivative_is_the_transcriptions_derivative_in_omega() {
    let cases: [(usize, f64, [f64; 2]); 2] = [(1, 2.5, [0.3, 1.2]), (1, 1.4, [-0.5, 0.8])];
    for (p, w, x) in cases {
        let (_, k) = map(p, w, x);
        assert!(k >= 1, "Ω = {w}, x = {x:?}, {p} periods: no impact");
        let (coarse, fine) = (central(p, w, x, 1e-4), central(p, w, x, 1e-5));
        let size = fine[0].abs().max(fine[1].abs());
        let agree = (coarse[0] - fine[0]).abs().max((coarse[1] - fine[1]).abs());
        assert!(agree <= 1e-6 * size, "Ω = {w}, x = {x:?}: the oracle's two steps differ by {agree:e} of {size:e}");
        for scale in [1.0, 3.0] {
            let gl = param_derivative(&Between(p), &x, w, scale).unwrap();
            let err = (gl[0] - fine[0]).abs().max((gl[1] - fine[1]).abs());
            eprintln!("Ω = {w}, x = {x:?}, {p} periods, {k} impacts, Λ = {scale}: G_λ {gl:?}, transcription {fine:?}, error {:e}", err / size);
            assert!(err <= 3e-6 * size, "Ω = {w}, x = {x:?}, Λ = {scale}: G_λ {gl:?} against the transcription's {fine:?} ({:e} of its size)", err / size);
        }
    }
}
