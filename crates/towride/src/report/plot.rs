//! Log-log work-precision plots with plotters, using a font shipped with the crate (no
//! system fonts needed).

use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

use super::ReportError;

static FONT: Once = Once::new();

/// Registers the bundled DejaVu Sans as plotters' "sans-serif".
pub fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/DejaVuSans.ttf");
        // The font is compiled in and known to be valid.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

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
    register_font();
    let rows = panels.len().div_ceil(cols.max(1));
    let size = (420 * cols as u32, 340 * rows as u32);
    let svg = path.extension().is_some_and(|e| e == "svg");
    if svg {
        let root = SVGBackend::new(path, size).into_drawing_area();
        draw(&root, panels, rows, cols)
    } else {
        let root = BitMapBackend::new(path, size).into_drawing_area();
        draw(&root, panels, rows, cols)
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    panels: &[Panel],
    rows: usize,
    cols: usize,
) -> Result<(), ReportError> {
    let e = |x: &dyn std::fmt::Display| x.to_string();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let areas = root.split_evenly((rows, cols));
    for (panel, area) in panels.iter().zip(areas.iter()) {
        let pts: Vec<(f64, f64)> = panel
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
            .collect();
        if pts.is_empty() {
            continue;
        }
        // Drawn on log10 of the values with a linear axis: its ticks fall at round
        // log10 steps whatever the range (plotters' log axis labels only decades, and a
        // range inside one decade, such as wall times of 0.25-0.45 s, got none).
        let span = |v: Vec<f64>| {
            let lo = v.iter().cloned().fold(f64::INFINITY, f64::min).log10();
            let hi = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max).log10();
            let pad = 0.08 * (hi - lo).max(0.5);
            (lo - pad)..(hi + pad)
        };
        let xr = span(pts.iter().map(|p| p.0).collect());
        let yr = span(pts.iter().map(|p| p.1).collect());
        let corner = emptiest_corner(panel, &xr, &yr);
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(56)
            .build_cartesian_2d(xr, yr)
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_desc(format!("{} (log scale)", panel.x_label))
            .y_desc(format!("{} (log scale)", panel.y_label))
            .x_labels(6)
            .y_labels(6)
            .x_label_formatter(&|v| sig2(10f64.powf(*v)))
            .y_label_formatter(&|v| sig2(10f64.powf(*v)))
            .label_style(("sans-serif", 11))
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(|x| e(&x))?;
        for (i, s) in panel.series.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
                .map(|(x, y)| (x.log10(), y.log10()))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                .map_err(|x| e(&x))?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2))
                });
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 3, colour.filled())))
                .map_err(|x| e(&x))?;
        }
        chart
            .configure_series_labels()
            .position(corner)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()
            .map_err(|x| e(&x))?;
    }
    root.present().map_err(|x| e(&x))?;
    Ok(())
}

/// The quarter of the panel (log axes) that the series' lines cross least, for the
/// legend: growth plots fill the lower left and upper right, and a legend there hid
/// their largest points.
fn emptiest_corner(
    panel: &Panel,
    xr: &std::ops::Range<f64>,
    yr: &std::ops::Range<f64>,
) -> SeriesLabelPosition {
    let (xm, ym) = (0.5 * (xr.start + xr.end), 0.5 * (yr.start + yr.end));
    let mut count = [0usize; 4]; // upper left, upper right, lower left, lower right
    for s in &panel.series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
            .map(|(x, y)| (x.log10(), y.log10()))
            .collect();
        let mut at =
            |(x, y): (f64, f64)| count[2 * usize::from(y < ym) + usize::from(x >= xm)] += 1;
        pts.iter().for_each(|&p| at(p));
        for w in pts.windows(2) {
            for k in 1..10 {
                let f = k as f64 / 10.0;
                at((
                    w[0].0 + f * (w[1].0 - w[0].0),
                    w[0].1 + f * (w[1].1 - w[0].1),
                ));
            }
        }
    }
    let best = (0..4)
        .min_by_key(|&k| (count[k], [1, 0, 3, 2][k]))
        .unwrap_or(1);
    match best {
        0 => SeriesLabelPosition::UpperLeft,
        1 => SeriesLabelPosition::UpperRight,
        2 => SeriesLabelPosition::LowerLeft,
        _ => SeriesLabelPosition::LowerRight,
    }
}

/// A tick label with two significant digits: 0.25, 3.5, 1.2e-5.
fn sig2(x: f64) -> String {
    if (1e-3..1e4).contains(&x) {
        let digits = (1 - x.log10().floor() as i32).max(0) as usize;
        let t = format!("{x:.digits$}");
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        }
    } else {
        format!("{x:.1e}")
    }
}
