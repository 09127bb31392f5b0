//! # signorini-cli
//!
//! The `signorini` command: `run` a TOML scene, `list` what is available,
//! `check` a scene (validation, stability limit, cost estimate), `sweep` and
//! `merge`. The scene format, its validation and instantiation live in
//! `signorini-scene` (re-exported as [`scene`]) and the sweep engine in
//! `signorini-sweep` ([`sweep`]); this crate holds what is the command's
//! own: output folders, files and plots of `run`, progress bars, signals,
//! the texts of `check` and `list`. `src/main.rs` is only argument parsing.
//!
//! `signorini list` is the registry's:
//!
//! ```
//! let text = signorini_cli::list();
//! assert!(text.contains("newmark-cn") && text.contains("cd-taylor") && text.contains("moreau-jean(THETA,E[,GAMMA])"));
//! ```
//!
//! Output files of `signorini run` (a contract: columns only ever added):
//! * bar: `series.csv` — `n,t,u_contact,v_contact,lambda_t,lambda,energy_t,energy`, plus
//!   `u_contact_exact,lambda_exact,energy_exact` when the scene uses a
//!   benchmark; `norms.csv` (benchmark only) — one row with the columns of the
//!   convergence study (`m,dx,dt,steps,linf_l2_u,…,l2_energy,wall_s,setup_s,step_s`);
//!   `snapshots.csv` (`n,t,x,u`) when `output.snapshots_every > 0`;
//!   `u_contact.svg`, `lambda.svg`, `energy.svg` (numerical against exact).
//! * beam: `series.csv` — `n,t_s,tip_m,v_tip_m_s,lambda_t,lambda`; `tip.svg`.
//! * oscillator: `series.csv` — `n,t,x,v,lambda_t,lambda,energy_t,energy`; `x.svg`.
//! * any scene, when `[output]` asks (`impacts`, `poincare`, `summary`):
//!   `impacts.csv` (`stop,t,phase,velocity,impulse,duration`) and
//!   `impact_map.svg`, `poincare.csv` (`t,displacement,velocity`) and
//!   `poincare.svg`, `summary.csv` (the columns of
//!   [`signorini_run::vibro::Summary`]). Sweeps: [`sweep`].
//! * any scene with `scheme = "event-driven"` (the exact reference,
//!   docs/theory.md §9): `events.csv` — `t,kind,contact,velocity_before,velocity_after,impulse`,
//!   one row per event (`kind`: `impact`, `release`, `accumulation`), also
//!   when the run stops early.
//!
//! `v_contact` / `v_tip_m_s` is the backward difference of the contact dof
//! over the last step (empty at n = 0).
//!
//! Every run watches its energy against its budget (`signorini_run::energy`):
//! the printed summary has `energy: largest E/budget … at t = …`, and when
//! E exceeds `[output] energy_warn` (default 2) × the budget, one warning
//! goes to stderr ([`Summary::warnings`]) with the factor, the time and
//! step. No file gets a column for it: `norms.csv` keeps the convergence
//! study's columns (`LEVEL_COLUMNS`, shared with its level files).
//!
//! * beam with `output.snapshots_every > 0`: `snapshots.csv` — `n,t_s,x_m,u_m`,
//!   the absolute displacement `ũ(x, t) = u(x, t) + h(x) φ(t)` at the nodes
//!   (`x = 0` is the support, `ũ = φ`).
//! * with `[[stop]]` / `[obstacle]` (only then), `series.csv` appends per
//!   contact, in contact order, `u_c<i>,lambda_<i>,active_<i>` (`active`:
//!   `-1` lower bound, `1` upper, `0` free); `u_contact` and `lambda` are
//!   contact 0's (the beam's `tip_m` stays the tip); `lambda.svg` (bar and
//!   beam) shows every contact's force: one line each up to 12 contacts,
//!   else a heat map of contacts against time.
//!
//! Rows go out whole (one write call per block of complete rows, every
//! 64 KiB or 1024 rows and at the end), also when a run blows up or is
//! interrupted (SIGINT/SIGTERM: the run stops at the next step — an
//! event-driven one inside its step, within 256 steps of its event search —
//! writes what it holds and its plots, exits 130). A SIGKILL can cut the write in
//! flight: every newline-terminated line is then a complete row, and a
//! reader drops a last line without a newline.
//!
//! The output folder must not hold another run's files (any of
//! [`OUTPUT_FILES`]): `run` refuses it unless asked to `clean` them first.

pub use signorini_scene as scene;
pub use signorini_scene::excitation;
pub use signorini_sweep as sweep;
pub mod basins;
pub mod orbits;

pub use scene::{check_report, energy_warning, CheckReport};
use scene::{free_space, io_reason as reason, output_estimate, sig12, sig6, ContactSet, Reads, Scene, SceneFile};
use signorini_plot::{heat_map, line_chart, Chart, Scale, Series, Style};
use signorini_run::study::{norm_value, LEVEL_COLUMNS, NORMS};
use signorini_run::{Observer, RowSink, RunConfig, RunError, Sample, SeriesWriter};
use signorini_schemes::TimeProfile;
use std::fs::File;
use std::io::Write;
use std::path::Path;

/// Every file `signorini run` writes.
pub const OUTPUT_FILES: [&str; 14] = [
    "series.csv",
    "norms.csv",
    "snapshots.csv",
    "u_contact.svg",
    "lambda.svg",
    "energy.svg",
    "tip.svg",
    "x.svg",
    "impacts.csv",
    "poincare.csv",
    "summary.csv",
    "impact_map.svg",
    "poincare.svg",
    "events.csv",
];

/// Errors of the command.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] scene::SceneError),
    /// A sweep's options, shards or folder.
    #[error(transparent)]
    Sweep(#[from] sweep::SweepError),
    /// The run failed (blow-up, instability, …).
    #[error(transparent)]
    Run(#[from] RunError),
    /// `signorini continue` was interrupted (SIGINT/SIGTERM): the branch so
    /// far is written.
    #[error("interrupted: the branch so far is written in {dir}")]
    ContinueInterrupted {
        /// The folder.
        dir: String,
    },
    /// A continuation's options, scene or Newton solve (`signorini continue`).
    #[error(transparent)]
    Orbits(#[from] signorini_orbits::OrbitError),
    /// A file of the output folder cannot be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A CSV file of the output folder cannot be written.
    #[error("cannot write {}: {source}", path.display())]
    Csv {
        /// The file.
        path: std::path::PathBuf,
        /// The cause.
        source: csv::Error,
    },
    /// An earlier run's file cannot be removed (`--clean`).
    #[error("cannot remove {}: {source}", path.display())]
    Remove {
        /// The file.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A scene could not be instantiated (other than an invalid scene or a
    /// failed run, which are [`CliError::Scene`] and [`CliError::Run`]).
    #[error(transparent)]
    Build(scene::BuildError),
    /// A sweep failed while running or writing its folder (bad input and
    /// interrupts are the variants above).
    #[error(transparent)]
    SweepRun(sweep::Error),
    /// The scene file cannot be read (missing, a folder, no permission).
    #[error("cannot read the scene file {}: {}", path.display(), reason(source))]
    SceneFile {
        /// The path given.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// `--out` cannot be a folder (a file of that name, no permission).
    #[error("--out {}: {}", path.display(), out_reason(source))]
    OutFolder {
        /// The path given.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The output folder holds another run's files.
    #[error("output folder {dir} holds files of an earlier run ({files}): pass --clean to remove them first, or choose another --out")]
    Stale {
        /// The folder.
        dir: String,
        /// The files found.
        files: String,
    },
    /// The output would not fit on the disk.
    #[error("the run would write about {need} into {dir}, which has {free} free: write fewer rows (output.every, output.snapshots_every), shorten t_end, or pass --no-disk-check")]
    Disk {
        /// Estimated output size.
        need: String,
        /// Free space.
        free: String,
        /// The folder.
        dir: String,
    },
    /// A sweep was interrupted (SIGINT/SIGTERM) between runs: whole runs kept.
    #[error("interrupted after {done} of {total} runs (whole runs kept in {dir}); continue with --resume")]
    SweepInterrupted {
        /// Runs written.
        done: usize,
        /// Runs of the sweep (or shard).
        total: usize,
        /// The folder.
        dir: String,
    },
    /// `signorini basins` was interrupted (SIGINT/SIGTERM) between cells:
    /// whole rows kept.
    #[error("interrupted after {done} of {total} cells (whole rows kept in {dir}/basins.csv)")]
    BasinsInterrupted {
        /// Cells written.
        done: usize,
        /// Cells of the grid (or shard).
        total: usize,
        /// The folder.
        dir: String,
    },
    /// A sweep ran to its end, and some of its runs failed (blow-up, …):
    /// their rows are kept, their status says why.
    #[error("{failed} of {total} runs failed (their status in {dir}/summary.csv says why; the rows they wrote are kept)")]
    SweepFailed {
        /// Runs whose status is not `ok`.
        failed: usize,
        /// Runs of the sweep (or shard).
        total: usize,
        /// The folder.
        dir: String,
    },
    /// The run stopped early (blow-up, interrupt); notes on what was still
    /// written (plots skipped) follow the error.
    #[error("{error}{}", notes.iter().map(|n| format!("\nnote: {n}")).collect::<String>())]
    Stopped {
        /// Why the run stopped.
        error: RunError,
        /// What happened to the outputs.
        notes: Vec<String>,
    },
}

impl From<scene::BuildError> for CliError {
    fn from(e: scene::BuildError) -> Self {
        match e {
            scene::BuildError::Scene(e) => CliError::Scene(e),
            scene::BuildError::Run(e) => CliError::Run(e),
            other => CliError::Build(other),
        }
    }
}

impl From<sweep::Error> for CliError {
    fn from(e: sweep::Error) -> Self {
        match e {
            sweep::Error::Options(e) => CliError::Sweep(e),
            sweep::Error::Scene(e) => CliError::Scene(e),
            sweep::Error::Build(e) => e.into(),
            sweep::Error::OutFolder { path, source } => CliError::OutFolder { path, source },
            sweep::Error::Interrupted { done, total, dir } => CliError::SweepInterrupted { done, total, dir },
            other => CliError::SweepRun(other),
        }
    }
}

impl CliError {
    /// The process exit code: 2 for an invalid scene or command (nothing
    /// was run), 130 for an interrupted run, 3 for a sweep that ran to its
    /// end with failed runs, 1 for a run that failed.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Orbits(signorini_orbits::OrbitError::Option { .. } | signorini_orbits::OrbitError::Scene(_)) => 2,
            CliError::Scene(_) | CliError::Sweep(_) | CliError::Stale { .. } | CliError::Disk { .. } | CliError::SceneFile { .. } | CliError::OutFolder { .. } => 2,
            CliError::Run(RunError::Interrupted { .. })
            | CliError::Stopped { error: RunError::Interrupted { .. }, .. }
            | CliError::SweepInterrupted { .. }
            | CliError::ContinueInterrupted { .. }
            | CliError::BasinsInterrupted { .. } => 130,
            CliError::SweepFailed { .. } => 3,
            _ => 1,
        }
    }
}

/// Why `--out` is not a usable folder.
fn out_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::AlreadyExists | std::io::ErrorKind::NotADirectory => "is a file (or has a file on its path), not a folder: choose another --out".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied: choose another --out".into(),
        _ => format!("{e}: choose another --out"),
    }
}

/// Reads a scene file: a missing or unreadable file is bad input.
pub fn read_scene_file(path: &Path) -> Result<String, CliError> {
    std::fs::read_to_string(path).map_err(|source| CliError::SceneFile { path: path.to_path_buf(), source })
}

/// The run stopped early: `notes` say what happened to the outputs, and the
/// rows written into `out` so far are kept.
fn stopped(error: RunError, mut notes: Vec<String>, out: &Path) -> CliError {
    notes.push(format!("the rows written so far are kept in {}", out.display()));
    CliError::Stopped { error, notes }
}

/// How `run_scene` runs (`RunOptions::default()`, then the fields).
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct RunOptions {
    /// Draw a progress bar with an ETA on stderr.
    pub progress: bool,
    /// Remove an earlier run's files from the output folder first.
    pub clean: bool,
    /// Skip the free-space check.
    pub no_disk_check: bool,
    /// Stop cleanly when this token is cancelled (by a signal handler).
    pub interrupt: Option<signorini_run::Cancel>,
}

/// Reads and validates a scene file within `limits`.
pub fn load(path: &Path, limits: &scene::Limits) -> Result<(SceneFile, Scene), CliError> {
    let text = read_scene_file(path)?;
    let file = SceneFile::parse(&text)?;
    let scene = file.validate_with(limits)?;
    Ok((file, scene))
}

/// Output files are opened unbuffered: the writers ([`RowSink`]) buffer
/// whole rows themselves and hand each block over with one write call.
fn create(dir: &Path, name: &str) -> Result<File, CliError> {
    let p = dir.join(name);
    File::create(&p).map_err(|source| CliError::Write { path: p, source })
}

/// One plotted level: `(t, u_c)`, `(t, λ)` when stepped, `(t, E)` when computed.
type PlotPoint = (f64, f64, Option<(f64, f64)>, Option<(f64, f64)>);

/// A decimated copy of the contact-dof history for the plots, and the
/// largest |u_c| over every level.
struct PlotData {
    every: usize,
    dof: usize,
    points: Vec<PlotPoint>,
    max_abs: f64,
    /// Several contacts: every contact's force.
    forces: Option<ForcePlot>,
}

impl PlotData {
    fn new(steps: usize, dof: usize, contacts: Option<&ContactSet>) -> Self {
        let every = scene::plot_every(steps);
        let forces = contacts.map(|c| {
            let k = c.sites.len();
            if k <= MAX_FORCE_LINES {
                ForcePlot::Lines { t: Vec::new(), f: vec![Vec::new(); k] }
            } else {
                ForcePlot::Map { steps: steps.max(1), cells: vec![0.0; k * MAP_BINS] }
            }
        });
        Self { every, dof, points: Vec::new(), max_abs: 0.0, forces }
    }
}

/// Contacts beyond which the force plot is a heat map, not one line each,
/// and its time bins (the output estimate counts the same).
use scene::{FORCE_MAP_BINS as MAP_BINS, MAX_FORCE_LINES};

/// Every contact's force for `lambda.svg`: one line per contact (at the
/// decimated levels), or, beyond [`MAX_FORCE_LINES`] contacts, the force of
/// largest magnitude of each contact in each of [`MAP_BINS`] time bins.
enum ForcePlot {
    Lines { t: Vec<f64>, f: Vec<Vec<f64>> },
    Map { steps: usize, cells: Vec<f64> },
}

impl Observer for PlotData {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let u = s.u[self.dof];
        self.max_abs = self.max_abs.max(u.abs());
        let keep = s.n % self.every == 0;
        if keep {
            self.points.push((s.t, u, s.lambda, s.energy));
        }
        match (&mut self.forces, s.lambda) {
            (Some(ForcePlot::Lines { t, f }), Some((tl, _))) if keep => {
                t.push(tl);
                for (line, v) in f.iter_mut().zip(s.forces) {
                    line.push(*v);
                }
            }
            (Some(ForcePlot::Map { steps, cells }), Some(_)) => {
                let bin = (s.n.min(*steps) * MAP_BINS / (*steps + 1)).min(MAP_BINS - 1);
                for (i, v) in s.forces.iter().enumerate() {
                    if let Some(c) = cells.get_mut(i * MAP_BINS + bin) {
                        if v.abs() > c.abs() || v.is_nan() {
                            *c = *v;
                        }
                    }
                }
            }
            _ => {}
        }
        Ok(())
    }
}

/// A contact's name in plots: `λ_<i> (stop.<j>, x = …)` or `λ_<i> (obstacle, x = …)`.
fn contact_label(set: &ContactSet, i: usize) -> String {
    let site = &set.sites[i];
    match site.stop {
        Some((j, _)) => format!("λ_{i} (stop.{j}, x = {})", site.x),
        None => format!("λ_{i} (obstacle, x = {})", site.x),
    }
}

/// `lambda.svg` with several contacts: one line per contact, or a heat map
/// of every contact's force (rows) over time (columns) beyond
/// [`MAX_FORCE_LINES`] contacts.
fn plot_forces(notes: &mut Vec<String>, dir: &Path, set: &ContactSet, forces: &ForcePlot, t_end: f64, unit: &str) {
    let name = "lambda.svg";
    let written = match forces {
        ForcePlot::Lines { t, f } => {
            let series: Vec<Series> = f
                .iter()
                .enumerate()
                .map(|(i, line)| Series {
                    label: contact_label(set, i),
                    points: t.iter().copied().zip(line.iter().copied()).filter(|p| p.0.is_finite() && p.1.is_finite()).collect(),
                    reference: false,
                    style: Style { group: Some(i), variant: None },
                })
                .collect();
            if series.iter().all(|s| s.points.is_empty()) {
                notes.push(format!("{name} not written: no finite point to plot"));
                return;
            }
            let y = format!("λ_i{unit}");
            let t = if unit.is_empty() { "t" } else { "t (s)" };
            line_chart(&Chart { title: "contact forces λ_i(t) (<= 0 at a lower bound, >= 0 at an upper one)", x_label: t, y_label: &y, scale: Scale::Linear, size: (900, 450) }, &series)
        }
        ForcePlot::Map { cells, .. } => {
            let k = set.sites.len();
            let label_every = k.div_ceil(100);
            let rows: Vec<String> = (0..k).map(|i| if i % label_every == 0 { format!("{i}: x = {:.4}", set.sites[i].x) } else { String::new() }).collect();
            let cols: Vec<String> = (0..MAP_BINS).map(|b| if b % 10 == 0 { format!("{:.3}", t_end * b as f64 / MAP_BINS as f64) } else { String::new() }).collect();
            let values: Vec<Vec<f64>> = cells.chunks(MAP_BINS).map(<[f64]>::to_vec).collect();
            let height = (120 + 14 * k).clamp(400, 2400) as u32;
            heat_map(
                &format!("contact forces λ_i{unit}: contact i (rows) against t (columns); blue lowest, red highest (largest |λ_i| in each time bin)"),
                &rows,
                &cols,
                &values,
                false,
                (1100, height),
            )
        }
    }
    .map_err(|e| e.to_string())
    .and_then(|svg| std::fs::write(dir.join(name), svg).map_err(|e| e.to_string()));
    if let Err(e) = written {
        notes.push(format!("{name} not written: {e}"));
    }
}

/// The displacement at the nodes every k steps: `n,t,x,u` (bar) or
/// `n,t_s,x_m,u_m` (beam, absolute).
struct Snapshots {
    out: RowSink<File>,
    every: usize,
    /// `(x, unknown holding u(x) or None where u = 0, lifting h(x))`.
    nodes: Vec<(f64, Option<usize>, f64)>,
    /// The support motion `φ(t)` (beam), added as `h(x) φ(t)`.
    support: Option<TimeProfile>,
}

impl Snapshots {
    fn new(dir: &Path, header: &str, every: usize, nodes: Vec<(f64, Option<usize>, f64)>, support: Option<TimeProfile>) -> Result<Self, CliError> {
        let mut out = RowSink::new(create(dir, "snapshots.csv")?);
        out.row(|b| b.write_all(header.as_bytes()))?;
        Ok(Self { out, every, nodes, support })
    }
}

impl Observer for Snapshots {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if s.n % self.every != 0 {
            return Ok(());
        }
        let phi = self.support.as_ref().map_or(0.0, |p| p.value(s.t));
        for &(x, dof, h) in &self.nodes {
            let u = dof.and_then(|i| s.u.get(i).copied()).unwrap_or(0.0) + h * phi;
            self.out.row(|b| write!(b, "{},{:.12e},{x:.12e},{u:.12e}", s.n, s.t))?;
        }
        Ok(())
    }
    fn finish(&mut self) -> Result<(), RunError> {
        self.out.flush()
    }
}

/// A progress line on a terminal.
struct Progress {
    bar: indicatif::ProgressBar,
    every: usize,
}

impl Observer for Progress {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        // Cheap (an atomic store); indicatif redraws at most 20 times a second.
        if s.n % self.every == 0 {
            self.bar.set_position(s.n as u64);
        }
        Ok(())
    }
    fn finish(&mut self) -> Result<(), RunError> {
        self.bar.finish_and_clear();
        Ok(())
    }
}

fn progress(total: usize, show: bool) -> Progress {
    Progress { bar: progress_bar(total as u64, show, "steps"), every: (total / 10_000).max(1) }
}

/// A progress bar with an ETA on stderr (hidden unless `show`).
/// A spinner with a message on stderr (hidden unless `show`): a
/// continuation's points as they come (their number is not known ahead).
pub(crate) fn progress_spinner(show: bool) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let b = indicatif::ProgressBar::new_spinner();
    b.set_style(indicatif::ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}").unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()));
    b
}

fn progress_bar(total: u64, show: bool, unit: &str) -> indicatif::ProgressBar {
    let target = if show { indicatif::ProgressDrawTarget::stderr() } else { indicatif::ProgressDrawTarget::hidden() };
    let bar = indicatif::ProgressBar::with_draw_target(Some(total), target);
    let template = format!("{{bar:40}} {{pos}}/{{len}} {unit}, {{elapsed}} elapsed, ETA {{eta}}");
    bar.set_style(indicatif::ProgressStyle::with_template(&template).unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()));
    bar
}

/// A sweep's progress bar (runs) on stderr, hidden unless `show`.
pub struct RunsBar(indicatif::ProgressBar);

impl RunsBar {
    /// A bar drawn on stderr when `show`.
    pub fn new(show: bool) -> Self {
        Self(progress_bar(0, show, "runs"))
    }
}

impl sweep::Progress for RunsBar {
    fn start(&self, total: u64, done: u64) {
        self.0.set_length(total);
        self.0.set_position(done);
    }
    fn advance(&self, runs: u64) {
        self.0.inc(runs);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct Summary {
    /// Lines for the terminal.
    pub lines: Vec<String>,
    /// Warnings for stderr (at most one: the energy grew past
    /// `[output] energy_warn` × its budget).
    pub warnings: Vec<String>,
}

/// The summary line of the energy monitor (the largest E/budget) and, if
/// the energy went past the factor, the one warning.
fn energy_report(s: &signorini_run::RunSummary, lines: &mut Vec<String>) -> Vec<String> {
    use signorini_run::text::num;
    let Some(g) = s.energy else { return Vec::new() };
    let budget = if g.closed { "E_ref + load/support work − dissipation" } else { "E_ref + Σ|load work|: the scheme does not track its work" };
    lines.push(format!("energy: largest E/budget {} at t = {} (budget {budget}; warn above {})", num(sig6(g.max_ratio)), num(sig12(g.max_ratio_time)), num(g.factor)));
    energy_warning(&g).map(|w| format!("warning: {w}")).into_iter().collect()
}

/// Writes one plot; a plot never fails a run: a problem becomes a note.
/// Non-finite points are left out (a blown-up run plots what was finite).
/// `t` is the time axis's label (`t (s)` where the scene has units).
fn plot(notes: &mut Vec<String>, dir: &Path, name: &str, title: &str, (t, y): (&str, &str), num: Vec<(f64, f64)>, exact: Option<Vec<(f64, f64)>>) {
    let finite = |v: Vec<(f64, f64)>| -> Vec<(f64, f64)> { v.into_iter().filter(|p| p.0.is_finite() && p.1.is_finite()).collect() };
    let num = finite(num);
    if num.is_empty() {
        notes.push(format!("{name} not written: no finite point to plot"));
        return;
    }
    let mut s = vec![Series { label: "numerical".into(), points: num, reference: false, style: Default::default() }];
    if let Some(e) = exact {
        s.push(Series { label: "exact".into(), points: finite(e), reference: true, style: Default::default() });
    }
    let written = line_chart(&Chart { title, x_label: t, y_label: y, scale: Scale::Linear, size: (900, 450) }, &s)
        .map_err(|e| e.to_string())
        .and_then(|svg| std::fs::write(dir.join(name), svg).map_err(|e| e.to_string()));
    if let Err(e) = written {
        notes.push(format!("{name} not written: {e}"));
    }
}

/// Refuses an output folder holding another run's files, or removes them
/// (`clean`); then creates the folder. Files that are not the run's own are
/// never touched.
fn prepare_output(out: &Path, clean: bool) -> Result<(), CliError> {
    let stale: Vec<&str> = OUTPUT_FILES.iter().copied().filter(|f| out.join(f).exists()).collect();
    if !stale.is_empty() {
        if !clean {
            return Err(CliError::Stale { dir: out.display().to_string(), files: stale.join(", ") });
        }
        for f in stale {
            std::fs::remove_file(out.join(f)).map_err(|source| CliError::Remove { path: out.join(f), source })?;
        }
    }
    std::fs::create_dir_all(out).map_err(|source| CliError::OutFolder { path: out.to_path_buf(), source })
}

/// Runs a validated scene, writing into `out` (see the module docs for the
/// files, the folder rule and interrupts).
pub fn run_scene(scene: &Scene, scene_file: &SceneFile, out: &Path, opts: &RunOptions) -> Result<Summary, CliError> {
    if !opts.no_disk_check {
        // An event-driven run's events.csv: from a bounded probe of its
        // events, run only where its estimate could refuse the run (the
        // file's bound at max_events does not fit: the probe steps the run
        // a second time, up to the whole horizon).
        let free = free_space(out);
        let mut need = output_estimate(scene, &scene_file.output);
        if let Some(bound) = scene::EventProbe::bytes_bound_unprobed(scene) {
            if free.is_some_and(|f| need <= f && need + bound > f) {
                need += scene::event_probe(scene)?.map_or(0.0, |p| p.bytes_estimate());
            }
        }
        if let Some(free) = free {
            if need > free {
                return Err(CliError::Disk { need: scene::bytes(need), free: scene::bytes(free), dir: out.display().to_string() });
            }
        }
    }
    prepare_output(out, opts.clean)?;
    // norms.csv's setup_s: from here to the loop (the scene's problem was
    // built, and its integrator once for validation, when it was read).
    let setup_start = std::time::Instant::now();
    let facts = scene.facts();
    let file = scene_file;
    let exact = scene.exact()?;
    // A reduced model steps in reduced coordinates; the observers see the
    // scene's unknowns, reconstructed (only the contact rows for those that
    // read the contacts alone): `run_observed`.
    let mut sim = scene.instantiate(None)?;
    let mut cfg = RunConfig::new(facts.dt, facts.t_end)?.with_energy_warn(file.energy_warn())?;
    cfg.interrupt = opts.interrupt.clone();
    let steps = cfg.steps();
    // The series' tip is contact 0's dof (the bar's first stop, the
    // oscillator's dof, the beam's tip); with a contact set, every contact's
    // dof of the scene's unknowns, in contact order.
    let dofs: Option<Vec<usize>> = facts.contacts.map(|_| sim.contacts().iter().map(|c| c.0).collect());
    let cols = facts.series_columns(exact.as_deref(), dofs.as_deref());
    let mut series = SeriesWriter::new(create(out, "series.csv")?, file.output.every, sim.tip, cols)?;
    let mut data = PlotData::new(steps, sim.tip, facts.contacts);
    let mut norms = facts.norms.zip(exact.as_deref()).map(|(n, e)| n.observer(e, facts.dt));
    let mut snaps = match scene.snapshot_nodes().filter(|_| file.output.snapshots_every > 0) {
        Some(s) => Some(Snapshots::new(out, s.header, file.output.snapshots_every, s.nodes, s.support)?),
        None => None,
    };
    let mut vib = Analysis::new(file, out, &sim, facts.dt, facts.t_end, facts.omega)?;
    let mut prog = progress(steps, opts.progress);
    let setup_s = setup_start.elapsed().as_secs_f64();
    let start = std::time::Instant::now();
    let res = run_observed(
        &mut sim,
        &cfg,
        vec![(Reads::Contacts, &mut series), (Reads::Contacts, &mut data), (Reads::Nothing, &mut prog)],
        [
            norms.as_mut().map(|n| (Reads::Full, n as &mut dyn Observer)),
            vib.as_mut().map(|v| (Reads::Contacts, &mut v.vibro as &mut dyn Observer)),
            snaps.as_mut().map(|s| (Reads::Full, s as &mut dyn Observer)),
        ],
    );
    write_events(out, &sim)?;
    let wall = start.elapsed().as_secs_f64();
    let mut notes = Vec::new();
    if file.output.plots {
        let t_max = data.points.last().map_or(0.0, |p| p.0);
        let grid = |f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> { (0..=scene::EXACT_CURVE_SEGMENTS).map(|i| t_max * i as f64 / scene::EXACT_CURVE_SEGMENTS as f64).map(|t| (t, f(t))).collect() };
        let exact_curve = |p: &scene::Plot| {
            let e = exact.as_deref()?;
            Some(match p.exact? {
                scene::ExactCurve::U(x) => grid(&|t| e.fields(x, t).u),
                scene::ExactCurve::Lambda => grid(&|t| e.lambda(t)),
                scene::ExactCurve::Energy => grid(&|_| e.energy()),
                _ => return None,
            })
        };
        let p = &facts.tip_plot;
        plot(&mut notes, out, p.file, &p.title, p.axes, data.points.iter().map(|p| (p.0, p.1)).collect(), exact_curve(p));
        match (facts.contacts, &data.forces, &facts.lambda_plot) {
            (Some(set), Some(f), _) => plot_forces(&mut notes, out, set, f, facts.t_end, facts.force_unit),
            (_, _, Some(p)) => plot(&mut notes, out, p.file, &p.title, p.axes, data.points.iter().filter_map(|p| p.2).collect(), exact_curve(p)),
            _ => {}
        }
        if let Some(p) = &facts.energy_plot {
            plot(&mut notes, out, p.file, &p.title, p.axes, data.points.iter().filter_map(|p| p.3).collect(), exact_curve(p));
        }
    }
    let analysis_lines = match vib {
        Some(v) => v.finish(file.output.plots, &mut notes)?,
        None => Vec::new(),
    };
    // A run that stopped early has no norms over [0, T]: no norms.csv.
    let s = match res {
        Ok(s) => s,
        Err(error) => return Err(stopped(error, notes, out)),
    };
    let mut lines = vec![facts.run_line(file, s.steps, s.contact_steps, wall, data.max_abs)];
    lines.extend(analysis_lines);
    if let (Some(n), Some(f)) = (norms, facts.norms) {
        let r = n.report();
        let mut w = csv::Writer::from_writer(create(out, "norms.csv")?);
        let csv_err = |source| CliError::Csv { path: out.join("norms.csv"), source };
        w.write_record(LEVEL_COLUMNS).map_err(csv_err)?;
        // The study's level m (bar-mirrored's m elements per half-bar) and dx.
        let (level, dx) = f.level();
        let mut rec = vec![level.to_string(), format!("{dx:.10e}"), format!("{:.10e}", facts.dt), s.steps.to_string()];
        rec.extend(NORMS.iter().map(|k| format!("{:.10e}", norm_value(&r, k))));
        // wall_s (the loop, as always), then setup_s and step_s (= wall_s here).
        rec.extend([format!("{wall:.6}"), format!("{setup_s:.6}"), format!("{wall:.6}")]);
        w.write_record(&rec).map_err(csv_err)?;
        w.flush().map_err(|source| CliError::Write { path: out.join("norms.csv"), source })?;
        lines.push(format!(
            "errors: L∞(L²) {:.4e}, L²(L²) {:.4e}, L∞(V) {:.4e}, L²(λ) {:.4e}, L∞(E) {:.4e}; λ TV ratio {:.2}",
            r.linf_l2_u, r.l2_l2_u, r.linf_v_u, r.l2_lambda, r.linf_energy, r.lambda_tv_ratio
        ));
    }
    let warnings = energy_report(&s, &mut lines);
    lines.extend(notes.into_iter().map(|n| format!("note: {n}")));
    lines.push(format!("wrote {}", out.display()));
    Ok(Summary { lines, warnings })
}

/// `signorini check`: what a run would do, its stability, memory, output
/// size (against the free space of `out`) and cost.
pub fn check(scene: &Scene, file: &SceneFile, out: &Path) -> Result<String, CliError> {
    Ok(check_report(scene, file, out)?.text)
}

/// `signorini list`: every preset and scheme family of the registry
/// (`signorini_schemes::FAMILIES`), with what each needs and takes.
pub fn list() -> String {
    use signorini_schemes::{Capabilities, Node, SchemeSpec, FAMILIES};
    let needs = |c: &Capabilities| -> String {
        let node = match (c.node, c.diagonal_mass) {
            (_, true) => "lumped only",
            (Node::Massive, _) => "std or lumped only",
            (Node::Massless, _) => "massless-node masses only",
            (Node::Any, _) => "",
        };
        let mut v: Vec<&str> = vec![if c.explicit { "explicit" } else { "implicit" }];
        if !node.is_empty() {
            v.push(node);
        }
        v.extend(
            [
                (c.restitution, "restitution"),
                (c.stiffness, "contact stiffness"),
                (c.damping, "damping"),
                (c.forcing, "time-dependent load"),
                (c.several_contacts, "several contacts"),
                (c.beam, "beam"),
            ]
            .iter()
            .filter(|t| t.0)
            .map(|t| t.1),
        );
        v.join(", ")
    };
    let mut s = String::from("schemes (presets):\n");
    for (name, spec, _) in SchemeSpec::presets() {
        s.push_str(&format!("  {name:<16} {:<20} [{}]\n", spec.call(), needs(&spec.capabilities())));
    }
    s.push_str("scheme families (what each call takes):\n");
    for f in FAMILIES {
        let ranges = if f.params.is_empty() { String::new() } else { format!("  {}", f.ranges()) };
        s.push_str(&format!("  {}\n      {}\n", format!("{:<24}{ranges}", f.syntax()).trim_end(), f.about));
        // A family without presets is listed above by no preset: what it
        // takes (at its defaults, as `families_with` reads it) goes here.
        if f.presets.is_empty() {
            let defaults: Vec<f64> = f.params.iter().map(|p| p.default.unwrap_or(f64::NAN)).collect();
            s.push_str(&format!("      [{}]\n", needs(&(f.capabilities)(&defaults))));
        }
    }
    s.push_str("masses (bar): std, lumped (massive contact node); mod = mod1, mod2, mod3, transfer, singular (massless contact node)\n");
    s.push_str("benchmarks (bar, with exact solutions): bar-dirichlet, bar-neumann-gravity (g = 1/9), bar-neumann-gravity-0.11 (T <= 225), bar-mirrored (bar-dirichlet mirrored onto [0, 2] between two stops; elements = m per half)\n");
    s.push_str("beam scenes: fig2 fig3 fig4 (β = 1/2, projection), fig5 fig6 fig7 (penalty 1e8 N/m), fig8 (β = 1/4); contact = \"projection\" (β ∈ [0, 1/2]) or \"penalty\" (stiffness > 0 N/m), or scheme = a preset or family marked beam above\n");
    s.push_str(&format!(
        "several contacts (bar or beam): [[stop]] x (a mesh node), lo, hi, restitution ∈ [0, 1] ({}, beam projection), stiffness > 0 ({}); [obstacle] lo, hi (number, expression in x or table)\n",
        signorini_schemes::families_with(|c| c.restitution),
        signorini_schemes::families_with(|c| c.stiffness)
    ));
    s
}

/// The analysis observers a scene's `[output]` asks for (`impacts`,
/// `poincare`, `summary`), writing `impacts.csv` / `poincare.csv` as they
/// go and `summary.csv`, `impact_map.svg`, `poincare.svg` at the end.
struct Analysis {
    vibro: signorini_run::vibro::Vibro<File, File>,
    out: std::path::PathBuf,
    summary: bool,
}

impl Analysis {
    fn new(file: &SceneFile, out: &Path, sim: &signorini_scene::Simulation, dt: f64, t_end: f64, omega: Option<f64>) -> Result<Option<Self>, CliError> {
        use signorini_run::vibro::{Piece, VibroConfig};
        let o = &file.output;
        if !(o.impacts || o.poincare || o.summary) {
            return Ok(None);
        }
        // `poincare` without a forcing and an empty record window are refused by the scene's validation.
        let record_from = o.record_from(omega);
        // The tip and the contacts in the scene's unknowns (a reduced model's parent's).
        let mut cfg = VibroConfig::new(dt, omega, record_from, sim.tip, sim.contacts())?;
        cfg.t_end = Some(t_end);
        cfg.period_tol = o.period_tol.unwrap_or(cfg.period_tol);
        let impacts = if o.impacts {
            // The observers write their own headers.
            Piece::Csv(create(out, "impacts.csv")?)
        } else if o.summary {
            Piece::Memory
        } else {
            Piece::Off
        };
        let poincare = if o.poincare { Piece::Csv(create(out, "poincare.csv")?) } else { Piece::Off };
        let vibro = cfg.build(impacts, poincare, o.summary)?;
        Ok(Some(Self { vibro, out: out.to_path_buf(), summary: o.summary }))
    }

    /// Writes `summary.csv` and the plots; lines for the terminal.
    fn finish(self, plots: bool, notes: &mut Vec<String>) -> Result<Vec<String>, CliError> {
        let mut lines = Vec::new();
        let s = self.vibro.summary();
        if self.summary {
            let mut buf = format!("{}\n", signorini_run::vibro::Summary::csv_header()).into_bytes();
            let write_err = |source| CliError::Write { path: self.out.join("summary.csv"), source };
            s.write_row(&mut buf).map_err(write_err)?;
            buf.push(b'\n');
            std::fs::write(self.out.join("summary.csv"), buf).map_err(write_err)?;
            if let Some(st) = s.impacts {
                lines.push(format!("impacts in the record window: {} ({:.4} per period), mean impulse {:.4e}, impact power {:.4e}", st.count, st.per_period, st.mean_impulse, st.power));
            }
            if let Some((n, p)) = s.poincare {
                lines.push(match p {
                    Some(p) => format!("response: period-{p} over {n} Poincaré samples"),
                    None => format!("response: not periodic over {n} Poincaré samples"),
                });
            }
        }
        if plots {
            if let Some(im) = &self.vibro.impacts {
                match signorini_plot::impact_map(im.impacts().iter().map(|i| (i.stop, i.phase, i.velocity)), |_| 2) {
                    Ok(svg) => std::fs::write(self.out.join("impact_map.svg"), svg).map_err(|source| CliError::Write { path: self.out.join("impact_map.svg"), source })?,
                    Err(e) => notes.push(format!("impact_map.svg not written: {e}")),
                }
            }
            if let Some(p) = &self.vibro.poincare {
                let (pts, title) =
                    signorini_plot::thin(p.points().iter().map(|q| (q.displacement, q.velocity)).collect(), "Poincaré section: (displacement, velocity) at the forcing period", "samples");
                let chart = Chart { title: &title, x_label: "displacement", y_label: "velocity", scale: Scale::Linear, size: (700, 600) };
                match signorini_plot::scatter(&chart, &[Series { label: "section".into(), points: pts, reference: false, style: Style::default() }], 3) {
                    Ok(svg) => std::fs::write(self.out.join("poincare.svg"), svg).map_err(|source| CliError::Write { path: self.out.join("poincare.svg"), source })?,
                    Err(e) => notes.push(format!("poincare.svg not written: {e}")),
                }
            }
        }
        Ok(lines)
    }
}

/// Runs a simulation with the observers `always` and those of `optional`
/// that are present ([`signorini_scene::Simulation::run`]).
/// `events.csv` of an event-driven scheme (the events so far, also when
/// the run stopped early); nothing for a time-stepping one.
fn write_events(out: &Path, sim: &signorini_scene::Simulation) -> Result<(), CliError> {
    let Some(events) = sim.stepper.events() else { return Ok(()) };
    let path = out.join("events.csv");
    let f = std::io::BufWriter::new(create(out, "events.csv")?);
    signorini_run::observers::write_events(f, events).map_err(|source| CliError::Write { path, source })
}

fn run_observed<'a, const K: usize>(
    sim: &mut signorini_scene::Simulation,
    cfg: &RunConfig,
    mut always: Vec<(Reads, &'a mut dyn Observer)>,
    optional: [Option<(Reads, &'a mut dyn Observer)>; K],
) -> Result<signorini_run::RunSummary, RunError> {
    always.extend(optional.into_iter().flatten());
    sim.run(cfg, always)
}
