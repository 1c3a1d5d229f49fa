//! The ISO 2631-1:1997 measures of a weighted acceleration `a_w(t)` sampled at step `dt`.
//!
//! - weighted r.m.s. `a_w = (1/T int a_w^2 dt)^(1/2)` (clause 6.2.1, eq. 1);
//! - running r.m.s. with linear integration over `tau = 1 s` (clause 6.3.1, eq. 2: "it is
//!   recommended to use tau = 1 s ... linear integration"; exponential integration, eq. 3,
//!   is the alternative the standard allows), and the maximum transient vibration value
//!   MTVV, its largest value (eq. 4);
//! - fourth-power vibration dose value `VDV = (int a_w^4 dt)^(1/4)` [m/s^1.75] (clause
//!   6.3.2, eq. 5);
//! - crest factor `max |a_w| / a_w` (clause 6.2.1): above 9 the basic r.m.s. method may
//!   underestimate (clause 6.2.1), as may MTVV/a_w > 1.5 or VDV/(a_w T^(1/4)) > 1.75
//!   (clause 6.3.3); then VDV and MTVV are the measures to report, which is the case for
//!   short transient passages such as an obstacle crossing.
//!
//! The integrals are sums times `dt` (rectangle rule on the samples).

/// The measures of one weighted channel.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Measures {
    /// Weighted r.m.s. [m/s^2].
    pub rms_m_s2: f64,
    /// Vibration dose value [m/s^1.75].
    pub vdv_m_s1_75: f64,
    /// Maximum transient vibration value (1 s linear running r.m.s.) [m/s^2].
    pub mtvv_m_s2: f64,
    /// Largest |weighted acceleration| [m/s^2].
    pub peak_m_s2: f64,
    /// `peak / rms` [-].
    pub crest_factor: f64,
    /// Duration [s].
    pub duration_s: f64,
}

impl Measures {
    /// Whether the basic (r.m.s.) method may underestimate (ISO 2631-1 6.2.1, 6.3.3):
    /// crest factor above 9, MTVV/a_w above 1.5 or VDV/(a_w T^(1/4)) above 1.75.
    pub fn transient(&self) -> bool {
        self.crest_factor > 9.0
            || self.mtvv_m_s2 > 1.5 * self.rms_m_s2
            || self.vdv_m_s1_75 > 1.75 * self.rms_m_s2 * self.duration_s.powf(0.25)
    }
}

/// Integration time of the running r.m.s. for MTVV [s] (ISO 2631-1 6.3.1).
pub const MTVV_TAU_S: f64 = 1.0;

/// The measures of the weighted signal `aw` sampled at step `dt` [s]; `None` for an
/// empty signal or a step that is not positive.
pub fn measures(aw: &[f64], dt: f64) -> Option<Measures> {
    if aw.is_empty() || !(dt > 0.0 && dt.is_finite()) {
        return None;
    }
    let n = aw.len() as f64;
    let sq: f64 = aw.iter().map(|v| v * v).sum();
    let rms = (sq / n).sqrt();
    let vdv = (aw.iter().map(|v| v.powi(4)).sum::<f64>() * dt).powf(0.25);
    let peak = aw.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    Some(Measures {
        rms_m_s2: rms,
        vdv_m_s1_75: vdv,
        mtvv_m_s2: mtvv(aw, dt, MTVV_TAU_S),
        peak_m_s2: peak,
        crest_factor: if rms > 0.0 { peak / rms } else { 0.0 },
        duration_s: n * dt,
    })
}

/// The largest running r.m.s. over windows of `tau` [s] ending at each sample (linear
/// integration, ISO 2631-1 eq. 2); before `tau` has elapsed the signal is taken as zero
/// before its start, as an instrument started at t = 0 would.
pub fn mtvv(aw: &[f64], dt: f64, tau: f64) -> f64 {
    let m = ((tau / dt).round() as usize).max(1);
    let (mut sum, mut best) = (0.0_f64, 0.0_f64);
    for i in 0..aw.len() {
        sum += aw[i] * aw[i];
        if i >= m {
            sum -= aw[i - m] * aw[i - m];
        }
        best = best.max(sum.max(0.0));
    }
    (best * dt / tau).sqrt()
}

/// Multiplying factors `k` (x, y, z) for a seated person on the seat surface:
/// for comfort all three are 1 (ISO 2631-1 clause 8.2.3); for health x and y are 1.4,
/// z is 1 (clause 7.2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Assessment {
    /// k = 1, 1, 1.
    Comfort,
    /// k = 1.4, 1.4, 1.
    Health,
}

impl Assessment {
    /// The factors `[kx, ky, kz]`.
    pub fn k(self) -> [f64; 3] {
        match self {
            Assessment::Comfort => [1.0, 1.0, 1.0],
            Assessment::Health => [1.4, 1.4, 1.0],
        }
    }
}

/// The vibration total value `a_v = (kx^2 a_wx^2 + ky^2 a_wy^2 + kz^2 a_wz^2)^(1/2)`
/// (ISO 2631-1 eq. 9) of three axes' r.m.s. values.
pub fn combined(rms_xyz: [f64; 3], a: Assessment) -> f64 {
    let k = a.k();
    (0..3)
        .map(|i| (k[i] * rms_xyz[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}
