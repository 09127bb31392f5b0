//! `cargo xtask test`: every test of the project in one command — the Rust
//! workspace's (`cargo test --workspace --release --tests --no-run`, each
//! test binary run as soon as cargo has built it — those of a package with
//! binaries of its own, the CLI's and xtask's, once the build has ended —
//! two at a time, as cargo would run them, then `cargo test --doc` beside the last ones; the Python
//! crate excluded: maturin builds it with its own environment),
//! then the Python package built by maturin (while the Rust test binaries
//! run) into a virtual environment this command creates while the Rust
//! tests build (`target/py-venv`,
//! with maturin, numpy, pytest, dask.distributed (the scale-out test) and
//! matplotlib (the examples) from the package index), then, as soon as the
//! wheel is built and beside the last Rust test binaries, its pytest suite
//! (`python/tests`) and the lints with warnings denied (`cargo
//! fmt --check`, `cargo clippy --workspace --all-targets -- -D warnings`,
//! which also compiles the examples, `cargo doc --workspace --no-deps` with
//! `RUSTDOCFLAGS=-D warnings`),
//! then the user guide: the
//! generated tables checked against `data/reference` (`cargo xtask docs
//! --check`) and `mkdocs build --strict` (MkDocs, the Material theme and
//! mkdocstrings from the package index into the same environment) into
//! `target/site`.
//!
//! Every phase runs even when an earlier one failed (the Python phases
//! only after the environment and the wheel were built), and the Rust tests
//! run with `--no-fail-fast`, so that the count is complete. The last two
//! lines are the verdict: every test counted, Rust and Python, and PASS or
//! FAIL (with the phases that failed), then the total alone on a line,
//! `tests: N passed, M failed` (the form CI reads; a phase that failed
//! without a failed test — a lint, a build — counts as one failed).
//!
//! `--record` also times each phase and the whole command (from the start
//! of the `cargo` process that built and started this binary), and writes
//! them with the counts to `docs/generated/test-record.md`: the one place
//! those numbers live.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

/// Arguments of `cargo xtask test`.
#[derive(clap::Args)]
pub struct Args {
    /// Skip the Rust tests (only build the package, run pytest and build the guide).
    #[arg(long)]
    python_only: bool,
    /// Count the tests, time each phase and write docs/generated/test-record.md.
    #[arg(long)]
    record: bool,
}

/// The guide's build tools, installed from the package index into the test
/// environment (ranges known to work together: mkdocstrings 0.30 fails
/// with the highlighter of pymdown-extensions 13, which mkdocs-material
/// pulls in; mkdocstrings 1 with mkdocstrings-python 2 works).
const GUIDE_PACKAGES: [&str; 4] = ["mkdocs>=1.6,<2", "mkdocs-material>=9.5,<10", "mkdocstrings[python]>=1,<2", "mkdocstrings-python>=2,<3"];

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn run(cmd: &mut Command, what: &str) -> Result<(), String> {
    let status = cmd.status().map_err(|e| format!("{what}: cannot start: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{what} failed ({status})"))
    }
}

/// One line of a program's output as bytes, without its end (`\r` before
/// the `\n` the line was split at); invalid UTF-8 kept, replaced.
fn line_text(line: &[u8]) -> String {
    String::from_utf8_lossy(line).trim_end_matches('\r').to_string()
}

/// [`run`], with stdout passed through line by line and kept: the lines
/// and whether the command succeeded (the lines of a failed run count too).
fn run_capture(cmd: &mut Command, what: &str) -> (Vec<String>, Result<(), String>) {
    let mut child = match cmd.stdout(Stdio::piped()).spawn() {
        Ok(c) => c,
        Err(e) => return (Vec::new(), Err(format!("{what}: cannot start: {e}"))),
    };
    let mut lines = Vec::new();
    if let Some(out) = child.stdout.take() {
        // Invalid UTF-8 in a test's output is kept, replaced.
        for line in BufReader::new(out).split(b'\n').map_while(Result::ok) {
            let line = line_text(&line);
            println!("{line}");
            lines.push(line);
        }
    }
    let status = match child.wait() {
        Ok(s) => s,
        Err(e) => return (lines, Err(format!("{what}: {e}"))),
    };
    let r = if status.success() { Ok(()) } else { Err(format!("{what} failed ({status})")) };
    (lines, r)
}

/// Passed, failed and ignored tests over cargo's `test result:` lines.
pub fn rust_counts(lines: &[String]) -> (u64, u64, u64) {
    lines.iter().filter_map(|l| l.find("test result:").map(|i| &l[i..])).fold((0, 0, 0), |(p, f, i), l| (p + count(l, "passed"), f + count(l, "failed"), i + count(l, "ignored")))
}

/// One test executable of `cargo test --no-run`: the file, its package's
/// directory (where cargo runs it, and its `CARGO_MANIFEST_DIR`) and its
/// source (`tests/it/main.rs`, `src/lib.rs`).
#[derive(Debug, Clone, PartialEq)]
pub struct TestBinary {
    pub exe: PathBuf,
    pub dir: PathBuf,
    pub src: String,
}

/// A string field of one line of cargo's JSON messages (`"key":"value"`,
/// the first occurrence; `\\` and `\"` unescaped): xtask has no JSON reader,
/// and cargo writes each message on one line with these keys once.
fn json_str(line: &str, key: &str) -> Option<String> {
    let start = line.find(&format!("\"{key}\":\""))? + key.len() + 4;
    let mut out = String::new();
    let mut chars = line[start..].chars();
    while let Some(c) = chars.next() {
        match c {
            '"' => return Some(out),
            '\\' => out.push(match chars.next()? {
                'n' => '\n',
                't' => '\t',
                c => c,
            }),
            c => out.push(c),
        }
    }
    None
}

/// The test executable of one of cargo's JSON messages (`--message-format
/// json`), if it names one: an artifact whose profile says `"test":true`
/// (a binary built for the integration tests has an executable too, and
/// its target's own `"test":true` says only that it could be tested).
pub fn test_binary(line: &str) -> Option<TestBinary> {
    let profile = line.split("\"profile\":{").nth(1).and_then(|p| p.split('}').next());
    if !line.contains("\"reason\":\"compiler-artifact\"") || !profile.is_some_and(|p| p.contains("\"test\":true")) {
        return None;
    }
    let exe = PathBuf::from(json_str(line, "executable")?);
    let dir = PathBuf::from(json_str(line, "manifest_path")?).parent()?.to_path_buf();
    let src = json_str(line, "src_path")?;
    let src = Path::new(&src).strip_prefix(&dir).map_or(src.clone(), |p| p.display().to_string());
    Some(TestBinary { exe, dir, src })
}

/// The test executables among cargo's JSON messages ([`test_binary`]), in
/// the order cargo built them. None is an error: a format of cargo's that
/// this does not read would otherwise run no test and count none.
pub fn test_binaries(messages: &[String]) -> Result<Vec<TestBinary>, String> {
    let bins: Vec<TestBinary> = messages.iter().filter_map(|l| test_binary(l)).collect();
    if bins.is_empty() {
        return Err(NO_TEST_EXECUTABLE.into());
    }
    Ok(bins)
}

const NO_TEST_EXECUTABLE: &str = "cargo test --tests --no-run: no test executable in cargo's JSON messages";

/// `cargo test --tests --no-run` (`args`: the test command's own), each
/// test executable sent to `bins` as soon as cargo has built it (cargo
/// writes an artifact's message once it is linked), so that the binaries
/// built first run while cargo compiles the others: on two cores the last
/// test crates compile largely one at a time, and the runs fill the other
/// core. The tests of a package with binaries of its own ([`has_binaries`]:
/// the CLI's tests call `signorini`, xtask's call `xtask`) are sent only once cargo
/// has ended: cargo links a package's binaries beside its tests, and a test
/// run before its binary is there fails (every CLI test did on a fresh
/// clone). Cargo's progress and diagnostics go to stderr as usual. The
/// error says when the build failed or built no test executable.
pub fn build_tests(cargo: &str, root: &Path, args: &[&str], bins: std::sync::mpsc::Sender<TestBinary>) -> Result<(), String> {
    let mut child = Command::new(cargo)
        .current_dir(root)
        .args(args)
        .args(["--tests", "--no-run", "--message-format=json-render-diagnostics"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .map_err(|e| format!("cargo test --tests --no-run: cannot start: {e}"))?;
    let mut built = 0usize;
    let mut after = Vec::new();
    if let Some(out) = child.stdout.take() {
        for line in BufReader::new(out).split(b'\n').map_while(Result::ok) {
            if let Some(b) = test_binary(&line_text(&line)) {
                built += 1;
                if has_binaries(&b.dir) {
                    after.push(b);
                } else {
                    // The runners end only after this sender is dropped.
                    let _ = bins.send(b);
                }
            }
        }
    }
    let end = match child.wait() {
        Ok(s) if !s.success() => Err(format!("cargo test --tests --no-run failed ({s})")),
        Err(e) => Err(format!("cargo test --tests --no-run: {e}")),
        Ok(_) if built == 0 => Err(NO_TEST_EXECUTABLE.into()),
        Ok(_) => Ok(()),
    };
    if end.is_ok() {
        for b in after {
            let _ = bins.send(b);
        }
    }
    end
}

/// Whether the package in `dir` has binary targets (`src/main.rs`,
/// `src/bin/`, or a `[[bin]]` in its manifest), whose executables its
/// tests may run (`CARGO_BIN_EXE_…`).
pub fn has_binaries(dir: &Path) -> bool {
    dir.join("src/main.rs").exists() || dir.join("src/bin").is_dir() || std::fs::read_to_string(dir.join("Cargo.toml")).is_ok_and(|m| m.lines().any(|l| l.trim() == "[[bin]]"))
}

/// Runs the test binaries `jobs` at a time (each with the test harness's
/// own threads) as they arrive from `bins` (cargo's build, [`build_tests`],
/// in the order it built them) until it is closed, as `cargo test` would
/// run them one after the other: in its package's directory with its
/// `CARGO_MANIFEST_DIR`. Each binary's output is printed whole when it
/// ends, under cargo's `Running` line; the lines of every binary are
/// returned, and an error names each binary that failed.
fn run_binaries(bins: std::sync::mpsc::Receiver<TestBinary>, jobs: usize) -> (Vec<String>, Result<(), String>) {
    let queue = std::sync::Mutex::new(bins);
    let done = std::sync::Mutex::new((Vec::<String>::new(), Vec::<String>::new()));
    let (queue, done) = (&queue, &done);
    std::thread::scope(|s| {
        for _ in 0..jobs.max(1) {
            // The queue's lock is held while waiting for the next binary.
            let next = || queue.lock().ok().and_then(|q| q.recv().ok());
            s.spawn(move || {
                while let Some(b) = next() {
                    let head = format!("     Running {} ({})", b.src, b.exe.display());
                    let out = Command::new(&b.exe).current_dir(&b.dir).env("CARGO_MANIFEST_DIR", &b.dir).stdin(Stdio::null()).output();
                    let (mut lines, err) = match out {
                        Ok(o) => {
                            let text = |b: &[u8]| String::from_utf8_lossy(b).lines().map(|l| l.trim_end_matches('\r').to_string()).collect::<Vec<_>>();
                            let mut lines = text(&o.stdout);
                            lines.extend(text(&o.stderr));
                            (lines, (!o.status.success()).then(|| format!("{} ({}) failed ({})", b.src, b.exe.display(), o.status)))
                        }
                        Err(e) => (Vec::new(), Some(format!("{}: cannot start: {e}", b.exe.display()))),
                    };
                    lines.insert(0, head);
                    if let Ok(mut d) = done.lock() {
                        println!("{}", lines.join("\n"));
                        d.0.append(&mut lines);
                        d.1.extend(err);
                    }
                }
            });
        }
    });
    let (lines, errors) = std::mem::take(&mut *done.lock().unwrap_or_else(|e| e.into_inner()));
    let r = if errors.is_empty() { Ok(()) } else { Err(format!("cargo test --tests: {}", errors.join("; "))) };
    (lines, r)
}

/// `cargo test --doc` in a thread of its own, with a signal once it has
/// passed cargo's build phase (its first `Doc-tests` line on stderr, or
/// its end), after which it holds no lock on the build directory. Its
/// stdout is printed whole when it ends; the thread returns its lines,
/// whether it passed, and when it ended.
#[allow(clippy::type_complexity)]
fn doc_tests(cargo: &str, root: &Path, base: &[&str]) -> (std::thread::JoinHandle<(Vec<String>, Result<(), String>, Instant)>, std::sync::mpsc::Receiver<()>) {
    let (tx, rx) = std::sync::mpsc::channel();
    let mut cmd = Command::new(cargo);
    cmd.current_dir(root).args(base).arg("--doc").stdout(Stdio::piped()).stderr(Stdio::piped());
    let handle = std::thread::spawn(move || {
        let mut child = match cmd.spawn() {
            Ok(c) => c,
            Err(e) => {
                let _ = tx.send(());
                return (Vec::new(), Err(format!("cargo test --doc: cannot start: {e}")), Instant::now());
            }
        };
        let err = child.stderr.take().map(|e| {
            std::thread::spawn(move || {
                let mut tx = Some(tx);
                let mut lines = Vec::new();
                for line in BufReader::new(e).split(b'\n').map_while(Result::ok) {
                    let line = line_text(&line);
                    if line.contains("Doc-tests") {
                        tx.take().map(|t| t.send(()));
                    }
                    lines.push(line);
                }
                lines
            })
        });
        let mut lines = Vec::new();
        if let Some(out) = child.stdout.take() {
            lines = BufReader::new(out).split(b'\n').map_while(Result::ok).map(|l| line_text(&l)).collect();
        }
        let err = err.and_then(|h| h.join().ok()).unwrap_or_default();
        let status = child.wait();
        eprintln!("{}", err.join("\n"));
        println!("{}", lines.join("\n"));
        let r = match status {
            Ok(s) if s.success() => Ok(()),
            Ok(s) => Err(format!("cargo test --doc failed ({s})")),
            Err(e) => Err(format!("cargo test --doc: {e}")),
        };
        (lines, r, Instant::now())
    });
    (handle, rx)
}

/// Passed, failed (errors included: a test that could not be collected or
/// set up) and skipped tests from pytest's summary line, its last line of
/// the form `1 failed, 113 passed, 2 skipped in 15.20s` (with `=` around
/// it or not).
pub fn python_counts(lines: &[String]) -> (u64, u64, u64) {
    let summary = lines.iter().rev().map(|l| l.trim().trim_matches('=').trim()).find(|l| {
        l.starts_with(|c: char| c.is_ascii_digit())
            // `in 15.32s`, or `in 81.19s (0:01:21)` past a minute.
            && l.split(" in ").last().map(|t| t.split(" (").next().unwrap_or(t)).is_some_and(|t| t.ends_with('s') && t.trim_end_matches('s').parse::<f64>().is_ok())
            && ["passed", "failed", "skipped", "error", "errors", "deselected", "xfailed", "xpassed", "warning", "warnings"].iter().any(|w| count(l, w) > 0)
    });
    summary.map_or((0, 0, 0), |l| (count(l, "passed"), count(l, "failed") + count(l, "error") + count(l, "errors"), count(l, "skipped")))
}

/// The closing lines of `cargo xtask test`: the verdict with the counts
/// per language and the phases that failed, then the total alone, in the
/// form CI reads (`tests: N passed, M failed`). A phase that failed without
/// reporting a failed test (a lint, a build, the guide) counts as one
/// failed; a phase not run is named.
pub fn verdict_lines(rec: &Record, failed_phases: &[(String, bool)], not_run: &[&str], skipped: Option<&str>) -> (String, String) {
    let pass = failed_phases.is_empty() && not_run.is_empty() && rec.rust.1 == 0 && rec.python.1 == 0;
    let extra = failed_phases.iter().filter(|(_, counted)| !counted).count() as u64;
    let mut detail = format!(
        "signorini tests: {} — {} passed, {} failed, {} ignored (Rust); {} passed, {} failed, {} skipped (Python)",
        if pass { "PASS" } else { "FAIL" },
        rec.rust.0,
        rec.rust.1,
        rec.rust.2,
        rec.python.0,
        rec.python.1,
        rec.python.2
    );
    if !failed_phases.is_empty() {
        detail.push_str(&format!("; failed: {}", failed_phases.iter().map(|(p, _)| p.as_str()).collect::<Vec<_>>().join("; ")));
    }
    if !not_run.is_empty() {
        detail.push_str(&format!("; not run: {}", not_run.join(", ")));
    }
    if let Some(s) = skipped {
        detail.push_str(&format!("; skipped: {s}"));
    }
    let total = format!("tests: {} passed, {} failed", rec.rust.0 + rec.python.0, rec.rust.1 + rec.python.1 + extra + not_run.len() as u64);
    (detail, total)
}

/// Seconds since the `cargo` process that started this binary began
/// (`cargo xtask test`: the build of the xtask binary included), from
/// /proc; `None` when not started by cargo or /proc cannot tell.
/// `cargo run` builds the binary, then replaces itself with it (exec: the
/// same process), so this process's start time is cargo's.
#[cfg(target_os = "linux")]
fn since_cargo_started() -> Option<f64> {
    // `cargo run` sets CARGO for the program it runs.
    std::env::var_os("CARGO")?;
    // /proc/self/stat: the fields after the command name's ')': state
    // (3), ppid (4), …, starttime (22, clock ticks after boot).
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    let start_ticks: f64 = s[s.rfind(')')? + 1..].split_whitespace().nth(19)?.parse().ok()?;
    // SAFETY: sysconf only reads a configuration value.
    let tck = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
    let uptime: f64 = std::fs::read_to_string("/proc/uptime").ok()?.split_whitespace().next()?.parse().ok()?;
    (tck > 0).then(|| uptime - start_ticks / tck as f64).filter(|t| *t >= 0.0)
}

#[cfg(not(target_os = "linux"))]
fn since_cargo_started() -> Option<f64> {
    None
}

/// The numbers before `word` in `line` (`"12 passed, 3 skipped"`).
fn count(line: &str, word: &str) -> u64 {
    let toks: Vec<&str> = line.split(|c: char| c.is_whitespace() || c == ',' || c == ';').filter(|t| !t.is_empty()).collect();
    toks.windows(2).filter(|w| w[1].trim_end_matches('.') == word).filter_map(|w| w[0].parse::<u64>().ok()).sum()
}

/// What `--record` measures.
#[derive(Default)]
pub struct Record {
    /// Each phase's name, its start (s after the command's) and its wall
    /// time (s): phases overlap.
    pub phases: Vec<(&'static str, f64, f64)>,
    /// Rust tests passed, failed, ignored.
    pub rust: (u64, u64, u64),
    /// Python tests passed, failed, skipped.
    pub python: (u64, u64, u64),
}

impl Record {
    /// `f`, recorded as the phase `name` (`origin`: the command's start).
    fn time<T>(&mut self, origin: Instant, name: &'static str, f: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
        let t = Instant::now();
        let r = f();
        self.phases.push((name, since(origin, t), t.elapsed().as_secs_f64()));
        r
    }
}

/// Seconds from `origin` to `t`.
fn since(origin: Instant, t: Instant) -> f64 {
    t.duration_since(origin).as_secs_f64()
}

fn minutes(s: f64) -> String {
    let s = s.round() as u64;
    if s >= 60 {
        format!("{} min {} s", s / 60, s % 60)
    } else {
        format!("{s} s")
    }
}

fn machine() -> String {
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(0);
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| c.lines().find(|l| l.starts_with("model name")).and_then(|l| l.split(':').nth(1)).map(|s| s.trim().to_string()))
        .unwrap_or_else(|| "unknown CPU".into());
    format!("{cores} cores ({cpu})")
}

fn tool_version(cmd: &str, arg: &str) -> String {
    Command::new(cmd).arg(arg).output().ok().and_then(|o| String::from_utf8(o.stdout).ok()).map(|s| s.trim().to_string()).unwrap_or_else(|| format!("{cmd}: unknown"))
}

fn write_record(rec: &Record, cold: bool, total: f64, cargo: &str, py: &Path) -> Result<(), String> {
    let now = Command::new("date").args(["-u", "+%Y-%m-%d %H:%M UTC"]).output().ok().and_then(|o| String::from_utf8(o.stdout).ok()).map(|s| s.trim().to_string()).unwrap_or_default();
    let mut s = String::from("<!-- Written by `cargo xtask test --record`; do not edit. -->\n");
    s.push_str(&format!(
        "Recorded {now} on {}, {}, {}; the build directory was {}.\n\n",
        machine(),
        tool_version("rustc", "--version"),
        tool_version(py.to_str().unwrap_or("python3"), "--version"),
        if cold { "empty (every crate compiled, the virtual environment created: a fresh clone's time)" } else { "warm (an earlier build reused)" }
    ));
    s.push_str("| | passed | failed | ignored / skipped |\n|---|---|---|---|\n");
    s.push_str(&format!("| Rust tests (`cargo test --workspace --release --tests`, the binaries two at a time, and `--doc`) | {} | {} | {} |\n", rec.rust.0, rec.rust.1, rec.rust.2));
    s.push_str(&format!("| Python tests (pytest, `python/tests`) | {} | {} | {} |\n\n", rec.python.0, rec.python.1, rec.python.2));
    s.push_str("| phase of `cargo xtask test` | starts at | wall time |\n|---|---|---|\n");
    for (name, at, t) in &rec.phases {
        s.push_str(&format!("| {name} | {} | {} |\n", minutes(*at), minutes(*t)));
    }
    // The whole command: from the start of the `cargo` that built this
    // binary (on a fresh clone most of the workspace) and started it.
    // After the main job's build: `cargo xtask convergence` builds the same
    // `cargo xtask` binary (the workspace's libraries in release), so the
    // test command that follows it costs the phases above, this binary's
    // own run from its start.
    s.push_str(&format!("| **after the main job's build** (the phases above: `cargo xtask convergence` builds the same `cargo xtask` binary first) | | **{}** |\n", minutes(total)));
    if let Some(whole) = since_cargo_started() {
        s.push_str(&format!("| **the whole `cargo xtask test`** (from the start of `cargo`: the `cargo xtask` binary's own build included) | | **{}** |\n", minutes(whole)));
    }
    let _ = cargo;
    let path = root().join("docs/generated/test-record.md");
    std::fs::write(&path, s).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// The workspace's lints, warnings denied: formatting (`rustfmt.toml`),
/// clippy on every target (`[workspace.lints]` in Cargo.toml; the examples
/// are compiled here), and the API docs (broken intra-doc links, bad HTML).
/// Their output is printed when one fails (the Python tests run beside
/// them).
fn lints(cargo: &str, root: &Path) -> Result<(), String> {
    run_quiet(Command::new(cargo).current_dir(root).args(["fmt", "--all", "--check"]), "cargo fmt --check (run `cargo fmt --all`)")?;
    run_quiet(Command::new(cargo).current_dir(root).args(["clippy", "--workspace", "--all-targets", "--release", "--"]).args(CLIPPY_ARGS), "cargo clippy -D warnings")?;
    let mut doc = Command::new(cargo);
    doc.current_dir(root).env("RUSTDOCFLAGS", "-D warnings").args(["doc", "--workspace", "--no-deps", "--release"]);
    // rustdoc reads the metadata of the workspace's libraries it documents
    // against, which cargo otherwise checks again: clippy's own checks of
    // them sit under other file names (cargo hashes the wrapper that `cargo
    // clippy` puts in front of rustc for the workspace's crates into them).
    // With the same wrapper and arguments, `cargo doc` finds them fresh and
    // only documents (40.2, 40.7 -> 26.2, 31.1 CPU-s after a clippy run on
    // the workspace's crates). Without clippy's driver next to
    // cargo, the libraries are checked again: slower, the same checks.
    if let Some(driver) = clippy_driver(cargo) {
        doc.env("RUSTC_WORKSPACE_WRAPPER", driver).env("CLIPPY_ARGS", clippy_env_args(&CLIPPY_ARGS));
    }
    run_quiet(&mut doc, "cargo doc (warnings denied)")
}

/// The arguments the lints pass to clippy (after `--`).
const CLIPPY_ARGS: [&str; 2] = ["-D", "warnings"];

/// The driver `cargo clippy` wraps rustc in for the workspace's crates: the
/// `clippy-driver` beside the toolchain's cargo (`$CARGO`, where
/// `cargo-clippy` has it), when it is there.
pub fn clippy_driver(cargo: &str) -> Option<PathBuf> {
    let driver = Path::new(cargo).parent()?.join(format!("clippy-driver{}", std::env::consts::EXE_SUFFIX));
    driver.is_file().then_some(driver)
}

/// Clippy's arguments as `cargo clippy` hands them to its driver (the
/// `CLIPPY_ARGS` variable, each argument followed by its separator), which
/// the driver records in its checks' dependencies: `cargo doc` reuses them
/// only with the same value.
pub fn clippy_env_args(args: &[&str]) -> String {
    args.iter().map(|a| format!("{a}__CLIPPY_HACKERY__")).collect()
}

/// [`run`] with the output kept and printed only when the command fails
/// (the lints run beside the Python tests, whose output stays readable).
fn run_quiet(cmd: &mut Command, what: &str) -> Result<(), String> {
    let out = cmd.output().map_err(|e| format!("{what}: cannot start: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        eprintln!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        Err(format!("{what} failed ({})", out.status))
    }
}

/// The wheel built by maturin and installed into the environment, and the
/// `signorini` command the Python tests compare with (a no-op after `cargo
/// test`, which builds it for the CLI's tests).
fn build_wheel(cargo: &str, root: &Path, target: &Path, venv: &Path, py: &Path) -> Result<(), String> {
    let wheels = target.join("wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    run(Command::new(venv.join("bin/maturin")).current_dir(root).args(["build", "--release", "-m", "python/Cargo.toml", "-i"]).arg(py).arg("-o").arg(&wheels), "maturin build")?;
    let wheel = std::fs::read_dir(&wheels)
        .map_err(|e| format!("{}: {e}", wheels.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "whl"))
        .ok_or("maturin wrote no wheel")?;
    run(Command::new(py).args(["-m", "pip", "install", "-q", "--force-reinstall", "--no-deps"]).arg(&wheel), "pip install the wheel")?;
    run(Command::new(cargo).current_dir(root).args(["build", "--release", "-p", "signorini-cli", "--bin", "signorini"]), "cargo build signorini")
}

/// The test environment: `target/py-venv` (created when absent) with the
/// build tools, the test dependencies and the guide's tools from the
/// package index (upgraded when newer ones are allowed). `--no-compile`:
/// Python compiles a module when it is first imported (into the same
/// `__pycache__`), and the tests and the guide import a small part of what
/// is installed (dask, distributed, matplotlib, the guide's tools): the
/// same packages from local wheels, 21.3, 27.2 -> 7.9, 12.5 CPU-s, then
/// 2.9 CPU-s more on the first imports of the tests' modules and 0.6 on
/// the guide's build.
fn python_env(py: &Path, venv: &Path) -> Result<(), String> {
    if !py.exists() {
        run(Command::new("python3").args(["-m", "venv"]).arg(venv), "python3 -m venv")?;
    }
    run(
        Command::new(py)
            .args(["-m", "pip", "install", "-q", "--disable-pip-version-check", "--no-compile", "--upgrade", "maturin>=1.9.4,<2", "numpy", "pytest", "dask[distributed]", "matplotlib"])
            .args(GUIDE_PACKAGES),
        "pip install maturin numpy pytest dask[distributed] matplotlib mkdocs mkdocs-material mkdocstrings[python]",
    )
}

/// `cargo xtask test`.
pub fn run_tests(a: Args) -> Result<(), crate::Failure> {
    let start = Instant::now();
    let root = root();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let target = std::env::var("CARGO_TARGET_DIR").map(PathBuf::from).unwrap_or_else(|_| root.join("target"));
    let venv = target.join("py-venv");
    let py = venv.join("bin/python");
    // "Cold": no test binary (tests/independent.rs's, a binary of its own
    // under that name) and no environment yet (the xtask binary itself is
    // necessarily built).
    let cold = !venv.exists() && !target.join("release/deps").read_dir().map(|d| d.filter_map(|e| e.ok()).any(|e| e.file_name().to_string_lossy().starts_with("independent-"))).unwrap_or(false);
    let mut rec = Record::default();
    // The phases that failed, each with whether it reported a failed test.
    let mut failed: Vec<(String, bool)> = Vec::new();
    let mut not_run: Vec<&str> = Vec::new();
    // The Python environment waits mostly on the package index and the
    // disk, not on the processor: it is made while the Rust tests build and
    // run (on two cores, their compilation leaves it the gaps), and joined
    // before the wheel, the first phase that needs it.
    let env = {
        let (py, venv) = (py.clone(), venv.clone());
        std::thread::spawn(move || {
            let t = Instant::now();
            let r = python_env(&py, &venv);
            (r, t.elapsed().as_secs_f64())
        })
    };
    // The environment, then the wheel (maturin) and the `signorini`
    // command, in a thread of their own: started once the Rust tests are
    // built, since cargo holds its build directory's lock while it compiles
    // but not while the test binaries run, and the wheel's compilation
    // fills what the test binaries leave of the two cores.
    let spawn_wheel = {
        let (cargo, root, target, venv, py) = (cargo.clone(), root.clone(), target.clone(), venv.clone(), py.clone());
        move || {
            std::thread::spawn(move || {
                let env = env.join().unwrap_or_else(|_| (Err("the Python environment's thread panicked".into()), 0.0));
                let t = Instant::now();
                let wheel = env.0.clone().and_then(|()| build_wheel(&cargo, &root, &target, &venv, &py));
                (env, wheel, t.elapsed().as_secs_f64(), Instant::now())
            })
        }
    };
    let mut spawn_wheel = Some(spawn_wheel);
    let mut handle = None;
    // The Rust tests under way: their start, the test runners, the doc
    // tests and the build's error; joined after the lints, which start
    // beside the last test binaries.
    let mut rust = None;
    if !a.python_only {
        let t = Instant::now();
        // `--tests` (every library's, binary's and integration test's
        // harness), then the doc tests: cargo's default selection would
        // also build the examples, which test nothing; clippy
        // (`--all-targets`, below) still compiles and lints them.
        let base = ["test", "--workspace", "--release", "--exclude", "signorini-py", "--no-fail-fast"];
        // The test binaries run, two at a time, as cargo builds them.
        let (tx, rx) = std::sync::mpsc::channel();
        let runners = std::thread::spawn(move || {
            let (lines, r) = run_binaries(rx, 2);
            (lines, r, Instant::now())
        });
        let (build, doc) = match build_tests(&cargo, &root, &base, tx) {
            Err(e) => (Err(e), None),
            Ok(()) => {
                // The doc tests first: cargo takes its build directory's
                // lock only until they start, and the wheel's build holds
                // it while it compiles. The test binaries need no lock at all.
                let (doc, doc_started) = doc_tests(&cargo, &root, &base);
                let _ = doc_started.recv();
                (Ok(()), Some(doc))
            }
        };
        handle = spawn_wheel.take().map(|f| f());
        rust = Some((t, runners, doc, build));
    }
    let wheel_thread = handle.or_else(|| spawn_wheel.take().map(|f| f()));
    let wheel = match wheel_thread.map(|h| h.join()) {
        None => Err("the wheel's thread was not started".into()),
        Some(j) => match j {
            Ok(((env, env_t), wheel, t, t_end)) => {
                rec.phases.push(("Python: the environment and the packages (made while the Rust tests build and run)", 0.0, env_t));
                if env.is_ok() {
                    rec.phases.push(("Python: build and install the wheel, build the command (beside the Rust test binaries)", since(start, t_end) - t, t));
                }
                wheel
            }
            Err(_) => Err("the wheel's thread panicked".into()),
        },
    };
    let python_ready = match wheel {
        Ok(()) => true,
        Err(e) => {
            failed.push((e, false));
            not_run.push("the Python tests");
            false
        }
    };
    // The xtask binary the Python tests run: `cargo test` builds
    // target/release/xtask for xtask's own tests and may replace this
    // running binary's file (its features unified over the workspace), and
    // then /proc/self/exe names a deleted file: the path, when it is there.
    let xtask = Some(target.join("release/xtask")).filter(|p| p.exists()).unwrap_or_else(|| std::env::current_exe().unwrap_or_default());
    // The Python tests and the lints side by side, started as soon as the
    // wheel is built, beside the last Rust test binaries: pytest runs built
    // programs and never cargo (which the lints hold), the test binaries
    // need no lock on the build directory, and the wheel's build was the
    // last to hold it. On two cores each fills the others' gaps (clippy
    // and rustdoc work through the workspace's crates largely one at a
    // time, and a test binary's last tests run on one thread).
    let pytest = python_ready.then(|| {
        let mut cmd = Command::new(&py);
        cmd.current_dir(&root).env("SIGNORINI_BIN", target.join("release/signorini")).env("SIGNORINI_XTASK", &xtask).args(["-m", "pytest", "-q", "python/tests"]);
        std::thread::spawn(move || {
            let t = Instant::now();
            let (lines, r) = run_capture(&mut cmd, "pytest");
            (lines, r, t, t.elapsed().as_secs_f64())
        })
    });
    if !a.python_only {
        if let Err(e) = rec.time(
            start,
            "lints: `cargo fmt --check`, `cargo clippy -D warnings`, `cargo doc -D warnings` (once the wheel is built: beside the last Rust test binaries and the Python tests)",
            || lints(&cargo, &root),
        ) {
            failed.push((e, false));
        }
    }
    if let Some((t, runners, doc, build)) = rust {
        let (mut lines, r, mut end) = runners.join().unwrap_or_else(|_| (Vec::new(), Err("the test runners' thread panicked".into()), Instant::now()));
        let mut r = match build {
            Ok(()) => r,
            Err(e) => Err(match r {
                Ok(()) => e,
                Err(r) => format!("{e}; {r}"),
            }),
        };
        if let Some(doc) = doc {
            let (doc_lines, r_doc, doc_end) = doc.join().unwrap_or_else(|_| (Vec::new(), Err("the doc tests' thread panicked".into()), Instant::now()));
            lines.extend(doc_lines);
            r = r.and(r_doc);
            end = end.max(doc_end);
        }
        rec.phases.insert(0, ("Rust: build the tests and run them: each test binary as soon as it is built (the CLI's and xtask's, packages with binaries of their own, once the build has ended), two at a time, then the doc tests and the wheel's build beside them", since(start, t), end.duration_since(t).as_secs_f64()));
        rec.rust = rust_counts(&lines);
        if let Err(e) = r {
            failed.push((e, rec.rust.1 > 0));
        }
    }
    if let Some(pytest) = pytest {
        match pytest.join() {
            Ok((lines, r, t, wall)) => {
                rec.phases.push(("Python: the tests (once the wheel is built: beside the lints)", since(start, t), wall));
                rec.python = python_counts(&lines);
                if let Err(e) = r {
                    failed.push((e, rec.python.1 > 0));
                }
            }
            Err(_) => failed.push(("the Python tests' thread panicked".into(), false)),
        }
    }
    if a.record {
        // Written once before the guide's build (which includes it: the
        // first record of a clone needs a file to include), once after.
        if let Err(e) = write_record(&rec, cold, start.elapsed().as_secs_f64(), &cargo, &py) {
            failed.push((e, false));
        }
    }
    let guide = rec.time(start, "the guide: generated tables checked, `mkdocs build --strict`", || {
        crate::docs::check(&root).map_err(|e| format!("cargo xtask docs --check:\n{e}"))?;
        if !python_ready {
            return Err("mkdocs build --strict not run: no Python environment".into());
        }
        run(
            Command::new(venv.join("bin/mkdocs")).current_dir(&root).env("NO_MKDOCS_2_WARNING", "1").args(["build", "--strict", "--quiet", "-f", "mkdocs.yml", "-d"]).arg(target.join("site")),
            "mkdocs build --strict (the guide; warnings are errors)",
        )
    });
    if let Err(e) = guide {
        failed.push((e, false));
    }
    if a.record {
        if let Err(e) = write_record(&rec, cold, start.elapsed().as_secs_f64(), &cargo, &py) {
            failed.push((e, false));
        }
    }
    for (e, _) in &failed {
        eprintln!("error: {e}");
    }
    let (detail, total) = verdict_lines(&rec, &failed, &not_run, a.python_only.then_some("the Rust tests and the lints (--python-only)"));
    println!("{detail}");
    println!("{total}");
    if failed.is_empty() {
        Ok(())
    } else {
        // The errors are printed above the verdict, which stays the last line.
        Err(crate::Failure::Reported)
    }
}
