//! Reading TOML property files with errors that name the file, the line and the field.
//!
//! Every input file (mechanisms, flexible bodies, roads, tyres, vehicles, scenes) is read
//! through [`Source`]: serde does the typing, and both serde's errors and the semantic
//! checks that follow (a negative mass, a joint naming a missing body, NaN) are reported
//! as `file:line:column: field `path`: message`, the line found from the TOML spans.

pub mod bounds;
pub mod csv_table;
pub(crate) mod loader;
pub(crate) mod overrides;
pub mod provenance;
pub mod regular;
pub mod suggest;
pub mod tir;
pub mod tyre_factors;

pub use loader::{fnv1a, normalized, read_text, Applied, Layer, Loader};
pub use overrides::{read_file as read_overrides, value_text, Origin, Override};

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use toml_edit::{ImDocument, Item};

/// A bad input file: where, which field, and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct InputError {
    /// The file the error is in.
    pub file: PathBuf,
    /// 1-based line and column, when the position is known.
    pub line: Option<usize>,
    /// 1-based column, when the position is known.
    pub column: Option<usize>,
    /// Dotted path of the field, e.g. `body[2].mass_kg`; empty for the whole file.
    pub field: String,
    /// What is wrong, in words.
    pub message: String,
    /// What is wrong, for a caller that acts on it (most errors are only shown).
    pub kind: InputErrorKind,
}

/// What an [`InputError`] is about, where a caller acts on more than its message.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum InputErrorKind {
    /// Anything else: the message says it.
    #[default]
    Other,
    /// A flexible-body file lacks the variant asked for (the message lists those it
    /// defines).
    NoVariant {
        /// The variant asked for.
        number: u32,
    },
    /// A trailer file lacks the load case asked for (the message lists those it
    /// defines).
    NoLoadCase,
}

impl InputError {
    /// The same error, of kind `kind`.
    pub fn with_kind(self, kind: InputErrorKind) -> InputError {
        InputError { kind, ..self }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
            if let Some(c) = self.column {
                write!(f, ":{c}")?;
            }
        }
        if self.field.is_empty() {
            write!(f, ": {}", self.message)
        } else {
            write!(f, ": field `{}`: {}", self.field, self.message)
        }
    }
}

impl std::error::Error for InputError {}

/// The field a TOML syntax error at `line` (1-based) lies in: the key written on that
/// line inside the table above it (`hardpoints.strut_top_m`), or the table header the
/// line is.
fn syntax_field(text: &str, line: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let header = |s: &str| {
        let t = s.trim();
        t.starts_with('[').then(|| {
            t.split(']')
                .next()
                .unwrap_or("")
                .trim_matches('[')
                .trim()
                .to_string()
        })
    };
    let Some(here) = lines.get(line.saturating_sub(1)) else {
        return String::new();
    };
    if let Some(h) = header(here).filter(|h| !h.is_empty()) {
        return h;
    }
    let key = here
        .split_once('=')
        .map(|(k, _)| k.trim())
        .filter(|k| !k.is_empty() && !k.starts_with('#'))
        .unwrap_or("");
    let table = lines[..line - 1]
        .iter()
        .rev()
        .find_map(|s| header(s))
        .unwrap_or_default();
    match (table.is_empty(), key.is_empty()) {
        // A line cut short: what is written there.
        (true, true) => here.trim().chars().take(40).collect(),
        (true, false) => key.to_string(),
        (false, true) => table,
        (false, false) => format!("{table}.{key}"),
    }
}

/// A value refused before it is located in a file: the field's path relative to the
/// value checked (`bump_stop.clearance_m`, `stiffness_n_m[2]`; empty for the value
/// itself) and the message. [`Source::locate`] puts it at its file, line and field.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldError {
    /// Path below the checked value, as file keys name it.
    pub field: Vec<Seg>,
    /// What is wrong.
    pub message: String,
}

impl FieldError {
    /// An error about the checked value itself.
    pub fn here(message: impl Into<String>) -> FieldError {
        FieldError {
            field: Vec::new(),
            message: message.into(),
        }
    }

    /// An error about the key `key` of the checked value.
    pub fn at(key: impl Into<Seg>, message: impl Into<String>) -> FieldError {
        FieldError {
            field: vec![key.into()],
            message: message.into(),
        }
    }

    /// The same error one level further down: under `key`.
    pub fn under(mut self, key: impl Into<Seg>) -> FieldError {
        self.field.insert(0, key.into());
        self
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "field `{}`: {}", path_string(&self.field), self.message)
        }
    }
}

impl std::error::Error for FieldError {}

/// One step of a field path: a table key or an array index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Seg {
    /// A table key.
    Key(String),
    /// An array index (0-based).
    Index(usize),
}

impl From<&str> for Seg {
    fn from(s: &str) -> Self {
        Seg::Key(s.to_string())
    }
}

impl From<String> for Seg {
    fn from(s: String) -> Self {
        Seg::Key(s)
    }
}

impl From<usize> for Seg {
    fn from(i: usize) -> Self {
        Seg::Index(i)
    }
}

/// Builds a field path: `path!["body", 2, "mass_kg"]`.
#[macro_export]
macro_rules! path {
    ($($s:expr),* $(,)?) => { [$($crate::input::Seg::from($s)),*] };
}

/// Renders a path as `body[2].mass_kg`.
pub fn path_string(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// A TOML file kept with its text and spans, so any field can be located later.
#[derive(Debug)]
pub struct Source {
    /// The file's path as given.
    pub path: PathBuf,
    text: String,
    doc: ImDocument<String>,
    /// Values overrides put in place of the file's: errors about them are theirs.
    set_by: Vec<SetBy>,
}

/// A value of a [`Source`] set by an override, not by its file.
#[derive(Clone, Debug)]
pub struct SetBy {
    /// The path set (`table.key`, `array[2].key`).
    pub path: String,
    /// The value, as written in the override.
    pub value: String,
    /// Where the override was written.
    pub origin: Origin,
}

impl Source {
    /// Reads and parses `path` as it is on disk (syntax only; typing happens in
    /// [`Source::parse`]). Files of a run are read through a [`Loader`] instead, which
    /// applies the run's overrides.
    pub fn read(path: &Path) -> Result<Source, InputError> {
        Source::from_text(path, loader::read_text(path)?)
    }

    /// Parses `text` as if read from `path` (used by tests and generated inputs).
    pub fn from_text(path: &Path, text: String) -> Result<Source, InputError> {
        Source::from_text_set_by(path, text, Vec::new())
    }

    /// Parses `text`, in which overrides set the values `set_by` (errors about those
    /// values, and about fields inside them, are located at the override).
    pub fn from_text_set_by(
        path: &Path,
        text: String,
        set_by: Vec<SetBy>,
    ) -> Result<Source, InputError> {
        match ImDocument::parse(text.clone()) {
            Ok(doc) => {
                let src = Source {
                    path: path.to_path_buf(),
                    text,
                    doc,
                    set_by,
                };
                src.check_bounds()?;
                Ok(src)
            }
            Err(e) => {
                let (line, column) = match e.span() {
                    Some(s) => line_col(&text, s.start),
                    None => (None, None),
                };
                Err(InputError {
                    file: path.to_path_buf(),
                    line,
                    column,
                    field: line.map_or(String::new(), |l| syntax_field(&text, l)),
                    message: format!("TOML syntax: {}", e.message()),
                    kind: Default::default(),
                })
            }
        }
    }

    /// Every number of the file against its key's plausibility bound
    /// ([`bounds::for_key`]); a key without a bound of its own inherits its table's
    /// (`stiffness_n_m = { x = [...], y = [...] }`).
    fn check_bounds(&self) -> Result<(), InputError> {
        fn value(
            v: &toml_edit::Value,
            b: &'static bounds::Bound,
            path: &mut Vec<Seg>,
        ) -> Option<(Vec<Seg>, String)> {
            use toml_edit::Value as V;
            let x = match v {
                V::Float(f) => *f.value(),
                V::Integer(i) => *i.value() as f64,
                V::Array(a) => {
                    for (k, e) in a.iter().enumerate() {
                        path.push(Seg::Index(k));
                        let r = value(e, b, path);
                        path.pop();
                        if r.is_some() {
                            return r;
                        }
                    }
                    return None;
                }
                V::InlineTable(t) => {
                    for (k, e) in t.iter() {
                        path.push(Seg::Key(k.to_string()));
                        let r = value(e, bound_of(k, b), path);
                        path.pop();
                        if r.is_some() {
                            return r;
                        }
                    }
                    return None;
                }
                _ => return None,
            };
            (!b.accepts(x)).then(|| (path.clone(), b.message(x)))
        }
        fn bound_of(key: &str, inherited: &'static bounds::Bound) -> &'static bounds::Bound {
            let own = bounds::for_key(key);
            if std::ptr::eq(own, bounds::any_number()) {
                inherited
            } else {
                own
            }
        }
        fn table(
            t: &toml_edit::Table,
            b: &'static bounds::Bound,
            path: &mut Vec<Seg>,
        ) -> Option<(Vec<Seg>, String)> {
            for (k, e) in t.iter() {
                path.push(Seg::Key(k.to_string()));
                let r = item(e, bound_of(k, b), path);
                path.pop();
                if r.is_some() {
                    return r;
                }
            }
            None
        }
        fn item(
            it: &Item,
            b: &'static bounds::Bound,
            path: &mut Vec<Seg>,
        ) -> Option<(Vec<Seg>, String)> {
            match it {
                Item::Table(t) => table(t, b, path),
                Item::ArrayOfTables(a) => {
                    for (k, t) in a.iter().enumerate() {
                        path.push(Seg::Index(k));
                        let r = table(t, b, path);
                        path.pop();
                        if r.is_some() {
                            return r;
                        }
                    }
                    None
                }
                Item::Value(v) => value(v, b, path),
                Item::None => None,
            }
        }
        match item(self.doc.as_item(), bounds::any_number(), &mut Vec::new()) {
            Some((path, message)) => Err(self.error(&path, message)),
            None => Ok(()),
        }
    }

    /// The raw text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Deserialises the whole file into `T`; type errors, unknown and missing keys come
    /// back located.
    pub fn parse<T: DeserializeOwned>(&self) -> Result<T, InputError> {
        toml::from_str(&self.text).map_err(|e| self.serde_error(e))
    }

    /// Deserialises only the top-level key `key` into `T` (`None` when the file lacks
    /// it); errors are located in the whole file.
    pub fn parse_key<T: DeserializeOwned>(&self, key: &str) -> Result<Option<T>, InputError> {
        use serde::de::{DeserializeSeed, IgnoredAny, MapAccess, Visitor};
        use std::marker::PhantomData;
        struct Pick<'k, T>(&'k str, PhantomData<T>);
        impl<'de, T: DeserializeOwned> Visitor<'de> for Pick<'_, T> {
            type Value = Option<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "a table")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<Option<T>, A::Error> {
                let mut out = None;
                while let Some(k) = m.next_key::<String>()? {
                    if k == self.0 {
                        out = Some(m.next_value::<T>()?);
                    } else {
                        m.next_value::<IgnoredAny>()?;
                    }
                }
                Ok(out)
            }
        }
        impl<'de, T: DeserializeOwned> DeserializeSeed<'de> for Pick<'_, T> {
            type Value = Option<T>;
            fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<Option<T>, D::Error> {
                d.deserialize_map(self)
            }
        }
        Pick(key, PhantomData)
            .deserialize(toml::Deserializer::new(&self.text))
            .map_err(|e| self.serde_error(e))
    }

    /// A serde error of this file, located.
    fn serde_error(&self, e: toml::de::Error) -> InputError {
        let span = e.span();
        let (line, column) = match &span {
            Some(s) => line_col(&self.text, s.start),
            None => (None, None),
        };
        let mut field = span
            .map(|s| path_string(&self.path_at(s)))
            .unwrap_or_default();
        if field.is_empty() {
            // A value of the wrong type whose span the document does not map to a path:
            // the key written on its line.
            field = line.map_or(String::new(), |l| syntax_field(&self.text, l));
        }
        self.blamed(InputError {
            file: self.path.clone(),
            line,
            column,
            field,
            message: e.message().trim().to_string(),
            kind: Default::default(),
        })
    }

    /// `e` moved to the override that set its field, if one did.
    fn blamed(&self, e: InputError) -> InputError {
        let under = |p: &str| {
            e.field == p
                || e.field.starts_with(&format!("{p}."))
                || e.field.starts_with(&format!("{p}["))
        };
        match self.set_by.iter().rev().find(|s| under(&s.path)) {
            // towride's own values (a stress case, a study): the file and field say
            // more than "towride", and the message says the value was set.
            Some(s) if matches!(s.origin, Origin::Program(_) | Origin::Derived(_)) => InputError {
                message: format!(
                    "{} (value {} set by {})",
                    e.message,
                    s.value,
                    s.origin.describe()
                ),
                ..e
            },
            Some(s) => s
                .origin
                .at_path(format!(
                    "{} `{}` = {}: {}",
                    normalized(&self.path).display(),
                    e.field,
                    s.value,
                    e.message
                ))
                .with_kind(e.kind),
            None => e,
        }
    }

    /// An error about the field at `path`, located at that field (or at its nearest
    /// existing parent when the field itself is absent).
    pub fn error(&self, path: &[Seg], message: impl Into<String>) -> InputError {
        let (line, column) = match self.span_of(path) {
            Some(s) => line_col(&self.text, s.start),
            None => (None, None),
        };
        self.blamed(InputError {
            file: self.path.clone(),
            line,
            column,
            field: path_string(path),
            message: message.into(),
            kind: Default::default(),
        })
    }

    /// A [`FieldError`] of the value at `base`, located at its field.
    pub fn locate(&self, base: &[Seg], e: FieldError) -> InputError {
        let mut p = base.to_vec();
        p.extend(e.field);
        self.error(&p, e.message)
    }

    /// Checks that `value` is finite, else an error at `path`.
    pub fn finite(&self, path: &[Seg], value: f64) -> Result<f64, InputError> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.error(path, format!("must be a finite number, got {value}")))
        }
    }

    /// The file `rel` names, relative to this file's folder, or an error at `path` (the
    /// field that refers to it) when there is no such file.
    pub fn existing_file(&self, path: &[Seg], rel: &str) -> Result<PathBuf, InputError> {
        let full = self.path.parent().unwrap_or(Path::new(".")).join(rel);
        if full.is_file() {
            Ok(full)
        } else {
            Err(self.error(path, no_file(&full)))
        }
    }

    /// Checks that `value` is finite and > 0.
    pub fn positive(&self, path: &[Seg], value: f64) -> Result<f64, InputError> {
        self.finite(path, value)?;
        if value > 0.0 {
            Ok(value)
        } else {
            Err(self.error(path, format!("must be positive, got {value}")))
        }
    }

    /// Checks that `value` is finite and >= 0.
    pub fn non_negative(&self, path: &[Seg], value: f64) -> Result<f64, InputError> {
        self.finite(path, value)?;
        if value >= 0.0 {
            Ok(value)
        } else {
            Err(self.error(path, format!("must not be negative, got {value}")))
        }
    }

    /// Span of the deepest existing item along `path` (tables, arrays of tables, inline
    /// tables and arrays alike).
    fn span_of(&self, path: &[Seg]) -> Option<Range<usize>> {
        let mut item: &Item = self.doc.as_item();
        let mut best = None;
        for seg in path {
            let next = match seg {
                Seg::Key(k) => {
                    if let Some(s) = item
                        .as_table_like()
                        .and_then(|t| t.key(k))
                        .and_then(|k| k.span())
                    {
                        best = Some(s);
                    }
                    item.get(k.as_str())
                }
                Seg::Index(i) => item.get(*i),
            };
            match next {
                Some(n) => {
                    if let Some(s) = n.span() {
                        best = Some(s);
                    }
                    item = n;
                }
                None => break,
            }
        }
        best
    }

    /// The path of the innermost item whose span contains `span` (for serde errors).
    fn path_at(&self, span: Range<usize>) -> Vec<Seg> {
        let mut path = Vec::new();
        let mut item: &Item = self.doc.as_item();
        let inside = |s: Option<Range<usize>>| {
            s.is_some_and(|s| s.start <= span.start && span.start < s.end.max(s.start + 1))
        };
        loop {
            let mut next: Option<(Seg, &Item)> = None;
            match item {
                Item::Table(t) => {
                    for (k, v) in t.iter() {
                        let key_span = t.key(k).and_then(|kk| kk.span());
                        if inside(v.span()) || inside(key_span) {
                            next = Some((Seg::Key(k.to_string()), v));
                            break;
                        }
                    }
                }
                Item::ArrayOfTables(a) => {
                    for (i, t) in a.iter().enumerate() {
                        if inside(t.span()) {
                            next = Some((Seg::Index(i), &item[i]));
                            break;
                        }
                    }
                    // A key inside an array-of-tables entry lies after the header span.
                    if next.is_none() {
                        let mut last = None;
                        for (i, t) in a.iter().enumerate() {
                            if t.span().is_some_and(|s| s.start <= span.start) {
                                last = Some(i);
                            }
                        }
                        if let Some(i) = last {
                            next = Some((Seg::Index(i), &item[i]));
                        }
                    }
                }
                Item::Value(toml_edit::Value::InlineTable(t)) => {
                    for (k, v) in t.iter() {
                        if inside(v.span()) {
                            path.push(Seg::Key(k.to_string()));
                            break;
                        }
                    }
                }
                _ => {}
            }
            match next {
                Some((seg, it)) => {
                    path.push(seg);
                    item = it;
                }
                None => return path,
            }
        }
    }
}

/// "no file X", with the files of X's folder closest to its name (a misspelt name).
pub fn no_file(full: &Path) -> String {
    let name = full
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let dir = full.parent().filter(|d| !d.as_os_str().is_empty());
    let siblings: Vec<String> = std::fs::read_dir(dir.unwrap_or(Path::new(".")))
        .map(|rd| {
            rd.flatten()
                .take(10_000)
                .map(|e| e.file_name().to_string_lossy().to_string())
                .collect()
        })
        .unwrap_or_default();
    format!(
        "no file {}{}",
        normalized(full).display(),
        crate::input::suggest::did_you_mean(&name, siblings.iter().map(|s| s.as_str()))
    )
}

/// 1-based (line, column) of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (Option<usize>, Option<usize>) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (Some(line), Some(col))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Body {
        name: String,
        mass_kg: f64,
    }

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct File {
        body: Vec<Body>,
    }

    const TEXT: &str =
        "# test\n[[body]]\nname = \"a\"\nmass_kg = 1.0\n\n[[body]]\nname = \"b\"\nmass_kg = -2.0\n";

    #[test]
    fn semantic_error_names_line_and_field() {
        let src = Source::from_text(Path::new("m.toml"), TEXT.into()).unwrap();
        let e = src.error(&path!["body", 1, "mass_kg"], "must be positive");
        assert_eq!(e.line, Some(8));
        assert_eq!(e.field, "body[1].mass_kg");
        assert!(e.to_string().starts_with("m.toml:8:"), "{e}");
    }

    #[test]
    fn serde_errors_are_located() {
        let text = TEXT.replace("mass_kg = -2.0", "mas_kg = -2.0");
        let src = Source::from_text(Path::new("m.toml"), text).unwrap();
        let e = src.parse::<File>().unwrap_err();
        assert_eq!(e.line, Some(8), "{e}");
        assert!(e.field.starts_with("body[1]"), "{e}");
        assert!(e.message.contains("mas_kg"), "{e}");
    }

    #[test]
    fn syntax_error_is_located() {
        let e = Source::from_text(Path::new("m.toml"), "a = [1,\nb = 2\n".into())
            .err()
            .unwrap();
        assert!(e.line.is_some(), "{e}");
    }
}
