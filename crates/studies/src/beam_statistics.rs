//! The beam statistics study (`cargo xtask beam-statistics`): statistics of
//! the paper's beam scenes over a long window after a transient, each with
//! a 95 % batch-means confidence interval (`signorini_run::stats`), against
//! dt and J, and their self-convergence to the finest level.
//!
//! The beam is chaotic (`cargo xtask lyapunov`): trajectories at two time
//! steps part after about a second, so only statistics over long windows
//! can converge. The window `[t0, t0 + W)` (`t0` = `transient` forcing
//! periods, `W` = `window` forcing periods) is cut into `batches` batches of
//! equal length; each statistic is computed per batch, its estimate is the
//! mean of the batch values and its interval `± t_{0.975, B−1} s/√B`.
//!
//! Statistics (per unit time: per second; "per period": per forcing period):
//! * `impact_power`: `Σ |J_i| |v_i|` over the active runs, per second (the
//!   impact work rate of wear laws; `v_i` the pre-impact velocity);
//! * `impulse_rate_lower`, `impulse_rate_upper`: the momentum the lower and
//!   upper stops give the beam per second, `dt Σ |λ|` by sign (the mean
//!   contact force of each stop);
//! * `episodes_per_period`, `impulse_per_episode`: contact *episodes* —
//!   active runs of one contact and side merged when the gap between them is
//!   shorter than `episode_gap` (default 5 ms) — and the mean |impulse| of one
//!   episode (a chattering contact is one episode);
//! * `rms_tip`: the RMS displacement of the contact dof;
//! * **step-dependent**: `impacts_per_period` (active runs: chatter counted
//!   as separate impacts) and `rms_force` (`√(mean λ²)` over levels: an
//!   impulsive force sampled per step grows as dt → 0) and
//!   `contact_fraction` (the fraction of levels with a contact active: with
//!   rigid stops the contacts are impulsive, runs of one or two levels, so
//!   the time in contact is about runs × dt and falls as dt → 0).
//!
//! Outputs (`--out`, default `out/beam-statistics`):
//! * `statistics.csv`: `scene,dt,elements,statistic,mean,ci_low,ci_high,finest_mean,rel_diff,within_ci,kind,scheme,wall_s`
//!   — `rel_diff = mean/finest_mean − 1` against the scene's finest level
//!   (smallest dt, then largest J, of the first scheme), `within_ci` 1 when
//!   the two intervals overlap, `kind` `converges` or `step-dependent` (as
//!   declared above: what the statistic is expected to do, not a verdict),
//!   `scheme` the run's scheme (`--schemes`; the scene's own by default),
//!   `wall_s` the run's wall time (its cost);
//! * `statistics.svg`: |rel_diff| against dt at the largest J (not drawn,
//!   with a note, when that J has no level but the finest: one dt given).
//!
//! The report's last column is the verdict of each level against the finest
//! ([`verdict`]): the two 95 % intervals overlap (`agrees`), or they do not
//! — then a statistic expected to converge is `undecided` at that level (a
//! coarse level's discretisation error and a statistic that does not
//! converge look alike from one pair of levels), a step-dependent one
//! `differs`.

use crate::{create_dir, fde, fe, ff, int, since, txt, Kind, StudyError, TableOut};
use signorini_plot::{Chart, Scale, Series, Style};
use signorini_run::stats::{batch_means, Interval};
use signorini_run::{run as run_steps, ImpactObserver, Observer, RunConfig, RunError, Sample};
use signorini_scene::{Limits, Scene};
use signorini_schemes::{Active, SchemeSpec};
use std::fmt::Write as _;
use std::path::PathBuf;

/// The scenes this study knows (data/scenes/beam-fig2-support.toml, beam-obstacles.toml).
pub const SCENES: [&str; 2] = ["fig2-support", "beam-obstacles"];

/// The statistics, in CSV order, and whether they are step-dependent.
pub const STATISTICS: [(&str, bool); 9] = [
    ("impact_power", false),
    ("impulse_rate_lower", false),
    ("impulse_rate_upper", false),
    ("contact_fraction", true),
    ("episodes_per_period", false),
    ("impulse_per_episode", false),
    ("rms_tip", false),
    ("impacts_per_period", true),
    ("rms_force", true),
];

crate::options::study_config! {
    /// Statistics that converge: the beam ⟨scenes⟩ at every ⟨dts⟩ and
    /// ⟨elements⟩ over ⟨window⟩ forcing periods after ⟨transient⟩, each
    /// statistic with a 95 % interval from ⟨batches⟩ batch means, against the
    /// finest level. statistics.csv: scene, dt, elements, statistic, mean,
    /// ci_low, ci_high, finest_mean, rel_diff, within_ci, kind (converges or
    /// step-dependent); active runs closer than ⟨episode_gap⟩ seconds form one
    /// contact episode.
    study "beam_statistics";
    pub struct Config {
        /// Scenes, comma-separated (fig2-support, beam-obstacles).
        pub scenes: Vec<String> = vec!["fig2-support".into()],
        /// Time steps (s), comma-separated.
        pub dts: Vec<f64> = vec![5e-5, 2.5e-5, 1e-5],
        /// Elements J, comma-separated.
        pub elements: Vec<usize> = vec![19, 38],
        /// Forcing periods before the window.
        pub transient: f64 = 10.0,
        /// Forcing periods of the window (at least 10; 320 is 201 s at ω = 10).
        pub window: f64 = 320.0,
        /// Batches of the 95 % intervals (at least 10; 20 are 10-s batches).
        pub batches: usize = 20,
        /// Active runs closer than this (s) form one contact episode.
        pub episode_gap: f64 = 5e-3,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/beam-statistics"),
        /// Schemes, comma-separated (default: the scene's own, the paper's
        /// projection scheme `ps(0,0.5)`). Every scheme runs every level,
        /// and every level is compared with the finest level of the first.
        #[serde(deserialize_with = "crate::options::with::some_schemes")]
        pub schemes: Option<Vec<SchemeSpec>> = None,
    }
}

impl Config {
    /// Every check, before anything runs.
    pub fn validate(&self) -> Result<(), StudyError> {
        if self.scenes.is_empty() {
            return Err(StudyError::config("scenes", format!("⟨scenes⟩: allowed one or more of {}", SCENES.join(", "))));
        }
        if let Some(s) = self.scenes.iter().find(|s| !SCENES.contains(&s.as_str())) {
            return Err(StudyError::config("scenes", format!("⟨scenes⟩ {s:?}: allowed {}", SCENES.join(", "))));
        }
        if self.dts.is_empty() || self.dts.iter().any(|d| !(d.is_finite() && *d > 0.0 && *d <= 1e-3)) {
            return Err(StudyError::config("dts", format!("⟨dts⟩ {:?}: allowed at least one, each finite and in (0, 1e-3]", self.dts)));
        }
        if self.elements.is_empty() || self.elements.iter().any(|&j| !(2..=1000).contains(&j)) {
            return Err(StudyError::config("elements", format!("⟨elements⟩ {:?}: allowed at least one, each in [2, 1000]", self.elements)));
        }
        if !(self.transient.is_finite() && (0.0..=1e4).contains(&self.transient)) {
            return Err(StudyError::config("transient", format!("⟨transient⟩ {}: allowed finite, in [0, 10000] forcing periods", self.transient)));
        }
        if !(self.window.is_finite() && (10.0..=1e5).contains(&self.window)) {
            return Err(StudyError::config("window", format!("⟨window⟩ {}: allowed finite, in [10, 100000] forcing periods (a statistic over fewer than ten periods has no meaning)", self.window)));
        }
        if !(10..=1000).contains(&self.batches) {
            return Err(StudyError::config("batches", format!("⟨batches⟩ {}: allowed an integer in [10, 1000] (fewer batches give no usable interval)", self.batches)));
        }
        if !(self.episode_gap.is_finite() && self.episode_gap >= 0.0 && self.episode_gap <= 1.0) {
            return Err(StudyError::config("episode_gap", format!("⟨episode_gap⟩ {}: allowed finite, in [0, 1] s", self.episode_gap)));
        }
        if let Some(s) = &self.schemes {
            crate::time_stepping_schemes("schemes", Some(s))?;
            if let Some(s) = s.iter().find(|s| !s.capabilities().beam) {
                return Err(StudyError::config("schemes", format!("⟨schemes⟩ {s}: it does not take the beam (`signorini list` marks the families that do)")));
            }
        }
        let steps = (self.transient + self.window) * std::f64::consts::TAU / 10.0 / self.dts.iter().copied().fold(f64::INFINITY, f64::min);
        if steps > 2e9 {
            return Err(StudyError::config("window", format!("⟨window⟩ {}: {steps:.2e} steps at the smallest dt, allowed at most 2e9", self.window)));
        }
        Ok(())
    }
}

/// The verdict of a level's interval `c` against the finest level's `f`
/// for a statistic expected to converge (`step_dependent` false) or not:
/// `agrees` when the intervals overlap, else `undecided` (expected to
/// converge) or `differs` (step-dependent). The finest level itself is
/// `finest`.
pub fn verdict(c: &Interval, f: &Interval, step_dependent: bool, finest: bool) -> &'static str {
    if finest {
        "finest"
    } else if c.low <= f.high && f.low <= c.high {
        "agrees (intervals overlap)"
    } else if step_dependent {
        "differs (intervals apart; step-dependent)"
    } else {
        "undecided (intervals apart)"
    }
}

/// What the study computed and wrote ([`crate::Report`]); its table: `statistics.csv`.
pub type Output = crate::Report;

/// The scene `name` at step `dt`, `j` elements, horizon `t_end`, with
/// `scheme` (`None`: the scene's own) (the Lyapunov study's scene text,
/// validated).
fn scene(name: &str, dt: f64, j: usize, t_end: f64, scheme: Option<&SchemeSpec>) -> Result<Scene, StudyError> {
    let case = crate::lyapunov::Case::Beam { name: name.to_string(), dt: Some(dt), elements: Some(j), scheme: scheme.cloned() };
    let file = crate::lyapunov::scene_file(&case, t_end).map_err(|e| StudyError::failed(name, e))?;
    file.validate_with(&Limits::machine()).map_err(|e| StudyError::failed(format!("{name}, dt = {dt:e}, J = {j}"), e))
}

/// Per-batch sums over levels.
struct Levels {
    t0: f64,
    batch_len: f64,
    dt: f64,
    tip: usize,
    /// Per batch: impulse lower, upper, active levels, Σλ², Σ tip², levels.
    sums: Vec<[f64; 6]>,
}

impl Observer for Levels {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if s.t < self.t0 {
            return Ok(());
        }
        let b = (((s.t - self.t0) / self.batch_len) as usize).min(self.sums.len() - 1);
        let row = &mut self.sums[b];
        let mut active = false;
        for (l, st) in s.forces.iter().zip(s.status) {
            let j = -self.dt * l;
            if j > 0.0 {
                row[0] += j;
            } else {
                row[1] -= j;
            }
            row[3] += l * l;
            active |= *st != Active::None;
        }
        row[2] += f64::from(u8::from(active));
        row[4] += s.u[self.tip] * s.u[self.tip];
        row[5] += 1.0;
        Ok(())
    }
}

/// The per-batch values of every statistic of one run, in [`STATISTICS`]
/// order, and the steps it took.
pub(crate) fn run_case(name: &str, dt: f64, j: usize, scheme: Option<&SchemeSpec>, a: &Config) -> Result<(Vec<Vec<f64>>, usize), StudyError> {
    let fail = |e: String| StudyError::Run(format!("{name}, dt = {dt:e}, J = {j}: {e}"));
    let probe = scene(name, dt, j, 1.0, scheme)?;
    let (omega, _, _) = probe.sweep_clock().ok_or_else(|| fail("no periodic forcing".into()))?;
    let period = std::f64::consts::TAU / omega;
    let t0 = (a.transient * period / dt).round() * dt;
    let t_end = ((a.transient + a.window) * period / dt).round() * dt;
    let sc = scene(name, dt, j, t_end, scheme)?;
    let mut built = sc.instantiate(None).map_err(|e| StudyError::failed(format!("{name}, dt = {dt:e}, J = {j}"), e))?;
    let contacts = built.contacts();
    let w = t_end - t0;
    let nb = a.batches;
    let batch_len = w / nb as f64;
    let mut imp = ImpactObserver::<std::io::Sink>::new(&contacts, dt, Some(omega), t0, 1 << 16, None).map_err(|e| StudyError::failed(format!("{name}, dt = {dt:e}, J = {j}"), e))?;
    let mut lv = Levels { t0, batch_len, dt, tip: built.tip, sums: vec![[0.0; 6]; nb] };
    let cfg = RunConfig::new(dt, t_end).map_err(|e| StudyError::failed(format!("{name}, dt = {dt:e}, J = {j}"), e))?;
    let steps = run_steps(built.stepper.as_mut(), &built.u0.clone(), &cfg, &mut [&mut imp, &mut lv]).map_err(|e| StudyError::failed(format!("{name}, dt = {dt:e}, J = {j}"), e))?.steps;
    let batch_of = |t: f64| (((t - t0) / batch_len).max(0.0) as usize).min(nb - 1);
    let mut power = vec![0.0; nb];
    let mut runs = vec![0.0; nb];
    // Episodes: runs of one contact and side closer than the gap merge.
    let mut episodes = vec![0.0; nb];
    let mut ep_impulse = vec![0.0; nb];
    let mut open: Vec<Option<(f64, f64, f64, Active)>> = vec![None; contacts.len()]; // (start, end, |J|, side)
    let close = |e: (f64, f64, f64, Active), episodes: &mut Vec<f64>, ep_impulse: &mut Vec<f64>| {
        let b = batch_of(e.0);
        episodes[b] += 1.0;
        ep_impulse[b] += e.2;
    };
    let mut list: Vec<_> = imp.impacts().to_vec();
    list.sort_by_key(|x| x.first_level);
    for i in &list {
        let b = batch_of(i.t);
        if i.velocity.is_finite() {
            power[b] += i.impulse.abs() * i.velocity.abs();
        }
        runs[b] += 1.0;
        let start = i.first_level as f64 * dt;
        let end = start + i.duration;
        match open[i.stop] {
            Some(mut e) if e.3 == i.side && start - e.1 < a.episode_gap => {
                e.1 = end;
                e.2 += i.impulse.abs();
                open[i.stop] = Some(e);
            }
            other => {
                if let Some(e) = other {
                    close(e, &mut episodes, &mut ep_impulse);
                }
                open[i.stop] = Some((start, end, i.impulse.abs(), i.side));
            }
        }
    }
    for e in open.into_iter().flatten() {
        close(e, &mut episodes, &mut ep_impulse);
    }
    let periods_per_batch = batch_len / period;
    let mut out = vec![Vec::with_capacity(nb); STATISTICS.len()];
    for b in 0..nb {
        let s = lv.sums[b];
        let levels = s[5].max(1.0);
        let vals = [
            power[b] / batch_len,
            s[0] / batch_len,
            s[1] / batch_len,
            s[2] / levels,
            episodes[b] / periods_per_batch,
            if episodes[b] > 0.0 { ep_impulse[b] / episodes[b] } else { 0.0 },
            (s[4] / levels).sqrt(),
            runs[b] / periods_per_batch,
            (s[3] / levels).sqrt(),
        ];
        for (o, v) in out.iter_mut().zip(vals) {
            o.push(v);
        }
    }
    Ok((out, steps))
}

/// Runs the study; `progress` after every run.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    a.validate()?;
    // The schemes: the given ones, or the scene's own (`None`).
    let schemes: Vec<Option<SchemeSpec>> = match &a.schemes {
        Some(v) => v.iter().cloned().map(Some).collect(),
        None => vec![None],
    };
    // Cases: scene, then scheme, then J, then dt.
    let cases: Vec<(String, usize, f64, usize)> =
        a.scenes.iter().flat_map(|s| (0..schemes.len()).flat_map(move |k| a.elements.iter().flat_map(move |&j| a.dts.iter().map(move |&dt| (s.clone(), k, dt, j))))).collect();
    // Every scene is read (and its scheme named) before a file is created.
    let mut names = Vec::with_capacity(cases.len());
    for (s, k, dt, j) in &cases {
        names.push(scene(s, *dt, *j, 1.0, schemes[*k].as_ref())?.facts().scheme.to_string());
    }
    create_dir(&a.out)?;
    let start = std::time::Instant::now();
    let results = crate::run_cases(&cases, progress, &|c: &(String, usize, f64, usize)| {
        let t = std::time::Instant::now();
        run_case(&c.0, c.2, c.3, schemes[c.1].as_ref(), a).map(|r| (r, since(t)))
    });
    let mut cis: Vec<Vec<Interval>> = Vec::new();
    let mut walls = Vec::new();
    for r in results {
        let ((r, _), wall) = r?;
        cis.push(r.iter().map(|v| batch_means(v, a.batches, 0.95).expect("validated batches")).collect());
        walls.push(wall);
    }
    let (f_, i_, s_) = (Kind::F, Kind::I, Kind::S);
    let mut t = TableOut::create(
        &a.out,
        "statistics.csv",
        &[
            ("scene", s_),
            ("dt", f_),
            ("elements", i_),
            ("statistic", s_),
            ("mean", f_),
            ("ci_low", f_),
            ("ci_high", f_),
            ("finest_mean", f_),
            ("rel_diff", f_),
            ("within_ci", i_),
            ("kind", s_),
            ("scheme", s_),
            ("wall_s", f_),
        ],
    )?;
    let mut md = format!(
        "# Beam statistics over {} forcing periods after {} ({} batches, 95 % batch-means intervals; output in {})\n\n`expected`: what the statistic is expected to do as dt → 0. Last column: a level *agrees* with the finest when their intervals overlap; when they do not, a statistic expected to converge is *undecided* at that level (a coarse level's error and a statistic that does not converge look alike from one pair of levels), a step-dependent one *differs*.\n",
        a.window,
        a.transient,
        a.batches,
        a.out.display()
    );
    let w_ = |r: std::fmt::Result| r.expect("writing to a String");
    let mut series = Vec::new();
    let jmax = a.elements.iter().copied().max().expect("validated");
    for sname in &a.scenes {
        let of_scene: Vec<usize> = (0..cases.len()).filter(|&i| &cases[i].0 == sname).collect();
        // The finest: the first scheme's smallest dt, then largest J.
        let finest = *of_scene.iter().filter(|&&i| cases[i].1 == 0).min_by(|&&x, &&y| cases[x].2.total_cmp(&cases[y].2).then(cases[y].3.cmp(&cases[x].3))).expect("one case at least");
        for k in 0..schemes.len() {
            let idx: Vec<usize> = of_scene.iter().copied().filter(|&i| cases[i].1 == k).collect();
            let label = if schemes.len() > 1 { format!("{sname}, {}", names[idx[0]]) } else { sname.clone() };
            w_(writeln!(
                md,
                "\n## {label} (finest: dt = {:e}, J = {}{})\n\n| statistic | expected | dt | J | mean [95 % interval] | relative to the finest | against the finest |\n|---|---|---|---|---|---|---|",
                cases[finest].2,
                cases[finest].3,
                if schemes.len() > 1 { format!(", {}", names[finest]) } else { String::new() }
            ));
            for (s, (stat, dep)) in STATISTICS.iter().enumerate() {
                let f = cis[finest][s];
                let kind = if *dep { "step-dependent" } else { "converges" };
                let mut pts = Vec::new();
                for &i in &idx {
                    let c = cis[i][s];
                    let rel = c.mean / f.mean - 1.0;
                    let within = c.low <= f.high && f.low <= c.high;
                    t.row(vec![
                        txt(sname),
                        fde(cases[i].2),
                        int(cases[i].3),
                        txt(*stat),
                        fe(c.mean, 6),
                        fe(c.low, 6),
                        fe(c.high, 6),
                        fe(f.mean, 6),
                        fe(rel, 4),
                        int(usize::from(within)),
                        txt(kind),
                        txt(&names[i]),
                        ff(walls[i], 3),
                    ])?;
                    let shown = if rel.is_finite() { format!("{:+.2} %", 100.0 * rel) } else { "—".to_string() };
                    w_(writeln!(md, "| {stat} | {kind} | {:e} | {} | {:.4} [{:.4}, {:.4}] | {shown} | {} |", cases[i].2, cases[i].3, c.mean, c.low, c.high, verdict(&c, &f, *dep, i == finest)));
                    // Log-log: a zero or undefined difference has no point.
                    if cases[i].3 == jmax && i != finest && rel.is_finite() && rel != 0.0 {
                        pts.push((cases[i].2, rel.abs()));
                    }
                }
                if !pts.is_empty() {
                    let who = if schemes.len() > 1 { format!("{sname}, {}", names[idx[0]]) } else { sname.clone() };
                    series.push(Series { label: format!("{who}: {stat}{}", if *dep { " (step-dependent)" } else { "" }), points: pts, reference: false, style: Style::default() });
                }
            }
        }
    }
    let tables = vec![t.finish()?];
    let chart = Chart { title: "beam statistics: relative difference to the finest dt", x_label: "dt (s)", y_label: "|mean / finest − 1|", scale: Scale::LogLog, size: (800, 560) };
    let why = format!("it shows the difference to the finest level against dt at J = {jmax}, and no time step but the finest has a nonzero difference there (--dts {:?}); the comparison is in the report and statistics.csv", a.dts);
    let notes: Vec<String> = crate::draw_or_skip(&a.out, "statistics.svg", &chart, &series, &why)?.into_iter().collect();
    if !notes.is_empty() {
        w_(writeln!(md, "\nNo plot: at J = {jmax} no time step but the finest has a nonzero difference to it (statistics.svg not drawn)."));
    }
    let wall_s = since(start);
    w_(writeln!(md, "\nwrote {} in {wall_s:.1} s", a.out.display()));
    Ok(Output { tables, report: md, wall_s, notes })
}
