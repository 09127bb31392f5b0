//! `docs/generated/scene-keys.md`: the reference of every key of a scene
//! file, generated from the scene schema itself — the serde structs of
//! `crates/scene/src/schema.rs` and `crates/scene/src/excitation.rs`.
//!
//! # Why `syn` on the sources (and not a derived JSON schema)
//!
//! The generator parses the two files with `syn` and reads, for every
//! field, its name, its Rust type, its `///` doc comment and its
//! `#[serde(...)]` attributes. Deriving `schemars::JsonSchema` on the
//! structs would give the same facts, but at the price of a new dependency
//! (schemars, its derive, serde_json) in the library crate that the command,
//! the sweeps and the Python wheel all link, plus `#[schemars(with)]`
//! shadows next to every `deserialize_with`; and the JSON schema would then
//! have to be translated back into TOML terms anyway. Reading the sources
//! keeps the scene crate untouched (its doc comments are the text), costs
//! nothing to build (`syn` with `full` is already compiled for the
//! workspace's derives), and the generator is strict: a serde attribute,
//! a container attribute or a type it does not know how to document
//! (`rename`, `flatten`, `alias`, a new type, a `default = "fn"` whose body
//! is not a literal, …) is an error naming the field, never a silently
//! wrong row.
//!
//! Whatever reads the sources can still misread serde, so the test
//! `generated_keys_are_the_readers` checks the result against the reader
//! itself: for every table it feeds `SceneFile::parse` a document with an
//! unknown key and compares serde's list of expected fields (the set the
//! reader really accepts) with the keys of the generated table.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use syn::{Attribute, Expr, Fields, GenericArgument, Item, Lit, PathArguments, Type};

/// The files the schema lives in, relative to the workspace root.
pub const SOURCES: [&str; 2] = ["crates/scene/src/schema.rs", "crates/scene/src/excitation.rs"];

/// The root struct: the whole scene file.
const ROOT: &str = "SceneFile";

/// The title of the root's table (the file's own keys).
const TOP: &str = "Top level";

/// How a field defaults when the key is absent.
#[derive(Clone, Debug, PartialEq)]
enum Presence {
    /// No default: the key must be given (within its table).
    Required,
    /// `Option<T>`: may be absent (what absence means is the doc's to say).
    Optional,
    /// `#[serde(default)]` or `#[serde(default = "fn")]`: this value.
    Default(String),
}

/// One field of a serde struct.
#[derive(Clone)]
struct Field {
    key: String,
    ty: Type,
    doc: String,
    presence: Presence,
}

/// A `deny_unknown_fields` struct (a TOML table).
#[derive(Clone)]
struct Struct {
    doc: String,
    fields: Vec<Field>,
}

/// An `untagged` enum: one of several value forms.
#[derive(Clone)]
struct Enum {
    variants: Vec<Type>,
}

/// The schema read from the sources.
struct Schema {
    structs: BTreeMap<String, Struct>,
    enums: BTreeMap<String, Enum>,
}

/// One generated table: its title (`[bar]`, `[[stop]]`, `reduce = { … }`),
/// the struct it documents, and its rows.
pub struct Section {
    /// The TOML spellings of where the table appears.
    pub titles: Vec<String>,
    /// The struct's doc comment.
    pub doc: String,
    /// (key, type in TOML terms, required / default, description).
    pub rows: Vec<[String; 4]>,
}

fn doc_of(attrs: &[Attribute]) -> String {
    let mut lines = Vec::new();
    for a in attrs {
        if !a.path().is_ident("doc") {
            continue;
        }
        if let syn::Meta::NameValue(nv) = &a.meta {
            if let Expr::Lit(syn::ExprLit { lit: Lit::Str(s), .. }) = &nv.value {
                lines.push(s.value().trim().to_string());
            }
        }
    }
    // One line per table cell: paragraphs and lines joined with spaces.
    lines.into_iter().filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" ")
}

fn derives_deserialize(attrs: &[Attribute]) -> bool {
    attrs.iter().filter(|a| a.path().is_ident("derive")).any(|a| {
        let mut found = false;
        let _ = a.parse_nested_meta(|m| {
            found |= m.path.segments.last().is_some_and(|s| s.ident == "Deserialize");
            Ok(())
        });
        found
    })
}

/// The container's serde flags (`deny_unknown_fields`, `untagged`); any
/// other is refused.
fn container_flags(attrs: &[Attribute], name: &str) -> Result<Vec<String>, String> {
    let mut flags = Vec::new();
    for a in attrs.iter().filter(|a| a.path().is_ident("serde")) {
        a.parse_nested_meta(|m| {
            let id = m.path.get_ident().map(|i| i.to_string()).unwrap_or_default();
            match id.as_str() {
                "deny_unknown_fields" | "untagged" => {
                    flags.push(id);
                    Ok(())
                }
                _ => Err(m.error(format!("#[serde({id})] on {name} is not understood by xtask/src/scene_keys.rs: teach it (or the key reference would be wrong)"))),
            }
        })
        .map_err(|e| e.to_string())?;
    }
    Ok(flags)
}

/// The TOML literal a default function returns: its body must be a
/// literal (`1`, `true`, `"std".into()`, `String::from("std")`).
fn default_fn_value(fns: &BTreeMap<String, syn::ItemFn>, name: &str) -> Result<String, String> {
    let f = fns.get(name).ok_or_else(|| format!("default function {name} not found in the scene sources"))?;
    let [syn::Stmt::Expr(e, None)] = f.block.stmts.as_slice() else {
        return Err(format!("default function {name}: its body is not a single expression"));
    };
    fn lit(e: &Expr) -> Option<String> {
        match e {
            Expr::Lit(l) => match &l.lit {
                Lit::Str(s) => Some(format!("\"{}\"", s.value())),
                Lit::Int(i) => Some(i.base10_digits().to_string()),
                Lit::Float(x) => Some(x.base10_digits().to_string()),
                Lit::Bool(b) => Some(b.value.to_string()),
                _ => None,
            },
            Expr::MethodCall(m) if ["into", "to_string", "to_owned"].contains(&m.method.to_string().as_str()) && m.args.is_empty() => lit(&m.receiver),
            Expr::Call(c) if c.args.len() == 1 => lit(&c.args[0]),
            _ => None,
        }
    }
    lit(e).ok_or_else(|| format!("default function {name}: its body is not a literal (write it as one, or teach xtask/src/scene_keys.rs)"))
}

/// The value `#[serde(default)]` gives a type (its `Default`).
fn type_default(ty: &Type, schema_structs: &[String]) -> Result<Presence, String> {
    let (name, _) = head(ty);
    Ok(match name.as_str() {
        "bool" => Presence::Default("false".into()),
        "usize" | "u64" | "u32" | "i64" | "i32" => Presence::Default("0".into()),
        "f64" => Presence::Default("0".into()),
        "Option" | "Vec" => Presence::Optional,
        s if schema_structs.iter().any(|x| x == s) => Presence::Optional,
        _ => return Err(format!("#[serde(default)] on a field of type {name}: xtask/src/scene_keys.rs does not know its default")),
    })
}

/// The last path segment's name and its generic arguments.
fn head(ty: &Type) -> (String, Vec<Type>) {
    match ty {
        Type::Path(p) => {
            let seg = p.path.segments.last().expect("a path has a segment");
            let args = match &seg.arguments {
                PathArguments::AngleBracketed(a) => a.args.iter().filter_map(|g| if let GenericArgument::Type(t) = g { Some(t.clone()) } else { None }).collect(),
                _ => Vec::new(),
            };
            (seg.ident.to_string(), args)
        }
        Type::Array(_) => ("[array]".into(), Vec::new()),
        _ => ("?".into(), Vec::new()),
    }
}

fn read_schema(root: &Path) -> Result<Schema, String> {
    let mut items = Vec::new();
    for f in SOURCES {
        let text = std::fs::read_to_string(root.join(f)).map_err(|e| format!("{f}: {e}"))?;
        let file = syn::parse_file(&text).map_err(|e| format!("{f}: {e}"))?;
        items.extend(file.items);
    }
    let fns: BTreeMap<String, syn::ItemFn> = items.iter().filter_map(|i| if let Item::Fn(f) = i { Some((f.sig.ident.to_string(), f.clone())) } else { None }).collect();
    let struct_names: Vec<String> = items.iter().filter_map(|i| if let Item::Struct(s) = i { derives_deserialize(&s.attrs).then(|| s.ident.to_string()) } else { None }).collect();
    let mut schema = Schema { structs: BTreeMap::new(), enums: BTreeMap::new() };
    for item in &items {
        match item {
            Item::Struct(s) if derives_deserialize(&s.attrs) => {
                let name = s.ident.to_string();
                if !container_flags(&s.attrs, &name)?.iter().any(|f| f == "deny_unknown_fields") {
                    return Err(format!("{name}: a scene table without #[serde(deny_unknown_fields)] would accept any key"));
                }
                let Fields::Named(named) = &s.fields else {
                    return Err(format!("{name}: a table struct needs named fields"));
                };
                let mut fields = Vec::new();
                for f in &named.named {
                    let key = f.ident.as_ref().expect("named").to_string();
                    let mut skip = false;
                    let mut default: Option<Option<String>> = None;
                    for a in f.attrs.iter().filter(|a| a.path().is_ident("serde")) {
                        a.parse_nested_meta(|m| {
                            let id = m.path.get_ident().map(|i| i.to_string()).unwrap_or_default();
                            match id.as_str() {
                                "skip" => skip = true,
                                "default" => default = Some(if m.input.peek(syn::Token![=]) { Some(m.value()?.parse::<syn::LitStr>()?.value()) } else { None }),
                                // The declared type stays the documented one
                                // (the function only checks the form harder).
                                "deserialize_with" => {
                                    m.value()?.parse::<syn::LitStr>()?;
                                }
                                _ => return Err(m.error(format!("#[serde({id})] on {name}.{key} is not understood by xtask/src/scene_keys.rs: teach it (or the key reference would be wrong)"))),
                            }
                            Ok(())
                        })
                        .map_err(|e| e.to_string())?;
                    }
                    if skip {
                        continue;
                    }
                    let presence = match default {
                        Some(Some(func)) => Presence::Default(default_fn_value(&fns, &func)?),
                        Some(None) => type_default(&f.ty, &struct_names).map_err(|e| format!("{name}.{key}: {e}"))?,
                        None if head(&f.ty).0 == "Option" => Presence::Optional,
                        None => Presence::Required,
                    };
                    fields.push(Field { key, ty: f.ty.clone(), doc: doc_of(&f.attrs), presence });
                }
                schema.structs.insert(name, Struct { doc: doc_of(&s.attrs), fields });
            }
            Item::Enum(e) if derives_deserialize(&e.attrs) => {
                let name = e.ident.to_string();
                if !container_flags(&e.attrs, &name)?.iter().any(|f| f == "untagged") {
                    return Err(format!("{name}: only untagged enums (one of several value forms) are documented"));
                }
                let mut variants = Vec::new();
                for v in &e.variants {
                    match &v.fields {
                        Fields::Unnamed(u) if u.unnamed.len() == 1 => variants.push(u.unnamed[0].ty.clone()),
                        _ => return Err(format!("{name}::{}: a value form must hold exactly one value", v.ident)),
                    }
                }
                schema.enums.insert(name, Enum { variants });
            }
            _ => {}
        }
    }
    if !schema.structs.contains_key(ROOT) {
        return Err(format!("no struct {ROOT} in the scene sources"));
    }
    Ok(schema)
}

impl Schema {
    /// A type in TOML terms.
    fn toml_type(&self, ty: &Type) -> Result<String, String> {
        if let Type::Array(a) = ty {
            let n = match &a.len {
                Expr::Lit(syn::ExprLit { lit: Lit::Int(i), .. }) => i.base10_parse::<usize>().map_err(|e| e.to_string())?,
                _ => return Err("an array of unknown length".into()),
            };
            let inner = self.toml_type(&a.elem)?;
            return match (inner.as_str(), n) {
                ("number", 2) => Ok("`[a, b]` pair".into()),
                ("number", 3) => Ok("`[a, b, c]` triple".into()),
                _ => Err(format!("an array of {n} {inner}")),
            };
        }
        let (name, args) = head(ty);
        Ok(match name.as_str() {
            "f64" | "f32" => "number".into(),
            "usize" | "u64" | "u32" | "i64" | "i32" => "integer".into(),
            "String" => "string".into(),
            "bool" => "bool".into(),
            "Option" => self.toml_type(args.first().ok_or("Option without its type")?)?,
            "Vec" => {
                let inner = args.first().ok_or("Vec without its type")?;
                let t = self.toml_type(inner)?;
                if self.structs.contains_key(&head(inner).0) {
                    "array of tables".into()
                } else {
                    match t.strip_suffix(" pair").or_else(|| t.strip_suffix(" triple")) {
                        Some(p) => format!("`[{}, …]`", p.trim_matches('`')),
                        None if t == "array of numbers" => "array of number arrays".into(),
                        None => format!("array of {t}s"),
                    }
                }
            }
            s if self.structs.contains_key(s) => "table".into(),
            s if self.enums.contains_key(s) => {
                let forms = self.enums[s].variants.iter().map(|v| self.toml_type(v)).collect::<Result<Vec<_>, _>>()?;
                match forms.split_last() {
                    Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
                    _ => forms.join(""),
                }
            }
            other => return Err(format!("the type {other} is not known to xtask/src/scene_keys.rs: teach it its TOML spelling")),
        })
    }

    /// The tables of a scene in reading order: the file's own keys, then
    /// each struct reached from them (depth first), once per struct, titled
    /// by every place it appears.
    fn sections(&self) -> Result<Vec<Section>, String> {
        let mut order: Vec<String> = vec![ROOT.into()];
        let mut titles: BTreeMap<String, Vec<String>> = BTreeMap::new();
        titles.insert(ROOT.into(), vec![TOP.into()]);
        let mut i = 0;
        while i < order.len() {
            let st = &self.structs[&order[i]];
            let parent = order[i].clone();
            for f in &st.fields {
                let (outer, args) = head(&f.ty);
                let (inner, vec) = match outer.as_str() {
                    "Option" => (head(&args[0]).0, head(&args[0]).0 == "Vec"),
                    "Vec" => (head(&args[0]).0, true),
                    _ => (outer.clone(), false),
                };
                if !self.structs.contains_key(&inner) {
                    continue;
                }
                let title = if parent == ROOT {
                    if vec {
                        format!("`[[{}]]`", f.key)
                    } else {
                        format!("`[{}]`", f.key)
                    }
                } else {
                    let in_ = titles[&parent].join(", ");
                    format!("`{} = {{ … }}` in {in_}", f.key)
                };
                let t = titles.entry(inner.clone()).or_default();
                if !t.contains(&title) {
                    t.push(title);
                }
                if !order.contains(&inner) {
                    order.push(inner);
                }
            }
            i += 1;
        }
        // A struct reached from several tables (`reduce` in [bar] and [beam])
        // is titled once: `reduce = { … }` in `[bar]`, `[beam]`.
        let mut out = Vec::new();
        for name in &order {
            let st = &self.structs[name];
            let mut rows = Vec::new();
            for f in &st.fields {
                let ty = self.toml_type(&f.ty).map_err(|e| format!("{name}.{}: {e}", f.key))?;
                let presence = match &f.presence {
                    Presence::Required => "required".to_string(),
                    Presence::Optional => "optional".to_string(),
                    Presence::Default(v) => format!("default `{v}`"),
                };
                rows.push([format!("`{}`", f.key), ty, presence, f.doc.clone()]);
            }
            out.push(Section { titles: merge_titles(&titles[name]), doc: st.doc.clone(), rows });
        }
        Ok(out)
    }
}

/// `reduce = { … }` in `[bar]` and `reduce = { … }` in `[beam]` → one title.
fn merge_titles(titles: &[String]) -> Vec<String> {
    let mut merged: Vec<(String, Vec<String>)> = Vec::new();
    for t in titles {
        match t.split_once(" in ") {
            Some((k, place)) => match merged.iter_mut().find(|(m, _)| m == k) {
                Some((_, places)) => places.push(place.to_string()),
                None => merged.push((k.to_string(), vec![place.to_string()])),
            },
            None => merged.push((t.clone(), Vec::new())),
        }
    }
    merged.into_iter().map(|(k, p)| if p.is_empty() { k } else { format!("{k} in {}", p.join(", ")) }).collect()
}

/// The struct's doc comment without a leading repeat of the title
/// (`[bar]: a P1/P2/P3 bar …` under the title `[bar]`).
fn intro(sec: &Section) -> String {
    for t in &sec.titles {
        if let Some(rest) = sec.doc.strip_prefix(t.as_str()) {
            let rest = rest.trim_start_matches([':', '.']).trim_start();
            let mut c = rest.chars();
            return match c.next() {
                Some(f) => f.to_uppercase().chain(c).collect(),
                None => String::new(),
            };
        }
    }
    sec.doc.clone()
}

fn cell(s: &str) -> String {
    s.replace('|', "\\|")
}

/// The generated tables of the schema.
pub fn sections(root: &Path) -> Result<Vec<Section>, String> {
    read_schema(root)?.sections()
}

/// The body of `docs/generated/scene-keys.md`.
pub fn render(root: &Path) -> Result<String, String> {
    let mut s = String::new();
    for sec in sections(root)? {
        match intro(&sec) {
            i if i.is_empty() => writeln!(s, "**{}**\n", sec.titles.join(", ")),
            i => writeln!(s, "**{}** — {}\n", sec.titles.join(", "), cell(&i)),
        }
        .expect("writing to a String");
        s.push_str("| key | type | required / default | description |\n|---|---|---|---|\n");
        for r in &sec.rows {
            let _ = writeln!(s, "| {} |", r.iter().map(|c| cell(c)).collect::<Vec<_>>().join(" | "));
        }
        s.push('\n');
    }
    let _ = writeln!(s, "<small>Generated from the `///` comments and serde attributes of `{}` by `cargo xtask docs`.</small>", SOURCES.join("` and `"));
    Ok(s)
}
