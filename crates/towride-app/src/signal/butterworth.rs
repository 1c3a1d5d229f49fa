//! Digital Butterworth low-pass filters made of second-order sections (biquads): the
//! analog prototype's poles s_k = wc exp(i (pi/2 + (2k-1) pi / (2n))) are paired into
//! sections s^2 + 2 sin((2k-1) pi / (2n)) s + 1 (plus s + 1 for odd n) and mapped by the
//! bilinear transform with the cutoff pre-warped, s = (1 - z^-1) / ((1 + z^-1) tan(pi fc / fs)),
//! so the gain at fc is exactly 1/sqrt(2) and at DC exactly 1. [`Butterworth::apply`]
//! runs causally, as an analog acquisition filter does, so its phase lag is reproduced.

use crate::error::SignalError;

/// y[n] = b0 x[n] + b1 x[n-1] + b2 x[n-2] - a1 y[n-1] - a2 y[n-2].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Biquad {
    /// Numerator coefficients b0, b1, b2.
    pub b: [f64; 3],
    /// Denominator coefficients a1, a2 (a0 = 1).
    pub a: [f64; 2],
}

/// A cascade of biquads.
#[derive(Clone, Debug)]
pub struct Butterworth {
    /// Second-order sections, applied in turn.
    pub sections: Vec<Biquad>,
    /// Sample rate the coefficients are designed for [Hz].
    pub rate_hz: f64,
}

impl Butterworth {
    /// Low-pass of `order` with -3 dB at `cutoff_hz`, for samples at `rate_hz`.
    pub fn low_pass(
        order: usize,
        cutoff_hz: f64,
        rate_hz: f64,
    ) -> Result<Butterworth, SignalError> {
        let ok = cutoff_hz > 0.0 && cutoff_hz < 0.5 * rate_hz;
        if order == 0 || !ok {
            return Err(SignalError::FilterDesign {
                order,
                cutoff_hz,
                rate_hz,
            });
        }
        let c = 1.0 / (std::f64::consts::PI * cutoff_hz / rate_hz).tan();
        let n = order as f64;
        let mut sections = Vec::new();
        for k in 1..=order / 2 {
            let a = 2.0 * ((2 * k - 1) as f64 * std::f64::consts::PI / (2.0 * n)).sin();
            let d0 = c * c + a * c + 1.0;
            sections.push(Biquad {
                b: [1.0 / d0, 2.0 / d0, 1.0 / d0],
                a: [(2.0 - 2.0 * c * c) / d0, (c * c - a * c + 1.0) / d0],
            });
        }
        if order % 2 == 1 {
            let d0 = c + 1.0;
            sections.push(Biquad {
                b: [1.0 / d0, 1.0 / d0, 0.0],
                a: [(1.0 - c) / d0, 0.0],
            });
        }
        Ok(Butterworth { sections, rate_hz })
    }

    /// |H| at frequency `f_hz`.
    pub fn magnitude(&self, f_hz: f64) -> f64 {
        let w = 2.0 * std::f64::consts::PI * f_hz / self.rate_hz;
        let (c1, s1, c2, s2) = (w.cos(), -w.sin(), (2.0 * w).cos(), -(2.0 * w).sin());
        self.sections
            .iter()
            .map(|q| {
                let (nr, ni) = (
                    q.b[0] + q.b[1] * c1 + q.b[2] * c2,
                    q.b[1] * s1 + q.b[2] * s2,
                );
                let (dr, di) = (1.0 + q.a[0] * c1 + q.a[1] * c2, q.a[0] * s1 + q.a[1] * s2);
                ((nr * nr + ni * ni) / (dr * dr + di * di)).sqrt()
            })
            .product()
    }

    /// Filters `x` causally, starting from the steady state for `x[0]` (no start-up
    /// transient when a channel does not start at zero).
    pub fn apply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = x.to_vec();
        for q in &self.sections {
            let x0 = y.first().copied().unwrap_or(0.0);
            // Direct form II transposed, states at the DC steady state of x0.
            let mut s2 = (q.b[2] - q.a[1]) * x0;
            let mut s1 = (q.b[1] - q.a[0]) * x0 + s2;
            for v in y.iter_mut() {
                let xin = *v;
                let out = q.b[0] * xin + s1;
                s1 = q.b[1] * xin - q.a[0] * out + s2;
                s2 = q.b[2] * xin - q.a[1] * out;
                *v = out;
            }
        }
        y
    }
}

/// Linear interpolation of (t, y) at `tq`, holding the end values outside.
pub fn interp(t: &[f64], y: &[f64], tq: f64) -> f64 {
    match t.len() {
        0 => 0.0,
        _ if tq <= t[0] => y[0],
        n if tq >= t[n - 1] => y[n - 1],
        _ => {
            let i = t.partition_point(|&v| v <= tq).max(1);
            let (t0, t1) = (t[i - 1], t[i]);
            let f = if t1 > t0 { (tq - t0) / (t1 - t0) } else { 0.0 };
            y[i - 1] + f * (y[i] - y[i - 1])
        }
    }
}
