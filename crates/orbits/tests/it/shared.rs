//! A family of scenes shares its models' load-free parts (the flows' and
//! the linearisation's modes) across parameter values where the structure
//! stays (a forcing's frequency, a stop), and builds them anew where it
//! changes (a stiffness, a damping). Every value visited, in an order
//! that goes back and forth between structures, against the closed-form
//! period-1 orbits of `signorini_exact::oscillator` and their multipliers:
//! a model on another structure's modes misses both.

use crate::oscillator::{closed_orbits_at, sorted};
use signorini_orbits::{periodic_orbit, Family, Newton, SceneFamily};

/// `(k, ζ, gap, Ω)` of the scene with one of them set.
type Params = (f64, f64, f64, f64);

/// The family in `path` at each of `values` in turn (`params` the closed
/// form's at a value): each orbit and its multipliers to 1e-9.
fn check(path: &str, values: &[f64], params: impl Fn(f64) -> Params) {
    let doc = crate::oscillator(0.05, 0.2, 0.8, 2.0);
    let fam = SceneFamily::new(doc, path, 1).unwrap().0;
    for &p in values {
        let mut seen = 0;
        let model = fam.model(p).unwrap();
        let t = fam.period(p).unwrap();
        let (k, zeta, gap, omega) = params(p);
        for (x, mu, _) in closed_orbits_at(k, zeta, gap, omega) {
            let guess = [x[0] * 1.01 + 1e-3, x[1] * 0.99];
            let orbit = periodic_orbit(&model, 0.0, t, &guess, &Newton::default()).unwrap_or_else(|e| panic!("{path} = {p}: {e}"));
            let err = (orbit.x[0] - x[0]).abs().max((orbit.x[1] - x[1]).abs());
            assert!(err <= 1e-9, "{path} = {p}: state {:?} vs closed form {x:?} (error {err:e})", orbit.x);
            let got = sorted(orbit.multipliers.iter().map(|m| [m.re, m.im]).collect());
            for (a, b) in got.iter().zip(&sorted(mu.to_vec())) {
                let e = (a[0] - b[0]).hypot(a[1] - b[1]);
                assert!(e <= 1e-9 * a[0].hypot(a[1]).max(1.0), "{path} = {p}: multiplier {a:?} vs closed form {b:?} (error {e:e})");
            }
            seen += 1;
        }
        assert!(seen > 0, "{path} = {p}: no closed-form orbit to check");
    }
}

#[test]
fn a_family_in_a_load_or_a_stop_shares_its_modes_and_keeps_the_closed_form_orbits() {
    check("forcing.omega", &[2.2, 2.4, 2.3, 2.2, 2.35], |w| (1.0, 0.05, 0.2, w));
    check("oscillator.stop", &[0.2, 0.25, 0.15, 0.2], |g| (1.0, 0.05, g, 2.0));
}

#[test]
fn a_family_in_a_stiffness_or_a_damping_builds_each_structures_modes() {
    check("oscillator.stiffness", &[1.0, 1.4, 0.8, 1.0, 1.4], |k| (k, 0.05, 0.2, 2.0));
    check("oscillator.damping_ratio", &[0.05, 0.2, 0.01, 0.05], |z| (1.0, z, 0.2, 2.0));
}
