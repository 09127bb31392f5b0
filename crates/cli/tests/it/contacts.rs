//! Several contacts in scenes (issue 12): `[[stop]]` and `[obstacle]`, the
//! per-contact series columns and plots, the shipped multi-contact scenes,
//! and bad input (each a typed error naming its field and value).

use signorini_cli::scene::{Limits, Scene, SceneError, SceneFile};
use signorini_fem::{Bar, BarMass, RightEnd};
use signorini_run::{BarProblem, Stop};
use signorini_schemes::SchemeSpec;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/scenes").join(name)
}

/// Runs a shipped scene into a temporary folder: (folder guard, output folder, stdout).
fn run_shipped(name: &str) -> (tempfile::TempDir, PathBuf, String) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = bin().args(["run", scene_path(name).to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
    (dir, out, String::from_utf8_lossy(&o.stdout).into_owned())
}

/// The series as a header and rows of cells (`None` for an empty cell).
fn series(out: &Path) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    let mut rd = csv::Reader::from_path(out.join("series.csv")).unwrap();
    let header: Vec<String> = rd.headers().unwrap().iter().map(String::from).collect();
    let rows = rd.records().map(|r| r.unwrap().iter().map(|c| if c.is_empty() { None } else { Some(c.parse::<f64>().unwrap()) }).collect()).collect();
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

/// Feasibility and complementarity of every contact at every row, against
/// bounds the test knows: `lo - 1e-12 <= u_c <= hi + 1e-12`; free contacts
/// carry no force; at a bound the contact sits on it with the force's sign
/// (`λ <= 0` at lo, `>= 0` at hi, `active = -1` / `1`). Returns how many
/// rows each contact was at its lower and upper bound.
fn check_contacts(header: &[String], rows: &[Vec<Option<f64>>], bounds: &[(f64, f64)]) -> Vec<(usize, usize)> {
    let mut at = vec![(0, 0); bounds.len()];
    for (n, r) in rows.iter().enumerate() {
        for (i, &(lo, hi)) in bounds.iter().enumerate() {
            let u = r[col(header, &format!("u_c{i}"))].unwrap();
            assert!(lo - 1e-12 <= u && u <= hi + 1e-12, "row {n}: u_c{i} = {u} outside [{lo}, {hi}]");
            let (lam, act) = (r[col(header, &format!("lambda_{i}"))], r[col(header, &format!("active_{i}"))]);
            let (Some(lam), Some(act)) = (lam, act) else {
                assert!(n <= 1 && lam.is_none() && act.is_none(), "row {n}: contact {i} has an empty force or status");
                continue;
            };
            match act as i64 {
                0 => assert!(lam == 0.0, "row {n}: contact {i} free with λ = {lam}"),
                -1 => {
                    assert!((u - lo).abs() <= 1e-12 * (1.0 + lo.abs()) && lam <= 0.0, "row {n}: contact {i} at lo = {lo}: u = {u}, λ = {lam}");
                    at[i].0 += 1;
                }
                1 => {
                    assert!((u - hi).abs() <= 1e-12 * (1.0 + hi.abs()) && lam >= 0.0, "row {n}: contact {i} at hi = {hi}: u = {u}, λ = {lam}");
                    at[i].1 += 1;
                }
                other => panic!("row {n}: active_{i} = {other}"),
            }
        }
    }
    at
}

/// The shipped bar between two walls: its per-contact columns are the
/// stepper's own state driven here step by step (the CLI's plumbing), every
/// row is feasible and complementary, and the impacts follow the wave
/// solution: a free bar of length 1 (c = 1) thrown at 0.5 against a wall
/// stays on it for 2L/c = 2, its force an impulse of twice its momentum
/// (mass `mod` empties the element next to each contact node: mass 0.98),
/// then flies 0.02 to the other wall; the discrete waves arrive within a
/// few dx (0.01) of the exact times.
#[test]
fn bar_two_walls_columns_follow_the_stepper_and_the_wave_solution() {
    let (_dir, out, stdout) = run_shipped("bar-two-walls.toml");
    assert!(stdout.contains("800 steps"), "{stdout}");
    let (header, rows) = series(&out);
    let first = ["n", "t", "u_contact", "v_contact", "lambda_t", "lambda", "energy_t", "energy"];
    assert_eq!(&header[..8], first);
    assert_eq!(&header[8..], ["u_c0", "lambda_0", "active_0", "u_c1", "lambda_1", "active_1"]);
    assert_eq!(rows.len(), 801);

    // The same run driven here.
    let bar = Bar::new(1.0, 100, 1.0, RightEnd::Free).unwrap();
    let p = BarProblem::new(bar, BarMass::Mod, -1.0, 0.0, |_| 0.0, |_| -0.5).unwrap();
    let p = p.with_stops(vec![Stop::new(0, -0.02, f64::INFINITY), Stop::new(100, f64::NEG_INFINITY, 0.0)]).unwrap();
    let mut s = SchemeSpec::newmark(0.25, 0.5).build(p.dynamics(), 0.01, &p.initial).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-11 * (1.0 + b.abs());
    for (n, r) in rows.iter().enumerate().skip(1) {
        s.step().unwrap();
        let u = s.displacement();
        let code = |a: signorini_contact::Active| match a {
            signorini_contact::Active::Lower => -1.0,
            signorini_contact::Active::Upper => 1.0,
            signorini_contact::Active::None => 0.0,
        };
        for (i, dof) in [0, 100].into_iter().enumerate() {
            let c = 8 + 3 * i;
            assert!(close(r[c].unwrap(), u[dof]), "row {n}: u_c{i} = {:?}, stepper {}", r[c], u[dof]);
            assert!(close(r[c + 1].unwrap(), s.contact_forces()[i]), "row {n}: lambda_{i}");
            assert_eq!(r[c + 2].unwrap(), code(s.contact_status()[i]), "row {n}: active_{i}");
        }
        // u_contact and lambda are contact 0's.
        assert!(close(r[2].unwrap(), u[0]) && close(r[5].unwrap(), s.contact_forces()[0]), "row {n}");
    }

    let at = check_contacts(&header, &rows, &[(-0.02, f64::INFINITY), (f64::NEG_INFINITY, 0.0)]);
    assert!(at[0].0 > 300 && at[1].1 > 300 && at[0].1 == 0 && at[1].0 == 0, "rows at the walls: {at:?}");
    // The wave solution: contact 0 on [0.04, 2.04], contact 1 on [2.08, 4.08],
    // contact 0 again on [4.12, 6.12] (the rigid flights take 0.02 / 0.5);
    // checked 5 dx inside each window.
    let t = |r: &Vec<Option<f64>>| r[1].unwrap();
    let inside = |a: f64, b: f64| rows.iter().filter(move |r| t(r) > a + 0.05 && t(r) < b - 0.05);
    let on = |i: usize, a: f64, b: f64| inside(a, b).all(|r| r[10 + 3 * i].unwrap() != 0.0);
    let off = |i: usize, a: f64, b: f64| inside(a, b).all(|r| r[10 + 3 * i].unwrap_or(0.0) == 0.0);
    assert!(on(0, 0.04, 2.04) && off(0, 2.04, 4.12) && on(1, 2.08, 4.08) && off(1, 0.0, 2.08) && on(0, 4.12, 6.12), "contact windows");
    // Impulses ∫λ dt of the first two impacts: ∓2 · 0.98 · 0.5 (to 1.5 %).
    let impulse = |i: usize, a: f64, b: f64| 0.01 * rows.iter().filter(|r| t(r) > a && t(r) < b).map(|r| r[9 + 3 * i].unwrap_or(0.0)).sum::<f64>();
    let (j0, j1) = (impulse(0, 0.0, 2.06), impulse(1, 2.06, 4.1));
    assert!((j0 + 0.98).abs() < 0.015 * 0.98 && (j1 - 0.98).abs() < 0.015 * 0.98, "impulses {j0}, {j1}");
    // lambda.svg: one line per contact.
    let svg = std::fs::read_to_string(out.join("lambda.svg")).unwrap();
    assert!(svg.contains("λ_0 (stop.0, x = 0)") && svg.contains("λ_1 (stop.1, x = 1)"), "lambda.svg lacks a contact");
}

/// The shipped beam scenes run, keep every contact inside its bounds (the
/// β-scheme's projection puts the displacement itself in K), report the
/// tip in `tip_m` as its contact's `u_c<i>`, and reach their bounds; with
/// obstacles at ±0.1 along the pipe where only the tip reaches them, the
/// run is figure 2's (same β, dt, J; the one-contact closed form against
/// the multi-contact solve) until the chaotic rattling amplifies round-off.
#[test]
fn beam_scenes_with_stops_and_obstacles_stay_inside() {
    let (_d1, out, stdout) = run_shipped("beam-three-supports.toml");
    assert!(stdout.contains("40000 steps") && stdout.contains("2 contacts"), "{stdout}");
    let (header, rows) = series(&out);
    assert_eq!(&header[..6], ["n", "t_s", "tip_m", "v_tip_m_s", "lambda_t", "lambda"]);
    assert_eq!(rows.len(), 4001);
    let at = check_contacts(&header, &rows, &[(-0.1, 0.1), (-0.03, 0.03)]);
    assert!(at.iter().all(|&(l, u)| l > 0 && u > 0), "each stop reached on both sides: {at:?}");
    assert!(rows.iter().all(|r| r[2] == r[col(&header, "u_c0")]), "tip_m is u_c0");
    assert!(out.join("lambda.svg").exists() && out.join("tip.svg").exists());

    let (_d2, out, _) = run_shipped("beam-obstacles.toml");
    let (header, rows) = series(&out);
    assert_eq!(header.len(), 6 + 3 * 19);
    let at = check_contacts(&header, &rows, &[(-0.1, 0.1); 19]);
    assert!(at[18].0 > 0 && at[18].1 > 0, "the tip reaches both obstacles: {at:?}");
    assert!(rows.iter().all(|r| r[2] == r[col(&header, "u_c18")]), "tip_m is the last node's u_c18");
    let svg = std::fs::read_to_string(out.join("lambda.svg")).unwrap();
    assert!(svg.contains("18: x = 1.5010") && svg.contains("0: x = 0.0790"), "the heat map has a row per contact");

    let (_d3, fig2, _) = run_shipped("beam-fig2.toml");
    let (_, rows2) = series(&fig2);
    assert_eq!(rows2.len(), rows.len());
    for (a, b) in rows.iter().zip(&rows2).take_while(|(a, _)| a[1].unwrap() <= 0.25) {
        let (x, y) = (a[2].unwrap(), b[2].unwrap());
        assert!((x - y).abs() <= 1e-7, "t = {:?}: tip {x} with [obstacle], {y} in figure 2", a[1]);
    }
}

fn field_error(text: &str, limits: &Limits) -> (String, String) {
    match SceneFile::parse(text).unwrap_or_else(|e| panic!("{text}: {e}")).validate_with(limits) {
        Err(SceneError::Field { field, message }) => (field, message),
        Err(e) => panic!("{text}: expected a field error, got {e}"),
        Ok(_) => panic!("{text}: accepted"),
    }
}

/// A bar of 10 elements on [0, 1] (nodes every 0.1), free end, at rest at u0.
fn bar(extra: &str, u0: &str, tail: &str) -> String {
    format!("[bar]\nelements = 10\nfar_end = \"free\"\ndt = 0.01\nt_end = 0.1\ninitial_displacement = {u0}\n{extra}\n{tail}")
}

/// Every refusal names its field and value, says what is allowed, and comes
/// from `check` as from `validate` (exit 2, never a panic).
#[test]
fn bad_stops_and_obstacles_name_field_and_value() {
    let here = Limits::machine();
    let stop = |x: &str, more: &str| format!("[[stop]]\nx = {x}\n{more}\n");
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        // x not a node: the nearest nodes are named.
        (bar("", "0.0", &stop("0.55", "lo = -1.0")), "stop.0.x", vec!["0.55", "mesh node", "node 5", "node 6", "0.5", "0.6"]),
        (bar("", "0.0", &stop("1.5", "lo = -1.0")), "stop.0.x", vec!["1.5", "[0, 1]"]),
        (bar("", "0.0", &stop("nan", "lo = -1.0")), "stop.0.x", vec!["NaN"]),
        // The clamped end has no displacement.
        (bar("", "0.0", &stop("1.0", "lo = -1.0")).replace("far_end = \"free\"\n", ""), "stop.0.x", vec!["node 10", "clamped", "0..=9"]),
        // lo > hi, no bound, a bound on the wrong side.
        (bar("", "0.0", &stop("0.0", "lo = 0.5\nhi = -0.5")), "stop.0.lo", vec!["0.5", "lo <= hi = -0.5"]),
        (bar("", "0.0", &stop("0.0", "")), "stop.0.lo", vec!["give lo and/or hi"]),
        (bar("", "0.0", &stop("0.0", "hi = -inf")), "stop.0.hi", vec!["-inf", "+inf (no upper bound)"]),
        (bar("", "0.0", &stop("0.0", "lo = -inf")), "stop.0.lo", vec!["-inf", "at least one finite bound"]),
        // Two stops on one node (x = 0 and 1e-12 snap to node 0).
        (bar("", "0.0", &format!("{}{}", stop("0.0", "lo = -1.0"), stop("1e-12", "hi = 1.0"))), "stop.1.x", vec!["snaps to node 0", "stop.0", "one stop per node"]),
        // The initial state outside a stop, an obstacle, or their intersection.
        (bar("", "0.1", &stop("0.5", "hi = 0.05")), "stop.0.hi", vec!["0.05", "x = 0.5", "u0 = 0.1", "above"]),
        (bar("", "0.1", "[obstacle]\nhi = \"0.05 + 0 * x\"\n"), "obstacle.hi", vec!["0.05", "x = 0 ", "u0 = 0.1"]),
        (bar("", "\"x\"", "[obstacle]\nlo = \"-x\"\nhi = \"x / 2\"\n"), "obstacle.hi", vec!["0.05", "x = 0.1", "u0 = 0.1"]),
        (bar("", "0.0", &format!("{}[obstacle]\nhi = 0.1\n", stop("0.3", "lo = 0.2"))), "stop.0.lo", vec!["0.2", "obstacle.hi = 0.1", "x = 0.3"]),
        ("[beam]\nscene = \"fig2\"\n[obstacle]\nlo = 0.05\n".to_string(), "obstacle.lo", vec!["0.05", "u0 = 0", "below"]),
        // Obstacle expressions that fail or are not finite at a node.
        (bar("", "0.0", "[obstacle]\nlo = \"y - 1\"\n"), "obstacle.lo", vec!["y - 1"]),
        (bar("", "0.0", "[obstacle]\nlo = \"-1/x\"\n"), "obstacle.lo", vec!["-inf", "x = 0", "finite at every node"]),
        ("[beam]\nscene = \"fig2\"\n[obstacle]\nhi = \"math::ln(x - 1)\"\n".to_string(), "obstacle.hi", vec!["NaN", "x = 0.079", "finite at every node"]),
        (bar("", "0.0", "[obstacle]\nlo = nan\n"), "obstacle.lo", vec!["NaN"]),
        (bar("", "0.0", "[obstacle]\nlo = 1.0\nhi = \"x\"\n"), "obstacle.lo", vec!["lo(0) = 1", "hi(x) = 0"]),
        (bar("", "0.0", "[obstacle]\n"), "obstacle", vec!["give lo and/or hi"]),
        // Per-stop keys the scheme does not use, or out of range.
        (bar("", "0.0", &stop("0.0", "lo = -1.0\nrestitution = 0.5")), "stop.0.restitution", vec!["acts only", "newmark-cn", "ps"]),
        (bar("scheme = \"ps-e0\"", "0.0", &stop("0.0", "lo = -1.0\nrestitution = 1.5")), "stop.0.restitution", vec!["1.5", "[0, 1]"]),
        (bar("scheme = \"penalty-cn\"", "0.0", &stop("0.0", "lo = -1.0\nstiffness = -1.0")), "stop.0.stiffness", vec!["-1", "> 0"]),
        (bar("", "0.0", &stop("0.0", "lo = -1.0\nstiffness = 10.0")), "stop.0.stiffness", vec!["acts only", "penalty"]),
        (
            bar("scheme = \"penalty-cn\"", "0.0", &format!("{}{}", stop("0.0", "lo = -1.0"), stop("1.0", "hi = 1.0\nstiffness = 1e30"))),
            "stop.1.stiffness",
            vec!["1e30", "usable range", "stiffness <="],
        ),
        ("[beam]\nscene = \"fig5\"\n[[stop]]\nx = 1.501\nlo = -0.1\nrestitution = 0.5\n".to_string(), "stop.0.restitution", vec!["acts only", "projection"]),
        ("[beam]\nscene = \"fig2\"\n[[stop]]\nx = 1.501\nlo = -0.1\nstiffness = 1e8\n".to_string(), "stop.0.stiffness", vec!["acts only", "penalty"]),
        ("[beam]\nscene = \"fig5\"\n[[stop]]\nx = 1.501\nlo = -0.1\nstiffness = 1e40\n".to_string(), "stop.0.stiffness", vec!["N/m", "usable range"]),
        ("[beam]\nscene = \"fig2\"\n[[stop]]\nx = 0.0\nlo = -0.1\n".to_string(), "stop.0.x", vec!["node 0", "clamped"]),
        // Schemes that take one contact.
        (bar("mass = \"mod\"\nscheme = \"hybrid\"", "0.0", &format!("{}{}", stop("0.0", "lo = -1.0"), stop("1.0", "hi = 1.0"))), "bar.scheme", vec!["reduced schemes", "several contacts"]),
        (bar("scheme = \"nitsche-cn\"", "0.0", &format!("{}{}", stop("0.0", "lo = -1.0"), stop("1.0", "hi = 1.0"))), "bar.scheme", vec!["Nitsche", "several contacts"]),
        (bar("scheme = \"nitsche-cn\"", "0.0", "[obstacle]\nlo = -1.0\n"), "bar.scheme", vec!["Nitsche"]),
        // Keys that would not act next to stops: the default contact's.
        (bar("gap = -0.1", "0.0", &stop("0.0", "lo = -1.0")), "bar.gap", vec!["acts only without [[stop]]"]),
        ("[bar]\nbenchmark = \"bar-dirichlet\"\nelements = 10\nratio = 10.0\n[[stop]]\nx = 0.0\nlo = 0.0\n".to_string(), "stop", vec!["benchmark"]),
        ("[beam]\nscene = \"fig2\"\nstops = [-0.1, 0.1]\n[obstacle]\nlo = -0.1\n".to_string(), "beam.stops", vec!["acts only without"]),
        // Mass treatments that do not fit the contact set.
        (bar("mass = \"mod\"", "0.0", "[obstacle]\nlo = -1.0\n"), "bar.mass", vec!["std or lumped"]),
        (bar("mass = \"mod\"", "0.0", &stop("0.5", "lo = -1.0")), "bar.mass", vec!["node 0", "node 5"]),
        (bar("mass = \"singular\"", "0.0", &format!("{}{}", stop("0.0", "lo = -1.0"), stop("0.5", "lo = -1.0"))), "bar.mass", vec!["singular", "node 5", "allowed"]),
        (bar("mass = \"transfer\"", "0.0", &format!("{}{}", stop("0.0", "lo = -1.0"), stop("0.1", "lo = -1.0"))), "bar.mass", vec!["transfer", "allowed"]),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (text, want, words) in &cases {
        let (f, m) = field_error(text, &here);
        assert_eq!(&f, want, "{text}\n→ {f}: {m}");
        for w in words {
            assert!(m.contains(w), "{text}\n→ {f}: {m:?} lacks {w:?}");
        }
        let p = dir.path().join("scene.toml");
        std::fs::write(&p, text).unwrap();
        let o = bin().args(["check", p.to_str().unwrap()]).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{text}: {err}");
        assert!(err.contains(&format!("error: {f}: ")), "{err}");
    }
}

/// The multi-contact solve's memory (k influence columns of n doubles and
/// the k × k Delassus matrix with its factor) is counted before anything is
/// allocated: `[obstacle]` on a 10⁶-element bar is refused by a cap the mesh
/// alone fits in, naming the obstacle; what fits is accepted.
#[test]
fn contact_memory_is_refused_before_allocating() {
    let cap = Limits { max_memory: 1e9 };
    let big = "[bar]\nelements = 1000000\ndt = 0.01\nt_end = 0.01\ninitial_displacement = 0.0\n";
    assert!(SceneFile::parse(big).unwrap().validate_with(&cap).is_ok(), "the mesh alone fits");
    let (f, m) = field_error(&format!("{big}[obstacle]\nlo = \"-1 - x\"\n"), &cap);
    assert_eq!(f, "obstacle");
    // 10⁶ + 1 columns of 10⁶ + 1 doubles (8.0 TB) and the Delassus matrix (16.0 TB).
    assert!(m.contains("1000001 contacts") && m.contains("24.0 TB") && m.contains("at most") && m.contains("fit"), "{m}");
    let most: f64 = m.split("at most ").nth(1).unwrap().split_whitespace().next().unwrap().parse().unwrap();
    // 8 k n + 16 k² <= 1e9 − 32 MiB − 320 MB: k = 80 for n = 10⁶ + 1.
    let room = 1e9 - 32.0 * 1024.0 * 1024.0 - 320e6;
    let n = 1_000_001.0;
    assert!(8.0 * most * n + 16.0 * most * most <= room && 8.0 * (most + 1.0) * n + 16.0 * (most + 1.0).powi(2) > room, "at most {most}");
    // Stops: counted one by one; two fit where an obstacle everywhere does not.
    let two = format!("{big}[[stop]]\nx = 0.0\nlo = -1.0\n[[stop]]\nx = 0.5\nlo = -1.0\n");
    assert!(SceneFile::parse(&two).unwrap().validate_with(&cap).is_ok());
    // The beam: obstacles at every node of J = 10⁵ (n = 2·10⁵) under a 1 GB cap.
    let (f, m) = field_error("[beam]\nscene = \"fig2\"\nelements = 100000\n[obstacle]\nlo = -0.1\n", &cap);
    assert_eq!(f, "obstacle");
    assert!(m.contains("100000 contacts on 200000 unknowns"), "{m}");
}

/// `check` says where each stop snapped to (within 1e-9 L of a node) and
/// summarises the obstacle; the series of a bar with an obstacle has a
/// column triple per node; old scenes keep their columns.
#[test]
fn check_reports_snapping_and_obstacles() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("s.toml");
    std::fs::write(&p, bar("", "0.0", "[[stop]]\nx = 0.30000000001\nlo = -1.0\n[obstacle]\nhi = \"0.5 + x\"\n")).unwrap();
    let o = bin().args(["check", p.to_str().unwrap()]).output().unwrap();
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(s.contains("contacts: 11") && s.contains("stop.0 x = 0.30000000001 snapped to node 3 (x = 0.3)") && s.contains("intersected with [obstacle]"), "{s}");
    assert!(s.contains("1..=10: [obstacle] at 10 nodes, x = 0 … 1"), "{s}");
    let scene = SceneFile::parse(&std::fs::read_to_string(&p).unwrap()).unwrap().validate().unwrap();
    let Scene::Bar(b) = scene else { panic!("a bar") };
    let set = b.contacts.as_ref().unwrap();
    // Contact order: the stop, then the obstacle's other nodes by increasing x.
    let nodes: Vec<usize> = set.stops.iter().map(|s| s.node).collect();
    assert_eq!(nodes, [3, 0, 1, 2, 4, 5, 6, 7, 8, 9, 10]);
    // Node 3: the stop's lo, the obstacle's hi 0.5 + 0.3.
    assert_eq!((set.stops[0].lo, set.stops[0].hi), (-1.0, 0.5 + 0.3));
    assert!(set.stops[1..].iter().all(|s| s.lo == f64::NEG_INFINITY));
    let out = dir.path().join("o");
    let o = bin().args(["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (header, rows) = series(&out);
    assert_eq!(header.len(), 8 + 3 * 11);
    let bounds: Vec<(f64, f64)> = set.stops.iter().map(|s| (s.lo, s.hi)).collect();
    check_contacts(&header, &rows, &bounds);
    // An old scene: exactly its old columns.
    let q = dir.path().join("old.toml");
    std::fs::write(&q, bar("", "0.0", "")).unwrap();
    let out = dir.path().join("old");
    assert!(bin().args(["run", q.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap().status.success());
    assert!(std::fs::read_to_string(out.join("series.csv")).unwrap().starts_with("n,t,u_contact,v_contact,lambda_t,lambda,energy_t,energy\n"));
}

/// With the beam's penalty contact, `penalty_stiffness` (N/m) is the spring
/// of every stop that gives none of its own (not the library's default of
/// the first stop's spring scaled by the stiffness diagonal): the run equals
/// one built here with that spring at each stop explicitly.
#[test]
fn beam_penalty_stiffness_is_every_stops_spring() {
    use signorini_run::beam::{BeamScene, BeamSetup, Pipe};
    use signorini_schemes::SchemeSpec;
    let text = "[beam]\nscene = \"fig5\"\nelements = 20\nt_end = 0.15\npenalty_stiffness = 2e8\n[[stop]]\nx = 0.7505\nlo = -0.03\nhi = 0.03\nstiffness = 1e7\n[[stop]]\nx = 1.501\nlo = -0.1\nhi = 0.1\n[output]\nevery = 100\n";
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("s.toml");
    std::fs::write(&p, text).unwrap();
    let out = dir.path().join("o");
    let o = bin().args(["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (header, rows) = series(&out);
    let scene = BeamScene::new("test", 20, 5e-6, 0.15, SchemeSpec::penalty(10.0, false)).with_spring(2e8);
    let stops = [Stop { node: 10, lo: -0.03, hi: 0.03, restitution: None, stiffness: Some(1e7) }, Stop { node: 20, lo: -0.1, hi: 0.1, restitution: None, stiffness: Some(2e8) }];
    let mut s = BeamSetup::new(Pipe::paper(), scene).with_stops(stops.to_vec()).build().unwrap().stepper;
    let (c0, c1) = (col(&header, "u_c0"), col(&header, "u_c1"));
    let mut touched = false;
    for (k, r) in rows.iter().enumerate().skip(1) {
        while s.level() < 100 * k {
            s.step().unwrap();
        }
        let (mid, tip) = (s.displacement()[18], s.displacement()[38]);
        assert!((r[c0].unwrap() - mid).abs() <= 1e-12 && (r[c1].unwrap() - tip).abs() <= 1e-12, "row {k}: ({:?}, {:?}) against ({mid}, {tip})", r[c0], r[c1]);
        touched |= tip.abs() > 0.1;
    }
    assert!(touched, "the tip reaches its stop");
}
