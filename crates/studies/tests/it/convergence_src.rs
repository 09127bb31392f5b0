//! The tests of `signorini_studies::convergence` that were unit tests in src/convergence.rs (the
//! library is not compiled a second time as a test harness).

use signorini_fem::BarMass;
use signorini_norms::NormKind;
use signorini_reduce::Keep;
use signorini_studies::convergence::*;
use signorini_studies::{parse_schemes, StudyError};
use std::path::PathBuf;

#[test]
fn parse_helpers_name_their_option() {
    assert!(matches!(parse_norms("l2"), Err(StudyError::Config { field, .. }) if field == "norms"));
    assert!(matches!(parse_benchmark("nope"), Err(StudyError::Config { field, .. }) if field == "benchmark"));
    assert_eq!(parse_norms("getfem").ok(), Some(NormKind::GetfemInterpolated));
}

/// `--reduce`: parsed, and refused naming the option at fault before anything runs.
#[test]
fn reduce_is_parsed_and_checked_naming_the_option() {
    assert_eq!(parse_reduce("modes=8").ok(), Some(Keep::Modes(8)));
    assert_eq!(parse_reduce("cutoff_hz=2.5").ok(), Some(Keep::CutoffHz(2.5)));
    for bad in ["modes=0", "modes=x", "cutoff_hz=-1", "cutoff_hz=nan", "modes", "r=3"] {
        assert!(matches!(parse_reduce(bad), Err(StudyError::Config { field, .. }) if field == "reduce"), "{bad}");
    }
    let field_of = |cfg: Config| match cfg.validate() {
        Err(StudyError::Config { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    let base = Config { schemes: parse_schemes(&["newmark-cn".to_string()]).unwrap(), masses: vec![BarMass::Mod], levels: vec![10, 20], reduce: Some(Keep::Modes(4)), ..Config::default() };
    assert!(base.validate().is_ok());
    assert_eq!(field_of(Config { masses: vec![BarMass::Std], ..base.clone() }), "masses");
    assert_eq!(field_of(Config { schemes: parse_schemes(&["moreau-jean".to_string()]).unwrap(), ..base.clone() }), "schemes");
    // m = 10: 9 interior modes.
    assert_eq!(field_of(Config { reduce: Some(Keep::Modes(10)), ..base.clone() }), "reduce");
    assert_eq!(field_of(Config { reduce: Some(Keep::CutoffHz(0.01)), ..base }), "reduce");
}

fn field_of(cfg: &Config) -> Option<String> {
    match cfg.validate() {
        Err(StudyError::Config { field, .. }) => Some(field.to_string()),
        _ => None,
    }
}

#[test]
fn a_bad_degree_names_its_option() {
    for k in [0, 4] {
        assert_eq!(field_of(&Config { degree: k, ..Config::default() }).as_deref(), Some("degree"), "degree {k}");
    }
    assert_eq!(field_of(&Config { degree: 2, norms: NormKind::GetfemInterpolated, ..Config::default() }).as_deref(), Some("degree"));
    assert_eq!(field_of(&Config { degree: 3, masses: vec![BarMass::Std, BarMass::Mod2], ..Config::default() }).as_deref(), Some("masses"));
    assert_eq!(field_of(&Config { degree: 3, ..Config::default() }), None);
    // Degree 1 keeps the P1 folder; others get their own.
    assert_eq!(Config::default().resolve().unwrap().1, PathBuf::from("out/convergence/bar-dirichlet"));
    assert_eq!(Config { degree: 2, ..Config::default() }.resolve().unwrap().1, PathBuf::from("out/convergence/bar-dirichlet-p2"));
}
