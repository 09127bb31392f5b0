//! `[[stop]]` lists and `[obstacle]` tables, classified against what the
//! rest of the document makes certain.

use crate::bar::{assemble_bar, BarPicks, Step, TEnd};
use crate::beam::{assemble_beam, BeamPicks, FIGURES, PENALTY_FIGURES};
use crate::config::Config;
use crate::doc::{bad, toml_count, toml_f64, val, Class, Doc, Form, Table, Value};
use crate::pools::oneof;
use crate::pools::{capabilities_of, form, good_expressions, maybe, pick, pow2, schemes, Node, MASSIVE, MASSLESS};
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;

// -------------------------------------------------------------- contacts --

/// Where a generated `[[stop]]` sits.
#[derive(Clone, Debug)]
pub(crate) enum XPick {
    /// `x = 0`: the bar's contact node 0 (the beam's clamped node: refused).
    Zero,
    /// `x = L`: the bar's far end (refused if clamped), the beam's tip.
    End,
    /// A position that is no mesh node of any generated mesh (0.4142136 L).
    NotNode,
    /// Refused whatever the mesh (non-finite, outside [0, L]).
    Invalid(&'static str),
    /// A wrong type, or no `x` at all: a parse error.
    WrongType(Option<&'static str>),
}

/// A per-stop number (`restitution`, `stiffness`): in range, out of range,
/// or of the wrong type.
#[derive(Clone, Debug)]
pub(crate) enum Num {
    Good(&'static str),
    Invalid(&'static str),
    WrongType(&'static str),
}

/// A generated `[[stop]]` entry.
#[derive(Clone, Debug)]
pub(crate) struct StopPick {
    pub(crate) x: XPick,
    /// `Ok(choice)`: valid bounds (which depend on where the stop is);
    /// `Err((lo, hi, field))`: bounds refused whatever the mesh, naming `field`.
    pub(crate) bounds: Result<usize, (Option<&'static str>, Option<&'static str>, &'static str)>,
    pub(crate) restitution: Option<Num>,
    pub(crate) stiffness: Option<Num>,
    /// An unknown key (a parse error).
    pub(crate) unknown_key: bool,
}

/// A generated `[obstacle]`.
#[derive(Clone, Debug)]
pub(crate) enum ObstaclePick {
    /// Valid bounds for every valid initial state (choice of lo, hi).
    Good(usize, usize),
    /// Refused whatever the mesh: `(lo, hi, field)`.
    Invalid(Option<&'static str>, Option<&'static str>, &'static str),
    /// A bound above every valid initial displacement (bar: u0 <= 16 on
    /// [0, 4]; beam: u = 0): refused naming `obstacle.lo` when the initial
    /// state is known.
    AboveStart,
    /// A wrong type or an unknown key.
    WrongType(Option<&'static str>, Option<&'static str>, bool),
}

/// The `[[stop]]` list and `[obstacle]` of a document, and how `[obstacle]` is written.
pub(crate) type ContactPicks = (Option<Vec<StopPick>>, Option<ObstaclePick>, Form, bool);

pub(crate) fn stop_pick(tw: u32) -> BoxedStrategy<StopPick> {
    let x = oneof![
        6 => Just(XPick::Zero),
        6 => Just(XPick::End),
        1 => Just(XPick::NotNode),
        2 => pick(&["nan", "inf", "-inf", "-1.0", "1e9", "-1e-3"]).prop_map(XPick::Invalid),
        tw => pick(&[Some("\"0\""), Some("true"), Some("[0.0]"), None]).prop_map(XPick::WrongType),
    ];
    let bounds = prop_oneof![
        8 => (0usize..4).prop_map(Ok),
        3 => pick(&[
            (Some("nan"), None, "lo"),
            (Some("inf"), Some("1.0"), "lo"),
            (None, Some("nan"), "hi"),
            (Some("-1.0"), Some("-inf"), "hi"),
            (Some("1.0"), Some("0.0"), "lo"),
            (None, None, "lo"),
            (Some("-inf"), None, "lo"),
            (None, Some("inf"), "hi"),
            (Some("-inf"), Some("inf"), "lo"),
        ])
        .prop_map(Err),
    ];
    let num = |good: &'static [&'static str], invalid: &'static [&'static str]| -> BoxedStrategy<Num> {
        oneof![3 => pick(good).prop_map(Num::Good), 1 => pick(invalid).prop_map(Num::Invalid), tw => pick(&["true", "\"0.5\"", "[1.0]"]).prop_map(Num::WrongType)]
    };
    let restitution = num(&["0.5", "0.0", "1", "1.0"], &["1.5", "-0.1", "nan", "inf"]);
    let stiffness = num(&["10.0", "1e3"], &["0.0", "-1.0", "nan", "inf", "-0.0"]);
    (x, bounds, maybe(0.25, restitution), maybe(0.25, stiffness), maybe(if tw > 0 { 0.1 } else { 0.0 }, Just(true).boxed()))
        .prop_map(|(x, bounds, restitution, stiffness, unknown)| StopPick { x, bounds, restitution, stiffness, unknown_key: unknown.is_some() })
        .boxed()
}

pub(crate) fn obstacle_pick(tw: u32) -> BoxedStrategy<ObstaclePick> {
    oneof![
        6 => (0usize..4, 0usize..4).prop_map(|(a, b)| ObstaclePick::Good(a, b)),
        3 => pick(&[
            (Some("nan"), None, "obstacle.lo"),
            (Some("inf"), None, "obstacle.lo"),
            (None, Some("-inf"), "obstacle.hi"),
            (Some("\"(\""), None, "obstacle.lo"),
            (Some("\"math::ln(x - 100)\""), None, "obstacle.lo"),
            (None, Some("\"y + 1\""), "obstacle.hi"),
            (Some("1.0"), Some("0.0"), "obstacle.lo"),
            (Some("\"1 + x\""), Some("\"x\""), "obstacle.lo"),
            (None, None, "obstacle"),
            (Some("-inf"), None, "obstacle.lo"),
            (Some("-inf"), Some("inf"), "obstacle.lo"),
            (Some("[]"), None, "obstacle.lo"),
            (Some("[[1.0, 0.0], [0.5, 0.0]]"), None, "obstacle.lo"),
        ])
        .prop_map(|(lo, hi, f)| ObstaclePick::Invalid(lo, hi, f)),
        1 => Just(ObstaclePick::AboveStart),
        tw => pick(&[(Some("true"), None, false), (Some("[[0.0]]"), None, false), (None, Some("{ a = 1 }"), false), (Some("-1.0"), None, true)]).prop_map(|(lo, hi, u)| ObstaclePick::WrongType(lo, hi, u)),
    ]
}

/// Contacts with probabilities `p_stops`, `p_obstacle`.
pub(crate) fn contact_picks(tw: u32, p_stops: f64, p_obstacle: f64) -> BoxedStrategy<ContactPicks> {
    (
        maybe(p_stops, prop::collection::vec(stop_pick(tw), 1..4).boxed()),
        maybe(p_obstacle, obstacle_pick(tw)),
        form(),
        maybe(if tw > 0 { 0.05 } else { 0.0 }, Just(true).boxed()).prop_map(|b| b.is_some()),
    )
        .boxed()
}

/// A custom bar or a paper beam whose every value is valid (the scheme
/// unconditionally stable), with `[[stop]]` and/or `[obstacle]`: the
/// documents in which the contacts' own answer decides.
pub(crate) fn contact_documents(cfg: Config) -> BoxedStrategy<Doc> {
    prop_oneof![2 => contact_bar_documents(cfg), 1 => contact_beam_documents(cfg)].boxed()
}

pub(crate) fn contact_beam_documents(cfg: Config) -> BoxedStrategy<Doc> {
    (pick(&FIGURES), maybe(0.5, (1u32..=64).boxed()), maybe(0.4, pick(&["\"projection\"", "\"penalty\""])), contact_picks(0, 0.7, 0.5), any::<bool>())
        .prop_map(move |(figure, elements, contact, contacts, crlf)| {
            let beam = BeamPicks {
                scene: Some(val(format!("\"{figure}\""), Class::Good)),
                elements: elements.map(|j| val(j.to_string(), Class::Good)),
                dt: None,
                t_end: None,
                contact: contact.map(|c| val(c, Class::Good)),
                beta: None,
                stiffness: None,
                stops: None,
                support: None,
                force: None,
                extra: Vec::new(),
            };
            let ctx = beam_ctx(&beam);
            let (stop_tables, obstacle_table, structure) = assemble_contacts(contacts, &ctx);
            let mut tables = vec![Table { name: "beam".into(), entries: assemble_beam(beam, cfg), form: Form::Header }];
            tables.extend(obstacle_table);
            tables.extend(stop_tables);
            Doc { tables, structure, known_fields: Vec::new(), length: 1.0, crlf }
        })
        .boxed()
}

pub(crate) fn contact_bar_documents(cfg: Config) -> BoxedStrategy<Doc> {
    let schemes: Vec<(String, Node, bool)> = schemes().into_iter().filter(|s| !s.2).collect();
    // Massive masses half the time (a massless one is refused with [obstacle]).
    let masses: Vec<&str> = MASSIVE.iter().cycle().take(MASSLESS.len()).chain(&MASSLESS).copied().collect();
    (
        (pow2(-1, 2), proptest::sample::select(good_expressions(cfg.float_expressions)), any::<bool>(), pow2(2, 6), pick(&masses), pick(&schemes), pow2(4, 10), 1u32..200),
        contact_picks(0, 0.6, 0.5),
        any::<bool>(),
    )
        .prop_map(|((l, (expr, f), free, m, mass, (scheme, node, cond), k, n), contacts, crlf)| {
            let bar = BarPicks {
                benchmark: None,
                length: Some((val(toml_f64(2f64.powi(l)), Class::Good), l)),
                wave_speed: None,
                far_end: Some(val(if free { "\"free\"" } else { "\"clamped\"" }, Class::Good)),
                gap: None,
                body_force: None,
                u0: Some((val(format!("\"{expr}\""), Class::Good), Some(f))),
                v0: None,
                elements: Some((val(format!("{}", 1u32 << m), Class::Good), Some(m))),
                mass: Some(val(format!("\"{mass}\""), Class::Good)),
                scheme: Some((val(format!("\"{scheme}\""), Class::Good), node, cond)),
                step: Step::Dt(k),
                t_end: TEnd::Steps(n),
                extra: Vec::new(),
            };
            let ctx = bar_ctx(&bar);
            let (stop_tables, obstacle_table, mut structure) = assemble_contacts(contacts, &ctx);
            let (entries, s, known, length) = assemble_bar(bar);
            structure.extend(s);
            let mut tables = vec![Table { name: "bar".into(), entries, form: Form::Header }];
            tables.extend(obstacle_table);
            tables.extend(stop_tables);
            Doc { tables, structure, known_fields: known, length, crlf }
        })
        .boxed()
}

/// What a document's contacts can rely on: the table they go with and,
/// where the document makes it certain, the mesh, the initial state and
/// which per-stop keys the scheme uses.
#[derive(Clone, Debug, Default)]
pub(crate) struct ContactCtx {
    /// A beam (else a bar, or both/none: refused anyway).
    pub(crate) beam: bool,
    /// Every fact below is known (else the contacts' answer is not predicted).
    pub(crate) certain: bool,
    /// Bar: benchmark given (stops refused, naming the table).
    pub(crate) benchmark: bool,
    /// Bar: `gap` given (refused with stops).
    pub(crate) gap: bool,
    /// Beam: `stops` given (refused with stops).
    pub(crate) beam_stops: bool,
    /// Length (bar: 2^e or 1; beam: 1.501).
    pub(crate) length: f64,
    /// Bar: the far end is free (node m is an unknown).
    pub(crate) free_end: bool,
    /// Bar: a massless-node mass.
    pub(crate) massless: bool,
    /// The scheme has a restitution law (bar: ps, taylor-flanagan,
    /// moreau-jean; beam: the projection).
    pub(crate) restitution_acts: bool,
    /// The scheme is a penalty.
    pub(crate) stiffness_acts: bool,
    /// Bar: the scheme takes one contact only, at node 0, one-sided
    /// (hybrid, reduced-cn, cd-massless, nitsche).
    pub(crate) single_only: bool,
    /// Bar: the event-driven reference with a massless node (a restitution
    /// other than 0 is refused naming the scheme: the node lands without
    /// an impact).
    pub(crate) restitution_zero_only: bool,
}

pub(crate) fn bar_ctx(p: &BarPicks) -> ContactCtx {
    let good = |v: &Value| v.class == Class::Good;
    let length = match &p.length {
        None => Some(1.0),
        Some((v, e)) if good(v) => Some(2f64.powi(*e)),
        _ => None,
    };
    let free_end = match &p.far_end {
        None => Some(false),
        Some(v) if good(v) => Some(v.toml.contains("free")),
        _ => None,
    };
    let m = p.elements.as_ref().filter(|(v, _)| good(v)).and_then(|(v, _)| toml_count(&v.toml));
    let mass = match &p.mass {
        None => Some("std".to_string()),
        Some(v) if good(v) => Some(v.toml.trim_matches('"').to_string()),
        _ => None,
    };
    let scheme = match &p.scheme {
        None => Some("newmark-cn".to_string()),
        Some((v, _, _)) if good(v) => Some(v.toml.trim_matches('"').to_string()),
        _ => None,
    };
    let u0_good = p.u0.as_ref().is_none_or(|(v, _)| good(v));
    let s = scheme.clone().unwrap_or_default();
    ContactCtx {
        beam: false,
        certain: p.benchmark.is_none() && p.gap.is_none() && length.is_some() && free_end.is_some() && m.is_some_and(|m| m >= 4) && mass.is_some() && scheme.is_some() && u0_good,
        benchmark: p.benchmark.is_some(),
        gap: p.gap.is_some(),
        beam_stops: false,
        length: length.unwrap_or(1.0),
        free_end: free_end.unwrap_or(false),
        massless: mass.as_deref().is_some_and(|m| MASSLESS.contains(&m)),
        restitution_acts: capabilities_of(&s).is_some_and(|c| c.restitution),
        stiffness_acts: capabilities_of(&s).is_some_and(|c| c.stiffness),
        single_only: capabilities_of(&s).is_some_and(|c| !c.several_contacts),
        restitution_zero_only: s.starts_with("event-driven") && mass.as_deref().is_some_and(|m| MASSLESS.contains(&m)),
    }
}

pub(crate) fn beam_ctx(p: &BeamPicks) -> ContactCtx {
    let figure = p.scene.as_ref().filter(|v| v.class == Class::Good).map(|v| v.toml.trim_matches('"').to_string());
    let contact_given = p.contact.as_ref().filter(|v| v.class == Class::Good).map(|v| v.toml.trim_matches('"').to_string());
    let penalty = match (&p.contact, &contact_given) {
        (_, Some(c)) => Some(c == "penalty"),
        (None, None) => Some(figure.as_deref().is_some_and(|f| PENALTY_FIGURES.contains(&f))),
        (Some(_), None) => None,
    };
    ContactCtx {
        beam: true,
        certain: penalty.is_some(),
        beam_stops: p.stops.is_some(),
        length: 1.501,
        restitution_acts: penalty == Some(false),
        stiffness_acts: penalty == Some(true),
        ..ContactCtx::default()
    }
}

/// Valid bounds for a stop at `x` (choice `c`): they hold every valid
/// initial state (bar: u0(0) in [0, 1], |u0| <= 16 on [0, 4]; beam: u = 0).
pub(crate) fn good_stop_bounds(beam: bool, x: &XPick, c: usize) -> (Option<&'static str>, Option<&'static str>) {
    match (beam, x) {
        (true, _) => [(Some("-0.1"), Some("0.1")), (Some("-0.1"), None), (None, Some("0.05")), (Some("-inf"), Some("0.1"))][c % 4],
        (false, XPick::Zero) => [(Some("0.0"), None), (Some("-0.25"), Some("2.0")), (Some("-1"), None), (Some("0"), Some("inf"))][c % 4],
        (false, _) => [(Some("-20.0"), Some("20.0")), (Some("-20.0"), None), (None, Some("20")), (Some("-1e3"), Some("1e3"))][c % 4],
    }
}

/// Valid `[obstacle]` bounds (choices `a`, `b`; at least one finite).
pub(crate) fn good_obstacle_bounds(beam: bool, a: usize, b: usize) -> (Option<&'static str>, Option<&'static str>) {
    let (los, his): (&[Option<&str>], &[Option<&str>]) = if beam {
        (&[Some("-0.1"), Some("\"-0.1 - 0.01 * x\""), Some("[[0.0, -0.2], [2.0, -0.1]]"), None], &[Some("0.1"), Some("\"0.1 + x^2\""), Some("inf"), None])
    } else {
        (&[Some("-20.0"), Some("\"-20 - x\""), Some("[[0.0, -20.0], [8.0, -30.0]]"), Some("-inf")], &[Some("20.0"), Some("\"20 + math::abs(x)\""), None, Some("inf")])
    };
    let (lo, hi) = (los[a % 4], his[b % 4]);
    let finite = |v: Option<&str>| v.is_some_and(|t| !t.contains("inf"));
    if finite(lo) || finite(hi) {
        (lo, hi)
    } else {
        (los[0], hi)
    }
}

/// The `[[stop]]` tables, the `[obstacle]` table and the classes they add,
/// for a document whose contacts go with `ctx`.
pub(crate) fn assemble_contacts(picks: ContactPicks, ctx: &ContactCtx) -> (Vec<Table>, Option<Table>, Vec<Class>) {
    let (stops, obstacle, obstacle_form, stop_inline) = picks;
    let stops = stops.unwrap_or_default();
    let mut classes = Vec::new();
    if stops.is_empty() && obstacle.is_none() {
        return (Vec::new(), None, classes);
    }
    let table = if stops.is_empty() { "obstacle" } else { "stop" };
    // Every field a contact error may name, for the answers not predicted.
    let mut broad: Vec<String> = ["stop", "obstacle", "obstacle.lo", "obstacle.hi"].map(String::from).to_vec();
    if ctx.beam {
        broad.extend(["beam", "beam.stops", "beam.dt", "beam.penalty_stiffness", "beam.beta"].map(String::from));
    } else {
        broad.extend(["bar", "bar.gap", "bar.mass", "bar.scheme", "bar.dt", "bar.ratio", "bar.t_end", "bar.length", "bar.elements", "bar.initial_displacement", "bar.wave_speed"].map(String::from));
    }
    for i in 0..stops.len() {
        broad.extend(["x", "lo", "hi", "restitution", "stiffness"].map(|k| format!("stop.{i}.{k}")));
    }
    if ctx.benchmark {
        classes.push(bad(&[table]));
    }
    if ctx.gap {
        classes.push(bad(&["bar.gap"]));
    }
    if ctx.beam_stops {
        classes.push(bad(&["beam.stops"]));
    }
    if !ctx.certain {
        classes.push(Class::Unknown(broad.clone()));
    }
    let l = ctx.length;
    let mut tables = Vec::new();
    // Nodes of the valid stops (for duplicates and the schemes' rules): (node is 0, one-sided).
    let mut sites: Vec<(bool, bool)> = Vec::new();
    let mut seen: Vec<&'static str> = Vec::new();
    for (i, st) in stops.iter().enumerate() {
        let key = |k: &str| format!("stop.{i}.{k}");
        let mut entries: Vec<(String, Value)> = Vec::new();
        let mut valid = true;
        let x_name = match &st.x {
            XPick::Zero => "zero",
            XPick::End => "end",
            _ => "other",
        };
        match &st.x {
            XPick::Zero | XPick::End => {
                let text = if matches!(st.x, XPick::Zero) { "0.0".to_string() } else { toml_f64(l) };
                let clamped = if ctx.beam { matches!(st.x, XPick::Zero) } else { matches!(st.x, XPick::End) && !ctx.free_end };
                let class = if clamped || seen.contains(&x_name) {
                    valid = false;
                    Class::Bad(vec![key("x")])
                } else {
                    Class::Good
                };
                seen.push(x_name);
                entries.push(("x".into(), val(text, class)));
            }
            XPick::NotNode => {
                valid = false;
                entries.push(("x".into(), val(toml_f64(0.414_213_6 * l), Class::Bad(vec![key("x")]))));
            }
            XPick::Invalid(t) => {
                valid = false;
                entries.push(("x".into(), val(*t, Class::Bad(vec![key("x")]))));
            }
            XPick::WrongType(Some(t)) => entries.push(("x".into(), val(*t, Class::Type))),
            XPick::WrongType(None) => {
                // No x at all: a missing field is a parse error.
                entries.push(("lo".into(), val("0.0", Class::Type)));
            }
        }
        let (lo, hi) = match st.bounds {
            Ok(c) => good_stop_bounds(ctx.beam, &st.x, c),
            Err((lo, hi, f)) => {
                valid = false;
                if lo.is_none() && hi.is_none() {
                    // No bound at all: nothing to hold the class.
                    classes.push(Class::Bad(vec![key(f)]));
                }
                let class = Class::Bad(vec![key(f)]);
                for (k, v) in [("lo", lo), ("hi", hi)] {
                    if let Some(v) = v {
                        entries.push((k.into(), val(v, class.clone())));
                    }
                }
                (None, None)
            }
        };
        let one_sided = hi.is_none_or(|h| h.contains("inf"));
        for (k, v) in [("lo", lo), ("hi", hi)] {
            if let Some(v) = v {
                entries.push((k.into(), val(v, Class::Good)));
            }
        }
        for (k, num, acts) in [("restitution", &st.restitution, ctx.restitution_acts), ("stiffness", &st.stiffness, ctx.stiffness_acts)] {
            match num {
                None => {}
                Some(Num::Good(v)) => {
                    let v = if k == "stiffness" && ctx.beam { "1e8" } else { v };
                    let nonzero = v.parse::<f64>().is_ok_and(|x| x != 0.0);
                    let class = if k == "restitution" && ctx.restitution_zero_only && nonzero {
                        // A conflict with the scheme, not with the site: the
                        // stop still counts for the mass's placement rules,
                        // which the scene checks first.
                        Class::Bad(vec!["bar.scheme".to_string(), key(k)])
                    } else if acts {
                        Class::Good
                    } else {
                        valid = false;
                        Class::Bad(vec![key(k)])
                    };
                    entries.push((k.into(), val(v, class)));
                }
                Some(Num::Invalid(v)) => {
                    valid = false;
                    entries.push((k.into(), val(*v, Class::Bad(vec![key(k)]))));
                }
                Some(Num::WrongType(v)) => entries.push((k.into(), val(*v, Class::Type))),
            }
        }
        if st.unknown_key {
            entries.push(("node".into(), val("3", Class::Type)));
        }
        if valid && matches!(st.x, XPick::Zero | XPick::End) {
            sites.push((matches!(st.x, XPick::Zero), one_sided));
        }
        tables.push(Table { name: "stop".into(), entries, form: Form::ArrayItem });
    }
    if stop_inline && !tables.is_empty() {
        // `stop = { … }`: a table where an array of tables is expected.
        tables[0].form = Form::Inline;
        classes.push(Class::Type);
    }
    let mut obstacle_table = None;
    let mut with_obstacle = false;
    if let Some(ob) = obstacle {
        let mut entries: Vec<(String, Value)> = Vec::new();
        let push = |entries: &mut Vec<(String, Value)>, lo: Option<&'static str>, hi: Option<&'static str>, class: Class| {
            for (k, v) in [("lo", lo), ("hi", hi)] {
                if let Some(v) = v {
                    entries.push((k.into(), val(v, class.clone())));
                }
            }
        };
        match ob {
            ObstaclePick::Good(a, b) => {
                let (lo, hi) = good_obstacle_bounds(ctx.beam, a, b);
                push(&mut entries, lo, hi, Class::Good);
                with_obstacle = true;
            }
            ObstaclePick::Invalid(lo, hi, f) => {
                // The field names its table's key: the table itself when empty.
                classes.push(Class::Bad(vec![f.to_string()]));
                push(&mut entries, lo, hi, Class::Bad(vec![f.to_string()]));
            }
            ObstaclePick::AboveStart => {
                let lo = if ctx.beam { "0.05" } else { "100.0" };
                let known = ctx.beam || ctx.certain;
                // A stop's bounds may not meet it: then the stop is named.
                let mut fields = vec!["obstacle.lo".to_string()];
                fields.extend((0..stops.len()).flat_map(|i| [format!("stop.{i}.lo"), format!("stop.{i}.hi")]));
                push(&mut entries, Some(lo), None, if known { Class::Bad(fields) } else { Class::Unknown(broad.clone()) });
            }
            ObstaclePick::WrongType(lo, hi, unknown_key) => {
                push(&mut entries, lo, hi, Class::Type);
                if unknown_key {
                    entries.push(("g".into(), val("1.0", Class::Type)));
                }
            }
        }
        obstacle_table = Some(Table { name: "obstacle".into(), entries, form: obstacle_form });
    }
    // Valid contacts refused by the bar's scheme or mass (the beam takes any set).
    let all_valid = sites.len() == stops.len() && (obstacle_table.is_none() || with_obstacle);
    // A massless-node mass with any [obstacle] is refused before its values are read.
    if !ctx.beam && ctx.massless && obstacle_table.is_some() {
        classes.push(bad(&["bar.mass"]));
    } else if ctx.certain && !ctx.beam && all_valid {
        {
            let k = if with_obstacle { 2 } else { sites.len() };
            if ctx.massless && k == 1 && !sites[0].0 {
                classes.push(bad(&["bar.mass"]));
            }
            if ctx.single_only && (k > 1 || !sites[0].0 || !sites[0].1) {
                classes.push(bad(&["bar.scheme", "bar.mass"]));
            }
        }
    }
    (tables, obstacle_table, classes)
}
