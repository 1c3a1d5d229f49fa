//! What a descriptor needs to know of its scene without building it: the obstacle's
//! name (the road file's stem) and the load cases the scene's trailer defines.
//!
//! A descriptor's `scene` may also be a road file (the pipeline's own test simulators
//! drive over a road file); then the measurement plan's load cases apply.

use std::path::{Path, PathBuf};

fn table(path: &Path) -> Option<toml::Table> {
    std::fs::read_to_string(path).ok()?.parse().ok()
}

fn str_at<'a>(t: &'a toml::Table, a: &str, b: &str) -> Option<&'a str> {
    t.get(a)?.get(b)?.as_str()
}

/// The scene's vehicle file, when `scene` is a scene file.
fn vehicle_file(scene: &Path) -> Option<(PathBuf, toml::Table)> {
    let s = table(scene)?;
    let v = str_at(&s, "scene", "vehicle")?;
    let path = scene.parent().unwrap_or(Path::new(".")).join(v);
    let t = table(&path)?;
    Some((path, t))
}

/// The obstacle's name: the stem of the scene's road file (of `scene` itself when it is
/// not a scene file).
pub fn road_name(scene: &Path) -> Option<String> {
    let stem = |p: &Path| p.file_stem().map(|s| s.to_string_lossy().to_string());
    match table(scene) {
        Some(s) if s.contains_key("scene") => {
            str_at(&s, "road", "file").and_then(|r| stem(Path::new(r)))
        }
        _ => stem(scene),
    }
}

/// The load cases a descriptor of `scene` may name, and where they come from: the
/// scene's trailer file's, `None` (any) when its vehicle has no trailer, the measurement
/// plan's when `scene` is not a scene file.
pub fn load_cases(scene: &Path) -> (Option<Vec<String>>, String) {
    let plan = || {
        (
            Some(super::plan::load_cases()),
            "the measurement plan's".to_string(),
        )
    };
    let Some((vpath, v)) = vehicle_file(scene) else {
        return plan();
    };
    let names = |cases: Option<&toml::Value>| -> Vec<String> {
        cases
            .and_then(|c| c.as_array())
            .map(|a| {
                a.iter()
                    .filter_map(|c| c.get("name").and_then(|n| n.as_str()).map(String::from))
                    .collect()
            })
            .unwrap_or_default()
    };
    let Some(trailer) = v.get("trailer") else {
        return (None, format!("{} has no trailer", vpath.display()));
    };
    if str_at(&v, "vehicle", "template") == Some("simple") {
        return (
            Some(names(trailer.get("load_case"))),
            format!("the trailer of {}", vpath.display()),
        );
    }
    let Some(file) = trailer.get("file").and_then(|f| f.as_str()) else {
        return plan();
    };
    let tpath = vpath.parent().unwrap_or(Path::new(".")).join(file);
    match table(&tpath) {
        Some(t) => (
            Some(names(t.get("load_case"))),
            format!("the scene's trailer file {}", tpath.display()),
        ),
        None => plan(),
    }
}
