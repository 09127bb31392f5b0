//! `signorini run` has one path for every kind of scene, reading the
//! scene's facts (`Scene::facts`): each kind's files, series header and
//! summary line against the contract written out here by hand (the crate
//! docs' list of output files), not against the facts themselves.

use signorini_cli::scene::{output_estimate, SceneFile};
use signorini_cli::{run_scene, RunOptions};
use std::collections::BTreeSet;

const OSC: &str = "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = 0.8\ndt = 1e-2\nt_end = 2.0\n[forcing]\namplitude = 1.0\nomega = 2.0\n";
const BAR_BENCH: &str = "[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nmass = \"mod\"\nscheme = \"newmark-cn\"\nratio = 10.0\nt_end = 0.5\n";
/// Contact 0 is the stop at x = 0.5 (node 5), contact 1 the end x = 0.
const BAR_STOPS: &str = "[bar]\nlength = 1.0\nwave_speed = 1.0\nfar_end = \"clamped\"\ninitial_displacement = \"0.1 * x\"\ninitial_velocity = -0.5\nelements = 10\nmass = \"std\"\nscheme = \"ps(0.5)\"\ndt = 0.01\nt_end = 1.0\n[[stop]]\nx = 0.5\nlo = -0.05\nhi = 0.06\n[[stop]]\nx = 0.0\nlo = -0.01\n[output]\nsnapshots_every = 10\n";
const BEAM: &str = "[beam]\nscene = \"fig2\"\nt_end = 0.005\n[output]\nsnapshots_every = 20\n";
/// Contact 0 is the stop at x = 0.7505 (node 10 of 20), not the tip.
const BEAM_STOPS: &str = "[beam]\nscene = \"fig2\"\nelements = 20\nt_end = 0.005\n[[stop]]\nx = 0.7505\nlo = -0.03\nhi = 0.03\n[[stop]]\nx = 1.501\nlo = -0.1\nhi = 0.1\n";

/// What one run wrote: its files, `series.csv`'s header and rows, the
/// summary's first line, the check's output estimate.
struct Ran {
    files: BTreeSet<String>,
    header: String,
    rows: Vec<Vec<f64>>,
    first_line: String,
    snapshots_header: Option<String>,
}

fn run(text: &str) -> Ran {
    let dir = tempfile::tempdir().unwrap();
    let file = SceneFile::parse(text).unwrap();
    let scene = file.validate().unwrap();
    let out = dir.path().join("out");
    let summary = run_scene(&scene, &file, &out, &RunOptions::default()).unwrap();
    let files = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let mut lines = series.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines.skip(1).map(|l| l.split(',').map(|c| c.parse().unwrap_or(f64::NAN)).collect()).collect();
    let snapshots_header = std::fs::read_to_string(out.join("snapshots.csv")).ok().map(|s| s.lines().next().unwrap().to_string());
    Ran { files, header, rows, first_line: summary.lines[0].clone(), snapshots_header }
}

fn set(names: &[&str]) -> BTreeSet<String> {
    names.iter().map(|s| s.to_string()).collect()
}

/// The series' numeric columns (after the step counter) the output
/// estimate counts: its row is 11 + 21 bytes per column (`report.rs`),
/// over `t_end / dt + 2` rows (the scene without its snapshots and plots).
fn estimated_columns(text: &str) -> f64 {
    let text: String = text.lines().filter(|l| !l.starts_with("snapshots_every")).map(|l| format!("{l}\n")).collect();
    let mut file = SceneFile::parse(&text).unwrap();
    let scene = file.validate().unwrap();
    file.output.plots = false;
    let t_end = scene.forcing_and_horizon().1;
    let dt = match (&file.bar, &file.beam, &file.oscillator) {
        (Some(b), _, _) => b.dt.unwrap_or_else(|| 1.0 / b.elements as f64 / b.ratio.unwrap()),
        (_, Some(_), _) => 5e-5, // fig. 2's
        (_, _, Some(o)) => o.dt,
        _ => unreachable!(),
    };
    let rows = t_end / dt + 2.0;
    let series = output_estimate(&scene, &file.output);
    (series / rows - 11.0) / 21.0
}

/// A scene, its series header, files, summary line and snapshots header.
type Case = (&'static str, &'static str, &'static str, BTreeSet<String>, &'static str, Option<&'static str>);

#[test]
fn every_kind_writes_its_documented_files_and_columns() {
    let energy = "n,t,u_contact,v_contact,lambda_t,lambda,energy_t,energy";
    let cases: [Case; 5] = [
        (
            "bar benchmark",
            BAR_BENCH,
            "n,t,u_contact,v_contact,lambda_t,lambda,energy_t,energy,u_contact_exact,lambda_exact,energy_exact",
            set(&["series.csv", "norms.csv", "u_contact.svg", "lambda.svg", "energy.svg"]),
            "bar-dirichlet (10 elements, mass mod, scheme newmark-cn, dt = 1e-2): 50 steps in ",
            None,
        ),
        (
            "bar with stops",
            BAR_STOPS,
            "",
            set(&["series.csv", "snapshots.csv", "u_contact.svg", "lambda.svg", "energy.svg"]),
            "bar (10 elements, mass std, scheme ps-e0.5, dt = 1e-2): 100 steps in ",
            Some("n,t,x,u"),
        ),
        ("beam", BEAM, "n,t_s,tip_m,v_tip_m_s,lambda_t,lambda", set(&["series.csv", "snapshots.csv", "tip.svg"]), "100 steps in ", Some("n,t_s,x_m,u_m")),
        ("beam with stops", BEAM_STOPS, "n,t_s,tip_m,v_tip_m_s,lambda_t,lambda,u_c0,lambda_0,active_0,u_c1,lambda_1,active_1", set(&["series.csv", "tip.svg", "lambda.svg"]), "100 steps in ", None),
        ("oscillator", OSC, "n,t,x,v,lambda_t,lambda,energy_t,energy", set(&["series.csv", "x.svg"]), "oscillator (ps(0.8), dt = 1e-2): 200 steps in ", None),
    ];
    for (name, text, header, files, first, snapshots) in cases {
        let ran = run(text);
        let header = if header.is_empty() { format!("{energy},u_c0,lambda_0,active_0,u_c1,lambda_1,active_1") } else { header.to_string() };
        assert_eq!(ran.header, header, "{name}: series.csv's header");
        assert_eq!(ran.files, files, "{name}: the files written");
        assert!(ran.first_line.starts_with(first), "{name}: {}", ran.first_line);
        assert_eq!(ran.snapshots_header.as_deref(), snapshots, "{name}: snapshots.csv's header");
        let cols = header.split(',').count() - 1;
        let est = estimated_columns(text);
        assert!((est - cols as f64).abs() < 1e-6, "{name}: the output estimate counts {est} columns, the series has {cols}");
    }
}

/// The series' tip column is contact 0's dof for a bar (its first stop,
/// here x = 0.5, not the end x = 0) and the tip for a beam (not its
/// contact 0 at mid-span).
#[test]
fn the_tip_column_is_contact_0_for_a_bar_and_the_tip_for_a_beam() {
    let bar = run(BAR_STOPS);
    let (u, c0, c1) = (2, 8, 11);
    assert!(bar.rows.iter().all(|r| r[u] == r[c0]), "the bar's u_contact is u_c0");
    assert!(bar.rows.iter().any(|r| r[u] != r[c1]), "the bar's u_contact is not the end's");
    let beam = run(BEAM_STOPS);
    let (tip, c0, c1) = (2, 6, 9);
    assert!(beam.rows.iter().all(|r| r[tip] == r[c1]), "the beam's tip_m is its tip (contact 1, x = 1.501)");
    assert!(beam.rows.iter().any(|r| r[tip] != r[c0]), "the beam's tip_m is not contact 0");
}

/// The output estimate (what `signorini check` states and the disk check
/// of `run` refuses by) against the bytes a run writes, for every kind with
/// its plots, long enough that the line plots are decimated: within
/// [1, 2] of them. (It used to count a fixed 8 MB of plots: 10–60 × the
/// written size here.)
#[test]
fn the_output_estimate_is_within_twice_the_bytes_written() {
    let long = |text: &str, from: &str, to: &str| text.replace(from, to);
    let cases = [
        ("oscillator", long(OSC, "t_end = 2.0", "t_end = 500.0")),
        ("bar benchmark", long(BAR_BENCH, "ratio = 10.0\nt_end = 0.5", "ratio = 1.0\nelements = 40\nt_end = 30.0").replace("elements = 10\n", "")),
        ("bar with stops", long(BAR_STOPS, "t_end = 1.0", "t_end = 300.0")),
        ("beam", long(BEAM, "t_end = 0.005", "t_end = 2.0")),
        ("beam with stops", long(BEAM_STOPS, "t_end = 0.005", "t_end = 2.0")),
    ];
    for (name, text) in cases {
        let dir = tempfile::tempdir().unwrap();
        let file = SceneFile::parse(&text).unwrap();
        let scene = file.validate().unwrap();
        let out = dir.path().join("out");
        run_scene(&scene, &file, &out, &RunOptions::default()).unwrap();
        let written: u64 = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().metadata().unwrap().len()).sum();
        let est = output_estimate(&scene, &file.output);
        let ratio = est / written as f64;
        assert!((1.0..=2.0).contains(&ratio), "{name}: estimated {est:.0} bytes, written {written} ({ratio:.2}×)");
    }
}

/// The estimate's scatter bound is the plot crate's.
#[test]
fn the_scatter_bound_is_the_plot_crates() {
    assert_eq!(signorini_cli::scene::SCATTER_POINTS, signorini_plot::MAX_PLOT_POINTS);
}
