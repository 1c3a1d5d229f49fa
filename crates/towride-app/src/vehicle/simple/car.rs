//! The car of a compact file: the lumped body's mass properties from the total mass,
//! axle loads and centre-of-gravity height less the unsprung corners, the wheel centres
//! at the tyre's loaded radius, each axle's `trailing_arm_axle` data ([`super::corner`]).

use serde::Deserialize;

use super::corner::{self, corner_masses, AxleSec, CornerParts};
use super::suspension::suspension;
use super::{tyre, Ctx, File, Kind};
use crate::vehicle::axle::AxleSpec;
use crate::vehicle::description::{AxleDesc, BodySpec, TyreSpec};
use crate::vehicle::geom::V;
use crate::vehicle::props::Mass;
use towride_mbs::input::InputError;
use towride_mbs::path;
use towride_mbs::tyre::TyreKind;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct MassSec {
    /// With driver [kg].
    total_kg: f64,
    /// Static front axle load [kg].
    front_axle_kg: f64,
    /// Centre of mass above ground [m].
    cg_height_m: f64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct BodySec {
    /// Roll, pitch, yaw radii of gyration of the sprung body [m].
    radii_of_gyration_m: [f64; 3],
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct GeometrySec {
    wheelbase_m: f64,
    front_track_m: f64,
    rear_track_m: f64,
}

/// The car's slots and what the rest of the translation needs of it.
pub(super) struct Car {
    pub body: BodySpec,
    pub axles: [AxleDesc; 2],
    /// With driver [kg].
    pub total_kg: f64,
    pub wheelbase_m: f64,
    /// Rear wheel centre height: the loaded radius [m].
    pub rear_radius_m: f64,
    /// Left wheel centres, front and rear [m].
    pub wheel_centres: [V; 2],
    /// Left upper spring seats on the body, front and rear [m].
    pub spring_tops: [V; 2],
}

/// The lowest static stability factor t/2h accepted: margin below the 1.0 of the most
/// top-heavy vans (NHTSA, Rollover Resistance notice, ch. V).
const MIN_SSF: f64 = 0.8;

/// The car of `f` with tyres of model `kind`.
pub(super) fn translate(ctx: &Ctx, f: &File, kind: TyreKind) -> Result<Car, InputError> {
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
    // A centre of mass too high for the track: the static stability factor t/2h of
    // cars and vans lies near 1.0-1.5 (NHTSA, Rollover Resistance notice, ch. V); below
    // MIN_SSF the vehicle would tip over at a lateral acceleration no car tips at.
    let ssf = 0.25 * (tf + tr) / h;
    if ssf < MIN_SSF {
        return Err(src.error(
            &path!["mass", "cg_height_m"],
            format!(
                "{h} m over a mean track of {:.2} m gives a static stability factor t/2h of {ssf:.2}; cars and vans have 1.0-1.5 (NHTSA), this file needs at least {MIN_SSF}",
                0.5 * (tf + tr)
            ),
        ));
    }
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
    let (tyre, r0) = tyre::build(ctx, &f.tyre, &path!["tyre"], kind, load_f)?;
    let cz = tyre.params().cz;
    let rim_in = tyre::parse_size(&f.tyre.size).map_or(16.0, |s| s.2);
    // Wheel centres at the loaded radius under the static corner loads.
    let zf = r0 - load_f / cz;
    let zr = r0 - load_r / cz;
    let wf = [0.0, 0.5 * tf, zf];
    let wr = [-l, 0.5 * tr, zr];
    let (rim_f, arm_f) = corner_masses(ctx, &f.front, &path!["front"], &tyre, rim_in, wf)?;
    let (rim_r, arm_r) = corner_masses(ctx, &f.rear, &path!["rear"], &tyre, rim_in, wr)?;
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
            // Each principal moment at most the sum of the other two (a rigid body's
            // triangle inequality): blamed on the default that set the offending radius.
            let k2 = [kx * kx, ky * ky, kz * kz];
            let keys = [
                "roll_gyration_per_track",
                "dynamic_index",
                "yaw_gyration_per_pitch_gyration",
            ];
            for i in 0..3 {
                let others = k2[(i + 1) % 3] + k2[(i + 2) % 3];
                if k2[i] > others {
                    return Err(ctx.defaults.src.error(
                        &path!["body", keys[i]],
                        format!(
                            "gives radii of gyration {kx:.3}, {ky:.3}, {kz:.3} m: no rigid body has a principal moment larger than the other two together"
                        ),
                    ));
                }
            }
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
    let (spring_f, damp_f) = suspension(ctx, &f.front, &path!["front"], load_f, mu_f, cz)?;
    let (spring_r, damp_r) = suspension(ctx, &f.rear, &path!["rear"], load_r, mu_r, cz)?;

    let slot = |parts: CornerParts, anti_roll: f64| {
        Ok::<_, InputError>(AxleDesc {
            spec: AxleSpec::Given(Box::new(corner::axle(ctx, parts, anti_roll)?)),
            tyre: TyreSpec::Given(Box::new(tyre.clone())),
        })
    };
    let front = CornerParts {
        wheel_centre: wf,
        rim: rim_f,
        arm: arm_f,
        spring: spring_f,
        damping: damp_f,
        corner_load: load_f,
        spring_at: path!["front", "spring"].to_vec(),
    };
    let front = slot(front, anti_roll(ctx, &f.front, "front")?)?;
    let rear = CornerParts {
        wheel_centre: wr,
        rim: rim_r,
        arm: arm_r,
        spring: spring_r,
        damping: damp_r,
        corner_load: load_r,
        spring_at: path!["rear", "spring"].to_vec(),
    };
    let rear = slot(rear, anti_roll(ctx, &f.rear, "rear")?)?;
    note_geometry(ctx);
    let d = &ctx.defaults.d.corner;
    Ok(Car {
        body: BodySpec::Given(body_mass),
        axles: [front, rear],
        total_kg: total,
        wheelbase_m: l,
        rear_radius_m: zr,
        wheel_centres: [wf, wr],
        spring_tops: [
            corner::points(d, wf).spring_upper,
            corner::points(d, wr).spring_upper,
        ],
    })
}

/// The roll stiffness an anti-roll bar adds at the axle `a` (at `p`) [N m/rad].
fn anti_roll(ctx: &Ctx, a: &AxleSec, p: &str) -> Result<f64, InputError> {
    Ok(match a.anti_roll_n_m_rad {
        Some(k) => ctx.src.non_negative(&path![p, "anti_roll_n_m_rad"], k)?,
        None => {
            let k = ctx.defaults.d.corner.anti_roll_n_m_rad;
            ctx.default(
                &format!("{p}.anti_roll_n_m_rad"),
                k,
                "N m/rad",
                "corner.anti_roll_n_m_rad",
            )
        }
    })
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
