//! A scene's longitudinal manoeuvre: the speed the driveline and the brakes follow, a
//! jerk-limited change from the set speed (braking to a stop, braking over an
//! obstacle, accelerating) instead of a held speed.
//!
//! ```toml
//! [run.manoeuvre]
//! start_s = 0.5                # when the change starts [s]
//! to_speed_km_h = 0.0          # the speed it ends at
//! acceleration_m_s2 = 5.0      # magnitude of the (de)celeration held meanwhile
//! jerk_m_s3 = 25.0             # how fast the (de)celeration builds and falls
//! ```
//!
//! The controller follows the target with a feed-forward torque (the vehicle's mass
//! times the target's rate times the rolling radius) and its PI loop; what it asks
//! beyond the drive's drag goes to the friction brakes of the driveline file
//! (`[brakes]`). Whether the tyres can carry it is the model's answer, not a check here.

use serde::Deserialize;

use towride_mbs::input::{InputError, Source};
use towride_mbs::model::function::TimeFunction;
use towride_mbs::path;

/// `[run.manoeuvre]`.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct ManoeuvreSec {
    start_s: f64,
    to_speed_km_h: f64,
    acceleration_m_s2: f64,
    jerk_m_s3: f64,
}

/// The speed target of a manoeuvre starting from `speed` [m/s] in a run of `duration`
/// [s], checked field by field.
pub fn target(
    src: &Source,
    sec: &ManoeuvreSec,
    speed: f64,
    duration: f64,
) -> Result<TimeFunction, InputError> {
    let p = |k: &str| path!["run", "manoeuvre", k];
    let start = src.non_negative(&p("start_s"), sec.start_s)?;
    if start >= duration {
        return Err(src.error(
            &p("start_s"),
            format!("starts at {start} s, after the run's {duration} s"),
        ));
    }
    let to = src.non_negative(&p("to_speed_km_h"), sec.to_speed_km_h)? / 3.6;
    let rate = src.positive(&p("acceleration_m_s2"), sec.acceleration_m_s2)?;
    let jerk = src.positive(&p("jerk_m_s3"), sec.jerk_m_s3)?;
    let f = TimeFunction::JerkLimited {
        start_s: start,
        from: speed,
        to,
        rate,
        jerk,
    };
    f.check()
        .map_err(|e| src.error(&p("acceleration_m_s2"), e.to_string()))?;
    Ok(f)
}

/// True when the manoeuvre slows the vehicle (it then needs brakes).
pub fn slows(f: &TimeFunction) -> bool {
    matches!(f, TimeFunction::JerkLimited { from, to, .. } if to < from)
}

/// `[run.steering]`: the steering rack's travel to the left [m] over time, any function
/// of time of the mechanism files (`{ type = "table", time_s = [...], value = [...] }` for
/// a lane change). With the tie rods behind the wheel centres (the Fabia's rack sits
/// behind the front axle), rack travel to the left steers the car to the right.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SteeringSec {
    rack_m: TimeFunction,
}

/// The rack travel of `sec`, checked.
pub fn steering(src: &Source, sec: &SteeringSec) -> Result<TimeFunction, InputError> {
    sec.rack_m
        .check()
        .map_err(|e| src.error(&path!["run", "steering", "rack_m"], e.to_string()))?;
    Ok(sec.rack_m.clone())
}
