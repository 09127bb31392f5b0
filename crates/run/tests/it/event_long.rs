//! The event-driven reference over long runs, on the bars the scenes build
//! (`BarProblem::dynamics`, as `[bar]` with `scheme = "event-driven"`):
//! the redistributed mass (`mod`) and the massless node of `singular`, the
//! consistent mass with `e = 1` and `e < 1`; one stop and two.
//!
//! Oracles, none read from the code under test:
//! - **time reversal**: the conservative flow with a load even in time
//!   (none, or `A cos Ω t`) is reversible — `q̃(s) = q(−s)` solves the same
//!   problem — so the run from `(q(T), −v(T))` at `−T` to `0` ends at
//!   `(q(0), −v(0))`. Its miss is the reference's error after the forward
//!   and backward runs' events together;
//! - **the energy identity**, `½vᵀMv + ½qᵀKq` (written here from the
//!   matrices' entries): constant without forcing when every impact is
//!   elastic; with `e < 1`, lowered at each impact of contact `c` by
//!   `½ (1 − e²)(v_c⁻)² / (M⁻¹)_cc` (docs/schemes.md), `(M⁻¹)_cc` from a
//!   dense Gauss–Jordan inverse written here.

use signorini_fem::{Bar, BarMass, RightEnd, SymBand};
use signorini_run::{BarProblem, Stop};
use signorini_schemes::events::{EventDriven, EventKind};
use signorini_schemes::{Dynamics, Harmonic, TimeProfile};

/// A bar of `m` elements and unit length and speed as a scene builds it:
/// clamped at `x = 1` with a stop `u(0) >= -0.05`, or free between the
/// walls `u(0) >= -0.02`, `u(1) <= 0` of `bar-two-walls.toml`; released
/// from `u = 0` (clamped; `−0.01` between the walls, off both) at the speed
/// `v0(x)`, optionally loaded at node `m/2` by
/// `a cos(Ω t)`.
fn bar(mass: BarMass, two: bool, m: usize, load: Option<(f64, f64)>) -> (Dynamics, Vec<f64>, Vec<f64>) {
    let end = if two { RightEnd::Free } else { RightEnd::Clamped };
    let b = Bar::new(1.0, m, 1.0, end).expect("a valid bar");
    let v0 = |x: f64| if two { -0.5 } else { -0.5 * (1.0 - x) + 0.2 * (3.0 * x).sin() };
    let mut p = BarProblem::new(b, mass, -0.05, 0.0, |_| if two { -0.01 } else { 0.0 }, v0).expect("a valid problem");
    if two {
        p = p.with_stops(vec![Stop::new(0, -0.02, f64::INFINITY), Stop::new(m, f64::NEG_INFINITY, 0.0)]).expect("valid stops");
    }
    if let Some((a, w)) = load {
        let cos = TimeProfile::harmonics(vec![Harmonic { amplitude: a, omega: w, phase: std::f64::consts::FRAC_PI_2 }]).expect("a valid profile");
        p = p.with_load(Some(m / 2), cos).expect("a valid node");
    }
    let (u, v) = (p.initial.u.clone(), p.initial.v.clone());
    (p.dynamics(), u, v)
}

fn quad(a: &SymBand, x: &[f64]) -> f64 {
    let n = a.n();
    (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| x[i] * a.get(i, j) * x[j]).sum()
}

fn energy(dy: &Dynamics, q: &[f64], v: &[f64]) -> f64 {
    0.5 * quad(&dy.mass, v) + 0.5 * quad(&dy.stiffness, q)
}

/// `(M⁻¹)_cc` by Gauss–Jordan on the dense `M` with partial pivoting.
fn inverse_entry(m: &SymBand, c: usize) -> f64 {
    let n = m.n();
    let mut a: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| m.get(i, j)).chain((0..n).map(|j| f64::from(u8::from(i == j)))).collect()).collect();
    for col in 0..n {
        let p = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs())).expect("rows");
        a.swap(col, p);
        let d = a[col][col];
        a[col].iter_mut().for_each(|x| *x /= d);
        let pivot = a[col].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != col {
                let f = row[col];
                row.iter_mut().zip(&pivot).for_each(|(x, y)| *x -= f * y);
            }
        }
    }
    a[c][n + c]
}

/// Forward to `t`, reversed back to 0: `(events forward and back, the
/// miss max|Δq| over the dofs and max|Δv| over the massive ones)` (a
/// massless node's velocity is its neighbours' condensed; landing at the
/// end, it stops).
fn reversal(dy: &Dynamics, q0: &[f64], v0: &[f64], e: f64, t: f64) -> (usize, f64) {
    let mut fwd = EventDriven::new(dy, 0.0, q0, v0, e).expect("starts");
    // The start as the run settles it (a massless node's velocity is
    // condensed from the rest).
    let (_, q0, v0) = fwd.state();
    fwd.run_until(t, usize::MAX).expect("runs forward");
    let (_, q, v) = fwd.state();
    let back: Vec<f64> = v.iter().map(|x| -x).collect();
    let mut bwd = EventDriven::new(dy, -t, &q, &back, e).expect("starts back");
    bwd.run_until(0.0, usize::MAX).expect("runs back");
    let (_, q1, v1) = bwd.state();
    let dq = q1.iter().zip(&q0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    let dv = (0..v1.len()).filter(|&i| dy.mass.get(i, i) > 0.0).map(|i| (v1[i] + v0[i]).abs()).fold(0.0, f64::max);
    (fwd.events().len() + bwd.events().len(), dq.max(dv))
}

/// A case, and the horizon up to which its reversal holds to 1e-10: the
/// last rung of `2 · 1.25^k` before the measured crossing (in brackets).
type Case = (&'static str, BarMass, bool, Option<(f64, f64)>, f64, f64);

const ELASTIC: [Case; 6] = [
    // 1e-10 passed at T = 36.4 (72 events forward and back), 1e-6 at 111 (140).
    ("std, one stop, e = 1", BarMass::Std, false, None, 1.0, 23.3),
    // 11.9 (264), 14.9 (314).
    ("std, two stops, e = 1", BarMass::Std, true, None, 1.0, 7.7),
    // 18.6 (92), 45.5 (168).
    ("std, one stop, e = 1, a cos", BarMass::Std, false, Some((0.3, 1.3)), 1.0, 11.93),
    // 339 (736), 827 (1628).
    ("mod, one stop", BarMass::Mod, false, None, 0.0, 216.9),
    // 217 (392), 424 (724).
    ("singular, one stop", BarMass::Singular, false, None, 0.0, 138.8),
    // 339 (786), 1034 (5036).
    ("mod, two stops", BarMass::Mod, true, None, 0.0, 216.9),
];

/// The miss stays at round-off (<= 1e-10) up to each case's horizon, then
/// grows exponentially (a burst of decades at a slow impact, docs/theory.md
/// §9.2): the rungs printed with `--nocapture`.
#[test]
fn elastic_bars_run_back_to_their_start_until_the_impacts_amplify_round_off() {
    for (name, mass, two, load, e, horizon) in ELASTIC {
        let (dy, q0, v0) = bar(mass, two, 8, load);
        let mut t = 2.0;
        while t <= horizon {
            let (n, miss) = reversal(&dy, &q0, &v0, e, t);
            eprintln!("{name}: T = {t:.4}, events {n}, miss {miss:.3e}");
            assert!(miss <= 1e-10, "{name}: T = {t}, {n} events, the miss {miss:e}");
            t *= 1.25;
        }
    }
}

/// Energy over `10⁴` to `2·10⁴` events of the conservative bars, unforced:
/// within `2·10⁻¹⁵` per event of its start (the drift printed against the
/// events).
#[test]
fn elastic_bars_keep_their_energy_over_a_hundred_thousand_events() {
    for (name, mass, two, _, e, _) in ELASTIC.into_iter().filter(|c| c.3.is_none()) {
        let (dy, q0, v0) = bar(mass, two, 8, None);
        let mut r = EventDriven::new(&dy, 0.0, &q0, &v0, e).expect("starts");
        let (_, q, v) = r.state();
        let e0 = energy(&dy, &q, &v);
        let mut t = 16.0;
        while r.events().len() < 10_000 {
            r.run_until(t, usize::MAX).expect("runs");
            let (_, q, v) = r.state();
            let drift = (energy(&dy, &q, &v) - e0).abs() / e0;
            eprintln!("{name}: T = {t}, events {}, energy drift {drift:.3e}", r.events().len());
            // Measured: linear in the events, 1.9e-16 to 4.2e-16 per event
            // (9.2e-12 after 42 466, 2.2e-11 after 93 475; at most 8.5e-16
            // per event over the first dozen).
            assert!(drift <= 2e-15 * (1 + r.events().len()) as f64, "{name}: T = {t}, drift {drift:e}");
            t *= 4.0;
        }
    }
}

/// Each impact of the consistent mass (one stop, unforced) lowers the
/// energy by `½ ((v_c⁻)² − (v_c⁺)²) / (M⁻¹)_cc` (`½ (1 − e²)(v_c⁻)²/(M⁻¹)_cc`,
/// checked too), an accumulation likewise; nothing else changes it.
#[test]
fn each_impact_of_the_consistent_mass_loses_newtons_energy() {
    let (dy, q0, v0) = bar(BarMass::Std, false, 8, None);
    let minv = inverse_entry(&dy.mass, 0);
    for e in [0.0, 0.5, 0.9] {
        let mut r = EventDriven::new(&dy, 0.0, &q0, &v0, e).expect("starts");
        let e0 = energy(&dy, &q0, &v0);
        r.run_until(400.0, usize::MAX).expect("runs");
        let mut lost = 0.0;
        for ev in r.events() {
            match ev.kind {
                EventKind::Impact => {
                    assert!((ev.velocity_after + e * ev.velocity_before).abs() <= 1e-14 * ev.velocity_before.abs(), "e = {e}: {ev:?}");
                    lost += 0.5 * (1.0 - e * e) * ev.velocity_before * ev.velocity_before / minv;
                }
                EventKind::Accumulation => lost += 0.5 * (ev.velocity_before.powi(2) - ev.velocity_after.powi(2)) / minv,
                _ => {}
            }
        }
        let (_, q, v) = r.state();
        let residual = (energy(&dy, &q, &v) - (e0 - lost)).abs() / e0;
        eprintln!("std, e = {e}: {} events, energy lost {:.6}, residual {residual:.3e}", r.events().len(), lost / e0);
        // Measured: 1.9e-16 to 1.1e-14 (42 to 159 events).
        assert!(residual <= 1e-13, "e = {e}: residual {residual:e}");
    }
}
