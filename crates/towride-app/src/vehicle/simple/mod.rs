//! The `simple` vehicle file: a complete vehicle from a compact property file of the
//! numbers a vehicle lab knows (total and axle masses, centre-of-gravity height,
//! wheelbase, tracks, corner springs and damping or ride frequencies and damping ratios,
//! unsprung masses, tyre size and vertical stiffness, an optional trailer likewise).
//!
//! ```toml
//! [vehicle]
//! name = "light van"
//! template = "simple"
//! defaults = "../simple_defaults.toml"   # every value left out comes from here
//!
//! [mass]
//! total_kg = 2250.0
//! front_axle_kg = 1250.0
//! cg_height_m = 0.80
//!
//! [geometry]
//! wheelbase_m = 3.3
//! front_track_m = 1.74
//! rear_track_m = 1.71
//!
//! [front]                                 # per corner
//! unsprung_kg = 55.0
//! spring = { kind = "coil", ride_frequency_hz = 1.25 }   # or wheel_rate_n_m
//! damping_ratio = 0.25                                   # or damping_n_s_m
//! # or damping_compression_n_s_m = 1500.0 and damping_rebound_n_s_m = 4500.0
//!
//! [rear]
//! unsprung_kg = 75.0
//! spring = { kind = "air", effective_area_m2 = 0.0177, volume_m3 = 0.0045 }
//!
//! [tyre]
//! size = "215/65 R16 C"
//! vertical_stiffness_n_m = 3.2e5
//! ```
//!
//! The file is data for the one assembly path: [`describe`] translates it into a
//! [`Description`] whose slots name registered templates with derived data, and
//! [`crate::vehicle::assembly::assemble`] builds it like any assembly file. The body is
//! one lumped rigid body; each axle the `trailing_arm_axle` template, its hardpoints
//! derived from the wheel centre and the defaults' corner geometry ([`corner`]); wheels
//! and tyres the defaults' base `.tir` with size, masses and stiffness replaced
//! ([`tyre`]); the trailer the `lumped_trailer` template on a trailing-arm axle, on a
//! ball fixed on the car body ([`trailer`]); the speed controller's gains from the mass
//! ([`drive`]). Every value taken from the defaults file and every value derived from
//! the file's numbers is listed in [`Assumed`] (the run summary's `scene.assumed`).
//! docs/vehicle.md documents the format.

mod car;
mod corner;
mod defaults;
mod drive;
mod suspension;
mod trailer;
mod tyre;

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use self::corner::AxleSec;
use self::tyre::TyreSec;
use super::description::{Description, DrivelineSpec, HitchSpec};
use super::sensors::SensorSpec;
use super::{assembly, BallCoupling, CrossMember, Options, Vehicle};
use towride_mbs::input::{InputError, Loader, Seg, Source};
use towride_mbs::path;
use towride_mbs::tyre::TyreKind;

pub use super::air::AirSpring;
pub use super::description::{Assumed, Kind};

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    vehicle: Head,
    mass: car::MassSec,
    body: Option<car::BodySec>,
    geometry: car::GeometrySec,
    front: AxleSec,
    rear: AxleSec,
    tyre: TyreSec,
    driveline: Option<drive::DrivelineSec>,
    trailer: Option<trailer::TrailerSec>,
    #[serde(default)]
    sensor: Vec<SensorSpec>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Head {
    name: String,
    template: String,
    defaults: String,
    gravity_m_s2: Option<[f64; 3]>,
    tyre_model: Option<TyreKind>,
}

/// What the translation carries along: the compact file, the defaults, the list of
/// assumed and derived values.
struct Ctx {
    src: Source,
    dir: PathBuf,
    defaults: defaults::Read,
    loader: Loader,
    assumed: RefCell<Vec<Assumed>>,
    /// Gravity's magnitude [m/s^2].
    g: f64,
}

impl Ctx {
    fn note(&self, field: &str, value: f64, unit: &str, kind: Kind, source: String) {
        self.assumed.borrow_mut().push(Assumed {
            field: field.to_string(),
            value,
            unit: unit.to_string(),
            kind,
            source,
        });
    }

    /// A default, noted as assumed for `field`.
    fn default(&self, field: &str, value: f64, unit: &str, key: &str) -> f64 {
        let src = format!("{} ({key})", self.defaults.path.display());
        self.note(field, value, unit, Kind::Assumed, src);
        value
    }

    /// The values noted so far, taken (each part of the description keeps its own).
    fn take_notes(&self) -> Vec<Assumed> {
        std::mem::take(&mut self.assumed.borrow_mut())
    }

    fn defaults_dir(&self) -> PathBuf {
        self.defaults
            .path
            .parent()
            .unwrap_or(Path::new("."))
            .to_path_buf()
    }
}

fn at(p: &[Seg], k: &str) -> Vec<Seg> {
    super::props::at(p, k)
}

/// True when `path` is a compact vehicle file (`[vehicle] template = "simple"`).
pub fn is_simple(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|t| {
            t.get("vehicle")
                .and_then(|v| v.get("template"))
                .and_then(|s| s.as_str().map(|s| s == "simple"))
        })
        .unwrap_or(false)
}

/// Reads the compact vehicle file `path` and builds the vehicle, every file read through
/// `loader`.
pub fn load(path: &Path, opts: &Options, loader: &Loader) -> Result<Vehicle, InputError> {
    assembly::assemble(describe(path, opts, loader)?, opts, loader)
}

/// Reads the compact vehicle file `path` (with the choices of `opts`) and translates it
/// into the description of the vehicle it stands for.
pub(crate) fn describe(
    path: &Path,
    opts: &Options,
    loader: &Loader,
) -> Result<Description, InputError> {
    let src = loader.toml(path)?;
    let f: File = src.parse()?;
    if f.vehicle.template != "simple" {
        return Err(src.error(&path!["vehicle", "template"], "this reader takes `simple`"));
    }
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let dpath = dir.join(&f.vehicle.defaults);
    if !dpath.is_file() {
        return Err(src.error(
            &path!["vehicle", "defaults"],
            towride_mbs::input::no_file(&dpath),
        ));
    }
    let defaults = defaults::read(&dpath, loader)?;
    let mut ctx = Ctx {
        src,
        dir,
        defaults,
        loader: loader.clone(),
        assumed: Default::default(),
        g: 0.0,
    };
    // The simple set's axles and hitch have one variant each.
    let cross_member = opts.rear_cross_member.filter(|k| *k != CrossMember::Rigid);
    let ball = opts.ball_coupling.filter(|k| *k != BallCoupling::Spherical);
    for (k, v) in [
        ("rear_cross_member", cross_member.map(|k| k.to_string())),
        ("ball_coupling", ball.map(|k| k.to_string())),
    ] {
        if let Some(v) = v {
            return Err(ctx.src.error(
                &path!["vehicle", "template"],
                format!("the simple template has no {k} '{v}'"),
            ));
        }
    }
    let gravity = match f.vehicle.gravity_m_s2 {
        Some(g) => super::props::point(&ctx.src, &path!["vehicle", "gravity_m_s2"], &g)?,
        None => {
            let g = ctx.defaults.d.vehicle.gravity_m_s2;
            ctx.default(
                "vehicle.gravity_m_s2",
                g[2],
                "m/s^2",
                "vehicle.gravity_m_s2 (z)",
            );
            g
        }
    };
    ctx.g = super::geom::norm(&gravity);
    if ctx.g == 0.0 {
        return Err(ctx.src.error(
            &path!["vehicle", "gravity_m_s2"],
            "gravity must not be zero (it sets the design loads)",
        ));
    }
    let kind = match (opts.tyre_kind, f.vehicle.tyre_model) {
        (Some(k), _) | (None, Some(k)) => k,
        (None, None) => {
            ctx.note(
                "vehicle.tyre_model",
                f64::NAN,
                "",
                Kind::Assumed,
                format!(
                    "{:?} ({} vehicle.tyre_model)",
                    ctx.defaults.d.vehicle.tyre_model,
                    ctx.defaults.path.display()
                ),
            );
            ctx.defaults.d.vehicle.tyre_model
        }
    };
    let car = car::translate(&ctx, &f, kind)?;
    let car_notes = ctx.take_notes();
    let towed = match &f.trailer {
        Some(t) => Some(trailer::translate(&ctx, t, car.wheelbase_m, opts, kind)?),
        None => None,
    };
    let trailer_notes = ctx.take_notes();
    // The speed controller holds the car with its trailer: the gains follow the sum.
    let driven_kg = match &towed {
        Some(t) => car.total_kg + t.mass_kg,
        None => car.total_kg,
    };
    let gains = drive::gains(&ctx, &f, driven_kg, car.rear_radius_m)?;
    let driveline = DrivelineSpec::Given {
        gains,
        assumed: ctx.take_notes(),
    };
    let sensors = vec![
        (
            path!["vehicle"].to_vec(),
            drive::standard_sensors(&car, towed.as_ref().map(|t| t.wheel_centre)),
        ),
        (path!["sensor"].to_vec(), f.sensor),
    ];
    let (hitch, trailer) = match towed {
        Some(t) => {
            let mut desc = t.desc;
            desc.assumed = trailer_notes;
            (Some(HitchSpec::Ball(t.ball)), Some(desc))
        }
        None => (None, None),
    };
    Ok(Description {
        src: ctx.src,
        name: f.vehicle.name,
        gravity,
        tyre_kind: kind,
        body: car.body,
        engine: None,
        axles: car.axles,
        driveline,
        hitch,
        trailer,
        sensors,
        assumed: car_notes,
    })
}
