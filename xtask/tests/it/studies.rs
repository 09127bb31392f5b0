//! The tests of `xtask::studies` (xtask/src/studies.rs).

use signorini_studies::long_horizon;
use xtask::studies::*;
use xtask::Failure;

/// Every flag each study had when its flags were written by hand (before
/// issue 33): the flags are a contract, kept when they came to be built
/// from the `Config`s. The switches take no value.
const FLAGS: [(&str, &[&str]); 11] = [
    ("convergence", &["benchmark", "schemes", "masses", "levels", "ratio", "t-end", "out", "norms", "reduce", "degree", "clean", "reference"]),
    ("weighted", &["out", "t-end"]),
    ("beam", &["out", "scenes", "force", "penalty-dts"]),
    ("beam-obstacles", &["out", "gap", "beta", "t-end", "dts", "j", "js", "j-dt"]),
    ("oscillator", &["out", "omegas", "dts", "transient", "record"]),
    ("work-precision", &["out", "levels", "degrees", "modes", "beam-dts", "beam-ref-dt", "beam-window", "beam-t-end", "beam-stat-dts", "beam-stat-ref-dt", "beam-stat-window", "reference", "repeats"]),
    ("stress", &["out", "steps", "elements", "seed"]),
    ("courant1", &["out", "benchmarks", "levels", "t-end"]),
    ("long-horizon", &["out", "runs", "levels", "ratio", "t-end", "no-energy", "energy-runs", "energy-all", "energy-ratios", "energy-m", "energy-t-end"]),
    ("lyapunov", &["out", "scenes", "refine", "dts", "elements", "omegas", "perturbation", "transient", "window", "per-period", "batches"]),
    ("beam-statistics", &["out", "scenes", "dts", "elements", "transient", "window", "batches", "episode-gap"]),
];
const SWITCHES: [&str; 4] = ["clean", "force", "no-energy", "energy-all"];

#[test]
fn every_flag_of_before_is_there() {
    let entries = entries();
    assert_eq!(entries.iter().map(|e| e.name()).collect::<Vec<_>>(), FLAGS.iter().map(|f| f.0).collect::<Vec<_>>());
    for (sub, flags) in FLAGS {
        let cmd = entries.iter().find(|e| e.name() == sub).expect("the study").command();
        for flag in flags {
            let arg = cmd.get_arguments().find(|a| a.get_long() == Some(flag)).unwrap_or_else(|| panic!("{sub}: --{flag} is gone"));
            assert_eq!(arg.get_num_args().is_some_and(|n| n.takes_values()), !SWITCHES.contains(flag), "{sub} --{flag}");
        }
    }
}

#[test]
fn a_list_flag_may_be_repeated_and_a_switch_on_by_default_turns_off() {
    let m = command::<long_horizon::Config>("").get_matches_from(["long-horizon", "--levels", "10,20", "--levels", "40", "--no-energy", "--t-end", "-3"]);
    let c = config::<long_horizon::Config>(&m).expect_err("t-end -3 is refused");
    assert!(matches!(&c, Failure::Input(m) if m.starts_with("--t-end -3: allowed")), "{c:?}");
    let m = command::<long_horizon::Config>("").get_matches_from(["long-horizon", "--levels", "10,20", "--levels", "40", "--no-energy"]);
    let c = config::<long_horizon::Config>(&m).expect("valid");
    assert_eq!(c.levels, vec![10, 20, 40]);
    assert!(!c.energy);
}
