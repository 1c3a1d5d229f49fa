//! The parameters of a sensitivity study: property-file values addressed as overrides
//! address them (`FILE:PATH`, [`towride_mbs::input::Override`]), found in the files a scene
//! reads.
//!
//! Discovery is generic: the scene is loaded once and every file it read is searched for
//! stiffness, damping and mass values by their field names (TOML: a key containing
//! `stiffness` or `damping`, or ending in `_kg`, `_kg_m2`, `_kg_m3`, `modulus_pa`;
//! `.tir`: `*STIFFNESS`, `*DAMPING`, `DAMP_*`, `FREQ_*` (ring frequencies set the ring's
//! stiffness), `MASS`, `BELT_MASS`, `I*`/`BELT_I*` inertias). A file's group is the
//! vehicle-file key that names it (`hitch`, `front`, `body`, `trailer`; `tyre` keys give
//! `tyres`); files named from those files (a hitch's FE model) inherit their group. So
//! new fields and files join without a list in code. A value the assembled model does not
//! depend on (a bushing of a ball coupling modelled as a joint, the payload of a load
//! case not driven) is dropped as inactive: a 10 % change leaves the model description
//! unchanged. A ring tyre's `.tir` file also offers its independent factors
//! (`factor.NAME`, [`towride_mbs::tyre::factors`]); the default lists take them instead
//! of the coupled values they drive ([`driven_by_factors`]), which stay addressable by
//! name.

use std::path::{Path, PathBuf};

use serde::Serialize;

use towride_mbs::input::{InputError, Loader};
use towride_mbs::input::{Origin, Override};
use towride_mbs::tyre::factors;

/// The value a parameter scales.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Base {
    /// A number.
    Scalar(f64),
    /// A vector, scaled as a whole unless one component is addressed.
    Vector(Vec<f64>),
}

/// One parameter.
#[derive(Clone, Debug, Serialize)]
pub struct Param {
    /// `FILE:PATH` (with `[i]` for one component of a vector), FILE relative to the
    /// scene's vehicle file.
    pub name: String,
    /// File, matched by the end of its path.
    pub file: String,
    /// TOML path or `.tir` `SECTION.KEY`.
    pub path: String,
    /// The component addressed, `None`: the whole value.
    pub component: Option<usize>,
    /// The vehicle part it belongs to.
    pub group: String,
    /// stiffness, damping or mass.
    pub kind: String,
    /// Its value in the files.
    pub base: Base,
    /// 1-based line in its file.
    pub line: usize,
    /// The file as read (for its provenance tags).
    #[serde(skip)]
    pub disk_path: PathBuf,
}

impl Param {
    /// The override setting the value to `factor` times its base.
    pub fn scaled(&self, factor: f64) -> Override {
        let text = match (&self.base, self.component) {
            (Base::Scalar(v), _) => num(v * factor),
            (Base::Vector(v), c) => {
                let parts: Vec<String> = v
                    .iter()
                    .enumerate()
                    .map(|(i, x)| {
                        if c.is_none() || c == Some(i) {
                            num(x * factor)
                        } else {
                            num(*x)
                        }
                    })
                    .collect();
                format!("[{}]", parts.join(", "))
            }
        };
        // The study is a caller (its values replace a scene's `[[override]]` of the same
        // value, and one also set by `--set` is refused as set twice); errors name the
        // parameter and factor.
        let at = InputError {
            file: "sensitivity study".into(),
            line: None,
            column: None,
            field: format!("{} x {factor}", self.name),
            message: String::new(),
            kind: Default::default(),
        };
        Override {
            file: self.file.clone(),
            path: self.path.clone(),
            value: text,
            origin: Origin::File {
                file: Box::new(at.clone()),
                path: Box::new(at),
            },
        }
    }

    /// The base value (the addressed component of a vector, or its largest magnitude).
    pub fn base_value(&self) -> f64 {
        match (&self.base, self.component) {
            (Base::Scalar(v), _) => *v,
            (Base::Vector(v), Some(c)) => v[c],
            (Base::Vector(v), None) => v.iter().fold(0.0f64, |m, x| m.max(x.abs())),
        }
    }
}

/// A number as TOML text (always with a decimal point or exponent).
fn num(v: f64) -> String {
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E', 'i', 'N']) {
        s
    } else {
        format!("{s}.0")
    }
}

/// Stiffness, damping or mass by a TOML key (name and unit suffix), or `None`.
fn toml_kind(key: &str) -> Option<&'static str> {
    let stiff_unit = key.ends_with("_n_m") || key.ends_with("_n_m_rad");
    let damp_unit = key.ends_with("_n_s_m") || key.ends_with("_n_m_s_rad");
    if (key.contains("stiffness") && stiff_unit) || key.ends_with("modulus_pa") {
        Some("stiffness")
    } else if key.contains("damping") && damp_unit || key == "damping_ratio" {
        Some("damping")
    } else if key == "ride_frequency_hz" {
        // A `simple` vehicle's spring: the stiffness follows from it and the mass.
        Some("stiffness")
    } else if key.ends_with("_kg") || key.ends_with("_kg_m2") || key.ends_with("_kg_m3") {
        Some("mass")
    } else {
        None
    }
}

/// The same for a `.tir` key.
fn tir_kind(key: &str) -> Option<&'static str> {
    let inertia = |k: &str| {
        k.len() == 3 && k.starts_with('I') && k[1..].chars().all(|c| matches!(c, 'X' | 'Y' | 'Z'))
    };
    if key.ends_with("STIFFNESS") || key.starts_with("FREQ_") {
        Some("stiffness")
    } else if key.ends_with("DAMPING") || key.starts_with("DAMP_") {
        Some("damping")
    } else if key == "MASS"
        || key == "BELT_MASS"
        || inertia(key)
        || key.strip_prefix("BELT_").is_some_and(inertia)
    {
        Some("mass")
    } else {
        None
    }
}

/// Every stiffness, damping and mass value of the files `scene` reads whose group is in
/// `groups` (empty: all), before the inactive ones are dropped.
pub fn candidates(scene: &Path, groups: &[String]) -> Result<Vec<Param>, crate::Error> {
    collect(scene, groups, false)
}

/// Every numeric value of every file `scene` reads (the scene's and road's too), kind
/// `value` where the name says neither stiffness, damping nor mass, group `scene` for
/// files outside the vehicle's groups: what `calibrate --params` may address.
pub fn every_value(scene: &Path) -> Result<Vec<Param>, crate::Error> {
    collect(scene, &[], true)
}

fn collect(scene: &Path, groups: &[String], every: bool) -> Result<Vec<Param>, crate::Error> {
    let loader = Loader::new();
    let is_scene = crate::scene::is_scene(scene);
    if is_scene {
        crate::scene::load_with(scene, &crate::scene::Changes::default(), &loader)?;
    } else {
        crate::job::Job::from_mechanism_file(scene, &loader)?;
    }
    let files = loader.files_read();
    let mut group = assign_groups(&files);
    if !is_scene {
        // A mechanism file's own values form the group `model`.
        group[0] = Some("model".into());
    }
    // Files are named relative to the deepest folder holding them all (the repository
    // for the shipped scenes): `vehicles/fabia/hitch.toml`, `flex/hitch_crossbeam.toml`.
    let canon: Vec<PathBuf> = files
        .iter()
        .map(|f| f.canonicalize().unwrap_or_else(|_| f.clone()))
        .collect();
    let root = canon.iter().skip(1).fold(None::<PathBuf>, |acc, f| {
        let dir = f.parent().unwrap_or(Path::new("")).to_path_buf();
        Some(match acc {
            None => dir,
            Some(a) => a
                .ancestors()
                .find(|x| dir.starts_with(x))
                .map(Path::to_path_buf)
                .unwrap_or_default(),
        })
    });
    // Base values as the run sees them: a scene's `[[override]]` tables replace values of
    // the files (and the study's own overrides then replace those, see `scene::load_with`).
    let scene_overrides = if is_scene {
        crate::scene::file_overrides(scene)?
    } else {
        Vec::new()
    };
    let effective = Loader::with_overrides(scene_overrides);
    let mut out = Vec::new();
    for ((f, c), g) in files.iter().zip(&canon).zip(&group) {
        let g = match (g, every) {
            (Some(g), _) => g.clone(),
            (None, true) => "scene".to_string(),
            (None, false) => continue,
        };
        let g = &g;
        if !groups.is_empty() && !groups.contains(g) {
            continue;
        }
        let rel = root
            .as_ref()
            .and_then(|r| c.strip_prefix(r).ok())
            .unwrap_or(f)
            .display()
            .to_string();
        let text = towride_mbs::input::read_text(f)?;
        if f.extension().is_some_and(|e| e == "tir") {
            let first = out.len();
            tir_values(&text, &rel, g, every, &mut out);
            out[first..]
                .iter_mut()
                .for_each(|p| p.disk_path = f.clone());
            for ov in effective.overrides_of(f)? {
                let x = ov.value.trim().parse::<f64>();
                let p = out[first..].iter_mut().find(|p| p.path == ov.path);
                if let (Some(p), Ok(x)) = (p, x) {
                    p.base = Base::Scalar(x);
                }
            }
            tyre_factors(f, &rel, g, &mut out);
        } else if let Ok(t) = effective.toml_text(f)?.parse::<toml_edit::DocumentMut>() {
            let mut found = Vec::new();
            walk(t.as_item(), "", &mut found);
            for (path, base, key) in found {
                let Some(kind) = toml_kind(&key).or(every.then_some("value")) else {
                    continue;
                };
                out.push(Param {
                    name: format!("{rel}:{path}"),
                    file: rel.clone(),
                    path: path.clone(),
                    component: None,
                    group: g.clone(),
                    kind: kind.into(),
                    base,
                    line: line_of(&text, &key, &path),
                    disk_path: f.clone(),
                });
            }
        }
    }
    Ok(out)
}

/// 1-based line of the first `key =` after the table the path names (a good guess for
/// the reader of the study's tables; overrides do not use it).
fn line_of(text: &str, key: &str, path: &str) -> usize {
    let table = path.rsplit_once('.').map(|(t, _)| t).unwrap_or("");
    let head = table.split('.').next().unwrap_or("");
    let head = head.split('[').next().unwrap_or(head);
    let mut in_table = head.is_empty();
    for (i, l) in text.lines().enumerate() {
        let t = l.trim();
        if t.starts_with('[') {
            let name = t.trim_matches(|c| c == '[' || c == ']').trim();
            in_table = name == head || name.starts_with(&format!("{head}."));
        }
        if in_table
            && (t.starts_with(&format!("{key} "))
                || t.starts_with(&format!("{key}="))
                || t.contains(&format!(" {key} =")))
        {
            return i + 1;
        }
    }
    0
}

/// Numeric leaves (numbers and arrays of numbers) with their override paths.
fn walk(item: &toml_edit::Item, prefix: &str, out: &mut Vec<(String, Base, String)>) {
    use toml_edit::Item;
    let join = |k: &str| {
        if prefix.is_empty() {
            k.to_string()
        } else {
            format!("{prefix}.{k}")
        }
    };
    match item {
        Item::Table(t) => {
            for (k, v) in t.iter() {
                walk(v, &join(k), out);
            }
        }
        Item::ArrayOfTables(a) => {
            for (i, t) in a.iter().enumerate() {
                for (k, v) in t.iter() {
                    walk(v, &format!("{prefix}[{i}].{k}"), out);
                }
            }
        }
        Item::Value(v) => value(v, prefix, out),
        Item::None => {}
    }
}

fn value(v: &toml_edit::Value, path: &str, out: &mut Vec<(String, Base, String)>) {
    use toml_edit::Value;
    let key = path.rsplit('.').next().unwrap_or(path).to_string();
    let f = |v: &Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
    match v {
        Value::InlineTable(t) => {
            for (k, x) in t.iter() {
                value(x, &format!("{path}.{k}"), out);
            }
        }
        Value::Array(a) => {
            let xs: Option<Vec<f64>> = a.iter().map(f).collect();
            if let Some(xs) = xs.filter(|x| !x.is_empty()) {
                out.push((path.into(), Base::Vector(xs), key));
            }
        }
        other => {
            // Integers (variant numbers, counts) are not physical values to scale.
            if let Some(x) = other.as_float() {
                out.push((path.into(), Base::Scalar(x), key));
            }
        }
    }
}

/// `.tir` values by a line scan: `[SECTION]`, `KEY = value  $ comment`.
fn tir_values(text: &str, rel: &str, group: &str, every: bool, out: &mut Vec<Param>) {
    let mut section = String::new();
    for (i, line) in text.lines().enumerate() {
        let l = line.split(['$', '!']).next().unwrap_or("").trim();
        if l.starts_with('[') {
            section = l.trim_matches(|c| c == '[' || c == ']').trim().to_string();
            continue;
        }
        let Some((k, v)) = l.split_once('=') else {
            continue;
        };
        let (k, v) = (k.trim(), v.trim());
        let kind = tir_kind(k).or(every.then_some("value"));
        let (Some(kind), Ok(x)) = (kind, v.parse::<f64>()) else {
            continue;
        };
        if section == "UNITS" || x == 0.0 {
            continue;
        }
        let path = format!("{section}.{k}");
        out.push(Param {
            name: format!("{rel}:{path}"),
            file: rel.into(),
            path,
            component: None,
            group: group.into(),
            kind: kind.into(),
            base: Base::Scalar(x),
            line: i + 1,
            disk_path: PathBuf::new(),
        });
    }
}

/// The independent factors of a ring tyre's `.tir` file ([`factors`]), base values from
/// the file as written (the reader keeps unset factors there, whatever raw values a
/// scene changes); nothing for a file without the ring's values.
fn tyre_factors(f: &Path, rel: &str, group: &str, out: &mut Vec<Param>) {
    let Ok(t) = towride_mbs::input::tir::TirFile::read(f, &Loader::new()) else {
        return;
    };
    let Ok(x) = factors::values(&t) else {
        return;
    };
    for (fac, v) in factors::FACTORS.iter().zip(x) {
        let path = format!("{}{}", factors::PREFIX, fac.name);
        let (sec, key) = fac.main.split_once('.').unwrap_or_default();
        out.push(Param {
            name: format!("{rel}:{path}"),
            file: rel.into(),
            path,
            component: None,
            group: group.into(),
            kind: fac.kind.into(),
            base: Base::Scalar(v),
            line: t.entry(sec, key).map_or(0, |e| e.line),
            disk_path: f.to_path_buf(),
        });
    }
}

/// True when `p` is a `.tir` value that the independent factors of its file, listed in
/// `all`, drive: the factors are varied instead (a default list has one or the other).
pub fn driven_by_factors(p: &Param, all: &[Param]) -> bool {
    factors::DRIVEN.contains(&p.path.as_str())
        && all
            .iter()
            .any(|q| q.file == p.file && q.path.starts_with(factors::PREFIX))
}

/// The multipliers of a factor's base `v` at which its margin to each end of its open
/// range (a, b), v - a and b - v, has shrunk to the fraction `keep`:
/// [(a + (v - a) keep) / v, (b - (b - v) keep) / v] (infinite above for b = inf). A study
/// varying a factor by 1 -+ F stays within these at keep = 1 - F (a belt share of 0.78
/// goes up to 1 - 0.22 (1 - F), not past 1). `None` for a value that is not a factor.
pub fn factor_limits(p: &Param, keep: f64) -> Option<[f64; 2]> {
    let f = factors::find(p.path.strip_prefix(factors::PREFIX)?)?;
    let v = p.base_value();
    let (a, b) = f.range;
    Some([(a + (v - a) * keep) / v, (b - (b - v) * keep) / v])
}

/// The group of each file read (first the scene, then what it names): files named by
/// the scene or the vehicle file take the key naming them (`tyre` gives `tyres`; a key
/// `file` its table's name); files named from those inherit their group. `None`: the
/// scene and vehicle files themselves.
fn assign_groups(files: &[PathBuf]) -> Vec<Option<String>> {
    let mut group: Vec<Option<String>> = vec![None; files.len()];
    let mut depth: Vec<usize> = vec![usize::MAX; files.len()];
    if files.is_empty() {
        return group;
    }
    depth[0] = 0;
    // Breadth first over references between the files read.
    for _ in 0..4 {
        for (i, f) in files.iter().enumerate() {
            if depth[i] == usize::MAX || f.extension().is_some_and(|e| e == "tir") {
                continue;
            }
            let Ok(text) = std::fs::read_to_string(f) else {
                continue;
            };
            let Ok(doc) = text.parse::<toml::Table>() else {
                continue;
            };
            let dir = f.parent().unwrap_or(Path::new("."));
            let mut refs = Vec::new();
            refs_in(&toml::Value::Table(doc), &[], &mut refs);
            for (keys, rel) in refs {
                let full = dir.join(&rel);
                let Some(j) = files.iter().position(|g| same(g, &full)) else {
                    continue;
                };
                if depth[j] != usize::MAX {
                    continue;
                }
                depth[j] = depth[i] + 1;
                group[j] = if depth[i] <= 1 {
                    let k = keys
                        .iter()
                        .rev()
                        .find(|k| !k.ends_with("file"))
                        .cloned()
                        .unwrap_or_default();
                    Some(if k == "tyre" { "tyres".into() } else { k })
                } else {
                    group[i].clone()
                };
            }
        }
    }
    // The vehicle file itself has no group, unless it is a `simple` vehicle's, whose
    // own numbers (masses, ride frequencies, damping ratios, tyre) are the vehicle.
    for (i, d) in depth.iter().enumerate() {
        if *d <= 1 && files[i].extension().is_some_and(|e| e == "toml") {
            let is_vehicle = *d == 1 && group[i].as_deref() == Some("vehicle");
            if *d == 0 || (is_vehicle && !is_simple(&files[i])) {
                group[i] = None;
            }
        }
    }
    group
}

/// True for a vehicle file of the `simple` template.
fn is_simple(file: &Path) -> bool {
    std::fs::read_to_string(file)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|t| {
            t.get("vehicle")?
                .get("template")?
                .as_str()
                .map(String::from)
        })
        .is_some_and(|t| t == "simple")
}

fn same(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

/// String values that look like file names, with the keys leading to them.
fn refs_in(v: &toml::Value, keys: &[String], out: &mut Vec<(Vec<String>, String)>) {
    match v {
        toml::Value::String(s)
            if s.ends_with(".toml") || s.ends_with(".tir") || s.ends_with(".csv") =>
        {
            out.push((keys.to_vec(), s.clone()));
        }
        toml::Value::Table(t) => {
            for (k, x) in t {
                let mut ks = keys.to_vec();
                ks.push(k.clone());
                refs_in(x, &ks, out);
            }
        }
        toml::Value::Array(a) => {
            for x in a {
                refs_in(x, keys, out);
            }
        }
        _ => {}
    }
}

/// The parameters a user names: `FILE:PATH` or `FILE:PATH[i]` (one component of a
/// vector), each matched against the candidates of all groups by the end of the file
/// path and the exact path.
pub fn named(all: &[Param], names: &[String]) -> Result<Vec<Param>, InputError> {
    let mut out = Vec::new();
    for n in names {
        let bad = |m: String| InputError {
            file: "command line".into(),
            line: None,
            column: None,
            field: format!("--params {n}"),
            message: m,
            kind: Default::default(),
        };
        let (file, path) = n
            .rsplit_once(':')
            .filter(|(f, p)| !f.trim().is_empty() && !p.trim().is_empty())
            .ok_or_else(|| {
                bad("write FILE:PATH, e.g. hitch.toml:bracket_bushing.stiffness_n_m".into())
            })?;
        // A path ending in `[i]` addresses a component (array-of-table paths end in a key).
        let (path, component) = match path
            .strip_suffix(']')
            .and_then(|p| p.rsplit_once('['))
            .and_then(|(p, i)| Some((p, i.parse::<usize>().ok()?)))
        {
            Some((p, i)) => (p.to_string(), Some(i)),
            None => (path.to_string(), None),
        };
        let hit = all
            .iter()
            .find(|c| c.path == path && (ends_with_file(&c.file, file) || ends_with_file(file, &c.file)))
            .ok_or_else(|| {
                bad(format!(
                    "no stiffness, damping or mass value `{path}` in a file ending `{file}` of this scene (see `towride sensitivity SCENE --list`)"
                ))
            })?;
        let mut p = hit.clone();
        if let Some(i) = component {
            match &p.base {
                Base::Vector(v) if i < v.len() => {}
                _ => return Err(bad(format!("`{path}` has no component {i}"))),
            }
            p.component = Some(i);
            p.name = format!("{}[{i}]", p.name);
        }
        // Twice the same value would be varied as two parameters that are one.
        if out
            .iter()
            .any(|q: &Param| q.file == p.file && q.path == p.path && q.component == p.component)
        {
            return Err(bad(format!("`{file}:{path}` is named twice")));
        }
        out.push(p);
    }
    Ok(out)
}

/// `path` ends with the file name(s) `tail` at a `/` boundary (`fabia/hitch.toml`
/// matches `hitch.toml`, not `ch.toml`).
pub(crate) fn ends_with_file(path: &str, tail: &str) -> bool {
    path.strip_suffix(tail)
        .is_some_and(|head| head.is_empty() || head.ends_with('/'))
}
