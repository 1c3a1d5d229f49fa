//! The values a calibration fits: property-file values addressed as `--set` addresses
//! them (`FILE:PATH`), each with bounds, its value in the files and its source tag.
//!
//! A positive physical value is fitted in log scale (a stiffness is as likely 20 % low
//! as 25 % high); the least-squares variable is then mapped into its bounds by the
//! sine transform of MINUIT (James and Roos, MINUIT user's guide, CERN D506, section
//! "Parameter limits": u = (1 + sin z) / 2), so every trial is inside the bounds and
//! the fit itself is unconstrained.

use std::path::Path;

use serde::Serialize;

use crate::study::sensitivity::params::{ends_with_file, every_value, Base, Param};
use towride_mbs::input::provenance::read_provenance;
use towride_mbs::input::{InputError, Override};

/// One fitted value.
#[derive(Clone, Debug, Serialize)]
pub struct ParamSpec {
    /// `FILE:PATH`, FILE as found (relative to the scene's common folder).
    pub name: String,
    /// File, matched by the end of its path (as an override matches it).
    pub file: String,
    /// TOML path or `.tir` `SECTION.KEY`.
    pub path: String,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Fitted in log scale (both bounds positive).
    pub log: bool,
    /// The value in the files.
    pub file_value: f64,
    /// Its source class (`assumed`, ...; `untagged` without one).
    pub class: String,
    /// The source text beside it.
    pub source: String,
    /// `Some(k)`: not a property value but run k's time shift [s], a nuisance value
    /// fitted beside the others (see [`ParamSpec::time_shift`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shift_of: Option<usize>,
}

impl ParamSpec {
    /// Run `k`'s time shift within +-`bound` [s] on top of `validate`'s alignment: the
    /// cross-correlation finds the shift to a fraction of a sample with the model as it
    /// is, and a model that moves moves the best shift with it; fitted with the values,
    /// the shift cannot leave a misfit that the values would then absorb.
    pub fn time_shift(k: usize, run: &str, bound: f64) -> ParamSpec {
        ParamSpec {
            name: format!("time shift of {run}"),
            file: String::new(),
            path: String::new(),
            lo: -bound,
            hi: bound,
            log: false,
            file_value: 0.0,
            class: "alignment".into(),
            source: "on top of validate's cross-correlation".into(),
            shift_of: Some(k),
        }
    }

    /// From `param` with bounds `lo..hi` (checked: ordered, finite, containing the file
    /// value is not required — a recording may want a value the file never had).
    pub fn new(param: &Param, lo: f64, hi: f64) -> Result<ParamSpec, String> {
        let file_value = match (&param.base, param.component) {
            (Base::Scalar(v), _) => *v,
            _ => return Err(format!("{} is not a single number", param.name)),
        };
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(format!(
                "{}: bounds {lo}..{hi} must be finite and increasing",
                param.name
            ));
        }
        let (class, source) = provenance(param);
        Ok(ParamSpec {
            name: param.name.clone(),
            file: param.file.clone(),
            path: param.path.clone(),
            lo,
            hi,
            log: lo > 0.0,
            file_value,
            class,
            source,
            shift_of: None,
        })
    }

    /// The value at the bounded coordinate `u` in [0, 1].
    pub fn value(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        if self.log {
            self.lo * (self.hi / self.lo).powf(u)
        } else {
            self.lo + (self.hi - self.lo) * u
        }
    }

    /// The bounded coordinate of `x` (clamped into the bounds).
    pub fn coordinate(&self, x: f64) -> f64 {
        let u = if self.log {
            (x.max(f64::MIN_POSITIVE) / self.lo).ln() / (self.hi / self.lo).ln()
        } else {
            (x - self.lo) / (self.hi - self.lo)
        };
        u.clamp(0.0, 1.0)
    }

    /// The fit's scale of `x`: ln x in log scale, else x (intervals are symmetric there).
    pub fn scale(&self, x: f64) -> f64 {
        if self.log {
            x.ln()
        } else {
            x
        }
    }

    /// The inverse of [`ParamSpec::scale`].
    pub fn unscale(&self, s: f64) -> f64 {
        if self.log {
            s.exp()
        } else {
            s
        }
    }

    /// d(scale) / du: the width of the bounds in the fit's scale.
    pub fn scale_per_u(&self) -> f64 {
        if self.log {
            (self.hi / self.lo).ln()
        } else {
            self.hi - self.lo
        }
    }

    /// The override setting the value to `x`.
    pub fn override_for(&self, x: f64) -> Override {
        Override::program(&self.file, &self.path, number(x), "calibrate")
    }
}

/// u of the least-squares variable z (MINUIT's sine transform) and du/dz.
pub fn bounded(z: f64) -> (f64, f64) {
    (0.5 * (1.0 + z.sin()), 0.5 * z.cos())
}

/// The least-squares variable of u (the branch in [-pi/2, pi/2]).
pub fn unbounded(u: f64) -> f64 {
    (2.0 * u.clamp(0.0, 1.0) - 1.0).asin()
}

/// A number as TOML text (with a decimal point or exponent, so it stays a float).
pub fn number(v: f64) -> String {
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E', 'i', 'N']) {
        s
    } else {
        format!("{s}.0")
    }
}

fn provenance(p: &Param) -> (String, String) {
    let mut entries = read_provenance(&p.disk_path).unwrap_or_default();
    // A ring tyre's factor takes the weakest class of the values it is computed from.
    entries.extend(towride_mbs::tyre::factors::provenance(&entries));
    // A value inside an inline table is tagged on the table's line (`spring = {...}  #
    // [assumed] ...`): the nearest tagged ancestor speaks for it.
    let mut key = p.path.as_str();
    let found = loop {
        if let Some(e) = entries.iter().find(|e| e.key == key) {
            break Some(e);
        }
        match key.rsplit_once('.') {
            Some((parent, _)) => key = parent,
            None => break None,
        }
    };
    match found {
        Some(e) => (e.class.as_str().to_string(), e.source.clone()),
        None => ("untagged".into(), String::new()),
    }
}

/// Parses `FILE:PATH=LO..HI` or `FILE:PATH` (bounds: half to twice the file value, or
/// +-50 % of its magnitude for a value that is not positive), comma-separated, against
/// the values `scene` reads.
pub fn parse(list: &str, scene: &Path) -> Result<Vec<ParamSpec>, crate::Error> {
    let all = every_value(scene)?;
    let mut out: Vec<ParamSpec> = Vec::new();
    for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let bad = |m: String| InputError {
            file: "command line".into(),
            line: None,
            column: None,
            field: format!("--params {item}"),
            message: m,
            kind: Default::default(),
        };
        let (addr, bounds) = match item.split_once('=') {
            Some((a, b)) => (a.trim(), Some(b.trim())),
            None => (item, None),
        };
        let param = find(&all, addr).map_err(&bad)?;
        let x0 = param.base_value();
        let (lo, hi) = match bounds {
            Some(b) => {
                let (l, h) = b
                    .split_once("..")
                    .ok_or_else(|| bad("write the bounds as LO..HI, e.g. 0.2..0.5".into()))?;
                let num = |t: &str| {
                    t.trim()
                        .parse::<f64>()
                        .map_err(|_| bad(format!("`{t}` is not a number")))
                };
                (num(l)?, num(h)?)
            }
            None if x0 > 0.0 => (0.5 * x0, 2.0 * x0),
            None if x0 < 0.0 => (1.5 * x0, 0.5 * x0),
            None => return Err(bad("the file value is 0: give bounds LO..HI".into()).into()),
        };
        let spec = ParamSpec::new(param, lo, hi).map_err(bad)?;
        if out.iter().any(|q| q.name == spec.name) {
            return Err(bad(format!("`{}` is named twice", spec.name)).into());
        }
        out.push(spec);
    }
    if out.is_empty() {
        return Err(InputError {
            file: "command line".into(),
            line: None,
            column: None,
            field: "--params".into(),
            message: "name at least one value: FILE:PATH=LO..HI[,...] or `auto`".into(),
            kind: Default::default(),
        }
        .into());
    }
    Ok(out)
}

/// The value `addr` (`FILE:PATH`) names: FILE matched by the end of the path at a `/`.
pub fn find<'a>(all: &'a [Param], addr: &str) -> Result<&'a Param, String> {
    let (file, path) = addr
        .rsplit_once(':')
        .filter(|(f, p)| !f.trim().is_empty() && !p.trim().is_empty())
        .ok_or("write FILE:PATH, e.g. van.toml:rear.damping_ratio")?;
    let hits: Vec<&Param> = all
        .iter()
        .filter(|c| c.path == path.trim() && c.component.is_none())
        .filter(|c| ends_with_file(&c.file, file.trim()) || ends_with_file(file.trim(), &c.file))
        .collect();
    match hits.as_slice() {
        [one] => Ok(one),
        [] => Err(format!(
            "no number `{path}` in a file ending `{file}` among the files the scene reads"
        )),
        many => Err(format!(
            "`{file}` matches {} files ({}); give more of the path",
            many.len(),
            many.iter()
                .map(|p| p.file.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(lo: f64, hi: f64, log: bool) -> ParamSpec {
        ParamSpec {
            name: "f:x".into(),
            file: "f".into(),
            path: "x".into(),
            lo,
            hi,
            log,
            file_value: lo,
            class: "assumed".into(),
            source: String::new(),
            shift_of: None,
        }
    }

    /// The log map sends the midpoint to the geometric mean; both maps invert.
    #[test]
    fn coordinates_invert_and_log_scale_is_geometric() {
        let s = spec(1e4, 4e4, true);
        assert!((s.value(0.5) - 2e4).abs() < 1e-9 * 2e4);
        for x in [1e4, 1.3e4, 3.99e4] {
            assert!((s.value(s.coordinate(x)) - x).abs() < 1e-9 * x);
        }
        let l = spec(-1.0, 3.0, false);
        assert!((l.value(0.25) - 0.0).abs() < 1e-12);
        assert!((l.value(l.coordinate(2.2)) - 2.2).abs() < 1e-12);
    }

    /// MINUIT's transform keeps every z inside [0, 1] and its derivative is the
    /// analytical one (checked by a central difference).
    #[test]
    fn sine_transform_is_bounded_and_differentiable() {
        for k in -50..50 {
            let z = k as f64 * 0.37;
            let (u, du) = bounded(z);
            assert!((0.0..=1.0).contains(&u));
            let h = 1e-6;
            let fd = (bounded(z + h).0 - bounded(z - h).0) / (2.0 * h);
            assert!((du - fd).abs() < 1e-8, "z {z}: {du} vs {fd}");
        }
        for u in [0.0, 0.1, 0.5, 0.93, 1.0] {
            assert!((bounded(unbounded(u)).0 - u).abs() < 1e-12);
        }
    }
}
