//! The pools values are drawn from — valid, boundary, out-of-range and
//! wrong-type — for numbers, counts, expressions, schemes and masses, and
//! the strategy helpers they are built with.

use crate::config::Config;
use crate::doc::{bad, unknown, val, Class, Exact, FieldPick, Form, Value, Written};
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;
use signorini_schemes::SchemeSpec;

/// A weighted choice in which options of weight 0 are left out (so that the
/// wrong-type options can be switched off).
macro_rules! oneof {
    ($($w:expr => $s:expr),+ $(,)?) => {
        $crate::pools::union(vec![$(($w, $s.boxed())),+])
    };
}

pub(crate) use oneof;

pub(crate) fn union<T: std::fmt::Debug + 'static>(options: Vec<(u32, BoxedStrategy<T>)>) -> BoxedStrategy<T> {
    proptest::strategy::Union::new_weighted(options.into_iter().filter(|(w, _)| *w > 0).collect()).boxed()
}

pub(crate) fn pick<T: Clone + std::fmt::Debug + 'static>(items: &[T]) -> BoxedStrategy<T> {
    proptest::sample::select(items.to_vec()).boxed()
}

/// Values of one class from a fixed pool.
pub(crate) fn pool(toml: &[&str], class: Class) -> BoxedStrategy<Value> {
    pool_owned(toml.iter().map(|s| s.to_string()).collect(), class)
}

pub(crate) fn pool_owned(items: Vec<String>, class: Class) -> BoxedStrategy<Value> {
    proptest::sample::select(items).prop_map(move |t| val(t, class.clone())).boxed()
}

/// Expressions as TOML strings.
pub(crate) fn quoted(exprs: &[&str]) -> Vec<String> {
    exprs.iter().map(|e| format!("\"{e}\"")).collect()
}

pub(crate) const NON_FINITE: [&str; 6] = ["nan", "+nan", "-nan", "inf", "+inf", "-inf"];

/// Wrong types where a number is expected.
pub(crate) const NOT_A_NUMBER: [&str; 9] = ["\"1.0\"", "'2'", "true", "[1.0]", "[]", "{ a = 1 }", "1979-05-27", "07:32:00", "\"\""];

/// Not a usize: negative, fractional, float syntax, too large for 64 bits, other types.
pub(crate) const NOT_A_COUNT: [&str; 11] = ["-1", "-9223372036854775808", "1.5", "2.0", "1e3", "nan", "inf", "18446744073709551616", "\"10\"", "true", "[10]"];

/// Not a string.
pub(crate) const NOT_A_STRING: [&str; 5] = ["1", "1.5", "true", "[\"a\"]", "{ name = \"a\" }"];

/// Not a bool.
pub(crate) const NOT_A_BOOL: [&str; 5] = ["1", "0", "\"true\"", "\"yes\"", "[true]"];

/// Element counts no machine holds; validation must refuse them before allocating.
pub(crate) const HUGE_COUNTS: [&str; 5] = ["1000000000", "1099511627776", "9223372036854775807", "0x7fffffffffffffff", "18446744073709551615"];

pub(crate) fn type_bad(pool_: &[&str]) -> BoxedStrategy<Value> {
    pool(pool_, Class::Type)
}

/// An exponent e in `lo..=hi` (the value written is 2^e: exact in binary).
pub(crate) fn pow2(lo: i32, hi: i32) -> BoxedStrategy<i32> {
    (lo..=hi).boxed()
}

/// An expression in `x` that is valid on [0, 4], with its value in Rust.
/// Values at 0 are in [0, 1] (so that any gap <= 0 is below u0(0)).
pub(crate) fn good_expressions(float_expressions: bool) -> Vec<Written> {
    let mut v: Vec<Written> = vec![
        ("0.5 * (1 - x)", |x| 0.5 * (1.0 - x)),
        ("math::sin(pi * x)", |x| (std::f64::consts::PI * x).sin()),
        ("x^2", |x| x * x),
        ("1 - x / 2.0", |x| 1.0 - x / 2.0),
        ("0.1 + 0.0 * x", |_| 0.1),
        ("math::exp(-x) * math::cos(2 * pi * x)", |x| (-x).exp() * (2.0 * std::f64::consts::PI * x).cos()),
        ("  0.25  ", |_| 0.25),
        ("if(x < 0.5, 0.5, 0.25)", |x| if x < 0.5 { 0.5 } else { 0.25 }),
        ("math::abs(x - 0.5)", |x| (x - 0.5).abs()),
        ("min(x, 0.75)", |x| x.min(0.75)),
        ("math::sqrt(x)", |x| x.sqrt()),
        ("1", |_| 1.0),
    ];
    if float_expressions {
        v.extend([("1/2", (|_| 0.5) as Exact), ("3/4", |_| 0.75), ("2^-1", |_| 0.5), ("x + 1/2", |x| x + 0.5)]);
    }
    v
}

/// Integer-division expressions (§3): their values are checked only with
/// [`Config::float_expressions`]; positive at 0 so the gap check cannot fire.
pub(crate) const INTEGER_DIVISIONS: [&str; 4] = ["1/2", "3/4", "2^-1", "x + 1/2"];

/// Velocities may be negative: these check that `-1/2` is -0.5 (today 0).
pub(crate) fn good_velocity_expressions(float_expressions: bool) -> Vec<Written> {
    let mut v = good_expressions(float_expressions);
    v.push(("-0.5 - 0.2 * math::sin(pi * x / 2)", |x| -0.5 - 0.2 * (std::f64::consts::PI * x / 2.0).sin()));
    if float_expressions {
        v.extend([("-1/2", (|_| -0.5) as Exact), ("-x/2", |x| -x / 2.0)]);
    }
    v
}

/// Piecewise-linear tables valid on [0, 4], with their values in Rust.
pub(crate) fn good_tables() -> Vec<Written> {
    vec![
        ("[[0.0, 0.5]]", |_| 0.5),
        ("[[0.0, 0.0], [4.0, 1.0]]", |x| x / 4.0),
        ("[[-1.0, 0.5], [0.5, 0.5], [10.0, 0.0]]", |x| if x <= 0.5 { 0.5 } else { 0.5 - 0.5 * (x - 0.5) / 9.5 }),
        ("[[0, 1], [1, 0]]", |x| if x <= 1.0 { 1.0 - x } else { 0.0 }),
        ("[ [0.0, 0.1], [2.0, 0.3] ]", |x| if x <= 2.0 { 0.1 + 0.1 * x } else { 0.3 }),
    ]
}

/// Expressions that do not build, evaluate or stay finite at x = 0 (integer
/// literals are reals: "9223372036854775807 + 1" is a valid 9.2e18).
pub(crate) const BROKEN_EXPRESSIONS: [&str; 16] = ["", "(", ")", "x +", "(x", "x)", "math::sin(", "math::nosuch(x)", "y", "1 2", "\\\"text\\\"", "x = 3", "a = 3; a", "1 % 0", "math::sin()", "true"];

/// Expressions that evaluate at x = 0 but are not finite at some node.
pub(crate) const NON_FINITE_EXPRESSIONS: [&str; 6] = ["1.0/0", "math::ln(x)", "1 / x", "math::sqrt(x - 1000)", "math::pow(2, 100000)", "1e308 * 10"];

/// Tokens of random expressions.
pub(crate) const TOKENS: [&str; 44] = [
    "x",
    "x",
    "pi",
    "0",
    "1",
    "2",
    "0.5",
    "-1",
    "1e308",
    "1e-308",
    "9223372036854775807",
    "-",
    "+",
    "*",
    "/",
    "^",
    "%",
    "(",
    "(",
    ")",
    ")",
    ",",
    "math::sin",
    "math::ln",
    "math::sqrt",
    "math::pow",
    "math::abs",
    "math::floor",
    "min",
    "max",
    "if",
    "true",
    "==",
    "<",
    "&&",
    "!",
    "\\\"s\\\"",
    ";",
    "=",
    "y",
    "()",
    "math::exp",
    "floor",
    "2.5e3",
];

/// An initial field (`bar.initial_displacement` or `bar.initial_velocity`):
/// a number, an expression or a table. Good values carry their function.
pub(crate) fn initial_field(key: &'static str, cfg: Config, tw: u32) -> BoxedStrategy<FieldPick> {
    let path: &'static str = if key == "initial_displacement" { "bar.initial_displacement" } else { "bar.initial_velocity" };
    let on_node: Vec<&'static str> = if cfg.expression_errors { vec![path] } else { vec![path, "bar"] };
    let good_exprs = if key == "initial_displacement" { good_expressions(cfg.float_expressions) } else { good_velocity_expressions(cfg.float_expressions) };
    let good_expr = proptest::sample::select(good_exprs).prop_map(|(e, f)| (val(format!("\"{e}\""), Class::Good), Some(f)));
    let good_table = proptest::sample::select(good_tables()).prop_map(|(t, f)| (val(t, Class::Good), Some(f)));
    let numbers: Vec<Written> = vec![("0.5", |_| 0.5), ("0", |_| 0.0), ("1", |_| 1.0), ("0.0", |_| 0.0), ("1e-300", |_| 1e-300)];
    let good_number = proptest::sample::select(numbers).prop_map(|(t, f)| (val(t, Class::Good), Some(f)));
    let p = [path];
    let bad_number = pool(&NON_FINITE, bad(&p)).prop_map(|v| (v, None));
    let bad_table = pool(&["[]", "[[1.0, 0.0], [0.5, 0.0]]", "[[0.0, 0.0], [0.0, 1.0]]", "[[0.0, nan]]", "[[inf, 0.0]]", "[[0.0, 1.0], [1.0, -inf]]"], bad(&p)).prop_map(|v| (v, None));
    let broken = pool_owned(quoted(&BROKEN_EXPRESSIONS), bad(&p)).prop_map(|v| (v, None));
    let non_finite = pool_owned(quoted(&NON_FINITE_EXPRESSIONS), bad(&on_node)).prop_map(|v| (v, None));
    // Integer division: today "-1/2" is 0; checked for its value only when float_expressions.
    let int_div = if cfg.float_expressions { None } else { Some(pool_owned(quoted(&INTEGER_DIVISIONS), unknown(&[path, "bar"])).prop_map(|v| (v, None))) };
    let random_tokens =
        (prop::collection::vec(pick(&TOKENS), 1..12), any::<bool>()).prop_map(move |(toks, spaced)| (val(format!("\"{}\"", toks.join(if spaced { " " } else { "" })), unknown(&[path, "bar"])), None));
    // Deep nesting: the parser must not overflow the stack (the test thread has 2 MiB).
    let nested = (1usize..300, any::<bool>()).prop_map(move |(d, balanced)| {
        let close = if balanced { d } else { d - 1 };
        (val(format!("\"{}x{}\"", "(".repeat(d), ")".repeat(close)), if balanced { Class::Good } else { bad(&[path]) }), if balanced { Some((|x| x) as Exact) } else { None })
    });
    // Very deep or long expressions (only with cfg.deep_expressions: today they overflow the stack).
    let deep = (0usize..5, 10_000usize..200_000).prop_map(move |(kind, n)| {
        let e = match kind {
            0 => format!("{}x{}", "(".repeat(n), ")".repeat(n)),
            1 => format!("{}x", "-".repeat(n)),
            2 => vec!["x"; n].join("+"),
            3 => vec!["x"; n].join("^"),
            _ => format!("{}x{}", "math::abs(".repeat(n), ")".repeat(n)),
        };
        (val(format!("\"{e}\""), unknown(&[path, "bar"])), None)
    });
    let wrong_type = pool(&["true", "[1.0, 2.0]", "[[0.0, 1.0, 2.0]]", "[[0.0]]", "[[\"a\", 1.0]]", "{ x = 1 }", "1979-05-27", "[[0.0, 1.0], 2.0]"], Class::Type).prop_map(|v| (v, None));
    let mut options: Vec<(u32, BoxedStrategy<FieldPick>)> = vec![
        (4, good_expr.boxed()),
        (2, good_table.boxed()),
        (2, good_number.boxed()),
        (1, bad_number.boxed()),
        (1, bad_table.boxed()),
        (2, broken.boxed()),
        (1, non_finite.boxed()),
        (3, random_tokens.boxed()),
        (1, nested.boxed()),
        (tw, wrong_type.boxed()),
    ];
    if let Some(s) = int_div {
        options.push((1, s.boxed()));
    }
    if cfg.deep_expressions {
        options.push((1, deep.boxed()));
    }
    union(options)
}

/// A float key that must be finite and > 0 (`length`, `wave_speed`, …):
/// good values from `good`, the rest out of range or of the wrong type.
pub(crate) fn positive_key(path: &'static str, good: &'static [&'static str], extreme: Class, tw: u32) -> BoxedStrategy<Value> {
    let p = [path];
    oneof![
        5 => pool(good, Class::Good),
        2 => pool(&["0.0", "0", "-0.0", "-1.0", "-1e300", "-9223372036854775807"], bad(&p)),
        2 => pool(&NON_FINITE, bad(&p)),
        1 => pool(&["1e300", "5e-324", "1.7976931348623157e308", "9223372036854775807"], extreme),
        tw => type_bad(&NOT_A_NUMBER),
    ]
    .boxed()
}

/// A key present with a probability.
pub(crate) fn maybe<T: std::fmt::Debug + Clone + 'static>(p: f64, s: BoxedStrategy<T>) -> BoxedStrategy<Option<T>> {
    if p <= 0.0 {
        Just(None).boxed()
    } else if p >= 1.0 {
        s.prop_map(Some).boxed()
    } else {
        prop::option::weighted(p, s).boxed()
    }
}

// ------------------------------------------------------------------- bar --

/// Which nodes a scheme needs at the contact point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Node {
    Any,
    Massless,
    Massive,
    /// A diagonal mass with a massive node: `lumped` only.
    Lumped,
}

/// The contact node (and mass) a scheme needs, from the registry's capabilities.
pub(crate) fn node_of(spec: &SchemeSpec) -> Node {
    let c = spec.capabilities();
    match (c.diagonal_mass, c.node) {
        (true, _) => Node::Lumped,
        (_, signorini_schemes::Node::Massive) => Node::Massive,
        (_, signorini_schemes::Node::Massless) => Node::Massless,
        _ => Node::Any,
    }
}

/// Valid schemes, from the registry (`signorini_schemes::FAMILIES`): every
/// preset, and each family's call with each preset's values (written with
/// and without spaces) and, where trailing parameters have defaults,
/// without them; with the contact node they need and whether they are
/// conditionally stable (then a stricter validation may refuse a dt); and
/// each family without a preset, at values it accepts.
pub(crate) fn schemes() -> Vec<(String, Node, bool)> {
    let mut out = Vec::new();
    for (name, spec, _) in SchemeSpec::presets() {
        let conditional = spec.stability_rule().is_some();
        out.push((name.to_string(), node_of(&spec), conditional));
        let f = spec.family();
        if f.params.is_empty() {
            continue;
        }
        let args: Vec<String> = spec.args().iter().map(|a| a.to_string()).collect();
        out.push((format!("{}({})", f.name, args.join(", ")), node_of(&spec), conditional));
        let required = f.params.iter().filter(|p| p.default.is_none()).count();
        let defaults_hold = f.params.iter().zip(spec.args()).skip(required).all(|(p, a)| p.default == Some(*a));
        if required < f.params.len() && defaults_hold {
            out.push((format!("{}({})", f.name, args[..required].join(",")), node_of(&spec), conditional));
        }
    }
    // A family without presets (run by name only): its bare name, or its
    // call with the first values from {½, 0, 1} per parameter it accepts.
    for f in signorini_schemes::FAMILIES.iter().filter(|f| f.presets.is_empty()) {
        let k = f.params.len();
        let tuple = (0..3usize.pow(k as u32)).map(|code| (0..k).map(|i| [0.5, 0.0, 1.0][code / 3usize.pow(i as u32) % 3]).collect::<Vec<f64>>()).find(|a| f.with(a).validate().is_ok());
        if let Some(a) = tuple {
            let spec = f.with(&a);
            let text = if k == 0 { f.name.to_string() } else { format!("{}({})", f.name, a.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(",")) };
            out.push((text, node_of(&spec), spec.stability_rule().is_some()));
        }
    }
    out
}

/// The capabilities of a scheme string, if it names one.
pub(crate) fn capabilities_of(s: &str) -> Option<signorini_schemes::Capabilities> {
    s.parse::<SchemeSpec>().ok().map(|spec| spec.capabilities())
}

/// Scheme strings that must be refused (`bar.scheme`).
pub(crate) const BAD_SCHEMES: [&str; 18] = [
    "newmark(0.1, 0.9)",
    "newmark(0, 0.5)",
    "theta(0.2)",
    "theta(inf)",
    "ps(2)",
    "ps(0.5, 0.7)",
    "ps(nan)",
    "penalty(0)",
    "penalty(-1)",
    "nitsche(0, 1)",
    "nitsche(1, 2)",
    "moreau-jean(0.4, 0)",
    "foo",
    "",
    "newmark(",
    "newmark(1,2,3)",
    "ps()",
    "NEWMARK-CN",
];

/// Valid by their ranges, but a stricter validation may refuse them
/// (§2: `nitsche(0.001,1)` passes `check` and fails `run`; §3: a 1e30 penalty).
pub(crate) const EDGE_SCHEMES: [&str; 3] = ["nitsche(0.001,1)", "penalty(1e30)", "penalty-cd(1e30)"];

pub(crate) const MASSIVE: [&str; 2] = ["std", "lumped"];

pub(crate) const MASSLESS: [&str; 6] = ["mod", "mod1", "mod2", "mod3", "transfer", "singular"];

// ---------------------------------------------------------------- output --

pub(crate) fn output_entries(tw: u32) -> BoxedStrategy<Vec<(String, Value)>> {
    let every = oneof![
        6 => (1u32..=100).prop_map(|k| val(k.to_string(), Class::Good)),
        1 => pool(&["9223372036854775807", "18446744073709551615", "0x10"], Class::Good),
        2 => pool(&["0", "+0", "0b0"], bad(&["output.every"])),
        2 * tw => type_bad(&NOT_A_COUNT),
    ];
    let snapshots = oneof![
        6 => (0u32..=1000).prop_map(|k| val(k.to_string(), Class::Good)),
        1 => pool(&["9223372036854775807", "18446744073709551615"], Class::Good),
        2 * tw => type_bad(&NOT_A_COUNT),
    ];
    let plots = oneof![3 => pool(&["true", "false"], Class::Good), tw => type_bad(&NOT_A_BOOL)];
    let extra = prop::collection::vec(pool(&["1", "\"csv\""], Class::Type).prop_map(|v| ("format".to_string(), v)), 0..1 + tw as usize);
    (maybe(0.6, every.boxed()), maybe(0.4, snapshots.boxed()), maybe(0.4, plots.boxed()), extra)
        .prop_map(|(e, s, p, x)| {
            let mut v: Vec<(String, Value)> = Vec::new();
            for (k, o) in [("every", e), ("snapshots_every", s), ("plots", p)] {
                if let Some(o) = o {
                    v.push((k.into(), o));
                }
            }
            v.extend(x);
            v
        })
        .boxed()
}

// ------------------------------------------------------------- documents --

pub(crate) fn form() -> BoxedStrategy<Form> {
    prop_oneof![7 => Just(Form::Header), 2 => Just(Form::Inline), 2 => Just(Form::Dotted)].boxed()
}
