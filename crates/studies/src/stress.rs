//! The stability stress study (`cargo xtask stress`): long runs at extreme dx/dt with random initial data,
//! per (scheme, mass): energy drift and growth, first non-finite value. A
//! run that blows up is reported, not crashed.
//!
//! Outputs (`out/stress/`): `stress.csv` with columns
//! `scheme,mass,ratio,steps,seed,status,stop_step,max_rel_drift,max_growth,wall_s`
//! (`status`: `ok`, `blow-up` (non-finite state), `energy-growth`
//! (> 10⁶ E₀) or `refused-cfl` (an explicit scheme asked for dt beyond its
//! exact CFL limit; `stop_step` then holds the limit)); `stress.svg`, a heat
//! map of the largest relative energy drift per (scheme × mass, dx/dt),
//! black where a run blew up, grey where it was refused.

use crate::{create_dir, fd, fe, ff, int, since, txt, Cell, Kind, StudyError, TableOut};
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_plot::heat_map;
use signorini_run::{run as run_steps, BarProblem, Observer, RunConfig, RunError, Sample};
use signorini_schemes::SchemeSpec;
use std::path::PathBuf;

crate::options::study_config! {
    /// Stability stress: long runs at extreme dx/dt with random initial data;
    /// energy drift and blow-ups.
    study "stress";
    pub struct Config {
        /// Steps per run.
        pub steps: usize = 100_000,
        /// Elements.
        pub elements: usize = 40,
        /// Random seed; run `k` of a (scheme, mass) row uses
        /// `seed · 1000 + k` (wrapping), written as an `I64` (wrapping too).
        pub seed: u64 = 1,
        /// Output folder.
        pub out: PathBuf = PathBuf::from("out/stress"),
        /// Schemes, comma-separated (default: every named scheme of
        /// `signorini list`, by name); a family without presets by its call
        /// (`contact-stabilized`, `nsga(0.5)`). Each runs with every mass
        /// it accepts.
        #[serde(deserialize_with = "crate::options::with::some_schemes")]
        pub schemes: Option<Vec<SchemeSpec>> = None,
    }
}

impl Config {
    /// Every check done before a file is created; an error names the option.
    pub fn validate(&self) -> Result<(), StudyError> {
        if !(1..=1_000_000_000).contains(&self.steps) {
            return Err(StudyError::config("steps", format!("⟨steps⟩ {}: allowed 1 ..= 1e9", self.steps)));
        }
        if !(2..=signorini_fem::MAX_ELEMENTS).contains(&self.elements) {
            return Err(StudyError::config("elements", format!("⟨elements⟩ {}: allowed an integer >= 2", self.elements)));
        }
        crate::time_stepping_schemes("schemes", self.schemes.as_deref())?;
        crate::fits_memory("elements", self.elements, 1)
    }
}

/// What the study computed and wrote ([`crate::Report`]); its tables: `stress.csv`.
pub type Output = crate::Report;

/// The dx/dt of every run of a (scheme, mass) row.
pub const RATIOS: [f64; 7] = [0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0];

/// A small deterministic generator (splitmix64), enough for initial data.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[derive(Default)]
struct Energy {
    first: Option<f64>,
    max_drift: f64,
    max_growth: f64,
}

impl Observer for Energy {
    fn wants_energy(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if let Some((_, e)) = s.energy {
            // Reference: the first energy after the first step (a massless
            // node's equilibration is not drift).
            if s.n >= 1 {
                let e0 = *self.first.get_or_insert(e);
                self.max_drift = self.max_drift.max(((e - e0) / e0).abs());
                self.max_growth = self.max_growth.max(e / e0);
            }
        }
        Ok(())
    }
}

/// Runs the study; `progress` after every run (refused ones included).
pub fn run(a: &Config, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Output, StudyError> {
    // Everything is checked before a file is created.
    a.validate()?;
    let start = std::time::Instant::now();
    create_dir(&a.out)?;
    let ratios = RATIOS;
    // Every mass treatment (mod1 is mod under another name).
    let masses: Vec<BarMass> = BarMass::ALL.into_iter().filter(|m| *m != BarMass::Mod1).collect();
    let schemes = crate::time_stepping_schemes("schemes", a.schemes.as_deref())?;
    let total = (schemes.iter().map(|(_, s)| masses.iter().filter(|&&m| crate::takes_mass(s, m)).count()).sum::<usize>() * ratios.len()) as u64;
    let mut done = 0u64;
    let (s_, f_, i_) = (Kind::S, Kind::F, Kind::I);
    let mut w = TableOut::create(
        &a.out,
        "stress.csv",
        &[("scheme", s_), ("mass", s_), ("ratio", f_), ("steps", i_), ("seed", i_), ("status", s_), ("stop_step", s_), ("max_rel_drift", f_), ("max_growth", f_), ("wall_s", f_)],
    )?;
    let (mut rows, mut grid) = (Vec::new(), Vec::new());
    let mut md = String::from("| scheme | mass | worst relative energy change, dx/dt = 0.1 … 100 | largest E/E₀ | blow-ups | refused (CFL) |\n|---|---|---|---|---|---|\n");
    for (name, scheme) in &schemes {
        let name = name.as_str();
        for &mass in &masses {
            if !crate::takes_mass(scheme, mass) {
                continue;
            }
            let mut line = Vec::new();
            let (mut worst, mut blowups, mut growth, mut refused) = (0.0f64, 0, 0.0f64, 0);
            for (ri, ratio) in ratios.iter().enumerate() {
                let seed = a.seed.wrapping_mul(1000).wrapping_add(ri as u64);
                let mut rng = Rng(seed);
                let amps: Vec<f64> = (0..6).map(|_| rng.next() - 0.5).collect();
                let vamps: Vec<f64> = (0..6).map(|_| rng.next() - 0.5).collect();
                let u0 = |x: f64| 0.3 + 0.2 * x + amps.iter().enumerate().map(|(k, a)| 0.1 * a * ((k + 1) as f64 * std::f64::consts::PI * x).sin()).sum::<f64>();
                let v0 = |x: f64| -0.5 + vamps.iter().enumerate().map(|(k, a)| a * ((k + 1) as f64 * std::f64::consts::PI * x).sin()).sum::<f64>();
                let bar = Bar::new(1.0, a.elements, 1.0, RightEnd::Free).map_err(|e| StudyError::failed("", e))?;
                let p = BarProblem::new(bar, mass, 0.0, 0.0, u0, v0)?;
                done += 1;
                let dt = bar.h() / ratio;
                let mut s = match scheme.build(p.dynamics(), dt, &p.initial) {
                    Ok(s) => s,
                    // An explicit scheme beyond its CFL limit is refused up
                    // front: reported, like a blow-up would be.
                    Err(signorini_schemes::SchemeError::Unstable { limit, .. }) => {
                        w.row(vec![
                            txt(name),
                            txt(mass.to_string()),
                            fd(*ratio),
                            int(a.steps),
                            Cell::I(seed as i64),
                            txt("refused-cfl"),
                            txt(format!("limit {limit:.3e}")),
                            Cell::E,
                            Cell::E,
                            Cell::F(0.0, "0".into()),
                        ])?;
                        progress(done, total);
                        line.push(f64::NAN);
                        refused += 1;
                        continue;
                    }
                    Err(e) => return Err(StudyError::failed(format!("{name}/{mass} ratio {ratio}"), e)),
                };
                let mut en = Energy::default();
                let start = std::time::Instant::now();
                let res = run_steps(s.as_mut(), &p.initial.u, &RunConfig::new(dt, dt * a.steps as f64)?, &mut [&mut en]);
                let wall = start.elapsed().as_secs_f64();
                let (status, stop) = match res {
                    Ok(_) => ("ok", String::new()),
                    Err(RunError::BlowUp { step, .. }) => ("blow-up", step.to_string()),
                    Err(RunError::EnergyGrowth { step, .. }) => ("energy-growth", step.to_string()),
                    Err(e) => return Err(StudyError::failed(format!("{name}/{mass} ratio {ratio}"), e)),
                };
                let cell = if status == "ok" { en.max_drift } else { f64::INFINITY };
                if status != "ok" {
                    blowups += 1;
                }
                worst = worst.max(cell);
                growth = growth.max(en.max_growth);
                line.push(cell);
                w.row(vec![txt(name), txt(mass.to_string()), fd(*ratio), int(a.steps), Cell::I(seed as i64), txt(status), txt(stop), fe(en.max_drift, 3), ff(en.max_growth, 6), ff(wall, 3)])?;
                w.flush()?;
                progress(done, total);
            }
            md.push_str(&format!("| {name} | {mass} | {worst:.2e} | {growth:.3} | {blowups} | {refused} |\n"));
            rows.push(format!("{name} {mass}"));
            grid.push(line);
        }
    }
    let cols: Vec<String> = ratios.iter().map(|r| format!("dx/dt={r}")).collect();
    let table = w.finish()?;
    let svg = heat_map(
        &format!("max relative energy drift over {} steps (log10, blue low, red high; black: blow-up; grey: refused, beyond the CFL limit)", a.steps),
        &rows,
        &cols,
        &grid,
        true,
        (900, 40 + 28 * rows.len() as u32),
    )
    .map_err(StudyError::Plot)?;
    crate::write_file(&a.out.join("stress.svg"), &svg)?;
    let report = format!("# Stress: {} steps per run, {} elements, free bar thrown at the obstacle with random data\n\n{md}\n", a.steps, a.elements);
    Ok(Output { tables: vec![table], report, wall_s: since(start), notes: Vec::new() })
}
