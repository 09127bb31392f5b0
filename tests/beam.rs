//! The beam between two stops: exact constraint, discrete energy balance,
//! penalty law, stability refusal, and the paper's first impact.

use proptest::prelude::*;
use signorini::run::beam::{build, stability_limit, BeamContact, BeamScene, Pipe};
use signorini::schemes::{Bounds, ContactLaw, Forcing, OneStep, OneStepParams, PaoliSchatzman, Stepper, TimeProfile};

fn scene(dt: f64, t_end: f64, contact: BeamContact) -> BeamScene {
    BeamScene { name: "test", elements: 19, dt, t_end, contact, paper_seconds: None }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// β-scheme with the projection (β ∈ [1/4, 1/2], dt below the exact
    /// limit): the tip stays in [g1, g2] exactly, the contact work never
    /// increases the energy (e = 0 impacts dissipate: the paper's energy
    /// estimate), and E^{n+1/2} - E^{1/2} = W_support + W_contact to rounding.
    #[test]
    fn beta_scheme_constraint_and_energy_balance(j in 2usize..10, beta in 0.25f64..=0.5, amp in 0.05f64..0.4, omega in 5.0f64..40.0,
                                                 gap in 0.01f64..0.1, cfl in 0.05f64..0.95) {
        let pipe = Pipe { stops: (-gap, 0.8 * gap), support: (amp, omega), ..Pipe::paper() };
        let (beam, dy, init) = pipe.dynamics(j).unwrap();
        let lim = stability_limit(&beam, beta).unwrap();
        let dt = if beta < 0.5 { cfl * lim.dt_sufficient } else { cfl * 2e-4 };
        let tip = beam.tip_dof();
        let mut s = PaoliSchatzman::new("beta".into(), dy, beta, 0.0, dt, &init).unwrap();
        let e_half = s.energy().unwrap().1;
        let mut wc_prev = 0.0;
        let mut contacts = 0;
        for _ in 0..400 {
            let r = s.step().unwrap();
            contacts += usize::from(r.active != signorini::contact::Active::None);
            let u = s.displacement()[tip];
            prop_assert!(u >= -gap && u <= 0.8 * gap, "tip {} outside [{}, {}]", u, -gap, 0.8 * gap);
            let (wf, wc) = s.work().unwrap();
            prop_assert!(wc <= wc_prev + 1e-15 * (1.0 + wc.abs()), "contact work grew: {} -> {}", wc_prev, wc);
            wc_prev = wc;
            let e = s.energy().unwrap().1;
            let scale = e.abs().max(e_half.abs()).max(wf.abs()).max(1e-12);
            prop_assert!(((e - e_half) - (wf + wc)).abs() <= 1e-9 * scale, "balance {} vs {}", e - e_half, wf + wc);
        }
        let _ = contacts;
    }
}

/// Normal compliance: the reported force is the spring law of the tip
/// displacement, exactly (to rounding), and the stops are violated.
#[test]
fn penalty_force_law() {
    let pipe = Pipe::paper();
    let (_, dy, init) = pipe.dynamics(19).unwrap();
    let tip = dy.contact_dof;
    let Bounds { lo, hi } = dy.bounds;
    let kappa = 1e8 / pipe.rho_s;
    let mut s = OneStep::new("pen".into(), dy, OneStepParams::newmark(0.25, 0.5), 5e-6, &init).unwrap().with_contact_law(ContactLaw::Penalty { stiffness: kappa }).unwrap();
    let mut max_excess: f64 = 0.0;
    let mut active = 0;
    for _ in 0..40_000 {
        let r = s.step().unwrap();
        let u = s.displacement()[tip];
        let law = kappa * (lo - u).max(0.0) - kappa * (u - hi).max(0.0);
        let lambda = r.lambda.unwrap().1;
        // κ(hi − u) cancels: rounding of a few ulps of κ·|u| (κ = 8.4e8).
        assert!((lambda + law).abs() <= 4e-16 * kappa * (u.abs() + hi), "λ = {lambda}, spring {law} at u = {u}");
        active += usize::from(law != 0.0);
        max_excess = max_excess.max(u.abs() - 0.1);
    }
    assert!(active > 100 && max_excess > 1e-5, "{active} penalty steps, max excess {max_excess}");
    assert!(matches!(
        OneStep::new("pen".into(), Pipe::paper().dynamics(3).unwrap().1, OneStepParams::newmark(0.25, 0.5), 1e-5, &Pipe::paper().dynamics(3).unwrap().2).unwrap().with_contact_law(ContactLaw::Penalty { stiffness: -1.0 }),
        Err(signorini::schemes::SchemeError::Invalid { field: "penalty stiffness", .. })
    ));
}

// The β-scheme's stability limit and its refusal: tests/stability.rs.

/// Fig. 2 data (β = 1/2, dt = 5e-5): the tip never leaves [-0.1, 0.1] and
/// first touches the upper stop at t = 0.0878 s, as every finer run does.
#[test]
fn first_impact_of_the_paper_scene() {
    let pipe = Pipe::paper();
    let (mut s, init, beam) = build(&pipe, &scene(5e-5, 0.2, BeamContact::Projection { beta: 0.5 }), false).unwrap();
    let _ = init;
    let mut first = None;
    for _ in 0..4000 {
        let r = s.step().unwrap();
        let u = s.displacement()[beam.tip_dof()];
        assert!(u.abs() <= 0.1);
        if first.is_none() && r.active != signorini::contact::Active::None {
            first = Some((r.t, u));
        }
    }
    let (t, u) = first.unwrap();
    assert!((t - 0.08785).abs() < 1e-4 && u == 0.1, "first impact at {t} (tip {u})");
    // The support forcing's time averages are exact.
    let p = TimeProfile::Sine { amplitude: 2.0, omega: 10.0 };
    let (t0, t1): (f64, f64) = (0.3, 0.3 + 1e-3);
    let exact = 2.0 * ((10.0 * t0).cos() - (10.0 * t1).cos()) / (10.0 * 1e-3);
    assert!((p.mean(t0, t1) - exact).abs() < 1e-12);
    let _ = Forcing { shape: vec![], time: p };
}
