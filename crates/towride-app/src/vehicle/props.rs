//! Property-file pieces the templates share (mass properties, bushings, dampers, stops)
//! and their checks, every error located at its file, line and field.

use serde::Deserialize;

use super::geom::{frame, Axes, V};
use towride_mbs::input::{InputError, Seg, Source};
use towride_mbs::model::builder::inertia_tensor;
use towride_mbs::model::elements::{JointBushing, Law, LawSpec, Stop, StopSpec};
use towride_mbs::model::math::{add, scale, sub};

/// `p` extended by one key or index.
pub fn at(p: &[Seg], k: impl Into<Seg>) -> Vec<Seg> {
    let mut v = p.to_vec();
    v.push(k.into());
    v
}

/// A point or vector of finite numbers.
pub fn point(src: &Source, p: &[Seg], v: &[f64; 3]) -> Result<V, InputError> {
    for (c, x) in v.iter().enumerate() {
        src.finite(&at(p, c), *x)?;
    }
    Ok(*v)
}

/// Mass, centre of mass and inertia of a rigid part.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct MassProps {
    pub mass_kg: f64,
    /// Centre of mass in the subsystem's coordinates [m].
    pub cm_m: [f64; 3],
    /// [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] about the centre of mass, in the
    /// subsystem's axes [kg m^2].
    pub inertia_kg_m2: Vec<f64>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Mass {
    pub mass: f64,
    pub cm: V,
    pub inertia: [[f64; 3]; 3],
}

impl Mass {
    /// The right-side image of a left-side part (itself when `right` is false).
    pub fn side(&self, right: bool) -> Mass {
        if !right {
            return self.clone();
        }
        Mass {
            mass: self.mass,
            cm: super::geom::mirror(self.cm),
            inertia: super::geom::mirror_inertia(&self.inertia),
        }
    }
}

impl MassProps {
    pub fn check(&self, src: &Source, p: &[Seg]) -> Result<Mass, InputError> {
        let mass = src.positive(&at(p, "mass_kg"), self.mass_kg)?;
        let cm = point(src, &at(p, "cm_m"), &self.cm_m)?;
        let inertia = inertia(src, &at(p, "inertia_kg_m2"), &self.inertia_kg_m2)?;
        Ok(Mass { mass, cm, inertia })
    }
}

/// A physical inertia tensor (the model builder's rule), located at `p`.
pub fn inertia(src: &Source, p: &[Seg], v: &[f64]) -> Result<[[f64; 3]; 3], InputError> {
    inertia_tensor(v).map_err(|e| src.locate(p, e))
}

/// A linear coefficient (non-negative) or a table (natural cubic spline), checked by the
/// one rule of `LawSpec::check`, located at `p`.
pub fn law(src: &Source, p: &[Seg], l: &LawSpec) -> Result<Law, InputError> {
    l.check().map_err(|e| src.locate(p, e))
}

/// A 6-DOF rubber bushing: axes (z along `z_axis`), and per axis stiffness and damping.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct BushingProps {
    /// Bushing z axis in subsystem coordinates (left side); the template gives a default.
    pub z_axis: Option<[f64; 3]>,
    pub x_axis: Option<[f64; 3]>,
    /// Along the bushing's x, y, z [N/m] (numbers or tables deflection -> force).
    pub stiffness_n_m: [LawSpec; 3],
    pub damping_n_s_m: [LawSpec; 3],
    /// About x, y, z [N m/rad].
    pub stiffness_n_m_rad: [LawSpec; 3],
    pub damping_n_m_s_rad: [LawSpec; 3],
}

#[derive(Clone, Debug)]
pub struct BushingLaws {
    /// The bushing's axes in subsystem coordinates (left side).
    pub axes: Axes,
    pub stiffness: [Law; 6],
    pub damping: [Law; 6],
}

impl BushingLaws {
    /// The right-side image of a left-side bushing (mirrored axes).
    pub fn side(&self, right: bool) -> BushingLaws {
        let mut b = self.clone();
        if right {
            b.axes = super::geom::mirror_axes(&self.axes);
        }
        b
    }
}

impl BushingProps {
    /// Checks the laws; the axes default to z along `default_z`.
    pub fn check(&self, src: &Source, p: &[Seg], default_z: V) -> Result<BushingLaws, InputError> {
        if let Some(z) = &self.z_axis {
            point(src, &at(p, "z_axis"), z)?;
        }
        if let Some(x) = &self.x_axis {
            point(src, &at(p, "x_axis"), x)?;
        }
        let axes = frame(self.z_axis.unwrap_or(default_z), self.x_axis).ok_or_else(|| {
            src.error(
                &at(p, "z_axis"),
                "axes must be non-zero and x_axis not parallel to z_axis",
            )
        })?;
        let (stiffness, damping) = towride_mbs::model::elements::bushing::six_laws(
            &self.stiffness_n_m,
            &self.damping_n_s_m,
            &self.stiffness_n_m_rad,
            &self.damping_n_m_s_rad,
        )
        .map_err(|e| src.locate(p, e))?;
        Ok(BushingLaws {
            axes,
            stiffness,
            damping,
        })
    }
}

/// A damper's force-velocity curve: velocity of extension [m/s] -> force resisting it
/// [N] (negative in compression). Bump and rebound may differ.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct DamperProps {
    pub velocity_m_s: Vec<f64>,
    pub force_n: Vec<f64>,
}

impl DamperProps {
    pub fn check(&self, src: &Source, p: &[Seg]) -> Result<Law, InputError> {
        for (k, (v, f)) in self.velocity_m_s.iter().zip(&self.force_n).enumerate() {
            // A passive damper never feeds energy in: the force opposes the motion.
            if v * f < 0.0 || (*v == 0.0 && *f != 0.0) {
                return Err(src.error(
                    &at(&at(p, "force_n"), k),
                    format!("{f} N at {v} m/s: a damper's force has the sign of the velocity (extension positive) and is zero at rest"),
                ));
            }
        }
        towride_mbs::model::function::Spline::new(&self.velocity_m_s, &self.force_n)
            .map(Law::Curve)
            .map_err(|e| src.locate(&at(p, "velocity_m_s"), e))
    }
}

/// A bump or rebound stop, checked by the one rule of `StopSpec::check`.
pub fn stop(src: &Source, p: &[Seg], s: &Option<StopSpec>) -> Result<Option<Stop>, InputError> {
    s.as_ref()
        .map(|s| s.check().map_err(|e| src.locate(p, e)))
        .transpose()
}

/// A template's ideal joints: kept, or all replaced by one bushing (thesis 6b: stiff,
/// small but non-zero damping, only in the directions the joint locks).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct JointsProps {
    pub as_bushings: bool,
    pub bushing: JointBushing,
}

/// The bushing that replaces the template's joints, if they are switched.
pub fn joints(
    src: &Source,
    p: &[Seg],
    j: &JointsProps,
) -> Result<Option<JointBushing>, InputError> {
    let jb = joint_bushing(src, &at(p, "bushing"), &Some(j.bushing.clone()))?;
    Ok(if j.as_bushings { jb } else { None })
}

/// Bushing properties standing in for ideal joints, checked.
pub fn joint_bushing(
    src: &Source,
    p: &[Seg],
    jb: &Option<JointBushing>,
) -> Result<Option<JointBushing>, InputError> {
    let Some(jb) = jb else { return Ok(None) };
    jb.check().map_err(|e| src.locate(p, e))?;
    Ok(Some(jb.clone()))
}

/// A rigid wheel (rim, brake disc or drum, hub: everything that spins except the tyre).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct WheelProps {
    pub mass_kg: f64,
    /// About the spin axis [kg m^2].
    pub spin_inertia_kg_m2: f64,
    /// About a diameter [kg m^2].
    pub tilt_inertia_kg_m2: f64,
}

/// A torsion element between two parts about a common axis.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct TorsionProps {
    pub stiffness_n_m_rad: LawSpec,
    pub damping_n_m_s_rad: LawSpec,
}

impl TorsionProps {
    /// Stiffness and damping laws, errors at `p`.`stiffness_n_m_rad` / `damping_n_m_s_rad`.
    pub fn laws(&self, src: &Source, p: &[Seg]) -> Result<(Law, Law), InputError> {
        Ok((
            law(src, &at(p, "stiffness_n_m_rad"), &self.stiffness_n_m_rad)?,
            law(src, &at(p, "damping_n_m_s_rad"), &self.damping_n_m_s_rad)?,
        ))
    }
}

/// Two bodies merged: mass, centre of mass and inertia about it (parallel axes).
pub fn merge(a: &Mass, b: &Mass) -> Mass {
    let m = a.mass + b.mass;
    let cm = scale(&add(&scale(&a.cm, a.mass), &scale(&b.cm, b.mass)), 1.0 / m);
    let mut inertia = [[0.0; 3]; 3];
    for part in [a, b] {
        let d = sub(&part.cm, &cm);
        let d2: f64 = d.iter().map(|x| x * x).sum();
        for r in 0..3 {
            for c in 0..3 {
                let delta = if r == c { 1.0 } else { 0.0 };
                inertia[r][c] += part.inertia[r][c] + part.mass * (d2 * delta - d[r] * d[c]);
            }
        }
    }
    Mass {
        mass: m,
        cm,
        inertia,
    }
}
