//! The car body: sprung mass and inertia lumped in one body at the body's centre of mass
//! (the thesis's model, 5.5.3.1), axes along the vehicle's.

use std::path::Path;

use serde::Deserialize;

use super::build::Builder;
use super::props::MassProps;
use towride_mbs::input::InputError;
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    body: MassProps,
}

/// Reads `file` and adds the body `car_body`; returns its index.
pub fn build(b: &mut Builder, file: &Path) -> Result<BodyHandle, InputError> {
    let src = b.read(file)?;
    let f: File = src.parse()?;
    let m = f.body.check(&src, &path!["body"])?;
    b.body("car_body", &m)
}
