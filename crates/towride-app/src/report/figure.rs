//! The figure renderer every PNG and SVG of towride goes through: panels of traces in a
//! grid, each trace one continuous line clipped to its plot area with its true extremes
//! on it (per-pixel-column min/max decimation, [`super::decimate`]), round ticks with
//! legible, distinct labels ([`super::ticks`]), legends in a band above the plot area
//! (never over the data), colour-blind-safe colours (Okabe-Ito), and left/right pairs
//! told apart by line style. [`render`] returns where each panel went ([`PanelLayout`]),
//! which the figure test reads the picture back against.

use std::path::{Path, PathBuf};

use plotters::prelude::*;

use super::canvas::{digit_height, text_width, Align, Canvas, Rect};
use super::decimate::pixel_path;
use super::ticks;
use super::ReportError;

/// An RGB colour.
pub type Rgb = [u8; 3];

/// Okabe and Ito's colour-blind-safe palette without its black (frames are dark) and
/// with its yellow last (faint on white): blue, vermillion, bluish green, reddish
/// purple, orange, sky blue, yellow.
pub const PALETTE: [Rgb; 7] = [
    [0, 114, 178],
    [213, 94, 0],
    [0, 158, 115],
    [204, 121, 167],
    [230, 159, 0],
    [86, 180, 233],
    [240, 228, 66],
];

/// Measured data in validation overlays (Okabe-Ito blue).
pub const MEASURED: Rgb = PALETTE[0];
/// Simulated data in validation overlays (Okabe-Ito vermillion).
pub const SIMULATED: Rgb = PALETTE[1];

/// Picture file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// Portable network graphics (bitmap).
    #[default]
    Png,
    /// Scalable vector graphics.
    Svg,
}

impl Format {
    /// The file extension ("png", "svg").
    pub fn ext(self) -> &'static str {
        match self {
            Format::Png => "png",
            Format::Svg => "svg",
        }
    }

    /// `stem` with this format's extension.
    pub fn file(self, dir: &Path, stem: &str) -> PathBuf {
        dir.join(format!("{stem}.{}", self.ext()))
    }
}

/// How a trace is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Colour.
    pub colour: Rgb,
    /// Line width [px]; 0 draws no line.
    pub width: u32,
    /// Radius of a dot at every point [px]; 0 draws none.
    pub dot: f64,
}

impl Style {
    /// A 2 px line.
    pub fn line(colour: Rgb) -> Style {
        Style {
            colour,
            width: 2,
            dot: 0.0,
        }
    }

    /// The `i`-th palette colour, 2 px line.
    pub fn nth(i: usize) -> Style {
        Style::line(PALETTE[i % PALETTE.len()])
    }

    /// A left/right pair in the `i`-th colour: the left side a 3 px line, the right side
    /// a 1 px line in a darker shade drawn over it, so that both stay visible where they
    /// coincide and each keeps its own extremes.
    pub fn side(i: usize, right: bool) -> Style {
        let c = PALETTE[i % PALETTE.len()];
        if right {
            Style {
                colour: [c[0] / 2, c[1] / 2, c[2] / 2],
                width: 1,
                dot: 0.0,
            }
        } else {
            Style {
                colour: c,
                width: 3,
                dot: 0.0,
            }
        }
    }

    /// Dots of radius `r` without a line.
    pub fn dots(colour: Rgb, r: f64) -> Style {
        Style {
            colour,
            width: 0,
            dot: r,
        }
    }

    /// A line with a dot at each point.
    pub fn line_dots(colour: Rgb) -> Style {
        Style {
            colour,
            width: 2,
            dot: 4.0,
        }
    }
}

/// One trace: label and (x, y) points in drawing order (non-finite values break it).
#[derive(Clone, Debug)]
pub struct Trace {
    /// Legend label.
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub style: Style,
}

impl Trace {
    /// A trace.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Trace {
        Trace {
            label: label.into(),
            points,
            style,
        }
    }
}

/// One axis.
#[derive(Clone, Debug, Default)]
pub struct Axis {
    /// Label with the unit, e.g. "force [N]".
    pub label: String,
    /// Logarithmic (positive values only).
    pub log: bool,
    /// Fixed range; `None`: the data's, padded.
    pub range: Option<(f64, f64)>,
    /// Named ticks (value, label) instead of numbers: categories such as the rows of a
    /// tornado chart.
    pub labels: Vec<(f64, String)>,
}

impl Axis {
    /// A linear axis fitted to the data.
    pub fn linear(label: impl Into<String>) -> Axis {
        Axis {
            label: label.into(),
            ..Axis::default()
        }
    }

    /// A log axis fitted to the data.
    pub fn log(label: impl Into<String>) -> Axis {
        Axis {
            label: label.into(),
            log: true,
            ..Axis::default()
        }
    }
}

/// One panel: title, axes and traces.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// The x axis.
    pub x: Axis,
    /// The y axis.
    pub y: Axis,
    /// The traces, drawn in order (later ones on top).
    pub traces: Vec<Trace>,
}

impl Panel {
    /// A panel with linear axes and no traces yet.
    pub fn new(title: impl Into<String>, x: impl Into<String>, y: impl Into<String>) -> Panel {
        Panel {
            title: title.into(),
            x: Axis::linear(x),
            y: Axis::linear(y),
            traces: Vec::new(),
        }
    }

    /// Adds traces with the palette's colours in order.
    pub fn lines(mut self, lines: impl IntoIterator<Item = (String, Vec<(f64, f64)>)>) -> Panel {
        for (label, points) in lines {
            let style = Style::nth(self.traces.len());
            self.traces.push(Trace::new(label, points, style));
        }
        self
    }
}

/// A line of text above the panels.
#[derive(Clone, Debug)]
pub struct HeaderLine {
    /// The text.
    pub text: String,
    /// Font size [px].
    pub size: f64,
    /// Colour.
    pub colour: Rgb,
}

/// A whole figure: header lines, then panels in a grid.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Width of the picture [px].
    pub width: u32,
    /// Panels per row.
    pub cols: usize,
    /// Height of a row of panels [px].
    pub panel_height: u32,
    /// Lines of text above the panels.
    pub header: Vec<HeaderLine>,
    /// The panels, row by row.
    pub panels: Vec<Panel>,
}

impl Figure {
    /// 1600 px wide, `cols` panels per row, 520 px per row.
    pub fn new(panels: Vec<Panel>, cols: usize) -> Figure {
        Figure {
            width: 1600,
            cols: cols.max(1),
            panel_height: 520,
            header: Vec::new(),
            panels,
        }
    }
}

/// An axis as drawn: value `lo` at pixel `px_lo`, `hi` at `px_hi` (log10 of the values
/// on a log axis).
#[derive(Clone, Debug)]
pub struct AxisMap {
    /// Lower end of the axis range.
    pub lo: f64,
    /// Upper end of the axis range.
    pub hi: f64,
    /// Pixel coordinate of `lo`.
    pub px_lo: f64,
    /// Pixel coordinate of `hi`.
    pub px_hi: f64,
    /// Logarithmic axis.
    pub log: bool,
}

impl AxisMap {
    /// The pixel coordinate of value `v`.
    pub fn px(&self, v: f64) -> f64 {
        let (v, lo, hi) = if self.log {
            (v.log10(), self.lo.log10(), self.hi.log10())
        } else {
            (v, self.lo, self.hi)
        };
        self.px_lo + (v - lo) / (hi - lo) * (self.px_hi - self.px_lo)
    }
}

/// Where one panel was drawn.
#[derive(Clone, Debug)]
pub struct PanelLayout {
    /// The plot area: pixels with x0 <= x < x1 and y0 <= y < y1.
    pub plot: [i32; 4],
    /// The x axis.
    pub x: AxisMap,
    /// The y axis.
    pub y: AxisMap,
    /// The x tick labels, as drawn.
    pub x_ticks: Vec<String>,
    /// The y tick labels, as drawn.
    pub y_ticks: Vec<String>,
    /// Height of a digit of the tick labels [px].
    pub tick_digit_px: f64,
    /// The colour of each trace.
    pub colours: Vec<Rgb>,
    /// The legend's box when it is drawn outside the plot area (x0, y0, x1, y1).
    pub legend: Option<[i32; 4]>,
}

// Font sizes [px]: a tick digit is 0.63 of the size, 13 px at 21.
const TICK: f64 = 21.0;
const LABEL: f64 = 21.0;
const TITLE: f64 = 25.0;
const LEGEND: f64 = 19.0;
const DARK: Rgb = [40, 40, 40];
const GRID: Rgb = [226, 226, 226];

/// Draws `fig` into `path` (PNG, or SVG when the extension is `svg`); returns where each
/// panel went.
pub fn render(path: &Path, fig: &Figure) -> Result<Vec<PanelLayout>, ReportError> {
    let cols = fig.cols.max(1);
    let rows = fig.panels.len().div_ceil(cols).max(1);
    let head: f64 = fig.header.iter().map(|h| h.size * 1.5).sum::<f64>()
        + if fig.header.is_empty() { 0.0 } else { 16.0 };
    let size = (
        fig.width,
        head.ceil() as u32 + fig.panel_height * rows as u32,
    );
    let e = |x: &dyn std::fmt::Display| ReportError::Plot(format!("{}: {x}", path.display()));
    if path.extension().is_some_and(|x| x == "svg") {
        let root = SVGBackend::new(path, size).into_drawing_area();
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let l = draw(
            &Canvas {
                root: &root,
                vector: true,
            },
            fig,
            head,
        )?;
        root.present().map_err(|x| e(&x))?;
        Ok(l)
    } else {
        let root = BitMapBackend::new(path, size).into_drawing_area();
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let l = draw(
            &Canvas {
                root: &root,
                vector: false,
            },
            fig,
            head,
        )?;
        root.present().map_err(|x| e(&x))?;
        Ok(l)
    }
}

fn draw<DB: DrawingBackend>(
    cv: &Canvas<DB>,
    fig: &Figure,
    head: f64,
) -> Result<Vec<PanelLayout>, ReportError> {
    let mut y = 12.0;
    for h in &fig.header {
        cv.text(&h.text, 20.0, y, h.size, h.colour, Align::Left, 0.0, false)?;
        y += h.size * 1.5;
    }
    let cols = fig.cols.max(1);
    let w = fig.width as f64 / cols as f64;
    let mut out = Vec::new();
    for (k, p) in fig.panels.iter().enumerate() {
        let (r, c) = (k / cols, k % cols);
        let cell = Rect {
            x0: (c as f64 * w) as i32,
            y0: head as i32 + (r as u32 * fig.panel_height) as i32,
            x1: ((c + 1) as f64 * w) as i32,
            y1: head as i32 + ((r + 1) as u32 * fig.panel_height) as i32,
        };
        out.push(panel(cv, p, cell)?);
    }
    Ok(out)
}

/// The data range of an axis: finite values (positive on a log axis), padded.
fn range(axis: &Axis, vals: impl Iterator<Item = f64>) -> (f64, f64) {
    if let Some(r) = axis.range {
        return r;
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| v.is_finite() && (!axis.log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return if axis.log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if axis.log {
        let (a, b) = (lo.log10(), hi.log10());
        let pad = 0.05 * (b - a).max(0.5);
        return (10f64.powf(a - pad), 10f64.powf(b + pad));
    }
    if hi == lo {
        let pad = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
        return (lo - pad, hi + pad);
    }
    let pad = 0.04 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Ticks and labels of an axis `len` pixels long, at least `gap` pixels apart, with room
/// for labels `along` wide (x axis) when `along` is set.
fn axis_ticks(a: &Axis, lo: f64, hi: f64, len: f64, gap: f64, along: bool) -> Vec<(f64, String)> {
    if !a.labels.is_empty() {
        let (a0, a1) = (lo.min(hi), lo.max(hi));
        return a
            .labels
            .iter()
            .filter(|(v, _)| *v >= a0 && *v <= a1)
            .cloned()
            .collect();
    }
    if a.log {
        let t = ticks::log(lo, hi);
        let labels = ticks::log_labels(&t, 2);
        return t.into_iter().zip(labels).collect();
    }
    let (mut t, mut step) = ticks::linear(lo, hi, (len / gap).floor().max(2.0) as usize);
    loop {
        let labels = ticks::labels(&t, step);
        let px = len * step / (hi - lo);
        let widest = labels
            .iter()
            .map(|l| text_width(l, TICK))
            .fold(0.0, f64::max);
        if !along || widest + 24.0 <= px || t.len() <= 2 {
            return t.into_iter().zip(labels).collect();
        }
        step = ticks::coarser(step);
        t = ticks::with_step(lo, hi, step);
    }
}

fn panel<DB: DrawingBackend>(
    cv: &Canvas<DB>,
    p: &Panel,
    cell: Rect,
) -> Result<PanelLayout, ReportError> {
    let cw = (cell.x1 - cell.x0) as f64;
    let mut top = cell.y0 as f64 + 10.0;
    if !p.title.is_empty() {
        cv.text(
            &p.title,
            cell.x0 as f64 + cw / 2.0,
            top,
            TITLE,
            DARK,
            Align::Centre,
            0.0,
            false,
        )?;
        top += digit_height(TITLE) + 16.0;
    }
    // Legend entries flow left to right in a band between the title and the plot.
    let show_legend = p.traces.len() > 1 || p.traces.iter().any(|t| !t.label.is_empty());
    let mut legend = None;
    if show_legend {
        let (x_start, x_end) = (cell.x0 as f64 + 24.0, cell.x1 as f64 - 24.0);
        let row_h = digit_height(LEGEND) + 14.0;
        let (mut x, mut y) = (x_start, top);
        let mut rows = 1;
        for t in &p.traces {
            let w = 36.0 + 8.0 + text_width(&t.label, LEGEND) + 26.0;
            if x + w > x_end && x > x_start {
                x = x_start;
                y += row_h;
                rows += 1;
            }
            let mid = y + 0.5 * digit_height(LEGEND);
            let whole = Rect {
                x0: 0,
                y0: 0,
                x1: i32::MAX,
                y1: i32::MAX,
            };
            if t.style.width > 0 {
                cv.polyline(
                    &[(x, mid.round()), (x + 36.0, mid.round())],
                    t.style.colour,
                    t.style.width,
                    whole,
                )?;
            }
            if t.style.dot > 0.0 {
                cv.dot((x + 18.0, mid), t.style.dot, t.style.colour, whole)?;
            }
            cv.text(&t.label, x + 44.0, y, LEGEND, DARK, Align::Left, 0.0, false)?;
            x += w;
        }
        let bottom = top + rows as f64 * row_h;
        legend = Some([
            cell.x0,
            (top - 4.0) as i32,
            cell.x1,
            (bottom - 4.0).ceil() as i32,
        ]);
        top = bottom;
    }
    let tick_h = digit_height(TICK);
    let plot_top = (top + 6.0).round() as i32;
    let plot_bottom = cell.y1 - (8.0 + tick_h + 12.0 + digit_height(LABEL) + 18.0).round() as i32;
    let pts = || p.traces.iter().flat_map(|t| t.points.iter());
    let (ylo, yhi) = range(&p.y, pts().map(|q| q.1));
    let (xlo, xhi) = range(&p.x, pts().map(|q| q.0));
    let plot_h = (plot_bottom - plot_top) as f64;
    let yt = axis_ticks(&p.y, ylo, yhi, plot_h, 56.0, false);
    let widest = yt
        .iter()
        .map(|(_, l)| text_width(l, TICK))
        .fold(0.0, f64::max);
    let plot = Rect {
        x0: cell.x0 + (16.0 + digit_height(LABEL) + 16.0 + widest + 12.0).round() as i32,
        y0: plot_top,
        x1: cell.x1 - 28,
        y1: plot_bottom,
    };
    let xt = axis_ticks(&p.x, xlo, xhi, (plot.x1 - plot.x0) as f64, 120.0, true);
    let xm = AxisMap {
        lo: xlo,
        hi: xhi,
        px_lo: plot.x0 as f64,
        px_hi: (plot.x1 - 1) as f64,
        log: p.x.log,
    };
    let ym = AxisMap {
        lo: ylo,
        hi: yhi,
        px_lo: (plot.y1 - 1) as f64,
        px_hi: plot.y0 as f64,
        log: p.y.log,
    };
    // Grid, frame (just outside the plot area), ticks and labels.
    for (v, l) in &xt {
        let x = xm.px(*v).round() as i32;
        cv.hairline((x, plot.y0), (x, plot.y1 - 1), GRID)?;
        cv.hairline((x, plot.y1), (x, plot.y1 + 6), DARK)?;
        let ty = (plot.y1 + 10) as f64;
        cv.text(l, x as f64, ty, TICK, DARK, Align::Centre, 0.0, false)?;
    }
    for (v, l) in &yt {
        let y = ym.px(*v).round() as i32;
        cv.hairline((plot.x0, y), (plot.x1 - 1, y), GRID)?;
        cv.hairline((plot.x0 - 7, y), (plot.x0 - 1, y), DARK)?;
        let tx = (plot.x0 - 12) as f64;
        cv.text(l, tx, y as f64, TICK, DARK, Align::Right, 0.5, false)?;
    }
    let (fx0, fy0, fx1, fy1) = (plot.x0 - 1, plot.y0 - 1, plot.x1, plot.y1);
    for (a, b) in [
        ((fx0, fy0), (fx1, fy0)),
        ((fx1, fy0), (fx1, fy1)),
        ((fx1, fy1), (fx0, fy1)),
        ((fx0, fy1), (fx0, fy0)),
    ] {
        cv.hairline(a, b, DARK)?;
    }
    cv.text(
        &p.x.label,
        (plot.x0 + plot.x1) as f64 / 2.0,
        (plot.y1 + 10) as f64 + tick_h + 12.0,
        LABEL,
        DARK,
        Align::Centre,
        0.0,
        false,
    )?;
    cv.text(
        &p.y.label,
        cell.x0 as f64 + 16.0,
        (plot.y0 + plot.y1) as f64 / 2.0,
        LABEL,
        DARK,
        Align::Centre,
        0.0,
        true,
    )?;
    let to_px = |x: f64, y: f64| -> Option<(f64, f64)> {
        if (p.x.log && x <= 0.0) || (p.y.log && y <= 0.0) {
            return None;
        }
        Some((xm.px(x), ym.px(y)))
    };
    for t in &p.traces {
        if t.style.width > 0 {
            for piece in pixel_path(&t.points, to_px) {
                cv.polyline(&piece, t.style.colour, t.style.width, plot)?;
            }
        }
        if t.style.dot > 0.0 {
            for &(x, y) in &t.points {
                if let Some(q) = to_px(x, y) {
                    cv.dot(q, t.style.dot, t.style.colour, plot)?;
                }
            }
        }
    }
    Ok(PanelLayout {
        plot: [plot.x0, plot.y0, plot.x1, plot.y1],
        x: xm,
        y: ym,
        x_ticks: xt.into_iter().map(|(_, l)| l).collect(),
        y_ticks: yt.into_iter().map(|(_, l)| l).collect(),
        tick_digit_px: digit_height(TICK),
        colours: p.traces.iter().map(|t| t.style.colour).collect(),
        legend,
    })
}
