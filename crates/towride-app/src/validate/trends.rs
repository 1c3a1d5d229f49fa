//! What a folder of runs says beyond each run's rating: per channel the trend of its peak
//! against the measured speed, measured and simulated, and its dominant frequencies
//! (body bounce, wheel hop, from [`crate::signal::spectrum`]) measured against
//! simulated. Runs differ in more than speed (obstacle, trailer load), so every trend is
//! per group of runs with the same obstacle and load case: a line pooled over a 25 mm
//! bump and a 50 mm ramp, or over four loads, would mix their peaks into one slope that
//! fits none of them. Written as `trends.csv` (one row per run and channel) and
//! `trends.html` (per channel the scatter of peak against speed, a panel per obstacle and
//! a colour per load case, as inline SVG, [`super::trends_svg`], and a table per group).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::folder::FolderResult;
use super::ValidateError;
use crate::report::html::escape;

/// One run's figures for one channel.
#[derive(Clone, Debug)]
pub struct Point {
    /// Run name.
    pub run: String,
    /// The obstacle driven over.
    pub obstacle: String,
    /// Trailer load case (empty: the scene's).
    pub load_case: String,
    /// Measured speed [km/h].
    pub speed_kmh: f64,
    /// Measured and simulated peak magnitude [m/s^2] (primary comparison).
    pub peak_mps2: [f64; 2],
    /// Measured and simulated body-bounce frequency [Hz].
    pub body_hz: [Option<f64>; 2],
    /// Measured and simulated wheel-hop frequency [Hz].
    pub wheel_hz: [Option<f64>; 2],
}

impl Point {
    /// The group of runs it belongs to: (obstacle, load case).
    pub fn group(&self) -> (&str, &str) {
        (&self.obstacle, &self.load_case)
    }
}

/// A group's name for legends and tables.
pub fn group_label(obstacle: &str, load_case: &str) -> String {
    if load_case.is_empty() {
        obstacle.to_string()
    } else {
        format!("{obstacle}, {load_case}")
    }
}

/// The groups present in `pts`, sorted (obstacle, then load case).
pub fn groups(pts: &[Point]) -> Vec<(String, String)> {
    let mut g: Vec<(String, String)> = pts
        .iter()
        .map(|p| (p.obstacle.clone(), p.load_case.clone()))
        .collect();
    g.sort();
    g.dedup();
    g
}

/// Per channel the points of every run, channels in first-seen order.
pub fn collect(res: &FolderResult) -> Vec<(String, Vec<Point>)> {
    let mut out: Vec<(String, Vec<Point>)> = Vec::new();
    for r in &res.runs {
        let p = r.primary();
        for (f, c) in p.channels.iter().zip(&r.channels) {
            let point = Point {
                run: r.name.clone(),
                obstacle: r.obstacle.clone(),
                load_case: r.load_case.clone(),
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

/// The least-squares line of peak against speed over `pts`, measured (`k` = 0) or
/// simulated (1).
pub fn fit(pts: &[&Point], k: usize) -> Option<(f64, f64)> {
    let x: Vec<f64> = pts.iter().map(|p| p.speed_kmh).collect();
    let y: Vec<f64> = pts.iter().map(|p| p.peak_mps2[k]).collect();
    line(&x, &y)
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
    // The group's keys last: the earlier columns keep their places.
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
        "obstacle",
        "load_case",
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
                p.obstacle.clone(),
                p.load_case.clone(),
            ])
            .map_err(|x| io(&csv_path, &x))?;
        }
    }
    w.flush().map_err(|x| io(&csv_path, &x))?;
    let html_path = dir.join("trends.html");
    crate::atomic::write(&html_path, html(&data, &res.simulator))
        .map_err(|x| io(&html_path, &x))?;
    Ok((csv_path, html_path))
}

/// Mean of the present values.
fn mean(v: impl Iterator<Item = Option<f64>>) -> Option<f64> {
    let x: Vec<f64> = v.flatten().collect();
    (!x.is_empty()).then(|| x.iter().sum::<f64>() / x.len() as f64)
}

/// A number for a table cell: four decimals, a dash when absent.
fn cell(v: Option<f64>) -> String {
    v.map_or("–".into(), |x| format!("{x:.4}"))
}

/// The table of one channel: per group its runs, slopes and mean frequencies.
fn group_table(pts: &[Point]) -> String {
    let mut s = String::from("<div class=\"wide\"><table><tr><th>obstacle</th><th class=\"l\">load case</th><th>runs</th><th>speeds [km/h]</th><th>peak slope measured [m/s² per km/h]</th><th>simulated</th><th>body measured [Hz]</th><th>simulated</th><th>wheel hop measured [Hz]</th><th>simulated</th></tr>");
    for (o, l) in groups(pts) {
        let g: Vec<&Point> = pts.iter().filter(|p| p.group() == (&o, &l)).collect();
        let (lo, hi) = g.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
            (a.0.min(p.speed_kmh), a.1.max(p.speed_kmh))
        });
        let _ = write!(
            s,
            "<tr><td>{}</td><td class=\"l\">{}</td><td>{}</td><td>{lo:.1}–{hi:.1}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&o),
            escape(if l.is_empty() { "(the scene's)" } else { &l }),
            g.len(),
            cell(fit(&g, 0).map(|l| l.1)),
            cell(fit(&g, 1).map(|l| l.1)),
            cell(mean(g.iter().map(|p| p.body_hz[0]))),
            cell(mean(g.iter().map(|p| p.body_hz[1]))),
            cell(mean(g.iter().map(|p| p.wheel_hz[0]))),
            cell(mean(g.iter().map(|p| p.wheel_hz[1]))),
        );
    }
    s.push_str("</table></div>");
    s
}

fn html(data: &[(String, Vec<Point>)], simulator: &str) -> String {
    let mut s = format!(
        "<p>Simulator: {}. Per channel: peak |a| against the measured speed, a panel per obstacle and a colour per trailer load case (dots and solid lines measured, crosses and dashed lines simulated; a least-squares line per obstacle and load case), then per group the slopes and the mean dominant frequencies of the compared window (body bounce 0.5–6 Hz, wheel hop 6–30 Hz).</p>",
        escape(simulator)
    );
    s.push_str("<p>Channels: ");
    for (k, (ch, _)) in data.iter().enumerate() {
        let (sep, c) = (if k > 0 { ", " } else { "" }, escape(ch));
        let _ = write!(s, "{sep}<a href=\"#{c}\">{c}</a>");
    }
    s.push_str("</p>");
    for (ch, pts) in data {
        let _ = write!(
            s,
            "<h2 id=\"{0}\">{0}</h2>{1}{2}",
            escape(ch),
            super::trends_svg::scatter(pts),
            group_table(pts)
        );
    }
    super::html::static_page("Validation trends over the folder", &s)
}

#[cfg(test)]
mod tests {
    #[test]
    fn least_squares_line() {
        let (a, b) = super::line(&[10.0, 20.0, 40.0], &[3.0, 5.0, 9.0]).unwrap();
        assert!((a - 1.0).abs() < 1e-12 && (b - 0.2).abs() < 1e-12);
        assert!(super::line(&[5.0, 5.0], &[1.0, 2.0]).is_none());
    }
}
