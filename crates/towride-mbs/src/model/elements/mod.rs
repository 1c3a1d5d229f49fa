//! Force elements: each file holds one element's data, its checks, its load evaluation
//! (generic over the scalar, so dual numbers give the iteration matrix), the channels it
//! reports and its table in a mechanism file. The list at the bottom of this file,
//! `force_elements!`, declares and registers them: adding an element is its own file
//! plus one line there (see `docs/architecture.md`).
//!
//! An element acts on one marker or between two, as its type says ([`Markers`]): its
//! `load` receives one frame per marker, both frames of a two-marker element by type.
//! It sees them as [`Dual`]s with one direction, the time derivative along the motion,
//! so a deflection and its rate come from one expression (the rate of a bushing's
//! rotation vector is its exact time derivative, not the relative angular velocity). It
//! returns the force on marker I's body applied at I's origin plus a torque, world axes;
//! the J body gets the opposite.

pub mod law;

pub use law::{JointBushing, Law, LawSpec, Stop, StopSpec};

use serde::de::DeserializeOwned;

use super::builder::ModelBuilder;
use super::desc::MarkerHandle;
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

/// The two markers of an element acting between them: a spring's ends, a bushing's I
/// and J.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TwoMarkers {
    /// Marker I: the element's load is the load on its body.
    pub i: MarkerHandle,
    /// Marker J: its body takes the opposite load.
    pub j: MarkerHandle,
}

/// The markers of a force element, as its type says: one ([`MarkerHandle`], a load on
/// one body) or two ([`TwoMarkers`]). Whatever goes per marker has the same shape
/// ([`Markers::Each`]): a two-marker element's `load` receives `(&Frame, &Frame)`.
pub trait Markers: Copy + std::fmt::Debug {
    /// One `T` per marker: `T` for one marker, `(T, T)` for I and J.
    type Each<T>;
    /// Marker I and, for two markers, J: every element's markers walked alike (the
    /// system's layout, the bodies an element links).
    fn pair(self) -> (MarkerHandle, Option<MarkerHandle>);
    /// `f` of each marker and its side (0: I, 1: J).
    fn each<T>(self, f: impl FnMut(MarkerHandle, usize) -> T) -> Self::Each<T>;
    /// The values by reference.
    fn each_ref<T>(each: &Self::Each<T>) -> Self::Each<&T>;
    /// Marker I's value.
    fn first<T>(each: Self::Each<T>) -> T;
}

impl Markers for MarkerHandle {
    type Each<T> = T;

    fn pair(self) -> (MarkerHandle, Option<MarkerHandle>) {
        (self, None)
    }

    fn each<T>(self, mut f: impl FnMut(MarkerHandle, usize) -> T) -> T {
        f(self, 0)
    }

    fn each_ref<T>(each: &T) -> &T {
        each
    }

    fn first<T>(each: T) -> T {
        each
    }
}

impl Markers for TwoMarkers {
    type Each<T> = (T, T);

    fn pair(self) -> (MarkerHandle, Option<MarkerHandle>) {
        (self.i, Some(self.j))
    }

    fn each<T>(self, mut f: impl FnMut(MarkerHandle, usize) -> T) -> (T, T) {
        (f(self.i, 0), f(self.j, 1))
    }

    fn each_ref<T>(each: &(T, T)) -> (&T, &T) {
        (&each.0, &each.1)
    }

    fn first<T>(each: (T, T)) -> T {
        each.0
    }
}

/// What every force element provides.
pub trait ForceElement: Clone + std::fmt::Debug {
    /// The table of a mechanism file that lists elements of this kind (`spring`, ...).
    const TABLE: &'static str;
    /// How the mechanism file writes one element.
    type Spec: DeserializeOwned;
    /// Its markers: [`MarkerHandle`] for a load on one marker, [`TwoMarkers`] for an
    /// element between two.
    type Markers: Markers;

    /// The element's name.
    fn name(&self) -> &str;
    /// Its markers.
    fn markers(&self) -> Self::Markers;
    /// Checks the parameters; errors name the field as the file keys do.
    fn check(&self) -> Result<(), FieldError>;
    /// Load and measures at time `t` given the frame of each marker: `&Frame` for one
    /// marker, `(&Frame, &Frame)` for I and J.
    fn load<S: Scalar>(
        &self,
        t: f64,
        frames: <Self::Markers as Markers>::Each<&Frame<S>>,
    ) -> ElementLoad<S>;
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
            pub fn markers(&self) -> (MarkerHandle, Option<MarkerHandle>) {
                match self { $(Force::$variant(e) => e.markers().pair(),)* }
            }
            /// Checks the parameters.
            pub fn check(&self) -> Result<(), FieldError> {
                match self { $(Force::$variant(e) => e.check(),)* }
            }
            /// Load and measures at time `t`, the frame of each of the element's markers
            /// made by `frame` (given the marker and its side, 0: I, 1: J); returns them
            /// with marker I's frame.
            pub fn load<S: Scalar>(
                &self,
                t: f64,
                frame: impl FnMut(MarkerHandle, usize) -> Frame<S>,
            ) -> (ElementLoad<S>, Frame<S>) {
                match self {
                    $(Force::$variant(e) => {
                        type M = <$ty as ForceElement>::Markers;
                        let frames = e.markers().each(frame);
                        let load = e.load(t, M::each_ref(&frames));
                        (load, M::first(frames))
                    })*
                }
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
