//! Independent factors of the rigid-ring tyre: the coupled `.tir` values re-parameterised
//! so that every combination of factor values, each inside its open range, is a tyre the
//! checks of [`crate::tyre::params`] accept (issue 33).
//!
//! The `.tir` values are coupled by the rigid-ring model (Pacejka 2012, sec. 9.2, after
//! Zegelaar 1998): the belt must be lighter than the tyre (BELT_MASS < MASS, BELT_IYY <
//! IYY), the sidewall spring c_b = BELT_MASS (2 pi FREQ_LONG)^2 must be stiffer than the
//! overall VERTICAL_STIFFNESS (the residual spring is in series), and the overall
//! LONGITUDINAL_STIFFNESS must stay below the ring's own,
//! 1 / (1/c_b + r_l^2 / c_theta), c_theta = BELT_IYY (2 pi FREQ_WINDUP)^2,
//! r_l = UNLOADED_RADIUS - FNOMIN / VERTICAL_STIFFNESS. Varying these values one by one
//! leaves that region. The factors are (formula, range, the constraint it removes):
//!
//! | factor | value | open range | removes |
//! |---|---|---|---|
//! | `total_mass_kg` | MASS | (0, inf) | - |
//! | `belt_mass_share` | BELT_MASS / MASS | (0, 1) | BELT_MASS < MASS |
//! | `spin_inertia_kg_m2` | IYY | (0, inf) | - |
//! | `belt_inertia_share` | BELT_IYY / IYY | (0, 1) | BELT_IYY < IYY |
//! | `vertical_stiffness_n_m` | VERTICAL_STIFFNESS | (0, inf) | - |
//! | `ring_stiffness_ratio` | c_b / VERTICAL_STIFFNESS | (1, inf) | c_b > VERTICAL_STIFFNESS |
//! | `longitudinal_tread_share` | 1 - LONGITUDINAL_STIFFNESS (1/c_b + r_l^2/c_theta) | (0, 1) | LONGITUDINAL_STIFFNESS < ring's |
//!
//! The tread share is the residual (tread) spring's part of the overall longitudinal
//! compliance. The overall longitudinal stiffness cannot be a free factor of its own:
//! the ring's translation stiffness is the vertical one (MF-Swift's FREQ_LONG serves
//! both), so the ring's longitudinal stiffness follows from the vertical factors, the
//! belt inertia and FREQ_WINDUP, and the overall one is (1 - tread share) times it.
//! FREQ_WINDUP, UNLOADED_RADIUS and FNOMIN stay raw values (any positive value is valid).
//!
//! Setting any factor of a file recomputes the seven driven values (MASS, BELT_MASS, IYY,
//! BELT_IYY, VERTICAL_STIFFNESS, FREQ_LONG, LONGITUDINAL_STIFFNESS) from the factors, the
//! unset ones at their values in the file as written, and the raw values that are not
//! driven (FREQ_WINDUP, ...) as overridden; so a factor set to its file value reproduces
//! the file to round-off, and a raw FREQ_WINDUP beside a factor keeps the tread share. A raw override of a driven
//! value together with a factor of the same file is refused, naming both.

use std::f64::consts::PI;
use std::path::Path;

use crate::input::provenance::{ProvenanceEntry, SourceClass};
use crate::input::tir::TirFile;
use crate::input::InputError;

/// The path prefix of a factor in an override: `FILE.tir:factor.NAME`.
pub const PREFIX: &str = "factor.";

/// One factor.
#[derive(Clone, Copy, Debug)]
pub struct Factor {
    /// Its name after `factor.`.
    pub name: &'static str,
    /// Open range of valid values (lower, upper).
    pub range: (f64, f64),
    /// What it is in the sensitivity tables: `mass` or `stiffness`.
    pub kind: &'static str,
    /// The `.tir` values it is computed from (its provenance is the weakest of theirs).
    pub sources: &'static [&'static str],
    /// The `.tir` value it stands for most directly (where it is listed).
    pub main: &'static str,
}

const INF: f64 = f64::INFINITY;
const RING: &[&str] = &["INERTIA.BELT_MASS", "STRUCTURAL.FREQ_LONG"];

/// The factors, in the order they are listed.
pub const FACTORS: [Factor; 7] = [
    Factor {
        name: "total_mass_kg",
        range: (0.0, INF),
        kind: "mass",
        sources: &["INERTIA.MASS"],
        main: "INERTIA.MASS",
    },
    Factor {
        name: "belt_mass_share",
        range: (0.0, 1.0),
        kind: "mass",
        sources: &["INERTIA.BELT_MASS", "INERTIA.MASS"],
        main: "INERTIA.BELT_MASS",
    },
    Factor {
        name: "spin_inertia_kg_m2",
        range: (0.0, INF),
        kind: "mass",
        sources: &["INERTIA.IYY"],
        main: "INERTIA.IYY",
    },
    Factor {
        name: "belt_inertia_share",
        range: (0.0, 1.0),
        kind: "mass",
        sources: &["INERTIA.BELT_IYY", "INERTIA.IYY"],
        main: "INERTIA.BELT_IYY",
    },
    Factor {
        name: "vertical_stiffness_n_m",
        range: (0.0, INF),
        kind: "stiffness",
        sources: &["VERTICAL.VERTICAL_STIFFNESS"],
        main: "VERTICAL.VERTICAL_STIFFNESS",
    },
    Factor {
        name: "ring_stiffness_ratio",
        range: (1.0, INF),
        kind: "stiffness",
        sources: &[RING[0], RING[1], "VERTICAL.VERTICAL_STIFFNESS"],
        main: "STRUCTURAL.FREQ_LONG",
    },
    Factor {
        name: "longitudinal_tread_share",
        range: (0.0, 1.0),
        kind: "stiffness",
        sources: &[
            "STRUCTURAL.LONGITUDINAL_STIFFNESS",
            RING[0],
            RING[1],
            "INERTIA.BELT_IYY",
            "STRUCTURAL.FREQ_WINDUP",
            "DIMENSION.UNLOADED_RADIUS",
            "VERTICAL.FNOMIN",
            "VERTICAL.VERTICAL_STIFFNESS",
        ],
        main: "STRUCTURAL.LONGITUDINAL_STIFFNESS",
    },
];

/// The `.tir` values the factors drive: set from the factors once any factor is set.
pub const DRIVEN: [&str; 7] = [
    "INERTIA.MASS",
    "INERTIA.BELT_MASS",
    "INERTIA.IYY",
    "INERTIA.BELT_IYY",
    "VERTICAL.VERTICAL_STIFFNESS",
    "STRUCTURAL.FREQ_LONG",
    "STRUCTURAL.LONGITUDINAL_STIFFNESS",
];

/// The factor named `name` (after `factor.`).
pub fn find(name: &str) -> Option<&'static Factor> {
    FACTORS.iter().find(|f| f.name == name)
}

/// True when `value` lies in the factor's open range.
pub fn in_range(f: &Factor, value: f64) -> bool {
    value.is_finite() && value > f.range.0 && value < f.range.1
}

/// The factor values of a parsed file, in [`FACTORS`] order (checked only for being
/// numbers: an invalid file gives factors outside their ranges, which the tyre's own
/// checks then refuse).
pub fn values(t: &TirFile) -> Result<[f64; 7], InputError> {
    let v = |k: &str| {
        let (s, key) = k.split_once('.').expect("SECTION.KEY");
        t.f64(s, key)
    };
    let (m, mb, iyy, ib) = (
        v("INERTIA.MASS")?,
        v("INERTIA.BELT_MASS")?,
        v("INERTIA.IYY")?,
        v("INERTIA.BELT_IYY")?,
    );
    let (cz, f_long, cx) = (
        v("VERTICAL.VERTICAL_STIFFNESS")?,
        v("STRUCTURAL.FREQ_LONG")?,
        v("STRUCTURAL.LONGITUDINAL_STIFFNESS")?,
    );
    let c_b = mb * (2.0 * PI * f_long).powi(2);
    let ring = ring_compliance(t, c_b, ib, cz)?;
    Ok([m, mb / m, iyy, ib / iyy, cz, c_b / cz, 1.0 - cx * ring])
}

/// The ring's longitudinal compliance 1/c_b + r_l^2 / c_theta (see the module text).
fn ring_compliance(t: &TirFile, c_b: f64, belt_iyy: f64, cz: f64) -> Result<f64, InputError> {
    let r0 = t.f64("DIMENSION", "UNLOADED_RADIUS")?;
    let fnomin = t.f64("VERTICAL", "FNOMIN")?;
    let f_wind = t.f64("STRUCTURAL", "FREQ_WINDUP")?;
    let c_theta = belt_iyy * (2.0 * PI * f_wind).powi(2);
    let r_l = r0 - fnomin / cz;
    Ok(1.0 / c_b + r_l * r_l / c_theta)
}

/// The driven values (in [`DRIVEN`] order) of factor values `x` ([`FACTORS`] order),
/// the other values taken from `t`.
pub fn driven(t: &TirFile, x: &[f64; 7]) -> Result<[f64; 7], InputError> {
    let [m, s_m, iyy, s_i, cz, ratio, s_t] = *x;
    let (mb, ib) = (s_m * m, s_i * iyy);
    let c_b = ratio * cz;
    let f_long = (c_b / mb).sqrt() / (2.0 * PI);
    let cx = (1.0 - s_t) / ring_compliance(t, c_b, ib, cz)?;
    Ok([m, mb, iyy, ib, cz, f_long, cx])
}

/// The factor provenance entries of a `.tir` file's tagged values: each factor takes
/// the weakest class of the values it is computed from (untagged counts as assumed).
pub fn provenance(entries: &[ProvenanceEntry]) -> Vec<ProvenanceEntry> {
    FACTORS
        .iter()
        .filter_map(|f| {
            let of = |k: &str| entries.iter().find(|e| e.key == k);
            let main = of(f.main)?;
            let class = f
                .sources
                .iter()
                .map(|k| of(k).map_or(SourceClass::Assumed, |e| e.class))
                .max()?;
            let from: Vec<String> = f
                .sources
                .iter()
                .map(|k| {
                    let c = of(k).map_or("untagged", |e| e.class.as_str());
                    format!("{k} [{c}]")
                })
                .collect();
            Some(ProvenanceEntry {
                key: format!("{PREFIX}{}", f.name),
                line: main.line,
                class,
                source: format!(
                    "independent tyre factor, the weakest class of {}",
                    from.join(", ")
                ),
            })
        })
        .collect()
}

/// Sets the factor overrides `factors` and the values they drive in `t` (the file with
/// its raw overrides `raw` applied, none of which may set a driven value); the factors
/// not set take their values in `original`, the file as written.
pub(crate) fn apply(
    t: &mut TirFile,
    original: &TirFile,
    path: &Path,
    factors: &[&crate::input::loader::Entry],
    raw: &[&crate::input::loader::Entry],
) -> Result<(), InputError> {
    let mut x = values(original)?;
    for e in factors {
        let o = &e.ov;
        let name = o.path.trim().strip_prefix(PREFIX).unwrap_or_default();
        let i = FACTORS.iter().position(|f| f.name == name).ok_or_else(|| {
            o.origin.at_path(format!(
                "{} has no tyre factor `{name}`{}",
                path.display(),
                crate::input::suggest::did_you_mean(name, FACTORS.iter().map(|f| f.name))
            ))
        })?;
        let f = &FACTORS[i];
        let v: f64 = o.value.trim().parse().map_err(|_| {
            o.origin
                .at_path(format!("`{}` is not a number", o.value.trim()))
        })?;
        if !in_range(f, v) {
            return Err(o.origin.at_path(format!(
                "factor.{name} = {v} lies outside its open range ({}, {})",
                f.range.0, f.range.1
            )));
        }
        // A driven value set raw as well: two answers for one number.
        if let Some(r) = raw.iter().find(|r| DRIVEN.contains(&r.ov.path.trim())) {
            // A value towride derives (a `simple` vehicle's tyre): the factor is the one
            // that cannot be set.
            if matches!(r.ov.origin, crate::input::Origin::Derived(_)) {
                return Err(o.origin.at_path(format!(
                    "`factor.{name}` cannot be set: `{}` of {} is derived by {}",
                    r.ov.path.trim(),
                    path.display(),
                    r.ov.origin.describe()
                )));
            }
            return Err(r.ov.origin.at_path(format!(
                "`{}` of {} is derived from the tyre factors once one is set, and `factor.{name}` is set by {}: set one of the two",
                r.ov.path.trim(),
                path.display(),
                o.origin.describe()
            )));
        }
        x[i] = v;
        e.placed(path);
    }
    let d = driven(t, &x)?;
    for (k, v) in DRIVEN.iter().zip(d) {
        let (sec, key) = k.split_once('.').expect("SECTION.KEY");
        // `values` read every driven key, so each is there to be set.
        let _ = t.set_value(sec, key, format!("{v:?}"));
    }
    Ok(())
}
