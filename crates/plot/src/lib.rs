//! # signorini-plot
//!
//! SVG line charts of the outputs of signorini: time series (numerical
//! against exact) and log-log error curves. Returns the SVG as a `String`;
//! writing it is the caller's business.
//!
//! Architecture invariant: no IO, no numerics; depends only on plotters.

use plotters::prelude::*;

/// One curve.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points `(x, y)`; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
    /// Draw dashed-looking (thin, grey) — used for exact solutions.
    pub reference: bool,
}

/// Axis scaling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Linear axes.
    Linear,
    /// Both axes logarithmic (points with non-positive coordinates are skipped).
    LogLog,
}

/// A chart's texts and size.
#[derive(Clone, Debug)]
pub struct Chart<'a> {
    /// Title.
    pub title: &'a str,
    /// x-axis label.
    pub x_label: &'a str,
    /// y-axis label.
    pub y_label: &'a str,
    /// Axes.
    pub scale: Scale,
    /// Size in pixels.
    pub size: (u32, u32),
}

const COLORS: [RGBColor; 6] = [RGBColor(31, 119, 180), RGBColor(214, 39, 40), RGBColor(44, 160, 44), RGBColor(148, 103, 189), RGBColor(255, 127, 14), RGBColor(140, 86, 75)];

/// Renders the series as an SVG document. Errors only if plotters fails
/// (reported as text).
pub fn line_chart(chart: &Chart<'_>, series: &[Series]) -> Result<String, String> {
    let keep = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && (chart.scale == Scale::Linear || (p.0 > 0.0 && p.1 > 0.0));
    let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.points.iter().copied().filter(keep)).collect();
    if all.is_empty() {
        return Err("nothing to plot: no finite points".into());
    }
    let (mut x0, mut x1, mut y0, mut y1) = all.iter().fold((f64::MAX, f64::MIN, f64::MAX, f64::MIN), |(a, b, c, d), p| (a.min(p.0), b.max(p.0), c.min(p.1), d.max(p.1)));
    if x1 <= x0 {
        x1 = x0 + 1.0;
    }
    if y1 <= y0 {
        let pad = if y0 == 0.0 { 1.0 } else { 0.1 * y0.abs() };
        y0 -= pad;
        y1 += pad;
    }
    if chart.scale == Scale::Linear {
        let pad = 0.05 * (y1 - y0);
        y0 -= pad;
        y1 += pad;
    } else {
        x0 /= 1.2;
        x1 *= 1.2;
        y0 /= 1.5;
        y1 *= 1.5;
    }
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, chart.size).into_drawing_area();
        let err = |e: &dyn std::fmt::Display| e.to_string();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let mut b = ChartBuilder::on(&root);
        b.caption(chart.title, ("sans-serif", 20)).margin(12).x_label_area_size(40).y_label_area_size(70);
        macro_rules! draw {
            ($ctx:expr) => {{
                let mut ctx = $ctx;
                ctx.configure_mesh().x_desc(chart.x_label).y_desc(chart.y_label).draw().map_err(|e| err(&e))?;
                for (i, s) in series.iter().enumerate() {
                    let color = if s.reference { RGBColor(90, 90, 90) } else { COLORS[i % COLORS.len()] };
                    let style = ShapeStyle { color: color.to_rgba(), filled: false, stroke_width: if s.reference { 1 } else { 2 } };
                    let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(keep).collect();
                    ctx.draw_series(LineSeries::new(pts, style))
                        .map_err(|e| err(&e))?
                        .label(s.label.clone())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
                }
                ctx.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(|e| err(&e))?;
            }};
        }
        match chart.scale {
            Scale::Linear => draw!(b.build_cartesian_2d(x0..x1, y0..y1).map_err(|e| err(&e))?),
            Scale::LogLog => draw!(b.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale()).map_err(|e| err(&e))?),
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

/// A heat map: `values[row][col]` drawn as coloured cells (blue = low,
/// red = high, on a log10 scale when `log` is set; grey = NaN, black = +∞
/// meaning "blew up"), with row and column labels.
pub fn heat_map(title: &str, rows: &[String], cols: &[String], values: &[Vec<f64>], log: bool, size: (u32, u32)) -> Result<String, String> {
    let tr = |v: f64| if log { v.abs().max(1e-300).log10() } else { v };
    let finite: Vec<f64> = values.iter().flatten().copied().filter(|v| v.is_finite()).map(tr).collect();
    let (lo, hi) = finite.iter().fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    let (lo, hi) = if finite.is_empty() { (0.0, 1.0) } else if hi > lo { (lo, hi) } else { (lo - 1.0, hi + 1.0) };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let err = |e: &dyn std::fmt::Display| e.to_string();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let (nr, nc) = (rows.len(), cols.len());
        // Segmented axes put one label at the centre of each cell.
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(160)
            .build_cartesian_2d((0..nc).into_segmented(), (0..nr).into_segmented())
            .map_err(|e| err(&e))?;
        let label = |names: &[String], v: &SegmentValue<usize>| match v {
            SegmentValue::CenterOf(i) => names.get(*i).cloned().unwrap_or_default(),
            _ => String::new(),
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(nc)
            .y_labels(nr)
            .x_label_formatter(&|v| label(cols, v))
            .y_label_formatter(&|v| label(rows, v))
            .draw()
            .map_err(|e| err(&e))?;
        for (r, row) in values.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                let color = if v.is_nan() {
                    RGBColor(180, 180, 180)
                } else if v.is_infinite() {
                    RGBColor(0, 0, 0)
                } else {
                    let s = ((tr(*v) - lo) / (hi - lo)).clamp(0.0, 1.0);
                    RGBColor((255.0 * s) as u8, (80.0 * (1.0 - (2.0 * s - 1.0).abs())) as u8, (255.0 * (1.0 - s)) as u8)
                };
                let corners = [(SegmentValue::Exact(c), SegmentValue::Exact(r)), (SegmentValue::Exact(c + 1), SegmentValue::Exact(r + 1))];
                chart.draw_series(std::iter::once(Rectangle::new(corners, color.filled()))).map_err(|e| err(&e))?;
            }
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_svg_with_legend_and_skips_bad_points() {
        let s = vec![
            Series { label: "numerical".into(), points: vec![(0.0, 0.5), (1.0, f64::NAN), (2.0, -0.1)], reference: false },
            Series { label: "exact".into(), points: vec![(0.0, 0.5), (2.0, 0.0)], reference: true },
        ];
        let c = Chart { title: "u(0,t)", x_label: "t", y_label: "u", scale: Scale::Linear, size: (640, 400) };
        let svg = line_chart(&c, &s).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("numerical") && svg.contains("exact") && svg.contains("u(0,t)"));
        let log = Chart { scale: Scale::LogLog, ..c };
        let curve = Series { label: "error".into(), points: vec![(0.1, 1e-2), (0.05, 5e-3), (0.0, 1.0)], reference: false };
        assert!(line_chart(&log, &[curve]).unwrap().contains("error"));
        // Every point invalid on log axes: an error, not a panic.
        assert!(line_chart(&log, &[Series { label: "x".into(), points: vec![(0.0, -1.0)], reference: false }]).is_err());
    }
}
