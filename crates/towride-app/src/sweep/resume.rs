//! Resuming a sweep: the journal each finished case is appended to (its first line the
//! layout version and the sweep's fingerprint) and the cases an earlier run of the same
//! sweep and shard left in its summary or journal.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::exec::{check_version, legacy_figure, CaseRow, Figures, SCHEMA_VERSION};
use super::fingerprint::Fingerprint;
use super::Sweep;
use crate::error::{Error, Result};
use crate::scene::SceneError;

/// The first line of a journal: the layout version of the rows after it.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct JournalHead {
    schema_version: u32,
    #[serde(default)]
    fingerprint: Option<Fingerprint>,
}

/// The journal beside a summary CSV: `summary.csv.journal`.
pub(super) fn journal_path(csv: &Path) -> PathBuf {
    let mut name = csv.file_name().unwrap_or_default().to_os_string();
    name.push(".journal");
    csv.with_file_name(name)
}

/// Writes the journal's first line.
pub(super) fn journal_head(f: &mut std::fs::File, fp: &Fingerprint) -> std::io::Result<()> {
    let head = JournalHead {
        schema_version: SCHEMA_VERSION,
        fingerprint: Some(fp.clone()),
    };
    let line = serde_json::to_string(&head).map_err(std::io::Error::other)?;
    f.write_all(format!("{line}\n").as_bytes())?;
    f.flush()
}

/// Appends one finished case to the journal.
pub(super) fn journal_line(f: &mut std::fs::File, r: &CaseRow) -> std::io::Result<()> {
    let line = serde_json::to_string(r).map_err(std::io::Error::other)?;
    f.write_all(format!("{line}\n").as_bytes())?;
    f.flush()
}

/// The completed and failed cases of an earlier run of this shard: its summary CSV
/// (when written) and its journal (when it was killed before writing one).
pub(super) fn previous_rows(
    sweep: &Sweep,
    shard: (usize, usize),
    csv: &Path,
    journal: &Path,
    fp: &Fingerprint,
) -> Result<Vec<CaseRow>> {
    let bad = |p: &Path, message: String| -> Error {
        SceneError::Merge {
            file: p.to_path_buf(),
            message,
        }
        .into()
    };
    let mut rows: Vec<CaseRow> = Vec::new();
    if csv.is_file() {
        let twin = csv.with_extension("json");
        let mut theirs = None;
        if let Ok(text) = std::fs::read_to_string(&twin) {
            let v: serde_json::Value =
                serde_json::from_str(&text).map_err(|e| super::guard::not_json(&twin, &e))?;
            check_version(&twin, v["schema_version"].as_u64(), "resume it")?;
            theirs = Some(v["fingerprint"].clone());
        }
        // Flexible: a row of the wrong length is refused below at its line.
        let mut r = csv::ReaderBuilder::new()
            .flexible(true)
            .from_path(csv)
            .map_err(|e| Error::io(csv, e.into()))?;
        let h = r.headers().map_err(|e| bad(csv, e.to_string()))?.clone();
        let np = sweep.parameters.len();
        let cols: Vec<&str> = h.iter().collect();
        let params: Vec<&str> = sweep.parameters.iter().map(|p| p.name.as_str()).collect();
        if cols.len() < np + 4
            || cols[0] != "case"
            || cols[1..=np] != params[..]
            || cols[np + 1] != "status"
            || cols.last() != Some(&"error")
        {
            return Err(SceneError::MergeAt {
                file: csv.to_path_buf(),
                line: 1,
                field: cols.first().unwrap_or(&"case").to_string(),
                message: format!(
                    "not a summary of this sweep (columns {cols:?}): remove it or run without --resume"
                ),
            }
            .into());
        }
        let figure_names = &cols[np + 3..cols.len() - 1];
        if figure_names.iter().any(|n| legacy_figure(n)) {
            check_version(csv, None, "resume it")?;
        }
        // Named by the CSV: its rows are what would be kept.
        super::guard::same_sweep(csv, theirs.as_ref(), fp)?;
        for (k, rec) in r.records().enumerate() {
            let line = k + 2;
            let at = |field: &str, message: String| -> Error {
                SceneError::MergeAt {
                    file: csv.to_path_buf(),
                    line,
                    field: field.to_string(),
                    message,
                }
                .into()
            };
            let rec = rec.map_err(|e| at("case", e.to_string()))?;
            if rec.len() != cols.len() {
                return Err(at(
                    cols[cols.len().min(rec.len()).saturating_sub(1)],
                    format!("{} fields, the header has {}", rec.len(), cols.len()),
                ));
            }
            let get = |c: usize| rec.get(c).unwrap_or("");
            let index: usize = get(0)
                .parse()
                .map_err(|_| at("case", "not a case number".into()))?;
            if index >= sweep.len() || index % shard.1 != shard.0 {
                return Err(at(
                    "case",
                    format!("case {index} is not a case of this shard"),
                ));
            }
            let case = sweep.case(index);
            for (p, v) in case.values.iter().enumerate() {
                if get(p + 1) != v.trim_matches('"') {
                    return Err(at(
                        params[p],
                        format!(
                            "case {index} has {} but the sweep file gives {v}: the sweep \
                             changed; remove the summary or run without --resume",
                            get(p + 1)
                        ),
                    ));
                }
            }
            let status = get(np + 1).to_string();
            if status != "completed" && status != "failed" {
                continue;
            }
            let mut figures = Figures::new();
            for (f, name) in figure_names.iter().enumerate() {
                let cell = get(np + 3 + f);
                if !cell.is_empty() {
                    let v = cell
                        .parse()
                        .map_err(|_| at(name, format!("not a number: `{cell}`")))?;
                    figures.push((name.to_string(), v));
                }
            }
            let error = get(cols.len() - 1);
            rows.push(CaseRow {
                index,
                values: case.values,
                status,
                error: (!error.is_empty()).then(|| error.to_string()),
                wall_s: get(np + 2).parse().unwrap_or(0.0),
                figures,
            });
        }
    }
    if let Ok(text) = std::fs::read_to_string(journal) {
        // The version line first; a journal of rows without one is older than version 4.
        let first = text.lines().find(|l| !l.trim().is_empty());
        if let Some(first) = first {
            let version = serde_json::from_str::<JournalHead>(first)
                .ok()
                .map(|h| h.schema_version as u64);
            if version.is_some() || serde_json::from_str::<CaseRow>(first).is_ok() {
                check_version(journal, version, "resume it")?;
            }
            let head = serde_json::from_str::<serde_json::Value>(first).ok();
            super::guard::same_sweep(journal, head.as_ref().map(|h| &h["fingerprint"]), fp)?;
        }
        for (k, l) in text.lines().enumerate() {
            // A line cut short by a kill is the case still running: run it again.
            let Ok(r) = serde_json::from_str::<CaseRow>(l) else {
                continue;
            };
            if r.index >= sweep.len() || sweep.case(r.index).values != r.values {
                return Err(bad(
                    journal,
                    format!("line {}: case {} is not of this sweep", k + 1, r.index),
                ));
            }
            if !rows.iter().any(|x| x.index == r.index) {
                rows.push(r);
            }
        }
    }
    Ok(rows)
}
