//! Axis ticks and their labels: round steps (1, 2, 5 times a power of ten) on linear
//! axes, decades on log axes, labels with as many decimals as the step needs, no `.0` on
//! integers, and SI prefixes (k, M, m, µ, n, ...) outside 0.001..9999 so that a 1e-7 span
//! reads "20n, 40n, ..." rather than "0.0, 0.0, ...".

/// Ticks of a linear axis over `lo..hi`: the round step with at most `max_ticks` ticks
/// (at least one tick whatever the range).
pub fn linear(lo: f64, hi: f64, max_ticks: usize) -> (Vec<f64>, f64) {
    let span = (hi - lo).abs().max(f64::MIN_POSITIVE);
    let mut step = 10f64.powf((span / max_ticks.max(1) as f64).log10().floor());
    for m in [1.0, 2.0, 5.0, 10.0, 20.0, 50.0] {
        let s = step * m;
        if span / s <= max_ticks as f64 {
            step = s;
            break;
        }
    }
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    let ticks: Vec<f64> = (first..=last).map(|k| k as f64 * step).collect();
    if ticks.is_empty() {
        return (vec![0.5 * (lo + hi)], step);
    }
    (ticks, step)
}

/// The next coarser round step after `step` (1 -> 2 -> 5 -> 10).
pub fn coarser(step: f64) -> f64 {
    let e = 10f64.powf(step.log10().floor());
    let m = (step / e).round();
    if m < 2.0 {
        2.0 * e
    } else if m < 5.0 {
        5.0 * e
    } else {
        10.0 * e
    }
}

/// Ticks over `lo..hi` with a given step.
pub fn with_step(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// Ticks of a log axis over `lo..hi` (positive values): decades, with 2 and 5 between
/// them when the range spans fewer than three decades; a range inside a decade gets
/// every multiple it holds, or round linear steps, never fewer than two ticks.
pub fn log(lo: f64, hi: f64) -> Vec<f64> {
    let (a, b) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let mults: &[f64] = if b - a < 3 { &[1.0, 2.0, 5.0] } else { &[1.0] };
    let step = ((b - a) as usize).div_ceil(8).max(1);
    let mut v = Vec::new();
    let inside = |x: &f64| *x >= lo * (1.0 - 1e-9) && *x <= hi * (1.0 + 1e-9);
    for e in (a..=b).step_by(step) {
        v.extend(mults.iter().map(|m| m * 10f64.powi(e)).filter(inside));
    }
    if v.len() < 2 {
        // A range inside a decade (wall times 0.24 to 0.46 s): every multiple, else round
        // linear steps, so that the axis keeps at least two labelled ticks.
        v = (a..=b)
            .flat_map(|e| (1..10).map(move |m| m as f64 * 10f64.powi(e)))
            .filter(inside)
            .collect();
        if v.len() < 2 {
            v = linear(lo, hi, 5).0;
        }
    }
    v
}

const PREFIXES: [(i32, &str); 11] = [
    (-15, "f"),
    (-12, "p"),
    (-9, "n"),
    (-6, "µ"),
    (-3, "m"),
    (0, ""),
    (3, "k"),
    (6, "M"),
    (9, "G"),
    (12, "T"),
    (15, "P"),
];

/// Labels for linear ticks spaced `step` apart: as many decimals as the step needs, no
/// trailing zeros (1, 1.5, 2), with an SI prefix when the largest tick is 1e4 or more or below 1e-3.
pub fn labels(ticks: &[f64], step: f64) -> Vec<String> {
    let big = ticks.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let e = if big > 0.0 {
        big.log10().floor() as i32
    } else {
        0
    };
    let p = if (-3..4).contains(&e) {
        0
    } else {
        (3 * e.div_euclid(3)).clamp(-15, 15)
    };
    let prefix = PREFIXES.iter().find(|(q, _)| *q == p).map_or("", |x| x.1);
    let scale = 10f64.powi(p);
    let decimals = (-((step / scale).log10() + 1e-9).floor()).max(0.0) as usize;
    ticks
        .iter()
        .map(|&t| {
            if t.abs() < step * 1e-6 {
                return "0".to_string();
            }
            let mut s = format!("{:.*}", decimals, t / scale);
            if s.contains('.') {
                s = s.trim_end_matches('0').trim_end_matches('.').to_string();
            }
            format!("{}{prefix}", s.replace('-', "\u{2212}"))
        })
        .collect()
}

/// One value with an SI prefix and `sig` significant digits, trailing zeros dropped
/// (log-axis labels, table entries): 2.5e-5 -> "25µ", 3000 -> "3k", 0.5 -> "0.5".
pub fn si(v: f64, sig: usize) -> String {
    si_with(v, sig, false)
}

/// Labels of log-axis ticks: all with an SI prefix when any of them needs one, so that
/// one axis does not mix "0.002" with "500µ".
pub fn log_labels(ticks: &[f64], sig: usize) -> Vec<String> {
    let prefixed = ticks
        .iter()
        .any(|v| *v != 0.0 && !(1e-3..1e4).contains(&v.abs()));
    ticks.iter().map(|&v| si_with(v, sig, prefixed)).collect()
}

fn si_with(v: f64, sig: usize, always_prefix: bool) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let e = v.abs().log10().floor() as i32;
    let p = if (-3..4).contains(&e) && !always_prefix {
        0
    } else {
        3 * e.div_euclid(3)
    };
    let Some((_, prefix)) = PREFIXES.iter().find(|(q, _)| *q == p) else {
        return format!("{v:.*e}", sig.saturating_sub(1)).replace('-', "\u{2212}");
    };
    let x = v / 10f64.powi(p);
    let decimals = (sig as i32 - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    let mut s = format!("{x:.decimals$}");
    if s.contains('.') {
        s = s.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    format!("{}{prefix}", s.replace('-', "\u{2212}"))
}
