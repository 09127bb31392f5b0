//! The discrete equations, contact conditions and energy identities of
//! docs/theory.md §4 and §7 with **several contacts**: a free P1 bar with
//! three stops — a lower stop at node 0, a two-sided stop at the middle
//! node, an upper stop at the free end, every gap nonzero — under a body
//! force and a sine forcing, with `std`, `lumped` and `mod` mass (massless
//! at all three nodes).
//!
//! As in `energy.rs`, nothing checked comes from the scheme but its recorded
//! displacements and its reported forces (`contact_forces()`, every
//! contact): `M`, `K`, the loads, momenta, velocities, energies and works
//! are rebuilt here (`common`), and each identity is checked step by step to
//! `1e-11` of its largest term (measured worst ratios are printed: 1e-14 to
//! 1e-13). Each run must touch every stop.
//!
//! * One-step schemes (every Newmark preset, any Newmark(β, γ), θ): the
//!   momentum-form update, the box complementarity at every contact
//!   (`lo_i <= u_i <= hi_i`, `λ_i = 0` strictly inside, `u_i` exactly on the
//!   bound its force's sign names), the energy identity with the work of the
//!   forcing and of all contact forces; for Crank–Nicolson the accumulated
//!   balance `Eⁿ − E⁰ = W_f + W_c`.
//! * Paoli–Schatzman with a restitution of its own at two of the stops
//!   (0 and 1, the third the scheme's 0.5): the two-step equation, each
//!   stop's restitution constraint, the half-step balance.
//! * Penalty (Newmark-CN and the explicit central difference): the Newmark
//!   identity with the spring forces, and each force is its spring's law
//!   `κ_i (lo_i − u_i)⁺ − κ_i (u_i − hi_i)⁺` with `κ_i` the stop's own
//!   stiffness or `γ_P K_{c_i c_i}` (`1/h` at an end node, `2/h` inside).
//! * Moreau–Jean (steady load): the velocity-level θ-scheme with the
//!   velocities rebuilt from the displacements, Newton's law at every
//!   predicted-active stop, `p_i = 0` elsewhere, and the energy identity
//!   `ΔE = Σ p_i (v_iⁿ + v_iⁿ⁺¹)/2`.

use crate::common;

use common::*;
use signorini_fem::BarMass;
use signorini_schemes::{Initial, SchemeSpec};

const TOL: f64 = 1e-11;
const M: usize = 12;
const MASSES: [BarMass; 3] = [BarMass::Std, BarMass::Lumped, BarMass::Mod];

/// Node 0 above −0.05; the middle node between −0.12 and 0.1; the free end
/// below 0.08.
fn stops() -> Vec<OStop> {
    vec![OStop::new(0, -0.05, f64::INFINITY), OStop::new(M / 2, -0.12, 0.1), OStop::new(M, f64::NEG_INFINITY, 0.08)]
}

/// The bar tilts: node 0 moves down, the free end up, the middle is driven
/// by the forcing (shape `h(1 + x)`, amplitude 3, ω = 9) against the body
/// force −0.4.
fn scene(mass: BarMass, stops: &[OStop], forcing: bool) -> (signorini_schemes::Dynamics, Oracle, Initial) {
    let n = M + 1;
    let h = 1.0 / M as f64;
    let f = forcing.then(|| ((0..n).map(|i| h * (1.0 + i as f64 * h)).collect(), Sine { amp: 3.0, omega: 9.0 }));
    let (dy, o) = bar_stops_scene(M, mass, true, stops, -0.4, f);
    let x = |i: usize| i as f64 * h;
    let init = Initial { u: vec![0.0; n], v: (0..n).map(|i| -0.8 + 1.6 * x(i) + 0.3 * (std::f64::consts::PI * x(i)).sin()).collect() };
    (dy, o, init)
}

/// The contact force vector at level `l` from the recorded forces.
fn recorded_force<'a>(o: &'a Oracle, traj: &'a Traj) -> impl Fn(usize, &[f64], f64) -> Vec<f64> + 'a {
    let all = traj.all_forces(0);
    move |l, _, _| if l == 0 { vec![0.0; o.n()] } else { o.force_vector(all[l].as_ref().unwrap()) }
}

fn touched(o: &Oracle, traj: &Traj, lag: usize) -> Vec<usize> {
    let all = traj.all_forces(lag);
    (0..o.stops.len()).map(|i| all.iter().flatten().filter(|f| f[i] != 0.0).count()).collect()
}

#[test]
fn one_step_schemes_with_three_stops() {
    let schemes: [(&str, Coefs); 6] = [
        ("newmark-cn", Coefs::newmark(0.25, 0.5)),
        ("newmark-i", Coefs::newmark(0.5, 1.0)),
        ("newmark-ii", Coefs::newmark(0.5, 0.5)),
        ("backward-euler", Coefs::theta(1.0)),
        ("theta(0.7)", Coefs::theta(0.7)),
        ("newmark(0.3,0.55)", Coefs::newmark(0.3, 0.55)),
    ];
    for mass in MASSES {
        for (name, cf) in schemes {
            let (dy, o, init) = scene(mass, &stops(), true);
            let spec: SchemeSpec = name.parse().unwrap();
            let mut s = spec.build(dy, 0.01, &init).unwrap();
            let traj = record(s.as_mut(), 400);
            let st = check_one_step(&o, &o.k, cf, &init, &traj, recorded_force(&o, &traj), TOL);
            check_projection(&o, &traj);
            let hits = touched(&o, &traj, 0);
            assert!(hits.iter().all(|&k| k > 0), "{mass} {name}: contact levels per stop {hits:?}");
            if name == "newmark-cn" {
                // Eⁿ − E⁰ = W_f + W_c accumulated (from the first step on
                // with massless nodes, whose start is not in equilibrium).
                let s0 = usize::from(o.massless);
                let (e0, wf0, wc0) = st.path[s0];
                let scale = st.path.iter().fold(0.0f64, |a, p| a.max(p.0.abs()).max(p.1.abs()).max(p.2.abs()));
                let mut worst = 0.0f64;
                for (l, &(e, wf, wc)) in st.path.iter().enumerate().skip(s0) {
                    let d = (e - e0) - (wf - wf0) - (wc - wc0);
                    worst = worst.max(d.abs() / scale);
                    assert!(d.abs() <= TOL * scale, "{mass} newmark-cn: level {l}: Eⁿ − E⁰ = {:e}, W_f + W_c = {:e}", e - e0, wf - wf0 + wc - wc0);
                }
                let (wf, wc) = (st.path.last().unwrap().1, st.path.last().unwrap().2);
                assert!(wf.abs() > 1e-3 && wc.abs() > 1e-3, "{mass}: the forcing ({wf:e}) and the contacts ({wc:e}) must both work");
                println!("{mass} newmark-cn: accumulated balance worst {worst:.1e} (W_f = {wf:.4}, W_c = {wc:.4})");
            }
            println!("{mass} {name}: update residual {:.1e}, energy identity {:.1e}; contact levels per stop {hits:?}", st.residual.ratio, st.energy.ratio);
        }
    }
}

#[test]
fn paoli_schatzman_with_a_restitution_per_stop() {
    let mut st3 = stops();
    st3[0].e = Some(0.0);
    st3[2].e = Some(1.0);
    for mass in MASSES {
        for beta in [0.25, 0.35] {
            let (dy, o, init) = scene(mass, &st3, true);
            let spec = SchemeSpec::ps(0.5, beta);
            let mut s = spec.build(dy, 0.01, &init).unwrap();
            let traj = record(s.as_mut(), 400);
            let st = check_ps(&o, beta, 0.5, &init, &traj);
            assert!(st.active_per_contact.iter().all(|&k| k > 0), "{mass} {spec}: contact levels per stop {:?}", st.active_per_contact);
            println!("{mass} {spec}: residual {:.1e}, energy balance {:.1e}; contact levels per stop {:?}", st.residual.ratio, st.energy.ratio, st.active_per_contact);
        }
    }
}

#[test]
fn penalty_with_a_stiffness_per_stop() {
    let mut st3 = stops();
    st3[1].kappa = Some(500.0);
    let h = 1.0 / M as f64;
    let gamma_p = 10.0;
    // The springs as the test knows them: the stop's own, or γ_P K_cc.
    let kappas = [gamma_p / h, 500.0, gamma_p / h];
    for mass in MASSES {
        for explicit in [false, true] {
            if explicit && mass.massless_contact_node() {
                continue;
            }
            let (dy, o, init) = scene(mass, &st3, true);
            let (cf, dt) = if explicit {
                let mut kp = o.k.clone();
                for (s, k) in o.stops.iter().zip(kappas) {
                    kp[s.dof][s.dof] += k;
                }
                (Coefs::newmark(0.0, 0.5), 0.8 * 2.0 / kappa_max(&kp, &o.m).sqrt())
            } else {
                (Coefs::newmark(0.25, 0.5), 0.01)
            };
            let spec = SchemeSpec::penalty(gamma_p, explicit);
            let mut s = spec.build(dy, dt, &init).unwrap();
            let traj = record(s.as_mut(), (4.0 / dt) as usize);
            let st = check_one_step(&o, &o.k, cf, &init, &traj, recorded_force(&o, &traj), TOL);
            let all = traj.all_forces(0);
            let mut engaged = [0usize; 3];
            for l in 1..=traj.last() {
                let f = all[l].as_ref().unwrap();
                for (i, (s, k)) in o.stops.iter().zip(kappas).enumerate() {
                    let u = traj.at(l)[s.dof];
                    let want = -(k * (s.lo - u).max(0.0) - k * (u - s.hi).max(0.0));
                    engaged[i] += usize::from(want != 0.0);
                    let scale = k * (u.abs() + s.lo.abs().min(1.0) + s.hi.abs().min(1.0));
                    assert!((f[i] - want).abs() <= 1e-13 * scale, "{mass} {spec} level {l}, stop {i}: λ = {} but the spring law gives {want}", f[i]);
                }
            }
            assert!(engaged.iter().all(|&k| k > 0), "{mass} {spec}: springs engaged per stop {engaged:?}");
            println!("{mass} {spec} (dt {dt:.2e}): residual {:.1e}, energy identity {:.1e}; engaged per stop {engaged:?}", st.residual.ratio, st.energy.ratio);
        }
    }
}

#[test]
fn moreau_jean_with_three_stops() {
    let mut st3 = stops();
    st3[2].e = Some(0.7);
    for mass in [BarMass::Std, BarMass::Lumped] {
        for e in [0.0, 0.5] {
            let (dy, o, init) = scene(mass, &st3, false);
            let dt = 0.01;
            let spec = SchemeSpec::moreau_jean(0.5, e);
            let mut s = spec.build(dy, dt, &init).unwrap();
            let traj = record(s.as_mut(), 600);
            let (res_w, en_w, active) = check_moreau_jean(&o, e, &init, &traj);
            assert!(active.iter().all(|&k| k > 0), "{mass} e = {e}: impulses per stop {active:?}");
            println!("{mass} moreau-jean e = {e}: momentum residual {:.1e}, energy identity {:.1e}; impulses per stop {active:?}", res_w.ratio, en_w.ratio);
        }
    }
}
