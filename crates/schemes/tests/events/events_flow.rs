//! The exact flow against an independent reference: the matrix exponential
//! of the first-order system, augmented with the load's own states (a
//! constant 1 and, per harmonic, `sin` and `cos` of its phase), computed
//! here by scaling and squaring of a Taylor series — the solution of the
//! same linear ODE with nothing in common with the modal formulas.

use crate::events_common as common;

use faer::linalg::solvers::DenseSolveCore;
use faer::Mat;
use proptest::prelude::*;
use signorini_fem::SymBand;
use signorini_schemes::events::{critical_plane, repeated_line, repeated_planes, slow_plane, EventsError, ModalFlow};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};

type Dense = Vec<Vec<f64>>;

fn zeros(n: usize) -> Dense {
    vec![vec![0.0; n]; n]
}

fn mul(a: &Dense, b: &Dense) -> Dense {
    let n = a.len();
    let mut c = zeros(n);
    for i in 0..n {
        for k in 0..n {
            let aik = a[i][k];
            if aik != 0.0 {
                for j in 0..n {
                    c[i][j] += aik * b[k][j];
                }
            }
        }
    }
    c
}

/// `exp(a)` by scaling and squaring a degree-20 Taylor series.
fn expm(a: &Dense) -> Dense {
    let n = a.len();
    let norm = a.iter().map(|r| r.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max);
    let s = if norm > 0.25 { (norm / 0.25).log2().ceil() as i32 } else { 0 };
    let scaled: Dense = a.iter().map(|r| r.iter().map(|x| x / 2f64.powi(s)).collect()).collect();
    let mut e = zeros(n);
    let mut term = zeros(n);
    for i in 0..n {
        e[i][i] = 1.0;
        term[i][i] = 1.0;
    }
    for k in 1..=20 {
        term = mul(&term, &scaled);
        for i in 0..n {
            for j in 0..n {
                term[i][j] /= k as f64;
                e[i][j] += term[i][j];
            }
        }
    }
    for _ in 0..s {
        e = mul(&e, &e);
    }
    e
}

fn inverse(a: &Dense) -> Dense {
    let n = a.len();
    let mut m: Dense = a.iter().enumerate().map(|(i, r)| r.iter().copied().chain((0..n).map(|j| f64::from(u8::from(i == j)))).collect()).collect();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs())).unwrap();
        m.swap(c, p);
        let d = m[c][c];
        m[c].iter_mut().for_each(|x| *x /= d);
        for r in 0..n {
            if r != c {
                let f = m[r][c];
                let row = m[c].clone();
                m[r].iter_mut().zip(&row).for_each(|(x, y)| *x -= f * y);
            }
        }
    }
    m.into_iter().map(|r| r[n..].to_vec()).collect()
}

fn band(a: &SymBand) -> Dense {
    (0..a.n()).map(|i| (0..a.n()).map(|j| a.get(i, j)).collect()).collect()
}

/// The harmonic terms of the forcing, flattened: (shape, amplitude, Ω, phase).
fn terms(dy: &Dynamics) -> Vec<(Vec<f64>, f64, f64, f64)> {
    let mut out = Vec::new();
    for f in &dy.forcing {
        match &f.time {
            &TimeProfile::Sine { amplitude, omega } => out.push((f.shape.clone(), amplitude, omega, 0.0)),
            TimeProfile::Harmonics(h) => out.extend(h.iter().map(|t| (f.shape.clone(), t.amplitude, t.omega, t.phase))),
            TimeProfile::Series(_) => unreachable!(),
        }
    }
    out
}

/// The reference: `z(t0 + τ) = exp(A τ) z(t0)` for the augmented state.
pub(crate) fn reference(dy: &Dynamics, t0: f64, q0: &[f64], v0: &[f64], tau: f64) -> (Vec<f64>, Vec<f64>) {
    let n = dy.n();
    let h = terms(dy);
    let dim = 2 * n + 1 + 2 * h.len();
    let minv = inverse(&band(&dy.mass));
    let k = band(&dy.stiffness);
    let c = dy.damping.as_ref().map_or_else(|| zeros(n), band);
    let mut a = zeros(dim);
    for i in 0..n {
        a[i][n + i] = 1.0;
        for j in 0..n {
            a[n + i][j] = -(0..n).map(|r| minv[i][r] * k[r][j]).sum::<f64>();
            a[n + i][n + j] = -(0..n).map(|r| minv[i][r] * c[r][j]).sum::<f64>();
        }
        a[n + i][2 * n] = (0..n).map(|r| minv[i][r] * dy.load[r]).sum();
        for (j, (shape, amp, _, _)) in h.iter().enumerate() {
            a[n + i][2 * n + 1 + 2 * j] = amp * (0..n).map(|r| minv[i][r] * shape[r]).sum::<f64>();
        }
    }
    for (j, (_, _, w, _)) in h.iter().enumerate() {
        let (s, co) = (2 * n + 1 + 2 * j, 2 * n + 2 + 2 * j);
        a[s][co] = *w;
        a[co][s] = -*w;
    }
    let at: Dense = a.iter().map(|r| r.iter().map(|x| x * tau).collect()).collect();
    let e = expm(&at);
    let mut z0 = vec![0.0; dim];
    z0[..n].copy_from_slice(q0);
    z0[n..2 * n].copy_from_slice(v0);
    z0[2 * n] = 1.0;
    for (j, (_, _, w, p)) in h.iter().enumerate() {
        z0[2 * n + 1 + 2 * j] = (w * t0 + p).sin();
        z0[2 * n + 2 + 2 * j] = (w * t0 + p).cos();
    }
    let z: Vec<f64> = e.iter().map(|r| r.iter().zip(&z0).map(|(x, y)| x * y).sum()).collect();
    (z[..n].to_vec(), z[n..2 * n].to_vec())
}

/// A chain of `n` masses (consistent P1-like mass), unit springs, tied to a
/// wall at the far end unless `free`.
fn chain(n: usize, free: bool) -> Dynamics {
    let (m, k) = common::chain_matrices(n, free);
    Dynamics::new(m, k, (0..n).map(|i| 0.1 * (i as f64 - 1.0)).collect(), vec![Contact::new(0, Bounds::obstacle(-1e9), false)])
}

fn check(dy: &Dynamics, t0: f64, tau: f64, tol: f64) {
    let err = flow_error(dy, t0, tau);
    assert!(err <= tol, "t0 = {t0}, τ = {tau}: the flow {err:e} of the state's scale from the reference");
}

/// [`scaled_error`] of the problem's own flow.
pub(crate) fn flow_error(dy: &Dynamics, t0: f64, tau: f64) -> f64 {
    scaled_error(&ModalFlow::new(dy).unwrap(), dy, t0, tau)
}

/// The flow's largest error against [`reference`] over `τ` from `t0`, over
/// the state's scale (at least 1), from [`check`]'s initial state.
fn scaled_error(flow: &ModalFlow, dy: &Dynamics, t0: f64, tau: f64) -> f64 {
    let n = dy.n();
    let q0: Vec<f64> = (0..n).map(|i| 0.3 * (i as f64 + 1.0).sin()).collect();
    let v0: Vec<f64> = (0..n).map(|i| 0.2 * (2.0 * i as f64 + 0.5).cos()).collect();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    flow.advance(t0, &q0, &v0, tau, &mut q, &mut v);
    let (qr, vr) = reference(dy, t0, &q0, &v0, tau);
    let scale = qr.iter().chain(&vr).fold(1.0f64, |a, x| a.max(x.abs()));
    q.iter().zip(&qr).chain(v.iter().zip(&vr)).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale
}

fn forced(mut dy: Dynamics) -> Dynamics {
    let n = dy.n();
    dy.forcing = vec![
        Forcing { shape: (0..n).map(|i| 1.0 / (i as f64 + 1.0)).collect(), time: TimeProfile::Sine { amplitude: 0.7, omega: 1.3 } },
        Forcing {
            shape: (0..n).map(|i| if i == n - 1 { 1.0 } else { 0.0 }).collect(),
            time: TimeProfile::harmonics(vec![Harmonic { amplitude: 0.4, omega: 2.9, phase: 0.3 }, Harmonic { amplitude: -0.2, omega: 0.45, phase: 1.1 }]).unwrap(),
        },
    ];
    dy
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Undamped and Rayleigh-damped (some modes overdamped), with a steady
    /// load and harmonic forcing, at random start times and horizons.
    #[test]
    fn free_flight_is_the_matrix_exponential(t0 in 0.0f64..20.0, tau in 0.01f64..6.0, a in 0.0f64..0.3, b in 0.0f64..0.6, damped: bool, free: bool) {
        let mut dy = forced(chain(5, free));
        if damped {
            dy.damping = Some(dy.mass.lin_comb(a, &dy.stiffness, b));
        }
        check(&dy, t0, tau, 1e-12);
    }
}

/// A chain with a damper at one dof and one between two dofs (no modes of
/// `(K, M)` diagonalise it: the first-order form), loaded and forced,
/// against the exponential at random start times and horizons.
fn nonclassical(mut dy: Dynamics, at: usize, d: f64, link: f64) -> Dynamics {
    let n = dy.n();
    let mut c = dy.mass.lin_comb(0.01, &dy.stiffness, 0.005);
    c.set(at, at, c.get(at, at) + d);
    let j = (at + 1) % n;
    let (lo, hi) = (at.min(j), at.max(j));
    if lo != hi && hi - lo <= 1 {
        c.set(lo, lo, c.get(lo, lo) + link);
        c.set(hi, hi, c.get(hi, hi) + link);
        c.set(hi, lo, c.get(hi, lo) - link);
    }
    dy.damping = Some(c);
    dy
}

// The tolerance, measured on the code as it is (each plane's vector chosen
// by `pair_score`, flow.rs): over 10⁶ samples of this property (t0, τ, the
// dashpot's dof, d and link drawn uniformly as here) the flow is within
// 1.03e-12 of the state's scale of the Taylor exponential; 1493 samples
// above 1e-13, 2 above 1e-12, none above 2e-12. On the worst 8 of the
// first 525 000 (1.03e-12 … 4.2e-13) a 50-digit
// exponential (mpmath) agrees with the Taylor one to 5.4e-14 and with the
// flow to 4.3e-13 … 1.01e-12: the flow's error. They are all near a
// critically damped mode (d ≈ 1.4–1.76 with link ≈ 0.53–0.96 on a clamped
// chain, d ≈ 0.85–1.5 on a free one): a real pair within 0.004–0.07 of
// each other, or a complex one of ω = 0.07, whose eigenvectors are nearly
// parallel, so the plane they span (or, when ascending pairing splits the
// near pair, the two planes) is known to ε over their angle; `T`'s
// condition there is 3e2–8e3. The choice of the plane's vector is not the
// cause: choosing by the sine alone (hcap's 240 000 samples, worst 5.8e-13)
// gives the same errors within 20 % and the same condition on these 8
// (and is refused, condition 1.9e16, on one of them). So 2e-12 stays: twice
// the worst of 10⁶, the tail above 1e-12 at 2e-6 per sample (1e-4 per
// 48-case run even if all were above 2e-12). Before each mode's plane took
// its best-conditioned vector the flow was off by up to 3.9e-11 (1.7e-10
// once: the proptest then failed at its 1e-10).
proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn nonclassical_damping_is_the_matrix_exponential(t0 in 0.0f64..20.0, tau in 0.01f64..6.0, at in 0usize..5, d in 0.05f64..3.0, link in 0.0f64..1.0, free: bool) {
        let dy = nonclassical(forced(chain(5, free)), at, d, link);
        let flow = ModalFlow::new(&dy).unwrap();
        prop_assert!(!flow.classical());
        check(&dy, t0, tau, 2e-12);
    }
}

/// The worst of those samples before the fix: a free chain whose rigid
/// translation a weak dashpot (`d = 0.06` at dof 0) decays at `c = 0.025`.
/// The first-order basis took `x_b = u₁ + u₂` from the pair's two nearly
/// parallel eigenvectors (`λ = −2e-14` and `−0.025`), with `x_a = c u₁`
/// parallel to it within `c/2`: `T`'s condition was 6.3e4 and the flow off
/// the exponential by 3.9e-11 of the state (the 50-digit exponential:
/// 3.91e-11, the Taylor one within 3.9e-14 of it); with the plane's
/// best-conditioned vector the condition is 33 and the error 1e-14.
#[test]
fn a_weakly_damped_rigid_pair_keeps_its_digits() {
    let dy = nonclassical(forced(chain(5, true)), 0, 0.06152056541736281, 0.7810990945979267);
    check(&dy, 2.552356792404289, 4.625333610268269, 1e-13);
}

/// Stiffness-proportional damping overdamps the high modes: `e^{−ατ} cosh(βτ)`
/// with `βτ` beyond 710 overflowed to NaN before it was evaluated as a sum
/// of decaying exponentials.
#[test]
fn heavily_overdamped_modes_stay_finite() {
    let mut dy = forced(chain(5, false));
    dy.damping = Some(dy.mass.lin_comb(0.0, &dy.stiffness, 40.0));
    for tau in [0.5, 6.0, 40.0] {
        check(&dy, 0.7, tau, 1e-10);
    }
}

/// Resonance: an undamped mode driven at its own frequency (the secular
/// solution), against the exponential.
#[test]
fn a_mode_driven_at_its_frequency_grows_secularly() {
    let mut dy = chain(4, false);
    let w = ModalFlow::new(&dy).unwrap().omega2()[1].sqrt();
    dy.forcing = vec![Forcing { shape: vec![0.0, 0.0, 1.0, 0.0], time: TimeProfile::Sine { amplitude: 1.0, omega: w } }];
    for tau in [0.5, 3.0, 17.0] {
        check(&dy, 1.3, tau, 1e-11);
    }
}

/// A free-free chain has a rigid mode (ω = 0): the steady load
/// accelerates it, `t²/2` exactly.
#[test]
fn a_rigid_mode_integrates_the_load() {
    let dy = chain(4, true);
    assert!(ModalFlow::new(&dy).unwrap().omega2()[0].abs() < 1e-12);
    for tau in [0.2, 4.0] {
        check(&dy, 0.0, tau, 1e-11);
    }
}

#[test]
fn refusals_are_typed() {
    let mut dy = chain(3, false);
    dy.mass.set(0, 0, 0.0);
    dy.mass.set(1, 0, 0.0);
    assert!(matches!(ModalFlow::new(&dy), Err(EventsError::MassNotDefinite)));
    // A NaN or an infinite entry of M, K or C, refused by name (before, a NaN
    // in K or C was taken: the flow's folds of the largest entry drop it).
    for (matrix, (i, j), value) in [("stiffness", (1, 0), f64::NAN), ("damping", (2, 2), f64::NAN), ("mass", (1, 1), f64::INFINITY), ("stiffness", (0, 0), f64::NEG_INFINITY)] {
        let mut dy = chain(3, false);
        dy.damping = Some(dy.mass.lin_comb(0.1, &dy.stiffness, 0.01));
        match matrix {
            "mass" => dy.mass.set(i, j, value),
            "stiffness" => dy.stiffness.set(i, j, value),
            _ => dy.damping.as_mut().unwrap().set(i, j, value),
        }
        let r = ModalFlow::new(&dy);
        assert!(matches!(&r, Err(EventsError::NotFinite { matrix: m, row, col, .. }) if *m == matrix && ((*row, *col) == (i, j) || (*row, *col) == (j, i))), "{matrix}: {r:?}");
        let text = r.unwrap_err().to_string();
        assert!(text.starts_with(matrix) && text.ends_with("allowed: finite"), "{text}");
        let r = signorini_schemes::events::EventDriven::new(&dy, 0.0, &[0.0; 3], &[0.0; 3], 0.5);
        assert!(matches!(&r, Err(EventsError::NotFinite { .. })), "{matrix}: the run {:?}", r.err());
    }
    // Two equal modes (K = M = I) and C with eigenvalues 2 and 3: the
    // first one critically damped, a defective eigenvalue −1 of the
    // first-order form (C's off-diagonal makes the identity modes see it as
    // non-classical). Refused before (`condition` above 1e8); its plane
    // from `(A + 1)²`, now taken and exact.
    let (mut m, mut k, mut c) = (SymBand::zeros(2, 1), SymBand::zeros(2, 1), SymBand::zeros(2, 1));
    for i in 0..2 {
        m.set(i, i, 1.0);
        k.set(i, i, 1.0);
        c.set(i, i, 2.5);
    }
    c.set(1, 0, 0.5);
    let mut dy = Dynamics::new(m, k, vec![0.0; 2], vec![Contact::new(0, Bounds::obstacle(-1.0), false)]);
    dy.damping = Some(c);
    let r = ModalFlow::new(&dy);
    assert!(r.is_ok(), "{r:?}");
    check(&forced(dy), 0.4, 3.0, 1e-13);
    // `repeated_planes` refuses a defective complex pair (`±iω` twice with
    // one eigenvector, `[J I; 0 J]`), whose message names the condition
    // (the flow then takes its chain, `defective_chain`).
    let w = 1.7;
    let jordan = Mat::from_fn(4, 4, |i, j| match (i / 2 == j / 2, i % 2, j % 2) {
        (true, 0, 1) => w,
        (true, 1, 0) => -w,
        (false, _, _) if j == i + 2 => 1.0,
        _ => 0.0,
    });
    let r = repeated_planes(&jordan, w * w, 0.0, 2);
    assert!(matches!(r, Err(EventsError::Defective { condition }) if condition == f64::INFINITY), "{r:?}");
    let text = r.unwrap_err().to_string();
    assert!(text.starts_with("damping:") && text.contains("condition number") && text.contains("up to 1e8") && text.contains("is inf,"), "{text}");
    // Through the flow that pair is taken now, as a chain
    // (a_defective_complex_pair_is_exact); a basis above the bound is
    // still refused, its message naming the condition and the bound.
    let text = EventsError::Defective { condition: 4.9e8 }.to_string();
    assert!(text.contains("is 4.9e8,") && text.contains("up to 1e8"), "{text}");
    let mut dy = chain(3, false);
    dy.forcing = vec![Forcing { shape: vec![1.0; 3], time: TimeProfile::series(vec![0.0, 1.0], vec![0.0, 1.0]).unwrap() }];
    assert!(matches!(ModalFlow::new(&dy), Err(EventsError::Profile { index: 0 })));
}

/// A free chain whose damping leaves its rigid mode undamped (a dashpot
/// between dofs 0 and 1, no mass-proportional part), under a steady load
/// and harmonics: either refused as defective, or its flow is the
/// exponential. With 2 dofs the dashpot is `d K` (classical): the rigid
/// mode's modal damping was round-off (1e-17) and the steady load's
/// particular solution `f t / c` put the chain at 9e15; now it is 0 and
/// the 40 runs match to 8.4e-13. With 3 and 4 dofs (first-order form)
/// the defective eigenvalue 0 comes out as a pair `±1.5e-8` with nearly
/// parallel eigenvectors; 48 of the 80 were taken with a well-conditioned
/// (15) but wrong basis, off the exponential by up to 0.93 (a run on two
/// stops cycled release → impact at 1e-16 → accumulation → release at one
/// instant: `NoProgress`, found by the sampling hunt of docs/schemes.md);
/// then all 80 were refused; now all 80 are taken, the pair's plane
/// `{(e, 0), (0, e)}` from `A²` (flow.rs, `slow_plane`; docs/theory.md §9.1).
#[test]
fn a_free_chain_with_an_undamped_rigid_mode_is_refused_or_exact() {
    let (mut taken, mut refused) = (0, 0);
    for n in [2, 3, 4] {
        for i in 0..40 {
            let d = 0.02 + 0.05 * f64::from(i);
            let mut dy = forced(chain(n, true));
            let mut c = SymBand::zeros(n, 1);
            c.set(0, 0, d);
            c.set(1, 1, d);
            c.set(1, 0, -d);
            dy.damping = Some(c);
            match ModalFlow::new(&dy) {
                Err(EventsError::Defective { .. }) => refused += 1,
                Err(e) => panic!("n = {n}, d = {d}: {e}"),
                Ok(_) => {
                    taken += 1;
                    for (t0, tau) in [(0.0, 0.7), (3.1, 4.0)] {
                        check(&dy, t0, tau, 1e-10);
                    }
                }
            }
        }
    }
    assert_eq!(taken + refused, 120);
}

/// Two blocks with a shared undamped frequency, one damped: the part
/// {0, 1, 2} of a uniform free consistent chain held at its node 3 (its
/// mode (1, 0, −1) at ω² = 3 has a node at the dashpot on dof 1) and the
/// lone end node 4 (k/m = 1/(1/3) = 3). The first-order form has `±i√3`
/// twice, with two independent eigenvectors (not defective): the flow
/// takes a real basis of the 4-dimensional invariant subspace (docs/theory.md
/// §9.1) and matches the exponential; a detuned lone node (mass 0.35)
/// separates the eigenvalues.
fn shared_frequency(lone_mass: f64, d: f64) -> Dynamics {
    let (mut m, mut k) = (SymBand::zeros(4, 1), SymBand::zeros(4, 1));
    for (i, (mi, ki)) in [(1.0 / 3.0, 1.0), (2.0 / 3.0, 2.0), (2.0 / 3.0, 2.0), (lone_mass, 1.0)].into_iter().enumerate() {
        m.set(i, i, mi);
        k.set(i, i, ki);
    }
    for i in 1..3 {
        m.set(i, i - 1, 1.0 / 6.0);
        k.set(i, i - 1, -1.0);
    }
    let mut c = SymBand::zeros(4, 1);
    c.set(1, 1, d);
    let mut dy = Dynamics::new(m, k, vec![0.1, -0.05, 0.2, -0.1], vec![Contact::new(0, Bounds::obstacle(-1e9), false)]);
    dy.damping = Some(c);
    forced(dy)
}

#[test]
fn a_repeated_undamped_frequency_across_blocks_is_exact() {
    for d in [0.05, 0.4, 1.0, 2.5] {
        for lone in [1.0 / 3.0, 0.35] {
            let dy = shared_frequency(lone, d);
            let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("lone mass {lone}, d = {d}: {e}"));
            assert!(!flow.classical());
            for (t0, tau) in [(0.0, 0.7), (3.1, 4.0), (1.3, 11.0)] {
                check(&dy, t0, tau, 1e-12);
            }
        }
    }
}

/// `J = [0 ω; −ω 0]` has `±iω`: `[J 0; 0 J]` has it twice with a
/// 4-dimensional real invariant subspace (two planes, each invariant:
/// `A² x = −ω² x`, together a basis), `[J I; 0 J]` twice with only one
/// eigenvector (a Jordan block): refused.
#[test]
fn a_repeated_pair_gives_independent_planes_unless_defective() {
    let w = 1.7;
    let block = |jordan: bool| {
        Mat::from_fn(4, 4, |i, j| match (i / 2 == j / 2, i % 2, j % 2) {
            (true, 0, 1) => w,
            (true, 1, 0) => -w,
            (false, _, _) if jordan && j == i + 2 => 1.0,
            _ => 0.0,
        })
    };
    let a = block(false);
    let xs = repeated_planes(&a, w * w, 0.0, 2).unwrap();
    let mut t = Mat::<f64>::zeros(4, 4);
    for (p, x) in xs.iter().enumerate() {
        // A x by hand: rows (ω x₁, −ω x₀, ω x₃, −ω x₂).
        let ax = [w * x[1], -w * x[0], w * x[3], -w * x[2]];
        let a2x = [w * ax[1], -w * ax[0], w * ax[3], -w * ax[2]];
        for r in 0..4 {
            assert!((a2x[r] + w * w * x[r]).abs() <= 1e-13, "plane {p} not invariant");
            t[(r, 2 * p)] = x[r];
            t[(r, 2 * p + 1)] = ax[r];
        }
    }
    let tinv = t.full_piv_lu().inverse();
    let norm = |x: &Mat<f64>| (0..4).map(|i| (0..4).map(|j| x[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max);
    assert!(norm(&t) * norm(&tinv) <= 100.0, "planes not independent: condition {}", norm(&t) * norm(&tinv));
    assert!(matches!(repeated_planes(&block(true), w * w, 0.0, 2), Err(EventsError::Defective { .. })));
}

/// A block of two lumped masses `m` between walls (springs 1, 1, 1) with a
/// dashpot `d` at its first mass and `2d` at its second (not proportional
/// to `M` or `K`: non-classical), its time stretched by `s` (mass `m/s²`,
/// damping `d/s`: every eigenvalue of its first-order form times `s`).
fn overdamped_block(m: f64, d: f64, s: f64) -> (Dense, Dense, Dense) {
    let mass = vec![vec![m / (s * s), 0.0], vec![0.0, m / (s * s)]];
    let stiffness = vec![vec![2.0, -1.0], vec![-1.0, 2.0]];
    let damping = vec![vec![d / s, 0.0], vec![0.0, 2.0 * d / s]];
    (mass, stiffness, damping)
}

/// The decoupled blocks (block-diagonal `M`, `K`, `C`), loaded and forced:
/// a chain split by held dofs into parts, as an active set of the
/// event-driven run sees it. With `mix`, seen through the dofs `p = Q q`
/// (`Q` orthogonal): `Qᵀ M Q`, `Qᵀ K Q`, `Qᵀ C Q`, the first-order form
/// `diag(Q, Q)ᵀ A diag(Q, Q)`, with the same eigenvalues but no longer
/// block-diagonal (the eigen-decomposition sees no blocks).
fn blocks(parts: &[(Dense, Dense, Dense)], mix: Option<&Dense>) -> Dynamics {
    let n: usize = parts.iter().map(|p| p.0.len()).sum();
    let (mut m, mut k, mut c) = (zeros(n), zeros(n), zeros(n));
    let mut at = 0;
    for (pm, pk, pc) in parts {
        for i in 0..pm.len() {
            for j in 0..pm.len() {
                m[at + i][at + j] = pm[i][j];
                k[at + i][at + j] = pk[i][j];
                c[at + i][at + j] = pc[i][j];
            }
        }
        at += pm.len();
    }
    if let Some(q) = mix {
        let qt: Dense = (0..n).map(|i| (0..n).map(|j| q[j][i]).collect()).collect();
        let congruence = |a: &Dense| mul(&qt, &mul(a, q));
        (m, k, c) = (congruence(&m), congruence(&k), congruence(&c));
    }
    let band = |a: &Dense| {
        let mut b = SymBand::zeros(n, n - 1);
        for i in 0..n {
            for j in 0..=i {
                b.set(i, j, 0.5 * (a[i][j] + a[j][i]));
            }
        }
        b
    };
    let mut dy = Dynamics::new(band(&m), band(&k), (0..n).map(|i| 0.1 * (i as f64 - 1.0)).collect(), vec![Contact::new(0, Bounds::obstacle(-1e9), false)]);
    dy.damping = Some(band(&c));
    forced(dy)
}

/// A fixed mixing of four dofs: the reflection `I − 2 w wᵀ/(wᵀw)`,
/// `w = (1, 2, −1, 3)` (orthogonal, so the mixed first-order form is as
/// well conditioned as the blocks', and dense).
fn mixing() -> Dense {
    let w = [1.0, 2.0, -1.0, 3.0];
    let ww: f64 = w.iter().map(|x| x * x).sum();
    (0..4).map(|i| (0..4).map(|j| f64::from(u8::from(i == j)) - 2.0 * w[i] * w[j] / ww).collect()).collect()
}

/// The eigenvalues of a block's first-order form, by faer (the test's set-up,
/// not its oracle): all real (overdamped), ascending.
fn block_eigenvalues(part: &(Dense, Dense, Dense)) -> Vec<f64> {
    let (m, k, c) = part;
    let minv = inverse(m);
    let a = Mat::from_fn(4, 4, |i, j| match (i < 2, j < 2) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - 2 == i)),
        (false, true) => -(0..2).map(|r| minv[i - 2][r] * k[r][j]).sum::<f64>(),
        (false, false) => -(0..2).map(|r| minv[i - 2][r] * c[r][j - 2]).sum::<f64>(),
    });
    let s = a.eigenvalues().unwrap();
    assert!(s.iter().all(|l| l.im == 0.0), "not overdamped: {s:?}");
    let mut l: Vec<f64> = s.iter().map(|l| l.re).collect();
    l.sort_by(f64::total_cmp);
    l
}

/// Two identical overdamped blocks: each real eigenvalue of the
/// first-order form twice, with two independent eigenvectors (not
/// defective). The ascending pairs put both copies of one eigenvalue into
/// one plane `{x, A x}` (a line): refused before (`condition inf`); round-off
/// may also split a copy pair into `λ ± iε` (`m = 1/2`, `d = 4`: `ε` of
/// 1e-16), and seen through a mixing of the dofs the decomposition's
/// vectors are any basis of the eigenspace. Now each eigenspace's
/// orthonormal basis, each copy paired with another eigenvalue
/// (docs/theory.md §9.1): the exponential to 1e-12 over several dampings,
/// masses and stretches, decoupled and mixed.
#[test]
fn identical_overdamped_blocks_are_exact() {
    let cases = [0.3, 1.0, 3.0].into_iter().flat_map(|m| [6.0, 12.0, 50.0].map(|f| (m, f * f64::sqrt(m))));
    for (m, d) in cases.chain([(0.5, 4.0)]) {
        for mix in [None, Some(mixing())] {
            let part = overdamped_block(m, d, 1.0);
            block_eigenvalues(&part);
            let dy = blocks(&[part.clone(), part], mix.as_ref());
            let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("m = {m}, d = {d}, mixed {}: {e}", mix.is_some()));
            assert!(!flow.classical());
            for (t0, tau) in [(0.0, 0.7), (3.1, 4.0), (1.3, 11.0)] {
                check(&dy, t0, tau, 1e-12);
            }
        }
    }
}

/// The tolerance's edge: the second block stretched by `1 + ε` splits each
/// repeated eigenvalue `λ` into `λ, (1 + ε) λ`. Inside (`ε = 5e-13`, every
/// split within 1e-12 of the spectral radius): one repeated eigenvalue,
/// its mean and its eigenspace. Just outside (every split 2e-12 of the
/// radius or more): simple eigenvalues, but closer than 1e-8 of the
/// radius, so not paired with each other. Between (`ε = 2e-12`: the
/// fastest pair split by 2e-12 of the radius, the slower ones within
/// 1e-12): both kinds at once. All the exponential to 1e-12.
#[test]
fn a_nearly_repeated_real_eigenvalue_is_exact_either_side_of_the_tolerance() {
    for (m, d) in [(1.0, 4.0), (0.5, 10.0)] {
        let l = block_eigenvalues(&overdamped_block(m, d, 1.0));
        let (radius, slowest) = (l[0].abs(), l[3].abs());
        for eps in [5e-13, 2e-12, 2e-12 * radius / slowest] {
            let dy = blocks(&[overdamped_block(m, d, 1.0), overdamped_block(m, d, 1.0 + eps)], None);
            let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("m = {m}, d = {d}, ε = {eps}: {e}"));
            assert!(!flow.classical());
            for (t0, tau) in [(0.0, 0.7), (3.1, 4.0), (1.3, 11.0)] {
                check(&dy, t0, tau, 1e-12);
            }
        }
    }
}

/// `repeated_line`: a real eigenvalue twice with two eigenvectors (`λ I`
/// on a plane, seen through a non-orthogonal change of basis) gives an
/// orthonormal basis of its eigenspace, each vector checked by `A x = λ x`
/// written here; `λ` twice with one eigenvector (the real Jordan block
/// `[λ 1; 0 λ]`) is refused.
#[test]
fn a_repeated_real_eigenvalue_gives_its_eigenspace_unless_defective() {
    let (l, mu, nu) = (-1.3, -0.4, -7.0);
    // S (unit upper triangular, far from orthogonal) and its inverse.
    let s = [[1.0, 3.0, -2.0, 0.5], [0.0, 1.0, 4.0, 1.0], [0.0, 0.0, 1.0, -3.0], [0.0, 0.0, 0.0, 1.0]];
    let sinv = inverse(&s.iter().map(|r| r.to_vec()).collect());
    let similar = |jordan: bool| {
        let d = [[l, if jordan { 1.0 } else { 0.0 }, 0.0, 0.0], [0.0, l, 0.0, 0.0], [0.0, 0.0, mu, 0.0], [0.0, 0.0, 0.0, nu]];
        Mat::from_fn(4, 4, |i, j| (0..4).map(|p| (0..4).map(|q| s[i][p] * d[p][q] * sinv[q][j]).sum::<f64>()).sum::<f64>())
    };
    let a = similar(false);
    let xs = repeated_line(&a, l, 2).unwrap();
    assert_eq!(xs.len(), 2);
    for (p, x) in xs.iter().enumerate() {
        for r in 0..4 {
            let ax: f64 = (0..4).map(|c| a[(r, c)] * x[c]).sum();
            assert!((ax - l * x[r]).abs() <= 1e-12, "vector {p} not an eigenvector: row {r}");
        }
        for (q, y) in xs.iter().enumerate() {
            let dot: f64 = x.iter().zip(y).map(|(u, v)| u * v).sum();
            assert!((dot - f64::from(u8::from(p == q))).abs() <= 1e-12, "not orthonormal: {p}, {q}: {dot}");
        }
    }
    assert!(matches!(repeated_line(&similar(true), l, 2), Err(EventsError::Defective { .. })));
}

/// The plane's best vector chosen by its columns' sine alone took, in a
/// rigid pair (`λ₁ ≈ 0`), a direction near the other eigenvector, whose
/// `x_a = −λ₁ x` is round-off: `T`'s condition 3e16 and the run refused
/// (a proptest draw: a free chain, a dashpot of 1.17 at dof 1).
#[test]
fn a_rigid_pair_under_a_strong_dashpot_is_not_refused() {
    let dy = nonclassical(forced(chain(5, true)), 1, 1.167048062702446, 0.7011207647557629);
    check(&dy, 0.0, 0.01, 2e-12);
    check(&dy, 3.0, 4.0, 2e-12);
}

/// A damping matrix of round-off size against the stiffness (a 1e-17
/// dashpot: `|φ_iᵀ C φ_j| <= 1e-15 ω_max`) is none (flow.rs,
/// `ROUND_OFF_DAMPING`): the undamped flow to 1e-15 of the state, and the
/// exponential of the damped system to 1e-12. Before, it took the
/// first-order form: refused on a free chain (its rigid pair defective to
/// round-off, `T`'s condition 1.8e16–2.4e16, for 1e-17 and 1e-15
/// dashpots), 1.1e-14–1.9e-14 off the undamped flow on a clamped one.
#[test]
fn a_round_off_dashpot_is_the_undamped_flow() {
    for free in [false, true] {
        let undamped = forced(chain(5, free));
        let n = undamped.n();
        let q0: Vec<f64> = (0..n).map(|i| 0.3 * (i as f64 + 1.0).sin()).collect();
        let v0: Vec<f64> = (0..n).map(|i| 0.2 * (2.0 * i as f64 + 0.5).cos()).collect();
        for (at, size) in [(0, 1e-17), (2, 1e-17), (4, 1e-16)] {
            let mut dy = undamped.clone();
            let mut c = SymBand::zeros(n, 1);
            c.set(at, at, size);
            dy.damping = Some(c);
            let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("free {free}, a dashpot {size:e} at {at}: {e}"));
            check(&dy, 1.3, 4.0, 1e-12);
            let plain = ModalFlow::new(&undamped).unwrap();
            let (mut q, mut v, mut qu, mut vu) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            for (t0, tau) in [(0.0, 0.3), (1.3, 4.0), (7.0, 11.0)] {
                flow.advance(t0, &q0, &v0, tau, &mut q, &mut v);
                plain.advance(t0, &q0, &v0, tau, &mut qu, &mut vu);
                let scale = qu.iter().chain(&vu).fold(1.0f64, |m, x| m.max(x.abs()));
                for (a, b) in q.iter().zip(&qu).chain(v.iter().zip(&vu)) {
                    assert!((a - b).abs() <= 1e-15 * scale, "free {free}, a dashpot {size:e} at {at}, t0 = {t0}, τ = {tau}: {a} against the undamped {b}");
                }
            }
        }
    }
}

/// The same with contacts: a free chain falling onto a stop with a 1e-17
/// dashpot runs the undamped run's events (refused before).
#[test]
fn a_round_off_dashpot_runs_the_undamped_events() {
    let (m, k) = common::chain_matrices(4, true);
    let undamped = Dynamics::new(m, k, vec![-0.1; 4], vec![Contact::new(0, Bounds::obstacle(-0.05), false)]);
    let mut c = SymBand::zeros(4, 1);
    c.set(1, 1, 1e-17);
    let damped = undamped.clone().with_damping(Some(c));
    let run = |dy: &Dynamics| {
        let mut r = signorini_schemes::events::EventDriven::new(dy, 0.0, &[0.0; 4], &[-0.5, -0.3, -0.4, -0.2], 0.5).unwrap();
        r.run_until(3.0, 10_000).unwrap();
        (r.events().to_vec(), r.state())
    };
    let ((a, (_, qa, va)), (b, (_, qb, vb))) = (run(&damped), run(&undamped));
    assert!(a.len() == b.len() && a.len() > 3, "{a:?}\n{b:?}");
    for (x, y) in a.iter().zip(&b) {
        assert!(x.kind == y.kind && (x.t - y.t).abs() <= 1e-15 * y.t.max(1.0) && (x.velocity_before - y.velocity_before).abs() <= 1e-15, "{x:?} against {y:?}");
    }
    for (x, y) in qa.iter().zip(&qb).chain(va.iter().zip(&vb)) {
        assert!((x - y).abs() <= 1e-14, "{x} against the undamped {y}");
    }
}

/// A weak dashpot on a free chain under a steady load: the rigid pair
/// (`λ = 0` and `λ ≈ −c`) is a mode `η'' + c η' = g₀` whose particular
/// solution `g₀ τ/c` cancelled against its homogeneous part, `g₀ (1 −
/// e^{−cτ})/c²`, to leave `g₀ τ²/2`: `ε/(cτ)` of the motion lost (flow.rs
/// takes the φ-functions now, `g₀ τ² φ₂(−cτ)`, docs/theory.md §9.1). A
/// 5-dof free chain (load 0.3 more at dof 0), a dashpot `c` at dof 2 (the
/// first-order form) or `C = c M` (classical, its rigid mode damped by
/// `c`), from `t0 = 1.3` over `τ = 0.1, 1, 4, 10`, against the Taylor
/// exponential. Measured, the error of the state against a 50-digit
/// exponential (mpmath, the same matrices' f64 entries): the flow within
/// 3.9e-15 (c ≤ 1e-8, both forms), the Taylor one within 3.9e-14 (τ =
/// 10: its squarings): so 1e-13 of the state's scale. At `c = 1e-3` the
/// dashpot's flow was 2.6e-13 off (τ = 10; as before the fix, so not the
/// load's cancellation: its plane, now 3.5e-15) and takes 1e-12. Before the fix (plant:
/// the old form) the dashpot's worst over τ was 1.1e-3, 4.8e-5, 5.0e-6,
/// 1.4e-6, 1.4e-8 at c = 1e-13, 1e-12, 1e-11, 1e-10, 1e-8 (`C = c M`:
/// see theory §9.1). `C = 0.3 M` and `3 M` reach `|cτ|` of 3 and 30
/// (the φ-functions' recurrence beyond the series): 2e-14 and 8.4e-15
/// (plants: the recurrence for every `z`, 8.4e-4 at the 1e-13 dashpot; the
/// series for every `z`, 1.7e10 at `C = 3 M`, τ = 10). A 1e-6 dashpot
/// at dof 2 was refused (condition reported infinite: the rigid pair's
/// eigenvalues split by round-off into a near-defective pair); with the
/// pair's slow plane (flow.rs, `slow_plane`) it is 4.1e-15 off the
/// 50-digit exponential and takes 1e-13, as every `c <= 1e-6` (all of them
/// now on that plane: 1.6e-15–3.8e-15).
#[test]
fn a_weak_dashpot_keeps_the_steady_loads_digits() {
    let n = 5;
    let mut worst = Vec::new();
    for classical in [false, true] {
        for c in [1e-13, 1e-12, 1e-11, 1e-10, 1e-8, 1e-6, 1e-3, 0.3, 3.0] {
            let mut dy = chain(n, true);
            dy.load[0] += 0.3;
            if c > 0.1 && !classical {
                continue;
            } else if classical {
                dy.damping = Some(dy.mass.lin_comb(c, &dy.stiffness, 0.0));
            } else {
                let mut d = SymBand::zeros(n, 1);
                d.set(2, 2, c);
                dy.damping = Some(d);
            }
            let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("c = {c:e}: {e}"));
            assert_eq!(flow.classical(), classical);
            let tol = if classical || c <= 1e-6 { 1e-13 } else { 1e-12 };
            for tau in [0.1, 1.0, 4.0, 10.0] {
                let err = scaled_error(&flow, &dy, 1.3, tau);
                if !(err <= tol) {
                    worst.push(format!("{} c = {c:e}, τ = {tau}: {err:.1e} > {tol:e}", if classical { "C = c M" } else { "dashpot" }));
                }
            }
        }
    }
    assert!(worst.is_empty(), "off the exponential:\n{}", worst.join("\n"));
}

/// A weak dashpot on a free chain (docs/theory.md §9.1): the rigid pair
/// `λ = 0, −c_eff` of the first-order form has two eigenvectors parallel
/// within `~c_eff`, and the plane they spanned was known to `ε/c_eff`
/// only: of the 72 chains below with `c <= 1e-6` (3 to 5 dofs, the
/// dashpot at each dof), 42 were refused (`condition inf`: the plane not
/// invariant to 1e-11) and the rest taken up to 3.1e-11 off (`c = 1e-11`
/// at dof 0 of 4 and 5 dofs, the velocity), `c = 1e-4` up to 6.1e-11 and
/// `1e-3` up to 7.6e-12. The plane is now the null space of `(A − λ₁)(A −
/// λ₂)` (flow.rs, `slow_plane`): all 96 taken, within 5.4e-15 of the state's
/// scale of a 50-digit exponential (mpmath, the steady load, every τ),
/// where the Taylor exponential is within 5.2e-14 of it (τ = 10, its
/// squarings): so 1e-13, about twice the oracle's own error; with the
/// harmonics of `forced` too (the Taylor one only: 6.7e-14 at worst).
/// Plants: the old path (no slow pair) refuses 84 of the 192 flows and is
/// up to 6.1e-11 off; the slow pair's plane spanned by its two
/// eigenvectors (its vector chosen as before) refuses 80, the rest up to
/// 5.8e-11 off.
#[test]
fn a_weak_dashpot_on_a_free_chain_is_taken_and_exact() {
    let mut bad = Vec::new();
    for n in [3usize, 4, 5] {
        for at in 0..n {
            for c in [1e-13, 1e-12, 1e-11, 1e-10, 1e-8, 1e-6, 1e-4, 1e-3] {
                for loads in [false, true] {
                    let mut dy = if loads { forced(chain(n, true)) } else { chain(n, true) };
                    dy.load[0] += 0.3;
                    let mut d = SymBand::zeros(n, 1);
                    d.set(at, at, c);
                    dy.damping = Some(d);
                    let flow = match ModalFlow::new(&dy) {
                        Ok(flow) => flow,
                        Err(e) => {
                            bad.push(format!("n = {n}, dof {at}, c = {c:e}: {e}"));
                            continue;
                        }
                    };
                    assert!(!flow.classical());
                    for tau in [0.1, 1.0, 4.0, 10.0] {
                        let err = scaled_error(&flow, &dy, 1.3, tau);
                        if !(err <= 1e-13) {
                            bad.push(format!("n = {n}, dof {at}, c = {c:e}, harmonics {loads}, τ = {tau}: {err:.1e}"));
                        }
                    }
                }
            }
        }
    }
    assert!(bad.is_empty(), "{} off the exponential or refused:\n{}", bad.len(), bad.join("\n"));
}

/// `slow_plane` on a matrix whose slow plane is known by construction:
/// `A = S D S⁻¹` with `D` the blocks `[0 1; 0 −c]` (a rigid pair: `λ = 0,
/// −c`, its eigenvectors `S e₁` and `S (e₁ − c e₂)` parallel within `~c`)
/// and `[−0.3 2; −2 −0.3]`, `S` far from orthogonal. The vector `x` it
/// returns lies in `span(S e₁, S e₂)` (the last two entries of `S⁻¹ x`
/// vanish, to 1e-13 of its first two), and spans an invariant plane with
/// `x_a = (A + c) x`: `A x_a = 0` (`k = 0`) to 1e-13 of `|A| |x_a|`, the two
/// columns at least 30° apart; `c = 0` is the Jordan block, whose plane
/// is exact too. Plant: the null space of `A²` (the pair's `c A` left
/// out of `Q`) is off the plane by `~c`: fails at `c = 1e-6` and `1e-3`.
#[test]
fn a_slow_pairs_plane_is_found_without_its_eigenvectors() {
    let s = [[1.0, 3.0, -2.0, 0.5], [0.0, 1.0, 4.0, 1.0], [0.0, 0.0, 1.0, -3.0], [0.0, 0.0, 0.0, 1.0]];
    let sinv = inverse(&s.iter().map(|r| r.to_vec()).collect());
    for c in [0.0, 1e-13, 1e-10, 1e-6, 1e-3] {
        let d = [[0.0, 1.0, 0.0, 0.0], [0.0, -c, 0.0, 0.0], [0.0, 0.0, -0.3, 2.0], [0.0, 0.0, -2.0, -0.3]];
        let a = Mat::from_fn(4, 4, |i, j| (0..4).map(|p| (0..4).map(|q| s[i][p] * d[p][q] * sinv[q][j]).sum::<f64>()).sum::<f64>());
        let x = slow_plane(&a, 0.0, c).unwrap_or_else(|| panic!("c = {c:e}: no plane"));
        let y: Vec<f64> = (0..4).map(|i| (0..4).map(|j| sinv[i][j] * x[j]).sum()).collect();
        let inside = y[0].abs().max(y[1].abs());
        assert!(y[2].abs().max(y[3].abs()) <= 1e-13 * inside, "c = {c:e}: off the plane, S⁻¹ x = {y:?}");
        let xa: Vec<f64> = (0..4).map(|i| (0..4).map(|j| a[(i, j)] * x[j]).sum::<f64>() + c * x[i]).collect();
        let axa: Vec<f64> = (0..4).map(|i| (0..4).map(|j| a[(i, j)] * xa[j]).sum()).collect();
        let norm = |v: &[f64]| v.iter().map(|p| p * p).sum::<f64>().sqrt();
        let anorm = (0..4).map(|i| (0..4).map(|j| a[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max);
        assert!(norm(&axa) <= 1e-13 * anorm * norm(&xa), "c = {c:e}: A x_a = {axa:?}");
        let cos = xa.iter().zip(&x).map(|(p, q)| p * q).sum::<f64>() / (norm(&xa) * norm(&x));
        assert!(cos.abs() <= 0.87, "c = {c:e}: columns within 30°: cos {cos}");
    }
}

/// `∫ q` over a flight of a damped free mode (`k = 0 < c`: a lone damped
/// mass, and a free chain's rigid pair under a dashpot, the first-order
/// form), taken as a held force's impulse is (`ModalFlow::position_integral`),
/// against a 50-digit exponential of the state augmented with the
/// integral (`oracles/position_integral.py`, mpmath; `cτ` from 1e-15 to
/// 10, a steady load and a harmonic). The mode's integral was
/// `e₀ τ + e₀' (τ + expm1(−cτ)/c)/c + g₀ τ²/(2c)`, `e₀' = η₀' − g₀/c`:
/// its terms cancel to `~ε/(cτ)` of them: off by up to 4.6e9 of the
/// integral's scale (`max(|∫ q|, τ)`) at `c = 1e-13`, 4e-3 at `1e-7`,
/// 4e-11 at `1e-3`; now the φ-form `e₀ τ + τ² (e₀' φ₂ + τ (g₀ φ₃ + b τ
/// φ₄))` (docs/theory.md §9.1): within 3.6e-16 (the lone mass) and 3.0e-14
/// (the chain's first-order form, the shortest flight, every `c` alike:
/// 3.2e-15 at `c = 1` before and after). Asserts 1e-13. Plant: the `1/c`
/// form fails 35 of the 48.
#[test]
fn a_damped_free_modes_integral_keeps_its_digits() {
    let text = include_str!("../oracles/position_integral.csv");
    let mut bad = Vec::new();
    let mut worst = 0.0f64;
    for line in text.lines().skip(1) {
        let cols: Vec<&str> = line.split(',').collect();
        let (name, c, tau): (&str, f64, f64) = (cols[0], cols[1].parse().unwrap(), cols[2].parse().unwrap());
        let want: Vec<f64> = cols[3..].iter().map(|x| x.parse().unwrap()).collect();
        let sine = TimeProfile::Sine { amplitude: 0.4, omega: 1.7 };
        let (dy, q0, v0) = if name == "one" {
            let (m, k, d) = (SymBand::from_diagonal(&[1.3]), SymBand::from_diagonal(&[0.0]), SymBand::from_diagonal(&[c]));
            let mut dy = Dynamics::new(m, k, vec![0.7], vec![Contact::new(0, Bounds::obstacle(-1e9), false)]).with_damping(Some(d));
            dy.forcing = vec![Forcing { shape: vec![1.0], time: sine }];
            (dy, vec![0.3], vec![-0.2])
        } else {
            let (m, k) = common::chain_matrices(3, true);
            let mut d = SymBand::zeros(3, 1);
            d.set(0, 0, c);
            let mut dy = Dynamics::new(m, k, vec![0.2, 0.0, 0.1], vec![Contact::new(0, Bounds::obstacle(-1e9), false)]).with_damping(Some(d));
            dy.forcing = vec![Forcing { shape: vec![1.0, 0.5, 0.0], time: sine }];
            (dy, vec![0.3, -0.1, 0.25], vec![-0.2, 0.15, 0.05])
        };
        let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("{name}, c = {c:e}: {e}"));
        assert_eq!(flow.classical(), name == "one");
        let scale = want.iter().fold(tau, |a, x| a.max(x.abs()));
        let err = (0..want.len()).map(|j| (flow.position_integral(1.3, &q0, &v0, tau, j) - want[j]).abs()).fold(0.0f64, f64::max) / scale;
        worst = worst.max(err);
        if !(err <= 1e-13) {
            bad.push(format!("{name}, c = {c:e}, τ = {tau}: {err:.1e}"));
        }
    }
    assert!(bad.is_empty(), "{} integrals off the 50-digit ones (worst {worst:.1e}):\n{}", bad.len(), bad.join("\n"));
}

/// A free chain of `n` consistent masses and unit springs cut at the links
/// `cuts` (link `i` joins dofs `i − 1` and `i`; cut, it loses its spring
/// and its mass coupling): free parts, one rigid mode each, under the
/// steady load of [`chain`] and 0.3 more at dof 0.
fn cut_chain(n: usize, cuts: &[usize]) -> Dynamics {
    let (m, k) = common::cut_chain_matrices(n, cuts);
    let mut dy = Dynamics::new(m, k, (0..n).map(|i| 0.1 * (i as f64 - 1.0)).collect(), vec![Contact::new(0, Bounds::obstacle(-1e9), false)]);
    dy.load[0] += 0.3;
    dy
}

/// Two or more rigid modes at once (docs/theory.md §9.1): chains of 4–8
/// dofs cut into 2–4 free parts, under dashpots that leave the modes of
/// `(K, M)` undiagonalised (the first-order form: `2r` eigenvalues near 0),
/// against the exponential over `τ = 0.1, 1, 4, 10`, with and without
/// harmonics: one part damped (the others' rigid modes undamped, a Jordan
/// block each), every part damped (distinct decays, and equal ones on
/// mirror-identical parts), a dashpot across a cut (the parts' relative
/// motion damped, their common one not), and dashpots within parts only
/// (every rigid mode undamped); and without a dashpot, and with `C = 0.2 M`
/// (classical); `c` from 1e-13 to 0.3: 350 flows. The rigid modes are one
/// block from `K`'s null space (flow.rs, `rigid_block`): all taken, within
/// 3.0e-13 of the state's scale; asserts 1e-12. Plant: the eigenvalue
/// path (no block, as before) refuses 195 of the 350 (`condition inf` or
/// above 1e8: the undamped parts' Jordan blocks, the weak decays' parallel
/// eigenvectors) and 40 of the others' samples are off by more than
/// 1e-12 (up to 1.6e-10).
#[test]
fn several_rigid_modes_at_once_are_exact() {
    let mut bad = Vec::new();
    let mut worst = 0.0f64;
    for (n, cuts) in [(4usize, vec![2usize]), (6, vec![3]), (6, vec![2, 4]), (8, vec![3, 6]), (8, vec![2, 4, 6])] {
        // Each part's first and last dof.
        let parts: Vec<(usize, usize)> = std::iter::once(0).chain(cuts.iter().copied()).zip(cuts.iter().copied().chain(std::iter::once(n))).map(|(a, b)| (a, b - 1)).collect();
        for config in ["one part", "every part", "equal", "across", "within", "none", "classical"] {
            for c in [1e-13, 1e-8, 1e-4, 1e-2, 0.3] {
                let mut d = SymBand::zeros(n, 1);
                let mut add = |i: usize, j: usize, x: f64| {
                    d.set(i, i, d.get(i, i) + x);
                    if i != j {
                        d.set(j, j, d.get(j, j) + x);
                        let (a, b) = (i.max(j), i.min(j));
                        d.set(a, b, d.get(a, b) - x);
                    }
                };
                match config {
                    "one part" => add(0, 0, c),
                    "every part" => parts.iter().enumerate().for_each(|(p, &(i, _))| add(i, i, c * (1.0 + 0.7 * p as f64))),
                    // One end of each part, alternately: equal parts are
                    // mirror images, their decays equal.
                    "equal" => parts.iter().enumerate().for_each(|(p, &(i, j))| {
                        let at = if p % 2 == 0 { i } else { j };
                        add(at, at, c);
                    }),
                    "across" => {
                        add(0, 0, c);
                        add(cuts[0] - 1, cuts[0], c);
                    }
                    "within" => add(0, 1, c),
                    _ => {}
                }
                for loads in [false, true] {
                    let mut dy = if loads { forced(cut_chain(n, &cuts)) } else { cut_chain(n, &cuts) };
                    dy.damping = match config {
                        "none" => None,
                        "classical" => Some(dy.mass.lin_comb(0.2, &dy.stiffness, 0.0)),
                        _ => Some(d.clone()),
                    };
                    let name = format!("n = {n}, cuts {cuts:?}, {config}, c = {c:e}, harmonics {loads}");
                    let flow = match ModalFlow::new(&dy) {
                        Ok(flow) => flow,
                        Err(e) => {
                            bad.push(format!("{name}: {e}"));
                            continue;
                        }
                    };
                    for tau in [0.1, 1.0, 4.0, 10.0] {
                        let err = scaled_error(&flow, &dy, 1.3, tau);
                        worst = worst.max(err);
                        if !(err <= 1e-12) {
                            bad.push(format!("{name}, τ = {tau}: {err:.1e}"));
                        }
                    }
                }
            }
        }
    }
    assert!(bad.is_empty(), "{} off the exponential or refused (worst {worst:.1e}):\n{}", bad.len(), bad.join("\n"));
}

/// A chain of two unit masses with an exactly critically damped mode under
/// a non-classical damping, by construction: springs `k₁` (wall–0), `s`
/// (0–1), `k₃` (1–wall), a dashpot `d` at dof 0 (`C = d e₀e₀ᵀ`, which the
/// modes of `(K, I)` do not diagonalise). `λ` is a root of `p(λ) =
/// det(λ² + λ C + K) = (λ² + dλ + k₁₁)(λ² + k₂₂) − s²` with eigenvector
/// `φ` iff `(λ² + λC + K) φ = 0`, and a double one with the single
/// eigenvector `φ` (a Jordan block of the first-order form) iff moreover
/// `φᵀ (2λ + C) φ = 0` (`p'(λ)` is that times `p`'s cofactor, the
/// solvability of the Jordan chain `(λ² + λC + K) ψ = −(2λ + C) φ`). With
/// `λ = −a`, `φ = (1, r)`: the second gives `d = 2a (1 + r²)`, the first
/// `k₁₁ + r k₁₂ = a² − a d` … written out, `k₁₁ = a² (1 + 2r²) + r s`,
/// `k₂₂ = s/r − a²` (`k₁₂ = −s`). Then `p(λ) = (λ + a)² (λ² + bλ + e)`
/// with `b = d − 2a`, `e = (k₁₁ k₂₂ − s²)/a²`: the critical mode `(k, c) =
/// (a², 2a)` and an underdamped one `(e, b)`. `(a, r, s) = (1, ½, 2)`:
/// `d = 5/2`, `K = [5/2 −2; −2 3]`, exact in binary (the block exact),
/// `p = (λ + 1)² (λ² + λ/2 + 7/2)`. The dashpot scaled by `1 + η` splits
/// the double root by `~√|η|` (reals for one sign, a complex pair for
/// the other): a nearly critical mode.
fn critical_chain(a: f64, r: f64, s: f64, eta: f64) -> (Dynamics, f64, f64) {
    let d = 2.0 * a * (1.0 + r * r);
    let (k11, k22) = (a * a * (1.0 + 2.0 * r * r) + r * s, s / r - a * a);
    let (mut m, mut k, mut c) = (SymBand::zeros(2, 1), SymBand::zeros(2, 1), SymBand::zeros(2, 1));
    m.set(0, 0, 1.0);
    m.set(1, 1, 1.0);
    k.set(0, 0, k11);
    k.set(1, 1, k22);
    k.set(1, 0, -s);
    c.set(0, 0, d * (1.0 + eta));
    let e = (k11 * k22 - s * s) / (a * a);
    let mut dy = Dynamics::new(m, k, vec![0.3, -0.2], vec![Contact::new(0, Bounds::obstacle(-1e9), false)]);
    dy.damping = Some(c);
    (dy, e, d - 2.0 * a)
}

/// `p(λ)` and `p'(λ)` of [`critical_chain`] from its matrices, by the
/// determinant of `λ² M + λ C + K` (2 × 2).
fn char_poly(dy: &Dynamics, l: f64) -> (f64, f64) {
    let (m, k) = (band(&dy.mass), band(&dy.stiffness));
    let c = band(dy.damping.as_ref().unwrap());
    let q = |l: f64, i: usize, j: usize| l * l * m[i][j] + l * c[i][j] + k[i][j];
    let dq = |l: f64, i: usize, j: usize| 2.0 * l * m[i][j] + c[i][j];
    let p = q(l, 0, 0) * q(l, 1, 1) - q(l, 0, 1) * q(l, 1, 0);
    let dp = dq(l, 0, 0) * q(l, 1, 1) + q(l, 0, 0) * dq(l, 1, 1) - dq(l, 0, 1) * q(l, 1, 0) - q(l, 0, 1) * dq(l, 1, 0);
    (p, dp)
}

/// A critically damped mode of a non-classical damping (a Jordan block of
/// the first-order form, split by round-off into two nearly parallel
/// eigenvectors) was refused (`T`'s condition above 1e8); its plane from
/// `(A + c/2)²` it is exact: free, under a steady load and harmonics,
/// against the exponential. Measured: 1.2e-14, 1.6e-14, 3.9e-14 of the
/// state (`a` = 1, 0.7, 1.9, forced) over
/// these horizons (to 12: 12 to 23 e-foldings of the critical mode).
/// Plants, each failing: the old refusal (no `critical_plane`:
/// `Defective`); the plane from the eigenvectors (`x_b = u₁ + u₂`, or a
/// complex pair's `u`: refused, `condition inf`); the critical mode's `k`
/// off by 1e-6 relative (its `k` against `a²`), its `c` (2.6e-8 of the
/// state against the exponential).
#[test]
fn a_critically_damped_mode_of_a_nonclassical_damping_is_exact() {
    for (a, r, s) in [(1.0, 0.5, 2.0), (0.7, 0.3, 0.5), (1.9, 0.6, 7.0)] {
        let (dy, e, b) = critical_chain(a, r, s, 0.0);
        // The construction: `−a` a double root (to round-off of `p`'s terms).
        let (p, dp) = char_poly(&dy, -a);
        assert!(p.abs() <= 1e-14 * (1.0 + a.powi(4)) && dp.abs() <= 1e-14 * (1.0 + a.powi(3)), "a = {a}: p = {p:e}, p' = {dp:e}");
        let flow = ModalFlow::new(&dy).unwrap_or_else(|err| panic!("a = {a}, r = {r}, s = {s}: {err}"));
        assert!(!flow.classical());
        // The modes' `k`: `a²` (critical) and `e`, ascending.
        let mut want = [a * a, e];
        want.sort_by(f64::total_cmp);
        for (got, want) in flow.omega2().iter().zip(want) {
            assert!((got - want).abs() <= 1e-13 * want, "a = {a}: k {got} against {want} (b = {b})");
        }
        for damped_free in [false, true] {
            let dy = if damped_free { dy.clone() } else { forced(dy.clone()) };
            for (t0, tau) in [(0.0, 0.3), (1.3, 2.0), (4.1, 7.0), (0.6, 12.0)] {
                check(&dy, t0, tau, 1e-13);
            }
        }
    }
}

/// A nearly critical mode (the dashpot of [`critical_chain`] scaled by `1 +
/// η`, `|η|` from 1e-16 to 1e-4: the double root split by 1.3e-8 to 2e-2
/// of the spectral radius, into two reals for `η > 0` and a complex pair
/// for `η < 0`), either side of flow.rs's `NEAR_CRITICAL` (1e-2), against
/// the exponential. Measured: at most 5.9e-14 of the state (1.2e-14 to
/// 5.9e-14 over the three chains, the largest on the stiffest). Before,
/// two reals' eigenvectors: refused up to a split of ~2e-6, 3.5e-11 off at
/// 1.7e-6, 1.1e-12 at 1.7e-4, 3.3e-13 at 6e-4, 1.3e-13 at 1.7e-3, 2.2e-14
/// at 6e-3 (two reals; a complex pair's plane from its `u`, `y` was within
/// 5e-14 once taken). Plants, each failing: the threshold at 1e-4 (1.1e-12
/// at a split of 1.7e-4), at 0 (refused).
#[test]
fn a_nearly_critical_mode_is_exact_either_side_of_the_threshold() {
    for (a, r, s) in [(1.0, 0.5, 2.0), (0.7, 0.3, 0.5), (1.9, 0.6, 7.0)] {
        for sign in [1.0, -1.0] {
            for x in [0.0, 1e-16, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4] {
                let (dy, _, _) = critical_chain(a, r, s, sign * x);
                let dy = forced(dy);
                let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("a = {a}, η = {}: {e}", sign * x));
                for (t0, tau) in [(0.0, 0.3), (1.3, 2.0), (4.1, 7.0), (0.6, 12.0)] {
                    let err = scaled_error(&flow, &dy, t0, tau);
                    assert!(err <= 1e-13, "a = {a}, η = {}, t0 = {t0}, τ = {tau}: {err:e} of the state", sign * x);
                }
            }
        }
    }
}

/// `dy` on a stop under dof 0 at `lo` (`e = 0.8`, from `([0.1, 0.1],
/// [−0.8, 0.3])` to `t = 20`), run by the event-driven flow and by
/// [`exponential_impacts`]: the impacts (at least five, as many in both),
/// and the largest differences of their times, their speeds and the
/// final state.
fn on_a_stop_against_the_exponential(mut dy: Dynamics, lo: f64) -> (usize, f64, f64, f64) {
    dy.contacts = vec![Contact::new(0, Bounds::obstacle(lo), false)];
    let (q0, v0, e, t_end) = ([0.1, 0.1], [-0.8, 0.3], 0.8, 20.0);
    let mut run = signorini_schemes::events::EventDriven::new(&dy, 0.0, &q0, &v0, e).unwrap();
    run.run_until(t_end, 1000).unwrap();
    let (_, q, v) = run.state();
    let (rows, qw, vw) = exponential_impacts(&dy, lo, e, &q0, &v0, t_end, 0.01);
    let got: Vec<(f64, f64)> = run.events().iter().map(|r| (r.t, r.velocity_before)).collect();
    assert!(got.len() == rows.len() && rows.len() >= 5, "{} events against {}:\n{got:?}\n{rows:?}", got.len(), rows.len());
    let (mut dt, mut dw) = (0.0f64, 0.0f64);
    for (g, w) in got.iter().zip(&rows) {
        (dt, dw) = (dt.max((g.0 - w.0).abs()), dw.max((g.1 - w.1).abs()));
    }
    let dz = q.iter().chain(&v).zip(qw.iter().chain(&vw)).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    (rows.len(), dt, dw, dz)
}

/// An event-located exponential (written here): each flight by
/// [`reference`] from the last event, the first crossing of `q₀ = lo`
/// bracketed on a grid of `h` and bisected to round-off in time, Newton's
/// law `v⁺ = v⁻ − (1 + e) v₀⁻ M⁻¹e₀/(M⁻¹)₀₀` there, the contact put on
/// its bound. Impacts only (no chatter within `t_end`): the impacts' `(t,
/// v₀⁻)` and the state at `t_end`.
fn exponential_impacts(dy: &Dynamics, lo: f64, e: f64, q0: &[f64], v0: &[f64], t_end: f64, h: f64) -> (Vec<(f64, f64)>, Vec<f64>, Vec<f64>) {
    let minv = inverse(&band(&dy.mass));
    let (mut t, mut q, mut v) = (0.0, q0.to_vec(), v0.to_vec());
    let mut rows = Vec::new();
    loop {
        let mut hit = None;
        let mut s = 0.0;
        while t + s < t_end {
            let next = (s + h).min(t_end - t);
            if reference(dy, t, &q, &v, next).0[0] < lo {
                hit = Some((s, next));
                break;
            }
            s = next;
        }
        let Some((mut a, mut b)) = hit else {
            let (qe, ve) = reference(dy, t, &q, &v, t_end - t);
            return (rows, qe, ve);
        };
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            if mid <= a || mid >= b {
                break;
            }
            if reference(dy, t, &q, &v, mid).0[0] < lo {
                b = mid;
            } else {
                a = mid;
            }
        }
        let (qi, mut vi) = reference(dy, t, &q, &v, b);
        let w = vi[0];
        let p = -(1.0 + e) * w / minv[0][0];
        for (x, row) in vi.iter_mut().zip(&minv) {
            *x += row[0] * p;
        }
        rows.push((t + b, w));
        (t, q, v) = (t + b, qi, vi);
        q[0] = lo;
    }
}

/// The critically damped chain (`a, r, s = 1, ½, 2`) under its steady
/// load and [`forced`]'s harmonics, on a stop under dof 0 (`e = 0.8`):
/// its impacts against the event-located exponential above. Measured:
/// 9 impacts to `t = 20` (the slowest at 0.061), times within 2.3e-14 s,
/// speeds within 8.2e-15, the final state within 6.4e-15. Plants, each
/// failing: the old refusal and the eigenvectors' plane (`EventDriven::new`
/// refused, `condition inf`); the critical mode's `k` off by 1e-6
/// relative (times off by 2.2e-6 s), its `c` (4.2e-6 s).
#[test]
fn a_critically_damped_chain_meets_its_stop_as_the_exponential_does() {
    let (dy, _, _) = critical_chain(1.0, 0.5, 2.0, 0.0);
    let dy = forced(dy);
    let lo = 0.05;
    let (_, dt, dw, dz) = on_a_stop_against_the_exponential(dy, lo);
    assert!(dt <= 1e-12 && dw <= 1e-12 && dz <= 1e-12, "times {dt:e} s, speeds {dw:e}, state {dz:e}");
}

/// `critical_plane` on the first-order matrix of the exactly critical
/// chain (`a, r, s = 1, ½, 2`): its plane is the Jordan chain's, written
/// out here — `λ = −1`, `φ = (1, ½)`, and `ψ = (−½, 0)` solving
/// `(λ² + λC + K) ψ = −(2λ + C) φ`: `z₁ = (φ, λφ)`, `z₂ = (ψ, φ + λψ)`,
/// `(A + 1) z₂ = z₁`. Both columns `x_b`, `(A + 2) x_b` lie in it to round-off, and they
/// are apart. On `A = diag(−1, −1, −3, −4)` (`−1` semisimple: every vector
/// of its plane an eigenvector, `x_a ∥ x_b`) it gives no plane.
#[test]
fn a_critical_plane_is_the_jordan_chains() {
    let (dy, _, _) = critical_chain(1.0, 0.5, 2.0, 0.0);
    let (k, c) = (band(&dy.stiffness), band(dy.damping.as_ref().unwrap()));
    let a = Mat::from_fn(4, 4, |i, j| match (i < 2, j < 2) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - 2 == i)),
        (false, true) => -k[i - 2][j],
        (false, false) => -c[i - 2][j - 2],
    });
    let (z1, z2) = ([1.0, 0.5, -1.0, -0.5], [-0.5, 0.0, 1.5, 0.5]);
    let x = critical_plane(&a, 1.0, 2.0, 0.0).expect("a plane");
    let xa: Vec<f64> = (0..4).map(|i| (0..4).map(|j| a[(i, j)] * x[j]).sum::<f64>() + 2.0 * x[i]).collect();
    // The distance of `y` from span{z₁, z₂} (the 2 × 2 normal equations).
    let off = |y: &[f64]| {
        let dot = |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(a, b)| a * b).sum::<f64>();
        let (g11, g12, g22) = (dot(&z1, &z1), dot(&z1, &z2), dot(&z2, &z2));
        let (b1, b2) = (dot(&z1, y), dot(&z2, y));
        let det = g11 * g22 - g12 * g12;
        let (c1, c2) = ((b1 * g22 - g12 * b2) / det, (g11 * b2 - g12 * b1) / det);
        let r = (0..4).map(|i| (y[i] - c1 * z1[i] - c2 * z2[i]).abs()).fold(0.0, f64::max);
        r / y.iter().fold(0.0f64, |m, v| m.max(v.abs()))
    };
    assert!(off(&x) <= 1e-14 && off(&xa) <= 1e-14, "x_b off the plane by {:e}, x_a by {:e}", off(&x), off(&xa));
    let dot = |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(a, b)| a * b).sum::<f64>();
    let cosine = dot(&x, &xa) / (dot(&x, &x) * dot(&xa, &xa)).sqrt();
    assert!(cosine.abs() <= 0.9, "columns within {:.1}°", cosine.acos().to_degrees());
    let semisimple = Mat::from_fn(4, 4, |i, j| if i == j { [-1.0, -1.0, -3.0, -4.0][i] } else { 0.0 });
    assert!(critical_plane(&semisimple, 1.0, 2.0, 0.0).is_none());
}

/// A triple root (a Jordan block of three, beyond a critically damped
/// pair): `M = I`, `C = diag(4, 1)`, `K = [13/3 −s; −s 2/3]`, `s² = 8/9`,
/// so that `det(λ² + λC + K) = (λ² + 4λ + 13/3)(λ² + λ + 2/3) − 8/9 =
/// (λ + 1)³ (λ + 2)`. Round-off splits it by ~`ε^{1/3}`: refused (typed)
/// or exact, never a wrong flow (measured: refused, `Defective`).
#[test]
fn a_triple_root_is_refused_or_exact() {
    let (mut m, mut k, mut c) = (SymBand::zeros(2, 1), SymBand::zeros(2, 1), SymBand::zeros(2, 1));
    m.set(0, 0, 1.0);
    m.set(1, 1, 1.0);
    k.set(0, 0, 13.0 / 3.0);
    k.set(1, 1, 2.0 / 3.0);
    k.set(1, 0, -(8.0f64 / 9.0).sqrt());
    c.set(0, 0, 4.0);
    c.set(1, 1, 1.0);
    let mut dy = Dynamics::new(m, k, vec![0.3, -0.2], vec![Contact::new(0, Bounds::obstacle(-1e9), false)]);
    dy.damping = Some(c);
    let (p, dp) = char_poly(&dy, -1.0);
    assert!(p.abs() <= 1e-14 && dp.abs() <= 1e-14, "p = {p:e}, p' = {dp:e}");
    let dy = forced(dy);
    match ModalFlow::new(&dy) {
        Err(EventsError::Defective { .. }) => println!("triple root: refused"),
        Err(e) => panic!("{e}"),
        Ok(flow) => {
            let err = [(0.0, 0.3), (1.3, 2.0), (4.1, 7.0)].iter().map(|&(t0, tau)| scaled_error(&flow, &dy, t0, tau)).fold(0.0, f64::max);
            println!("triple root: taken, {err:.1e} of the state");
            assert!(err <= 1e-10, "{err:e}");
        }
    }
}

/// `M = I`, `K = [5 −2; −2 4 + δ]`, `C = diag(2, 0)`: at `δ = 0`
/// `det(λ² + λC + K) = (λ² + λ + 4)²`, the pair `−½ ± i√15/2` twice with
/// one eigenvector (`λ² + λC + K` of rank 1 there): a defective complex
/// pair; `δ ≠ 0` splits it by `~√|δ|` into two pairs with nearly parallel
/// eigenvectors.
fn defective_pair(delta: f64) -> Dynamics {
    let (mut m, mut k, mut c) = (SymBand::zeros(2, 1), SymBand::zeros(2, 1), SymBand::zeros(2, 1));
    m.set(0, 0, 1.0);
    m.set(1, 1, 1.0);
    k.set(0, 0, 5.0);
    k.set(1, 1, 4.0 + delta);
    k.set(1, 0, -2.0);
    c.set(0, 0, 2.0);
    let mut dy = Dynamics::new(m, k, vec![0.3, -0.2], vec![Contact::new(0, Bounds::obstacle(-1e9), false)]);
    dy.damping = Some(c);
    dy
}

/// [`forced`]'s loads plus a sine at the defective pair's frequency `√15/2`.
fn forced_at_the_pair(dy: Dynamics) -> Dynamics {
    let mut dy = forced(dy);
    dy.forcing.push(Forcing { shape: vec![0.4, -0.9], time: TimeProfile::Sine { amplitude: 0.6, omega: 15f64.sqrt() / 2.0 } });
    dy
}

/// The defective pair of [`defective_pair`] (`δ = 0`) was refused (`T`'s
/// condition 4.9e8 against 1e8); its chain (flow.rs, `defective_chain`:
/// the null space of `Q₁ Q₂`, a driven mode and its driver) is exact.
/// Free, against the closed form written here: `q − K⁻¹F = e^{−t/2} [(a +
/// b t) cos ωt + (c + d t) sin ωt]` per dof (`ω = √15/2`), `a … d` from the
/// derivatives of orders 0–3 at 0 (`q'' = −C q' − K q` and its derivative);
/// forced ([`forced_at_the_pair`]: a sine at `ω` among them), against the
/// exponential. Measured: free within 8.2e-15 of the closed form, forced
/// within 1.2e-14 of the state, over `τ` to 12. Plants, each failing: the
/// old refusal (no chain: `Defective`, condition 4.9e8); the driver's
/// response dropped (`driven_delta` 0: 0.71 off the closed form); the
/// partner's threshold NEAR_CRITICAL at 0 (refused).
#[test]
fn a_defective_complex_pair_is_exact() {
    let dy = defective_pair(0.0);
    for l in [-2.0, -1.0, 0.0, 1.0, 3.0] {
        let q = l * l + l + 4.0;
        assert!((char_poly(&dy, l).0 - q * q).abs() <= 1e-13 * q * q, "p({l})");
    }
    let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("the defective pair: {e}"));
    // The closed form: derivatives of e^{μt}, t e^{μt} at 0 (μ = σ + iω).
    let (sg, w) = (-0.5, 15f64.sqrt() / 2.0);
    let mu = faer::c64::new(sg, w);
    let pow = |k: i32| if k < 0 { faer::c64::new(0.0, 0.0) } else { mu.powi(k) };
    // Rows: order j; columns: cos, t cos, sin, t sin.
    let basis: Dense = (0..4)
        .map(|j| {
            let (e, te) = (pow(j), pow(j - 1) * f64::from(j));
            vec![e.re, te.re, e.im, te.im]
        })
        .collect();
    let binv = inverse(&basis);
    let (k, c) = (band(&dy.stiffness), band(dy.damping.as_ref().unwrap()));
    let kinv = inverse(&k);
    let qs: Vec<f64> = (0..2).map(|i| (0..2).map(|j| kinv[i][j] * dy.load[j]).sum()).collect();
    let (q0, v0) = ([0.4, -0.7], [0.9, 0.25]);
    let y0: Vec<f64> = (0..2).map(|i| q0[i] - qs[i]).collect();
    let next = |a: &[f64], b: &[f64]| -> Vec<f64> { (0..2).map(|i| -(0..2).map(|j| c[i][j] * a[j] + k[i][j] * b[j]).sum::<f64>()).collect() };
    let y2 = next(&v0, &y0);
    let y3 = next(&y2, &v0);
    let mut worst = 0.0f64;
    for tau in [0.01, 0.3, 1.7, 4.0, 12.0] {
        let (mut q, mut v) = ([0.0; 2], [0.0; 2]);
        flow.advance(0.0, &q0, &v0, tau, &mut q, &mut v);
        let (ct, st, ex) = ((w * tau).cos(), (w * tau).sin(), (sg * tau).exp());
        for d in 0..2 {
            let derivs = [y0[d], v0[d], y2[d], y3[d]];
            let co: Vec<f64> = (0..4).map(|r| (0..4).map(|j| binv[r][j] * derivs[j]).sum()).collect();
            let (a, b, cc, dd) = (co[0], co[1], co[2], co[3]);
            let want_q = qs[d] + ex * ((a + b * tau) * ct + (cc + dd * tau) * st);
            // d/dt: σ times the bracket plus its own derivative.
            let want_v = ex * (sg * ((a + b * tau) * ct + (cc + dd * tau) * st) + b * ct - (a + b * tau) * w * st + dd * st + (cc + dd * tau) * w * ct);
            worst = worst.max((q[d] - want_q).abs()).max((v[d] - want_v).abs());
        }
    }
    println!("defective pair, free: {worst:.1e} against the closed form");
    assert!(worst <= 1e-14, "free: {worst:e} off the closed form");
    let dy = forced_at_the_pair(dy);
    let flow = ModalFlow::new(&dy).unwrap();
    let err = [(0.0, 0.3), (1.3, 2.0), (4.1, 7.0), (0.6, 12.0)].iter().map(|&(t0, tau)| scaled_error(&flow, &dy, t0, tau)).fold(0.0, f64::max);
    println!("defective pair, forced: {err:.1e} of the state");
    assert!(err <= 1e-13, "forced: {err:e} of the state");
}

/// [`defective_pair`] detuned by `δ` (`±1e-14 … ±1e-2`: the pairs split by
/// `~√|δ|`; up to 1e-4 the chain is taken, from 1e-3 on the two planes,
/// either side of NEAR_CRITICAL), forced ([`forced_at_the_pair`]), against
/// the exponential over `τ` to 12. Measured: at most 2.5e-14 of the state
/// (1.0e-14 to 2.5e-14). Before, the planes: refused at `δ` = 0 and 1e-14
/// (condition 4.9e8, 1.1e8), then taken and off by 7.6e-10 at 1e-12,
/// 3.4e-11 at 1e-10, 3.3e-12 at 1e-8, 5.8e-13 at 1e-6, 4.9e-14 at 1e-4.
/// Plants, each failing: no chain (refused at 1e-14); the driver's
/// response dropped (0.22 of the state up to 1e-4); the threshold at 0
/// (refused).
#[test]
fn a_nearly_defective_pair_is_exact_either_side_of_the_threshold() {
    let mut worst = 0.0f64;
    for sign in [1.0, -1.0] {
        for x in [1e-14, 1e-12, 1e-10, 1e-8, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2] {
            let dy = forced_at_the_pair(defective_pair(sign * x));
            let flow = ModalFlow::new(&dy).unwrap_or_else(|e| panic!("δ = {}: {e}", sign * x));
            let err = [(0.0, 0.3), (1.3, 2.0), (4.1, 7.0), (0.6, 12.0)].iter().map(|&(t0, tau)| scaled_error(&flow, &dy, t0, tau)).fold(0.0, f64::max);
            println!("δ = {:e}: {err:.1e} of the state", sign * x);
            worst = worst.max(err);
        }
    }
    println!("nearly defective pairs: {worst:.1e} of the state");
    assert!(worst <= 1e-13, "{worst:e} of the state");
}

/// The defective pair (forced at its frequency) on a stop under dof 0 (`e
/// = 0.8`): its impacts against the event-located exponential
/// ([`exponential_impacts`]). Measured: 12 impacts to `t = 20`, times
/// within 5.2e-14 s, speeds 1.4e-14, the final state 4.8e-14. Plants, each
/// failing: the old refusal and the threshold at 0 (`EventDriven::new`
/// refused); the driver's response dropped.
#[test]
fn a_defective_pair_meets_its_stop_as_the_exponential_does() {
    let dy = forced_at_the_pair(defective_pair(0.0));
    let lo = -0.05;
    let (n, dt, dw, dz) = on_a_stop_against_the_exponential(dy, lo);
    println!("defective pair on a stop: {n} impacts, times {dt:.1e} s, speeds {dw:.1e}, state {dz:.1e}");
    assert!(dt <= 1e-12 && dw <= 1e-12 && dz <= 1e-12, "times {dt:e} s, speeds {dw:e}, state {dz:e}");
}

/// The clamped–free P1 bar with consistent mass (`n` dofs, `h = 1/n`,
/// unit stiffness and density; transcribed here, not fem's): its modes are
/// `sin(θ_j i)` with `cos(θ_j n) = 0`, `θ_j = (2j − 1)π/(2n)`, and
/// `ω_j² = (6/h²)(1 − cos θ_j)/(2 + cos θ_j)` (`1 − cos θ = 2 sin²(θ/2)`,
/// without its cancellation). The flow's `ω²` against it, every mode, at
/// a spread of 4e5 (n = 200) and 2e6 (n = 400). The eigensolver alone
/// gives the slow ones to round-off of the largest; the refinement in
/// `(K, M)` (docs/theory.md §9.1), its products with `K` and `M` by band,
/// brings them to round-off of their own.
#[test]
fn the_long_bars_frequencies_are_its_closed_form() {
    for n in [200, 400] {
        let h = 1.0 / n as f64;
        let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
        for i in 0..n {
            let end = if i == n - 1 { 0.5 } else { 1.0 };
            m.set(i, i, end * 4.0 * h / 6.0);
            k.set(i, i, end * 2.0 / h);
            if i > 0 {
                m.set(i, i - 1, h / 6.0);
                k.set(i, i - 1, -1.0 / h);
            }
        }
        let dy = Dynamics::new(m, k, vec![0.0; n], vec![Contact::new(n - 1, Bounds::obstacle(-1.0), false)]);
        let flow = ModalFlow::new(&dy).unwrap();
        let worst = (0..n)
            .map(|j| {
                let theta = (2 * j + 1) as f64 * std::f64::consts::PI / (2 * n) as f64;
                let want = 6.0 / (h * h) * 2.0 * (0.5 * theta).sin().powi(2) / (2.0 + theta.cos());
                ((flow.omega2()[j] - want) / want).abs()
            })
            .fold(0.0, f64::max);
        eprintln!("n = {n}: ω² within {worst:e} of the closed form (relative)");
        assert!(worst <= 1e-12, "n = {n}: ω² {worst:e} off the closed form (relative)");
    }
}
