//! `D1MinusLinearLockstep` (`d1-minus-linear(e)` and
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
//! selects, AVX2, baseline x86-64). The problems are the Paoli–Schatzman
//! engine's (`lockstep.rs`: the paper's pipe with its support motion); the
//! step is explicit, so dt = 1e-5 on J = 19 (limit 1.2395e-5).

use super::lockstep::{failing_lanes, lane, pipe, pipe_harmonics};
use crate::common::{check_lane_refusals, check_lockstep, Extra};
use signorini_schemes::{D1Level, D1MinusLinear, D1MinusLinearLockstep, Harmonic, Lockstep, LockstepLane, SchemeError, Stepper};

const DT: f64 = 1e-5;
const LEVELS: [D1Level; 2] = [D1Level::Acceleration, D1Level::Velocity];

fn single(level: D1Level, dt: f64, l: &LockstepLane) -> D1MinusLinear {
    D1MinusLinear::at_level(level, "single".into(), l.dynamics.clone(), l.restitution, dt, &l.initial).unwrap()
}

/// Steps the batch (every build) and each lane's single run `steps` times
/// and compares them bit for bit at every step ([`check_lockstep`]; and
/// Vⁿ); returns per lane the number of steps closed at the lower and upper
/// stop.
fn compare<const L: usize>(level: D1Level, dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Vec<(usize, usize)> {
    let mut singles: Vec<D1MinusLinear> = lanes.iter().map(|l| single(level, dt, l)).collect();
    let extras = [Extra { name: "V^n", lane: |b: &D1MinusLinearLockstep<L>, k, out| b.velocity_into(k, out), single: |s: &D1MinusLinear| s.velocity(), from: 0 }];
    check_lockstep(|| D1MinusLinearLockstep::<L>::new(level, dt, lanes.clone()).unwrap(), &mut singles, &extras, steps)
}

/// The parts of each lane's contact force (the impulse `Λ`, the forces
/// `λ⁺`, `λ⁻`, the impact flag) against its single run's at every step,
/// bit for bit (the build the CPU selects), until the single run fails;
/// returns per lane the number of steps with a nonzero force (`λ⁺` or
/// `λ⁻`) and the number with an impact, both as the single run has them.
fn compare_parts<const L: usize>(level: D1Level, dt: f64, lanes: &[LockstepLane], steps: usize) -> Vec<(usize, usize)> {
    let mut singles: Vec<D1MinusLinear> = lanes.iter().map(|l| single(level, dt, l)).collect();
    let mut b = D1MinusLinearLockstep::<L>::new(level, dt, lanes.to_vec()).unwrap();
    assert_eq!(b.contact_level(), level);
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
            let (bp, bm) = b.forces(k);
            let at = format!("lane {k} step {step}");
            assert_eq!(b.impulse(k).to_bits(), s.impulses()[0].to_bits(), "{at}: Λ {} vs {}", b.impulse(k), s.impulses()[0]);
            assert_eq!((bp.to_bits(), bm.to_bits()), (fp[0].to_bits(), fm[0].to_bits()), "{at}: forces ({bp}, {bm}) vs ({}, {})", fp[0], fm[0]);
            assert_eq!(b.impact(k), s.impact(), "{at}: impact");
            counts[k].0 += usize::from(fp[0] != 0.0 || fm[0] != 0.0);
            counts[k].1 += usize::from(s.impact());
        }
    }
    counts
}

/// Four lanes of the paper beam (J = 19, e = 0) with different ω and A,
/// narrow stops so the tip rattles: 20 000 steps on each level.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_on_both_levels() {
    let stops = (-0.01, 0.01);
    for level in LEVELS {
        let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.2, 37.0, stops), 0.0), lane(pipe(19, 0.35, 23.5, stops), 0.0), lane(pipe(19, 0.05, 61.0, (-0.1, 0.1)), 0.0)];
        let counts = compare::<4>(level, DT, lanes, 20_000);
        for (k, &(lo, hi)) in counts.iter().enumerate().take(3) {
            assert!(lo > 20 && hi > 20, "{level:?}, lane {k} should rattle between both stops: {lo} lower, {hi} upper steps");
        }
    }
}

/// An amplitude sweep (same profile in every lane: samples shared) on 8
/// lanes, and two forcing terms per lane (a support motion of two
/// harmonics) on 4, on each level.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    let stops = (-0.01, 0.02);
    for level in LEVELS {
        let lanes: Vec<LockstepLane> = (0..5).map(|i| lane(pipe(19, 0.1 + 0.07 * i as f64, 30.0, stops), 0.0)).collect();
        let counts = compare::<8>(level, DT, lanes, 12_000);
        assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{level:?}: {counts:?}");
        let two: Vec<LockstepLane> = [(0.01, 40.0), (0.012, 70.0), (0.02, 25.0)]
            .iter()
            .map(|&(a, w)| lane(pipe_harmonics(19, vec![Harmonic { amplitude: a, omega: w, phase: 0.3 }, Harmonic { amplitude: 0.5 * a, omega: 2.7 * w, phase: -1.0 }], stops), 0.0))
            .collect();
        let counts = compare::<4>(level, DT, two, 12_000);
        assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{level:?}: {counts:?}");
    }
}

/// Partial batches (4 lanes in a batch of 8, one with a fast forcing; 1
/// lane in a batch of 2), and 16 lanes, 11 in use: frequencies,
/// amplitudes, restitutions 1/2 and 1, and two lanes at rest with zero
/// forcing (A = 0 and A = -0).
#[test]
fn partial_batches_and_sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    let stops = (-0.01, 0.01);
    for level in LEVELS {
        let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 31.0, stops), 0.0), lane(pipe(19, 0.1, 55.0, stops), 0.0), lane(pipe(19, 1e-4, 1e5, stops), 0.0)];
        compare::<8>(level, DT, lanes, 6000);
        let counts = compare::<2>(level, DT, vec![lane(pipe(19, 0.25, 44.0, stops), 0.0)], 6000);
        assert!(counts[0].0 + counts[0].1 > 10, "{level:?}: {counts:?}");
        let mut lanes: Vec<LockstepLane> = (0..7).map(|i| lane(pipe(19, 0.1 + 0.05 * i as f64, 9.5 + 7.0 * i as f64, stops), 0.0)).collect();
        lanes.push(lane(pipe(19, 0.0, 10.0, stops), 0.0));
        lanes.push(lane(pipe(19, -0.0, 12.0, stops), 0.0));
        lanes.push(lane(pipe(19, 0.2, 37.0, stops), 0.5));
        lanes.push(lane(pipe(19, 0.2, 37.0, stops), 1.0));
        let counts = compare::<16>(level, DT, lanes, 8000);
        assert_eq!(&counts[7..9], &[(0, 0), (0, 0)], "{level:?}: the lanes at rest stay at rest");
        assert!(counts[..7].iter().chain(&counts[9..]).all(|&(lo, hi)| lo + hi > 10), "{level:?}: {counts:?}");
    }
}

/// Short beams, J = 4, 5, 6, 8, with restitutions (the lane's, a
/// contact's own) and a one-sided obstacle; contacts off the tip
/// (mid-beam, row n-4, the tip's slope); on each level.
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    let stops = (-0.01, 0.01);
    for level in LEVELS {
        for j in [4, 5, 6, 8] {
            let mut own = pipe(j, 0.2, 37.0, stops);
            own.0.contacts[0].restitution = Some(0.8);
            let lanes = vec![lane(pipe(j, 0.2, 10.0, stops), 0.0), lane(own, 0.0), lane(pipe(j, 0.35, 23.5, stops), 0.5), lane(pipe(j, 0.3, 20.0, (-0.01, f64::INFINITY)), 0.7)];
            let counts = compare::<4>(level, DT, lanes, 6000);
            assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{level:?}, J = {j}: {counts:?}");
        }
        let n = 38;
        for (dof, gap) in [(20, 0.004), (n - 4, 0.008), (n - 1, 0.01)] {
            let at = |amp: f64, omega: f64| {
                let (mut dy, init) = pipe(19, amp, omega, (-gap, gap));
                dy.contacts[0].dof = dof;
                lane((dy, init), 0.0)
            };
            let counts = compare::<4>(level, DT, vec![at(0.2, 10.0), at(0.3, 31.0), at(0.35, 23.5), at(0.1, 55.0)], 6000);
            assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{level:?}, dof {dof}: {counts:?}");
        }
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
    let pressed = |p: f64| {
        let stops = if p > 0.0 { (0.0, 0.01) } else { (-0.01, 0.0) };
        let (mut dy, mut init) = pipe(19, 0.0, 10.0, stops);
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
    for level in LEVELS {
        let lanes = vec![pressed(0.1), loaded(0.2, 10.0, 0.05), pressed(1e-3), loaded(0.3, 31.0, -0.02), pressed(-2.0)];
        let counts = compare::<8>(level, DT, lanes.clone(), 12_000);
        for k in [0, 2] {
            assert!(counts[k].0 > 11_000, "{level:?}: lane {k} is held on its lower stop: {:?}", counts[k]);
        }
        assert!(counts[4].1 > 11_000, "{level:?}: lane 4 is held on its upper stop: {:?}", counts[4]);
        assert!(counts[1].0 + counts[1].1 > 10 && counts[3].0 + counts[3].1 > 10, "{level:?}: {counts:?}");
        let parts = compare_parts::<8>(level, DT, &lanes, 12_000);
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
    use signorini_schemes::Lockstep;
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
        compare_parts::<4>(level, DT, &lanes, 300);
        let oracles: Vec<Oracle> = lanes.iter().map(|l| Oracle::new(&l.dynamics, l.restitution, DT).at(level)).collect();
        let mut b = D1MinusLinearLockstep::<4>::new(level, DT, lanes.clone()).unwrap();
        let n = b.dofs();
        let (mut u, mut v) = (vec![0.0; n], vec![0.0; n]);
        let mut held = vec![0usize; lanes.len()];
        for step in 0..300 {
            let want: Vec<_> = (0..lanes.len())
                .map(|k| {
                    b.displacement_into(k, &mut u);
                    b.velocity_into(k, &mut v);
                    oracles[k].step(&u, &v, step)
                })
                .collect();
            b.step();
            for (k, o) in want.iter().enumerate() {
                let at = format!("{level:?}, lane {k}, step {step}");
                b.displacement_into(k, &mut u);
                b.velocity_into(k, &mut v);
                let scale = 1.0 + o.u.iter().chain(&o.v).fold(0.0f64, |m, x| m.max(x.abs()));
                for (i, (g, w)) in u.iter().chain(&v).zip(o.u.iter().chain(&o.v)).enumerate() {
                    assert!((g - w).abs() <= 1e-12 * scale, "{at}: state {i}: {g} vs the dense step's {w}");
                }
                assert_eq!(b.impact(k), o.impact, "{at}: impact");
                let (fp, fm) = b.forces(k);
                for (name, g, w) in [("Λ", b.impulse(k), o.big[0]), ("λ⁺", fp, o.plus[0]), ("λ⁻", fm, o.minus[0])] {
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
        let lanes = failing_lanes(|l| {
            let mut s = single(level, DT, l);
            (0..3000).find_map(|_| s.step().err())
        });
        compare::<4>(level, DT, lanes, 3000);
    }
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    for level in LEVELS {
        check_lane_refusals(|lanes| D1MinusLinearLockstep::<4>::new(level, DT, lanes).err(), base);
        let mut d = base();
        d.restitution = 1.5;
        assert!(matches!(D1MinusLinearLockstep::<4>::new(level, DT, vec![d]).err(), Some(SchemeError::Invalid { field: "restitution", .. })));
        // What the single run refuses: a non-positive step.
        assert!(D1MinusLinearLockstep::<4>::new(level, 0.0, vec![base()]).is_err() && D1MinusLinear::at_level(level, "s".into(), base().dynamics, 0.0, 0.0, &base().initial).is_err());
    }
    let b = D1MinusLinearLockstep::<4>::new(D1Level::Velocity, DT, vec![base(), base()]).unwrap();
    assert_eq!((b.lanes(), b.contact_level()), (2, D1Level::Velocity));
}
