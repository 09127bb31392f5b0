//! Paoli–Schatzman with a massless contact node (docs/theory.md §4.3) against
//! a dense, slow transcription of its equations written here, step by step
//! (issue 35: the growth of `ps-e0.5` with the modified masses on the
//! bouncing bar, docs/schemes.md).
//!
//! The transcription solves each step as a linear system with Gaussian
//! elimination, not as the code's projection on the factor of `M + β dt² K`:
//!
//! ```text
//! rows i ≠ c:  M (U⁺ − 2U + U⁻) + dt² K (β U⁺ + (1 − 2β) U + β U⁻) = dt² F
//! row c:       (K U⁺)_c = F_c − λ⁺                 (equilibrium at t_{n+1})
//! u_c⁺ ≥ (1 + e) g − e u_c⁻,  λ⁺ ≤ 0,  complementary
//! ```
//!
//! first without the constraint, then, if the node ends below its bound, with
//! `u_c⁺` fixed on it (column c moved to the right-hand side) and `λ⁺` read
//! from row c. The code's levels `U⁻`, `U` are the input of each step; its
//! `U⁺` and `λ⁺` are compared with the transcription's.

use crate::common::*;
use crate::stabilized::solve as gauss;
use signorini_fem::BarMass;
use signorini_schemes::{Initial, SchemeSpec};

/// One step of the scheme with a massless contact node `c`, bound `g`,
/// written from docs/theory.md §4.3: returns `(U⁺, λ⁺)`.
#[allow(clippy::too_many_arguments)]
fn dense_step(m: &Dense, k: &Dense, f: &[f64], c: usize, g: f64, beta: f64, e: f64, dt: f64, um: &[f64], u: &[f64]) -> (Vec<f64>, f64) {
    let n = u.len();
    let dt2 = dt * dt;
    let mut a = zeros(n);
    let mut b = vec![0.0; n];
    for i in 0..n {
        if i == c {
            a[i].clone_from(&k[i]);
            b[i] = f[i];
            continue;
        }
        for j in 0..n {
            a[i][j] = m[i][j] + beta * dt2 * k[i][j];
            b[i] += m[i][j] * (2.0 * u[j] - um[j]) - dt2 * k[i][j] * ((1.0 - 2.0 * beta) * u[j] + beta * um[j]);
        }
        b[i] += dt2 * f[i];
    }
    let free = gauss(a.clone(), b.clone());
    let lo = (1.0 + e) * g - e * um[c];
    if free[c] >= lo {
        return (free, 0.0);
    }
    // u_c⁺ = lo: drop row c and column c, move the column to the right-hand side.
    let keep: Vec<usize> = (0..n).filter(|&i| i != c).collect();
    let ar: Dense = keep.iter().map(|&i| keep.iter().map(|&j| a[i][j]).collect()).collect();
    let br: Vec<f64> = keep.iter().map(|&i| b[i] - a[i][c] * lo).collect();
    let mut up = vec![lo; n];
    for (&i, x) in keep.iter().zip(gauss(ar, br)) {
        up[i] = x;
    }
    let lam = f[c] - mul(k, &up)[c];
    (up, lam)
}

/// Every massless-node mass, e ∈ {0, ½, 1}, β ∈ {¼, 0.4}, a free bar of 6
/// elements falling under gravity onto the obstacle (many impacts and
/// releases, the node also held): each step of the code equals the dense
/// transcription to 1e-12 (U⁺ relative to max |U|, λ⁺ relative to
/// max(|λ|, |F|)).
#[test]
fn massless_node_steps_follow_the_dense_transcription() {
    let (m, body, gap) = (6, -2.0, 0.01);
    let mut worst = 0.0f64;
    for mass in [BarMass::Mod, BarMass::Mod2, BarMass::Mod3, BarMass::Transfer, BarMass::Singular] {
        for e in [0.0, 0.5, 1.0] {
            for (beta, ratio) in [(0.25, 2.0), (0.25, 0.5), (0.4, 1.0)] {
                let (dy, o) = bar_scene(m, mass, true, gap, body, None);
                let n = o.n();
                // Released at rest, 0.05 above the obstacle; a wiggle so that
                // the nodes do not move together.
                let init = Initial { u: (0..n).map(|i| gap + 0.05 + 0.01 * (i as f64).sin()).collect(), v: vec![0.0; n] };
                let dt = 1.0 / (m as f64 * ratio);
                let spec = SchemeSpec::ps(e, beta);
                let mut s = spec.build(dy, dt, &init).unwrap();
                let traj = record(s.as_mut(), 600);
                let lams = traj.lambdas(0);
                let (mut held, mut penetrated) = (0, 0);
                for l in traj.first.max(1)..traj.last() {
                    let um = if l == 1 { &init.u[..] } else { traj.at(l - 1) };
                    let (want, lam) = dense_step(&o.m, &o.k, &o.load, 0, gap, beta, e, dt, um, traj.at(l));
                    let got = traj.at(l + 1);
                    let scale = max_abs(got).max(max_abs(&want));
                    let err = max_abs(&sub(got, &want)) / scale;
                    let lam_got = lams[l + 1].unwrap();
                    let lam_err = (lam_got - lam).abs() / lam.abs().max(max_abs(&o.load)).max(lam_got.abs());
                    worst = worst.max(err).max(lam_err);
                    assert!(err <= 1e-12, "{mass} {spec} dt {dt}: U at level {} off the transcription by {err:e}", l + 1);
                    assert!(lam_err <= 1e-12, "{mass} {spec} dt {dt}: λ at level {} = {lam_got}, the transcription's {lam}", l + 1);
                    held += usize::from(lam != 0.0);
                    penetrated += usize::from(want[0] < gap);
                }
                assert!(held > 20, "{mass} {spec}: {held} held levels");
                // With e > 0 the bound on the weighted mean lets the node below the obstacle.
                assert_eq!(penetrated > 0, e > 0.0, "{mass} {spec}: {penetrated} levels below the obstacle");
            }
        }
    }
    println!("worst relative difference to the dense transcription: {worst:.1e}");
}
