//! The sweep run: runs in batches written in run order ([`run`]), its
//! [`Progress`] and [`SweepReport`].

use crate::error::{io, Error, SweepError};
use crate::lockstep::{lockstep_jobs, simulate_lockstep, LANES};
use crate::output::{complete_lines, failed_row, headers, plots, read_state, rows_text, run_of, write_state, Outputs, SWEEP_FILES};
use crate::setup::{manifest_id, Manifest, Sweep};
use crate::simulate::{failed, simulate, Plan, RunRows, ScenePlan};
use rayon::prelude::*;
use signorini_run::Cancel;
use signorini_scene::Scene;
use std::io::Write;
use std::path::Path;

/// A run's value(s): the first axis's, and the second's on a map.
pub(crate) type Values = (f64, Option<f64>);

/// A run of a batch: its index, value(s) and scene (or why it has none).
pub(crate) type Prepared = (usize, Values, Result<ScenePlan, Error>);

/// How far a sweep is: the engine calls it as runs finish (from several
/// threads). The CLI draws a progress bar with it; a caller that does not
/// watch passes [`NoProgress`].
pub trait Progress: Sync {
    /// The sweep starts: `total` runs, of which `done` are already in the
    /// folder (a resumed sweep).
    fn start(&self, _total: u64, _done: u64) {}
    /// `runs` more runs are done.
    fn advance(&self, _runs: u64) {}
    /// The sweep stopped (finished, interrupted or failed).
    fn finish(&self) {}
}

/// A [`Progress`] that shows nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}

/// What a finished sweep (or shard) did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SweepReport {
    /// Lines for the terminal.
    pub lines: Vec<String>,
    /// Runs of the sweep (of the shard).
    pub runs: usize,
    /// Runs whose status is not `ok` (blow-ups, …), resumed ones included.
    pub failed: usize,
}

/// The engine of [`run`], with `simulate(scene, plan, start state)` doing
/// each run that the lockstep engine does not take. Every value of the
/// sweep's (shard's) runs is checked before anything is written: a value
/// that makes the scene invalid is refused ([`SweepError::Value`]).
pub(crate) fn sweep_report<F>(sweep: &Sweep, dir: &Path, simulate: F, progress: &dyn Progress) -> Result<SweepReport, Error>
where
    F: Fn(&Scene, &Plan, Option<&(Vec<f64>, Vec<f64>)>) -> RunRows + Sync,
{
    let o = &sweep.opts;
    let interrupt = o.interrupt.as_ref();
    let runs = o.runs();
    let pool = {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(t) = o.threads {
            b = b.num_threads(t);
        }
        b.build().map_err(Error::ThreadPool)?
    };
    // Every value before the first run (the first invalid one in run order).
    if let Some(r) = pool.install(|| runs.clone().into_par_iter().find_first(|&r| sweep.scene(o.value(r)).is_err())) {
        sweep.scene(o.value(r))?;
    }
    std::fs::create_dir_all(dir).map_err(|source| Error::OutFolder { path: dir.to_path_buf(), source })?;
    let manifest = sweep.manifest(o.shard);
    let mpath = dir.join("sweep.toml");
    let mut first = runs.start;
    let mut state: Option<(Vec<f64>, Vec<f64>)> = None;
    let mut stopped = 0usize;
    if o.resume {
        let old = std::fs::read_to_string(&mpath).map_err(|e| io(&mpath, e))?;
        // The manifests compared as values (a different key, or a file that
        // is not a manifest, is another sweep).
        if Manifest::parse(&old).ok().as_ref() != Some(&manifest) {
            return Err(SweepError::Folder(format!(
                "--resume: {} holds another sweep (its sweep.toml differs: id {} here, {} asked); use a new --out",
                dir.display(),
                manifest_id(&old).as_deref().unwrap_or("?"),
                sweep.id
            ))
            .into());
        }
        let summary = complete_lines(&dir.join("summary.csv"))?;
        let done: Vec<usize> = summary.iter().skip(1).filter_map(|l| run_of(l)).collect();
        // The prefix of runs whose summary row is complete.
        let mut next = runs.start;
        for r in &done {
            if *r == next {
                next += 1;
            }
        }
        first = next;
        // The kept runs' failures count in the sweep's.
        stopped = summary.iter().skip(1).filter(|l| run_of(l).is_some_and(|r| r < first) && failed_row(l, o.second.is_some())).count();
        for (name, header) in headers(o.second.is_some(), o.impacts) {
            let p = dir.join(name);
            let lines = complete_lines(&p)?;
            let mut text = header + "\n";
            for l in lines.iter().skip(1).filter(|l| run_of(l).is_some_and(|r| r < first)) {
                text.push_str(l);
                text.push('\n');
            }
            std::fs::write(&p, text).map_err(|e| io(&p, e))?;
        }
        if o.follow && first > runs.start {
            state = read_state(&dir.join("follow_state.txt"))?;
        }
    } else {
        if let Some(f) = SWEEP_FILES.iter().find(|f| dir.join(f).exists()) {
            return Err(SweepError::Folder(format!("{} holds a sweep's files ({f}): pass --resume to continue that sweep, or choose another --out", dir.display())).into());
        }
        std::fs::write(&mpath, manifest.text()).map_err(|e| io(&mpath, e))?;
        for (name, header) in headers(o.second.is_some(), o.impacts) {
            let p = dir.join(name);
            std::fs::write(&p, header + "\n").map_err(|e| io(&p, e))?;
        }
    }
    let mut out =
        Outputs { sweep: Outputs::append(dir, "sweep.csv")?, impacts: if o.impacts { Some(Outputs::append(dir, "impacts.csv")?) } else { None }, summary: Outputs::append(dir, "summary.csv")? };
    let batch = if o.follow { 1 } else { (2 * LANES * pool.current_num_threads()).max(1) };
    let bar = progress;
    bar.start(runs.len() as u64, (first - runs.start) as u64);
    let start = std::time::Instant::now();
    let mut next = first;
    let mut interrupted = false;
    while next < runs.end {
        if interrupt.is_some_and(Cancel::is_cancelled) {
            interrupted = true;
            break;
        }
        let end = (next + batch).min(runs.end);
        let results: Vec<(usize, Values, Result<RunRows, Error>)> = if o.follow {
            // One run at a time, each from the last one's state.
            let i = next;
            let v = o.value(i);
            // A followed map restarts from the scene's own state on each row.
            let start = if i % o.count == 0 { None } else { state.as_ref() };
            let r = sweep.scene(v).map(|(_, scene, plan)| simulate(&scene, &plan, start));
            bar.advance(1);
            vec![(i, v, r)]
        } else {
            pool.install(|| {
                let prepared: Vec<Prepared> = (next..end).into_par_iter().map(|i| (i, o.value(i), sweep.scene(o.value(i)).map(|(_, s, p)| (s, p)))).collect();
                let jobs = lockstep_jobs(&prepared, pool.current_num_threads());
                let done: Vec<Vec<(usize, RunRows)>> = jobs
                    .into_par_iter()
                    .map(|job| {
                        let out = match job.as_slice() {
                            [k] => match &prepared[*k].2 {
                                Ok((scene, plan)) => vec![(*k, simulate(scene, plan, None))],
                                Err(_) => Vec::new(),
                            },
                            ks => {
                                let group: Vec<(&Scene, &Plan)> = ks.iter().filter_map(|k| prepared[*k].2.as_ref().ok().map(|(s, p)| (s, p))).collect();
                                match simulate_lockstep(&group, interrupt) {
                                    Some(rows) => ks.iter().copied().zip(rows).collect(),
                                    None => ks.iter().filter_map(|k| prepared[*k].2.as_ref().ok().map(|(s, p)| (*k, simulate(s, p, None)))).collect(),
                                }
                            }
                        };
                        bar.advance(job.len() as u64);
                        out
                    })
                    .collect();
                let mut rows: Vec<Option<RunRows>> = (0..prepared.len()).map(|_| None).collect();
                for (k, r) in done.into_iter().flatten() {
                    rows[k] = Some(r);
                }
                prepared.into_iter().zip(rows).map(|((i, v, p), r)| (i, v, p.and_then(|_| r.ok_or(Error::MissingRun)))).collect()
            })
        };
        let (mut sw, mut im, mut su) = (String::new(), String::new(), String::new());
        for (i, v, r) in results {
            // A value whose scene is invalid (every value was checked before
            // the first run: only if building it fails now) is a failed run,
            // like a blow-up: the sweep goes on.
            let rows = r.unwrap_or_else(|e| failed(&e));
            if rows.status == "interrupted" {
                interrupted = true;
                break;
            }
            stopped += usize::from(rows.status != "ok");
            let (a, b, c) = rows_text(v, i, &rows);
            sw.push_str(&a);
            im.push_str(&b);
            su.push_str(&c);
            next = i + 1;
            if o.follow {
                state = rows.state.clone();
            }
        }
        out.sweep.write_all(sw.as_bytes()).map_err(|e| io(&dir.join("sweep.csv"), e))?;
        if let Some(f) = out.impacts.as_mut() {
            f.write_all(im.as_bytes()).map_err(|e| io(&dir.join("impacts.csv"), e))?;
        }
        if o.follow {
            write_state(&dir.join("follow_state.txt"), state.as_ref())?;
        }
        out.summary.write_all(su.as_bytes()).map_err(|e| io(&dir.join("summary.csv"), e))?;
        if interrupted {
            break;
        }
    }
    bar.finish();
    let wall = start.elapsed().as_secs_f64();
    if interrupted {
        return Err(Error::Interrupted { done: next - runs.start, total: runs.len(), dir: dir.display().to_string() });
    }
    let mut lines = vec![format!("{} runs in {wall:.3} s ({} of them stopped early: see summary.csv's status)", runs.len() - (first - runs.start), stopped)];
    if o.shard.is_none() {
        lines.extend(plots(dir)?);
    }
    lines.push(format!("wrote {}", dir.display()));
    Ok(SweepReport { lines, runs: runs.len(), failed: stopped })
}

/// Runs a sweep into `dir` (see the module docs), telling `progress` as
/// runs finish: its lines for the terminal and the count of failed runs (a
/// sweep whose runs failed is still a sweep; `signorini sweep` exits 3
/// when there are any).
pub fn run(sweep: &Sweep, dir: &Path, progress: &dyn Progress) -> Result<SweepReport, Error> {
    let interrupt = sweep.opts.interrupt.as_ref();
    let follow = sweep.opts.follow;
    sweep_report(sweep, dir, |scene, plan, start| simulate(scene, plan, start, follow, interrupt), progress)
}
