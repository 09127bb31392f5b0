//! The map's flow read on the way (`Model::flow_reading`): a continuation's
//! return check takes an orbit's states after `k` forcing periods, and its
//! mirror images' half periods, from the corrector's last flow instead of
//! flowing to each. The readings must change nothing: the image, its
//! Jacobian and events are `flow`'s to the end bit for bit, and each state
//! read is `flow`'s to that time bit for bit (the same run, neither
//! started again nor re-based at a reading). Checked on the isola's
//! oscillator (isola.rs), the oscillator between symmetric stops read at
//! its own impacts' instants, and a plastic stop with held phases; the
//! isola's readings also against the transcription of between.rs (no code
//! of the crate) to 1e-9.

use crate::between::{flow_between, C, F};
use signorini_fem::SymBand;
use signorini_orbits::{Image, Model};
use signorini_schemes::events::EventKind;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};
use std::f64::consts::TAU;

/// `x'' + 0.1 x' + x = 2 sin Ωt`, `lo <= x <= hi`, restitution `e`.
fn oscillator(w: f64, (lo, hi): (f64, f64), e: f64) -> Model {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo, hi }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: F, omega: w } }])
        .with_damping(Some(SymBand::from_diagonal(&[C])));
    Model::new(dy, e).unwrap()
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// An image's state, Jacobian, events (time, impulse, contact), held
/// contacts and field, as bits.
#[derive(Debug, PartialEq)]
struct ImageBits {
    x: Vec<u64>,
    jacobian: Vec<u64>,
    events: Vec<(u64, u64, usize)>,
    held: Vec<usize>,
    field: Vec<u64>,
}

fn image_bits(img: &Image) -> ImageBits {
    let j = img.jacobian.as_ref().expect("asked for");
    let jacobian = (0..j.nrows()).flat_map(|r| (0..j.ncols()).map(move |c| j[(r, c)].to_bits())).collect();
    let events = img.events.iter().map(|e| (e.t.to_bits(), e.impulse.to_bits(), e.contact)).collect();
    ImageBits { x: bits(&img.x), jacobian, events, held: img.held.clone(), field: bits(&img.field) }
}

/// Reads `model`'s flow from `x` over `tau` at `reads` and checks it
/// against plain flows bit for bit; returns the states read.
fn read_and_check(model: &Model, x: &[f64], tau: f64, reads: &[f64]) -> Vec<Vec<f64>> {
    let (img, states) = model.flow_reading(0.0, x, tau, true, reads).unwrap();
    let plain = model.flow(0.0, x, tau, true).unwrap();
    assert_eq!(image_bits(&img), image_bits(&plain), "the image read on the way differs from the flow's");
    assert_eq!(states.len(), reads.len());
    for (r, s) in reads.iter().zip(&states) {
        let to = model.flow(0.0, x, *r, false).unwrap();
        assert_eq!(bits(s), bits(&to.x), "the state read at {r} is not the flow's to it: {s:?} against {:?}", to.x);
    }
    states
}

#[test]
fn a_flow_read_on_the_way_is_the_flow_bit_for_bit() {
    // The isola's orbits: 5 forcing periods, read as the return check
    // reads them (`k T / 5` and `(2k + 1) T / 10`).
    let (w, stops, e) = (5.6, (-1.0, 0.5), 0.3);
    let model = oscillator(w, stops, e);
    let period = 5.0 * TAU / w;
    let x = [-0.5385, -0.1181];
    let mut reads: Vec<f64> = (1..5).map(|k| period * k as f64 / 5.0).chain((0..5).map(|k| (2 * k + 1) as f64 * (0.5 * period / 5.0))).collect();
    reads.sort_by(f64::total_cmp);
    let states = read_and_check(&model, &x, period, &reads);
    // Each against the transcription's flow to it.
    for (r, s) in reads.iter().zip(&states) {
        let (y, _, _) = flow_between(w, 0.0, *r, x, stops, e, 1000.0);
        let off = (y[0] - s[0]).abs().max((y[1] - s[1]).abs());
        assert!(off <= 1e-9, "the state read at {r}: {s:?}, the transcription's {y:?} ({off:e} off)");
    }
    assert!(model.flow(0.0, &x, period, false).unwrap().events.iter().any(|e| e.kind == EventKind::Impact), "the isola's run has an impact");

    // Between symmetric stops, read at its own impacts' instants, and a
    // hair before and after each.
    let model = oscillator(1.3, (-1.0, 1.0), 0.8);
    let period = 3.0 * TAU / 1.3;
    for x in [[0.0, 0.0], [0.9, -1.5], [-0.3, 2.0]] {
        let events = model.flow(0.0, &x, period, false).unwrap().events;
        assert!(events.len() >= 2, "impacts in the run from {x:?}");
        let mut reads: Vec<f64> =
            events.iter().flat_map(|e| [e.t * (1.0 - 1e-12), e.t, e.t * (1.0 + 1e-12)]).chain((1..40).map(|k| period * k as f64 / 40.0)).filter(|&r| r > 0.0 && r < period).collect();
        reads.sort_by(f64::total_cmp);
        read_and_check(&model, &x, period, &reads);
    }

    // A plastic stop: held phases and their releases.
    let model = oscillator(1.3, (-3.0, 0.2), 0.0);
    let period = 2.0 * TAU / 1.3;
    let x = [0.0, 0.5];
    let events = model.flow(0.0, &x, period, false).unwrap().events;
    assert!(events.iter().any(|e| e.kind == EventKind::Release), "a held phase released in the run");
    let mut reads: Vec<f64> = events.iter().map(|e| e.t).chain((1..25).map(|k| period * k as f64 / 25.0)).filter(|&r| r > 0.0 && r < period).collect();
    reads.sort_by(f64::total_cmp);
    read_and_check(&model, &x, period, &reads);
}
