//! An event inside an accumulation's tail (docs/theory.md §9.3, "An event
//! inside an accumulation's tail"): free consistent-mass chains on three
//! stops (under both ends, a two-sided one at mid-chain), `0 < e < 1`,
//! found by a sampling hunt (400 random chains: 67 rows logged before an
//! earlier row's time, in 9 of them). A contact lifted by another's
//! accumulation joins it at rest, its row at the limit of its rebounds
//! `t_k + 2w/(|a|(1 − e))`, or a run of impacts its geometric limit;
//! another contact, free, arrived before that time and its impact was
//! logged after the accumulation but earlier (1.3e-8 to 1.5e-6 s). Case
//! 301 has the accumulated contact's own impact (the LCP of another's
//! arrival gives it an impulse) logged inside its own tail.
//!
//! Oracles, none of them the run's own accessors: the free chain's
//! momentum `Σ_c p_c = ΔP − ∫ 1ᵀ f` over every output step (`1ᵀ K = 0`,
//! `C = b K`, the harmonic load integrated in closed form here), the same
//! state bits and events sampled at `dt` and `dt/4`, and the events in
//! time order.

use crate::events_common as common;
use signorini_schemes::events::{EventKind, EventStepper};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, Initial, Stepper, TimeProfile};
use std::sync::Arc;

struct Case {
    name: &'static str,
    dy: Dynamics,
    e: f64,
    v0: Vec<f64>,
    f0: Vec<f64>,
    shape: Vec<f64>,
    wave: (f64, f64, f64),
}

/// The free chain of `v0.len()` dofs with `C = b K` (none for `b = 0`),
/// stops under dof 0 at `lo0`, under the last at `lo1`, and `[-0.2, 0.2]`
/// at `mid`; the load `f0 + shape A sin(ω t + p)`, `wave = (A, ω, p)`.
fn case(name: &'static str, (e, b): (f64, f64), (lo0, lo1, mid): (f64, f64, usize), f0: Vec<f64>, shape: Vec<f64>, wave: (f64, f64, f64), v0: Vec<f64>) -> Case {
    let n = v0.len();
    let (m, k) = common::chain_matrices(n, true);
    let contacts = vec![Contact::new(0, Bounds::obstacle(lo0), false), Contact::new(n - 1, Bounds::obstacle(lo1), false), Contact::new(mid, Bounds { lo: -0.2, hi: 0.2 }, false)];
    let forcing = vec![Forcing { shape: shape.clone(), time: TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: wave.0, omega: wave.1, phase: wave.2 }])) }];
    let c = (b > 0.0).then(|| common::rayleigh(&m, &k, 0.0, b));
    let dy = Dynamics::new(m, k, f0.clone(), contacts).with_forcing(forcing).with_damping(c);
    Case { name, dy, e, v0, f0, shape, wave }
}

/// Hunt case 277: five dofs, `e = 0.5`, undamped (46 rows inside a tail).
fn case277() -> Case {
    let f0 = vec![-0.005371205512749222, 0.014589285628121118, -0.18215871703849756, -0.34734884286400136, 0.02045492984998043];
    let v0 = vec![-0.17278048419013592, -0.4608865123371686, -0.7668781661229344, -0.7305496172382062, -0.22359615406277222];
    case("277", (0.5, 0.0), (-0.08904622198649235, -0.026990502012741294, 2), f0, vec![0.7764550233031238, 0.0, 0.0, 0.0, 0.0], (0.628008473393161, 0.3046646459216326, 3.393320251892892), v0)
}

/// Hunt case 301: six dofs, `e = 0.3`, `C = b K`.
fn case301() -> Case {
    let f0 = vec![-0.13030522313376242, 0.07937130374228785, -0.37282088406470915, -0.2820921017785743, -0.24015449685369067, -0.44315077729290614];
    let v0 = vec![-0.016162574056107326, -0.6651067907822981, -0.3166573909504544, 0.12040623819944996, 0.4613157045050076, -0.29925766459576697];
    let shape = vec![-0.6234605034987599, 0.0, 0.0, 0.0, 0.0, 0.9918211805217891];
    case("301", (0.3, 0.0017917436262390608), (-0.031755408160214646, -0.054349629057005945, 3), f0, shape, (0.7555210965368133, 3.988408582521469, 1.752489033234755), v0)
}

/// `∫_a^b 1ᵀ f`, in closed form.
fn load_integral(c: &Case, a: f64, b: f64) -> f64 {
    let (amp, w, p) = c.wave;
    c.f0.iter().sum::<f64>() * (b - a) + c.shape.iter().sum::<f64>() * amp * ((w * a + p).cos() - (w * b + p).cos()) / w
}

/// `1ᵀ M v` of the free consistent chain (`M` rows summing to 1/2 at the
/// ends, 1 inside), written here.
fn momentum(v: &[f64]) -> f64 {
    let n = v.len();
    v.iter().enumerate().map(|(i, x)| x * if i == 0 || i == n - 1 { 0.5 } else { 1.0 }).sum()
}

/// Each case over [0, 8] through the registry's stepper sampled every
/// `dt = 1/2` and `dt/4`: the events in time order (before: 46 and 1 rows
/// logged up to 1.5e-6 s before an earlier accumulation row), the same
/// events and state bits at both samplings, the contacts' impulses
/// balancing the momentum over every step to 1e-11 (relative), and each
/// case meeting an event inside a tail (an accumulation row followed, at
/// its own time, by another contact's impact: the tail ended there).
#[test]
fn an_event_inside_an_accumulations_tail_is_logged_in_time_order() {
    for c in [case277(), case301()] {
        let n = c.v0.len();
        let dt = 0.5;
        let init = Initial { u: vec![0.0; n], v: c.v0.clone() };
        let mut coarse = EventStepper::new("c".into(), c.dy.clone(), c.e, dt, &init).unwrap().with_max_events(20_000);
        let mut fine = EventStepper::new("f".into(), c.dy.clone(), c.e, dt / 4.0, &init).unwrap().with_max_events(20_000);
        let mut p_prev = momentum(&c.v0);
        for lv in 1..=16 {
            for _ in 0..4 {
                fine.step().unwrap_or_else(|e| panic!("case {}, dt/4: {e}", c.name));
            }
            coarse.step().unwrap_or_else(|e| panic!("case {}, dt: {e}", c.name));
            let (sc, sf) = (coarse.state().unwrap(), fine.state().unwrap());
            assert!(sc.iter().zip(&sf).all(|(a, b)| a.to_bits() == b.to_bits()), "case {}, t = {}: {sc:?} sampled at dt, {sf:?} at dt/4", c.name, coarse.time());
            let t1 = lv as f64 * dt;
            let p = momentum(&sc[n..]);
            let got: f64 = coarse.contact_forces().iter().map(|l| -l * dt).sum();
            let want = p - p_prev - load_integral(&c, t1 - dt, t1);
            assert!((got - want).abs() <= 1e-11 * (1.0 + p.abs() + p_prev.abs() + got.abs()), "case {}, step to t = {t1}: impulses {got}, momentum balance {want}", c.name);
            p_prev = p;
        }
        assert_eq!(coarse.time(), 8.0, "case {}", c.name);
        let ev = coarse.events();
        assert!(ev == fine.events(), "case {}: the events differ at dt and dt/4 ({} against {})", c.name, ev.len(), fine.events().len());
        if let Some(w) = ev.windows(2).find(|w| w[1].t < w[0].t) {
            panic!("case {}: events out of time order: {:?} then {:?}", c.name, w[0], w[1]);
        }
        let cut = ev.windows(2).filter(|w| w[0].kind == EventKind::Accumulation && w[1].kind == EventKind::Impact && w[1].t == w[0].t).count();
        assert!(cut > 0, "case {}: no event inside a tail", c.name);
        // A held contact let go at the instant a tail starts: its release
        // row at that instant, before the accumulation's row at the limit.
        let let_go = ev.windows(2).filter(|w| w[0].kind == EventKind::Release && w[1].kind == EventKind::Accumulation && w[0].t < w[1].t).count();
        assert!(c.name != "277" || let_go > 0, "case {}: no release at a tail's start", c.name);
    }
}
