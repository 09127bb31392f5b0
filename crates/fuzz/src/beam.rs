//! The `[beam]` table: its picks and the table assembled from them.

use crate::config::Config;
use crate::doc::{bad, toml_f64, unknown, val, Class, Value};
use crate::pools::oneof;
use crate::pools::{maybe, pick, pool, pow2, type_bad, HUGE_COUNTS, NON_FINITE, NOT_A_BOOL, NOT_A_COUNT, NOT_A_NUMBER, NOT_A_STRING};
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;

// ------------------------------------------------------------------ beam --

pub(crate) const FIGURES: [&str; 7] = ["fig2", "fig3", "fig4", "fig5", "fig6", "fig7", "fig8"];

/// The paper's scenes whose contact is the penalty (the others: projection).
pub(crate) const PENALTY_FIGURES: [&str; 3] = ["fig5", "fig6", "fig7"];

#[derive(Clone, Debug)]
pub(crate) struct BeamPicks {
    pub(crate) scene: Option<Value>,
    pub(crate) elements: Option<Value>,
    pub(crate) dt: Option<(Value, Option<i32>)>,
    pub(crate) t_end: Option<(Value, Option<u32>)>,
    pub(crate) contact: Option<Value>,
    pub(crate) beta: Option<Value>,
    pub(crate) stiffness: Option<Value>,
    pub(crate) stops: Option<Value>,
    pub(crate) support: Option<Value>,
    pub(crate) force: Option<Value>,
    pub(crate) extra: Vec<(String, Value)>,
}

pub(crate) fn pair_pool(good: &[&str], bad_: &[&str], path: &'static str, cfg: Config, extreme: &[&str], tw: u32) -> BoxedStrategy<Value> {
    let extra_items = if cfg.exact_arrays { Class::Type } else { unknown(&[path]) };
    oneof![
        5 => pool(good, Class::Good),
        3 => pool(bad_, bad(&[path])),
        1 => pool(extreme, unknown(&[path])),
        1 => pool(&["[-1.0, 1.0, 2.0]", "[0.0, 1.0, 0.0, 0.0]"], extra_items),
        2 * tw => type_bad(&["[1.0]", "[]", "\"a\"", "[[1.0, 2.0]]", "1.0", "[\"a\", 1]", "[1.0, \"b\"]", "{ g1 = 0 }", "[true, 1.0]"]),
    ]
    .boxed()
}

pub(crate) fn beam_picks(cfg: Config, tw: u32) -> BoxedStrategy<BeamPicks> {
    let scene = oneof![
        6 => pick(&FIGURES).prop_map(|f| val(format!("\"{f}\""), Class::Good)),
        1 => pool(&["\"fig9\"", "\"\"", "\"Fig2\"", "\"custom\"", "\"fig1\""], bad(&["beam.scene"])),
        tw => type_bad(&NOT_A_STRING),
    ];
    // Sizes no machine holds: only with cfg.huge_sizes (today validation accepts them).
    let huge = if cfg.huge_sizes { pool(&HUGE_COUNTS, bad(&["beam.elements"])) } else { pool(&["19"], Class::Good) };
    let elements = oneof![
        6 => (1u32..=64).prop_map(|m| val(m.to_string(), Class::Good)),
        2 => pool(&["0", "+0", "0x0", "0o0"], bad(&["beam.elements"])),
        1 => huge,
        2 * tw => type_bad(&NOT_A_COUNT),
    ];
    let dt = oneof![
        6 => pow2(10, 20).prop_map(|k| (val(toml_f64(2f64.powi(-k)), Class::Good), Some(k))),
        2 => pool(&["0.0", "-1e-5", "-0.0"], bad(&["beam.dt"])).prop_map(|v| (v, None)),
        2 => pool(&NON_FINITE, bad(&["beam.dt"])).prop_map(|v| (v, None)),
        1 => pool(&["1e-300", "5e-324", "1e-12"], bad(&["beam.dt"])).prop_map(|v| (v, None)),
        1 => pool(&["1e300", "9223372036854775807", "3.0"], unknown(&["beam.dt", "beam.t_end"])).prop_map(|v| (v, None)),
        tw => type_bad(&NOT_A_NUMBER).prop_map(|v| (v, None)),
    ];
    let t_end = oneof![
        6 => (1u32..100_000).prop_map(|n| (val("", Class::Good), Some(n))),
        2 => pool(&["0.0", "-2.0"], bad(&["beam.t_end"])).prop_map(|v| (v, None)),
        2 => pool(&NON_FINITE, bad(&["beam.t_end"])).prop_map(|v| (v, None)),
        1 => pool(&["1e300", "1e6", "1.7976931348623157e308"], bad(&["beam.dt"])).prop_map(|v| (v, None)),
        tw => type_bad(&NOT_A_NUMBER).prop_map(|v| (v, None)),
    ];
    let contact = oneof![
        6 => pool(&["\"projection\"", "\"penalty\""], Class::Good),
        1 => pool(&["\"glue\"", "\"\"", "\"Penalty\""], bad(&["beam.contact"])),
        tw => type_bad(&NOT_A_STRING),
    ];
    let beta = oneof![
        5 => pool(&["0.25", "0.3", "0.5", "0.4999", "0.375"], Class::Good),
        // β < 1/4: conditionally stable (the runner checks dt; validation may come to).
        2 => pool(&["0.0", "0.1", "0.2", "0.2499", "-0.0", "0"], unknown(&["beam.beta", "beam.dt"])),
        3 => pool(&["-0.1", "0.51", "1.0", "1e300", "-1e-300", "nan", "inf", "-inf"], bad(&["beam.beta"])),
        tw => type_bad(&NOT_A_NUMBER),
    ];
    let stiffness = oneof![
        5 => pool(&["1e8", "1e3", "1e10", "1", "100000000"], Class::Good),
        3 => pool(&["0.0", "-1e8", "-0.0", "nan", "inf", "-inf"], bad(&["beam.penalty_stiffness"])),
        1 => pool(&["1e30", "1e300", "5e-324"], unknown(&["beam.penalty_stiffness"])),
        tw => type_bad(&NOT_A_NUMBER),
    ];
    let stops = pair_pool(
        &["[-0.1, 0.1]", "[0.0, 1.0]", "[-1.0, 0.0]", "[-1, 1]", "[ -0.05 , 0.2 ]"],
        &["[0.1, 0.2]", "[-0.2, -0.1]", "[0.1, -0.1]", "[0.0, 0.0]", "[nan, 1.0]", "[-inf, 1.0]", "[-1.0, inf]", "[-1.0, nan]"],
        "beam.stops",
        cfg,
        &["[-1e300, 1e300]", "[-5e-324, 5e-324]"],
        tw,
    );
    let support = pair_pool(
        &["[0.0, 1.0]", "[0.001, 62.8]", "[-0.5, 1e3]", "[0, 1]"],
        &["[nan, 1.0]", "[inf, 1.0]", "[1.0, 0.0]", "[1.0, -1.0]", "[1.0, inf]", "[1.0, nan]", "[-inf, 1.0]"],
        "beam.support",
        cfg,
        &["[1e300, 1.0]", "[0.001, 1e300]", "[0.001, 5e-324]"],
        tw,
    );
    let force = oneof![3 => pool(&["true", "false"], Class::Good), tw => type_bad(&NOT_A_BOOL)];
    let extra = prop::collection::vec(
        prop_oneof![
            pool(&["1", "\"x\""], Class::Type).prop_map(|v| ("bogus".to_string(), v)),
            pool(&["0.5"], Class::Type).prop_map(|v| ("Beta".to_string(), v)),
            pool(&["1e8"], Class::Type).prop_map(|v| ("stiffness".to_string(), v)),
            pool(&["10"], Class::Type).prop_map(|v| ("snapshots_every".to_string(), v)),
        ],
        0..1 + tw as usize,
    );
    (
        (maybe(0.6, scene.boxed()), maybe(0.5, elements.boxed()), maybe(0.5, dt.boxed()), maybe(0.5, t_end.boxed()), maybe(0.4, contact.boxed()), maybe(0.3, beta.boxed())),
        (maybe(0.3, stiffness.boxed()), maybe(0.4, stops), maybe(0.3, support), maybe(0.2, force.boxed()), extra),
    )
        .prop_map(|((scene, elements, dt, t_end, contact, beta), (stiffness, stops, support, force, extra))| BeamPicks {
            scene,
            elements,
            dt,
            t_end,
            contact,
            beta,
            stiffness,
            stops,
            support,
            force,
            extra,
        })
        .boxed()
}

pub(crate) fn assemble_beam(p: BeamPicks, cfg: Config) -> Vec<(String, Value)> {
    let mut entries = Vec::new();
    let figure = p.scene.as_ref().filter(|v| v.class == Class::Good).map(|v| v.toml.trim_matches('"').to_string());
    let contact_given = p.contact.as_ref().filter(|v| v.class == Class::Good).map(|v| v.toml.trim_matches('"').to_string());
    let penalty = match (&p.contact, &contact_given) {
        (_, Some(c)) => Some(c == "penalty"),
        (None, None) => Some(figure.as_deref().is_some_and(|f| PENALTY_FIGURES.contains(&f))),
        (Some(_), None) => None, // invalid contact: refused anyway
    };
    if let Some(s) = p.scene.clone() {
        entries.push(("scene".into(), s));
    }
    if let Some(e) = p.elements.clone() {
        entries.push(("elements".into(), e));
    }
    let dt_exp = p.dt.as_ref().and_then(|(_, k)| *k);
    if let Some((v, _)) = p.dt.clone() {
        entries.push(("dt".into(), v));
    }
    if let Some((v, n)) = p.t_end.clone() {
        let v = match n {
            // A whole number of steps: of dt = 2^-k when given, else T in {1/2, 1, 2}
            // (multiples of every figure's dt and of the custom 1e-5).
            Some(n) => match (dt_exp, &p.dt) {
                (Some(k), _) => val(toml_f64(f64::from(1 + n % 100_000) * 2f64.powi(-k)), Class::Good),
                (None, None) => val(["0.5", "1.0", "2.0"][n as usize % 3], Class::Good),
                (None, Some(_)) => val("1.0", Class::Good),
            },
            // Too many steps only if dt is valid or the figure's (an extreme dt may be as long).
            None if v.class == bad(&["beam.dt"]) && p.dt.as_ref().is_some_and(|(d, _)| d.class != Class::Good) => val(v.toml, unknown(&["beam.dt", "beam.t_end"])),
            None => v,
        };
        entries.push(("t_end".into(), v));
    }
    if let Some(c) = p.contact.clone() {
        entries.push(("contact".into(), c));
    }
    // A key the effective contact does not use (§2: every key acts or is refused).
    let ignored = |key: &str| {
        if cfg.refuse_ignored_keys {
            Class::Bad(vec![key.to_string()])
        } else {
            Class::Unknown(vec![key.to_string()])
        }
    };
    if let Some(mut b) = p.beta.clone() {
        if b.class != Class::Type && penalty == Some(true) {
            b.class = ignored("beam.beta");
        }
        entries.push(("beta".into(), b));
    }
    if let Some(mut s) = p.stiffness.clone() {
        if s.class != Class::Type && penalty == Some(false) {
            s.class = ignored("beam.penalty_stiffness");
        }
        entries.push(("penalty_stiffness".into(), s));
    }
    for (k, v) in [("stops", p.stops.clone()), ("support", p.support.clone()), ("force", p.force.clone())] {
        if let Some(v) = v {
            entries.push((k.into(), v));
        }
    }
    entries.extend(p.extra);
    entries
}
