//! Step-size and order histories of integrators over a run (the solver's
//! `Stats::step_history`), one colour per integrator: step size on a log axis and order
//! against time.

use plotters::prelude::*;
use std::path::Path;

use super::plot::register_font;
use super::ReportError;

/// One integrator's accepted steps: (end time [s], step [s], order).
pub struct StepHistory {
    /// The integrator's name in the legend.
    pub label: String,
    /// (end time [s], step [s], order) of each accepted step.
    pub steps: Vec<(f64, f64, usize)>,
}

/// Draws step size (top) and order (bottom) against time into a PNG or SVG file.
pub fn step_history_plot(path: &Path, runs: &[StepHistory]) -> Result<(), ReportError> {
    register_font();
    let size = (1000, 680);
    if path.extension().is_some_and(|e| e == "svg") {
        draw(&SVGBackend::new(path, size).into_drawing_area(), runs)?;
    } else {
        draw(&BitMapBackend::new(path, size).into_drawing_area(), runs)?;
    }
    Ok(())
}

/// Distinct, well-visible colours for the runs (red, green, blue, then plotters' palette).
fn colour(i: usize) -> RGBAColor {
    match i {
        0 => RGBColor(200, 30, 60).to_rgba(),
        1 => RGBColor(40, 150, 60).to_rgba(),
        2 => RGBColor(30, 80, 210).to_rgba(),
        _ => Palette99::pick(i).to_rgba(),
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    runs: &[StepHistory],
) -> Result<(), String> {
    let e = |x: &dyn std::fmt::Display| x.to_string();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let all = || runs.iter().flat_map(|r| r.steps.iter());
    let t_end = all().map(|s| s.0).fold(0.0, f64::max).max(1e-9);
    let hs: Vec<f64> = all().map(|s| s.1).filter(|h| *h > 0.0).collect();
    if hs.is_empty() {
        return Err("no steps recorded".into());
    }
    let lo = hs
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min)
        .log10()
        .floor();
    let hi = hs.iter().cloned().fold(0.0, f64::max).log10().ceil();
    let (top, bottom) = root.split_vertically(440);
    let mut chart = ChartBuilder::on(&top)
        .caption("step size", ("sans-serif", 16))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..t_end, lo..hi)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc("step [s] (log scale)")
        .y_label_formatter(&|v| format!("{:.0e}", 10f64.powf(*v)))
        .label_style(("sans-serif", 11))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(|x| e(&x))?;
    for (i, r) in runs.iter().enumerate() {
        let colour = colour(i);
        chart
            .draw_series(
                r.steps
                    .iter()
                    .filter(|s| s.1 > 0.0)
                    .map(|s| Circle::new((s.0, s.1.log10()), 1, colour.filled())),
            )
            .map_err(|x| e(&x))?
            .label(format!("{} ({} steps)", r.label, r.steps.len()))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, colour.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(|x| e(&x))?;
    let mut chart = ChartBuilder::on(&bottom)
        .caption("order", ("sans-serif", 16))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..t_end, 0.5..5.5)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc("order")
        .y_labels(6)
        .label_style(("sans-serif", 11))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(|x| e(&x))?;
    for (i, r) in runs.iter().enumerate() {
        let colour = colour(i);
        // Each run's orders drawn a little apart so that equal orders stay visible.
        let dy = 0.08 * i as f64;
        chart
            .draw_series(
                r.steps
                    .iter()
                    .map(|s| Circle::new((s.0, s.2 as f64 - dy), 1, colour.filled())),
            )
            .map_err(|x| e(&x))?;
    }
    root.present().map_err(|x| e(&x))?;
    Ok(())
}
