//! The branch as text: `branch.csv`, `bifurcations.csv` and `branch.svg`
//! (strings; the front ends write them).

use crate::continuation::Branch;
use signorini_plot::{Chart, PlotError, Scale, Series, Style};
use std::f64::consts::TAU;
use std::fmt::Write;

/// The columns of `branch.csv` before the state's.
pub const BRANCH_COLUMNS: &str = "param,period,stable,mu_max,impact_velocity,impact_phase,impacts_per_period,releases_per_period,displacement,branch,residual";

/// The columns of `bifurcations.csv`.
pub const BIFURCATION_COLUMNS: &str = "param,kind,mu_re,mu_im,impacts_before,impacts_after,releases_before,releases_after,displacement,branch";

/// One branch with what the front end knows of it: the forcing periods
/// per orbit, the forcing frequency at each point, and each point's tip
/// displacement on the section (the quantity a sweep's bifurcation
/// diagram shows).
pub struct Labelled<'a> {
    /// The branch.
    pub branch: &'a Branch,
    /// Forcing periods per orbit.
    pub periods: usize,
    /// The forcing frequency Ω at each point.
    pub omega: Vec<f64>,
    /// The tip displacement at each point.
    pub displacement: Vec<f64>,
    /// The tip displacement at each bifurcation.
    pub bif_displacement: Vec<f64>,
}

fn cell(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        format!("{x:.12e}")
    }
}

/// `branch.csv`: a header ([`BRANCH_COLUMNS`], then `q<dof>` and `v<dof>`
/// of each state dof) and one row per point of every branch, numbered in
/// the `branch` column.
pub fn branch_csv(branches: &[Labelled<'_>], state_dofs: &[usize]) -> String {
    let mut out = String::from(BRANCH_COLUMNS);
    for d in state_dofs {
        let _ = write!(out, ",q{d}");
    }
    for d in state_dofs {
        let _ = write!(out, ",v{d}");
    }
    out.push('\n');
    for (b, lb) in branches.iter().enumerate() {
        for (i, p) in lb.branch.points.iter().enumerate() {
            let (speed, phase) =
                match p.orbit.events.iter().filter(|e| e.kind == signorini_schemes::events::EventKind::Impact).max_by(|a, b| a.velocity_before.abs().total_cmp(&b.velocity_before.abs())) {
                    Some(e) => (e.velocity_before.abs(), (lb.omega[i] * e.t).rem_euclid(TAU)),
                    None => (f64::NAN, f64::NAN),
                };
            let _ = write!(
                out,
                "{},{},{},{},{},{},{},{},{},{b},{}",
                cell(p.param),
                lb.periods,
                u8::from(p.stable()),
                cell(p.orbit.mu_max()),
                cell(speed),
                cell(phase),
                p.orbit.impacts(),
                p.orbit.releases(),
                cell(lb.displacement[i]),
                cell(p.orbit.residual)
            );
            for x in &p.orbit.x {
                let _ = write!(out, ",{}", cell(*x));
            }
            out.push('\n');
        }
    }
    out
}

/// `bifurcations.csv` ([`BIFURCATION_COLUMNS`]).
pub fn bifurcations_csv(branches: &[Labelled<'_>]) -> String {
    let mut out = format!("{BIFURCATION_COLUMNS}\n");
    for (b, lb) in branches.iter().enumerate() {
        for (k, f) in lb.branch.bifurcations.iter().enumerate() {
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{},{},{},{b}",
                cell(f.param),
                f.kind.name(),
                cell(f.mu.re),
                cell(f.mu.im),
                f.impacts.0,
                f.impacts.1,
                f.releases.0,
                f.releases.1,
                cell(lb.bif_displacement[k])
            );
        }
    }
    out
}

/// A point's class in `branch.svg`: 0 stable (every multiplier inside the
/// unit circle), 1 unstable, 2 neutral (every multiplier on the unit
/// circle to 1e-4: an undamped structure's orbit without impacts, whose
/// multipliers `e^{±iω_k T}` the paper's beam (J = 19) gets to 2e-5, the
/// condition of its monodromy's eigenproblem; `branch.csv`'s `stable`
/// counts it as 0).
fn class(p: &crate::BranchPoint) -> usize {
    if p.stable() {
        0
    } else if !p.orbit.multipliers.is_empty() && p.orbit.multipliers.iter().all(|m| (m.norm() - 1.0).abs() <= 1e-4) {
        2
    } else {
        1
    }
}

/// Neutral: every multiplier on the unit circle to 1e-4 (not stable, yet
/// not unstable either: [`class`] 2).
pub(crate) fn neutral(p: &crate::BranchPoint) -> bool {
    class(p) == 2
}

/// `branch.svg`: the tip displacement on the section against the
/// parameter, stable stretches solid, unstable dashed, neutral ones (every
/// multiplier on the unit circle) dotted, over `sweep` (a sweep's
/// bifurcation diagram: `(param, displacement)` dots) if given.
pub fn branch_svg(branches: &[Labelled<'_>], param: &str, sweep: &[(f64, f64)]) -> Result<String, PlotError> {
    let mut series = Vec::new();
    for (b, lb) in branches.iter().enumerate() {
        let pts = &lb.branch.points;
        let mut start = 0;
        while start < pts.len() {
            let kind = class(&pts[start]);
            let mut end = start;
            while end + 1 < pts.len() && class(&pts[end + 1]) == kind {
                end += 1;
            }
            // Each stretch joins the next one's first point.
            let last = (end + 1).min(pts.len() - 1);
            let points: Vec<(f64, f64)> = (start..=last).map(|i| (pts[i].param, lb.displacement[i])).collect();
            let label = format!("{} ({} T{})", ["stable", "unstable", "neutral"][kind], lb.periods, if b > 0 { format!(", branch {b}") } else { String::new() });
            series.push(Series { label, points, reference: false, style: Style { group: Some(b), variant: [None, Some(1), Some(2)][kind] } });
            start = end + 1;
        }
    }
    let dots: Vec<Series> = if sweep.is_empty() {
        Vec::new()
    } else {
        vec![Series { label: "sweep (stroboscopic samples)".into(), points: sweep.to_vec(), reference: false, style: Style { group: Some(7), variant: None } }]
    };
    let title = format!("Periodic orbits in {param}");
    let chart = Chart { title: &title, x_label: param, y_label: "tip displacement on the section", scale: Scale::Linear, size: (900, 560) };
    signorini_plot::line_chart_over(&chart, &series, &dots, 1)
}

/// The columns of `backbone.csv` (the contract's five, then what the
/// shooting adds: the exact contact time, the largest multiplier's modulus
/// and Newton's residual).
pub const BACKBONE_COLUMNS: &str = "energy,period,contact_time,impacts_per_period,exact_period,exact_contact_time,mu_max,residual";

/// `backbone.csv` ([`BACKBONE_COLUMNS`]): one row per point; the exact
/// columns empty where no closed form is known.
pub fn backbone_csv(modes: &crate::modes::Modes) -> String {
    let mut out = format!("{BACKBONE_COLUMNS}\n");
    for p in &modes.points {
        let (ep, ec) = p.exact.map_or((f64::NAN, f64::NAN), |e| (e.period, e.contact_time));
        let _ = writeln!(out, "{},{},{},{},{},{},{},{}", cell(p.energy), cell(p.period), cell(p.contact_time), p.impacts_per_period, cell(ep), cell(ec), cell(p.mu_max()), cell(p.residual));
    }
    out
}

/// The frequency–energy plot of a backbone (`backbone.svg`): the
/// frequency `1/T` against the energy, log–log, the discrete bar's points
/// and the continuous bar's closed form (a reference line) where known.
pub fn backbone_svg(modes: &crate::modes::Modes) -> Result<String, PlotError> {
    let own: Vec<(f64, f64)> = modes.points.iter().map(|p| (p.energy, 1.0 / p.period)).collect();
    let exact: Vec<(f64, f64)> = modes.points.iter().filter_map(|p| p.exact.map(|e| (p.energy, 1.0 / e.period))).collect();
    let mut series = vec![Series { label: format!("discrete bar, m = {}", modes.elements), points: own, reference: false, style: Style { group: Some(0), variant: Some(0) } }];
    if !exact.is_empty() {
        series.push(Series { label: "continuous bar (closed form, §11.3)".into(), points: exact, reference: true, style: Style::default() });
    }
    let chart = Chart { title: "Nonsmooth modes: frequency against energy", x_label: "energy", y_label: "frequency 1/T", scale: Scale::LogLog, size: (900, 560) };
    signorini_plot::line_chart(&chart, &series)
}
