//! The options every command that reads a scene takes, with one parser: `--set
//! FILE:PATH=VALUE` (repeatable) and `--overrides FILE` (a run's `overrides.toml`).

use std::path::PathBuf;

use clap::Args;
use towride_app::job::ProducedBy;
use towride_mbs::input::{read_overrides, InputError, Loader, Override};

#[derive(Args, Debug, Clone, Default)]
pub struct InputArgs {
    /// Replace a value of any file read: FILE:PATH=VALUE (FILE matched by the end of its
    /// path, which must name one file; PATH `table.key`, `.tir` `SECTION.KEY`, CSV
    /// `column[row]`). Repeatable; wins over a scene's `[[override]]` of the same value.
    #[arg(long = "set", value_name = "FILE:PATH=VALUE")]
    pub set: Vec<String>,
    /// Overrides from a file of `"FILE:PATH" = VALUE` lines, as every run writes them to
    /// its folder's `overrides.toml` (applies that run's overrides again).
    #[arg(long, value_name = "FILE")]
    pub overrides: Option<PathBuf>,
}

impl InputArgs {
    /// The overrides given, the file's first; one value set twice is refused when read.
    pub fn overrides(&self) -> Result<Vec<Override>, InputError> {
        let mut out = match &self.overrides {
            Some(f) => read_overrides(f)?,
            None => Vec::new(),
        };
        for s in &self.set {
            out.push(Override::from_argument(s)?);
        }
        Ok(out)
    }

    /// A loader applying them.
    pub fn loader(&self) -> Result<Loader, InputError> {
        Ok(Loader::with_overrides(self.overrides()?))
    }
}

/// `record` with this program's version, commit and command line.
pub fn stamp(record: &ProducedBy) -> ProducedBy {
    record.clone().stamped(
        env!("CARGO_PKG_VERSION"),
        env!("TOWRIDE_GIT_COMMIT"),
        std::env::args().collect(),
    )
}
