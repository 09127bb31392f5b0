//! `bar-mirrored` against values computed independently of the crate:
//!
//! * an oracle written here for the **two-stop** bar on `[0, 2]` from the
//!   reflection rules of the wave equation alone (Riemann invariants carried
//!   along the characteristics, reflected at `x = 0` by the lower stop's
//!   Signorini rule and at `x = 2` by the upper stop's), marched in time —
//!   it never uses the mirror, the period or the single-contact solution, so
//!   the antisymmetry is a result here, not an assumption;
//! * the mirror identities against `BarDirichlet` (`u(x) = -u_D(2 - x)`,
//!   `u_x(x) = u_D,x(2 - x)`, `u_t(x) = -u_D,t(2 - x)`) at test points;
//! * hand values from the table of docs/theory.md §5.1 mirrored by hand.
//!
//! The solution is piecewise affine with dyadic data, so values agree to a
//! few ulps (u_x, u_t, λ exactly; the oracle's u is a sum of about a
//! hundred dyadic terms: 1e-14).

use proptest::prelude::*;
use signorini_exact::{BarDirichlet, BarMirrored, ExactSolution, FarEnd};

use crate::common;
use common::{CELLS_PER_UNIT, DELTA};
/// Cells in the bar's length 2 (the travel time from one end to the other).
const CROSS: usize = 2 * CELLS_PER_UNIT;

/// The d'Alembert solution of `u_tt = u_xx` on `(0, 2)` with
/// `0 <= u(0, t) ⊥ u_x(0, t) <= 0` and `0 >= u(2, t) ⊥ u_x(2, t) <= 0`,
/// `u(x, 0) = (1 - x)/2`, `u_t(x, 0) = 0`.
///
/// `r = u_t + u_x = R(x + t)`, `s = u_t - u_x = S(x - t)`; initially
/// `R = -1/2`, `S = 1/2` on `[0, 2]`. At `x = 0` with `z0 = u(0, t)` and the
/// incoming `R(t)`: free (`u_x = 0`) `S(-t) = R(t)`, `z0' = R`; held
/// (`u_t = 0`) `S(-t) = -R(t)`, held iff `z0 <= 0` and `R(t) < 0`. At
/// `x = 2` with `z2 = u(2, t)` and the incoming `S(2 - t)`: free
/// `R(2 + t) = S(2 - t)`, `z2' = S`; held `R(2 + t) = -S(2 - t)`, held iff
/// `z2 >= 0` and `S(2 - t) > 0`.
struct TwoStops {
    /// `S(-τ)` on cell `k` of `τ` (waves leaving `x = 0`).
    s_out0: Vec<f64>,
    /// `R(2 + τ)` on cell `k` of `τ` (waves leaving `x = 2`).
    r_out2: Vec<f64>,
    z0: Vec<f64>,
    z0_rate: Vec<f64>,
    z2: Vec<f64>,
    z2_rate: Vec<f64>,
}

impl TwoStops {
    fn new(t_end: f64) -> Self {
        let cells = (t_end * CELLS_PER_UNIT as f64).ceil() as usize + CROSS + 1;
        let mut o = TwoStops { s_out0: Vec::new(), r_out2: Vec::new(), z0: vec![0.5], z0_rate: Vec::new(), z2: vec![-0.5], z2_rate: Vec::new() };
        for k in 0..cells {
            // Incoming at x = 0: R(t), t in cell k.
            let r_in = if k < CROSS { -0.5 } else { o.r_out2[k - CROSS] };
            let held0 = o.z0[k] <= 0.0 && r_in < 0.0;
            let (s, rate0) = if held0 { (-r_in, 0.0) } else { (r_in, r_in) };
            // Incoming at x = 2: S(2 - t), 2 - t in the cell (2 - (k+1)δ, 2 - kδ].
            let s_in = if k < CROSS { 0.5 } else { o.s_out0[k - CROSS] };
            let held2 = o.z2[k] >= 0.0 && s_in > 0.0;
            let (r, rate2) = if held2 { (-s_in, 0.0) } else { (s_in, s_in) };
            let (z0, z2) = (o.z0[k] + DELTA * rate0, o.z2[k] + DELTA * rate2);
            assert!(z0 >= 0.0 && z2 <= 0.0, "the oracle's lattice misses an impact inside cell {k}");
            o.s_out0.push(s);
            o.r_out2.push(r);
            o.z0_rate.push(rate0);
            o.z2_rate.push(rate2);
            o.z0.push(z0);
            o.z2.push(z2);
        }
        o
    }

    fn cell(v: f64) -> usize {
        (v / DELTA).floor() as usize
    }

    fn r(&self, xi: f64) -> f64 {
        if xi < 2.0 {
            -0.5
        } else {
            self.r_out2[Self::cell(xi - 2.0)]
        }
    }

    fn s(&self, eta: f64) -> f64 {
        if eta >= 0.0 {
            0.5
        } else {
            self.s_out0[Self::cell(-eta)]
        }
    }

    /// `(u_x, u_t)` at `(x, t)` (off the lattice's characteristic lines).
    fn derivatives(&self, x: f64, t: f64) -> (f64, f64) {
        let (r, s) = (self.r(x + t), self.s(x - t));
        ((r - s) / 2.0, (r + s) / 2.0)
    }

    /// `u(x, t) = z0(t) + ∫_0^x u_x`, integrated exactly piece by piece.
    fn u(&self, x: f64, t: f64) -> f64 {
        let k = Self::cell(t);
        let z = self.z0[k] + (t - k as f64 * DELTA) * self.z0_rate[k];
        z + common::lattice_integral(x, t, |xi| self.derivatives(xi, t).0)
    }

    /// `u(2, t)` as marched at the right end.
    fn z2(&self, t: f64) -> f64 {
        let k = Self::cell(t);
        self.z2[k] + (t - k as f64 * DELTA) * self.z2_rate[k]
    }

    /// `u_x(0, t)` (right-continuous).
    fn lambda0(&self, t: f64) -> f64 {
        let k = Self::cell(t);
        let r_in = if k < CROSS { -0.5 } else { self.r_out2[k - CROSS] };
        (r_in - self.s_out0[k]) / 2.0
    }

    /// `u_x(2, t)` (right-continuous).
    fn lambda2(&self, t: f64) -> f64 {
        let k = Self::cell(t);
        let s_in = if k < CROSS { 0.5 } else { self.s_out0[k - CROSS] };
        (self.r_out2[k] - s_in) / 2.0
    }

    /// `∫_0^2 (u_t² + u_x²)/2 dx` at a dyadic time (exact: piecewise constant).
    fn energy(&self, t: f64) -> f64 {
        let n = 8192;
        (0..n)
            .map(|i| {
                let (ux, ut) = self.derivatives(2.0 * (i as f64 + 0.5) / n as f64, t);
                (ut * ut + ux * ux) / 2.0 * 2.0 / n as f64
            })
            .sum()
    }
}

fn oracle() -> &'static TwoStops {
    static O: std::sync::OnceLock<TwoStops> = std::sync::OnceLock::new();
    O.get_or_init(|| TwoStops::new(13.0))
}

/// Distance from `x` to the nearest line `x ± t ∈ Z`.
fn line_distance(x: f64, t: f64) -> f64 {
    let d = |v: f64| (v - v.round()).abs();
    d(x - t).min(d(x + t))
}

#[test]
fn declared_data() {
    let s = BarMirrored;
    assert_eq!(s.name(), "bar-mirrored");
    assert_eq!(s.length(), 2.0);
    assert_eq!(s.far_end(), FarEnd::Free);
    assert_eq!(s.wave_speed(), 1.0);
    assert_eq!(s.gap(), 0.0);
    assert_eq!(s.body_force(), 0.0);
    assert_eq!(s.degree_x(), 1);
    assert_eq!(s.period(), Some(3.0));
    // Twice the Dirichlet bar's 1/8: at t = 0, ∫_0^2 (1/2)²/2 dx = 1/4.
    assert_eq!(s.energy(), 0.25);
}

#[test]
fn initial_data_and_hand_values() {
    for i in 0..=200 {
        let x = i as f64 / 100.0;
        let f = BarMirrored.fields(x, 0.0);
        assert!((f.u - (1.0 - x) / 2.0).abs() <= 1e-15 && f.ut == 0.0 && f.ux == -0.5, "t = 0, x = {x}: {f:?}");
    }
    // docs/theory.md §5.1's table at (2 - x, t), mirrored by hand:
    // u ↦ -u, u_x ↦ u_x, u_t ↦ -u_t.
    let v = [
        (1.75, 0.5, -0.25, 0.0, 0.5),   // D(0.25, 0.5) = (0.25, 0, -0.5)
        (1.25, 0.5, -0.125, -0.5, 0.0), // D(0.75, 0.5) = (0.125, -0.5, 0)
        (1.8, 1.5, 0.1, -0.5, 0.0),     // D(0.2, 1.5) = (-0.1, -0.5, 0)
        (1.7, 1.2, 0.1, 0.0, 0.5),      // D(0.3, 1.2) = (-0.1, 0, -0.5)
        (1.2, 1.5, 0.1, 0.5, 0.0),      // D(0.8, 1.5) = (-0.1, 0.5, 0)
        (1.4, 1.7, 0.15, 0.0, -0.5),    // D(0.6, 1.7) = (-0.15, 0, 0.5)
        (1.8, 2.5, -0.25, 0.0, -0.5),   // D(0.2, 2.5) = (0.25, 0, 0.5)
        (1.2, 2.5, -0.1, -0.5, 0.0),    // D(0.8, 2.5) = (0.1, -0.5, 0)
        (1.6, 3.3, -0.3, -0.5, 0.0),    // D(0.4, 3.3) = (0.3, -0.5, 0)
        (1.1, 7.6, 0.05, 0.5, 0.0),     // D(0.9, 7.6) = (-0.05, 0.5, 0)
        // and on [0, 1], the table itself.
        (0.25, 0.5, 0.25, 0.0, -0.5),
        (0.6, 1.7, -0.15, 0.0, 0.5),
    ];
    for (x, t, u, ux, ut) in v {
        let f = BarMirrored.fields(x, t);
        assert!((f.u - u).abs() <= 1e-15 && f.ux == ux && f.ut == ut, "({x}, {t}): {f:?} vs ({u}, {ux}, {ut})");
    }
    for (t, l) in [(0.5, 0.0), (1.0, -0.5), (1.25, -0.5), (1.75, -0.5), (2.0, 0.0), (2.5, 0.0), (4.5, -0.5)] {
        assert_eq!(BarMirrored.lambda(t), l, "lambda({t})");
    }
}

#[test]
fn the_two_stop_oracle_is_odd_about_the_middle_and_holds_its_stops() {
    // Checked on the oracle alone before it serves as a reference: the
    // antisymmetry comes out of the marching, and u(2, t) from the
    // integration agrees with the right end's own record.
    let o = oracle();
    let mut worst = 0.0f64;
    for it in 0..300 {
        let t = 0.0371 + it as f64 * 0.04;
        for ix in 0..=40 {
            let x = ix as f64 / 20.0 * 0.999 + 0.0007;
            worst = worst.max((o.u(x, t) + o.u(2.0 - x, t)).abs());
        }
        assert!((o.u(2.0, t) - o.z2(t)).abs() <= 1e-14, "t = {t}: u(2) {} vs z2 {}", o.u(2.0, t), o.z2(t));
        assert!(o.u(1.0, t).abs() <= 1e-14);
        let (l0, l2) = (o.lambda0(t), o.lambda2(t));
        assert!(l0 <= 0.0 && l2 <= 0.0 && (o.u(0.0, t) * l0).abs() <= 1e-15 && (o.z2(t) * l2).abs() <= 1e-15);
    }
    assert!(worst <= 1e-14, "oracle: |u(x) + u(2 - x)| up to {worst:e}");
    // Its energy is 1/4 at dyadic times over four periods.
    for it in 0..=96 {
        let t = it as f64 / 8.0;
        assert!((o.energy(t) - 0.25).abs() <= 1e-15, "t = {t}: oracle energy {}", o.energy(t));
    }
}

#[test]
fn kinks_are_the_mirrored_characteristic_lines() {
    let mut k = Vec::new();
    BarMirrored.kinks(1.3, &mut k);
    let want = [0.3, 0.7, 1.3, 1.7];
    assert!(k.len() == 4 && k.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-15), "{k:?}");
    BarMirrored.kinks(0.5, &mut k);
    assert_eq!(k, vec![0.5, 1.5]);
    // At integer times the lines leaving both ends meet at x = 1, where
    // u_t jumps (at t = 2: from +1/2 to -1/2).
    BarMirrored.kinks(2.0, &mut k);
    assert_eq!(k, vec![1.0]);
    let (l, r) = (BarMirrored.fields(1.0 - 1e-9, 2.0), BarMirrored.fields(1.0, 2.0));
    assert!(l.ut == 0.5 && r.ut == -0.5, "{l:?} {r:?}");
    // Every jump of the oracle's u_x or u_t in (0, 2) is a reported kink.
    let o = oracle();
    for it in 0..1200 {
        let t = it as f64 * 0.01 + 0.003;
        BarMirrored.kinks(t, &mut k);
        assert!(k.windows(2).all(|w| w[0] < w[1]) && k.iter().all(|&x| x > 0.0 && x < 2.0), "t = {t}: {k:?}");
        for j in -16i64..=16 {
            for x in [j as f64 - t, t - j as f64] {
                if x > 1e-6 && x < 2.0 - 1e-6 {
                    let (a, b) = (o.derivatives(x - 1e-9, t), o.derivatives(x + 1e-9, t));
                    if a != b {
                        assert!(k.iter().any(|&q| (q - x).abs() < 1e-12), "t = {t}: jump at {x} not in {k:?}");
                    }
                }
            }
        }
        // On a kink, the values are those of the piece towards larger x.
        for &q in &k {
            let (f, g) = (BarMirrored.fields(q, t), BarMirrored.fields(q + 1e-9, t));
            assert!(f.ux == g.ux && f.ut == g.ut, "t = {t}, kink {q}: {f:?} vs the right piece {g:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// u, u_x, u_t, λ and `u_at` against the two-stop oracle over four periods.
    #[test]
    fn fields_match_the_two_stop_oracle(x in 0.0f64..=2.0, t in 0.0f64..12.0) {
        let o = oracle();
        let f = BarMirrored.fields(x, t);
        prop_assert!((f.u - o.u(x, t)).abs() <= 1e-14, "u({}, {}) = {} vs {}", x, t, f.u, o.u(x, t));
        if line_distance(x, t) > 1e-12 {
            let (ux, ut) = o.derivatives(x, t);
            prop_assert!(f.ux == ux && f.ut == ut, "({}, {}): u_x {} vs {}, u_t {} vs {}", x, t, f.ux, ux, f.ut, ut);
        }
        if (t - t.round()).abs() > 1e-12 {
            prop_assert_eq!(BarMirrored.lambda(t), o.lambda0(t));
            // The force at x = 2 is the opposite reaction: u_x(2) = λ.
            prop_assert_eq!(BarMirrored.fields(2.0, t).ux, o.lambda2(t));
        }
        let mut out = [0.0; 2];
        BarMirrored.u_at(t, &[x, 2.0 - x], &mut out);
        prop_assert!((out[0] - o.u(x, t)).abs() <= 1e-14 && (out[1] - o.u(2.0 - x, t)).abs() <= 1e-14);
    }

    /// The mirror identities against the single-contact solution.
    #[test]
    fn mirror_identities(y in 0.0f64..=1.0, t in 0.0f64..12.0) {
        let (d, m, l) = (BarDirichlet.fields(y, t), BarMirrored.fields(2.0 - y, t), BarMirrored.fields(y, t));
        prop_assert!((m.u + d.u).abs() <= 1e-15 && (l.u - d.u).abs() <= 1e-15, "u(2 - y) = {}, u(y) = {} vs u_D(y) = {}", m.u, l.u, d.u);
        if line_distance(y, t) > 1e-12 && y < 1.0 {
            prop_assert!(l == d, "on [0, 1) it is the Dirichlet bar: {:?} vs {:?}", l, d);
            prop_assert!(m.ux == d.ux && m.ut == -d.ut, "(2 - {}, {}): {:?} vs {:?}", y, t, m, d);
        }
        prop_assert_eq!(BarMirrored.lambda(t), BarDirichlet.lambda(t));
        let (mut kd, mut km) = (Vec::new(), Vec::new());
        BarDirichlet.kinks(t, &mut kd);
        BarMirrored.kinks(t, &mut km);
        let mut want = kd.clone();
        want.extend(kd.iter().rev().map(|k| 2.0 - k));
        prop_assert_eq!(km.len(), want.len());
        prop_assert!(km.iter().zip(&want).all(|(a, b)| (a - b).abs() <= 1e-15), "{:?} vs {:?}", km, want);
    }
}
