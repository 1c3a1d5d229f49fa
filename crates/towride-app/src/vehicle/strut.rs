//! McPherson strut kinematics at the design position, for the design statics: the body
//! held and the bushings rigid, the lower arm turns about its pivot axis and the knuckle
//! follows the ball joint, with its strut axis through the top mount and its steering
//! arm on the tie rod. All velocities per unit rotation rate of the arm.

use super::geom::{length_rate, mirror, turning, unit, V};
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::math::{add, cross, dot, scale, sub};
use towride_mbs::path;

/// Hardpoints of one side [m] (the property file's `[hardpoints]`, without `_m`).
#[derive(Clone, Debug)]
pub struct StrutPoints {
    pub wheel_centre: V,
    /// Lower arm's front and rear body bushings (its pivot axis).
    pub lower_arm_front: V,
    pub lower_arm_rear: V,
    /// The lower arm's ball joint on the knuckle.
    pub ball_joint: V,
    /// Strut axis: lower point on the knuckle, top-mount centre.
    pub strut_lower: V,
    pub strut_top: V,
    /// Lower spring seat (knuckle).
    pub spring_seat: V,
    /// Tie rod: inner (rack) and outer (steering arm) ends.
    pub tie_rod_inner: V,
    pub tie_rod_outer: V,
}

impl StrutPoints {
    /// The right side's points (itself when `right` is false).
    pub fn side(&self, right: bool) -> StrutPoints {
        let m = |p: V| if right { mirror(p) } else { p };
        StrutPoints {
            wheel_centre: m(self.wheel_centre),
            lower_arm_front: m(self.lower_arm_front),
            lower_arm_rear: m(self.lower_arm_rear),
            ball_joint: m(self.ball_joint),
            strut_lower: m(self.strut_lower),
            strut_top: m(self.strut_top),
            spring_seat: m(self.spring_seat),
            tie_rod_inner: m(self.tie_rod_inner),
            tie_rod_outer: m(self.tie_rod_outer),
        }
    }
}

/// Velocities per unit rotation rate of the lower arm.
pub struct Rates {
    /// Centres of mass of knuckle, lower arm, rod, tie rod.
    pub parts: [V; 4],
    pub wheel_centre: V,
    /// Spring length rate.
    pub spring: f64,
    /// The knuckle's angular velocity.
    pub knuckle: V,
}

/// The rates of side `p` with the parts' centres of mass `cms` (knuckle, lower arm,
/// rod, tie rod).
pub fn rates(p: &StrutPoints, src: &Source, cms: &[V; 4]) -> Result<Rates, InputError> {
    let u = unit(&sub(&p.lower_arm_front, &p.lower_arm_rear));
    let vb = turning(&p.lower_arm_rear, &u, &p.ball_joint);
    let a = unit(&sub(&p.strut_top, &p.strut_lower));
    let guess = if a[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = unit(&cross(&a, &guess));
    let e2 = cross(&a, &e1);
    // Knuckle angular velocity w: the knuckle point at the top mount moves along the
    // strut axis only (two rows: e.(vb + w x (T - B)) = 0), and the tie rod keeps its
    // length (one row); e.(w x r) = w.(r x e).
    let tb = sub(&p.strut_top, &p.ball_joint);
    let rs = sub(&p.tie_rod_outer, &p.tie_rod_inner);
    let rows = [
        cross(&tb, &e1),
        cross(&tb, &e2),
        cross(&sub(&p.tie_rod_outer, &p.ball_joint), &rs),
    ];
    let rhs = [-dot(&e1, &vb), -dot(&e2, &vb), -dot(&rs, &vb)];
    let m = nalgebra::Matrix3::from_fn(|i, j| rows[i][j]);
    let w = m
        .lu()
        .solve(&nalgebra::Vector3::from_fn(|i, _| rhs[i]))
        .ok_or_else(|| {
            src.error(
                &path!["hardpoints"],
                "the strut, ball joint and tie rod lock the knuckle (singular geometry)",
            )
        })?;
    let w = [w[0], w[1], w[2]];
    let on_knuckle = |x: &V| add(&vb, &cross(&w, &sub(x, &p.ball_joint)));
    // The rod tilts with the knuckle about the top mount but does not spin with it.
    let w_rod = sub(&w, &scale(&a, dot(&w, &a)));
    // The tie rod turns about its inner joint: its points move in proportion.
    let along = dot(&sub(&cms[3], &p.tie_rod_inner), &rs) / dot(&rs, &rs);
    Ok(Rates {
        parts: [
            on_knuckle(&cms[0]),
            turning(&p.lower_arm_rear, &u, &cms[1]),
            cross(&w_rod, &sub(&cms[2], &p.strut_top)),
            scale(&on_knuckle(&p.tie_rod_outer), along),
        ],
        wheel_centre: on_knuckle(&p.wheel_centre),
        spring: length_rate(&p.spring_seat, &on_knuckle(&p.spring_seat), &p.strut_top),
        knuckle: w,
    })
}
