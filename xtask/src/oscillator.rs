//! `cargo xtask oscillator`: the impact oscillator scene
//! (data/scenes/oscillator.toml) against its exact period-1 orbits and its
//! grazing frequency (signorini-exact's `ImpactOscillator`, closed forms).
//!
//! For every forcing frequency of the scene's stable range and every time
//! step, a run of `transient + record` forcing periods through the sweep's
//! own run function; the record window's impacts against the exact orbit's
//! impact velocity (relative) and forcing phase (rad), largest over the
//! window; least-squares and last rates in dt. Then the grazing check: from
//! the non-impacting steady state, runs just above and below Ω_g.
//!
//! Outputs (`--out`, default `out/oscillator`): `orbits.csv`
//! (`omega,dt,impacts,velocity_exact,phase_exact,multiplier,velocity_err,phase_err`),
//! `rates.csv` (`omega,velocity_lsq_rate,velocity_last_rate,phase_lsq_rate,phase_last_rate`),
//! `grazing.csv` (`omega,offset,impacts,first_velocity`), `errors.svg`.

use crate::create;
use signorini_cli::scene::Limits;
use signorini_cli::sweep::{simulate, Sweep, SweepOptions};
use signorini_exact::{ImpactOscillator, OscillatorParams};
use signorini_plot::{line_chart, Chart, Scale, Series, Style};
use signorini_run::study::rate;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `cargo xtask oscillator`.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder.
    #[arg(long, default_value = "out/oscillator")]
    out: PathBuf,
    /// Forcing frequencies (the scene's stable period-1 range).
    #[arg(long, value_delimiter = ',', default_value = "1.6,1.7,1.8,1.9,2.0,2.1,2.2")]
    omegas: Vec<f64>,
    /// Time steps.
    #[arg(long, value_delimiter = ',', default_value = "2e-3,1e-3,5e-4,2.5e-4,1.25e-4,6.25e-5,3.125e-5,1.5625e-5,7.8125e-6")]
    dts: Vec<f64>,
    /// Forcing periods before the record window.
    #[arg(long, default_value_t = 60.0)]
    transient: f64,
    /// Forcing periods recorded.
    #[arg(long, default_value_t = 10.0)]
    record: f64,
}

fn scene_text(dt: f64, x0: f64, v0: f64) -> Result<String, String> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/scenes/oscillator.toml");
    let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
    Ok(text.replace("dt = 1e-3", &format!("dt = {dt:e}")).replace("initial_displacement = 0.0", &format!("initial_displacement = {x0:e}")).replace("initial_velocity = 0.0", &format!("initial_velocity = {v0:e}")))
}

/// The record window's impacts `(phase, velocity)` of one run.
fn impacts(text: &str, omega: f64, transient: f64, record: f64) -> Result<Vec<(f64, f64)>, String> {
    let mut o = SweepOptions::new("forcing.omega", omega, omega, 1);
    o.transient = transient;
    o.record = record;
    let sweep = Sweep::new(text, "oscillator.toml", None, o, Limits::machine()).map_err(|e| e.to_string())?;
    let (_, scene, plan) = sweep.scene((omega, None)).map_err(|e| e.to_string())?;
    let rows = simulate(&scene, &plan, None, false, None);
    if rows.status != "ok" {
        return Err(format!("Ω = {omega}: {}", rows.status));
    }
    Ok(rows.impacts.iter().map(|(_, v)| (v[1], v[2])).collect())
}

fn exact(omega: f64) -> Result<ImpactOscillator, String> {
    ImpactOscillator::new(OscillatorParams { mass: 1.0, stiffness: 1.0, damping_ratio: 0.05, force: 1.0, forcing_frequency: omega, gap: 0.2, restitution: 0.8 }).map_err(|e| e.to_string())
}

/// `cargo xtask oscillator`.
pub fn run_oscillator(a: Args) -> Result<(), String> {
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let start = std::time::Instant::now();
    let cases: Vec<(f64, f64)> = a.omegas.iter().flat_map(|&w| a.dts.iter().map(move |&dt| (w, dt))).collect();
    // Every case on its own thread, two at a time per core at most.
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut results: Vec<Option<Result<Vec<(f64, f64)>, String>>> = (0..cases.len()).map(|_| None).collect();
    for chunk in (0..cases.len()).collect::<Vec<_>>().chunks(threads) {
        let out: Vec<(usize, Result<Vec<(f64, f64)>, String>)> = std::thread::scope(|s| {
            let (transient, record) = (a.transient, a.record);
            let hs: Vec<_> = chunk
                .iter()
                .map(|&i| {
                    let (w, dt) = cases[i];
                    (i, s.spawn(move || scene_text(dt, 0.0, 0.0).and_then(|t| impacts(&t, w, transient, record))))
                })
                .collect();
            hs.into_iter().map(|(i, h)| (i, h.join().unwrap_or_else(|_| Err("a run panicked".into())))).collect()
        });
        for (i, r) in out {
            results[i] = Some(r);
        }
    }
    let mut orbits = create(&a.out, "orbits.csv")?;
    writeln!(orbits, "omega,dt,impacts,velocity_exact,phase_exact,multiplier,velocity_err,phase_err").map_err(|e| e.to_string())?;
    let mut rates = create(&a.out, "rates.csv")?;
    writeln!(rates, "omega,velocity_lsq_rate,velocity_last_rate,phase_lsq_rate,phase_last_rate").map_err(|e| e.to_string())?;
    let mut series = Vec::new();
    println!("# Impact oscillator against its exact period-1 orbits\n\n| Ω | V exact | |μ| | velocity error (relative) at dt = {} … {} | rate | phase error (rad) | rate |\n|---|---|---|---|---|---|---|", a.dts[0], a.dts[a.dts.len() - 1]);
    for &w in &a.omegas {
        let orbits_w = exact(w)?.period1_orbits();
        let [o] = orbits_w.as_slice() else {
            return Err(format!("Ω = {w}: {} admissible period-1 orbits (one expected in the stable range)", orbits_w.len()));
        };
        let mut ev = Vec::new();
        let mut ep = Vec::new();
        for (k, &(cw, dt)) in cases.iter().enumerate().filter(|(_, c)| c.0 == w) {
            let got = results[k].take().unwrap_or_else(|| Err("missing".into()))?;
            let e_v = got.iter().map(|(_, v)| (v - o.impact_velocity).abs() / o.impact_velocity).fold(0.0, f64::max);
            let e_p = got.iter().map(|(p, _)| (p - o.phase).abs()).fold(0.0, f64::max);
            writeln!(orbits, "{cw},{dt:e},{},{:.15e},{:.15e},{:.6e},{e_v:.6e},{e_p:.6e}", got.len(), o.impact_velocity, o.phase, o.multipliers[0].abs()).map_err(|e| e.to_string())?;
            ev.push((dt, e_v));
            ep.push((dt, e_p));
        }
        let (rv, rp) = (rate(&ev), rate(&ep));
        writeln!(rates, "{w},{:.4},{:.4},{:.4},{:.4}", rv.lsq, rv.last, rp.lsq, rp.last).map_err(|e| e.to_string())?;
        println!("| {w} | {:.6} | {:.3} | {:.2e} … {:.2e} | {:.2} | {:.2e} … {:.2e} | {:.2} |", o.impact_velocity, o.multipliers[0].abs(), ev[0].1, ev[ev.len() - 1].1, rv.lsq, ep[0].1, ep[ep.len() - 1].1, rp.lsq);
        series.push(Series { label: format!("Ω = {w}"), points: ev, reference: false, style: Style::default() });
    }
    orbits.flush().map_err(|e| e.to_string())?;
    rates.flush().map_err(|e| e.to_string())?;
    let chart = Chart { title: "impact oscillator: impact velocity error against the exact period-1 orbit", x_label: "dt", y_label: "max relative error", scale: Scale::LogLog, size: (800, 560) };
    let svg = line_chart(&chart, &series)?;
    std::fs::write(a.out.join("errors.svg"), svg).map_err(|e| e.to_string())?;
    // Grazing: from the non-impacting steady state of each Ω.
    let wg = exact(2.0)?.grazing_frequencies();
    let mut graz = create(&a.out, "grazing.csv")?;
    writeln!(graz, "omega,offset,impacts,first_velocity").map_err(|e| e.to_string())?;
    println!("\nGrazing frequency (steady amplitude = gap): {wg:?}; from the non-impacting steady state (dt = 1e-4, 30 periods):\n\n| Ω − Ω_g | impacts | first impact velocity |\n|---|---|---|");
    for &g in &wg {
        for d in [1e-3, 3e-4, -3e-4, -1e-3, -1e-2] {
            let w = g + d;
            let z = exact(w)?.steady_state(0.0);
            let im = impacts(&scene_text(1e-4, z.x, z.v)?, w, 0.0, 30.0)?;
            let v1 = im.first().map_or(f64::NAN, |p| p.1);
            writeln!(graz, "{w},{d:e},{},{v1:.6e}", im.len()).map_err(|e| e.to_string())?;
            println!("| {d:+.0e} | {} | {} |", im.len(), if v1.is_nan() { "—".to_string() } else { format!("{v1:.4}") });
        }
    }
    graz.flush().map_err(|e| e.to_string())?;
    println!("\nwrote {} in {:.1} s", a.out.display(), start.elapsed().as_secs_f64());
    Ok(())
}
