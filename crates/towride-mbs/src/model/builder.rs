//! The one way to build a [`Model`]: bodies, markers, joints (or the bushings that
//! replace them), force elements, motions, tyres, speed controllers and outputs, added
//! through [`ModelBuilder`] with every value checked once, here. Mechanism files
//! (`spec.rs`) and vehicle templates (`crate::vehicle`) are thin translations into it;
//! Rust programs can use it directly:
//!
//! ```
//! use towride_mbs::model::builder::{BodyDesc, ModelBuilder, IDENTITY};
//! use towride_mbs::model::desc::JointKind;
//!
//! let mut b = ModelBuilder::new("pendulum", [0.0, 0.0, -9.81]);
//! let link = b
//!     .body(BodyDesc::new("link", 1.0, [0.01, 0.01, 0.01], [0.5, 0.0, 0.0]))
//!     .unwrap();
//! b.joint("pivot", JointKind::Revolute, Some(link), None, [0.0; 3], &IDENTITY, None)
//!     .unwrap();
//! let model = b.finish();
//! assert_eq!(model.bodies.len(), 1);
//! ```
//!
//! Geometry is given in the coordinates of the current subsystem ([`Placement`], the
//! world by default): hardpoints at the initial configuration, as vehicle engineers
//! write them. The builder turns them into body-fixed markers once.

use std::collections::HashSet;

use super::desc::{
    Body, Carrier, Joint, JointKind, Marker, Model, Motion, MotionDof, Output, SpeedControl,
    TwoMarkers, TyreElem,
};
pub use super::desc::{BodyHandle, ElementHandle, JointHandle, MarkerHandle, TyreHandle};
use super::elements::law::{finite, positive};
use super::elements::{
    Applied, Bushing, FieldError, Force, JointBushing, Law, RotSpring, SpringDamper, Stop,
};
use super::function::TimeFunction;
use super::math::{add, dot, frame_from_axes, mm, mtv, mv, quat_from_matrix, rot, sub, transpose};
use super::ModelError;

/// A point or vector [m].
pub type V = [f64; 3];
/// A frame's axes as columns.
pub type Axes = [[f64; 3]; 3];

/// The identity frame.
pub const IDENTITY: Axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// What an ideal joint became: either way a link between two markers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Link {
    /// The ideal joint.
    Joint(JointHandle),
    /// The bushing that replaces it, and its markers (kept here, as the element list
    /// does not say which kind of element a handle names).
    Bushing(ElementHandle, TwoMarkers),
}

impl Link {
    /// The joint or the bushing, as an output names what carries a load.
    pub fn carrier(self) -> Carrier {
        match self {
            Link::Joint(k) => Carrier::Joint(k),
            Link::Bushing(e, _) => Carrier::Element(e),
        }
    }

    /// Markers I and J of the joint or bushing.
    pub fn markers(self, model: &Model) -> TwoMarkers {
        match self {
            Link::Joint(k) => model.joints[k].markers(),
            Link::Bushing(_, markers) => markers,
        }
    }
}

/// A rigid placement of subsystem coordinates in the world: p_world = R p + t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Subsystem axes in world axes (columns).
    pub rotation: Axes,
    /// Subsystem origin in the world [m].
    pub translation: V,
}

impl Placement {
    /// The world itself.
    pub const WORLD: Placement = Placement {
        rotation: IDENTITY,
        translation: [0.0; 3],
    };

    /// A translation by `t`.
    pub fn translate(t: V) -> Placement {
        Placement {
            rotation: IDENTITY,
            translation: t,
        }
    }

    /// Rotation by `angle` [rad] about the y axis through `pivot` (subsystem
    /// coordinates), then the translation `t`.
    pub fn pitched(pivot: V, angle: f64, t: V) -> Placement {
        let (s, c) = angle.sin_cos();
        let r = [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]];
        let shift = sub(&pivot, &mv(&r, &pivot));
        Placement {
            rotation: r,
            translation: add(&shift, &t),
        }
    }

    /// A subsystem point in the world.
    pub fn point(&self, p: V) -> V {
        add(&mv(&self.rotation, &p), &self.translation)
    }

    /// A subsystem vector in world axes.
    pub fn vector(&self, v: V) -> V {
        mv(&self.rotation, &v)
    }

    /// A vector given in world axes, in subsystem axes.
    pub fn vector_local(&self, v: V) -> V {
        mtv(&self.rotation, &v)
    }

    /// Subsystem axes in world axes.
    pub fn axes(&self, a: &Axes) -> Axes {
        mm(&self.rotation, a)
    }
}

/// A rigid body to add: mass properties and initial state, in subsystem coordinates.
#[derive(Clone, Debug)]
pub struct BodyDesc {
    /// Name, unique; `ground` is reserved.
    pub name: String,
    /// Mass [kg].
    pub mass: f64,
    /// Inertia tensor about the centre of mass in the body's axes [kg m^2]
    /// ([`inertia_tensor`] makes one from the 3 or 6 values files give).
    pub inertia: [[f64; 3]; 3],
    /// Centre of mass [m].
    pub cm: V,
    /// Body axes (columns).
    pub axes: Axes,
    /// Initial velocity of the centre of mass [m/s].
    pub velocity: V,
    /// Initial angular velocity, world axes [rad/s].
    pub angular_velocity: V,
}

impl BodyDesc {
    /// A body at rest with principal moments `inertia` about axes along the subsystem's.
    pub fn new(name: &str, mass: f64, inertia: [f64; 3], cm: V) -> BodyDesc {
        BodyDesc {
            name: name.into(),
            mass,
            inertia: [
                [inertia[0], 0.0, 0.0],
                [0.0, inertia[1], 0.0],
                [0.0, 0.0, inertia[2]],
            ],
            cm,
            axes: IDENTITY,
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
        }
    }
}

/// A spring-damper along the line between two points, before it is added.
#[derive(Clone, Debug)]
pub struct SpringLine {
    /// Name, unique among the elements.
    pub name: String,
    /// Body at one end (`None`: ground).
    pub body_i: Option<BodyHandle>,
    /// That end [m].
    pub point_i: V,
    /// Body at the other end.
    pub body_j: Option<BodyHandle>,
    /// The other end [m].
    pub point_j: V,
    /// Relaxed length [m] (default: the distance of the points).
    pub free_length: f64,
    /// Repulsive force at the free length [N].
    pub preload: f64,
    /// Spring law.
    pub spring: Law,
    /// Damper law.
    pub damper: Law,
    /// Stop in compression.
    pub bump_stop: Option<Stop>,
    /// Stop in extension.
    pub rebound_stop: Option<Stop>,
}

impl SpringLine {
    /// A line element without force laws, free at its current length.
    pub fn new(
        name: &str,
        body_i: Option<BodyHandle>,
        point_i: V,
        body_j: Option<BodyHandle>,
        point_j: V,
    ) -> SpringLine {
        let d = sub(&point_i, &point_j);
        SpringLine {
            name: name.into(),
            body_i,
            point_i,
            body_j,
            point_j,
            free_length: dot(&d, &d).sqrt(),
            preload: 0.0,
            spring: Law::Linear(0.0),
            damper: Law::Linear(0.0),
            bump_stop: None,
            rebound_stop: None,
        }
    }
}

/// A 6-DOF bushing at one point, before it is added.
#[derive(Clone, Debug)]
pub struct BushingLine {
    /// Name, unique among the elements.
    pub name: String,
    /// Body of marker I.
    pub body_i: Option<BodyHandle>,
    /// Body of marker J.
    pub body_j: Option<BodyHandle>,
    /// Where both markers sit [m].
    pub point: V,
    /// The bushing's axes.
    pub axes: Axes,
    /// Per direction x, y, z, rx, ry, rz.
    pub stiffness: [Law; 6],
    /// Per direction.
    pub damping: [Law; 6],
    /// Per direction [N or N m].
    pub preload: [f64; 6],
}

/// A rotational spring-damper about the z axis of `axes`, before it is added.
#[derive(Clone, Debug)]
pub struct RotLine {
    /// Name, unique among the elements.
    pub name: String,
    /// Body of marker I.
    pub body_i: Option<BodyHandle>,
    /// Body of marker J.
    pub body_j: Option<BodyHandle>,
    /// Where both markers sit [m].
    pub point: V,
    /// The markers' axes; z is the spring's axis.
    pub axes: Axes,
    /// Relaxed angle [rad].
    pub free_angle: f64,
    /// Torque at the free angle [N m].
    pub preload: f64,
    /// Spring law.
    pub spring: Law,
    /// Damper law.
    pub damper: Law,
}

/// A load of time on one body, before it is added.
#[derive(Clone, Debug)]
pub struct AppliedLine {
    /// Name, unique among the elements.
    pub name: String,
    /// The body loaded (not the ground).
    pub body: Option<BodyHandle>,
    /// Point of application [m].
    pub point: V,
    /// The marker's axes.
    pub axes: Axes,
    /// Force components [N].
    pub force: [Option<TimeFunction>; 3],
    /// Torque components [N m].
    pub torque: [Option<TimeFunction>; 3],
    /// Components in the marker's axes, else in world axes.
    pub in_marker_axes: bool,
}

/// Builds a [`Model`], checking every value as it is added.
pub struct ModelBuilder {
    model: Model,
    place: Placement,
    joints_as_bushings: Option<JointBushing>,
    body_place: Vec<Placement>,
    body_names: HashSet<String>,
    marker_names: HashSet<String>,
    joint_names: HashSet<String>,
    element_names: HashSet<String>,
}

impl ModelBuilder {
    /// An empty model named `name` with gravity `gravity` [m/s^2] in world axes.
    pub fn new(name: &str, gravity: V) -> ModelBuilder {
        ModelBuilder {
            model: Model {
                name: name.into(),
                gravity,
                ..Default::default()
            },
            place: Placement::WORLD,
            joints_as_bushings: None,
            body_place: Vec::new(),
            body_names: HashSet::new(),
            marker_names: HashSet::new(),
            joint_names: HashSet::new(),
            element_names: HashSet::new(),
        }
    }

    /// A builder that goes on adding to `model` (its names stay taken).
    pub fn from_model(model: Model) -> ModelBuilder {
        let names = |it: &mut dyn Iterator<Item = String>| it.collect::<HashSet<String>>();
        ModelBuilder {
            body_names: names(&mut model.bodies.iter().map(|b| b.name.clone())),
            marker_names: names(&mut model.markers.iter().map(|m| m.name.clone())),
            joint_names: names(&mut model.joints.iter().map(|j| j.name.clone()).chain(
                model.forces.iter().filter_map(|f| match f {
                    Force::Bushing(b) => b.replaces.clone(),
                    _ => None,
                }),
            )),
            element_names: names(&mut model.forces.iter().map(|f| f.name().to_string())),
            body_place: vec![Placement::WORLD; model.bodies.len()],
            place: Placement::WORLD,
            joints_as_bushings: None,
            model,
        }
    }

    /// Checks the gravity vector (finite components).
    pub fn check_gravity(&self) -> Result<(), ModelError> {
        for (c, g) in self.model.gravity.iter().enumerate() {
            finite(*g).map_err(|m| build("model", FieldError::at(c, m).under("gravity_m_s2")))?;
        }
        Ok(())
    }

    /// The model so far.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The model so far, for changes the builder does not make (a template setting a
    /// preload once the design statics know it).
    pub fn model_mut(&mut self) -> &mut Model {
        &mut self.model
    }

    /// The finished model.
    pub fn finish(self) -> Model {
        self.model
    }

    /// Where the coordinates handed to the builder lie in the world from now on.
    pub fn set_place(&mut self, p: Placement) {
        self.place = p;
    }

    /// The current placement.
    pub fn place(&self) -> Placement {
        self.place
    }

    /// Every body built so far by name, with its handle.
    pub fn body_handles(&self) -> impl Iterator<Item = (&str, BodyHandle)> {
        self.model()
            .bodies
            .iter()
            .enumerate()
            .map(|(k, b)| (b.name.as_str(), BodyHandle(k)))
    }

    /// The placement each body was created in (indexed like `Model::bodies`).
    pub fn body_places(&self) -> &[Placement] {
        &self.body_place
    }

    /// Every ideal joint added from now on becomes a bushing of these properties.
    pub fn set_joints_as_bushings(&mut self, jb: Option<JointBushing>) -> Result<(), ModelError> {
        if let Some(j) = &jb {
            j.check()
                .map_err(|e| build("model", e.under("joints_as_bushings")))?;
        }
        self.joints_as_bushings = jb;
        Ok(())
    }

    /// The body named `name` (`ground`: `None`), or an error naming the missing one.
    pub fn body_by_name(&self, name: &str) -> Result<Option<BodyHandle>, FieldError> {
        if name == "ground" {
            return Ok(None);
        }
        self.model
            .bodies
            .iter()
            .position(|b| b.name == name)
            .map(|k| Some(BodyHandle(k)))
            .ok_or_else(|| FieldError::here(format!("names a body '{name}' that does not exist")))
    }

    /// The marker named `name`.
    pub fn marker_by_name(&self, name: &str) -> Option<MarkerHandle> {
        self.model.marker_by_name(name)
    }

    /// The joint named `name` (an ideal joint, not one replaced by a bushing).
    pub fn joint_by_name(&self, name: &str) -> Option<JointHandle> {
        self.model.joint_by_name(name)
    }

    /// The element named `name`.
    pub fn element_by_name(&self, name: &str) -> Option<ElementHandle> {
        self.model.element_by_name(name)
    }

    /// Axes from a z axis (default world z) and an optional x axis; errors at `z_axis`
    /// or `x_axis`.
    pub fn axes_from(&self, z: Option<V>, x: Option<V>) -> Result<Axes, FieldError> {
        if let Some(z) = z {
            vec3(&z).map_err(|e| e.under("z_axis"))?;
        }
        if let Some(x) = x {
            vec3(&x).map_err(|e| e.under("x_axis"))?;
        }
        frame_from_axes(z.unwrap_or([0.0, 0.0, 1.0]), x).ok_or_else(|| {
            FieldError::at(
                if x.is_some() { "x_axis" } else { "z_axis" },
                "axes must be non-zero and x_axis not parallel to z_axis",
            )
        })
    }

    /// A rigid body and its marker `<name>.cm`.
    pub fn body(&mut self, d: BodyDesc) -> Result<BodyHandle, ModelError> {
        let item = format!("body '{}'", d.name);
        let bad = |e: FieldError| build(&item, e);
        if d.name.is_empty() || d.name == "ground" || self.body_names.contains(&d.name) {
            return Err(bad(FieldError::at(
                "name",
                format!("body name '{}' is empty, reserved or used twice", d.name),
            )));
        }
        positive(d.mass).map_err(|m| bad(FieldError::at("mass_kg", m)))?;
        check_inertia(&d.inertia).map_err(|e| bad(e.under("inertia_kg_m2")))?;
        let inertia = d.inertia;
        vec3(&d.cm).map_err(|e| bad(e.under("cm_position_m")))?;
        vec3(&d.velocity).map_err(|e| bad(e.under("velocity_m_s")))?;
        vec3(&d.angular_velocity).map_err(|e| bad(e.under("angular_velocity_rad_s")))?;
        let axes = self.place.axes(&d.axes);
        self.model.bodies.push(Body {
            name: d.name.clone(),
            mass: d.mass,
            inertia,
            position: self.place.point(d.cm),
            orientation: quat_from_matrix(&axes),
            velocity: d.velocity,
            angular_velocity: d.angular_velocity,
            modal: None,
        });
        self.body_names.insert(d.name.clone());
        self.body_place.push(self.place);
        let k = BodyHandle(self.model.bodies.len() - 1);
        self.marker(&format!("{}.cm", d.name), Some(k), d.cm, &d.axes)?;
        Ok(k)
    }

    /// A marker at `p` with `axes` (subsystem coordinates) on `body`.
    pub fn marker(
        &mut self,
        name: &str,
        body: Option<BodyHandle>,
        p: V,
        axes: &Axes,
    ) -> Result<MarkerHandle, ModelError> {
        vec3(&p).map_err(|e| build(&format!("marker '{name}'"), e.under("position_m")))?;
        let (pw, aw) = (self.place.point(p), self.place.axes(axes));
        self.world_marker(name, body, pw, aw)
    }

    /// A marker at a world point with world axes.
    pub fn world_marker(
        &mut self,
        name: &str,
        body: Option<BodyHandle>,
        point: V,
        axes_world: Axes,
    ) -> Result<MarkerHandle, ModelError> {
        if !self.marker_names.insert(name.to_string()) {
            return Err(build(
                &format!("marker '{name}'"),
                FieldError::at("name", format!("marker '{name}' defined twice")),
            ));
        }
        let (r, a) = match body {
            None => ([0.0; 3], IDENTITY),
            Some(k) => (
                self.model.bodies[k].position,
                rot(&self.model.bodies[k].orientation),
            ),
        };
        self.model.markers.push(Marker {
            name: name.to_string(),
            body,
            position: mtv(&a, &sub(&point, &r)),
            axes: mm(&transpose(&a), &axes_world),
            node: None,
        });
        Ok(MarkerHandle(self.model.markers.len() - 1))
    }

    /// A marker on a modal body attached to node `node` (undeformed position `p`).
    pub fn node_marker(
        &mut self,
        name: &str,
        body: BodyHandle,
        node: usize,
        p: V,
    ) -> Result<MarkerHandle, ModelError> {
        let k = self.marker(name, Some(body), p, &IDENTITY)?;
        self.model.markers[k].node = Some(node);
        Ok(k)
    }

    /// Moves marker `m` onto node `node` of its modal body, so what acts there follows
    /// the node's deformation.
    pub fn pin_to_node(&mut self, m: MarkerHandle, node: usize) {
        self.model.markers[m].node = Some(node);
    }

    /// An ideal joint of `kind` at `p` (axes: z = joint axis; universal: z = pin on
    /// `bj`, x = pin on `bi`), or the bushing replacing it when `replace` or the
    /// model-wide setting asks for one.
    #[allow(clippy::too_many_arguments)]
    pub fn joint(
        &mut self,
        name: &str,
        kind: JointKind,
        bi: Option<BodyHandle>,
        bj: Option<BodyHandle>,
        p: V,
        axes: &Axes,
        replace: Option<&JointBushing>,
    ) -> Result<Link, ModelError> {
        let replace = replace.or(self.joints_as_bushings.as_ref()).cloned();
        let Some(jb) = replace else {
            return self.ideal_joint(name, kind, bi, bj, p, axes);
        };
        let item = format!("joint '{name}'");
        jb.check().map_err(|e| build(&item, e.under("bushing")))?;
        self.joint_checks(&item, name, bi, bj, &p)?;
        // A bushing's deflection is I relative to J: both markers share the joint's axes
        // so it starts undeflected.
        let mi = self.marker(&format!("{name}.i"), bi, p, axes)?;
        let mj = self.marker(&format!("{name}.j"), bj, p, axes)?;
        let locked = kind.locked();
        let law = |a: usize, t: f64, r: f64| {
            Law::Linear(match (locked[a], a < 3) {
                (false, _) => 0.0,
                (true, true) => t,
                (true, false) => r,
            })
        };
        let e = self.add_force(
            &item,
            Force::Bushing(Bushing {
                name: name.to_string(),
                i: mi,
                j: mj,
                stiffness: std::array::from_fn(|a| law(a, jb.stiffness_n_m, jb.stiffness_n_m_rad)),
                damping: std::array::from_fn(|a| law(a, jb.damping_n_s_m, jb.damping_n_m_s_rad)),
                preload: [0.0; 6],
                replaces: Some(name.to_string()),
            }),
        )?;
        self.joint_names.insert(name.to_string());
        Ok(Link::Bushing(e, TwoMarkers { i: mi, j: mj }))
    }

    /// An ideal joint that is never replaced: a spinning wheel's bearing (a bushing
    /// measures rotation as a rotation vector, which cannot follow a full turn).
    pub fn ideal_joint(
        &mut self,
        name: &str,
        kind: JointKind,
        bi: Option<BodyHandle>,
        bj: Option<BodyHandle>,
        p: V,
        axes: &Axes,
    ) -> Result<Link, ModelError> {
        let item = format!("joint '{name}'");
        self.joint_checks(&item, name, bi, bj, &p)?;
        // Universal: marker I turns its z onto the I pin (J's x); a cyclic permutation
        // keeps it right-handed.
        let axes_i = if kind == JointKind::Universal {
            let c = |k: usize| [axes[0][k], axes[1][k], axes[2][k]];
            let (x, y, z) = (c(0), c(1), c(2));
            [[y[0], z[0], x[0]], [y[1], z[1], x[1]], [y[2], z[2], x[2]]]
        } else {
            *axes
        };
        let mi = self.marker(&format!("{name}.i"), bi, p, &axes_i)?;
        let mj = self.marker(&format!("{name}.j"), bj, p, axes)?;
        self.model.joints.push(Joint {
            name: name.to_string(),
            kind,
            i: mi,
            j: mj,
        });
        self.joint_names.insert(name.to_string());
        Ok(Link::Joint(JointHandle(self.model.joints.len() - 1)))
    }

    fn joint_checks(
        &self,
        item: &str,
        name: &str,
        bi: Option<BodyHandle>,
        bj: Option<BodyHandle>,
        p: &V,
    ) -> Result<(), ModelError> {
        if self.joint_names.contains(name) {
            return Err(build(
                item,
                FieldError::at("name", format!("joint '{name}' defined twice")),
            ));
        }
        if bi == bj {
            return Err(build(
                item,
                FieldError::at("body_j", "a joint needs two different bodies"),
            ));
        }
        vec3(p).map_err(|e| build(item, e.under("position_m")))
    }

    /// The markers `<name>.i` and `<name>.j` of an element acting at one point between
    /// two different bodies.
    fn pair(
        &mut self,
        item: &str,
        name: &str,
        bodies: [Option<BodyHandle>; 2],
        p: V,
        axes: &Axes,
    ) -> Result<(MarkerHandle, MarkerHandle), ModelError> {
        if bodies[0] == bodies[1] {
            return Err(build(
                item,
                FieldError::at("body_j", format!("{item} needs two different bodies")),
            ));
        }
        vec3(&p).map_err(|e| build(item, e.under("position_m")))?;
        let mi = self.marker(&format!("{name}.i"), bodies[0], p, axes)?;
        let mj = self.marker(&format!("{name}.j"), bodies[1], p, axes)?;
        Ok((mi, mj))
    }

    /// A rubber bushing.
    pub fn bushing(&mut self, l: BushingLine) -> Result<ElementHandle, ModelError> {
        Ok(self.bushing_between(l)?.0)
    }

    /// A rubber bushing linking two bodies as a joint would (its markers named in the
    /// [`Link`]).
    pub fn bushing_link(&mut self, l: BushingLine) -> Result<Link, ModelError> {
        let (e, markers) = self.bushing_between(l)?;
        Ok(Link::Bushing(e, markers))
    }

    fn bushing_between(
        &mut self,
        l: BushingLine,
    ) -> Result<(ElementHandle, TwoMarkers), ModelError> {
        let item = format!("bushing '{}'", l.name);
        let (mi, mj) = self.pair(&item, &l.name, [l.body_i, l.body_j], l.point, &l.axes)?;
        let e = self.add_force(
            &item,
            Force::Bushing(Bushing {
                name: l.name,
                i: mi,
                j: mj,
                stiffness: l.stiffness,
                damping: l.damping,
                preload: l.preload,
                replaces: None,
            }),
        )?;
        Ok((e, TwoMarkers { i: mi, j: mj }))
    }

    /// A spring-damper along the line between two points.
    pub fn spring(&mut self, l: SpringLine) -> Result<ElementHandle, ModelError> {
        let item = format!("spring '{}'", l.name);
        vec3(&l.point_i).map_err(|e| build(&item, e.under("point_i_m")))?;
        vec3(&l.point_j).map_err(|e| build(&item, e.under("point_j_m")))?;
        let d = sub(&l.point_i, &l.point_j);
        let len = dot(&d, &d).sqrt();
        if len.is_nan() || len <= 0.0 {
            return Err(build(
                &item,
                FieldError::at(
                    "point_j_m",
                    "the two spring points coincide; a spring needs a line of action",
                ),
            ));
        }
        let mi = self.marker(&format!("{}.i", l.name), l.body_i, l.point_i, &IDENTITY)?;
        let mj = self.marker(&format!("{}.j", l.name), l.body_j, l.point_j, &IDENTITY)?;
        self.add_force(
            &item,
            Force::Spring(SpringDamper {
                name: l.name,
                i: mi,
                j: mj,
                free_length: l.free_length,
                preload: l.preload,
                spring: l.spring,
                damper: l.damper,
                bump_stop: l.bump_stop,
                rebound_stop: l.rebound_stop,
            }),
        )
    }

    /// A rotational spring-damper about the z axis of `l.axes`.
    pub fn rot_spring(&mut self, l: RotLine) -> Result<ElementHandle, ModelError> {
        let item = format!("rotational spring '{}'", l.name);
        let (mi, mj) = self.pair(&item, &l.name, [l.body_i, l.body_j], l.point, &l.axes)?;
        self.add_force(
            &item,
            Force::Rot(RotSpring {
                name: l.name,
                i: mi,
                j: mj,
                free_angle: l.free_angle,
                preload: l.preload,
                spring: l.spring,
                damper: l.damper,
            }),
        )
    }

    /// A load of time on a body.
    pub fn applied(&mut self, l: AppliedLine) -> Result<ElementHandle, ModelError> {
        let item = format!("load '{}'", l.name);
        if l.body.is_none() {
            return Err(build(
                &item,
                FieldError::at("body", "a load on ground does nothing"),
            ));
        }
        vec3(&l.point).map_err(|e| build(&item, e.under("position_m")))?;
        let mi = self.marker(&format!("{}.i", l.name), l.body, l.point, &l.axes)?;
        self.add_force(
            &item,
            Force::Applied(Applied {
                name: l.name,
                i: mi,
                force: l.force,
                torque: l.torque,
                in_marker_axes: l.in_marker_axes,
            }),
        )
    }

    /// Adds a force element whose markers already exist, after its checks.
    pub fn add_force(&mut self, item: &str, f: Force) -> Result<ElementHandle, ModelError> {
        if !self.element_names.insert(f.name().to_string()) {
            return Err(build(
                item,
                FieldError::at("name", format!("element '{}' defined twice", f.name())),
            ));
        }
        f.check().map_err(|e| build(item, e))?;
        self.model.forces.push(f);
        Ok(ElementHandle(self.model.forces.len() - 1))
    }

    /// A prescribed motion of joint `joint`: displacement s(t) (or, with
    /// `is_velocity`, its rate) along or about J's z.
    pub fn motion(
        &mut self,
        name: &str,
        joint: JointHandle,
        dof: Option<MotionDof>,
        function: TimeFunction,
        is_velocity: bool,
    ) -> Result<(), ModelError> {
        let item = format!("motion '{name}'");
        let kind = self.model.joints[joint].kind;
        let dof = match (dof, kind) {
            (Some(MotionDof::Rotation), JointKind::Revolute | JointKind::Cylindrical) => {
                MotionDof::Rotation
            }
            (
                Some(MotionDof::Translation),
                JointKind::Translational | JointKind::Cylindrical,
            ) => MotionDof::Translation,
            (None, JointKind::Revolute) => MotionDof::Rotation,
            (None, JointKind::Translational) => MotionDof::Translation,
            (d, _) => {
                return Err(build(
                    &item,
                    FieldError::at(
                        "dof",
                        format!(
                            "{d:?} cannot drive a {} joint (rotation: revolute, cylindrical; translation: translational, cylindrical)",
                            kind.name()
                        ),
                    ),
                ))
            }
        };
        function.check().map_err(|e| {
            build(
                &item,
                e.under(if is_velocity {
                    "velocity"
                } else {
                    "displacement"
                }),
            )
        })?;
        self.model.motions.push(Motion {
            name: name.to_string(),
            joint,
            dof,
            function,
            is_velocity,
        });
        Ok(())
    }

    /// A tyre on the wheel-centre marker `marker` (its y axis the spin axis).
    pub fn tyre(
        &mut self,
        name: &str,
        marker: MarkerHandle,
        tyre: crate::tyre::Tyre,
    ) -> TyreHandle {
        self.model.tyres.push(TyreElem {
            name: name.to_string(),
            marker,
            tyre,
        });
        TyreHandle(self.model.tyres.len() - 1)
    }

    /// A speed-holding driveline.
    pub fn speed_control(&mut self, c: SpeedControl) {
        self.model.controls.push(c);
    }

    /// An output request.
    pub fn output(&mut self, o: Output) {
        self.model.outputs.push(o);
    }
}

/// A builder refusal of `item`.
fn build(item: &str, error: FieldError) -> ModelError {
    ModelError::Build {
        item: item.to_string(),
        error,
    }
}

/// Three finite numbers.
fn vec3(v: &V) -> Result<(), FieldError> {
    for (c, x) in v.iter().enumerate() {
        finite(*x).map_err(|m| FieldError::at(c, m))?;
    }
    Ok(())
}

/// A physical inertia tensor from [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]:
/// positive principal moments obeying the triangle inequality.
pub fn inertia_tensor(v: &[f64]) -> Result<[[f64; 3]; 3], FieldError> {
    for (c, x) in v.iter().enumerate() {
        finite(*x).map_err(|m| FieldError::at(c, m))?;
    }
    let (ixx, iyy, izz, ixy, ixz, iyz) = match v.len() {
        3 => (v[0], v[1], v[2], 0.0, 0.0, 0.0),
        6 => (v[0], v[1], v[2], v[3], v[4], v[5]),
        n => {
            return Err(FieldError::here(format!(
                "give 3 (Ixx, Iyy, Izz) or 6 (plus Ixy, Ixz, Iyz) values, not {n}"
            )))
        }
    };
    for (c, d) in [ixx, iyy, izz].iter().enumerate() {
        if d.is_nan() || *d <= 0.0 {
            return Err(FieldError::at(
                c,
                format!("principal moment must be positive, got {d}"),
            ));
        }
    }
    let t = [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]];
    check_inertia(&t)?;
    Ok(t)
}

/// A physical inertia tensor: finite, symmetric, positive principal moments obeying the
/// triangle inequality.
pub fn check_inertia(t: &[[f64; 3]; 3]) -> Result<(), FieldError> {
    let scale = t[0][0].abs() + t[1][1].abs() + t[2][2].abs();
    for r in 0..3 {
        for c in 0..3 {
            finite(t[r][c]).map_err(FieldError::here)?;
            if (t[r][c] - t[c][r]).abs() > 1e-9 * scale {
                return Err(FieldError::here("an inertia tensor is symmetric"));
            }
        }
    }
    let e = nalgebra::Matrix3::from_fn(|r, c| t[r][c]).symmetric_eigenvalues();
    let (a, b, c) = (e[0], e[1], e[2]);
    let tol = 1e-9 * (a + b + c).abs();
    if a <= 0.0 || b <= 0.0 || c <= 0.0 || a + b < c - tol || a + c < b - tol || b + c < a - tol {
        return Err(FieldError::here(format!("not a physical inertia tensor (principal moments {a:.4e}, {b:.4e}, {c:.4e} must be positive and satisfy the triangle inequality)")));
    }
    Ok(())
}

impl ModelError {
    /// The refused field of a builder error, for locating it in a file (other errors
    /// become a message about the value itself).
    pub fn into_field(self) -> FieldError {
        match self {
            ModelError::Build { error, .. } => error,
            other => FieldError::here(other.to_string()),
        }
    }
}
