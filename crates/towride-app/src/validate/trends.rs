//! What a folder of runs says beyond each run's rating: per channel the trend of its peak
//! against the measured speed, measured and simulated (a least-squares line each), and
//! its dominant frequencies (body bounce, wheel hop, from [`crate::signal::spectrum`]) measured
//! against simulated. Written as `trends.csv` (one row per run and channel) and
//! `trends.html` (per channel a scatter of peak against speed as inline SVG, no script,
//! and the frequency table), beside the summary.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::folder::FolderResult;
use super::ValidateError;

/// One run's figures for one channel.
#[derive(Clone, Debug)]
pub struct Point {
    /// Run name.
    pub run: String,
    /// Measured speed [km/h].
    pub speed_kmh: f64,
    /// Measured and simulated peak magnitude [m/s^2] (primary comparison).
    pub peak_mps2: [f64; 2],
    /// Measured and simulated body-bounce frequency [Hz].
    pub body_hz: [Option<f64>; 2],
    /// Measured and simulated wheel-hop frequency [Hz].
    pub wheel_hz: [Option<f64>; 2],
}

/// Per channel the points of every run, channels in first-seen order.
pub fn collect(res: &FolderResult) -> Vec<(String, Vec<Point>)> {
    let mut out: Vec<(String, Vec<Point>)> = Vec::new();
    for r in &res.runs {
        let p = r.primary();
        for (f, c) in p.channels.iter().zip(&r.channels) {
            let point = Point {
                run: r.name.clone(),
                speed_kmh: r.speed.speed_mps * 3.6,
                peak_mps2: [f.peak_measured_mps2.abs(), f.peak_simulated_mps2.abs()],
                body_hz: [c.measured_hz.body_hz, c.simulated_hz.body_hz],
                wheel_hz: [c.measured_hz.wheel_hz, c.simulated_hz.wheel_hz],
            };
            match out.iter_mut().find(|(n, _)| *n == f.channel) {
                Some((_, v)) => v.push(point),
                None => out.push((f.channel.clone(), vec![point])),
            }
        }
    }
    out
}

/// Least-squares line y = a + b x: (a, b); `None` with fewer than two distinct x.
pub fn line(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = x.len() as f64;
    if x.len() < 2 {
        return None;
    }
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    if sxx <= 1e-12 * (1.0 + mx * mx) * n {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let b = sxy / sxx;
    Some((my - b * mx, b))
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x:.4}"))
}

/// Writes `trends.csv` and `trends.html` into `dir`.
pub fn write(res: &FolderResult, dir: &Path) -> Result<(PathBuf, PathBuf), ValidateError> {
    let io = |p: &Path, x: &dyn std::fmt::Display| ValidateError::Io {
        path: p.to_path_buf(),
        source: std::io::Error::other(x.to_string()),
    };
    let data = collect(res);
    let csv_path = dir.join("trends.csv");
    let mut w = csv::Writer::from_path(&csv_path).map_err(|x| io(&csv_path, &x))?;
    w.write_record([
        "channel",
        "run",
        "speed [km/h]",
        "peak_measured [m/s^2]",
        "peak_simulated [m/s^2]",
        "body_measured [Hz]",
        "body_simulated [Hz]",
        "wheel_measured [Hz]",
        "wheel_simulated [Hz]",
    ])
    .map_err(|x| io(&csv_path, &x))?;
    for (ch, pts) in &data {
        for p in pts {
            w.write_record([
                ch.clone(),
                p.run.clone(),
                format!("{:.4}", p.speed_kmh),
                format!("{:.6}", p.peak_mps2[0]),
                format!("{:.6}", p.peak_mps2[1]),
                opt(p.body_hz[0]),
                opt(p.body_hz[1]),
                opt(p.wheel_hz[0]),
                opt(p.wheel_hz[1]),
            ])
            .map_err(|x| io(&csv_path, &x))?;
        }
    }
    w.flush().map_err(|x| io(&csv_path, &x))?;
    let html_path = dir.join("trends.html");
    std::fs::write(&html_path, html(&data, &res.simulator)).map_err(|x| io(&html_path, &x))?;
    Ok((csv_path, html_path))
}

/// Mean of the present values.
fn mean(v: impl Iterator<Item = Option<f64>>) -> Option<f64> {
    let x: Vec<f64> = v.flatten().collect();
    (!x.is_empty()).then(|| x.iter().sum::<f64>() / x.len() as f64)
}

fn scatter(pts: &[Point]) -> String {
    let (w, h, m) = (520.0, 260.0, 48.0);
    let xs: Vec<f64> = pts.iter().map(|p| p.speed_kmh).collect();
    let ys: Vec<f64> = pts.iter().flat_map(|p| p.peak_mps2).collect();
    let (x0, x1) = xs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, v| {
        (a.0.min(*v), a.1.max(*v))
    });
    // 5 % room each side so no point sits on an axis.
    let pad = (0.05 * (x1 - x0)).max(1.0);
    let (x0, x1) = (x0 - pad, x1 + pad);
    let y1 = ys.iter().fold(0.0_f64, |a, v| a.max(*v)) * 1.1 + 1e-9;
    let px = |x: f64| m + (x - x0) / (x1 - x0) * (w - 1.5 * m);
    let py = |y: f64| h - m + -(y / y1) * (h - 1.5 * m);
    let mut s = format!(
        "<svg width=\"{w}\" height=\"{h}\" xmlns=\"http://www.w3.org/2000/svg\" font-size=\"11\">"
    );
    let _ = write!(
        s,
        "<line x1=\"{m}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"black\"/><line x1=\"{m}\" y1=\"{}\" x2=\"{m}\" y2=\"{}\" stroke=\"black\"/>",
        h - m, w - 0.5 * m, h - m, h - m, 0.5 * m
    );
    // Round ticks with distinct labels (the figures' rules: no repeated values, no `.0`).
    use crate::report::ticks;
    let (xt, xstep) = ticks::linear(x0, x1, 5);
    for (xv, label) in xt.iter().zip(ticks::labels(&xt, xstep)) {
        let _ = write!(
            s,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{label}</text>",
            px(*xv),
            h - m + 14.0
        );
    }
    let (yt, ystep) = ticks::linear(0.0, y1, 4);
    for (yv, label) in yt.iter().zip(ticks::labels(&yt, ystep)) {
        let _ = write!(
            s,
            "<text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{label}</text>",
            m - 4.0,
            py(*yv) + 4.0
        );
    }
    let _ = write!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">measured speed [km/h]</text><text x=\"12\" y=\"{}\" transform=\"rotate(-90 12 {})\" text-anchor=\"middle\">peak |a| [m/s^2]</text>",
        0.5 * w, h - 8.0, 0.5 * h, 0.5 * h
    );
    for (k, colour) in [(0, "#0072B2"), (1, "#D55E00")] {
        let y: Vec<f64> = pts.iter().map(|p| p.peak_mps2[k]).collect();
        if let Some((a, b)) = line(&xs, &y) {
            let _ = write!(
                s,
                "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{colour}\" stroke-dasharray=\"4 3\"/>",
                px(x0), py(a + b * x0), px(x1), py(a + b * x1)
            );
        }
        for p in pts {
            let (cx, cy) = (px(p.speed_kmh), py(p.peak_mps2[k]));
            if k == 0 {
                let _ = write!(s, "<circle cx=\"{cx:.1}\" cy=\"{cy:.1}\" r=\"3.5\" fill=\"{colour}\"><title>{} measured {:.3}</title></circle>", p.run, p.peak_mps2[0]);
            } else {
                let _ = write!(
                    s,
                    "<path d=\"M{:.1} {:.1}l7 7m0 -7l-7 7\" stroke=\"{colour}\" stroke-width=\"1.5\"><title>{} simulated {:.3}</title></path>",
                    cx - 3.5, cy - 3.5, p.run, p.peak_mps2[1]
                );
            }
        }
    }
    s.push_str("</svg>");
    s
}

fn html(data: &[(String, Vec<Point>)], simulator: &str) -> String {
    let mut s = String::from("<!doctype html><html><head><meta charset=\"utf-8\"><title>towride validation trends</title><style>body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:2px 8px;text-align:right}</style></head><body>");
    let _ = write!(
        s,
        "<h1>Trends over the folder</h1><p>Simulator: {simulator}. Per channel: peak |a| against the measured speed (dots measured, crosses simulated, dashed least-squares lines), and the dominant frequencies of the compared window (body bounce 0.5-6 Hz, wheel hop 6-30 Hz), means over the runs.</p>"
    );
    s.push_str("<table><tr><th>channel</th><th>runs</th><th>peak slope measured [m/s^2 per km/h]</th><th>simulated</th><th>body measured [Hz]</th><th>simulated</th><th>wheel hop measured [Hz]</th><th>simulated</th></tr>");
    for (ch, pts) in data {
        let xs: Vec<f64> = pts.iter().map(|p| p.speed_kmh).collect();
        let slope = |k: usize| {
            let y: Vec<f64> = pts.iter().map(|p| p.peak_mps2[k]).collect();
            line(&xs, &y).map(|l| l.1)
        };
        let _ = write!(
            s,
            "<tr><td style=\"text-align:left\">{ch}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            pts.len(),
            opt(slope(0)),
            opt(slope(1)),
            opt(mean(pts.iter().map(|p| p.body_hz[0]))),
            opt(mean(pts.iter().map(|p| p.body_hz[1]))),
            opt(mean(pts.iter().map(|p| p.wheel_hz[0]))),
            opt(mean(pts.iter().map(|p| p.wheel_hz[1]))),
        );
    }
    s.push_str("</table>");
    for (ch, pts) in data {
        let _ = write!(s, "<h2>{ch}</h2>{}", scatter(pts));
    }
    s.push_str("</body></html>");
    s
}

#[cfg(test)]
mod tests {
    #[test]
    fn least_squares_line() {
        let (a, b) = super::line(&[10.0, 20.0, 40.0], &[3.0, 5.0, 9.0]).unwrap();
        assert!((a - 1.0).abs() < 1e-12 && (b - 0.2).abs() < 1e-12);
        assert!(super::line(&[5.0, 5.0], &[1.0, 2.0]).is_none());
    }

    #[test]
    fn scatter_tick_labels_are_distinct() {
        // Two runs 0.6 km/h apart: the old labels read "48, 48, 49, 49, 50".
        let p = |speed_kmh: f64, peak: f64| super::Point {
            run: format!("r{speed_kmh}"),
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
