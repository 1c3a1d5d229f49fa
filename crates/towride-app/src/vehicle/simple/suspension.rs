//! A compact file's spring and damping of a corner: the rate at the wheel from a ride
//! frequency in series with the tyre, an air spring's gas from the defaults, the damping
//! from a fraction of critical on the ride rate.

use super::corner::AxleSec;
use super::{at, Ctx, Kind};
use crate::vehicle::air::AirSpec;
use crate::vehicle::trailing_arm_axle::{Spring, SpringKind, WheelDamping};
use towride_mbs::input::{InputError, Seg};
use towride_mbs::path;

/// The spring and damping of an axle at `p`: corner load `load` [N], unsprung mass
/// `mu` [kg], tyre rate `cz` [N/m].
pub(super) fn suspension(
    ctx: &Ctx,
    a: &AxleSec,
    p: &[Seg],
    load: f64,
    mu: f64,
    cz: f64,
) -> Result<(Spring, WheelDamping), InputError> {
    let name = towride_mbs::input::path_string(p);
    let sp = at(p, "spring");
    let s = &a.spring;
    let sprung = load / ctx.g - mu;
    if sprung <= 0.0 {
        return Err(ctx.src.error(
            &at(p, "unsprung_kg"),
            format!(
                "{mu} kg is more than the corner's static load ({:.1} kg)",
                load / ctx.g
            ),
        ));
    }
    // Ride rate: the wheel rate in series with the tyre, on the corner's sprung mass.
    let wheel_rate = match (s.wheel_rate_n_m, s.ride_frequency_hz) {
        (Some(k), None) => Some(ctx.src.positive(&at(&sp, "wheel_rate_n_m"), k)?),
        (None, Some(f)) => {
            let f = ctx.src.positive(&at(&sp, "ride_frequency_hz"), f)?;
            let ride = sprung * (2.0 * std::f64::consts::PI * f).powi(2);
            if ride >= cz {
                return Err(ctx.src.error(
                    &at(&sp, "ride_frequency_hz"),
                    format!(
                        "{f} Hz needs a ride rate of {ride:.0} N/m, above the tyre's {cz:.0} N/m"
                    ),
                ));
            }
            let k = ride * cz / (cz - ride);
            ctx.note(&format!("{name}.spring.wheel_rate_n_m"), k, "N/m", Kind::Derived, format!(
                "ride frequency {f} Hz on {sprung:.1} kg sprung per corner, in series with the tyre's {cz:.0} N/m"
            ));
            Some(k)
        }
        (Some(_), Some(_)) => {
            return Err(ctx
                .src
                .error(&sp, "give wheel_rate_n_m or ride_frequency_hz, not both"))
        }
        (None, None) if s.kind == SpringKind::Coil => {
            return Err(ctx
                .src
                .error(&sp, "give wheel_rate_n_m or ride_frequency_hz"))
        }
        (None, None) => None,
    };
    let choice = match s.kind {
        SpringKind::Coil => {
            for (k, v) in [
                ("effective_area_m2", s.effective_area_m2),
                ("volume_m3", s.volume_m3),
                ("polytropic_exponent", s.polytropic_exponent),
            ] {
                if v.is_some() {
                    return Err(ctx.src.error(&at(&sp, k), "only an air spring has this"));
                }
            }
            Spring::Coil {
                wheel_rate_n_m: wheel_rate.unwrap_or(0.0),
            }
        }
        SpringKind::Air => {
            let area = s
                .effective_area_m2
                .ok_or_else(|| ctx.src.error(&sp, "an air spring needs effective_area_m2"))?;
            let area = ctx.src.positive(&at(&sp, "effective_area_m2"), area)?;
            let volume = match (s.volume_m3, wheel_rate) {
                (Some(v), None) => Some(ctx.src.positive(&at(&sp, "volume_m3"), v)?),
                (None, Some(_)) => None,
                (Some(_), Some(_)) => {
                    return Err(ctx.src.error(
                        &sp,
                        "an air spring's rate follows from its volume: give volume_m3 or the rate, not both",
                    ))
                }
                (None, None) => {
                    return Err(ctx.src.error(
                        &sp,
                        "give volume_m3, or wheel_rate_n_m or ride_frequency_hz",
                    ))
                }
            };
            let d = &ctx.defaults.d.air_spring;
            let (dn, pa) = (d.polytropic_exponent, d.atmosphere_pa);
            let exponent = match s.polytropic_exponent {
                Some(n) => ctx.src.positive(&at(&sp, "polytropic_exponent"), n)?,
                None => ctx.default(
                    &format!("{name}.spring.polytropic_exponent"),
                    dn,
                    "-",
                    "air_spring.polytropic_exponent",
                ),
            };
            ctx.default(
                &format!("{name}.spring.atmosphere_pa"),
                pa,
                "Pa",
                "air_spring.atmosphere_pa",
            );
            let table = &ctx.defaults.d.air_spring;
            Spring::Air(AirSpec {
                area_m2: area,
                volume_m3: volume,
                wheel_rate_n_m: wheel_rate,
                exponent,
                atmosphere_pa: pa,
                table_span: table.table_span,
                table_points: table.table_points,
                table_at: ctx.defaults.src.error(&path!["air_spring"], ""),
            })
        }
    };
    if let Some(d) = two_rates(ctx, a, p, &name)? {
        return Ok((choice, d));
    }
    // Damping at the wheel: given, or a fraction of critical on the ride rate.
    let ride_rate = |k: f64| k * cz / (k + cz);
    let damping = match (a.damping_n_s_m, a.damping_ratio) {
        (Some(c), None) => ctx.src.non_negative(&at(p, "damping_n_s_m"), c)?,
        (c, z) => {
            if c.is_some() {
                return Err(ctx.src.error(
                    &at(p, "damping_ratio"),
                    "give damping_n_s_m or damping_ratio, not both",
                ));
            }
            let zeta = match z {
                Some(z) => ctx.src.positive(&at(p, "damping_ratio"), z)?,
                None => {
                    let z = ctx.defaults.d.corner.damping_ratio;
                    ctx.default(
                        &format!("{name}.damping_ratio"),
                        z,
                        "-",
                        "corner.damping_ratio",
                    )
                }
            };
            // The air spring's rate is known from its volume only after the statics;
            // its ride rate at the design pressure is estimated with P = load - mu g.
            let k = match &choice {
                Spring::Coil { wheel_rate_n_m } => *wheel_rate_n_m,
                Spring::Air(a) => a.wheel_rate_n_m.unwrap_or_else(|| {
                    let (area, volume) = (a.area_m2, a.volume_m3.unwrap_or(f64::NAN));
                    let gauge = (load - mu * ctx.g) / area;
                    a.exponent * (gauge + a.atmosphere_pa) * area * area / volume
                }),
            };
            let c = 2.0 * zeta * (ride_rate(k) * sprung).sqrt();
            ctx.note(&format!("{name}.damping_n_s_m"), c, "N s/m", Kind::Derived, format!(
                "{zeta} of critical on the ride rate {:.0} N/m and {sprung:.1} kg sprung per corner",
                ride_rate(k)
            ));
            c
        }
    };
    Ok((choice, WheelDamping::linear(damping)))
}

/// Separate compression and rebound rates, when the axle gives them (both, and neither
/// `damping_n_s_m` nor `damping_ratio`); the transition from the defaults.
fn two_rates(
    ctx: &Ctx,
    a: &AxleSec,
    p: &[Seg],
    name: &str,
) -> Result<Option<WheelDamping>, InputError> {
    let (c, r) = match (a.damping_compression_n_s_m, a.damping_rebound_n_s_m) {
        (None, None) => return Ok(None),
        (Some(c), Some(r)) => (c, r),
        (Some(_), None) => {
            return Err(ctx.src.error(
                &at(p, "damping_compression_n_s_m"),
                "give damping_rebound_n_s_m with it",
            ))
        }
        (None, Some(_)) => {
            return Err(ctx.src.error(
                &at(p, "damping_rebound_n_s_m"),
                "give damping_compression_n_s_m with it",
            ))
        }
    };
    for (k, v) in [
        ("damping_n_s_m", a.damping_n_s_m),
        ("damping_ratio", a.damping_ratio),
    ] {
        if v.is_some() {
            return Err(ctx.src.error(
                &at(p, k),
                "give damping_n_s_m, damping_ratio or the compression and rebound rates, not two of them",
            ));
        }
    }
    let c = ctx
        .src
        .non_negative(&at(p, "damping_compression_n_s_m"), c)?;
    let r = ctx.src.non_negative(&at(p, "damping_rebound_n_s_m"), r)?;
    let dsrc = &ctx.defaults.src;
    let key = path!["corner", "damper_transition_m_s"];
    let w = ctx.defaults.d.corner.damper_transition_m_s.ok_or_else(|| {
        dsrc.error(
            &key,
            "a file giving compression and rebound rates needs this: the wheel velocity over which they blend",
        )
    })?;
    let w = dsrc.positive(&key, w)?;
    ctx.default(
        &format!("{name}.damper_transition_m_s"),
        w,
        "m/s",
        "corner.damper_transition_m_s",
    );
    Ok(Some(WheelDamping {
        compression_n_s_m: c,
        rebound_n_s_m: r,
        transition_m_s: w,
    }))
}
