//! The page of plots a vehicle run writes beside its CSV.

use std::path::Path;

use super::lineplot::{line_panels, Line, LinePanel};
use super::ReportError;
use crate::model::run::Samples;

/// One PNG page: hitch force, trailer acceleration, tyre normal forces, crossbeam strain
/// energy, the vertical sensor accelerations and the speed.
pub fn run_page(res: &Samples, path: &Path) -> Result<(), ReportError> {
    let series = |pred: &dyn Fn(&str) -> bool| -> Vec<Line> {
        res.channels
            .iter()
            .enumerate()
            .filter(|(_, ch)| pred(&ch.name))
            .map(|(c, ch)| Line {
                label: ch.name.clone(),
                points: res
                    .times
                    .iter()
                    .zip(&res.rows)
                    .map(|(t, r)| (*t, r[c]))
                    .collect(),
            })
            .collect()
    };
    let panel = |title: &str, y: &str, lines: Vec<Line>| LinePanel {
        title: title.into(),
        x_label: "time [s]".into(),
        y_label: y.into(),
        lines,
    };
    let panels = vec![
        panel(
            "hitch force on the car",
            "force [N]",
            series(&|n| n == "hitch_fx" || n == "hitch_fz"),
        ),
        panel(
            "trailer box",
            "acceleration [m/s^2]",
            series(&|n| n == "trailer_ax"),
        ),
        panel(
            "tyre normal forces",
            "force [N]",
            series(&|n| n.starts_with("tyre_") && n.ends_with("_fz")),
        ),
        panel(
            "crossbeam strain energy",
            "energy [J]",
            series(&|n| n == "hitch_strain_energy"),
        ),
        panel(
            "vertical accelerations at the sensors",
            "acceleration [m/s^2]",
            series(&|n| n.starts_with("acc_") && n.ends_with("_z")),
        ),
        panel("speed", "speed [m/s]", series(&|n| n == "speed")),
    ];
    let panels: Vec<LinePanel> = panels.into_iter().filter(|p| !p.lines.is_empty()).collect();
    line_panels(path, &panels, 2)
}
