//! `cargo xtask <study>` on bad input (issue 31 §6): negative numbers in
//! exponent form reach the study (clap took `-1e-10` for a flag), which
//! refuses them with its range message naming the flag, and the process
//! exits 2 (as clap's own errors and `signorini` do); a failure of the work
//! itself exits 1.

use std::process::Command;

fn xtask(args: &[&str], out: &std::path::Path) -> (i32, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_xtask")).args(args).arg("--out").arg(out).output().expect("the xtask binary starts");
    (o.status.code().unwrap_or(-1), String::from_utf8_lossy(&o.stderr).into_owned())
}

fn nowhere(name: &str) -> std::path::PathBuf {
    let p = std::env::temp_dir().join(format!("signorini-xtask-exit-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    p
}

#[test]
fn negative_numbers_in_exponent_form_get_the_range_message_and_exit_2() {
    let out = nowhere("bad");
    // (arguments, the flag, the range its study names)
    let cases: [(&[&str], &str, &str); 8] = [
        (&["lyapunov", "--perturbation", "-1e-10"], "--perturbation", "allowed 0 < perturbation < 1e-3"),
        (&["lyapunov", "--dts", "-1e-5"], "--dts", "(0, 1e-3]"),
        (&["lyapunov", "--omegas", "-2"], "--omegas", "(0, 100]"),
        (&["beam-statistics", "--dts", "5e-5,-1e-5"], "--dts", "(0, 1e-3]"),
        (&["beam-statistics", "--episode-gap", "-5e-3"], "--episode-gap", "[0, 1]"),
        (&["oscillator", "--transient", "-1e1"], "--transient", ">= 0"),
        (&["long-horizon", "--energy-ratios", "-1e-1"], "--energy-ratios", "> 0"),
        (&["courant1", "--t-end", "-6e0"], "--t-end", "allowed"),
    ];
    for (args, flag, range) in cases {
        let (code, err) = xtask(args, &out);
        assert_eq!(code, 2, "{args:?}: exit {code}, {err}");
        assert!(err.contains(flag) && err.contains(range), "{args:?}: {err}");
        assert!(!err.contains("unexpected argument"), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?}: {} was created", out.display());
    }
    // A negative count: clap refuses it naming the flag, exit 2.
    let (code, err) = xtask(&["beam-statistics", "--batches", "-5"], &out);
    assert!(code == 2 && err.contains("--batches") && !err.contains("unexpected argument"), "exit {code}: {err}");
}

#[test]
fn a_failure_after_valid_input_exits_1() {
    // Valid flags, an output folder that cannot be created (its parent is a file).
    let file = nowhere("file");
    std::fs::write(&file, "a file, not a folder").unwrap();
    let (code, err) = xtask(&["beam-statistics", "--dts", "5e-5", "--elements", "19", "--window", "10", "--batches", "10"], &file.join("sub"));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("cannot create"), "{err}");
    let _ = std::fs::remove_file(&file);
}
