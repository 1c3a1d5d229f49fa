//! One numeric column of a CSV file, strictly read: the header is the first line not
//! starting with `#`; the separator is `;` or tab when the header holds one, else `,`;
//! a column matches by its full header text or by its name before ` [unit]` (towride's
//! `outputs.csv` style, `hitch_fx [N]`). Every data cell must be a finite number: an
//! empty, non-numeric or NaN cell is an error naming file, line and column, since a
//! repaired sample would change the cycles counted.

use std::path::Path;

use towride_mbs::input::InputError;

/// A column read from a CSV file.
#[derive(Clone, Debug)]
pub struct Column {
    /// The column's name without its unit.
    pub name: String,
    /// The unit from the header (`[N]`), if given.
    pub unit: Option<String>,
    /// The values, in file order.
    pub values: Vec<f64>,
}

pub(crate) fn err(file: &Path, line: Option<usize>, field: &str, message: String) -> InputError {
    InputError {
        file: file.to_path_buf(),
        line,
        column: None,
        field: field.to_string(),
        message,
        kind: Default::default(),
    }
}

/// Splits `name [unit]` into name and unit.
pub fn split_unit(header: &str) -> (String, Option<String>) {
    let h = header.trim().trim_matches('"').trim();
    match (h.rfind('['), h.ends_with(']')) {
        (Some(i), true) => (
            h[..i].trim().to_string(),
            Some(h[i + 1..h.len() - 1].trim().to_string()),
        ),
        _ => (h.to_string(), None),
    }
}

/// Reads the column `name` of `file` (at least 3 values, as rainflow counting needs).
pub fn read_column(file: &Path, name: &str) -> Result<Column, InputError> {
    let col = read_columns(file, &[name])?.columns.remove(0);
    if col.values.len() < 3 {
        return Err(err(
            file,
            None,
            &col.name,
            format!(
                "{} values: rainflow counting needs at least 3",
                col.values.len()
            ),
        ));
    }
    Ok(col)
}

/// Several columns read from a CSV file, and where their lines are.
#[derive(Clone, Debug)]
pub struct Table {
    /// The header's line number (1-based).
    pub header_line: usize,
    /// Each data row's line number (1-based).
    pub lines: Vec<usize>,
    /// The columns, in the order asked for.
    pub columns: Vec<Column>,
}

/// Reads the columns `names` of `file`, in that order.
pub fn read_columns(file: &Path, names: &[&str]) -> Result<Table, InputError> {
    let text = std::fs::read_to_string(file)
        .map_err(|e| err(file, None, "", format!("cannot read: {e}")))?;
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')));
    let (header_line, header) = lines
        .by_ref()
        .find(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .ok_or_else(|| err(file, None, "", "no header line".into()))?;
    let sep = if header.contains('\t') {
        '\t'
    } else if header.contains(';') {
        ';'
    } else {
        ','
    };
    let heads: Vec<(String, Option<String>)> = header.split(sep).map(split_unit).collect();
    let full: Vec<&str> = header
        .split(sep)
        .map(|h| h.trim().trim_matches('"'))
        .collect();
    let mut idx = Vec::with_capacity(names.len());
    for name in names {
        let k = full
            .iter()
            .position(|h| h == name)
            .or_else(|| heads.iter().position(|(n, _)| n == name))
            .ok_or_else(|| {
                let names: Vec<&str> = heads.iter().map(|(n, _)| n.as_str()).collect();
                err(
                    file,
                    Some(header_line),
                    name,
                    format!(
                        "no column `{name}` in the header (columns: {})",
                        names.join(", ")
                    ),
                )
            })?;
        idx.push(k);
    }
    let mut cols: Vec<Column> = idx
        .iter()
        .map(|k| Column {
            name: heads[*k].0.clone(),
            unit: heads[*k].1.clone(),
            values: Vec::new(),
        })
        .collect();
    let mut rows = Vec::new();
    for (line, l) in lines {
        if l.trim().is_empty() || l.trim_start().starts_with('#') {
            continue;
        }
        rows.push(line);
        let cells: Vec<&str> = l.split(sep).collect();
        for (col, k) in cols.iter_mut().zip(&idx) {
            col.values
                .push(cell(file, line, &col.name, *k, cells.get(*k))?);
        }
    }
    Ok(Table {
        header_line,
        lines: rows,
        columns: cols,
    })
}

/// The finite number in the cell `k` (0-based) of a row, `c`.
fn cell(
    file: &Path,
    line: usize,
    name: &str,
    k: usize,
    c: Option<&&str>,
) -> Result<f64, InputError> {
    let c = c
        .map(|c| c.trim().trim_matches('"').trim())
        .ok_or_else(|| {
            err(
                file,
                Some(line),
                name,
                format!("the row has no column {}", k + 1),
            )
        })?;
    let v: f64 = c
        .parse()
        .map_err(|_| err(file, Some(line), name, format!("`{c}` is not a number")))?;
    if !v.is_finite() {
        return Err(err(
            file,
            Some(line),
            name,
            format!("`{c}` is not a finite number"),
        ));
    }
    Ok(v)
}
