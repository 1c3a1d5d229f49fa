//! Figures and reports as files: plotting with a bundled font (no system fonts needed).

pub mod lineplot;
pub mod plot;
pub mod steps;
