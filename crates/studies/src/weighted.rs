//! The weighted-mass-redistribution study (`cargo xtask weighted`)
//! (the weighted mass-redistribution paper, docs/theory.md §10; masses §2.1.2,
//! schemes §4.5).
//!
//! Outputs (folder `out/weighted/` by default):
//! * `series/<scheme>_<mass>_m<M>.csv`: time series on [0, T] of the contact
//!   node — columns `t,u0,u0_exact,lambda_t,lambda,lambda_exact,energy_t,energy,energy_exact`;
//! * `plots/<scheme>_{u0,lambda,energy}_T<T>.svg`: the three weights against the exact solution;
//! * `phase.csv`: `scheme,mass,m,dt,takeoff,takeoff_error,impact2,impact2_error,u0_linf_0_30`
//!   (exact take-off at t = 2, next impact at t = 4);
//! * `energy.csv`: `scheme,mass,m,dt,energy_1,energy_3,energy_30,initial_loss,dissipated_3,dissipated_30`:
//!   `energy_1` is E_h after the first step, which moves the massless node to
//!   its equilibrium: `initial_loss = 1/8 - energy_1` is h/8 plus a
//!   scheme-dependent O(dt²/h) term (docs/theory.md §7.7); `dissipated_T =
//!   energy_1 - E_h(T)`. For `ps-e1` (two-step, energies at half steps),
//!   `energy_1` is `E^{3/2}`: its `E^{1/2}` has lost only part (3h/32) of
//!   the start-up loss, the rest goes in the next half step;
//! * `convergence/`: the same files as `cargo xtask convergence` for the
//!   (scheme, weight) pairs.

use crate::{create_dir, fe, int, opt, since, txt, Cell, Kind, StudyError, Table, TableOut};
use signorini_exact::{BarDirichlet, ExactSolution};
use signorini_fem::BarMass;
use signorini_plot::{line_chart, Chart, Scale, Series};
use signorini_run::analysis::{events, linf_error};
use signorini_run::study::{self, ConfigResult, StudyConfig};
use signorini_run::{Benchmark, History, Record, RunConfig};
use signorini_schemes::SchemeSpec;
use std::path::{Path, PathBuf};

crate::options::study_config! {
    /// The weighted-mass-redistribution study (mod1/mod2/mod3 × newmark-cn,
    /// backward-euler, ps-e1, hybrid): figure runs, phase errors, energy loss and
    /// convergence.
    study "weighted";
    pub struct Config {
        /// Horizon of the figure runs (the paper's figures show [0, 3]; the
        /// phase and energy tables use 3 and 30).
        pub t_end: f64 = 30.0,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/weighted"),
    }
}

impl Config {
    /// Every check done before a file is created; an error names `--t-end`.
    pub fn validate(&self) -> Result<(), StudyError> {
        if !(self.t_end >= 4.5 && self.t_end.is_finite()) {
            return Err(StudyError::config("t_end", format!("⟨t_end⟩ {}: allowed finite and >= 4.5 (the second impact is at t = 4)", self.t_end)));
        }
        for (_, dt) in RESOLUTIONS {
            RunConfig::new(dt, self.t_end).map_err(|e| StudyError::config("t_end", format!("⟨t_end⟩: {e}")))?;
        }
        Ok(())
    }
}

/// What the study computed and wrote.
#[derive(Clone, Debug)]
pub struct Output {
    /// Per (scheme, weight) pair, the convergence sweep's levels (dx/dt = 10, T = 3).
    pub convergence: Vec<ConfigResult>,
    /// One table per CSV written: `series/<scheme>_<mass>_m<M>.csv` in run
    /// order, `phase.csv`, `energy.csv`, then the `convergence/` files.
    pub tables: Vec<Table>,
    /// The Markdown report `cargo xtask weighted` prints.
    pub report: String,
    /// Wall time of the whole study (s).
    pub wall_s: f64,
    /// Notes and warnings for stderr.
    pub notes: Vec<String>,
}

const SCHEMES: [&str; 4] = ["newmark-cn", "backward-euler", "ps-e1", "hybrid"];
const MASSES: [BarMass; 3] = [BarMass::Mod1, BarMass::Mod2, BarMass::Mod3];
/// The paper's figure resolution (dx = 1/6, dt = 1/100) and a 4× finer one at the same ratio.
const RESOLUTIONS: [(usize, f64); 2] = [(6, 0.01), (24, 0.0025)];

struct FigureRun {
    scheme: String,
    mass: BarMass,
    m: usize,
    dt: f64,
    records: Vec<Record>,
}

fn figure_run(scheme: SchemeSpec, mass: BarMass, m: usize, dt: f64, t_end: f64) -> Result<FigureRun, StudyError> {
    let exact = BarDirichlet;
    let p = Benchmark::BarDirichlet.problem(&exact, m, mass)?;
    let mut s = scheme.build(p.dynamics(), dt, &p.initial).map_err(|e| StudyError::failed("", e))?;
    let mut h = History::new(0, true);
    signorini_run::run(s.as_mut(), &p.initial.u, &RunConfig::new(dt, t_end)?, &mut [&mut h])?;
    Ok(FigureRun { scheme: scheme.to_string(), mass, m, dt, records: h.records })
}

fn write_series(dir: &Path, r: &FigureRun) -> Result<Table, StudyError> {
    let ex = BarDirichlet;
    let names = ["t", "u0", "u0_exact", "lambda_t", "lambda", "lambda_exact", "energy_t", "energy", "energy_exact"].map(|n| (n, Kind::F));
    let mut w = TableOut::create_in(dir, "series/", &format!("{}_{}_m{}.csv", r.scheme, r.mass, r.m), &names)?;
    let f = |x: f64| fe(x, 10);
    let o = |x: Option<f64>| opt(x.map(f));
    for rec in &r.records {
        let lt = rec.lambda.map(|l| l.0);
        w.row(vec![
            f(rec.t),
            f(rec.u_contact),
            f(ex.fields(0.0, rec.t).u),
            o(lt),
            o(rec.lambda.map(|l| l.1)),
            o(lt.map(|t| ex.lambda(t))),
            o(rec.energy.map(|e| e.0)),
            o(rec.energy.map(|e| e.1)),
            f(ex.energy()),
        ])?;
    }
    w.finish()
}

fn plot(dir: &Path, scheme: &str, runs: &[&FigureRun], what: &str, t_max: f64) -> Result<(), StudyError> {
    let ex = BarDirichlet;
    let pick = |rec: &Record| -> Option<(f64, f64)> {
        match what {
            "u0" => Some((rec.t, rec.u_contact)),
            "lambda" => rec.lambda,
            _ => rec.energy,
        }
    };
    let mut series: Vec<Series> =
        runs.iter().map(|r| Series { label: r.mass.to_string(), points: r.records.iter().filter_map(pick).filter(|p| p.0 <= t_max).collect(), reference: false, style: Default::default() }).collect();
    let n = 3000;
    let exact: Vec<(f64, f64)> = (0..=n)
        .map(|i| t_max * i as f64 / n as f64)
        .map(|t| {
            (
                t,
                match what {
                    "u0" => ex.fields(0.0, t).u,
                    "lambda" => ex.lambda(t),
                    _ => ex.energy(),
                },
            )
        })
        .collect();
    series.push(Series { label: "exact".into(), points: exact, reference: true, style: Default::default() });
    let m = runs.first().map_or(0, |r| r.m);
    let dt = runs.first().map_or(0.0, |r| r.dt);
    let title = format!("{scheme}: {what}, dx = 1/{m}, dt = {dt}");
    let y = match what {
        "u0" => "u(0,t)",
        "lambda" => "λ(t)",
        _ => "energy",
    };
    let svg = line_chart(&Chart { title: &title, x_label: "t", y_label: y, scale: Scale::Linear, size: (900, 450) }, &series).map_err(StudyError::Plot)?;
    crate::write_file(&dir.join(format!("{scheme}_{what}_T{t_max}.svg")), &svg)
}

/// Runs the study: figure runs, phase and energy tables, then the
/// convergence of every (scheme, weight) pair (the only part that reports
/// progress, after every run of its sweep).
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    // Everything is checked before a file is created.
    a.validate()?;
    let (series_dir, plots_dir) = (a.out.join("series"), a.out.join("plots"));
    for d in [&a.out, &series_dir, &plots_dir] {
        create_dir(d)?;
    }
    let start = std::time::Instant::now();
    let schemes: Vec<SchemeSpec> = SCHEMES.iter().map(|s| s.parse().map_err(|e| StudyError::failed("", e))).collect::<Result<_, _>>()?;
    // Figure runs.
    let mut runs = Vec::new();
    for (m, dt) in RESOLUTIONS {
        for s in &schemes {
            for mass in MASSES {
                runs.push(figure_run(*s, mass, m, dt, a.t_end)?);
            }
        }
    }
    let mut tables = Vec::new();
    for r in &runs {
        tables.push(write_series(&series_dir, r)?);
    }
    for s in SCHEMES {
        let fig: Vec<&FigureRun> = runs.iter().filter(|r| r.scheme == s && r.m == RESOLUTIONS[0].0).collect();
        plot(&plots_dir, s, &fig, "u0", 3.0)?;
        plot(&plots_dir, s, &fig, "u0", a.t_end)?;
        plot(&plots_dir, s, &fig, "lambda", 3.0)?;
        plot(&plots_dir, s, &fig, "energy", a.t_end)?;
    }
    // Phase shift and energy tables.
    let ex = BarDirichlet;
    let head = |names: &[&'static str]| -> Vec<(&'static str, Kind)> {
        names
            .iter()
            .map(|&n| {
                (
                    n,
                    if n == "scheme" || n == "mass" {
                        Kind::S
                    } else if n == "m" {
                        Kind::I
                    } else {
                        Kind::F
                    },
                )
            })
            .collect()
    };
    let mut phase = TableOut::create(&a.out, "phase.csv", &head(&["scheme", "mass", "m", "dt", "takeoff", "takeoff_error", "impact2", "impact2_error", "u0_linf_0_30"]))?;
    let mut energy = TableOut::create(&a.out, "energy.csv", &head(&["scheme", "mass", "m", "dt", "energy_1", "energy_3", "energy_30", "initial_loss", "dissipated_3", "dissipated_30"]))?;
    let mut md_phase = String::from("| scheme | mass | m | take-off − 2 | 2nd impact − 4 | max |u₀ − u₀ₑₓ| on [0,30] |\n|---|---|---|---|---|---|\n");
    let mut md_energy = String::from("| scheme | mass | m | E_h(dt) | E_h(3) | E_h(30) | dissipated by 3 | dissipated by 30 |\n|---|---|---|---|---|---|---|---|\n");
    let opt = |x: Option<f64>| x.map_or("none".to_string(), |v| format!("{v:+.4}"));
    for r in &runs {
        let ev = events(&r.records);
        let (to_err, im_err) = (ev.first_takeoff.map(|t| t - 2.0), ev.second_impact.map(|t| t - 4.0));
        let linf = linf_error(&r.records, 30.0, |t| ex.fields(0.0, t).u);
        let e_at = |t: f64| r.records.iter().rev().filter_map(|x| x.energy).find(|e| e.0 <= t + 1e-9).map_or(f64::NAN, |e| e.1);
        // After the first full step: E^1, or E^{3/2} for a two-step scheme
        // (whose first energy, E^{1/2}, still holds part of the start-up loss).
        let e1 = r.records.iter().filter_map(|x| x.energy).find(|e| e.0 >= r.dt - 1e-9).map_or(f64::NAN, |e| e.1);
        let (e3, e30) = (e_at(3.0), e_at(30.0));
        let f = |x: f64| fe(x, 6);
        let fo = |x: Option<f64>| -> Cell { crate::opt(x.map(f)) };
        phase.row(vec![txt(r.scheme.clone()), txt(r.mass.to_string()), int(r.m), f(r.dt), fo(ev.first_takeoff), fo(to_err), fo(ev.second_impact), fo(im_err), f(linf)])?;
        energy.row(vec![txt(r.scheme.clone()), txt(r.mass.to_string()), int(r.m), f(r.dt), f(e1), f(e3), f(e30), f(0.125 - e1), f(e1 - e3), f(e1 - e30)])?;
        md_phase.push_str(&format!("| {} | {} | {} | {} | {} | {:.4} |\n", r.scheme, r.mass, r.m, opt(to_err), opt(im_err), linf));
        md_energy.push_str(&format!("| {} | {} | {} | {:.5} | {:.5} | {:.5} | {:.2e} | {:.2e} |\n", r.scheme, r.mass, r.m, e1, e3, e30, e1 - e3, e1 - e30));
    }
    tables.push(phase.finish()?);
    tables.push(energy.finish()?);
    // Convergence of every (scheme, weight) pair, as `cargo xtask convergence`.
    let cfg = StudyConfig::new(Benchmark::BarDirichlet, schemes, MASSES.to_vec(), vec![10, 20, 40, 80, 160, 320, 640], 10.0, 3.0);
    let mut notes = Vec::new();
    let (results, _, conv_tables) = crate::convergence::sweep_into(&cfg, &a.out.join("convergence"), "convergence/", progress, &mut notes)?;
    tables.extend(conv_tables);
    let mut report = format!("# Weighted mass redistribution (bar-dirichlet; output in {})\n\n", a.out.display());
    report.push_str(&format!("## Phase: events of the contact node (resolution dt; exact take-off 2, next impact 4)\n\n{md_phase}\n"));
    report.push_str(&format!("## Energy (exact E = 1/8; the first step loses h/8 + O(dt²/h) to the massless node's equilibrium)\n\n{md_energy}\n"));
    report.push_str(&format!("## Convergence (dx/dt = 10, T = 3), least-squares rates\n\n{}\n", study::markdown_table(&results)));
    let wall_s = since(start);
    report.push_str(&format!("done in {wall_s:.1} s\n"));
    Ok(Output { convergence: results, tables, report, wall_s, notes })
}
