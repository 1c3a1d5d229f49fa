//! `towride road`: samples a road along its two tracks (y = +-B/2), writes the profile
//! (`road_profile.csv`, `road_profile.png`) and, for an ISO 8608 random road, each track's
//! displacement PSD (Welch, [`crate::signal::psd`]) against the class band
//! (`road_psd.png`) with a verdict: the fraction of the PSD's frequency bins from 0.05 to
//! 2 cycles/m that lie between the class's lower and upper limits (ISO 8608:2016; see
//! `towride_mbs::road::random`).

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;
use towride_mbs::road::random::{class_band, N0};
use towride_mbs::road::{RandomSpec, Road};

use super::figure::{render, Axis, Figure, Panel, Style, Trace};
use crate::signal::psd::{segment_length, welch};

/// Version of the JSON document `towride road --json` prints.
pub const SCHEMA_VERSION: u32 = 1;

/// The spatial-frequency band of the verdict [cycles/m] (the must-show band).
pub const VERDICT_BAND: (f64, f64) = (0.05, 2.0);

/// Files this command writes into its folder.
pub const WRITES: [&str; 3] = ["road_profile.csv", "road_profile.png", "road_psd.png"];

/// What to sample.
#[derive(Clone, Debug)]
pub struct SampleRequest {
    /// First x [m].
    pub x_from: f64,
    /// Last x [m].
    pub x_to: f64,
    /// Spacing [m].
    pub dx: f64,
    /// Lateral distance of the tracks [m].
    pub track_width: f64,
}

/// The PSD of one track against the class band.
#[derive(Clone, Debug, Serialize)]
pub struct TrackPsd {
    /// Bins from 0.05 to 2 cycles/m.
    pub bins_in_band: usize,
    /// Of those, the fraction between the class's lower and upper limit [-].
    pub fraction_inside: f64,
    /// Gd(n0) of a least-squares line through log PSD vs log n over the band (the
    /// waviness held at the road's) [m^3].
    pub fitted_gd_n0_m3: f64,
}

/// The random road's PSD verdict.
#[derive(Clone, Debug, Serialize)]
pub struct PsdVerdict {
    /// ISO 8608 class letter, if the road names one.
    pub class: Option<char>,
    /// The class's geometric-mean Gd(n0) [m^3] (or the file's explicit value).
    pub gd_n0_m3: f64,
    /// Lower and upper class limit of Gd(n0) [m^3].
    pub lower_m3: f64,
    /// See `lower_m3`.
    pub upper_m3: f64,
    /// Waviness w [-].
    pub waviness: f64,
    /// The verdict's band [cycles/m].
    pub band_cycles_per_m: [f64; 2],
    /// Welch segment length [samples] and frequency resolution [cycles/m].
    pub welch_segment: usize,
    /// See `welch_segment`.
    pub resolution_cycles_per_m: f64,
    /// Left track.
    pub left: TrackPsd,
    /// Right track.
    pub right: TrackPsd,
    /// The figure.
    pub png: String,
}

/// The command's result.
#[derive(Clone, Debug, Serialize)]
pub struct RoadSampling {
    /// Version of this document.
    pub schema_version: u32,
    /// The road file.
    pub file: String,
    /// The road, described.
    pub road: String,
    /// Sampled range and spacing [m].
    pub x_from_m: f64,
    /// See `x_from_m`.
    pub x_to_m: f64,
    /// See `x_from_m`.
    pub dx_m: f64,
    /// Samples per track.
    pub samples: usize,
    /// Lateral distance of the tracks [m].
    pub track_width_m: f64,
    /// Extremes of the left and right track [m].
    pub z_left_min_m: f64,
    /// See `z_left_min_m`.
    pub z_left_max_m: f64,
    /// See `z_left_min_m`.
    pub z_right_min_m: f64,
    /// See `z_left_min_m`.
    pub z_right_max_m: f64,
    /// Files written.
    pub csv: String,
    /// See `csv`.
    pub png: String,
    /// Random roads: the PSD against the class band.
    pub psd: Option<PsdVerdict>,
}

/// Samples `road` as `req` asks and writes the files into `dir` (which must exist).
pub fn sample(
    road: &Road,
    file: &Path,
    req: &SampleRequest,
    dir: &Path,
) -> Result<RoadSampling, String> {
    let n = ((req.x_to - req.x_from) / req.dx).round() as usize + 1;
    if n < 2 {
        return Err(format!(
            "{}: nothing to sample: x {}..{} m",
            file.display(),
            req.x_from,
            req.x_to
        ));
    }
    let half = req.track_width / 2.0;
    let x: Vec<f64> = (0..n).map(|i| req.x_from + i as f64 * req.dx).collect();
    let zl: Vec<f64> = x.iter().map(|&xi| road.height(xi, half)).collect();
    let zr: Vec<f64> = x.iter().map(|&xi| road.height(xi, -half)).collect();
    let mut text = String::from("x [m],z_left [m],z_right [m]\n");
    for i in 0..n {
        let _ = writeln!(text, "{},{},{}", x[i], zl[i], zr[i]);
    }
    let csv = dir.join("road_profile.csv");
    crate::atomic::write(&csv, text).map_err(|e| format!("{}: {e}", csv.display()))?;
    let png = dir.join("road_profile.png");
    let pts = |z: &[f64]| x.iter().zip(z).map(|(&a, &b)| (a, b)).collect::<Vec<_>>();
    let panel = Panel::new(
        format!(
            "road profile: {}",
            file.file_name()
                .map_or(String::new(), |f| f.to_string_lossy().to_string())
        ),
        "x along the road [m]",
        "height z [m]",
    )
    .lines([
        (format!("left track (y = +{half} m)"), pts(&zl)),
        (format!("right track (y = -{half} m)"), pts(&zr)),
    ]);
    render(&png, &Figure::new(vec![panel], 1)).map_err(|e| e.to_string())?;
    let psd = match road.random_spec() {
        Some(spec) => Some(psd_verdict(
            spec,
            &zl,
            &zr,
            req.dx,
            &dir.join("road_psd.png"),
        )?),
        None => None,
    };
    let lo = |z: &[f64]| z.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = |z: &[f64]| z.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    Ok(RoadSampling {
        schema_version: SCHEMA_VERSION,
        file: file.display().to_string(),
        road: road.describe(),
        x_from_m: req.x_from,
        x_to_m: x[n - 1],
        dx_m: req.dx,
        samples: n,
        track_width_m: req.track_width,
        z_left_min_m: lo(&zl),
        z_left_max_m: hi(&zl),
        z_right_min_m: lo(&zr),
        z_right_max_m: hi(&zr),
        csv: csv.display().to_string(),
        png: png.display().to_string(),
        psd,
    })
}

/// Welch PSD of both tracks against the class band, the verdict and the figure.
fn psd_verdict(
    spec: &RandomSpec,
    zl: &[f64],
    zr: &[f64],
    dx: f64,
    png: &Path,
) -> Result<PsdVerdict, String> {
    let fs = 1.0 / dx;
    // The longest power-of-two segment that still gives four half-overlapping segments.
    let len = segment_length(zl.len(), 1 << 20);
    let (pl, pr) = match (welch(zl, fs, len), welch(zr, fs, len)) {
        (Some(a), Some(b)) => (a, b),
        _ => return Err(format!("road too short for a PSD: {} samples", zl.len())),
    };
    let (lower, upper) = class_band(spec.gd_n0);
    let w = spec.waviness;
    let shape = |n: f64| (n / N0).powf(-w);
    let judge = |p: &crate::signal::psd::Psd| {
        let (mut inside, mut total, mut sx, mut sy) = (0, 0, 0.0, 0.0);
        for (&n, &g) in p.freq.iter().zip(&p.density) {
            if n >= VERDICT_BAND.0 && n <= VERDICT_BAND.1 {
                total += 1;
                inside += usize::from(g >= lower * shape(n) && g <= upper * shape(n));
                // With w fixed, ln Gd(n0) is the mean of ln(G(n) / shape(n)).
                sx += 1.0;
                sy += (g / shape(n)).ln();
            }
        }
        TrackPsd {
            bins_in_band: total,
            fraction_inside: if total > 0 {
                inside as f64 / total as f64
            } else {
                0.0
            },
            fitted_gd_n0_m3: (sy / sx).exp(),
        }
    };
    let band_pts = |k: f64| -> Vec<(f64, f64)> {
        pl.freq
            .iter()
            .filter(|&&n| n > 0.0)
            .map(|&n| (n, k * spec.gd_n0 * shape(n)))
            .collect()
    };
    let curve = |p: &crate::signal::psd::Psd| -> Vec<(f64, f64)> {
        p.freq
            .iter()
            .zip(&p.density)
            .filter(|(&n, _)| n > 0.0)
            .map(|(&n, &g)| (n, g))
            .collect()
    };
    let name = spec
        .class
        .map_or(format!("Gd(n0) = {:e} m^3", spec.gd_n0), |c| {
            format!("class {c}")
        });
    let grey = [110, 110, 110];
    let red = Style {
        colour: [200, 0, 0],
        width: 1,
        dot: 0.0,
    };
    let mut panel = Panel::new(
        format!("displacement PSD (Welch, {len} samples) against ISO 8608 {name}; verdict band {}..{} cycles/m", VERDICT_BAND.0, VERDICT_BAND.1),
        "spatial frequency n [cycles/m]",
        "Gd(n) [m^3]",
    );
    panel.x = Axis::log("spatial frequency n [cycles/m]");
    panel.y = Axis::log("Gd(n) [m^3]");
    panel.traces = vec![
        Trace::new("left track", curve(&pl), Style::side(0, false)),
        Trace::new("right track", curve(&pr), Style::side(1, true)),
        Trace::new(
            format!(
                "{name} mean {:e} m^3 at n0 = 0.1 cycles/m, slope -{w}",
                spec.gd_n0
            ),
            band_pts(1.0),
            Style::line([0, 0, 0]),
        ),
        Trace::new(
            format!("lower limit {lower:e} m^3 at n0"),
            band_pts(0.5),
            Style {
                colour: grey,
                width: 1,
                dot: 0.0,
            },
        ),
        Trace::new(
            format!("upper limit {upper:e} m^3 at n0"),
            band_pts(2.0),
            Style {
                colour: grey,
                width: 1,
                dot: 0.0,
            },
        ),
        Trace::new(
            format!("verdict band from {} cycles/m", VERDICT_BAND.0),
            vec![
                (VERDICT_BAND.0, lower * shape(VERDICT_BAND.0) / 4.0),
                (VERDICT_BAND.0, upper * shape(VERDICT_BAND.0) * 4.0),
            ],
            red,
        ),
        Trace::new(
            format!("to {} cycles/m", VERDICT_BAND.1),
            vec![
                (VERDICT_BAND.1, lower * shape(VERDICT_BAND.1) / 4.0),
                (VERDICT_BAND.1, upper * shape(VERDICT_BAND.1) * 4.0),
            ],
            red,
        ),
    ];
    render(png, &Figure::new(vec![panel], 1)).map_err(|e| e.to_string())?;
    Ok(PsdVerdict {
        class: spec.class,
        gd_n0_m3: spec.gd_n0,
        lower_m3: lower,
        upper_m3: upper,
        waviness: w,
        band_cycles_per_m: [VERDICT_BAND.0, VERDICT_BAND.1],
        welch_segment: len,
        resolution_cycles_per_m: fs / len as f64,
        left: judge(&pl),
        right: judge(&pr),
        png: png.display().to_string(),
    })
}
