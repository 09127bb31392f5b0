//! What a scene would do before it runs (`signorini check`, Python's
//! `check()`), its output estimate, and the texts every front end prints
//! the same way (the energy warning, IO reasons).

use crate::{BuildError, OutputToml, Scene, SceneFile};
use signorini_run::RunConfig;
use std::path::Path;

/// An IO error in words, without the OS's error number.
pub fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        std::io::ErrorKind::IsADirectory => "a folder, not a file".into(),
        _ => e.to_string(),
    }
}

/// The energy-growth warning of a run (its text, without a `warning:`
/// prefix; Python emits it as `signorini.EnergyGrowthWarning`), if the
/// energy exceeded its budget by more than the factor.
pub fn energy_warning(g: &signorini_run::EnergyGrowth) -> Option<String> {
    use signorini_run::text::num;
    let x = g.exceeded?;
    Some(format!(
        "the discrete energy exceeds {} × its budget from t = {} (step {}: E = {}, budget {}, E/budget {}); largest E/budget {} at t = {}; the contact (or what else the scheme's energy identity does not balance, docs/theory.md §7) created energy: long runs of this scheme, mass and dt are not to be trusted",
        num(g.factor),
        num(sig12(x.time)),
        x.step,
        num(sig6(x.energy)),
        num(sig6(x.budget)),
        num(sig6(x.ratio)),
        num(sig6(g.max_ratio)),
        num(sig12(g.max_ratio_time)),
    ))
}

/// `x` to 6 significant digits (for the summary).
pub fn sig6(x: f64) -> f64 {
    format!("{x:.5e}").parse().unwrap_or(x)
}

/// `x` to 12 significant digits (times: `1.455`, not `1.4549999999999998`).
pub fn sig12(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

/// Bytes of one CSV row of `cols` numeric cells (`{:.12e}`: at most 20
/// characters and a comma) after a step counter of up to 10 digits.
fn row_bytes(cols: usize) -> f64 {
    11.0 + 21.0 * cols as f64
}

/// Levels a run's line plots keep: every `plot_every(steps)`-th level
/// (under 40 000 points a line).
pub fn plot_every(steps: usize) -> usize {
    (steps / 20_000).max(1)
}

/// The exact curve of a line plot: its value at this many equal intervals
/// of the plotted time, and the ends.
pub const EXACT_CURVE_SEGMENTS: usize = 2000;

/// An SVG plot's frame (axes, ticks, labels, legend), bytes, and a line
/// plot's bytes per point (plotters writes a polyline's points as pixel
/// pairs: 6–10 bytes each, measured on the scenes of `data/scenes`).
const SVG_FRAME: f64 = 20e3;
const SVG_POINT: f64 = 10.0;
/// A Poincaré sample's row in `poincare.csv` and dot in `poincare.svg`.
const POINCARE_ROW: f64 = 70.0;
const SCATTER_DOT: f64 = 40.0;

/// The size of what a run of `scene` writes (bytes), estimated from its
/// row counts and the plots it draws (line plots are decimated to under
/// 40 000 points a line, [`plot_every`]). `impacts.csv` and the impact map
/// are not included: they grow with the impacts, which are not known
/// before the run ([`output_estimate_note`] says so).
pub fn output_estimate(scene: &Scene, output: &OutputToml) -> f64 {
    let f = scene.facts();
    let (steps, series_cols, nodes) = (f.t_end / f.dt, f.series_width(), f.nodes as f64);
    let series = (steps / output.every.max(1) as f64 + 2.0) * row_bytes(series_cols);
    let snaps = if output.snapshots_every > 0 { (steps / output.snapshots_every as f64 + 1.0) * nodes * row_bytes(3) } else { 0.0 };
    // The Poincaré section: a sample per forcing period of the record window.
    let periods = f.omega.map_or(0.0, |w| ((f.t_end - output.record_from(f.omega)).max(0.0) * w / std::f64::consts::TAU).floor() + 1.0);
    let poincare = if output.poincare { periods * POINCARE_ROW } else { 0.0 };
    let plots = if output.plots { plots_estimate(&f, steps) + if output.poincare { SVG_FRAME + periods.min(SCATTER_POINTS as f64) * SCATTER_DOT } else { 0.0 } } else { 0.0 };
    series + snaps + poincare + plots
}

/// The scatter plots' point bound: `signorini_plot::MAX_PLOT_POINTS`
/// (the plot crate thins beyond it; the CLI's tests check the two agree).
pub const SCATTER_POINTS: usize = 100_000;
/// Contacts beyond which `lambda.svg` is a heat map, not one line each.
pub const MAX_FORCE_LINES: usize = 12;
/// Time bins of that heat map.
pub const FORCE_MAP_BINS: usize = 60;

/// The line plots' bytes: the tip, the contact force(s), the energy, each
/// with its exact curve where the scene has an exact solution.
fn plots_estimate(f: &crate::Facts<'_>, steps: f64) -> f64 {
    let steps = steps.max(0.0).ceil() as usize;
    let points = (steps / plot_every(steps) + 1) as f64;
    let exact = if f.norms.is_some() { EXACT_CURVE_SEGMENTS as f64 + 1.0 } else { 0.0 };
    let line = |p: &crate::Plot| SVG_FRAME + SVG_POINT * (points + if p.exact.is_some() { exact } else { 0.0 });
    let tip = line(&f.tip_plot);
    let forces = match (f.contacts, &f.lambda_plot) {
        // One line a contact, or a heat map of 60 time bins a contact.
        (Some(set), _) if set.sites.len() <= MAX_FORCE_LINES => SVG_FRAME + SVG_POINT * points * set.sites.len() as f64,
        (Some(set), _) => SVG_FRAME + (FORCE_MAP_BINS * set.sites.len()) as f64 * SCATTER_DOT,
        (None, Some(p)) => line(p),
        (None, None) => 0.0,
    };
    tip + forces + f.energy_plot.as_ref().map_or(0.0, line)
}

/// What the output estimate leaves out, for the check's text (empty when
/// nothing is left out).
pub fn output_estimate_note(output: &OutputToml) -> &'static str {
    if output.impacts {
        " (impacts.csv and impact_map.svg not included: they grow with the impacts)"
    } else {
        ""
    }
}

/// The event-driven scheme of a scene and its event limit, if it has one.
fn event_driven(scene: &Scene) -> Option<(signorini_schemes::SchemeSpec, f64, f64)> {
    let f = scene.facts();
    (f.scheme.family().name == "event-driven").then_some((f.scheme, f.dt, f.t_end))
}

/// Search steps a probe may take: 512 polls of the event search (one per
/// 256 steps; 0.9 s for fig. 2's beam, 38 dofs), and at most
/// [`PROBE_WALL_S`] seconds (larger problems).
const PROBE_POLLS: usize = 512;
const PROBE_WALL_S: f64 = 1.0;
/// A probe covers at least this fraction of the horizon, then goes on to
/// [`PROBE_EVENTS`] events (within its budget).
const PROBE_FRACTION: f64 = 0.01;
const PROBE_EVENTS: usize = 1000;
/// `events.csv`'s header, and a row's bytes when the probe saw no event.
const EVENTS_HEADER: f64 = 55.0;
const NOMINAL_EVENT_ROW: f64 = 100.0;

/// How an event-driven run's probe ended.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ProbeEnd {
    /// It reached the horizon: its counts are the run's.
    Horizon,
    /// It covered its share: at least 1 % of the horizon and 1000 events.
    Share,
    /// It used its budget of search steps (or of time) before its share.
    Budget,
    /// The run stops there with this error (the run will too).
    Failed(String),
}

/// A bounded probe of an event-driven run from its start (what `signorini
/// check` and the disk check of `run` extrapolate its events, its
/// `events.csv` and its time from): the run stepped until it covers 1 % of
/// the horizon and 1000 events, or until 512 × 256 steps of its event
/// search or 1 s, or to the horizon.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct EventProbe {
    /// The time covered from 0 (the last whole level, or the last event if
    /// later: the probe may stop inside a step).
    pub covered: f64,
    /// The horizon `T`.
    pub horizon: f64,
    /// Events in `[0, covered]`.
    pub events: usize,
    /// Bytes of their `events.csv` rows (header excluded).
    pub row_bytes: f64,
    /// Wall-clock seconds of the probe's stepping.
    pub wall_s: f64,
    /// The run's event limit (`max_events`).
    pub max_events: f64,
    /// How it ended.
    pub end: ProbeEnd,
}

/// The most bytes one `events.csv` row can take: four `{:.16e}` numbers
/// of at most 24 characters each (`-1.2345678901234567e-308`; `NaN`,
/// `-inf` shorter), the longest kind (`accumulation`, 12), a contact index
/// of at most 20 digits (`usize`), five commas and the newline.
const MAX_EVENT_ROW: f64 = 4.0 * 24.0 + 12.0 + 20.0 + 6.0;

impl EventProbe {
    /// An upper bound of an event-driven scene's `events.csv`, without
    /// running anything: `max_events` rows of `MAX_EVENT_ROW` bytes (a run
    /// that reaches the horizon logged at most `max_events` events, one
    /// that did not is estimated at most `max_events`); `None` for other
    /// schemes. Every probe's [`bytes_estimate`](Self::bytes_estimate) is
    /// at most this, so where the rest of the output and this bound fit
    /// the free space no probe can refuse the run: `run`'s disk check then
    /// skips the probe (which would step the run a second time).
    pub fn bytes_bound_unprobed(scene: &Scene) -> Option<f64> {
        let (spec, _, _) = event_driven(scene)?;
        let max_events = spec.param("max_events").unwrap_or(signorini_schemes::events::MAX_EVENTS as f64);
        Some(EVENTS_HEADER + max_events * MAX_EVENT_ROW)
    }

    /// The run's events: the probe's rate `events / covered` over the
    /// horizon, at most `max_events` (exact when the probe reached the
    /// horizon); `None` when the probe covered no time.
    pub fn events_estimate(&self) -> Option<f64> {
        match self.end {
            ProbeEnd::Horizon => Some(self.events as f64),
            _ if self.covered > 0.0 => Some((self.events as f64 * self.horizon / self.covered).min(self.max_events)),
            _ => None,
        }
    }

    /// Bytes per `events.csv` row: the probe's mean (100 without events).
    pub fn bytes_per_event(&self) -> f64 {
        if self.events > 0 {
            self.row_bytes / self.events as f64
        } else {
            NOMINAL_EVENT_ROW
        }
    }

    /// `events.csv`'s size at the estimated events (the header alone when
    /// the rate is unknown).
    pub fn bytes_estimate(&self) -> f64 {
        EVENTS_HEADER + self.events_estimate().unwrap_or(0.0) * self.bytes_per_event()
    }

    /// `events.csv`'s size at `max_events` events (a run that reaches the
    /// limit stops there).
    pub fn bytes_bound(&self) -> f64 {
        EVENTS_HEADER + self.max_events * self.bytes_per_event()
    }

    /// Seconds of stepping: the probe's wall time per unit of simulated
    /// time over the horizon (`None` when it covered no time).
    pub fn seconds_estimate(&self) -> Option<f64> {
        match self.end {
            ProbeEnd::Horizon => Some(self.wall_s),
            _ => (self.covered > 0.0).then(|| self.wall_s * self.horizon / self.covered),
        }
    }

    /// What the probe saw and what it estimates, in words (`signorini check`).
    pub fn describe(&self) -> String {
        use signorini_run::text::num;
        let pct = 100.0 * self.covered / self.horizon;
        let seen = format!("{} events in [0, {}] ({pct:.3} % of T), {:.3} s of stepping", self.events, num(sig6(self.covered)), self.wall_s);
        let bound = format!("at most max_events = {:e} events: events.csv at most {}", self.max_events, crate::bytes(self.bytes_bound()));
        match (&self.end, self.events_estimate(), self.seconds_estimate()) {
            (ProbeEnd::Horizon, _, _) => format!("events: the probe ran the whole horizon: {seen}; events.csv {} ({bound})", crate::bytes(self.bytes_estimate())),
            (end, Some(n), Some(secs)) => format!(
                "events: estimated from a probe of the run{}: {seen}; at that rate about {} events to T = {} (events.csv about {}, {:.0} bytes per row) and {:.3} s of stepping — an extrapolation, not a bound: the rate of events can change along the run (chatter comes in bursts); {bound}",
                match end {
                    ProbeEnd::Failed(why) => format!(" (it stopped: {why}: the run will stop there too)"),
                    ProbeEnd::Budget => " (it stopped at its budget: 131 072 steps of the event search or 1 s)".to_string(),
                    _ => String::new(),
                },
                num(sig6(n).round()),
                num(self.horizon),
                crate::bytes(self.bytes_estimate()),
                self.bytes_per_event(),
                secs
            ),
            (end, _, _) => format!(
                "events: a probe of the run covered no time{} ({seen}): no estimate; {bound}",
                match end {
                    ProbeEnd::Failed(why) => format!(" (it stopped: {why})"),
                    _ => String::new(),
                }
            ),
        }
    }
}

/// Counts the bytes written.
struct Count(usize);

impl std::io::Write for Count {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0 += b.len();
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A probe of an event-driven scene's run ([`EventProbe`]); `None` for
/// other schemes.
pub fn event_probe(scene: &Scene) -> Result<Option<EventProbe>, BuildError> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let Some((spec, dt, t_end)) = event_driven(scene) else { return Ok(None) };
    let max_events = spec.param("max_events").unwrap_or(signorini_schemes::events::MAX_EVENTS as f64);
    let mut sim = scene.instantiate(None)?;
    let steps = RunConfig::new(dt, t_end)?.steps();
    let share = ((PROBE_FRACTION * steps as f64).ceil() as usize).clamp(1, steps);
    let polls = std::sync::Arc::new(AtomicUsize::new(0));
    let p = std::sync::Arc::clone(&polls);
    let start = std::time::Instant::now();
    sim.stepper.set_interrupt(Some(std::sync::Arc::new(move || p.fetch_add(1, Ordering::Relaxed) >= PROBE_POLLS || start.elapsed().as_secs_f64() > PROBE_WALL_S)));
    let mut end = ProbeEnd::Budget;
    loop {
        let s = &mut sim.stepper;
        let events = s.events().map_or(0, <[_]>::len);
        if s.level() >= steps {
            end = ProbeEnd::Horizon;
            break;
        }
        if s.level() >= share && events >= PROBE_EVENTS {
            end = ProbeEnd::Share;
            break;
        }
        match s.step() {
            Ok(_) => {}
            Err(signorini_schemes::SchemeError::Interrupted { .. }) => break,
            Err(e) => {
                end = ProbeEnd::Failed(signorini_run::RunError::from(e).to_string());
                break;
            }
        }
    }
    let wall_s = start.elapsed().as_secs_f64();
    let events = sim.stepper.events().unwrap_or(&[]);
    let covered = events.last().map_or(0.0, |e| e.t).max(sim.stepper.time()).min(t_end);
    let mut count = Count(0);
    signorini_run::observers::write_events(&mut count, events).map_err(|e| BuildError::Run(signorini_run::RunError::Output(e)))?;
    Ok(Some(EventProbe { covered, horizon: t_end, events: events.len(), row_bytes: count.0 as f64 - EVENTS_HEADER, wall_s, max_events, end }))
}

/// Free bytes on the file system holding `dir` (or its nearest existing
/// ancestor), if the system says.
pub fn free_space(dir: &Path) -> Option<f64> {
    use std::os::unix::ffi::OsStrExt;
    let mut p = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
    while !p.exists() {
        p = p.parent().filter(|q| !q.as_os_str().is_empty()).unwrap_or(Path::new("."));
    }
    let c = std::ffi::CString::new(p.as_os_str().as_bytes()).ok()?;
    let mut st = std::mem::MaybeUninit::<libc::statvfs>::uninit();
    // SAFETY: `c` is a valid NUL-terminated path and `st` a writable statvfs.
    let rc = unsafe { libc::statvfs(c.as_ptr(), st.as_mut_ptr()) };
    if rc != 0 {
        return None;
    }
    // SAFETY: statvfs returned 0, so it filled `st`.
    let st = unsafe { st.assume_init() };
    Some(st.f_bavail as f64 * st.f_frsize as f64)
}

/// What `signorini check` states, as text and as numbers.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CheckReport {
    /// The text `signorini check` prints.
    pub text: String,
    /// Time steps to the horizon.
    pub steps: usize,
    /// The exact stability limit of a conditionally stable scheme (s for
    /// the beam), `None` for an unconditionally stable one.
    pub stability_limit: Option<f64>,
    /// The memory estimate, bytes.
    pub memory_bytes: f64,
    /// The output estimate, bytes (`events.csv` included: from the probe).
    pub output_bytes: f64,
    /// An event-driven run's probe (its events, `events.csv` and time).
    pub events: Option<EventProbe>,
}

/// What `signorini check` states, with its numbers (the Python `check()` returns them).
pub fn check_report(scene: &Scene, file: &SceneFile, out: &Path) -> Result<CheckReport, BuildError> {
    let facts = scene.facts();
    let probe = event_probe(scene)?;
    let need = output_estimate(scene, &file.output) + probe.as_ref().map_or(0.0, EventProbe::bytes_estimate);
    let free = free_space(out)
        .map_or_else(|| "free space unknown".to_string(), |f| format!("{} free there{}", crate::bytes(f), if need > f { ": the run will be refused (--no-disk-check to force)" } else { "" }));
    let memory = facts.memory_bytes;
    let mut resources = format!("\nmemory estimate: {}\noutput estimate: {} into {} ({free}){}", crate::bytes(memory), crate::bytes(need), out.display(), output_estimate_note(&file.output));
    if let Some(p) = &probe {
        resources.push_str(" (events.csv included: the probe's estimate)\n");
        resources.push_str(&p.describe());
    }
    if let Some(c) = facts.contacts {
        resources = format!("\n{}{resources}", c.describe());
    }
    // An event-driven run's cost is its events', from the probe.
    let probe_cost = probe.as_ref().map(|p| match p.seconds_estimate() {
        Some(s) => format!("cost estimate: about {s:.3} s stepping (event-driven: from the probe of its events below; the run's writing and norms come on top)"),
        None => "cost estimate: unknown (event-driven: the probe below covered no time)".to_string(),
    });
    let (text, steps, stability_limit) = scene.check_text(probe_cost.as_deref())?;

    // A reduced model's basis: the validated simulation's (or, once a probe
    // took it, built anew).
    let reduced = match facts.reduce {
        Some(_) => scene.instantiate(None)?.reduction,
        None => None,
    };
    let reduced = reduced.map_or(String::new(), |red| {
        format!(
            "\nreduced model (docs/theory.md §2.5): {} contact(s) + {} of {} fixed-interface modes = {} unknowns (highest kept {:.6e} Hz); explicit CD limit of the reduced pencil 2/ω_r = {:.6e}",
            red.contacts().len(),
            red.modes().len(),
            red.interior_dofs(),
            red.dofs(),
            red.modes().last().map_or(0.0, |w| w.sqrt() / std::f64::consts::TAU),
            red.cfl_limit()
        )
    });
    Ok(CheckReport { text: text + &reduced + &resources, steps, stability_limit, memory_bytes: memory, output_bytes: need, events: probe })
}
