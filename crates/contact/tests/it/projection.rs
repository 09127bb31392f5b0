//! The projection against a brute-force KKT solve on random SPD systems
//! (dense faer oracle), and the scalar piecewise-linear solve.
//! Tolerances: residuals relative to ‖b‖ at 1e-11 (systems here have
//! condition number < 1e3 by construction).

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use proptest::prelude::*;
use signorini_contact::{check_bounds, solve_piecewise_linear, Active, ContactError, PiecewiseLinear, Projection};

fn solve(a: &Mat<f64>, b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let x = a.llt(Side::Lower).unwrap().solve(Mat::from_fn(n, 1, |i, _| b[i]));
    (0..n).map(|i| x[(i, 0)]).collect()
}

/// Brute force: try the three candidate active sets and keep the one that
/// satisfies all KKT conditions.
fn brute_force(a: &Mat<f64>, b: &[f64], c: usize, lo: f64, hi: f64) -> (Vec<f64>, f64) {
    let n = b.len();
    let y = solve(a, b);
    if y[c] >= lo && y[c] <= hi {
        return (y, 0.0);
    }
    let xc = if y[c] < lo { lo } else { hi };
    // Reduced system on the dofs other than c, with x_c fixed.
    let idx: Vec<usize> = (0..n).filter(|&i| i != c).collect();
    let ar = Mat::from_fn(n - 1, n - 1, |i, j| a[(idx[i], idx[j])]);
    let br: Vec<f64> = idx.iter().map(|&i| b[i] - a[(i, c)] * xc).collect();
    let xr = if n > 1 { solve(&ar, &br) } else { vec![] };
    let mut x = vec![0.0; n];
    x[c] = xc;
    for (k, &i) in idx.iter().enumerate() {
        x[i] = xr[k];
    }
    let mu: f64 = (0..n).map(|j| a[(c, j)] * x[j]).sum::<f64>() - b[c];
    (x, mu)
}

fn spd(n: usize, vals: &[f64]) -> Mat<f64> {
    let g = Mat::from_fn(n, n, |i, j| vals[i * n + j]);
    let mut a = &g * g.transpose();
    for i in 0..n {
        a[(i, i)] += 0.5;
    }
    a
}

proptest! {
    #[test]
    fn projection_solves_the_kkt_system(
        n in 1usize..7,
        vals in proptest::collection::vec(-1.0f64..1.0, 49),
        bv in proptest::collection::vec(-2.0f64..2.0, 7),
        c_frac in 0.0f64..1.0,
        lo in -1.0f64..0.5,
        width in 0.0f64..1.5,
        one_sided in proptest::bool::ANY,
    ) {
        let a = spd(n, &vals);
        let b = &bv[..n];
        let c = ((c_frac * n as f64) as usize).min(n - 1);
        let hi = if one_sided { f64::INFINITY } else { lo + width };
        let mut ec = vec![0.0; n];
        ec[c] = 1.0;
        let proj = Projection::new(c, solve(&a, &ec)).unwrap();
        let mut x = solve(&a, b);
        let r = proj.project(&mut x, lo, hi);
        let (xb, mub) = brute_force(&a, b, c, lo, hi);
        let scale = 1.0 + b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        for i in 0..n {
            prop_assert!((x[i] - xb[i]).abs() <= 1e-11 * scale, "x[{}] {} vs {}", i, x[i], xb[i]);
        }
        prop_assert!((r.mu - mub).abs() <= 1e-11 * scale, "mu {} vs {}", r.mu, mub);
        // KKT: A x = b + mu e_c, bounds, sign and complementarity of mu.
        for i in 0..n {
            let ax: f64 = (0..n).map(|j| a[(i, j)] * x[j]).sum();
            let rhs = b[i] + if i == c { r.mu } else { 0.0 };
            prop_assert!((ax - rhs).abs() <= 1e-11 * scale);
        }
        prop_assert!(x[c] >= lo && x[c] <= hi);
        match r.active {
            Active::None => prop_assert!(r.mu == 0.0 && x[c] > lo - 0.0 && x[c] < hi + 0.0),
            Active::Lower => prop_assert!(r.mu >= 0.0 && x[c] == lo),
            Active::Upper => prop_assert!(r.mu <= 0.0 && x[c] == hi),
        }
    }

    /// A penalty law N(x) = -k min(x - g, 0) (continuous, non-increasing):
    /// the branch solve satisfies the equation to rounding.
    #[test]
    fn piecewise_linear_branch_solve(yc in -2.0f64..2.0, wc in 1e-3f64..10.0, k in 0.0f64..1e4, g in -0.5f64..0.5) {
        let law = PiecewiseLinear { breaks: &[g], branches: &[(k * g, -k), (0.0, 0.0)] };
        let (x, n) = solve_piecewise_linear(yc, wc, law).unwrap();
        // Evaluating k g - k x cancels: the rounding scale is w_c k (|g| + |x|) ulps.
        let scale = 1.0 + yc.abs() + wc * k * (g.abs() + x.abs());
        prop_assert!((x - (yc + wc * law.eval(x))).abs() <= 1e-14 * scale);
        prop_assert!((n - law.eval(x)).abs() <= 1e-14 * scale / wc);
        prop_assert!(n >= 0.0);
    }
}

#[test]
fn errors_are_typed() {
    assert_eq!(Projection::new(3, vec![1.0; 3]).unwrap_err(), ContactError::DofOutOfRange { dof: 3, n: 3 });
    assert_eq!(Projection::new(0, vec![0.0]).unwrap_err(), ContactError::BadInfluence(0.0));
    assert!(check_bounds(1.0, 0.0).is_err());
    assert!(check_bounds(f64::NAN, 0.0).is_err());
    assert!(check_bounds(0.0, f64::INFINITY).is_ok());
    // An increasing law with w_c b >= 1 has no solution on any branch.
    let law = PiecewiseLinear { breaks: &[], branches: &[(1.0, 2.0)] };
    assert_eq!(solve_piecewise_linear(0.0, 1.0, law).unwrap_err(), ContactError::NoBranch);
}
