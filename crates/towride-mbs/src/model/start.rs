//! Starting a vehicle "in static equilibrium at speed".
//!
//! A rolling vehicle has no static equilibrium in the strict sense (wheels turn, tyres
//! slip a little, the driveline pushes against rolling resistance), so the start is
//! built in three steps, each checkable:
//!
//! 1. static equilibrium at rest on a flat road at the start height (speed controllers
//!    off): ride heights, wheel loads, hitch preload;
//! 2. every body given the set speed along the world x axis, every wheel its free-rolling
//!    spin, the tyres their steady states for that motion, velocities projected onto the
//!    constraints;
//! 3. a settling run of `settle_s` seconds on the same flat road (time running from
//!    -settle_s to 0) with the speed controllers on, so the driveline torque, the tyre
//!    slip and the pitch they cause reach their steady values; then every body is shifted
//!    along x so the first body is back at its design position (exact on a flat road:
//!    nothing depends on x there).
//!
//! The state at t = 0 is then consistent for the model on its real road as long as the
//! road is flat under the tyres at the start, which is checked.

use super::desc::Model;
use super::ic::initial_state;
use super::statics::{equilibrium, StaticsReport};
use super::system::{ExtKind, System};
use super::ModelError;
use crate::road::Road;
use towride_solver::{solve_to, SolverOptions};

/// What the start procedure did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct StartReport {
    /// The static equilibrium found first.
    pub statics: StaticsReport,
    /// Length of the settling run before t = 0 [s].
    pub settle_s: f64,
    /// Solver steps of the settling run.
    pub settle_steps: usize,
    /// Wall-clock time of the settling run [s].
    pub settle_wall_s: f64,
    /// Speed of the controlled marker at the end of the settling run [m/s] (first
    /// controller), and the largest body acceleration left [m/s^2].
    pub settled_speed_m_s: Option<f64>,
    /// Largest body acceleration left at the end of the settling run [m/s^2].
    pub residual_acceleration_m_s2: f64,
}

/// The consistent state (y, y') at t = 0 of `model` rolling at `speed` [m/s] along x.
pub fn at_speed(
    model: &Model,
    speed: f64,
    settle_s: f64,
    opts: &SolverOptions,
) -> Result<(Vec<f64>, Vec<f64>, StartReport), ModelError> {
    let road = model
        .road
        .as_ref()
        .ok_or_else(|| ModelError::Start("starting at speed needs a road".into()))?;
    let mut rep = StartReport {
        settle_s,
        ..Default::default()
    };
    // Flat road at the height under the wheels, which must be flat there.
    let sys0 = System::new(model.clone());
    let (q0, v0) = sys0.initial_q_v();
    let mut heights = Vec::new();
    for t in &model.tyres {
        let c = sys0.marker_frame(&q0, t.marker).origin;
        let reach = t.tyre.reach(c[0]);
        let h = road
            .flat_height(reach.0, reach.1, c[1] - 0.2, c[1] + 0.2)
            .ok_or_else(|| {
                ModelError::Start(format!(
                    "tyre '{}' does not start on flat road (x {:.3} m): move the obstacle ahead",
                    t.name, c[0]
                ))
            })?;
        heights.push(h);
    }
    let h = heights.first().copied().unwrap_or(0.0);
    if heights.iter().any(|x| (x - h).abs() > 1e-9) {
        return Err(ModelError::Start(
            "the tyres start at different road heights".into(),
        ));
    }
    let mut flat_model = model.clone();
    flat_model.road = Some(Road::flat(h));
    let flat = System::new(flat_model);
    let t0 = -settle_s;
    // 1. Statics at rest.
    let st = equilibrium(&flat, t0, opts)?;
    rep.statics = st.report.clone();
    let (_, ov, _, _) = flat.offsets();
    let mut q = st.y[..ov].to_vec();
    let _ = v0;
    // 2. Set speed and wheel spin.
    let mut v = vec![0.0; flat.nv];
    for b in 0..flat.nb() {
        v[flat.vo[b]] = speed;
    }
    for e in &flat.ext {
        let ExtKind::Tyre(k) = e.kind else { continue };
        let te = &flat.model.tyres[k];
        let b = flat
            .body_of(te.marker)
            .ok_or_else(|| ModelError::Start("tyre on ground".into()))?;
        let c = flat.marker_frame(&q, te.marker);
        let spin_axis = [c.axes[0][1], c.axes[1][1], c.axes[2][1]];
        let road = flat.model.road.as_ref().expect("flat road");
        let spin = crate::tyre::rig::free_rolling_spin(
            &te.tyre,
            road,
            c.origin[0],
            c.origin[2],
            speed,
            0.0,
        );
        let (_, p) = flat.pose(&q, b);
        let a = super::math::rot(&p);
        let wb = super::math::mtv(&a, &spin_axis.map(|s| s * spin));
        v[flat.vo[b] + 3..flat.vo[b] + 6].copy_from_slice(&wb);
    }
    let x = flat.ext_initial(&q, &v, 0.0);
    let (y0, yp0, _) = initial_state(&flat, t0, &mut q, &mut v, &x)?;
    if settle_s <= 0.0 {
        return Ok((y0, yp0, rep));
    }
    // 3. Settle with the BDF at order <= 2, whatever the run's method: the settle is
    // there to let transients die, and on flat road the steps grow to several ms, where
    // orders 3-5 are unstable for the lightly damped 20-60 Hz bushing modes (their
    // stability regions leave out the imaginary axis) and would hand the run a ringing
    // start. BDF2 is A-stable; against Radau IIA it settles further in less time
    // (default scene: residual acceleration 2.5e-5 against 1.5e-2 m/s^2, 0.016 against
    // 0.057 s).
    let settle_opts = SolverOptions {
        method: towride_solver::Method::Variable,
        max_order: opts.max_order.min(2),
        ..opts.clone()
    };
    let end = solve_to(&flat, t0, &y0, &yp0, 0.0, &settle_opts)
        .map_err(|e| ModelError::Start(format!("settling run at speed failed: {e}")))?;
    rep.settle_steps = end.stats.steps;
    rep.settle_wall_s = end.wall_s;
    let (mut y, yp) = (end.y, end.yp);
    let dx = model.bodies[0].position[0] - y[flat.qo[0]];
    for b in 0..flat.nb() {
        y[flat.qo[b]] += dx;
    }
    let vel = &y[ov..ov + flat.nv];
    rep.settled_speed_m_s =
        (!model.controls.is_empty()).then(|| flat.control_speed(0, &y[..ov], vel));
    rep.residual_acceleration_m_s2 = (0..flat.nb())
        .map(|b| {
            let w = ov + flat.vo[b];
            (yp[w].powi(2) + yp[w + 1].powi(2) + yp[w + 2].powi(2)).sqrt()
        })
        .fold(0.0, f64::max);
    Ok((y, yp, rep))
}
