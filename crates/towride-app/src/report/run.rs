//! The page of plots a vehicle run writes beside its CSV.

use std::path::Path;

use super::display::display_unit;
use super::figure::{render, Figure, Panel, Style, Trace};
use super::ReportError;
use crate::scene::channels;
use towride_mbs::model::run::Samples;

/// Channel `c` of `res` as a trace, values times `factor`: a left/right channel in its
/// pair's colour, any other in the `n`-th free colour (`n` counts them).
pub(super) fn trace(res: &Samples, c: usize, factor: f64, n: &mut usize) -> Trace {
    let name = &res.channels[c].name;
    let style = match side_of(name) {
        Some((k, right)) => Style::side(k, right),
        None => {
            *n += 1;
            Style::nth(*n - 1)
        }
    };
    let points = res
        .times
        .iter()
        .zip(&res.rows)
        .map(|(t, r)| (*t, r[c] * factor))
        .collect();
    Trace::new(name.clone(), points, style)
}

/// Left/right pairs by the last part of a channel name: the colour index of the pair
/// and whether this is the right side (fl/fr, rl/rr, tl/tr; *_left_*/*_right_*).
pub(crate) fn side_of(name: &str) -> Option<(usize, bool)> {
    for (k, (l, r)) in [("_fl", "_fr"), ("_rl", "_rr"), ("_tl", "_tr")]
        .iter()
        .enumerate()
    {
        if name.contains(&format!("{l}_")) || name.ends_with(l) {
            return Some((k, false));
        }
        if name.contains(&format!("{r}_")) || name.ends_with(r) {
            return Some((k, true));
        }
    }
    for (k, pos) in ["front", "rear"].iter().enumerate() {
        if name.contains(&format!("{pos}_left")) {
            return Some((k, false));
        }
        if name.contains(&format!("{pos}_right")) {
            return Some((k, true));
        }
    }
    None
}

/// The band-limited twin of channel `name` in `res` (`<name>_lp<cutoff>`,
/// [`crate::job::band`]) and its suffix.
pub fn band_twin<'a>(res: &'a Samples, name: &str) -> Option<(usize, &'a str)> {
    res.channels.iter().enumerate().find_map(|(k, c)| {
        let suffix = c.name.strip_prefix(name)?;
        (suffix.starts_with("_lp") && channels::is_band_limited(&c.name)).then_some((k, suffix))
    })
}

/// The panels of the run page: each panel's traces, left/right pairs in one colour told
/// apart by line style. The accelerometers are drawn as the instrument saw them, their
/// band-limited twins where the run has them (the panel's title names the band); the
/// forces raw.
pub fn run_panels(res: &Samples) -> Vec<Panel> {
    // The sensors' columns: a raw channel's band-limited twin in its place.
    let shown = |c: usize| -> usize {
        let name = &res.channels[c].name;
        match channels::band(name) {
            Some(channels::Band::Sensor) => band_twin(res, name).map_or(c, |t| t.0),
            _ => c,
        }
    };
    let series = |pred: &dyn Fn(&str) -> bool| -> Vec<Trace> {
        let mut n = 0;
        res.channels
            .iter()
            .enumerate()
            .filter(|(_, ch)| !channels::is_band_limited(&ch.name) && pred(&ch.name))
            .map(|(c, _)| shown(c))
            .map(|c| (c, &res.channels[c]))
            .map(|(c, _)| trace(res, c, 1.0, &mut n))
            .collect()
    };
    // A panel of band-limited traces says so in its title (the axis label has no room).
    let panel = |title: &str, y: &str, traces: Vec<Trace>| {
        let band = traces.iter().find_map(|t| {
            let (_, cutoff) = t.label.rsplit_once("_lp")?;
            channels::is_band_limited(&t.label).then(|| cutoff.to_string())
        });
        let title = match band {
            Some(fc) => format!("{title} ({fc} Hz low-pass)"),
            None => title.to_string(),
        };
        Panel {
            traces,
            ..Panel::new(&title, "time [s]", y)
        }
    };
    let acc = format!("acceleration [{}]", display_unit("m/s^2"));
    let acc = acc.as_str();
    // The vehicles' sensors at the wheels and on the body: `acc_wheel_*`, `acc_body_*`.
    let wheel_sensors = format!("{}wheel_", channels::ACC_PREFIX);
    let body_sensors = format!("{}body_", channels::ACC_PREFIX);
    // The floor point under the driver's seat is on the body too (docs/comfort.md).
    let floor = format!("{}{}_", channels::ACC_PREFIX, crate::comfort::FLOOR_SENSOR);
    let on_body = |n: &str| n.starts_with(&body_sensors) || n.starts_with(&floor);
    let panels = vec![
        panel(
            "hitch force on the car",
            "force [N]",
            series(&|n| n == channels::HITCH_FX || n == channels::HITCH_FZ),
        ),
        panel("trailer box", acc, series(&|n| n == channels::TRAILER_AX)),
        panel(
            "tyre normal forces",
            "force [N]",
            series(&|n| channels::is_tyre(n, channels::TYRE_FZ)),
        ),
        panel(
            "crossbeam strain energy",
            "energy [J]",
            series(&|n| n == channels::HITCH_STRAIN_ENERGY),
        ),
        panel(
            "vertical accelerations at the wheels",
            acc,
            series(&|n| n.starts_with(&wheel_sensors) && n.ends_with("_z")),
        ),
        panel(
            "vertical accelerations on the car body",
            acc,
            series(&|n| on_body(n) && n.ends_with("_z")),
        ),
        panel(
            "vertical accelerations at the hitch and drawbar",
            acc,
            series(&|n| {
                n.starts_with(channels::ACC_PREFIX)
                    && n.ends_with("_z")
                    && !n.starts_with(&wheel_sensors)
                    && !on_body(n)
            }),
        ),
        panel("speed", "speed [m/s]", series(&|n| n == channels::SPEED)),
    ];
    panels
        .into_iter()
        .filter(|p| !p.traces.is_empty())
        .collect()
}

/// One page (PNG or SVG by extension): hitch force, trailer acceleration, tyre normal
/// forces, crossbeam strain energy, the vertical accelerations at the wheels, on the
/// body and at the hitch and drawbar, and the speed.
pub fn run_page(res: &Samples, path: &Path) -> Result<(), ReportError> {
    let mut fig = Figure::new(run_panels(res), 2);
    fig.panel_height = 560;
    render(path, &fig).map(|_| ())
}
