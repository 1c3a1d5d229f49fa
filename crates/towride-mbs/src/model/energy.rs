//! Strain-energy mode selection after a run (the commercial tool's method in the
//! thesis): each mode's share of a modal body's strain energy, as the peak of
//! w_j^2 eta_j^2 / 2 over the run and as its time integral, and the modes whose share
//! reaches a threshold.
//!
//! With unit modal mass and mass-orthogonal modes the strain energy is a sum over modes,
//! so the shares add up to one and need no cross terms.

use serde::Serialize;

use super::run::Samples;
use super::system::System;

/// Strain energy of one mode of a modal body over a run.
#[derive(Clone, Debug, Serialize)]
pub struct ModeEnergy {
    /// Number in the body's mode table (1-based, rigid modes counted).
    pub number: usize,
    /// Natural frequency [Hz].
    pub frequency_hz: f64,
    /// Largest strain energy of the mode over the run [J].
    pub peak_j: f64,
    /// Time integral of its strain energy [J s].
    pub integral_j_s: f64,
    /// Shares of the body's summed peaks and of its total integral.
    pub share_peak: f64,
    /// The mode's share of the body's total strain-energy integral.
    pub share_integral: f64,
}

/// Strain-energy shares of the modes of one modal body.
#[derive(Clone, Debug, Serialize)]
pub struct BodyEnergy {
    /// Body name.
    pub body: String,
    /// Largest total strain energy over the run [J].
    pub peak_total_j: f64,
    /// Every mode the model keeps for the body, in mode-table order.
    pub modes: Vec<ModeEnergy>,
}

/// Per modal body, each mode's strain-energy share over `run`.
pub fn strain_shares(sys: &System, run: &Samples) -> Vec<BodyEnergy> {
    let mut out = Vec::new();
    for (b, rows) in &run.modal {
        let Some(m) = &sys.model.bodies[*b].modal else {
            continue;
        };
        let k: Vec<f64> = m.data.modes.iter().map(|md| md.stiffness).collect();
        let nm = k.len();
        let (mut peak, mut integral) = (vec![0.0f64; nm], vec![0.0f64; nm]);
        let mut peak_total = 0.0f64;
        let energy =
            |r: &[f64]| -> Vec<f64> { (0..nm).map(|j| 0.5 * k[j] * r[j] * r[j]).collect() };
        for (i, r) in rows.iter().enumerate() {
            let e = energy(r);
            peak_total = peak_total.max(e.iter().sum());
            for j in 0..nm {
                peak[j] = peak[j].max(e[j]);
            }
            if i > 0 {
                // Trapezoidal rule over the sample grid.
                let dt = run.times[i] - run.times[i - 1];
                let e0 = energy(&rows[i - 1]);
                for j in 0..nm {
                    integral[j] += 0.5 * dt * (e[j] + e0[j]);
                }
            }
        }
        let sp: f64 = peak.iter().sum();
        let si: f64 = integral.iter().sum();
        let frac = |x: f64, s: f64| if s > 0.0 { x / s } else { 0.0 };
        out.push(BodyEnergy {
            body: sys.model.bodies[*b].name.clone(),
            peak_total_j: peak_total,
            modes: m
                .data
                .modes
                .iter()
                .enumerate()
                .map(|(j, md)| ModeEnergy {
                    number: md.number,
                    frequency_hz: md.frequency_hz,
                    peak_j: peak[j],
                    integral_j_s: integral[j],
                    share_peak: frac(peak[j], sp),
                    share_integral: frac(integral[j], si),
                })
                .collect(),
        });
    }
    out
}

/// Mode numbers whose peak or integral share reaches `threshold` (a fraction, e.g. 0.01).
pub fn select_by_energy(body: &BodyEnergy, threshold: f64) -> Vec<usize> {
    body.modes
        .iter()
        .filter(|m| m.share_peak >= threshold || m.share_integral >= threshold)
        .map(|m| m.number)
        .collect()
}
