//! Scatter plots of many points: thinning beyond [`MAX_PLOT_POINTS`] and
//! the impact map of vibro-impact runs and sweeps.

use crate::{scatter, Chart, Scale, Series, Style};

/// Points beyond which a scatter plot shows every k-th (a plot of 10⁶ dots
/// would be a file of 100 MB); the CSVs keep them all.
pub const MAX_PLOT_POINTS: usize = 100_000;

/// Every k-th point when there are more than [`MAX_PLOT_POINTS`], and the
/// title saying so.
pub fn thin(pts: Vec<(f64, f64)>, title: &str, what: &str) -> (Vec<(f64, f64)>, String) {
    if pts.len() <= MAX_PLOT_POINTS {
        return (pts, title.to_string());
    }
    let every = pts.len().div_ceil(MAX_PLOT_POINTS);
    let n = pts.len();
    (pts.into_iter().step_by(every).collect(), format!("{title} (every {every}th of {n} {what})"))
}

/// [`thin`] over several series together; returns the title.
pub fn thin_series(series: &mut [Series], title: &str, what: &str) -> String {
    let total: usize = series.iter().map(|s| s.points.len()).sum();
    if total <= MAX_PLOT_POINTS {
        return title.to_string();
    }
    let every = total.div_ceil(MAX_PLOT_POINTS);
    for s in series.iter_mut() {
        s.points = s.points.iter().copied().step_by(every).collect();
    }
    format!("{title} (every {every}th of {total} {what})")
}

/// The impact map: pre-impact velocity against forcing phase, one series
/// per stop, from `(stop, phase, velocity)` points (thinned beyond
/// [`MAX_PLOT_POINTS`]); `radius(n)` sizes the dots for the `n` drawn.
pub fn impact_map(points: impl Iterator<Item = (usize, f64, f64)>, radius: impl Fn(usize) -> u32) -> Result<String, crate::PlotError> {
    let mut by_stop: Vec<Series> = Vec::new();
    for (k, phase, velocity) in points {
        while by_stop.len() <= k {
            by_stop.push(Series { label: format!("stop {}", by_stop.len()), points: vec![], reference: false, style: Style::default() });
        }
        by_stop[k].points.push((phase, velocity));
    }
    by_stop.retain(|s| !s.points.is_empty());
    let title = thin_series(&mut by_stop, "impact map: pre-impact velocity against forcing phase", "impacts");
    let chart = Chart { title: &title, x_label: "forcing phase (rad)", y_label: "pre-impact velocity", scale: Scale::Linear, size: (900, 600) };
    let n: usize = by_stop.iter().map(|s| s.points.len()).sum();
    scatter(&chart, &by_stop, radius(n))
}
