//! A ball coupling's rating under UN Regulation No. 55 (mechanical coupling
//! components) and a run's ball forces set beside it (`docs/durability.md`,
//! "Coupling loads against the D-value").
//!
//! The D-value (R55, paragraph 2 "definitions", the D-value of a coupling) is the
//! theoretical reference force for the horizontal force between towing vehicle and
//! trailer: D = g T C / (T + C), T the towing vehicle's and C the trailer's technically
//! permissible maximum mass (R55 states it in kN with T, C in tonnes and g = 9.81 m/s^2;
//! with masses in kg it gives N). R55 Annex 6 tests a coupling ball with its towing
//! bracket dynamically with an alternating force of amplitude 0.6 D along a line
//! through the ball centre inclined 15 degrees down to the rear, for 2e6 cycles
//! (the 15-degree line as in Regulation (EU) No 44/2014, Annex V, Appendix 3, 6.4, for
//! coupling heads; the 0.6 D amplitude as we recall Annex 6, not read at the source):
//! the file carries the fraction and angle with their provenance.

use serde::Deserialize;

/// The `[rating]` table of a hitch file, as read.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct RatingIn {
    /// T: technically permissible maximum laden mass of the towing vehicle [kg].
    pub towing_vehicle_max_mass_kg: f64,
    /// C: technically permissible maximum mass of the trailer [kg].
    pub trailer_max_mass_kg: f64,
    /// g of the D-value formula [m/s^2].
    pub gravity_m_s2: f64,
    /// Amplitude of the dynamic test's alternating force as a fraction of D [-].
    pub test_force_fraction_of_d: f64,
    /// Incline of the test force below the horizontal, down to the rear [deg].
    pub test_force_incline_deg: f64,
}

/// A coupling's rating in SI units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Rating {
    /// T [kg].
    pub towing_vehicle_max_mass_kg: f64,
    /// C [kg].
    pub trailer_max_mass_kg: f64,
    /// D-value [N].
    pub d_value_n: f64,
    /// Amplitude of the R55 dynamic test force [N].
    pub test_amplitude_n: f64,
    /// Its horizontal (fore-aft) component [N].
    pub test_amplitude_x_n: f64,
    /// Its vertical component [N].
    pub test_amplitude_z_n: f64,
}

/// D = g T C / (T + C) [N] for masses in kg.
pub fn d_value_n(g: f64, t_kg: f64, c_kg: f64) -> f64 {
    g * t_kg * c_kg / (t_kg + c_kg)
}

impl RatingIn {
    /// The rating, each value checked (> 0; the incline 0..90 degrees) against `src`.
    pub fn check(
        &self,
        src: &towride_mbs::input::Source,
    ) -> Result<Rating, towride_mbs::input::InputError> {
        use towride_mbs::path;
        let p = |f: &'static str| path!["rating", f];
        let t = src.positive(
            &p("towing_vehicle_max_mass_kg"),
            self.towing_vehicle_max_mass_kg,
        )?;
        let c = src.positive(&p("trailer_max_mass_kg"), self.trailer_max_mass_kg)?;
        let g = src.positive(&p("gravity_m_s2"), self.gravity_m_s2)?;
        let k = src.positive(
            &p("test_force_fraction_of_d"),
            self.test_force_fraction_of_d,
        )?;
        let a = src.finite(&p("test_force_incline_deg"), self.test_force_incline_deg)?;
        if !(0.0..90.0).contains(&a) {
            return Err(src.error(
                &p("test_force_incline_deg"),
                format!("must lie in 0..90 degrees, got {a}"),
            ));
        }
        let d = d_value_n(g, t, c);
        let f = k * d;
        Ok(Rating {
            towing_vehicle_max_mass_kg: t,
            trailer_max_mass_kg: c,
            d_value_n: d,
            test_amplitude_n: f,
            test_amplitude_x_n: f * a.to_radians().cos(),
            test_amplitude_z_n: f * a.to_radians().sin(),
        })
    }
}

/// A run's ball forces beside the rating (`summary.json` `coupling`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CouplingCheck {
    /// The rating.
    pub rating: Rating,
    /// Largest |F| of the ball force vector [N].
    pub ball_force_peak_n: f64,
    /// Largest fore-aft amplitude: half the largest rainflow range of hitch_fx [N].
    pub fx_amplitude_n: f64,
    /// Largest vertical amplitude: half the largest rainflow range of hitch_fz [N].
    pub fz_amplitude_n: f64,
    /// ball_force_peak_n / D [-].
    pub peak_over_d: f64,
    /// fx_amplitude_n over the test force's horizontal amplitude [-].
    pub fx_amplitude_over_test: f64,
}

/// The check of ball force components `fx`, `fy`, `fz` [N] against `rating`.
pub fn check(rating: Rating, fx: &[f64], fy: &[f64], fz: &[f64]) -> Option<CouplingCheck> {
    let peak = (0..fx.len().min(fy.len()).min(fz.len()))
        .map(|k| (fx[k] * fx[k] + fy[k] * fy[k] + fz[k] * fz[k]).sqrt())
        .fold(0.0, f64::max);
    let half_range = |y: &[f64]| -> Option<f64> {
        let c = super::count(&super::turning_points(y, 0.0).ok()?);
        Some(0.5 * c.iter().map(|c| c.range).fold(0.0, f64::max))
    };
    let ax = half_range(fx)?;
    Some(CouplingCheck {
        rating,
        ball_force_peak_n: peak,
        fx_amplitude_n: ax,
        fz_amplitude_n: half_range(fz)?,
        peak_over_d: peak / rating.d_value_n,
        fx_amplitude_over_test: ax / rating.test_amplitude_x_n,
    })
}
