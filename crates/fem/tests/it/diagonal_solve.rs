//! `BandLdlt::solve_in_place` on a tridiagonal matrix whose off-diagonal
//! is zero (a lumped mass): its diagonal path against the two sweeps of
//! the tridiagonal LDLᵀ solve transcribed here (`y_i = b_i − l_i y_{i−1}`,
//! `x_i = y_i d_i⁻¹ − l_{i+1} x_{i+1}` with `l = ±0` and the factor's own
//! inverse pivots), bit for bit, on sizes 1–100, with zeros of both signs
//! (off-diagonals stored as `+0` and as `−0`), infinities, NaN, products
//! that overflow and products that underflow to `−0`: the values where
//! `b − 0·y` is not `b` and the sweeps carry a zero's sign or a NaN.

use signorini_fem::SymBand;
use signorini_schemes_free_rng::Rng;

mod signorini_schemes_free_rng {
    /// SplitMix64 (its own here: the fem crate has no dependency on the schemes').
    pub struct Rng(pub u64);
    impl Rng {
        pub fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        }
        pub fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
    }
}

/// The sweeps, with `l` the stored sub-diagonal (every entry `±0`).
fn sweeps(l: &[f64], inv_d: &[f64], b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut y = b.to_vec();
    for i in 1..n {
        y[i] = b[i] - l[i] * y[i - 1];
    }
    let mut x = y.clone();
    x[n - 1] = y[n - 1] * inv_d[n - 1];
    for i in (0..n - 1).rev() {
        x[i] = y[i] * inv_d[i] - l[i + 1] * x[i + 1];
    }
    x
}

fn value(rng: &mut Rng, odd: bool) -> f64 {
    if odd {
        match rng.next() % 9 {
            0 => -0.0,
            1 => 0.0,
            2 => f64::INFINITY,
            3 => f64::NEG_INFINITY,
            4 => f64::NAN,
            5 => 1e308,
            6 => -1e-320,
            7 => -4e-324,
            _ => -(rng.unit() + 0.1),
        }
    } else {
        match rng.next() % 5 {
            0 => 0.0,
            1 => -(rng.unit() + 0.1),
            _ => rng.unit() - 0.5,
        }
    }
}

#[test]
fn a_lumped_mass_solve_is_the_sweeps_bit_for_bit() {
    let mut rng = Rng(35);
    let mut odd_cases = 0;
    for n in (1..=12).chain([31, 32, 33, 100]) {
        for negative_zero in [false, true] {
            let mut m = SymBand::zeros(n, 1);
            for i in 0..n {
                // Pivots of every size, 1/D overflowing the products below.
                m.set(i, i, [0.5 + rng.unit(), 1e-3, 3.0e5][(rng.next() % 3) as usize]);
                if i > 0 && negative_zero {
                    m.set(i, i - 1, -0.0);
                }
            }
            let f = m.factor().unwrap();
            let (l, _, inv_d) = f.band_factors();
            let l: Vec<f64> = l.to_vec();
            assert!(l.iter().all(|x| *x == 0.0));
            for trial in 0..200 {
                // A third of the trials with one or more odd values.
                let odd = trial % 3 == 0;
                let mut b: Vec<f64> = (0..n).map(|_| value(&mut rng, false)).collect();
                if odd {
                    for _ in 0..1 + rng.next() % 3 {
                        let i = (rng.next() % n as u64) as usize;
                        b[i] = value(&mut rng, true);
                    }
                    odd_cases += 1;
                }
                let want = sweeps(&l, inv_d, &b);
                let mut got = b.clone();
                f.solve_in_place(&mut got);
                for i in 0..n {
                    assert_eq!(got[i].to_bits(), want[i].to_bits(), "n {n}, row {i}: {} vs the sweeps' {} (b {:?})", got[i], want[i], b);
                }
            }
        }
    }
    assert!(odd_cases > 1000);
}
