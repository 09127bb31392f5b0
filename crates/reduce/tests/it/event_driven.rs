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

/// The reduced system `(M_r, K_r)` dense, its massless contact dofs
/// `0..nz` with their bounds, the load `f0 + shape A sin(Ωt)`.
struct Oracle {
    n: usize,
    nz: usize,
    k: Vec<f64>,
    minv: Vec<f64>,
    f0: Vec<f64>,
    shape: Vec<f64>,
    wave: (f64, f64),
    bounds: Vec<(f64, f64)>,
}

fn dense(b: &SymBand) -> Vec<f64> {
    let n = b.n();
    (0..n * n).map(|x| b.get(x / n, x % n)).collect()
}

/// The inverse of the block of `a` on dofs `nz..n` (Gauss–Jordan, partial
/// pivoting), embedded in `n × n` with zero rows and columns `0..nz`.
fn inverse_massive(a: &[f64], n: usize, nz: usize) -> Vec<f64> {
    let p = n - nz;
    let mut w: Vec<Vec<f64>> = (0..p).map(|i| (0..p).map(|j| a[(i + nz) * n + j + nz]).chain((0..p).map(|j| f64::from(u8::from(i == j)))).collect()).collect();
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
            out[(i + nz) * n + j + nz] = w[i][p + j];
        }
    }
    out
}

/// The largest reduced model the oracle's stack buffers hold.
const MAXN: usize = 40;

impl Oracle {
    fn load(&self, i: usize, t: f64) -> f64 {
        self.f0[i] + self.shape[i] * self.wave.0 * (self.wave.1 * t).sin()
    }

    /// The massless contacts' static positions, the exact solution of
    /// their static LCP `K_ZZ q_Z = f_Z − K_ZR q_R + r`, `lo <= q_Z <= hi`,
    /// `r >= 0` at `lo`, `<= 0` at `hi`, `0` between (every combination of
    /// free, lower, upper tried; `K_ZZ` SPD: one fits), into `q[..nz]`;
    /// which are held.
    fn contacts(&self, q: &mut [f64], t: f64) -> [bool; 2] {
        let (n, nz) = (self.n, self.nz);
        assert!(nz <= 2, "at most two contacts here");
        let mut b = [0.0; 2];
        for (i, bi) in b.iter_mut().enumerate().take(nz) {
            *bi = self.load(i, t) - (nz..n).map(|j| self.k[i * n + j] * q[j]).sum::<f64>();
        }
        for code in 0..3usize.pow(nz as u32) {
            let mut side = [0usize; 2];
            let mut x = [0.0; 2];
            for i in 0..nz {
                side[i] = code / 3usize.pow(i as u32) % 3;
                x[i] = [0.0, self.bounds[i].0, self.bounds[i].1][side[i]];
            }
            let (mut free, mut nf) = ([0usize; 2], 0);
            for i in 0..nz {
                if side[i] == 0 {
                    free[nf] = i;
                    nf += 1;
                }
            }
            // The free ones: K_FF x_F = b_F − K_FC x_C (at most 2 × 2 here).
            let mut rhs = [0.0; 2];
            for (f, &i) in free[..nf].iter().enumerate() {
                rhs[f] = b[i] - (0..nz).filter(|j| side[*j] != 0).map(|j| self.k[i * n + j] * x[j]).sum::<f64>();
            }
            match nf {
                0 => {}
                1 => x[free[0]] = rhs[0] / self.k[free[0] * n + free[0]],
                _ => {
                    let (a, c, d) = (self.k[free[0] * n + free[0]], self.k[free[0] * n + free[1]], self.k[free[1] * n + free[1]]);
                    let det = a * d - c * c;
                    x[free[0]] = (d * rhs[0] - c * rhs[1]) / det;
                    x[free[1]] = (a * rhs[1] - c * rhs[0]) / det;
                }
            }
            let fits = (0..nz).all(|i| {
                let r: f64 = (0..nz).map(|j| self.k[i * n + j] * x[j]).sum::<f64>() - b[i];
                match side[i] {
                    0 => x[i] >= self.bounds[i].0 && x[i] <= self.bounds[i].1,
                    1 => r >= 0.0,
                    _ => r <= 0.0,
                }
            });
            if fits {
                q[..nz].copy_from_slice(&x[..nz]);
                return [side[0] != 0, side[1] != 0];
            }
        }
        panic!("no solution of the static LCP at t = {t}");
    }

    /// `(q_R', v_R')` at `(q, v)`, `q[0]` set to the tip's position.
    fn rate(&self, t: f64, q: &mut [f64], v: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        let (n, nz) = (self.n, self.nz);
        self.contacts(q, t);
        let mut r = [0.0; MAXN];
        for (i, ri) in r.iter_mut().enumerate().take(n) {
            *ri = self.load(i, t) - (0..n).map(|j| self.k[i * n + j] * q[j]).sum::<f64>();
        }
        for i in nz..n {
            dq[i] = v[i];
            dv[i] = (nz..n).map(|j| self.minv[i * n + j] * r[j]).sum();
        }
    }

    fn step(&self, t: f64, h: f64, q: &mut [f64], v: &mut [f64]) {
        let (n, nz) = (self.n, self.nz);
        assert!(n <= MAXN);
        let mut k = [[[0.0; MAXN]; 2]; 4];
        let (mut qs, mut vs) = ([0.0; MAXN], [0.0; MAXN]);
        qs[..n].copy_from_slice(q);
        vs[..n].copy_from_slice(v);
        for s in 0..4 {
            let c = [0.0, 0.5, 0.5, 1.0][s];
            if s > 0 {
                for i in nz..n {
                    qs[i] = q[i] + c * h * k[s - 1][0][i];
                    vs[i] = v[i] + c * h * k[s - 1][1][i];
                }
            }
            let [dq, dv] = &mut k[s];
            self.rate(t + c * h, &mut qs[..n], &vs[..n], &mut dq[..n], &mut dv[..n]);
        }
        for i in nz..n {
            q[i] += h / 6.0 * (k[0][0][i] + 2.0 * k[1][0][i] + 2.0 * k[2][0][i] + k[3][0][i]);
            v[i] += h / 6.0 * (k[0][1][i] + 2.0 * k[1][1][i] + 2.0 * k[2][1][i] + k[3][1][i]);
        }
        self.contacts(q, t + h);
    }
}

/// Figure 2's pipe (L = 1.501, J = 20) clamped at 0, its tip between
/// stops at ±`gap` and, with `plate`, its mid-span node between stops at
/// ±`gap`/2 (two massless contacts coupled through `K_ZZ`), reduced to `r`
/// modes; a uniform load `f0` plus a harmonic one `A sin(Ω t)` on the
/// shape `x/L`; starting at zero with the velocity `v0 x/L` (projected).
fn reduced(r: usize, plate: bool, gap: f64, f0: f64, wave: (f64, f64), v0: f64) -> (Dynamics, Oracle, Vec<f64>) {
    let beam = Beam::new(1.501, 20, 282.84).unwrap();
    let (k, m) = (beam.stiffness(), beam.mass());
    // The mid-span node 10's displacement is unknown 2 (10 − 1).
    let (parents, bounds) = if plate { (vec![beam.tip_dof(), 18], vec![(-gap, gap), (-gap / 2.0, gap / 2.0)]) } else { (vec![beam.tip_dof()], vec![(-gap, gap)]) };
    let red = Reduction::new(&k, &m, &parents, Keep::Modes(r)).unwrap();
    let (n, nz) = (red.dofs(), parents.len());
    for (i, &d) in parents.iter().enumerate() {
        assert_eq!(red.reduced_contact(d), Some(i));
    }
    let steady = red.project_vector(&beam.load(|_| f0));
    let shape = red.project_vector(&beam.load(|x| x / 1.501));
    let v_parent = beam.interpolate(|x| v0 * x / 1.501, |_| v0 / 1.501);
    let v = red.project_state(&v_parent);
    let forcing = vec![Forcing { shape: shape.clone(), time: TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: wave.0, omega: wave.1, phase: 0.0 }])) }];
    let contacts = bounds.iter().enumerate().map(|(i, b)| Contact::new(i, Bounds { lo: b.0, hi: b.1 }, true)).collect();
    let dy = Dynamics::new(red.mass().clone(), red.stiffness().clone(), steady.clone(), contacts).with_forcing(forcing);
    let mm = dense(red.mass());
    let oracle = Oracle { n, nz, k: dense(red.stiffness()), minv: inverse_massive(&mm, n, nz), f0: steady, shape, wave, bounds };
    (dy, oracle, v)
}

/// The reduced pipe rattling between its tip's stops (r = 4, 16 modes:
/// 10, 26 landings) and, its mid-span held by a plate too, between both
/// (r = 12: 20 and 11 landings) over [0, 0.2] s under a steady and a
/// harmonic load (every landing followed by a held phase and a release):
/// the event-driven state every 2 ms against the oracle's (RK4, h = 2e-7
/// s), every reduced coordinate to 2e-5 of the state's scale, and its
/// landings: per contact as many `impact` rows as oracle landings (the
/// contact turning held), each within 2h. The oracle converges to the
/// run: largest relative difference 1.1e-8, 1.5e-7, 9.9e-6 (r = 4, 16,
/// 12 with the plate) at h = 2e-7, the last 7.3e-7 at 1e-7.
#[test]
fn a_reduced_beam_under_event_driven_matches_an_integration_of_its_matrices() {
    let cases = [(4, false, 0.01, 0.0, (30.0, 60.0), 0.5), (16, false, 0.01, 2.0, (40.0, 40.0), -0.5), (12, true, 0.02, -5.0, (20.0, 100.0), 1.0)];
    for (r, plate, gap, f0, wave, v0) in cases {
        let (dy, o, v) = reduced(r, plate, gap, f0, wave, v0);
        let (n, nz) = (o.n, o.nz);
        let mut run = EventDriven::new(&dy, 0.0, &vec![0.0; n], &v, 0.0).unwrap();
        let (mut q, mut vo) = (vec![0.0; n], v.clone());
        let mut held = o.contacts(&mut q, 0.0);
        let (h, per) = (2e-7, 10_000);
        let mut landings = vec![Vec::new(); nz];
        let mut worst = 0.0f64;
        let scale = |x: &[f64]| x.iter().fold(0.0f64, |a, y| a.max(y.abs()));
        for sample in 1..=100 {
            let t1 = sample as f64 * 2e-3;
            for s in 0..per {
                let t = t1 - 2e-3 + s as f64 * h;
                o.step(t, h, &mut q, &mut vo);
                let now = o.contacts(&mut q, t + h);
                for c in 0..nz {
                    if now[c] && !held[c] {
                        landings[c].push(t + h);
                    }
                }
                held = now;
            }
            run.run_until(t1, 100_000).unwrap();
            let (_, qe, _) = run.state();
            let s = scale(&q).max(1e-3);
            let err = q.iter().zip(&qe).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            worst = worst.max(err / s);
            assert!(err <= 2e-5 * s, "r = {r}, plate {plate}, t = {t1}: event-driven {qe:?}, oracle {q:?}");
        }
        for (c, land) in landings.iter().enumerate() {
            let impacts: Vec<f64> = run.events().iter().filter(|e| e.kind == EventKind::Impact && e.contact == c).map(|e| e.t).collect();
            assert!(land.len() >= 4, "r = {r}, plate {plate}, contact {c}: {} landings", land.len());
            assert_eq!(impacts.len(), land.len(), "r = {r}, plate {plate}, contact {c}: impacts {impacts:?}, oracle landings {land:?}");
            for (a, b) in impacts.iter().zip(land) {
                assert!((a - b).abs() <= 2.0 * h, "r = {r}, plate {plate}, contact {c}: impact at {a}, oracle landing at {b}");
            }
        }
        println!("r = {r}, plate {plate}: landings {:?}, worst relative state difference {worst:.2e}", landings.iter().map(Vec::len).collect::<Vec<_>>());
    }
}
