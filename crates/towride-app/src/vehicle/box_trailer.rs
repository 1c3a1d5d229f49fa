//! The box trailer template (`box_trailer`): box, chassis and drawbar as one rigid body
//! (plus the payload of the load case, merged into it), a rubber torsion axle of two
//! swinging halves, wheels and tyres; optionally the drawbar as a flexible body fixed to
//! the box ([`super::drawbar`]).
//!
//! The axle follows the thesis (5.5.3.1): two rigid halves joined on the centreline by a
//! torsion element (the inner bar) and carried by two bushings (the rubber packs), whose
//! rotation about the axle axis springs and damps the box. The rubber's preload holds
//! the empty trailer at its design position; a payload makes it sit lower. Trailer
//! coordinates: [`super::trailer`].

use crate::error::DesignError;
use std::path::Path;

use serde::Deserialize;

use super::build::Builder;
use super::drawbar::{self, DrawbarProps, Flexible};
use super::design::{self, centre_of_mass, Corner, Preloaded};
use super::geom::{mirror, Placement, V};
use super::props::{
    joints, merge, point, BushingLaws, BushingProps, JointsProps, Mass, MassProps,
    TorsionProps, WheelProps,
};
use super::swing::{self, Spec};
use super::trailer::{self, Trailer, TrailerData, TrailerSlot, TrailerTemplate};
use super::wheel;
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::desc::Law;
use towride_mbs::model::elements::JointBushing;
use towride_mbs::path;
use towride_mbs::tyre::Tyre;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    trailer: Coupling,
    body: MassProps,
    hardpoints: Hardpoints,
    half: MassProps,
    wheel: WheelProps,
    pivot_bushing: BushingProps,
    torsion: TorsionProps,
    joints: JointsProps,
    load_case: Vec<LoadCase>,
    /// The drawbar: rigid (in `[body]`) when absent.
    drawbar: Option<DrawbarProps>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Coupling {
    /// Ball-socket centre on the drawbar [m].
    coupling_m: [f64; 3],
}

/// Left-side hardpoints [m].
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Hardpoints {
    pivot_m: [f64; 3],
    wheel_centre_m: [f64; 3],
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct LoadCase {
    name: String,
    /// Added mass (none: the empty trailer).
    payload: Option<MassProps>,
}

/// The box trailer template.
pub struct BoxTrailer;

impl TrailerTemplate for BoxTrailer {
    fn name(&self) -> &'static str {
        "box_trailer"
    }

    fn read(
        &self,
        b: &mut Builder,
        file: &Path,
        load_case: Option<&str>,
    ) -> Result<Box<dyn TrailerData>, InputError> {
        Ok(Box::new(read(file, load_case, b)?))
    }
}

/// A trailer read and checked, before it is placed.
struct Props {
    src_path: std::path::PathBuf,
    coupling: V,
    /// Wheel centre (left), trailer coordinates.
    wheel_centre: V,
    /// Payload of the chosen load case.
    payload: Option<Mass>,
    load_case: String,
    box_mass: Mass,
    half: Mass,
    pivot: V,
    wheel: WheelProps,
    bushing: BushingLaws,
    torsion: (Law, Law),
    joints_as_bushings: Option<JointBushing>,
    /// The flexible drawbar, and the box without it.
    drawbar: Option<(Flexible, Mass)>,
    src: Source,
}

/// Reads `file`, choosing the load case `case` (the first one when `None`).
fn read(file: &Path, case: Option<&str>, b: &Builder) -> Result<Props, InputError> {
    let src = b.loader.toml(file)?;
    let f: File = src.parse()?;
    let coupling = point(&src, &path!["trailer", "coupling_m"], &f.trailer.coupling_m)?;
    let pivot = point(&src, &path!["hardpoints", "pivot_m"], &f.hardpoints.pivot_m)?;
    let wc = point(
        &src,
        &path!["hardpoints", "wheel_centre_m"],
        &f.hardpoints.wheel_centre_m,
    )?;
    if wc[1] <= 0.0 || pivot[1] <= 0.0 {
        return Err(src.error(
            &path!["hardpoints"],
            "give the left side (y > 0); the right side is mirrored",
        ));
    }
    if f.load_case.is_empty() {
        return Err(src.error(&path!["load_case"], "define at least one load case"));
    }
    let k = match case {
        None => 0,
        Some(name) => f
            .load_case
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = f.load_case.iter().map(|c| c.name.as_str()).collect();
                src.error(
                    &path!["load_case"],
                    format!(
                        "no load case '{name}' (cases: {}){}",
                        names.join(", "),
                        towride_mbs::model::suggest::did_you_mean(name, names.iter().copied())
                    ),
                )
                .with_kind(towride_mbs::input::InputErrorKind::NoLoadCase)
            })?,
    };
    let mut payload = None;
    for (i, c) in f.load_case.iter().enumerate() {
        // Every case is checked, not only the chosen one.
        let m = match &c.payload {
            Some(p) => Some(p.check(&src, &path!["load_case", i, "payload"])?),
            None => None,
        };
        if i == k {
            payload = m;
        }
    }
    let box_mass = f.body.check(&src, &path!["body"])?;
    let drawbar = match &f.drawbar {
        Some(d) => drawbar::read(&src, &path!["drawbar"], file, d, coupling, b)?,
        None => None,
    };
    let drawbar = match drawbar {
        Some(d) => {
            let rest = drawbar::remove(&box_mass, &d.mass())
                .map_err(|m| src.error(&path!["body", "mass_kg"], m))?;
            Some((d, rest))
        }
        None => None,
    };
    Ok(Props {
        coupling,
        drawbar,
        wheel_centre: wc,
        payload,
        load_case: f.load_case[k].name.clone(),
        box_mass,
        half: f.half.check(&src, &path!["half"])?,
        pivot,
        bushing: f
            .pivot_bushing
            .check(&src, &path!["pivot_bushing"], [0.0, 1.0, 0.0])?,
        torsion: f.torsion.laws(&src, &path!["torsion"])?,
        joints_as_bushings: joints(&src, &path!["joints"], &f.joints)?,
        wheel: f.wheel.clone(),
        src_path: file.to_path_buf(),
        src,
    })
}

impl TrailerData for Props {
    fn place(&self, ball: V) -> Result<(Placement, f64), DesignError> {
        let origin = self.src_path.display().to_string();
        trailer::pitched_on_ball(&origin, self.coupling, self.wheel_centre[0], ball)
    }

    fn build(
        self: Box<Self>,
        b: &mut Builder,
        slot: &TrailerSlot,
    ) -> Result<Trailer, InputError> {
        build(b, *self, slot.tyre)
    }
}

/// Adds the trailer (the builder placed in trailer coordinates).
fn build(b: &mut Builder, t: Props, tyre: &Tyre) -> Result<Trailer, InputError> {
    let src = &t.src;
    let rim = wheel::rim_mass(src, &path!["wheel"], &t.wheel, tyre, t.wheel_centre)?;
    // With a flexible drawbar the box is the body less the drawbar's FE mass.
    let rigid = match &t.drawbar {
        Some((_, rest)) => rest.clone(),
        None => t.box_mass.clone(),
    };
    let loaded = match &t.payload {
        Some(p) => merge(&rigid, p),
        None => rigid.clone(),
    };
    let body = b.body("trailer_box", &loaded)?;
    let spec = Spec {
        prefix: "trailer_arm",
        wheels: ["tl", "tr"],
        centre: "trailer_axle",
        carrier: body,
        pivot: t.pivot,
        half: t.half.clone(),
        rim: rim.clone(),
        bushing: t.bushing.clone(),
        torsion: t.torsion.clone(),
        joints_as_bushings: t.joints_as_bushings.clone(),
    };
    let built = swing::build(b, &spec, tyre)?;
    swing::join(b, &spec, built.halves)?;
    // Design statics of the empty trailer: ball and axle share its weight.
    let belt = wheel::tyre_own_mass(tyre);
    let mut parts = vec![(rigid.mass, rigid.cm)];
    if let Some((d, _)) = &t.drawbar {
        let m = d.mass();
        parts.push((m.mass, m.cm));
    }
    for side in [false, true] {
        let m = |p: V| if side { mirror(p) } else { p };
        parts.push((t.half.mass, m(t.half.cm)));
        parts.push((rim.mass + belt, m(t.wheel_centre)));
    }
    let (m_empty, cm_empty) = centre_of_mass(&parts);
    let g = b.model().gravity;
    let w = m_empty * super::geom::norm(&g);
    let (ball, axle) = design::lever(w, cm_empty[0], t.coupling[0], t.wheel_centre[0]);
    let mut corners = Vec::new();
    for k in 0..2 {
        let mut rates = built.rates[k].clone();
        rates.element_rate = built.bushing_rates[k];
        let rate = match &t.bushing.stiffness[5] {
            Law::Linear(r) => *r,
            l => l.stiffness(),
        };
        let c = Corner {
            wheel: built.wheels[k].name.clone(),
            rates,
            element: Preloaded::Torsion {
                force: built.bushings[k],
                rate,
            },
            complaint: src.error(&path!["pivot_bushing", "stiffness_n_m_rad", 2], ""),
        };
        corners.push(design::finish(b, c, 0.5 * axle)?.0);
    }
    let mut all = parts.clone();
    if let Some(p) = &t.payload {
        all.push((p.mass, p.cm));
    }
    let (mass, cm) = centre_of_mass(&all);
    let (coupling_body, coupling_node) = match t.drawbar {
        Some((d, _)) => {
            let j = drawbar::join(b, d, body, t.joints_as_bushings.as_ref())?;
            (j.body, Some(j.ball_node))
        }
        None => (body, None),
    };
    Ok(Trailer {
        body,
        coupling_body,
        coupling_node,
        wheels: built.wheels,
        corners,
        design_ball_load_n: ball,
        mass,
        cm,
        load_case: t.load_case.clone(),
    })
}
