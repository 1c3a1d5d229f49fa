//! The convergence verdict of a run (`run --check`): every reported channel's max, min and
//! RMS against a companion run of the same job at a tolerance ten times tighter.
//!
//! Why a companion run and not the solver's own local errors: the local error estimates
//! bound one step's error, not how errors accumulate in a lightly damped mode or at a
//! contact that opens a few samples earlier; the difference between two tolerances is
//! what "converged" means for the user's number. With Radau IIA the companion costs about
//! what the run costs (its steps are set by the road and the contacts: 806 steps at rtol
//! 1e-3, 792 at 1e-4 on the default scene's variant 1).
//!
//! A channel is judged where the report shows it: the band-limited twin of an
//! accelerometer, force or deflection when the scene has an acquisition chain, else the
//! raw channel. Differences are relative to the tighter run's value, or to a floor when
//! that value is smaller: an absolute floor per unit, so near-zero channels (the lateral
//! force of a symmetric run) are not judged by round-off, and 1 % of the channel's own
//! |peak|, so an extreme far below it (the crossbeam strain energy's minimum, 1e-4 of its
//! maximum) is judged on the channel's scale.
//!
//! A channel whose values stay within its unit's floor in both runs carries no result:
//! it is round-off (the lateral hitch acceleration of a left/right symmetric run, a few
//! mm/s^2 that move by 1-3 mm/s^2 between tolerances), so it is listed as below its floor
//! instead of being judged, and is neither converged nor failing in the count. The same
//! holds for one statistic of a judged channel: an extreme or RMS within the floor in both
//! runs is round-off and is listed in `unjudged` (the lateral hitch acceleration's
//! minimum, -3.2 against -4.4 mm/s^2 late in a run whose maximum, 0.057 m/s^2, converged).

use std::collections::BTreeMap;

use serde::Serialize;

use super::{RunResult, Signal};

/// Relative difference a converged channel may show (2 %).
pub const DEFAULT_THRESHOLD: f64 = 0.02;
/// The companion run's rtol and atol are the run's divided by this.
pub const TIGHTEN: f64 = 10.0;

/// The absolute floor of a unit: differences below it are round-off for this application
/// (forces: 1e-3 of the hitch's 5 kN; accelerations: an accelerometer's noise floor class;
/// deflections: 10 um, 1 % of the hitch's fore-aft deflection; stresses: 0.1 MPa). 0 for
/// other units.
pub fn floor(unit: &str) -> f64 {
    match unit {
        "N" => 5.0,
        "N*m" | "N m" => 1.0,
        "m/s^2" => crate::comfort::evaluate::RESOLUTION_M_S2,
        "m" => 1e-5,
        "m/s" => 1e-3,
        "rad" => 1e-4,
        "rad/s" => 1e-3,
        "J" => 1e-3,
        // Stress: 0.1 MPa, 1e-3 of the crossbeam's 100 MPa peaks (as 5 N of 5 kN).
        "Pa" => 1e5,
        _ => 0.0,
    }
}

/// Share of a channel's |peak| below which its extremes are judged against that share.
pub const PEAK_FLOOR: f64 = 0.01;

/// One channel's differences, relative to max(|tighter value|, floor).
#[derive(Clone, Debug, Serialize)]
pub struct ChannelCheck {
    /// Unit of the channel.
    pub unit: String,
    /// Relative difference of the maxima.
    pub max_diff: f64,
    /// Relative difference of the minima.
    pub min_diff: f64,
    /// Relative difference of the RMS values.
    pub rms_diff: f64,
    /// The floor used [unit]: the unit's, or 1 % of the channel's |peak| if larger.
    pub floor: f64,
    /// Every judged statistic within the threshold, or the channel is below its floor.
    pub converged: bool,
    /// Both runs' values stay within the unit's floor: round-off, not a result, not judged.
    pub below_floor: bool,
    /// The statistics ("max", "min", "rms") within the unit's floor in both runs, not
    /// judged (all three when `below_floor`).
    pub unjudged: Vec<&'static str>,
}

impl ChannelCheck {
    /// The largest relative difference among the judged statistics (0 when none is).
    pub fn worst(&self) -> f64 {
        [
            ("max", self.max_diff),
            ("min", self.min_diff),
            ("rms", self.rms_diff),
        ]
        .iter()
        .filter(|(n, _)| !self.unjudged.contains(n))
        .map(|(_, d)| *d)
        .fold(0.0, f64::max)
    }
}

/// The verdict of a run against its companion.
#[derive(Clone, Debug, Serialize)]
pub struct Verdict {
    /// How it was found: "companion run".
    pub method: &'static str,
    /// Relative threshold.
    pub threshold: f64,
    /// The run's rtol.
    pub rtol: f64,
    /// The companion's rtol.
    pub check_rtol: f64,
    /// The companion's steps.
    pub check_steps: usize,
    /// The companion's wall time [s].
    pub check_wall_s: f64,
    /// Every judged channel converged.
    pub converged: bool,
    /// The channels that did not, largest difference first.
    pub failing: Vec<String>,
    /// The channels whose values stay within their unit's floor in both runs.
    pub below_floor: Vec<String>,
    /// Per judged channel, written in natural order.
    #[serde(serialize_with = "crate::report::display::serialize_natural")]
    pub channels: BTreeMap<String, ChannelCheck>,
}

/// Compares `run` with `check`, the same job at a tighter tolerance. `None` when either
/// run did not complete (there is nothing to compare over the whole time).
pub fn verdict(run: &RunResult, check: &RunResult, rtol: f64, threshold: f64) -> Option<Verdict> {
    if run.failure().is_some() || check.failure().is_some() {
        return None;
    }
    if run.summary.interrupted_at_s.is_some() || check.summary.interrupted_at_s.is_some() {
        return None;
    }
    let mut channels = BTreeMap::new();
    for (name, c) in &run.summary.channels {
        if !judged(name, c) {
            continue;
        }
        let (Some(a), Some(b)) = (stats(run, name), stats(check, name)) else {
            continue;
        };
        let fl = floor(&c.unit).max(PEAK_FLOOR * b.0.abs().max(b.1.abs()));
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(fl).max(f64::MIN_POSITIVE);
        let (max_diff, min_diff, rms_diff) = (rel(a.0, b.0), rel(a.1, b.1), rel(a.2, b.2));
        let peak = |s: (f64, f64, f64)| s.0.abs().max(s.1.abs());
        let unit_floor = floor(&c.unit);
        let below_floor = peak(a).max(peak(b)) < unit_floor;
        let unjudged: Vec<&'static str> = [("max", a.0, b.0), ("min", a.1, b.1), ("rms", a.2, b.2)]
            .into_iter()
            .filter(|(_, x, y)| x.abs().max(y.abs()) < unit_floor)
            .map(|(n, _, _)| n)
            .collect();
        let mut check = ChannelCheck {
            unit: c.unit.clone(),
            max_diff,
            min_diff,
            rms_diff,
            floor: fl,
            converged: true,
            below_floor,
            unjudged,
        };
        check.converged = below_floor || check.worst() <= threshold;
        channels.insert(name.clone(), check);
    }
    let mut failing: Vec<(&String, f64)> = channels
        .iter()
        .filter(|(_, c)| !c.converged)
        .map(|(n, c)| (n, c.worst()))
        .collect();
    failing.sort_by(|a, b| b.1.total_cmp(&a.1));
    let below_floor = channels
        .iter()
        .filter(|(_, c)| c.below_floor)
        .map(|(n, _)| n.clone())
        .collect();
    Some(Verdict {
        method: "companion run",
        threshold,
        rtol,
        check_rtol: rtol / TIGHTEN,
        check_steps: check.summary.solver.steps,
        check_wall_s: check.summary.wall_s,
        converged: failing.is_empty(),
        failing: failing.into_iter().map(|(n, _)| n.clone()).collect(),
        below_floor,
        channels,
    })
}

/// The channels a verdict judges: the band-limited twin where there is one, physical
/// units only (not contact flags or modal coordinates, whose basis is the body's own).
fn judged(name: &str, c: &super::ChannelSummary) -> bool {
    let has_twin_shown_instead = c.signal == Signal::Raw && c.twin.is_some();
    !has_twin_shown_instead
        && !name.starts_with(crate::scene::channels::HITCH_ETA_PREFIX)
        && !crate::scene::channels::is_stress_envelope(name)
        && floor(&c.unit) > 0.0
}

/// (max, min, RMS) of a channel over the run's samples.
fn stats(r: &RunResult, name: &str) -> Option<(f64, f64, f64)> {
    let c = r.samples.channels.iter().position(|c| c.name == name)?;
    let n = r.samples.rows.len();
    if n == 0 {
        return None;
    }
    let (mut max, mut min, mut sq) = (f64::NEG_INFINITY, f64::INFINITY, 0.0);
    for row in &r.samples.rows {
        let v = row[c];
        max = max.max(v);
        min = min.min(v);
        sq += v * v;
    }
    Some((max, min, (sq / n as f64).sqrt()))
}
