//! The generic mechanism file (TOML): bodies, markers, joints, springs, bushings,
//! rotational springs, applied loads, motions, outputs, run and solver settings.
//! `docs/mechanism.md` documents every field with an example.
//!
//! Positions and axes are written in world coordinates at the initial configuration
//! (hardpoints), as vehicle engineers give them; the builder turns them into body-fixed
//! markers once.

use super::suggest::did_you_mean;
use std::path::Path;

use serde::Deserialize;

use super::builder::{BodyDesc, ModelBuilder};
use super::desc::{
    Accelerations, Axes, ElementQuantity, JointHandle, JointKind, JointQuantity, MarkerQuantity,
    Model, MotionDof, Output, Request,
};
use super::elements;
pub use super::elements::JointBushing;
use super::function::TimeFunction;
use crate::input::{InputError, Loader, Source};
use crate::path;
use towride_solver::SolverOptions;

/// The tables of a mechanism file other than the force elements' (whose tables the
/// element registry lists: `model::elements::TABLES`).
#[derive(Deserialize, Debug)]
pub struct File {
    /// Name, gravity, joint replacement.
    pub model: ModelSpec,
    /// Run settings.
    #[serde(default)]
    pub run: RunSpec,
    /// Integrator settings.
    #[serde(default)]
    pub solver: SolverOptions,
    /// Bodies.
    #[serde(default)]
    pub body: Vec<BodySpec>,
    /// Extra markers (outputs, axes).
    #[serde(default)]
    pub marker: Vec<MarkerSpec>,
    /// Ideal joints (or bushings in their place).
    #[serde(default)]
    pub joint: Vec<JointSpec>,
    /// Prescribed joint motions.
    #[serde(default)]
    pub motion: Vec<MotionSpec>,
    /// Requested outputs.
    #[serde(default)]
    pub output: Vec<OutputSpec>,
    /// Every other top-level key: a force element table, or an error.
    #[serde(flatten)]
    pub other: std::collections::BTreeMap<String, toml::Value>,
}

/// `[model]`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// The model's name.
    pub name: String,
    /// Gravity in world axes [m/s^2].
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

/// `[run]`.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// End time [s].
    pub end_time_s: f64,
    /// Output sample rate [Hz].
    pub sample_rate_hz: f64,
    /// Where the run starts from.
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

/// A `[[body]]`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name, unique; `ground` is reserved.
    pub name: String,
    /// Mass [kg].
    pub mass_kg: f64,
    /// [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] about the centre of mass, in the
    /// body axes given by z_axis / x_axis.
    pub inertia_kg_m2: Vec<f64>,
    /// Centre of mass, world coordinates [m].
    pub cm_position_m: [f64; 3],
    /// Body z axis (default world z).
    pub z_axis: Option<[f64; 3]>,
    /// Body x axis.
    pub x_axis: Option<[f64; 3]>,
    /// Initial velocity [m/s].
    #[serde(default)]
    pub velocity_m_s: [f64; 3],
    /// Initial angular velocity, world axes [rad/s].
    #[serde(default)]
    pub angular_velocity_rad_s: [f64; 3],
}

/// A `[[marker]]`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct MarkerSpec {
    /// Name, unique.
    pub name: String,
    /// The body it is fixed on (`ground` for the ground).
    pub body: String,
    /// Origin, world coordinates [m].
    pub position_m: [f64; 3],
    /// z axis.
    pub z_axis: Option<[f64; 3]>,
    /// x axis.
    pub x_axis: Option<[f64; 3]>,
}

/// A `[[joint]]`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Name, unique among the joints.
    pub name: String,
    /// fixed, revolute, spherical, cylindrical, translational, universal, inline,
    /// inplane, perpendicular, orientation.
    #[serde(rename = "type")]
    pub kind: String,
    /// The moving body.
    pub body_i: String,
    /// The reference body.
    pub body_j: String,
    /// Joint point, world coordinates [m].
    pub position_m: [f64; 3],
    /// Joint axis.
    pub z_axis: Option<[f64; 3]>,
    /// Second axis.
    pub x_axis: Option<[f64; 3]>,
    /// Replace this joint by a bushing.
    pub bushing: Option<JointBushing>,
}

/// A `[[motion]]`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct MotionSpec {
    /// Name.
    pub name: String,
    /// The joint driven.
    pub joint: String,
    /// "rotation" or "translation"; default from the joint type.
    pub dof: Option<String>,
    /// Displacement [m or rad] as a function of time, or...
    pub displacement: Option<TimeFunction>,
    /// ...velocity [m/s or rad/s], integrated from zero at t = 0.
    pub velocity: Option<TimeFunction>,
}

/// An `[[output]]`.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Channel name (default `<item>.<quantity>`).
    pub name: Option<String>,
    /// A marker's kinematics...
    pub marker: Option<String>,
    /// ...or a joint's reaction or coordinate...
    pub joint: Option<String>,
    /// ...or an element's force, deflection or velocity.
    pub element: Option<String>,
    /// What to report.
    pub quantity: String,
    /// "world" (default) or a marker name.
    pub axes: Option<String>,
}

/// A mechanism read from a file, validated and ready to assemble.
pub struct Mechanism {
    /// The model.
    pub model: Model,
    /// Run settings.
    pub run: RunSpec,
    /// Integrator settings.
    pub solver: SolverOptions,
    /// The overrides that took effect (placed, not superseded).
    pub overrides: Vec<crate::input::Applied>,
}

/// Reads and validates a mechanism file, read through `loader` (its overrides; one
/// that matches nothing read is an error).
pub fn load(path: &Path, loader: &Loader) -> Result<Mechanism, InputError> {
    let loader = loader.fresh();
    let src = loader.toml(path)?;
    let file: File = src.parse()?;
    let mut m = build(&src, file)?;
    loader.check_used()?;
    m.overrides = loader.applied();
    Ok(m)
}

/// Validates a parsed file into a model, through the model builder; every refusal is
/// located at its file, line and field.
pub fn build(src: &Source, f: File) -> Result<Mechanism, InputError> {
    for key in f.other.keys() {
        if !elements::TABLES.contains(&key.as_str()) {
            return Err(src.error(
                &path![key.as_str()],
                format!(
                    "unknown table `{key}` (expected model, run, solver, body, marker, joint, motion, output or an element table: {})",
                    elements::TABLES.join(", ")
                ),
            ));
        }
    }
    let mut b = ModelBuilder::new(&f.model.name, f.model.gravity_m_s2);
    b.check_gravity()
        .map_err(|e| src.locate(&path![], e.into_field()))?;
    b.set_joints_as_bushings(f.model.joints_as_bushings.clone())
        .map_err(|e| src.locate(&path![], e.into_field()))?;
    check_run(src, &f.run)?;
    solver_keys_used(src, f.solver.method)?;
    f.solver
        .validate(1)
        .map_err(|e| src.error(&path!["solver"], e.to_string()))?;
    for (k, s) in f.body.iter().enumerate() {
        let at = path!["body", k];
        let axes = b
            .axes_from(s.z_axis, s.x_axis)
            .map_err(|e| src.locate(&at, e))?;
        let inertia = crate::model::builder::inertia_tensor(&s.inertia_kg_m2)
            .map_err(|e| src.locate(&at, e.under("inertia_kg_m2")))?;
        b.body(BodyDesc {
            name: s.name.clone(),
            mass: s.mass_kg,
            inertia,
            cm: s.cm_position_m,
            axes,
            velocity: s.velocity_m_s,
            angular_velocity: s.angular_velocity_rad_s,
        })
        .map_err(|e| src.locate(&at, e.into_field()))?;
    }
    for (k, s) in f.marker.iter().enumerate() {
        let at = path!["marker", k];
        let body = b
            .body_by_name(&s.body)
            .map_err(|e| src.locate(&at, e.under("body")))?;
        let axes = b
            .axes_from(s.z_axis, s.x_axis)
            .map_err(|e| src.locate(&at, e))?;
        b.marker(&s.name, body, s.position_m, &axes)
            .map_err(|e| src.locate(&at, e.into_field()))?;
    }
    for (k, s) in f.joint.iter().enumerate() {
        let at = path!["joint", k];
        let kind = JointKind::parse(&s.kind).ok_or_else(|| {
            src.error(&path!["joint", k, "type"], format!("unknown joint type '{}' (fixed, revolute, spherical, cylindrical, translational, universal, inline, inplane, perpendicular, orientation)", s.kind))
        })?;
        let bi = b
            .body_by_name(&s.body_i)
            .map_err(|e| src.locate(&at, e.under("body_i")))?;
        let bj = b
            .body_by_name(&s.body_j)
            .map_err(|e| src.locate(&at, e.under("body_j")))?;
        let axes = b
            .axes_from(s.z_axis, s.x_axis)
            .map_err(|e| src.locate(&at, e))?;
        b.joint(
            &s.name,
            kind,
            bi,
            bj,
            s.position_m,
            &axes,
            s.bushing.as_ref(),
        )
        .map_err(|e| src.locate(&at, e.into_field()))?;
    }
    elements::add_all_from_file(src, &mut b)?;
    for (k, s) in f.motion.iter().enumerate() {
        let at = path!["motion", k];
        let joint = b.joint_by_name(&s.joint).ok_or_else(|| {
            src.error(
                &path!["motion", k, "joint"],
                format!(
                    "names a joint '{}' that does not exist (or was replaced by a bushing)",
                    s.joint
                ),
            )
        })?;
        let dof = match s.dof.as_deref() {
            None => None,
            Some("rotation") => Some(MotionDof::Rotation),
            Some("translation") => Some(MotionDof::Translation),
            Some(other) => {
                return Err(src.error(
                    &path!["motion", k, "dof"],
                    format!("'{other}': use \"rotation\" or \"translation\""),
                ))
            }
        };
        let (function, is_velocity) = match (&s.displacement, &s.velocity) {
            (Some(f), None) => (f.clone(), false),
            (None, Some(f)) => (f.clone(), true),
            _ => {
                return Err(src.error(
                    &path!["motion", k, "displacement"],
                    "give exactly one of displacement or velocity",
                ))
            }
        };
        b.motion(&s.name, joint, dof, function, is_velocity)
            .map_err(|e| src.locate(&at, e.into_field()))?;
    }
    let mut m = b.finish();
    m.accelerations = f.run.accelerations;
    let joints: std::collections::HashMap<String, JointHandle> =
        m.each_joint().map(|(k, j)| (j.name.clone(), k)).collect();
    for (k, o) in f.output.iter().enumerate() {
        let out = output_of(src, &m, k, o, &joints)?;
        m.outputs.push(out);
    }
    Ok(Mechanism {
        model: m,
        run: f.run,
        solver: f.solver,
        overrides: Vec::new(),
    })
}

fn check_run(src: &Source, r: &RunSpec) -> Result<(), InputError> {
    src.positive(&path!["run", "end_time_s"], r.end_time_s)?;
    src.positive(&path!["run", "sample_rate_hz"], r.sample_rate_hz)?;
    crate::input::bounds::budget::check(r.end_time_s, r.sample_rate_hz, 0)
        .map_err(|e| src.error(&path!["run", "sample_rate_hz"], e.to_string()))?;
    Ok(())
}

/// The output `[[output]]` number `k` asks for, its names resolved against `m` (an unknown
/// name is an error at its field, with the closest names suggested). Scenes read their
/// `[[output]]` tables through this too.
pub fn output_of(
    src: &Source,
    m: &Model,
    k: usize,
    o: &OutputSpec,
    joints: &std::collections::HashMap<String, JointHandle>,
) -> Result<Output, InputError> {
    let p = |x: &str| path!["output", k, x];
    let axes = match o.axes.as_deref() {
        None | Some("world") => Axes::World,
        Some(name) => Axes::Marker(m.marker_by_name(name).ok_or_else(|| {
            src.error(
                &p("axes"),
                format!(
                    "no marker '{name}'{}",
                    did_you_mean(name, m.markers.iter().map(|k| k.name.as_str()))
                ),
            )
        })?),
    };
    let bad_q = |allowed: &str| {
        src.error(
            &p("quantity"),
            format!(
                "'{}' is not one of {allowed}{}",
                o.quantity,
                did_you_mean(&o.quantity, allowed.split(", "))
            ),
        )
    };
    let (request, default_name) = match (&o.marker, &o.joint, &o.element) {
        (Some(mk), None, None) => {
            let marker = m.marker_by_name(mk).ok_or_else(|| {
                src.error(
                    &p("marker"),
                    format!(
                        "names a marker '{mk}' that does not exist{} (body centres are '<body>.cm')",
                        did_you_mean(mk, m.markers.iter().map(|k| k.name.as_str()))
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
            let &joint = joints.get(j).ok_or_else(|| {
                src.error(
                    &p("joint"),
                    format!(
                        "names a joint '{j}' that does not exist{} (or was replaced by a bushing: ask for its element outputs)",
                        did_you_mean(j, m.joints.iter().map(|k| k.name.as_str()))
                    ),
                )
            })?;
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
            let element = m.element_by_name(e).ok_or_else(|| {
                src.error(
                    &p("element"),
                    format!(
                        "names an element '{e}' that does not exist{}",
                        did_you_mean(e, m.forces.iter().map(|f| f.name()))
                    ),
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

/// Refuses `[solver]` keys the file's method does not read (`[solver.radau]` under a BDF
/// method, `max_order` under Radau IIA): the value would silently change nothing.
pub fn solver_keys_used(src: &Source, method: towride_solver::Method) -> Result<(), InputError> {
    let raw: Option<toml::Table> = src.text().parse().ok();
    let Some(solver) = raw
        .as_ref()
        .and_then(|t| t.get("solver")?.as_table().cloned())
    else {
        return Ok(());
    };
    for key in method.unused_keys() {
        if solver.contains_key(*key) {
            return Err(src.error(
                &path!["solver", *key],
                format!(
                    "the method in use ({}) does not read `{key}`; remove it or choose a method that does",
                    method_name(method)
                ),
            ));
        }
    }
    Ok(())
}

fn method_name(m: towride_solver::Method) -> &'static str {
    match m {
        towride_solver::Method::Variable => "variable-coefficient BDF",
        towride_solver::Method::FixedCoefficient => "fixed-coefficient BDF",
        towride_solver::Method::Radau5 => "Radau IIA",
    }
}
