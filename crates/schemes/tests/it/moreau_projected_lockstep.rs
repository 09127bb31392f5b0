//! `MoreauJeanLockstep::projected` (`moreau-jean-projected(θ, e, γ)` in
//! lockstep): every lane bit for bit the single `MoreauJeanProjected` run
//! of its data (U^n, V^n, λ, the active bound at every step), with the
//! index set kept per lane and the positions' projection acting (counted
//! on the single runs); partial batches; restitutions; lanes at rest and
//! lanes pressed on a stop by a steady load; a failing lane; typed
//! refusals. The oracle is the single run (`MoreauJean` with its
//! `IndexSet`, then `MoreauJeanProjected::project`; `SymBand::mul_vec` by
//! diagonals, `BandLdlt::solve_in_place`, `Projection::project`), checked
//! by `check_lockstep` in every build of the step. The problems are the
//! Paoli–Schatzman engine's (`lockstep.rs`: the paper's pipe with its
//! support motion).

use super::lockstep::{failing_lanes, lane, pipe, pipe_harmonics};
use crate::common::{check_lane_refusals, check_lockstep, Extra};
use signorini_schemes::{Harmonic, LockstepLane, MoreauJeanLockstep, MoreauJeanProjected, SchemeError, Stepper};

/// Steps the batch (every build) and each lane's single run `steps` times
/// and compares them bit for bit at every step ([`check_lockstep`]; and
/// V); returns per lane the steps held at the lower and upper bound, and
/// the steps whose positions' projection acted.
fn compare<const L: usize>(theta: f64, gamma: f64, dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Vec<(usize, usize, u64)> {
    let mut singles: Vec<MoreauJeanProjected> = lanes.iter().map(|l| MoreauJeanProjected::new("single".into(), l.dynamics.clone(), theta, l.restitution, gamma, dt, &l.initial).unwrap()).collect();
    let extras = [Extra { name: "V", lane: |b: &MoreauJeanLockstep<L>, k, out| b.velocity_into(k, out), single: |s: &MoreauJeanProjected| s.velocity(), from: 0 }];
    let counts = check_lockstep(|| MoreauJeanLockstep::<L>::projected(theta, gamma, dt, lanes.clone()).unwrap(), &mut singles, &extras, steps);
    counts.iter().zip(&singles).map(|(&(lo, hi), s)| (lo, hi, s.projections())).collect()
}

/// Four lanes of the paper beam (J = 19, θ = 1/2, γ = 1/2, e = 0) with
/// different ω and A, narrow stops so the tip rattles and the positions'
/// projection acts: 4000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.2, 37.0, stops), 0.0), lane(pipe(19, 0.35, 23.5, stops), 0.0), lane(pipe(19, 0.05, 61.0, (-0.1, 0.1)), 0.0)];
    let counts = compare::<4>(0.5, 0.5, 5e-5, lanes, 4000);
    for (k, &(lo, hi, p)) in counts.iter().enumerate().take(3) {
        assert!(lo > 20 && hi > 20 && p > 5, "lane {k} should rattle between both stops, projected: {lo} lower, {hi} upper steps, {p} projections");
    }
}

/// An amplitude sweep (same profile in every lane: means shared) on 8
/// lanes, and two forcing terms per lane on 4; θ = 0.7, γ = 0.3.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    let stops = (-0.01, 0.02);
    let lanes: Vec<LockstepLane> = (0..5).map(|i| lane(pipe(19, 0.1 + 0.07 * i as f64, 30.0, stops), 0.0)).collect();
    let counts = compare::<8>(0.7, 0.3, 5e-5, lanes, 3000);
    assert!(counts.iter().all(|&(lo, hi, p)| lo + hi > 10 && p > 0), "{counts:?}");
    let two: Vec<LockstepLane> = [(0.01, 40.0), (0.012, 70.0), (0.02, 25.0)]
        .iter()
        .map(|&(a, w)| lane(pipe_harmonics(19, vec![Harmonic { amplitude: a, omega: w, phase: 0.3 }, Harmonic { amplitude: 0.5 * a, omega: 2.7 * w, phase: -1.0 }], stops), 0.0))
        .collect();
    let counts = compare::<4>(0.7, 0.3, 5e-5, two, 3000);
    assert!(counts.iter().all(|&(lo, hi, _)| lo + hi > 10), "{counts:?}");
}

/// Partial batches: 4 lanes in a batch of 8 (one with ω dt = 1), 1 lane
/// in a batch of 2.
#[test]
fn partial_batches_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 31.0, stops), 0.0), lane(pipe(19, 0.1, 55.0, stops), 0.0), lane(pipe(19, 1e-4, 2e4, stops), 0.0)];
    compare::<8>(0.5, 0.5, 5e-5, lanes, 3000);
    compare::<2>(0.5, 0.5, 5e-5, vec![lane(pipe(19, 0.25, 44.0, stops), 0.0)], 2000);
}

/// 16 lanes, 11 in use: frequencies, amplitudes, restitutions 1/2 and 1,
/// and two lanes at rest with zero forcing (A = 0 and A = -0).
#[test]
fn sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let mut lanes: Vec<LockstepLane> = (0..7).map(|i| lane(pipe(19, 0.1 + 0.05 * i as f64, 9.5 + 7.0 * i as f64, stops), 0.0)).collect();
    lanes.push(lane(pipe(19, 0.0, 10.0, stops), 0.0));
    lanes.push(lane(pipe(19, -0.0, 12.0, stops), 0.0));
    lanes.push(lane(pipe(19, 0.2, 37.0, stops), 0.5));
    lanes.push(lane(pipe(19, 0.2, 37.0, stops), 1.0));
    let counts = compare::<16>(0.5, 0.5, 5e-5, lanes, 3000);
    assert_eq!(&counts[7..9], &[(0, 0, 0), (0, 0, 0)], "the lanes at rest stay at rest");
    assert!(counts[..7].iter().chain(&counts[9..]).all(|&(lo, hi, _)| lo + hi > 10), "{counts:?}");
}

/// Short beams, J = 4, 5, 6, 8, θ = 1/2 and 1, a contact's own
/// restitution and a one-sided obstacle; contacts off the tip (mid-beam,
/// row n-4, the tip's slope).
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    let stops = (-0.01, 0.01);
    for j in [4, 5, 6, 8] {
        for theta in [0.5, 1.0] {
            let mut own = pipe(j, 0.2, 37.0, stops);
            own.0.contacts[0].restitution = Some(0.8);
            let lanes = vec![lane(pipe(j, 0.2, 10.0, stops), 0.0), lane(own, 0.0), lane(pipe(j, 0.35, 23.5, stops), 0.5), lane(pipe(j, 0.3, 20.0, (-0.01, f64::INFINITY)), 0.7)];
            let counts = compare::<4>(theta, 0.5, 5e-5, lanes, 2000);
            assert!(counts.iter().all(|&(lo, hi, _)| lo + hi > 10), "J = {j}, θ = {theta}: {counts:?}");
        }
    }
    let n = 38;
    for (dof, gap) in [(20, 0.004), (n - 4, 0.008), (n - 1, 0.01)] {
        let at = |amp: f64, omega: f64| {
            let (mut dy, init) = pipe(19, amp, omega, (-gap, gap));
            dy.contacts[0].dof = dof;
            lane((dy, init), 0.0)
        };
        let counts = compare::<4>(0.5, 0.5, 5e-5, vec![at(0.2, 10.0), at(0.3, 31.0), at(0.35, 23.5), at(0.1, 55.0)], 2000);
        assert!(counts.iter().all(|&(lo, hi, _)| lo + hi > 10), "dof {dof}: {counts:?}");
    }
}

/// Lanes at rest on their lower stop pressed onto it by a steady load
/// (`U = 0`, `V = 0`, the stop at 0, no forcing): their contact joins the
/// index set at once and stays held, the velocity law holding it and the
/// projection putting back what it lets through; beside them vibrating
/// lanes with a steady load as well.
#[test]
fn lanes_pressed_on_a_stop_by_a_steady_load_are_bit_identical() {
    let pressed = |p: f64| {
        let (mut dy, mut init) = pipe(19, 0.0, 10.0, (0.0, 0.01));
        let shape = pipe(19, 1.0, 10.0, (0.0, 0.0)).0.forcing[0].shape.clone();
        dy.load = shape.iter().map(|g| -p * g).collect();
        init.v.iter_mut().for_each(|v| *v = 0.0);
        lane((dy, init), 0.0)
    };
    let loaded = |amp: f64, omega: f64, p: f64| {
        let (mut dy, init) = pipe(19, amp, omega, (-0.01, 0.01));
        dy.load = dy.forcing[0].shape.iter().map(|g| p * g).collect();
        lane((dy, init), 0.0)
    };
    let lanes = vec![pressed(0.1), loaded(0.2, 10.0, 0.05), pressed(1e-3), loaded(0.3, 31.0, -0.02), pressed(2.0)];
    let counts = compare::<8>(0.5, 0.5, 5e-5, lanes, 3000);
    for k in [0, 2, 4] {
        assert!(counts[k].0 > 2500, "lane {k} is held on its stop: {:?}", counts[k]);
    }
    assert!(counts[1].0 + counts[1].1 > 10 && counts[3].0 + counts[3].1 > 10, "{counts:?}");
}

/// Lanes whose forcing overflows report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    let lanes = failing_lanes(|l| {
        let mut s = MoreauJeanProjected::new("s".into(), l.dynamics.clone(), 0.5, 0.0, 0.5, 5e-5, &l.initial).unwrap();
        (0..1500).find_map(|_| s.step().err())
    });
    compare::<4>(0.5, 0.5, 5e-5, lanes, 1500);
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    check_lane_refusals(|lanes| MoreauJeanLockstep::<4>::projected(0.5, 0.5, 5e-5, lanes).err(), base);
    assert!(matches!(MoreauJeanLockstep::<4>::projected(0.4, 0.5, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "theta", .. })));
    assert!(matches!(MoreauJeanLockstep::<4>::projected(0.5, 1.5, 5e-5, vec![base()]).err(), Some(SchemeError::Invalid { field: "gamma", .. })));
    let mut d = base();
    d.restitution = 1.5;
    assert!(matches!(MoreauJeanLockstep::<4>::projected(0.5, 0.5, 5e-5, vec![d]).err(), Some(SchemeError::Invalid { field: "restitution", .. })));
    // What the single run refuses: a non-positive step.
    assert!(MoreauJeanLockstep::<4>::projected(0.5, 0.5, 0.0, vec![base()]).is_err());
}
