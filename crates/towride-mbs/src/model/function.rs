//! Functions of time (applied loads, prescribed motions) and tabulated curves
//! (force-deflection, force-velocity), each with the derivatives the solver needs.

use crate::input::FieldError;
pub use crate::model::function_jerk::JerkLimited;
use serde::Deserialize;

/// A function of time, written in a mechanism file as an inline table, e.g.
/// `{ type = "harmonic", amplitude = 0.1, frequency_hz = 2.0 }`. Values carry the unit of
/// whatever they drive (N, N m, m, rad, m/s, rad/s).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum TimeFunction {
    /// f(t) = value.
    Constant {
        /// The constant value.
        value: f64,
    },
    /// f(t) = offset + slope (t - start_s) for t > start_s, offset before.
    Ramp {
        /// Value up to `start_s`.
        #[serde(default)]
        offset: f64,
        /// Slope after `start_s` [unit/s].
        slope_per_s: f64,
        /// Start of the ramp [s].
        #[serde(default)]
        start_s: f64,
    },
    /// The Adams STEP: a cubic blend from `from` at `t0_s` to `to` at `t1_s`, with zero
    /// slope at both ends.
    Step {
        /// Start of the blend [s].
        t0_s: f64,
        /// Value up to `t0_s`.
        from: f64,
        /// End of the blend [s], later than `t0_s`.
        t1_s: f64,
        /// Value from `t1_s` on.
        to: f64,
    },
    /// f(t) = offset + amplitude sin(2 pi frequency_hz t + phase_rad).
    Harmonic {
        /// Amplitude.
        amplitude: f64,
        /// Frequency [Hz].
        frequency_hz: f64,
        /// Phase at t = 0 [rad].
        #[serde(default)]
        phase_rad: f64,
        /// Mean value.
        #[serde(default)]
        offset: f64,
    },
    /// A jerk-limited change from `from` at `start_s` to `to`: the rate rises at `jerk`
    /// to `rate` (magnitudes), holds, and falls so the value lands with zero rate
    /// ([`JerkLimited`]); a speed target for braking or accelerating.
    JerkLimited {
        /// Start of the change [s].
        start_s: f64,
        /// Value up to `start_s`.
        from: f64,
        /// Value at the end.
        to: f64,
        /// Largest rate magnitude [unit/s].
        rate: f64,
        /// Rate of change of the rate [unit/s^2].
        jerk: f64,
    },
    /// A natural cubic spline through (time_s, value), held constant outside.
    Table {
        /// Sample times, ascending [s].
        time_s: Vec<f64>,
        /// Values at `time_s`.
        value: Vec<f64>,
    },
}

impl TimeFunction {
    /// Checks the parameters; the error names the offending field.
    pub fn check(&self) -> Result<(), FieldError> {
        let finite = |x: f64, what: &str| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(FieldError::at(what, format!("{what} must be finite")))
            }
        };
        match self {
            TimeFunction::Constant { value } => finite(*value, "value"),
            TimeFunction::Ramp {
                offset,
                slope_per_s,
                start_s,
            } => {
                finite(*offset, "offset")?;
                finite(*slope_per_s, "slope_per_s")?;
                finite(*start_s, "start_s")
            }
            TimeFunction::Step {
                t0_s,
                from,
                t1_s,
                to,
            } => {
                for (x, w) in [(t0_s, "t0_s"), (from, "from"), (t1_s, "t1_s"), (to, "to")] {
                    finite(*x, w)?;
                }
                if t1_s <= t0_s {
                    return Err(FieldError::at("t1_s", "t1_s must be later than t0_s"));
                }
                Ok(())
            }
            TimeFunction::Harmonic {
                amplitude,
                frequency_hz,
                phase_rad,
                offset,
            } => {
                for (x, w) in [
                    (amplitude, "amplitude"),
                    (frequency_hz, "frequency_hz"),
                    (phase_rad, "phase_rad"),
                    (offset, "offset"),
                ] {
                    finite(*x, w)?;
                }
                Ok(())
            }
            TimeFunction::JerkLimited { .. } => self.jerk_limited().map(|_| ()),
            TimeFunction::Table { time_s, value } => Spline::new(time_s, value).map(|_| ()),
        }
    }

    fn jerk_limited(&self) -> Result<JerkLimited, FieldError> {
        match *self {
            TimeFunction::JerkLimited {
                start_s,
                from,
                to,
                rate,
                jerk,
            } => JerkLimited::new(start_s, from, to, rate, jerk),
            _ => unreachable!("called on a jerk-limited function only"),
        }
    }

    /// (f, f', f'') at t.
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        match self {
            TimeFunction::Constant { value } => (*value, 0.0, 0.0),
            TimeFunction::Ramp {
                offset,
                slope_per_s,
                start_s,
            } => {
                if t > *start_s {
                    (offset + slope_per_s * (t - start_s), *slope_per_s, 0.0)
                } else {
                    (*offset, 0.0, 0.0)
                }
            }
            TimeFunction::Step {
                t0_s,
                from,
                t1_s,
                to,
            } => {
                let (s, ds, d2s) = step01(t, *t0_s, *t1_s);
                let a = to - from;
                (from + a * s, a * ds, a * d2s)
            }
            TimeFunction::Harmonic {
                amplitude,
                frequency_hz,
                phase_rad,
                offset,
            } => {
                let w = 2.0 * std::f64::consts::PI * frequency_hz;
                let arg = w * t + phase_rad;
                (
                    offset + amplitude * arg.sin(),
                    amplitude * w * arg.cos(),
                    -amplitude * w * w * arg.sin(),
                )
            }
            TimeFunction::JerkLimited { .. } => self.jerk_limited().expect("checked").eval(t),
            TimeFunction::Table { time_s, value } => {
                let s = Spline::new(time_s, value).expect("checked table");
                if t <= time_s[0] {
                    (value[0], 0.0, 0.0)
                } else if t >= *time_s.last().unwrap() {
                    (*value.last().unwrap(), 0.0, 0.0)
                } else {
                    s.eval(t)
                }
            }
        }
    }

    /// The integral of f from 0 to t (a prescribed velocity becomes a displacement).
    pub fn integral(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant { value } => value * t,
            TimeFunction::Ramp {
                offset,
                slope_per_s,
                start_s,
            } => {
                let ramp = |x: f64| (x - start_s).max(0.0).powi(2);
                offset * t + 0.5 * slope_per_s * (ramp(t) - ramp(0.0))
            }
            TimeFunction::Step {
                t0_s,
                from,
                t1_s,
                to,
            } => {
                let a = to - from;
                from * t + a * (step01_int(t, *t0_s, *t1_s) - step01_int(0.0, *t0_s, *t1_s))
            }
            TimeFunction::Harmonic {
                amplitude,
                frequency_hz,
                phase_rad,
                offset,
            } => {
                let w = 2.0 * std::f64::consts::PI * frequency_hz;
                if w == 0.0 {
                    return (offset + amplitude * phase_rad.sin()) * t;
                }
                offset * t + amplitude / w * (phase_rad.cos() - (w * t + phase_rad).cos())
            }
            TimeFunction::JerkLimited { .. } => self.jerk_limited().expect("checked").integral(t),
            TimeFunction::Table { time_s, value } => {
                let s = Spline::new(time_s, value).expect("checked table");
                let int_to = |x: f64| -> f64 {
                    // integral from time_s[0] to x, constant extension both sides
                    if x <= time_s[0] {
                        value[0] * (x - time_s[0])
                    } else if x >= *time_s.last().unwrap() {
                        s.integral(*time_s.last().unwrap())
                            + value.last().unwrap() * (x - time_s.last().unwrap())
                    } else {
                        s.integral(x)
                    }
                };
                int_to(t) - int_to(0.0)
            }
        }
    }
}

/// The Adams STEP shape from 0 to 1 over [a, b]: 3 s^2 - 2 s^3, with its derivatives.
fn step01(t: f64, a: f64, b: f64) -> (f64, f64, f64) {
    if t <= a {
        (0.0, 0.0, 0.0)
    } else if t >= b {
        (1.0, 0.0, 0.0)
    } else {
        let h = b - a;
        let s = (t - a) / h;
        (
            s * s * (3.0 - 2.0 * s),
            6.0 * s * (1.0 - s) / h,
            (6.0 - 12.0 * s) / (h * h),
        )
    }
}

/// Integral of step01 from a to t.
fn step01_int(t: f64, a: f64, b: f64) -> f64 {
    let h = b - a;
    if t <= a {
        0.0
    } else if t >= b {
        0.5 * h + (t - b)
    } else {
        let s = (t - a) / h;
        h * (s * s * s - 0.5 * s * s * s * s)
    }
}

/// A natural cubic spline (C2) through tabulated points, extended linearly with the end
/// slopes, so a curve never jumps and its derivative never explodes outside the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    x: Vec<f64>,
    y: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl Spline {
    /// Builds the spline; needs >= 2 strictly increasing, finite abscissae.
    pub fn new(x: &[f64], y: &[f64]) -> Result<Spline, FieldError> {
        if x.len() != y.len() {
            return Err(FieldError::here("the two columns differ in length"));
        }
        if x.len() < 2 {
            return Err(FieldError::here("a table needs at least two points"));
        }
        if x.iter().chain(y).any(|v| !v.is_finite()) {
            return Err(FieldError::here("table values must be finite"));
        }
        if x.windows(2).any(|w| w[1] <= w[0]) {
            return Err(FieldError::here("abscissae must increase strictly"));
        }
        let n = x.len();
        let mut m = vec![0.0; n];
        if n > 2 {
            // Tridiagonal system for the interior second derivatives (Thomas algorithm).
            let mut c = vec![0.0; n];
            let mut d = vec![0.0; n];
            for i in 1..n - 1 {
                let h0 = x[i] - x[i - 1];
                let h1 = x[i + 1] - x[i];
                let rhs = 6.0 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
                let diag = 2.0 * (h0 + h1) - h0 * c[i - 1];
                c[i] = h1 / diag;
                d[i] = (rhs - h0 * d[i - 1]) / diag;
            }
            for i in (1..n - 1).rev() {
                m[i] = d[i] - c[i] * m[i + 1];
            }
        }
        Ok(Spline {
            x: x.to_vec(),
            y: y.to_vec(),
            m,
        })
    }

    fn segment(&self, t: f64) -> usize {
        match self.x.partition_point(|&v| v <= t) {
            0 => 0,
            k => (k - 1).min(self.x.len() - 2),
        }
    }

    /// (f, f', f'') at t.
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        let n = self.x.len();
        if t < self.x[0] || t > self.x[n - 1] {
            let (k, x0) = if t < self.x[0] {
                (0, self.x[0])
            } else {
                (n - 1, self.x[n - 1])
            };
            let (f, df, _) = self.eval_in(if k == 0 { 0 } else { n - 2 }, x0);
            return (f + df * (t - x0), df, 0.0);
        }
        self.eval_in(self.segment(t), t)
    }

    fn eval_in(&self, i: usize, t: f64) -> (f64, f64, f64) {
        let h = self.x[i + 1] - self.x[i];
        let a = (self.x[i + 1] - t) / h;
        let b = (t - self.x[i]) / h;
        let (m0, m1) = (self.m[i], self.m[i + 1]);
        let f = a * self.y[i]
            + b * self.y[i + 1]
            + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
        let df = (self.y[i + 1] - self.y[i]) / h - (3.0 * a * a - 1.0) * h * m0 / 6.0
            + (3.0 * b * b - 1.0) * h * m1 / 6.0;
        let d2f = a * m0 + b * m1;
        (f, df, d2f)
    }

    /// Integral from x[0] to t (t inside the table).
    pub fn integral(&self, t: f64) -> f64 {
        let seg = self.segment(t);
        let mut acc = 0.0;
        for i in 0..=seg {
            let x1 = if i == seg { t } else { self.x[i + 1] };
            acc += self.segment_integral(i, x1);
        }
        acc
    }

    /// Integral over segment i from x[i] to x1.
    fn segment_integral(&self, i: usize, x1: f64) -> f64 {
        // Gauss-Legendre with 3 points is exact for the cubic.
        let (a, b) = (self.x[i], x1);
        let (c, r) = (0.5 * (a + b), 0.5 * (b - a));
        let g = (0.6f64).sqrt();
        let w = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
        let xs = [c - r * g, c, c + r * g];
        r * (0..3).map(|k| w[k] * self.eval_in(i, xs[k]).0).sum::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spline_reproduces_a_line_and_is_c2() {
        let s = Spline::new(&[0.0, 1.0, 3.0, 4.0], &[1.0, 3.0, 7.0, 9.0]).unwrap();
        for t in [-1.0, 0.5, 2.0, 3.9, 5.0] {
            let (f, df, _) = s.eval(t);
            assert!((f - (1.0 + 2.0 * t)).abs() < 1e-12 && (df - 2.0).abs() < 1e-12);
        }
        let q = Spline::new(&[0.0, 1.0, 2.0, 3.0], &[0.0, 1.0, 0.0, 2.0]).unwrap();
        let e = 1e-9;
        let (l, r) = (q.eval(1.0 - e), q.eval(1.0 + e));
        assert!((l.1 - r.1).abs() < 1e-6 && (l.2 - r.2).abs() < 1e-6);
    }

    #[test]
    fn integrals_match_quadrature() {
        let fs = [
            TimeFunction::Ramp {
                offset: 0.5,
                slope_per_s: 2.0,
                start_s: 0.3,
            },
            TimeFunction::Step {
                t0_s: 0.2,
                from: 1.0,
                t1_s: 0.7,
                to: -2.0,
            },
            TimeFunction::Harmonic {
                amplitude: 1.5,
                frequency_hz: 2.0,
                phase_rad: 0.3,
                offset: 0.1,
            },
            TimeFunction::Table {
                time_s: vec![0.1, 0.4, 0.9],
                value: vec![1.0, -1.0, 2.0],
            },
        ];
        for f in &fs {
            let t = 1.1;
            let n = 20000;
            let h = t / n as f64;
            let quad: f64 = (0..n).map(|k| f.eval((k as f64 + 0.5) * h).0 * h).sum();
            assert!(
                (quad - f.integral(t)).abs() < 1e-6,
                "{f:?}: {quad} vs {}",
                f.integral(t)
            );
        }
    }
}
