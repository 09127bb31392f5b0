//! A family of scenes builds a value's model without the scene's own
//! validated run (its dynamics on the family's structure) and keeps the
//! last few values' dynamics: a value built again is not parsed again. Its
//! models must be the models of the dynamics the scene writes, at each
//! value, in any order: checked against the oscillator's dynamics written
//! here by hand (`x'' + 0.1x' + x = 2 sin Ωt` between the stops −1 and 0.5,
//! e = 0.3), their map and its Jacobian bit for bit, and the horizon
//! `2π/Ω` bit for bit.

use signorini_fem::SymBand;
use signorini_orbits::{Family, Model, SceneFamily};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};
use std::f64::consts::TAU;

fn by_hand(w: f64) -> Model {
    let contact = Contact::new(0, Bounds { lo: -1.0, hi: 0.5 }, false).with_restitution(Some(0.3));
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![contact])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: 2.0, omega: w } }])
        .with_damping(Some(SymBand::from_diagonal(&[0.1])));
    Model::new(dy, 0.3).unwrap()
}

#[test]
fn a_value_built_again_is_the_model_of_its_own_dynamics() {
    let doc: toml::Table = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstops = [-1.0, 0.5]\nrestitution = 0.3\n\
                            dt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\nprofile = \"sine\"\namplitude = 2.0\nomega = 5.6\n"
        .parse()
        .unwrap();
    let (family, w0) = SceneFamily::new(doc, "forcing.omega", 1).unwrap();
    assert_eq!(w0, 5.6);
    // Values and their shifts as a continuation asks them (G_λ's forward
    // difference), then earlier ones again (kept), then one evicted.
    let h = 1e-7;
    let values = [5.6, 5.6 + h, 5.7, 5.7 + h, 5.6, 5.7 + h, 4.0, 4.0 + h, 5.8, 5.9, 6.0, 5.6 + h, 4.0];
    // A state that impacts the upper stop within the period.
    let x = [0.3, 0.8];
    for w in values {
        let (model, horizon) = family.model_and_period(w).unwrap();
        assert_eq!(horizon.to_bits(), (TAU / w).to_bits(), "the horizon at {w}");
        let got = model.flow(0.0, &x, horizon, true).unwrap();
        let want = by_hand(w).flow(0.0, &x, TAU / w, true).unwrap();
        assert!(!want.events.is_empty(), "no impact at {w}");
        let bits = |v: &[f64]| v.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&got.x), bits(&want.x), "the map at {w}: {:?} against {:?}", got.x, want.x);
        let (a, b) = (got.jacobian.unwrap(), want.jacobian.unwrap());
        for i in 0..2 {
            for j in 0..2 {
                assert_eq!(a[(i, j)].to_bits(), b[(i, j)].to_bits(), "the Jacobian's ({i}, {j}) at {w}");
            }
        }
        // The model alone and the horizon alone: the same.
        assert_eq!(family.period(w).unwrap().to_bits(), horizon.to_bits());
        assert_eq!(bits(&family.model(w).unwrap().flow(0.0, &x, horizon, false).unwrap().x), bits(&want.x));
    }
}
