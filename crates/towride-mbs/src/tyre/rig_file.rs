//! Rig files (TOML, read with [`crate::input::Source`]): `[tyre]`, `[road]`, `[rig]` (kind
//! "cleat", "quarter" or "lateral"), optional `[solver]`, `[output]`; see
//! `docs/road_tyre.md` and `scenes/tyre_rigs/`.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::input::InputError;
use crate::path;
use crate::road::Road;
use towride_solver::SolverError;

use super::rig::{rig_options, CleatRig, QuarterRig, RigRun, Spin};
use super::rig_lateral::LateralRig;
use super::{Tyre, TyreKind};

/// A rig file: `[tyre]`, `[road]`, `[rig]`, optional `[solver]` and `[output]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RigFile {
    tyre: TyreRef,
    road: RoadRef,
    rig: RigSection,
    #[serde(default)]
    solver: SolverSection,
    output: OutputSection,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TyreRef {
    file: String,
    model: TyreKind,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RoadRef {
    file: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
enum RigSection {
    Cleat {
        speed_m_s: f64,
        start_x_m: f64,
        duration_s: f64,
        load_n: f64,
        spin: Spin,
        rim_iyy_kg_m2: f64,
    },
    Quarter {
        speed_m_s: f64,
        start_x_m: f64,
        duration_s: f64,
        mass_kg: f64,
        rim_iyy_kg_m2: f64,
        damper_n_s_m: f64,
        /// Release height above first contact [m]; absent = start in equilibrium.
        #[serde(default)]
        drop_height_m: Option<f64>,
    },
    Lateral {
        speed_m_s: f64,
        start_x_m: f64,
        spin: Spin,
        rim_iyy_kg_m2: f64,
        /// Steady sweep: loads and slip angles, run length per point.
        loads_n: Vec<f64>,
        slip_angles_deg: Vec<f64>,
        settle_s: f64,
        /// Step response: load, slip angle and run length.
        step_load_n: f64,
        step_angle_deg: f64,
        duration_s: f64,
        /// Optional reference table (relative to the rig file).
        #[serde(default)]
        reference_csv: Option<String>,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SolverSection {
    #[serde(default = "default_rtol")]
    rtol: f64,
}

fn default_rtol() -> f64 {
    1e-6
}

impl Default for SolverSection {
    fn default() -> Self {
        SolverSection {
            rtol: default_rtol(),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct OutputSection {
    dt_s: f64,
}

/// A rig read from a file, ready to run.
pub enum RigSetup {
    /// A cleat rig run for `duration` seconds.
    Cleat {
        /// The rig.
        rig: CleatRig,
        /// Run length [s].
        duration: f64,
    },
    /// A quarter rig run for `duration` seconds, dropped or from rest.
    Quarter {
        /// The rig.
        rig: QuarterRig,
        /// Run length [s].
        duration: f64,
        /// Drop height above first contact [m]; `None` starts at rest in equilibrium.
        drop: Option<f64>,
    },
    /// A side-slip rig: a step in slip angle (`rig`, run for `duration` seconds) and a
    /// steady sweep over loads and slip angles.
    Lateral {
        /// The step-response rig.
        rig: LateralRig,
        /// Run length of the step response [s].
        duration: f64,
        /// The steady sweep.
        sweep: LateralSweep,
    },
}

/// The steady slip-angle sweep of a lateral rig file.
pub struct LateralSweep {
    /// Forward speed [m/s].
    pub speed: f64,
    /// Vertical loads [N].
    pub loads: Vec<f64>,
    /// Slip angles [rad].
    pub alphas: Vec<f64>,
    /// Run length per point [s].
    pub settle: f64,
    /// Driven or free rim.
    pub spin: Spin,
    /// Rim spin inertia [kg m^2].
    pub rim_iyy: f64,
    /// Reference table to compare with, if any.
    pub reference: Option<PathBuf>,
}

/// A rig file read and checked.
pub struct RigCase {
    /// The rig file.
    pub file: PathBuf,
    /// The rig with its run settings.
    pub setup: RigSetup,
    /// Relative tolerance of the run (file's `[solver] rtol`).
    pub rtol: f64,
    /// Output sample interval [s] (file's `[output] dt_s`).
    pub dt: f64,
}

impl RigCase {
    /// Reads and checks a rig file; the tyre and road paths are relative to it.
    pub fn from_file(path: &Path, loader: &crate::input::Loader) -> Result<RigCase, InputError> {
        let src = loader.toml(path)?;
        let f: RigFile = src.parse()?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let tyre = Tyre::from_file(&dir.join(&f.tyre.file), f.tyre.model, loader)?;
        let road = Road::from_file(&dir.join(&f.road.file), loader)?;
        let rtol = src.positive(&path!["solver", "rtol"], f.solver.rtol)?;
        let dt = src.positive(&path!["output", "dt_s"], f.output.dt_s)?;
        let setup = match f.rig {
            RigSection::Cleat {
                speed_m_s,
                start_x_m,
                duration_s,
                load_n,
                spin,
                rim_iyy_kg_m2,
            } => {
                src.non_negative(&path!["rig", "speed_m_s"], speed_m_s)?;
                src.finite(&path!["rig", "start_x_m"], start_x_m)?;
                src.positive(&path!["rig", "duration_s"], duration_s)?;
                src.positive(&path!["rig", "load_n"], load_n)?;
                src.positive(&path!["rig", "rim_iyy_kg_m2"], rim_iyy_kg_m2)?;
                RigSetup::Cleat {
                    rig: CleatRig::new(
                        tyre,
                        road,
                        speed_m_s,
                        start_x_m,
                        load_n,
                        spin,
                        rim_iyy_kg_m2,
                    ),
                    duration: duration_s,
                }
            }
            RigSection::Quarter {
                speed_m_s,
                start_x_m,
                duration_s,
                mass_kg,
                rim_iyy_kg_m2,
                damper_n_s_m,
                drop_height_m,
            } => {
                src.non_negative(&path!["rig", "speed_m_s"], speed_m_s)?;
                src.finite(&path!["rig", "start_x_m"], start_x_m)?;
                src.positive(&path!["rig", "duration_s"], duration_s)?;
                src.positive(&path!["rig", "mass_kg"], mass_kg)?;
                src.positive(&path!["rig", "rim_iyy_kg_m2"], rim_iyy_kg_m2)?;
                src.non_negative(&path!["rig", "damper_n_s_m"], damper_n_s_m)?;
                if let Some(d) = drop_height_m {
                    src.non_negative(&path!["rig", "drop_height_m"], d)?;
                }
                RigSetup::Quarter {
                    rig: QuarterRig::new(
                        tyre,
                        road,
                        speed_m_s,
                        start_x_m,
                        mass_kg,
                        rim_iyy_kg_m2,
                        damper_n_s_m,
                    ),
                    duration: duration_s,
                    drop: drop_height_m,
                }
            }
            RigSection::Lateral {
                speed_m_s,
                start_x_m,
                spin,
                rim_iyy_kg_m2,
                loads_n,
                slip_angles_deg,
                settle_s,
                step_load_n,
                step_angle_deg,
                duration_s,
                reference_csv,
            } => {
                src.positive(&path!["rig", "speed_m_s"], speed_m_s)?;
                src.finite(&path!["rig", "start_x_m"], start_x_m)?;
                src.positive(&path!["rig", "rim_iyy_kg_m2"], rim_iyy_kg_m2)?;
                src.positive(&path!["rig", "settle_s"], settle_s)?;
                src.positive(&path!["rig", "step_load_n"], step_load_n)?;
                src.positive(&path!["rig", "duration_s"], duration_s)?;
                for (i, l) in loads_n.iter().enumerate() {
                    src.positive(&path!["rig", "loads_n", i], *l)?;
                }
                for (i, a) in slip_angles_deg.iter().chain([&step_angle_deg]).enumerate() {
                    src.finite(&path!["rig", "slip_angles_deg", i], *a)?;
                    if a.abs() >= 45.0 {
                        return Err(src.error(
                            &path!["rig", "slip_angles_deg", i],
                            format!("a slip angle of {a} deg is outside the rig's range (|alpha| < 45 deg)"),
                        ));
                    }
                }
                let mut rig = LateralRig::new(
                    tyre.clone(),
                    road.clone(),
                    speed_m_s,
                    step_angle_deg.to_radians(),
                    start_x_m,
                    step_load_n,
                    spin,
                    rim_iyy_kg_m2,
                );
                rig.step = true;
                RigSetup::Lateral {
                    rig,
                    duration: duration_s,
                    sweep: LateralSweep {
                        speed: speed_m_s,
                        loads: loads_n,
                        alphas: slip_angles_deg.iter().map(|a| a.to_radians()).collect(),
                        settle: settle_s,
                        spin,
                        rim_iyy: rim_iyy_kg_m2,
                        reference: reference_csv.map(|r| dir.join(r)),
                    },
                }
            }
        };
        Ok(RigCase {
            file: path.to_path_buf(),
            setup,
            rtol,
            dt,
        })
    }

    /// The steady sweep of a lateral rig file (`None` for the other rigs), at the file's
    /// tolerance or `rtol`.
    pub fn lateral_sweep(
        &self,
        rtol: Option<f64>,
    ) -> Option<Result<Vec<super::rig_lateral::LateralPoint>, SolverError>> {
        let RigSetup::Lateral { rig, sweep: w, .. } = &self.setup else {
            return None;
        };
        Some(super::rig_lateral::sweep(
            &rig.tyre,
            &rig.road,
            w.speed,
            &w.loads,
            &w.alphas,
            w.settle,
            w.spin,
            w.rim_iyy,
            rtol.unwrap_or(self.rtol),
        ))
    }

    /// Runs the case at its own tolerance (or `rtol` if given).
    pub fn run(&self, rtol: Option<f64>) -> Result<RigRun, SolverError> {
        let rtol = rtol.unwrap_or(self.rtol);
        match &self.setup {
            RigSetup::Cleat { rig, duration } => {
                let opts = rig_options(&rig.tyre, rtol, &[1e-3]);
                rig.run(*duration, self.dt, &opts)
            }
            RigSetup::Quarter {
                rig,
                duration,
                drop,
            } => {
                let opts = rig_options(&rig.tyre, rtol, &[1e-6, 1e-4, 1e-3]);
                rig.run(*drop, *duration, self.dt, &opts)
            }
            RigSetup::Lateral { rig, duration, .. } => {
                let opts = rig_options(&rig.tyre, rtol, &[1e-3]);
                rig.run(*duration, self.dt, &opts)
            }
        }
    }
}
