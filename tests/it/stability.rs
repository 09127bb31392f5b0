//! The β-scheme's true stability limit (issue 11 §1): unconditionally stable
//! for β >= 1/4, and for β < 1/4 stable iff dt < 2/sqrt((1 - 4β) κ_h). Runs
//! just below the limit stay bounded, runs just above blow up; the limit is
//! checked against κ_h from a dense eigensolver (beam) or a closed form
//! (lumped bar), not against the code's own eigenvalue iteration.

use faer::{Mat, Side};
use signorini::fem::{Bar, BarMass, Beam, RightEnd, SymBand};
use signorini::run::beam::{stability_limit, BeamScene, BeamSetup, Pipe};
use signorini::run::{BarProblem, RunError};
use signorini::schemes::{PaoliSchatzman, SchemeError, SchemeSpec, Stepper};

fn dense(a: &SymBand) -> Mat<f64> {
    Mat::from_fn(a.n(), a.n(), |i, j| a.get(i, j))
}

/// Largest eigenvalue of `(K, M)` by a dense solve: `L⁻¹ K L⁻ᵀ`, `M = L Lᵀ`.
fn dense_kappa(k: &SymBand, m: &SymBand) -> f64 {
    let (k, m) = (dense(k), dense(m));
    let n = m.nrows();
    let l = m.llt(Side::Lower).unwrap().L().to_owned();
    let mut linv = Mat::<f64>::identity(n, n);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), faer::Par::Seq);
    let c = &linv * &k * linv.transpose();
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    *c.self_adjoint_eigenvalues(Side::Lower).unwrap().last().unwrap()
}

fn scene(dt: f64, t_end: f64, beta: f64) -> BeamScene {
    BeamScene::new("test", 19, dt, t_end, SchemeSpec::ps(0.0, beta))
}

/// The beam run of `scene`, forced past the stability limit or not.
fn build(pipe: &Pipe, scene: &BeamScene, force: bool) -> Result<(Box<dyn Stepper>, (), ()), RunError> {
    BeamSetup::new(*pipe, *scene).forced(force).build().map(|b| (b.stepper, (), ()))
}

/// Steps a stepper `steps` times; the largest |U_i| reached, or infinity
/// when the state stopped being finite.
fn max_abs(s: &mut dyn Stepper, steps: usize) -> f64 {
    let mut m: f64 = 0.0;
    for _ in 0..steps {
        match s.step() {
            Ok(_) => m = m.max(s.displacement().iter().fold(0.0_f64, |a, x| a.max(x.abs()))),
            Err(SchemeError::NonFinite { .. }) => return f64::INFINITY,
            Err(e) => panic!("{e}"),
        }
        if !m.is_finite() {
            return f64::INFINITY;
        }
    }
    m
}

/// Beam J = 19 (the paper's pipe): for β ∈ {0, 0.1, 0.2} the limit equals
/// 2/sqrt((1-4β) κ_h) with κ_h from a dense eigensolver; a run at 0.98× the
/// limit stays bounded for 20 000 steps (through the first impacts), at
/// 1.02× it grows ~100-fold (capped by the stops), at 1.2× it overflows;
/// the refusal triggers exactly at the limit.
#[test]
fn beam_beta_below_a_quarter_just_below_and_above_the_limit() {
    let pipe = Pipe::paper();
    let beam = Beam::new(pipe.length, 19, pipe.k2).unwrap();
    let kappa = dense_kappa(&beam.stiffness(), &beam.mass());
    assert!((kappa / 2.603_530_158_7e10 - 1.0).abs() < 1e-9, "dense κ_h = {kappa}");
    for beta in [0.0, 0.1, 0.2] {
        let want = 2.0 / ((1.0 - 4.0 * beta) * kappa).sqrt();
        let lim = stability_limit(&beam, beta).unwrap();
        assert!((lim.dt_critical / want - 1.0).abs() < 1e-9, "β = {beta}: limit {} vs {want}", lim.dt_critical);
        // The paper's sufficient condition (3.1), reported, is smaller.
        assert!((lim.dt_sufficient / (2.0 / ((1.0 - 2.0 * beta) * kappa).sqrt()) - 1.0).abs() < 1e-9);
        assert!(lim.dt_paper < lim.dt_sufficient && lim.dt_sufficient <= lim.dt_critical);

        let below = scene(0.98 * want, 1.0, beta);
        let (mut s, _, _) = build(&pipe, &below, false).unwrap_or_else(|e| panic!("β = {beta}: run below the limit refused: {e}"));
        let m = max_abs(s.as_mut(), 20_000);
        assert!(m < 1.0, "β = {beta}, dt = 0.98 × limit: max |U| = {m} (should stay bounded)");

        let above = scene(1.02 * want, 1.0, beta);
        match build(&pipe, &above, false) {
            Err(RunError::Scheme(SchemeError::Unstable { dt, limit, scheme, rule })) => {
                assert_eq!((dt, scheme), (1.02 * want, SchemeSpec::ps(0.0, beta).to_string()));
                assert!((limit / want - 1.0).abs() < 1e-9, "β = {beta}: refused at the limit {limit}, the dense one is {want}");
                assert!(rule.contains("(1 - 4β)") || beta == 0.0, "{rule}");
            }
            Err(e) => panic!("β = {beta}: unexpected {e}"),
            Ok(_) => panic!("β = {beta}: a run beyond the limit was accepted"),
        }
        // Beyond the limit the highest mode (tip-dominated) grows until the
        // stops' projection caps it: |U| (slopes included) reaches ~100× the
        // stable run's size within 20 000 steps (~15 against 0.14) and
        // overflows at 1.2× the limit.
        let (mut s, _, _) = build(&pipe, &above, true).unwrap();
        let m_above = max_abs(s.as_mut(), 20_000);
        assert!(m_above > 50.0 * m, "β = {beta}, dt = 1.02 × limit: max |U| = {m_above} vs {m} below (should blow up)");
        let (mut s, _, _) = build(&pipe, &scene(1.2 * want, 1.0, beta), true).unwrap();
        assert_eq!(max_abs(s.as_mut(), 20_000), f64::INFINITY, "β = {beta}, dt = 1.2 × limit");
    }
}

/// β = 1/4 is unconditionally stable: dt = 2e-4 s (11× the limit the code
/// used to enforce, 1.7529e-5 s) is accepted and stays bounded over the
/// paper's whole horizon, impacts included.
#[test]
fn beam_beta_quarter_far_beyond_the_old_limit() {
    let pipe = Pipe::paper();
    let beam = Beam::new(pipe.length, 19, pipe.k2).unwrap();
    let lim = stability_limit(&beam, 0.25).unwrap();
    assert_eq!(lim.dt_critical, f64::INFINITY);
    // The paper prints its sufficient condition with its κ bound: 3.3469e-6 s.
    assert!((lim.dt_paper - 3.3469e-6).abs() < 1e-10, "paper bound {}", lim.dt_paper);
    let (mut s, _, _) = build(&pipe, &scene(2e-4, 2.0, 0.25), false).expect("β = 1/4 must not be refused");
    let tip = beam.tip_dof();
    let mut contacts = 0;
    let mut m: f64 = 0.0;
    for _ in 0..10_000 {
        let r = s.step().unwrap();
        contacts += usize::from(r.active != signorini::contact::Active::None);
        m = m.max(s.displacement().iter().fold(0.0_f64, |a, x| a.max(x.abs())));
        let u = s.displacement()[tip];
        assert!((-0.1..=0.1).contains(&u), "tip {u}");
    }
    assert!(contacts > 10, "{contacts} contact steps");
    assert!(m < 1.0, "max |U| = {m}");
}

/// The lumped P1 bar, free at the contact end and clamped at x = 1: κ_h =
/// (4c²/h²) sin²((2m-1)π/(4m)) in closed form. `ps(e, β)` with β < 1/4
/// reports and enforces 2/sqrt((1-4β) κ_h); just below it runs stay bounded,
/// just above they blow up (built directly, bypassing the refusal).
#[test]
fn bar_ps_beta_below_a_quarter() {
    let m = 40;
    let h = 1.0 / m as f64;
    let kappa = 4.0 / (h * h) * ((2 * m - 1) as f64 * std::f64::consts::PI / (4 * m) as f64).sin().powi(2);
    let bar = Bar::new(1.0, m, 1.0, RightEnd::Clamped).unwrap();
    let p = BarProblem::new(bar, BarMass::Lumped, 0.0, 0.0, |x| 0.5 * (1.0 - x), |_| 0.0).unwrap();
    for beta in [0.0, 0.1, 0.2] {
        let spec = SchemeSpec::ps(0.5, beta);
        let want = 2.0 / ((1.0 - 4.0 * beta) * kappa).sqrt();
        let lim = spec.cfl_limit(&p.dynamics()).unwrap().expect("β < 1/4 is conditionally stable");
        assert!((lim / want - 1.0).abs() < 1e-9, "β = {beta}: {lim} vs {want}");
        match spec.build(p.dynamics(), 1.02 * want, &p.initial) {
            Err(SchemeError::Unstable { limit, rule, .. }) => {
                assert!((limit / want - 1.0).abs() < 1e-9);
                assert!(rule.contains("pencil (K, M)") && !rule.contains("penalty"), "{rule}");
            }
            Err(e) => panic!("unexpected {e}"),
            Ok(_) => panic!("β = {beta}: a run beyond the limit was accepted"),
        }
        let mut s = spec.build(p.dynamics(), 0.98 * want, &p.initial).unwrap();
        let m_below = max_abs(s.as_mut(), 20_000);
        assert!(m_below < 1.0, "β = {beta}: max |U| = {m_below} below the limit");
        let mut s = PaoliSchatzman::new("above".into(), p.dynamics(), beta, 0.5, 1.02 * want, &p.initial).unwrap();
        let m_above = max_abs(&mut s, 20_000);
        assert!(m_above > 1e6, "β = {beta}: max |U| = {m_above} above the limit");
    }
    // β >= 1/4: no limit; a massless contact node refuses β < 1/4.
    assert_eq!(SchemeSpec::ps(0.5, 0.25).cfl_limit(&p.dynamics()).unwrap(), None);
    let pm = BarProblem::new(Bar::new(1.0, m, 1.0, RightEnd::Clamped).unwrap(), BarMass::Mod, 0.0, 0.0, |x| 0.5 * (1.0 - x), |_| 0.0).unwrap();
    assert!(matches!(SchemeSpec::ps(0.0, 0.1).build(pm.dynamics(), h, &pm.initial), Err(SchemeError::MassNotSupported { .. })));
}
