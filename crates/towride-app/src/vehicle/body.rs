//! The car body: sprung mass and inertia lumped in one body at the body's centre of mass
//! (the thesis's model, 5.5.3.1), axes along the vehicle's.

use std::path::Path;

use serde::Deserialize;

use super::build::Builder;
use super::props::MassProps;
use crate::comfort::seat::{Seat, SeatSpec};
use towride_mbs::input::InputError;
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    body: MassProps,
    /// The driver's seat with its occupant, for the comfort at the seat surface; not
    /// part of the multibody model (`crate::comfort::seat`).
    seat: Option<SeatSpec>,
}

/// Reads `file` and adds the body `car_body`; returns its index and the driver's seat
/// when the file gives one.
pub fn build(b: &mut Builder, file: &Path) -> Result<(BodyHandle, Option<Seat>), InputError> {
    let src = b.read(file)?;
    let f: File = src.parse()?;
    let m = f.body.check(&src, &path!["body"])?;
    let seat = match &f.seat {
        Some(s) => Some(s.check(&src, &path!["seat"])?),
        None => None,
    };
    Ok((b.body("car_body", &m)?, seat))
}
