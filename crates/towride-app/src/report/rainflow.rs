//! The files of `towride rainflow --out DIR`: the cycles (`rainflow_<column>.csv`), the
//! range-mean matrix (`rainflow_<column>_matrix.csv`) and a picture
//! (`rainflow_<column>.png`): a histogram of cycle ranges and the cumulative load
//! spectrum (cycles at or above each range, log scale), the usual way a load history
//! is shown to a designer.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::figure::{render, Axis, Figure, HeaderLine, Panel, Style, Trace, PALETTE};
use super::ReportError;
use crate::durability::{Cycle, RangeMeanMatrix};

/// The three files written.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RainflowFiles {
    /// The cycles: range, mean, count.
    pub cycles_csv: String,
    /// The range-mean matrix.
    pub matrix_csv: String,
    /// The histogram and load spectrum.
    pub png: String,
}

/// Writes the files for `column` (unit `unit`) into `dir`; `title` heads the picture.
pub fn write(
    dir: &Path,
    column: &str,
    unit: &str,
    cycles: &[Cycle],
    matrix: &RangeMeanMatrix,
    title: &str,
) -> Result<RainflowFiles, ReportError> {
    let io = |p: &Path, e: std::io::Error| ReportError::Plot(format!("{}: {e}", p.display()));
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    let stem = format!("rainflow_{column}");
    let cycles_csv = dir.join(format!("{stem}.csv"));
    let mut s = format!("range [{unit}],mean [{unit}],count [-]\n");
    for c in cycles {
        let _ = writeln!(s, "{},{},{}", c.range, c.mean, c.count);
    }
    crate::atomic::write(&cycles_csv, s).map_err(|e| io(&cycles_csv, e))?;

    let matrix_csv = dir.join(format!("{stem}_matrix.csv"));
    let mut s = format!("range_lo [{unit}],range_hi [{unit}]");
    for w in matrix.mean_edges.windows(2) {
        let _ = write!(s, ",mean {}..{} [{unit}] count [-]", w[0], w[1]);
    }
    s.push('\n');
    for (i, row) in matrix.counts.iter().enumerate() {
        let _ = write!(s, "{},{}", matrix.range_edges[i], matrix.range_edges[i + 1]);
        for c in row {
            let _ = write!(s, ",{c}");
        }
        s.push('\n');
    }
    crate::atomic::write(&matrix_csv, s).map_err(|e| io(&matrix_csv, e))?;

    let png = dir.join(format!("{stem}.png"));
    render(&png, &figure(column, unit, cycles, matrix, title))?;
    let show = |p: PathBuf| p.display().to_string();
    Ok(RainflowFiles {
        cycles_csv: show(cycles_csv),
        matrix_csv: show(matrix_csv),
        png: show(png),
    })
}

fn figure(
    column: &str,
    unit: &str,
    cycles: &[Cycle],
    matrix: &RangeMeanMatrix,
    title: &str,
) -> Figure {
    // Histogram as an outline of bars: counts per range bin, summed over the means.
    let mut bars = vec![(0.0, 0.0)];
    for (i, row) in matrix.counts.iter().enumerate() {
        let n: f64 = row.iter().sum();
        let (lo, hi) = (matrix.range_edges[i], matrix.range_edges[i + 1]);
        bars.extend([(lo, n), (hi, n)]);
    }
    bars.push((*matrix.range_edges.last().unwrap_or(&0.0), 0.0));
    let mut hist = Panel::new(
        format!(
            "{column}: cycles per range bin ({} bins)",
            matrix.counts.len()
        ),
        format!("range [{unit}]"),
        "cycles [-]",
    );
    hist.traces
        .push(Trace::new("rainflow cycles", bars, Style::line(PALETTE[0])));

    // Load spectrum: the number of cycles with a range at or above each range.
    let mut sorted: Vec<&Cycle> = cycles.iter().filter(|c| c.range > 0.0).collect();
    sorted.sort_by(|a, b| b.range.total_cmp(&a.range));
    let mut cum: f64 = 0.0;
    let mut spectrum = Vec::new();
    for c in sorted {
        spectrum.push((cum.max(0.5), c.range));
        cum += c.count;
        spectrum.push((cum, c.range));
    }
    let mut spec = Panel::new(
        format!("{column}: load spectrum"),
        "",
        format!("range [{unit}]"),
    );
    spec.x = Axis::log("cycles at or above the range [-]");
    spec.traces.push(Trace::new(
        "cumulative cycles",
        spectrum,
        Style::line(PALETTE[1]),
    ));
    let mut fig = Figure::new(vec![hist, spec], 2);
    fig.header.push(HeaderLine {
        text: title.to_string(),
        size: 18.0,
        colour: [0, 0, 0],
    });
    fig
}
