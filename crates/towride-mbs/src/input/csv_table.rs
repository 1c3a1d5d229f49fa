//! Numeric CSV tables with named columns: each row's values in the order asked for, with
//! its line number, and errors that name the file, the line and the column.

use std::path::Path;

use super::InputError;

/// One data row: the 1-based line and the requested columns' values.
pub struct Row {
    /// 1-based line in the file, when known.
    pub line: Option<usize>,
    /// The requested columns' values, in the order asked for.
    pub values: Vec<f64>,
    /// The override that changed a value of this row (`column[row] = value`, where it
    /// was written): errors about the row are its.
    pub set_by: Option<(String, super::Origin)>,
}

/// Moves an error located at a row an override changed to the override (the file's line
/// still holds the old value): wrap a reader's checks of `rows` in it.
pub fn blamed(file: &Path, rows: &[Row], e: InputError) -> InputError {
    let hit = rows
        .iter()
        .find(|r| r.line.is_some() && r.line == e.line && e.file == file);
    match hit.and_then(|r| r.set_by.as_ref()) {
        // towride's own values keep the file's place (see `Source`).
        Some((_, super::Origin::Program(_) | super::Origin::Derived(_))) => e,
        Some((what, origin)) => origin
            .at_path(format!(
                "{}:{} ({what}): field `{}`: {}",
                file.display(),
                e.line.unwrap_or(0),
                e.field,
                e.message
            ))
            .with_kind(e.kind),
        None => e,
    }
}

/// Reads `file` (`#` comments, trimmed fields) and returns the columns `names` of every
/// row as finite numbers, with the loader's overrides of this file applied (path
/// `column[row]`, the row counted from 0 over the data rows).
pub fn read_columns(
    file: &Path,
    names: &[&str],
    loader: &super::Loader,
) -> Result<Vec<Row>, InputError> {
    let err = |line: Option<usize>, field: &str, msg: String| error(file, line, field, msg);
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_path(file)
        .map_err(|e| err(None, "", format!("cannot read: {e}")))?;
    let headers = rdr
        .headers()
        .map_err(|e| err(Some(1), "", format!("bad header: {e}")))?
        .clone();
    let cols = names
        .iter()
        .map(|name| {
            headers.iter().position(|h| h == *name).ok_or_else(|| {
                err(
                    Some(1),
                    name,
                    format!(
                        "missing column (header must name {}; found {headers:?})",
                        names.join(", ")
                    ),
                )
            })
        })
        .collect::<Result<Vec<usize>, InputError>>()?;
    let mut rows = Vec::new();
    for rec in rdr.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map(|p| p.line() as usize);
            match e.kind() {
                // Name the column: the first one missing, or the first of a row with more
                // (decimal commas, `0,5`, split a number in two).
                csv::ErrorKind::UnequalLengths {
                    expected_len, len, ..
                } => {
                    let (col, hint) = if len < expected_len {
                        (headers.get(*len as usize).unwrap_or(""), "")
                    } else {
                        (
                            headers.get(0).unwrap_or(""),
                            ": decimal commas? (write `0.5`)",
                        )
                    };
                    err(
                        line,
                        col,
                        format!("row has {len} fields, the header {expected_len}{hint}"),
                    )
                }
                _ => err(line, "", e.to_string()),
            }
        })?;
        let line = rec.position().map(|p| p.line() as usize);
        let mut values = Vec::with_capacity(cols.len());
        for (&c, name) in cols.iter().zip(names) {
            let v: f64 = rec
                .get(c)
                .unwrap_or("")
                .parse()
                .map_err(|e| err(line, name, format!("not a number: {e}")))?;
            if !v.is_finite() {
                return Err(err(line, name, format!("must be finite, got {v}")));
            }
            let v = super::bounds::for_key(name)
                .check(v)
                .map_err(|e| err(line, name, e.message))?;
            values.push(v);
        }
        rows.push(Row {
            line,
            values,
            set_by: None,
        });
    }
    let entries = super::loader::in_force(file, loader.matching(file)?, |p| p.replace(' ', ""))?;
    for e in entries {
        let o = &e.ov;
        let cell = o
            .path
            .strip_suffix(']')
            .and_then(|p| p.split_once('['))
            .and_then(|(c, r)| Some((c, r.parse::<usize>().ok()?)));
        let Some((col, row)) = cell else {
            return Err(o.origin.at_path(format!(
                "a CSV value is addressed as `column[row]`, not `{}`",
                o.path
            )));
        };
        let c = names.iter().position(|n| *n == col).ok_or_else(|| {
            o.origin.at_path(format!(
                "{} has no column `{col}` that is read (columns: {})",
                file.display(),
                names.join(", ")
            ))
        })?;
        let n = rows.len();
        let r = rows.get_mut(row).ok_or_else(|| {
            o.origin.at_path(format!(
                "{} has {n} data rows; row {row} does not exist",
                file.display()
            ))
        })?;
        r.values[c] = o
            .value
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                o.origin
                    .at_path(format!("`{}` is not a finite number", o.value))
            })?;
        // The same plausibility bound as a value written in the file.
        super::bounds::for_key(col)
            .check(r.values[c])
            .map_err(|b| {
                o.origin
                    .at_path(format!("{}: {}", file.display(), b.message))
            })?;
        r.set_by = Some((
            format!("{} = {}", o.path.trim(), o.value.trim()),
            o.origin.clone(),
        ));
        e.placed(file);
    }
    Ok(rows)
}

/// An error about a CSV file at a line and column.
pub fn error(file: &Path, line: Option<usize>, field: &str, message: String) -> InputError {
    InputError {
        file: file.to_path_buf(),
        line,
        column: None,
        field: field.to_string(),
        message,
        kind: Default::default(),
    }
}
