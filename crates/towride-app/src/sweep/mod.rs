//! Parameter sweeps: the Cartesian product of parameter values, each a property-file
//! value addressed by file and TOML path (hitch variant, speed, trailer load, obstacle
//! or any stiffness), run in parallel, one summary row per case.
//!
//! A sweep file:
//!
//! ```toml
//! [sweep]
//! name = "hitch variants"
//! scene = "scenes/default.toml"     # relative to the sweep file
//!
//! [[parameter]]
//! name = "hitch_variant"            # column name in the summary
//! file = "vehicles/hitch.toml"      # any file the scene reads, matched by path ending
//! path = "hitch.variant"            # TOML path, `array[2].key` for arrays of tables
//! values = [1, 2, 3]
//! ```
//!
//! Cases are numbered in row-major order (the last parameter varies fastest), so shard
//! `I/N` (cases with index mod N = I) and `merge` are reproducible on any machine.

pub mod cases;
pub mod check;
pub mod exec;
pub mod figures;
pub mod fingerprint;
pub mod guard;
pub mod page;
pub mod rank;
pub mod resume;
pub mod robust;
pub mod robust_run;
pub mod usage;

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::job::ProducedBy;
use crate::scene::SceneError;
use towride_mbs::input::{InputError, Loader, Source};
use towride_mbs::input::{Origin, Override};
use towride_mbs::path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    sweep: Head,
    #[serde(default)]
    parameter: Vec<ParamIn>,
    usage: Option<usage::UsageIn>,
    robustness: Option<robust::RobustnessIn>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Head {
    name: String,
    scene: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParamIn {
    name: String,
    file: String,
    path: String,
    values: Vec<toml::Value>,
}

/// One swept parameter.
#[derive(Clone, Debug)]
pub struct Parameter {
    /// Column name in the summary.
    pub name: String,
    /// The file whose value is swept, matched by the end of its path.
    pub file: String,
    /// The value's path in that file.
    pub path: String,
    /// Values as TOML text.
    pub values: Vec<String>,
    /// Where the parameter is written (errors about its file or path point here).
    pub origin: Origin,
    /// Located error template for its `values` (a value of the wrong type points here).
    pub values_at: Box<InputError>,
}

/// A validated sweep.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// Sweep name (from `[sweep]`).
    pub name: String,
    /// The base scene file, resolved next to the sweep file.
    pub scene: PathBuf,
    /// The swept parameters; the cases are their full product.
    pub parameters: Vec<Parameter>,
    /// The caller's overrides (`--set`, `--overrides`), applied to every case under the
    /// case's own: a sweep value and a `--set` of the same value are refused as set twice.
    pub base: Loader,
    /// The record each case's run starts from (version, commit, command line: the
    /// binary fills them in); the case's overrides are added to it.
    pub produced_by: ProducedBy,
    /// The usage spectrum of `[usage]`, for damage per km ([`usage::per_km`]).
    pub usage: Option<usage::Usage>,
    /// The `[robustness]` block: values to move and the grid to re-run
    /// ([`robust_run`]).
    pub robustness: Option<robust::Robustness>,
}

/// One case: its index and the values it sets.
#[derive(Clone, Debug)]
pub struct Case {
    /// Position in the product (0-based).
    pub index: usize,
    /// The parameter values of this case, as TOML text, in parameter order.
    pub values: Vec<String>,
    /// The overrides that set them.
    pub overrides: Vec<Override>,
}

impl Sweep {
    /// Reads and checks a sweep file.
    pub fn load(path: &Path) -> Result<Sweep, InputError> {
        let src = Source::read(path)?;
        let f: SweepFile = src.parse()?;
        let base = path.parent().unwrap_or(Path::new("."));
        let scene = base.join(&f.sweep.scene);
        if !scene.exists() {
            return Err(src.error(
                &path!["sweep", "scene"],
                format!("no such file: {}", scene.display()),
            ));
        }
        let mut parameters = Vec::new();
        for (k, p) in f.parameter.iter().enumerate() {
            if p.values.is_empty() {
                return Err(src.error(&path!["parameter", k, "values"], "is empty"));
            }
            if parameters.iter().any(|q: &Parameter| q.name == p.name) {
                return Err(src.error(&path!["parameter", k, "name"], "is used twice"));
            }
            parameters.push(Parameter {
                name: p.name.clone(),
                file: p.file.clone(),
                path: p.path.clone(),
                values: p
                    .values
                    .iter()
                    .map(towride_mbs::input::value_text)
                    .collect(),
                origin: Origin::File {
                    file: Box::new(src.error(&path!["parameter", k, "file"], "")),
                    path: Box::new(src.error(&path!["parameter", k, "path"], "")),
                },
                values_at: Box::new(src.error(&path!["parameter", k, "values"], "")),
            });
        }
        let named: Vec<(String, Vec<String>)> = parameters
            .iter()
            .map(|p| (p.name.clone(), p.values.clone()))
            .collect();
        let usage = f.usage.map(|u| u.check(&src, &named)).transpose()?;
        let robustness = f
            .robustness
            .map(|r| r.check(&src, &scene, &named))
            .transpose()?;
        Ok(Sweep {
            name: f.sweep.name,
            scene,
            parameters,
            base: Loader::new(),
            produced_by: ProducedBy::default(),
            usage,
            robustness,
        })
    }

    /// Number of cases of the full product.
    pub fn len(&self) -> usize {
        self.parameters.iter().map(|p| p.values.len()).product()
    }

    /// True when the product has no case.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Case `index` of the product.
    pub fn case(&self, index: usize) -> Case {
        let mut rest = index;
        let mut values = vec![String::new(); self.parameters.len()];
        for (k, p) in self.parameters.iter().enumerate().rev() {
            values[k] = p.values[rest % p.values.len()].clone();
            rest /= p.values.len();
        }
        let overrides = self
            .parameters
            .iter()
            .zip(&values)
            .map(|(p, v)| Override {
                file: p.file.clone(),
                path: p.path.clone(),
                value: v.clone(),
                origin: p.origin.clone(),
            })
            .collect();
        Case {
            index,
            values,
            overrides,
        }
    }

    /// The cases of shard `i` of `n` (index mod n = i).
    pub fn shard(&self, i: usize, n: usize) -> Vec<Case> {
        (0..self.len())
            .filter(|k| k % n == i)
            .map(|k| self.case(k))
            .collect()
    }
}

/// Parses `I/N` (0 <= I < N).
pub fn parse_shard(s: &str) -> Result<(usize, usize), SceneError> {
    let bad = || SceneError::Shard(format!("--shard wants I/N with 0 <= I < N, got `{s}`"));
    let (a, b) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}
