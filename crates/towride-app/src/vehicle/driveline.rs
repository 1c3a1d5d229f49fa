//! A driveline that holds a set speed, like the thesis's engine: a PI controller on the
//! car body's forward speed sets the drive torque, split equally over the driven wheels
//! (an open differential) and reacted on their knuckles.

use std::path::Path;

use serde::Deserialize;

use super::wheel::WheelHandle;
use towride_mbs::input::InputError;
use towride_mbs::model::builder::MarkerHandle;
use towride_mbs::model::desc::SpeedControl;
use towride_mbs::model::function::TimeFunction;
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    speed_control: Control,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Control {
    /// Total drive torque per unit speed error [N m s/m].
    proportional_n_m_s_per_m: f64,
    /// Total drive torque per unit distance error [N m/m].
    integral_n_m_per_m: f64,
    /// Magnitude limit of the total drive torque [N m].
    max_torque_n_m: f64,
    /// Short names of the driven wheels.
    driven_wheels: Vec<String>,
}

/// A speed controller's gains and driven wheels (a compact file's derived values).
#[derive(Clone, Debug)]
pub struct Gains {
    /// Total drive torque per unit speed error [N m s/m].
    pub proportional_n_m_s_per_m: f64,
    /// Total drive torque per unit distance error [N m/m].
    pub integral_n_m_per_m: f64,
    /// Magnitude limit of the total drive torque [N m].
    pub max_torque_n_m: f64,
    /// Short names of the driven wheels.
    pub driven_wheels: Vec<String>,
}

/// The speed controller of `g` holding `speed` [m/s], measured along x of the marker
/// `sensor`, driving those of `wheels` that `g` names (in `wheels`' order).
pub fn control(
    g: &Gains,
    sensor: MarkerHandle,
    speed: f64,
    wheels: &[WheelHandle],
) -> SpeedControl {
    SpeedControl {
        name: "driveline".into(),
        sensor,
        target: TimeFunction::Constant { value: speed },
        kp: g.proportional_n_m_s_per_m,
        ki: g.integral_n_m_per_m,
        max_torque: g.max_torque_n_m,
        wheels: wheels
            .iter()
            .filter(|w| g.driven_wheels.contains(&w.name))
            .map(|w| (w.centre, w.carrier_centre))
            .collect(),
    }
}

/// Reads `file`: a speed controller holding `speed` [m/s], measured along x of the
/// marker `sensor`, driving the named `wheels`.
pub fn build(
    file: &Path,
    sensor: MarkerHandle,
    speed: f64,
    wheels: &[WheelHandle],
    loader: &towride_mbs::input::Loader,
) -> Result<SpeedControl, InputError> {
    let src = loader.toml(file)?;
    let f: File = src.parse()?;
    let c = &f.speed_control;
    let p = |k: &str| path!["speed_control", k];
    let kp = src.positive(&p("proportional_n_m_s_per_m"), c.proportional_n_m_s_per_m)?;
    let ki = src.non_negative(&p("integral_n_m_per_m"), c.integral_n_m_per_m)?;
    let max_torque = src.positive(&p("max_torque_n_m"), c.max_torque_n_m)?;
    if c.driven_wheels.is_empty() {
        return Err(src.error(&p("driven_wheels"), "name at least one driven wheel"));
    }
    let mut driven = Vec::new();
    for (k, name) in c.driven_wheels.iter().enumerate() {
        let w = wheels.iter().find(|w| &w.name == name).ok_or_else(|| {
            let known: Vec<&str> = wheels.iter().map(|w| w.name.as_str()).collect();
            src.error(
                &path!["speed_control", "driven_wheels", k],
                format!("no wheel '{name}' (the car has {})", known.join(", ")),
            )
        })?;
        driven.push((w.centre, w.carrier_centre));
    }
    Ok(SpeedControl {
        name: "driveline".into(),
        sensor,
        target: TimeFunction::Constant { value: speed },
        kp,
        ki,
        max_torque,
        wheels: driven,
    })
}
