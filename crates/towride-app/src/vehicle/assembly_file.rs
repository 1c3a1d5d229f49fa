//! The assembly file: which templates and property files make a vehicle, and its
//! sensors, read into a [`Description`].
//!
//! ```toml
//! [vehicle]
//! name = "Fabia 1.4 MPI with a box trailer"
//! gravity_m_s2 = [0.0, 0.0, -9.81]
//! tyre_model = "rigid-ring"                  # or "point-follower"
//!
//! [car]
//! body = { template = "lumped_body", file = "fabia/body.toml" }
//! engine = { template = "engine_on_mounts", file = "fabia/engine.toml" }     # optional
//! front = { template = "mcpherson", file = "fabia/front_mcpherson.toml", tyre = "tyres/car_185_60r14.tir" }
//! rear = { template = "twist_beam", file = "fabia/rear_twist_beam.toml", tyre = "tyres/car_185_60r14.tir" }
//! driveline = { template = "speed_control", file = "fabia/driveline.toml" }
//! hitch = { template = "modal_hitch", file = "fabia/hitch.toml" }          # optional
//!
//! [trailer]                                                                # optional
//! template = "box_trailer"
//! file = "trailer/box_trailer.toml"
//! tyre = "tyres/trailer_155_80r13.tir"
//! load_case = "empty"
//!
//! [[sensor]]
//! name = "wheel_front_left"
//! body = "knuckle_fl"
//! position_m = [0.0, 0.7175, 0.273]
//! axes = ["z"]
//! ```
//!
//! Paths are relative to the assembly file. The axle slots take any registered axle
//! template ([`super::axle`]), the trailer any registered trailer template
//! ([`super::trailer`]); the other slots have one template each.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::description::{
    AxleDesc, BodySpec, Description, DrivelineSpec, HitchSpec, TrailerDesc, TyreSpec,
};
use super::props::at;
use super::sensors::SensorSpec;
use super::{axle, trailer, Options};
use towride_mbs::input::{InputError, Loader, Seg, Source};
use towride_mbs::path;
use towride_mbs::tyre::TyreKind;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    vehicle: VehicleSec,
    car: Car,
    trailer: Option<Part>,
    #[serde(default)]
    sensor: Vec<SensorSpec>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct VehicleSec {
    name: String,
    gravity_m_s2: [f64; 3],
    #[serde(default)]
    tyre_model: TyreKind,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Car {
    body: Part,
    /// The engine on its mounts (`engine_on_mounts`); without it the body file holds
    /// the engine's mass.
    engine: Option<Part>,
    front: Part,
    rear: Part,
    driveline: Part,
    hitch: Option<Part>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Part {
    template: String,
    file: String,
    tyre: Option<String>,
    /// Trailer only.
    load_case: Option<String>,
}

/// A part's file, checked: template name, existence.
fn part(
    src: &Source,
    dir: &Path,
    p: &[Seg],
    part: &Part,
    template: &str,
) -> Result<PathBuf, InputError> {
    if part.template != template {
        return Err(src.error(
            &at(p, "template"),
            format!(
                "'{}': this slot takes the template '{template}'",
                part.template
            ),
        ));
    }
    let f = dir.join(&part.file);
    if !f.is_file() {
        return Err(src.error(&at(p, "file"), towride_mbs::input::no_file(&f)));
    }
    Ok(f)
}

/// A part's `.tir` file, checked for existence.
fn tyre(src: &Source, dir: &Path, p: &[Seg], part: &Part) -> Result<TyreSpec, InputError> {
    let at = at(p, "tyre");
    let t = part
        .tyre
        .as_ref()
        .ok_or_else(|| src.error(&at, "name the tyre's .tir file"))?;
    let f = dir.join(t);
    if !f.is_file() {
        return Err(src.error(&at, towride_mbs::input::no_file(&f)));
    }
    Ok(TyreSpec::File(f))
}

/// Reads the assembly file `path` (through `loader`) into a description; `opts` choose
/// the tyre model over the file's.
pub fn describe(path: &Path, opts: &Options, loader: &Loader) -> Result<Description, InputError> {
    let src = loader.toml(path)?;
    let f: File = src.parse()?;
    let dir = path.parent().unwrap_or(Path::new("."));
    for (c, g) in f.vehicle.gravity_m_s2.iter().enumerate() {
        src.finite(&path!["vehicle", "gravity_m_s2", c], *g)?;
    }
    if super::geom::norm(&f.vehicle.gravity_m_s2) == 0.0 {
        return Err(src.error(
            &path!["vehicle", "gravity_m_s2"],
            "gravity must not be zero (it sets the design loads)",
        ));
    }
    let c = &f.car;
    let axle = |p: Vec<Seg>, a: &Part| {
        Ok::<_, InputError>(AxleDesc {
            spec: axle::spec(&src, &p, &a.template, dir, &a.file)?,
            tyre: tyre(&src, dir, &p, a)?,
        })
    };
    let axles = [
        axle(path!["car", "front"].to_vec(), &c.front)?,
        axle(path!["car", "rear"].to_vec(), &c.rear)?,
    ];
    let body = part(&src, dir, &path!["car", "body"], &c.body, "lumped_body")?;
    let engine = match &c.engine {
        Some(e) => Some(part(
            &src,
            dir,
            &path!["car", "engine"],
            e,
            "engine_on_mounts",
        )?),
        None => None,
    };
    let driveline = part(
        &src,
        dir,
        &path!["car", "driveline"],
        &c.driveline,
        "speed_control",
    )?;
    let hitch = match &c.hitch {
        Some(h) => Some(HitchSpec::Modal(part(
            &src,
            dir,
            &path!["car", "hitch"],
            h,
            "modal_hitch",
        )?)),
        None => None,
    };
    let trailer = match &f.trailer {
        Some(t) => {
            let tp = path!["trailer"];
            let template = trailer::template(&t.template).ok_or_else(|| {
                src.error(
                    &at(&tp, "template"),
                    format!(
                        "'{}': the trailer takes one of the trailer templates ({})",
                        t.template,
                        trailer::names().join(", ")
                    ),
                )
            })?;
            let file = dir.join(&t.file);
            if !file.is_file() {
                return Err(src.error(&at(&tp, "file"), format!("no file {}", file.display())));
            }
            Some(TrailerDesc {
                spec: trailer::TrailerSpec::File {
                    template,
                    file,
                    load_case: t.load_case.clone(),
                },
                tyre: tyre(&src, dir, &tp, t)?,
                at: tp.to_vec(),
                assumed: Vec::new(),
            })
        }
        None => None,
    };
    Ok(Description {
        name: f.vehicle.name,
        gravity: f.vehicle.gravity_m_s2,
        tyre_kind: opts.tyre_kind.unwrap_or(f.vehicle.tyre_model),
        body: BodySpec::File(body),
        engine,
        axles,
        driveline: DrivelineSpec::File(driveline),
        hitch,
        trailer,
        sensors: vec![(path!["sensor"].to_vec(), f.sensor)],
        assumed: Vec::new(),
        src,
    })
}
