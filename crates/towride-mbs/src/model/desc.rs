//! The validated model description: what a mechanism file or a vehicle template
//! produces, and what [`super::system::System`] assembles into equations.
//!
//! Everything is in SI units. Geometry is stored in body frames (markers) so the
//! description is independent of where the bodies are; the builders convert the global
//! hardpoints users write into these local frames once.

pub use super::elements::{
    Applied, Bushing, Force, JointBushing, Law, LawSpec, RotSpring, SpringDamper, Stop, StopSpec,
    TwoMarkers,
};
use super::function::TimeFunction;

macro_rules! handle {
    ($(#[$doc:meta])* $name:ident for $item:ty) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub(crate) usize);

        impl $name {
            /// The handle of entry `index` of the model's list, for a model written out
            /// by hand (the builder hands handles out otherwise).
            pub const fn new(index: usize) -> $name {
                $name(index)
            }

            /// The index in the model's list: for what needs a plain number (a column
            /// of the system's unknowns, an index in a JSON array); the model's lists
            /// are indexed by the handle itself.
            pub fn index(self) -> usize {
                self.0
            }
        }

        impl std::ops::Index<$name> for Vec<$item> {
            type Output = $item;
            fn index(&self, h: $name) -> &$item {
                &self[h.0]
            }
        }

        impl std::ops::IndexMut<$name> for Vec<$item> {
            fn index_mut(&mut self, h: $name) -> &mut $item {
                &mut self[h.0]
            }
        }
    };
}

// The typed references between the model's parts: the builder hands them out, the
// model stores them, and its lists are indexed by them (`model.bodies[handle]`).
handle!(
    /// A body of the model (`Model::bodies`).
    BodyHandle for Body
);
handle!(
    /// A marker (`Model::markers`).
    MarkerHandle for Marker
);
handle!(
    /// An ideal joint (`Model::joints`).
    JointHandle for Joint
);
handle!(
    /// A force element (`Model::forces`).
    ElementHandle for Force
);
handle!(
    /// A tyre (`Model::tyres`).
    TyreHandle for TyreElem
);

/// A body, `None` for ground.
pub type BodyId = Option<BodyHandle>;

/// A rigid or modal body with its initial state.
#[derive(Clone, Debug)]
pub struct Body {
    /// Unique body name (used in messages and output channel names).
    pub name: String,
    /// Mass [kg].
    pub mass: f64,
    /// Inertia tensor about the centre of mass in body axes [kg m^2].
    pub inertia: [[f64; 3]; 3],
    /// Initial centre-of-mass position in world axes [m].
    pub position: [f64; 3],
    /// Initial orientation, unit quaternion (w, x, y, z), body to world.
    pub orientation: [f64; 4],
    /// Initial velocity of the centre of mass, world axes [m/s].
    pub velocity: [f64; 3],
    /// Initial angular velocity, world axes [rad/s].
    pub angular_velocity: [f64; 3],
    /// The elastic part of a modal (floating-frame) body; `None` for a rigid body.
    /// For a modal body `mass`, `inertia` and `position` are the undeformed body's (CM)
    /// and the body axes are the FE file's axes.
    pub modal: Option<Box<Modal>>,
}

/// How much of the inertia coupling between a modal body's frame motion and its modal
/// coordinates is kept (see `docs/flex.md`, "Coupling levels").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Coupling {
    /// Block-diagonal mass matrix: undeformed rigid inertia plus the identity modal mass.
    /// Exact at eta = 0 because the kept modes are mass-orthogonal to the rigid modes.
    #[default]
    Constant,
    /// Constant mass matrix plus the centrifugal load of the frame's rotation on the
    /// modes (omega^T I8_j omega), the one zero-order coupling term that survives
    /// mass-orthogonality.
    Partial,
    /// The floating-frame equations without truncation: deformation-dependent mass
    /// matrix (first moment, inertia tensor and rotation-modal coupling as functions of
    /// eta) and the quadratic-velocity vector that belongs to it (`modal.rs`).
    Full,
}

impl Coupling {
    /// The level called `s` in an input file ("constant", "partial" or "full").
    pub fn parse(s: &str) -> Option<Coupling> {
        Some(match s {
            "constant" => Coupling::Constant,
            "partial" => Coupling::Partial,
            "full" => Coupling::Full,
            _ => return None,
        })
    }

    /// The accepted names, for messages.
    pub const NAMES: &'static str = "constant, partial or full";
}

/// The elastic part of a modal body: the selected modes of a Craig-Bampton reduction.
#[derive(Clone, Debug)]
pub struct Modal {
    /// Selected modes only (`ModalData::selected`); body frame = FE frame.
    pub data: crate::flex::ModalData,
    /// How much frame-mode inertia coupling the equations keep.
    pub coupling: Coupling,
}

/// A frame fixed on a body: origin and axes in body coordinates.
#[derive(Clone, Debug)]
pub struct Marker {
    /// Unique marker name.
    pub name: String,
    /// The body the marker is fixed on (`None`: ground).
    pub body: BodyId,
    /// Origin in body coordinates relative to the centre of mass [m].
    pub position: [f64; 3],
    /// Axes as columns, in body coordinates.
    pub axes: [[f64; 3]; 3],
    /// On a modal body: the index of the modal node (`Modal::data.nodes`) the marker is
    /// attached to; it then translates and rotates with that node's mode shapes. The
    /// marker's `position` must be the node's undeformed position relative to the CM.
    pub node: Option<usize>,
}

/// Kind of an ideal joint between marker I and marker J.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// All six relative motions locked.
    Fixed,
    /// Coincident origins and z axes: only the rotation about z is free.
    Revolute,
    /// Coincident origins: the three rotations are free.
    Spherical,
    /// Translation along and rotation about J's z are free.
    Cylindrical,
    /// Only the translation along J's z is free.
    Translational,
    /// Coincident origins with z of I kept perpendicular to z of J (a cardan joint: two
    /// rotations free).
    Universal,
    /// Origin of I on the z axis of J.
    Inline,
    /// Origin of I in the xy plane of J.
    Inplane,
    /// z of I perpendicular to z of J.
    Perpendicular,
    /// Axes of I parallel to those of J.
    Orientation,
}

impl JointKind {
    /// The kind called `s` in a mechanism file (lower case, e.g. "revolute").
    pub fn parse(s: &str) -> Option<JointKind> {
        Some(match s {
            "fixed" => JointKind::Fixed,
            "revolute" => JointKind::Revolute,
            "spherical" => JointKind::Spherical,
            "cylindrical" => JointKind::Cylindrical,
            "translational" => JointKind::Translational,
            "universal" => JointKind::Universal,
            "inline" => JointKind::Inline,
            "inplane" => JointKind::Inplane,
            "perpendicular" => JointKind::Perpendicular,
            "orientation" => JointKind::Orientation,
            _ => return None,
        })
    }

    /// The kind's name as mechanism files write it.
    pub fn name(self) -> &'static str {
        match self {
            JointKind::Fixed => "fixed",
            JointKind::Revolute => "revolute",
            JointKind::Spherical => "spherical",
            JointKind::Cylindrical => "cylindrical",
            JointKind::Translational => "translational",
            JointKind::Universal => "universal",
            JointKind::Inline => "inline",
            JointKind::Inplane => "inplane",
            JointKind::Perpendicular => "perpendicular",
            JointKind::Orientation => "orientation",
        }
    }

    /// Which of the six relative motions (tx, ty, tz, rx, ry, rz of I in J's axes) the
    /// joint removes; used when a joint is replaced by a bushing.
    pub fn locked(self) -> [bool; 6] {
        match self {
            JointKind::Fixed => [true; 6],
            JointKind::Revolute => [true, true, true, true, true, false],
            JointKind::Spherical => [true, true, true, false, false, false],
            JointKind::Cylindrical => [true, true, false, true, true, false],
            JointKind::Translational => [true, true, false, true, true, true],
            // The cross axes are z of I and z of J; the locked rotation is about their
            // common normal, which is J's y axis when I's z lies along J's x.
            JointKind::Universal => [true, true, true, false, true, false],
            JointKind::Inline => [true, true, false, false, false, false],
            JointKind::Inplane => [false, false, true, false, false, false],
            JointKind::Perpendicular => [false, false, false, false, false, false],
            JointKind::Orientation => [false, false, false, true, true, true],
        }
    }
}

/// An ideal joint between marker `i` (on the moving body) and marker `j`.
#[derive(Clone, Debug)]
pub struct Joint {
    /// Unique joint name.
    pub name: String,
    /// Which relative motions the joint removes.
    pub kind: JointKind,
    /// Marker I, on the moving body.
    pub i: MarkerHandle,
    /// Marker J, on the reference body.
    pub j: MarkerHandle,
}

impl Joint {
    /// Markers I and J.
    pub fn markers(&self) -> TwoMarkers {
        TwoMarkers {
            i: self.i,
            j: self.j,
        }
    }
}

/// What a motion prescribes: the joint's translation along or rotation about J's z.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionDof {
    /// Translation along J's z [m].
    Translation,
    /// Rotation about J's z [rad].
    Rotation,
}

/// A prescribed joint motion: displacement s(t) directly, or s(t) = s0 + integral of a
/// prescribed velocity.
#[derive(Clone, Debug)]
pub struct Motion {
    /// Unique motion name.
    pub name: String,
    /// The driven joint.
    pub joint: JointHandle,
    /// Which of the joint's free coordinates is driven.
    pub dof: MotionDof,
    /// The prescribed displacement s(t) [m or rad], or velocity when `is_velocity` [m/s or
    /// rad/s].
    pub function: TimeFunction,
    /// `function` prescribes the velocity; the displacement is its integral from s0.
    pub is_velocity: bool,
}

impl Motion {
    /// (s, s', s'') at t.
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        if self.is_velocity {
            let (v, a, _) = self.function.eval(t);
            (self.function.integral(t), v, a)
        } else {
            self.function.eval(t)
        }
    }
}

/// The axes an output is resolved in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axes {
    /// World axes.
    World,
    /// The axes of a marker.
    Marker(MarkerHandle),
}

/// What a marker output reports (three components, in the output's axes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkerQuantity {
    /// Position of the marker origin [m].
    Position,
    /// Velocity of the marker origin [m/s].
    Velocity,
    /// Acceleration of the marker origin [m/s^2].
    Acceleration,
    /// Angular velocity of the marker axes [rad/s].
    AngularVelocity,
    /// Angular acceleration of the marker axes [rad/s^2].
    AngularAcceleration,
}

/// What a joint output reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointQuantity {
    /// Reaction force on the I body at marker I.
    Force,
    /// Reaction torque on the I body about marker I.
    Torque,
    /// The free coordinate along / about J's z (translation [m] or angle [rad]).
    Displacement,
}

/// What a force-element output reports: one channel per measured direction of the
/// element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementQuantity {
    /// Force or torque along each direction [N or N m].
    Force,
    /// Deflection along each direction [m or rad].
    Deflection,
    /// Deflection rate along each direction [m/s or rad/s].
    Velocity,
}

/// What a tyre output reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TyreQuantity {
    /// Contact normal force [N].
    NormalForce,
    /// 1 while the tyre touches the road, 0 in flight.
    Contact,
    /// Longitudinal contact force [N].
    LongitudinalForce,
    /// Height of the effective road plane under the wheel (the enveloped obstacle as the
    /// tyre feels it) [m].
    EffectiveRoadHeight,
}

/// One law of a spring-damper line element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinePart {
    /// The spring with its preload.
    Spring,
    /// The damper.
    Damper,
    /// The bump stop (in compression).
    BumpStop,
    /// The rebound stop (in extension).
    ReboundStop,
}

/// A relative kinematic quantity of two markers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RelativeQuantity {
    /// Position of I's origin relative to J's, in J's axes [m].
    Position,
    /// Its time derivative as seen from J (in J's axes) [m/s].
    Velocity,
}

/// A body's rigid motion at its centre of mass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyQuantity {
    /// Height of the centre of mass above its reference [m].
    Heave,
    /// Pitch angle (ISO 8855 yaw-pitch-roll sequence; positive nose down) [rad].
    Pitch,
    /// Roll angle (positive right side down) [rad].
    Roll,
}

/// What a modal-body output reports.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ModalQuantity {
    /// The modal coordinates, one channel per selected mode.
    Coordinates,
    /// Strain energy sum w_j^2 eta_j^2 / 2 [J].
    StrainEnergy,
    /// Elastic displacement of modal node `node` relative to the mean of the nodes
    /// `reference` (e.g. the ball relative to the brackets), body axes [m].
    Deflection {
        /// Modal node whose displacement is reported (index into the body's modal nodes).
        node: usize,
        /// Modal nodes whose mean displacement is subtracted.
        reference: Vec<usize>,
    },
    /// Nominal stresses at a stress point of the flex file (index into the body's
    /// `stress.points`) from the modal coordinates: sx_max, sx_min, tau, eq [Pa]
    /// (`flex::stress`).
    Stress {
        /// Stress point index.
        point: usize,
    },
}

/// What carries a load between two markers: an ideal joint (its reaction) or a force
/// element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Carrier {
    /// An ideal joint.
    Joint(JointHandle),
    /// A force element (a bushing, spring, ...).
    Element(ElementHandle),
}

/// What an output measures.
#[derive(Clone, Debug)]
pub enum Request {
    /// A tyre's contact quantity.
    Tyre {
        /// The tyre.
        tyre: TyreHandle,
        /// Which quantity.
        quantity: TyreQuantity,
    },
    /// A modal body's elastic state.
    Modal {
        /// The modal body.
        body: BodyHandle,
        /// Which quantity.
        quantity: ModalQuantity,
    },
    /// A marker's kinematics.
    Marker {
        /// The marker.
        marker: MarkerHandle,
        /// Which quantity.
        quantity: MarkerQuantity,
        /// Axes the vector is resolved in.
        axes: Axes,
    },
    /// A joint's reaction or free coordinate.
    Joint {
        /// The joint.
        joint: JointHandle,
        /// Which quantity.
        quantity: JointQuantity,
        /// Axes the vector is resolved in.
        axes: Axes,
    },
    /// A force element's measures.
    Element {
        /// The element.
        element: ElementHandle,
        /// Which quantity.
        quantity: ElementQuantity,
    },
    /// One law's share of a spring-damper line's force, positive pushing the ends apart
    /// (compression in a suspension spring or strut) [N].
    LinePart {
        /// The spring-damper element.
        element: ElementHandle,
        /// Which law.
        part: LinePart,
    },
    /// The force of a spring-damper line's spring law (preload included, positive
    /// pushing the ends apart) over an area: the gauge pressure of a gas spring whose
    /// force is p A [Pa].
    LinePressure {
        /// The spring-damper element.
        element: ElementHandle,
        /// Effective area [m^2].
        area_m2: f64,
    },
    /// One component of marker I's origin relative to marker J's, in J's axes, less
    /// `offset` (or its rate).
    Relative {
        /// Marker I.
        i: MarkerHandle,
        /// Marker J.
        j: MarkerHandle,
        /// Component 0, 1, 2 (x, y, z of J).
        axis: usize,
        /// Position or velocity.
        quantity: RelativeQuantity,
        /// Subtracted from the position [m] (its design value, say).
        offset: f64,
    },
    /// The load a joint or two-marker force element passes into the body of its marker
    /// J: the force on J's body, then the moment on it about J's origin (six components,
    /// N and N m), resolved in `axes`. An element acts at marker I's origin, so the
    /// moment carries the offset of I from J (the element's deflection).
    Transmitted {
        /// The joint or force element.
        by: Carrier,
        /// Axes the force and moment are resolved in.
        axes: Axes,
    },
    /// A body's heave, pitch or roll at its centre of mass.
    Body {
        /// The body.
        body: BodyHandle,
        /// Which quantity.
        quantity: BodyQuantity,
        /// Reference height of the centre of mass [m] (heave is measured from it).
        z_ref: f64,
    },
    /// The engine's share of a speed controller's demand, the total drive torque at the
    /// driven wheels before the drag's spin weighting [N m].
    DriveTorque {
        /// Index into `Model::controls`.
        control: usize,
    },
    /// The friction brakes' share of a speed controller's demand: the total brake
    /// torque capacity of the moment, negative (a brake opposes forward spin) [N m].
    BrakeTorque {
        /// Index into `Model::controls`.
        control: usize,
    },
}

/// A named output request: one or more channels of the output table.
#[derive(Clone, Debug)]
pub struct Output {
    /// Output name; channels are `<name>.x`, `<name>.y`, ... unless `components` names them.
    pub name: String,
    /// What is measured.
    pub request: Request,
    /// Channel names replacing the default `<name>.x`, `<name>.y`, ... (one per component
    /// the request produces, in order); an empty name drops that component. Fixed
    /// channel names such as `hitch_fx` or `acc_wheel_front_left_z` come from here.
    pub components: Option<Vec<String>>,
    /// Factor on every component (-1 reports an element's load on its J body).
    pub scale: f64,
}

impl Output {
    /// An output with the default channel names and no scaling.
    pub fn new(name: impl Into<String>, request: Request) -> Output {
        Output {
            name: name.into(),
            request,
            components: None,
            scale: 1.0,
        }
    }
}

/// A tyre on a wheel: the wheel centre marker sits on the rim body, its y axis is the
/// spin axis (pointing left on a car). The tyre reads the model's road.
#[derive(Clone, Debug)]
pub struct TyreElem {
    /// Unique tyre name.
    pub name: String,
    /// Wheel-centre marker on the rim body.
    pub marker: MarkerHandle,
    /// The tyre model with its parameters.
    pub tyre: crate::tyre::Tyre,
}

/// A speed-holding driveline: a PI controller on the drive torque, split equally over
/// the driven wheels (an open differential), like the thesis's engine.
#[derive(Clone, Debug)]
pub struct SpeedControl {
    /// Unique controller name.
    pub name: String,
    /// Marker whose velocity along its own x axis is held (the car body, x forward).
    pub sensor: MarkerHandle,
    /// Set speed of time [m/s].
    pub target: TimeFunction,
    /// Proportional gain [N m / (m/s)] on the total drive torque.
    pub kp: f64,
    /// Integral gain [N m / m].
    pub ki: f64,
    /// Limit of the total drive torque magnitude [N m].
    pub max_torque: f64,
    /// Driven wheels: (wheel-centre marker on the wheel, y axis = spin axis; marker on the
    /// carrier that takes the reaction, e.g. the knuckle). Torque +T/n about the wheel
    /// marker's y axis on the wheel, -T/n on the carrier.
    pub wheels: Vec<(MarkerHandle, MarkerHandle)>,
    /// Feed-forward on the target's rate [N m / (m/s^2)]: the vehicle's mass (with its
    /// wheels' spin inertia) times the rolling radius, so that a demanded acceleration
    /// needs no speed error to build its torque. No effect on a constant target.
    pub feedforward_kg_m: f64,
    /// Friction brakes taking what the controller asks beyond the drive's drag; without
    /// them the drive takes any torque, as an engine that brakes would.
    pub brakes: Option<Brakes>,
    /// The engine's and gearbox's rotating inertia behind an open differential; without
    /// it the drive torque acts on the wheels directly (no driveline inertia).
    pub driveline: Option<DrivelineInertia>,
}

/// Rotating inertia of the driveline on the differential of a [`SpeedControl`]'s driven
/// wheels. The engine turns a shaft of inertia `inertia` (the crank-side inertia times
/// the squared overall ratio, reflected to the wheels) whose spin w_d follows the MEAN of
/// the driven wheels' spins on their carriers (an open differential: the two wheels may
/// turn at different rates, their mean is geared to the engine). The gearing is held by a
/// stiff viscous coupling T_s = `coupling` (w_d - mean spin), a penalty regularisation of
/// that constraint with time constant `inertia / coupling`; T_s is shared equally over the
/// wheels (the open differential's equal torque split).
#[derive(Clone, Copy, Debug)]
pub struct DrivelineInertia {
    /// Rotating inertia reflected to the wheels, J_crank (i_gear i_final)^2 [kg m^2].
    pub inertia: f64,
    /// Coupling rate between the shaft's spin and the wheels' mean spin [N m s/rad].
    pub coupling: f64,
}

/// Friction brakes under a [`SpeedControl`]: the torque asked below `-engine_drag` goes
/// to them, blended in over `blend` so the split stays differentiable.
#[derive(Clone, Debug)]
pub struct Brakes {
    /// Braked wheels: (wheel-centre marker, y axis = spin axis; carrier marker taking the
    /// reaction; share of the total brake torque, the shares summing to 1).
    pub wheels: Vec<(MarkerHandle, MarkerHandle, f64)>,
    /// Limit of the total brake torque magnitude [N m].
    pub max_torque: f64,
    /// Torque the drive takes before the brakes engage (engine braking) [N m].
    pub engine_drag: f64,
    /// Width of the smooth hand-over from the drive to the brakes [N m].
    pub blend: f64,
    /// The bristle of every brake and of the engine's drag: stick-slip friction that
    /// holds a part at rest against any torque below the contact's capacity
    /// ([`crate::model::stick`]).
    pub stick: crate::model::stick::StickFriction,
    /// Brake torque a driver keeps on at a standstill, added to the controller's as
    /// the target speed falls below `hold_speed` (smoothly, full at zero) [N m].
    pub hold_torque: f64,
    /// Target speed below which the hold comes in [m/s].
    pub hold_speed: f64,
}

/// Where sampled accelerations and joint reactions come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Accelerations {
    /// The integrator's own solution: the derivative of its interpolating polynomial
    /// (v') and its multipliers, which satisfy the equations of motion at every step
    /// to the integration tolerance. Costs nothing extra per sample.
    #[default]
    Interpolant,
    /// Solved again at each sample from the acceleration-level equations at the sampled
    /// (q, v): [M B^T; B 0] [v'; lambda] = [f; -gamma]. Consistent with the positions and
    /// velocities to round-off; in a vehicle run this costs about a third of the run.
    Solve,
}

/// A complete mechanism.
#[derive(Clone, Debug, Default)]
pub struct Model {
    /// Model name (used in reports).
    pub name: String,
    /// Gravity in world axes [m/s^2].
    pub gravity: [f64; 3],
    /// Rigid and modal bodies.
    pub bodies: Vec<Body>,
    /// Frames fixed on bodies or ground; joints, elements and outputs refer to them.
    pub markers: Vec<Marker>,
    /// Ideal joints.
    pub joints: Vec<Joint>,
    /// Force elements: springs, dampers, bushings, stops and applied loads.
    pub forces: Vec<Force>,
    /// Prescribed joint motions.
    pub motions: Vec<Motion>,
    /// Output requests, in channel order.
    pub outputs: Vec<Output>,
    /// Tyres on wheels.
    pub tyres: Vec<TyreElem>,
    /// Speed-holding drivelines.
    pub controls: Vec<SpeedControl>,
    /// The road the tyres roll on (required when there are tyres).
    pub road: Option<crate::road::Road>,
    /// Source of sampled accelerations and reactions.
    pub accelerations: Accelerations,
}

impl Model {
    /// Name of body `b`; "ground" for `None`.
    pub fn body_name(&self, b: BodyId) -> &str {
        match b {
            None => "ground",
            Some(k) => &self.bodies[k].name,
        }
    }

    /// The marker called `name`.
    pub fn marker_by_name(&self, name: &str) -> Option<MarkerHandle> {
        self.markers
            .iter()
            .position(|m| m.name == name)
            .map(MarkerHandle)
    }

    /// The joint called `name` (an ideal joint, not one replaced by a bushing).
    pub fn joint_by_name(&self, name: &str) -> Option<JointHandle> {
        self.joints
            .iter()
            .position(|j| j.name == name)
            .map(JointHandle)
    }

    /// The force element called `name`.
    pub fn element_by_name(&self, name: &str) -> Option<ElementHandle> {
        self.forces
            .iter()
            .position(|f| f.name() == name)
            .map(ElementHandle)
    }

    /// Every body with its handle, in order.
    pub fn each_body(&self) -> impl Iterator<Item = (BodyHandle, &Body)> {
        self.bodies
            .iter()
            .enumerate()
            .map(|(k, b)| (BodyHandle(k), b))
    }

    /// Every marker with its handle, in order.
    pub fn each_marker(&self) -> impl Iterator<Item = (MarkerHandle, &Marker)> {
        self.markers
            .iter()
            .enumerate()
            .map(|(k, m)| (MarkerHandle(k), m))
    }

    /// Every ideal joint with its handle, in order.
    pub fn each_joint(&self) -> impl Iterator<Item = (JointHandle, &Joint)> {
        self.joints
            .iter()
            .enumerate()
            .map(|(k, j)| (JointHandle(k), j))
    }

    /// Every force element with its handle, in order.
    pub fn each_element(&self) -> impl Iterator<Item = (ElementHandle, &Force)> {
        self.forces
            .iter()
            .enumerate()
            .map(|(k, f)| (ElementHandle(k), f))
    }

    /// Every tyre with its handle, in order.
    pub fn each_tyre(&self) -> impl Iterator<Item = (TyreHandle, &TyreElem)> {
        self.tyres
            .iter()
            .enumerate()
            .map(|(k, t)| (TyreHandle(k), t))
    }
}
