//! Obstacles on a flat road: trapezoidal ramps, circular-segment bumps, speed humps of a
//! continuous shape ([`super::hump`]) and steps.
//!
//! Every obstacle spans the lateral range [y_min, y_max] (the whole road width unless
//! given) and starts at `start_m`, the x of its first edge (the foot of a ramp's rising
//! flank, the start of a bump's chord, the face of a step).
//!
//! Ramp geometry (the thesis's "ramp", section 5.5.3.1: 50 mm high, 500 mm long, flanks at
//! 45 deg, 1 m ahead of the front wheels): a trapezoid with flank run f = h / tan(angle).
//! `length_measured_at = "base"` (the default of the shipped files) takes `length_m` as the
//! distance foot to foot along the road (top plateau = length - 2 f); `"top"` takes it as
//! the plateau length (base = length + 2 f). A flank angle of 90 deg gives vertical faces
//! (a rectangular cleat).

use super::RoadError;
use serde::Deserialize;

use crate::input::{InputError, Source};
use crate::path;

use super::hump::Hump;
use super::push_x_crossing;
use super::push_y_crossing;

/// Where a ramp's length is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LengthAt {
    /// Foot to foot (the trapezoid's base).
    Base,
    /// The top plateau.
    Top,
}

/// One obstacle, heights absolute (base road height included).
#[derive(Clone, Debug, PartialEq)]
pub struct Obstacle {
    /// The longitudinal shape.
    pub shape: Shape,
    /// Height of the road around the obstacle [m].
    pub base: f64,
    /// Lateral start of the obstacle [m] (-infinity: across the whole road).
    pub y_min: f64,
    /// Lateral end of the obstacle [m] (+infinity: across the whole road).
    pub y_max: f64,
}

/// The longitudinal shape of an obstacle.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Trapezoid: rises from x0 to x1, plateau to x2, falls to x3; `h` high.
    Ramp { x: [f64; 4], h: f64 },
    /// Circular segment over the chord [x0, x0 + chord], `h` high at the middle.
    Bump {
        x0: f64,
        chord: f64,
        h: f64,
        radius: f64,
    },
    /// A step of height `h` (either sign) at x0, continuing to +infinity.
    Step { x0: f64, h: f64 },
    /// A round-top to flat-top speed hump ([`Hump`]).
    Hump(Hump),
}

impl Obstacle {
    /// A ramp (trapezoid); `flank_angle_deg` in (0, 90].
    pub fn ramp(
        start: f64,
        height: f64,
        length: f64,
        at: LengthAt,
        flank_angle_deg: f64,
        base: f64,
    ) -> Result<Obstacle, RoadError> {
        if height.is_nan() || height <= 0.0 {
            return Err(RoadError::Geometry(format!(
                "ramp height must be positive, got {height}"
            )));
        }
        if !(flank_angle_deg > 0.0 && flank_angle_deg <= 90.0) {
            return Err(RoadError::Geometry(format!(
                "flank angle must be in (0, 90] deg, got {flank_angle_deg}"
            )));
        }
        let run = if flank_angle_deg == 90.0 {
            0.0
        } else {
            height / flank_angle_deg.to_radians().tan()
        };
        let top = match at {
            LengthAt::Base => length - 2.0 * run,
            LengthAt::Top => length,
        };
        if top.is_nan() || top < 0.0 || length.is_nan() || length <= 0.0 {
            return Err(RoadError::Geometry(format!(
                "length {length} m measured at the {} leaves no plateau with {run:.4} m flanks",
                if at == LengthAt::Base { "base" } else { "top" }
            )));
        }
        let x = [
            start,
            start + run,
            start + run + top,
            start + 2.0 * run + top,
        ];
        Ok(Obstacle {
            shape: Shape::Ramp { x, h: height },
            base,
            y_min: f64::NEG_INFINITY,
            y_max: f64::INFINITY,
        })
    }

    /// A circular-segment bump of `height` over `chord`, starting at `start`.
    pub fn bump(start: f64, height: f64, chord: f64, base: f64) -> Result<Obstacle, RoadError> {
        if !(height > 0.0 && chord > 0.0) {
            return Err(RoadError::Geometry(format!(
                "bump height and chord must be positive, got {height} and {chord}"
            )));
        }
        if height > chord / 2.0 {
            return Err(RoadError::Geometry(format!(
                "a circular segment cannot be higher ({height} m) than half its chord ({chord} m)"
            )));
        }
        // Sagitta relation: R = (c^2/4 + h^2) / (2 h).
        let radius = (chord * chord / 4.0 + height * height) / (2.0 * height);
        Ok(Obstacle {
            shape: Shape::Bump {
                x0: start,
                chord,
                h: height,
                radius,
            },
            base,
            y_min: f64::NEG_INFINITY,
            y_max: f64::INFINITY,
        })
    }

    /// A step of `height` (up if positive) at `start`.
    pub fn step(start: f64, height: f64, base: f64) -> Result<Obstacle, RoadError> {
        if !(height != 0.0 && height.is_finite()) {
            return Err(RoadError::Geometry(format!(
                "step height must be non-zero, got {height}"
            )));
        }
        Ok(Obstacle {
            shape: Shape::Step {
                x0: start,
                h: height,
            },
            base,
            y_min: f64::NEG_INFINITY,
            y_max: f64::INFINITY,
        })
    }

    /// Longitudinal extent [x_start, x_end)).
    pub fn x_range(&self) -> (f64, f64) {
        match self.shape {
            Shape::Ramp { x, .. } => (x[0], x[3]),
            Shape::Bump { x0, chord, .. } => (x0, x0 + chord),
            Shape::Step { x0, .. } => (x0, f64::INFINITY),
            Shape::Hump(ref m) => (m.x0, m.x0 + m.length),
        }
    }

    /// Largest height above the base road [m] (negative for a step down).
    pub fn rise(&self) -> f64 {
        match self.shape {
            Shape::Ramp { h, .. } | Shape::Bump { h, .. } | Shape::Step { h, .. } => h,
            Shape::Hump(ref m) => m.h,
        }
    }

    fn covers(&self, x: f64, y: f64) -> bool {
        let (a, b) = self.x_range();
        x >= a && x < b && y >= self.y_min && y <= self.y_max
    }

    /// Absolute height where the obstacle covers (x, y), else `None`.
    pub fn height(&self, x: f64, y: f64) -> Option<f64> {
        if !self.covers(x, y) {
            return None;
        }
        let dz = match self.shape {
            Shape::Ramp { x: p, h } => {
                if x < p[1] {
                    h * (x - p[0]) / (p[1] - p[0])
                } else if x < p[2] {
                    h
                } else {
                    h * (p[3] - x) / (p[3] - p[2])
                }
            }
            Shape::Bump {
                x0,
                chord,
                h,
                radius,
            } => {
                let u = x - (x0 + chord / 2.0);
                (radius * radius - u * u).max(0.0).sqrt() - (radius - h)
            }
            Shape::Step { h, .. } => h,
            Shape::Hump(ref m) => m.at(x).0,
        };
        Some(self.base + dz)
    }

    /// Gradient where the obstacle covers (x, y) (zero elsewhere).
    pub fn slope(&self, x: f64, y: f64) -> (f64, f64) {
        if !self.covers(x, y) {
            return (0.0, 0.0);
        }
        let dzdx = match self.shape {
            Shape::Ramp { x: p, h } => {
                if x < p[1] {
                    h / (p[1] - p[0])
                } else if x < p[2] {
                    0.0
                } else {
                    -h / (p[3] - p[2])
                }
            }
            Shape::Bump {
                x0, chord, radius, ..
            } => {
                let u = x - (x0 + chord / 2.0);
                -u / (radius * radius - u * u).max(1e-300).sqrt()
            }
            Shape::Step { .. } => 0.0,
            Shape::Hump(ref m) => m.at(x).1,
        };
        (dzdx, 0.0)
    }

    /// True when the obstacle reaches into the rectangle (closed on both ends, so a
    /// rectangle that merely touches an edge is not flat).
    pub fn overlaps(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> bool {
        let (a, b) = self.x_range();
        x1 >= a && x0 <= b && y1 >= self.y_min && y0 <= self.y_max
    }

    /// Kinks and jumps along the line p + s d (see `Road::kinks_along`).
    pub fn kinks_along(&self, p: [f64; 2], d: [f64; 2], s0: f64, s1: f64, out: &mut Vec<f64>) {
        match self.shape {
            Shape::Ramp { x, .. } => {
                for xk in x {
                    push_x_crossing(p, d, xk, s0, s1, out);
                }
            }
            Shape::Bump { x0, chord, .. } => {
                push_x_crossing(p, d, x0, s0, s1, out);
                push_x_crossing(p, d, x0 + chord, s0, s1, out);
            }
            Shape::Step { x0, .. } => push_x_crossing(p, d, x0, s0, s1, out),
            Shape::Hump(ref m) => {
                for xk in m.kinks() {
                    push_x_crossing(p, d, xk, s0, s1, out);
                }
            }
        }
        for yk in [self.y_min, self.y_max] {
            if yk.is_finite() {
                push_y_crossing(p, d, yk, s0, s1, out);
            }
        }
    }

    /// A pothole: a ramp `depth` deep (a trapezoid turned down), `length` at the rim.
    pub fn pothole(
        start: f64,
        depth: f64,
        length: f64,
        flank_angle_deg: f64,
        base: f64,
    ) -> Result<Obstacle, RoadError> {
        let mut o = Obstacle::ramp(start, depth, length, LengthAt::Base, flank_angle_deg, base)
            .map_err(|e| {
                RoadError::Geometry(e.to_string().replace("ramp height", "pothole depth"))
            })?;
        if let Shape::Ramp { h, .. } = &mut o.shape {
            *h = -*h;
        }
        Ok(o)
    }

    /// " on the left/right half" for a one-sided obstacle, else "".
    fn side(&self) -> String {
        match (self.y_min.is_finite(), self.y_max.is_finite()) {
            (false, false) => String::new(),
            _ => format!(", y {}..{} m", self.y_min, self.y_max),
        }
    }

    /// A short description for logs and reports.
    pub fn describe(&self) -> String {
        match self.shape {
            Shape::Ramp { x, h } if h < 0.0 => format!(
                "pothole {:.0} mm deep, rim {:.3}..{:.3} m, bottom {:.3}..{:.3} m{}",
                -h * 1e3,
                x[0],
                x[3],
                x[1],
                x[2],
                self.side()
            ),
            Shape::Ramp { x, h } => format!(
                "ramp {:.0} mm high, base {:.3}..{:.3} m, plateau {:.3}..{:.3} m",
                h * 1e3,
                x[0],
                x[3],
                x[1],
                x[2]
            ),
            Shape::Bump { x0, chord, h, .. } => format!(
                "circular bump {:.0} mm high over {:.3}..{:.3} m",
                h * 1e3,
                x0,
                x0 + chord
            ),
            Shape::Step { x0, h } => format!("step of {:+.0} mm at {x0:.3} m", h * 1e3),
            Shape::Hump(ref m) => format!("{}{}", m.describe(), self.side()),
        }
    }
}

/// Which half of the road a one-sided obstacle covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Track {
    /// y >= 0.
    Left,
    /// y <= 0.
    Right,
}

/// One `[[obstacle]]` table of a road file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
pub(crate) enum ObstacleToml {
    Ramp {
        start_m: f64,
        height_m: f64,
        length_m: f64,
        length_measured_at: LengthAt,
        flank_angle_deg: f64,
        #[serde(default)]
        y_min_m: Option<f64>,
        #[serde(default)]
        y_max_m: Option<f64>,
        #[serde(default)]
        track: Option<Track>,
    },
    Bump {
        start_m: f64,
        height_m: f64,
        chord_m: f64,
        #[serde(default)]
        y_min_m: Option<f64>,
        #[serde(default)]
        y_max_m: Option<f64>,
        #[serde(default)]
        track: Option<Track>,
    },
    Hump {
        start_m: f64,
        height_m: f64,
        length_m: f64,
        shape: f64,
        flank_angle_deg: f64,
        #[serde(default)]
        y_min_m: Option<f64>,
        #[serde(default)]
        y_max_m: Option<f64>,
        #[serde(default)]
        track: Option<Track>,
    },
    Step {
        start_m: f64,
        height_m: f64,
        #[serde(default)]
        y_min_m: Option<f64>,
        #[serde(default)]
        y_max_m: Option<f64>,
        #[serde(default)]
        track: Option<Track>,
    },
    Pothole {
        start_m: f64,
        depth_m: f64,
        length_m: f64,
        flank_angle_deg: f64,
        #[serde(default)]
        y_min_m: Option<f64>,
        #[serde(default)]
        y_max_m: Option<f64>,
        #[serde(default)]
        track: Option<Track>,
    },
}

impl ObstacleToml {
    /// Checks and builds obstacle number `i` of the file.
    pub(crate) fn build(&self, src: &Source, i: usize, base: f64) -> Result<Obstacle, InputError> {
        let at = |k: &str| path!["obstacle", i, k];
        // A ramp's or a pothole's flank: steeper than flat, at most vertical.
        let flank = |deg: f64| {
            if deg > 0.0 && deg <= 90.0 {
                Ok(())
            } else {
                Err(src.error(
                    &at("flank_angle_deg"),
                    format!("must be in (0, 90], got {deg}"),
                ))
            }
        };
        let (mut o, y_min, y_max, track) = match self {
            ObstacleToml::Ramp {
                start_m,
                height_m,
                length_m,
                length_measured_at,
                flank_angle_deg,
                y_min_m,
                y_max_m,
                track,
            } => {
                src.finite(&at("start_m"), *start_m)?;
                src.positive(&at("height_m"), *height_m)?;
                src.positive(&at("length_m"), *length_m)?;
                flank(*flank_angle_deg)?;
                let o = Obstacle::ramp(
                    *start_m,
                    *height_m,
                    *length_m,
                    *length_measured_at,
                    *flank_angle_deg,
                    base,
                )
                .map_err(|m| src.error(&at("length_m"), m.to_string()))?;
                (o, y_min_m, y_max_m, track)
            }
            ObstacleToml::Bump {
                start_m,
                height_m,
                chord_m,
                y_min_m,
                y_max_m,
                track,
            } => {
                src.finite(&at("start_m"), *start_m)?;
                src.positive(&at("height_m"), *height_m)?;
                src.positive(&at("chord_m"), *chord_m)?;
                let o = Obstacle::bump(*start_m, *height_m, *chord_m, base)
                    .map_err(|m| src.error(&at("height_m"), m.to_string()))?;
                (o, y_min_m, y_max_m, track)
            }
            ObstacleToml::Hump {
                start_m,
                height_m,
                length_m,
                shape,
                flank_angle_deg,
                y_min_m,
                y_max_m,
                track,
            } => {
                src.finite(&at("start_m"), *start_m)?;
                src.positive(&at("height_m"), *height_m)?;
                src.positive(&at("length_m"), *length_m)?;
                flank(*flank_angle_deg)?;
                if !(0.0..=1.0).contains(shape) {
                    return Err(src.error(
                        &at("shape"),
                        format!("must be in [0, 1] (0 round-top, 1 flat-top), got {shape}"),
                    ));
                }
                let m = Hump::new(*start_m, *height_m, *length_m, *shape, *flank_angle_deg)
                    .map_err(|m| src.error(&at("height_m"), m.to_string()))?;
                let o = Obstacle {
                    shape: Shape::Hump(m),
                    base,
                    y_min: f64::NEG_INFINITY,
                    y_max: f64::INFINITY,
                };
                (o, y_min_m, y_max_m, track)
            }
            ObstacleToml::Step {
                start_m,
                height_m,
                y_min_m,
                y_max_m,
                track,
            } => {
                src.finite(&at("start_m"), *start_m)?;
                let o = Obstacle::step(*start_m, *height_m, base)
                    .map_err(|m| src.error(&at("height_m"), m.to_string()))?;
                (o, y_min_m, y_max_m, track)
            }
            ObstacleToml::Pothole {
                start_m,
                depth_m,
                length_m,
                flank_angle_deg,
                y_min_m,
                y_max_m,
                track,
            } => {
                src.finite(&at("start_m"), *start_m)?;
                src.positive(&at("depth_m"), *depth_m)?;
                src.positive(&at("length_m"), *length_m)?;
                flank(*flank_angle_deg)?;
                let o = Obstacle::pothole(*start_m, *depth_m, *length_m, *flank_angle_deg, base)
                    .map_err(|m| src.error(&at("length_m"), m.to_string()))?;
                (o, y_min_m, y_max_m, track)
            }
        };
        if let Some(t) = track {
            if y_min.is_some() || y_max.is_some() {
                return Err(src.error(
                    &at("track"),
                    "give either `track` or `y_min_m` / `y_max_m`, not both",
                ));
            }
            match t {
                Track::Left => o.y_min = 0.0,
                Track::Right => o.y_max = 0.0,
            }
        }
        if let Some(y) = y_min {
            o.y_min = src.finite(&at("y_min_m"), *y)?;
        }
        if let Some(y) = y_max {
            o.y_max = src.finite(&at("y_max_m"), *y)?;
        }
        if o.y_min >= o.y_max || o.y_min.is_nan() || o.y_max.is_nan() {
            return Err(src.error(&at("y_max_m"), "must be above y_min_m"));
        }
        Ok(o)
    }
}

/// True when two obstacles share ground (heights would be ambiguous).
pub(crate) fn overlap(a: &Obstacle, b: &Obstacle) -> bool {
    let (a0, a1) = a.x_range();
    let (b0, b1) = b.x_range();
    a0 < b1 && b0 < a1 && a.y_min < b.y_max && b.y_min < a.y_max
}

/// Refuses overlapping obstacles.
pub(crate) fn check_overlaps(src: &Source, obs: &[Obstacle]) -> Result<(), InputError> {
    for i in 0..obs.len() {
        for j in 0..i {
            if overlap(&obs[i], &obs[j]) {
                return Err(src.error(
                    &path!["obstacle", i, "start_m"],
                    format!("obstacle {i} overlaps obstacle {j}"),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_ramp_corners() {
        let r = Obstacle::ramp(1.0, 0.05, 0.5, LengthAt::Base, 45.0, 0.0).unwrap();
        let Shape::Ramp { x, .. } = r.shape else {
            unreachable!()
        };
        let want = [1.0, 1.05, 1.45, 1.5];
        for k in 0..4 {
            assert!((x[k] - want[k]).abs() < 1e-12, "{x:?}");
        }
        assert!((r.height(1.025, 0.0).unwrap() - 0.025).abs() < 1e-12);
        assert_eq!(r.height(1.2, 0.0), Some(0.05));
        let top = Obstacle::ramp(1.0, 0.05, 0.5, LengthAt::Top, 45.0, 0.0).unwrap();
        assert!((top.x_range().1 - 1.6).abs() < 1e-12);
    }

    #[test]
    fn bump_is_a_circular_segment() {
        let b = Obstacle::bump(0.0, 0.05, 0.5, 0.0).unwrap();
        assert!((b.height(0.25, 0.0).unwrap() - 0.05).abs() < 1e-12);
        assert!(b.height(0.0, 0.0).unwrap().abs() < 1e-12);
        // Points on the circle: (x - 0.25)^2 + (z + R - h)^2 = R^2.
        let Shape::Bump { radius, .. } = b.shape else {
            unreachable!()
        };
        let z = b.height(0.1, 0.0).unwrap();
        let lhs = (0.1f64 - 0.25).powi(2) + (z + radius - 0.05).powi(2);
        assert!((lhs - radius * radius).abs() < 1e-12);
    }
}
