//! `cargo xtask beam`: the beam between two stops (Dumont & Paoli; docs/theory.md §8).
//!
//! Outputs (folder `out/beam/` by default):
//! * `<scene>_tip.csv` (`t_s,tip_m`: the physical tip displacement ũ(L,t),
//!   decimated to at most 20 000 rows) and `<scene>_tip.svg`;
//! * `scenes.csv`: `scene,contact,beta,dt_s,steps,impacts,contact_episodes,first_impacts_s,max_abs_tip_minus_gap_m,energy_start,energy_end,work_support,work_contact,balance_residual,wall_s,paper_s,speedup`;
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
use signorini_run::beam::{build, stability_limit, BeamContact, BeamScene, Pipe};
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
}

/// Watches the tip: decimated trajectory, impacts, extreme, energies, work.
struct Tip {
    dof: usize,
    every: usize,
    gap: f64,
    series: Vec<(f64, f64)>,
    impacts: Vec<f64>,
    was_active: bool,
    max_excess: f64,
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
        Ok(())
    }
}

struct SceneResult {
    steps: usize,
    tip: Tip,
    wall: f64,
}

fn run_scene(pipe: &Pipe, scene: &BeamScene, force: bool, t_end: f64, max_rows: usize) -> Result<SceneResult, String> {
    let start = Instant::now();
    let (mut stepper, init, beam) = build(pipe, scene, force).map_err(|e| format!("{}: {e}", scene.name))?;
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
    std::fs::create_dir_all(&a.out).map_err(|e| format!("cannot create {}: {e}", a.out.display()))?;
    let pipe = Pipe::paper();
    let scenes: Vec<BeamScene> = a
        .scenes
        .iter()
        .map(|n| BeamScene::PAPER.iter().find(|s| s.name == n.trim()).copied().ok_or_else(|| format!("--scenes: unknown scene {n:?}: allowed fig2 … fig8")))
        .collect::<Result<_, _>>()?;
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
    for scene in &scenes {
        let r = run_scene(&pipe, scene, a.force, scene.t_end, 20_000)?;
        let (contact, beta) = match scene.contact {
            BeamContact::Projection { beta } => ("projection".to_string(), beta),
            BeamContact::Penalty { stiffness } => (format!("penalty {stiffness:e} N/m"), 0.25),
        };
        let (e0, e1) = (r.tip.energy.map_or(f64::NAN, |e| e.0), r.tip.energy_last.unwrap_or(f64::NAN));
        let (wf, wc) = r.tip.work.unwrap_or((f64::NAN, f64::NAN));
        let residual = (e1 - e0) - wf - wc;
        let paper = scene.paper_seconds.unwrap_or(f64::NAN);
        let first: Vec<String> = r.tip.impacts.iter().take(8).map(|t| format!("{t:.5}")).collect();
        let episodes = 1 + r.tip.impacts.windows(2).filter(|w| w[1] - w[0] > 5e-3).count();
        let episodes = if r.tip.impacts.is_empty() { 0 } else { episodes };
        sc.write_record([
            scene.name.to_string(),
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
            scene.name,
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
        let mut w = csv::Writer::from_writer(create(&a.out, &format!("{}_tip.csv", scene.name))?);
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
        let title = format!("{}: tip of the pipe, {contact}, β = {beta}, dt = {:e} s", scene.name, scene.dt);
        let svg = line_chart(&Chart { title: &title, x_label: "t (s)", y_label: "ũ(L,t) (m)", scale: Scale::Linear, size: (1000, 450) }, &series)?;
        std::fs::write(a.out.join(format!("{}_tip.svg", scene.name)), svg).map_err(|e| e.to_string())?;
    }
    sc.flush().map_err(|e| e.to_string())?;
    // Self-convergence of the tip on [0, 0.2] s (β = 1/2, projection).
    let base = BeamScene { name: "self-convergence", elements: 19, dt: 4e-5, t_end: 0.2, contact: BeamContact::Projection { beta: 0.5 }, paper_seconds: None };
    let reference = run_scene(&pipe, &BeamScene { dt: base.dt / 64.0, ..base }, false, 0.2, usize::MAX)?;
    let mut sv = csv::Writer::from_writer(create(&a.out, "self_convergence.csv")?);
    sv.write_record(["dt_s", "linf_tip_error_before_impact_m", "rate_before_impact", "linf_tip_error_m", "rate"]).map_err(io)?;
    let mut md_conv = String::from("| dt (s) | error on [0, 0.085] s (m) | rate | error on [0, 0.2] s (m) | rate |\n|---|---|---|---|---|\n");
    let mut last: Option<(f64, f64, f64)> = None;
    for k in 0..5 {
        let dt = base.dt / f64::powi(2.0, k);
        let r = run_scene(&pipe, &BeamScene { dt, ..base }, false, 0.2, usize::MAX)?;
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
    println!("## Self-convergence of the tip (β = 1/2, reference dt = {:e} s)\n\n{md_conv}", base.dt / 64.0);
    Ok(())
}
