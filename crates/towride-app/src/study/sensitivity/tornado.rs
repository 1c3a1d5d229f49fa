//! One tornado chart per output (`tornado_<output>.png`, through
//! [`crate::report::figure`], the colour-blind palette): the parameters with the largest
//! figures as horizontal bars, those raising the output in one colour and those lowering
//! it in another. Small enough for two side by side on the page.

use crate::report::display::display_unit;
use std::path::{Path, PathBuf};

use super::numbers::{sig, with_unit};
use super::{Method, OutputInfo, ParamResult, Study};
use crate::error::{Error, Result};
use crate::report::figure::{render, Axis, Figure, HeaderLine, Panel, Style, Trace, PALETTE};

/// Bars in a chart (the table gives every parameter).
pub const TORNADO_ROWS: usize = 12;

/// Width of a chart [px]: shown two to a row on a 1300 px page, its text stays near the
/// page's own size.
const WIDTH: u32 = 1000;

/// Prefix of the charts' file names (a study's folder holds no other such file).
const PREFIX: &str = "tornado";

/// The chart file of output `name` in `dir`: `tornado_hitch_fx.abs_peak.png`.
pub fn file(dir: &Path, name: &str) -> PathBuf {
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._-".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    dir.join(format!("{PREFIX}_{safe}.png"))
}

/// Removes the charts in `dir` that are not in `keep`: those of an earlier study's
/// outputs (and its single `tornado.png`) must not stand beside this one's page.
pub fn remove_stale(dir: &Path, keep: &[PathBuf]) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with(PREFIX) && name.ends_with(".png") && !keep.contains(&p) {
            std::fs::remove_file(&p).map_err(|x| Error::io(&p, x))?;
        }
    }
    Ok(())
}

/// The value a parameter is ranked by for output `o`, signed where the method gives a
/// sign (the OAT elasticity; Morris: mu with the sign of mu, mu* as the length).
pub fn bar(s: &Study, p: &ParamResult, o: usize) -> Option<f64> {
    match s.method {
        Method::Oat => p.elasticity.get(o).copied().flatten(),
        Method::Morris => {
            let e = p.morris.get(o)?;
            let r = *p.mu_star_rel.get(o)?;
            r.is_finite().then(|| if e.mu < 0.0 { -r } else { r })
        }
    }
}

/// What the bars measure, for the x axis.
pub fn measure(m: Method) -> &'static str {
    match m {
        Method::Oat => "elasticity d ln y / d ln p at ±10 % [-]",
        Method::Morris => "Morris mu* / |base output| (sign of mu) [-]",
    }
}

/// The chart of output `o` into `path`. False (nothing drawn) when no parameter has a
/// figure for it.
pub fn tornado(s: &Study, o: usize, path: &Path) -> Result<bool> {
    let Some(out) = s.outputs.get(o) else {
        return Ok(false);
    };
    let rank: Vec<_> = s
        .ranking(o)
        .into_iter()
        .filter(|p| bar(s, p, o).is_some())
        .take(TORNADO_ROWS)
        .collect();
    let n = rank.len();
    if n == 0 {
        return Ok(false);
    }
    // A bar too short to see is left out: drawn, it was a sliver that read as a tick
    // mark (the table gives the value).
    let longest = rank
        .iter()
        .filter_map(|p| bar(s, p, o))
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let (mut up, mut down) = (Vec::new(), Vec::new());
    let mut labels = Vec::new();
    for (i, p) in rank.iter().enumerate() {
        let y = (n - i) as f64;
        let v = bar(s, p, o).unwrap_or(0.0);
        if v.abs() > 0.01 * longest {
            let seg = if v >= 0.0 { &mut up } else { &mut down };
            seg.extend([(0.0, y), (v, y), (f64::NAN, f64::NAN)]);
        }
        labels.push(y);
    }
    let names: Vec<&str> = rank.iter().map(|p| p.param.name.as_str()).collect();
    let labels = labels.into_iter().zip(compact(&names)).collect();
    // The title goes above as header lines, left-aligned: a centred panel title of
    // the name and the signed base ran past both edges of the chart.
    let mut panel = Panel::new("", measure(s.method), "");
    panel.y = Axis {
        label: String::new(),
        log: false,
        range: Some((0.4, n as f64 + 0.6)),
        labels,
    };
    let bars = |width: u32| -> Vec<Trace> {
        [
            (&up, "raises the output", PALETTE[1]),
            (&down, "lowers the output", PALETTE[0]),
        ]
        .into_iter()
        .filter(|(pts, _, _)| !pts.is_empty())
        .map(|(pts, label, colour)| {
            let style = Style {
                colour,
                width,
                dot: 0.0,
            };
            Trace::new(label, pts.clone(), style)
        })
        .collect()
    };
    panel.traces = bars(1);
    let mut fig = Figure::new(vec![panel], 1);
    fig.width = WIDTH;
    fig.panel_height = 150 + 34 * n as u32;
    fig.header.extend(
        [
            (title(out), 24.0, [40, 40, 40]),
            (base_run(out), 19.0, [40, 40, 40]),
            (
                format!("{}, {} runs: {}", s.method.short(), s.runs, s.file),
                16.0,
                [100, 100, 100],
            ),
        ]
        .map(|(text, size, colour)| HeaderLine { text, size, colour }),
    );
    if let Some(note) = &s.note {
        fig.header.push(HeaderLine {
            text: note.clone(),
            size: 17.0,
            colour: [180, 30, 30],
        });
    }
    // A bar is a line as thick as 0.6 of the rows' pitch, which the first drawing
    // measures: a fixed thickness overlapped the neighbouring rows of a short chart.
    let layout = render(path, &fig)?;
    if let Some(l) = layout.first() {
        let pitch = (l.y.px(1.0) - l.y.px(2.0)).abs();
        fig.panels[0].traces = bars((0.6 * pitch).round().max(2.0) as u32);
        render(path, &fig)?;
    }
    Ok(true)
}

/// The chart's title: the output and its unit.
pub fn title(out: &OutputInfo) -> String {
    format!("{} [{}]", out.name, display_unit(&out.unit))
}

/// The base run's value of an output; an `.abs_peak`'s also signed, which its
/// magnitude hides.
pub fn base_run(out: &OutputInfo) -> String {
    let v = |x: f64| with_unit(&sig(x, 4), &display_unit(&out.unit));
    match out.base_signed {
        Some(x) => format!("base run {}, signed {}", v(out.base), v(x)),
        None => format!("base run {}", v(out.base)),
    }
}

/// The charts' labels of parameters: the file's name without folder and extension and,
/// for a `.tir` value, the key without its section (`car_185_60r14:VERTICAL_STIFFNESS`),
/// since long labels left the bars a third of a chart; [`short`] ones when two would
/// read alike.
pub fn compact(names: &[&str]) -> Vec<String> {
    let one = |name: &str| -> String {
        let Some((file, path)) = name.split_once(':') else {
            return name.into();
        };
        let base = file.rsplit('/').next().unwrap_or(file);
        let (stem, ext) = base.rsplit_once('.').unwrap_or((base, ""));
        let key = if ext.eq_ignore_ascii_case("tir") {
            path.rsplit('.').next().unwrap_or(path)
        } else {
            path
        };
        format!("{stem}:{key}")
    };
    let mut v: Vec<String> = names.iter().map(|n| one(n)).collect();
    let mut sorted = v.clone();
    sorted.sort();
    sorted.dedup();
    if sorted.len() < v.len() {
        v = names.iter().map(|n| short(n)).collect();
    }
    v
}

/// `fabia/hitch.toml:bracket_bushing.stiffness_n_m` as `hitch.toml:bracket_bushing.stiffness_n_m`.
pub fn short(name: &str) -> String {
    match name.split_once(':') {
        Some((f, p)) => format!("{}:{p}", f.rsplit('/').next().unwrap_or(f)),
        None => name.into(),
    }
}
