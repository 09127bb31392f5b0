//! What can go wrong when drawing a chart.

/// plotters' error, boxed: its type depends on the drawing backend.
pub(crate) type Boxed = Box<dyn std::error::Error + Send + Sync + 'static>;

/// A chart that could not be drawn.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// No point of any series can be drawn: every one has a non-finite
    /// coordinate (NaN, ±∞), or is ≤ 0 on a log axis, or the series are
    /// empty.
    #[error("nothing to plot: no finite points")]
    NothingToPlot {
        /// The chart's title.
        chart: String,
    },
    /// plotters failed while drawing (its error is the source).
    #[error("drawing \"{chart}\": {source}")]
    Drawing {
        /// The chart's title.
        chart: String,
        /// plotters' error.
        source: Boxed,
    },
    /// A panel given to [`crate::stack_vertically`] is not an SVG document
    /// with a size in pixels.
    #[error("panel {panel}: {problem}")]
    Panel {
        /// The panel's index (from 0).
        panel: usize,
        /// What is wrong with it.
        problem: PanelProblem,
    },
}

/// Why a panel cannot be stacked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PanelProblem {
    /// The text holds no `<svg` element.
    #[error("no <svg> element")]
    NoSvgElement,
    /// The `<svg` tag is never closed by `>`.
    #[error("an unclosed <svg> tag")]
    UnclosedTag,
    /// The `<svg>` tag has no `width` and `height` in pixels.
    #[error("no width and height in pixels")]
    NoPixelSize,
}
