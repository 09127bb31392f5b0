//! `bar-dirichlet` against values computed independently of the crate's
//! piecewise table: the hand-derived test vectors of docs/theory.md §5.1, and
//! an oracle written here from the reflection rules of the wave equation
//! (Riemann invariants carried along the characteristics, reflected at the
//! clamped end, and at the contact end by the Signorini rule), marched in
//! time without any use of the period. The solution is piecewise affine with
//! dyadic data, so values agree to a few ulps (1e-15 on u_x, u_t, λ; the
//! oracle's u is a sum of about a hundred dyadic terms: 1e-14).

use proptest::prelude::*;
use signorini_exact::{BarDirichlet, ExactSolution, FarEnd};

const TOL: f64 = 1e-15;

use crate::common;
use common::{CELLS_PER_UNIT, DELTA};

/// The d'Alembert solution of `u_tt = u_xx` on `(0, 1)`, `u(1, t) = 0`,
/// `0 <= u(0, t) ⊥ u_x(0, t) <= 0`, `u(x, 0) = (1 - x)/2`, `u_t(x, 0) = 0`,
/// built from the reflection rules alone.
///
/// With `r = u_t + u_x` (constant along `x + t = const`, `r(x, t) = R(x + t)`)
/// and `s = u_t - u_x` (constant along `x - t = const`, `s(x, t) = S(x - t)`):
/// * initial data: `R = -1/2` and `S = +1/2` on `[0, 1]`;
/// * clamped end `x = 1` (`u_t = 0`): `R(1 + t) = -S(1 - t)`;
/// * contact end `x = 0`, with `z(t) = u(0, t)`: free (`u_x = 0`) gives
///   `S(-t) = R(t)` and `z' = R(t)`; in contact (`u_t = 0`) `S(-t) = -R(t)`
///   and `λ = u_x(0, t) = R(t)`. The end is in contact iff `z = 0` and the
///   incoming `R(t) < 0` (free motion would penetrate).
///
/// `S` on negative arguments (the waves leaving `x = 0`) is marched cell by
/// cell of length [`DELTA`]; it is constant on each cell because the data
/// are and the contact switches only at lattice times (checked).
struct Oracle {
    /// `S(-τ)` for `τ` in cell `k`, i.e. `[kδ, (k + 1)δ)`.
    s_out: Vec<f64>,
    /// `z(kδ) = u(0, kδ)`.
    z: Vec<f64>,
    /// `u_t(0, τ)` on cell `k`.
    z_rate: Vec<f64>,
}

impl Oracle {
    /// Marched up to `t_end`; evaluations need `x + t <= t_end`.
    fn new(t_end: f64) -> Self {
        let cells = (t_end * CELLS_PER_UNIT as f64).ceil() as usize + 1;
        let mut o = Oracle { s_out: Vec::with_capacity(cells), z: vec![0.5], z_rate: Vec::with_capacity(cells) };
        for k in 0..cells {
            let r = o.r_cell(k);
            let z = o.z[k];
            let contact = z <= 0.0 && r < 0.0;
            let (s, rate) = if contact { (-r, 0.0) } else { (r, r) };
            let z_next = z + DELTA * rate;
            assert!(z_next >= 0.0, "the oracle's lattice misses an impact inside cell {k}");
            o.s_out.push(s);
            o.z_rate.push(rate);
            o.z.push(z_next);
        }
        o
    }

    /// `R` on the cell `[cδ, (c + 1)δ)` of its argument `ξ >= 0`.
    fn r_cell(&self, c: usize) -> f64 {
        let two = 2 * CELLS_PER_UNIT;
        if c < two {
            // ξ < 1: initial data; 1 <= ξ < 2: reflected at x = 1 from S on (0, 1].
            -0.5
        } else {
            // ξ >= 2: R(ξ) = -S(2 - ξ), a wave that left x = 0 at τ = ξ - 2.
            -self.s_out[c - two]
        }
    }

    fn cell(v: f64) -> usize {
        (v / DELTA).floor() as usize
    }

    fn r(&self, xi: f64) -> f64 {
        self.r_cell(Self::cell(xi))
    }

    fn s(&self, eta: f64) -> f64 {
        if eta >= 0.0 {
            0.5
        } else {
            self.s_out[Self::cell(-eta)]
        }
    }

    /// `(u_x, u_t)` at `(x, t)` (off the characteristic lines through the lattice).
    fn derivatives(&self, x: f64, t: f64) -> (f64, f64) {
        let (r, s) = (self.r(x + t), self.s(x - t));
        ((r - s) / 2.0, (r + s) / 2.0)
    }

    /// `u(x, t) = z(t) + ∫_0^x u_x(ξ, t) dξ`, integrated exactly: `u_x(·, t)` is
    /// constant between the points where `ξ ± t` crosses the lattice.
    fn u(&self, x: f64, t: f64) -> f64 {
        let k = Self::cell(t);
        let z = self.z[k] + (t - k as f64 * DELTA) * self.z_rate[k];
        z + common::lattice_integral(x, t, |xi| self.derivatives(xi, t).0)
    }

    /// `λ(t) = u_x(0, t)` (right-continuous: the cell starting at `t`).
    fn lambda(&self, t: f64) -> f64 {
        let k = Self::cell(t);
        (self.r_cell(k) - self.s_out[k]) / 2.0
    }

    /// `∫_0^1 (u_t² + u_x²)/2 dx`, exact (piecewise constant integrand).
    fn energy(&self, t: f64) -> f64 {
        let n = 4096; // a multiple of the lattice: cells of 1/4096 never straddle a line when t is dyadic
        (0..n)
            .map(|i| {
                let (ux, ut) = self.derivatives((i as f64 + 0.5) / n as f64, t);
                (ut * ut + ux * ux) / 2.0 / n as f64
            })
            .sum()
    }
}

/// Distance from `x` to the nearest characteristic line `x ± t ∈ Z` (the
/// only lines across which this solution's derivatives can jump).
fn line_distance(x: f64, t: f64) -> f64 {
    let d = |v: f64| (v - v.round()).abs();
    d(x - t).min(d(x + t))
}

fn check(x: f64, t: f64, u: f64, ux: f64, ut: f64) {
    let f = BarDirichlet.fields(x, t);
    assert!((f.u - u).abs() <= TOL && (f.ux - ux).abs() <= TOL && (f.ut - ut).abs() <= TOL, "({x},{t}): {f:?} vs ({u},{ux},{ut})");
}

#[test]
fn test_vectors() {
    check(0.25, 0.5, 0.25, 0.0, -0.5);
    check(0.75, 0.5, 0.125, -0.5, 0.0);
    check(0.2, 1.5, -0.1, -0.5, 0.0);
    check(0.3, 1.2, -0.1, 0.0, -0.5);
    check(0.8, 1.5, -0.1, 0.5, 0.0);
    check(0.6, 1.7, -0.15, 0.0, 0.5);
    check(0.2, 2.5, 0.25, 0.0, 0.5);
    check(0.8, 2.5, 0.1, -0.5, 0.0);
    check(0.4, 3.3, 0.3, -0.5, 0.0);
    check(0.9, 7.6, -0.05, 0.5, 0.0);
    for (t, l) in [(0.5, 0.0), (1.25, -0.5), (1.75, -0.5), (2.5, 0.0), (4.5, -0.5)] {
        assert_eq!(BarDirichlet.lambda(t), l, "lambda({t})");
    }
}

#[test]
fn oracle_reproduces_the_hand_derived_vectors() {
    // The oracle is checked on its own before it is used as a reference.
    let o = Oracle::new(9.0);
    let v = [
        (0.25, 0.5, 0.25, 0.0, -0.5),
        (0.75, 0.5, 0.125, -0.5, 0.0),
        (0.2, 1.5, -0.1, -0.5, 0.0),
        (0.3, 1.2, -0.1, 0.0, -0.5),
        (0.8, 1.5, -0.1, 0.5, 0.0),
        (0.6, 1.7, -0.15, 0.0, 0.5),
        (0.2, 2.5, 0.25, 0.0, 0.5),
        (0.8, 2.5, 0.1, -0.5, 0.0),
        (0.4, 3.3, 0.3, -0.5, 0.0),
        (0.9, 7.6, -0.05, 0.5, 0.0),
    ];
    for (x, t, u, ux, ut) in v {
        let (oux, out) = o.derivatives(x, t);
        assert!((o.u(x, t) - u).abs() <= 1e-14 && oux == ux && out == ut, "oracle ({x},{t})");
        // u(1, t) = 0 comes out of the integration, not by construction.
        assert!(o.u(1.0, t).abs() <= 1e-14, "oracle u(1,{t}) = {}", o.u(1.0, t));
    }
    for (t, l) in [(0.5, 0.0), (1.25, -0.5), (1.75, -0.5), (2.5, 0.0), (4.5, -0.5)] {
        assert_eq!(o.lambda(t), l, "oracle lambda({t})");
    }
    // The oracle's motion is periodic with period 3 (it never uses it) and
    // not with period 3/2: the crate's declared period is a property of the
    // solution, not of its formula.
    assert_eq!(BarDirichlet.period(), Some(3.0));
    let (mut d3, mut d15) = (0.0_f64, 0.0_f64);
    for it in 0..60 {
        let t = 0.0371 + it as f64 * 0.1;
        for ix in 1..20 {
            let x = ix as f64 / 20.0 + 0.0013;
            d3 = d3.max((o.u(x, t + 3.0) - o.u(x, t)).abs());
            d15 = d15.max((o.u(x, t + 1.5) - o.u(x, t)).abs());
        }
    }
    assert!(d3 <= 1e-14 && d15 > 0.1, "oracle: shift 3 {d3:e}, shift 1.5 {d15}");
}

#[test]
fn initial_and_boundary_data() {
    for i in 0..=100 {
        let x = i as f64 / 100.0;
        let f = BarDirichlet.fields(x, 0.0);
        assert!((f.u - (1.0 - x) / 2.0).abs() <= TOL);
        assert_eq!(f.ut, 0.0);
        // u(1, t) = 0 for all t: the declared far end is the clamped one.
        let t = i as f64 * 0.0731;
        assert!(BarDirichlet.fields(1.0, t).u.abs() <= TOL, "u(1,{t})");
    }
    assert_eq!(BarDirichlet.far_end(), FarEnd::Clamped);
    assert_eq!(BarDirichlet.length(), 1.0);
    assert_eq!(BarDirichlet.body_force(), 0.0);
}

#[test]
fn energy_is_the_integral_of_the_oracle_density() {
    // E = ∫ (u_t² + u_x²)/2 dx of the oracle at dyadic times (lines on the
    // integration cells' edges), over four periods.
    let o = Oracle::new(13.0);
    for it in 0..=96 {
        let t = it as f64 / 8.0;
        let e = o.energy(t);
        assert!((e - BarDirichlet.energy()).abs() <= 1e-15, "t = {t}: oracle energy {e} vs {}", BarDirichlet.energy());
    }
    // and E = 1/8 by hand: at t = 0, ∫ (1/2)²/2 dx = 1/8.
    assert_eq!(BarDirichlet.energy(), 0.125);
}

#[test]
fn kinks_are_the_characteristic_lines() {
    let mut k = Vec::new();
    BarDirichlet.kinks(1.3, &mut k);
    assert_eq!(k.len(), 2);
    assert!((k[0] - 0.3).abs() < 1e-15 && (k[1] - 0.7).abs() < 1e-15);
    BarDirichlet.kinks(0.5, &mut k);
    assert_eq!(k, vec![0.5]);
    BarDirichlet.kinks(2.0, &mut k);
    assert!(k.is_empty());
    // Every jump of the oracle's u_x or u_t in (0, 1) is a reported kink,
    // over four periods (the exact norms split elements only there).
    let o = Oracle::new(13.0);
    for it in 0..1200 {
        let t = it as f64 * 0.01 + 0.003;
        BarDirichlet.kinks(t, &mut k);
        assert!(k.windows(2).all(|w| w[0] < w[1]) && k.iter().all(|&x| x > 0.0 && x < 1.0), "t = {t}: {k:?}");
        for j in -14i64..=14 {
            for x in [j as f64 - t, t - j as f64] {
                if x > 1e-6 && x < 1.0 - 1e-6 {
                    let (a, b) = (o.derivatives(x - 1e-9, t), o.derivatives(x + 1e-9, t));
                    if a != b {
                        assert!(k.iter().any(|&q| (q - x).abs() < 1e-12), "t = {t}: jump at {x} not in {k:?}");
                    }
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    /// u, u_x, u_t, λ and `u_at` against the oracle over four periods.
    #[test]
    fn fields_match_the_characteristics_oracle(x in 0.0f64..1.0, t in 0.0f64..12.0) {
        let o = oracle();
        let f = BarDirichlet.fields(x, t);
        prop_assert!((f.u - o.u(x, t)).abs() <= 1e-14, "u({}, {}) = {} vs {}", x, t, f.u, o.u(x, t));
        if line_distance(x, t) > 1e-12 {
            let (ux, ut) = o.derivatives(x, t);
            prop_assert!(f.ux == ux && f.ut == ut, "({}, {}): u_x {} vs {}, u_t {} vs {}", x, t, f.ux, ux, f.ut, ut);
        }
        if (t - t.round()).abs() > 1e-12 {
            prop_assert_eq!(BarDirichlet.lambda(t), o.lambda(t), "lambda({})", t);
        }
        let mut out = [0.0; 2];
        BarDirichlet.u_at(t, &[x, 1.0 - x], &mut out);
        prop_assert!((out[0] - o.u(x, t)).abs() <= 1e-14 && (out[1] - o.u(1.0 - x, t)).abs() <= 1e-14);
    }

    /// Complementarity, sign, continuity and the parallelogram identity (the
    /// weak form of the wave equation), which hold across the lines.
    #[test]
    fn properties(x in 0.0f64..1.0, t in 0.0f64..12.0, h in 0.0f64..0.2) {
        let s = BarDirichlet;
        let u0 = s.fields(0.0, t).u;
        let l = s.lambda(t);
        prop_assert!(u0 >= -TOL);
        prop_assert!(l <= 0.0);
        prop_assert!((u0 * l).abs() <= TOL);
        // Continuity of u across any line: left/right limits agree.
        let e = 1e-9;
        if x > e && x < 1.0 - e {
            // |u_x| <= 1/2, so a jump-free u moves at most e across [x-e, x+e].
            prop_assert!((s.fields(x - e, t).u - s.fields(x + e, t).u).abs() <= e + 1e-15);
        }
        // Parallelogram identity u(x,t+h)+u(x,t-h)-u(x+h,t)-u(x-h,t) = 0.
        if x >= h && x + h <= 1.0 && t >= h {
            let d = s.fields(x, t + h).u + s.fields(x, t - h).u - s.fields(x + h, t).u - s.fields(x - h, t).u;
            prop_assert!(d.abs() <= 4.0 * TOL, "defect {}", d);
        }
    }
}

/// One oracle for all proptest cases (marched to t = 13 once).
fn oracle() -> &'static Oracle {
    static O: std::sync::OnceLock<Oracle> = std::sync::OnceLock::new();
    O.get_or_init(|| Oracle::new(13.0))
}

/// `u_at` (one phase, branch-free zones) gives `fields(x, t).u` bit for bit:
/// at the nodes of meshes at the levels of runs over every phase, on the
/// kinks `x = τ` and `x = 1 − τ` themselves and an ulp either side, at the
/// ends within and beyond the slack, for signed zeros and NaN. (The norms
/// take `u_at`, the analysis and plots `fields`: the convergence CSVs must
/// not move.)
#[test]
fn u_at_is_fields_bit_for_bit() {
    let s = BarDirichlet;
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    let mut out = Vec::new();
    for (m, dt) in [(10usize, 1e-2), (37, 1.0 / 370.0), (80, 1.0 / 160.0), (1000, 1e-4)] {
        let mut xs: Vec<f64> = (0..=m).map(|i| i as f64 / m as f64).collect();
        xs.extend([-0.0, -1e-9, -1.1e-9, 1.0 + 1e-9, 1.0 + 1.1e-9, -0.5, 1.5, f64::NAN]);
        let steps = (9.5 / dt) as usize;
        for n in (0..steps).step_by(7) {
            let t = n as f64 * dt;
            let tau = t.rem_euclid(3.0).fract();
            let mut pts = xs.clone();
            for k in [tau, 1.0 - tau] {
                pts.extend([k, f64::from_bits(k.to_bits().wrapping_add(1)), f64::from_bits(k.to_bits().wrapping_sub(1))]);
            }
            out.resize(pts.len(), 0.0);
            s.u_at(t, &pts, &mut out);
            for (x, u) in pts.iter().zip(&out) {
                let f = s.fields(*x, t).u;
                assert!(same(*u, f), "t = {t}, x = {x:e}: u_at {u:e}, fields {f:e}");
            }
        }
    }
}
