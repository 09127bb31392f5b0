//! `cargo xtask stress`: long runs at extreme dx/dt with random initial data,
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

use crate::create;
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_plot::heat_map;
use signorini_run::{run, BarProblem, Observer, RunConfig, RunError, Sample};
use signorini_schemes::SchemeSpec;
use std::path::PathBuf;

/// Arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/stress")]
    out: PathBuf,
    /// Steps per run.
    #[arg(long, default_value_t = 100_000)]
    steps: usize,
    /// Elements.
    #[arg(long, default_value_t = 40)]
    elements: usize,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

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

/// Runs the study.
pub fn run_stress(a: Args) -> Result<(), String> {
    // Everything is checked before a file is created.
    if !(1..=1_000_000_000).contains(&a.steps) {
        return Err(format!("--steps {}: allowed 1 ..= 1e9", a.steps));
    }
    if !(2..=signorini_fem::MAX_ELEMENTS).contains(&a.elements) {
        return Err(format!("--elements {}: allowed an integer >= 2", a.elements));
    }
    crate::fits_memory("--elements", a.elements, 1)?;
    std::fs::create_dir_all(&a.out).map_err(|e| e.to_string())?;
    let ratios = [0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0];
    // Every mass treatment (mod1 is mod under another name).
    let masses: Vec<BarMass> = BarMass::ALL.into_iter().filter(|m| *m != BarMass::Mod1).collect();
    let mut w = csv::Writer::from_writer(create(&a.out, "stress.csv")?);
    w.write_record(["scheme", "mass", "ratio", "steps", "seed", "status", "stop_step", "max_rel_drift", "max_growth", "wall_s"]).map_err(|e| e.to_string())?;
    let (mut rows, mut grid) = (Vec::new(), Vec::new());
    let mut md = String::from("| scheme | mass | worst relative energy change, dx/dt = 0.1 … 100 | largest E/E₀ | blow-ups | refused (CFL) |\n|---|---|---|---|---|---|\n");
    for (name, scheme) in SchemeSpec::named() {
        for &mass in &masses {
            if !scheme.accepts_massless_node(mass.massless_contact_node()) {
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
                let bar = Bar::new(1.0, a.elements, 1.0, RightEnd::Free).map_err(|e| e.to_string())?;
                let p = BarProblem::new(bar, mass, 0.0, 0.0, u0, v0).map_err(|e| e.to_string())?;
                let dt = bar.h() / ratio;
                let mut s = match scheme.build(p.dynamics(), dt, &p.initial) {
                    Ok(s) => s,
                    // An explicit scheme beyond its CFL limit is refused up
                    // front: reported, like a blow-up would be.
                    Err(signorini_schemes::SchemeError::Unstable { limit, .. }) => {
                        w.write_record([name.to_string(), mass.to_string(), ratio.to_string(), a.steps.to_string(), seed.to_string(), "refused-cfl".to_string(), format!("limit {limit:.3e}"), String::new(), String::new(), "0".to_string()])
                            .map_err(|e| e.to_string())?;
                        line.push(f64::NAN);
                        refused += 1;
                        continue;
                    }
                    Err(e) => return Err(format!("{name}/{mass} ratio {ratio}: {e}")),
                };
                let mut en = Energy::default();
                let start = std::time::Instant::now();
                let res = run(s.as_mut(), &p.initial.u, &RunConfig::new(dt, dt * a.steps as f64).map_err(|e| e.to_string())?, &mut [&mut en]);
                let wall = start.elapsed().as_secs_f64();
                let (status, stop) = match res {
                    Ok(_) => ("ok", String::new()),
                    Err(RunError::BlowUp { step, .. }) => ("blow-up", step.to_string()),
                    Err(RunError::EnergyGrowth { step, .. }) => ("energy-growth", step.to_string()),
                    Err(e) => return Err(format!("{name}/{mass} ratio {ratio}: {e}")),
                };
                let cell = if status == "ok" { en.max_drift } else { f64::INFINITY };
                if status != "ok" {
                    blowups += 1;
                }
                worst = worst.max(cell);
                growth = growth.max(en.max_growth);
                line.push(cell);
                w.write_record([name.to_string(), mass.to_string(), ratio.to_string(), a.steps.to_string(), seed.to_string(), status.to_string(), stop, format!("{:.3e}", en.max_drift), format!("{:.6}", en.max_growth), format!("{wall:.3}")])
                    .map_err(|e| e.to_string())?;
                w.flush().map_err(|e| e.to_string())?;
            }
            md.push_str(&format!("| {name} | {mass} | {worst:.2e} | {growth:.3} | {blowups} | {refused} |\n"));
            rows.push(format!("{name} {mass}"));
            grid.push(line);
        }
    }
    let cols: Vec<String> = ratios.iter().map(|r| format!("dx/dt={r}")).collect();
    let svg = heat_map(&format!("max relative energy drift over {} steps (log10, blue low, red high; black: blow-up; grey: refused, beyond the CFL limit)", a.steps), &rows, &cols, &grid, true, (900, 40 + 28 * rows.len() as u32))?;
    std::fs::write(a.out.join("stress.svg"), svg).map_err(|e| e.to_string())?;
    println!("# Stress: {} steps per run, {} elements, free bar thrown at the obstacle with random data\n\n{md}", a.steps, a.elements);
    Ok(())
}
