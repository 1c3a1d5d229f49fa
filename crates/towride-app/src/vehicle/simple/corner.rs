//! One axle of the simple set: two trailing arms on body bushings joined on the
//! centreline (the swing-axle layout of the twist beam and the trailer axle,
//! [`crate::vehicle::swing`]), a spring and a damper standing vertically on each arm over
//! the wheel centre, bump and rebound stops on the damper. The arm pivots ahead of the
//! wheel at wheel-centre height, so at the design position the wheel moves vertically and
//! spring and damper move with it (motion ratio 1).

use super::air::AirSpring;
use super::Ctx;
use crate::vehicle::build::Builder;
use crate::vehicle::design::{self, Corner, CornerDesign, CornerRates, Preloaded};
use crate::vehicle::geom::{length_rate, mirror, turning, V};
use crate::vehicle::props::Mass;
use crate::vehicle::swing::{self, Spec};
use crate::vehicle::wheel::WheelHandle;
use towride_mbs::input::{InputError, Seg};
use towride_mbs::model::builder::{BodyHandle, SpringLine};
use towride_mbs::model::desc::Law;
use towride_mbs::model::elements::StopSpec;
use towride_mbs::tyre::Tyre;

/// The spring of a corner.
#[derive(Clone, Debug)]
pub(super) enum SpringChoice {
    /// A linear coil with this rate at the wheel [N/m].
    Coil { wheel_rate: f64 },
    /// A levelled air spring: effective area [m^2], and either its volume [m^3] or the
    /// wheel rate [N/m] it must give; polytropic exponent, ambient pressure [Pa].
    Air {
        area: f64,
        volume: Option<f64>,
        wheel_rate: Option<f64>,
        exponent: f64,
        atmosphere: f64,
    },
}

/// What an axle is made of (left side; the right is mirrored).
pub(super) struct AxleInput<'a> {
    /// Name of the centre joint and torsion element (`front_axle`, `rear_axle`, ...).
    pub centre: &'a str,
    /// Body name prefix of the arms (`arm`, `trailer_arm`).
    pub prefix: &'a str,
    pub wheels: [&'a str; 2],
    pub carrier: BodyHandle,
    /// Wheel centre, left side [m].
    pub wheel_centre: V,
    pub tyre: &'a Tyre,
    /// The arm (hub carrier, brake, half the arm) at the wheel centre.
    pub arm: Mass,
    /// The wheel with the tyre's share that turns with it.
    pub rim: Mass,
    pub spring: SpringChoice,
    /// Damping at the wheel [N s/m].
    pub damping: f64,
    /// Roll stiffness added at the axle [N m/rad].
    pub anti_roll: f64,
    /// Static load of a corner [N] (the bump stop's scale).
    pub corner_load: f64,
    /// Where the spring is given in the compact file (errors of the design statics).
    pub spring_at: Vec<Seg>,
}

/// An axle awaiting its static loads.
pub(super) struct Axle {
    pub wheels: Vec<WheelHandle>,
    pub pending: Vec<Pending>,
    /// The spring tops (ride heights are measured to them).
    pub mounts: Vec<V>,
}

/// A corner whose spring gets its preload from the static load.
pub(super) enum Pending {
    Coil(Corner),
    Air {
        wheel: String,
        rates: CornerRates,
        line: Box<SpringLine>,
        spring: SpringChoice,
        complaint: InputError,
    },
}

/// Builds the axle: arms, bushings, wheels, centre joint, dampers with stops.
pub(super) fn build(ctx: &Ctx, b: &mut Builder, a: &AxleInput) -> Result<Axle, InputError> {
    let d = &ctx.defaults.d.corner;
    let dsrc = &ctx.defaults.src;
    let w = a.wheel_centre;
    let pivot = [w[0] + d.arm_length_m, w[1] - d.pivot_inboard_m, w[2]];
    let bushing = d.pivot_bushing.check(
        dsrc,
        &towride_mbs::path!["corner", "pivot_bushing"],
        [0.0, 1.0, 0.0],
    )?;
    let track = 2.0 * w[1];
    // Roll twists the arms by t phi / L against each other: K_roll = k_t t^2 / L^2.
    let torsion = a.anti_roll * d.arm_length_m * d.arm_length_m / (track * track);
    let spec = Spec {
        prefix: a.prefix,
        wheels: a.wheels,
        centre: a.centre,
        carrier: a.carrier,
        pivot,
        half: a.arm.clone(),
        rim: a.rim.clone(),
        bushing,
        torsion: (Law::Linear(torsion), Law::Linear(0.0)),
        joints_as_bushings: None,
    };
    let built = swing::build(b, &spec, a.tyre)?;
    swing::join(b, &spec, built.halves)?;
    let bump = StopSpec {
        clearance_m: d.bump_clearance_m,
        stiffness_n_m: d.bump_stop_load_factor * a.corner_load / d.bump_stop_reference_m.powi(2),
        exponent: 2.0,
        damping_n_s_m: d.bump_stop_damping_n_s_m,
        damping_depth_m: d.bump_stop_damping_depth_m,
    }
    .check()
    .map_err(|e| dsrc.locate(&towride_mbs::path!["corner"], e))?;
    let rebound = StopSpec {
        clearance_m: d.rebound_clearance_m,
        stiffness_n_m: d.rebound_stiffness_n_m,
        exponent: 1.0,
        damping_n_s_m: 0.0,
        damping_depth_m: 0.0,
    }
    .check()
    .map_err(|e| dsrc.locate(&towride_mbs::path!["corner"], e))?;
    let y = [0.0, 1.0, 0.0];
    let g = b.model().gravity;
    let mut pending = Vec::new();
    let mut mounts = Vec::new();
    for (k, right) in [false, true].into_iter().enumerate() {
        let m = |p: V| if right { mirror(p) } else { p };
        let name = built.wheels[k].name.clone();
        let arm = Some(built.halves[k]);
        let piv = m(pivot);
        let dl = m([w[0], w[1] - d.damper_inboard_m, w[2]]);
        let du = [dl[0], dl[1], dl[2] + d.damper_length_m];
        let mut rates = built.rates[k].clone();
        rates.element_rate = length_rate(&dl, &turning(&piv, &y, &dl), &du);
        let mr_damper = design::motion_ratio(&rates, g);
        let mut damper = SpringLine::new(&format!("damper_{name}"), arm, dl, Some(a.carrier), du);
        damper.damper = Law::Linear(a.damping / (mr_damper * mr_damper));
        damper.bump_stop = Some(bump.clone());
        damper.rebound_stop = Some(rebound.clone());
        b.add(|mb| mb.spring(damper))?;
        let sl = m([w[0], w[1] - d.spring_inboard_m, w[2]]);
        let su = [sl[0], sl[1], sl[2] + d.spring_length_m];
        let mut rates = built.rates[k].clone();
        rates.element_rate = length_rate(&sl, &turning(&piv, &y, &sl), &su);
        let mr = design::motion_ratio(&rates, g);
        let line = Box::new(SpringLine::new(
            &format!("spring_{name}"),
            arm,
            sl,
            Some(a.carrier),
            su,
        ));
        let complaint = ctx.src.error(&a.spring_at, "");
        pending.push(match &a.spring {
            SpringChoice::Coil { wheel_rate } => Pending::Coil(Corner {
                wheel: name,
                rates,
                element: Preloaded::Coil {
                    line,
                    rate: wheel_rate / (mr * mr),
                },
                complaint,
            }),
            s @ SpringChoice::Air { .. } => Pending::Air {
                wheel: name,
                rates,
                line,
                spring: s.clone(),
                complaint,
            },
        });
        mounts.push(su);
    }
    Ok(Axle {
        wheels: built.wheels,
        pending,
        mounts,
    })
}

/// Gives the corner's spring the preload that holds it at the design position under
/// `load` [N]; returns what was found and the air spring, if it is one.
pub(super) fn finish(
    ctx: &Ctx,
    b: &mut Builder,
    p: Pending,
    load: f64,
) -> Result<(CornerDesign, Option<AirSpring>), InputError> {
    let (wheel, rates, mut line, spring, complaint) = match p {
        Pending::Coil(c) => return Ok((design::finish(b, c, load)?, None)),
        Pending::Air {
            wheel,
            rates,
            line,
            spring,
            complaint,
        } => (wheel, rates, line, spring, complaint),
    };
    let SpringChoice::Air {
        area,
        volume,
        wheel_rate,
        exponent,
        atmosphere,
    } = spring
    else {
        unreachable!("only air springs are pending as air")
    };
    let g = b.model().gravity;
    let preload = design::preload(&rates, g, load);
    let mr = design::motion_ratio(&rates, g);
    let gauge = preload / area;
    let fail = |msg: String| {
        let mut e = complaint.clone();
        e.message = msg;
        e
    };
    if gauge.is_nan() || gauge <= 0.0 {
        return Err(fail(format!(
            "the air spring would carry {preload:.1} N at the design height: it cannot pull"
        )));
    }
    let volume = match (volume, wheel_rate) {
        (Some(v), _) => v,
        (None, Some(k)) => {
            AirSpring::volume_for_rate(area, gauge, atmosphere, exponent, k / (mr * mr))
        }
        (None, None) => return Err(fail("give volume_m3 or ride_frequency_hz".into())),
    };
    let air = AirSpring {
        area_m2: area,
        volume_m3: volume,
        gauge_pa: gauge,
        atmosphere_pa: atmosphere,
        exponent,
    };
    let a = &ctx.defaults.d.air_spring;
    line.free_length = crate::vehicle::geom::distance(&line.point_i, &line.point_j);
    line.preload = preload;
    line.spring = air.law(a.table_span, a.table_points).map_err(|e| {
        ctx.defaults
            .src
            .locate(&towride_mbs::path!["air_spring"], e)
    })?;
    b.add(|m| m.spring(*line))?;
    Ok((
        CornerDesign {
            wheel,
            load_n: load,
            preload,
            motion_ratio: mr,
            wheel_rate_n_m: air.rate() * mr * mr,
            free_length_m: None,
            unsprung_kg: design::reduced_mass(&rates, g),
        },
        Some(air),
    ))
}
