//! Packages that skip the unit-test harness: a `[lib]` or `[[bin]]` with
//! `test = false` in its manifest is not compiled a second time as a test
//! binary by `cargo test` (the README's test command's largest saving in
//! a package without unit tests). The price is that a `#[test]` written in
//! such a package's `src/` would never run: `cargo xtask docs --check`
//! fails on one, naming the file, so the manifest and the sources agree.

use std::path::{Path, PathBuf};

/// The workspace's package folders: the root (the facade) and `crates/*`.
fn packages(root: &Path) -> Result<Vec<PathBuf>, String> {
    let mut dirs = vec![root.to_path_buf()];
    let crates = root.join("crates");
    let mut sub: Vec<PathBuf> =
        std::fs::read_dir(&crates).map_err(|e| format!("{}: {e}", crates.display()))?.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.join("Cargo.toml").is_file()).collect();
    sub.sort();
    dirs.extend(sub);
    Ok(dirs)
}

/// Whether a manifest turns the test harness off for one of its targets
/// (`test = false` inside a `[lib]` or `[[bin]]` table).
pub fn skips_harness(manifest: &str) -> bool {
    let mut in_target = false;
    for line in manifest.lines() {
        let l = line.trim();
        if l.starts_with('[') {
            in_target = l == "[lib]" || l == "[[bin]]";
        } else if in_target && l.split('#').next().unwrap_or("").replace(' ', "") == "test=false" {
            return true;
        }
    }
    false
}

/// Whether Rust source declares a unit test (`#[test]` or `#[cfg(test)]`),
/// comments aside.
pub fn declares_tests(source: &str) -> bool {
    source.lines().map(|l| l.split("//").next().unwrap_or("").replace(' ', "")).any(|l| l.contains("#[test]") || l.contains("#[cfg(test)]"))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The files of packages that skip the harness yet declare unit tests.
pub fn check(root: &Path) -> Result<Vec<String>, String> {
    let mut bad = Vec::new();
    for dir in packages(root)? {
        let manifest = dir.join("Cargo.toml");
        let text = std::fs::read_to_string(&manifest).map_err(|e| format!("{}: {e}", manifest.display()))?;
        if !skips_harness(&text) {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&dir.join("src"), &mut files);
        files.sort();
        for f in files {
            if std::fs::read_to_string(&f).is_ok_and(|s| declares_tests(&s)) {
                let rel = f.strip_prefix(root).unwrap_or(&f).display().to_string();
                bad.push(format!("{rel} declares unit tests, but its package's manifest says `test = false` (move them to tests/, or remove the line)"));
            }
        }
    }
    Ok(bad)
}
