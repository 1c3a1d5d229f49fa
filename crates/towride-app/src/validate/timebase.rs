//! The time base of a recording: its time column as written, a time column coarser than
//! the sampling rebuilt from the row count, or a declared sample rate.
//!
//! A logger sampling at 5 kHz that prints time to 1 ms writes five rows per stamp; they
//! are not repeated samples. When at least 30 % of the rows repeat the stamp before
//! them the column is taken as quantised: the rate is the rows of the whole interior
//! stamps (the first and last may be cut) over their span, rounded to a whole hertz when
//! that lies within two rows of it (or the declared rate when given and within 1 %), and
//! the clock t_k = t0 + k / fs is placed so that every stamp is its row's time rounded to
//! the stamp step (t0 the middle of the interval all rows allow).

use serde::Serialize;

/// Where the sample times come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TimeBaseKind {
    /// The time column as written.
    Column,
    /// A quantised time column, rebuilt from the row count and the column's span.
    Reconstructed,
    /// No time column: the declared sample rate from the first row.
    Declared,
}

/// How the time base was found.
#[derive(Clone, Debug, Serialize)]
pub struct TimeBase {
    /// Where the times come from.
    pub kind: TimeBaseKind,
    /// Sample rate [Hz].
    pub rate_hz: f64,
    /// Step of the time column's stamps [s] (reconstructed only).
    pub stamp_step_s: Option<f64>,
    /// Mean rows per stamp (reconstructed only).
    pub rows_per_stamp: Option<f64>,
}

/// A row's stamp did not fit: (row index, message).
pub type Misfit = (usize, String);

/// Rebuilds the clock of `stamps` (one per row, non-decreasing) when they are
/// quantised; `None` when they are not. `declared`: the descriptor's sample rate.
pub fn reconstruct(
    stamps: &[f64],
    declared: Option<f64>,
) -> Result<Option<(Vec<f64>, TimeBase, String)>, Misfit> {
    let n = stamps.len();
    if n < 10 {
        return Ok(None);
    }
    let repeats = stamps.windows(2).filter(|w| w[1] == w[0]).count();
    if (repeats as f64) < 0.3 * (n - 1) as f64 {
        return Ok(None);
    }
    if let Some(k) = stamps.windows(2).position(|w| w[1] < w[0]) {
        return Err((
            k + 1,
            format!("time goes back from {} s to {} s", stamps[k], stamps[k + 1]),
        ));
    }
    // Groups of equal stamps: (first row, count).
    let mut groups: Vec<(usize, usize)> = Vec::new();
    for (k, t) in stamps.iter().enumerate() {
        match groups.last_mut() {
            Some((first, count)) if stamps[*first] == *t => *count += 1,
            _ => groups.push((k, 1)),
        }
    }
    let g = groups.len();
    if g < 4 {
        return Err((
            0,
            format!("only {g} distinct stamps: too few to rebuild the clock"),
        ));
    }
    let mut steps: Vec<f64> = groups
        .windows(2)
        .map(|w| stamps[w[1].0] - stamps[w[0].0])
        .collect();
    steps.sort_by(f64::total_cmp);
    let step = steps[steps.len() / 2];
    // A stamp with no row means rows are missing: the row count cannot be the clock.
    for w in groups.windows(2) {
        let d = stamps[w[1].0] - stamps[w[0].0];
        if d > 1.5 * step {
            return Err((
                w[1].0,
                format!(
                    "no row is stamped between {} s and {} s (stamp step {step} s): rows are missing, the clock cannot be rebuilt from the row count",
                    stamps[w[0].0], stamps[w[1].0]
                ),
            ));
        }
    }
    let rows: usize = groups[1..g - 1].iter().map(|x| x.1).sum();
    let span = stamps[groups[g - 1].0] - stamps[groups[1].0];
    let estimate = rows as f64 / span;
    let (rate, how) = match declared {
        Some(r) if (estimate / r - 1.0).abs() < 0.01 => (r, format!("the declared {r} Hz")),
        Some(r) => {
            return Err((
                groups[1].0,
                format!("the stamps give {estimate:.3} Hz ({rows} rows in {span} s) but the descriptor declares {r} Hz"),
            ))
        }
        None if (estimate - estimate.round()).abs() <= 2.0 / span => (
            estimate.round(),
            format!("{estimate:.3} Hz rounded to the whole hertz"),
        ),
        None => (estimate, format!("{estimate:.3} Hz")),
    };
    // Stamps rounded to the step: t0 + k / fs lies within half a step of stamp k.
    let a: Vec<f64> = (0..n).map(|k| stamps[k] - k as f64 / rate).collect();
    let lo = a.iter().copied().fold(f64::NEG_INFINITY, f64::max) - 0.5 * step;
    let hi = a.iter().copied().fold(f64::INFINITY, f64::min) + 0.5 * step;
    let t0 = 0.5 * (lo + hi);
    let misfit = (lo - hi).max(0.0);
    if misfit > step {
        let worst = (0..n)
            .max_by(|&i, &j| (a[i] - t0).abs().total_cmp(&(a[j] - t0).abs()))
            .unwrap_or(0);
        return Err((
            worst,
            format!(
                "the stamps do not fit one clock at {rate} Hz (off by {:.3} ms here): rows missing or repeated?",
                (a[worst] - t0).abs() * 1e3
            ),
        ));
    }
    let times: Vec<f64> = (0..n).map(|k| t0 + k as f64 / rate).collect();
    let per = n as f64 / g as f64;
    let mut note = format!(
        "time column quantised to {:.3} ms ({per:.2} rows per stamp): time base rebuilt from the row count, {n} rows at {how}, stamps taken as rounded to the nearest step",
        step * 1e3
    );
    if misfit > 0.0 {
        note.push_str(&format!(" (largest misfit {:.3} ms)", misfit * 1e3));
    }
    Ok(Some((
        times,
        TimeBase {
            kind: TimeBaseKind::Reconstructed,
            rate_hz: rate,
            stamp_step_s: Some(step),
            rows_per_stamp: Some(per),
        },
        note,
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 5 kHz rows stamped to the nearest millisecond, starting mid-stamp.
    fn stamps(rate: f64, n: usize, t0: f64) -> Vec<f64> {
        (0..n)
            .map(|k| ((t0 + k as f64 / rate) * 1e3).round() / 1e3)
            .collect()
    }

    #[test]
    fn rebuilds_a_5_khz_clock_from_millisecond_stamps() {
        let s = stamps(5000.0, 12_345, 0.1234);
        let (t, tb, note) = reconstruct(&s, None).unwrap().unwrap();
        assert_eq!(tb.rate_hz, 5000.0);
        assert_eq!(tb.kind, TimeBaseKind::Reconstructed);
        for (k, tk) in t.iter().enumerate() {
            assert!(
                (tk - (0.1234 + k as f64 / 5000.0)).abs() <= 1e-4 + 1e-12,
                "{k}"
            );
        }
        assert!(note.contains("rebuilt"), "{note}");
        // 2.4 kHz: 2 or 3 rows per stamp.
        let s = stamps(2400.0, 10_000, 0.0);
        let (_, tb, _) = reconstruct(&s, None).unwrap().unwrap();
        assert_eq!(tb.rate_hz, 2400.0);
        // Distinct stamps are not quantised.
        let s: Vec<f64> = (0..100).map(|k| k as f64 * 1e-3).collect();
        assert!(reconstruct(&s, None).unwrap().is_none());
        // A missing block of rows is an error, not a wrong clock.
        let mut s = stamps(5000.0, 5000, 0.0);
        s.drain(2000..2030);
        assert!(reconstruct(&s, None).is_err());
    }
}
