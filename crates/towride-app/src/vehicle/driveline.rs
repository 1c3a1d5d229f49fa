//! A driveline that holds a set speed, like the thesis's engine: a PI controller on the
//! car body's forward speed sets the drive torque, split equally over the driven wheels
//! (an open differential) and reacted on their knuckles. An optional
//! `[driveline_inertia]` puts the engine's and gearbox's rotating inertia, reflected
//! through the gear and final-drive ratios (J i^2), on the differential: a shaft whose
//! spin follows the mean of the driven wheels' spins
//! ([`towride_mbs::model::desc::DrivelineInertia`]; docs/manoeuvres.md).

use std::path::Path;

use serde::Deserialize;

use super::wheel::WheelHandle;
use towride_mbs::input::InputError;
use towride_mbs::model::builder::MarkerHandle;
use towride_mbs::model::desc::{Brakes, DrivelineInertia, SpeedControl};
use towride_mbs::model::function::TimeFunction;
use towride_mbs::model::stick::StickFriction;
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    speed_control: Control,
    brakes: Option<BrakesSec>,
    driveline_inertia: Option<InertiaSec>,
}

/// Whether the driveline's rotating inertia is modelled.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
enum InertiaKind {
    /// Left out: the drive torque acts on the wheels directly.
    None,
    /// On the differential: a shaft geared to the driven wheels' mean spin.
    Differential,
}

/// The engine's and gearbox's rotating inertia on the differential.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct InertiaSec {
    kind: InertiaKind,
    /// Rotating inertia at the crank: flywheel, crank train, clutch, gearbox input [kg m^2].
    crank_side_inertia_kg_m2: f64,
    /// Ratio of the engaged gear [-].
    gear_ratio: f64,
    /// Final-drive ratio [-].
    final_drive_ratio: f64,
    /// Time constant of the coupling that gears the shaft to the wheels (a penalty
    /// regularisation of that constraint) [s].
    coupling_time_s: f64,
}

/// Friction brakes: what the speed controller asks beyond the engine's drag.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct BrakesSec {
    /// Share of the total brake torque on the front wheels (brake balance) [-].
    front_share: f64,
    /// Short names of the front and rear braked wheels.
    front_wheels: Vec<String>,
    rear_wheels: Vec<String>,
    /// Magnitude limit of the total brake torque at the wheels [N m].
    max_torque_n_m: f64,
    /// Drag torque the drive takes before the brakes engage (engine braking) [N m].
    engine_drag_n_m: f64,
    /// Width of the smooth hand-over from the drive to the brakes [N m].
    blend_n_m: f64,
    /// Bristle deflection at which a brake or the engine's drag slips, z_ss [rad].
    stick_deflection_rad: f64,
    /// Share of that deflection that stays elastic (no creep below it), z_ba / z_ss [-].
    stick_elastic_share: f64,
    /// Damping time constant of the bristle [s].
    stick_damping_s: f64,
    /// Brake torque a driver keeps on at a standstill [N m].
    hold_torque_n_m: f64,
    /// Target speed below which that hold comes in [m/s].
    hold_below_m_s: f64,
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
        feedforward_kg_m: 0.0,
        brakes: None,
        driveline: None,
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
    let find = |names: &[String], key: &str, table: &str| {
        names
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let w = wheels.iter().find(|w| &w.name == name).ok_or_else(|| {
                    let known: Vec<&str> = wheels.iter().map(|w| w.name.as_str()).collect();
                    src.error(
                        &path![table, key, k],
                        format!("no wheel '{name}' (the car has {})", known.join(", ")),
                    )
                })?;
                Ok((w.centre, w.carrier_centre))
            })
            .collect::<Result<Vec<_>, InputError>>()
    };
    let driven = find(&c.driven_wheels, "driven_wheels", "speed_control")?;
    let brakes = match &f.brakes {
        None => None,
        Some(b) => {
            let p = |k: &str| path!["brakes", k];
            let front = src.non_negative(&p("front_share"), b.front_share)?;
            if front > 1.0 {
                return Err(src.error(
                    &p("front_share"),
                    format!("is a share of the brake torque, 0 to 1, got {front}"),
                ));
            }
            let elastic_share = |x: f64| {
                let x = src.non_negative(&p("stick_elastic_share"), x)?;
                if x >= 1.0 {
                    return Err(src.error(
                        &p("stick_elastic_share"),
                        format!("is a share of the slip deflection, 0 to below 1, got {x}"),
                    ));
                }
                Ok(x)
            };
            let mut shared = Vec::new();
            for (key, names, share) in [
                ("front_wheels", &b.front_wheels, front),
                ("rear_wheels", &b.rear_wheels, 1.0 - front),
            ] {
                if names.is_empty() && share > 0.0 {
                    return Err(src.error(&p(key), "name the wheels that take this share"));
                }
                for (w, c) in find(names, key, "brakes")? {
                    shared.push((w, c, share / names.len() as f64));
                }
            }
            Some(Brakes {
                wheels: shared,
                max_torque: src.positive(&p("max_torque_n_m"), b.max_torque_n_m)?,
                engine_drag: src.non_negative(&p("engine_drag_n_m"), b.engine_drag_n_m)?,
                blend: src.positive(&p("blend_n_m"), b.blend_n_m)?,
                stick: StickFriction {
                    deflection_rad: src
                        .positive(&p("stick_deflection_rad"), b.stick_deflection_rad)?,
                    elastic_share: elastic_share(b.stick_elastic_share)?,
                    damping_s: src.non_negative(&p("stick_damping_s"), b.stick_damping_s)?,
                },
                hold_torque: src.non_negative(&p("hold_torque_n_m"), b.hold_torque_n_m)?,
                hold_speed: src.positive(&p("hold_below_m_s"), b.hold_below_m_s)?,
            })
        }
    };
    let driveline = match &f.driveline_inertia {
        Some(d) if d.kind == InertiaKind::Differential => {
            let p = |k: &str| path!["driveline_inertia", k];
            let j = src.positive(&p("crank_side_inertia_kg_m2"), d.crank_side_inertia_kg_m2)?;
            let gear = src.positive(&p("gear_ratio"), d.gear_ratio)?;
            let final_drive = src.positive(&p("final_drive_ratio"), d.final_drive_ratio)?;
            let tau = src.positive(&p("coupling_time_s"), d.coupling_time_s)?;
            // Kinetic energy J w_crank^2 / 2 with w_crank = i w_wheels: J i^2 at the wheels.
            let inertia = j * (gear * final_drive).powi(2);
            Some(DrivelineInertia {
                inertia,
                coupling: inertia / tau,
            })
        }
        _ => None,
    };
    Ok(SpeedControl {
        name: "driveline".into(),
        sensor,
        target: TimeFunction::Constant { value: speed },
        kp,
        ki,
        max_torque,
        wheels: driven,
        feedforward_kg_m: 0.0,
        brakes,
        driveline,
    })
}
