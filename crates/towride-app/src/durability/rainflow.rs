//! Turning points and the rainflow count of ASTM E1049-85 (reapproved 2017), "Standard
//! Practices for Cycle Counting in Fatigue Analysis", section 5.4.4 (rainflow counting,
//! three-point method with the starting-point rule): of the three most recent turning
//! points, X is the range of the newest pair and Y the one before it; while X >= Y,
//! Y is counted: as half a cycle when it holds the history's starting point (which is
//! then dropped), else as a full cycle (both its points dropped). What remains (the
//! residue) counts as half cycles. Range = |peak - valley|, mean = (peak + valley) / 2.

use super::{positive, DurabilityError};

/// One counted cycle or half cycle.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Cycle {
    /// Range |peak - valley|, in the signal's unit.
    pub range: f64,
    /// Mean (peak + valley) / 2, in the signal's unit.
    pub mean: f64,
    /// 0.5 for a half cycle, 1.0 for a full one.
    pub count: f64,
}

/// The reversals of `x`: the first and last samples and every sample where the
/// direction changes, plateaus merged. With `gate` > 0 (signal unit) a reversal is
/// kept only once the signal has moved back from it by more than `gate` (a hysteresis
/// filter: smaller wiggles are dropped); `gate` = 0 keeps every reversal.
pub fn turning_points(x: &[f64], gate: f64) -> Result<Vec<f64>, DurabilityError> {
    if let Some((index, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(DurabilityError::NotFinite { index, value });
    }
    if !(gate.is_finite() && gate >= 0.0) {
        return Err(DurabilityError::Parameter {
            name: "gate",
            value: gate,
            why: "must be a finite number >= 0",
        });
    }
    if x.len() < 3 {
        return Err(DurabilityError::TooShort { found: x.len() });
    }
    let mut tp = Vec::new();
    // Until the signal leaves the gate, track its extremes: the first turning point is
    // the one the signal then moves away from.
    let (mut lo, mut hi) = (x[0], x[0]);
    let mut dir = 0.0;
    for &v in x {
        if dir == 0.0 {
            lo = lo.min(v);
            hi = hi.max(v);
            if hi - lo > gate && hi > lo {
                if v == hi {
                    tp.extend([lo, hi]);
                    dir = 1.0;
                } else {
                    tp.extend([hi, lo]);
                    dir = -1.0;
                }
            }
            continue;
        }
        let last = *tp.last().expect("two points pushed");
        if (v - last) * dir > 0.0 {
            *tp.last_mut().expect("non-empty") = v;
        } else if (last - v) * dir > gate && v != last {
            tp.push(v);
            dir = -dir;
        }
    }
    if tp.is_empty() {
        // A flat (or within-gate) signal: one point, no range.
        tp.push(x[0]);
    }
    Ok(tp)
}

/// The rainflow count of a sequence of turning points (ASTM E1049-85 section 5.4.4),
/// cycles in the order they close, the residue's half cycles last.
pub fn count(tp: &[f64]) -> Vec<Cycle> {
    let mut out = Vec::new();
    // Stack of turning points; s[0] is always the (current) starting point.
    let mut s: Vec<f64> = Vec::with_capacity(tp.len());
    for &p in tp {
        s.push(p);
        while s.len() >= 3 {
            let n = s.len();
            let x = (s[n - 1] - s[n - 2]).abs();
            let y = (s[n - 2] - s[n - 3]).abs();
            if x < y {
                break;
            }
            if n == 3 {
                // Y holds the starting point s[0]: half a cycle, and the starting point
                // moves on to Y's second point.
                out.push(cycle(s[0], s[1], 0.5));
                s.remove(0);
            } else {
                out.push(cycle(s[n - 3], s[n - 2], 1.0));
                s.drain(n - 3..n - 1);
            }
        }
    }
    for w in s.windows(2) {
        out.push(cycle(w[0], w[1], 0.5));
    }
    out
}

fn cycle(a: f64, b: f64, count: f64) -> Cycle {
    Cycle {
        range: (a - b).abs(),
        mean: 0.5 * (a + b),
        count,
    }
}

/// Total cycles (full cycles plus half the half cycles).
pub fn total_cycles(cycles: &[Cycle]) -> f64 {
    cycles.iter().map(|c| c.count).sum()
}

/// Counts binned over range and mean: equal-width bins, ranges from 0 to the largest
/// range, means from the smallest to the largest mean; a value on an inner edge falls
/// in the upper bin, the largest in the last.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RangeMeanMatrix {
    /// Range bin edges (`range_bins` + 1), signal unit.
    pub range_edges: Vec<f64>,
    /// Mean bin edges (`mean_bins` + 1), signal unit.
    pub mean_edges: Vec<f64>,
    /// Cycles per bin, `counts[range_bin][mean_bin]`.
    pub counts: Vec<Vec<f64>>,
}

impl RangeMeanMatrix {
    /// Bins `cycles` into `range_bins` x `mean_bins`.
    pub fn of(
        cycles: &[Cycle],
        range_bins: usize,
        mean_bins: usize,
    ) -> Result<RangeMeanMatrix, DurabilityError> {
        positive("range_bins", range_bins as f64)?;
        positive("mean_bins", mean_bins as f64)?;
        let r_max = cycles.iter().map(|c| c.range).fold(0.0, f64::max);
        let m_lo = cycles.iter().map(|c| c.mean).fold(f64::INFINITY, f64::min);
        let m_hi = cycles
            .iter()
            .map(|c| c.mean)
            .fold(f64::NEG_INFINITY, f64::max);
        let (m_lo, m_hi) = if cycles.is_empty() {
            (0.0, 0.0)
        } else {
            (m_lo, m_hi)
        };
        let edges = |lo: f64, hi: f64, n: usize| -> Vec<f64> {
            // A degenerate span (one value) still gets bins of unit width around it.
            let w = if hi > lo {
                (hi - lo) / n as f64
            } else {
                1.0 / n as f64
            };
            (0..=n).map(|i| lo + w * i as f64).collect()
        };
        let range_edges = edges(0.0, r_max, range_bins);
        let mean_edges = edges(m_lo, m_hi, mean_bins);
        let mut counts = vec![vec![0.0; mean_bins]; range_bins];
        for c in cycles {
            let i = bin(&range_edges, c.range);
            let j = bin(&mean_edges, c.mean);
            counts[i][j] += c.count;
        }
        Ok(RangeMeanMatrix {
            range_edges,
            mean_edges,
            counts,
        })
    }
}

fn bin(edges: &[f64], v: f64) -> usize {
    let n = edges.len() - 1;
    let w = edges[1] - edges[0];
    (((v - edges[0]) / w).floor().max(0.0) as usize).min(n - 1)
}
