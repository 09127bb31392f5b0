//! The sweep's lockstep path (beam runs sharing a step matrix stepped
//! together) writes exactly what the one-run path writes: every Poincaré
//! sample, impact and summary cell, bit for bit, for lanes with different
//! frequencies (so different horizons and section times), amplitudes and a
//! partial batch.

use signorini_cli::scene::Limits;
use signorini_cli::sweep::{simulate, simulate_lockstep, Axis, Sweep, SweepOptions};

#[test]
fn lockstep_lanes_are_the_single_runs_bit_for_bit() {
    let text = "[beam]\nscene = \"fig2\"\n\n[support]\namplitude = 0.2\nomega = 10.0\n";
    let mut o = SweepOptions::new("support.omega", 8.0, 12.0, 3);
    o.second = Some(Axis { param: "support.amplitude".into(), from: 0.15, to: 0.25, count: 2, log: false });
    o.transient = 2.0;
    o.record = 3.0;
    o.phase = 1.0;
    let sweep = Sweep::new(text, "beam.toml", None, o, Limits { max_memory: 1e9 }).unwrap();
    let runs: Vec<_> = (0..6).map(|r| sweep.scene(sweep.options().value(r)).unwrap()).collect();
    // Engines of 4 lanes (full) and 2, and of 8 with 6 lanes (partial).
    for group in [&runs[..4], &runs[4..], &runs[..]] {
        let pairs: Vec<_> = group.iter().map(|(_, s, p)| (s, p)).collect();
        let lock = simulate_lockstep(&pairs, None).expect("beam runs on the tip's stops share the engine");
        for ((_, scene, plan), l) in group.iter().zip(&lock) {
            let one = simulate(scene, plan, None, false, None);
            assert_eq!(l.status, "ok");
            assert_eq!((l.steps, &l.status, &l.summary), (one.steps, &one.status, &one.summary));
            assert!(!one.poincare.is_empty() && !one.impacts.is_empty());
            let bits = |v: &[[f64; 4]]| v.iter().flat_map(|r| r.map(f64::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(&l.poincare), bits(&one.poincare));
            let ibits = |v: &[(usize, [f64; 5])]| v.iter().flat_map(|(s, r)| std::iter::once(*s as u64).chain(r.map(f64::to_bits))).collect::<Vec<_>>();
            assert_eq!(ibits(&l.impacts), ibits(&one.impacts));
        }
    }
}

/// A group of 11 runs takes the 16-lane engine (5 lanes padded): every lane
/// still writes its single run's rows, bit for bit.
#[test]
fn a_group_of_eleven_takes_the_sixteen_lane_engine_bit_for_bit() {
    let text = "[beam]\nscene = \"fig2\"\n\n[support]\namplitude = 0.2\nomega = 10.0\n";
    let mut o = SweepOptions::new("support.omega", 8.0, 13.0, 11);
    o.transient = 1.0;
    o.record = 2.0;
    let sweep = Sweep::new(text, "beam.toml", None, o, Limits { max_memory: 1e9 }).unwrap();
    let runs: Vec<_> = (0..11).map(|r| sweep.scene(sweep.options().value(r)).unwrap()).collect();
    let pairs: Vec<_> = runs.iter().map(|(_, s, p)| (s, p)).collect();
    let lock = simulate_lockstep(&pairs, None).expect("11 beam runs on the tip's stops share one engine");
    assert_eq!(lock.len(), 11);
    let bits = |v: &[[f64; 4]]| v.iter().flat_map(|r| r.map(f64::to_bits)).collect::<Vec<_>>();
    for (k, ((_, scene, plan), l)) in runs.iter().zip(&lock).enumerate() {
        let one = simulate(scene, plan, None, false, None);
        assert_eq!(one.status, "ok");
        assert!(!one.impacts.is_empty(), "run {k} must reach the stops for the test to mean anything");
        assert_eq!((l.steps, &l.status, &l.summary), (one.steps, &one.status, &one.summary), "run {k}");
        assert_eq!(bits(&l.poincare), bits(&one.poincare), "run {k}");
        assert_eq!(l.impacts.len(), one.impacts.len(), "run {k}");
    }
}

#[test]
fn runs_that_do_not_share_a_matrix_are_not_locked() {
    // A sweep over the mesh: different matrices, one run at a time.
    let text = "[beam]\nscene = \"fig2\"\n\n[support]\namplitude = 0.2\nomega = 10.0\n";
    let mut o = SweepOptions::new("beam.elements", 10.0, 12.0, 2);
    o.transient = 0.0;
    o.record = 1.0;
    let sweep = Sweep::new(text, "beam.toml", None, o, Limits { max_memory: 1e9 }).unwrap();
    let runs: Vec<_> = (0..2).map(|r| sweep.scene(sweep.options().value(r)).unwrap()).collect();
    let pairs: Vec<_> = runs.iter().map(|(_, s, p)| (s, p)).collect();
    assert!(simulate_lockstep(&pairs, None).is_none());
}

/// A lane that blows up stops where its single run stops: the same steps,
/// status (step and time of the blow-up) and rows, while the other lanes go
/// on to their horizons.
#[test]
fn a_lane_that_blows_up_stops_where_its_single_run_does() {
    for scheme in ["projection", "nsga(0.5)", "contact-stabilized", "moreau-jean-projected(1,0)", "cd-lagrange(0)", "d1-minus-linear(0)", "d1-minus-linear-velocity(0.5)"] {
        lane_blows_up(scheme);
    }
}

fn lane_blows_up(scheme: &str) {
    let text = if scheme == "projection" {
        "[beam]\nscene = \"fig2\"\n\n[support]\namplitude = 0.2\nomega = 10.0\n".to_string()
    } else {
        format!("[beam]\nscene = \"fig2\"\nscheme = \"{scheme}\"\n{}\n[support]\namplitude = 0.2\nomega = 10.0\n", explicit_dt(scheme))
    };
    let text = text.as_str();
    let mut o = SweepOptions::new("support.amplitude", 0.2, 1e303, 3);
    o.transient = 0.0;
    o.record = 1.0;
    let sweep = Sweep::new(text, "beam.toml", None, o, Limits { max_memory: 1e9 }).unwrap();
    let runs: Vec<_> = (0..3).map(|r| sweep.scene(sweep.options().value(r)).unwrap()).collect();
    let pairs: Vec<_> = runs.iter().map(|(_, s, p)| (s, p)).collect();
    let lock = simulate_lockstep(&pairs, None).expect("one engine");
    let bits = |v: &[[f64; 4]]| v.iter().flat_map(|r| r.map(f64::to_bits)).collect::<Vec<_>>();
    for (k, ((_, scene, plan), l)) in runs.iter().zip(&lock).enumerate() {
        let one = simulate(scene, plan, None, false, None);
        if k == 0 {
            assert_eq!(one.status, "ok");
        } else {
            assert!(one.status.contains("blew up"), "{scheme} run {k}: {}", one.status);
            assert!(one.steps < 12_566, "{scheme} run {k} stopped early: {}", one.steps);
        }
        assert_eq!((l.steps, &l.status), (one.steps, &one.status), "{scheme} run {k}");
        assert_eq!(l.summary, one.summary, "{scheme} run {k}");
        assert_eq!(bits(&l.poincare), bits(&one.poincare), "{scheme} run {k}");
    }
}

/// `[beam] dt = 1e-5` for the explicit schemes (below their limit,
/// 1.2395e-5 on fig. 2), nothing for the others (fig. 2's 5e-5).
fn explicit_dt(scheme: &str) -> &'static str {
    if scheme.starts_with("cd-lagrange") || scheme.starts_with("d1-minus-linear") {
        "dt = 1e-5\n"
    } else {
        ""
    }
}

/// A sweep of a registry-named scheme that can run in lockstep
/// (`Capabilities::lockstep`: `ps(e, β)`, with restitution and any β,
/// `moreau-jean(θ, e, γ)`, `moreau-jean-projected(θ, e, γ)`, `nsga(ρ∞, e)`,
/// `contact-stabilized`, `cd-lagrange(e)`, `d1-minus-linear(e)` on both
/// levels and `moreau-jean-combined(θ, e)`) takes its engine, each lane its
/// single run bit for bit; schemes that cannot (penalty, Newmark, the
/// event-driven reference) run one at a time.
#[test]
fn registry_schemes_that_can_run_in_lockstep_do() {
    let bits = |v: &[[f64; 4]]| v.iter().flat_map(|r| r.map(f64::to_bits)).collect::<Vec<_>>();
    let ibits = |v: &[(usize, [f64; 5])]| v.iter().flat_map(|(s, r)| std::iter::once(*s as u64).chain(r.map(f64::to_bits))).collect::<Vec<_>>();
    for (scheme, locks) in [
        ("ps(0.5,0.5)", true),
        ("ps-e1", true),
        ("ps(0.8,0.3)", true),
        ("moreau-jean", true),
        ("moreau-jean(0.7,0.5)", true),
        ("moreau-jean(0.5,0,0.3)", true),
        ("moreau-jean(1,1)", true),
        ("nsga(0.5)", true),
        ("nsga(0,0.5)", true),
        ("nsga(1,1)", true),
        ("contact-stabilized", true),
        ("moreau-jean-projected(0.5,0)", true),
        ("moreau-jean-projected(0.7,0.5,0.3)", true),
        ("cd-lagrange(0)", true),
        ("cd-lagrange(0.5)", true),
        ("d1-minus-linear(0)", true),
        ("d1-minus-linear(0.5)", true),
        ("d1-minus-linear-velocity(0)", true),
        ("d1-minus-linear-velocity(0.5)", true),
        ("moreau-jean-combined(0.7,0.3)", true),
        ("moreau-jean-combined(0.5,0)", true),
        ("penalty-cn", false),
        ("newmark-cn", false),
        ("event-driven", false),
    ] {
        let text = format!("[beam]\nscene = \"fig2\"\nscheme = \"{scheme}\"\n{}\n[support]\namplitude = 0.2\nomega = 10.0\n", explicit_dt(scheme));
        let mut o = SweepOptions::new("support.omega", 9.0, 11.0, 3);
        o.transient = 1.0;
        o.record = 2.0;
        let sweep = Sweep::new(&text, "beam.toml", None, o, Limits { max_memory: 1e9 }).unwrap();
        let runs: Vec<_> = (0..3).map(|r| sweep.scene(sweep.options().value(r)).unwrap()).collect();
        let pairs: Vec<_> = runs.iter().map(|(_, s, p)| (s, p)).collect();
        let Some(lock) = simulate_lockstep(&pairs, None) else {
            assert!(!locks, "{scheme}: a scheme that can run in lockstep was run one at a time");
            continue;
        };
        assert!(locks, "{scheme}: cannot run in lockstep, yet the engine took it");
        for ((_, scene, plan), l) in runs.iter().zip(&lock) {
            let one = simulate(scene, plan, None, false, None);
            assert_eq!((l.steps, &l.status, &l.summary), (one.steps, &one.status, &one.summary), "{scheme}");
            assert!(!one.impacts.is_empty(), "{scheme}: the runs must reach the stops for the test to mean anything");
            assert_eq!(bits(&l.poincare), bits(&one.poincare), "{scheme}");
            assert_eq!(ibits(&l.impacts), ibits(&one.impacts), "{scheme}");
        }
    }
}
