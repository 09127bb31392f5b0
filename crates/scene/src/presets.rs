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

/// Sets the value at the dotted `path` (table keys, `forcing.omega`) of a
/// scene document. Every table on the way must exist (an error names the
/// path otherwise); the last key is replaced, or added when the document
/// leaves it at its default, and the scene reader then decides whether
/// the scene has such a key.
pub fn set_path(doc: &mut toml::Table, path: &str, value: toml::Value) -> Result<(), SceneError> {
    let segs: Vec<&str> = path.split('.').collect();
    let Some((last, parents)) = segs.split_last().filter(|_| segs.iter().all(|s| !s.is_empty())) else {
        return Err(field(path, "allowed a dotted path of keys, e.g. forcing.omega"));
    };
    let mut table = doc;
    let mut walked = String::new();
    for s in parents {
        walked = if walked.is_empty() { s.to_string() } else { format!("{walked}.{s}") };
        table = match table.get_mut(*s) {
            Some(toml::Value::Table(t)) => t,
            Some(_) => return Err(field(path, format!("{walked} is not a table"))),
            None => return Err(field(path, format!("{walked} is not in the scene"))),
        };
    }
    table.insert(last.to_string(), value);
    Ok(())
}
