//! The forward-increment Lagrange multiplier method of Carpenter, Taylor
//! and Katona (IJNME 32, 1991) is `taylor-flanagan` (`ps(0,0)`): the
//! central difference whose contact multiplier at `tⁿ` is chosen so that
//! `Uⁿ⁺¹` meets the constraints (docs/theory.md §4.6.3). Here their step is
//! written densely — the predictor `U* = 2Uⁿ − Uⁿ⁻¹ + dt² M⁻¹(F − K Uⁿ)`,
//! then the multipliers by their Gauss–Seidel sweeps on
//! `G (U* + dt² M⁻¹ Gᵀ λ)` against the bounds until they stop changing — and
//! followed against `taylor-flanagan` on random systems with consistent
//! and lumped masses, a steady load and two contacts (one two-sided),
//! from the scheme's second level on (the starts differ: theory §4.3).

use crate::stabilized::{dense, mv, solve, system, Dense};
use signorini_schemes::{Dynamics, SchemeSpec, SplitMix64};

/// One step of Carpenter–Taylor–Katona from `(Uⁿ⁻¹, Uⁿ)`.
fn carpenter_step(m: &Dense, k: &Dense, f: &[f64], cons: &[(usize, f64, f64)], dt: f64, um: &[f64], u: &[f64]) -> Vec<f64> {
    let n = u.len();
    let r: Vec<f64> = mv(k, u).iter().zip(f).map(|(ku, f)| f - ku).collect();
    let acc = solve(m.clone(), r);
    let mut x: Vec<f64> = (0..n).map(|i| 2.0 * u[i] - um[i] + dt * dt * acc[i]).collect();
    // Influence of a unit multiplier at contact j: dt² M⁻¹ e_{c_j}.
    let cols: Vec<Vec<f64>> = cons
        .iter()
        .map(|&(c, _, _)| {
            let mut e = vec![0.0; n];
            e[c] = 1.0;
            solve(m.clone(), e).iter().map(|w| dt * dt * w).collect()
        })
        .collect();
    let mut lam = vec![0.0; cons.len()];
    for _sweep in 0..10_000 {
        let mut change = 0.0f64;
        for (j, &(c, lo, hi)) in cons.iter().enumerate() {
            // Contact j's multiplier with the others fixed: the one that puts
            // x_c on the bound it would cross, zero if it crosses none.
            let w = cols[j][c];
            let y = x[c] - lam[j] * w;
            let new = if y < lo {
                (lo - y) / w
            } else if y > hi {
                (hi - y) / w
            } else {
                0.0
            };
            let d = new - lam[j];
            if d != 0.0 {
                for (xi, wi) in x.iter_mut().zip(&cols[j]) {
                    *xi += d * wi;
                }
                change = change.max(d.abs());
                lam[j] = new;
            }
        }
        if change <= 1e-16 {
            break;
        }
    }
    x
}

#[test]
fn carpenters_forward_increment_multipliers_are_taylor_flanagan() {
    let spec: SchemeSpec = "taylor-flanagan".parse().unwrap();
    let mut rng = SplitMix64::new(1991);
    let (mut worst, mut active) = (0.0f64, 0usize);
    for case in 0..8 {
        let (dy, init) = system(&mut rng, case & 1 == 1, false, true);
        let dy = Dynamics::new(dy.mass.clone(), dy.stiffness.clone(), dy.load.clone(), dy.contacts.clone());
        let (m, k, f) = (dense(&dy.mass), dense(&dy.stiffness), dy.load.clone());
        let cons: Vec<(usize, f64, f64)> = dy.contacts.iter().map(|c| (c.dof, c.bounds.lo, c.bounds.hi)).collect();
        let dt = 0.5 * spec.cfl_limit(&dy).unwrap().expect("explicit");
        // The scheme's start step is taken when it is built (level 1).
        let mut s = spec.build(dy, dt, &init).unwrap();
        assert_eq!(s.level(), 1);
        let (mut um, mut u) = (init.u.clone(), s.displacement().to_vec());
        for step in 1..300 {
            let want = carpenter_step(&m, &k, &f, &cons, dt, &um, &u);
            s.step().unwrap();
            let got = s.displacement();
            let scale = 1.0 + want.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                let e = (g - w).abs() / scale;
                worst = worst.max(e);
                assert!(e <= 1e-12, "case {case}, step {step}, dof {i}: {g} vs Carpenter's {w}");
            }
            active += cons.iter().filter(|&&(c, lo, hi)| want[c] == lo || want[c] == hi).count();
            (um, u) = (u, want);
        }
    }
    assert!(active > 50, "only {active} constrained contact-steps: the test would be vacuous");
    eprintln!("Carpenter–Taylor–Katona vs taylor-flanagan: worst {worst:.1e}, {active} constrained contact-steps");
}

/// The cases a user meets first, 2000 steps each against the same dense
/// step, with a consistent (tridiagonal) and a lumped mass:
/// * a held start: a chain at rest on its stop (`U = 0`, `lo = 0`) pressed
///   by a steady load on the contact dof — it stays at rest (every dof
///   within 1e-15 of 0), the contact held at every step;
/// * mirror-symmetric stops reached together: a lower stop at dof 0 and an
///   upper one at dof n − 1, each 0.05 away, an antisymmetric start — the
///   motion stays antisymmetric to round-off through repeated impacts.
#[test]
fn held_starts_and_symmetric_contacts_are_carpenters() {
    use signorini_fem::SymBand;
    use signorini_schemes::{Bounds, Contact, Initial};
    let spec: SchemeSpec = "taylor-flanagan".parse().unwrap();
    let n = 6;
    for lumped in [false, true] {
        let chain = || {
            let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
            for i in 0..n {
                m.set(i, i, if lumped { 1.0 } else { 2.0 / 3.0 });
                k.set(i, i, 2.0);
                if i > 0 {
                    if !lumped {
                        m.set(i, i - 1, 1.0 / 6.0);
                    }
                    k.set(i, i - 1, -1.0);
                }
            }
            (m, k)
        };
        let run = |dy: Dynamics, init: Initial, label: &str| {
            let (m, k, f) = (dense(&dy.mass), dense(&dy.stiffness), dy.load.clone());
            let cons: Vec<(usize, f64, f64)> = dy.contacts.iter().map(|c| (c.dof, c.bounds.lo, c.bounds.hi)).collect();
            let dt = 0.5 * spec.cfl_limit(&dy).unwrap().expect("explicit");
            let mut s = spec.build(dy, dt, &init).unwrap();
            let (mut um, mut u) = (init.u.clone(), s.displacement().to_vec());
            let (mut worst, mut active, mut states) = (0.0f64, 0usize, vec![u.clone()]);
            for step in 1..2000 {
                let want = carpenter_step(&m, &k, &f, &cons, dt, &um, &u);
                s.step().unwrap();
                let scale = 1.0 + want.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for (i, (g, w)) in s.displacement().iter().zip(&want).enumerate() {
                    let e = (g - w).abs() / scale;
                    worst = worst.max(e);
                    assert!(e <= 1e-12, "{label}, lumped {lumped}, step {step}, dof {i}: {g} vs Carpenter's {w}");
                }
                active += cons.iter().filter(|&&(c, lo, hi)| want[c] == lo || want[c] == hi).count();
                states.push(s.displacement().to_vec());
                (um, u) = (u, want);
            }
            eprintln!("Carpenter {label}, lumped {lumped}: worst {worst:.1e}, {active} constrained contact-steps");
            (active, states)
        };
        // Held.
        let (m, k) = chain();
        let mut load = vec![0.0; n];
        load[0] = -1.0;
        let dy = Dynamics::new(m, k, load, vec![Contact::new(0, Bounds::obstacle(0.0), false)]);
        let (active, states) = run(dy, Initial { u: vec![0.0; n], v: vec![0.0; n] }, "held start");
        assert_eq!(active, 1999, "held start, lumped {lumped}: the contact must be held at every step");
        for (j, x) in states.iter().enumerate() {
            // At rest to round-off (the consistent mass spreads the pressing
            // load and the multiplier over the chain; they cancel to 1e-18).
            assert!(x.iter().all(|&v| v.abs() <= 1e-15), "held start, lumped {lumped}: moved at level {j}: {x:?}");
        }
        // Two stops reached together.
        let (m, k) = chain();
        let contacts = vec![Contact::new(0, Bounds { lo: -0.05, hi: f64::INFINITY }, false), Contact::new(n - 1, Bounds { lo: f64::NEG_INFINITY, hi: 0.05 }, false)];
        let dy = Dynamics::new(m, k, vec![0.0; n], contacts);
        let v: Vec<f64> = (0..n).map(|i| -0.5 * (1.0 - 2.0 * i as f64 / (n - 1) as f64)).collect();
        let (active, states) = run(dy, Initial { u: vec![0.0; n], v }, "symmetric stops");
        assert!(active > 20, "symmetric stops, lumped {lumped}: {active} constrained contact-steps");
        for (j, x) in states.iter().enumerate() {
            for i in 0..n {
                assert!((x[i] + x[n - 1 - i]).abs() <= 1e-13, "symmetric stops, lumped {lumped}, level {j}: dof {i} {} against {}", x[i], x[n - 1 - i]);
            }
        }
    }
}
