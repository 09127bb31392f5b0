//! The several-contact solve of the schemes (`MultiSolve`, crates/schemes/src/multi.rs):
//! its reduced banded solve of large active sets against the dense Delassus pivots.

use signorini_fem::SymBand;
use signorini_schemes::{Active, Bounds, Contact, Dynamics, MultiSolve};

/// A tridiagonal or pentadiagonal SPD matrix with a pseudo-random
/// diagonal excess.
fn matrix(n: usize, p: usize, seed: u64) -> SymBand {
    let mut a = SymBand::zeros(n, p);
    let mut r = seed;
    let mut next = || {
        r = r.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (r >> 11) as f64 / (1u64 << 53) as f64
    };
    for i in 0..n {
        for q in 1..=p.min(i) {
            a.set(i, i - q, -0.5 - 0.5 * next());
        }
    }
    for i in 0..n {
        let off: f64 = (i.saturating_sub(p)..(i + p + 1).min(n)).filter(|&j| j != i).map(|j| a.get(i, j).abs()).sum();
        a.set(i, i, off + 0.01 + next());
    }
    a
}

/// The banded solve of large active sets and the dense Delassus pivots
/// give the same solution and multipliers (the dense one is checked
/// against brute-force KKT in signorini-contact's tests): rigid and
/// spring bounds, one- and two-sided, cold and warm starts.
#[test]
fn banded_large_active_sets_equal_the_dense_pivots() {
    for (n, p, springs, seed) in [(200, 1, false, 1), (200, 1, true, 2), (120, 3, false, 3), (120, 3, true, 4)] {
        let a = matrix(n, p, seed);
        let contacts: Vec<Contact> = (0..n).map(|i| Contact::new(i, if i % 3 == 0 { Bounds { lo: -0.2, hi: 0.3 } } else { Bounds::obstacle(-0.1) }, false)).collect();
        let dy = Dynamics::new(a.clone(), a.clone(), vec![0.0; n], contacts);
        let fac = a.factor().unwrap();
        let build = |banded: bool| {
            let mut ms = MultiSolve::new(&dy, &fac).unwrap();
            if springs {
                let kappa: Vec<f64> = (0..n).map(|i| 50.0 + i as f64).collect();
                ms = ms.with_springs(&kappa, 1.0).unwrap();
            }
            let mut ms = ms.with_banded(a.clone()).unwrap();
            assert!(ms.banded_state().0, "k = {n} is beyond the cap");
            ms.set_dense_cap(if banded { 0 } else { usize::MAX });
            for (i, c) in dy.contacts.iter().enumerate() {
                (ms.lo[i], ms.hi[i]) = (c.bounds.lo, c.bounds.hi);
            }
            ms
        };
        let (mut dense, mut banded) = (build(false), build(true));
        for step in 0..4 {
            // A right-hand side violating many bounds: y = A⁻¹ b.
            let mut y: Vec<f64> = (0..n).map(|i| 0.4 * ((i as f64 * 0.37 + step as f64).sin()) - 0.05 * step as f64).collect();
            fac.solve_in_place(&mut y);
            let mut y2 = y.clone();
            dense.solve(&mut y).unwrap();
            banded.solve(&mut y2).unwrap();
            assert!(banded.banded_state().1 && !dense.banded_state().1);
            let active = dense.status().iter().filter(|s| **s != Active::None).count();
            assert!(active > 20, "case ({n}, {p}, {springs}): only {active} active");
            let scale = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            for i in 0..n {
                assert!((y[i] - y2[i]).abs() <= 1e-11 * scale, "case ({n}, {p}, {springs}) step {step}: x_{i} {} vs {}", y[i], y2[i]);
                let (m1, m2) = (dense.multipliers()[i], banded.multipliers()[i]);
                assert!((m1 - m2).abs() <= 1e-9 * (1.0 + m1.abs()), "case ({n}, {p}, {springs}) step {step}: μ_{i} {m1} vs {m2}");
                assert_eq!(dense.status()[i], banded.status()[i], "status {i}");
            }
            let mut s1: Vec<usize> = dense.active_set().to_vec();
            s1.sort_unstable();
            let mut s2: Vec<usize> = banded.active_set().to_vec();
            s2.sort_unstable();
            assert_eq!(s1, s2);
        }
    }
}
