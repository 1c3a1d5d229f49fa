//! The frequency weightings of ISO 2631-1:1997 (Annex A, Table A.2) as the product of
//! four analogue sections, and their digital (IIR) form for sampled recordings.
//!
//! Definition (ISO 2631-1 Annex A; the same parameters in ISO 8041:2005 Table 3, as
//! reproduced in Rimell & Mansfield 2007, "Design of digital filters for frequency
//! weightings required for risk assessments of workers exposed to vibration",
//! Industrial Health 45, 512-519, Table 1, and in the Larson Davis HVM200 manual,
//! Table 3.1 "source: ISO 8041"), with `w_i = 2 pi f_i`:
//!
//! - band-limiting high-pass `s^2 / (s^2 + w1 s / Q1 + w1^2)`, `Q1 = 1/sqrt(2)`;
//! - band-limiting low-pass `w2^2 / (s^2 + w2 s / Q2 + w2^2)`, `Q2 = 1/sqrt(2)`
//!   (both 2nd-order Butterworth);
//! - a-v transition `(1 + s/w3) / (1 + s/(Q4 w4) + s^2/w4^2)`;
//! - upward step `(s^2 + w5 s/Q5 + w5^2) / (s^2 + w6 s/Q6 + w6^2)` (gain `(f5/f6)^2`
//!   at low frequency, 1 at high);
//! - times the gain `K`. An infinite `f` removes its factor.
//!
//! Digital form: each section through the bilinear transform, as Rimell & Mansfield do,
//! but prewarped (`s = c (1 - 1/z)/(1 + 1/z)`, `c = w_p / tan(w_p T / 2)`) at the
//! section's own corner (`f1`, `f2`, `f4`, `f6`) so that each corner lands exactly
//! where the standard puts it (Oppenheim & Schafer, Discrete-Time Signal Processing,
//! 3rd ed., section 7.2.2). The remaining warping away from the corners is checked
//! against the analogue gain in `tests/app/comfort_iso2631.rs`.

use nalgebra::Complex;

/// The ISO 2631-1 weightings implemented.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Weighting {
    /// Vertical (z) on the seat, feet, recumbent: health, comfort, perception.
    Wk,
    /// Horizontal (x, y) on the seat, feet, recumbent.
    Wd,
    /// Motion sickness (vertical, 0.1 to 0.5 Hz).
    Wf,
    /// Seat-back x (comfort).
    Wc,
    /// Rotational (roll, pitch, yaw) on the seat [rad/s^2].
    We,
}

impl Weighting {
    /// Every weighting, in the standard's order.
    pub const ALL: [Weighting; 5] = [
        Weighting::Wk,
        Weighting::Wd,
        Weighting::Wf,
        Weighting::Wc,
        Weighting::We,
    ];

    /// The name as written on the command line and in files (`wk`, `wd`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Weighting::Wk => "wk",
            Weighting::Wd => "wd",
            Weighting::Wf => "wf",
            Weighting::Wc => "wc",
            Weighting::We => "we",
        }
    }

    /// The weighting named `s` (case-insensitive), if any.
    pub fn parse(s: &str) -> Option<Weighting> {
        Weighting::ALL
            .into_iter()
            .find(|w| w.name().eq_ignore_ascii_case(s))
    }

    /// The standard's parameters (ISO 2631-1 Table A.2 = ISO 8041 Table 3).
    pub fn params(self) -> Params {
        const INF: f64 = f64::INFINITY;
        // f1 f2 f3 f4 Q4 f5 Q5 f6 Q6 K, frequencies in Hz.
        let p = match self {
            Weighting::Wk => [0.4, 100.0, 12.5, 12.5, 0.63, 2.37, 0.91, 3.35, 0.91, 1.0],
            Weighting::Wd => [0.4, 100.0, 2.0, 2.0, 0.63, INF, 1.0, INF, 1.0, 1.0],
            Weighting::Wf => [0.08, 0.63, INF, 0.25, 0.86, 0.0625, 0.80, 0.10, 0.80, 1.0],
            Weighting::Wc => [0.4, 100.0, 8.0, 8.0, 0.63, INF, 1.0, INF, 1.0, 1.0],
            Weighting::We => [0.4, 100.0, 1.0, 1.0, 0.63, INF, 1.0, INF, 1.0, 1.0],
        };
        Params {
            f1: p[0],
            f2: p[1],
            f3: p[2],
            f4: p[3],
            q4: p[4],
            f5: p[5],
            q5: p[6],
            f6: p[7],
            q6: p[8],
            k: p[9],
        }
    }

    /// The analogue (defining) gain |H(j 2 pi f)| at `f_hz`.
    pub fn analogue_gain(self, f_hz: f64) -> f64 {
        let s = Complex::new(0.0, 2.0 * std::f64::consts::PI * f_hz);
        let h: Complex<f64> = self.params().sections().iter().map(|q| q.eval(s)).product();
        self.params().k * h.norm()
    }
}

/// The parameters of one weighting [Hz, -].
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(missing_docs)]
pub struct Params {
    pub f1: f64,
    pub f2: f64,
    pub f3: f64,
    pub f4: f64,
    pub q4: f64,
    pub f5: f64,
    pub q5: f64,
    pub f6: f64,
    pub q6: f64,
    pub k: f64,
}

/// An analogue biquad `(b2 s^2 + b1 s + b0) / (a2 s^2 + a1 s + a0)` and the angular
/// frequency [rad/s] at which its digital form is prewarped.
#[derive(Clone, Copy, Debug)]
struct Section {
    b: [f64; 3],
    a: [f64; 3],
    w_warp: f64,
}

impl Section {
    fn eval(&self, s: Complex<f64>) -> Complex<f64> {
        let p = |c: &[f64; 3]| s * s * c[2] + s * c[1] + c[0];
        p(&self.b) / p(&self.a)
    }
}

impl Params {
    /// The four sections (fewer where a frequency is infinite).
    fn sections(&self) -> Vec<Section> {
        let w = |f: f64| 2.0 * std::f64::consts::PI * f;
        let q12 = std::f64::consts::FRAC_1_SQRT_2;
        let (w1, w2, w3, w4, w5, w6) = (
            w(self.f1),
            w(self.f2),
            w(self.f3),
            w(self.f4),
            w(self.f5),
            w(self.f6),
        );
        let mut out = vec![
            Section {
                b: [0.0, 0.0, 1.0],
                a: [w1 * w1, w1 / q12, 1.0],
                w_warp: w1,
            },
            Section {
                b: [w2 * w2, 0.0, 0.0],
                a: [w2 * w2, w2 / q12, 1.0],
                w_warp: w2,
            },
        ];
        if w4.is_finite() {
            // 1/w3 is 0 for an infinite f3: the numerator is then 1.
            out.push(Section {
                b: [1.0, 1.0 / w3, 0.0],
                a: [1.0, 1.0 / (self.q4 * w4), 1.0 / (w4 * w4)],
                w_warp: w4,
            });
        }
        if w5.is_finite() && w6.is_finite() {
            out.push(Section {
                b: [w5 * w5, w5 / self.q5, 1.0],
                a: [w6 * w6, w6 / self.q6, 1.0],
                w_warp: w6,
            });
        }
        out
    }
}

/// One digital 2nd-order section `(b0 + b1/z + b2/z^2) / (1 + a1/z + a2/z^2)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Biquad {
    /// Numerator coefficients.
    pub b: [f64; 3],
    /// Denominator coefficients `[1, a1, a2]`.
    pub a: [f64; 3],
}

impl Biquad {
    /// The bilinear transform of `sec` at sample rate `rate_hz`, prewarped at its corner.
    fn bilinear(sec: &Section, rate_hz: f64) -> Biquad {
        let c = sec.w_warp / (sec.w_warp / (2.0 * rate_hz)).tan();
        let z = |p: &[f64; 3]| {
            let (p2, p1, p0) = (p[2] * c * c, p[1] * c, p[0]);
            [p2 + p1 + p0, 2.0 * (p0 - p2), p2 - p1 + p0]
        };
        let (b, a) = (z(&sec.b), z(&sec.a));
        Biquad {
            b: [b[0] / a[0], b[1] / a[0], b[2] / a[0]],
            a: [1.0, a[1] / a[0], a[2] / a[0]],
        }
    }

    fn response(&self, f_hz: f64, rate_hz: f64) -> Complex<f64> {
        let zi = Complex::from_polar(1.0, -2.0 * std::f64::consts::PI * f_hz / rate_hz);
        let p = |c: &[f64; 3]| Complex::new(c[0], 0.0) + zi * c[1] + zi * zi * c[2];
        p(&self.b) / p(&self.a)
    }
}

/// A weighting as a digital filter at one sample rate.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightingFilter {
    /// Which weighting.
    pub weighting: Weighting,
    /// Sample rate [Hz].
    pub rate_hz: f64,
    /// The cascade of sections.
    pub sections: Vec<Biquad>,
    k: f64,
}

impl WeightingFilter {
    /// The digital filter of `weighting` at `rate_hz`; `None` when a corner (up to the
    /// 100 Hz band limit) is not below the Nyquist frequency: ISO 2631-1 needs a
    /// recording sampled above 200 Hz for Wk, Wd, Wc, We.
    pub fn new(weighting: Weighting, rate_hz: f64) -> Option<WeightingFilter> {
        let p = weighting.params();
        let secs = p.sections();
        if !(rate_hz.is_finite()
            && secs
                .iter()
                .all(|s| s.w_warp / rate_hz < std::f64::consts::PI))
        {
            return None;
        }
        Some(WeightingFilter {
            weighting,
            rate_hz,
            sections: secs.iter().map(|s| Biquad::bilinear(s, rate_hz)).collect(),
            k: p.k,
        })
    }

    /// The digital filter's gain at `f_hz`.
    pub fn gain(&self, f_hz: f64) -> f64 {
        let h: Complex<f64> = self
            .sections
            .iter()
            .map(|b| b.response(f_hz, self.rate_hz))
            .product();
        self.k * h.norm()
    }

    /// `x` weighted (zero initial state; direct form II transposed).
    pub fn apply(&self, x: &[f64]) -> Vec<f64> {
        let mut y: Vec<f64> = x.iter().map(|v| v * self.k).collect();
        for q in &self.sections {
            let (mut s1, mut s2) = (0.0, 0.0);
            for v in y.iter_mut() {
                let u = *v;
                let o = q.b[0] * u + s1;
                s1 = q.b[1] * u - q.a[1] * o + s2;
                s2 = q.b[2] * u - q.a[2] * o;
                *v = o;
            }
        }
        y
    }
}
