//! The `[oscillator]` scene: its keys, its `[forcing]`, and the document
//! assembled from them ([`oscillator_documents`]), each value classified
//! against what the rest of the document makes certain (the stops against
//! the start, the restitution against the scheme's own e).

use crate::doc::{bad, toml_f64, val, Class, Doc, Form, Table, Value};
use crate::pools::{form, maybe, oneof, pick, pool, type_bad, NON_FINITE, NOT_A_NUMBER, NOT_A_STRING};
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;

/// A number as written, with its value when it is finite (`None`: a value
/// of the wrong type, or one the reader refuses whatever the rest says).
type Num = (Value, Option<f64>);

/// How the document gives the stops.
#[derive(Clone, Debug)]
enum Stops {
    /// `stop = g`.
    One(Num),
    /// `stops = [lo, hi]` (the bounds when both are finite and lo < hi).
    Two(Value, Option<(f64, f64)>),
    /// Both keys (refused: one acts).
    Both(Num, Value),
    /// Neither (refused: the stop is required).
    Neither,
}

/// What a scheme does with the restitution (docs/vibro-impact.md, "Which
/// restitution acts").
#[derive(Clone, Copy, Debug, PartialEq)]
enum Law {
    /// Absent, or a family name alone: takes the restitution.
    Takes,
    /// States its e: the restitution may only repeat it.
    States(f64),
    /// No impact law: the restitution must be absent or 0.
    None,
    /// Not a scheme of the oscillator (refused, naming the scheme).
    Bad,
}

#[derive(Clone, Debug)]
struct Picks {
    mass: Value,
    stiffness: Value,
    damping: Option<Value>,
    stops: Stops,
    restitution: Option<Num>,
    x0: Option<Num>,
    v0: Option<Value>,
    scheme: Option<(Value, Law)>,
    /// `dt` as written, and its exponent when it is 2^-k.
    dt: (Value, Option<i32>),
    /// `t_end`: a whole number of steps (`None`), or a value of its own.
    t_end: (u32, Option<Value>),
    forcing: Option<(Option<Value>, Option<Value>, Form)>,
    /// A table the oscillator refuses (`[support]`, `[load]`), by name.
    other: Option<&'static str>,
    form: Form,
}

fn num(good: &'static [(&'static str, f64)], bad_: &'static [&'static str], field: &'static str, tw: u32) -> BoxedStrategy<Num> {
    oneof![
        5 => pick(good).prop_map(|(t, x)| (val(t, Class::Good), Some(x))),
        2 => pick(bad_).prop_map(move |t| (val(t, bad(&[field])), None)),
        tw => type_bad(&NOT_A_NUMBER).prop_map(|v| (v, None)),
    ]
}

fn plain(good: &'static [(&'static str, f64)], bad_: &'static [&'static str], field: &'static str, tw: u32) -> BoxedStrategy<Value> {
    num(good, bad_, field, tw).prop_map(|(v, _)| v).boxed()
}

const POSITIVE: [(&str, f64); 4] = [("1.0", 1.0), ("2.5", 2.5), ("0.5", 0.5), ("1", 1.0)];
const NOT_POSITIVE: [&str; 9] = ["0.0", "-1.0", "-0.0", "nan", "+nan", "-nan", "inf", "+inf", "-inf"];
const NOT_NONNEGATIVE: [&str; 5] = ["-1.0", "-1e-300", "nan", "inf", "-inf"];

/// Documents with an `[oscillator]` table; `tw` weighs the wrong types.
pub(crate) fn oscillator_documents(tw: u32) -> BoxedStrategy<Doc> {
    let stop = num(&[("0.2", 0.2), ("1.0", 1.0), ("0.5", 0.5), ("-0.5", -0.5), ("0", 0.0)], &NON_FINITE, "oscillator.stop", tw);
    let two = oneof![
        5 => pick(&[("[-0.5, 0.8]", (-0.5, 0.8)), ("[-1.0, 1.0]", (-1.0, 1.0)), ("[-0.2, 0.2]", (-0.2, 0.2)), ("[0.5, 1.0]", (0.5, 1.0)), ("[-1, 0]", (-1.0, 0.0))])
            .prop_map(|(t, b)| (val(t, Class::Good), Some(b))),
        // lo >= hi, and bounds that are not finite.
        3 => pool(&["[0.5, 0.5]", "[0.8, -0.5]", "[0.0, -0.0]", "[nan, 1.0]", "[-inf, 1.0]", "[-1.0, inf]", "[-1.0, nan]", "[inf, -inf]"], bad(&["oscillator.stops"])).prop_map(|v| (v, None)),
        2 * tw => type_bad(&["[1.0]", "[]", "[-1.0, 0.0, 1.0]", "1.0", "\"[-1, 1]\"", "[\"a\", 1.0]"]).prop_map(|v| (v, None)),
    ];
    let stops = prop_oneof![
        4 => stop.clone().prop_map(Stops::One),
        4 => two.clone().prop_map(|(v, b)| Stops::Two(v, b)),
        1 => (stop, two).prop_map(|(s, (t, _))| Stops::Both(s, t)),
        1 => Just(Stops::Neither),
    ];
    let restitution = num(&[("0.0", 0.0), ("0.5", 0.5), ("0.8", 0.8), ("1.0", 1.0), ("0", 0.0)], &["-0.1", "1.5", "1.0000001", "nan", "inf", "-inf"], "oscillator.restitution", tw);
    // Inside every good stop pair but [0.5, 1.0] and under every one stop but -0.5 and 0.
    let x0 = num(&[("0.1", 0.1), ("0.0", 0.0), ("-0.15", -0.15), ("0.7", 0.7), ("5.0", 5.0), ("-5.0", -5.0)], &NON_FINITE, "oscillator.initial_displacement", tw);
    let scheme = oneof![
        2 => pick(&["\"event-driven\"", "\"moreau-jean\""]).prop_map(|t| (val(t, Class::Good), Law::Takes)),
        2 => pick(&[("\"event-driven(0.5)\"", 0.5), ("\"ps(0.8,0.25)\"", 0.8), ("\"ps-e0.5\"", 0.5)]).prop_map(|(t, e)| (val(t, Class::Good), Law::States(e))),
        1 => pick(&["\"newmark-cn\""]).prop_map(|t| (val(t, Class::Good), Law::None)),
        1 => pool(&["\"nope\"", "\"\"", "\"event-driven(2)\"", "\"ps(0.5\""], bad(&["oscillator.scheme"])).prop_map(|v| (v, Law::Bad)),
        tw => type_bad(&NOT_A_STRING).prop_map(|v| (v, Law::Bad)),
    ];
    let dt = oneof![
        6 => (4i32..=8).prop_map(|k| (val(toml_f64(2f64.powi(-k)), Class::Good), Some(k))),
        2 => pool(&NOT_POSITIVE, bad(&["oscillator.dt"])).prop_map(|v| (v, None)),
        tw => type_bad(&NOT_A_NUMBER).prop_map(|v| (v, None)),
    ];
    let t_end = (
        1u32..40,
        maybe(
            0.25,
            oneof![
                3 => pool(&NOT_POSITIVE, bad(&["oscillator.t_end"])),
                // Not a whole number of steps of any dt = 2^-k.
                1 => pool(&["0.3", "1e-3"], bad(&["oscillator.t_end"])),
                tw => type_bad(&NOT_A_NUMBER),
            ],
        ),
    );
    let amplitude = oneof![
        5 => pool(&["1.0", "0.0", "-0.5", "2"], Class::Good),
        2 => pool(&NON_FINITE, bad(&["forcing.amplitude"])),
        tw => type_bad(&NOT_A_NUMBER),
    ];
    let omega = oneof![
        5 => pool(&["2.0", "0.5", "1", "2.2"], Class::Good),
        2 => pool(&NOT_POSITIVE, bad(&["forcing.omega"])),
        tw => type_bad(&NOT_A_NUMBER),
    ];
    let forcing = (maybe(0.9, amplitude), maybe(0.9, omega), prop_oneof![Just(Form::Header), Just(Form::Inline), Just(Form::Dotted)]);
    (
        (
            plain(&POSITIVE, &NOT_POSITIVE, "oscillator.mass", tw),
            plain(&[("1.0", 1.0), ("0.0", 0.0), ("4", 4.0)], &NOT_NONNEGATIVE, "oscillator.stiffness", tw),
            maybe(0.5, plain(&[("0.0", 0.0), ("0.05", 0.05), ("1.0", 1.0)], &NOT_NONNEGATIVE, "oscillator.damping_ratio", tw)),
            stops,
            maybe(0.6, restitution),
            maybe(0.6, x0),
        ),
        (
            maybe(0.4, plain(&[("0.0", 0.0), ("1.0", 1.0), ("-2.0", -2.0)], &NON_FINITE, "oscillator.initial_velocity", tw)),
            maybe(0.6, scheme),
            dt,
            t_end,
            maybe(0.7, forcing.boxed()),
            maybe(0.05, pick(&["support", "load"])),
            form(),
        ),
    )
        .prop_map(|((mass, stiffness, damping, stops, restitution, x0), (v0, scheme, dt, t_end, forcing, other, form))| {
            assemble(Picks { mass, stiffness, damping, stops, restitution, x0, v0, scheme, dt, t_end, forcing, other, form })
        })
        .boxed()
}

fn assemble(p: Picks) -> Doc {
    let mut entries: Vec<(String, Value)> = vec![("mass".into(), p.mass), ("stiffness".into(), p.stiffness)];
    let mut structure = Vec::new();
    if let Some(d) = p.damping {
        entries.push(("damping_ratio".into(), d));
    }
    // The bounds `(lo, hi)` when the stops given are valid.
    let bounds = match p.stops {
        Stops::One((v, g)) => {
            entries.push(("stop".into(), v));
            g.map(|g| (f64::NEG_INFINITY, g, "oscillator.stop"))
        }
        Stops::Two(v, b) => {
            entries.push(("stops".into(), v));
            b.map(|(lo, hi)| (lo, hi, "oscillator.stops"))
        }
        Stops::Both((s, _), t) => {
            entries.push(("stop".into(), s));
            entries.push(("stops".into(), t));
            structure.push(bad(&["oscillator.stops"]));
            None
        }
        Stops::Neither => {
            structure.push(bad(&["oscillator.stop"]));
            None
        }
    };
    // The start against the stops: refused naming the start where it is
    // given, the stops where it is the default 0.
    let start = p.x0.as_ref().map_or(Some(0.0), |(_, x)| *x);
    if let (Some((lo, hi, key)), Some(x)) = (bounds, start) {
        if !(lo <= x && x <= hi) {
            structure.push(bad(&[if p.x0.is_some() { "oscillator.initial_displacement" } else { key }]));
        }
    }
    if let Some((v, _)) = p.x0 {
        entries.push(("initial_displacement".into(), v));
    }
    if let Some(v) = p.v0 {
        entries.push(("initial_velocity".into(), v));
    }
    // The restitution against the scheme's law.
    let law = p.scheme.as_ref().map_or(Law::Takes, |(_, l)| *l);
    if let Some((v, r)) = p.restitution {
        let conflict = match (law, r) {
            (Law::States(e), Some(r)) => r != e,
            (Law::None, Some(r)) => r != 0.0,
            _ => false,
        };
        if conflict {
            structure.push(bad(&["oscillator.restitution"]));
        }
        entries.push(("restitution".into(), v));
    }
    if let Some((v, _)) = p.scheme {
        entries.push(("scheme".into(), v));
    }
    let (dt, k) = p.dt;
    entries.push(("dt".into(), dt));
    let t_end = match (p.t_end, k) {
        ((_, Some(v)), _) => v,
        ((n, None), Some(k)) => val(toml_f64(f64::from(n) * 2f64.powi(-k)), Class::Good),
        // dt refused: any horizon.
        ((_, None), None) => val("1.0", Class::Good),
    };
    entries.push(("t_end".into(), t_end));
    let mut tables = vec![Table { name: "oscillator".into(), entries, form: p.form }];
    if let Some((amplitude, omega, form)) = p.forcing {
        let mut f = Vec::new();
        match amplitude {
            Some(a) => f.push(("amplitude".to_string(), a)),
            None => structure.push(bad(&["forcing.amplitude"])),
        }
        match omega {
            Some(w) => f.push(("omega".to_string(), w)),
            None => structure.push(bad(&["forcing.omega"])),
        }
        tables.push(Table { name: "forcing".into(), entries: f, form });
    }
    if let Some(name) = p.other {
        structure.push(bad(&[name]));
        tables.push(Table { name: name.into(), entries: vec![("amplitude".into(), val("1.0", Class::Good)), ("omega".into(), val("2.0", Class::Good))], form: Form::Header });
    }
    Doc { tables, structure, known_fields: Vec::new(), length: 1.0, crlf: false }
}
