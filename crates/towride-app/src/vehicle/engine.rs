//! The engine with its gearbox as a rigid body on rubber mounts (the thesis's template
//! set has an engine; issue 21): mass properties and three or more mounts, each a 6-DOF
//! bushing between the engine (I) and the car body (J), in vehicle coordinates. The
//! car body's property file then holds the body without the engine.

use std::path::Path;

use serde::Deserialize;

use super::build::Builder;
use super::props::{at, point, BushingProps, MassProps};
use towride_mbs::input::InputError;
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    engine: MassProps,
    mount: Vec<Mount>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Mount {
    name: String,
    /// Mount centre, vehicle coordinates [m].
    position_m: [f64; 3],
    bushing: BushingProps,
}

/// Fewest mounts that hold a rigid body in all six directions with rubber of ordinary
/// proportions (a power unit is held on three or four).
const MIN_MOUNTS: usize = 3;

/// Reads `file` and adds the body `engine` on its mounts to the car body `body`.
pub fn build(b: &mut Builder, file: &Path, body: BodyHandle) -> Result<BodyHandle, InputError> {
    let src = b.read(file)?;
    let f: File = src.parse()?;
    let m = f.engine.check(&src, &path!["engine"])?;
    if f.mount.len() < MIN_MOUNTS {
        return Err(src.error(
            &path!["mount"],
            format!(
                "{} mount(s): an engine needs at least {MIN_MOUNTS}",
                f.mount.len()
            ),
        ));
    }
    let engine = b.body("engine", &m)?;
    for (k, mt) in f.mount.iter().enumerate() {
        let p = path!["mount", k];
        let pos = point(&src, &at(&p, "position_m"), &mt.position_m)?;
        let laws = mt
            .bushing
            .check(&src, &at(&p, "bushing"), [0.0, 0.0, 1.0])?;
        b.bushing(
            &format!("engine_mount_{}", mt.name),
            Some(engine),
            Some(body),
            pos,
            &laws.axes,
            &laws,
            [0.0; 6],
        )?;
    }
    Ok(engine)
}
