//! # signorini-plot
//!
//! A log-log error curve of a second-order method against its reference
//! slope; the SVG comes back as text:
//!
//! ```
//! use signorini_plot::{line_chart, Chart, Scale, Series, Style};
//!
//! let hs = [0.1, 0.05, 0.025, 0.0125];
//! let error = Series { label: "P1 error".into(), points: hs.iter().map(|&h| (h, 0.3 * h * h)).collect(), reference: false, style: Style::default() };
//! let slope = Series { label: "slope 2".into(), points: vec![(0.1, 0.01), (0.0125, 0.01 / 64.0)], reference: true, style: Style::default() };
//! let chart = Chart { title: "convergence", x_label: "h", y_label: "error", scale: Scale::LogLog, size: (640, 400) };
//! let svg = line_chart(&chart, &[error, slope])?;
//! assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
//! assert!(svg.contains("convergence") && svg.contains("P1 error") && svg.contains("slope 2"));
//! // Log axes are labelled at decades when three or more fit (the errors':
//! // 10⁻⁴ to 10⁻²), else at 1, 2 and 5 × 10ᵏ (h's, which holds 10⁻¹ only).
//! let labels: Vec<&str> = svg.lines().map(str::trim).filter(|l| l.contains("10")).collect();
//! for label in ["10⁻⁴", "10⁻³", "10⁻²", "2×10⁻²", "5×10⁻²", "10⁻¹"] {
//!     assert!(labels.contains(&label), "no label {label} in {labels:?}");
//! }
//! assert!(!svg.contains("10⁻⁵") && !svg.contains("10⁰"));
//! // Nothing finite to draw (log axes skip points <= 0) is an error, not an empty chart.
//! let bad = Series { label: "x".into(), points: vec![(0.0, 1.0)], reference: false, style: Style::default() };
//! assert!(line_chart(&chart, &[bad]).is_err());
//! # Ok::<(), signorini_plot::PlotError>(())
//! ```
//!
//! SVG line charts of the outputs of signorini: time series (numerical
//! against exact) and log-log error curves. Returns the SVG as a `String`;
//! writing it is the caller's business.
//!
//! Line charts keep every series distinguishable: a series' colour comes
//! from its [`Style::group`] (a palette of twelve colours, the first seven
//! Okabe–Ito's colour-blind-safe set) and its marker and dash pattern from
//! its [`Style::variant`]. The legend sits to the right of the plotting
//! area, never over the data. Logarithmic axes are labelled at decades
//! (10⁻³, 10⁻², …), with unlabelled minor grid lines between them.
//!
//! Errors are a [`PlotError`]: nothing to plot, a panel that is not an
//! SVG document, or plotters' own drawing error (wrapped as the source).
//!
//! Architecture invariant: no IO, no numerics; depends only on plotters
//! and thiserror.

mod error;
mod thin;

pub use error::{PanelProblem, PlotError};
pub use thin::{impact_map, thin, thin_series, MAX_PLOT_POINTS};

use error::Boxed;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One curve.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points `(x, y)`; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
    /// Draw dashed-looking (thin, grey) — used for exact solutions.
    pub reference: bool,
    /// Colour and marker; the default picks the colour by position.
    pub style: Style,
}

/// How a series is drawn: its colour comes from `group`, its marker and
/// dash pattern from `variant`, so that series sharing a group (e.g. one
/// scheme) share a colour and differ by marker (e.g. the mass).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Style {
    /// Palette index; `None`: the series' position in the chart.
    pub group: Option<usize>,
    /// Marker and dash index; `None`: a solid line without markers.
    pub variant: Option<usize>,
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
    /// Size in pixels of the chart without its legend; the legend widens
    /// the canvas to the right (and lengthens it if it has many entries).
    pub size: (u32, u32),
}

/// Twelve colours: Okabe and Ito's seven colour-blind-safe colours (black
/// last), then five of Paul Tol's muted scheme.
const PALETTE: [RGBColor; 12] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(230, 159, 0),   // orange
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(0, 0, 0),       // black
    RGBColor(136, 34, 85),   // wine
    RGBColor(153, 153, 51),  // olive
    RGBColor(51, 34, 136),   // indigo
    RGBColor(68, 170, 153),  // teal
    RGBColor(140, 86, 75),   // brown
];

/// Colour of reference curves (exact solutions, stops).
const REFERENCE_GREY: RGBColor = RGBColor(90, 90, 90);

/// Marker shapes, in the order variants take them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Marker {
    Circle,
    HollowSquare,
    TriangleUp,
    HollowDiamond,
    Cross,
    HollowTriangleDown,
    Plus,
    Square,
}

const MARKERS: [Marker; 8] = [Marker::Circle, Marker::HollowSquare, Marker::TriangleUp, Marker::HollowDiamond, Marker::Cross, Marker::HollowTriangleDown, Marker::Plus, Marker::Square];

/// Line patterns, in the order variants take them: `(dash, gap)` in pixels.
const DASHES: [Option<(i32, i32)>; 4] = [None, Some((8, 4)), Some((2, 3)), Some((14, 4))];

/// Marker half-size in pixels.
const MARKER_R: i32 = 4;

/// How one series is drawn.
#[derive(Clone, Copy, Debug)]
struct Look {
    color: RGBColor,
    width: u32,
    marker: Option<Marker>,
    dash: Option<(i32, i32)>,
}

impl Look {
    /// The look of the `index`-th series of a chart.
    fn of(series: &Series, index: usize) -> Look {
        if series.reference {
            return Look { color: REFERENCE_GREY, width: 1, marker: None, dash: None };
        }
        let group = series.style.group.unwrap_or(index);
        let (marker, dash) = match series.style.variant {
            Some(v) => (Some(MARKERS[v % MARKERS.len()]), DASHES[v % DASHES.len()]),
            // Past the palette's length, position-styled series change dash.
            None => (None, DASHES[(index / PALETTE.len()) % DASHES.len()]),
        };
        Look { color: PALETTE[group % PALETTE.len()], width: 2, marker, dash }
    }

    fn line(&self) -> ShapeStyle {
        ShapeStyle { color: self.color.to_rgba(), filled: false, stroke_width: self.width }
    }
}

/// Draws `marker` centred on `at` in `area`'s coordinates.
fn draw_marker<DB: DrawingBackend, CT: CoordTranslate>(area: &DrawingArea<DB, CT>, at: CT::From, marker: Marker, color: RGBColor) -> Result<(), Boxed>
where
    CT::From: Clone,
    DB::ErrorType: 'static,
{
    let r = MARKER_R;
    let fill = color.filled();
    let stroke = ShapeStyle { color: color.to_rgba(), filled: false, stroke_width: 2 };
    let white = WHITE.filled();
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| -> Boxed { Box::new(e) };
    let hollow = |outline: Vec<(i32, i32)>| -> Result<(), Boxed> {
        area.draw(&(EmptyElement::at(at.clone()) + Polygon::new(outline.clone(), white))).map_err(e)?;
        let mut closed = outline;
        closed.push(closed[0]);
        area.draw(&(EmptyElement::at(at.clone()) + PathElement::new(closed, stroke))).map_err(e)
    };
    let strokes = |a: [(i32, i32); 2], b: [(i32, i32); 2]| -> Result<(), Boxed> {
        area.draw(&(EmptyElement::at(at.clone()) + PathElement::new(a.to_vec(), stroke) + PathElement::new(b.to_vec(), stroke))).map_err(e)
    };
    match marker {
        Marker::Circle => area.draw(&(EmptyElement::at(at.clone()) + Circle::new((0, 0), r, fill))).map_err(e),
        Marker::Square => area.draw(&(EmptyElement::at(at.clone()) + Rectangle::new([(-r, -r), (r, r)], fill))).map_err(e),
        Marker::TriangleUp => area.draw(&(EmptyElement::at(at.clone()) + Polygon::new(vec![(0, -r - 1), (r + 1, r), (-r - 1, r)], fill))).map_err(e),
        Marker::HollowSquare => hollow(vec![(-r, -r), (r, -r), (r, r), (-r, r)]),
        Marker::HollowDiamond => hollow(vec![(0, -r - 1), (r + 1, 0), (0, r + 1), (-r - 1, 0)]),
        Marker::HollowTriangleDown => hollow(vec![(0, r + 1), (r + 1, -r), (-r - 1, -r)]),
        Marker::Cross => strokes([(-r, -r), (r, r)], [(-r, r), (r, -r)]),
        Marker::Plus => strokes([(-r - 1, 0), (r + 1, 0)], [(0, -r - 1), (0, r + 1)]),
    }
}

/// Tick positions of a logarithmic axis over `[lo, hi]` (`0 < lo < hi`):
/// labelled (major) and unlabelled (minor) values.
#[derive(Clone, Debug, PartialEq)]
struct LogTicks {
    major: Vec<f64>,
    minor: Vec<f64>,
}

/// At most this many labelled decades on one axis.
const MAX_DECADE_LABELS: usize = 9;

/// Decade ticks over `[lo, hi]`; when fewer than three decades fit, the
/// 1-2-5 values, then every integer mantissa; every tenth of the range
/// (in log) as a last resort.
fn log_ticks(lo: f64, hi: f64) -> LogTicks {
    let inside = |v: &f64| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9);
    let (k0, k1) = ((lo.log10() - 1e-9).floor() as i32, (hi.log10() + 1e-9).ceil() as i32);
    let with = |mantissas: &[f64]| -> Vec<f64> { (k0..=k1).flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k))).filter(inside).collect() };
    let decades = with(&[1.0]);
    if decades.len() >= 3 {
        let step = decades.len().div_ceil(MAX_DECADE_LABELS);
        let (major, skipped): (Vec<_>, Vec<_>) = decades.iter().copied().enumerate().partition(|(i, _)| i % step == 0);
        let mut minor: Vec<f64> = skipped.into_iter().map(|(_, v)| v).collect();
        if step == 1 {
            minor.extend(with(&[2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]));
        }
        return LogTicks { major: major.into_iter().map(|(_, v)| v).collect(), minor };
    }
    for (labelled, rest) in [(&[1.0, 2.0, 5.0][..], &[3.0, 4.0, 6.0, 7.0, 8.0, 9.0][..]), (&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0][..], &[][..])] {
        let major = with(labelled);
        if major.len() >= 3 {
            return LogTicks { major, minor: with(rest) };
        }
    }
    let ratio = hi / lo;
    LogTicks { major: (0..=4).map(|i| lo * ratio.powf(i as f64 / 4.0)).collect(), minor: vec![] }
}

/// `10⁻³`, `2×10⁻³`, `1.37×10⁻³`: a positive tick value in scientific
/// notation with a superscript exponent.
fn format_log_tick(v: f64) -> String {
    let mut k = v.log10().floor() as i32;
    let mut m = v / 10f64.powi(k);
    if m >= 9.9995 {
        m /= 10.0;
        k += 1;
    }
    let sup: String = k
        .to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            d => ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'][d.to_digit(10).unwrap_or(0) as usize],
        })
        .collect();
    if (m - 1.0).abs() < 5e-4 {
        format!("10{sup}")
    } else if (m - m.round()).abs() < 5e-4 {
        format!("{}×10{sup}", m.round())
    } else {
        let mantissa = format!("{m:.2}");
        format!("{}×10{sup}", mantissa.trim_end_matches('0').trim_end_matches('.'))
    }
}

/// A tick label of a linear axis: plotters' own format (`0.5`, `-1.25`,
/// `3.0`), but a value that rounds to zero is `0.0` and never `-0.0` (a
/// tick at `-1e-17`, a sum of steps that misses 0 by round-off, or −0).
#[doc(hidden)]
pub fn format_linear_tick(v: f64) -> String {
    use plotters::coord::ranged1d::ValueFormatter;
    let s = <plotters::coord::types::RangedCoordf64 as ValueFormatter<f64>>::format(&v);
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// Legend text size (plotters' units) and the layout of an entry.
const LEGEND_FONT: u32 = 15;
const LEGEND_ROW: i32 = 20;
const LEGEND_SAMPLE: i32 = 34;
const LEGEND_PAD: i32 = 12;
/// A generous width per character of the legend font, in pixels.
const LEGEND_CHAR_W: i32 = 8;

/// Width in pixels of the legend column for these labels.
fn legend_width(series: &[Series]) -> u32 {
    let chars = series.iter().map(|s| s.label.chars().count()).max().unwrap_or(0) as i32;
    (2 * LEGEND_PAD + LEGEND_SAMPLE + 8 + LEGEND_CHAR_W * chars + LEGEND_PAD) as u32
}

/// Draws the legend in `area`, a column right of the plot, its first entry
/// at height `top` (pixels from the column's top).
fn draw_legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, series: &[Series], top: i32) -> Result<(), Boxed>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| -> Boxed { Box::new(e) };
    let (w, _) = area.dim_in_pixel();
    let x0 = LEGEND_PAD;
    let bottom = top + LEGEND_ROW * series.len() as i32 + 4;
    area.draw(&Rectangle::new([(x0 - 6, top - 4), (w as i32 - 4, bottom)], ShapeStyle { color: RGBColor(160, 160, 160).to_rgba(), filled: false, stroke_width: 1 })).map_err(e)?;
    let font = TextStyle::from(("sans-serif", LEGEND_FONT).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, s) in series.iter().enumerate() {
        let look = Look::of(s, i);
        let y = top + LEGEND_ROW * i as i32 + LEGEND_ROW / 2;
        let sample = vec![(x0, y), (x0 + LEGEND_SAMPLE, y)];
        match look.dash {
            None => area.draw(&PathElement::new(sample, look.line())).map_err(e)?,
            Some((dash, gap)) => area.draw(&DashedPathElement::new(sample, dash, gap, look.line())).map_err(e)?,
        }
        if let Some(m) = look.marker {
            draw_marker(area, (x0 + LEGEND_SAMPLE / 2, y), m, look.color)?;
        }
        area.draw(&Text::new(s.label.clone(), (x0 + LEGEND_SAMPLE + 8, y), font.clone())).map_err(e)?;
    }
    Ok(())
}

/// Renders the series as an SVG document: the chart of `chart.size` and,
/// to its right, the legend. Errors only if no point can be drawn
/// ([`PlotError::NothingToPlot`]) or plotters fails ([`PlotError::Drawing`]).
pub fn line_chart(chart: &Chart<'_>, series: &[Series]) -> Result<String, PlotError> {
    line_chart_over(chart, series, &[], 1)
}

/// [`line_chart`] drawn over `dots`, each of their points a dot of radius
/// `radius` pixels as in [`scatter`] (a continuation's branch over a
/// sweep's bifurcation diagram); the dots' series join the legend.
pub fn line_chart_over(chart: &Chart<'_>, series: &[Series], dots: &[Series], radius: u32) -> Result<String, PlotError> {
    let keep = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && (chart.scale == Scale::Linear || (p.0 > 0.0 && p.1 > 0.0));
    let all: Vec<(f64, f64)> = series.iter().chain(dots).flat_map(|s| s.points.iter().copied().filter(keep)).collect();
    if all.is_empty() {
        return Err(PlotError::NothingToPlot { chart: chart.title.to_string() });
    }
    let (mut x0, mut x1, mut y0, mut y1) = all.iter().fold((f64::MAX, f64::MIN, f64::MAX, f64::MIN), |(a, b, c, d), p| (a.min(p.0), b.max(p.0), c.min(p.1), d.max(p.1)));
    if chart.scale == Scale::Linear {
        if x1 <= x0 {
            x1 = x0 + 1.0;
        }
        if y1 <= y0 {
            let pad = if y0 == 0.0 { 1.0 } else { 0.1 * y0.abs() };
            y0 -= pad;
            y1 += pad;
        }
        let pad = 0.05 * (y1 - y0);
        y0 -= pad;
        y1 += pad;
    } else {
        x0 /= 1.2;
        x1 *= 1.2;
        y0 /= 1.5;
        y1 *= 1.5;
    }
    let dot_series: Vec<Series> = dots.iter().map(|s| Series { style: Style { variant: Some(0), ..s.style }, ..s.clone() }).collect();
    let legend_entries: Vec<Series> = dot_series.iter().cloned().chain(series.iter().cloned()).collect();
    let legend_w = legend_width(&legend_entries);
    let title_h = 36;
    let legend_h = title_h + 12 + LEGEND_ROW * legend_entries.len() as i32 + 16;
    let size = (chart.size.0 + legend_w, chart.size.1.max(legend_h as u32));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let err = |source: Boxed| PlotError::Drawing { chart: chart.title.to_string(), source };
        root.fill(&WHITE).map_err(|e| err(e.into()))?;
        let body = root.titled(chart.title, ("sans-serif", 20)).map_err(|e| err(e.into()))?;
        let (plot, legend) = body.split_horizontally(chart.size.0);
        let mut b = ChartBuilder::on(&plot);
        b.margin(12).x_label_area_size(40).y_label_area_size(80);
        let label_font = ("sans-serif", 15);
        let log_label = |v: &f64| format_log_tick(*v);
        let linear_label = |v: &f64| format_linear_tick(*v);
        macro_rules! draw {
            ($ctx:expr, $log:expr) => {{
                let mut ctx = $ctx;
                let mut mesh = ctx.configure_mesh();
                mesh.x_desc(chart.x_label).y_desc(chart.y_label).label_style(label_font).axis_desc_style(label_font).light_line_style(RGBColor(235, 235, 235));
                if $log {
                    mesh.x_label_formatter(&log_label).y_label_formatter(&log_label);
                } else {
                    mesh.x_label_formatter(&linear_label).y_label_formatter(&linear_label);
                }
                mesh.draw().map_err(|e| err(e.into()))?;
                for (i, s) in dots.iter().enumerate() {
                    let color = Look::of(s, i).color;
                    ctx.draw_series(s.points.iter().copied().filter(keep).map(|p| Circle::new(p, radius, color.filled()))).map_err(|e| err(e.into()))?;
                }
                for (i, s) in series.iter().enumerate() {
                    let look = Look::of(s, i + dots.len());
                    let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(keep).collect();
                    match look.dash {
                        None => ctx.draw_series(LineSeries::new(pts.iter().copied(), look.line())).map(|_| ()),
                        Some((dash, gap)) => ctx.draw_series(DashedLineSeries::new(pts.iter().copied(), dash, gap, look.line())).map(|_| ()),
                    }
                    .map_err(|e| err(e.into()))?;
                    if let Some(m) = look.marker {
                        for p in &pts {
                            draw_marker(ctx.plotting_area(), *p, m, look.color).map_err(err)?;
                        }
                    }
                }
                let top = ctx.plotting_area().get_pixel_range().1.start - legend.get_base_pixel().1;
                draw_legend(&legend, &legend_entries, top.max(0)).map_err(err)?;
            }};
        }
        match chart.scale {
            Scale::Linear => draw!(b.build_cartesian_2d(x0..x1, y0..y1).map_err(|e| err(e.into()))?, false),
            Scale::LogLog => {
                let (tx, ty) = (log_ticks(x0, x1), log_ticks(y0, y1));
                let xs = (x0..x1).log_scale().with_key_points(tx.major).with_light_points(tx.minor);
                let ys = (y0..y1).log_scale().with_key_points(ty.major).with_light_points(ty.minor);
                draw!(b.build_cartesian_2d(xs, ys).map_err(|e| err(e.into()))?, true)
            }
        }
        root.present().map_err(|e| err(e.into()))?;
    }
    Ok(svg)
}

/// Stacks whole SVG documents (as [`line_chart`] returns them) top to
/// bottom in one document: one panel per chart, each at its own size, the
/// document as wide as the widest. Errors ([`PlotError::Panel`]) if a
/// document has no root `<svg` element with a `width` and a `height` in pixels.
pub fn stack_vertically(panels: &[String]) -> Result<String, PlotError> {
    let attr = |tag: &str, name: &str| -> Option<u32> {
        let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
        tag[at..].split('"').next()?.trim_end_matches("px").parse().ok()
    };
    let mut body = String::new();
    let (mut width, mut height) = (0u32, 0u32);
    for (i, svg) in panels.iter().enumerate() {
        let start = svg.find("<svg").ok_or(PlotError::Panel { panel: i, problem: PanelProblem::NoSvgElement })?;
        let end = start + svg[start..].find('>').ok_or(PlotError::Panel { panel: i, problem: PanelProblem::UnclosedTag })?;
        let tag = &svg[start..end];
        let (w, h) = attr(tag, "width").zip(attr(tag, "height")).ok_or(PlotError::Panel { panel: i, problem: PanelProblem::NoPixelSize })?;
        body.push_str(&format!("<svg x=\"0\" y=\"{height}\"{}", &svg[start + 4..]));
        body.push('\n');
        width = width.max(w);
        height += h;
    }
    Ok(format!("<svg width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\" xmlns=\"http://www.w3.org/2000/svg\">\n{body}</svg>\n"))
}

/// A scatter chart (bifurcation diagrams, impact maps): every point of
/// every series a dot of radius `radius` pixels (1 for diagrams of 10⁵
/// points), no lines, linear axes, a legend when there is more than one
/// series. A large diagram stays a few MB: one `<circle>` per point. Errors
/// only if no point is finite ([`PlotError::NothingToPlot`]) or plotters
/// fails ([`PlotError::Drawing`]).
pub fn scatter(chart: &Chart<'_>, series: &[Series], radius: u32) -> Result<String, PlotError> {
    let keep = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.points.iter().copied().filter(keep)).collect();
    if all.is_empty() {
        return Err(PlotError::NothingToPlot { chart: chart.title.to_string() });
    }
    let (mut x0, mut x1, mut y0, mut y1) = all.iter().fold((f64::MAX, f64::MIN, f64::MAX, f64::MIN), |(a, b, c, d), p| (a.min(p.0), b.max(p.0), c.min(p.1), d.max(p.1)));
    let widen = |lo: &mut f64, hi: &mut f64| {
        if *hi <= *lo {
            let pad = if *lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
            *lo -= pad;
            *hi += pad;
        }
        let pad = 0.03 * (*hi - *lo);
        *lo -= pad;
        *hi += pad;
    };
    widen(&mut x0, &mut x1);
    widen(&mut y0, &mut y1);
    let legend = series.len() > 1;
    let legend_w = if legend { legend_width(series) } else { 0 };
    let title_h = 36;
    let legend_h = title_h + 12 + LEGEND_ROW * series.len() as i32 + 16;
    let size = (chart.size.0 + legend_w, chart.size.1.max(if legend { legend_h as u32 } else { 0 }));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let err = |source: Boxed| PlotError::Drawing { chart: chart.title.to_string(), source };
        root.fill(&WHITE).map_err(|e| err(e.into()))?;
        let body = root.titled(chart.title, ("sans-serif", 20)).map_err(|e| err(e.into()))?;
        let (plot, legend_area) = body.split_horizontally(chart.size.0);
        let mut ctx = ChartBuilder::on(&plot).margin(12).x_label_area_size(40).y_label_area_size(80).build_cartesian_2d(x0..x1, y0..y1).map_err(|e| err(e.into()))?;
        let label_font = ("sans-serif", 15);
        let linear_label = |v: &f64| format_linear_tick(*v);
        ctx.configure_mesh()
            .x_desc(chart.x_label)
            .y_desc(chart.y_label)
            .label_style(label_font)
            .axis_desc_style(label_font)
            .light_line_style(RGBColor(235, 235, 235))
            .x_label_formatter(&linear_label)
            .y_label_formatter(&linear_label)
            .draw()
            .map_err(|e| err(e.into()))?;
        for (i, s) in series.iter().enumerate() {
            let color = Look::of(s, i).color;
            ctx.draw_series(s.points.iter().copied().filter(keep).map(|p| Circle::new(p, radius, color.filled()))).map_err(|e| err(e.into()))?;
        }
        if legend {
            let top = ctx.plotting_area().get_pixel_range().1.start - legend_area.get_base_pixel().1;
            let dots: Vec<Series> = series.iter().map(|s| Series { style: Style { variant: Some(0), ..s.style }, ..s.clone() }).collect();
            draw_legend(&legend_area, &dots, top.max(0)).map_err(err)?;
        }
        root.present().map_err(|e| err(e.into()))?;
    }
    Ok(svg)
}

/// A heat map: `values[row][col]` drawn as coloured cells (blue = low,
/// red = high, on a log10 scale when `log` is set; grey = NaN, black = +∞
/// meaning "blew up"), with row and column labels. Errors only if plotters
/// fails ([`PlotError::Drawing`]).
pub fn heat_map(title: &str, rows: &[String], cols: &[String], values: &[Vec<f64>], log: bool, size: (u32, u32)) -> Result<String, PlotError> {
    let tr = |v: f64| if log { v.abs().max(1e-300).log10() } else { v };
    let finite: Vec<f64> = values.iter().flatten().copied().filter(|v| v.is_finite()).map(tr).collect();
    let (lo, hi) = finite.iter().fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    let (lo, hi) = if finite.is_empty() {
        (0.0, 1.0)
    } else if hi > lo {
        (lo, hi)
    } else {
        (lo - 1.0, hi + 1.0)
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let err = |source: Boxed| PlotError::Drawing { chart: title.to_string(), source };
        root.fill(&WHITE).map_err(|e| err(e.into()))?;
        let (nr, nc) = (rows.len(), cols.len());
        // Segmented axes put one label at the centre of each cell.
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(160)
            .build_cartesian_2d((0..nc).into_segmented(), (0..nr).into_segmented())
            .map_err(|e| err(e.into()))?;
        let label = |names: &[String], v: &SegmentValue<usize>| match v {
            SegmentValue::CenterOf(i) => names.get(*i).cloned().unwrap_or_default(),
            _ => String::new(),
        };
        chart.configure_mesh().disable_mesh().x_labels(nc).y_labels(nr).x_label_formatter(&|v| label(cols, v)).y_label_formatter(&|v| label(rows, v)).draw().map_err(|e| err(e.into()))?;
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
                chart.draw_series(std::iter::once(Rectangle::new(corners, color.filled()))).map_err(|e| err(e.into()))?;
            }
        }
        root.present().map_err(|e| err(e.into()))?;
    }
    Ok(svg)
}

/// One category of a [`category_map`]: its legend name and colour (`None`:
/// the palette's colour of its index).
#[derive(Clone, Debug, PartialEq)]
pub struct Category {
    /// Legend name.
    pub name: String,
    /// Colour `(r, g, b)`; `None` picks the palette's.
    pub color: Option<(u8, u8, u8)>,
}

/// A map of categories over a regular grid (a basin of attraction):
/// `cells[j][i]` is the category index (into `categories`) of the cell
/// centred at `(x_i, y_j)`, the `x_i` evenly spaced over `x` and the `y_j`
/// over `y` (`None`: left white). Runs of equal cells along a row are drawn
/// as one rectangle; the legend lists the categories. Errors only if
/// plotters fails ([`PlotError::Drawing`]) or there is nothing to draw.
pub fn category_map(chart: &Chart, x: (f64, f64), y: (f64, f64), cells: &[Vec<Option<usize>>], categories: &[Category]) -> Result<String, PlotError> {
    let (ny, nx) = (cells.len(), cells.iter().map(Vec::len).max().unwrap_or(0));
    if nx == 0 {
        return Err(PlotError::NothingToPlot { chart: chart.title.to_string() });
    }
    let step = |(a, b): (f64, f64), n: usize| if n > 1 && b != a { (b - a) / (n - 1) as f64 } else { 1.0 };
    let (dx, dy) = (step(x, nx), step(y, ny));
    let span = |a: f64, d: f64, n: usize| {
        let (lo, hi) = (a.min(a + d * (n as f64 - 1.0)), a.max(a + d * (n as f64 - 1.0)));
        (lo - 0.5 * d.abs(), hi + 0.5 * d.abs())
    };
    let (xs, ys) = (span(x.0, dx, nx), span(y.0, dy, ny));
    let color = |k: usize| match categories.get(k).and_then(|c| c.color) {
        Some((r, g, b)) => RGBColor(r, g, b),
        None => PALETTE[k % PALETTE.len()],
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, chart.size).into_drawing_area();
        let err = |source: Boxed| PlotError::Drawing { chart: chart.title.to_string(), source };
        root.fill(&WHITE).map_err(|e| err(e.into()))?;
        let legend_w = 220u32.min(chart.size.0 / 3);
        let (plot_area, legend_area) = root.split_horizontally(chart.size.0 - legend_w);
        let mut ctx = ChartBuilder::on(&plot_area)
            .caption(chart.title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(xs.0..xs.1, ys.0..ys.1)
            .map_err(|e| err(e.into()))?;
        ctx.configure_mesh().disable_mesh().x_desc(chart.x_label).y_desc(chart.y_label).draw().map_err(|e| err(e.into()))?;
        for (j, row) in cells.iter().enumerate() {
            let yc = y.0 + dy * j as f64;
            let mut i = 0;
            while i < row.len() {
                let mut e = i;
                while e + 1 < row.len() && row[e + 1] == row[i] {
                    e += 1;
                }
                if let Some(k) = row[i] {
                    let (x0, x1) = (x.0 + dx * (i as f64 - 0.5), x.0 + dx * (e as f64 + 0.5));
                    let corners = [(x0, yc - 0.5 * dy), (x1, yc + 0.5 * dy)];
                    ctx.draw_series(std::iter::once(Rectangle::new(corners, color(k).filled()))).map_err(|e| err(e.into()))?;
                }
                i = e + 1;
            }
        }
        let e = |e: DrawingAreaErrorKind<std::io::Error>| err(Box::new(e));
        for (k, c) in categories.iter().enumerate() {
            let top = 40 + LEGEND_ROW * k as i32;
            legend_area.draw(&Rectangle::new([(8, top), (22, top + 14)], color(k).filled())).map_err(e)?;
            legend_area.draw(&Text::new(c.name.clone(), (28, top), ("sans-serif", 13).into_font())).map_err(e)?;
        }
        root.present().map_err(|e| err(e.into()))?;
    }
    Ok(svg)
}
