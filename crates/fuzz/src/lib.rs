//! Fuzzing of the scene reader and validator of `signorini-scene` (issue 11 §3;
//! an unpublished crate of its own, so that the CLI builds without proptest).
//!
//! Two generators of scene files, and the contract every file must meet:
//!
//! * [`documents`] writes documents from the scene grammar: the tables
//!   `[bar]`, `[beam]`, `[output]` (one, both, none, unknown ones; as
//!   headers, inline tables or dotted keys), every key of [`signorini_scene`]
//!   with a value drawn from valid, boundary, out-of-range and wrong-type
//!   pools (NaN, ±inf, 0, 2^63 - 1, strings for numbers, arrays of the wrong
//!   length, random expression tokens), unknown and duplicate keys; and
//!   `[[stop]]` lists and `[obstacle]` tables (valid stops at nodes, stops off
//!   the mesh or on clamped nodes, duplicates, bad bounds, per-stop keys the
//!   scheme does not use, obstacles that fail, are not finite or exclude the
//!   initial state), classified against what the rest of the document makes
//!   certain (mesh, initial state, scheme, mass). The generator knows the
//!   class of each value it writes ([`Class`]) and so what the reader must
//!   answer.
//! * [`mutations`] applies byte-level edits to the shipped scenes.
//!
//! [`check_doc`] and [`check_text`] run `parse` and `validate` under
//! `catch_unwind` and check:
//! 1. no panic;
//! 2. a parse error is `SceneError::Toml` with a line number (or a `Field`);
//! 3. a validation error is `SceneError::Field` whose `field` is a dotted
//!    path of the grammar (`bar.dt`, `beam.stops`, `output.every`,
//!    `stop.<i>.<key>`, `obstacle.lo`, a table, or `bar/beam`) whose table
//!    (stop entry) is in the document, that names a key the
//!    document gives when it says the value "is not allowed", and whose
//!    message states what is allowed ([`states_allowed`]);
//! 4. for [`documents`] only: a file with a wrong type parses to an error, any
//!    other parses; a file whose values are all valid is accepted (and its
//!    initial fields hold the values of the expressions, computed here in
//!    Rust); a file with an invalid value is refused, naming that value's
//!    field.
//!
//! [`fuzz`] drives both generators with a seeded proptest runner; the short
//! run is `crates/fuzz/tests/fuzz.rs`, the long one `cargo xtask fuzz`.
//! [`Config`] holds the expectations that today's reader does not meet yet
//! (issue 11 §2–§3): [`Config::TODAY`] tolerates them, [`Config::STRICT`]
//! checks them.

mod bar;
mod beam;
mod check;
mod config;
mod contacts;
mod doc;
mod documents;
mod mutations;
mod oscillator;
mod pools;
mod runner;

pub use check::{check_doc, check_text, run_reader, states_allowed, Outcome};
pub use config::{Config, ALLOWED_WORDS, MAX_VALIDATED_BAR_ELEMENTS, OUTPUT_KEYS};
pub use doc::{toml_f64, Class, Doc, Exact, Form, KnownField, Table, Value};
pub use documents::documents;
pub use mutations::mutations;
pub use runner::{fuzz, Failure, Stats};
