//! Linear-axis line plots (time histories, profiles) with the bundled font.

use plotters::prelude::*;
use std::path::Path;

use super::figure::{AxisMap, PanelLayout};
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

/// Draws panels in a grid of `size` pixels into a PNG; returns where each panel went.
pub fn draw_panels_layout(
    path: &Path,
    panels: &[LinePanel],
    cols: usize,
    size: (u32, u32),
) -> Result<Vec<PanelLayout>, ReportError> {
    register_font();
    let rows = panels.len().div_ceil(cols);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let layout = draw_panels_with_layout(&root, panels, rows, cols)?;
    root.present().map_err(|e| e.to_string())?;
    Ok(layout)
}

/// Draws panels in a `rows` x `cols` grid into `root` (part of a larger page, say).
pub fn draw_panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    panels: &[LinePanel],
    rows: usize,
    cols: usize,
) -> Result<(), ReportError> {
    draw_panels_with_layout(root, panels, rows, cols).map(|_| ())
}

fn draw_panels_with_layout<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    panels: &[LinePanel],
    rows: usize,
    cols: usize,
) -> Result<Vec<PanelLayout>, ReportError> {
    use plotters::coord::ranged1d::ValueFormatter;
    use plotters::coord::types::RangedCoordf64;
    use std::cell::RefCell;
    let mut layouts = Vec::new();
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
        let (xr0, yr0) = (xr.clone(), yr.clone());
        // The labels plotters draws, recorded by value (its own formatter, unchanged).
        let x_seen: RefCell<Vec<(f64, String)>> = RefCell::new(Vec::new());
        let y_seen: RefCell<Vec<(f64, String)>> = RefCell::new(Vec::new());
        let record = |seen: &RefCell<Vec<(f64, String)>>, v: &f64| {
            let s = <RangedCoordf64 as ValueFormatter<f64>>::format(v);
            let mut seen = seen.borrow_mut();
            if !seen.iter().any(|(w, _)| w == v) {
                seen.push((*v, s.clone()));
            }
            s
        };
        let x_fmt = |v: &f64| record(&x_seen, v);
        let y_fmt = |v: &f64| record(&y_seen, v);
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
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(|x| e(&x))?;
        let (px, py) = chart.plotting_area().get_pixel_range();
        let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
        let labels = |seen: &RefCell<Vec<(f64, String)>>| {
            let mut v = seen.borrow().clone();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            v.into_iter().map(|(_, s)| s).collect()
        };
        layouts.push(PanelLayout {
            plot: [px.start, py.start, px.end, py.end],
            x: AxisMap {
                lo: xr0.start,
                hi: xr0.end,
                px_lo: at(xr0.start, yr0.start).0 as f64,
                px_hi: at(xr0.end, yr0.start).0 as f64,
            },
            y: AxisMap {
                lo: yr0.start,
                hi: yr0.end,
                px_lo: at(xr0.start, yr0.start).1 as f64,
                px_hi: at(xr0.start, yr0.end).1 as f64,
            },
            x_ticks: labels(&x_seen),
            y_ticks: labels(&y_seen),
            // DejaVu Sans digits are 0.729 em high.
            tick_digit_px: 11.0 * 0.729,
            colours: (0..panel.lines.len())
                .map(|i| {
                    let c = Palette99::pick(i).to_rgba();
                    [c.0, c.1, c.2]
                })
                .collect(),
            // Inside the plot area, where plotters puts it.
            legend: None,
        });
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
    Ok(layouts)
}
