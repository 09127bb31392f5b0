//! The studies' one reader of options (`signorini_studies::options`), which
//! `cargo xtask` and Python both use: a flag's text or a keyword's value
//! into the study's `Config`, and errors naming the field in each front
//! end's spelling.

use signorini_studies::options::{self, Input, Spelling, Study, Value};
use signorini_studies::{beam, beam_statistics, convergence, courant1, long_horizon, lyapunov, obstacles, oscillator, stress, weighted, work_precision, StudyError};

fn flags(pairs: &[(&str, &str)]) -> Vec<(String, Input)> {
    pairs.iter().map(|(k, v)| (k.to_string(), Input::text(v))).collect()
}

/// The error's message in both spellings, and its field.
#[track_caller]
fn refused<C: Study + std::fmt::Debug>(given: &[(String, Input)]) -> (String, String, String) {
    match options::read_valid::<C>(given) {
        Err(e @ StudyError::Config { .. }) => {
            let StudyError::Config { field, .. } = &e else { unreachable!() };
            (field.clone(), e.render(Spelling::Flag), e.render(Spelling::Neutral))
        }
        other => panic!("expected a Config error, got {other:?}"),
    }
}

#[test]
fn flags_are_read_as_the_fields_types() {
    let c: convergence::Config = options::read(&flags(&[("levels", "10, 20,40"), ("t_end", "2.5"), ("schemes", "newmark(0.25,0.5),ps-e0"), ("clean", "true"), ("reduce", "modes=3")])).unwrap();
    assert_eq!(c.levels, vec![10, 20, 40]);
    assert_eq!(c.t_end, Some(2.5));
    assert_eq!(c.schemes.len(), 2, "{:?}", c.schemes);
    assert!(c.clean);
    assert_eq!(c.reduce, Some(signorini_reduce::Keep::Modes(3)));
    // The fields not given keep their defaults.
    assert_eq!(c.masses, convergence::Config::default().masses);
    assert_eq!(c.ratio, None);
    // `none` and '' are empty lists (lyapunov --omegas none, work-precision --degrees '').
    let l: lyapunov::Config = options::read(&flags(&[("omegas", "none"), ("scenes", "")])).unwrap();
    assert!(l.omegas.is_empty() && l.scenes.is_empty());
    // Python's values: numbers, a str as a one-word list, a whole float as an int.
    let py = |v: Value| Input { value: v, words: String::new() };
    let b: beam_statistics::Config = options::read(&[
        ("scenes".into(), py(Value::Str("beam-obstacles".into()))),
        ("batches".into(), py(Value::Float(30.0))),
        ("dts".into(), py(Value::List(vec![py(Value::Int(1)), py(Value::Float(2e-5))]))),
    ])
    .unwrap();
    assert_eq!((b.scenes, b.batches, b.dts), (vec!["beam-obstacles".to_string()], 30, vec![1.0, 2e-5]));
}

#[test]
fn errors_name_the_field_in_each_front_ends_spelling() {
    let (field, flag, neutral) = refused::<weighted::Config>(&flags(&[("t_end", "3")]));
    assert_eq!(field, "t_end");
    assert!(flag.starts_with("--t-end 3: allowed finite and >= 4.5"), "{flag}");
    assert!(neutral.starts_with("t_end 3: allowed finite and >= 4.5"), "{neutral}");
    // A field named inside the text is spelled too.
    let (_, flag, neutral) = refused::<obstacles::Config>(&flags(&[("js", "5,7")]));
    assert!(flag.contains("--js [5, 7] / --j 20") && flag.contains("(and --j in [2, 2000])"), "{flag}");
    assert!(neutral.contains("js [5, 7] / j 20") && !neutral.contains("--"), "{neutral}");
    // A word where a number is wanted: the range the study states for it.
    let (field, flag, neutral) = refused::<beam_statistics::Config>(&flags(&[("batches", "2.5")]));
    assert_eq!(field, "batches");
    assert_eq!(flag, "--batches: \"2.5\" is not allowed: an integer in [10, 1000] (fewer batches give no usable interval)");
    assert_eq!(neutral, "batches: \"2.5\" is not allowed: an integer in [10, 1000] (fewer batches give no usable interval)");
    // A field the study does not have.
    let (field, flag, _) = refused::<stress::Config>(&flags(&[("stesp", "10")]));
    assert_eq!(field, "stesp");
    assert!(flag.starts_with("--stesp: not an argument of the stress study (allowed: --steps, --elements, --seed, --out, --schemes)"), "{flag}");
    // A name its parser refuses, for a field read through it (long_horizon's two lists of runs).
    let (field, flag, _) = refused::<long_horizon::Config>(&flags(&[("energy_runs", "ps-e0:heavy")]));
    assert_eq!(field, "energy_runs");
    assert!(flag.starts_with("--energy-runs \"ps-e0:heavy\""), "{flag}");
    let (field, _, neutral) = refused::<long_horizon::Config>(&flags(&[("energy", "false"), ("energy_m", "50")]));
    assert_eq!(field, "energy");
    assert!(neutral.starts_with("energy off: energy_runs, energy_all"), "{neutral}");
}

/// Every field's default, written as its text (what `cargo xtask <study>
/// --help` shows and the Python documentation states), reads back as that
/// default: the shown defaults are the defaults.
fn defaults_read_back<C: Study + std::fmt::Debug>() {
    let d = C::default();
    for f in C::FIELDS {
        let Some(text) = d.show(f.name) else { continue };
        let c: C = options::read(&flags(&[(f.name, &text)])).unwrap_or_else(|e| panic!("{} {}={text:?}: {e}", C::NAME, f.name));
        assert_eq!(format!("{c:?}"), format!("{d:?}"), "{} {}={text:?}", C::NAME, f.name);
    }
}

#[test]
fn every_shown_default_reads_back_as_the_default() {
    defaults_read_back::<convergence::Config>();
    defaults_read_back::<weighted::Config>();
    defaults_read_back::<beam::Config>();
    defaults_read_back::<obstacles::Config>();
    defaults_read_back::<oscillator::Config>();
    defaults_read_back::<courant1::Config>();
    defaults_read_back::<long_horizon::Config>();
    defaults_read_back::<lyapunov::Config>();
    defaults_read_back::<beam_statistics::Config>();
    defaults_read_back::<work_precision::Config>();
    defaults_read_back::<stress::Config>();
}
