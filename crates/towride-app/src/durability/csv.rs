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

fn err(file: &Path, line: Option<usize>, field: &str, message: String) -> InputError {
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

/// Reads the column `name` of `file`.
pub fn read_column(file: &Path, name: &str) -> Result<Column, InputError> {
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
    let idx = full
        .iter()
        .position(|h| *h == name)
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
    let (col_name, unit) = heads[idx].clone();
    let mut values = Vec::new();
    for (line, l) in lines {
        if l.trim().is_empty() || l.trim_start().starts_with('#') {
            continue;
        }
        let cell = l
            .split(sep)
            .nth(idx)
            .map(|c| c.trim().trim_matches('"').trim());
        let cell = cell.ok_or_else(|| {
            err(
                file,
                Some(line),
                &col_name,
                format!("the row has no column {}", idx + 1),
            )
        })?;
        let v: f64 = cell.parse().map_err(|_| {
            err(
                file,
                Some(line),
                &col_name,
                format!("`{cell}` is not a number"),
            )
        })?;
        if !v.is_finite() {
            return Err(err(
                file,
                Some(line),
                &col_name,
                format!("`{cell}` is not a finite number"),
            ));
        }
        values.push(v);
    }
    if values.len() < 3 {
        return Err(err(
            file,
            None,
            &col_name,
            format!(
                "{} values: rainflow counting needs at least 3",
                values.len()
            ),
        ));
    }
    Ok(Column {
        name: col_name,
        unit,
        values,
    })
}
