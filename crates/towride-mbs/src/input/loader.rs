//! Reading input files with property overrides, and knowing which overrides were used.
//!
//! Every reader of a run's files (TOML property files, `.tir` tyre files, CSV tables)
//! takes a [`Loader`] and reads through it, so an override reaches whatever file it
//! names, whatever its format. The loader records, per override, whether some file read
//! matched its `file` and whether the value was placed at its `path`: an override that
//! matched nothing is an error ([`Loader::check_used`]) located where the override was
//! written (a sweep file's line and field, a scene's `[[override]]`, a `--set`
//! argument), so a sweep over a value nobody reads cannot silently "complete".
//!
//! Overrides come in layers ([`Layer`]): a scene's own `[[override]]` tables, then the
//! caller's (the command line, an `--overrides` file, a sweep case, a study), then the
//! values towride derives itself (a `simple` vehicle's tyre). Where two address one
//! value, the caller's replace the scene's (recorded as superseded); two of one layer,
//! or a caller's override of a derived value, are errors naming where both were written.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use super::overrides::{self, Override};
use super::{InputError, Source};

/// Which layer an override comes from (later layers win, see the module text).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Layer {
    /// A scene's own `[[override]]` tables.
    Scene,
    /// The caller's: `--set`, `--overrides`, a sweep case, a study.
    Caller,
    /// Derived by towride from other inputs.
    Program,
}

/// One override and what became of it.
#[derive(Debug)]
pub(crate) struct Entry {
    pub(crate) ov: Override,
    pub(crate) layer: Layer,
    /// Some file read matched `ov.file`.
    pub(crate) file_hit: AtomicBool,
    /// The value was placed at `ov.path` in such a file.
    pub(crate) path_hit: AtomicBool,
    /// A later layer's override of the same value replaced this one.
    pub(crate) superseded: AtomicBool,
    /// The files (normalised) the value was placed in.
    pub(crate) placed_in: Mutex<Vec<PathBuf>>,
    /// The files (normalised) `ov.file` matched.
    matched: Mutex<Vec<PathBuf>>,
}

/// An override that took effect: the file it changed, the path, the value and where
/// the override was written (the record a run keeps in `overrides.toml`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Applied {
    /// The file changed, as read (normalised).
    pub file: PathBuf,
    /// The field inside it.
    pub path: String,
    /// The value, as written (TOML syntax for TOML files, a number otherwise).
    pub value: String,
    /// Where the override was written.
    pub origin: String,
    /// Its layer.
    pub layer: Layer,
}

impl Entry {
    /// Whether the override names `path`; an error when it named another file before
    /// (an override changes one file: `bump_50mm.toml` may be a scene and a road).
    pub(crate) fn matches(&self, path: &Path) -> Result<bool, InputError> {
        // `scenes/van/../../vehicles/x.toml` is `vehicles/x.toml`: files named through
        // `..` (a scene's relative references) are matched by where they are.
        let path = normalized(path);
        if !path.ends_with(normalized(Path::new(&self.ov.file))) {
            return Ok(false);
        }
        self.file_hit.store(true, Ordering::Relaxed);
        if let Ok(mut m) = self.matched.lock() {
            if let Some(other) = m.iter().find(|p| **p != path) {
                return Err(self.ov.origin.at_file(format!(
                    "`{}` names two files this run reads, {} and {}: write more of the path",
                    self.ov.file,
                    other.display(),
                    path.display()
                )));
            }
            if m.is_empty() {
                m.push(path);
            }
        }
        Ok(true)
    }

    pub(crate) fn placed(&self, file: &Path) {
        self.path_hit.store(true, Ordering::Relaxed);
        if let Ok(mut p) = self.placed_in.lock() {
            let f = normalized(file);
            if !p.contains(&f) {
                p.push(f);
            }
        }
    }

    fn new(ov: Override, layer: Layer) -> Arc<Entry> {
        // Values towride derives are a layer of their own, whoever adds them.
        let layer = if matches!(ov.origin, super::Origin::Derived(_)) {
            Layer::Program
        } else {
            layer
        };
        Arc::new(Entry {
            ov,
            layer,
            file_hit: AtomicBool::new(false),
            path_hit: AtomicBool::new(false),
            superseded: AtomicBool::new(false),
            placed_in: Mutex::new(Vec::new()),
            matched: Mutex::new(Vec::new()),
        })
    }
}

/// The overrides of one file that take effect, in order: a later layer's replaces an
/// earlier layer's of the same value (`key` says which value a path addresses); two of
/// one layer, or a caller's and a derived one, are an error at the later one's origin.
pub(crate) fn in_force<'a>(
    file: &Path,
    entries: Vec<&'a Entry>,
    key: impl Fn(&str) -> String,
) -> Result<Vec<&'a Entry>, InputError> {
    let mut out: Vec<&Entry> = Vec::new();
    for e in entries {
        let k = key(&e.ov.path);
        let Some(i) = out.iter().position(|f| key(&f.ov.path) == k) else {
            out.push(e);
            continue;
        };
        let f = out[i];
        let what = format!("`{}` of {}", e.ov.path.trim(), normalized(file).display());
        match (f.layer, e.layer) {
            (a, b) if a == b => {
                return Err(e.ov.origin.at_path(format!(
                    "{what} is set twice: also by {}; keep one",
                    f.ov.origin.describe()
                )))
            }
            (Layer::Program, _) | (_, Layer::Program) => {
                let (user, derived) = if f.layer == Layer::Program {
                    (e, f)
                } else {
                    (f, e)
                };
                return Err(user.ov.origin.at_path(format!(
                    "{what} is derived by {}: change that instead",
                    derived.ov.origin.describe()
                )));
            }
            (Layer::Scene, _) => {
                f.superseded.store(true, Ordering::Relaxed);
                f.path_hit.store(true, Ordering::Relaxed);
                out[i] = e;
            }
            (_, _) => {
                e.superseded.store(true, Ordering::Relaxed);
                e.path_hit.store(true, Ordering::Relaxed);
            }
        }
    }
    Ok(out)
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

    /// This loader plus `more` overrides of the caller's layer (towride's own, with an
    /// [`super::Origin::Derived`], are of theirs); the record of use is shared with
    /// `self`.
    pub fn extended(&self, more: Vec<Override>) -> Loader {
        let mut entries = self.entries.clone();
        entries.extend(more.into_iter().map(|ov| Entry::new(ov, Layer::Caller)));
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
            .map(|ov| Entry::new(ov, Layer::Scene))
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
        Loader {
            entries: self
                .entries
                .iter()
                .map(|e| Entry::new(e.ov.clone(), e.layer))
                .collect(),
            read: Arc::clone(&self.read),
        }
    }

    /// The overrides that took effect (placed, not superseded), towride's derived
    /// values left out: what reproduces the run's inputs from the files on disk.
    pub fn applied(&self) -> Vec<Applied> {
        let mut out = Vec::new();
        for e in &self.entries {
            if e.layer == Layer::Program || e.superseded.load(Ordering::Relaxed) {
                continue;
            }
            let files = e.placed_in.lock().map(|p| p.clone()).unwrap_or_default();
            for file in files {
                out.push(Applied {
                    file,
                    path: e.ov.path.trim().to_string(),
                    value: e.ov.value.trim().to_string(),
                    origin: e.ov.origin.describe(),
                    layer: e.layer,
                });
            }
        }
        out
    }

    /// The override of the highest layer whose path is `path` (in whichever file), and
    /// its layer: for a setting another input also decides (a scene's `hitch_variant`
    /// and the hitch file's `hitch.variant`).
    pub fn override_at(&self, path: &str) -> Option<(&Override, Layer)> {
        let rank = |l: Layer| match l {
            Layer::Scene => 0,
            Layer::Caller => 1,
            Layer::Program => 2,
        };
        self.entries
            .iter()
            .rev()
            .filter(|e| e.ov.path.trim() == path)
            .max_by_key(|e| rank(e.layer))
            .map(|e| (&e.ov, e.layer))
    }

    /// The overrides in force.
    pub fn overrides(&self) -> impl Iterator<Item = &Override> {
        self.entries.iter().map(|e| &e.ov)
    }

    /// The overrides whose `file` matches `path`, marked as having found their file.
    pub fn overrides_of(&self, path: &Path) -> Result<Vec<&Override>, InputError> {
        Ok(self.matching(path)?.into_iter().map(|e| &e.ov).collect())
    }

    /// The text of the TOML file `path` with this loader's overrides applied (what
    /// [`Loader::toml`] parses), for readers that walk the document themselves.
    pub fn toml_text(&self, path: &Path) -> Result<String, InputError> {
        Ok(self.applied_toml(path)?.0)
    }

    /// The text of the TOML file `path` with the overrides in force applied, and those
    /// overrides.
    fn applied_toml(&self, path: &Path) -> Result<(String, Vec<&Entry>), InputError> {
        let entries = in_force(path, self.matching(path)?, overrides::toml_key)?;
        let text = overrides::apply_toml(path, read_text(path)?, &entries)?;
        Ok((text, entries))
    }

    /// The overrides whose `file` matches `path`, marked as having found their file.
    pub(crate) fn matching(&self, path: &Path) -> Result<Vec<&Entry>, InputError> {
        self.note_read(path);
        let mut out = Vec::new();
        for e in &self.entries {
            if e.matches(path)? {
                out.push(e.as_ref());
            }
        }
        Ok(out)
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
            r.push(normalized(path));
        }
    }

    /// Reads a TOML file with the overrides that match it applied.
    /// An error about a value an override set is blamed on the override (where it was
    /// written), not on the file's line, which still holds the old value.
    pub fn toml(&self, path: &Path) -> Result<Source, InputError> {
        let (text, entries) = self.applied_toml(path)?;
        let set_by = entries
            .iter()
            .map(|e| super::SetBy {
                path: overrides::toml_key(&e.ov.path),
                value: e.ov.value.trim().to_string(),
                origin: e.ov.origin.clone(),
            })
            .collect();
        Source::from_text_set_by(path, text, set_by)
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

/// 64-bit FNV-1a of `bytes` (Fowler, Noll and Vo; offset basis 0xcbf29ce484222325,
/// prime 0x100000001b3): the same on every machine and Rust version, which std's
/// `DefaultHasher` does not promise, so it names inputs and results stably (a sweep's
/// fingerprint, a study folder outside the working directory).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// `path` with `.` components dropped and each `..` cancelling the component before it
/// (lexically: the project's inputs name files, not symbolic links).
pub fn normalized(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = Vec::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => match out.last() {
                Some(Component::Normal(_)) => {
                    out.pop();
                }
                // `..` at the root stays at the root; leading `..` are kept.
                Some(Component::RootDir | Component::Prefix(_)) => {}
                _ => out.push(c),
            },
            other => out.push(other),
        }
    }
    out.iter().collect()
}

/// The text of `path`, or a located "cannot read" error; what is not a regular file (a
/// named pipe would block forever) or exceeds the property-file cap is refused.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    super::regular::read_regular_text(path, super::regular::PROPERTY_FILE_MAX_BYTES)
}
