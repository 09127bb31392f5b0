//! `MoreauJeanCombinedLockstep` (through `LockstepBatch`,
//! `moreau-jean-combined(θ, e)`): every lane bit for bit the single `MoreauJeanCombined` run of
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
//! problems and the shared cases are in `common`'s lockstep part (the
//! paper's pipe with its support motion).

use crate::common::{lane, pipe, Engine, Extra, Seen};
use signorini_schemes::{LaneVector, Lockstep, LockstepBatch, LockstepLane, LockstepScheme, MoreauJeanCombined, SchemeError, Stepper};

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

/// `moreau-jean-combined(θ, e)`'s engine against its single runs (and V);
/// each comparison also checks that the batch took, step by step, as many
/// passes as its slowest lane's single run (no more: the lanes that did
/// not grow wait).
fn mjc(theta: f64) -> Engine<MoreauJeanCombined> {
    let mut eng = Engine::new(
        LockstepScheme::MoreauJeanCombined { theta, restitution: 0.0 },
        move |l, dt| single(theta, dt, l),
        vec![Extra { name: "V", vector: LaneVector::Velocity, single: |s: &MoreauJeanCombined| s.velocity(), from: 0 }],
    );
    eng.also = Some(Box::new(move |width, dt, lanes, steps| {
        // The bound on the passes: Σ over steps of the slowest lane's passes
        // (a failed lane takes none after its failure; padding lanes copy lane 0).
        let per = passes_per_step(theta, dt, lanes, steps);
        let want: u64 = (0..steps).map(|n| per.iter().filter_map(|p| p.get(n)).copied().max().unwrap_or(1)).sum();
        let mut b = LockstepBatch::with_width(LockstepScheme::MoreauJeanCombined { theta, restitution: 0.0 }, width, dt, lanes.to_vec()).unwrap();
        for _ in 0..steps {
            b.step();
        }
        assert_eq!(b.passes(), Some(want), "the batch's passes against its slowest lane's, step by step");
    }));
    eng
}

/// The steps whose projection acted and the passes of each single run.
fn projections_and_passes(seen: &Seen<MoreauJeanCombined>) -> (Vec<u64>, Vec<u64>) {
    (seen.singles.iter().map(|s| s.projections()).collect(), seen.singles.iter().map(|s| s.passes()).collect())
}

/// Four lanes of the paper beam (θ = 1/2, e = 0) with different ω and A,
/// narrow stops so the tip rattles, the projection acts and steps are
/// redone: 4000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    let seen = mjc(0.5).rattles(DT, 4000);
    let (projections, passes) = projections_and_passes(&seen);
    for k in 0..3 {
        assert!(projections[k] > 5 && passes[k] > 4000 + 5, "lane {k} should be projected and redone: {projections:?} {passes:?}");
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
    let seen = mjc(0.7).compare(8, DT, lanes, steps);
    assert!(seen.counts[1].0 + seen.counts[1].1 > 10 && seen.counts[2].0 + seen.counts[2].1 > 10, "{:?}", seen.counts);
}

/// Partial batches: 4 lanes in a batch of 8 (one with ω dt = 1), 1 lane in
/// a batch of 2; 16 lanes, 11 in use, two at rest (A = 0 and A = -0)
/// that never redo a step.
#[test]
fn partial_batches_and_sixteen_lanes_are_bit_identical() {
    mjc(0.5).partial_batches(DT, 2e4, (2000, 1500));
    let seen = mjc(1.0).sixteen(DT, 2000);
    assert_eq!(&projections_and_passes(&seen).1[7..9], &[2000, 2000], "the lanes at rest never redo a step");
}

/// Short beams, J = 4, 5, 6, 8, θ = 1/2 and 1, a contact's own
/// restitution and a one-sided obstacle; contacts off the tip (mid-beam,
/// row n-4, the tip's slope).
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    for theta in [0.5, 1.0] {
        mjc(theta).short_beams(DT, 1500);
    }
    mjc(0.5).off_the_tip(DT, &[(20, 0.004), (34, 0.008), (37, 0.01)], 1500);
}

/// Lanes whose forcing overflows report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    mjc(0.5).failing_lane(DT, 1500);
}

#[test]
fn refusals_are_typed() {
    mjc(0.5).refusals(DT);
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    assert!(matches!(mjc(0.4).batch(4, DT, vec![base()]).err(), Some(SchemeError::Invalid { field: "theta", .. })));
    // What the single run refuses: a non-positive step.
    assert!(mjc(0.5).batch(4, 0.0, vec![base()]).is_err());
}
