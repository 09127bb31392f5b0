//! What the characteristics oracles of the exact-solution tests share.

/// Time (and space) step of the oracles' lattices: `1/64`, dyadic, so every
/// event of the Dirichlet-type benchmarks (impacts and take-offs at integer
/// times) and every value (multiples of 1/2) is represented exactly.
pub const CELLS_PER_UNIT: usize = 64;
pub const DELTA: f64 = 1.0 / CELLS_PER_UNIT as f64;

/// `∫_0^x u_x(ξ, t) dξ`, exactly, for a strain `ux` that is constant
/// between the points where `ξ ± t` crosses the lattice `j·DELTA`.
pub fn lattice_integral(x: f64, t: f64, ux: impl Fn(f64) -> f64) -> f64 {
    let mut pts = vec![0.0, x];
    let lo = ((-t) / DELTA).floor() as i64;
    let hi = ((x + t) / DELTA).ceil() as i64;
    for j in lo..=hi {
        let line = j as f64 * DELTA;
        for p in [line - t, line + t] {
            if p > 0.0 && p < x {
                pts.push(p);
            }
        }
    }
    pts.sort_by(f64::total_cmp);
    pts.windows(2).map(|w| (w[1] - w[0]) * ux(0.5 * (w[0] + w[1]))).sum()
}
