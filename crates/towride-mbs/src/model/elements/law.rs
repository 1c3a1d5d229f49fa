//! Force laws and one-sided stops, shared by the force elements, with their one set of
//! checks: mechanism files, vehicle property files and Rust callers all go through
//! [`LawSpec::check`], [`StopSpec::check`] and [`JointBushing::check`].

use serde::Deserialize;

use super::FieldError;
use crate::model::dual::Scalar;
use crate::model::function::Spline;

/// Force law of one direction: linear, a tabulated (spline) curve, or two slopes.
#[derive(Clone, Debug)]
pub enum Law {
    /// Force = k x.
    Linear(f64),
    /// Force = spline(x) (natural cubic through the table).
    Curve(Spline),
    /// Linear beyond a play: F = k [sp(x - g) - sp(-x - g)] with the softplus
    /// sp(u) = w ln(1 + e^(u/w)), a smooth dead band of half-width g (the play) whose
    /// corners are rounded over about w; as w -> 0 it is 0 inside |x| < g and
    /// k (|x| - g) sign(x) outside. F(0) = 0 and F is odd, C-infinity and monotone.
    DeadBand {
        /// Stiffness beyond the play [N/m].
        k: f64,
        /// Half-width of the dead band [m].
        play: f64,
        /// Rounding width of its corners [m].
        width: f64,
    },
    /// Regularised Coulomb friction on a rate: F = T tanh(x / r), T the friction force or
    /// torque and r the rate over which it changes sign.
    Friction {
        /// Friction force or torque [N or N m].
        t: f64,
        /// Release rate [m/s or rad/s].
        r: f64,
    },
    /// Slope `above` for x > 0, `below` for x < 0, joined smoothly over `width`
    /// ([`two_slopes`]): a damper's rebound and compression rates.
    TwoSlopes {
        /// Slope for x < 0 (a damper's compression rate) [N s/m].
        below: f64,
        /// Slope for x > 0 (rebound) [N s/m].
        above: f64,
        /// Width of the transition [m/s].
        width: f64,
    },
}

/// Softplus w ln(1 + e^(u/w)) with its first and second derivatives, without overflow.
fn softplus(u: f64, w: f64) -> (f64, f64, f64) {
    let z = u / w;
    let s = if z >= 0.0 {
        1.0 / (1.0 + (-z).exp())
    } else {
        let e = z.exp();
        e / (1.0 + e)
    };
    (
        u.max(0.0) + w * (-z.abs()).exp().ln_1p(),
        s,
        s * (1.0 - s) / w,
    )
}

/// (value, slope, curvature) of f(x) = x (m + d tanh(x / w)), m and d the mean and half
/// the difference of the slopes: f'(x) tends to `above` for x >> w and to `below` for
/// x << -w (the gap falls as exp(-2|x|/w)), f(0) = 0, and f is smooth at 0 (slope m
/// there), so an implicit solver meets no kink when a damper changes direction. The tanh
/// regularisation of a sign switch is the usual one for piecewise dampers (e.g. the
/// smooth Coulomb friction models compared by Pennestri et al., "Review and comparison of
/// dry friction force models", Nonlinear Dynamics 83, 2016).
pub fn two_slopes(below: f64, above: f64, width: f64, x: f64) -> (f64, f64, f64) {
    let (m, d) = (0.5 * (above + below), 0.5 * (above - below));
    let u = x / width;
    let t = u.tanh();
    let sech2 = 1.0 - t * t;
    (
        x * (m + d * t),
        m + d * (t + u * sech2),
        2.0 * d / width * sech2 * (1.0 - u * t),
    )
}

impl Law {
    /// (value, slope, curvature) at x.
    pub fn eval(&self, x: f64) -> (f64, f64, f64) {
        match self {
            Law::Linear(k) => (k * x, *k, 0.0),
            Law::Curve(s) => s.eval(x),
            Law::DeadBand { k, play, width } => {
                let (a, da, dda) = softplus(x - play, *width);
                let (b, db, ddb) = softplus(-x - play, *width);
                (k * (a - b), k * (da + db), k * (dda - ddb))
            }
            Law::Friction { t, r } => {
                let th = (x / r).tanh();
                let sech2 = 1.0 - th * th;
                (t * th, t / r * sech2, -2.0 * t / (r * r) * th * sech2)
            }
            Law::TwoSlopes {
                below,
                above,
                width,
            } => two_slopes(*below, *above, *width, x),
        }
    }

    /// Slope at zero (for frequency estimates).
    pub fn stiffness(&self) -> f64 {
        self.eval(0.0).1
    }

    /// The law at a generic scalar (derivatives carried by the chain rule).
    pub fn at<S: Scalar>(&self, x: S) -> S {
        match self {
            Law::Linear(k) => x * *k,
            _ => {
                let (f, df, d2f) = self.eval(x.re());
                x.chain(f, df, d2f)
            }
        }
    }
}

/// A law as written in a file: a number (the linear coefficient) or a table.
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum LawSpec {
    /// Linear coefficient (non-negative).
    Linear(f64),
    /// Table of x and y (strictly increasing x).
    Table {
        /// Deflection or rate.
        x: Vec<f64>,
        /// Force or torque.
        y: Vec<f64>,
    },
    /// A stiffness beyond a play, corners rounded ([`Law::DeadBand`]).
    DeadBand {
        /// Stiffness beyond the play [N/m].
        stiffness_n_m: f64,
        /// Half-width of the dead band [m].
        play_m: f64,
        /// Rounding width of its corners [m].
        smoothing_m: f64,
    },
    /// Regularised friction on a rotation rate ([`Law::Friction`]).
    Friction {
        /// Friction torque [N m].
        friction_torque_n_m: f64,
        /// Rate over which it changes sign [rad/s].
        release_rad_s: f64,
    },
}

impl LawSpec {
    /// The law, checked: a linear coefficient is finite and not negative (a negative
    /// stiffness or damping feeds energy in); a table makes a spline.
    pub fn check(&self) -> Result<Law, FieldError> {
        match self {
            LawSpec::Linear(k) => non_negative(*k).map(Law::Linear).map_err(FieldError::here),
            LawSpec::Table { x, y } => Spline::new(x, y).map(Law::Curve),
            LawSpec::DeadBand {
                stiffness_n_m,
                play_m,
                smoothing_m,
            } => Ok(Law::DeadBand {
                k: non_negative(*stiffness_n_m).map_err(|m| FieldError::at("stiffness_n_m", m))?,
                play: non_negative(*play_m).map_err(|m| FieldError::at("play_m", m))?,
                width: positive(*smoothing_m).map_err(|m| FieldError::at("smoothing_m", m))?,
            }),
            LawSpec::Friction {
                friction_torque_n_m,
                release_rad_s,
            } => Ok(Law::Friction {
                t: non_negative(*friction_torque_n_m)
                    .map_err(|m| FieldError::at("friction_torque_n_m", m))?,
                r: positive(*release_rad_s).map_err(|m| FieldError::at("release_rad_s", m))?,
            }),
        }
    }
}

/// A one-sided stop engaged beyond a clearance: F = k pen^e + c pen' (for pen > 0), the
/// damping blended in over `damping_depth` so the force starts from zero.
#[derive(Clone, Debug)]
pub struct Stop {
    /// Free travel before the stop engages [m] (>= 0).
    pub clearance: f64,
    /// Stiffness coefficient [N/m^e].
    pub stiffness: f64,
    /// Exponent e >= 1.
    pub exponent: f64,
    /// Damping [N s/m].
    pub damping: f64,
    /// Penetration over which the damping blends in [m].
    pub damping_depth: f64,
}

impl Stop {
    /// Force of the stop for penetration `pen` with rate `pen_rate`.
    pub fn force<S: Scalar>(&self, pen: S, pen_rate: S) -> S {
        if pen.re() <= 0.0 {
            return S::cst(0.0);
        }
        // pen^e = exp(e ln pen) written through chain to stay generic.
        let p = pen.re();
        let e = self.exponent;
        let elastic = pen.chain(
            p.powf(e),
            e * p.powf(e - 1.0),
            e * (e - 1.0) * p.powf(e - 2.0),
        );
        let ramp = if self.damping_depth > 0.0 && p < self.damping_depth {
            let s = p / self.damping_depth;
            let h = self.damping_depth;
            pen.chain(
                s * s * (3.0 - 2.0 * s),
                6.0 * s * (1.0 - s) / h,
                (6.0 - 12.0 * s) / (h * h),
            )
        } else {
            S::cst(1.0)
        };
        elastic * self.stiffness + ramp * pen_rate * self.damping
    }
}

/// A stop as written in a file.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct StopSpec {
    /// Free travel before the stop engages [m].
    pub clearance_m: f64,
    /// Stiffness coefficient [N/m^e].
    pub stiffness_n_m: f64,
    /// Exponent of the penetration (default 1).
    #[serde(default = "one")]
    pub exponent: f64,
    /// Damping [N s/m].
    #[serde(default)]
    pub damping_n_s_m: f64,
    /// Penetration over which the damping blends in [m].
    #[serde(default)]
    pub damping_depth_m: f64,
}

fn one() -> f64 {
    1.0
}

impl StopSpec {
    /// The stop, checked. A clearance of zero is allowed: the stop then engages at the
    /// reference length, and its force still starts from zero (exponent >= 1, damping
    /// blended in), so it is a one-sided spring, not a jump; a negative clearance would
    /// start preloaded and is refused.
    pub fn check(&self) -> Result<Stop, FieldError> {
        let exponent = finite(self.exponent).map_err(|m| FieldError::at("exponent", m))?;
        if exponent < 1.0 {
            return Err(FieldError::at(
                "exponent",
                "must be at least 1 (a force that starts from zero)",
            ));
        }
        Ok(Stop {
            clearance: non_negative(self.clearance_m)
                .map_err(|m| FieldError::at("clearance_m", m))?,
            stiffness: positive(self.stiffness_n_m)
                .map_err(|m| FieldError::at("stiffness_n_m", m))?,
            exponent,
            damping: non_negative(self.damping_n_s_m)
                .map_err(|m| FieldError::at("damping_n_s_m", m))?,
            damping_depth: non_negative(self.damping_depth_m)
                .map_err(|m| FieldError::at("damping_depth_m", m))?,
        })
    }
}

/// The bushing that replaces an ideal joint: stiff, lightly damped, acting only in the
/// directions the joint locks.
#[derive(Deserialize, Debug, Clone, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JointBushing {
    /// Translational stiffness [N/m].
    pub stiffness_n_m: f64,
    /// Translational damping [N s/m].
    pub damping_n_s_m: f64,
    /// Rotational stiffness [N m/rad].
    pub stiffness_n_m_rad: f64,
    /// Rotational damping [N m s/rad].
    pub damping_n_m_s_rad: f64,
}

impl JointBushing {
    /// Stiffnesses positive, dampings not negative.
    pub fn check(&self) -> Result<(), FieldError> {
        positive(self.stiffness_n_m).map_err(|m| FieldError::at("stiffness_n_m", m))?;
        positive(self.stiffness_n_m_rad).map_err(|m| FieldError::at("stiffness_n_m_rad", m))?;
        non_negative(self.damping_n_s_m).map_err(|m| FieldError::at("damping_n_s_m", m))?;
        non_negative(self.damping_n_m_s_rad).map_err(|m| FieldError::at("damping_n_m_s_rad", m))?;
        Ok(())
    }
}

/// `v` if finite.
pub(crate) fn finite(v: f64) -> Result<f64, String> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("must be a finite number, got {v}"))
    }
}

/// `v` if finite and > 0.
pub(crate) fn positive(v: f64) -> Result<f64, String> {
    finite(v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("must be positive, got {v}"))
    }
}

/// `v` if finite and >= 0.
pub(crate) fn non_negative(v: f64) -> Result<f64, String> {
    finite(v)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("must not be negative, got {v}"))
    }
}
