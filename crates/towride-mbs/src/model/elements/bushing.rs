//! 6-DOF bushing between two markers: per axis of J, a law of the deflection (the
//! translation of I relative to J, then the rotation vector) and one of its rate.

use serde::Deserialize;

use super::law::{finite, Law, LawSpec};
use super::{ElementLoad, FieldError, ForceElement, Frame, Measure, TwoMarkers, SIX};
use crate::model::builder::{BushingLine, MarkerHandle, ModelBuilder};
use crate::model::dual::Scalar;
use crate::model::math::{mtv, mv, qmul, rotation_vector, sub};

/// Force and torque on I = preload - K(d) - C(d'), in J's axes.
#[derive(Clone, Debug)]
pub struct Bushing {
    /// Name, unique among the elements.
    pub name: String,
    /// Marker I.
    pub i: MarkerHandle,
    /// Marker J (its axes are the bushing's).
    pub j: MarkerHandle,
    /// Per direction x, y, z, rx, ry, rz [N/m or N m/rad].
    pub stiffness: [Law; 6],
    /// Per direction [N s/m or N m s/rad].
    pub damping: [Law; 6],
    /// Per direction [N or N m].
    pub preload: [f64; 6],
    /// Set when the bushing stands in for an ideal joint (its name).
    pub replaces: Option<String>,
}

impl ForceElement for Bushing {
    const TABLE: &'static str = "bushing";
    type Spec = BushingSpec;
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
        for (a, p) in self.preload.iter().enumerate() {
            let (key, c) = if a < 3 {
                ("preload_n", a)
            } else {
                ("preload_n_m", a - 3)
            };
            finite(*p).map_err(|m| FieldError::at(c, m).under(key))?;
        }
        Ok(())
    }

    fn load<S: Scalar>(&self, _t: f64, (i, j): (&Frame<S>, &Frame<S>)) -> ElementLoad<S> {
        let ((i, qi), (j, qj)) = (i, j);
        let d = mtv(&j.axes, &sub(&i.origin, &j.origin));
        // Relative rotation of I in J: q_J^-1 q_I (the marker quaternions include the body's).
        let qrel = qmul(&[qj[0], -qj[1], -qj[2], -qj[3]], qi);
        let th = rotation_vector(&qrel);
        let defl = [d[0], d[1], d[2], th[0], th[1], th[2]];
        let mut loads = [S::cst(0.0); 6];
        let mut measures = Vec::with_capacity(6);
        for k in 0..6 {
            loads[k] = S::cst(self.preload[k])
                - self.stiffness[k].at(defl[k].v)
                - self.damping[k].at(defl[k].d[0]);
            measures.push((loads[k], defl[k].v, defl[k].d[0]));
        }
        let aj: [[S; 3]; 3] = j.axes.map(|r| r.map(|x| x.v));
        ElementLoad {
            force: mv(&aj, &[loads[0], loads[1], loads[2]]),
            torque: mv(&aj, &[loads[3], loads[4], loads[5]]),
            measures,
        }
    }

    fn measures(&self) -> Vec<Measure> {
        SIX.to_vec()
    }

    fn add_from_file(s: &BushingSpec, b: &mut ModelBuilder) -> Result<(), FieldError> {
        let body_i = b.body_by_name(&s.body_i).map_err(|e| e.under("body_i"))?;
        let body_j = b.body_by_name(&s.body_j).map_err(|e| e.under("body_j"))?;
        let axes = b.axes_from(s.z_axis, s.x_axis)?;
        let (stiffness, damping) = six_laws(
            &s.stiffness_n_m,
            &s.damping_n_s_m,
            &s.stiffness_n_m_rad,
            &s.damping_n_m_s_rad,
        )?;
        let mut preload = [0.0; 6];
        preload[..3].copy_from_slice(&s.preload_n);
        preload[3..].copy_from_slice(&s.preload_n_m);
        b.bushing(BushingLine {
            name: s.name.clone(),
            body_i,
            body_j,
            point: s.position_m,
            axes,
            stiffness,
            damping,
            preload,
        })
        .map_err(|e| e.into_field())?;
        Ok(())
    }
}

/// The six stiffness and six damping laws of a bushing as files write them (per axis x,
/// y, z: translations, then rotations), checked; errors name `stiffness_n_m[k]` etc. The
/// one reader of bushing laws, for mechanism files and vehicle property files alike.
pub fn six_laws(
    stiffness_n_m: &[LawSpec; 3],
    damping_n_s_m: &[LawSpec; 3],
    stiffness_n_m_rad: &[LawSpec; 3],
    damping_n_m_s_rad: &[LawSpec; 3],
) -> Result<([Law; 6], [Law; 6]), FieldError> {
    let three = |key: &str, list: &[LawSpec; 3]| -> Result<Vec<Law>, FieldError> {
        (0..3)
            .map(|k| list[k].check().map_err(|e| e.under(k).under(key)))
            .collect()
    };
    let mut stiffness = three("stiffness_n_m", stiffness_n_m)?;
    stiffness.extend(three("stiffness_n_m_rad", stiffness_n_m_rad)?);
    let mut damping = three("damping_n_s_m", damping_n_s_m)?;
    damping.extend(three("damping_n_m_s_rad", damping_n_m_s_rad)?);
    let six = |v: Vec<Law>| -> [Law; 6] { v.try_into().expect("six laws") };
    Ok((six(stiffness), six(damping)))
}

/// A `[[bushing]]` of a mechanism file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct BushingSpec {
    /// Name, unique among the elements.
    pub name: String,
    /// Body of marker I (`ground` for the ground).
    pub body_i: String,
    /// Body of marker J.
    pub body_j: String,
    /// Where both markers sit, world coordinates [m].
    pub position_m: [f64; 3],
    /// The bushing's z axis (default: world z).
    pub z_axis: Option<[f64; 3]>,
    /// The bushing's x axis.
    pub x_axis: Option<[f64; 3]>,
    /// Per axis x, y, z: N/m or tables.
    pub stiffness_n_m: [LawSpec; 3],
    /// Per axis: N s/m or tables.
    pub damping_n_s_m: [LawSpec; 3],
    /// Per axis: N m/rad or tables.
    pub stiffness_n_m_rad: [LawSpec; 3],
    /// Per axis: N m s/rad or tables.
    pub damping_n_m_s_rad: [LawSpec; 3],
    /// Preload force per axis [N].
    #[serde(default)]
    pub preload_n: [f64; 3],
    /// Preload torque per axis [N m].
    #[serde(default)]
    pub preload_n_m: [f64; 3],
}
