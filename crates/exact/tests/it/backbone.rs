//! The nonsmooth modes' closed form (docs/theory.md §11) against values
//! computed without it:
//!
//! * the continuous bar itself, by the Courant-one central difference
//!   written here (docs/theory.md §4.10: `u_i^{n+1} = u_{i+1}^n + u_{i-1}^n
//!   − u_i^{n-1}` inside, which d'Alembert's solution satisfies exactly at
//!   the nodes; the clamped node held at 0; the contact node by the
//!   characteristic rule `E^{n+1} = 2 u_1^n − u_0^{n-1} − s^n`,
//!   `u_0^{n+1} = max(g, E^{n+1})`, `s^{n+1} = E^{n+1} − u_0^{n+1}`, exact
//!   while the end is free or held over a whole step). With the data chosen
//!   so that every impact and release falls on a time level the nodal values
//!   are the exact solution's: the run must return to its initial state
//!   after the closed form's period and not before, hold the end on the
//!   obstacle for the closed form's contact time, and agree with the closed
//!   form's `u` at every node and level;
//! * the linear theory (periods `4L/((2k−1)c)` below the threshold,
//!   `2L/(kc)` held at the static state), and the hand-written `bar-dirichlet`;
//! * the energy integrated from the closed form's own fields.

use signorini_exact::{Backbone, BackboneError, BarDirichlet, ExactSolution, FarEnd, ModeBar, NonsmoothMode};

/// Nodal agreement: the runs below are a few hundred levels of sums of
/// values of order 1.
const NODAL: f64 = 1e-12;

/// The Courant-one central difference on `m` uniform elements, from the
/// two first levels; returns every level `0 ..= levels`.
fn courant_one(gap: f64, u0: &[f64], u1: &[f64], levels: usize) -> Vec<Vec<f64>> {
    let m = u0.len() - 1;
    let mut out = vec![u0.to_vec(), u1.to_vec()];
    // What the obstacle took from the end's free update (0: free at the start).
    let mut s = 0.0;
    for n in 1..levels {
        let (prev, cur) = (&out[n - 1], &out[n]);
        let mut next = vec![0.0; m + 1];
        for i in 1..m {
            next[i] = cur[i + 1] + cur[i - 1] - prev[i];
        }
        let free = 2.0 * cur[1] - prev[0] - s;
        next[0] = free.max(gap);
        s = free - next[0];
        next[m] = 0.0;
        out.push(next);
    }
    out
}

struct Case {
    length: f64,
    c: f64,
    gap: f64,
    energy: f64,
    family: u32,
    m: usize,
}

impl Case {
    fn backbone(&self) -> Backbone {
        Backbone::new(ModeBar { length: self.length, wave_speed: self.c, gap: self.gap, far_end: FarEnd::Clamped }, self.family).unwrap()
    }
    fn dt(&self) -> f64 {
        self.length / (self.m as f64 * self.c)
    }
    fn x(&self, i: usize) -> f64 {
        self.length * i as f64 / self.m as f64
    }
}

/// What the run measured over its first period.
struct Measured {
    period: f64,
    contact_time: f64,
    contact_phases: usize,
}

/// Runs the Courant-one scheme over two periods from `u0`, `u1`; checks every
/// node at every level against the closed form; measures the period (the
/// first level where the two-level state is back) and the contact phases.
fn run(case: &Case, mode: &NonsmoothMode, u0: Vec<f64>, u1: Vec<f64>) -> Measured {
    let dt = case.dt();
    let period_levels = (mode.period().unwrap() / dt).round() as usize;
    let levels = 2 * period_levels + 2;
    let run = courant_one(case.gap, &u0, &u1, levels);
    for (n, level) in run.iter().enumerate() {
        for (i, &u) in level.iter().enumerate() {
            let want = mode.fields(case.x(i), n as f64 * dt).u;
            assert!((u - want).abs() < NODAL, "node {i}, level {n}: scheme {u}, closed form {want}");
        }
    }
    let diff = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
    let back = (1..levels - 1).find(|&n| diff(&run[n], &run[0]) + diff(&run[n + 1], &run[1]) < NODAL).expect("the run never returns to its initial state");
    // Contact levels in the first period: the end on the obstacle.
    let held: Vec<bool> = (0..=back).map(|n| (run[n][0] - case.gap).abs() < NODAL).collect();
    let phases = held.windows(2).filter(|w| !w[0] && w[1]).count();
    let first = held.iter().position(|&h| h);
    let contact_levels = first.map_or(0, |f| held[f..].iter().take_while(|&&h| h).count() - 1);
    Measured { period: back as f64 * dt, contact_time: contact_levels as f64 * dt, contact_phases: phases }
}

/// The family `k = 1` from the state derived in docs/theory.md §11 (the bar
/// stretched linearly, `u = (Q/c)(L − x)`, at rest), without the closed form:
/// the second level by d'Alembert with `v0 = 0` (the mean of the
/// neighbours inside; the free end's mirror `u_0 = u_1`).
fn stretched_start(case: &Case) -> (Vec<f64>, Vec<f64>) {
    let q = (2.0 * case.energy / case.length).sqrt();
    let u0: Vec<f64> = (0..=case.m).map(|i| q / case.c * (case.length - case.x(i))).collect();
    let mut u1 = u0.clone();
    for i in 1..case.m {
        u1[i] = 0.5 * (u0[i - 1] + u0[i + 1]);
    }
    u1[0] = u0[1];
    u1[case.m] = 0.0;
    (u0, u1)
}

/// The family `k = 1` at the listed data: the run's period and contact
/// time are the closed form's, one contact phase per period, every node
/// exact. The events fall on levels: `g/Q` and `t_f/2` are multiples of
/// `dt = L/(mc)`.
#[test]
fn fundamental_family_against_the_courant_one_bar() {
    let cases = [
        // Clearance: t_f = 2.5, t_c = 0.75, T = 3.25.
        Case { length: 1.0, c: 1.0, gap: -0.25, energy: 0.5, family: 1, m: 40 },
        // Just above the threshold 1/32 (E = 1.5625 × it): t_c = 0.2, T = 3.8.
        Case { length: 1.0, c: 1.0, gap: -0.25, energy: 0.048828125, family: 1, m: 40 },
        // Another length and wave speed: τ = 8, Q = 1/2, T = 12.2, t_c = 3.8.
        Case { length: 2.0, c: 0.5, gap: -0.1, energy: 0.25, family: 1, m: 40 },
        // Prestress: t_f = 1.5, t_c = 1.25, T = 2.75.
        Case { length: 1.0, c: 1.0, gap: 0.25, energy: 0.5, family: 1, m: 40 },
        // Touching, bar-dirichlet's data: T = 3, t_c = 1.
        Case { length: 1.0, c: 1.0, gap: 0.0, energy: 0.125, family: 1, m: 40 },
    ];
    for case in &cases {
        let mode = case.backbone().mode(case.energy).unwrap();
        let p = mode.point();
        let (u0, u1) = stretched_start(case);
        let got = run(case, &mode, u0, u1);
        let tag = format!("L = {}, c = {}, g = {}, E = {}", case.length, case.c, case.gap, case.energy);
        assert!((got.period - p.period).abs() < 1e-9, "{tag}: period measured {}, closed form {}", got.period, p.period);
        assert!((got.contact_time - p.contact_time).abs() < 1e-9, "{tag}: contact time measured {}, closed form {}", got.contact_time, p.contact_time);
        assert_eq!((got.contact_phases, p.impacts_per_period), (1, 1), "{tag}");
    }
}

/// The higher families, from the closed form's own two first levels: the
/// run must still come back after the closed form's period, with its
/// contact time, every node exact. `L = c = 1`, `g = −1/4`. `k = 2`
/// (through the linear period `4L/(3c)`), `Q = 1`: `t_f = 5/4`,
/// `T = 21/16`, `t_c = 1/16`, `m = 80`. `k = 3` (through `4L/(5c)`, its
/// threshold `Q = 5/4`), `Q = 2`: `t_f = 3/4`, `T = 19/24`, `t_c = 1/24`,
/// `m = 48`.
#[test]
fn higher_families_against_the_courant_one_bar() {
    for (case, period, contact) in [
        (Case { length: 1.0, c: 1.0, gap: -0.25, energy: 0.5, family: 2, m: 80 }, 21.0 / 16.0, 1.0 / 16.0),
        (Case { length: 1.0, c: 1.0, gap: -0.25, energy: 2.0, family: 3, m: 48 }, 19.0 / 24.0, 1.0 / 24.0),
    ] {
        let mode = case.backbone().mode(case.energy).unwrap();
        let p = mode.point();
        assert!((p.period - period).abs() < 1e-15 && (p.contact_time - contact).abs() < 1e-15, "k = {}: {p:?}", case.family);
        let level = |t: f64| (0..=case.m).map(|i| mode.fields(case.x(i), t).u).collect::<Vec<_>>();
        let got = run(&case, &mode, level(0.0), level(case.dt()));
        assert!((got.period - p.period).abs() < 1e-9, "k = {}: period measured {}, closed form {}", case.family, got.period, p.period);
        assert!((got.contact_time - p.contact_time).abs() < 1e-9, "k = {}: contact measured {}, closed form {}", case.family, got.contact_time, p.contact_time);
        assert_eq!(got.contact_phases, 1, "k = {}", case.family);
    }
}

/// Below the threshold the family is the linear motion: no contact, period
/// `4L/c`, in the run as in the closed form.
#[test]
fn below_the_threshold_the_linear_period() {
    // Threshold c² g²/(2L) = 1/32; E = 0.02.
    let case = Case { length: 1.0, c: 1.0, gap: -0.25, energy: 0.02, family: 1, m: 40 };
    let mode = case.backbone().mode(case.energy).unwrap();
    let (u0, u1) = stretched_start(&case);
    let got = run(&case, &mode, u0, u1);
    assert!((got.period - 4.0).abs() < 1e-9, "period measured {}", got.period);
    assert_eq!((got.contact_phases, got.contact_time), (0, 0.0));
    let p = mode.point();
    assert_eq!((p.period, p.contact_time, p.impacts_per_period), (4.0, 0.0, 0));
}

/// The limits, against the linear theory's numbers: `4L/((2k−1)c)` below
/// and at the threshold `(2k−1)² c² g²/(2L)` and continuous across it,
/// `(2k+1)L/(k²c)` at `g = 0` at every energy and as `E → ∞`, the
/// `k`-th clamped–clamped period `2L/(kc)` at the static state of a
/// prestressed bar (the family's limit there).
#[test]
fn limits_and_thresholds() {
    let (l, c) = (1.5, 2.0);
    let bb = |gap: f64, k: u32| Backbone::new(ModeBar { length: l, wave_speed: c, gap, far_end: FarEnd::Clamped }, k).unwrap();
    for k in 1..=3u32 {
        let odd = f64::from(2 * k - 1);
        let (linear, touching) = (4.0 * l / (odd * c), f64::from(2 * k + 1) * l / (f64::from(k * k) * c));
        let b = bb(-0.3, k);
        let threshold = (odd * c * 0.3).powi(2) / (2.0 * l);
        assert!((b.threshold() - threshold).abs() < 1e-15 * threshold, "k = {k}");
        for e in [0.0, 0.5 * threshold, threshold] {
            let p = b.point(e).unwrap();
            assert_eq!((p.period, p.contact_time, p.impacts_per_period), (linear, 0.0, 0), "k = {k}, E = {e}");
        }
        let just = b.point(threshold * (1.0 + 1e-10)).unwrap();
        assert!((just.period - linear).abs() < 1e-9 && just.contact_time < 1e-9 && just.impacts_per_period == 1, "k = {k}: {just:?}");
        let far = b.point(1e16).unwrap();
        assert!((far.period - touching).abs() < 1e-8, "k = {k}: E → ∞ gives {}", far.period);
        for e in [1e-8, 1.0, 1e8] {
            let p = bb(0.0, k).point(e).unwrap();
            assert!((p.period - touching).abs() < 1e-14, "k = {k}, g = 0, E = {e}: {}", p.period);
        }
        // Prestress: the static state (energy c² g²/(2L)) held on the obstacle.
        let pre = bb(0.3, k);
        let p = pre.point((c * 0.3_f64).powi(2) / (2.0 * l)).unwrap();
        assert!((p.period - 2.0 * l / (f64::from(k) * c)).abs() < 1e-14 && p.flight_time == 0.0 && p.impacts_per_period == 0, "k = {k}: {p:?}");
        let near = pre.point((c * 0.3_f64).powi(2) / (2.0 * l) * (1.0 + 1e-10)).unwrap();
        assert!((near.period - p.period).abs() < 1e-5 && near.impacts_per_period == 1, "k = {k}: {near:?}");
    }
    // k = 1: the period falls from 4L/c to 3L/c with a clearance, rises from 2L/c to 3L/c with a prestress.
    let (d, pre) = (bb(-0.3, 1), bb(0.3, 1));
    let e = [0.13, 0.2, 1.0, 10.0]; // above both thresholds, 0.12
    for w in e.windows(2) {
        assert!(d.point(w[1]).unwrap().period < d.point(w[0]).unwrap().period);
        assert!(pre.point(w[1]).unwrap().period > pre.point(w[0]).unwrap().period);
    }
}

/// `bar-dirichlet` (hand-written phases, docs/theory.md §5.1) is the point
/// `g = 0`, `E = 1/8` of the fundamental family: the same `u`, `u_x`, `u_t`
/// and `λ` everywhere, period 3, contact 1.
#[test]
fn the_dirichlet_benchmark_is_a_point_of_the_backbone() {
    let mode = Backbone::new(ModeBar::default(), 1).unwrap().mode(BarDirichlet.energy()).unwrap();
    let p = mode.point();
    assert_eq!((p.period, p.contact_time, p.impacts_per_period, p.contact_force), (3.0, 1.0, 1, -0.5));
    assert_eq!(mode.period(), BarDirichlet.period());
    // Points off the characteristic lines (irrational offsets).
    for j in 0..400 {
        let t = 0.013 + j as f64 * 0.0151 * std::f64::consts::SQRT_2;
        lambda_matches(&mode, t);
        for i in 0..=20 {
            let x = (i as f64 + 0.37) / 21.0;
            let (a, b) = (mode.fields(x, t), BarDirichlet.fields(x, t));
            assert!((a.u - b.u).abs() < 1e-14 && (a.ux - b.ux).abs() < 1e-15 && (a.ut - b.ut).abs() < 1e-15, "x = {x}, t = {t}: {a:?} vs {b:?}");
        }
    }
}

fn lambda_matches(mode: &NonsmoothMode, t: f64) {
    assert_eq!(mode.lambda(t), BarDirichlet.lambda(t), "t = {t}");
}

/// The energy `∫ (u_t² + c² u_x²)/2`, integrated exactly from the fields
/// (constant between the kinks), is the requested one at every time; the
/// Signorini conditions hold at the end.
#[test]
fn energy_and_signorini_conditions_from_the_fields() {
    for (gap, e, k) in [(-0.2, 0.7, 1), (0.0, 0.3, 1), (0.15, 0.4, 1), (-0.1, 2.0, 2), (0.1, 1.0, 3)] {
        let (l, c) = (1.3, 0.8);
        let mode = Backbone::new(ModeBar { length: l, wave_speed: c, gap, far_end: FarEnd::Clamped }, k).unwrap().mode(e).unwrap();
        let mut kinks = Vec::new();
        for j in 0..200 {
            let t = j as f64 * 0.0731;
            mode.kinks(t, &mut kinks);
            let mut pts = vec![0.0];
            pts.extend(&kinks);
            pts.push(l);
            let energy: f64 = pts
                .windows(2)
                .map(|w| {
                    let f = mode.fields(0.5 * (w[0] + w[1]), t);
                    0.5 * (w[1] - w[0]) * (f.ut * f.ut + c * c * f.ux * f.ux)
                })
                .sum();
            assert!((energy - e).abs() < 1e-12, "g = {gap}, k = {k}, t = {t}: energy {energy}");
            let (z, lam) = (mode.fields(0.0, t).u, mode.lambda(t));
            assert!(z >= gap - 1e-13 && lam <= 0.0 && (lam == 0.0 || (z - gap).abs() < 1e-13), "g = {gap}, k = {k}, t = {t}: u(0) = {z}, λ = {lam}");
            assert!(mode.fields(l, t).u.abs() < 1e-13);
        }
    }
}

/// Bad input is a typed error naming the field.
#[test]
fn bad_input_is_a_typed_error() {
    let bar = ModeBar::default();
    let field = |r: Result<Backbone, BackboneError>| r.unwrap_err().field();
    assert_eq!(field(Backbone::new(ModeBar { length: 0.0, ..bar }, 1)), "length");
    assert_eq!(field(Backbone::new(ModeBar { wave_speed: f64::NAN, ..bar }, 1)), "wave_speed");
    assert_eq!(field(Backbone::new(ModeBar { gap: f64::INFINITY, ..bar }, 1)), "gap");
    assert_eq!(field(Backbone::new(bar, 0)), "family");
    assert_eq!(Backbone::new(ModeBar { far_end: FarEnd::Free, ..bar }, 1), Err(BackboneError::FreeFarEnd));
    let b = Backbone::new(bar, 1).unwrap();
    for e in [-1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(b.point(e).unwrap_err().field(), "energy");
    }
    let pre = Backbone::new(ModeBar { gap: 0.5, ..bar }, 1).unwrap();
    let err = pre.point(0.1).unwrap_err();
    assert_eq!(err, BackboneError::BelowStatic { energy: 0.1, minimum: 0.125 });
    assert!(err.to_string().contains("energy") && err.to_string().contains("0.125"), "{err}");
    // Off the bar or at a non-finite time: NaN, no panic.
    let mode = b.mode(1.0).unwrap();
    assert!(mode.fields(2.0, 0.5).u.is_nan() && mode.fields(0.5, f64::NAN).u.is_nan() && mode.lambda(f64::INFINITY).is_nan());
}
