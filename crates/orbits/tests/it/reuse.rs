//! A model keeps its event runs and starts them again at each evaluation
//! (`EventDriven::restart`): whatever it ran before — flows from other
//! states, with held phases and chatter, margins — its flow from a state
//! and the Jacobian are a new model's, bit for bit.

use signorini_fem::SymBand;
use signorini_orbits::Model;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};

/// Two unit masses, springs 1 (the second grounded), Rayleigh damping,
/// a stop above dof 1 at `0.2` pressed by the steady load `p`, a sine on dof 0.
fn model(p: f64) -> Model {
    let band = |d: f64, o: f64| {
        let mut b = SymBand::zeros(2, 1);
        b.set(0, 0, d);
        b.set(1, 1, d);
        b.set(0, 1, o);
        b
    };
    let dy = Dynamics::new(band(1.0, 0.0), band(2.0, -1.0), vec![0.0, p], vec![Contact::new(1, Bounds { lo: f64::NEG_INFINITY, hi: 0.2 }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.2, 0.0], time: TimeProfile::Sine { amplitude: 1.0, omega: 1.3 } }])
        .with_damping(Some(band(0.06, -0.02)));
    Model::new(dy, 0.6).unwrap()
}

fn bits(img: &signorini_orbits::Image) -> Vec<u64> {
    let j = img.jacobian.as_ref().expect("asked for");
    let mut out: Vec<u64> = img.x.iter().chain(&img.field).map(|x| x.to_bits()).collect();
    out.extend((0..j.nrows()).flat_map(|r| (0..j.ncols()).map(move |c| (r, c))).map(|(r, c)| j[(r, c)].to_bits()));
    out.extend(img.events.iter().flat_map(|e| [e.t, e.velocity_before, e.velocity_after, e.impulse].map(f64::to_bits)));
    out.extend(img.held.iter().map(|&h| h as u64));
    out
}

#[test]
fn a_models_flows_do_not_depend_on_what_it_ran_before() {
    // p = 0.5: pressed on the stop (held phases, chatter to rest).
    for p in [0.0, 0.5] {
        let x = [0.05, 0.1, -0.3, 0.4];
        let want = bits(&model(p).flow(0.0, &x, 9.0, true).unwrap());
        let used = model(p);
        for y in [[0.0, 0.19, 0.0, 2.0], [-0.5, 0.0, 1.5, -1.0]] {
            used.flow(0.3, &y, 14.0, true).unwrap();
            used.margin(0.0, &y, 6.0).unwrap();
        }
        let got = used.flow(0.0, &x, 9.0, true).unwrap();
        assert!(got.events.len() > 2, "p = {p}: {} events", got.events.len());
        assert_eq!(bits(&got), want, "p = {p}: a used model's flow differs from a new one's");
    }
}
