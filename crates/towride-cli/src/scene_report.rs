//! What a vehicle run adds to its summary: wheel lift-off intervals, the crossbeam's
//! strain-energy shares per mode, and a page of plots.

use std::path::Path;

use serde_json::{json, Value};

use towride::model::energy::{select_by_energy, strain_shares};
use towride::model::run::RunResult;
use towride::model::System;
use towride::report::lineplot::{line_panels, Line, LinePanel};

/// Intervals without contact per wheel, from the `tyre_<w>_contact` channels.
pub fn lift_off(res: &RunResult) -> Vec<Value> {
    let mut out = Vec::new();
    for (c, ch) in res.channels.iter().enumerate() {
        let Some(w) = ch
            .name
            .strip_prefix("tyre_")
            .and_then(|n| n.strip_suffix("_contact"))
        else {
            continue;
        };
        let mut start: Option<f64> = None;
        for (t, row) in res.times.iter().zip(&res.rows) {
            match (row[c] < 0.5, start) {
                (true, None) => start = Some(*t),
                (false, Some(t0)) => {
                    out.push(json!({"wheel": w, "start_s": t0, "end_s": t, "duration_s": t - t0}));
                    start = None;
                }
                _ => {}
            }
        }
        if let (Some(t0), Some(t1)) = (start, res.times.last()) {
            out.push(
                json!({"wheel": w, "start_s": t0, "end_s": Value::Null, "duration_s": t1 - t0}),
            );
        }
    }
    out
}

/// Strain-energy shares of every modal body's modes over the run, and the modes a 1 %
/// threshold would keep (the thesis's commercial-tool method).
pub fn energy(sys: &System, res: &RunResult) -> Value {
    let shares = strain_shares(sys, res);
    Value::Array(
        shares
            .iter()
            .map(|b| {
                json!({
                    "body": b.body,
                    "peak_total_j": b.peak_total_j,
                    "kept_at_1_percent": select_by_energy(b, 0.01),
                    "modes": b.modes,
                })
            })
            .collect(),
    )
}

/// One PNG page: hitch force, trailer acceleration, tyre normal forces, crossbeam strain
/// energy and the vertical sensor accelerations.
pub fn plots(res: &RunResult, path: &Path) -> Result<(), String> {
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
