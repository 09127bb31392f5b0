//! The autonomous shooting (period unknown, a phase condition, the energy
//! fixed) on a conservative oscillator against its period in closed form
//! (derived here), and the nonsmooth modes of the bar (`modes`) against
//! what holds independently of the code: the positive homogeneity of the
//! bar without gap, the continuous bar's closed form, and bad input.

use signorini_fem::SymBand;
use signorini_orbits::modes::{backbone, energies};
use signorini_orbits::{autonomous_orbit, Model, Newton, OrbitError};
use signorini_schemes::{Bounds, Contact, Dynamics};

/// `x'' + ω² x = 0` (mass `MASS`, stiffness `MASS ω²`) under an elastic
/// stop at `x = D`.
const MASS: f64 = 2.0;
const OMEGA: f64 = 1.5;
const D: f64 = 0.3;

fn oscillator(stop: f64) -> Model {
    let mut m = SymBand::zeros(1, 0);
    m.set(0, 0, MASS);
    let mut k = SymBand::zeros(1, 0);
    k.set(0, 0, MASS * OMEGA * OMEGA);
    Model::new(Dynamics::new(m, k, vec![0.0], vec![Contact::new(0, Bounds { lo: f64::NEG_INFINITY, hi: stop }, false)]), 1.0).unwrap()
}

/// The closed form: the energy `E` gives the amplitude `A = √(2E/(M ω²))`;
/// from `x = −A` at rest the mass rises as `−A cos ωt`, reaches the stop
/// `D < A` at `ωt₁ = arccos(−D/A)`, is reflected (e = 1) and retraces its
/// path: `T = 2 arccos(−D/A)/ω`; without touching (`D ≥ A`), `2π/ω`.
fn period(energy: f64, stop: f64) -> f64 {
    let a = (2.0 * energy / (MASS * OMEGA * OMEGA)).sqrt();
    if stop >= a {
        std::f64::consts::TAU / OMEGA
    } else {
        2.0 * (-stop / a).acos() / OMEGA
    }
}

#[test]
fn the_autonomous_shooting_finds_the_oscillators_period_and_energy() {
    let model = oscillator(D);
    for energy in [0.2, 0.21, 0.5, 1.0, 4.0] {
        let a = (2.0 * energy / (MASS * OMEGA * OMEGA)).sqrt();
        // A start off the orbit: 10 % too low, moving, and the period 20 % off.
        let guess = [-0.9 * a, 0.1 * a * OMEGA];
        let exact = period(energy, D);
        let orbit = autonomous_orbit(&model, &guess, 1.2 * exact, energy, &Newton::default()).unwrap();
        let (e, _) = model.energy(0.0, &orbit.x).unwrap();
        assert!((orbit.period - exact).abs() <= 1e-10 * exact, "E = {energy}: T = {} against {exact}", orbit.period);
        assert!((e - energy).abs() <= 1e-10 * energy, "E = {energy}: the orbit's energy {e}");
        assert_eq!(orbit.impacts(), usize::from(D < a), "one impact a period above the contact threshold E = M ω² D²/2 = 0.2025, none below");
        // The phase condition: the orbit is on the section through the
        // guess normal to the flow there (here: the mass at rest at its
        // lowest point moves along v; the section fixes the phase).
        assert!(orbit.residual <= 1e-10 * a);
    }
}

#[test]
fn the_autonomous_shooting_refuses_bad_input() {
    let model = oscillator(D);
    let n = Newton::default();
    assert!(matches!(autonomous_orbit(&model, &[0.1], 1.0, 1.0, &n), Err(OrbitError::Size { given: 1, expected: 2 })));
    assert!(matches!(autonomous_orbit(&model, &[-0.1, 0.0], 1.0, -1.0, &n), Err(OrbitError::Option { option: "energy", .. })));
    assert!(matches!(autonomous_orbit(&model, &[-0.1, 0.0], 0.0, 1.0, &n), Err(OrbitError::Option { option: "period", .. })));
    assert!(matches!(autonomous_orbit(&model, &[0.0, 0.0], 1.0, 1.0, &n), Err(OrbitError::NoConvergence { .. })));
}

fn bar(m: usize, mass: &str, scheme: &str, gap: f64) -> toml::Table {
    format!("[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"clamped\"\ngap = {gap:?}\nelements = {m}\nmass = \"{mass}\"\nscheme = \"{scheme}\"\ndt = 0.01\nt_end = 10.0\n").parse().unwrap()
}
