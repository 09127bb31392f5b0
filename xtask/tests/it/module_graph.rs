//! The tests of `xtask::module_graph` (xtask/src/module_graph.rs).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use xtask::module_graph::*;

/// The graph of a crate given as (file, text) pairs under `src/`.
fn graph_of(files: &[(&str, &str)]) -> Graph {
    let texts: BTreeMap<PathBuf, String> = files.iter().map(|(f, t)| (Path::new("src").join(f), t.to_string())).collect();
    let mut out = BTreeMap::new();
    load(Path::new("src/lib.rs"), "crate", None, Path::new("src"), &mut out, &mut |p| texts.get(p).cloned().ok_or_else(|| format!("{}: missing", p.display()))).unwrap();
    edges(&out)
}

fn deps(g: &Graph, m: &str) -> Vec<String> {
    g[m].iter().cloned().collect()
}

// A crate written by hand: re-exports at the root and in `ev/mod.rs`,
// a `#[path]` child, inline paths, a test module.
const CRATE: &[(&str, &str)] = &[
    ("lib.rs", "//! Doc naming crate::b::B.\npub mod ev;\nmod a;\nmod b;\npub use a::A;\npub use b::{B, Bee as Renamed};\npub use std::fmt::Debug;\npub struct Root;\npub use ev::Flow as Fl;\npub struct Holder(pub Fl);\n"),
    ("a.rs", "use crate::Renamed;\npub struct A;\nfn f() { let _ = crate::ev::Flow::new(); }\n#[cfg(test)]\nmod tests { use crate::b::B; }\n"),
    ("b.rs", "use crate::Root;\npub struct B;\npub struct Bee;\n/// [`crate::A`]\nfn g() -> std::vec::Vec<u8> { Vec::new() }\n"),
    ("ev/mod.rs", "mod flow;\nmod search;\npub use flow::Flow;\npub enum Bound { L }\n"),
    ("ev/flow.rs", "use super::Bound;\npub struct Flow;\nimpl Flow { pub fn new() -> Self { Flow } }\n#[path = \"held.rs\"]\nmod held;\n"),
    ("ev/held.rs", "use super::super::search::go;\n"),
    ("ev/search.rs", "pub fn go() { let _: super::Bound; }\n"),
];

#[test]
fn edges_follow_paths_and_re_exports() {
    let g = graph_of(CRATE);
    assert_eq!(g.keys().cloned().collect::<Vec<_>>(), ["a", "b", "crate", "ev", "ev::flow", "ev::flow::held", "ev::search"]);
    // `crate::Renamed` is `b::Bee`; `crate::ev::Flow` is `ev::flow`'s;
    // the test module's `crate::b::B` is no edge of its own.
    assert_eq!(deps(&g, "a"), ["b", "ev::flow"]);
    // `Root` is defined at the root; doc comments and std paths are no edges.
    assert_eq!(deps(&g, "b"), ["crate"]);
    // `mod` lines and re-exports are no edges; the root's own code
    // naming `Fl`, which it re-exports, is.
    assert_eq!(deps(&g, "crate"), ["ev::flow"]);
    assert!(deps(&g, "ev").is_empty());
    assert_eq!(deps(&g, "ev::flow"), ["ev"]);
    assert_eq!(deps(&g, "ev::flow::held"), ["ev::search"]);
    assert_eq!(deps(&g, "ev::search"), ["ev"]);
    assert!(cycles(&g).is_empty(), "{:?}", cycles(&g));
}

#[test]
fn a_cycle_is_found_and_named() {
    // `ev/mod.rs`'s code names its child `flow` by a bare path, and
    // `flow` names `ev`'s `Bound`.
    let mut files = CRATE.to_vec();
    files[3] = ("ev/mod.rs", "mod flow;\nmod search;\npub use flow::Flow;\npub enum Bound { L }\nfn h() { flow::Flow::new(); }\n");
    assert_eq!(cycles(&graph_of(&files)), [["ev", "ev::flow", "ev"]]);
    // `ev/search.rs` names a type of `flow` (acyclic so far: `flow`'s
    // child `held` names `search`, but `flow` names neither); then `flow`
    // calls `search` by an inline path.
    let mut files = CRATE.to_vec();
    files[6] = ("ev/search.rs", "pub fn go() { let _: super::flow::Flow; }\n");
    let g = graph_of(&files);
    assert_eq!(deps(&g, "ev::search"), ["ev::flow"]);
    assert!(cycles(&g).is_empty(), "{:?}", cycles(&g));
    files[4] = ("ev/flow.rs", "use super::Bound;\npub struct Flow;\nfn k() { super::search::go(); }\n#[path = \"held.rs\"]\nmod held;\n");
    assert_eq!(cycles(&graph_of(&files)), [["ev::flow", "ev::search", "ev::flow"]]);
    // Two modules naming each other through inline paths only.
    let mut files = CRATE.to_vec();
    files[2] = ("b.rs", "pub struct B;\npub struct Bee;\nfn g() { crate::a::A; }\n");
    assert_eq!(cycles(&graph_of(&files)), [["a", "b", "a"]]);
}

#[test]
fn the_listed_crates_have_no_module_cycle() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    assert_eq!(check(&root).unwrap(), Vec::<String>::new());
}
