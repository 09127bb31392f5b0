//! The sweep's folder: its files' columns, rows and plots, the state a
//! follow run resumes from, and [`merge`] of shards.

use crate::error::{io, Error, SweepError};
use crate::setup::Manifest;
use crate::simulate::RunRows;
use signorini_plot::{impact_map, scatter, thin, Chart, Scale, Series, Style};
use signorini_run::text::num;
use signorini_scene::io_reason;
use std::fmt::Write as _;
use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

/// A displacement and velocity to start a run from (a followed sweep).
pub(crate) type StartState = (Vec<f64>, Vec<f64>);

/// Header of `sweep.csv`.
pub const SWEEP_COLUMNS: &str = "param,run,t,displacement,velocity,phase";

/// Header of `impacts.csv` in a sweep folder.
pub const IMPACT_COLUMNS: &str = "param,run,stop,t,phase,velocity,impulse,duration";

/// The files a sweep writes.
pub const SWEEP_FILES: [&str; 6] = ["sweep.csv", "summary.csv", "impacts.csv", "bifurcation.svg", "impact_map.svg", "sweep.toml"];

/// The rows of one run, formatted: `param,run,<values>[,param2]`.
pub(crate) fn rows_text(value: (f64, Option<f64>), run: usize, r: &RunRows) -> (String, String, String) {
    let (p, p2) = value;
    let tail = p2.map_or(String::new(), |v| format!(",{}", num(v)));
    let p = num(p);
    let mut sw = String::new();
    for row in &r.poincare {
        let _ = writeln!(sw, "{p},{run},{},{},{},{}{tail}", row[0], row[1], row[2], row[3]);
    }
    let mut im = String::new();
    for (stop, v) in &r.impacts {
        let _ = writeln!(im, "{p},{run},{stop},{},{},{},{},{}{tail}", v[0], v[1], v[2], v[3], v[4]);
    }
    let su = format!("{p},{run},{},{},{}{tail}\n", r.summary, r.steps, r.status);
    (sw, im, su)
}

/// The headers of `sweep.csv`, `impacts.csv` (unless `--no-impacts`),
/// `summary.csv` (`,param2` last for a map).
pub(crate) fn headers(map: bool, impacts: bool) -> Vec<(&'static str, String)> {
    let tail = if map { ",param2" } else { "" };
    let mut h = vec![("sweep.csv", format!("{SWEEP_COLUMNS}{tail}")), ("summary.csv", format!("{}{tail}", summary_header()))];
    if impacts {
        h.insert(1, ("impacts.csv", format!("{IMPACT_COLUMNS}{tail}")));
    }
    h
}

/// Reads the complete lines of a file (a last line without its newline,
/// cut by a kill, is dropped).
pub(crate) fn complete_lines(p: &Path) -> Result<Vec<String>, Error> {
    let text = std::fs::read_to_string(p).map_err(|e| io(p, e))?;
    Ok(text.split_inclusive('\n').filter(|l| l.ends_with('\n')).map(|l| l.trim_end_matches('\n').to_string()).collect())
}

/// The run index (second column) of a data row.
pub(crate) fn run_of(line: &str) -> Option<usize> {
    line.split(',').nth(1)?.parse().ok()
}

/// The open output files of a sweep.
pub(crate) struct Outputs {
    pub(crate) sweep: File,
    pub(crate) impacts: Option<File>,
    pub(crate) summary: File,
}

impl Outputs {
    pub(crate) fn append(dir: &Path, name: &str) -> Result<File, Error> {
        let p = dir.join(name);
        OpenOptions::new().append(true).open(&p).map_err(|e| io(&p, e))
    }
}

/// Whether a `summary.csv` data row is of a run that failed (its status
/// is not `ok`; a map's row ends with `param2` after it).
pub(crate) fn failed_row(line: &str, map: bool) -> bool {
    let line = if map { line.rsplit_once(',').map_or(line, |(a, _)| a) } else { line };
    !line.ends_with(",ok")
}

pub(crate) fn write_state(p: &Path, state: Option<&(Vec<f64>, Vec<f64>)>) -> Result<(), Error> {
    let mut s = String::new();
    if let Some((u, v)) = state {
        let join = |x: &[f64]| x.iter().map(|a| format!("{a:?}")).collect::<Vec<_>>().join(",");
        let _ = writeln!(s, "{}\n{}", join(u), join(v));
    }
    std::fs::write(p, s).map_err(|e| io(p, e))
}

pub(crate) fn read_state(p: &Path) -> Result<Option<StartState>, Error> {
    let text = std::fs::read_to_string(p).map_err(|e| io(p, e))?;
    let mut lines = text.lines();
    let parse = |l: Option<&str>| -> Option<Vec<f64>> { l.map(|l| l.split(',').filter_map(|x| x.parse().ok()).collect()) };
    Ok(match (parse(lines.next()), parse(lines.next())) {
        (Some(u), Some(v)) if !u.is_empty() && u.len() == v.len() => Some((u, v)),
        _ => None,
    })
}

/// `summary.csv`'s header.
pub fn summary_header() -> String {
    format!("param,run,{},steps,status", signorini_run::vibro::Summary::csv_header())
}

/// Draws `bifurcation.svg` and `impact_map.svg` from the folder's CSVs.
pub(crate) fn plots(dir: &Path) -> Result<Vec<String>, Error> {
    let mut notes = Vec::new();
    let col = |l: &str, i: usize| l.split(',').nth(i).and_then(|x| x.parse::<f64>().ok()).unwrap_or(f64::NAN);
    let sweep = complete_lines(&dir.join("sweep.csv"))?;
    let (pts, title) = thin(sweep.iter().skip(1).map(|l| (col(l, 0), col(l, 3))).collect(), "bifurcation diagram: Poincaré displacement", "samples");
    // The x axis names the swept parameter, as the manifest records it.
    let param = std::fs::read_to_string(dir.join("sweep.toml"))
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|m| m.get("param").and_then(|p| p.as_str()).map(str::to_string))
        .unwrap_or_else(|| "parameter".into());
    let chart = Chart { title: &title, x_label: &param, y_label: "displacement", scale: Scale::Linear, size: (900, 600) };
    let radius = if pts.len() > 20_000 { 1 } else { 2 };
    match scatter(&chart, &[Series { label: "Poincaré samples".into(), points: pts, reference: false, style: Style::default() }], radius) {
        Ok(svg) => std::fs::write(dir.join("bifurcation.svg"), svg).map_err(|e| io(&dir.join("bifurcation.svg"), e))?,
        Err(e) => notes.push(format!("note: bifurcation.svg not written: {e}")),
    }
    if !dir.join("impacts.csv").exists() {
        return Ok(notes);
    }
    let impacts = complete_lines(&dir.join("impacts.csv"))?;
    let points = impacts.iter().skip(1).map(|l| {
        let stop = col(l, 2);
        (if stop.is_finite() && stop >= 0.0 { stop as usize } else { 0 }, col(l, 4), col(l, 5))
    });
    match impact_map(points, |n| if n > 20_000 { 1 } else { 2 }) {
        Ok(svg) => std::fs::write(dir.join("impact_map.svg"), svg).map_err(|e| io(&dir.join("impact_map.svg"), e))?,
        Err(e) => notes.push(format!("note: impact_map.svg not written: {e} (no impacts in the record windows)")),
    }
    Ok(notes)
}

/// Merges shard folders into `out`: the files an unsharded sweep writes,
/// byte for byte. Refuses shards of different sweeps (ids), missing or
/// repeated shards, and incomplete ones.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<Vec<String>, Error> {
    let bad = |m: String| Error::from(SweepError::Folder(m));
    if shards.is_empty() {
        return Err(bad("merge: give the shard folders".into()));
    }
    let mut found: Vec<(usize, usize, usize, usize, &PathBuf, String, Manifest)> = Vec::new();
    for d in shards {
        let p = d.join("sweep.toml");
        let text = std::fs::read_to_string(&p)
            .map_err(|e| bad(format!("{} is not a shard folder ({}: {}): give the folders `signorini sweep --shard I/N` wrote", d.display(), p.display(), io_reason(&e))))?;
        let m = Manifest::parse(&text).map_err(|e| bad(format!("{}: not a sweep manifest ({})", p.display(), e.message().trim_end())))?;
        let [i, n] = m.shard.ok_or_else(|| bad(format!("{} is not a shard (no shard = [I, N] in its sweep.toml)", d.display())))?;
        let [r0, r1] = m.runs.ok_or_else(|| bad(format!("{}: no runs range", p.display())))?;
        found.push((i, n, r0, r1, d, m.id.clone(), m));
    }
    let (id0, n0) = (found[0].5.clone(), found[0].1);
    if let Some(f) = found.iter().find(|f| f.5 != id0) {
        return Err(bad(format!("{} belongs to sweep {}, {} to sweep {}: shards of different sweeps are not merged", f.4.display(), f.5, found[0].4.display(), id0)));
    }
    if let Some(f) = found.iter().find(|f| f.1 != n0) {
        return Err(bad(format!("{} is a shard of {} and {} of {}: not one sharding", f.4.display(), f.1, found[0].4.display(), n0)));
    }
    found.sort_by_key(|f| f.0);
    for (k, f) in found.iter().enumerate() {
        if f.0 != k {
            let what = if k > 0 && found[k - 1].0 == f.0 { format!("shard {} is given twice", f.0) } else { format!("shard {k} of {n0} is missing") };
            return Err(bad(format!("merge: {what}")));
        }
    }
    if found.len() != n0 {
        return Err(bad(format!("merge: shard {} of {n0} is missing ({} given)", found.len(), found.len())));
    }
    std::fs::create_dir_all(out).map_err(|source| Error::OutFolder { path: out.to_path_buf(), source })?;
    if let Some(f) = SWEEP_FILES.iter().find(|f| out.join(f).exists()) {
        return Err(bad(format!("{} holds a sweep's files ({f}): choose another --out", out.display())));
    }
    let manifest0 = &found[0].6;
    let (map, impacts) = (manifest0.is_map(), manifest0.impacts != Some(false));
    // Every shard's files are read and checked before anything is written:
    // the summary against the manifest's runs, the other files' rows of
    // each run against the counts its summary row gives.
    let files = headers(map, impacts);
    let mut texts: Vec<String> = files.iter().map(|(_, h)| format!("{h}\n")).collect();
    for f in &found {
        let dir = f.4;
        let lines: Vec<Vec<String>> = files.iter().map(|(name, _)| complete_lines(&dir.join(name))).collect::<Result<_, _>>()?;
        for ((name, header), l) in files.iter().zip(&lines) {
            if l.first() != Some(header) {
                return Err(bad(format!("{}: its first line is not the header {header:?}: a damaged shard; run it again", dir.join(name).display())));
            }
        }
        let summary = &lines[files.iter().position(|(n, _)| *n == "summary.csv").unwrap_or(0)];
        let runs: Vec<usize> = summary.iter().skip(1).filter_map(|l| run_of(l)).collect();
        if runs != (f.2..f.3).collect::<Vec<_>>() {
            return Err(bad(format!(
                "{}: expected {} rows (runs {}..{} of the manifest), found {} (runs {}..{}): finish the shard (--resume) or run it again before merging",
                dir.join("summary.csv").display(),
                f.3 - f.2,
                f.2,
                f.3,
                summary.len() - 1,
                runs.first().copied().unwrap_or(f.2),
                runs.last().map_or(f.2, |r| r + 1)
            )));
        }
        // Rows per run that summary.csv counts: `poincare_points` for
        // sweep.csv, `impacts` (the record window's) for impacts.csv.
        let column = |c: &str| summary[0].split(',').position(|h| h == c);
        let expected = |c: Option<usize>| -> Vec<usize> { summary.iter().skip(1).map(|l| c.and_then(|c| l.split(',').nth(c)).and_then(|x| x.parse().ok()).unwrap_or(0)).collect() };
        for (k, (name, _)) in files.iter().enumerate() {
            let want = match *name {
                "sweep.csv" => expected(column("poincare_points")),
                "impacts.csv" => expected(column("impacts")),
                _ => continue,
            };
            let mut got = vec![0usize; want.len()];
            let mut stray = 0usize;
            for l in lines[k].iter().skip(1) {
                match run_of(l).and_then(|r| r.checked_sub(f.2)).filter(|r| *r < got.len()) {
                    Some(r) => got[r] += 1,
                    None => stray += 1,
                }
            }
            let (e, g): (usize, usize) = (want.iter().sum(), got.iter().sum::<usize>() + stray);
            if want != got || stray > 0 {
                let first = want.iter().zip(&got).position(|(a, b)| a != b).map_or(String::new(), |r| format!("; run {} has {} of its {}", f.2 + r, got[r], want[r]));
                return Err(bad(format!(
                    "{}: expected {e} rows (runs {}..{} as the manifest and summary.csv count them), found {g}{first}: a damaged shard; run it again (--shard {}/{})",
                    dir.join(name).display(),
                    f.2,
                    f.3,
                    f.0,
                    f.1
                )));
            }
        }
        for (t, l) in texts.iter_mut().zip(&lines) {
            for row in l.iter().skip(1) {
                t.push_str(row);
                t.push('\n');
            }
        }
    }
    for ((name, _), text) in files.iter().zip(texts) {
        std::fs::write(out.join(name), text).map_err(|e| io(&out.join(name), e))?;
    }
    // The unsharded manifest: the shard's without its shard and runs.
    let unsharded = Manifest { shard: None, runs: None, ..found[0].6.clone() };
    std::fs::write(out.join("sweep.toml"), unsharded.text()).map_err(|e| io(&out.join("sweep.toml"), e))?;
    let mut lines = vec![format!("merged {n0} shards of sweep {id0}")];
    lines.extend(plots(out)?);
    lines.push(format!("wrote {}", out.display()));
    Ok(lines)
}
