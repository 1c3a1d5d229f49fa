//! What produced a run: towride's version and commit, the command line, and the
//! overrides that took effect, each with where it was written. The run's folder keeps
//! the overrides as `overrides.toml` (`"FILE:PATH" = VALUE`), which `--overrides FILE`
//! reads back: the files on disk plus that file reproduce the run's inputs.

use serde::Serialize;
use towride_mbs::input::{Applied, Layer};

/// The provenance of a run (`summary.json` `produced_by`, the report's "Produced by").
#[derive(Clone, Debug, Default, Serialize)]
pub struct ProducedBy {
    /// towride's version (Cargo package version).
    pub towride_version: String,
    /// The git commit towride was built from ("unknown" outside a git checkout).
    pub git_commit: String,
    /// The command line, argument by argument (empty when not run from one).
    pub command_line: Vec<String>,
    /// The overrides that took effect.
    pub overrides: Vec<Applied>,
}

impl ProducedBy {
    /// This record with the producing program's version, commit and command line.
    pub fn stamped(mut self, version: &str, commit: &str, command_line: Vec<String>) -> Self {
        self.towride_version = version.into();
        self.git_commit = commit.into();
        self.command_line = command_line;
        self
    }

    /// The `overrides.toml` text: one `"FILE:PATH" = VALUE` line per override that took
    /// effect, commented with where it was written.
    pub fn overrides_toml(&self) -> String {
        let mut s = String::from(
            "# The overrides that took effect in this run, \"FILE:PATH\" = VALUE, each with where\n\
             # it was written. `--overrides overrides.toml` applies them again.\n",
        );
        if !self.towride_version.is_empty() {
            s += &format!(
                "# towride {} (commit {})\n",
                self.towride_version, self.git_commit
            );
        }
        if !self.command_line.is_empty() {
            s += &format!("# command line: {}\n", self.command_line.join(" "));
        }
        if self.overrides.is_empty() {
            s += "# (none)\n";
        }
        for a in &self.overrides {
            let key = format!("{}:{}", a.file.display(), a.path);
            // A value that is not TOML (a .tir word) is written as a string.
            let value = if a.value.parse::<toml_edit::Value>().is_ok() {
                a.value.clone()
            } else {
                format!("{:?}", a.value)
            };
            s += &format!("{key:?} = {value}  # {}\n", a.origin.replace('\n', " "));
        }
        s
    }
}

/// "overrides: run.speed_km_h = 40, ..." when the caller's overrides changed the run
/// (the scene's own `[[override]]` tables are part of the scene it names).
pub(crate) fn caller_changes(overrides: &[Applied]) -> Option<String> {
    const SHOWN: usize = 3;
    let caller: Vec<String> = overrides
        .iter()
        .filter(|a| a.layer == Layer::Caller)
        .map(|a| format!("{} = {}", a.path, a.value))
        .collect();
    if caller.is_empty() {
        return None;
    }
    let mut said = format!(
        "override{}: {}",
        if caller.len() > 1 { "s" } else { "" },
        caller[..caller.len().min(SHOWN)].join(", ")
    );
    if caller.len() > SHOWN {
        said += &format!(" and {} more", caller.len() - SHOWN);
    }
    Some(said)
}
