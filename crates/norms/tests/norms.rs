//! Space and time norms against integrals known in closed form. The
//! integration is exact (piecewise polynomial), so agreement is to rounding:
//! 1e-14 relative.

use signorini_exact::{ExactSolution, FarEnd, Fields};
use signorini_norms::{ErrorNorms, SpaceIntegrator, TimeNorm, VNorm};

/// A test "solution" u(x) = s(x - a)|x - a|^(p-1) for p = 1, 2 (kink at a), or x² (no kink).
struct Kinked {
    a: f64,
    p: usize,
    square: bool,
}

impl ExactSolution for Kinked {
    fn name(&self) -> &str {
        "kinked"
    }
    fn length(&self) -> f64 {
        1.0
    }
    fn far_end(&self) -> FarEnd {
        FarEnd::Free
    }
    fn degree_x(&self) -> usize {
        if self.square {
            2
        } else {
            self.p
        }
    }
    fn fields(&self, x: f64, _t: f64) -> Fields {
        let u = if self.square {
            x * x
        } else if self.p == 1 {
            (x - self.a).abs()
        } else {
            (x - self.a) * (x - self.a).abs()
        };
        Fields { u, ux: f64::NAN, ut: 0.0 }
    }
    fn lambda(&self, t: f64) -> f64 {
        if t > 1.0 {
            -0.5
        } else {
            0.0
        }
    }
    fn energy(&self) -> f64 {
        2.0
    }
    fn kinks(&self, _t: f64, out: &mut Vec<f64>) {
        out.clear();
        if !self.square {
            out.push(self.a);
        }
    }
}

fn check(exact: &Kinked, m: usize, u: &[f64], vnorm: VNorm, l2: f64, v: f64) {
    check_tol(exact, m, u, vnorm, l2, v, 1e-14);
}

fn check_tol(exact: &Kinked, m: usize, u: &[f64], vnorm: VNorm, l2: f64, v: f64, tol: f64) {
    let mut s = SpaceIntegrator::new(exact, m, vnorm);
    let e = s.errors(0.0, u);
    assert!((e.l2 - l2).abs() <= tol * l2.max(1e-300), "L2 {} vs {l2}", e.l2);
    assert!((e.v - v).abs() <= tol * v.max(1e-300), "V {} vs {v}", e.v);
}

#[test]
fn affine_kink_inside_an_element() {
    let a: f64 = 0.37; // inside element [0.2, 0.4] of m = 5
    let k = Kinked { a, p: 1, square: false };
    let l2 = ((a.powi(3) + (1.0 - a).powi(3)) / 3.0).sqrt();
    check(&k, 5, &[0.0; 6], VNorm::H1Seminorm, l2, 1.0);
    check(&k, 5, &[0.0; 6], VNorm::H1Full, l2, (1.0 + l2 * l2).sqrt());
    // Clamped convention: m values, the last taken as 0.
    check(&k, 5, &[0.0; 5], VNorm::H1Seminorm, l2, 1.0);
}

#[test]
fn kinks_on_or_next_to_nodes() {
    // 0.3/0.1 rounds to 2.9999999999999996: the element search must settle
    // on the right element (a wrong one once looped forever).
    for (a, m) in [(0.3, 10usize), (0.7, 10), (0.5, 4), (1.0 / 3.0, 3), (0.6 + 1e-15, 5), (0.6 - 1e-15, 5)] {
        let k = Kinked { a, p: 1, square: false };
        let l2 = ((a.powi(3) + (1.0 - a).powi(3)) / 3.0).sqrt();
        check(&k, m, &vec![0.0; m + 1], VNorm::H1Seminorm, l2, 1.0);
    }
}

#[test]
fn quadratic_kink_inside_an_element() {
    let a: f64 = 0.61;
    let k = Kinked { a, p: 2, square: false };
    let l2 = ((a.powi(5) + (1.0 - a).powi(5)) / 5.0).sqrt();
    let semi = (4.0 * (a.powi(3) + (1.0 - a).powi(3)) / 3.0).sqrt();
    check(&k, 7, &[0.0; 8], VNorm::H1Seminorm, l2, semi);
}

#[test]
fn interpolation_error_of_x_squared() {
    // Error of the P1 interpolant of x²: per element -(x-a)(b-x), so
    // ∫e² = h⁵/30 and ∫e'² = h³/3 per element.
    let k = Kinked { a: 0.0, p: 2, square: true };
    for m in [1usize, 4, 33] {
        let h = 1.0 / m as f64;
        let u: Vec<f64> = (0..=m).map(|i| (i as f64 * h).powi(2)).collect();
        let l2 = (m as f64 * h.powi(5) / 30.0).sqrt();
        let semi = (m as f64 * h.powi(3) / 3.0).sqrt();
        // The error (≤ h²/4) is a difference of O(1) values: relative
        // rounding up to ~eps / (h²/4) in the pointwise error.
        check_tol(&k, m, &u, VNorm::H1Seminorm, l2, semi, 1e-15 * 4.0 / (h * h));
    }
}

#[test]
fn time_norms() {
    let mut t = TimeNorm::default();
    for e in [1.0, -3.0, 2.0] {
        t.push(e);
    }
    assert_eq!(t.linf(), 3.0);
    assert!((t.l2(0.5) - 7.0f64.sqrt()).abs() < 1e-15);
    assert_eq!(t.samples(), 3);
    let mut n = TimeNorm::default();
    n.push(f64::NAN);
    n.push(1.0);
    assert!(n.linf().is_nan(), "a NaN sample must not be hidden");
}

#[test]
fn error_norms_accumulate_lambda_energy_and_tv() {
    let k = Kinked { a: 0.5, p: 1, square: false };
    let mut n = ErrorNorms::new(&k, 4, VNorm::H1Seminorm);
    // λ_h oscillates around the exact step -0.5 at t > 1.
    for (t, l) in [(0.5, 0.0), (1.5, -0.4), (2.0, -0.6), (2.5, -0.5)] {
        n.add_lambda(t, l);
        n.add_energy(t, 2.0 + t);
    }
    let r = n.report(0.5);
    // λ errors 0, 0.1, -0.1, 0: L2 = sqrt(0.5 * 0.02) = 0.1.
    assert!((r.l2_lambda - 0.1).abs() < 1e-15);
    // TV(λ_h) = 0.4 + 0.2 + 0.1 = 0.7, TV(λ) = 0.5.
    assert!((r.lambda_tv_ratio - 1.4).abs() < 1e-14);
    assert_eq!(r.linf_energy, 2.5);
}

#[test]
fn getfem_style_norms_are_relative_interpolation_errors() {
    use signorini_norms::NormKind;
    let k = Kinked { a: 0.37, p: 1, square: false };
    let m = 5;
    let interp: Vec<f64> = (0..=m).map(|i| (i as f64 / m as f64 - 0.37).abs()).collect();
    // u_h = I_h u: zero error (the kink inside an element is not seen).
    let mut n = ErrorNorms::with_kind(&k, m, VNorm::H1Full, NormKind::GetfemInterpolated);
    n.add_displacement(0.0, &interp);
    n.add_lambda(1.5, -0.5);
    n.add_energy(1.5, 2.0);
    let r = n.report(0.1);
    assert_eq!((r.linf_l2_u, r.linf_v_u, r.l2_lambda, r.linf_energy), (0.0, 0.0, 0.0, 0.0));
    // u_h = 0, λ_h = 0, E_h = 0: every relative error is exactly 1.
    let mut z = ErrorNorms::with_kind(&k, m, VNorm::H1Full, NormKind::GetfemInterpolated);
    for t in [0.0, 0.5] {
        z.add_displacement(t, &vec![0.0; m + 1]);
    }
    z.add_lambda(1.5, 0.0);
    z.add_energy(1.5, 0.0);
    let r = z.report(0.1);
    for v in [r.linf_l2_u, r.l2_l2_u, r.linf_v_u, r.l2_v_u, r.l2_lambda, r.linf_energy, r.l2_energy] {
        assert!((v - 1.0).abs() < 1e-15, "{v}");
    }
    // The exact norms of the same u_h = I_h u are not zero (the kink).
    let mut x = ErrorNorms::new(&k, m, VNorm::H1Full);
    assert!(x.add_displacement(0.0, &interp).l2 > 1e-3);
}
