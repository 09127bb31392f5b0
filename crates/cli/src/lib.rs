//! # signorini-cli
//!
//! The `signorini` command: `run` a TOML scene, `list` what is available,
//! `check` a scene (validation, stability limit, cost estimate). The library
//! half holds the scene format ([`scene`]) and the run logic so that tests
//! and other tools can call them; `src/main.rs` is only argument parsing.
//!
//! Output files of `signorini run` (a contract: columns only ever added):
//! * bar: `series.csv` — `n,t,u_contact,v_contact,lambda_t,lambda,energy_t,energy`, plus
//!   `u_contact_exact,lambda_exact,energy_exact` when the scene uses a
//!   benchmark; `norms.csv` (benchmark only) — one row with the columns of the
//!   convergence study (`m,dx,dt,steps,linf_l2_u,…,l2_energy,wall_s`);
//!   `snapshots.csv` (`n,t,x,u`) when `output.snapshots_every > 0`;
//!   `u_contact.svg`, `lambda.svg`, `energy.svg` (numerical against exact).
//! * beam: `series.csv` — `n,t_s,tip_m,v_tip_m_s,lambda_t,lambda`; `tip.svg`.
//!
//! `v_contact` / `v_tip_m_s` is the backward difference of the contact dof
//! over the last step (empty at n = 0).
//!
//! Every file is flushed as the run goes (every 1024 rows) and at the end,
//! also when a run blows up, so an interrupted run leaves valid CSV up to its
//! last complete row.

#[cfg(feature = "fuzz")]
pub mod fuzz;
pub mod scene;

use scene::{BarRun, Scene, SceneFile};
use signorini_plot::{line_chart, Chart, Scale, Series};
use signorini_run::beam::{build as build_beam, stability_limit, BeamContact};
use signorini_run::study::{norm_value, LEVEL_COLUMNS, NORMS};
use signorini_run::{run, NormObserver, Observer, RunConfig, RunError, Sample, SeriesColumns, SeriesWriter};
use std::fs::File;
use std::io::LineWriter;
use std::path::Path;

/// Errors of the command.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] scene::SceneError),
    /// The run failed (blow-up, instability, …).
    #[error(transparent)]
    Run(#[from] RunError),
    /// Files.
    #[error("{0}")]
    Io(String),
}

/// Reads and validates a scene file.
pub fn load(path: &Path) -> Result<Scene, CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| CliError::Io(format!("cannot read {}: {e}", path.display())))?;
    Ok(SceneFile::parse(&text)?.validate()?)
}

/// Output files are line-buffered: the csv writer hands over chunks that
/// may end mid-record, and `LineWriter` passes on only whole lines, so a run
/// that is killed leaves a file that ends with a complete record.
fn create(dir: &Path, name: &str) -> Result<LineWriter<File>, CliError> {
    let p = dir.join(name);
    File::create(&p).map(LineWriter::new).map_err(|e| CliError::Io(format!("cannot write {}: {e}", p.display())))
}

/// A decimated copy of the contact-dof history for the plots, and the
/// largest |u_c| over every level.
struct PlotData {
    every: usize,
    dof: usize,
    points: Vec<(f64, f64, Option<(f64, f64)>, Option<(f64, f64)>)>,
    max_abs: f64,
}

impl Observer for PlotData {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let u = s.u[self.dof];
        self.max_abs = self.max_abs.max(u.abs());
        if s.n % self.every == 0 {
            self.points.push((s.t, u, s.lambda, s.energy));
        }
        Ok(())
    }
}

/// `u(x)` every k steps: `n,t,x,u`.
struct Snapshots {
    out: csv::Writer<LineWriter<File>>,
    every: usize,
    nodes: Vec<f64>,
}

impl Observer for Snapshots {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if s.n % self.every != 0 {
            return Ok(());
        }
        for (i, x) in self.nodes.iter().enumerate() {
            let u = s.u.get(i).copied().unwrap_or(0.0); // clamped end: u = 0
            self.out.write_record([s.n.to_string(), format!("{:.12e}", s.t), format!("{x:.12e}"), format!("{u:.12e}")]).map_err(|e| RunError::Output(e.to_string()))?;
        }
        self.out.flush().map_err(|e| RunError::Output(e.to_string()))
    }
}

/// A progress line on a terminal.
struct Progress {
    bar: indicatif::ProgressBar,
    every: usize,
}

impl Observer for Progress {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
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
    let target = if show { indicatif::ProgressDrawTarget::stderr() } else { indicatif::ProgressDrawTarget::hidden() };
    let bar = indicatif::ProgressBar::with_draw_target(Some(total as u64), target);
    bar.set_style(indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} steps {elapsed}").unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()));
    Progress { bar, every: (total / 200).max(1) }
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct Summary {
    /// Lines for the terminal.
    pub lines: Vec<String>,
}

fn plot(dir: &Path, name: &str, title: &str, y: &str, num: Vec<(f64, f64)>, exact: Option<Vec<(f64, f64)>>) -> Result<(), CliError> {
    let mut s = vec![Series { label: "numerical".into(), points: num, reference: false, style: Default::default() }];
    if let Some(e) = exact {
        s.push(Series { label: "exact".into(), points: e, reference: true, style: Default::default() });
    }
    let svg = line_chart(&Chart { title, x_label: "t", y_label: y, scale: Scale::Linear, size: (900, 450) }, &s).map_err(CliError::Io)?;
    std::fs::write(dir.join(name), svg).map_err(|e| CliError::Io(e.to_string()))
}

/// Runs a validated scene, writing into `out`.
pub fn run_scene(scene: &Scene, scene_file: &SceneFile, out: &Path, show_progress: bool) -> Result<Summary, CliError> {
    std::fs::create_dir_all(out).map_err(|e| CliError::Io(format!("cannot create {}: {e}", out.display())))?;
    match scene {
        Scene::Bar(b) => run_bar(b, scene_file, out, show_progress),
        Scene::Beam { pipe, scene, force } => {
            let (mut stepper, init, beam) = build_beam(pipe, scene, *force)?;
            let cfg = RunConfig::new(scene.dt, scene.t_end)?;
            let steps = cfg.steps();
            let cols = SeriesColumns { t: "t_s", u: "tip_m", v: "v_tip_m_s", energy: false, exact: None };
            let mut series = SeriesWriter::new(create(out, "series.csv")?, scene_file.output.every, beam.tip_dof(), cols)?;
            let mut data = PlotData { every: (steps / 20_000).max(1), dof: beam.tip_dof(), points: Vec::new(), max_abs: 0.0 };
            let mut prog = progress(steps, show_progress);
            let start = std::time::Instant::now();
            let res = run(stepper.as_mut(), &init.u, &cfg, &mut [&mut series, &mut data, &mut prog]);
            let wall = start.elapsed().as_secs_f64();
            if scene_file.output.plots && !data.points.is_empty() {
                let pts: Vec<(f64, f64)> = data.points.iter().map(|p| (p.0, p.1)).collect();
                plot(out, "tip.svg", "tip of the beam ũ(L,t)", "ũ(L,t) (m)", pts, None)?;
            }
            let s = res?;
            let max = data.max_abs;
            Ok(Summary { lines: vec![format!("{} steps in {wall:.3} s; {} contact steps; max |tip| = {max:.6} m (stops {:?})", s.steps, s.contact_steps, pipe.stops)] })
        }
    }
}

fn run_bar(b: &BarRun, file: &SceneFile, out: &Path, show_progress: bool) -> Result<Summary, CliError> {
    let p = &b.problem;
    let exact = match b.benchmark {
        Some(bench) => Some(bench.exact(b.t_end)?),
        None => None,
    };
    let mut stepper = b.scheme.build(p.dynamics(), b.dt, &p.initial).map_err(RunError::from)?;
    let cfg = RunConfig::new(b.dt, b.t_end)?;
    let steps = cfg.steps();
    let cols = SeriesColumns { exact: exact.as_deref(), ..SeriesColumns::default() };
    let mut series = SeriesWriter::new(create(out, "series.csv")?, file.output.every, 0, cols)?;
    let mut data = PlotData { every: (steps / 20_000).max(1), dof: 0, points: Vec::new(), max_abs: 0.0 };
    let mut norms = exact.as_deref().map(|e| NormObserver::new(e, p.bar.elements, p.vnorm(), b.dt));
    let mut snaps = if file.output.snapshots_every > 0 {
        let mut w = csv::Writer::from_writer(create(out, "snapshots.csv")?);
        w.write_record(["n", "t", "x", "u"]).map_err(|e| CliError::Io(e.to_string()))?;
        Some(Snapshots { out: w, every: file.output.snapshots_every, nodes: (0..=p.bar.elements).map(|i| p.bar.node(i)).collect() })
    } else {
        None
    };
    let mut prog = progress(steps, show_progress);
    let start = std::time::Instant::now();
    let res = {
        let mut obs: Vec<&mut dyn Observer> = vec![&mut series, &mut data, &mut prog];
        if let Some(n) = norms.as_mut() {
            obs.push(n);
        }
        if let Some(s) = snaps.as_mut() {
            obs.push(s);
        }
        run(stepper.as_mut(), &p.initial.u, &cfg, &mut obs)
    };
    let wall = start.elapsed().as_secs_f64();
    if file.output.plots && !data.points.is_empty() {
        let t_max = data.points.last().map_or(0.0, |p| p.0);
        let grid = |f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> { (0..=2000).map(|i| t_max * i as f64 / 2000.0).map(|t| (t, f(t))).collect() };
        let ex = exact.as_deref();
        plot(out, "u_contact.svg", "u(0,t)", "u(0,t)", data.points.iter().map(|p| (p.0, p.1)).collect(), ex.map(|e| grid(&|t| e.fields(0.0, t).u)))?;
        plot(out, "lambda.svg", "contact force λ(t)", "λ", data.points.iter().filter_map(|p| p.2).collect(), ex.map(|e| grid(&|t| e.lambda(t))))?;
        plot(out, "energy.svg", "discrete energy", "E", data.points.iter().filter_map(|p| p.3).collect(), ex.map(|e| grid(&|_| e.energy())))?;
    }
    let s = res?;
    let mut lines = vec![format!("{} ({} elements, mass {}, scheme {}, dt = {:e}): {} steps in {wall:.3} s, {} contact steps", file.bar.as_ref().and_then(|b| b.benchmark.clone()).unwrap_or_else(|| "bar".into()), p.bar.elements, p.mass, b.scheme, b.dt, s.steps, s.contact_steps)];
    if let Some(n) = norms {
        let r = n.report();
        let mut w = csv::Writer::from_writer(create(out, "norms.csv")?);
        w.write_record(LEVEL_COLUMNS).map_err(|e| CliError::Io(e.to_string()))?;
        let mut rec = vec![p.bar.elements.to_string(), format!("{:.10e}", p.bar.h()), format!("{:.10e}", b.dt), s.steps.to_string()];
        rec.extend(NORMS.iter().map(|k| format!("{:.10e}", norm_value(&r, k))));
        rec.push(format!("{wall:.6}"));
        w.write_record(&rec).map_err(|e| CliError::Io(e.to_string()))?;
        w.flush().map_err(|e| CliError::Io(e.to_string()))?;
        lines.push(format!("errors: L∞(L²) {:.4e}, L²(L²) {:.4e}, L∞(V) {:.4e}, L²(λ) {:.4e}, L∞(E) {:.4e}; λ TV ratio {:.2}", r.linf_l2_u, r.l2_l2_u, r.linf_v_u, r.l2_lambda, r.linf_energy, r.lambda_tv_ratio));
    }
    lines.push(format!("wrote {}", out.display()));
    Ok(Summary { lines })
}

/// `signorini check`: what a run would do, its stability and cost.
pub fn check(scene: &Scene) -> Result<String, CliError> {
    Ok(match scene {
        Scene::Bar(b) => {
            let steps = RunConfig::new(b.dt, b.t_end)?.steps();
            let dofs = b.problem.bar.dofs();
            let stability = match b.scheme.cfl_limit(&b.problem.dynamics()).map_err(RunError::from)? {
                None => "unconditionally stable".to_string(),
                Some(limit) => format!(
                    "conditionally stable: exact limit dt < {limit:.6e} ({}); dt = {:e} is {}",
                    b.scheme.stability_rule().unwrap_or(""),
                    b.dt,
                    if b.dt < limit { "below it" } else { "BEYOND it: the run will be refused" }
                ),
            };
            format!(
                "valid bar scene: {} elements ({} unknowns), mass {}, scheme {}, dt = {:e}, T = {}: {} steps, {:.3e} dof-steps\n\
                 stability: {stability}\n\
                 cost estimate: {:.2} s stepping with all norms (10 ns per dof-step, measured on 2 cores)",
                b.problem.bar.elements, dofs, b.problem.mass, b.scheme, b.dt, b.t_end, steps, (dofs * steps) as f64, 1e-8 * (dofs * steps) as f64
            )
        }
        Scene::Beam { pipe, scene, force } => {
            let (_, _, beam_) = pipe.dynamics(scene.elements).map(|(b, d, i)| (d, i, b))?;
            let steps = RunConfig::new(scene.dt, scene.t_end)?.steps();
            let beta = match scene.contact {
                BeamContact::Projection { beta } => beta,
                BeamContact::Penalty { .. } => 0.25,
            };
            let lim = stability_limit(&beam_, beta)?;
            let stab = match scene.contact {
                BeamContact::Projection { beta } if beta < 0.25 => format!(
                    "conditionally stable (β = {beta} < 1/4): κ_h = {:.6e}, exact critical dt = 2/sqrt((1-4β) κ_h) = {:.6e} s (the paper's sufficient condition (3.1) gives {:.6e} s; with its κ bound {:.6e} s); dt = {:e} is {}",
                    lim.kappa,
                    lim.dt_critical,
                    lim.dt_sufficient,
                    lim.dt_paper,
                    scene.dt,
                    if scene.dt < lim.dt_critical { "below it" } else if *force { "BEYOND it (forced)" } else { "BEYOND it: the run will be refused" }
                ),
                BeamContact::Projection { beta } => format!(
                    "unconditionally stable (β = {beta} >= 1/4); κ_h = {:.6e} (the paper's sufficient condition (3.1) would ask dt < {:.6e} s: not a limit)",
                    lim.kappa, lim.dt_sufficient
                ),
                BeamContact::Penalty { .. } => format!("Newmark β = 1/4 with a penalty spring: unconditionally stable; κ_h = {:.6e}", lim.kappa),
            };
            format!(
                "valid beam scene: J = {} ({} unknowns), dt = {:e} s, T = {} s: {} steps\nstability: {stab}\ncost estimate: {:.2} s (0.42 µs per step at J = 19, measured)",
                scene.elements,
                beam_.dofs(),
                scene.dt,
                scene.t_end,
                steps,
                4.2e-7 * steps as f64 * (scene.elements as f64 / 19.0)
            )
        }
    })
}

/// `signorini list`.
pub fn list() -> String {
    use signorini_schemes::SchemeSpec;
    let mut s = String::from("schemes (bar):\n");
    for (name, spec) in SchemeSpec::named() {
        let note = if spec.needs_massless_node() {
            "  [massless-node masses only]"
        } else if spec.needs_massive_node() {
            "  [std or lumped only]"
        } else {
            ""
        };
        s.push_str(&format!("  {name:<16} {spec:?}{note}\n"));
    }
    s.push_str("  newmark(BETA,GAMMA)  β ∈ (0, 1/2], γ ∈ [1/2, 2β]\n  theta(THETA)         θ ∈ [1/2, 1]\n  ps(E) / ps(E,BETA)   e ∈ [0, 1], β ∈ [0, 1/2] (default 1/4; β = 0 needs a massive contact node)\n  penalty(G) / penalty-cd(G)   γ_P > 0 (penalty-cd: explicit, CFL-checked)\n  moreau-jean(THETA,E)         θ ∈ [1/2, 1], e ∈ [0, 1]\n  nitsche(GAMMA0,THETA)        γ_0 > 0, θ ∈ [-1, 1]\n");
    s.push_str("masses (bar): std, lumped (massive contact node); mod = mod1, mod2, mod3, transfer, singular (massless contact node)\n");
    s.push_str("benchmarks (bar, with exact solutions): bar-dirichlet, bar-neumann-gravity (g = 1/9), bar-neumann-gravity-0.11 (T <= 225)\n");
    s.push_str("beam scenes: fig2 fig3 fig4 (β = 1/2, projection), fig5 fig6 fig7 (penalty 1e8 N/m), fig8 (β = 1/4); contact = \"projection\" (β ∈ [0, 1/2]) or \"penalty\" (stiffness > 0 N/m)\n");
    s
}
