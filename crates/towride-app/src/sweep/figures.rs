//! The figures a sweep records of each case: extremes of the hitch force and the
//! sensors, the crossbeam's deflection and energy, solver effort and, with `--check`,
//! the convergence verdict.

use crate::job::RunResult;
use crate::scene::channels;

/// Named figures of one case (extremes, energies), in a stable order.
pub type Figures = Vec<(String, f64)>;

/// The figures of a case's convergence verdict (`sweep --check`): 1 or 0, the largest
/// relative difference of any judged channel's max, min or RMS [%], and how many
/// channels failed.
pub const CONVERGED: &str = "converged [-]";
/// See [`CONVERGED`].
pub const CONVERGENCE_WORST: &str = "convergence worst difference [%]";
/// See [`CONVERGED`].
pub const UNCONVERGED: &str = "unconverged channels [-]";

/// The figures a sweep records of a run (named `<channel> <field> [unit]`, the field
/// as in `summary.json`: `max`, `min`, `abs_peak`). A mechanism: every channel's max and
/// min and the steps. A vehicle scene: the hitch force components' max, min and |peak|
/// raw and the |peak| of their band-limited twins; each accelerometer's |peak|
/// band-limited (as the instrument saw it) and raw; the crossbeam's largest deflection
/// and strain energy; the driver's floor comfort (a_w and VDV per axis, total value) and
/// the seat surface's (z a_w and VDV, total value) when the vehicle has a seat;
/// solver effort. No signed peak: a larger pull and a larger push
/// both read as a larger |peak|.
pub fn figures(r: &RunResult) -> Figures {
    let s = &r.summary;
    let mut out = Figures::new();
    if s.scene.is_none() {
        for (name, c) in &s.channels {
            out.push((format!("{name} max [{}]", c.unit), c.extremes.max));
            out.push((format!("{name} min [{}]", c.unit), c.extremes.min));
        }
        out.push(("steps".into(), s.solver.steps as f64));
        verdict_figures(r, &mut out);
        return out;
    }
    let twin = |c: &crate::job::ChannelSummary| c.twin.as_ref().and_then(|t| s.channels.get(t));
    for n in [channels::HITCH_FX, channels::HITCH_FY, channels::HITCH_FZ] {
        if let Some(c) = s.channels.get(n) {
            let e = &c.extremes;
            out.push((format!("{n} max [N]"), e.max));
            out.push((format!("{n} min [N]"), e.min));
            out.push((format!("{n} abs_peak [N]"), e.abs_peak));
            if let (Some(b), Some(t)) = (twin(c), &c.twin) {
                out.push((format!("{t} abs_peak [N]"), b.extremes.abs_peak));
            }
        }
    }
    for (name, c) in &s.channels {
        if channels::band(name) != Some(channels::Band::Sensor)
            || c.signal != crate::job::Signal::Raw
        {
            continue;
        }
        if let (Some(b), Some(t)) = (twin(c), &c.twin) {
            out.push((format!("{t} abs_peak [{}]", c.unit), b.extremes.abs_peak));
        }
        out.push((format!("{name} abs_peak [{}]", c.unit), c.extremes.abs_peak));
    }
    // Fatigue: the damage-equivalent loads (rainflow, m and N_ref of `durability`) of
    // the ball force, of each bracket load component at the worse bracket (a design
    // must hold on both sides; a symmetric scene loads them alike), and of the crossbeam
    // points' equivalent stress; and the crossbeam's largest equivalent stress per
    // point.
    let mut brackets: Vec<(String, f64)> = Vec::new();
    for d in &s.durability {
        let side = channels::HITCH_BRACKETS.iter().find_map(|b| {
            d.channel
                .strip_prefix(&format!("{}{b}_", channels::HITCH_BRACKET_PREFIX))
        });
        match side {
            Some(c) => {
                let name = format!("{}{c} DEL [{}]", channels::HITCH_BRACKET_PREFIX, d.unit);
                match brackets.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, v)) => *v = v.max(d.del_at_n_ref),
                    None => brackets.push((name, d.del_at_n_ref)),
                }
            }
            None => out.push((format!("{} DEL [{}]", d.channel, d.unit), d.del_at_n_ref)),
        }
    }
    out.extend(brackets);
    for (name, c) in &s.channels {
        if name.starts_with("hitch_stress_")
            && name.ends_with("_eq")
            && c.signal == crate::job::Signal::Raw
        {
            out.push((format!("{name} max [Pa]"), c.extremes.max));
        }
    }
    // The IIW check of each stress point with a FAT class (Miner sum of one passage,
    // worst fibre) and the ball forces against the coupling's R55 rating.
    for c in &s.fat_check {
        out.push((
            format!("hitch_stress_{} IIW damage per passage [-]", c.point),
            c.damage_per_passage,
        ));
    }
    if let Some(c) = &s.coupling {
        out.push((BALL_PEAK_OVER_D.into(), c.peak_over_d));
        out.push((FX_AMPLITUDE_OVER_TEST.into(), c.fx_amplitude_over_test));
    }
    // Ride comfort at the driver's floor (ISO 2631-1): each axis's a_w and VDV (the
    // measure that counts for a short passage, docs/comfort.md) and the total value.
    if let Some(c) = &s.comfort {
        for a in &c.axes {
            out.push((format!("{} a_w [m/s^2]", a.channel), a.measures.rms_m_s2));
            out.push((
                format!("{} VDV [m/s^1.75]", a.channel),
                a.measures.vdv_m_s1_75,
            ));
        }
        if let Some(v) = c.total_value_m_s2 {
            out.push((COMFORT_TOTAL.into(), v));
        }
    }
    // And at the seat surface when the body file gives a seat: its z (x and y are the
    // floor's) and the total value.
    if let Some(c) = &s.comfort_seat {
        for a in c
            .comfort
            .axes
            .iter()
            .filter(|a| a.channel == crate::comfort::SEAT_Z)
        {
            out.push((format!("{} a_w [m/s^2]", a.channel), a.measures.rms_m_s2));
            out.push((
                format!("{} VDV [m/s^1.75]", a.channel),
                a.measures.vdv_m_s1_75,
            ));
        }
        if let Some(v) = c.comfort.total_value_m_s2 {
            out.push((COMFORT_SEAT_TOTAL.into(), v));
        }
    }
    let [dx, dy, dz] = channels::HITCH_DEFLECTION;
    if let (Some(x), Some(y), Some(z)) = (r.channel(dx), r.channel(dy), r.channel(dz)) {
        let d = (0..x.len()).fold(0.0f64, |m, k| {
            m.max((x[k] * x[k] + y[k] * y[k] + z[k] * z[k]).sqrt())
        });
        out.push((CROSSBEAM_DEFLECTION.into(), d));
    }
    if let Some(c) = s.channels.get(channels::HITCH_STRAIN_ENERGY) {
        out.push((CROSSBEAM_ENERGY.into(), c.extremes.max));
    }
    out.push(("steps".into(), s.solver.steps as f64));
    out.push(("run wall time [s]".into(), s.start_wall_s + s.wall_s));
    verdict_figures(r, &mut out);
    out
}

/// Appends the convergence verdict's figures when the run has one.
fn verdict_figures(r: &RunResult, out: &mut Figures) {
    let Some(v) = &r.summary.convergence else {
        return;
    };
    let worst = v
        .channels
        .values()
        .filter(|c| !c.below_floor)
        .map(|c| c.worst())
        .fold(0.0f64, f64::max);
    out.push((CONVERGED.into(), if v.converged { 1.0 } else { 0.0 }));
    out.push((CONVERGENCE_WORST.into(), 100.0 * worst));
    out.push((UNCONVERGED.into(), v.failing.len() as f64));
}

/// The figure of the crossbeam's largest deflection: the length of the ball's
/// displacement vector, at its largest.
pub const CROSSBEAM_DEFLECTION: &str = "crossbeam |deflection| max [m]";
/// The figure of the driver's floor point's vibration total value (ISO 2631-1 eq. 9).
pub const COMFORT_TOTAL: &str = "comfort a_v [m/s^2]";
/// The figure of the seat surface's vibration total value (z through the seat).
pub const COMFORT_SEAT_TOTAL: &str = "comfort seat a_v [m/s^2]";
/// The figure of the crossbeam's largest strain energy.
pub const CROSSBEAM_ENERGY: &str = "crossbeam strain energy max [J]";
/// The figure of the ball force's largest |F| over the coupling's D-value (UN R55).
pub const BALL_PEAK_OVER_D: &str = "ball |F| peak / D [-]";
/// The figure of hitch_fx's largest amplitude over the R55 test force's fore-aft one.
pub const FX_AMPLITUDE_OVER_TEST: &str = "hitch_fx amplitude / R55 test [-]";
