//! The tests of `xtask::pytest` (xtask/src/pytest.rs).

use std::process::Command;
use xtask::pytest::*;

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

/// The test executables are read from cargo's own messages (lines as
/// `cargo test --no-run --message-format json` writes them, copied from
/// cargo 1.95): a test harness is run, the command built for the
/// integration tests (an executable whose target is testable but whose
/// profile is not the test profile) and a library (no executable) are
/// not; escaped characters in a path are read back.
#[test]
fn the_test_binaries_are_the_test_profiles_executables() {
    let lib = r##"{"reason":"compiler-artifact","package_id":"path+file:///w/crates/exact#signorini-exact@0.1.0","manifest_path":"/w/crates/exact/Cargo.toml","target":{"kind":["lib"],"crate_types":["lib"],"name":"signorini_exact","src_path":"/w/crates/exact/src/lib.rs","edition":"2021","doc":true,"doctest":true,"test":true},"profile":{"opt_level":"3","debuginfo":"line-tables-only","debug_assertions":false,"overflow_checks":false,"test":false},"features":[],"filenames":["/w/target/release/deps/libsignorini_exact-1.rlib"],"executable":null,"fresh":true}"##;
    let unit = r##"{"reason":"compiler-artifact","package_id":"path+file:///w/crates/exact#signorini-exact@0.1.0","manifest_path":"/w/crates/exact/Cargo.toml","target":{"kind":["lib"],"crate_types":["lib"],"name":"signorini_exact","src_path":"/w/crates/exact/src/lib.rs","edition":"2021","doc":true,"doctest":true,"test":true},"profile":{"opt_level":"3","debuginfo":"line-tables-only","debug_assertions":false,"overflow_checks":false,"test":true},"features":[],"filenames":["/w/target/release/deps/signorini_exact-58c1"],"executable":"/w/target/release/deps/signorini_exact-58c1","fresh":false}"##;
    let bin = r##"{"reason":"compiler-artifact","package_id":"path+file:///w/crates/cli#signorini-cli@0.1.0","manifest_path":"/w/crates/cli/Cargo.toml","target":{"kind":["bin"],"crate_types":["bin"],"name":"signorini","src_path":"/w/crates/cli/src/main.rs","edition":"2021","doc":true,"doctest":false,"test":true},"profile":{"opt_level":"3","debuginfo":"line-tables-only","debug_assertions":false,"overflow_checks":false,"test":false},"features":[],"filenames":["/w/target/release/signorini"],"executable":"/w/target/release/signorini","fresh":true}"##;
    let it = r##"{"reason":"compiler-artifact","package_id":"path+file:///w/a \"b\"#signorini-cli@0.1.0","manifest_path":"/w/a \"b\"/Cargo.toml","target":{"kind":["test"],"crate_types":["bin"],"name":"it","src_path":"/w/a \"b\"/tests/it/main.rs","edition":"2021","doc":false,"doctest":false,"test":true},"profile":{"opt_level":"3","debuginfo":"line-tables-only","debug_assertions":false,"overflow_checks":false,"test":true},"features":[],"filenames":["/w/target/release/deps/it-8d5c"],"executable":"/w/target/release/deps/it-8d5c","fresh":false}"##;
    let done = r##"{"reason":"build-finished","success":true}"##;
    let lines: Vec<String> = [lib, unit, bin, it, done].iter().map(|s| s.to_string()).collect();
    let bins = xtask::pytest::test_binaries(&lines).expect("two test executables");
    let want = [("/w/target/release/deps/signorini_exact-58c1", "/w/crates/exact", "src/lib.rs"), ("/w/target/release/deps/it-8d5c", "/w/a \"b\"", "tests/it/main.rs")];
    assert_eq!(bins.len(), want.len(), "{bins:?}");
    for (b, (exe, dir, src)) in bins.iter().zip(want) {
        assert_eq!((b.exe.to_str(), b.dir.to_str(), b.src.as_str()), (Some(exe), Some(dir), src));
    }
}

/// Messages with no test executable (a format of cargo's that is not read,
/// or a build of nothing) are an error, not a run of no test that passes.
#[test]
fn no_test_executable_is_an_error() {
    let bin = r##"{"reason":"compiler-artifact","package_id":"path+file:///w/crates/cli#signorini-cli@0.1.0","manifest_path":"/w/crates/cli/Cargo.toml","target":{"kind":["bin"],"crate_types":["bin"],"name":"signorini","src_path":"/w/crates/cli/src/main.rs","edition":"2021","doc":true,"doctest":false,"test":true},"profile":{"opt_level":"3","debuginfo":"line-tables-only","debug_assertions":false,"overflow_checks":false,"test":false},"features":[],"filenames":["/w/target/release/signorini"],"executable":"/w/target/release/signorini","fresh":true}"##;
    for lines in [vec![], vec![bin.to_string(), r#"{"reason":"build-finished","success":true}"#.to_string()]] {
        let e = xtask::pytest::test_binaries(&lines).expect_err("no test executable");
        assert!(e.contains("no test executable"), "{e}");
    }
}

/// Each test executable is handed to the runners as soon as cargo writes
/// its message, not when the build ends: the binaries built first run
/// while cargo compiles the rest. Here `cargo` is a shell that writes one
/// test artifact's message, then waits until this test has received it
/// (a file the test creates), and fails if it never comes (after a minute,
/// a bound only against a hang): a build that handed the executables over
/// only at its end would hand this one over after the shell failed.
#[cfg(unix)]
/// The tests of a package with a binary of its own (the CLI's tests run
/// `signorini`) are handed over only once cargo has ended, when every
/// binary is linked: a fake cargo writes such a test's message, then a
/// marker, then exits; the executable must come after the marker. Handed
/// over at once, as other tests are, every CLI test failed on a fresh clone
/// (the binary not yet there).
#[test]
fn tests_of_a_package_with_binaries_wait_for_the_build_to_end() {
    let dir = std::env::temp_dir().join(format!("signorini-build-bins-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("pkg/src")).expect("a scratch package");
    std::fs::write(dir.join("pkg/Cargo.toml"), "[package]\nname = \"pkg\"\n\n[[bin]]\nname = \"pkg\"\npath = \"src/main.rs\"\n").expect("its manifest");
    assert!(has_binaries(&dir.join("pkg")) && !has_binaries(&dir), "the scratch package has a binary, the folder none");
    let (pkg, marker) = (dir.join("pkg"), dir.join("ended"));
    let it = format!(
        r##"{{"reason":"compiler-artifact","package_id":"pkg","manifest_path":"{}/Cargo.toml","target":{{"kind":["test"],"crate_types":["bin"],"name":"it","src_path":"{}/tests/it/main.rs","test":true}},"profile":{{"opt_level":"3","test":true}},"filenames":["/w/it-1"],"executable":"/w/it-1","fresh":false}}"##,
        pkg.display(),
        pkg.display()
    );
    let script = format!("printf '%s\\n' '{it}'; sleep 0.5; : > '{}'", marker.display());
    let (tx, rx) = std::sync::mpsc::channel();
    let build = std::thread::spawn(move || build_tests("sh", std::path::Path::new("."), &["-c", &script, "sh"], tx));
    let b = rx.recv().expect("the executable, handed over");
    assert!(marker.exists(), "handed over before the build ended");
    assert_eq!(b.src, "tests/it/main.rs");
    assert_eq!(build.join().expect("the build's thread"), Ok(()));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn each_test_executable_runs_as_soon_as_it_is_built() {
    let dir = std::env::temp_dir().join(format!("signorini-build-tests-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let flag = dir.join("received");
    let it = r##"{"reason":"compiler-artifact","package_id":"path+file:///w/crates/cli#signorini-cli@0.1.0","manifest_path":"/w/crates/cli/Cargo.toml","target":{"kind":["test"],"crate_types":["bin"],"name":"it","src_path":"/w/crates/cli/tests/it/main.rs","edition":"2021","doc":false,"doctest":false,"test":true},"profile":{"opt_level":"3","debuginfo":"line-tables-only","debug_assertions":false,"overflow_checks":false,"test":true},"features":[],"filenames":["/w/target/release/deps/it-8d5c"],"executable":"/w/target/release/deps/it-8d5c","fresh":false}"##;
    let script = format!("printf '%s\\n' '{it}'; i=0; while [ ! -e '{}' ]; do i=$((i+1)); [ $i -gt 600 ] && exit 1; sleep 0.1; done", flag.display());
    let (tx, rx) = std::sync::mpsc::channel();
    let build = std::thread::spawn(move || build_tests("sh", std::path::Path::new("."), &["-c", &script, "sh"], tx));
    let b = rx.recv().expect("the executable, handed over");
    std::fs::write(&flag, "").expect("the flag");
    assert_eq!((b.exe.to_str(), b.src.as_str()), (Some("/w/target/release/deps/it-8d5c"), "tests/it/main.rs"));
    assert_eq!(build.join().expect("the build's thread"), Ok(()), "the build ends once the executable was received");
    assert!(rx.recv().is_err(), "one executable only, and the channel closed");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cargo doc` in the lints reuses clippy's checks of the workspace's
/// libraries only with the wrapper and the arguments `cargo clippy` itself
/// sets: asked of the installed `cargo-clippy`, run with a stand-in cargo
/// that prints the environment it was given.
#[cfg(unix)]
#[test]
fn the_docs_see_clippy_s_own_wrapper_and_arguments() {
    use std::os::unix::fs::PermissionsExt;
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| env!("CARGO").to_string());
    let bin = std::path::Path::new(&cargo).parent().expect("the toolchain's bin directory");
    let dir = std::env::temp_dir().join(format!("signorini-clippy-env-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let fake = dir.join("cargo");
    std::fs::write(&fake, "#!/bin/sh\nprintf '%s\\n' \"RUSTC_WORKSPACE_WRAPPER=$RUSTC_WORKSPACE_WRAPPER\" \"CLIPPY_ARGS=$CLIPPY_ARGS\"\n").expect("the stand-in");
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).expect("executable");
    let out = Command::new(bin.join("cargo-clippy")).args(["clippy", "--release", "--", "-D", "warnings"]).env("CARGO", &fake).output().expect("cargo-clippy runs");
    let _ = std::fs::remove_dir_all(&dir);
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let driver = clippy_driver(&cargo).expect("clippy-driver beside cargo");
    let want = format!("RUSTC_WORKSPACE_WRAPPER={}\nCLIPPY_ARGS={}\n", driver.display(), clippy_env_args(&["-D", "warnings"]));
    assert_eq!(text, want, "stderr: {}", String::from_utf8_lossy(&out.stderr));
}
