//! The compact file's optional trailer: a rigid box on one trailing-arm axle (the simple
//! set's corner, [`super::corner`]), coupled to the car body at the ball by a spherical
//! joint. Trailer coordinates as for the box trailer: origin on the ground under the
//! ball, x towards the car.

use serde::Deserialize;

use super::corner::{self, AxleInput};
use super::tyre::{self, TyreSec};
use super::{AxleSec, Ctx, Kind};
use crate::vehicle::build::{Builder, Link};
use crate::vehicle::design::{centre_of_mass, lever};
use crate::vehicle::geom::{IDENTITY, V};
use crate::vehicle::hitch::BallKind;
use crate::vehicle::props::Mass;
use crate::vehicle::trailer::merge;
use crate::vehicle::wheel::WheelHandle;
use crate::vehicle::{Options, TrailerDesign};
use towride_mbs::input::InputError;
use towride_mbs::model::builder::{BodyHandle, Placement};
use towride_mbs::model::desc::JointKind;
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

pub(super) struct Built {
    pub body: BodyHandle,
    pub wheels: Vec<WheelHandle>,
    pub ball: (Link, BallKind),
    pub place: Placement,
    pub design: TrailerDesign,
}

/// The load-case names of a compact file's trailer (empty without a trailer).
pub(super) fn load_cases(t: &TrailerSec) -> Vec<String> {
    t.load_case.iter().map(|c| c.name.clone()).collect()
}

/// Builds the trailer behind the rear axle at `rear_axle` (car coordinates).
pub(super) fn build(
    ctx: &Ctx,
    b: &mut Builder,
    t: &TrailerSec,
    car_body: BodyHandle,
    rear_axle: V,
    opts: &Options,
    kind: TyreKind,
) -> Result<Built, InputError> {
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
    let (rim, arm) =
        super::corner_masses(ctx, &t.axle, &path!["trailer", "axle"], &tyre, rim_in, w)?;
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
    let mut body_mass = Mass {
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
            let m = Mass {
                mass: pm,
                cm: [-c.payload_behind_ball_m, 0.0, c.payload_height_m],
                inertia: [[0.0; 3]; 3],
            };
            body_mass = merge(&body_mass, &m);
            payload = Some(m);
        }
    }
    let (spring, damping) =
        super::suspension(ctx, &t.axle, &path!["trailer", "axle"], corner_load, mu, cz)?;
    let car_place = b.mb.place();
    let ball = [rear_axle[0] - behind, 0.0, hb];
    let place = Placement::translate([car_place.point(ball)[0], 0.0, 0.0]);
    b.set_place(place);
    let body = b.body("trailer_box", &body_mass)?;
    let anti_roll = t
        .axle
        .anti_roll_n_m_rad
        .unwrap_or(ctx.defaults.d.corner.anti_roll_n_m_rad);
    let axle = corner::build(
        ctx,
        b,
        &AxleInput {
            centre: "trailer_axle",
            prefix: "trailer_arm",
            wheels: ["tl", "tr"],
            carrier: body,
            wheel_centre: w,
            tyre: &tyre,
            arm,
            rim,
            spring,
            damping,
            anti_roll,
            corner_load,
            spring_at: path!["trailer", "axle", "spring"].to_vec(),
        },
    )?;
    let mut corners = Vec::new();
    for pend in axle.pending {
        corners.push(corner::finish(ctx, b, pend, corner_load)?.0);
    }
    b.set_place(car_place);
    // A bushing measures I relative to J: with joints as bushings the drawbar is I (the
    // hitch channels take minus its force), as in the modal hitch's coupling.
    let link = match &opts.joints_as_bushings {
        None => b.add(|m| {
            m.joint(
                "ball_coupling",
                JointKind::Spherical,
                Some(car_body),
                Some(body),
                ball,
                &IDENTITY,
                None,
            )
        })?,
        Some(_) => b.add(|m| {
            m.joint(
                "ball_coupling",
                JointKind::Spherical,
                Some(body),
                Some(car_body),
                ball,
                &IDENTITY,
                None,
            )
        })?,
    };
    let ball_kind = match &opts.joints_as_bushings {
        None => BallKind::Spherical,
        Some(jb) => BallKind::Bushing(jb.clone()),
    };
    ctx.note(
        "trailer.ball_load_n",
        ball_load,
        "N",
        Kind::Derived,
        "lever rule between ball and axle".into(),
    );
    let mut parts = vec![(mass, [xc, 0.0, zc])];
    if let Some(m) = &payload {
        parts.push((m.mass, m.cm));
    }
    let (total, cm_all) = centre_of_mass(&parts);
    Ok(Built {
        body,
        wheels: axle.wheels,
        ball: (link, ball_kind),
        place,
        design: TrailerDesign {
            load_case: case.map_or("as_given".into(), |c| c.name.clone()),
            mass_kg: total,
            cm_m: cm_all,
            empty_ball_load_n: ball_load,
            corners,
            pitch_rad: 0.0,
        },
    })
}
