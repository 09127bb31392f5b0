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

/// A quadratic kink at round-off distance from a node with an O(1) error:
/// the sliver it cuts off an element must contribute its tiny share, not
/// the cancellation error of e² over the sliver's length (0.17 % of the
/// seminorm here — 0.6099 against 0.6110 — before the seminorm of a
/// degree-2 piece was computed from its differences).
#[test]
fn quadratic_kink_next_to_a_node_with_a_large_error() {
    for (a, m) in [(0.6 + 1e-15, 5usize), (0.6 - 1e-15, 5), (0.7, 10), (0.6999999999999993, 10)] {
        let k = Kinked { a, p: 2, square: false };
        let c = 0.123_456_7; // u_h = c: e = c − (x − a)|x − a|
        let int_u = ((1.0 - a).powi(3) - a.powi(3)) / 3.0;
        let int_u2 = (a.powi(5) + (1.0 - a).powi(5)) / 5.0;
        let l2 = (c * c - 2.0 * c * int_u + int_u2).sqrt();
        let semi = (4.0 * (a.powi(3) + (1.0 - a).powi(3)) / 3.0).sqrt();
        check_tol(&k, m, &vec![c; m + 1], VNorm::H1Seminorm, l2, semi, 1e-13);
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

// ---------------------------------------------------------------------------
// Elements crossed by two (or more) kinks, against an independent adaptive
// quadrature of the same integrals, which uses the exact strain `u_x` (the
// integrator uses only values of `u`).

/// `∫_a^b f` by adaptive Simpson with Richardson's correction: each
/// interval is halved at least 8 times, then until the halves agree with the
/// whole to `15 tol` per unit length. Simpson samples the interval ends, so
/// a jump of `f` anywhere inside an interval changes the halves' sum and
/// keeps it splitting, down to an interval of length ~1e-15: the integral is
/// accurate to rounding whatever the kinks (a Gauss rule, blind near the
/// ends, can accept an interval whose jump lies between its end and first node).
fn adaptive(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    struct Q<'f> {
        f: &'f dyn Fn(f64) -> f64,
        tol: f64,
    }
    impl Q<'_> {
        /// Midpoint, f there, Simpson on [a, b].
        fn simpson(&self, a: f64, fa: f64, b: f64, fb: f64) -> (f64, f64, f64) {
            let m = 0.5 * (a + b);
            let fm = (self.f)(m);
            (m, fm, (b - a) / 6.0 * (fa + 4.0 * fm + fb))
        }
        #[allow(clippy::too_many_arguments)]
        fn rec(&self, a: f64, fa: f64, b: f64, fb: f64, m: f64, fm: f64, whole: f64, depth: u32) -> f64 {
            let (lm, flm, l) = self.simpson(a, fa, m, fm);
            let (rm, frm, r) = self.simpson(m, fm, b, fb);
            let diff = l + r - whole;
            if depth >= 60 || (depth >= 8 && diff.abs() <= 15.0 * self.tol * (b - a)) {
                l + r + diff / 15.0
            } else {
                self.rec(a, fa, m, fm, lm, flm, l, depth + 1) + self.rec(m, fm, b, fb, rm, frm, r, depth + 1)
            }
        }
    }
    let q = Q { f, tol };
    let (fa, fb) = (f(a), f(b));
    let (m, fm, whole) = q.simpson(a, fa, b, fb);
    q.rec(a, fa, b, fb, m, fm, whole, 0)
}

/// `(∫(u_h - u)², ∫(u_h' - u_x)²)` over `[0, L]` by [`adaptive`], element by
/// element, with `u_h` the P1 function of `nodal` (`m` values: the last node is 0).
fn reference(exact: &dyn ExactSolution, m: usize, nodal: &[f64], t: f64) -> (f64, f64) {
    let l = exact.length();
    let h = l / m as f64;
    let node = |i: usize| nodal.get(i).copied().unwrap_or(0.0);
    let (mut l2, mut semi) = (0.0, 0.0);
    for j in 0..m {
        let (a, b) = (j as f64 * h, (j + 1) as f64 * h);
        let (ua, ub) = (node(j), node(j + 1));
        let slope = (ub - ua) / h;
        let uh = move |x: f64| ua + slope * (x - a);
        l2 += adaptive(&|x| (uh(x) - exact.fields(x, t).u).powi(2), a, b, 1e-15);
        semi += adaptive(&|x| (slope - exact.fields(x, t).ux).powi(2), a, b, 1e-15);
    }
    (l2, semi)
}

/// Kinks of `exact` at `t` per element of a mesh of `m` elements.
fn kinks_per_element(exact: &dyn ExactSolution, m: usize, t: f64) -> Vec<usize> {
    let mut k = Vec::new();
    exact.kinks(t, &mut k);
    let h = exact.length() / m as f64;
    (0..m).map(|j| k.iter().filter(|&&x| x > j as f64 * h && x < (j + 1) as f64 * h).count()).collect()
}

#[test]
fn bar_dirichlet_with_both_kinks_in_one_element() {
    use signorini_exact::BarDirichlet;
    let exact = BarDirichlet;
    // Contact phase (t in [1, 2)): τ = t - 1, kinks at τ and 1 - τ, both real
    // (u = -x/2, then -τ/2, then (x-1)/2). With m = 3 both lie in the middle
    // element [1/3, 2/3] for τ in (1/3, 2/3); with m = 5 in [0.4, 0.6] for
    // τ in (0.4, 0.6).
    for (m, t) in [(3usize, 1.4), (3, 1.35), (3, 1.45), (3, 1.55), (3, 1.62), (5, 1.45), (5, 1.58)] {
        assert!(kinks_per_element(&exact, m, t).contains(&2), "m = {m}, t = {t}: set-up must put two kinks in one element");
        for pert in [[0.0; 3], [0.01, -0.02, 0.03]] {
            // u_h = nodal interpolant + a perturbation (clamped: m values).
            let h = 1.0 / m as f64;
            let u: Vec<f64> = (0..m).map(|i| exact.fields(i as f64 * h, t).u + pert[i % 3]).collect();
            let (l2, semi) = reference(&exact, m, &u, t);
            let mut s = SpaceIntegrator::new(&exact, m, VNorm::H1Seminorm);
            let e = s.errors(t, &u);
            assert!((e.l2 - l2.sqrt()).abs() <= 1e-12 * l2.sqrt(), "m = {m}, t = {t}, {pert:?}: L2 {} vs quadrature {}", e.l2, l2.sqrt());
            assert!((e.v - semi.sqrt()).abs() <= 1e-12 * semi.sqrt(), "m = {m}, t = {t}, {pert:?}: H1 {} vs quadrature {}", e.v, semi.sqrt());
        }
    }
    // By hand, m = 3, t = 1.4, u_h = I_h u: the error vanishes outside
    // [1/3, 2/3]; inside, u_h = -1/6 and e = u_h - u is x/2 - 1/6 on
    // [1/3, 0.4], 1/30 on [0.4, 0.6], 1/3 - x/2 on [0.6, 2/3]:
    // ∫e² = 2 (1/15)(1/30)²/3 + 0.2 (1/30)² = 11/40500, ∫e'² = 2 (1/15)(1/4) = 1/30.
    let u: Vec<f64> = (0..3).map(|i| exact.fields(i as f64 / 3.0, 1.4).u).collect();
    let e = SpaceIntegrator::new(&exact, 3, VNorm::H1Seminorm).errors(1.4, &u);
    assert!((e.l2 - (11.0f64 / 40500.0).sqrt()).abs() <= 1e-13, "L2 {} vs {}", e.l2, (11.0f64 / 40500.0).sqrt());
    assert!((e.v - (1.0f64 / 30.0).sqrt()).abs() <= 1e-13, "H1 {} vs {}", e.v, (1.0f64 / 30.0).sqrt());
}

/// `u(x) = Σ c_k (x - a_k)|x - a_k|^(p-1)` (p = 1: kinks of `u`; p = 2: of `u_x`).
struct ManyKinks {
    at: Vec<f64>,
    coef: Vec<f64>,
    p: usize,
}

impl ExactSolution for ManyKinks {
    fn name(&self) -> &str {
        "many-kinks"
    }
    fn length(&self) -> f64 {
        1.0
    }
    fn far_end(&self) -> FarEnd {
        FarEnd::Free
    }
    fn degree_x(&self) -> usize {
        self.p
    }
    fn fields(&self, x: f64, _t: f64) -> Fields {
        let (mut u, mut ux) = (0.0, 0.0);
        for (a, c) in self.at.iter().zip(&self.coef) {
            let d = x - a;
            if self.p == 1 {
                u += c * d.abs();
                ux += c * if d >= 0.0 { 1.0 } else { -1.0 };
            } else {
                u += c * d * d.abs();
                ux += 2.0 * c * d.abs();
            }
        }
        Fields { u, ux, ut: 0.0 }
    }
    fn lambda(&self, _t: f64) -> f64 {
        0.0
    }
    fn energy(&self) -> f64 {
        0.0
    }
    fn kinks(&self, _t: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend(&self.at);
    }
}

#[test]
fn two_and_three_kinks_in_one_element_of_degree_one_and_two() {
    // m = 4: element [0.25, 0.5] holds the kinks; another kink alone in [0.75, 1].
    let cases: [(&[f64], &[f64]); 4] = [(&[0.3, 0.45], &[1.0, -2.0]), (&[0.26, 0.31, 0.49], &[0.7, -1.5, 2.0]), (&[0.3, 0.45, 0.8], &[1.0, 1.0, -0.5]), (&[0.3, 0.301], &[1.0, -1.0])];
    for p in [1usize, 2] {
        for (at, coef) in cases {
            let exact = ManyKinks { at: at.to_vec(), coef: coef.to_vec(), p };
            let m = 4;
            assert!(kinks_per_element(&exact, m, 0.0)[1] >= 2);
            let u = [0.1, -0.3, 0.25, 0.0, -0.2];
            let (l2, semi) = reference(&exact, m, &u, 0.0);
            for vnorm in [VNorm::H1Seminorm, VNorm::H1Full] {
                let e = SpaceIntegrator::new(&exact, m, vnorm).errors(0.0, &u);
                let v2 = if vnorm == VNorm::H1Full { semi + l2 } else { semi };
                assert!((e.l2 - l2.sqrt()).abs() <= 1e-12 * l2.sqrt(), "p = {p}, kinks {at:?}: L2 {} vs quadrature {}", e.l2, l2.sqrt());
                assert!((e.v - v2.sqrt()).abs() <= 1e-12 * v2.sqrt(), "p = {p}, kinks {at:?}, {vnorm:?}: V {} vs quadrature {}", e.v, v2.sqrt());
            }
        }
    }
}

/// The P1 element sums are the per-element formula `h/3 (e₀² + e₀e₁ + e₁²)`,
/// `(e₁ − e₀)²/h` summed element by element in order, bit for bit (the loop
/// computes the elements' terms a chunk at a time, vectorised, then sums
/// them in order): a kink on a node splits nothing, so no element is
/// re-integrated; a free end (m + 1 values) and a clamped one (m values,
/// the last 0); meshes shorter than a chunk, at and around chunk bounds
/// (32 elements) and of several chunks; the AVX2 code and the baseline's.
#[test]
fn p1_element_sums_are_the_plain_formula_bit_for_bit() {
    for m in [1usize, 2, 3, 7, 31, 32, 33, 34, 65, 100, 257, 1000, 2049] {
        let h = 1.0 / m as f64;
        let exact = Kinked { a: 0.0, p: 1, square: false };
        let nodes: Vec<f64> = (0..=m).map(|i| if i == m { 1.0 } else { i as f64 * h }).collect();
        let ex: Vec<f64> = nodes.iter().map(|&x| exact.fields(x, 0.0).u).collect();
        for clamped in [false, true] {
            let u: Vec<f64> = (0..m + usize::from(!clamped)).map(|i| (0.7 * i as f64 + 0.3).sin()).collect();
            let node_u = |i: usize| if i < u.len() { u[i] } else { 0.0 };
            let (mut l2, mut semi) = (0.0, 0.0);
            for j in 0..m {
                let (e0, e1) = (node_u(j) - ex[j], node_u(j + 1) - ex[j + 1]);
                l2 += e0 * e0 + e0 * e1 + e1 * e1;
                semi += (e1 - e0) * (e1 - e0);
            }
            if m == 1 {
                // One element: the piece formula scales before summing.
                (l2, semi) = (h * l2 / 3.0, semi / h);
            } else {
                (l2, semi) = (l2 * (h / 3.0), semi / h);
            }
            for baseline in [false, true] {
                let space = SpaceIntegrator::new(&exact, m, VNorm::H1Seminorm);
                let mut space = if baseline { space.without_avx2() } else { space };
                let e = space.errors(0.0, &u);
                assert_eq!((e.l2.to_bits(), e.v.to_bits()), (l2.sqrt().to_bits(), semi.sqrt().to_bits()), "m = {m}, clamped {clamped}, baseline {baseline}");
            }
        }
    }
}

/// The P1 errors with elements split at kinks, bit for bit as the plain
/// algorithm gives them with the exact solution's `fields` point by point:
/// the unsplit element sums, then, element by element in order, the
/// element's unsplit contribution removed and its pieces' added (the
/// integrator finds the exact solution at every split element's points in
/// one call). The Dirichlet bar (two kinks: in one element or two, on
/// nodes) and the mirrored bar (four kinks) at many times, clamped and free
/// ends, meshes within one chunk (32 elements) and of several.
#[test]
fn p1_split_elements_are_the_plain_algorithm_bit_for_bit() {
    use signorini_exact::{BarDirichlet, BarMirrored};
    let piece = |len: f64, e0: f64, e1: f64| (len * (e0 * e0 + e0 * e1 + e1 * e1) / 3.0, (e1 - e0) * (e1 - e0) / len);
    let exacts: [&dyn ExactSolution; 2] = [&BarDirichlet, &BarMirrored];
    let mut split_levels = [0usize; 2];
    for (which, exact) in exacts.into_iter().enumerate() {
        let length = exact.length();
        for m in [3usize, 10, 100, 257, 2100] {
            let h = length / m as f64;
            let nodes: Vec<f64> = (0..=m).map(|i| if i == m { length } else { i as f64 * h }).collect();
            for free in [false, true] {
                let u: Vec<f64> = (0..m + usize::from(free)).map(|i| 0.3 * (0.37 * i as f64 + 0.2).sin()).collect();
                let node_u = |i: usize| if i < u.len() { u[i] } else { 0.0 };
                let mut space = SpaceIntegrator::new(exact, m, VNorm::H1Full);
                let mut kinks = Vec::new();
                for n in 0..400 {
                    let t = n as f64 * (3.0 / 400.0) + 1e-3;
                    let ex = |x: f64| exact.fields(x, t).u;
                    let (mut l2, mut semi) = (0.0, 0.0);
                    for j in 0..m {
                        let (e0, e1) = (node_u(j) - ex(nodes[j]), node_u(j + 1) - ex(nodes[j + 1]));
                        l2 += e0 * e0 + e0 * e1 + e1 * e1;
                        semi += (e1 - e0) * (e1 - e0);
                    }
                    (l2, semi) = (l2 * (h / 3.0), semi / h);
                    exact.kinks(t, &mut kinks);
                    for j in 0..m {
                        let (a, b) = (nodes[j], nodes[j + 1]);
                        let inner: Vec<f64> = kinks.iter().copied().filter(|&x| a < x && x < b).collect();
                        if inner.is_empty() {
                            continue;
                        }
                        split_levels[which] += 1;
                        let (ua, ub) = (node_u(j), node_u(j + 1));
                        let (wa, wb) = piece(h, ua - ex(a), ub - ex(b));
                        l2 -= wa;
                        semi -= wb;
                        let pts: Vec<f64> = std::iter::once(a).chain(inner).chain(std::iter::once(b)).collect();
                        let e: Vec<f64> = pts.iter().map(|&x| ua + (ub - ua) * ((x - a) / h) - ex(x)).collect();
                        for (p, w) in pts.windows(2).enumerate() {
                            let len = w[1] - w[0];
                            if len > 0.0 {
                                let (pa, pb) = piece(len, e[p], e[p + 1]);
                                l2 += pa;
                                semi += pb;
                            }
                        }
                    }
                    let (l2, v) = (l2.max(0.0).sqrt(), (semi + l2).max(0.0).sqrt());
                    let got = space.errors(t, &u);
                    assert_eq!((got.l2.to_bits(), got.v.to_bits()), (l2.to_bits(), v.to_bits()), "{} m = {m}, free {free}, t = {t}: {got:?} vs ({l2}, {v})", exact.name());
                }
            }
        }
    }
    // Both bars had split elements to check (each level has one or more).
    assert!(split_levels.iter().all(|&s| s > 1000), "{split_levels:?}");
}
