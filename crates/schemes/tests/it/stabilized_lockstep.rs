//! `ContactStabilizedLockstep`: every lane bit for bit the single
//! `ContactStabilized` run of its data (U^n, V^n, the stabilised predictor,
//! λ, the active bound at every step), through repeated contacts with both
//! stops; partial batches; lanes at rest; a failing lane; typed refusals.
//! The oracle is the single run (a separate code path: `SymBand::mul_vec`
//! by diagonals, `add_terms`, `BandLdlt::solve_in_place`, and both
//! projections through the several-contacts solve `MultiSolve`, principal
//! pivoting with a dense Cholesky factor). Every build of the step is
//! checked: the one the CPU selects (AVX-512 or AVX2 where available), the
//! AVX2 one (`without_avx512()`) and the baseline x86-64 one
//! (`portable()`). The problems are the Paoli–Schatzman engine's
//! (`lockstep.rs`: the paper's pipe with its support motion).

use super::lockstep::{failing_lanes, lane, pipe, pipe_harmonics};
use crate::common::{check_lane_refusals, check_lockstep, Extra};
use signorini_schemes::{Bounds, ContactStabilized, ContactStabilizedLockstep, Harmonic, LockstepLane, SchemeError, Stepper};

/// Steps the batch (every build) and each lane's single run `steps` times
/// and compares them bit for bit at every step ([`check_lockstep`]; and
/// V, predictor); returns per lane the number of steps held at the
/// lower and upper bound.
fn compare<const L: usize>(dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Vec<(usize, usize)> {
    let mut singles: Vec<ContactStabilized> = lanes.iter().map(|l| ContactStabilized::new("single".into(), l.dynamics.clone(), dt, &l.initial).unwrap()).collect();
    let extras = [
        Extra { name: "V", lane: |b: &ContactStabilizedLockstep<L>, k, out| b.velocity_into(k, out), single: |s: &ContactStabilized| s.velocity(), from: 0 },
        Extra { name: "predictor", lane: |b: &ContactStabilizedLockstep<L>, k, out| b.predictor_into(k, out), single: |s: &ContactStabilized| s.predictor(), from: 1 },
    ];
    check_lockstep(|| ContactStabilizedLockstep::<L>::new(dt, lanes.clone()).unwrap(), &mut singles, &extras, steps)
}

/// Four lanes of the paper beam (J = 19) with different ω and A, narrow
/// stops so the tip rattles: 4000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.2, 37.0, stops), 0.0), lane(pipe(19, 0.35, 23.5, stops), 0.0), lane(pipe(19, 0.05, 61.0, (-0.1, 0.1)), 0.0)];
    let counts = compare::<4>(5e-5, lanes, 4000);
    for (k, &(lo, hi)) in counts.iter().enumerate().take(3) {
        assert!(lo > 20 && hi > 20, "lane {k} should rattle between both stops: {lo} lower, {hi} upper steps");
    }
}

/// An amplitude sweep (same profile in every lane: samples shared) on 8
/// lanes, and two forcing terms per lane (a support motion of two
/// harmonics: `Sampler`'s phasors) on 4; a larger step on the first.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    let stops = (-0.01, 0.02);
    let lanes: Vec<LockstepLane> = (0..5).map(|i| lane(pipe(19, 0.1 + 0.07 * i as f64, 30.0, stops), 0.0)).collect();
    let counts = compare::<8>(1e-4, lanes, 3000);
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
    let two: Vec<LockstepLane> = [(0.01, 40.0), (0.012, 70.0), (0.02, 25.0)]
        .iter()
        .map(|&(a, w)| lane(pipe_harmonics(19, vec![Harmonic { amplitude: a, omega: w, phase: 0.3 }, Harmonic { amplitude: 0.5 * a, omega: 2.7 * w, phase: -1.0 }], stops), 0.0))
        .collect();
    let counts = compare::<4>(5e-5, two, 3000);
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
}

/// Partial batches: 4 lanes in a batch of 8 (one with ω dt = 1: a fast
/// forcing), 1 lane in a batch of 2.
#[test]
fn partial_batches_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 31.0, stops), 0.0), lane(pipe(19, 0.1, 55.0, stops), 0.0), lane(pipe(19, 1e-4, 2e4, stops), 0.0)];
    compare::<8>(5e-5, lanes, 3000);
    compare::<2>(5e-5, vec![lane(pipe(19, 0.25, 44.0, stops), 0.0)], 2000);
}

/// 16 lanes (the sweeps' widest engine), 11 in use: frequencies,
/// amplitudes, and two lanes at rest with zero forcing (A = 0 and A = -0).
#[test]
fn sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let mut lanes: Vec<LockstepLane> = (0..9).map(|i| lane(pipe(19, 0.1 + 0.05 * i as f64, 9.5 + 7.0 * i as f64, stops), 0.0)).collect();
    lanes.insert(4, lane(pipe(19, 0.0, 10.0, stops), 0.0));
    lanes.insert(6, lane(pipe(19, -0.0, 12.0, stops), 0.0));
    let counts = compare::<16>(5e-5, lanes, 3000);
    assert_eq!((counts[4], counts[6]), ((0, 0), (0, 0)), "the lanes at rest stay at rest");
    assert!(counts.iter().enumerate().filter(|(k, _)| *k != 4 && *k != 6).all(|(_, &(lo, hi))| lo + hi > 10), "{counts:?}");
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
        let counts = compare::<4>(5e-5, lanes, 2000);
        assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "J = {j}: {counts:?}");
    }
    let n = 38;
    for (dof, gap) in [(20, 0.004), (n - 4, 0.008), (n - 3, 0.01), (n - 1, 0.01)] {
        let at = |amp: f64, omega: f64| {
            let (mut dy, init) = pipe(19, amp, omega, (-gap, gap));
            dy.contacts[0].dof = dof;
            lane((dy, init), 0.0)
        };
        let counts = compare::<4>(5e-5, vec![at(0.2, 10.0), at(0.3, 31.0), at(0.35, 23.5), at(0.1, 55.0)], 2000);
        assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "dof {dof}: {counts:?}");
    }
}

/// Lanes whose forcing overflows (the single runs turn non-finite at some
/// step) report the single run's `NonFinite` error at that step; the other
/// lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    let lanes = failing_lanes(|l| {
        let mut s = ContactStabilized::new("s".into(), l.dynamics.clone(), 5e-5, &l.initial).unwrap();
        (0..1500).find_map(|_| s.step().err())
    });
    compare::<4>(5e-5, lanes, 1500);
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    check_lane_refusals(|lanes| ContactStabilizedLockstep::<4>::new(5e-5, lanes).err(), base);
    let new = |lanes: Vec<LockstepLane>| ContactStabilizedLockstep::<4>::new(5e-5, lanes).err().expect("refused");
    // No impact law: a restitution is refused, in range or not.
    for e in [0.5, 1.0, 1.5] {
        let mut d = base();
        d.restitution = e;
        assert!(matches!(new(vec![base(), d]), SchemeError::Invalid { field: "restitution", .. }), "e = {e}");
    }
    // What the single run refuses: a non-positive step.
    assert!(ContactStabilizedLockstep::<4>::new(0.0, vec![base()]).is_err() && ContactStabilized::new("s".into(), base().dynamics, 0.0, &base().initial).is_err());
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
    let loaded = |amp: f64, omega: f64, p: f64| {
        let (mut dy, init) = pipe(19, amp, omega, (-0.01, 0.01));
        dy.load = dy.forcing[0].shape.iter().map(|g| p * g).collect();
        lane((dy, init), 0.0)
    };
    let lanes = vec![resting(19, 0.1), loaded(0.2, 10.0, 0.05), resting(19, 1e-3), loaded(0.3, 31.0, -0.02), resting(19, 2.0)];
    let counts = compare::<8>(5e-5, lanes, 3000);
    for k in [0, 2, 4] {
        assert!(counts[k].0 > 100, "lane {k} rests on its stop: {:?}", counts[k]);
    }
    assert!(counts[1].0 + counts[1].1 > 10 && counts[3].0 + counts[3].1 > 10, "{counts:?}");
}
