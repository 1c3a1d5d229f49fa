//! McPherson strut kinematics at the design position, for the design statics: the body
//! held and the bushings rigid, the lower arm turns about its pivot axis and the knuckle
//! follows the ball joint, with its strut axis through the top mount and its steering
//! arm on the tie rod. All velocities per unit rotation rate of the arm.

use super::geom::{length_rate, mirror, turning, unit, V};
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::math::{add, cross, dot, scale, sub};
use towride_mbs::path;

/// Hardpoints of one side [m].
#[derive(Clone, Debug)]
pub struct Pts {
    /// Wheel centre.
    pub w: V,
    /// Lower arm's front and rear body bushings.
    pub af: V,
    pub ar: V,
    /// Ball joint.
    pub b: V,
    /// Strut axis: lower point on the knuckle, top-mount centre.
    pub l: V,
    pub t: V,
    /// Lower spring seat (knuckle).
    pub q: V,
    /// Tie rod: inner (rack) and outer (steering arm) ends.
    pub s: V,
    pub r: V,
}

impl Pts {
    /// The right side's points (itself when `right` is false).
    pub fn side(&self, right: bool) -> Pts {
        let m = |p: V| if right { mirror(p) } else { p };
        Pts {
            w: m(self.w),
            af: m(self.af),
            ar: m(self.ar),
            b: m(self.b),
            l: m(self.l),
            t: m(self.t),
            q: m(self.q),
            s: m(self.s),
            r: m(self.r),
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
}

/// The rates of side `p` with the parts' centres of mass `cms` (knuckle, lower arm,
/// rod, tie rod).
pub fn rates(p: &Pts, src: &Source, cms: &[V; 4]) -> Result<Rates, InputError> {
    let u = unit(&sub(&p.af, &p.ar));
    let vb = turning(&p.ar, &u, &p.b);
    let a = unit(&sub(&p.t, &p.l));
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
    let tb = sub(&p.t, &p.b);
    let rs = sub(&p.r, &p.s);
    let rows = [
        cross(&tb, &e1),
        cross(&tb, &e2),
        cross(&sub(&p.r, &p.b), &rs),
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
    let on_knuckle = |x: &V| add(&vb, &cross(&w, &sub(x, &p.b)));
    // The rod tilts with the knuckle about the top mount but does not spin with it.
    let w_rod = sub(&w, &scale(&a, dot(&w, &a)));
    // The tie rod turns about its inner joint: its points move in proportion.
    let along = dot(&sub(&cms[3], &p.s), &rs) / dot(&rs, &rs);
    Ok(Rates {
        parts: [
            on_knuckle(&cms[0]),
            turning(&p.ar, &u, &cms[1]),
            cross(&w_rod, &sub(&cms[2], &p.t)),
            scale(&on_knuckle(&p.r), along),
        ],
        wheel_centre: on_knuckle(&p.w),
        spring: length_rate(&p.q, &on_knuckle(&p.q), &p.t),
    })
}
