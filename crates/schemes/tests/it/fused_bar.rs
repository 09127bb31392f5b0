//! The fused steps of the implicit schemes on the P1 bar (issue 35): the
//! right-hand side made inside the forward sweep of the tridiagonal solve
//! (`ps(e, β)`, Moreau–Jean, `nitsche`, the reduced schemes) gives the bits
//! of each scheme's general path (its products, passes and solve) on random
//! tridiagonal chains — massive and massless contact nodes, one and two
//! contacts, restitution, time-dependent loads, random states — in the
//! baseline x86-64 build of the kernel and in the one the CPU selects.
//! Each scheme's general path is checked against independent
//! transcriptions elsewhere (`conformance.rs`, `ps_massless.rs`,
//! `moreau_lockstep.rs`, `energy.rs`); here the two paths are compared bit
//! for bit at every step: the report, `U`, the state, the contact forces,
//! the works and the energy.

use signorini_fem::SymBand;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Initial, MoreauJean, Nitsche, PaoliSchatzman, Reduced, ReducedLaw, SplitMix64, Stepper, TimeProfile};

/// A random P1-like chain of `n` dofs: `M` consistent (or lumped), node 0
/// massless if asked (its row of `M` zero, `K_00 = −K_01`: the end node of
/// one element), `K` tridiagonal and positive definite.
pub(crate) fn chain(rng: &mut SplitMix64, n: usize, lumped: bool, massless: bool) -> (SymBand, SymBand) {
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        let mi = 0.5 + rng.next_f64();
        m.set(i, i, if lumped { mi } else { 2.0 * mi / 3.0 });
        if i > 0 && !lumped {
            m.set(i, i - 1, mi / 6.0);
        }
        let ki = 1.0 + 3.0 * rng.next_f64();
        k.set(i, i, 2.0 * ki);
        if i > 0 {
            k.set(i, i - 1, -ki);
        }
    }
    if massless {
        m.set(0, 0, 0.0);
        if n > 1 {
            m.set(1, 0, 0.0);
            k.set(0, 0, -k.get(1, 0));
        }
    }
    (m, k)
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

fn forcing(rng: &mut SplitMix64, n: usize) -> Vec<Forcing> {
    (0..2).map(|j| Forcing { shape: (0..n).map(|_| rng.next_f64() - 0.5).collect(), time: TimeProfile::Sine { amplitude: 0.5 + j as f64, omega: 3.0 + 2.0 * j as f64 } }).collect()
}

/// Steps `plain` (general path) and `fused` side by side, random states
/// every 25 steps where the scheme has a state; every bit compared. Returns
/// the steps with a contact force.
fn compare(what: &str, plain: &mut dyn Stepper, fused: &mut dyn Stepper, rng: &mut SplitMix64, steps: usize) -> usize {
    let mut held = 0;
    for step in 0..steps {
        let what = format!("{what}, step {step}");
        if step % 25 == 24 {
            if let Some(s) = plain.state() {
                let n = plain.displacement().len();
                let st: Vec<f64> = (0..s.len()).map(|i| if i < n { 0.06 * (rng.next_f64() - 0.5) } else { rng.next_f64() - 0.5 }).collect();
                plain.set_state(&st).unwrap();
                fused.set_state(&st).unwrap();
            }
        }
        let (ra, rb) = (plain.step().unwrap(), fused.step().unwrap());
        assert_eq!(ra, rb, "{what}: report");
        assert!(bits(plain.displacement()) == bits(fused.displacement()), "{what}: U");
        assert_eq!(plain.state().map(|s| bits(&s)), fused.state().map(|s| bits(&s)), "{what}: state");
        assert!(bits(plain.contact_forces()) == bits(fused.contact_forces()), "{what}: λ");
        let w = |x: Option<(f64, f64)>| x.map(|(a, b)| (a.to_bits(), b.to_bits()));
        assert_eq!(w(plain.work()), w(fused.work()), "{what}: work");
        if step % 7 == 0 {
            assert_eq!(w(plain.energy()), w(fused.energy()), "{what}: energy");
        }
        if plain.contact_forces().iter().any(|l| *l != 0.0) {
            held += 1;
        }
    }
    held
}

const SIZES: [usize; 6] = [2, 3, 4, 33, 40, 100];

#[test]
fn ps_fused_bar_step_is_the_general_path_bit_for_bit() {
    let mut rng = SplitMix64::new(351);
    let (mut held, mut runs) = (0, 0);
    for n in SIZES {
        for case in 0..8 {
            // Every contact massless or every one massive: the second (massive) only with a massive first.
            let (lumped, massless) = (case & 1 == 1, case & 4 == 4);
            let two = case & 2 == 2 && n > 2 && !massless;
            let (m, k) = chain(&mut rng, n, lumped, massless);
            let load: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.7).collect();
            let mut contacts = vec![Contact::new(0, Bounds { lo: -0.02, hi: f64::INFINITY }, massless)];
            if two {
                contacts.push(Contact::new(n / 2, Bounds { lo: -0.03, hi: 0.01 }, false).with_restitution(Some(0.3)));
            }
            let dy = Dynamics::new(m, k, load, contacts).with_forcing(forcing(&mut rng, n));
            let init = Initial { u: vec![0.0; n], v: (0..n).map(|_| rng.next_f64() - 0.5).collect() };
            for (e, beta) in [(0.0, 0.25), (0.5, 0.25), (1.0, 0.3), (0.5, 0.1)] {
                if beta < 0.25 && massless {
                    continue;
                }
                for portable in [false, true] {
                    let build = || PaoliSchatzman::new("ps".into(), dy.clone(), beta, e, 0.05, &init).unwrap();
                    let (mut plain, mut fused) = (build(), if portable { build().portable() } else { build() });
                    plain.set_fused(false);
                    assert!(!plain.fused() && fused.fused(), "n = {n}, case {case}: the fused step applies");
                    let what = format!("n = {n}, case {case}, e = {e}, β = {beta}, portable {portable}");
                    held += compare(&what, &mut plain, &mut fused, &mut rng, 150);
                    runs += 1;
                }
            }
        }
    }
    // Per size: four massive cases × 4 (e, β) × 2 builds, four massless × 3 × 2.
    assert!(runs == 6 * (4 * 8 + 4 * 6) && held > 3000, "{runs} runs, {held} steps with a contact force");
}

#[test]
fn moreau_jean_fused_bar_step_is_the_general_path_bit_for_bit() {
    let mut rng = SplitMix64::new(352);
    let (mut held, mut runs) = (0, 0);
    for n in SIZES {
        for case in 0..4 {
            let (lumped, two) = (case & 1 == 1, case & 2 == 2 && n > 2);
            let (m, k) = chain(&mut rng, n, lumped, false);
            let load: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.7).collect();
            let mut contacts = vec![Contact::new(0, Bounds { lo: -0.02, hi: f64::INFINITY }, false)];
            if two {
                contacts.push(Contact::new(n / 2, Bounds { lo: -0.03, hi: 0.01 }, false).with_restitution(Some(0.3)));
            }
            let dy = Dynamics::new(m, k, load, contacts).with_forcing(forcing(&mut rng, n));
            let init = Initial { u: vec![0.0; n], v: (0..n).map(|_| rng.next_f64() - 0.5).collect() };
            for (theta, e, gamma) in [(0.5, 0.0, 0.5), (0.7, 0.5, 1.0), (1.0, 1.0, 0.0)] {
                for portable in [false, true] {
                    let build = || MoreauJean::new("mj".into(), dy.clone(), theta, e, gamma, 0.05, &init).unwrap();
                    let (mut plain, mut fused) = (build(), if portable { build().portable() } else { build() });
                    plain.set_fused(false);
                    assert!(!plain.fused() && fused.fused(), "n = {n}, case {case}: the fused step applies");
                    let what = format!("n = {n}, case {case}, θ = {theta}, e = {e}, γ = {gamma}, portable {portable}");
                    held += compare(&what, &mut plain, &mut fused, &mut rng, 150);
                    runs += 1;
                }
            }
        }
    }
    assert!(runs == 6 * 4 * 6 && held > 1000, "{runs} runs, {held} steps with a contact force");
}

#[test]
fn nitsche_fused_bar_step_is_the_general_path_bit_for_bit() {
    let mut rng = SplitMix64::new(353);
    let (mut held, mut runs) = (0, 0);
    for n in SIZES {
        for case in 0..4 {
            let (lumped, massless) = (case & 1 == 1, case & 2 == 2);
            let (m, k) = chain(&mut rng, n, lumped, massless);
            let load: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.7).collect();
            let dy = Dynamics::new(m, k, load, vec![Contact::new(0, Bounds { lo: -0.02, hi: f64::INFINITY }, massless)]);
            for (gamma0, theta) in [(10.0, 1.0), (5.0, 0.0), (20.0, -1.0)] {
                for portable in [false, true] {
                    let init = Initial { u: (0..n).map(|_| 0.02 * (rng.next_f64() - 0.5)).collect(), v: (0..n).map(|_| rng.next_f64() - 0.6).collect() };
                    let build = || Nitsche::new("nitsche".into(), dy.clone(), 0.25, 0.5, gamma0, theta, 0.05, &init).unwrap();
                    let (mut plain, mut fused) = (build(), if portable { build().portable() } else { build() });
                    plain.set_fused(false);
                    assert!(!plain.fused() && fused.fused(), "n = {n}, case {case}: the fused step applies");
                    let what = format!("n = {n}, case {case}, γ0 = {gamma0}, θ = {theta}, portable {portable}");
                    held += compare(&what, &mut plain, &mut fused, &mut rng, 150);
                    let (mut va, mut vb) = (vec![0.0; n], vec![0.0; n]);
                    plain.velocity(&mut va);
                    fused.velocity(&mut vb);
                    assert!(bits(&va) == bits(&vb), "{what}: V");
                    runs += 1;
                }
            }
        }
    }
    assert!(runs == 6 * 4 * 6 && held > 1000, "{runs} runs, {held} steps with a contact force");
}

#[test]
fn reduced_fused_bar_step_is_the_general_path_bit_for_bit() {
    let mut rng = SplitMix64::new(354);
    let (mut held, mut runs) = (0, 0);
    for n in [3usize, 4, 5, 34, 41, 101] {
        for lumped in [false, true] {
            let (m, k) = chain(&mut rng, n, lumped, true);
            let load: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.7).collect();
            let dy = Dynamics::new(m, k, load, vec![Contact::new(0, Bounds { lo: -0.02, hi: f64::INFINITY }, true)]);
            for law in [ReducedLaw::Hybrid, ReducedLaw::CrankNicolson] {
                for portable in [false, true] {
                    let init = Initial { u: (0..n).map(|_| 0.02 * (rng.next_f64() - 0.5)).collect(), v: (0..n).map(|_| rng.next_f64() - 0.6).collect() };
                    let build = || Reduced::new("reduced".into(), dy.clone(), law, 0.05, &init).unwrap();
                    let (mut plain, mut fused) = (build(), if portable { build().portable() } else { build() });
                    plain.set_fused(false);
                    assert!(!plain.fused() && fused.fused(), "n = {n}, lumped {lumped}: the fused step applies");
                    let what = format!("n = {n}, lumped {lumped}, {law:?}, portable {portable}");
                    held += compare(&what, &mut plain, &mut fused, &mut rng, 150);
                    assert!(bits(plain.velocity()) == bits(fused.velocity()), "{what}: V");
                    runs += 1;
                }
            }
        }
    }
    assert!(runs == 6 * 2 * 4 && held > 500, "{runs} runs, {held} steps with a contact force");
}
