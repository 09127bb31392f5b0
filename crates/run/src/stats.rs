//! Confidence intervals for the mean of a stationary, correlated series:
//! batch means with Student-t quantiles.
//!
//! The series `x_1 … x_N` is cut into `B` consecutive batches of `m = ⌊N/B⌋`
//! values (the first `N − B m` values, the oldest, are dropped); the batch
//! means `Y_b` are nearly independent when a batch is much longer than the
//! series' correlation time, so `Ȳ ± t_{(1+c)/2, B−1} s_Y / √B` with
//! `s_Y² = Σ (Y_b − Ȳ)² / (B − 1)` covers the mean with probability about
//! `c`. No IO.

/// A confidence interval for a mean.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// The estimate (the mean of the batch means).
    pub mean: f64,
    /// Lower end.
    pub low: f64,
    /// Upper end.
    pub high: f64,
    /// The standard error `s_Y / √B`.
    pub std_err: f64,
    /// Number of batches `B`.
    pub batches: usize,
}

impl Interval {
    /// Half the width.
    pub fn half_width(&self) -> f64 {
        0.5 * (self.high - self.low)
    }

    /// The half width relative to `|mean|` (∞ for a zero mean).
    pub fn relative_half_width(&self) -> f64 {
        self.half_width() / self.mean.abs()
    }

    /// Every value mapped by `f`, increasing (a change of units).
    pub fn scaled(&self, f: f64) -> Interval {
        let (a, b) = (self.low * f, self.high * f);
        Interval { mean: self.mean * f, low: a.min(b), high: a.max(b), std_err: self.std_err * f.abs(), batches: self.batches }
    }
}

/// The batch-means interval of level `level` (e.g. 0.95) for the mean of
/// `x`, with `batches` batches. `None` with fewer than two batches, fewer
/// values than batches or a level outside (0, 1).
pub fn batch_means(x: &[f64], batches: usize, level: f64) -> Option<Interval> {
    if batches < 2 || x.len() < batches || !(level > 0.0 && level < 1.0) {
        return None;
    }
    let m = x.len() / batches;
    let skip = x.len() - m * batches;
    let means: Vec<f64> = x[skip..].chunks_exact(m).map(|c| c.iter().sum::<f64>() / m as f64).collect();
    let b = means.len() as f64;
    let mean = means.iter().sum::<f64>() / b;
    let var = means.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (b - 1.0);
    let std_err = (var / b).sqrt();
    let half = t_quantile(0.5 * (1.0 + level), batches - 1) * std_err;
    Some(Interval { mean, low: mean - half, high: mean + half, std_err, batches })
}

/// The `p`-quantile of Student's t distribution with `df` degrees of
/// freedom (`0 < p < 1`, `df >= 1`), by bisection on its CDF to full
/// precision.
pub fn t_quantile(p: f64, df: usize) -> f64 {
    assert!(p > 0.0 && p < 1.0 && df >= 1, "t_quantile({p}, {df})");
    if p < 0.5 {
        return -t_quantile(1.0 - p, df);
    }
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    while t_cdf(hi, df) < p {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if t_cdf(mid, df) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// The CDF of Student's t with `df` degrees of freedom.
pub fn t_cdf(t: f64, df: usize) -> f64 {
    let nu = df as f64;
    let x = nu / (nu + t * t);
    let tail = 0.5 * incomplete_beta(0.5 * nu, 0.5, x);
    if t >= 0.0 {
        1.0 - tail
    } else {
        tail
    }
}

/// The regularised incomplete beta function `I_x(a, b)` (continued
/// fraction, modified Lentz).
fn incomplete_beta(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    if x < (a + 1.0) / (a + b + 2.0) {
        ln_front.exp() * beta_cf(a, b, x) / a
    } else {
        1.0 - ln_front.exp() * beta_cf(b, a, 1.0 - x) / b
    }
}

fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..500 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + aa / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + aa / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        let del = d * c;
        h *= del;
        if (del - 1.0).abs() < 1e-16 {
            break;
        }
    }
    h
}

/// `ln Γ(x)`, x > 0 (Lanczos, g = 7, n = 9: about 15 digits).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection.
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut s = G[0];
    for (i, g) in G.iter().enumerate().skip(1) {
        s += g / (x + i as f64);
    }
    let t = x + 7.5;
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + s.ln()
}
