//! The obstacle geometry a validated run's scene assumes: the road file's obstacle values
//! (with the command line's `--set` applied), each with the source class and comment the
//! file tags it with (`towride provenance`), and which of them are assumed. A comparison
//! with a recording is only as good as the obstacle it drives over: a report that hides
//! an assumed chord or shape invites reading a geometry error as a vehicle error.

use std::path::{Path, PathBuf};

use serde::Serialize;

use towride_mbs::input::provenance::{read_provenance, SourceClass};
use towride_mbs::input::{normalized, Loader};
use towride_mbs::road::Road;

/// The keys of an `[[obstacle]]` that make its shape (not where it lies).
const SHAPE_KEYS: [&str; 6] = [
    "height_m",
    "depth_m",
    "length_m",
    "chord_m",
    "shape",
    "flank_angle_deg",
];

/// One geometric value of an obstacle.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct GeometryValue {
    /// Dotted path in the road file (`obstacle[0].height_m`).
    pub key: String,
    /// The value used (after `--set`).
    pub value: f64,
    /// The file's source class (`None`: untagged).
    pub class: Option<SourceClass>,
    /// The file's comment after the class: citation, rule or reasoning.
    pub source: String,
    /// Changed on the command line (`--set`): the file's class no longer describes it.
    pub set: bool,
}

/// The obstacles of the scene's road.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ObstacleGeometry {
    /// The road file.
    pub road_file: PathBuf,
    /// The road as the model reads it (`Road::describe`).
    pub description: String,
    /// The shape values of every obstacle, in file order.
    pub values: Vec<GeometryValue>,
    /// Keys of the values that are assumed (class `assumed`, or untagged).
    pub assumed: Vec<String>,
}

/// The road file of `scene` (`[road] file`, relative to the scene), or `scene` itself
/// when it is not a scene file (a road file, as the pipeline's test simulators take).
pub fn road_file(scene: &Path) -> Option<PathBuf> {
    let t: toml::Table = std::fs::read_to_string(scene).ok()?.parse().ok()?;
    if !t.contains_key("scene") {
        return t.contains_key("road").then(|| scene.to_path_buf());
    }
    let f = t.get("road")?.get("file")?.as_str()?;
    Some(normalized(
        &scene.parent().unwrap_or(Path::new(".")).join(f),
    ))
}

/// `obstacle.0.height_m` and `obstacle[0].height_m` alike.
fn normalised(key: &str) -> String {
    key.replace('[', ".").replace(']', "").trim().to_string()
}

/// The geometry `scene` assumes, read through `loader`; `None` when its road cannot be
/// read (the simulation reports why).
pub fn of_scene(scene: &Path, loader: &Loader) -> Option<ObstacleGeometry> {
    let path = road_file(scene)?;
    let road = Road::from_file(&path, loader).ok()?;
    let text = loader.toml_text(&path).ok()?;
    let doc: toml::Table = text.parse().ok()?;
    let tags = read_provenance(&path).unwrap_or_default();
    let set: Vec<String> = loader
        .overrides_of(&path)
        .map(|o| o.iter().map(|o| normalised(&o.path)).collect())
        .unwrap_or_default();
    let mut values = Vec::new();
    let obstacles = doc.get("obstacle").and_then(|o| o.as_array());
    for (i, o) in obstacles.into_iter().flatten().enumerate() {
        for k in SHAPE_KEYS {
            let Some(v) = o
                .get(k)
                .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
            else {
                continue;
            };
            let key = format!("obstacle[{i}].{k}");
            let tag = tags.iter().find(|t| t.key == key);
            values.push(GeometryValue {
                value: v,
                class: tag.map(|t| t.class),
                source: tag.map_or(String::new(), |t| t.source.clone()),
                set: set.contains(&normalised(&key)),
                key,
            });
        }
    }
    let assumed = values
        .iter()
        .filter(|v| !v.set && v.class.is_none_or(|c| c == SourceClass::Assumed))
        .map(|v| v.key.clone())
        .collect();
    Some(ObstacleGeometry {
        road_file: path,
        description: road.describe(),
        values,
        assumed,
    })
}

impl ObstacleGeometry {
    /// Short lines for a page's header: the road, the values with their classes three to
    /// a line, and what is assumed (the last line, when anything is).
    pub fn header_lines(&self) -> Vec<String> {
        let name = self
            .road_file
            .file_name()
            .map_or(String::new(), |f| f.to_string_lossy().to_string());
        let mut out = vec![format!("obstacle ({name}): {}", self.description)];
        let tagged: Vec<String> = self
            .values
            .iter()
            .map(|v| {
                let class = match (v.set, v.class) {
                    (true, _) => "set".to_string(),
                    (false, Some(c)) => c.to_string(),
                    (false, None) => "untagged".to_string(),
                };
                format!("{} {} [{class}]", v.key, v.value)
            })
            .collect();
        for chunk in tagged.chunks(3) {
            out.push(format!("  {}", chunk.join(", ")));
        }
        if !self.assumed.is_empty() {
            out.push(format!(
                "  ASSUMED obstacle geometry: {}",
                self.assumed.join(", ")
            ));
        }
        out
    }

    /// Lines for the text report.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![format!(
            "obstacle geometry ({}): {}",
            self.road_file.display(),
            self.description
        )];
        for v in &self.values {
            let class = match (v.set, v.class) {
                (true, _) => "set on the command line".to_string(),
                (false, Some(c)) => format!("[{c}] {}", v.source),
                (false, None) => "untagged".to_string(),
            };
            out.push(format!("  {} = {}  {class}", v.key, v.value));
        }
        if !self.assumed.is_empty() {
            out.push(format!(
                "  ASSUMED geometry: {} (not measured or published: a mismatch may be the obstacle's)",
                self.assumed.join(", ")
            ));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use towride_mbs::input::Override;

    const SCENE: &str = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/van_air/bump_50mm.toml"
    );

    #[test]
    fn the_bump_s_chord_is_flagged_assumed_until_set() {
        let g = of_scene(Path::new(SCENE), &Loader::new()).unwrap();
        assert!(g.road_file.ends_with("roads/bump_50mm.toml"));
        let keys: Vec<(&str, f64, Option<SourceClass>)> = g
            .values
            .iter()
            .map(|v| (v.key.as_str(), v.value, v.class))
            .collect();
        assert_eq!(
            keys,
            [
                ("obstacle[0].height_m", 0.05, Some(SourceClass::Published)),
                ("obstacle[0].chord_m", 0.5, Some(SourceClass::Assumed)),
            ]
        );
        assert_eq!(g.assumed, ["obstacle[0].chord_m"]);
        assert!(g.header_lines().last().unwrap().contains("ASSUMED"));
        // A chord set on the command line is the caller's, not the file's assumption.
        let set = Override::from_argument("bump_50mm.toml:obstacle[0].chord_m=0.6").unwrap();
        let g = of_scene(Path::new(SCENE), &Loader::with_overrides(vec![set])).unwrap();
        assert!(g.assumed.is_empty(), "{:?}", g.assumed);
        assert_eq!(g.values[1].value, 0.6);
        assert!(g.values[1].set);
        assert!(g.description.contains("1.000..1.600"), "{}", g.description);
    }
}
