//! One axle of a compact file: its section, and the `trailing_arm_axle` data derived from
//! it. The arm pivots ahead of the wheel at wheel-centre height, spring and damper stand
//! vertically on it over the wheel centre (motion ratio 1), the corner geometry, bushing
//! and stops from the defaults file; the arm's mass is what the unsprung mass leaves
//! after wheel and tyre, lumped at the wheel centre.

use serde::Deserialize;

use super::defaults::CornerDefaults;
use super::{at, Ctx, Kind};
use crate::vehicle::geom::V;
use crate::vehicle::props::{Mass, WheelProps};
use crate::vehicle::swing::ArmPoints;
use crate::vehicle::trailing_arm_axle::{Props, Spring, SpringKind, WheelDamping};
use crate::vehicle::wheel;
use towride_mbs::input::{InputError, Seg};
use towride_mbs::model::desc::Law;
use towride_mbs::model::elements::StopSpec;
use towride_mbs::path;

/// One axle of the compact file (per corner).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(super) struct AxleSec {
    /// Mass moving with the wheel: wheel, tyre, brake, hub carrier, share of the arms
    /// and spring [kg].
    pub unsprung_kg: f64,
    pub spring: SpringSec,
    /// Damping at the wheel [N s/m] (or `damping_ratio`).
    pub damping_n_s_m: Option<f64>,
    /// Fraction of critical on the corner's ride rate.
    pub damping_ratio: Option<f64>,
    /// Damping at the wheel in compression (bump) [N s/m], with `damping_rebound_n_s_m`
    /// in place of `damping_n_s_m` / `damping_ratio`.
    pub damping_compression_n_s_m: Option<f64>,
    /// Damping at the wheel in rebound [N s/m].
    pub damping_rebound_n_s_m: Option<f64>,
    /// Roll stiffness an anti-roll bar adds at the axle [N m/rad].
    pub anti_roll_n_m_rad: Option<f64>,
    /// Wheel without tyre (rim, brake, hub) [kg].
    pub wheel_mass_kg: Option<f64>,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(super) struct SpringSec {
    pub kind: SpringKind,
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

/// The points of the left corner with its wheel centre at `w`: the defaults' corner
/// geometry.
pub(super) fn points(d: &CornerDefaults, w: V) -> ArmPoints {
    let spring_lower = [w[0], w[1] - d.spring_inboard_m, w[2]];
    let damper_lower = [w[0], w[1] - d.damper_inboard_m, w[2]];
    ArmPoints {
        wheel_centre: w,
        pivot: [w[0] + d.arm_length_m, w[1] - d.pivot_inboard_m, w[2]],
        spring_lower,
        spring_upper: [
            spring_lower[0],
            spring_lower[1],
            spring_lower[2] + d.spring_length_m,
        ],
        damper_lower,
        damper_upper: [
            damper_lower[0],
            damper_lower[1],
            damper_lower[2] + d.damper_length_m,
        ],
    }
}

/// What a corner is made of, left side.
pub(super) struct CornerParts {
    /// Wheel centre [m].
    pub wheel_centre: V,
    /// The wheel with the tyre's share that turns with it; the arm at the wheel centre.
    pub rim: Mass,
    pub arm: Mass,
    pub spring: Spring,
    /// Damping at the wheel.
    pub damping: WheelDamping,
    /// Static load of a corner [N] (the bump stop's scale).
    pub corner_load: f64,
    /// Where the spring is given in the compact file (errors of the design statics).
    pub spring_at: Vec<Seg>,
}

/// The `trailing_arm_axle` data of an axle of corners `c` with an anti-roll bar adding
/// `anti_roll` [N m/rad].
pub(super) fn axle(ctx: &Ctx, c: CornerParts, anti_roll: f64) -> Result<Props, InputError> {
    let d = &ctx.defaults.d.corner;
    let dsrc = &ctx.defaults.src;
    let w = c.wheel_centre;
    let bushing =
        d.pivot_bushing
            .check(dsrc, &path!["corner", "pivot_bushing"], [0.0, 1.0, 0.0])?;
    let track = 2.0 * w[1];
    // Roll twists the arms by t phi / L against each other: K_roll = k_t t^2 / L^2.
    let torsion = anti_roll * d.arm_length_m * d.arm_length_m / (track * track);
    let bump = StopSpec {
        clearance_m: d.bump_clearance_m,
        stiffness_n_m: d.bump_stop_load_factor * c.corner_load / d.bump_stop_reference_m.powi(2),
        exponent: 2.0,
        damping_n_s_m: d.bump_stop_damping_n_s_m,
        damping_depth_m: d.bump_stop_damping_depth_m,
    }
    .check()
    .map_err(|e| dsrc.locate(&path!["corner"], e))?;
    let rebound = StopSpec {
        clearance_m: d.rebound_clearance_m,
        stiffness_n_m: d.rebound_stiffness_n_m,
        exponent: 1.0,
        damping_n_s_m: 0.0,
        damping_depth_m: 0.0,
    }
    .check()
    .map_err(|e| dsrc.locate(&path!["corner"], e))?;
    Ok(Props {
        points: points(d, w),
        arm: c.arm,
        rim: c.rim,
        spring: c.spring,
        wheel_damping: c.damping,
        bump: Some(bump),
        rebound: Some(rebound),
        bushing,
        torsion: (Law::Linear(torsion), Law::Linear(0.0)),
        joints: None,
        spring_at: ctx.src.error(&c.spring_at, ""),
    })
}

/// The wheel (rim, brake, hub) and the arm of a corner with unsprung mass `mu`, tyre
/// `t` and rim diameter `rim_in` [in]: (rim with the tyre's share, arm) masses, left
/// side, at the wheel centre `w`.
pub(super) fn corner_masses(
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
    let props = WheelProps {
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
