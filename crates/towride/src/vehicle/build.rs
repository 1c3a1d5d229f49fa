//! Adding parts to a [`Model`] in subsystem coordinates: bodies with their `.cm` markers,
//! markers, joints (or the bushings that replace them), bushings, springs and torsion
//! elements. The builder knows where the current subsystem lies in the world
//! ([`Placement`]) and converts once.

use super::geom::{Axes, Placement, V};
use super::props::{BushingLaws, Mass};
use crate::model::desc::{
    Body, BodyId, Bushing, Force, Joint, JointKind, Law, Marker, Model, RotSpring, SpringDamper,
    Stop,
};
use crate::model::math::quat_from_matrix;
use crate::model::spec::JointBushing;

/// What an ideal joint became.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Link {
    /// Index in `Model::joints`.
    Joint(usize),
    /// Index in `Model::forces` of the bushing that replaces it.
    Bushing(usize),
}

/// A spring-damper between two markers, before it is added.
pub struct Line {
    pub name: String,
    pub body_i: BodyId,
    pub point_i: V,
    pub body_j: BodyId,
    pub point_j: V,
    pub free_length: f64,
    pub preload: f64,
    pub spring: Law,
    pub damper: Law,
    pub bump_stop: Option<Stop>,
    pub rebound_stop: Option<Stop>,
}

impl Line {
    /// A line element without force laws, free at its current length.
    pub fn new(name: String, body_i: BodyId, point_i: V, body_j: BodyId, point_j: V) -> Line {
        Line {
            name,
            body_i,
            point_i,
            body_j,
            point_j,
            free_length: super::geom::distance(&point_i, &point_j),
            preload: 0.0,
            spring: Law::Linear(0.0),
            damper: Law::Linear(0.0),
            bump_stop: None,
            rebound_stop: None,
        }
    }
}

pub struct Builder<'m> {
    pub model: &'m mut Model,
    /// Where the coordinates handed to the builder lie in the world.
    pub place: Placement,
    /// Every ideal joint of the model becomes a bushing of these properties when set.
    pub joints_as_bushings: Option<JointBushing>,
    /// The placement each body was created in (indexed like `Model::bodies`).
    pub body_place: Vec<Placement>,
    /// Reads the templates' property files with the run's overrides.
    pub loader: crate::input::Loader,
}

impl<'m> Builder<'m> {
    pub fn new(
        model: &'m mut Model,
        joints_as_bushings: Option<JointBushing>,
        loader: &crate::input::Loader,
    ) -> Builder<'m> {
        let body_place = vec![Placement::translate([0.0; 3]); model.bodies.len()];
        Builder {
            model,
            place: Placement::translate([0.0; 3]),
            joints_as_bushings,
            body_place,
            loader: loader.clone(),
        }
    }

    /// A rigid body with axes along the subsystem's, and its marker `<name>.cm`.
    pub fn body(&mut self, name: &str, m: &Mass) -> usize {
        let axes = self.place.rotation;
        self.model.bodies.push(Body {
            name: name.to_string(),
            mass: m.mass,
            inertia: m.inertia,
            position: self.place.point(m.cm),
            orientation: quat_from_matrix(&axes),
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
            modal: None,
        });
        self.body_place.push(self.place);
        let k = self.model.bodies.len() - 1;
        self.marker(&format!("{name}.cm"), Some(k), m.cm, &super::geom::IDENTITY);
        k
    }

    /// A marker at `p` with `axes` (subsystem coordinates) on `body`.
    pub fn marker(&mut self, name: &str, body: BodyId, p: V, axes: &Axes) -> usize {
        let (pw, aw) = (self.place.point(p), self.place.axes(axes));
        self.model.add_marker_world(name.to_string(), body, pw, aw)
    }

    /// A marker on a modal body attached to node `node` (undeformed position `p`).
    pub fn node_marker(&mut self, name: &str, body: usize, node: usize, p: V) -> usize {
        let k = self.marker(name, Some(body), p, &super::geom::IDENTITY);
        self.model.markers[k].node = Some(node);
        k
    }

    /// An ideal joint of `kind` at `p` (axes: z = joint axis; universal: z = pin on
    /// `bj`, x = pin on `bi`), or the bushing replacing it when `replace` or the
    /// model-wide setting asks for one.
    #[allow(clippy::too_many_arguments)]
    pub fn joint(
        &mut self,
        name: &str,
        kind: JointKind,
        bi: BodyId,
        bj: BodyId,
        p: V,
        axes: &Axes,
        replace: Option<&JointBushing>,
    ) -> Link {
        let replace = replace.or(self.joints_as_bushings.as_ref()).cloned();
        if let Some(jb) = replace {
            // A bushing's deflection is I relative to J: both markers share the joint's
            // axes so it starts undeflected.
            let mi = self.marker(&format!("{name}.i"), bi, p, axes);
            let mj = self.marker(&format!("{name}.j"), bj, p, axes);
            let locked = kind.locked();
            let law = |a: usize, t: f64, r: f64| {
                Law::Linear(match (locked[a], a < 3) {
                    (false, _) => 0.0,
                    (true, true) => t,
                    (true, false) => r,
                })
            };
            self.model.forces.push(Force::Bushing(Bushing {
                name: name.to_string(),
                i: mi,
                j: mj,
                stiffness: std::array::from_fn(|a| law(a, jb.stiffness_n_m, jb.stiffness_n_m_rad)),
                damping: std::array::from_fn(|a| law(a, jb.damping_n_s_m, jb.damping_n_m_s_rad)),
                preload: [0.0; 6],
                replaces: Some(name.to_string()),
            }));
            return Link::Bushing(self.model.forces.len() - 1);
        }
        self.ideal_joint(name, kind, bi, bj, p, axes)
    }

    /// An ideal joint that is never replaced: a spinning wheel's bearing (a bushing
    /// measures rotation as a rotation vector, which cannot follow a full turn).
    pub fn ideal_joint(
        &mut self,
        name: &str,
        kind: JointKind,
        bi: BodyId,
        bj: BodyId,
        p: V,
        axes: &Axes,
    ) -> Link {
        // Universal: marker I turns its z onto the I pin (J's x); a cyclic permutation
        // keeps it right-handed.
        let axes_i = if kind == JointKind::Universal {
            let c = |k: usize| [axes[0][k], axes[1][k], axes[2][k]];
            let (x, y, z) = (c(0), c(1), c(2));
            [[y[0], z[0], x[0]], [y[1], z[1], x[1]], [y[2], z[2], x[2]]]
        } else {
            *axes
        };
        let mi = self.marker(&format!("{name}.i"), bi, p, &axes_i);
        let mj = self.marker(&format!("{name}.j"), bj, p, axes);
        self.model.joints.push(Joint {
            name: name.to_string(),
            kind,
            i: mi,
            j: mj,
        });
        Link::Joint(self.model.joints.len() - 1)
    }

    /// A rubber bushing at `p`; `axes` are the bushing's (subsystem coordinates).
    #[allow(clippy::too_many_arguments)]
    pub fn bushing(
        &mut self,
        name: &str,
        bi: BodyId,
        bj: BodyId,
        p: V,
        axes: &Axes,
        laws: &BushingLaws,
        preload: [f64; 6],
    ) -> usize {
        let mi = self.marker(&format!("{name}.i"), bi, p, axes);
        let mj = self.marker(&format!("{name}.j"), bj, p, axes);
        self.model.forces.push(Force::Bushing(Bushing {
            name: name.to_string(),
            i: mi,
            j: mj,
            stiffness: laws.stiffness.clone(),
            damping: laws.damping.clone(),
            preload,
            replaces: None,
        }));
        self.model.forces.len() - 1
    }

    /// A spring-damper along the line between two points.
    pub fn line(&mut self, l: Line) -> usize {
        let id = super::geom::IDENTITY;
        let mi = self.marker(&format!("{}.i", l.name), l.body_i, l.point_i, &id);
        let mj = self.marker(&format!("{}.j", l.name), l.body_j, l.point_j, &id);
        self.model.forces.push(Force::Spring(SpringDamper {
            name: l.name,
            i: mi,
            j: mj,
            free_length: l.free_length,
            preload: l.preload,
            spring: l.spring,
            damper: l.damper,
            bump_stop: l.bump_stop,
            rebound_stop: l.rebound_stop,
        }));
        self.model.forces.len() - 1
    }

    /// A torsion spring-damper about the z axis of `axes` at `p`.
    #[allow(clippy::too_many_arguments)]
    pub fn torsion(
        &mut self,
        name: &str,
        bi: BodyId,
        bj: BodyId,
        p: V,
        axes: &Axes,
        spring: Law,
        damper: Law,
    ) -> usize {
        let mi = self.marker(&format!("{name}.i"), bi, p, axes);
        let mj = self.marker(&format!("{name}.j"), bj, p, axes);
        self.model.forces.push(Force::Rot(RotSpring {
            name: name.to_string(),
            i: mi,
            j: mj,
            free_angle: 0.0,
            preload: 0.0,
            spring,
            damper,
        }));
        self.model.forces.len() - 1
    }

    pub fn marker_ref(&self, k: usize) -> &Marker {
        &self.model.markers[k]
    }
}
