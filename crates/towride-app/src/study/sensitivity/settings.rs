//! What a study is asked for: the method, the parameters' groups, the Morris design and
//! its limits (refused before any run), and where its files go by default.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::Param;
use crate::error::{Error, Result};
use towride_mbs::input::Loader;

/// The screening method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// One at a time, central differences at +-10 %.
    Oat,
    /// Morris elementary effects.
    Morris,
}

impl Method {
    /// The method as engineers write it ("OAT", "Morris"): the JSON's snake_case name
    /// (`oat`) is for programs, a Debug print of it read "Oat".
    pub fn short(self) -> &'static str {
        match self {
            Method::Oat => "OAT",
            Method::Morris => "Morris",
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Oat => "OAT (one-at-a-time) study",
            Method::Morris => "Morris screening (elementary effects)",
        })
    }
}

/// What to study.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Scene or mechanism file.
    pub file: PathBuf,
    /// Parameters named `FILE:PATH` (empty: discovered in `groups`).
    pub params: Vec<String>,
    /// Groups searched when `params` is empty (empty: [`DEFAULT_GROUPS`]).
    pub groups: Vec<String>,
    /// Outputs (empty: the defaults of [`outputs::defaults`]).
    pub outputs: Vec<String>,
    /// OAT or Morris.
    pub method: Method,
    /// Morris trajectories.
    pub trajectories: usize,
    /// Morris levels (even).
    pub levels: usize,
    /// Morris range: each value times 1 -+ this (OAT varies by +-10 % and ignores it).
    pub range: f64,
    /// Morris seed.
    pub seed: u64,
    /// Parallel runs.
    pub jobs: usize,
    /// The caller's overrides (`--set`, `--overrides`), under every run's own.
    pub base: Loader,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            file: PathBuf::new(),
            params: Vec::new(),
            groups: Vec::new(),
            outputs: Vec::new(),
            method: Method::Oat,
            trajectories: 10,
            levels: 4,
            range: 0.3,
            seed: 1,
            jobs: 2,
            base: Loader::new(),
        }
    }
}

/// The groups searched when none are named: the hitch, the trailer, the tyres and a
/// `simple` vehicle's own file (its masses, ride frequencies, damping ratios, tyre).
pub const DEFAULT_GROUPS: [&str; 4] = ["hitch", "trailer", "tyres", "vehicle"];

/// Settings a study cannot be made with, refused before any run.
pub(super) fn check_settings(s: &Settings) -> Result<()> {
    let bad = |field: &str, message: String| -> Error {
        towride_mbs::input::InputError {
            file: "command line".into(),
            line: None,
            column: None,
            field: field.into(),
            message,
            kind: Default::default(),
        }
        .into()
    };
    if s.method == Method::Morris
        && !(MIN_TRAJECTORIES..=MAX_TRAJECTORIES).contains(&s.trajectories)
    {
        return Err(bad(
            "--trajectories",
            format!(
                "{}: Morris needs {MIN_TRAJECTORIES} to {MAX_TRAJECTORIES} trajectories \
                 (sigma takes two elementary effects per parameter)",
                s.trajectories
            ),
        ));
    }
    if !(s.range > 0.0 && s.range < 1.0) {
        return Err(bad(
            "--range",
            format!("{}: a fraction between 0 and 1", s.range),
        ));
    }
    Ok(())
}

/// Morris trajectories accepted: two give sigma its first degree of freedom; a thousand
/// is far beyond screening practice (10 to 50) and bounds the runs.
pub const MIN_TRAJECTORIES: usize = 2;
/// See [`MIN_TRAJECTORIES`].
pub const MAX_TRAJECTORIES: usize = 1000;

/// The Morris range of a parameter's scale factor: 1 -+ `range`, narrowed to the
/// plausibility bounds of its key (a ring tyre's factor: to its open range, see
/// [`super::params::factor_limits`]).
pub fn range_of(p: &Param, range: f64) -> [f64; 2] {
    if let Some([lo, hi]) = super::params::factor_limits(p, 1.0 - range) {
        return [(1.0 - range).max(lo), (1.0 + range).min(hi)];
    }
    let key = p.path.rsplit('.').next().unwrap_or(&p.path);
    let b = towride_mbs::input::bounds::for_key(key);
    let v = p.base_value().abs();
    let (mut lo, mut hi) = (1.0 - range, 1.0 + range);
    if v > 0.0 {
        lo = lo.max(b.min / v);
        hi = hi.min(b.max / v);
    }
    [lo, hi]
}

/// The study's directory for a scene: `out/sensitivity/<scene path>`, the scene's path
/// relative to the working directory without its extension, separators as `_`
/// (`scenes/van_air/bump_50mm.toml`: `scenes_van_air_bump_50mm`), so two scenes of one
/// name in different folders keep their own studies. A scene outside the working
/// directory: its stem and 8 hex digits of the FNV-1a of its normalised path.
pub fn default_dir(file: &Path) -> PathBuf {
    use towride_mbs::input::normalized;
    let cwd = std::env::current_dir().unwrap_or_default();
    let full = normalized(&cwd.join(file));
    let name = match full.strip_prefix(normalized(&cwd)) {
        Ok(rel) if !rel.as_os_str().is_empty() => rel
            .with_extension("")
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join("_"),
        _ => {
            let stem = file.file_stem().unwrap_or_default().to_string_lossy();
            let h = towride_mbs::input::fnv1a(full.to_string_lossy().as_bytes());
            format!("{stem}_{:08x}", h as u32)
        }
    };
    PathBuf::from("out").join("sensitivity").join(name)
}
