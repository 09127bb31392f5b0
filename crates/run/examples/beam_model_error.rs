//! Why the massless-tip reduction does not reach the full beam model's
//! accuracy on figure 2 (docs/theory.md §2.5; README "The accuracy–cost
//! frontier"). Prints, against the full model at J = 152, dt = 5e-7 s:
//!
//! 1. how far the tip trajectory converges in dt at all (J = 19 and 152,
//!    dt = 4e-6 … 5e-7 s against the finest): windows [0, t] for t up to 1 s;
//! 2. the model error of the massless tip with every interior mode kept
//!    (no truncation, dt = 1e-6 s) for J = 19, 38, 76: the tip row of the
//!    consistent mass dropped as the method does, and with that row's
//!    translational mass moved to the neighbouring node (a redistribution,
//!    not in the library);
//! 3. the truncation r = 4, 8, 16 on top of the redistributed model.
//!
//! `cargo run -p signorini-run --release --example beam_model_error` (about a minute)

use signorini_reduce::Keep;
use signorini_run::beam::{BeamScene, BeamSetup, Pipe};
use signorini_run::{run, History, RunConfig};
use signorini_schemes::{PaoliSchatzman, Stepper};

/// Tip history `(t, u)` of the beam on `j` elements: the full model
/// (`massless = None`), or the massless-tip model reduced to `keep` with the
/// tip's translational mass dropped (`Some(false)`) or moved to the
/// neighbouring node (`Some(true)`).
fn tip(j: usize, dt: f64, t_end: f64, massless: Option<bool>, keep: Keep) -> Vec<(f64, f64)> {
    let sc = BeamScene::new("x", j, dt, t_end, signorini_schemes::SchemeSpec::ps(0.0, 0.5));
    let (beam, mut dy, init) = BeamSetup::new(Pipe::paper(), sc).problem().unwrap();
    let b = beam.tip_dof();
    let (mut s, u0, dof): (Box<dyn Stepper>, Vec<f64>, usize) = match massless {
        None => (Box::new(PaoliSchatzman::new("ps".into(), dy, 0.5, 0.0, dt, &init).unwrap()), init.u.clone(), b),
        Some(redistribute) => {
            let moved = dy.mass.get(b, b) + 2.0 * dy.mass.get(b, b - 2);
            dy.mass.zero_row_col(b);
            if redistribute {
                dy.mass.add(b - 2, b - 2, moved);
            }
            let red = signorini_run::reduced::reduce(&dy, &init, keep).unwrap();
            (Box::new(PaoliSchatzman::new("ps".into(), red.dynamics.clone(), 0.5, 0.0, dt, &red.initial).unwrap()), red.initial.u.clone(), 0)
        }
    };
    let mut h = History::new(dof, false);
    run(s.as_mut(), &u0, &RunConfig::new(dt, t_end).unwrap(), &mut [&mut h]).unwrap();
    h.records.iter().map(|r| (r.t, r.u_contact)).collect()
}

fn at(h: &[(f64, f64)], t: f64) -> f64 {
    let i = h.partition_point(|r| r.0 < t).clamp(1, h.len() - 1);
    let (a, b) = (h[i - 1], h[i]);
    a.1 + (b.1 - a.1) * (t - a.0) / (b.0 - a.0)
}

/// Largest difference over `[0, t_max]`, sampled every 1e-5 s.
fn err(h: &[(f64, f64)], r: &[(f64, f64)], t_max: f64) -> f64 {
    (0..=(t_max / 1e-5).round() as usize).fold(0.0_f64, |e, k| e.max((at(h, k as f64 * 1e-5) - at(r, k as f64 * 1e-5)).abs()))
}

fn main() {
    let all = Keep::Modes(usize::MAX);
    println!("1. dt-convergence of the full model's tip: largest difference from the finest step over [0, t]");
    let ws = [0.05, 0.09, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0];
    println!("| J | dt (s) | {} |", ws.map(|t| format!("t = {t}")).join(" | "));
    println!("|---|---|{}", "---|".repeat(ws.len()));
    for j in [19usize, 152] {
        let dts = [4e-6, 2e-6, 1e-6, 5e-7];
        let hs: Vec<_> = dts.iter().map(|&dt| tip(j, dt, 1.0, None, all)).collect();
        for (dt, h) in dts.iter().zip(&hs).take(dts.len() - 1) {
            println!("| {j} | {dt:e} | {} |", ws.map(|t| format!("{:.1e}", err(h, &hs[3], t))).join(" | "));
        }
    }
    let t_end = 0.1;
    let reference = tip(152, 5e-7, t_end, None, all);
    let ws = [0.05, 0.08, 0.1];
    println!("\n2–3. against the full model at J = 152, dt = 5e-7 s: largest tip error over [0, t] (first impact at t = 0.0878 s)");
    println!("| J | model | r | {} |", ws.map(|t| format!("t = {t}")).join(" | "));
    println!("|---|---|---|{}", "---|".repeat(ws.len()));
    for j in [19usize, 38, 76] {
        let row = |name: &str, r: String, h: &[(f64, f64)]| println!("| {j} | {name} | {r} | {} |", ws.map(|t| format!("{:.1e}", err(h, &reference, t))).join(" | "));
        row("full (consistent mass)", "-".into(), &tip(j, 1e-6, t_end, None, all));
        let every = Keep::Modes(2 * j - 1);
        row("massless tip (the method)", format!("all ({})", 2 * j - 1), &tip(j, 1e-6, t_end, Some(false), every));
        row("massless tip, mass moved to the neighbour", format!("all ({})", 2 * j - 1), &tip(j, 1e-6, t_end, Some(true), every));
        for r in [4, 8, 16] {
            row("massless tip, mass moved to the neighbour", r.to_string(), &tip(j, 1e-6, t_end, Some(true), Keep::Modes(r)));
        }
    }
}
