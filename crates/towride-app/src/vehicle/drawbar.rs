//! The box trailer's drawbar as an option (`[drawbar] kind`): rigid, part of the trailer
//! body (the default), or flexible, a modal body (the Craig-Bampton data of a beam FE
//! model, `flex/drawbar.toml`) fixed to the trailer body at its frame interface nodes
//! and carrying the ball coupling at its ball node. The thesis modelled the drawbar as a
//! flexible FE body (5.5.3.1). The FE model's mass, centre of mass and inertia are taken
//! out of the trailer body's so the trailer's total and its static nose load stay the
//! same (docs/hitch_mounts.md, "Drawbar").

use std::path::Path;

use serde::Deserialize;

use super::build::Builder;
use super::geom::{IDENTITY, V};
use super::modal_body;
use super::props::{at, point, Mass};
use towride_mbs::flex::ModalData;
use towride_mbs::input::{InputError, Seg, Source};
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::model::desc::{Coupling, JointKind};
use towride_mbs::model::elements::JointBushing;
use towride_mbs::model::math::{add, scale, sub};

/// Which drawbar the trailer has.
#[derive(Deserialize, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum DrawbarKind {
    /// Part of the rigid trailer body.
    #[default]
    Rigid,
    /// A modal body fixed to the trailer body.
    Flexible,
}

/// `[drawbar]` of the trailer's property file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct DrawbarProps {
    pub kind: DrawbarKind,
    /// The FE model (relative to the property file).
    pub fe_file: String,
    /// Where the FE file's origin lies in trailer coordinates [m] (axes the trailer's).
    pub fe_origin_m: [f64; 3],
    /// Inertia coupling of the modal body: constant, partial or full.
    pub inertia_coupling: String,
    /// Interface nodes bolted to the trailer frame.
    pub frame_nodes: [String; 2],
    /// Interface node at the ball-socket centre.
    pub ball_node: String,
}

/// The flexible drawbar, read and reduced.
pub struct Flexible {
    data: ModalData,
    origin: V,
    coupling: Coupling,
    frame: [usize; 2],
    ball: usize,
}

impl Flexible {
    /// Mass, centre of mass and inertia of the undeformed drawbar (trailer coordinates).
    pub fn mass(&self) -> Mass {
        Mass {
            mass: self.data.mass_kg,
            cm: add(&self.origin, &self.data.com_m),
            inertia: self.data.inertia_com_kg_m2,
        }
    }
}

/// The flexible drawbar of `d` (the table at `p` of `src`, read from `file`) when its
/// kind asks for one; `coupling` is the trailer's ball-socket centre, which the ball
/// node must sit on.
pub fn read(
    src: &Source,
    p: &[Seg],
    file: &Path,
    d: &DrawbarProps,
    coupling_at: V,
    b: &Builder,
) -> Result<Option<Flexible>, InputError> {
    if d.kind == DrawbarKind::Rigid {
        return Ok(None);
    }
    let origin = point(src, &at(p, "fe_origin_m"), &d.fe_origin_m)?;
    let coupling = modal_body::coupling(src, &at(p, "inertia_coupling"), &d.inertia_coupling)?;
    let fe = file.parent().unwrap_or(Path::new(".")).join(&d.fe_file);
    let data = modal_body::load(src, &at(p, "fe_file"), &fe, None, None, b, "drawbar")?;
    let frame = modal_body::nodes(src, &at(p, "frame_nodes"), &data, &fe, &d.frame_nodes)?;
    let ball = modal_body::node(src, &at(p, "ball_node"), &data, &fe, &d.ball_node)?;
    let pos = add(&origin, &data.nodes[ball].position_m);
    let off = sub(&pos, &coupling_at);
    // The coupling holds the ball node: it must be the trailer's coupling point.
    if off.iter().any(|x| x.abs() > 1e-6) {
        return Err(src.error(
            &at(p, "ball_node"),
            format!(
                "node '{}' lies at ({:.4}, {:.4}, {:.4}) m, not at the trailer's coupling_m",
                d.ball_node, pos[0], pos[1], pos[2]
            ),
        ));
    }
    Ok(Some(Flexible {
        data,
        origin,
        coupling,
        frame,
        ball,
    }))
}

/// The rigid part `whole` less the part `part` (same coordinates): mass, centre of mass
/// and inertia about it (parallel-axis theorem), or a message when what is left is no
/// body (mass or inertia not positive).
pub fn remove(whole: &Mass, part: &Mass) -> Result<Mass, String> {
    let m = whole.mass - part.mass;
    if m <= 0.0 {
        return Err(format!(
            "the drawbar's {:.3} kg is not less than the body's {:.3} kg",
            part.mass, whole.mass
        ));
    }
    let cm = scale(
        &sub(&scale(&whole.cm, whole.mass), &scale(&part.cm, part.mass)),
        1.0 / m,
    );
    // Inertia about the common origin cm: each part's own plus its parallel-axis term.
    let shift = |p: &Mass| {
        let d = sub(&p.cm, &cm);
        let d2: f64 = d.iter().map(|x| x * x).sum();
        let mut out = p.inertia;
        for (r, row) in out.iter_mut().enumerate() {
            for (c, x) in row.iter_mut().enumerate() {
                let delta = if r == c { 1.0 } else { 0.0 };
                *x += p.mass * (d2 * delta - d[r] * d[c]);
            }
        }
        out
    };
    let (iw, ip) = (shift(whole), shift(part));
    let mut inertia = [[0.0; 3]; 3];
    for r in 0..3 {
        for c in 0..3 {
            inertia[r][c] = iw[r][c] - ip[r][c];
        }
    }
    // Positive definite: leading principal minors (Sylvester's criterion).
    let i = &inertia;
    let m2 = i[0][0] * i[1][1] - i[0][1] * i[1][0];
    let m3 = i[0][0] * (i[1][1] * i[2][2] - i[1][2] * i[2][1])
        - i[0][1] * (i[1][0] * i[2][2] - i[1][2] * i[2][0])
        + i[0][2] * (i[1][0] * i[2][1] - i[1][1] * i[2][0]);
    if i[0][0] <= 0.0 || m2 <= 0.0 || m3 <= 0.0 {
        return Err(format!(
            "without the drawbar the body's inertia is not positive definite (diagonal {:.3}, {:.3}, {:.3} kg m^2): give the body's inertia with the drawbar in it",
            i[0][0], i[1][1], i[2][2]
        ));
    }
    Ok(Mass {
        mass: m,
        cm,
        inertia,
    })
}

/// What the drawbar added.
pub struct Joined {
    pub body: BodyHandle,
    /// Its ball node, where the coupling acts.
    pub ball_node: usize,
}

/// Adds the drawbar and fixes its frame nodes to the trailer body `frame` (fixed joints,
/// or the trailer's `[joints]` bushing when its joints are switched to bushings).
pub fn join(
    b: &mut Builder,
    f: Flexible,
    frame: BodyHandle,
    jb: Option<&JointBushing>,
) -> Result<Joined, InputError> {
    let (origin, nodes, ball_node) = (f.origin, f.frame, f.ball);
    let body = modal_body::add_body(b, "drawbar", f.data, origin, f.coupling)?;
    for (k, side) in ["left", "right"].into_iter().enumerate() {
        let p = modal_body::node_position(b, body, origin, nodes[k]);
        let name = format!("drawbar_frame_{side}");
        let link = b.add(|m| {
            m.joint(
                &name,
                JointKind::Fixed,
                Some(body),
                Some(frame),
                p,
                &IDENTITY,
                jb,
            )
        })?;
        modal_body::pin(b, link, true, nodes[k]);
    }
    Ok(Joined { body, ball_node })
}
