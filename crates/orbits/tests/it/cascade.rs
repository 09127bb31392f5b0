//! `--switch` follows the period-doubling cascade of the impact oscillator
//! (the scene of `switch.rs`, from Ω = 2.2 down to 1.03): the period-1
//! branch doubles at 1.0648, the period-2 loop born there doubles again
//! at 1.0753 and 1.0820, and the period-4 branch born there is continued
//! too. Checked against a transcription of the oscillator sharing no code
//! with the crate: its closed-form flow between impacts (the underdamped
//! free motion plus the forced steady state), its own impact search
//! (sampling and bisection), the restitution applied by hand. The period-4
//! orbits are fixed points of its map over 4 periods and not over 2; where
//! one is stable a long run of that map from beside it lands on it; the
//! period doublings of the period-2 loop are where `det(P₂' + I)` of its
//! orbits (Newton on the transcribed map, its Jacobian by central
//! differences) changes sign.

use signorini_orbits::front::{continue_scene, ContinueOptions};

const ZETA: f64 = 0.05;
const GAP: f64 = 0.2;
const E: f64 = 0.8;

/// The free flow of `x'' + 2ζx' + x = cos Ωt` (the scene's `[forcing]`) from `(x, v)` at `t0` to
/// `t`, in closed form.
pub(crate) fn flow(omega: f64, t0: f64, x: f64, v: f64, t: f64) -> (f64, f64) {
    // x_p = A cos Ωt + B sin Ωt: (1 − Ω²) A + 2ζΩ B = 1, (1 − Ω²) B − 2ζΩ A = 0.
    let d = (1.0 - omega * omega).powi(2) + (2.0 * ZETA * omega).powi(2);
    let (a, b) = ((1.0 - omega * omega) / d, 2.0 * ZETA * omega / d);
    let xp = |t: f64| a * (omega * t).cos() + b * (omega * t).sin();
    let vp = |t: f64| omega * (b * (omega * t).cos() - a * (omega * t).sin());
    let wd = (1.0 - ZETA * ZETA).sqrt();
    let c1 = x - xp(t0);
    let c2 = (v - vp(t0) + ZETA * c1) / wd;
    let s = t - t0;
    let (ex, (sn, cs)) = ((-ZETA * s).exp(), (wd * s).sin_cos());
    let h = ex * (c1 * cs + c2 * sn);
    let hv = ex * (-ZETA * (c1 * cs + c2 * sn) + wd * (-c1 * sn + c2 * cs));
    (h + xp(t), hv + vp(t))
}

/// The map over `periods` forcing periods with the stop at `gap`: the flow
/// sampled at 1/4000 of a period, each crossing of the stop bisected to
/// round-off and its velocity reversed times `e`.
pub(crate) fn map(gap: f64, omega: f64, x: [f64; 2], periods: usize) -> [f64; 2] {
    let end = periods as f64 * std::f64::consts::TAU / omega;
    let h = std::f64::consts::TAU / omega / 4000.0;
    let (mut t0, mut z) = (0.0, (x[0], x[1]));
    let mut t = 0.0;
    while t < end {
        let t1 = (t + h).min(end);
        if flow(omega, t0, z.0, z.1, t1).0 > gap {
            let (mut lo, mut hi) = (t, t1);
            for _ in 0..200 {
                let m = 0.5 * (lo + hi);
                if m <= lo || m >= hi {
                    break;
                }
                if flow(omega, t0, z.0, z.1, m).0 > gap {
                    hi = m;
                } else {
                    lo = m;
                }
            }
            let v = flow(omega, t0, z.0, z.1, lo).1;
            (t0, z) = (lo, (gap, -E * v));
            t = lo;
            continue;
        }
        t = t1;
    }
    let z = flow(omega, t0, z.0, z.1, end);
    [z.0, z.1]
}

fn off(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).abs().max((a[1] - b[1]).abs())
}

/// The map's Jacobian over `periods` by central differences.
fn jacobian(gap: f64, omega: f64, x: [f64; 2], periods: usize) -> [[f64; 2]; 2] {
    let mut j = [[0.0; 2]; 2];
    for c in 0..2 {
        let h = 1e-6;
        let (mut p, mut q) = (x, x);
        p[c] += h;
        q[c] -= h;
        let (fp, fq) = (map(gap, omega, p, periods), map(gap, omega, q, periods));
        for r in 0..2 {
            j[r][c] = (fp[r] - fq[r]) / (2.0 * h);
        }
    }
    j
}

/// A fixed point of the map over `periods` by Newton from `x`.
fn orbit(gap: f64, omega: f64, mut x: [f64; 2], periods: usize) -> [f64; 2] {
    for _ in 0..30 {
        let g = map(gap, omega, x, periods);
        let r = [g[0] - x[0], g[1] - x[1]];
        if r[0].abs().max(r[1].abs()) < 1e-13 {
            break;
        }
        let j = jacobian(gap, omega, x, periods);
        let a = [[j[0][0] - 1.0, j[0][1]], [j[1][0], j[1][1] - 1.0]];
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        x[0] -= (a[1][1] * r[0] - a[0][1] * r[1]) / det;
        x[1] -= (-a[1][0] * r[0] + a[0][0] * r[1]) / det;
    }
    x
}

/// `det(P' + I)` at the orbit of `periods` periods near `x`, and the orbit.
fn pd_test(gap: f64, omega: f64, x: [f64; 2], periods: usize) -> (f64, [f64; 2]) {
    let x = orbit(gap, omega, x, periods);
    let j = jacobian(gap, omega, x, periods);
    ((j[0][0] + 1.0) * (j[1][1] + 1.0) - j[0][1] * j[1][0], x)
}

/// The period doubling of the orbits of `periods` periods between `lo`
/// and `hi` (Newton from `x`): `det(P' + I)` bisected to 1e-12, its sign
/// asserted to change.
pub(crate) fn pd_between(gap: f64, mut lo: f64, mut hi: f64, x: [f64; 2], periods: usize) -> f64 {
    let (mut flo, mut x) = pd_test(gap, lo, x, periods);
    let (fhi, _) = pd_test(gap, hi, x, periods);
    assert!(flo * fhi < 0.0, "det(P' + I) keeps its sign from {lo} to {hi}: {flo} {fhi}");
    while hi - lo > 1e-12 {
        let m = 0.5 * (lo + hi);
        let (f, xm) = pd_test(gap, m, x, periods);
        x = xm;
        if f * flo > 0.0 {
            (lo, flo) = (m, f);
        } else {
            hi = m;
        }
    }
    lo
}

/// The rows of a CSV as (header, rows).
pub(crate) fn rows(csv: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = csv.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    (head, lines.map(|l| l.split(',').map(String::from).collect()).collect())
}

#[test]
fn the_switch_follows_the_cascade_to_period_four() {
    let doc = crate::oscillator(ZETA, GAP, E, 2.2);
    let opts = ContinueOptions { param: "forcing.omega".into(), from: 2.2, to: 1.03, period: 1, transient: 100.0, max_points: 400, switch: true, sweep: Vec::new(), param_scale: None };
    let done = continue_scene(doc, &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true).unwrap();
    for l in &done.lines {
        eprintln!("{l}");
    }
    let (hb, pts) = rows(&done.files.iter().find(|f| f.0 == "branch.csv").unwrap().1);
    let c = |n: &str| hb.iter().position(|h| h == n).unwrap();
    let (cp, cper, cs, cq, cv) = (c("param"), c("period"), c("stable"), c("q0"), c("v0"));
    let num = |r: &Vec<String>, k: usize| r[k].parse::<f64>().unwrap();
    let four: Vec<&Vec<String>> = pts.iter().filter(|r| r[cper] == "4").collect();
    assert!(four.len() >= 5, "a period-4 branch: {} points", four.len());
    // Every fifth period-4 orbit: a fixed point of the transcribed map over
    // 4 periods, not over 2.
    for r in four.iter().step_by(5) {
        let (w, x) = (num(r, cp), [num(r, cq), num(r, cv)]);
        let (two, four) = (off(map(GAP, w, x, 2), x), off(map(GAP, w, x, 4), x));
        eprintln!("Ω = {w}: |P⁴(x) − x| {four:e}, |P²(x) − x| {two:e}");
        assert!(four <= 1e-8 && two >= 1e-4, "Ω = {w}: |P⁴(x) − x| {four:e}, |P²(x) − x| {two:e}");
    }
    // A stable one attracts: a run of the transcribed map from 1e-3 beside
    // the most stable one (least |μ|max) lands on its orbit (on one of
    // the orbit's states at 0, 1, 2, 3 periods).
    let cm = c("mu_max");
    let r = four.iter().filter(|r| r[cs] == "1").min_by(|a, b| num(a, cm).total_cmp(&num(b, cm))).expect("stable period-4 orbits");
    let (w, x) = (num(r, cp), [num(r, cq), num(r, cv)]);
    let mut y = [x[0] + 1e-3, x[1] - 1e-3];
    for _ in 0..200 {
        y = map(GAP, w, y, 4);
    }
    let states: Vec<[f64; 2]> = (0..4).map(|k| map(GAP, w, x, k)).collect();
    let d = states.iter().map(|s| off(y, *s)).fold(f64::INFINITY, f64::min);
    eprintln!("Ω = {w} (|μ|max {}): a run from beside the stable period-4 orbit ends {d:e} from it", num(r, cm));
    assert!(d <= 1e-8, "Ω = {w}: the run ends {d:e} from the orbit");
    // The period doublings of the period-2 branch (where the period-4 one
    // is born), against det(P₂' + I) of the transcription, bisected.
    let (hf, bifs) = rows(&done.files.iter().find(|f| f.0 == "bifurcations.csv").unwrap().1);
    let cf = |n: &str| hf.iter().position(|h| h == n).unwrap();
    let (fp, fk, fb) = (cf("param"), cf("kind"), cf("branch"));
    let period_of = |branch: &str| pts.iter().find(|r| r[c("branch")] == branch).map(|r| r[cper].clone()).unwrap();
    let pds: Vec<f64> = bifs.iter().filter(|r| r[fk] == "period-doubling" && period_of(&r[fb]) == "2").map(|r| r[fp].parse().unwrap()).collect();
    assert!(!pds.is_empty());
    let twos: Vec<&Vec<String>> = pts.iter().filter(|r| r[cper] == "2").collect();
    for pd in pds {
        // The period-2 orbit listed nearest, as Newton's start.
        let r = twos.iter().min_by(|a, b| (num(a, cp) - pd).abs().total_cmp(&(num(b, cp) - pd).abs())).unwrap();
        let lo = pd_between(GAP, pd - 2e-4, pd + 2e-4, [num(r, cq), num(r, cv)], 2);
        eprintln!("period doubling of the period-2 branch at {pd} vs the transcription's {lo}: {:e}", (pd - lo).abs());
        assert!((pd - lo).abs() <= 1e-7, "period doubling at {pd} vs the transcription's {lo}");
    }
}
