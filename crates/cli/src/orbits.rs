//! `signorini continue`: the branch of periodic orbits of a scene in one of
//! its numeric keys ([`signorini_orbits::front::continue_scene`]), written
//! as `branch.csv`, `bifurcations.csv` and `branch.svg`.

use crate::CliError;
use signorini_orbits::front::{continue_scene as compute, ContinueOptions};
use signorini_orbits::OrbitError;
use signorini_scene::Limits;
use std::path::Path;

fn opt(option: &'static str, message: String) -> CliError {
    CliError::Orbits(OrbitError::Option { option, message })
}

/// The sweep's stroboscopic samples `(param, displacement)` of `sweep.csv`.
pub fn sweep_points(dir: &Path) -> Result<Vec<(f64, f64)>, CliError> {
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
/// A progress line on stderr when `show_progress`; `interrupt` (SIGINT)
/// ends the branch at its last point, writes the files and returns
/// [`CliError::ContinueInterrupted`].
pub fn continue_scene(text: &str, opts: &ContinueOptions, out: &Path, limits: Limits, show_progress: bool, interrupt: Option<signorini_run::Cancel>) -> Result<Vec<String>, CliError> {
    let started = std::time::Instant::now();
    let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| CliError::Scene(signorini_scene::SceneError::Toml(e)))?;
    // Parse the scene as such first: its own errors name its fields.
    signorini_scene::SceneFile::from_table(doc.clone())?;
    let bar = crate::progress_spinner(show_progress);
    let mut watch = |branch: usize, points: usize, param: f64| {
        bar.set_message(format!("branch {branch}: {points} points, {} = {param:.9}", opts.param));
        bar.tick();
        !interrupt.as_ref().is_some_and(|c| c.is_cancelled())
    };
    let poll: Option<signorini_schemes::Interrupt> = interrupt.clone().map(|c| std::sync::Arc::new(move || c.is_cancelled()) as signorini_schemes::Interrupt);
    let done = match compute(doc, opts, limits, poll, &mut watch) {
        Err(OrbitError::Interrupted) => return Err(CliError::ContinueInterrupted { dir: format!("{} (nothing: interrupted before the first orbit)", out.display()) }),
        other => other?,
    };
    bar.finish_and_clear();
    std::fs::create_dir_all(out).map_err(|source| CliError::OutFolder { path: out.to_path_buf(), source })?;
    for (name, body) in &done.files {
        let path = out.join(name);
        std::fs::write(&path, body).map_err(|source| CliError::Write { path, source })?;
    }
    if done.interrupted {
        return Err(CliError::ContinueInterrupted { dir: out.display().to_string() });
    }
    let mut lines = done.lines;
    let names: Vec<&str> = done.files.iter().map(|f| f.0).collect();
    lines.push(format!("wrote {} to {} in {:.2} s", names.join(", "), out.display(), started.elapsed().as_secs_f64()));
    Ok(lines)
}

/// Runs `signorini modes` on the scene text `text` (an unforced `[bar]`
/// with `scheme = "event-driven"`): the backbone from energy `from` to `to`
/// in `points` energies, written as `backbone.csv` and `backbone.svg` in
/// `out`; returns the lines to print.
pub fn modes_scene(text: &str, from: f64, to: f64, points: usize, out: &Path) -> Result<Vec<String>, CliError> {
    let started = std::time::Instant::now();
    let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| CliError::Scene(signorini_scene::SceneError::Toml(e)))?;
    signorini_scene::SceneFile::from_table(doc.clone())?;
    let modes = signorini_orbits::modes::backbone(&doc, from, to, points)?;
    std::fs::create_dir_all(out).map_err(|source| CliError::OutFolder { path: out.to_path_buf(), source })?;
    let mut written = vec!["backbone.csv"];
    let path = out.join("backbone.csv");
    std::fs::write(&path, signorini_orbits::output::backbone_csv(&modes)).map_err(|source| CliError::Write { path, source })?;
    let mut lines = Vec::new();
    match signorini_orbits::output::backbone_svg(&modes) {
        Ok(svg) => {
            let path = out.join("backbone.svg");
            std::fs::write(&path, svg).map_err(|source| CliError::Write { path, source })?;
            written.push("backbone.svg");
        }
        Err(e) => lines.push(format!("note: backbone.svg not drawn: {e}")),
    }
    lines.insert(0, format!("{} of {points} energies on the backbone ({} elements)", modes.points.len(), modes.elements));
    if let Some((e, why)) = &modes.stopped {
        lines.push(format!("the family ended at energy {e}: {why}"));
    }
    lines.push(format!("wrote {} to {} in {:.2} s", written.join(", "), out.display(), started.elapsed().as_secs_f64()));
    Ok(lines)
}
