//! True speed from the foils and the obstacle time from the photocell.
//!
//! The foil positions are surveyed (exact) and the pulse times carry the timing error,
//! so the fit is t = t0 + x / v by least squares in t (time regressed on position).

use super::descriptor::Trigger;
use super::ValidateError;

/// Speed from the foils by least squares.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FoilSpeed {
    /// [m/s]
    pub speed_mps: f64,
    /// RMS residual of the pulse times about the fitted line [s].
    pub residual_rms_s: f64,
}

/// Fits t = t0 + x / v through (position [m], time [s]) pairs.
pub fn speed_from_foils(foils: &[(f64, f64)]) -> Result<FoilSpeed, ValidateError> {
    let n = foils.len() as f64;
    if foils.len() < 2 {
        return Err(ValidateError::Signal(
            "at least two foils are needed".into(),
        ));
    }
    let mx = foils.iter().map(|f| f.0).sum::<f64>() / n;
    let mt = foils.iter().map(|f| f.1).sum::<f64>() / n;
    let sxx: f64 = foils.iter().map(|f| (f.0 - mx).powi(2)).sum();
    let sxt: f64 = foils.iter().map(|f| (f.0 - mx) * (f.1 - mt)).sum();
    if sxx <= 0.0 {
        return Err(ValidateError::Signal(
            "the foils must be at different positions".into(),
        ));
    }
    let slope = sxt / sxx; // s/m
    if !slope.is_finite() || slope <= 0.0 {
        return Err(ValidateError::Signal(format!(
            "the pulse times do not increase along the road (fitted {slope:.4e} s/m): the car must pass the foils in +x order"
        )));
    }
    let t0 = mt - slope * mx;
    let ss: f64 = foils.iter().map(|f| (f.1 - t0 - slope * f.0).powi(2)).sum();
    Ok(FoilSpeed {
        speed_mps: 1.0 / slope,
        residual_rms_s: (ss / n).sqrt(),
    })
}

/// When the front wheels reach the obstacle start on the recording's clock, from the
/// photocell pulse and the speed.
pub fn obstacle_time(trigger: &Trigger, speed_mps: f64) -> f64 {
    trigger.photocell_time_s - trigger.photocell_position_m / speed_mps
}
