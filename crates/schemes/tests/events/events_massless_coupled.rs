//! Event-driven runs with several massless contact dofs COUPLED through
//! `K_ZZ` (docs/theory.md §9.3, "Massless contact dofs"), loads applied at
//! the massless dofs themselves, against an oracle written here: the
//! massive dofs by classical RK4 with a fixed step, the massless dofs at
//! every stage at the exact solution of their static LCP
//! `K_ZZ q_Z + K_ZR q_R = f_Z(t) + r`, `lo ≤ q_Z ≤ hi`, `r ⟂` the bounds,
//! found by enumerating every active set (each contact free, at its lower
//! or at its upper bound) and keeping the one that satisfies the KKT
//! conditions; a landing or a release located by bisection where that
//! active set changes. Neither the event crate's condensation, its LCPs nor
//! its modal flow is used. `events_massless.rs` has no such case: its
//! massless dofs are never neighbours (`K_ZZ` diagonal), so a free
//! contact's position never reads another massless dof's load and a held
//! contact's force never reads a free one.

use crate::events_common as common;

use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind, EventsError};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, TimeProfile};

const N: usize = 6;
type V = [f64; N];

/// A structure of `n` dofs: springs `(i, j, k)` between dofs, springs
/// `(i, k)` to the ground, masses `(i, j, m)` (the diagonal and the
/// couplings of the massive dofs), as dense banded matrices.
fn structure(n: usize, springs: &[(usize, usize, f64)], grounds: &[(usize, f64)], masses: &[(usize, usize, f64)]) -> (SymBand, SymBand) {
    let (mut m, mut k) = (SymBand::zeros(n, n - 1), SymBand::zeros(n, n - 1));
    for &(i, j, s) in springs {
        let (a, b) = (i.max(j), i.min(j));
        k.set(a, a, k.get(a, a) + s);
        k.set(b, b, k.get(b, b) + s);
        k.set(a, b, k.get(a, b) - s);
    }
    for &(i, s) in grounds {
        k.set(i, i, k.get(i, i) + s);
    }
    for &(i, j, x) in masses {
        let (a, b) = (i.max(j), i.min(j));
        m.set(a, b, m.get(a, b) + x);
    }
    (m, k)
}

/// The static solution of the massless dofs at one instant.
#[derive(Clone, Debug)]
struct Static {
    /// The full displacement (the massless dofs solved).
    q: V,
    /// Per contact: its force `r = (K q − f)_c` (0 when free).
    r: Vec<f64>,
    /// Per contact: 0 free, 1 at its lower bound, 2 at its upper one.
    status: Vec<u8>,
}

struct Oracle {
    n: usize,
    k: Vec<f64>,
    load: common::Load,
    /// The contacts `(dof, lo, hi)` (the massless dofs).
    sites: Vec<(usize, f64, f64)>,
    mass: Vec<usize>,
    /// `M_RR⁻¹` embedded in `n × n`.
    minv: Vec<f64>,
    /// Per set of free contacts (a bit mask): `K_SS⁻¹` embedded in `n × n`.
    inv: Vec<Vec<f64>>,
}

/// An oracle event: (t, kind, contact, speed of the massless dof before).
#[derive(Debug, Clone, Copy)]
struct Ev {
    t: f64,
    kind: EventKind,
    contact: usize,
    before: f64,
}

/// A sample of the oracle: t, q, v (massless dofs' rates included), forces.
type Sample = (f64, V, V, Vec<f64>);

impl Oracle {
    fn new(dy: &Dynamics) -> Self {
        let n = dy.n();
        let dense = |b: &SymBand| (0..n * n).map(|x| b.get(x / n, x % n)).collect::<Vec<f64>>();
        let (m, k) = (dense(&dy.mass), dense(&dy.stiffness));
        let sites: Vec<(usize, f64, f64)> = dy.contacts.iter().map(|c| (c.dof, c.bounds.lo, c.bounds.hi)).collect();
        let mass: Vec<usize> = (0..n).filter(|d| !sites.iter().any(|s| s.0 == *d)).collect();
        let minv = common::inverse(&m, n, &mass);
        let inv = (0..1usize << sites.len())
            .map(|mask| {
                let dofs: Vec<usize> = sites.iter().enumerate().filter(|(j, _)| mask >> j & 1 == 1).map(|(_, s)| s.0).collect();
                common::inverse(&k, n, &dofs)
            })
            .collect();
        Self { n, k, load: common::Load::of(dy), sites, mass, minv, inv }
    }

    /// The static LCP of the massless dofs at `t` given the massive ones
    /// in `q`: every active set tried, the one with the smallest violation
    /// of its KKT conditions kept (0 but at an event, where two tie).
    fn statics(&self, t: f64, q: &V) -> Static {
        let (n, nz) = (self.n, self.sites.len());
        let mut best: Option<(f64, Static)> = None;
        for code in 0..3usize.pow(nz as u32) {
            let status: Vec<u8> = (0..nz).map(|j| (code / 3usize.pow(j as u32) % 3) as u8).collect();
            if status.iter().zip(&self.sites).any(|(&s, &(_, lo, hi))| (s == 1 && !lo.is_finite()) || (s == 2 && !hi.is_finite())) {
                continue;
            }
            let mut x = *q;
            let mut mask = 0;
            for (j, &(d, lo, hi)) in self.sites.iter().enumerate() {
                match status[j] {
                    0 => mask |= 1 << j,
                    1 => x[d] = lo,
                    _ => x[d] = hi,
                }
            }
            let free: Vec<usize> = (0..nz).filter(|j| mask >> j & 1 == 1).map(|j| self.sites[j].0).collect();
            let b: Vec<f64> = free.iter().map(|&i| self.load.value(i, t) - (0..n).filter(|j| !free.contains(j)).map(|j| self.k[i * n + j] * x[j]).sum::<f64>()).collect();
            let inv = &self.inv[mask];
            for &i in &free {
                x[i] = free.iter().zip(&b).map(|(&j, bj)| inv[i * n + j] * bj).sum();
            }
            let mut r = vec![0.0; nz];
            let mut violation = 0.0f64;
            for (j, &(d, lo, hi)) in self.sites.iter().enumerate() {
                if status[j] == 0 {
                    violation = violation.max(lo - x[d]).max(x[d] - hi);
                } else {
                    r[j] = (0..n).map(|l| self.k[d * n + l] * x[l]).sum::<f64>() - self.load.value(d, t);
                    violation = violation.max(if status[j] == 1 { -r[j] } else { r[j] });
                }
            }
            if best.as_ref().is_none_or(|b| violation < b.0) {
                best = Some((violation, Static { q: x, r, status }));
            }
        }
        best.expect("an active set").1
    }

    /// The massless dofs' rates in the active set `status`: a free one's
    /// `K_SS⁻¹ (f_S' − K_S· v)` (held ones at rest), into `v`.
    fn rates(&self, t: f64, status: &[u8], v: &mut V) {
        let n = self.n;
        let mut mask = 0;
        for (j, &(d, _, _)) in self.sites.iter().enumerate() {
            if status[j] == 0 {
                mask |= 1 << j;
            } else {
                v[d] = 0.0;
            }
        }
        let free: Vec<usize> = (0..self.sites.len()).filter(|j| mask >> j & 1 == 1).map(|j| self.sites[j].0).collect();
        let b: Vec<f64> = free.iter().map(|&i| self.load.rate(i, t) - (0..n).filter(|j| !free.contains(j)).map(|j| self.k[i * n + j] * v[j]).sum::<f64>()).collect();
        let inv = &self.inv[mask];
        let out: Vec<f64> = free.iter().map(|&i| free.iter().zip(&b).map(|(&j, bj)| inv[i * n + j] * bj).sum()).collect();
        for (&i, x) in free.iter().zip(out) {
            v[i] = x;
        }
    }

    fn accel(&self, t: f64, q: &V) -> V {
        let n = self.n;
        let q = self.statics(t, q).q;
        let rhs: Vec<f64> = (0..n).map(|i| self.load.value(i, t) - (0..n).map(|j| self.k[i * n + j] * q[j]).sum::<f64>()).collect();
        let mut a = [0.0; N];
        for &d in &self.mass {
            a[d] = (0..n).map(|j| self.minv[d * n + j] * rhs[j]).sum();
        }
        a
    }

    fn rk4(&self, t: f64, q: &V, v: &V, h: f64) -> (V, V) {
        let axpy = |x: &V, a: f64, y: &V| -> V { std::array::from_fn(|i| x[i] + a * y[i]) };
        let k1 = (*v, self.accel(t, q));
        let (q2, v2) = (axpy(q, h / 2.0, &k1.0), axpy(v, h / 2.0, &k1.1));
        let k2 = (v2, self.accel(t + h / 2.0, &q2));
        let (q3, v3) = (axpy(q, h / 2.0, &k2.0), axpy(v, h / 2.0, &k2.1));
        let k3 = (v3, self.accel(t + h / 2.0, &q3));
        let (q4, v4) = (axpy(q, h, &k3.0), axpy(v, h, &k3.1));
        let k4 = (v4, self.accel(t + h, &q4));
        let q1 = std::array::from_fn(|i| q[i] + h / 6.0 * (k1.0[i] + 2.0 * k2.0[i] + 2.0 * k3.0[i] + k4.0[i]));
        let v1 = std::array::from_fn(|i| v[i] + h / 6.0 * (k1.1[i] + 2.0 * k2.1[i] + 2.0 * k3.1[i] + k4.1[i]));
        (q1, v1)
    }

    /// The full sample at `t`: the static solution and the massless rates.
    fn sample(&self, t: f64, q: &V, v: &V) -> Sample {
        let s = self.statics(t, q);
        let mut w = *v;
        self.rates(t, &s.status, &mut w);
        (t, s.q, w, s.r)
    }

    /// Runs from `(q0, v0)` (massive dofs) to the last of `samples`: the
    /// events and the samples. Steps end at the samples.
    fn run(&self, q0: &[f64], v0: &[f64], samples: &[f64], h: f64) -> (Vec<Ev>, Vec<Sample>) {
        let (mut q, mut v) = ([0.0; N], [0.0; N]);
        q[..self.n].copy_from_slice(q0);
        v[..self.n].copy_from_slice(v0);
        let mut t = 0.0;
        let (mut events, mut out) = (Vec::new(), Vec::new());
        let mut next = 0;
        // The active set just after the start (at the start a contact on
        // its bound without force ties both sets: its rate decides).
        let mut status = self.statics(1e-9, &self.rk4(0.0, &q, &v, 1e-9).0).status;
        let mut instant = (f64::NEG_INFINITY, status.clone());
        while next < samples.len() {
            if t >= samples[next] {
                out.push(self.sample(t, &q, &v));
                next += 1;
                continue;
            }
            // Steps end at the samples and at the series' breakpoints.
            let step = h.min(samples[next] - t).min(self.load.to_kink(t));
            let (q1, v1) = self.rk4(t, &q, &v, step);
            if self.statics(t + step, &q1).status == status {
                (t, q, v) = (t + step, q1, v1);
                continue;
            }
            // The first change of the active set in the step.
            let (mut a, mut b) = (0.0, step);
            for _ in 0..64 {
                let mid = 0.5 * (a + b);
                let (qm, _) = self.rk4(t, &q, &v, mid);
                if self.statics(t + mid, &qm).status == status {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            let (qb, vb) = self.rk4(t, &q, &v, b);
            let after = self.statics(t + b, &qb).status;
            // The landing speeds: the free rates of the active set before
            // (before the instant: two contacts reached together, located
            // by round-off a few ulps apart, both take the set before both).
            if t + b - instant.0 > 1e-12 {
                instant = (t + b, status.clone());
            }
            let mut w = vb;
            self.rates(t + b, &instant.1, &mut w);
            for j in 0..self.sites.len() {
                if (status[j] == 0) != (after[j] == 0) {
                    let landing = status[j] == 0;
                    events.push(Ev { t: t + b, kind: if landing { EventKind::Impact } else { EventKind::Release }, contact: j, before: if landing { w[self.sites[j].0] } else { 0.0 } });
                }
            }
            (t, q, v, status) = (t + b, qb, vb, after);
            assert!(events.len() < 200, "an oracle event list too long");
        }
        (events, out)
    }
}

/// A case: the structure, its loads, bounds and start.
struct Case {
    dy: Dynamics,
    q0: Vec<f64>,
    v0: Vec<f64>,
    /// Sample times (the last one the end).
    samples: Vec<f64>,
}

/// The largest differences of a run against the oracle, by quantity.
#[derive(Debug, Default)]
struct Diff {
    events: usize,
    t: f64,
    before: f64,
    q: f64,
    v: f64,
    r: f64,
}

/// Runs `case` by `EventDriven` and the oracle (step `h`); asserts the
/// same events (kind, contact; time, landing speed within `tol`) and at
/// every sample the state (every dof, the massless dofs' rates included)
/// and the held forces within `tol` of the state's (forces') scale.
fn check(name: &str, case: &Case, h: f64, tol: f64) -> Diff {
    let oracle = Oracle::new(&case.dy);
    let (want, samples) = oracle.run(&case.q0, &case.v0, &case.samples, h);
    let mut run = EventDriven::new(&case.dy, 0.0, &case.q0, &case.v0, 0.0).unwrap();
    let mut d = Diff { events: want.len(), ..Diff::default() };
    for (t, qo, vo, ro) in &samples {
        run.run_until(*t, 10_000).unwrap();
        let (_, q, v) = run.state();
        let r = run.forces();
        let scale = (0..oracle.n).fold(1e-3f64, |a, i| a.max(qo[i].abs()).max(vo[i].abs()));
        let fscale = ro.iter().fold(1e-3f64, |a, x| a.max(x.abs()));
        for i in 0..oracle.n {
            d.q = d.q.max((q[i] - qo[i]).abs() / scale);
            d.v = d.v.max((v[i] - vo[i]).abs() / scale);
        }
        for j in 0..ro.len() {
            d.r = d.r.max((r[j] - ro[j]).abs() / fscale);
        }
        assert!(d.q <= tol && d.v <= tol && d.r <= tol, "{name}, t = {t}: q {q:?} v {v:?} r {r:?}\nagainst q {qo:?} v {vo:?} r {ro:?}\n{d:?}");
    }
    let mut got = run.events().to_vec();
    assert_eq!(got.len(), want.len(), "{name}: {got:?}\nagainst {want:?}");
    // Events of one instant (contacts reached together, located a few
    // ulps apart in either order) in the order of their contacts.
    let mut want = want;
    for i in 1..want.len() {
        let mut j = i;
        while j > 0 && (want[j].t - want[j - 1].t).abs() <= 1e-9 && want[j].contact < want[j - 1].contact {
            want.swap(j, j - 1);
            j -= 1;
        }
    }
    for i in 1..got.len() {
        let mut j = i;
        while j > 0 && (got[j].t - got[j - 1].t).abs() <= 1e-9 && got[j].contact < got[j - 1].contact {
            got.swap(j, j - 1);
            j -= 1;
        }
    }
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!(g.kind == w.kind && g.contact == w.contact, "{name}, event {i}: {g:?} against {w:?}");
        d.t = d.t.max((g.t - w.t).abs());
        d.before = d.before.max((g.velocity_before - w.before).abs() / w.before.abs().max(1.0));
        assert!(d.t <= tol && d.before <= tol, "{name}, event {i}: {g:?} against {w:?}");
        assert!(g.velocity_after == 0.0 && g.impulse == 0.0);
    }
    eprintln!("{name}: {d:?}");
    d
}

fn samples(t_end: f64, k: usize) -> Vec<f64> {
    (1..=k).map(|i| t_end * i as f64 / k as f64).collect()
}

/// Two massless contact dofs 0 and 1 coupled by a spring (`K_01 ≠ 0`, so
/// `G_01 = (K_ZZ⁻¹)_01 ≠ 0`), three masses; a steady and a harmonic load
/// at `load_dof`.
fn pair(load: [f64; 5], shape: [f64; 5], amplitude: f64, omega: f64, bounds: [(f64, f64); 2], v0: [f64; 5], t_end: f64) -> Case {
    let (m, k) = structure(5, &[(0, 1, 2.0), (1, 2, 1.5), (0, 2, 0.5), (2, 3, 1.0), (3, 4, 1.2)], &[(4, 0.4), (1, 0.3)], &[(2, 2, 1.0), (3, 3, 0.8), (4, 4, 1.1), (3, 2, 0.1), (4, 3, 0.15)]);
    let contacts = vec![Contact::new(0, Bounds { lo: bounds[0].0, hi: bounds[0].1 }, true), Contact::new(1, Bounds { lo: bounds[1].0, hi: bounds[1].1 }, true)];
    let dy = Dynamics::new(m, k, load.to_vec(), contacts).with_forcing(vec![Forcing { shape: shape.to_vec(), time: TimeProfile::Sine { amplitude, omega } }]);
    Case { dy, q0: vec![0.0, 0.0, 0.05, -0.03, 0.02], v0: v0.to_vec(), samples: samples(t_end, 8) }
}

/// Three massless contact dofs 0, 1, 2 coupled to each other (a spring
/// 0–2 too: a held contact 0 loads a free 2, and through `G_12` a free 1),
/// three masses 3, 4, 5.
fn triple(load: [f64; 6], shape: [f64; 6], amplitude: f64, omega: f64, lo: [f64; 3], v0: [f64; 6], t_end: f64) -> Case {
    let springs = [(0, 1, 1.5), (1, 2, 2.0), (0, 2, 0.8), (0, 3, 1.0), (1, 4, 1.2), (2, 5, 0.9), (3, 4, 1.0), (4, 5, 0.7)];
    let (m, k) = structure(6, &springs, &[(3, 0.3), (5, 0.5)], &[(3, 3, 1.0), (4, 4, 0.9), (5, 5, 1.2), (4, 3, 0.1), (5, 4, 0.12)]);
    let contacts = (0..3).map(|j| Contact::new(j, Bounds::obstacle(lo[j]), true)).collect();
    let dy = Dynamics::new(m, k, load.to_vec(), contacts).with_forcing(vec![Forcing { shape: shape.to_vec(), time: TimeProfile::Sine { amplitude, omega } }]);
    Case { dy, q0: vec![0.0, 0.0, 0.0, 0.02, -0.01, 0.03], v0: v0.to_vec(), samples: samples(t_end, 8) }
}

/// A mirror-symmetric structure: massless ends 0 and 3 (springs 0–1, 2–3,
/// and 0–3: `K_03 ≠ 0`), masses 1 and 2; both ends between the same bounds.
fn mirror(load: f64, amplitude: f64, omega: f64, bounds: (f64, f64), q0: f64, v0: f64, t_end: f64) -> Case {
    let (m, k) = structure(4, &[(0, 1, 2.0), (2, 3, 2.0), (0, 3, 0.7), (1, 2, 1.0)], &[(1, 0.4), (2, 0.4)], &[(1, 1, 1.0), (2, 2, 1.0), (2, 1, 0.2)]);
    let contacts = [0, 3].iter().map(|&d| Contact::new(d, Bounds { lo: bounds.0, hi: bounds.1 }, true)).collect();
    let shape = vec![1.0, 0.0, 0.0, 1.0];
    let dy = Dynamics::new(m, k, vec![load, 0.0, 0.0, load], contacts).with_forcing(vec![Forcing { shape, time: TimeProfile::Sine { amplitude, omega } }]);
    Case { dy, q0: vec![0.0, q0, q0, 0.0], v0: vec![0.0, v0, v0, 0.0], samples: samples(t_end, 8) }
}

/// The case for a free contact's position: `q_0 = Σ_i G_0i (f_i − K_iR
/// q_R − K_iA q_A)` reads the harmonic load at massless dof 1 through
/// `G_01` (contact 0 has no load of its own). Contact 0 lands and leaves
/// its stops, then contact 1 lands while 0 is held (the held force of 0
/// reads 1's load through `K_01 G_11`, and 1's position 0's bound through
/// `G_11 K_10`), both are held, 1 leaves.
fn neighbour_load() -> Case {
    pair([0.0, 0.02, 0.0, 0.0, -0.01], [0.0, 1.0, 0.0, 0.0, 0.0], 0.1, 1.3, [(-0.05, 0.06), (-0.08, f64::INFINITY)], [0.0, 0.0, 0.3, -0.2, 0.1], 10.0)
}

/// Step and tolerance of the comparisons. At `h = 1e-3` the oracle is
/// within 1.2e-11 (event times) and 8e-12 (state) of itself at `h = 2e-3`
/// (the neighbour case), and the runs within 7.7e-12 (times), 2.2e-12
/// (state) and 7.1e-12 (massless rates) relative to the state's scale,
/// 1.5e-11 (forces, relative to theirs) of it.
const H: f64 = 1e-3;
const TOL: f64 = 1e-9;

/// A free massless contact's landings read the load applied at another
/// massless dof coupled to it (`G_01 f_1`), and a held one's force reads
/// the free one's load, position and bound: 9 events (contact 0: 4
/// landings, 3 releases; contact 1: a landing and a release while 0 is
/// held), the state, the massless rates and the held forces at 8 times.
#[test]
fn a_massless_contact_reads_the_load_at_its_coupled_massless_neighbour() {
    let d = check("neighbour load", &neighbour_load(), H, TOL);
    assert_eq!(d.events, 9);
}

/// Three massless contacts coupled to each other (`K_02 ≠ 0`): contact 0
/// starts held by its own load, leaves, lands again; while it is held the
/// free contacts 1 and 2 read its bound through each other (`G_21 K_10
/// lo_0`), contact 2 lands and leaves, 0 leaves (5 events).
#[test]
fn three_coupled_massless_contacts_read_each_others_bounds() {
    let case = triple([-0.1, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 1.0, -0.5, 0.0, 0.0, 0.0], 0.1, 1.2, [-0.02, -0.06, -0.05], [0.0, 0.0, 0.0, 0.2, -0.1, 0.1], 10.0);
    let d = check("three contacts", &case, H, TOL);
    assert_eq!(d.events, 5);
}

/// Two massless ends of a mirror-symmetric structure coupled through
/// `K_03`: they land together, at the same speed, and leave together, 7
/// times over (14 events, each pair within 1e-9 s of the oracle's one
/// instant).
#[test]
fn two_massless_contacts_reached_at_one_instant_land_and_leave_together() {
    let case = mirror(-0.02, 0.05, 1.7, (-0.04, 0.05), 0.01, -0.2, 10.0);
    let d = check("mirror", &case, H, TOL);
    assert_eq!(d.events, 14);
}

/// A massless contact pressed on its stop at the start (its static force
/// positive) by its own load, which reverses (a harmonic larger than the
/// steady part): it leaves the instant its force reaches 0, lands again
/// when its static position comes back (13 events over 10 s). Its
/// neighbour carries a load too.
#[test]
fn a_massless_contact_pressed_at_the_start_leaves_when_its_own_load_reverses() {
    let case = pair([-0.2, 0.0, 0.0, 0.0, 0.0], [1.0, 0.5, 0.0, 0.0, 0.0], 0.3, 1.1, [(-0.01, 0.08), (-0.1, 0.1)], [0.0, 0.0, 0.1, -0.1, 0.0], 10.0);
    let run = EventDriven::new(&case.dy, 0.0, &case.q0, &case.v0, 0.0).unwrap();
    assert_eq!(run.held(), vec![(0, false)]);
    let d = check("pressed at the start", &case, H, TOL);
    assert_eq!(d.events, 13);
}

/// A massless dof's entries of the start `(q0, v0)` are not data: its
/// position is the static solution. A start that puts contact 0 on its
/// upper bound moving away (the marks of a contact that an event has put
/// on its bound, leaving it) while its static position is inside, moving
/// towards that bound, gives the same run, bit for bit, as the start at
/// the static position.
#[test]
fn a_massless_dofs_start_entries_do_not_change_the_run() {
    let case = neighbour_load();
    let mut clean = EventDriven::new(&case.dy, 0.0, &case.q0, &case.v0, 0.0).unwrap();
    let (_, q, _) = clean.state();
    assert!(q[0] > -0.05 + 1e-3, "inside at the start: {}", q[0]);
    let (mut q0, mut v0) = (case.q0.clone(), case.v0.clone());
    (q0[0], v0[0], q0[1], v0[1]) = (0.06, -1.0, 0.3, -2.0);
    let mut marked = EventDriven::new(&case.dy, 0.0, &q0, &v0, 0.0).unwrap();
    clean.run_until(10.0, 1000).unwrap();
    marked.run_until(10.0, 1000).unwrap();
    assert_eq!(clean.events(), marked.events());
    assert_eq!(clean.state(), marked.state());
}

/// Two coupled massless contacts at rest on their stops at 0 (the whole
/// structure at rest at 0, unloaded but for `∓a sin t` at both contact
/// dofs): at the start each contact's static position is its bound and its
/// force 0. Pressed by `−a sin t` (its static rate `K_ZZ⁻¹ f_Z' < 0`, both
/// entries: `K_ZZ⁻¹` is positive here), both are held; nothing moves while
/// they are (the load goes into the reactions `r = a sin t`), so both leave
/// at π exactly (the closed form), then land and leave again as the
/// oracle has it. Under `+a sin t` both leave at once: no event at the
/// start, the first ones landings, as the oracle has them.
#[test]
fn massless_contacts_on_their_stops_without_force_at_the_start() {
    for sign in [-1.0, 1.0] {
        let mut case = pair([0.0; 5], [sign, sign, 0.0, 0.0, 0.0], 0.05, 1.0, [(0.0, 0.05), (0.0, 0.05)], [0.0; 5], 12.0);
        case.q0 = vec![0.0; 5];
        let mut run = EventDriven::new(&case.dy, 0.0, &case.q0, &case.v0, 0.0).unwrap();
        let held: Vec<(usize, bool)> = if sign < 0.0 { vec![(0, false), (1, false)] } else { Vec::new() };
        assert_eq!(run.held(), held);
        run.run_until(12.0, 1000).unwrap();
        let ev = run.events();
        assert!(ev.iter().all(|e| e.t > 0.0), "no event at the start: {ev:?}");
        if sign < 0.0 {
            for (e, c) in ev[..2].iter().zip([0, 1]) {
                assert!(e.kind == EventKind::Release && e.contact == c && (e.t - std::f64::consts::PI).abs() <= 1e-12, "{e:?}");
            }
        }
        let d = check(if sign < 0.0 { "pressed from rest" } else { "leaving from rest" }, &case, H, TOL);
        assert!(d.events >= 4, "{d:?}");
    }
}

/// The neighbour case with a piecewise-linear load at massless dof 1 too
/// (it rises, reverses, falls): its slopes reach contact 0's position
/// through `G_01` and the massless rates piece by piece (the oracle steps
/// to the breakpoints).
#[test]
fn a_piecewise_linear_load_at_a_massless_neighbour() {
    let mut case = neighbour_load();
    let series = TimeProfile::series(vec![0.5, 2.0, 3.5, 6.0], vec![0.0, 0.08, -0.06, 0.0]).unwrap();
    let forcing = case.dy.forcing.clone().into_iter().chain([Forcing { shape: vec![0.0, 1.0, 0.0, 0.0, 0.0], time: series }]).collect();
    case.dy = case.dy.with_forcing(forcing);
    let d = check("series at the neighbour", &case, H, TOL);
    assert!(d.events >= 6, "{d:?}");
}

/// With massless contact dofs the damping matrix's rows there must be zero
/// (the nodes have no velocity of their own; `Dynamics::validate` says so
/// too): a stiffness-proportional damping `C = b K` is a typed error, not
/// a run that drops `C_ZR`.
#[test]
fn a_massless_contact_dofs_damping_row_is_a_typed_error() {
    let case = neighbour_load();
    let c = case.dy.stiffness.clone();
    let damped = case.dy.clone().with_damping(Some(c));
    let r = EventDriven::new(&damped, 0.0, &case.q0, &case.v0, 0.0);
    assert!(matches!(r, Err(EventsError::Contacts(ref s)) if s.contains("row of C")), "{:?}", r.err());
}
