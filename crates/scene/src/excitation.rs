//! Excitation tables of a scene: `[forcing]` (the oscillator's load),
//! `[support]` (the beam's support motion φ(t)) and `[load]` (a distributed
//! or nodal load on a bar or a beam), each a time profile:
//!
//! ```toml
//! [support]                 # or [forcing], [load]
//! profile = "sine"          # sine | cosine | harmonics | series | random
//! amplitude = 0.2           # sine / cosine: A sin(ω t + phase) / A cos(ω t + phase)
//! omega = 10.0              # rad/s; with other profiles: the frequency of the
//!                           # Poincaré section and impact phases (optional)
//! phase = 0.0               # rad (sine / cosine, optional)
//! harmonics = [[0.1, 10.0, 0.0], [0.05, 30.0, 1.5]]   # [amplitude, omega, phase] each
//! series = "drive.csv"      # a CSV `t,value` (header optional) relative to the scene
//!                           # file, or inline [[t, value], ...]; piecewise linear,
//!                           # end values held outside
//! f_lo = 1.0                # random: band [f_lo, f_hi] in Hz,
//! f_hi = 20.0
//! psd = 1e-4                # one-sided PSD (units²/Hz): a level or [[f, S], ...]
//! count = 400               # harmonics of the realisation
//! seed = 7                  # same seed, same signal
//! x = 0.75                  # [load] only: a nodal load at this mesh node
//!                           # (absent: uniform distributed load per unit length)
//! ```
//!
//! Defaults: `[forcing]` is `cosine` (the oscillator's `F cos(Ω t)`),
//! `[support]` and `[load]` are `sine`. A series support motion is refused:
//! φ'' of a piecewise-linear φ is a train of impulses, which the lifting
//! would turn into loads concentrated at single instants; give the load
//! itself in `[load]` instead.

use crate::{field, finite, positive, SceneError};
use serde::Deserialize;
use signorini_schemes::{Harmonic, ProfileError, Psd, RandomSpec, TimeProfile};
use std::path::Path;
use std::sync::Arc;

/// An excitation table: a time profile, the oscillator's load
/// (`[forcing]`), the beam's support motion φ(t) (`[support]`) or a
/// distributed or nodal load on a bar or a beam (`[load]`).
#[derive(Debug, Clone, Deserialize, PartialEq, Default)]
#[serde(deny_unknown_fields)]
pub struct ExcitationToml {
    /// `sine`, `cosine`, `harmonics`, `series` or `random` (default
    /// `cosine` in `[forcing]`, `sine` in `[support]` and `[load]`).
    pub profile: Option<String>,
    /// Amplitude A (sine, cosine: `A sin(ω t + phase)`, `A cos(ω t + phase)`).
    pub amplitude: Option<f64>,
    /// Angular frequency ω (rad/s) of a sine or cosine; with the other
    /// profiles (optional), the frequency of the Poincaré section and the
    /// impact phases.
    pub omega: Option<f64>,
    /// Phase (rad; sine, cosine; default 0).
    pub phase: Option<f64>,
    /// `[amplitude, omega, phase]` triples (profile `harmonics`).
    #[serde(default, deserialize_with = "triples")]
    pub harmonics: Option<Vec<[f64; 3]>>,
    /// Profile `series`: a CSV file `t,value` (header optional) relative to
    /// the scene file, or inline `[[t, value], …]`; piecewise linear, end
    /// values held outside. Not in `[support]` (give the load itself in
    /// `[load]`).
    pub series: Option<SeriesToml>,
    /// Random: lower band edge (Hz).
    pub f_lo: Option<f64>,
    /// Random: upper band edge (Hz).
    pub f_hi: Option<f64>,
    /// Random: one-sided PSD (units²/Hz), a level or a table `[[f, S], …]`
    /// (piecewise linear in f).
    pub psd: Option<PsdToml>,
    /// Random: number of harmonics of the realisation (default 200).
    pub count: Option<usize>,
    /// Random: seed (default 0; same seed, same signal).
    pub seed: Option<u64>,
    /// `[load]` only: the mesh node of a nodal load (absent: a uniform
    /// distributed load per unit length).
    pub x: Option<f64>,
}

/// `series`: a file or points.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum SeriesToml {
    /// A CSV file `t,value`.
    File(String),
    /// Inline `[[t, value], …]`.
    Points(Vec<Vec<f64>>),
}

/// `psd`: a level or a table.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum PsdToml {
    /// A flat level.
    Level(f64),
    /// `[[f, S], …]`, piecewise linear in f.
    Table(Vec<Vec<f64>>),
}

fn triples<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<Vec<[f64; 3]>>, D::Error> {
    let v: Vec<Vec<f64>> = Deserialize::deserialize(d)?;
    v.into_iter()
        .map(|t| <[f64; 3]>::try_from(t.as_slice()).map_err(|_| serde::de::Error::custom(format!("{} numbers are not allowed: exactly three, [amplitude, omega, phase]", t.len()))))
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// Which table, for defaults and refusals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Table {
    /// `[forcing]` (default cosine).
    Forcing,
    /// `[support]` (default sine; no series).
    Support,
    /// `[load]` (default sine; `x` allowed).
    Load,
}

impl Table {
    fn name(self) -> &'static str {
        match self {
            Table::Forcing => "forcing",
            Table::Support => "support",
            Table::Load => "load",
        }
    }
}

/// A validated excitation: the profile and the section frequency.
#[derive(Clone, Debug, PartialEq)]
pub struct Excitation {
    /// The time profile (the amplitude is in it).
    pub profile: TimeProfile,
    /// The frequency of the Poincaré section and impact phases: `omega`
    /// (given, or the sine's), if any.
    pub omega: Option<f64>,
    /// `[load]`: the node position of a nodal load.
    pub x: Option<f64>,
}

/// A profile constructor's error under the table's name: `random.f_hi` →
/// `support.f_hi`, `series.t[3]` → `load.series.t[3]`.
fn profile_error(table: &str, e: ProfileError) -> SceneError {
    let f = e.field();
    let name = match f.strip_prefix("random.") {
        Some(rest) => format!("{table}.{rest}"),
        None => format!("{table}.{f}"),
    };
    field(&name, e)
}

/// Reads a series CSV: `t,value` rows, an optional header line, `#` comments.
fn read_series(path: &Path, name: &str) -> Result<Vec<(f64, f64)>, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| field(name, format!("cannot read {}: {e}", path.display())))?;
    let mut pts = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let cols: Vec<&str> = l.split(',').map(str::trim).collect();
        let nums: Option<Vec<f64>> = cols.iter().map(|c| c.parse::<f64>().ok()).collect();
        match nums {
            Some(v) if v.len() == 2 => pts.push((v[0], v[1])),
            None if pts.is_empty() && i == 0 => continue, // a header
            _ => return Err(field(name, format!("{}: line {} is not `t,value` (two numbers)", path.display(), i + 1))),
        }
    }
    Ok(pts)
}

impl ExcitationToml {
    /// Validates the table into a profile. `base`: the scene file's folder,
    /// for a series file.
    pub fn build(&self, table: Table, base: Option<&Path>) -> Result<Excitation, SceneError> {
        let t = table.name();
        let t_name = t;
        let key = |k: &str| format!("{t}.{k}");
        let default = if table == Table::Forcing { "cosine" } else { "sine" };
        let profile = self.profile.as_deref().unwrap_or(default);
        let allowed: &[&str] = match profile {
            "sine" | "cosine" => &["amplitude", "omega", "phase"],
            "harmonics" => &["harmonics", "omega"],
            "series" => &["series", "omega"],
            "random" => &["f_lo", "f_hi", "psd", "count", "seed", "omega"],
            other => return Err(field(&key("profile"), format!("{other:?} is not allowed: \"sine\", \"cosine\", \"harmonics\", \"series\" or \"random\""))),
        };
        let given = [
            ("amplitude", self.amplitude.is_some()),
            ("omega", self.omega.is_some()),
            ("phase", self.phase.is_some()),
            ("harmonics", self.harmonics.is_some()),
            ("series", self.series.is_some()),
            ("f_lo", self.f_lo.is_some()),
            ("f_hi", self.f_hi.is_some()),
            ("psd", self.psd.is_some()),
            ("count", self.count.is_some()),
            ("seed", self.seed.is_some()),
        ];
        if let Some((k, _)) = given.iter().find(|(k, g)| *g && !allowed.contains(k)) {
            return Err(field(&key(k), format!("acts only with another profile (this one is {profile:?}, which takes {}): remove it, or set profile", allowed.join(", "))));
        }
        if self.x.is_some() && table != Table::Load {
            return Err(field(&key("x"), "acts only in [load] (a nodal load's position): remove it"));
        }
        let omega = self.omega.map(|w| positive(&key("omega"), w)).transpose()?;
        let need = |k: &str| field(&key(k), format!("is missing: profile {profile:?} needs it"));
        let built = match profile {
            "sine" | "cosine" => {
                let a = finite(&key("amplitude"), self.amplitude.ok_or_else(|| need("amplitude"))?)?;
                let w = omega.ok_or_else(|| need("omega"))?;
                let p = finite(&key("phase"), self.phase.unwrap_or(0.0))?;
                if !(a * w * w).is_finite() {
                    return Err(field(&key("amplitude"), format!("{a} is not allowed with omega = {w}: A ω² must be finite")));
                }
                if profile == "sine" && p == 0.0 {
                    TimeProfile::Sine { amplitude: a, omega: w }
                } else {
                    let shift = if profile == "cosine" { std::f64::consts::FRAC_PI_2 } else { 0.0 };
                    TimeProfile::Harmonics(Arc::from(vec![Harmonic { amplitude: a, omega: w, phase: p + shift }]))
                }
            }
            "harmonics" => {
                let h = self.harmonics.as_ref().ok_or_else(|| need("harmonics"))?;
                if h.is_empty() {
                    return Err(field(&key("harmonics"), "an empty list is not allowed: at least one [amplitude, omega, phase]"));
                }
                let mut v = Vec::with_capacity(h.len());
                for (i, [a, w, p]) in h.iter().copied().enumerate() {
                    let k = format!("harmonics[{i}]");
                    if !(a.is_finite() && w.is_finite() && p.is_finite() && w >= 0.0 && (a * w * w).is_finite()) {
                        return Err(field(&key(&k), format!("[{a}, {w}, {p}] is not allowed: finite, omega >= 0, amplitude·omega² finite")));
                    }
                    v.push(Harmonic { amplitude: a, omega: w, phase: p });
                }
                TimeProfile::harmonics(v).map_err(|e| profile_error(t_name, e))?
            }
            "series" => {
                if table == Table::Support {
                    return Err(field(
                        &key("profile"),
                        "\"series\" is not allowed for a support motion: φ'' of a piecewise-linear φ is a train of impulses; give the load itself in [load] (profile = \"series\")",
                    ));
                }
                let pts: Vec<(f64, f64)> = match self.series.as_ref().ok_or_else(|| need("series"))? {
                    SeriesToml::File(f) => {
                        let p = base.map_or_else(|| Path::new(f).to_path_buf(), |b| b.join(f));
                        read_series(&p, &key("series"))?
                    }
                    SeriesToml::Points(v) => v
                        .iter()
                        .enumerate()
                        .map(|(i, p)| {
                            <[f64; 2]>::try_from(p.as_slice())
                                .map(|[a, b]| (a, b))
                                .map_err(|_| field(&key(&format!("series[{i}]")), format!("{} numbers are not allowed: exactly two, [t, value]", p.len())))
                        })
                        .collect::<Result<_, _>>()?,
                };
                let (t, v): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
                TimeProfile::series(t, v).map_err(|e| profile_error(t_name, e))?
            }
            _ => {
                let f_lo = self.f_lo.ok_or_else(|| need("f_lo"))?;
                let f_hi = self.f_hi.ok_or_else(|| need("f_hi"))?;
                let psd = match self.psd.as_ref().ok_or_else(|| need("psd"))? {
                    PsdToml::Level(s) => Psd::Flat(*s),
                    PsdToml::Table(v) => {
                        let pairs: Vec<(f64, f64)> = v
                            .iter()
                            .enumerate()
                            .map(|(i, p)| {
                                <[f64; 2]>::try_from(p.as_slice())
                                    .map(|[a, b]| (a, b))
                                    .map_err(|_| field(&key(&format!("psd[{i}]")), format!("{} numbers are not allowed: exactly two, [f, S]", p.len())))
                            })
                            .collect::<Result<_, _>>()?;
                        let (f, s) = pairs.into_iter().unzip();
                        Psd::Table { f, s }
                    }
                };
                let spec = RandomSpec { f_lo, f_hi, psd, count: self.count.unwrap_or(200), seed: self.seed.unwrap_or(0) };
                TimeProfile::random(&spec).map_err(|e| profile_error(t_name, e))?
            }
        };
        Ok(Excitation { profile: built, omega, x: self.x })
    }
}
