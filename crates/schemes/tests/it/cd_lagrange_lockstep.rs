//! `CdLagrangeLockstep` (through `LockstepBatch`, `cd-lagrange(e)`): every
//! lane bit for bit the single `CdLagrange` run of its data (U^n, V^{n−½},
//! λ, the closed side at every step), through repeated impacts on both
//! stops; partial batches; restitutions (the lane's, a contact's own);
//! lanes at rest and lanes pressed on a stop by a steady load; a failing
//! lane; typed refusals. The oracle is the single run (a separate code
//! path: `SymBand::mul_vec` by diagonals, `add_terms`,
//! `BandLdlt::solve_in_place` with M's factor, and Newton's law through the
//! several-contacts solve `MultiSolve`, principal pivoting with a dense
//! Cholesky factor), checked by `check_lockstep` in every build of the step
//! (the one the CPU selects, AVX2, baseline x86-64). The problems and the
//! shared cases are in `common`'s lockstep part (the paper's pipe with its
//! support motion); the step is explicit, so dt = 1e-5 on J = 19 (limit
//! 1.2395e-5).

use crate::common::{assert_contacts, lane, pipe, pressed_lanes, Engine, Extra};
use signorini_schemes::{CdLagrange, LaneVector, LockstepLane, LockstepScheme, Stepper, TimeProfile};

const DT: f64 = 1e-5;

/// `cd-lagrange(e)`'s engine against its single runs (and V^{n−½}).
fn cd() -> Engine<CdLagrange> {
    Engine::new(
        LockstepScheme::CdLagrange { restitution: 0.0 },
        |l, dt| CdLagrange::new("single".into(), l.dynamics.clone(), l.restitution, dt, &l.initial).unwrap(),
        vec![Extra { name: "V^(n-1/2)", vector: LaneVector::HalfStepVelocity, single: |s: &CdLagrange| s.half_step_velocity(), from: 0 }],
    )
}

/// Four lanes of the paper beam (e = 0) with different ω and A, narrow
/// stops so the tip rattles: 20 000 steps.
#[test]
fn frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    cd().rattles(DT, 20_000);
}

/// An amplitude sweep (same profile in every lane: samples shared) on 8
/// lanes, and two forcing terms per lane (a support motion of two
/// harmonics) on 4.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    cd().amplitude_and_two_terms(DT, DT, 15_000);
}

/// Partial batches: 4 lanes in a batch of 8 (one with a fast forcing), 1
/// lane in a batch of 2 (in contact).
#[test]
fn partial_batches_are_bit_identical() {
    let (lo, hi) = cd().partial_batches(DT, 1e5, (12_000, 10_000));
    assert!(lo + hi > 10, "the lone lane: {lo} lower, {hi} upper");
}

/// 16 lanes, 11 in use: frequencies, amplitudes, restitutions 1/2 and 1,
/// and two lanes at rest with zero forcing (A = 0 and A = -0).
#[test]
fn sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    cd().sixteen(DT, 12_000);
}

/// Short beams, J = 4, 5, 6, 8, with restitutions (the lane's, a
/// contact's own) and a one-sided obstacle; contacts off the tip
/// (mid-beam, row n-4, the tip's slope).
#[test]
fn short_beams_restitutions_and_contacts_off_the_tip_are_bit_identical() {
    cd().short_beams(DT, 8000);
    cd().off_the_tip(DT, &[(20, 0.004), (34, 0.008), (37, 0.01)], 8000);
}

/// Lanes at rest on their lower stop pressed onto it by a steady load
/// (`U = 0`, `V = 0`, the stop at 0, no forcing): their contact is closed
/// at every step and the velocity law holds it (the law's warm start
/// acting); beside them vibrating lanes with a steady load as well.
#[test]
fn lanes_pressed_on_a_stop_by_a_steady_load_are_bit_identical() {
    let counts = cd().counts(8, DT, pressed_lanes(2.0), 12_000);
    for k in [0, 2, 4] {
        assert!(counts[k].0 > 11_000, "lane {k} is held on its stop: {:?}", counts[k]);
    }
    assert_contacts(&[counts[1], counts[3]], "the vibrating lanes");
}

/// Lanes whose forcing overflows report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    cd().failing_lane(DT, 3000);
}

#[test]
fn refusals_are_typed() {
    cd().refusals(DT);
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    // What the single run refuses: a non-positive step.
    assert!(cd().batch(4, 0.0, vec![base()]).is_err() && CdLagrange::new("s".into(), base().dynamics, 0.0, 0.0, &base().initial).is_err());
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
    let counts = cd().counts(4, DT, lanes, 2000);
    assert!(counts[0].0 > 1 && counts[2].1 > 1, "{counts:?}");
}
