//! `signorini basins`: the basins of attraction of an event-driven scene
//! over a grid of initial states (signorini-orbits' `basins`), written as
//! `basins.csv`, `basins.svg` and the manifest `basins.toml`; `--shard I/N`
//! runs one contiguous block of cells, and [`merge`] (`signorini merge`)
//! joins the shards into exactly the files of the unsharded grid.
//!
//! `basins.csv` (a contract: columns only ever added) — one row per cell,
//! cells in the order `c = j·nx + i`:
//! `i,j,x,v,attractor,period,impacts_per_period,sticking,label`, then the
//! attractor's point on the section, `q<dof>` and `v<dof>` of each state
//! dof. `attractor` numbers the distinct periodic attractors in the order
//! the cells first reach them (empty for a non-periodic or failed cell);
//! `period` is in forcing periods (0: non-periodic); `impacts_per_period`
//! counts the impacts over one period of the orbit; `sticking` is 1 when
//! the orbit has a held phase; `label` is the known orbit matched
//! (`branch<B>:<N>` of `--orbits`), else `p<k>-i<n>[-sticking]`,
//! `non-periodic` or `failed`.

use crate::CliError;
use rayon::prelude::*;
use signorini_orbits::basins::{describe, match_known, parse_branch, Axis, BasinOptions, BasinScene, Grouper, KnownOrbit, Outcome};
use signorini_orbits::OrbitError;
use signorini_plot::{category_map, Category, Chart, Scale};
use signorini_run::Cancel;
use signorini_scene::Limits;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The columns of `basins.csv` before the state's.
pub const BASIN_COLUMNS: &str = "i,j,x,v,attractor,period,impacts_per_period,sticking,label";

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

fn cell(x: f64) -> String {
    format!("{x:.12e}")
}

/// FNV-1a (64 bit), as sweeps hash their ids.
fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The id of a grid: the scene text and every option that changes a number.
fn grid_id(text: &str, o: &BasinsOptions, orbits: &str) -> String {
    let c = &o.classify;
    let mut h = fnv1a(text.as_bytes(), 0xcbf2_9ce4_8422_2325);
    for a in [&o.x, &o.v] {
        h = fnv1a(format!("|{}|{:016x}|{:016x}|{}", a.path, a.from.to_bits(), a.to.to_bits(), a.count).as_bytes(), h);
    }
    h = fnv1a(format!("|{}|{}|{:016x}|{:016x}|", c.transient, c.max_period, c.tol.to_bits(), c.match_tol.to_bits()).as_bytes(), h);
    h = fnv1a(orbits.as_bytes(), h);
    format!("{h:016x}")
}

/// The cells of shard `(I, N)` of `total`: `[I·total/N, (I+1)·total/N)`.
fn block(total: usize, shard: Option<(usize, usize)>) -> std::ops::Range<usize> {
    match shard {
        None => 0..total,
        Some((i, n)) => (i * total / n)..((i + 1) * total / n),
    }
}

/// The manifest: what `merge` checks.
#[derive(Clone, Debug, PartialEq)]
struct Manifest {
    id: String,
    nx: usize,
    ny: usize,
    x: (f64, f64),
    v: (f64, f64),
    x_path: String,
    v_path: String,
    match_tol: f64,
    shard: Option<(usize, usize)>,
}

impl Manifest {
    fn text(&self) -> String {
        let mut t = toml::Table::new();
        t.insert("id".into(), self.id.clone().into());
        t.insert("x".into(), self.x_path.clone().into());
        t.insert("v".into(), self.v_path.clone().into());
        t.insert("grid".into(), toml::Value::Array(vec![(self.nx as i64).into(), (self.ny as i64).into()]));
        t.insert("x_range".into(), toml::Value::Array(vec![self.x.0.into(), self.x.1.into()]));
        t.insert("v_range".into(), toml::Value::Array(vec![self.v.0.into(), self.v.1.into()]));
        t.insert("match_tol".into(), self.match_tol.into());
        if let Some((i, n)) = self.shard {
            t.insert("shard".into(), toml::Value::Array(vec![(i as i64).into(), (n as i64).into()]));
            let b = block(self.nx * self.ny, self.shard);
            t.insert("cells".into(), toml::Value::Array(vec![(b.start as i64).into(), (b.end as i64).into()]));
        }
        format!("# signorini basins manifest: merge checks that shards share the id\n{}", toml::to_string(&t).unwrap_or_default())
    }

    fn read(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
        let t: toml::Table = text.parse().map_err(|e: toml::de::Error| e.to_string())?;
        let s = |k: &str| t.get(k).and_then(|v| v.as_str()).map(str::to_string).ok_or_else(|| format!("no {k}"));
        let pair = |k: &str| -> Result<(toml::Value, toml::Value), String> {
            match t.get(k).and_then(|v| v.as_array()) {
                Some(a) if a.len() == 2 => Ok((a[0].clone(), a[1].clone())),
                _ => Err(format!("no {k} = [a, b]")),
            }
        };
        let int = |v: &toml::Value| v.as_integer().and_then(|i| usize::try_from(i).ok()).ok_or("not an integer >= 0".to_string());
        let num = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)).ok_or("not a number".to_string());
        let (gx, gy) = pair("grid")?;
        let (x0, x1) = pair("x_range")?;
        let (v0, v1) = pair("v_range")?;
        let shard = match t.get("shard") {
            None => None,
            Some(_) => {
                let (i, n) = pair("shard")?;
                Some((int(&i)?, int(&n)?))
            }
        };
        Ok(Self {
            id: s("id")?,
            nx: int(&gx)?,
            ny: int(&gy)?,
            x: (num(&x0)?, num(&x1)?),
            v: (num(&v0)?, num(&v1)?),
            x_path: s("x")?,
            v_path: s("v")?,
            match_tol: t.get("match_tol").map(num).transpose()?.ok_or("no match_tol")?,
            shard,
        })
    }
}

/// A row of `basins.csv` before its attractor id: the cell's columns after
/// `attractor` and its period and section point as written (so grouping the
/// written rows again — a merge — gives the same ids).
struct Row {
    head: String,
    tail: String,
    period: usize,
    state: Vec<f64>,
}

fn row(s: &BasinScene, c: usize, outcome: &Outcome, known: &[KnownOrbit], match_tol: f64, width: usize) -> Row {
    let (i, j) = s.ij(c);
    let head = format!("{i},{j},{},{}", cell(s.x.value(i)), cell(s.v.value(j)));
    match outcome {
        Outcome::Attractor(a) => {
            let label = match_known(a, known, match_tol).map_or_else(|| describe(a), |o| o.label.clone());
            let mut tail = format!("{},{},{},{label}", a.period, a.impacts, u8::from(a.sticking));
            let text: Vec<String> = a.state.iter().map(|x| cell(*x)).collect();
            for t in &text {
                let _ = write!(tail, ",{t}");
            }
            let state = text.iter().map(|t| t.parse().unwrap_or(f64::NAN)).collect();
            Row { head, tail, period: a.period, state }
        }
        Outcome::Failed(_) => Row { head, tail: format!(",,,failed{}", ",".repeat(width)), period: 0, state: Vec::new() },
    }
}

fn id_cell(id: Option<usize>) -> String {
    id.map(|k| k.to_string()).unwrap_or_default()
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
    signorini_scene::SceneFile::from_table(doc.clone())?;
    opts.classify.validate()?;
    if let Some(0) = opts.threads {
        return Err(opt("threads", "0 is not allowed: an integer >= 1".into()));
    }
    let orbits_text = match &opts.orbits {
        Some(p) => std::fs::read_to_string(p).map_err(|e| opt("orbits", format!("{}: {e} (a branch.csv of signorini continue)", p.display())))?,
        None => String::new(),
    };
    let known = if opts.orbits.is_some() { parse_branch(&orbits_text)? } else { Vec::new() };
    let scene = BasinScene::new(doc, opts.x.clone(), opts.v.clone(), limits)?;
    let total = scene.cells();
    if let Some((i, n)) = opts.shard {
        if n == 0 || i >= n || n > total {
            return Err(opt("shard", format!("{i}/{n} is not allowed: I/N with 1 <= N <= {total} (the cells) and 0 <= I < N")));
        }
    }
    let dofs = scene.state_dofs()?;
    let manifest = Manifest {
        id: grid_id(text, opts, &orbits_text),
        nx: opts.x.count,
        ny: opts.v.count,
        x: (opts.x.from, opts.x.to),
        v: (opts.v.from, opts.v.to),
        x_path: opts.x.path.clone(),
        v_path: opts.v.path.clone(),
        match_tol: opts.classify.match_tol,
        shard: opts.shard,
    };
    std::fs::create_dir_all(out).map_err(|source| CliError::OutFolder { path: out.to_path_buf(), source })?;
    let write = |name: &str, body: &str| -> Result<(), CliError> {
        let path = out.join(name);
        std::fs::write(&path, body).map_err(|source| CliError::Write { path, source })
    };
    write("basins.toml", &manifest.text())?;
    let csv_path = out.join("basins.csv");
    let mut file = std::fs::File::create(&csv_path).map_err(|source| CliError::Write { path: csv_path.clone(), source })?;
    let header = header(&dofs);
    file.write_all(header.as_bytes()).map_err(|source| CliError::Write { path: csv_path.clone(), source })?;
    let cells = block(total, opts.shard);
    let bar = crate::progress_bar(cells.len() as u64, opts.progress, "cells");
    let pool = rayon::ThreadPoolBuilder::new().num_threads(opts.threads.unwrap_or(0)).build().map_err(|e| opt("threads", e.to_string()))?;
    let mut grouper = Grouper::new(opts.classify.match_tol);
    let mut done = cells.start;
    let mut failed = 0usize;
    let mut first_failure: Option<String> = None;
    let batch = 256usize;
    let cancelled = || opts.interrupt.as_ref().is_some_and(Cancel::is_cancelled);
    let mut map = MapData::default();
    while done < cells.end && !cancelled() {
        let end = (done + batch).min(cells.end);
        let outcomes: Vec<Option<Outcome>> = pool.install(|| {
            (done..end)
                .into_par_iter()
                .map(|c| {
                    if cancelled() {
                        return None;
                    }
                    let o = scene.classify(c, &opts.classify);
                    bar.inc(1);
                    Some(o)
                })
                .collect()
        });
        let mut text = String::new();
        for (k, o) in outcomes.iter().enumerate() {
            let Some(o) = o else { break };
            let r = row(&scene, done + k, o, &known, opts.classify.match_tol, 2 * dofs.len());
            let id = grouper.id(r.period, &r.state);
            if let Outcome::Failed(why) = o {
                failed += 1;
                first_failure.get_or_insert_with(|| format!("cell {} (i, j = {}, {}): {why}", done + k, r.head.split(',').next().unwrap_or(""), r.head.split(',').nth(1).unwrap_or("")));
            }
            map.push(id, r.tail.split(',').nth(3).unwrap_or(""));
            let _ = writeln!(text, "{},{},{}", r.head, id_cell(id), r.tail);
        }
        let written = outcomes.iter().take_while(|o| o.is_some()).count();
        file.write_all(text.as_bytes()).and_then(|()| file.flush()).map_err(|source| CliError::Write { path: csv_path.clone(), source })?;
        done += written;
        if written < outcomes.len() {
            break;
        }
    }
    bar.finish_and_clear();
    if done < cells.end {
        return Err(CliError::BasinsInterrupted { done: done - cells.start, total: cells.len(), dir: out.display().to_string() });
    }
    let mut lines = vec![format!(
        "{} cells in {:.3} s: {} attractor{} found{}",
        cells.len(),
        started.elapsed().as_secs_f64(),
        grouper.len(),
        if grouper.len() == 1 { "" } else { "s" },
        match &first_failure {
            Some(f) => format!(", {failed} cells failed (label failed; the first, {f})"),
            None => String::new(),
        }
    )];
    if opts.shard.is_none() {
        lines.extend(plot(out, &manifest, &map)?);
    }
    lines.push(format!("wrote {}", out.display()));
    Ok(BasinsReport { lines })
}

fn header(dofs: &[usize]) -> String {
    let mut h = String::from(BASIN_COLUMNS);
    for d in dofs {
        let _ = write!(h, ",q{d}");
    }
    for d in dofs {
        let _ = write!(h, ",v{d}");
    }
    h.push('\n');
    h
}

/// What the map needs of each cell: its attractor (`>= 0`), `-1` for a
/// non-periodic cell, `-2` for a failed one; each attractor's name (its
/// first cell's label).
#[derive(Default)]
struct MapData {
    cells: Vec<i64>,
    names: Vec<String>,
}

impl MapData {
    fn push(&mut self, id: Option<usize>, label: &str) {
        let k = match id {
            Some(k) => {
                if self.names.len() <= k {
                    self.names.resize(k + 1, String::new());
                }
                if self.names[k].is_empty() {
                    self.names[k] = format!("{k}: {label}");
                }
                k as i64
            }
            None if label == "failed" => -2,
            None => -1,
        };
        self.cells.push(k);
    }
}

/// `basins.svg`: each cell coloured by its attractor, grey for
/// non-periodic cells, black for failed ones; the legend names each
/// attractor by its first cell's label.
fn plot(out: &Path, m: &Manifest, map: &MapData) -> Result<Vec<String>, CliError> {
    let n_attr = map.names.len();
    let mut counts = vec![0usize; n_attr + 2];
    let mut cells = vec![vec![None; m.nx]; m.ny];
    for (c, &id) in map.cells.iter().enumerate() {
        let k = if id >= 0 {
            id as usize
        } else if id == -1 {
            n_attr
        } else {
            n_attr + 1
        };
        counts[k] += 1;
        cells[c / m.nx][c % m.nx] = Some(k);
    }
    let mut cats: Vec<Category> = map.names.iter().enumerate().map(|(k, name)| Category { name: format!("{name} ({} cells)", counts[k]), color: None }).collect();
    cats.push(Category { name: format!("non-periodic ({} cells)", counts[n_attr]), color: Some((190, 190, 190)) });
    cats.push(Category { name: format!("failed ({} cells)", counts[n_attr + 1]), color: Some((0, 0, 0)) });
    let title = "Basins of attraction";
    let chart = Chart { title, x_label: &m.x_path, y_label: &m.v_path, scale: Scale::Linear, size: (900, 700) };
    match category_map(&chart, m.x, m.v, &cells, &cats) {
        Ok(svg) => {
            let path = out.join("basins.svg");
            std::fs::write(&path, svg).map_err(|source| CliError::Write { path, source })?;
            Ok(Vec::new())
        }
        Err(e) => Ok(vec![format!("note: basins.svg not written: {e}")]),
    }
}

/// Is `dir` a shard folder of `signorini basins` (it holds `basins.toml`)?
pub fn is_basins_folder(dir: &Path) -> bool {
    dir.join("basins.toml").is_file()
}

/// Merges the shard folders of one grid into `out`: `basins.csv` (the
/// attractor ids given again in cell order, as the unsharded grid gives
/// them), `basins.svg` and `basins.toml`, byte for byte the unsharded
/// grid's files. Refuses shards of different grids (ids), missing or
/// repeated shards, and incomplete ones.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<Vec<String>, CliError> {
    let bad = |m: String| opt("merge", m);
    if shards.is_empty() {
        return Err(bad("give the shard folders".into()));
    }
    let mut found = Vec::new();
    for d in shards {
        let p = d.join("basins.toml");
        let m = Manifest::read(&p).map_err(|e| bad(format!("{} is not a basins shard folder ({}: {e}): give the folders `signorini basins --shard I/N` wrote", d.display(), p.display())))?;
        let (i, n) = m.shard.ok_or_else(|| bad(format!("{} is not a shard (no shard = [I, N] in its basins.toml)", d.display())))?;
        found.push((i, n, d.clone(), m));
    }
    found.sort_by_key(|f| f.0);
    let (id0, n0) = (found[0].3.id.clone(), found[0].1);
    for f in &found {
        if f.3.id != id0 {
            return Err(bad(format!("{} belongs to grid {}, {} to grid {id0}: shards of different grids are not merged", f.2.display(), f.3.id, found[0].2.display())));
        }
        if f.1 != n0 {
            return Err(bad(format!("{} is a shard of {} and {} of {n0}: not one sharding", f.2.display(), f.1, found[0].2.display())));
        }
    }
    for (k, f) in found.iter().enumerate() {
        if f.0 != k {
            let what = if k > 0 && found[k - 1].0 == f.0 { format!("shard {} is given twice", f.0) } else { format!("shard {k} of {n0} is missing") };
            return Err(bad(what));
        }
    }
    if found.len() != n0 {
        return Err(bad(format!("shard {} of {n0} is missing ({} given)", found.len(), found.len())));
    }
    let m0 = Manifest { shard: None, ..found[0].3.clone() };
    let total = m0.nx * m0.ny;
    let mut header: Option<String> = None;
    let mut rows: Vec<Vec<String>> = Vec::with_capacity(total);
    for f in &found {
        let path = f.2.join("basins.csv");
        let text = std::fs::read_to_string(&path).map_err(|e| bad(format!("{}: {e}", path.display())))?;
        let mut lines = text.split_inclusive('\n');
        let h = lines.next().unwrap_or("").to_string();
        if !h.starts_with(BASIN_COLUMNS) {
            return Err(bad(format!("{}: its first line is not the header of basins.csv: a damaged shard; run it again", path.display())));
        }
        if header.as_ref().is_some_and(|h0| *h0 != h) {
            return Err(bad(format!("{}: its header differs from the first shard's", path.display())));
        }
        header = Some(h);
        let expect = block(total, Some((f.0, n0)));
        let got: Vec<Vec<String>> = lines.filter(|l| l.ends_with('\n')).map(|l| l.trim_end().split(',').map(str::to_string).collect()).collect();
        if got.len() != expect.len() {
            return Err(bad(format!(
                "{}: expected {} rows (cells {}..{} of the manifest), found {}: finish the shard (run it again) before merging",
                path.display(),
                expect.len(),
                expect.start,
                expect.end,
                got.len()
            )));
        }
        rows.extend(got);
    }
    let header = header.unwrap_or_default();
    let state_at = BASIN_COLUMNS.split(',').count();
    let mut grouper = Grouper::new(m0.match_tol);
    let mut map = MapData::default();
    let mut text = header.clone();
    for r in &mut rows {
        let period: usize = r.get(5).and_then(|p| p.parse().ok()).unwrap_or(0);
        let state: Vec<f64> = r.iter().skip(state_at).map(|t| t.parse().unwrap_or(f64::NAN)).collect();
        let id = if r.get(8).is_some_and(|l| l == "failed") { None } else { grouper.id(period, &state) };
        if r.len() > 4 {
            r[4] = id_cell(id);
        }
        map.push(id, r.get(8).map_or("", String::as_str));
        text.push_str(&r.join(","));
        text.push('\n');
    }
    std::fs::create_dir_all(out).map_err(|source| CliError::OutFolder { path: out.to_path_buf(), source })?;
    let path = out.join("basins.csv");
    std::fs::write(&path, text).map_err(|source| CliError::Write { path, source })?;
    let path = out.join("basins.toml");
    std::fs::write(&path, m0.text()).map_err(|source| CliError::Write { path, source })?;
    let mut lines = vec![format!("merged {n0} shards of grid {id0}: {total} cells, {} attractors", grouper.len())];
    lines.extend(plot(out, &m0, &map)?);
    lines.push(format!("wrote {}", out.display()));
    Ok(lines)
}
