//! A held contact let go by another contact's impact (docs/theory.md §9.3,
//! "A contact let go by another's event"): unit masses on unit springs,
//! each on a stop at 0, dashpots `d` from the held mass (pushed onto its
//! stop by `p`, held from the start) to the landing ones. Before the
//! landing the held mass is at rest, so each landing mass follows
//! `x'' + d x' + x = 0` (ζ = d/2, ω = √(1 − ζ²)) from `(X, 0)`: it lands
//! at `ω t_i = π − atan(ω/ζ)` at the speed `V = X e^{−ζ t_i} sin(ω t_i)/ω`.
//! The held force `p + d Σ V` jumps there to `p − d Σ e V`: below 0 the
//! held mass leaves at `t_i` (a release row, after the impact rows at
//! that instant), above 0 it stays held (no row). Oracles written here.

use crate::events_common as common;
use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind, EventRecord};
use signorini_schemes::{Bounds, Contact, Dynamics};
use std::f64::consts::PI;

const D: f64 = 0.5;

fn band(n: usize, entries: &[(usize, usize, f64)]) -> SymBand {
    let mut b = SymBand::zeros(n, 1);
    for &(i, j, v) in entries {
        b.set(i, j, v);
    }
    b
}

/// `(t_i, V)` of a mass landing from `(x0, 0)` under `x'' + d x' + x = 0`.
fn landing(x0: f64) -> (f64, f64) {
    let (z, w) = (0.5 * D, (1.0 - 0.25 * D * D).sqrt());
    let ti = (PI - (w / z).atan()) / w;
    (ti, x0 * (-z * ti).exp() * (w * ti).sin() / w)
}

/// Unit masses and springs on stops at 0, the dashpots `D` between the
/// dofs of `pairs`, the load `−p` on `held`.
fn pairs(n: usize, held: usize, p: f64, pairs: &[(usize, usize)]) -> Dynamics {
    let unit: Vec<_> = (0..n).map(|i| (i, i, 1.0)).collect();
    let mut c = SymBand::zeros(n, 1);
    for &(i, j) in pairs {
        for (a, b, v) in [(i, i, D), (j, j, D), (i.max(j), i.min(j), -D)] {
            c.set(a, b, c.get(a, b) + v);
        }
    }
    let mut f = vec![0.0; n];
    f[held] = -p;
    Dynamics::new(band(n, &unit), band(n, &unit), f, (0..n).map(|d| Contact::new(d, Bounds::obstacle(0.0), false)).collect()).with_damping(Some(c))
}

/// The rows at the landing `t_i`: the impacts of `landing` (speeds `−V`
/// to `e V`), then the release of `held` iff the force reverses.
fn check_rows(ev: &[EventRecord], ti: f64, big_v: f64, e: f64, landing: &[usize], held: Option<usize>, case: &str) {
    common::check_order(ev).unwrap();
    assert_eq!(ev.len(), landing.len() + usize::from(held.is_some()), "{case}");
    for (imp, &c) in ev.iter().zip(landing) {
        assert!(imp.kind == EventKind::Impact && imp.contact == c && (imp.t - ti).abs() <= 1e-13, "{case}");
        assert!((imp.velocity_before + big_v).abs() <= 1e-13 && (imp.velocity_after - e * big_v).abs() <= 1e-13, "{case}");
    }
    if let Some(h) = held {
        let rel = ev[landing.len()];
        assert!(rel.kind == EventKind::Release && rel.contact == h && rel.t == ev[0].t && rel.velocity_after == 0.0, "{case}");
    }
}

/// Two masses, mass 0 held by `p`, mass 1 landing from 1: for `p = 0.1`
/// (`e = 0.5, 1`) the force `p − d e V` reverses, a release row at the
/// impact's time, then `s = (x₀ + x₁)/2`, `s'' + s = −p/2`, and
/// `a = (x₀ − x₁)/2`, `a'' + 2d a' + a = −p/2`, from `(0, eV/2)`,
/// `(0, −eV/2)`, 0.3 s on within 1e-12; for `p = 0.2`, `e = 0.5` it does
/// not (`0.2 − 0.156`): one row, mass 0 still held at `t_i + 0.3`.
#[test]
fn a_held_contact_let_go_at_another_impact_logs_its_release() {
    let x0 = 1.0;
    let (ti, big_v) = landing(x0);
    let span = 0.3;
    for (p, e) in [(0.1f64, 0.5), (0.1, 1.0), (0.2, 0.5)] {
        let dy = pairs(2, 0, p, &[(0, 1)]);
        let reverses = p - D * e * big_v < 0.0;
        let case = format!("p = {p}, e = {e}: against t_i = {ti}, V = {big_v}");
        let mut r = EventDriven::new(&dy, 0.0, &[0.0, x0], &[0.0, 0.0], e).expect("starts");
        assert_eq!(r.held(), vec![(0, false)], "{case}");
        r.run_until(ti + span, 100).unwrap_or_else(|err| panic!("{case}: {err}"));
        check_rows(r.events(), ti, big_v, e, &[1], reverses.then_some(0), &format!("{case}: {:?}", r.events()));
        if !reverses {
            assert_eq!(r.held(), vec![(0, false)], "{case}");
            continue;
        }
        let w2 = (1.0 - D * D).sqrt();
        let (a0, b0) = (0.5 * p, (-0.5 * e * big_v + D * 0.5 * p) / w2);
        let after = |u: f64| -> [f64; 4] {
            let (s, ds) = (-0.5 * p * (1.0 - u.cos()) + 0.5 * e * big_v * u.sin(), -0.5 * p * u.sin() + 0.5 * e * big_v * u.cos());
            let (sn, cs, ex) = ((w2 * u).sin(), (w2 * u).cos(), (-D * u).exp());
            let a = -0.5 * p + ex * (a0 * cs + b0 * sn);
            let da = ex * ((-D * a0 + w2 * b0) * cs + (-D * b0 - w2 * a0) * sn);
            [s + a, s - a, ds + da, ds - da]
        };
        assert!((1..=300).all(|i| after(span * i as f64 / 300.0)[..2].iter().all(|x| *x > 0.0)), "the oracle's premise: both fly");
        assert!(r.held().is_empty(), "{case}");
        let (_, q, v) = r.state();
        let x = after(span);
        assert!((0..2).all(|i| (q[i] - x[i]).abs() <= 1e-12 && (v[i] - x[2 + i]).abs() <= 1e-12), "{case}: {q:?} {v:?} against {x:?}");
    }
}

/// Three masses, the middle one held by `p`, the outer two landing from 1
/// together (symmetric: one instant): the force `p − 2 d e V` reverses for
/// `p = 0.1` (`e = 0.5, 1`), both impacts then the release of the middle
/// mass at their time; for `p = 0.4`, `e = 0.5` it does not (`0.4 −
/// 0.312`): two rows, the middle mass still held. The state 0.3 s on
/// within 1e-12 of RK4 on the symmetric equations written here.
#[test]
fn two_symmetric_impacts_reached_together_let_a_held_contact_go() {
    let (ti, big_v) = landing(1.0);
    for (p, e) in [(0.1f64, 0.5), (0.1, 1.0), (0.4, 0.5)] {
        let dy = pairs(3, 1, p, &[(0, 1), (1, 2)]);
        let reverses = p - 2.0 * D * e * big_v < 0.0;
        let mut r = EventDriven::new(&dy, 0.0, &[1.0, 0.0, 1.0], &[0.0; 3], e).expect("starts");
        assert_eq!(r.held(), vec![(1, false)]);
        r.run_until(ti + 0.3, 100).unwrap_or_else(|err| panic!("p = {p}, e = {e}: {err}"));
        let case = format!("p = {p}, e = {e}: {:?} against t_i = {ti}, V = {big_v}", r.events());
        check_rows(r.events(), ti, big_v, e, &[0, 2], reverses.then_some(1), &case);
        assert_eq!(r.held(), if reverses { vec![] } else { vec![(1, false)] }, "{case}");
        // The symmetric motion after `t_i`, by RK4 (2·10⁴ steps): the held
        // mass `x` (at 0 if held), the outer ones `y` from `(0, e V)`.
        let (_, q, v) = r.state();
        let rhs = |s: [f64; 4]| {
            let [x, dx, y, dy] = s;
            let ax = if reverses { -p - x - 2.0 * D * (dx - dy) } else { 0.0 };
            [dx, ax, dy, -y - D * (dy - dx)]
        };
        let (steps, h) = (20_000, 0.3 / 20_000.0);
        let mut s = [0.0, 0.0, 0.0, e * big_v];
        for _ in 0..steps {
            let add = |a: [f64; 4], b: [f64; 4], c: f64| [a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2], a[3] + c * b[3]];
            let k1 = rhs(s);
            let k2 = rhs(add(s, k1, h / 2.0));
            let k3 = rhs(add(s, k2, h / 2.0));
            let k4 = rhs(add(s, k3, h));
            s = std::array::from_fn(|i| s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        }
        assert!(s[0] >= 0.0 && s[2] > 0.0, "the oracle's premise: no landing");
        let want = [(s[2], s[3]), (s[0], s[1]), (s[2], s[3])];
        assert!((0..3).all(|i| (q[i] - want[i].0).abs() <= 1e-12 && (v[i] - want[i].1).abs() <= 1e-12), "{case}: {q:?} {v:?} against {want:?}");
    }
}

/// A consistent mass `M = [[1, m], [m, 1]]`, `m = −1/4`, unit springs, no
/// dashpot: mass 0 held by `p = 0.1` (its force `p − m cos t > 0`), mass 1
/// from `(1, 0)` flying `x'' + x = 0` lands at π/2 at the speed 1. The
/// impulse `(1 + e)(1 − m²)` that turns it to `e` lifts mass 0 through the
/// mass (`W₀₁ = −m/(1 − m²)`): it leaves at `−m (1 + e)`, a release row at
/// the impact's time with that speed after.
#[test]
fn a_held_contact_lifted_by_another_impulse_logs_its_release() {
    let (m, p) = (-0.25f64, 0.1);
    let mass = {
        let mut b = band(2, &[(0, 0, 1.0), (1, 1, 1.0)]);
        b.set(1, 0, m);
        b
    };
    let stop = |d| Contact::new(d, Bounds::obstacle(0.0), false);
    let dy = Dynamics::new(mass, band(2, &[(0, 0, 1.0), (1, 1, 1.0)]), vec![-p, 0.0], vec![stop(0), stop(1)]);
    for e in [0.0, 0.5, 1.0] {
        let mut r = EventDriven::new(&dy, 0.0, &[0.0, 1.0], &[0.0, 0.0], e).expect("starts");
        assert_eq!(r.held(), vec![(0, false)]);
        r.run_until(PI / 2.0 + 0.05, 100).unwrap_or_else(|err| panic!("e = {e}: {err}"));
        let ev = r.events();
        let case = format!("e = {e}: {ev:?}");
        common::check_order(ev).unwrap();
        assert_eq!(ev.len(), 2, "{case}");
        let (imp, rel) = (ev[0], ev[1]);
        assert!(imp.kind == EventKind::Impact && imp.contact == 1 && (imp.t - PI / 2.0).abs() <= 1e-14, "{case}");
        assert!((imp.velocity_before + 1.0).abs() <= 1e-14 && (imp.velocity_after - e).abs() <= 1e-14, "{case}");
        assert!((imp.impulse - (1.0 + e) * (1.0 - m * m)).abs() <= 1e-14, "{case}");
        assert!(rel.kind == EventKind::Release && rel.contact == 0 && rel.t == imp.t, "{case}");
        assert!((rel.velocity_after + m * (1.0 + e)).abs() <= 1e-14, "{case}");
    }
}
