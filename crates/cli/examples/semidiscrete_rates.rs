//! How the time steppers converge, as `dt → 0` at a fixed mesh, to the exact
//! solution of the semi-discrete problem (`event-driven(E)`, docs/theory.md
//! §9): the bar-dirichlet benchmark with the consistent (`std`) mass, every
//! scheme run in lockstep with the event-driven reference of the matching
//! restitution at the same `m` and the same `dt` (its levels are exact
//! whatever `dt`), through the path `signorini run` takes (scene text →
//! `Scene::instantiate` → the registry's stepper).
//!
//! ```sh
//! cargo run --release -p signorini-cli --example semidiscrete_rates -- 40 80
//! ```
//!
//! Arguments: the element counts (default 40 80); `--levels K` (default 7:
//! `dx/dt = 10, 20, …, 10·2^(K−1)`), `--fit F` (the least-squares rate over the
//! finest F levels, default 4), `--t-end T` (default 3, one period), `--schemes a,b,…` (`scheme@reference` overrides
//! the reference, e.g. `newmark-cn@event-driven(1)`). Prints, per `m`, one
//! markdown table of the errors at every level and one of the observed rates
//! (docs/theory.md §9.4 reads them).
//!
//! Quantities (max over the levels `t_n = n dt`, `0 < t_n <= T`, unless said):
//! * `u_c`: `|u_c − u_c^ED|`, the contact node's displacement;
//! * `v_c`: the backward differences `(u_c^n − u_c^{n−1})/dt` of both (the
//!   `v_contact` column of `series.csv`);
//! * `v_own`: the scheme's own contact velocity (`Stepper::state`: Newmark's
//!   `M⁻¹P`, Paoli–Schatzman's backward difference) against the exact one;
//! * `L2`: the `L²(0, L)` norm of the P1 field of `U − U^ED`; `max`: its
//!   largest nodal value;
//! * `λ`: `sqrt(dt Σ (λ_n − λ_ref)²)`, the reference being the event-driven
//!   mean force over the window the step's impulse covers (`[t_{n−1}, t_n]`
//!   for the one-step schemes, `[t_{n−2}, t_n]` centred on the Paoli–Schatzman
//!   force's `t_{n−1}`);
//! * `I`: the cumulative impulse `I_n = dt Σ_{k<=n} (λ_k − λ_ref,k)`, in
//!   `L²(0, T)` (its max is half an impact's impulse at any `dt`: the
//!   windows of the two runs' forces are offset by up to a step);
//! * `E`: the scheme's discrete energy against the exact one at its time
//!   (`t_{n−½}` for Paoli–Schatzman: the mean of the two neighbouring levels);
//!   `v_c`, `v_own` and `E` also in `L²(0, T)` (`L²t`): they jump at an
//!   impact, where their max over the levels cannot converge.

use signorini_cli::scene::{Limits, SceneFile};
use std::time::Instant;

fn build(m: usize, scheme: &str, ratio: f64, t_end: f64) -> signorini_cli::scene::Simulation {
    let text = format!("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = {m}\nmass = \"std\"\nscheme = \"{scheme}\"\nratio = {ratio:?}\nt_end = {t_end:?}\n");
    let scene = SceneFile::parse(&text).unwrap().validate_with(&Limits { max_memory: 4e9 }).unwrap();
    scene.instantiate(None).unwrap()
}

/// The reference a scheme converges to: `event-driven(e)` with the scheme's
/// impact law (`ps(e)`: restitution e; projection schemes: e = 0).
fn reference(scheme: &str) -> &str {
    match scheme {
        "ps-e0.5" => "event-driven(0.5)",
        "ps-e1" => "event-driven(1)",
        _ => "event-driven(0)",
    }
}

/// The errors of one scheme at one `(m, dt)` (module docs).
#[derive(Clone, Copy, Debug, Default)]
struct Errors {
    uc: f64,
    vc: f64,
    vown: f64,
    l2: f64,
    max: f64,
    lam: f64,
    imp: f64,
    energy: f64,
    /// `L²(0, T)` of the contact velocities' and the energy's differences.
    vc2: f64,
    vown2: f64,
    energy2: f64,
    /// The reference's `max |E^ED(t_n) − E^ED(0)|`: its drift for e = 1, its loss otherwise.
    ref_drift: f64,
}

impl Errors {
    const NAMES: [&'static str; 11] = ["u_c", "v_c", "v_c L²t", "v_own", "v_own L²t", "L2", "max", "λ L²t", "I L²t", "E", "E L²t"];
    fn get(&self) -> [f64; 11] {
        [self.uc, self.vc, self.vc2, self.vown, self.vown2, self.l2, self.max, self.lam, self.imp, self.energy, self.energy2]
    }
}

/// Runs `scheme` and its reference in lockstep at `dx/dt = ratio`.
fn compare(m: usize, scheme: &str, reference: &str, ratio: f64, t_end: f64) -> Errors {
    let (mut a, mut b) = (build(m, scheme, ratio, t_end), build(m, reference, ratio, t_end));
    let (sa, sb) = (a.stepper.as_mut(), b.stepper.as_mut());
    let dt = sa.dt();
    let h = 1.0 / m as f64;
    let steps = (t_end / dt).round() as usize;
    let mut e = Errors::default();
    let e0 = sb.energy().unwrap().1;
    let (mut ua_prev, mut ub_prev) = (sa.displacement()[0], sb.displacement()[0]);
    // The reference's mean forces and energies per level (index = level).
    let mut lam_b = vec![0.0; steps + 1];
    let mut en_b = vec![e0; steps + 1];
    let mut lam_sq = 0.0;
    let mut imp = 0.0;
    // A two-step scheme arrives at level 1 already (its start step, whose
    // force is not part of its sequence): the levels are compared from there.
    let mut k = 0;
    while k < steps {
        let ra = if k == 0 && sa.level() == 1 { None } else { Some(sa.step().unwrap()) };
        let rb = sb.step().unwrap();
        k = rb.n;
        assert_eq!(sa.level(), k);
        let t = rb.t;
        lam_b[k] = rb.lambda.unwrap().1;
        en_b[k] = sb.energy().unwrap().1;
        e.ref_drift = e.ref_drift.max((en_b[k] - e0).abs());
        let (ua, ub) = (sa.displacement(), sb.displacement());
        e.uc = e.uc.max((ua[0] - ub[0]).abs());
        let dv = ((ua[0] - ua_prev) - (ub[0] - ub_prev)) / dt;
        e.vc = e.vc.max(dv.abs());
        e.vc2 += dt * dv * dv;
        (ua_prev, ub_prev) = (ua[0], ub[0]);
        // The P1 field's L² norm (the clamped end's value is 0) and max norm.
        let d: Vec<f64> = ua.iter().zip(ub).map(|(x, y)| x - y).chain(std::iter::once(0.0)).collect();
        let l2: f64 = d.windows(2).map(|w| h / 3.0 * (w[0] * w[0] + w[0] * w[1] + w[1] * w[1])).sum();
        e.l2 = e.l2.max(l2.sqrt());
        e.max = e.max.max(d.iter().fold(0.0_f64, |s, x| s.max(x.abs())));
        if let (Some(sta), Some(stb)) = (sa.state(), sb.state()) {
            let n = ua.len();
            e.vown = e.vown.max((sta[n] - stb[n]).abs());
            e.vown2 += dt * (sta[n] - stb[n]).powi(2);
        } else {
            e.vown = f64::NAN;
        }
        if let Some((tl, l)) = ra.and_then(|r| r.lambda) {
            let lag = ((t - tl) / dt).round() as usize;
            let r = match lag {
                0 => lam_b[k],
                1 => 0.5 * (lam_b[k - 1] + lam_b[k]),
                _ => panic!("{scheme}: force at {tl} reported at {t}"),
            };
            lam_sq += dt * (l - r) * (l - r);
            imp += dt * (l - r);
            e.imp += dt * imp * imp;
        }
        if let Some((te, en)) = sa.energy() {
            let lag2 = (2.0 * (t - te) / dt).round() as usize;
            let r = match lag2 {
                0 => en_b[k],
                1 => 0.5 * (en_b[k - 1] + en_b[k]),
                _ => panic!("{scheme}: energy at {te} reported at {t}"),
            };
            e.energy = e.energy.max((en - r).abs());
            e.energy2 += dt * (en - r).powi(2);
        }
    }
    assert!((sb.time() - t_end).abs() < 1e-9);
    e.lam = lam_sq.sqrt();
    (e.vc2, e.vown2, e.energy2, e.imp) = (e.vc2.sqrt(), e.vown2.sqrt(), e.energy2.sqrt(), e.imp.sqrt());
    e
}

/// Least-squares slope of `log e` against `log dt`.
fn slope(dts: &[f64], es: &[f64]) -> f64 {
    let pts: Vec<(f64, f64)> = dts.iter().zip(es).filter(|(_, e)| **e > 0.0 && e.is_finite()).map(|(d, e)| (d.ln(), e.ln())).collect();
    if pts.len() < 2 {
        return f64::NAN;
    }
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

fn main() {
    let mut ms = Vec::new();
    let (mut levels, mut fit, mut t_end) = (7usize, 4usize, 3.0);
    let mut schemes: Vec<String> = ["newmark-cn", "newmark-i", "newmark-ii", "backward-euler", "ps-e0", "ps-e0.5", "ps-e1"].map(String::from).to_vec();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--levels" => levels = args.next().unwrap().parse().unwrap(),
            "--fit" => fit = args.next().unwrap().parse().unwrap(),
            "--t-end" => t_end = args.next().unwrap().parse().unwrap(),
            "--schemes" => schemes = args.next().unwrap().split(',').map(String::from).collect(),
            x => ms.push(x.parse::<usize>().expect("an element count")),
        }
    }
    if ms.is_empty() {
        ms = vec![40, 80];
    }
    for &m in &ms {
        println!("\n## m = {m} (std mass), T = {t_end}, dx/dt = 10·2^k, k = 0..{}\n", levels - 1);
        let mut rates = Vec::new();
        for s in &schemes {
            let (s, refname) = s.split_once('@').unwrap_or((s, reference(s)));
            println!("### {s} against {refname}\n");
            println!("| dt | {} | ref. max ΔE | wall s |", Errors::NAMES.join(" | "));
            println!("|---|{}---|---|", "---|".repeat(Errors::NAMES.len()));
            let mut dts = Vec::new();
            let mut all = Vec::new();
            for k in 0..levels {
                let ratio = 10.0 * f64::from(1u32 << k);
                let t0 = Instant::now();
                let e = compare(m, s, refname, ratio, t_end);
                let wall = t0.elapsed().as_secs_f64();
                let dt = 1.0 / (m as f64 * ratio);
                println!("| {dt:.3e} | {} | {:.1e} | {wall:.2} |", e.get().iter().map(|x| format!("{x:.2e}")).collect::<Vec<_>>().join(" | "), e.ref_drift);
                dts.push(dt);
                all.push(e.get());
            }
            let lo = levels.saturating_sub(fit);
            let r: Vec<f64> = (0..Errors::NAMES.len()).map(|q| slope(&dts[lo..], &all[lo..].iter().map(|e| e[q]).collect::<Vec<_>>())).collect();
            let last: Vec<f64> = (0..Errors::NAMES.len()).map(|q| slope(&dts[levels - 2..], &all[levels - 2..].iter().map(|e| e[q]).collect::<Vec<_>>())).collect();
            println!();
            rates.push((s.to_string(), refname.to_string(), r, last, *all.last().unwrap()));
        }
        println!("### m = {m}: observed rates (least squares over the finest {fit} levels; last pair in brackets) and the finest level's errors\n");
        println!("| scheme | reference | {} |", Errors::NAMES.join(" | "));
        println!("|---|---|{}", "---|".repeat(Errors::NAMES.len()));
        for (s, refname, r, last, fin) in &rates {
            let cells: Vec<String> = r.iter().zip(last).zip(fin).map(|((a, b), f)| format!("{a:.2} [{b:.2}] ({f:.1e})")).collect();
            println!("| {s} | {refname} | {} |", cells.join(" | "));
        }
    }
}
