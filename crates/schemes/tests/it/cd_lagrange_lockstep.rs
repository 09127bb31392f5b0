//! `CdLagrangeLockstep` (`cd-lagrange(e)` in lockstep): every lane bit for
//! bit the single `CdLagrange` run of its data (U^n, V^{n−½}, λ, the closed
//! side at every step), through repeated impacts on both stops; partial
//! batches; restitutions (the lane's, a contact's own); lanes at rest and
//! lanes pressed on a stop by a steady load; a failing lane; typed
//! refusals. The oracle is the single run (a separate code path:
//! `SymBand::mul_vec` by diagonals, `add_terms`, `BandLdlt::solve_in_place`
//! with M's factor, and Newton's law through the several-contacts solve
//! `MultiSolve`, principal pivoting with a dense Cholesky factor), checked
//! by `check_lockstep` in every build of the step (the one the CPU
//! selects, AVX2, baseline x86-64). The problems are the Paoli–Schatzman
//! engine's (`lockstep.rs`: the paper's pipe with its support motion);
//! the step is explicit, so dt = 1e-5 on J = 19 (limit 1.2395e-5).

use super::lockstep::{failing_lanes, lane, pipe, pipe_harmonics};
use crate::common::{check_lane_refusals, check_lockstep, Extra};
use signorini_schemes::{CdLagrange, CdLagrangeLockstep, Harmonic, LockstepLane, SchemeError, Stepper, TimeProfile};

const DT: f64 = 1e-5;

/// Steps the batch (every build) and each lane's single run `steps` times
/// and compares them bit for bit at every step ([`check_lockstep`]; and
/// V^{n−½}); returns per lane the number of steps closed at the lower and
/// upper stop.
fn compare<const L: usize>(dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Vec<(usize, usize)> {
    let mut singles: Vec<CdLagrange> = lanes.iter().map(|l| CdLagrange::new("single".into(), l.dynamics.clone(), l.restitution, dt, &l.initial).unwrap()).collect();
    let extras = [Extra { name: "V^(n-1/2)", lane: |b: &CdLagrangeLockstep<L>, k, out| b.half_step_velocity_into(k, out), single: |s: &CdLagrange| s.half_step_velocity(), from: 0 }];
    check_lockstep(|| CdLagrangeLockstep::<L>::new(dt, lanes.clone()).unwrap(), &mut singles, &extras, steps)
}

/// Four lanes of the paper beam (J = 19, e = 0) with different ω and A,
/// narrow stops so the tip rattles: 20 000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.2, 37.0, stops), 0.0), lane(pipe(19, 0.35, 23.5, stops), 0.0), lane(pipe(19, 0.05, 61.0, (-0.1, 0.1)), 0.0)];
    let counts = compare::<4>(DT, lanes, 20_000);
    for (k, &(lo, hi)) in counts.iter().enumerate().take(3) {
        assert!(lo > 20 && hi > 20, "lane {k} should rattle between both stops: {lo} lower, {hi} upper steps");
    }
}

/// An amplitude sweep (same profile in every lane: samples shared) on 8
/// lanes, and two forcing terms per lane (a support motion of two
/// harmonics) on 4.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    let stops = (-0.01, 0.02);
    let lanes: Vec<LockstepLane> = (0..5).map(|i| lane(pipe(19, 0.1 + 0.07 * i as f64, 30.0, stops), 0.0)).collect();
    let counts = compare::<8>(DT, lanes, 15_000);
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
    let two: Vec<LockstepLane> = [(0.01, 40.0), (0.012, 70.0), (0.02, 25.0)]
        .iter()
        .map(|&(a, w)| lane(pipe_harmonics(19, vec![Harmonic { amplitude: a, omega: w, phase: 0.3 }, Harmonic { amplitude: 0.5 * a, omega: 2.7 * w, phase: -1.0 }], stops), 0.0))
        .collect();
    let counts = compare::<4>(DT, two, 15_000);
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
}

/// Partial batches: 4 lanes in a batch of 8 (one with a fast forcing), 1
/// lane in a batch of 2.
#[test]
fn partial_batches_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 31.0, stops), 0.0), lane(pipe(19, 0.1, 55.0, stops), 0.0), lane(pipe(19, 1e-4, 1e5, stops), 0.0)];
    compare::<8>(DT, lanes, 12_000);
    let counts = compare::<2>(DT, vec![lane(pipe(19, 0.25, 44.0, stops), 0.0)], 10_000);
    assert!(counts[0].0 + counts[0].1 > 10, "{counts:?}");
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
    let counts = compare::<16>(DT, lanes, 12_000);
    assert_eq!(&counts[7..9], &[(0, 0), (0, 0)], "the lanes at rest stay at rest");
    assert!(counts[..7].iter().chain(&counts[9..]).all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
}

/// Short beams, J = 4, 5, 6, 8, with restitutions (the lane's, a
/// contact's own) and a one-sided obstacle; contacts off the tip
/// (mid-beam, row n-4, the tip's slope).
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    let stops = (-0.01, 0.01);
    for j in [4, 5, 6, 8] {
        let mut own = pipe(j, 0.2, 37.0, stops);
        own.0.contacts[0].restitution = Some(0.8);
        let lanes = vec![lane(pipe(j, 0.2, 10.0, stops), 0.0), lane(own, 0.0), lane(pipe(j, 0.35, 23.5, stops), 0.5), lane(pipe(j, 0.3, 20.0, (-0.01, f64::INFINITY)), 0.7)];
        let counts = compare::<4>(DT, lanes, 8000);
        assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "J = {j}: {counts:?}");
    }
    let n = 38;
    for (dof, gap) in [(20, 0.004), (n - 4, 0.008), (n - 1, 0.01)] {
        let at = |amp: f64, omega: f64| {
            let (mut dy, init) = pipe(19, amp, omega, (-gap, gap));
            dy.contacts[0].dof = dof;
            lane((dy, init), 0.0)
        };
        let counts = compare::<4>(DT, vec![at(0.2, 10.0), at(0.3, 31.0), at(0.35, 23.5), at(0.1, 55.0)], 8000);
        assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "dof {dof}: {counts:?}");
    }
}

/// Lanes at rest on their lower stop pressed onto it by a steady load
/// (`U = 0`, `V = 0`, the stop at 0, no forcing): their contact is closed
/// at every step and the velocity law holds it (the law's warm start
/// acting); beside them vibrating lanes with a steady load as well.
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
    let counts = compare::<8>(DT, lanes, 12_000);
    for k in [0, 2, 4] {
        assert!(counts[k].0 > 11_000, "lane {k} is held on its stop: {:?}", counts[k]);
    }
    assert!(counts[1].0 + counts[1].1 > 10 && counts[3].0 + counts[3].1 > 10, "{counts:?}");
}

/// Lanes whose forcing overflows report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    let lanes = failing_lanes(|l| {
        let mut s = CdLagrange::new("s".into(), l.dynamics.clone(), 0.0, DT, &l.initial).unwrap();
        (0..3000).find_map(|_| s.step().err())
    });
    compare::<4>(DT, lanes, 3000);
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    check_lane_refusals(|lanes| CdLagrangeLockstep::<4>::new(DT, lanes).err(), base);
    let mut d = base();
    d.restitution = 1.5;
    assert!(matches!(CdLagrangeLockstep::<4>::new(DT, vec![d]).err(), Some(SchemeError::Invalid { field: "restitution", .. })));
    // What the single run refuses: a non-positive step.
    assert!(CdLagrangeLockstep::<4>::new(0.0, vec![base()]).is_err() && CdLagrange::new("s".into(), base().dynamics, 0.0, 0.0, &base().initial).is_err());
}

/// A lane whose Newton's law lands in its warm start's window: the contact
/// held at step 1 (status `Lower` kept per lane) and at step 2 its free
/// velocity `y_c` above the bound `−e v_c^{n−½}` by less than the pivoting
/// tolerance (`64 ε` of their size), where the warm start keeps the contact
/// held (a multiplier `<= 0`, `v_c` put on the bound) and a cold start
/// would leave it free. The lane starts at `U = 0` below its lower stop
/// (`lo = 1e-3`: closed at steps 1 and 2), `V = −e_c`, e = ½, driven by the
/// pipe's forcing shape with the profile `A sin t` (0 at step 1, so step 1
/// is held whatever `A`; `y_c` at step 2 affine in `A`). `A` is found here
/// by bisection on the single run (its step-2 force: `< 0` held by a
/// genuine violation, `> 0` only from the warm start's window, `−0` free).
/// Its mirror image at the upper stop, and two rattling lanes beside them;
/// checked bit for bit, and on the single runs that step 2's force is
/// `> 0` (lower) and `< 0` (upper): the window reached.
#[test]
fn lanes_in_the_warm_starts_window_are_bit_identical() {
    let window = |amp: f64, sign: f64| {
        let (mut dy, mut init) = pipe(19, 1.0, 10.0, if sign > 0.0 { (1e-3, 1.0) } else { (-1.0, -1e-3) });
        dy.forcing[0].time = TimeProfile::Sine { amplitude: sign * amp, omega: 1.0 };
        let c = dy.contacts[0].dof;
        init.u.iter_mut().for_each(|u| *u = 0.0);
        init.v.iter_mut().for_each(|v| *v = 0.0);
        init.v[c] = -sign;
        lane((dy, init), 0.5)
    };
    // The single run's forces at steps 1 and 2.
    let forces = |l: &LockstepLane| {
        let mut s = CdLagrange::new("s".into(), l.dynamics.clone(), l.restitution, DT, &l.initial).unwrap();
        let first = s.step().unwrap().lambda.unwrap().1;
        (first, s.step().unwrap().lambda.unwrap().1)
    };
    let second = |amp: f64| {
        let (first, second) = forces(&window(amp, 1.0));
        assert!(first < 0.0, "step 1 is held: A = {amp:e}");
        second
    };
    // Bisection on A between a held (λ < 0) and a free (λ = −0) step 2.
    let (mut held, mut free) = (-1e12, 1e12);
    assert!(second(held) < 0.0 && second(free) == 0.0, "{} {}", second(held), second(free));
    let mut found = None;
    for _ in 0..300 {
        let mid = 0.5 * (held + free);
        let lam = second(mid);
        if lam > 0.0 {
            found = Some(mid);
            break;
        }
        if lam < 0.0 {
            held = mid;
        } else {
            free = mid;
        }
    }
    let amp = found.expect("an amplitude whose step 2 lands in the warm start's window");
    let (lower, upper) = (window(amp, 1.0), window(amp, -1.0));
    assert!(forces(&lower).1 > 0.0 && forces(&upper).1 < 0.0, "the window at both stops: A = {amp:e}");
    let stops = (-0.01, 0.01);
    let lanes = vec![lower, lane(pipe(19, 0.2, 10.0, stops), 0.5), upper, lane(pipe(19, 0.3, 31.0, stops), 0.0)];
    let counts = compare::<4>(DT, lanes, 2000);
    assert!(counts[0].0 > 1 && counts[2].1 > 1, "{counts:?}");
}
