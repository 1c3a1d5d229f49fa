//! Lumped trailer (`lumped_trailer`): box, chassis and drawbar as one rigid body
//! `trailer_box` (the load case's payload merged into it) on one axle of any registered
//! axle template, placed level with its coupling on the ball. The `simple` vehicle files'
//! trailers are built with it, on a trailing-arm axle.
//!
//! ```toml
//! [trailer]
//! coupling_m = [0.0, 0.0, 0.45]      # ball-socket centre, trailer coordinates
//! axle = { template = "trailing_arm_axle", file = "trailer_axle.toml" }
//!
//! [body]                             # MassProps, without payload
//! mass_kg = 340.0
//! cm_m = [-2.1, 0.0, 0.62]
//! inertia_kg_m2 = [150.0, 400.0, 450.0]
//!
//! [[load_case]]                      # optional; the first when the scene names none
//! name = "ahead"
//! payload = { mass_kg = 150.0, cm_m = [-1.9, 0.0, 0.5], inertia_kg_m2 = [10.0, 10.0, 10.0] }
//! ```
//!
//! The axle file is relative to this file, in trailer coordinates (wheels `tl`, `tr`,
//! bodies prefixed `trailer_`). The springs are preloaded for the empty trailer, its
//! weight shared by ball and axle by the lever rule; a payload makes it sit lower.

use crate::error::DesignError;
use std::path::Path;

use serde::Deserialize;

use super::axle::{self, AxleSlot, AxleSpec};
use super::build::Builder;
use super::design::{self, centre_of_mass};
use super::geom::{norm, Placement, V};
use super::props::{merge, point, Mass, MassProps};
use super::trailer::{Trailer, TrailerData, TrailerSlot, TrailerTemplate};
use super::wheel;
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::math::sub;
use towride_mbs::path;

/// The coupling may sit this far [m] above or below the ball: a lumped trailer is placed
/// level, its axle's ground line unknown until the axle is built.
const LEVEL_TOLERANCE_M: f64 = 1e-6;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    trailer: Head,
    body: MassProps,
    #[serde(default)]
    load_case: Vec<LoadCase>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Head {
    /// Ball-socket centre on the drawbar [m].
    coupling_m: [f64; 3],
    axle: AxleRef,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct AxleRef {
    template: String,
    file: String,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct LoadCase {
    name: String,
    /// Added mass (none: the empty trailer).
    payload: Option<MassProps>,
}

/// The lumped trailer template.
pub struct LumpedTrailer;

impl TrailerTemplate for LumpedTrailer {
    fn name(&self) -> &'static str {
        "lumped_trailer"
    }

    fn read(
        &self,
        b: &mut Builder,
        file: &Path,
        load_case: Option<&str>,
    ) -> Result<Box<dyn TrailerData>, InputError> {
        let src = b.read(file)?;
        Ok(Box::new(read(&src, file, load_case)?))
    }
}

/// The trailer's data, checked, from a property file or derived in code.
pub struct Props {
    /// Ball-socket centre, trailer coordinates [m].
    pub coupling: V,
    /// The body without payload.
    pub body: Mass,
    pub axle: AxleSpec,
    /// Payload of the load case built.
    pub payload: Option<Mass>,
    pub load_case: String,
    /// What the data came from (the placement's complaint names it).
    pub origin: String,
}

fn read(src: &Source, file: &Path, case: Option<&str>) -> Result<Props, InputError> {
    let f: File = src.parse()?;
    let t = &f.trailer;
    let dir = file.parent().unwrap_or(Path::new("."));
    let ap = path!["trailer", "axle"];
    let axle = axle::spec(src, &ap, &t.axle.template, dir, &t.axle.file)?;
    let mut payloads = Vec::new();
    for (i, c) in f.load_case.iter().enumerate() {
        // Every case is checked, not only the chosen one.
        let p = path!["load_case", i, "payload"];
        payloads.push(c.payload.as_ref().map(|m| m.check(src, &p)).transpose()?);
    }
    let k = match case {
        Some(name) => {
            let k = f.load_case.iter().position(|c| c.name == name);
            Some(k.ok_or_else(|| {
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
            })?)
        }
        // The first case when none is asked for, none when the file has none.
        None => (!f.load_case.is_empty()).then_some(0),
    };
    Ok(Props {
        coupling: point(src, &path!["trailer", "coupling_m"], &t.coupling_m)?,
        body: f.body.check(src, &path!["body"])?,
        axle,
        payload: k.and_then(|k| payloads[k].clone()),
        load_case: k.map_or(AS_GIVEN.into(), |k| f.load_case[k].name.clone()),
        origin: file.display().to_string(),
    })
}

/// The load case's name when the trailer has none.
pub const AS_GIVEN: &str = "as_given";

impl TrailerData for Props {
    fn place(&self, ball: V) -> Result<(Placement, f64), DesignError> {
        let c = self.coupling;
        if (ball[2] - c[2]).abs() > LEVEL_TOLERANCE_M || c[1] != 0.0 {
            return Err(DesignError::CouplingNotLevel {
                origin: self.origin.clone(),
                coupling_height_m: c[2],
                coupling_y_m: c[1],
                ball_height_m: ball[2],
            });
        }
        Ok((Placement::translate([ball[0] - c[0], ball[1], 0.0]), 0.0))
    }

    fn build(self: Box<Self>, b: &mut Builder, slot: &TrailerSlot) -> Result<Trailer, InputError> {
        let loaded = match &self.payload {
            Some(p) => merge(&self.body, p),
            None => self.body.clone(),
        };
        let body = b.body("trailer_box", &loaded)?;
        let axle = self.axle.build(
            b,
            &AxleSlot {
                carrier: body,
                tyre: slot.tyre,
                wheels: ["tl", "tr"],
                name: "trailer",
                prefix: "trailer_",
                cross_member: None,
                steering: None,
            },
        )?;
        // Design statics of the empty trailer: its weight (body, the axle's parts, the
        // tyres' belts) shared by ball and axle, the axle's load equally by its wheels.
        let place = b.mb.place();
        let mut parts = vec![(self.body.mass, self.body.cm)];
        // The axle's parts: every body built after the trailer's own.
        for (_, x) in b.model().each_body().filter(|(h, _)| *h > body) {
            parts.push((
                x.mass,
                place.vector_local(sub(&x.position, &place.translation)),
            ));
        }
        let belt = wheel::tyre_own_mass(slot.tyre);
        for w in &axle.wheels {
            parts.push((belt, w.design_centre));
        }
        let (m_empty, cm_empty) = centre_of_mass(&parts);
        let w = m_empty * norm(&b.model().gravity);
        let axle_x = axle.wheels[0].design_centre[0];
        let (ball, axle_load) = design::lever(w, cm_empty[0], self.coupling[0], axle_x);
        let mut corners = Vec::new();
        for c in axle.corners {
            corners.push(design::finish(b, c, 0.5 * axle_load)?.0);
        }
        if let Some(p) = &self.payload {
            parts.push((p.mass, p.cm));
        }
        let (mass, cm) = centre_of_mass(&parts);
        Ok(Trailer {
            body,
            coupling_body: body,
            coupling_node: None,
            wheels: axle.wheels,
            corners,
            design_ball_load_n: ball,
            mass,
            cm,
            load_case: self.load_case,
        })
    }
}
