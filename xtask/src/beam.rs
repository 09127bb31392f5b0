//! `cargo xtask beam`: the beam between two stops (Dumont & Paoli; docs/theory.md §8).
//!
//! Outputs (folder `out/beam/` by default):
//! * `<scene>_tip.csv` (`t_s,tip_m`: the physical tip displacement ũ(L,t),
//!   decimated to at most 20 000 rows) and `<scene>_tip.svg`;
//! * `scenes.csv`: `scene,contact,beta,dt_s,steps,impacts,contact_episodes,first_impacts_s,max_abs_tip_minus_gap_m,energy_start,energy_end,work_support,work_contact,balance_residual,wall_s,paper_s,speedup`;
//!   each penalty figure (`fig5`–`fig7`, the spring read in N/m) is followed
//!   by a row `<fig>-unscaled` with the same number used unscaled in the
//!   scaled equation ([`PenaltyUnits`]; contact `penalty 1e8 unscaled`);
//! * `penalty.csv`: `units,stiffness,kappa_scaled_s2,dt_s,max_abs_tip_minus_gap_m,min_over_dt_m,max_over_dt_m,relative_spread`:
//!   the largest violation of the stops with the penalty (J = 19, T = 2 s)
//!   for each reading of the stiffness and each dt of `--penalty-dts`, and
//!   its least and largest value over those dt (`relative_spread` =
//!   (max − min)/min), so that the paper's 2.25e-4 m can be compared with
//!   both (docs/theory.md §8.1);
//! * `stability.csv`: `J,beta,kappa_h,dt_critical_s,dt_paper_bound_s,dt_sufficient_exact_kappa_s`
//!   (exact limit, `inf` for β >= 1/4; the paper's sufficient condition (3.1)
//!   with its κ bound, and with the exact κ_h);
//! * `self_convergence.csv`: `dt_s,linf_tip_error_before_impact_m,rate_before_impact,linf_tip_error_m,rate`:
//!   the tip against a run with dt/64 (β = 1/2, projection), on [0, 0.085] s
//!   (before the first impact, at 0.0878 s) and on [0, 0.2] s (the first
//!   contact period, where the paper says trajectories agree).
//!
//! `impacts` counts every step at which contact starts (the tip chatters:
//! many one-step contacts per contact period); `contact_episodes` groups
//! contacts separated by less than 5 ms.
//!
//! Energies are those of the lifted variable `u = ũ - h φ` (unit ρS), whose
//! balance with the work of the load `f` is exact for the β-scheme.

use crate::create;
use signorini_plot::{line_chart, Chart, Scale, Series};
use signorini_run::beam::{build_with_units, stability_limit, BeamContact, BeamScene, PenaltyUnits, Pipe};
use signorini_run::{run, Observer, RunConfig, RunError, Sample};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `cargo xtask beam`.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/beam")]
    out: PathBuf,
    /// Scenes to run, comma-separated (fig2 … fig8).
    #[arg(long, value_delimiter = ',', default_value = "fig2,fig3,fig4,fig5,fig6,fig7,fig8")]
    scenes: Vec<String>,
    /// Run conditionally stable scenes even beyond their stability limit.
    #[arg(long)]
    force: bool,
    /// Time steps (s) of the penalty study (`penalty.csv`), comma-separated;
    /// the paper's are 5e-6, 1e-6, 5e-7 (runs the figures already made are
    /// reused).
    #[arg(long = "penalty-dts", value_delimiter = ',', default_value = "5e-6,1e-6,5e-7")]
    penalty_dts: Vec<f64>,
}

/// End of the first contact period (s): trajectories of different dt agree
/// up to here.
const FIRST_PERIOD: f64 = 0.2;

/// Watches the tip: decimated trajectory, impacts, extreme, energies, work.
struct Tip {
    dof: usize,
    every: usize,
    gap: f64,
    series: Vec<(f64, f64)>,
    impacts: Vec<f64>,
    was_active: bool,
    max_excess: f64,
    /// The largest excess on the first contact period [0, 0.2] s, where
    /// runs with different dt still agree (docs/theory.md §5.3).
    max_excess_first: f64,
    /// Energy at the first level the scheme defines it (t_{1/2} for the
    /// β-scheme, 0 for Newmark) and at the end, and the work at the end
    /// (read from the scheme before and after the run: no per-step cost).
    energy: Option<(f64, f64)>,
    energy_last: Option<f64>,
    work: Option<(f64, f64)>,
}

impl Observer for Tip {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let u = s.u[self.dof];
        if s.n % self.every == 0 {
            self.series.push((s.t, u));
        }
        if s.active && !self.was_active {
            self.impacts.push(s.t);
        }
        self.was_active = s.active;
        self.max_excess = self.max_excess.max(u.abs() - self.gap);
        if s.t <= FIRST_PERIOD + 1e-12 {
            self.max_excess_first = self.max_excess_first.max(u.abs() - self.gap);
        }
        Ok(())
    }
}

struct SceneResult {
    steps: usize,
    tip: Tip,
    wall: f64,
}

fn run_scene(pipe: &Pipe, scene: &BeamScene, units: PenaltyUnits, force: bool, t_end: f64, max_rows: usize) -> Result<SceneResult, String> {
    let start = Instant::now();
    let (mut stepper, init, beam) = build_with_units(pipe, scene, force, units).map_err(|e| format!("{}: {e}", scene.name))?;
    let cfg = RunConfig::new(scene.dt, t_end).map_err(|e| e.to_string())?;
    let steps = cfg.steps();
    let mut tip = Tip {
        dof: beam.tip_dof(),
        every: (steps / max_rows).max(1),
        gap: pipe.stops.1,
        series: Vec::new(),
        impacts: Vec::new(),
        was_active: false,
        max_excess: f64::NEG_INFINITY,
        max_excess_first: f64::NEG_INFINITY,
        energy: None,
        energy_last: None,
        work: None,
    };
    tip.energy = stepper.energy().map(|e| (e.1, e.1));
    let work0 = stepper.work().unwrap_or((0.0, 0.0));
    run(stepper.as_mut(), &init.u, &cfg, &mut [&mut tip]).map_err(|e| format!("{}: {e}", scene.name))?;
    tip.energy_last = stepper.energy().map(|e| e.1);
    tip.work = stepper.work().map(|w| (w.0 - work0.0, w.1 - work0.1));
    Ok(SceneResult { steps, tip, wall: start.elapsed().as_secs_f64() })
}

/// Runs the study.
pub fn run_beam(a: Args) -> Result<(), String> {
    let pipe = Pipe::paper();
    let scenes: Vec<BeamScene> = a
        .scenes
        .iter()
        .map(|n| BeamScene::PAPER.iter().find(|s| s.name == n.trim()).copied().ok_or_else(|| format!("--scenes: unknown scene {n:?}: allowed fig2 … fig8")))
        .collect::<Result<_, _>>()?;
    // Validate before any file is created.
    if let Some(dt) = a.penalty_dts.iter().find(|dt| !(dt.is_finite() && **dt > 0.0)) {
        return Err(format!("--penalty-dts: {dt} is not allowed: finite and > 0"));
    }
    std::fs::create_dir_all(&a.out).map_err(|e| format!("cannot create {}: {e}", a.out.display()))?;
    // Stability limits.
    let (beam, _, _) = pipe.dynamics(19).map_err(|e| e.to_string())?;
    let mut st = csv::Writer::from_writer(create(&a.out, "stability.csv")?);
    st.write_record(["J", "beta", "kappa_h", "dt_critical_s", "dt_paper_bound_s", "dt_sufficient_exact_kappa_s"]).map_err(|e| e.to_string())?;
    let mut md_stab = String::from("| β | κ_h (J = 19) | exact critical dt | paper's sufficient (3.1), exact κ_h | paper's (3.1) with its κ bound |\n|---|---|---|---|---|\n");
    for beta in [0.0, 0.1, 0.2, 0.25, 0.4, 0.5] {
        let l = stability_limit(&beam, beta).map_err(|e| e.to_string())?;
        st.write_record([19.to_string(), beta.to_string(), format!("{:.10e}", l.kappa), format!("{:.10e}", l.dt_critical), format!("{:.10e}", l.dt_paper), format!("{:.10e}", l.dt_sufficient)]).map_err(|e| e.to_string())?;
        let crit = if l.dt_critical.is_finite() { format!("{:.6e} s", l.dt_critical) } else { "∞ (unconditionally stable)".into() };
        md_stab.push_str(&format!("| {beta} | {:.6e} | {crit} | {:.6e} s | {:.6e} s |\n", l.kappa, l.dt_sufficient, l.dt_paper));
    }
    st.flush().map_err(|e| e.to_string())?;
    // Scenes.
    let mut sc = csv::Writer::from_writer(create(&a.out, "scenes.csv")?);
    let io = |e: csv::Error| e.to_string();
    sc.write_record([
        "scene", "contact", "beta", "dt_s", "steps", "impacts", "contact_episodes", "first_impacts_s", "max_abs_tip_minus_gap_m", "energy_start", "energy_end", "work_support", "work_contact", "balance_residual", "wall_s", "paper_s", "speedup",
    ])
    .map_err(io)?;
    let mut md = String::from("| scene | contact | dt (s) | contact onsets (episodes) | max \\|ũ(L,t)\\| − 0.1 (m) | ΔE − W_support − W_contact | wall (s) | paper (s) | speed-up |\n|---|---|---|---|---|---|---|---|---|\n");
    // Every penalty figure runs with the stiffness in N/m and unscaled.
    let jobs: Vec<(BeamScene, PenaltyUnits)> = scenes
        .iter()
        .flat_map(|s| match s.contact {
            BeamContact::Projection { .. } => vec![(*s, PenaltyUnits::NewtonPerMetre)],
            BeamContact::Penalty { .. } => PenaltyUnits::ALL.iter().map(|u| (*s, *u)).collect(),
        })
        .collect();
    // Largest violation per (units, stiffness, dt), for penalty.csv.
    let mut violations: Vec<Violation> = Vec::new();
    for (scene, units) in &jobs {
        let r = run_scene(&pipe, scene, *units, a.force, scene.t_end, 20_000)?;
        let name = match (scene.contact, units) {
            (BeamContact::Penalty { .. }, PenaltyUnits::Unscaled) => format!("{}-unscaled", scene.name),
            _ => scene.name.to_string(),
        };
        let (contact, beta) = match scene.contact {
            BeamContact::Projection { beta } => ("projection".to_string(), beta),
            BeamContact::Penalty { stiffness } => {
                violations.push(Violation { units: *units, stiffness, dt: scene.dt, max: r.tip.max_excess, first: r.tip.max_excess_first });
                match units {
                    PenaltyUnits::NewtonPerMetre => (format!("penalty {stiffness:e} N/m"), 0.25),
                    PenaltyUnits::Unscaled => (format!("penalty {stiffness:e} unscaled"), 0.25),
                }
            }
        };
        let (e0, e1) = (r.tip.energy.map_or(f64::NAN, |e| e.0), r.tip.energy_last.unwrap_or(f64::NAN));
        let (wf, wc) = r.tip.work.unwrap_or((f64::NAN, f64::NAN));
        let residual = (e1 - e0) - wf - wc;
        let paper = scene.paper_seconds.unwrap_or(f64::NAN);
        let first: Vec<String> = r.tip.impacts.iter().take(8).map(|t| format!("{t:.5}")).collect();
        let episodes = 1 + r.tip.impacts.windows(2).filter(|w| w[1] - w[0] > 5e-3).count();
        let episodes = if r.tip.impacts.is_empty() { 0 } else { episodes };
        sc.write_record([
            name.clone(),
            contact.clone(),
            beta.to_string(),
            format!("{:e}", scene.dt),
            r.steps.to_string(),
            r.tip.impacts.len().to_string(),
            episodes.to_string(),
            first.join(" "),
            format!("{:.6e}", r.tip.max_excess),
            format!("{e0:.10e}"),
            format!("{e1:.10e}"),
            format!("{wf:.10e}"),
            format!("{wc:.10e}"),
            format!("{residual:.3e}"),
            format!("{:.4}", r.wall),
            format!("{paper}"),
            format!("{:.0}", paper / r.wall),
        ])
        .map_err(io)?;
        md.push_str(&format!(
            "| {} | {} | {:e} | {} ({}) | {:.3e} | {:.2e} | {:.3} | {} | {:.0}× |\n",
            name,
            contact,
            scene.dt,
            r.tip.impacts.len(),
            episodes,
            r.tip.max_excess,
            residual,
            r.wall,
            paper,
            paper / r.wall
        ));
        let mut w = csv::Writer::from_writer(create(&a.out, &format!("{name}_tip.csv"))?);
        w.write_record(["t_s", "tip_m"]).map_err(io)?;
        for (t, u) in &r.tip.series {
            w.write_record([format!("{t:.9e}"), format!("{u:.10e}")]).map_err(io)?;
        }
        w.flush().map_err(|e| e.to_string())?;
        let stops: Vec<Series> = [pipe.stops.0, pipe.stops.1]
            .iter()
            .map(|g| Series { label: format!("stop {g} m"), points: vec![(0.0, *g), (scene.t_end, *g)], reference: true, style: Default::default() })
            .collect();
        let mut series = vec![Series { label: "ũ(L,t)".into(), points: r.tip.series.clone(), reference: false, style: Default::default() }];
        series.extend(stops);
        let title = format!("{name}: tip of the pipe, {contact}, β = {beta}, dt = {:e} s", scene.dt);
        let svg = line_chart(&Chart { title: &title, x_label: "t (s)", y_label: "ũ(L,t) (m)", scale: Scale::Linear, size: (1000, 450) }, &series)?;
        std::fs::write(a.out.join(format!("{name}_tip.svg")), svg).map_err(|e| e.to_string())?;
    }
    sc.flush().map_err(|e| e.to_string())?;
    let md_pen = penalty_study(&a, &pipe, &mut violations)?;
    // Self-convergence of the tip on [0, 0.2] s (β = 1/2, projection).
    let base = BeamScene { name: "self-convergence", elements: 19, dt: 4e-5, t_end: 0.2, contact: BeamContact::Projection { beta: 0.5 }, paper_seconds: None };
    let reference = run_scene(&pipe, &BeamScene { dt: base.dt / 64.0, ..base }, PenaltyUnits::NewtonPerMetre, false, 0.2, usize::MAX)?;
    let mut sv = csv::Writer::from_writer(create(&a.out, "self_convergence.csv")?);
    sv.write_record(["dt_s", "linf_tip_error_before_impact_m", "rate_before_impact", "linf_tip_error_m", "rate"]).map_err(io)?;
    let mut md_conv = String::from("| dt (s) | error on [0, 0.085] s (m) | rate | error on [0, 0.2] s (m) | rate |\n|---|---|---|---|---|\n");
    let mut last: Option<(f64, f64, f64)> = None;
    for k in 0..5 {
        let dt = base.dt / f64::powi(2.0, k);
        let r = run_scene(&pipe, &BeamScene { dt, ..base }, PenaltyUnits::NewtonPerMetre, false, 0.2, usize::MAX)?;
        // Compare at the coarse run's times (multiples of dt, which the reference also has).
        let stride = (dt / (base.dt / 64.0)).round() as usize;
        let err_until = |t_max: f64| {
            r.tip.series.iter().enumerate().filter(|(_, (t, _))| *t <= t_max).map(|(i, (_, u))| (u - reference.tip.series[i * stride].1).abs()).fold(0.0, f64::max)
        };
        let (e_pre, e_all) = (err_until(0.085), err_until(0.2 + 1e-9));
        let rate = |e0: f64, e: f64, d0: f64| (e0 / e).ln() / (d0 / dt).ln();
        let (r_pre, r_all) = last.map_or((f64::NAN, f64::NAN), |(d0, p0, a0)| (rate(p0, e_pre, d0), rate(a0, e_all, d0)));
        sv.write_record([format!("{dt:e}"), format!("{e_pre:.6e}"), format!("{r_pre:.3}"), format!("{e_all:.6e}"), format!("{r_all:.3}")]).map_err(io)?;
        md_conv.push_str(&format!("| {dt:e} | {e_pre:.3e} | {r_pre:.2} | {e_all:.3e} | {r_all:.2} |\n"));
        last = Some((dt, e_pre, e_all));
    }
    sv.flush().map_err(|e| e.to_string())?;
    println!("# Beam between stops (J = 19, T = 2 s; output in {})\n", a.out.display());
    println!("## Stability limit of the β-scheme\n\n{md_stab}");
    println!("## Scenes\n\n{md}");
    println!("## Penalty: largest violation of the stops over dt (J = 19, T = 2 s)\n\n{md_pen}");
    println!("## Self-convergence of the tip (β = 1/2, reference dt = {:e} s)\n\n{md_conv}", base.dt / 64.0);
    Ok(())
}

/// The penalty's violation of the stops in one run.
#[derive(Clone, Copy)]
struct Violation {
    units: PenaltyUnits,
    stiffness: f64,
    dt: f64,
    /// max |ũ(L, t)| − g over [0, T].
    max: f64,
    /// The same over the first contact period [0, 0.2] s.
    first: f64,
}

/// Least and largest of `v`, and the relative spread (max − min)/min.
fn spread(v: impl Iterator<Item = f64> + Clone) -> (f64, f64, f64) {
    let lo = v.clone().fold(f64::INFINITY, f64::min);
    let hi = v.fold(f64::NEG_INFINITY, f64::max);
    (lo, hi, (hi - lo) / lo)
}

/// The penalty's violation of the stops for both readings of the stiffness
/// ([`PenaltyUnits`]) at every dt of `--penalty-dts` (J = 19, T = 2 s, the
/// paper's 10⁸), reusing the figure runs in `done`; writes `penalty.csv`
/// and returns its Markdown table.
fn penalty_study(a: &Args, pipe: &Pipe, done: &mut Vec<Violation>) -> Result<String, String> {
    let stiffness = 1e8;
    let mut rows: Vec<Violation> = Vec::new();
    for units in PenaltyUnits::ALL {
        for &dt in &a.penalty_dts {
            let known = done.iter().find(|v| v.units == units && v.stiffness == stiffness && v.dt == dt).copied();
            let v = match known {
                Some(v) => v,
                None => {
                    let scene = BeamScene { name: "penalty", elements: 19, dt, t_end: 2.0, contact: BeamContact::Penalty { stiffness }, paper_seconds: None };
                    let tip = run_scene(pipe, &scene, units, false, scene.t_end, 1)?.tip;
                    let v = Violation { units, stiffness, dt, max: tip.max_excess, first: tip.max_excess_first };
                    done.push(v);
                    v
                }
            };
            rows.push(v);
        }
    }
    let io = |e: csv::Error| e.to_string();
    let mut w = csv::Writer::from_writer(create(&a.out, "penalty.csv")?);
    w.write_record([
        "units",
        "stiffness",
        "kappa_scaled_s2",
        "dt_s",
        "max_abs_tip_minus_gap_m",
        "min_over_dt_m",
        "max_over_dt_m",
        "relative_spread",
        "first_period_max_abs_tip_minus_gap_m",
        "first_period_min_over_dt_m",
        "first_period_max_over_dt_m",
        "first_period_relative_spread",
    ])
    .map_err(io)?;
    let mut md = String::from(
        "| stiffness 10⁸ read as | κ (s⁻²) | max \\|ũ(L,t)\\| − 0.1 on [0, 2] s (m), per dt | least – largest (spread) | same on [0, 0.2] s: least – largest (spread) |\n|---|---|---|---|---|\n",
    );
    for units in PenaltyUnits::ALL {
        let group: Vec<&Violation> = rows.iter().filter(|r| r.units == units).collect();
        let (lo, hi, rel) = spread(group.iter().map(|r| r.max));
        let (flo, fhi, frel) = spread(group.iter().map(|r| r.first));
        let kappa = units.kappa(stiffness, pipe.rho_s);
        for r in &group {
            w.write_record([
                units.label().to_string(),
                format!("{stiffness:e}"),
                format!("{kappa:.6e}"),
                format!("{:e}", r.dt),
                format!("{:.6e}", r.max),
                format!("{lo:.6e}"),
                format!("{hi:.6e}"),
                format!("{rel:.4e}"),
                format!("{:.6e}", r.first),
                format!("{flo:.6e}"),
                format!("{fhi:.6e}"),
                format!("{frel:.4e}"),
            ])
            .map_err(io)?;
        }
        let per_dt: Vec<String> = group.iter().map(|r| format!("{:.3e} ({:e})", r.max, r.dt)).collect();
        md.push_str(&format!(
            "| {} | {kappa:.4e} | {} | {lo:.3e} – {hi:.3e} ({:.1} %) | {flo:.4e} – {fhi:.4e} ({:.2} %) |\n",
            units.label(),
            per_dt.join(", "),
            100.0 * rel,
            100.0 * frel
        ));
    }
    w.flush().map_err(|e| e.to_string())?;
    Ok(md)
}
