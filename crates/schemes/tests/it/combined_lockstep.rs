//! `MoreauJeanCombinedLockstep` (`moreau-jean-combined(θ, e)` in
//! lockstep): every lane bit for bit the single `MoreauJeanCombined` run of
//! its data (U^n, V^n, λ, the active bound at every step), with lanes that
//! redo their step a different number of times in the same step (their
//! index sets grow differently), the projection acting; partial batches;
//! restitutions; short beams and contacts off the tip; a failing lane;
//! typed refusals. The oracle is the single run (`MoreauJean` with a given
//! index set: `SymBand::mul_vec` by diagonals, `BandLdlt::solve_in_place`,
//! `Projection::project`; then `MoreauJeanCombined`'s projection and
//! growth, the step redone from saved vectors), checked by `check_lockstep`
//! in every build of the step (the one the CPU selects, AVX2, baseline
//! x86-64); the passes each single run took (`MoreauJeanCombined::passes`,
//! step by step) say which lanes redid their step and how often. The
//! problems are the Paoli–Schatzman engine's (`lockstep.rs`: the paper's
//! pipe with its support motion).

use super::lockstep::{failing_lanes, lane, pipe};
use crate::common::{check_lane_refusals, check_lockstep, Extra};
use signorini_schemes::{Lockstep, LockstepLane, MoreauJeanCombined, MoreauJeanCombinedLockstep, SchemeError, Stepper};

const DT: f64 = 5e-5;

fn single(theta: f64, dt: f64, l: &LockstepLane) -> MoreauJeanCombined {
    MoreauJeanCombined::new("single".into(), l.dynamics.clone(), theta, l.restitution, dt, &l.initial).unwrap()
}

/// Per lane, the passes its single run takes at each of `steps` steps
/// (until it fails).
fn passes_per_step(theta: f64, dt: f64, lanes: &[LockstepLane], steps: usize) -> Vec<Vec<u64>> {
    lanes
        .iter()
        .map(|l| {
            let mut s = single(theta, dt, l);
            let mut out = Vec::with_capacity(steps);
            for _ in 0..steps {
                let before = s.passes();
                if s.step().is_err() {
                    break;
                }
                out.push(s.passes() - before);
            }
            out
        })
        .collect()
}

/// What a comparison saw, from the single runs: per lane the steps held at
/// the lower and upper bound, the steps whose projection acted, the passes.
#[derive(Debug)]
struct Seen {
    counts: Vec<(usize, usize)>,
    projections: Vec<u64>,
    passes: Vec<u64>,
}

/// Steps the batch (every build) and each lane's single run `steps` times
/// and compares them bit for bit at every step ([`check_lockstep`]; and
/// V); checks that the batch took, step by step, as many passes as its
/// slowest lane's single run (no more: the lanes that did not grow wait).
fn compare<const L: usize>(theta: f64, dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Seen {
    let mut singles: Vec<MoreauJeanCombined> = lanes.iter().map(|l| single(theta, dt, l)).collect();
    let extras = [Extra { name: "V", lane: |b: &MoreauJeanCombinedLockstep<L>, k, out| b.velocity_into(k, out), single: |s: &MoreauJeanCombined| s.velocity(), from: 0 }];
    let counts = check_lockstep(|| MoreauJeanCombinedLockstep::<L>::new(theta, dt, lanes.clone()).unwrap(), &mut singles, &extras, steps);
    // The bound on the passes: Σ over steps of the slowest lane's passes
    // (a failed lane takes none after its failure; padding lanes copy lane 0).
    let per = passes_per_step(theta, dt, &lanes, steps);
    let want: u64 = (0..steps).map(|n| per.iter().filter_map(|p| p.get(n)).copied().max().unwrap_or(1)).sum();
    let mut b = MoreauJeanCombinedLockstep::<L>::new(theta, dt, lanes).unwrap();
    for _ in 0..steps {
        b.step();
    }
    assert_eq!(b.passes(), want, "the batch's passes against its slowest lane's, step by step");
    Seen { counts, projections: singles.iter().map(|s| s.projections()).collect(), passes: singles.iter().map(|s| s.passes()).collect() }
}

/// Four lanes of the paper beam (J = 19, θ = 1/2, e = 0) with different ω
/// and A, narrow stops so the tip rattles, the projection acts and steps
/// are redone: 4000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.2, 37.0, stops), 0.0), lane(pipe(19, 0.35, 23.5, stops), 0.0), lane(pipe(19, 0.05, 61.0, (-0.1, 0.1)), 0.0)];
    let seen = compare::<4>(0.5, DT, lanes, 4000);
    for k in 0..3 {
        let (lo, hi) = seen.counts[k];
        assert!(lo > 20 && hi > 20 && seen.projections[k] > 5 && seen.passes[k] > 4000 + 5, "lane {k} should rattle between both stops, projected and redone: {seen:?}");
    }
}

/// Lanes that redo their step a different number of times at the same
/// step: a contact pinned at 0 (`lo = hi = 0`: two passes, or three when
/// the projection puts the tip back on the pin and the other side joins),
/// one pinned at 5e-3 (the tip starts below it: three passes every step,
/// one side added on each of the first two), rattling lanes (one or two
/// passes) and a lane whose stops are never reached (one pass); θ = 0.7,
/// restitutions 0, ½ and 1. Checked on the single runs: at some steps the
/// lanes take 1, 2 and 3 passes at once.
#[test]
fn lanes_redoing_their_step_different_numbers_of_times_are_bit_identical() {
    let lanes = vec![
        lane(pipe(19, 0.2, 10.0, (0.0, 0.0)), 0.0),
        lane(pipe(19, 0.2, 37.0, (-0.01, 0.01)), 0.0),
        lane(pipe(19, 0.3, 31.0, (-0.004, 0.006)), 0.5),
        lane(pipe(19, 0.1, 20.0, (5e-3, 5e-3)), 1.0),
        lane(pipe(19, 0.01, 10.0, (-1.0, 1.0)), 0.0),
    ];
    let steps = 3000;
    let per = passes_per_step(0.7, DT, &lanes, steps);
    // Per lane, the steps that took 1, 2 and 3 passes.
    let hist: Vec<[usize; 3]> = per.iter().map(|p| std::array::from_fn(|i| p.iter().filter(|&&x| x == i as u64 + 1).count())).collect();
    assert!(hist[0][1] > 100 && hist[0][2] > 100, "the lane pinned at 0 takes two or three passes: {hist:?}");
    assert_eq!(hist[3], [0, 0, steps], "the lane pinned off its start takes three passes every step");
    assert_eq!(hist[4], [steps, 0, 0], "the free lane takes one");
    let mixed = (0..steps).filter(|&n| [1, 2, 3].iter().all(|want| per.iter().any(|p| p[n] == *want))).count();
    let two = (0..steps).filter(|&n| per[1][n] == 2 && per[2][n] == 1).count() + (0..steps).filter(|&n| per[1][n] == 1 && per[2][n] == 2).count();
    assert!(mixed > 100 && two > 50, "steps with 1, 2 and 3 passes at once: {mixed}; the rattling lanes apart: {two}");
    let seen = compare::<8>(0.7, DT, lanes, steps);
    assert!(seen.counts[1].0 + seen.counts[1].1 > 10 && seen.counts[2].0 + seen.counts[2].1 > 10, "{seen:?}");
}

/// Partial batches: 4 lanes in a batch of 8 (one with ω dt = 1), 1 lane in
/// a batch of 2; 16 lanes, 11 in use, two at rest (A = 0 and A = -0).
#[test]
fn partial_batches_and_sixteen_lanes_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 31.0, stops), 0.0), lane(pipe(19, 0.1, 55.0, stops), 0.0), lane(pipe(19, 1e-4, 2e4, stops), 0.0)];
    compare::<8>(0.5, DT, lanes, 2000);
    compare::<2>(0.5, DT, vec![lane(pipe(19, 0.25, 44.0, stops), 0.0)], 1500);
    let mut lanes: Vec<LockstepLane> = (0..7).map(|i| lane(pipe(19, 0.1 + 0.05 * i as f64, 9.5 + 7.0 * i as f64, stops), 0.0)).collect();
    lanes.push(lane(pipe(19, 0.0, 10.0, stops), 0.0));
    lanes.push(lane(pipe(19, -0.0, 12.0, stops), 0.0));
    lanes.push(lane(pipe(19, 0.2, 37.0, stops), 0.5));
    lanes.push(lane(pipe(19, 0.2, 37.0, stops), 1.0));
    let seen = compare::<16>(1.0, DT, lanes, 2000);
    assert_eq!(&seen.counts[7..9], &[(0, 0), (0, 0)], "the lanes at rest stay at rest");
    assert_eq!(&seen.passes[7..9], &[2000, 2000], "and never redo a step");
    assert!(seen.counts[..7].iter().chain(&seen.counts[9..]).all(|&(lo, hi)| lo + hi > 10), "{seen:?}");
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
            let seen = compare::<4>(theta, DT, lanes, 1500);
            assert!(seen.counts.iter().all(|&(lo, hi)| lo + hi > 10), "J = {j}, θ = {theta}: {seen:?}");
        }
    }
    let n = 38;
    for (dof, gap) in [(20, 0.004), (n - 4, 0.008), (n - 1, 0.01)] {
        let at = |amp: f64, omega: f64| {
            let (mut dy, init) = pipe(19, amp, omega, (-gap, gap));
            dy.contacts[0].dof = dof;
            lane((dy, init), 0.0)
        };
        let seen = compare::<4>(0.5, DT, vec![at(0.2, 10.0), at(0.3, 31.0), at(0.35, 23.5), at(0.1, 55.0)], 1500);
        assert!(seen.counts.iter().all(|&(lo, hi)| lo + hi > 10), "dof {dof}: {seen:?}");
    }
}

/// Lanes whose forcing overflows report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    let lanes = failing_lanes(|l| {
        let mut s = MoreauJeanCombined::new("s".into(), l.dynamics.clone(), 0.5, 0.0, DT, &l.initial).unwrap();
        (0..1500).find_map(|_| s.step().err())
    });
    compare::<4>(0.5, DT, lanes, 1500);
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    check_lane_refusals(|lanes| MoreauJeanCombinedLockstep::<4>::new(0.5, DT, lanes).err(), base);
    assert!(matches!(MoreauJeanCombinedLockstep::<4>::new(0.4, DT, vec![base()]).err(), Some(SchemeError::Invalid { field: "theta", .. })));
    let mut d = base();
    d.restitution = 1.5;
    assert!(matches!(MoreauJeanCombinedLockstep::<4>::new(0.5, DT, vec![d]).err(), Some(SchemeError::Invalid { field: "restitution", .. })));
    // What the single run refuses: a non-positive step.
    assert!(MoreauJeanCombinedLockstep::<4>::new(0.5, 0.0, vec![base()]).is_err());
}
