//! `cargo xtask test`: every test of the project in one command — the Rust
//! workspace's (`cargo test --workspace --release`, the Python crate
//! excluded: maturin builds it with its own environment), then the lints
//! with warnings denied (`cargo fmt --check`, `cargo clippy --workspace
//! --all-targets -- -D warnings`, `cargo doc --workspace --no-deps` with
//! `RUSTDOCFLAGS=-D warnings`), then the Python
//! package built by maturin into a virtual environment this command creates
//! (`target/py-venv`, with maturin, numpy, pytest, dask.distributed (the
//! scale-out test) and matplotlib (the examples) from the package index)
//! and its pytest suite (`python/tests`), then the user guide: the
//! generated tables checked against `data/reference` (`cargo xtask docs
//! --check`) and `mkdocs build --strict` (MkDocs, the Material theme and
//! mkdocstrings from the package index into the same environment) into
//! `target/site`.
//!
//! `--record` also counts the tests and times each phase, and writes them
//! to `docs/generated/test-record.md`: the one place those numbers live.

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

/// [`run`], with stdout passed through line by line and kept when
/// `capture` (else inherited, and nothing kept).
fn run_capture(cmd: &mut Command, what: &str, capture: bool) -> Result<Vec<String>, String> {
    if !capture {
        return run(cmd, what).map(|()| Vec::new());
    }
    let mut child = cmd.stdout(Stdio::piped()).spawn().map_err(|e| format!("{what}: cannot start: {e}"))?;
    let mut lines = Vec::new();
    if let Some(out) = child.stdout.take() {
        for line in BufReader::new(out).lines() {
            let line = line.map_err(|e| format!("{what}: {e}"))?;
            println!("{line}");
            lines.push(line);
        }
    }
    let status = child.wait().map_err(|e| format!("{what}: {e}"))?;
    if status.success() {
        Ok(lines)
    } else {
        Err(format!("{what} failed ({status})"))
    }
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
    s.push_str(&format!("| **`cargo xtask test`** (the `cargo xtask` binary's own build not included) | **{}** |\n", minutes(total)));
    // `.ci/run` exports the time it started: the whole run, the build of
    // the xtask binary (on a fresh clone: most of the workspace) included.
    let ci = std::env::var("SIGNORINI_RECORD_START").ok().and_then(|v| v.trim().parse::<u64>().ok());
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
    if let Some(t0) = ci.filter(|t0| *t0 <= now) {
        s.push_str(&format!("| **the whole `.ci/run`** (the `cargo xtask` binary built too) | **{}** |\n", minutes((now - t0) as f64)));
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

/// `cargo xtask test`.
pub fn run_tests(a: Args) -> Result<(), String> {
    let start = Instant::now();
    let root = root();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let target = std::env::var("CARGO_TARGET_DIR").map(PathBuf::from).unwrap_or_else(|_| root.join("target"));
    let venv = target.join("py-venv");
    let py = venv.join("bin/python");
    // "Cold": no test binary and no environment yet (the xtask binary
    // itself is necessarily built).
    let cold = !venv.exists() && !target.join("release/deps").read_dir().map(|d| d.filter_map(|e| e.ok()).any(|e| e.file_name().to_string_lossy().starts_with("convergence-"))).unwrap_or(false);
    let mut rec = Record::default();
    if !a.python_only {
        let lines = rec.time("Rust: build and run the tests", || {
            run_capture(Command::new(&cargo).current_dir(&root).args(["test", "--workspace", "--release", "--exclude", "signorini-py"]), "cargo test", a.record)
        })?;
        for l in lines.iter().filter(|l| l.starts_with("test result:")) {
            rec.rust.0 += count(l, "passed");
            rec.rust.1 += count(l, "failed");
            rec.rust.2 += count(l, "ignored");
        }
    }
    if !a.python_only {
        rec.time("lints: `cargo fmt --check`, `cargo clippy -D warnings`, `cargo doc -D warnings`", || lints(&cargo, &root))?;
    }
    rec.time("Python: the environment and the packages", || {
        if !py.exists() {
            run(Command::new("python3").args(["-m", "venv"]).arg(&venv), "python3 -m venv")?;
        }
        run(
            Command::new(&py).args(["-m", "pip", "install", "-q", "--upgrade", "maturin>=1.9.4,<2", "numpy", "pytest", "dask[distributed]", "matplotlib"]).args(GUIDE_PACKAGES),
            "pip install maturin numpy pytest dask[distributed] matplotlib mkdocs mkdocs-material mkdocstrings[python]",
        )
    })?;
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
    })?;
    let lines = rec.time("Python: the tests", || {
        run_capture(
            Command::new(&py).current_dir(&root).env("SIGNORINI_BIN", target.join("release/signorini")).env("SIGNORINI_XTASK", std::env::current_exe().unwrap_or_default()).args([
                "-m",
                "pytest",
                "-q",
                "python/tests",
            ]),
            "pytest",
            a.record,
        )
    })?;
    for l in lines.iter().filter(|l| l.contains(" passed") || l.contains(" failed")) {
        rec.python.0 += count(l, "passed");
        rec.python.1 += count(l, "failed");
        rec.python.2 += count(l, "skipped");
    }
    if a.record {
        // Written once before the guide's build (which includes it: the
        // first record of a clone needs a file to include), once after.
        write_record(&rec, cold, start.elapsed().as_secs_f64(), &cargo, &py)?;
    }
    rec.time("the guide: generated tables checked, `mkdocs build --strict`", || {
        crate::docs::check(&root).map_err(|e| format!("cargo xtask docs --check:\n{e}"))?;
        run(
            Command::new(venv.join("bin/mkdocs")).current_dir(&root).env("NO_MKDOCS_2_WARNING", "1").args(["build", "--strict", "--quiet", "-f", "mkdocs.yml", "-d"]).arg(target.join("site")),
            "mkdocs build --strict (the guide; warnings are errors)",
        )
    })?;
    if a.record {
        write_record(&rec, cold, start.elapsed().as_secs_f64(), &cargo, &py)?;
    }
    Ok(())
}
