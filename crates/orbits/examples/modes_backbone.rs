//! A backbone of a discrete bar as `signorini modes` would write it:
//! `cargo run --release -p signorini-orbits --example modes_backbone -- M GAP FROM TO POINTS`
//! prints `backbone.csv` and where the family stopped.
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: f64| a.get(i).map_or(d, |s| s.parse().unwrap());
    let (m, gap, from, to, points) = (arg(1, 20.0) as usize, arg(2, -0.25), arg(3, 0.1), arg(4, 2.0), arg(5, 8.0) as usize);
    let doc: toml::Table =
        format!("[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"clamped\"\ngap = {gap:?}\nelements = {m}\nmass = \"mod\"\nscheme = \"event-driven\"\ndt = 0.01\nt_end = 10.0\n").parse().unwrap();
    match signorini_orbits::modes::backbone(&doc, from, to, points) {
        Ok(modes) => {
            print!("{}", signorini_orbits::output::backbone_csv(&modes));
            if let Some((e, why)) = &modes.stopped {
                println!("stopped at E = {e}: {why}");
            }
        }
        Err(e) => println!("error: {e}"),
    }
}
