//! `moreau-jean(θ,e,γ)` against Siconos's `MoreauJeanOSI(θ, γ)`, step by
//! step, on the systems of `tests/siconos/moreau_jean.py` (its numbers are
//! kept in `data/siconos/moreau-jean.csv`, written by Siconos 4.4.0 from
//! Debian's python3-siconos: rerun the script to regenerate them).
//!
//! Three dofs, `M q'' + C q' + K q = F`, a steady load, one contact
//! (`q_0 >= 0`, e = ½) or two (`q_0 >= 0` and `q_2 <= 0.08`, e = ½ or 0
//! and 0.8, each its own restitution), with and without Rayleigh damping;
//! θ ∈ {½, ¾, 1}, γ ∈ {0, ½, 1}; 300 steps of 0.01 with resting contact,
//! impacts and releases. Siconos solves its LCP by Lemke's method, we by
//! the closed-form projection (one contact) or the exact multi-contact
//! solve: positions, velocities and impulses agree to 1e-10 of their
//! scale at every step.
//!
//! The same for `moreau-jean-projected(θ,e,γ)` (Siconos's direct
//! projection, `data/siconos/moreau-jean-projected.csv`) and
//! `moreau-jean-combined(θ,e)` (its combined projection,
//! `data/siconos/moreau-jean-combined.csv`).

use signorini_fem::SymBand;
use signorini_schemes::{Bounds, Contact, D1Level, D1MinusLinear, Dynamics, Initial, MoreauJeanCombined, SchemeSpec, Stepper};

const M: [[f64; 3]; 3] = [[2.0 / 6.0, 1.0 / 6.0, 0.0], [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0], [0.0, 1.0 / 6.0, 2.0 / 6.0]];
const K: [[f64; 3]; 3] = [[30.0, -30.0, 0.0], [-30.0, 60.0, -30.0], [0.0, -30.0, 30.0]];
const F: [f64; 3] = [-2.0, 0.1, 1.5];
const F_DOWN: [f64; 3] = [-2.0, -0.5, -0.5];
const Q0: [f64; 3] = [0.05, 0.0, -0.02];
const V0: [f64; 3] = [-1.0, 0.3, 0.8];
const HI: f64 = 0.08;
const DT: f64 = 0.01;

fn band(a: impl Fn(usize, usize) -> f64) -> SymBand {
    let mut s = SymBand::zeros(3, 2);
    for i in 0..3 {
        for j in 0..=i {
            s.set(i, j, a(i, j));
        }
    }
    s
}

/// The case's problem, as the script builds it for Siconos.
fn dynamics(case: &str) -> Dynamics {
    let (contacts, damped, load) = match case {
        "one-contact" => (vec![Contact::new(0, Bounds::obstacle(0.0), false).with_restitution(Some(0.5))], false, F_DOWN),
        "two-contacts" | "two-contacts-damped" | "two-contacts-loaded" => {
            let e0 = if case == "two-contacts-damped" { 0.0 } else { 0.5 };
            let upper = Bounds { lo: f64::NEG_INFINITY, hi: HI };
            // The loaded case (projected runs only): twice F.
            let load = if case == "two-contacts-loaded" { F.map(|f| 2.0 * f) } else { F };
            (vec![Contact::new(0, Bounds::obstacle(0.0), false).with_restitution(Some(e0)), Contact::new(2, upper, false).with_restitution(Some(0.8))], case.ends_with("damped"), load)
        }
        other => panic!("unknown case {other}"),
    };
    // Siconos's M, and its C = 0.1 M + 0.05 K, written as the script does (M = [..] / 6).
    let m = |i: usize, j: usize| [[2.0, 1.0, 0.0], [1.0, 4.0, 1.0], [0.0, 1.0, 2.0]][i][j] / 6.0;
    assert!((0..3).all(|i| (0..3).all(|j| m(i, j) == M[i][j])));
    let dy = Dynamics::new(band(m), band(|i, j| K[i][j]), load.to_vec(), contacts);
    dy.with_damping(damped.then(|| band(|i, j| 0.1 * m(i, j) + 0.05 * K[i][j])))
}

struct Row {
    step: usize,
    q: [f64; 3],
    v: [f64; 3],
    p: [f64; 2],
    /// Siconos's projection iterations in the step (the projected runs).
    projections: usize,
    /// Siconos's index-set passes in the step (the combined runs).
    passes: u64,
}

fn siconos_runs(file: &str) -> Vec<((String, f64, f64), Vec<Row>)> {
    let path = format!("{}/../../data/siconos/{file}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("data/siconos/{file} (tests/siconos/moreau_jean.py writes it): {e}"));
    let mut runs: Vec<((String, f64, f64), Vec<Row>)> = Vec::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let x = |i: usize| f[i].parse::<f64>().unwrap();
        let key = (f[0].to_string(), x(1), x(2));
        let projections = f.get(13).map_or(0, |n| n.parse().unwrap());
        let passes = f.get(14).map_or(0, |n| n.parse().unwrap());
        let row = Row { step: f[3].parse().unwrap(), q: [x(5), x(6), x(7)], v: [x(8), x(9), x(10)], p: [x(11), x(12)], projections, passes };
        match runs.last_mut() {
            Some((k, rows)) if *k == key => rows.push(row),
            _ => runs.push((key, vec![row])),
        }
    }
    runs
}

/// Runs `spec(θ, γ)` next to every run of `file`; the worst difference
/// (of the velocity scale), the impulses and the steps Siconos projected.
fn compare(file: &str, n_runs: usize, spec: impl Fn(f64, f64) -> SchemeSpec) -> (f64, usize, usize) {
    let runs = siconos_runs(file);
    assert_eq!(runs.len(), n_runs, "3 systems × 5 (θ, γ) (× 3 θ, combined), and the projected runs' loaded one");
    let mut worst = 0.0f64;
    let (mut impulses, mut projected) = (0, 0);
    for ((case, theta, gamma), rows) in &runs {
        let dy = dynamics(case);
        let k = dy.contacts.len();
        let init = Initial { u: Q0.to_vec(), v: V0.to_vec() };
        assert_eq!((rows[0].q, rows[0].v), (Q0, V0), "{case}: the script's initial state");
        // The scheme's own restitution is overridden by each contact's.
        let spec = spec(*theta, *gamma);
        let mut s = spec.build(dy, DT, &init).unwrap();
        for r in &rows[1..] {
            let rep = s.step().unwrap();
            assert_eq!(rep.n, r.step);
            projected += usize::from(r.projections > 0);
            let st = s.state().unwrap();
            let (q, v) = (&st[..3], &st[3..]);
            let scale = 1.0 + r.v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for i in 0..3 {
                let d = ((q[i] - r.q[i]).abs() / scale).max((v[i] - r.v[i]).abs() / scale);
                worst = worst.max(d);
                assert!(d <= 1e-10, "{spec} on {case}, step {}: dof {i}: q {} vs Siconos {}, v {} vs {}", r.step, q[i], r.q[i], v[i], r.v[i]);
            }
            // The impulses: ours is signed along the dof (λ = −p/dt), Siconos's
            // along its constraint's normal (`y = hi − q_2`: the opposite sign
            // at an upper bound); the second column is dof 2's contact.
            let lams = s.contact_forces();
            for (j, lam) in lams.iter().enumerate().take(k) {
                let normal = if j == 1 { -1.0 } else { 1.0 };
                let p = -normal * lam * DT;
                impulses += usize::from(r.p[j] != 0.0);
                assert!((p - r.p[j]).abs() <= 1e-10 * scale, "{spec} on {case}, step {}: impulse {j} {p} vs Siconos {}", r.step, r.p[j]);
            }
        }
    }
    (worst, impulses, projected)
}

#[test]
fn moreau_jean_equals_siconos_moreau_jean_osi_step_by_step() {
    let (worst, impulses, _) = compare("moreau-jean.csv", 15, |theta, gamma| SchemeSpec::moreau_jean_gamma(theta, 0.0, gamma));
    println!("moreau-jean vs Siconos MoreauJeanOSI: 15 runs × 300 steps, {impulses} impulses, worst difference {worst:.1e} of the velocity scale");
    assert!(impulses > 1000, "{impulses} impulses: the runs must be contact-heavy");
}

/// `moreau-jean-projected(θ,e,γ)` against Siconos's
/// `MoreauJeanDirectProjectionOSI(θ, γ)` with `TimeSteppingDirectProjection`
/// and `MLCPProjectOnConstraints` (the index set's thresholds, the
/// projection's tolerance and metric at Siconos's defaults), step by step.
#[test]
fn moreau_jean_projected_equals_siconos_direct_projection_step_by_step() {
    let (worst, impulses, projected) = compare("moreau-jean-projected.csv", 16, |theta, gamma| SchemeSpec::moreau_jean_projected(theta, 0.0, gamma));
    println!(
        "moreau-jean-projected vs Siconos MoreauJeanDirectProjectionOSI: 16 runs × 300 steps, {impulses} impulses, {projected} projected steps, worst difference {worst:.1e} of the velocity scale"
    );
    assert!(impulses > 1000, "{impulses} impulses: the runs must be contact-heavy");
    assert!(projected > 1000, "{projected} projected steps: the projection must act");
}

/// `moreau-jean-combined(θ,e)` against Siconos's
/// `MoreauJeanCombinedProjectionOSI(θ)` with `TimeSteppingCombinedProjection`
/// and `MLCPProjectOnConstraints` (index set from the step's positions, the
/// step redone while it grows, projection on equalities, tolerance 1e-8),
/// step by step: the 3 systems at θ ∈ {½, ¾, 1} and the loaded one at ½.
#[test]
fn moreau_jean_combined_equals_siconos_combined_projection_step_by_step() {
    let (worst, impulses, projected) = compare("moreau-jean-combined.csv", 10, |theta, _| SchemeSpec::moreau_jean_combined(theta, 0.0));
    println!(
        "moreau-jean-combined vs Siconos MoreauJeanCombinedProjectionOSI: 10 runs × 300 steps, {impulses} impulses, {projected} projected steps, worst difference {worst:.1e} of the velocity scale"
    );
    assert!(impulses > 1000, "{impulses} impulses: the runs must be contact-heavy");
    assert!(projected > 300, "{projected} projected steps: the projection must act");
    // The passes (steps redone while the index set grows), step by step.
    let mut redone = 0;
    for ((case, theta, _), rows) in siconos_runs("moreau-jean-combined.csv") {
        let init = Initial { u: Q0.to_vec(), v: V0.to_vec() };
        let mut s = MoreauJeanCombined::new("c".into(), dynamics(&case), theta, 0.0, DT, &init).unwrap();
        for r in &rows[1..] {
            let before = s.passes();
            s.step().unwrap();
            assert_eq!(s.passes() - before, r.passes, "{case}, θ = {theta}, step {}: passes", r.step);
            redone += usize::from(r.passes > 1);
        }
    }
    assert!(redone > 1000, "{redone} redone steps: the index set must grow within steps");
}

/// `d1-minus-linear(e)` against Siconos's `D1MinusLinearOSI`
/// (`halfexplicit_acceleration_level`) with `TimeSteppingD1Minus` and two
/// `LCP()`, step by step, on the same three systems
/// (`data/siconos/d1-minus-linear.csv`, written by the C++ harness
/// `tests/siconos/d1_minus_linear.cpp` against Siconos 4.4.0's shared
/// libraries; its recipe is in its header). The damped system goes
/// through [`D1MinusLinear::new`] (the registry refuses a damping matrix
/// for this explicit scheme), the others through the registry as well,
/// bit for bit the same. Positions, velocities and the impulses `Λ`
/// (Siconos's `lambda(1)`) agree to 1e-10 of the velocity scale.
#[test]
fn d1_minus_linear_equals_siconos_d1_minus_linear_osi_step_by_step() {
    let (worst, impulses, impacts, _) = d1_against_siconos(D1Level::Acceleration, 1e-10);
    println!("d1-minus-linear vs Siconos D1MinusLinearOSI: 3 runs × 300 steps, {impulses} impulses, {impacts} impact steps, worst difference {worst:.1e} of the velocity scale");
    assert!(impulses > 300 && impacts > 5, "{impulses} impulses, {impacts} impact steps: the runs must be contact-heavy");
}

/// `d1-minus-linear-velocity(e)` against the same harness's
/// `halfexplicit_velocity_level` rows of `data/siconos/d1-minus-linear.csv`,
/// step by step: positions, velocities, the impulses `Λ` (`lambda(1)`) and
/// the end's velocity-level multipliers `μ⁻` (`lambda(2)`, zero in a step
/// where a contact closed) to 1e-12 of the velocity scale.
#[test]
fn d1_minus_linear_velocity_equals_siconos_velocity_level_step_by_step() {
    let (worst, impulses, impacts, smooth) = d1_against_siconos(D1Level::Velocity, 1e-12);
    println!("d1-minus-linear-velocity vs Siconos D1MinusLinearOSI(halfexplicit_velocity_level): 3 runs × 300 steps, {impulses} impulses above 1e-9, {smooth} end impulses μ⁻, {impacts} impact steps, worst difference {worst:.1e} of the velocity scale");
    // Without an impact Λ is zero up to rounding (H V_f >= 0 already):
    // the impulses counted are those above 1e-9.
    assert!(impulses > 30 && impacts > 5 && smooth > 300, "{impulses} impulses, {smooth} end impulses, {impacts} impact steps: the runs must be contact-heavy");
}

/// The rows of `level` against the scheme on that level; the worst
/// difference and the counts of impulses (nonzero; above 1e-9 on the
/// velocity level), impact steps and nonzero `lambda(2)` compared
/// (velocity level only).
fn d1_against_siconos(level: D1Level, tol: f64) -> (f64, usize, usize, usize) {
    let name = match level {
        D1Level::Acceleration => "acceleration",
        D1Level::Velocity => "velocity",
    };
    let spec = |e: f64| match level {
        D1Level::Acceleration => SchemeSpec::d1_minus_linear(e),
        D1Level::Velocity => SchemeSpec::d1_minus_linear_velocity(e),
    };
    let path = format!("{}/../../data/siconos/d1-minus-linear.csv", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("data/siconos/d1-minus-linear.csv (tests/siconos/d1_minus_linear.cpp writes it): {e}"));
    // Per case, the rows with Siconos's lambda(2) (f0, f2).
    type Run = (String, Vec<(Row, [f64; 2])>);
    let mut runs: Vec<Run> = Vec::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f[1] != name {
            continue;
        }
        let x = |i: usize| f[i].parse::<f64>().unwrap();
        let row = Row { step: f[2].parse().unwrap(), q: [x(4), x(5), x(6)], v: [x(7), x(8), x(9)], p: [x(10), x(11)], projections: 0, passes: 0 };
        match runs.last_mut() {
            Some((k, rows)) if k == f[0] => rows.push((row, [x(12), x(13)])),
            _ => runs.push((f[0].to_string(), vec![(row, [x(12), x(13)])])),
        }
    }
    assert_eq!(runs.len(), 3, "three systems");
    let (mut worst, mut impulses, mut impacts, mut smooth) = (0.0f64, 0, 0, 0);
    for (case, rows) in &runs {
        let init = Initial { u: Q0.to_vec(), v: V0.to_vec() };
        assert_eq!((rows[0].0.q, rows[0].0.v), (Q0, V0), "{case}: the harness's initial state");
        let dy = dynamics(case);
        let damped = dy.damping.is_some();
        let mut s = D1MinusLinear::at_level(level, "d1".into(), dy.clone(), 0.0, DT, &init).unwrap();
        let mut via_registry = (!damped).then(|| spec(0.0).build(dy.clone(), DT, &init).unwrap());
        if damped {
            assert!(spec(0.0).build(dy, DT, &init).is_err(), "the registry refuses damping");
        }
        for (r, f) in &rows[1..] {
            let rep = s.step().unwrap();
            assert_eq!(rep.n, r.step);
            impacts += usize::from(s.impact());
            let (q, v) = (s.displacement(), s.velocity());
            if let Some(o) = via_registry.as_mut() {
                o.step().unwrap();
                assert_eq!(o.state().unwrap(), s.state().unwrap(), "{case}, step {}: the registry's run", r.step);
            }
            let scale = 1.0 + r.v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for i in 0..3 {
                let d = ((q[i] - r.q[i]).abs() / scale).max((v[i] - r.v[i]).abs() / scale);
                worst = worst.max(d);
                assert!(d <= tol, "{name} level on {case}, step {}: dof {i}: q {} vs Siconos {}, v {} vs {}", r.step, q[i], r.q[i], v[i], r.v[i]);
            }
            // Along the dof; Siconos's along its constraint's normal (the
            // opposite sign at the upper stop of dof 2, contact 1).
            let normal = |j: usize, x: f64| if j == 1 { -x } else { x };
            for (j, big) in s.impulses().iter().enumerate() {
                let p = normal(j, *big);
                impulses += usize::from(match level {
                    D1Level::Acceleration => r.p[j] != 0.0,
                    D1Level::Velocity => r.p[j].abs() > 1e-9,
                });
                worst = worst.max((p - r.p[j]).abs() / scale);
                assert!((p - r.p[j]).abs() <= tol * scale, "{name} level on {case}, step {}: impulse {j} {p} vs Siconos {}", r.step, r.p[j]);
            }
            // On the velocity level Siconos's lambda(2) at the step's end is μ⁻.
            if level == D1Level::Velocity {
                for (j, mu) in s.forces().1.iter().enumerate() {
                    let m = normal(j, *mu);
                    smooth += usize::from(f[j] != 0.0);
                    worst = worst.max((m - f[j]).abs() / scale);
                    assert!((m - f[j]).abs() <= tol * scale, "{name} level on {case}, step {}: μ⁻ {j} {m} vs Siconos's lambda(2) {}", r.step, f[j]);
                }
            }
        }
    }
    (worst, impulses, impacts, smooth)
}
