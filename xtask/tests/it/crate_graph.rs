//! The tests of `xtask::crate_graph` (xtask/src/crate_graph.rs).

use xtask::crate_graph::*;

// A trimmed `cargo tree` output, written by hand: a third-party
// dependency, a repeated root, and a path crate outside the workspace.
const TREE: &str = "0signorini-exact v0.1.0 (/w/crates/exact)\n1thiserror v2.0.1\n\n0signorini-norms v0.1.0 (/w/crates/norms)\n1signorini-exact v0.1.0 (/w/crates/exact)\n1outside v0.1.0 (/elsewhere)\n\n0signorini-contact v0.1.0 (/w/crates/contact)\n\n0signorini-cli v0.1.0 (/w/crates/cli)\n1signorini-norms v0.1.0 (/w/crates/norms)\n1clap v4.5.0\n";

fn graph_of(edges: &[(&str, &[&str])]) -> Graph {
    edges.iter().map(|(k, v)| (k.to_string(), v.iter().map(|s| s.to_string()).collect())).collect()
}

#[test]
fn parse_keeps_workspace_edges_only() {
    let want = graph_of(&[("signorini-cli", &["signorini-norms"]), ("signorini-contact", &[]), ("signorini-exact", &[]), ("signorini-norms", &["signorini-exact"])]);
    assert_eq!(parse(TREE), want);
    assert!(rules(&want).is_empty());
}

#[test]
fn rules_catch_a_leaf_with_a_dependency_and_a_crate_on_the_cli() {
    let g = graph_of(&[("signorini-cli", &[]), ("signorini-contact", &["signorini-fem"]), ("signorini-exact", &[]), ("signorini-norms", &["signorini-cli", "signorini-exact"])]);
    let bad = rules(&g);
    assert_eq!(bad.len(), 2, "{bad:?}");
    assert!(bad[0].contains("signorini-norms depends on signorini-cli"), "{bad:?}");
    assert!(bad[1].contains("signorini-contact depends on signorini-fem"), "{bad:?}");
}

#[test]
fn splice_replaces_only_the_block() {
    let text = format!("a\n{BEGIN}\nold\n{END}\nb\n");
    assert_eq!(splice(&text, "NEW").unwrap(), "a\nNEW\nb\n");
    assert!(splice("no markers", "NEW").is_err());
}
