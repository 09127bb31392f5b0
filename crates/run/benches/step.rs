//! Cost per (dof × step) of `newmark-cn` with `mod` mass on `bar-dirichlet`:
//! (a) stepping only, (b) stepping with every error norm of docs/theory.md §6 (L², H¹
//! split at kinks, λ, energy), next to (floor) a bare hand-written
//! tridiagonal solve of the same size with precomputed factors.
//!
//! `cargo bench -p signorini-run --bench step`; divan prints the time per
//! iteration (one iteration = `STEPS` steps) and the throughput in
//! dof-steps/s. docs/performance.md records the ratios (a)/floor and
//! (b)/floor, the `parts_*` (what (b) adds, piece by piece), the beam's
//! β-step against its band solve (and against that solve when each solve
//! waits for the one before, `beam_band_solve_chained`, as the β-step's
//! must) and issue 35's implicit schemes
//! (`implicit_scheme_step`, `massless_node_scheme_step`) against the floor
//! at m = 1000, its explicit ones (`c_explicit_contact_step`, the explicit
//! `cd-massless`) against one tridiagonal product (`floor_tridiagonal_product`)
//! and the minimal explicit step (`floor_explicit_step`: the central
//! difference without contact, one pass over its two levels).
//!
//! On a machine shared with other processes, shorter samples fit between
//! their time slices: `DOF_STEPS=200000 cargo bench ...` (default 2·10⁶
//! dof-steps per sample), and compare the fastest samples.

use divan::counter::ItemsCount;
use divan::Bencher;
use signorini_fem::BarMass;
use signorini_run::{run, Benchmark, NormObserver, RunConfig};
use signorini_schemes::{SchemeSpec, Stepper};

fn main() {
    divan::main();
}

const SIZES: [usize; 3] = [100, 1000, 10000];

/// Steps per iteration: about 2·10⁶ dof-steps per sample (`DOF_STEPS`).
fn steps(m: usize) -> usize {
    (std::env::var("DOF_STEPS").ok().and_then(|s| s.parse::<usize>().ok()).unwrap_or(2_000_000) / m).max(10)
}

fn setup(m: usize) -> (Box<dyn Stepper>, Vec<f64>, f64, Box<dyn signorini_exact::ExactSolution>) {
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(3.0).unwrap();
    let p = b.problem(exact.as_ref(), m, BarMass::Mod).unwrap();
    let dt = p.bar.h() / 10.0;
    let s = SchemeSpec::newmark(0.25, 0.5).build(p.dynamics(), dt, &p.initial).unwrap();
    (s, p.initial.u, dt, exact)
}

#[divan::bench(args = SIZES)]
fn a_stepping(bencher: Bencher, m: usize) {
    let n = steps(m);
    bencher.counter(ItemsCount::new(m * n)).with_inputs(|| setup(m)).bench_local_values(|(mut s, _, _, _)| {
        for _ in 0..n {
            divan::black_box(s.step().unwrap());
        }
        s
    });
}

#[divan::bench(args = SIZES)]
fn b_stepping_with_all_norms(bencher: Bencher, m: usize) {
    let n = steps(m);
    bencher.counter(ItemsCount::new(m * n)).with_inputs(|| setup(m)).bench_local_values(|(mut s, u0, dt, exact)| {
        let mut norms = NormObserver::new(exact.as_ref(), m, signorini_norms::VNorm::H1Seminorm, dt);
        let cfg = RunConfig::new(dt, dt * n as f64).unwrap();
        run(s.as_mut(), &u0, &cfg, &mut [&mut norms]).unwrap();
        divan::black_box(norms.report());
    });
}

/// Where (b)'s extra time goes, part by part, per dof and step: the scheme's
/// discrete energy asked for on its own (`Stepper::energy` outside a step;
/// in (b) the runner sets `Stepper::fuse_energy` and the step computes it
/// inside its own loops, for less), the exact space errors (`SpaceIntegrator::errors`:
/// the exact solution at the nodes, the element sums, the kinked
/// elements), and the exact solution at the nodes alone.
#[divan::bench(args = SIZES)]
fn parts_energy(bencher: Bencher, m: usize) {
    let n = steps(m);
    bencher
        .counter(ItemsCount::new(m * n))
        .with_inputs(|| {
            let (mut s, _, _, _) = setup(m);
            s.step().unwrap();
            s
        })
        .bench_local_values(|mut s| {
            for _ in 0..n {
                divan::black_box(s.energy());
            }
            s
        });
}

/// (b) without the norms: the same run with one observer that wants the
/// energy at every level and does nothing else (so the step fuses the
/// energy as in (b)): (b) minus this is what the norms cost inside a run,
/// this minus (a) what the fused energy and the runner add to the step.
#[divan::bench(args = SIZES)]
fn parts_run_energy_only(bencher: Bencher, m: usize) {
    struct EnergyOnly(f64);
    impl signorini_run::Observer for EnergyOnly {
        fn wants_energy(&self) -> bool {
            true
        }
        fn observe(&mut self, s: &signorini_run::Sample<'_>) -> Result<(), signorini_run::RunError> {
            if let Some((_, e)) = s.energy {
                self.0 += e;
            }
            Ok(())
        }
    }
    let n = steps(m);
    bencher.counter(ItemsCount::new(m * n)).with_inputs(|| setup(m)).bench_local_values(|(mut s, u0, dt, _)| {
        let mut energy = EnergyOnly(0.0);
        let cfg = RunConfig::new(dt, dt * n as f64).unwrap();
        run(s.as_mut(), &u0, &cfg, &mut [&mut energy]).unwrap();
        divan::black_box(energy.0);
    });
}

#[divan::bench(args = SIZES)]
fn parts_space_errors(bencher: Bencher, m: usize) {
    let n = steps(m);
    bencher.counter(ItemsCount::new(m * n)).with_inputs(|| setup(m)).bench_local_values(|(s, u0, dt, exact)| {
        let mut space = signorini_norms::SpaceIntegrator::new(exact.as_ref(), m, signorini_norms::VNorm::H1Seminorm);
        let u = &u0[..];
        for k in 0..n {
            divan::black_box(space.errors(k as f64 * dt, divan::black_box(u)));
        }
        s
    });
}

#[divan::bench(args = SIZES)]
fn parts_exact_at_nodes(bencher: Bencher, m: usize) {
    let n = steps(m);
    bencher.counter(ItemsCount::new(m * n)).with_inputs(|| setup(m)).bench_local_values(|(s, _, dt, exact)| {
        let nodes: Vec<f64> = (0..=m).map(|i| i as f64 / m as f64).collect();
        let mut out = vec![0.0; m + 1];
        for k in 0..n {
            exact.u_at(k as f64 * dt, &nodes, &mut out);
            divan::black_box(&mut out);
        }
        s
    });
}

/// The velocity-level schemes on the same bar with `std` mass (they need a
/// massive contact node), `bar-dirichlet` with its impacts: the nonsmooth
/// generalized-α step (`nsga(0.8)`: the predictor, `F − K Û` and the
/// forward sweep of `S = M + c β dt² K` fused in one pass, the backward
/// sweep and the updates of `U, V, a, q̈` in another; at a contact step two
/// closed-form projections) and Moreau–Jean's (`M V`, `K(U + …)`, one
/// solve), against the floor below (docs/theory.md §4.6.5 records the
/// ratios).
#[divan::bench(args = [1000], consts = [0, 1])]
fn velocity_level_stepping<const MJ: usize>(bencher: Bencher, m: usize) {
    let n = steps(m);
    let spec = if MJ == 1 { SchemeSpec::moreau_jean(0.5, 0.0) } else { SchemeSpec::nsga(0.8, 0.0) };
    bencher
        .counter(ItemsCount::new(m * n))
        .with_inputs(|| {
            let b = Benchmark::BarDirichlet;
            let exact = b.exact(3.0).unwrap();
            let p = b.problem(exact.as_ref(), m, BarMass::Std).unwrap();
            spec.build(p.dynamics(), p.bar.h() / 10.0, &p.initial).unwrap()
        })
        .bench_local_values(|mut s| {
            for _ in 0..n {
                divan::black_box(s.step().unwrap());
            }
            s
        });
}

/// Issue 35's implicit schemes on the same bar and mass as
/// `velocity_level_stepping` (`bar-dirichlet`, m = 1000, std mass,
/// dt = h/10, its impacts), stepping only, per dof-step, against the floor
/// below: `contact-stabilized` (one banded solve a step — its mass-norm
/// projection of the predictor is a bound check, and an axpy with `M⁻¹e_c`
/// at a contact step, not a solve), `nsga(0.8)` and `newmark-cn` for
/// reference (docs/performance.md records the ratios); and the registry's
/// other implicit schemes that take a massive node, for the same table.
#[divan::bench(args = ["contact-stabilized", "nsga(0.8)", "newmark-cn", "newmark-i", "newmark-ii", "backward-euler", "ps-e0", "ps-e0.5", "ps-e1",
                       "penalty-cn", "nitsche-cn", "moreau-jean", "moreau-jean-projected(0.5,0)", "moreau-jean-combined(0.5,0)"])]
fn implicit_scheme_step(bencher: Bencher, scheme: &str) {
    scheme_step(bencher, scheme, BarMass::Std);
}

/// The schemes of a massless contact node on the same bar with `mod` mass
/// (`hybrid`, `reduced-cn`, the explicit `cd-massless`) and, for
/// comparison, `newmark-cn` and `ps-e0` with it.
#[divan::bench(args = ["hybrid", "reduced-cn", "cd-massless", "newmark-cn", "ps-e0"])]
fn massless_node_scheme_step(bencher: Bencher, scheme: &str) {
    scheme_step(bencher, scheme, BarMass::Mod);
}

/// `bar-dirichlet`, m = 1000, dt = h/10, the given mass: stepping only.
fn scheme_step(bencher: Bencher, scheme: &str, mass: BarMass) {
    let m = 1000;
    let n = steps(m);
    let setup = || {
        let b = Benchmark::BarDirichlet;
        let exact = b.exact(3.0).unwrap();
        let p = b.problem(exact.as_ref(), m, mass).unwrap();
        let spec: SchemeSpec = scheme.parse().unwrap();
        spec.build(p.dynamics(), p.bar.h() / 10.0, &p.initial).unwrap()
    };
    bencher.counter(ItemsCount::new(m * n)).with_inputs(setup).bench_local_values(|mut s| {
        for _ in 0..n {
            divan::black_box(s.step().unwrap());
        }
        s
    });
}

/// The floor: forward/backward sweeps of a factored tridiagonal system
/// (`l` sub-diagonal of L, `inv_d` inverse pivots), written out by hand.
#[divan::bench(args = SIZES)]
fn floor_tridiagonal_solve(bencher: Bencher, m: usize) {
    let n = steps(m);
    let l: Vec<f64> = (0..m).map(|i| if i == 0 { 0.0 } else { -0.3 - 1e-6 * i as f64 }).collect();
    let inv_d: Vec<f64> = (0..m).map(|i| 0.5 + 1e-6 * i as f64).collect();
    bencher.counter(ItemsCount::new(m * n)).with_inputs(|| (0..m).map(|i| (i as f64).sin()).collect::<Vec<f64>>()).bench_local_values(|mut b| {
        for _ in 0..n {
            let (l, inv_d, b) = (&l[..m], &inv_d[..m], &mut b[..m]);
            let mut prev = b[0];
            for i in 1..m {
                prev = b[i] - l[i] * prev;
                b[i] = prev;
            }
            let mut next = b[m - 1] * inv_d[m - 1];
            b[m - 1] = next;
            for i in (0..m - 1).rev() {
                next = b[i] * inv_d[i] - l[i + 1] * next;
                b[i] = next;
            }
            divan::black_box(&mut *b);
        }
        b
    });
}

/// The explicit schemes' floor: `y = K x` for the P1 bar's tridiagonal
/// stiffness (three diagonals, hand-written, one pass), the product each
/// explicit step needs at least once.
#[divan::bench(args = [1000, 4000])]
fn floor_tridiagonal_product(bencher: Bencher, m: usize) {
    let n = steps(m);
    let d: Vec<f64> = (0..m).map(|i| 2.0 + 1e-6 * i as f64).collect();
    let off: Vec<f64> = (0..m).map(|i| -1.0 - 1e-6 * i as f64).collect();
    bencher.counter(ItemsCount::new(m * n)).with_inputs(|| ((0..m).map(|i| (i as f64).sin()).collect::<Vec<f64>>(), vec![0.0; m])).bench_local_values(|(mut x, mut y)| {
        for _ in 0..n {
            // x may change between products (as a step's U does): not hoisted.
            let (d, off, x, y) = (&d[..m], &off[..m], &divan::black_box(&mut x)[..m], &mut y[..m]);
            y[0] = d[0] * x[0] + off[1] * x[1];
            for i in 1..m - 1 {
                y[i] = off[i] * x[i - 1] + d[i] * x[i] + off[i + 1] * x[i + 1];
            }
            y[m - 1] = off[m - 1] * x[m - 2] + d[m - 1] * x[m - 1];
            divan::black_box(&mut *y);
        }
        (x, y)
    });
}

/// The explicit schemes' second floor: the minimal explicit step, the
/// central difference without contact `U⁺ = 2U − U⁻ + dt² M⁻¹ (F − K U)`
/// on a lumped `M` (`w = dt² M⁻¹` precomputed) and the P1 bar's
/// tridiagonal `K`, hand-written, one pass: per dof it reads `U` (three
/// neighbours), `U⁻`, `K`'s two diagonals, `w` and `F` and writes `U⁺`
/// over `U⁻` (56 bytes a dof, six arrays of `m` doubles, against the
/// product's 32 bytes and four arrays), the least a scheme that keeps two
/// levels and the general coefficients must move. At m = 1000 the
/// product's four arrays (32 kB) fit the 48 kB L1 data cache of this
/// machine's cores, the step's six (48 kB) do not quite; m = 4000 puts
/// both in L2.
#[divan::bench(args = [1000, 4000])]
fn floor_explicit_step(bencher: Bencher, m: usize) {
    explicit_floor::<false>(bencher, m, 0);
}

/// The floors' kernels compiled with AVX2 (no FMA), as the schemes' fused
/// passes are where the CPU has it (`floor_tridiagonal_product` and
/// `floor_explicit_step` are compiled for the baseline target: SSE2, two
/// doubles a vector), at m = 1000: `product`, `explicit-step`, and
/// `explicit-step-uniform`, the step with `K`'s diagonals and `w`
/// constant (as on a uniform mesh: scalars, not arrays), whose three arrays
/// (24 kB) leave the L1 cache room.
#[divan::bench(args = ["product", "explicit-step", "explicit-step-uniform"])]
fn floor_avx2(bencher: Bencher, which: &str) {
    let m = 1000;
    match which {
        "product" => product_floor::<true>(bencher, m),
        "explicit-step" => explicit_floor::<true>(bencher, m, 0),
        _ => explicit_floor::<true>(bencher, m, 1),
    }
}

fn product_floor<const AVX2: bool>(bencher: Bencher, m: usize) {
    let n = steps(m);
    let d: Vec<f64> = (0..m).map(|i| 2.0 + 1e-6 * i as f64).collect();
    let off: Vec<f64> = (0..m).map(|i| -1.0 - 1e-6 * i as f64).collect();
    bencher.counter(ItemsCount::new(m * n)).with_inputs(|| ((0..m).map(|i| (i as f64).sin()).collect::<Vec<f64>>(), vec![0.0; m])).bench_local_values(|(mut x, mut y)| {
        for _ in 0..n {
            // x may change between products (as a step's U does): not hoisted.
            divan::black_box(&mut x);
            floor_kernels::product::<AVX2>(&d, &off, &x, &mut y);
            divan::black_box(&mut y);
        }
        (x, y)
    });
}

/// `uniform = 1`: the coefficients as scalars.
fn explicit_floor<const AVX2: bool>(bencher: Bencher, m: usize, uniform: usize) {
    let n = steps(m);
    let d: Vec<f64> = (0..m).map(|i| 2.0 + 1e-6 * i as f64).collect();
    let off: Vec<f64> = (0..m).map(|i| -1.0 - 1e-6 * i as f64).collect();
    // dt² M⁻¹ well inside the stability limit (w λ_max(K) < 4: |U| stays bounded).
    let w: Vec<f64> = (0..m).map(|i| 0.01 + 1e-9 * i as f64).collect();
    let f: Vec<f64> = (0..m).map(|i| 1e-3 * (i as f64).cos()).collect();
    let start = || {
        let u: Vec<f64> = (0..m).map(|i| (i as f64).sin()).collect();
        (u.clone(), u)
    };
    bencher.counter(ItemsCount::new(m * n)).with_inputs(start).bench_local_values(|(mut u, mut um)| {
        for _ in 0..n {
            if uniform == 1 {
                floor_kernels::explicit_uniform::<AVX2>(d[1], off[1], w[1], &f, &u, &mut um);
            } else {
                floor_kernels::explicit::<AVX2>(&d, &off, &w, &f, &u, &mut um);
            }
            // U⁻ now holds U⁺: the levels swap, as a step's do.
            std::mem::swap(&mut u, &mut um);
            divan::black_box(&mut u);
        }
        (u, um)
    });
}

/// The floors' passes, hand-written; `AVX2`: compiled with it (when the
/// CPU has it).
mod floor_kernels {
    macro_rules! dispatch {
        ($avx2:expr, fn $name:ident($($a:ident: $t:ty),*) $body:block) => {{
            #[inline(always)]
            fn plain($($a: $t),*) $body
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2")]
            unsafe fn avx2($($a: $t),*) {
                plain($($a),*)
            }
            #[cfg(target_arch = "x86_64")]
            if $avx2 && std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU reports AVX2.
                return unsafe { avx2($($a),*) };
            }
            plain($($a),*)
        }};
    }

    /// `y = K x`, `K` by its diagonal `d` and sub-diagonal `off`
    /// (`floor_tridiagonal_product`'s rows, the interior by sub-slices as
    /// the schemes' fused passes take them).
    pub fn product<const AVX2: bool>(d: &[f64], off: &[f64], x: &[f64], y: &mut [f64]) {
        dispatch!(
            AVX2,
            fn product(d: &[f64], off: &[f64], x: &[f64], y: &mut [f64]) {
                let m = x.len();
                let (d, off, y) = (&d[..m], &off[..m], &mut y[..m]);
                y[0] = d[0] * x[0] + off[1] * x[1];
                y[m - 1] = off[m - 1] * x[m - 2] + d[m - 1] * x[m - 1];
                let (sl, dc, sr, xl, xc, xr) = (&off[1..m - 1], &d[1..m - 1], &off[2..], &x[..m - 2], &x[1..m - 1], &x[2..]);
                for (j, yj) in y[1..m - 1].iter_mut().enumerate() {
                    *yj = sl[j] * xl[j] + dc[j] * xc[j] + sr[j] * xr[j];
                }
            }
        )
    }

    /// `U⁻ ← 2U − U⁻ + w (F − K U)`.
    pub fn explicit<const AVX2: bool>(d: &[f64], off: &[f64], w: &[f64], f: &[f64], u: &[f64], um: &mut [f64]) {
        dispatch!(
            AVX2,
            fn explicit(d: &[f64], off: &[f64], w: &[f64], f: &[f64], u: &[f64], um: &mut [f64]) {
                let m = u.len();
                let (d, off, w, f, um) = (&d[..m], &off[..m], &w[..m], &f[..m], &mut um[..m]);
                um[0] = 2.0 * u[0] - um[0] + w[0] * (f[0] - (d[0] * u[0] + off[1] * u[1]));
                um[m - 1] = 2.0 * u[m - 1] - um[m - 1] + w[m - 1] * (f[m - 1] - (off[m - 1] * u[m - 2] + d[m - 1] * u[m - 1]));
                let (sl, dc, sr, ul, uc, ur) = (&off[1..m - 1], &d[1..m - 1], &off[2..], &u[..m - 2], &u[1..m - 1], &u[2..]);
                let (wc, fc) = (&w[1..m - 1], &f[1..m - 1]);
                for (j, o) in um[1..m - 1].iter_mut().enumerate() {
                    *o = 2.0 * uc[j] - *o + wc[j] * (fc[j] - (sl[j] * ul[j] + dc[j] * uc[j] + sr[j] * ur[j]));
                }
            }
        )
    }

    /// [`explicit`] with `d`, `off`, `w` the same on every row.
    pub fn explicit_uniform<const AVX2: bool>(d: f64, off: f64, w: f64, f: &[f64], u: &[f64], um: &mut [f64]) {
        dispatch!(
            AVX2,
            fn explicit_uniform(d: f64, off: f64, w: f64, f: &[f64], u: &[f64], um: &mut [f64]) {
                let m = u.len();
                let (f, um) = (&f[..m], &mut um[..m]);
                um[0] = 2.0 * u[0] - um[0] + w * (f[0] - (d * u[0] + off * u[1]));
                um[m - 1] = 2.0 * u[m - 1] - um[m - 1] + w * (f[m - 1] - (off * u[m - 2] + d * u[m - 1]));
                let (ul, uc, ur, fc) = (&u[..m - 2], &u[1..m - 1], &u[2..], &f[1..m - 1]);
                for (j, o) in um[1..m - 1].iter_mut().enumerate() {
                    *o = 2.0 * uc[j] - *o + w * (fc[j] - (off * ul[j] + d * uc[j] + off * ur[j]));
                }
            }
        )
    }
}

/// The beam's step (β-scheme, J = 19, dt = 1e-6): ns per step.
#[divan::bench]
fn beam_beta_scheme_step(bencher: Bencher) {
    use signorini_run::beam::{BeamScene, BeamSetup, Pipe};
    let scene = BeamScene::new("bench", 19, 1e-6, 1.0, SchemeSpec::ps(0.0, 0.5));
    bencher.counter(ItemsCount::new(10_000usize)).with_inputs(|| BeamSetup::new(Pipe::paper(), scene).build().unwrap().stepper).bench_local_values(|mut s| {
        for _ in 0..10_000 {
            divan::black_box(s.step().unwrap());
        }
        s
    });
}

/// The banded solve alone (half-bandwidth 3, n = 38): ns per solve.
#[divan::bench]
fn beam_band_solve(bencher: Bencher) {
    let b = signorini_fem::Beam::new(1.501, 19, 282.84).unwrap();
    let f = b.mass().lin_comb(1.0, &b.stiffness(), 0.25e-12).factor().unwrap();
    let rhs: Vec<f64> = (0..38).map(|i| (i as f64).sin()).collect();
    bencher.counter(ItemsCount::new(10_000usize)).with_inputs(|| vec![0.0; 38]).bench_local_values(|mut x| {
        for _ in 0..10_000 {
            x.copy_from_slice(&rhs);
            f.solve_in_place(divan::black_box(&mut x));
        }
        x
    });
}

/// The band solve of `beam_band_solve` with each solve waiting for the one
/// before, as the β-step's must (its right-hand side is made of the last
/// step's solution): the first entry of each right-hand side is
/// `rhs₀ + 0 × x₀` of the last solution (the same numbers), so the next
/// forward sweep cannot start before the last backward sweep has ended —
/// where `beam_band_solve`'s solves, independent of each other, overlap in
/// the processor's out-of-order window. `AVX2 = 0`: `BandLdlt::solve_in_place`
/// (the floor's code, compiled for the baseline target); `AVX2 = 1`: the same
/// two sweeps (`solve_p3`'s operations, written out here) compiled for AVX2,
/// as the fused β-step's are (the baseline build where the CPU has no AVX2).
/// ns per solve.
#[divan::bench(consts = [0, 1])]
fn beam_band_solve_chained<const AVX2: usize>(bencher: Bencher) {
    let b = signorini_fem::Beam::new(1.501, 19, 282.84).unwrap();
    let f = b.mass().lin_comb(1.0, &b.stiffness(), 0.25e-12).factor().unwrap();
    let rhs: Vec<f64> = (0..38).map(|i| (i as f64).sin()).collect();
    // The written-out sweeps are the solve's: the same bits.
    let (mut mine, mut theirs) = (vec![0.0; 38], rhs.clone());
    chained_p3::solves(&f, &rhs, &mut mine, 1);
    f.solve_in_place(&mut theirs);
    assert!(mine.iter().zip(&theirs).all(|(a, b)| a.to_bits() == b.to_bits()), "chained_p3 is not solve_p3");
    bencher.counter(ItemsCount::new(10_000usize)).with_inputs(|| vec![0.0; 38]).bench_local_values(|mut x| {
        if AVX2 == 1 {
            chained_p3::solves(&f, &rhs, &mut x, 10_000);
        } else {
            for _ in 0..10_000 {
                let last = x[0];
                x.copy_from_slice(&rhs);
                x[0] += 0.0 * last;
                f.solve_in_place(divan::black_box(&mut x));
            }
        }
        x
    });
}

/// `beam_band_solve_chained`'s solves with the two sweeps of
/// `BandLdlt::solve_p3` written out and compiled for AVX2 where the CPU has it.
mod chained_p3 {
    use signorini_fem::BandLdlt;

    pub fn solves(f: &BandLdlt, rhs: &[f64], x: &mut [f64], count: usize) {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU reports AVX2.
            return unsafe { solves_avx2(f, rhs, x, count) };
        }
        solves_body(f, rhs, x, count)
    }

    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn solves_avx2(f: &BandLdlt, rhs: &[f64], x: &mut [f64], count: usize) {
        solves_body(f, rhs, x, count)
    }

    #[inline(always)]
    fn solves_body(f: &BandLdlt, rhs: &[f64], x: &mut [f64], count: usize) {
        let (l, lt, inv_d) = f.band_factors();
        let n = x.len();
        let (l, lt, inv_d) = (&l[..3 * n], &lt[..3 * n], &inv_d[..n]);
        for _ in 0..count {
            let last = x[0];
            x.copy_from_slice(rhs);
            x[0] += 0.0 * last;
            let b = &mut *divan::black_box(&mut *x);
            b[1] -= l[3] * b[0];
            b[2] -= l[7] * b[0] + l[6] * b[1];
            let (mut w1, mut w2, mut w3) = (b[2], b[1], b[0]);
            for (bi, row) in b[3..].iter_mut().zip(l[9..].chunks_exact(3)) {
                let s = (*bi - row[2] * w3 - row[1] * w2) - row[0] * w1;
                (w3, w2, w1) = (w2, w1, s);
                *bi = s;
            }
            b[n - 1] *= inv_d[n - 1];
            b[n - 2] = b[n - 2] * inv_d[n - 2] - lt[(n - 2) * 3] * b[n - 1];
            b[n - 3] = b[n - 3] * inv_d[n - 3] - lt[(n - 3) * 3 + 1] * b[n - 1] - lt[(n - 3) * 3] * b[n - 2];
            let (mut x1, mut x2, mut x3) = (b[n - 3], b[n - 2], b[n - 1]);
            for ((bi, col), di) in b[..n - 3].iter_mut().rev().zip(lt[..(n - 3) * 3].chunks_exact(3).rev()).zip(inv_d[..n - 3].iter().rev()) {
                let s = (*bi * di - col[2] * x3 - col[1] * x2) - col[0] * x1;
                (x3, x2, x1) = (x2, x1, s);
                *bi = s;
            }
        }
    }
}

/// The beam's banded product (half-bandwidth 3, n = 38: `K x`), as every
/// scheme but the fused β-step makes it (Moreau–Jean, nsga,
/// contact-stabilized, d1-minus-linear on the beam): by rows (`ROWS = 1`,
/// `SymBand::mul_vec_p3`, the old path) and by diagonals (`ROWS = 0`,
/// `SymBand::mul_vec`), the same bits: ns per product.
#[divan::bench(consts = [0, 1])]
fn beam_band_product<const ROWS: usize>(bencher: Bencher) {
    let b = signorini_fem::Beam::new(1.501, 19, 282.84).unwrap();
    let k = b.stiffness();
    let x: Vec<f64> = (0..38).map(|i| (i as f64).sin()).collect();
    bencher.counter(ItemsCount::new(10_000usize)).with_inputs(|| vec![0.0; 38]).bench_local_values(|mut y| {
        for _ in 0..10_000 {
            if ROWS == 1 {
                k.mul_vec_p3(divan::black_box(&x), &mut y);
            } else {
                k.mul_vec(divan::black_box(&x), &mut y);
            }
        }
        y
    });
}

/// The explicit Nitsche step (`verlet-nitsche(10,1)`, docs/theory.md
/// §4.6.8) and the CD-Lagrange step (`cd-lagrange(0)`, §4.6.9: the central
/// difference and a velocity-level impulse where a contact is closed) next
/// to `penalty-cd` (the same central difference with a penalty spring),
/// and Schindler–Acary's scheme on its two levels (§4.6.7) next to
/// `newmark-cn`; lumped mass, `bar-dirichlet` at dx/dt = 10 (below every
/// limit): stepping only, per dof-step.
#[divan::bench(args = ["verlet-nitsche(10,1)", "cd-lagrange(0)", "penalty-cd", "d1-minus-linear(0)", "d1-minus-linear-velocity(0)", "newmark-cn", "taylor-flanagan", "cd-taylor"])]
fn c_explicit_contact_step(bencher: Bencher, scheme: &str) {
    let m = 1000;
    let n = steps(m);
    let setup = || explicit_stepper(scheme, m, false);
    bencher.counter(ItemsCount::new(m * n)).with_inputs(setup).bench_local_values(|mut s| {
        for _ in 0..n {
            divan::black_box(s.step().unwrap());
        }
        s
    });
}

/// `scheme` on `bar-dirichlet` with `m` elements, lumped mass, dt = h/10,
/// with its energy fused into every step if `energy`
/// (`Stepper::fuse_energy`): the explicit benches' stepper.
fn explicit_stepper(scheme: &str, m: usize, energy: bool) -> Box<dyn Stepper> {
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(3.0).unwrap();
    let p = b.problem(exact.as_ref(), m, BarMass::Lumped).unwrap();
    let spec: SchemeSpec = scheme.parse().unwrap();
    let mut s = spec.build(p.dynamics(), p.bar.h() / 10.0, &p.initial).unwrap();
    if energy {
        s.fuse_energy(true);
    }
    s
}

/// `c_explicit_contact_step` with the energy after every step, as
/// `signorini run` asks for it (`Stepper::fuse_energy`, then `energy()`):
/// what the energy's sums add to each explicit step.
#[divan::bench(args = ["verlet-nitsche(10,1)", "cd-lagrange(0)", "penalty-cd", "d1-minus-linear(0)", "taylor-flanagan"])]
fn d_explicit_step_with_energy(bencher: Bencher, scheme: &str) {
    let m = 1000;
    let n = steps(m);
    let setup = || explicit_stepper(scheme, m, true);
    bencher.counter(ItemsCount::new(m * n)).with_inputs(setup).bench_local_values(|mut s| {
        for _ in 0..n {
            divan::black_box(s.step().unwrap());
            divan::black_box(s.energy());
        }
        s
    });
}
