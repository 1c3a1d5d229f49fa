//! The HTML page of `towride linear`: the mode table, each mode named by its dominant
//! motion ([`towride_mbs::model::linear::Mode::name`]), and the 3D view animating the
//! selected mode's shape.

use std::fmt::Write as _;

use super::html::{escape, string, view_scripts, COMMON_JS, ERROR_HOOK, REPORT_CSS};
use super::scene3d::{modes_view, ModeShape};
use towride_mbs::model::linear::Linearisation;
use towride_mbs::model::System;

const LINEAR_JS: &str = include_str!("assets/linear.js");

/// The page for the linearisation `lin` of `sys` about the state `y`; `at` says which
/// state ("equilibrium", "state of the run at t = 0.5 s").
pub fn linear_report(sys: &System, y: &[f64], lin: &Linearisation, at: &str) -> String {
    // Shapes for the modes that move a body.
    let mut shapes = Vec::new();
    let mut view_index = Vec::new();
    for m in &lin.modes {
        if m.name_share > 0.0 && !m.shape.is_empty() {
            view_index.push(shapes.len() as i64);
            shapes.push(ModeShape {
                label: format!("mode {}: {} ({:.3} Hz)", m.index, m.name, m.undamped_hz),
                frequency_hz: m.undamped_hz,
                shape: m.shape.clone(),
            });
        } else {
            view_index.push(-1);
        }
    }
    let mut d = String::from("{\"model\":");
    string(&mut d, &sys.model.name);
    d.push_str(",\"at\":");
    string(&mut d, at);
    let _ = write!(
        d,
        ",\"dof\":{},\"first_order_states\":{},\"eigenvalues\":{},\"stiffness_ratio\":",
        lin.dof, lin.first_order_states, lin.eigenvalues
    );
    match lin.stiffness_ratio {
        Some(s) if s.is_finite() => {
            let _ = write!(d, "{s}");
        }
        _ => d.push_str("null"),
    }
    d.push_str(",\"modes\":");
    let modes: Vec<serde_json::Value> = lin
        .modes
        .iter()
        .zip(&view_index)
        .map(|(m, v)| {
            let mut j = serde_json::to_value(m).unwrap_or_default();
            j["view"] = serde_json::json!(v);
            j
        })
        .collect();
    d.push_str(
        &serde_json::to_string(&modes)
            .unwrap_or_default()
            .replace("</", "<\\/"),
    );
    d.push_str(",\"view\":");
    d.push_str(&modes_view(sys, y, &shapes));
    d.push('}');
    let title = format!("{}: modes about the {at}", sys.model.name);
    let esc = escape(&title);
    let mut h = String::with_capacity(d.len() + 800_000);
    let _ = write!(
        h,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"generator\" content=\"towride {}\">\
         <title>towride: {esc}</title>\n<style>{REPORT_CSS}</style></head>\n\
         <body>\n<h1>{esc}</h1>\n<div id=\"app\"><noscript>This report needs JavaScript \
         (no network: everything is in this file).</noscript></div>\n\
         <script type=\"application/json\" id=\"data\">{d}</script>\n\
         {ERROR_HOOK}\n{three}<script>{COMMON_JS}</script>\n<script>{LINEAR_JS}</script>\n</body></html>\n",
        env!("CARGO_PKG_VERSION"),
        three = view_scripts(true),
    );
    h
}

/// Writes [`linear_report`] to `dir/linear.html` (whole or not at all) and returns its
/// path.
pub fn write(
    dir: &std::path::Path,
    sys: &System,
    y: &[f64],
    lin: &Linearisation,
    at: &str,
) -> Result<std::path::PathBuf, crate::Error> {
    std::fs::create_dir_all(dir).map_err(|e| crate::Error::io(dir, e))?;
    let path = dir.join("linear.html");
    crate::atomic::write(&path, linear_report(sys, y, lin, at))
        .map_err(|e| crate::Error::io(&path, e))?;
    Ok(path)
}
