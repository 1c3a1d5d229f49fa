//! Command-line numbers checked against the library's plausibility table
//! (`towride_mbs::input::bounds`) as clap parses them, so `--step 0`, `--step nan` or
//! `--at 1e300` are refused with the option's name and the accepted range before any
//! work starts (they used to hang: an SVD of a non-finite matrix, a run of 1e300 s).

use towride_mbs::input::bounds::{self, Bound};

fn number(s: &str, b: &Bound, zero: bool) -> Result<f64, String> {
    let v: f64 = s.trim().parse().map_err(|e| format!("not a number: {e}"))?;
    if v == 0.0 && !zero {
        return Err(format!(
            "must not be 0; accepted: |value| in [{:e}, {:e}] {}",
            b.min, b.max, b.unit
        ));
    }
    b.check(v).map_err(|e| e.message)
}

fn non_negative(s: &str, key: &str, zero: bool) -> Result<f64, String> {
    let v = number(s, bounds::for_key(key), zero)?;
    if v < 0.0 {
        return Err(format!("must not be negative, got {v}"));
    }
    Ok(v)
}

/// A step size [s] (`--step`).
pub fn step_s(s: &str) -> Result<f64, String> {
    non_negative(s, "dt_s", false)
}

/// A time [s] (`--at`).
pub fn time_s(s: &str) -> Result<f64, String> {
    non_negative(s, "time_s", true)
}

/// A time [ms] (`--max-shift-ms`, `--trigger-delay-ms`, `--foil-jitter-ms`).
pub fn time_ms(s: &str) -> Result<f64, String> {
    Ok(non_negative(&scaled(s, 1e-3)?, "time_s", true)? * 1e3)
}

fn scaled(s: &str, by: f64) -> Result<String, String> {
    let v: f64 = s.trim().parse().map_err(|e| format!("not a number: {e}"))?;
    Ok((v * by).to_string())
}

/// A relative tolerance (`--tol`, `--rtol`, `--reference-tol`).
pub fn tolerance(s: &str) -> Result<f64, String> {
    non_negative(s, "rtol", false)
}

/// A speed [km/h] (`--speed-kmh`).
pub fn speed_kmh(s: &str) -> Result<f64, String> {
    non_negative(s, "speed_km_h", false)
}

/// A frequency [Hz] (`--cutoff`, `--band`, `--rate-hz`, `--cutoff-hz`).
pub fn hz(s: &str) -> Result<f64, String> {
    non_negative(s, "cutoff_hz", true)
}

/// A sample rate or cut-off [Hz], not 0 (`--rate-hz`, `--cutoff-hz`).
pub fn rate_hz(s: &str) -> Result<f64, String> {
    non_negative(s, "rate_hz", false)
}

/// A share [%], above 0 (`--share`).
pub fn share_pct(s: &str) -> Result<f64, String> {
    non_negative(s, "error_pct", false)
}

/// A signed percentage (`--speed-error-pct`, `--gain-error-pct`).
pub fn pct(s: &str) -> Result<f64, String> {
    number(s, bounds::for_key("error_pct"), true)
}

/// An acceleration [m/s^2] (`--noise-rms-mps2`).
pub fn mps2(s: &str) -> Result<f64, String> {
    non_negative(s, "noise_rms_mps2", true)
}

/// Worker threads (`--jobs`): 1 to 1024.
pub fn jobs(s: &str) -> Result<usize, String> {
    let n: usize = s.trim().parse().map_err(|e| format!("not a count: {e}"))?;
    if (1..=1024).contains(&n) {
        Ok(n)
    } else {
        Err(format!("must lie in 1..=1024, got {n}"))
    }
}

/// A count of modes or a filter order (`--fixed-modes`, `--filter-order`).
pub fn count(s: &str) -> Result<usize, String> {
    let n: usize = s.trim().parse().map_err(|e| format!("not a count: {e}"))?;
    number(s, bounds::for_key("fixed_interface_modes"), true)?;
    Ok(n)
}

/// Morris trajectories (`--trajectories`): the library's bounds (2: sigma needs two
/// elementary effects; 1000).
pub fn trajectories(s: &str) -> Result<usize, String> {
    use towride_app::study::sensitivity::{MAX_TRAJECTORIES, MIN_TRAJECTORIES};
    let n: usize = s.trim().parse().map_err(|e| format!("not a count: {e}"))?;
    if (MIN_TRAJECTORIES..=MAX_TRAJECTORIES).contains(&n) {
        Ok(n)
    } else {
        Err(format!(
            "must lie in {MIN_TRAJECTORIES}..={MAX_TRAJECTORIES} (Morris needs two elementary effects per parameter for sigma), got {n}"
        ))
    }
}
