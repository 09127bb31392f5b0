//! A generated document: its tables, values and the class of each value
//! ([`Class`]), which says what the reader must answer ([`Doc`]).

/// What the generator knows of one value (or of the document's structure).
#[derive(Clone, Debug, PartialEq)]
pub enum Class {
    /// Valid: alone, it does not make validation fail.
    Good,
    /// Invalid: validation must fail and name one of these fields.
    Bad(Vec<String>),
    /// Wrong type, unknown key or table, duplicate key: parsing must fail.
    Type,
    /// Not predicted (random expression tokens; values a stricter validation
    /// may refuse): any answer, but an error must name one of these fields.
    Unknown(Vec<String>),
}

pub(crate) fn bad(fields: &[&str]) -> Class {
    Class::Bad(fields.iter().map(|f| f.to_string()).collect())
}

pub(crate) fn unknown(fields: &[&str]) -> Class {
    Class::Unknown(fields.iter().map(|f| f.to_string()).collect())
}

/// A value as written in TOML, with its class.
#[derive(Clone, Debug)]
pub struct Value {
    /// TOML text of the value.
    pub toml: String,
    /// What the reader must do with it.
    pub class: Class,
}

pub(crate) fn val(toml: impl Into<String>, class: Class) -> Value {
    Value { toml: toml.into(), class }
}

/// How a table is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// `[bar]` then `key = value` lines.
    Header,
    /// `bar = { key = value, … }`.
    Inline,
    /// `bar.key = value` lines at the top level.
    Dotted,
    /// `[[stop]]` then `key = value` lines: one item of an array of tables.
    ArrayItem,
}

/// One table of a generated document.
#[derive(Clone, Debug)]
pub struct Table {
    /// `bar`, `beam`, `output` or an unknown name.
    pub name: String,
    /// Its keys and values.
    pub entries: Vec<(String, Value)>,
    /// How it is written.
    pub form: Form,
}

/// A field's exact value as a function of x, computed in Rust.
pub type Exact = fn(f64) -> f64;

/// An initial field whose value the generator knows: `("u" or "v", f(x))`.
pub type KnownField = (&'static str, Exact);

/// A TOML text (expression, table, number) with its value in Rust.
pub(crate) type Written = (&'static str, Exact);

/// An initial field's value, and its function when it is a valid one.
pub(crate) type FieldPick = (Value, Option<Exact>);

/// A `[bar]` table as written: entries, structural classes, known fields, length.
pub(crate) type BarTable = (Vec<(String, Value)>, Vec<Class>, Vec<KnownField>, f64);

/// A generated scene document.
#[derive(Clone, Debug)]
pub struct Doc {
    /// The tables, in order.
    pub tables: Vec<Table>,
    /// Classes of the document as a whole (both or no bar/beam table, keys
    /// that conflict, an unknown table).
    pub structure: Vec<Class>,
    /// Initial fields of a valid custom bar with their exact values, and the
    /// bar's length: checked node by node when the document is accepted.
    pub known_fields: Vec<KnownField>,
    /// Length of the custom bar (for the nodes of `known_fields`).
    pub length: f64,
    /// Line ending (`\n` or `\r\n`).
    pub crlf: bool,
}

impl Doc {
    /// The TOML text: dotted and inline tables first (a dotted key after a
    /// header would belong to that header's table), then the headers.
    pub fn render(&self) -> String {
        let nl = if self.crlf { "\r\n" } else { "\n" };
        let mut top = String::new();
        let mut headers = String::new();
        for t in &self.tables {
            match t.form {
                Form::Dotted => {
                    for (k, v) in &t.entries {
                        top += &format!("{}.{k} = {}{nl}", t.name, v.toml);
                    }
                    if t.entries.is_empty() {
                        top += &format!("{} = {{}}{nl}", t.name);
                    }
                }
                Form::Inline => {
                    let items: Vec<String> = t.entries.iter().map(|(k, v)| format!("{k} = {}", v.toml)).collect();
                    top += &format!("{} = {{ {} }}{nl}", t.name, items.join(", "));
                }
                Form::Header | Form::ArrayItem => {
                    let header = if t.form == Form::Header { format!("[{}]", t.name) } else { format!("[[{}]]", t.name) };
                    headers += &format!("# the {} table{nl}{header}{nl}", t.name);
                    for (k, v) in &t.entries {
                        headers += &format!("{k} = {}{nl}", v.toml);
                    }
                    headers += nl;
                }
            }
        }
        top + &headers
    }

    pub(crate) fn classes(&self) -> impl Iterator<Item = &Class> {
        self.tables.iter().flat_map(|t| t.entries.iter().map(|(_, v)| &v.class)).chain(&self.structure)
    }
}

// ---------------------------------------------------------------- values --

/// A float as TOML writes it (`nan`, `inf`, `-inf`, or Rust's shortest
/// round-trip form, which TOML reads back exactly).
pub fn toml_f64(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{v:?}")
    }
}

/// An integer as TOML reads it (`0x10`, `1_6`, `+8`).
pub(crate) fn toml_count(text: &str) -> Option<u64> {
    let v: toml::Table = toml::from_str(&format!("v = {text}")).ok()?;
    v.get("v")?.as_integer().and_then(|i| u64::try_from(i).ok())
}

/// The first and last x of a table `[[x, v], …]` as TOML reads it (`None`
/// for anything else).
pub(crate) fn table_span(text: &str) -> Option<(f64, f64)> {
    let v: toml::Table = toml::from_str(&format!("v = {text}")).ok()?;
    let rows = v.get("v")?.as_array()?;
    let x = |r: &toml::Value| r.as_array()?.first().and_then(|x| x.as_float().or(x.as_integer().map(|i| i as f64)));
    Some((x(rows.first()?)?, x(rows.last()?)?))
}
