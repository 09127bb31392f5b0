//! The module graph of a crate, read from its sources: which module's code
//! names which other module. `cargo xtask docs --check` fails when the
//! graph of a crate in [`ACYCLIC`] has a cycle, naming it.
//!
//! A module is a file (`lib.rs`, `a.rs`, `a/mod.rs`, or a `#[path]`
//! file). Module `A` depends on `B` when `A`'s code names an item of `B`:
//! through a path that starts with `crate::`, `super::`, `self::` or a child
//! module's name, in a private `use` or anywhere in the code (`super::search::Search::new(n)`
//! counts). A name re-exported by a module (`pub use flow::ModalFlow` in
//! `events/mod.rs`, `pub use registry::SchemeSpec` in `lib.rs`) leads to the
//! module that defines it. Not edges: `mod` declarations and `pub`/`pub(crate)`
//! re-exports (the module tree and a module's public face, not its code),
//! `#[cfg(test)]` modules (tests may reach anything), doc comments. A
//! method call names no module (`spec.to_string()`), so an `impl` block in
//! another module is no edge; a type named is.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use proc_macro2::{TokenStream, TokenTree};
use quote::ToTokens;
use syn::{Item, UseTree, Visibility};

/// The crates (folders under the workspace root) whose module graph must
/// be acyclic.
pub const ACYCLIC: &[&str] = &["crates/schemes", "crates/sweep", "crates/fuzz"];

/// The edges the check leaves out, each with its reason: (crate, from, to, why).
pub const EXEMPT: &[(&str, &str, &str, &str)] = &[(
    "crates/schemes",
    "events::driven",
    "events::driven::massless",
    "massless.rs is the second half of EventDriven's impl, a private child of driven.rs: the child uses its parent's private types, the parent calls one helper of the child (static_delassus)",
)];

/// A module of the crate: its path (`events::flow`; `crate` for the root).
#[derive(Default)]
pub struct Module {
    /// child name → module path.
    children: BTreeMap<String, String>,
    /// re-exported name → the path it re-exports (relative to this module).
    reexports: BTreeMap<String, Vec<String>>,
    /// Paths named by the module's code (each relative to this module).
    paths: Vec<Vec<String>>,
    /// Every identifier of its code (a name it re-exports and uses itself
    /// is an edge too).
    idents: BTreeSet<String>,
    /// Its parent's module path (none for the root).
    parent: Option<String>,
}

/// module path → the module paths its code depends on (self excluded).
pub type Graph = BTreeMap<String, BTreeSet<String>>;

/// The module graph of the crate whose root file is `lib` (its `src/lib.rs`).
pub fn graph(lib: &Path) -> Result<Graph, String> {
    let mut files = BTreeMap::new();
    load(lib, "crate", None, lib.parent().unwrap_or(Path::new(".")), &mut files, &mut |p| std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display())))?;
    Ok(edges(&files))
}

/// Reads the module at `file` (module path `name`) and, recursively, its
/// file children. `dir` is where its children's files are.
pub fn load(file: &Path, name: &str, parent: Option<&str>, dir: &Path, out: &mut BTreeMap<String, Module>, read: &mut dyn FnMut(&Path) -> Result<String, String>) -> Result<(), String> {
    let text = read(file)?;
    let parsed = syn::parse_file(&text).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut m = Module { parent: parent.map(str::to_string), ..Module::default() };
    let mut kids = Vec::new();
    collect(&parsed.items, &mut m, &mut kids, name);
    out.insert(name.to_string(), m);
    for (kid, path_attr) in kids {
        let path = match path_attr {
            Some(p) => file.parent().unwrap_or(Path::new(".")).join(p),
            None => {
                let flat = dir.join(format!("{kid}.rs"));
                if read(&flat).is_ok() {
                    flat
                } else {
                    dir.join(&kid).join("mod.rs")
                }
            }
        };
        let kid_dir = if path.file_name().is_some_and(|f| f == "mod.rs") { path.parent().unwrap_or(Path::new(".")).to_path_buf() } else { path.with_extension("") };
        let kid_name = if name == "crate" { kid.clone() } else { format!("{name}::{kid}") };
        load(&path, &kid_name, Some(name), &kid_dir, out, read)?;
    }
    Ok(())
}

fn is_cfg_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| a.path().is_ident("cfg") && a.to_token_stream().to_string().replace(' ', "").contains("(test)"))
}

fn path_attr(attrs: &[syn::Attribute]) -> Option<PathBuf> {
    attrs.iter().find(|a| a.path().is_ident("path")).and_then(|a| match &a.meta {
        syn::Meta::NameValue(syn::MetaNameValue { value: syn::Expr::Lit(syn::ExprLit { lit: syn::Lit::Str(s), .. }), .. }) => Some(PathBuf::from(s.value())),
        _ => None,
    })
}

/// Sorts a module's items into children, re-exports and the paths of its code.
fn collect(items: &[Item], m: &mut Module, kids: &mut Vec<(String, Option<PathBuf>)>, name: &str) {
    for item in items {
        match item {
            Item::Mod(md) if is_cfg_test(&md.attrs) => {}
            Item::Mod(md) => match &md.content {
                None => {
                    let kid = md.ident.to_string();
                    let kid_name = if name == "crate" { kid.clone() } else { format!("{name}::{kid}") };
                    m.children.insert(kid.clone(), kid_name);
                    kids.push((kid, path_attr(&md.attrs)));
                }
                // An inline module's code counts as its file's.
                Some((_, inner)) => collect(inner, m, kids, name),
            },
            Item::Use(u) => {
                let mut flat = Vec::new();
                flatten(&u.tree, &mut Vec::new(), &mut flat);
                if matches!(u.vis, Visibility::Inherited) {
                    m.paths.extend(flat.into_iter().map(|(p, _)| p));
                } else {
                    for (p, as_name) in flat {
                        if let Some(n) = as_name {
                            m.reexports.insert(n, p);
                        }
                    }
                }
            }
            other => scan(other.to_token_stream(), &mut m.paths, &mut m.idents),
        }
    }
}

/// A use tree as (path, the name it brings in; none for a glob).
fn flatten(t: &UseTree, prefix: &mut Vec<String>, out: &mut Vec<(Vec<String>, Option<String>)>) {
    match t {
        UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            flatten(&p.tree, prefix, out);
            prefix.pop();
        }
        UseTree::Name(n) => {
            let mut p = prefix.clone();
            let id = n.ident.to_string();
            if id == "self" {
                out.push((p.clone(), p.last().cloned()));
            } else {
                p.push(id.clone());
                out.push((p, Some(id)));
            }
        }
        UseTree::Rename(r) => {
            let mut p = prefix.clone();
            p.push(r.ident.to_string());
            out.push((p, Some(r.rename.to_string())));
        }
        UseTree::Glob(_) => out.push((prefix.clone(), None)),
        UseTree::Group(g) => {
            for t in &g.items {
                flatten(t, prefix, out);
            }
        }
    }
}

/// Every path `a::b::c` in the tokens (longest, starting at an identifier
/// not itself after `::`).
fn scan(ts: TokenStream, out: &mut Vec<Vec<String>>, idents: &mut BTreeSet<String>) {
    let toks: Vec<TokenTree> = ts.into_iter().collect();
    let colons = |i: usize| matches!((toks.get(i), toks.get(i + 1)), (Some(TokenTree::Punct(a)), Some(TokenTree::Punct(b))) if a.as_char() == ':' && b.as_char() == ':');
    let mut i = 0;
    while i < toks.len() {
        let after_colons = i >= 2 && colons(i - 2);
        match &toks[i] {
            TokenTree::Group(g) => scan(g.stream(), out, idents),
            TokenTree::Ident(id) if !after_colons && !colons(i + 1) => {
                idents.insert(id.to_string());
            }
            TokenTree::Ident(id) if !after_colons && colons(i + 1) => {
                let mut p = vec![id.to_string()];
                let mut j = i + 1;
                while colons(j) {
                    match toks.get(j + 2) {
                        Some(TokenTree::Ident(next)) => {
                            p.push(next.to_string());
                            j += 3;
                        }
                        _ => break,
                    }
                }
                out.push(p);
                i = j;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
}

/// The module that `path`, named in module `at`, leads to; none for a path
/// outside the crate (a dependency's, the standard library's, a local name's).
fn resolve(files: &BTreeMap<String, Module>, at: &str, path: &[String], depth: usize) -> Option<String> {
    let mut cur = at.to_string();
    let mut rest = path;
    match rest.first().map(String::as_str) {
        Some("crate") => {
            cur = "crate".into();
            rest = &rest[1..];
        }
        Some("self") => rest = &rest[1..],
        Some("super") => {
            while rest.first().map(String::as_str) == Some("super") {
                cur = files.get(&cur)?.parent.clone()?;
                rest = &rest[1..];
            }
        }
        Some(first) if files.get(&cur)?.children.contains_key(first) => {}
        _ => return None,
    }
    for (i, seg) in rest.iter().enumerate() {
        let m = files.get(&cur)?;
        if let Some(kid) = m.children.get(seg) {
            cur = kid.clone();
            continue;
        }
        if let Some(target) = m.reexports.get(seg) {
            if depth < 16 {
                let mut p = target.clone();
                p.extend(rest[i + 1..].iter().cloned());
                return resolve(files, &cur, &p, depth + 1);
            }
        }
        return Some(cur);
    }
    Some(cur)
}

pub fn edges(files: &BTreeMap<String, Module>) -> Graph {
    let mut g = Graph::new();
    for (name, m) in files {
        let deps = g.entry(name.clone()).or_default();
        let own = m.reexports.iter().filter(|(n, _)| m.idents.contains(*n)).map(|(_, p)| p);
        for p in m.paths.iter().chain(own) {
            if let Some(t) = resolve(files, name, p, 0) {
                if t != *name {
                    deps.insert(t);
                }
            }
        }
    }
    g
}

/// The cycles of `g`: a shortest one through each module that is on no
/// cycle found before it, each as a closed path `a → b → … → a`.
pub fn cycles(g: &Graph) -> Vec<Vec<String>> {
    let mut found = Vec::new();
    let mut seen: BTreeSet<&str> = BTreeSet::new();
    for start in g.keys() {
        if seen.contains(start.as_str()) {
            continue;
        }
        // The modules on a path back to `start`: a shortest cycle through it (BFS).
        let mut prev: BTreeMap<&str, &str> = BTreeMap::new();
        let mut queue = std::collections::VecDeque::from([start.as_str()]);
        let mut closed = None;
        while let Some(n) = queue.pop_front() {
            for d in g.get(n).into_iter().flatten() {
                if d == start {
                    closed = Some(n);
                    break;
                }
                if !prev.contains_key(d.as_str()) {
                    prev.insert(d, n);
                    queue.push_back(d);
                }
            }
            if closed.is_some() {
                break;
            }
        }
        if let Some(last) = closed {
            let mut c = vec![last];
            while *c.last().expect("not empty") != start.as_str() {
                c.push(prev[c.last().expect("not empty")]);
            }
            c.reverse();
            c.push(start.as_str());
            let c: Vec<String> = c.into_iter().map(str::to_string).collect();
            seen.extend(g.keys().filter(|k| c.contains(k)).map(String::as_str));
            found.push(c);
        }
    }
    found
}

/// `cargo xtask docs --check`: one message per cycle in a crate of [`ACYCLIC`].
pub fn check(root: &Path) -> Result<Vec<String>, String> {
    let mut bad = Vec::new();
    for krate in ACYCLIC {
        let mut g = graph(&root.join(krate).join("src/lib.rs"))?;
        for (_, from, to, _) in EXEMPT.iter().filter(|e| e.0 == *krate) {
            if !g.get_mut(*from).is_some_and(|d| d.remove(*to)) {
                bad.push(format!("{krate}: the exempt edge {from} → {to} is gone: remove it from EXEMPT"));
            }
        }
        for c in cycles(&g) {
            bad.push(format!("{krate}: a cycle among its modules: {}", c.join(" → ")));
        }
    }
    Ok(bad)
}
