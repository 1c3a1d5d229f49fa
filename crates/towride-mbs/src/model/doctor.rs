//! The numerical doctor: the checks of the thesis's chapters 5 and 6, automated.
//! Redundant constraints, the Newton matrix's condition number at a typical step, mass
//! and inertia ratios, bushing frequencies against the masses they connect, and the
//! eigenvalue spread, each turned into plain advice.

use nalgebra::DMatrix;
use serde::Serialize;

use super::desc::{Force, MarkerHandle};
use super::linear::{linearise, Linearisation};
use super::system::System;
use towride_solver::problem::JacobianSink;
use towride_solver::SolverOptions;

/// A constraint row found redundant at assembly.
#[derive(Clone, Debug, Serialize)]
pub struct RedundantRow {
    /// The row, named by its joint or motion and what it locks.
    pub row: String,
    /// The kept rows it is a combination of.
    pub duplicates: Vec<String>,
    /// What was done about it.
    pub action: String,
}

/// The natural frequency of one stiff bushing direction against the bodies it connects.
#[derive(Clone, Debug, Serialize)]
pub struct BushingFrequency {
    /// Bushing name.
    pub bushing: String,
    /// Direction in the bushing's J axes: "x", "y", "z", "rx", "ry" or "rz".
    pub axis: String,
    /// Stiffness in that direction [N/m or N m/rad, [`Self::units`]]; in the JSON
    /// `stiffness_n_per_m` or `stiffness_n_m_per_rad`.
    #[serde(skip)]
    pub stiffness: f64,
    /// Effective mass or inertia of the two bodies in series [kg or kg m^2] (one body's
    /// alone when the other is ground); in the JSON `effective_mass_kg` or
    /// `effective_inertia_kg_m2`.
    #[serde(skip)]
    pub effective_inertia: f64,
    // The JSON's unit-named copies of the two above: the unit depends on the axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    stiffness_n_per_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    stiffness_n_m_per_rad: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    effective_mass_kg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    effective_inertia_kg_m2: Option<f64>,
    /// sqrt(stiffness / effective_inertia) / 2 pi [Hz].
    pub frequency_hz: f64,
}

impl BushingFrequency {
    /// A bushing direction's frequency: `axis` "x", "y", "z" translational, "rx", "ry",
    /// "rz" rotational.
    pub fn new(bushing: &str, axis: &str, stiffness: f64, effective_inertia: f64) -> Self {
        let rotational = axis.starts_with('r');
        let lin = |v: f64| (!rotational).then_some(v);
        let rot = |v: f64| rotational.then_some(v);
        BushingFrequency {
            bushing: bushing.into(),
            axis: axis.into(),
            stiffness,
            effective_inertia,
            stiffness_n_per_m: lin(stiffness),
            stiffness_n_m_per_rad: rot(stiffness),
            effective_mass_kg: lin(effective_inertia),
            effective_inertia_kg_m2: rot(effective_inertia),
            frequency_hz: (stiffness / effective_inertia).sqrt() / (2.0 * std::f64::consts::PI),
        }
    }

    /// The units of the stiffness and the effective inertia: ("N/m", "kg") along an
    /// axis, ("N m/rad", "kg m^2") about one.
    pub fn units(&self) -> (&'static str, &'static str) {
        if self.axis.starts_with('r') {
            ("N m/rad", "kg m^2")
        } else {
            ("N/m", "kg")
        }
    }
}

/// The doctor's findings on a model, with advice in plain words.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Model name.
    pub model: String,
    /// Number of bodies.
    pub bodies: usize,
    /// Number of unknowns (equations) of the DAE.
    pub equations: usize,
    /// Number of kept constraint rows.
    pub constraint_rows: usize,
    /// Rows eliminated as redundant.
    pub redundant: Vec<RedundantRow>,
    /// Step used for the condition estimate [s].
    pub step_s: f64,
    /// 2-norm condition number of the Newton matrix dF/dy + dF/dy' / h as the solver
    /// factors it (scaled as `SolverOptions::scale_newton_matrix` says).
    pub newton_condition: Option<f64>,
    /// Largest over smallest body mass.
    pub mass_ratio: f64,
    /// Largest over smallest principal moment of inertia over all bodies.
    pub inertia_ratio: f64,
    /// Stiff bushing directions with their frequencies.
    pub bushings: Vec<BushingFrequency>,
    /// Where the linearisation was taken: "equilibrium" or "initial state".
    pub linearised_at: String,
    /// Eigen-analysis at `linearised_at`, when the linearisation succeeded.
    pub linearisation: Option<Linearisation>,
    /// What to change, one finding per entry.
    pub advice: Vec<String>,
}

/// Runs every check on an assembled model.
pub fn examine(sys: &System, opts: &SolverOptions, step: f64) -> Report {
    let mut advice = Vec::new();
    let redundant: Vec<RedundantRow> = sys
        .redundant
        .iter()
        .map(|r| {
            let e = &sys.cons[r.elem];
            let dups: Vec<String> = r
                .depends_on
                .iter()
                .map(|&(de, dr, _)| sys.row_name(&sys.cons[de], dr))
                .collect();
            RedundantRow {
                row: sys.row_name(e, r.row),
                duplicates: dups,
                action:
                    "eliminated before the run; its reaction is carried by the rows it duplicates"
                        .into(),
            }
        })
        .collect();
    let mut over: Vec<String> = Vec::new();
    for r in &sys.redundant {
        let name = sys.con_name(&sys.cons[r.elem]);
        if !over.contains(&name) {
            over.push(name);
        }
    }
    for name in &over {
        let rows: Vec<&RedundantRow> = redundant
            .iter()
            .filter(|r| r.row.starts_with(name.as_str()))
            .collect();
        let others: std::collections::BTreeSet<String> = rows
            .iter()
            .flat_map(|r| {
                r.duplicates
                    .iter()
                    .map(|d| d.split(':').next().unwrap_or("").to_string())
            })
            .filter(|d| d != name)
            .collect();
        if others.is_empty() {
            advice.push(format!("{name} is degenerate at the initial position (a constraint row vanishes there): check its axes"));
            continue;
        }
        advice.push(format!(
            "{name} over-constrains the model ({} rows repeat {}): replace it (or one of those) by a bushing, or use a joint that locks fewer directions",
            rows.len(),
            others.into_iter().collect::<Vec<_>>().join(", ")
        ));
    }
    // State: equilibrium when one exists, else the assembled initial state.
    let (state, at) = match super::statics::equilibrium(sys, 0.0, opts) {
        Ok(s) => (Some(s.y), "equilibrium"),
        Err(_) => {
            let (mut q, mut v) = sys.initial_q_v();
            (
                {
                    let x = sys.ext_initial(&q, &v, 0.0);
                    super::ic::initial_state(sys, 0.0, &mut q, &mut v, &x)
                }
                .ok()
                .map(|s| s.0),
                "initial state",
            )
        }
    };
    let newton_condition = state.as_ref().and_then(|y| condition(sys, opts, y, step));
    if let Some(k) = newton_condition {
        if k > 1e12 {
            advice.push(format!(
                "the Newton matrix at h = {step:.0e} s has condition number {k:.2e}: expect lost digits and Newton failures; look for extreme mass ratios, very stiff bushings or fixed joints on heavy bodies"
            ));
        }
    }
    let masses: Vec<f64> = sys.model.bodies.iter().map(|b| b.mass).collect();
    let mass_ratio = ratio(&masses);
    let inertias: Vec<f64> = sys
        .model
        .bodies
        .iter()
        .flat_map(|b| {
            nalgebra::Matrix3::from_fn(|r, c| b.inertia[r][c])
                .symmetric_eigenvalues()
                .iter()
                .copied()
                .collect::<Vec<_>>()
        })
        .collect();
    let inertia_ratio = ratio(&inertias);
    if mass_ratio > 1e6 {
        advice.push(format!("mass ratio {mass_ratio:.1e}: give reference parts a sane mass or none (a heavy road slab ruined a model in the thesis, 5.5.1)"));
    }
    let bushings = bushing_frequencies(sys);
    let lin = state.as_ref().and_then(|y| linearise(sys, 0.0, y).ok());
    if let Some(l) = &lin {
        if let Some(s) = l.stiffness_ratio {
            if s > 200.0 {
                advice.push(format!("stiffness ratio S = {s:.2e} (> 200: stiff); use the implicit BDF solver, and drop what sets the top of the spectrum if it is not needed"));
            }
        }
        if let Some(top) = l.modes.last() {
            let who = top
                .elements
                .first()
                .map(|e| {
                    format!(
                        "; {} holds {:.0} % of its strain energy",
                        e.name,
                        100.0 * e.share
                    )
                })
                .unwrap_or_default();
            let body = top
                .bodies
                .first()
                .map(|b| format!(", moving mostly {}", b.name))
                .unwrap_or_default();
            advice.push(format!(
                "mode {} at {:.4} Hz sets the stiffness{body}{who}",
                top.index, top.undamped_hz
            ));
        }
    }
    for bf in &bushings {
        if bf.frequency_hz > 0.5 / step {
            advice.push(format!(
                "bushing {} ({}) rings at {:.0} Hz, above the {:.0} Hz a {step:.0e} s step resolves: soften it or accept that the integrator only damps it",
                bf.bushing, bf.axis, bf.frequency_hz, 0.5 / step
            ));
        }
    }
    Report {
        model: sys.model.name.clone(),
        bodies: sys.nb(),
        equations: sys.size(),
        constraint_rows: sys.m,
        redundant,
        step_s: step,
        newton_condition,
        mass_ratio,
        inertia_ratio,
        bushings,
        linearised_at: at.into(),
        linearisation: lin,
        advice,
    }
}

fn ratio(v: &[f64]) -> f64 {
    let hi = v.iter().fold(0.0f64, |a, b| a.max(*b));
    let lo = v.iter().fold(f64::INFINITY, |a, b| a.min(*b));
    if lo > 0.0 && lo.is_finite() {
        hi / lo
    } else {
        1.0
    }
}

/// Condition number of dF/dy + dF/dy' / h (BDF1 at step h) as the solver factors it,
/// by dense SVD: with `scale_newton_matrix`, the columns of index-k unknowns times
/// h^(k-1) and every row divided by its largest entry. Unscaled, a multibody model's
/// multiplier columns are 1e-9 of its stiffness entries and the SVD deflates them to 0
/// (an infinite condition number on the default scene, which runs cleanly).
fn condition(sys: &System, opts: &SolverOptions, y: &[f64], h: f64) -> Option<f64> {
    use towride_solver::problem::DaeProblem;
    let n = sys.size();
    if n > 3000 {
        return None;
    }
    let mut e = Vec::new();
    sys.jacobian_entries(0.0, y, 1.0 / h, &mut JacobianSink::new(&mut e), false);
    let mut a = DMatrix::<f64>::zeros(n, n);
    for (r, c, v) in e {
        a[(r, c)] += v;
    }
    if opts.scale_newton_matrix {
        let hs = h.min(1.0);
        for (c, k) in sys.var_kinds().iter().enumerate() {
            let f = hs.powi(k.level() - 1);
            a.column_mut(c).scale_mut(1.0 / f);
        }
        for r in 0..n {
            let m = a.row(r).amax();
            if m > 0.0 {
                a.row_mut(r).scale_mut(1.0 / m);
            }
        }
    }
    let s = a.singular_values();
    let hi = s.iter().fold(0.0f64, |a, b| a.max(*b));
    let lo = s.iter().fold(f64::INFINITY, |a, b| a.min(*b));
    Some(if lo > 0.0 { hi / lo } else { f64::INFINITY })
}

/// Frequency of every stiff bushing direction against the two-body effective inertia.
fn bushing_frequencies(sys: &System) -> Vec<BushingFrequency> {
    let m = &sys.model;
    let mut out = Vec::new();
    let axes = ["x", "y", "z", "rx", "ry", "rz"];
    let (q, _) = sys.initial_q_v();
    for f in &m.forces {
        let Force::Bushing(b) = f else { continue };
        let fj = sys.marker_frame(&q, b.j);
        for a in 0..6 {
            let k = b.stiffness[a].stiffness();
            if k <= 0.0 {
                continue;
            }
            let dir = [fj.axes[0][a % 3], fj.axes[1][a % 3], fj.axes[2][a % 3]];
            let inertia_of = |mk: MarkerHandle| -> f64 {
                let Some(bi) = m.markers[mk].body else {
                    return f64::INFINITY;
                };
                let body = &m.bodies[bi];
                if a < 3 {
                    return body.mass;
                }
                // inertia about the axis through the bushing point (parallel axis)
                let rot = super::math::rot(&body.orientation);
                let jw = super::math::mm(
                    &super::math::mm(&rot, &body.inertia),
                    &super::math::transpose(&rot),
                );
                let jd = super::math::mv(&jw, &dir);
                let arm = super::math::sub(&sys.marker_frame(&q, mk).origin, &body.position);
                let along = super::math::dot(&arm, &dir);
                super::math::dot(&dir, &jd)
                    + body.mass * (super::math::dot(&arm, &arm) - along * along)
            };
            let (ia, ib) = (inertia_of(b.i), inertia_of(b.j));
            let eff = if ia.is_infinite() {
                ib
            } else if ib.is_infinite() {
                ia
            } else {
                ia * ib / (ia + ib)
            };
            out.push(BushingFrequency::new(&b.name, axes[a], k, eff));
        }
    }
    out
}
