//! The event-driven reference at large stiffness and mass spreads and near
//! resonance (docs/theory.md §9.1) against an oracle whose accuracy does
//! not degrade with the spread: the modes of a lumped chain from a one-sided
//! Jacobi SVD of its factor `G = S^{1/2} B M^{-1/2}` (`K = Bᵀ S B`, `B` the
//! springs' incidence, `GᵀG = M^{-1/2} K M^{-1/2}`), relatively accurate
//! when the grading sits in the columns of the matrix it orthogonalises
//! (Demmel–Veselić 1992): `G` for a light mass, `Gᵀ` for a stiff spring.
//! Each mode is then advanced by its closed form, its load by a
//! Gauss–Legendre Duhamel integral: nothing of flow.rs is used.

use crate::events_scales::{replay, spread};
use signorini_fem::SymBand;
use signorini_schemes::events::ModalFlow;
use signorini_schemes::{Dynamics, Forcing, TimeProfile};

/// A lumped chain: `masses`, `links[j]` joining dofs `j` and `j + 1`,
/// `wall` tying the last dof to the ground (0: a free chain).
pub(crate) struct Chain {
    pub masses: Vec<f64>,
    pub links: Vec<f64>,
    pub wall: f64,
}

/// The oracle's modes: `ω²` and `Φ` (column `i` of `phi[r][i]`), `Φᵀ M Φ = I`.
pub(crate) struct Modes {
    pub k: Vec<f64>,
    pub phi: Vec<Vec<f64>>,
}

impl Chain {
    /// The chain of [`spread`]'s matrices.
    fn spread(ratio: f64, light: bool) -> Self {
        let mut masses = vec![1.0; 4];
        if light {
            masses[1] = 1.0 / ratio;
        }
        Self { masses, links: vec![if light { 1.0 } else { ratio }, 1.0, 1.0], wall: 1.0 }
    }

    /// `(M, K)`, `K = Bᵀ S B` entry by entry.
    fn matrices(&self) -> (SymBand, SymBand) {
        let n = self.masses.len();
        let (m, mut k) = (SymBand::from_diagonal(&self.masses), SymBand::zeros(n, 1));
        for (j, s) in self.links.iter().enumerate() {
            k.set(j, j, k.get(j, j) + s);
            k.set(j + 1, j + 1, k.get(j + 1, j + 1) + s);
            k.set(j + 1, j, -s);
        }
        k.set(n - 1, n - 1, k.get(n - 1, n - 1) + self.wall);
        (m, k)
    }

    /// The modes by one-sided Jacobi on `G` (`columns`: the grading is in
    /// `M`) or on `Gᵀ` (in `S`).
    fn modes(&self, columns: bool) -> Modes {
        let n = self.masses.len();
        // Rows of G: one per spring (a free chain's last row is zero).
        let mut g = vec![vec![0.0; n]; n];
        for (j, s) in self.links.iter().enumerate() {
            g[j][j] = -s.sqrt() / self.masses[j].sqrt();
            g[j][j + 1] = s.sqrt() / self.masses[j + 1].sqrt();
        }
        g[n - 1][n - 1] = self.wall.sqrt() / self.masses[n - 1].sqrt();
        // `y` holds the columns of the matrix orthogonalised.
        let y: Vec<Vec<f64>> = if columns { (0..n).map(|c| (0..n).map(|r| g[r][c]).collect()).collect() } else { g.clone() };
        let (y, v) = hestenes(y);
        let mut order: Vec<usize> = (0..n).collect();
        let norm = |x: &[f64]| x.iter().map(|a| a * a).sum::<f64>().sqrt();
        order.sort_by(|&a, &b| norm(&y[a]).total_cmp(&norm(&y[b])));
        let top = order.iter().fold(0.0f64, |m, &i| m.max(norm(&y[i])));
        // A free chain's rigid mode: a column of round-off, `ω² = 0`.
        let k = order.iter().map(|&i| norm(&y[i])).map(|s| if s <= 1e-14 * top { 0.0 } else { s * s }).collect();
        // The eigenvectors of GᵀG: G's right singular vectors (the
        // rotations when orthogonalising G's columns, the normalised
        // columns when orthogonalising Gᵀ's).
        let vecs: Vec<Vec<f64>> = order.iter().map(|&i| if columns { v[i].clone() } else { y[i].iter().map(|a| a / norm(&y[i])).collect() }).collect();
        let phi = (0..n).map(|r| (0..n).map(|i| vecs[i][r] / self.masses[r].sqrt()).collect()).collect();
        Modes { k, phi }
    }
}

/// One-sided Jacobi (Hestenes): rotates the columns `y` until every pair is
/// orthogonal to `ε` of their norms; returns them and the rotations' product
/// (columns of `v`, from the identity).
fn hestenes(mut y: Vec<Vec<f64>>) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let n = y.len();
    let mut v: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect()).collect();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    // A column of round-off against the whole (a free chain's rigid mode)
    // is done: its rotations would only stir the round-off.
    let floor = 1e-30 * y.iter().map(|c| dot(c, c)).sum::<f64>();
    for _ in 0..60 {
        let mut rotated = false;
        for p in 0..n {
            for q in p + 1..n {
                let (a, b, c) = (dot(&y[p], &y[p]), dot(&y[q], &y[q]), dot(&y[p], &y[q]));
                if c.abs() <= f64::EPSILON * (a * b).sqrt() || a.min(b) <= floor {
                    continue;
                }
                rotated = true;
                let zeta = (b - a) / (2.0 * c);
                let t = zeta.signum() / (zeta.abs() + zeta.hypot(1.0));
                let cs = 1.0 / t.hypot(1.0);
                let sn = cs * t;
                for w in [&mut y, &mut v] {
                    for r in 0..w[p].len() {
                        let (x, z) = (w[p][r], w[q][r]);
                        w[p][r] = cs * x - sn * z;
                        w[q][r] = sn * x + cs * z;
                    }
                }
            }
        }
        if !rotated {
            return (y, v);
        }
    }
    panic!("one-sided Jacobi did not converge in 60 sweeps");
}

/// The 16-point Gauss–Legendre rule on `[−1, 1]` (Newton on `P₁₆`).
fn gauss16() -> [(f64, f64); 16] {
    let n = 16;
    let mut out = [(0.0, 0.0); 16];
    for (i, o) in out.iter_mut().enumerate() {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                (p0, p1) = (p1, p2);
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() <= 1e-17 {
                break;
            }
        }
        *o = (x, 2.0 / ((1.0 - x * x) * dp * dp));
    }
    out
}

/// A mode `η'' + c η' + k η = g₀ + Σ g sin(Ω t)` from `(η₀, η₀')` at `t0`
/// over `τ`: a textbook particular solution (`g₀/k`;
/// `Im g e^{iΩt}/(k − Ω² + icΩ)`) plus the free motion from the remainder,
/// in closed form; a
/// rigid mode (`k = c = 0`) `η₀ + η₀' τ + g₀ τ²/2`; a harmonic within
/// ten percent of resonance (`|k − Ω²| <= 0.1 max(k, Ω²)`, where the
/// steady form cancels) by its Duhamel integral from rest, `∫₀^τ G(τ − u)
/// g sin(Ω (t0 + u)) du` (`G = e^{−αs} S(s)`), Gauss–Legendre on panels of
/// at most one radian, summed compensated.
fn mode(k: f64, c: f64, (eta, deta): (f64, f64), t0: f64, tau: f64, g0: f64, waves: &[(f64, f64)]) -> (f64, f64) {
    let alpha = 0.5 * c;
    let lambda = k - alpha * alpha;
    // `C(s), S(s)`: cos, sin/√λ (cosh, sinh for λ < 0; 1, s at 0).
    let cs = |s: f64| {
        if lambda > 0.0 {
            let w = lambda.sqrt();
            ((w * s).cos(), (w * s).sin() / w)
        } else if lambda < 0.0 {
            let w = (-lambda).sqrt();
            ((w * s).cosh(), (w * s).sinh() / w)
        } else {
            (1.0, s)
        }
    };
    let resonant = |w: f64| (k - w * w).abs() <= 0.1 * k.max(w * w);
    // The particular solution and its rate at `t` (the steady parts only).
    let steady = |t: f64| {
        let mut p = if k > 0.0 { (g0 / k, 0.0) } else { (0.0, 0.0) };
        for &(g, w) in waves.iter().filter(|x| !resonant(x.1)) {
            let z = g / faer::c64::new(k - w * w, c * w);
            let e = faer::c64::new((w * t).cos(), (w * t).sin());
            p.0 += (z * e).im;
            p.1 += (z * e * faer::c64::new(0.0, w)).im;
        }
        p
    };
    let (p0, p1) = (steady(t0), steady(t0 + tau));
    let (e0, de0) = (eta - p0.0, deta - p0.1);
    let (c0, s0) = cs(tau);
    let decay = (-alpha * tau).exp();
    let (mut x, mut dx) = (p1.0 + decay * (e0 * c0 + (de0 + alpha * e0) * s0), p1.1 + decay * (de0 * c0 - (alpha * de0 + k * e0) * s0));
    if k == 0.0 {
        assert!(c == 0.0, "the oracle's rigid modes are undamped");
        (x, dx) = (x + 0.5 * g0 * tau * tau, dx + g0 * tau);
    }
    for &(g, w) in waves.iter().filter(|x| resonant(x.1)) {
        let panels = (tau * k.sqrt().max(w).max(c).max(1.0)).ceil();
        let h = tau / panels;
        let (mut sx, mut sv) = (Neumaier::default(), Neumaier::default());
        for p in 0..panels as usize {
            for (node, weight) in gauss16() {
                let u = h * (p as f64 + 0.5 * (node + 1.0));
                let s = tau - u;
                let (co, si) = cs(s);
                let (e, fu) = ((-alpha * s).exp() * 0.5 * h * weight, g * (w * (t0 + u)).sin());
                sx.add(e * si * fu);
                sv.add(e * (co - alpha * si) * fu);
            }
        }
        x += sx.sum();
        dx += sv.sum();
    }
    (x, dx)
}

/// Neumaier's compensated sum.
#[derive(Default)]
struct Neumaier {
    s: f64,
    comp: f64,
}

impl Neumaier {
    fn add(&mut self, x: f64) {
        let t = self.s + x;
        self.comp += if self.s.abs() >= x.abs() { (self.s - t) + x } else { (x - t) + self.s };
        self.s = t;
    }
    fn sum(&self) -> f64 {
        self.s + self.comp
    }
}

/// The oracle's state of `dy` (lumped `M`, its damping classical with
/// modal `c_i = a + b ω_i²`, steady load and sines) after `τ` from `t0`.
pub(crate) fn oracle(dy: &Dynamics, modes: &Modes, (a, b): (f64, f64), t0: f64, q0: &[f64], v0: &[f64], tau: f64) -> (Vec<f64>, Vec<f64>) {
    let n = dy.n();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    let sines: Vec<(&[f64], f64, f64)> = dy
        .forcing
        .iter()
        .map(|f| match &f.time {
            TimeProfile::Sine { amplitude, omega } => (f.shape.as_slice(), *amplitude, *omega),
            _ => unreachable!("the oracle takes sines"),
        })
        .collect();
    for i in 0..n {
        let col = |x: &[f64]| (0..n).map(|r| modes.phi[r][i] * x[r]).sum::<f64>();
        let m = |x: &[f64]| (0..n).map(|r| modes.phi[r][i] * dy.mass.get(r, r) * x[r]).collect::<Vec<f64>>();
        let (eta, deta) = (m(q0).iter().sum(), m(v0).iter().sum());
        let waves: Vec<(f64, f64)> = sines.iter().map(|(s, amp, w)| (col(s) * amp, *w)).collect();
        let (x, dx) = mode(modes.k[i], a + b * modes.k[i], (eta, deta), t0, tau, col(&dy.load), &waves);
        for r in 0..n {
            q[r] += modes.phi[r][i] * x;
            v[r] += modes.phi[r][i] * dx;
        }
    }
    (q, v)
}

/// The chain's energy `½ vᵀ M v + ½ Σ s_j (Δq_j)²` (by springs: no
/// cancellation of a stiff link's `qᵀ K q`).
fn energy(chain: &Chain, q: &[f64], v: &[f64]) -> f64 {
    let n = q.len();
    let kin: f64 = (0..n).map(|i| chain.masses[i] * v[i] * v[i]).sum();
    let pot: f64 = chain.links.iter().enumerate().map(|(j, s)| s * (q[j + 1] - q[j]).powi(2)).sum::<f64>() + chain.wall * q[n - 1] * q[n - 1];
    0.5 * (kin + pot)
}

/// The flow's largest error against [`oracle`] over `τ` from `t0`, from
/// [`events_flow`]'s initial state: in `q` over its scale (at least 1), in
/// each `v_r` over the speed `√(2E/m_r)` the energy allows that dof (at
/// least `|v|`'s scale: a light mass's fast mode swings its speed through
/// 0), and in energy over the energy.
fn errors(flow: &ModalFlow, dy: &Dynamics, chain: &Chain, modes: &Modes, damp: (f64, f64), t0: f64, tau: f64) -> (f64, f64, f64) {
    let n = dy.n();
    let q0: Vec<f64> = (0..n).map(|i| 0.3 * (i as f64 + 1.0).sin()).collect();
    let v0: Vec<f64> = (0..n).map(|i| 0.2 * (2.0 * i as f64 + 0.5).cos()).collect();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    flow.advance(t0, &q0, &v0, tau, &mut q, &mut v);
    let (qr, vr) = oracle(dy, modes, damp, t0, &q0, &v0, tau);
    let er = energy(chain, &qr, &vr);
    let big = |x: &[f64]| x.iter().fold(1.0f64, |a, y| a.max(y.abs()));
    let eq = q.iter().zip(&qr).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / big(&qr);
    let ev = (0..n).map(|r| (v[r] - vr[r]).abs() / big(&vr).max((2.0 * er / chain.masses[r]).sqrt())).fold(0.0, f64::max);
    (eq, ev, (energy(chain, &q, &v) - er).abs() / er)
}

/// The oracle's own error on two masses (`m₁ = 1`, `m₂`, links: `k₁` wall
/// side, `k₂` between), whose `ω²` have closed forms: `λ₊ = (tr + √disc)/2`
/// (a sum of positives), `λ₋ = det/λ₊` (`det = k₁k₂/m₂`): relatively
/// accurate where `(tr − √disc)/2` cancels. Within 8 ε at every spread
/// from 1 to 1e12 (measured 0.76 ε at 1; the other orientation, `Gᵀ` for
/// `G`, 1.5 ε at most: on two dofs one rotation does it, so this case
/// cannot tell the orientations apart).
#[test]
fn the_oracles_modes_are_relatively_accurate_on_two_masses() {
    for ratio in [1.0, 1e4, 1e6, 1e8, 1e12] {
        for light in [false, true] {
            let (m2, k1, k2) = if light { (1.0 / ratio, 1.0, 1.0) } else { (1.0, 1.0, ratio) };
            // Dof 0 (m₂) joined by k₂ to dof 1 (mass 1), tied by k₁ to the wall.
            let chain = Chain { masses: vec![m2, 1.0], links: vec![k2], wall: k1 };
            let modes = chain.modes(light);
            let (a, d, b2) = (k2 / m2, k1 + k2, k2 * k2 / m2);
            let tr = a + d;
            let disc = (a - d).powi(2) + 4.0 * b2;
            let hi = 0.5 * (tr + disc.sqrt());
            let lo = k1 * k2 / m2 / hi;
            let err = ((modes.k[0] - lo) / lo).abs().max(((modes.k[1] - hi) / hi).abs());
            assert!(err <= 8.0 * f64::EPSILON, "ratio {ratio}, light {light}: {:?} against ({lo}, {hi}): {err:e}", modes.k);
            // Φᵀ M Φ = I and Φᵀ K Φ = diag(ω²), each to ε relative.
            for i in 0..2 {
                for j in 0..2 {
                    let mm: f64 = (0..2).map(|r| modes.phi[r][i] * chain.masses[r] * modes.phi[r][j]).sum();
                    assert!((mm - f64::from(u8::from(i == j))).abs() <= 8.0 * f64::EPSILON, "ratio {ratio}, light {light}: ΦᵀMΦ[{i}][{j}] = {mm}");
                }
            }
        }
    }
}

/// A Duhamel mode against closed forms: `x'' + x = sin(0.97 t)` from rest
/// (`(sin 0.97t − 0.97 sin t)/(1 − 0.97²)`) and exact resonance `x'' + x =
/// sin t` (`(sin t − t cos t)/2`), to 1e-14 at `t = 10` and 50.
#[test]
fn the_oracles_duhamel_integral_meets_its_closed_forms() {
    for t in [10.0, 50.0] {
        let (x, dx) = mode(1.0, 0.0, (0.0, 0.0), 0.0, t, 0.0, &[(1.0, 0.97)]);
        let (xe, dxe) = (((0.97 * t).sin() - 0.97 * t.sin()) / (1.0 - 0.97 * 0.97), 0.97 * ((0.97 * t).cos() - t.cos()) / (1.0 - 0.97 * 0.97));
        assert!((x - xe).abs() <= 1e-13 && (dx - dxe).abs() <= 1e-13, "t = {t}: ({x}, {dx}) against ({xe}, {dxe})");
        let (x, dx) = mode(1.0, 0.0, (0.0, 0.0), 0.0, t, 0.0, &[(1.0, 1.0)]);
        let (xe, dxe) = (0.5 * (t.sin() - t * t.cos()), 0.5 * t * t.sin());
        assert!((x - xe).abs() <= 1e-13 && (dx - dxe).abs() <= 1e-13, "t = {t}: ({x}, {dx}) against ({xe}, {dxe})");
    }
}

/// `ω_i²`'s first-order change under a relative change `ε` of every entry
/// of `M` and `K` (the inputs' componentwise condition, from the oracle's
/// modes): `ε Σ |φ_r| (|K_rs| + ω² |M_rs|) |φ_s|`. A stiff link's
/// `K₁₁ = R + 1` rounded by `ε R` moves the soft `ω²` by `~ε R`; a light
/// mass's graded `M^{-1/2} K M^{-1/2}` does not (Demmel–Veselić).
fn conditions(dy: &Dynamics, modes: &Modes) -> Vec<f64> {
    let n = dy.n();
    (0..n)
        .map(|i| {
            let p = |r: usize| modes.phi[r][i].abs();
            f64::EPSILON * (0..n).flat_map(|r| (0..n).map(move |s| (r, s))).map(|(r, s)| p(r) * (dy.stiffness.get(r, s).abs() + modes.k[i] * dy.mass.get(r, s).abs()) * p(s)).sum::<f64>()
        })
        .collect()
}

/// A state's tolerance over `τ`: each mode's phase error `ω τ` times its
/// frequency's relative condition (and `ε`, the oracle's own), ten times.
fn tolerance(modes: &Modes, conds: &[f64], tau: f64) -> f64 {
    1e-13 + 10.0 * tau * modes.k.iter().zip(conds).map(|(k, c)| k.sqrt() * (f64::EPSILON + c / k)).fold(0.0, f64::max)
}

/// [`spread`]'s chain at stiffness or mass spreads 1e4 to 1e8: the flow's
/// `ω²` within 4 times the inputs' componentwise condition of the
/// oracle's ([`conditions`]); its state after `τ` (`q`, `v` over the
/// state's scale, energy by springs over the energy) within [`tolerance`].
/// Measured (`τ` = 10): a light mass, every `ω²` within 2 ε and the state
/// within 4.1e-15 (`q`), 8.9e-11 (`v`, the 1e8 chain's stiff mode: `ω τ ε`
/// = 1.6e-11 of its speed); a stiff link, the soft `ω²` off by 2.0e-11
/// (1e6) and 3.5e-8 (1e8) relatively, 0.1 of its condition `ε R`, the
/// state by 3.5e-13 and 1.1e-10, the energy by 3.5e-14.
#[test]
fn a_chain_with_a_large_spread_is_the_oracle_to_its_inputs_condition() {
    let mut rows = Vec::new();
    for ratio in [1e4, 1e6, 1e8] {
        for light in [false, true] {
            let chain = Chain::spread(ratio, light);
            let modes = chain.modes(light);
            let dy = spread(ratio, light, 0);
            let (m, k) = chain.matrices();
            assert!((0..4).all(|i| (0..4).all(|j| m.get(i, j) == dy.mass.get(i, j) && k.get(i, j) == dy.stiffness.get(i, j))));
            let flow = ModalFlow::new(&dy).unwrap();
            let conds = conditions(&dy, &modes);
            let worst = (0..4).map(|i| (flow.omega2()[i] - modes.k[i]).abs() / conds[i]).fold(0.0, f64::max);
            assert!(worst <= 4.0, "ratio {ratio}, light {light}: ω² {:?} against {:?}, {worst} conditions", flow.omega2(), modes.k);
            for tau in [0.01, 1.0, 10.0] {
                let (eq, ev, ee) = errors(&flow, &dy, &chain, &modes, (0.0, 0.0), 0.3, tau);
                let tol = tolerance(&modes, &conds, tau);
                rows.push((ratio, light, tau, worst, eq, ev, ee, tol));
            }
        }
    }
    assert!(rows.iter().all(|r| r.4.max(r.5).max(r.6) <= r.7), "(ratio, light, τ, ω² off in conditions, q, v, energy, tolerance): {rows:?}");
}

/// Every impact of [`spread`]'s run (contact on the stiff or the soft
/// side, e = 0.8 and 1) replayed on the oracle: event times `|gap|/|v|`
/// and impact speeds within [`tolerance`] over `t = 10` (÷ 0.05, the
/// slowest impact). Measured: a light mass within 4.6e-15 s and 2.8e-15
/// in speed at every spread; a stiff link 1.0e-11 s (1e4), 6.6e-11 s
/// (1e6) and 1.3e-7 s (1e8), speeds 5.0e-12, 2.7e-11, 4.6e-8: the soft
/// frequencies' `ε R` over the run (4e-8 × 0.36 × 10).
#[test]
fn a_chains_impacts_at_a_large_spread_replay_on_the_oracle() {
    let mut rows = Vec::new();
    for ratio in [1e4, 1e6, 1e8] {
        for light in [false, true] {
            let chain = Chain::spread(ratio, light);
            let modes = chain.modes(light);
            for contact in [0, 2] {
                let dy = spread(ratio, light, contact);
                let tol = tolerance(&modes, &conditions(&dy, &modes), 10.0) / 0.05;
                let flight = |t: f64, q: &[f64], v: &[f64], tau: f64| oracle(&dy, &modes, (0.0, 0.0), t, q, v, tau);
                for e in [0.8, 1.0] {
                    let (ok, _, dt, dv, gap) = replay(&dy, &[0.0; 4], &[-0.3, -0.2, -0.1, 0.0], e, 10.0, &flight);
                    rows.push((ratio, light, contact, e, ok && gap > 0.0, dt, dv, tol));
                }
            }
        }
    }
    assert!(rows.iter().all(|r| r.4 && r.5.max(r.6) <= r.7), "(ratio, light, contact, e, ok, t off, v off, tolerance): {rows:?}");
}

/// Four unit masses, unit springs, a wall (or none: a free chain).
fn chain4(wall: f64) -> Chain {
    Chain { masses: vec![1.0; 4], links: vec![1.0; 3], wall }
}

/// A chain forced at `Ω = ω_j (1 + r)` of each elastic mode `j`, `r` from
/// 0 to ±1e-3, under Rayleigh damping that leaves another mode free: a free
/// chain under `C = b K` (its rigid mode undamped, under a steady load that
/// grows as `t²`), and a walled chain under `C = b (K − ω₁² M)` (its lowest
/// mode undamped, the others damped), `b` = 1e-14, 1e-6, 1e-2; and
/// undamped. Against the oracle (the resonant harmonic by its Duhamel
/// integral): `q`, `v` over the state's scale and the energy within 1e-12
/// (`τ` = 1 and 10).
#[test]
fn chains_forced_near_one_of_their_modes_resonance_are_the_oracle() {
    let mut worst = (0.0f64, String::new());
    for wall in [0.0, 1.0] {
        let chain = chain4(wall);
        let modes = chain.modes(true);
        let (m, k) = chain.matrices();
        for b in [0.0, 1e-14, 1e-6, 1e-2] {
            let a = if wall > 0.0 { -b * modes.k[0] } else { 0.0 };
            for j in usize::from(wall == 0.0)..4 {
                for r in [0.0, 1e-12, -1e-12, 1e-9, 1e-6, -1e-6, 1e-3] {
                    let mut dy = Dynamics::new(m.clone(), k.clone(), vec![0.2, 0.0, 0.0, -0.1], vec![]);
                    if b > 0.0 {
                        dy.damping = Some(crate::events_common::rayleigh(&m, &k, a, b));
                    }
                    dy.forcing = vec![Forcing { shape: vec![0.0, 0.4, 0.0, 1.0], time: TimeProfile::Sine { amplitude: 1.0, omega: modes.k[j].sqrt() * (1.0 + r) } }];
                    let flow = ModalFlow::new(&dy).unwrap();
                    for tau in [1.0, 10.0] {
                        let (eq, ev, ee) = errors(&flow, &dy, &chain, &modes, (a, b), 0.3, tau);
                        let err = eq.max(ev).max(ee);
                        if err > worst.0 {
                            worst = (err, format!("wall {wall}, b = {b}, mode {j}, r = {r}, τ = {tau}: q {eq:e}, v {ev:e}, energy {ee:e}"));
                        }
                    }
                }
            }
        }
    }
    assert!(worst.0 <= 1e-12, "{}", worst.1);
    eprintln!("{}", worst.1);
}
