//! `signorini basins`: the basins of attraction of an event-driven scene
//! over a grid of initial states (signorini-orbits' [`Grid`], which also
//! gives the files' text and columns: `basins_csv`), written as
//! `basins.csv`, `basins.svg` and the manifest `basins.toml`; `--shard I/N`
//! runs one contiguous block of cells, and [`merge`] (`signorini merge`)
//! joins the shards into exactly the files of the unsharded grid.

use crate::CliError;
use signorini_orbits::basins::{basins_svg, Axis, BasinOptions, Grid, GridOptions};
use signorini_orbits::OrbitError;
use signorini_run::Cancel;
use signorini_scene::Limits;
use std::io::Write as _;
use std::path::{Path, PathBuf};

pub use signorini_orbits::basins::BASIN_COLUMNS;

/// What `signorini basins` is asked.
#[derive(Clone, Debug)]
pub struct BasinsOptions {
    /// The displacement axis (`--x`, `--x-range`, the grid's first count).
    pub x: Axis,
    /// The velocity axis (`--v`, `--v-range`, the grid's second count).
    pub v: Axis,
    /// The classification's options.
    pub classify: BasinOptions,
    /// A continuation's `branch.csv`: the known orbits.
    pub orbits: Option<PathBuf>,
    /// `(I, N)`: run only block I of N.
    pub shard: Option<(usize, usize)>,
    /// Threads (default: rayon's).
    pub threads: Option<usize>,
    /// Checked between cells: whole rows are kept.
    pub interrupt: Option<Cancel>,
    /// Draw a progress bar on stderr.
    pub progress: bool,
}

fn opt(option: &'static str, message: String) -> CliError {
    CliError::Orbits(OrbitError::Option { option, message })
}

/// What a finished grid (or shard) did.
#[derive(Clone, Debug)]
pub struct BasinsReport {
    /// Lines for the terminal.
    pub lines: Vec<String>,
}

/// Runs `signorini basins` on the scene text `text` into `out`.
pub fn basins(text: &str, opts: &BasinsOptions, out: &Path, limits: Limits) -> Result<BasinsReport, CliError> {
    let started = std::time::Instant::now();
    let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| CliError::Scene(signorini_scene::SceneError::Toml(e)))?;
    signorini_scene::SceneFile::from_table(doc)?;
    let mut g = GridOptions::new(opts.x.clone(), opts.v.clone());
    g.classify = opts.classify.clone();
    g.shard = opts.shard;
    g.threads = opts.threads;
    g.validate()?;
    g.orbits = match &opts.orbits {
        Some(p) => Some(std::fs::read_to_string(p).map_err(|e| opt("orbits", format!("{}: {e} (a branch.csv of signorini continue)", p.display())))?),
        None => None,
    };
    let grid = Grid::new(text, g, limits)?;
    std::fs::create_dir_all(out).map_err(|source| CliError::OutFolder { path: out.to_path_buf(), source })?;
    let write = |name: &str, body: &str| -> Result<(), CliError> {
        let path = out.join(name);
        std::fs::write(&path, body).map_err(|source| CliError::Write { path, source })
    };
    write("basins.toml", &grid.manifest().text())?;
    let csv_path = out.join("basins.csv");
    let mut file = std::fs::File::create(&csv_path).map_err(|source| CliError::Write { path: csv_path.clone(), source })?;
    file.write_all(grid.header().as_bytes()).map_err(|source| CliError::Write { path: csv_path.clone(), source })?;
    let cells = grid.cells();
    let bar = crate::progress_bar(cells.len() as u64, opts.progress, "cells");
    let cancelled = || opts.interrupt.as_ref().is_some_and(Cancel::is_cancelled);
    // The rows go to the file batch by batch: an interrupt keeps them.
    let mut failed_write = None;
    let mut rows = |text: &str| match file.write_all(text.as_bytes()).and_then(|()| file.flush()) {
        Ok(()) => true,
        Err(e) => {
            failed_write = Some(e);
            false
        }
    };
    let b = grid.run(&|| bar.inc(1), &cancelled, &mut rows)?;
    if let Some(source) = failed_write {
        return Err(CliError::Write { path: csv_path, source });
    }
    bar.finish_and_clear();
    if !b.complete() {
        return Err(CliError::BasinsInterrupted { done: b.attractor.len(), total: cells.len(), dir: out.display().to_string() });
    }
    let mut lines = vec![b.summary(started.elapsed().as_secs_f64())];
    if opts.shard.is_none() {
        match basins_svg(&b) {
            Ok(svg) => write("basins.svg", &svg)?,
            Err(e) => lines.push(format!("note: basins.svg not written: {e}")),
        }
    }
    lines.push(format!("wrote {}", out.display()));
    Ok(BasinsReport { lines })
}

/// Is `dir` a shard folder of `signorini basins` (it holds `basins.toml`)?
pub fn is_basins_folder(dir: &Path) -> bool {
    dir.join("basins.toml").is_file()
}

/// Merges the shard folders of one grid into `out`
/// ([`signorini_orbits::basins::merge`]): `basins.csv` (the attractor ids
/// given again in cell order, as the unsharded grid gives them),
/// `basins.svg` and `basins.toml`, byte for byte the unsharded grid's
/// files. Refuses shards of different grids (ids), missing or repeated
/// shards, and incomplete ones.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<Vec<String>, CliError> {
    let merged = signorini_orbits::basins::merge(shards, &mut |p| std::fs::read_to_string(p).map_err(|e| e.to_string()))?;
    std::fs::create_dir_all(out).map_err(|source| CliError::OutFolder { path: out.to_path_buf(), source })?;
    for (name, body) in &merged.files {
        let path = out.join(name);
        std::fs::write(&path, body).map_err(|source| CliError::Write { path, source })?;
    }
    let mut lines = merged.lines;
    lines.push(format!("wrote {}", out.display()));
    Ok(lines)
}
