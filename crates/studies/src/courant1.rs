//! The Courant-number-one study (`cargo xtask courant1`): is the central
//! difference with the lumped P1 mass at `dx/dt = c` — nodally exact for
//! the free wave equation — still exact with the contact projection?
//!
//! For each benchmark and level `m`, the central difference (β = 0,
//! restitution 0, lumped mass, `dt = h/c`) runs with two starts: Taylor's
//! (`U¹ = U⁰ + dt V⁰ + dt²/2 M⁻¹(F − K U⁰)`,
//! [`PaoliSchatzman::central_difference_taylor`]) and the Newmark(1/4, 1/2)
//! step of `taylor-flanagan`. At every time level the nodal error
//! `max_i |U_i^n − u(x_i, t_n)|` is taken against the exact solution; the
//! table says where it first exceeds `1e-10` (round-off stays below), and when the exact contact
//! force first switches off on the grid (the first release).
//!
//! Outputs (`out/courant1/`): `courant1.csv` with columns
//! `benchmark,m,start,dt,first_error_t,first_error_x,first_error,exact_release_t,max_nodal_error,linf_l2_u`
//! (`first_error_*` empty when the run is exact to 1e-10 throughout).

use crate::{create_dir, fd, fe, int, since, txt, Cell, Kind, StudyError, TableOut};
use signorini_exact::ExactSolution;
use signorini_fem::BarMass;
use signorini_run::{run as run_steps, Benchmark, NormObserver, Observer, RunConfig, RunError, Sample};
use signorini_schemes::{PaoliSchatzman, SchemeSpec, Stepper};
use std::path::PathBuf;

crate::options::study_config! {
    /// Courant number one: the lumped central difference at dx/dt = c with
    /// Taylor's and Newmark's starts, node by node against the exact solutions;
    /// where the first nodal error appears.
    study "courant1";
    pub struct Config {
        /// Benchmarks, comma-separated (default: all four).
        #[serde(deserialize_with = "de_benchmarks")]
        pub benchmarks: Vec<Benchmark> = Benchmark::ALL.to_vec(),
        /// Numbers of elements m, comma-separated.
        pub levels: Vec<usize> = vec![10, 20, 40, 80],
        /// Horizon (default: 6 for the Dirichlet and mirrored bars, two
        /// periods, and 16 for the falling bars).
        pub t_end: Option<f64> = None,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/courant1"),
    }
}

fn de_benchmarks<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<Benchmark>, D::Error> {
    crate::options::with::list(d, |v| v.iter().map(|b| crate::convergence::parse_benchmark(b.trim())).collect())
}

impl Config {
    /// Every check, before anything runs.
    pub fn validate(&self) -> Result<(), StudyError> {
        if self.benchmarks.is_empty() {
            return Err(StudyError::config("benchmarks", "⟨benchmarks⟩: allowed one or more of bar-dirichlet, bar-mirrored, bar-neumann-gravity, bar-neumann-gravity-0.11"));
        }
        if self.levels.is_empty() || self.levels.iter().any(|&m| !(2..=100_000).contains(&m)) {
            return Err(StudyError::config("levels", format!("⟨levels⟩ {:?}: allowed one or more integers in [2, 100000]", self.levels)));
        }
        if let Some(t) = self.t_end {
            if !(t > 0.0 && t.is_finite() && t <= 1e4) {
                return Err(StudyError::config("t_end", format!("⟨t_end⟩ {t}: allowed finite, > 0 and <= 1e4")));
            }
        }
        Ok(())
    }

    fn horizon(&self, b: Benchmark) -> f64 {
        self.t_end.unwrap_or(match b {
            Benchmark::BarDirichlet | Benchmark::BarMirrored => 6.0,
            _ => 16.0,
        })
    }
}

/// What the study computed and wrote ([`crate::Report`]); its tables: `courant1.csv`.
pub type Output = crate::Report;

/// The nodal error at every level against the exact solution.
struct NodalError<'a> {
    exact: &'a dyn ExactSolution,
    x: Vec<f64>,
    /// `(t, x, error)` of the first level with an error above 1e-10.
    first: Option<(f64, f64, f64)>,
    max: f64,
}

impl Observer for NodalError<'_> {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        for (&x, &u) in self.x.iter().zip(s.u) {
            let e = (u - self.exact.fields(x, s.t).u).abs();
            self.max = self.max.max(e);
            if e > 1e-10 && self.first.is_none() {
                self.first = Some((s.t, x, e));
            }
        }
        Ok(())
    }
}

/// One run: the central difference with the lumped mass at `dt = h/c`.
fn one(b: Benchmark, exact: &dyn ExactSolution, m: usize, taylor: bool, t_end: f64) -> Result<(f64, NodalError<'_>, f64), StudyError> {
    let p = b.problem(exact, m, BarMass::Lumped)?;
    let dt = p.bar.h() / p.bar.wave_speed;
    let label = if taylor { "cd-taylor" } else { "taylor-flanagan" };
    let mut stepper: Box<dyn Stepper> = if taylor {
        Box::new(PaoliSchatzman::central_difference_taylor(label.into(), p.dynamics(), 0.0, dt, &p.initial).map_err(RunError::from)?)
    } else {
        let spec: SchemeSpec = "taylor-flanagan".parse().map_err(|e| StudyError::failed("", e))?;
        spec.build(p.dynamics(), dt, &p.initial).map_err(RunError::from)?
    };
    let cfg = RunConfig::new(dt, t_end)?;
    let mut nodal = NodalError { exact, x: (0..p.bar.dofs()).map(|i| p.bar.node(i)).collect(), first: None, max: 0.0 };
    let mut norms = NormObserver::new(exact, p.bar.elements, p.vnorm(), dt);
    run_steps(stepper.as_mut(), &p.initial.u, &cfg, &mut [&mut nodal, &mut norms])?;
    Ok((dt, nodal, norms.report().linf_l2_u))
}

/// The first time level at which the exact contact force has just switched
/// off (nonzero at `t_{n-1}`, zero at `t_n`), if any before `t_end`.
fn exact_release(exact: &dyn ExactSolution, dt: f64, t_end: f64) -> Option<f64> {
    let steps = (t_end / dt).round() as usize;
    (1..=steps).map(|n| (exact.lambda((n - 1) as f64 * dt), n as f64 * dt, exact.lambda(n as f64 * dt))).find(|(a, _, b)| *a != 0.0 && *b == 0.0).map(|(_, t, _)| t)
}

/// Runs the study.
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    a.validate()?;
    let start = std::time::Instant::now();
    create_dir(&a.out)?;
    let mut w = TableOut::create(
        &a.out,
        "courant1.csv",
        &[
            ("benchmark", Kind::S),
            ("m", Kind::I),
            ("start", Kind::S),
            ("dt", Kind::F),
            ("first_error_t", Kind::F),
            ("first_error_x", Kind::F),
            ("first_error", Kind::F),
            ("exact_release_t", Kind::F),
            ("max_nodal_error", Kind::F),
            ("linf_l2_u", Kind::F),
        ],
    )?;
    let total = (a.benchmarks.len() * a.levels.len() * 2) as u64;
    let mut done = 0;
    let mut md = String::from("| benchmark | m | start | first nodal error > 1e-10 at t | x | size | exact release on the grid | max nodal error | L∞(L²) |\n|---|---|---|---|---|---|---|---|---|\n");
    for &b in &a.benchmarks {
        let t_end = a.horizon(b);
        let exact = b.exact(t_end)?;
        for &m in &a.levels {
            for taylor in [true, false] {
                let (dt, nodal, linf) = one(b, exact.as_ref(), m, taylor, t_end)?;
                let release = exact_release(exact.as_ref(), dt, t_end);
                let start_name = if taylor { "taylor" } else { "newmark" };
                let (ft, fx, fe_) = nodal.first.map_or((Cell::E, Cell::E, Cell::E), |(t, x, e)| (fd(t), fd(x), fe(e, 4)));
                w.row(vec![txt(b.name()), int(m), txt(start_name), fd(dt), ft, fx, fe_, release.map_or(Cell::E, fd), fe(nodal.max, 4), fe(linf, 4)])?;
                let first = nodal.first.map_or("exact throughout".to_string(), |(t, x, e)| format!("{t:.4} | {x:.4} | {e:.3e}"));
                let first = if nodal.first.is_none() { format!("{first} | | ") } else { first };
                md.push_str(&format!("| {b} | {m} | {start_name} | {first} | {} | {:.3e} | {linf:.3e} |\n", release.map_or("none".into(), |t| format!("{t:.4}")), nodal.max));
                done += 1;
                progress(done, total);
            }
        }
    }
    let table = w.finish()?;
    let report = format!("# Courant number one: the central difference with the lumped mass at dx/dt = c (output in {})\n\n{md}", a.out.display());
    Ok(crate::Report { tables: vec![table], report, wall_s: since(start), notes: Vec::new() })
}
