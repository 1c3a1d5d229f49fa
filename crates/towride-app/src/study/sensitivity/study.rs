//! A finished study: its outputs with their base values, each parameter's figures,
//! the runs that failed, and the status its files open with.

use serde::Serialize;

use super::{morris, Method, Param};

/// An output with its base value.
#[derive(Clone, Debug, Serialize)]
pub struct OutputInfo {
    /// `CHANNEL.measure`.
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// Value of the base run.
    pub base: f64,
    /// A `.abs_peak` output's signed sample at the base run's |peak|: whether the peak
    /// was a pull or a push, which its magnitude hides.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub base_signed: Option<f64>,
}

/// One parameter's results, per output in `Study::outputs` order.
#[derive(Clone, Debug, Serialize)]
pub struct ParamResult {
    /// The parameter.
    pub param: Param,
    /// OAT elasticities d ln y / d ln p (`None`: a run failed, or y is 0 or changes sign).
    pub elasticity: Vec<Option<f64>>,
    /// Morris statistics.
    pub morris: Vec<morris::Effects>,
    /// Morris mu* relative to the base output.
    pub mu_star_rel: Vec<f64>,
    /// Morris range of the scale factor [low, high].
    pub range: [f64; 2],
    /// Why a figure is missing (a base value of 0 has no relative change; no pair of
    /// Morris runs completed).
    pub note: Option<String>,
}

/// A run that failed.
#[derive(Clone, Debug, Serialize)]
pub struct FailedRun {
    /// The parameter values of the run (`name=factor`).
    pub changes: String,
    /// The error.
    pub error: String,
}

/// A finished study.
#[derive(Clone, Debug, Serialize)]
pub struct Study {
    /// Layout version ([`super::SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// "completed" (every run completed), "partial" (some failed: the figures they take
    /// part in are missing) or "interrupted" (stopped on request; some not run).
    pub status: String,
    /// What the reader must know first when the status is not "completed".
    pub note: Option<String>,
    /// The caller's overrides under every run (`FILE:PATH = VALUE`): a study of a
    /// shortened run is not one of the scene as filed.
    pub overrides: Vec<String>,
    /// Version, commit and command line of the program that made the study (the binary
    /// fills them in before writing).
    pub produced_by: crate::job::ProducedBy,
    /// The scene or mechanism.
    pub file: String,
    /// OAT or Morris.
    pub method: Method,
    /// The outputs.
    pub outputs: Vec<OutputInfo>,
    /// The parameters studied.
    pub params: Vec<ParamResult>,
    /// Values found but not studied: the model does not depend on them, or they cannot
    /// be varied (the reason follows the name).
    pub inactive: Vec<String>,
    /// Runs that failed.
    pub failed: Vec<FailedRun>,
    /// Runs not made: the study was interrupted before they started (or while they ran).
    pub not_run: usize,
    /// Runs made (the base run included).
    pub runs: usize,
    /// Parallel runs.
    pub jobs: usize,
    /// Morris trajectories, levels and seed.
    pub trajectories: usize,
    /// Morris levels.
    pub levels: usize,
    /// Morris seed.
    pub seed: u64,
    /// Wall time of the runs [s].
    pub runs_wall_s: f64,
    /// Wall time of the whole study (discovery included) [s].
    pub wall_s: f64,
    /// Files written.
    pub written: Vec<String>,
}

impl Study {
    /// Parameters ranked by output `output`'s |elasticity| (OAT) or mu* (Morris),
    /// largest first.
    pub fn ranking(&self, output: usize) -> Vec<&ParamResult> {
        let key = |p: &ParamResult| match self.method {
            Method::Oat => p
                .elasticity
                .get(output)
                .copied()
                .flatten()
                .map_or(-1.0, f64::abs),
            Method::Morris => p
                .mu_star_rel
                .get(output)
                .copied()
                .filter(|v| v.is_finite())
                .unwrap_or(-1.0),
        };
        let mut v: Vec<&ParamResult> = self.params.iter().collect();
        v.sort_by(|a, b| key(b).total_cmp(&key(a)));
        v
    }
}

/// The study's status and the sentence its outputs open with (see [`Study::status`]).
pub(super) fn verdict(runs: usize, failed: usize, not_run: usize) -> (String, Option<String>) {
    if not_run > 0 {
        let f = if failed > 0 {
            format!(" and {failed} failed")
        } else {
            String::new()
        };
        return (
            "interrupted".into(),
            Some(format!(
                "interrupted: {not_run} of {runs} runs not run{f}; the figures are partial \
                 (those without a completed run are left empty)"
            )),
        );
    }
    if failed > 0 {
        return (
            "partial".into(),
            Some(format!(
                "{failed} of {runs} runs failed: the figures they take part in are missing \
                 (the failures are listed with the study)"
            )),
        );
    }
    ("completed".into(), None)
}
