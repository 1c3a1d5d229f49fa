//! Figures as PNG or SVG files: panels of traces, and where the renderer put them
//! (the [`PanelLayout`] a test reads the picture back against).
//!
//! This first version draws through the existing plotters line-panel code
//! ([`super::lineplot::draw_panels`]) unchanged, so that the figure test can be run
//! against it.

use std::path::Path;

use super::lineplot::{draw_panels_layout, Line, LinePanel};
use super::ReportError;

/// An RGB colour.
pub type Rgb = [u8; 3];

/// A whole figure: panels in a grid.
pub struct Figure {
    /// Width of the picture [px].
    pub width: u32,
    /// Panels per row.
    pub cols: usize,
    /// The panels, row by row.
    pub panels: Vec<Panel>,
}

/// One panel: axes and traces.
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// The traces.
    pub traces: Vec<Trace>,
}

/// One trace: label and (x, y) points in drawing order.
pub struct Trace {
    /// Legend label.
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
}

/// A linear axis as drawn: value `lo` at pixel `px_lo`, `hi` at `px_hi`.
#[derive(Clone, Debug)]
pub struct AxisMap {
    /// Lower end of the axis range.
    pub lo: f64,
    /// Upper end of the axis range.
    pub hi: f64,
    /// Pixel coordinate of `lo`.
    pub px_lo: f64,
    /// Pixel coordinate of `hi`.
    pub px_hi: f64,
}

impl AxisMap {
    /// The pixel coordinate of value `v`.
    pub fn px(&self, v: f64) -> f64 {
        self.px_lo + (v - self.lo) / (self.hi - self.lo) * (self.px_hi - self.px_lo)
    }
}

/// Where one panel was drawn.
#[derive(Clone, Debug)]
pub struct PanelLayout {
    /// The plot area: pixels with x0 <= x < x1 and y0 <= y < y1.
    pub plot: [i32; 4],
    /// The x axis.
    pub x: AxisMap,
    /// The y axis.
    pub y: AxisMap,
    /// The x tick labels, as drawn.
    pub x_ticks: Vec<String>,
    /// The y tick labels, as drawn.
    pub y_ticks: Vec<String>,
    /// Height of a digit of the tick labels [px].
    pub tick_digit_px: f64,
    /// The colour of each trace.
    pub colours: Vec<Rgb>,
    /// The legend's box when it is drawn outside the plot area (x0, y0, x1, y1).
    pub legend: Option<[i32; 4]>,
}

/// Draws `fig` into `path` (PNG, or SVG by extension); returns where each panel went.
pub fn render(path: &Path, fig: &Figure) -> Result<Vec<PanelLayout>, ReportError> {
    let panels: Vec<LinePanel> = fig
        .panels
        .iter()
        .map(|p| LinePanel {
            title: p.title.clone(),
            x_label: p.x_label.clone(),
            y_label: p.y_label.clone(),
            lines: p
                .traces
                .iter()
                .map(|t| Line {
                    label: t.label.clone(),
                    points: t.points.clone(),
                })
                .collect(),
        })
        .collect();
    let cols = fig.cols.max(1);
    let rows = panels.len().div_ceil(cols);
    let height = (fig.width as f64 / (560.0 * cols as f64) * 360.0) as u32 * rows as u32;
    draw_panels_layout(path, &panels, cols, (fig.width, height))
}
