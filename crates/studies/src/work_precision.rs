//! The work–precision study (`cargo xtask work-precision`): error reached against wall time, per scheme
//! and mass, on `bar-dirichlet` (dx/dt = 10, T = 3) and `bar-neumann-gravity`
//! (dx/dt = 1, T = 16; 10 for the explicit schemes, whose CFL limit is below h).
//!
//! Outputs (`out/work-precision/`): `work_precision.csv` with columns
//! `benchmark,scheme,mass,m,dt,steps,l2_l2_u,linf_energy,wall_s` (wall time
//! of the stepping alone, best of 3, runs one at a time), `<benchmark>.svg`
//! (log-log, L²(L²) error against wall time), and on stdout the cheapest
//! configuration reaching each accuracy band.

use crate::{create_dir, fe, int, since, txt, Kind, StudyError, TableOut};
use signorini_fem::BarMass;
use signorini_plot::{line_chart, Chart, Scale, Series};
use signorini_run::study::{self, StudyConfig};
use signorini_run::{run as run_steps, Benchmark, RunConfig};
use signorini_schemes::SchemeSpec;
use std::fmt::Write as _;
use std::path::PathBuf;

/// What to run.
#[derive(Clone, Debug)]
pub struct Config {
    /// Output folder (`--out`, default `out/work-precision`).
    pub out: PathBuf,
    /// Levels m (`--levels`, default 10, 20, …, 640).
    pub levels: Vec<usize>,
}

impl Default for Config {
    /// `cargo xtask work-precision` without options.
    fn default() -> Self {
        Config { out: PathBuf::from("out/work-precision"), levels: vec![10, 20, 40, 80, 160, 320, 640] }
    }
}

impl Config {
    /// Every check done before a file is created; an error names `--levels`.
    pub fn validate(&self) -> Result<(), StudyError> {
        let schemes: Vec<SchemeSpec> = SchemeSpec::named().map(|(_, s)| s).collect();
        for benchmark in [Benchmark::BarDirichlet, Benchmark::BarNeumannGravity] {
            let (ratio, t_end) = benchmark.default_ratio_and_horizon();
            for r in [ratio, ratio.max(10.0)] {
                StudyConfig { benchmark, schemes: schemes.clone(), masses: vec![BarMass::Std], levels: self.levels.clone(), ratio: r, t_end, norms: Default::default(), degree: 1 }
                    .validate()
                    .map_err(|e| StudyError::config("--levels", format!("--levels: {e}")))?;
            }
        }
        crate::fits_memory("--levels", self.levels.iter().copied().max().unwrap_or(0), 1)
    }
}

/// What the study computed and wrote ([`crate::Report`]); its tables: `work_precision.csv`.
pub type Output = crate::Report;

struct Point {
    benchmark: Benchmark,
    scheme: SchemeSpec,
    mass: BarMass,
    m: usize,
    dt: f64,
    steps: usize,
    err: f64,
    energy: f64,
    wall: f64,
}

/// Wall time of the stepping alone (no observers), best of 3.
fn time_stepping(b: Benchmark, scheme: SchemeSpec, mass: BarMass, m: usize, ratio: f64, t_end: f64) -> Result<f64, StudyError> {
    let exact = b.exact(t_end)?;
    let p = b.problem(exact.as_ref(), m, mass)?;
    let dt = p.bar.h() / ratio;
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let mut s = scheme.build(p.dynamics(), dt, &p.initial).map_err(|e| StudyError::Run(e.to_string()))?;
        let start = std::time::Instant::now();
        run_steps(s.as_mut(), &p.initial.u, &RunConfig::new(dt, t_end)?, &mut [])?;
        best = best.min(start.elapsed().as_secs_f64());
    }
    Ok(best)
}

/// Runs the study; `progress` after every (benchmark, scheme) sweep and its timings.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    let schemes: Vec<SchemeSpec> = SchemeSpec::named().map(|(_, s)| s).collect();
    // Everything is checked before a file is created.
    a.validate()?;
    let start = std::time::Instant::now();
    create_dir(&a.out)?;
    let total = 2 * schemes.len() as u64;
    let mut done = 0;
    // Every mass treatment (mod1 is mod under another name).
    let masses: Vec<BarMass> = BarMass::ALL.into_iter().filter(|m| *m != BarMass::Mod1).collect();
    let mut points = Vec::new();
    for benchmark in [Benchmark::BarDirichlet, Benchmark::BarNeumannGravity] {
        let (ratio, t_end) = benchmark.default_ratio_and_horizon();
        for scheme in &schemes {
            let ok: Vec<BarMass> = masses.iter().copied().filter(|m| scheme.accepts_massless_node(m.massless_contact_node())).collect();
            // Explicit schemes cannot take dt = h (their CFL limit is below it):
            // they run at dx/dt = 10 on every benchmark.
            let ratio = if scheme.is_explicit() { ratio.max(10.0) } else { ratio };
            let cfg = StudyConfig { benchmark, schemes: vec![*scheme], masses: ok, levels: a.levels.clone(), ratio, t_end, norms: Default::default(), degree: 1 };
            for r in study::sweep(&cfg, &|| {})? {
                for l in &r.levels {
                    let wall = time_stepping(benchmark, r.scheme, r.mass, l.m, ratio, t_end)?;
                    points.push(Point { benchmark, scheme: r.scheme, mass: r.mass, m: l.m, dt: l.dt, steps: l.steps, err: l.norms.l2_l2_u, energy: l.norms.linf_energy, wall });
                }
            }
            done += 1;
            progress(done, total);
        }
    }
    let (s_, f_, i_) = (Kind::S, Kind::F, Kind::I);
    let mut w = TableOut::create(&a.out, "work_precision.csv", &[("benchmark", s_), ("scheme", s_), ("mass", s_), ("m", i_), ("dt", f_), ("steps", i_), ("l2_l2_u", f_), ("linf_energy", f_), ("wall_s", f_)])?;
    for p in &points {
        w.row(vec![txt(p.benchmark.to_string()), txt(p.scheme.to_string()), txt(p.mass.to_string()), int(p.m), fe(p.dt, 6), int(p.steps), fe(p.err, 6), fe(p.energy, 6), fe(p.wall, 6)])?;
    }
    let table = w.finish()?;
    let mut report = String::from("# Work–precision (L²(0,T;L²) error of u against stepping wall time)\n\n");
    for benchmark in [Benchmark::BarDirichlet, Benchmark::BarNeumannGravity] {
        let pts: Vec<&Point> = points.iter().filter(|p| p.benchmark == benchmark).collect();
        let mut keys: Vec<(String, String)> = pts.iter().map(|p| (p.scheme.to_string(), p.mass.to_string())).collect();
        keys.dedup();
        let series: Vec<Series> = keys
            .iter()
            .map(|(s, m)| Series { label: format!("{s} {m}"), points: pts.iter().filter(|p| &p.scheme.to_string() == s && &p.mass.to_string() == m).map(|p| (p.wall, p.err)).collect(), reference: false, style: Default::default() })
            .collect();
        let svg = line_chart(&Chart { title: &format!("{benchmark}: error against wall time"), x_label: "wall time (s)", y_label: "L²(0,T;L²) error", scale: Scale::LogLog, size: (1000, 650) }, &series).map_err(StudyError::Plot)?;
        crate::write_file(&a.out.join(format!("{benchmark}.svg")), &svg)?;
        report.push_str(&format!("## {benchmark}\n\n| target error | cheapest (scheme, mass, m) | wall (s) | error | runner-up | wall (s) |\n|---|---|---|---|---|---|\n"));
        for target in [3e-2, 1e-2, 3e-3, 1e-3] {
            // Per configuration, the cheapest level that reaches the target.
            let mut best: Vec<&Point> = keys
                .iter()
                .filter_map(|(s, m)| pts.iter().filter(|p| &p.scheme.to_string() == s && &p.mass.to_string() == m && p.err <= target).min_by(|a, b| a.wall.total_cmp(&b.wall)).copied())
                .collect();
            best.sort_by(|a, b| a.wall.total_cmp(&b.wall));
            match (best.first(), best.get(1)) {
                (Some(b0), r) => writeln!(
                    report,
                    "| {target:.0e} | {} {} m={} | {:.2e} | {:.2e} | {} | {} |",
                    b0.scheme,
                    b0.mass,
                    b0.m,
                    b0.wall,
                    b0.err,
                    r.map_or("-".into(), |r| format!("{} {} m={}", r.scheme, r.mass, r.m)),
                    r.map_or("-".into(), |r| format!("{:.2e}", r.wall))
                ),
                (None, _) => writeln!(report, "| {target:.0e} | not reached at these levels | | | | |"),
            }
            .expect("writing to a String");
        }
        report.push('\n');
    }
    Ok(Output { tables: vec![table], report, wall_s: since(start), notes: Vec::new() })
}
