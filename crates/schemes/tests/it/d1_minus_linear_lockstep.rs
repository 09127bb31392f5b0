//! `D1MinusLinearLockstep` (through `LockstepBatch`, `d1-minus-linear(e)` and
//! `d1-minus-linear-velocity(e)` in lockstep): on both levels every lane
//! bit for bit the single `D1MinusLinear` run of its data (Uⁿ, Vⁿ, λ, the
//! closed side at every step; the impulse, the two forces and the impact
//! flag too), through repeated impacts on both stops; partial batches;
//! restitutions (the lane's, a contact's own); lanes at rest and lanes
//! pressed on a stop by a steady load (the force problems acting); short
//! beams and contacts off the tip; a failing lane; typed refusals. The
//! oracle is the single run (a separate code path: `SymBand::mul_vec` by
//! diagonals, `add_terms`, `BandLdlt::solve_in_place` with M's factor, the
//! force problems and Newton's law through the several-contacts solve
//! `MultiSolve`, principal pivoting with a dense Cholesky factor), checked
//! by `check_lockstep` in every build of the step (the one the CPU
//! selects, AVX2, baseline x86-64). The problems and the shared cases are
//! in `common`'s lockstep part (the paper's pipe with its support motion); the
//! step is explicit, so dt = 1e-5 on J = 19 (limit 1.2395e-5).

use crate::common::{assert_contacts, lane, pipe, pressed_lanes, Engine, Extra};
use signorini_schemes::{D1Level, D1MinusLinear, LaneVector, Lockstep, LockstepBatch, LockstepLane, LockstepScheme, Stepper};

const DT: f64 = 1e-5;
const LEVELS: [D1Level; 2] = [D1Level::Acceleration, D1Level::Velocity];

fn single(level: D1Level, dt: f64, l: &LockstepLane) -> D1MinusLinear {
    D1MinusLinear::at_level(level, "single".into(), l.dynamics.clone(), l.restitution, dt, &l.initial).unwrap()
}

/// `d1-minus-linear(e)` on `level`: its engine against its single runs (and Vⁿ).
fn d1(level: D1Level) -> Engine<D1MinusLinear> {
    Engine::new(
        LockstepScheme::D1MinusLinear { level, restitution: 0.0 },
        move |l, dt| single(level, dt, l),
        vec![Extra { name: "V^n", vector: LaneVector::Velocity, single: |s: &D1MinusLinear| s.velocity(), from: 0 }],
    )
}

/// The parts of each lane's contact force (the impulse `Λ`, the forces
/// `λ⁺`, `λ⁻`, the impact flag) against its single run's at every step,
/// bit for bit (the build the CPU selects), until the single run fails;
/// returns per lane the number of steps with a nonzero force (`λ⁺` or
/// `λ⁻`) and the number with an impact, both as the single run has them.
fn compare_parts(level: D1Level, width: usize, dt: f64, lanes: &[LockstepLane], steps: usize) -> Vec<(usize, usize)> {
    let mut singles: Vec<D1MinusLinear> = lanes.iter().map(|l| single(level, dt, l)).collect();
    let mut b = d1(level).batch(width, dt, lanes.to_vec()).unwrap();
    assert_eq!(b.contact_level(), Some(level));
    let mut counts = vec![(0, 0); lanes.len()];
    let mut done = vec![false; lanes.len()];
    for step in 1..=steps {
        b.step();
        for (k, s) in singles.iter_mut().enumerate() {
            if done[k] || s.step().is_err() {
                done[k] = true;
                continue;
            }
            let (fp, fm) = s.forces();
            let p = b.impact_parts(k).expect("the engine's parts");
            let (bp, bm) = p.forces;
            let at = format!("lane {k} step {step}");
            assert_eq!(p.impulse.to_bits(), s.impulses()[0].to_bits(), "{at}: Λ {} vs {}", p.impulse, s.impulses()[0]);
            assert_eq!((bp.to_bits(), bm.to_bits()), (fp[0].to_bits(), fm[0].to_bits()), "{at}: forces ({bp}, {bm}) vs ({}, {})", fp[0], fm[0]);
            assert_eq!(p.impact, s.impact(), "{at}: impact");
            counts[k].0 += usize::from(fp[0] != 0.0 || fm[0] != 0.0);
            counts[k].1 += usize::from(s.impact());
        }
    }
    counts
}

/// Four lanes of the paper beam (e = 0) with different ω and A, narrow
/// stops so the tip rattles: 20 000 steps on each level.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_on_both_levels() {
    for level in LEVELS {
        d1(level).rattles(DT, 20_000);
    }
}

/// An amplitude sweep (same profile in every lane: samples shared) on 8
/// lanes, and two forcing terms per lane (a support motion of two
/// harmonics) on 4, on each level.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    for level in LEVELS {
        d1(level).amplitude_and_two_terms(DT, DT, 12_000);
    }
}

/// Partial batches (4 lanes in a batch of 8, one with a fast forcing; 1
/// lane in a batch of 2, in contact), and 16 lanes, 11 in use:
/// frequencies, amplitudes, restitutions 1/2 and 1, and two lanes at rest
/// with zero forcing (A = 0 and A = -0).
#[test]
fn partial_batches_and_sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    for level in LEVELS {
        let (lo, hi) = d1(level).partial_batches(DT, 1e5, (6000, 6000));
        assert!(lo + hi > 10, "{level:?}: the lone lane: {lo} lower, {hi} upper");
        d1(level).sixteen(DT, 8000);
    }
}

/// Short beams, J = 4, 5, 6, 8, with restitutions (the lane's, a
/// contact's own) and a one-sided obstacle; contacts off the tip
/// (mid-beam, row n-4, the tip's slope); on each level.
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    for level in LEVELS {
        d1(level).short_beams(DT, 6000);
        d1(level).off_the_tip(DT, &[(20, 0.004), (34, 0.008), (37, 0.01)], 6000);
    }
}

/// Lanes at rest on a stop (the lower one at 0, or the upper one at 0)
/// pressed onto it by a steady load (`U = 0`, `V = 0`, no forcing): their
/// contact is closed at every step and the force problems hold it (the
/// force solve's warm start acting); beside them vibrating lanes with a
/// steady load as well, whose contacts close in impacts. On each level,
/// with the parts of the force checked at every step.
#[test]
fn lanes_pressed_on_a_stop_by_a_steady_load_are_bit_identical() {
    for level in LEVELS {
        let lanes = pressed_lanes(-2.0);
        let counts = d1(level).counts(8, DT, lanes.clone(), 12_000);
        for k in [0, 2] {
            assert!(counts[k].0 > 11_000, "{level:?}: lane {k} is held on its lower stop: {:?}", counts[k]);
        }
        assert!(counts[4].1 > 11_000, "{level:?}: lane 4 is held on its upper stop: {:?}", counts[4]);
        assert_contacts(&[counts[1], counts[3]], &format!("{level:?}: the vibrating lanes"));
        let parts = compare_parts(level, 8, DT, &lanes, 12_000);
        // (The acceleration level's contact leaves its stop by more than
        // the 1e-8 threshold now and then and closes again in an impact.)
        for k in [0, 2, 4] {
            assert!(parts[k].0 > 11_000, "{level:?}: lane {k} is held by its force: {:?}", parts[k]);
        }
        for k in [1, 3] {
            assert!(parts[k].1 > 5, "{level:?}: lane {k} impacts: {:?}", parts[k]);
        }
    }
}

/// A lane whose two stops are closer than a step's travel, pressed down by
/// a steady load while its tip moves up (`V⁰` at the tip only): on the
/// velocity level `μ⁺` holds the tip at the lower stop and the step's
/// travel `dt/2 V⁰_c` closes the upper one, an impact step (`I₃ ≠ ∅`)
/// that starts with a held contact, whose `μ⁺` the impact drops (its mean
/// force and state do not read it: only the parts show it). Each lane
/// against the dense transcription of the step (`d1minus.rs`'s `Oracle`,
/// stepped from the lane's own state) to 1e-9, and against its single run
/// bit for bit; on both levels (the acceleration level holds only contacts
/// with a rate `<= 1e-8`, which cannot cross such stops: there no held
/// impact is asked for).
#[test]
fn a_held_lane_that_closes_its_other_stop_drops_its_start_force() {
    use crate::d1minus::Oracle;
    use crate::stabilized::{dense, solve};
    let narrow = |v0: f64, gap: f64, e: f64| {
        let (mut dy, mut init) = pipe(19, 0.0, 10.0, (0.0, gap));
        let c = dy.contacts[0].dof;
        // The load whose free acceleration at the tip is −10 V⁰/dt.
        let shape = pipe(19, 1.0, 10.0, (0.0, 0.0)).0.forcing[0].shape.clone();
        let a_unit = solve(dense(&dy.mass), shape.clone())[c];
        let p = -10.0 * v0 / (DT * a_unit);
        dy.load = shape.iter().map(|g| p * g).collect();
        init.v.iter_mut().for_each(|v| *v = 0.0);
        init.v[c] = v0;
        lane((dy, init), e)
    };
    let lanes = vec![narrow(1.0, 2e-6, 0.0), narrow(2.0, 5e-6, 0.5), lane(pipe(19, 0.2, 10.0, (-0.01, 0.01)), 0.0), narrow(0.5, 1e-6, 1.0)];
    for level in LEVELS {
        compare_parts(level, 4, DT, &lanes, 300);
        let oracles: Vec<Oracle> = lanes.iter().map(|l| Oracle::new(&l.dynamics, l.restitution, DT).at(level)).collect();
        let mut b = LockstepBatch::with_width(LockstepScheme::D1MinusLinear { level, restitution: 0.0 }, 4, DT, lanes.clone()).unwrap();
        let n = b.dofs();
        let (mut u, mut v) = (vec![0.0; n], vec![0.0; n]);
        let mut held = vec![0usize; lanes.len()];
        for step in 0..300 {
            let want: Vec<_> = (0..lanes.len())
                .map(|k| {
                    b.displacement_into(k, &mut u);
                    assert!(b.vector_into(LaneVector::Velocity, k, &mut v));
                    oracles[k].step(&u, &v, step)
                })
                .collect();
            b.step();
            for (k, o) in want.iter().enumerate() {
                let at = format!("{level:?}, lane {k}, step {step}");
                b.displacement_into(k, &mut u);
                assert!(b.vector_into(LaneVector::Velocity, k, &mut v));
                let scale = 1.0 + o.u.iter().chain(&o.v).fold(0.0f64, |m, x| m.max(x.abs()));
                for (i, (g, w)) in u.iter().chain(&v).zip(o.u.iter().chain(&o.v)).enumerate() {
                    assert!((g - w).abs() <= 1e-12 * scale, "{at}: state {i}: {g} vs the dense step's {w}");
                }
                let p = b.impact_parts(k).expect("the engine's parts");
                assert_eq!(p.impact, o.impact, "{at}: impact");
                let (fp, fm) = p.forces;
                for (name, g, w) in [("Λ", p.impulse, o.big[0]), ("λ⁺", fp, o.plus[0]), ("λ⁻", fm, o.minus[0])] {
                    assert!((g - w).abs() <= 1e-9 * (1.0 + w.abs()), "{at}: {name} {g} vs the dense step's {w}");
                }
                held[k] += usize::from(o.impact && o.held);
            }
        }
        if level == D1Level::Velocity {
            for k in [0, 1, 3] {
                assert!(held[k] > 0, "lane {k}: no impact step that starts with a held contact: {held:?}");
            }
        }
        eprintln!("{level:?}: impact steps that start with a held contact, per lane: {held:?}");
    }
}

/// Lanes whose forcing overflows report the single run's `NonFinite`
/// error at that step; the other lanes carry on bit for bit; on each level.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    for level in LEVELS {
        d1(level).failing_lane(DT, 3000);
    }
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    for level in LEVELS {
        d1(level).refusals(DT);
        // What the single run refuses: a non-positive step.
        assert!(d1(level).batch(4, 0.0, vec![base()]).is_err() && D1MinusLinear::at_level(level, "s".into(), base().dynamics, 0.0, 0.0, &base().initial).is_err());
    }
    let b = d1(D1Level::Velocity).batch(4, DT, vec![base(), base()]).unwrap();
    assert_eq!((b.lanes(), b.contact_level()), (2, Some(D1Level::Velocity)));
}
