//! The tests of `signorini_run::beam` that were unit tests in src/beam.rs (the
//! library is not compiled a second time as a test harness).

use signorini_run::beam::*;
use signorini_run::Stop;
use signorini_schemes::SchemeSpec;

/// `ρS` of the paper's tube, computed here from its data: outer
/// diameter 1 cm, wall 0.5 mm, ρ = 8000 kg/m³.
fn rho_s() -> f64 {
    8000.0 * std::f64::consts::PI / 4.0 * (0.01f64.powi(2) - 0.009f64.powi(2))
}

#[test]
fn penalty_units_convert_as_documented() {
    let r = rho_s();
    assert!((r - 0.119_380_52).abs() < 1e-8, "ρS = {r}");
    assert_eq!(PenaltyUnits::Unscaled.kappa(1e8, r), 1e8);
    let k = PenaltyUnits::NewtonPerMetre.kappa(1e8, r);
    assert!((k / 8.376_576e8 - 1.0).abs() < 1e-6, "κ = {k}");
    assert_eq!(PenaltyUnits::default(), PenaltyUnits::NewtonPerMetre);
}

/// Largest `|tip| − 0.1` over the first impacts ([0, 0.1] s; the first
/// contact is at 0.0878 s) with the paper's 10⁸ read in `units`.
fn first_violation(units: PenaltyUnits) -> f64 {
    let pipe = Pipe::paper();
    let scene = BeamScene::new("test", 19, 5e-6, 0.1, SchemeSpec::penalty(10.0, false)).with_spring(1e8);
    let BuiltBeam { stepper: mut s, beam, .. } = BeamSetup::new(pipe, scene).with_units(units).build().unwrap();
    let mut worst = f64::NEG_INFINITY;
    for _ in 0..20_000 {
        s.step().unwrap();
        worst = worst.max(s.displacement()[beam.tip_dof()].abs() - 0.1);
    }
    worst
}

/// A stop without its own stiffness gets the scene's spring as is (N/m,
/// like the tip's), not scaled by its stiffness diagonal: the same run
/// as with every stop's stiffness given explicitly.
#[test]
fn stops_without_stiffness_get_the_scene_spring() {
    let pipe = Pipe::paper();
    let scene = BeamScene::new("test", 19, 5e-6, 0.02, SchemeSpec::penalty(10.0, false)).with_spring(1e8);
    let stops = vec![Stop::new(19, -0.1, 0.1), Stop::new(10, -0.002, 0.002)];
    let given: Vec<Stop> = stops.iter().map(|s| Stop { stiffness: Some(1e8), ..*s }).collect();
    let mut a = BeamSetup::new(pipe, scene).with_stops(stops).build().unwrap().stepper;
    let mut b = BeamSetup::new(pipe, scene).with_stops(given).build().unwrap().stepper;
    let mut engaged = false;
    for _ in 0..4000 {
        a.step().unwrap();
        b.step().unwrap();
        engaged |= a.contact_forces()[1] != 0.0;
        assert_eq!(a.displacement(), b.displacement());
    }
    assert!(engaged, "the mid-span stop must act for the test to mean anything");
}

/// The unscaled reading is a spring ρS times (8.4×) softer, so the tip
/// goes further past the stop; the default reading is N/m.
#[test]
fn unscaled_penalty_is_softer_and_build_reads_newton_per_metre() {
    let (phys, unscaled) = (first_violation(PenaltyUnits::NewtonPerMetre), first_violation(PenaltyUnits::Unscaled));
    assert!(phys > 0.0 && unscaled > 2.0 * phys, "violations: N/m {phys:e}, unscaled {unscaled:e}");
    // A linear spring stopping the same tip: penetration ∝ 1/sqrt(κ), i.e.
    // a ratio sqrt(1/ρS) = 2.89; chatter makes it approximate.
    let ratio = unscaled / phys;
    assert!((2.0..4.0).contains(&ratio), "ratio {ratio}");
    let pipe = Pipe::paper();
    let scene = BeamScene::new("test", 19, 5e-6, 0.1, SchemeSpec::penalty(10.0, false)).with_spring(1e8);
    let BuiltBeam { stepper: mut s, beam, .. } = BeamSetup::new(pipe, scene).build().unwrap();
    let mut worst = f64::NEG_INFINITY;
    for _ in 0..20_000 {
        s.step().unwrap();
        worst = worst.max(s.displacement()[beam.tip_dof()].abs() - 0.1);
    }
    assert_eq!(worst, phys);
}
