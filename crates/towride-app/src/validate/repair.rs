//! Repairs of a recorded time series: a repeated sample (same time) is dropped, a short
//! gap in time is filled by linear interpolation, an empty cell is interpolated from its
//! column's neighbours; each repair leaves a note. Longer gaps and time running backwards
//! cannot be repaired and are errors at their line.

use std::path::Path;

use towride_mbs::input::InputError;

use super::csv_reader::{err, MAX_GAP_SAMPLES};

pub(super) type Repaired = (Vec<f64>, Vec<Vec<f64>>, Vec<String>);

/// Drops repeated samples, fills short time gaps and empty cells by linear interpolation.
pub(super) fn repair(
    file: &Path,
    rows: Vec<(usize, f64, Vec<Option<f64>>)>,
    nc: usize,
    tcol: usize,
    time_column: &str,
    names: &[&str],
) -> Result<Repaired, InputError> {
    // The caller refuses fewer than 10 rows, at their lines.
    debug_assert!(rows.len() >= 10);
    let mut dts: Vec<f64> = rows
        .windows(2)
        .map(|w| w[1].1 - w[0].1)
        .filter(|d| *d > 0.0)
        .collect();
    dts.sort_by(f64::total_cmp);
    let dt = dts.get(dts.len() / 2).copied().unwrap_or(0.0);
    if dt.is_nan() || dt <= 0.0 {
        return Err(err(
            file,
            Some(rows[0].0),
            Some(tcol),
            time_column,
            "time does not increase".into(),
        ));
    }
    let mut notes = Vec::new();
    let mut t: Vec<f64> = Vec::with_capacity(rows.len());
    let mut v: Vec<Vec<Option<f64>>> = vec![Vec::with_capacity(rows.len()); nc];
    let mut prev_line = rows[0].0;
    for (line, tr, vals) in rows {
        if let Some(&tp) = t.last() {
            let d = tr - tp;
            if d.abs() < 0.5 * dt {
                notes.push(format!(
                    "line {line}: repeated sample at t = {tr:.6} s (as line {prev_line}) dropped"
                ));
                continue;
            }
            if d < 0.0 {
                return Err(err(
                    file,
                    Some(line),
                    Some(tcol),
                    time_column,
                    format!("time goes back from {tp} s (line {prev_line}) to {tr} s"),
                ));
            }
            let missing = (d / dt).round() as usize - 1;
            if missing > MAX_GAP_SAMPLES {
                return Err(err(file, Some(line), Some(tcol), time_column, format!(
                    "{missing} samples missing after {tp} s (line {prev_line}); more than {MAX_GAP_SAMPLES} cannot be interpolated")));
            }
            if missing > 0 {
                notes.push(format!("line {line}: {missing} missing sample(s) between t = {tp:.6} s and {tr:.6} s interpolated"));
                for k in 1..=missing {
                    t.push(tp + d * k as f64 / (missing + 1) as f64);
                    v.iter_mut().for_each(|c| c.push(None));
                }
            }
        }
        for (c, x) in v.iter_mut().zip(&vals) {
            c.push(*x);
        }
        if vals.iter().any(|x| x.is_none()) {
            let which: Vec<&str> = vals
                .iter()
                .zip(names)
                .filter(|(x, _)| x.is_none())
                .map(|(_, n)| *n)
                .collect();
            notes.push(format!(
                "line {line}: empty value in {} interpolated",
                which.join(", ")
            ));
        }
        t.push(tr);
        prev_line = line;
    }
    let mut cols = Vec::with_capacity(nc);
    for (k, c) in v.into_iter().enumerate() {
        let known: Vec<(f64, f64)> = t
            .iter()
            .zip(&c)
            .filter_map(|(&ti, x)| x.map(|x| (ti, x)))
            .collect();
        if known.is_empty() {
            return Err(err(
                file,
                None,
                None,
                names[k],
                "column has no values".into(),
            ));
        }
        let (kt, kv): (Vec<f64>, Vec<f64>) = known.into_iter().unzip();
        cols.push(
            t.iter()
                .zip(&c)
                .map(|(&ti, x)| {
                    x.unwrap_or_else(|| crate::signal::butterworth::interp(&kt, &kv, ti))
                })
                .collect(),
        );
    }
    Ok((t, cols, notes))
}
