//! Benettin's largest Lyapunov exponent on systems whose exponent is known,
//! and batch-means intervals: their arithmetic and their coverage.

use signorini_run::chaos::{lyapunov, predictability_horizon, Benettin, Flow};
use signorini_run::stats::{batch_means, t_quantile};
use signorini_run::RunError;
use signorini_schemes::SplitMix64;

/// A linear map `x ← P x` (the exact propagator of a linear ODE over `dt`).
struct Linear {
    p: [[f64; 2]; 2],
    x: [f64; 2],
    dt: f64,
}

impl Flow for Linear {
    fn dt(&self) -> f64 {
        self.dt
    }
    fn state(&self) -> Result<Vec<f64>, RunError> {
        Ok(self.x.to_vec())
    }
    fn set_state(&mut self, s: &[f64]) -> Result<(), RunError> {
        self.x = [s[0], s[1]];
        Ok(())
    }
    fn advance(&mut self, steps: usize) -> Result<(), RunError> {
        for _ in 0..steps {
            let [[a, b], [c, d]] = self.p;
            self.x = [a * self.x[0] + b * self.x[1], c * self.x[0] + d * self.x[1]];
        }
        Ok(())
    }
}

/// The logistic map `x ← 4 x (1 − x)`: λ = ln 2 per iteration.
struct Logistic(f64);

impl Flow for Logistic {
    fn dt(&self) -> f64 {
        1.0
    }
    fn state(&self) -> Result<Vec<f64>, RunError> {
        Ok(vec![self.0])
    }
    fn set_state(&mut self, s: &[f64]) -> Result<(), RunError> {
        self.0 = s[0];
        Ok(())
    }
    fn advance(&mut self, steps: usize) -> Result<(), RunError> {
        for _ in 0..steps {
            self.0 = 4.0 * self.0 * (1.0 - self.0);
        }
        Ok(())
    }
}

/// A scaled Euclidean norm (not the one the rotation preserves).
fn skewed(s: &[f64]) -> f64 {
    (s[0] * s[0] + 4.0 * s.get(1).map_or(0.0, |v| v * v)).sqrt()
}

fn cfg(interval_steps: usize, intervals: usize) -> Benettin {
    Benettin { perturbation: 1e-10, interval_steps, discard: 10, intervals, batches: 20, seed: 7 }
}

#[test]
fn linear_oscillator_has_a_zero_exponent() {
    // x'' = -x: the exact flow over dt is a rotation of (x, v).
    let dt = 0.01_f64;
    let (c, s) = (dt.cos(), dt.sin());
    let p = [[c, s], [-s, c]];
    let mut a = Linear { p, x: [1.0, 0.0], dt };
    let mut b = Linear { p, x: [0.0, 0.0], dt };
    let r = lyapunov(&mut a, &mut b, &skewed, &cfg(37, 4000)).unwrap();
    assert!(r.lambda.abs() < 2e-3, "λ = {}", r.lambda);
    assert!(r.ci.low <= 0.0 && 0.0 <= r.ci.high, "{:?}", r.ci);
    assert_eq!(predictability_horizon(r.lambda.min(0.0), 0.1, 1e-16, 1e-3), f64::INFINITY);
}

#[test]
fn unstable_linear_system_gives_its_eigenvalue() {
    // x' = A x, A = Q diag(0.7, -1.3) Q⁻¹ with a non-orthogonal Q: the exact
    // propagator over dt is Q diag(e^{0.7 dt}, e^{-1.3 dt}) Q⁻¹.
    let dt = 0.05_f64;
    let q = [[1.0, 1.0], [0.3, -2.0]];
    let det = q[0][0] * q[1][1] - q[0][1] * q[1][0];
    let qi = [[q[1][1] / det, -q[0][1] / det], [-q[1][0] / det, q[0][0] / det]];
    let (e1, e2) = ((0.7 * dt).exp(), (-1.3 * dt).exp());
    let mut p = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            p[i][j] = q[i][0] * e1 * qi[0][j] + q[i][1] * e2 * qi[1][j];
        }
    }
    // The reference starts on the stable eigenvector (it stays bounded over
    // T = 40 while the round-off in the unstable direction grows e^{0.7 t} from
    // 1e-16 to ~1e-4); the twin's random perturbation aligns with the unstable one.
    let mut a = Linear { p, x: [q[0][1], q[1][1]], dt };
    let mut b = Linear { p, x: [0.0, 0.0], dt };
    let r = lyapunov(&mut a, &mut b, &skewed, &cfg(4, 200)).unwrap();
    assert!((r.lambda - 0.7).abs() < 5e-3, "λ = {}", r.lambda);
    assert!((r.ci.low - 1e-3..r.ci.high + 1e-3).contains(&0.7), "{:?}", r.ci);
}

#[test]
fn logistic_map_gives_ln_2() {
    let mut a = Logistic(0.3);
    let mut b = Logistic(0.0);
    let r = lyapunov(&mut a, &mut b, &|s: &[f64]| s[0].abs(), &cfg(1, 200_000)).unwrap();
    let l2 = std::f64::consts::LN_2;
    assert!((r.lambda - l2).abs() < 0.01, "λ = {} against ln 2", r.lambda);
    assert!(r.ci.low <= l2 && l2 <= r.ci.high, "{:?}", r.ci);
    // Renormalised every iteration: d stays near d₀, never saturates.
    assert!(r.growths.iter().all(|g| g.abs() < 40.0));
    // Also with several iterations per interval (growth up to 2^5).
    let mut a = Logistic(0.3);
    let r = lyapunov(&mut a, &mut b, &|s: &[f64]| s[0].abs(), &cfg(5, 40_000)).unwrap();
    assert!((r.lambda - l2).abs() < 0.01, "λ = {} (τ = 5)", r.lambda);
}

#[test]
fn bad_perturbations_are_refused() {
    for eps in [0.0, -1e-10, 1e-3, 0.5, f64::NAN] {
        let mut a = Logistic(0.3);
        let mut b = Logistic(0.0);
        let c = Benettin { perturbation: eps, ..cfg(1, 100) };
        match lyapunov(&mut a, &mut b, &|s: &[f64]| s[0].abs(), &c) {
            Err(RunError::Invalid { field: "perturbation", .. }) => {}
            other => panic!("ε = {eps}: {other:?}"),
        }
    }
}

#[test]
fn horizon_is_log_of_the_range_over_lambda() {
    // ln(1e-3 / (1e-16 · 0.1)) / 25 = ln(1e14) / 25.
    let h = predictability_horizon(25.0, 0.1, 1e-16, 1e-3);
    assert!((h - 14.0 * std::f64::consts::LN_10 / 25.0).abs() < 1e-12);
}

#[test]
fn batch_means_interval_of_a_known_series() {
    // Batch means 1, 2, 3, 4 (a dropped first value, then 4 batches of 3):
    // mean 2.5, s² = 5/3 (divisor B − 1 = 3), standard error √(5/12),
    // half width t_{0.975,3} √(5/12).
    let x = [99.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0, 4.0, 4.0, 4.0];
    let i = batch_means(&x, 4, 0.95).unwrap();
    let se = (5.0_f64 / 12.0).sqrt();
    assert!((i.mean - 2.5).abs() < 1e-15);
    assert!((i.std_err - se).abs() < 1e-15, "{}", i.std_err);
    assert!((i.half_width() - 3.182_446_305 * se).abs() < 1e-8, "{}", i.half_width());
    assert!((t_quantile(0.975, 3) - 3.182_446_305).abs() < 1e-8);
}

#[test]
fn batch_means_cover_the_mean_of_a_correlated_series() {
    // AR(1), φ = 0.9 (correlation time ~10), mean 3: 400 seeds of 4000
    // values, 20 batches of 200; the 95 % interval covers 3 in about 95 %.
    let (phi, mu): (f64, f64) = (0.9, 3.0);
    let mut hits = 0;
    for seed in 0..400u64 {
        let mut rng = SplitMix64::new(seed);
        let mut normal = || {
            let (u1, u2) = (rng.next_f64().max(1e-300), rng.next_f64());
            (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
        };
        // Started in the stationary law.
        let mut y = normal() / (1.0 - phi * phi).sqrt();
        let x: Vec<f64> = (0..4000)
            .map(|_| {
                y = phi * y + normal();
                mu + y
            })
            .collect();
        let i = batch_means(&x, 20, 0.95).unwrap();
        hits += usize::from(i.low <= mu && mu <= i.high);
    }
    let cover = hits as f64 / 400.0;
    assert!((0.92..=0.98).contains(&cover), "coverage {cover}");
}

#[test]
fn a_copied_state_continues_the_run() {
    // Two copies of the Dirichlet bar (m = 20): after 37 steps the twin gets
    // the reference's state; 200 steps later they agree to round-off (the
    // state is all the schemes carry besides the time level). The reduced
    // hybrid scheme offers no state: refused, naming the scheme.
    use signorini_fem::BarMass;
    use signorini_run::chaos::StepperFlow;
    use signorini_run::Benchmark;
    use signorini_schemes::SchemeSpec;
    let b = Benchmark::BarDirichlet;
    let exact = b.exact(3.0).unwrap();
    // cd-taylor at Courant number one carries the characteristic release's
    // shift too: its twin is perturbed and copied back inside the contact
    // phase (t = 1 … 2, levels 20 … 40 at dt = h = 0.05).
    for (name, mass, ratio, pre) in [
        ("ps-e0", BarMass::Std, 10.0, 37),
        ("ps-e1", BarMass::Lumped, 10.0, 37),
        ("moreau-jean", BarMass::Std, 10.0, 37),
        ("newmark-cn", BarMass::Std, 10.0, 37),
        ("cd-taylor", BarMass::Lumped, 1.0, 22),
        ("hybrid", BarMass::Mod, 10.0, 37),
        // State (U, V) and what they rebuild in set_state: a(t_n) and the
        // index set; U^{n-1} from V^{n-1/2}.
        ("d1-minus-linear(0)", BarMass::Lumped, 10.0, 37),
        ("d1-minus-linear-velocity(0)", BarMass::Lumped, 10.0, 37),
        ("cd-lagrange(0)", BarMass::Lumped, 10.0, 37),
    ] {
        let p = b.problem(exact.as_ref(), 20, mass).unwrap();
        let spec: SchemeSpec = name.parse().unwrap();
        let dt = p.bar.h() / ratio;
        let mut a = StepperFlow(spec.build(p.dynamics(), dt, &p.initial).unwrap());
        let mut t = StepperFlow(spec.build(p.dynamics(), dt, &p.initial).unwrap());
        a.advance(pre).unwrap();
        t.advance(pre).unwrap();
        let s = match a.state() {
            Ok(s) => s,
            Err(RunError::NotAllowed { field: "scheme", .. }) if name == "hybrid" => continue,
            Err(e) => panic!("{name}: {e}"),
        };
        assert_ne!(name, "hybrid", "the hybrid scheme offers no state");
        assert!(t.set_state(&s[1..]).is_err(), "{name}: a wrong length is refused");
        // Perturb the twin, then give it the reference's state back.
        let mut off = s.clone();
        off.iter_mut().for_each(|x| *x += 1e-3);
        t.set_state(&off).unwrap();
        t.advance(3).unwrap();
        a.advance(3).unwrap();
        t.set_state(&a.state().unwrap()).unwrap();
        // What the scheme rebuilds from the state (U^{n-1}, a(t_n), …) gives
        // the reference's energy at once, to round-off.
        if let (Some((ta, ea)), Some((tt, et))) = (a.0.energy(), t.0.energy()) {
            assert!(ta == tt && (ea - et).abs() <= 1e-12 * ea.abs().max(1e-300), "{name}: the copied state's energy {et:e} against {ea:e}");
        }
        a.advance(200).unwrap();
        t.advance(200).unwrap();
        let (ua, ut) = (a.0.displacement().to_vec(), t.0.displacement().to_vec());
        let diff = ua.iter().zip(&ut).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        assert!(diff < 1e-12, "{name}: the copied state's run differs by {diff:e}");
    }
}
