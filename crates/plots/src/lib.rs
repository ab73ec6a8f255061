//! Small SVG charts for reports: line and marker series on linear or log₁₀ axes, with ticks,
//! labels, a title and a legend — what a work-precision diagram or an error-against-time plot
//! needs, without a font or drawing dependency.
//!
//! ```
//! use rsts_plots::{Chart, Scale, Series, Style};
//! let chart = Chart {
//!     title: "Work–precision".into(),
//!     x_label: "max error".into(),
//!     y_label: "seconds".into(),
//!     x_scale: Scale::Log10,
//!     y_scale: Scale::Log10,
//!     series: vec![Series::new("dop853", vec![(1e-6, 1e-3), (1e-9, 3e-3)], Style::LineMarkers)],
//!     ..Chart::default()
//! };
//! let svg = rsts_plots::render_svg(&chart).unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```

mod axis;
mod labels;
mod render;
#[cfg(test)]
mod tests;

pub use render::render_svg;

/// Axis scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Scale {
    #[default]
    Linear,
    Log10,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Style {
    #[default]
    Line,
    Markers,
    LineMarkers,
}

/// One named series of (x, y) points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// CSS colour; `None` takes the next colour of the palette.
    pub color: Option<String>,
    /// Dashed line (e.g. for a peer's series).
    pub dashed: bool,
    /// A short text beside each point (e.g. the tolerance it was run at); empty: none.
    pub point_labels: Vec<String>,
    /// A shaded band in the series' colour, drawn under it: pairs (one edge, other edge) of
    /// points, the area between the two edges (e.g. the 5 % and 95 % percentiles); empty: none.
    pub band: Vec<((f64, f64), (f64, f64))>,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Self {
            label: label.into(),
            points,
            style,
            color: None,
            dashed: false,
            point_labels: Vec::new(),
            band: Vec::new(),
        }
    }

    /// The same series with `labels[k]` written beside point k.
    pub fn with_point_labels(mut self, labels: Vec<String>) -> Self {
        self.point_labels = labels;
        self
    }
}

/// A chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    /// The title above the frame; a second line after `\n` is a subtitle in smaller type.
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    pub series: Vec<Series>,
    pub width: u32,
    pub height: u32,
}

impl Chart {
    /// A log–log chart of the reports' size (820×540): work–precision, tolerance
    /// proportionality, observed order.
    pub fn log_log(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        series: Vec<Series>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_scale: Scale::Log10,
            y_scale: Scale::Log10,
            series,
            width: 820,
            height: 540,
        }
    }
}

impl Default for Chart {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: Vec::new(),
            width: 760,
            height: 480,
        }
    }
}

/// Why a chart cannot be drawn.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PlotError {
    #[error("nothing to plot: no finite point (positive on log axes) in any series")]
    Empty,
    #[error("chart size {0}×{1} is too small")]
    TooSmall(u32, u32),
}

/// Colour-blind-friendly palette (Okabe–Ito, then greys).
pub const PALETTE: [&str; 8] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#999999",
];
