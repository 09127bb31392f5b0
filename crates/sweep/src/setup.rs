//! A sweep set up: the scene, its options and id ([`Sweep`]), and its
//! manifest, `sweep.toml`.

use crate::error::{Error, SweepError};
use crate::options::{integral_grid, set_path, SweepOptions};
use crate::simulate::Plan;
use signorini_run::text::num;
use signorini_scene::{Limits, Scene, SceneError, SceneFile};
use std::path::{Path, PathBuf};

/// FNV-1a (64 bit): a stable, portable hash for sweep ids.
pub(crate) fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// A validated sweep of a scene.
pub struct Sweep {
    pub(crate) opts: SweepOptions,
    pub(crate) doc: toml::Table,
    pub(crate) id: String,
    pub(crate) limits: Limits,
    pub(crate) scene_name: String,
    pub(crate) base: Option<PathBuf>,
}

impl Sweep {
    /// Checks the options and the path, that an integer field's grid gives
    /// integral values only, and the scene at the first and last values (so
    /// a sweep fails at once; [`run`](fn@crate::run) checks every value before it runs).
    pub fn new(scene_text: &str, scene_name: &str, base: Option<PathBuf>, opts: SweepOptions, limits: Limits) -> Result<Self, Error> {
        opts.validate()?;
        let doc: toml::Table = toml::from_str(scene_text).map_err(SceneError::Toml)?;
        let mut h = fnv1a(scene_text.as_bytes(), 0xcbf2_9ce4_8422_2325);
        let mut key = format!(
            "|{}|{:016x}|{:016x}|{}|{}|{:016x}|{:016x}|{:016x}|{}|{:016x}",
            opts.param,
            opts.from.to_bits(),
            opts.to.to_bits(),
            opts.count,
            opts.log,
            opts.transient.to_bits(),
            opts.record.to_bits(),
            opts.phase.to_bits(),
            opts.follow,
            opts.period_tol.to_bits()
        );
        if !opts.impacts {
            key += "|no-impacts";
        }
        if let Some(a) = &opts.second {
            key += &format!("|{}|{:016x}|{:016x}|{}|{}", a.param, a.from.to_bits(), a.to.to_bits(), a.count, a.log);
        }
        h = fnv1a(key.as_bytes(), h);
        // A key that would not act is refused: the sweep's runs are not
        // watched by the energy monitor of `signorini run`.
        if doc.get("output").and_then(|o| o.get("energy_warn")).is_some() {
            return Err(signorini_scene::field(
                "output.energy_warn",
                "is not allowed in a sweep: its runs are not watched against their energy budget (run one value with `signorini run` for the warning); allowed: no energy_warn",
            )
            .into());
        }
        let sweep = Self { id: format!("{h:016x}"), opts, doc, limits, scene_name: scene_name.into(), base };
        let o = &sweep.opts;
        integral_grid(&sweep.doc, &o.param, "", o.from, o.to, o.count, o.log)?;
        if let Some(a) = &o.second {
            integral_grid(&sweep.doc, &a.param, "2", a.from, a.to, a.count, a.log)?;
        }
        let last = sweep.opts.total() - 1;
        for r in [0, last] {
            sweep.scene(sweep.opts.value(r))?;
        }
        Ok(sweep)
    }

    /// A sweep of the scene file `path` (its text `text`): files the scene
    /// names are found next to it.
    pub fn from_file(path: &Path, text: &str, opts: SweepOptions, limits: Limits) -> Result<Self, Error> {
        let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned());
        Self::new(text, &name, path.parent().map(Path::to_path_buf), opts, limits)
    }

    /// The sweep's id (hash of the scene text and the options that change numbers).
    pub fn id(&self) -> &str {
        &self.id
    }

    /// The options.
    pub fn options(&self) -> &SweepOptions {
        &self.opts
    }

    /// The scene document with the swept field(s) at `value`.
    pub fn document(&self, value: (f64, Option<f64>)) -> Result<toml::Table, SweepError> {
        let mut doc = self.doc.clone();
        set_path(&mut doc, &self.opts.param, value.0)?;
        if let (Some(a), Some(v)) = (&self.opts.second, value.1) {
            set_path(&mut doc, &a.param, v)?;
        }
        Ok(doc)
    }

    /// The validated scene at `value`, its horizon set to the sweep's.
    pub fn scene(&self, value: (f64, Option<f64>)) -> Result<(SceneFile, Scene, Plan), Error> {
        // A map's error names both values: `--param P = v, --param2 Q = w`.
        let (path, shown) = match (&self.opts.second, value.1) {
            (Some(a), Some(v)) => (format!("{} = {}, --param2 {}", self.opts.param, num(value.0), a.param), v),
            _ => (self.opts.param.clone(), value.0),
        };
        let bad = |e: SceneError| SweepError::Value { path: path.clone(), value: shown, error: e };
        let doc = self.document(value)?;
        let parse = |doc: toml::Table| -> Result<SceneFile, SweepError> {
            let mut f = SceneFile::from_table(doc).map_err(bad)?;
            f.base = self.base.clone();
            Ok(f)
        };
        // The forcing and dt first, the scene's own horizon left aside: the
        // sweep's replaces it (a swept dt need not divide the scene's t_end).
        let file = parse(doc.clone())?;
        let scene = file.validate_clock(&self.limits).map_err(bad)?;
        let (omega, dt, key) = scene.sweep_clock().ok_or_else(|| {
            SweepError::Scene(format!(
                "{}: a sweep samples the response at the forcing period, and this scene has no periodic forcing (an oscillator's [forcing], a beam's support motion)",
                self.scene_name
            ))
        })?;
        let period = std::f64::consts::TAU / omega;
        let total = self.opts.transient + self.opts.record;
        let steps = (total * period / dt).round().max(1.0);
        let t_end = steps * dt;
        let mut doc = doc;
        set_path(&mut doc, key, t_end).map_err(|e| SweepError::Scene(format!("cannot set the horizon {key}: {e}")))?;
        let file = parse(doc)?;
        let scene = file.validate_with(&self.limits).map_err(bad)?;
        Ok((file, scene, Plan { omega, dt, t_end, record_from: self.opts.transient * period, phase: self.opts.phase, period_tol: self.opts.period_tol }))
    }

    /// The manifest of this sweep (of `shard` of it).
    pub(crate) fn manifest(&self, shard: Option<(usize, usize)>) -> Manifest {
        let o = &self.opts;
        let a = o.second.as_ref();
        Manifest {
            id: self.id.clone(),
            scene: self.scene_name.clone(),
            param: o.param.clone(),
            from: o.from,
            to: o.to,
            count: o.count,
            log: o.log,
            param2: a.map(|a| a.param.clone()),
            from2: a.map(|a| a.from),
            to2: a.map(|a| a.to),
            count2: a.map(|a| a.count),
            log2: a.map(|a| a.log),
            transient: o.transient,
            record: o.record,
            phase: o.phase,
            period_tol: o.period_tol,
            follow: o.follow,
            impacts: (!o.impacts).then_some(false),
            shard: shard.map(|(i, n)| [i, n]),
            runs: shard.map(|_| [o.runs().start, o.runs().end]),
        }
    }
}

/// The first line of `sweep.toml`.
pub(crate) const MANIFEST_HEADER: &str = "# signorini sweep manifest: merge checks that shards share the id\n";

/// `sweep.toml`: the sweep's id, scene and options (the second axis of a
/// map, `impacts = false` with `--no-impacts`, and a shard's `shard` and
/// `runs` only when they apply), written with the toml crate in this
/// field order after [`MANIFEST_HEADER`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Manifest {
    pub(crate) id: String,
    pub(crate) scene: String,
    pub(crate) param: String,
    pub(crate) from: f64,
    pub(crate) to: f64,
    pub(crate) count: usize,
    pub(crate) log: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) param2: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) from2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) to2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) count2: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) log2: Option<bool>,
    pub(crate) transient: f64,
    pub(crate) record: f64,
    pub(crate) phase: f64,
    pub(crate) period_tol: f64,
    pub(crate) follow: bool,
    /// `Some(false)` with `--no-impacts`; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) impacts: Option<bool>,
    /// `[I, N]` of a shard.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) shard: Option<[usize; 2]>,
    /// The shard's runs `[start, end)`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) runs: Option<[usize; 2]>,
}

impl Manifest {
    /// The text of `sweep.toml`.
    pub(crate) fn text(&self) -> String {
        // Serialising a struct of numbers, strings, booleans and arrays of
        // integers cannot fail.
        format!("{MANIFEST_HEADER}{}", toml::to_string(self).unwrap_or_default())
    }

    /// Reads a `sweep.toml`.
    pub(crate) fn parse(text: &str) -> Result<Self, toml::de::Error> {
        toml::from_str(text)
    }

    /// Whether the runs have a second parameter (a map).
    pub(crate) fn is_map(&self) -> bool {
        self.param2.is_some()
    }
}

/// The `id` of a manifest's text, also of one that is not this version's.
pub(crate) fn manifest_id(text: &str) -> Option<String> {
    text.parse::<toml::Table>().ok()?.get("id")?.as_str().map(str::to_string)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fmt::Write as _;

    /// The manifest as it was written by hand before the toml crate wrote
    /// it (`writeln!` with `{:?}` for strings and floats).
    fn by_hand(m: &Manifest) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "# signorini sweep manifest: merge checks that shards share the id");
        let _ = writeln!(s, "id = \"{}\"", m.id);
        let _ = writeln!(s, "scene = {:?}", m.scene);
        let _ = writeln!(s, "param = {:?}", m.param);
        let _ = writeln!(s, "from = {:?}\nto = {:?}\ncount = {}\nlog = {}", m.from, m.to, m.count, m.log);
        if let Some(p) = &m.param2 {
            let _ = writeln!(s, "param2 = {:?}\nfrom2 = {:?}\nto2 = {:?}\ncount2 = {}\nlog2 = {}", p, m.from2.unwrap(), m.to2.unwrap(), m.count2.unwrap(), m.log2.unwrap());
        }
        let _ = writeln!(s, "transient = {:?}\nrecord = {:?}\nphase = {:?}\nperiod_tol = {:?}\nfollow = {}", m.transient, m.record, m.phase, m.period_tol, m.follow);
        if m.impacts == Some(false) {
            let _ = writeln!(s, "impacts = false");
        }
        if let (Some([i, n]), Some([a, b])) = (m.shard, m.runs) {
            let _ = writeln!(s, "shard = [{i}, {n}]\nruns = [{a}, {b}]");
        }
        s
    }

    fn manifest(from: f64, to: f64, scene: &str, map: bool, shard: bool) -> Manifest {
        Manifest {
            id: "a60189f356524119".into(),
            scene: scene.into(),
            param: "support.omega".into(),
            from,
            to,
            count: 1000,
            log: false,
            param2: map.then(|| "stop.0.hi".into()),
            from2: map.then_some(to),
            to2: map.then_some(from),
            count2: map.then_some(7),
            log2: map.then_some(true),
            transient: 20.0,
            record: 2.5,
            phase: from.abs().min(6.0),
            period_tol: 0.001,
            follow: !map,
            impacts: map.then_some(false),
            shard: shard.then_some([1, 4]),
            runs: shard.then_some([250, 500]),
        }
    }

    /// The toml crate writes what the hand-written manifest was, byte for
    /// byte, for numbers in `[1e-4, 1e16)` in magnitude (or 0) and names
    /// without `"` or `\` (the reference sweep's among them), and reads it
    /// back to the same values.
    #[test]
    fn the_toml_manifest_is_the_hand_written_one() {
        let floats = [4.0, 16.0, 0.0, 0.001, 0.1, 1e-4, 123456789.125, 1e15, 9.999e15, -3.5, 1.0 / 3.0, 9.5, 2.0 * std::f64::consts::PI];
        for (k, &from) in floats.iter().enumerate() {
            let to = floats[(k + 3) % floats.len()];
            for scene in ["beam-fig2-support.toml", "my scene (2).toml", "é.toml", "t\tab.toml", "it's.toml"] {
                for (map, shard) in [(false, false), (true, false), (false, true), (true, true)] {
                    let m = manifest(from, to, scene, map, shard);
                    assert_eq!(m.text(), by_hand(&m), "from {from:?} to {to:?} scene {scene:?} map {map} shard {shard}");
                    assert_eq!(Manifest::parse(&m.text()).unwrap(), m);
                }
            }
        }
    }

    /// Where the two differ, both are TOML for the same values: the toml
    /// crate writes floats below 1e-4 or from 1e16 in magnitude in
    /// positional notation (`0.00001`, `10000000000000000.0`: Rust's
    /// `Display`, where `{:?}` wrote `1e-5`, `1e16`), and a name with `"`
    /// or `\` as a literal string (`'a"b.toml'`) or a multi-line one,
    /// where `{:?}` wrote Rust escapes. A folder written by hand (an older
    /// version) still resumes and merges: it reads to the same manifest.
    #[test]
    fn where_the_texts_differ_the_values_do_not() {
        let floats = [1e-5, 2.5e-7, 3e-300, f64::MIN_POSITIVE, 1e16, 1e20, 6.02e23, -1e300, f64::MAX];
        for (k, &from) in floats.iter().enumerate() {
            let to = floats[(k + 1) % floats.len()];
            for scene in ["beam.toml", "a\"b.toml", "c:\\x\\s.toml", "it's \"x\".toml"] {
                for (map, shard) in [(false, false), (true, true)] {
                    let m = manifest(from, to, scene, map, shard);
                    assert_ne!(m.text(), by_hand(&m));
                    for text in [m.text(), by_hand(&m)] {
                        let back = Manifest::parse(&text).unwrap();
                        assert_eq!(back, m, "{text}");
                        assert_eq!((back.from.to_bits(), back.to.to_bits()), (m.from.to_bits(), m.to.to_bits()));
                    }
                }
            }
        }
    }
}
