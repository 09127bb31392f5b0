//! Shared by the event tests: the chain of masses they run, and the
//! oracles' dense inverse and the order every event record keeps.

use signorini_fem::SymBand;
use signorini_schemes::events::{EventKind, EventRecord};

/// `(M, K)` of `n` masses in a chain: a P1-like consistent mass, unit
/// springs, tied to a wall at the far end unless `free` (then both ends
/// are half elements).
#[allow(dead_code)]
pub fn chain_matrices(n: usize, free: bool) -> (SymBand, SymBand) {
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        let end = i == 0 || (free && i == n - 1);
        m.set(i, i, if end { 1.0 / 3.0 } else { 2.0 / 3.0 });
        k.set(i, i, if end { 1.0 } else { 2.0 });
        if i > 0 {
            m.set(i, i - 1, 1.0 / 6.0);
            k.set(i, i - 1, -1.0);
        }
    }
    (m, k)
}

/// Rayleigh damping `C = a M + b K` on the chain's band (half-bandwidth
/// 1), entry by entry.
#[allow(dead_code)]
pub fn rayleigh(m: &SymBand, k: &SymBand, a: f64, b: f64) -> SymBand {
    let mut c = SymBand::zeros(m.n(), 1);
    for i in 0..m.n() {
        for j in i.saturating_sub(1)..=i {
            c.set(i, j, a * m.get(i, j) + b * k.get(i, j));
        }
    }
    c
}

/// The inverse of the dense `a` restricted to the dofs `keep` (Gauss–Jordan
/// with partial pivoting), embedded in `n × n` with zeros elsewhere.
#[allow(dead_code)]
pub fn inverse(a: &[f64], n: usize, keep: &[usize]) -> Vec<f64> {
    let p = keep.len();
    let mut w: Vec<Vec<f64>> = (0..p).map(|i| (0..p).map(|j| a[keep[i] * n + keep[j]]).chain((0..p).map(|j| if i == j { 1.0 } else { 0.0 })).collect()).collect();
    for col in 0..p {
        let piv = (col..p).max_by(|&x, &y| w[x][col].abs().total_cmp(&w[y][col].abs())).unwrap();
        w.swap(col, piv);
        let d = w[col][col];
        assert!(d.abs() > 1e-300, "singular");
        w[col].iter_mut().for_each(|x| *x /= d);
        for r in 0..p {
            if r != col {
                let f = w[r][col];
                if f != 0.0 {
                    let row = w[col].clone();
                    w[r].iter_mut().zip(&row).for_each(|(x, y)| *x -= f * y);
                }
            }
        }
    }
    let mut out = vec![0.0; n * n];
    for i in 0..p {
        for j in 0..p {
            out[keep[i] * n + keep[j]] = w[i][p + j];
        }
    }
    out
}

/// The load of the oracles, evaluated here from the data of `Dynamics`
/// (not through the code under test): `f0 + shape a sin(ω t) + ramp s(t)`
/// with `s` the piecewise-linear series through `points` (end values held).
#[allow(dead_code)]
pub struct Load {
    pub f0: Vec<f64>,
    pub shape: Vec<f64>,
    pub amplitude: f64,
    pub omega: f64,
    pub ramp: Vec<f64>,
    pub points: Vec<(f64, f64)>,
}

#[allow(dead_code)]
impl Load {
    /// From `dy`'s steady load, one `Sine` and one `Series` forcing at most.
    pub fn of(dy: &signorini_schemes::Dynamics) -> Self {
        use signorini_schemes::TimeProfile;
        let n = dy.n();
        let mut load = Self { f0: dy.load.clone(), shape: vec![0.0; n], amplitude: 0.0, omega: 0.0, ramp: vec![0.0; n], points: Vec::new() };
        for f in &dy.forcing {
            match &f.time {
                TimeProfile::Sine { amplitude, omega } => (load.amplitude, load.omega, load.shape) = (*amplitude, *omega, f.shape.clone()),
                TimeProfile::Series(s) => (load.ramp, load.points) = (f.shape.clone(), s.times().iter().copied().zip(s.values().iter().copied()).collect()),
                other => panic!("the oracles take a Sine and a Series: {other:?}"),
            }
        }
        load
    }

    /// `s(t)` and its slope (right-continuous).
    pub fn series(&self, t: f64) -> (f64, f64) {
        let p = &self.points;
        match p.iter().position(|x| x.0 > t) {
            None => (p.last().map_or(0.0, |x| x.1), 0.0),
            Some(0) => (p[0].1, 0.0),
            Some(k) => {
                let slope = (p[k].1 - p[k - 1].1) / (p[k].0 - p[k - 1].0);
                (p[k - 1].1 + slope * (t - p[k - 1].0), slope)
            }
        }
    }

    /// `f_i(t)`.
    pub fn value(&self, i: usize, t: f64) -> f64 {
        self.f0[i] + self.shape[i] * self.amplitude * (self.omega * t).sin() + self.ramp[i] * self.series(t).0
    }

    /// `f_i'(t)`.
    pub fn rate(&self, i: usize, t: f64) -> f64 {
        self.shape[i] * self.amplitude * self.omega * (self.omega * t).cos() + self.ramp[i] * self.series(t).1
    }

    /// The time to the next breakpoint after `t` (infinite: none): an
    /// oracle's step ends there (RK4 is of order 4 on each piece, not
    /// across a kink of the load).
    pub fn to_kink(&self, t: f64) -> f64 {
        self.points.iter().map(|p| p.0).find(|&b| b > t).map_or(f64::INFINITY, |b| b - t)
    }
}

/// [`chain_matrices`] of a free chain with the links `cuts` cut (link `i`
/// joins dofs `i − 1` and `i`: its spring and its mass coupling removed):
/// free parts, each with a rigid mode.
#[allow(dead_code)]
pub fn cut_chain_matrices(n: usize, cuts: &[usize]) -> (SymBand, SymBand) {
    let (mut m, mut k) = chain_matrices(n, true);
    for &i in cuts {
        k.set(i, i - 1, 0.0);
        m.set(i, i - 1, 0.0);
        for j in [i - 1, i] {
            k.set(j, j, k.get(j, j) - 1.0);
            m.set(j, j, m.get(j, j) - 1.0 / 3.0);
        }
    }
    (m, k)
}

/// Every event after the one before it in time, no event of a contact at
/// the instant of its own release (the livelock's signature), and no impact
/// row without speed and impulse (a landing at rest is no impact).
#[allow(dead_code)]
pub fn check_order(events: &[EventRecord]) -> Result<(), String> {
    if let Some(e) = events.iter().find(|e| e.kind == EventKind::Impact && e.velocity_before == 0.0 && e.impulse == 0.0) {
        return Err(format!("an impact row without speed or impulse: {e:?}"));
    }
    for w in events.windows(2) {
        if w[1].t < w[0].t {
            return Err(format!("out of time order: {:?} then {:?}", w[0], w[1]));
        }
        if w[0].kind == EventKind::Release && w[1].t == w[0].t && w[1].contact == w[0].contact {
            return Err(format!("an event at the instant of its own release: {:?} then {:?}", w[0], w[1]));
        }
    }
    Ok(())
}
