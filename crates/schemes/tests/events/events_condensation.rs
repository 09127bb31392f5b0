//! `Condensation`, the static condensation that the event-driven run's
//! massless phases and the orbits' parameter sensitivity share, against
//! closed forms of a three-dof chain written here: dof 0 (mass 2, a ground
//! spring 5), massless dof 1 between the springs `ka` = 4 (to dof 0) and
//! `kb` = 6 (to dof 2), dof 2 (mass 3, a ground spring 1). Condensing dof
//! 1 puts the series spring `ka kb/(ka + kb)` = 2.4 between dofs 0 and 2
//! and shares a load on it as `ka/(ka + kb)` = 0.4 to dof 0 and 0.6 to dof
//! 2; dof 1 sits at `(f_1 + ka q_0 + kb q_2)/(ka + kb)`.

use signorini_fem::SymBand;
use signorini_schemes::events::{Condensation, EventsError};
use signorini_schemes::{Dynamics, Forcing, TimeProfile};

const KA: f64 = 4.0;
const KB: f64 = 6.0;

/// The chain with the steady load `f` and a sine `shape · a sin(Ω t)`.
fn chain(f: [f64; 3], shape: [f64; 3], a: f64, omega: f64) -> Dynamics {
    let m = SymBand::from_diagonal(&[2.0, 0.0, 3.0]);
    let mut k = SymBand::zeros(3, 1);
    for (i, j, v) in [(0, 0, 5.0 + KA), (1, 0, -KA), (1, 1, KA + KB), (2, 1, -KB), (2, 2, KB + 1.0)] {
        k.set(i, j, v);
    }
    let forcing = vec![Forcing { shape: shape.to_vec(), time: TimeProfile::Sine { amplitude: a, omega } }];
    Dynamics::new(m, k, f.to_vec(), Vec::new()).with_forcing(forcing)
}

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() <= 1e-14 * b.abs().max(1.0), "{what}: {a} against {b}");
}

/// Nothing fixed: the free dofs 0 and 2 with the series spring between
/// them, the load map's shares, `K_SS⁻¹` = 1/10.
#[test]
fn the_series_spring_and_the_load_shares_of_a_massless_dof() {
    let cd = Condensation::new(&chain([0.0; 3], [0.0; 3], 0.0, 1.0), &[], &[1]).unwrap();
    assert_eq!((cd.free(), cd.condensed()), (&[0, 2][..], &[1][..]));
    let series = KA * KB / (KA + KB);
    let want = [[5.0 + series, -series], [-series, 1.0 + series]];
    for (i, row) in want.iter().enumerate() {
        for (j, w) in row.iter().enumerate() {
            close(cd.stiffness()[(i, j)], *w, &format!("K_eff[{i}][{j}]"));
        }
    }
    close(cd.inverse()[(0, 0)], 1.0 / (KA + KB), "K_SS⁻¹");
    let y = cd.load(&[1.5, -2.0, 0.25]);
    close(y[0], 1.5 - 2.0 * KA / (KA + KB), "the load on dof 0");
    close(y[1], 0.25 - 2.0 * KB / (KA + KB), "the load on dof 2");
}

/// Dof 2 held at `b`: one free dof, `2 x'' + (5 + 2.4) x = F + G a sin Ωt`
/// with `F = f_0 + 0.4 (f_1 + kb b)` (the held value pulls dof 1) and
/// `G = g_0 + 0.4 g_1`, advanced by `flow` against its closed form.
#[test]
fn the_condensed_flow_with_a_held_dof_is_the_one_dof_oscillators() {
    let (b, a, w) = (0.3, 0.7, 1.3);
    let (f, shape) = ([0.5, -1.25, 2.0], [1.0, 0.5, -3.0]);
    let dy = chain(f, shape, a, w);
    let cd = Condensation::new(&dy, &[(2, b)], &[1]).unwrap();
    assert_eq!(cd.free(), &[0]);
    let share = KA / (KA + KB);
    let (m, k) = (2.0, 5.0 + KA * KB / (KA + KB));
    let (steady, g) = (f[0] + share * (f[1] + KB * b), shape[0] + share * shape[1]);
    let flow = cd.flow(&dy).unwrap();
    let (x0, v0) = (0.2, -0.4);
    let om = (k / m).sqrt();
    let (p, q) = (steady / k, g * a / (k - m * w * w));
    let exact = |t: f64| {
        let (c1, c2) = (x0 - p, (v0 - q * w) / om);
        (p + q * (w * t).sin() + c1 * (om * t).cos() + c2 * (om * t).sin(), q * w * (w * t).cos() - c1 * om * (om * t).sin() + c2 * om * (om * t).cos())
    };
    for tau in [0.1, 1.7, 6.0] {
        let (mut x, mut v) = ([0.0], [0.0]);
        flow.advance(0.0, &[x0], &[v0], tau, &mut x, &mut v);
        let (xe, ve) = exact(tau);
        assert!((x[0] - xe).abs() <= 1e-13 && (v[0] - ve).abs() <= 1e-13, "τ = {tau}: ({}, {}) against ({xe}, {ve})", x[0], v[0]);
    }
}

/// A condensed dof without stiffness has no static position: a typed
/// error, and a piecewise-linear series is refused by `flow` (no piece).
#[test]
fn a_condensed_dof_without_stiffness_and_a_series_are_refused() {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0, 0.0]), SymBand::from_diagonal(&[1.0, 0.0]), vec![0.0; 2], Vec::new());
    assert!(matches!(Condensation::new(&dy, &[], &[1]), Err(EventsError::Contacts(_))));
    let series = signorini_schemes::Series::new(vec![0.0, 1.0], vec![0.0, 1.0]).unwrap();
    let dy = chain([0.0; 3], [0.0; 3], 0.0, 1.0).with_forcing(vec![Forcing { shape: vec![1.0, 0.0, 0.0], time: TimeProfile::Series(series) }]);
    let cd = Condensation::new(&dy, &[], &[1]).unwrap();
    assert!(matches!(cd.flow(&dy), Err(EventsError::Profile { index: 0 })));
}
