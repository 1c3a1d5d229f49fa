//! Mode selection from a finished run (the thesis's commercial-tool method, closing the
//! loop): the strain-energy shares a run's summary holds per modal body
//! (`summary.json`, `modal_energy`, [`crate::model::energy`]) select the modes of the
//! next run. A mode is kept when its share of the body's peak or of its time-integrated
//! strain energy reaches the threshold ([`crate::model::energy::select_by_energy`]'s
//! rule). Only modes the earlier run integrated can be kept: run the reference with
//! all modes (`selection.rule = "all"`) to rank them all.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::input::InputError;

/// One mode's shares in the earlier run.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ModeShare {
    /// Mode-table number (rigid-body modes counted).
    pub number: usize,
    /// Natural frequency [Hz].
    pub frequency_hz: f64,
    /// Share of the summed peak strain energies.
    pub share_peak: f64,
    /// Share of the strain-energy integral.
    pub share_integral: f64,
    /// Kept at the threshold.
    pub kept: bool,
}

/// One modal body's run-based selection.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct BodyModes {
    /// Body name in the model (`hitch`, `cross_member`).
    pub body: String,
    /// Every mode of the earlier run with its shares.
    pub modes: Vec<ModeShare>,
}

impl BodyModes {
    /// The mode numbers kept.
    pub fn kept(&self) -> Vec<usize> {
        self.modes
            .iter()
            .filter(|m| m.kept)
            .map(|m| m.number)
            .collect()
    }
}

/// The run-based selections of every modal body of an earlier run.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RunModes {
    /// The run's folder.
    pub run_dir: PathBuf,
    /// Share threshold (a fraction).
    pub min_energy_share: f64,
    /// Per modal body.
    pub bodies: Vec<BodyModes>,
}

impl RunModes {
    /// The selection of body `name`.
    pub fn body(&self, name: &str) -> Option<&BodyModes> {
        self.bodies.iter().find(|b| b.body == name)
    }
}

/// Reads `dir/summary.json` and selects, per modal body, the modes whose peak or
/// integral share reaches `min_energy_share` (a fraction in (0, 1)). `at` says where
/// the request was written, for errors.
pub fn from_run(
    dir: &Path,
    min_energy_share: f64,
    at: &InputError,
) -> Result<RunModes, InputError> {
    let err = |m: String| InputError {
        message: m,
        ..at.clone()
    };
    if !(min_energy_share > 0.0 && min_energy_share < 1.0) {
        return Err(err(format!(
            "energy-share threshold {min_energy_share} must be a fraction between 0 and 1"
        )));
    }
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        err(format!(
            "cannot read {}: {e} (run the scene there first)",
            path.display()
        ))
    })?;
    let v: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| err(format!("{} is not a run summary: {e}", path.display())))?;
    let bodies = v["modal_energy"].as_array().ok_or_else(|| {
        err(format!(
            "{} holds no strain-energy shares (`modal_energy`)",
            path.display()
        ))
    })?;
    let mut out = Vec::new();
    for b in bodies {
        let name = b["body"].as_str().unwrap_or_default().to_string();
        let modes = b["modes"]
            .as_array()
            .map(|ms| {
                ms.iter()
                    .map(|m| {
                        let f = |k: &str| m[k].as_f64().unwrap_or(0.0);
                        ModeShare {
                            number: m["number"].as_u64().unwrap_or(0) as usize,
                            frequency_hz: f("frequency_hz"),
                            share_peak: f("share_peak"),
                            share_integral: f("share_integral"),
                            kept: f("share_peak") >= min_energy_share
                                || f("share_integral") >= min_energy_share,
                        }
                    })
                    .collect::<Vec<_>>()
            })
            .unwrap_or_default();
        if modes.iter().any(|m| m.number <= 6) {
            return Err(err(format!(
                "{}: body `{name}` lists a mode number below 7",
                path.display()
            )));
        }
        out.push(BodyModes { body: name, modes });
    }
    Ok(RunModes {
        run_dir: dir.to_path_buf(),
        min_energy_share,
        bodies: out,
    })
}

/// One mode in the side-by-side view of the two selections.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ComparedMode {
    /// Mode-table number.
    pub number: usize,
    /// Natural frequency [Hz].
    pub frequency_hz: f64,
    /// Kept by the body file's a-priori rule.
    pub a_priori: bool,
    /// The load-path rule's largest weighted share, if that rule is in force.
    pub a_priori_share: Option<f64>,
    /// The earlier run's shares (peak, integral); `None`: the run did not integrate it.
    pub run_shares: Option<[f64; 2]>,
    /// Kept by the run-based selection.
    pub run_based: bool,
}

/// The a-priori and the run-based selections of one body side by side.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Comparison {
    /// Layout version.
    pub schema_version: u32,
    /// The body file's rule in words.
    pub a_priori_rule: String,
    /// The run folder and threshold.
    pub run_dir: String,
    /// Threshold of the run-based selection (fraction).
    pub min_energy_share: f64,
    /// The body.
    pub body: String,
    /// Every elastic mode.
    pub modes: Vec<ComparedMode>,
    /// Mode numbers kept a priori.
    pub a_priori_modes: Vec<usize>,
    /// Mode numbers kept by the run.
    pub run_based_modes: Vec<usize>,
}

/// Compares the a-priori selection of `report` with the run-based one of `run`.
pub fn compare(
    report: &super::report::ModesReport,
    run: &RunModes,
    body: &BodyModes,
) -> Comparison {
    let modes: Vec<ComparedMode> = report
        .modes
        .iter()
        .filter(|m| m.kind == "elastic")
        .map(|m| {
            let r = body.modes.iter().find(|x| x.number == m.index);
            ComparedMode {
                number: m.index,
                frequency_hz: m.frequency_hz,
                a_priori: m.selected,
                a_priori_share: m.energy_share,
                run_shares: r.map(|x| [x.share_peak, x.share_integral]),
                run_based: r.is_some_and(|x| x.kept),
            }
        })
        .collect();
    Comparison {
        schema_version: 1,
        a_priori_rule: report.selection_rule.clone(),
        run_dir: run.run_dir.display().to_string(),
        min_energy_share: run.min_energy_share,
        body: body.body.clone(),
        a_priori_modes: report.selected_modes.clone(),
        run_based_modes: body.kept(),
        modes,
    }
}
