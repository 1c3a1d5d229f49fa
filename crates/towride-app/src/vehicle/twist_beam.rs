//! Twist-beam rear axle: two trailing arms on body bushings joined by the cross member,
//! coil springs and dampers between arms and body, wheels and tyres. One property set
//! describes the left side; the right side is mirrored.
//!
//! The cross member (`[cross_member] kind`): "rigid" (default, the thesis's rigid model):
//! two halves, each an arm with half the cross member (`[half]`), joined by a revolute
//! joint and a torsion element about the pivot axis (`[torsion]`); "flexible": the arms
//! alone (`[cross_member.arm]`) and the cross member as a modal body fixed to them
//! ([`super::twist_flex`]).

use serde::Deserialize;

use super::axle::{Axle, AxleSlot, AxleTemplate};
use super::build::Builder;
use super::design::{Corner, Preloaded};
use super::geom::{distance, length_rate, mirror, turning, V};
use super::props::{
    at, joints, point, stop, BushingProps, DamperProps, JointsProps, MassProps, TorsionProps,
    WheelProps,
};
use super::swing::{self, Spec};
use super::twist_flex::{self, CrossMemberProps};
use super::wheel::{self};
use towride_mbs::input::InputError;
use towride_mbs::model::builder::SpringLine;
use towride_mbs::model::elements::StopSpec;
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    hardpoints: Hardpoints,
    half: MassProps,
    wheel: WheelProps,
    spring: Spring,
    damper: DamperProps,
    bump_stop: Option<StopSpec>,
    rebound_stop: Option<StopSpec>,
    pivot_bushing: BushingProps,
    torsion: TorsionProps,
    joints: JointsProps,
    cross_member: Option<CrossMemberProps>,
}

/// Left-side hardpoints, vehicle coordinates at the design position [m].
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Hardpoints {
    wheel_centre_m: [f64; 3],
    pivot_m: [f64; 3],
    spring_lower_m: [f64; 3],
    spring_upper_m: [f64; 3],
    damper_lower_m: [f64; 3],
    damper_upper_m: [f64; 3],
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Spring {
    stiffness_n_m: f64,
}

/// The twist-beam axle template.
pub struct TwistBeam;

impl AxleTemplate for TwistBeam {
    fn name(&self) -> &'static str {
        "twist_beam"
    }

    fn build(
        &self,
        b: &mut Builder,
        file: &std::path::Path,
        slot: &AxleSlot,
    ) -> Result<Axle, InputError> {
        build(b, file, slot)
    }
}

/// Reads `file` and adds the axle at `slot`; the slot's variant ("rigid" or
/// "flexible") overrides the file's cross member.
fn build(b: &mut Builder, file: &std::path::Path, slot: &AxleSlot) -> Result<Axle, InputError> {
    let (body, tyre, kind) = (slot.carrier, slot.tyre, slot.variant);
    let src = b.read(file)?;
    let f: File = src.parse()?;
    let cp = path!["cross_member"];
    let flexible = match (&f.cross_member, kind) {
        (Some(c), _) => {
            let k = kind.unwrap_or(&c.kind);
            twist_flex::is_flexible(&src, &at(&cp, "kind"), k)?
                .then(|| twist_flex::read(&src, &cp, file, c, b))
                .transpose()?
        }
        (None, None | Some("rigid")) => None,
        (None, Some(k)) => {
            return Err(src.error(
                &cp,
                format!("cross member '{k}' asked for: it needs a [cross_member] table"),
            ))
        }
    };
    let h = &f.hardpoints;
    let hp = |k: &str, v: &[f64; 3]| point(&src, &path!["hardpoints", k], v);
    let w = hp("wheel_centre_m", &h.wheel_centre_m)?;
    let pivot = hp("pivot_m", &h.pivot_m)?;
    let sl = hp("spring_lower_m", &h.spring_lower_m)?;
    let su = hp("spring_upper_m", &h.spring_upper_m)?;
    let dl = hp("damper_lower_m", &h.damper_lower_m)?;
    let du = hp("damper_upper_m", &h.damper_upper_m)?;
    for (k, v) in [("wheel_centre_m", w), ("pivot_m", pivot)] {
        if v[1] <= 0.0 {
            return Err(src.error(
                &path!["hardpoints", k, 1],
                "give the left side (y > 0); the right side is mirrored",
            ));
        }
    }
    // Coincident ends are the hardpoints' fault, not the element's line that the
    // builder would otherwise blame (named in no file).
    for (k, a, other, b, what) in [
        ("wheel_centre_m", w, "pivot_m", pivot, "the trailing arm"),
        ("spring_upper_m", su, "spring_lower_m", sl, "the spring's line"),
        ("damper_upper_m", du, "damper_lower_m", dl, "the damper's line"),
    ] {
        if distance(&a, &b) < 1e-6 {
            return Err(src.error(
                &path!["hardpoints", k],
                format!("coincides with `{other}`; the two set {what}"),
            ));
        }
    }
    let half = match &flexible {
        Some(x) => x.arm.clone(),
        None => f.half.check(&src, &path!["half"])?,
    };
    let rim = wheel::rim_mass(&src, &path!["wheel"], &f.wheel, tyre, w)?;
    let k_spring = src.positive(&path!["spring", "stiffness_n_m"], f.spring.stiffness_n_m)?;
    let damper_law = f.damper.check(&src, &path!["damper"])?;
    let bump = stop(&src, &path!["bump_stop"], &f.bump_stop)?;
    let rebound = stop(&src, &path!["rebound_stop"], &f.rebound_stop)?;
    let bushing = f
        .pivot_bushing
        .check(&src, &path!["pivot_bushing"], [0.0, 1.0, 0.0])?;
    let torsion = f.torsion.laws(&src, &path!["torsion"])?;
    let jb = joints(&src, &path!["joints"], &f.joints)?;
    let spec = Spec {
        prefix: "arm",
        wheels: slot.wheels,
        centre: "twist_beam",
        carrier: body,
        pivot,
        half,
        rim,
        bushing,
        torsion,
        joints_as_bushings: jb,
    };
    let mut built = swing::build(b, &spec, tyre)?;
    let y = [0.0, 1.0, 0.0];
    let cross_member = match flexible {
        None => {
            swing::join(b, &spec, built.halves)?;
            None
        }
        Some(x) => {
            let j = twist_flex::join(b, x, built.halves, spec.joints_as_bushings.as_ref())?;
            // Heave turns both arms alike, so the cross member turns with them about
            // the pivot axis: half its mass rides on each corner.
            for (k, r) in built.rates.iter_mut().enumerate() {
                let piv = if k == 1 { mirror(pivot) } else { pivot };
                r.masses.push((0.5 * j.mass, turning(&piv, &y, &j.cm)));
            }
            Some((j.body, j.modes))
        }
    };
    let mut corners = Vec::new();
    let mut spring_tops = Vec::new();
    for (k, side) in [false, true].into_iter().enumerate() {
        let m = |p: V| if side { mirror(p) } else { p };
        let name = built.wheels[k].name.clone();
        let arm = Some(built.halves[k]);
        let piv = m(pivot);
        let mut damper = SpringLine::new(&format!("damper_{name}"), arm, m(dl), Some(body), m(du));
        damper.damper = damper_law.clone();
        damper.bump_stop = bump.clone();
        damper.rebound_stop = rebound.clone();
        b.add(|m| m.spring(damper))?;
        let mut rates = built.rates[k].clone();
        rates.element_rate = length_rate(&m(sl), &turning(&piv, &y, &m(sl)), &m(su));
        corners.push(Corner {
            wheel: name.clone(),
            rates,
            element: Preloaded::Coil {
                line: Box::new(SpringLine::new(
                    &format!("spring_{name}"),
                    arm,
                    m(sl),
                    Some(body),
                    m(su),
                )),
                rate: k_spring,
            },
            complaint: src.error(&path!["spring", "stiffness_n_m"], ""),
        });
        spring_tops.push(m(su));
    }
    Ok(Axle {
        wheels: built.wheels,
        corners,
        body_mounts: spring_tops,
        flexible: cross_member,
    })
}
