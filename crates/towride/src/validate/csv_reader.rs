//! A forgiving reader for recorded CSV files: `;`, tab or `,` separators (detected from
//! the header), decimal commas, junk lines before the header (the header is the first
//! line naming every needed column), a units row under the header, columns in any order,
//! units in the header (`name [unit]`). Repaired, with a note each: a missing sample (a
//! gap in time, interpolated), a repeated sample (same time, dropped), an empty cell
//! (interpolated). Anything else that does not read is an error naming file, line and
//! column.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::input::InputError;

use super::descriptor::{Descriptor, Unit};

/// Longest gap [samples] that is interpolated rather than refused.
pub const MAX_GAP_SAMPLES: usize = 20;

/// The requested columns of a CSV file, time in seconds, values as recorded.
#[derive(Clone, Debug)]
pub struct Table {
    /// The CSV file read.
    pub file: PathBuf,
    /// Sample times [s], ascending, gaps filled.
    pub time_s: Vec<f64>,
    /// Values of the requested columns, as recorded, in the order asked for.
    pub columns: Vec<Vec<f64>>,
    /// Unit of each requested column from the header or units row, if given.
    pub units: Vec<Option<String>>,
    /// Column separator found in the header: `;`, tab or `,`.
    pub separator: char,
    /// Numbers are written with a decimal comma.
    pub decimal_comma: bool,
    /// 1-based line of the header.
    pub header_line: usize,
    /// One line per repair.
    pub notes: Vec<String>,
}

/// A recorded run in SI units, keyed by simulated channel name.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// The CSV file read.
    pub file: PathBuf,
    /// Sample times on the recording's clock [s].
    pub time_s: Vec<f64>,
    /// Channels in SI units (gain, sign and unit applied), by simulated channel name.
    pub channels: BTreeMap<String, Vec<f64>>,
    /// Sample rate [Hz].
    pub rate_hz: f64,
    /// One line per repair made while reading.
    pub notes: Vec<String>,
}

pub(super) fn err(
    file: &Path,
    line: Option<usize>,
    column: Option<usize>,
    field: &str,
    msg: String,
) -> InputError {
    InputError {
        file: file.to_path_buf(),
        line,
        column,
        field: field.to_string(),
        message: msg,
    }
}

/// Splits a line at `sep`, returning each trimmed, unquoted cell with its 1-based
/// character column.
fn cells(line: &str, sep: char) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    let mut start_chars = 0;
    for part in line.split(sep) {
        let lead = part.chars().take_while(|c| c.is_whitespace()).count();
        let cell = part.trim().trim_matches('"').trim().to_string();
        out.push((cell, start_chars + lead + 1));
        start_chars += part.chars().count() + 1;
    }
    out
}

/// `name [unit]` or `name (unit)` -> (name, unit).
fn split_unit(cell: &str) -> (String, Option<String>) {
    for (open, close) in [('[', ']'), ('(', ')')] {
        if cell.ends_with(close) {
            if let Some(i) = cell.rfind(open) {
                let unit = cell[i + 1..cell.len() - 1].trim().to_string();
                return (cell[..i].trim().to_string(), Some(unit));
            }
        }
    }
    (cell.trim().to_string(), None)
}

fn parse_number(s: &str, decimal_comma: bool) -> Option<f64> {
    let v: f64 = if decimal_comma && s.contains(',') {
        s.replace(',', ".").parse().ok()?
    } else {
        s.parse().ok()?
    };
    v.is_finite().then_some(v)
}

fn is_missing(s: &str) -> bool {
    matches!(s, "" | "NaN" | "nan" | "NA" | "-")
}

/// Reads `time_column` and `columns` from `file`.
pub fn read_table(file: &Path, time_column: &str, columns: &[&str]) -> Result<Table, InputError> {
    let bytes =
        std::fs::read(file).map_err(|e| err(file, None, None, "", format!("cannot read: {e}")))?;
    let text = String::from_utf8_lossy(&bytes).replace('\u{feff}', "");
    let lines: Vec<&str> = text.split('\n').map(|l| l.trim_end_matches('\r')).collect();
    let mut wanted: Vec<&str> = vec![time_column];
    wanted.extend_from_slice(columns);
    // The header: the first line that names every wanted column for some separator.
    let mut found = None;
    let mut best: (usize, usize, Vec<&str>) = (0, 0, wanted.clone());
    'search: for (i, line) in lines.iter().enumerate() {
        for sep in [';', '\t', ','] {
            let names: Vec<(String, Option<String>, usize)> = cells(line, sep)
                .into_iter()
                .map(|(c, col)| {
                    let (n, u) = split_unit(&c);
                    (n, u, col)
                })
                .collect();
            let idx: Vec<Option<usize>> = wanted
                .iter()
                .map(|w| names.iter().position(|n| n.0 == *w))
                .collect();
            let hits = idx.iter().filter(|x| x.is_some()).count();
            if hits == wanted.len() {
                found = Some((i, sep, names, idx.into_iter().flatten().collect::<Vec<_>>()));
                break 'search;
            }
            if hits > best.0 {
                let missing = wanted
                    .iter()
                    .zip(&idx)
                    .filter(|(_, x)| x.is_none())
                    .map(|(w, _)| *w)
                    .collect();
                best = (hits, i + 1, missing);
            }
        }
    }
    let Some((hline, sep, names, idx)) = found else {
        let msg = if best.0 > 0 {
            format!(
                "no header line names all of {wanted:?}; line {} comes closest but lacks {:?}",
                best.1, best.2
            )
        } else {
            format!("no header line names the columns {wanted:?}")
        };
        return Err(err(file, (best.0 > 0).then_some(best.1), None, "", msg));
    };
    let mut units: Vec<Option<String>> = idx.iter().map(|&c| names[c].1.clone()).collect();
    let decimal_comma_allowed = sep != ',';
    let mut decimal_comma = false;
    // (line, time, values): raw rows in file order.
    let mut rows: Vec<(usize, f64, Vec<Option<f64>>)> = Vec::new();
    for (i, line) in lines.iter().enumerate().skip(hline + 1) {
        let ln = i + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let cs = cells(line, sep);
        let need = idx.iter().copied().max().unwrap_or(0) + 1;
        if cs.len() < need {
            let missing = idx
                .iter()
                .position(|&c| c >= cs.len())
                .map_or("", |k| wanted[k]);
            return Err(err(
                file,
                Some(ln),
                Some(line.chars().count() + 1),
                missing,
                format!(
                    "row has {} fields, the header has {}",
                    cs.len(),
                    names.len()
                ),
            ));
        }
        // More fields than the header in a comma-separated file: decimal commas
        // (`0,5`) split every number in two and would shift the columns silently.
        if sep == ','
            && cs[names.len().min(cs.len())..]
                .iter()
                .any(|c| !c.0.is_empty())
        {
            return Err(err(
                file,
                Some(ln),
                Some(cs[names.len()].1),
                &names[0].0,
                format!(
                    "row has {} fields, the header has {}: decimal commas in a \
                     comma-separated file? (write `0.5`, or separate the columns with `;`)",
                    cs.len(),
                    names.len()
                ),
            ));
        }
        // A units row right under the header (common in logger exports).
        let is_unit =
            |c: &usize| time_factor(&cs[*c].0).is_some() || Unit::parse(&cs[*c].0).is_some();
        if rows.is_empty() && idx.iter().all(is_unit) {
            for (k, &c) in idx.iter().enumerate() {
                units[k].get_or_insert(cs[c].0.clone());
            }
            continue;
        }
        let mut values = Vec::with_capacity(idx.len());
        for (k, &c) in idx.iter().enumerate() {
            let (s, col) = (&cs[c].0, cs[c].1);
            if k > 0 && is_missing(s) {
                values.push(None);
                continue;
            }
            match parse_number(s, decimal_comma_allowed) {
                Some(v) if !crate::input::bounds::any_number().accepts(v) => {
                    let m = crate::input::bounds::any_number().message(v);
                    return Err(err(file, Some(ln), Some(col), wanted[k], m));
                }
                Some(v) => {
                    decimal_comma |= decimal_comma_allowed && s.contains(',');
                    values.push(Some(v));
                }
                None => {
                    return Err(err(
                        file,
                        Some(ln),
                        Some(col),
                        wanted[k],
                        format!("not a number: `{s}`"),
                    ))
                }
            }
        }
        let t = values.remove(0).unwrap_or(f64::NAN);
        rows.push((ln, t, values));
    }
    let tcol = names[idx[0]].2;
    let factor = match &units[0] {
        None => 1.0,
        Some(u) => time_factor(u).ok_or_else(|| {
            err(
                file,
                Some(hline + 1),
                Some(tcol),
                time_column,
                format!("time unit `{u}` is not s or ms"),
            )
        })?,
    };
    for r in rows.iter_mut() {
        r.1 *= factor;
    }
    let (time_s, columns, notes) =
        super::repair::repair(file, rows, idx.len() - 1, tcol, time_column, columns)?;
    Ok(Table {
        file: file.to_path_buf(),
        time_s,
        columns,
        units: units.split_off(1),
        separator: sep,
        decimal_comma,
        header_line: hline + 1,
        notes,
    })
}

fn time_factor(u: &str) -> Option<f64> {
    match u {
        "s" | "sec" => Some(1.0),
        "ms" => Some(1e-3),
        _ => None,
    }
}

/// Reads the CSV of a descriptor and converts every channel to SI with its gain and sign.
pub fn read_measurement(desc: &Descriptor) -> Result<Measurement, InputError> {
    let names: Vec<&str> = desc.channels.iter().map(|c| c.column.as_str()).collect();
    let table = read_table(&desc.data, &desc.time_column, &names)?;
    let mut channels = BTreeMap::new();
    for (k, spec) in desc.channels.iter().enumerate() {
        let header_unit = match &table.units[k] {
            None => None,
            Some(u) => Some(Unit::parse(u).ok_or_else(|| {
                err(
                    &table.file,
                    Some(table.header_line),
                    None,
                    &spec.column,
                    format!("unit `{u}` is not m/s^2 or g"),
                )
            })?),
        };
        let unit = match (spec.unit, header_unit) {
            (Some(d), Some(h)) if d != h => {
                return Err(err(
                    &table.file,
                    Some(table.header_line),
                    None,
                    &spec.column,
                    format!(
                        "header says {} but the descriptor {} says {}",
                        h.label(),
                        desc.path.display(),
                        d.label()
                    ),
                ))
            }
            (Some(u), _) | (None, Some(u)) => u,
            (None, None) => {
                return Err(err(
                    &table.file,
                    Some(table.header_line),
                    None,
                    &spec.column,
                    "no unit in the header (`name [unit]`) nor in the descriptor's channel".into(),
                ))
            }
        };
        let f = unit.to_si() * spec.gain * spec.sign;
        channels.insert(
            spec.simulated.clone(),
            table.columns[k].iter().map(|x| x * f).collect(),
        );
    }
    let n = table.time_s.len();
    let rate_hz = (n - 1) as f64 / (table.time_s[n - 1] - table.time_s[0]);
    Ok(Measurement {
        file: table.file,
        time_s: table.time_s,
        channels,
        rate_hz,
        notes: table.notes,
    })
}
