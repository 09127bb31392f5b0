//! The contract every file must meet: [`check_text`], [`check_doc`].

use crate::config::{Config, ALLOWED_WORDS, MAX_VALIDATED_BAR_ELEMENTS, OUTPUT_KEYS};
use crate::doc::{Class, Doc};
use signorini_scene::{Scene, SceneError, SceneFile};
use std::panic::{catch_unwind, AssertUnwindSafe};

// -------------------------------------------------------------- contract --

/// What `parse` and `validate` returned for a text.
// One outcome per generated document: the size of the scene variant does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Outcome {
    /// `parse` failed.
    ParseError(SceneError),
    /// `parse` succeeded; `validate`'s answer (`None`: not validated, the bar
    /// has more than [`MAX_VALIDATED_BAR_ELEMENTS`] elements).
    Parsed(Box<SceneFile>, Option<Result<Scene, SceneError>>),
}

/// Runs `parse` and `validate` under `catch_unwind`: a panic is an `Err`
/// with its message.
pub fn run_reader(text: &str, cfg: Config) -> Result<Outcome, String> {
    catch_unwind(AssertUnwindSafe(|| match SceneFile::parse(text) {
        Err(e) => Outcome::ParseError(e),
        Ok(file) => {
            let too_big = !cfg.huge_sizes && file.bar.as_ref().is_some_and(|b| b.elements > MAX_VALIDATED_BAR_ELEMENTS);
            let v = if too_big { None } else { Some(file.validate()) };
            Outcome::Parsed(Box::new(file), v)
        }
    }))
    .map_err(|p| {
        let msg = p.downcast_ref::<String>().cloned().or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string())).unwrap_or_else(|| "(no message)".into());
        format!("panic: {msg}")
    })
}

/// The message without the quoted input it echoes (`"…"` with `\"` escapes).
pub(crate) fn strip_quoted(m: &str) -> String {
    let mut out = String::new();
    let mut chars = m.chars();
    while let Some(c) = chars.next() {
        if c == '"' {
            while let Some(d) = chars.next() {
                match d {
                    '\\' => {
                        chars.next();
                    }
                    '"' => break,
                    _ => {}
                }
            }
            out.push_str("\"…\"");
        } else {
            out.push(c);
        }
    }
    out
}

/// Whether a TOML error message gives a line number ("at line 3").
pub(crate) fn has_line_number(m: &str) -> bool {
    m.match_indices("line ").any(|(i, _)| m[i + 5..].starts_with(|c: char| c.is_ascii_digit()))
}

/// Whether the document gives the key a validation error names (`None`:
/// the path is not a key of the grammar).
pub(crate) fn given(file: &SceneFile, path: &str) -> Option<bool> {
    let (table, key) = path.split_once('.')?;
    Some(match table {
        "bar" => {
            let b = file.bar.as_ref()?;
            match key {
                "benchmark" => b.benchmark.is_some(),
                "length" => b.length.is_some(),
                "wave_speed" => b.wave_speed.is_some(),
                "far_end" => b.far_end.is_some(),
                "gap" => b.gap.is_some(),
                "body_force" => b.body_force.is_some(),
                "initial_displacement" => b.initial_displacement.is_some(),
                "initial_velocity" => b.initial_velocity.is_some(),
                "dt" => b.dt.is_some(),
                "ratio" => b.ratio.is_some(),
                "t_end" => b.t_end.is_some(),
                // Required, or with a default a user may have written.
                "elements" | "mass" | "scheme" => true,
                _ => return None,
            }
        }
        "beam" => {
            let b = file.beam.as_ref()?;
            match key {
                "scene" => b.scene.is_some(),
                "elements" => b.elements.is_some(),
                "dt" => b.dt.is_some(),
                "t_end" => b.t_end.is_some(),
                "contact" => b.contact.is_some(),
                "beta" => b.beta.is_some(),
                "penalty_stiffness" => b.penalty_stiffness.is_some(),
                "stops" => b.stops.is_some(),
                "support" => b.support.is_some(),
                "force" => true,
                _ => return None,
            }
        }
        "output" if OUTPUT_KEYS.contains(&key) => true,
        "oscillator" => {
            let o = file.oscillator.as_ref()?;
            match key {
                "damping_ratio" => o.damping_ratio.is_some(),
                "restitution" => o.restitution.is_some(),
                "initial_displacement" => o.initial_displacement.is_some(),
                "initial_velocity" => o.initial_velocity.is_some(),
                "scheme" => o.scheme.is_some(),
                "stop" => o.stop.is_some(),
                "stops" => o.stops.is_some(),
                "mass" | "stiffness" | "dt" | "t_end" => true,
                _ => return None,
            }
        }
        "forcing" | "support" | "load" => {
            let e = match table {
                "forcing" => file.forcing.as_ref(),
                "support" => file.support.as_ref(),
                _ => file.load.as_ref(),
            }?;
            // `harmonics[2]`, `series.t[3]`, `psd[1]`: the list's key.
            let base = key.split(['[', '.']).next().unwrap_or(key);
            match base {
                "profile" => e.profile.is_some(),
                "amplitude" => e.amplitude.is_some(),
                "omega" => e.omega.is_some(),
                "phase" => e.phase.is_some(),
                "harmonics" => e.harmonics.is_some(),
                "series" => e.series.is_some(),
                "f_lo" => e.f_lo.is_some(),
                "f_hi" => e.f_hi.is_some(),
                "psd" => e.psd.is_some(),
                "count" => e.count.is_some(),
                "seed" => e.seed.is_some(),
                "x" => e.x.is_some(),
                _ => return None,
            }
        }
        "stop" => {
            let (i, key) = key.split_once('.')?;
            let st = file.stop.get(i.parse::<usize>().ok()?)?;
            match key {
                "x" => true,
                "lo" => st.lo.is_some(),
                "hi" => st.hi.is_some(),
                "restitution" => st.restitution.is_some(),
                "stiffness" => st.stiffness.is_some(),
                _ => return None,
            }
        }
        "obstacle" => {
            let o = file.obstacle.as_ref()?;
            match key {
                "lo" => o.lo.is_some(),
                "hi" => o.hi.is_some(),
                _ => return None,
            }
        }
        _ => return None,
    })
}

/// The rules every validation error meets, whatever the input.
pub(crate) fn check_validation_error(file: &SceneFile, e: &SceneError, cfg: Config) -> Result<(), String> {
    let SceneError::Field { field, message } = e else {
        return Err(format!("validation error is not SceneError::Field: {e:?}"));
    };
    let tables_ok = match field.as_str() {
        "bar/beam" => file.bar.is_some() == file.beam.is_some(),
        "bar" => file.bar.is_some(),
        "beam" => file.beam.is_some(),
        "output" => true,
        "stop" => !file.stop.is_empty(),
        "obstacle" => file.obstacle.is_some(),
        "oscillator" => file.oscillator.is_some(),
        "forcing" => file.forcing.is_some(),
        "support" => file.support.is_some(),
        "load" => file.load.is_some(),
        "" => return Err("empty field path".into()),
        path => match given(file, path) {
            None => return Err(format!("field {path:?} is not a key of the scene grammar, or its table is not in the document")),
            Some(g) => {
                if strip_quoted(message).contains("is not allowed") && !g {
                    return Err(format!("{path}: says a value \"is not allowed\" but the document does not give {path}: {message}"));
                }
                true
            }
        },
    };
    if !tables_ok {
        return Err(format!("field {field:?} names a table the document does not have (or bar/beam when exactly one is given)"));
    }
    let is_expression_key = ["bar.initial_displacement", "bar.initial_velocity", "obstacle.lo", "obstacle.hi"].contains(&field.as_str());
    let exempt = !cfg.expression_errors && is_expression_key && message.starts_with("expression ");
    if !exempt && !states_allowed(message) {
        return Err(format!("{field}: the message does not state what is allowed (\"not allowed: <what is>\", or one of {ALLOWED_WORDS:?}): {message:?}"));
    }
    Ok(())
}

/// Whether a message states what is allowed: "… is not allowed: …" with
/// the range after the colon, or, without "not allowed", one of
/// [`ALLOWED_WORDS`]; the quoted input a message echoes does not count.
pub fn states_allowed(message: &str) -> bool {
    let m = strip_quoted(message);
    match m.find("not allowed") {
        Some(i) => m[i + "not allowed".len()..].strip_prefix(':').is_some_and(|rest| !rest.trim().is_empty()),
        None => ALLOWED_WORDS.iter().any(|w| m.contains(w)),
    }
}

/// The rules every input meets: no panic, typed errors that name a field
/// and say what is allowed. Returns the outcome for further checks.
pub fn check_text(text: &str, cfg: Config) -> Result<Outcome, String> {
    let outcome = run_reader(text, cfg)?;
    match &outcome {
        Outcome::ParseError(SceneError::Toml(e)) if !has_line_number(&e.to_string()) => return Err(format!("TOML error without a line number: {:?}", e.to_string())),
        Outcome::ParseError(SceneError::Toml(_)) => {}
        Outcome::ParseError(e @ SceneError::Field { field, message }) => {
            if field.is_empty() || !states_allowed(message) {
                return Err(format!("parse field error without a field or an allowed range: {e:?}"));
            }
        }
        // SceneError is non-exhaustive: a kind this check does not know breaks the rule.
        Outcome::ParseError(e) => return Err(format!("parse error neither Toml nor Field: {e:?}")),
        Outcome::Parsed(file, Some(Err(e))) => check_validation_error(file, e, cfg)?,
        Outcome::Parsed(..) => {}
    }
    Ok(outcome)
}

/// The fields a class lets a validation error name.
pub(crate) fn fields_of(c: &Class) -> &[String] {
    match c {
        Class::Bad(f) | Class::Unknown(f) => f,
        _ => &[],
    }
}

/// [`check_text`] plus what the generator knows: wrong types fail to parse
/// and nothing else does; an invalid value is refused naming its field; a
/// document of valid values is accepted with the initial fields it wrote.
pub fn check_doc(doc: &Doc, cfg: Config) -> Result<(), String> {
    let text = doc.render();
    let outcome = check_text(&text, cfg)?;
    let must_fail_parse = doc.classes().any(|c| *c == Class::Type);
    let bad: Vec<&Class> = doc.classes().filter(|c| matches!(c, Class::Bad(_))).collect();
    let allowed: Vec<&String> = doc.classes().flat_map(fields_of).collect();
    match outcome {
        Outcome::ParseError(e) if !must_fail_parse => Err(format!("a document without a wrong type failed to parse: {e}")),
        Outcome::ParseError(_) => Ok(()),
        Outcome::Parsed(..) if must_fail_parse => Err("a document with a wrong type, unknown key or duplicate key parsed".into()),
        Outcome::Parsed(_, None) => Ok(()),
        Outcome::Parsed(_, Some(Ok(scene))) => {
            if !bad.is_empty() {
                return Err(format!("accepted a document with invalid values: {bad:?}"));
            }
            if allowed.is_empty() {
                check_known_fields(doc, &scene)?;
                check_runs(&scene)?;
            }
            Ok(())
        }
        Outcome::Parsed(_, Some(Err(SceneError::Field { field, message }))) => {
            if !allowed.iter().any(|f| **f == field) {
                return Err(format!("refused naming {field:?} ({message}); the generator expected one of {allowed:?} (none if the document is valid)"));
            }
            Ok(())
        }
        Outcome::Parsed(_, Some(Err(e))) => Err(format!("unexpected error {e:?}")),
    }
}

/// An accepted oscillator's scene runs: its simulation is instantiated and
/// steps to its horizon (at most 64 steps; the generator writes at most
/// 39), without an error or a panic.
pub(crate) fn check_runs(scene: &Scene) -> Result<(), String> {
    let Scene::Oscillator { dt, t_end, .. } = scene else {
        return Ok(());
    };
    let steps = (t_end / dt).round().min(64.0) as usize;
    let run = catch_unwind(AssertUnwindSafe(|| -> Result<(), String> {
        let mut sim = scene.instantiate(None).map_err(|e| format!("an accepted oscillator scene does not instantiate: {e}"))?;
        for k in 0..steps {
            sim.stepper.step().map_err(|e| format!("an accepted oscillator scene does not run: step {} of {steps}: {e}", k + 1))?;
        }
        Ok(())
    }));
    run.unwrap_or_else(|_| Err("an accepted oscillator scene panics in its run".into()))
}

/// The initial displacement and velocity of an accepted custom bar against
/// the generator's functions at the nodes x_i = L i / m.
pub(crate) fn check_known_fields(doc: &Doc, scene: &Scene) -> Result<(), String> {
    let Scene::Bar(run) = scene else {
        return Ok(());
    };
    let p = &run.problem;
    let m = p.bar.elements as f64;
    for (which, f) in &doc.known_fields {
        let values = if *which == "u" { &p.initial.u } else { &p.initial.v };
        for (i, got) in values.iter().enumerate() {
            let x = doc.length * i as f64 / m;
            let want = f(x);
            if (got - want).abs() > 1e-12 * (1.0 + want.abs()) {
                return Err(format!("initial {which}({x}) = {got}, the expression's value is {want}"));
            }
        }
    }
    Ok(())
}
