//! The reduced model (docs/theory.md §2.5) against its parent.
//!
//! With every interior mode kept the basis is an invertible change of
//! variables and the `mod` parent has massless contact rows, so the reduced
//! run is the parent run in other coordinates: contact displacement, λ and
//! the exact error norms agree to round-off. With fewer modes the contact
//! history converges to the parent's as `r` grows.

use signorini_fem::BarMass;
use signorini_reduce::Keep;
use signorini_run::reduced::{reduce, Need, Reconstruct};
use signorini_run::{run, Benchmark, History, NormObserver, Observer, RunConfig};
use signorini_schemes::SchemeSpec;

struct Runs {
    hist: History,
    norms: signorini_norms::NormReport,
}

fn full(m: usize, dt: f64, t_end: f64) -> Runs {
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(t_end).unwrap();
    let p = b.problem(exact.as_ref(), m, BarMass::Mod).unwrap();
    let spec: SchemeSpec = "newmark-cn".parse().unwrap();
    let mut s = spec.build(p.dynamics(), dt, &p.initial).unwrap();
    let mut hist = History::new(0, false);
    let mut norms = NormObserver::new(exact.as_ref(), m, p.vnorm(), dt);
    run(s.as_mut(), &p.initial.u, &RunConfig::new(dt, t_end).unwrap(), &mut [&mut hist, &mut norms]).unwrap();
    Runs { hist, norms: norms.report() }
}

fn reduced(m: usize, dt: f64, t_end: f64, keep: Keep) -> Runs {
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(t_end).unwrap();
    let p = b.problem(exact.as_ref(), m, BarMass::Mod).unwrap();
    let red = reduce(&p.dynamics(), &p.initial, keep).unwrap();
    let spec: SchemeSpec = "newmark-cn".parse().unwrap();
    let mut s = spec.build(red.dynamics.clone(), dt, &red.initial).unwrap();
    // The contact is reduced dof 0: its history needs no reconstruction.
    let mut hist = History::new(red.reduction.reduced_contact(0).unwrap(), false);
    let mut norms = NormObserver::new(exact.as_ref(), m, p.vnorm(), dt);
    let mut full_field = Reconstruct::new(&red.reduction, &mut norms, Need::Full);
    let obs: &mut [&mut dyn Observer] = &mut [&mut hist, &mut full_field];
    run(s.as_mut(), &red.initial.u, &RunConfig::new(dt, t_end).unwrap(), obs).unwrap();
    Runs { hist, norms: norms.report() }
}

fn max_diff(a: &History, b: &History) -> (f64, f64) {
    assert_eq!(a.records.len(), b.records.len());
    let mut du = 0.0_f64;
    let mut dl = 0.0_f64;
    for (x, y) in a.records.iter().zip(&b.records) {
        du = du.max((x.u_contact - y.u_contact).abs());
        let (lx, ly) = (x.lambda.map_or(0.0, |l| l.1), y.lambda.map_or(0.0, |l| l.1));
        dl = dl.max((lx - ly).abs());
    }
    (du, dl)
}

/// r = all interior modes (m = 20: 20 dofs, 1 contact, 19 modes): the same
/// contact displacement and λ history as the full `mod` model to ~1e-12,
/// and the same norms (the full field reconstructed through `T`).
#[test]
fn all_modes_reproduce_the_parent_to_round_off() {
    let (m, dt, t_end) = (20, 0.005, 3.0);
    let a = full(m, dt, t_end);
    let b = reduced(m, dt, t_end, Keep::Modes(m - 1));
    let (du, dl) = max_diff(&a.hist, &b.hist);
    eprintln!("r = all: max |Δu_c| = {du:e}, max |Δλ| = {dl:e}, norms full {:?} reduced {:?}", a.norms, b.norms);
    let umax = a.hist.records.iter().fold(0.0_f64, |s, r| s.max(r.u_contact.abs()));
    let lmax = a.hist.records.iter().fold(0.0_f64, |s, r| s.max(r.lambda.map_or(0.0, |l| l.1.abs())));
    assert!(lmax > 0.1 && umax > 0.1, "the run must hit the obstacle: λ max {lmax}, u max {umax}");
    assert!(du <= 1e-12 * umax, "contact displacement differs by {du:e}");
    assert!(dl <= 1e-11 * lmax, "λ differs by {dl:e} (max λ {lmax})");
    let (na, nb) = (a.norms, b.norms);
    for (x, y, what) in [(na.linf_l2_u, nb.linf_l2_u, "L∞L²"), (na.l2_v_u, nb.l2_v_u, "L²H¹"), (na.l2_lambda, nb.l2_lambda, "L²λ"), (na.linf_energy, nb.linf_energy, "L∞ energy")] {
        assert!((x - y).abs() <= 1e-9 * x.abs().max(1e-12), "{what}: full {x:e}, reduced {y:e}");
    }
}

/// Truncation: the contact history's distance to the parent shrinks as r
/// grows (4, 8, 16 of 39 modes at m = 40), and r = 2 is far off.
#[test]
fn contact_history_converges_as_modes_grow() {
    let (m, dt, t_end) = (40, 0.0025, 3.0);
    let a = full(m, dt, t_end);
    let errs: Vec<f64> = [2, 4, 8, 16, 32].iter().map(|&r| max_diff(&a.hist, &reduced(m, dt, t_end, Keep::Modes(r)).hist).0).collect();
    eprintln!("max |Δu_c| for r = 2, 4, 8, 16, 32: {errs:?}");
    for w in errs.windows(2) {
        assert!(w[1] < w[0], "not decreasing: {errs:?}");
    }
    assert!(errs[4] < 0.2 * errs[0], "{errs:?}");
}
