//! The contacts of `[[stop]]` / `[obstacle]`: snapped to mesh nodes,
//! checked against the initial state, and the errors named by their field.

use crate::{field, FieldToml, InitialField, ObstacleToml, SceneError, StopToml};
use signorini_run::{RunError, Stop};
use std::fmt;

/// One contact of a scene with `[[stop]]` / `[obstacle]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Site {
    /// The mesh node (bar: `0..=m`; beam: `1..=J`).
    pub node: usize,
    /// The node's position.
    pub x: f64,
    /// The `[[stop]]` entry it comes from (its index and `x` as written).
    pub stop: Option<(usize, f64)>,
    /// The obstacle's `(lo, hi)` at the node, where `[obstacle]` applies.
    pub obstacle: Option<(f64, f64)>,
    /// Whether the stop gave its own `stiffness`.
    pub own_stiffness: bool,
}

/// The contacts of a scene with `[[stop]]` / `[obstacle]`, in contact
/// order (the series' `u_c<i>` order): the stops as listed, then the
/// obstacle's other nodes by increasing x.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSet {
    /// The stops as the problem takes them (bounds intersected with the
    /// obstacle's where both apply).
    pub stops: Vec<Stop>,
    /// Where each comes from, in the same order.
    pub sites: Vec<Site>,
}

impl ContactSet {
    /// The field a library error on contact `index` belongs to:
    /// `stop.<i>.<field>`, or `obstacle.lo` / `obstacle.hi` with the node's x.
    pub(crate) fn field_of(&self, index: usize, what: &str) -> (String, String) {
        let Some(site) = self.sites.get(index) else {
            return ("stop".into(), String::new());
        };
        match site.stop {
            Some((i, _)) => (format!("stop.{i}.{}", if what == "node" { "x" } else { what }), String::new()),
            None => (format!("obstacle.{}", if what == "hi" { "hi" } else { "lo" }), format!(" (at the node x = {})", site.x)),
        }
    }

    /// One line per stop and a summary of the obstacle's nodes, for `check`.
    pub fn describe(&self) -> String {
        let bound = |v: f64| {
            if v.is_finite() {
                format!("{v}")
            } else {
                "none".into()
            }
        };
        let mut s = format!("contacts: {} (series columns u_c<i>, lambda_<i>, active_<i> in this order)", self.sites.len());
        let mut obstacle_only = Vec::new();
        for (i, (site, st)) in self.sites.iter().zip(&self.stops).enumerate() {
            match site.stop {
                Some((j, x)) => {
                    s += &format!(
                        "\n  {i}: stop.{j} x = {x} snapped to node {} (x = {}): lo = {}, hi = {}{}",
                        site.node,
                        site.x,
                        bound(st.lo),
                        bound(st.hi),
                        if site.obstacle.is_some() { " (intersected with [obstacle])" } else { "" }
                    )
                }
                None => obstacle_only.push((i, site, st)),
            }
        }
        if let (Some(first), Some(last)) = (obstacle_only.first(), obstacle_only.last()) {
            let (lo_min, lo_max) = obstacle_only.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.2.lo), b.max(p.2.lo)));
            let (hi_min, hi_max) = obstacle_only.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.2.hi), b.max(p.2.hi)));
            s += &format!(
                "\n  {}..={}: [obstacle] at {} nodes, x = {} … {}: lo in [{}, {}], hi in [{}, {}]",
                first.0,
                last.0,
                obstacle_only.len(),
                first.1.x,
                last.1.x,
                bound(lo_min),
                bound(lo_max),
                bound(hi_min),
                bound(hi_max)
            );
        }
        s
    }
}

/// The relative tolerance (of the length) within which a stop's `x` is a node.
pub const NODE_TOLERANCE: f64 = 1e-9;

/// The nodes a scene's contacts may use.
pub(crate) struct NodeMesh<'a> {
    /// Length of the bar or beam.
    pub(crate) length: f64,
    /// Elements (nodes `0..=elements`, at `x(i)`; for a P`k` bar, `k m`:
    /// its nodes are those of a P1 bar of `k m` elements).
    pub(crate) elements: usize,
    /// The nodes that are unknowns (a clamped node cannot be a contact).
    pub(crate) unknown: std::ops::RangeInclusive<usize>,
    /// Node positions.
    pub(crate) x: &'a dyn Fn(usize) -> f64,
}

impl NodeMesh<'_> {
    /// The node at `x` (within `NODE_TOLERANCE·L`) that is an unknown;
    /// errors name `name` and give the nearest nodes or the allowed ones.
    pub(crate) fn node(&self, name: &str, x: f64) -> Result<usize, SceneError> {
        let (l, m) = (self.length, self.elements);
        let tol = NODE_TOLERANCE * l;
        let h = l / m as f64;
        if !x.is_finite() || x < -tol || x > l + tol {
            return Err(field(name, format!("{x} is not allowed: the position of a mesh node, in [0, {l}]")));
        }
        let node = ((x / h).round().max(0.0) as usize).min(m);
        if (x - (self.x)(node)).abs() > tol {
            let below = ((x / h).floor().max(0.0) as usize).min(m);
            let above = (below + 1).min(m);
            return Err(field(
                name,
                format!(
                    "{x} is not allowed: a mesh node, within {NODE_TOLERANCE:e}·L = {tol:e} (nodes x = i L/{m}); the nearest nodes are x = {} (node {below}) and x = {} (node {above})",
                    (self.x)(below),
                    (self.x)(above)
                ),
            ));
        }
        let (first, last) = (*self.unknown.start(), *self.unknown.end());
        if !self.unknown.contains(&node) {
            return Err(field(
                name,
                format!("{x} is not allowed: node {node} is clamped (no displacement to bound); allowed: the nodes {first}..={last}, x = {} to {}", (self.x)(first), (self.x)(last)),
            ));
        }
        Ok(node)
    }
}

/// Which per-stop keys act with the scene's scheme: `Err(why)` refuses the key.
pub(crate) struct KeyRules {
    pub(crate) restitution: Result<(), String>,
    pub(crate) stiffness: Result<(), String>,
}

/// One bound of `[obstacle]`, `None` where it is absent or is the number
/// `none` (`-inf` for lo, `+inf` for hi).
fn obstacle_bound(name: &str, f: Option<&FieldToml>, none: f64) -> Result<Option<InitialField>, SceneError> {
    match f {
        None => Ok(None),
        Some(FieldToml::Number(v)) if *v == none => Ok(None),
        Some(FieldToml::Number(v)) if !v.is_finite() => Err(field(name, format!("{v} is not allowed: a finite number, an expression or table in x, or {none} (no bound)"))),
        Some(f) => InitialField::compile(name, f).map(Some),
    }
}

/// The contacts of `[[stop]]` and `[obstacle]` on `mesh`, checked against
/// the initial displacement `u0(node)`: every error names its field
/// (`stop.<i>.<key>`, `obstacle.lo`/`obstacle.hi` with the node's x).
pub(crate) fn contact_set(stops: &[StopToml], obstacle: Option<&ObstacleToml>, mesh: &NodeMesh<'_>, u0: &dyn Fn(usize) -> f64, rules: &KeyRules) -> Result<ContactSet, SceneError> {
    let (first, last) = (*mesh.unknown.start(), *mesh.unknown.end());
    let mut sites: Vec<Site> = Vec::with_capacity(stops.len());
    let mut list: Vec<Stop> = Vec::with_capacity(stops.len());
    for (i, st) in stops.iter().enumerate() {
        let key = |k: &str| format!("stop.{i}.{k}");
        let x = st.x;
        let node = mesh.node(&key("x"), x)?;
        if let Some(p) = sites.iter().position(|s| s.node == node) {
            return Err(field(&key("x"), format!("{x} is not allowed: it snaps to node {node}, where stop.{p} is already; allowed: one stop per node (give lo and hi in one stop)")));
        }
        let lo = match st.lo {
            None => f64::NEG_INFINITY,
            Some(v) if v.is_nan() || v == f64::INFINITY => return Err(field(&key("lo"), format!("{v} is not allowed: a number, or -inf (no lower bound)"))),
            Some(v) => v,
        };
        let hi = match st.hi {
            None => f64::INFINITY,
            Some(v) if v.is_nan() || v == f64::NEG_INFINITY => return Err(field(&key("hi"), format!("{v} is not allowed: a number, or +inf (no upper bound)"))),
            Some(v) => v,
        };
        if !lo.is_finite() && !hi.is_finite() {
            return match (st.lo, st.hi) {
                (Some(v), _) => Err(field(&key("lo"), format!("{v} without a finite hi is not allowed: at least one finite bound (a finite lo, or a finite hi)"))),
                (None, Some(v)) => Err(field(&key("hi"), format!("{v} without a finite lo is not allowed: at least one finite bound (a finite hi, or a finite lo)"))),
                (None, None) => Err(field(&key("lo"), "give lo and/or hi: a stop needs at least one finite bound")),
            };
        }
        if lo > hi {
            return Err(field(&key("lo"), format!("{lo} is not allowed: lo <= hi = {hi}")));
        }
        if let Some(e) = st.restitution {
            if let Err(why) = &rules.restitution {
                return Err(field(&key("restitution"), why));
            }
            if !(0.0..=1.0).contains(&e) {
                return Err(field(&key("restitution"), format!("{e} is not allowed: [0, 1]")));
            }
        }
        if let Some(k) = st.stiffness {
            if let Err(why) = &rules.stiffness {
                return Err(field(&key("stiffness"), why));
            }
            if !(k > 0.0 && k.is_finite()) {
                return Err(field(&key("stiffness"), format!("{k} is not allowed: finite and > 0")));
            }
        }
        sites.push(Site { node, x: (mesh.x)(node), stop: Some((i, x)), obstacle: None, own_stiffness: st.stiffness.is_some() });
        list.push(Stop { node, lo, hi, restitution: st.restitution, stiffness: st.stiffness });
    }
    if let Some(ob) = obstacle {
        if ob.lo.is_none() && ob.hi.is_none() {
            return Err(field("obstacle", "give lo and/or hi (a number, an expression in x or a table)"));
        }
        let lo_f = obstacle_bound("obstacle.lo", ob.lo.as_ref(), f64::NEG_INFINITY)?;
        let hi_f = obstacle_bound("obstacle.hi", ob.hi.as_ref(), f64::INFINITY)?;
        // A table must cover the nodes the obstacle bounds.
        for (name, f) in [("obstacle.lo", &lo_f), ("obstacle.hi", &hi_f)] {
            if let Some(f) = f {
                f.check_covers(name, (mesh.x)(first), (mesh.x)(last))?;
            }
        }
        if lo_f.is_none() && hi_f.is_none() {
            let name = if ob.lo.is_some() { "obstacle.lo" } else { "obstacle.hi" };
            return Err(field(name, "-inf / +inf alone is not a bound: give at least one finite bound (lo or hi)"));
        }
        let at = |name: &str, f: &Option<InitialField>, x: f64, none: f64| -> Result<f64, SceneError> {
            match f {
                None => Ok(none),
                Some(f) => {
                    let v = f.eval(x);
                    if v.is_finite() {
                        Ok(v)
                    } else {
                        Err(field(name, format!("{v} at the node x = {x} is not allowed: a value finite at every node (for no bound give the number {none}, not an expression)")))
                    }
                }
            }
        };
        for node in first..=last {
            let x = (mesh.x)(node);
            let lo = at("obstacle.lo", &lo_f, x, f64::NEG_INFINITY)?;
            let hi = at("obstacle.hi", &hi_f, x, f64::INFINITY)?;
            if lo > hi {
                return Err(field("obstacle.lo", format!("lo({x}) = {lo} is not allowed: lo(x) <= hi(x) = {hi} at every node")));
            }
            match sites.iter().position(|s| s.node == node) {
                Some(p) => {
                    // A stop there: the intersection of both.
                    let (st, i) = (&mut list[p], sites[p].stop.map_or(p, |s| s.0));
                    if st.lo > hi {
                        return Err(field(
                            &format!("stop.{i}.lo"),
                            format!("{} is not allowed: above obstacle.hi = {hi} at its node x = {x}; allowed: bounds that meet the obstacle's (the two are intersected)", st.lo),
                        ));
                    }
                    if st.hi < lo {
                        return Err(field(
                            &format!("stop.{i}.hi"),
                            format!("{} is not allowed: below obstacle.lo = {lo} at its node x = {x}; allowed: bounds that meet the obstacle's (the two are intersected)", st.hi),
                        ));
                    }
                    st.lo = st.lo.max(lo);
                    st.hi = st.hi.min(hi);
                    sites[p].obstacle = Some((lo, hi));
                }
                None => {
                    sites.push(Site { node, x, stop: None, obstacle: Some((lo, hi)), own_stiffness: false });
                    list.push(Stop::new(node, lo, hi));
                }
            }
        }
    }
    // The initial state inside every contact's bounds, the violated bound named.
    for (site, st) in sites.iter().zip(&list) {
        let u = u0(site.node);
        if !(st.lo <= u && u <= st.hi) {
            let (which, bound, side) = if u < st.lo { ("lo", st.lo, "below") } else { ("hi", st.hi, "above") };
            // The stop's own bound if it is the one violated, else the obstacle's.
            let own = site.stop.filter(|(i, _)| (if which == "lo" { stops[*i].lo } else { stops[*i].hi }) == Some(bound));
            let name = match own {
                Some((i, _)) => format!("stop.{i}.{which}"),
                None => format!("obstacle.{which}"),
            };
            return Err(field(
                &name,
                format!(
                    "{bound} at x = {} (node {}) is not allowed: the initial displacement u0 = {u} is {side} it; allowed: bounds the initial state satisfies, lo <= u0(x) <= hi",
                    site.x, site.node
                ),
            ));
        }
    }
    Ok(ContactSet { stops: list, sites })
}

/// The table a scene-level contact error names: `stop` when `[[stop]]` is
/// given, else `obstacle`.
pub(crate) fn contacts_table(stops: &[StopToml]) -> &'static str {
    if stops.is_empty() {
        "obstacle"
    } else {
        "stop"
    }
}

/// A library error on a scene's contacts, named by the contact's field.
pub(crate) fn contact_error(e: RunError, set: &ContactSet, table: &str) -> SceneError {
    match e {
        RunError::Stop { index, field: f, value, allowed } => {
            let (name, at) = set.field_of(index, f);
            field(&name, format!("{value}{at}: allowed {allowed}"))
        }
        RunError::Fem(e @ signorini_fem::FemError::MassAtContacts { .. }) => field(
            &format!("{table}.mass"),
            format!("{e}; allowed: std or lumped (any contact nodes), or contact nodes this treatment supports (docs/scenes.md, \"Several contacts: [[stop]] and [obstacle]\")"),
        ),
        e => field(table, e),
    }
}

/// The stop a "stop stiffness" error is about: the first contact whose
/// stiffness is `value` (in the scheme's units `kappa(stiffness)`).
pub(crate) fn stiff_stop(set: &ContactSet, value: f64, kappa: impl Fn(f64) -> f64) -> Option<&Site> {
    set.stops.iter().zip(&set.sites).find(|(st, _)| st.stiffness.is_some_and(|k| kappa(k) == value)).map(|(_, site)| site)
}

/// The softest own stop stiffness of `set` (its stop index and value).
pub(crate) fn softest_stop(set: &ContactSet) -> Option<(usize, f64)> {
    set.stops.iter().zip(&set.sites).filter(|(_, site)| site.own_stiffness).filter_map(|(st, site)| Some((site.stop?.0, st.stiffness?))).min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The message of a spring too soft for floating point.
pub(crate) fn too_soft(e: impl fmt::Display) -> String {
    format!("{e}: a spring this soft has a compliance 1/(β dt² κ) beyond the floating-point range; allowed: stiffness with β dt² κ >= 2.2e-308 (κ in the scaled equation)")
}
