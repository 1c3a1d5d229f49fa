//! A dynamic run on a fixed sample grid: integrate, sample the requested outputs, and
//! keep everything computed so far when the solver fails.

use std::time::Instant;

use super::desc::BodyHandle;
use super::ic::{initial_state, AssemblyReport};
use super::output::{channels, evaluate, ChannelInfo};
use super::system::System;
use towride_solver::problem::DaeProblem;
use towride_solver::{Advance, Integrator, SolverOptions, Stats};

/// The sampled result of a simulation: channels on the sample grid, solver statistics,
/// and the final state.
#[derive(Clone, Debug)]
pub struct Samples {
    /// The output channels (columns of `rows`).
    pub channels: Vec<ChannelInfo>,
    /// Sample times [s].
    pub times: Vec<f64>,
    /// rows[k][c]: channel c at times[k].
    pub rows: Vec<Vec<f64>>,
    /// Solver counters of the run.
    pub stats: Stats,
    /// Wall-clock time of the run [s].
    pub wall_s: f64,
    /// What the initial-state analysis did.
    pub assembly: AssemblyReport,
    /// Set when the run stopped early: the message and the time reached.
    pub error: Option<(String, f64)>,
    /// Set when the caller interrupted the run ([`crate::progress::Progress::cancelled`]):
    /// the time of the last sample kept.
    pub interrupted: Option<f64>,
    /// Final solver state (t, y, y'), for follow-up analyses.
    pub last: Option<(f64, Vec<f64>, Vec<f64>)>,
    /// Modal coordinates of every modal body at every sample: (body, rows[k][mode]).
    pub modal: Vec<(BodyHandle, Vec<Vec<f64>>)>,
    /// Where the wall time went.
    pub phases: Phases,
    /// Body poses for the report's animation, when asked for.
    pub poses: Option<Poses>,
}

/// The position unknowns of every body (centre of mass, unit quaternion, modal
/// coordinates: `System::qo` layout) on the animation's own time grid, interpolated by
/// the integrator's dense output like the channels.
#[derive(Clone, Debug, Default)]
pub struct Poses {
    /// Times [s].
    pub times: Vec<f64>,
    /// q[k]: the position block of the state at times[k].
    pub q: Vec<Vec<f64>>,
}

/// Wall time of a run's phases [s] (they add up to `Samples::wall_s` but for the
/// bookkeeping between them).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Phases {
    /// The consistent initial state (assembly, velocity projection, accelerations and
    /// multipliers), when the run makes it rather than being handed one.
    pub start_s: f64,
    /// The integrator's set-up: the iteration matrix's structure, its fill-reducing
    /// order and column colouring, the first evaluation.
    pub solver_setup_s: f64,
    /// Stepping to the sample times.
    pub integration_s: f64,
    /// The output channels at the samples (interpolation and evaluation).
    pub outputs_s: f64,
}

/// Runs from `t0` (state from the model's initial values, or `start` if given) to
/// `t_end`, sampling every 1/rate seconds.
pub fn simulate(
    sys: &System,
    t0: f64,
    t_end: f64,
    rate: f64,
    opts: &SolverOptions,
    start: Option<(Vec<f64>, Vec<f64>)>,
    progress: &dyn crate::progress::Progress,
) -> Samples {
    simulate_with_poses(sys, t0, t_end, rate, 0.0, opts, start, progress)
}

/// [`simulate`], also recording the bodies' poses every 1/`pose_rate` seconds
/// ([`Samples::poses`]; 0: none). Pose times are at most as dense as the samples (the
/// rate is capped at `rate`), so the integrator's first call still aims at the first
/// sample and the steps are those of a run without poses.
#[allow(clippy::too_many_arguments)]
pub fn simulate_with_poses(
    sys: &System,
    t0: f64,
    t_end: f64,
    rate: f64,
    pose_rate: f64,
    opts: &SolverOptions,
    start: Option<(Vec<f64>, Vec<f64>)>,
    progress: &dyn crate::progress::Progress,
) -> Samples {
    let wall = Instant::now();
    let chans = channels(sys);
    let mut res = Samples {
        channels: chans.clone(),
        times: Vec::new(),
        rows: Vec::new(),
        stats: Stats::default(),
        wall_s: 0.0,
        assembly: AssemblyReport::default(),
        error: None,
        interrupted: None,
        last: None,
        modal: sys
            .model
            .each_body()
            .filter(|(_, b)| b.modal.as_ref().is_some_and(|m| !m.data.modes.is_empty()))
            .map(|(b, _)| (b, Vec::new()))
            .collect(),
        phases: Phases::default(),
        poses: None,
    };
    let pose_rate = pose_rate.min(rate);
    let mut poses = (pose_rate > 0.0).then(Poses::default);
    // Pose j at t0 + j / pose_rate, up to t_end.
    let n_poses = if pose_rate > 0.0 {
        ((t_end - t0) * pose_rate * (1.0 + 1e-12)).floor() as usize
    } else {
        0
    };
    let pose_time = |j: usize| t0 + j as f64 / pose_rate;
    let mut lap = Instant::now();
    let mut took = || {
        let s = lap.elapsed().as_secs_f64();
        lap = Instant::now();
        s
    };
    let (y0, yp0) = match start {
        Some(s) => s,
        None => {
            let (mut q, mut v) = sys.initial_q_v();
            let x = sys.ext_initial(&q, &v, 0.0);
            match initial_state(sys, t0, &mut q, &mut v, &x) {
                Ok((y, yp, rep)) => {
                    res.assembly = rep;
                    (y, yp)
                }
                Err(e) => {
                    res.error = Some((format!("initial state: {e}"), t0));
                    return res;
                }
            }
        }
    };
    res.phases.start_s = took();
    res.times.push(t0);
    res.rows.push(evaluate(sys, t0, &y0, &yp0));
    record_modal(sys, &mut res, &y0);
    if let Some(p) = &mut poses {
        p.times.push(t0);
        p.q.push(y0[..sys.nq].to_vec());
    }
    let mut next_pose = 1;
    res.phases.outputs_s += took();
    // BDF or Radau IIA, as `opts.method` says.
    let mut bdf = match Integrator::new(sys, t0, &y0, &yp0, opts.clone()) {
        Ok(b) => b,
        Err(e) => {
            res.error = Some((e.to_string(), t0));
            return res;
        }
    };
    res.phases.solver_setup_s = took();
    bdf.set_stop_time(t_end);
    let n = ((t_end - t0) * rate).round() as usize;
    progress.begin(n as u64);
    let mut y = vec![0.0; y0.len()];
    let mut yp = vec![0.0; y0.len()];
    'samples: for k in 1..=n {
        if progress.cancelled() {
            res.interrupted = res.times.last().copied();
            break;
        }
        let ts = if k == n { t_end } else { t0 + k as f64 / rate };
        // Poses before this sample: advancing to them takes the same steps (the
        // integrator does not shorten steps to reach an output time).
        let mut pose_here = false;
        while let Some(p) = poses.as_mut().filter(|_| next_pose <= n_poses) {
            let tp = pose_time(next_pose);
            if tp > ts + 1e-9 / rate {
                break;
            }
            next_pose += 1;
            if tp >= ts - 1e-9 / rate {
                pose_here = true;
                break;
            }
            if let Err(e) = reach(&mut bdf, tp) {
                res.error = Some(e);
                break 'samples;
            }
            bdf.interpolate(tp, &mut y, &mut yp);
            p.times.push(tp);
            p.q.push(y[..sys.nq].to_vec());
        }
        if let Err(e) = reach(&mut bdf, ts) {
            res.error = Some(e);
            break 'samples;
        }
        res.phases.integration_s += took();
        bdf.interpolate(ts, &mut y, &mut yp);
        res.times.push(ts);
        res.rows.push(evaluate(sys, ts, &y, &yp));
        record_modal(sys, &mut res, &y);
        if let Some(p) = poses.as_mut().filter(|_| pose_here) {
            p.times.push(ts);
            p.q.push(y[..sys.nq].to_vec());
        }
        progress.set(k as u64);
        res.phases.outputs_s += took();
    }
    res.phases.integration_s += took();
    unwrap_angles(&mut res);
    res.stats = bdf.stats().clone();
    res.stats.step_limiters = bdf.step_limiters(5);
    if let Some(&t) = res.times.last() {
        if res.error.is_none() && res.interrupted.is_none() {
            res.last = Some((t, y.clone(), yp.clone()));
        }
    }
    res.poses = poses;
    res.wall_s = wall.elapsed().as_secs_f64();
    res
}

/// Integrates to `t` (past any root on the way); the message and time of a failure.
fn reach<P: DaeProblem + ?Sized>(bdf: &mut Integrator<'_, P>, t: f64) -> Result<(), (String, f64)> {
    loop {
        match bdf.advance(t) {
            Ok(Advance::Reached) => return Ok(()),
            Ok(Advance::Root { .. }) => continue,
            Err(e) => return Err((e.to_string(), e.time().unwrap_or(bdf.t()))),
        }
    }
}

fn record_modal(sys: &System, res: &mut Samples, y: &[f64]) {
    for (b, rows) in &mut res.modal {
        // The body's number in the system's layout: its modal coordinates are columns of y.
        let k = b.index();
        let o = sys.qo[k] + 7;
        rows.push(y[o..o + sys.nm[k]].to_vec());
    }
}

/// Removes 2 pi jumps from angle channels so a turning crank reads continuously.
fn unwrap_angles(res: &mut Samples) {
    let tau = 2.0 * std::f64::consts::PI;
    for (c, ch) in res.channels.iter().enumerate() {
        if !ch.angle {
            continue;
        }
        let mut offset = 0.0;
        for k in 1..res.rows.len() {
            let prev = res.rows[k - 1][c];
            let cur = res.rows[k][c] + offset;
            let jump = ((cur - prev) / tau).round();
            offset -= jump * tau;
            res.rows[k][c] += offset;
        }
    }
}

impl Samples {
    /// The samples of channel `name`.
    pub fn channel(&self, name: &str) -> Option<Vec<f64>> {
        let c = self.channels.iter().position(|ch| ch.name == name)?;
        Some(self.rows.iter().map(|r| r[c]).collect())
    }
}
