//! Reading a run's `outputs.csv` for `compare`, refusing what would give numbers that
//! mean nothing: no data rows or one, time that does not increase, two columns of one
//! name, a file that is not regular or too large. Each error names file, line, field.

use std::path::Path;

use towride_mbs::input::csv_table;
use towride_mbs::input::regular::{read_regular, DATA_FILE_MAX_BYTES, PROPERTY_FILE_MAX_BYTES};

use super::basis::bases;
use super::Run;
use crate::Error;

pub(super) fn bad(file: &Path, line: Option<usize>, field: &str, message: String) -> Error {
    csv_table::error(file, line, field, message).into()
}

/// `dir/summary.json` as JSON, if it reads (a run without one compares all the same).
fn summary(dir: &Path) -> Option<serde_json::Value> {
    let bytes = read_regular(&dir.join("summary.json"), PROPERTY_FILE_MAX_BYTES).ok()?;
    serde_json::from_slice(&bytes).ok()
}

/// The convergence verdict of a summary, if it has one.
fn verdict(v: &serde_json::Value) -> Option<Vec<(String, bool)>> {
    let channels = v.get("convergence")?.get("channels")?.as_object()?;
    Some(
        channels
            .iter()
            .map(|(n, c)| (n.clone(), c["converged"].as_bool().unwrap_or(false)))
            .collect(),
    )
}

/// Reads `dir/outputs.csv` (headers `name [unit]`, the first column time, increasing)
/// and what `dir/summary.json` says of its convergence and modal bases.
pub fn load(dir: &Path) -> Result<Run, Error> {
    let file = dir.join("outputs.csv");
    let bytes = read_regular(&file, DATA_FILE_MAX_BYTES)?;
    let mut r = csv::Reader::from_reader(&bytes[..]);
    let headers = r
        .headers()
        .map_err(|e| bad(&file, Some(1), "", e.to_string()))?
        .clone();
    let mut names: Vec<(String, String)> = Vec::new();
    let mut seen = std::collections::HashMap::new();
    for (k, h) in headers.iter().enumerate() {
        let (name, unit) = h
            .rsplit_once(" [")
            .and_then(|(n, u)| Some((n, u.strip_suffix(']')?)))
            .ok_or_else(|| bad(&file, Some(1), h, "header is not 'name [unit]'".into()))?;
        // Two columns of one name: which one a comparison took would be a guess.
        if let Some(first) = seen.insert(name.to_string(), k) {
            return Err(bad(
                &file,
                Some(1),
                name,
                format!(
                    "column {} repeats the name of column {}: every column needs its own name",
                    k + 1,
                    first + 1
                ),
            ));
        }
        names.push((name.to_string(), unit.to_string()));
    }
    if names.first().map(|n| n.0.as_str()) != Some("time") {
        return Err(bad(
            &file,
            Some(1),
            "",
            "the first column is not time".into(),
        ));
    }
    let mut cols = vec![Vec::new(); names.len()];
    for (k, rec) in r.records().enumerate() {
        let line = k + 2;
        let rec = rec.map_err(|e| bad(&file, Some(line), "", e.to_string()))?;
        for (c, v) in rec.iter().enumerate() {
            let x: f64 = v.trim().parse().map_err(|_| {
                bad(
                    &file,
                    Some(line),
                    &names[c.min(names.len() - 1)].0,
                    format!("'{v}' is not a number"),
                )
            })?;
            cols[c].push(x);
        }
        // Interpolation and the overlap assume increasing times.
        let t = &cols[0];
        if let [.., a, b] = t.as_slice() {
            if b.partial_cmp(a) != Some(std::cmp::Ordering::Greater) {
                return Err(bad(
                    &file,
                    Some(line),
                    "time",
                    format!(
                        "time does not increase: {b} s after {a} s on line {}",
                        line - 1
                    ),
                ));
            }
        }
    }
    match cols[0].len() {
        0 => {
            return Err(bad(
                &file,
                Some(2),
                "",
                "no data rows under the header: nothing to compare".into(),
            ))
        }
        1 => {
            return Err(bad(
                &file,
                Some(2),
                "",
                "one data row: a comparison needs at least two samples".into(),
            ))
        }
        _ => {}
    }
    let times = std::mem::take(&mut cols[0]);
    let channels = names
        .into_iter()
        .zip(cols)
        .skip(1)
        .map(|((n, u), v)| (n, u, v))
        .collect();
    let label = dir.file_name().map_or_else(
        || dir.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let s = summary(dir);
    Ok(Run {
        label,
        file,
        times,
        channels,
        verdict: s.as_ref().and_then(verdict),
        bases: s.as_ref().map_or_else(Vec::new, bases),
    })
}
