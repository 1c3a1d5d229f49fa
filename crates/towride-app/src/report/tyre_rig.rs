//! What a tyre-rig run (simulated by `towride_mbs::tyre::rig`) reports: rim-load peaks, contact loss, solver effort, and the
//! history as CSV and a plot.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result};
use crate::report::lineplot::{line_panels, Line, LinePanel};
use towride_mbs::tyre::rig::{RigCase, RigRun, RigSample, RigSetup};

/// Version of the rig summary's layout.
pub const SCHEMA_VERSION: u32 = 1;

/// The figures of one rig run.
#[derive(Clone, Debug, Serialize)]
pub struct RigSummary {
    /// Layout version.
    pub schema_version: u32,
    /// The rig file.
    pub file: String,
    /// "cleat" or "quarter".
    pub rig: &'static str,
    /// The tyre file and model.
    pub tyre: String,
    /// The road.
    pub road: String,
    /// Relative tolerance used.
    pub rtol: f64,
    /// Last sample time [s].
    pub t_end_s: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected_steps: usize,
    /// Residual evaluations.
    pub residual_evals: usize,
    /// Wall time [s].
    pub wall_s: f64,
    /// Largest vertical rim load [N].
    pub hub_fz_max_n: f64,
    /// Smallest vertical rim load [N].
    pub hub_fz_min_n: f64,
    /// Largest longitudinal rim load [N].
    pub hub_fx_max_n: f64,
    /// Smallest longitudinal rim load [N].
    pub hub_fx_min_n: f64,
    /// Smallest contact normal force [N].
    pub normal_force_min_n: f64,
    /// Time without contact [s].
    pub airborne_s: f64,
    /// Rolling radius at the end [m].
    pub final_rolling_radius_m: f64,
    /// Tyre deflection at the end [m].
    pub final_deflection_m: f64,
    /// The history CSV, once written.
    pub csv: Option<String>,
    /// The plot, once written.
    pub png: Option<String>,
}

impl RigSummary {
    /// The figures of `run`, a run of `case` (read from `file`) at `rtol`.
    pub fn of(case: &RigCase, file: &Path, rtol: f64, run: &RigRun) -> Result<RigSummary> {
        let (rig, tyre, road) = match &case.setup {
            RigSetup::Cleat { rig, .. } => ("cleat", &rig.tyre, &rig.road),
            RigSetup::Quarter { rig, .. } => ("quarter", &rig.tyre, &rig.road),
            RigSetup::Lateral { rig, .. } => ("lateral", &rig.tyre, &rig.road),
        };
        let s = &run.samples;
        let last = s.last().ok_or_else(|| {
            Error::from(crate::scene::SceneError::RunFailed {
                name: file.display().to_string(),
                t: 0.0,
                message: "no output sample".into(),
            })
        })?;
        let max = |f: &dyn Fn(&RigSample) -> f64| s.iter().map(f).fold(f64::MIN, f64::max);
        let min = |f: &dyn Fn(&RigSample) -> f64| s.iter().map(f).fold(f64::MAX, f64::min);
        let dt = if s.len() > 1 {
            s[1].t_s - s[0].t_s
        } else {
            0.0
        };
        Ok(RigSummary {
            schema_version: SCHEMA_VERSION,
            file: file.display().to_string(),
            rig,
            tyre: format!("{} ({:?})", tyre.params().file.display(), tyre.kind()),
            road: road.describe(),
            rtol,
            t_end_s: last.t_s,
            steps: run.stats.steps,
            rejected_steps: run.stats.rejected_steps,
            residual_evals: run.stats.residual_evals,
            wall_s: run.wall_s,
            hub_fz_max_n: max(&|x| x.hub_fz_n),
            hub_fz_min_n: min(&|x| x.hub_fz_n),
            hub_fx_max_n: max(&|x| x.hub_fx_n),
            hub_fx_min_n: min(&|x| x.hub_fx_n),
            normal_force_min_n: min(&|x| x.normal_force_n),
            airborne_s: s.iter().filter(|x| x.normal_force_n == 0.0).count() as f64 * dt,
            final_rolling_radius_m: last.rolling_radius_m,
            final_deflection_m: last.deflection_m,
            csv: None,
            png: None,
        })
    }

    /// Writes `<name>.csv` (the history, units in the headers) and `<name>.png` into
    /// `dir`.
    pub fn write(&mut self, run: &RigRun, dir: &Path, name: &str) -> Result<(PathBuf, PathBuf)> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let csv = dir.join(format!("{name}.csv"));
        let io = |e: csv::Error| Error::io(&csv, e.into());
        let mut w = csv::Writer::from_path(&csv).map_err(io)?;
        // Field names carry their units (serde names of RigSample).
        for s in &run.samples {
            w.serialize(s).map_err(io)?;
        }
        w.flush().map_err(|e| Error::io(&csv, e))?;
        let png = dir.join(format!("{name}.png"));
        plot(&png, run, name)?;
        self.csv = Some(csv.display().to_string());
        self.png = Some(png.display().to_string());
        Ok((csv, png))
    }
}

fn plot(path: &Path, run: &RigRun, name: &str) -> Result<()> {
    let s = &run.samples;
    let series = |label: &str, f: &dyn Fn(&RigSample) -> f64| Line {
        label: label.into(),
        points: s.iter().map(|x| (x.t_s, f(x))).collect(),
    };
    line_panels(
        path,
        &[
            LinePanel {
                title: format!("{name}: load on the rim"),
                x_label: "time [s]".into(),
                y_label: "force [N]".into(),
                lines: vec![
                    series("Fz", &|x| x.hub_fz_n),
                    series("Fx", &|x| x.hub_fx_n),
                    series("normal contact force", &|x| x.normal_force_n),
                ],
            },
            LinePanel {
                title: format!("{name}: wheel centre and effective road"),
                x_label: "time [s]".into(),
                y_label: "height [mm]".into(),
                lines: vec![
                    series("wheel centre z", &|x| x.z_m * 1e3),
                    series("effective road height", &|x| x.effective_height_m * 1e3),
                ],
            },
        ],
        1,
    )?;
    Ok(())
}
