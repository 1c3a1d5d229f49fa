//! Morris's elementary-effects screening (Morris 1991; mu* of Campolongo, Cariboni and
//! Saltelli 2007): `r` trajectories through a grid of `p` levels on [0, 1]^k, each
//! changing one factor at a time by Delta = p / (2 (p - 1)); per factor the mean of the
//! absolute elementary effects (mu*) and their standard deviation (sigma: interactions
//! and non-linearity).
//!
//! The random numbers are a SplitMix64 stream (Steele, Lea and Flood 2014) of our own:
//! ten lines, and a seed gives the same design on every machine and every version,
//! which a general-purpose generator crate does not promise across its releases.

use serde::Serialize;

/// SplitMix64: a seedable, reproducible stream.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A stream from `seed`.
    pub fn new(seed: u64) -> SplitMix64 {
        SplitMix64(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform integer in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// One trajectory: k + 1 points in [0, 1]^k; point j + 1 differs from point j in factor
/// `order[j]` by +Delta.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Trajectory {
    /// The points, each a level value per factor.
    pub points: Vec<Vec<f64>>,
    /// Which factor each step changes.
    pub order: Vec<usize>,
}

/// `r` trajectories for `k` factors on `levels` levels (even, >= 2), from `seed`. Each
/// starts at a random point of the lower levels (so that +Delta stays in [0, 1]) and
/// moves the factors in a random order.
pub fn design(k: usize, r: usize, levels: usize, seed: u64) -> Vec<Trajectory> {
    let mut rng = SplitMix64::new(seed);
    let step = 1.0 / (levels - 1) as f64;
    let delta = delta(levels);
    (0..r)
        .map(|_| {
            let mut x: Vec<f64> = (0..k)
                .map(|_| rng.below(levels / 2) as f64 * step)
                .collect();
            let mut order: Vec<usize> = (0..k).collect();
            for i in (1..k).rev() {
                order.swap(i, rng.below(i + 1));
            }
            let mut points = vec![x.clone()];
            for &i in &order {
                x[i] += delta;
                points.push(x.clone());
            }
            Trajectory { points, order }
        })
        .collect()
}

/// Delta = p / (2 (p - 1)) for `p` levels.
pub fn delta(levels: usize) -> f64 {
    levels as f64 / (2.0 * (levels - 1) as f64)
}

/// Morris statistics of one factor.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Effects {
    /// Mean of the absolute elementary effects [output unit per unit of the normalised
    /// factor range].
    pub mu_star: f64,
    /// Mean of the elementary effects.
    pub mu: f64,
    /// Standard deviation of the elementary effects (n - 1 in the denominator).
    pub sigma: f64,
    /// Elementary effects that could be computed (both runs completed).
    pub effects: usize,
}

/// Per factor, the statistics of the elementary effects of `design` given the output
/// `y[t][j]` at point j of trajectory t (`None`: the run failed, its effects skipped).
pub fn effects(design: &[Trajectory], y: &[Vec<Option<f64>>], levels: usize) -> Vec<Effects> {
    let k = design.first().map_or(0, |t| t.order.len());
    let d = delta(levels);
    let mut ee: Vec<Vec<f64>> = vec![Vec::new(); k];
    for (t, ys) in design.iter().zip(y) {
        for (j, &i) in t.order.iter().enumerate() {
            if let (Some(a), Some(b)) = (ys[j], ys[j + 1]) {
                ee[i].push((b - a) / d);
            }
        }
    }
    ee.iter()
        .map(|e| {
            let n = e.len() as f64;
            let mu = e.iter().sum::<f64>() / n;
            let mu_star = e.iter().map(|v| v.abs()).sum::<f64>() / n;
            let sigma = if e.len() > 1 {
                (e.iter().map(|v| (v - mu).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
            } else {
                f64::NAN
            };
            Effects {
                mu_star,
                mu,
                sigma,
                effects: e.len(),
            }
        })
        .collect()
}
