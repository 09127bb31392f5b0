//! The time schemes' period of the first nonsmooth mode (docs/theory.md
//! §11.7): each scheme run through the scene machinery from the exact
//! mode's state at the top of its flight (`u = (Q/c)(L − x)`, at rest),
//! the period measured between the first two landings (the contact node
//! reaching the obstacle after a flight longer than T/4, located by linear
//! interpolation between levels), the contact time as the time between a
//! landing and the next release (the node leaving the obstacle).
//! `cargo run --release -p signorini-orbits --example modes_schemes -- GAP ENERGY MASS SCHEME RATIO`.
use signorini_exact::{Backbone, FarEnd, ModeBar};
use signorini_scene::SceneFile;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let gap: f64 = a.get(1).map_or(0.0, |s| s.parse().unwrap());
    let energy: f64 = a.get(2).map_or(0.5, |s| s.parse().unwrap());
    let mass = a.get(3).cloned().unwrap_or("lumped".into());
    let scheme = a.get(4).cloned().unwrap_or("cd-taylor".into());
    let ratio: f64 = a.get(5).map_or(1.0, |s| s.parse().unwrap());
    let ex = Backbone::new(ModeBar { length: 1.0, wave_speed: 1.0, gap, far_end: FarEnd::Clamped }, 1).unwrap().point(energy).unwrap();
    let q = ex.impact_velocity;
    println!("gap = {gap}, E = {energy}, mass = {mass}, scheme = {scheme}, dx/dt = {ratio}: exact T = {}, t_c = {}", ex.period, ex.contact_time);
    println!("m,T,err_T,t_c,err_tc,landings");
    for m in [10, 20, 40, 80, 160] {
        let text = format!(
            "[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"clamped\"\ngap = {gap:?}\ninitial_displacement = \"{q:?} * (1.0 - x)\"\ninitial_velocity = 0.0\nelements = {m}\nmass = \"{mass}\"\nscheme = \"{scheme}\"\nratio = {ratio:?}\nt_end = {:?}\n",
            (2.6 * ex.period * m as f64 * ratio).ceil() / (m as f64 * ratio)
        );
        let scene = SceneFile::parse(&text).unwrap().validate().unwrap();
        let mut sim = scene.instantiate(None).unwrap();
        let st = &mut sim.stepper;
        let dt = st.dt();
        let scale = q;
        let on = |u: f64| u <= gap + 1e-9 * scale;
        let (mut prev, mut was_on) = (st.displacement()[0], on(st.displacement()[0]));
        let (mut lands, mut releases): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
        while st.time() < 2.6 * ex.period {
            st.step().unwrap();
            let u = st.displacement()[0];
            let now = on(u);
            let t = st.time();
            if now && !was_on {
                // Linear interpolation of the crossing of g between levels.
                let tc = t - dt + dt * (prev - gap) / (prev - u).max(f64::MIN_POSITIVE);
                if lands.last().is_none_or(|&l: &f64| tc - l > 0.25 * ex.period) && releases.last().is_none_or(|&r: &f64| tc - r > 0.25 * ex.period) {
                    lands.push(tc);
                }
            }
            if !now && was_on {
                let tr = t - dt + dt * (gap + 1e-9 * scale - prev).max(0.0) / (u - prev).max(f64::MIN_POSITIVE);
                releases.retain(|&r| r < lands.last().copied().unwrap_or(0.0));
                releases.push(tr);
            }
            (prev, was_on) = (u, now);
        }
        let t = if lands.len() >= 2 { lands[1] - lands[0] } else { f64::NAN };
        let tc = lands.first().and_then(|&l| releases.iter().find(|&&r| r > l).map(|r| r - l)).unwrap_or(f64::NAN);
        println!("{m},{t:.10},{:.3e},{tc:.8},{:.3e},{}", t - ex.period, tc - ex.contact_time, lands.len());
    }
}
