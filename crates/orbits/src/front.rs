//! One continuation as every front end runs it (`signorini continue`,
//! Python's `signorini.continuation`): the scene document in one key, the
//! start after a transient, the branch, the period-doubled branches, and
//! the files' text. No IO: the front ends read and write the files.

use crate::output::{bifurcations_csv, branch_csv, branch_svg, Labelled};
use crate::{continuation_watched, crossing_branch, doubled_branch, BifurcationKind, Branch, ContinuationOptions, OrbitError, SceneFamily};
use signorini_scene::Limits;

/// What a continuation is asked (the options of `signorini continue`).
#[derive(Clone, Debug)]
pub struct ContinueOptions {
    /// The parameter's dotted path (`forcing.omega`).
    pub param: String,
    /// From.
    pub from: f64,
    /// To.
    pub to: f64,
    /// Forcing periods per orbit.
    pub period: usize,
    /// Forcing periods run from the scene's initial state before Newton.
    pub transient: f64,
    /// Most points per branch.
    pub max_points: usize,
    /// Continue the period-doubled branch at each period doubling.
    pub switch: bool,
    /// A sweep's bifurcation diagram `(param, displacement)` drawn under the branch.
    pub sweep: Vec<(f64, f64)>,
    /// The parameter's scale for the steps and the searches' offsets
    /// ([`ContinuationOptions::scale`]); `None`: the range.
    pub param_scale: Option<f64>,
}

/// A continuation's result: its files (`branch.csv`, `bifurcations.csv`,
/// `branch.svg` when it could be drawn) and the lines a front end prints.
#[derive(Clone, Debug)]
pub struct Continued {
    /// `(file name, contents)`.
    pub files: Vec<(&'static str, String)>,
    /// What to print (one line per branch, one per bifurcation, notes).
    pub lines: Vec<String>,
    /// `watch` stopped the run: the files hold the points so far.
    pub interrupted: bool,
}

/// How many period doublings `--switch` follows in a cascade: from the
/// branch of p forcing periods to the doubled branches born on it, theirs,
/// and so on, down to orbits of `2^SWITCH_LEVELS p` periods. The period
/// doublings of those are listed and not followed, a note saying so.
pub const SWITCH_LEVELS: usize = 3;

/// The most branches `--switch` lists (the first included); a period
/// doubling or branch point met beyond is listed and not followed, a note
/// saying so.
pub const SWITCH_BRANCHES: usize = 24;

/// When Newton from the state after the transient finds no orbit of the
/// family's periods at `from` (the continuation failed at its start): that
/// error, saying what the transient settled on — the smallest number of
/// forcing periods (up to 8 times the family's) after which its state
/// returns to itself (to 1e-3 of its size: after the default 100 periods
/// the oscillator below was still 3e-4 of it from its 2-period orbit), or
/// none. `None` when the start
/// is not what failed (Newton converges from the guess: the failure came
/// later) or a flow fails. On the oscillator (`osc.toml`) at Ω = 1.1,
/// between the period doublings at 1.0648 and 1.1300, the period-1 orbit
/// is unstable and the transient settles on an orbit of 2 periods (3
/// impacts); Newton from it wandered (residual 0.73 after 40 iterations)
/// and the message said only that no orbit was near. (`--period 2` from
/// the same transient fails too, 3.3e-4 from that orbit: from 400 periods
/// it converges, hence the message's advice.)
fn unfound_start(family: &SceneFamily, built: &crate::Built, guess: &[f64], opts: &ContinueOptions, newton: &crate::Newton) -> Option<OrbitError> {
    let (model, p) = (&built.model, family.periods());
    let period = built.horizon;
    let Err(OrbitError::NoConvergence { residual, iterations, why }) = crate::periodic_orbit(model, 0.0, period, guess, newton) else { return None };
    let size = guess.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(newton.scale);
    let mut x = guess.to_vec();
    let mut returns = None;
    for k in 1..=8 {
        x = model.flow(0.0, &x, period, false).ok()?.x;
        let d = x.iter().zip(guess).fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
        if d <= 1e-3 * size {
            returns = Some((k * p, d));
            break;
        }
    }
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    let settled = match returns {
        Some((q, d)) if q != p => format!(
            "the transient settled on a motion that returns to itself after {q} forcing periods (to {d:.1e}), not {p} (continue it with --period {q}, with a longer --transient where Newton does not converge from {d:.1e} away); an orbit of {p} forcing period{} at {} = {}, if there is one, is unstable or not near it: start the range where it is stable",
            plural(p),
            opts.param,
            opts.from
        ),
        Some(_) => "the transient's state returns to itself after the period to 1e-3 of its size but Newton cannot refine it (an orbit at a grazing, or a sliding/held motion)".into(),
        None => format!(
            "after the {} forcing periods of the transient the state returns to itself after none of 1 … 8 times the orbit's {p} forcing period{} (to 1e-3 of its size): the motion has not settled (a longer --transient) or is not periodic",
            opts.transient,
            plural(p)
        ),
    };
    Some(OrbitError::NoConvergence { residual, iterations, why: format!("{why}; from the state after the {}-period transient: {settled}", opts.transient) })
}

fn opt(option: &'static str, message: String) -> OrbitError {
    OrbitError::Option { option, message }
}

/// Runs the continuation of `doc` (a scene document) with `opts`; `watch`
/// sees each point as it comes (`(branch, points so far, param)`) and
/// stops the run by returning `false` (the points so far are kept and
/// written: [`Continued::interrupted`]).
///
/// `interrupt` is polled inside every run of the flow too (a slow first
/// orbit): it ends the branch like `watch`, or, before the first point,
/// fails with [`OrbitError::Interrupted`].
pub fn continue_scene(
    doc: toml::Table,
    opts: &ContinueOptions,
    limits: Limits,
    interrupt: Option<signorini_schemes::Interrupt>,
    watch: &mut dyn FnMut(usize, usize, f64) -> bool,
) -> Result<Continued, OrbitError> {
    if !(opts.transient.is_finite() && opts.transient >= 0.0) {
        return Err(opt("transient", format!("{} is not allowed: forcing periods, finite and >= 0", opts.transient)));
    }
    let (family, _) = SceneFamily::with_limits(doc, &opts.param, opts.period, limits)?;
    let family = family.with_interrupt(interrupt);
    // Both ends of the range must be valid scenes (a branch that meets an
    // invalid one between them ends there, with the scene's error).
    if let Err(e) = family.build(opts.to) {
        return Err(match e {
            OrbitError::Scene(m) => OrbitError::Option { option: "to", message: format!("the scene at the end of the range is invalid: {m}") },
            other => other,
        });
    }
    let mut copts = ContinuationOptions::new(opts.from, opts.to);
    copts.max_points = opts.max_points;
    copts.scale = opts.param_scale;
    // The start: the scene's own initial state after the transient.
    let built = family.build(opts.from)?;
    let guess = if opts.transient > 0.0 { built.model.flow(0.0, &built.start, opts.transient * std::f64::consts::TAU / built.omega, false)?.x } else { built.start.clone() };
    let mut stopped = false;
    // An interrupt inside a flow ends the branch with `end` saying so.
    let main = {
        let mut count = 0;
        let mut w = |p: &crate::BranchPoint| {
            count += 1;
            let go = watch(0, count, p.param);
            stopped |= !go;
            go
        };
        match continuation_watched(&family, &guess, &copts, &mut w) {
            Ok(b) => b,
            Err(e @ OrbitError::NoConvergence { .. }) => return Err(unfound_start(&family, &built, &guess, opts, &copts.newton).unwrap_or(e)),
            Err(e) => return Err(e),
        }
    };
    stopped |= main.end.starts_with("interrupted");
    let mut branches: Vec<(Branch, SceneFamily)> = vec![(main, family.clone())];
    let mut notes = Vec::new();
    if opts.switch && !stopped {
        // Each branch in turn, the doubled ones as they come (a cascade:
        // p → 2p → 4p …, down to [`SWITCH_LEVELS`] doublings).
        let span = (opts.to - opts.from).abs();
        // The branch points switched at or met again, with the branch.
        let mut crossed: Vec<(f64, Vec<f64>, usize)> = Vec::new();
        let mut i = 0;
        while i < branches.len() && !stopped {
            let fam = branches[i].1.clone();
            let pds: Vec<_> = branches[i].0.bifurcations.iter().filter(|b| b.kind == BifurcationKind::PeriodDoubling).cloned().collect();
            let deepest = fam.periods() >= opts.period << SWITCH_LEVELS;
            if deepest {
                for b in &pds {
                    notes.push(format!(
                        "note: the period doubling of branch {i} ({} forcing periods) at {} is not followed: --switch follows {SWITCH_LEVELS} doublings, to orbits of {} forcing periods",
                        fam.periods(),
                        b.param,
                        opts.period << SWITCH_LEVELS
                    ));
                }
            }
            let doubled = fam.with_periods(2 * fam.periods());
            // A doubled branch that rejoins its branch at another period
            // doubling is the loop of orbits between the two: the branch
            // from that one is the same loop (its orbits or their
            // phase-shifted copies) and is not listed again.
            let nearest = |at: f64| pds.iter().map(|p| p.param).min_by(|a, b| (a - at).abs().total_cmp(&(b - at).abs())).filter(|p| (p - at).abs() <= 1e-2 * span);
            // This branch's doubled ones: from `first` on.
            let first = branches.len();
            let mut from_pd: Vec<f64> = Vec::new();
            for b in pds.iter().filter(|_| !deepest) {
                if branches.len() >= SWITCH_BRANCHES {
                    notes.push(format!("note: the period-doubled branch from {} (branch {i}) is not followed: --switch lists at most {SWITCH_BRANCHES} branches", b.param));
                    continue;
                }
                if stopped || !watch(branches.len(), 0, b.param) {
                    stopped = true;
                    break;
                }
                if let Some(k) = branches[first..].iter().position(|(br, _)| br.rejoins.and_then(nearest) == Some(b.param)) {
                    notes.push(format!("note: the period-doubled branch from {} is branch {}'s loop, which rejoins there: not continued again", b.param, first + k));
                    continue;
                }
                match doubled_branch(&fam, &doubled, b, (opts.from, opts.to), &copts) {
                    Ok(br) => {
                        // An earlier branch from the period doubling this one
                        // rejoins at is part of this loop: dropped.
                        if let Some(k) = br.rejoins.and_then(nearest).and_then(|back| from_pd.iter().position(|&f| f == back)) {
                            notes.push(format!("note: the period-doubled branch from {} is part of the loop of the branch from {}, which rejoins there: listed once", from_pd[k], b.param));
                            branches.remove(first + k);
                            from_pd.remove(k);
                        }
                        branches.push((br, doubled.clone()));
                        from_pd.push(b.param);
                    }
                    Err(e) => notes.push(format!("note: no period-doubled branch continued from {}: {e}", b.param)),
                }
            }
            // Its branch points: the branch crossing there, unless one
            // listed already starts or ends at it (the asymmetric branch
            // born at one pitchfork of a symmetric orbit that meets it
            // again at the other; the point where a crossing branch
            // rejoined the branch it crossed).
            let bps: Vec<_> = branches[i].0.bifurcations.iter().filter(|b| b.kind == BifurcationKind::BranchPoint).cloned().collect();
            for b in &bps {
                let scale = b.x.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
                if let Some(&(_, _, k)) = crossed.iter().find(|(p, x, _)| (p - b.param).abs() <= 1e-4 * span && x.iter().zip(&b.x).all(|(u, v)| (u - v).abs() <= 1e-2 * scale)) {
                    notes.push(format!("note: the branch crossing branch {i} at its branch point at {} is branch {k}, which starts or ends there: not continued again", b.param));
                    continue;
                }
                if branches.len() >= SWITCH_BRANCHES {
                    notes.push(format!("note: the branch crossing branch {i} at its branch point at {} is not followed: --switch lists at most {SWITCH_BRANCHES} branches", b.param));
                    continue;
                }
                if stopped || !watch(branches.len(), 0, b.param) {
                    stopped = true;
                    break;
                }
                match crossing_branch(&fam, &branches[i].0, b, (opts.from, opts.to), &copts) {
                    Ok(br) => {
                        let k = branches.len();
                        crossed.push((b.param, b.x.clone(), k));
                        if let Some(met) = br.rejoins.and_then(|at| br.bifurcations.iter().find(|f| f.kind == BifurcationKind::BranchPoint && f.param == at)) {
                            crossed.push((met.param, met.x.clone(), k));
                        }
                        branches.push((br, fam.clone()));
                    }
                    Err(e) => notes.push(format!("note: no branch continued from the branch point at {}: {e}", b.param)),
                }
            }
            i += 1;
        }
    }
    let mut labelled = Vec::new();
    for (b, fam) in &branches {
        let (mut omega, mut disp, mut bd) = (Vec::new(), Vec::new(), Vec::new());
        // Each point carries its Ω and tip (the scene built for its
        // model); only a point or bifurcation without one (a grazing
        // located by its distance to the stop) builds its scene here.
        for p in &b.points {
            let m = match p.mark {
                Some(m) => m,
                None => {
                    let built = fam.build(p.param)?;
                    crate::Mark { omega: built.omega, tip: built.tip(&p.orbit.x)? }
                }
            };
            omega.push(m.omega);
            disp.push(m.tip);
        }
        for f in &b.bifurcations {
            bd.push(match f.mark {
                Some(m) => m.tip,
                None => fam.build(f.param)?.tip(&f.x)?,
            });
        }
        labelled.push(Labelled { branch: b, periods: fam.periods(), omega, displacement: disp, bif_displacement: bd });
    }
    let mut files = vec![("branch.csv", branch_csv(&labelled, built.model.state_dofs())), ("bifurcations.csv", bifurcations_csv(&labelled))];
    match branch_svg(&labelled, &opts.param, &opts.sweep) {
        Ok(svg) => files.push(("branch.svg", svg)),
        Err(e) => notes.push(format!("note: branch.svg not drawn: {e}")),
    }
    let mut lines = Vec::new();
    for (i, (b, fam)) in branches.iter().enumerate() {
        let stable = b.points.iter().filter(|p| p.stable()).count();
        // Neutral orbits (every multiplier on the unit circle: an undamped
        // structure's orbit without impacts) are neither: counted apart,
        // as branch.svg draws them (said only when there are some).
        let neutral = b.points.iter().filter(|p| crate::output::neutral(p)).count();
        let neutral_text = if neutral > 0 { format!(", {neutral} neutral") } else { String::new() };
        lines.push(format!(
            "branch {i} ({} forcing period{}): {} points from {} to {} ({stable} stable, {} unstable{neutral_text}); {}",
            fam.periods(),
            if fam.periods() == 1 { "" } else { "s" },
            b.points.len(),
            b.points.first().map_or(f64::NAN, |p| p.param),
            b.points.last().map_or(f64::NAN, |p| p.param),
            b.points.len() - stable - neutral,
            b.end
        ));
        for f in &b.bifurcations {
            lines.push(format!("  {} at {} = {:.12} (multiplier {:.6}{:+.6}i; impacts per period {} -> {})", f.kind.name(), opts.param, f.param, f.mu.re, f.mu.im, f.impacts.0, f.impacts.1));
        }
    }
    lines.extend(notes);
    Ok(Continued { files, lines, interrupted: stopped })
}
