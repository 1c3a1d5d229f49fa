//! What `sweep` and `sweep merge` refuse to write over: another command's results (a
//! run's folder, whose `summary.json` and `report.html` a sweep's files would replace),
//! one of the command's own inputs (a shard being merged), or another sweep's table.

use std::path::{Path, PathBuf};

use super::fingerprint::Fingerprint;
use crate::error::{Error, Result};
use crate::scene::SceneError;

fn refuse(file: &Path, message: String) -> Error {
    SceneError::Merge {
        file: file.to_path_buf(),
        message,
    }
    .into()
}

/// Refuses an output folder that holds a run's results (a `summary.json` that is not a
/// sweep's).
pub fn out_dir(dir: &Path) -> Result<()> {
    let json = dir.join("summary.json");
    let Ok(text) = std::fs::read_to_string(&json) else {
        return Ok(());
    };
    // Unreadable: a cut or spoilt summary, not another command's; it is still refused.
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| not_json(&json, &e))?;
    if v.get("sweep").is_some() && v.get("cases_total").is_some() {
        return Ok(());
    }
    Err(refuse(
        &json,
        format!(
            "{} holds another command's results (this summary.json is not a sweep's): the \
             sweep's summary and report would replace them; choose another --out",
            dir.display()
        ),
    ))
}

/// Refuses a merge whose `out` is one of its `inputs` (or its JSON twin is one's), a
/// table of another sweep than `fp`'s, or a file in a run's folder.
pub fn merge_out(out: &Path, inputs: &[PathBuf], fp: &Fingerprint) -> Result<()> {
    let canon = |p: &Path| p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    let twin = out.with_extension("json");
    for i in inputs {
        if canon(i) == canon(out) || canon(&i.with_extension("json")) == canon(&twin) {
            return Err(refuse(
                out,
                format!(
                    "--out is {}, one of the shards being merged: the merge would overwrite \
                     its own input; choose another --out",
                    i.display()
                ),
            ));
        }
    }
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        out_dir(dir)?;
    }
    if !out.exists() {
        return Ok(());
    }
    let theirs = std::fs::read_to_string(&twin)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| serde_json::from_value::<Fingerprint>(v["fingerprint"].clone()).ok());
    match theirs {
        Some(f) if f.hash == fp.hash => Ok(()),
        Some(f) => Err(refuse(
            out,
            format!(
                "holds the table of another sweep ({}): remove it or choose another --out",
                f.differences(fp).join("; ")
            ),
        )),
        None => Err(refuse(
            out,
            "exists and is not a table of this sweep (no fingerprint beside it): remove it or \
             choose another --out"
                .into(),
        )),
    }
}

/// Refuses results (`file`'s fingerprint `theirs`) of another sweep than `fp`'s.
pub fn same_sweep(file: &Path, theirs: Option<&serde_json::Value>, fp: &Fingerprint) -> Result<()> {
    let bad = |message: String| -> Error {
        SceneError::Merge {
            file: file.to_path_buf(),
            message,
        }
        .into()
    };
    let theirs = theirs.and_then(|v| serde_json::from_value::<Fingerprint>(v.clone()).ok());
    match theirs {
        Some(f) if f.hash == fp.hash => Ok(()),
        Some(f) => Err(bad(format!(
            "the results there are of another sweep ({}): run without --resume, or with \
             another --out",
            f.differences(fp).join("; ")
        ))),
        None => Err(bad(
            "no fingerprint: cannot tell whether these results are of this sweep (written by \
             an older towride, or the JSON twin is missing): run without --resume, or with \
             another --out"
                .into(),
        )),
    }
}

/// A summary or shard JSON that does not parse, at its line: cut short or spoilt.
pub fn not_json(file: &Path, e: &serde_json::Error) -> crate::error::Error {
    crate::scene::SceneError::MergeAt {
        file: file.to_path_buf(),
        line: e.line(),
        field: "JSON".into(),
        message: format!(
            "not readable ({e}): a cut or spoilt summary; remove it or choose another --out"
        ),
    }
    .into()
}
