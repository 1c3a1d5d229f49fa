//! A speed hump whose shape is a continuous value: `shape` blends the round-top
//! (circular-segment) hump into the flat-top (trapezoidal) hump of the same height and
//! length,
//!
//! ```text
//! z(x) = (1 - s) z_circle(x) + s z_trapezoid(x),   0 <= s <= 1
//! ```
//!
//! Both ends are the two profiles road authorities build: the round-top hump is a
//! circular segment (the TRRL "Watts" profile, 3.7 m long and up to 100 mm high; TRL
//! report TRL377, Webster & Layfield 1998), the flat-top hump a plateau reached by
//! straight ramps (TRL report TRL186: ramp gradients 1:10 to 1:15; the "Seminole" flat-top
//! hump of the ITE's "Towards a North American geometric design standard for speed humps").
//! The trapezoid's flanks are set by their angle, as the `ramp`'s; `length_m` is
//! the chord of the circle and the trapezoid's foot-to-foot base.
//!
//! Why a blend and not a cosine in between: between its kinks (the feet and the plateau's
//! edges) the blend is a concave arc plus a line, so concave, which the tyre's enveloping
//! model needs (`docs/road_tyre.md`); a cosine hump is convex near its feet. The height,
//! its slope and the area are linear in `s`, so they move continuously with it (a
//! least-squares fit can vary it), and continuously with the height, the length and the
//! flank angle.

use super::RoadError;

/// A blended hump over [x0, x0 + length].
#[derive(Clone, Debug, PartialEq)]
pub struct Hump {
    /// Start of the chord [m].
    pub x0: f64,
    /// Chord, foot to foot [m].
    pub length: f64,
    /// Height at the middle [m].
    pub h: f64,
    /// 0: circular segment, 1: trapezoid.
    pub shape: f64,
    /// The trapezoid's flank run h / tan(angle) [m].
    pub run: f64,
    /// The circle's radius (sagitta relation) [m].
    pub radius: f64,
}

impl Hump {
    /// A hump of `height` over `length` from `start`; `shape` in [0, 1], the trapezoid's
    /// flanks at `flank_angle_deg` in (0, 90].
    pub fn new(
        start: f64,
        height: f64,
        length: f64,
        shape: f64,
        flank_angle_deg: f64,
    ) -> Result<Hump, RoadError> {
        let bad = |m: String| Err(RoadError::Geometry(m));
        if !(height > 0.0 && length > 0.0) {
            return bad(format!(
                "hump height and length must be positive, got {height} and {length}"
            ));
        }
        if height > length / 2.0 {
            return bad(format!(
                "a circular segment cannot be higher ({height} m) than half its chord ({length} m)"
            ));
        }
        if !(0.0..=1.0).contains(&shape) {
            return bad(format!(
                "shape must be in [0, 1] (0 round-top, 1 flat-top), got {shape}"
            ));
        }
        if !(flank_angle_deg > 0.0 && flank_angle_deg <= 90.0) {
            return bad(format!(
                "flank angle must be in (0, 90] deg, got {flank_angle_deg}"
            ));
        }
        let run = if flank_angle_deg == 90.0 {
            0.0
        } else {
            height / flank_angle_deg.to_radians().tan()
        };
        if 2.0 * run > length {
            return bad(format!(
                "{flank_angle_deg} deg flanks ({run:.4} m each) are longer than half of {length} m: no plateau"
            ));
        }
        // Sagitta relation: R = (c^2/4 + h^2) / (2 h).
        let radius = (length * length / 4.0 + height * height) / (2.0 * height);
        Ok(Hump {
            x0: start,
            length,
            h: height,
            shape,
            run,
            radius,
        })
    }

    /// The places where the slope jumps: feet and plateau edges.
    pub fn kinks(&self) -> [f64; 4] {
        let x = self.x0;
        [x, x + self.run, x + self.length - self.run, x + self.length]
    }

    fn circle(&self, u: f64) -> (f64, f64) {
        let c = u - self.length / 2.0;
        let root = (self.radius * self.radius - c * c).max(0.0).sqrt();
        (root - (self.radius - self.h), -c / root.max(1e-150))
    }

    fn trapezoid(&self, u: f64) -> (f64, f64) {
        let (f, l, h) = (self.run, self.length, self.h);
        if u < f {
            (h * u / f, h / f)
        } else if u < l - f {
            (h, 0.0)
        } else {
            (h * (l - u) / f, -h / f)
        }
    }

    /// (height above the base, dz/dx) at `x` inside [x0, x0 + length).
    pub fn at(&self, x: f64) -> (f64, f64) {
        let u = x - self.x0;
        let (zc, sc) = self.circle(u);
        let (zt, st) = self.trapezoid(u);
        let s = self.shape;
        ((1.0 - s) * zc + s * zt, (1.0 - s) * sc + s * st)
    }

    /// Cross-section area above the base [m^2]: the segment's R^2 acos((R-h)/R) -
    /// (R-h) sqrt(2Rh - h^2) and the trapezoid's h (L - f), blended.
    pub fn area(&self) -> f64 {
        let (r, h) = (self.radius, self.h);
        let segment = r * r * ((r - h) / r).acos() - (r - h) * (2.0 * r * h - h * h).sqrt();
        let trapezoid = h * (self.length - self.run);
        (1.0 - self.shape) * segment + self.shape * trapezoid
    }

    /// A short description.
    pub fn describe(&self) -> String {
        let angle = if self.run == 0.0 {
            90.0
        } else {
            (self.h / self.run).atan().to_degrees()
        };
        format!(
            "hump {:.0} mm high over {:.3}..{:.3} m, shape {:.3} (0 round-top, 1 flat-top with {angle:.1} deg flanks)",
            self.h * 1e3,
            self.x0,
            self.x0 + self.length,
            self.shape
        )
    }
}
