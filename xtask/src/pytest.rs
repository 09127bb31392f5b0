//! `cargo xtask test`: every test of the project in one command — the Rust
//! workspace's (`cargo test --workspace --release`, the Python crate
//! excluded: maturin builds it with its own environment), then the Python
//! package built by maturin into a virtual environment this command creates
//! (`target/py-venv`, with maturin, numpy, pytest, dask.distributed (the
//! scale-out test) and matplotlib (the examples) from the package index)
//! and its pytest suite (`python/tests`).

use std::path::PathBuf;
use std::process::Command;

/// Arguments of `cargo xtask test`.
#[derive(clap::Args)]
pub struct Args {
    /// Skip the Rust tests (only build the package and run pytest).
    #[arg(long)]
    python_only: bool,
}

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

/// `cargo xtask test`.
pub fn run_tests(a: Args) -> Result<(), String> {
    let root = root();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    if !a.python_only {
        run(Command::new(&cargo).current_dir(&root).args(["test", "--workspace", "--release", "--exclude", "signorini-py"]), "cargo test")?;
    }
    let target = std::env::var("CARGO_TARGET_DIR").map(PathBuf::from).unwrap_or_else(|_| root.join("target"));
    let venv = target.join("py-venv");
    let py = venv.join("bin/python");
    if !py.exists() {
        run(Command::new("python3").args(["-m", "venv"]).arg(&venv), "python3 -m venv")?;
    }
    run(Command::new(&py).args(["-m", "pip", "install", "-q", "--upgrade", "maturin>=1.9.4,<2", "numpy", "pytest", "dask[distributed]", "matplotlib"]), "pip install maturin numpy pytest dask[distributed] matplotlib")?;
    let wheels = target.join("wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    run(
        Command::new(venv.join("bin/maturin")).current_dir(&root).args(["build", "--release", "-m", "python/Cargo.toml", "-i"]).arg(&py).arg("-o").arg(&wheels),
        "maturin build",
    )?;
    let wheel = std::fs::read_dir(&wheels).map_err(|e| format!("{}: {e}", wheels.display()))?.filter_map(|e| e.ok().map(|e| e.path())).find(|p| p.extension().is_some_and(|x| x == "whl")).ok_or("maturin wrote no wheel")?;
    run(Command::new(&py).args(["-m", "pip", "install", "-q", "--force-reinstall", "--no-deps"]).arg(&wheel), "pip install the wheel")?;
    // The tests compare with the `signorini` command's files: build it (a
    // no-op after `cargo test`) and tell them where it is.
    run(Command::new(&cargo).current_dir(&root).args(["build", "--release", "-p", "signorini-cli", "--bin", "signorini"]), "cargo build signorini")?;
    run(Command::new(&py).current_dir(&root).env("SIGNORINI_BIN", target.join("release/signorini")).env("SIGNORINI_XTASK", std::env::current_exe().unwrap_or_default()).args(["-m", "pytest", "-q", "python/tests"]), "pytest")?;
    Ok(())
}
