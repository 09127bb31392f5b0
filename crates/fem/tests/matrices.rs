//! Tests of the P1 bar matrices and the banded factorisation.
//!
//! Tolerances: entries are sums of at most a few terms of size h, so exact
//! identities are checked to 1e-13 relative; factor/solve residuals against a
//! dense faer oracle to 1e-12 relative (condition numbers here are < 1e4).

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use proptest::prelude::*;
use signorini_fem::{Bar, BarMass, FemError, RightEnd, SymBand};

fn bar(m: usize, right_end: RightEnd) -> Bar {
    Bar::new(1.0, m, 1.0, right_end).unwrap()
}

fn dense(a: &SymBand) -> Mat<f64> {
    Mat::from_fn(a.n(), a.n(), |i, j| a.get(i, j))
}

fn total(a: &SymBand) -> f64 {
    let ones = vec![1.0; a.n()];
    a.quad_form(&ones)
}

/// Total mass `1ᵀ M 1` on all nodes (free bar), for a variant, as a multiple of L and h.
fn check_total_mass(variant: BarMass, expected: impl Fn(f64, f64) -> f64) {
    for m in [2, 3, 7, 50] {
        let b = bar(m, RightEnd::Free);
        let got = total(&b.mass(variant));
        let want = expected(b.length, b.h());
        assert!((got - want).abs() <= 1e-13 * want, "{variant} m={m}: total mass {got} != {want}");
    }
}

#[test]
fn total_mass_per_variant() {
    check_total_mass(BarMass::Std, |l, _| l);
    check_total_mass(BarMass::Lumped, |l, _| l);
    check_total_mass(BarMass::Mod, |l, h| l - h);
    check_total_mass(BarMass::Mod1, |l, h| l - h);
    check_total_mass(BarMass::Mod2, |l, _| l);
    check_total_mass(BarMass::Mod3, |l, _| l);
    // transfer: removes M00 + 2 M01 = 2h/3, adds M00 + M01 = h/2 to M11.
    check_total_mass(BarMass::Transfer, |l, h| l - h / 6.0);
    // singular: removes M00 + 2 M01 = 2h/3 and lowers M11 from 2h/3 to 7h/12.
    check_total_mass(BarMass::Singular, |l, h| l - 3.0 * h / 4.0);
}

#[test]
fn mod_is_mod1_and_variants_touch_only_the_contact_end() {
    let b = bar(9, RightEnd::Clamped);
    assert_eq!(b.mass(BarMass::Mod), b.mass(BarMass::Mod1));
    let h = b.h();
    let std = b.mass(BarMass::Std);
    for v in [BarMass::Mod, BarMass::Mod3, BarMass::Transfer, BarMass::Singular] {
        let mm = b.mass(v);
        assert_eq!(mm.get(0, 0), 0.0, "{v}");
        assert_eq!(mm.get(0, 1), 0.0, "{v}");
        for i in 3..9 {
            assert_eq!(mm.get(i, i), std.get(i, i), "{v} row {i}");
            assert_eq!(mm.get(i, i - 1), std.get(i, i - 1), "{v} row {i}");
        }
    }
    assert!((b.mass(BarMass::Mod).get(1, 1) - h / 3.0).abs() < 1e-15);
    // mod3: element 1 has density 2, so node 1 gets 2·h/3 and node 2 gets 2·h/3 + h/3.
    assert!((b.mass(BarMass::Mod3).get(1, 1) - 2.0 * h / 3.0).abs() < 1e-15);
    assert!((b.mass(BarMass::Mod3).get(2, 2) - h).abs() < 1e-15);
    assert!((b.mass(BarMass::Mod3).get(1, 2) - 2.0 * h / 6.0).abs() < 1e-15);
    assert!((b.mass(BarMass::Transfer).get(1, 1) - 7.0 * h / 6.0).abs() < 1e-15);
    assert!((b.mass(BarMass::Singular).get(1, 1) - 7.0 * h / 12.0).abs() < 1e-15);
}

#[test]
fn stiffness_annihilates_constants_on_free_bar() {
    let b = Bar::new(2.5, 17, 1.7, RightEnd::Free).unwrap();
    let k = b.stiffness();
    let ones = vec![1.0; b.dofs()];
    let mut y = vec![0.0; b.dofs()];
    k.mul_vec(&ones, &mut y);
    let scale = k.get(0, 0);
    assert!(y.iter().all(|v| v.abs() <= 1e-14 * scale), "{y:?}");
    // and its energy of a linear function is c² L (slope 1): ∫ c² dx.
    let x: Vec<f64> = (0..=b.elements).map(|i| b.node(i)).collect();
    assert!((k.quad_form(&x) - 1.7 * 1.7 * 2.5).abs() < 1e-12);
}

#[test]
fn matrices_are_symmetric_and_positive_definite_on_free_dofs() {
    for end in [RightEnd::Clamped, RightEnd::Free] {
        let b = bar(12, end);
        let k = b.stiffness();
        for v in BarMass::ALL {
            let mm = b.mass(v);
            let dm = dense(&mm);
            assert_eq!(dm, dm.transpose().to_owned(), "{v}");
            // M is positive definite on the dofs that carry mass.
            let start = usize::from(v.massless_contact_node());
            let eig = dense(&mm.trailing(start)).self_adjoint_eigenvalues(Side::Lower).unwrap();
            assert!(eig[0] > 0.0, "{v} {end:?}: min eigenvalue {}", eig[0]);
            assert!(mm.trailing(start).factor().is_ok());
        }
        let eig = dense(&k).self_adjoint_eigenvalues(Side::Lower).unwrap();
        match end {
            RightEnd::Clamped => assert!(eig[0] > 0.0),
            // Free-free: exactly one zero eigenvalue (rigid motion), then positive.
            RightEnd::Free => assert!(eig[0].abs() < 1e-12 && eig[1] > 1e-3),
        }
    }
}

#[test]
fn load_vector_is_exact_for_quadratics() {
    let b = Bar::new(2.0, 8, 1.0, RightEnd::Free).unwrap();
    let f = b.load(|x| 3.0 * x * x - x + 0.5);
    // Sum of F_i = ∫ f over [0, 2] = 8 - 2 + 1 = 7; Σ F_i x_i = ∫ f x = 12 - 8/3 + 1.
    let s: f64 = f.iter().sum();
    let sx: f64 = f.iter().enumerate().map(|(i, v)| v * b.node(i)).sum();
    assert!((s - 7.0).abs() < 1e-13);
    assert!((sx - (12.0 - 8.0 / 3.0 + 1.0)).abs() < 1e-13);
    // Clamped: same entries without the last node.
    let bc = Bar::new(2.0, 8, 1.0, RightEnd::Clamped).unwrap();
    assert_eq!(bc.load(|x| 3.0 * x * x - x + 0.5), f[..8].to_vec());
}

#[test]
fn invalid_bars_are_typed_errors() {
    assert!(matches!(Bar::new(1.0, 1, 1.0, RightEnd::Clamped), Err(FemError::Invalid { field: "m", .. })));
    assert!(matches!(Bar::new(0.0, 4, 1.0, RightEnd::Clamped), Err(FemError::Invalid { field: "length", .. })));
    assert!(matches!(Bar::new(1.0, 4, f64::NAN, RightEnd::Clamped), Err(FemError::Invalid { field: "wave_speed", .. })));
    assert!(matches!("heavy".parse::<BarMass>(), Err(FemError::UnknownMass(_))));
    for v in BarMass::ALL {
        assert_eq!(v.name().parse::<BarMass>().unwrap(), v);
    }
    let mut not_pd = SymBand::zeros(3, 1);
    not_pd.set(0, 0, 1.0);
    not_pd.set(1, 1, -1.0);
    not_pd.set(2, 2, 1.0);
    assert!(matches!(not_pd.factor(), Err(FemError::NotPositiveDefinite { pivot: 1, .. })));
}

fn spd_band() -> impl Strategy<Value = SymBand> {
    (1usize..40, 0usize..5).prop_flat_map(|(n, p)| {
        let p = p.min(n.saturating_sub(1));
        proptest::collection::vec(-1.0f64..1.0, n * (p + 1)).prop_map(move |vals| {
            let mut a = SymBand::zeros(n, p);
            for i in 0..n {
                for k in 1..=p.min(i) {
                    a.set(i, i - k, vals[i * (p + 1) + k]);
                }
            }
            // Diagonal dominance makes it SPD.
            for i in 0..n {
                let mut row = 0.0;
                for j in i.saturating_sub(p)..(i + p + 1).min(n) {
                    if j != i {
                        row += a.get(i, j).abs();
                    }
                }
                a.set(i, i, row + 0.1 + vals[i * (p + 1)].abs());
            }
            a
        })
    })
}

proptest! {
    #[test]
    fn banded_ldlt_matches_dense_oracle(a in spd_band(), seed in 0u64..1000) {
        let n = a.n();
        let b: Vec<f64> = (0..n).map(|i| ((i as f64 + 1.0) * (seed as f64 + 0.5)).sin()).collect();
        let mut x = b.clone();
        a.factor().unwrap().solve_in_place(&mut x);
        let llt = dense(&a).llt(Side::Lower).unwrap();
        let want = llt.solve(Mat::from_fn(n, 1, |i, _| b[i]));
        let scale = b.iter().fold(0.0f64, |s, v| s.max(v.abs())) / 0.1;
        for i in 0..n {
            prop_assert!((x[i] - want[(i, 0)]).abs() <= 1e-12 * scale.max(1.0), "i={} {} vs {}", i, x[i], want[(i, 0)]);
        }
        // mul_vec, quad_form and bilinear agree with the dense product.
        let mut y = vec![0.0; n];
        a.mul_vec(&b, &mut y);
        let da = dense(&a);
        for i in 0..n {
            let yi: f64 = (0..n).map(|j| da[(i, j)] * b[j]).sum();
            prop_assert!((y[i] - yi).abs() <= 1e-13 * (1.0 + yi.abs()) * n as f64);
        }
        let q: f64 = b.iter().zip(&y).map(|(u, v)| u * v).sum();
        prop_assert!((a.quad_form(&b) - q).abs() <= 1e-12 * (1.0 + q.abs()));
        prop_assert!((a.bilinear(&b, &b) - q).abs() <= 1e-12 * (1.0 + q.abs()));
    }
}
