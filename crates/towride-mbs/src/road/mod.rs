//! Roads and obstacles: the surface z = h(x, y) a tyre rolls on.
//!
//! World axes: x along the road (direction of travel), y to the left, z up; x = 0 is where
//! the front wheels touch the road at the start of a scene. A [`Road`] is one of
//!
//! - a flat road at a given height, optionally carrying obstacles: trapezoidal ramps,
//!   circular-segment bumps, speed humps whose shape blends round-top into flat-top
//!   ([`hump`]) and steps (`[[obstacle]]` in the TOML file, see [`obstacle`]);
//! - a longitudinal profile per track (left and right) read from CSV (see [`profile`]);
//! - a 3D road: a height field on a regular grid, triangulated and queried through
//!   `parry3d-f64` (see [`mesh`]);
//! - an ISO 8608 random road: two seeded tracks built as a profile (see [`random`]);
//! - an OpenCRG grid from a text `.crg` file (see [`crg`]).
//!
//! Queries: [`Road::height`], [`Road::slope`], [`Road::flat_height`] / [`Road::is_flat`]
//! (a cheap "is there anything here" test so a scene can skip contact work), and
//! [`Road::kinks_along`], the places along a line where the surface is not smooth (edges of
//! obstacles, nodes of a profile, grid lines of a mesh). The tyre's enveloping model
//! maximises a smooth function piece by piece between those places, which makes its
//! result continuous in the wheel position (see `crate::tyre::envelope`).
//!
//! Heights are right-continuous in x: at a vertical face (a step, a 90 deg ramp flank) the
//! height at the face is the value just after it. The file format and the ramp convention
//! are documented in `docs/road_tyre.md`.

pub mod crg;
pub mod hump;
pub(crate) mod mesh;
pub(crate) mod obstacle;
pub(crate) mod profile;
pub mod random;

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::input::{InputError, Source};
use crate::path;

pub use hump::Hump;
pub use mesh::HeightField;
pub use obstacle::Obstacle;
pub use profile::{Piece, TrackProfile};
pub use random::RandomSpec;

/// A road surface.
#[derive(Clone, Debug)]
pub struct Road {
    kind: Kind,
    /// The file it came from (for messages), if any.
    pub source: Option<PathBuf>,
}

#[derive(Clone, Debug)]
enum Kind {
    Flat {
        height: f64,
        obstacles: Vec<Obstacle>,
    },
    Profile(TrackProfile),
    Mesh(Box<HeightField>),
    /// An OpenCRG grid (see [`crg`]).
    Crg(Box<crg::CrgGrid>),
    /// A random road: its spec and the profile built from it.
    Random(Box<(RandomSpec, TrackProfile)>),
}

/// A road that cannot be built from the values given.
#[derive(Debug, Clone, thiserror::Error)]
pub enum RoadError {
    /// A bad road file.
    #[error(transparent)]
    Input(#[from] InputError),
    /// Geometry that is not a road (overlapping obstacles, a grid out of order).
    #[error("{0}")]
    Geometry(String),
}

/// The TOML file: `[road]` plus, for a flat road, any number of `[[obstacle]]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RoadFile {
    road: RoadSection,
    #[serde(default)]
    obstacle: Vec<obstacle::ObstacleToml>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
enum RoadSection {
    Flat {
        height_m: f64,
    },
    Profile {
        /// CSV with columns x_m, z_left_m, z_right_m (path relative to the TOML file).
        file: String,
        /// Lateral distance between the left and the right track.
        track_width_m: f64,
        /// Height before the first and after the last profile point.
        #[serde(default)]
        outside_height_m: Option<f64>,
    },
    HeightField {
        /// CSV with columns x_m, y_m, z_m on a regular grid (path relative to the TOML).
        file: String,
    },
    /// ISO 8608 random road (see [`random`]).
    Random(random::RandomToml),
    /// OpenCRG text file (path relative to the TOML; see [`crg`]).
    Crg {
        file: String,
    },
}

impl Road {
    /// A flat road at height `height` [m].
    pub fn flat(height: f64) -> Road {
        Road {
            kind: Kind::Flat {
                height,
                obstacles: Vec::new(),
            },
            source: None,
        }
    }

    /// A flat road at `height` carrying `obstacles` (their `base` should be `height`);
    /// refuses overlapping obstacles.
    pub fn with_obstacles(height: f64, obstacles: Vec<Obstacle>) -> Result<Road, RoadError> {
        for i in 0..obstacles.len() {
            for j in 0..i {
                if obstacle::overlap(&obstacles[i], &obstacles[j]) {
                    return Err(RoadError::Geometry(format!(
                        "obstacle {i} overlaps obstacle {j}"
                    )));
                }
            }
        }
        Ok(Road {
            kind: Kind::Flat { height, obstacles },
            source: None,
        })
    }

    /// A two-track profile road.
    pub fn from_profile(p: TrackProfile) -> Road {
        Road {
            kind: Kind::Profile(p),
            source: None,
        }
    }

    /// A height-field road.
    pub fn from_height_field(h: HeightField) -> Road {
        Road {
            kind: Kind::Mesh(Box::new(h)),
            source: None,
        }
    }

    /// Reads a road TOML file (see `docs/road_tyre.md`).
    pub fn from_file(path: &Path, loader: &crate::input::Loader) -> Result<Road, InputError> {
        let src = loader.toml(path)?;
        Road::from_source(&src, loader)
    }

    /// Builds the road from an already read TOML source.
    pub fn from_source(src: &Source, loader: &crate::input::Loader) -> Result<Road, InputError> {
        let f: RoadFile = src.parse()?;
        let kind = match f.road {
            RoadSection::Flat { height_m } => {
                src.finite(&path!["road", "height_m"], height_m)?;
                let mut obstacles = Vec::with_capacity(f.obstacle.len());
                for (i, o) in f.obstacle.iter().enumerate() {
                    obstacles.push(o.build(src, i, height_m)?);
                }
                obstacle::check_overlaps(src, &obstacles)?;
                Kind::Flat {
                    height: height_m,
                    obstacles,
                }
            }
            RoadSection::Profile {
                file,
                track_width_m,
                outside_height_m,
            } => {
                if !f.obstacle.is_empty() {
                    return Err(src.error(
                        &path!["obstacle"],
                        "obstacles are only allowed on a flat road",
                    ));
                }
                src.positive(&path!["road", "track_width_m"], track_width_m)?;
                if let Some(h) = outside_height_m {
                    src.finite(&path!["road", "outside_height_m"], h)?;
                }
                let csv = src.existing_file(&path!["road", "file"], &file)?;
                Kind::Profile(TrackProfile::from_csv(
                    &csv,
                    track_width_m,
                    outside_height_m,
                    loader,
                )?)
            }
            RoadSection::HeightField { file } => {
                if !f.obstacle.is_empty() {
                    return Err(src.error(
                        &path!["obstacle"],
                        "obstacles are only allowed on a flat road",
                    ));
                }
                let csv = src.existing_file(&path!["road", "file"], &file)?;
                Kind::Mesh(Box::new(HeightField::from_csv(&csv, loader)?))
            }
            RoadSection::Crg { file } => {
                if !f.obstacle.is_empty() {
                    return Err(src.error(
                        &path!["obstacle"],
                        "obstacles are only allowed on a flat road",
                    ));
                }
                let crg = src.existing_file(&path!["road", "file"], &file)?;
                let g =
                    crg::CrgGrid::read(&crg).map_err(|m| src.error(&path!["road", "file"], m))?;
                Kind::Crg(Box::new(g))
            }
            RoadSection::Random(r) => {
                if !f.obstacle.is_empty() {
                    return Err(src.error(
                        &path!["obstacle"],
                        "obstacles are only allowed on a flat road",
                    ));
                }
                let spec = r.build(src)?;
                let p = spec
                    .profile()
                    .map_err(|e| src.error(&path!["road", "length_m"], e.to_string()))?;
                Kind::Random(Box::new((spec, p)))
            }
        };
        Ok(Road {
            kind,
            source: Some(src.path.clone()),
        })
    }

    /// Road height z [m] at (x, y).
    pub fn height(&self, x: f64, y: f64) -> f64 {
        match &self.kind {
            Kind::Flat { height, obstacles } => {
                // Obstacles do not overlap (checked on reading): the one covering (x, y)
                // decides.
                obstacles
                    .iter()
                    .find_map(|o| o.height(x, y))
                    .unwrap_or(*height)
            }
            Kind::Profile(p) => p.height(x, y),
            Kind::Random(r) => r.1.height(x, y),
            Kind::Crg(g) => g.height(x, y),
            Kind::Mesh(m) => m.height(x, y),
        }
    }

    /// Surface gradient (dz/dx, dz/dy) at (x, y); one-sided (from the right in x) at
    /// edges.
    pub fn slope(&self, x: f64, y: f64) -> (f64, f64) {
        match &self.kind {
            Kind::Flat { height, obstacles } => {
                let _ = height;
                obstacles
                    .iter()
                    .find(|o| o.height(x, y).is_some())
                    .map_or((0.0, 0.0), |o| o.slope(x, y))
            }
            Kind::Profile(p) => p.slope(x, y),
            Kind::Random(r) => r.1.slope(x, y),
            Kind::Crg(g) => g.slope(x, y),
            Kind::Mesh(m) => m.slope(x, y),
        }
    }

    /// `Some(z)` when the road is flat at height z over the rectangle
    /// [x0, x1] x [y0, y1], else `None`. Cheap: a scene calls it to skip contact work.
    pub fn flat_height(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> Option<f64> {
        let (x0, x1) = (x0.min(x1), x0.max(x1));
        let (y0, y1) = (y0.min(y1), y0.max(y1));
        match &self.kind {
            Kind::Flat { height, obstacles } => {
                if obstacles.iter().all(|o| !o.overlaps(x0, x1, y0, y1)) {
                    Some(*height)
                } else {
                    None
                }
            }
            Kind::Profile(p) => p.flat_height(x0, x1, y0, y1),
            Kind::Random(r) => r.1.flat_height(x0, x1, y0, y1),
            // A measured surface: never skip the contact work.
            Kind::Crg(_) => None,
            Kind::Mesh(m) => m.flat_height(x0, x1, y0, y1),
        }
    }

    /// True when the road along the line y = const is flat over [x0, x1].
    pub fn is_flat(&self, x0: f64, x1: f64, y: f64) -> bool {
        self.flat_height(x0, x1, y, y).is_some()
    }

    /// Appends to `out` the parameters s in [s0, s1] at which the surface along the
    /// horizontal line (x, y) = p + s d (d a unit vector) has a kink or a jump. Between
    /// two such places the height along the line is smooth and concave or linear for every
    /// road type here (flat pieces, flanks, circular caps, linear profile and mesh pieces),
    /// which the enveloping model relies on.
    pub fn kinks_along(&self, p: [f64; 2], d: [f64; 2], s0: f64, s1: f64, out: &mut Vec<f64>) {
        let from = out.len();
        match &self.kind {
            Kind::Flat { obstacles, .. } => {
                for o in obstacles {
                    o.kinks_along(p, d, s0, s1, out);
                }
            }
            Kind::Profile(pr) => pr.kinks_along(p, d, s0, s1, out),
            Kind::Random(r) => r.1.kinks_along(p, d, s0, s1, out),
            Kind::Crg(g) => g.kinks_along(p, d, s0, s1, out),
            Kind::Mesh(m) => m.kinks_along(p, d, s0, s1, out),
        }
        out[from..].sort_by(f64::total_cmp);
    }

    /// The road along p + s d, s in [s0, s1], as exact quadratic pieces between its kinks
    /// (see [`TrackProfile::pieces_along`]); `false` (and `out` empty) for a road whose
    /// pieces are not polynomials (obstacles, meshes, CRG grids), which callers search.
    pub fn pieces_along(
        &self,
        p: [f64; 2],
        d: [f64; 2],
        s0: f64,
        s1: f64,
        kinks: &mut Vec<f64>,
        out: &mut Vec<Piece>,
    ) -> bool {
        let pr = match &self.kind {
            Kind::Profile(pr) => pr,
            Kind::Random(r) => &r.1,
            _ => {
                out.clear();
                return false;
            }
        };
        kinks.clear();
        self.kinks_along(p, d, s0, s1, kinks);
        pr.pieces_along(p, d, s0, s1, kinks, out);
        true
    }

    /// A short description for logs and reports.
    pub fn describe(&self) -> String {
        match &self.kind {
            Kind::Flat { height, obstacles } => {
                if obstacles.is_empty() {
                    format!("flat road at z = {height} m")
                } else {
                    let list: Vec<String> = obstacles.iter().map(|o| o.describe()).collect();
                    format!("flat road at z = {height} m with {}", list.join(", "))
                }
            }
            Kind::Profile(p) => p.describe(),
            Kind::Random(r) => format!(
                "ISO 8608 random road ({}, Gd(n0) = {:e} m^3, w = {}), {} m at {} m, seed {}",
                r.0.class
                    .map_or("no class".to_string(), |c| format!("class {c}")),
                r.0.gd_n0,
                r.0.waviness,
                r.0.length,
                r.0.dx,
                r.0.seed
            ),
            Kind::Mesh(m) => m.describe(),
            Kind::Crg(g) => g.describe(),
        }
    }

    /// The spec of a random road, else `None`.
    pub fn random_spec(&self) -> Option<&RandomSpec> {
        match &self.kind {
            Kind::Random(r) => Some(&r.0),
            _ => None,
        }
    }

    /// Lateral distance of the two tracks of a profile or random road, else `None`.
    pub fn track_width(&self) -> Option<f64> {
        match &self.kind {
            Kind::Profile(p) => Some(p.track_width()),
            Kind::Random(r) => Some(r.1.track_width()),
            _ => None,
        }
    }

    /// The x range the road's data cover (profile, random, height field), else `None`.
    pub fn x_extent(&self) -> Option<(f64, f64)> {
        match &self.kind {
            Kind::Profile(p) => Some(p.x_range()),
            Kind::Random(r) => Some(r.1.x_range()),
            Kind::Mesh(m) => Some(m.x_range()),
            Kind::Crg(g) => Some(g.x_range()),
            Kind::Flat { obstacles, .. } => {
                let ends = obstacles.iter().map(|o| o.x_range());
                let lo = ends.clone().map(|e| e.0).fold(f64::INFINITY, f64::min);
                let hi = ends
                    .map(|e| e.1)
                    .filter(|v| v.is_finite())
                    .fold(lo, f64::max);
                lo.is_finite().then_some((lo, hi))
            }
        }
    }
}

/// Appends s where the line p + s d crosses x = xk, for s in [s0, s1].
pub(crate) fn push_x_crossing(
    p: [f64; 2],
    d: [f64; 2],
    xk: f64,
    s0: f64,
    s1: f64,
    out: &mut Vec<f64>,
) {
    if d[0].abs() < 1e-12 {
        return;
    }
    let s = (xk - p[0]) / d[0];
    if s >= s0 && s <= s1 {
        out.push(s);
    }
}

/// Appends s where the line p + s d crosses y = yk, for s in [s0, s1].
pub(crate) fn push_y_crossing(
    p: [f64; 2],
    d: [f64; 2],
    yk: f64,
    s0: f64,
    s1: f64,
    out: &mut Vec<f64>,
) {
    if d[1].abs() < 1e-12 {
        return;
    }
    let s = (yk - p[1]) / d[1];
    if s >= s0 && s <= s1 {
        out.push(s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_road_is_flat_everywhere() {
        let r = Road::flat(0.1);
        assert_eq!(r.height(3.0, -2.0), 0.1);
        assert_eq!(r.flat_height(-1.0, 5.0, -1.0, 1.0), Some(0.1));
        let mut k = Vec::new();
        r.kinks_along([0.0, 0.0], [1.0, 0.0], -1.0, 1.0, &mut k);
        assert!(k.is_empty());
    }
}
