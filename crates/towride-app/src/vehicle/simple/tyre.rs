//! A tyre from its size and vertical stiffness: the base `.tir` of the defaults file read
//! with its size, masses, inertias and stiffnesses replaced (property overrides, so the
//! `.tir` reader checks them as if written in the file).

use std::path::Path;

use serde::Deserialize;

use super::{Ctx, Kind};
use towride_mbs::input::{InputError, Override, Seg};
use towride_mbs::tyre::{Tyre, TyreKind};

/// The compact file's tyre: `{ size = "215/65 R16 C", vertical_stiffness_n_m = 3.2e5 }`.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(super) struct TyreSec {
    /// ISO metric size, `WIDTH/ASPECT RRIM` (a trailing `C` or load index is ignored).
    pub size: String,
    /// Overall vertical stiffness at the operating pressure [N/m].
    pub vertical_stiffness_n_m: f64,
    /// Whole tyre [kg]; scaled from the base tyre when absent.
    pub mass_kg: Option<f64>,
    /// A `.tir` to take everything else from (relative to the compact file).
    pub base: Option<String>,
}

/// Width [m], aspect ratio [-] and rim diameter [in] of `215/65 R16 C`.
pub(super) fn parse_size(s: &str) -> Option<(f64, f64, f64)> {
    let (w, rest) = s.trim().split_once('/')?;
    let rest = rest.trim();
    let r = rest.find(['R', 'r'])?;
    let aspect: f64 = rest[..r].trim().parse().ok()?;
    let rim: String = rest[r + 1..]
        .trim()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    let (w, rim): (f64, f64) = (w.trim().parse().ok()?, rim.parse().ok()?);
    (w > 0.0 && aspect > 0.0 && rim > 0.0).then_some((w * 1e-3, aspect * 1e-2, rim))
}

/// The tyre of `t` (at `p` in the compact file), nominal load `fnomin` [N].
pub(super) fn build(
    ctx: &Ctx,
    t: &TyreSec,
    p: &[Seg],
    kind: TyreKind,
    fnomin: f64,
) -> Result<(Tyre, f64), InputError> {
    let at = |k: &str| super::at(p, k);
    let (width, aspect, rim_in) = parse_size(&t.size).ok_or_else(|| {
        ctx.src.error(
            &at("size"),
            format!(
                "'{}': write the ISO size as WIDTH/ASPECT RRIM, e.g. 215/65 R16",
                t.size
            ),
        )
    })?;
    let cz = ctx
        .src
        .positive(&at("vertical_stiffness_n_m"), t.vertical_stiffness_n_m)?;
    let d = &ctx.defaults.d.tyre;
    let r0 = 0.5 * rim_in * 0.0254 + width * aspect;
    let field = |k: &str| format!("{}.{k}", towride_mbs::input::path_string(p));
    let mass = match t.mass_kg {
        Some(m) => ctx.src.positive(&at("mass_kg"), m)?,
        None => {
            let m = d.mass_per_width_radius_kg_m2 * width * r0;
            ctx.note(
                &field("mass_kg"),
                m,
                "kg",
                Kind::Assumed,
                format!(
                "{} kg/m^2 x width {width} m x radius {r0:.4} m (tyre.mass_per_width_radius_kg_m2)",
                d.mass_per_width_radius_kg_m2
            ),
            );
            m
        }
    };
    let base = match &t.base {
        Some(b) => ctx.dir.join(b),
        None => {
            let b = ctx.defaults_dir().join(&d.base);
            ctx.note(
                &field("base"),
                f64::NAN,
                "",
                Kind::Assumed,
                format!(
                    "every other tyre parameter from {} (tyre.base)",
                    b.display()
                ),
            );
            b
        }
    };
    if !base.is_file() {
        return Err(ctx
            .src
            .error(&at("base"), towride_mbs::input::no_file(&base)));
    }
    let name = base
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().to_string());
    let belt = d.belt_share * mass;
    let values = [
        ("DIMENSION.UNLOADED_RADIUS", r0, "m", "from the size"),
        ("DIMENSION.WIDTH", width, "m", "from the size"),
        ("INERTIA.MASS", mass, "kg", "the tyre's mass"),
        (
            "INERTIA.IYY",
            d.inertia_per_m_r0sq * mass * r0 * r0,
            "kg m^2",
            "tyre.inertia_per_m_r0sq x m r0^2",
        ),
        ("INERTIA.BELT_MASS", belt, "kg", "tyre.belt_share x mass"),
        (
            "INERTIA.BELT_IYY",
            d.belt_inertia_per_m_r0sq * belt * r0 * r0,
            "kg m^2",
            "tyre.belt_inertia_per_m_r0sq x belt mass x r0^2",
        ),
        (
            "VERTICAL.VERTICAL_STIFFNESS",
            cz,
            "N/m",
            "the file's vertical stiffness",
        ),
        (
            "VERTICAL.FNOMIN",
            fnomin,
            "N",
            "the front corner's static load",
        ),
        (
            "STRUCTURAL.LONGITUDINAL_STIFFNESS",
            d.longitudinal_per_vertical * cz,
            "N/m",
            "tyre.longitudinal_per_vertical x vertical stiffness",
        ),
    ];
    let overrides = values
        .iter()
        .map(|(k, v, _, why)| {
            Override::derived(
                &name,
                k,
                format!("{v:e}"),
                &format!(
                    "{} `{}` ({why})",
                    towride_mbs::input::normalized(&ctx.src.path).display(),
                    field("size")
                ),
            )
        })
        .collect();
    for (k, v, unit, why) in &values[..6] {
        ctx.note(
            &format!("{} {k}", field("size")),
            *v,
            unit,
            Kind::Derived,
            why.to_string(),
        );
    }
    let loader = ctx.loader.extended(overrides);
    let tyre = Tyre::from_file(Path::new(&base), kind, &loader)?;
    Ok((tyre, r0))
}

#[cfg(test)]
mod tests {
    #[test]
    fn iso_sizes() {
        assert_eq!(super::parse_size("215/65 R16 C"), Some((0.215, 0.65, 16.0)));
        assert_eq!(super::parse_size("155/80R13"), Some((0.155, 0.8, 13.0)));
        assert_eq!(super::parse_size("R16"), None);
    }
}
