//! The tests of `xtask::unit_tests` (xtask/src/unit_tests.rs).

use std::path::Path;
use xtask::unit_tests::*;

#[test]
fn a_lib_or_bin_with_test_false_is_seen_and_other_tables_are_not() {
    assert!(skips_harness("[package]\nname = \"a\"\n\n[lib]\ntest = false\n"));
    assert!(skips_harness("[[bin]]\nname = \"a\"\ntest=false # none\n"));
    assert!(!skips_harness("[lib]\ndoctest = false\n[profile.test]\ntest = false\n"));
    assert!(!skips_harness("[package]\ntest = false\n"));
}

#[test]
fn unit_tests_are_seen_in_code_not_in_comments() {
    assert!(declares_tests("#[cfg(test)]\nmod tests {}\n"));
    assert!(declares_tests("    #[test]\n    fn f() {}\n"));
    assert!(!declares_tests("// #[test] is not here\nfn f() {}\n"));
}

#[test]
fn the_workspace_as_committed_passes_and_a_planted_test_fails() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    assert_eq!(check(root).unwrap(), Vec::<String>::new());
    // A copy of a package that skips the harness, with a unit test planted.
    let tmp = std::env::temp_dir().join(format!("xtask-unit-tests-{}", std::process::id()));
    let pkg = tmp.join("crates/fem");
    std::fs::create_dir_all(pkg.join("src")).unwrap();
    std::fs::copy(root.join("crates/fem/Cargo.toml"), pkg.join("Cargo.toml")).unwrap();
    std::fs::copy(root.join("Cargo.toml"), tmp.join("Cargo.toml")).unwrap();
    std::fs::write(pkg.join("src/lib.rs"), "#[cfg(test)]\nmod t {}\n").unwrap();
    let bad = check(&tmp).unwrap();
    std::fs::remove_dir_all(&tmp).unwrap();
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(bad[0].starts_with("crates/fem/src/lib.rs"), "{bad:?}");
}
