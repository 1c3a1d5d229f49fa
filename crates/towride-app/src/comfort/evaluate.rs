//! The comfort evaluation of one measuring point: each axis weighted (Wd for x and y,
//! Wk for z, ISO 2631-1 Table 1) and measured (a_w, VDV, MTVV, crest factor), and the
//! vibration total value a_v of the three axes (eq. 9). Used by `towride comfort` on a
//! CSV and by the run summary on the floor point under the driver's seat.

use serde::Serialize;

use super::record::{Axis, Channel};
use super::{combined, Assessment, Measures, Weighting, WeightingFilter};

/// Why a point cannot be evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ComfortError {
    /// The rate is too low for the weighting's 100 Hz band limit.
    #[error("{rate_hz} Hz is too low for {weighting:?}: its band-limiting corners (up to 100 Hz) must lie below the Nyquist frequency, so record above 200 Hz")]
    RateTooLow {
        /// Sample rate [Hz].
        rate_hz: f64,
        /// The weighting.
        weighting: Weighting,
    },
    /// A channel without samples.
    #[error("channel `{0}` has no samples")]
    Empty(String),
}

/// One axis's result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AxisComfort {
    /// The channel (column) evaluated.
    pub channel: String,
    /// Its unit as read (`m/s^2`, `g`); the measures are in SI.
    pub unit: String,
    /// The axis.
    pub axis: Axis,
    /// The weighting applied.
    pub weighting: Weighting,
    /// The axis's multiplying factor in the total value [-].
    pub k: f64,
    /// a_w, VDV, MTVV, peak, crest factor, duration.
    #[serde(flatten)]
    pub measures: Measures,
    /// Whether the r.m.s. method may underestimate ([`Measures::transient`]).
    pub transient: bool,
    /// The weighted peak is below [`RESOLUTION_M_S2`]: the axis carries round-off (the
    /// lateral axis of a straight, symmetric run), not vibration; its figures are no
    /// result and its crest factor and transient flag mean nothing.
    pub below_resolution: bool,
}

/// Smallest weighted peak an axis must reach to be a result [m/s^2]: an accelerometer's
/// noise floor class, the same floor `job::convergence` judges acceleration channels by.
pub const RESOLUTION_M_S2: f64 = 0.05;

/// The evaluation of one point.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PointComfort {
    /// Where the point is.
    pub point: String,
    /// Sample rate [Hz].
    pub sample_rate_hz: f64,
    /// Which k factors the total value uses.
    pub assessment: Assessment,
    /// Per axis.
    pub axes: Vec<AxisComfort>,
    /// The vibration total value a_v (ISO 2631-1 eq. 9) [m/s^2], when x, y and z are
    /// each present once.
    pub total_value_m_s2: Option<f64>,
    /// True when any axis is transient: then VDV and MTVV are the measures that count.
    pub transient: bool,
    /// What to read for a short passage.
    pub note: &'static str,
}

/// The sentence the summary, the command and the report carry.
pub const NOTE: &str = "for a short transient passage (an obstacle crossing) VDV and MTVV are the measures that count: the r.m.s. a_w averages the shock over the record and underestimates it (ISO 2631-1 6.2.1, 6.3.3)";

/// Evaluates `channels` (sampled at `rate_hz`) for `assessment` at `point`.
pub fn evaluate(
    point: &str,
    rate_hz: f64,
    channels: &[Channel],
    assessment: Assessment,
) -> Result<PointComfort, ComfortError> {
    let k = assessment.k();
    let mut axes = Vec::with_capacity(channels.len());
    for c in channels {
        let w = c.spec.weighting;
        let f = WeightingFilter::new(w, rate_hz).ok_or(ComfortError::RateTooLow {
            rate_hz,
            weighting: w,
        })?;
        let m = super::measures(&f.apply(&c.values_m_s2), 1.0 / rate_hz)
            .ok_or_else(|| ComfortError::Empty(c.name.clone()))?;
        axes.push(AxisComfort {
            channel: c.name.clone(),
            unit: c.unit.clone(),
            axis: c.spec.axis,
            weighting: w,
            k: k[c.spec.axis.index()],
            below_resolution: m.peak_m_s2 < RESOLUTION_M_S2,
            transient: m.transient() && m.peak_m_s2 >= RESOLUTION_M_S2,
            measures: m,
        });
    }
    // Eq. 9 needs each axis once.
    let mut rms = [None; 3];
    let mut once = true;
    for a in &axes {
        let slot = &mut rms[a.axis.index()];
        once &= slot.is_none();
        *slot = Some(a.measures.rms_m_s2);
    }
    let total = match (once, rms) {
        (true, [Some(x), Some(y), Some(z)]) => Some(combined([x, y, z], assessment)),
        _ => None,
    };
    Ok(PointComfort {
        point: point.to_string(),
        sample_rate_hz: rate_hz,
        assessment,
        transient: axes.iter().any(|a| a.transient),
        axes,
        total_value_m_s2: total,
        note: NOTE,
    })
}

/// The sensor on the car floor under the driver's seat (`[[sensor]] name` in the
/// vehicle files): its channels `acc_driver_floor_x`, `_y`, `_z` feed the run summary's
/// comfort block.
pub const FLOOR_SENSOR: &str = "driver_floor";

/// The run summary's comfort block: the raw channels `acc_<sensor>_<x,y,z>` from
/// `channel` (name to samples), those present, at `rate_hz`, the point described as
/// `place`; `None` when the run has none of them or its rate is too low for the
/// weightings.
pub fn of_sensor(
    sensor: &str,
    place: &str,
    rate_hz: f64,
    channel: impl Fn(&str) -> Option<Vec<f64>>,
) -> Option<PointComfort> {
    let chans: Vec<Channel> = [Axis::X, Axis::Y, Axis::Z]
        .into_iter()
        .filter_map(|axis| {
            let name = format!("acc_{sensor}_{}", ["x", "y", "z"][axis.index()]);
            let values_m_s2 = channel(&name)?;
            Some(Channel {
                spec: super::record::ColumnSpec {
                    column: name.clone(),
                    axis,
                    weighting: axis.weighting(),
                },
                name,
                unit: "m/s^2".into(),
                values_m_s2,
            })
        })
        .collect();
    if chans.is_empty() {
        return None;
    }
    let point = format!("sensor `{sensor}`: {place}");
    evaluate(&point, rate_hz, &chans, Assessment::Comfort).ok()
}

/// The comfort at the seat surface of a seat on a floor sensor: the seat model, its
/// resonance and the evaluation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SeatComfort {
    /// The seat with its occupant (SI).
    pub seat: super::Seat,
    /// Frequency of the largest vertical transmissibility [Hz].
    pub resonance_hz: f64,
    /// The largest vertical transmissibility |a_seat / a_floor| [-].
    pub peak_transmissibility: f64,
    /// |T(f)| of the seat on [`CURVE_POINTS`] frequencies log-spaced over 0.5-80 Hz (the
    /// weightings' band), for the report's figure: (frequency [Hz], |T| [-]).
    pub transmissibility: Vec<[f64; 2]>,
    /// The evaluation: z through the seat (channel [`SEAT_Z`]), x and y as the floor's.
    pub comfort: PointComfort,
    /// SEAT value of the vertical axis, r.m.s. form: Wk-weighted a_w on the seat over
    /// that on the floor, "the vibration experienced on top of the seat" over "the
    /// vibration that one would be exposed to when sitting directly on the vibrating
    /// floor" (van Niekerk et al. 2003, J. Sound Vib. 260, 867-888, abstract) [-].
    pub seat_value_rms: f64,
    /// The same ratio of the Wk-weighted VDVs, the form for shocks [-].
    pub seat_value_vdv: f64,
}

/// Points of the seat's |T(f)| curve in the summary.
pub const CURVE_POINTS: usize = 97;

/// The name of the seat surface's vertical acceleration.
pub const SEAT_Z: &str = "acc_driver_seat_z";

/// The run summary's seat block: the sensor's raw channels as [`of_sensor`] takes them,
/// z through `seat` (discretised at `rate_hz`), x and y passed through (no horizontal
/// seat model); `None` when [`of_sensor`] gives none.
pub fn of_seat(
    sensor: &str,
    place: &str,
    rate_hz: f64,
    seat: &super::Seat,
    channel: impl Fn(&str) -> Option<Vec<f64>>,
) -> Option<SeatComfort> {
    let filter = super::SeatFilter::new(seat, rate_hz);
    let z = format!("acc_{sensor}_z");
    let floor = super::weighted_measures(&channel(&z)?, rate_hz, Weighting::Wk)?;
    let mut comfort = of_sensor(sensor, place, rate_hz, |c| {
        let v = channel(c)?;
        Some(if c == z { filter.apply(&v) } else { v })
    })?;
    comfort.point = format!("seat surface over sensor `{sensor}`: {place}");
    for a in &mut comfort.axes {
        if a.channel == z {
            a.channel = SEAT_Z.to_string();
        }
    }
    let (resonance_hz, peak_transmissibility) = seat.resonance();
    let on_seat = comfort.axes.iter().find(|a| a.channel == SEAT_Z)?.measures;
    let transmissibility = (0..CURVE_POINTS)
        .map(|k| {
            let f = 0.5 * 160f64.powf(k as f64 / (CURVE_POINTS - 1) as f64);
            [f, seat.transmissibility(f).norm()]
        })
        .collect();
    Some(SeatComfort {
        transmissibility,
        seat_value_rms: on_seat.rms_m_s2 / floor.rms_m_s2,
        seat_value_vdv: on_seat.vdv_m_s1_75 / floor.vdv_m_s1_75,
        seat: seat.clone(),
        resonance_hz,
        peak_transmissibility,
        comfort,
    })
}
