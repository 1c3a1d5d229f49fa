//! The defaults file of the `simple` vehicle files (`vehicles/simple_defaults.toml`): the
//! values a compact vehicle file may leave out, each documented there with its source.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::vehicle::props::BushingProps;
use towride_mbs::input::{InputError, Loader, Source};
use towride_mbs::tyre::TyreKind;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct Defaults {
    pub vehicle: VehicleDefaults,
    pub body: BodyDefaults,
    pub corner: CornerDefaults,
    pub air_spring: AirDefaults,
    pub tyre: TyreDefaults,
    pub driveline: DrivelineDefaults,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct VehicleDefaults {
    pub gravity_m_s2: [f64; 3],
    pub tyre_model: TyreKind,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct BodyDefaults {
    pub dynamic_index: f64,
    pub roll_gyration_per_track: f64,
    pub yaw_gyration_per_pitch_gyration: f64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct CornerDefaults {
    pub arm_length_m: f64,
    pub arm_gyration_m: f64,
    pub pivot_inboard_m: f64,
    pub spring_inboard_m: f64,
    pub damper_inboard_m: f64,
    pub spring_length_m: f64,
    pub damper_length_m: f64,
    pub wheel_mass_at_16in_kg: f64,
    pub wheel_spin_inertia_per_m_rrim2: f64,
    pub wheel_tilt_per_spin: f64,
    pub damping_ratio: f64,
    /// Wheel velocity over which compression and rebound rates blend [m/s]; needed only
    /// by a file giving the two.
    #[serde(default)]
    pub damper_transition_m_s: Option<f64>,
    pub anti_roll_n_m_rad: f64,
    pub bump_clearance_m: f64,
    pub bump_stop_load_factor: f64,
    pub bump_stop_reference_m: f64,
    pub bump_stop_damping_n_s_m: f64,
    pub bump_stop_damping_depth_m: f64,
    pub rebound_clearance_m: f64,
    pub rebound_stiffness_n_m: f64,
    pub pivot_bushing: BushingProps,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct AirDefaults {
    pub polytropic_exponent: f64,
    pub atmosphere_pa: f64,
    pub table_span: f64,
    pub table_points: usize,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct TyreDefaults {
    pub base: String,
    pub mass_per_width_radius_kg_m2: f64,
    pub belt_share: f64,
    pub inertia_per_m_r0sq: f64,
    pub belt_inertia_per_m_r0sq: f64,
    pub longitudinal_per_vertical: f64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct DrivelineDefaults {
    pub driven: super::drive::Driven,
    pub bandwidth_hz: f64,
    pub damping_ratio: f64,
    pub max_acceleration_g: f64,
}

/// The defaults read and checked, with the file they came from.
pub(super) struct Read {
    pub d: Defaults,
    pub src: Source,
    pub path: PathBuf,
}

/// Reads and checks the defaults file (every number positive where it must be).
pub(super) fn read(path: &Path, loader: &Loader) -> Result<Read, InputError> {
    let src = loader.toml(path)?;
    let d: Defaults = src.parse()?;
    let c = &d.corner;
    for (k, v) in [
        ("arm_length_m", c.arm_length_m),
        ("arm_gyration_m", c.arm_gyration_m),
        ("spring_length_m", c.spring_length_m),
        ("damper_length_m", c.damper_length_m),
        ("wheel_mass_at_16in_kg", c.wheel_mass_at_16in_kg),
        (
            "wheel_spin_inertia_per_m_rrim2",
            c.wheel_spin_inertia_per_m_rrim2,
        ),
        ("wheel_tilt_per_spin", c.wheel_tilt_per_spin),
        ("damping_ratio", c.damping_ratio),
        ("bump_stop_load_factor", c.bump_stop_load_factor),
        ("bump_stop_reference_m", c.bump_stop_reference_m),
        ("rebound_stiffness_n_m", c.rebound_stiffness_n_m),
    ] {
        src.positive(&towride_mbs::path!["corner", k], v)?;
    }
    for (k, v) in [
        ("pivot_inboard_m", c.pivot_inboard_m),
        ("spring_inboard_m", c.spring_inboard_m),
        ("damper_inboard_m", c.damper_inboard_m),
        ("anti_roll_n_m_rad", c.anti_roll_n_m_rad),
        ("bump_clearance_m", c.bump_clearance_m),
        ("bump_stop_damping_n_s_m", c.bump_stop_damping_n_s_m),
        ("bump_stop_damping_depth_m", c.bump_stop_damping_depth_m),
        ("rebound_clearance_m", c.rebound_clearance_m),
    ] {
        src.non_negative(&towride_mbs::path!["corner", k], v)?;
    }
    let b = &d.body;
    for (k, v) in [
        ("dynamic_index", b.dynamic_index),
        ("roll_gyration_per_track", b.roll_gyration_per_track),
        (
            "yaw_gyration_per_pitch_gyration",
            b.yaw_gyration_per_pitch_gyration,
        ),
    ] {
        src.positive(&towride_mbs::path!["body", k], v)?;
    }
    let a = &d.air_spring;
    src.positive(
        &towride_mbs::path!["air_spring", "polytropic_exponent"],
        a.polytropic_exponent,
    )?;
    src.non_negative(
        &towride_mbs::path!["air_spring", "atmosphere_pa"],
        a.atmosphere_pa,
    )?;
    let t = &d.tyre;
    for (k, v) in [
        ("mass_per_width_radius_kg_m2", t.mass_per_width_radius_kg_m2),
        ("belt_share", t.belt_share),
        ("inertia_per_m_r0sq", t.inertia_per_m_r0sq),
        ("belt_inertia_per_m_r0sq", t.belt_inertia_per_m_r0sq),
        ("longitudinal_per_vertical", t.longitudinal_per_vertical),
    ] {
        src.positive(&towride_mbs::path!["tyre", k], v)?;
    }
    if t.belt_share >= 1.0 {
        return Err(src.error(&towride_mbs::path!["tyre", "belt_share"], "must be below 1"));
    }
    let dl = &d.driveline;
    for (k, v) in [
        ("bandwidth_hz", dl.bandwidth_hz),
        ("damping_ratio", dl.damping_ratio),
        ("max_acceleration_g", dl.max_acceleration_g),
    ] {
        src.positive(&towride_mbs::path!["driveline", k], v)?;
    }
    Ok(Read {
        d,
        src,
        path: path.to_path_buf(),
    })
}
