//! Property overrides: values in input files replaced as they are read, by file and
//! path, without touching the files. A sweep varies any value of any file a case reads
//! ("vehicles/fabia/front_mcpherson.toml" `spring.stiffness_n_m` = 2.5e4); a single run
//! takes them from `--set FILE:PATH=VALUE` or a scene's `[[override]]` table. The
//! overrides travel explicitly with the [`super::Loader`] that reads the files, and every
//! override is validated like a hand-edited value by the file's own reader.
//!
//! Paths: TOML files `table.key`, `array[2].key`; `.tir` files `SECTION.KEY`; CSV tables
//! `column[row]` (row counted from 0 over the data rows).

use std::path::Path;

use toml_edit::{DocumentMut, Item, Value};

use super::loader::Entry;
use super::InputError;

/// One value to replace: in every file whose path ends with `file`, at `path`, the value
/// `value` (TOML syntax for TOML files: `2.5e4`, `"text"`, `[1, 2]`; a number for `.tir`
/// and CSV files).
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// Matched against the end of each file's path, e.g. `front_mcpherson.toml`.
    pub file: String,
    /// Field inside the file: `table.key` or `array[2].key` (TOML), `SECTION.KEY` (`.tir`),
    /// `column[row]` (CSV).
    pub path: String,
    /// New value, as text (TOML syntax, or a number for `.tir` and CSV files).
    pub value: String,
    /// Where the override was written, for errors about it.
    pub origin: Origin,
}

impl Override {
    /// A value towride derives from other inputs (`what` says from which).
    pub fn derived(file: &str, path: &str, value: impl Into<String>, what: &str) -> Override {
        Override {
            file: file.into(),
            path: path.into(),
            value: value.into(),
            origin: Origin::Derived(what.into()),
        }
    }

    /// An override set by the program itself (`what` says which part of it).
    pub fn program(file: &str, path: &str, value: impl Into<String>, what: &str) -> Override {
        Override {
            file: file.into(),
            path: path.into(),
            value: value.into(),
            origin: Origin::Program(what.into()),
        }
    }

    /// Parses a command-line `FILE:PATH=VALUE`.
    pub fn from_argument(arg: &str) -> Result<Override, InputError> {
        let bad = |m: &str| Origin::Argument(arg.to_string()).error(m.to_string());
        let (lhs, value) = arg.split_once('=').ok_or_else(|| {
            bad("write FILE:PATH=VALUE, e.g. front_mcpherson.toml:spring.stiffness_n_m=2.5e4")
        })?;
        let (file, path) = lhs.rsplit_once(':').ok_or_else(|| {
            bad("write FILE:PATH=VALUE, e.g. front_mcpherson.toml:spring.stiffness_n_m=2.5e4")
        })?;
        if file.trim().is_empty() || path.trim().is_empty() || value.trim().is_empty() {
            return Err(bad("FILE, PATH and VALUE must not be empty"));
        }
        Ok(Override {
            file: file.trim().into(),
            path: path.trim().into(),
            value: value.trim().into(),
            origin: Origin::Argument(arg.to_string()),
        })
    }
}

/// Where an override was written.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// In an input file: located errors for its `file` and its `path` fields (their
    /// messages are replaced).
    File {
        /// Located error template for the override's `file` field.
        file: Box<InputError>,
        /// Located error template for the override's `path` field.
        path: Box<InputError>,
    },
    /// A command-line argument.
    Argument(String),
    /// Set by the program for the caller (a stress case, a sensitivity study, the
    /// validation's lead-in): the caller's layer.
    Program(String),
    /// A value towride derives from other inputs (a `simple` vehicle's tyre): a layer
    /// of its own, which no other override may replace.
    Derived(String),
}

impl Origin {
    fn error(&self, message: String) -> InputError {
        match self {
            Origin::File { path, .. } => InputError {
                message,
                ..(**path).clone()
            },
            Origin::Argument(a) => InputError {
                file: "command line".into(),
                line: None,
                column: None,
                field: format!("--set {a}"),
                message,
                kind: Default::default(),
            },
            Origin::Program(w) | Origin::Derived(w) => InputError {
                file: "towride".into(),
                line: None,
                column: None,
                field: w.clone(),
                message,
                kind: Default::default(),
            },
        }
    }

    /// An error about the override's file.
    pub fn at_file(&self, message: String) -> InputError {
        match self {
            Origin::File { file, .. } => InputError {
                message,
                ..(**file).clone()
            },
            other => other.error(message),
        }
    }

    /// An error about the override's path or value.
    pub fn at_path(&self, message: String) -> InputError {
        self.error(message)
    }

    /// Where the override was written, in words: `--set ARG`, `FILE:LINE field`, or
    /// what in towride set it.
    pub fn describe(&self) -> String {
        match self {
            Origin::File { path, .. } => {
                let mut s = path.file.display().to_string();
                if let Some(l) = path.line {
                    s += &format!(":{l}");
                }
                if !path.field.is_empty() {
                    s += &format!(" `{}`", path.field);
                }
                s
            }
            Origin::Argument(a) if a.contains(":") && a.contains('=') => format!("--set {a}"),
            Origin::Argument(a) => a.clone(),
            Origin::Program(w) => format!("towride ({w})"),
            Origin::Derived(w) => format!("towride from {w}"),
        }
    }
}

/// The value a TOML path addresses, written one way (`a . b [2]` is `a.b[2]`).
pub(crate) fn toml_key(path: &str) -> String {
    path.split('.')
        .map(|p| p.trim().replace(' ', ""))
        .collect::<Vec<_>>()
        .join(".")
}

/// Reads an overrides file (`--overrides FILE`, a run's `overrides.toml`): top-level
/// `"FILE:PATH" = VALUE` lines, each an override located at its line.
pub fn read_file(path: &Path) -> Result<Vec<Override>, InputError> {
    let src = super::Source::read(path)?;
    let table: toml::Table = src.parse()?;
    let mut out = Vec::new();
    for (key, v) in &table {
        let at = src.error(&crate::path![key.as_str()], "");
        let bad = |m: &str| InputError {
            message: m.to_string(),
            ..at.clone()
        };
        if v.is_table() || v.as_array().is_some_and(|a| a.iter().any(|x| x.is_table())) {
            return Err(bad(
                "write each override as a top-level \"FILE:PATH\" = VALUE line, not a table",
            ));
        }
        let Some((file, p)) = key.rsplit_once(':') else {
            return Err(bad(
                "the key names FILE:PATH, e.g. \"vehicles/fabia/front_mcpherson.toml:spring.stiffness_n_m\"",
            ));
        };
        if file.trim().is_empty() || p.trim().is_empty() {
            return Err(bad("FILE and PATH must not be empty"));
        }
        out.push(Override {
            file: file.trim().into(),
            path: p.trim().into(),
            value: value_text(v),
            origin: Origin::File {
                file: Box::new(at.clone()),
                path: Box::new(at),
            },
        });
    }
    Ok(out)
}

/// Applies `entries` (the overrides matching `path`) to the TOML `text`.
pub(crate) fn apply_toml(
    path: &Path,
    text: String,
    entries: &[&Entry],
) -> Result<String, InputError> {
    if entries.is_empty() {
        return Ok(text);
    }
    let mut doc: DocumentMut = text.parse().map_err(|e| InputError {
        file: path.to_path_buf(),
        line: None,
        column: None,
        field: String::new(),
        message: format!("TOML syntax (reading it to apply overrides): {e}"),
        kind: Default::default(),
    })?;
    for e in entries {
        let o = &e.ov;
        let value: Value = o.value.parse().map_err(|err| {
            o.origin
                .at_path(format!("override value `{}` is not TOML: {err}", o.value))
        })?;
        match locate(doc.as_item_mut(), &o.path) {
            Some(slot) => *slot = Item::Value(value),
            // A key missing from an existing table is added (the file's own checks
            // then refuse a key that does not belong there).
            None => insert(doc.as_item_mut(), &o.path, value).ok_or_else(|| {
                o.origin.at_path(format!(
                    "`{}` is not a value or table of {}",
                    o.path,
                    path.display()
                ))
            })?,
        }
        e.placed(path);
    }
    Ok(doc.to_string())
}

type Segs = [(String, Option<usize>)];

/// `table.key`, `array[2].key` as (key, index) segments.
fn segments(path: &str) -> Option<Vec<(String, Option<usize>)>> {
    path.split('.')
        .map(|part| match part.find('[') {
            Some(i) => {
                let idx: usize = part[i + 1..].strip_suffix(']')?.parse().ok()?;
                Some((part[..i].to_string(), Some(idx)))
            }
            None => Some((part.to_string(), None)),
        })
        .collect()
}

/// The item at a dotted path with `[k]` indices into arrays of tables.
fn locate<'a>(item: &'a mut Item, path: &str) -> Option<&'a mut Item> {
    walk(item, &segments(path)?)
}

/// Adds `value` under the last key of `path` in the table its parent path names.
fn insert(item: &mut Item, path: &str, value: Value) -> Option<()> {
    let (parent, key) = match path.rsplit_once('.') {
        Some((p, k)) => (Some(p), k),
        None => (None, path),
    };
    if key.contains('[') {
        return None;
    }
    let table = match parent {
        Some(p) => locate(item, p)?,
        None => item,
    };
    table.as_table_like_mut()?.insert(key, Item::Value(value));
    Some(())
}

fn walk<'a>(item: &'a mut Item, segs: &Segs) -> Option<&'a mut Item> {
    let Some(((key, idx), rest)) = segs.split_first() else {
        return Some(item);
    };
    let next = item.as_table_like_mut()?.get_mut(key)?;
    match idx {
        None => walk(next, rest),
        Some(k) => match next {
            Item::ArrayOfTables(a) => walk_table(a.get_mut(*k)?, rest),
            _ => None,
        },
    }
}

fn walk_table<'a>(t: &'a mut toml_edit::Table, segs: &Segs) -> Option<&'a mut Item> {
    let ((key, idx), rest) = segs.split_first()?;
    let next = t.get_mut(key)?;
    match idx {
        None => walk(next, rest),
        Some(k) => match next {
            Item::ArrayOfTables(a) => walk_table(a.get_mut(*k)?, rest),
            _ => None,
        },
    }
}

/// A TOML value as it would be written in a file (strings quoted): the text of an
/// override given as a TOML value (a scene's `[[override]]`, a sweep's values).
pub fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("{s:?}"),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::Loader;

    fn ov(path: &str, value: &str) -> Override {
        Override::program("car.toml", path, value, "test")
    }

    #[test]
    fn overrides_replace_values_by_path_and_refuse_missing_paths() {
        let dir = std::env::temp_dir().join(format!("towride-ov-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("car.toml");
        let text =
            "[spring]\nstiffness_n_m = 1.0\n\n[[axle]]\nmass_kg = 2.0\n[[axle]]\nmass_kg = 3.0\n";
        std::fs::write(&p, text).unwrap();
        let l = Loader::with_overrides(vec![
            ov("spring.stiffness_n_m", "2.5e4"),
            ov("axle[1].mass_kg", "7.5"),
        ]);
        let doc: DocumentMut = l.toml(&p).unwrap().text().parse().unwrap();
        assert_eq!(doc["spring"]["stiffness_n_m"].as_float(), Some(2.5e4));
        assert_eq!(doc["axle"][1]["mass_kg"].as_float(), Some(7.5));
        assert_eq!(doc["axle"][0]["mass_kg"].as_float(), Some(2.0));
        assert!(l.check_used().is_ok());
        let l = Loader::with_overrides(vec![ov("sprin.stiffness_n_m", "1")]);
        let e = l.toml(&p).unwrap_err();
        assert!(e.message.contains("sprin.stiffness_n_m"), "{e}");
        // A missing key of an existing table is added.
        let l = Loader::with_overrides(vec![ov("spring.damping_n_s_m", "3.0")]);
        let doc: DocumentMut = l.toml(&p).unwrap().text().parse().unwrap();
        assert_eq!(doc["spring"]["damping_n_s_m"].as_float(), Some(3.0));
        // A loader without overrides reads the file as it is.
        assert_eq!(Loader::new().toml(&p).unwrap().text(), text);
        // An override of a file never read is reported, naming what was read.
        let l = Loader::with_overrides(vec![Override::program("other.toml", "a", "1", "test")]);
        l.toml(&p).unwrap();
        let e = l.check_used().unwrap_err();
        assert!(
            e.message.contains("other.toml") && e.message.contains("car.toml"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn command_line_overrides_parse_and_refuse_bad_forms() {
        let o = Override::from_argument("fabia/hitch.toml:hitch.variant=7").unwrap();
        assert_eq!(
            (o.file.as_str(), o.path.as_str(), o.value.as_str()),
            ("fabia/hitch.toml", "hitch.variant", "7")
        );
        for bad in ["hitch.toml", "hitch.toml=7", ":a=1", "f:a="] {
            let e = Override::from_argument(bad).unwrap_err();
            assert!(e.field.contains(bad), "{e}");
        }
    }
}
