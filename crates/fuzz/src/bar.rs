//! The `[bar]` table: its picks and the table assembled from them.

use crate::config::Config;
use crate::doc::{bad, table_span, toml_f64, unknown, val, BarTable, Class, FieldPick, KnownField, Value};
use crate::pools::oneof;
use crate::pools::{
    initial_field, maybe, pick, pool, positive_key, pow2, schemes, type_bad, Node, BAD_SCHEMES, EDGE_SCHEMES, HUGE_COUNTS, MASSIVE, MASSLESS, NON_FINITE, NOT_A_COUNT, NOT_A_NUMBER, NOT_A_STRING,
};
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;

pub(crate) const BENCHMARKS: [&str; 3] = ["bar-dirichlet", "bar-neumann-gravity", "bar-neumann-gravity-0.11"];

/// The raw choices for a `[bar]` table, classified together by [`assemble_bar`].
#[derive(Clone, Debug)]
pub(crate) struct BarPicks {
    pub(crate) benchmark: Option<Value>,
    pub(crate) length: Option<(Value, i32)>,
    pub(crate) wave_speed: Option<Value>,
    pub(crate) far_end: Option<Value>,
    pub(crate) gap: Option<Value>,
    pub(crate) body_force: Option<Value>,
    pub(crate) u0: Option<FieldPick>,
    pub(crate) v0: Option<FieldPick>,
    pub(crate) elements: Option<(Value, Option<i32>)>,
    pub(crate) mass: Option<Value>,
    pub(crate) scheme: Option<(Value, Node, bool)>,
    pub(crate) step: Step,
    pub(crate) t_end: TEnd,
    pub(crate) extra: Vec<(String, Value)>,
}

/// How the bar's step is given.
#[derive(Clone, Debug)]
pub(crate) enum Step {
    /// `dt = 2^-k`.
    Dt(i32),
    /// `ratio = 2^c` (dx/dt).
    Ratio(i32),
    /// Any other dt or ratio value (out of range, extreme, wrong type).
    Other(&'static str, Value),
    /// Both keys.
    Both(Value, Value),
    /// Neither.
    Neither,
}

/// Horizons too long for 1e9 steps of a valid dt.
pub(crate) const LONG_HORIZONS: [&str; 3] = ["1e300", "1e12", "1.7976931348623157e308"];

/// How the bar's horizon is given.
#[derive(Clone, Debug)]
pub(crate) enum TEnd {
    /// `t_end = N dt` with N = 1 + (n mod the number that keeps T <= 16).
    Steps(u32),
    /// Absent: the default.
    Default,
    /// Another value.
    Other(Value),
}

pub(crate) fn bar_picks(cfg: Config, tw: u32) -> BoxedStrategy<BarPicks> {
    let benchmark = oneof![
        8 => pick(&BENCHMARKS).prop_map(|b| val(format!("\"{b}\""), Class::Good)),
        1 => pool(&["\"bar-foo\"", "\"\"", "\"Bar-Dirichlet\"", "\"bar-dirichlet \""], bad(&["bar.benchmark"])),
        tw => type_bad(&NOT_A_STRING),
    ];
    // Lengths are powers of two so that dx/dt and N dt are exact.
    let length = oneof![
        5 => pow2(-1, 2).prop_map(|e| (val(toml_f64(2f64.powi(e)), Class::Good), e)),
        1 => Just((val("1", Class::Good), 0)),
        4 => positive_key("bar.length", &["1.0"], unknown(&["bar.length", "bar.dt", "bar"]), tw).prop_map(|v| (v, 0)),
    ];
    let wave_speed = positive_key("bar.wave_speed", &["1.0", "2.0", "0.5", "1"], unknown(&["bar.wave_speed"]), tw);
    let far_end = oneof![
        4 => pool(&["\"clamped\"", "\"free\""], Class::Good),
        1 => pool(&["\"pinned\"", "\"\"", "\"Clamped\"", "\"free \""], bad(&["bar.far_end"])),
        tw => type_bad(&NOT_A_STRING),
    ];
    let gap = oneof![
        4 => pool(&["0.0", "-0.5", "-1.0", "-1e-300", "0", "-0.0"], Class::Good),
        1 => pool(&NON_FINITE, bad(&["bar.gap"])),
        1 => pool(&["2.0", "1e300"], bad(&["bar"])),
        tw => type_bad(&NOT_A_NUMBER),
    ];
    let body_force = oneof![
        4 => pool(&["0.0", "-1.0", "1e3", "-9.81", "0"], Class::Good),
        1 => pool(&NON_FINITE, bad(&["bar.body_force"])),
        1 => pool(&["1e300", "-1.7976931348623157e308"], unknown(&["bar.body_force"])),
        tw => type_bad(&NOT_A_NUMBER),
    ];
    // Sizes no machine holds: only with cfg.huge_sizes (today they allocate or panic).
    let huge = if cfg.huge_sizes { pool(&HUGE_COUNTS, bad(&["bar.elements"])) } else { pool(&["4"], Class::Good) };
    let elements = oneof![
        6 => pow2(1, 6).prop_map(|e| (val(format!("{}", 1u32 << e), Class::Good), Some(e))),
        1 => pool(&["0x10", "1_6", "+8"], Class::Good).prop_map(|v| { let e = if v.toml == "+8" { 3 } else { 4 }; (v, Some(e)) }),
        2 => (3u32..200).prop_map(|m| (val(m.to_string(), Class::Good), None)),
        2 => pool(&["0", "1", "+0", "0x1"], bad(&["bar.elements"])).prop_map(|v| (v, None)),
        1 => huge.prop_map(|v| { let e = (v.toml == "4").then_some(2); (v, e) }),
        2 * tw => type_bad(&NOT_A_COUNT).prop_map(|v| (v, None)),
    ];
    let mass = oneof![
        8 => pick(&MASSIVE.iter().chain(&MASSLESS).copied().collect::<Vec<_>>()).prop_map(|m| val(format!("\"{m}\""), Class::Good)),
        1 => pool(&["\"heavy\"", "\"\"", "\"STD\"", "\"mod4\""], bad(&["bar.mass"])),
        tw => type_bad(&NOT_A_STRING),
    ];
    let scheme = oneof![
        8 => pick(&schemes()).prop_map(|(s, n, c)| (val(format!("\"{s}\""), Class::Good), n, c)),
        2 => pick(&BAD_SCHEMES).prop_map(|s| (val(format!("\"{s}\""), bad(&["bar.scheme"])), Node::Any, false)),
        1 => pick(&EDGE_SCHEMES).prop_map(|s| (val(format!("\"{s}\""), unknown(&["bar.scheme", "bar.dt"])), if s.starts_with("penalty-cd") { Node::Massive } else { Node::Any }, false)),
        tw => type_bad(&NOT_A_STRING).prop_map(|v| (v, Node::Any, false)),
    ];
    let dt_other = oneof![
        2 => pool(&["0.0", "-0.001", "-1"], bad(&["bar.dt"])),
        2 => pool(&NON_FINITE, bad(&["bar.dt"])),
        // Steps beyond 1e9 (T >= 1/16).
        1 => pool(&["1e-300", "5e-324", "1e-12"], bad(&["bar.dt"])),
        // dt beyond T: the runner decides today; a stricter validation may refuse.
        1 => pool(&["1e300", "9223372036854775807", "1.7976931348623157e308", "0.3"], unknown(&["bar.dt", "bar.t_end"])),
        tw => type_bad(&NOT_A_NUMBER),
    ]
    .prop_map(|v| Step::Other("dt", v));
    let ratio_other = oneof![
        2 => pool(&["0.0", "-10.0", "-0"], bad(&["bar.ratio"])),
        2 => pool(&NON_FINITE, bad(&["bar.ratio"])),
        // dx/dt so large the steps exceed 1e9: named `bar.dt` (the step it gives) or `bar.ratio`.
        1 => pool(&["1e300", "1e12", "1.7976931348623157e308"], bad(&["bar.dt", "bar.ratio"])),
        1 => pool(&["1e-300", "5e-324", "3.0"], unknown(&["bar.dt", "bar.ratio", "bar.t_end"])),
        tw => type_bad(&NOT_A_NUMBER),
    ]
    .prop_map(|v| Step::Other("ratio", v));
    let step = oneof![
        6 => pow2(0, 10).prop_map(Step::Dt),
        4 => pow2(-1, 4).prop_map(Step::Ratio),
        3 => dt_other,
        2 => ratio_other,
        1 => (pool(&["0.01", "-1.0"], Class::Good), pool(&["10.0", "nan"], Class::Good)).prop_map(|(a, b)| Step::Both(a, b)),
        1 => Just(Step::Neither),
    ];
    let t_end = oneof![
        5 => (1u32..100_000).prop_map(TEnd::Steps),
        3 => Just(TEnd::Default),
        1 => pool(&["0.0", "-1.0", "-0.0"], bad(&["bar.t_end"])).prop_map(TEnd::Other),
        1 => pool(&NON_FINITE, bad(&["bar.t_end"])).prop_map(TEnd::Other),
        // Too long: too many steps, or beyond the falling bar's exact solution.
        1 => pool(&LONG_HORIZONS, bad(&["bar.dt", "bar.t_end"])).prop_map(TEnd::Other),
        tw => type_bad(&NOT_A_NUMBER).prop_map(TEnd::Other),
    ];
    let extra = prop::collection::vec(
        prop_oneof![
            pool(&["1", "\"x\""], Class::Type).prop_map(|v| ("bogus".to_string(), v)),
            pool(&["1.0"], Class::Type).prop_map(|v| ("Elements".to_string(), v)),
            pool(&["0.1"], Class::Type).prop_map(|v| ("dx".to_string(), v)),
            pool(&["\"std\""], Class::Type).prop_map(|v| ("\"mass \"".to_string(), v)),
        ],
        0..1 + tw as usize,
    );
    let u0 = initial_field("initial_displacement", cfg, tw);
    let v0 = initial_field("initial_velocity", cfg, tw);
    // proptest tuples go up to 12: nest them.
    (
        (any::<bool>(), benchmark.prop_map(Some).boxed(), maybe(0.5, length.boxed()), maybe(0.5, wave_speed), maybe(0.5, far_end.boxed()), maybe(0.5, gap.boxed()), maybe(0.4, body_force.boxed())),
        (maybe(0.9, u0), maybe(0.5, v0), maybe(if tw > 0 { 0.97 } else { 1.0 }, elements.boxed()), maybe(0.7, mass.boxed()), maybe(0.7, scheme.boxed()), step, t_end, extra, any::<bool>()),
    )
        .prop_map(|((with_benchmark, benchmark, length, wave_speed, far_end, gap, body_force), (u0, v0, elements, mass, scheme, step, t_end, extra, geometry_with_benchmark))| {
            let geo = |o: Option<Value>| {
                if with_benchmark && !geometry_with_benchmark {
                    None
                } else {
                    o
                }
            };
            BarPicks {
                benchmark: if with_benchmark { benchmark } else { None },
                length: if with_benchmark && !geometry_with_benchmark { None } else { length },
                wave_speed: geo(wave_speed),
                far_end: geo(far_end),
                gap: geo(gap),
                body_force: geo(body_force),
                u0: if with_benchmark && !geometry_with_benchmark { None } else { u0 },
                v0: if with_benchmark && !geometry_with_benchmark { None } else { v0 },
                elements,
                mass,
                scheme,
                step,
                t_end,
                extra,
            }
        })
        .boxed()
}

/// Classifies the bar's values together (mass against scheme, gap against
/// u0(0), steps against the horizon) and writes the table.
pub(crate) fn assemble_bar(p: BarPicks) -> BarTable {
    let mut entries: Vec<(String, Value)> = Vec::new();
    let mut structure = Vec::new();
    let mut known: Vec<KnownField> = Vec::new();
    let benchmark_mode = p.benchmark.is_some();
    let is_type = |v: &Value| v.class == Class::Type;
    // Geometry keys: with a benchmark every one given is refused.
    let geometry = |key: &str, v: Option<Value>, entries: &mut Vec<(String, Value)>| {
        if let Some(mut v) = v {
            if benchmark_mode && !is_type(&v) {
                v.class = Class::Bad(vec![format!("bar.{key}")]);
            }
            entries.push((key.to_string(), v));
        }
    };
    let mut length = 1.0;
    let mut length_exp = 0;
    if let Some((v, e)) = p.length.clone() {
        if v.class == Class::Good {
            length = 2f64.powi(e);
            length_exp = e;
        }
        geometry("length", Some(v), &mut entries);
    }
    geometry("wave_speed", p.wave_speed.clone(), &mut entries);
    geometry("far_end", p.far_end.clone(), &mut entries);
    geometry("body_force", p.body_force.clone(), &mut entries);
    // Absent, u0 is 0 (its documented default): known and good.
    let u0_good = p.u0.as_ref().is_none_or(|(v, _)| v.class == Class::Good);
    if let Some(mut g) = p.gap.clone() {
        // A gap above u0(0) is refused only if u0 is known (valid values have u0(0) in [0, 1]).
        if g.class == bad(&["bar"]) && !u0_good {
            g.class = unknown(&["bar", "bar.gap"]);
        }
        geometry("gap", Some(g), &mut entries);
    }
    let length_known = p.length.as_ref().is_none_or(|(v, _)| v.class == Class::Good);
    for (key, f) in [("initial_displacement", p.u0.clone()), ("initial_velocity", p.v0.clone())] {
        if let Some((mut v, func)) = f {
            // A table must cover the whole bar [0, length]; with a length
            // that may be refused or not, whether it does is not known.
            let path = if key == "initial_displacement" { "bar.initial_displacement" } else { "bar.initial_velocity" };
            if let (false, Class::Good, Some((first, last))) = (benchmark_mode, &v.class, table_span(&v.toml)) {
                if !length_known {
                    v.class = unknown(&[path]);
                } else if first > 0.0 || last < length {
                    v.class = bad(&[path]);
                }
            }
            if let (Some(func), false, Class::Good) = (func, benchmark_mode, &v.class) {
                known.push((if key == "initial_displacement" { "u" } else { "v" }, func));
            }
            geometry(key, Some(v), &mut entries);
        }
    }
    if let Some(b) = p.benchmark.clone() {
        entries.push(("benchmark".into(), b));
    }
    // Elements: required.
    let mut m_exp = None;
    match p.elements.clone() {
        Some((v, e)) => {
            m_exp = e;
            entries.push(("elements".into(), v));
        }
        None => structure.push(Class::Type),
    }
    // Scheme and mass: a valid pair, or the mass is refused.
    let (node, conditional) = p.scheme.as_ref().map(|(v, n, c)| if matches!(v.class, Class::Good | Class::Unknown(_)) { (*n, *c) } else { (Node::Any, false) }).unwrap_or((Node::Any, false));
    let mass_name = p.mass.as_ref().map(|v| v.toml.trim_matches('"').to_string()).unwrap_or_else(|| "std".into());
    let massless = MASSLESS.contains(&mass_name.as_str());
    let massive = MASSIVE.contains(&mass_name.as_str());
    let mismatch = (node == Node::Massless && massive) || (matches!(node, Node::Massive | Node::Lumped) && massless) || (node == Node::Lumped && mass_name != "lumped");
    if let Some(mut m) = p.mass.clone() {
        if m.class == Class::Good && mismatch {
            m.class = bad(&["bar.mass"]);
        }
        entries.push(("mass".into(), m));
    } else if mismatch {
        structure.push(bad(&["bar.mass"]));
    }
    if let Some((s, _, _)) = p.scheme.clone() {
        entries.push(("scheme".into(), s));
    }
    if conditional {
        // Conditionally stable: the runner checks dt today; validation may come to.
        structure.push(unknown(&["bar.dt", "bar.ratio", "bar.scheme", "bar.mass"]));
    }
    // Step and horizon. Valid steps are powers of two and valid horizons whole
    // numbers of steps with T <= 16 (the falling bar's exact solution is built
    // up to T; the paper's data only up to about 225).
    let default_t = match p.benchmark.as_ref().map(|b| b.toml.as_str()) {
        Some("\"bar-dirichlet\"") => 3.0,
        Some(_) => 16.0,
        None => 1.0,
    };
    let dt = match &p.step {
        Step::Dt(k) => Some(2f64.powi(-k)),
        Step::Ratio(c) => {
            let exact_m = m_exp.is_some() && (benchmark_mode || p.length.as_ref().is_none_or(|(v, _)| v.class == Class::Good));
            exact_m.then(|| 2f64.powi(if benchmark_mode { 0 } else { length_exp } - m_exp.unwrap_or(0) - c))
        }
        _ => None,
    };
    match &p.step {
        Step::Dt(k) => entries.push(("dt".into(), val(toml_f64(2f64.powi(-k)), Class::Good))),
        Step::Ratio(c) => entries.push(("ratio".into(), val(toml_f64(2f64.powi(*c)), Class::Good))),
        Step::Other(key, v) => {
            let mut v = v.clone();
            // dx/dt too large for 1e9 steps, unless an extreme length makes dx large too.
            if v.class == bad(&["bar.dt", "bar.ratio"]) && p.length.as_ref().is_some_and(|(l, _)| l.class != Class::Good) {
                v.class = unknown(&["bar.dt", "bar.ratio", "bar.length"]);
            }
            entries.push((key.to_string(), v));
        }
        Step::Both(a, b) => {
            entries.push(("dt".into(), a.clone()));
            entries.push(("ratio".into(), b.clone()));
            structure.push(bad(&["bar.ratio"]));
        }
        Step::Neither => structure.push(bad(&["bar.dt"])),
    }
    match (&p.t_end, dt) {
        (TEnd::Steps(n), Some(dt)) => {
            let max_n = ((16.0 / dt).floor() as u32).max(1);
            entries.push(("t_end".into(), val(toml_f64(f64::from(1 + n % max_n) * dt), Class::Good)));
        }
        (TEnd::Steps(n), None) => entries.push(("t_end".into(), val(toml_f64(f64::from(1 + n % 16)), Class::Good))),
        (TEnd::Default, Some(dt)) if default_t / dt > 1e9 => structure.push(bad(&["bar.dt"])),
        // The default horizon must be a whole number of steps.
        (TEnd::Default, Some(dt)) if (default_t / dt - (default_t / dt).round()).abs() > 1e-9 || default_t / dt < 0.5 => structure.push(bad(&["bar.t_end"])),
        (TEnd::Default, _) => {}
        (TEnd::Other(v), _) => {
            let mut v = v.clone();
            // Too many steps only if the step is a valid one (an extreme dt may be as long).
            if v.class == bad(&["bar.dt", "bar.t_end"]) && !matches!(p.step, Step::Dt(_) | Step::Ratio(_)) {
                v.class = unknown(&["bar.dt", "bar.t_end"]);
            }
            // The falling bar: validation builds the exact solution up to T
            // before counting steps, 0.5-0.7 s for T >= 1e6 before it refuses
            // (reported); keep the short run fast with a T that is still long.
            if LONG_HORIZONS.contains(&v.toml.as_str()) && p.benchmark.as_ref().is_some_and(|b| b.toml.contains("neumann")) {
                v = val("1000.0", unknown(&["bar.dt", "bar.t_end"]));
            }
            entries.push(("t_end".into(), v));
        }
    }
    if dt.is_none() && matches!(p.step, Step::Ratio(_)) {
        // dx/dt with an element count or length that is not a power of two:
        // T is not a whole number of steps (a stricter validation may refuse).
        structure.push(unknown(&["bar.dt", "bar.ratio", "bar.t_end"]));
    }
    for (k, v) in p.extra {
        entries.push((k, v));
    }
    let known = if benchmark_mode { Vec::new() } else { known };
    (entries, structure, known, length)
}
