//! Requested outputs: marker kinematics, joint reactions and element measures, evaluated
//! from a solver state (y, y') and laid out as named channels with units.

use super::desc::{
    Accelerations, Axes, BodyQuantity, Carrier, ElementQuantity, JointHandle, JointQuantity,
    LinePart, MarkerHandle, MarkerQuantity, ModalQuantity, Model, MotionDof, Output,
    RelativeQuantity, Request, TyreQuantity,
};
use super::elements::Force;
use super::joint::joint_coordinate;
use super::math::{add, cross, mtv, mv, rot, sub};
use super::system::{Owner, System};

/// One column of the output table.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ChannelInfo {
    /// Channel name, e.g. `hitch_fx` or `body.x`.
    pub name: String,
    /// Unit, e.g. "m/s^2".
    pub unit: &'static str,
    /// Angles that should be unwrapped over time.
    #[serde(skip)]
    pub angle: bool,
}

fn vec_channels(base: &str, unit: &'static str) -> Vec<ChannelInfo> {
    ["x", "y", "z"]
        .iter()
        .map(|c| ChannelInfo {
            name: format!("{base}.{c}"),
            unit,
            angle: false,
        })
        .collect()
}

/// Components of a stress-point output, in order (`flex::stress::NominalStress`, then
/// the signed fibre stresses of `flex::stress::Fibres::fibre_stresses`).
pub const STRESS_PARTS: [&str; 8] = [
    "sx_max", "sx_min", "tau", "eq", "sx_f1", "sx_f2", "sx_f3", "sx_f4",
];

/// Components of a transmitted-load output, in order: force, then moment.
pub const TRANSMITTED_PARTS: [&str; 6] = ["fx", "fy", "fz", "mx", "my", "mz"];

/// The channels of every requested output, in order.
pub fn channels(sys: &System) -> Vec<ChannelInfo> {
    channels_of(&sys.model)
}

/// The channels of every requested output of a model (no assembly needed).
pub fn channels_of(m: &Model) -> Vec<ChannelInfo> {
    let mut out = Vec::new();
    for o in &m.outputs {
        let raw = raw_channels(m, o);
        match &o.components {
            None => out.extend(raw),
            Some(names) => out.extend(raw.into_iter().zip(names).filter_map(|(c, n)| {
                (!n.is_empty()).then(|| ChannelInfo {
                    name: n.clone(),
                    ..c
                })
            })),
        }
    }
    out
}

/// How many components `request` produces (the length `Output::components` must have).
pub fn component_count(m: &Model, request: &Request) -> usize {
    raw_channels(m, &Output::new(String::new(), request.clone())).len()
}

/// The default channels of one output.
fn raw_channels(m: &Model, o: &Output) -> Vec<ChannelInfo> {
    let mut out = Vec::new();
    let one = |unit: &'static str| ChannelInfo {
        name: o.name.clone(),
        unit,
        angle: false,
    };
    match &o.request {
        Request::Tyre { quantity, .. } => out.push(match quantity {
            TyreQuantity::NormalForce | TyreQuantity::LongitudinalForce => one("N"),
            TyreQuantity::Contact => one("-"),
            TyreQuantity::EffectiveRoadHeight => one("m"),
        }),
        Request::LinePart { .. } => out.push(one("N")),
        Request::Transmitted { .. } => out.extend(TRANSMITTED_PARTS.iter().enumerate().map(
            |(k, c)| ChannelInfo {
                name: format!("{}.{c}", o.name),
                unit: if k < 3 { "N" } else { "N m" },
                angle: false,
            },
        )),
        Request::DriveTorque { .. } | Request::BrakeTorque { .. } => out.push(one("N m")),
        Request::LinePressure { .. } => out.push(one("Pa")),
        Request::Relative { quantity, .. } => out.push(one(match quantity {
            RelativeQuantity::Position => "m",
            RelativeQuantity::Velocity => "m/s",
        })),
        Request::Body { quantity, .. } => out.push(one(match quantity {
            BodyQuantity::Heave => "m",
            BodyQuantity::Pitch | BodyQuantity::Roll => "rad",
        })),
        Request::Modal { body, quantity } => match quantity {
            ModalQuantity::Coordinates => {
                let n = m.bodies[*body]
                    .modal
                    .as_ref()
                    .map_or(0, |md| md.data.modes.len());
                out.extend((1..=n).map(|k| ChannelInfo {
                    name: format!("{}.{k}", o.name),
                    unit: "-",
                    angle: false,
                }));
            }
            ModalQuantity::StrainEnergy => out.push(one("J")),
            ModalQuantity::Deflection { .. } => out.extend(vec_channels(&o.name, "m")),
            ModalQuantity::Stress { .. } => out.extend(STRESS_PARTS.iter().map(|c| ChannelInfo {
                name: format!("{}.{c}", o.name),
                unit: "Pa",
                angle: false,
            })),
        },
        Request::Marker { quantity, .. } => {
            let unit = match quantity {
                MarkerQuantity::Position => "m",
                MarkerQuantity::Velocity => "m/s",
                MarkerQuantity::Acceleration => "m/s^2",
                MarkerQuantity::AngularVelocity => "rad/s",
                MarkerQuantity::AngularAcceleration => "rad/s^2",
            };
            out.extend(vec_channels(&o.name, unit));
        }
        Request::Joint {
            joint, quantity, ..
        } => match quantity {
            JointQuantity::Force => out.extend(vec_channels(&o.name, "N")),
            JointQuantity::Torque => out.extend(vec_channels(&o.name, "N m")),
            JointQuantity::Displacement => {
                let rotational = matches!(m.joints[*joint].kind, super::desc::JointKind::Revolute);
                out.push(ChannelInfo {
                    name: o.name.clone(),
                    unit: if rotational { "rad" } else { "m" },
                    angle: rotational,
                });
            }
        },
        Request::Element { element, quantity } => {
            let q = match quantity {
                ElementQuantity::Force => 0,
                ElementQuantity::Deflection => 1,
                ElementQuantity::Velocity => 2,
            };
            let names: Vec<(String, &'static str, bool)> = m.forces[*element]
                .measures()
                .into_iter()
                .map(|ms| {
                    (
                        ms.suffix
                            .map_or(o.name.clone(), |sfx| format!("{}.{sfx}", o.name)),
                        ms.units[q],
                        ms.angle && q == 1,
                    )
                })
                .collect();
            out.extend(names.into_iter().map(|(name, unit, angle)| ChannelInfo {
                name,
                unit,
                angle,
            }));
        }
    }
    out
}

/// Applies an output's scale and drops its unnamed components, in place from `start`.
fn finish(o: &Output, out: &mut Vec<f64>, start: usize) {
    let vals: Vec<f64> = out.drain(start..).map(|v| o.scale * v).collect();
    match &o.components {
        None => out.extend(vals),
        Some(names) => out.extend(
            vals.into_iter()
                .zip(names)
                .filter_map(|(v, n)| (!n.is_empty()).then_some(v)),
        ),
    }
}

/// Values of every channel at (t, y, y').
pub fn evaluate(sys: &System, t: f64, y: &[f64], yp: &[f64]) -> Vec<f64> {
    let (_, ov, ol, om) = sys.offsets();
    let q = &y[..ov];
    let v = &y[ov..ol];
    let x = &y[sys.oe()..];
    let m = &sys.model;
    // With `Accelerations::Solve`, accelerations and reactions come from the
    // acceleration-level equations at (q, v) rather than from the integrator's
    // interpolant (y') and its index-2 multipliers.
    let needs = m.accelerations == Accelerations::Solve
        && m.outputs.iter().any(|o| {
            matches!(
                o.request,
                Request::Marker {
                    quantity: MarkerQuantity::Acceleration | MarkerQuantity::AngularAcceleration,
                    ..
                } | Request::Joint {
                    quantity: JointQuantity::Force | JointQuantity::Torque,
                    ..
                } | Request::Transmitted {
                    by: Carrier::Joint(_),
                    ..
                }
            )
        });
    let solved = if needs {
        super::ic::accelerations(sys, t, q, v, x).ok()
    } else {
        None
    };
    let (vd, lam): (&[f64], &[f64]) = match &solved {
        Some((a, l)) => (a, l),
        None => (&yp[ov..ol], &y[ol..om]),
    };
    let mut out = Vec::new();
    let resolve = |axes: Axes, w: [f64; 3]| -> [f64; 3] {
        match axes {
            Axes::World => w,
            Axes::Marker(k) => mtv(&sys.marker_frame(q, k).axes, &w),
        }
    };
    for o in &m.outputs {
        let start = out.len();
        match &o.request {
            Request::Marker {
                marker,
                quantity,
                axes,
            } => {
                let mk = &m.markers[*marker];
                let w = match sys.body_of(*marker) {
                    None if *quantity == MarkerQuantity::Position => mk.position,
                    None => [0.0; 3],
                    Some(b) => marker_kinematics(sys, *marker, b, *quantity, q, v, vd),
                };
                out.extend_from_slice(&resolve(*axes, w));
            }
            Request::Joint {
                joint,
                quantity,
                axes,
            } => {
                let j = &m.joints[*joint];
                match quantity {
                    JointQuantity::Displacement => {
                        let dof = match j.kind {
                            super::desc::JointKind::Revolute => MotionDof::Rotation,
                            _ => MotionDof::Translation,
                        };
                        out.push(joint_coordinate(
                            dof,
                            &sys.marker_frame(q, j.i),
                            &sys.marker_frame(q, j.j),
                        ));
                    }
                    JointQuantity::Force | JointQuantity::Torque => {
                        let (f, tq) = reaction(sys, *joint, t, q, lam);
                        let w = if *quantity == JointQuantity::Force {
                            f
                        } else {
                            tq
                        };
                        out.extend_from_slice(&resolve(*axes, w));
                    }
                }
            }
            Request::Tyre { tyre, quantity } => {
                let te = &m.tyres[*tyre];
                let road = m.road.as_ref().expect("validated: tyres need a road");
                let kin = sys.wheel_kinematics(q, v, te.marker);
                let e = sys
                    .ext
                    .iter()
                    .find(|e| e.kind == super::system::ExtKind::Tyre(*tyre))
                    .expect("every tyre has its states");
                let c = te.tyre.outputs(&kin, road, &x[e.off..e.off + e.n]);
                out.push(match quantity {
                    TyreQuantity::NormalForce => c.normal_force,
                    TyreQuantity::LongitudinalForce => c.longitudinal_force,
                    TyreQuantity::Contact => f64::from(c.normal_force > 0.0),
                    TyreQuantity::EffectiveRoadHeight => c.effective.height,
                });
            }
            Request::Transmitted { by, axes } => {
                let (f, tq) = transmitted(sys, *by, t, q, v, lam);
                out.extend_from_slice(&resolve(*axes, f));
                out.extend_from_slice(&resolve(*axes, tq));
            }
            Request::DriveTorque { control } | Request::BrakeTorque { control } => {
                let e = sys
                    .ext
                    .iter()
                    .find(|e| e.kind == super::system::ExtKind::Control(*control))
                    .expect("every controller has its states");
                let speed = sys.control_speed(*control, q, v);
                let demand = sys.control_demand(*control, t, speed, x[e.off]);
                let (engine, brake) = sys.control_split(*control, t, demand);
                let drive = matches!(o.request, Request::DriveTorque { .. });
                out.push(if drive { engine } else { brake });
            }
            Request::LinePart { element, part } => {
                let (_, _, meas) = sys.force_eval(*element, t, q, v);
                let (_, x, rate) = meas[0];
                out.push(line_part(&m.forces[*element], *part, x, rate));
            }
            Request::LinePressure { element, area_m2 } => {
                let (_, _, meas) = sys.force_eval(*element, t, q, v);
                let (_, x, rate) = meas[0];
                out.push(line_part(&m.forces[*element], LinePart::Spring, x, rate) / area_m2);
            }
            Request::Relative {
                i,
                j,
                axis,
                quantity,
                offset,
            } => {
                let (fi, fj) = (sys.marker_frame(q, *i), sys.marker_frame(q, *j));
                let d = sub(&fi.origin, &fj.origin);
                out.push(match quantity {
                    RelativeQuantity::Position => mtv(&fj.axes, &d)[*axis] - offset,
                    RelativeQuantity::Velocity => {
                        let kin = |k: MarkerHandle, what| match sys.body_of(k) {
                            Some(b) => marker_kinematics(sys, k, b, what, q, v, &yp[ov..ol]),
                            None => [0.0; 3],
                        };
                        let vi = kin(*i, MarkerQuantity::Velocity);
                        let vj = kin(*j, MarkerQuantity::Velocity);
                        let wj = kin(*j, MarkerQuantity::AngularVelocity);
                        // d/dt (A^T d) = A^T (d' - w x d) for axes A turning at w.
                        let rate = sub(&sub(&vi, &vj), &cross(&wj, &d));
                        mtv(&fj.axes, &rate)[*axis]
                    }
                });
            }
            Request::Body {
                body,
                quantity,
                z_ref,
            } => {
                // The body's number in the system's layout of the unknowns.
                let (r, p) = sys.pose(q, body.index());
                let a = rot(&p);
                out.push(match quantity {
                    BodyQuantity::Heave => r[2] - z_ref,
                    BodyQuantity::Pitch => -a[2][0].clamp(-1.0, 1.0).asin(),
                    BodyQuantity::Roll => a[2][1].atan2(a[2][2]),
                });
            }
            Request::Modal { body, quantity } => {
                // The body's number in the system's layout of the unknowns: its modal
                // coordinates are columns of q.
                let k = body.index();
                let o0 = sys.qo[k] + 7;
                let eta = &q[o0..o0 + sys.nm[k]];
                match quantity {
                    ModalQuantity::Coordinates => out.extend_from_slice(eta),
                    ModalQuantity::StrainEnergy => out.push(sys.strain_energy(k, q).0),
                    ModalQuantity::Stress { point } => {
                        let md = &m.bodies[*body].modal.as_ref().expect("modal body").data;
                        let s = md.stress.stress_at(*point, eta);
                        out.extend([s.sx_max, s.sx_min, s.tau, s.eq]);
                        out.extend(md.stress.fibres_at(*point, eta));
                    }
                    ModalQuantity::Deflection { node, reference } => {
                        let md = &m.bodies[*body].modal.as_ref().expect("modal body").data;
                        let disp = |n: usize| -> [f64; 3] {
                            std::array::from_fn(|c| {
                                md.nodes[n]
                                    .shapes
                                    .iter()
                                    .zip(eta)
                                    .map(|(s, e)| s[c] * e)
                                    .sum()
                            })
                        };
                        let mut d = disp(*node);
                        for r in reference {
                            let dr = disp(*r);
                            for c in 0..3 {
                                d[c] -= dr[c] / reference.len() as f64;
                            }
                        }
                        out.extend_from_slice(&d);
                    }
                }
            }
            Request::Element { element, quantity } => {
                let fe = *element;
                let (_, _, meas) = sys.force_eval(fe, t, q, v);
                for (f, d, r) in meas {
                    out.push(match quantity {
                        ElementQuantity::Force => f,
                        ElementQuantity::Deflection => d,
                        ElementQuantity::Velocity => r,
                    });
                }
            }
        }
        finish(o, &mut out, start);
    }
    out
}

/// One law's share of a spring-damper line's repulsive force at extension `x` [m] and
/// its rate [m/s] (zero for a law the element does not have, or another element).
fn line_part(f: &Force, part: LinePart, x: f64, rate: f64) -> f64 {
    let Force::Spring(s) = f else {
        return 0.0;
    };
    match part {
        LinePart::Spring => s.preload - s.spring.at(x),
        LinePart::Damper => -s.damper.at(rate),
        LinePart::BumpStop => s
            .bump_stop
            .as_ref()
            .map_or(0.0, |st| st.force(-x - st.clearance, -rate)),
        LinePart::ReboundStop => s
            .rebound_stop
            .as_ref()
            .map_or(0.0, |st| -st.force(x - st.clearance, rate)),
    }
}

/// The force (world) that joint or element `by` passes into the body of its marker J, and
/// the moment about J's origin. Both act at marker I's origin (a joint's reaction, an
/// element's load) with the opposite sign on J, so the moment about J adds the arm from J
/// to I: m_J = -(t_I + (p_I - p_J) x f_I). An element without marker J reports the load
/// it puts on the ground at I.
fn transmitted(
    sys: &System,
    by: Carrier,
    t: f64,
    q: &[f64],
    v: &[f64],
    lam: &[f64],
) -> ([f64; 3], [f64; 3]) {
    let (f, tq, p_i, j) = match by {
        Carrier::Joint(k) => {
            let (f, tq) = reaction(sys, k, t, q, lam);
            let jt = &sys.model.joints[k];
            (f, tq, sys.marker_frame(q, jt.i).origin, Some(jt.j))
        }
        Carrier::Element(e) => {
            let (f, tq, p) = sys.element_wrench(e, t, q, v);
            (f, tq, p, sys.model.forces[e].markers().1)
        }
    };
    let p_j = j.map_or(p_i, |j| sys.marker_frame(q, j).origin);
    let m = add(&tq, &cross(&sub(&p_i, &p_j), &f));
    (f.map(|x| -x), m.map(|x| -x))
}

/// Reaction force (world) on joint `jk`'s I body at marker I, and torque about marker I,
/// from the multipliers of the joint and of any motion acting on it.
pub fn reaction(
    sys: &System,
    jk: JointHandle,
    t: f64,
    q: &[f64],
    lam: &[f64],
) -> ([f64; 3], [f64; 3]) {
    let j = &sys.model.joints[jk];
    let Some(bi) = sys.body_of(j.i) else {
        return ([0.0; 3], [0.0; 3]);
    };
    let mut gen = [0.0; 6];
    for e in &sys.cons {
        let on_joint = match e.owner {
            Owner::Joint(k) => k == jk,
            Owner::Motion(k) => sys.model.motions[k].joint == jk,
        };
        if !on_joint {
            continue;
        }
        let ev = sys.con_eval(e, t, q);
        for (r, slot) in e.slot.iter().enumerate() {
            if let Some(row) = slot {
                for (c, g) in gen.iter_mut().enumerate() {
                    *g -= ev.at(r, 0, c) * lam[*row];
                }
            }
        }
    }
    let (r, p) = sys.pose(q, bi);
    let a = rot(&p);
    let f = [gen[0], gen[1], gen[2]];
    let t_cm = mv(&a, &[gen[3], gen[4], gen[5]]);
    let arm = sub(&sys.marker_frame(q, j.i).origin, &r);
    // moment about I = moment about the centre of mass - arm x F
    let t_i = sub(&t_cm, &cross(&arm, &f));
    (f, t_i)
}

/// Kinematics of marker `mk` on body `b` (world axes). Rigid markers use the rigid-body
/// formulas; on a modal body the velocity is J(q) v and the acceleration J v' + J' v,
/// with J' v differentiated numerically along the motion.
fn marker_kinematics(
    sys: &System,
    mk: MarkerHandle,
    b: usize,
    quantity: MarkerQuantity,
    q: &[f64],
    v: &[f64],
    vd: &[f64],
) -> [f64; 3] {
    let w0 = sys.vo[b];
    let nvb = 6 + sys.nm[b];
    if quantity == MarkerQuantity::Position {
        return sys.marker_frame(q, mk).origin;
    }
    if !sys.is_flex_marker(mk) {
        let (_, p) = sys.pose(q, b);
        let a = rot(&p);
        let om_b = [v[w0 + 3], v[w0 + 4], v[w0 + 5]];
        let al_b = [vd[w0 + 3], vd[w0 + 4], vd[w0 + 5]];
        let s = sys.model.markers[mk].position;
        return match quantity {
            MarkerQuantity::Velocity => {
                add(&[v[w0], v[w0 + 1], v[w0 + 2]], &mv(&a, &cross(&om_b, &s)))
            }
            MarkerQuantity::Acceleration => {
                let rel = add(&cross(&al_b, &s), &cross(&om_b, &cross(&om_b, &s)));
                add(&[vd[w0], vd[w0 + 1], vd[w0 + 2]], &mv(&a, &rel))
            }
            MarkerQuantity::AngularVelocity => mv(&a, &om_b),
            _ => mv(&a, &al_b),
        };
    }
    let ff = sys.flex_frame(q, mk);
    let vb = &v[w0..w0 + nvb];
    let (vel, om) = ff.rates(vb);
    match quantity {
        MarkerQuantity::Velocity => vel,
        MarkerQuantity::AngularVelocity => om,
        _ => {
            let (a1, al1) = ff.rates(&vd[w0..w0 + nvb]);
            let qd = sys.qdot_of(q, v);
            let h = 1e-6;
            let shift =
                |s: f64| -> Vec<f64> { q.iter().zip(&qd).map(|(x, d)| x + s * h * d).collect() };
            let (vp, wp) = sys.flex_frame(&shift(1.0), mk).rates(vb);
            let (vm, wm) = sys.flex_frame(&shift(-1.0), mk).rates(vb);
            let d = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| -> [f64; 3] {
                std::array::from_fn(|k| a[k] + (b[k] - c[k]) / (2.0 * h))
            };
            if quantity == MarkerQuantity::Acceleration {
                d(a1, vp, vm)
            } else {
                d(al1, wp, wm)
            }
        }
    }
}
