//! The event-driven reference (`signorini_schemes::events`) on reduced
//! models (massless contact dofs, docs/theory.md §2.5, §9.3 "Massless
//! contact dofs") against an integration of the same reduced matrices
//! written here: classical RK4 with a fixed step on the massive dofs, the
//! massless tip at every stage at `clamp((f_0 − K_0R q_R)/K_00, lo, hi)`,
//! the exact solution of its one-dof static LCP (landing, held, released).
//! Neither the event crate's condensation, its modes nor its LCPs are used.

use signorini_fem::{Beam, SymBand};
use signorini_reduce::{Keep, Reduction};
use signorini_schemes::events::{EventDriven, EventKind};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};
use std::sync::Arc;

/// The reduced system `(M_r, K_r)` dense, the load `f0 + shape A sin(Ωt)`.
struct Oracle {
    n: usize,
    k: Vec<f64>,
    minv: Vec<f64>,
    f0: Vec<f64>,
    shape: Vec<f64>,
    wave: (f64, f64),
    bounds: (f64, f64),
}

fn dense(b: &SymBand) -> Vec<f64> {
    let n = b.n();
    (0..n * n).map(|x| b.get(x / n, x % n)).collect()
}

/// The inverse of the block of `a` on dofs `1..n` (Gauss–Jordan, partial
/// pivoting), embedded in `n × n` with a zero row and column 0.
fn inverse_massive(a: &[f64], n: usize) -> Vec<f64> {
    let p = n - 1;
    let mut w: Vec<Vec<f64>> = (0..p).map(|i| (0..p).map(|j| a[(i + 1) * n + j + 1]).chain((0..p).map(|j| f64::from(u8::from(i == j)))).collect()).collect();
    for c in 0..p {
        let piv = (c..p).max_by(|&x, &y| w[x][c].abs().total_cmp(&w[y][c].abs())).unwrap();
        w.swap(c, piv);
        let d = w[c][c];
        w[c].iter_mut().for_each(|x| *x /= d);
        for r in 0..p {
            if r != c {
                let f = w[r][c];
                let row = w[c].clone();
                w[r].iter_mut().zip(&row).for_each(|(x, y)| *x -= f * y);
            }
        }
    }
    let mut out = vec![0.0; n * n];
    for i in 0..p {
        for j in 0..p {
            out[(i + 1) * n + j + 1] = w[i][p + j];
        }
    }
    out
}

impl Oracle {
    fn load(&self, i: usize, t: f64) -> f64 {
        self.f0[i] + self.shape[i] * self.wave.0 * (self.wave.1 * t).sin()
    }

    /// The massless tip's static position, clamped: `(q_0, held)`.
    fn tip(&self, q: &[f64], t: f64) -> (f64, bool) {
        let free = (self.load(0, t) - (1..self.n).map(|j| self.k[j] * q[j]).sum::<f64>()) / self.k[0];
        let c = free.clamp(self.bounds.0, self.bounds.1);
        (c, c != free)
    }

    /// `(q_R', v_R')` at `(q, v)`, `q[0]` set to the tip's position.
    fn rate(&self, t: f64, q: &mut [f64], v: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        let n = self.n;
        q[0] = self.tip(q, t).0;
        let r: Vec<f64> = (0..n).map(|i| self.load(i, t) - (0..n).map(|j| self.k[i * n + j] * q[j]).sum::<f64>()).collect();
        for i in 1..n {
            dq[i] = v[i];
            dv[i] = (1..n).map(|j| self.minv[i * n + j] * r[j]).sum();
        }
    }

    fn step(&self, t: f64, h: f64, q: &mut [f64], v: &mut [f64]) {
        let n = self.n;
        let mut k = [[vec![0.0; n], vec![0.0; n]], [vec![0.0; n], vec![0.0; n]], [vec![0.0; n], vec![0.0; n]], [vec![0.0; n], vec![0.0; n]]];
        let (mut qs, mut vs) = (q.to_vec(), v.to_vec());
        for s in 0..4 {
            let c = [0.0, 0.5, 0.5, 1.0][s];
            if s > 0 {
                for i in 1..n {
                    qs[i] = q[i] + c * h * k[s - 1][0][i];
                    vs[i] = v[i] + c * h * k[s - 1][1][i];
                }
            }
            let [dq, dv] = &mut k[s];
            self.rate(t + c * h, &mut qs, &vs, dq, dv);
        }
        for i in 1..n {
            q[i] += h / 6.0 * (k[0][0][i] + 2.0 * k[1][0][i] + 2.0 * k[2][0][i] + k[3][0][i]);
            v[i] += h / 6.0 * (k[0][1][i] + 2.0 * k[1][1][i] + 2.0 * k[2][1][i] + k[3][1][i]);
        }
        q[0] = self.tip(q, t + h).0;
    }
}

/// Figure 2's pipe (L = 1.501, J = 19) clamped at 0, its tip between
/// stops at ±`gap`, reduced to `r` modes; a uniform load `f0` plus a
/// harmonic one `A sin(Ω t)` on the first shape; starting from rest at
/// zero except the velocity `v0 x/L` (projected).
fn reduced(r: usize, gap: f64, f0: f64, wave: (f64, f64), v0: f64) -> (Dynamics, Oracle, Vec<f64>) {
    let beam = Beam::new(1.501, 19, 282.84).unwrap();
    let (k, m) = (beam.stiffness(), beam.mass());
    let red = Reduction::new(&k, &m, &[beam.tip_dof()], Keep::Modes(r)).unwrap();
    let n = red.dofs();
    let steady = red.project_vector(&beam.load(|_| f0));
    let shape = red.project_vector(&beam.load(|x| x / 1.501));
    let v_parent = beam.interpolate(|x| v0 * x / 1.501, |_| v0 / 1.501);
    let v = red.project_state(&v_parent);
    let forcing = vec![Forcing { shape: shape.clone(), time: TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: wave.0, omega: wave.1, phase: 0.0 }])) }];
    let dy = Dynamics::new(red.mass().clone(), red.stiffness().clone(), steady.clone(), vec![Contact::new(0, Bounds { lo: -gap, hi: gap }, true)]).with_forcing(forcing);
    let mm = dense(red.mass());
    let oracle = Oracle { n, k: dense(red.stiffness()), minv: inverse_massive(&mm, n), f0: steady, shape, wave, bounds: (-gap, gap) };
    (dy, oracle, v)
}

/// The reduced pipe (r = 4, 8, 16 modes) rattling between its tip's stops
/// over [0, 0.2] s under a steady and a harmonic load (10, 18 and 27
/// landings, each followed by a held phase and a release): the
/// event-driven state every 2 ms against the oracle's (RK4, h = 2e-7 s),
/// the tip and every modal coordinate to 5e-6 of the state's scale, and
/// its landings: as many `impact` rows as oracle landings (the clamp
/// turning on), each within 2h. The oracle converges to the run: its
/// largest relative difference is 1.6e-8, 1.5e-7, 3.0e-6 (r = 4, 8, 16)
/// at h = 2e-7, 2.6e-9, 3.3e-8, 6.4e-7 at 1e-7 and 5.2e-10, 4.0e-9,
/// 1.6e-8 at 5e-8.
#[test]
fn a_reduced_beam_under_event_driven_matches_an_integration_of_its_matrices() {
    for (r, gap, f0, wave, v0) in [(4, 0.01, 0.0, (30.0, 60.0), 0.5), (8, 0.02, -5.0, (20.0, 100.0), 1.0), (16, 0.01, 2.0, (40.0, 40.0), -0.5)] {
        let (dy, o, v) = reduced(r, gap, f0, wave, v0);
        let n = o.n;
        let mut run = EventDriven::new(&dy, 0.0, &vec![0.0; n], &v, 0.0).unwrap();
        let (mut q, mut vo) = (vec![0.0; n], v.clone());
        q[0] = o.tip(&q, 0.0).0;
        let (h, per) = (2e-7, 10_000);
        let mut landings = Vec::new();
        let mut held = o.tip(&q, 0.0).1;
        let mut worst = 0.0f64;
        let scale = |x: &[f64]| x.iter().fold(0.0f64, |a, y| a.max(y.abs()));
        for sample in 1..=100 {
            let t1 = sample as f64 * 2e-3;
            for s in 0..per {
                let t = t1 - 2e-3 + s as f64 * h;
                o.step(t, h, &mut q, &mut vo);
                let now = o.tip(&q, t + h).1;
                if now && !held {
                    landings.push(t + h);
                }
                held = now;
            }
            run.run_until(t1, 100_000).unwrap();
            let (_, qe, _) = run.state();
            let s = scale(&q).max(1e-3);
            let err = q.iter().zip(&qe).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            worst = worst.max(err / s);
            assert!(err <= 5e-6 * s, "r = {r}, t = {t1}: event-driven {qe:?}, oracle {q:?}");
        }
        let impacts: Vec<f64> = run.events().iter().filter(|e| e.kind == EventKind::Impact).map(|e| e.t).collect();
        assert!(landings.len() >= 4, "r = {r}: {} landings", landings.len());
        assert_eq!(impacts.len(), landings.len(), "r = {r}: impacts {impacts:?}, oracle landings {landings:?}");
        for (a, b) in impacts.iter().zip(&landings) {
            assert!((a - b).abs() <= 2.0 * h, "r = {r}: impact at {a}, oracle landing at {b}");
        }
        println!("r = {r}: {} landings, worst relative state difference {worst:.2e}", landings.len());
    }
}
