//! Every CSV a study writes is one `Output::tables` entry holding exactly
//! what the file holds: the same file names, headers and values (read back
//! with the csv crate, numbers equal within the printed precision).

use signorini_fem::BarMass;
use signorini_run::Benchmark;
use signorini_studies::{convergence, obstacles, stress, Column, Table};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// A fresh folder under the system's temp dir (removed first if present).
fn temp_out(name: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("signorini-studies-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    p
}

/// Every `.csv` under `dir`, relative to it, with `/` separators.
fn csv_files(dir: &Path, prefix: &str, out: &mut BTreeSet<String>) {
    for e in std::fs::read_dir(dir).expect("the output folder exists") {
        let e = e.expect("a folder entry");
        let name = e.file_name().to_string_lossy().to_string();
        if e.file_type().expect("a file type").is_dir() {
            csv_files(&e.path(), &format!("{prefix}{name}/"), out);
        } else if name.ends_with(".csv") {
            out.insert(format!("{prefix}{name}"));
        }
    }
}

/// Half a unit in the last printed digit of `text` (a real as Rust formats
/// it: `1.2345e-3`, `0.1234`, `12`), with a little room for rounding.
fn half_ulp_printed(text: &str) -> f64 {
    let (mantissa, exp) = match text.find(['e', 'E']) {
        Some(i) => (&text[..i], text[i + 1..].parse::<i32>().expect("an exponent")),
        None => (text, 0),
    };
    let decimals = mantissa.find('.').map_or(0, |i| mantissa.len() - i - 1) as i32;
    0.5 * 10f64.powi(exp - decimals) * (1.0 + 1e-12) + f64::MIN_POSITIVE
}

/// Asserts that the CSV files under `out` are exactly `tables`, cell by cell.
fn assert_tables_match_files(out: &Path, tables: &[Table]) {
    let mut on_disk = BTreeSet::new();
    csv_files(out, "", &mut on_disk);
    let listed: BTreeSet<String> = tables.iter().map(|t| t.file.clone()).collect();
    assert_eq!(listed.len(), tables.len(), "a file is listed twice");
    assert_eq!(on_disk, listed, "files written vs tables");
    for t in tables {
        let mut r = csv::Reader::from_path(out.join(&t.file)).expect("the CSV opens");
        let header: Vec<String> = r.headers().expect("a header").iter().map(String::from).collect();
        let names: Vec<String> = t.columns.iter().map(|c| c.0.clone()).collect();
        assert_eq!(header, names, "{}: header", t.file);
        let rows: Vec<csv::StringRecord> = r.records().map(|x| x.expect("a row")).collect();
        for (j, (name, col)) in t.columns.iter().enumerate() {
            assert_eq!(col.len(), rows.len(), "{}: column {name} rows", t.file);
            for (i, row) in rows.iter().enumerate() {
                let cell = &row[j];
                let at = format!("{} row {i} column {name}: file {cell:?}", t.file);
                match col {
                    Column::F64(v) => {
                        if cell.is_empty() || cell == "NaN" {
                            assert!(v[i].is_nan(), "{at}, table {}", v[i]);
                        } else {
                            let x: f64 = cell.parse().unwrap_or_else(|_| panic!("{at}: not a real"));
                            if x.is_infinite() {
                                assert_eq!(x, v[i], "{at}");
                            } else {
                                assert!((x - v[i]).abs() <= half_ulp_printed(cell), "{at}, table {}", v[i]);
                            }
                        }
                    }
                    Column::I64(v) => assert_eq!(cell.parse::<i64>().ok(), Some(v[i]), "{at}"),
                    Column::Str(v) => assert_eq!(cell, v[i], "{at}"),
                }
            }
        }
    }
}

fn f64s<'a>(t: &'a Table, name: &str) -> &'a [f64] {
    match t.column(name) {
        Some(Column::F64(v)) => v,
        other => panic!("{}: column {name} is {other:?}", t.file),
    }
}

/// Least-squares slope of log y against log x, computed here (the oracle).
fn lsq_slope(x: &[f64], y: &[f64]) -> f64 {
    let (lx, ly): (Vec<f64>, Vec<f64>) = x.iter().zip(y).map(|(a, b)| (a.ln(), b.ln())).unzip();
    let n = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn convergence_tables_are_the_files() {
    let out = temp_out("convergence");
    let cfg = convergence::Config {
        benchmark: Benchmark::BarDirichlet,
        schemes: signorini_studies::parse_schemes(&["newmark-cn,ps(1,0.25)".to_string()]).expect("schemes"),
        masses: vec![BarMass::Std, BarMass::Mod],
        levels: vec![10, 20, 40],
        out: Some(out.clone()),
        ..Default::default()
    };
    let calls = std::sync::atomic::AtomicU64::new(0);
    let o = convergence::run(&cfg, &|_, total| {
        assert_eq!(total, 12);
        calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    })
    .expect("the study runs");
    assert_eq!(calls.into_inner(), 12, "one progress call per run");
    assert_eq!(o.tables.len(), 4 + 2, "four pairs, rates, oscillation");
    assert_tables_match_files(&out, &o.tables);
    // rates.csv holds the least-squares slopes of the pairs' own error curves.
    let rates = o.tables.iter().find(|t| t.file == "rates.csv").expect("rates.csv");
    let Some(Column::Str(norm)) = rates.column("norm") else { panic!("norm column") };
    let Some(Column::Str(scheme)) = rates.column("scheme") else { panic!("scheme column") };
    let Some(Column::Str(mass)) = rates.column("mass") else { panic!("mass column") };
    let lsq = f64s(rates, "lsq_rate");
    let mut checked = 0;
    for i in 0..norm.len() {
        let pair = o.tables.iter().find(|t| t.file == format!("{}_{}.csv", scheme[i], mass[i])).expect("the pair's CSV");
        let slope = lsq_slope(f64s(pair, "dx"), f64s(pair, &norm[i]));
        if slope.is_finite() {
            assert!((slope - lsq[i]).abs() <= 5e-5 + 1e-9 * slope.abs(), "{} {} {}: {slope} vs {}", scheme[i], mass[i], norm[i], lsq[i]);
            checked += 1;
        }
    }
    assert!(checked >= 20, "only {checked} rates checked");
    assert!(o.report.starts_with("# Convergence: bar-dirichlet, dx/dt = 10, T = 3, m = [10, 20, 40]"), "{}", o.report);
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn stress_table_is_the_file() {
    let out = temp_out("stress");
    let cfg = stress::Config { out: out.clone(), steps: 100, elements: 4, seed: 7, schemes: None };
    let o = stress::run(&cfg, &|_, _| {}).expect("the study runs");
    assert_tables_match_files(&out, &o.tables);
    let t = &o.tables[0];
    let Some(Column::Str(status)) = t.column("status") else { panic!("status column") };
    // Explicit schemes are refused at dx/dt = 0.1 (dt = 10 h, beyond any CFL limit).
    assert!(status.iter().any(|s| s == "refused-cfl") && status.iter().any(|s| s == "ok"), "{status:?}");
    let Some(Column::I64(seed)) = t.column("seed") else { panic!("seed column") };
    assert!(seed.iter().all(|s| (7000..7007).contains(s)), "seeds 7·1000 + ratio index: {seed:?}");
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn obstacles_tables_are_the_files() {
    let out = temp_out("obstacles");
    let cfg = obstacles::Config { out: out.clone(), t_end: 0.01, dts: vec![1e-4, 5e-5], j: 10, js: vec![5, 10], ..Default::default() };
    let o = obstacles::run(&cfg, &|_, _| {}).expect("the study runs");
    assert_eq!(o.tables.iter().map(|t| t.file.as_str()).collect::<Vec<_>>(), ["dt.csv", "j.csv", "rates.csv"]);
    assert_tables_match_files(&out, &o.tables);
    // The reference row (last) has no errors: empty cells, NaN in the table.
    let dt = &o.tables[0];
    let e = f64s(dt, "tip_linf_err_m");
    assert_eq!(e.len(), 3);
    assert!(e[..2].iter().all(|x| x.is_finite()) && e[2].is_nan(), "{e:?}");
    std::fs::remove_dir_all(&out).ok();
}

/// The CSV and SVG file names in `dir` (not recursive), sorted.
fn study_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).expect("the folder").map(|e| e.expect("entry").file_name().to_string_lossy().to_string()).filter(|f| f.ends_with(".csv") || f.ends_with(".svg")).collect();
    v.sort();
    v
}

/// Issue 22 §5: a second study with fewer schemes into the same folder is
/// refused (naming --out and a stale file) instead of mixing with the first
/// one's files; `clean` removes exactly the stale files; the same study
/// again overwrites its own files.
#[test]
fn convergence_refuses_a_folder_of_another_configuration() {
    let out = temp_out("convergence-mixed");
    let with = |schemes: &str, clean: bool| convergence::Config {
        schemes: signorini_studies::parse_schemes(&[schemes.to_string()]).expect("schemes"),
        masses: vec![BarMass::Std],
        levels: vec![10, 20],
        out: Some(out.clone()),
        clean,
        ..Default::default()
    };
    let plots = ["plot_l2_energy.svg", "plot_l2_l2_u.svg", "plot_linf_l2_u.svg", "plot_linf_v_u.svg"];
    convergence::run(&with("newmark-cn,ps-e1", false), &|_, _| {}).expect("a fresh folder");
    let mut first: Vec<String> = ["newmark-cn_std.csv", "oscillation.csv", "ps-e1_std.csv", "rates.csv"].into_iter().chain(plots).map(String::from).collect();
    first.sort();
    assert_eq!(study_files(&out), first);
    convergence::run(&with("newmark-cn,ps-e1", false), &|_, _| {}).expect("the same study again overwrites its own files");
    let rates_before = std::fs::read_to_string(out.join("rates.csv")).expect("rates");
    match convergence::run(&with("newmark-cn", false), &|_, _| {}) {
        Err(signorini_studies::StudyError::Config { field, message }) => {
            let (field, message) = (signorini_studies::options::Spelling::Flag.spell(&field), message.render(signorini_studies::options::Spelling::Flag));
            assert_eq!(field, "--out", "{message}");
            assert!(message.contains("ps-e1_std.csv") && message.contains("--clean"), "{message}");
        }
        other => panic!("a folder with another configuration's files was accepted: {:?}", other.map(|o| o.out)),
    }
    assert_eq!(std::fs::read_to_string(out.join("rates.csv")).expect("rates"), rates_before, "the refusal wrote nothing");
    convergence::run(&with("newmark-cn", true), &|_, _| {}).expect("--clean");
    let mut second: Vec<String> = ["newmark-cn_std.csv", "oscillation.csv", "rates.csv"].into_iter().chain(plots).map(String::from).collect();
    second.sort();
    assert_eq!(study_files(&out), second, "clean removed the stale pair and kept nothing else");
    // §12: the plots name the norm in words, one panel per mass.
    let svg = std::fs::read_to_string(out.join("plot_l2_l2_u.svg")).expect("plot");
    assert!(svg.contains("L² in time of the L² error of u") && svg.contains("mass std") && !svg.contains("y_label"), "axis in words");
    let _ = std::fs::remove_dir_all(&out);
}
