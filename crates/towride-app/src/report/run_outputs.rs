//! The page of a scene's `[[output]]` channels (`plots_outputs.png` beside `plots.png`):
//! one panel per family of channels ([`super::families`]), titled in words, angles in
//! degrees, left/right pairs in one colour as on the run page.

use std::path::Path;

use super::families::families;
use super::figure::{render, Figure, Panel};
use super::run::trace;
use super::ReportError;
use towride_mbs::model::run::Samples;

/// The panels of the channels named in `requested` (those `res` holds), one per family,
/// in the order the scene asked for them; values in the figure's units.
pub fn output_panels(res: &Samples, requested: &[String]) -> Vec<Panel> {
    let asked = |c: usize| requested.contains(&res.channels[c].name);
    families(res, asked)
        .into_iter()
        .map(|f| {
            let mut n = 0;
            let traces = f
                .members
                .iter()
                .map(|&c| trace(res, c, f.factor, &mut n))
                .collect();
            Panel {
                traces,
                ..Panel::new(&f.title, "time [s]", &f.axis)
            }
        })
        .collect()
}

/// Draws the `[[output]]` channels' page into `path` (PNG, or SVG by extension); `false`
/// without drawing when `res` holds none of them.
pub fn outputs_page(res: &Samples, requested: &[String], path: &Path) -> Result<bool, ReportError> {
    let panels = output_panels(res, requested);
    if panels.is_empty() {
        return Ok(false);
    }
    let mut fig = Figure::new(panels, 2);
    fig.panel_height = 560;
    render(path, &fig).map(|_| true)
}
