//! A force's ringing: max, min and |peak|, RMS, dominant frequency and the damping ratio
//! of its free decay (what the run summary reports of the hitch force).
//!
//! - Dominant frequency: the largest peak of the amplitude spectrum (mean removed, Hann
//!   window, [`crate::signal::spectrum::peak_in`]) between 1 Hz and 0.45 times the
//!   sample rate.
//! - Damping: the log decrement of the free decay, fitted. The ringing's frequency is
//!   the spectral peak of the half second centred on the force peak; the signal,
//!   low-passed at 2.5 times that frequency, less its running mean over one period of that frequency (which keeps that frequency and
//!   removes the slow trailer and body motion under it) is searched for its half-cycle
//!   extremes from the largest peak on. The decay starts at the largest of the first four
//!   extremes (the obstacle may still force the first cycle) and runs while each extreme
//!   is smaller than the one before and above 5 % of the first; a least-squares line
//!   through ln|extreme| against time gives the decay rate sigma, and
//!   zeta = sigma / sqrt(sigma^2 + omega_d^2) with omega_d from the extremes' spacing.
//!   At least four half cycles are needed, otherwise no damping is reported.

use serde::Serialize;

/// The ringing of one channel.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Ringing {
    /// The channel.
    pub channel: String,
    /// Largest value [N].
    pub max_n: f64,
    /// Its time [s].
    pub t_max_s: f64,
    /// Smallest value [N].
    pub min_n: f64,
    /// Its time [s].
    pub t_min_s: f64,
    /// The larger magnitude, max(|max|, |min|) [N]: where the free decay starts.
    pub abs_peak_n: f64,
    /// Its time [s].
    pub t_abs_peak_s: f64,
    /// Root mean square over the run [N].
    pub rms_n: f64,
    /// Peak of the amplitude spectrum [Hz].
    pub dominant_hz: Option<f64>,
    /// Fraction of critical damping of the free decay after the peak.
    pub damping_ratio: Option<f64>,
    /// The decay the damping was fitted on.
    pub decay: Option<Decay>,
}

/// The stretch of free decay fitted.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Decay {
    /// First extreme used [s].
    pub from_s: f64,
    /// Last extreme used [s].
    pub to_s: f64,
    /// Half cycles (extremes) in the fit.
    pub half_cycles: usize,
    /// Damped frequency from the extremes' spacing [Hz].
    pub frequency_hz: f64,
    /// Coefficient of determination of the log-amplitude line.
    pub fit_r2: f64,
}

/// Extremes, RMS, dominant frequency and damping of `y` (samples at times `t`, uniform).
pub fn ringing(channel: &str, t: &[f64], y: &[f64]) -> Option<Ringing> {
    let n = y.len().min(t.len());
    if n < 8 {
        return None;
    }
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let ext = super::Extremes::of(&t[..n], y[..n].iter().copied());
    if ext.abs_peak.is_nan() {
        return None;
    }
    // The sample of largest magnitude: the decay is searched from there.
    let (k_peak, _) = y[..n]
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    let rms = (y[..n].iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
    let dominant = crate::signal::spectrum::peak_in(&y[..n], dt, [1.0, 0.45 / dt]);
    // The ringing's own frequency: the spectrum of half a second centred on the peak
    // (Hann-weighted there), where the ringing outweighs slower motion of larger energy
    // over the whole run.
    let w = ((0.25 / dt).round() as usize).max(8);
    let (a, b) = (k_peak.saturating_sub(w), (k_peak + w + 1).min(n));
    let local = crate::signal::spectrum::peak_in(&y[a..b], dt, [1.0, 0.45 / dt]);
    let decay = local.and_then(|f| free_decay(&t[..n], &y[..n], f, k_peak));
    Some(Ringing {
        channel: channel.into(),
        max_n: ext.max,
        t_max_s: ext.t_max,
        min_n: ext.min,
        t_min_s: ext.t_min,
        abs_peak_n: ext.abs_peak,
        t_abs_peak_s: ext.t_abs_peak,
        rms_n: rms,
        dominant_hz: dominant,
        damping_ratio: decay.as_ref().map(|d| d.1),
        decay: decay.map(|d| d.0),
    })
}

/// The free decay of `y` at about `f_hz` from sample `from` on: the fitted stretch and
/// its damping ratio.
pub fn free_decay(t: &[f64], y: &[f64], f_hz: f64, from: usize) -> Option<(Decay, f64)> {
    let n = y.len();
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let period = (1.0 / (f_hz * dt)).round() as usize;
    if period < 4 || 4 * period > n {
        return None;
    }
    // Higher modes (a flexible hitch's, hundreds of Hz) off by a low-pass at 2.5 times
    // the ringing (fourth-order Butterworth: its delay shifts the extremes in time, not
    // their decay), then less the centred running mean over one period.
    let rate = 1.0 / dt;
    let y = match crate::signal::butterworth::Butterworth::low_pass(
        4,
        (2.5 * f_hz).min(0.4 * rate),
        rate,
    ) {
        Ok(lp) => lp.apply(y),
        Err(_) => y.to_vec(),
    };
    let half = period / 2;
    let mut prefix = vec![0.0; n + 1];
    for k in 0..n {
        prefix[k + 1] = prefix[k] + y[k];
    }
    let x: Vec<f64> = (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(half), (k + half + 1).min(n));
            y[k] - (prefix[b] - prefix[a]) / (b - a) as f64
        })
        .collect();
    // Half-cycle extremes: the largest |x| within a quarter period either side.
    let q = (period / 4).max(1);
    let mut ext: Vec<(f64, f64)> = Vec::new();
    let mut k = from.max(q);
    while k + q < n && ext.len() < 80 {
        let win = &x[k - q..=k + q];
        let (j, v) = win
            .iter()
            .copied()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
        if j == q && v != 0.0 {
            // Parabolic refinement of the extreme's time and height.
            let (a, b, c) = (x[k - 1].abs(), v.abs(), x[k + 1].abs());
            let den = a - 2.0 * b + c;
            let (d, h) = if den < 0.0 {
                let d = (0.5 * (a - c) / den).clamp(-0.5, 0.5);
                (d, b - 0.25 * (a - c) * d)
            } else {
                (0.0, b)
            };
            ext.push((t[k] + d * dt, h));
            k += q + 1;
        } else {
            k += 1;
        }
    }
    let start = (0..ext.len().min(4)).max_by(|&a, &b| ext[a].1.total_cmp(&ext[b].1))?;
    let mut used = vec![ext[start]];
    for e in &ext[start + 1..] {
        let last = used[used.len() - 1].1;
        if e.1 >= last || e.1 < 0.05 * used[0].1 {
            break;
        }
        used.push(*e);
    }
    if used.len() < 4 {
        return None;
    }
    let m = used.len() as f64;
    let (st, sl) = used
        .iter()
        .fold((0.0, 0.0), |s, e| (s.0 + e.0, s.1 + e.1.ln()));
    let (mt, ml) = (st / m, sl / m);
    let (mut stt, mut stl, mut sll) = (0.0, 0.0, 0.0);
    for e in &used {
        let (a, b) = (e.0 - mt, e.1.ln() - ml);
        stt += a * a;
        stl += a * b;
        sll += b * b;
    }
    let sigma = -stl / stt;
    let (t0, t1) = (used[0].0, used[used.len() - 1].0);
    let fd = (m - 1.0) / (2.0 * (t1 - t0));
    let wd = 2.0 * std::f64::consts::PI * fd;
    if sigma.is_nan() || sigma <= 0.0 || !wd.is_finite() {
        return None;
    }
    let zeta = sigma / (sigma * sigma + wd * wd).sqrt();
    let r2 = if sll > 0.0 {
        stl * stl / (stt * sll)
    } else {
        1.0
    };
    Some((
        Decay {
            from_s: t0,
            to_s: t1,
            half_cycles: used.len(),
            frequency_hz: fd,
            fit_r2: r2,
        },
        zeta,
    ))
}
