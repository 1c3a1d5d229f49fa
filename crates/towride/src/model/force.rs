//! Force elements, generic over the scalar.
//!
//! Each element sees its two marker frames as [`Dual`]s with one direction, the time
//! derivative along the motion, so a deflection and its rate come from one expression
//! (the rate of a bushing's rotation vector is its exact time derivative, not the
//! relative angular velocity). The element returns the force on marker I's body applied
//! at I's origin plus a torque, world axes; the J body gets the opposite.

use super::desc::{Bushing, Force, Law, RotSpring, SpringDamper, Stop};
use super::dual::{Dual, Scalar};
use super::joint::MFrame;
use super::math::{col, cross, dot, mtv, mv, qmul, rotation_vector, scale, sub, V3};

/// A quantity and its time derivative.
pub type Rate<S> = Dual<S, 1>;

/// What an element puts on its bodies, plus its measures for outputs.
pub struct ElementLoad<S: Scalar> {
    /// Force on I's body at I's origin (world) and torque on I's body (world).
    pub force: V3<S>,
    pub torque: V3<S>,
    /// Force (or torque) components, deflections and their rates, element-specific.
    pub measures: Vec<(S, S, S)>,
}

/// Evaluates a law as a function of a [`Scalar`].
fn law<S: Scalar>(l: &Law, x: S) -> S {
    match l {
        Law::Linear(k) => x * *k,
        Law::Curve(s) => {
            let (f, df, d2f) = s.eval(x.re());
            x.chain(f, df, d2f)
        }
    }
}

/// Force of a one-sided stop for penetration `pen` with rate `pen_rate`.
fn stop_force<S: Scalar>(st: &Stop, pen: S, pen_rate: S) -> S {
    if pen.re() <= 0.0 {
        return S::cst(0.0);
    }
    // pen^e = exp(e ln pen) written through chain to stay generic.
    let p = pen.re();
    let e = st.exponent;
    let elastic = pen.chain(
        p.powf(e),
        e * p.powf(e - 1.0),
        e * (e - 1.0) * p.powf(e - 2.0),
    );
    let ramp = if st.damping_depth > 0.0 && p < st.damping_depth {
        let s = p / st.damping_depth;
        let h = st.damping_depth;
        pen.chain(
            s * s * (3.0 - 2.0 * s),
            6.0 * s * (1.0 - s) / h,
            (6.0 - 12.0 * s) / (h * h),
        )
    } else {
        S::cst(1.0)
    };
    elastic * st.stiffness + ramp * pen_rate * st.damping
}

/// Generic evaluation of a force element (not `Applied`, handled by the system).
pub fn element_load<S: Scalar>(
    f: &Force,
    i: &MFrame<Rate<S>>,
    j: &MFrame<Rate<S>>,
    qi: &[Rate<S>; 4],
    qj: &[Rate<S>; 4],
) -> ElementLoad<S> {
    match f {
        Force::Spring(s) => spring(s, i, j),
        Force::Bushing(b) => bushing(b, i, j, qi, qj),
        Force::Rot(r) => rot_spring(r, i, j),
        Force::Applied(_) => unreachable!("applied loads are evaluated by the system"),
    }
}

fn spring<S: Scalar>(s: &SpringDamper, i: &MFrame<Rate<S>>, j: &MFrame<Rate<S>>) -> ElementLoad<S> {
    let d = sub(&i.origin, &j.origin);
    let l = dot(&d, &d).sqrt();
    let x = l.v - s.free_length;
    let rate = l.d[0];
    let mut repulsive = S::cst(s.preload) - law(&s.spring, x) - law(&s.damper, rate);
    if let Some(st) = &s.bump_stop {
        repulsive = repulsive + stop_force(st, -x - st.clearance, -rate);
    }
    if let Some(st) = &s.rebound_stop {
        repulsive = repulsive - stop_force(st, x - st.clearance, rate);
    }
    let unit = [d[0].v / l.v, d[1].v / l.v, d[2].v / l.v];
    ElementLoad {
        force: scale(&unit, repulsive),
        torque: [S::cst(0.0); 3],
        measures: vec![(repulsive, x, rate)],
    }
}

fn bushing<S: Scalar>(
    b: &Bushing,
    i: &MFrame<Rate<S>>,
    j: &MFrame<Rate<S>>,
    qi: &[Rate<S>; 4],
    qj: &[Rate<S>; 4],
) -> ElementLoad<S> {
    let d = mtv(&j.axes, &sub(&i.origin, &j.origin));
    // Relative rotation of I in J: q_J^-1 q_I (the marker quaternions include the body's).
    let qrel = qmul(&[qj[0], -qj[1], -qj[2], -qj[3]], qi);
    let th = rotation_vector(&qrel);
    let defl = [d[0], d[1], d[2], th[0], th[1], th[2]];
    let mut loads = [S::cst(0.0); 6];
    let mut measures = Vec::with_capacity(6);
    for k in 0..6 {
        loads[k] = S::cst(b.preload[k])
            - law(&b.stiffness[k], defl[k].v)
            - law(&b.damping[k], defl[k].d[0]);
        measures.push((loads[k], defl[k].v, defl[k].d[0]));
    }
    let aj: [[S; 3]; 3] = j.axes.map(|r| r.map(|x| x.v));
    let force = mv(&aj, &[loads[0], loads[1], loads[2]]);
    let torque = mv(&aj, &[loads[3], loads[4], loads[5]]);
    ElementLoad {
        force,
        torque,
        measures,
    }
}

fn rot_spring<S: Scalar>(
    r: &RotSpring,
    i: &MFrame<Rate<S>>,
    j: &MFrame<Rate<S>>,
) -> ElementLoad<S> {
    let xi = col(&i.axes, 0);
    let angle = dot(&xi, &col(&j.axes, 1)).atan2(dot(&xi, &col(&j.axes, 0)));
    let x = angle.v - r.free_angle;
    let rate = angle.d[0];
    let t = S::cst(r.preload) - law(&r.spring, x) - law(&r.damper, rate);
    let z: V3<S> = col(&j.axes, 2).map(|c| c.v);
    ElementLoad {
        force: [S::cst(0.0); 3],
        torque: scale(&z, t),
        measures: vec![(t, x, rate)],
    }
}

/// Generalised force (force, body-frame torque) of a world force `f` at world point `p`
/// plus a world torque `t` on a body at `r` with rotation `a`.
pub fn generalised<S: Scalar>(
    r: &V3<S>,
    a: &[[S; 3]; 3],
    p: &V3<S>,
    f: &V3<S>,
    t: &V3<S>,
) -> [S; 6] {
    let arm = sub(p, r);
    let m = cross(&arm, f);
    let mw = [m[0] + t[0], m[1] + t[1], m[2] + t[2]];
    let mb = mtv(a, &mw);
    [f[0], f[1], f[2], mb[0], mb[1], mb[2]]
}
