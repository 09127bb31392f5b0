//! Period-doubled branches that return (bubbles). The impact oscillator
//! with its stop at the equilibrium (gap 0, ζ = 0.05, e = 0.8), from
//! Ω = 1.5 down to 0.95 with `--switch`: the period-1 orbits double their
//! period at 1.22974 and again at 1.03997, and the period-2 branch born at
//! the lower one returns onto them at the upper one; its own period
//! doublings (1.04785 and 1.19286) bound a period-4 bubble in the same way.
//! On its way up the period-2 branch's impact crosses the section's time
//! twice (the section state jumps by the impulse, `across_section`): the
//! search for phase-shifted copies read the jump as a stretch of the
//! branch, found the image of an orbit beside it and cut the branch there,
//! reporting the return "at its period doubling" at 1.2283582 — 1.4e-3
//! before it, where no multiplier is −1 (|μ|max 0.975). Checked against
//! the transcription of `cascade.rs` (its own flow, impact search and
//! restitution; the period doublings where `det(P_p' + I)` of its orbits
//! changes sign, bisected): each doubled branch starts beside one period
//! doubling of its parent and returns at the other; its orbits are fixed
//! points of the transcribed map over their period.

use crate::cascade::{map, pd_between, rows};
use signorini_orbits::front::{continue_scene, ContinueOptions};

const GAP: f64 = 0.0;

#[test]
fn a_doubled_branch_returns_at_the_other_period_doubling() {
    let doc = crate::oscillator(0.05, GAP, 0.8, 1.5);
    let opts = ContinueOptions { param: "forcing.omega".into(), from: 1.5, to: 0.95, period: 1, transient: 100.0, max_points: 400, switch: true, sweep: Vec::new(), param_scale: None };
    let done = continue_scene(doc, &opts, signorini_scene::Limits::machine(), None, &mut |_, _, _| true).unwrap();
    for l in &done.lines {
        eprintln!("{l}");
    }
    let file = |n: &str| &done.files.iter().find(|f| f.0 == n).unwrap().1;
    let (hb, pts) = rows(file("branch.csv"));
    let c = |n: &str| hb.iter().position(|h| h == n).unwrap();
    let num = |r: &Vec<String>, k: usize| r[k].parse::<f64>().unwrap();
    let (cp, cq, cv, cb, cper) = (c("param"), c("q0"), c("v0"), c("branch"), c("period"));
    let (hf, bifs) = rows(file("bifurcations.csv"));
    let f = |n: &str| hf.iter().position(|h| h == n).unwrap();
    for (child, parent) in [("1", "0"), ("2", "1")] {
        let on = |b: &'static str| pts.iter().filter(move |r| r[cb] == b);
        let periods: usize = on(parent).next().expect("the parent branch")[cper].parse().unwrap();
        // The child starts beside one of the parent's period doublings and
        // returns at another: each located on the transcription from the
        // parent's orbit listed nearest.
        let first = num(on(child).next().expect("the doubled branch"), cp);
        let line = done.lines.iter().find(|l| l.starts_with(&format!("branch {child} "))).unwrap();
        let at: f64 = line.split("at its period doubling at param = ").nth(1).unwrap_or_else(|| panic!("branch {child} does not return: {line}")).split(' ').next().unwrap().parse().unwrap();
        let listed: Vec<f64> = bifs.iter().filter(|r| r[f("branch")] == parent && r[f("kind")] == "period-doubling").map(|r| r[f("param")].parse().unwrap()).collect();
        let transcribed = |w: f64| {
            let pd = *listed.iter().min_by(|a, b| (*a - w).abs().total_cmp(&(*b - w).abs())).unwrap();
            let r = on(parent).min_by(|a, b| (num(a, cp) - pd).abs().total_cmp(&(num(b, cp) - pd).abs())).unwrap();
            pd_between(GAP, pd - 2e-4, pd + 2e-4, [num(r, cq), num(r, cv)], periods)
        };
        let (born, back) = (transcribed(first), transcribed(at));
        eprintln!("branch {child}: born beside {born}, returns at {at} (transcription {back}: {:e} off)", (at - back).abs());
        assert!((first - born).abs() <= 1e-3, "branch {child} starts at {first}, not beside a period doubling of branch {parent}");
        assert!((back - born).abs() > 1e-3, "branch {child} returns where it was born ({born})");
        assert!((at - back).abs() <= 1e-7, "branch {child} returns at {at}; branch {parent}'s period doubling is at {back}");
        // Its orbits: fixed points of the transcribed map over their period.
        for r in on(child).step_by(4) {
            let (w, x) = (num(r, cp), [num(r, cq), num(r, cv)]);
            let y = map(GAP, w, x, 2 * periods);
            let d = (y[0] - x[0]).abs().max((y[1] - x[1]).abs());
            assert!(d <= 1e-8, "branch {child} at Ω = {w}: |P(x) − x| = {d:e} on the transcription");
        }
    }
    // The period doubling at the grazing (1.0166) starts no branch: the
    // note says what its guesses came to (each converged onto the period-1
    // orbit or failed, the closest failure's residual), not a NaN residual
    // "after 0 iterations".
    let note = done.lines.iter().find(|l| l.starts_with("note: no period-doubled branch continued from 1.016")).expect("the grazing's period doubling");
    let count = |after: &str| -> usize {
        note.split(after).nth(1).and_then(|t| t.split(' ').next()).and_then(|t| t.trim_end_matches(',').parse().ok()).unwrap_or_else(|| panic!("no count after {after:?}: {note}"))
    };
    let (tried, back) = (count("of "), count("guesses, "));
    let failed = if back < tried { count(&format!("{back} converged onto the branch's own orbit of 1 period(s), ")) } else { 0 };
    assert!(tried > 0 && back + failed == tried && !note.contains("NaN"), "{note}");
}
