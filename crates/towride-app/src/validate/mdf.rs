//! ASAM MDF4 recordings (`.mf4`), read with the `falcon_mdf` crate (ASAM MCD-2 MDF 4.x:
//! an `##ID` block whose first eight bytes are `MDF     `, or `UnFinMF ` for a file its
//! logger did not finalise). Every channel group has its own master (time) channel and
//! rate; values are physical (the file's conversions applied by the crate) and units are
//! the channels' own. The pipeline compares one table, so the wanted channels are put
//! on the time base of the fastest group holding one of them: other groups are
//! interpolated linearly onto it over the span all of them cover, and a note says so.
//! After that the rows go through the text path's time-base check and repairs
//! ([`super::timebase`], [`super::repair`]); a "line" in their messages is the record
//! number (1-based) in the fastest group.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use falcon_mdf::blocks::ChannelType;
use falcon_mdf::Mf4File;
use towride_mbs::input::regular::{read_regular, DATA_FILE_MAX_BYTES};
use towride_mbs::input::InputError;

use super::csv_reader::{err, normalised, Table, TimeSpec};
use super::timebase::{self, TimeBase, TimeBaseKind};
use super::units::time_factor;

/// The identification of an MDF4 file, finalised or not.
pub const MAGICS: [&[u8; 8]; 2] = [b"MDF     ", b"UnFinMF "];

/// One channel of a recording with its own group's time base.
#[derive(Clone, Debug)]
pub struct Channel {
    /// Channel name.
    pub name: String,
    /// Unit as written in the file (`None` when empty).
    pub unit: Option<String>,
    /// Index of its channel group, counted over the file's data groups.
    pub group: usize,
    /// Its group's master channel name.
    pub master: String,
    /// Sample times [s] from its group's master channel.
    pub time_s: Vec<f64>,
    /// Physical values.
    pub values: Vec<f64>,
}

/// `bytes` begin like an MDF4 file.
pub fn has_magic(bytes: &[u8]) -> bool {
    MAGICS.iter().any(|m| bytes.starts_with(&m[..]))
}

/// `file` is meant as MDF: by its `.mf4`/`.mdf` extension or by its first bytes.
pub fn is_mdf(file: &Path) -> bool {
    let ext = file
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if matches!(ext.as_deref(), Some("mf4" | "mdf")) {
        return true;
    }
    // Only a regular file is opened: a FIFO would block here (the readers refuse it).
    if !std::fs::metadata(file).is_ok_and(|m| m.is_file()) {
        return false;
    }
    let mut head = [0u8; 8];
    use std::io::Read;
    std::fs::File::open(file)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok_and(|_| has_magic(&head))
}

fn bad(file: &Path, field: &str, msg: String) -> InputError {
    err(file, None, None, field, msg)
}

/// Every non-master channel of `file` with its group's times.
pub fn read_channels(file: &Path) -> Result<Vec<Channel>, InputError> {
    let bytes = read_regular(file, DATA_FILE_MAX_BYTES)?;
    if !has_magic(&bytes) {
        let head = String::from_utf8_lossy(&bytes[..bytes.len().min(8)]).into_owned();
        return Err(bad(
            file,
            "##ID",
            format!(
                "not an MDF4 file: it begins `{}`, not `MDF     ` or `UnFinMF ` (a text \
                 recording needs a .csv/.txt name)",
                head.escape_debug()
            ),
        ));
    }
    // The crate returns errors for the damage it checks; a panic on damage it does not
    // check is turned into an error too, so no recording can abort the command.
    let read = catch_unwind(AssertUnwindSafe(|| decode(bytes)));
    match read {
        Ok(Ok(chans)) if chans.is_empty() => Err(bad(
            file,
            "##CG",
            "the file holds no channel besides masters".into(),
        )),
        Ok(Ok(chans)) => Ok(chans),
        Ok(Err(e)) => Err(bad(file, "MDF4", format!("damaged or unsupported: {e}"))),
        Err(_) => Err(bad(
            file,
            "MDF4",
            "damaged: a block could not be decoded (the reader stopped on it)".into(),
        )),
    }
}

fn decode(bytes: Vec<u8>) -> falcon_mdf::error::Result<Vec<Channel>> {
    let f = Mf4File::from_bytes(bytes)?;
    let mut out = Vec::new();
    let mut group = 0;
    for dg in f.data_groups() {
        for cg in &dg.channel_groups {
            let master = cg.master_channel();
            let master_name = master.map_or(String::new(), |m| m.name.clone());
            let factor = master.and_then(|m| time_factor(&m.unit)).unwrap_or(1.0);
            for ch in &cg.channels {
                if matches!(
                    ch.channel_type,
                    ChannelType::Master | ChannelType::VirtualMaster
                ) {
                    continue;
                }
                let time_s: Vec<f64> = f
                    .channel_timestamps(ch)?
                    .into_iter()
                    .map(|t| t * factor)
                    .collect();
                let values = f.signal(ch)?.values_f64()?;
                out.push(Channel {
                    name: ch.name.clone(),
                    unit: Some(ch.unit.trim().to_string()).filter(|u| !u.is_empty()),
                    group,
                    master: master_name.clone(),
                    time_s,
                    values,
                });
            }
            group += 1;
        }
    }
    Ok(out)
}

/// Linear interpolation of (`t`, `v`) at `x` (inside `t`'s span).
fn interp(t: &[f64], v: &[f64], x: f64) -> f64 {
    let k = t.partition_point(|ti| *ti <= x).clamp(1, t.len() - 1);
    let (t0, t1) = (t[k - 1], t[k]);
    let w = if t1 > t0 { (x - t0) / (t1 - t0) } else { 0.0 };
    v[k - 1] + w * (v[k] - v[k - 1])
}

fn rate(t: &[f64]) -> f64 {
    (t.len().saturating_sub(1)) as f64 / (t[t.len() - 1] - t[0])
}

/// Reads `columns` of the MDF4 `file` as one table (see the module doc).
pub fn read_table(file: &Path, time: &TimeSpec, columns: &[&str]) -> Result<Table, InputError> {
    let chans = read_channels(file)?;
    let mut picked: Vec<&Channel> = Vec::new();
    for c in columns {
        let hit = chans.iter().find(|ch| ch.name == *c).or_else(|| {
            chans
                .iter()
                .find(|ch| normalised(&ch.name) == normalised(c))
        });
        let Some(ch) = hit else {
            let names: Vec<&str> = chans.iter().take(12).map(|c| c.name.as_str()).collect();
            return Err(bad(
                file,
                c,
                format!(
                    "no channel `{c}` in the file (its channels: {})",
                    names.join(", ")
                ),
            ));
        };
        if ch.time_s.len() < 10 {
            return Err(bad(
                file,
                c,
                format!(
                    "channel group {} has {} records; a recording needs at least 10",
                    ch.group,
                    ch.time_s.len()
                ),
            ));
        }
        picked.push(ch);
    }
    let Some(fast) = picked
        .iter()
        .max_by(|a, b| rate(&a.time_s).total_cmp(&rate(&b.time_s)))
    else {
        return Err(bad(file, "", "no channel asked for".into()));
    };
    let tname = fast.master.clone();
    let (lo, hi) = picked.iter().fold((f64::MIN, f64::MAX), |(lo, hi), c| {
        (lo.max(c.time_s[0]), hi.min(c.time_s[c.time_s.len() - 1]))
    });
    let mut notes = Vec::new();
    let mut rows = Vec::new();
    for (k, &t) in fast.time_s.iter().enumerate() {
        if t < lo || t > hi {
            continue;
        }
        let vals = picked
            .iter()
            .map(|c| {
                Some(if c.group == fast.group {
                    c.values[k]
                } else {
                    interp(&c.time_s, &c.values, t)
                })
            })
            .collect();
        rows.push((k + 1, t, vals));
    }
    let groups: std::collections::BTreeSet<usize> = picked.iter().map(|c| c.group).collect();
    if groups.len() > 1 {
        let others: Vec<String> = picked
            .iter()
            .filter(|c| c.group != fast.group)
            .map(|c| format!("{} ({:.6} Hz)", c.name, rate(&c.time_s)))
            .collect();
        notes.push(format!(
            "MDF4 channel groups {groups:?}: {} resampled linearly onto the time base of \
             group {} ({:.6} Hz, master `{tname}`), {:.6}-{:.6} s (the span all cover)",
            others.join(", "),
            fast.group,
            rate(&fast.time_s),
            lo,
            hi
        ));
    }
    if rows.len() < 10 {
        return Err(bad(
            file,
            &tname,
            format!("the channel groups overlap in only {} records", rows.len()),
        ));
    }
    if let Some(c) = &time.column {
        if normalised(c) != normalised(&tname) {
            notes.push(format!(
                "time from the master channel `{tname}` of group {} (`{c}` asked for)",
                fast.group
            ));
        }
    }
    let stamps: Vec<f64> = rows.iter().map(|r| r.1).collect();
    let mut time_base = TimeBase {
        kind: TimeBaseKind::Column,
        rate_hz: f64::NAN,
        stamp_step_s: None,
        rows_per_stamp: None,
    };
    match timebase::reconstruct(&stamps, time.rate_hz) {
        Err((k, msg)) => return Err(err(file, rows.get(k).map(|r| r.0), None, &tname, msg)),
        Ok(Some((t, tb, note))) => {
            for (r, tk) in rows.iter_mut().zip(t) {
                r.1 = tk;
            }
            notes.push(note);
            time_base = tb;
        }
        Ok(None) => {}
    }
    let (time_s, cols, repairs) =
        super::repair::repair(file, rows, picked.len(), 1, &tname, columns)?;
    notes.extend(repairs);
    if time_base.kind == TimeBaseKind::Column {
        time_base.rate_hz = rate(&time_s);
    }
    Ok(Table {
        file: file.to_path_buf(),
        time_s,
        columns: cols,
        units: picked.iter().map(|c| c.unit.clone()).collect(),
        separator: '\0',
        decimal_comma: false,
        header_line: 0,
        units_line: None,
        time_base,
        notes,
    })
}
