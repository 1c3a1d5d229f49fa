//! Ride comfort after ISO 2631-1:1997: the frequency weightings as digital filters
//! ([`weighting`]), the measures of a weighted acceleration ([`metrics`]): r.m.s.,
//! VDV, MTVV, crest factor and the combined vibration total value; acceleration
//! columns of a CSV ([`record`]), the evaluation of a measuring point ([`evaluate`])
//! and the driver's seat from the floor to the seat surface ([`seat`]). `docs/comfort.md` gives the definitions and sources.

pub mod evaluate;
pub mod metrics;
pub mod record;
pub mod seat;
pub mod weighting;

pub use evaluate::{evaluate, ComfortError, PointComfort, SeatComfort, FLOOR_SENSOR, SEAT_Z};
pub use metrics::{combined, measures, Assessment, Measures};
pub use record::{Axis, ColumnSpec, TimeBase};
pub use seat::{Seat, SeatFilter, SeatSpec};
pub use weighting::{Weighting, WeightingFilter};

/// The measures of the acceleration `a` [m/s^2] sampled at `rate_hz`, weighted by `w`;
/// `None` when the rate is too low for the weighting or the signal is empty.
pub fn weighted_measures(a: &[f64], rate_hz: f64, w: Weighting) -> Option<Measures> {
    let f = WeightingFilter::new(w, rate_hz)?;
    measures(&f.apply(a), 1.0 / rate_hz)
}
