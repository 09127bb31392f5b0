//! One definition of a study's options, read by every front end.
//!
//! Each study's `Config` is declared once with `study_config!`: every
//! field with its documentation and its default. The macro derives
//! `serde::Deserialize` (unknown fields refused, absent ones at their
//! default), `Default`, and the [`Study`] table: the fields' names,
//! documents and [`Kind`]s, and each field's default as text. From that
//! table `cargo xtask` builds its flags (`t_end` is `--t-end`; a switch
//! whose default is on is `--no-<name>`) and the Python package its
//! keyword arguments (`t_end`) and their documentation; both hand what the
//! user gave to [`read`], one generic path that deserializes it into the
//! `Config` (the numbers of a flag's text parsed, a list split on commas)
//! and checks it with the study's `validate`.
//!
//! **Field names are neutral.** A field is named by its Rust name; each
//! front end spells it ([`Spelling`]). In an error message or a field's
//! document, `⟨name⟩` marks a field (written with [`at`]); [`Message`]
//! keeps those marks as parts and renders them in the front end's spelling,
//! so neither front end rewrites the other's text.

use crate::StudyError;
use serde::de::{self, DeserializeOwned, IntoDeserializer, Visitor};
use std::cell::RefCell;
use std::fmt;

/// How a front end spells a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spelling {
    /// The field's own name, `t_end` (the Python keyword argument).
    Neutral,
    /// `cargo xtask`'s flag, `--t-end`.
    Flag,
}

impl Spelling {
    /// `name` (a field's Rust name) in this spelling.
    pub fn spell(self, name: &str) -> String {
        match self {
            Spelling::Neutral => name.to_string(),
            Spelling::Flag => format!("--{}", name.replace('_', "-")),
        }
    }
}

/// The mark of field `name` in a message or a document: `⟨name⟩`.
pub fn at(name: &str) -> String {
    format!("⟨{name}⟩")
}

/// A message whose field names are kept apart from its text, rendered in a
/// front end's [`Spelling`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Message(Vec<Part>);

#[derive(Clone, Debug, PartialEq, Eq)]
enum Part {
    Text(String),
    Field(String),
}

impl Message {
    /// Reads `⟨name⟩` marks out of `text` (an unclosed `⟨` is text).
    pub fn new(text: &str) -> Self {
        let mut parts = Vec::new();
        let mut rest = text;
        while let Some(open) = rest.find('⟨') {
            let Some(len) = rest[open..].find('⟩') else { break };
            let name = &rest[open + '⟨'.len_utf8()..open + len];
            if !rest[..open].is_empty() {
                parts.push(Part::Text(rest[..open].to_string()));
            }
            parts.push(Part::Field(name.to_string()));
            rest = &rest[open + len + '⟩'.len_utf8()..];
        }
        if !rest.is_empty() {
            parts.push(Part::Text(rest.to_string()));
        }
        Message(parts)
    }

    /// The text with every field spelled as `spelling` says.
    pub fn render(&self, spelling: Spelling) -> String {
        self.render_with(|f| spelling.spell(f))
    }

    /// The text with every field `f` written as `spell(f)` (a document's
    /// `` `t_end` ``).
    pub fn render_with(&self, spell: impl Fn(&str) -> String) -> String {
        self.0
            .iter()
            .map(|p| match p {
                Part::Text(t) => t.clone(),
                Part::Field(f) => spell(f),
            })
            .collect()
    }

    /// The fields the message names, in order.
    pub fn fields(&self) -> impl Iterator<Item = &str> {
        self.0.iter().filter_map(|p| match p {
            Part::Field(f) => Some(f.as_str()),
            Part::Text(_) => None,
        })
    }

    /// The message with the field `from` named `to` (a check borrowed from
    /// another study's configuration).
    pub fn rename(mut self, from: &str, to: &str) -> Self {
        for p in &mut self.0 {
            if matches!(p, Part::Field(f) if f == from) {
                *p = Part::Field(to.to_string());
            }
        }
        self
    }

    /// The message with its marks, as written (`⟨t_end⟩ 3: allowed …`).
    pub fn marked(&self) -> String {
        self.0
            .iter()
            .map(|p| match p {
                Part::Text(t) => t.clone(),
                Part::Field(f) => at(f),
            })
            .collect()
    }

    /// The part after the word "allowed" (`⟨batches⟩ 9: allowed an integer
    /// in [10, 1000]` → `an integer in [10, 1000]`), else after the first
    /// `": "`; marks kept.
    pub fn allowed(&self) -> Option<Message> {
        let m = self.marked();
        let rest = match m.find("allowed") {
            Some(i) => &m[i + "allowed".len()..],
            None => m.split_once(": ").map_or("", |(_, r)| r),
        };
        let rest = rest.trim_start_matches(':').trim();
        (!rest.is_empty()).then(|| Message::new(rest))
    }
}

impl fmt::Display for Message {
    /// The neutral spelling.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(Spelling::Neutral))
    }
}

/// What a field takes, as far as a front end must know to read it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// On or off (a flag without value; `--no-<name>` when on by default).
    Switch,
    /// One number.
    Number,
    /// One word (a name, a path).
    Text,
    /// A list of numbers (a flag's text: comma-separated).
    Numbers,
    /// A list of words (a flag's text: comma-separated).
    Texts,
}

impl Kind {
    /// A list.
    pub fn is_list(self) -> bool {
        matches!(self, Kind::Numbers | Kind::Texts)
    }
    /// Numbers (a flag's value may start with `-`: the study states the range).
    pub fn is_numeric(self) -> bool {
        matches!(self, Kind::Number | Kind::Numbers)
    }
}

/// One field of a study's `Config`.
#[derive(Clone, Copy, Debug)]
pub struct Field {
    /// The Rust name, `t_end`.
    pub name: &'static str,
    /// Its document (`⟨name⟩` marks other fields).
    pub doc: &'static str,
    /// What it takes.
    pub kind: Kind,
}

impl Field {
    /// The document with the fields spelled as `spelling` says, one paragraph.
    pub fn doc(&self, spelling: Spelling) -> String {
        Message::new(&self.doc.split_whitespace().collect::<Vec<_>>().join(" ")).render(spelling)
    }
}

/// A study's configuration as its front ends see it (`study_config!`).
pub trait Study: DeserializeOwned + Default + Clone {
    /// The study's name, `beam_statistics` (`cargo xtask beam-statistics`).
    const NAME: &'static str;
    /// What the study does (the `Config`'s document; `⟨name⟩` marks a field).
    const DOC: &'static str;
    /// Every field, in declaration order.
    const FIELDS: &'static [Field];
    /// Field `name`'s value as text (lists comma-separated); `None` for an
    /// absent optional value (its default is computed).
    fn show(&self, name: &str) -> Option<String>;
    /// The study's checks (`Config::validate`).
    fn check(&self) -> Result<(), StudyError>;
}

/// A field type's [`Kind`] and its value as text (the defaults a front end shows).
pub trait FieldType {
    /// What it takes.
    const KIND: Kind;
    /// The value as text; `None` for an absent optional value.
    fn show(&self) -> Option<String>;
}

macro_rules! field_type {
    ($kind:ident: $($t:ty),*) => {$(
        impl FieldType for $t {
            const KIND: Kind = Kind::$kind;
            fn show(&self) -> Option<String> { Some(self.to_string()) }
        }
    )*};
}
field_type!(Number: usize, u64);
field_type!(Text: String, signorini_schemes::SchemeSpec, signorini_fem::BarMass);

impl FieldType for f64 {
    const KIND: Kind = Kind::Number;
    /// `5e-5`, `0.25`, `320`: exponent form below 1e-3 and from 1e5.
    fn show(&self) -> Option<String> {
        let a = self.abs();
        Some(if a != 0.0 && !(1e-3..1e5).contains(&a) { format!("{self:e}") } else { format!("{self}") })
    }
}
impl FieldType for bool {
    const KIND: Kind = Kind::Switch;
    fn show(&self) -> Option<String> {
        Some(self.to_string())
    }
}
impl FieldType for std::path::PathBuf {
    const KIND: Kind = Kind::Text;
    fn show(&self) -> Option<String> {
        Some(self.display().to_string())
    }
}
impl<T: FieldType> FieldType for Option<T> {
    const KIND: Kind = T::KIND;
    fn show(&self) -> Option<String> {
        self.as_ref().and_then(T::show)
    }
}
impl<T: FieldType> FieldType for Vec<T> {
    const KIND: Kind = match T::KIND {
        Kind::Number => Kind::Numbers,
        _ => Kind::Texts,
    };
    fn show(&self) -> Option<String> {
        Some(self.iter().filter_map(T::show).collect::<Vec<_>>().join(","))
    }
}
impl<A: FieldType, B: FieldType> FieldType for (A, B) {
    const KIND: Kind = Kind::Text;
    fn show(&self) -> Option<String> {
        Some(format!("{}:{}", self.0.show()?, self.1.show()?))
    }
}

/// Declares a study's `Config` once: each field with its document, type
/// and default (`pub name: Type = default`; an optional `#[serde(...)]`
/// after the document, e.g. a `deserialize_with` for a type read from
/// text). Generates the struct (`serde::Deserialize`, unknown fields
/// refused, absent ones at their default), `Default` and [`Study`]; the
/// study writes its `validate`.
macro_rules! study_config {
    (
        $(#[doc = $sdoc:literal])*
        study $study:literal;
        pub struct $name:ident {
            $(
                $(#[doc = $doc:literal])*
                $(#[serde($($serde:tt)*)])?
                pub $field:ident : $ty:ty = $default:expr
            ),* $(,)?
        }
    ) => {
        $(#[doc = $sdoc])*
        #[derive(Clone, Debug, serde::Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct $name {
            $(
                $(#[doc = $doc])*
                $(#[serde($($serde)*)])?
                pub $field: $ty,
            )*
        }

        impl Default for $name {
            /// The defaults of `cargo xtask` and the Python package.
            fn default() -> Self {
                $name { $($field: $default,)* }
            }
        }

        impl $crate::options::Study for $name {
            const NAME: &'static str = $study;
            const DOC: &'static str = concat!($($sdoc, "\n",)*);
            const FIELDS: &'static [$crate::options::Field] = &[$(
                $crate::options::Field { name: stringify!($field), doc: concat!($($doc, "\n",)*), kind: <$ty as $crate::options::FieldType>::KIND },
            )*];
            fn show(&self, name: &str) -> Option<String> {
                match name {
                    $(stringify!($field) => $crate::options::FieldType::show(&self.$field),)*
                    _ => None,
                }
            }
            fn check(&self) -> Result<(), $crate::StudyError> {
                $name::validate(self)
            }
        }
    };
}
pub(crate) use study_config;

/// A value a front end hands over for a field, with its words for an
/// error (`'x' (a str)` in Python, `"x"` on the command line).
#[derive(Clone, Debug)]
pub struct Input {
    /// The value.
    pub value: Value,
    /// How the user wrote it.
    pub words: String,
}

/// The values [`Input`] carries.
#[derive(Clone, Debug)]
pub enum Value {
    /// A flag's text, read as the field's type: a number parsed, a list
    /// split on commas (empty pieces dropped; `none` alone: empty).
    Text(String),
    /// True or false.
    Bool(bool),
    /// An integer.
    Int(i128),
    /// A real.
    Float(f64),
    /// A string (one word; a one-word list where a list is wanted).
    Str(String),
    /// A list.
    List(Vec<Input>),
    /// Anything else.
    Other,
}

impl Input {
    /// A flag's text.
    pub fn text(s: &str) -> Self {
        Input { value: Value::Text(s.to_string()), words: format!("{s:?}") }
    }
    /// A switch given on the command line.
    pub fn switch(on: bool) -> Self {
        Input { value: Value::Bool(on), words: on.to_string() }
    }
}

/// Which out-of-range value stands in for a wrongly typed number while the
/// study's `validate` is asked for the allowed range.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Sentinel {
    /// 0 for an integer (below every minimum but 0), NaN for a real.
    Low,
    /// The largest integer (above every maximum), NaN for a real.
    High,
}

/// The first number of a wrong type: its field, the item (`[1]`), the
/// user's words, whether an integer was wanted.
#[derive(Clone, Debug)]
struct Wrong {
    field: String,
    item: String,
    words: String,
    int: bool,
}

struct Ctx {
    sentinel: Sentinel,
    wrong: RefCell<Option<Wrong>>,
}

/// A deserialization error: the message (`⟨⟩` marks the field being read
/// until [`FieldsDe`] knows it).
#[derive(Debug)]
struct DeError(String);

impl fmt::Display for DeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for DeError {}
impl de::Error for DeError {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        DeError(msg.to_string())
    }
}

/// A [`StudyError`] handed through serde from a `deserialize_with`
/// function (its marks kept, `⟨⟩` for the field being read).
pub(crate) fn de_err<E: de::Error>(e: StudyError) -> E {
    match e {
        StudyError::Config { message, .. } => E::custom(message.marked()),
        other => E::custom(other),
    }
}

/// One field's value.
struct ValueDe<'a> {
    input: &'a Input,
    field: &'a str,
    item: String,
    ctx: &'a Ctx,
}

impl<'a> ValueDe<'a> {
    fn refuse(&self, want: &str) -> DeError {
        DeError(format!("⟨⟩{}: {} is not allowed: {want}", self.item, self.input.words))
    }
    fn wrong(&self, int: bool) {
        let mut w = self.ctx.wrong.borrow_mut();
        if w.is_none() {
            *w = Some(Wrong { field: self.field.to_string(), item: self.item.clone(), words: self.input.words.clone(), int });
        }
    }
    fn float(&self) -> f64 {
        let got = match &self.input.value {
            Value::Float(x) => Some(*x),
            Value::Int(i) => Some(*i as f64),
            Value::Text(s) => s.trim().parse::<f64>().ok(),
            _ => None,
        };
        got.unwrap_or_else(|| {
            self.wrong(false);
            f64::NAN
        })
    }
    fn int(&self, max: u128) -> u128 {
        let got = match &self.input.value {
            Value::Int(i) => u128::try_from(*i).ok(),
            // A real with a whole value is that integer (80.0); 80.5 is not.
            Value::Float(f) => (f.fract() == 0.0 && *f >= 0.0 && *f < 2f64.powi(53)).then_some(*f as u128),
            Value::Text(s) => s.trim().parse::<u128>().ok(),
            _ => None,
        };
        match got.filter(|&v| v <= max) {
            Some(v) => v,
            None => {
                self.wrong(true);
                match self.ctx.sentinel {
                    Sentinel::Low => 0,
                    Sentinel::High => max,
                }
            }
        }
    }
    fn items(&self) -> Vec<(String, Input)> {
        match &self.input.value {
            Value::List(v) => v.iter().enumerate().map(|(i, x)| (format!("{}[{i}]", self.item), x.clone())).collect(),
            Value::Text(s) => {
                let pieces: Vec<&str> = s.split(',').map(str::trim).filter(|p| !p.is_empty()).collect();
                if pieces.iter().all(|p| *p == "none") {
                    return Vec::new();
                }
                // A flag's items are named by the flag alone.
                pieces.into_iter().map(|p| (self.item.clone(), Input::text(p))).collect()
            }
            _ => vec![(format!("{}[0]", self.item), self.input.clone())],
        }
    }
}

macro_rules! ints {
    ($($method:ident $visit:ident $t:ty),*) => {$(
        fn $method<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
            v.$visit(self.int(<$t>::MAX as u128) as $t)
        }
    )*};
}

impl<'de> de::Deserializer<'de> for ValueDe<'_> {
    type Error = DeError;

    fn deserialize_any<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        match &self.input.value {
            Value::Bool(b) => v.visit_bool(*b),
            Value::Int(i) => v.visit_i128(*i),
            Value::Float(x) => v.visit_f64(*x),
            Value::Text(s) | Value::Str(s) => v.visit_str(s),
            Value::List(_) => self.deserialize_seq(v),
            Value::Other => Err(self.refuse("a value")),
        }
    }
    fn deserialize_bool<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        match &self.input.value {
            Value::Bool(b) => v.visit_bool(*b),
            Value::Text(s) if s == "true" || s == "false" => v.visit_bool(s == "true"),
            _ => Err(self.refuse("True or False")),
        }
    }
    ints!(deserialize_u8 visit_u8 u8, deserialize_u16 visit_u16 u16, deserialize_u32 visit_u32 u32, deserialize_u64 visit_u64 u64);
    fn deserialize_f64<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        v.visit_f64(self.float())
    }
    fn deserialize_f32<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        v.visit_f32(self.float() as f32)
    }
    fn deserialize_str<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        match &self.input.value {
            Value::Text(s) | Value::Str(s) => v.visit_str(s),
            _ => Err(self.refuse("a string")),
        }
    }
    fn deserialize_string<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        self.deserialize_str(v)
    }
    fn deserialize_option<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        v.visit_some(self)
    }
    fn deserialize_seq<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        let items = self.items();
        v.visit_seq(SeqDe { items: items.into_iter(), field: self.field, ctx: self.ctx })
    }
    fn deserialize_newtype_struct<V: Visitor<'de>>(self, _name: &'static str, v: V) -> Result<V::Value, DeError> {
        v.visit_newtype_struct(self)
    }
    serde::forward_to_deserialize_any! {
        i8 i16 i32 i64 i128 u128 char bytes byte_buf unit unit_struct tuple tuple_struct map struct enum identifier ignored_any
    }
}

struct SeqDe<'a> {
    items: std::vec::IntoIter<(String, Input)>,
    field: &'a str,
    ctx: &'a Ctx,
}

impl<'de> de::SeqAccess<'de> for SeqDe<'_> {
    type Error = DeError;
    fn next_element_seed<T: de::DeserializeSeed<'de>>(&mut self, seed: T) -> Result<Option<T::Value>, DeError> {
        match self.items.next() {
            None => Ok(None),
            Some((item, input)) => seed.deserialize(ValueDe { input: &input, field: self.field, item, ctx: self.ctx }).map(Some),
        }
    }
}

/// The fields given, as a map.
struct FieldsDe<'a> {
    entries: &'a [(String, Input)],
    ctx: &'a Ctx,
}

struct MapDe<'a> {
    entries: std::slice::Iter<'a, (String, Input)>,
    current: Option<&'a (String, Input)>,
    ctx: &'a Ctx,
}

impl<'de> de::Deserializer<'de> for FieldsDe<'_> {
    type Error = DeError;
    fn deserialize_any<V: Visitor<'de>>(self, v: V) -> Result<V::Value, DeError> {
        v.visit_map(MapDe { entries: self.entries.iter(), current: None, ctx: self.ctx })
    }
    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf option unit unit_struct newtype_struct seq tuple tuple_struct map struct enum identifier ignored_any
    }
}

impl<'de> de::MapAccess<'de> for MapDe<'_> {
    type Error = DeError;
    fn next_key_seed<K: de::DeserializeSeed<'de>>(&mut self, seed: K) -> Result<Option<K::Value>, DeError> {
        match self.entries.next() {
            None => Ok(None),
            Some(e) => {
                self.current = Some(e);
                seed.deserialize(e.0.as_str().into_deserializer()).map(Some)
            }
        }
    }
    fn next_value_seed<V: de::DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, DeError> {
        let (field, input) = self.current.ok_or_else(|| DeError("a value without its field".into()))?;
        seed.deserialize(ValueDe { input, field, item: String::new(), ctx: self.ctx }).map_err(|e| {
            // `⟨⟩` is the field being read; a message without any mark gets the field in front.
            let m = e.0.replace("⟨⟩", &at(field));
            DeError(if m.contains('⟨') { m } else { format!("{}: {m}", at(field)) })
        })
    }
}

/// The field named by a message made while reading (its first mark).
fn field_of(message: &str, fallback: &str) -> String {
    Message::new(message).fields().next().unwrap_or(fallback).to_string()
}

fn deserialize<C: Study>(entries: &[(String, Input)], sentinel: Sentinel) -> Result<(C, Option<Wrong>), StudyError> {
    let ctx = Ctx { sentinel, wrong: RefCell::new(None) };
    let c = C::deserialize(FieldsDe { entries, ctx: &ctx }).map_err(|e| StudyError::config(&field_of(&e.0, C::NAME), e.0))?;
    Ok((c, ctx.wrong.into_inner()))
}

/// What `c.validate()` says is allowed for `w`'s field, when it refuses
/// the stand-in naming that field.
fn range_of<C: Study>(c: &C, w: &Wrong) -> Option<Message> {
    // A panic on the stand-in would be a bug of `validate`: no range then.
    let e = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| c.check())).ok()?.err()?;
    let StudyError::Config { field, message } = e else { return None };
    // The error names the field, or (a check of two fields together:
    // `⟨js⟩ … / ⟨j⟩ …`) mentions it.
    if field != w.field && !message.fields().any(|f| f == w.field) {
        return None;
    }
    message.allowed()
}

/// The `Config` of study `C` from the fields a front end was given (each
/// its Rust name and value; the others at their default), not yet
/// validated. A field the study does not have is refused naming it and the
/// fields there are; a value that cannot be read names its field; a number
/// of a wrong type (a word, a switch, a fraction where an integer is
/// wanted) is refused with the range the study's `validate` states for it
/// (found by handing `validate` an out-of-range stand-in).
pub fn read<C: Study>(given: &[(String, Input)]) -> Result<C, StudyError> {
    if let Some((k, _)) = given.iter().find(|(k, _)| !C::FIELDS.iter().any(|f| f.name == k)) {
        let names: Vec<String> = C::FIELDS.iter().map(|f| at(f.name)).collect();
        return Err(StudyError::config(k, format!("{}: not an argument of the {} study (allowed: {})", at(k), C::NAME, names.join(", "))));
    }
    let (c, wrong) = deserialize::<C>(given, Sentinel::Low)?;
    let Some(w) = wrong else { return Ok(c) };
    let mut allowed = range_of(&c, &w);
    if allowed.is_none() && w.int {
        allowed = range_of(&deserialize::<C>(given, Sentinel::High)?.0, &w);
    }
    let want = allowed.map_or_else(|| if w.int { "an int >= 0".to_string() } else { "a number (int or float)".to_string() }, |m| m.marked());
    Err(StudyError::config(&w.field, format!("{}{}: {} is not allowed: {want}", at(&w.field), w.item, w.words)))
}

/// [`read`], then the study's `validate`.
pub fn read_valid<C: Study>(given: &[(String, Input)]) -> Result<C, StudyError> {
    let c = read::<C>(given)?;
    c.check()?;
    Ok(c)
}

/// `deserialize_with` helpers: a type read from text through its parser.
pub(crate) mod with {
    use super::de_err;
    use serde::{Deserialize, Deserializer};

    /// A word read by `f`, a study's parser.
    pub fn text<'de, D: Deserializer<'de>, T>(d: D, f: fn(&str) -> Result<T, crate::StudyError>) -> Result<T, D::Error> {
        let s = String::deserialize(d)?;
        f(s.trim()).map_err(de_err)
    }

    /// A list read by `f`, a study's parser of the whole list.
    pub fn list<'de, D: Deserializer<'de>, T>(d: D, f: fn(&[String]) -> Result<Vec<T>, crate::StudyError>) -> Result<Vec<T>, D::Error> {
        let v = Vec::<String>::deserialize(d)?;
        f(&v).map_err(de_err)
    }

    /// Scheme names (commas inside parentheses do not split).
    pub fn schemes<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<signorini_schemes::SchemeSpec>, D::Error> {
        list(d, crate::parse_schemes)
    }

    /// Scheme names, given (`None` when the option is not: the study's
    /// default list).
    pub fn some_schemes<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<signorini_schemes::SchemeSpec>>, D::Error> {
        schemes(d).map(Some)
    }

    /// Mass treatments.
    pub fn masses<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<signorini_fem::BarMass>, D::Error> {
        list(d, crate::parse_masses)
    }
}
