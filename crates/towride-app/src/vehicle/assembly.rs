//! The assembly file: which templates and property files make a vehicle, its sensors,
//! and [`load`], which builds it.
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
//! Paths are relative to the assembly file.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::build::Builder;
use super::design::{self, centre_of_mass};
use super::geom::{Placement, IDENTITY, V};
use super::props::at;
use super::sensors::{self, SensorSpec};
use super::{
    axle, body, driveline, engine, hitch, trailer, wheel, Design, Handles, Options, TrailerDesign,
    Vehicle,
};
use towride_mbs::input::{InputError, Loader, Seg, Source};
use towride_mbs::model::builder::{BodyHandle, MarkerHandle, ModelBuilder};
use towride_mbs::model::math::sub;
use towride_mbs::model::Model;
use towride_mbs::path;
use towride_mbs::tyre::{Tyre, TyreKind};

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

/// Rear axle and hitch FE origin may differ by this much [m] (the hitch file is drawn
/// from the rear axle).
const HITCH_ORIGIN_TOLERANCE_M: f64 = 0.01;

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
    file(src, dir, p, part)
}

/// A part's file, checked for existence.
fn file(src: &Source, dir: &Path, p: &[Seg], part: &Part) -> Result<PathBuf, InputError> {
    let f = dir.join(&part.file);
    if !f.is_file() {
        return Err(src.error(&at(p, "file"), format!("no file {}", f.display())));
    }
    Ok(f)
}

/// An axle slot's template, from the registry.
fn axle_template(
    src: &Source,
    p: &[Seg],
    part: &Part,
) -> Result<&'static dyn axle::AxleTemplate, InputError> {
    axle::template(&part.template).ok_or_else(|| {
        src.error(
            &at(p, "template"),
            format!(
                "'{}': an axle slot takes one of the axle templates ({})",
                part.template,
                axle::names().join(", ")
            ),
        )
    })
}

fn tyre(
    src: &Source,
    dir: &Path,
    p: &[Seg],
    part: &Part,
    kind: TyreKind,
    loader: &Loader,
) -> Result<Tyre, InputError> {
    let mut at = p.to_vec();
    at.push(Seg::from("tyre"));
    let t = part
        .tyre
        .as_ref()
        .ok_or_else(|| src.error(&at, "name the tyre's .tir file"))?;
    let f = dir.join(t);
    if !f.is_file() {
        return Err(src.error(&at, format!("no file {}", f.display())));
    }
    Tyre::from_file(&f, kind, loader)
}

/// Reads the assembly file `path` and builds the vehicle, every file read through
/// `loader`.
pub fn load(path: &Path, opts: &Options, loader: &Loader) -> Result<Vehicle, InputError> {
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
    let kind = opts.tyre_kind.unwrap_or(f.vehicle.tyre_model);
    let mut mb = ModelBuilder::new(&f.vehicle.name, f.vehicle.gravity_m_s2);
    mb.set_joints_as_bushings(opts.joints_as_bushings.clone())
        .map_err(|e| src.locate(&path!["vehicle"], e.into_field()))?;
    let car_place = Placement::translate([opts.x_offset, 0.0, 0.0]);
    let mut b = Builder::new(mb, loader, opts.run_modes.clone());
    b.set_place(car_place);
    let c = &f.car;
    let car_body = body::build(
        &mut b,
        &part(&src, dir, &path!["car", "body"], &c.body, "lumped_body")?,
    )?;
    if let Some(e) = &c.engine {
        let file = part(&src, dir, &path!["car", "engine"], e, "engine_on_mounts")?;
        engine::build(&mut b, &file, car_body)?;
    }
    let car_ref = b.mb.marker_by_name("car_body.cm").expect("body marker");
    let mut axles = Vec::new();
    for (slot, p, wheels, variant) in [
        (&c.front, path!["car", "front"], ["fl", "fr"], None),
        (
            &c.rear,
            path!["car", "rear"],
            ["rl", "rr"],
            opts.rear_cross_member.as_deref(),
        ),
    ] {
        let template = axle_template(&src, &p, slot)?;
        let t = tyre(&src, dir, &p, slot, kind, loader)?;
        let axle = template.build(
            &mut b,
            &file(&src, dir, &p, slot)?,
            &axle::AxleSlot {
                carrier: car_body,
                tyre: &t,
                wheels,
                variant,
            },
        )?;
        axles.push(axle);
    }
    let rear_x = axles[1].wheels[0].design_centre[0];
    let hitch = match &c.hitch {
        Some(h) => {
            let file = part(&src, dir, &path!["car", "hitch"], h, "modal_hitch")?;
            let hh = hitch::build(
                &mut b,
                &file,
                car_body,
                opts.hitch_variant,
                opts.ball_coupling.as_deref(),
            )?;
            if (hh.fe_origin[0] - rear_x).abs() > HITCH_ORIGIN_TOLERANCE_M {
                let mut e = hh.origin_complaint.clone();
                e.message = format!(
                    "the FE model is drawn from the rear axle, which is at x = {rear_x} m here"
                );
                return Err(e);
            }
            Some(hh)
        }
        None => None,
    };
    // Design statics of the car alone: its weight shared by the axles (lever rule), then
    // across each axle.
    let wheel_sets: Vec<&Vec<wheel::WheelHandle>> = axles.iter().map(|a| &a.wheels).collect();
    let parts = masses(b.model(), &car_place, &wheel_sets);
    let (car_mass, car_cm) = centre_of_mass(&parts);
    let w = car_mass * super::geom::norm(&b.model().gravity);
    let (xf, xr) = (
        axles[0].wheels[0].design_centre[0],
        axles[1].wheels[0].design_centre[0],
    );
    let (ff, fr) = design::lever(w, car_cm[0], xf, xr);
    let mut car_corners = Vec::new();
    let mut ride = Vec::new();
    let mut wheels = Vec::new();
    for (axle_load, axle) in [ff, fr].into_iter().zip(axles) {
        let (yl, yr) = (
            axle.wheels[0].design_centre[1],
            axle.wheels[1].design_centre[1],
        );
        let (fl, fr) = design::lever(axle_load, car_cm[1], yl, yr);
        for (corner, load) in axle.corners.into_iter().zip([fl, fr]) {
            car_corners.push(design::finish(&mut b, corner, load)?);
        }
        for (w, p) in axle.wheels.iter().zip(&axle.body_mounts) {
            ride.push((w.name.clone(), *p));
        }
        wheels.extend(axle.wheels);
    }
    let ride = ride
        .into_iter()
        .map(|(w, p)| {
            let m = b.add(|m| m.marker(&format!("ride_{w}"), Some(car_body), p, &IDENTITY))?;
            Ok((w, m))
        })
        .collect::<Result<Vec<_>, InputError>>()?;
    let dl = part(
        &src,
        dir,
        &path!["car", "driveline"],
        &c.driveline,
        "speed_control",
    )?;
    let control = driveline::build(&dl, car_ref, opts.speed, &wheels, loader)?;
    b.mb.speed_control(control);

    let mut handles = Handles::car(car_body, car_ref, ride, car_place, hitch.clone());
    let mut trailer_design = None;
    if let Some(t) = &f.trailer {
        let tp = path!["trailer"];
        let file = part(&src, dir, &tp, t, "box_trailer")?;
        let h = hitch
            .as_ref()
            .ok_or_else(|| src.error(&tp, "a trailer needs a hitch ([car] hitch = ...)"))?;
        let tt = tyre(&src, dir, &tp, t, kind, loader)?;
        let case = opts.load_case.as_deref().or(t.load_case.as_deref());
        let tf = trailer::read(&file, case, loader)?;
        let (place, pitch) = trailer::place(&src, &tf, car_place.point(h.ball))?;
        b.set_place(place);
        let built = trailer::build(&mut b, &tf, &tt)?;
        b.set_place(car_place);
        handles.ball = Some(hitch::couple(
            &mut b,
            h,
            built.body,
            opts.joints_as_bushings.as_ref(),
        )?);
        handles.trailer_body = Some(built.body);
        handles.trailer_ref = b.mb.marker_by_name("trailer_box.cm");
        handles.trailer_place = Some(place);
        wheels.extend(built.wheels.iter().cloned());
        trailer_design = Some(TrailerDesign {
            load_case: tf.load_case.clone(),
            mass_kg: built.mass,
            cm_m: built.cm,
            empty_ball_load_n: built.design_ball_load_n,
            corners: built.corners,
            pitch_rad: pitch,
        });
    }
    handles.index_bodies(&b);
    handles.sensors = sensors::add(&mut b, &handles, &src, &path!["sensor"], &f.sensor)?;
    let design = Design {
        car_mass_kg: car_mass,
        car_cm_m: car_cm,
        car_corners,
        trailer: trailer_design,
        total_mass_kg: 0.0,
    };
    Ok(finish(b, handles, wheels, opts.speed, design, Vec::new()))
}

impl Handles {
    /// The car's handles before wheels, trailer and sensors are added.
    pub(crate) fn car(
        car_body: BodyHandle,
        car_ref: MarkerHandle,
        ride: Vec<(String, MarkerHandle)>,
        car_place: Placement,
        hitch: Option<super::HitchHandle>,
    ) -> Handles {
        Handles {
            car_body,
            car_ref,
            wheels: Vec::new(),
            hitch,
            ball: None,
            trailer_body: None,
            trailer_ref: None,
            ride,
            sensors: Vec::new(),
            bodies: Default::default(),
            car_place,
            trailer_place: None,
            body_place: Vec::new(),
        }
    }

    /// Names every body built so far and records where each was placed (the sensors and
    /// the scene's outputs address bodies by name).
    pub(crate) fn index_bodies(&mut self, b: &Builder) {
        self.bodies =
            b.mb.body_handles()
                .map(|(name, h)| (name.to_string(), h))
                .collect();
        self.body_place = b.mb.body_places().to_vec();
    }
}

/// Finishes a vehicle for both template sets: sets the wheels spinning at `speed`, builds
/// the model and sums the total mass (bodies and the tyres' own masses) into `design`.
pub(crate) fn finish(
    mut b: Builder,
    mut handles: Handles,
    wheels: Vec<wheel::WheelHandle>,
    speed: f64,
    mut design: Design,
    assumed: Vec<super::simple::Assumed>,
) -> Vehicle {
    wheel::set_speed(b.model_mut(), &wheels, speed);
    handles.wheels = wheels;
    let model = b.mb.finish();
    design.total_mass_kg = model.bodies.iter().map(|x| x.mass).sum::<f64>()
        + handles
            .wheels
            .iter()
            .map(|w| wheel::tyre_own_mass(&model.tyres[w.tyre].tyre))
            .sum::<f64>();
    Vehicle {
        model,
        handles,
        design,
        assumed,
    }
}

/// Point masses of the bodies built so far and of the tyres' belts, vehicle coordinates.
fn masses(m: &Model, place: &Placement, axles: &[&Vec<wheel::WheelHandle>]) -> Vec<(f64, V)> {
    let mut parts: Vec<(f64, V)> = m
        .bodies
        .iter()
        .map(|b| (b.mass, sub(&b.position, &place.translation)))
        .collect();
    for w in axles.iter().flat_map(|a| a.iter()) {
        parts.push((wheel::tyre_own_mass(&m.tyres[w.tyre].tyre), w.design_centre));
    }
    parts
}
