//! The beam between obstacles (`cargo xtask beam-obstacles`): the beam paper's general problem (P) —
//! the pipe of Dumont & Paoli between longitudinal obstacles `-g <= u(x) <= g`
//! at every node (the convex set K_h at the nodes), integrated by the
//! β-scheme with the exact multi-contact solve. Checks feasibility at every
//! step, measures self-convergence in dt (J fixed) and in J (dt fixed) of
//! the tip trajectory and of the displacement at the nodes every mesh
//! shares, and the discrete energy balance residual
//! `E^{N-1/2} - E^{1/2} - (W_support + W_contact)`.
//!
//! Outputs (`--out`, default `out/beam-obstacles`): `dt.csv`, `j.csv` (one
//! row per run, the reference last), `rates.csv`, `dt.svg`, `j.svg`
//! (log-log errors), `tip.svg` (the reference tip trajectory against ±g).

use crate::{create_dir, fde, fe, ff, int, since, txt, Cell, Kind, StudyError, Table, TableOut};
use signorini_plot::{line_chart, Chart, Scale, Series};
use signorini_run::beam::{node_dof, BeamScene, BeamSetup, BuiltBeam, Pipe};
use signorini_run::study::rate;
use signorini_run::{run as run_steps, Observer, RunConfig, RunError, Sample, Stop};
use signorini_schemes::SchemeSpec;
use std::path::PathBuf;
use std::time::Instant;

crate::options::study_config! {
    /// The beam between obstacles along its whole length (problem (P)):
    /// feasibility, self-convergence in dt (J = ⟨j⟩, time steps ⟨dts⟩) and in J
    /// (meshes ⟨js⟩ at ⟨j_dt⟩), energy balance.
    study "beam_obstacles";
    pub struct Config {
        /// Obstacles at -g and +g (m) along the whole beam.
        pub gap: f64 = 0.05,
        /// β of the β-scheme (>= 1/4: unconditionally stable).
        pub beta: f64 = 0.25,
        /// Horizon (s): long enough for several impacts, short enough that
        /// the vibro-impact motion has not become sensitive to rounding.
        pub t_end: f64 = 0.2,
        /// Time steps of the dt study (s), J fixed at ⟨j⟩; each must divide
        /// the first (coarsest), the reference is the last divided by 4.
        pub dts: Vec<f64> = vec![1e-4, 5e-5, 2.5e-5, 1.25e-5, 6.25e-6],
        /// Elements of the dt study.
        pub j: usize = 20,
        /// Meshes of the J study (each a multiple of the first), dt fixed at
        /// ⟨j_dt⟩; the reference is the last times 2.
        pub js: Vec<usize> = vec![5, 10, 20, 40, 80],
        /// Time step of the J study (s).
        pub j_dt: f64 = 1e-5,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/beam-obstacles"),
    }
}

/// What the study computed and wrote ([`crate::Report`]); its tables: `dt.csv`, `j.csv`, `rates.csv`.
pub type Output = crate::Report;

/// Records, at every `every`-th level, the displacement at the nodes
/// `x = i L / base` (i = 1..=base), and the largest bound violation.
struct Probe {
    dofs: Vec<usize>,
    every: usize,
    samples: Vec<Vec<f64>>,
    gap: f64,
    node_dofs: Vec<usize>,
    max_violation: f64,
    contact_steps: usize,
    max_active: usize,
    first_contact: Option<f64>,
}

impl Observer for Probe {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if s.n % self.every == 0 {
            self.samples.push(self.dofs.iter().map(|&d| s.u[d]).collect());
        }
        let mut worst = 0.0_f64;
        for &d in &self.node_dofs {
            worst = worst.max(s.u[d].abs() - self.gap);
        }
        self.max_violation = self.max_violation.max(worst);
        let active = s.status.iter().filter(|a| **a != signorini_schemes::Active::None).count();
        self.contact_steps += usize::from(active > 0);
        if active > 0 && self.first_contact.is_none() {
            self.first_contact = Some(s.t);
        }
        self.max_active = self.max_active.max(active);
        Ok(())
    }
}

struct RunOut {
    steps: usize,
    /// Per sampled level, the probe values (the tip last).
    samples: Vec<Vec<f64>>,
    max_violation: f64,
    balance: f64,
    energy_scale: f64,
    contact_steps: usize,
    max_active: usize,
    first_contact: Option<f64>,
    pivots: (u64, u64),
    wall: f64,
}

/// One run on `j` elements at `dt`, sampling the nodes `x = i L / base`
/// every `every` steps.
fn run_one(a: &Config, j: usize, dt: f64, base: usize, every: usize) -> Result<RunOut, StudyError> {
    let pipe = Pipe::paper();
    let scene = BeamScene::new("beam-obstacles", j, dt, a.t_end, SchemeSpec::ps(0.0, a.beta));
    let stops: Vec<Stop> = (1..=j).map(|i| Stop::new(i, -a.gap, a.gap)).collect();
    let start = Instant::now();
    let BuiltBeam { mut stepper, initial: init, beam, .. } = BeamSetup::new(pipe, scene).with_stops(stops).build().map_err(|e| StudyError::failed(format!("J = {j}, dt = {dt}"), e))?;
    let cfg = RunConfig::new(dt, a.t_end)?;
    let dofs: Vec<usize> = (1..=base).map(|i| node_dof(&beam, i * j / base).expect("a node")).collect();
    let node_dofs: Vec<usize> = (1..=j).map(|i| node_dof(&beam, i).expect("a node")).collect();
    let mut probe = Probe { dofs, every, samples: Vec::new(), gap: a.gap, node_dofs, max_violation: 0.0, contact_steps: 0, max_active: 0, first_contact: None };
    let e0 = stepper.energy().map(|e| e.1).unwrap_or(0.0);
    let w0 = stepper.work().unwrap_or((0.0, 0.0));
    run_steps(stepper.as_mut(), &init.u, &cfg, &mut [&mut probe]).map_err(|e| StudyError::failed(format!("J = {j}, dt = {dt}"), e))?;
    let e1 = stepper.energy().map(|e| e.1).unwrap_or(0.0);
    let w1 = stepper.work().unwrap_or((0.0, 0.0));
    let balance = (e1 - e0) - ((w1.0 - w0.0) + (w1.1 - w0.1));
    let energy_scale = e0.abs().max(e1.abs()).max((w1.0 - w0.0).abs());
    Ok(RunOut {
        steps: cfg.steps(),
        samples: probe.samples,
        max_violation: probe.max_violation,
        balance,
        energy_scale,
        contact_steps: probe.contact_steps,
        max_active: probe.max_active,
        first_contact: probe.first_contact,
        pivots: stepper.contact_pivots().unwrap_or((0, 0)),
        wall: start.elapsed().as_secs_f64(),
    })
}

/// (tip L∞ error, tip RMS error, all-probes L∞ error) against the
/// reference over the first `n` samples.
fn errors(r: &RunOut, reference: &RunOut, n: usize) -> (f64, f64, f64) {
    let (mut tip_max, mut tip_sq, mut all_max) = (0.0_f64, 0.0, 0.0_f64);
    let n = n.min(r.samples.len()).min(reference.samples.len());
    for (s, q) in r.samples.iter().zip(&reference.samples).take(n) {
        let tip = (s[s.len() - 1] - q[q.len() - 1]).abs();
        tip_max = tip_max.max(tip);
        tip_sq += tip * tip;
        for (x, y) in s.iter().zip(q) {
            all_max = all_max.max((x - y).abs());
        }
    }
    (tip_max, (tip_sq / n.max(1) as f64).sqrt(), all_max)
}

/// Columns of `dt.csv` and `j.csv`.
const COLUMNS: [(&str, Kind); 15] = [
    ("j", Kind::I),
    ("dt_s", Kind::F),
    ("steps", Kind::I),
    ("pre_impact_tip_linf_err_m", Kind::F),
    ("tip_linf_err_m", Kind::F),
    ("tip_rms_err_m", Kind::F),
    ("nodes_linf_err_m", Kind::F),
    ("max_violation_m", Kind::F),
    ("contact_steps", Kind::I),
    ("max_active", Kind::I),
    ("pivoting_steps", Kind::I),
    ("pivots_per_pivoting_step", Kind::F),
    ("energy_balance_residual", Kind::F),
    ("relative_balance_residual", Kind::F),
    ("wall_s", Kind::F),
];

/// The row of a run on `j` elements at `dt` (errors empty for the reference).
fn row(j: usize, dt: f64, r: &RunOut, pre: Option<f64>, e: Option<(f64, f64, f64)>) -> Vec<Cell> {
    let o = |x: Option<f64>| crate::opt(x.map(|x| fe(x, 6)));
    vec![
        int(j),
        fde(dt),
        int(r.steps),
        o(pre),
        o(e.map(|e| e.0)),
        o(e.map(|e| e.1)),
        o(e.map(|e| e.2)),
        fe(r.max_violation, 3),
        int(r.contact_steps),
        int(r.max_active),
        Cell::I(r.pivots.0 as i64),
        ff(r.pivots.1 as f64 / r.pivots.0.max(1) as f64, 3),
        fe(r.balance, 3),
        fe(r.balance / r.energy_scale.max(f64::MIN_POSITIVE), 3),
        ff(r.wall, 3),
    ]
}

/// Error points of a study: (tip L∞, probe nodes L∞, tip before the first
/// impact), each against the study's abscissa (dt or h).
type Points = (Vec<(f64, f64)>, Vec<(f64, f64)>, Vec<(f64, f64)>);

impl Config {
    /// Every check done before a file is created; an error names the option.
    pub fn validate(&self) -> Result<(), StudyError> {
        validate(self)
    }
}

fn validate(a: &Config) -> Result<(), StudyError> {
    if !(a.gap > 0.0 && a.gap.is_finite()) {
        return Err(StudyError::config("gap", format!("⟨gap⟩ {}: allowed finite and > 0", a.gap)));
    }
    if !(0.25..=0.5).contains(&a.beta) {
        return Err(StudyError::config("beta", format!("⟨beta⟩ {}: allowed [0.25, 0.5] (unconditionally stable)", a.beta)));
    }
    if !(a.t_end > 0.0 && a.t_end <= 10.0) {
        return Err(StudyError::config("t_end", format!("⟨t_end⟩ {}: allowed (0, 10] s", a.t_end)));
    }
    if a.dts.len() < 2 || a.dts.iter().any(|d| !(*d > 0.0 && d.is_finite())) {
        return Err(StudyError::config("dts", format!("⟨dts⟩ {:?}: allowed at least two positive time steps", a.dts)));
    }
    for d in &a.dts {
        let q = a.dts[0] / d;
        if (q - q.round()).abs() > 1e-9 * q || RunConfig::new(*d, a.t_end).is_err() {
            return Err(StudyError::config("dts", format!("⟨dts⟩: {d} must divide the first, {}, and ⟨t_end⟩ {} a whole number of times", a.dts[0], a.t_end)));
        }
    }
    if a.js.len() < 2 || a.js.iter().any(|j| *j == 0 || j % a.js[0] != 0 || *j > 2000) || !(2..=2000).contains(&a.j) {
        return Err(StudyError::config("js", format!("⟨js⟩ {:?} / ⟨j⟩ {}: allowed multiples of the first, each in [1, 2000] (and ⟨j⟩ in [2, 2000])", a.js, a.j)));
    }
    if RunConfig::new(a.j_dt, a.t_end).is_err() || RunConfig::new(a.j_dt, a.dts[0]).is_err() {
        return Err(StudyError::config("j_dt", format!("⟨j_dt⟩ {}: must divide ⟨t_end⟩ and the coarsest dt a whole number of times", a.j_dt)));
    }
    Ok(())
}

/// Runs the study; `progress` after every run.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    validate(a)?;
    let start = Instant::now();
    create_dir(&a.out)?;
    let mut notes = Vec::new();
    let total = (a.dts.len() + a.js.len() + 2) as u64;
    let done = std::cell::Cell::new(0u64);
    let tick = || {
        done.set(done.get() + 1);
        progress(done.get(), total);
    };
    let coarse = a.dts[0];
    let base = a.js[0];
    // dt study: J fixed, samples at the coarsest dt's levels.
    let dt_ref = a.dts[a.dts.len() - 1] / 4.0;
    let every = |dt: f64| (coarse / dt).round() as usize;
    let probes_j = if a.j % base == 0 { base } else { 1 };
    let reference = run_one(a, a.j, dt_ref, probes_j, every(dt_ref))?;
    tick();
    // Samples strictly before the reference's first contact.
    let pre_samples = |r: &RunOut| r.first_contact.map_or(usize::MAX, |t| (t / coarse - 1e-9).ceil() as usize);
    // One study: each case (J, dt, its abscissa) against `reference`, a row
    // of `file` each, then the reference's row; the error points
    // (tip L∞, probes L∞, tip before the first impact) against the abscissa.
    let study = |file: &str, reference: &RunOut, (j_ref, dt_ref): (usize, f64), cases: &[(usize, f64, f64)], probes: usize, notes: &mut Vec<String>| -> Result<(Points, Table), StudyError> {
        let mut f = TableOut::create(&a.out, file, &COLUMNS)?;
        let mut pts = (Vec::new(), Vec::new(), Vec::new());
        for &(j, dt, x) in cases {
            let r = run_one(a, j, dt, probes, every(dt))?;
            tick();
            let e = errors(&r, reference, usize::MAX);
            let pre = errors(&r, reference, pre_samples(reference)).0;
            pts.0.push((x, e.0));
            pts.1.push((x, e.2));
            pts.2.push((x, pre));
            f.row(row(j, dt, &r, Some(pre), Some(e)))?;
            notes.push(format!("J = {j}, dt = {dt:e}: tip error {:.3e} (before the first impact {pre:.3e}), max violation {:.1e}, balance {:.1e}", e.0, r.max_violation, r.balance));
        }
        f.row(row(j_ref, dt_ref, reference, None, None))?;
        Ok((pts, f.finish()?))
    };
    // dt study: J fixed; the reference's row last.
    let dt_cases: Vec<(usize, f64, f64)> = a.dts.iter().map(|&dt| (a.j, dt, dt)).collect();
    let (dt_pts, dt_table) = study("dt.csv", &reference, (a.j, dt_ref), &dt_cases, probes_j, &mut notes)?;
    // J study: dt fixed, samples at the coarsest dt's levels, nodes x = iL/base.
    let j_ref = 2 * a.js[a.js.len() - 1];
    let reference_j = run_one(a, j_ref, a.j_dt, base, every(a.j_dt))?;
    tick();
    let j_cases: Vec<(usize, f64, f64)> = a.js.iter().map(|&j| (j, a.j_dt, Pipe::paper().length / j as f64)).collect();
    let (j_pts, j_table) = study("j.csv", &reference_j, (j_ref, a.j_dt), &j_cases, base, &mut notes)?;
    let mut r = TableOut::create(&a.out, "rates.csv", &[("study", Kind::S), ("error", Kind::S), ("lsq_rate", Kind::F), ("last_rate", Kind::F)])?;
    for (study, err, pts) in [
        ("dt", "pre_impact_tip_linf", &dt_pts.2),
        ("dt", "tip_linf", &dt_pts.0),
        ("dt", "nodes_linf", &dt_pts.1),
        ("j", "pre_impact_tip_linf", &j_pts.2),
        ("j", "tip_linf", &j_pts.0),
        ("j", "nodes_linf", &j_pts.1),
    ] {
        let q = rate(pts);
        r.row(vec![txt(study), txt(err), ff(q.lsq, 3), ff(q.last, 3)])?;
        notes.push(format!("rate in {study} ({err}): {:.2} (least squares), {:.2} (last two)", q.lsq, q.last));
    }
    let tables = vec![dt_table, j_table, r.finish()?];
    let plot = |name: &str, title: &str, x: &str, pts: &Points| -> Result<(), StudyError> {
        let series = [
            Series { label: "tip, L∞ in time".into(), points: pts.0.clone(), reference: false, style: Default::default() },
            Series { label: "probe nodes, L∞".into(), points: pts.1.clone(), reference: false, style: Default::default() },
            Series { label: "tip, before the first impact".into(), points: pts.2.clone(), reference: false, style: Default::default() },
        ];
        let svg = line_chart(&Chart { title, x_label: x, y_label: "error against the reference (m)", scale: Scale::LogLog, size: (640, 420) }, &series).map_err(StudyError::Plot)?;
        crate::write_file(&a.out.join(name), &svg)
    };
    plot("dt.svg", "beam-obstacles: self-convergence in dt", "dt (s)", &dt_pts)?;
    plot("j.svg", "beam-obstacles: self-convergence in J", "h = L/J (m)", &j_pts)?;
    let tip: Vec<(f64, f64)> = reference_j.samples.iter().enumerate().map(|(n, s)| (n as f64 * coarse, s[s.len() - 1])).collect();
    let t = a.t_end;
    let series = [
        Series { label: format!("tip, J = {j_ref}, dt = {:e}", a.j_dt), points: tip, reference: false, style: Default::default() },
        Series { label: format!("obstacle +{}", a.gap), points: vec![(0.0, a.gap), (t, a.gap)], reference: true, style: Default::default() },
        Series { label: format!("obstacle -{}", a.gap), points: vec![(0.0, -a.gap), (t, -a.gap)], reference: true, style: Default::default() },
    ];
    let svg =
        line_chart(&Chart { title: "beam-obstacles: tip displacement u(L, t)", x_label: "t (s)", y_label: "u (m)", scale: Scale::Linear, size: (720, 420) }, &series).map_err(StudyError::Plot)?;
    crate::write_file(&a.out.join("tip.svg"), &svg)?;
    notes.push(format!("wrote {}", a.out.display()));
    Ok(Output { tables, report: String::new(), wall_s: since(start), notes })
}
