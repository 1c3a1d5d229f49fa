//! Constraint equations of the ideal joints and prescribed motions, generic over the
//! scalar so [`super::system`] can differentiate them exactly.
//!
//! Each joint is built from the classic primitives (Haug, Computer Aided Kinematics and
//! Dynamics of Mechanical Systems, 1989, ch. 3; the Adams JPRIM set): with d the vector
//! from J's origin to I's origin and x, y, z the marker axes in world coordinates,
//! - point coincidence: d . x_J = d . y_J = d . z_J = 0;
//! - parallel z axes: z_I . y_J = 0 (locks rotation about x_J), z_I . x_J = 0 (about y_J);
//! - no twist: x_I . y_J = 0 (locks rotation about z_J);
//! - in-line: d . x_J = d . y_J = 0; in-plane: d . z_J = 0; perpendicular: z_I . z_J = 0.

use super::desc::{JointKind, MotionDof};
use super::dual::Scalar;
use super::math::{col, dot, sub, M3, V3};

/// A marker frame in world coordinates.
#[derive(Clone, Copy)]
pub struct MFrame<T: Scalar> {
    pub origin: V3<T>,
    /// Axes as columns.
    pub axes: M3<T>,
}

/// The primitive rows of a joint: what each locks (used in messages).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Row {
    AlongX,
    AlongY,
    AlongZ,
    AboutX,
    AboutY,
    AboutZ,
    Perpendicular,
}

impl Row {
    pub fn describe(self) -> &'static str {
        match self {
            Row::AlongX => "translation along x",
            Row::AlongY => "translation along y",
            Row::AlongZ => "translation along z",
            Row::AboutX => "rotation about x",
            Row::AboutY => "rotation about y",
            Row::AboutZ => "rotation about z",
            Row::Perpendicular => "perpendicularity of the z axes",
        }
    }
}

/// The rows a joint kind contributes, in order.
pub fn rows(kind: JointKind) -> &'static [Row] {
    use Row::*;
    match kind {
        JointKind::Fixed => &[AlongX, AlongY, AlongZ, AboutX, AboutY, AboutZ],
        JointKind::Revolute => &[AlongX, AlongY, AlongZ, AboutX, AboutY],
        JointKind::Spherical => &[AlongX, AlongY, AlongZ],
        JointKind::Cylindrical => &[AlongX, AlongY, AboutX, AboutY],
        JointKind::Translational => &[AlongX, AlongY, AboutX, AboutY, AboutZ],
        JointKind::Universal => &[AlongX, AlongY, AlongZ, Perpendicular],
        JointKind::Inline => &[AlongX, AlongY],
        JointKind::Inplane => &[AlongZ],
        JointKind::Perpendicular => &[Perpendicular],
        JointKind::Orientation => &[AboutX, AboutY, AboutZ],
    }
}

/// Value of one primitive row.
pub fn row_value<T: Scalar>(row: Row, i: &MFrame<T>, j: &MFrame<T>) -> T {
    let d = sub(&i.origin, &j.origin);
    match row {
        Row::AlongX => dot(&d, &col(&j.axes, 0)),
        Row::AlongY => dot(&d, &col(&j.axes, 1)),
        Row::AlongZ => dot(&d, &col(&j.axes, 2)),
        Row::AboutX => dot(&col(&i.axes, 2), &col(&j.axes, 1)),
        Row::AboutY => -dot(&col(&i.axes, 2), &col(&j.axes, 0)),
        Row::AboutZ => dot(&col(&i.axes, 0), &col(&j.axes, 1)),
        Row::Perpendicular => dot(&col(&i.axes, 2), &col(&j.axes, 2)),
    }
}

/// The driving constraint of a motion with prescribed value s: for a translation
/// d . z_J - s, for a rotation sin(theta - s) written without angles as
/// (x_I . y_J) cos s - (x_I . x_J) sin s, smooth for any number of turns.
pub fn motion_value<T: Scalar>(dof: MotionDof, s: T, i: &MFrame<T>, j: &MFrame<T>) -> T {
    match dof {
        MotionDof::Translation => {
            let d = sub(&i.origin, &j.origin);
            dot(&d, &col(&j.axes, 2)) - s
        }
        MotionDof::Rotation => {
            let xi = col(&i.axes, 0);
            dot(&xi, &col(&j.axes, 1)) * s.cos() - dot(&xi, &col(&j.axes, 0)) * s.sin()
        }
    }
}

/// The joint's free coordinate along or about J's z (for outputs): translation d . z_J,
/// or the angle from x_J to x_I about z_J in (-pi, pi].
pub fn joint_coordinate(dof: MotionDof, i: &MFrame<f64>, j: &MFrame<f64>) -> f64 {
    match dof {
        MotionDof::Translation => dot(&sub(&i.origin, &j.origin), &col(&j.axes, 2)),
        MotionDof::Rotation => {
            let xi = col(&i.axes, 0);
            dot(&xi, &col(&j.axes, 1)).atan2(dot(&xi, &col(&j.axes, 0)))
        }
    }
}
