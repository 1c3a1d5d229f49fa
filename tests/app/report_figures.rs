//! The figure renderer read back: known signals drawn through `report::figure`, the PNG
//! decoded, and the pixels checked against where the values map. A spike's top must lie
//! on the trace within 1 px of its value, the trace must be one connected line from its
//! first to its last column, no trace pixel may fall outside the plot area, and the tick
//! labels must be distinct and legible (digits at least 12 px high in a 1600 px figure).

use std::collections::VecDeque;
use std::path::Path;

use towride_app::report::figure::{render, Figure, Panel, PanelLayout};

struct Drawn {
    img: image::RgbImage,
    layout: PanelLayout,
}

/// Renders one panel with one trace into `dir/name.png` and reads it back.
fn draw(dir: &Path, name: &str, points: Vec<(f64, f64)>) -> Drawn {
    let path = dir.join(format!("{name}.png"));
    let panel = Panel::new(name, "time [s]", "value [-]").lines([("signal".into(), points)]);
    let mut fig = Figure::new(vec![panel], 1);
    fig.width = 1600;
    fig.panel_height = 1000;
    let mut layout = render(&path, &fig).expect("figure drawn");
    assert_eq!(layout.len(), 1);
    let img = image::open(&path).expect("a PNG").to_rgb8();
    Drawn {
        img,
        layout: layout.remove(0),
    }
}

impl Drawn {
    fn is_trace(&self, x: i32, y: i32) -> bool {
        let c = self.layout.colours[0];
        x >= 0
            && y >= 0
            && (x as u32) < self.img.width()
            && (y as u32) < self.img.height()
            && self.img.get_pixel(x as u32, y as u32).0 == c
    }

    fn inside(&self, x: i32, y: i32) -> bool {
        let [x0, y0, x1, y1] = self.layout.plot;
        (x0..x1).contains(&x) && (y0..y1).contains(&y)
    }

    /// Trace pixels in the plot area.
    fn trace_pixels(&self) -> Vec<(i32, i32)> {
        let [x0, y0, x1, y1] = self.layout.plot;
        let mut v = Vec::new();
        for y in y0..y1 {
            for x in x0..x1 {
                if self.is_trace(x, y) {
                    v.push((x, y));
                }
            }
        }
        v
    }

    /// Trace-coloured pixels outside the plot area and outside the legend.
    fn outside(&self) -> Vec<(i32, i32)> {
        let mut v = Vec::new();
        for y in 0..self.img.height() as i32 {
            for x in 0..self.img.width() as i32 {
                let in_legend = self
                    .layout
                    .legend
                    .is_some_and(|[a, b, c, d]| (a..c).contains(&x) && (b..d).contains(&y));
                if self.is_trace(x, y) && !self.inside(x, y) && !in_legend {
                    v.push((x, y));
                }
            }
        }
        v
    }

    /// The trace pixels 8-connected to `start` through trace pixels of the plot area.
    fn connected(&self, start: (i32, i32)) -> Vec<(i32, i32)> {
        let [x0, y0, x1, y1] = self.layout.plot;
        let (w, h) = ((x1 - x0) as usize, (y1 - y0) as usize);
        let mut seen = vec![false; w * h];
        let idx = |(x, y): (i32, i32)| (y - y0) as usize * w + (x - x0) as usize;
        let mut queue = VecDeque::from([start]);
        seen[idx(start)] = true;
        let mut out = Vec::new();
        while let Some(p) = queue.pop_front() {
            out.push(p);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let q = (p.0 + dx, p.1 + dy);
                    if self.inside(q.0, q.1) && self.is_trace(q.0, q.1) && !seen[idx(q)] {
                        seen[idx(q)] = true;
                        queue.push_back(q);
                    }
                }
            }
        }
        out
    }

    /// Pixels outside the plot area, tick labels distinct, without `.0` and legible.
    fn common_checks(&self, what: &str, bad: &mut Vec<String>) {
        let out = self.outside();
        if !out.is_empty() {
            bad.push(format!(
                "{what}: {} trace pixels outside the plot area {:?}, first {:?}",
                out.len(),
                self.layout.plot,
                &out[..out.len().min(5)]
            ));
        }
        for (axis, ticks) in [("x", &self.layout.x_ticks), ("y", &self.layout.y_ticks)] {
            if ticks.len() < 3 {
                bad.push(format!("{what}: {axis} ticks {ticks:?}"));
            }
            for (k, t) in ticks.iter().enumerate() {
                if ticks[..k].contains(t) {
                    bad.push(format!(
                        "{what}: {axis} tick label '{t}' repeats: {ticks:?}"
                    ));
                    break;
                }
            }
            if let Some(t) = ticks.iter().find(|t| t.ends_with(".0")) {
                bad.push(format!(
                    "{what}: {axis} tick label '{t}' ends in .0: {ticks:?}"
                ));
            }
        }
        if self.layout.tick_digit_px < 12.0 {
            bad.push(format!(
                "{what}: tick digits {:.1} px high",
                self.layout.tick_digit_px
            ));
        }
    }

    /// The trace is one line: every column from the first value's to the last's holds
    /// trace pixels connected to `from`.
    fn one_line(
        &self,
        what: &str,
        from: (i32, i32),
        x_first: f64,
        x_last: f64,
        bad: &mut Vec<String>,
    ) {
        let comp = self.connected(from);
        let c0 = self.layout.x.px(x_first).round() as i32;
        let c1 = self.layout.x.px(x_last).round() as i32;
        let mut missing = Vec::new();
        for c in c0 + 1..c1 {
            if !comp.iter().any(|p| p.0 == c) {
                missing.push(c);
            }
        }
        if !missing.is_empty() {
            bad.push(format!(
                "{what}: {} of the columns {c0}..{c1} hold no pixel of the line through {from:?} (first {:?})",
                missing.len(),
                &missing[..missing.len().min(8)]
            ));
        }
    }
}

/// Checks the pixel row of a value.
fn at_row(what: &str, row: i32, want: f64, v: f64, bad: &mut Vec<String>) {
    if (row as f64 - want).abs() > 1.0 {
        bad.push(format!(
            "{what}: drawn at row {row}, but {v:e} maps to row {want:.1}"
        ));
    }
}

fn report(bad: Vec<String>) {
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

fn out_dir() -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("towride_figures_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn a_spike_is_drawn_on_the_trace_at_its_value() {
    let dir = out_dir();
    // 20001 samples over 2 s: a 3 Hz sine of amplitude 1 and one sample at 6.
    let n = 20001;
    let spike = 6000;
    let pts: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let t = 2.0 * k as f64 / (n - 1) as f64;
            let y = if k == spike {
                6.0
            } else {
                (2.0 * std::f64::consts::PI * 3.0 * t).sin()
            };
            (t, y)
        })
        .collect();
    let t_spike = pts[spike].0;
    let d = draw(&dir, "spike", pts);
    let mut bad = Vec::new();
    d.common_checks("spike", &mut bad);
    let px = d.trace_pixels();
    // The spike's top: the highest trace pixel near the spike's column.
    let xs = d.layout.x.px(t_spike).round() as i32;
    let top = px
        .iter()
        .filter(|p| (p.0 - xs).abs() <= 2)
        .min_by_key(|p| p.1)
        .copied()
        .expect("trace pixels at the spike");
    at_row("spike top", top.1, d.layout.y.px(6.0), 6.0, &mut bad);
    // The lowest trace pixel is the sine's minimum.
    let bottom = px.iter().map(|p| p.1).max().unwrap();
    at_row("trace bottom", bottom, d.layout.y.px(-1.0), -1.0, &mut bad);
    d.one_line("spike", top, 0.0, 2.0, &mut bad);
    report(bad);
}

#[test]
fn a_constant_is_one_straight_line() {
    let dir = out_dir();
    let pts: Vec<(f64, f64)> = (0..2001).map(|k| (k as f64 * 1e-3, 3.0)).collect();
    let d = draw(&dir, "constant", pts);
    let mut bad = Vec::new();
    d.common_checks("constant", &mut bad);
    let want = d.layout.y.px(3.0);
    let px = d.trace_pixels();
    assert!(!px.is_empty());
    if let Some(p) = px.iter().find(|p| (p.1 as f64 - want).abs() > 1.0) {
        bad.push(format!(
            "constant: trace pixel {p:?}, but 3.0 maps to row {want:.1}"
        ));
    }
    d.one_line("constant", px[0], 0.0, 2.0, &mut bad);
    report(bad);
}

#[test]
fn a_signal_spanning_1e_minus_7_gets_distinct_ticks() {
    let dir = out_dir();
    // 0 .. 1e-7 (the hitch's lateral deflection is of this size).
    let pts: Vec<(f64, f64)> = (0..3001)
        .map(|k| {
            let t = k as f64 * 1e-3;
            (
                t,
                0.5e-7 * (1.0 + (2.0 * std::f64::consts::PI * 2.0 * t).sin()),
            )
        })
        .collect();
    let d = draw(&dir, "tiny", pts);
    let mut bad = Vec::new();
    d.common_checks("tiny", &mut bad);
    let px = d.trace_pixels();
    let top = px.iter().map(|p| p.1).min().unwrap();
    let bottom = px.iter().map(|p| p.1).max().unwrap();
    at_row("tiny maximum", top, d.layout.y.px(1e-7), 1e-7, &mut bad);
    at_row("tiny minimum", bottom, d.layout.y.px(0.0), 0.0, &mut bad);
    let start = *px.iter().min_by_key(|p| p.0).unwrap();
    d.one_line("tiny", start, 0.0, 3.0, &mut bad);
    report(bad);
}

#[test]
fn log_axis_labels_use_one_notation() {
    use towride_app::report::ticks::log_labels;
    // A range crossing 1e-3 takes powers of ten on every tick, not "0.002" beside
    // "5×10⁻⁴" (and no SI prefix: "2m" on an axis of seconds reads as minutes).
    assert_eq!(
        log_labels(&[2e-4, 5e-4, 1e-3, 2e-3], 2),
        ["2×10⁻⁴", "5×10⁻⁴", "10⁻³", "2×10⁻³"]
    );
    // Inside 1e-3..1e6 plain decimals stay.
    assert_eq!(
        log_labels(&[0.01, 0.1, 1.0, 10.0], 2),
        ["0.01", "0.1", "1", "10"]
    );
    assert_eq!(log_labels(&[1e3, 1e4, 1e5], 2), ["1000", "10000", "100000"]);
    assert_eq!(log_labels(&[1e5, 1e6, 1e7], 2), ["10⁵", "10⁶", "10⁷"]);
}

#[test]
fn a_log_axis_inside_one_decade_keeps_labelled_ticks() {
    use towride_app::report::ticks::{log, log_labels};
    // The work-precision plot's wall times (0.24 to 0.46 s) hold no 1, 2 or 5 multiple.
    for (lo, hi) in [(0.24, 0.46), (0.31, 0.39), (3.1e-5, 3.4e-5), (0.24, 0.96)] {
        let t = log(lo, hi);
        assert!(t.len() >= 2, "{lo}..{hi}: {t:?}");
        assert!(t.iter().all(|x| (lo..=hi).contains(x)), "{lo}..{hi}: {t:?}");
        let l = log_labels(&t, 2);
        let distinct: std::collections::BTreeSet<&String> = l.iter().collect();
        assert_eq!(distinct.len(), l.len(), "{lo}..{hi}: {l:?}");
    }
}

#[test]
fn a_linear_axis_never_labels_a_single_tick_when_two_fit() {
    use towride_app::report::ticks::linear;
    // 1.2e5..9e5 with room for three ticks: the step of 5e5 would put one tick (5e5)
    // inside; the next finer round step, 2e5, puts four (2e5, 4e5, 6e5, 8e5).
    let (t, step) = linear(1.2e5, 9.0e5, 3);
    assert_eq!(step, 2.0e5);
    assert_eq!(t, [2.0e5, 4.0e5, 6.0e5, 8.0e5]);
    // Where the coarse step already gives two ticks it stays: 0..10, five ticks, step 2.
    let (t, step) = linear(0.0, 10.0, 5);
    assert_eq!((t.len(), step), (6, 2.0));
}
