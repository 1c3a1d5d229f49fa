//! What `validate init` proposes for each sensor beyond its mapping: the fixed offset it
//! reads before the passage, and its range.
//!
//! **Offset.** A DC accelerometer reads gravity plus its own bias (zero-g offset, mounting
//! tilt) before the car reaches the obstacle, where the simulation's kinematic
//! acceleration is zero. The quiet part of the record is found in the accelerations
//! themselves: their combined envelope ([`super::passage::envelope`]: each channel less
//! its 0.05 s trailing mean, squared, averaged, smoothed) first rises above
//! max(4 x its median, 5 % of its peak), the passage detector's threshold; the window
//! ends [`QUIET_MARGIN_S`] before that. Each channel's offset is its median over the
//! window (a median, so a stray spike does not move it).
//!
//! **Range.** A clipped sensor holds its largest reading: the file's clipping level is
//! the largest |value| when it is held for [`PLATEAU_SAMPLES`] samples or more, in two
//! separate plateaus at least or at a standard range (within 1 %). One plateau alone is
//! what a slow, finely quantised peak also gives (a 1.3 Hz body motion of 0.15 g crosses
//! one step of a 16-bit +-50 g converter in about 17 ms around its top), so it is not
//! taken as clipping. Without a clipping level the proposed range is [`DEFAULT_RANGE_G`],
//! or the smallest standard range above the largest reading when that is higher.

use super::measurement::STANDARD_RANGES_G;
use super::passage::envelope;

/// The quiet window ends this long before the first rise [s].
pub const QUIET_MARGIN_S: f64 = 0.05;
/// A quiet window shorter than this gives no offset [s].
pub const QUIET_MIN_S: f64 = 0.1;
/// A reading held this many samples is a plateau.
pub const PLATEAU_SAMPLES: usize = 3;
/// The range proposed when the file shows no clipping [g]: a common range of the
/// piezoelectric and MEMS accelerometers used on wheel carriers (the largest reading of
/// a wheel over a 50 mm bump is a few tens of g).
pub const DEFAULT_RANGE_G: f64 = 50.0;

/// The quiet window before the passage, [start, end] in the times `t` of the
/// acceleration channels `acc` (any unit); `None` when there is none long enough.
pub fn quiet_window(t: &[f64], acc: &[&[f64]]) -> Option<[f64; 2]> {
    if acc.is_empty() || t.len() < 10 {
        return None;
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let env = envelope(acc, dt);
    let mut sorted: Vec<f64> = env.iter().copied().filter(|v| v.is_finite()).collect();
    if sorted.is_empty() {
        return None;
    }
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let peak = sorted[sorted.len() - 1];
    let thr = (4.0 * median).max(0.05 * peak);
    let first = env.iter().position(|v| *v > thr)?;
    let end = t[first] - QUIET_MARGIN_S;
    (end - t[0] >= QUIET_MIN_S).then_some([t[0], end])
}

/// Median of `v` over the samples whose time in `t` lies inside `w`.
pub fn median_in(t: &[f64], v: &[f64], w: [f64; 2]) -> Option<f64> {
    let mut s: Vec<f64> = t
        .iter()
        .zip(v)
        .filter(|(x, y)| **x >= w[0] && **x <= w[1] && y.is_finite())
        .map(|(_, y)| *y)
        .collect();
    if s.is_empty() {
        return None;
    }
    s.sort_by(f64::total_cmp);
    Some(s[s.len() / 2])
}

/// The file's clipping level of a channel read in g (module text), if it clips.
pub fn clip_level(values_g: &[f64]) -> Option<f64> {
    let top = values_g
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    if top == 0.0 {
        return None;
    }
    let at_top = |v: &f64| v.abs() >= top * (1.0 - 1e-9);
    let (mut plateaus, mut run) = (0, 0);
    for v in values_g {
        if at_top(v) {
            run += 1;
            if run == PLATEAU_SAMPLES {
                plateaus += 1;
            }
        } else {
            run = 0;
        }
    }
    let standard = STANDARD_RANGES_G
        .iter()
        .any(|r| (top / r - 1.0).abs() < 0.01);
    (plateaus >= 2 || (plateaus == 1 && standard)).then_some(top)
}

/// The range proposed for a channel that does not clip: [`DEFAULT_RANGE_G`], or the
/// smallest standard range above its largest reading `peak_g`.
pub fn default_range(peak_g: f64) -> f64 {
    STANDARD_RANGES_G
        .iter()
        .copied()
        .find(|r| *r >= DEFAULT_RANGE_G && *r > peak_g)
        .unwrap_or(peak_g)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plateaus_and_defaults() {
        // A sine clamped at 6 g: two plateaus per period.
        let clamped: Vec<f64> = (0..2000)
            .map(|k| (8.0 * (k as f64 * 0.01).sin()).clamp(-6.0, 6.0))
            .collect();
        assert_eq!(clip_level(&clamped), Some(6.0));
        // One flat top at 1.15 g (a quantised slow peak) is not clipping.
        let mut once: Vec<f64> = (0..2000).map(|k| (k as f64 * 0.001).sin()).collect();
        once[900..910].iter_mut().for_each(|v| *v = 1.15);
        assert_eq!(clip_level(&once), None);
        assert_eq!(default_range(3.0), 50.0);
        assert_eq!(default_range(70.0), 100.0);
    }
}
