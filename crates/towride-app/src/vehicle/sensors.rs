//! Sensors: accelerometer positions (body, point or modal node, measuring axes), read
//! from the vehicle's assembly file or a scene. Each becomes a marker whose axes are
//! those of the subsystem the body belongs to; its channels are `acc_<name>_<axis>`.

use serde::Deserialize;

use super::build::Builder;
use super::geom::IDENTITY;
use super::props::point;
use super::Handles;
use towride_mbs::input::{InputError, Seg, Source};
use towride_mbs::model::builder::MarkerHandle;

/// A sensor as written in a file.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    pub name: String,
    /// Body name (`car_body`, `knuckle_fl`, `arm_rl`, `hitch`, `trailer_box`, ...).
    pub body: String,
    /// Position in the coordinates of the body's subsystem (vehicle or trailer) [m].
    pub position_m: Option<[f64; 3]>,
    /// On the modal hitch: the node it sits on (instead of a position).
    pub node: Option<String>,
    /// Measuring axes, a subset of "x", "y", "z" (the subsystem's axes).
    pub axes: Vec<String>,
}

/// A sensor in the model.
#[derive(Clone, Debug)]
pub struct Sensor {
    /// Sensor name; its channels are `acc_<name>_<axis>`.
    pub name: String,
    /// Marker at the sensor, with the measuring axes.
    pub marker: MarkerHandle,
    /// Which of x, y, z it measures.
    pub axes: [bool; 3],
}

/// Adds the sensors of `specs` (at `p` in `src`) as markers.
pub fn add(
    b: &mut Builder,
    h: &Handles,
    src: &Source,
    p: &[Seg],
    specs: &[SensorSpec],
) -> Result<Vec<Sensor>, InputError> {
    let mut out: Vec<Sensor> = Vec::new();
    for (k, s) in specs.iter().enumerate() {
        let at = |key: &str| {
            let mut v = p.to_vec();
            v.push(Seg::Index(k));
            v.push(Seg::from(key));
            v
        };
        let ok_name = !s.name.is_empty()
            && s.name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !ok_name || out.iter().any(|o| o.name == s.name) {
            return Err(src.error(
                &at("name"),
                format!(
                    "sensor name '{}' must be unique, of letters, digits and '_'",
                    s.name
                ),
            ));
        }
        let &body = h.bodies.get(&s.body).ok_or_else(|| {
            src.error(&at("body"), format!("no body '{}' in this vehicle", s.body))
        })?;
        let mut axes = [false; 3];
        for (a, name) in s.axes.iter().enumerate() {
            let c = ["x", "y", "z"]
                .iter()
                .position(|x| x == name)
                .ok_or_else(|| {
                    let mut q = at("axes");
                    q.push(Seg::Index(a));
                    src.error(&q, format!("'{name}': use x, y or z"))
                })?;
            axes[c] = true;
        }
        if !axes.iter().any(|a| *a) {
            return Err(src.error(&at("axes"), "name at least one axis"));
        }
        let name = format!("sensor_{}", s.name);
        let place = h
            .place_of(body)
            .expect("the bodies named in the handles are placed");
        let marker = match (&s.node, &s.position_m) {
            (Some(node), None) => {
                let modal = b.model().bodies[body].modal.as_ref().ok_or_else(|| {
                    src.error(
                        &at("node"),
                        format!("body '{}' is rigid: give position_m", s.body),
                    )
                })?;
                let n = modal
                    .data
                    .nodes
                    .iter()
                    .position(|x| &x.name == node)
                    .ok_or_else(|| {
                        src.error(&at("node"), format!("no node '{node}' on '{}'", s.body))
                    })?;
                let pos = modal.data.nodes[n].position_m;
                let cm = modal.data.com_m;
                // Node position relative to the body's centre of mass, in world axes.
                let rel = place.vector(towride_mbs::model::math::sub(&pos, &cm));
                let world = towride_mbs::model::math::add(&b.model().bodies[body].position, &rel);
                let k =
                    b.mb.world_marker(&name, Some(body), world, place.rotation)
                        .map_err(|e| src.locate(&at("name"), e.into_field()))?;
                b.mb.pin_to_node(k, n);
                k
            }
            (None, Some(pos)) => {
                let pos = point(src, &at("position_m"), pos)?;
                let saved = b.mb.place();
                b.set_place(place);
                let k = b.add(|m| m.marker(&name, Some(body), pos, &IDENTITY));
                b.set_place(saved);
                k?
            }
            _ => return Err(src.error(&at("position_m"), "give exactly one of position_m or node")),
        };
        out.push(Sensor {
            name: s.name.clone(),
            marker,
            axes,
        });
    }
    Ok(out)
}
