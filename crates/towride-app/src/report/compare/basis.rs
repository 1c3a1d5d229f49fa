//! The Craig-Bampton basis of each modal body of a run, from its `summary.json`: the
//! body, the scene's hitch variant for the hitch (another crossbeam, other mode shapes)
//! and the kept modes (numbers and frequencies; `modal_energy`). The modal coordinates
//! `<body>_eta_<k>` of two runs are amplitudes of the k-th kept mode shape: compared
//! across different bases they mean nothing.

use serde::Serialize;

/// One modal body's basis in one run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Basis {
    /// The modal body (`hitch`): its coordinates are the channels `<body>_eta_<k>`.
    pub body: String,
    /// The scene's hitch variant, for the hitch body.
    pub variant: Option<u64>,
    /// The kept modes: (number in the file's mode table, frequency [Hz]).
    pub modes: Vec<(u64, f64)>,
}

impl Basis {
    /// Whether `other` is the same basis: same variant, same modes at the same
    /// frequencies (1e-6 relative: the summary's printed digits).
    pub fn same(&self, other: &Basis) -> bool {
        self.body == other.body
            && self.variant == other.variant
            && self.modes.len() == other.modes.len()
            && self
                .modes
                .iter()
                .zip(&other.modes)
                .all(|(a, b)| a.0 == b.0 && (a.1 - b.1).abs() <= 1e-6 * a.1.abs().max(b.1.abs()))
    }

    /// `variant 1, modes 7-8-9...` for the text, JSON and page.
    pub fn describe(&self) -> String {
        let modes: Vec<String> = self.modes.iter().map(|m| m.0.to_string()).collect();
        let variant = self
            .variant
            .map_or(String::new(), |v| format!("variant {v}, "));
        format!("{variant}{} modes ({})", modes.len(), modes.join(" "))
    }
}

/// The bases in a run's summary (none when it lists no modal body).
pub fn bases(summary: &serde_json::Value) -> Vec<Basis> {
    let variant = summary
        .get("scene")
        .and_then(|s| s.get("hitch_variant"))
        .and_then(|v| v.as_u64());
    let Some(bodies) = summary.get("modal_energy").and_then(|m| m.as_array()) else {
        return Vec::new();
    };
    bodies
        .iter()
        .filter_map(|b| {
            let body = b.get("body")?.as_str()?.to_string();
            let modes = b
                .get("modes")?
                .as_array()?
                .iter()
                .filter_map(|m| {
                    Some((m.get("number")?.as_u64()?, m.get("frequency_hz")?.as_f64()?))
                })
                .collect();
            Some(Basis {
                variant: if body == "hitch" { variant } else { None },
                body,
                modes,
            })
        })
        .collect()
}

/// Why the modal coordinates of `body` in `run` do not compare with the reference's
/// (`None` when they do, or when neither run records the body's basis).
pub fn mismatch(body: &str, reference: &[Basis], run: &[Basis]) -> Option<String> {
    let find = |bs: &[Basis]| bs.iter().find(|b| b.body == body).cloned();
    match (find(reference), find(run)) {
        (Some(a), Some(b)) if a.same(&b) => None,
        (Some(a), Some(b)) => Some(format!("{} against {}", b.describe(), a.describe())),
        (Some(a), None) => Some(format!(
            "this run's basis is not recorded (no summary.json) against {}",
            a.describe()
        )),
        (None, Some(b)) => Some(format!(
            "{} against a reference whose basis is not recorded (no summary.json)",
            b.describe()
        )),
        (None, None) => None,
    }
}
