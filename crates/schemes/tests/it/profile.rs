//! The time profiles of `signorini_schemes::profile` against independent
//! values: means against composite Gauss–Legendre quadrature written here
//! (and, for series, an interpolation written here by linear scan), series
//! values against hand values, derivatives against centred finite
//! differences, the random realisation's generator against SplitMix64's
//! published test vector and its PSD against an averaged-periodogram
//! estimate, and every bad input against its typed error's field.

use signorini_schemes::{Harmonic, ProfileError, Psd, RandomSpec, Sampler, SplitMix64, TimeProfile, MAX_RANDOM_COUNT};
use std::f64::consts::{FRAC_PI_2, TAU};

// ---------------------------------------------------------------------------
// Oracles.

/// 5-point Gauss–Legendre nodes and weights on [-1, 1] (closed forms).
fn gl5() -> [(f64, f64); 5] {
    let a = (5.0 - 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
    let b = (5.0 + 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
    let wa = (322.0 + 13.0 * 70.0f64.sqrt()) / 900.0;
    let wb = (322.0 - 13.0 * 70.0f64.sqrt()) / 900.0;
    [(-b, wb), (-a, wa), (0.0, 128.0 / 225.0), (a, wa), (b, wb)]
}

/// `∫_a^b f` by composite 5-point Gauss–Legendre on `panels` equal panels.
fn gauss(f: &dyn Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
    let h = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let (lo, hi) = (a + p as f64 * h, a + (p + 1) as f64 * h);
        let (c, r) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        sum += r * gl5().iter().map(|&(x, w)| w * f(c + r * x)).sum::<f64>();
    }
    sum
}

/// `Σ a sin(ω t + p)`, written here.
fn harmonic_sum(h: &[(f64, f64, f64)], t: f64) -> f64 {
    h.iter().map(|&(a, w, p)| a * (w * t + p).sin()).sum()
}

/// Piecewise-linear interpolation by linear scan, ends held.
fn interp(ts: &[f64], vs: &[f64], t: f64) -> f64 {
    if t <= ts[0] {
        return vs[0];
    }
    for k in 0..ts.len() - 1 {
        if t <= ts[k + 1] {
            let th = (t - ts[k]) / (ts[k + 1] - ts[k]);
            return (1.0 - th) * vs[k] + th * vs[k + 1];
        }
    }
    vs[ts.len() - 1]
}

/// The exact mean of the interpolant over `[a, b]` (a < b): Gauss–Legendre
/// on every sub-interval between consecutive breakpoints (exact on lines).
fn series_mean_oracle(ts: &[f64], vs: &[f64], a: f64, b: f64) -> f64 {
    let mut cuts = vec![a];
    cuts.extend(ts.iter().copied().filter(|&t| t > a && t < b));
    cuts.push(b);
    let f = |t: f64| interp(ts, vs, t);
    cuts.windows(2).map(|w| gauss(&f, w[0], w[1], 1)).sum::<f64>() / (b - a)
}

fn harmonics_profile(h: &[(f64, f64, f64)]) -> TimeProfile {
    TimeProfile::harmonics(h.iter().map(|&(amplitude, omega, phase)| Harmonic { amplitude, omega, phase }).collect()).unwrap()
}

fn terms(p: &TimeProfile) -> &[Harmonic] {
    match p {
        TimeProfile::Harmonics(h) => h,
        other => panic!("expected harmonics, got {other:?}"),
    }
}

// A constant 3 (ω = 0, phase π/2) plus terms of total amplitude 2: every
// mean lies in [1, 5], so a relative tolerance means something.
const H: [(f64, f64, f64); 5] = [(3.0, 0.0, FRAC_PI_2), (0.8, 1.3, 0.4), (-0.5, 7.1, 2.0), (0.4, 23.0, -1.1), (0.3, 0.05, 5.0)];

// ---------------------------------------------------------------------------
// Harmonics and Sine.

#[test]
fn harmonics_values_and_means_match_quadrature() {
    let p = harmonics_profile(&H);
    let f = |t: f64| harmonic_sum(&H, t);
    for t in [-3.7, 0.0, 0.123, 10.0, 1234.5] {
        let (got, want) = (p.value(t), f(t));
        assert!((got - want).abs() <= 1e-14 * 5.0, "value({t}) = {got}, want {want}");
    }
    let intervals: [(f64, f64); 7] = [(0.0, 0.01), (0.3, 0.9), (-2.0, 5.0), (1.0, 41.0), (100.0, 100.3), (7.0, 2.0), (0.0, 1e-3)];
    for (t0, t1) in intervals {
        let (a, b) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
        // Panels with ω_max h <= 0.25: the 5-point rule is then exact to rounding.
        let panels = ((23.0 * (b - a) / 0.25).ceil() as usize).max(1);
        let want = gauss(&f, a, b, panels) / (b - a);
        let got = p.mean(t0, t1);
        assert!((got - want).abs() <= 1e-13 * want.abs(), "mean({t0}, {t1}) = {got:e}, quadrature {want:e}, rel {:e}", (got - want).abs() / want.abs());
    }
    // A degenerate interval is the value.
    assert!((p.mean(0.7, 0.7) - f(0.7)).abs() <= 1e-15 * 5.0);
}

#[test]
fn harmonics_short_interval_mean_has_no_cancellation() {
    // Over δ = 1e-7 the mean is s(t_mid) - δ²/24 Σ a ω² sin(ω t_mid + p) + O(δ⁴):
    // a Taylor expansion, independent of the sinc form. A difference of
    // cosines over ω δ would lose ~7 digits here.
    let p = harmonics_profile(&H);
    for mid in [0.3, 2.0, 17.5] {
        let d = 1e-7;
        let want = harmonic_sum(&H, mid) - d * d / 24.0 * H.iter().map(|&(a, w, ph)| a * w * w * (w * mid + ph).sin()).sum::<f64>();
        let got = p.mean(mid - 0.5 * d, mid + 0.5 * d);
        assert!((got - want).abs() <= 1e-14 * want.abs(), "mean around {mid}: {got:e} vs {want:e}");
    }
}

#[test]
fn sine_keeps_its_arithmetic_and_exact_mean() {
    let (a, w) = (1.7, 9.3);
    let p = TimeProfile::Sine { amplitude: a, omega: w };
    for (t0, t1) in [(0.0, 0.01), (0.2, 3.1), (5.0, 5.0 + 1e-9), (3.0, 1.0)] {
        // The arithmetic before this module grew variants, bit for bit.
        let half = 0.5 * w * (t1 - t0);
        let sinc = if half.abs() < 1e-8 { 1.0 - half * half / 6.0 } else { half.sin() / half };
        assert_eq!(p.mean(t0, t1).to_bits(), (a * (w * 0.5 * (t0 + t1)).sin() * sinc).to_bits());
        assert_eq!(p.value(t1).to_bits(), (a * (w * t1).sin()).to_bits());
        let (lo, hi): (f64, f64) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
        let want = gauss(&|t| a * (w * t).sin(), lo, hi, 200) / (hi - lo);
        assert!((p.mean(t0, t1) - want).abs() <= 1e-13 * a, "sine mean({t0}, {t1})");
    }
    assert_eq!(p.max_abs(), a);
    // Bit for bit over many steps of many sizes (a last-bit change in the
    // arithmetic shows up somewhere here).
    for dt in [1e-9, 1e-6, 1e-4, 3e-3, 0.05, 0.7] {
        for n in 0..200 {
            let (t0, t1) = (n as f64 * dt, (n + 1) as f64 * dt);
            let half = 0.5 * w * (t1 - t0);
            let sinc = if half.abs() < 1e-8 { 1.0 - half * half / 6.0 } else { half.sin() / half };
            assert_eq!(p.mean(t0, t1).to_bits(), (a * (w * 0.5 * (t0 + t1)).sin() * sinc).to_bits(), "dt {dt}, n {n}");
        }
    }
}

#[test]
fn max_abs_is_the_stated_bound() {
    // Σ|a_i| (a bound) for harmonics, max|v_k| (exact) for series.
    assert_eq!(harmonics_profile(&H).max_abs(), 3.0 + 0.8 + 0.5 + 0.4 + 0.3);
    assert_eq!(TimeProfile::series(vec![0.0, 1.0, 2.0], vec![1.0, -4.5, 2.0]).unwrap().max_abs(), 4.5);
}

#[test]
fn derivatives_match_centred_finite_differences() {
    let sine = TimeProfile::Sine { amplitude: 1.7, omega: 9.3 };
    let harm = harmonics_profile(&H[1..]);
    for p in [&sine, &harm] {
        let d1 = p.derivative().unwrap();
        let d2 = p.second_derivative().unwrap();
        // Scales: Σ|a|ω and Σ|a|ω² bound |s'| and |s''|.
        let (s1, s2) = match p {
            TimeProfile::Sine { amplitude, omega } => (amplitude.abs() * omega, amplitude.abs() * omega * omega),
            _ => (H[1..].iter().map(|h| h.0.abs() * h.1).sum(), H[1..].iter().map(|h| h.0.abs() * h.1 * h.1).sum()),
        };
        for t in [0.0, 0.37, 2.5, -1.2] {
            let h = 1e-5;
            let fd1 = (p.value(t + h) - p.value(t - h)) / (2.0 * h);
            let fd2 = (p.value(t + 1e-4) - 2.0 * p.value(t) + p.value(t - 1e-4)) / 1e-8;
            assert!((d1.value(t) - fd1).abs() <= 1e-7 * s1, "s'({t}) = {} vs FD {fd1} ({p:?})", d1.value(t));
            assert!((p.derivative_at(t).unwrap() - fd1).abs() <= 1e-7 * s1, "derivative_at({t})");
            assert!((d2.value(t) - fd2).abs() <= 1e-5 * s2, "s''({t}) = {} vs FD {fd2} ({p:?})", d2.value(t));
        }
    }
    // The initial rate of A sin(ω t) is A ω.
    assert!((sine.derivative().unwrap().value(0.0) - 1.7 * 9.3).abs() <= 1e-14 * 1.7 * 9.3);
    assert!((sine.derivative_at(0.0).unwrap() - 1.7 * 9.3).abs() <= 1e-14 * 1.7 * 9.3);
    // Series: no derivative (φ'' would be a train of impulses).
    let s = TimeProfile::series(vec![0.0, 1.0], vec![0.0, 1.0]).unwrap();
    assert_eq!((s.derivative(), s.second_derivative(), s.derivative_at(0.5)), (None, None, None));
}

// ---------------------------------------------------------------------------
// Series.

#[test]
fn series_values_at_points_and_midpoints() {
    let p = TimeProfile::series(vec![-1.0, 0.0, 2.0, 2.5, 6.0], vec![4.0, -2.0, 1.0, 1.0, 8.0]).unwrap();
    // At the points: the values; at midpoints: the averages of neighbours (by hand).
    for (t, want) in [(-1.0, 4.0), (0.0, -2.0), (2.0, 1.0), (2.5, 1.0), (6.0, 8.0)] {
        assert_eq!(p.value(t), want, "s({t})");
    }
    for (t, want) in [(-0.5, 1.0), (1.0, -0.5), (2.25, 1.0), (4.25, 4.5), (0.5, -1.25)] {
        assert!((p.value(t) - want).abs() <= 1e-15 * 8.0, "s({t}) = {} vs {want}", p.value(t));
    }
    // Held ends.
    assert_eq!((p.value(-100.0), p.value(-1.0 - 1e-12), p.value(6.5), p.value(1e300)), (4.0, 4.0, 8.0, 8.0));
    assert!(p.value(f64::NAN).is_nan());
}

/// 200 irregularly spaced points, values in [1, 3].
fn long_series() -> (Vec<f64>, Vec<f64>) {
    let ts: Vec<f64> = (0..200).map(|k| k as f64 * 0.5 + 0.2 * (1.3 * k as f64).sin()).collect();
    let vs: Vec<f64> = (0..200).map(|k| 2.0 + (0.7 * k as f64).cos()).collect();
    (ts, vs)
}

#[test]
fn series_means_match_quadrature() {
    let (ts, vs) = long_series();
    let p = TimeProfile::series(ts.clone(), vs.clone()).unwrap();
    let last = ts[199];
    let cases = [
        (ts[3] + 0.1, ts[150] - 0.2), // ~150 pieces
        (-5.0, last + 20.0),          // all of it, both held ends
        (-10.0, -2.0),                // before the data
        (last + 1.0, last + 7.0),     // after the data
        (-1.0, ts[2] + 0.05),         // held start into the data
        (ts[190] + 0.01, last + 3.0), // data into the held end
        (ts[5], ts[6]),               // exactly one piece
        (ts[5] + 0.1, ts[5] + 0.2),   // inside one piece
        (ts[10], ts[20]),             // node to node
        (ts[40] - 1e-9, ts[40] + 1e-9),
        (ts[77] + 0.3, ts[12] - 0.1), // reversed
    ];
    for (t0, t1) in cases {
        let (a, b) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
        let want = series_mean_oracle(&ts, &vs, a, b);
        let got = p.mean(t0, t1);
        assert!((got - want).abs() <= 1e-13 * want.abs(), "mean({t0}, {t1}) = {got} vs {want}");
    }
    assert_eq!(p.mean(ts[9], ts[9]), vs[9]);
    // The integral itself, signed: ∫_b^a = −∫_a^b.
    let TimeProfile::Series(series) = &p else { panic!("a series") };
    let (a, b) = (-3.0, ts[60] + 0.4);
    let want = series_mean_oracle(&ts, &vs, a, b) * (b - a);
    assert!((series.integral(a, b) - want).abs() <= 1e-13 * want.abs());
    assert!((series.integral(b, a) + want).abs() <= 1e-13 * want.abs());
}

// ---------------------------------------------------------------------------
// The generator and the random realisation.

#[test]
fn splitmix64_matches_its_published_test_vector() {
    // The first five outputs for seed 1234567 (Rosetta Code,
    // "Pseudo-random numbers/Splitmix64", from the reference algorithm).
    let mut g = SplitMix64::new(1234567);
    let want = [6457827717110365317u64, 3203168211198807973, 9817491932198370423, 4593380528125082431, 16408922859458223821];
    assert_eq!([g.next_u64(), g.next_u64(), g.next_u64(), g.next_u64(), g.next_u64()], want);
    let mut g = SplitMix64::new(1234567);
    assert_eq!(g.next_f64(), (6457827717110365317u64 >> 11) as f64 / 9007199254740992.0);
}

fn table_spec(seed: u64) -> RandomSpec {
    // S(f) = f/10 over [1, 5] Hz, 8 bins of 0.5 Hz.
    RandomSpec { f_lo: 1.0, f_hi: 5.0, psd: Psd::Table { f: vec![0.0, 10.0], s: vec![0.0, 1.0] }, count: 8, seed }
}

#[test]
fn random_realisation_is_the_documented_contract() {
    // Computed once, independently (Python: the SplitMix64 outputs through
    // u = (x >> 11) 2⁻⁵³, f_i = f_lo + (i + u_i) Δf, p_i = 2π r_i,
    // a_i = sqrt(2 ∫_bin f/10 df)); frequencies and phases bit for bit.
    let p = TimeProfile::random(&table_spec(1234567)).unwrap();
    let h = terms(&p);
    assert_eq!(h.len(), 8);
    let want = [
        (0.3535533905932738, 7.382992624566121, 1.0910380368811499),
        (0.4183300132670378, 11.096756517398704, 1.5645612542396214),
        (0.4743416490252569, 15.360909927237985, 2.6583399208857372),
        (0.5244044240850758, 17.56353751791419, 1.7296823715499674),
    ];
    for (i, (a, w, ph)) in want.into_iter().enumerate() {
        assert_eq!((h[i].omega, h[i].phase), (w, ph), "term {i}");
        assert!((h[i].amplitude - a).abs() <= 2.0 * f64::EPSILON * a, "term {i}: amplitude {} vs {a}", h[i].amplitude);
    }
}

#[test]
fn random_terms_lie_in_their_bins_and_carry_the_exact_variance() {
    let flat = |count, seed| RandomSpec { f_lo: 0.0, f_hi: 20.0, psd: Psd::Flat(0.3), count, seed };
    let tri = |count, seed| RandomSpec { f_lo: 2.0, f_hi: 6.0, psd: Psd::Table { f: vec![1.0, 4.0, 8.0], s: vec![0.0, 3.0, 1.0] }, count, seed };
    // ∫ S df by hand: flat 0.3 · 20 = 6; the table over [2, 6]: S(2) = 1,
    // S(4) = 3, S(6) = 2, so (1 + 3)/2 · 2 + (3 + 2)/2 · 2 = 9.
    for (spec, var, df) in [(flat(1, 5), 6.0, 20.0), (flat(1000, 6), 6.0, 0.02), (tri(7, 7), 9.0, 4.0 / 7.0), (tri(1000, 8), 9.0, 0.004)] {
        let p = TimeProfile::random(&spec).unwrap();
        let h = terms(&p);
        assert_eq!(h.len(), spec.count);
        let got: f64 = h.iter().map(|h| 0.5 * h.amplitude * h.amplitude).sum();
        assert!((got - var).abs() <= 1e-12 * var, "variance {got} vs ∫S = {var}");
        for (i, h) in h.iter().enumerate() {
            let f = h.omega / TAU;
            let lo = spec.f_lo + i as f64 * df;
            assert!(f >= lo * (1.0 - 1e-15) && f <= (lo + df) * (1.0 + 1e-15), "term {i}: f = {f} outside [{lo}, {}]", lo + df);
            assert!((0.0..TAU).contains(&h.phase), "term {i}: phase {}", h.phase);
        }
    }
}

#[test]
fn random_same_seed_same_signal_other_seed_other_signal() {
    let a = TimeProfile::random(&table_spec(42)).unwrap();
    let b = TimeProfile::random(&table_spec(42)).unwrap();
    let c = TimeProfile::random(&table_spec(43)).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.value(1.234).to_bits(), b.value(1.234).to_bits());
    let (ta, tc) = (terms(&a), terms(&c));
    assert!(ta.iter().zip(tc).all(|(x, y)| x.omega != y.omega && x.phase != y.phase), "seeds 42 and 43 share a term");
    assert_ne!(a.value(1.234), c.value(1.234));
}

#[test]
fn random_psd_matches_averaged_periodograms() {
    // Estimator: K = 400 realisations (seeds 1..=400), each sampled at
    // fs = 32 Hz over N = 256 samples (T = 8 s, bins of 1/T = 0.125 Hz),
    // Hann window w_n, one-sided periodogram
    //     P(f_k) = 2 dt |Σ w_n x_n e^{-2πi k n/N}|² / Σ w_n²,
    // averaged. Each bin sums ~20 lines of independent random phase, so a
    // single periodogram is close to exponential (relative standard
    // deviation <= 1) and the average's relative standard error is about
    // 1/sqrt(K) = 5%: assert within 4 of them (20%). Bins within 3 bins of
    // the band edges and of the PSD's kink (where the window's 0.25 Hz main
    // lobe smooths S) are skipped; out of band (>= 1 Hz away) the Hann
    // leakage is far below 1e-4 S.
    const K: u64 = 400;
    const N: usize = 256;
    let dt = 1.0 / 32.0;
    let s_of = |f: f64| if f <= 4.0 { 0.01 + 0.01 * (f - 2.0) } else { 0.03 - 0.005 * (f - 4.0) };
    let w: Vec<f64> = (0..N).map(|n| 0.5 - 0.5 * (TAU * n as f64 / N as f64).cos()).collect();
    let w2: f64 = w.iter().map(|x| x * x).sum();
    let (cs, sn): (Vec<f64>, Vec<f64>) = (0..N).map(|m| (TAU * m as f64 / N as f64).sin_cos()).map(|(s, c)| (c, s)).unzip();
    let mut avg = vec![0.0; N / 2 + 1];
    let mut x = vec![0.0; N];
    for seed in 1..=K {
        let spec = RandomSpec { f_lo: 2.0, f_hi: 6.0, psd: Psd::Table { f: vec![2.0, 4.0, 6.0], s: vec![0.01, 0.03, 0.02] }, count: 160, seed };
        let p = TimeProfile::random(&spec).unwrap();
        for (n, xn) in x.iter_mut().enumerate() {
            *xn = w[n] * p.value(n as f64 * dt);
        }
        for (k, a) in avg.iter_mut().enumerate() {
            let (mut re, mut im) = (0.0, 0.0);
            for (n, xn) in x.iter().enumerate() {
                let m = (k * n) % N;
                re += xn * cs[m];
                im -= xn * sn[m];
            }
            *a += 2.0 * dt * (re * re + im * im) / w2 / K as f64;
        }
    }
    let mut tested = 0;
    for (k, &est) in avg.iter().enumerate() {
        let f = k as f64 / (N as f64 * dt);
        if (2.375..=5.625).contains(&f) && (f - 4.0).abs() >= 0.375 {
            let want = s_of(f);
            assert!((est - want).abs() <= 4.0 / (K as f64).sqrt() * want, "P({f} Hz) = {est:e}, S = {want:e}");
            tested += 1;
        } else if !(1.0..=7.0).contains(&f) {
            assert!(est <= 1e-4 * 0.03, "P({f} Hz) = {est:e} out of band");
        }
    }
    assert_eq!(tested, 22);
}

// ---------------------------------------------------------------------------
// Step sampler.

#[test]
fn sampler_matches_value_and_mean() {
    let spec = RandomSpec { f_lo: 0.5, f_hi: 40.0, psd: Psd::Flat(1.0), count: 1000, seed: 9 };
    let p = TimeProfile::random(&spec).unwrap();
    let scale = p.max_abs();
    let (t0, dt) = (0.25, 1.0 / 1024.0);
    let mut vals = Sampler::values(&p, t0, dt);
    let mut means = Sampler::means(&p, t0, dt);
    let mut worst: f64 = 0.0;
    for n in 0..3000u64 {
        let (a, b) = (t0 + n as f64 * dt, t0 + (n + 1) as f64 * dt);
        worst = worst.max((vals.next_value() - p.value(a)).abs()).max((means.next_value() - p.mean(a, b)).abs());
    }
    assert!(worst <= 1e-12 * scale, "sampler drift {worst:e} (scale {scale})");
    // A long run where value() itself is accurate to one ulp per term
    // (ω with few bits, t = n 2⁻¹⁰, p = 0.5: ω t + p exact), so the
    // comparison sees the recurrence's own drift: re-synchronised every 64
    // steps it stays at rounding level over 100 000 steps.
    let h: Vec<(f64, f64, f64)> = [1.5, 7.25, 30.125, 101.5, 250.75, 3.0625, 60.5, 180.25].iter().map(|&w| (1.0, w, 0.5)).collect();
    let q = harmonics_profile(&h);
    let dt = 1.0 / 1024.0;
    let mut vals = Sampler::values(&q, 0.0, dt);
    let mut worst: f64 = 0.0;
    for n in 0..100_000u64 {
        worst = worst.max((vals.next_value() - harmonic_sum(&h, n as f64 * dt)).abs());
    }
    assert!(worst <= 2e-14 * 8.0, "long-run sampler drift {worst:e}");
    // Sine and Series are evaluated directly: identical.
    for q in [TimeProfile::Sine { amplitude: 2.0, omega: 3.0 }, TimeProfile::series(vec![0.0, 0.1, 0.3], vec![1.0, -1.0, 2.0]).unwrap()] {
        let (mut v, mut m) = (Sampler::values(&q, 0.0, 0.01), Sampler::means(&q, 0.0, 0.01));
        for n in 0..50u64 {
            assert_eq!(v.next_value().to_bits(), q.value(n as f64 * 0.01).to_bits());
            assert_eq!(m.next_value().to_bits(), q.mean(n as f64 * 0.01, (n + 1) as f64 * 0.01).to_bits());
        }
    }
}

// ---------------------------------------------------------------------------
// Bad input: a typed error naming the field.

fn field(e: Result<TimeProfile, ProfileError>) -> String {
    let e = e.expect_err("bad input accepted");
    assert!(e.to_string().contains(e.field()), "message {e} does not name {}", e.field());
    e.field().to_string()
}

#[test]
fn bad_random_specs_are_typed_errors_naming_the_field() {
    let ok = RandomSpec { f_lo: 1.0, f_hi: 5.0, psd: Psd::Flat(1.0), count: 10, seed: 0 };
    assert!(TimeProfile::random(&ok).is_ok());
    let with = |edit: &dyn Fn(&mut RandomSpec)| {
        let mut s = ok.clone();
        edit(&mut s);
        field(TimeProfile::random(&s))
    };
    assert_eq!(with(&|s| s.f_hi = 1.0), "random.f_hi");
    assert_eq!(with(&|s| s.f_hi = 0.5), "random.f_hi");
    assert_eq!(with(&|s| s.f_hi = f64::NAN), "random.f_hi");
    assert_eq!(with(&|s| s.f_hi = f64::INFINITY), "random.f_hi");
    assert_eq!(with(&|s| s.f_lo = -1.0), "random.f_lo");
    assert_eq!(with(&|s| s.f_lo = f64::NAN), "random.f_lo");
    assert_eq!(with(&|s| s.count = 0), "random.count");
    assert_eq!(with(&|s| s.count = MAX_RANDOM_COUNT + 1), "random.count");
    assert_eq!(with(&|s| s.psd = Psd::Flat(-1e-3)), "random.psd");
    assert_eq!(with(&|s| s.psd = Psd::Flat(f64::NAN)), "random.psd");
    let table = |f: Vec<f64>, v: Vec<f64>| move |s: &mut RandomSpec| s.psd = Psd::Table { f: f.clone(), s: v.clone() };
    assert_eq!(with(&table(vec![0.0, 3.0, 9.0], vec![1.0, f64::NAN, 1.0])), "random.psd.s[1]");
    assert_eq!(with(&table(vec![0.0, 3.0, 9.0], vec![1.0, 1.0, -0.5])), "random.psd.s[2]");
    assert_eq!(with(&table(vec![0.0, 3.0, 3.0], vec![1.0, 1.0, 1.0])), "random.psd.f[2]");
    assert_eq!(with(&table(vec![1.5, 9.0], vec![1.0, 1.0])), "random.psd.f[0]");
    assert_eq!(with(&table(vec![0.0, 4.0], vec![1.0, 1.0])), "random.psd.f[1]");
    assert_eq!(with(&table(vec![0.0], vec![1.0])), "random.psd");
}

#[test]
fn bad_series_and_harmonics_are_typed_errors_naming_the_field() {
    let s = |t: Vec<f64>, v: Vec<f64>| field(TimeProfile::series(t, v));
    assert_eq!(s(vec![0.0, 1.0, 2.0, 1.5], vec![0.0; 4]), "series.t[3]");
    assert_eq!(s(vec![0.0, 1.0, 1.0], vec![0.0; 3]), "series.t[2]");
    assert_eq!(s(vec![0.0, f64::NAN, 2.0], vec![0.0; 3]), "series.t[1]");
    assert_eq!(s(vec![0.0, 1.0, f64::INFINITY], vec![0.0; 3]), "series.t[2]");
    assert_eq!(s(vec![0.0, 1.0, 2.0], vec![0.0, 1.0, f64::NAN]), "series.v[2]");
    assert_eq!(s(vec![0.0], vec![1.0]), "series");
    assert_eq!(s(vec![], vec![]), "series");
    assert_eq!(s(vec![0.0, 1.0], vec![1.0]), "series.v");
    let h = |v: Vec<Harmonic>| field(TimeProfile::harmonics(v));
    assert_eq!(h(vec![]), "harmonics");
    let g = Harmonic { amplitude: 1.0, omega: 2.0, phase: 0.0 };
    assert_eq!(h(vec![g, Harmonic { omega: f64::NAN, ..g }]), "harmonics[1].omega");
    assert_eq!(h(vec![Harmonic { amplitude: f64::INFINITY, ..g }]), "harmonics[0].amplitude");
}
