//! `cargo xtask work-precision`: error reached against wall time, per scheme
//! and mass, on `bar-dirichlet` (dx/dt = 10, T = 3) and `bar-neumann-gravity`
//! (dx/dt = 1, T = 16; 10 for the explicit schemes, whose CFL limit is below h).
//!
//! Outputs (`out/work-precision/`): `work_precision.csv` with columns
//! `benchmark,scheme,mass,m,dt,steps,l2_l2_u,linf_energy,wall_s` (wall time
//! of the stepping alone, best of 3, runs one at a time), `<benchmark>.svg`
//! (log-log, L²(L²) error against wall time), and on stdout the cheapest
//! configuration reaching each accuracy band.

use crate::create;
use signorini_fem::BarMass;
use signorini_plot::{line_chart, Chart, Scale, Series};
use signorini_run::study::{self, StudyConfig};
use signorini_run::{run, Benchmark, RunConfig};
use signorini_schemes::SchemeSpec;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/work-precision")]
    out: PathBuf,
    /// Levels m.
    #[arg(long, value_delimiter = ',', default_value = "10,20,40,80,160,320,640")]
    levels: Vec<usize>,
}

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
fn time_stepping(b: Benchmark, scheme: SchemeSpec, mass: BarMass, m: usize, ratio: f64, t_end: f64) -> Result<f64, String> {
    let exact = b.exact(t_end).map_err(|e| e.to_string())?;
    let p = b.problem(exact.as_ref(), m, mass).map_err(|e| e.to_string())?;
    let dt = p.bar.h() / ratio;
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let mut s = scheme.build(p.dynamics(), dt, &p.initial).map_err(|e| e.to_string())?;
        let start = std::time::Instant::now();
        run(s.as_mut(), &p.initial.u, &RunConfig::new(dt, t_end).map_err(|e| e.to_string())?, &mut []).map_err(|e| e.to_string())?;
        best = best.min(start.elapsed().as_secs_f64());
    }
    Ok(best)
}

/// Runs the study.
pub fn run_wp(a: Args) -> Result<(), String> {
    let schemes: Vec<SchemeSpec> = SchemeSpec::named().map(|(_, s)| s).collect();
    // Everything is checked before a file is created.
    for benchmark in [Benchmark::BarDirichlet, Benchmark::BarNeumannGravity] {
        let (ratio, t_end) = benchmark.default_ratio_and_horizon();
        for r in [ratio, ratio.max(10.0)] {
            StudyConfig { benchmark, schemes: schemes.clone(), masses: vec![BarMass::Std], levels: a.levels.clone(), ratio: r, t_end, norms: Default::default() }.validate().map_err(|e| format!("--levels: {e}"))?;
        }
    }
    crate::fits_memory("--levels", a.levels.iter().copied().max().unwrap_or(0), 1)?;
    std::fs::create_dir_all(&a.out).map_err(|e| e.to_string())?;
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
            let cfg = StudyConfig { benchmark, schemes: vec![*scheme], masses: ok, levels: a.levels.clone(), ratio, t_end, norms: Default::default() };
            for r in study::sweep(&cfg, &|| {}).map_err(|e| e.to_string())? {
                for l in &r.levels {
                    let wall = time_stepping(benchmark, r.scheme, r.mass, l.m, ratio, t_end)?;
                    points.push(Point { benchmark, scheme: r.scheme, mass: r.mass, m: l.m, dt: l.dt, steps: l.steps, err: l.norms.l2_l2_u, energy: l.norms.linf_energy, wall });
                }
            }
        }
    }
    let mut w = csv::Writer::from_writer(create(&a.out, "work_precision.csv")?);
    w.write_record(["benchmark", "scheme", "mass", "m", "dt", "steps", "l2_l2_u", "linf_energy", "wall_s"]).map_err(|e| e.to_string())?;
    for p in &points {
        w.write_record([p.benchmark.to_string(), p.scheme.to_string(), p.mass.to_string(), p.m.to_string(), format!("{:.6e}", p.dt), p.steps.to_string(), format!("{:.6e}", p.err), format!("{:.6e}", p.energy), format!("{:.6e}", p.wall)])
            .map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())?;
    println!("# Work–precision (L²(0,T;L²) error of u against stepping wall time)\n");
    for benchmark in [Benchmark::BarDirichlet, Benchmark::BarNeumannGravity] {
        let pts: Vec<&Point> = points.iter().filter(|p| p.benchmark == benchmark).collect();
        let mut keys: Vec<(String, String)> = pts.iter().map(|p| (p.scheme.to_string(), p.mass.to_string())).collect();
        keys.dedup();
        let series: Vec<Series> = keys
            .iter()
            .map(|(s, m)| Series { label: format!("{s} {m}"), points: pts.iter().filter(|p| &p.scheme.to_string() == s && &p.mass.to_string() == m).map(|p| (p.wall, p.err)).collect(), reference: false, style: Default::default() })
            .collect();
        let svg = line_chart(&Chart { title: &format!("{benchmark}: error against wall time"), x_label: "wall time (s)", y_label: "L²(0,T;L²) error", scale: Scale::LogLog, size: (1000, 650) }, &series)?;
        std::fs::write(a.out.join(format!("{benchmark}.svg")), svg).map_err(|e| e.to_string())?;
        println!("## {benchmark}\n\n| target error | cheapest (scheme, mass, m) | wall (s) | error | runner-up | wall (s) |\n|---|---|---|---|---|---|");
        for target in [3e-2, 1e-2, 3e-3, 1e-3] {
            // Per configuration, the cheapest level that reaches the target.
            let mut best: Vec<&Point> = keys
                .iter()
                .filter_map(|(s, m)| pts.iter().filter(|p| &p.scheme.to_string() == s && &p.mass.to_string() == m && p.err <= target).min_by(|a, b| a.wall.total_cmp(&b.wall)).copied())
                .collect();
            best.sort_by(|a, b| a.wall.total_cmp(&b.wall));
            match (best.first(), best.get(1)) {
                (Some(b0), r) => println!(
                    "| {target:.0e} | {} {} m={} | {:.2e} | {:.2e} | {} | {} |",
                    b0.scheme,
                    b0.mass,
                    b0.m,
                    b0.wall,
                    b0.err,
                    r.map_or("-".into(), |r| format!("{} {} m={}", r.scheme, r.mass, r.m)),
                    r.map_or("-".into(), |r| format!("{:.2e}", r.wall))
                ),
                (None, _) => println!("| {target:.0e} | not reached at these levels | | | | |"),
            }
        }
        println!();
    }
    Ok(())
}
