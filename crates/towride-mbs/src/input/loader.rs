//! Reading input files with property overrides, and knowing which overrides were used.
//!
//! Every reader of a run's files (TOML property files, `.tir` tyre files, CSV tables)
//! takes a [`Loader`] and reads through it, so an override reaches whatever file it
//! names, whatever its format. The loader records, per override, whether some file read
//! matched its `file` and whether the value was placed at its `path`: an override that
//! matched nothing is an error ([`Loader::check_used`]) located where the override was
//! written (a sweep file's line and field, a scene's `[[override]]`, a `--set`
//! argument), so a sweep over a value nobody reads cannot silently "complete".

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use super::overrides::{self, Override};
use super::{InputError, Source};

/// One override and what became of it.
#[derive(Debug)]
pub(crate) struct Entry {
    pub(crate) ov: Override,
    /// Some file read matched `ov.file`.
    pub(crate) file_hit: AtomicBool,
    /// The value was placed at `ov.path` in such a file.
    pub(crate) path_hit: AtomicBool,
}

impl Entry {
    pub(crate) fn matches(&self, path: &Path) -> bool {
        let hit = path.ends_with(&self.ov.file);
        if hit {
            self.file_hit.store(true, Ordering::Relaxed);
        }
        hit
    }

    pub(crate) fn placed(&self) {
        self.path_hit.store(true, Ordering::Relaxed);
    }
}

/// Reads files, applying overrides by file and path. Cheap to clone; clones share the
/// record of which overrides were used.
#[derive(Clone, Debug, Default)]
pub struct Loader {
    entries: Vec<Arc<Entry>>,
    /// Every file read, in order (for messages about overrides that matched nothing).
    read: Arc<Mutex<Vec<PathBuf>>>,
}

impl Loader {
    /// A loader without overrides.
    pub fn new() -> Loader {
        Loader::default()
    }

    /// A loader applying `overrides` (later ones win where two address one value).
    pub fn with_overrides(overrides: Vec<Override>) -> Loader {
        Loader::new().extended(overrides)
    }

    /// This loader plus `more` overrides; the record of use is shared with `self`.
    pub fn extended(&self, more: Vec<Override>) -> Loader {
        let mut entries = self.entries.clone();
        entries.extend(more.into_iter().map(|ov| {
            Arc::new(Entry {
                ov,
                file_hit: AtomicBool::new(false),
                path_hit: AtomicBool::new(false),
            })
        }));
        Loader {
            entries,
            read: Arc::clone(&self.read),
        }
    }

    /// This loader with `first` applied before its own overrides, so that its own win
    /// where both set a value (a scene's `[[override]]` tables under the command line's
    /// `--set`); the record of use is shared with `self`.
    pub fn under(&self, first: Vec<Override>) -> Loader {
        let mut entries: Vec<Arc<Entry>> = first
            .into_iter()
            .map(|ov| {
                Arc::new(Entry {
                    ov,
                    file_hit: AtomicBool::new(false),
                    path_hit: AtomicBool::new(false),
                })
            })
            .collect();
        entries.extend(self.entries.iter().cloned());
        Loader {
            entries,
            read: Arc::clone(&self.read),
        }
    }

    /// The same overrides with a fresh record of use (one case of a batch); the list of
    /// files read stays shared, so the caller learns what the case read.
    pub fn fresh(&self) -> Loader {
        let mut l = Loader::with_overrides(self.entries.iter().map(|e| e.ov.clone()).collect());
        l.read = Arc::clone(&self.read);
        l
    }

    /// The overrides in force.
    pub fn overrides(&self) -> impl Iterator<Item = &Override> {
        self.entries.iter().map(|e| &e.ov)
    }

    /// The overrides whose `file` matches `path`, marked as having found their file.
    pub fn overrides_of(&self, path: &Path) -> Vec<&Override> {
        self.matching(path).into_iter().map(|e| &e.ov).collect()
    }

    /// The text of the TOML file `path` with this loader's overrides applied (what
    /// [`Loader::toml`] parses), for readers that walk the document themselves.
    pub fn toml_text(&self, path: &Path) -> Result<String, InputError> {
        overrides::apply_toml(path, read_text(path)?, &self.matching(path))
    }

    /// The overrides whose `file` matches `path`, marked as having found their file.
    pub(crate) fn matching(&self, path: &Path) -> Vec<&Entry> {
        self.note_read(path);
        self.entries
            .iter()
            .filter(|e| e.matches(path))
            .map(|e| e.as_ref())
            .collect()
    }

    /// Every file read so far through this loader or its clones, in first-read order,
    /// each once.
    pub fn files_read(&self) -> Vec<PathBuf> {
        let read = self.read.lock().map(|r| r.clone()).unwrap_or_default();
        let mut out: Vec<PathBuf> = Vec::new();
        for p in read {
            if !out.contains(&p) {
                out.push(p);
            }
        }
        out
    }

    fn note_read(&self, path: &Path) {
        if let Ok(mut r) = self.read.lock() {
            r.push(path.to_path_buf());
        }
    }

    /// Reads a TOML file with the overrides that match it applied.
    pub fn toml(&self, path: &Path) -> Result<Source, InputError> {
        Source::from_text(path, self.toml_text(path)?)
    }

    /// The overrides that matched no file read, or whose path was found in none: the
    /// first is an error located where it was written.
    pub fn check_used(&self) -> Result<(), InputError> {
        for e in &self.entries {
            let o = &e.ov;
            if !e.file_hit.load(Ordering::Relaxed) {
                let read = self.read.lock().map(|r| r.clone()).unwrap_or_default();
                let mut names: Vec<String> = read.iter().map(|p| p.display().to_string()).collect();
                names.sort();
                names.dedup();
                return Err(o.origin.at_file(format!(
                    "`{}` matches no file this run reads (it read: {})",
                    o.file,
                    names.join(", ")
                )));
            }
            if !e.path_hit.load(Ordering::Relaxed) {
                return Err(o
                    .origin
                    .at_path(format!("`{}` is not a value of {}", o.path, o.file)));
            }
        }
        Ok(())
    }
}

/// The text of `path`, or a located "cannot read" error.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    std::fs::read_to_string(path).map_err(|e| InputError {
        file: path.to_path_buf(),
        line: None,
        column: None,
        field: String::new(),
        message: format!("cannot read: {e}"),
        kind: Default::default(),
    })
}
