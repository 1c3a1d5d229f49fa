//! The generated models of the scaling study, built through the model builder: a chain of
//! links on revolute joints, and a ladder of closed loops (parallelogram four-bars stacked
//! on each other), both moving in the x-z plane under gravity.

use serde::Deserialize;

use towride_mbs::model::builder::{BodyDesc, ModelBuilder};
use towride_mbs::model::desc::{Axes as OutputAxes, JointQuantity, MarkerQuantity, Request};
use towride_mbs::model::desc::{JointKind, Model, Output};
use towride_mbs::model::ModelError;

/// A slender link: a uniform rod.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Link {
    /// Mass [kg].
    pub mass_kg: f64,
    /// Length, joint to joint [m].
    pub length_m: f64,
    /// Radius of the rod, for its inertia about its own axis [m].
    pub radius_m: f64,
}

impl Link {
    /// A body along the world x axis from `a` (rotated `angle` [rad] about +y, turning x
    /// towards -z): mass at its middle, m L^2 / 12 across it and m r^2 / 2 along it.
    fn body(&self, name: &str, a: [f64; 3], angle: f64) -> BodyDesc {
        let (m, l, r) = (self.mass_kg, self.length_m, self.radius_m);
        let across = m * l * l / 12.0 + m * r * r / 4.0;
        let dir = [angle.cos(), 0.0, -angle.sin()];
        let cm = [a[0] + 0.5 * l * dir[0], a[1], a[2] + 0.5 * l * dir[2]];
        let mut d = BodyDesc::new(name, m, [0.5 * m * r * r, across, across], cm);
        d.axes = [
            [dir[0], 0.0, -dir[2]],
            [0.0, 1.0, 0.0],
            [dir[2], 0.0, dir[0]],
        ];
        d
    }

    /// The far end of the link from `a` at `angle`.
    fn end(&self, a: [f64; 3], angle: f64) -> [f64; 3] {
        let l = self.length_m;
        [a[0] + l * angle.cos(), a[1], a[2] - l * angle.sin()]
    }
}

/// Revolute axes: z along world y (the joints turn in the x-z plane).
const HINGE: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]];

/// A chain of `n` links on revolute joints, the first hinged to ground at the origin,
/// laid out along +x (horizontal) and falling under `gravity`. Outputs: the last link's
/// centre of mass position and the first joint's reaction force.
pub fn chain(link: &Link, n: usize, gravity: [f64; 3]) -> Result<Model, ModelError> {
    let mut b = ModelBuilder::new(&format!("chain of {n} links"), gravity);
    let mut prev = None;
    let mut at = [0.0; 3];
    for k in 0..n {
        let body = b.body(link.body(&format!("link{k}"), at, 0.0))?;
        b.joint(
            &format!("hinge{k}"),
            JointKind::Revolute,
            Some(body),
            prev,
            at,
            &HINGE,
            None,
        )?;
        prev = Some(body);
        at = link.end(at, 0.0);
    }
    outputs(&mut b, &format!("link{}.cm", n.saturating_sub(1)), "hinge0");
    Ok(b.finish())
}

/// A ladder of `n` parallelogram loops hanging from ground: loop k is two posts hinged
/// to rung k - 1 (ground for the first) at its ends and to rung k at theirs, every link
/// `link` long, the posts leaning `angle` [rad] from the vertical, so the ladder swings
/// down under `gravity`. Each loop closes in the plane, so three of its rows repeat the
/// others (a planar loop built of 3D revolute joints). Outputs: the last rung's centre
/// of mass position and the first joint's reaction force.
pub fn ladder(link: &Link, n: usize, angle: f64, gravity: [f64; 3]) -> Result<Model, ModelError> {
    let mut b = ModelBuilder::new(&format!("ladder of {n} loops"), gravity);
    let l = link.length_m;
    // Post direction from its top, measured like Link::body's angle (from +x towards -z).
    let post = std::f64::consts::FRAC_PI_2 - angle;
    let mut rung = None;
    let mut top = [[0.0, 0.0, 0.0], [l, 0.0, 0.0]];
    for k in 0..n {
        let mut bottoms = [[0.0; 3]; 2];
        let mut posts = Vec::new();
        for (s, side) in ["left", "right"].iter().enumerate() {
            let p = b.body(link.body(&format!("post{k}_{side}"), top[s], post))?;
            b.joint(
                &format!("top{k}_{side}"),
                JointKind::Revolute,
                Some(p),
                rung,
                top[s],
                &HINGE,
                None,
            )?;
            bottoms[s] = link.end(top[s], post);
            posts.push(p);
        }
        let r = b.body(link.body(&format!("rung{k}"), bottoms[0], 0.0))?;
        for (s, side) in ["left", "right"].iter().enumerate() {
            b.joint(
                &format!("bottom{k}_{side}"),
                JointKind::Revolute,
                Some(r),
                Some(posts[s]),
                bottoms[s],
                &HINGE,
                None,
            )?;
        }
        rung = Some(r);
        top = bottoms;
    }
    outputs(
        &mut b,
        &format!("rung{}.cm", n.saturating_sub(1)),
        "top0_left",
    );
    Ok(b.finish())
}

/// The position of `marker` and the reaction of `joint` (world axes).
fn outputs(b: &mut ModelBuilder, marker: &str, joint: &str) {
    let m = b.marker_by_name(marker);
    let j = b.joint_by_name(joint);
    if let Some(marker) = m {
        b.output(Output::new(
            "tip",
            Request::Marker {
                marker,
                quantity: MarkerQuantity::Position,
                axes: OutputAxes::World,
            },
        ));
    }
    if let Some(joint) = j {
        b.output(Output::new(
            "root",
            Request::Joint {
                joint,
                quantity: JointQuantity::Force,
                axes: OutputAxes::World,
            },
        ));
    }
}
