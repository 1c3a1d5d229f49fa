//! Linear-axis line plots (time histories, profiles) with the bundled font.

use plotters::prelude::*;
use std::path::Path;

use super::plot::register_font;
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

/// Draws panels in a grid with `cols` columns into a PNG (or SVG by extension).
pub fn line_panels(path: &Path, panels: &[LinePanel], cols: usize) -> Result<(), ReportError> {
    register_font();
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols);
    let size = (560 * cols as u32, 360 * rows as u32);
    if path.extension().is_some_and(|e| e == "svg") {
        let root = SVGBackend::new(path, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        draw_panels(&root, panels, rows, cols)?;
        root.present().map_err(|e| e.to_string())?;
        Ok(())
    } else {
        let root = BitMapBackend::new(path, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        draw_panels(&root, panels, rows, cols)?;
        root.present().map_err(|e| e.to_string())?;
        Ok(())
    }
}

/// Draws panels in a `rows` x `cols` grid into `root` (part of a larger page, say).
pub fn draw_panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    panels: &[LinePanel],
    rows: usize,
    cols: usize,
) -> Result<(), ReportError> {
    let e = |x: &dyn std::fmt::Display| x.to_string();
    for (panel, area) in panels.iter().zip(root.split_evenly((rows, cols)).iter()) {
        let pts: Vec<(f64, f64)> = panel
            .lines
            .iter()
            .flat_map(|l| l.points.iter().copied())
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        if pts.is_empty() {
            continue;
        }
        let range = |v: &mut dyn Iterator<Item = f64>| {
            let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
            let pad = if hi > lo {
                0.05 * (hi - lo)
            } else {
                1.0_f64.max(hi.abs() * 0.1)
            };
            (lo - pad)..(hi + pad)
        };
        let xr = range(&mut pts.iter().map(|p| p.0));
        let yr = range(&mut pts.iter().map(|p| p.1));
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(64)
            .build_cartesian_2d(xr, yr)
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_desc(&panel.x_label)
            .y_desc(&panel.y_label)
            .label_style(("sans-serif", 11))
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(|x| e(&x))?;
        for (i, l) in panel.lines.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    l.points.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(|x| e(&x))?
                .label(l.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()
            .map_err(|x| e(&x))?;
    }
    Ok(())
}
