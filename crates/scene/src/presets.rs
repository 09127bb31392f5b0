//! The scene files the studies start from (`data/scenes/`, compiled in),
//! and edits of their values by dotted path.
//!
//! A study that needs a preset at another horizon, step or frequency
//! edits the parsed document, never the text: [`set_path`] walks the
//! document and fails naming the path when a table on the way is missing,
//! and [`Preset::edited`] reads the result with the scene reader, which
//! refuses a key it does not know. An edit of a key that is not there
//! therefore fails; it cannot leave the value as it was, as a replacement
//! of text that no longer matches the file would.
//!
//! ```
//! use signorini_scene::presets::Preset;
//!
//! let f = Preset::Oscillator.edited(&[("forcing.omega", 1.8.into()), ("oscillator.t_end", 50.0.into())])?;
//! assert_eq!(f.oscillator.as_ref().map(|o| o.t_end), Some(50.0));
//! // A key the scene does not have is refused, not ignored.
//! assert!(Preset::Oscillator.edited(&[("forcing.omgea", 1.8.into())]).is_err());
//! assert!(Preset::Oscillator.edited(&[("forcng.omega", 1.8.into())]).is_err());
//! # Ok::<(), signorini_scene::SceneError>(())
//! ```

use crate::{field, SceneError, SceneFile};

/// A scene file of `data/scenes/` the studies start from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Preset {
    /// `beam-fig2-support.toml`: the paper's beam (fig. 2) driven by its support.
    Fig2Support,
    /// `beam-obstacles.toml`: the beam between obstacles along its whole length.
    BeamObstacles,
    /// `oscillator.toml`: the forced impact oscillator.
    Oscillator,
}

impl Preset {
    /// The file's text, as compiled in.
    pub fn text(self) -> &'static str {
        match self {
            Preset::Fig2Support => include_str!("../../../data/scenes/beam-fig2-support.toml"),
            Preset::BeamObstacles => include_str!("../../../data/scenes/beam-obstacles.toml"),
            Preset::Oscillator => include_str!("../../../data/scenes/oscillator.toml"),
        }
    }

    /// The file's name in `data/scenes/`.
    pub fn file(self) -> &'static str {
        match self {
            Preset::Fig2Support => "beam-fig2-support.toml",
            Preset::BeamObstacles => "beam-obstacles.toml",
            Preset::Oscillator => "oscillator.toml",
        }
    }

    /// The parsed document.
    pub fn document(self) -> Result<toml::Table, SceneError> {
        self.text().parse::<toml::Table>().map_err(|e| field(self.file(), e))
    }

    /// The scene with each `(path, value)` of `edits` set ([`set_path`]),
    /// read by the scene reader (unknown keys refused); not validated.
    pub fn edited(self, edits: &[(&str, toml::Value)]) -> Result<SceneFile, SceneError> {
        edit(self.document()?, edits)
    }
}

/// The scene of `doc` with each `(path, value)` of `edits` set
/// ([`set_path`]), read by the scene reader (unknown keys refused).
pub fn edit(mut doc: toml::Table, edits: &[(&str, toml::Value)]) -> Result<SceneFile, SceneError> {
    for (path, value) in edits {
        set_path(&mut doc, path, value.clone())?;
    }
    SceneFile::from_table(doc)
}

/// Sets the value at the dotted `path` of a scene document: segments are
/// table keys or array indices (`forcing.omega`, `stop.0.hi`). Every table
/// or list on the way must exist (an error names the path and, for a
/// missing key, the keys that are there); the last key is replaced, or
/// added when the document leaves it at its default, and the scene reader
/// then decides whether the scene has such a key; the last index of a list
/// must be one of its entries. The one path editor of scene documents: the
/// sweep's and the orbit families' numeric edits go through it.
pub fn set_path(doc: &mut toml::Table, path: &str, value: toml::Value) -> Result<(), SceneError> {
    let segs = segments(path)?;
    let Some((last, parents)) = segs.split_last() else {
        return Err(field(path, PATH_FORM));
    };
    let mut here = toml::Value::Table(std::mem::take(doc));
    let result = (|| {
        let (cur, walked) = walk(&mut here, parents, path)?;
        match cur {
            toml::Value::Table(t) => {
                t.insert(last.to_string(), value);
                Ok(())
            }
            toml::Value::Array(a) => {
                let len = a.len();
                let i: usize = last.parse().map_err(|_| field(path, format!("{walked} is a list: the next segment is an index 0..{len}")))?;
                let slot = a.get_mut(i).ok_or_else(|| field(path, format!("{walked} has {len} entries: index {i} is out of range")))?;
                *slot = value;
                Ok(())
            }
            _ => Err(field(path, format!("{walked} is a value, not a table"))),
        }
    })();
    if let toml::Value::Table(t) = here {
        *doc = t;
    }
    result
}

/// The value at the dotted `path` (keys and array indices, as for
/// [`set_path`]) of a scene document, `None` where a segment is missing.
pub fn get_path<'a>(doc: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let mut segs = path.split('.');
    let mut cur = doc.get(segs.next()?)?;
    for s in segs {
        cur = match cur {
            toml::Value::Table(t) => t.get(s),
            toml::Value::Array(a) => s.parse::<usize>().ok().and_then(|i| a.get(i)),
            _ => None,
        }?;
    }
    Some(cur)
}

/// What a dotted path is, for an error about one.
const PATH_FORM: &str = "allowed a dotted path of keys and array indices, e.g. forcing.omega, support.amplitude, stop.0.hi";

fn segments(path: &str) -> Result<Vec<&str>, SceneError> {
    let segs: Vec<&str> = path.split('.').collect();
    if segs.iter().any(|s| s.is_empty()) {
        return Err(field(path, PATH_FORM));
    }
    Ok(segs)
}

/// Walks `parents` from `root`: the value reached and its dotted name.
fn walk<'a>(root: &'a mut toml::Value, parents: &[&str], path: &str) -> Result<(&'a mut toml::Value, String), SceneError> {
    let mut cur = root;
    let mut walked = String::new();
    for s in parents {
        let name = if walked.is_empty() { s.to_string() } else { format!("{walked}.{s}") };
        let hint = keys_hint(cur, &walked);
        cur = match cur {
            toml::Value::Table(t) => t.get_mut(*s),
            toml::Value::Array(a) => s.parse::<usize>().ok().and_then(move |i| a.get_mut(i)),
            _ => None,
        }
        .ok_or_else(|| field(path, format!("{name} is not in the scene{hint}")))?;
        walked = name;
    }
    Ok((cur, walked))
}

/// The keys of a table, for an error about a key that is not there.
fn keys_hint(v: &toml::Value, walked: &str) -> String {
    match v {
        toml::Value::Table(t) if !t.is_empty() => {
            let keys: Vec<&str> = t.keys().map(String::as_str).collect();
            format!(" ({} has: {})", if walked.is_empty() { "the scene" } else { walked }, keys.join(", "))
        }
        _ => String::new(),
    }
}
