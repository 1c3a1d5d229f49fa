//! `validate init`: sniffs a recording (separator, header, units row, time base, sample
//! rate, channels with units) and drafts a commented descriptor for a scene. Channels are
//! mapped onto the scene's sensors by name patterns (FL/FR/RL/RR, front/rear
//! left/right, sprung/body, unsprung/wheel/hub, drawbar, hitch; x/y/z or
//! longitudinal/lateral/vertical, vertical by default); unmapped columns are listed as
//! comments; gravity is set to be removed where a vertical channel's median over the
//! record (its level in steady driving, which is most of a bump run; a mean would follow
//! the events and a short rest part) is within 0.1 g of 1 g; each channel's fixed offset
//! over the quiet part before the passage is measured and removed, and a range proposed
//! from the file's clipping level or a stated default ([`super::offsets`]).

use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use serde::Serialize;

use towride_mbs::input::InputError;

use super::csv_reader::{
    cells, err, first_content, lines_of, no_content, parse_number, read_table_with, split_unit,
    TimeSpec,
};
use super::offsets::{clip_level, default_range, median_in, quiet_window, DEFAULT_RANGE_G};
use super::timebase::TimeBase;
use super::units::{time_factor, SpeedUnit, Unit};
use super::G_MPS2;
use crate::scene::channels;

/// A vertical channel whose mean at rest lies this close to 1 g reads gravity [g].
const GRAVITY_TOL_G: f64 = 0.1;

/// What a column is, from its unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// An acceleration (`g`, `gn`, `m/s^2`).
    Acceleration,
    /// A speed (`km/h`, `m/s`, `mph`).
    Speed,
    /// Anything else (pressures, angles, rates, no unit).
    Other,
}

/// One column of a sniffed file.
#[derive(Clone, Debug, Serialize)]
pub struct Column {
    /// Name in the header (without a `[unit]`).
    pub name: String,
    /// Unit from the header or units row.
    pub unit: Option<String>,
    /// What it is.
    pub kind: Kind,
    /// Median over the record, in the column's unit.
    pub median: f64,
    /// The file's clipping level [g] (a clipped sensor, [`clip_level`]), if seen.
    pub flat_top_g: Option<f64>,
    /// Largest |reading| [g] of an acceleration.
    pub peak_g: Option<f64>,
    /// Median over the quiet window before the passage, in the column's unit.
    pub quiet_median: Option<f64>,
    /// The scene's channel it is mapped onto, if any.
    pub simulated: Option<String>,
    /// Mapped as the vehicle-speed channel (the draft's `[speed] column`).
    pub speed_channel: bool,
    /// Why it is not mapped, when it is not.
    pub unmapped: Option<String>,
}

/// What `validate init` found in a recording.
#[derive(Clone, Debug, Serialize)]
pub struct Sniff {
    /// The file.
    pub file: PathBuf,
    /// Column separator.
    pub separator: char,
    /// Numbers with a decimal comma.
    pub decimal_comma: bool,
    /// 1-based header line.
    pub header_line: usize,
    /// 1-based units row, if any.
    pub units_line: Option<usize>,
    /// The time column, if any.
    pub time_column: Option<String>,
    /// Data rows.
    pub rows: usize,
    /// The time base and sample rate.
    pub time_base: TimeBase,
    /// The columns other than time.
    pub columns: Vec<Column>,
    /// The quiet part before the passage [s] (recording's clock), if found.
    pub quiet_window_s: Option<[f64; 2]>,
    /// Repairs and inferences made while reading.
    pub notes: Vec<String>,
}

/// A line's cells when every one is a number or empty (`None` otherwise).
fn numeric_cells(line: &str, sep: char) -> Option<usize> {
    let cs = cells(line, sep);
    let ok = cs
        .iter()
        .all(|(c, _)| c.is_empty() || parse_number(c, sep != ',').is_some());
    (ok && cs.iter().any(|(c, _)| !c.is_empty())).then_some(cs.len())
}

/// (separator, header line index, units line index) of the layout with most columns.
fn layout(lines: &[String]) -> Option<(char, usize, Option<usize>)> {
    let mut best: Option<(usize, char, usize, Option<usize>)> = None;
    let content = |l: &String| !l.trim().is_empty() && !l.trim_start().starts_with('#');
    for sep in ['\t', ';', ','] {
        // The first numeric row followed by four more of as many cells.
        let data = (0..lines.len()).find(|&i| {
            let Some(n) = numeric_cells(&lines[i], sep).filter(|&n| n >= 2) else {
                return false;
            };
            lines[i + 1..]
                .iter()
                .filter(|l| content(l))
                .take(4)
                .all(|l| numeric_cells(l, sep) == Some(n))
        });
        let Some(d) = data else { continue };
        let n = cells(&lines[d], sep).len();
        let above: Vec<usize> = (0..d)
            .rev()
            .filter(|&i| content(&lines[i]))
            .take(2)
            .filter(|&i| cells(&lines[i], sep).len() == n)
            .collect();
        let (h, u) = match above.as_slice() {
            [u, h] if *h + 1 == *u || lines[h + 1..*u].iter().all(|l| !content(l)) => {
                (*h, Some(*u))
            }
            [h, ..] => (*h, None),
            [] => continue,
        };
        if best.is_none_or(|b| n > b.0) {
            best = Some((n, sep, h, u));
        }
    }
    best.map(|(_, s, h, u)| (s, h, u))
}

/// A sample rate declared in a comment line before the header (`2000 Hz`, `5 kHz`), and
/// the line's 0-based index.
fn declared_rate(lines: &[String]) -> Option<(f64, usize)> {
    for (n, l) in lines.iter().enumerate() {
        let words: Vec<&str> = l
            .split(|c: char| c.is_whitespace() || c == ':' || c == '=')
            .filter(|w| !w.is_empty())
            .collect();
        for (i, w) in words.iter().enumerate() {
            let lw = w.to_ascii_lowercase();
            let (num, unit) = match lw.find(|c: char| c.is_ascii_alphabetic()) {
                Some(k) if k > 0 => (&lw[..k], &lw[k..]),
                _ => (
                    words.get(i.wrapping_sub(1)).copied().unwrap_or(""),
                    lw.as_str(),
                ),
            };
            let f = match unit {
                "hz" => 1.0,
                "khz" => 1e3,
                _ => continue,
            };
            if let Ok(v) = num.replace(',', ".").parse::<f64>() {
                if v > 0.0 && v.is_finite() {
                    return Some((v * f, n));
                }
            }
        }
    }
    None
}

/// `rate` [Hz] within the bounds `validate` applies to a descriptor's `sample_rate_hz`
/// (so a draft is never refused later), positive; `line`: where it was declared.
fn checked_rate(
    file: &Path,
    line: Option<usize>,
    rate: f64,
    what: &str,
) -> Result<f64, InputError> {
    let b = towride_mbs::input::bounds::for_key("sample_rate_hz");
    if rate > 0.0 && b.accepts(rate) {
        return Ok(rate);
    }
    let why = if rate.is_finite() && rate <= 0.0 {
        format!("must be positive, got {rate}; accepted: {}", b.range())
    } else {
        b.message(rate)
    };
    Err(err(file, line, None, what, format!("sample rate {why}")))
}

/// Sniffs `file`; `rate_hz`: the sample rate when the file has no time column (else read
/// from a comment such as `# sample rate: 2000 Hz`).
pub fn sniff(file: &Path, rate_hz: Option<f64>) -> Result<Sniff, InputError> {
    if super::mdf::is_mdf(file) {
        return sniff_mdf(file, rate_hz);
    }
    let lines = lines_of(file)?;
    let (sep, h, u) = layout(&lines).ok_or_else(|| match first_content(&lines) {
        Some(i) => err(
            file,
            Some(i + 1),
            None,
            "header",
            "no header followed by rows of numbers with as many fields (separators tab, \
             `;` or `,`); the first line of content is here"
                .into(),
        ),
        None => err(file, Some(1), None, "header", no_content(&lines)),
    })?;
    let mut names: Vec<(String, Option<String>)> = cells(&lines[h], sep)
        .into_iter()
        .map(|(c, _)| split_unit(&c))
        .collect();
    if let Some(u) = u {
        for ((_, unit), (c, _)) in names.iter_mut().zip(cells(&lines[u], sep)) {
            if unit.is_none() && !c.is_empty() {
                *unit = Some(c);
            }
        }
    }
    let time = names.iter().position(|(n, unit)| {
        let l = super::csv_reader::normalised(n);
        let unit_ok = unit.as_deref().is_none_or(|u| time_factor(u).is_some());
        unit_ok && (l == "t" || l.starts_with("time") || l.starts_with("zeit") || l == "timestamp")
    });
    let header_cells = cells(&lines[h], sep);
    // Two columns of one name: every later reader would take the first for both.
    let mut seen = std::collections::HashMap::new();
    for (k, (n, _)) in names.iter().enumerate() {
        if n.is_empty() {
            return Err(err(
                file,
                Some(h + 1),
                Some(header_cells[k].1),
                "",
                format!("column {} has no name", k + 1),
            ));
        }
        if let Some(first) = seen.insert(super::csv_reader::normalised(n), k) {
            return Err(err(
                file,
                Some(h + 1),
                Some(header_cells[k].1),
                n,
                format!(
                    "column {} repeats the name of column {}: give every column its own name",
                    k + 1,
                    first + 1
                ),
            ));
        }
    }
    let rate = match (time, rate_hz) {
        (Some(k), Some(_)) => {
            return Err(err(
                file,
                Some(h + 1),
                Some(header_cells[k].1),
                &names[k].0,
                format!(
                    "the file has a time column `{}`; --rate-hz applies only to files without one",
                    names[k].0
                ),
            ))
        }
        (Some(_), None) => None,
        (None, Some(r)) => Some(checked_rate(file, None, r, "--rate-hz")?),
        (None, None) => {
            let (r, n) = declared_rate(&lines[..h]).ok_or_else(|| {
                err(file, Some(h + 1), None, "", "no time column and no sample rate: give the rate (--rate-hz) or a comment `# sample rate: 2000 Hz`".into())
            })?;
            Some(checked_rate(file, Some(n + 1), r, "sample rate")?)
        }
    };
    let spec = TimeSpec {
        column: time.map(|k| names[k].0.clone()),
        rate_hz: rate,
        fall_back_to_rate: false,
    };
    let others: Vec<&str> = (0..names.len())
        .filter(|k| Some(*k) != time)
        .map(|k| names[k].0.as_str())
        .collect();
    finish(file, spec, &others)
}

/// An MDF4 recording: every non-master channel (each group has its own master clock).
fn sniff_mdf(file: &Path, rate_hz: Option<f64>) -> Result<Sniff, InputError> {
    if rate_hz.is_some() {
        return Err(err(
            file,
            None,
            None,
            "--rate-hz",
            "an MDF4 file times every channel group with its master channel; --rate-hz \
             applies only to text files without a time column"
                .into(),
        ));
    }
    let chans = super::mdf::read_channels(file)?;
    let master = chans
        .iter()
        .find(|c| !c.master.is_empty())
        .map(|c| c.master.clone());
    let mut others: Vec<&str> = Vec::new();
    for c in &chans {
        if !others.contains(&c.name.as_str()) {
            others.push(&c.name);
        }
    }
    let spec = TimeSpec {
        column: master,
        rate_hz: None,
        fall_back_to_rate: false,
    };
    finish(file, spec, &others)
}

/// Reads the columns and describes each.
fn finish(file: &Path, spec: TimeSpec, others: &[&str]) -> Result<Sniff, InputError> {
    let table = read_table_with(file, &spec, others)?;
    let rows = table.time_s.len();
    let in_g = |values: &Vec<f64>, unit: &Option<String>| {
        unit.as_deref().and_then(Unit::parse).map(|un| {
            values
                .iter()
                .map(|v| v * un.to_si() / G_MPS2)
                .collect::<Vec<f64>>()
        })
    };
    let acc: Vec<Vec<f64>> = table
        .columns
        .iter()
        .zip(&table.units)
        .filter_map(|(v, u)| in_g(v, u))
        .collect();
    let acc_refs: Vec<&[f64]> = acc.iter().map(|v| v.as_slice()).collect();
    let quiet = quiet_window(&table.time_s, &acc_refs);
    let columns = others
        .iter()
        .zip(&table.columns)
        .zip(&table.units)
        .map(|((name, values), unit)| {
            let kind = match unit.as_deref() {
                Some(u) if Unit::parse(u).is_some() => Kind::Acceleration,
                Some(u) if SpeedUnit::parse(u).is_some() => Kind::Speed,
                _ => Kind::Other,
            };
            let median = {
                let mut v = values.clone();
                v.sort_by(f64::total_cmp);
                v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
            };
            let g = in_g(values, unit);
            let flat_top_g = g.as_deref().and_then(clip_level);
            let peak_g = g
                .as_deref()
                .map(|g| g.iter().fold(0.0_f64, |m, v| m.max(v.abs())));
            Column {
                name: name.to_string(),
                unit: unit.clone(),
                kind,
                median,
                flat_top_g,
                peak_g,
                quiet_median: quiet.and_then(|w| median_in(&table.time_s, values, w)),
                simulated: None,
                speed_channel: false,
                unmapped: None,
            }
        })
        .collect();
    Ok(Sniff {
        file: file.to_path_buf(),
        separator: table.separator,
        decimal_comma: table.decimal_comma,
        header_line: table.header_line,
        units_line: table.units_line,
        time_column: spec.column,
        rows,
        time_base: table.time_base,
        columns,
        quiet_window_s: quiet,
        notes: table.notes,
    })
}

/// The words of a column name: lower case, split at spaces, `_`, `-`, `.`, `/` and
/// brackets, with FL/FR/RL/RR and German VL/VR/HL/HR spelled out.
fn words(name: &str) -> Vec<String> {
    let mut out = Vec::new();
    for w in name
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_lowercase)
    {
        match w.as_str() {
            "fl" | "vl" => out.extend(["front".into(), "left".into()]),
            "fr" | "vr" => out.extend(["front".into(), "right".into()]),
            "rl" | "hl" => out.extend(["rear".into(), "left".into()]),
            "rr" | "hr" => out.extend(["rear".into(), "right".into()]),
            "sprung" | "body" | "chassis" => out.push("body".into()),
            "unsprung" | "wheel" | "hub" | "knuckle" => out.push("wheel".into()),
            "vertical" | "vert" => out.push("z".into()),
            "longitudinal" | "long" => out.push("x".into()),
            "lateral" | "lat" => out.push("y".into()),
            _ => out.push(w),
        }
    }
    out
}

/// The scene channel `name` maps onto among `sensors` (name, measured axes).
fn map_channel(name: &str, sensors: &[(String, [bool; 3])]) -> Result<String, String> {
    let w = words(name);
    let has = |x: &str| w.iter().any(|v| v == x);
    let axis = ["x", "y", "z"].into_iter().position(&has).unwrap_or(2);
    let mut need: Vec<&str> = Vec::new();
    for k in [
        "body", "wheel", "drawbar", "hitch", "trailer", "front", "rear", "left", "right",
    ] {
        if has(k) {
            need.push(k);
        }
    }
    if !need
        .iter()
        .any(|k| ["body", "wheel", "drawbar", "hitch"].contains(k))
    {
        return Err("no sprung/body, unsprung/wheel/hub, drawbar or hitch in the name".into());
    }
    // The sensor holding every wanted word with the fewest others.
    let best = sensors
        .iter()
        .filter(|(s, axes)| {
            let sw: Vec<&str> = s.split('_').collect();
            axes[axis] && need.iter().all(|k| sw.contains(k))
        })
        .min_by_key(|(s, _)| s.split('_').count());
    match best {
        Some((s, _)) => Ok(channels::acc(s, ["x", "y", "z"][axis])),
        None => Err(format!(
            "no sensor of the scene measures {} with {need:?} in its name",
            ["x", "y", "z"][axis]
        )),
    }
}

/// The acceleration sensors of `scene` (built as a run would): name and measured axes.
pub fn scene_sensors(scene: &Path) -> Result<Vec<(String, [bool; 3])>, InputError> {
    let s = crate::scene::load(scene)?;
    Ok(s.vehicle
        .handles
        .sensors
        .iter()
        .map(|x| (x.name.clone(), x.axes))
        .collect())
}

/// Maps the sniffed acceleration columns onto `sensors`, each scene channel once, and
/// the first speed column as the vehicle-speed channel (it is mapped, not unmapped).
pub fn map_columns(s: &mut Sniff, sensors: &[(String, [bool; 3])]) {
    let mut taken: Vec<String> = Vec::new();
    let mut speed: Option<String> = None;
    for c in s.columns.iter_mut() {
        c.speed_channel = false;
        if c.kind == Kind::Speed {
            match &speed {
                None => {
                    c.unmapped = None;
                    c.speed_channel = true;
                    speed = Some(c.name.clone());
                }
                Some(first) => {
                    c.unmapped = Some(format!("a second speed: `{first}` is the speed channel"))
                }
            }
            continue;
        }
        if c.kind != Kind::Acceleration {
            c.unmapped = Some(format!(
                "not an acceleration (unit {})",
                c.unit.as_deref().unwrap_or("none")
            ));
            continue;
        }
        match map_channel(&c.name, sensors) {
            Ok(m) if taken.contains(&m) => {
                c.unmapped = Some(format!("{m} is already mapped from another column"))
            }
            Ok(m) => {
                taken.push(m.clone());
                c.simulated = Some(m);
            }
            Err(e) => c.unmapped = Some(e),
        }
    }
}

/// `to` relative to the directory `from` (both made absolute against the working
/// directory), for paths written into a descriptor.
fn relative(to: &Path, from: &Path) -> PathBuf {
    let abs = |p: &Path| -> Vec<String> {
        let p = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
        let mut v: Vec<String> = Vec::new();
        for c in p.components() {
            match c {
                Component::ParentDir => {
                    v.pop();
                }
                Component::CurDir => {}
                c => v.push(c.as_os_str().to_string_lossy().to_string()),
            }
        }
        v
    };
    let (t, f) = (abs(to), abs(from));
    let common = t.iter().zip(&f).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..f.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c);
    }
    out
}

fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// The descriptor draft for `s` (mapped by [`map_columns`]) and `scene`, to be written
/// to `out`.
pub fn draft(s: &Sniff, scene: &Path, out: &Path) -> String {
    let dir = out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let path = |p: &Path| quoted(&relative(p, dir).to_string_lossy());
    let sep = match s.separator {
        '\t' => "separator tab".to_string(),
        '\0' => "ASAM MDF4".to_string(),
        c => format!("separator `{c}`"),
    };
    let mut t = String::new();
    let _ = writeln!(
        t,
        "# Descriptor drafted by `towride validate init` from {}:",
        s.file.display()
    );
    let _ = writeln!(
        t,
        "# {sep}{}{}{}, {} rows, {} at {} Hz.",
        if s.decimal_comma {
            ", decimal commas"
        } else {
            ""
        },
        if s.header_line > 0 {
            format!(", header on line {}", s.header_line)
        } else {
            String::new()
        },
        s.units_line
            .map_or(String::new(), |u| format!(", units row on line {u}")),
        s.rows,
        match s.time_base.kind {
            super::timebase::TimeBaseKind::Column => "time column",
            super::timebase::TimeBaseKind::Reconstructed =>
                "time column rebuilt from the row count",
            super::timebase::TimeBaseKind::Declared => "no time column, declared rate",
        },
        s.time_base.rate_hz
    );
    for n in &s.notes {
        let _ = writeln!(t, "#   {n}");
    }
    let _ = writeln!(
        t,
        "# Check every line marked CHECK, then run `towride validate {}`.\n",
        out.display()
    );
    let _ = writeln!(t, "scene = {}", path(scene));
    let _ = writeln!(t, "data = {}", path(&s.file));
    match &s.time_column {
        Some(c) => {
            let _ = writeln!(t, "time_column = {}", quoted(c));
        }
        None => {
            let _ = writeln!(
                t,
                "sample_rate_hz = {}  # CHECK: the logger's rate (no time column)",
                s.time_base.rate_hz
            );
        }
    }
    let _ = writeln!(t, "# nominal_speed_kmh = 30.0  # the speed the driver aimed at, for the uncorrected comparison");
    let _ = writeln!(t, "# load_case = \"empty\"     # default: the scene's");
    let _ = writeln!(
        t,
        "\n[acquisition]  # CHECK: the logger's anti-alias low-pass"
    );
    let _ = writeln!(t, "filter = \"butterworth\"\norder = 4\ncutoff_hz = 100.0");
    if s.time_base.rate_hz >= 1000.0 {
        let _ = writeln!(
            t,
            "# {} Hz is far above the band compared: the recording is passed through the same\n# low-pass as the simulation.\nmeasurement = \"filtered\"",
            s.time_base.rate_hz
        );
    }
    // The speed channel as mapped (the first speed column when not mapped yet).
    let speed = s
        .columns
        .iter()
        .find(|c| c.speed_channel)
        .or_else(|| s.columns.iter().find(|c| c.kind == Kind::Speed));
    if let Some(c) = speed {
        let _ = writeln!(t, "\n[speed]  # the vehicle-speed channel: the simulated speed is its mean over the passage");
        let _ = writeln!(t, "column = {}", quoted(&c.name));
    } else {
        let _ = writeln!(
            t,
            "\n# No speed channel: give nominal_speed_kmh above or [trigger] foils."
        );
    }
    let _ = writeln!(
        t,
        "\n# No trigger: the passage is found in the wheel channels (front axle's onset, then\n# the rear axle's where the wheelbase puts it). Give [trigger] photocell and foils if\n# recorded; they take precedence."
    );
    for c in s.columns.iter().filter(|c| c.simulated.is_some()) {
        let sim = c.simulated.as_deref().unwrap_or_default();
        let _ = writeln!(
            t,
            "\n[[channel]]\ncolumn = {}\nsimulated = {}",
            quoted(&c.name),
            quoted(sim)
        );
        let _ = writeln!(t, "axis = \"{}\"", sim.chars().last().unwrap_or('z'));
        channel_lines(&mut t, s, c, sim);
    }
    let unmapped: Vec<&super::init::Column> = s
        .columns
        .iter()
        .filter(|c| c.simulated.is_none() && speed.is_none_or(|v| v.name != c.name))
        .collect();
    if !unmapped.is_empty() {
        let _ = writeln!(t, "\n# Columns not mapped onto the scene's channels:");
        for c in unmapped {
            let _ = writeln!(
                t,
                "#   {} [{}]: {}",
                c.name,
                c.unit.as_deref().unwrap_or(""),
                c.unmapped.as_deref().unwrap_or("")
            );
        }
    }
    t
}

/// A mapped channel's gravity, offset and range lines.
fn channel_lines(t: &mut String, s: &Sniff, c: &Column, sim: &str) {
    let unit = c.unit.as_deref().and_then(Unit::parse);
    let to_g = |v: f64| unit.map_or(f64::NAN, |u| v * u.to_si() / G_MPS2);
    let mean_g = to_g(c.median);
    let gravity = sim.ends_with("_z") && (mean_g - 1.0).abs() < GRAVITY_TOL_G;
    if gravity {
        let _ = writeln!(
            t,
            "remove_gravity = true  # reads {mean_g:.3} g in steady driving (median)"
        );
    } else if mean_g.is_finite() {
        let _ = writeln!(t, "# median {mean_g:.3} g: no gravity removed");
    }
    match (s.quiet_window_s, c.quiet_median.map(to_g)) {
        (Some([a, b]), Some(q)) if q.is_finite() => {
            let offset = q - if gravity { 1.0 } else { 0.0 };
            let less = if gravity {
                " less the 1 g of gravity"
            } else {
                ""
            };
            let _ = writeln!(
                t,
                "offset_g = {offset:.6}  # CHECK: median {q:.6} g over {a:.3}..{b:.3} s, quiet before the passage,{less}: the sensor's fixed offset, removed"
            );
        }
        _ => {
            let _ = writeln!(
                t,
                "# offset_g = 0.0  # no quiet part before the passage found: no offset removed"
            );
        }
    }
    match c.flat_top_g {
        Some(r) => {
            let _ = writeln!(
                t,
                "range_g = {r:.6}  # CHECK: the file holds |{r:.6}| g in plateaus: this sensor's clipping level"
            );
        }
        None => {
            let peak = c.peak_g.unwrap_or(0.0);
            let r = default_range(peak);
            let _ = writeln!(
                t,
                "range_g = {r}  # CHECK: no clipping in the file (largest |reading| {peak:.3} g): the default {DEFAULT_RANGE_G} g, or the next standard range above the largest reading"
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_map_onto_sensors() {
        let s: Vec<(String, [bool; 3])> = [
            "wheel_front_left",
            "body_rear_right",
            "hitch",
            "trailer_drawbar",
            "trailer_wheel_left",
        ]
        .iter()
        .map(|n| (n.to_string(), [true, true, true]))
        .collect();
        let m = |n: &str| map_channel(n, &s);
        assert_eq!(
            m("FL Unsprung acceleration").unwrap(),
            "acc_wheel_front_left_z"
        );
        assert_eq!(
            m("RR Sprung acceleration").unwrap(),
            "acc_body_rear_right_z"
        );
        assert_eq!(m("rear right body acc").unwrap(), "acc_body_rear_right_z");
        assert_eq!(m("Drawbar vertical").unwrap(), "acc_trailer_drawbar_z");
        assert_eq!(m("hitch_x").unwrap(), "acc_hitch_x");
        assert!(m("IMU acc z").is_err());
        assert!(m("FR Sprung acceleration").is_err());
        assert_eq!(
            declared_rate(&["# Sample rate: 5 kHz".into()]),
            Some((5000.0, 0))
        );
        assert_eq!(declared_rate(&["# rate 2000 Hz".into()]), Some((2000.0, 0)));
        assert_eq!(
            relative(Path::new("/a/b/c.toml"), Path::new("/a/d")),
            PathBuf::from("../b/c.toml")
        );
    }
}
