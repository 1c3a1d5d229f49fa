//! Axis ticks and their labels: round steps (1, 2, 5 times a power of ten) on linear
//! axes, decades on log axes, labels with as many decimals as the step needs, no `.0` on
//! integers, and powers of ten outside 0.001..999999 so that a 1e-7 span reads
//! "2×10⁻⁸, 4×10⁻⁸, ..." rather than "0.0, 0.0, ...". Never SI prefixes: on an axis of
//! seconds "10m" reads as ten minutes, and the unit is in the axis label already.

/// Ticks of a linear axis over `lo..hi`: the round step with at most `max_ticks` ticks,
/// or the next finer one when that step leaves fewer than two ticks inside the range
/// (one labelled tick gives no scale: 1.2e5..9e5 at three ticks would label 5e5 alone);
/// at least one tick whatever the range.
pub fn linear(lo: f64, hi: f64, max_ticks: usize) -> (Vec<f64>, f64) {
    let span = (hi - lo).abs().max(f64::MIN_POSITIVE);
    let base = 10f64.powf((span / max_ticks.max(1) as f64).log10().floor());
    let steps = [1.0, 2.0, 5.0, 10.0, 20.0, 50.0].map(|m| base * m);
    let k = steps
        .iter()
        .position(|s| span / s <= max_ticks as f64)
        .unwrap_or(steps.len() - 1);
    let mut step = steps[k];
    let mut ticks = with_step(lo, hi, step);
    if ticks.len() < 2 && k > 0 {
        let finer = with_step(lo, hi, steps[k - 1]);
        if finer.len() >= 2 {
            (ticks, step) = (finer, steps[k - 1]);
        }
    }
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

/// `10ⁿ` with a superscript exponent.
pub fn pow10(e: i32) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::from("10");
    if e < 0 {
        s.push('⁻');
    }
    for d in e.unsigned_abs().to_string().bytes() {
        s.push(SUP[(d - b'0') as usize]);
    }
    s
}

/// `x` with `decimals` decimals, trailing zeros and a trailing point dropped, a true
/// minus sign.
fn decimal(x: f64, decimals: usize) -> String {
    let mut s = format!("{x:.decimals$}");
    if s.contains('.') {
        s = s.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    s.replace('-', "\u{2212}")
}

/// Whether a label of `v` needs a power of ten (outside 0.001..999999: "20000 N" reads
/// at a glance, "0.00002" does not).
fn needs_power(v: f64) -> bool {
    v != 0.0 && v.is_finite() && !(1e-3..1e6).contains(&v.abs())
}

/// Labels for linear ticks spaced `step` apart: as many decimals as the step needs, no
/// trailing zeros (1, 1.5, 2); when the largest tick is 1e6 or more or below 1e-3, every
/// label in units of the largest tick's power of ten (0.5×10⁻⁷, 1×10⁻⁷).
pub fn labels(ticks: &[f64], step: f64) -> Vec<String> {
    let big = ticks.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let e = if needs_power(big) {
        big.log10().floor() as i32
    } else {
        0
    };
    let scale = 10f64.powi(e);
    let decimals = (-((step / scale).log10() + 1e-9).floor()).max(0.0) as usize;
    ticks
        .iter()
        .map(|&t| {
            if t.abs() < step * 1e-6 {
                return "0".to_string();
            }
            let m = decimal(t / scale, decimals);
            if e == 0 {
                m
            } else {
                format!("{m}×{}", pow10(e))
            }
        })
        .collect()
}

/// Labels of log-axis ticks: all as powers of ten when any of them needs one, so that
/// one axis does not mix "0.002" with "5×10⁻⁴".
pub fn log_labels(ticks: &[f64], sig: usize) -> Vec<String> {
    let powers = ticks.iter().any(|v| needs_power(*v));
    ticks.iter().map(|&v| sci_with(v, sig, powers)).collect()
}

fn sci_with(v: f64, sig: usize, always_power: bool) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let e = v.abs().log10().floor() as i32;
    let sig_decimals = |x: f64| (sig as i32 - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    if !always_power && !needs_power(v) {
        return decimal(v, sig_decimals(v));
    }
    let m = decimal(v / 10f64.powi(e), sig_decimals(v / 10f64.powi(e)));
    match m.as_str() {
        // A decade reads 10ⁿ, not 1×10ⁿ.
        "1" => pow10(e),
        "\u{2212}1" => format!("\u{2212}{}", pow10(e)),
        _ => format!("{m}×{}", pow10(e)),
    }
}
