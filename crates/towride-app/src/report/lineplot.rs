//! Linear-axis line plots (time histories, profiles): panels of labelled curves drawn by
//! the figure renderer ([`super::figure`]).

use std::path::Path;

use super::figure::{render, Figure, Panel};
use super::ReportError;

/// One curve.
pub struct Line {
    /// Legend label.
    pub label: String,
    /// (x, y) points in drawing order.
    pub points: Vec<(f64, f64)>,
}

/// One panel.
pub struct LinePanel {
    /// Panel title.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// The curves.
    pub lines: Vec<Line>,
}

impl LinePanel {
    /// The figure panel: the curves in the palette's colours.
    pub fn panel(&self) -> Panel {
        Panel::new(&self.title, &self.x_label, &self.y_label).lines(
            self.lines
                .iter()
                .map(|l| (l.label.clone(), l.points.clone())),
        )
    }
}

/// Draws panels in a grid with `cols` columns into a PNG (or SVG by extension).
pub fn line_panels(path: &Path, panels: &[LinePanel], cols: usize) -> Result<(), ReportError> {
    let fig = Figure::new(panels.iter().map(LinePanel::panel).collect(), cols);
    render(path, &fig).map(|_| ())
}
