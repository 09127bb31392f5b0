//! Cost of one multi-contact solve (`MultiProjection::project`) on a
//! tridiagonal SPD step matrix of 1000 unknowns (a P1 bar's `M + β dt² K`
//! shape), against the number of constrained dofs `k` (spread evenly) and
//! of active ones: (a) none active (every obstacle a bound check plus the
//! status bookkeeping), (b) one active, (c) all active. Each iteration
//! copies `y` (1000 values) and solves; `copy_only` is that copy alone.
//!
//! `cargo bench -p signorini-contact --bench multi`.

use divan::Bencher;
use signorini_contact::MultiProjection;

fn main() {
    divan::main();
}

const N: usize = 1000;
const KS: [usize; 4] = [1, 2, 8, 64];

/// `A⁻¹ e_c` for `A = tridiag(-1, 2.01, -1)` (Thomas algorithm).
fn column(c: usize) -> Vec<f64> {
    let (a, d) = (-1.0, 2.01);
    let mut cp = vec![0.0; N];
    let mut x: Vec<f64> = (0..N).map(|i| f64::from(u8::from(i == c))).collect();
    cp[0] = a / d;
    x[0] /= d;
    for i in 1..N {
        let m = d - a * cp[i - 1];
        cp[i] = a / m;
        x[i] = (x[i] - a * x[i - 1]) / m;
    }
    for i in (0..N - 1).rev() {
        x[i] -= cp[i] * x[i + 1];
    }
    x
}

/// The solver for `k` dofs, bounds `[-1, 1]`, and a `y` with `active` of
/// them outside (by 0.5).
fn setup(k: usize, active: usize) -> (MultiProjection, Vec<f64>, Vec<f64>, Vec<f64>) {
    let dofs: Vec<usize> = (0..k).map(|i| (2 * i + 1) * N / (2 * k)).collect();
    let cols = dofs.iter().map(|&c| column(c)).collect();
    let mp = MultiProjection::new(dofs.clone(), cols).unwrap();
    let mut y = vec![0.3; N];
    for &c in dofs.iter().take(active) {
        y[c] = 1.5;
    }
    (mp, y, vec![-1.0; k], vec![1.0; k])
}

fn bench(bencher: Bencher, k: usize, active: usize) {
    let (mut mp, y, lo, hi) = setup(k, active);
    let mut x = y.clone();
    bencher.bench_local(|| {
        x.copy_from_slice(&y);
        divan::black_box(mp.project(&mut x, &lo, &hi).unwrap());
    });
}

#[divan::bench(args = KS)]
fn a_none_active(bencher: Bencher, k: usize) {
    bench(bencher, k, 0);
}

#[divan::bench(args = KS)]
fn b_one_active(bencher: Bencher, k: usize) {
    bench(bencher, k, 1);
}

#[divan::bench(args = KS)]
fn c_all_active(bencher: Bencher, k: usize) {
    bench(bencher, k, k);
}

#[divan::bench]
fn copy_only(bencher: Bencher) {
    let y = vec![0.3; N];
    let mut x = y.clone();
    bencher.bench_local(|| {
        x.copy_from_slice(&y);
        divan::black_box(&mut x);
    });
}
