//! The table of a plan's run: one row per case (status, time reached, the hitch force's
//! max, min and |peak|, steps, wall time, folder), written as `plan_summary.csv` and `plan_summary.json`
//! beside the cases' own folders.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result as LibResult};
use crate::job::{Extremes, RunResult, RunStatus, RunSummary};
use crate::scene::plan::{Case, Plan};

/// Version of a plan run's summary layout (`plan_summary.json`). 2: the signed
/// `hitch_fx_peak_n` is gone for `hitch_fx` (max, min, |peak| with their times).
pub const SCHEMA_VERSION: u32 = 2;

/// A plan's cases run (or some of them): one row per case, written as the plan-level
/// table `plan_summary.csv` and `plan_summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct PlanRun {
    /// Layout version.
    pub schema_version: u32,
    /// The plan's name.
    pub plan: String,
    /// The plan file.
    pub file: String,
    /// "completed" (every case asked for ran to its end), "failed" (some stopped early)
    /// or "interrupted" (stopped on request; the cases not run are listed).
    pub status: String,
    /// One row per case asked for, in plan order.
    pub cases: Vec<PlanRow>,
}

/// One case of a plan run.
#[derive(Clone, Debug, Serialize)]
pub struct PlanRow {
    /// Case name.
    pub name: String,
    /// Obstacle.
    pub obstacle: String,
    /// Nominal speed [km/h].
    pub speed_km_h: f64,
    /// Trailer load case.
    pub load_case: String,
    /// "completed", "failed", "interrupted" or "not_run".
    pub status: String,
    /// Last sample time [s] (0 when not run).
    pub t_reached_s: f64,
    /// The longitudinal hitch force's (raw `hitch_fx`) max, min and |peak| [N] with
    /// their times [s].
    pub hitch_fx: Option<Extremes>,
    /// Accepted solver steps.
    pub steps: usize,
    /// Wall time, start included [s].
    pub wall_s: f64,
    /// The case's output folder.
    pub out: String,
    /// The solver's message when it stopped early.
    pub error: Option<String>,
    /// The case's whole summary (in the command's JSON, not in `plan_summary.json`,
    /// which points to each case's own `summary.json`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub summary: Option<Box<RunSummary>>,
}

impl PlanRun {
    /// An empty run of the plan read from `file`.
    pub fn new(plan: &Plan, file: &Path) -> PlanRun {
        PlanRun {
            schema_version: SCHEMA_VERSION,
            plan: plan.name.clone(),
            file: file.display().to_string(),
            status: "completed".into(),
            cases: Vec::new(),
        }
    }

    /// Records `case`, run into `out` with result `r` (`None`: not run).
    pub fn push(&mut self, case: &Case, out: &Path, r: Option<&RunResult>) {
        let s = r.map(|r| &r.summary);
        let hitch = s.and_then(|s| s.channels.get(crate::scene::channels::HITCH_FX));
        let status = match s.map(|s| s.status) {
            None => "not_run",
            Some(RunStatus::Completed) => "completed",
            Some(RunStatus::Failed) => "failed",
            Some(RunStatus::Interrupted) => "interrupted",
        };
        if status == "failed" && self.status == "completed" {
            self.status = "failed".into();
        }
        if status == "interrupted" || status == "not_run" {
            self.status = "interrupted".into();
        }
        self.cases.push(PlanRow {
            name: case.name.clone(),
            obstacle: case.obstacle.clone(),
            speed_km_h: case.speed_km_h,
            load_case: case.load_case.clone(),
            status: status.into(),
            t_reached_s: s.map_or(0.0, |s| s.t_reached_s),
            hitch_fx: hitch.map(|c| c.extremes),
            steps: s.map_or(0, |s| s.solver.steps),
            wall_s: s.map_or(0.0, |s| s.wall_s + s.start_wall_s),
            out: out.display().to_string(),
            error: s.and_then(|s| s.error.clone()),
            summary: s.map(|s| Box::new(s.clone())),
        });
    }

    /// Writes `plan_summary.csv` and `plan_summary.json` into `dir` (each whole or not
    /// at all); returns the CSV's path.
    pub fn write(&self, dir: &Path) -> LibResult<PathBuf> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let csv = dir.join("plan_summary.csv");
        let io = |e: std::io::Error| Error::io(&csv, e);
        let mut text = String::from(
            "case,obstacle,speed [km/h],load_case,status,t_reached [s],hitch_fx max [N],hitch_fx max time [s],hitch_fx min [N],hitch_fx min time [s],hitch_fx abs_peak [N],hitch_fx abs_peak time [s],steps,wall_time [s],out,error\n",
        );
        let extremes = |e: Option<&Extremes>| {
            let v = |x: f64| format!("{x:.6e}");
            e.map_or(",,,,,".into(), |e| {
                [e.max, e.t_max, e.min, e.t_min, e.abs_peak, e.t_abs_peak]
                    .map(v)
                    .join(",")
            })
        };
        for r in &self.cases {
            text.push_str(&format!(
                "{},{},{},{},{},{:.6},{},{},{:.3},{},\"{}\"\n",
                r.name,
                r.obstacle,
                r.speed_km_h,
                r.load_case,
                r.status,
                r.t_reached_s,
                extremes(r.hitch_fx.as_ref()),
                r.steps,
                r.wall_s,
                r.out,
                r.error.as_deref().unwrap_or("").replace('"', "'")
            ));
        }
        crate::atomic::write(&csv, text).map_err(io)?;
        let mut slim = self.clone();
        for r in &mut slim.cases {
            r.summary = None;
        }
        let json = dir.join("plan_summary.json");
        let text = serde_json::to_string_pretty(&slim).unwrap_or_default();
        crate::atomic::write(&json, text).map_err(|e| Error::io(&json, e))?;
        Ok(csv)
    }
}
