//! Case folders of a sweep run with `--keep-histories`: each case's `outputs.csv`,
//! `summary.json`, plot page and `report.html` in `OUT/cases/<case id>/`.
//!
//! A case is written into `<case id>.part/` and renamed into place once whole, so a
//! killed run leaves at most a `.part` folder, which `--resume` ignores (and replaces
//! when it runs the case again): a case folder without `.part` is always complete.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::job::RunResult;
use towride_mbs::model::System;

/// The folder of the case folders inside a sweep's output folder.
pub fn cases_dir(out: &Path) -> PathBuf {
    out.join("cases")
}

/// A case's folder name: `case_0007` (zero-padded to at least four digits so that
/// listings sort by case).
pub fn case_id(index: usize) -> String {
    format!("case_{index:04}")
}

/// The folder of case `index` under `cases` ([`cases_dir`]).
pub fn case_dir(cases: &Path, index: usize) -> PathBuf {
    cases.join(case_id(index))
}

/// True when case `index` has a complete folder (renamed into place, summary written).
pub fn is_kept(cases: &Path, index: usize) -> bool {
    case_dir(cases, index).join("summary.json").is_file()
}

/// Writes run `r` of case `index` into its folder under `cases`, whole or not at all:
/// first into `<id>.part/`, then renamed over any earlier folder of the case.
pub fn keep(r: &mut RunResult, system: &System, cases: &Path, index: usize) -> Result<PathBuf> {
    let dir = case_dir(cases, index);
    let part = cases.join(format!("{}.part", case_id(index)));
    let io = |p: &Path, e: std::io::Error| Error::io(p, e);
    if part.exists() {
        std::fs::remove_dir_all(&part).map_err(|e| io(&part, e))?;
    }
    crate::report::write_run(r, system, &part)?;
    // The summary names the files where they end up, not under the temporary name.
    let (from, to) = (part.display().to_string(), dir.display().to_string());
    let s = &mut r.summary;
    for f in [&mut s.outputs_csv, &mut s.plots, &mut s.report] {
        if let Some(p) = f.as_mut() {
            *p = p.replace(&from, &to);
        }
    }
    let json = part.join("summary.json");
    crate::atomic::write(&json, s.to_json()).map_err(|e| io(&json, e))?;
    if dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(|e| io(&dir, e))?;
    }
    std::fs::rename(&part, &dir).map_err(|e| io(&dir, e))?;
    Ok(dir)
}
