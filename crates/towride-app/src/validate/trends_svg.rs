//! The trends page's figure of one channel: peak |a| against the measured speed as
//! inline SVG (no script), a panel per obstacle side by side over the page's width, a
//! colour per load case; dots and a solid least-squares line per group measured,
//! crosses and a dashed line simulated. The lines span their group's speeds only.

use std::fmt::Write as _;

use super::trends::{fit, groups, Point};
use crate::report::figure::{Rgb, PALETTE};
use crate::report::html::escape;
use crate::report::ticks;

/// Width of the figure's coordinate system; the page scales it to the content width.
const W: f64 = 1200.0;
/// Plot height.
const PH: f64 = 300.0;
/// Legend row, panel title row and the room below for the x axis.
const LEGEND: f64 = 30.0;
const TITLE: f64 = 24.0;
const BOTTOM: f64 = 46.0;
/// Left margin (y labels), room between panels (the next one's y labels), right margin.
const ML: f64 = 70.0;
const GAP: f64 = 64.0;
const MR: f64 = 14.0;

fn hex(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The colour of load case `k` (of the figure's sorted load cases).
fn colour(k: usize) -> String {
    hex(PALETTE[k % PALETTE.len()])
}

fn load_name(l: &str) -> &str {
    if l.is_empty() {
        "the scene's load"
    } else {
        l
    }
}

/// The figure of one channel's points.
pub fn scatter(pts: &[Point]) -> String {
    let mut obstacles: Vec<&str> = pts.iter().map(|p| p.obstacle.as_str()).collect();
    obstacles.sort();
    obstacles.dedup();
    let mut loads: Vec<&str> = pts.iter().map(|p| p.load_case.as_str()).collect();
    loads.sort();
    loads.dedup();
    let nf = obstacles.len().max(1) as f64;
    let fw = (W - ML - MR - (nf - 1.0) * GAP) / nf;
    let h = LEGEND + TITLE + PH + BOTTOM;
    let (x0, x1) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p.speed_kmh), a.1.max(p.speed_kmh))
    });
    // 5 % room each side so no point sits on an axis.
    let pad = (0.05 * (x1 - x0)).max(1.0);
    let (x0, x1) = (x0 - pad, x1 + pad);
    let mut s = format!(
        "<svg class=\"trend\" viewBox=\"0 0 {W} {h}\" xmlns=\"http://www.w3.org/2000/svg\" font-size=\"13\" font-family=\"system-ui, sans-serif\">"
    );
    legend(&mut s, &loads);
    let top = LEGEND + TITLE;
    for (i, obstacle) in obstacles.iter().enumerate() {
        let left = ML + i as f64 * (fw + GAP);
        let mine: Vec<&Point> = pts.iter().filter(|p| p.obstacle == *obstacle).collect();
        let y1 = mine
            .iter()
            .flat_map(|p| p.peak_mps2)
            .fold(0.0_f64, f64::max)
            * 1.1
            + 1e-9;
        let px = |x: f64| left + (x - x0) / (x1 - x0) * fw;
        let py = |y: f64| top + PH - y / y1 * PH;
        let _ = write!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\" font-weight=\"bold\">{}</text>\
             <rect x=\"{left:.1}\" y=\"{top}\" width=\"{fw:.1}\" height=\"{PH}\" fill=\"none\" stroke=\"#444\"/>",
            left + 0.5 * fw,
            top - 8.0,
            escape(obstacle)
        );
        // Round ticks with distinct labels (the figures' rules: no repeated values, no `.0`).
        let (xt, xstep) = ticks::linear(x0, x1, (fw / 70.0).clamp(3.0, 8.0) as usize);
        for (xv, label) in xt.iter().zip(ticks::labels(&xt, xstep)) {
            let _ = write!(
                s,
                "<line x1=\"{0:.1}\" x2=\"{0:.1}\" y1=\"{top}\" y2=\"{1}\" stroke=\"#e4e4e4\"/><text x=\"{0:.1}\" y=\"{2}\" text-anchor=\"middle\">{label}</text>",
                px(*xv),
                top + PH,
                top + PH + 16.0
            );
        }
        let (yt, ystep) = ticks::linear(0.0, y1, 5);
        for (yv, label) in yt.iter().zip(ticks::labels(&yt, ystep)) {
            let _ = write!(
                s,
                "<line x1=\"{left:.1}\" x2=\"{:.1}\" y1=\"{1:.1}\" y2=\"{1:.1}\" stroke=\"#e4e4e4\"/><text x=\"{2:.1}\" y=\"{3:.1}\" text-anchor=\"end\">{label}</text>",
                left + fw,
                py(*yv),
                left - 5.0,
                py(*yv) + 4.0
            );
        }
        let (ly, lx) = (top + 0.5 * PH, left - 48.0);
        let _ = write!(
            s,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">measured speed [km/h]</text><text x=\"{lx:.1}\" y=\"{ly:.1}\" transform=\"rotate(-90 {lx:.1} {ly:.1})\" text-anchor=\"middle\">peak |a| [m/s²]</text>",
            left + 0.5 * fw,
            top + PH + 36.0
        );
        let own: Vec<Point> = mine.iter().map(|p| (*p).clone()).collect();
        for (o, l) in groups(&own) {
            let c = colour(loads.iter().position(|x| *x == l).unwrap_or(0));
            let g: Vec<&Point> = mine
                .iter()
                .copied()
                .filter(|p| p.group() == (&o, &l))
                .collect();
            let (g0, g1) = g.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
                (a.0.min(p.speed_kmh), a.1.max(p.speed_kmh))
            });
            for (k, (kind, dash)) in [("measured", ""), ("simulated", " stroke-dasharray=\"7 4\"")]
                .into_iter()
                .enumerate()
            {
                if let Some((a, b)) = fit(&g, k) {
                    let _ = write!(
                        s,
                        "<line class=\"fit\" data-obstacle=\"{}\" data-load=\"{}\" data-kind=\"{kind}\" data-intercept=\"{a}\" data-slope=\"{b}\" x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{c}\" stroke-width=\"2\"{dash}><title>{}: {kind} {b:+.4} m/s² per km/h</title></line>",
                        escape(&o), escape(&l), px(g0), py(a + b * g0), px(g1), py(a + b * g1),
                        escape(&super::trends::group_label(&o, &l))
                    );
                }
            }
            for p in &g {
                let (cx, cm, cs) = (px(p.speed_kmh), py(p.peak_mps2[0]), py(p.peak_mps2[1]));
                let run = escape(&p.run);
                let _ = write!(
                    s,
                    "<circle cx=\"{cx:.1}\" cy=\"{cm:.1}\" r=\"4\" fill=\"{c}\"><title>{run}: measured {:.3} m/s²</title></circle>\
                     <path d=\"M{:.1} {:.1}l8 8m0 -8l-8 8\" stroke=\"{c}\" stroke-width=\"1.6\"><title>{run}: simulated {:.3} m/s²</title></path>",
                    p.peak_mps2[0], cx - 4.0, cs - 4.0, p.peak_mps2[1]
                );
            }
        }
    }
    s.push_str("</svg>");
    s
}

/// The legend row: a colour per load case, then what dots and crosses mean.
fn legend(s: &mut String, loads: &[&str]) {
    let mut x = ML;
    let y = 18.0;
    for (k, l) in loads.iter().enumerate() {
        let name = escape(load_name(l));
        let _ = write!(
            s,
            "<line x1=\"{x:.1}\" x2=\"{:.1}\" y1=\"{1}\" y2=\"{1}\" stroke=\"{2}\" stroke-width=\"3\"/><text x=\"{3:.1}\" y=\"{4}\">{name}</text>",
            x + 22.0,
            y - 4.0,
            colour(k),
            x + 28.0,
            y
        );
        x += 48.0 + 7.5 * name.chars().count() as f64;
    }
    let _ = write!(
        s,
        "<circle cx=\"{:.1}\" cy=\"{1}\" r=\"4\" fill=\"#555\"/><line x1=\"{2:.1}\" x2=\"{3:.1}\" y1=\"{1}\" y2=\"{1}\" stroke=\"#555\" stroke-width=\"2\"/><text x=\"{4:.1}\" y=\"{y}\">measured</text>\
         <path d=\"M{5:.1} {6}l8 8m0 -8l-8 8\" stroke=\"#555\" stroke-width=\"1.6\"/><line x1=\"{7:.1}\" x2=\"{8:.1}\" y1=\"{1}\" y2=\"{1}\" stroke=\"#555\" stroke-width=\"2\" stroke-dasharray=\"7 4\"/><text x=\"{9:.1}\" y=\"{y}\">simulated</text>",
        x + 20.0,
        y - 4.0,
        x + 28.0,
        x + 50.0,
        x + 56.0,
        x + 136.0,
        y - 8.0,
        x + 150.0,
        x + 172.0,
        x + 178.0,
    );
}

#[cfg(test)]
mod tests {
    #[test]
    fn scatter_tick_labels_are_distinct() {
        // Two runs 0.6 km/h apart: the old labels read "48, 48, 49, 49, 50".
        let p = |speed_kmh: f64, peak: f64| super::Point {
            run: format!("r{speed_kmh}"),
            obstacle: "bump".into(),
            load_case: "empty".into(),
            speed_kmh,
            peak_mps2: [peak, 0.9 * peak],
            body_hz: [None; 2],
            wheel_hz: [None; 2],
        };
        let svg = super::scatter(&[p(48.55, 11.2), p(49.15, 11.9)]);
        let labels: Vec<&str> = svg
            .split("text-anchor=\"middle\">")
            .skip(1)
            .map(|t| t.split('<').next().unwrap())
            .filter(|t| t.chars().all(|c| c.is_ascii_digit() || c == '.'))
            .collect();
        assert!(labels.len() >= 3, "{labels:?}");
        let mut sorted = labels.clone();
        sorted.dedup();
        assert_eq!(sorted, labels, "repeated x tick labels");
        assert!(labels.iter().all(|l| !l.ends_with(".0")), "{labels:?}");
    }
}
