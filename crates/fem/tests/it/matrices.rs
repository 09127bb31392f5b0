//! Tests of the P1 bar matrices and the banded factorisation.
//!
//! Matrices are compared entry by entry with dense matrices assembled by
//! hand from docs/theory.md §2.1; eigenvalues with a dense faer solve and,
//! for the std and lumped masses, with the closed-form spectrum.
//!
//! Tolerances: entries are sums of at most a few terms of size h, so exact
//! identities are checked to 1e-13 relative; factor/solve residuals against a
//! dense faer oracle to 1e-12 relative (condition numbers here are < 1e4);
//! κ_h to 1e-11 (the iteration stops at a relative change of 1e-15, and the
//! dense solve carries a few ulps of ‖C‖); the smallest eigenvalue, of size
//! c²/L² against a matrix norm c²/h², to 1e-9 relative.

use crate::common;

use common::{assert_matrix_eq, close, dense, generalized_eigenvalues, trailing};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use proptest::prelude::*;
use signorini_fem::{max_generalized_eigenvalue, max_generalized_eigenvalue_auto, Bar, BarMass, FemError, RightEnd, SymBand};
use std::f64::consts::PI;

fn bar(m: usize, right_end: RightEnd) -> Bar {
    Bar::new(1.0, m, 1.0, right_end).unwrap()
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

/// Mass entry `(i, j)` on all `m + 1` nodes, by hand from docs/theory.md
/// §2.1.2: element `e` (on `[eh, (e+1)h]`, density weight `w_e`) adds
/// `w_e h/6 [2 1; 1 2]` (consistent) or `w_e h/2 [1 0; 0 1]` (lumped) to
/// nodes `e, e+1`; `transfer` then adds `M00 + M01` to `M11` and `singular`
/// sets `M11 = 7h/12`, both zeroing row and column 0.
fn hand_mass(variant: BarMass, m: usize, h: f64, i: usize, j: usize) -> f64 {
    let mf = m as f64;
    let w = |e: isize| -> f64 {
        if e < 0 || e >= m as isize {
            return 0.0; // no element there
        }
        match (variant, e) {
            (BarMass::Mod | BarMass::Mod1 | BarMass::Mod2 | BarMass::Mod3, 0) => 0.0,
            (BarMass::Mod2, _) => mf / (mf - 1.0),
            (BarMass::Mod3, 1) => 2.0,
            _ => 1.0,
        }
    };
    let (lo, hi) = (i.min(j), i.max(j));
    if matches!(variant, BarMass::Transfer | BarMass::Singular) {
        if lo == 0 {
            return 0.0;
        }
        if (i, j) == (1, 1) {
            // Consistent M11 = 2h/3 (m >= 2: node 1 has two elements, or one if m = 1).
            let m11 = (w(0) + w(1)) * h / 3.0;
            return if variant == BarMass::Transfer { m11 + h / 3.0 + h / 6.0 } else { 7.0 * h / 12.0 };
        }
    }
    let lumped = variant == BarMass::Lumped;
    match hi - lo {
        0 => (w(i as isize - 1) + w(i as isize)) * h * if lumped { 0.5 } else { 1.0 / 3.0 },
        1 if !lumped => w(lo as isize) * h / 6.0,
        _ => 0.0,
    }
}

/// Stiffness entry `(i, j)` on all nodes: `c²/h [1 -1; -1 1]` per element.
fn hand_stiffness(m: usize, h: f64, c: f64, i: usize, j: usize) -> f64 {
    let k = c * c / h;
    match i.abs_diff(j) {
        0 => k * f64::from(u8::from(i > 0) + u8::from(i < m)),
        1 => -k,
        _ => 0.0,
    }
}

/// The hand-built dense matrix on the unknowns (node `m` dropped when clamped).
fn hand_dense(b: &Bar, entry: impl Fn(usize, usize) -> f64) -> Mat<f64> {
    Mat::from_fn(b.dofs(), b.dofs(), entry)
}

fn test_bars() -> Vec<Bar> {
    let mut out = Vec::new();
    for end in [RightEnd::Clamped, RightEnd::Free] {
        for m in [2usize, 3, 4, 9, 25] {
            // L and c different from 1 so that a wrong power of h or c shows.
            out.push(Bar::new(2.5, m, 1.7, end).unwrap());
        }
    }
    out
}

#[test]
fn bar_matrices_equal_hand_assembled_dense_matrices() {
    for b in test_bars() {
        let (m, h, c) = (b.elements, b.h(), b.wave_speed);
        let k = hand_dense(&b, |i, j| hand_stiffness(m, h, c, i, j));
        assert_matrix_eq(&b.stiffness(), &k, 1e-14, &format!("K, m = {m}, {:?}", b.right_end));
        for v in BarMass::ALL {
            let mm = hand_dense(&b, |i, j| hand_mass(v, m, h, i, j));
            assert_matrix_eq(&b.mass(v), &mm, 1e-14, &format!("M {v}, m = {m}, {:?}", b.right_end));
        }
    }
    // A few entries written out, for the reader (m = 4, L = 2.5, h = 0.625).
    let b = Bar::new(2.5, 4, 1.7, RightEnd::Clamped).unwrap();
    let h = 0.625;
    assert!(close(b.mass(BarMass::Std).get(0, 0), h / 3.0, 1e-15));
    assert!(close(b.mass(BarMass::Lumped).get(2, 2), h, 1e-15));
    assert!(close(b.mass(BarMass::Mod2).get(1, 1), 4.0 / 3.0 * h / 3.0, 1e-15));
    assert!(close(b.mass(BarMass::Transfer).get(1, 1), 7.0 * h / 6.0, 1e-15));
    assert!(close(b.stiffness().get(3, 3), 2.0 * 1.7 * 1.7 / h, 1e-15));
}

/// Closed-form spectrum of the std and lumped P1 bar, free at `x = 0`
/// (the contact node is an unknown) and clamped or free at `x = L`: with
/// `u_i = cos(iθ)` every row holds (the row of a free end is half an
/// interior row), and the far end fixes `θ`: `cos(mθ) = 0` when clamped,
/// `θ_k = (2k-1)π/(2m)`, `k = 1..m`; `sin(mθ) = 0` when free,
/// `θ_k = kπ/m`, `k = 0..m`. Then
/// lumped: `κ = (4c²/h²) sin²(θ/2)`; consistent: `κ = (6c²/h²)(1 - cos θ)/(2 + cos θ)`.
fn closed_form_spectrum(b: &Bar, variant: BarMass) -> Vec<f64> {
    let (m, h, c) = (b.elements as f64, b.h(), b.wave_speed);
    let thetas: Vec<f64> = match b.right_end {
        RightEnd::Clamped => (1..=b.elements).map(|k| (2.0 * k as f64 - 1.0) * PI / (2.0 * m)).collect(),
        RightEnd::Free => (0..=b.elements).map(|k| k as f64 * PI / m).collect(),
    };
    let c2h2 = c * c / (h * h);
    thetas
        .into_iter()
        .map(|th| match variant {
            BarMass::Lumped => 4.0 * c2h2 * (0.5 * th).sin().powi(2),
            BarMass::Std => 6.0 * c2h2 * (1.0 - th.cos()) / (2.0 + th.cos()),
            _ => unreachable!("no closed form for {variant}"),
        })
        .collect()
}

/// The pencil whose `κ_h` the schemes use: `(K, M)` for a massive contact
/// node, the reduced `(K*, M*)` (node 0 removed) for a massless one.
fn pencils(b: &Bar, v: BarMass) -> (SymBand, SymBand, Mat<f64>, Mat<f64>) {
    let (m, h, c) = (b.elements, b.h(), b.wave_speed);
    let kd = hand_dense(b, |i, j| hand_stiffness(m, h, c, i, j));
    let md = hand_dense(b, |i, j| hand_mass(v, m, h, i, j));
    let start = usize::from(v.massless_contact_node());
    (b.stiffness().trailing(start), b.mass(v).trailing(start), trailing(&kd, start), trailing(&md, start))
}

#[test]
fn kappa_h_matches_dense_faer_and_closed_forms() {
    for b in test_bars() {
        for v in BarMass::ALL {
            let what = format!("{v}, m = {}, {:?}", b.elements, b.right_end);
            let (k, mm, kd, md) = pencils(&b, v);
            let dense = generalized_eigenvalues(&kd, &md);
            let (lo, hi) = (dense[0], *dense.last().unwrap());
            let auto = max_generalized_eigenvalue_auto(&k, &mm).unwrap();
            assert!(close(auto, hi, 1e-11), "{what}: κ_h = {auto}, dense faer {hi}");
            let (shifted, _) = max_generalized_eigenvalue(&k, &mm, 1.001 * hi, 1_000_000).unwrap();
            assert!(close(shifted, hi, 1e-11), "{what}: κ_h (shift-invert) = {shifted}, dense faer {hi}");
            // A shift below κ_h must be refused (σM - K not positive definite).
            assert!(max_generalized_eigenvalue(&k, &mm, 0.999 * hi, 10).is_err(), "{what}");
            if matches!(v, BarMass::Std | BarMass::Lumped) {
                let want = closed_form_spectrum(&b, v);
                assert_eq!(want.len(), dense.len(), "{what}");
                let top = *want.last().unwrap();
                assert!(close(hi, top, 1e-12), "{what}: κ_h dense {hi}, closed form {top}");
                assert!(close(auto, top, 1e-11), "{what}: κ_h {auto}, closed form {top}");
                for (i, (d, w)) in dense.iter().zip(&want).enumerate() {
                    assert!((d - w).abs() <= 1e-12 * top, "{what}: eigenvalue {i}: dense {d}, closed form {w}");
                }
                match b.right_end {
                    // Smallest: θ_1 = π/(2m), positive.
                    RightEnd::Clamped => assert!(close(lo, want[0], 1e-9) && lo > 0.0, "{what}: smallest {lo} vs {}", want[0]),
                    // Free-free: the rigid motion (0), then θ_1 = π/m.
                    RightEnd::Free => {
                        assert!(lo.abs() <= 1e-12 * top, "{what}: smallest {lo}");
                        assert!(close(dense[1], want[1], 1e-9), "{what}: second {} vs {}", dense[1], want[1]);
                    }
                }
            } else {
                // The massive part is positive definite: smallest > 0.
                assert!(lo > 0.0, "{what}: smallest {lo}");
            }
        }
    }
    // The lumped free-free bar's κ_h is exactly 4c²/h² (θ = π: nodes alternate).
    let b = Bar::new(2.5, 9, 1.7, RightEnd::Free).unwrap();
    let kappa = max_generalized_eigenvalue_auto(&b.stiffness(), &b.mass(BarMass::Lumped)).unwrap();
    assert!(close(kappa, 4.0 * 1.7 * 1.7 / (b.h() * b.h()), 1e-12), "{kappa}");
}

#[test]
fn massless_variants_make_the_full_mass_singular() {
    for b in test_bars() {
        for v in BarMass::ALL.into_iter().filter(|v| v.massless_contact_node()) {
            assert!(matches!(b.mass(v).factor(), Err(FemError::NotPositiveDefinite { pivot: 0, .. })), "{v}");
            assert!(b.mass(v).trailing(1).factor().is_ok(), "{v}");
        }
        for v in [BarMass::Std, BarMass::Lumped] {
            assert!(b.mass(v).factor().is_ok(), "{v}");
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

proptest! {
    /// `BandLdlt::backward_in_place` after a forward sweep written here
    /// from `band_factors` (`y = L⁻¹ b`, nearest terms first) solves
    /// `A x = b` (the dense faer oracle, 1e-12 relative) for every
    /// half-bandwidth 0–4; for p = 1 that forward sweep is the solve's own,
    /// so the result is `solve_in_place`'s bit for bit (p = 3, the beam's,
    /// is compared bit for bit in signorini-schemes' fused-step test).
    #[test]
    fn backward_half_after_a_forward_sweep_solves(a in spd_band(), seed in 0u64..1000) {
        let (n, p) = (a.n(), a.half_bandwidth());
        let b: Vec<f64> = (0..n).map(|i| ((i as f64 + 1.0) * (seed as f64 + 0.5)).sin()).collect();
        let f = a.factor().unwrap();
        let (l, _, _) = f.band_factors();
        let mut x = b.clone();
        for i in 0..n {
            let mut s = x[i];
            for k in 1..=p.min(i) {
                s -= l[i * p + k - 1] * x[i - k];
            }
            x[i] = s;
        }
        f.backward_in_place(&mut x);
        let want = dense(&a).llt(Side::Lower).unwrap().solve(Mat::from_fn(n, 1, |i, _| b[i]));
        let scale = b.iter().fold(0.0f64, |s, v| s.max(v.abs())) / 0.1;
        for i in 0..n {
            prop_assert!((x[i] - want[(i, 0)]).abs() <= 1e-12 * scale.max(1.0), "p={} i={} {} vs {}", p, i, x[i], want[(i, 0)]);
        }
        if p == 1 {
            let mut y = b.clone();
            f.solve_in_place(&mut y);
            prop_assert!(x.iter().zip(&y).all(|(u, v)| u.to_bits() == v.to_bits()), "p = 1: not solve_in_place's bits");
        }
    }
}

/// `A x` of half-bandwidth 3, row by row in the order the product keeps
/// (written out here from the entries): interior rows
/// `(a_ii x_i + a_i,i−1 x_i−1 + a_i,i−2 x_i−2 + a_i,i−3 x_i−3) + (a_i+1,i x_i+1 + a_i+2,i x_i+2 + a_i+3,i x_i+3)`,
/// the three first and last rows the diagonal then each neighbour left
/// and right.
fn band3_product_by_rows(a: &SymBand, x: &[f64]) -> Vec<f64> {
    let n = a.n();
    (0..n)
        .map(|i| {
            if i >= 3 && i + 3 < n {
                (a.get(i, i) * x[i] + a.get(i, i - 1) * x[i - 1] + a.get(i, i - 2) * x[i - 2] + a.get(i, i - 3) * x[i - 3])
                    + (a.get(i + 1, i) * x[i + 1] + a.get(i + 2, i) * x[i + 2] + a.get(i + 3, i) * x[i + 3])
            } else {
                let mut s = a.get(i, i) * x[i];
                for k in 1..=3 {
                    if i >= k {
                        s += a.get(i, i - k) * x[i - k];
                    }
                    if i + k < n {
                        s += a.get(i + k, i) * x[i + k];
                    }
                }
                s
            }
        })
        .collect()
}

proptest! {
    /// The beam's banded product (half-bandwidth 3, by diagonals,
    /// vectorised) gives the row-by-row sums' bits, also after the matrix
    /// is changed between products (`set`, `add`, `copy_from`,
    /// `lin_comb_into`: the diagonals are made again).
    #[test]
    fn band3_product_is_the_row_sums_bit_for_bit(n in 7usize..64, seed in any::<u64>()) {
        let mut rng = seed;
        let mut next = move || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut a = SymBand::zeros(n, 3);
        for i in 0..n {
            for j in i.saturating_sub(3)..=i {
                a.set(i, j, next() * 10f64.powi((next() * 6.0) as i32));
            }
        }
        let x: Vec<f64> = (0..n).map(|_| next() * 1e3).collect();
        let mut y = vec![0.0; n];
        a.mul_vec(&x, &mut y);
        prop_assert_eq!(y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), band3_product_by_rows(&a, &x).iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        // Changed after a product: the next product sees the change.
        let (i, j) = (n / 2, n / 2 - 2);
        a.set(i, j, 0.5);
        a.mul_vec(&x, &mut y);
        prop_assert_eq!(y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), band3_product_by_rows(&a, &x).iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        a.add(n - 1, n - 4, 0.25);
        a.mul_vec(&x, &mut y);
        prop_assert_eq!(y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), band3_product_by_rows(&a, &x).iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        let mut b = SymBand::zeros(n, 3);
        b.mul_vec(&x, &mut y);
        b.copy_from(&a);
        b.mul_vec(&x, &mut y);
        prop_assert_eq!(y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), band3_product_by_rows(&a, &x).iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        a.lin_comb_into(2.0, &a.clone(), -0.5, &mut b);
        b.mul_vec(&x, &mut y);
        prop_assert_eq!(y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), band3_product_by_rows(&b, &x).iter().map(|v| v.to_bits()).collect::<Vec<_>>());
    }
}
