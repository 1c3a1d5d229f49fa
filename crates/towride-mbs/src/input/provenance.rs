//! Where each physical value of a property file comes from: its source class.
//!
//! The class is written as a trailing comment on the value's line whose text starts with
//! the class in square brackets, followed by the source in words:
//!
//! ```text
//! stiffness_n_m = [2.0e6, 2.0e6, 4.0e6]  # [published] Yu et al. 2001, tab. 2
//! VERTICAL_STIFFNESS = 2.0e5 $ [scaled] 205/60 R15 reference x (185/205), docs/road_tyre.md
//! ```
//!
//! Classes are exactly `measured`, `published` (with the citation), `scaled` (with the
//! rule) and `assumed`. TOML files (`#` comments) are read through their syntax tree, so
//! the key is the value's dotted path (`bracket_mount.stiffness_n_m`, `sensor[3].position_m`;
//! an inline table or an array is one value); `.tir` files (`$` or `!` comments) are keyed
//! `SECTION.KEY`. For a value written over several lines the comment may stand on the
//! key's line or on the value's last line. Any other bracketed text (`$ [m]`, a unit) is
//! not a class: such a value counts as untagged.

use std::path::Path;

use toml_edit::{ImDocument, Item, Value};

use crate::input::regular::{read_regular_text, PROPERTY_FILE_MAX_BYTES};
use crate::input::tir::TirFile;
use crate::input::{line_col, path_string, InputError, Seg};

/// Where a value comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SourceClass {
    /// Measured on the object modelled (or its twin), with the measurement named.
    Measured,
    /// Taken from a publication, with the citation.
    Published,
    /// Derived from a published or measured value by a stated rule (size, load, geometry).
    Scaled,
    /// Chosen without a source: engineering judgement, a class figure, a placeholder.
    Assumed,
}

impl SourceClass {
    /// All classes, in the order of decreasing confidence.
    pub const ALL: [SourceClass; 4] = [
        SourceClass::Measured,
        SourceClass::Published,
        SourceClass::Scaled,
        SourceClass::Assumed,
    ];

    /// The word written in the file (`measured`, `published`, `scaled`, `assumed`).
    pub fn as_str(self) -> &'static str {
        match self {
            SourceClass::Measured => "measured",
            SourceClass::Published => "published",
            SourceClass::Scaled => "scaled",
            SourceClass::Assumed => "assumed",
        }
    }

    /// The class a comment's text starts with (`[scaled] ...`), and the rest of the text.
    pub fn parse_comment(comment: &str) -> Option<(SourceClass, &str)> {
        let rest = comment.trim_start().strip_prefix('[')?;
        let (word, after) = rest.split_once(']')?;
        let class = SourceClass::ALL
            .into_iter()
            .find(|c| c.as_str() == word.trim())?;
        Some((class, after.trim()))
    }
}

impl std::fmt::Display for SourceClass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.as_str())
    }
}

/// One tagged value of a property file.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ProvenanceEntry {
    /// Dotted path of the value (`bracket_mount.stiffness_n_m`; in `.tir` files
    /// `SECTION.KEY`).
    pub key: String,
    /// 1-based line of the key.
    pub line: usize,
    /// The source class.
    pub class: SourceClass,
    /// The comment's text after the class: citation, rule or reasoning.
    pub source: String,
}

/// A numeric value without a class: its key and line.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Untagged {
    /// Dotted path of the value, as in [`ProvenanceEntry::key`].
    pub key: String,
    /// 1-based line of the key.
    pub line: usize,
}

/// The classes of every tagged value of the file at `path` (`.tir` by its extension,
/// else TOML), in file order. Values without a class are not listed (see
/// [`untagged_values`]).
pub fn read_provenance(path: &Path) -> Result<Vec<ProvenanceEntry>, InputError> {
    Ok(scan(path)?.0)
}

/// The numeric values of the file at `path` that carry no class, in file order, apart
/// from the format and discretisation settings that are not physical values
/// ([`is_setting`]).
pub fn untagged_values(path: &Path) -> Result<Vec<Untagged>, InputError> {
    Ok(scan(path)?.1)
}

/// Keys whose numbers are format versions, indices, discretisation counts or mode
/// selection settings, not physical values: they need no source class (the mesh
/// `divisions`, a variant's `number`, everything under a flexible body's `[selection]`).
pub fn is_setting(key: &str) -> bool {
    let last = key.rsplit('.').next().unwrap_or(key);
    if last == "divisions"
        || key.starts_with("selection.")
        || (key.starts_with("variant[") && last == "number")
    {
        return true;
    }
    const SETTINGS: [&str; 7] = [
        "MDI_HEADER.FILE_VERSION",
        "MODEL.FITTYP",
        "CONTACT_PATCH.ELLIPS_NWIDTH",
        "CONTACT_PATCH.ELLIPS_NLENGTH",
        "hitch.variant",
        "fixed_interface_modes",
        "schema_version",
    ];
    SETTINGS.contains(&key)
}

/// The classes of one file: tagged values, untagged numbers, and how many of each class.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FileProvenance {
    /// The file.
    pub file: String,
    /// Tagged values in file order.
    pub entries: Vec<ProvenanceEntry>,
    /// Numeric values without a class (physical values only, see [`is_setting`]).
    pub untagged: Vec<Untagged>,
}

/// The classes of every property file under some paths (`towride provenance`).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Survey {
    /// Version of this JSON layout.
    pub schema_version: u32,
    /// Per file, in path order.
    pub files: Vec<FileProvenance>,
    /// Number of values per class over all files (measured, published, scaled, assumed).
    pub counts: Vec<(SourceClass, usize)>,
    /// Number of numeric values without a class over all files.
    pub untagged: usize,
}

/// Reads the classes of the files at `paths`: a file as given, a folder recursively
/// (its `.toml` and `.tir` files, in name order).
pub fn survey(paths: &[std::path::PathBuf]) -> Result<Survey, InputError> {
    fn walk(p: &Path, out: &mut Vec<std::path::PathBuf>) -> Result<(), InputError> {
        if !p.is_dir() {
            out.push(p.to_path_buf());
            return Ok(());
        }
        let mut kids: Vec<_> = std::fs::read_dir(p)
            .map_err(|e| InputError {
                file: p.to_path_buf(),
                line: None,
                column: None,
                field: String::new(),
                message: format!("cannot read the folder: {e}"),
                kind: Default::default(),
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        kids.sort();
        for k in kids {
            let ext = k.extension().and_then(|e| e.to_str()).unwrap_or("");
            if k.is_dir() || ext == "toml" || ext == "tir" {
                walk(&k, out)?;
            }
        }
        Ok(())
    }
    let mut list = Vec::new();
    for p in paths {
        let before = list.len();
        walk(p, &mut list)?;
        // A survey of nothing would pass with exit 0 and "0 numbers without a class".
        if list.len() == before {
            return Err(InputError {
                file: p.to_path_buf(),
                line: None,
                column: None,
                field: String::new(),
                message: "no property file (.toml or .tir) in this folder".into(),
                kind: Default::default(),
            });
        }
    }
    let mut files = Vec::new();
    for f in list {
        let (entries, untagged) = scan(&f)?;
        files.push(FileProvenance {
            file: f.display().to_string(),
            entries,
            untagged,
        });
    }
    let counts = SourceClass::ALL
        .into_iter()
        .map(|c| {
            let n = files
                .iter()
                .map(|f| f.entries.iter().filter(|e| e.class == c).count())
                .sum();
            (c, n)
        })
        .collect();
    let untagged = files.iter().map(|f| f.untagged.len()).sum();
    Ok(Survey {
        schema_version: 1,
        files,
        counts,
        untagged,
    })
}

type Scan = (Vec<ProvenanceEntry>, Vec<Untagged>);

fn scan(path: &Path) -> Result<Scan, InputError> {
    // Not `loader::read_text`: a pipe or `/dev/zero` named here must not hang.
    let text = read_regular_text(path, PROPERTY_FILE_MAX_BYTES)?;
    if text.trim().is_empty() {
        return Err(InputError {
            file: path.to_path_buf(),
            line: None,
            column: None,
            field: String::new(),
            message: "is empty: no values to classify".into(),
            kind: Default::default(),
        });
    }
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("tir"))
    {
        scan_tir(path, &text)
    } else {
        scan_toml(path, &text)
    }
}

/// The text of the comment that starts on `line` (0-based) at or after byte `from`
/// (`marks`: the comment characters), skipping quoted strings.
fn comment_on(line: &str, from: usize, marks: &[char]) -> Option<String> {
    let mut quote: Option<char> = None;
    for (i, c) in line.char_indices().filter(|(i, _)| *i >= from) {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '"' || c == '\'' => quote = Some(c),
            None if marks.contains(&c) => return Some(line[i + c.len_utf8()..].to_string()),
            None => {}
        }
    }
    None
}

fn scan_tir(path: &Path, text: &str) -> Result<Scan, InputError> {
    let tir = TirFile::parse(path, text)?;
    let lines: Vec<&str> = text.lines().collect();
    let mut tagged = Vec::new();
    let mut untagged = Vec::new();
    for (section, key, entry) in tir.entries() {
        let full = format!("{section}.{key}");
        let raw = lines.get(entry.line - 1).copied().unwrap_or("");
        let from = raw.find('=').map_or(0, |e| e + 1);
        match comment_on(raw, from, &['$', '!'])
            .as_deref()
            .and_then(SourceClass::parse_comment)
        {
            Some((class, source)) => tagged.push(ProvenanceEntry {
                key: full,
                line: entry.line,
                class,
                source: source.to_string(),
            }),
            None if entry.value.trim().parse::<f64>().is_ok() && !is_setting(&full) => untagged
                .push(Untagged {
                    key: full,
                    line: entry.line,
                }),
            None => {}
        }
    }
    tagged.sort_by_key(|e| e.line);
    untagged.sort_by_key(|e| e.line);
    Ok((tagged, untagged))
}

fn scan_toml(path: &Path, text: &str) -> Result<Scan, InputError> {
    let doc = ImDocument::parse(text.to_string()).map_err(|e| {
        let (line, column) = match e.span() {
            Some(s) => line_col(text, s.start),
            None => (None, None),
        };
        InputError {
            file: path.to_path_buf(),
            line,
            column,
            field: String::new(),
            message: format!("TOML syntax: {}", e.message()),
            kind: Default::default(),
        }
    })?;
    let lines: Vec<&str> = text.lines().collect();
    let mut out: Scan = (Vec::new(), Vec::new());
    let mut walk = Walk {
        text,
        lines: &lines,
        out: &mut out,
    };
    walk.item(doc.as_item(), &mut Vec::new());
    out.0.sort_by_key(|e| e.line);
    out.1.sort_by_key(|e| e.line);
    Ok(out)
}

struct Walk<'a> {
    text: &'a str,
    lines: &'a [&'a str],
    out: &'a mut Scan,
}

impl Walk<'_> {
    fn item(&mut self, it: &Item, path: &mut Vec<Seg>) {
        match it {
            Item::Table(t) => {
                for (k, v) in t.iter() {
                    path.push(Seg::Key(k.to_string()));
                    let key_start = t.key(k).and_then(|kk| kk.span()).map(|s| s.start);
                    match v {
                        Item::Value(val) => self.value(val, key_start, path),
                        other => self.item(other, path),
                    }
                    path.pop();
                }
            }
            Item::ArrayOfTables(a) => {
                for (i, t) in a.iter().enumerate() {
                    path.push(Seg::Index(i));
                    self.item(&Item::Table(t.clone()), path);
                    path.pop();
                }
            }
            Item::Value(v) => self.value(v, None, path),
            Item::None => {}
        }
    }

    fn value(&mut self, v: &Value, key_start: Option<usize>, path: &[Seg]) {
        let Some(span) = v.span() else { return };
        let start = key_start.unwrap_or(span.start);
        let (Some(first), _) = line_col(self.text, start) else {
            return;
        };
        let (Some(last), _) = line_col(self.text, span.end.saturating_sub(1)) else {
            return;
        };
        // Byte offset of the value's end within its last line: the comment follows it.
        let last_line_start = self.text[..span.end].rfind('\n').map_or(0, |i| i + 1);
        let on_last = self
            .lines
            .get(last - 1)
            .and_then(|l| comment_on(l, (span.end - last_line_start).min(l.len()), &['#']));
        let on_first = (first != last)
            .then(|| {
                let l = self.lines.get(first - 1)?;
                comment_on(l, 0, &['#'])
            })
            .flatten();
        let tag = on_first
            .as_deref()
            .and_then(SourceClass::parse_comment)
            .or_else(|| on_last.as_deref().and_then(SourceClass::parse_comment));
        let key = path_string(path);
        match tag {
            Some((class, source)) => self.out.0.push(ProvenanceEntry {
                key,
                line: first,
                class,
                source: source.to_string(),
            }),
            None if has_number(v) && !is_setting(&key) => {
                self.out.1.push(Untagged { key, line: first })
            }
            None => {}
        }
    }
}

/// True when `v` is or contains a number.
fn has_number(v: &Value) -> bool {
    match v {
        Value::Float(_) | Value::Integer(_) => true,
        Value::Array(a) => a.iter().any(has_number),
        Value::InlineTable(t) => t.iter().any(|(_, e)| has_number(e)),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("towride-prov-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn toml_classes_keys_and_lines() {
        let p = write(
            "a.toml",
            "# head [assumed] not a value\n[mount]\nk_n_m = 2.0e6  # [published] Yu 2001, tab. 2\n\
             c = [1.0, # [scaled] x 0.5 of ref\n  2.0]\nname = \"x # [assumed]\"\nm_kg = 3.0 # [kg]\n\
             [[node]]\nposition_m = [0.0, 1.0] # [measured] tape\nb = { k = 1.0 } # [assumed] guess\n",
        );
        let got = read_provenance(&p).unwrap();
        let keys: Vec<_> = got
            .iter()
            .map(|e| (e.key.as_str(), e.line, e.class))
            .collect();
        assert_eq!(
            keys,
            [
                ("mount.k_n_m", 3, SourceClass::Published),
                ("mount.c", 4, SourceClass::Scaled),
                ("node[0].position_m", 9, SourceClass::Measured),
                ("node[0].b", 10, SourceClass::Assumed),
            ]
        );
        assert_eq!(got[0].source, "Yu 2001, tab. 2");
        let un = untagged_values(&p).unwrap();
        assert_eq!(
            un,
            [Untagged {
                key: "mount.m_kg".into(),
                line: 7
            }]
        );
    }

    #[test]
    fn tir_classes_and_settings() {
        let p = write(
            "a.tir",
            "[MDI_HEADER]\nFILE_VERSION = 3.0\n[VERTICAL]\nVERTICAL_STIFFNESS = 2.0e5 $ [scaled] ref x 0.9\n\
             FNOMIN = 3500 $ [N]\nNAME = 'a $ [assumed]'\nQ_V1 = 0 ! [assumed] no data\n",
        );
        let got = read_provenance(&p).unwrap();
        assert_eq!(got.len(), 2);
        assert_eq!(got[0].key, "VERTICAL.VERTICAL_STIFFNESS");
        assert_eq!((got[0].line, got[0].class), (4, SourceClass::Scaled));
        assert_eq!(got[1].class, SourceClass::Assumed);
        let un = untagged_values(&p).unwrap();
        assert_eq!(un.len(), 1);
        assert_eq!((un[0].key.as_str(), un[0].line), ("VERTICAL.FNOMIN", 5));
    }

    #[test]
    fn bad_syntax_is_located() {
        let p = write("bad.toml", "a = 1.0\nb = [1.0,\n");
        let e = read_provenance(&p).unwrap_err();
        assert!(
            e.line.is_some() && e.to_string().contains("bad.toml"),
            "{e}"
        );
    }
}
