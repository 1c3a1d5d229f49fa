//! The data of the reports' 3D view (`assets/view3d.js`, three.js): every body of the
//! model drawn from its mass properties and hardpoints, the force elements between
//! them, the wheels with their tyres, a modal body's FE mesh with its mode shapes, and
//! the road under the vehicle; then either a run's poses or a linearisation's mode
//! shapes to move them.
//!
//! Nothing here knows the vehicle: a body is a box with the inertia of the body (a
//! uniform box with the same principal moments), rods from its centre of mass to the
//! markers that joints, force elements and tyres use, a wheel where a tyre sits.

use std::fmt::Write as _;

use nalgebra::{Matrix3, SymmetricEigen, UnitQuaternion};

use super::html::{quantised, string};
use towride_mbs::model::run::Poses;
use towride_mbs::model::System;

/// Road grid spacing along x [m]: the surface's kinks (an obstacle's edges) are added
/// exactly, and between them the roads here are linear or gently curved.
const ROAD_DX_M: f64 = 0.05;
/// Road drawn beyond the vehicle's travel at each end [m].
const ROAD_MARGIN_M: f64 = 3.0;
/// Smallest box side drawn [m] (a body with a near-zero principal moment).
const MIN_SIDE_M: f64 = 0.02;

/// A number rounded to 6 decimals (micrometres, microradians: below any pixel), as
/// `format!("{}", (v * 1e6).round() / 1e6)` prints it, written from the integer of
/// millionths: the poses are most of the view's numbers, and the formatting machinery
/// was most of the view's build time.
fn n6(out: &mut String, v: f64) {
    if !v.is_finite() {
        out.push_str("null");
        return;
    }
    let micro = (v * 1e6).round();
    if micro.abs() >= 9e15 {
        let _ = write!(out, "{}", micro / 1e6);
        return;
    }
    let micro = micro as i64;
    if micro < 0 {
        out.push('-');
    }
    let (whole, frac) = (
        micro.unsigned_abs() / 1_000_000,
        micro.unsigned_abs() % 1_000_000,
    );
    crate::report::html::integer(out, whole as i64);
    if frac > 0 {
        let mut digits = [b'0'; 6];
        let mut f = frac;
        for d in digits.iter_mut().rev() {
            *d = b'0' + (f % 10) as u8;
            f /= 10;
        }
        let end = 6 - digits.iter().rev().take_while(|&&d| d == b'0').count();
        out.push('.');
        out.push_str(std::str::from_utf8(&digits[..end]).unwrap_or("0"));
    }
}

/// `[a,b,...]` with each item written by `f`.
fn list<T>(
    out: &mut String,
    items: impl IntoIterator<Item = T>,
    mut f: impl FnMut(&mut String, T),
) {
    out.push('[');
    for (k, x) in items.into_iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        f(out, x);
    }
    out.push(']');
}

/// Numbers with 6 significant digits as a JSON array.
fn numbers(out: &mut String, v: impl IntoIterator<Item = f64>) {
    list(out, v, n6);
}

fn vec3(out: &mut String, v: [f64; 3]) {
    numbers(out, v);
}

/// Side lengths of the uniform box with the body's principal moments, and the
/// orientation of its principal axes in body axes (w, x, y, z).
pub fn inertia_box(mass: f64, inertia: &[[f64; 3]; 3]) -> ([f64; 3], [f64; 4]) {
    let j = Matrix3::from_fn(|r, c| inertia[r][c]);
    let e = SymmetricEigen::new(j);
    let mut axes = e.eigenvectors;
    if axes.determinant() < 0.0 {
        axes.set_column(2, &(-axes.column(2)));
    }
    let i = e.eigenvalues;
    // I_x = m (b^2 + c^2) / 12 ... => a^2 = 6 (I_y + I_z - I_x) / m.
    let side = |a: usize, b: usize, c: usize| {
        if mass > 0.0 {
            (6.0 * (i[b] + i[c] - i[a]) / mass).max(0.0).sqrt()
        } else {
            0.0
        }
        .max(MIN_SIDE_M)
    };
    let q = UnitQuaternion::from_matrix(&axes);
    (
        [side(0, 1, 2), side(1, 2, 0), side(2, 0, 1)],
        [q.w, q.i, q.j, q.k],
    )
}

/// The geometry part of the view's JSON (`{"bodies":..., "markers":..., ...}` without
/// the closing brace): `x_range` is the stretch of road to draw [m].
fn geometry(out: &mut String, sys: &System, x_range: (f64, f64)) {
    let m = &sys.model;
    // Markers something acts on: joints, force elements, tyres.
    let mut used = std::collections::HashSet::new();
    for j in &m.joints {
        used.insert(j.i);
        used.insert(j.j);
    }
    for f in &m.forces {
        let (i, j) = f.markers();
        used.insert(i);
        used.extend(j);
    }
    for t in &m.tyres {
        used.insert(t.marker);
    }
    // Bodies are numbered as the system numbers them (their JSON index, `qo`, `nm`).
    let wheel_of = |b: usize| m.tyres.iter().any(|t| sys.body_of(t.marker) == Some(b));
    out.push_str("{\"bodies\":[");
    for (b, body) in m.bodies.iter().enumerate() {
        if b > 0 {
            out.push(',');
        }
        let (side, axes) = inertia_box(body.mass, &body.inertia);
        out.push_str("{\"name\":");
        string(out, &body.name);
        let _ = write!(
            out,
            ",\"qo\":{},\"nm\":{},\"wheel\":{},\"mass\":",
            sys.qo[b],
            sys.nm[b],
            wheel_of(b)
        );
        n6(out, body.mass);
        out.push_str(",\"box\":");
        vec3(out, side);
        out.push_str(",\"box_q\":");
        numbers(out, axes);
        out.push_str(",\"flex\":");
        match &body.modal {
            Some(md) => {
                let sk = &md.data.skeleton;
                let c = md.data.com_m;
                out.push_str("{\"pts\":");
                list(out, &sk.positions_m, |o, p| {
                    vec3(o, [p[0] - c[0], p[1] - c[1], p[2] - c[2]])
                });
                out.push_str(",\"edges\":");
                out.push_str(&serde_json::to_string(&sk.edges).unwrap_or_default());
                out.push_str(",\"shapes\":");
                list(out, &sk.shapes, |o, s| list(o, s, |o, d| vec3(o, *d)));
                out.push('}');
            }
            None => out.push_str("null"),
        }
        out.push('}');
    }
    // Markers: body (-1 ground), position in body axes, the FE node it moves with.
    out.push_str("],\"markers\":[");
    for (n, (k, mk)) in m.each_marker().enumerate() {
        if n > 0 {
            out.push(',');
        }
        let _ = write!(
            out,
            "{{\"b\":{},\"p\":",
            sys.body_of(k).map_or(-1, |b| b as i64)
        );
        vec3(out, mk.position);
        let node = mk.node.and_then(|_| {
            let md = m.bodies[mk.body?].modal.as_ref()?;
            nearest_node(&md.data.skeleton.positions_m, md.data.com_m, mk.position)
        });
        let _ = write!(
            out,
            ",\"node\":{},\"used\":{}}}",
            node.map_or(-1, |n| n as i64),
            used.contains(&k)
        );
    }
    // Force elements between two markers on different bodies: springs, dampers,
    // bushings, drawn as lines.
    out.push_str("],\"struts\":[");
    let mut first = true;
    for f in &m.forces {
        if let (i, Some(j)) = f.markers() {
            if m.markers[i].body == m.markers[j].body {
                continue;
            }
            if !first {
                out.push(',');
            }
            first = false;
            out.push_str("{\"name\":");
            string(out, f.name());
            out.push_str(",\"kind\":");
            string(out, f.kind());
            // Markers by their index in the JSON's marker list.
            let _ = write!(out, ",\"i\":{},\"j\":{}}}", i.index(), j.index());
        }
    }
    out.push_str("],\"tyres\":[");
    for (k, t) in m.tyres.iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        let p = t.tyre.params();
        let axes = m.markers[t.marker].axes;
        out.push_str("{\"name\":");
        string(out, &t.name);
        // The marker by its index in the JSON's marker list.
        let _ = write!(out, ",\"marker\":{},\"radius\":", t.marker.index());
        n6(out, p.r0);
        out.push_str(",\"width\":");
        n6(out, p.width);
        // The spin axis: the wheel marker's y axis (axes are columns).
        out.push_str(",\"axis\":");
        vec3(out, [axes[0][1], axes[1][1], axes[2][1]]);
        out.push('}');
    }
    out.push(']');
    road(out, sys, x_range);
}

/// The FE node at `p` (relative to the centre of mass `c`) on a skeleton.
fn nearest_node(pts: &[[f64; 3]], c: [f64; 3], p: [f64; 3]) -> Option<usize> {
    let d = |q: &[f64; 3]| (0..3).map(|i| (q[i] - c[i] - p[i]).powi(2)).sum::<f64>();
    (0..pts.len()).min_by(|&a, &b| d(&pts[a]).total_cmp(&d(&pts[b])))
}

/// The road as a grid of heights: x on a regular grid plus every kink of the surface
/// along the vehicle's track (the obstacle's edges drawn sharp), y across the wheels.
fn road(out: &mut String, sys: &System, (x0, x1): (f64, f64)) {
    let m = &sys.model;
    let Some(road) = &m.road else {
        out.push_str(",\"road\":null");
        return;
    };
    // Across: the design wheel-centre y values, half a metre beyond.
    let ys: Vec<f64> = m
        .tyres
        .iter()
        .filter_map(|t| {
            let mk = &m.markers[t.marker];
            let b = &m.bodies[mk.body?];
            // Row y of the body's rotation times the marker's body-axes position.
            let r = towride_mbs::model::math::rot(&b.orientation);
            let p = &mk.position;
            Some(b.position[1] + r[1][0] * p[0] + r[1][1] * p[1] + r[1][2] * p[2])
        })
        .collect();
    let (ya, yb) = ys
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(*y), b.max(*y))
        });
    let (ya, yb) = if ya.is_finite() {
        (ya - 0.5, yb + 0.5)
    } else {
        (-1.5, 1.5)
    };
    let ny = 5;
    let y: Vec<f64> = (0..ny)
        .map(|k| ya + (yb - ya) * k as f64 / (ny - 1) as f64)
        .collect();
    let (x0, x1) = (x0 - ROAD_MARGIN_M, x1 + ROAD_MARGIN_M);
    let n = ((x1 - x0) / ROAD_DX_M).ceil() as usize;
    let mut x: Vec<f64> = (0..=n).map(|k| x0 + k as f64 * ROAD_DX_M).collect();
    for yy in &y {
        let mut kinks = Vec::new();
        road.kinks_along([x0, *yy], [1.0, 0.0], 0.0, x1 - x0, &mut kinks);
        // Both sides of a step.
        x.extend(kinks.iter().flat_map(|s| [x0 + s - 1e-4, x0 + s + 1e-4]));
    }
    x.sort_by(f64::total_cmp);
    x.dedup_by(|a, b| (*a - *b).abs() < 1e-5);
    out.push_str(",\"road\":{\"x\":");
    numbers(out, x.iter().copied());
    out.push_str(",\"y\":");
    numbers(out, y.iter().copied());
    out.push_str(",\"z\":");
    list(out, &y, |o, yy| {
        numbers(o, x.iter().map(|xx| road.height(*xx, *yy)))
    });
    out.push('}');
}

/// The x range the bodies' centres of mass cover over the poses.
fn x_range(sys: &System, frames: &[Vec<f64>]) -> (f64, f64) {
    let mut r = (f64::INFINITY, f64::NEG_INFINITY);
    for q in frames {
        for &o in &sys.qo[..sys.model.bodies.len()] {
            r = (r.0.min(q[o]), r.1.max(q[o]));
        }
    }
    r
}

/// The view of a run: the geometry and the poses (times quantised, each position
/// unknown a quantised column). `None` when the run recorded no poses.
pub fn run_view(sys: &System, poses: &Poses) -> Option<String> {
    if poses.times.is_empty() {
        return None;
    }
    let mut out = String::with_capacity(64 * poses.q.len() * sys.nq / 4 + 65536);
    geometry(&mut out, sys, x_range(sys, &poses.q));
    out.push_str(",\"frames\":{\"t\":");
    quantised(&mut out, poses.times.iter().copied());
    out.push_str(",\"q\":[");
    for c in 0..sys.nq {
        if c > 0 {
            out.push(',');
        }
        quantised(&mut out, poses.q.iter().map(|q| q[c]));
    }
    out.push_str("]}}");
    Some(out)
}

/// One mode for the view: the velocity-space shape (per body: translation [m], rotation
/// about body axes [rad], modal coordinates) scaled to a unit largest translation.
pub struct ModeShape {
    /// Label shown in the mode picker.
    pub label: String,
    /// Frequency [Hz] the animation uses.
    pub frequency_hz: f64,
    /// Velocity-space shape (`System::vo` layout).
    pub shape: Vec<f64>,
}

/// The view of a linearisation: the geometry at the state `q` and the mode shapes.
pub fn modes_view(sys: &System, q: &[f64], modes: &[ModeShape]) -> String {
    let mut out = String::new();
    geometry(&mut out, sys, x_range(sys, &[q.to_vec()]));
    out.push_str(",\"vo\":");
    out.push_str(&serde_json::to_string(&sys.vo).unwrap_or_default());
    out.push_str(",\"q0\":");
    numbers(&mut out, q[..sys.nq].iter().copied());
    out.push_str(",\"modes\":");
    list(&mut out, modes, |o, m| {
        o.push_str("{\"label\":");
        string(o, &m.label);
        o.push_str(",\"f\":");
        n6(o, m.frequency_hz);
        o.push_str(",\"v\":");
        numbers(o, m.shape.iter().copied());
        o.push('}');
    });
    out.push('}');
    out
}

#[cfg(test)]
mod tests {
    /// The fast writer prints what the formatting machinery prints for the rounded value.
    #[test]
    fn n6_matches_display_of_the_rounded_value() {
        let values = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            1e-7,
            -4e-7,
            6e-7,
            0.123456789,
            -2.462,
            12.3400001,
            -0.000001,
            0.000010,
            1234567.8912345,
            -98765.4321,
            3.0e9,
            f64::NAN,
        ];
        for v in values {
            let mut fast = String::new();
            super::n6(&mut fast, v);
            let want = if v.is_finite() {
                format!("{}", (v * 1e6).round() / 1e6)
            } else {
                "null".to_string()
            };
            // -0 prints as "-0" by Display; the fast path writes "0" for it.
            let want = if want == "-0" { "0".to_string() } else { want };
            assert_eq!(fast, want, "{v}");
        }
    }
}
