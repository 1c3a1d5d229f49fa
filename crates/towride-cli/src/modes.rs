//! `towride modes`: the mode table, selection and invariants summary of a flexible body.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use towride::flex::modes::frequency_hz;
use towride::flex::selection::{LoadPath, DEFAULT_MIN_ENERGY_SHARE};
use towride::flex::{FlexBody, ModeKind, Options, Rule};

#[derive(Args, Debug)]
pub struct ModesArgs {
    /// Flexible-body file (flex/*.toml).
    file: PathBuf,
    /// Stiffness variant (a [[variant]] number of the file); default: the base sections.
    #[arg(long)]
    variant: Option<u32>,
    /// Keep the elastic modes up to this frequency [Hz] instead of the file's selection.
    #[arg(long, conflicts_with_all = ["modes", "band"])]
    cutoff: Option<f64>,
    /// Keep these modes (mode-table numbers; 7 is the first elastic mode).
    #[arg(long, value_delimiter = ',', conflicts_with = "band")]
    modes: Vec<usize>,
    /// Load-path selection for this excitation band [Hz]: LOW,HIGH.
    #[arg(long, value_delimiter = ',', num_args = 1)]
    band: Option<Vec<f64>>,
    /// Load-path selection: minimum strain-energy share of a mode [%].
    #[arg(long)]
    share: Option<f64>,
    /// Fixed-interface modes of the Craig-Bampton reduction (default: the file's).
    #[arg(long)]
    fixed_modes: Option<usize>,
    /// Print machine-readable JSON instead of tables.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct ModeRecord {
    index: usize,
    frequency_hz: f64,
    kind: &'static str,
    generalised_mass: f64,
    /// x, y, z [kg], rx, ry, rz about the centre of mass [kg m^2].
    effective_mass: [f64; 6],
    selected: bool,
    damping_ratio: Option<f64>,
    /// Load-path rule: largest weighted strain-energy share over the load cases.
    energy_share: Option<f64>,
    /// Share of the mode's kinetic energy per section, largest first.
    kinetic_energy_by_section: Vec<(String, f64)>,
}

/// A fixed-interface normal mode with its effective mass relative to the held
/// interface (rigid-body directions about the centre of mass).
#[derive(Serialize)]
struct FixedModeRecord {
    frequency_hz: f64,
    effective_mass: [f64; 6],
}

#[derive(Serialize)]
struct NodeRecord {
    name: String,
    kind: &'static str,
    position_m: [f64; 3],
}

#[derive(Serialize)]
struct InvariantSummary {
    /// max |I3|, max |I4|: first-order coupling, zero for modes orthogonal to rigid motion.
    i3_max_abs: f64,
    i4_max_abs: f64,
    /// max |I6 - identity|: modal mass.
    i6_identity_error: f64,
    i5_max_abs: f64,
    i8_max_abs: f64,
    i9_max_abs: f64,
}

#[derive(Serialize)]
struct Report {
    file: String,
    name: String,
    variant: Option<u32>,
    variant_description: Option<String>,
    fe_nodes: usize,
    elements: usize,
    dof: usize,
    fixed_interface_modes: usize,
    fixed_interface_frequencies_hz: Vec<f64>,
    fixed_interface_table: Vec<FixedModeRecord>,
    mass_kg: f64,
    com_m: [f64; 3],
    /// About the centre of mass.
    inertia_kg_m2: [[f64; 3]; 3],
    nodes: Vec<NodeRecord>,
    modes: Vec<ModeRecord>,
    selection_rule: String,
    selected_modes: Vec<usize>,
    invariants: InvariantSummary,
}

fn rule_from_args(a: &ModesArgs, file_rule: &Rule) -> Result<Option<Rule>, String> {
    if let Some(c) = a.cutoff {
        if c.is_nan() || c <= 0.0 {
            return Err(format!("--cutoff must be positive, got {c}"));
        }
        return Ok(Some(Rule::Cutoff { max_hz: c }));
    }
    if !a.modes.is_empty() {
        return Ok(Some(Rule::List {
            modes: a.modes.clone(),
        }));
    }
    if a.band.is_some() || a.share.is_some() {
        let band = match &a.band {
            Some(b) if b.len() == 2 && b[0] >= 0.0 && b[1] > b[0] => [b[0], b[1]],
            Some(b) => {
                return Err(format!(
                    "--band needs LOW,HIGH with 0 <= LOW < HIGH, got {b:?}"
                ))
            }
            None => match file_rule {
                Rule::LoadPath(l) => l.band_hz,
                _ => return Err("--share needs --band (the file's rule is not load_path)".into()),
            },
        };
        let share = match a.share {
            Some(s) if s > 0.0 && s < 100.0 => s / 100.0,
            Some(s) => return Err(format!("--share is a percentage in (0, 100), got {s}")),
            None => match file_rule {
                Rule::LoadPath(l) => l.min_energy_share,
                _ => DEFAULT_MIN_ENERGY_SHARE,
            },
        };
        let (load_interfaces, load_moments, load_n) = match file_rule {
            Rule::LoadPath(l) => (l.load_interfaces.clone(), l.load_moments, l.load_n),
            _ => (vec![], true, None),
        };
        return Ok(Some(Rule::LoadPath(LoadPath {
            band_hz: band,
            min_energy_share: share,
            load_interfaces,
            load_moments,
            load_n,
        })));
    }
    Ok(None)
}

fn max_abs<'a>(it: impl Iterator<Item = &'a f64>) -> f64 {
    it.fold(0.0, |m, x| m.max(x.abs()))
}

fn summary(body: &FlexBody) -> InvariantSummary {
    let inv = &body.modal.invariants;
    let n = inv.i6.len();
    let mut i6e: f64 = 0.0;
    for j in 0..n {
        for k in 0..n {
            let want = if j == k { 1.0 } else { 0.0 };
            i6e = i6e.max((inv.i6[j][k] - want).abs());
        }
    }
    InvariantSummary {
        i3_max_abs: max_abs(inv.i3.iter().flatten()),
        i4_max_abs: max_abs(inv.i4.iter().flatten()),
        i6_identity_error: i6e,
        i5_max_abs: max_abs(inv.i5.iter().flatten().flatten()),
        i8_max_abs: max_abs(inv.i8.iter().flatten().flatten()),
        i9_max_abs: max_abs(inv.i9.iter().flatten().flatten().flatten()),
    }
}

pub fn run(a: &ModesArgs) -> Result<i32, String> {
    // The file's own rule is needed to complete partial --band/--share overrides.
    let mesh = towride::flex::Mesh::read(&a.file, a.variant).map_err(|e| e.to_string())?;
    let rule = rule_from_args(a, &mesh.selection)?;
    let body = FlexBody::from_mesh(
        mesh,
        &Options {
            fixed_interface_modes: a.fixed_modes,
            rule,
        },
    )
    .map_err(|e| e.to_string())?;
    let md = &body.modal;
    let share_of = |number: usize| -> Option<f64> {
        let k = md.modes.iter().position(|m| m.number == number)?;
        body.selection.max_share.as_ref().map(|s| s[k])
    };
    let modes: Vec<ModeRecord> = body
        .table
        .iter()
        .map(|r| {
            let m = md.modes.iter().find(|m| m.number == r.number);
            ModeRecord {
                index: r.number,
                frequency_hz: r.frequency_hz,
                kind: r.kind.as_str(),
                generalised_mass: r.generalised_mass,
                effective_mass: r.effective_mass,
                selected: r.kind == ModeKind::Elastic && m.is_some_and(|m| m.selected),
                damping_ratio: m.map(|m| m.damping_ratio),
                energy_share: share_of(r.number),
                kinetic_energy_by_section: r.kinetic_energy_by_section.clone(),
            }
        })
        .collect();
    let report = Report {
        file: a.file.display().to_string(),
        name: body.mesh.name.clone(),
        variant: body.mesh.variant.as_ref().map(|v| v.number),
        variant_description: body.mesh.variant.as_ref().map(|v| v.description.clone()),
        fe_nodes: body.mesh.nodes.len(),
        elements: body.mesh.elements.len(),
        dof: body.assembly.n_dof,
        fixed_interface_modes: body.cb.fixed_interface_omega2.len(),
        fixed_interface_frequencies_hz: body
            .cb
            .fixed_interface_omega2
            .iter()
            .map(|&w| frequency_hz(w))
            .collect(),
        fixed_interface_table: towride::flex::craig_bampton::effective_masses(
            &body.assembly,
            &body.cb.fixed_interface_modes,
        )
        .into_iter()
        .zip(&body.cb.fixed_interface_omega2)
        .map(|((_, e), &w)| FixedModeRecord {
            frequency_hz: frequency_hz(w),
            effective_mass: e,
        })
        .collect(),
        mass_kg: md.mass_kg,
        com_m: md.com_m,
        inertia_kg_m2: md.inertia_com_kg_m2,
        nodes: md
            .nodes
            .iter()
            .map(|n| NodeRecord {
                name: n.name.clone(),
                kind: match n.kind {
                    towride::flex::NodeKind::Interface => "interface",
                    towride::flex::NodeKind::Marker => "marker",
                },
                position_m: n.position_m,
            })
            .collect(),
        selected_modes: md
            .modes
            .iter()
            .filter(|m| m.selected)
            .map(|m| m.number)
            .collect(),
        selection_rule: body.rule.describe(),
        invariants: summary(&body),
        modes,
    };
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?
        );
        return Ok(0);
    }
    print_text(&report);
    Ok(0)
}

fn print_text(r: &Report) {
    let variant = match (&r.variant, &r.variant_description) {
        (Some(v), Some(d)) if !d.is_empty() => format!(", variant {v} ({d})"),
        (Some(v), _) => format!(", variant {v}"),
        _ => String::new(),
    };
    println!("{}{variant}: {}", r.name, r.file);
    println!(
        "{} FE nodes, {} beam elements, {} DOF; Craig-Bampton with {} interface nodes and {} fixed-interface modes",
        r.fe_nodes,
        r.elements,
        r.dof,
        r.nodes.iter().filter(|n| n.kind == "interface").count(),
        r.fixed_interface_modes
    );
    println!(
        "mass {:.4} kg, centre of mass ({:.4}, {:.4}, {:.4}) m",
        r.mass_kg, r.com_m[0], r.com_m[1], r.com_m[2]
    );
    println!("inertia about the centre of mass [kg m^2]:");
    for row in &r.inertia_kg_m2 {
        println!("  {:>12.5e} {:>12.5e} {:>12.5e}", row[0], row[1], row[2]);
    }
    for n in &r.nodes {
        println!(
            "{:<9} {:<16} ({:.4}, {:.4}, {:.4}) m",
            n.kind, n.name, n.position_m[0], n.position_m[1], n.position_m[2]
        );
    }
    println!();
    println!(
        "{:>4} {:>12} {:<7} {:>8} {:>9} {:>9} {:>9} {:>10} {:>10} {:>10} {:>6} {:>7} {:>4}  moving part",
        "mode", "freq [Hz]", "kind", "gen.mass", "m_x [kg]", "m_y [kg]", "m_z [kg]",
        "I_x[kgm2]", "I_y[kgm2]", "I_z[kgm2]", "zeta", "share%", "sel"
    );
    for m in &r.modes {
        let e = m.effective_mass;
        let part = m
            .kinetic_energy_by_section
            .iter()
            .take(2)
            .map(|(n, e)| format!("{n} {:.0}%", 100.0 * e))
            .collect::<Vec<_>>()
            .join(", ");
        println!(
            "{:>4} {:>12.4} {:<7} {:>8.5} {:>9.3e} {:>9.3e} {:>9.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>6} {:>7} {:>4}  {part}",
            m.index,
            m.frequency_hz,
            m.kind,
            m.generalised_mass,
            e[0],
            e[1],
            e[2],
            e[3],
            e[4],
            e[5],
            m.damping_ratio.map_or("-".to_string(), |z| format!("{z:.2}")),
            m.energy_share.map_or("-".to_string(), |s| format!("{:.2}", 100.0 * s)),
            if m.selected { "*" } else { "" }
        );
    }
    println!();
    println!(
        "fixed-interface modes (interface held), effective mass in % of the body's mass / inertia:"
    );
    println!(
        "{:>4} {:>12} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7}",
        "", "freq [Hz]", "x", "y", "z", "rx", "ry", "rz"
    );
    let totals = [
        r.mass_kg,
        r.mass_kg,
        r.mass_kg,
        r.inertia_kg_m2[0][0],
        r.inertia_kg_m2[1][1],
        r.inertia_kg_m2[2][2],
    ];
    for (i, m) in r.fixed_interface_table.iter().enumerate() {
        let p: Vec<String> = (0..6)
            .map(|d| format!("{:>7.2}", 100.0 * m.effective_mass[d] / totals[d]))
            .collect();
        println!("{:>4} {:>12.4} {}", i + 1, m.frequency_hz, p.join(" "));
    }
    println!(
        "selection ({}): {} of {} elastic modes: {:?}",
        r.selection_rule,
        r.selected_modes.len(),
        r.modes.iter().filter(|m| m.kind == "elastic").count(),
        r.selected_modes
    );
    let i = &r.invariants;
    println!(
        "invariants: I1 = {:.4} kg; max|I3| = {:.2e} kg, max|I4| = {:.2e} kg m (mean-axis frame: ~0); \
         max|I6 - I| = {:.2e}; max|I5| = {:.3e}, max|I8| = {:.3e}, max|I9| = {:.3e}",
        r.mass_kg, i.i3_max_abs, i.i4_max_abs, i.i6_identity_error, i.i5_max_abs, i.i8_max_abs, i.i9_max_abs
    );
}
