//! A reader for `.tir` tyre property files (the TNO / MF-Tyre / MF-Swift format).
//!
//! The format is not TOML: `[SECTION]` headers, `KEY = value` lines, comments starting
//! with `$` or `!` (whole line or after a value), strings in single quotes, and tables
//! (a `{column names}` line followed by rows of numbers, e.g. in [SHAPE]) which this
//! reader skips. Keys
//! are case-sensitive and looked up per section, so [UNITS] MASS and [INERTIA] MASS do not
//! clash. The reader keeps the line of every key and every section header so that a
//! missing key is reported at its section's header and a bad value at its own line, both
//! as `file:line:column: field `SECTION.KEY`: message` ([`crate::input::InputError`]).
//!
//! Unknown keys and sections are kept but ignored by the tyre models, as MF-Swift users
//! expect (one file serves several tools); the keys that are read are listed in
//! `docs/road_tyre.md`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::input::InputError;

/// One `KEY = value` entry.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The value text, quotes removed for strings.
    pub value: String,
    /// 1-based line of the entry.
    pub line: usize,
    /// 1-based column of the value.
    pub column: usize,
}

#[derive(Clone, Debug, Default)]
struct Section {
    line: usize,
    keys: HashMap<String, Entry>,
}

/// A parsed `.tir` file.
#[derive(Clone, Debug)]
pub struct TirFile {
    /// The file read.
    pub path: PathBuf,
    sections: HashMap<String, Section>,
    /// The last line: where a missing section is reported (the file ends without it).
    end_line: usize,
}

impl TirFile {
    /// Reads and parses `path`, with the loader's overrides of this file applied (path
    /// `SECTION.KEY`, value as it would be written in the file).
    pub fn read(path: &Path, loader: &crate::input::Loader) -> Result<TirFile, InputError> {
        let text = crate::input::loader::read_text(path)?;
        let mut t = TirFile::parse(path, &text)?;
        let entries =
            crate::input::loader::in_force(path, loader.matching(path)?, |p| p.trim().to_string())?;
        // Independent tyre factors (`factor.NAME`) are applied after the raw values.
        let (factors, entries): (Vec<_>, Vec<_>) = entries.into_iter().partition(|e| {
            e.ov.path
                .trim()
                .starts_with(crate::input::tyre_factors::PREFIX)
        });
        // The factors not set keep the file's own values, whatever raw values change.
        let original = (!factors.is_empty()).then(|| t.clone());
        for e in entries.iter() {
            let o = &e.ov;
            let (sec, key) = o.path.trim().split_once('.').ok_or_else(|| {
                o.origin.at_path(format!(
                    "a .tir value is addressed as `SECTION.KEY`, not `{}`",
                    o.path
                ))
            })?;
            let secs: Vec<String> = t.sections.keys().cloned().collect();
            let s = t.sections.get_mut(sec).ok_or_else(|| {
                let known = secs.iter().map(|k| k.as_str());
                o.origin.at_path(format!(
                    "{} has no section [{sec}]{}",
                    path.display(),
                    crate::input::suggest::did_you_mean(sec, known)
                ))
            })?;
            // Only a value the file has: a misspelt key would otherwise be added, read
            // by nothing, and the run would go on with the file's value.
            let keys: Vec<String> = s.keys.keys().cloned().collect();
            let v = s.keys.get_mut(key).ok_or_else(|| {
                o.origin.at_path(format!(
                    "{} has no key {key} in [{sec}]{}",
                    path.display(),
                    crate::input::suggest::did_you_mean(key, keys.iter().map(|k| k.as_str()))
                ))
            })?;
            v.value = o.value.trim().to_string();
            e.placed(path);
        }
        if let Some(original) = original {
            crate::input::tyre_factors::apply(&mut t, &original, path, &factors, &entries)?;
        }
        Ok(t)
    }

    /// Replaces the value text of `section.key`; false when the file has no such key.
    pub(crate) fn set_value(&mut self, section: &str, key: &str, value: String) -> bool {
        match self
            .sections
            .get_mut(section)
            .and_then(|s| s.keys.get_mut(key))
        {
            Some(e) => {
                e.value = value;
                true
            }
            None => false,
        }
    }

    /// Parses `text` as if read from `path`.
    pub fn parse(path: &Path, text: &str) -> Result<TirFile, InputError> {
        let err = |line: usize, column: usize, field: String, message: String| InputError {
            file: path.to_path_buf(),
            line: Some(line),
            column: Some(column),
            field,
            message,
            kind: Default::default(),
        };
        let mut sections: HashMap<String, Section> = HashMap::new();
        let mut current: Option<String> = None;
        let mut brace_depth = 0usize;
        // The line of the `{` still open, so an unclosed one is reported, not swallowing
        // the rest of the file.
        let mut brace_line = 0usize;
        // Editors on Windows start files with a byte-order mark.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let unclosed = |from: usize| {
            err(
                from,
                1,
                String::new(),
                "`{` is never closed (a table header must end with `}`)".into(),
            )
        };
        for (idx, raw) in text.lines().enumerate() {
            let line_no = idx + 1;
            let indent = raw.len() - raw.trim_start().len();
            let line = raw.trim();
            if brace_depth > 0 && (line.starts_with('[') || line.contains('=')) {
                return Err(unclosed(brace_line));
            }
            if brace_depth > 0 {
                brace_depth += line.matches('{').count();
                brace_depth = brace_depth.saturating_sub(line.matches('}').count());
                continue;
            }
            if line.is_empty() || line.starts_with('$') || line.starts_with('!') {
                continue;
            }
            if line.starts_with('{') {
                brace_line = line_no;
                brace_depth = line
                    .matches('{')
                    .count()
                    .saturating_sub(line.matches('}').count());
                continue;
            }
            if let Some(rest) = line.strip_prefix('[') {
                let name = rest
                    .split(']')
                    .next()
                    .filter(|_| rest.contains(']'))
                    .ok_or_else(|| {
                        err(
                            line_no,
                            indent + 1,
                            rest.trim().to_string(),
                            "section header without `]`".into(),
                        )
                    })?
                    .trim()
                    .to_string();
                if sections.contains_key(&name) {
                    return Err(err(
                        line_no,
                        indent + 1,
                        name.clone(),
                        format!("section [{name}] appears twice"),
                    ));
                }
                sections.insert(
                    name.clone(),
                    Section {
                        line: line_no,
                        keys: HashMap::new(),
                    },
                );
                current = Some(name);
                continue;
            }
            let Some(eq) = line.find('=') else {
                // Rows of a table (e.g. [SHAPE] {radial width} followed by number pairs).
                if line
                    .split_whitespace()
                    .all(|tok| tok.parse::<f64>().is_ok())
                {
                    continue;
                }
                // The field: the section and what stands on the line (a key cut short).
                let field = match &current {
                    Some(sec) => format!("{sec}.{line}"),
                    None => line.to_string(),
                };
                return Err(err(
                    line_no,
                    indent + 1,
                    field,
                    format!("expected `KEY = value`, `[SECTION]` or a comment, found `{line}`"),
                ));
            };
            let key = line[..eq].trim().to_string();
            let Some(sec) = current.as_ref() else {
                return Err(err(
                    line_no,
                    indent + 1,
                    key,
                    "key before the first [SECTION] header".into(),
                ));
            };
            let mut value = line[eq + 1..].trim();
            let value_col =
                indent + eq + 2 + (line[eq + 1..].len() - line[eq + 1..].trim_start().len());
            let value = if let Some(q) = value.strip_prefix('\'') {
                match q.find('\'') {
                    Some(end) => q[..end].to_string(),
                    None => {
                        return Err(err(
                            line_no,
                            value_col,
                            format!("{sec}.{key}"),
                            "string without closing quote".into(),
                        ))
                    }
                }
            } else {
                if let Some(c) = value.find(['$', '!']) {
                    value = value[..c].trim();
                }
                value.to_string()
            };
            let s = sections.get_mut(sec).expect("current section exists");
            if s.keys.contains_key(&key) {
                return Err(err(
                    line_no,
                    indent + 1,
                    format!("{sec}.{key}"),
                    format!("key given twice (first on line {})", s.keys[&key].line),
                ));
            }
            s.keys.insert(
                key,
                Entry {
                    value,
                    line: line_no,
                    column: value_col,
                },
            );
        }
        if brace_depth > 0 {
            return Err(unclosed(brace_line));
        }
        Ok(TirFile {
            path: path.to_path_buf(),
            sections,
            end_line: text.lines().count().max(1),
        })
    }

    /// The entry of `section.key`, if present.
    pub fn entry(&self, section: &str, key: &str) -> Option<&Entry> {
        self.sections.get(section).and_then(|s| s.keys.get(key))
    }

    /// Every entry as (section, key, entry), in no particular order.
    pub fn entries(&self) -> impl Iterator<Item = (&str, &str, &Entry)> {
        self.sections.iter().flat_map(|(s, sec)| {
            sec.keys
                .iter()
                .map(move |(k, e)| (s.as_str(), k.as_str(), e))
        })
    }

    /// True when the file has section `[section]`.
    pub fn has_section(&self, section: &str) -> bool {
        self.sections.contains_key(section)
    }

    /// An error about `section.key`, located at the key, else at the section header, else
    /// (no such section) at the file's last line.
    pub fn error(&self, section: &str, key: &str, message: impl Into<String>) -> InputError {
        let (line, column) = match (self.entry(section, key), self.sections.get(section)) {
            (Some(e), _) => (Some(e.line), Some(e.column)),
            (None, Some(s)) => (Some(s.line), Some(1)),
            (None, None) => (Some(self.end_line), None),
        };
        InputError {
            file: self.path.clone(),
            line,
            column,
            field: format!("{section}.{key}"),
            message: message.into(),
            kind: Default::default(),
        }
    }

    /// A required number.
    pub fn f64(&self, section: &str, key: &str) -> Result<f64, InputError> {
        let Some(e) = self.entry(section, key) else {
            let msg = if self.has_section(section) {
                format!("missing key {key} in [{section}]")
            } else {
                format!("missing section [{section}] (needed for {key})")
            };
            return Err(self.error(section, key, msg));
        };
        let v: f64 = e.value.parse().map_err(|_| {
            self.error(
                section,
                key,
                format!("expected a number, found `{}`", e.value),
            )
        })?;
        if !v.is_finite() {
            return Err(self.error(section, key, format!("must be finite, got {v}")));
        }
        crate::input::bounds::for_key(key)
            .check(v)
            .map_err(|e| self.error(section, key, e.message))
    }

    /// An optional number with a default.
    pub fn f64_or(&self, section: &str, key: &str, default: f64) -> Result<f64, InputError> {
        if self.entry(section, key).is_some() {
            self.f64(section, key)
        } else {
            Ok(default)
        }
    }

    /// A required number > 0.
    pub fn positive(&self, section: &str, key: &str) -> Result<f64, InputError> {
        let v = self.f64(section, key)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.error(section, key, format!("must be positive, got {v}")))
        }
    }

    /// A required number >= 0.
    pub fn non_negative(&self, section: &str, key: &str) -> Result<f64, InputError> {
        let v = self.f64(section, key)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.error(section, key, format!("must not be negative, got {v}")))
        }
    }

    /// A required number in [lo, hi].
    pub fn in_range(&self, section: &str, key: &str, lo: f64, hi: f64) -> Result<f64, InputError> {
        let v = self.f64(section, key)?;
        if v >= lo && v <= hi {
            Ok(v)
        } else {
            Err(self.error(section, key, format!("must lie in [{lo}, {hi}], got {v}")))
        }
    }

    /// A required string (quotes removed).
    pub fn string(&self, section: &str, key: &str) -> Result<String, InputError> {
        match self.entry(section, key) {
            Some(e) => Ok(e.value.clone()),
            None => {
                let msg = if self.has_section(section) {
                    format!("missing key {key} in [{section}]")
                } else {
                    format!("missing section [{section}] (needed for {key})")
                };
                Err(self.error(section, key, msg))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "$ header comment\n[UNITS]\nLENGTH = 'meter'\nMASS = 'kg'\n[INERTIA]\nMASS = 9.3 $ whole tyre\n!comment\n[SHAPE]\n{radial width}\n 1.0 0.0\n 1.0 0.4\n[VERTICAL]\nVERTICAL_STIFFNESS = -2e5\n";

    #[test]
    fn sections_keys_and_lines() {
        let t = TirFile::parse(Path::new("a.tir"), TEXT).unwrap();
        assert_eq!(t.string("UNITS", "MASS").unwrap(), "kg");
        assert_eq!(t.f64("INERTIA", "MASS").unwrap(), 9.3);
        assert_eq!(t.entry("INERTIA", "MASS").unwrap().line, 6);
        let e = t.positive("VERTICAL", "VERTICAL_STIFFNESS").unwrap_err();
        assert_eq!(e.line, Some(13));
        assert!(e.to_string().starts_with("a.tir:13:"), "{e}");
        assert!(e.to_string().contains("VERTICAL.VERTICAL_STIFFNESS"), "{e}");
        let m = t.f64("VERTICAL", "FNOMIN").unwrap_err();
        assert_eq!(m.line, Some(12), "{m}");
        assert!(m.message.contains("missing key FNOMIN"), "{m}");
    }

    #[test]
    fn duplicate_key_and_junk_are_refused() {
        let e = TirFile::parse(Path::new("b.tir"), "[A]\nX = 1\nX = 2\n").unwrap_err();
        assert_eq!(e.line, Some(3));
        let e = TirFile::parse(Path::new("b.tir"), "[A]\nX 1\n").unwrap_err();
        assert_eq!(e.line, Some(2));
    }
}
