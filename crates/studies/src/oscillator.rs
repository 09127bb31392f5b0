//! The impact oscillator study (`cargo xtask oscillator`): the impact oscillator scene
//! (data/scenes/oscillator.toml) against its exact period-1 orbits and its
//! grazing frequency (signorini-exact's `ImpactOscillator`, closed forms).
//!
//! For every forcing frequency of the scene's stable range and every time
//! step, a run of `transient + record` forcing periods through the sweep's
//! own run function; the record window's impacts against the exact orbit's
//! impact velocity (relative) and forcing phase (rad), largest over the
//! window; least-squares and last rates in dt. Then the grazing check: from
//! the non-impacting steady state, runs just above and below Ω_g.
//!
//! Outputs (`--out`, default `out/oscillator`): `orbits.csv`
//! (`omega,dt,impacts,velocity_exact,phase_exact,multiplier,velocity_err,phase_err`),
//! `rates.csv` (`omega,velocity_lsq_rate,velocity_last_rate,phase_lsq_rate,phase_last_rate`),
//! `grazing.csv` (`omega,offset,impacts,first_velocity`), `errors.svg`.

use crate::{create_dir, fd, fde, fe, ff, int, since, Kind, StudyError, TableOut};
use signorini_exact::{ImpactOscillator, OscillatorParams};
use signorini_plot::{Chart, Scale, Series, Style};
use signorini_run::study::rate;
use signorini_scene::presets::{self, Preset};
use signorini_scene::Limits;
use signorini_sweep::{simulate, Sweep, SweepOptions};
use std::fmt::Write as _;
use std::path::PathBuf;

crate::options::study_config! {
    /// The impact oscillator against its exact period-1 orbits: impact
    /// velocity and phase errors and their rates in dt at each forcing frequency
    /// of ⟨omegas⟩; the grazing frequency.
    study "oscillator";
    pub struct Config {
        /// Forcing frequencies (the scene's stable period-1 range).
        pub omegas: Vec<f64> = vec![1.6, 1.7, 1.8, 1.9, 2.0, 2.1, 2.2],
        /// Time steps (2e-3 halved eight times).
        pub dts: Vec<f64> = vec![2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5, 1.5625e-5, 7.8125e-6],
        /// Forcing periods before the record window.
        pub transient: f64 = 60.0,
        /// Forcing periods recorded.
        pub record: f64 = 10.0,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/oscillator"),
    }
}

impl Config {
    /// Checks the lists are not empty and every value finite and positive
    /// (the transient may be 0); the runs check the rest (the sweep's own
    /// ranges), naming `forcing.omega` or the scene's field.
    pub fn validate(&self) -> Result<(), StudyError> {
        if self.omegas.is_empty() || self.omegas.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(StudyError::config("omegas", format!("⟨omegas⟩ {:?}: allowed at least one, each finite and > 0", self.omegas)));
        }
        if self.dts.is_empty() || self.dts.iter().any(|d| !(d.is_finite() && *d > 0.0)) {
            return Err(StudyError::config("dts", format!("⟨dts⟩ {:?}: allowed at least one, each finite and > 0", self.dts)));
        }
        if !(self.transient.is_finite() && self.transient >= 0.0) {
            return Err(StudyError::config("transient", format!("⟨transient⟩ {}: allowed finite and >= 0", self.transient)));
        }
        if !(self.record.is_finite() && self.record > 0.0) {
            return Err(StudyError::config("record", format!("⟨record⟩ {}: allowed finite and > 0", self.record)));
        }
        // The study compares with the one period-1 orbit of each Ω (closed
        // form, cheap): an Ω without exactly one is refused before any run.
        for &w in &self.omegas {
            let n = exact(w).map(|o| o.period1_orbits().len()).unwrap_or(0);
            if n != 1 {
                return Err(StudyError::config(
                    "omegas",
                    format!("⟨omegas⟩ {w}: the scene has {n} admissible period-1 orbits there; allowed the frequencies with exactly one (the stable range, about 1.6 … 2.2)"),
                ));
            }
        }
        Ok(())
    }
}

/// What the study computed and wrote ([`crate::Report`]); its tables: `orbits.csv`, `rates.csv`, `grazing.csv`.
pub type Output = crate::Report;

/// The scene crate's preset `oscillator.toml` at step `dt` from `(x0, v0)`,
/// as the text a sweep reads: its values set by path and the result read by
/// the scene reader first (an edit of a key the scene does not have fails,
/// [`presets::set_path`]).
#[doc(hidden)]
pub fn scene_text(dt: f64, x0: f64, v0: f64) -> Result<String, StudyError> {
    let edits = [("oscillator.dt", dt.into()), ("oscillator.initial_displacement", x0.into()), ("oscillator.initial_velocity", v0.into())];
    let mut doc = Preset::Oscillator.document().map_err(|e| StudyError::failed("", e))?;
    for (path, value) in edits {
        presets::set_path(&mut doc, path, value).map_err(|e| StudyError::failed("", e))?;
    }
    signorini_scene::SceneFile::from_table(doc.clone()).map_err(|e| StudyError::failed("", e))?;
    toml::to_string(&doc).map_err(|e| StudyError::Run(format!("the oscillator scene: {e}")))
}

/// The `(phase, velocity)` impacts of a run, or why it failed.
type Impacts = Result<Vec<(f64, f64)>, StudyError>;

/// The record window's impacts `(phase, velocity)` of one run.
fn impacts(text: &str, omega: f64, transient: f64, record: f64) -> Result<Vec<(f64, f64)>, StudyError> {
    let mut o = SweepOptions::new("forcing.omega", omega, omega, 1);
    o.transient = transient;
    o.record = record;
    let sweep = Sweep::new(text, "oscillator.toml", None, o, Limits::machine()).map_err(|e| StudyError::failed("", e))?;
    let (_, scene, plan) = sweep.scene((omega, None)).map_err(|e| StudyError::failed("", e))?;
    let rows = simulate(&scene, &plan, None, false, None);
    if rows.status != "ok" {
        return Err(StudyError::Run(format!("Ω = {omega}: {}", rows.status)));
    }
    Ok(rows.impacts.iter().map(|(_, v)| (v[1], v[2])).collect())
}

fn exact(omega: f64) -> Result<ImpactOscillator, StudyError> {
    ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: omega, gap: 0.2, restitution: 0.8 }).map_err(|e| StudyError::failed("", e))
}

/// Runs the study; `progress` after every batch of (Ω, dt) runs.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    a.validate()?;
    create_dir(&a.out)?;
    let start = std::time::Instant::now();
    let cases: Vec<(f64, f64)> = a.omegas.iter().flat_map(|&w| a.dts.iter().map(move |&dt| (w, dt))).collect();
    let (transient, record) = (a.transient, a.record);
    let mut results: Vec<Option<Impacts>> = crate::run_cases(&cases, progress, &|&(w, dt)| scene_text(dt, 0.0, 0.0).and_then(|t| impacts(&t, w, transient, record))).into_iter().map(Some).collect();
    let (f_, i_) = (Kind::F, Kind::I);
    let mut orbits = TableOut::create(
        &a.out,
        "orbits.csv",
        &[("omega", f_), ("dt", f_), ("impacts", i_), ("velocity_exact", f_), ("phase_exact", f_), ("multiplier", f_), ("velocity_err", f_), ("phase_err", f_)],
    )?;
    let mut rates = TableOut::create(&a.out, "rates.csv", &[("omega", f_), ("velocity_lsq_rate", f_), ("velocity_last_rate", f_), ("phase_lsq_rate", f_), ("phase_last_rate", f_)])?;
    let mut series = Vec::new();
    let mut report = String::new();
    let w_ = |r: std::fmt::Result| r.expect("writing to a String");
    // A rate needs two time steps: with one, the cell says so.
    let shown = |r: f64| if r.is_finite() { format!("{r:.2}") } else { "—".to_string() };
    w_(writeln!(
        report,
        "# Impact oscillator against its exact period-1 orbits\n\n| Ω | V exact | |μ| | velocity error (relative) at dt = {} … {} | rate | phase error (rad) | rate |\n|---|---|---|---|---|---|---|",
        a.dts[0],
        a.dts[a.dts.len() - 1]
    ));
    for &w in &a.omegas {
        let orbits_w = exact(w)?.period1_orbits();
        let [o] = orbits_w.as_slice() else {
            return Err(StudyError::Run(format!("Ω = {w}: {} admissible period-1 orbits (one expected in the stable range)", orbits_w.len())));
        };
        let mut ev = Vec::new();
        let mut ep = Vec::new();
        for (k, &(cw, dt)) in cases.iter().enumerate().filter(|(_, c)| c.0 == w) {
            let got = results[k].take().unwrap_or_else(|| Err(StudyError::Run("missing".into())))?;
            let e_v = got.iter().map(|(_, v)| (v - o.impact_velocity).abs() / o.impact_velocity).fold(0.0, f64::max);
            let e_p = got.iter().map(|(p, _)| (p - o.phase).abs()).fold(0.0, f64::max);
            orbits.row(vec![fd(cw), fde(dt), int(got.len()), fe(o.impact_velocity, 15), fe(o.phase, 15), fe(o.multipliers[0].abs(), 6), fe(e_v, 6), fe(e_p, 6)])?;
            ev.push((dt, e_v));
            ep.push((dt, e_p));
        }
        let (rv, rp) = (rate(&ev), rate(&ep));
        rates.row(vec![fd(w), ff(rv.lsq, 4), ff(rv.last, 4), ff(rp.lsq, 4), ff(rp.last, 4)])?;
        w_(writeln!(
            report,
            "| {w} | {:.6} | {:.3} | {:.2e} … {:.2e} | {} | {:.2e} … {:.2e} | {} |",
            o.impact_velocity,
            o.multipliers[0].abs(),
            ev[0].1,
            ev[ev.len() - 1].1,
            shown(rv.lsq),
            ep[0].1,
            ep[ep.len() - 1].1,
            shown(rp.lsq)
        ));
        series.push(Series { label: format!("Ω = {w}"), points: ev, reference: false, style: Style::default() });
    }
    let mut tables = vec![orbits.finish()?, rates.finish()?];
    let chart = Chart { title: "impact oscillator: impact velocity error against the exact period-1 orbit", x_label: "dt", y_label: "max relative error", scale: Scale::LogLog, size: (800, 560) };
    let notes: Vec<String> = crate::draw_or_skip(&a.out, "errors.svg", &chart, &series, "no impact velocity error above 0 to draw on its log-log axes")?.into_iter().collect();
    // Grazing: from the non-impacting steady state of each Ω.
    let wg = exact(2.0)?.grazing_frequencies();
    let mut graz = TableOut::create(&a.out, "grazing.csv", &[("omega", f_), ("offset", f_), ("impacts", i_), ("first_velocity", f_)])?;
    w_(writeln!(
        report,
        "\nGrazing frequency (steady amplitude = gap): {wg:?}; from the non-impacting steady state (dt = 1e-4, 30 periods):\n\n| Ω − Ω_g | impacts | first impact velocity |\n|---|---|---|"
    ));
    for &g in &wg {
        for d in [1e-3, 3e-4, -3e-4, -1e-3, -1e-2] {
            let w = g + d;
            let z = exact(w)?.steady_state(0.0);
            let im = impacts(&scene_text(1e-4, z.x, z.v)?, w, 0.0, 30.0)?;
            let v1 = im.first().map_or(f64::NAN, |p| p.1);
            graz.row(vec![fd(w), fde(d), int(im.len()), fe(v1, 6)])?;
            w_(writeln!(report, "| {d:+.0e} | {} | {} |", im.len(), if v1.is_nan() { "—".to_string() } else { format!("{v1:.4}") }));
        }
    }
    tables.push(graz.finish()?);
    let wall_s = since(start);
    w_(writeln!(report, "\nwrote {} in {wall_s:.1} s", a.out.display()));
    Ok(Output { tables, report, wall_s, notes })
}
