//! The multi-contact solve against brute force: on random banded SPD
//! matrices (diagonally dominant, and Gram matrices `BᵀB` whose Delassus
//! matrices are not M-matrices), k <= 8 constrained dofs with random one- or
//! two-sided (or equal) bounds, every status assignment (free, lower,
//! upper: 3^k of them) is solved by Gaussian elimination written here, and
//! the one that satisfies the KKT conditions is the exact solution; the
//! crate's `x` must equal it, its multipliers must satisfy `A x = b + Σ μ e_c`
//! with complementarity, all to round-off.

use proptest::prelude::*;
use signorini_contact::{Active, ContactError, MultiProjection};

/// Dense `n × n` solve by Gaussian elimination with partial pivoting.
fn solve(a: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut m: Vec<Vec<f64>> = a.iter().zip(b).map(|(r, &bi)| r.iter().copied().chain([bi]).collect()).collect();
    for col in 0..n {
        let p = (col..n).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs())).unwrap();
        m.swap(col, p);
        for r in col + 1..n {
            let f = m[r][col] / m[col][col];
            for c in col..=n {
                m[r][c] -= f * m[col][c];
            }
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|c| m[r][c] * x[c]).sum();
        x[r] = (m[r][n] - s) / m[r][r];
    }
    x
}

/// The influence column `A⁻¹ e_c`.
fn column(a: &[Vec<f64>], c: usize) -> Vec<f64> {
    solve(a, &(0..a.len()).map(|i| f64::from(u8::from(i == c))).collect::<Vec<_>>())
}

fn matvec(a: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
    a.iter().map(|r| r.iter().zip(x).map(|(p, q)| p * q).sum()).collect()
}

/// A random banded SPD matrix: diagonally dominant, or `BᵀB` with `B`
/// banded upper triangular.
fn spd(n: usize, p: usize, vals: &[f64], gram: bool) -> Vec<Vec<f64>> {
    let mut it = vals.iter().cycle();
    if gram {
        let mut b = vec![vec![0.0; n]; n];
        for i in 0..n {
            b[i][i] = 2.0 + it.next().unwrap().abs(); // cond(A) below ~1e3: the 1e-11 bound is round-off
            for j in i + 1..(i + p + 1).min(n) {
                b[i][j] = *it.next().unwrap();
            }
        }
        (0..n).map(|i| (0..n).map(|j| (0..n).map(|r| b[r][i] * b[r][j]).sum()).collect()).collect()
    } else {
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in i + 1..(i + p + 1).min(n) {
                let v = *it.next().unwrap();
                a[i][j] = v;
                a[j][i] = v;
            }
        }
        for i in 0..n {
            let off: f64 = (0..n).filter(|&j| j != i).map(|j| a[i][j].abs()).sum();
            a[i][i] = off + 0.1 + it.next().unwrap().abs();
        }
        a
    }
}

/// Every status assignment (0 free, 1 at the lower bound, 2 at the upper)
/// of `lo.len()` dofs, except those holding an infinite bound: 3^k of them.
fn statuses<'a>(lo: &'a [f64], hi: &'a [f64]) -> impl Iterator<Item = Vec<usize>> + 'a {
    let k = lo.len();
    (0..3usize.pow(k as u32))
        .map(move |code| (0..k).map(|i| code / 3usize.pow(i as u32) % 3).collect::<Vec<usize>>())
        .filter(move |st| !(0..k).any(|i| (st[i] == 1 && !lo[i].is_finite()) || (st[i] == 2 && !hi[i].is_finite())))
}

/// The exact solution by enumeration: `(x, μ)`.
fn brute_force(a: &[Vec<f64>], b: &[f64], dofs: &[usize], lo: &[f64], hi: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let k = dofs.len();
    let y = solve(a, b);
    let cols: Vec<Vec<f64>> = dofs.iter().map(|&c| column(a, c)).collect();
    let d = |i: usize, j: usize| cols[j][dofs[i]];
    for st in statuses(lo, hi) {
        let s: Vec<usize> = (0..k).filter(|&i| st[i] != 0).collect();
        let mut mu = vec![0.0; k];
        if !s.is_empty() {
            let m: Vec<Vec<f64>> = s.iter().map(|&i| s.iter().map(|&j| d(i, j)).collect()).collect();
            let r: Vec<f64> = s.iter().map(|&i| if st[i] == 1 { lo[i] } else { hi[i] } - y[dofs[i]]).collect();
            for (v, &i) in solve(&m, &r).iter().zip(&s) {
                mu[i] = *v;
            }
        }
        let z: Vec<f64> = (0..k).map(|i| y[dofs[i]] + (0..k).map(|j| d(i, j) * mu[j]).sum::<f64>()).collect();
        let tol = 1e-9;
        let ok = (0..k).all(|i| match st[i] {
            0 => z[i] >= lo[i] - tol && z[i] <= hi[i] + tol,
            1 => mu[i] >= -tol,
            _ => mu[i] <= tol,
        });
        if ok {
            let mut rhs = b.to_vec();
            for (i, &c) in dofs.iter().enumerate() {
                rhs[c] += mu[i];
            }
            return (solve(a, &rhs), mu);
        }
    }
    panic!("no status satisfies the KKT conditions");
}

fn bounds_of(code: u8, a: f64, w: f64) -> (f64, f64) {
    match code % 5 {
        0 => (a, f64::INFINITY),
        1 => (f64::NEG_INFINITY, a),
        2 => (a, a + w),
        3 => (a, a), // a fixed dof
        _ => (f64::NEG_INFINITY, f64::INFINITY),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    #[test]
    fn matches_brute_force_kkt(
        n in 3usize..24, p in 1usize..4, gram in any::<bool>(),
        vals in prop::collection::vec(-1.0f64..1.0, 64),
        picks in prop::collection::vec(0usize..1000, 1..9),
        codes in prop::collection::vec((0u8..5, -1.0f64..0.5, 0.0f64..1.0), 8),
        b in prop::collection::vec(-3.0f64..3.0, 24),
        warm in any::<bool>(),
    ) {
        let a = spd(n, p, &vals, gram);
        let b = &b[..n];
        let mut dofs: Vec<usize> = picks.iter().map(|q| q % n).collect();
        dofs.sort_unstable();
        dofs.dedup();
        let k = dofs.len();
        let (lo, hi): (Vec<f64>, Vec<f64>) = codes[..k].iter().map(|&(c, x, w)| bounds_of(c, x, w)).unzip();
        let (x_ref, mu_ref) = brute_force(&a, b, &dofs, &lo, &hi);
        let cols: Vec<Vec<f64>> = dofs.iter().map(|&c| column(&a, c)).collect();
        let mut mp = MultiProjection::new(dofs.clone(), cols).unwrap();
        if warm {
            // A first solve with other data leaves statuses behind (warm start).
            let mut y0 = solve(&a, &b.iter().map(|v| -v).collect::<Vec<_>>());
            mp.project(&mut y0, &lo, &hi).unwrap();
        }
        let mut x = solve(&a, b);
        let rep = mp.project(&mut x, &lo, &hi).unwrap();
        let scale = x_ref.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let err = x.iter().zip(&x_ref).fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        prop_assert!(err <= 1e-11 * scale, "x differs by {err:e} (k = {k}, {} iterations)", rep.iterations);
        prop_assert!(rep.residual <= 1e-12 * scale, "residual {:e}", rep.residual);
        // KKT from the crate's own multipliers: A x - b = Σ μ e_c, signs, bounds.
        let mut r = matvec(&a, &x);
        for (ri, bi) in r.iter_mut().zip(b) { *ri -= bi; }
        for (i, &c) in dofs.iter().enumerate() {
            r[c] -= mp.multipliers()[i];
            let (m, s) = (mp.multipliers()[i], mp.status()[i]);
            prop_assert!((m - mu_ref[i]).abs() <= 1e-9 * (1.0 + mu_ref[i].abs()) || lo[i] == hi[i], "μ_{i} = {m}, brute force {}", mu_ref[i]);
            match s {
                Active::None => prop_assert!(m == 0.0 && x[c] >= lo[i] && x[c] <= hi[i]),
                Active::Lower => prop_assert!(x[c] == lo[i] && m >= -1e-12 * scale),
                Active::Upper => prop_assert!(x[c] == hi[i] && m <= 1e-12 * scale),
            }
        }
        let res = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        prop_assert!(res <= 1e-10 * scale * a.iter().map(|r| r.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max), "A x - b - Σ μ e_c = {res:e}");
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let a = vec![vec![2.0, -1.0, 0.0], vec![-1.0, 2.0, -1.0], vec![0.0, -1.0, 2.0]];
    let col = |c: usize| column(&a, c);
    assert_eq!(MultiProjection::new(vec![0, 0], vec![col(0), col(0)]).unwrap_err(), ContactError::DuplicateDof(0));
    assert_eq!(MultiProjection::new(vec![0, 5], vec![col(0), col(2)]).unwrap_err(), ContactError::DofOutOfRange { dof: 5, n: 3 });
    assert!(matches!(MultiProjection::new(vec![0, 2], vec![col(0)]).unwrap_err(), ContactError::Columns { .. }));
    assert!(matches!(MultiProjection::new(vec![], vec![]).unwrap_err(), ContactError::Columns { .. }));
    // Columns that are not A⁻¹ e_c of an SPD A: D = [[1, 2], [2, 1]] is indefinite.
    let bad = vec![vec![1.0, 0.0, 2.0], vec![2.0, 0.0, 1.0]];
    assert_eq!(MultiProjection::new(vec![0, 2], bad).unwrap_err(), ContactError::NotPositiveDefinite);
}

/// One dof: the same as the closed-form projection.
#[test]
fn one_dof_equals_the_closed_form() {
    let a = vec![vec![2.0, -1.0, 0.0], vec![-1.0, 2.0, -1.0], vec![0.0, -1.0, 2.0]];
    let w = solve(&a, &[1.0, 0.0, 0.0]);
    let single = signorini_contact::Projection::new(0, w.clone()).unwrap();
    let mut multi = MultiProjection::new(vec![0], vec![w]).unwrap();
    for (y0, lo, hi) in [(-0.3, 0.0, f64::INFINITY), (0.7, f64::NEG_INFINITY, 0.5), (0.2, 0.0, 1.0)] {
        let mut y1 = vec![y0, 0.1, -0.2];
        let mut y2 = y1.clone();
        let p = single.project(&mut y1, lo, hi);
        multi.project(&mut y2, &[lo], &[hi]).unwrap();
        assert_eq!(p.active, multi.status()[0]);
        assert!((p.mu - multi.multipliers()[0]).abs() <= 1e-15 * (1.0 + p.mu.abs()));
        for (u, v) in y1.iter().zip(&y2) {
            assert!((u - v).abs() <= 1e-15, "{y1:?} {y2:?}");
        }
    }
}

/// The spring law by enumeration, independent of the Delassus form: for
/// each assignment of springs (off, lower engaged, upper engaged) solve the
/// stiffened system `(A + Σ κ_i e e ᵀ) x = b + Σ κ_i bound_i e` and keep the
/// one whose engaged springs are stretched and whose others are inside.
fn brute_force_springs(a: &[Vec<f64>], b: &[f64], dofs: &[usize], lo: &[f64], hi: &[f64], kappa: &[f64]) -> Vec<f64> {
    let k = dofs.len();
    for st in statuses(lo, hi) {
        let mut m = a.to_vec();
        let mut r = b.to_vec();
        for i in (0..k).filter(|&i| st[i] != 0) {
            let bound = if st[i] == 1 { lo[i] } else { hi[i] };
            m[dofs[i]][dofs[i]] += kappa[i];
            r[dofs[i]] += kappa[i] * bound;
        }
        let x = solve(&m, &r);
        let tol = 1e-9;
        if (0..k).all(|i| {
            let xc = x[dofs[i]];
            match st[i] {
                0 => xc >= lo[i] - tol && xc <= hi[i] + tol,
                1 => xc <= lo[i] + tol,
                _ => xc >= hi[i] - tol,
            }
        }) {
            return x;
        }
    }
    panic!("no spring assignment is consistent");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    /// Compliant bounds (`with_compliance`, c = 1/κ) are the penalty law:
    /// the solve equals the brute-force spring solution, and each
    /// multiplier is the spring force `κ (lo − x)⁺ − κ (x − hi)⁺`.
    #[test]
    fn compliance_is_the_spring_law(
        n in 3usize..16, p in 1usize..4, gram in any::<bool>(),
        vals in prop::collection::vec(-1.0f64..1.0, 64),
        picks in prop::collection::vec(0usize..1000, 1..7),
        codes in prop::collection::vec((0u8..3, -1.0f64..0.5, 0.0f64..1.0, -2.0f64..4.0), 6),
        b in prop::collection::vec(-3.0f64..3.0, 16),
    ) {
        let a = spd(n, p, &vals, gram);
        let b = &b[..n];
        let mut dofs: Vec<usize> = picks.iter().map(|q| q % n).collect();
        dofs.sort_unstable();
        dofs.dedup();
        let k = dofs.len();
        let (lo, hi): (Vec<f64>, Vec<f64>) = codes[..k].iter().map(|&(c, x, w, _)| bounds_of(c, x, w)).unzip();
        let kappa: Vec<f64> = codes[..k].iter().map(|c| 10f64.powf(c.3)).collect();
        let x_ref = brute_force_springs(&a, b, &dofs, &lo, &hi, &kappa);
        let cols: Vec<Vec<f64>> = dofs.iter().map(|&c| column(&a, c)).collect();
        let mut mp = MultiProjection::new(dofs.clone(), cols).unwrap().with_compliance(kappa.iter().map(|k| 1.0 / k).collect()).unwrap();
        let mut x = solve(&a, b);
        let rep = mp.project(&mut x, &lo, &hi).unwrap();
        let scale = x_ref.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let err = x.iter().zip(&x_ref).fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        prop_assert!(err <= 1e-10 * scale, "x differs by {err:e} (k = {k}, {} iterations)", rep.iterations);
        for (i, &c) in dofs.iter().enumerate() {
            let spring = kappa[i] * (lo[i] - x[c]).max(0.0) - kappa[i] * (x[c] - hi[i]).max(0.0);
            let m = mp.multipliers()[i];
            prop_assert!((m - spring).abs() <= 1e-9 * (1.0 + kappa[i]) * scale, "μ_{i} = {m}, spring {spring}");
        }
    }
}

#[test]
fn bad_compliance_is_a_typed_error() {
    let a = vec![vec![2.0, -1.0, 0.0], vec![-1.0, 2.0, -1.0], vec![0.0, -1.0, 2.0]];
    let col = |c: usize| column(&a, c);
    let mp = || MultiProjection::new(vec![0, 2], vec![col(0), col(2)]).unwrap();
    assert_eq!(mp().with_compliance(vec![1.0, -1.0]).unwrap_err(), ContactError::Compliance(-1.0));
    assert_eq!(mp().with_compliance(vec![f64::NAN, 1.0]).unwrap_err().to_string(), "invalid compliance NaN: allowed finite and >= 0");
    assert!(matches!(mp().with_compliance(vec![1.0]).unwrap_err(), ContactError::Columns { .. }));
}
