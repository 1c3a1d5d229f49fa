//! Log-log plots (work-precision diagrams): panels of curves with a dot at every
//! measured point, drawn by the figure renderer ([`super::figure`]).

use std::path::Path;

use super::figure::{render, Axis, Figure, Panel as FigPanel, Style, Trace, PALETTE};
use super::ReportError;

/// One curve: label and (x, y) points, both positive.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points, both positive (log axes).
    pub points: Vec<(f64, f64)>,
}

/// One panel of a figure.
pub struct Panel {
    /// Panel title.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
}

/// Draws panels side by side in a grid (log-log axes) into a PNG or SVG file.
pub fn loglog_panels(path: &Path, panels: &[Panel], cols: usize) -> Result<(), ReportError> {
    let panels = panels
        .iter()
        .map(|p| FigPanel {
            title: p.title.clone(),
            x: Axis::log(format!("{} (log scale)", p.x_label)),
            y: Axis::log(format!("{} (log scale)", p.y_label)),
            traces: p
                .series
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    Trace::new(
                        s.label.clone(),
                        s.points.clone(),
                        Style::line_dots(PALETTE[i % PALETTE.len()]),
                    )
                })
                .collect(),
        })
        .collect();
    let mut fig = Figure::new(panels, cols);
    fig.panel_height = if cols >= 3 { 560 } else { 640 };
    render(path, &fig).map(|_| ())
}
