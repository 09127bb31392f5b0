//! The event-located RK4 oracle of the event tests under a dashpot (a
//! non-classical damping): written here from the data, nothing shared with
//! the code under test but the matrices. Dense `M`, `K`, `C`; the load
//! `f0 + shape A sin(Ω t + p)`; contacts `lo <= q[dof] <= hi`, one
//! restitution `e`. Fixed steps `h`, an event located by bisection on the
//! step length (to round-off in time), the state at it from one step of
//! that length:
//!
//! - **free flight** until a free contact crosses a bound;
//! - **impacts**: every contact within `1e-12` of its length scale of a
//!   bound (the held ones included) takes Newton's law at once, the LCP
//!   `v⁺ = v⁻ + M⁻¹ Σ p_c s_c e_c`, `0 <= p_c ⊥ s_c v_c⁺ + e min(s_c v_c⁻,
//!   0) >= 0` (`s_c = +1` at a lower bound, `−1` at an upper one), solved
//!   by enumerating its active sets (one or two contacts here);
//! - **accumulation**: an impact slower than `10⁻⁶` of its contact's
//!   fastest ends that contact's run of impacts at the geometric limit of
//!   its last three impact times, the contact put at rest (the projection
//!   of the velocity onto `v_c = 0` for all such contacts at once);
//! - **held phases**: contacts at rest on their bounds are held when the
//!   acceleration LCP presses them (enumerated); held, the rows of the held
//!   dofs are removed (`M_ff⁻¹` embedded) and each one's force `r = (M q'' +
//!   C v + K q − f)_c` is watched: where `s_c r` turns negative the contact
//!   is released.
//!
//! Its error is the RK4's, `O(h⁴)` per unit time, plus the micro-impact
//! rule's neglected tail (`10⁻⁶ v_max` over the chatter's duration), plus
//! a round-off that grows with the step count (`1/h`: near 1e-12 at `h =
//! 5e-4` over a few units of time, doubling as `h` halves): a test measures
//! it by running the oracle at `h` and `h/2` and takes its tolerance from
//! that difference (the RK4's error at `h/2` is 1/16 of it), over a whole
//! state rather than per entry (where the two parts can cancel); a finer
//! `h` is no better reference below 1e-11.

use crate::events_common::inverse;
use signorini_schemes::events::EventKind;

/// A contact: `lo <= q[dof] <= hi`.
#[derive(Clone, Copy, Debug)]
pub struct Stop {
    pub dof: usize,
    pub lo: f64,
    pub hi: f64,
}

/// An oracle's event: `(t, kind, contact, v_c before)`.
pub type Row = (f64, EventKind, usize, f64);

/// The problem, dense and row-major.
#[derive(Clone, Debug)]
pub struct Rk4 {
    pub n: usize,
    pub m: Vec<f64>,
    pub k: Vec<f64>,
    pub c: Vec<f64>,
    pub f0: Vec<f64>,
    pub shape: Vec<f64>,
    /// `(A, Ω, p)`.
    pub wave: (f64, f64, f64),
    pub stops: Vec<Stop>,
    pub e: f64,
}

/// A held contact's side: `Some(false)` at its lower bound, `Some(true)` at
/// its upper one.
type Held = Vec<Option<bool>>;

/// The run's output: its events and the state at each requested time.
pub struct Output {
    pub rows: Vec<Row>,
    pub samples: Vec<(Vec<f64>, Vec<f64>)>,
}

impl Rk4 {
    fn side(up: bool) -> f64 {
        if up {
            -1.0
        } else {
            1.0
        }
    }

    fn load(&self, i: usize, t: f64) -> f64 {
        self.f0[i] + self.shape[i] * self.wave.0 * (self.wave.1 * t + self.wave.2).sin()
    }

    /// `f − K q − C v` at `t`.
    fn residual(&self, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        let n = self.n;
        (0..n).map(|i| self.load(i, t) - (0..n).map(|j| self.k[i * n + j] * q[j] + self.c[i * n + j] * v[j]).sum::<f64>()).collect()
    }

    /// `M_ff⁻¹` embedded, the dofs of `held` removed.
    fn minv(&self, held: &Held) -> Vec<f64> {
        let free: Vec<usize> = (0..self.n).filter(|&i| !self.stops.iter().zip(held).any(|(s, h)| h.is_some() && s.dof == i)).collect();
        inverse(&self.m, self.n, &free)
    }

    fn acc(&self, minv: &[f64], t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        let n = self.n;
        let r = self.residual(t, q, v);
        (0..n).map(|i| (0..n).map(|j| minv[i * n + j] * r[j]).sum()).collect()
    }

    /// `s_c r_c` of every contact (the pressing force; 0 if not held).
    fn forces(&self, minv: &[f64], held: &Held, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        let n = self.n;
        let a = self.acc(minv, t, q, v);
        let res = self.residual(t, q, v);
        self.stops.iter().zip(held).map(|(s, h)| h.map_or(0.0, |up| Self::side(up) * ((0..n).map(|j| self.m[s.dof * n + j] * a[j]).sum::<f64>() - res[s.dof]))).collect()
    }

    fn step(&self, minv: &[f64], t: f64, q: &[f64], v: &[f64], h: f64) -> (Vec<f64>, Vec<f64>) {
        let ax = |x: &[f64], a: f64, y: &[f64]| x.iter().zip(y).map(|(x, y)| x + a * y).collect::<Vec<f64>>();
        let a1 = self.acc(minv, t, q, v);
        let (q2, v2) = (ax(q, h / 2.0, v), ax(v, h / 2.0, &a1));
        let a2 = self.acc(minv, t + h / 2.0, &q2, &v2);
        let (q3, v3) = (ax(q, h / 2.0, &v2), ax(v, h / 2.0, &a2));
        let a3 = self.acc(minv, t + h / 2.0, &q3, &v3);
        let (q4, v4) = (ax(q, h, &v3), ax(v, h, &a3));
        let a4 = self.acc(minv, t + h, &q4, &v4);
        let q1 = (0..self.n).map(|i| q[i] + h / 6.0 * (v[i] + 2.0 * v2[i] + 2.0 * v3[i] + v4[i])).collect();
        let v1 = (0..self.n).map(|i| v[i] + h / 6.0 * (a1[i] + 2.0 * a2[i] + 2.0 * a3[i] + a4[i])).collect();
        (q1, v1)
    }

    /// The earliest `s` in `(0, end]` where `bad` holds after a step of `s`
    /// (bisection; `bad` holds at `end`, not near 0).
    fn locate(&self, minv: &[f64], t: f64, q: &[f64], v: &[f64], end: f64, bad: impl Fn(&[f64], &[f64], f64) -> bool) -> f64 {
        let (mut a, mut b) = (0.0, end);
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            if mid <= a || mid >= b {
                break;
            }
            let (qs, vs) = self.step(minv, t, q, v, mid);
            if bad(&qs, &vs, t + mid) {
                b = mid;
            } else {
                a = mid;
            }
        }
        b
    }

    fn crossed(&self, held: &Held, q: &[f64]) -> bool {
        self.stops.iter().zip(held).any(|(s, h)| h.is_none() && (q[s.dof] < s.lo || q[s.dof] > s.hi))
    }

    /// The Delassus entry `s_i s_j (M⁻¹)_{d_i d_j}` over the contacts `set`,
    /// and the LCP's impulses for the targets `w_min` from `w` (`s_c v_c`):
    /// the active set (enumerated) with `p >= 0` and every inactive contact
    /// at or above its target.
    fn lcp(&self, minv: &[f64], set: &[(usize, bool)], w: &[f64], w_min: &[f64]) -> Vec<f64> {
        let n = self.n;
        let k = set.len();
        let wm = |i: usize, j: usize| Self::side(set[i].1) * Self::side(set[j].1) * minv[self.stops[set[i].0].dof * n + self.stops[set[j].0].dof];
        for mask in 0..(1usize << k) {
            let act: Vec<usize> = (0..k).filter(|i| mask >> i & 1 == 1).collect();
            // Solve W_AA p_A = w_min_A − w_A (Cramer: one or two).
            let mut p = vec![0.0; k];
            match act.len() {
                0 => {}
                1 => p[act[0]] = (w_min[act[0]] - w[act[0]]) / wm(act[0], act[0]),
                2 => {
                    let (a, b) = (act[0], act[1]);
                    let (r1, r2) = (w_min[a] - w[a], w_min[b] - w[b]);
                    let det = wm(a, a) * wm(b, b) - wm(a, b) * wm(b, a);
                    p[a] = (r1 * wm(b, b) - wm(a, b) * r2) / det;
                    p[b] = (wm(a, a) * r2 - wm(b, a) * r1) / det;
                }
                _ => unreachable!("at most two contacts"),
            }
            let ok = (0..k).all(|i| {
                let wi = w[i] + (0..k).map(|j| wm(i, j) * p[j]).sum::<f64>();
                p[i] >= 0.0 && (act.contains(&i) || wi >= w_min[i] - 1e-15 * (1.0 + w[i].abs()))
            });
            if ok {
                return p;
            }
        }
        panic!("the oracle's LCP has no solution: {w:?} {w_min:?}");
    }

    /// Applies impulses `p` (pressing, per contact of `set`) to `v`.
    fn kick(&self, minv: &[f64], set: &[(usize, bool)], p: &[f64], v: &mut [f64]) {
        let n = self.n;
        for (&(j, up), &pj) in set.iter().zip(p) {
            let d = self.stops[j].dof;
            (0..n).for_each(|i| v[i] += minv[i * n + d] * Self::side(up) * pj);
        }
    }

    /// The held set for the contacts at rest `rest`: the acceleration LCP by
    /// enumeration (held: pressing force; not held: acceleration off the bound).
    fn hold(&self, rest: &[(usize, bool)], t: f64, q: &[f64], v: &[f64]) -> Held {
        let k = rest.len();
        for mask in (0..(1usize << k)).rev() {
            let mut held: Held = vec![None; self.stops.len()];
            for (i, &(j, up)) in rest.iter().enumerate() {
                if mask >> i & 1 == 1 {
                    held[j] = Some(up);
                }
            }
            let minv = self.minv(&held);
            let f = self.forces(&minv, &held, t, q, v);
            let a = self.acc(&minv, t, q, v);
            let ok = rest.iter().all(|&(j, up)| if held[j].is_some() { f[j] >= 0.0 } else { Self::side(up) * a[self.stops[j].dof] >= 0.0 });
            if ok {
                return held;
            }
        }
        vec![None; self.stops.len()]
    }

    /// Runs from `(q0, v0)` at 0 (its contacts at rest on a bound held if
    /// pressed) to `t_end` with step `h`; the state at each of `at` (ascending).
    pub fn run(&self, q0: &[f64], v0: &[f64], t_end: f64, h: f64, at: &[f64]) -> Output {
        let kc = self.stops.len();
        let scale: Vec<f64> = self.stops.iter().map(|s| [s.lo, s.hi].iter().filter(|x| x.is_finite()).fold(0.0f64, |m, x| m.max(x.abs())).max(q0[s.dof].abs())).collect();
        let (mut t, mut q, mut v) = (0.0, q0.to_vec(), v0.to_vec());
        let on_bound = |q: &[f64], j: usize| -> Option<bool> {
            let s = self.stops[j];
            let tol = 1e-12 * scale[j];
            if q[s.dof] - s.lo <= tol {
                Some(false)
            } else if s.hi - q[s.dof] <= tol {
                Some(true)
            } else {
                None
            }
        };
        let rest: Vec<(usize, bool)> = (0..kc).filter_map(|j| on_bound(&q, j).filter(|_| v[self.stops[j].dof] == 0.0).map(|up| (j, up))).collect();
        let mut held = self.hold(&rest, t, &q, &v);
        let mut minv = self.minv(&held);
        let mut rows: Vec<Row> = Vec::new();
        let mut samples = Vec::new();
        let mut next_sample = 0;
        let (mut streak, mut vmax): (Vec<Vec<f64>>, Vec<f64>) = (vec![Vec::new(); kc], vec![0.0; kc]);
        while t < t_end {
            let mut hh = h.min(t_end - t);
            let sample = at.get(next_sample).copied().filter(|&s| s <= t + hh);
            if let Some(s) = sample {
                hh = s - t;
            }
            let (q1, v1) = self.step(&minv, t, &q, &v, hh);
            let released = held.iter().any(Option::is_some) && self.forces(&minv, &held, t + hh, &q1, &v1).iter().any(|&f| f < 0.0);
            let crossed = self.crossed(&held, &q1);
            if !released && !crossed {
                (t, q, v) = (t + hh, q1, v1);
                if sample.is_some() {
                    t = at[next_sample];
                    samples.push((q.clone(), v.clone()));
                    next_sample += 1;
                }
                continue;
            }
            // The earlier of a release and a crossing.
            let s = self.locate(&minv, t, &q, &v, hh, |qs, vs, ts| (released && self.forces(&minv, &held, ts, qs, vs).iter().any(|&f| f < 0.0)) || (crossed && self.crossed(&held, qs)));
            (q, v) = self.step(&minv, t, &q, &v, s);
            t += s;
            // At the bisection's end the event has happened: a held force
            // below 0 is a release, else a free contact crossed its bound.
            let f = self.forces(&minv, &held, t, &q, &v);
            if released && (0..kc).any(|j| held[j].is_some() && f[j] < 0.0) {
                for j in 0..kc {
                    if held[j].is_some() && f[j] < 0.0 {
                        held[j] = None;
                        rows.push((t, EventKind::Release, j, 0.0));
                    }
                }
                minv = self.minv(&held);
                continue;
            }
            // An impact: every contact on or across a bound (held ones included).
            let set: Vec<(usize, bool)> = (0..kc).filter_map(|j| held[j].or_else(|| on_bound(&q, j)).map(|up| (j, up))).collect();
            for &(j, up) in &set {
                q[self.stops[j].dof] = if up { self.stops[j].hi } else { self.stops[j].lo };
            }
            let full = self.minv(&vec![None; kc]);
            let w: Vec<f64> = set.iter().map(|&(j, up)| Self::side(up) * v[self.stops[j].dof]).collect();
            let w_min: Vec<f64> = w.iter().map(|&x| (-self.e * x).max(0.0)).collect();
            let p = self.lcp(&full, &set, &w, &w_min);
            let vb = v.clone();
            self.kick(&full, &set, &p, &mut v);
            let mut due = Vec::new();
            for (i, &(j, _)) in set.iter().enumerate() {
                if p[i] <= 0.0 {
                    continue;
                }
                rows.push((t, EventKind::Impact, j, vb[self.stops[j].dof]));
                if held[j].is_some() {
                    continue;
                }
                let speed = w[i].abs();
                let micro = speed <= 1e-6 * vmax[j];
                vmax[j] = vmax[j].max(speed);
                streak[j].push(t);
                if micro {
                    let st = &streak[j];
                    let k = st.len();
                    let (d1, d0) = (st[k - 1] - st[k - 2], st[k - 2] - st[k - 3]);
                    let rho = d1 / d0;
                    due.push((t + d1 * rho / (1.0 - rho), j));
                }
            }
            let mut rest: Vec<(usize, bool)> = set.iter().copied().filter(|&(j, up)| held[j].is_some() || Self::side(up) * v[self.stops[j].dof] <= 0.0).collect();
            if !due.is_empty() {
                // At rest: the projection onto v_c = 0 of every due contact
                // (and every contact on its bound not leaving it).
                let zero: Vec<(usize, bool)> = set.iter().copied().filter(|&(j, up)| due.iter().any(|d| d.1 == j) || held[j].is_some() || Self::side(up) * v[self.stops[j].dof] <= 0.0).collect();
                let wz: Vec<f64> = zero.iter().map(|&(j, up)| Self::side(up) * v[self.stops[j].dof]).collect();
                let k = zero.len();
                let n2 = self.n;
                let wm = |a: usize, b: usize| Self::side(zero[a].1) * Self::side(zero[b].1) * full[self.stops[zero[a].0].dof * n2 + self.stops[zero[b].0].dof];
                let p = match k {
                    1 => vec![-wz[0] / wm(0, 0)],
                    2 => {
                        let det = wm(0, 0) * wm(1, 1) - wm(0, 1) * wm(1, 0);
                        vec![(-wz[0] * wm(1, 1) + wm(0, 1) * wz[1]) / det, (-wm(0, 0) * wz[1] + wm(1, 0) * wz[0]) / det]
                    }
                    _ => unreachable!(),
                };
                self.kick(&full, &zero, &p, &mut v);
                due.sort_by(|a, b| a.0.total_cmp(&b.0));
                for &(ti, j) in &due {
                    rows.push((ti, EventKind::Accumulation, j, vb[self.stops[j].dof]));
                    streak[j].clear();
                }
                rest = zero;
            }
            for &(j, _) in &rest {
                v[self.stops[j].dof] = 0.0;
            }
            held = self.hold(&rest, t, &q, &v);
            for j in 0..kc {
                if held[j].is_some() {
                    streak[j].clear();
                }
            }
            minv = self.minv(&held);
        }
        Output { rows, samples }
    }
}
