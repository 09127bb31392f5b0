//! `PaoliSchatzmanLockstep` (through `LockstepBatch`, `ps(e, β)`): every
//! lane bit for bit the single `PaoliSchatzman` run of its data (U^n,
//! U^{n-1}, λ, active bound at every step), through repeated impacts on
//! both stops; partial batches; restitution; typed refusals. The oracle is
//! the single run (a separate code path: on the beam its fused β-step —
//! the right-hand side inside the solve's forward sweep, then its own copy
//! of `BandLdlt::backward_in_place`'s sweep, `Projection::project`).
//! Every build of the step is checked: the one the CPU selects (AVX-512 or
//! AVX2 where available), the AVX2 one (`without_avx512()`) and the
//! baseline x86-64 one (`portable()`). The problems and the cases shared by
//! every engine are in `common`'s lockstep part (the paper's pipe with its
//! support motion). The fused β-step is itself checked bit for bit against
//! the plain one (`Bands3::rhs`, `BandLdlt::solve_in_place`) at the end of
//! this file.

use crate::common::{assert_contacts, bits, lane, pipe, pipe_harmonics, Engine, Extra};
use signorini_fem::SymBand;
use signorini_schemes::{Active, Bounds, Contact, Dynamics, Harmonic, Initial, LaneVector, LockstepLane, LockstepScheme, PaoliSchatzman, SchemeError, SchemeSpec, Stepper};

/// `ps(e, β)`'s engine against its single runs (and U^{n-1}).
fn ps(beta: f64) -> Engine<PaoliSchatzman> {
    Engine::new(
        LockstepScheme::PaoliSchatzman { beta, restitution: 0.0 },
        move |l, dt| PaoliSchatzman::new("single".into(), l.dynamics.clone(), beta, l.restitution, dt, &l.initial).unwrap(),
        vec![Extra { name: "U^(n-1)", vector: LaneVector::PreviousDisplacement, single: |s: &PaoliSchatzman| s.previous_displacement(), from: 0 }],
    )
}

/// Four lanes of the paper beam (J = 19, β = 1/2, e = 0) with different
/// ω and A, narrow stops so the tip rattles: 4000 steps, bit for bit.
#[test]
fn beam_frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    ps(0.5).rattles(5e-5, 4000);
}

/// An amplitude sweep (same profile in every lane: means shared) on 8
/// lanes and two forcing terms per lane (support motion of two harmonics)
/// on 4 (one forcing term vs two is refused: two groups), β = 1/4.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    ps(0.25).amplitude_and_two_terms(5e-5, 5e-5, 3000);
}

/// A partial batch: 4 lanes in a batch of 8, 1 lane in a batch of 2. One
/// lane has ω dt = 1 (ω = 2·10⁴): its factor sin(ω δ/2)/(ω δ/2) changes with
/// the rounding of δ = (n+2) dt - (n+1) dt, so a stale δ shows.
#[test]
fn partial_batches_are_bit_identical() {
    ps(0.5).partial_batches(5e-5, 2e4, (3000, 2000));
}

/// 16 lanes (the sweeps' widest engine), 11 of them in use: frequencies,
/// amplitudes, restitutions, and two lanes at rest with zero forcing (A = 0
/// and A = -0: zeros of both signs in the data), β = 1/2.
#[test]
fn sixteen_lanes_with_lanes_at_rest_are_bit_identical() {
    ps(0.5).sixteen(5e-5, 3000);
}

/// Short beams, J = 4, 5, 6, 8 (8 to 16 unknowns: the fewest the engine
/// takes, and about as many as the ring of 8 rows that holds `2U^n - U^{n-1}`
/// and `(1-2β) U^n + β U^{n-1}`, so its first and last rows overlap), 4
/// lanes each, β = 1/2 and 1/4: bit for bit.
#[test]
fn short_beams_are_bit_identical() {
    let stops = (-0.01, 0.01);
    for j in [4, 5, 6, 8] {
        for beta in [0.5, 0.25] {
            let lanes = vec![lane(pipe(j, 0.2, 10.0, stops), 0.0), lane(pipe(j, 0.3, 31.0, stops), 0.0), lane(pipe(j, 0.35, 23.5, stops), 0.5), lane(pipe(j, 0.1, 55.0, stops), 0.0)];
            assert_contacts(&ps(beta).counts(4, 5e-5, lanes, 2000), &format!("J = {j}, β = {beta}"));
        }
    }
}

/// The contact elsewhere than the tip's displacement (row n-2): mid-beam
/// (row 20), row n-4, and the tip's slope (rows n-3 and n-1): the
/// projection's column and the row it sets differ. J = 19, β = 1/2, 4
/// lanes each: bit for bit.
#[test]
fn contacts_off_the_tip_are_bit_identical() {
    ps(0.5).off_the_tip(5e-5, &[(20, 0.004), (34, 0.008), (35, 0.01), (37, 0.01)], 2000);
}

/// Restitution per lane (e = 0.5, 1, a contact's own e overriding the
/// lane's), a one-sided obstacle, β = 1/4.
#[test]
fn restitution_lanes_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let mut own = pipe(19, 0.2, 37.0, stops);
    own.0.contacts[0].restitution = Some(0.8);
    let lanes = vec![lane(pipe(19, 0.2, 37.0, stops), 0.5), lane(pipe(19, 0.2, 37.0, stops), 1.0), lane(own, 0.0), lane(pipe(19, 0.3, 20.0, (-0.01, f64::INFINITY)), 0.7)];
    let counts = ps(0.25).counts(4, 5e-5, lanes, 3000);
    assert!(counts.iter().all(|&(lo, _)| lo > 0), "{counts:?}");
}

#[test]
fn refusals_are_typed() {
    ps(0.5).refusals(5e-5);
    // Half-bandwidth 1 (a P1 bar) is not supported.
    let n = 10;
    let mut m = SymBand::zeros(n, 1);
    let mut k = SymBand::zeros(n, 1);
    for i in 0..n {
        m.set(i, i, 1.0);
        k.set(i, i, 2.0);
        if i > 0 {
            k.set(i, i - 1, -1.0);
        }
    }
    let dy = Dynamics::new(m, k, vec![0.0; n], vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
    let bar = LockstepLane { dynamics: dy, initial: Initial { u: vec![0.1; n], v: vec![0.0; n] }, restitution: 0.0 };
    assert!(matches!(ps(0.5).batch(4, 5e-5, vec![bar]).err(), Some(SchemeError::Structure(m)) if m.contains("half-bandwidth 3")));
}

/// Lanes whose forcing overflows (amplitudes 1e306, 1e304: the single runs
/// turn non-finite at some step) report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    ps(0.5).failing_lane(5e-5, 1500);
}

/// β = 0 (the start step is Newmark(1/4, 1/2), the step matrix is `M`): the
/// step itself takes no special path; bit for bit too.
#[test]
fn beta_zero_lanes_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 37.0, stops), 0.5)];
    ps(0.0).counts(2, 2e-6, lanes, 3000);
}

/// The beam's fused β-step (right-hand side inside the solve's forward
/// sweep, the forcing's work summed in the next step's forward pass) is
/// the plain step bit for bit: against the same scheme with it switched off
/// (`Bands3::rhs`, `add_terms`, `BandLdlt::solve_in_place`,
/// `add_step_work`), `U^n`, `U^{n−1}`, the report, λ, the work of the
/// forcing and of the contact force and the energy are equal (`to_bits`)
/// at every step — sizes with no, a partial and several full chunks of
/// rows, β = 1/2, 1/4 and 0.1, e = 0 and 1/2, none, one and two forcing
/// terms with a static load (one: the first term's work summed inside the
/// backward sweep; two: the second's beside it), the baseline x86-64 build and the one the CPU
/// selects, across a `set_state` (which settles the pending work) and
/// with the fused step switched off and on mid-run.
#[test]
fn fused_beam_step_is_the_plain_step_bit_for_bit() {
    let h = |f: f64, w: f64, p: f64| Harmonic { amplitude: 0.02 * f, omega: w, phase: p };
    let mut fused_steps = 0;
    for j in [4usize, 5, 7, 12, 19] {
        for beta in [0.5, 0.25, 0.1] {
            for e in [0.0, 0.5] {
                for terms in [0, 1, 2] {
                    // β = 0.1 within its stability limit, nearer stops.
                    let (dt, stops) =
                        if beta < 0.25 { (0.5 * SchemeSpec::ps(e, beta).cfl_limit(&pipe(j, 0.2, 10.0, (-1.0, 1.0)).0).unwrap().unwrap(), (-2e-4, 1e-4)) } else { (1e-4, (-0.004, 0.003)) };
                    let (mut dy, init) = if terms == 1 { pipe(j, 0.2, 10.0, stops) } else { pipe_harmonics(j, vec![h(1.0, 10.0, 0.3), h(0.5, 23.0, 1.1)], stops) };
                    if terms == 0 {
                        dy.forcing.clear();
                    }
                    let n = dy.n();
                    dy.load = (0..n).map(|i| 0.3 * (i as f64 * 0.7).sin()).collect();
                    let build = || PaoliSchatzman::new("ps".into(), dy.clone(), beta, e, dt, &init).unwrap();
                    let (mut plain, mut fused) = (build(), if j == 12 { build().portable() } else { build() });
                    plain.set_fused(false);
                    assert!(!plain.fused() && fused.fused(), "J = {j}: the fused step applies to the beam");
                    let mut contacts = 0;
                    for step in 0..400 {
                        if step == 150 {
                            let mut st = plain.state().unwrap();
                            st.iter_mut().enumerate().for_each(|(i, x)| *x += 1e-5 * (i as f64).sin());
                            plain.set_state(&st).unwrap();
                            fused.set_state(&st).unwrap();
                        }
                        if step == 250 || step == 253 {
                            fused.set_fused(step == 253);
                        }
                        fused_steps += usize::from(fused.fused());
                        let (ra, rb) = (plain.step().unwrap(), fused.step().unwrap());
                        let what = format!("J = {j} β = {beta} e = {e} terms {terms}, step {step}");
                        assert_eq!(ra, rb, "{what}: report");
                        assert_eq!(ra.lambda.map(|l| l.1.to_bits()), rb.lambda.map(|l| l.1.to_bits()), "{what}: λ");
                        assert!(bits(plain.displacement()) == bits(fused.displacement()), "{what}: U");
                        assert!(bits(plain.previous_displacement()) == bits(fused.previous_displacement()), "{what}: U^(n-1)");
                        // The work every fifth step: asked for, `work` adds the
                        // pending sum itself; not asked for, the next step's
                        // forward pass does.
                        if step % 5 == 4 {
                            let (wa, wb) = (plain.work().unwrap(), fused.work().unwrap());
                            assert!(wa.0.to_bits() == wb.0.to_bits() && wa.1.to_bits() == wb.1.to_bits(), "{what}: work {wa:?} vs {wb:?}");
                        }
                        if step % 7 == 0 {
                            let (ea, eb) = (plain.energy().unwrap(), fused.energy().unwrap());
                            assert!(ea.1.to_bits() == eb.1.to_bits(), "{what}: energy");
                        }
                        contacts += usize::from(rb.active != Active::None);
                    }
                    // The work read only at the end (the pending sum added by `work` itself).
                    let (mut a, mut b) = (build(), build());
                    a.set_fused(false);
                    for _ in 0..57 {
                        a.step().unwrap();
                        b.step().unwrap();
                    }
                    assert_eq!(a.work().map(|w| (w.0.to_bits(), w.1.to_bits())), b.work().map(|w| (w.0.to_bits(), w.1.to_bits())), "J = {j} β = {beta}: work at the end");
                    // (Unforced, the beam need not reach a stop.)
                    assert!(terms == 0 || contacts > 10, "J = {j} β = {beta} e = {e}: {contacts} contact steps");
                }
            }
        }
    }
    assert!(fused_steps > 20_000, "{fused_steps} fused steps");
}

/// The fused β-step (the whole unconstrained step — `2U^n − U^{n−1}`,
/// `(1−2β) U^n + β U^{n−1}`, the right-hand side in the forward sweep and
/// its own copy of `BandLdlt::backward_in_place`'s sweep, compiled together)
/// from random states: every 40 steps both runs are put in the same random
/// state (`set_state`: displacements around the stops, random velocities),
/// so contacts start active and inactive; the contact at the tip, at a dof
/// in the middle and at dof 0; the sine support with a static load; the
/// baseline build (`portable`) and the one the CPU selects. `U^n`, `U^{n−1}`,
/// the report and λ are equal (`to_bits`) at every step, the works and the
/// energy at every state change.
#[test]
fn fused_beam_step_from_random_states_is_the_plain_step_bit_for_bit() {
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut rand = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut active, mut free) = (0, 0);
    for j in [7usize, 19] {
        let n = 2 * j;
        for c in [n - 2, n / 2 + 1, 0] {
            for portable in [false, true] {
                let stops = (-0.004, 0.003);
                let (mut dy, init) = pipe(j, 0.2, 10.0, stops);
                dy.contacts[0].dof = c;
                dy.load = (0..n).map(|i| 0.3 * (i as f64 * 0.7).sin()).collect();
                let build = || PaoliSchatzman::new("ps".into(), dy.clone(), 0.5, 0.0, 1e-4, &init).unwrap();
                let (mut plain, mut fused) = (build(), if portable { build().portable() } else { build() });
                plain.set_fused(false);
                assert!(fused.fused(), "J = {j}, c = {c}: the fused step applies");
                for step in 0..600 {
                    let what = format!("J = {j}, c = {c}, portable {portable}, step {step}");
                    if step % 40 == 0 {
                        if step > 0 {
                            let (wa, wb) = (plain.work().unwrap(), fused.work().unwrap());
                            assert!(wa.0.to_bits() == wb.0.to_bits() && wa.1.to_bits() == wb.1.to_bits(), "{what}: work {wa:?} vs {wb:?}");
                            let (ea, eb) = (plain.energy().unwrap(), fused.energy().unwrap());
                            assert_eq!(ea.1.to_bits(), eb.1.to_bits(), "{what}: energy");
                        }
                        let st: Vec<f64> = (0..2 * n).map(|i| if i < n { 0.01 * (rand() - 0.5) } else { 0.2 * (rand() - 0.5) }).collect();
                        plain.set_state(&st).unwrap();
                        fused.set_state(&st).unwrap();
                    }
                    let (ra, rb) = (plain.step().unwrap(), fused.step().unwrap());
                    assert_eq!(ra, rb, "{what}: report");
                    assert_eq!(ra.lambda.map(|l| l.1.to_bits()), rb.lambda.map(|l| l.1.to_bits()), "{what}: λ");
                    assert!(bits(plain.displacement()) == bits(fused.displacement()), "{what}: U");
                    assert!(bits(plain.previous_displacement()) == bits(fused.previous_displacement()), "{what}: U^(n-1)");
                    if rb.active == Active::None {
                        free += 1;
                    } else {
                        active += 1;
                    }
                }
            }
        }
    }
    assert!(active > 500 && free > 1000, "{active} steps with the contact active, {free} free");
}
