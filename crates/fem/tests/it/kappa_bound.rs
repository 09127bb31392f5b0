//! The certified bound of `κ_h` that the CFL checks use (issue 23, item 3):
//! the closed form of the uniform P1 bar (docs/theory.md §2.4) against a
//! dense faer generalized eigensolve, and the Lanczos bound with its inertia
//! certificate on every other pencil (non-uniform meshes, P2/P3, the beam,
//! massless-node reductions, a penalty spring): never below the dense
//! `κ_h`, within 1e-8 of it, with an iteration count that does not grow
//! with `n` (checked at n = 100 and n = 10 000).
//!
//! Tolerances: the dense solve carries a few ulps of `‖L⁻¹KL⁻ᵀ‖ = κ_h`
//! (n <= 120 here), so the closed form is compared to 1e-12 relative; the
//! Lanczos bound adds a relative 1e-13 above a shift certified by the
//! inertia test, so `upper >= dense` holds with room against the dense
//! solve's rounding.

use crate::common;

use common::{close, dense, generalized_eigenvalues};
use signorini_fem::{lanczos_top, max_generalized_eigenvalue_bound, max_generalized_eigenvalue_lanczos, uniform_p1_max_eigenvalue, Bar, BarMass, Beam, RightEnd, SymBand};

fn dense_spectrum(k: &SymBand, m: &SymBand) -> Vec<f64> {
    generalized_eigenvalues(&dense(k), &dense(m))
}

fn dense_max(k: &SymBand, m: &SymBand) -> f64 {
    *dense_spectrum(k, m).last().unwrap()
}

/// A P1 bar on a non-uniform mesh (element lengths vary by ±40 %), free at
/// node 0, clamped or free at the far end, lumped or consistent mass.
fn nonuniform_p1(m: usize, free: bool, lumped: bool) -> (SymBand, SymBand) {
    let c2 = 1.7 * 1.7;
    let n = if free { m + 1 } else { m };
    let (mut k, mut mm) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for j in 0..m {
        let h = 2.5 / m as f64 * (1.0 + 0.4 * (1.3 * j as f64).sin());
        let (a, b) = (j, j + 1);
        let add = |x: &mut SymBand, i: usize, l: usize, v: f64| {
            if i < n && l < n {
                x.add(i, l, v);
            }
        };
        add(&mut k, a, a, c2 / h);
        add(&mut k, b, b, c2 / h);
        add(&mut k, a, b, -c2 / h);
        if lumped {
            add(&mut mm, a, a, h / 2.0);
            add(&mut mm, b, b, h / 2.0);
        } else {
            add(&mut mm, a, a, h / 3.0);
            add(&mut mm, b, b, h / 3.0);
            add(&mut mm, a, b, h / 6.0);
        }
    }
    (k, mm)
}

fn ends() -> [RightEnd; 2] {
    [RightEnd::Clamped, RightEnd::Free]
}

/// The closed form, from the bar's parameters and recognised from its
/// matrices, equals the largest dense generalized eigenvalue for several m,
/// both far ends, both masses that have one; the certified bound uses it.
#[test]
fn closed_form_matches_the_dense_eigensolve() {
    for end in ends() {
        for m in [2usize, 3, 5, 8, 17, 40, 101] {
            let b = Bar::new(2.5, m, 1.7, end).unwrap();
            for v in [BarMass::Lumped, BarMass::Std] {
                let what = format!("{v}, m = {m}, {end:?}");
                let (k, mm) = (b.stiffness(), b.mass(v));
                let want = dense_max(&k, &mm);
                let from_bar = b.max_eigenvalue_closed_form(v).expect("std and lumped have a closed form");
                let recognised = uniform_p1_max_eigenvalue(&k, &mm).unwrap_or_else(|| panic!("{what}: not recognised as a uniform P1 bar"));
                assert!(close(from_bar, want, 1e-12), "{what}: closed form {from_bar}, dense {want}");
                assert!(close(recognised, want, 1e-12), "{what}: recognised closed form {recognised}, dense {want}");
                let bound = max_generalized_eigenvalue_bound(&k, &mm).unwrap();
                assert!(bound.closed_form && bound.iterations() == 0, "{what}: {bound:?}");
                assert!(bound.upper >= recognised && close(bound.upper, want, 1e-12), "{what}: {bound:?} vs dense {want}");
            }
        }
    }
    // Written out: lumped free-free 4c²/h², consistent free-free 12c²/h².
    let b = Bar::new(2.5, 10, 1.7, RightEnd::Free).unwrap();
    let c2h2 = 1.7 * 1.7 / (b.h() * b.h());
    assert!(close(b.max_eigenvalue_closed_form(BarMass::Lumped).unwrap(), 4.0 * c2h2, 1e-15));
    assert!(close(b.max_eigenvalue_closed_form(BarMass::Std).unwrap(), 12.0 * c2h2, 1e-15));
}

/// Only a uniform P1 bar's pencil with std or lumped mass is recognised:
/// the massless-node masses (and their reduced pencils), P2/P3, the beam,
/// a penalty spring at the contact node, a non-uniform mesh and a one-ulp
/// change of one entry all go to Lanczos.
#[test]
fn other_pencils_are_not_taken_for_a_uniform_bar() {
    let b = Bar::new(1.0, 12, 1.0, RightEnd::Clamped).unwrap();
    for v in BarMass::ALL.into_iter().filter(|v| v.massless_contact_node()) {
        assert_eq!(b.max_eigenvalue_closed_form(v), None, "{v}");
        assert_eq!(uniform_p1_max_eigenvalue(&b.stiffness().trailing(1), &b.mass(v).trailing(1)), None, "{v}");
    }
    for k in [2, 3] {
        let p = b.with_degree(k).unwrap();
        for v in [BarMass::Std, BarMass::Lumped] {
            assert_eq!(p.max_eigenvalue_closed_form(v), None);
            assert_eq!(uniform_p1_max_eigenvalue(&p.stiffness(), &p.mass(v)), None, "P{k} {v}");
        }
    }
    let beam = Beam::new(1.0, 10, 1.0).unwrap();
    assert_eq!(uniform_p1_max_eigenvalue(&beam.stiffness(), &beam.mass()), None);
    let mut kp = b.stiffness();
    kp.add(0, 0, 10.0 * 12.0);
    assert_eq!(uniform_p1_max_eigenvalue(&kp, &b.mass(BarMass::Lumped)), None);
    for (free, lumped) in [(true, true), (false, false)] {
        let (k, mm) = nonuniform_p1(12, free, lumped);
        assert_eq!(uniform_p1_max_eigenvalue(&k, &mm), None);
    }
    let mut mm = b.mass(BarMass::Lumped);
    let x = mm.get(5, 5);
    mm.set(5, 5, f64::from_bits(x.to_bits() + 1));
    assert_eq!(uniform_p1_max_eigenvalue(&b.stiffness(), &mm), None);
    assert!(uniform_p1_max_eigenvalue(&b.stiffness(), &b.mass(BarMass::Lumped)).is_some());
}

/// Every pencil without a closed form that the schemes meet, or could.
fn other_pencils() -> Vec<(String, SymBand, SymBand)> {
    let mut out = Vec::new();
    for m in [7usize, 30, 60] {
        for free in [true, false] {
            for lumped in [true, false] {
                let (k, mm) = nonuniform_p1(m, free, lumped);
                out.push((format!("non-uniform P1 m = {m} free {free} lumped {lumped}"), k, mm));
            }
        }
    }
    for end in ends() {
        for m in [5usize, 20] {
            let b = Bar::new(2.5, m, 1.7, end).unwrap();
            for deg in [2, 3] {
                let p = b.with_degree(deg).unwrap();
                for v in [BarMass::Std, BarMass::Lumped] {
                    out.push((format!("P{deg} {v} m = {m} {end:?}"), p.stiffness(), p.mass(v)));
                }
            }
            for v in BarMass::ALL.into_iter().filter(|v| v.massless_contact_node()) {
                out.push((format!("reduced (K*, M*) {v} m = {m} {end:?}"), b.stiffness().trailing(1), b.mass(v).trailing(1)));
            }
            let mut kp = b.stiffness();
            kp.add(0, 0, 10.0 * kp.get(0, 0));
            out.push((format!("penalty lumped m = {m} {end:?}"), kp, b.mass(BarMass::Lumped)));
        }
    }
    for j in [4usize, 19, 40] {
        let beam = Beam::new(1.3, j, 2.0).unwrap();
        out.push((format!("beam J = {j}"), beam.stiffness(), beam.mass()));
    }
    out
}

/// The Lanczos bound is never below the dense `κ_h` and within 1e-8 of it
/// (in fact 1e-12), for every pencil without a closed form; the certified
/// bound takes that path for them.
#[test]
fn lanczos_bound_is_above_and_close_to_the_dense_kappa() {
    for (what, k, mm) in other_pencils() {
        let want = dense_max(&k, &mm);
        let b = max_generalized_eigenvalue_lanczos(&k, &mm).unwrap();
        assert!(b.upper >= want, "{what}: bound {:e} below the dense κ_h {want:e} ({b:?})", b.upper);
        assert!(b.upper <= want * (1.0 + 1e-8), "{what}: bound {:e}, dense κ_h {want:e}: {:e} relative above ({b:?})", b.upper, b.upper / want - 1.0);
        assert!(b.lower <= want * (1.0 + 1e-13), "{what}: lower {:e} above the dense κ_h {want:e}", b.lower);
        assert!(b.iterations() <= 80, "{what}: {} iterations ({b:?})", b.iterations());
        let auto = max_generalized_eigenvalue_bound(&k, &mm).unwrap();
        assert!(!auto.closed_form && auto.upper == b.upper, "{what}: {auto:?}");
    }
}

/// The Ritz value and its residual bound: some dense eigenvalue lies in
/// `[θ − r, θ + r]`, and `θ <= κ_h`. Few Lanczos steps, so the Ritz value
/// is not yet an eigenvalue and the residual term is what makes the
/// interval hold.
#[test]
fn ritz_value_and_residual_enclose_an_eigenvalue() {
    for (what, k, mm) in other_pencils() {
        let spectrum = dense_spectrum(&k, &mm);
        let top = *spectrum.last().unwrap();
        for steps in [3, 5, 8] {
            let r = lanczos_top(&k, &mm, steps).unwrap();
            assert!(r.value <= top * (1.0 + 1e-13), "{what}, {steps} steps: Ritz value {:e} above κ_h {top:e}", r.value);
            let slack = 1e-13 * top;
            let nearest = spectrum.iter().map(|l| (l - r.value).abs()).fold(f64::INFINITY, f64::min);
            assert!(nearest <= r.residual + slack, "{what}, {steps} steps: no eigenvalue within {:e} of θ = {:e} (nearest at {nearest:e})", r.residual, r.value);
        }
    }
}

/// The iteration count does not grow with n: n = 100 and n = 10 000 for a
/// P2 bar, the beam, a non-uniform P1 bar and the uniform lumped P1 bar
/// forced through Lanczos (bound checked against its closed form there).
#[test]
fn iteration_count_does_not_grow_with_n() {
    let mut counts = Vec::new();
    for n in [100usize, 10_000] {
        let p2 = Bar::new(1.0, n / 2, 1.0, RightEnd::Clamped).unwrap().with_degree(2).unwrap();
        let beam = Beam::new(1.0, n / 2, 1.0).unwrap();
        let (kn, mn) = nonuniform_p1(n, false, false);
        let p1 = Bar::new(1.0, n, 1.0, RightEnd::Clamped).unwrap();
        let cases = [
            ("P2 std", p2.stiffness(), p2.mass(BarMass::Std)),
            ("beam", beam.stiffness(), beam.mass()),
            ("non-uniform P1 std", kn, mn),
            ("uniform P1 lumped (Lanczos)", p1.stiffness(), p1.mass(BarMass::Lumped)),
        ];
        for (what, k, mm) in cases {
            assert_eq!(k.n(), n, "{what}");
            let b = max_generalized_eigenvalue_lanczos(&k, &mm).unwrap();
            assert!(b.iterations() <= 80, "{what}, n = {n}: {} iterations ({b:?})", b.iterations());
            assert!(b.upper >= b.lower && b.upper - b.lower <= 2e-12 * b.upper, "{what}, n = {n}: {b:?}");
            if what.starts_with("uniform") {
                let exact = p1.max_eigenvalue_closed_form(BarMass::Lumped).unwrap();
                assert!(b.upper >= exact && b.upper <= exact * (1.0 + 1e-8), "n = {n}: bound {:e}, closed form {exact:e}", b.upper);
            }
            counts.push((what, n, b.iterations()));
        }
    }
    println!("iterations: {counts:?}");
}
