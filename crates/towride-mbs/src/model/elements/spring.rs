//! Translational spring-damper between two marker origins, acting along the line between
//! them, with optional bump and rebound stops.

use serde::Deserialize;

use super::law::{finite, positive, Law, LawSpec, StopSpec};
use super::{ElementLoad, FieldError, ForceElement, Frame, Measure, TwoMarkers};
use crate::model::builder::{MarkerHandle, ModelBuilder, SpringLine};
use crate::model::dual::Scalar;
use crate::model::math::{dot, scale, sub};

/// Repulsive force = preload - spring(l - free_length) - damper(l'), plus the stops.
#[derive(Clone, Debug)]
pub struct SpringDamper {
    /// Name, unique among the elements.
    pub name: String,
    /// Marker I (its origin is one end).
    pub i: MarkerHandle,
    /// Marker J (its origin is the other end).
    pub j: MarkerHandle,
    /// Length at which the spring is relaxed [m].
    pub free_length: f64,
    /// Repulsive force at the free length [N].
    pub preload: f64,
    /// Spring law of the extension [m -> N].
    pub spring: Law,
    /// Damper law of the extension rate [m/s -> N].
    pub damper: Law,
    /// Engages in compression: l < free_length - clearance.
    pub bump_stop: Option<super::Stop>,
    /// Engages in extension: l > free_length + clearance.
    pub rebound_stop: Option<super::Stop>,
}

impl ForceElement for SpringDamper {
    const TABLE: &'static str = "spring";
    type Spec = SpringSpec;
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
        positive(self.free_length).map_err(|m| FieldError::at("free_length_m", m))?;
        finite(self.preload).map_err(|m| FieldError::at("preload_n", m))?;
        Ok(())
    }

    fn load<S: Scalar>(&self, _t: f64, (i, j): (&Frame<S>, &Frame<S>)) -> ElementLoad<S> {
        let (i, j) = (&i.0, &j.0);
        let d = sub(&i.origin, &j.origin);
        let l = dot(&d, &d).sqrt();
        let x = l.v - self.free_length;
        let rate = l.d[0];
        let mut repulsive = S::cst(self.preload) - self.spring.at(x) - self.damper.at(rate);
        if let Some(st) = &self.bump_stop {
            repulsive = repulsive + st.force(-x - st.clearance, -rate);
        }
        if let Some(st) = &self.rebound_stop {
            repulsive = repulsive - st.force(x - st.clearance, rate);
        }
        let unit = [d[0].v / l.v, d[1].v / l.v, d[2].v / l.v];
        ElementLoad {
            force: scale(&unit, repulsive),
            torque: [S::cst(0.0); 3],
            measures: vec![(repulsive, x, rate)],
        }
    }

    fn measures(&self) -> Vec<Measure> {
        vec![Measure {
            suffix: None,
            units: ["N", "m", "m/s"],
            angle: false,
        }]
    }

    fn add_from_file(s: &SpringSpec, b: &mut ModelBuilder) -> Result<(), FieldError> {
        let body_i = b.body_by_name(&s.body_i).map_err(|e| e.under("body_i"))?;
        let body_j = b.body_by_name(&s.body_j).map_err(|e| e.under("body_j"))?;
        let mut line = SpringLine::new(&s.name, body_i, s.point_i_m, body_j, s.point_j_m);
        if let Some(l) = s.free_length_m {
            line.free_length = l;
        }
        line.preload = s.preload_n;
        line.spring = s
            .stiffness_n_m
            .check()
            .map_err(|e| e.under("stiffness_n_m"))?;
        line.damper = s
            .damping_n_s_m
            .check()
            .map_err(|e| e.under("damping_n_s_m"))?;
        line.bump_stop = stop(&s.bump_stop, "bump_stop")?;
        line.rebound_stop = stop(&s.rebound_stop, "rebound_stop")?;
        b.spring(line).map_err(|e| e.into_field())?;
        Ok(())
    }
}

fn stop(s: &Option<StopSpec>, key: &str) -> Result<Option<super::Stop>, FieldError> {
    s.as_ref()
        .map(|s| s.check().map_err(|e| e.under(key)))
        .transpose()
}

/// A `[[spring]]` of a mechanism file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// Name, unique among the elements.
    pub name: String,
    /// The body at one end (`ground` for the ground).
    pub body_i: String,
    /// That end, world coordinates at the initial configuration [m].
    pub point_i_m: [f64; 3],
    /// The body at the other end.
    pub body_j: String,
    /// The other end [m].
    pub point_j_m: [f64; 3],
    /// N/m, or a table { x = deflection [m], y = force [N] } (extension positive).
    pub stiffness_n_m: LawSpec,
    /// N s/m, or a table { x = velocity [m/s], y = force [N] }.
    #[serde(default = "zero_law")]
    pub damping_n_s_m: LawSpec,
    /// Default: the initial distance.
    pub free_length_m: Option<f64>,
    /// Repulsive force at the free length [N].
    #[serde(default)]
    pub preload_n: f64,
    /// Stop in compression.
    pub bump_stop: Option<StopSpec>,
    /// Stop in extension.
    pub rebound_stop: Option<StopSpec>,
}

/// A law that is zero everywhere.
pub fn zero_law() -> LawSpec {
    LawSpec::Linear(0.0)
}
