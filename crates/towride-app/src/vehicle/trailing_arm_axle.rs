//! Trailing-arm axle (`trailing_arm_axle`): two trailing arms on body bushings joined on
//! the centreline by a revolute joint and a torsion element about the pivot axis (an
//! anti-roll spring; the swing-axle layout of the twist beam and the trailer axle,
//! [`super::swing`]), and on each arm a spring (coil, or a levelled air spring:
//! [`super::air`]) and a linear damper with bump and rebound stops, wheels and tyres. One
//! property set describes the left side; the right side is mirrored.
//!
//! Spring and damper rates are given at the wheel: the template divides them by its motion
//! ratios squared, so the wheel feels the file's numbers whatever the geometry. The
//! `simple` vehicle files build every axle with this template (their derived hardpoints:
//! the arm pivoting ahead of the wheel at wheel-centre height, spring and damper standing
//! vertically over it, motion ratio 1).

use std::path::Path;

use serde::Deserialize;

use super::air::AirSpec;
use super::axle::{Axle, AxleData, AxleSlot, AxleTemplate};
use super::build::Builder;
use super::design::{self, Corner, Preloaded};
use super::geom::{length_rate, turning};
use super::props::{
    at, joints, stop, BushingLaws, BushingProps, JointsProps, Mass, MassProps, TorsionProps,
    WheelProps,
};
use super::swing::{self, ArmHardpoints, ArmPoints, Spec};
use super::twist_flex::CrossMember;
use super::wheel;
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::builder::SpringLine;
use towride_mbs::model::desc::{Law, Stop};
use towride_mbs::model::elements::{JointBushing, StopSpec};
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    hardpoints: ArmHardpoints,
    arm: MassProps,
    wheel: WheelProps,
    spring: SpringFile,
    damper: DamperFile,
    bump_stop: Option<StopSpec>,
    rebound_stop: Option<StopSpec>,
    pivot_bushing: BushingProps,
    torsion: TorsionProps,
    joints: Option<JointsProps>,
}

/// A spring's kind: the property file's `spring.kind`, a compact file's `spring.kind`.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SpringKind {
    /// A linear coil.
    Coil,
    /// A levelled air spring.
    Air,
}

/// `[spring]`: a coil (`wheel_rate_n_m`) or an air spring (area, volume or wheel rate,
/// gas and table).
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SpringFile {
    kind: SpringKind,
    wheel_rate_n_m: Option<f64>,
    effective_area_m2: Option<f64>,
    volume_m3: Option<f64>,
    polytropic_exponent: Option<f64>,
    atmosphere_pa: Option<f64>,
    table_span: Option<f64>,
    table_points: Option<usize>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct DamperFile {
    /// Linear damping at the wheel [N s/m].
    wheel_damping_n_s_m: f64,
}

/// A corner's damping at the wheel: compression (bump) and rebound rates [N s/m], joined
/// smoothly over `transition_m_s` of wheel velocity ([`Law::TwoSlopes`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelDamping {
    pub compression_n_s_m: f64,
    pub rebound_n_s_m: f64,
    pub transition_m_s: f64,
}

impl WheelDamping {
    /// One rate both ways.
    pub fn linear(c: f64) -> WheelDamping {
        WheelDamping {
            compression_n_s_m: c,
            rebound_n_s_m: c,
            transition_m_s: 0.0,
        }
    }

    /// The law of an element whose length changes `mr` times as fast as the wheel
    /// moves: rates over mr^2, the transition (a velocity) times |mr|. The element
    /// shortens in bump whatever the sign of mr, so its negative rates are compression.
    pub fn law(&self, mr: f64) -> Law {
        let k = 1.0 / (mr * mr);
        if self.compression_n_s_m == self.rebound_n_s_m {
            Law::Linear(self.rebound_n_s_m * k)
        } else {
            Law::TwoSlopes {
                below: self.compression_n_s_m * k,
                above: self.rebound_n_s_m * k,
                width: self.transition_m_s * mr.abs(),
            }
        }
    }
}

/// A corner's spring, its rate at the wheel.
#[derive(Clone, Debug)]
pub enum Spring {
    /// A linear coil giving this rate at the wheel [N/m].
    Coil { wheel_rate_n_m: f64 },
    /// A levelled air spring.
    Air(AirSpec),
}

/// The trailing-arm axle template.
pub struct TrailingArmAxle;

impl AxleTemplate for TrailingArmAxle {
    fn name(&self) -> &'static str {
        "trailing_arm_axle"
    }

    fn read(
        &self,
        b: &mut Builder,
        file: &Path,
        slot: &AxleSlot,
    ) -> Result<Box<dyn AxleData>, InputError> {
        let src = b.read(file)?;
        Ok(Box::new(read(&src, slot)?))
    }
}

/// The axle's data, checked (left side), from a property file or derived in code.
pub struct Props {
    pub points: ArmPoints,
    /// Arm with hub carrier, stub axle and brake.
    pub arm: Mass,
    /// The wheel with the tyre's share that turns with it ([`wheel::rim_mass`]).
    pub rim: Mass,
    pub spring: Spring,
    /// Damping at the wheel.
    pub wheel_damping: WheelDamping,
    pub bump: Option<Stop>,
    pub rebound: Option<Stop>,
    pub bushing: BushingLaws,
    /// Torsion between the arms about the pivot axis: spring and damper laws.
    pub torsion: (Law, Law),
    pub joints: Option<JointBushing>,
    /// Where the design statics complain about the spring.
    pub spring_at: InputError,
}

fn read(src: &Source, slot: &AxleSlot) -> Result<Props, InputError> {
    let f: File = src.parse()?;
    let points = f.hardpoints.check(src, &path!["hardpoints"])?;
    Ok(Props {
        arm: f.arm.check(src, &path!["arm"])?,
        rim: wheel::rim_mass(
            src,
            &path!["wheel"],
            &f.wheel,
            slot.tyre,
            points.wheel_centre,
        )?,
        spring: spring(src, &f.spring)?,
        wheel_damping: WheelDamping::linear(src.non_negative(
            &path!["damper", "wheel_damping_n_s_m"],
            f.damper.wheel_damping_n_s_m,
        )?),
        bump: stop(src, &path!["bump_stop"], &f.bump_stop)?,
        rebound: stop(src, &path!["rebound_stop"], &f.rebound_stop)?,
        bushing: f
            .pivot_bushing
            .check(src, &path!["pivot_bushing"], [0.0, 1.0, 0.0])?,
        torsion: f.torsion.laws(src, &path!["torsion"])?,
        joints: match &f.joints {
            Some(j) => joints(src, &path!["joints"], j)?,
            None => None,
        },
        spring_at: src.error(&path!["spring"], ""),
        points,
    })
}

/// `[spring]`, checked: the fields of its kind, one of volume and wheel rate for air.
fn spring(src: &Source, s: &SpringFile) -> Result<Spring, InputError> {
    let p = path!["spring"];
    let air_fields = [
        ("effective_area_m2", s.effective_area_m2),
        ("volume_m3", s.volume_m3),
        ("polytropic_exponent", s.polytropic_exponent),
        ("atmosphere_pa", s.atmosphere_pa),
        ("table_span", s.table_span),
    ];
    let need = |k: &str, v: Option<f64>| {
        v.ok_or_else(|| src.error(&p, format!("an air spring needs {k}")))
    };
    match s.kind {
        SpringKind::Coil => {
            let points = ("table_points", s.table_points.map(|n| n as f64));
            for (k, v) in air_fields.into_iter().chain([points]) {
                if v.is_some() {
                    return Err(src.error(&at(&p, k), "only an air spring has this"));
                }
            }
            let k = s
                .wheel_rate_n_m
                .ok_or_else(|| src.error(&p, "a coil needs wheel_rate_n_m"))?;
            Ok(Spring::Coil {
                wheel_rate_n_m: src.positive(&at(&p, "wheel_rate_n_m"), k)?,
            })
        }
        SpringKind::Air => {
            let (volume, rate) = match (s.volume_m3, s.wheel_rate_n_m) {
                (Some(v), None) => (Some(src.positive(&at(&p, "volume_m3"), v)?), None),
                (None, Some(k)) => (None, Some(src.positive(&at(&p, "wheel_rate_n_m"), k)?)),
                _ => return Err(src.error(&p, "give volume_m3 or wheel_rate_n_m (not both)")),
            };
            let points = s
                .table_points
                .ok_or_else(|| src.error(&p, "an air spring needs table_points"))?;
            Ok(Spring::Air(AirSpec {
                area_m2: src.positive(
                    &at(&p, "effective_area_m2"),
                    need("effective_area_m2", s.effective_area_m2)?,
                )?,
                volume_m3: volume,
                wheel_rate_n_m: rate,
                exponent: src.positive(
                    &at(&p, "polytropic_exponent"),
                    need("polytropic_exponent", s.polytropic_exponent)?,
                )?,
                atmosphere_pa: src.non_negative(
                    &at(&p, "atmosphere_pa"),
                    need("atmosphere_pa", s.atmosphere_pa)?,
                )?,
                table_span: need("table_span", s.table_span)?,
                table_points: points,
                table_at: src.error(&at(&p, "table_span"), ""),
            }))
        }
    }
}

impl AxleData for Props {
    fn build(self: Box<Self>, b: &mut Builder, slot: &AxleSlot) -> Result<Axle, InputError> {
        build(b, *self, slot)
    }
}

/// Adds the axle at `slot`: arms, bushings, wheels, centre joint, dampers with stops;
/// the springs await their loads.
fn build(b: &mut Builder, a: Props, slot: &AxleSlot) -> Result<Axle, InputError> {
    // Its arms are joined rigidly, as the twist beam's rigid variant.
    if slot.cross_member == Some(CrossMember::Flexible) {
        return Err(b.refused(towride_mbs::model::ModelError::Unsupported(
            "the trailing-arm axle has no flexible cross member".into(),
        )));
    }
    let spec = Spec {
        prefix: &format!("{}arm", slot.prefix),
        wheels: slot.wheels,
        centre: &format!("{}_axle", slot.name),
        carrier: slot.carrier,
        pivot: a.points.pivot,
        half: a.arm,
        rim: a.rim,
        bushing: a.bushing,
        torsion: a.torsion,
        joints_as_bushings: a.joints,
    };
    let built = swing::build(b, &spec, slot.tyre)?;
    swing::join(b, &spec, built.halves)?;
    let y = [0.0, 1.0, 0.0];
    let g = b.model().gravity;
    let mut corners = Vec::new();
    let mut mounts = Vec::new();
    for (k, right) in [false, true].into_iter().enumerate() {
        let p = a.points.side(right);
        let name = built.wheels[k].name.clone();
        let arm = Some(built.halves[k]);
        // Each element's rate over the wheel's: its motion ratio.
        let ratio = |lower: &[f64; 3], upper: &[f64; 3]| {
            let mut rates = built.rates[k].clone();
            rates.element_rate = length_rate(lower, &turning(&p.pivot, &y, lower), upper);
            let mr = design::motion_ratio(&rates, g);
            (rates, mr)
        };
        let (_, mr_damper) = ratio(&p.damper_lower, &p.damper_upper);
        let mut damper = SpringLine::new(
            &format!("damper_{name}"),
            arm,
            p.damper_lower,
            Some(slot.carrier),
            p.damper_upper,
        );
        damper.damper = a.wheel_damping.law(mr_damper);
        damper.bump_stop = a.bump.clone();
        damper.rebound_stop = a.rebound.clone();
        b.add(|mb| mb.spring(damper))?;
        let (rates, mr) = ratio(&p.spring_lower, &p.spring_upper);
        let line = Box::new(SpringLine::new(
            &format!("spring_{name}"),
            arm,
            p.spring_lower,
            Some(slot.carrier),
            p.spring_upper,
        ));
        let element = match &a.spring {
            Spring::Coil { wheel_rate_n_m } => Preloaded::Coil {
                line,
                rate: wheel_rate_n_m / (mr * mr),
            },
            Spring::Air(air) => Preloaded::Air {
                line,
                spring: air.clone(),
            },
        };
        corners.push(Corner {
            wheel: name,
            rates,
            element,
            complaint: a.spring_at.clone(),
        });
        mounts.push(p.spring_upper);
    }
    Ok(Axle {
        wheels: built.wheels,
        corners,
        body_mounts: mounts,
        flexible: None,
    })
}
