//! Event-driven runs of random small systems against an independent fine
//! time-stepping solution written here: classical RK4 on the first-order
//! system with a fixed step, the dense `M⁻¹` by Gauss–Jordan (neither the
//! events crate's modal flow nor faer), each event located inside the step
//! where its function changes sign by bisection on the length of an RK4
//! sub-step, Newton's law applied to one contact at the located time; with
//! `e = 0`, a held phase integrated as the constrained system (the held dof
//! fixed, RK4 on the others) and its release located where the contact force
//! `r = (M q'' + C q' + K q − f)_c` computed from the equation changes sign.
//!
//! The oracle's accuracy: with `h = 1e-3` and the highest frequency of
//! the random systems below `ω ≈ 4`, RK4's global error over a horizon of
//! 5 is `~ ω T (ωh)⁴/120 ≈ 4e-11` of the amplitude; an event time's error is
//! that over the contact velocity (`>= 0.05` by the choice of the cases
//! kept), `~ 1e-9`.

use crate::events_common as common;

use proptest::collection::vec;
use proptest::prelude::*;
use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};

/// The largest system.
const N: usize = 8;
type V = [f64; N];

/// An oracle's event: `(t, kind, contact, v_c before, v_c after)`.
#[derive(Clone, Copy, Debug)]
struct Ev {
    t: f64,
    kind: EventKind,
    contact: usize,
    before: f64,
    after: f64,
}

/// What the oracle saw that makes a case ill-posed for it (rejected).
#[derive(Debug, Default)]
struct Doubt {
    /// The smallest impact speed.
    slowest: f64,
    /// A free contact's gap passed a local minimum within this of its bound.
    closest_graze: f64,
}

/// `M q'' + C q' + K q = f0 + shape · a sin(ω t)`, `lo_i <= q[dof_i] <= hi_i`,
/// dense and row-major.
struct Oracle {
    n: usize,
    m: Vec<f64>,
    c: Vec<f64>,
    k: Vec<f64>,
    /// The load (`events_common`).
    load: common::Load,
    /// `(dof, lo, hi, e)`.
    contacts: Vec<(usize, f64, f64, f64)>,
    h: f64,
}

impl Oracle {
    fn from(dy: &Dynamics, e: &[f64], h: f64) -> Self {
        let n = dy.n();
        let dense = |b: &SymBand| (0..n * n).map(|x| b.get(x / n, x % n)).collect::<Vec<f64>>();
        Self {
            n,
            m: dense(&dy.mass),
            c: dy.damping.as_ref().map_or(vec![0.0; n * n], dense),
            k: dense(&dy.stiffness),
            load: common::Load::of(dy),
            contacts: dy.contacts.iter().zip(e).map(|(c, &e)| (c.dof, c.bounds.lo, c.bounds.hi, e)).collect(),
            h,
        }
    }

    /// `f(t) − C v − K q`.
    fn residual(&self, t: f64, q: &V, v: &V) -> V {
        let n = self.n;
        let mut r = [0.0; N];
        for i in 0..n {
            let mut x = self.load.value(i, t);
            for j in 0..n {
                x -= self.c[i * n + j] * v[j] + self.k[i * n + j] * q[j];
            }
            r[i] = x;
        }
        r
    }

    /// The acceleration with `minv` the inverse on the free dofs (zero rows
    /// at the held ones: their acceleration is 0).
    fn accel(&self, minv: &[f64], t: f64, q: &V, v: &V) -> V {
        let n = self.n;
        let r = self.residual(t, q, v);
        let mut a = [0.0; N];
        for i in 0..n {
            a[i] = (0..n).map(|j| minv[i * n + j] * r[j]).sum();
        }
        a
    }

    /// One classical RK4 step of length `h`.
    fn rk4(&self, minv: &[f64], t: f64, q: &V, v: &V, h: f64) -> (V, V) {
        let n = self.n;
        let axpy = |x: &V, a: f64, y: &V| {
            let mut z = *x;
            z.iter_mut().zip(y).take(n).for_each(|(z, y)| *z += a * y);
            z
        };
        let (k1q, k1v) = (*v, self.accel(minv, t, q, v));
        let (q2, v2) = (axpy(q, h / 2.0, &k1q), axpy(v, h / 2.0, &k1v));
        let (k2q, k2v) = (v2, self.accel(minv, t + h / 2.0, &q2, &v2));
        let (q3, v3) = (axpy(q, h / 2.0, &k2q), axpy(v, h / 2.0, &k2v));
        let (k3q, k3v) = (v3, self.accel(minv, t + h / 2.0, &q3, &v3));
        let (q4, v4) = (axpy(q, h, &k3q), axpy(v, h, &k3v));
        let (k4q, k4v) = (v4, self.accel(minv, t + h, &q4, &v4));
        let (mut q1, mut v1) = (*q, *v);
        for i in 0..n {
            q1[i] += h / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i]);
            v1[i] += h / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i]);
        }
        (q1, v1)
    }

    /// The force `r_c = (M a + C v + K q − f)_c` of the contact at `dof`
    /// with the acceleration `a` of the constrained system.
    fn force(&self, minv: &[f64], dof: usize, t: f64, q: &V, v: &V) -> f64 {
        let n = self.n;
        let a = self.accel(minv, t, q, v);
        let res = self.residual(t, q, v);
        (0..n).map(|j| self.m[dof * n + j] * a[j]).sum::<f64>() - res[dof]
    }

    /// The functions whose sign change from `>= 0` to `< 0` is an event,
    /// with what the event is: the free contacts' gaps, the held one's
    /// force (toward its bound).
    fn watched(&self, held: Option<(usize, bool)>, minv: &[f64], t: f64, q: &V, v: &V) -> Vec<(f64, usize, Option<bool>)> {
        let mut out = Vec::new();
        for (j, &(d, lo, hi, _)) in self.contacts.iter().enumerate() {
            match held {
                Some((h, upper)) if h == j => {
                    let r = self.force(minv, d, t, q, v);
                    out.push((if upper { -r } else { r }, j, None));
                }
                _ => {
                    if lo.is_finite() {
                        out.push((q[d] - lo, j, Some(false)));
                    }
                    if hi.is_finite() {
                        out.push((hi - q[d], j, Some(true)));
                    }
                }
            }
        }
        out
    }

    /// Runs from `(q, v)` at `t0` to `t_end`: the events, the final state,
    /// and what makes the case doubtful for this oracle.
    fn run(&self, t0: f64, q0: &[f64], v0: &[f64], t_end: f64) -> (Vec<Ev>, V, V, Doubt) {
        let n = self.n;
        let all: Vec<usize> = (0..n).collect();
        let full = common::inverse(&self.m, n, &all);
        let reduced: Vec<Vec<f64>> = self.contacts.iter().map(|&(d, ..)| common::inverse(&self.m, n, &all.iter().copied().filter(|&x| x != d).collect::<Vec<_>>())).collect();
        let (mut q, mut v) = ([0.0; N], [0.0; N]);
        q[..n].copy_from_slice(q0);
        v[..n].copy_from_slice(v0);
        let mut t = t0;
        let mut held: Option<(usize, bool)> = None;
        let mut events = Vec::new();
        let mut doubt = Doubt { slowest: f64::INFINITY, closest_graze: f64::INFINITY };
        while t < t_end && events.len() <= MAX_ORACLE_EVENTS {
            // Steps end at the series' breakpoints (RK4 is of order 4 on
            // each piece, not across a kink of the load).
            let kink = self.load.to_kink(t);
            let h = self.h.min(t_end - t).min(kink);
            let minv = held.map_or(&full, |(j, _)| &reduced[j]);
            let (q1, v1) = self.rk4(minv, t, &q, &v, h);
            let g0 = self.watched(held, minv, t, &q, &v);
            let g1 = self.watched(held, minv, t + h, &q1, &v1);
            // The earliest sign change, located by bisection on the sub-step.
            let mut first: Option<(f64, usize)> = None;
            for (w, (a, b)) in g0.iter().zip(&g1).enumerate() {
                if a.0 >= 0.0 && b.0 < 0.0 {
                    let (mut lo, mut hi) = (0.0, h);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        let (qm, vm) = self.rk4(minv, t, &q, &v, mid);
                        if self.watched(held, minv, t + mid, &qm, &vm)[w].0 < 0.0 {
                            hi = mid;
                        } else {
                            lo = mid;
                        }
                    }
                    if first.is_none_or(|f| hi < f.0) {
                        first = Some((hi, w));
                    }
                } else if let Some(upper) = a.2 {
                    // A gap passing its minimum inside the step.
                    let d = self.contacts[a.1].0;
                    let (s0, s1) = if upper { (-v[d], -v1[d]) } else { (v[d], v1[d]) };
                    if s0 <= 0.0 && s1 >= 0.0 {
                        doubt.closest_graze = doubt.closest_graze.min(a.0.min(b.0));
                    }
                }
            }
            let Some((tau, w)) = first else {
                (t, q, v) = (t + h, q1, v1);
                continue;
            };
            (q, v) = self.rk4(minv, t, &q, &v, tau);
            t += tau;
            let (_, j, side) = g0[w];
            let (d, lo, hi, e) = self.contacts[j];
            match side {
                None => {
                    events.push(Ev { t, kind: EventKind::Release, contact: j, before: 0.0, after: 0.0 });
                    held = None;
                }
                Some(upper) => {
                    q[d] = if upper { hi } else { lo };
                    let before = v[d];
                    let p = -(1.0 + e) * before / full[d * n + d];
                    for i in 0..n {
                        v[i] += full[i * n + d] * p;
                    }
                    doubt.slowest = doubt.slowest.min(before.abs());
                    events.push(Ev { t, kind: EventKind::Impact, contact: j, before, after: v[d] });
                    if e == 0.0 {
                        v[d] = 0.0;
                        let r = self.force(&reduced[j], d, t, &q, &v);
                        if (if upper { -r } else { r }) > 0.0 {
                            held = Some((j, upper));
                        }
                    }
                }
            }
        }
        (events, q, v, doubt)
    }
}

/// A random small system (the proptest's case).
#[derive(Clone, Debug)]
struct Case {
    n: usize,
    /// Per dof: a lumped mass, a spring to the ground, the steady load, the
    /// forcing's shape, the start.
    lumped: Vec<f64>,
    ground: Vec<f64>,
    load: Vec<f64>,
    shape: Vec<f64>,
    q0: Vec<f64>,
    v0: Vec<f64>,
    /// Per link `(i, i + 1)`: a consistent element mass and a spring.
    element: Vec<f64>,
    spring: Vec<f64>,
    amplitude: f64,
    omega: f64,
    /// Rayleigh `C = a M + b K`.
    rayleigh: Option<(f64, f64)>,
    /// The contacts: dof, which bounds (0 lower, 1 upper, 2 both), the
    /// distances of the bounds from the start, the restitution.
    contacts: Vec<(usize, u8, f64, f64, f64)>,
}

impl Case {
    fn dynamics(&self) -> Dynamics {
        let n = self.n;
        let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
        for i in 0..n {
            m.set(i, i, self.lumped[i]);
            k.set(i, i, self.ground[i]);
        }
        for i in 0..n - 1 {
            let (me, ke) = (self.element[i], self.spring[i]);
            for (a, b, mv, kv) in [(i, i, me / 3.0, ke), (i + 1, i + 1, me / 3.0, ke), (i + 1, i, me / 6.0, -ke)] {
                m.set(a, b, m.get(a, b) + mv);
                k.set(a, b, k.get(a, b) + kv);
            }
        }
        let contacts = self
            .contacts
            .iter()
            .map(|&(d, sides, below, above, e)| {
                let lo = if sides != 1 { self.q0[d] - below } else { f64::NEG_INFINITY };
                let hi = if sides != 0 { self.q0[d] + above } else { f64::INFINITY };
                Contact::new(d, Bounds { lo, hi }, false).with_restitution(Some(e))
            })
            .collect();
        let damping = self.rayleigh.map(|(a, b)| m.lin_comb(a, &k, b));
        Dynamics::new(m, k, self.load.clone(), contacts)
            .with_forcing(vec![Forcing { shape: self.shape.clone(), time: TimeProfile::Sine { amplitude: self.amplitude, omega: self.omega } }])
            .with_damping(damping)
    }
}

prop_compose! {
    fn sizes()(n in 1usize..=N)(n in Just(n), k in 1..=n.min(3), dofs in Just((0..n).collect::<Vec<usize>>()).prop_shuffle()) -> (usize, usize, Vec<usize>) {
        (n, k, dofs)
    }
}

prop_compose! {
    fn case()((n, k, dofs) in sizes())(
        n in Just(n),
        dofs in Just(dofs[..k].to_vec()),
        lumped in vec(0.5f64..1.5, n),
        ground in vec(0.05f64..1.0, n),
        load in vec(-0.2f64..0.2, n),
        shape in vec(-1.0f64..1.0, n),
        q0 in vec(-0.05f64..0.05, n),
        v0 in vec(-1.5f64..1.5, n),
        element in vec(0.0f64..1.0, n - 1),
        spring in vec(0.2f64..3.0, n - 1),
        amplitude in 0.0f64..1.0,
        omega in 0.5f64..3.0,
        rayleigh in proptest::option::of((0.0f64..0.1, 0.0f64..0.02)),
        sides in vec((0u8..3, 0.1f64..0.6, 0.1f64..0.6, 0.3f64..=1.0), k),
    ) -> Case {
        let contacts = dofs.iter().zip(&sides).map(|(&d, &(s, below, above, e))| (d, s, below, above, e)).collect();
        Case { n, lumped, ground, load, shape, q0, v0, element, spring, amplitude, omega, rayleigh, contacts }
    }
}

/// The oracle stops after this many events (it does not detect an
/// accumulation of impacts: the cases that come near one are rejected).
const MAX_ORACLE_EVENTS: usize = 40;

/// The oracle's step (module docs).
const H: f64 = 1e-3;
/// The horizon of the random runs.
const T_END: f64 = 5.0;

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, max_global_rejects: 4096, ..ProptestConfig::default() })]
    /// Random chains (n <= 8, up to three contacts at distinct dofs with one
    /// or two bounds, restitutions in [0.3, 1], a harmonic load, Rayleigh
    /// damping or none): every impact of the event-driven run at the
    /// oracle's time, with its contact, side and velocities, and the same
    /// final state. Cases the oracle cannot resolve honestly are rejected:
    /// an impact slower than 0.05 (near grazing or chattering), a gap
    /// passing a minimum within 1e-3 of its bound (a graze a fixed step may
    /// miss), two events closer than 1e-2 (near-simultaneous impacts are
    /// the LCP's, tested elsewhere), more than 10 impacts.
    #[test]
    fn random_impacting_chains_match_a_fine_rk4_oracle(case in case()) {
        check_case(&case, case.dynamics())?;
    }

    /// The same with a piecewise-linear load on top (2 to 5 points at
    /// random times in [0, 5], random values and shape): the event-driven
    /// run stops at each breakpoint and takes the next piece's ramp, the
    /// oracle's steps end there.
    #[test]
    fn random_chains_under_a_piecewise_linear_load_match_the_oracle(
        case in case(),
        ramp in vec(-1.0f64..1.0, N),
        pts in vec((0.1f64..1.5, -0.6f64..0.6), 2..6),
    ) {
        let mut dy = case.dynamics();
        let mut t = -0.1;
        let (times, values): (Vec<f64>, Vec<f64>) = pts.iter().map(|&(d, v)| { t += d; (t, v) }).unzip();
        dy.forcing.push(Forcing { shape: ramp[..case.n].to_vec(), time: TimeProfile::series(times, values).unwrap() });
        check_case(&case, dy)?;
    }

    /// With a dashpot at one dof on top of the case's damping (no modes of
    /// `(K, M)` diagonalise `C`: the first-order form, also for the held
    /// phases' reduced systems).
    #[test]
    fn random_chains_with_a_nonclassical_damper_match_the_oracle(
        case in case(),
        at in 0usize..N,
        d in 0.05f64..1.0,
        series in proptest::option::of((vec(-1.0f64..1.0, N), vec((0.1f64..1.5, -0.6f64..0.6), 2..6))),
    ) {
        let mut dy = case.dynamics();
        let at = at % case.n;
        prop_assume!(case.n >= 2);
        let mut c = dy.damping.take().unwrap_or_else(|| SymBand::zeros(case.n, 1));
        c.set(at, at, c.get(at, at) + d);
        dy.damping = Some(c);
        // Half the cases with a series on top (the first-order form's load
        // shift then has ramps).
        if let Some((ramp, pts)) = series {
            let mut t = -0.1;
            let (times, values): (Vec<f64>, Vec<f64>) = pts.iter().map(|&(d, v)| { t += d; (t, v) }).unzip();
            dy.forcing.push(Forcing { shape: ramp[..case.n].to_vec(), time: TimeProfile::series(times, values).unwrap() });
        }
        check_case(&case, dy)?;
    }
}

/// One random case against the oracle (the proptests above).
fn check_case(case: &Case, dy: Dynamics) -> Result<(), TestCaseError> {
    let e: Vec<f64> = case.contacts.iter().map(|c| c.4).collect();
    let oracle = Oracle::from(&dy, &e, H);
    let (want, qo, vo, doubt) = oracle.run(0.0, &case.q0, &case.v0, T_END);
    prop_assume!(doubt.slowest >= 0.05 && doubt.closest_graze >= 1e-3 && want.len() <= 10);
    prop_assume!(want.windows(2).all(|w| w[1].t - w[0].t >= 1e-2));
    let mut run = EventDriven::new(&dy, 0.0, &case.q0, &case.v0, 0.5).unwrap();
    run.run_until(T_END, 1000).unwrap();
    let got = run.events();
    let show = |x: &[Ev]| x.iter().map(|e| format!("{:.12} {:?} {} {:.6}", e.t, e.kind, e.contact, e.before)).collect::<Vec<_>>().join("; ");
    prop_assert_eq!(got.len(), want.len(), "events {:?}\nagainst the oracle's {}", got, show(&want));
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        prop_assert!(g.kind == w.kind && g.contact == w.contact, "event {}: {:?} against {:?}", i, g, w);
        prop_assert!((g.t - w.t).abs() <= TOL_T, "event {}: t = {} against {} ({:e})", i, g.t, w.t, g.t - w.t);
        let vs = w.before.abs().max(1.0);
        prop_assert!((g.velocity_before - w.before).abs() <= TOL_V * vs, "event {}: v⁻ = {} against {}", i, g.velocity_before, w.before);
        prop_assert!((g.velocity_after - w.after).abs() <= TOL_V * vs, "event {}: v⁺ = {} against {}", i, g.velocity_after, w.after);
        prop_assert!(g.velocity_before.signum() != g.velocity_after.signum() || g.velocity_after == 0.0, "event {}: {:?}", i, g);
    }
    let (t, q, v) = run.state();
    prop_assert_eq!(t, T_END);
    for i in 0..case.n {
        prop_assert!((q[i] - qo[i]).abs() <= TOL_Q && (v[i] - vo[i]).abs() <= TOL_Q, "dof {}: (q, v) = ({}, {}) against ({}, {})", i, q[i], v[i], qo[i], vo[i]);
    }
    Ok(())
}

/// The tolerances (absolute; times <= 20, velocities and displacements of
/// order 1): the oracle's own error bound of the module docs is `~1e-9` in
/// an event time; measured over 200 random cases, the largest differences
/// were 4e-12 in an event time, 6e-12 in a velocity, 1e-11 in the final
/// state (2e-11 in the held chain's times). 1e-9 leaves a factor 100.
const TOL_T: f64 = 1e-9;
const TOL_V: f64 = 1e-9;
const TOL_Q: f64 = 1e-9;

/// The held chains below against the oracle, from `(q0, v0)` over
/// `[0, t_end]` with `e = 0`: the same events (at least two releases), each
/// landing at rest, and the same final state.
fn held_chain_matches_the_oracle(dy: &Dynamics, q0: &[f64], v0: &[f64], t_end: f64) {
    let n = dy.n();
    let mut run = EventDriven::new(dy, 0.0, q0, v0, 0.0).unwrap();
    run.run_until(t_end, 100).unwrap();
    let got = run.events().to_vec();
    let oracle = Oracle::from(dy, &[0.0], H);
    let (want, qo, vo, _) = oracle.run(0.0, q0, v0, t_end);
    assert_eq!(got.len(), want.len(), "{got:?}\nagainst {want:?}");
    assert!(want.iter().filter(|e| e.kind == EventKind::Release).count() >= 2, "{want:?}");
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!(g.kind == w.kind && g.contact == w.contact, "event {i}: {g:?} against {w:?}");
        assert!((g.t - w.t).abs() <= TOL_T, "event {i}: t = {} against {} ({:e})", g.t, w.t, g.t - w.t);
        assert!((g.velocity_before - w.before).abs() <= TOL_V, "event {i}: v⁻ = {} against {}", g.velocity_before, w.before);
        assert_eq!(g.velocity_after, 0.0);
    }
    let (_, q, v) = run.state();
    for i in 0..n {
        assert!((q[i] - qo[i]).abs() <= TOL_Q && (v[i] - vo[i]).abs() <= TOL_Q, "dof {i}: (q, v) = ({}, {}) against ({}, {})", q[i], v[i], qo[i], vo[i]);
    }
}

/// A chain of three masses over a stop at `−0.1` under its first one,
/// `e = 0`, pressed by a steady load and shaken by a harmonic one: it lands
/// with zero restitution, stays held while its contact force is positive,
/// is released when that force reaches 0, flies and lands again. The events
/// against the oracle's, whose held phases are RK4 on the two free masses
/// and whose releases are the sign changes of the force computed from the
/// equation.
#[test]
fn a_held_chain_is_released_when_its_force_computed_from_the_equation_vanishes() {
    held_chain_matches_the_oracle(&held_chain(false, false), &[0.0, 0.0, 0.0], &[-0.5, 0.2, 0.1], 20.0);
}

/// The held chain under a piecewise-linear load instead of the harmonic
/// one: pressed on its stop while the load pushes, released when the
/// ramp of the current piece brings the contact force to 0 (the force's
/// ramp term, not only its constant), against the oracle.
#[test]
fn a_held_chain_is_released_by_a_ramp_of_a_piecewise_linear_load() {
    held_chain_matches_the_oracle(&held_chain(true, false), &[0.0, 0.0, 0.0], &[-0.5, 0.2, 0.1], 20.0);
}

/// The held chain with a dashpot on its second mass (non-classical damping:
/// the held phase's reduced system too) and zero restitution on a stop that
/// it lands on and leaves several times, against the oracle.
#[test]
fn a_held_chain_with_a_dashpot_is_released_when_its_force_vanishes() {
    held_chain_matches_the_oracle(&held_chain(false, true), &[0.0, 0.0, 0.0], &[-0.5, 0.2, 0.1], 20.0);
}

/// The ramp-released chain with the dashpot too: the first-order form's
/// held force with the series' ramps.
#[test]
fn a_held_chain_with_a_dashpot_is_released_by_a_ramp() {
    held_chain_matches_the_oracle(&held_chain(true, true), &[0.0, 0.0, 0.0], &[-0.5, 0.2, 0.1], 20.0);
}

/// The held chains' problem: three masses over a stop at `−0.1` under the
/// first, Rayleigh damping, a steady load and a harmonic one (`ramp`:
/// a piecewise-linear one instead), a dashpot of 0.4 on the second mass if
/// `dashpot`.
fn held_chain(ramp: bool, dashpot: bool) -> Dynamics {
    let (m, k) = common::chain_matrices(3, false);
    let mut c = m.lin_comb(0.02, &k, 0.01);
    if dashpot {
        c.set(1, 1, c.get(1, 1) + 0.4);
    }
    let (load, time) = if ramp {
        (vec![-0.05, -0.05, 0.0], TimeProfile::series(vec![0.0, 3.0, 8.0, 11.0, 15.5, 20.0], vec![0.0, -0.3, 0.25, -0.2, 0.4, -0.1]).unwrap())
    } else {
        (vec![-0.1, -0.05, 0.0], TimeProfile::Sine { amplitude: 0.4, omega: 1.3 })
    };
    Dynamics::new(m, k, load, vec![Contact::new(0, Bounds::obstacle(-0.1), false)]).with_forcing(vec![Forcing { shape: vec![1.0, 0.5, 0.0], time }]).with_damping(Some(c))
}
