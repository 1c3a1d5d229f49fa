//! Running a scene programmatically (benchmarks, stress tests, sweeps, validation): load
//! with property overrides, assemble, start, integrate, and the figures that compare runs.

use std::path::Path;

use super::{Overrides, Scene, Start};
use crate::input::overrides::{self, Override};
use crate::model::run::{simulate, RunResult};
use crate::model::System;
use towride_solver::SolverOptions;

/// A finished scene run.
pub struct SceneRun {
    pub scene: Scene,
    pub result: RunResult,
    /// Wall time of start and run [s].
    pub wall_s: f64,
    /// Number of unknowns and of modal coordinates.
    pub equations: usize,
    pub modes: usize,
}

/// Loads `path` with property overrides `props` and scene overrides `o`, lets `tune`
/// adjust the solver options, then starts and runs it.
pub fn run(
    path: &Path,
    props: &[Override],
    o: &Overrides,
    tune: &dyn Fn(&mut SolverOptions),
) -> Result<SceneRun, String> {
    let scene = overrides::with(props, || super::load_with(path, o)).map_err(|e| e.to_string())?;
    let wall = std::time::Instant::now();
    let sys = System::new(scene.model().clone());
    let mut opts = scene.solver_for(&sys);
    tune(&mut opts);
    opts.validate(sys.size()).map_err(|e| e.to_string())?;
    let (start, _) = start(&scene, &opts)?;
    let result = simulate(
        &sys,
        0.0,
        scene.duration,
        scene.sample_rate,
        &opts,
        start,
        &crate::progress::Silent,
    );
    Ok(SceneRun {
        equations: sys.size(),
        modes: sys.nm.iter().sum(),
        scene,
        result,
        wall_s: wall.elapsed().as_secs_f64(),
    })
}

/// A consistent (y, y') to start from; `None`: the model's initial values.
pub type StartState = Option<(Vec<f64>, Vec<f64>)>;

/// The state at t = 0 by the scene's start mode, and what the start did.
pub fn start(
    s: &Scene,
    opts: &SolverOptions,
) -> Result<(StartState, Option<crate::model::start::StartReport>), String> {
    match s.start {
        Start::EquilibriumAtSpeed => {
            let (y, yp, rep) = crate::model::start::at_speed(s.model(), s.speed, s.settle, opts)?;
            Ok((Some((y, yp)), Some(rep)))
        }
        Start::Assembly => Ok((None, None)),
    }
}

impl SceneRun {
    /// Samples of channel `name`.
    pub fn channel(&self, name: &str) -> Option<Vec<f64>> {
        self.result.channel(name)
    }

    /// Largest magnitude of channel `name` (keeping its sign).
    pub fn peak(&self, name: &str) -> Option<f64> {
        let v = self.channel(name)?;
        v.into_iter().max_by(|a, b| a.abs().total_cmp(&b.abs()))
    }
}

/// RMS of the difference of two equally sampled signals, relative to the RMS of `b`.
pub fn rel_rms(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len()).max(1) as f64;
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / n;
    let r: f64 = b.iter().map(|y| y * y).sum::<f64>() / n;
    if r > 0.0 {
        (d / r).sqrt()
    } else {
        d.sqrt()
    }
}
