//! The energy-growth monitor (`RunConfig::with_energy_warn`,
//! `RunSummary::energy`): the largest `E/budget` and the first level past
//! the factor (strictly), the budget being `E_ref + W_f − D` (closed: the
//! scheme's own load work and dissipation) or `E_ref + Σ|ΔW_f|` (open: the
//! runner's trapezoidal load work, for schemes that do not track theirs).
//!
//! Every expected value is computed here, independently: from a scripted
//! stepper's prescribed energy, work and dissipation; or from a real run's
//! energies and displacements recorded by an observer, with the load work
//! summed in the test by the trapezoid rule.

use signorini_contact::Active;
use signorini_fem::{BarMass, SymBand};
use signorini_run::{run, Benchmark, EnergyGrowth, Observer, RunConfig, RunError, Sample};
use signorini_schemes::{Bounds, Contact, Dynamics, SchemeError, SchemeSpec, StepReport, Stepper, TimeProfile};

/// A stepper with prescribed energy, load work and dissipation sequences
/// (`work: None`: it does not track work, the open budget applies).
struct Scripted {
    dy: Dynamics,
    dt: f64,
    n: usize,
    u: Vec<f64>,
    energy: fn(usize) -> f64,
    work: Option<fn(usize) -> (f64, f64)>,
}

impl Stepper for Scripted {
    fn label(&self) -> String {
        "scripted".into()
    }
    fn dt(&self) -> f64 {
        self.dt
    }
    fn level(&self) -> usize {
        self.n
    }
    fn displacement(&self) -> &[f64] {
        &self.u
    }
    fn dynamics(&self) -> &Dynamics {
        &self.dy
    }
    fn step(&mut self) -> Result<StepReport, SchemeError> {
        self.n += 1;
        let t = self.n as f64 * self.dt;
        Ok(StepReport { n: self.n, t, lambda: Some((t, 0.0)), active: Active::None })
    }
    fn energy(&mut self) -> Option<(f64, f64)> {
        Some((self.time(), (self.energy)(self.n)))
    }
    fn contact_forces(&self) -> &[f64] {
        &[0.0]
    }
    fn contact_status(&self) -> &[Active] {
        &[Active::None]
    }
    fn work(&self) -> Option<(f64, f64)> {
        self.work.map(|w| (w(self.n).0, 0.0))
    }
    fn dissipation(&self) -> Option<f64> {
        self.work.map(|w| w(self.n).1)
    }
}

fn scripted(energy: fn(usize) -> f64, work: Option<fn(usize) -> (f64, f64)>) -> Scripted {
    let (mass, stiffness) = (SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]));
    let dy = Dynamics::new(mass, stiffness, vec![0.0], vec![Contact::new(0, Bounds::obstacle(-1.0), false)]);
    Scripted { dy, dt: 0.125, n: 0, u: vec![0.0], energy, work }
}

fn monitor(s: &mut Scripted, steps: usize, factor: f64) -> EnergyGrowth {
    let cfg = RunConfig::new(s.dt, s.dt * steps as f64).unwrap().with_energy_warn(factor).unwrap();
    run(s, &[0.0], &cfg, &mut []).unwrap().energy.expect("the monitor ran")
}

#[test]
fn the_first_level_strictly_past_the_factor_is_recorded_once() {
    // E = 1 up to level 20, then 1 + (n − 20)/8 (exact in binary): exactly 2
    // at n = 28, past it from n = 29; no loads: the budget is E(0) = 1.
    fn e(n: usize) -> f64 {
        if n <= 20 {
            1.0
        } else {
            1.0 + (n - 20) as f64 / 8.0
        }
    }
    let g = monitor(&mut scripted(e, None), 40, 2.0);
    let x = g.exceeded.expect("the energy doubled");
    assert_eq!(x.step, 29, "{x:?}");
    assert_eq!((x.time, x.ratio, x.energy, x.budget), (29.0 * 0.125, e(29), e(29), 1.0));
    assert_eq!((g.max_ratio, g.max_ratio_time, g.factor, g.closed), (e(40), 40.0 * 0.125, 2.0, false));
    // Reaching the factor is not exceeding it: 3.5 is reached at the last level only.
    let g = monitor(&mut scripted(e, None), 40, 3.5);
    assert_eq!((g.exceeded, g.max_ratio), (None, 3.5));
}

#[test]
fn the_closed_budget_takes_the_load_work_and_the_dissipation() {
    // Energy that grows only by the work of the load: W_f = n/4, E = 1 + W_f.
    // Budget 1 + n/4: ratio 1 at every level (without the load work it would
    // pass 2 at n = 5).
    fn loaded(n: usize) -> f64 {
        1.0 + n as f64 / 4.0
    }
    fn loaded_work(n: usize) -> (f64, f64) {
        (n as f64 / 4.0, 0.0)
    }
    let g = monitor(&mut scripted(loaded, Some(loaded_work)), 12, 2.0);
    assert_eq!((g.exceeded, g.max_ratio, g.closed), (None, 1.0, true), "{g:?}");

    // Damping dissipates D = n/16 but the energy falls only by n/32: budget
    // 1 − n/16, ratio (1 − n/32)/(1 − n/16) = 2 at n = 32/3, past it at 11.
    fn damped(n: usize) -> f64 {
        1.0 - n as f64 / 32.0
    }
    fn damped_work(n: usize) -> (f64, f64) {
        (0.0, n as f64 / 16.0)
    }
    let g = monitor(&mut scripted(damped, Some(damped_work)), 12, 2.0);
    let x = g.exceeded.expect("past 2 at level 11");
    assert_eq!((x.step, x.budget), (11, 1.0 - 11.0 / 16.0));
    assert!((x.ratio - damped(11) / (1.0 - 11.0 / 16.0)).abs() <= 1e-15 * x.ratio);
    assert!((g.max_ratio - damped(12) / 0.25).abs() <= 1e-15 * g.max_ratio);
}

/// Records every level's energy (and its time) and the whole displacement.
#[derive(Default)]
struct Tape {
    n: Vec<usize>,
    t: Vec<f64>,
    e: Vec<(f64, f64)>,
    u: Vec<Vec<f64>>,
}

impl Observer for Tape {
    fn wants_energy(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if let Some(e) = s.energy {
            self.n.push(s.n);
            self.e.push(e);
        }
        self.t.push(s.t);
        self.u.push(s.u.to_vec());
        Ok(())
    }
}

/// `(first level with E > factor · budget, its time and ratio; max ratio)`
/// from recorded energies and budgets, by the documented rule.
fn expected(tape: &Tape, budget: &[f64], factor: f64) -> (Option<(usize, f64, f64)>, f64) {
    let r: Vec<f64> = tape.e.iter().zip(budget).map(|(e, b)| e.1 / b).collect();
    let first = (0..r.len()).find(|&i| r[i] > factor).map(|i| (tape.n[i], tape.e[i].0, r[i]));
    (first, r.iter().copied().fold(f64::NEG_INFINITY, f64::max))
}

fn bar_run(scheme: &str, mass: BarMass, m: usize, ratio: f64, t_end: f64, load: Option<(usize, TimeProfile)>) -> (EnergyGrowth, Tape) {
    let b = Benchmark::BarDirichlet;
    let ex = b.exact(t_end).unwrap();
    let mut p = b.problem(ex.as_ref(), m, mass).unwrap();
    if let Some((node, s)) = load {
        p = p.with_load(Some(node), s).unwrap();
    }
    let dt = p.bar.h() / ratio;
    let spec: SchemeSpec = scheme.parse().unwrap();
    let mut st = spec.build(p.dynamics(), dt, &p.initial).unwrap();
    let cfg = RunConfig::new(dt, t_end).unwrap().with_energy_warn(2.0).unwrap();
    let mut tape = Tape::default();
    let sum = run(st.as_mut(), &p.initial.u, &cfg, &mut [&mut tape]).unwrap();
    (sum.energy.unwrap(), tape)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs().max(1.0)
}

#[test]
fn newmark_cn_with_a_massive_contact_node_grows_and_is_caught_where_its_energy_doubles() {
    // bar-dirichlet, no load, no damping: the budget is E(0) = 1/8 (to rounding).
    let (g, tape) = bar_run("newmark-cn", BarMass::Std, 100, 1.0, 3.0, None);
    let e0 = tape.e[0].1;
    assert!((e0 - 0.125).abs() < 1e-12);
    let (first, max) = expected(&tape, &vec![e0; tape.e.len()], 2.0);
    let (step, time, ratio) = first.expect("newmark-cn std doubles its energy before t = 3");
    let x = g.exceeded.unwrap();
    assert_eq!(x.step, step);
    assert!(close(x.time, time) && close(x.ratio, ratio) && close(g.max_ratio, max), "{g:?} vs {first:?}, {max}");
    // After the first impact (t = 1), not before.
    assert!(x.time > 1.0 && x.time < 2.0, "{x:?}");
}

#[test]
fn conservative_and_dissipative_runs_stay_within_their_budget() {
    // newmark-cn with a massless contact node (mod): the energy never rises
    // above E(0); ps-e0 with std: contact only dissipates (docs/theory.md §7.3).
    for (scheme, mass) in [("newmark-cn", BarMass::Mod), ("ps-e0", BarMass::Std), ("ps-e0", BarMass::Mod)] {
        let (g, tape) = bar_run(scheme, mass, 100, 1.0, 30.0, None);
        let e_ref = tape.e[0].1;
        let (first, max) = expected(&tape, &vec![e_ref; tape.e.len()], 2.0);
        assert_eq!((g.exceeded, first), (None, None), "{scheme} {mass}");
        assert!(close(g.max_ratio, max) && max <= 1.0 + 1e-12, "{scheme} {mass}: {g:?}, {max}");
    }
}

#[test]
fn a_forced_bar_is_measured_against_its_initial_energy_plus_the_load_work() {
    // A point load s(t) = 0.3 sin(5t) at node 10 of 40. The load work is
    // summed here by the trapezoid rule from the recorded displacements: the
    // closed budget (newmark-cn, whose identity uses that rule) and the open
    // one (moreau-jean: Σ|ΔW|).
    let s = TimeProfile::Sine { amplitude: 0.3, omega: 5.0 };
    for scheme in ["newmark-cn", "moreau-jean"] {
        let (g, tape) = bar_run(scheme, BarMass::Std, 40, 2.0, 6.0, Some((10, s.clone())));
        let open = scheme == "moreau-jean";
        assert_eq!(g.closed, !open);
        let mut budget = vec![tape.e[0].1];
        let mut w = 0.0;
        for k in 1..tape.u.len() {
            let dw = 0.5 * (s.value(tape.t[k - 1]) + s.value(tape.t[k])) * (tape.u[k][10] - tape.u[k - 1][10]);
            w += if open { dw.abs() } else { dw };
            budget.push(tape.e[0].1 + w);
        }
        let (first, max) = expected(&tape, &budget, 2.0);
        assert!((g.max_ratio - max).abs() <= 1e-9 * max, "{scheme}: {} vs {max}", g.max_ratio);
        assert_eq!(g.exceeded.map(|x| x.step), first.map(|f| f.0), "{scheme}");
        // The load matters: against E(0) alone the ratio would be different.
        let (_, bare) = expected(&tape, &vec![tape.e[0].1; tape.e.len()], 2.0);
        assert!((bare - max).abs() > 0.05 * max, "{scheme}: the load does too little work to test the budget ({bare} vs {max})");
    }
}

#[test]
fn two_step_schemes_take_their_budget_from_the_half_step() {
    // ps-e0 with a load: E^{n+1/2} − E^{1/2} = W_f + W_c with W_c <= 0
    // (e = 0), so E/budget <= 1; the reference is E^{1/2} at t = dt/2.
    let s = TimeProfile::Sine { amplitude: 0.3, omega: 5.0 };
    let (g, tape) = bar_run("ps-e0", BarMass::Std, 40, 2.0, 6.0, Some((10, s)));
    assert_eq!(tape.n[0], 1);
    assert!(close(tape.e[0].0, 0.5 / 80.0));
    assert!(g.closed && g.exceeded.is_none() && g.max_ratio <= 1.0 + 1e-9, "{g:?}");
    assert!(g.max_ratio >= 1.0 - 1e-12, "starts at its budget: {g:?}");
}

#[test]
fn energy_warn_must_be_finite_and_above_one() {
    let cfg = RunConfig::new(0.1, 1.0).unwrap();
    assert_eq!(cfg.energy_warn, None, "no monitor by default");
    for bad in [1.0, 0.5, 0.0, -2.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        match cfg.clone().with_energy_warn(bad) {
            Err(e @ RunError::Invalid { field: "energy_warn", .. }) => assert!(e.to_string().contains("allowed finite and > 1"), "{e}"),
            other => panic!("{bad}: {other:?}"),
        }
    }
    assert_eq!(cfg.with_energy_warn(1.000001).unwrap().energy_warn, Some(1.000001));
}
