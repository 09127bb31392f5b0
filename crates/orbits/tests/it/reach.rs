//! The variational Jacobian against central differences of the exact map
//! on the models the shooting must reach: the bar with a massless contact
//! node (mass redistribution: the contact condensed, landings and
//! lift-offs without a jump), the bar with a massive contact node and
//! restitution, the paper's beam between its stops, and its reduced model.
//! Each over one forcing period from a state after a transient.

use signorini_orbits::SceneFamily;

fn check(scene: &str, path: &str, transient_periods: f64, tol: f64, steps: &[f64]) -> (usize, usize) {
    let doc: toml::Table = scene.parse().unwrap();
    let (fam, value) = SceneFamily::new(doc, path, 1).unwrap();
    let built = fam.build(value).unwrap();
    let (model, t) = (&built.model, built.horizon);
    let x = model.flow(0.0, &built.start, transient_periods * t, false).unwrap().x;
    let img = model.flow(0.0, &x, t, true).unwrap();
    let j = img.jacobian.unwrap();
    let n = x.len();
    let scale: Vec<f64> = {
        let (qs, vs) = x.split_at(n / 2);
        let q = qs.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-12);
        let v = vs.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-12);
        (0..n).map(|i| if i < n / 2 { q } else { v }).collect()
    };
    // Differences whose perturbed runs keep the event sequence's length (a
    // strongly expanding map such as the paper's beam, whose one-period
    // Jacobian reaches 1e8, may need h down to 1e-10 of the state for that;
    // there the differences' round-off, ∝ 1/h, reached 1.4e-3 of a column,
    // 8.8e-5 at 1e-9), each column's error against its largest entry.
    let base = img.events.len();
    let mut worst: f64 = 0.0;
    for c in 0..n {
        let mut col = None;
        for &f in steps {
            let h = f * scale[c];
            let (mut p, mut m) = (x.clone(), x.clone());
            p[c] += h;
            m[c] -= h;
            let (fp, fm) = (model.flow(0.0, &p, t, false).unwrap(), model.flow(0.0, &m, t, false).unwrap());
            if fp.events.len() == base && fm.events.len() == base {
                col = Some((0..n).map(|r| (fp.x[r] - fm.x[r]) / (2.0 * h) * scale[c] / scale[r]).collect::<Vec<f64>>());
                break;
            }
        }
        let col = col.unwrap_or_else(|| panic!("column {c}: no perturbation in {steps:?} keeps the event sequence"));
        let big = col.iter().fold(1.0f64, |a, v| a.max(v.abs()));
        for r in 0..n {
            let jv = j[(r, c)] * scale[c] / scale[r];
            worst = worst.max((col[r] - jv).abs() / big);
        }
    }
    let kinds = |k: signorini_schemes::events::EventKind| img.events.iter().filter(|e| e.kind == k).count();
    use signorini_schemes::events::EventKind::{Accumulation, Impact, Release};
    eprintln!("slowest impact {:e}", img.events.iter().filter(|e| e.kind == Impact && e.velocity_before != 0.0).map(|e| e.velocity_before.abs()).fold(f64::INFINITY, f64::min));
    eprintln!(
        "{path}: {n} unknowns, {} events a period ({} impacts, {} releases, {} accumulations), worst relative error {worst:e}",
        img.events.len(),
        kinds(Impact),
        kinds(Release),
        kinds(Accumulation)
    );
    assert!(worst <= tol, "worst relative error {worst:e}");
    (n, img.events.len())
}

/// Perturbations (of the state's scale) tried in turn.
const MILD: &[f64] = &[1e-7, 1e-8, 1e-9];

pub(crate) const BAR: &str = r#"
[bar]
length = 1.0
wave_speed = 1.0
far_end = "clamped"
gap = 0.0
initial_displacement = 0.05
elements = 8
mass = "mod"
scheme = "event-driven"
dt = 0.01
t_end = 40.0
[load]
profile = "harmonics"
harmonics = [[0.2, 1.0, 0.0], [0.05, 3.0, 0.5]]
omega = 1.0
x = 0.5
"#;

#[test]
fn the_bar_with_a_massless_contact_node() {
    let (n, events) = check(BAR, "bar.gap", 3.0, 1e-5, MILD);
    assert_eq!(n, 14, "7 massive dofs: the contact node carries no state");
    assert!(events > 0);
}

#[test]
fn the_bar_with_a_massive_contact_node_and_restitution() {
    let scene = BAR.replace("mass = \"mod\"", "mass = \"std\"").replace("scheme = \"event-driven\"", "scheme = \"event-driven(1)\"");
    let (n, events) = check(&scene, "bar.gap", 3.0, 1e-5, MILD);
    assert_eq!(n, 16);
    assert!(events > 0);
}

#[test]
fn the_papers_beam_between_its_stops_and_its_reduced_model() {
    let beam = "[beam]\nscene = \"fig2\"\nscheme = \"event-driven\"\nelements = 3\n";
    let (_, events) = check(beam, "beam.elements", 2.0, 1e-3, &[1e-9, 1e-10]);
    assert!(events > 50, "a period of the paper's beam with many impacts and releases");
    let reduced = "[beam]\nscene = \"fig2\"\nscheme = \"event-driven\"\nelements = 4\nreduce = { modes = 3 }\n";
    check(reduced, "beam.elements", 2.0, 1e-5, MILD);
}
