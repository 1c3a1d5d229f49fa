//! Channels charted together: a family is the channels whose names differ only in a
//! wheel, a number or a final axis letter (`susp_fl_travel`, `susp_fr_travel`, ...), in
//! one unit. Its title says in words what the chart shows ("suspension travel, car
//! wheels"), never the pattern the family was found by. The run's outputs page and the
//! HTML report's extra charts both group by these.

use super::display::{figure_unit, natural_key};
use towride_mbs::model::run::Samples;

const WHEELS: [&str; 6] = ["fl", "fr", "rl", "rr", "tl", "tr"];
const AXES: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

/// Whether part `k` of `parts` varies within a family: a wheel, a number, or an axis
/// letter at the end.
fn wild(parts: &[&str], k: usize) -> bool {
    let p = parts[k];
    WHEELS.contains(&p)
        || (!p.is_empty() && p.chars().all(|c| c.is_ascii_digit()))
        || (k + 1 == parts.len() && k > 0 && AXES.contains(&p))
}

fn parts(name: &str) -> Vec<&str> {
    name.split(['_', '.']).collect()
}

/// A channel's family key: its name with wheels, numbers and a final axis letter as `*`
/// (`tyre_*_contact`, `hitch_eta_*`): an identifier, not a title.
pub fn family(name: &str) -> String {
    let p = parts(name);
    (0..p.len())
        .map(|k| if wild(&p, k) { "*" } else { p[k] })
        .collect::<Vec<_>>()
        .join("_")
}

/// Abbreviations in channel names, in words.
fn word(p: &str) -> &str {
    match p {
        "susp" => "suspension",
        "acc" => "acceleration",
        "eta" => "modal coordinate",
        "fx" => "Fx",
        "fy" => "Fy",
        "fz" => "Fz",
        "cm" => "centre of mass",
        p => p,
    }
}

/// What the varying values of one part of the names cover, in words.
fn describe(values: &[&str]) -> String {
    let has = |set: &[&str]| set.iter().all(|w| values.contains(w));
    let only = |set: &[&str]| values.iter().all(|v| set.contains(v));
    if only(&WHEELS) {
        let (car, trailer) = (["fl", "fr", "rl", "rr"], ["tl", "tr"]);
        return match (has(&car), has(&trailer), values.len()) {
            (true, true, 6) => "all wheels".into(),
            (true, false, 4) => "car wheels".into(),
            (false, true, 2) => "trailer wheels".into(),
            (_, _, 1) => format!("wheel {}", values[0]),
            _ => format!("wheels {}", values.join(", ")),
        };
    }
    if values.iter().all(|v| v.chars().all(|c| c.is_ascii_digit())) {
        let n: Vec<u64> = values.iter().filter_map(|v| v.parse().ok()).collect();
        let run = n.windows(2).all(|w| w[1] == w[0] + 1);
        return match n.as_slice() {
            [one] => one.to_string(),
            [a, .., b] if run && n.len() > 2 => format!("{a} to {b}"),
            _ => values.join(", "),
        };
    }
    if values.len() == 1 {
        return format!("axis {}", values[0]);
    }
    format!("axes {}", values.join(", "))
}

/// The readable title of the channels `names` (one family): the fixed words of the
/// names, then what the varying parts cover ("suspension travel, car wheels",
/// "hitch modal coordinate, 1 to 10"); a single channel's name in words.
pub fn title(names: &[&str]) -> String {
    let Some(first) = names.first() else {
        return String::new();
    };
    let p0 = parts(first);
    let varies = |k: usize| names.iter().any(|n| parts(n).get(k) != p0.get(k));
    let words: Vec<&str> = (0..p0.len())
        .filter(|&k| !(names.len() > 1 && wild(&p0, k) && varies(k)))
        .map(|k| word(p0[k]))
        .filter(|w| !w.is_empty())
        .collect();
    let mut t = words.join(" ");
    for k in (0..p0.len()).filter(|&k| names.len() > 1 && wild(&p0, k) && varies(k)) {
        let mut values: Vec<&str> = Vec::new();
        for n in names {
            let v = parts(n)[k];
            if !values.contains(&v) {
                values.push(v);
            }
        }
        values.sort_by_cached_key(|v| natural_key(v));
        t.push_str(", ");
        t.push_str(&describe(&values));
    }
    t
}

/// The quantity an axis in `unit` shows, for its label ("acceleration [m/s²]").
fn quantity(unit: &str) -> &'static str {
    match unit {
        "m" => "displacement",
        "m/s" => "velocity",
        "m/s^2" => "acceleration",
        "N" => "force",
        "N m" | "N*m" | "Nm" => "moment",
        "rad" => "angle",
        "rad/s" => "angular velocity",
        "rad/s^2" => "angular acceleration",
        "J" => "energy",
        "W" => "power",
        _ => "",
    }
}

/// One family of channels of a run.
#[derive(Clone, Debug)]
pub struct Family {
    /// Readable title ([`title`]).
    pub title: String,
    /// The channels' unit as written in the CSV (ASCII, SI).
    pub unit: String,
    /// Factor from SI to the figure's unit ([`figure_unit`]: angles in degrees).
    pub factor: f64,
    /// The axis label with the figure's unit, "angle [deg]".
    pub axis: String,
    /// The channels (indices into `Samples::channels`), in natural order.
    pub members: Vec<usize>,
}

/// The families of the channels `pick` selects, in the order of their first channel;
/// members in natural order.
pub fn families(res: &Samples, pick: impl Fn(usize) -> bool) -> Vec<Family> {
    let mut out: Vec<(String, Family)> = Vec::new();
    for (c, ch) in res.channels.iter().enumerate().filter(|(c, _)| pick(*c)) {
        let key = family(&ch.name);
        match out.iter_mut().find(|(k, f)| *k == key && f.unit == ch.unit) {
            Some((_, f)) => f.members.push(c),
            None => {
                let (factor, shown) = figure_unit(ch.unit);
                let q = quantity(ch.unit);
                let axis = if q.is_empty() {
                    format!("[{shown}]")
                } else {
                    format!("{q} [{shown}]")
                };
                out.push((
                    key,
                    Family {
                        title: String::new(),
                        unit: ch.unit.to_string(),
                        factor,
                        axis,
                        members: vec![c],
                    },
                ));
            }
        }
    }
    out.into_iter()
        .map(|(_, mut f)| {
            f.members
                .sort_by_cached_key(|&c| natural_key(&res.channels[c].name));
            let names: Vec<&str> = f
                .members
                .iter()
                .map(|&c| res.channels[c].name.as_str())
                .collect();
            f.title = title(&names);
            f
        })
        .collect()
}
