//! `MoreauJeanLockstep` (through `LockstepBatch`, `moreau-jean(θ, e, γ)`):
//! every lane bit for bit the single `MoreauJean` run of its data (U^n,
//! V^n, λ, the active bound at every step), through repeated impacts on
//! both stops; partial batches; restitutions; lanes at rest; a failing
//! lane; typed refusals. The oracle is the single run (a separate code
//! path: `SymBand::mul_vec` by diagonals, `BandLdlt::solve_in_place`,
//! `Projection::project`). Every build of the step is checked: the one the
//! CPU selects (AVX-512 or AVX2 where available), the AVX2 one
//! (`without_avx512()`) and the baseline x86-64 one (`portable()`). The
//! problems and the cases shared by every engine are in `common`'s
//! lockstep part (the paper's pipe with its support motion).

use crate::common::{lane, pipe, Engine, Extra};
use signorini_schemes::{LaneVector, LockstepScheme, MoreauJean, SchemeError};

/// `moreau-jean(θ, e, γ)`'s engine against its single runs (and V).
fn mj(theta: f64, gamma: f64) -> Engine<MoreauJean> {
    Engine::new(
        LockstepScheme::MoreauJean { theta, restitution: 0.0, gamma },
        move |l, dt| MoreauJean::new("single".into(), l.dynamics.clone(), theta, l.restitution, gamma, dt, &l.initial).unwrap(),
        vec![Extra { name: "V", vector: LaneVector::Velocity, single: |s: &MoreauJean| s.velocity(), from: 0 }],
    )
}

/// Four lanes of the paper beam (θ = 1/2, γ = 1/2, e = 0) with different
/// ω and A, narrow stops so the tip rattles: 4000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    mj(0.5, 0.5).rattles(5e-5, 4000);
}

/// An amplitude sweep (same profile in every lane: means shared) on 8
/// lanes, and two forcing terms per lane (`Sampler`'s phasors) on 4;
/// θ = 0.7, γ = 0.3.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    mj(0.7, 0.3).amplitude_and_two_terms(5e-5, 5e-5, 3000);
}

/// Partial batches: 4 lanes in a batch of 8 (one with ω dt = 1), 1 lane in
/// a batch of 2.
#[test]
fn partial_batches_are_bit_identical() {
    mj(0.5, 0.5).partial_batches(5e-5, 2e4, (3000, 2000));
}

/// 16 lanes (the sweeps' widest engine), 11 in use: frequencies,
/// amplitudes, restitutions 1/2 and 1, and two lanes at rest.
#[test]
fn sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    mj(0.5, 0.5).sixteen(5e-5, 3000);
}

/// Short beams, J = 4, 5, 6, 8, θ = 1/2 and 1, with a contact's own
/// restitution and a one-sided obstacle; and contacts off the tip
/// (mid-beam, row n-4, the tip's slope).
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    for theta in [0.5, 1.0] {
        mj(theta, 0.5).short_beams(5e-5, 2000);
    }
    mj(0.5, 0.5).off_the_tip(5e-5, &[(20, 0.004), (34, 0.008), (37, 0.01)], 2000);
}

/// Lanes whose forcing overflows report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    mj(0.5, 0.5).failing_lane(5e-5, 1500);
}

#[test]
fn refusals_are_typed() {
    mj(0.5, 0.5).refusals(5e-5);
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    assert!(matches!(mj(0.4, 0.5).batch(4, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "theta", .. })));
    assert!(matches!(mj(0.5, 1.5).batch(4, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "gamma", .. })));
}
