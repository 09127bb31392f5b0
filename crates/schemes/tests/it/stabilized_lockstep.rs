//! `ContactStabilizedLockstep` (through `LockstepBatch`,
//! `contact-stabilized`): every lane bit for bit the single
//! `ContactStabilized` run of its data (U^n, V^n, the stabilised predictor,
//! λ, the active bound at every step), through repeated contacts with both
//! stops; partial batches; lanes at rest; a failing lane; typed refusals.
//! The oracle is the single run (a separate code path: `SymBand::mul_vec`
//! by diagonals, `add_terms`, `BandLdlt::solve_in_place`, and both
//! projections through the several-contacts solve `MultiSolve`, principal
//! pivoting with a dense Cholesky factor). Every build of the step is
//! checked: the one the CPU selects (AVX-512 or AVX2 where available), the
//! AVX2 one (`without_avx512()`) and the baseline x86-64 one
//! (`portable()`). The problems and the shared cases are in `common`'s
//! lockstep part (the paper's pipe with its support motion).

use crate::common::{assert_contacts, check_lane_refusals, lane, loaded, pipe, Engine, Extra};
use signorini_schemes::{Bounds, ContactStabilized, LaneVector, LockstepLane, LockstepScheme, SchemeError};

/// `contact-stabilized`'s engine against its single runs (and V, the predictor).
fn cs() -> Engine<ContactStabilized> {
    Engine::new(
        LockstepScheme::ContactStabilized,
        |l, dt| ContactStabilized::new("single".into(), l.dynamics.clone(), dt, &l.initial).unwrap(),
        vec![
            Extra { name: "V", vector: LaneVector::Velocity, single: |s: &ContactStabilized| s.velocity(), from: 0 },
            Extra { name: "predictor", vector: LaneVector::Predictor, single: |s: &ContactStabilized| s.predictor(), from: 1 },
        ],
    )
}

/// Four lanes of the paper beam with different ω and A, narrow stops so
/// the tip rattles: 4000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    cs().rattles(5e-5, 4000);
}

/// An amplitude sweep (same profile in every lane: samples shared) on 8
/// lanes, and two forcing terms per lane (`Sampler`'s phasors) on 4; a
/// larger step on the first.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    cs().amplitude_and_two_terms(1e-4, 5e-5, 3000);
}

/// Partial batches: 4 lanes in a batch of 8 (one with ω dt = 1: a fast
/// forcing), 1 lane in a batch of 2.
#[test]
fn partial_batches_are_bit_identical() {
    cs().partial_batches(5e-5, 2e4, (3000, 2000));
}

/// 16 lanes (the sweeps' widest engine), 11 in use: frequencies,
/// amplitudes, and two lanes at rest with zero forcing (A = 0 and A = -0)
/// at lanes 4 and 6 (no restitution: the scheme has no impact law).
#[test]
fn sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let mut lanes: Vec<LockstepLane> = (0..9).map(|i| lane(pipe(19, 0.1 + 0.05 * i as f64, 9.5 + 7.0 * i as f64, stops), 0.0)).collect();
    lanes.insert(4, lane(pipe(19, 0.0, 10.0, stops), 0.0));
    lanes.insert(6, lane(pipe(19, -0.0, 12.0, stops), 0.0));
    let counts = cs().counts(16, 5e-5, lanes, 3000);
    assert_eq!((counts[4], counts[6]), ((0, 0), (0, 0)), "the lanes at rest stay at rest");
    let moving: Vec<(usize, usize)> = counts.iter().enumerate().filter(|(k, _)| *k != 4 && *k != 6).map(|(_, c)| *c).collect();
    assert_contacts(&moving, "the moving lanes");
}

/// Short beams, J = 4, 5, 6, 8 (8 to 16 unknowns: the ring's first and
/// last rows overlap), with a one-sided obstacle; and contacts off the tip
/// (mid-beam and row n-4: the step finished in a pass after the backward
/// sweep; row n-3, the first of the last three, and the tip's slope: inside
/// it, as at the tip).
#[test]
fn short_beams_and_contacts_off_the_tip_are_bit_identical() {
    let stops = (-0.01, 0.01);
    for j in [4, 5, 6, 8] {
        let lanes = vec![lane(pipe(j, 0.2, 10.0, stops), 0.0), lane(pipe(j, 0.2, 37.0, stops), 0.0), lane(pipe(j, 0.35, 23.5, stops), 0.0), lane(pipe(j, 0.3, 20.0, (-0.01, f64::INFINITY)), 0.0)];
        assert_contacts(&cs().counts(4, 5e-5, lanes, 2000), &format!("J = {j}"));
    }
    cs().off_the_tip(5e-5, &[(20, 0.004), (34, 0.008), (35, 0.01), (37, 0.01)], 2000);
}

/// Lanes whose forcing overflows report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    cs().failing_lane(5e-5, 1500);
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    let eng = cs();
    check_lane_refusals(|lanes| eng.batch(4, 5e-5, lanes).err(), base);
    // No impact law: a restitution is refused, in range or not.
    for e in [0.5, 1.0, 1.5] {
        let mut d = base();
        d.restitution = e;
        assert!(matches!(eng.batch(4, 5e-5, vec![base(), d]).err(), Some(SchemeError::Invalid { field: "restitution", .. })), "e = {e}");
    }
    // What the single run refuses: a non-positive step.
    assert!(eng.batch(4, 0.0, vec![base()]).is_err() && ContactStabilized::new("s".into(), base().dynamics, 0.0, &base().initial).is_err());
}

/// Lanes resting on their lower stop at static equilibrium (`U = K⁻¹ F`
/// under a steady load, the stop at that `u_c` exactly, `V = 0`): the
/// contact value hovers within a few ulps of the bound, so both solves
/// start from the status they kept (their warm start) with values inside
/// their pivoting tolerance; beside them, vibrating lanes with a steady
/// load as well (`τ²/4 (2F − K U)` in full).
#[test]
fn lanes_resting_on_a_stop_and_steady_loads_are_bit_identical() {
    let resting = |j: usize, p: f64| {
        let (mut dy, mut init) = pipe(j, 0.0, 10.0, (0.0, 0.0));
        let shape = pipe(j, 1.0, 10.0, (0.0, 0.0)).0.forcing[0].shape.clone();
        dy.load = shape.iter().map(|g| -p * g).collect();
        let mut u = dy.load.clone();
        dy.stiffness.factor().unwrap().solve_in_place(&mut u);
        let c = dy.contacts[0].dof;
        dy.contacts[0].bounds = Bounds { lo: u[c], hi: u[c] + 0.01 };
        init.u = u;
        lane((dy, init), 0.0)
    };
    let lanes = vec![resting(19, 0.1), loaded(0.2, 10.0, 0.05), resting(19, 1e-3), loaded(0.3, 31.0, -0.02), resting(19, 2.0)];
    let counts = cs().counts(8, 5e-5, lanes, 3000);
    for k in [0, 2, 4] {
        assert!(counts[k].0 > 100, "lane {k} rests on its stop: {:?}", counts[k]);
    }
    assert_contacts(&[counts[1], counts[3]], "the vibrating lanes");
}
