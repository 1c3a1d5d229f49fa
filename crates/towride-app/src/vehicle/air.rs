//! A levelled air spring: a gas volume closed off at the design height, compressed
//! polytropically.
//!
//! The levelling valve fills the bellows until the spring carries its static load P at
//! the design height, so the gauge pressure there is p_g = P / A (A the effective area).
//! Stroked by x (extension positive) the volume is V = V0 + A x and the gas follows
//! p V^n = const, so the repulsive force is
//!
//! ```text
//! F(x) = A ((p_g + p_a) (V0 / (V0 + A x))^n - p_a)
//! ```
//!
//! with rate n (p_g + p_a) A^2 / V0 at the design height (the textbook air-spring rate
//! with a constant effective area: a rolling lobe on a straight piston). The law enters a
//! spring element as a table (natural cubic spline) of P - F(x) over the stroke, so the
//! element's preload P plus its spring term reproduces F.

use crate::error::DesignError;
use serde::Serialize;

use super::description::{Assumed, Kind};
use towride_mbs::input::{FieldError, InputError};
use towride_mbs::model::desc::Law;
use towride_mbs::model::function::Spline;

/// An air spring at its design height.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct AirSpring {
    /// Effective area [m^2].
    pub area_m2: f64,
    /// Gas volume at the design height [m^3].
    pub volume_m3: f64,
    /// Gauge pressure at the design height [Pa] (the static load over the area).
    pub gauge_pa: f64,
    /// Ambient pressure [Pa].
    pub atmosphere_pa: f64,
    /// Polytropic exponent [-].
    pub exponent: f64,
}

impl AirSpring {
    /// The volume that gives the rate `rate_n_m` at gauge pressure `gauge_pa`.
    pub fn volume_for_rate(area: f64, gauge_pa: f64, atmosphere_pa: f64, n: f64, rate: f64) -> f64 {
        n * (gauge_pa + atmosphere_pa) * area * area / rate
    }

    /// Repulsive force [N] at extension `x` [m] from the design height.
    pub fn force(&self, x: f64) -> f64 {
        let v = self.volume_m3 + self.area_m2 * x;
        self.area_m2
            * ((self.gauge_pa + self.atmosphere_pa) * (self.volume_m3 / v).powf(self.exponent)
                - self.atmosphere_pa)
    }

    /// Rate at the design height [N/m]: n (p_g + p_a) A^2 / V0.
    pub fn rate(&self) -> f64 {
        self.exponent * (self.gauge_pa + self.atmosphere_pa) * self.area_m2 * self.area_m2
            / self.volume_m3
    }

    /// The spring law of an element whose preload is `force(0)`: spring(x) = force(0) -
    /// force(x), tabulated in `points` points over +-`span` of the stroke V0 / A that
    /// would empty the bellows.
    pub fn law(&self, span: f64, points: usize) -> Result<Law, FieldError> {
        if !(span > 0.0 && span < 1.0) || points < 5 {
            return Err(FieldError::here(format!(
                "the table must span 0 < span < 1 of the stroke in at least 5 points, got {span} and {points}"
            )));
        }
        let stroke = span * self.volume_m3 / self.area_m2;
        let f0 = self.force(0.0);
        let (x, y): (Vec<f64>, Vec<f64>) = (0..points)
            .map(|k| {
                let x = -stroke + 2.0 * stroke * k as f64 / (points - 1) as f64;
                (x, f0 - self.force(x))
            })
            .unzip();
        Spline::new(&x, &y).map(Law::Curve)
    }
}

/// A levelled air spring before the design statics: its pressure follows from the
/// static load, its volume is given or follows from the wheel rate it must give.
#[derive(Clone, Debug)]
pub struct AirSpec {
    /// Effective area [m^2].
    pub area_m2: f64,
    /// Gas volume at the design height [m^3]; `None`: the volume giving `wheel_rate_n_m`.
    pub volume_m3: Option<f64>,
    /// Rate at the wheel [N/m] the volume must give (used without `volume_m3`).
    pub wheel_rate_n_m: Option<f64>,
    /// Polytropic exponent [-].
    pub exponent: f64,
    /// Ambient pressure [Pa].
    pub atmosphere_pa: f64,
    /// The tabulated law spans this fraction of the stroke V0 / A each way ([`AirSpring::law`]).
    pub table_span: f64,
    /// Points of the tabulated law.
    pub table_points: usize,
    /// Where a table the law refuses is blamed (message replaced).
    pub table_at: InputError,
}

impl AirSpec {
    /// The spring levelled to carry `preload` [N] at the design height, its rate seen at
    /// the wheel through the motion ratio `mr`; or why it cannot be.
    pub fn levelled(&self, preload: f64, mr: f64) -> Result<AirSpring, DesignError> {
        let gauge = preload / self.area_m2;
        if gauge.is_nan() || gauge <= 0.0 {
            return Err(DesignError::AirSpringPulls { preload_n: preload });
        }
        let volume = match (self.volume_m3, self.wheel_rate_n_m) {
            (Some(v), _) => v,
            (None, Some(k)) => AirSpring::volume_for_rate(
                self.area_m2,
                gauge,
                self.atmosphere_pa,
                self.exponent,
                k / (mr * mr),
            ),
            (None, None) => return Err(DesignError::AirSpringVolume),
        };
        Ok(AirSpring {
            area_m2: self.area_m2,
            volume_m3: volume,
            gauge_pa: gauge,
            atmosphere_pa: self.atmosphere_pa,
            exponent: self.exponent,
        })
    }

    /// The spring law of the levelled spring `air` as its table, refusals blamed at
    /// `table_at`.
    pub fn law(&self, air: &AirSpring) -> Result<Law, InputError> {
        air.law(self.table_span, self.table_points).map_err(|e| {
            let mut at = self.table_at.clone();
            at.message = e.message;
            at
        })
    }
}

/// What the design statics found for the air spring of wheel `w`, as derived values.
pub fn notes(w: &str, a: &AirSpring) -> [Assumed; 3] {
    let note = |what: &str, value: f64, unit: &str, source: &str| Assumed {
        field: format!("air_spring_{w}.{what}"),
        value,
        unit: unit.into(),
        kind: Kind::Derived,
        source: source.into(),
    };
    [
        note(
            "gauge_pressure_pa",
            a.gauge_pa,
            "Pa",
            "static load over the effective area (levelled at the design height)",
        ),
        note(
            "volume_m3",
            a.volume_m3,
            "m^3",
            "the file's volume, or the one giving its rate",
        ),
        note(
            "rate_n_m",
            a.rate(),
            "N/m",
            "n (p_g + p_a) A^2 / V0 at the design height",
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_is_the_slope_and_the_table_follows_the_gas_law() {
        let a = AirSpring {
            area_m2: 0.0177,
            volume_m3: 0.0045,
            gauge_pa: 2.4e5,
            atmosphere_pa: 101325.0,
            exponent: 1.3,
        };
        let h = 1e-6;
        let slope = -(a.force(h) - a.force(-h)) / (2.0 * h);
        assert!((slope / a.rate() - 1.0).abs() < 1e-6);
        assert!((a.force(0.0) - 0.0177 * 2.4e5).abs() < 1e-9);
        let law = a.law(0.6, 61).unwrap();
        for x in [-0.1, -0.05, 0.0, 0.03, 0.1] {
            let (s, _, _) = law.eval(x);
            let exact = a.force(0.0) - a.force(x);
            assert!(
                (s - exact).abs() < 1e-3 * a.force(0.0),
                "{x}: {s} vs {exact}"
            );
        }
        let v = AirSpring::volume_for_rate(0.0177, 2.4e5, 101325.0, 1.3, a.rate());
        assert!((v / 0.0045 - 1.0).abs() < 1e-12);
    }
}
