//! `towride._towride`: the extension module under the Python package `towride`
//! (python/towride/__init__.py wraps it). Each function mirrors a CLI command (src/run.rs,
//! src/sweep.rs, src/validate.rs, src/sensitivity.rs) and hands back the same data the
//! command writes: the summaries as the JSON text the CLI writes (the Python side parses
//! it, so every number is the CLI's to the last digit) and the channels as NumPy arrays.
//! Every run releases the GIL, so Python threads run cases in parallel.

mod errors;

use std::path::{Path, PathBuf};

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use towride_app::job::{Job, RunResult};
use towride_app::scene::{self, Changes};
use towride_app::study::sensitivity::{self, Method, Settings};
use towride_app::sweep::exec::{run_sweep, run_sweep_with, Options};
use towride_app::sweep::Sweep;
use towride_app::validate::folder::{find_descriptors, summary_json, validate_folder_until};
use towride_mbs::input::{read_overrides, InputError, Loader, Override};
use towride_mbs::progress::Silent;

use errors::to_py;

/// A loader applying `overrides` (a run's overrides.toml) and then each `FILE:PATH=VALUE`
/// of `set`, as the CLI's `--overrides` and `--set` (src/inputs.rs).
fn loader(set: &[String], overrides: Option<&Path>) -> Result<Loader, InputError> {
    let mut all = match overrides {
        Some(f) => read_overrides(f)?,
        None => Vec::new(),
    };
    for s in set {
        all.push(Override::from_argument(s)?);
    }
    Ok(Loader::with_overrides(all))
}

/// The version, commit and the call that made a run, in its summary's `produced_by`.
fn stamp(job: &mut Job, call: &str) {
    job.produced_by = job.produced_by.clone().stamped(
        env!("CARGO_PKG_VERSION"),
        // The package's build carries no commit of its own (the CLI's build.rs sets it).
        option_env!("TOWRIDE_GIT_COMMIT").unwrap_or("unknown"),
        vec!["python".into(), call.into()],
    );
}

/// Builds and runs a scene or mechanism file as `towride run` does, writing its files to
/// `out` when given.
fn run_file(
    path: &Path,
    set: &[String],
    overrides: Option<&Path>,
    out: Option<&Path>,
) -> towride_app::Result<RunResult> {
    let loader = loader(set, overrides)?;
    let mut job = if scene::is_scene(path) {
        Job::from_scene_file(path, &Changes::default(), &loader)?
    } else {
        Job::from_file(path, &loader)?
    };
    stamp(&mut job, &format!("towride.run({})", path.display()));
    // Without files there is no report to hold the 3D view: its poses are not recorded.
    let job = if out.is_some() {
        job
    } else {
        job.without_view()
    };
    let mut res = job.run(&Silent)?;
    if let Some(dir) = out {
        towride_app::atomic::claim(
            dir,
            "run",
            &[
                "outputs.csv",
                "summary.json",
                "report.html",
                "plots.png",
                "overrides.toml",
            ],
            &[path.to_path_buf()],
        )
        .map_err(|e| towride_app::Error::io(dir, std::io::Error::other(e)))?;
        towride_app::report::write_run(&mut res, &job.system, dir)?;
    }
    Ok(res)
}

/// The raw result the Python `Result` wraps: time, channels, units, summary JSON and,
/// for a run the solver stopped, (message, time).
fn result_dict<'py>(py: Python<'py>, res: RunResult) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let s = &res.samples;
    d.set_item("time", PyArray1::from_slice(py, &s.times))?;
    let channels = PyDict::new(py);
    let units = PyDict::new(py);
    for (c, info) in s.channels.iter().enumerate() {
        let v: Vec<f64> = s.rows.iter().map(|r| r[c]).collect();
        channels.set_item(&info.name, PyArray1::from_vec(py, v))?;
        units.set_item(&info.name, info.unit)?;
    }
    d.set_item("channels", channels)?;
    d.set_item("units", units)?;
    d.set_item("summary_json", res.summary.to_json())?;
    d.set_item("failure", res.failure().map(|(m, t)| (m.to_string(), t)))?;
    Ok(d)
}

/// Runs one scene or mechanism file (see `towride.run`).
#[pyfunction]
#[pyo3(signature = (path, set=Vec::new(), overrides=None, out=None))]
fn run<'py>(
    py: Python<'py>,
    path: PathBuf,
    set: Vec<String>,
    overrides: Option<PathBuf>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let res = py
        .detach(|| run_file(&path, &set, overrides.as_deref(), out.as_deref()))
        .map_err(|e| to_py(py, e))?;
    result_dict(py, res)
}

/// Runs a sweep file (see `towride.sweep`); returns the JSON the CLI prints.
#[pyfunction]
#[pyo3(signature = (path, set=Vec::new(), overrides=None, out=None, jobs=None))]
fn sweep(
    py: Python<'_>,
    path: PathBuf,
    set: Vec<String>,
    overrides: Option<PathBuf>,
    out: Option<PathBuf>,
    jobs: Option<usize>,
) -> PyResult<String> {
    let go = || -> towride_app::Result<String> {
        let mut sw = Sweep::load(&path)?;
        sw.base = loader(&set, overrides.as_deref())?;
        let jobs = jobs.unwrap_or_else(cores);
        let res = match &out {
            None => run_sweep(&sw, (0, 1), jobs, &Silent)?,
            Some(dir) => {
                let opts = Options {
                    jobs,
                    resume: false,
                    keep_histories: false,
                    check: None,
                };
                run_sweep_with(&sw, (0, 1), dir, &opts, &Silent)?
            }
        };
        Ok(serde_json::to_string(&res).unwrap_or_default())
    };
    py.detach(go).map_err(|e| to_py(py, e))
}

/// Validates recorded runs (see `towride.validate`); returns the summary JSON.
#[pyfunction]
#[pyo3(signature = (path, set=Vec::new(), overrides=None, out=None, correct=true, max_shift_ms=100.0))]
fn validate(
    py: Python<'_>,
    path: PathBuf,
    set: Vec<String>,
    overrides: Option<PathBuf>,
    out: Option<PathBuf>,
    correct: bool,
    max_shift_ms: f64,
) -> PyResult<String> {
    let go = || -> towride_app::Result<String> {
        let files = find_descriptors(&path)?;
        let sim = towride_app::validate::simulator_with(loader(&set, overrides.as_deref())?);
        let opts = towride_app::validate::Options {
            correct,
            max_shift_s: max_shift_ms * 1e-3,
            ..Default::default()
        };
        let res = validate_folder_until(&files, sim.as_ref(), &opts, &|_, _| {}, &|| false);
        if let Some(dir) = &out {
            towride_app::validate::write_summary(&res, dir)?;
        }
        Ok(serde_json::to_string(&summary_json(&res)).unwrap_or_default())
    };
    py.detach(go).map_err(|e| to_py(py, e))
}

/// A sensitivity study (see `towride.sensitivity`); returns the study's JSON.
#[pyfunction]
#[pyo3(signature = (path, set=Vec::new(), overrides=None, out=None, params=Vec::new(),
    groups=Vec::new(), outputs=Vec::new(), method="oat", trajectories=10, range=None,
    seed=1, jobs=None), name = "sensitivity")]
#[allow(clippy::too_many_arguments)]
fn sensitivity_study(
    py: Python<'_>,
    path: PathBuf,
    set: Vec<String>,
    overrides: Option<PathBuf>,
    out: Option<PathBuf>,
    params: Vec<String>,
    groups: Vec<String>,
    outputs: Vec<String>,
    method: &str,
    trajectories: usize,
    range: Option<f64>,
    seed: u64,
    jobs: Option<usize>,
) -> PyResult<String> {
    let method = match method {
        "oat" => Method::Oat,
        "morris" => Method::Morris,
        m => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "method {m:?}: \"oat\" or \"morris\""
            )))
        }
    };
    // The CLI's rules (src/sensitivity.rs): OAT varies by +-10 % and takes no range.
    let range = match (method, range) {
        (Method::Oat, Some(r)) => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "range {r} applies to method=\"morris\"; OAT varies each value by +-10 %"
            )))
        }
        (_, r) => r.unwrap_or(0.3),
    };
    if !(range > 0.0 && range < 1.0) {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "range {range}: a fraction between 0 and 1"
        )));
    }
    let go = || -> towride_app::Result<String> {
        let s = Settings {
            file: path.clone(),
            params,
            groups,
            outputs,
            method,
            trajectories,
            levels: 4,
            range,
            seed,
            jobs: jobs.unwrap_or_else(cores),
            base: loader(&set, overrides.as_deref())?,
        };
        let mut study = sensitivity::run(&s, &Silent)?;
        if let Some(dir) = &out {
            sensitivity::write::write(&mut study, dir)?;
        }
        Ok(serde_json::to_string(&study).unwrap_or_default())
    };
    py.detach(go).map_err(|e| to_py(py, e))
}

fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[pymodule]
fn _towride(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity_study, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
