//! A period-2 branch of the impact oscillator (ζ = 0.05, e = 0.3, stop at
//! 0.2) from Ω = 2.42 down: its 2-impact orbits gain a further impact at
//! 2.3843, the 3-impact ones fold at 2.4010, double their period at 2.3962
//! and gain a fourth impact at 2.3835123, where the branch turns back onto
//! the 4-impact orbits (the slow impact's speed growing from 0 with Ω).
//! Up that arc, trial steps of every length fall onto the 3-impact orbits
//! the branch came down (their states 1e-5 apart): the step was halved
//! below the least step and a later trial taken, and the branch went back
//! up the 3-impact arc, listing its period doubling and fold twice. It then
//! ended there, saying so; with `G_λ`'s difference step shrunk at a slow
//! impact (`slow_impact.rs`) it goes up the 4-impact arc to its fold at
//! 2.386056 and back down until the corrector stops at the map's round-off
//! (the slow impact 7.9e-5), saying so; with a trial of NaN flight margin
//! counted as failed in the grazing search (the switched branch's grazing,
//! `symmetric.rs`) it lists a grazing there at 2.380653 onto 2-impact
//! orbits, their period doubling at 2.426949 and fold at 2.434936, and
//! ends at the grazing at 2.367853 with no orbit found past it. An
//! independent transcription of the 2-period map confirms the 2-impact
//! orbits' period doubling, fold and end grazing to 1e-9, and says the
//! change from 4 to 2 impacts was a jump: the 4-impact orbits' third impact
//! vanishes at 2.3806475600435, where they turn back onto 3-impact orbits
//! that fold at 2.3927018 and end at 2.3678525 (the 2-impact orbits' end
//! grazing). A turn back is now taken only where the two arcs meet, the
//! orbit with an impact fewer sought beside the grazing: the branch
//! follows the 3-impact orbits through their fold, turns back at 2.3678525
//! onto the 2-impact ones and runs them until it returns onto itself (the
//! last test below). Every point is checked against runs of the map
//! (stable ones: a run from a nudged state settles on it; all: a fixed
//! point of the 2-period map), and no point lies on an arc the branch has
//! already traced.

use signorini_orbits::front::{continue_scene, ContinueOptions};
use signorini_orbits::{Family, SceneFamily};

/// The transcription's period doubling of the 2-impact orbits.
const PD: f64 = 2.4269491223329;
/// The transcription's fold of the 2-impact orbits.
const FOLD: f64 = 2.4349363812961;
/// The transcription's grazing of the 2-impact orbits (a flight reaching
/// the stop), where the branch ends; the 3-impact orbits born there (the
/// new impact's speed 1e-5 at 5.2e-6 above it, 1e-2 at 5.2e-3) lie on
/// the same side.
const GRAZING: f64 = 2.3678525327577;
/// The transcription's grazing of the 4-impact orbits: their third
/// impact's speed reaches 0 (the orbit with that speed 0 solved for Ω).
const VANISHING: f64 = 2.3806475600435;
/// The transcription's fold of the 3-impact orbits that turn back there.
const FOLD_3: f64 = 2.3927017995113;
/// The transcription's period doubling of those 3-impact orbits, 1.3e-5
/// past their fold (a scratch program of the same closed-form flow: its
/// 2-period map's central-difference multipliers at its orbits Newton
/// found from the branch's, the real one through −1 bisected in Ω: −0.87
/// at 2.3926900, −1.03 at 2.3926880). Past the fold the multiplier goes
/// from +1 through 0 to −1 and on to −3236 at the end grazing; before it,
/// from the vanishing impact, it stays above 1 (755 at 2.3806498, 37.5 at
/// 2.3898341): this is the arc's one period doubling.
const PD_3: f64 = 2.3926883055155;
/// The same transcription's period doubling of the 4-impact orbits, 1.8e-7
/// past their fold at 2.386056 (−0.81 at 2.3860559273, −1.03 at
/// 2.3860558882).
const PD_4: f64 = 2.38605589385;

/// The period-1 orbits' period doubling, where the period-2 orbits meet
/// their copies shifted by one forcing period (the branch's turn onto
/// them): [`period_one_doubling`]'s `det(J + I)` zero. The branch listed it
/// 1.5e-5 apart with the parameter scales 1, 0.05 and the range (the
/// bisection through the singular corrector: 2.262372856062, none,
/// 2.262387955394).
fn branch_point(bifs: &[(f64, &str)], scale: &str) {
    let at = period_one_doubling();
    let near: Vec<f64> = bifs.iter().filter(|b| b.1 == "branch-point" && (b.0 - at).abs() <= 1e-3).map(|b| b.0).collect();
    eprintln!("scale {scale}: branch points {near:?}, the transcription's {at}");
    assert!(near.len() == 1 && (near[0] - at).abs() <= 1e-10, "scale {scale}: branch points near the transcription's period-1 period doubling {at}: {near:?}");
}

/// The transcribed one-period map (`cascade.rs`'s closed-form flow of
/// `x'' + 0.1 x' + x = cos Ωt`, sampled at 1/4000 of a period, each
/// crossing of the stop 0.2 bisected to round-off, the speed reversed
/// times 0.3) and its Jacobian: the free flow's transition over each
/// flight (the flow is affine in the state: its columns are images of the
/// unit states less the image of 0, exactly) and at each impact the
/// saltation `[[−e, 0], [(a⁺ + e a⁻)/v⁻, −e]]` (`a±` the accelerations
/// just before and after, `v⁻` the speed), derived by hand.
fn period_one_map(w: f64, x: [f64; 2]) -> ([f64; 2], [[f64; 2]; 2]) {
    use crate::cascade::flow;
    const ZETA: f64 = 0.05;
    let (gap, e) = (0.2, 0.3);
    let end = std::f64::consts::TAU / w;
    let h = end / 4000.0;
    let mul = |a: [[f64; 2]; 2], b: [[f64; 2]; 2]| {
        [[a[0][0] * b[0][0] + a[0][1] * b[1][0], a[0][0] * b[0][1] + a[0][1] * b[1][1]], [a[1][0] * b[0][0] + a[1][1] * b[1][0], a[1][0] * b[0][1] + a[1][1] * b[1][1]]]
    };
    let transition = |t0: f64, t: f64| {
        let (z, c0, c1) = (flow(w, t0, 0.0, 0.0, t), flow(w, t0, 1.0, 0.0, t), flow(w, t0, 0.0, 1.0, t));
        [[c0.0 - z.0, c1.0 - z.0], [c0.1 - z.1, c1.1 - z.1]]
    };
    let (mut t0, mut z, mut t, mut j) = (0.0, (x[0], x[1]), 0.0, [[1.0, 0.0], [0.0, 1.0]]);
    while t < end {
        let t1 = (t + h).min(end);
        if flow(w, t0, z.0, z.1, t1).0 > gap {
            let lo = crate::between::bisect(t, t1, |m| flow(w, t0, z.0, z.1, m).0 <= gap);
            let v = flow(w, t0, z.0, z.1, lo).1;
            let force = (w * lo).cos() - gap;
            let (before, after) = (force - 2.0 * ZETA * v, force + 2.0 * ZETA * e * v);
            j = mul([[-e, 0.0], [(after + e * before) / v, -e]], mul(transition(t0, lo), j));
            (t0, z, t) = (lo, (gap, -e * v), lo);
            continue;
        }
        t = t1;
    }
    let y = flow(w, t0, z.0, z.1, end);
    ([y.0, y.1], mul(transition(t0, end), j))
}

/// The transcription's period-1 orbit (Newton on [`period_one_map`] from
/// `x`) and `det(J + I)` there.
fn period_one_test(w: f64, mut x: [f64; 2]) -> ([f64; 2], f64) {
    for _ in 0..50 {
        let (y, j) = period_one_map(w, x);
        let (r, a) = ([y[0] - x[0], y[1] - x[1]], [[j[0][0] - 1.0, j[0][1]], [j[1][0], j[1][1] - 1.0]]);
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        let dx = [(a[1][1] * r[0] - a[0][1] * r[1]) / det, (-a[1][0] * r[0] + a[0][0] * r[1]) / det];
        x = [x[0] - dx[0], x[1] - dx[1]];
        if dx[0].abs().max(dx[1].abs()) <= 1e-13 {
            break;
        }
    }
    let (y, j) = period_one_map(w, x);
    assert!((y[0] - x[0]).abs().max((y[1] - x[1]).abs()) <= 1e-13, "Ω = {w}: no period-1 orbit from the seed");
    // The hand-derived Jacobian against central differences of the map.
    let d = crate::between::differences(x, 1e-6, |z| period_one_map(w, z).0);
    assert!((0..2).all(|r| (0..2).all(|c| (d[r][c] - j[r][c]).abs() <= 1e-6 * (1.0 + j[r][c].abs()))), "Ω = {w}: J {j:?}, differences {d:?}");
    (x, (j[0][0] + 1.0) * (j[1][1] + 1.0) - j[0][1] * j[1][0])
}

/// The zero of [`period_one_test`]'s `det(J + I)` in Ω near 2.2624
/// (the orbit seeded at (−0.44, 0.06)), by secant steps to 1e-14, the
/// sign change across it asserted.
fn period_one_doubling() -> f64 {
    let (mut l0, (mut x, mut f0)) = (2.26, period_one_test(2.26, [-0.44, 0.06]));
    let (mut l1, mut f1) = (2.265, period_one_test(2.265, x).1);
    assert!(f0 * f1 < 0.0, "det(J + I) keeps its sign: {f0} at {l0}, {f1} at {l1}");
    for _ in 0..50 {
        let next = l1 - f1 * (l1 - l0) / (f1 - f0);
        let (y, f) = period_one_test(next, x);
        (l0, f0, l1, f1, x) = (l1, f1, next, f, y);
        if (l1 - l0).abs() <= 1e-14 || f == 0.0 {
            break;
        }
    }
    l1
}

fn rows(csv: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = csv.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    (head, lines.map(|l| l.split(',').map(String::from).collect()).collect())
}

#[test]
fn a_period_two_branch_does_not_go_back_along_an_arc_it_traced() {
    let doc = crate::oscillator(0.05, 0.2, 0.3, 2.42);
    let opts = ContinueOptions { param: "forcing.omega".into(), from: 2.42, to: 2.2, period: 2, transient: 100.0, max_points: 400, switch: false, sweep: Vec::new(), param_scale: None };
    let done = continue_scene(doc, &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true).unwrap();
    for l in &done.lines {
        eprintln!("{l}");
    }
    let file = |n: &str| &done.files.iter().find(|f| f.0 == n).unwrap().1;
    let (head, pts) = rows(file("branch.csv"));
    let col = |n: &str| head.iter().position(|h| h == n).unwrap();
    let num = |r: &Vec<String>, n: &str| r[col(n)].parse::<f64>().unwrap();
    let pts: Vec<(f64, [f64; 2], usize, bool, f64)> =
        pts.iter().map(|r| (num(r, "param"), [num(r, "q0"), num(r, "v0")], r[col("impacts_per_period")].parse().unwrap(), r[col("stable")] == "1", num(r, "mu_max"))).collect();
    let fam = SceneFamily::new(crate::oscillator(0.05, 0.2, 0.3, 2.42), "forcing.omega", 2).unwrap().0;
    let (mut fixed, mut settled) = (0.0f64, 0.0f64);
    for (w, x, k, stable, mu) in &pts {
        let (m, t) = (fam.model(*w).unwrap(), fam.period(*w).unwrap());
        let img = m.flow(0.0, x, t, false).unwrap();
        // The slow impact's orbits (|μ| up to 2e5) amplify the round-off.
        let d = img.x.iter().zip(x).fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
        assert!(d <= 1e-12 * mu.max(1.0) + 1e-10, "Ω = {w} ({k} impacts, |μ| {mu}): |P(x) − x| = {d:e}");
        fixed = fixed.max(d);
        if *stable && *mu < 0.9 {
            let mut y = vec![x[0] + 1e-6, x[1] - 1e-6];
            for _ in 0..400 {
                y = m.flow(0.0, &y, t, false).unwrap().x;
            }
            let d = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
            assert!(d <= 1e-8, "Ω = {w}: a run from the nudged orbit ends {d:e} from it");
            settled = settled.max(d);
        }
    }
    eprintln!("{} points: fixed to {fixed:e}, stable ones attract to {settled:e}", pts.len());
    // No point on an arc already traced: on no earlier step with as many
    // impacts and bracketing its parameter, within 1e-6 of the step's chord.
    for (j, (w, x, k, _, _)) in pts.iter().enumerate() {
        for i in 0..j.saturating_sub(2) {
            let (a, b) = (&pts[i], &pts[i + 1]);
            if a.2 != *k || b.2 != *k || (w - a.0) * (w - b.0) > 0.0 || a.0 == b.0 {
                continue;
            }
            let f = (w - a.0) / (b.0 - a.0);
            let d = (0..2).fold(0.0f64, |m, c| m.max((a.1[c] + f * (b.1[c] - a.1[c]) - x[c]).abs()));
            assert!(d > 1e-6 * (b.1[0] - a.1[0]).abs().max(1e-3), "point {j} (Ω = {w}, {k} impacts) lies on the step {i}–{} it traced before ({d:e})", i + 1);
        }
    }
    // Each bifurcation once.
    let (bh, bifs) = rows(file("bifurcations.csv"));
    let (cp, ck) = (bh.iter().position(|h| h == "param").unwrap(), bh.iter().position(|h| h == "kind").unwrap());
    let bifs: Vec<(f64, &str)> = bifs.iter().map(|r| (r[cp].parse().unwrap(), r[ck].as_str())).collect();
    for (i, a) in bifs.iter().enumerate() {
        for b in &bifs[i + 1..] {
            assert!(a.1 != b.1 || (a.0 - b.0).abs() > 1e-6, "{} listed twice: at {} and {}", a.1, a.0, b.0);
        }
    }
    // Against an independent transcription (a scratch program sharing no
    // code with the crate: the closed-form flow of x'' + 0.1x' + x = cos Ωt
    // between impacts, impacts by bisection on it, the 2-period orbits
    // solved as impact times and speeds by Newton on central differences,
    // parametrised by the first impact's speed through the fold): the
    // 2-impact orbits' period doubling (`det(P' + I)` of the transcribed
    // map's central differences changing sign), fold (`det(P' − I)`
    // changing sign, and the largest Ω of the family: both 2.4349363812961)
    // and the grazing where their flight reaches the stop (bisection on its
    // largest interior maximum), each listed once, to 1e-9.
    // The period doublings beside the 3- and 4-impact folds too (crossed
    // with their folds in one step, not listed before).
    for (kind, at) in [("period-doubling", PD), ("fold", FOLD), ("grazing", GRAZING), ("period-doubling", PD_3), ("period-doubling", PD_4)] {
        let near: Vec<f64> = bifs.iter().filter(|b| b.1 == kind && (b.0 - at).abs() <= 1e-5).map(|b| b.0).collect();
        assert!(near.len() == 1 && (near[0] - at).abs() <= 1e-9, "{kind}s near the transcription's {at}: {near:?}");
    }
    branch_point(&bifs, "of the range");
    // The 4-impact arc reached, and the end says why the branch stops:
    // past the two turns back (the vanishing impact, the 2-impact orbits'
    // end grazing) it runs the 2-impact arc through its period doubling
    // and fold down to where it returns onto itself.
    assert!(pts.iter().any(|p| p.2 == 4), "the 4-impact orbits past the grazing at 2.3835123");
    assert!(done.lines[0].contains("returned onto itself") || done.lines[0].contains("closed:"), "{}", done.lines[0]);
}

/// The crate's own map (`Model::flow` over two forcing periods) has the
/// transcription's orbits at the grazing at 2.380653 that the branch lists:
/// there the 4-impact orbit's third impact still hits at 9.5e-6 (it
/// vanishes at 2.3806475600435, 5.9e-6 below), and 1e-5 above the
/// vanishing point the 3-impact orbit that the branch should turn back
/// onto is a fixed point with its three impacts, where the branch jumps
/// instead onto a 2-impact orbit 0.23 away in the state (at 2.382314).
/// Each state is the transcription's, to 16 digits.
#[test]
fn the_orbits_at_the_vanishing_impact_are_fixed_points_of_the_crates_map() {
    let fam = SceneFamily::new(crate::oscillator(0.05, 0.2, 0.3, 2.42), "forcing.omega", 2).unwrap().0;
    for (w, x, impacts) in [
        (2.380653424790, [0.16568371487317332, 0.19441138782330053], 4),
        (VANISHING + 1e-4, [0.16568657015032562, 0.19440204952901832], 4),
        (VANISHING + 1e-5, [0.16567780141551994, 0.1944066641126845], 3),
    ] {
        let (m, t) = (fam.model(w).unwrap(), fam.period(w).unwrap());
        let img = m.flow(0.0, &x, t, false).unwrap();
        let d = img.x.iter().zip(&x).fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
        let k = img.events.iter().filter(|e| e.kind == signorini_schemes::events::EventKind::Impact && e.velocity_before != 0.0).count();
        eprintln!("Ω = {w}: |P(x) − x| = {d:e}, {k} impacts");
        // |μ| up to 1.5e4 at 2.380653: the transcription's round-off grows.
        assert!(d <= 1e-8 && k == impacts, "Ω = {w}: |P(x) − x| = {d:e}, {k} impacts (want {impacts})");
    }
}

/// At the 4-impact orbits' vanishing impact (the transcription's) the
/// branch turns back onto the unstable 3-impact orbits, which fold at
/// 2.3927017995113 and end at the grazing at 2.3678525327577 where the
/// 2-impact orbits begin (the new impact's speed → 0 there: the same Ω to
/// 1e-13). With the rule before it listed the grazing 5.9e-6 off, at
/// 2.380653424790, and jumped onto the 2-impact orbits at 2.382314 (the
/// other end of that arc, 0.23 away in the state), then ran them the
/// other way down to 2.3678525, the 3-impact arc not found.
#[test]
fn the_branch_turns_back_at_the_vanishing_impact_onto_the_three_impact_orbits() {
    let doc = crate::oscillator(0.05, 0.2, 0.3, 2.42);
    let opts = ContinueOptions { param: "forcing.omega".into(), from: 2.42, to: 2.2, period: 2, transient: 100.0, max_points: 400, switch: false, sweep: Vec::new(), param_scale: None };
    let done = continue_scene(doc, &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true).unwrap();
    let (bh, bifs) = rows(&done.files.iter().find(|f| f.0 == "bifurcations.csv").unwrap().1);
    let (cp, ck) = (bh.iter().position(|h| h == "param").unwrap(), bh.iter().position(|h| h == "kind").unwrap());
    let bifs: Vec<(f64, &str)> = bifs.iter().map(|r| (r[cp].parse().unwrap(), r[ck].as_str())).collect();
    for (kind, at) in [("grazing", VANISHING), ("fold", FOLD_3)] {
        let near: Vec<f64> = bifs.iter().filter(|b| b.1 == kind && (b.0 - at).abs() <= 1e-4).map(|b| b.0).collect();
        assert!(near.len() == 1 && (near[0] - at).abs() <= 1e-9, "{kind}s near the transcription's {at}: {near:?}");
    }
}

/// The same branch with the parameter's scale 0.05 and 0.01 (steps and
/// searches as fractions of it). With 0.05 its 4-impact arc went down
/// from its fold at 2.386056 to 2.38496, where a trial fell onto the
/// 2-impact orbits the branch began with (0.02 away, scaled), a grazing
/// 4 → 2 was listed at 2.3847259 where there is none, and the branch
/// ended there, "returned onto itself"; the trial is now halved as one
/// fallen onto another arc, and the branch turns back at the
/// transcription's vanishing impact and lists the 3-impact orbits' fold,
/// each once, to 1e-9. With 0.01, past the 3-impact fold at 2.4010173,
/// its orbit at 2.4004090 was taken for one of the arc traced before the
/// fold (3.6e-3 from it, scaled, where a quarter of a step is 5.9e-3) and
/// the branch ended there; now the corrector from that arc is asked to
/// land on the orbit, and the branch goes on to the 4-impact orbits, every
/// point a fixed point of the 2-period map. With 0.05, down the 3-impact
/// arc, a trial of 1.6e-2 from the orbit at 2.3728416 landed on the
/// 2-impact arc (1.3e-2 away, scaled) and was taken as an ordinary step, a
/// 3 → 2 grazing listed at 2.372073 where there is none; a step that
/// changes the impacts is now taken only where the two arcs meet at a
/// corner, and the branch lists the transcription's end grazing, period
/// doubling and fold of the 2-impact orbits, each once.
#[test]
fn a_period_two_branch_at_a_small_parameter_scale_goes_on_past_its_turns() {
    let fam = SceneFamily::new(crate::oscillator(0.05, 0.2, 0.3, 2.42), "forcing.omega", 2).unwrap().0;
    for scale in [0.05, 0.01] {
        let doc = crate::oscillator(0.05, 0.2, 0.3, 2.42);
        let opts = ContinueOptions { param: "forcing.omega".into(), from: 2.42, to: 2.2, period: 2, transient: 100.0, max_points: 400, switch: false, sweep: Vec::new(), param_scale: Some(scale) };
        let done = continue_scene(doc, &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true).unwrap();
        eprintln!("scale {scale}: {}", done.lines[0]);
        let file = |n: &str| &done.files.iter().find(|f| f.0 == n).unwrap().1;
        let (head, pts) = rows(file("branch.csv"));
        let col = |n: &str| head.iter().position(|h| h == n).unwrap();
        let num = |r: &Vec<String>, n: &str| r[col(n)].parse::<f64>().unwrap();
        for r in &pts {
            let (w, x, mu) = (num(r, "param"), [num(r, "q0"), num(r, "v0")], num(r, "mu_max"));
            let img = fam.model(w).unwrap().flow(0.0, &x, fam.period(w).unwrap(), false).unwrap();
            let d = img.x.iter().zip(&x).fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
            assert!(d <= 1e-12 * mu.max(1.0) + 1e-10, "scale {scale}, Ω = {w}: |P(x) − x| = {d:e}");
        }
        assert!(pts.iter().any(|r| r[col("impacts_per_period")] == "4"), "scale {scale}: no 4-impact orbit: {}", done.lines[0]);
        let (bh, bifs) = rows(file("bifurcations.csv"));
        let (cp, ck) = (bh.iter().position(|h| h == "param").unwrap(), bh.iter().position(|h| h == "kind").unwrap());
        // Each grazing once: with 0.01 the 4 → 3 one near 2.38354 was
        // listed three times (2.383542481165 twice, 2.383556130322), each
        // by a trial taken as a corner and then halved as one fallen onto
        // another arc, its grazing left listed.
        let grazings: Vec<f64> = bifs.iter().filter(|b| b[ck] == "grazing").map(|b| b[cp].parse().unwrap()).collect();
        for (i, a) in grazings.iter().enumerate() {
            assert!(grazings[i + 1..].iter().all(|b| (a - b).abs() > 1e-4), "scale {scale}: grazings listed twice: {grazings:?}");
        }
        // With 0.01 a trial up the 4-impact arc from 2.3855371 landed off
        // it at 2.3858515 (its chord turned from the tangent: cosine 0.83)
        // and was taken; a 4 → 3 grazing was listed there, where the
        // transcription's orbit of the arc keeps its 4 impacts (the
        // slowest at 5.1e-3), and the branch ended (162 points). Now it
        // passes the 4-impact fold and lists the period doubling past it.
        if scale == 0.01 {
            let cb = bh.iter().position(|h| h == "impacts_before").unwrap();
            let up: Vec<f64> = bifs.iter().filter(|b| b[ck] == "grazing" && b[cb] == "4").map(|b| b[cp].parse().unwrap()).filter(|w| *w > 2.3835124 && *w < 2.3860561).collect();
            assert!(up.is_empty(), "scale {scale}: grazings listed on the 4-impact arc below its fold: {up:?}");
            let near: Vec<f64> = bifs.iter().filter(|b| b[ck] == "period-doubling" && (b[cp].parse::<f64>().unwrap() - PD_4).abs() <= 1e-4).map(|b| b[cp].parse().unwrap()).collect();
            assert!(near.len() == 1 && (near[0] - PD_4).abs() <= 1e-9, "scale {scale}: period doublings near the transcription's {PD_4}: {near:?}");
        }
        if scale == 0.05 {
            for (kind, at) in [("grazing", VANISHING), ("fold", FOLD_3), ("period-doubling", PD_3), ("grazing", GRAZING), ("period-doubling", PD), ("fold", FOLD)] {
                let near: Vec<f64> = bifs.iter().filter(|b| b[ck] == kind && (b[cp].parse::<f64>().unwrap() - at).abs() <= 1e-4).map(|b| b[cp].parse().unwrap()).collect();
                assert!(near.len() == 1 && (near[0] - at).abs() <= 1e-9, "scale {scale}: {kind}s near the transcription's {at}: {near:?}");
            }
            // The 3-impact orbits run from the vanishing impact through
            // their fold down to the 2-impact orbits' end grazing with no
            // change of impacts: no grazing listed between (one was, at
            // 2.372073, where a trial landed on the 2-impact arc).
            let inside: Vec<f64> = bifs.iter().filter(|b| b[ck] == "grazing").map(|b| b[cp].parse().unwrap()).filter(|w| *w > GRAZING + 1e-6 && *w < VANISHING - 1e-6).collect();
            assert!(inside.is_empty(), "scale {scale}: grazings listed on the 3-impact arc: {inside:?}");
            let bifs: Vec<(f64, &str)> = bifs.iter().map(|b| (b[cp].parse().unwrap(), b[ck].as_str())).collect();
            branch_point(&bifs, "0.05");
        }
    }
}

/// With the parameter's scale 1 the branch crossed the 3-impact fold and
/// the period doubling 1.3e-5 past it in one step (from 2.3925294, μ
/// 8.18 and 5.3e-5, to 2.3926706, μ −2.05 and −2.1e-4: the multiplier
/// through +1, 0 and −1), and the 4-impact fold and the period doubling
/// 1.8e-7 past it likewise. The period-doubling test followed the real
/// negative multiplier nearest −1, at the step's end the small one (0.9998
/// from −1, the crossing one 1.05): it kept its sign and neither period
/// doubling was listed (nor by the default scale). `det(P' + I)` changes
/// sign (9.18 → −1.05): each is listed once, at the transcription's
/// multiplier through −1 to 1e-9, beside its fold (the transcription's,
/// to 1e-9).
#[test]
fn the_period_doublings_beside_the_folds_are_listed_at_scale_one() {
    let doc = crate::oscillator(0.05, 0.2, 0.3, 2.42);
    let opts = ContinueOptions { param: "forcing.omega".into(), from: 2.42, to: 2.2, period: 2, transient: 100.0, max_points: 400, switch: false, sweep: Vec::new(), param_scale: Some(1.0) };
    let done = continue_scene(doc, &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true).unwrap();
    let (bh, bifs) = rows(&done.files.iter().find(|f| f.0 == "bifurcations.csv").unwrap().1);
    let (cp, ck) = (bh.iter().position(|h| h == "param").unwrap(), bh.iter().position(|h| h == "kind").unwrap());
    let bifs: Vec<(f64, &str)> = bifs.iter().map(|r| (r[cp].parse().unwrap(), r[ck].as_str())).collect();
    for (kind, at) in [("period-doubling", PD_3), ("fold", FOLD_3), ("period-doubling", PD_4), ("period-doubling", PD), ("fold", FOLD)] {
        let near: Vec<f64> = bifs.iter().filter(|b| b.1 == kind && (b.0 - at).abs() <= 1e-5).map(|b| b.0).collect();
        assert!(near.len() == 1 && (near[0] - at).abs() <= 1e-9, "scale 1: {kind}s near the transcription's {at}: {near:?} (all: {bifs:?})");
    }
    branch_point(&bifs, "1");
}
