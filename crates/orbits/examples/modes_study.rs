//! The discrete bars' nonsmooth modes against the continuous bar's
//! (docs/theory.md §11.7): `cargo run --release -p signorini-orbits
//! --example modes_study -- GAP ENERGY MASS SCHEME`. For each m, the
//! shooting's result from the exact mode sampled at the nodes, and the
//! closest return of the discrete flow from that state.
use signorini_orbits::modes::{backbone, closest_return, ModeScene};

fn scene(m: usize, mass: &str, scheme: &str, gap: f64) -> toml::Table {
    format!("[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"clamped\"\ngap = {gap:?}\nelements = {m}\nmass = \"{mass}\"\nscheme = \"{scheme}\"\ndt = 0.01\nt_end = 10.0\n").parse().unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let gap: f64 = args.get(1).map_or(0.0, |s| s.parse().unwrap());
    let energy: f64 = args.get(2).map_or(0.5, |s| s.parse().unwrap());
    let mass = args.get(3).cloned().unwrap_or("mod".into());
    let scheme = args.get(4).cloned().unwrap_or("event-driven".into());
    println!("gap = {gap}, E = {energy}, mass = {mass}, scheme = {scheme}");
    println!("T_landing,err_landing,m,shooting,T_shoot,impacts_shoot,mu_max,T_return,T_exact,err_T,tc_return,tc_exact,err_tc,distance,impacts_return,energy_after");
    for m in [10, 20, 40, 80, 160] {
        let doc = scene(m, &mass, &scheme, gap);
        let sc = ModeScene::new(&doc).unwrap();
        let ex = sc.exact_point(energy).unwrap();
        let shot = match backbone(&doc, energy, energy, 1) {
            Ok(b) => {
                let p = &b.points[0];
                {
                    let x0 = sc.exact_state(energy).unwrap();
                    let d = p.orbit.x.iter().zip(&x0).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt() / x0.iter().map(|v| v * v).sum::<f64>().sqrt();
                    format!("converged tc={:.6} dist={:.3e},{:.10},{},{:.4}", p.contact_time, d, p.period, p.impacts_per_period, p.mu_max())
                }
            }
            Err(e) => format!("\"{}\",,,", e.to_string().replace('"', "'").chars().take(60).collect::<String>()),
        };
        let x0 = sc.exact_state(energy).unwrap();
        let r = closest_return(&sc.model, &x0, ex.period, 0.2).unwrap();
        // The period between landings: the first landing after each flight
        // longer than T/4, over 2.5 exact periods.
        let run = sc.model.flow(0.0, &x0, 2.5 * ex.period, false).unwrap();
        let mut lands = Vec::new();
        let mut last_release = 0.0;
        for e in &run.events {
            match e.kind {
                signorini_schemes::events::EventKind::Release => last_release = e.t,
                signorini_schemes::events::EventKind::Impact if (e.t - last_release > 0.25 * ex.period || lands.is_empty()) && lands.last().is_none_or(|&l: &f64| e.t - l > 0.25 * ex.period) => {
                    lands.push(e.t)
                }
                _ => {}
            }
        }
        let t_land = if lands.len() >= 2 { lands[1] - lands[0] } else { f64::NAN };
        print!("{:.10},{:.3e},", t_land, t_land - ex.period);
        let after = sc.model.flow(0.0, &x0, r.time, false).unwrap().x;
        let e1 = sc.model.energy(0.0, &after).unwrap().0 / sc.model.energy(0.0, &x0).unwrap().0;
        println!(
            "{m},{shot},{:.10},{:.10},{:.3e},{:.6},{:.6},{:.3e},{:.3e},{},{:.6}",
            r.time,
            ex.period,
            r.time - ex.period,
            r.contact_time,
            ex.contact_time,
            r.contact_time - ex.contact_time,
            r.distance,
            r.impacts,
            e1
        );
    }
}
