//! `MoreauJeanLockstep::projected` (through `LockstepBatch`,
//! `moreau-jean-projected(θ, e, γ)`): every lane bit for bit the single
//! `MoreauJeanProjected` run of its data (U^n, V^n, λ, the active bound at
//! every step), with the index set kept per lane and the positions'
//! projection acting (counted on the single runs); partial batches;
//! restitutions; lanes at rest and lanes pressed on a stop by a steady
//! load; a failing lane; typed refusals. The oracle is the single run
//! (`MoreauJean` with its `IndexSet`, then `MoreauJeanProjected::project`;
//! `SymBand::mul_vec` by diagonals, `BandLdlt::solve_in_place`,
//! `Projection::project`), checked by `check_lockstep` in every build of
//! the step. The problems and the shared cases are in `common`'s lockstep
//! part (the paper's pipe with its support motion).

use crate::common::{assert_contacts, lane, pipe, pressed_lanes, Engine, Extra};
use signorini_schemes::{LaneVector, LockstepScheme, MoreauJeanProjected, SchemeError};

/// `moreau-jean-projected(θ, e, γ)`'s engine against its single runs (and V).
fn mjp(theta: f64, gamma: f64) -> Engine<MoreauJeanProjected> {
    Engine::new(
        LockstepScheme::MoreauJeanProjected { theta, restitution: 0.0, gamma },
        move |l, dt| MoreauJeanProjected::new("single".into(), l.dynamics.clone(), theta, l.restitution, gamma, dt, &l.initial).unwrap(),
        vec![Extra { name: "V", vector: LaneVector::Velocity, single: |s: &MoreauJeanProjected| s.velocity(), from: 0 }],
    )
}

/// Four lanes of the paper beam (θ = 1/2, γ = 1/2, e = 0) with different
/// ω and A, narrow stops so the tip rattles and the positions' projection
/// acts (more than 5 steps on each of the first three): 4000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    let seen = mjp(0.5, 0.5).rattles(5e-5, 4000);
    let p: Vec<u64> = seen.singles.iter().map(|s| s.projections()).collect();
    assert!(p[..3].iter().all(|&p| p > 5), "the first three lanes projected: {p:?}");
}

/// An amplitude sweep on 8 lanes (the projection acting on each), and two
/// forcing terms per lane on 4; θ = 0.7, γ = 0.3.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    let seen = mjp(0.7, 0.3).amplitude_and_two_terms(5e-5, 5e-5, 3000);
    assert!(seen.singles.iter().all(|s| s.projections() > 0), "every lane of the amplitude sweep projected");
}

/// Partial batches: 4 lanes in a batch of 8 (one with ω dt = 1), 1 lane
/// in a batch of 2.
#[test]
fn partial_batches_are_bit_identical() {
    mjp(0.5, 0.5).partial_batches(5e-5, 2e4, (3000, 2000));
}

/// 16 lanes, 11 in use: frequencies, amplitudes, restitutions 1/2 and 1,
/// and two lanes at rest (never projected).
#[test]
fn sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    let seen = mjp(0.5, 0.5).sixteen(5e-5, 3000);
    assert_eq!((seen.singles[7].projections(), seen.singles[8].projections()), (0, 0), "the lanes at rest are never projected");
}

/// Short beams, J = 4, 5, 6, 8, θ = 1/2 and 1, a contact's own
/// restitution and a one-sided obstacle; contacts off the tip (mid-beam,
/// row n-4, the tip's slope).
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    for theta in [0.5, 1.0] {
        mjp(theta, 0.5).short_beams(5e-5, 2000);
    }
    mjp(0.5, 0.5).off_the_tip(5e-5, &[(20, 0.004), (34, 0.008), (37, 0.01)], 2000);
}

/// Lanes at rest on their lower stop pressed onto it by a steady load
/// (`U = 0`, `V = 0`, the stop at 0, no forcing): their contact joins the
/// index set at once and stays held, the velocity law holding it and the
/// projection putting back what it lets through; beside them vibrating
/// lanes with a steady load as well.
#[test]
fn lanes_pressed_on_a_stop_by_a_steady_load_are_bit_identical() {
    let counts = mjp(0.5, 0.5).counts(8, 5e-5, pressed_lanes(2.0), 3000);
    for k in [0, 2, 4] {
        assert!(counts[k].0 > 2500, "lane {k} is held on its stop: {:?}", counts[k]);
    }
    assert_contacts(&[counts[1], counts[3]], "the vibrating lanes");
}

/// Lanes whose forcing overflows report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    mjp(0.5, 0.5).failing_lane(5e-5, 1500);
}

#[test]
fn refusals_are_typed() {
    mjp(0.5, 0.5).refusals(5e-5);
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    assert!(matches!(mjp(0.4, 0.5).batch(4, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "theta", .. })));
    assert!(matches!(mjp(0.5, 1.5).batch(4, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "gamma", .. })));
    // What the single run refuses: a non-positive step.
    assert!(mjp(0.5, 0.5).batch(4, 0.0, vec![base()]).is_err());
}
