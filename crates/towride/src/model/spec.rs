//! The generic mechanism file (TOML): bodies, markers, joints, springs, bushings,
//! rotational springs, applied loads, motions, outputs, run and solver settings.
//! `docs/mechanism.md` documents every field with an example.
//!
//! Positions and axes are written in world coordinates at the initial configuration
//! (hardpoints), as vehicle engineers give them; the builder turns them into body-fixed
//! markers once.

use std::path::Path;

use serde::Deserialize;

use super::desc::{
    Accelerations, Applied, Axes, Body, BodyId, Bushing, ElementQuantity, Force, Joint, JointKind,
    JointQuantity, Law, MarkerQuantity, Model, Motion, MotionDof, Output, Request, RotSpring,
    SpringDamper, Stop,
};
use super::function::{Spline, TimeFunction};
use super::math::{dot, frame_from_axes, quat_from_matrix, sub};
use crate::input::{InputError, Loader, Seg, Source};
use crate::path;
use towride_solver::SolverOptions;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct File {
    pub model: ModelSpec,
    #[serde(default)]
    pub run: RunSpec,
    #[serde(default)]
    pub solver: SolverOptions,
    #[serde(default)]
    pub body: Vec<BodySpec>,
    #[serde(default)]
    pub marker: Vec<MarkerSpec>,
    #[serde(default)]
    pub joint: Vec<JointSpec>,
    #[serde(default)]
    pub spring: Vec<SpringSpec>,
    #[serde(default)]
    pub bushing: Vec<BushingSpec>,
    #[serde(default)]
    pub rotational_spring: Vec<RotSpringSpec>,
    #[serde(default)]
    pub force: Vec<AppliedSpec>,
    #[serde(default)]
    pub motion: Vec<MotionSpec>,
    #[serde(default)]
    pub output: Vec<OutputSpec>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    pub name: String,
    #[serde(default)]
    pub gravity_m_s2: [f64; 3],
    /// Replace every ideal joint by a bushing of these properties.
    pub joints_as_bushings: Option<JointBushing>,
}

/// Where a run starts from.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Start {
    /// The given positions, assembled onto the constraints.
    #[default]
    Assembly,
    /// Static equilibrium found from the given positions.
    Statics,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    pub end_time_s: f64,
    pub sample_rate_hz: f64,
    #[serde(default)]
    pub start: Start,
    /// Sampled accelerations and reactions: "interpolant" (default) or "solve".
    #[serde(default)]
    pub accelerations: Accelerations,
}

impl Default for RunSpec {
    fn default() -> Self {
        RunSpec {
            end_time_s: 1.0,
            sample_rate_hz: 1000.0,
            start: Start::Assembly,
            accelerations: Accelerations::Interpolant,
        }
    }
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    pub mass_kg: f64,
    /// [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] about the centre of mass, in the
    /// body axes given by z_axis / x_axis.
    pub inertia_kg_m2: Vec<f64>,
    pub cm_position_m: [f64; 3],
    pub z_axis: Option<[f64; 3]>,
    pub x_axis: Option<[f64; 3]>,
    #[serde(default)]
    pub velocity_m_s: [f64; 3],
    #[serde(default)]
    pub angular_velocity_rad_s: [f64; 3],
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct MarkerSpec {
    pub name: String,
    pub body: String,
    pub position_m: [f64; 3],
    pub z_axis: Option<[f64; 3]>,
    pub x_axis: Option<[f64; 3]>,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct JointBushing {
    pub stiffness_n_m: f64,
    pub damping_n_s_m: f64,
    pub stiffness_n_m_rad: f64,
    pub damping_n_m_s_rad: f64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    pub name: String,
    #[serde(rename = "type")]
    pub kind: String,
    pub body_i: String,
    pub body_j: String,
    pub position_m: [f64; 3],
    pub z_axis: Option<[f64; 3]>,
    pub x_axis: Option<[f64; 3]>,
    /// Replace this joint by a bushing.
    pub bushing: Option<JointBushing>,
}

/// A law: a number (linear coefficient) or a table.
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum LawSpec {
    Linear(f64),
    Table { x: Vec<f64>, y: Vec<f64> },
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct StopSpec {
    pub clearance_m: f64,
    pub stiffness_n_m: f64,
    #[serde(default = "one")]
    pub exponent: f64,
    #[serde(default)]
    pub damping_n_s_m: f64,
    #[serde(default)]
    pub damping_depth_m: f64,
}

fn one() -> f64 {
    1.0
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    pub name: String,
    pub body_i: String,
    pub point_i_m: [f64; 3],
    pub body_j: String,
    pub point_j_m: [f64; 3],
    /// N/m, or a table { x = deflection [m], y = force [N] } (extension positive).
    pub stiffness_n_m: LawSpec,
    /// N s/m, or a table { x = velocity [m/s], y = force [N] }.
    #[serde(default = "zero_law")]
    pub damping_n_s_m: LawSpec,
    /// Default: the initial distance.
    pub free_length_m: Option<f64>,
    #[serde(default)]
    pub preload_n: f64,
    pub bump_stop: Option<StopSpec>,
    pub rebound_stop: Option<StopSpec>,
}

fn zero_law() -> LawSpec {
    LawSpec::Linear(0.0)
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct BushingSpec {
    pub name: String,
    pub body_i: String,
    pub body_j: String,
    pub position_m: [f64; 3],
    pub z_axis: Option<[f64; 3]>,
    pub x_axis: Option<[f64; 3]>,
    /// Per axis x, y, z: N/m or tables.
    pub stiffness_n_m: [LawSpec; 3],
    pub damping_n_s_m: [LawSpec; 3],
    /// Per axis: N m/rad or tables.
    pub stiffness_n_m_rad: [LawSpec; 3],
    pub damping_n_m_s_rad: [LawSpec; 3],
    #[serde(default)]
    pub preload_n: [f64; 3],
    #[serde(default)]
    pub preload_n_m: [f64; 3],
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct RotSpringSpec {
    pub name: String,
    pub body_i: String,
    pub body_j: String,
    pub position_m: [f64; 3],
    pub z_axis: [f64; 3],
    pub x_axis: Option<[f64; 3]>,
    pub stiffness_n_m_rad: LawSpec,
    #[serde(default = "zero_law")]
    pub damping_n_m_s_rad: LawSpec,
    #[serde(default)]
    pub free_angle_rad: f64,
    #[serde(default)]
    pub preload_n_m: f64,
}

/// A number (constant) or a function of time.
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum FnSpec {
    Value(f64),
    Function(TimeFunction),
}

impl FnSpec {
    fn to_fn(&self) -> Option<TimeFunction> {
        match self {
            FnSpec::Value(v) if *v == 0.0 => None,
            FnSpec::Value(v) => Some(TimeFunction::Constant { value: *v }),
            FnSpec::Function(f) => Some(f.clone()),
        }
    }
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct AppliedSpec {
    pub name: String,
    pub body: String,
    pub position_m: [f64; 3],
    pub z_axis: Option<[f64; 3]>,
    pub x_axis: Option<[f64; 3]>,
    /// "world" or "marker" (the axes given here, moving with the body).
    #[serde(default = "world")]
    pub axes: String,
    pub force_n: Option<[FnSpec; 3]>,
    pub torque_n_m: Option<[FnSpec; 3]>,
}

fn world() -> String {
    "world".into()
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct MotionSpec {
    pub name: String,
    pub joint: String,
    /// "rotation" or "translation"; default from the joint type.
    pub dof: Option<String>,
    /// Displacement [m or rad] as a function of time, or...
    pub displacement: Option<TimeFunction>,
    /// ...velocity [m/s or rad/s], integrated from zero at t = 0.
    pub velocity: Option<TimeFunction>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    pub name: Option<String>,
    pub marker: Option<String>,
    pub joint: Option<String>,
    pub element: Option<String>,
    pub quantity: String,
    /// "world" (default) or a marker name.
    pub axes: Option<String>,
}

/// A mechanism read from a file, validated and ready to assemble.
pub struct Mechanism {
    pub model: Model,
    pub run: RunSpec,
    pub solver: SolverOptions,
}

/// Reads and validates a mechanism file, read through `loader` (its overrides; one
/// that matches nothing read is an error).
pub fn load(path: &Path, loader: &Loader) -> Result<Mechanism, InputError> {
    let loader = loader.fresh();
    let src = loader.toml(path)?;
    let file: File = src.parse()?;
    let m = build(&src, file)?;
    loader.check_used()?;
    Ok(m)
}

/// Validates a parsed file into a model.
pub fn build(src: &Source, f: File) -> Result<Mechanism, InputError> {
    let mut m = Model {
        name: f.model.name.clone(),
        ..Default::default()
    };
    for (c, g) in f.model.gravity_m_s2.iter().enumerate() {
        src.finite(&path!["model", "gravity_m_s2", c], *g)?;
    }
    m.gravity = f.model.gravity_m_s2;
    m.accelerations = f.run.accelerations;
    check_run(src, &f.run)?;
    f.solver
        .validate(1)
        .map_err(|e| src.error(&path!["solver"], e.to_string()))?;

    let mut names = std::collections::HashSet::new();
    for (k, b) in f.body.iter().enumerate() {
        let p = |s: &str| path!["body", k, s];
        if b.name == "ground" || !names.insert(b.name.clone()) {
            return Err(src.error(
                &p("name"),
                format!("body name '{}' is reserved or used twice", b.name),
            ));
        }
        src.positive(&p("mass_kg"), b.mass_kg)?;
        let inertia = inertia_tensor(src, k, &b.inertia_kg_m2)?;
        vec3(src, &p("cm_position_m"), &b.cm_position_m)?;
        vec3(src, &p("velocity_m_s"), &b.velocity_m_s)?;
        vec3(src, &p("angular_velocity_rad_s"), &b.angular_velocity_rad_s)?;
        let axes = axes_of(src, &path!["body", k], b.z_axis, b.x_axis)?;
        m.bodies.push(Body {
            name: b.name.clone(),
            mass: b.mass_kg,
            inertia,
            position: b.cm_position_m,
            orientation: quat_from_matrix(&axes),
            velocity: b.velocity_m_s,
            angular_velocity: b.angular_velocity_rad_s,
            modal: None,
        });
    }
    let body_ref = |m: &Model, pth: &[Seg], name: &str| -> Result<BodyId, InputError> {
        if name == "ground" {
            return Ok(None);
        }
        m.bodies
            .iter()
            .position(|b| b.name == name)
            .map(Some)
            .ok_or_else(|| src.error(pth, format!("names a body '{name}' that does not exist")))
    };
    for b in 0..m.bodies.len() {
        let name = m.bodies[b].name.clone();
        let (pos, ax) = (
            m.bodies[b].position,
            super::math::rot(&m.bodies[b].orientation),
        );
        m.add_marker_world(format!("{name}.cm"), Some(b), pos, ax);
    }
    for (k, mk) in f.marker.iter().enumerate() {
        let body = body_ref(&m, &path!["marker", k, "body"], &mk.body)?;
        vec3(src, &path!["marker", k, "position_m"], &mk.position_m)?;
        let axes = axes_of(src, &path!["marker", k], mk.z_axis, mk.x_axis)?;
        if m.marker_index(&mk.name).is_some() {
            return Err(src.error(
                &path!["marker", k, "name"],
                format!("marker '{}' defined twice", mk.name),
            ));
        }
        m.add_marker_world(mk.name.clone(), body, mk.position_m, axes);
    }
    // Joints (or their bushing replacements).
    let mut joint_index = std::collections::HashMap::new();
    for (k, j) in f.joint.iter().enumerate() {
        let p = |s: &str| path!["joint", k, s];
        let kind = JointKind::parse(&j.kind).ok_or_else(|| {
            src.error(&p("type"), format!("unknown joint type '{}' (fixed, revolute, spherical, cylindrical, translational, universal, inline, inplane, perpendicular, orientation)", j.kind))
        })?;
        let bi = body_ref(&m, &p("body_i"), &j.body_i)?;
        let bj = body_ref(&m, &p("body_j"), &j.body_j)?;
        if bi == bj {
            return Err(src.error(&p("body_j"), "a joint needs two different bodies"));
        }
        vec3(src, &p("position_m"), &j.position_m)?;
        let axes = axes_of(src, &path!["joint", k], j.z_axis, j.x_axis)?;
        let replace = j.bushing.clone().or(f.model.joints_as_bushings.clone());
        // A universal joint's pins: z_axis on body_j, x_axis on body_i; marker I turns
        // its z onto the I pin (cyclic permutation keeps the frame right-handed). A
        // bushing in its place keeps J's axes on I too, so it starts undeflected.
        let axes_i = if kind == JointKind::Universal && replace.is_none() {
            let c = |k: usize| [axes[0][k], axes[1][k], axes[2][k]];
            let (x, y, z) = (c(0), c(1), c(2));
            [[y[0], z[0], x[0]], [y[1], z[1], x[1]], [y[2], z[2], x[2]]]
        } else {
            axes
        };
        let mi = m.add_marker_world(format!("{}.i", j.name), bi, j.position_m, axes_i);
        let mj = m.add_marker_world(format!("{}.j", j.name), bj, j.position_m, axes);
        if let Some(jb) = replace {
            check_joint_bushing(src, &path!["joint", k, "bushing"], &jb)?;
            let locked = kind.locked();
            let law = |a: usize, k_t: f64, k_r: f64| {
                Law::Linear(if locked[a] {
                    if a < 3 {
                        k_t
                    } else {
                        k_r
                    }
                } else {
                    0.0
                })
            };
            m.forces.push(Force::Bushing(Bushing {
                name: j.name.clone(),
                i: mi,
                j: mj,
                stiffness: std::array::from_fn(|a| law(a, jb.stiffness_n_m, jb.stiffness_n_m_rad)),
                damping: std::array::from_fn(|a| law(a, jb.damping_n_s_m, jb.damping_n_m_s_rad)),
                preload: [0.0; 6],
                replaces: Some(j.name.clone()),
            }));
        } else {
            joint_index.insert(j.name.clone(), m.joints.len());
            m.joints.push(Joint {
                name: j.name.clone(),
                kind,
                i: mi,
                j: mj,
            });
        }
    }
    for (k, s) in f.spring.iter().enumerate() {
        let p = |x: &str| path!["spring", k, x];
        let bi = body_ref(&m, &p("body_i"), &s.body_i)?;
        let bj = body_ref(&m, &p("body_j"), &s.body_j)?;
        vec3(src, &p("point_i_m"), &s.point_i_m)?;
        vec3(src, &p("point_j_m"), &s.point_j_m)?;
        let d = sub(&s.point_i_m, &s.point_j_m);
        let l0 = dot(&d, &d).sqrt();
        if l0.is_nan() || l0 <= 0.0 {
            return Err(src.error(
                &p("point_j_m"),
                "the two spring points coincide; a spring needs a line of action",
            ));
        }
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mi = m.add_marker_world(format!("{}.i", s.name), bi, s.point_i_m, id);
        let mj = m.add_marker_world(format!("{}.j", s.name), bj, s.point_j_m, id);
        let free_length = match s.free_length_m {
            Some(v) => src.positive(&p("free_length_m"), v)?,
            None => l0,
        };
        m.forces.push(Force::Spring(SpringDamper {
            name: s.name.clone(),
            i: mi,
            j: mj,
            free_length,
            preload: src.finite(&p("preload_n"), s.preload_n)?,
            spring: law_of(src, &p("stiffness_n_m"), &s.stiffness_n_m)?,
            damper: law_of(src, &p("damping_n_s_m"), &s.damping_n_s_m)?,
            bump_stop: stop_of(src, &p("bump_stop"), &s.bump_stop)?,
            rebound_stop: stop_of(src, &p("rebound_stop"), &s.rebound_stop)?,
        }));
    }
    for (k, b) in f.bushing.iter().enumerate() {
        let p = |x: &str| path!["bushing", k, x];
        let bi = body_ref(&m, &p("body_i"), &b.body_i)?;
        let bj = body_ref(&m, &p("body_j"), &b.body_j)?;
        vec3(src, &p("position_m"), &b.position_m)?;
        let axes = axes_of(src, &path!["bushing", k], b.z_axis, b.x_axis)?;
        let mi = m.add_marker_world(format!("{}.i", b.name), bi, b.position_m, axes);
        let mj = m.add_marker_world(format!("{}.j", b.name), bj, b.position_m, axes);
        let mut stiffness = Vec::new();
        let mut damping = Vec::new();
        for a in 0..3 {
            stiffness.push(law_of(
                src,
                &path!["bushing", k, "stiffness_n_m", a],
                &b.stiffness_n_m[a],
            )?);
            damping.push(law_of(
                src,
                &path!["bushing", k, "damping_n_s_m", a],
                &b.damping_n_s_m[a],
            )?);
        }
        for a in 0..3 {
            stiffness.push(law_of(
                src,
                &path!["bushing", k, "stiffness_n_m_rad", a],
                &b.stiffness_n_m_rad[a],
            )?);
            damping.push(law_of(
                src,
                &path!["bushing", k, "damping_n_m_s_rad", a],
                &b.damping_n_m_s_rad[a],
            )?);
        }
        let mut preload = [0.0; 6];
        for a in 0..3 {
            preload[a] = src.finite(&path!["bushing", k, "preload_n", a], b.preload_n[a])?;
            preload[3 + a] =
                src.finite(&path!["bushing", k, "preload_n_m", a], b.preload_n_m[a])?;
        }
        m.forces.push(Force::Bushing(Bushing {
            name: b.name.clone(),
            i: mi,
            j: mj,
            stiffness: stiffness.try_into().expect("six laws"),
            damping: damping.try_into().expect("six laws"),
            preload,
            replaces: None,
        }));
    }
    for (k, r) in f.rotational_spring.iter().enumerate() {
        let p = |x: &str| path!["rotational_spring", k, x];
        let bi = body_ref(&m, &p("body_i"), &r.body_i)?;
        let bj = body_ref(&m, &p("body_j"), &r.body_j)?;
        vec3(src, &p("position_m"), &r.position_m)?;
        let axes = axes_of(
            src,
            &path!["rotational_spring", k],
            Some(r.z_axis),
            r.x_axis,
        )?;
        let mi = m.add_marker_world(format!("{}.i", r.name), bi, r.position_m, axes);
        let mj = m.add_marker_world(format!("{}.j", r.name), bj, r.position_m, axes);
        m.forces.push(Force::Rot(RotSpring {
            name: r.name.clone(),
            i: mi,
            j: mj,
            free_angle: src.finite(&p("free_angle_rad"), r.free_angle_rad)?,
            preload: src.finite(&p("preload_n_m"), r.preload_n_m)?,
            spring: law_of(src, &p("stiffness_n_m_rad"), &r.stiffness_n_m_rad)?,
            damper: law_of(src, &p("damping_n_m_s_rad"), &r.damping_n_m_s_rad)?,
        }));
    }
    for (k, a) in f.force.iter().enumerate() {
        let p = |x: &str| path!["force", k, x];
        let bi = body_ref(&m, &p("body"), &a.body)?;
        if bi.is_none() {
            return Err(src.error(&p("body"), "a load on ground does nothing"));
        }
        vec3(src, &p("position_m"), &a.position_m)?;
        let axes = axes_of(src, &path!["force", k], a.z_axis, a.x_axis)?;
        let in_marker_axes = match a.axes.as_str() {
            "world" => false,
            "marker" => true,
            other => {
                return Err(src.error(
                    &p("axes"),
                    format!("'{other}': use \"world\" or \"marker\""),
                ))
            }
        };
        let mi = m.add_marker_world(format!("{}.i", a.name), bi, a.position_m, axes);
        let fns = |spec: &Option<[FnSpec; 3]>,
                   key: &str|
         -> Result<[Option<TimeFunction>; 3], InputError> {
            let mut out: [Option<TimeFunction>; 3] = [None, None, None];
            if let Some(s) = spec {
                for c in 0..3 {
                    out[c] = s[c].to_fn();
                    if let Some(f) = &out[c] {
                        f.check()
                            .map_err(|e| src.error(&path!["force", k, key, c], e))?;
                    }
                }
            }
            Ok(out)
        };
        m.forces.push(Force::Applied(Applied {
            name: a.name.clone(),
            i: mi,
            force: fns(&a.force_n, "force_n")?,
            torque: fns(&a.torque_n_m, "torque_n_m")?,
            in_marker_axes,
        }));
    }
    for (k, mo) in f.motion.iter().enumerate() {
        let p = |x: &str| path!["motion", k, x];
        let &joint = joint_index.get(&mo.joint).ok_or_else(|| {
            src.error(
                &p("joint"),
                format!(
                    "names a joint '{}' that does not exist (or was replaced by a bushing)",
                    mo.joint
                ),
            )
        })?;
        let kind = m.joints[joint].kind;
        let dof = match (mo.dof.as_deref(), kind) {
            (Some("rotation"), JointKind::Revolute | JointKind::Cylindrical) => MotionDof::Rotation,
            (Some("translation"), JointKind::Translational | JointKind::Cylindrical) => MotionDof::Translation,
            (None, JointKind::Revolute) => MotionDof::Rotation,
            (None, JointKind::Translational) => MotionDof::Translation,
            (d, _) => {
                return Err(src.error(&p("dof"), format!("{d:?} cannot drive a {} joint (rotation: revolute, cylindrical; translation: translational, cylindrical)", kind.name())))
            }
        };
        let (function, is_velocity) = match (&mo.displacement, &mo.velocity) {
            (Some(f), None) => (f.clone(), false),
            (None, Some(f)) => (f.clone(), true),
            _ => {
                return Err(src.error(
                    &p("displacement"),
                    "give exactly one of displacement or velocity",
                ))
            }
        };
        function.check().map_err(|e| {
            src.error(
                &p(if is_velocity {
                    "velocity"
                } else {
                    "displacement"
                }),
                e,
            )
        })?;
        m.motions.push(Motion {
            name: mo.name.clone(),
            joint,
            dof,
            function,
            is_velocity,
        });
    }
    for (k, o) in f.output.iter().enumerate() {
        let out = output_of(src, &m, k, o, &joint_index)?;
        m.outputs.push(out);
    }
    Ok(Mechanism {
        model: m,
        run: f.run,
        solver: f.solver,
    })
}

fn check_run(src: &Source, r: &RunSpec) -> Result<(), InputError> {
    src.positive(&path!["run", "end_time_s"], r.end_time_s)?;
    src.positive(&path!["run", "sample_rate_hz"], r.sample_rate_hz)?;
    Ok(())
}

fn check_joint_bushing(src: &Source, p: &[Seg], jb: &JointBushing) -> Result<(), InputError> {
    let at = |k: &str| {
        let mut v = p.to_vec();
        v.push(Seg::from(k));
        v
    };
    src.positive(&at("stiffness_n_m"), jb.stiffness_n_m)?;
    src.positive(&at("stiffness_n_m_rad"), jb.stiffness_n_m_rad)?;
    src.non_negative(&at("damping_n_s_m"), jb.damping_n_s_m)?;
    src.non_negative(&at("damping_n_m_s_rad"), jb.damping_n_m_s_rad)?;
    Ok(())
}

fn vec3(src: &Source, p: &[Seg], v: &[f64; 3]) -> Result<(), InputError> {
    for (c, x) in v.iter().enumerate() {
        let mut pc = p.to_vec();
        pc.push(Seg::Index(c));
        src.finite(&pc, *x)?;
    }
    Ok(())
}

fn axes_of(
    src: &Source,
    p: &[Seg],
    z: Option<[f64; 3]>,
    x: Option<[f64; 3]>,
) -> Result<[[f64; 3]; 3], InputError> {
    let at = |k: &str| {
        let mut v = p.to_vec();
        v.push(Seg::from(k));
        v
    };
    if let Some(z) = z {
        vec3(src, &at("z_axis"), &z)?;
    }
    if let Some(x) = x {
        vec3(src, &at("x_axis"), &x)?;
    }
    let z = z.unwrap_or([0.0, 0.0, 1.0]);
    frame_from_axes(z, x).ok_or_else(|| {
        src.error(
            &at(if x.is_some() { "x_axis" } else { "z_axis" }),
            "axes must be non-zero and x_axis not parallel to z_axis",
        )
    })
}

/// Symmetric, positive definite, triangle inequality (a physical rigid body).
fn inertia_tensor(src: &Source, k: usize, v: &[f64]) -> Result<[[f64; 3]; 3], InputError> {
    let p = path!["body", k, "inertia_kg_m2"];
    for (c, x) in v.iter().enumerate() {
        src.finite(&path!["body", k, "inertia_kg_m2", c], *x)?;
    }
    let (ixx, iyy, izz, ixy, ixz, iyz) = match v.len() {
        3 => (v[0], v[1], v[2], 0.0, 0.0, 0.0),
        6 => (v[0], v[1], v[2], v[3], v[4], v[5]),
        n => {
            return Err(src.error(
                &p,
                format!("give 3 (Ixx, Iyy, Izz) or 6 (plus Ixy, Ixz, Iyz) values, not {n}"),
            ))
        }
    };
    for (c, d) in [ixx, iyy, izz].iter().enumerate() {
        if d.is_nan() || *d <= 0.0 {
            return Err(src.error(
                &path!["body", k, "inertia_kg_m2", c],
                format!("principal moment must be positive, got {d}"),
            ));
        }
    }
    let t = [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]];
    let e = nalgebra::Matrix3::from_fn(|r, c| t[r][c]).symmetric_eigenvalues();
    let (a, b, c) = (e[0], e[1], e[2]);
    let tol = 1e-9 * (a + b + c);
    if a <= 0.0 || b <= 0.0 || c <= 0.0 || a + b < c - tol || a + c < b - tol || b + c < a - tol {
        return Err(src.error(&p, format!("not a physical inertia tensor (principal moments {a:.4e}, {b:.4e}, {c:.4e} must be positive and satisfy the triangle inequality)")));
    }
    Ok(t)
}

fn law_of(src: &Source, p: &[Seg], l: &LawSpec) -> Result<Law, InputError> {
    match l {
        LawSpec::Linear(k) => Ok(Law::Linear(src.non_negative(p, *k)?)),
        LawSpec::Table { x, y } => Spline::new(x, y)
            .map(Law::Curve)
            .map_err(|e| src.error(p, e)),
    }
}

fn stop_of(src: &Source, p: &[Seg], s: &Option<StopSpec>) -> Result<Option<Stop>, InputError> {
    let Some(s) = s else { return Ok(None) };
    let at = |k: &str| {
        let mut v = p.to_vec();
        v.push(Seg::from(k));
        v
    };
    let exponent = src.finite(&at("exponent"), s.exponent)?;
    if exponent < 1.0 {
        return Err(src.error(
            &at("exponent"),
            "must be at least 1 (a force that starts from zero)",
        ));
    }
    Ok(Some(Stop {
        clearance: src.non_negative(&at("clearance_m"), s.clearance_m)?,
        stiffness: src.positive(&at("stiffness_n_m"), s.stiffness_n_m)?,
        exponent,
        damping: src.non_negative(&at("damping_n_s_m"), s.damping_n_s_m)?,
        damping_depth: src.non_negative(&at("damping_depth_m"), s.damping_depth_m)?,
    }))
}

fn output_of(
    src: &Source,
    m: &Model,
    k: usize,
    o: &OutputSpec,
    joints: &std::collections::HashMap<String, usize>,
) -> Result<Output, InputError> {
    let p = |x: &str| path!["output", k, x];
    let axes = match o.axes.as_deref() {
        None | Some("world") => Axes::World,
        Some(name) => Axes::Marker(
            m.marker_index(name)
                .ok_or_else(|| src.error(&p("axes"), format!("no marker '{name}'")))?,
        ),
    };
    let bad_q = |allowed: &str| {
        src.error(
            &p("quantity"),
            format!("'{}' is not one of {allowed}", o.quantity),
        )
    };
    let (request, default_name) = match (&o.marker, &o.joint, &o.element) {
        (Some(mk), None, None) => {
            let marker = m.marker_index(mk).ok_or_else(|| {
                src.error(
                    &p("marker"),
                    format!(
                        "names a marker '{mk}' that does not exist (body centres are '<body>.cm')"
                    ),
                )
            })?;
            let quantity =
                match o.quantity.as_str() {
                    "position" => MarkerQuantity::Position,
                    "velocity" => MarkerQuantity::Velocity,
                    "acceleration" => MarkerQuantity::Acceleration,
                    "angular_velocity" => MarkerQuantity::AngularVelocity,
                    "angular_acceleration" => MarkerQuantity::AngularAcceleration,
                    _ => return Err(bad_q(
                        "position, velocity, acceleration, angular_velocity, angular_acceleration",
                    )),
                };
            (
                Request::Marker {
                    marker,
                    quantity,
                    axes,
                },
                mk.clone(),
            )
        }
        (None, Some(j), None) => {
            let &joint = joints.get(j).ok_or_else(|| src.error(&p("joint"), format!("names a joint '{j}' that does not exist (or was replaced by a bushing: ask for its element outputs)")))?;
            let quantity = match o.quantity.as_str() {
                "force" => JointQuantity::Force,
                "torque" => JointQuantity::Torque,
                "displacement" => JointQuantity::Displacement,
                _ => return Err(bad_q("force, torque, displacement")),
            };
            (
                Request::Joint {
                    joint,
                    quantity,
                    axes,
                },
                j.clone(),
            )
        }
        (None, None, Some(e)) => {
            let element = m.forces.iter().position(|f| f.name() == e).ok_or_else(|| {
                src.error(
                    &p("element"),
                    format!("names an element '{e}' that does not exist"),
                )
            })?;
            let quantity = match o.quantity.as_str() {
                "force" => ElementQuantity::Force,
                "deflection" => ElementQuantity::Deflection,
                "velocity" => ElementQuantity::Velocity,
                _ => return Err(bad_q("force, deflection, velocity")),
            };
            (Request::Element { element, quantity }, e.clone())
        }
        _ => {
            return Err(src.error(
                &path!["output", k],
                "give exactly one of marker, joint or element",
            ))
        }
    };
    Ok(Output::new(
        o.name
            .clone()
            .unwrap_or(format!("{default_name}.{}", o.quantity)),
        request,
    ))
}
