//! The impact oscillator between two stops (`−g <= x <= g`), its symmetric
//! period-1 orbit (as many impacts on each stop): the variational Jacobian
//! against differences of the exact map, and the symmetry the orbit must
//! have (`x(t + T/2) = −x(t)`: an independent check of the shooting, which
//! knows nothing of it).

use signorini_fem::SymBand;
use signorini_orbits::{periodic_orbit, Model, Newton};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};
use std::f64::consts::TAU;

const W: f64 = 0.8;
const G: f64 = 1.0;

fn model() -> Model {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: -G, hi: G }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: 2.0, omega: W } }])
        .with_damping(Some(SymBand::from_diagonal(&[0.1])));
    Model::new(dy, 0.8).unwrap()
}

#[test]
fn the_symmetric_two_impact_orbit_and_its_jacobian() {
    let m = model();
    let t = TAU / W;
    let x = m.flow(0.0, &[0.0, 0.0], 300.0 * t, false).unwrap().x;
    let orbit = periodic_orbit(&m, 0.0, t, &x, &Newton::default()).unwrap();
    let k = orbit.impacts();
    assert!(k >= 2 && k % 2 == 0, "as many impacts on each stop: {k}");
    let stops: Vec<f64> = orbit.events.iter().map(|e| e.velocity_before.signum()).collect();
    assert!(stops.contains(&1.0) && stops.contains(&-1.0), "both stops hit: {stops:?}");
    // Half a period later the state is the mirror image (the forcing
    // changes sign, the stops are symmetric).
    let half = m.flow(0.0, &orbit.x, t / 2.0, false).unwrap().x;
    assert!((half[0] + orbit.x[0]).abs() < 1e-10 && (half[1] + orbit.x[1]).abs() < 1e-10, "{half:?} vs −{:?}", orbit.x);
    let j = orbit.monodromy;
    for c in 0..2 {
        let h = 1e-7;
        let (mut p, mut q) = (orbit.x.clone(), orbit.x.clone());
        p[c] += h;
        q[c] -= h;
        let (fp, fq) = (m.flow(0.0, &p, t, false).unwrap().x, m.flow(0.0, &q, t, false).unwrap().x);
        for r in 0..2 {
            let fd = (fp[r] - fq[r]) / (2.0 * h);
            assert!((fd - j[(r, c)]).abs() <= 1e-6 * (1.0 + fd.abs()), "J[{r},{c}] = {} vs {fd}", j[(r, c)]);
        }
    }
    // det J = r^{2k} e^{−c T} (each impact scales the area by r², the damping by e^{−cT}).
    let det = j[(0, 0)] * j[(1, 1)] - j[(0, 1)] * j[(1, 0)];
    let want = 0.8f64.powi(2 * k as i32) * (-0.1 * t).exp();
    assert!((det - want).abs() <= 1e-9 * want, "det {det} vs {want}");
}
