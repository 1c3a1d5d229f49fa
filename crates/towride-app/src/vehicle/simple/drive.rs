//! A compact file's speed controller (gains from the driven mass and the loaded radius,
//! the defaults' loop) and its standard accelerometers.

use serde::Deserialize;

use super::car::Car;
use super::{Ctx, File, Kind};
use crate::vehicle::driveline::Gains;
use crate::vehicle::geom::{mirror, V};
use crate::vehicle::sensors::SensorSpec;
use towride_mbs::input::InputError;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct DrivelineSec {
    driven: Option<Driven>,
}

/// The driven axles.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum Driven {
    Front,
    Rear,
    All,
}

impl std::fmt::Display for Driven {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            Driven::Front => "front",
            Driven::Rear => "rear",
            Driven::All => "all",
        })
    }
}

/// The speed controller holding `mass` [kg] on wheels of loaded radius `radius` [m]:
/// a loop of the defaults' bandwidth and damping on M r, its torque limited to the
/// defaults' acceleration.
pub(super) fn gains(ctx: &Ctx, f: &File, mass: f64, radius: f64) -> Result<Gains, InputError> {
    let d = &ctx.defaults.d.driveline;
    let (bw, zeta, amax, default) = (
        d.bandwidth_hz,
        d.damping_ratio,
        d.max_acceleration_g,
        d.driven,
    );
    let driven = match f.driveline.as_ref().and_then(|x| x.driven) {
        Some(x) => x,
        None => {
            let src = format!(
                "{} (driveline.driven = {default})",
                ctx.defaults.path.display()
            );
            ctx.note("driveline.driven", f64::NAN, "", Kind::Assumed, src);
            default
        }
    };
    let names: &[&str] = match driven {
        Driven::Front => &["fl", "fr"],
        Driven::Rear => &["rl", "rr"],
        Driven::All => &["fl", "fr", "rl", "rr"],
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
    Ok(Gains {
        proportional_n_m_s_per_m: kp,
        integral_n_m_per_m: ki,
        max_torque_n_m: max,
        driven_wheels: names.iter().map(|n| n.to_string()).collect(),
    })
}

/// Accelerometers at every corner, measuring z: `wheel_<front|rear|trailer>_<left|right>`
/// on the arm at the wheel centre, `body_<front|rear>_<left|right>` on the body at the
/// spring's top; `trailer_wheel` the trailer's left wheel centre, if it has one.
pub(super) fn standard_sensors(car: &Car, trailer_wheel: Option<V>) -> Vec<SensorSpec> {
    let spec = |name: String, body: &str, p: V| SensorSpec {
        name,
        body: body.into(),
        position_m: Some(p),
        node: None,
        axes: vec!["z".into()],
    };
    let [wf, wr] = car.wheel_centres;
    let mut wheels = vec![("front", "", wf), ("rear", "", wr)];
    wheels.extend(trailer_wheel.map(|w| ("trailer", "trailer_", w)));
    let mut out = Vec::new();
    for (axle, prefix, w) in wheels {
        let short = &axle[..1];
        for (side, s, p) in [("left", "l", w), ("right", "r", mirror(w))] {
            let arm = format!("{prefix}arm_{short}{s}");
            out.push(spec(format!("wheel_{axle}_{side}"), &arm, p));
        }
    }
    for (axle, top) in [("front", car.spring_tops[0]), ("rear", car.spring_tops[1])] {
        for (side, p) in [("left", top), ("right", mirror(top))] {
            out.push(spec(format!("body_{axle}_{side}"), "car_body", p));
        }
    }
    out
}
