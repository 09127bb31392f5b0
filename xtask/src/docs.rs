//! `cargo xtask docs`: the generated parts of the user guide, and the
//! checks of the Markdown that MkDocs does not see.
//!
//! * The studies' result tables: rendered from the CSV files in
//!   `data/reference/` into `docs/generated/*.md`, which the guide's pages
//!   include (`--8<-- "generated/…"`, pymdownx.snippets). They are
//!   committed, so they read on GitHub too; `cargo xtask docs --check` (run
//!   by `cargo xtask test`) regenerates them in memory and fails, naming
//!   the files, when a committed one differs: regenerate with
//!   `cargo xtask docs` after a study's reference data changed.
//! * `docs/generated/scene-keys.md`: the reference of every scene key,
//!   read from the scene schema's sources (`crate::scene_keys`), checked the
//!   same way: a field added to `crates/scene` without regenerating fails.
//! * `docs/generated/test-record.md` (test counts and timings) is not
//!   written here but by `cargo xtask test --record`, a measurement that no
//!   check can reproduce.
//! * The module graphs of the crates in `module_graph::ACYCLIC`: `--check`
//!   fails on a cycle among a crate's modules, naming it.
//! * Packages whose manifest turns the unit-test harness off (`test =
//!   false`, `crate::unit_tests`): `--check` fails on a `#[test]` in their
//!   `src/`, which would never run.
//! * README.md and ARCHITECTURE.md (outside the guide, so outside MkDocs'
//!   link validation): at most 200 README lines, the README opening with the
//!   two commands, and every relative link of both resolving to a file, and
//!   to a heading of it when the link has an anchor (GitHub's anchors).

use signorini_studies::work_precision;
use std::collections::{BTreeMap, HashSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Arguments of `cargo xtask docs`.
#[derive(clap::Args)]
pub struct Args {
    /// Do not write: fail if a generated file is missing or differs from
    /// what the reference data gives, or if README.md / ARCHITECTURE.md
    /// break a rule (length, opening, links).
    #[arg(long)]
    check: bool,
}

/// The README's longest allowed length, in lines.
pub const README_MAX_LINES: usize = 200;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `cargo xtask docs [--check]`.
pub fn run_docs(a: Args) -> Result<(), String> {
    let root = root();
    if a.check {
        check(&root)
    } else {
        let readme = readme_with_headline(&root)?;
        if std::fs::read_to_string(root.join("README.md")).ok().as_deref() != Some(readme.as_str()) {
            std::fs::write(root.join("README.md"), &readme).map_err(|e| format!("README.md: {e}"))?;
            eprintln!("rewrote the README's headline table");
        }
        let py = crate::py_studies::render(&root)?;
        if std::fs::read_to_string(root.join(crate::py_studies::FILE)).ok().as_deref() != Some(py.as_str()) {
            std::fs::write(root.join(crate::py_studies::FILE), &py).map_err(|e| format!("{}: {e}", crate::py_studies::FILE))?;
            eprintln!("rewrote the study functions of {}", crate::py_studies::FILE);
        }
        let files = generate(&root)?;
        let dir = root.join("docs/generated");
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for (name, text) in &files {
            let p = dir.join(name);
            std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))?;
        }
        eprintln!("wrote {} files in docs/generated/", files.len());
        crate::crate_graph::write(&root)?;
        check_markdown(&root)
    }
}

/// The checks `cargo xtask test` runs: generated files up to date, README
/// and ARCHITECTURE.md rules.
pub fn check(root: &Path) -> Result<(), String> {
    let files = generate(root)?;
    let mut stale = Vec::new();
    for (name, text) in &files {
        let p = root.join("docs/generated").join(name);
        match std::fs::read_to_string(&p) {
            Ok(old) if old == *text => {}
            Ok(_) => stale.push(format!("docs/generated/{name} differs from its sources (data/reference, or the scene schema for scene-keys.md)")),
            Err(_) => stale.push(format!("docs/generated/{name} is missing")),
        }
    }
    let readme = readme_with_headline(root)?;
    if std::fs::read_to_string(root.join("README.md")).ok().as_deref() != Some(readme.as_str()) {
        stale.push("README.md's headline table differs from data/reference/bar-dirichlet".into());
    }
    let py = crate::py_studies::render(root)?;
    if std::fs::read_to_string(root.join(crate::py_studies::FILE)).ok().as_deref() != Some(py.as_str()) {
        stale.push(format!("the study functions of {} differ from the studies' Configs (crates/studies)", crate::py_studies::FILE));
    }
    stale.extend(crate::crate_graph::check(root)?);
    let harness = crate::unit_tests::check(root)?;
    if !harness.is_empty() {
        return Err(harness.join("; "));
    }
    let cycles = crate::module_graph::check(root)?;
    if !cycles.is_empty() {
        return Err(format!("{}: move what the modules of a cycle share to a module below them", cycles.join("; ")));
    }
    if !stale.is_empty() {
        return Err(format!("{}; regenerate with `cargo xtask docs`", stale.join("; ")));
    }
    check_markdown(root)
}

// ---------------------------------------------------------------------------
// CSV

struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    fn read(path: &Path) -> Result<Table, String> {
        let mut r = csv::Reader::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let header = r.headers().map_err(|e| format!("{}: {e}", path.display()))?.iter().map(String::from).collect();
        let mut rows = Vec::new();
        for rec in r.records() {
            rows.push(rec.map_err(|e| format!("{}: {e}", path.display()))?.iter().map(String::from).collect());
        }
        Ok(Table { header, rows })
    }

    /// The rows as maps column → value.
    fn records(&self) -> Vec<BTreeMap<&str, &str>> {
        self.rows.iter().map(|r| self.header.iter().map(String::as_str).zip(r.iter().map(String::as_str)).collect()).collect()
    }
}

fn num(s: &str) -> Result<f64, String> {
    s.trim().parse::<f64>().map_err(|_| format!("not a number: {s:?}"))
}

fn get<'a>(r: &BTreeMap<&str, &'a str>, k: &str) -> Result<&'a str, String> {
    r.get(k).copied().ok_or_else(|| format!("no column {k}"))
}

fn getf(r: &BTreeMap<&str, &str>, k: &str) -> Result<f64, String> {
    num(get(r, k)?)
}

/// `1.2e-3` style (Rust's `{:.Pe}`), `0` for zero.
fn sci(x: f64, p: usize) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:.p$e}")
    }
}

fn md_row(cells: &[String]) -> String {
    format!("| {} |\n", cells.join(" | "))
}

fn md_head(cells: &[&str]) -> String {
    let mut s = md_row(&cells.iter().map(|c| c.to_string()).collect::<Vec<_>>());
    s.push_str(&format!("|{}\n", "---|".repeat(cells.len())));
    s
}

const NOTE: &str = "<!-- Generated by `cargo xtask docs` from data/reference; do not edit. -->\n";

fn source_line(what: &str) -> String {
    format!("\n<small>Generated from `data/reference/{what}` by `cargo xtask docs`.</small>\n")
}

// ---------------------------------------------------------------------------
// The tables

/// Every generated include file: (name under docs/generated, text).
pub fn generate(root: &Path) -> Result<Vec<(String, String)>, String> {
    let data = root.join("data/reference");
    let mut out = Vec::new();
    let mut add = |name: &str, r: Result<String, String>| -> Result<(), String> {
        let body = r.map_err(|e| format!("docs/generated/{name}: {e}"))?;
        out.push((name.to_string(), format!("{NOTE}{body}")));
        Ok(())
    };
    add("convergence-bar-dirichlet.md", rates_table(&data, "bar-dirichlet"))?;
    add("convergence-bar-mirrored.md", rates_table(&data, "bar-mirrored"))?;
    add("convergence-falling-bar.md", falling_bar(&data))?;
    add("beam-scenes.md", beam_scenes(&data))?;
    add("beam-stability.md", beam_stability(&data))?;
    add("beam-obstacles-rates.md", beam_obstacles(&data))?;
    add("oscillator-orbits.md", oscillator(&data))?;
    add("courant1.md", courant1(&data))?;
    add("long-horizon-masses.md", long_horizon(&data))?;
    add("long-horizon-energy.md", energy_growth(&data))?;
    add("lyapunov.md", lyapunov(&data))?;
    add("beam-statistics.md", beam_statistics(&data))?;
    add("stress.md", stress(&data))?;
    for (bench, quantities) in [("bar-dirichlet", &WP_QUANTITIES[..]), ("bar-neumann-gravity", &WP_QUANTITIES[..]), ("beam-fig2", &WP_QUANTITIES[..1])] {
        for q in quantities {
            add(&format!("wp-{bench}{}.md", q.2), work_precision(&data, bench, q))?;
        }
    }
    add("wp-impact-power.md", impact_power(&data))?;
    // Not from data/reference: the scene schema's own sources.
    let keys = crate::scene_keys::render(root).map_err(|e| format!("docs/generated/scene-keys.md: {e}"))?;
    out.push(("scene-keys.md".into(), format!("<!-- Generated by `cargo xtask docs` from {}; do not edit. -->\n{keys}", crate::scene_keys::SOURCES.join(" and "))));
    Ok(out)
}

const NORMS: [(&str, &str); 7] = [("linf_l2_u", "L∞(L²)"), ("l2_l2_u", "L²(L²)"), ("linf_v_u", "L∞(V)"), ("l2_v_u", "L²(V)"), ("l2_lambda", "L²(λ)"), ("linf_energy", "L∞(E)"), ("l2_energy", "L²(E)")];

/// (scheme, mass) pairs in file order, and rate[(scheme, mass, norm)].
type Rates = (Vec<(String, String)>, BTreeMap<(String, String, String), f64>);

fn rates(dir: &Path) -> Result<Rates, String> {
    let t = Table::read(&dir.join("rates.csv"))?;
    let mut pairs = Vec::new();
    let mut map = BTreeMap::new();
    for r in t.records() {
        let key = (get(&r, "scheme")?.to_string(), get(&r, "mass")?.to_string());
        if !pairs.contains(&key) {
            pairs.push(key.clone());
        }
        map.insert((key.0, key.1, get(&r, "norm")?.to_string()), getf(&r, "lsq_rate")?);
    }
    Ok((pairs, map))
}

fn rate(map: &BTreeMap<(String, String, String), f64>, s: &str, m: &str, norm: &str) -> Result<String, String> {
    map.get(&(s.into(), m.into(), norm.into())).map(|x| format!("{x:.2}")).ok_or_else(|| format!("no rate {s} {m} {norm}"))
}

/// The λ oscillation indicator at the finest level of each pair.
fn tv_finest(dir: &Path) -> Result<BTreeMap<(String, String), f64>, String> {
    let t = Table::read(&dir.join("oscillation.csv"))?;
    let mut best: BTreeMap<(String, String), (f64, f64)> = BTreeMap::new();
    for r in t.records() {
        let key = (get(&r, "scheme")?.to_string(), get(&r, "mass")?.to_string());
        let (m, v) = (getf(&r, "m")?, getf(&r, "lambda_tv_ratio")?);
        let e = best.entry(key).or_insert((m, v));
        if m >= e.0 {
            *e = (m, v);
        }
    }
    Ok(best.into_iter().map(|(k, (_, v))| (k, v)).collect())
}

fn rates_table(data: &Path, bench: &str) -> Result<String, String> {
    let dir = data.join(bench);
    let (pairs, map) = rates(&dir)?;
    let tv = tv_finest(&dir)?;
    let mut head = vec!["scheme", "mass"];
    head.extend(NORMS.iter().map(|n| n.1));
    head.push("λ TV ratio");
    let mut s = md_head(&head);
    for (sc, ma) in &pairs {
        let mut row = vec![sc.clone(), ma.clone()];
        for (n, _) in NORMS {
            row.push(rate(&map, sc, ma, n)?);
        }
        row.push(tv.get(&(sc.clone(), ma.clone())).map(|v| format!("{v:.1}")).unwrap_or_default());
        s.push_str(&md_row(&row));
    }
    s.push_str(&source_line(&format!("{bench}/rates.csv`, `oscillation.csv")));
    Ok(s)
}

fn falling_bar(data: &Path) -> Result<String, String> {
    let (pairs, r1) = rates(&data.join("bar-neumann-gravity-ratio1"))?;
    let (_, r10) = rates(&data.join("bar-neumann-gravity-ratio10"))?;
    let (_, r011) = rates(&data.join("bar-neumann-gravity-0.11-ratio1"))?;
    let mut s =
        md_head(&["scheme", "mass", "dx/dt = 1: L∞(L²)", "L²(L²)", "**L∞(H¹)**", "**L²(H¹)**", "L∞(E)", "dx/dt = 10: L∞(L²)", "**L∞(H¹)**", "**L²(H¹)**", "L∞(E)", "g = 0.11, dx/dt = 1: **L∞(H¹)**"]);
    for (sc, ma) in pairs.iter().filter(|p| ["std", "mod", "mod3"].contains(&p.1.as_str())) {
        let mut row = vec![sc.clone(), ma.clone()];
        for n in ["linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "linf_energy"] {
            row.push(rate(&r1, sc, ma, n)?);
        }
        for n in ["linf_l2_u", "linf_v_u", "l2_v_u", "linf_energy"] {
            row.push(rate(&r10, sc, ma, n)?);
        }
        row.push(rate(&r011, sc, ma, "linf_v_u")?);
        s.push_str(&md_row(&row));
    }
    s.push_str(&source_line("bar-neumann-gravity-ratio1/`, `-ratio10/`, `bar-neumann-gravity-0.11-ratio1/rates.csv"));
    Ok(s)
}

fn beam_scenes(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("beam/scenes.csv"))?;
    let mut s = md_head(&["scene", "contact", "β", "dt (s)", "contact onsets (episodes)", "max \\|ũ(L,t)\\| − 0.1 (m)", "energy balance residual", "wall (s)", "paper, Scilab 2003 (s)", "speed-up"]);
    for r in t.records() {
        s.push_str(&md_row(&[
            get(&r, "scene")?.into(),
            get(&r, "contact")?.into(),
            get(&r, "beta")?.into(),
            get(&r, "dt_s")?.into(),
            format!("{} ({})", get(&r, "impacts")?, get(&r, "contact_episodes")?),
            sci(getf(&r, "max_abs_tip_minus_gap_m")?, 1),
            sci(getf(&r, "balance_residual")?, 1),
            get(&r, "wall_s")?.into(),
            get(&r, "paper_s")?.into(),
            format!("{}×", get(&r, "speedup")?),
        ]));
    }
    s.push_str(&source_line("beam/scenes.csv"));
    Ok(s)
}

fn beam_stability(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("beam/stability.csv"))?;
    let mut s = md_head(&["J", "β", "κ_h", "exact limit dt (s)", "paper's (3.1) with its κ bound (s)", "(3.1) with the exact κ_h (s)"]);
    for r in t.records() {
        let f = |k: &str| -> Result<String, String> {
            let v = get(&r, k)?;
            Ok(num(v).map(|x| sci(x, 4)).unwrap_or_else(|_| v.to_string()))
        };
        s.push_str(&md_row(&[get(&r, "J")?.into(), get(&r, "beta")?.into(), f("kappa_h")?, f("dt_critical_s")?, f("dt_paper_bound_s")?, f("dt_sufficient_exact_kappa_s")?]));
    }
    s.push_str(&source_line("beam/stability.csv"));
    Ok(s)
}

fn beam_obstacles(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("beam-obstacles/rates.csv"))?;
    let mut s = md_head(&["study", "error", "least-squares rate", "last rate"]);
    for r in t.records() {
        s.push_str(&md_row(&[get(&r, "study")?.into(), format!("`{}`", get(&r, "error")?), get(&r, "lsq_rate")?.into(), get(&r, "last_rate")?.into()]));
    }
    s.push_str(&source_line("beam-obstacles/rates.csv"));
    Ok(s)
}

fn oscillator(data: &Path) -> Result<String, String> {
    let orbits = Table::read(&data.join("oscillator/orbits.csv"))?;
    let rates = Table::read(&data.join("oscillator/rates.csv"))?;
    let rates: BTreeMap<String, BTreeMap<&str, &str>> = rates.records().into_iter().map(|r| (r["omega"].to_string(), r)).collect();
    let mut by: Vec<(String, Vec<BTreeMap<&str, &str>>)> = Vec::new();
    for r in orbits.records() {
        let om = get(&r, "omega")?.to_string();
        match by.iter_mut().find(|(o, _)| *o == om) {
            Some((_, v)) => v.push(r),
            None => by.push((om, vec![r])),
        }
    }
    let mut s = md_head(&["Ω", "V exact", "\\|μ\\|", "velocity error, first … last dt", "rate", "phase error", "rate"]);
    for (om, rows) in &by {
        let (first, last) = (&rows[0], &rows[rows.len() - 1]);
        let rt = rates.get(om).ok_or_else(|| format!("no rate for omega {om}"))?;
        s.push_str(&md_row(&[
            om.clone(),
            format!("{:.6}", getf(first, "velocity_exact")?),
            format!("{:.3}", getf(first, "multiplier")?),
            format!("{} … {}", sci(getf(first, "velocity_err")?, 2), sci(getf(last, "velocity_err")?, 2)),
            format!("{:.2}", getf(rt, "velocity_lsq_rate")?),
            format!("{} … {}", sci(getf(first, "phase_err")?, 2), sci(getf(last, "phase_err")?, 2)),
            format!("{:.2}", getf(rt, "phase_lsq_rate")?),
        ]));
    }
    let dts: Vec<&str> = by.first().map(|(_, v)| v.iter().map(|r| r["dt"]).collect()).unwrap_or_default();
    let _ = write!(s, "\nTime steps: {}.\n", dts.join(", "));
    let g = Table::read(&data.join("oscillator/grazing.csv"))?;
    s.push_str("\nGrazing, from the non-impacting steady state:\n\n");
    s.push_str(&md_head(&["Ω − Ω_g", "impacts", "first impact velocity"]));
    for r in g.records() {
        let v = get(&r, "first_velocity")?;
        s.push_str(&md_row(&[get(&r, "offset")?.into(), get(&r, "impacts")?.into(), if v == "NaN" { "none".into() } else { sci(num(v)?, 2) }]));
    }
    s.push_str(&source_line("oscillator/orbits.csv`, `rates.csv`, `grazing.csv"));
    Ok(s)
}

fn courant1(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("courant1/courant1.csv"))?;
    let mut s = md_head(&["benchmark", "m", "start", "dt", "first nodal error > 1e-10 (t, x: size)", "exact release", "largest nodal error", "L∞(0,T;L²)"]);
    for r in t.records() {
        let first = if get(&r, "first_error_t")?.is_empty() {
            "none: exact throughout".to_string()
        } else {
            format!("t = {}, x = {}: {}", get(&r, "first_error_t")?, get(&r, "first_error_x")?, get(&r, "first_error")?)
        };
        s.push_str(&md_row(&[
            get(&r, "benchmark")?.into(),
            get(&r, "m")?.into(),
            get(&r, "start")?.into(),
            get(&r, "dt")?.into(),
            first,
            get(&r, "exact_release_t")?.into(),
            sci(getf(&r, "max_nodal_error")?, 1),
            sci(getf(&r, "linf_l2_u")?, 3),
        ]));
    }
    s.push_str(&source_line("courant1/courant1.csv"));
    Ok(s)
}

/// Rows grouped by (scheme, mass) in file order.
/// Rows of a table grouped by the values of some columns.
type Group<'a> = (Vec<String>, Vec<BTreeMap<&'a str, &'a str>>);

fn grouped<'a>(t: &'a Table, keys: &[&str]) -> Result<Vec<Group<'a>>, String> {
    let mut by: Vec<Group<'a>> = Vec::new();
    for r in t.records() {
        let k = keys.iter().map(|k| get(&r, k).map(String::from)).collect::<Result<Vec<_>, _>>()?;
        match by.iter_mut().find(|(o, _)| *o == k) {
            Some((_, v)) => v.push(r),
            None => by.push((k, vec![r])),
        }
    }
    Ok(by)
}

fn long_horizon(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("long-horizon/summary.csv"))?;
    let by = grouped(&t, &["scheme", "mass"])?;
    let ms: Vec<&str> = by.first().map(|(_, v)| v.iter().map(|r| r["m"]).collect()).unwrap_or_default();
    let ms = ms.join(" / ");
    let h1 = format!("L∞(0,T;L²), m = {ms}");
    let h2 = format!("impact drift per period, m = {ms}");
    let first_m = by.first().map(|(_, v)| v[0]["m"]).unwrap_or("");
    let h3 = format!("energy at T (exact 0.125), m = {first_m}");
    let mut s = md_head(&["scheme", "mass", &h1, &h2, &h3]);
    for (k, rows) in &by {
        let l: Vec<String> = rows.iter().map(|r| getf(r, "linf_l2_u").map(|x| format!("{x:.3}"))).collect::<Result<_, _>>()?;
        let d: Vec<String> = rows.iter().map(|r| getf(r, "mean_drift_per_period").map(|x| sci(x, 1))).collect::<Result<_, _>>()?;
        s.push_str(&md_row(&[k[0].clone(), k[1].clone(), l.join(" / "), d.join(" / "), format!("{:.3}", getf(&rows[0], "final_energy")?)]));
    }
    s.push_str(&source_line("long-horizon/summary.csv"));
    Ok(s)
}

fn energy_growth(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("long-horizon/energy_growth.csv"))?;
    let by = grouped(&t, &["scheme", "mass"])?;
    let ratios: Vec<String> = by.first().map(|(_, v)| v.iter().map(|r| format!("dx/dt = {}", r["dx_dt"])).collect()).unwrap_or_default();
    let mut head = vec!["scheme", "mass"];
    head.extend(ratios.iter().map(String::as_str));
    let mut s = md_head(&head);
    for (k, rows) in &by {
        let mut row = vec![k[0].clone(), k[1].clone()];
        for r in rows {
            let stopped = get(r, "t_stopped")?;
            let max = getf(r, "max_ratio")?;
            let over = get(r, "t_ratio_2")?;
            let mut cell = if !stopped.is_empty() {
                format!("**10⁶ guard at t = {:.0}**", num(stopped)?)
            } else if max > 2.0 {
                format!("**{}**", if max < 100.0 { format!("{max:.3}") } else { format!("{max:.3e}") })
            } else {
                format!("{max:.3}")
            };
            if !over.is_empty() {
                let _ = write!(cell, " (> 2 from t = {:.2})", num(over)?);
            }
            row.push(cell);
        }
        s.push_str(&md_row(&row));
    }
    s.push_str(&source_line("long-horizon/energy_growth.csv"));
    Ok(s)
}

fn lyapunov(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("lyapunov/lyapunov.csv"))?;
    let mut s = md_head(&["scene", "dt (s)", "J", "λ_max (1/s), 95 % interval", "e-folding time", "horizon to 1 mm"]);
    for r in t.records() {
        let l = getf(&r, "lambda_max")?;
        let h = get(&r, "horizon_s")?;
        let undecided = getf(&r, "ci_low")? <= 0.0 && 0.0 <= getf(&r, "ci_high")?;
        s.push_str(&md_row(&[
            get(&r, "scene")?.into(),
            get(&r, "dt")?.into(),
            get(&r, "elements")?.into(),
            format!("{} [{}, {}]", sig3(l), sig3(getf(&r, "ci_low")?), sig3(getf(&r, "ci_high")?)),
            // An interval that contains 0 leaves the sign of λ, and so the
            // horizon, undecided.
            if undecided {
                "—".into()
            } else if l > 0.0 {
                format!("{:.2} ms", 1e3 / l)
            } else {
                "—".into()
            },
            if undecided {
                "undecided (the interval contains 0)".into()
            } else if h.is_empty() {
                "∞".into()
            } else {
                format!("{:.2} s", num(h)?)
            },
        ]));
    }
    let o = Table::read(&data.join("lyapunov/oscillator.csv"))?;
    s.push_str("\nThe impact oscillator's period-1 orbits against the exact Floquet exponent `ln|μ₁| Ω/2π`:\n\n");
    s.push_str(&md_head(&["Ω", "λ_max, 95 % interval", "exact", "\\|μ₁\\|"]));
    for r in o.records() {
        s.push_str(&md_row(&[
            get(&r, "omega")?.into(),
            format!("{} [{}, {}]", sig3(getf(&r, "lambda_max")?), sig3(getf(&r, "ci_low")?), sig3(getf(&r, "ci_high")?)),
            sig3(getf(&r, "lambda_exact")?),
            get(&r, "multiplier")?.into(),
        ]));
    }
    s.push_str(&source_line("lyapunov/lyapunov.csv`, `oscillator.csv"));
    Ok(s)
}

/// Three significant digits, fixed notation.
fn sig3(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let d = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.d$}")
}

fn beam_statistics(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("beam-statistics/statistics.csv"))?;
    // One table per scene and scheme (the scheme named when there are several).
    let by = grouped(&t, &["scene", "scheme", "statistic"])?;
    let several = by.iter().any(|(k, _)| k[1] != by[0].0[1]);
    let mut s = String::new();
    let mut scene = String::new();
    for (k, rows) in &by {
        let title = if several { format!("{}, {}", k[0], k[1]) } else { k[0].clone() };
        if title != scene {
            scene = title;
            // Columns: the (J, dt) levels of this scene, grouped by J.
            let mut js: Vec<&str> = Vec::new();
            for r in rows {
                if !js.contains(&r["elements"]) {
                    js.push(r["elements"]);
                }
            }
            let heads: Vec<String> = js.iter().map(|j| format!("J = {j}: dt = {}", rows.iter().filter(|r| r["elements"] == *j).map(|r| r["dt"]).collect::<Vec<_>>().join(" / "))).collect();
            let mut head = vec!["statistic"];
            head.extend(heads.iter().map(String::as_str));
            head.extend(["interval (±)", "largest difference to the finest", "intervals overlapping the finest's", "expected"]);
            let _ = write!(s, "{}**{scene}**\n\n", if s.is_empty() { "" } else { "\n" });
            s.push_str(&md_head(&head));
        }
        let mut js: Vec<&str> = Vec::new();
        for r in rows {
            if !js.contains(&r["elements"]) {
                js.push(r["elements"]);
            }
        }
        let mut row = vec![format!("`{}`", k[2])];
        for j in &js {
            let v: Vec<String> = rows.iter().filter(|r| r["elements"] == *j).map(|r| getf(r, "mean").map(sig3)).collect::<Result<_, _>>()?;
            row.push(v.join(" / "));
        }
        let mut lo = f64::INFINITY;
        let mut hi = 0f64;
        let mut diff = 0f64;
        let mut overlap = 0;
        for r in rows {
            let w = (getf(r, "ci_high")? - getf(r, "ci_low")?) / 2.0;
            lo = lo.min(w);
            hi = hi.max(w);
            diff = diff.max(getf(r, "rel_diff")?.abs());
            overlap += usize::from(get(r, "within_ci")? == "1");
        }
        row.push(format!("{}–{}", sig3(lo), sig3(hi)));
        row.push(format!("{:.1} %", 100.0 * diff));
        // A fact, not a verdict: how many levels (the finest among them)
        // agree with the finest within the intervals.
        row.push(format!("{overlap} of {}", rows.len()));
        row.push(get(&rows[0], "kind")?.into());
        s.push_str(&md_row(&row));
    }
    s.push_str(&source_line("beam-statistics/statistics.csv"));
    Ok(s)
}

fn stress(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("stress/stress.csv"))?;
    let by = grouped(&t, &["scheme"])?;
    let mut s = md_head(&["scheme", "largest E/E₀ (mass, dx/dt)", "worst relative energy change", "blow-ups", "refused (CFL)"]);
    for (k, rows) in &by {
        let mut best: Option<(f64, &str, &str)> = None;
        let mut drift = 0f64;
        let (mut blow, mut refused) = (0, 0);
        for r in rows {
            match get(r, "status")? {
                "ok" => {}
                "refused-cfl" => {
                    refused += 1;
                    continue;
                }
                _ => blow += 1,
            }
            if let Ok(g) = getf(r, "max_growth") {
                if best.is_none_or(|b| g > b.0) {
                    best = Some((g, r["mass"], r["ratio"]));
                }
            }
            if let Ok(d) = getf(r, "max_rel_drift") {
                drift = drift.max(d);
            }
        }
        let best = best.map(|(g, m, r)| format!("{g:.3} ({m}, {r})")).unwrap_or_else(|| "—".into());
        s.push_str(&md_row(&[k[0].clone(), best, format!("{drift:.2e}"), format!("{blow} of {}", rows.len()), refused.to_string()]));
    }
    s.push_str(&source_line("stress/stress.csv"));
    Ok(s)
}

const HEADLINE_OPEN: &str = "<!-- generated:headline (cargo xtask docs, from data/reference/bar-dirichlet) -->";
const HEADLINE_CLOSE: &str = "<!-- /generated:headline -->";

/// README.md with the table between its headline markers rendered from
/// `data/reference/bar-dirichlet` (a few columns of the papers' study).
pub fn readme_with_headline(root: &Path) -> Result<String, String> {
    let readme = std::fs::read_to_string(root.join("README.md")).map_err(|e| format!("README.md: {e}"))?;
    let (Some(i), Some(j)) = (readme.find(HEADLINE_OPEN), readme.find(HEADLINE_CLOSE)) else {
        return Err(format!("README.md: the markers {HEADLINE_OPEN} … {HEADLINE_CLOSE} are missing"));
    };
    let dir = root.join("data/reference/bar-dirichlet");
    let (pairs, map) = rates(&dir)?;
    let tv = tv_finest(&dir)?;
    let cols = [("linf_l2_u", "L∞(L²)"), ("linf_v_u", "L∞(V)"), ("l2_lambda", "L²(λ)"), ("linf_energy", "L∞(E)")];
    let mut head = vec!["scheme", "mass"];
    head.extend(cols.iter().map(|c| c.1));
    head.push("λ TV ratio");
    let mut t = md_head(&head);
    for (sc, ma) in &pairs {
        let mut row = vec![sc.clone(), ma.clone()];
        for (n, _) in cols {
            row.push(rate(&map, sc, ma, n)?);
        }
        row.push(tv.get(&(sc.clone(), ma.clone())).map(|v| format!("{v:.1}")).unwrap_or_default());
        t.push_str(&md_row(&row));
    }
    Ok(format!("{}{HEADLINE_OPEN}\n{t}{}", &readme[..i], &readme[j..]))
}

/// Work–precision quantities: (column, name, file suffix, targets).
type WpQuantity = (&'static str, &'static str, &'static str, [f64; 5]);
const WP_QUANTITIES: [WpQuantity; 3] = [
    ("l2_l2_u", "u in L²(0,T;L²)", "", [3e-2, 1e-2, 3e-3, 1e-3, 3e-4]),
    ("linf_v_u", "strain: u in L∞(0,T;V)", "-strain", [3e-1, 1e-1, 3e-2, 1e-2, 3e-3]),
    ("l2_lambda", "contact force λ in L²(0,T)", "-force", [3e-1, 1e-1, 3e-2, 1e-2, 3e-3]),
];

/// The least-squares slope of ln e against ln d over the positive, finite points.
fn lsq_rate(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points.iter().filter(|(d, e)| *d > 0.0 && *e > 0.0 && e.is_finite()).map(|(d, e)| (d.ln(), e.ln())).collect();
    if pts.len() < 2 {
        return f64::NAN;
    }
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>()
}

struct WpPoint {
    label: String,
    m: usize,
    dt: f64,
    cost: work_precision::Cost,
    errors: BTreeMap<&'static str, f64>,
}

fn wp_points(data: &Path, bench: &str) -> Result<Vec<WpPoint>, String> {
    let t = Table::read(&data.join("work-precision/work_precision.csv"))?;
    let beam = bench.starts_with("beam");
    let mut pts = Vec::new();
    for r in t.records().into_iter().filter(|r| r.get("benchmark") == Some(&bench)) {
        let (degree, modes) = (getf(&r, "degree")? as usize, getf(&r, "modes")? as usize);
        let mut label = format!("{} {}", get(&r, "scheme")?, get(&r, "mass")?);
        if degree > 1 && !beam {
            let _ = write!(label, " P{degree}");
        }
        if modes > 0 {
            let _ = write!(label, " r={modes}");
        }
        let val = |k: &str| num(r.get(k).copied().unwrap_or("")).unwrap_or(f64::NAN);
        let errors = WP_QUANTITIES.iter().map(|q| (q.0, if beam { val("tip_err") } else { val(q.0) })).collect();
        // The cost's median and range (a file without the range: one run).
        let wall = getf(&r, "wall_s")?;
        let opt = |k: &str| num(r.get(k).copied().unwrap_or("")).ok();
        let cost = match (opt("step_s_min"), opt("step_s_max"), opt("repeats")) {
            (Some(min), Some(max), Some(n)) => work_precision::Cost { median: wall, min, max, n: n as usize },
            _ => work_precision::Cost::once(wall),
        };
        pts.push(WpPoint { label, m: getf(&r, "m")? as usize, dt: getf(&r, "dt")?, cost, errors });
    }
    Ok(pts)
}

/// The cheapest configurations reaching each target error, as the study's
/// report gives them (`work_precision::cheapest_table`, one code for both):
/// per configuration its cheapest level at or below the target, ranked by
/// median cost, ties where the cost ranges overlap, and where each cheapest
/// one holds.
fn work_precision(data: &Path, bench: &str, q: &WpQuantity) -> Result<String, String> {
    let pts = wp_points(data, bench)?;
    let beam = bench.starts_with("beam");
    let mut keys: Vec<&str> = pts.iter().map(|p| p.label.as_str()).collect();
    keys.dedup();
    // Configurations whose error does not fall with m (rate < 0.1, round-off aside).
    let failing = |label: &str| -> String {
        if beam {
            return String::new();
        }
        let qs: Vec<&str> = WP_QUANTITIES
            .iter()
            .filter(|w| {
                let e: Vec<(f64, f64)> = pts.iter().filter(|p| p.label == label).map(|p| (1.0 / p.m as f64, p.errors[w.0])).collect();
                let rate = lsq_rate(&e);
                e.len() >= 2 && e.iter().any(|x| x.1 > 1e-7) && !(rate >= 0.1)
            })
            .map(|w| w.1)
            .collect();
        if qs.is_empty() {
            String::new()
        } else {
            format!(" (does not converge in {})", qs.join(", "))
        }
    };
    let entries: Vec<work_precision::Entry> =
        pts.iter().map(|p| work_precision::Entry { label: p.label.clone(), at: if beam { format!("dt={:e}", p.dt) } else { format!("m={}", p.m) }, cost: p.cost, error: p.errors[q.0] }).collect();
    let mut s = work_precision::cheapest_table(bench, &entries, &q.3, &failing);
    if let Some(n) = pts.first().map(|p| p.cost.n).filter(|&n| n > 1) {
        let _ = write!(s, "\nTimings of the machine that wrote the reference: median of {n} runs [min, max]; configurations whose ranges overlap are a tie.\n");
    }
    if !beam && q.2 == "-force" {
        let mut listed: Vec<String> = keys.iter().map(|k| (k, failing(k))).filter(|(_, f)| !f.is_empty()).map(|(k, f)| format!("{k}{f}")).collect();
        listed.sort();
        listed.dedup();
        if !listed.is_empty() {
            let _ = write!(s, "\nConfigurations whose error does not fall with m in some quantity (least-squares rate below 0.1): {}.\n", listed.join("; "));
        }
    }
    s.push_str(&source_line("work-precision/work_precision.csv"));
    Ok(s)
}

fn impact_power(data: &Path) -> Result<String, String> {
    let t = Table::read(&data.join("work-precision/work_precision.csv"))?;
    let mut s = md_head(&["dt (s)", "impact power [95 % interval]", "±", "error against the reference", "wall (s)"]);
    for r in t.records().into_iter().filter(|r| !r.get("impact_power").copied().unwrap_or("").is_empty()) {
        let (mean, lo, hi) = (getf(&r, "impact_power")?, getf(&r, "impact_power_low")?, getf(&r, "impact_power_high")?);
        s.push_str(&md_row(&[
            format!("{:e}", getf(&r, "dt")?),
            format!("{mean:.4} [{lo:.4}, {hi:.4}]"),
            format!("{:.1} %", 100.0 * (hi - lo) / 2.0 / mean.abs()),
            format!("{:+.2} %", 100.0 * getf(&r, "impact_power_rel_err")?),
            format!("{:.2}", getf(&r, "wall_s")?),
        ]));
    }
    s.push_str(&source_line("work-precision/work_precision.csv"));
    Ok(s)
}

// ---------------------------------------------------------------------------
// README.md and ARCHITECTURE.md

/// GitHub's anchor of a heading: lower case, everything but letters,
/// digits, `-`, `_` and spaces dropped, spaces to `-`.
pub fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of a Markdown file's headings (outside code fences; a
/// repeated heading gets `-1`, `-2`, … as on GitHub).
pub fn anchors(text: &str) -> HashSet<String> {
    let mut out = HashSet::new();
    let mut fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
            continue;
        }
        if fence || !line.starts_with('#') {
            continue;
        }
        let h = line.trim_start_matches('#');
        if !h.starts_with(' ') {
            continue;
        }
        let base = slug(h);
        let mut a = base.clone();
        let mut k = 0;
        while out.contains(&a) {
            k += 1;
            a = format!("{base}-{k}");
        }
        out.insert(a);
    }
    out
}

/// The targets of the inline links `[text](target)` outside code.
pub fn links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
            continue;
        }
        if fence {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let tail = &rest[i + 2..];
            let Some(j) = tail.find(')') else { break };
            out.push(tail[..j].to_string());
            rest = &tail[j..];
        }
    }
    out
}

/// Every relative link of `file` (a path under `root`) resolves.
pub fn check_links(root: &Path, file: &str) -> Vec<String> {
    let path = root.join(file);
    let Ok(text) = std::fs::read_to_string(&path) else { return vec![format!("{file}: cannot read")] };
    let base = path.parent().unwrap_or(root).to_path_buf();
    let mut bad = Vec::new();
    for l in links(&text) {
        if l.contains("://") || l.starts_with("mailto:") {
            continue;
        }
        let (target, anchor) = match l.split_once('#') {
            Some((t, a)) => (t, Some(a)),
            None => (l.as_str(), None),
        };
        let p = if target.is_empty() { path.clone() } else { base.join(target) };
        if !p.exists() {
            bad.push(format!("{file}: link {l}: no file {target}"));
            continue;
        }
        if let Some(a) = anchor {
            let t = std::fs::read_to_string(&p).unwrap_or_default();
            if !anchors(&t).contains(a) {
                bad.push(format!("{file}: link {l}: no heading with the anchor #{a} in {}", if target.is_empty() { file } else { target }));
            }
        }
    }
    bad
}

/// README.md's rules, and the links of README.md and ARCHITECTURE.md.
pub fn check_markdown(root: &Path) -> Result<(), String> {
    let mut bad = Vec::new();
    let readme = std::fs::read_to_string(root.join("README.md")).map_err(|e| format!("README.md: {e}"))?;
    bad.extend(readme_rules(&readme));
    let test = std::fs::read_to_string(root.join("tests/it/readme.rs")).unwrap_or_default();
    bad.extend(readme_rust_is_tested(&readme, &test));
    for f in ["README.md", "ARCHITECTURE.md"] {
        bad.extend(check_links(root, f));
    }
    if bad.is_empty() {
        Ok(())
    } else {
        Err(bad.join("\n"))
    }
}

/// The README's ```rust block is, line for line (indentation aside), the
/// code between the markers of `tests/it/readme.rs`, which compiles and runs it.
pub fn readme_rust_is_tested(readme: &str, test: &str) -> Vec<String> {
    let block: Vec<&str> = readme.lines().skip_while(|l| l.trim() != "```rust").skip(1).take_while(|l| l.trim() != "```").map(str::trim).collect();
    let tested: Vec<&str> = test.lines().skip_while(|l| l.trim() != "// README quick start: begin").skip(1).take_while(|l| l.trim() != "// README quick start: end").map(str::trim).collect();
    if block.is_empty() || block != tested {
        vec!["README.md: its ```rust quick start differs from the code between the markers of tests/it/readme.rs (which compiles and runs it): change both".into()]
    } else {
        Vec::new()
    }
}

/// At most [`README_MAX_LINES`] lines, and the README opens with the two
/// commands: its first code block, within its first 8 lines (the title and
/// the section heading before it), is `cargo xtask convergence` then
/// `cargo xtask test`.
pub fn readme_rules(readme: &str) -> Vec<String> {
    let mut bad = Vec::new();
    let n = readme.lines().count();
    if n > README_MAX_LINES {
        bad.push(format!("README.md: {n} lines; at most {README_MAX_LINES} (move the rest into the guide, docs/)"));
    }
    let lines: Vec<&str> = readme.lines().collect();
    let open = lines.iter().position(|l| l.starts_with("```"));
    let ok = open.is_some_and(|i| {
        let block: Vec<&str> = lines[i + 1..].iter().take_while(|l| !l.starts_with("```")).map(|l| l.trim()).collect();
        i < 8 && block.len() >= 2 && block[0].starts_with("cargo xtask convergence") && block[1].starts_with("cargo xtask test")
    });
    if !ok {
        bad.push("README.md: it must open with the two commands: its first code block, within its first 8 lines,, `cargo xtask convergence` then `cargo xtask test`".into());
    }
    bad
}
