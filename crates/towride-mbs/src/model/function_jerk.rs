//! A jerk-limited change of a value (a speed, as a driver or a brake system changes it):
//! the rate rises at a constant jerk to its limit, holds, and falls at the same jerk so
//! the value lands on its target with zero rate. The rate is continuous (piecewise
//! linear), the value C1; a change too small to reach the rate limit makes a triangle.
//!
//! Braking is the use it is made for: a brake system builds its deceleration over a
//! response time rather than at once (UN R13-H, annex 3, measures it from the pedal to
//! the full deceleration), and a car that stops does so with a jerk, not a jump.

use crate::input::FieldError;

/// The shape: from `from` at `start_s` to `to`, at most `rate` in magnitude, the rate
/// changing at `jerk`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JerkLimited {
    start_s: f64,
    from: f64,
    /// Sign of the change, +1 or -1.
    sign: f64,
    /// Rate magnitude reached (the limit, or less for a triangle).
    peak: f64,
    jerk: f64,
    /// Time to build the rate [s].
    build_s: f64,
    /// Time at the peak rate [s].
    hold_s: f64,
}

impl JerkLimited {
    /// The shape; `rate` and `jerk` positive and finite, the others finite.
    pub fn new(start_s: f64, from: f64, to: f64, rate: f64, jerk: f64) -> Result<Self, FieldError> {
        for (x, w) in [(start_s, "start_s"), (from, "from"), (to, "to")] {
            if !x.is_finite() {
                return Err(FieldError::at(w, format!("{w} must be finite")));
            }
        }
        for (x, w) in [(rate, "rate"), (jerk, "jerk")] {
            if !(x.is_finite() && x > 0.0) {
                return Err(FieldError::at(w, format!("{w} must be positive")));
            }
        }
        let change = (to - from).abs();
        // The two ramps of the rate change the value by peak^2 / jerk together.
        let (peak, hold_s) = if change >= rate * rate / jerk {
            (rate, change / rate - rate / jerk)
        } else {
            ((change * jerk).sqrt(), 0.0)
        };
        Ok(JerkLimited {
            start_s,
            from,
            sign: if to >= from { 1.0 } else { -1.0 },
            peak,
            jerk,
            build_s: peak / jerk,
            hold_s,
        })
    }

    /// When the value reaches its target [s].
    pub fn end_s(&self) -> f64 {
        self.start_s + 2.0 * self.build_s + self.hold_s
    }

    /// (value, rate, jerk) at t, unsigned, measured from `from`, and the integral of
    /// the unsigned change from `start_s` to t.
    fn unsigned(&self, t: f64) -> (f64, f64, f64, f64) {
        let (a, j, tau, th) = (self.peak, self.jerk, self.build_s, self.hold_s);
        let u = t - self.start_s;
        if u <= 0.0 || a == 0.0 {
            return (0.0, 0.0, 0.0, 0.0);
        }
        // Value and integral at the ends of the first two phases.
        let (v1, i1) = (0.5 * a * tau, j * tau.powi(3) / 6.0);
        let (v2, i2) = (v1 + a * th, i1 + v1 * th + 0.5 * a * th * th);
        if u <= tau {
            return (0.5 * j * u * u, j * u, j, j * u.powi(3) / 6.0);
        }
        let u = u - tau;
        if u <= th {
            return (v1 + a * u, a, 0.0, i1 + v1 * u + 0.5 * a * u * u);
        }
        let u = u - th;
        if u <= tau {
            let v = v2 + a * u - 0.5 * j * u * u;
            let i = i2 + v2 * u + 0.5 * a * u * u - j * u.powi(3) / 6.0;
            return (v, a - j * u, -j, i);
        }
        let v3 = v2 + a * tau - 0.5 * j * tau * tau;
        let i3 = i2 + v2 * tau + 0.5 * a * tau * tau - j * tau.powi(3) / 6.0;
        (v3, 0.0, 0.0, i3 + v3 * (u - tau))
    }

    /// (f, f', f'') at t.
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        let (v, r, j, _) = self.unsigned(t);
        let s = self.sign;
        (self.from + s * v, s * r, s * j)
    }

    /// The integral of f from 0 to t.
    pub fn integral(&self, t: f64) -> f64 {
        let part = |x: f64| self.from * x + self.sign * self.unsigned(x).3;
        part(t) - part(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn braking_to_rest_lands_on_the_target_with_the_asked_rate() {
        // 50 km/h to rest at 5 m/s^2, the rate built in 0.2 s.
        let v0 = 50.0 / 3.6;
        let f = JerkLimited::new(0.5, v0, 0.0, 5.0, 25.0).unwrap();
        // Constant deceleration would take v0 / 5 s; the jerk ramps add 0.2 s in all.
        assert!((f.end_s() - (0.5 + v0 / 5.0 + 0.2)).abs() < 1e-12);
        assert_eq!(f.eval(0.4), (v0, 0.0, 0.0));
        assert!((f.eval(1.5).1 + 5.0).abs() < 1e-12);
        let e = f.eval(f.end_s() + 1e-9);
        assert!(e.0.abs() < 1e-9 && e.1 == 0.0);
        // The rate is continuous: no jump at any phase boundary.
        for t in [0.5, 0.7, f.end_s() - 0.2, f.end_s()] {
            let (a, b) = (f.eval(t - 1e-9).1, f.eval(t + 1e-9).1);
            assert!((a - b).abs() < 1e-6, "rate jumps at {t}: {a} -> {b}");
        }
    }

    #[test]
    fn a_small_change_makes_a_triangle_and_integrals_match_quadrature() {
        let f = JerkLimited::new(0.1, 2.0, 2.3, 5.0, 25.0).unwrap();
        // 0.3 < 5^2 / 25 = 1: the rate peaks at sqrt(0.3 * 25) below the limit.
        assert!((f.eval(f.start_s + f.build_s).1 - (7.5f64).sqrt()).abs() < 1e-12);
        assert!((f.eval(5.0).0 - 2.3).abs() < 1e-12);
        for g in [f, JerkLimited::new(0.2, 13.9, 0.0, 5.0, 25.0).unwrap()] {
            let t = 4.0;
            let n = 40000;
            let h = t / n as f64;
            let quad: f64 = (0..n).map(|k| g.eval((k as f64 + 0.5) * h).0 * h).sum();
            assert!(
                (quad - g.integral(t)).abs() < 1e-6,
                "{quad} vs {}",
                g.integral(t)
            );
        }
    }
}
