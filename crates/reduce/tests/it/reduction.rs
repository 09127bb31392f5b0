//! The reduction against closed forms and an independent code path.

use signorini_fem::{Bar, BarMass, RightEnd, SymBand};
use signorini_reduce::{Keep, ReduceError, Reduction};
use signorini_schemes::{Bounds, Contact, Dynamics, SchemeSpec};
use std::f64::consts::PI;

fn bar(m: usize, mass: BarMass) -> (SymBand, SymBand) {
    let b = Bar::new(1.0, m, 1.0, RightEnd::Clamped).unwrap();
    (b.stiffness(), b.mass(mass))
}

/// The kept eigenvalues are the lowest r of the fixed-interface problem:
/// with the contact node 0 held the lumped P1 bar on [0, 1] clamped at 1 is
/// a clamped–clamped chain of m − 1 nodes, `ω_k² = 4c²/h² sin²(kπ/(2m))`.
#[test]
fn modes_are_the_lowest_fixed_interface_eigenvalues() {
    let m = 16;
    let h = 1.0 / m as f64;
    let (k, mm) = bar(m, BarMass::Lumped);
    let want = |j: usize| 4.0 / (h * h) * (j as f64 * PI / (2.0 * m as f64)).sin().powi(2);
    for r in [1, 5, m - 1] {
        let red = Reduction::new(&k, &mm, &[0], Keep::Modes(r)).unwrap();
        assert_eq!(red.modes().len(), r);
        assert_eq!(red.dofs(), r + 1);
        for (j, &w2) in red.modes().iter().enumerate() {
            assert!((w2 - want(j + 1)).abs() <= 1e-12 * want(m - 1), "r = {r}, mode {}: {w2} vs {}", j + 1, want(j + 1));
        }
    }
    // A cutoff keeps exactly the modes at or below it.
    let f = (want(6).sqrt() + want(7).sqrt()) / 2.0 / (2.0 * PI);
    assert_eq!(Reduction::new(&k, &mm, &[0], Keep::CutoffHz(f)).unwrap().modes().len(), 6);
}

fn mod_dynamics(m: usize) -> Dynamics {
    let (k, mm) = bar(m, BarMass::Mod);
    let n = k.n();
    Dynamics::new(mm, k, vec![0.0; n], vec![Contact::new(0, Bounds::obstacle(0.0), true)])
}

/// With every mode kept, the reduced model's exact CD limit is the full
/// `mod` model's, computed by the schemes crate (`cd-massless`: the pencil
/// with the contact node held, largest eigenvalue by banded shift-invert
/// iteration) — a code path that shares nothing with the reduction's dense
/// eigensolver. And `project_state` inverts `T`; `K_r = Tᵀ K T`.
#[test]
fn all_modes_give_the_full_cfl_limit_and_an_invertible_basis() {
    let m = 24;
    let dy = mod_dynamics(m);
    let full = "cd-massless".parse::<SchemeSpec>().unwrap().cfl_limit(&dy).unwrap().unwrap();
    let red = Reduction::new(&dy.stiffness, &dy.mass, &[0], Keep::Modes(m - 1)).unwrap();
    assert!((red.cfl_limit() - full).abs() <= 1e-10 * full, "reduced {} vs full {full}", red.cfl_limit());
    let u: Vec<f64> = (0..m).map(|i| (0.3 + i as f64).sin()).collect();
    let q = red.project_state(&u);
    let mut back = vec![0.0; m];
    red.reconstruct(&q, &mut back);
    for (a, b) in u.iter().zip(&back) {
        assert!((a - b).abs() < 1e-12, "{a} vs {b}");
    }
    // The reduced stiffness is Tᵀ K T: energies agree for any q.
    let q: Vec<f64> = (0..m).map(|i| (1.7 * i as f64).cos()).collect();
    red.reconstruct(&q, &mut back);
    let (e_r, e) = (red.stiffness().quad_form(&q), dy.stiffness.quad_form(&back));
    assert!((e_r - e).abs() <= 1e-11 * e, "{e_r} vs {e}");
}

/// Fewer modes, larger stability limit: `cfl(r)` does not decrease as r
/// shrinks, equals `2/ω_r` with `ω_r²` from the closed form of the lumped
/// bar's clamped–clamped chain, and equals the schemes crate's
/// `cd-massless` limit of the reduced dynamics; the free-contact pencil
/// lies below `ω_r²`; the full model's limit is the smallest.
#[test]
fn cfl_limit_grows_as_the_cutoff_falls() {
    let m = 40;
    let h = 1.0 / m as f64;
    let (k, mm) = bar(m, BarMass::Lumped);
    let full = 2.0 / (4.0 / (h * h) * ((m - 1) as f64 * PI / (2.0 * m as f64)).sin().powi(2)).sqrt();
    let mut prev = f64::INFINITY;
    for r in [1, 2, 4, 8, 16, 32, 39] {
        let red = Reduction::new(&k, &mm, &[0], Keep::Modes(r)).unwrap();
        let c = red.cfl_limit();
        let w_r = 2.0 / h * (r as f64 * PI / (2.0 * m as f64)).sin();
        assert!((c - 2.0 / w_r).abs() <= 1e-11 * c, "r = {r}: {c} vs 2/ω_r = {}", 2.0 / w_r);
        assert!(c <= prev * (1.0 + 1e-12), "r = {r}: {c} > {prev}");
        assert!(c >= full * (1.0 - 1e-10), "r = {r}: {c} < full {full}");
        assert!(red.kappa_free() <= red.kappa() * (1.0 + 1e-12) && red.kappa_free() > 0.0);
        let dy = Dynamics::new(red.mass().clone(), red.stiffness().clone(), vec![0.0; r + 1], vec![Contact::new(0, Bounds::obstacle(0.0), true)]);
        let via_schemes = "cd-massless".parse::<SchemeSpec>().unwrap().cfl_limit(&dy).unwrap().unwrap();
        assert!((c - via_schemes).abs() <= 1e-9 * c, "r = {r}: {c} vs schemes {via_schemes}");
        prev = c;
    }
    assert!(Reduction::new(&k, &mm, &[0], Keep::Modes(4)).unwrap().cfl_limit() > 5.0 * full);
}

fn field(e: ReduceError) -> &'static str {
    match e {
        ReduceError::Invalid { field, .. } | ReduceError::NotDefinite { field, .. } => field,
    }
}

/// Bad input gets typed errors naming the field.
#[test]
fn bad_input_is_refused_naming_the_field() {
    let (k, mm) = bar(10, BarMass::Mod);
    let err = |c: &[usize], keep| field(Reduction::new(&k, &mm, c, keep).unwrap_err());
    assert_eq!(err(&[0], Keep::Modes(0)), "modes");
    assert_eq!(err(&[0], Keep::Modes(10)), "modes");
    assert!(Reduction::new(&k, &mm, &[0], Keep::Modes(9)).is_ok());
    let first_hz = Reduction::new(&k, &mm, &[0], Keep::Modes(1)).unwrap().modes()[0].sqrt() / (2.0 * PI);
    assert_eq!(err(&[0], Keep::CutoffHz(0.99 * first_hz)), "cutoff_hz");
    assert!(Reduction::new(&k, &mm, &[0], Keep::CutoffHz(1.01 * first_hz)).is_ok());
    assert_eq!(err(&[0], Keep::CutoffHz(f64::NAN)), "cutoff_hz");
    assert_eq!(err(&[0], Keep::CutoffHz(-1.0)), "cutoff_hz");
    assert_eq!(err(&[], Keep::Modes(1)), "contacts");
    assert_eq!(err(&[0, 0], Keep::Modes(1)), "contacts");
    assert_eq!(err(&[10], Keep::Modes(1)), "contacts");
    // The `mod` mass of a contact at node 0, reduced with the contact at
    // node 1: node 0 is then an interior dof without mass.
    assert_eq!(err(&[1], Keep::Modes(1)), "mass");
}

/// A fine beam (J = 76: 151 interior dofs, past the size at which faer's
/// default symmetric eigensolver switches to divide and conquer), every
/// mode kept: each basis column's interior is an eigenvector of the
/// fixed-interface pencil (residual at round-off of `ω_max²`), `K_r = Tᵀ K T`
/// entry by entry, and the contact entry of `K_r` is the parent's `K_bb`
/// (with every mode kept the condensation and the modal sum add back up to
/// it). Before the QR-only eigensolver the residual was 3e-4 · ω_max² and
/// `K_r[0][0]` was 4e-4 off.
#[test]
fn a_fine_beam_keeps_exact_modes_and_its_contact_stiffness() {
    let beam = signorini_fem::Beam::new(1.501, 76, 282.84).unwrap();
    let (k, m) = (beam.stiffness(), beam.mass());
    let (n, b) = (k.n(), beam.tip_dof());
    let red = Reduction::new(&k, &m, &[b], Keep::Modes(n - 1)).unwrap();
    let w2max = *red.modes().last().unwrap();
    let cols: Vec<Vec<f64>> = (0..red.dofs())
        .map(|c| {
            let mut q = vec![0.0; red.dofs()];
            q[c] = 1.0;
            let mut u = vec![0.0; n];
            red.reconstruct(&q, &mut u);
            u
        })
        .collect();
    let (mut ku, mut mu) = (vec![0.0; n], vec![0.0; n]);
    for (j, &w2) in red.modes().iter().enumerate() {
        let phi = &cols[1 + j];
        assert_eq!(phi[b], 0.0);
        k.mul_vec(phi, &mut ku);
        m.mul_vec(phi, &mut mu);
        let scale = mu.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        let res = (0..n).filter(|&i| i != b).fold(0.0_f64, |a, i| a.max((ku[i] - w2 * mu[i]).abs()));
        assert!(res <= 1e-9 * w2max * scale, "mode {j}: residual {res:e} against ω_max² |Mφ| = {:e}", w2max * scale);
    }
    for a in 0..red.dofs() {
        k.mul_vec(&cols[a], &mut ku);
        for c in 0..red.dofs() {
            let tkt: f64 = cols[c].iter().zip(&ku).map(|(x, y)| x * y).sum();
            let kr = red.stiffness().get(a, c);
            let scale = (red.stiffness().get(a, a) * red.stiffness().get(c, c)).sqrt();
            assert!((tkt - kr).abs() <= 1e-7 * scale, "K_r[{a}][{c}] = {kr:e}, Tᵀ K T = {tkt:e}");
        }
    }
    let kbb = k.get(b, b);
    assert!((red.stiffness().get(0, 0) - kbb).abs() <= 1e-9 * kbb, "K_r[0][0] = {:e}, K_bb = {kbb:e}", red.stiffness().get(0, 0));
}
