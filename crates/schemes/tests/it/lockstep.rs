//! `PaoliSchatzmanLockstep`: every lane bit for bit the single
//! `PaoliSchatzman` run of its data (U^n, λ, active bound at every step),
//! through repeated impacts on both stops; partial batches; restitution;
//! typed refusals. The oracle is the single run (a separate code path:
//! on the beam its fused β-step — the right-hand side inside the solve's
//! forward sweep, then its own copy of `BandLdlt::backward_in_place`'s sweep,
//! `Projection::project`).
//! Every build of the step is checked: the one the CPU selects (AVX-512 or
//! AVX2 where available), the AVX2 one (`without_avx512()`) and the
//! baseline x86-64 one (`portable()`). The fused β-step is itself checked
//! bit for bit against the plain one (`Bands3::rhs`, `BandLdlt::solve_in_place`)
//! at the end of this file.

pub(crate) use crate::common::bits;
use crate::common::{check_lane_refusals, check_lockstep, Extra};
use signorini_fem::{Beam, SymBand};
use signorini_schemes::{Active, Bounds, Contact, Dynamics, Forcing, Harmonic, Initial, LockstepLane, PaoliSchatzman, PaoliSchatzmanLockstep, SchemeError, SchemeSpec, Stepper, TimeProfile};

const LENGTH: f64 = 1.501;
const K2: f64 = 282.84;

/// `h(x)` of the lifting (crates/run/src/beam.rs, `Pipe::lifting`) and `h'`.
fn lifting(x: f64) -> (f64, f64) {
    let y = x / LENGTH;
    (1.0 - 2.0 * y * y + 4.0 / 3.0 * y.powi(3) - y.powi(4) / 3.0, (-4.0 * y + 4.0 * y * y - 4.0 / 3.0 * y.powi(3)) / LENGTH)
}

/// The paper's pipe (`Pipe::dynamics`, copied) with support `A sin(ω t)`
/// and stops `stops` at the tip: forcing `(A ω² h + 8 A k²/L⁴) sin(ω t)`,
/// `u = 0`, `u_t = -A ω h`.
pub(crate) fn pipe(j: usize, amp: f64, omega: f64, stops: (f64, f64)) -> (Dynamics, Initial) {
    let beam = Beam::new(LENGTH, j, K2).unwrap();
    let l4 = LENGTH.powi(4);
    let shape = beam.load(|x| amp * omega * omega * lifting(x).0 + 8.0 * amp * K2 / l4);
    let n = beam.dofs();
    let dy = Dynamics::new(beam.mass(), beam.stiffness(), vec![0.0; n], vec![Contact::new(beam.tip_dof(), Bounds { lo: stops.0, hi: stops.1 }, false)])
        .with_forcing(vec![Forcing { shape, time: TimeProfile::Sine { amplitude: 1.0, omega } }]);
    let v = beam.interpolate(|x| -amp * omega * lifting(x).0, |x| -amp * omega * lifting(x).1);
    (dy, Initial { u: vec![0.0; n], v })
}

/// The pipe driven by a support motion `φ` of two harmonics (`Pipe::excite`'s
/// two lifting terms, `-h φ''` and `8 k²/L⁴ φ`), starting at rest.
pub(crate) fn pipe_harmonics(j: usize, terms: Vec<Harmonic>, stops: (f64, f64)) -> (Dynamics, Initial) {
    let (beam, mut dy, _) = {
        let (dy, init) = pipe(j, 0.0, 1.0, stops);
        (Beam::new(LENGTH, j, K2).unwrap(), dy, init)
    };
    let phi = TimeProfile::harmonics(terms).unwrap();
    let acc = phi.second_derivative().unwrap();
    let l4 = LENGTH.powi(4);
    dy.forcing = vec![Forcing { shape: beam.load(|x| -lifting(x).0), time: acc }, Forcing { shape: beam.load(|_| 8.0 * K2 / l4), time: phi.clone() }];
    let (p0, dp0) = (phi.value(0.0), phi.derivative_at(0.0).unwrap());
    let u = beam.interpolate(|x| -p0 * lifting(x).0, |x| -p0 * lifting(x).1);
    let v = beam.interpolate(|x| -dp0 * lifting(x).0, |x| -dp0 * lifting(x).1);
    (dy, Initial { u, v })
}

pub(crate) fn lane(d: (Dynamics, Initial), e: f64) -> LockstepLane {
    LockstepLane { dynamics: d.0, initial: d.1, restitution: e }
}

/// The four lanes of every engine's failing-lane test: the pipe between
/// stops at ±0.01, lanes 1 and 3 forced with amplitudes 1e306 and 1e304
/// (their single runs turn non-finite at some step), lanes 0 and 2
/// ordinary. The oracle is checked here, on the scheme's own single runs:
/// `single_fails` (a lane's single run stepped as long as the test steps
/// the batch, its first error) fails on lanes 1 and 3 and on no other.
pub(crate) fn failing_lanes(single_fails: impl Fn(&LockstepLane) -> Option<SchemeError>) -> Vec<LockstepLane> {
    let stops = (-0.01, 0.01);
    let huge = |amp: f64| {
        let (mut dy, init) = pipe(19, 0.2, 37.0, stops);
        dy.forcing[0].time = TimeProfile::Sine { amplitude: amp, omega: 37.0 };
        lane((dy, init), 0.0)
    };
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), huge(1e306), lane(pipe(19, 0.3, 31.0, stops), 0.0), huge(1e304)];
    let fails: Vec<Option<SchemeError>> = lanes.iter().map(single_fails).collect();
    assert!(fails[0].is_none() && fails[2].is_none() && fails[1].is_some() && fails[3].is_some(), "the single runs' failures: {fails:?}");
    lanes
}

/// Steps the batch (every build) and each lane's single run `steps` times
/// and compares them bit for bit at every step ([`check_lockstep`]; and
/// `U^{n-1}`); returns per lane the number of steps held at the lower and
/// upper bound.
fn compare<const L: usize>(beta: f64, dt: f64, lanes: Vec<LockstepLane>, steps: usize) -> Vec<(usize, usize)> {
    let mut singles: Vec<PaoliSchatzman> = lanes.iter().map(|l| PaoliSchatzman::new("single".into(), l.dynamics.clone(), beta, l.restitution, dt, &l.initial).unwrap()).collect();
    let prev = Extra { name: "U^(n-1)", lane: |b: &PaoliSchatzmanLockstep<L>, k, out| b.previous_displacement_into(k, out), single: |s: &PaoliSchatzman| s.previous_displacement(), from: 0 };
    check_lockstep(|| PaoliSchatzmanLockstep::<L>::new(beta, dt, lanes.clone()).unwrap(), &mut singles, &[prev], steps)
}

/// Four lanes of the paper beam (J = 19, β = 1/2, e = 0) with different
/// ω and A, narrow stops so the tip rattles: 4000 steps, bit for bit.
#[test]
fn beam_frequency_and_amplitude_lanes_are_bit_identical_to_single_runs() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.2, 37.0, stops), 0.0), lane(pipe(19, 0.35, 23.5, stops), 0.0), lane(pipe(19, 0.05, 61.0, (-0.1, 0.1)), 0.0)];
    let counts = compare::<4>(0.5, 5e-5, lanes, 4000);
    for (k, &(lo, hi)) in counts.iter().enumerate().take(3) {
        assert!(lo > 20 && hi > 20, "lane {k} should rattle between both stops: {lo} lower, {hi} upper steps");
    }
}

/// An amplitude sweep (same profile in every lane: means shared) and two
/// forcing terms per lane (support motion of two harmonics), β = 1/4, 8 lanes.
#[test]
fn amplitude_sweep_and_two_forcing_terms_are_bit_identical() {
    let stops = (-0.01, 0.02);
    let mut lanes: Vec<LockstepLane> = (0..5).map(|i| lane(pipe(19, 0.1 + 0.07 * i as f64, 30.0, stops), 0.0)).collect();
    for (a, w) in [(0.01, 40.0), (0.012, 70.0), (0.02, 25.0)] {
        let terms = vec![Harmonic { amplitude: a, omega: w, phase: 0.3 }, Harmonic { amplitude: 0.5 * a, omega: 2.7 * w, phase: -1.0 }];
        lanes.push(lane(pipe_harmonics(19, terms, stops), 0.0));
    }
    // Mixing: one forcing term vs two is refused; run the two groups separately.
    let two: Vec<LockstepLane> = lanes.split_off(5);
    let counts = compare::<8>(0.25, 5e-5, lanes, 3000);
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
    let counts = compare::<4>(0.25, 5e-5, two, 3000);
    assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "{counts:?}");
}

/// A partial batch: 4 lanes in a batch of 8, 1 lane in a batch of 2. One
/// lane has ω dt = 1 (ω = 2·10⁴): its factor sin(ω δ/2)/(ω δ/2) changes with
/// the rounding of δ = (n+2) dt - (n+1) dt, so a stale δ shows.
#[test]
fn partial_batches_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 31.0, stops), 0.0), lane(pipe(19, 0.1, 55.0, stops), 0.0), lane(pipe(19, 1e-4, 2e4, stops), 0.0)];
    compare::<8>(0.5, 5e-5, lanes, 3000);
    compare::<2>(0.5, 5e-5, vec![lane(pipe(19, 0.25, 44.0, stops), 0.0)], 2000);
}

/// 16 lanes (the sweeps' widest engine), 11 of them in use: frequencies,
/// amplitudes, restitutions, and two lanes at rest with zero forcing (A = 0
/// and A = -0: zeros of both signs in the data), β = 1/2.
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
            let counts = compare::<4>(beta, 5e-5, lanes, 2000);
            assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "J = {j}, β = {beta}: {counts:?}");
        }
    }
}

/// The contact elsewhere than the tip's displacement (row n-2): mid-beam
/// (row 20), row n-4, and the tip's slope (rows n-3 and n-1): the
/// projection's column and the row it sets differ. J = 19, β = 1/2, 4
/// lanes each: bit for bit.
#[test]
fn contacts_off_the_tip_are_bit_identical() {
    let n = 38;
    for (dof, gap) in [(20, 0.004), (n - 4, 0.008), (n - 3, 0.01), (n - 1, 0.01)] {
        let at = |amp: f64, omega: f64| {
            let (mut dy, init) = pipe(19, amp, omega, (-gap, gap));
            dy.contacts[0].dof = dof;
            lane((dy, init), 0.0)
        };
        let lanes = vec![at(0.2, 10.0), at(0.3, 31.0), at(0.35, 23.5), at(0.1, 55.0)];
        let counts = compare::<4>(0.5, 5e-5, lanes, 2000);
        assert!(counts.iter().all(|&(lo, hi)| lo + hi > 10), "dof {dof}: {counts:?}");
    }
}

/// Restitution per lane (e = 0.5, 1, a contact's own e overriding the
/// lane's), a one-sided obstacle, β = 1/4.
#[test]
fn restitution_lanes_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let mut own = pipe(19, 0.2, 37.0, stops);
    own.0.contacts[0].restitution = Some(0.8);
    let lanes = vec![lane(pipe(19, 0.2, 37.0, stops), 0.5), lane(pipe(19, 0.2, 37.0, stops), 1.0), lane(own, 0.0), lane(pipe(19, 0.3, 20.0, (-0.01, f64::INFINITY)), 0.7)];
    let counts = compare::<4>(0.25, 5e-5, lanes, 3000);
    assert!(counts.iter().all(|&(lo, _)| lo > 0), "{counts:?}");
}

#[test]
fn refusals_are_typed() {
    let base = || lane(pipe(19, 0.2, 10.0, (-0.1, 0.1)), 0.0);
    check_lane_refusals(|lanes| PaoliSchatzmanLockstep::<4>::new(0.5, 5e-5, lanes).err(), base);
    let new = |lanes: Vec<LockstepLane>| PaoliSchatzmanLockstep::<4>::new(0.5, 5e-5, lanes).err().expect("refused");
    let mut d = base();
    d.restitution = 1.5;
    assert!(matches!(new(vec![d]), SchemeError::Invalid { field: "restitution", .. }));
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
    assert!(matches!(new(vec![bar]), SchemeError::Structure(m) if m.contains("half-bandwidth 3")));
}

/// Lanes whose forcing overflows (amplitudes 1e306, 1e304: the single runs
/// turn non-finite at some step) report the single run's `NonFinite` error
/// at that step; the other lanes carry on bit for bit.
#[test]
fn a_failing_lane_reports_the_single_runs_error_and_spares_the_others() {
    let lanes = failing_lanes(|l| {
        let mut s = PaoliSchatzman::new("s".into(), l.dynamics.clone(), 0.5, 0.0, 5e-5, &l.initial).unwrap();
        (0..1500).find_map(|_| s.step().err())
    });
    compare::<4>(0.5, 5e-5, lanes, 1500);
}

/// β = 0 (the start step is Newmark(1/4, 1/2), the step matrix is `M`): the
/// step itself takes no special path; bit for bit too.
#[test]
fn beta_zero_lanes_are_bit_identical() {
    let stops = (-0.01, 0.01);
    let lanes = vec![lane(pipe(19, 0.2, 10.0, stops), 0.0), lane(pipe(19, 0.3, 37.0, stops), 0.5)];
    compare::<2>(0.0, 2e-6, lanes, 3000);
}

/// The beam's fused β-step (right-hand side inside the solve's forward
/// sweep, the forcing's work summed in the next step's forward pass) is
/// the plain step bit for bit: against the same scheme with it switched off
/// (`Bands3::rhs`, `add_terms`, `BandLdlt::solve_in_place`,
/// `add_step_work`), `U^n`, `U^{n−1}`, the report, λ, the work of the
/// forcing and of the contact force and the energy are equal (`to_bits`)
/// at every step — sizes with no, a partial and several full chunks of
/// rows, β = 1/2, 1/4 and 0.1, e = 0 and 1/2, one and two forcing terms
/// with a static load, the baseline x86-64 build and the one the CPU
/// selects, across a `set_state` (which settles the pending work) and
/// with the fused step switched off and on mid-run.
#[test]
fn fused_beam_step_is_the_plain_step_bit_for_bit() {
    let h = |f: f64, w: f64, p: f64| Harmonic { amplitude: 0.02 * f, omega: w, phase: p };
    let mut fused_steps = 0;
    for j in [4usize, 5, 7, 12, 19] {
        for beta in [0.5, 0.25, 0.1] {
            for e in [0.0, 0.5] {
                for terms in [1, 2] {
                    // β = 0.1 within its stability limit, nearer stops.
                    let (dt, stops) =
                        if beta < 0.25 { (0.5 * SchemeSpec::ps(e, beta).cfl_limit(&pipe(j, 0.2, 10.0, (-1.0, 1.0)).0).unwrap().unwrap(), (-2e-4, 1e-4)) } else { (1e-4, (-0.004, 0.003)) };
                    let (mut dy, init) = if terms == 1 { pipe(j, 0.2, 10.0, stops) } else { pipe_harmonics(j, vec![h(1.0, 10.0, 0.3), h(0.5, 23.0, 1.1)], stops) };
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
                    assert!(contacts > 10, "J = {j} β = {beta} e = {e}: {contacts} contact steps");
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
