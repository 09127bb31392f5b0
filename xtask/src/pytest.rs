//! `cargo xtask test`: every test of the project in one command — the Rust
//! workspace's (`cargo test --workspace --release`, the Python crate
//! excluded: maturin builds it with its own environment), then the Python
//! package built by maturin into a virtual environment this command creates
//! while the Rust tests build and run (`target/py-venv`, with maturin,
//! numpy, pytest, dask.distributed (the scale-out test) and matplotlib (the
//! examples) from the package index), then its pytest suite
//! (`python/tests`) and, beside it, the lints with warnings denied (`cargo
//! fmt --check`, `cargo clippy --workspace --all-targets -- -D warnings`,
//! `cargo doc --workspace --no-deps` with `RUSTDOCFLAGS=-D warnings`),
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

fn root() -> PathBuf {
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
            let line = String::from_utf8_lossy(&line).trim_end_matches('\r').to_string();
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
fn rust_counts(lines: &[String]) -> (u64, u64, u64) {
    lines.iter().filter_map(|l| l.find("test result:").map(|i| &l[i..])).fold((0, 0, 0), |(p, f, i), l| (p + count(l, "passed"), f + count(l, "failed"), i + count(l, "ignored")))
}

/// Passed, failed (errors included: a test that could not be collected or
/// set up) and skipped tests from pytest's summary line, its last line of
/// the form `1 failed, 113 passed, 2 skipped in 15.20s` (with `=` around
/// it or not).
fn python_counts(lines: &[String]) -> (u64, u64, u64) {
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
fn verdict_lines(rec: &Record, failed_phases: &[(String, bool)], not_run: &[&str], skipped: Option<&str>) -> (String, String) {
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
struct Record {
    phases: Vec<(&'static str, f64)>,
    rust: (u64, u64, u64),   // passed, failed, ignored
    python: (u64, u64, u64), // passed, failed, skipped
}

impl Record {
    fn time<T>(&mut self, name: &'static str, f: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
        let t = Instant::now();
        let r = f();
        self.phases.push((name, t.elapsed().as_secs_f64()));
        r
    }
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
    s.push_str(&format!("| Rust tests (`cargo test --workspace --release`) | {} | {} | {} |\n", rec.rust.0, rec.rust.1, rec.rust.2));
    s.push_str(&format!("| Python tests (pytest, `python/tests`) | {} | {} | {} |\n\n", rec.python.0, rec.python.1, rec.python.2));
    s.push_str("| phase of `cargo xtask test` | wall time |\n|---|---|\n");
    for (name, t) in &rec.phases {
        s.push_str(&format!("| {name} | {} |\n", minutes(*t)));
    }
    // The whole command: from the start of the `cargo` that built this
    // binary (on a fresh clone most of the workspace) and started it.
    // After the main job's build: `cargo xtask convergence` builds the same
    // `cargo xtask` binary (the workspace's libraries in release), so the
    // test command that follows it costs the phases above, this binary's
    // own run from its start.
    s.push_str(&format!("| **after the main job's build** (the phases above: `cargo xtask convergence` builds the same `cargo xtask` binary first) | **{}** |\n", minutes(total)));
    if let Some(whole) = since_cargo_started() {
        s.push_str(&format!("| **the whole `cargo xtask test`** (from the start of `cargo`: the `cargo xtask` binary's own build included) | **{}** |\n", minutes(whole)));
    }
    let _ = cargo;
    let path = root().join("docs/generated/test-record.md");
    std::fs::write(&path, s).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// The workspace's lints, warnings denied: formatting (`rustfmt.toml`),
/// clippy on every target (`[workspace.lints]` in Cargo.toml), and the API
/// docs (broken intra-doc links, bad HTML).
fn lints(cargo: &str, root: &Path) -> Result<(), String> {
    run(Command::new(cargo).current_dir(root).args(["fmt", "--all", "--check"]), "cargo fmt --check (run `cargo fmt --all`)")?;
    run(Command::new(cargo).current_dir(root).args(["clippy", "--workspace", "--all-targets", "--release", "--", "-D", "warnings"]), "cargo clippy -D warnings")?;
    run(Command::new(cargo).current_dir(root).env("RUSTDOCFLAGS", "-D warnings").args(["doc", "--workspace", "--no-deps", "--release"]), "cargo doc (warnings denied)")
}

/// The test environment: `target/py-venv` (created when absent) with the
/// build tools, the test dependencies and the guide's tools from the
/// package index (upgraded when newer ones are allowed).
fn python_env(py: &Path, venv: &Path) -> Result<(), String> {
    if !py.exists() {
        run(Command::new("python3").args(["-m", "venv"]).arg(venv), "python3 -m venv")?;
    }
    run(
        Command::new(py)
            .args(["-m", "pip", "install", "-q", "--disable-pip-version-check", "--upgrade", "maturin>=1.9.4,<2", "numpy", "pytest", "dask[distributed]", "matplotlib"])
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
    if !a.python_only {
        let (lines, r) = rec.time("Rust: build and run the tests", || {
            Ok(run_capture(Command::new(&cargo).current_dir(&root).args(["test", "--workspace", "--release", "--exclude", "signorini-py", "--no-fail-fast"]), "cargo test"))
        })?;
        rec.rust = rust_counts(&lines);
        if let Err(e) = r {
            failed.push((e, rec.rust.1 > 0));
        }
    }
    let env = match env.join() {
        Ok((r, t)) => {
            rec.phases.push(("Python: the environment and the packages (made while the Rust tests build and run)", t));
            r
        }
        Err(_) => Err("the Python environment's thread panicked".into()),
    };
    let wheel = env.and_then(|()| {
        rec.time("Python: build and install the wheel, build the command", || {
            let wheels = target.join("wheels");
            let _ = std::fs::remove_dir_all(&wheels);
            run(Command::new(venv.join("bin/maturin")).current_dir(&root).args(["build", "--release", "-m", "python/Cargo.toml", "-i"]).arg(&py).arg("-o").arg(&wheels), "maturin build")?;
            let wheel = std::fs::read_dir(&wheels)
                .map_err(|e| format!("{}: {e}", wheels.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .find(|p| p.extension().is_some_and(|x| x == "whl"))
                .ok_or("maturin wrote no wheel")?;
            run(Command::new(&py).args(["-m", "pip", "install", "-q", "--force-reinstall", "--no-deps"]).arg(&wheel), "pip install the wheel")?;
            // The tests compare with the `signorini` command's files: build it (a
            // no-op after `cargo test`) and tell them where it is.
            run(Command::new(&cargo).current_dir(&root).args(["build", "--release", "-p", "signorini-cli", "--bin", "signorini"]), "cargo build signorini")
        })
    });
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
    // The Python tests and the lints side by side: pytest runs built
    // programs and never cargo (which the lints hold), and on two cores
    // each fills the other's gaps (clippy and rustdoc work through the
    // workspace's crates largely one at a time).
    let pytest = python_ready.then(|| {
        let mut cmd = Command::new(&py);
        cmd.current_dir(&root).env("SIGNORINI_BIN", target.join("release/signorini")).env("SIGNORINI_XTASK", &xtask).args(["-m", "pytest", "-q", "python/tests"]);
        std::thread::spawn(move || {
            let t = Instant::now();
            let (lines, r) = run_capture(&mut cmd, "pytest");
            (lines, r, t.elapsed().as_secs_f64())
        })
    });
    if !a.python_only {
        if let Err(e) = rec.time("lints: `cargo fmt --check`, `cargo clippy -D warnings`, `cargo doc -D warnings` (the Python tests run beside them)", || lints(&cargo, &root)) {
            failed.push((e, false));
        }
    }
    if let Some(pytest) = pytest {
        match pytest.join() {
            Ok((lines, r, t)) => {
                rec.phases.push(("Python: the tests (beside the lints)", t));
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
    let guide = rec.time("the guide: generated tables checked, `mkdocs build --strict`", || {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(s: &str) -> Vec<String> {
        s.lines().map(String::from).collect()
    }

    /// Issue 31 §12: the command ends with one line totalling every test,
    /// in the form CI reads, after the verdict per language.
    #[test]
    fn the_last_line_totals_every_test() {
        let rust = lines(
            "running 3 tests\ntest a ... ok\ntest result: ok. 3 passed; 0 failed; 1 ignored; 0 measured; 0 filtered out; finished in 0.1s\n\
             running 0 tests\ntest result: ok. 0 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out\n\
             test result: FAILED. 438 passed; 2 failed; 0 ignored; 0 measured; 0 filtered out; finished in 9s",
        );
        assert_eq!(rust_counts(&rust), (441, 2, 1));
        let py = lines("....F..s\nFAILED python/tests/test_x.py::test_y - AssertionError: 2 passed, 9 failed in 1.0s?\n1 failed, 110 passed, 3 skipped, 1 error in 15.20s");
        assert_eq!(python_counts(&py), (110, 2, 3));
        assert_eq!(python_counts(&lines("========= 114 passed in 15.32s =========")), (114, 0, 0));
        // Past a minute pytest adds the time as h:mm:ss.
        assert_eq!(python_counts(&lines("245 passed in 81.19s (0:01:21)")), (245, 0, 0));
        assert_eq!(python_counts(&lines("==== 1 failed, 244 passed in 95.02s (0:01:35) ====")), (244, 1, 0));
        let rec = Record { phases: Vec::new(), rust: (443, 0, 1), python: (114, 0, 0) };
        let (detail, total) = verdict_lines(&rec, &[], &[], None);
        assert_eq!(detail, "signorini tests: PASS — 443 passed, 0 failed, 1 ignored (Rust); 114 passed, 0 failed, 0 skipped (Python)");
        assert_eq!(total, "tests: 557 passed, 0 failed");
        // A failed test fails the verdict; its phase is not counted twice.
        let rec = Record { phases: Vec::new(), rust: (441, 2, 1), python: (114, 0, 0) };
        let (detail, total) = verdict_lines(&rec, &[("cargo test failed (exit status: 101)".into(), true)], &[], None);
        assert!(detail.starts_with("signorini tests: FAIL — 441 passed, 2 failed") && detail.ends_with("; failed: cargo test failed (exit status: 101)"), "{detail}");
        assert_eq!(total, "tests: 555 passed, 2 failed");
        // A lint that fails, and Python that could not run: failed, never "0 failed".
        let rec = Record { phases: Vec::new(), rust: (443, 0, 1), python: (0, 0, 0) };
        let (detail, total) = verdict_lines(&rec, &[("cargo clippy -D warnings failed".into(), false), ("maturin build failed".into(), false)], &["the Python tests"], None);
        assert!(detail.starts_with("signorini tests: FAIL") && detail.contains("not run: the Python tests"), "{detail}");
        assert_eq!(total, "tests: 443 passed, 3 failed");
    }

    /// The packages of one build as `cargo tree` resolves them: each
    /// package (name, version, source) with the feature sets it is built
    /// with (a package built for the host and for the target has two).
    fn features(args: &[&str]) -> std::collections::BTreeMap<String, std::collections::BTreeSet<String>> {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let out = Command::new(cargo).current_dir(root()).arg("tree").args(args).args(["--prefix", "none", "--no-dedupe", "-f", "{p}|{f}"]).output().expect("cargo tree starts");
        assert!(out.status.success(), "cargo tree {args:?}: {}", String::from_utf8_lossy(&out.stderr));
        let mut map = std::collections::BTreeMap::<String, std::collections::BTreeSet<String>>::new();
        for line in String::from_utf8_lossy(&out.stdout).lines() {
            let Some((p, f)) = line.split_once('|') else { continue };
            let p = p.replace(" (proc-macro)", "").replace(" (*)", "");
            map.entry(p.trim().to_string()).or_default().insert(f.trim().to_string());
        }
        map
    }

    /// The README's test command reuses what `cargo xtask convergence`
    /// built, and the wheel what the tests built (ARCHITECTURE.md, "One
    /// set of dependency artifacts"): every package the xtask binary's
    /// build and the wheel's share with the workspace's test build is
    /// resolved to the same features (a feature one build adds — syn 3's
    /// `extra-traits`, turned on by the wheel's pyo3 macros — changes that
    /// package's artifact and recompiles everything built on it: thiserror,
    /// serde, clap and every workspace crate).
    #[test]
    fn the_main_job_the_tests_and_the_wheel_build_the_same_crates() {
        let tests = features(&["--workspace", "--exclude", "signorini-py", "-e", "normal,build,dev"]);
        for (build, args) in [("cargo xtask convergence", ["-p", "xtask", "-e", "normal,build"]), ("the wheel", ["-p", "signorini-py", "-e", "normal,build"])] {
            let other = features(&args);
            let differ: Vec<String> = other.iter().filter_map(|(p, f)| tests.get(p).filter(|g| *g != f).map(|g| format!("{p}: {f:?} in {build}, {g:?} in the tests"))).collect();
            assert!(differ.is_empty(), "pin these features where {build} sees them:\n{}", differ.join("\n"));
            assert!(other.keys().filter(|p| tests.contains_key(*p)).count() > 50, "{build}: too few packages shared with the tests");
        }
    }
}
