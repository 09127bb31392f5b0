//! The domain of evaluation of every bar benchmark (issue 22, item 2): a
//! NaN or infinite time, or a point off the bar `[0, L]` (beyond round-off),
//! gives NaN fields, a NaN force and no kinks — never a finite value from
//! the phase cast to an integer or the affine pieces extrapolated. Points
//! within round-off of an end take the end's values. The expected values are
//! the closed forms of docs/theory.md §5 written out here.

use signorini_exact::{BarDirichlet, BarMirrored, BarNeumannGravity, ExactSolution};

fn solutions() -> Vec<Box<dyn ExactSolution>> {
    vec![Box::new(BarDirichlet), Box::new(BarMirrored), Box::new(BarNeumannGravity::periodic(16.0).unwrap()), Box::new(BarNeumannGravity::paper(20.0).unwrap())]
}

#[track_caller]
fn all_nan(s: &dyn ExactSolution, x: f64, t: f64) {
    let f = s.fields(x, t);
    assert!(f.u.is_nan() && f.ux.is_nan() && f.ut.is_nan(), "{}: fields({x}, {t}) = {f:?}", s.name());
    let mut o = [0.0];
    s.u_at(t, &[x], &mut o);
    assert!(o[0].is_nan(), "{}: u_at({t}, [{x}]) = {}", s.name(), o[0]);
}

#[test]
fn non_finite_time_is_nan_everywhere() {
    for s in solutions() {
        let s = s.as_ref();
        for t in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for x in [0.0, 0.5, s.length()] {
                all_nan(s, x, t);
            }
            assert!(s.lambda(t).is_nan(), "{}: lambda({t}) = {}", s.name(), s.lambda(t));
            assert!(s.energy_at(t).is_nan(), "{}: energy_at({t})", s.name());
            assert!(!s.defined_at(t));
            let mut k = vec![0.25];
            s.kinks(t, &mut k);
            assert!(k.is_empty(), "{}: kinks({t}) = {k:?}", s.name());
            // u_at fills every output with NaN, also for many points.
            let mut o = [0.0; 3];
            s.u_at(t, &[0.0, 0.3, 0.9], &mut o);
            assert!(o.iter().all(|v| v.is_nan()), "{}: u_at({t}) = {o:?}", s.name());
        }
    }
}

#[test]
fn points_off_the_bar_are_nan() {
    for s in solutions() {
        let s = s.as_ref();
        let l = s.length();
        for x in [-1e-3, -0.5, l + 1e-3, 5.0, 1e300, f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
            for t in [0.0, 0.5, 1.5] {
                all_nan(s, x, t);
            }
        }
        // The rest of a u_at batch is still evaluated.
        let mut o = [0.0; 3];
        s.u_at(0.0, &[-0.5, 0.5, l + 0.5], &mut o);
        assert!(o[0].is_nan() && o[2].is_nan() && o[1].is_finite(), "{}: {o:?}", s.name());
        assert!(s.defined_at(0.0) && s.energy_at(0.0) == s.energy());
    }
}

#[test]
fn the_issue_values() {
    // Issue 22: u(0.5, NaN) and u(0.5, inf) were 0.25, λ(NaN) and
    // u_t(0.5, NaN) 0.0, u(5, 0.5) = -2.
    for s in [&BarDirichlet as &dyn ExactSolution, &BarMirrored] {
        assert!(s.fields(0.5, f64::NAN).u.is_nan());
        assert!(s.fields(0.5, f64::INFINITY).u.is_nan());
        assert!(s.fields(0.5, f64::NAN).ut.is_nan());
        assert!(s.lambda(f64::NAN).is_nan());
        assert!(s.fields(5.0, 0.5).u.is_nan());
    }
}

#[test]
fn round_off_beyond_an_end_takes_the_end_values() {
    // u(x, 0) = (1 - x)/2 on [0, 1] (both Dirichlet-type bars), u(1, t) = 0
    // for the clamped bar, u(2, 0) = -1/2 for the mirrored one.
    let eps = 1e-12;
    assert_eq!(BarDirichlet.fields(-eps, 0.0).u, 0.5);
    assert_eq!(BarDirichlet.fields(1.0 + eps, 0.7).u, 0.0);
    assert_eq!(BarMirrored.fields(-eps, 0.0).u, 0.5);
    assert_eq!(BarMirrored.fields(2.0 + eps, 0.0).u, -0.5);
    let mut o = [0.0; 2];
    BarDirichlet.u_at(0.0, &[-eps, 1.0 + eps], &mut o);
    assert_eq!(o, [0.5, 0.0]);
    // The falling bar at rest before its first impact: u(x, t) = u0 - g t²/2.
    let n = BarNeumannGravity::periodic(16.0).unwrap();
    for x in [-eps, 1.0 + eps] {
        let want = 0.5 - t_sq_half(1.0) / 9.0;
        assert!((n.fields(x, 1.0).u - want).abs() < 1e-14, "{x}");
    }
}

fn t_sq_half(t: f64) -> f64 {
    0.5 * t * t
}
