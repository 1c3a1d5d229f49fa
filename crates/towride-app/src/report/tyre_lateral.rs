//! What a lateral tyre rig (`towride_mbs::tyre::rig_lateral`) reports: the steady
//! F_y(alpha), M_z(alpha) of the rig beside the Magic Formula evaluated directly and a
//! reference table (when the rig file names one), and the step response in slip angle
//! against the first-order law with the relaxation length; written as CSV and a figure.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result};
use crate::report::figure::{render, Figure, Panel, Style, Trace, PALETTE};
use towride_mbs::tyre::rig::RigRun;
use towride_mbs::tyre::rig_lateral::{LateralPoint, ReferencePoint};

/// Agreement of the sweep with a reference, and the step response.
#[derive(Clone, Debug, Serialize)]
pub struct LateralSummary {
    /// The steady points.
    pub points: Vec<LateralPoint>,
    /// Largest |F_y rig - F_y formula| [N] and |M_z rig - M_z formula| [N m].
    pub max_dev_formula_fy_n: f64,
    /// Largest |M_z rig - M_z formula| [N m].
    pub max_dev_formula_mz_n_m: f64,
    /// Largest |F_y rig - F_y reference| [N], over the points the reference has.
    pub max_dev_reference_fy_n: Option<f64>,
    /// Largest |M_z rig - M_z reference| [N m].
    pub max_dev_reference_mz_n_m: Option<f64>,
    /// Points compared with the reference.
    pub reference_points: usize,
    /// Relaxation length of the tyre sigma_alpha [m].
    pub sigma_alpha_m: f64,
    /// Distance rolled until tan(alpha') reached 1 - 1/e of its final value [m].
    pub step_distance_63_m: Option<f64>,
    /// Files written.
    pub csv: Option<String>,
    /// The figure.
    pub png: Option<String>,
}

/// The reference row at (load, kappa 0, alpha), if the table has it.
fn reference_at(r: &[ReferencePoint], load: f64, alpha: f64) -> Option<ReferencePoint> {
    r.iter()
        .find(|p| {
            (p.fz_n - load).abs() < 1e-6 && p.kappa == 0.0 && (p.alpha_rad - alpha).abs() < 1e-9
        })
        .copied()
}

/// Distance rolled at `speed` until the step response's tan(alpha') first reaches
/// 1 - 1/e of tan(`alpha`) (linear interpolation between samples).
pub fn step_distance_63(run: &RigRun, speed: f64, alpha: f64) -> Option<f64> {
    let target = (1.0 - (-1.0f64).exp()) * alpha.tan();
    let s = &run.samples;
    s.windows(2).find_map(|w| {
        let (a, b) = (w[0].slip_angle_rad.tan(), w[1].slip_angle_rad.tan());
        ((a - target) * (b - target) <= 0.0 && a != b).then(|| {
            let t = w[0].t_s + (target - a) / (b - a) * (w[1].t_s - w[0].t_s);
            speed * t
        })
    })
}

impl LateralSummary {
    /// Compares the sweep with the formula and the reference; `step` is the step response
    /// at `step_alpha` and `speed`.
    pub fn of(
        points: Vec<LateralPoint>,
        reference: &[ReferencePoint],
        sigma_alpha: f64,
        step: &RigRun,
        speed: f64,
        step_alpha: f64,
    ) -> LateralSummary {
        let maxf = |f: &dyn Fn(&LateralPoint) -> f64| points.iter().map(f).fold(0.0, f64::max);
        let mut dev_fy: Option<f64> = None;
        let mut dev_mz: Option<f64> = None;
        let mut n = 0;
        for p in &points {
            if let Some(r) = reference_at(reference, p.load_n, p.alpha_rad) {
                n += 1;
                dev_fy = Some(dev_fy.unwrap_or(0.0).max((p.fy_n - r.fy_n).abs()));
                dev_mz = Some(dev_mz.unwrap_or(0.0).max((p.mz_n_m - r.mz_n_m).abs()));
            }
        }
        LateralSummary {
            max_dev_formula_fy_n: maxf(&|p| (p.fy_n - p.fy_formula_n).abs()),
            max_dev_formula_mz_n_m: maxf(&|p| (p.mz_n_m - p.mz_formula_n_m).abs()),
            max_dev_reference_fy_n: dev_fy,
            max_dev_reference_mz_n_m: dev_mz,
            reference_points: n,
            sigma_alpha_m: sigma_alpha,
            step_distance_63_m: step_distance_63(step, speed, step_alpha),
            points,
            csv: None,
            png: None,
        }
    }

    /// Writes `<name>_sweep.csv` (the steady points) and `<name>_lateral.png` (F_y and
    /// M_z against the slip angle per load: rig dots, `formula` (load, alpha) -> (F_y,
    /// M_z) as a line on a fine grid, reference thin dark line; the step response against
    /// the first-order law) into `dir`.
    #[allow(clippy::too_many_arguments)]
    pub fn write(
        &mut self,
        dir: &Path,
        name: &str,
        formula: &dyn Fn(f64, f64) -> (f64, f64),
        reference: &[ReferencePoint],
        reference_label: &str,
        step: &RigRun,
        speed: f64,
        step_alpha: f64,
    ) -> Result<(PathBuf, PathBuf)> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let csv = dir.join(format!("{name}_sweep.csv"));
        let io = |e: csv::Error| Error::io(&csv, e.into());
        let mut w = csv::Writer::from_path(&csv).map_err(io)?;
        for p in &self.points {
            w.serialize(p).map_err(io)?;
        }
        w.flush().map_err(|e| Error::io(&csv, e))?;
        let png = dir.join(format!("{name}_lateral.png"));
        let mut loads: Vec<f64> = self.points.iter().map(|p| p.load_n).collect();
        loads.dedup();
        let deg = |a: f64| a.to_degrees();
        let (a_lo, a_hi) = self.points.iter().fold((0.0f64, 0.0f64), |(l, h), p| {
            (l.min(p.alpha_rad), h.max(p.alpha_rad))
        });
        let grid: Vec<f64> = (0..=400)
            .map(|k| a_lo + (a_hi - a_lo) * k as f64 / 400.0)
            .collect();
        let mut fy = Panel::new("steady lateral force F_y", "slip angle [deg]", "F_y [N]");
        let mut mz = Panel::new(
            "steady aligning moment M_z",
            "slip angle [deg]",
            "M_z [N m]",
        );
        // A round symmetric range, so the ticks land on it.
        let r = (a_lo.abs().max(a_hi.abs()).to_degrees() / 10.0)
            .ceil()
            .max(1.0)
            * 10.0;
        fy.x.range = Some((-r, r));
        mz.x.range = Some((-r, r));
        for (i, &load) in loads.iter().enumerate() {
            let pts: Vec<&LateralPoint> = self.points.iter().filter(|p| p.load_n == load).collect();
            let c = PALETTE[i % PALETTE.len()];
            let refs: Vec<ReferencePoint> = pts
                .iter()
                .filter_map(|p| reference_at(reference, load, p.alpha_rad))
                .collect();
            type Get<'a, T> = &'a dyn Fn(&T) -> f64;
            let panels: [(&mut Panel, bool, Get<LateralPoint>, Get<ReferencePoint>); 2] = [
                (&mut fy, true, &|p| p.fy_n, &|r| r.fy_n),
                (&mut mz, false, &|p| p.mz_n_m, &|r| r.mz_n_m),
            ];
            for (panel, is_fy, val, rval) in panels {
                panel.traces.push(Trace::new(
                    format!("Magic Formula, {load:.0} N"),
                    grid.iter()
                        .map(|&a| {
                            let (f, m) = formula(load, a);
                            (deg(a), if is_fy { f } else { m })
                        })
                        .collect(),
                    Style::side(i, false),
                ));
                if !refs.is_empty() {
                    panel.traces.push(Trace::new(
                        format!("{reference_label}, {load:.0} N"),
                        refs.iter().map(|r| (deg(r.alpha_rad), rval(r))).collect(),
                        Style::side(i, true),
                    ));
                }
                panel.traces.push(Trace::new(
                    format!("rig, {load:.0} N"),
                    pts.iter().map(|p| (deg(p.alpha_rad), val(p))).collect(),
                    Style::dots(c, 5.0),
                ));
            }
        }
        let mut st = Panel::new(
            format!(
                "step to {:.1} deg: sigma_alpha = {:.3} m",
                step_alpha.to_degrees(),
                self.sigma_alpha_m
            ),
            "distance rolled s [m]",
            "tan(alpha') / tan(alpha)",
        );
        let ta = step_alpha.tan();
        let every = (step.samples.len() / 60).max(1);
        st.traces.push(Trace::new(
            "rig",
            step.samples
                .iter()
                .step_by(every)
                .map(|x| (speed * x.t_s, x.slip_angle_rad.tan() / ta))
                .collect(),
            Style::dots(PALETTE[1], 4.0),
        ));
        st.traces.push(Trace::new(
            "1 - exp(-s / sigma_alpha)",
            step.samples
                .iter()
                .map(|x| {
                    let s = speed * x.t_s;
                    (s, 1.0 - (-s / self.sigma_alpha_m).exp())
                })
                .collect(),
            Style::side(0, true),
        ));
        let _ = name;
        let fig = Figure::new(vec![fy, mz, st], 3);
        render(&png, &fig)?;
        self.csv = Some(csv.display().to_string());
        self.png = Some(png.display().to_string());
        Ok((csv, png))
    }
}
