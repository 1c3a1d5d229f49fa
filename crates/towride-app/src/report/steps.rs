//! Step-size and order histories of integrators over a run (the solver's
//! `Stats::step_history`), one colour per integrator: step size on a log axis and order
//! against time.

use std::path::Path;

use super::figure::{render, Axis, Figure, Panel, Style, Trace, PALETTE};
use super::ReportError;

/// One integrator's accepted steps: (end time [s], step [s], order).
pub struct StepHistory {
    /// The integrator's name in the legend.
    pub label: String,
    /// (end time [s], step [s], order) of each accepted step.
    pub steps: Vec<(f64, f64, usize)>,
}

/// The step-size and order panels of `runs`.
pub fn step_panels(runs: &[StepHistory]) -> Vec<Panel> {
    let trace = |i: usize, r: &StepHistory, f: &dyn Fn(&(f64, f64, usize)) -> f64| {
        Trace::new(
            format!("{} ({} steps)", r.label, r.steps.len()),
            r.steps.iter().map(|s| (s.0, f(s))).collect(),
            Style::dots(PALETTE[i % PALETTE.len()], 2.0),
        )
    };
    let step = Panel {
        title: "step size".into(),
        x: Axis::linear("time [s]"),
        y: Axis::log("step [s] (log scale)"),
        traces: runs
            .iter()
            .enumerate()
            .map(|(i, r)| trace(i, r, &|s| s.1))
            .collect(),
    };
    let order = Panel {
        title: "order".into(),
        x: Axis::linear("time [s]"),
        y: Axis {
            range: Some((0.5, 5.5)),
            ..Axis::linear("order")
        },
        traces: runs
            .iter()
            .enumerate()
            // Each run's orders a little apart so that equal orders stay visible.
            .map(|(i, r)| trace(i, r, &|s| s.2 as f64 - 0.1 * i as f64))
            .collect(),
    };
    vec![step, order]
}

/// Draws step size (top) and order (bottom) against time into a PNG or SVG file.
pub fn step_history_plot(path: &Path, runs: &[StepHistory]) -> Result<(), ReportError> {
    if runs.iter().all(|r| r.steps.is_empty()) {
        return Err(ReportError::Plot("no steps recorded".into()));
    }
    let mut fig = Figure::new(step_panels(runs), 1);
    fig.panel_height = 480;
    render(path, &fig).map(|_| ())
}
