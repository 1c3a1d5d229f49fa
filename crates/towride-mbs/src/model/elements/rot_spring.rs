//! Rotational spring-damper about the common z axis of two markers.

use serde::Deserialize;

use super::law::{finite, Law, LawSpec};
use super::spring::zero_law;
use super::{ElementLoad, FieldError, ForceElement, Frame, Measure, TwoMarkers};
use crate::model::builder::{MarkerHandle, ModelBuilder, RotLine};
use crate::model::dual::Scalar;
use crate::model::math::{col, dot, scale, V3};

/// Torque about J's z = preload - spring(angle - free_angle) - damper(angle rate); the
/// angle is that of I's x axis in J's xy plane.
#[derive(Clone, Debug)]
pub struct RotSpring {
    /// Name, unique among the elements.
    pub name: String,
    /// Marker I.
    pub i: MarkerHandle,
    /// Marker J (its z axis is the spring's axis).
    pub j: MarkerHandle,
    /// Angle at which the spring is relaxed [rad].
    pub free_angle: f64,
    /// Torque at the free angle [N m].
    pub preload: f64,
    /// Spring law [rad -> N m].
    pub spring: Law,
    /// Damper law [rad/s -> N m].
    pub damper: Law,
}

impl ForceElement for RotSpring {
    const TABLE: &'static str = "rotational_spring";
    type Spec = RotSpringSpec;
    type Markers = TwoMarkers;

    fn name(&self) -> &str {
        &self.name
    }

    fn markers(&self) -> TwoMarkers {
        TwoMarkers {
            i: self.i,
            j: self.j,
        }
    }

    fn check(&self) -> Result<(), FieldError> {
        finite(self.free_angle).map_err(|m| FieldError::at("free_angle_rad", m))?;
        finite(self.preload).map_err(|m| FieldError::at("preload_n_m", m))?;
        Ok(())
    }

    fn load<S: Scalar>(&self, _t: f64, (i, j): (&Frame<S>, &Frame<S>)) -> ElementLoad<S> {
        let (i, j) = (&i.0, &j.0);
        let xi = col(&i.axes, 0);
        let angle = dot(&xi, &col(&j.axes, 1)).atan2(dot(&xi, &col(&j.axes, 0)));
        let x = angle.v - self.free_angle;
        let rate = angle.d[0];
        let t = S::cst(self.preload) - self.spring.at(x) - self.damper.at(rate);
        let z: V3<S> = col(&j.axes, 2).map(|c| c.v);
        ElementLoad {
            force: [S::cst(0.0); 3],
            torque: scale(&z, t),
            measures: vec![(t, x, rate)],
        }
    }

    fn measures(&self) -> Vec<Measure> {
        vec![Measure {
            suffix: None,
            units: ["N m", "rad", "rad/s"],
            angle: true,
        }]
    }

    fn add_from_file(s: &RotSpringSpec, b: &mut ModelBuilder) -> Result<(), FieldError> {
        let body_i = b.body_by_name(&s.body_i).map_err(|e| e.under("body_i"))?;
        let body_j = b.body_by_name(&s.body_j).map_err(|e| e.under("body_j"))?;
        let axes = b.axes_from(Some(s.z_axis), s.x_axis)?;
        b.rot_spring(RotLine {
            name: s.name.clone(),
            body_i,
            body_j,
            point: s.position_m,
            axes,
            free_angle: s.free_angle_rad,
            preload: s.preload_n_m,
            spring: s
                .stiffness_n_m_rad
                .check()
                .map_err(|e| e.under("stiffness_n_m_rad"))?,
            damper: s
                .damping_n_m_s_rad
                .check()
                .map_err(|e| e.under("damping_n_m_s_rad"))?,
        })
        .map_err(|e| e.into_field())?;
        Ok(())
    }
}

/// A `[[rotational_spring]]` of a mechanism file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct RotSpringSpec {
    /// Name, unique among the elements.
    pub name: String,
    /// Body of marker I (`ground` for the ground).
    pub body_i: String,
    /// Body of marker J.
    pub body_j: String,
    /// Where both markers sit, world coordinates [m].
    pub position_m: [f64; 3],
    /// The spring's axis.
    pub z_axis: [f64; 3],
    /// The markers' x axis (default: any perpendicular).
    pub x_axis: Option<[f64; 3]>,
    /// N m/rad, or a table.
    pub stiffness_n_m_rad: LawSpec,
    /// N m s/rad, or a table.
    #[serde(default = "zero_law")]
    pub damping_n_m_s_rad: LawSpec,
    /// Relaxed angle [rad].
    #[serde(default)]
    pub free_angle_rad: f64,
    /// Torque at the free angle [N m].
    #[serde(default)]
    pub preload_n_m: f64,
}
