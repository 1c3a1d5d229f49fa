//! Plain per-channel figures: peak and its time, RMS of the difference, Pearson
//! correlation, and the least-squares amplitude ratio (an estimate of a gain error).

/// (value, time) of the largest magnitude.
pub fn peak(t: &[f64], y: &[f64]) -> (f64, f64) {
    let i = (0..y.len())
        .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
        .unwrap_or(0);
    (
        y.get(i).copied().unwrap_or(f64::NAN),
        t.get(i).copied().unwrap_or(f64::NAN),
    )
}

/// Root mean square of a - b.
pub fn rms_diff(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len()).max(1) as f64;
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / n).sqrt()
}

/// Pearson correlation coefficient (0 when either curve is constant).
pub fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n < 2 {
        return 0.0;
    }
    let (ma, mb) = (
        a[..n].iter().sum::<f64>() / n as f64,
        b[..n].iter().sum::<f64>() / n as f64,
    );
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a[..n].iter().zip(&b[..n]) {
        let (dx, dy) = (x - ma, y - mb);
        sab += dx * dy;
        saa += dx * dx;
        sbb += dy * dy;
    }
    if saa <= 0.0 || sbb <= 0.0 {
        0.0
    } else {
        sab / (saa * sbb).sqrt()
    }
}

/// The factor g minimising |measured - g simulated|^2: 1.05 means the measurement reads
/// 5 % higher than the simulation (a calibration error, or a model one).
pub fn gain_ratio(measured: &[f64], simulated: &[f64]) -> f64 {
    let ss: f64 = simulated.iter().map(|s| s * s).sum();
    if ss <= 0.0 {
        return f64::NAN;
    }
    measured
        .iter()
        .zip(simulated)
        .map(|(m, s)| m * s)
        .sum::<f64>()
        / ss
}
