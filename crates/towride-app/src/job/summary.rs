//! The run summary: everything `summary.json` holds, as a typed, serialisable struct
//! that sweeps, benches and the command line read by field.

use std::collections::BTreeMap;

use serde::Serialize;

use super::{Job, StartState};
use crate::scene::channels;
use crate::signal::acquisition::AcqFilter;
use crate::vehicle::Design;
use towride_mbs::model::desc::Accelerations;
use towride_mbs::model::energy::{select_by_energy, strain_shares, BodyEnergy};
use towride_mbs::model::ic::AssemblyReport;
use towride_mbs::model::run::Samples;
use towride_mbs::model::start::StartReport;
use towride_mbs::model::statics::StaticsReport;
use towride_mbs::model::System;
use towride_solver::{MatrixRebuilds, Stats};

/// Version of the summary's layout; raised when a field changes meaning or goes away.
/// 2: the signed `peak`/`t_peak` of each channel and `hitch_force.peak_n` are gone
/// (`abs_peak` beside `max` and `min`); band-limited twins of the sensor, force and
/// deflection channels, with `signal`, `twin` and the top-level `acquisition`.
pub const SCHEMA_VERSION: u32 = 2;

/// The comfort block's point in words: where it is and how it is weighted.
const FLOOR_PLACE: &str = "car floor under the driver's seat, weighted as at the seat surface (Wd x, y; Wk z; k = 1), no seat transmissibility";

/// The seat block's point in words.
const SEAT_PLACE: &str = "z through the body file's [seat] model (cushion and seated occupant), x and y the floor's (no horizontal seat model), weighted Wd x, y; Wk z; k = 1";

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// The end time was reached.
    Completed,
    /// The solver stopped early; the samples up to `failed_at_s` are kept.
    Failed,
    /// Stopped on request (Ctrl-C); the samples up to `interrupted_at_s` are kept.
    Interrupted,
}

/// Solver effort, as the integrator counted it.
#[derive(Clone, Debug, Serialize)]
pub struct SolverSummary {
    /// Integration method: "bdf", "bdf_fixed_coefficient" or "radau5".
    pub method: &'static str,
    /// Relative tolerance of the run.
    pub rtol: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected step attempts.
    pub rejected_steps: usize,
    /// Residual evaluations.
    pub residual_evals: usize,
    /// Iteration-matrix evaluations.
    pub jacobian_evals: usize,
    /// Iteration matrices rebuilt for a new step size without an evaluation.
    pub matrix_recombinations: usize,
    /// LU factorisations.
    pub lu_factorizations: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Why the iteration matrix was rebuilt.
    pub matrix_rebuilds: MatrixRebuilds,
    /// The unknowns whose error estimate limited the most steps.
    pub step_limiters: Vec<StepLimiter>,
    /// Accepted steps per order 1..=5.
    pub order_counts: [usize; 5],
    /// Order reductions dictated by BDF stability limit detection.
    pub stability_order_reductions: usize,
}

/// An unknown that limited the step, and how often.
#[derive(Clone, Debug, Serialize)]
pub struct StepLimiter {
    /// The unknown's name.
    pub unknown: String,
    /// Accepted steps it limited.
    pub steps: usize,
}

/// The sizes of the assembled equations.
#[derive(Clone, Debug, Serialize)]
pub struct Unknowns {
    /// Position unknowns (centres, quaternions, modal coordinates).
    pub positions: usize,
    /// Velocity unknowns.
    pub velocities: usize,
    /// Constraint multipliers (kept rows).
    pub multipliers: usize,
    /// States of the extension elements (tyres, controllers).
    pub extension_states: usize,
}

/// A signal's extremes and the times they occur. No signed "peak": which side the
/// larger magnitude is on shows in `max` and `min`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Extremes {
    /// Largest value.
    pub max: f64,
    /// Time of the largest value [s].
    pub t_max: f64,
    /// Smallest value.
    pub min: f64,
    /// Time of the smallest value [s].
    pub t_min: f64,
    /// The larger magnitude, max(|max|, |min|) (NaN without samples).
    pub abs_peak: f64,
    /// Time of `abs_peak` [s] (on a tie, the earlier of the two).
    pub t_abs_peak: f64,
}

impl Extremes {
    /// The extremes of `y` sampled at times `t` (the first occurrence of each; NaN
    /// samples are passed over).
    pub fn of(t: &[f64], y: impl IntoIterator<Item = f64>) -> Extremes {
        let (mut max, mut t_max, mut min, mut t_min) = (f64::NEG_INFINITY, 0.0, f64::INFINITY, 0.0);
        for (t, v) in t.iter().zip(y) {
            if v < min {
                (min, t_min) = (v, *t);
            }
            if v > max {
                (max, t_max) = (v, *t);
            }
        }
        let (abs_peak, t_abs_peak) = if max < min {
            (f64::NAN, 0.0)
        } else if max.abs() > min.abs() || (max.abs() == min.abs() && t_max <= t_min) {
            (max.abs(), t_max)
        } else {
            (min.abs(), t_min)
        };
        Extremes {
            max,
            t_max,
            min,
            t_min,
            abs_peak,
            t_abs_peak,
        }
    }
}

/// Whether a channel is as the model computed it or through the acquisition chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Signal {
    /// As computed.
    Raw,
    /// Through the scene's acquisition low-pass ([`RunSummary::acquisition`]).
    BandLimited,
}

/// One channel's extremes and the times they occur.
#[derive(Clone, Debug, Serialize)]
pub struct ChannelSummary {
    /// Unit of the values.
    pub unit: String,
    /// Raw, or band-limited by the acquisition chain.
    pub signal: Signal,
    /// The other channel of a raw/band-limited pair: a raw channel's band-limited twin
    /// (`acc_hitch_z_lp100`), a band-limited channel's raw one (`acc_hitch_z`).
    pub twin: Option<String>,
    /// The one of a pair the console lists first and the report draws (its twin beside
    /// it, hidden in the chart's legend): the band-limited channel of an accelerometer,
    /// as the instrument saw it; the raw channel of a force or deflection. True for a
    /// channel without a twin.
    pub shown: bool,
    /// Max, min and |peak| with their times.
    #[serde(flatten)]
    pub extremes: Extremes,
}

/// The acquisition chain the band-limited channels went through.
#[derive(Clone, Debug, Serialize)]
pub struct Acquisition {
    /// Filter kind: "butterworth" (low-pass).
    pub filter: &'static str,
    /// Filter order.
    pub order: usize,
    /// -3 dB cut-off [Hz].
    pub cutoff_hz: f64,
    /// Run forward in time only, as the analog filter (its phase lag kept).
    pub causal: bool,
    /// The uniform grid the channels were filtered on [Hz]: the smallest multiple of
    /// the sample rate at or above 40 times the cutoff, cubic between samples
    /// ([`crate::signal::acquisition::band_limit`]).
    pub grid_rate_hz: f64,
    /// Suffix of a band-limited channel's name (`_lp100`).
    pub suffix: String,
    /// The filter in words.
    pub description: String,
    /// What is shown first, in the console and the report.
    pub shown: String,
}

impl Acquisition {
    /// The record of `f` for a run sampled at `rate` Hz.
    pub fn of(f: &AcqFilter, rate: f64) -> Acquisition {
        let m = (f.grid_rate(rate) / rate).ceil().max(1.0);
        let suffix = f.suffix();
        Acquisition {
            filter: "butterworth",
            order: f.order,
            cutoff_hz: f.cutoff_hz,
            causal: true,
            grid_rate_hz: m * rate,
            description: f.describe(),
            shown: format!(
                "accelerometers (acc_*, trailer_ax) band-limited (<channel>{suffix}) as the instrument saw them, raw beside; forces and deflections (hitch_f*, hitch_bracket_*, hitch_deflection_*) raw, band-limited (<channel>{suffix}) beside"
            ),
            suffix,
        }
    }
}

/// A wheel off the road.
#[derive(Clone, Debug, Serialize)]
pub struct LiftOff {
    /// Wheel short name (fl, fr, rl, rr, tl, tr).
    pub wheel: String,
    /// Start of the flight [s].
    pub start_s: f64,
    /// Landing [s]; `None` when still in the air at the end.
    pub end_s: Option<f64>,
    /// Time in the air [s].
    pub duration_s: f64,
}

/// A modal body's strain-energy shares over the run.
#[derive(Clone, Debug, Serialize)]
pub struct ModalEnergy {
    /// Per mode, over the run.
    #[serde(flatten)]
    pub shares: BodyEnergy,
    /// The modes a 1 % share threshold keeps (the thesis's commercial-tool method).
    pub kept_at_1_percent: Vec<usize>,
}

/// What a vehicle run adds.
#[derive(Clone, Debug, Serialize)]
pub struct SceneInfo {
    /// Set speed [m/s].
    pub speed_m_s: f64,
    /// The road file.
    pub road: String,
    /// Trailer load case.
    pub load_case: Option<String>,
    /// Hitch crossbeam variant.
    pub hitch_variant: Option<u32>,
    /// Design statics of the vehicle.
    pub design: Design,
    /// Values a compact (`simple`) vehicle file left to its defaults file or derived from
    /// its numbers (empty for an assembly file).
    pub assumed: Vec<crate::vehicle::simple::Assumed>,
    /// What the run did not compute, and why.
    pub skipped: Skipped,
    /// The channels the scene's `[[output]]` tables asked for, drawn in
    /// `plots_outputs.png`.
    pub output_channels: Vec<String>,
}

/// Work the run left out, and why (a scene skips what it does not need).
#[derive(Clone, Debug, Serialize)]
pub struct Skipped {
    /// Tyre-road queries.
    pub tyre_road_queries: u64,
    /// Queries answered by the memo of the last query.
    pub answered_from_memo: u64,
    /// Queries answered on flat road without an enveloping search.
    pub answered_flat_without_search: u64,
    /// Tandem-cam enveloping searches done.
    pub enveloping_searches: u64,
    /// Why.
    pub why: &'static str,
    /// Per modal body: the modes kept and why the others are not integrated.
    pub modal_bodies: Vec<ModesKept>,
    /// Whether the per-sample acceleration solve was skipped.
    pub acceleration_solves: SkippedSolves,
    /// Iteration matrices built without a Jacobian evaluation.
    pub jacobian_evaluations: SkippedJacobians,
}

/// A modal body's kept modes.
#[derive(Clone, Debug, Serialize)]
pub struct ModesKept {
    /// The body.
    pub body: String,
    /// Modes integrated.
    pub modes_kept: usize,
    /// Why.
    pub why: &'static str,
}

/// The per-sample acceleration solve.
#[derive(Clone, Debug, Serialize)]
pub struct SkippedSolves {
    /// True when sampled accelerations come from the interpolant.
    pub skipped: bool,
    /// Why.
    pub why: &'static str,
}

/// Jacobian evaluations saved by recombination.
#[derive(Clone, Debug, Serialize)]
pub struct SkippedJacobians {
    /// Evaluations done.
    pub evaluated: usize,
    /// Matrices rebuilt from kept parts.
    pub matrices_recombined_without_evaluation: usize,
    /// Why.
    pub why: &'static str,
}

/// Everything `summary.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// Layout version ([`SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// "mechanism" or "scene".
    pub kind: &'static str,
    /// The model's or the scene's name.
    pub name: String,
    /// The input file.
    pub file: String,
    /// How the run ended.
    pub status: RunStatus,
    /// The solver's message when it stopped early.
    pub error: Option<String>,
    /// Time reached when it stopped early [s].
    pub failed_at_s: Option<f64>,
    /// Time of the last sample kept when the run was interrupted [s].
    pub interrupted_at_s: Option<f64>,
    /// End time asked for [s].
    pub t_end_s: f64,
    /// Last sample time [s].
    pub t_reached_s: f64,
    /// Output sample rate [Hz].
    pub sample_rate_hz: f64,
    /// Output samples written.
    pub samples: usize,
    /// Wall time of the integration, initial state included [s].
    pub wall_s: f64,
    /// Wall time of the start policy (statics, start at speed) [s].
    pub start_wall_s: f64,
    /// Solver effort.
    #[serde(flatten)]
    pub solver: SolverSummary,
    /// Number of unknowns.
    pub equations: usize,
    /// The unknowns by kind.
    pub unknowns: Unknowns,
    /// Kept constraint rows.
    pub constraint_rows: usize,
    /// Constraint rows dropped as redundant.
    pub redundant_rows: usize,
    /// Warnings of the model checks.
    pub warnings: Vec<String>,
    /// The kinematic assembly of the initial state.
    pub assembly: AssemblyReport,
    /// The equilibrium search of a statics start.
    pub statics: Option<StaticsReport>,
    /// The start at speed of a scene.
    pub start: Option<StartReport>,
    /// Vehicle figures of a scene run.
    pub scene: Option<SceneInfo>,
    /// Wheels off the road.
    pub lift_off: Vec<LiftOff>,
    /// Strain-energy shares of the modal bodies.
    pub modal_energy: Vec<ModalEnergy>,
    /// The hitch's fore-aft force (`hitch_fx`, raw): max, min, |peak|, RMS, dominant
    /// frequency and the damping of its ringing ([`super::ringing`]); `None` without a
    /// hitch.
    pub hitch_force: Option<super::ringing::Ringing>,
    /// The acquisition chain of the band-limited channels (`None`: raw channels only).
    pub acquisition: Option<Acquisition>,
    /// Rainflow cycles and damage-equivalent loads (m = 3, N_ref = 2e6) of the hitch
    /// ball forces, the brackets' load components and the crossbeam stress points'
    /// equivalent stresses present ([`durability`]); empty without a hitch.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub durability: Vec<crate::durability::ChannelDurability>,
    /// Each crossbeam stress point with a FAT class checked over this passage (IIW,
    /// signed fibre stresses; docs/durability.md "IIW check").
    pub fat_check: Vec<crate::durability::FatCheck>,
    /// The ball forces beside the coupling's UN R55 D-value and test force, when the
    /// hitch file rates the coupling (docs/durability.md).
    pub coupling: Option<crate::durability::coupling::CouplingCheck>,
    /// Ride comfort (ISO 2631-1) at the car floor under the driver's seat, from the raw
    /// channels of the sensor [`crate::comfort::FLOOR_SENSOR`]; absent without them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comfort: Option<crate::comfort::PointComfort>,
    /// Ride comfort at the seat surface over that floor point, when the body file gives
    /// a seat (`[seat]`): the floor's z through the seat model (docs/comfort.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comfort_seat: Option<crate::comfort::SeatComfort>,
    /// Per channel, by name (raw and band-limited): unit, which it is, max, min and
    /// |peak| with their times; written in natural order (`hitch_eta_2` before
    /// `hitch_eta_10`).
    #[serde(serialize_with = "crate::report::display::serialize_natural")]
    pub channels: BTreeMap<String, ChannelSummary>,
    /// The convergence verdict against a companion run at a tighter tolerance (`run
    /// --check`); `None` when not asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub convergence: Option<super::convergence::Verdict>,
    /// What produced the run: version, commit, command line, overrides in effect.
    pub produced_by: super::ProducedBy,
    /// The CSV written, once written.
    pub outputs_csv: Option<String>,
    /// The MDF4 file written (`run --format mf4`), once written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub outputs_mf4: Option<String>,
    /// The plot page written (or why not), once written.
    pub plots: Option<String>,
    /// The page of the scene's `[[output]]` channels (or why not), once written; `None`
    /// when the scene asks for none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plots_outputs: Option<String>,
    /// The HTML report written (or why not), once written.
    pub report: Option<String>,
    /// Wall time of writing the HTML report [s] (spectra included).
    pub report_wall_s: Option<f64>,
}

impl RunSummary {
    /// The summary of `samples`, a run of `job` from `start`.
    pub fn of(job: &Job, samples: &Samples, start: StartState, start_wall_s: f64) -> RunSummary {
        let sys = &job.system;
        let st = &samples.stats;
        RunSummary {
            schema_version: SCHEMA_VERSION,
            kind: if job.scene.is_some() {
                "scene"
            } else {
                "mechanism"
            },
            name: job.name.clone(),
            file: job.file.display().to_string(),
            status: if samples.error.is_some() {
                RunStatus::Failed
            } else if samples.interrupted.is_some() {
                RunStatus::Interrupted
            } else {
                RunStatus::Completed
            },
            error: samples.error.as_ref().map(|e| e.0.clone()),
            failed_at_s: samples.error.as_ref().map(|e| e.1),
            interrupted_at_s: samples.interrupted,
            t_end_s: job.settings.t_end,
            t_reached_s: samples.times.last().copied().unwrap_or(0.0),
            sample_rate_hz: job.settings.sample_rate,
            samples: samples.times.len(),
            wall_s: samples.wall_s,
            start_wall_s,
            solver: solver_summary(st, &job.solver),
            equations: sys.size(),
            unknowns: Unknowns {
                positions: sys.nq,
                velocities: sys.nv,
                multipliers: sys.m,
                extension_states: sys.ne,
            },
            constraint_rows: sys.m,
            redundant_rows: sys.redundant.len(),
            warnings: job.warnings.clone(),
            assembly: samples.assembly.clone(),
            statics: start.statics,
            start: start.start,
            scene: job.scene.as_ref().map(|s| SceneInfo {
                speed_m_s: s.speed,
                road: s.road_file.display().to_string(),
                load_case: s
                    .vehicle
                    .design
                    .trailer
                    .as_ref()
                    .map(|t| t.load_case.clone()),
                hitch_variant: s.vehicle.handles.hitch.as_ref().map(|h| h.variant),
                design: s.vehicle.design.clone(),
                assumed: s.vehicle.assumed.clone(),
                skipped: skipped(sys, st),
                output_channels: s.requested.clone(),
            }),
            lift_off: lift_off(samples),
            modal_energy: strain_shares(sys, samples)
                .into_iter()
                .map(|b| ModalEnergy {
                    kept_at_1_percent: select_by_energy(&b, 0.01),
                    shares: b,
                })
                .collect(),
            hitch_force: samples
                .channel(channels::HITCH_FX)
                .and_then(|y| super::ringing::ringing(channels::HITCH_FX, &samples.times, &y)),
            acquisition: job
                .acquisition()
                .map(|f| Acquisition::of(&f, job.settings.sample_rate)),
            channels: channels(samples, job.acquisition().as_ref()),
            durability: durability(samples),
            fat_check: fat_checks(job, samples),
            coupling: coupling(job, samples),
            comfort: crate::comfort::evaluate::of_sensor(
                crate::comfort::FLOOR_SENSOR,
                FLOOR_PLACE,
                job.settings.sample_rate,
                |c| samples.channel(c),
            ),
            comfort_seat: job
                .scene
                .as_ref()
                .and_then(|s| s.vehicle.seat.as_ref())
                .and_then(|seat| {
                    crate::comfort::evaluate::of_seat(
                        crate::comfort::FLOOR_SENSOR,
                        SEAT_PLACE,
                        job.settings.sample_rate,
                        seat,
                        |c| samples.channel(c),
                    )
                }),
            produced_by: job.produced_by.clone(),
            outputs_csv: None,
            outputs_mf4: None,
            plots: None,
            plots_outputs: None,
            report: None,
            report_wall_s: None,
            convergence: None,
        }
    }

    /// The summary as pretty-printed JSON.
    pub fn to_json(&self) -> String {
        // Plain data (strings, numbers, maps): serialisation cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}

fn solver_summary(st: &Stats, o: &towride_solver::SolverOptions) -> SolverSummary {
    SolverSummary {
        method: match o.method {
            towride_solver::Method::Variable => "bdf",
            towride_solver::Method::FixedCoefficient => "bdf_fixed_coefficient",
            towride_solver::Method::Radau5 => "radau5",
        },
        rtol: o.rtol,
        steps: st.steps,
        rejected_steps: st.rejected_steps,
        residual_evals: st.residual_evals,
        jacobian_evals: st.jacobian_evals,
        matrix_recombinations: st.matrix_recombinations,
        lu_factorizations: st.lu_factorizations,
        newton_iterations: st.newton_iterations,
        matrix_rebuilds: st.matrix_rebuilds.clone(),
        step_limiters: st
            .step_limiters
            .iter()
            .map(|(u, n)| StepLimiter {
                unknown: u.clone(),
                steps: *n,
            })
            .collect(),
        order_counts: st.order_counts,
        stability_order_reductions: st.stability_order_reductions,
    }
}

/// Per channel: unit, raw or band-limited (and its twin), extremes and their times.
fn channels(s: &Samples, acquisition: Option<&AcqFilter>) -> BTreeMap<String, ChannelSummary> {
    let names: Vec<&str> = s.channels.iter().map(|c| c.name.as_str()).collect();
    let pairs: Vec<(String, String)> = acquisition.map_or_else(Vec::new, |f| {
        super::band::twins(names.iter().copied(), f)
            .into_iter()
            .filter(|(_, twin)| names.contains(&twin.as_str()))
            .map(|(k, twin)| (names[k].to_string(), twin))
            .collect()
    });
    let mut m = BTreeMap::new();
    for (c, ch) in s.channels.iter().enumerate() {
        let sensor = |raw: &str| channels::band(raw) == Some(channels::Band::Sensor);
        let (signal, twin, shown) = match pairs.iter().find(|(r, b)| *r == ch.name || *b == ch.name)
        {
            Some((r, b)) if *r == ch.name => (Signal::Raw, Some(b.clone()), !sensor(r)),
            Some((r, _)) => (Signal::BandLimited, Some(r.clone()), sensor(r)),
            None => (Signal::Raw, None, true),
        };
        m.insert(
            ch.name.clone(),
            ChannelSummary {
                unit: ch.unit.to_string(),
                signal,
                twin,
                shown,
                extremes: Extremes::of(&s.times, s.rows.iter().map(|r| r[c])),
            },
        );
    }
    m
}

/// Intervals without contact per wheel, from the `tyre_<w>_contact` channels.
pub fn lift_off(s: &Samples) -> Vec<LiftOff> {
    let mut out = Vec::new();
    for (c, ch) in s.channels.iter().enumerate() {
        let Some(w) = channels::tyre_wheel(&ch.name, channels::TYRE_CONTACT) else {
            continue;
        };
        let mut start: Option<f64> = None;
        for (t, row) in s.times.iter().zip(&s.rows) {
            match (row[c] < 0.5, start) {
                (true, None) => start = Some(*t),
                (false, Some(t0)) => {
                    out.push(LiftOff {
                        wheel: w.to_string(),
                        start_s: t0,
                        end_s: Some(*t),
                        duration_s: t - t0,
                    });
                    start = None;
                }
                _ => {}
            }
        }
        if let (Some(t0), Some(t1)) = (start, s.times.last()) {
            out.push(LiftOff {
                wheel: w.to_string(),
                start_s: t0,
                end_s: None,
                duration_s: t1 - t0,
            });
        }
    }
    out
}

/// What the run did not compute, and why.
fn skipped(sys: &System, st: &Stats) -> Skipped {
    let mut q = [0u64; 3];
    for t in &sys.model.tyres {
        if let Some(c) = t.tyre.query_counts() {
            for k in 0..3 {
                q[k] += c[k];
            }
        }
    }
    let solved = sys.model.accelerations == Accelerations::Solve;
    Skipped {
        tyre_road_queries: q[0],
        answered_from_memo: q[1],
        answered_flat_without_search: q[2],
        enveloping_searches: q[0] - q[1] - q[2],
        why: "no tandem-cam search where the road under a tyre is flat; the last query is memoised",
        modal_bodies: sys
            .model
            .bodies
            .iter()
            .filter_map(|b| b.modal.as_ref().map(|m| (b, m)))
            .map(|(b, m)| ModesKept {
                body: b.name.clone(),
                modes_kept: m.data.modes.len(),
                why: "modes outside the body file's selection rule are not integrated",
            })
            .collect(),
        acceleration_solves: SkippedSolves {
            skipped: !solved,
            why: if solved {
                "[run] accelerations = \"solve\": solved at every sample"
            } else {
                "sampled accelerations and hitch forces from the integrator's interpolant; the per-sample acceleration-level solve took about 30 % of a default run (docs/performance.md)"
            },
        },
        jacobian_evaluations: SkippedJacobians {
            evaluated: st.jacobian_evals,
            matrices_recombined_without_evaluation: st.matrix_recombinations,
            why: "a step change rebuilds the iteration matrix from the kept dF/dy and dF/dy' (jacobian_recombine); one evaluation costs about 25 Newton iterations",
        },
    }
}

/// The IIW check of each stress point with a FAT class: the rainflow of its four
/// fibres' signed normal stress (`hitch_stress_<point>_sx_f<k>`).
fn fat_checks(job: &Job, samples: &Samples) -> Vec<crate::durability::FatCheck> {
    let Some(s) = job.scene.as_ref() else {
        return Vec::new();
    };
    let Some(hh) = s.vehicle.handles.hitch.as_ref() else {
        return Vec::new();
    };
    let Some(md) = s.vehicle.model.bodies[hh.body].modal.as_ref() else {
        return Vec::new();
    };
    md.data
        .stress
        .points
        .iter()
        .filter_map(|p| {
            let fibres: Option<Vec<Vec<f64>>> = (1..=4)
                .map(|k| samples.channel(&format!("hitch_stress_{}_sx_f{k}", p.name)))
                .collect();
            crate::durability::fat_check(&p.name, p.fat_pa?, &fibres?)
        })
        .collect()
}

/// The ball forces against the hitch file's R55 rating.
fn coupling(job: &Job, samples: &Samples) -> Option<crate::durability::coupling::CouplingCheck> {
    let rating = job.scene.as_ref()?.vehicle.handles.hitch.as_ref()?.rating?;
    crate::durability::coupling::check(
        rating,
        &samples.channel(channels::HITCH_FX)?,
        &samples.channel(channels::HITCH_FY)?,
        &samples.channel(channels::HITCH_FZ)?,
    )
}

/// The durability block (`crate::durability`, docs/durability.md "In every run"): each
/// hitch ball force component; each bracket load component on its own (a multiaxial
/// load is counted per channel: the length of the force vector would hide a reversal
/// through zero, the largest range); each crossbeam stress point's equivalent stress
/// (Pa, with IIW's m = 3 of normal stress ranges).
fn durability(samples: &Samples) -> Vec<crate::durability::ChannelDurability> {
    samples
        .channels
        .iter()
        .filter(|c| {
            let n = c.name.as_str();
            [channels::HITCH_FX, channels::HITCH_FY, channels::HITCH_FZ].contains(&n)
                || (n.starts_with(channels::HITCH_BRACKET_PREFIX) && !channels::is_band_limited(n))
                || (n.starts_with("hitch_stress_") && n.ends_with("_eq"))
        })
        .filter_map(|c| {
            crate::durability::channel_block(&c.name, c.unit, &samples.channel(&c.name)?)
        })
        .collect()
}
