//! A forgiving reader for recorded CSV files: `;`, tab or `,` separators (detected from
//! the header), decimal commas, junk and comment lines before the header (the header is
//! the first line naming every needed column, exactly or ignoring case and spacing), a
//! units row under the header, columns in any order, units in the header
//! (`name [unit]`). Time bases ([`super::timebase`]): a time column, a time column
//! coarser than the sampling (rebuilt from the row count), or a declared sample rate
//! with no time column. Repaired, with a note each: a missing sample (a gap in time,
//! interpolated), a repeated sample (same time, dropped), an empty cell (interpolated).
//! Anything else that does not read is an error naming file, line and column.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use towride_mbs::input::regular::{read_regular, DATA_FILE_MAX_BYTES};
use towride_mbs::input::InputError;

use super::timebase::{self, TimeBase, TimeBaseKind};
use super::units::time_factor;

pub use super::measurement::{read_measurement, Measurement};

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
    /// 1-based line of the units row, if there is one.
    pub units_line: Option<usize>,
    /// How the sample times were found.
    pub time_base: TimeBase,
    /// One line per repair or inference.
    pub notes: Vec<String>,
}

/// Where the times of a table come from.
#[derive(Clone, Debug)]
pub struct TimeSpec {
    /// The time column's name, if the file has one.
    pub column: Option<String>,
    /// The declared sample rate [Hz]: the clock without a time column, else a check.
    pub rate_hz: Option<f64>,
    /// Use the declared rate when the file has no such column.
    pub fall_back_to_rate: bool,
}

impl TimeSpec {
    /// Times from the column `name`.
    pub fn column(name: &str) -> TimeSpec {
        TimeSpec {
            column: Some(name.to_string()),
            rate_hz: None,
            fall_back_to_rate: false,
        }
    }
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
        kind: Default::default(),
    }
}

/// Splits a line at `sep`, returning each trimmed, unquoted cell with its 1-based
/// character column.
pub(super) fn cells(line: &str, sep: char) -> Vec<(String, usize)> {
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
pub(super) fn split_unit(cell: &str) -> (String, Option<String>) {
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

/// A column name compared ignoring case and runs of spaces or underscores.
pub(super) fn normalised(name: &str) -> String {
    name.split(|c: char| c.is_whitespace() || c == '_')
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
        .to_lowercase()
}

pub(super) fn parse_number(s: &str, decimal_comma: bool) -> Option<f64> {
    let v: f64 = if decimal_comma && s.contains(',') {
        s.replace(',', ".").parse().ok()?
    } else {
        s.parse().ok()?
    };
    v.is_finite().then_some(v)
}

pub(super) fn is_missing(s: &str) -> bool {
    matches!(s, "" | "NaN" | "nan" | "NA" | "-")
}

/// The text of `file` as lines (BOM and CR removed; encodings as [`super::text`]).
pub(super) fn lines_of(file: &Path) -> Result<Vec<String>, InputError> {
    let bytes = read_regular(file, DATA_FILE_MAX_BYTES)?;
    let text = super::text::decode(file, &bytes)?;
    Ok(text
        .split('\n')
        .map(|l| l.trim_end_matches('\r').to_string())
        .collect())
}

/// The header names indexed for [`Names::find`]: a lookup per wanted column in a map.
/// A scan per column, normalising each name again, was quadratic: a comma-separated
/// header tried with `;` is one long cell, normalised once per wanted column (100 000
/// columns took over 10 minutes).
struct Names<'a> {
    exact: HashMap<&'a str, usize>,
    loose: HashMap<String, usize>,
}

impl<'a> Names<'a> {
    fn new(names: &'a [(String, Option<String>, usize)]) -> Names<'a> {
        let (mut exact, mut loose) = (HashMap::new(), HashMap::new());
        for (k, n) in names.iter().enumerate() {
            exact.entry(n.0.as_str()).or_insert(k);
            loose.entry(normalised(&n.0)).or_insert(k);
        }
        Names { exact, loose }
    }

    /// Position of `w` among the header names: exact, else ignoring case and spacing
    /// (the first such column).
    fn find(&self, w: &str) -> Option<usize> {
        self.exact
            .get(w)
            .or_else(|| self.loose.get(&normalised(w)))
            .copied()
    }
}

/// The header: the first line that names every wanted column for some separator.
type Header = (
    usize,
    char,
    Vec<(String, Option<String>, usize)>,
    Vec<usize>,
);

fn header(file: &Path, lines: &[String], wanted: &[&str]) -> Result<Header, InputError> {
    let mut best: (usize, usize, Vec<&str>) = (0, 0, wanted.to_vec());
    for (i, line) in lines.iter().enumerate() {
        if line.trim_start().starts_with('#') {
            continue;
        }
        for sep in [';', '\t', ','] {
            let names: Vec<(String, Option<String>, usize)> = cells(line, sep)
                .into_iter()
                .map(|(c, col)| {
                    let (n, u) = split_unit(&c);
                    (n, u, col)
                })
                .collect();
            let index = Names::new(&names);
            let idx: Vec<Option<usize>> = wanted.iter().map(|w| index.find(w)).collect();
            let hits = idx.iter().filter(|x| x.is_some()).count();
            if hits == wanted.len() {
                return Ok((i, sep, names, idx.into_iter().flatten().collect()));
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
    if best.0 > 0 {
        let msg = format!(
            "no header line names all of {wanted:?}; line {} comes closest but lacks {:?}",
            best.1, best.2
        );
        return Err(err(file, Some(best.1), None, best.2[0], msg));
    }
    // Nothing names a wanted column: blame the first line of content, where a header
    // belongs, and the first column looked for.
    let (line, msg) = match first_content(lines) {
        Some(i) => (
            i + 1,
            format!(
                "no header line names the columns {wanted:?}; the first line of content is here"
            ),
        ),
        None => (1, no_content(lines)),
    };
    Err(err(file, Some(line), None, wanted[0], msg))
}

/// 0-based index of the first line that is neither blank nor a `#` comment.
pub(super) fn first_content(lines: &[String]) -> Option<usize> {
    lines
        .iter()
        .position(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
}

/// Why a file without a line of content has no header.
pub(super) fn no_content(lines: &[String]) -> String {
    if lines.iter().all(|l| l.trim().is_empty()) {
        "the file is empty".into()
    } else {
        format!(
            "the file holds only comment lines (up to line {}), no header and no rows",
            lines.len()
        )
    }
}

/// Reads `time_column` and `columns` from `file`.
pub fn read_table(file: &Path, time_column: &str, columns: &[&str]) -> Result<Table, InputError> {
    read_table_with(file, &TimeSpec::column(time_column), columns)
}

/// Reads `columns` from `file` with the time base of `time`.
pub fn read_table_with(
    file: &Path,
    time: &TimeSpec,
    columns: &[&str],
) -> Result<Table, InputError> {
    if super::mdf::is_mdf(file) {
        return super::mdf::read_table(file, time, columns);
    }
    let lines = lines_of(file)?;
    let mut wanted: Vec<&str> = Vec::new();
    if let Some(t) = &time.column {
        wanted.push(t);
    }
    wanted.extend_from_slice(columns);
    let found = match header(file, &lines, &wanted) {
        Err(e) if time.fall_back_to_rate && time.column.is_some() && time.rate_hz.is_some() => {
            // No such time column: the declared rate is the clock.
            wanted.remove(0);
            header(file, &lines, &wanted).map_err(|_| e)?
        }
        other => other?,
    };
    let has_time = wanted.len() > columns.len();
    let (hline, sep, names, idx) = found;
    let mut units: Vec<Option<String>> = idx.iter().map(|&c| names[c].1.clone()).collect();
    let decimal_comma_allowed = sep != ',';
    let mut decimal_comma = false;
    let mut units_line = None;
    // (line, time, values): raw rows in file order.
    let mut rows: Vec<(usize, f64, Vec<Option<f64>>)> = Vec::new();
    let need = idx.iter().copied().max().unwrap_or(0) + 1;
    for (i, line) in lines.iter().enumerate().skip(hline + 1) {
        let ln = i + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let cs = cells(line, sep);
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
        // More filled fields than the header: values without a name, or columns shifted
        // (in a comma-separated file decimal commas, `0,5`, split every number in two).
        if let Some(extra) = cs[names.len().min(cs.len())..]
            .iter()
            .find(|c| !c.0.is_empty())
        {
            let hint = if sep == ',' {
                ": decimal commas in a comma-separated file? (write `0.5`, or separate \
                 the columns with `;`)"
            } else {
                ": a value without a column name"
            };
            return Err(err(
                file,
                Some(ln),
                Some(extra.1),
                &names[0].0,
                format!(
                    "row has {} fields, the header has {}{hint}",
                    cs.len(),
                    names.len()
                ),
            ));
        }
        // A units row right under the header (common in logger exports): no wanted
        // cell is a number and some are filled.
        if rows.is_empty() && units_line.is_none() {
            let text: Vec<&str> = idx.iter().map(|&c| cs[c].0.as_str()).collect();
            let numeric = text
                .iter()
                .any(|s| parse_number(s, decimal_comma_allowed).is_some());
            if !numeric && text.iter().any(|s| !s.is_empty()) {
                for (k, s) in text.iter().enumerate() {
                    if !s.is_empty() {
                        units[k].get_or_insert(s.to_string());
                    }
                }
                units_line = Some(ln);
                continue;
            }
        }
        let mut values = Vec::with_capacity(idx.len() + 1);
        if !has_time {
            values.push(Some(0.0));
        }
        for (k, &c) in idx.iter().enumerate() {
            let (s, col) = (&cs[c].0, cs[c].1);
            if (k > 0 || !has_time) && is_missing(s) {
                values.push(None);
                continue;
            }
            match parse_number(s, decimal_comma_allowed) {
                Some(v) if !towride_mbs::input::bounds::any_number().accepts(v) => {
                    let m = towride_mbs::input::bounds::any_number().message(v);
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
    if rows.len() < 10 {
        // Blame the last row read, or the header when no row follows it.
        let line = rows.last().map_or(hline + 1, |r| r.0);
        let what = if rows.is_empty() {
            "no data rows after the header".to_string()
        } else {
            format!("only {} data rows (lines {}-{line})", rows.len(), rows[0].0)
        };
        return Err(err(
            file,
            Some(line),
            None,
            wanted[0],
            format!("{what}; a recording needs at least 10"),
        ));
    }
    let chan_units = if has_time {
        units.split_off(1)
    } else {
        std::mem::take(&mut units)
    };
    let mut notes = Vec::new();
    let (tcol, tname) = if has_time {
        (names[idx[0]].2, wanted[0])
    } else {
        (1, "")
    };
    let time_base;
    if has_time {
        let factor = match &units[0] {
            None => 1.0,
            Some(u) => time_factor(u).ok_or_else(|| {
                err(
                    file,
                    Some(units_line.unwrap_or(hline + 1)),
                    Some(tcol),
                    tname,
                    format!("time unit `{u}` is not s or ms"),
                )
            })?,
        };
        for r in rows.iter_mut() {
            r.1 *= factor;
        }
        let stamps: Vec<f64> = rows.iter().map(|r| r.1).collect();
        match timebase::reconstruct(&stamps, time.rate_hz) {
            Err((k, msg)) => {
                let line = rows.get(k).map(|r| r.0);
                return Err(err(file, line, Some(tcol), tname, msg));
            }
            Ok(Some((t, tb, note))) => {
                for (r, tk) in rows.iter_mut().zip(t) {
                    r.1 = tk;
                }
                notes.push(note);
                time_base = tb;
            }
            Ok(None) => {
                time_base = TimeBase {
                    kind: TimeBaseKind::Column,
                    rate_hz: f64::NAN,
                    stamp_step_s: None,
                    rows_per_stamp: None,
                }
            }
        }
    } else {
        let rate = time.rate_hz.unwrap_or(f64::NAN);
        for (k, r) in rows.iter_mut().enumerate() {
            r.1 = k as f64 / rate;
        }
        notes.push(format!(
            "no time column{}: time base from the declared {rate} Hz, t = 0 at the first row",
            time.column
                .as_ref()
                .map_or(String::new(), |c| format!(" named `{c}`"))
        ));
        time_base = TimeBase {
            kind: TimeBaseKind::Declared,
            rate_hz: rate,
            stamp_step_s: None,
            rows_per_stamp: None,
        };
    }
    let (time_s, columns_out, repairs) = super::repair::repair(
        file,
        rows,
        idx.len() - usize::from(has_time),
        tcol,
        tname,
        columns,
    )?;
    notes.extend(repairs);
    let mut time_base = time_base;
    let n = time_s.len();
    if time_base.kind == TimeBaseKind::Column {
        time_base.rate_hz = (n - 1) as f64 / (time_s[n - 1] - time_s[0]);
        if let Some(r) = time.rate_hz {
            if (time_base.rate_hz / r - 1.0).abs() > 0.01 {
                notes.push(format!(
                    "the time column gives {:.3} Hz, the descriptor declares {r} Hz: the time column is used",
                    time_base.rate_hz
                ));
            }
        }
    }
    Ok(Table {
        file: file.to_path_buf(),
        time_s,
        columns: columns_out,
        units: chan_units,
        separator: sep,
        decimal_comma,
        header_line: hline + 1,
        units_line,
        time_base,
        notes,
    })
}
