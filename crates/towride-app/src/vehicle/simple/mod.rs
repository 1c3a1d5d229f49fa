//! The `simple` template set: a complete vehicle from a compact property file of the
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
//! The existing building blocks make the model through the model builder: the body as
//! one lumped rigid body (`lumped_body`), each axle as the trailing-arm layout of the
//! twist-beam and trailer axles ([`corner`]), wheels and tyres ([`tyre`]: the defaults'
//! base `.tir` with size, masses and stiffness replaced), springs preloaded by the design
//! statics ([`crate::vehicle::design`]), air springs by the gas law ([`air`]), the speed
//! controller. Every value taken from the defaults file and every value derived from
//! the file's numbers is listed in [`Assumed`] (the run summary's `scene.assumed`).
//! docs/vehicle.md documents the format.

pub mod air;
mod corner;
mod defaults;
mod trailer;
mod tyre;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use self::corner::{AxleInput, SpringChoice};
use self::tyre::TyreSec;
use super::build::Builder;
use super::design::{self, centre_of_mass};
use super::geom::{IDENTITY, V};
use super::props::Mass;
use super::sensors::{self, SensorSpec};
use super::{wheel, Design, Handles, Options, Vehicle};
use towride_mbs::input::{InputError, Loader, Seg, Source};
use towride_mbs::model::builder::{ModelBuilder, Placement};
use towride_mbs::model::desc::SpeedControl;
use towride_mbs::model::function::TimeFunction;
use towride_mbs::path;
use towride_mbs::tyre::TyreKind;

pub use air::AirSpring;

/// A value the compact file did not give or that follows from its numbers.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Assumed {
    /// What it stands for, as a field of the compact file (`front.wheel_mass_kg`).
    pub field: String,
    /// The value (NaN for a choice without a number, such as a file).
    pub value: f64,
    /// Its unit.
    pub unit: String,
    /// `assumed` (from the defaults file) or `derived` (from the file's numbers).
    pub kind: Kind,
    /// Where it comes from.
    pub source: String,
}

/// Whether a value was assumed or derived.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Taken from the defaults file.
    Assumed,
    /// Computed from the compact file's own numbers.
    Derived,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    vehicle: Head,
    mass: MassSec,
    body: Option<BodySec>,
    geometry: GeometrySec,
    front: AxleSec,
    rear: AxleSec,
    tyre: TyreSec,
    driveline: Option<DrivelineSec>,
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

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct MassSec {
    /// With driver [kg].
    total_kg: f64,
    /// Static front axle load [kg].
    front_axle_kg: f64,
    /// Centre of mass above ground [m].
    cg_height_m: f64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct BodySec {
    /// Roll, pitch, yaw radii of gyration of the sprung body [m].
    radii_of_gyration_m: [f64; 3],
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct GeometrySec {
    wheelbase_m: f64,
    front_track_m: f64,
    rear_track_m: f64,
}

/// One axle of the compact file (per corner).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
struct AxleSec {
    /// Mass moving with the wheel: wheel, tyre, brake, hub carrier, share of the arms
    /// and spring [kg].
    pub unsprung_kg: f64,
    pub spring: SpringSec,
    /// Damping at the wheel [N s/m] (or `damping_ratio`).
    pub damping_n_s_m: Option<f64>,
    /// Fraction of critical on the corner's ride rate.
    pub damping_ratio: Option<f64>,
    /// Roll stiffness an anti-roll bar adds at the axle [N m/rad].
    pub anti_roll_n_m_rad: Option<f64>,
    /// Wheel without tyre (rim, brake, hub) [kg].
    pub wheel_mass_kg: Option<f64>,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
struct SpringSec {
    /// `coil` or `air`.
    pub kind: String,
    /// Spring rate at the wheel [N/m] (or `ride_frequency_hz`).
    pub wheel_rate_n_m: Option<f64>,
    /// Ride frequency of the corner (wheel rate in series with the tyre, sprung share).
    pub ride_frequency_hz: Option<f64>,
    /// Air: effective area [m^2].
    pub effective_area_m2: Option<f64>,
    /// Air: gas volume at the design height [m^3] (or the rate from the ride frequency).
    pub volume_m3: Option<f64>,
    /// Air: polytropic exponent.
    pub polytropic_exponent: Option<f64>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct DrivelineSec {
    /// `front`, `rear` or `all`.
    driven: Option<String>,
}

/// What the translation carries along: the compact file, the defaults, the list of
/// assumed and derived values.
struct Ctx {
    pub src: Source,
    pub dir: PathBuf,
    pub defaults: defaults::Read,
    pub loader: Loader,
    pub assumed: std::cell::RefCell<Vec<Assumed>>,
    /// Gravity's magnitude [m/s^2].
    pub g: f64,
}

impl Ctx {
    pub fn note(&self, field: &str, value: f64, unit: &str, kind: Kind, source: String) {
        self.assumed.borrow_mut().push(Assumed {
            field: field.to_string(),
            value,
            unit: unit.to_string(),
            kind,
            source,
        });
    }

    /// A default, noted as assumed for `field`.
    pub fn default(&self, field: &str, value: f64, unit: &str, key: &str) -> f64 {
        let src = format!("{} ({key})", self.defaults.path.display());
        self.note(field, value, unit, Kind::Assumed, src);
        value
    }

    pub fn defaults_dir(&self) -> PathBuf {
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

/// The spring and damping of an axle at `p`: corner load `load` [N], unsprung mass
/// `mu` [kg], tyre rate `cz` [N/m].
fn suspension(
    ctx: &Ctx,
    a: &AxleSec,
    p: &[Seg],
    load: f64,
    mu: f64,
    cz: f64,
) -> Result<(SpringChoice, f64), InputError> {
    let name = towride_mbs::input::path_string(p);
    let sp = at(p, "spring");
    let s = &a.spring;
    let sprung = load / ctx.g - mu;
    if sprung <= 0.0 {
        return Err(ctx.src.error(
            &at(p, "unsprung_kg"),
            format!(
                "{mu} kg is more than the corner's static load ({:.1} kg)",
                load / ctx.g
            ),
        ));
    }
    // Ride rate: the wheel rate in series with the tyre, on the corner's sprung mass.
    let wheel_rate = match (s.wheel_rate_n_m, s.ride_frequency_hz) {
        (Some(k), None) => Some(ctx.src.positive(&at(&sp, "wheel_rate_n_m"), k)?),
        (None, Some(f)) => {
            let f = ctx.src.positive(&at(&sp, "ride_frequency_hz"), f)?;
            let ride = sprung * (2.0 * std::f64::consts::PI * f).powi(2);
            if ride >= cz {
                return Err(ctx.src.error(
                    &at(&sp, "ride_frequency_hz"),
                    format!(
                        "{f} Hz needs a ride rate of {ride:.0} N/m, above the tyre's {cz:.0} N/m"
                    ),
                ));
            }
            let k = ride * cz / (cz - ride);
            ctx.note(&format!("{name}.spring.wheel_rate_n_m"), k, "N/m", Kind::Derived, format!(
                "ride frequency {f} Hz on {sprung:.1} kg sprung per corner, in series with the tyre's {cz:.0} N/m"
            ));
            Some(k)
        }
        (Some(_), Some(_)) => {
            return Err(ctx
                .src
                .error(&sp, "give wheel_rate_n_m or ride_frequency_hz, not both"))
        }
        (None, None) if s.kind == "coil" => {
            return Err(ctx
                .src
                .error(&sp, "give wheel_rate_n_m or ride_frequency_hz"))
        }
        (None, None) => None,
    };
    let choice = match s.kind.as_str() {
        "coil" => {
            for (k, v) in [
                ("effective_area_m2", s.effective_area_m2),
                ("volume_m3", s.volume_m3),
                ("polytropic_exponent", s.polytropic_exponent),
            ] {
                if v.is_some() {
                    return Err(ctx.src.error(&at(&sp, k), "only an air spring has this"));
                }
            }
            SpringChoice::Coil {
                wheel_rate: wheel_rate.unwrap_or(0.0),
            }
        }
        "air" => {
            let area = s
                .effective_area_m2
                .ok_or_else(|| ctx.src.error(&sp, "an air spring needs effective_area_m2"))?;
            let area = ctx.src.positive(&at(&sp, "effective_area_m2"), area)?;
            let volume = match (s.volume_m3, wheel_rate) {
                (Some(v), None) => Some(ctx.src.positive(&at(&sp, "volume_m3"), v)?),
                (None, Some(_)) => None,
                (Some(_), Some(_)) => {
                    return Err(ctx.src.error(
                        &sp,
                        "an air spring's rate follows from its volume: give volume_m3 or the rate, not both",
                    ))
                }
                (None, None) => {
                    return Err(ctx.src.error(
                        &sp,
                        "give volume_m3, or wheel_rate_n_m or ride_frequency_hz",
                    ))
                }
            };
            let d = &ctx.defaults.d.air_spring;
            let (dn, pa) = (d.polytropic_exponent, d.atmosphere_pa);
            let exponent = match s.polytropic_exponent {
                Some(n) => ctx.src.positive(&at(&sp, "polytropic_exponent"), n)?,
                None => ctx.default(
                    &format!("{name}.spring.polytropic_exponent"),
                    dn,
                    "-",
                    "air_spring.polytropic_exponent",
                ),
            };
            ctx.default(
                &format!("{name}.spring.atmosphere_pa"),
                pa,
                "Pa",
                "air_spring.atmosphere_pa",
            );
            SpringChoice::Air {
                area,
                volume,
                wheel_rate,
                exponent,
                atmosphere: pa,
            }
        }
        k => {
            return Err(ctx
                .src
                .error(&at(&sp, "kind"), format!("'{k}': use coil or air")))
        }
    };
    // Damping at the wheel: given, or a fraction of critical on the ride rate.
    let ride_rate = |k: f64| k * cz / (k + cz);
    let damping = match (a.damping_n_s_m, a.damping_ratio) {
        (Some(c), None) => ctx.src.non_negative(&at(p, "damping_n_s_m"), c)?,
        (c, z) => {
            if c.is_some() {
                return Err(ctx.src.error(
                    &at(p, "damping_ratio"),
                    "give damping_n_s_m or damping_ratio, not both",
                ));
            }
            let zeta = match z {
                Some(z) => ctx.src.positive(&at(p, "damping_ratio"), z)?,
                None => {
                    let z = ctx.defaults.d.corner.damping_ratio;
                    ctx.default(
                        &format!("{name}.damping_ratio"),
                        z,
                        "-",
                        "corner.damping_ratio",
                    )
                }
            };
            // The air spring's rate is known from its volume only after the statics;
            // its ride rate at the design pressure is estimated with P = load - mu g.
            let k = match &choice {
                SpringChoice::Coil { wheel_rate } => *wheel_rate,
                SpringChoice::Air {
                    area,
                    volume,
                    wheel_rate,
                    exponent,
                    atmosphere,
                } => wheel_rate.unwrap_or_else(|| {
                    let gauge = (load - mu * ctx.g) / area;
                    exponent * (gauge + atmosphere) * area * area / volume.unwrap_or(f64::NAN)
                }),
            };
            let c = 2.0 * zeta * (ride_rate(k) * sprung).sqrt();
            ctx.note(&format!("{name}.damping_n_s_m"), c, "N s/m", Kind::Derived, format!(
                "{zeta} of critical on the ride rate {:.0} N/m and {sprung:.1} kg sprung per corner",
                ride_rate(k)
            ));
            c
        }
    };
    Ok((choice, damping))
}

/// The wheel (rim, brake, hub) and the arm of a corner with unsprung mass `mu`, tyre
/// `t` and rim diameter `rim_in` [in]: (rim with the tyre's share, arm) masses, left
/// side, at the wheel centre `w`.
fn corner_masses(
    ctx: &Ctx,
    a: &AxleSec,
    p: &[Seg],
    tyre: &towride_mbs::tyre::Tyre,
    rim_in: f64,
    w: V,
) -> Result<(Mass, Mass), InputError> {
    let name = towride_mbs::input::path_string(p);
    let d = &ctx.defaults.d.corner;
    let (k_spin, k_tilt, arm_k) = (
        d.wheel_spin_inertia_per_m_rrim2,
        d.wheel_tilt_per_spin,
        d.arm_gyration_m,
    );
    let wheel_mass = match a.wheel_mass_kg {
        Some(m) => ctx.src.positive(&at(p, "wheel_mass_kg"), m)?,
        None => {
            let m = d.wheel_mass_at_16in_kg * (rim_in / 16.0).powi(2);
            ctx.note(&format!("{name}.wheel_mass_kg"), m, "kg", Kind::Assumed, format!(
                "{} ({} kg at 16 in, scaled with the rim diameter squared: corner.wheel_mass_at_16in_kg)",
                ctx.defaults.path.display(),
                d.wheel_mass_at_16in_kg
            ));
            m
        }
    };
    let r_rim = 0.5 * rim_in * 0.0254;
    let spin = k_spin * wheel_mass * r_rim * r_rim;
    let props = super::props::WheelProps {
        mass_kg: wheel_mass,
        spin_inertia_kg_m2: spin,
        tilt_inertia_kg_m2: k_tilt * spin,
    };
    let rim = wheel::rim_mass(&ctx.src, &at(p, "wheel_mass_kg"), &props, tyre, w)?;
    let tyre_mass = tyre.params().mass;
    let arm_mass = a.unsprung_kg - wheel_mass - tyre_mass;
    if arm_mass.is_nan() || arm_mass <= 0.0 {
        return Err(ctx.src.error(
            &at(p, "unsprung_kg"),
            format!(
                "{} kg leaves nothing for the hub carrier and arm after the wheel ({wheel_mass:.1} kg) and the tyre ({tyre_mass:.1} kg)",
                a.unsprung_kg
            ),
        ));
    }
    ctx.note(&format!("{name}.arm_mass_kg"), arm_mass, "kg", Kind::Derived, format!(
        "unsprung {} kg less wheel and tyre, lumped at the wheel centre (radius of gyration {arm_k} m: corner.arm_gyration_m)",
        a.unsprung_kg
    ));
    let i = arm_mass * arm_k * arm_k;
    let arm = Mass {
        mass: arm_mass,
        cm: w,
        inertia: [[i, 0.0, 0.0], [0.0, i, 0.0], [0.0, 0.0, i]],
    };
    Ok((rim, arm))
}

/// Reads the compact vehicle file `path` and builds the vehicle, every file read through
/// `loader`.
pub fn load(path: &Path, opts: &Options, loader: &Loader) -> Result<Vehicle, InputError> {
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
            format!("no file {}", dpath.display()),
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
    for (k, v) in [
        (
            "rear_cross_member",
            opts.rear_cross_member.as_deref().filter(|k| *k != "rigid"),
        ),
        (
            "ball_coupling",
            opts.ball_coupling.as_deref().filter(|k| *k != "spherical"),
        ),
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
    let src = &ctx.src;
    let m = &f.mass;
    let total = src.positive(&path!["mass", "total_kg"], m.total_kg)?;
    let front_kg = src.positive(&path!["mass", "front_axle_kg"], m.front_axle_kg)?;
    if front_kg >= total {
        return Err(src.error(
            &path!["mass", "front_axle_kg"],
            "must be less than total_kg",
        ));
    }
    let h = src.positive(&path!["mass", "cg_height_m"], m.cg_height_m)?;
    let gm = &f.geometry;
    let l = src.positive(&path!["geometry", "wheelbase_m"], gm.wheelbase_m)?;
    let tf = src.positive(&path!["geometry", "front_track_m"], gm.front_track_m)?;
    let tr = src.positive(&path!["geometry", "rear_track_m"], gm.rear_track_m)?;
    let rear_kg = total - front_kg;
    let (load_f, load_r) = (0.5 * front_kg * ctx.g, 0.5 * rear_kg * ctx.g);
    // The car: origin on the ground under the front axle centre, x forward.
    let x_cg = -l * rear_kg / total;
    ctx.note(
        "mass.cg_x_m",
        x_cg,
        "m",
        Kind::Derived,
        "behind the front axle by the axle loads".into(),
    );
    let (tyre, r0) = tyre::build(&ctx, &f.tyre, &path!["tyre"], kind, load_f)?;
    let cz = tyre.params().cz;
    let rim_in = tyre::parse_size(&f.tyre.size).map_or(16.0, |s| s.2);
    // Wheel centres at the loaded radius under the static corner loads.
    let zf = r0 - load_f / cz;
    let zr = r0 - load_r / cz;
    let wf = [0.0, 0.5 * tf, zf];
    let wr = [-l, 0.5 * tr, zr];
    let (rim_f, arm_f) = corner_masses(&ctx, &f.front, &path!["front"], &tyre, rim_in, wf)?;
    let (rim_r, arm_r) = corner_masses(&ctx, &f.rear, &path!["rear"], &tyre, rim_in, wr)?;
    for (p, a) in [("front", &f.front), ("rear", &f.rear)] {
        src.positive(&path![p, "unsprung_kg"], a.unsprung_kg)?;
    }
    let (mu_f, mu_r) = (f.front.unsprung_kg, f.rear.unsprung_kg);
    let sprung = total - 2.0 * (mu_f + mu_r);
    let xs = (total * x_cg + 2.0 * mu_r * l) / sprung;
    let zs = (total * h - 2.0 * (mu_f * zf + mu_r * zr)) / sprung;
    if sprung <= 0.0 || zs <= 0.0 {
        return Err(src.error(
            &path!["mass", "cg_height_m"],
            format!("the sprung body ({sprung:.1} kg) would have its centre of mass {zs:.3} m above ground"),
        ));
    }
    ctx.note(
        "body.mass_kg",
        sprung,
        "kg",
        Kind::Derived,
        "total less four unsprung corners".into(),
    );
    ctx.note(
        "body.cm_x_m",
        xs,
        "m",
        Kind::Derived,
        "the car's centre of mass less the unsprung masses".into(),
    );
    ctx.note(
        "body.cm_z_m",
        zs,
        "m",
        Kind::Derived,
        "the car's centre of mass less the unsprung masses".into(),
    );
    let gyr = match &f.body {
        Some(b) => {
            for (c, v) in b.radii_of_gyration_m.iter().enumerate() {
                src.positive(&path!["body", "radii_of_gyration_m", c], *v)?;
            }
            b.radii_of_gyration_m
        }
        None => {
            let d = &ctx.defaults.d.body;
            let (a, bb) = (-xs, xs + l);
            let ky = (d.dynamic_index * a * bb).sqrt();
            let (kx, kz) = (
                d.roll_gyration_per_track * 0.5 * (tf + tr),
                d.yaw_gyration_per_pitch_gyration * ky,
            );
            ctx.default(
                "body.radii_of_gyration_m[0]",
                kx,
                "m",
                "body.roll_gyration_per_track",
            );
            ctx.default("body.radii_of_gyration_m[1]", ky, "m", "body.dynamic_index");
            ctx.default(
                "body.radii_of_gyration_m[2]",
                kz,
                "m",
                "body.yaw_gyration_per_pitch_gyration",
            );
            [kx, ky, kz]
        }
    };
    let body_mass = Mass {
        mass: sprung,
        cm: [xs, 0.0, zs],
        inertia: [
            [sprung * gyr[0] * gyr[0], 0.0, 0.0],
            [0.0, sprung * gyr[1] * gyr[1], 0.0],
            [0.0, 0.0, sprung * gyr[2] * gyr[2]],
        ],
    };
    let (spring_f, damp_f) = suspension(&ctx, &f.front, &path!["front"], load_f, mu_f, cz)?;
    let (spring_r, damp_r) = suspension(&ctx, &f.rear, &path!["rear"], load_r, mu_r, cz)?;

    let mut mb = ModelBuilder::new(&f.vehicle.name, gravity);
    mb.set_joints_as_bushings(opts.joints_as_bushings.clone())
        .map_err(|e| src.locate(&path!["vehicle"], e.into_field()))?;
    let car_place = Placement::translate([opts.x_offset, 0.0, 0.0]);
    let mut b = Builder::new(mb, loader, opts.run_modes.clone());
    b.set_place(car_place);
    let car_body = b.body("car_body", &body_mass)?;
    let car_ref = b.mb.marker_by_name("car_body.cm").expect("body marker");
    let mut axles = Vec::new();
    for (centre, wheels, w, rim, arm, spring, damping, a, p, load) in [
        (
            "front_axle",
            ["fl", "fr"],
            wf,
            rim_f,
            arm_f,
            spring_f,
            damp_f,
            &f.front,
            "front",
            load_f,
        ),
        (
            "rear_axle",
            ["rl", "rr"],
            wr,
            rim_r,
            arm_r,
            spring_r,
            damp_r,
            &f.rear,
            "rear",
            load_r,
        ),
    ] {
        let anti_roll = match a.anti_roll_n_m_rad {
            Some(k) => src.non_negative(&path![p, "anti_roll_n_m_rad"], k)?,
            None => {
                let k = ctx.defaults.d.corner.anti_roll_n_m_rad;
                ctx.default(
                    &format!("{p}.anti_roll_n_m_rad"),
                    k,
                    "N m/rad",
                    "corner.anti_roll_n_m_rad",
                )
            }
        };
        let input = AxleInput {
            centre,
            prefix: "arm",
            wheels,
            carrier: car_body,
            wheel_centre: w,
            tyre: &tyre,
            arm,
            rim,
            spring,
            damping,
            anti_roll,
            corner_load: load,
            spring_at: path![p, "spring"].to_vec(),
        };
        axles.push(corner::build(&ctx, &mut b, &input)?);
    }
    note_geometry(&ctx);
    // Design statics of the car alone, as the assembly does: its weight shared by the
    // axles by the lever rule, then across each axle.
    let mut parts: Vec<(f64, V)> = b
        .model()
        .bodies
        .iter()
        .map(|x| {
            (
                x.mass,
                towride_mbs::model::math::sub(&x.position, &car_place.translation),
            )
        })
        .collect();
    for w in axles.iter().flat_map(|a| a.wheels.iter()) {
        parts.push((
            wheel::tyre_own_mass(&b.model().tyres[w.tyre.index()].tyre),
            w.design_centre,
        ));
    }
    let (car_mass, car_cm) = centre_of_mass(&parts);
    let weight = car_mass * ctx.g;
    let (ff, fr) = design::lever(weight, car_cm[0], wf[0], wr[0]);
    let mut car_corners = Vec::new();
    let mut ride = Vec::new();
    let mut wheels = Vec::new();
    let mut air = Vec::new();
    let mut mounts = Vec::new();
    for (axle_load, axle) in [ff, fr].into_iter().zip(axles) {
        let (yl, yr) = (
            axle.wheels[0].design_centre[1],
            axle.wheels[1].design_centre[1],
        );
        let (fl, fr) = design::lever(axle_load, car_cm[1], yl, yr);
        for (p, load) in axle.pending.into_iter().zip([fl, fr]) {
            let (cd, a) = corner::finish(&ctx, &mut b, p, load)?;
            if let Some(a) = a {
                air.push((cd.wheel.clone(), a));
            }
            car_corners.push(cd);
        }
        for (w, p) in axle.wheels.iter().zip(&axle.mounts) {
            ride.push((w.name.clone(), *p));
        }
        mounts.extend(
            axle.wheels
                .iter()
                .map(|w| w.name.clone())
                .zip(axle.mounts.iter().copied()),
        );
        wheels.extend(axle.wheels);
    }
    note_air(&ctx, &air);
    let ride = ride
        .into_iter()
        .map(|(w, p)| {
            let m = b.add(|m| m.marker(&format!("ride_{w}"), Some(car_body), p, &IDENTITY))?;
            Ok((w, m))
        })
        .collect::<Result<Vec<_>, InputError>>()?;
    let mut handles = Handles::car(car_body, car_ref, ride, car_place, None);
    let mut trailer_design = None;
    let mut driven_mass = total;
    if let Some(t) = &f.trailer {
        let built = trailer::build(&ctx, &mut b, t, car_body, [-l, 0.0, 0.0], opts, kind)?;
        driven_mass += built.design.mass_kg;
        handles.ball = Some(built.ball);
        handles.trailer_body = Some(built.body);
        handles.trailer_ref = b.mb.marker_by_name("trailer_box.cm");
        handles.trailer_place = Some(built.place);
        wheels.extend(built.wheels);
        trailer_design = Some(built.design);
    }
    let control = driveline(&ctx, &f, car_ref, opts.speed, &wheels, driven_mass, zr)?;
    b.mb.speed_control(control);
    handles.index_bodies(&b);
    let mut sensors = sensors::add(
        &mut b,
        &handles,
        src,
        &path!["vehicle"],
        &standard_sensors(&wheels, &mounts),
    )?;
    sensors.extend(sensors::add(
        &mut b,
        &handles,
        src,
        &path!["sensor"],
        &f.sensor,
    )?);
    handles.sensors = sensors;
    let design = Design {
        car_mass_kg: car_mass,
        car_cm_m: car_cm,
        car_corners,
        trailer: trailer_design,
        total_mass_kg: 0.0,
    };
    Ok(super::assembly::finish(
        b,
        handles,
        wheels,
        opts.speed,
        design,
        ctx.assumed.into_inner(),
    ))
}

/// The corner geometry every simple vehicle shares, listed once.
fn note_geometry(ctx: &Ctx) {
    let d = &ctx.defaults.d.corner;
    let values = [
        ("corner.arm_length_m", d.arm_length_m, "m"),
        ("corner.pivot_inboard_m", d.pivot_inboard_m, "m"),
        ("corner.spring_inboard_m", d.spring_inboard_m, "m"),
        ("corner.damper_inboard_m", d.damper_inboard_m, "m"),
        ("corner.spring_length_m", d.spring_length_m, "m"),
        ("corner.bump_clearance_m", d.bump_clearance_m, "m"),
        ("corner.bump_stop_load_factor", d.bump_stop_load_factor, "-"),
        ("corner.rebound_clearance_m", d.rebound_clearance_m, "m"),
    ];
    for (k, v, u) in values {
        ctx.default(k, v, u, k);
    }
    let src = format!("{} (corner.pivot_bushing)", ctx.defaults.path.display());
    ctx.note("corner.pivot_bushing", f64::NAN, "", Kind::Assumed, src);
}

/// The air springs' pressures and volumes found by the design statics.
fn note_air(ctx: &Ctx, air: &[(String, AirSpring)]) {
    for (w, a) in air {
        ctx.note(
            &format!("air_spring_{w}.gauge_pressure_pa"),
            a.gauge_pa,
            "Pa",
            Kind::Derived,
            "static load over the effective area (levelled at the design height)".into(),
        );
        ctx.note(
            &format!("air_spring_{w}.volume_m3"),
            a.volume_m3,
            "m^3",
            Kind::Derived,
            "the file's volume, or the one giving its rate".into(),
        );
        ctx.note(
            &format!("air_spring_{w}.rate_n_m"),
            a.rate(),
            "N/m",
            Kind::Derived,
            "n (p_g + p_a) A^2 / V0 at the design height".into(),
        );
    }
}

/// The speed controller: gains from the mass and the loaded radius (defaults file).
fn driveline(
    ctx: &Ctx,
    f: &File,
    car_ref: towride_mbs::model::builder::MarkerHandle,
    speed: f64,
    wheels: &[wheel::WheelHandle],
    mass: f64,
    radius: f64,
) -> Result<SpeedControl, InputError> {
    let d = &ctx.defaults.d.driveline;
    let (bw, zeta, amax, default) = (
        d.bandwidth_hz,
        d.damping_ratio,
        d.max_acceleration_g,
        d.driven.clone(),
    );
    let (driven, at) = match f.driveline.as_ref().and_then(|x| x.driven.clone()) {
        Some(x) => (x, path!["driveline", "driven"].to_vec()),
        None => {
            let src = format!(
                "{} (driveline.driven = {default})",
                ctx.defaults.path.display()
            );
            ctx.note("driveline.driven", f64::NAN, "", Kind::Assumed, src);
            (default, path!["driveline", "driven"].to_vec())
        }
    };
    let names: &[&str] = match driven.as_str() {
        "front" => &["fl", "fr"],
        "rear" => &["rl", "rr"],
        "all" => &["fl", "fr", "rl", "rr"],
        x => return Err(ctx.src.error(&at, format!("'{x}': use front, rear or all"))),
    };
    let w = 2.0 * std::f64::consts::PI * bw;
    let mr = mass * radius;
    let (kp, ki, max) = (2.0 * zeta * w * mr, w * w * mr, amax * ctx.g * mr);
    for (k, v, u) in [
        ("proportional_n_m_s_per_m", kp, "N m s/m"),
        ("integral_n_m_per_m", ki, "N m/m"),
        ("max_torque_n_m", max, "N m"),
    ] {
        ctx.note(&format!("driveline.{k}"), v, u, Kind::Derived, format!(
            "{bw} Hz at {zeta} of critical on M r = {mr:.0} kg m, limit {amax} g (defaults' driveline)"
        ));
    }
    Ok(SpeedControl {
        name: "driveline".into(),
        sensor: car_ref,
        target: TimeFunction::Constant { value: speed },
        kp,
        ki,
        max_torque: max,
        wheels: wheels
            .iter()
            .filter(|w| names.contains(&w.name.as_str()))
            .map(|w| (w.centre, w.carrier_centre))
            .collect(),
    })
}

/// Accelerometers at every corner, measuring z: `wheel_<front|rear|trailer>_<left|right>`
/// on the arm at the wheel centre, `body_<front|rear>_<left|right>` on the body at the
/// spring's top (`mounts`: wheel name and point).
fn standard_sensors(wheels: &[wheel::WheelHandle], mounts: &[(String, V)]) -> Vec<SensorSpec> {
    let corner = |w: &str| match w {
        "fl" => Some(("front", "left", "arm_fl")),
        "fr" => Some(("front", "right", "arm_fr")),
        "rl" => Some(("rear", "left", "arm_rl")),
        "rr" => Some(("rear", "right", "arm_rr")),
        "tl" => Some(("trailer", "left", "trailer_arm_tl")),
        "tr" => Some(("trailer", "right", "trailer_arm_tr")),
        _ => None,
    };
    let spec = |name: String, body: &str, p: V| SensorSpec {
        name,
        body: body.into(),
        position_m: Some(p),
        node: None,
        axes: vec!["z".into()],
    };
    let mut out = Vec::new();
    for w in wheels {
        if let Some((axle, side, arm)) = corner(&w.name) {
            out.push(spec(format!("wheel_{axle}_{side}"), arm, w.design_centre));
        }
    }
    for (w, p) in mounts {
        if let Some((axle, side, _)) = corner(w) {
            out.push(spec(format!("body_{axle}_{side}"), "car_body", *p));
        }
    }
    out
}
