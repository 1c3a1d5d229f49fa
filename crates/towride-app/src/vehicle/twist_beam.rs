//! Twist-beam rear axle: two trailing arms on body bushings joined by the cross member,
//! coil springs and dampers between arms and body, wheels and tyres. One property set
//! describes the left side; the right side is mirrored.
//!
//! The cross member (`[cross_member] kind`, or the scene's `rear_cross_member`): rigid
//! (default, the thesis's rigid model):
//! two halves, each an arm with half the cross member (`[half]`), joined by a revolute
//! joint and a torsion element about the pivot axis (`[torsion]`); flexible: the arms
//! alone (`[cross_member.arm]`) and the cross member as a modal body fixed to them
//! ([`super::twist_flex`]).

use std::path::Path;

use serde::Deserialize;

use super::axle::{Axle, AxleData, AxleSlot, AxleTemplate};
use super::build::Builder;
use super::design::{Corner, Preloaded};
use super::geom::{length_rate, mirror, turning};
use super::props::{
    joints, stop, BushingLaws, BushingProps, DamperProps, JointsProps, Mass, MassProps,
    TorsionProps, WheelProps,
};
use super::swing::{self, ArmHardpoints, ArmPoints, Spec};
use super::twist_flex::{self, CrossMember, CrossMemberProps, Flexible};
use super::wheel;
use towride_mbs::input::InputError;
use towride_mbs::model::builder::SpringLine;
use towride_mbs::model::desc::{Law, Stop};
use towride_mbs::model::elements::{JointBushing, StopSpec};
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    hardpoints: ArmHardpoints,
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

    fn read(
        &self,
        b: &mut Builder,
        file: &Path,
        slot: &AxleSlot,
    ) -> Result<Box<dyn AxleData>, InputError> {
        Ok(Box::new(read(b, file, slot)?))
    }
}

/// The property file, checked (left side).
struct Props {
    points: ArmPoints,
    half: Mass,
    rim: Mass,
    spring_rate: f64,
    damper: Law,
    bump: Option<Stop>,
    rebound: Option<Stop>,
    bushing: BushingLaws,
    torsion: (Law, Law),
    joints: Option<JointBushing>,
    /// The flexible cross member, when it is the one built.
    flexible: Option<Flexible>,
    /// Where the design statics complain about the spring.
    spring_at: InputError,
}

/// Reads `file` for `slot`; the slot's cross member (the scene's) overrides the file's.
fn read(b: &mut Builder, file: &Path, slot: &AxleSlot) -> Result<Props, InputError> {
    let src = b.read(file)?;
    let f: File = src.parse()?;
    let cp = path!["cross_member"];
    let flexible = match (&f.cross_member, slot.cross_member) {
        (Some(c), asked) => (asked.unwrap_or(c.kind) == CrossMember::Flexible)
            .then(|| twist_flex::read(&src, &cp, file, c, b))
            .transpose()?,
        (None, None | Some(CrossMember::Rigid)) => None,
        (None, Some(k)) => {
            return Err(src.error(
                &cp,
                format!("cross member '{k}' asked for: it needs a [cross_member] table"),
            ))
        }
    };
    let points = f.hardpoints.check(&src, &path!["hardpoints"])?;
    let half = match &flexible {
        Some(x) => x.arm.clone(),
        None => f.half.check(&src, &path!["half"])?,
    };
    Ok(Props {
        rim: wheel::rim_mass(
            &src,
            &path!["wheel"],
            &f.wheel,
            slot.tyre,
            points.wheel_centre,
        )?,
        spring_rate: src.positive(&path!["spring", "stiffness_n_m"], f.spring.stiffness_n_m)?,
        damper: f.damper.check(&src, &path!["damper"])?,
        bump: stop(&src, &path!["bump_stop"], &f.bump_stop)?,
        rebound: stop(&src, &path!["rebound_stop"], &f.rebound_stop)?,
        bushing: f
            .pivot_bushing
            .check(&src, &path!["pivot_bushing"], [0.0, 1.0, 0.0])?,
        torsion: f.torsion.laws(&src, &path!["torsion"])?,
        joints: joints(&src, &path!["joints"], &f.joints)?,
        spring_at: src.error(&path!["spring", "stiffness_n_m"], ""),
        points,
        half,
        flexible,
    })
}

impl AxleData for Props {
    fn build(self: Box<Self>, b: &mut Builder, slot: &AxleSlot) -> Result<Axle, InputError> {
        build(b, *self, slot)
    }
}

/// Adds both sides at `slot`.
fn build(b: &mut Builder, c: Props, slot: &AxleSlot) -> Result<Axle, InputError> {
    let body = slot.carrier;
    let spec = Spec {
        prefix: &format!("{}arm", slot.prefix),
        wheels: slot.wheels,
        centre: &format!("{}twist_beam", slot.prefix),
        carrier: body,
        pivot: c.points.pivot,
        half: c.half,
        rim: c.rim,
        bushing: c.bushing,
        torsion: c.torsion,
        joints_as_bushings: c.joints,
    };
    let mut built = swing::build(b, &spec, slot.tyre)?;
    let y = [0.0, 1.0, 0.0];
    let cross_member = match c.flexible {
        None => {
            swing::join(b, &spec, built.halves)?;
            None
        }
        Some(x) => {
            let j = twist_flex::join(b, x, built.halves, spec.joints_as_bushings.as_ref())?;
            // Heave turns both arms alike, so the cross member turns with them about
            // the pivot axis: half its mass rides on each corner.
            for (k, r) in built.rates.iter_mut().enumerate() {
                let piv = if k == 1 {
                    mirror(c.points.pivot)
                } else {
                    c.points.pivot
                };
                r.masses.push((0.5 * j.mass, turning(&piv, &y, &j.cm)));
            }
            Some((j.body, j.modes))
        }
    };
    let mut corners = Vec::new();
    let mut spring_tops = Vec::new();
    for (k, right) in [false, true].into_iter().enumerate() {
        let p = c.points.side(right);
        let name = built.wheels[k].name.clone();
        let arm = Some(built.halves[k]);
        let mut damper = SpringLine::new(
            &format!("damper_{name}"),
            arm,
            p.damper_lower,
            Some(body),
            p.damper_upper,
        );
        damper.damper = c.damper.clone();
        damper.bump_stop = c.bump.clone();
        damper.rebound_stop = c.rebound.clone();
        b.add(|m| m.spring(damper))?;
        let mut rates = built.rates[k].clone();
        rates.element_rate = length_rate(
            &p.spring_lower,
            &turning(&p.pivot, &y, &p.spring_lower),
            &p.spring_upper,
        );
        corners.push(Corner {
            wheel: name.clone(),
            rates,
            element: Preloaded::Coil {
                line: Box::new(SpringLine::new(
                    &format!("spring_{name}"),
                    arm,
                    p.spring_lower,
                    Some(body),
                    p.spring_upper,
                )),
                rate: c.spring_rate,
            },
            complaint: c.spring_at.clone(),
        });
        spring_tops.push(p.spring_upper);
    }
    Ok(Axle {
        wheels: built.wheels,
        corners,
        body_mounts: spring_tops,
        flexible: cross_member,
    })
}
