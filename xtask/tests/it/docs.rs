//! The tests of `xtask::docs` (xtask/src/docs.rs).

use xtask::docs::*;

#[test]
fn slugs_are_githubs() {
    assert_eq!(slug(" 7.2 θ-method"), "72-θ-method");
    assert_eq!(slug(" 2.4 The uniform P1 bar's κ_h in closed form"), "24-the-uniform-p1-bars-κ_h-in-closed-form");
    assert_eq!(slug(" 5.1 `bar-dirichlet`: the Signorini–Dirichlet bar"), "51-bar-dirichlet-the-signorinidirichlet-bar");
}

#[test]
fn a_broken_link_and_a_long_readme_fail() {
    let root = root();
    let dir = std::env::temp_dir().join(format!("signorini-docs-check-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("docs")).unwrap();
    std::fs::write(dir.join("docs/theory.md"), "# T\n\n## 7.2 θ-method\n").unwrap();
    std::fs::write(dir.join("README.md"), "[a](docs/theory.md#72-θ-method) [b](docs/theory.md#nope) [c](docs/none.md)\n").unwrap();
    let bad = check_links(&dir, "README.md");
    assert_eq!(bad.len(), 2, "{bad:?}");
    assert!(bad[0].contains("#nope") && bad[1].contains("docs/none.md"), "{bad:?}");
    assert!(!readme_rules(&"x\n".repeat(201)).is_empty());
    assert!(readme_rules("# s\n\n```sh\ncargo xtask convergence\ncargo xtask test\n```\n").is_empty());
    assert!(!readme_rules("# s\n\n```sh\ncargo xtask test\ncargo xtask convergence\n```\n").is_empty());
    let readme = "```rust\nlet x = 1;\n```\n";
    assert!(readme_rust_is_tested(readme, "    // README quick start: begin\n    let x = 1;\n    // README quick start: end\n").is_empty());
    assert!(!readme_rust_is_tested(readme, "    // README quick start: begin\n    let x = 2;\n    // README quick start: end\n").is_empty());
    let _ = std::fs::remove_dir_all(&dir);
    let _ = root;
}
