//! Force elements: each file holds one element's data, its checks, its load evaluation
//! (generic over the scalar, so dual numbers give the iteration matrix), the channels it
//! reports and its table in a mechanism file. The list at the bottom of this file,
//! `force_elements!`, declares and registers them: adding an element is its own file
//! plus one line there (see `docs/architecture.md`).
//!
//! An element sees its marker frames as [`Dual`]s with one direction, the time
//! derivative along the motion, so a deflection and its rate come from one expression
//! (the rate of a bushing's rotation vector is its exact time derivative, not the
//! relative angular velocity). It returns the force on marker I's body applied at I's
//! origin plus a torque, world axes; the J body gets the opposite.

pub mod law;

pub use law::{JointBushing, Law, LawSpec, Stop, StopSpec};

use serde::de::DeserializeOwned;

use super::builder::ModelBuilder;
use super::dual::{Dual, Scalar};
use super::joint::MFrame;
use super::math::{cross, mtv, sub, Q4, V3};
pub use crate::input::FieldError;

/// A quantity and its time derivative.
pub type Rate<S> = Dual<S, 1>;

/// A marker frame with rates, and its orientation as a quaternion.
pub type Frame<S> = (MFrame<Rate<S>>, Q4<Rate<S>>);

/// What an element puts on its bodies, plus its measures for outputs.
pub struct ElementLoad<S: Scalar> {
    /// Force on I's body at I's origin (world).
    pub force: V3<S>,
    /// Torque on I's body (world).
    pub torque: V3<S>,
    /// Per measured direction: force (or torque), deflection and its rate.
    pub measures: Vec<(S, S, S)>,
}

/// One measured direction of an element: the channel suffix (`None`: the output's own
/// name), the units of force, deflection and rate, and whether the deflection is an
/// angle to unwrap over time.
#[derive(Clone, Copy, Debug)]
pub struct Measure {
    /// Appended to the output name as `<name>.<suffix>`.
    pub suffix: Option<&'static str>,
    /// Units of the force, deflection and velocity quantities.
    pub units: [&'static str; 3],
    /// The deflection is an angle.
    pub angle: bool,
}

/// The six directions of a 6-DOF element, translations then rotations.
pub const SIX: [Measure; 6] = [
    Measure::translation("x"),
    Measure::translation("y"),
    Measure::translation("z"),
    Measure::rotation("rx"),
    Measure::rotation("ry"),
    Measure::rotation("rz"),
];

impl Measure {
    const fn translation(s: &'static str) -> Measure {
        Measure {
            suffix: Some(s),
            units: ["N", "m", "m/s"],
            angle: false,
        }
    }

    const fn rotation(s: &'static str) -> Measure {
        Measure {
            suffix: Some(s),
            units: ["N m", "rad", "rad/s"],
            angle: false,
        }
    }
}

/// What every force element provides.
pub trait ForceElement: Clone + std::fmt::Debug {
    /// The table of a mechanism file that lists elements of this kind (`spring`, ...).
    const TABLE: &'static str;
    /// How the mechanism file writes one element.
    type Spec: DeserializeOwned;

    /// The element's name.
    fn name(&self) -> &str;
    /// Marker I and, for two-marker elements, marker J.
    fn markers(&self) -> (usize, Option<usize>);
    /// The same, for moving a marker onto a modal node.
    fn markers_mut(&mut self) -> (&mut usize, Option<&mut usize>);
    /// Checks the parameters; errors name the field as the file keys do.
    fn check(&self) -> Result<(), FieldError>;
    /// Load and measures at time `t` given the marker frames (`j` is `None` for a
    /// one-marker element).
    fn load<S: Scalar>(&self, t: f64, i: &Frame<S>, j: Option<&Frame<S>>) -> ElementLoad<S>;
    /// The measured directions, in the order of [`ElementLoad::measures`].
    fn measures(&self) -> Vec<Measure>;
    /// Adds one element written in a mechanism file; errors name the field below the
    /// element's entry.
    fn add_from_file(spec: &Self::Spec, b: &mut ModelBuilder) -> Result<(), FieldError>;
}

/// Generalised force (force, body-frame torque) of a world force `f` at world point `p`
/// plus a world torque `t` on a body at `r` with rotation `a`.
pub fn generalised<S: Scalar>(
    r: &V3<S>,
    a: &[[S; 3]; 3],
    p: &V3<S>,
    f: &V3<S>,
    t: &V3<S>,
) -> [S; 6] {
    let arm = sub(p, r);
    let m = cross(&arm, f);
    let mw = [m[0] + t[0], m[1] + t[1], m[2] + t[2]];
    let mb = mtv(a, &mw);
    [f[0], f[1], f[2], mb[0], mb[1], mb[2]]
}

/// Generates [`Force`], the closed set of element kinds, and its dispatch; one line per
/// element: `Variant(type)`.
macro_rules! force_elements {
    ($($module:ident::$ty:ident as $variant:ident),* $(,)?) => {
        $(
            pub mod $module;
            pub use $module::$ty;
        )*

        /// A force element of any registered kind.
        // A model holds a handful of elements; boxing the large bushing would buy nothing.
        #[allow(clippy::large_enum_variant)]
        #[derive(Clone, Debug)]
        pub enum Force {
            $(
                #[allow(missing_docs)]
                $variant($ty),
            )*
        }

        impl Force {
            /// The element's name.
            pub fn name(&self) -> &str {
                match self { $(Force::$variant(e) => e.name(),)* }
            }
            /// Its kind, as a mechanism file's table names it.
            pub fn kind(&self) -> &'static str {
                match self { $(Force::$variant(_) => <$ty as ForceElement>::TABLE,)* }
            }
            /// Marker I and, for two-marker elements, marker J.
            pub fn markers(&self) -> (usize, Option<usize>) {
                match self { $(Force::$variant(e) => e.markers(),)* }
            }
            /// The same, mutable.
            pub fn markers_mut(&mut self) -> (&mut usize, Option<&mut usize>) {
                match self { $(Force::$variant(e) => e.markers_mut(),)* }
            }
            /// Checks the parameters.
            pub fn check(&self) -> Result<(), FieldError> {
                match self { $(Force::$variant(e) => e.check(),)* }
            }
            /// Load and measures.
            pub fn load<S: Scalar>(&self, t: f64, i: &Frame<S>, j: Option<&Frame<S>>) -> ElementLoad<S> {
                match self { $(Force::$variant(e) => e.load(t, i, j),)* }
            }
            /// The measured directions.
            pub fn measures(&self) -> Vec<Measure> {
                match self { $(Force::$variant(e) => e.measures(),)* }
            }
        }

        $(
            impl From<$ty> for Force {
                fn from(e: $ty) -> Force {
                    Force::$variant(e)
                }
            }
        )*

        /// The mechanism-file tables of the registered elements, in registration order.
        pub const TABLES: &[&str] = &[$(<$ty as ForceElement>::TABLE),*];

        /// Adds every element of the registered tables of a mechanism file, table by
        /// table in registration order; errors are located at `table[k].field`.
        pub(crate) fn add_all_from_file(
            src: &crate::input::Source,
            b: &mut ModelBuilder,
        ) -> Result<(), crate::input::InputError> {
            $(
                {
                    let table = <$ty as ForceElement>::TABLE;
                    let specs: Vec<<$ty as ForceElement>::Spec> =
                        src.parse_key(table)?.unwrap_or_default();
                    for (k, spec) in specs.iter().enumerate() {
                        <$ty as ForceElement>::add_from_file(spec, b)
                            .map_err(|e| src.locate(&crate::path![table, k], e))?;
                    }
                }
            )*
            Ok(())
        }
    };
}

// The registered force elements: `file::Type as Variant`. A new element is its file in
// this folder and one line here (the line declares the module and registers the type).
force_elements! {
    spring::SpringDamper as Spring,
    bushing::Bushing as Bushing,
    rot_spring::RotSpring as Rot,
    applied::Applied as Applied,
}
