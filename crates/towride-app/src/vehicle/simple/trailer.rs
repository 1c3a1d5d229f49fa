//! The compact file's optional trailer, translated into the `lumped_trailer` template's
//! data: a rigid box on one trailing-arm axle (its corners derived as the car's,
//! [`super::corner`]), coupled at a ball fixed on the car body. Trailer coordinates:
//! origin on the ground under the ball, x towards the car.

use serde::Deserialize;

use super::corner::{self, corner_masses, AxleSec, CornerParts};
use super::suspension::suspension;
use super::tyre::{self, TyreSec};
use super::{Ctx, Kind};
use crate::vehicle::axle::AxleSpec;
use crate::vehicle::description::{TrailerDesc, TyreSpec};
use crate::vehicle::design::{centre_of_mass, lever};
use crate::vehicle::geom::V;
use crate::vehicle::lumped_trailer::{self, Props};
use crate::vehicle::props::Mass;
use crate::vehicle::trailer::TrailerSpec;
use crate::vehicle::Options;
use towride_mbs::input::InputError;
use towride_mbs::path;
use towride_mbs::tyre::TyreKind;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct TrailerSec {
    /// The trailer as it is preloaded (without the load cases' payload) [kg].
    mass_kg: f64,
    /// Centre of mass behind the ball [m] and above ground [m].
    cg_behind_ball_m: f64,
    cg_height_m: f64,
    /// Axle behind the ball [m].
    axle_behind_ball_m: f64,
    track_m: f64,
    /// The ball on the car: height above ground and distance behind the rear axle [m].
    ball_height_m: f64,
    ball_behind_rear_axle_m: f64,
    axle: AxleSec,
    tyre: TyreSec,
    #[serde(default)]
    load_case: Vec<LoadCase>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct LoadCase {
    name: String,
    /// Added mass [kg], its centre behind the ball and above ground [m] (a block on the
    /// floor: its own inertia is left out).
    payload_kg: f64,
    payload_behind_ball_m: f64,
    payload_height_m: f64,
}

/// The trailer slot and what the rest of the translation needs of it.
pub(super) struct Towed {
    pub desc: TrailerDesc,
    /// The ball on the car body, car coordinates [m].
    pub ball: V,
    /// With the payload [kg] (the file's numbers).
    pub mass_kg: f64,
    /// Left wheel centre, trailer coordinates [m].
    pub wheel_centre: V,
}

/// The load-case names of a compact file's trailer.
fn load_cases(t: &TrailerSec) -> Vec<String> {
    t.load_case.iter().map(|c| c.name.clone()).collect()
}

/// The trailer of `t` behind a car of wheelbase `wheelbase` [m], tyres of model `kind`,
/// the load case `opts.load_case` (the first when `None`).
pub(super) fn translate(
    ctx: &Ctx,
    t: &TrailerSec,
    wheelbase: f64,
    opts: &Options,
    kind: TyreKind,
) -> Result<Towed, InputError> {
    let src = &ctx.src;
    let p = |k: &str| path!["trailer", k];
    let mass = src.positive(&p("mass_kg"), t.mass_kg)?;
    let xc = -src.positive(&p("cg_behind_ball_m"), t.cg_behind_ball_m)?;
    let zc = src.positive(&p("cg_height_m"), t.cg_height_m)?;
    let xa = -src.positive(&p("axle_behind_ball_m"), t.axle_behind_ball_m)?;
    let track = src.positive(&p("track_m"), t.track_m)?;
    let hb = src.positive(&p("ball_height_m"), t.ball_height_m)?;
    let behind = src.positive(&p("ball_behind_rear_axle_m"), t.ball_behind_rear_axle_m)?;
    let mu = src.positive(&path!["trailer", "axle", "unsprung_kg"], t.axle.unsprung_kg)?;
    let (ball_load, axle_load) = lever(mass * ctx.g, xc, 0.0, xa);
    if ball_load < 0.0 || axle_load <= 0.0 {
        return Err(src.error(
            &p("cg_behind_ball_m"),
            "the centre of mass must lie between the ball and the axle",
        ));
    }
    let corner_load = 0.5 * axle_load;
    let (tyre, r0) = tyre::build(ctx, &t.tyre, &path!["trailer", "tyre"], kind, corner_load)?;
    let cz = tyre.params().cz;
    let rim_in = tyre::parse_size(&t.tyre.size).map_or(13.0, |s| s.2);
    let w = [xa, 0.5 * track, r0 - corner_load / cz];
    let axle_at = path!["trailer", "axle"];
    let (rim, arm) = corner_masses(ctx, &t.axle, &axle_at, &tyre, rim_in, w)?;
    let sprung = mass - 2.0 * mu;
    let cm = [
        (mass * xc - 2.0 * mu * xa) / sprung,
        0.0,
        (mass * zc - 2.0 * mu * w[2]) / sprung,
    ];
    if sprung <= 0.0 || cm[2] <= 0.0 {
        return Err(src.error(
            &p("cg_height_m"),
            "the trailer's sprung body must have positive mass and height",
        ));
    }
    let d = &ctx.defaults.d.body;
    let ky = (d.dynamic_index * (-cm[0]) * (cm[0] - xa)).sqrt();
    let (kx, kz) = (
        d.roll_gyration_per_track * track,
        d.yaw_gyration_per_pitch_gyration * ky,
    );
    for (k, v) in [
        ("trailer.radii_of_gyration_m[0]", kx),
        ("trailer.radii_of_gyration_m[1]", ky),
        ("trailer.radii_of_gyration_m[2]", kz),
    ] {
        ctx.default(k, v, "m", "body (ball and axle as the supports)");
    }
    let body = Mass {
        mass: sprung,
        cm,
        inertia: [
            [sprung * kx * kx, 0.0, 0.0],
            [0.0, sprung * ky * ky, 0.0],
            [0.0, 0.0, sprung * kz * kz],
        ],
    };
    // The load case: the first when none is asked for.
    let case = match (opts.load_case.as_deref(), t.load_case.first()) {
        (None, None) => None,
        (None, Some(c)) => Some(c),
        (Some(n), _) => Some(t.load_case.iter().find(|c| c.name == n).ok_or_else(|| {
            src.error(
                &p("load_case"),
                format!("no load case '{n}' (cases: {})", load_cases(t).join(", ")),
            )
        })?),
    };
    let mut payload = None;
    if let Some(c) = case {
        let pm = src.non_negative(&p("load_case"), c.payload_kg)?;
        if pm > 0.0 {
            payload = Some(Mass {
                mass: pm,
                cm: [-c.payload_behind_ball_m, 0.0, c.payload_height_m],
                inertia: [[0.0; 3]; 3],
            });
        }
    }
    let (spring, damping) = suspension(ctx, &t.axle, &axle_at, corner_load, mu, cz)?;
    let anti_roll = t
        .axle
        .anti_roll_n_m_rad
        .unwrap_or(ctx.defaults.d.corner.anti_roll_n_m_rad);
    let parts = CornerParts {
        wheel_centre: w,
        rim,
        arm,
        spring,
        damping,
        corner_load,
        spring_at: path!["trailer", "axle", "spring"].to_vec(),
    };
    let axle = corner::axle(ctx, parts, anti_roll)?;
    ctx.note(
        "trailer.ball_load_n",
        ball_load,
        "N",
        Kind::Derived,
        "lever rule between ball and axle".into(),
    );
    let mut all = vec![(mass, [xc, 0.0, zc])];
    if let Some(m) = &payload {
        all.push((m.mass, m.cm));
    }
    let data = Props {
        coupling: [0.0, 0.0, hb],
        body,
        axle: AxleSpec::Given(Box::new(axle)),
        payload,
        load_case: case.map_or(lumped_trailer::AS_GIVEN.into(), |c| c.name.clone()),
        origin: format!("{} [trailer]", src.path.display()),
    };
    Ok(Towed {
        desc: TrailerDesc {
            spec: TrailerSpec::Given(Box::new(data)),
            tyre: TyreSpec::Given(Box::new(tyre)),
            at: path!["trailer"].to_vec(),
            assumed: Vec::new(),
        },
        ball: [-wheelbase - behind, 0.0, hb],
        mass_kg: centre_of_mass(&all).0,
        wheel_centre: w,
    })
}
