//! Geometry shared by the templates: where a subsystem's coordinates lie in the world,
//! left-right mirroring, and rigid-body velocity fields for the design statics.
//!
//! Vehicle coordinates: x forward, y left, z up; origin on the ground under the centre of
//! the front axle with the car at its design ride height. Trailer coordinates: the same
//! axes, origin on the ground under the coupling's ball centre.

use towride_mbs::model::math::{cross, dot, scale, sub};

pub use towride_mbs::model::builder::{Axes, Placement, IDENTITY, V};

/// A frame with its z axis along y (columns x, -z, y): revolute axes of wheel bearings
/// and axle pivots.
pub const Z_ALONG_Y: Axes = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]];

/// The right-side image of a left-side point.
pub fn mirror(p: V) -> V {
    [p[0], -p[1], p[2]]
}

/// The inertia tensor of the mirror image (products with y change sign).
pub fn mirror_inertia(i: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut o = *i;
    o[0][1] = -i[0][1];
    o[1][0] = -i[1][0];
    o[1][2] = -i[1][2];
    o[2][1] = -i[2][1];
    o
}

/// The mirror image of a frame, made right-handed again (x and z mirrored, y = z x x).
pub fn mirror_axes(a: &Axes) -> Axes {
    let c = |k: usize| mirror([a[0][k], a[1][k], a[2][k]]);
    let (x, z) = (c(0), c(2));
    let y = cross(&z, &x);
    [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
}

pub fn norm(v: &V) -> f64 {
    dot(v, v).sqrt()
}

pub fn unit(v: &V) -> V {
    scale(v, 1.0 / norm(v))
}

pub fn distance(a: &V, b: &V) -> f64 {
    norm(&sub(a, b))
}

/// A right-handed frame with z along `z` (x from `x` or chosen), as columns.
pub fn frame(z: V, x: Option<V>) -> Option<Axes> {
    towride_mbs::model::math::frame_from_axes(z, x)
}

/// Velocity of point `p` of a body turning at unit rate about the axis through `on`
/// along the unit vector `axis`.
pub fn turning(on: &V, axis: &V, p: &V) -> V {
    cross(axis, &sub(p, on))
}

/// Rate of the distance between point `p` (moving with velocity `v`) and the fixed point
/// `q`.
pub fn length_rate(p: &V, v: &V, q: &V) -> f64 {
    dot(&unit(&sub(p, q)), v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirrored_frame_is_right_handed_and_mirrors_z() {
        let a = frame([0.1, 0.3, 0.9], Some([1.0, 0.2, 0.0])).unwrap();
        let m = mirror_axes(&a);
        let col = |a: &Axes, k: usize| [a[0][k], a[1][k], a[2][k]];
        assert!((norm(&sub(&col(&m, 2), &mirror(col(&a, 2))))) < 1e-12);
        let det = dot(&cross(&col(&m, 0), &col(&m, 1)), &col(&m, 2));
        assert!((det - 1.0).abs() < 1e-12);
    }

    #[test]
    fn z_along_y_is_a_right_handed_frame_with_z_on_y() {
        let col = |k: usize| [Z_ALONG_Y[0][k], Z_ALONG_Y[1][k], Z_ALONG_Y[2][k]];
        assert_eq!(col(2), [0.0, 1.0, 0.0]);
        assert_eq!(cross(&col(0), &col(1)), col(2));
    }

    #[test]
    fn pitched_placement_keeps_the_pivot() {
        let p = Placement::pitched([2.0, 0.0, 0.0], 0.1, [1.0, 0.0, 0.0]);
        let q = p.point([2.0, 0.0, 0.0]);
        assert!(norm(&sub(&q, &[3.0, 0.0, 0.0])) < 1e-12);
    }
}
