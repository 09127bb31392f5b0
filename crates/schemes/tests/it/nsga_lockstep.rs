//! `NsgaLockstep`: every lane bit for bit the single `Nsga` run of its
//! data (U^n, V^n, a^n, λ, the active bound at every step), through
//! repeated impacts on both stops, for ρ∞ = 0, 1/2, 0.8 and 1; partial
//! batches; restitutions; lanes at rest; a failing lane; typed refusals.
//! The oracle is the single run (a separate code path: `SymBand::mul_vec`
//! by diagonals, `BandLdlt::solve_in_place`, `Projection::project`,
//! `Predictor`, `correct_smooth`). Every build of the
//! step is checked: the one the CPU selects (AVX-512 or AVX2 where
//! available), the AVX2 one (`without_avx512()`) and the baseline x86-64
//! one (`portable()`). The problems are the Paoli–Schatzman engine's
//! (`lockstep.rs`: the paper's pipe with its support motion).

use super::lockstep::{failing_lanes, lane, pipe, pipe_harmonics};
use crate::common::{check_lane_refusals, check_lockstep, Extra};
use signorini_schemes::{Harmonic, LockstepLane, Nsga, NsgaLockstep, SchemeError, Stepper};

/// Steps the batch (every build) and each lane's single run `steps` times
/// and compares them bit for bit at every step ([`check_lockstep`]; and
/// V, a); returns per lane the number of steps held at the
/// lower and upper bound.
fn compare<const L: usize>(rho: f64, dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Vec<(usize, usize)> {
    let mut singles: Vec<Nsga> = lanes.iter().map(|l| Nsga::new("single".into(), l.dynamics.clone(), rho, l.restitution, dt, &l.initial).unwrap()).collect();
    let extras = [
        Extra { name: "V", lane: |b: &NsgaLockstep<L>, k, out| b.velocity_into(k, out), single: |s: &Nsga| s.velocity(), from: 0 },
        Extra { name: "a", lane: |b: &NsgaLockstep<L>, k, out| b.acceleration_like_into(k, out), single: |s: &Nsga| s.acceleration_like(), from: 0 },
    ];
    check_lockstep(|| NsgaLockstep::<L>::new(rho, dt, lanes.clone()).unwrap(), &mut singles, &extras, steps)
}

/// Four lanes of the paper beam (J = 19, e = 0) with different ω and A,
/// narrow stops so the tip rattles: 4000 steps, for ρ∞ = 1/2 (the
/// sweeps' `nsga(0.5)`), 0 (the most dissipative), 0.8 and 1 (the
/// trapezoidal rule: α_m = α_f = 1/2).
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    let stops = (-0.01, 0.01);
    for rho in [0.5, 0.0, 0.8, 1.0] {
        let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.2, 37.0, stops), 0.0), lane(pipe(19, 0.35, 23.5, stops), 0.0), lane(pipe(19, 0.05, 61.0, (-0.1, 0.1)), 0.0)];
        let counts = compare::<4>(rho, 5e-5, lanes, 4000);
        for (k, &(lo, hi)) in counts.iter().enumerate().take(3) {
            assert!(lo > 20 && hi > 20, "ρ∞ = {rho}: lane {k} should rattle between both stops: {lo} lower, {hi} upper steps");
        }
    }
}

/// An amplitude sweep (same profile in every lane: means shared) on 8
/// lanes, and two forcing terms per lane (a support motion of two
/// harmonics: `Sampler`'s phasors) on 4; ρ∞ = 0.7.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    let stops = (-0.01, 0.02);
    let lanes: Vec<LockstepLane> = (0..5).map(|i| lane(pipe(19, 0.1 + 0.07 * i as f64, 30.0, stops), 0.0)).collect();
    let counts = compare::<8>(0.7, 5e-5, lanes, 3000);
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
    let two: Vec<LockstepLane> = [(0.01, 40.0), (0.012, 70.0), (0.02, 25.0)]
        .iter()
        .map(|&(a, w)| lane(pipe_harmonics(19, vec![Harmonic { amplitude: a, omega: w, phase: 0.3 }, Harmonic { amplitude: 0.5 * a, omega: 2.7 * w, phase: -1.0 }], stops), 0.0))
        .collect();
    let counts = compare::<4>(0.7, 5e-5, two, 3000);
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
}

/// Partial batches: 4 lanes in a batch of 8 (one with ω dt = 1: a fast
/// forcing), 1 lane in a batch of 2.
#[test]
fn partial_batches_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 31.0, stops), 0.0), lane(pipe(19, 0.1, 55.0, stops), 0.0), lane(pipe(19, 1e-4, 2e4, stops), 0.0)];
    compare::<8>(0.5, 5e-5, lanes, 3000);
    compare::<2>(0.5, 5e-5, vec![lane(pipe(19, 0.25, 44.0, stops), 0.0)], 2000);
}

/// 16 lanes (the sweeps' widest engine), 11 in use: frequencies,
/// amplitudes, restitutions 1/2 and 1, and two lanes at rest with zero
/// forcing (A = 0 and A = -0).
#[test]
fn sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let mut lanes: Vec<LockstepLane> = (0..7).map(|i| lane(pipe(19, 0.1 + 0.05 * i as f64, 9.5 + 7.0 * i as f64, stops), 0.0)).collect();
    lanes.push(lane(pipe(19, 0.0, 10.0, stops), 0.0));
    lanes.push(lane(pipe(19, -0.0, 12.0, stops), 0.0));
    lanes.push(lane(pipe(19, 0.2, 37.0, stops), 0.5));
    lanes.push(lane(pipe(19, 0.2, 37.0, stops), 1.0));
    let counts = compare::<16>(0.5, 5e-5, lanes, 3000);
    assert_eq!(&counts[7..9], &[(0, 0), (0, 0)], "the lanes at rest stay at rest");
    assert!(counts[..7].iter().chain(&counts[9..]).all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
}

/// Short beams, J = 4, 5, 6, 8 (8 to 16 unknowns: the ring's first and
/// last rows overlap), ρ∞ = 1/2 and 1, with a contact's own restitution
/// and a one-sided obstacle; and contacts off the tip (mid-beam, row n-4,
/// the tip's slope).
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    let stops = (-0.01, 0.01);
    for j in [4, 5, 6, 8] {
        for rho in [0.5, 1.0] {
            let mut own = pipe(j, 0.2, 37.0, stops);
            own.0.contacts[0].restitution = Some(0.8);
            let lanes = vec![lane(pipe(j, 0.2, 10.0, stops), 0.0), lane(own, 0.0), lane(pipe(j, 0.35, 23.5, stops), 0.5), lane(pipe(j, 0.3, 20.0, (-0.01, f64::INFINITY)), 0.7)];
            let counts = compare::<4>(rho, 5e-5, lanes, 2000);
            assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "J = {j}, ρ∞ = {rho}: {counts:?}");
        }
    }
    let n = 38;
    for (dof, gap) in [(20, 0.004), (n - 4, 0.008), (n - 1, 0.01)] {
        let at = |amp: f64, omega: f64| {
            let (mut dy, init) = pipe(19, amp, omega, (-gap, gap));
            dy.contacts[0].dof = dof;
            lane((dy, init), 0.0)
        };
        let counts = compare::<4>(0.5, 5e-5, vec![at(0.2, 10.0), at(0.3, 31.0), at(0.35, 23.5), at(0.1, 55.0)], 2000);
        assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "dof {dof}: {counts:?}");
    }
}

/// Lanes whose forcing overflows (the single runs turn non-finite at some
/// step) report the single run's `NonFinite` error at that step; the other
/// lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    let lanes = failing_lanes(|l| {
        let mut s = Nsga::new("s".into(), l.dynamics.clone(), 0.5, 0.0, 5e-5, &l.initial).unwrap();
        (0..1500).find_map(|_| s.step().err())
    });
    compare::<4>(0.5, 5e-5, lanes, 1500);
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    check_lane_refusals(|lanes| NsgaLockstep::<4>::new(0.5, 5e-5, lanes).err(), base);
    let new = |lanes: Vec<LockstepLane>| NsgaLockstep::<4>::new(0.5, 5e-5, lanes).err().expect("refused");
    assert!(matches!(NsgaLockstep::<4>::new(-0.1, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "rho_inf", .. })));
    assert!(matches!(NsgaLockstep::<4>::new(1.5, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "rho_inf", .. })));
    assert!(matches!(NsgaLockstep::<4>::new(f64::NAN, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "rho_inf", .. })));
    let mut d = base();
    d.restitution = 1.5;
    assert!(matches!(new(vec![d]), SchemeError::Invalid { field: "restitution", .. }));
}
