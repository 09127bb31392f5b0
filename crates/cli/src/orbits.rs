//! `signorini continue`: the branch of periodic orbits of a scene in one of
//! its numeric keys (signorini-orbits), written as `branch.csv`,
//! `bifurcations.csv` and `branch.svg`.

use crate::CliError;
use signorini_orbits::output::{bifurcations_csv, branch_csv, branch_svg, Labelled};
use signorini_orbits::{continuation, doubled_branch, BifurcationKind, Branch, ContinuationOptions, OrbitError, SceneFamily};
use signorini_scene::Limits;
use std::path::Path;

/// What `signorini continue` is asked.
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
    /// A sweep folder whose `sweep.csv` the plot draws under the branch.
    pub sweep: Option<std::path::PathBuf>,
}

fn opt(option: &'static str, message: String) -> CliError {
    CliError::Orbits(OrbitError::Option { option, message })
}

/// The sweep's stroboscopic samples `(param, displacement)` of `sweep.csv`.
fn sweep_points(dir: &Path) -> Result<Vec<(f64, f64)>, CliError> {
    let path = dir.join("sweep.csv");
    let text = std::fs::read_to_string(&path).map_err(|e| opt("sweep", format!("{}: {e} (a sweep folder holds sweep.csv)", path.display())))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let (Some(p), Some(d)) = (header.iter().position(|h| *h == "param"), header.iter().position(|h| *h == "displacement")) else {
        return Err(opt("sweep", format!("{}: no param and displacement columns", path.display())));
    };
    Ok(lines
        .filter_map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            Some((c.get(p)?.parse().ok()?, c.get(d)?.parse().ok()?))
        })
        .collect())
}

/// Runs `signorini continue` on the scene text `text` into `out`; returns
/// the lines to print.
pub fn continue_scene(text: &str, opts: &ContinueOptions, out: &Path, limits: Limits) -> Result<Vec<String>, CliError> {
    let started = std::time::Instant::now();
    let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| CliError::Scene(signorini_scene::SceneError::Toml(e)))?;
    // Parse the scene as such first: its own errors name its fields.
    signorini_scene::SceneFile::from_table(doc.clone())?;
    if !(opts.transient.is_finite() && opts.transient >= 0.0) {
        return Err(opt("transient", format!("{} is not allowed: forcing periods, finite and >= 0", opts.transient)));
    }
    let sweep = opts.sweep.as_deref().map(sweep_points).transpose()?.unwrap_or_default();
    let (family, _) = SceneFamily::with_limits(doc, &opts.param, opts.period, limits)?;
    let mut copts = ContinuationOptions::new(opts.from, opts.to);
    copts.max_points = opts.max_points;
    // The start: the scene's own initial state after the transient.
    let built = family.build(opts.from)?;
    let guess = if opts.transient > 0.0 { built.model.flow(0.0, &built.start, opts.transient * std::f64::consts::TAU / built.omega, false)?.x } else { built.start.clone() };
    let main = continuation(&family, &guess, &copts)?;
    let mut branches: Vec<(Branch, SceneFamily)> = vec![(main, family.clone())];
    let mut notes = Vec::new();
    if opts.switch {
        let doubled = family.with_periods(2 * opts.period);
        let pds: Vec<_> = branches[0].0.bifurcations.iter().filter(|b| b.kind == BifurcationKind::PeriodDoubling).cloned().collect();
        for b in pds {
            match doubled_branch(&family, &doubled, &b, (opts.from, opts.to), &copts) {
                Ok(br) => branches.push((br, doubled.clone())),
                Err(e) => notes.push(format!("note: no period-doubled branch continued from {}: {e}", b.param)),
            }
        }
    }
    let mut labelled = Vec::new();
    for (b, fam) in &branches {
        let (mut omega, mut disp, mut bd) = (Vec::new(), Vec::new(), Vec::new());
        for p in &b.points {
            let built = fam.build(p.param)?;
            omega.push(built.omega);
            disp.push(built.tip(&p.orbit.x)?);
        }
        for f in &b.bifurcations {
            bd.push(fam.build(f.param)?.tip(&f.x)?);
        }
        labelled.push(Labelled { branch: b, periods: fam.periods(), omega, displacement: disp, bif_displacement: bd });
    }
    std::fs::create_dir_all(out).map_err(|source| CliError::OutFolder { path: out.to_path_buf(), source })?;
    let write = |name: &str, body: &str| -> Result<(), CliError> {
        let path = out.join(name);
        std::fs::write(&path, body).map_err(|source| CliError::Write { path, source })
    };
    write("branch.csv", &branch_csv(&labelled, built.model.state_dofs()))?;
    write("bifurcations.csv", &bifurcations_csv(&labelled))?;
    match branch_svg(&labelled, &opts.param, &sweep) {
        Ok(svg) => write("branch.svg", &svg)?,
        Err(e) => notes.push(format!("note: branch.svg not written: {e}")),
    }
    let mut lines = Vec::new();
    for (i, (b, fam)) in branches.iter().enumerate() {
        let stable = b.points.iter().filter(|p| p.stable()).count();
        lines.push(format!(
            "branch {i} ({} forcing period{}): {} points from {} to {} ({stable} stable, {} unstable); {}",
            fam.periods(),
            if fam.periods() == 1 { "" } else { "s" },
            b.points.len(),
            b.points.first().map_or(f64::NAN, |p| p.param),
            b.points.last().map_or(f64::NAN, |p| p.param),
            b.points.len() - stable,
            b.end
        ));
        for f in &b.bifurcations {
            lines.push(format!("  {} at {} = {:.12} (multiplier {:.6}{:+.6}i; impacts per period {} -> {})", f.kind.name(), opts.param, f.param, f.mu.re, f.mu.im, f.impacts.0, f.impacts.1));
        }
    }
    lines.extend(notes);
    lines.push(format!("wrote branch.csv, bifurcations.csv, branch.svg to {} in {:.2} s", out.display(), started.elapsed().as_secs_f64()));
    Ok(lines)
}
