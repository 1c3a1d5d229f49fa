//! `towride modes`: the mode table, selection and invariants summary of a flexible body.

use crate::CliResult;
use std::path::PathBuf;

use clap::Args;
use towride_mbs::flex::report::{rule_from, ModesReport, SelectionChoice};
use towride_mbs::flex::{FlexBody, Options};
use towride_mbs::input::Loader;

#[derive(Args, Debug)]
pub struct ModesArgs {
    /// Flexible-body file (flex/*.toml).
    file: PathBuf,
    /// Stiffness variant (a [[variant]] number of the file); default: the base sections.
    #[arg(long)]
    variant: Option<u32>,
    /// Keep the elastic modes up to this frequency [Hz] instead of the file's selection.
    #[arg(long, conflicts_with_all = ["modes", "band"], value_parser = crate::bounded::hz)]
    cutoff: Option<f64>,
    /// Keep these modes (mode-table numbers; 7 is the first elastic mode).
    #[arg(long, value_delimiter = ',', conflicts_with = "band")]
    modes: Vec<usize>,
    /// Load-path selection for this excitation band [Hz]: LOW,HIGH.
    #[arg(long, value_delimiter = ',', num_args = 1, value_parser = crate::bounded::hz)]
    band: Option<Vec<f64>>,
    /// Load-path selection: minimum strain-energy share of a mode [%].
    #[arg(long, value_parser = crate::bounded::share_pct)]
    share: Option<f64>,
    /// Fixed-interface modes of the Craig-Bampton reduction (default: the file's).
    #[arg(long, value_parser = crate::bounded::count)]
    fixed_modes: Option<usize>,
    /// Show beside the file's selection the one an earlier run's strain-energy shares
    /// make (the run's folder, holding summary.json).
    #[arg(long, value_name = "RUN_DIR")]
    from_run: Option<PathBuf>,
    /// With --from-run: the modal body of that run (default hitch).
    #[arg(long, default_value = "hitch", requires = "from_run")]
    body: String,
    /// With --from-run: the strain-energy share a mode needs [%] (default 1).
    #[arg(long, requires = "from_run", value_parser = crate::bounded::share_pct)]
    run_share: Option<f64>,
    /// Print machine-readable JSON instead of tables.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &ModesArgs) -> CliResult {
    // The file's own rule is needed to complete partial --band/--share overrides.
    let mesh = towride_mbs::flex::Mesh::read(&a.file, a.variant, &Loader::new())?;
    let choice = SelectionChoice {
        cutoff: a.cutoff,
        modes: a.modes.clone(),
        band: a.band.clone(),
        share: a.share,
    };
    let rule = rule_from(&choice, &mesh.selection)?;
    let body = FlexBody::from_mesh(
        mesh,
        &Options {
            fixed_interface_modes: a.fixed_modes,
            rule,
        },
    )?;
    let report = ModesReport::of(&body, &a.file);
    if let Some(dir) = &a.from_run {
        let at = towride_mbs::input::InputError {
            file: "command line".into(),
            line: None,
            column: None,
            field: "--from-run".into(),
            message: String::new(),
            kind: Default::default(),
        };
        let share = a.run_share.map_or(0.01, |p| p / 100.0);
        let run = towride_mbs::flex::feedback::from_run(dir, share, &at)?;
        let b = run.body(&a.body).ok_or_else(|| {
            let names: Vec<&str> = run.bodies.iter().map(|b| b.body.as_str()).collect();
            format!(
                "{}: no modal body `{}` in that run (bodies: {})",
                dir.display(),
                a.body,
                names.join(", ")
            )
        })?;
        let c = towride_mbs::flex::feedback::compare(&report, &run, b);
        if a.json {
            println!("{}", serde_json::to_string_pretty(&c)?);
        } else {
            print_comparison(&c);
        }
        return Ok(0);
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(0);
    }
    print_text(&report);
    Ok(0)
}
fn print_text(r: &ModesReport) {
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
        "{:>4} {:>12} {:<7} {:>8} {:>9} {:>9} {:>9} {:>10} {:>10} {:>10} {:>6} {:>7} {:>4}  {:<36} moving part",
        "mode", "freq [Hz]", "kind", "gen.mass", "m_x [kg]", "m_y [kg]", "m_z [kg]",
        "I_x[kgm2]", "I_y[kgm2]", "I_z[kgm2]", "zeta", "share%", "sel", "what it does (strain energy)"
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
        let what = m
            .character
            .as_ref()
            .map_or("-".to_string(), |(c, s)| format!("{c} ({:.0}%)", 100.0 * s));
        println!(
            "{:>4} {:>12.4} {:<7} {:>8.5} {:>9.3e} {:>9.3e} {:>9.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>6} {:>7} {:>4}  {what:<36} {part}",
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

fn print_comparison(c: &towride_mbs::flex::feedback::Comparison) {
    println!(
        "body {}: a priori ({}) against the run in {} (share >= {} %)",
        c.body,
        c.a_priori_rule,
        c.run_dir,
        100.0 * c.min_energy_share
    );
    println!(
        "{:>4} {:>10} {:>8} {:>9} {:>11} {:>13} {:>6}",
        "mode", "freq [Hz]", "a priori", "share %", "run peak %", "run integr. %", "run"
    );
    for m in &c.modes {
        let (p, i) = m
            .run_shares
            .map_or(("not run".to_string(), "-".to_string()), |s| {
                (
                    format!("{:.2}", 100.0 * s[0]),
                    format!("{:.2}", 100.0 * s[1]),
                )
            });
        println!(
            "{:>4} {:>10.2} {:>8} {:>9} {:>11} {:>13} {:>6}",
            m.number,
            m.frequency_hz,
            if m.a_priori { "*" } else { "" },
            m.a_priori_share
                .map_or("-".to_string(), |s| format!("{:.2}", 100.0 * s)),
            p,
            i,
            if m.run_based { "*" } else { "" }
        );
    }
    println!("a priori: {:?}", c.a_priori_modes);
    println!("run-based: {:?}", c.run_based_modes);
}
