//! Figures and reports as files: plotting with a bundled font (no system fonts needed),
//! the page of plots a vehicle run writes, and its interactive HTML report.

pub mod canvas;
pub mod compare;
pub mod decimate;
pub mod display;
pub mod families;
pub mod figure;
pub mod html;
pub mod linear;
pub mod lineplot;
pub mod plan_run;
pub mod plot;
pub mod rainflow;
pub mod road;

mod run;
pub mod run_files;
pub mod run_outputs;
pub mod scene3d;
pub mod steps;

pub mod ticks;
pub mod tyre_lateral;
pub mod tyre_rig;

pub use crate::error::ReportError;
pub use run::run_page;
pub use run_files::{samples_csv, samples_mf4, write_run, write_run_as};
