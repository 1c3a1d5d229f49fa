//! Figures and reports as files: plotting with a bundled font (no system fonts needed),
//! the page of plots a vehicle run writes, and its interactive HTML report.

pub mod canvas;
pub mod compare;
pub mod decimate;
pub mod figure;
pub mod html;
pub mod linear;
pub mod lineplot;
pub mod plot;
pub mod psd;
mod run;
pub mod scene3d;
pub mod steps;
pub mod sweep;
pub mod ticks;

pub use run::run_page;

/// A figure or report that could not be drawn or written.
#[derive(Debug, Clone, thiserror::Error)]
pub enum ReportError {
    /// The plotting backend failed (a file that cannot be written, a bad font).
    #[error("plot: {0}")]
    Plot(String),
}

impl From<String> for ReportError {
    fn from(message: String) -> Self {
        ReportError::Plot(message)
    }
}
