//! The beam between two stops (`cargo xtask beam`) (Dumont & Paoli; docs/theory.md §8).
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

use crate::{create_dir, fd, fde, fe, ff, int, since, txt, Kind, StudyError, Table, TableOut};
use signorini_plot::{line_chart, Chart, Scale, Series};
use signorini_run::beam::{stability_limit, BeamScene, BeamSetup, BuiltBeam, PenaltyUnits, Pipe};
use signorini_run::{run as run_steps, Observer, RunConfig, RunError, Sample};
use signorini_schemes::SchemeSpec;
use std::path::PathBuf;
use std::time::Instant;

crate::options::study_config! {
    /// The beam between two stops: the paper's scenes, the exact stability
    /// limit, self-convergence, the penalty study.
    study "beam";
    pub struct Config {
        /// Scenes to run, comma-separated (fig2 … fig8, the paper's).
        pub scenes: Vec<String> = ["fig2", "fig3", "fig4", "fig5", "fig6", "fig7", "fig8"].map(String::from).to_vec(),
        /// Run conditionally stable scenes even beyond their stability limit.
        pub force: bool = false,
        /// Time steps (s) of the penalty study (`penalty.csv`),
        /// comma-separated; the paper's are 5e-6, 1e-6, 5e-7 (runs the
        /// figures already made are reused).
        pub penalty_dts: Vec<f64> = vec![5e-6, 1e-6, 5e-7],
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/beam"),
    }
}

impl Config {
    /// The scenes by name; an error names `--scenes`.
    fn scenes(&self) -> Result<Vec<BeamScene>, StudyError> {
        self.scenes
            .iter()
            .map(|n| BeamScene::PAPER.iter().find(|s| s.name == n.trim()).copied().ok_or_else(|| StudyError::config("scenes", format!("⟨scenes⟩: unknown scene {n:?}: allowed fig2 … fig8"))))
            .collect()
    }

    /// Every check done before a file is created; an error names the option.
    pub fn validate(&self) -> Result<(), StudyError> {
        self.scenes()?;
        if let Some(dt) = self.penalty_dts.iter().find(|dt| !(dt.is_finite() && **dt > 0.0)) {
            return Err(StudyError::config("penalty_dts", format!("⟨penalty_dts⟩: {dt} is not allowed: finite and > 0")));
        }
        Ok(())
    }
}

/// What the study computed and wrote ([`crate::Report`]); one table per
/// CSV written: `stability.csv`, `<scene>_tip.csv` per
/// run, `scenes.csv`, `penalty.csv`, `self_convergence.csv`.
pub type Output = crate::Report;

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

fn run_scene(pipe: &Pipe, scene: &BeamScene, units: PenaltyUnits, force: bool, t_end: f64, max_rows: usize) -> Result<SceneResult, StudyError> {
    let start = Instant::now();
    let BuiltBeam { mut stepper, initial: init, beam, .. } = BeamSetup::new(*pipe, *scene).with_units(units).forced(force).build().map_err(|e| StudyError::failed(scene.name, e))?;
    let cfg = RunConfig::new(scene.dt, t_end)?;
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
    run_steps(stepper.as_mut(), &init.u, &cfg, &mut [&mut tip]).map_err(|e| StudyError::failed(scene.name, e))?;
    tip.energy_last = stepper.energy().map(|e| e.1);
    tip.work = stepper.work().map(|w| (w.0 - work0.0, w.1 - work0.1));
    Ok(SceneResult { steps, tip, wall: start.elapsed().as_secs_f64() })
}

/// Runs the study; `progress` after every scene run.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    let start = Instant::now();
    let pipe = Pipe::paper();
    // Validate before any file is created.
    a.validate()?;
    let scenes = a.scenes()?;
    create_dir(&a.out)?;
    let mut tables = Vec::new();
    // Stability limits.
    let (beam, _, _) = pipe.dynamics(19)?;
    let (s_, f_, i_) = (Kind::S, Kind::F, Kind::I);
    let mut st = TableOut::create(&a.out, "stability.csv", &[("J", i_), ("beta", f_), ("kappa_h", f_), ("dt_critical_s", f_), ("dt_paper_bound_s", f_), ("dt_sufficient_exact_kappa_s", f_)])?;
    let mut md_stab = String::from("| β | κ_h (J = 19) | exact critical dt | paper's sufficient (3.1), exact κ_h | paper's (3.1) with its κ bound |\n|---|---|---|---|---|\n");
    for beta in [0.0, 0.1, 0.2, 0.25, 0.4, 0.5] {
        let l = stability_limit(&beam, beta)?;
        st.row(vec![int(19), fd(beta), fe(l.kappa, 10), fe(l.dt_critical, 10), fe(l.dt_paper, 10), fe(l.dt_sufficient, 10)])?;
        let crit = if l.dt_critical.is_finite() { format!("{:.6e} s", l.dt_critical) } else { "∞ (unconditionally stable)".into() };
        md_stab.push_str(&format!("| {beta} | {:.6e} | {crit} | {:.6e} s | {:.6e} s |\n", l.kappa, l.dt_sufficient, l.dt_paper));
    }
    tables.push(st.finish()?);
    // Scenes.
    let mut sc = TableOut::create(
        &a.out,
        "scenes.csv",
        &[
            ("scene", s_),
            ("contact", s_),
            ("beta", f_),
            ("dt_s", f_),
            ("steps", i_),
            ("impacts", i_),
            ("contact_episodes", i_),
            ("first_impacts_s", s_),
            ("max_abs_tip_minus_gap_m", f_),
            ("energy_start", f_),
            ("energy_end", f_),
            ("work_support", f_),
            ("work_contact", f_),
            ("balance_residual", f_),
            ("wall_s", f_),
            ("paper_s", f_),
            ("speedup", f_),
        ],
    )?;
    let mut md = String::from(
        "| scene | contact | dt (s) | contact onsets (episodes) | max \\|ũ(L,t)\\| − 0.1 (m) | ΔE − W_support − W_contact | wall (s) | paper (s) | speed-up |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    // Every penalty figure runs with the stiffness in N/m and unscaled.
    let jobs: Vec<(BeamScene, PenaltyUnits)> = scenes
        .iter()
        .flat_map(|s| match s.spring {
            None => vec![(*s, PenaltyUnits::NewtonPerMetre)],
            Some(_) => PenaltyUnits::ALL.iter().map(|u| (*s, *u)).collect(),
        })
        .collect();
    // Largest violation per (units, stiffness, dt), for penalty.csv.
    let mut violations: Vec<Violation> = Vec::new();
    let total = jobs.len() as u64;
    for (done, (scene, units)) in jobs.iter().enumerate() {
        let r = run_scene(&pipe, scene, *units, a.force, scene.t_end, 20_000)?;
        let name = match (scene.spring, units) {
            (Some(_), PenaltyUnits::Unscaled) => format!("{}-unscaled", scene.name),
            _ => scene.name.to_string(),
        };
        let spec = scene.scheme;
        // The paper's spelling: the projection is ps(0, β), the penalty a spring.
        let projection = scene.projection_beta();
        let (contact, beta) = match (scene.spring, projection) {
            (None, Some(beta)) => ("projection".to_string(), beta),
            (None, None) => (spec.to_string(), spec.param("beta").unwrap_or(f64::NAN)),
            (Some(stiffness), _) => {
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
        sc.row(vec![
            txt(name.clone()),
            txt(contact.clone()),
            fd(beta),
            fde(scene.dt),
            int(r.steps),
            int(r.tip.impacts.len()),
            int(episodes),
            txt(first.join(" ")),
            fe(r.tip.max_excess, 6),
            fe(e0, 10),
            fe(e1, 10),
            fe(wf, 10),
            fe(wc, 10),
            fe(residual, 3),
            ff(r.wall, 4),
            fd(paper),
            ff(paper / r.wall, 0),
        ])?;
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
        let mut w = TableOut::create(&a.out, &format!("{name}_tip.csv"), &[("t_s", f_), ("tip_m", f_)])?;
        for (t, u) in &r.tip.series {
            w.row(vec![fe(*t, 9), fe(*u, 10)])?;
        }
        tables.push(w.finish()?);
        let stops: Vec<Series> =
            [pipe.stops.0, pipe.stops.1].iter().map(|g| Series { label: format!("stop {g} m"), points: vec![(0.0, *g), (scene.t_end, *g)], reference: true, style: Default::default() }).collect();
        let mut series = vec![Series { label: "ũ(L,t)".into(), points: r.tip.series.clone(), reference: false, style: Default::default() }];
        series.extend(stops);
        let title = format!("{name}: tip of the pipe, {contact}, β = {beta}, dt = {:e} s", scene.dt);
        let svg = line_chart(&Chart { title: &title, x_label: "t (s)", y_label: "ũ(L,t) (m)", scale: Scale::Linear, size: (1000, 450) }, &series).map_err(StudyError::Plot)?;
        crate::write_file(&a.out.join(format!("{name}_tip.svg")), &svg)?;
        progress(done as u64 + 1, total);
    }
    tables.push(sc.finish()?);
    let (md_pen, pen_table) = penalty_study(a, &pipe, &mut violations)?;
    tables.push(pen_table);
    // Self-convergence of the tip on [0, 0.2] s (β = 1/2, projection).
    let base = BeamScene::new("self-convergence", 19, 4e-5, 0.2, SchemeSpec::ps(0.0, 0.5));
    let reference = run_scene(&pipe, &BeamScene { dt: base.dt / 64.0, ..base }, PenaltyUnits::NewtonPerMetre, false, 0.2, usize::MAX)?;
    let mut sv = TableOut::create(&a.out, "self_convergence.csv", &[("dt_s", f_), ("linf_tip_error_before_impact_m", f_), ("rate_before_impact", f_), ("linf_tip_error_m", f_), ("rate", f_)])?;
    let mut md_conv = String::from("| dt (s) | error on [0, 0.085] s (m) | rate | error on [0, 0.2] s (m) | rate |\n|---|---|---|---|---|\n");
    let mut last: Option<(f64, f64, f64)> = None;
    for k in 0..5 {
        let dt = base.dt / f64::powi(2.0, k);
        let r = run_scene(&pipe, &BeamScene { dt, ..base }, PenaltyUnits::NewtonPerMetre, false, 0.2, usize::MAX)?;
        // Compare at the coarse run's times (multiples of dt, which the reference also has).
        let stride = (dt / (base.dt / 64.0)).round() as usize;
        let err_until = |t_max: f64| r.tip.series.iter().enumerate().filter(|(_, (t, _))| *t <= t_max).map(|(i, (_, u))| (u - reference.tip.series[i * stride].1).abs()).fold(0.0, f64::max);
        let (e_pre, e_all) = (err_until(0.085), err_until(0.2 + 1e-9));
        let rate = |e0: f64, e: f64, d0: f64| (e0 / e).ln() / (d0 / dt).ln();
        let (r_pre, r_all) = last.map_or((f64::NAN, f64::NAN), |(d0, p0, a0)| (rate(p0, e_pre, d0), rate(a0, e_all, d0)));
        sv.row(vec![fde(dt), fe(e_pre, 6), ff(r_pre, 3), fe(e_all, 6), ff(r_all, 3)])?;
        md_conv.push_str(&format!("| {dt:e} | {e_pre:.3e} | {r_pre:.2} | {e_all:.3e} | {r_all:.2} |\n"));
        last = Some((dt, e_pre, e_all));
    }
    tables.push(sv.finish()?);
    let mut report = format!("# Beam between stops (J = 19, T = 2 s; output in {})\n\n", a.out.display());
    report.push_str(&format!("## Stability limit of the β-scheme\n\n{md_stab}\n"));
    report.push_str(&format!("## Scenes\n\n{md}\n"));
    report.push_str(&format!("## Penalty: largest violation of the stops over dt (J = 19, T = 2 s)\n\n{md_pen}\n"));
    report.push_str(&format!("## Self-convergence of the tip (β = 1/2, reference dt = {:e} s)\n\n{md_conv}\n", base.dt / 64.0));
    Ok(Output { tables, report, wall_s: since(start), notes: Vec::new() })
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
/// and returns its Markdown table and the table.
fn penalty_study(a: &Config, pipe: &Pipe, done: &mut Vec<Violation>) -> Result<(String, Table), StudyError> {
    let stiffness = 1e8;
    let mut rows: Vec<Violation> = Vec::new();
    for units in PenaltyUnits::ALL {
        for &dt in &a.penalty_dts {
            let known = done.iter().find(|v| v.units == units && v.stiffness == stiffness && v.dt == dt).copied();
            let v = match known {
                Some(v) => v,
                None => {
                    let scene = BeamScene::new("penalty", 19, dt, 2.0, SchemeSpec::penalty(10.0, false)).with_spring(stiffness);
                    let tip = run_scene(pipe, &scene, units, false, scene.t_end, 1)?.tip;
                    let v = Violation { units, stiffness, dt, max: tip.max_excess, first: tip.max_excess_first };
                    done.push(v);
                    v
                }
            };
            rows.push(v);
        }
    }
    let mut names = vec![("units", Kind::S)];
    names.extend(
        [
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
        ]
        .map(|n| (n, Kind::F)),
    );
    let mut w = TableOut::create(&a.out, "penalty.csv", &names)?;
    let mut md = String::from(
        "| stiffness 10⁸ read as | κ (s⁻²) | max \\|ũ(L,t)\\| − 0.1 on [0, 2] s (m), per dt | least – largest (spread) | same on [0, 0.2] s: least – largest (spread) |\n|---|---|---|---|---|\n",
    );
    for units in PenaltyUnits::ALL {
        let group: Vec<&Violation> = rows.iter().filter(|r| r.units == units).collect();
        let (lo, hi, rel) = spread(group.iter().map(|r| r.max));
        let (flo, fhi, frel) = spread(group.iter().map(|r| r.first));
        let kappa = units.kappa(stiffness, pipe.rho_s);
        for r in &group {
            w.row(vec![txt(units.label()), fde(stiffness), fe(kappa, 6), fde(r.dt), fe(r.max, 6), fe(lo, 6), fe(hi, 6), fe(rel, 4), fe(r.first, 6), fe(flo, 6), fe(fhi, 6), fe(frel, 4)])?;
        }
        let per_dt: Vec<String> = group.iter().map(|r| format!("{:.3e} ({:e})", r.max, r.dt)).collect();
        md.push_str(&format!("| {} | {kappa:.4e} | {} | {lo:.3e} – {hi:.3e} ({:.1} %) | {flo:.4e} – {fhi:.4e} ({:.2} %) |\n", units.label(), per_dt.join(", "), 100.0 * rel, 100.0 * frel));
    }
    Ok((md, w.finish()?))
}
