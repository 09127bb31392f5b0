//! A grid of cells as every front end runs it (`signorini basins`, its
//! shards and `signorini merge`, Python's `signorini.basins`): the options
//! checked, the known orbits read from a `branch.csv` text, the cells
//! classified in parallel in batches of whole rows, the attractors numbered
//! in cell order, and the files' text — `basins.csv`, `basins.svg`,
//! `basins.toml` (the manifest) — as strings. No IO: a front end hands the
//! rows to its file as they come ([`Grid::run`]'s `rows`), reads the shard
//! folders for [`merge`] through a closure, and writes what it is given.

use super::{describe, match_known, parse_branch, Axis, BasinOptions, BasinScene, Grouper, KnownOrbit, Outcome};
use crate::OrbitError;
use rayon::prelude::*;
use signorini_plot::{category_map, Category, Chart, PlotError, Scale};
use signorini_scene::Limits;
use std::fmt::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The columns of `basins.csv` before the state's.
pub const BASIN_COLUMNS: &str = "i,j,x,v,attractor,period,impacts_per_period,sticking,label";

/// `attractor` of a non-periodic cell in [`Basins::attractor`].
pub const NON_PERIODIC: i64 = -1;
/// `attractor` of a failed cell in [`Basins::attractor`].
pub const FAILED: i64 = -2;

/// What a grid is asked (the options of `signorini basins`).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct GridOptions {
    /// The displacement axis (`--x`, `--x-range`, the grid's first count).
    pub x: Axis,
    /// The velocity axis (`--v`, `--v-range`, the grid's second count).
    pub v: Axis,
    /// The classification's options.
    pub classify: BasinOptions,
    /// A continuation's `branch.csv` text: the known orbits (`--orbits`).
    pub orbits: Option<String>,
    /// `(I, N)`: run only block I of N (`--shard I/N`).
    pub shard: Option<(usize, usize)>,
    /// Threads (default: rayon's); the result does not depend on it.
    pub threads: Option<usize>,
    /// Keep each cell's period, impacts, sticking, label and state in the
    /// result (Python's columns, [`basins_csv`]); without it a [`Basins`]
    /// holds the attractor ids only and the rows go to [`Grid::run`]'s
    /// `rows` alone (a CLI grid of millions of cells).
    pub keep: bool,
}

impl GridOptions {
    /// The grid of `x` by `v` with the default classification, no known
    /// orbits, unsharded, rayon's threads, cells not kept.
    pub fn new(x: Axis, v: Axis) -> Self {
        Self { x, v, classify: BasinOptions::default(), orbits: None, shard: None, threads: None, keep: false }
    }

    /// Checks the classification's options and the thread count (the grid
    /// itself is checked by [`Grid::new`]).
    pub fn validate(&self) -> Result<(), OrbitError> {
        self.classify.validate()?;
        if let Some(0) = self.threads {
            return Err(opt("threads", "0 is not allowed: an integer >= 1".into()));
        }
        Ok(())
    }
}

fn opt(option: &'static str, message: String) -> OrbitError {
    OrbitError::Option { option, message }
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
fn grid_id(text: &str, o: &GridOptions) -> String {
    let c = &o.classify;
    let mut h = fnv1a(text.as_bytes(), 0xcbf2_9ce4_8422_2325);
    for a in [&o.x, &o.v] {
        h = fnv1a(format!("|{}|{:016x}|{:016x}|{}", a.path, a.from.to_bits(), a.to.to_bits(), a.count).as_bytes(), h);
    }
    h = fnv1a(format!("|{}|{}|{:016x}|{:016x}|", c.transient, c.max_period, c.tol.to_bits(), c.match_tol.to_bits()).as_bytes(), h);
    h = fnv1a(o.orbits.as_deref().unwrap_or("").as_bytes(), h);
    format!("{h:016x}")
}

/// The cells of shard `(I, N)` of `total`: `[I·total/N, (I+1)·total/N)`.
pub fn block(total: usize, shard: Option<(usize, usize)>) -> Range<usize> {
    match shard {
        None => 0..total,
        Some((i, n)) => (i * total / n)..((i + 1) * total / n),
    }
}

/// The manifest `basins.toml`: what `merge` checks.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Manifest {
    /// The grid's id (a hash of the scene text and every option that
    /// changes a number).
    pub id: String,
    /// Cells along x.
    pub nx: usize,
    /// Cells along v.
    pub ny: usize,
    /// The x range.
    pub x: (f64, f64),
    /// The v range.
    pub v: (f64, f64),
    /// The x key's dotted path.
    pub x_path: String,
    /// The v key's dotted path.
    pub v_path: String,
    /// The grouping tolerance.
    pub match_tol: f64,
    /// `(I, N)` of a shard.
    pub shard: Option<(usize, usize)>,
}

impl Manifest {
    /// `basins.toml`'s text.
    pub fn text(&self) -> String {
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

    /// Reads a manifest's text; what is missing or wrong, in words.
    pub fn parse(text: &str) -> Result<Self, String> {
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

/// The state of an attractor as its row writes it, read back: what the
/// grouping sees, so that grouping the written rows again (a merge) gives
/// the same ids.
fn as_written(state: &[f64]) -> Vec<f64> {
    state.iter().map(|x| cell(*x).parse().unwrap_or(f64::NAN)).collect()
}

/// One row of `basins.csv`, with its newline.
#[allow(clippy::too_many_arguments)]
fn push_row(out: &mut String, x: &Axis, v: &Axis, c: usize, id: i64, period: usize, impacts: usize, sticking: bool, label: &str, state: &[f64], width: usize) {
    let (i, j) = (c % x.count, c / x.count);
    let _ = write!(out, "{i},{j},{},{}", cell(x.value(i)), cell(v.value(j)));
    if id == FAILED {
        out.push_str(",,,,,failed");
        out.push_str(&",".repeat(width));
    } else {
        let a = if id >= 0 { id.to_string() } else { String::new() };
        let _ = write!(out, ",{a},{period},{impacts},{},{label}", u8::from(sticking));
        for s in state {
            let _ = write!(out, ",{}", cell(*s));
        }
    }
    out.push('\n');
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

/// A distinct periodic attractor of a grid.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct AttractorEntry {
    /// Its period in forcing periods.
    pub period: usize,
    /// The label of its first cell (a known orbit's, else `p<k>-i<n>…`).
    pub label: String,
    /// Its point on the section as its first cell found it (the canonical
    /// point of the cycle; the grouping compares cells with it).
    pub state: Vec<f64>,
    /// The first cell that reached it.
    pub first_cell: usize,
    /// Cells that reached it.
    pub cells: usize,
}

/// A grid (or a shard of one) classified: the attractor id of each cell,
/// with [`GridOptions::keep`] each cell's columns, and the attractors.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Basins {
    /// The manifest (`basins.toml`).
    pub manifest: Manifest,
    /// The x axis.
    pub x: Axis,
    /// The v axis.
    pub v: Axis,
    /// The state dofs (`q<dof>`, `v<dof>` columns).
    pub state_dofs: Vec<usize>,
    /// The cells asked (the shard's block).
    pub cells: Range<usize>,
    /// Each classified cell's attractor id, in cell order from
    /// `cells.start`: `>= 0`, [`NON_PERIODIC`] or [`FAILED`]. Shorter than
    /// `cells` when the run was stopped (whole rows are kept).
    pub attractor: Vec<i64>,
    /// Each kept cell's period in forcing periods (0: non-periodic or failed).
    pub period: Vec<usize>,
    /// Each kept cell's impacts per period (0 for a failed cell).
    pub impacts: Vec<usize>,
    /// Each kept cell's held phase.
    pub sticking: Vec<bool>,
    /// Each kept cell's label.
    pub label: Vec<String>,
    /// Each kept cell's attractor point, `2·state_dofs.len()` values a
    /// cell (NaN for a failed cell).
    pub state: Vec<f64>,
    /// The distinct periodic attractors, by id.
    pub attractors: Vec<AttractorEntry>,
    /// Failed cells.
    pub failed: usize,
    /// The first failed cell and why.
    pub first_failure: Option<String>,
}

impl Basins {
    /// Every cell asked was classified.
    pub fn complete(&self) -> bool {
        self.attractor.len() == self.cells.len()
    }

    /// The line a front end prints: cells, time, attractors, failures.
    pub fn summary(&self, seconds: f64) -> String {
        let n = self.attractors.len();
        format!(
            "{} cells in {seconds:.3} s: {n} attractor{} found{}",
            self.cells.len(),
            if n == 1 { "" } else { "s" },
            match &self.first_failure {
                Some(f) => format!(", {} cells failed (label failed; the first, {f})", self.failed),
                None => String::new(),
            }
        )
    }

    fn names(&self) -> Vec<String> {
        self.attractors.iter().enumerate().map(|(k, a)| format!("{k}: {}", a.label)).collect()
    }
}

/// `basins.csv` of a grid run with [`GridOptions::keep`]: the header and
/// the rows of the cells classified (the text [`Grid::run`] hands out).
/// Without `keep` the header alone.
///
/// `basins.csv` (a contract: columns only ever added) — one row per cell,
/// cells in the order `c = j·nx + i`:
/// `i,j,x,v,attractor,period,impacts_per_period,sticking,label`, then the
/// attractor's point on the section, `q<dof>` and `v<dof>` of each state
/// dof. `attractor` numbers the distinct periodic attractors in the order
/// the cells first reach them (empty for a non-periodic or failed cell);
/// `period` is in forcing periods (0: non-periodic); `impacts_per_period`
/// counts the impacts over one period of the orbit; `sticking` is 1 when
/// the orbit has a held phase; `label` is the known orbit matched
/// (`branch<B>:<N>` of the known orbits), else `p<k>-i<n>[-sticking]`,
/// `non-periodic` or `failed`.
pub fn basins_csv(b: &Basins) -> String {
    let mut out = header(&b.state_dofs);
    let w = 2 * b.state_dofs.len();
    if b.period.len() == b.attractor.len() {
        for (k, &id) in b.attractor.iter().enumerate() {
            push_row(&mut out, &b.x, &b.v, b.cells.start + k, id, b.period[k], b.impacts[k], b.sticking[k], &b.label[k], &b.state[k * w..(k + 1) * w], w);
        }
    }
    out
}

/// `basins.svg` of a whole grid: each cell coloured by its attractor, grey
/// for non-periodic cells, black for failed ones; the legend names each
/// attractor by its first cell's label. A grid with cells missing (a
/// shard, a stopped run) draws the cells it has.
pub fn basins_svg(b: &Basins) -> Result<String, PlotError> {
    map_svg(&b.manifest, b.cells.start, &b.attractor, &b.names())
}

/// `basins.toml`.
pub fn basins_toml(b: &Basins) -> String {
    b.manifest.text()
}

fn map_svg(m: &Manifest, first: usize, ids: &[i64], names: &[String]) -> Result<String, PlotError> {
    let n_attr = names.len();
    let mut counts = vec![0usize; n_attr + 2];
    let mut cells = vec![vec![None; m.nx]; m.ny];
    for (k, &id) in ids.iter().enumerate() {
        let c = first + k;
        let k = if id >= 0 {
            id as usize
        } else if id == NON_PERIODIC {
            n_attr
        } else {
            n_attr + 1
        };
        counts[k] += 1;
        cells[c / m.nx][c % m.nx] = Some(k);
    }
    let mut cats: Vec<Category> = names.iter().enumerate().map(|(k, name)| Category { name: format!("{name} ({} cells)", counts[k]), color: None }).collect();
    cats.push(Category { name: format!("non-periodic ({} cells)", counts[n_attr]), color: Some((190, 190, 190)) });
    cats.push(Category { name: format!("failed ({} cells)", counts[n_attr + 1]), color: Some((0, 0, 0)) });
    let chart = Chart { title: "Basins of attraction", x_label: &m.x_path, y_label: &m.v_path, scale: Scale::Linear, size: (900, 700) };
    category_map(&chart, m.x, m.v, &cells, &cats)
}

/// A grid checked and ready to run.
#[derive(Debug)]
pub struct Grid {
    scene: BasinScene,
    opts: GridOptions,
    known: Vec<KnownOrbit>,
    dofs: Vec<usize>,
    manifest: Manifest,
}

impl Grid {
    /// The grid of `opts` over the scene text `text` (`scheme =
    /// "event-driven(e)"`, a periodic forcing): every option checked
    /// ([`GridOptions::validate`], the known orbits' text, the axes and the
    /// scene at the grid's corners by [`BasinScene::new`], the shard), a
    /// typed error naming the option otherwise.
    pub fn new(text: &str, opts: GridOptions, limits: Limits) -> Result<Self, OrbitError> {
        let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| OrbitError::Scene(e.to_string()))?;
        opts.validate()?;
        let known = match &opts.orbits {
            Some(t) => parse_branch(t)?,
            None => Vec::new(),
        };
        let scene = BasinScene::new(doc, opts.x.clone(), opts.v.clone(), limits)?;
        let total = scene.cells();
        if let Some((i, n)) = opts.shard {
            if n == 0 || i >= n || n > total {
                return Err(opt("shard", format!("{i}/{n} is not allowed: I/N with 1 <= N <= {total} (the cells) and 0 <= I < N")));
            }
        }
        let dofs = scene.state_dofs()?;
        let manifest = Manifest {
            id: grid_id(text, &opts),
            nx: opts.x.count,
            ny: opts.v.count,
            x: (opts.x.from, opts.x.to),
            v: (opts.v.from, opts.v.to),
            x_path: opts.x.path.clone(),
            v_path: opts.v.path.clone(),
            match_tol: opts.classify.match_tol,
            shard: opts.shard,
        };
        Ok(Self { scene, opts, known, dofs, manifest })
    }

    /// The manifest (`basins.toml`'s content).
    pub fn manifest(&self) -> &Manifest {
        &self.manifest
    }

    /// `basins.csv`'s header line (with its newline).
    pub fn header(&self) -> String {
        header(&self.dofs)
    }

    /// The cells this grid (or shard) runs.
    pub fn cells(&self) -> Range<usize> {
        block(self.scene.cells(), self.opts.shard)
    }

    /// Classifies the cells in parallel, in batches of 256 in cell order;
    /// after each batch its rows of `basins.csv` (whole lines) go to `rows`,
    /// which stops the run by returning `false`. `progress` is called once
    /// per cell classified (from the worker threads); `cancel` is checked
    /// before each cell: a stopped run keeps the whole rows before the
    /// first cell skipped ([`Basins::complete`] says whether all ran).
    /// Errors: the thread pool's (`threads`).
    pub fn run(&self, progress: &(dyn Fn() + Sync), cancel: &(dyn Fn() -> bool + Sync), rows: &mut dyn FnMut(&str) -> bool) -> Result<Basins, OrbitError> {
        let cells = self.cells();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(self.opts.threads.unwrap_or(0)).build().map_err(|e| opt("threads", e.to_string()))?;
        let (copts, keep) = (&self.opts.classify, self.opts.keep);
        let width = 2 * self.dofs.len();
        let mut b = Basins {
            manifest: self.manifest.clone(),
            x: self.opts.x.clone(),
            v: self.opts.v.clone(),
            state_dofs: self.dofs.clone(),
            cells: cells.clone(),
            attractor: Vec::new(),
            period: Vec::new(),
            impacts: Vec::new(),
            sticking: Vec::new(),
            label: Vec::new(),
            state: Vec::new(),
            attractors: Vec::new(),
            failed: 0,
            first_failure: None,
        };
        // The seeds, classified in full, and their attractors' targets: the
        // same for every shard and thread count (module docs).
        let seeds = self.scene.seeds();
        let seeded: Vec<Option<Outcome>> = pool.install(|| seeds.par_iter().map(|&c| (!cancel()).then(|| self.scene.classify(c, copts))).collect());
        if seeded.iter().any(Option::is_none) {
            return Ok(b);
        }
        let seeded: Vec<Outcome> = seeded.into_iter().flatten().collect();
        let mut targets = match self.scene.targets(&seeds, &seeded, copts) {
            Ok(t) => t,
            Err(OrbitError::Interrupted) => return Ok(b),
            Err(e) => return Err(e),
        };
        // The known orbits' stable points at the scene's map, beside them.
        match self.scene.known_targets(&self.known, &targets, copts) {
            Ok(t) => targets.extend(t),
            Err(OrbitError::Interrupted) => return Ok(b),
            Err(e) => return Err(e),
        }
        let mut grouper = Grouper::new(copts.match_tol);
        let mut done = cells.start;
        let batch = 256usize;
        while done < cells.end && !cancel() {
            let end = (done + batch).min(cells.end);
            let outcomes: Vec<Option<Outcome>> = pool.install(|| {
                (done..end)
                    .into_par_iter()
                    .map(|c| {
                        if cancel() {
                            return None;
                        }
                        let o = match seeds.binary_search(&c) {
                            Ok(k) => seeded[k].clone(),
                            Err(_) => self.scene.classify_near(c, copts, &targets).0,
                        };
                        progress();
                        Some(o)
                    })
                    .collect()
            });
            let mut text = String::new();
            for (k, o) in outcomes.iter().enumerate() {
                let Some(o) = o else { break };
                let c = done + k;
                let (id, period, impacts, sticking, label, state) = match o {
                    Outcome::Attractor(a) => {
                        let label = match_known(a, &self.known, copts.match_tol).map_or_else(|| describe(a), |o| o.label.clone());
                        let id = grouper.id(a.period, &as_written(&a.state));
                        let id = match id {
                            Some(k) => {
                                if k == b.attractors.len() {
                                    b.attractors.push(AttractorEntry { period: a.period, label: label.clone(), state: a.state.clone(), first_cell: c, cells: 0 });
                                }
                                b.attractors[k].cells += 1;
                                k as i64
                            }
                            None => NON_PERIODIC,
                        };
                        (id, a.period, a.impacts, a.sticking, label, a.state.clone())
                    }
                    Outcome::Failed(why) => {
                        b.failed += 1;
                        let (i, j) = self.scene.ij(c);
                        b.first_failure.get_or_insert_with(|| format!("cell {c} (i, j = {i}, {j}): {why}"));
                        (FAILED, 0, 0, false, "failed".to_string(), vec![f64::NAN; width])
                    }
                };
                push_row(&mut text, &self.opts.x, &self.opts.v, c, id, period, impacts, sticking, &label, &state, width);
                b.attractor.push(id);
                if keep {
                    b.period.push(period);
                    b.impacts.push(impacts);
                    b.sticking.push(sticking);
                    b.label.push(label);
                    b.state.extend_from_slice(&state);
                }
            }
            let written = outcomes.iter().take_while(|o| o.is_some()).count();
            done += written;
            if !rows(&text) || written < outcomes.len() {
                break;
            }
        }
        Ok(b)
    }
}

/// A merge's files and what to print.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Merged {
    /// `(file name, contents)`: `basins.csv`, `basins.toml`, and
    /// `basins.svg` when it could be drawn.
    pub files: Vec<(&'static str, String)>,
    /// What to print (the merge, a note when the map was not drawn).
    pub lines: Vec<String>,
}

/// Merges the shard folders `shards` of one grid (`signorini merge`):
/// `basins.csv` (the attractor ids given again in cell order, as the
/// unsharded grid gives them), `basins.svg` and `basins.toml`, byte for
/// byte the unsharded grid's files. Refuses shards of different grids
/// (ids), missing or repeated shards, and incomplete ones (option
/// `merge`). `read` reads a file (a folder's `basins.toml` or
/// `basins.csv`), the error in words.
pub fn merge(shards: &[PathBuf], read: &mut dyn FnMut(&Path) -> Result<String, String>) -> Result<Merged, OrbitError> {
    let bad = |m: String| opt("merge", m);
    if shards.is_empty() {
        return Err(bad("give the shard folders".into()));
    }
    let mut found = Vec::new();
    for d in shards {
        let p = d.join("basins.toml");
        let m = read(&p)
            .and_then(|t| Manifest::parse(&t))
            .map_err(|e| bad(format!("{} is not a basins shard folder ({}: {e}): give the folders `signorini basins --shard I/N` wrote", d.display(), p.display())))?;
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
        let text = read(&path).map_err(|e| bad(format!("{}: {e}", path.display())))?;
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
    let (mut ids, mut names) = (Vec::with_capacity(total), Vec::<String>::new());
    let mut text = header;
    for r in &mut rows {
        let period: usize = r.get(5).and_then(|p| p.parse().ok()).unwrap_or(0);
        let state: Vec<f64> = r.iter().skip(state_at).map(|t| t.parse().unwrap_or(f64::NAN)).collect();
        let failed = r.get(8).is_some_and(|l| l == "failed");
        let id = if failed { None } else { grouper.id(period, &state) };
        if r.len() > 4 {
            r[4] = id.map(|k| k.to_string()).unwrap_or_default();
        }
        ids.push(match id {
            Some(k) => {
                if names.len() == k {
                    names.push(format!("{k}: {}", r.get(8).map_or("", String::as_str)));
                }
                k as i64
            }
            None if failed => FAILED,
            None => NON_PERIODIC,
        });
        text.push_str(&r.join(","));
        text.push('\n');
    }
    let mut files = vec![("basins.csv", text), ("basins.toml", m0.text())];
    let mut lines = vec![format!("merged {n0} shards of grid {id0}: {total} cells, {} attractors", grouper.len())];
    match map_svg(&m0, 0, &ids, &names) {
        Ok(svg) => files.push(("basins.svg", svg)),
        Err(e) => lines.push(format!("note: basins.svg not written: {e}")),
    }
    Ok(Merged { files, lines })
}
