//! The one assembly path: a [`Description`], from either kind of vehicle file, turned
//! into builder calls (car body, engine, axles, hitch), the car's design statics, the
//! ride-height markers, the driveline, the trailer with its own statics, the sensors,
//! and the [`Vehicle`].

use super::air;
use super::axle::{Axle, AxleSlot};
use super::build::Builder;
use super::description::{Assumed, BodySpec, Description, DrivelineSpec, HitchSpec};
use super::design::{self, centre_of_mass, CornerDesign};
use super::geom::{Placement, IDENTITY, V};
use super::props::at;
use super::trailer::TrailerSlot;
use super::{
    body, driveline, engine, hitch, sensors, wheel, Design, Handles, Options, TrailerDesign,
    Vehicle,
};
use towride_mbs::input::{InputError, Loader};
use towride_mbs::model::builder::{BodyHandle, MarkerHandle, ModelBuilder};
use towride_mbs::model::function::TimeFunction;
use towride_mbs::model::math::sub;
use towride_mbs::model::Model;
use towride_mbs::path;

/// Rear axle and hitch FE origin may differ by this much [m] (the hitch file is drawn
/// from the rear axle).
const HITCH_ORIGIN_TOLERANCE_M: f64 = 0.01;

/// Builds the vehicle `d` describes with the choices of `opts`, every file read through
/// `loader`.
pub fn assemble(d: Description, opts: &Options, loader: &Loader) -> Result<Vehicle, InputError> {
    let src = d.src;
    let mut mb = ModelBuilder::new(&d.name, d.gravity);
    mb.set_joints_as_bushings(opts.joints_as_bushings.clone())
        .map_err(|e| src.locate(&path!["vehicle"], e.into_field()))?;
    let car_place = Placement::translate([opts.x_offset, 0.0, 0.0]);
    let mut b = Builder::new(mb, loader, opts.run_modes.clone());
    b.set_place(car_place);
    let (car_body, seat) = match d.body {
        BodySpec::File(file) => body::build(&mut b, &file)?,
        BodySpec::Given(m) => (b.body("car_body", &m)?, None),
    };
    if let Some(file) = &d.engine {
        engine::build(&mut b, file, car_body)?;
    }
    let car_ref = b.mb.marker_by_name("car_body.cm").expect("body marker");
    let mut axles = Vec::new();
    let slots = [
        ("front", ["fl", "fr"], None, opts.steering.as_ref()),
        ("rear", ["rl", "rr"], opts.rear_cross_member, None),
    ];
    for (a, (name, wheels, cross_member, steering)) in d.axles.into_iter().zip(slots) {
        let tyre = a.tyre.tyre(d.tyre_kind, loader)?;
        let slot = AxleSlot {
            carrier: car_body,
            tyre: &tyre,
            wheels,
            name,
            prefix: "",
            cross_member,
            steering,
        };
        axles.push(a.spec.build(&mut b, &slot)?);
    }
    let modal_hitch = match &d.hitch {
        Some(HitchSpec::Modal(file)) => {
            let h = hitch::build(
                &mut b,
                file,
                car_body,
                opts.hitch_variant,
                opts.ball_coupling,
            )?;
            let rear_x = axles[1].wheels[0].design_centre[0];
            if (h.fe_origin[0] - rear_x).abs() > HITCH_ORIGIN_TOLERANCE_M {
                let mut e = h.origin_complaint.clone();
                e.message = format!(
                    "the FE model is drawn from the rear axle, which is at x = {rear_x} m here"
                );
                return Err(e);
            }
            Some(h)
        }
        _ => None,
    };
    let statics = car_statics(&mut b, car_place, axles)?;
    let mut assumed = d.assumed;
    for (w, a) in &statics.air {
        assumed.extend(air::notes(w, a));
    }
    let mut wheels = statics.wheels;
    let ride = statics
        .ride
        .into_iter()
        .map(|(w, p)| {
            let m = b.add(|m| m.marker(&format!("ride_{w}"), Some(car_body), p, &IDENTITY))?;
            Ok((w, m))
        })
        .collect::<Result<Vec<_>, InputError>>()?;
    let (control, driveline_notes) = match d.driveline {
        DrivelineSpec::File(file) => (
            driveline::build(&file, car_ref, opts.speed, &wheels, loader)?,
            Vec::new(),
        ),
        DrivelineSpec::Given { gains, assumed } => (
            driveline::control(&gains, car_ref, opts.speed, &wheels),
            assumed,
        ),
    };
    b.mb.speed_control(control);

    let mut handles = Handles::car(car_body, car_ref, ride, car_place, modal_hitch.clone());
    handles.air_springs = statics.air.clone();
    let mut trailer_design = None;
    if let Some(t) = d.trailer {
        let ball = match (&d.hitch, &modal_hitch) {
            (Some(HitchSpec::Ball(p)), _) => *p,
            (_, Some(h)) => h.ball,
            _ => return Err(src.error(&t.at, "a trailer needs a hitch ([car] hitch = ...)")),
        };
        let tyre = t.tyre.tyre(d.tyre_kind, loader)?;
        let data = t.spec.data(&mut b, opts.load_case.as_deref())?;
        let (place, pitch) = data
            .place(car_place.point(ball))
            .map_err(|e| src.error(&at(&t.at, "file"), e.to_string()))?;
        b.set_place(place);
        let built = data.build(&mut b, &TrailerSlot { tyre: &tyre })?;
        b.set_place(car_place);
        let jb = opts.joints_as_bushings.as_ref();
        handles.ball = Some(match &modal_hitch {
            Some(h) => hitch::couple(&mut b, h, (built.coupling_body, built.coupling_node), jb)?,
            None => hitch::couple_on_body(
                &mut b,
                car_body,
                ball,
                (built.coupling_body, built.coupling_node),
                jb,
            )?,
        });
        handles.trailer_body = Some(built.body);
        handles.trailer_ref = b.mb.marker_by_name("trailer_box.cm");
        handles.trailer_place = Some(place);
        wheels.extend(built.wheels.iter().cloned());
        trailer_design = Some(TrailerDesign {
            load_case: built.load_case,
            mass_kg: built.mass,
            cm_m: built.cm,
            empty_ball_load_n: built.design_ball_load_n,
            corners: built.corners,
            pitch_rad: pitch,
        });
        assumed.extend(t.assumed);
    }
    // A compact file's driveline gains follow from the mass with the trailer: listed last.
    assumed.extend(driveline_notes);
    handles.index_bodies(&b);
    for (p, specs) in &d.sensors {
        let s = sensors::add(&mut b, &handles, &src, p, specs)?;
        handles.sensors.extend(s);
    }
    let design = Design {
        car_mass_kg: statics.mass,
        car_cm_m: statics.cm,
        car_corners: statics.corners,
        trailer: trailer_design,
        total_mass_kg: 0.0,
    };
    let mut v = finish(b, handles, wheels, opts, design, assumed);
    v.seat = seat;
    Ok(v)
}

/// What the car's design statics found.
struct CarStatics {
    mass: f64,
    cm: V,
    corners: Vec<CornerDesign>,
    /// The air springs, by wheel.
    air: Vec<(String, air::AirSpring)>,
    /// Per wheel, the body point its ride height is measured to.
    ride: Vec<(String, V)>,
    wheels: Vec<wheel::WheelHandle>,
}

/// Design statics of the car alone: its weight shared by the axles (lever rule), then
/// across each axle; every corner's spring preloaded for its share.
fn car_statics(
    b: &mut Builder,
    car_place: Placement,
    axles: Vec<Axle>,
) -> Result<CarStatics, InputError> {
    let wheel_sets: Vec<&Vec<wheel::WheelHandle>> = axles.iter().map(|a| &a.wheels).collect();
    let parts = masses(b.model(), &car_place, &wheel_sets);
    let (mass, cm) = centre_of_mass(&parts);
    let w = mass * super::geom::norm(&b.model().gravity);
    let (xf, xr) = (
        axles[0].wheels[0].design_centre[0],
        axles[1].wheels[0].design_centre[0],
    );
    let (front, rear) = design::lever(w, cm[0], xf, xr);
    let mut out = CarStatics {
        mass,
        cm,
        corners: Vec::new(),
        air: Vec::new(),
        ride: Vec::new(),
        wheels: Vec::new(),
    };
    for (axle_load, axle) in [front, rear].into_iter().zip(axles) {
        let (yl, yr) = (
            axle.wheels[0].design_centre[1],
            axle.wheels[1].design_centre[1],
        );
        let (left, right) = design::lever(axle_load, cm[1], yl, yr);
        for (corner, load) in axle.corners.into_iter().zip([left, right]) {
            let (found, air) = design::finish(b, corner, load)?;
            if let Some(a) = air {
                out.air.push((found.wheel.clone(), a));
            }
            out.corners.push(found);
        }
        for (w, p) in axle.wheels.iter().zip(&axle.body_mounts) {
            out.ride.push((w.name.clone(), *p));
        }
        out.wheels.extend(axle.wheels);
    }
    Ok(out)
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
            air_springs: Vec::new(),
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

/// Sets the wheels spinning at `speed`, builds the model and sums the total mass (bodies
/// and the tyres' own masses) into `design`.
fn finish(
    mut b: Builder,
    mut handles: Handles,
    wheels: Vec<wheel::WheelHandle>,
    opts: &Options,
    mut design: Design,
    assumed: Vec<Assumed>,
) -> Vehicle {
    wheel::set_speed(b.model_mut(), &wheels, opts.speed);
    handles.wheels = wheels;
    let mut model = b.mb.finish();
    design.total_mass_kg = model.bodies.iter().map(|x| x.mass).sum::<f64>()
        + handles
            .wheels
            .iter()
            .map(|w| wheel::tyre_own_mass(&model.tyres[w.tyre].tyre))
            .sum::<f64>();
    feed_forward(&mut model, &handles.wheels, design.total_mass_kg, opts);
    Vehicle {
        model,
        handles,
        design,
        assumed,
        seat: None,
    }
}

/// Sets the speed controllers' target (a manoeuvre, or the held speed) and their
/// feed-forward gain: the vehicle's `mass` plus its wheels' and its driveline's spin
/// inertia over r^2, times the driven wheels' design radius r, so that a demanded
/// acceleration asks the torque it needs without waiting for the PI loop (which corrects
/// what this leaves out: rolling losses, the tyres' own belt spin, slip).
///
/// A held speed is kept by the drive alone, as the thesis's engine did: the brakes are
/// left out of the model then. Over the default scene's ramp the controller never asks
/// for more than the engine's drag (the run is the same to the last digit with the drag
/// set to 1e5 N m), but the brakes' entries in the Newton matrix change its ordering and
/// with it the round-off (1112 against 1319 steps, hitch peak within 0.05 %).
fn feed_forward(model: &mut Model, wheels: &[wheel::WheelHandle], mass: f64, opts: &Options) {
    let radius_of = |markers: &[(MarkerHandle, MarkerHandle)]| {
        let r: Vec<f64> = wheels
            .iter()
            .filter(|w| markers.iter().any(|m| m.0 == w.centre))
            .map(|w| w.design_centre[2])
            .collect();
        r.iter().sum::<f64>() / r.len().max(1) as f64
    };
    for k in 0..model.controls.len() {
        let r = radius_of(&model.controls[k].wheels);
        if r <= 0.0 {
            continue;
        }
        let spin: f64 = wheels
            .iter()
            .map(|w| model.bodies[w.body].inertia[1][1] / w.design_centre[2].powi(2))
            .sum();
        let c = &mut model.controls[k];
        let shaft = c.driveline.map_or(0.0, |d| d.inertia / (r * r));
        c.feedforward_kg_m = (mass + spin + shaft) * r;
        match &opts.speed_target {
            Some(t) => {
                c.target = t.clone();
                // The driver's hold is for a stop: a manoeuvre that ends moving (a
                // start) has none, so nothing holds the car before it pulls away.
                let stops = matches!(t, TimeFunction::JerkLimited { to, .. } if *to <= 0.0);
                if let (false, Some(b)) = (stops, c.brakes.as_mut()) {
                    b.hold_torque = 0.0;
                }
            }
            None => c.brakes = None,
        }
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
