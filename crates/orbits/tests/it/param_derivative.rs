//! `G_λ`, the derivative of the shooting map in the parameter that steers
//! the continuation's corrector and tangent (`continuation.rs`,
//! `param_derivative`), against the transcription of `between.rs` (the
//! closed-form flow between impacts, its own impact search, the
//! restitution by hand: no code of the crate) differentiated in Ω by
//! central differences at two steps, which agree with each other first.
//! The oscillator between symmetric stops, `x'' + 0.1 x' + x = 2 sin Ωt`,
//! `|x| <= 1`, e = 0.8, its map over `p` forcing periods `2πp/Ω`: the
//! horizon moves with Ω.

use crate::between::{map_between, C, E, F};
use signorini_fem::SymBand;
use signorini_orbits::{param_derivative, Family, Model, OrbitError};
use signorini_schemes::events::EventKind;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};
use std::f64::consts::TAU;

/// The map over `p` forcing periods.
struct Between(usize);

impl Family for Between {
    fn model(&self, w: f64) -> Result<Model, OrbitError> {
        crate::between::model(w)
    }
    fn period(&self, w: f64) -> Result<f64, OrbitError> {
        Ok(self.0 as f64 * TAU / w)
    }
}

/// The transcription's map and its impacts (4000 samples a period).
fn map(p: usize, w: f64, x: [f64; 2]) -> ([f64; 2], usize) {
    let (y, k, _) = map_between(w, x, p, (-1.0, 1.0), E, 4000.0);
    (y, k)
}

/// `∂P/∂Ω` of the transcription by the central difference of step `d`.
fn central(p: usize, w: f64, x: [f64; 2], d: f64) -> [f64; 2] {
    let (a, b) = (map(p, w + d, x).0, map(p, w - d, x).0);
    [(a[0] - b[0]) / (2.0 * d), (a[1] - b[1]) / (2.0 * d)]
}

/// At two states whose runs have two impacts, none slow (the map smooth in Ω
/// there), with the parameter's scale 1 and 3: `G_λ` within 3e-6 of its
/// size of the transcription's, whose differences of step 1e-4 and 1e-5
/// agree to 1e-6 (the finer's truncation, a hundredth of the coarser's,
/// about 1e-8). `G_λ` is a forward difference of step `h` = 1e-7 Λ,
/// which errs by `h P''/2`: at Ω = 1.4 by 4.6e-7 and 1.5e-6 of its size
/// with Λ = 1 and 3 (in proportion to the step), 2.5e-8 at Ω = 2.5.
/// Dropping the period's dependence on Ω from the
/// crate's difference (the map at `Ω + h` over the horizon at `Ω`) leaves
/// out `ẋ(T) dT/dΩ` and fails.
#[test]
fn the_parameter_derivative_is_the_transcriptions_derivative_in_omega() {
    let cases: [(usize, f64, [f64; 2]); 2] = [(1, 2.5, [0.3, 1.2]), (1, 1.4, [-0.5, 0.8])];
    for (p, w, x) in cases {
        let (_, k) = map(p, w, x);
        assert!(k >= 1, "Ω = {w}, x = {x:?}, {p} periods: no impact");
        let (coarse, fine) = (central(p, w, x, 1e-4), central(p, w, x, 1e-5));
        let size = fine[0].abs().max(fine[1].abs());
        let agree = (coarse[0] - fine[0]).abs().max((coarse[1] - fine[1]).abs());
        assert!(agree <= 1e-6 * size, "Ω = {w}, x = {x:?}: the oracle's two steps differ by {agree:e} of {size:e}");
        for (scale, exact) in [(1.0, false), (3.0, false), (1.0, true), (3.0, true)] {
            let gl = param_derivative(&Between(p), &x, w, scale, exact).unwrap();
            let err = (gl[0] - fine[0]).abs().max((gl[1] - fine[1]).abs());
            eprintln!("Ω = {w}, x = {x:?}, {p} periods, {k} impacts, Λ = {scale}, exact {exact}: G_λ {gl:?}, transcription {fine:?}, error {:e}", err / size);
            let tol = if exact { 3e-8 } else { 3e-6 };
            assert!(err <= tol * size, "Ω = {w}, x = {x:?}, Λ = {scale}: G_λ {gl:?} against the transcription's {fine:?} ({:e} of its size)", err / size);
        }
    }
}

/// The oscillator of `between.rs` with the stops `(lo, hi)` and the
/// restitution `e`.
fn oscillator(w: f64, stops: (f64, f64), e: f64) -> Result<Model, OrbitError> {
    let dy = Dynamics::new(SymBand::from_diagonal(&[1.0]), SymBand::from_diagonal(&[1.0]), vec![0.0], vec![Contact::new(0, Bounds { lo: stops.0, hi: stops.1 }, false)])
        .with_forcing(vec![Forcing { shape: vec![1.0], time: TimeProfile::Sine { amplitude: F, omega: w } }])
        .with_damping(Some(SymBand::from_diagonal(&[C])));
    Model::new(dy, e)
}

/// The oscillator at Ω = 2.5 over one period in one of its data:
/// the upper stop (`hi`), the restitution (`e`).
enum Datum {
    Hi,
    E,
}

impl Family for Datum {
    fn model(&self, a: f64) -> Result<Model, OrbitError> {
        match self {
            Datum::Hi => oscillator(2.5, (-1.0, a), E),
            Datum::E => oscillator(2.5, (-1.0, 1.0), a),
        }
    }
    fn period(&self, _: f64) -> Result<f64, OrbitError> {
        Ok(TAU / 2.5)
    }
}

/// `d(a)` by central differences of steps 1e-4 and 1e-5, which agree to
/// 1e-6 of their size first: the oracle and its size.
fn converged(d: impl Fn(f64) -> [f64; 2], a: f64) -> ([f64; 2], f64) {
    let c = |h: f64| {
        let (p, m) = (d(a + h), d(a - h));
        [(p[0] - m[0]) / (2.0 * h), (p[1] - m[1]) / (2.0 * h)]
    };
    let (coarse, fine) = (c(1e-4), c(1e-5));
    let size = fine[0].abs().max(fine[1].abs());
    let agree = (coarse[0] - fine[0]).abs().max((coarse[1] - fine[1]).abs());
    assert!(agree <= 1e-6 * size, "a = {a}: the oracle's two steps differ by {agree:e} of {size:e}");
    (fine, size)
}

/// A parameter that moves the bound and one that sets the restitution:
/// `G_λ` against the transcription (`map_between`, its stops and
/// restitution by hand) differentiated in them, within 1e-7 of its size.
/// The guard's bound enters as the impact's time shift
/// `(f⁺ − DJ f⁻)(−∂b/∂λ)/v_n`, the restitution as `∂v⁺/∂e` (theory §12.2):
/// dropping either fails its case.
#[test]
fn the_parameter_derivative_in_a_bound_and_a_restitution_is_the_transcriptions() {
    let x = [0.3, 1.2];
    let cases: [(Datum, f64, &str); 3] = [(Datum::Hi, 1.0, "hi"), (Datum::Hi, 1.3, "hi"), (Datum::E, 0.8, "e")];
    for (family, a, name) in cases {
        let d = |v: f64| match family {
            Datum::Hi => map_between(2.5, x, 1, (-1.0, v), E, 4000.0).0,
            Datum::E => map_between(2.5, x, 1, (-1.0, 1.0), v, 4000.0).0,
        };
        let k = match family {
            Datum::Hi => map_between(2.5, x, 1, (-1.0, a), E, 4000.0).1,
            Datum::E => map_between(2.5, x, 1, (-1.0, 1.0), a, 4000.0).1,
        };
        assert!(k >= 1, "{name} = {a}: no impact");
        let (oracle, size) = converged(d, a);
        let gl = param_derivative(&family, &x, a, 1.0, true).unwrap();
        let err = (gl[0] - oracle[0]).abs().max((gl[1] - oracle[1]).abs());
        eprintln!("{name} = {a}, {k} impacts: G_λ {gl:?}, transcription {oracle:?}, error {:e}", err / size);
        assert!(err <= 1e-7 * size, "{name} = {a}: G_λ {gl:?} against {oracle:?} ({:e} of its size)", err / size);
    }
}

/// An impact near the section's start (at t ≈ 1.2e-4, the start 1e-4 from
/// the stop at speed 0.8): `G_λ` in Ω within 1e-7 of the transcription's.
#[test]
fn the_parameter_derivative_with_an_impact_at_the_section() {
    for x in [[0.9999, 0.8], [-0.9999, -0.8]] {
        let (fine, size) = converged(|w| map(1, w, x).0, 1.4);
        let gl = param_derivative(&Between(1), &x, 1.4, 1.0, true).unwrap();
        let err = (gl[0] - fine[0]).abs().max((gl[1] - fine[1]).abs());
        eprintln!("x = {x:?}: G_λ {gl:?}, transcription {fine:?}, error {:e}", err / size);
        assert!(err <= 1e-7 * size, "x = {x:?}: G_λ {gl:?} against {fine:?} ({:e} of its size)", err / size);
    }
}

/// Two masses in a chain, `M = I`, `K = [[2, −1], [−1, 1]]`, `C = 0.05 K`,
/// the second mass between stops at ±`g`, the first forced `sin 1.3t`, over
/// one period, in the gap `g`: `G_λ` against the central differences of
/// the crate's own map (steps 1e-4 and 1e-5 agreeing first), at a start
/// whose run has impacts, none within 0.05 of the section.
struct Chain;

impl Family for Chain {
    fn model(&self, g: f64) -> Result<Model, OrbitError> {
        let mut m = SymBand::zeros(2, 1);
        let mut k = SymBand::zeros(2, 1);
        let mut c = SymBand::zeros(2, 1);
        m.set(0, 0, 1.0);
        m.set(1, 1, 1.0);
        for (i, j, v) in [(0, 0, 2.0), (0, 1, -1.0), (1, 1, 1.0)] {
            k.set(i, j, v);
            c.set(i, j, 0.05 * v);
        }
        let dy = Dynamics::new(m, k, vec![0.0, 0.0], vec![Contact::new(1, Bounds { lo: -g, hi: g }, false)])
            .with_forcing(vec![Forcing { shape: vec![1.0, 0.0], time: TimeProfile::Sine { amplitude: 1.0, omega: 1.3 } }])
            .with_damping(Some(c));
        Model::new(dy, 0.7)
    }
    fn period(&self, _: f64) -> Result<f64, OrbitError> {
        Ok(TAU / 1.3)
    }
}

#[test]
fn the_parameter_derivative_of_a_chain_in_its_gap_is_its_maps() {
    let (g, x) = (0.4, [0.2, 0.3, 0.5, 0.9]);
    let t = Chain.period(g).unwrap();
    let img = Chain.model(g).unwrap().flow(0.0, &x, t, false).unwrap();
    let impacts: Vec<f64> = img.events.iter().filter(|e| e.kind == EventKind::Impact).map(|e| e.t).collect();
    assert!(!impacts.is_empty() && impacts.iter().all(|&s| s > 0.05 && s < t - 0.05), "impacts at {impacts:?} of {t}");
    let d = |v: f64| -> [f64; 4] {
        let y = Chain.model(v).unwrap().flow(0.0, &x, t, false).unwrap().x;
        [y[0], y[1], y[2], y[3]]
    };
    let c = |h: f64| -> [f64; 4] {
        let (p, m) = (d(g + h), d(g - h));
        std::array::from_fn(|i| (p[i] - m[i]) / (2.0 * h))
    };
    let (coarse, fine) = (c(1e-4), c(1e-5));
    let size = fine.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let agree = (0..4).map(|i| (coarse[i] - fine[i]).abs()).fold(0.0, f64::max);
    assert!(agree <= 1e-6 * size, "the map's two steps differ by {agree:e} of {size:e}");
    let gl = param_derivative(&Chain, &x, g, 1.0, true).unwrap();
    let err = (0..4).map(|i| (gl[i] - fine[i]).abs()).fold(0.0, f64::max);
    eprintln!("chain, {} impacts: G_λ {gl:?}, the map's differences {fine:?}, error {:e}", impacts.len(), err / size);
    assert!(err <= 1e-7 * size, "G_λ {gl:?} against {fine:?} ({:e} of its size)", err / size);
}

/// A run with a slow impact: the 3-impact orbit of `slow_impact.rs`'s
/// branch at Ω = 3.8264246 (its point there), the slow impact at 8.6e-4 (1.3e-3 of
/// the fastest), where the forward difference of 3e-7 gave 2642 for
/// 1490: `G_λ` against the central differences of the crate's own map at
/// steps 1e-8 and 1e-9 (agreeing to 1.4e-4: the coarser's truncation, the
/// finer's about 1e-6), within 1e-5 of its size (measured: 1.8e-6).
#[test]
fn the_parameter_derivative_through_a_slow_impact_is_its_maps() {
    let (w, x) = (3.8264246153867445, [-0.9540472325817279, -0.7387309815014147]);
    let fam = crate::slow_impact::Between;
    let t = fam.period(w).unwrap();
    let img = fam.model(w).unwrap().flow(0.0, &x, t, false).unwrap();
    let speeds: Vec<f64> = img.events.iter().filter(|e| e.kind == EventKind::Impact).map(|e| e.velocity_before.abs()).collect();
    let (slow, fast) = (speeds.iter().copied().fold(f64::INFINITY, f64::min), speeds.iter().copied().fold(0.0, f64::max));
    assert!(speeds.len() == 3 && slow < 2e-3 * fast, "impact speeds {speeds:?}");
    let d = |v: f64| fam.model(v).unwrap().flow(0.0, &x, fam.period(v).unwrap(), false).unwrap().x;
    let c = |h: f64| -> [f64; 2] {
        let (p, m) = (d(w + h), d(w - h));
        [(p[0] - m[0]) / (2.0 * h), (p[1] - m[1]) / (2.0 * h)]
    };
    let (coarse, fine) = (c(1e-8), c(1e-9));
    let size = fine[0].abs().max(fine[1].abs());
    let agree = (coarse[0] - fine[0]).abs().max((coarse[1] - fine[1]).abs());
    let gl = param_derivative(&fam, &x, w, 3.0, true).unwrap();
    let err = (gl[0] - fine[0]).abs().max((gl[1] - fine[1]).abs());
    eprintln!("slow impact {slow:e} of {fast:e}: G_λ {gl:?}, the map's differences {fine:?} (steps agree to {:e}), error {:e}", agree / size, err / size);
    assert!(agree <= 3e-4 * size, "the map's two steps differ by {agree:e} of {size:e}");
    assert!(err <= 1e-5 * size, "G_λ {gl:?} against {fine:?} ({:e} of its size)", err / size);
}

/// The bar with a massless contact node (`reach.rs`'s: mass
/// redistribution `mod`, the contact node condensed, landings and
/// lift-offs without a jump), from its state after three forcing periods,
/// over one, in three of its keys: the gap (the bound: the held phases'
/// load `K_fh b_h`), the first harmonic's amplitude and the forcing's
/// frequency (the horizon moves). `G_λ` against the crate's own map
/// differentiated by Richardson's extrapolation of central differences,
/// `(4 c(h/2) − c(h))/3` (the `h²` term gone), at `h` = 8e-5 and 4e-5 of
/// the value's scale (`max(|λ|, 0.1)`), which agree to 1e-8 of their size
/// first (every run with the point's number of events), within 1e-7 of
/// its size (measured: 3.2e-11 … 1.1e-10). Each phase's flow is the
/// condensed one (`K_ff − K_fS K_SS⁻¹ K_Sf`), and no event adds a term
/// (the vector field is continuous at a landing and a lift-off). Before,
/// these models took the forward difference (4.1e-6 … 6.7e-6 off).
#[test]
fn the_parameter_derivative_of_a_bar_with_a_massless_contact_node_is_its_maps() {
    for (path, at) in [("bar.gap", None), ("load.harmonics.0.0", None), ("load.omega", Some(1.02))] {
        let doc: toml::Table = crate::reach::BAR.parse().unwrap();
        let (fam, value) = signorini_orbits::SceneFamily::new(doc, path, 1).unwrap();
        let value = at.unwrap_or(value);
        let built = fam.build(value).unwrap();
        assert!(built.model.dim() < 2 * built.model.dynamics().n(), "{path}: the contact node carries no state");
        let x = built.model.flow(0.0, &built.start, 3.0 * built.horizon, false).unwrap().x;
        let events = built.model.flow(0.0, &x, built.horizon, false).unwrap().events.len();
        assert!(events >= 2, "{path}: {events} events a period");
        let d = |v: f64| {
            let img = fam.model(v).unwrap().flow(0.0, &x, fam.period(v).unwrap(), false).unwrap();
            assert_eq!(img.events.len(), events, "{path} = {v}: the difference crosses an event");
            img.x
        };
        let c = |h: f64| -> Vec<f64> {
            let (p, m) = (d(value + h), d(value - h));
            (0..x.len()).map(|i| (p[i] - m[i]) / (2.0 * h)).collect()
        };
        let richardson = |h: f64| -> Vec<f64> {
            let (a, b) = (c(h), c(0.5 * h));
            (0..x.len()).map(|i| (4.0 * b[i] - a[i]) / 3.0).collect()
        };
        let scale = value.abs().max(0.1);
        let (coarse, fine) = (richardson(8e-5 * scale), richardson(4e-5 * scale));
        let size = fine.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let agree = (0..x.len()).map(|i| (coarse[i] - fine[i]).abs()).fold(0.0, f64::max);
        assert!(agree <= 1e-8 * size, "{path}: the map's two extrapolations differ by {agree:e} of {size:e}");
        let gl = param_derivative(&fam, &x, value, 1.0, true).unwrap();
        let err = (0..x.len()).map(|i| (gl[i] - fine[i]).abs()).fold(0.0, f64::max);
        eprintln!("{path} = {value}, {events} events: G_λ {:e} of {size:e} off (the extrapolations agree to {:e})", err / size, agree / size);
        assert!(err <= 1e-7 * size, "{path}: G_λ {gl:?} against {fine:?} ({:e} of its size)", err / size);
    }
}
