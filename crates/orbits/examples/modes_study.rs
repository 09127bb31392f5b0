//! scratch
use signorini_orbits::modes::{backbone, contact_of};

fn scene(m: usize, mass: &str, scheme: &str, gap: f64) -> toml::Table {
    format!("[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"clamped\"\ngap = {gap:?}\nelements = {m}\nmass = \"{mass}\"\nscheme = \"{scheme}\"\ndt = 0.01\nt_end = 10.0\n").parse().unwrap()
}

fn main() {
    {
        let sc = signorini_orbits::modes::ModeScene::new(&scene(10, "mod", "event-driven", -0.25)).unwrap();
        let x = sc.exact_state(0.1).unwrap();
        let img = sc.model.flow(0.0, &x, 3.559, true).unwrap();
        let j = img.jacobian.unwrap();
        println!("x0 {:?}\nx1 {:?}\nfield {:?}\njac finite {}", x, img.x, img.field, (0..j.nrows()).all(|r| (0..j.ncols()).all(|c| j[(r, c)].is_finite())));
        let (e, g) = sc.model.energy(0.0, &x).unwrap();
        println!("E {e} g {:?}", g);
        let f0 = sc.model.flow(0.0, &x, 1e-12, false).unwrap().field;
        println!("f0 {:?}", f0);
        for ev in &img.events {
            println!("{:?}", ev);
        }
    }
    let args: Vec<String> = std::env::args().collect();
    let gap: f64 = args.get(1).map_or(-0.25, |s| s.parse().unwrap());
    let mass = args.get(2).cloned().unwrap_or("mod".into());
    let scheme = args.get(3).cloned().unwrap_or("event-driven".into());
    for m in [10, 20, 40, 80] {
        let t = std::time::Instant::now();
        match backbone(&scene(m, &mass, &scheme, gap), 0.1, 2.0, 5) {
            Ok(b) => {
                for p in &b.points {
                    let e = p.exact.unwrap();
                    println!(
                        "m={m} E={:.4} T={:.8} Tex={:.8} dT={:.3e} tc={:.6} tcex={:.6} imp={} mu={:.6} res={:.1e} it={}",
                        p.energy,
                        p.period,
                        e.period,
                        p.period - e.period,
                        p.contact_time,
                        e.contact_time,
                        p.impacts_per_period,
                        p.mu_max(),
                        p.residual,
                        p.orbit.iterations
                    );
                    let _ = contact_of(&p.orbit);
                }
                if let Some((e, err)) = &b.stopped {
                    println!("stopped at {e}: {err}");
                }
            }
            Err(e) => println!("m={m}: {e}"),
        }
        println!("  {:.2}s", t.elapsed().as_secs_f64());
    }
}
