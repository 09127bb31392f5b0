//! The autonomous shooting (period unknown, a phase condition, the energy
//! fixed) on a conservative oscillator against its period in closed form
//! (derived here), and the nonsmooth modes of the bar (`modes`) against
//! what holds independently of the code: the positive homogeneity of the
//! bar without gap, the continuous bar's closed form, and bad input.

use signorini_fem::SymBand;
use signorini_orbits::modes::{backbone, energies};
use signorini_orbits::{autonomous_orbit, Model, Newton, OrbitError};
use signorini_schemes::{Bounds, Contact, Dynamics};

/// `x'' + ω² x = 0` (mass `MASS`, stiffness `MASS ω²`) under an elastic
/// stop at `x = D`.
const MASS: f64 = 2.0;
const OMEGA: f64 = 1.5;
const D: f64 = 0.3;

fn oscillator(stop: f64) -> Model {
    let (m, k) = (SymBand::from_diagonal(&[MASS]), SymBand::from_diagonal(&[MASS * OMEGA * OMEGA]));
    Model::new(Dynamics::new(m, k, vec![0.0], vec![Contact::new(0, Bounds { lo: f64::NEG_INFINITY, hi: stop }, false)]), 1.0).unwrap()
}

/// The closed form: the energy `E` gives the amplitude `A = √(2E/(M ω²))`;
/// from `x = −A` at rest the mass rises as `−A cos ωt`, reaches the stop
/// `D < A` at `ωt₁ = arccos(−D/A)`, is reflected (e = 1) and retraces its
/// path: `T = 2 arccos(−D/A)/ω`; without touching (`D ≥ A`), `2π/ω`.
fn period(energy: f64, stop: f64) -> f64 {
    let a = (2.0 * energy / (MASS * OMEGA * OMEGA)).sqrt();
    if stop >= a {
        std::f64::consts::TAU / OMEGA
    } else {
        2.0 * (-stop / a).acos() / OMEGA
    }
}

#[test]
fn the_autonomous_shooting_finds_the_oscillators_period_and_energy() {
    let model = oscillator(D);
    for energy in [0.2, 0.21, 0.5, 1.0, 4.0] {
        let a = (2.0 * energy / (MASS * OMEGA * OMEGA)).sqrt();
        // A start off the orbit: 10 % too low, moving, and the period 20 % off.
        let guess = [-0.9 * a, 0.1 * a * OMEGA];
        let exact = period(energy, D);
        let orbit = autonomous_orbit(&model, &guess, 1.2 * exact, energy, &Newton::default()).unwrap();
        let (e, _) = model.energy(0.0, &orbit.x).unwrap();
        assert!((orbit.period - exact).abs() <= 1e-10 * exact, "E = {energy}: T = {} against {exact}", orbit.period);
        assert!((e - energy).abs() <= 1e-10 * energy, "E = {energy}: the orbit's energy {e}");
        assert_eq!(orbit.impacts(), usize::from(D < a), "one impact a period above the contact threshold E = M ω² D²/2 = 0.2025, none below");
        // The phase condition: the orbit is on the section through the
        // guess normal to the flow there (here: the mass at rest at its
        // lowest point moves along v; the section fixes the phase).
        assert!(orbit.residual <= 1e-10 * a);
    }
}

#[test]
fn the_autonomous_shooting_refuses_bad_input() {
    let model = oscillator(D);
    let n = Newton::default();
    assert!(matches!(autonomous_orbit(&model, &[0.1], 1.0, 1.0, &n), Err(OrbitError::Size { given: 1, expected: 2 })));
    assert!(matches!(autonomous_orbit(&model, &[-0.1, 0.0], 1.0, -1.0, &n), Err(OrbitError::Option { option: "energy", .. })));
    assert!(matches!(autonomous_orbit(&model, &[-0.1, 0.0], 0.0, 1.0, &n), Err(OrbitError::Option { option: "period", .. })));
    assert!(matches!(autonomous_orbit(&model, &[0.0, 0.0], 1.0, 1.0, &n), Err(OrbitError::NoConvergence { .. })));
}

fn bar(m: usize, mass: &str, scheme: &str, gap: f64) -> toml::Table {
    format!("[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"clamped\"\ngap = {gap:?}\nelements = {m}\nmass = \"{mass}\"\nscheme = \"{scheme}\"\ndt = 0.01\nt_end = 10.0\n").parse().unwrap()
}

/// The bar without gap is positively homogeneous (`u ↦ αu` maps motions
/// onto motions, docs/theory.md §11.3), and so is its discretisation with a
/// massless contact node: the discrete backbone must be flat, each point
/// the first one scaled. Measured at m = 10: T = 3.01764 (the exact
/// `3L/c` to 0.6 %), 13 landings a period (the massless node chatters),
/// unstable (|μ| = 2.51).
#[test]
fn the_redistributed_bar_without_gap_has_a_flat_backbone() {
    let modes = backbone(&bar(10, "mod", "event-driven", 0.0), 0.1, 2.0, 5).unwrap();
    assert!(modes.stopped.is_none(), "{:?}", modes.stopped);
    assert_eq!(modes.points.len(), 5);
    let (t0, x0) = (modes.points[0].period, &modes.points[0].orbit.x);
    for p in &modes.points {
        assert!((p.period - t0).abs() <= 1e-9 * t0, "E = {}: T = {} against {t0}", p.energy, p.period);
        let s = (p.energy / modes.points[0].energy).sqrt();
        let scaled = x0.iter().zip(&p.orbit.x).map(|(a, b)| (a * s - b).abs()).fold(0.0, f64::max);
        assert!(scaled <= 1e-8 * s, "E = {}: the orbit is not the first one scaled ({scaled:e})", p.energy);
        assert!((p.period - 3.0).abs() <= 0.02 * 3.0, "the period {} against 3L/c", p.period);
        assert_eq!(p.exact.map(|e| e.period), Some(3.0));
    }
    let csv = signorini_orbits::output::backbone_csv(&modes);
    let mut lines = csv.lines();
    assert!(lines.next().unwrap().starts_with("energy,period,contact_time,impacts_per_period,exact_period"));
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!((row[0], row[4]), ("1.000000000000e-1", "3.000000000000e0"));
    assert!(signorini_orbits::output::backbone_svg(&modes).unwrap().contains("<svg"));
}

/// The discrete flow from the continuous mode sampled at the nodes comes
/// back closest to its start at a time that tends to the exact period as
/// m grows (measured, g = 0, E = 1/2: error −0.225 at m = 10, −0.0315 at
/// m = 80 — about first order); at m = 80 within 0.05 of `3L/c`, at
/// m = 10 not within 0.2.
#[test]
fn the_closest_return_of_the_redistributed_bar_tends_to_the_exact_period() {
    let doc = |m| signorini_orbits::modes::ModeScene::new(&bar(m, "mod", "event-driven", 0.0)).unwrap();
    let t = |m| {
        let sc = doc(m);
        signorini_orbits::modes::closest_return(&sc.model, &sc.exact_state(0.5).unwrap(), 3.0, 0.2).unwrap().time
    };
    let (coarse, fine) = (t(10), t(80));
    assert!((fine - 3.0).abs() <= 0.05, "m = 80: {fine}");
    assert!((coarse - 3.0).abs() > 0.2, "m = 10: {coarse}");
}

#[test]
fn modes_refuse_bad_input() {
    let opt = |r: Result<signorini_orbits::modes::Modes, OrbitError>| match r {
        Err(OrbitError::Option { option, .. }) => option,
        other => panic!("{other:?}"),
    };
    let ok = bar(10, "mod", "event-driven", 0.0);
    assert_eq!(opt(backbone(&ok, -1.0, 1.0, 3)), "from");
    assert_eq!(opt(backbone(&ok, 1.0, 0.5, 3)), "to");
    assert_eq!(opt(backbone(&ok, 0.5, 1.0, 0)), "points");
    assert_eq!(opt(backbone(&bar(10, "mod", "newmark-cn", 0.0), 0.5, 1.0, 3)), "scheme");
    let free = ok.to_string().replace("\"clamped\"", "\"free\"").parse().unwrap();
    assert_eq!(opt(backbone(&free, 0.5, 1.0, 3)), "bar.far_end");
    assert_eq!(energies(1.0, 4.0, 3).unwrap(), vec![1.0, 2.0, 4.0]);
}

/// Below the threshold of a clearance (`E < c² g²/(2L)`) the backbone
/// starts from the discrete bar's first linear mode: its period must be
/// `2π/ω₁` of the bar's own matrices, computed here by inverse iteration
/// on `(K, M)` with the massless contact node condensed (`mod`: the first
/// element carries no mass), no contact, the multipliers on the unit circle.
#[test]
fn below_the_threshold_the_backbone_is_the_discrete_first_mode() {
    use signorini_fem::{Bar, BarMass, RightEnd};
    let m = 20;
    let b = Bar::new(1.0, m, 1.0, RightEnd::Clamped).unwrap();
    let (k, mm) = (b.stiffness(), b.mass(BarMass::Mod));
    let n = b.dofs();
    let kd = |i: usize, j: usize| if i.abs_diff(j) <= k.half_bandwidth() { k.get(i, j) } else { 0.0 };
    let md = |i: usize, j: usize| if i.abs_diff(j) <= mm.half_bandwidth() { mm.get(i, j) } else { 0.0 };
    assert_eq!(md(0, 0), 0.0, "mod: a massless contact node");
    // Condensed stiffness on dofs 1..n.
    let s = n - 1;
    let keff = faer::Mat::from_fn(s, s, |i, j| kd(i + 1, j + 1) - kd(i + 1, 0) * kd(0, j + 1) / kd(0, 0));
    let mss = faer::Mat::from_fn(s, s, |i, j| md(i + 1, j + 1));
    let lu = keff.partial_piv_lu();
    let mut x = faer::Mat::from_fn(s, 1, |i, _| 1.0 - i as f64 / s as f64);
    for _ in 0..400 {
        use faer::linalg::solvers::Solve;
        x = lu.solve(&(&mss * &x));
        let norm = (0..s).map(|i| x[(i, 0)] * x[(i, 0)]).sum::<f64>().sqrt();
        x *= faer::Scale(1.0 / norm);
    }
    let (kx, mx) = (&keff * &x, &mss * &x);
    let w2 = (0..s).map(|i| x[(i, 0)] * kx[(i, 0)]).sum::<f64>() / (0..s).map(|i| x[(i, 0)] * mx[(i, 0)]).sum::<f64>();
    let period = std::f64::consts::TAU / w2.sqrt();
    let modes = backbone(&bar(m, "mod", "event-driven", -0.25), 0.01, 0.02, 3).unwrap();
    assert_eq!(modes.points.len(), 3);
    for p in &modes.points {
        assert!((p.period - period).abs() <= 1e-9 * period, "E = {}: T = {} against 2π/ω₁ = {period}", p.energy, p.period);
        assert_eq!((p.impacts_per_period, p.contact_time), (0, 0.0));
        assert!(p.multipliers.iter().all(|mu| (mu.norm() - 1.0).abs() <= 1e-6), "{:?}", p.multipliers);
        assert_eq!(p.exact.map(|e| e.period), Some(4.0));
    }
}

/// `mod3` (the first element's mass moved onto the second: the total mass
/// kept) has, near the mode, a periodic orbit with one contact phase a
/// period whose period converges to the exact one (measured, g = 0,
/// E = 1/2: T − 3 = −4.6e-3, −2.6e-3, (no convergence at m = 40), −2.0e-4,
/// −4.6e-5 at m = 10, 20, 40, 80, 160). At m = 80 within 1e-3 of `3L/c`
/// (five times the measured error), one landing a period, the contact time
/// within 0.05 of `L/c` (measured 0.989), nearly neutral (|μ| = 1.03).
#[test]
fn mod3_has_a_periodic_orbit_near_the_mode_with_the_exact_period() {
    let modes = backbone(&bar(80, "mod3", "event-driven", 0.0), 0.5, 0.5, 1).unwrap();
    let p = &modes.points[0];
    assert!((p.period - 3.0).abs() <= 1e-3, "T = {}", p.period);
    assert_eq!(p.impacts_per_period, 1);
    assert!((p.contact_time - 1.0).abs() <= 0.05, "t_c = {}", p.contact_time);
    assert!(p.mu_max() < 1.1, "|μ| = {}", p.mu_max());
}

/// Huge energies in long steps (`modes --from 1e-2 --to 1e10 --points 4`,
/// the redistributed bar with a clearance): the guess extrapolated
/// linearly in the energy from the last two points is far off when the
/// energies' ratio is far from 1 (here a period of −181 at 1e6, and the
/// family ended there). The bar's positive homogeneity (`u ↦ αu` maps the
/// bar with gap `g` at energy `E` onto the one with `αg` at `α²E`) makes
/// the period a function of `g/√E` alone, smooth where no event changes:
/// `T(E) = T∞ + C g/√E + O(g²/E)`, so the periods at 1e2, 1e6, 1e10 step
/// down in the ratio √1e4 = 100 (measured: 100.0). Each orbit returns to
/// its state under the flow over its period.
#[test]
fn the_backbone_reaches_huge_energies_in_long_steps() {
    let doc = bar(10, "mod", "event-driven", -0.1);
    let modes = backbone(&doc, 1e-2, 1e10, 4).unwrap();
    assert!(modes.stopped.is_none(), "{:?}", modes.stopped.as_ref().map(|s| (s.0, s.1.to_string())));
    let t: Vec<f64> = modes.points.iter().map(|p| p.period).collect();
    assert_eq!(t.len(), 4);
    let ratio = (t[1] - t[2]) / (t[2] - t[3]);
    assert!((ratio - 100.0).abs() <= 1.0, "periods {t:?}: steps in the ratio {ratio}, not √(1e4) = 100");
    let scene = signorini_orbits::modes::ModeScene::new(&doc).unwrap();
    for p in &modes.points {
        let y = scene.model.flow(0.0, &p.orbit.x, p.period, false).unwrap().x;
        let size = p.orbit.x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let d = y.iter().zip(&p.orbit.x).fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
        assert!(d <= 1e-9 * size, "E = {}: the flow over T = {} ends {d:e} from the orbit's state (size {size:e})", p.energy, p.period);
    }
}

/// The lumped bar of 10 elements, gap 0.1, just above its contact
/// threshold (E = 0.006; 0.005 is the energy at which the exact bar's end
/// reaches the gap): Newton's first step took the period from the guess
/// 2.09 to 1.9e11, a flow of an event every ~80 time units that did not
/// end (`modes --from 0.006 --to 0.006 --points 1`). Now every trial
/// period is at most 4 times the guess. The search's work is counted
/// through the interrupt (polled every 256 steps): the whole shooting
/// must take fewer than a bound that the trial periods allow (31 Newton
/// iterations of 9 trials of at most 4 × 2.09, a few thousand steps
/// each), where the unbounded flow exhausted it; and the point found (or
/// the typed error) is checked against what holds independently.
#[test]
fn the_lumped_bar_above_its_threshold_ends() {
    use signorini_orbits::modes::{backbone_of, ModeScene};
    use std::sync::atomic::{AtomicU64, Ordering};
    use std::sync::Arc;
    let mut doc = bar(10, "lumped", "event-driven", 0.1);
    doc["bar"].as_table_mut().unwrap().insert("initial_displacement".into(), "0.1*(1-x)".into());
    let scene = ModeScene::new(&doc).unwrap();
    let polls = Arc::new(AtomicU64::new(0));
    let count = polls.clone();
    // 2e4 polls: 5e6 search steps.
    const BUDGET: u64 = 20_000;
    let model = scene.model.with_interrupt(Some(Arc::new(move || count.fetch_add(1, Ordering::Relaxed) >= BUDGET)));
    let scene = ModeScene { model, ..scene };
    let modes = backbone_of(&scene, &[0.006], &Newton { tol: 1e-11, scale: 1e-300, max_iter: 30, stall: 0 });
    let used = polls.load(Ordering::Relaxed);
    assert!(used < BUDGET, "the shooting took {used} polls of the search: a trial flow far beyond the period");
    match modes {
        Ok(m) => {
            let p = &m.points[0];
            assert!(p.period > 0.0 && p.period <= 4.0 * 2.1);
        }
        Err(OrbitError::NoConvergence { why, .. }) => assert!(why.contains("period"), "{why}"),
        Err(e) => panic!("{e}"),
    }
}

/// A map evaluation with more events than the model allows stops with the
/// orbit layer's own error, not the exact run's, whose message tells the
/// user to raise a scheme parameter that does not act here. The elastic
/// oscillator below its stop hits it once a period `2 arccos(−D/A)/ω`
/// (closed form above: about 3 s from `x = −0.5` at rest), so 20 s of flow
/// takes at least 6 impacts: over a limit of 3 events it must stop.
#[test]
fn a_map_with_more_events_than_allowed_names_the_orbit_layers_limit() {
    let model = oscillator(D).with_max_events(3);
    let x0 = model.pack(&[-0.5], &[0.0]);
    match model.flow(0.0, &x0, 20.0, false) {
        Err(e @ OrbitError::TooManyEvents { events, .. }) => {
            assert!(events > 3, "{events}");
            let m = e.to_string();
            assert!(!m.contains("scheme") && m.contains("evaluation of the map"), "{m}");
        }
        other => panic!("expected the orbit layer's event limit, got {other:?}"),
    }
    // Below the limit the same flow runs through.
    let within = oscillator(D).with_max_events(1000).flow(0.0, &x0, 20.0, false).unwrap();
    assert!(within.events.len() >= 6, "{}", within.events.len());
}

/// The same lumped bar at E = 0.006 with restitution 0 (the scheme's
/// default): Newton finds no orbit, and there is none with a flight to
/// find (theory §11.7). Independently of the shooting, a run of the flow
/// from the mode's start shows why: the contact node lands and is held
/// for good (no release over 10 periods of the mode). The error says so,
/// with Newton's residual, where it said only that Newton failed.
#[test]
fn the_lumped_bar_with_restitution_zero_says_its_node_stays_held() {
    use signorini_orbits::modes::ModeScene;
    use signorini_schemes::events::EventKind;
    let mut doc = bar(10, "lumped", "event-driven", 0.1);
    doc["bar"].as_table_mut().unwrap().insert("initial_displacement".into(), "0.1*(1-x)".into());
    let scene = ModeScene::new(&doc).unwrap();
    let x0 = scene.exact_state(0.006).unwrap();
    let period = scene.exact_point(0.006).unwrap().period;
    let run = scene.model.flow(0.0, &x0, 10.0 * period, false).unwrap();
    let kinds: Vec<_> = run.events.iter().map(|e| (e.kind, e.velocity_after)).collect();
    let landed = run.events.iter().any(|e| e.kind == EventKind::Accumulation || (e.kind == EventKind::Impact && e.velocity_after == 0.0));
    let released = run.events.iter().any(|e| e.kind == EventKind::Release);
    assert!(landed && !released, "the node lands and stays held: {kinds:?}");
    match backbone(&doc, 0.006, 0.006, 1) {
        Err(e @ OrbitError::NoConvergence { residual, .. }) => {
            let m = e.to_string();
            assert!(residual.is_finite() && m.contains(&format!("{residual:e}")), "{m}");
            assert!(m.contains("restitution 0") && m.contains("stays held") && m.contains("no periodic orbit with a flight"), "{m}");
        }
        other => panic!("expected Newton's failure, got {other:?}"),
    }
    // With restitution 0.5 nothing of the kind is said.
    let mut elastic = doc.clone();
    elastic["bar"].as_table_mut().unwrap().insert("scheme".into(), "event-driven(0.5)".into());
    if let Err(e) = backbone(&elastic, 0.006, 0.006, 1) {
        assert!(!e.to_string().contains("restitution 0"), "{e}");
    }
}
