//! The `assumed` values among the inputs a scene's key output is most sensitive to: the
//! ranking of a finished sensitivity study ([`super::write`]'s `sensitivity.json`) and
//! the source classes written beside the values ([`towride_mbs::input::provenance`]). No study
//! is run here: without one the answer says so.

use std::path::Path;

use serde::Serialize;

use towride_mbs::input::provenance::{read_provenance, SourceClass};
use towride_mbs::input::Loader;

/// One sensitive input without a better source than an assumption.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SensitiveInput {
    /// Rank by the output's sensitivity (1: most sensitive).
    pub rank: usize,
    /// `FILE:PATH`.
    pub parameter: String,
    /// |elasticity| (OAT) or mu* / base output (Morris).
    pub sensitivity: f64,
    /// `assumed`, or `untagged` when the value carries no source class.
    pub class: String,
    /// The source text beside the value.
    pub source: String,
}

/// What a run can say about its assumed inputs.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct AssumedInputs {
    /// The study read, `None` when there is none.
    pub study: Option<String>,
    /// The output ranked by.
    pub output: Option<String>,
    /// The assumed (or untagged) values among the `top` most sensitive inputs.
    pub inputs: Vec<SensitiveInput>,
    /// Why nothing could be listed, if so.
    pub note: Option<String>,
}

/// The assumed values among the `top` inputs the first output of the study in `dir`
/// ranks highest, for `scene`.
pub fn assumed_inputs(scene: &Path, dir: &Path, top: usize) -> AssumedInputs {
    match ranked(scene, &dir.join("sensitivity.json")) {
        Ok(r) => AssumedInputs {
            study: Some(r.study),
            output: r.output,
            inputs: r
                .inputs
                .into_iter()
                .filter(|i| i.input.rank <= top && i.class != Class::Tagged)
                .map(|i| i.input)
                .collect(),
            note: None,
        },
        Err(note) => AssumedInputs {
            study: None,
            output: None,
            inputs: Vec::new(),
            note: Some(note),
        },
    }
}

/// A ranked input's source class, as far as a ranking of assumed values cares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Class {
    /// Tagged `assumed`.
    Assumed,
    /// No source class.
    Untagged,
    /// Measured, published or scaled.
    Tagged,
}

/// One input of a study's ranking with its class and the study's range for it.
#[derive(Clone, Debug)]
pub struct RankedInput {
    /// Rank, name, sensitivity, class text and source text.
    pub input: SensitiveInput,
    /// Its class.
    pub class: Class,
    /// The study's scale factors [low, high] for it (Morris's range; an OAT study
    /// records the range it would have used).
    pub range: Option<[f64; 2]>,
}

/// A study's full ranking by its first output.
#[derive(Clone, Debug)]
pub struct Ranked {
    /// The study file.
    pub study: String,
    /// The output ranked by.
    pub output: Option<String>,
    /// Every parameter whose file the scene reads, most sensitive first.
    pub inputs: Vec<RankedInput>,
}

/// Every parameter of the study `path` (a `sensitivity.json`) of `scene`, ranked by
/// the study's first output (|elasticity| for OAT, mu* / base for Morris) with its
/// source class; `Err`: why there is no ranking (no study, another scene's).
pub fn ranked(scene: &Path, path: &Path) -> Result<Ranked, String> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Err(format!(
            "no sensitivity study of this scene in {} (`towride sensitivity {}` makes one)",
            path.parent().unwrap_or(Path::new(".")).display(),
            scene.display()
        ));
    };
    let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Err(format!("{} is not a sensitivity study", path.display()));
    };
    // A study of another scene (an older layout keyed studies by the scene's stem) says
    // nothing about this one's inputs.
    if let Some(of) = v["file"]
        .as_str()
        .filter(|f| !same_file(Path::new(f), scene))
    {
        return Err(format!(
            "the study in {} is of another scene ({of}): `towride sensitivity {}` makes \
             one of this scene",
            path.display(),
            scene.display()
        ));
    }
    let morris = v["method"] == "morris";
    let score = |p: &serde_json::Value| -> f64 {
        let x = if morris {
            p["mu_star_rel"][0].as_f64()
        } else {
            p["elasticity"][0].as_f64()
        };
        x.map_or(-1.0, f64::abs)
    };
    let mut params: Vec<&serde_json::Value> = v["params"]
        .as_array()
        .map(|a| a.iter().collect())
        .unwrap_or_default();
    params.sort_by(|a, b| score(b).total_cmp(&score(a)));
    // The files this scene reads, to find each parameter's file.
    let loader = Loader::new();
    let _ = crate::scene::load_with(scene, &crate::scene::Changes::default(), &loader);
    let files = loader.files_read();
    let mut inputs = Vec::new();
    for (i, p) in params.iter().enumerate() {
        let (file, key) = (
            p["param"]["file"].as_str().unwrap_or(""),
            p["param"]["path"].as_str().unwrap_or(""),
        );
        let Some(f) = files.iter().find(|f| f.ends_with(file)) else {
            continue;
        };
        let mut entries = read_provenance(f).unwrap_or_default();
        entries.extend(towride_mbs::tyre::factors::provenance(&entries));
        let (class, text, source) = match entries.iter().find(|e| e.key == key) {
            Some(e) if e.class == SourceClass::Assumed => {
                (Class::Assumed, "assumed", e.source.clone())
            }
            Some(e) => (Class::Tagged, e.class.as_str(), e.source.clone()),
            None => (Class::Untagged, "untagged", String::new()),
        };
        let range = match (p["range"][0].as_f64(), p["range"][1].as_f64()) {
            (Some(lo), Some(hi)) => Some([lo, hi]),
            _ => None,
        };
        inputs.push(RankedInput {
            input: SensitiveInput {
                rank: i + 1,
                parameter: p["param"]["name"].as_str().unwrap_or("").to_string(),
                sensitivity: score(p),
                class: text.into(),
                source,
            },
            class,
            range,
        });
    }
    Ok(Ranked {
        study: path.display().to_string(),
        output: v["outputs"][0]["name"].as_str().map(String::from),
        inputs,
    })
}

/// True when `a` and `b` name one file (by where they are, or by their normalised text
/// when one cannot be found).
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => towride_mbs::input::normalized(a) == towride_mbs::input::normalized(b),
    }
}
