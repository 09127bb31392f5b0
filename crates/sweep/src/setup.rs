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
#[doc(hidden)]
pub struct Manifest {
    pub id: String,
    pub scene: String,
    pub param: String,
    pub from: f64,
    pub to: f64,
    pub count: usize,
    pub log: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub param2: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count2: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub log2: Option<bool>,
    pub transient: f64,
    pub record: f64,
    pub phase: f64,
    pub period_tol: f64,
    pub follow: bool,
    /// `Some(false)` with `--no-impacts`; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub impacts: Option<bool>,
    /// `[I, N]` of a shard.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<[usize; 2]>,
    /// The shard's runs `[start, end)`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub runs: Option<[usize; 2]>,
}

impl Manifest {
    /// The text of `sweep.toml`.
    pub fn text(&self) -> String {
        // Serialising a struct of numbers, strings, booleans and arrays of
        // integers cannot fail.
        format!("{MANIFEST_HEADER}{}", toml::to_string(self).unwrap_or_default())
    }

    /// Reads a `sweep.toml`.
    pub fn parse(text: &str) -> Result<Self, toml::de::Error> {
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
