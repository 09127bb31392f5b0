//! Tests of the Pk bar (docs/theory.md §2.1.4): degree 1 through the Pk code
//! path against a verbatim copy of the P1 code it replaced (bit for bit), the
//! P2/P3 element matrices against integrals of the Lagrange basis done here
//! independently (monomial coefficients from a Vandermonde solve, integrated
//! exactly term by term), and the degree and mass refusals.
//!
//! Tolerances: the independent integrals carry the rounding of a 4×4
//! Vandermonde solve (condition < 1e3), so 1e-12 relative.

use signorini_fem::{Bar, BarMass, FemError, RightEnd, SymBand};

/// The P1 code before the Pk generalisation, verbatim (the oracle of the bit-for-bit test).
mod old {
    use signorini_fem::{BarMass, SymBand};

    pub fn mass_all_nodes(m: usize, h: f64, variant: BarMass) -> SymBand {
        let weight = |j: usize| -> f64 {
            match variant {
                BarMass::Mod | BarMass::Mod1 if j == 0 => 0.0,
                BarMass::Mod2 if j == 0 => 0.0,
                BarMass::Mod2 => m as f64 / (m as f64 - 1.0),
                BarMass::Mod3 if j == 0 => 0.0,
                BarMass::Mod3 if j == 1 => 2.0,
                _ => 1.0,
            }
        };
        let mut mm = SymBand::zeros(m + 1, 1);
        for j in 0..m {
            let w = weight(j) * h;
            if variant == BarMass::Lumped {
                mm.add(j, j, w / 2.0);
                mm.add(j + 1, j + 1, w / 2.0);
            } else {
                mm.add(j, j, w / 3.0);
                mm.add(j + 1, j + 1, w / 3.0);
                mm.add(j, j + 1, w / 6.0);
            }
        }
        match variant {
            BarMass::Transfer => {
                let moved = mm.get(0, 0) + mm.get(0, 1);
                mm.add(1, 1, moved);
                mm.zero_row_col(0);
            }
            BarMass::Singular => {
                mm.zero_row_col(0);
                mm.set(1, 1, 7.0 * h / 12.0);
            }
            _ => {}
        }
        mm
    }

    pub fn stiffness_all_nodes(m: usize, h: f64, c: f64) -> SymBand {
        let k = c * c / h;
        let mut kk = SymBand::zeros(m + 1, 1);
        for j in 0..m {
            kk.add(j, j, k);
            kk.add(j + 1, j + 1, k);
            kk.add(j, j + 1, -k);
        }
        kk
    }

    pub fn load(m: usize, h: f64, node: impl Fn(usize) -> f64, dofs: usize, f: impl Fn(f64) -> f64) -> Vec<f64> {
        const G: [(f64, f64); 3] = [(-0.774_596_669_241_483_4, 5.0 / 9.0), (0.0, 8.0 / 9.0), (0.774_596_669_241_483_4, 5.0 / 9.0)];
        let mut out = vec![0.0; m + 1];
        for j in 0..m {
            let a = node(j);
            for (xi, w) in G {
                let s = 0.5 * (xi + 1.0);
                let fx = f(a + s * h) * w * 0.5 * h;
                out[j] += fx * (1.0 - s);
                out[j + 1] += fx * s;
            }
        }
        out.truncate(dofs);
        out
    }
}

fn assert_bits(a: &SymBand, b: &SymBand, what: &str) {
    assert_eq!((a.n(), a.half_bandwidth()), (b.n(), b.half_bandwidth()), "{what}: shape");
    for i in 0..a.n() {
        for j in i.saturating_sub(a.half_bandwidth())..=i {
            assert!(a.get(i, j).to_bits() == b.get(i, j).to_bits(), "{what}: ({i},{j}) {} != {}", a.get(i, j), b.get(i, j));
        }
    }
}

#[test]
fn p1_through_the_pk_path_is_bit_identical() {
    for (length, c) in [(1.0, 1.0), (0.7, 1.3), (3.0, 0.37)] {
        for m in [2, 3, 7, 10, 33, 640] {
            let bar = Bar::new(length, m, c, RightEnd::Free).unwrap().with_degree(1).unwrap();
            let h = bar.h();
            for v in BarMass::ALL {
                assert_bits(&bar.mass_all_nodes(v), &old::mass_all_nodes(m, h, v), &format!("mass {v} m={m} L={length}"));
            }
            assert_bits(&bar.stiffness_all_nodes(), &old::stiffness_all_nodes(m, h, c), &format!("stiffness m={m}"));
            for end in [RightEnd::Free, RightEnd::Clamped] {
                let b = Bar { right_end: end, ..bar };
                let f = |x: f64| 0.3 - x * x + (2.0 * x).sin();
                let want = old::load(m, h, |i| length * i as f64 / m as f64, b.dofs(), f);
                let got = b.load(f);
                assert!(got.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()) && got.len() == want.len(), "load m={m} {end:?}");
                assert_eq!(b.dofs(), if end == RightEnd::Free { m + 1 } else { m });
                assert!((0..=m).all(|i| b.node(i).to_bits() == (length * i as f64 / m as f64).to_bits()));
            }
        }
    }
}

/// Coefficients `c_p` of the Lagrange polynomial `φ_i(s) = Σ c_p s^p` of degree `k`
/// on the nodes `r/k`, by Gaussian elimination on the Vandermonde system.
fn lagrange_coeffs(k: usize, i: usize) -> Vec<f64> {
    let n = k + 1;
    let mut a: Vec<Vec<f64>> = (0..n).map(|r| (0..n).map(|p| (r as f64 / k as f64).powi(p as i32)).collect()).collect();
    let mut b: Vec<f64> = (0..n).map(|r| if r == i { 1.0 } else { 0.0 }).collect();
    for col in 0..n {
        let piv = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs())).unwrap();
        a.swap(col, piv);
        b.swap(col, piv);
        for r in col + 1..n {
            let f = a[r][col] / a[col][col];
            for c in col..n {
                a[r][c] -= f * a[col][c];
            }
            b[r] -= f * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        x[r] = (b[r] - (r + 1..n).map(|c| a[r][c] * x[c]).sum::<f64>()) / a[r][r];
    }
    x
}

fn deriv(c: &[f64]) -> Vec<f64> {
    c.iter().enumerate().skip(1).map(|(p, v)| p as f64 * v).collect()
}

/// `∫_0^1 p q ds` for monomial coefficient vectors, exactly term by term.
fn int_product(p: &[f64], q: &[f64]) -> f64 {
    let mut s = 0.0;
    for (a, x) in p.iter().enumerate() {
        for (b, y) in q.iter().enumerate() {
            s += x * y / (a + b + 1) as f64;
        }
    }
    s
}

#[test]
fn p2_p3_matrices_are_the_integrals_of_the_lagrange_basis() {
    let (length, c, m) = (1.7, 1.3, 5);
    for k in [2, 3] {
        let bar = Bar::new(length, m, c, RightEnd::Free).unwrap().with_degree(k).unwrap();
        let h = bar.h();
        let basis: Vec<Vec<f64>> = (0..=k).map(|i| lagrange_coeffs(k, i)).collect();
        let n = k * m + 1;
        let (mut md, mut kd, mut ld) = (vec![vec![0.0; n]; n], vec![vec![0.0; n]; n], vec![0.0; n]);
        for j in 0..m {
            for a in 0..=k {
                ld[k * j + a] += h * int_product(&basis[a], &[1.0]);
                for b in 0..=k {
                    md[k * j + a][k * j + b] += h * int_product(&basis[a], &basis[b]);
                    kd[k * j + a][k * j + b] += c * c / h * int_product(&deriv(&basis[a]), &deriv(&basis[b]));
                }
            }
        }
        let (mm, kk, lm) = (bar.mass_all_nodes(BarMass::Std), bar.stiffness_all_nodes(), bar.mass_all_nodes(BarMass::Lumped));
        assert_eq!((mm.n(), mm.half_bandwidth(), kk.half_bandwidth()), (n, k, k));
        for i in 0..n {
            for j in 0..n {
                assert!((mm.get(i, j) - md[i][j]).abs() <= 1e-12 * h, "P{k} M({i},{j}) = {} != {}", mm.get(i, j), md[i][j]);
                assert!((kk.get(i, j) - kd[i][j]).abs() <= 1e-12 * c * c / h, "P{k} K({i},{j}) = {} != {}", kk.get(i, j), kd[i][j]);
                // Lumped: the row sums ∫ φ_i, on the diagonal, all positive.
                let want = if i == j { ld[i] } else { 0.0 };
                assert!((lm.get(i, j) - want).abs() <= 1e-12 * h, "P{k} lumped ({i},{j})");
            }
            assert!(lm.get(i, i) > 0.0);
        }
        // K annihilates constants (and linears only through the boundary rows);
        // the mass sums to the bar's length.
        let ones = vec![1.0; n];
        let mut y = vec![0.0; n];
        kk.mul_vec(&ones, &mut y);
        assert!(y.iter().all(|v| v.abs() <= 1e-12 * c * c / h), "P{k}: K·1 = {y:?}");
        assert!((mm.quad_form(&ones) - length).abs() <= 1e-12 * length);
        assert!((lm.quad_form(&ones) - length).abs() <= 1e-12 * length);
        // Loads: ∫ x φ_i (5-point Gauss is exact for x · φ_i).
        let lx = bar.load(|x| x);
        let mut want = vec![0.0; n];
        for j in 0..m {
            let x0 = j as f64 * h;
            for a in 0..=k {
                // x = x0 + h s
                want[k * j + a] += h * (x0 * int_product(&basis[a], &[1.0]) + h * int_product(&basis[a], &[0.0, 1.0]));
            }
        }
        assert!(lx.iter().zip(&want).all(|(g, w)| (g - w).abs() <= 1e-12), "P{k} load {lx:?} != {want:?}");
        // Nodes by position.
        assert!((0..n).all(|i| (bar.node(i) - i as f64 * h / k as f64).abs() <= 1e-15));
    }
}

#[test]
fn pk_massless_contact_node_keeps_every_other_node_massive() {
    for k in [2, 3] {
        let bar = Bar::new(1.0, 6, 1.0, RightEnd::Clamped).unwrap().with_degree(k).unwrap();
        let h = bar.h();
        let std = bar.mass(BarMass::Std);
        let md = bar.mass(BarMass::Mod);
        assert_bits(&md, &bar.mass(BarMass::Mod1), "mod == mod1");
        // Row and column 0 empty.
        assert!((0..=k).all(|j| md.get(0, j) == 0.0));
        // Element 0: only its interior block (the consistent mass of the
        // interior nodes' basis functions), independently ∫ φ_a φ_b h.
        let basis: Vec<Vec<f64>> = (0..=k).map(|i| lagrange_coeffs(k, i)).collect();
        for a in 1..=k {
            for b in 1..=k {
                let elem0 = if a < k && b < k { h * int_product(&basis[a], &basis[b]) } else { 0.0 };
                let elem1 = if a == k && b == k { h * int_product(&basis[0], &basis[0]) } else { 0.0 };
                assert!((md.get(a, b) - elem0 - elem1).abs() <= 1e-12 * h, "P{k} mod ({a},{b}) = {}", md.get(a, b));
            }
        }
        // Beyond element 0, identical to std.
        for i in k + 1..md.n() {
            for j in i - k..=i {
                assert_eq!(md.get(i, j), std.get(i, j));
            }
        }
        // Every node but the contact node massive: M restricted to 1.. is positive definite.
        assert!(md.trailing(1).factor().is_ok(), "P{k} mod: not positive definite off node 0");
    }
}

#[test]
fn bad_degree_and_mass_are_refused_by_name() {
    let bar = Bar::new(1.0, 4, 1.0, RightEnd::Free).unwrap();
    for k in [0, 4, 7] {
        match bar.with_degree(k) {
            Err(FemError::Invalid { field: "degree", .. }) => {}
            other => panic!("degree {k}: {other:?}"),
        }
    }
    for k in [2, 3] {
        let b = bar.with_degree(k).unwrap();
        for v in BarMass::ALL {
            let ok = matches!(v, BarMass::Std | BarMass::Lumped | BarMass::Mod | BarMass::Mod1);
            assert_eq!(b.check_mass(v).is_ok(), ok, "P{k} {v}");
            if !ok {
                assert_eq!(b.check_mass(v), Err(FemError::MassForDegree { mass: v.name(), degree: k }));
                assert!(b.mass_with_contacts(v, &[0]).is_err());
            }
        }
        assert!(matches!(b.mass_with_contacts(BarMass::Mod, &[0, 4 * k]), Err(FemError::MassAtContacts { .. })));
        assert!(b.mass_with_contacts(BarMass::Std, &[0, 4 * k]).is_ok());
        assert!(b.mass_with_contacts(BarMass::Mod, &[0]).is_ok());
    }
    assert!(bar.with_degree(1).unwrap().check_mass(BarMass::Singular).is_ok());
}
