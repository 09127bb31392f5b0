//! The reproducible studies of signorini as library functions.
//!
//! Each study `X` (`convergence`, `weighted`, `beam`, `obstacles`,
//! `oscillator`, `work_precision`, `stress`, `courant1`, `long_horizon`,
//! `lyapunov`, `beam_statistics`) is a module with a `Config`
//! (declared once with its fields' documents and defaults, [`options`]:
//! `cargo xtask`'s flags and Python's keyword arguments are its fields,
//! read by [`options::read`]; `validate` doing every check before anything
//! large is allocated), a `run(cfg, progress)`
//! that writes every CSV and SVG into the configured folder and returns an
//! `Output`: one [`Table`] per CSV file written (the values that were
//! formatted into it, column by column), the Markdown `report` that
//! `cargo xtask X` prints, the wall time and the `notes` it prints on
//! stderr. `xtask`, the CLI and the Python package are front ends over
//! these functions.
//!
//! `progress(done, total)` is called from the worker threads as runs
//! finish (studies that report no progress never call it).
//!
//! The convergence study at three levels: Newmark-CN with the massless-node
//! mass `mod` on the Dirichlet bar converges at first order in L∞(L²), its
//! error halving with `h` (docs/theory.md §6):
//!
//! ```
//! use signorini_studies::convergence::{run, Config};
//!
//! let out = std::env::temp_dir().join(format!("signorini-doctest-convergence-{}", std::process::id()));
//! let cfg = Config {
//!     schemes: vec!["newmark-cn".parse()?],
//!     masses: vec![signorini_fem::BarMass::Mod],
//!     levels: vec![10, 20, 40],
//!     out: Some(out.clone()),
//!     clean: true,
//!     ..Config::default()
//! };
//! let o = run(&cfg, &|_, _| {})?;
//! let errors: Vec<f64> = o.results[0].levels.iter().map(|l| l.norms.linf_l2_u).collect();
//! let rate = (errors[0] / errors[2]).log2() / 2.0;
//! assert!((0.8..1.2).contains(&rate), "rate {rate}");
//! assert!(out.join("newmark-cn_mod.csv").exists());
//! std::fs::remove_dir_all(&out)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod beam;
pub mod beam_statistics;
pub mod convergence;
pub mod courant1;
pub mod long_horizon;
pub mod lyapunov;
pub mod obstacles;
pub mod options;
pub mod oscillator;
pub mod stress;
pub mod time_error;
pub mod weighted;
pub mod work_precision;

use signorini_fem::BarMass;
use signorini_schemes::{Group, SchemeSpec};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Why a study did not run or did not finish.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StudyError {
    /// Bad input: `field` is the configuration's field by its Rust name
    /// (`levels`, `t_end`), which each front end spells its own way
    /// ([`options::Spelling`]: `--t-end` for `cargo xtask`, `t_end` in
    /// Python); `message` is the whole message, which starts with the field
    /// and names the allowed range, its field names kept apart for that
    /// spelling (shown here in the neutral one).
    #[error("{message}")]
    Config {
        /// The offending field, e.g. `levels`.
        field: String,
        /// The whole message, e.g. `⟨t_end⟩ 3: allowed finite and >= 4.5 (...)`.
        message: options::Message,
    },
    /// A run failed, in the study's words (no error underneath: a status,
    /// a missing result, a panic).
    #[error("{0}")]
    Run(String),
    /// A run failed ([`signorini_run::RunError`]).
    #[error(transparent)]
    RunFailed(#[from] signorini_run::RunError),
    /// A step of the study failed: `what` names the run or case, `source`
    /// is the error underneath (a scene, a scheme, a sweep, an exact solution).
    #[error("{what}{}{source}", if what.is_empty() { "" } else { ": " })]
    Failed {
        /// The run or case (empty when the error says it all).
        what: String,
        /// The cause.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// A file or folder could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// An output folder could not be created.
    #[error("cannot create {}: {source}", path.display())]
    CreateDir {
        /// The folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A chart could not be drawn.
    #[error(transparent)]
    Plot(#[from] signorini_plot::PlotError),
}

impl StudyError {
    /// A [`StudyError::Config`] for `field` (its Rust name) with the whole
    /// `message`, in which `⟨name⟩` marks a field ([`options::at`]).
    pub fn config(field: &str, message: impl AsRef<str>) -> Self {
        StudyError::Config { field: field.to_string(), message: options::Message::new(message.as_ref()) }
    }

    /// The message with the fields spelled as `spelling` says (the
    /// `Display` text is the neutral spelling).
    pub fn render(&self, spelling: options::Spelling) -> String {
        match self {
            StudyError::Config { message, .. } => message.render(spelling),
            other => other.to_string(),
        }
    }
}

impl StudyError {
    /// A [`StudyError::Failed`]: `source` failed in `what` (empty: the
    /// error says it all).
    pub fn failed(what: impl Into<String>, source: impl std::error::Error + Send + Sync + 'static) -> Self {
        StudyError::Failed { what: what.into(), source: Box::new(source) }
    }
}

/// One column of a [`Table`]: the values written into the CSV, as the
/// number that was formatted (an empty cell is `NaN` in an `F64` column).
#[derive(Clone, Debug, PartialEq)]
pub enum Column {
    /// Real values.
    F64(Vec<f64>),
    /// Integer values (counts, numbers of elements, steps, seeds).
    I64(Vec<i64>),
    /// Text (scheme and mass names, statuses, lists).
    Str(Vec<String>),
}

impl Column {
    /// Number of rows.
    pub fn len(&self) -> usize {
        match self {
            Column::F64(v) => v.len(),
            Column::I64(v) => v.len(),
            Column::Str(v) => v.len(),
        }
    }

    /// True without rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// What a study computed and wrote: the Output of the studies that return
/// nothing beyond their files and their report.
#[derive(Clone, Debug)]
pub struct Report {
    /// One table per CSV written, in the order written.
    pub tables: Vec<Table>,
    /// The Markdown report `cargo xtask <study>` prints.
    pub report: String,
    /// Wall time of the whole study (s).
    pub wall_s: f64,
    /// Notes for stderr.
    pub notes: Vec<String>,
}

/// The content of one CSV file a study wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// The file name relative to the study's output folder, e.g.
    /// `rates.csv` or `convergence/newmark-cn_mod1.csv`.
    pub file: String,
    /// `(header, values)` in the CSV's column order.
    pub columns: Vec<(String, Column)>,
}

impl Table {
    /// The column named `name`, if any.
    pub fn column(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.0 == name).map(|c| &c.1)
    }
}

/// The type a [`Table`] column is declared with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    F,
    I,
    S,
}

/// One CSV cell: its text and the value it was formatted from.
#[derive(Clone, Debug)]
pub(crate) enum Cell {
    /// A real and its text.
    F(f64, String),
    /// An integer.
    I(i64),
    /// Text.
    S(String),
    /// An empty cell.
    E,
}

impl Cell {
    fn text(&self) -> String {
        match self {
            Cell::F(_, s) | Cell::S(s) => s.clone(),
            Cell::I(v) => v.to_string(),
            Cell::E => String::new(),
        }
    }
}

/// `x` formatted with `{:.p$e}`.
pub(crate) fn fe(x: f64, p: usize) -> Cell {
    Cell::F(x, format!("{x:.p$e}"))
}
/// `x` formatted with `{:.p$}`.
pub(crate) fn ff(x: f64, p: usize) -> Cell {
    Cell::F(x, format!("{x:.p$}"))
}
/// `x` formatted with `{}`.
pub(crate) fn fd(x: f64) -> Cell {
    Cell::F(x, format!("{x}"))
}
/// `x` formatted with `{:e}`.
pub(crate) fn fde(x: f64) -> Cell {
    Cell::F(x, format!("{x:e}"))
}
/// An integer cell.
pub(crate) fn int(v: usize) -> Cell {
    Cell::I(v as i64)
}
/// A text cell.
pub(crate) fn txt(s: impl Into<String>) -> Cell {
    Cell::S(s.into())
}
/// `c`, or an empty cell.
pub(crate) fn opt(c: Option<Cell>) -> Cell {
    c.unwrap_or(Cell::E)
}

/// A CSV file being written: the header goes out at creation, every row
/// as it is pushed (csv quoting), and the cells are kept for the [`Table`].
pub(crate) struct TableOut {
    file: String,
    path: PathBuf,
    names: Vec<(String, Kind)>,
    rows: Vec<Vec<Cell>>,
    w: csv::Writer<BufWriter<File>>,
}

impl TableOut {
    /// Creates `dir/file` (`file` may hold a sub-folder already created) and writes the header.
    pub(crate) fn create(dir: &Path, file: &str, names: &[(&str, Kind)]) -> Result<Self, StudyError> {
        Self::create_in(dir, "", file, names)
    }

    /// As [`TableOut::create`], the table named `prefix` + `file` relative to the output folder.
    pub(crate) fn create_in(dir: &Path, prefix: &str, file: &str, names: &[(&str, Kind)]) -> Result<Self, StudyError> {
        let path = dir.join(file);
        let f = File::create(&path).map_err(|source| StudyError::Io { path: path.clone(), source })?;
        let mut w = csv::Writer::from_writer(BufWriter::new(f));
        w.write_record(names.iter().map(|n| n.0)).map_err(|e| csv_err(&path, e))?;
        Ok(TableOut { file: format!("{prefix}{file}"), path, names: names.iter().map(|(n, k)| (n.to_string(), *k)).collect(), rows: Vec::new(), w })
    }

    /// Writes one row and keeps it.
    #[track_caller]
    pub(crate) fn row(&mut self, cells: Vec<Cell>) -> Result<(), StudyError> {
        assert_eq!(cells.len(), self.names.len(), "{}: row of {} cells for {} columns", self.file, cells.len(), self.names.len());
        self.w.write_record(cells.iter().map(Cell::text)).map_err(|e| csv_err(&self.path, e))?;
        self.rows.push(cells);
        Ok(())
    }

    /// Flushes what was written so far to the file.
    pub(crate) fn flush(&mut self) -> Result<(), StudyError> {
        self.w.flush().map_err(|source| StudyError::Io { path: self.path.clone(), source })
    }

    /// Flushes the file and returns its table.
    pub(crate) fn finish(mut self) -> Result<Table, StudyError> {
        self.flush()?;
        let columns = self
            .names
            .iter()
            .enumerate()
            .map(|(j, (name, kind))| {
                let cells = self.rows.iter().map(|r| &r[j]);
                let col = match kind {
                    Kind::F => Column::F64(
                        cells
                            .map(|c| match c {
                                Cell::F(x, _) => *x,
                                Cell::I(v) => *v as f64,
                                Cell::S(s) => s.parse().unwrap_or(f64::NAN),
                                Cell::E => f64::NAN,
                            })
                            .collect(),
                    ),
                    Kind::I => Column::I64(
                        cells
                            .map(|c| match c {
                                Cell::I(v) => *v,
                                Cell::F(x, _) => *x as i64,
                                Cell::S(s) => s.parse().unwrap_or(i64::MIN),
                                Cell::E => i64::MIN,
                            })
                            .collect(),
                    ),
                    Kind::S => Column::Str(cells.map(Cell::text).collect()),
                };
                (name.clone(), col)
            })
            .collect();
        Ok(Table { file: self.file, columns })
    }
}

fn csv_err(path: &Path, e: csv::Error) -> StudyError {
    StudyError::Io { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) }
}

/// Creates `dir` and its parents.
pub(crate) fn create_dir(dir: &Path) -> Result<(), StudyError> {
    std::fs::create_dir_all(dir).map_err(|source| StudyError::CreateDir { path: dir.to_path_buf(), source })
}

/// Creates `dir` for a study that will write the `expected` files (names
/// relative to `dir`) and refuses it when it holds study outputs (CSV or SVG
/// files) that this run would not write: left from another study or another
/// configuration, they would mix with this run's files. With `clean` those
/// files are removed first. Files the run writes are overwritten.
pub(crate) fn prepare_dir(dir: &Path, expected: &[String], clean: bool) -> Result<(), StudyError> {
    create_dir(dir)?;
    let entries = std::fs::read_dir(dir).map_err(|source| StudyError::Io { path: dir.to_path_buf(), source })?;
    let mut stale: Vec<String> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter_map(|e| e.file_name().into_string().ok())
        .filter(|f| (f.ends_with(".csv") || f.ends_with(".svg")) && !expected.iter().any(|x| x == f))
        .collect();
    if stale.is_empty() {
        return Ok(());
    }
    stale.sort();
    if !clean {
        let shown = if stale.len() > 4 { format!("{}, … ({} files)", stale[..4].join(", "), stale.len()) } else { stale.join(", ") };
        return Err(StudyError::config(
            "out",
            format!("output folder {} holds files of another study or configuration ({shown}): pass ⟨clean⟩ to remove them first, or choose another ⟨out⟩", dir.display()),
        ));
    }
    for f in &stale {
        let path = dir.join(f);
        std::fs::remove_file(&path).map_err(|source| StudyError::Io { path, source })?;
    }
    Ok(())
}

/// Runs `f` on every case, each on its own thread, as many at a time as
/// the machine has cores, calling `progress(done, total)` after each batch;
/// the results in the cases' order (a panicking run is an error).
pub(crate) fn run_cases<C: Sync, T: Send>(cases: &[C], progress: &(dyn Fn(u64, u64) + Sync), f: &(dyn Fn(&C) -> Result<T, StudyError> + Sync)) -> Vec<Result<T, StudyError>> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut results: Vec<Result<T, StudyError>> = Vec::with_capacity(cases.len());
    for chunk in cases.chunks(threads) {
        std::thread::scope(|s| {
            let hs: Vec<_> = chunk.iter().map(|c| s.spawn(move || f(c))).collect();
            results.extend(hs.into_iter().map(|h| h.join().unwrap_or_else(|_| Err(StudyError::Run("a run panicked".into())))));
        });
        progress(results.len() as u64, cases.len() as u64);
    }
    results
}

/// Whether `line_chart` has a point of `series` to draw on `scale`'s axes
/// (finite, and positive on a log-log chart).
pub(crate) fn drawable(series: &[signorini_plot::Series], scale: signorini_plot::Scale) -> bool {
    series.iter().flat_map(|s| &s.points).any(|p| p.0.is_finite() && p.1.is_finite() && (scale == signorini_plot::Scale::Linear || (p.0 > 0.0 && p.1 > 0.0)))
}

/// Draws `series` as a line chart into `dir/file`; when there is nothing
/// to draw (see [`drawable`]) the chart is skipped, a file of that name
/// left by an earlier run removed (it would pass for this run's), and the
/// note returned, saying why (`why`).
pub(crate) fn draw_or_skip(dir: &Path, file: &str, chart: &signorini_plot::Chart<'_>, series: &[signorini_plot::Series], why: &str) -> Result<Option<String>, StudyError> {
    let path = dir.join(file);
    if !drawable(series, chart.scale) {
        if path.exists() {
            std::fs::remove_file(&path).map_err(|source| StudyError::Io { path: path.clone(), source })?;
        }
        return Ok(Some(format!("note: {file} not drawn: {why}")));
    }
    let svg = signorini_plot::line_chart(chart, series).map_err(StudyError::Plot)?;
    write_file(&path, &svg)?;
    Ok(None)
}

/// Writes an SVG (or any text) file.
pub(crate) fn write_file(path: &Path, text: &str) -> Result<(), StudyError> {
    std::fs::write(path, text).map_err(|source| StudyError::Io { path: path.to_path_buf(), source })
}

/// Joins pieces split inside parentheses, e.g. `newmark(0.25` + `0.5)`,
/// after splitting every piece on `,`: `["newmark(0.25,0.5),ps-e0"]` →
/// `["newmark(0.25,0.5)", "ps-e0"]`. Empty names are dropped.
pub fn split_schemes(raw: &[String]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for piece in raw.iter().flat_map(|s| s.split(',')) {
        match out.last_mut() {
            Some(last) if last.matches('(').count() > last.matches(')').count() => {
                last.push(',');
                last.push_str(piece.trim());
            }
            _ => out.push(piece.trim().to_string()),
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

/// Parses scheme names (presets or `newmark(B,G)`, `theta(T)`, `ps(E[,B])`;
/// commas inside parentheses do not split, see [`split_schemes`]); an
/// error names `--schemes`.
pub fn parse_schemes(raw: &[String]) -> Result<Vec<SchemeSpec>, StudyError> {
    split_schemes(raw).iter().map(|s| s.parse::<SchemeSpec>().map_err(|e| StudyError::config("schemes", format!("⟨schemes⟩: {e}")))).collect()
}

/// The time-stepping schemes of a study over every scheme and mass: the
/// `given` list (its own call as the name: `contact-stabilized`,
/// `nsga(0.5)`), or every named preset (`SchemeSpec::named`, by its name)
/// when none is given. A scheme of one mass treatment only (`cd-taylor`,
/// which `cargo xtask courant1` runs) or the event-driven reference, which
/// has no time step, is refused naming `field`.
pub(crate) fn time_stepping_schemes(field: &str, given: Option<&[SchemeSpec]>) -> Result<Vec<(String, SchemeSpec)>, StudyError> {
    let Some(given) = given else {
        return Ok(SchemeSpec::named().map(|(n, s)| (n.to_string(), s)).collect());
    };
    if given.is_empty() {
        return Err(StudyError::config(field, format!("⟨{field}⟩: allowed one or more time-stepping schemes")));
    }
    let of = |g: Group, s: &SchemeSpec| SchemeSpec::group(g).any(|(_, p)| std::ptr::eq(p.family(), s.family()));
    for s in given {
        let (single, reference) = (of(Group::SingleMass, s), of(Group::Reference, s));
        if single || reference {
            let why = if reference {
                "the exact event-driven reference has no time step"
            } else {
                "it takes one mass treatment only (the loops over every scheme and mass leave it out; `cargo xtask courant1` runs it)"
            };
            return Err(StudyError::config(field, format!("⟨{field}⟩ {s}: {why}; allowed the time-stepping schemes of `signorini list` for the bar")));
        }
    }
    Ok(given.iter().map(|s| (s.to_string(), *s)).collect())
}

/// Whether `scheme` runs with `mass`: the contact node it needs, and the
/// lumped mass when it needs a diagonal one (`verlet-nitsche` with θ ≠ 1).
pub(crate) fn takes_mass(scheme: &SchemeSpec, mass: BarMass) -> bool {
    scheme.accepts_massless_node(mass.massless_contact_node()) && (!scheme.needs_diagonal_mass() || mass == BarMass::Lumped)
}

/// Parses mass treatments (`std`, `lumped`, `mod`, ...), each piece trimmed; an error names `--masses`.
pub fn parse_masses(raw: &[String]) -> Result<Vec<BarMass>, StudyError> {
    raw.iter().map(|s| s.trim().parse::<BarMass>().map_err(|e| StudyError::config("masses", format!("⟨masses⟩: {e}")))).collect()
}

/// Refuses `copies` runs of `elements` elements at once beyond the
/// machine's available memory (the estimate of `signorini check`); the
/// error names `flag`.
pub fn fits_memory(flag: &str, elements: usize, copies: usize) -> Result<(), StudyError> {
    let need = signorini_scene::memory_estimate(elements, false) * copies.max(1) as f64;
    let have = signorini_scene::Limits::machine().max_memory;
    if need > have {
        return Err(StudyError::config(
            flag,
            format!("{}: {elements} elements need about {} of memory ({copies} at once), beyond the {} available", options::at(flag), signorini_scene::bytes(need), signorini_scene::bytes(have)),
        ));
    }
    Ok(())
}

/// Wall time since `start`, in seconds.
pub(crate) fn since(start: std::time::Instant) -> f64 {
    start.elapsed().as_secs_f64()
}
