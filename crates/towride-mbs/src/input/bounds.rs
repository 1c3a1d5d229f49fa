//! Plausibility bounds: one table of accepted ranges per physical or run quantity, used
//! by every reader (TOML property files as they are parsed, `.tir` values, CSV columns,
//! command-line values) and by the run pipeline's allocation limit.
//!
//! The readers keep their own checks of sign and meaning (a mass must be positive, a
//! Poisson's ratio below 0.5); a bound refuses what no vehicle, road or test rig has: a
//! 1e300 m arm, a Young's modulus of 1e300 Pa, a sample rate that would fill the memory.
//! A value is accepted when it is 0 or its magnitude lies in `[min, max]`. A TOML key is
//! matched by its name: the entry with the longest matching ending (`stiffness_n_m` by
//! `_n_m`, `inertia_kg_m2` by `_kg_m2`, not `_m2`); a key no entry names meets the
//! catch-all `number`. `docs/reliability.md` shows the table ([`markdown_table`]).

use super::FieldError;

/// The accepted range of one quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// What is bounded, in words.
    pub quantity: &'static str,
    /// Key endings it covers (`_kg`), or whole key names (`rtol`, `.tir` `FNOMIN`),
    /// matched as the name itself or its ending after an underscore.
    pub keys: &'static [&'static str],
    /// Unit of `min` and `max`.
    pub unit: &'static str,
    /// Smallest accepted magnitude other than 0.
    pub min: f64,
    /// Largest accepted magnitude.
    pub max: f64,
    /// Why these limits.
    pub why: &'static str,
}

const fn b(
    quantity: &'static str,
    keys: &'static [&'static str],
    unit: &'static str,
    min: f64,
    max: f64,
    why: &'static str,
) -> Bound {
    Bound {
        quantity,
        keys,
        unit,
        min,
        max,
        why,
    }
}

/// Smallest non-zero magnitude of the quantities without a physical floor: far below
/// anything the models read, so that `1e-300` (a typo, or a unit lost) is refused instead
/// of turning a stiffness or a load into a singular rate equation.
pub const TINY: f64 = 1.0e-30;

/// The table. Edit here only; the docs are generated from it (a test compares).
pub const BOUNDS: &[Bound] = &[
    b(
        "length, position",
        &["_m"],
        "m",
        TINY,
        1.0e4,
        "roads up to 10 km; every part of a car or trailer lies within metres",
    ),
    b(
        "tyre size",
        &["UNLOADED_RADIUS", "WIDTH", "RIM_RADIUS", "RIM_WIDTH"],
        "m",
        0.01,
        10.0,
        "a castor wheel to an earth-mover's tyre",
    ),
    b(
        "tyre overall stiffness",
        &[
            "VERTICAL_STIFFNESS",
            "LONGITUDINAL_STIFFNESS",
            "LATERAL_STIFFNESS",
        ],
        "N/m",
        1.0e3,
        1.0e8,
        "a soft bicycle tyre is about 1e4 N/m, a car's 2e5, a truck's 1e6; the rate \
         equations go singular near 0",
    ),
    b(
        "tyre nominal load",
        &["FNOMIN"],
        "N",
        10.0,
        1.0e6,
        "the load the Magic Formula is normalised by: a few kN for a car",
    ),
    b(
        "tyre reference speed",
        &["LONGVL"],
        "m/s",
        0.1,
        150.0,
        "the speed the tyre was measured at (usually 16.7 m/s)",
    ),
    b(
        "contact blend width",
        &["TOWRIDE_CONTACT_BLEND"],
        "m",
        1.0e-7,
        0.01,
        "a smoothing width, far below the tyre deflection (mm)",
    ),
    b(
        "mass",
        &["_kg", "MASS", "BELT_MASS"],
        "kg",
        1.0e-6,
        1.0e5,
        "a gram-scale sensor to a 100 t vehicle",
    ),
    b(
        "moment of inertia",
        &["_kg_m2", "IXX", "IYY", "IZZ", "BELT_IXX", "BELT_IYY"],
        "kg m^2",
        1.0e-12,
        1.0e6,
        "point masses carry 1e-9 kg m^2; a loaded truck about 1e5",
    ),
    b(
        "density",
        &["_kg_m3"],
        "kg/m^3",
        1.0,
        1.0e5,
        "foams to the densest metals",
    ),
    b(
        "Young's modulus",
        &["_pa"],
        "Pa",
        1.0e3,
        1.0e13,
        "rubber (1e6) to diamond (1.2e12)",
    ),
    b(
        "section area",
        &["_m2"],
        "m^2",
        1.0e-12,
        10.0,
        "a wire to a bridge girder",
    ),
    b(
        "second moment of area, torsion constant",
        &["_m4"],
        "m^4",
        1.0e-20,
        10.0,
        "as for areas",
    ),
    b(
        "translational stiffness",
        &["_n_m"],
        "N/m",
        TINY,
        1.0e12,
        "the stress test's stiffest bushing is 1e9 N/m; 1e12 is a rigid weld",
    ),
    b(
        "rotational stiffness",
        &["_n_m_rad"],
        "N m/rad",
        TINY,
        1.0e12,
        "as for translational stiffness",
    ),
    b(
        "translational damping",
        &["_n_s_m", "VERTICAL_DAMPING"],
        "N s/m",
        TINY,
        1.0e9,
        "dampers are 1e3..1e5 N s/m",
    ),
    b(
        "rotational damping",
        &["_n_m_s_rad"],
        "N m s/rad",
        TINY,
        1.0e9,
        "as for translational damping",
    ),
    b(
        "controller gain",
        &["_n_m_per_m", "_n_m_s_per_m"],
        "N m per m, N m s per m",
        TINY,
        1.0e9,
        "speed-holding gains of a few kN m per m/s",
    ),
    b(
        "force",
        &["_n"],
        "N",
        TINY,
        1.0e7,
        "a 100 t vehicle's weight is 1e6 N",
    ),
    b(
        "torque",
        &["torque_n_m"],
        "N m",
        TINY,
        1.0e6,
        "engines give 1e2..1e4 N m at the wheels",
    ),
    b(
        "speed",
        &["_m_s"],
        "m/s",
        TINY,
        150.0,
        "road vehicles, with room (540 km/h)",
    ),
    b(
        "speed",
        &["_km_h", "_kmh"],
        "km/h",
        0.01,
        540.0,
        "a plan's run lasts travel / speed, so a speed must not be vanishingly small",
    ),
    b(
        "angular velocity",
        &["_rad_s"],
        "rad/s",
        TINY,
        1.0e4,
        "a wheel at 540 km/h turns at 500 rad/s",
    ),
    b(
        "acceleration",
        &["_m_s2", "_mps2", "GRAVITY"],
        "m/s^2",
        TINY,
        1.0e4,
        "1000 g",
    ),
    b(
        "time, duration",
        &["_s"],
        "s",
        TINY,
        3600.0,
        "a run of one hour of simulated time at most",
    ),
    b(
        "output interval",
        &["dt_s"],
        "s",
        1.0e-7,
        10.0,
        "sets the number of samples written",
    ),
    b(
        "frequency, sample rate",
        &["_hz", "FREQ_LONG", "FREQ_WINDUP", "FREQ_TWIST"],
        "Hz",
        1.0e-6,
        1.0e6,
        "the sample rate sets the rows kept in memory",
    ),
    b("angle", &["_deg"], "deg", 0.0, 360.0, "one turn"),
    b(
        "angle",
        &["_rad", "rad", "phi", "theta"],
        "rad",
        TINY,
        100.0,
        "a few turns",
    ),
    b("percentage", &["_pct"], "%", 0.0, 100.0, "a share"),
    b(
        "relative tolerance",
        &["rtol"],
        "-",
        1.0e-14,
        1.0,
        "below 1e-14 is beyond double precision",
    ),
    b(
        "absolute tolerance",
        &["atol"],
        "unit of the unknown",
        1.0e-20,
        1.0e3,
        "as for rtol",
    ),
    b(
        "share, ratio",
        &["min_energy_share", "poissons_ratio"],
        "-",
        TINY,
        1.0,
        "a fraction",
    ),
    b(
        "direction component",
        &["_axis", "local_y"],
        "-",
        TINY,
        1.0e6,
        "normalised when read",
    ),
    b(
        "element divisions per member",
        &["divisions"],
        "-",
        1.0,
        1000.0,
        "the finite-element matrices grow with the square of the nodes",
    ),
    b(
        "number of modes",
        &["fixed_interface_modes", "modes"],
        "-",
        1.0,
        1000.0,
        "Craig-Bampton keeps tens of modes",
    ),
    b(
        "filter order",
        &["order"],
        "-",
        1.0,
        20.0,
        "Butterworth filters of order 2..8",
    ),
    b(
        "random seed",
        &["seed"],
        "-",
        TINY,
        1.8446744073709552e19,
        "any 64-bit number",
    ),
    b(
        "car or van mass (`simple` file)",
        &["total_kg"],
        "kg",
        300.0,
        3500.0,
        "the `simple` template's cars and vans: EU categories M1 and N1 end at 3.5 t (Regulation (EU) 2018/858, Annex I)",
    ),
    b(
        "centre-of-mass height (`simple` file)",
        &["cg_height_m"],
        "m",
        0.2,
        1.5,
        "cars and vans: with their tracks (1.2-1.8 m) a static stability factor t/2h of 1.0-1.5 (NHTSA, Rollover Resistance notice, ch. V) puts h near 0.45-0.9 m; the reader checks t/2h too",
    ),
    b(
        "wheelbase (`simple` file)",
        &["wheelbase_m"],
        "m",
        1.5,
        5.0,
        "series cars and vans: 1.87 m (Smart ForTwo) to 4.33 m (long-wheelbase Sprinter)",
    ),
    b(
        "track (`simple` file)",
        &["front_track_m", "rear_track_m"],
        "m",
        0.8,
        2.55,
        "no road vehicle is wider than 2.55 m (Directive 96/53/EC, Annex I)",
    ),
    b(
        "number (any other key)",
        &[],
        "as the key says",
        TINY,
        1.0e12,
        "nothing the models read is larger; 1e300 and 1e-300 are typos",
    ),
];

/// The catch-all bound of keys no entry names.
pub fn any_number() -> &'static Bound {
    BOUNDS.last().expect("the table ends with the catch-all")
}

/// The bound of a key: the entry whose ending matches the most characters.
pub fn for_key(key: &str) -> &'static Bound {
    let mut best: Option<(usize, &'static Bound)> = None;
    for b in BOUNDS {
        for k in b.keys {
            let hit = if k.starts_with('_') {
                key.ends_with(k)
            } else {
                key == *k || key.strip_suffix(k).is_some_and(|p| p.ends_with('_'))
            };
            if hit && best.is_none_or(|(n, _)| k.len() > n) {
                best = Some((k.len(), b));
            }
        }
    }
    best.map_or(any_number(), |(_, b)| b)
}

impl Bound {
    /// The accepted range in words.
    pub fn range(&self) -> String {
        if self.min > 0.0 {
            format!(
                "0 or |value| in [{:e}, {:e}] {}",
                self.min, self.max, self.unit
            )
        } else {
            format!("|value| <= {:e} {}", self.max, self.unit)
        }
    }

    /// True when `v` is finite and 0 or its magnitude lies in `[min, max]`.
    pub fn accepts(&self, v: f64) -> bool {
        v.is_finite() && (v == 0.0 || (v.abs() >= self.min && v.abs() <= self.max))
    }

    /// `v`, or an error saying the accepted range.
    pub fn check(&self, v: f64) -> Result<f64, FieldError> {
        if self.accepts(v) {
            Ok(v)
        } else {
            Err(FieldError::here(self.message(v)))
        }
    }

    /// The message for a refused `v`.
    pub fn message(&self, v: f64) -> String {
        if !v.is_finite() {
            return format!("must be finite, got {v}");
        }
        format!(
            "{v:e} lies outside the accepted range for {}: {} (docs/reliability.md)",
            self.quantity,
            self.range()
        )
    }
}

/// The bound of one command-line option: `value`, or an error naming the option and the
/// accepted range (file "command line", field the option).
pub fn argument(option: &str, bound: &Bound, value: f64) -> Result<f64, super::InputError> {
    bound.check(value).map_err(|e| super::InputError {
        file: "command line".into(),
        line: None,
        column: None,
        field: option.to_string(),
        message: e.message,
        kind: Default::default(),
    })
}

/// The bound of `key` (see [`for_key`]) on the command line.
pub fn argument_as(option: &str, key: &str, value: f64) -> Result<f64, super::InputError> {
    argument(option, for_key(key), value)
}

/// Limits on what one run may hold in memory: the sampled rows and their bytes,
/// estimated before the run starts.
pub mod budget {
    /// Most output rows (samples) of one run.
    pub const MAX_ROWS: f64 = 2.0e7;
    /// Most bytes of sampled output of one run (1 GiB).
    pub const MAX_BYTES: f64 = GIB;

    /// A run whose samples would not fit the limits.
    #[derive(Clone, Debug, PartialEq, thiserror::Error)]
    pub enum BudgetError {
        /// More samples than [`MAX_ROWS`].
        #[error(
            "{duration:e} s at {rate:e} Hz would keep {rows:.3e} samples, above the limit \
             of {max:e} (shorten the run or lower the sample rate)",
            max = MAX_ROWS
        )]
        TooManyRows {
            /// Duration of the run [s].
            duration: f64,
            /// Sample rate [Hz].
            rate: f64,
            /// Samples it would keep.
            rows: f64,
        },
        /// More bytes than [`MAX_BYTES`].
        #[error(
            "{rows:.3e} samples of {columns} channels would take {gib:.1} GiB, above the \
             limit of {max:.0} GiB (lower the sample rate or the outputs)",
            gib = .bytes / MAX_BYTES,
            max = MAX_BYTES / GIB
        )]
        TooManyBytes {
            /// Samples it would keep.
            rows: f64,
            /// Values per sample.
            columns: usize,
            /// Bytes they would take.
            bytes: f64,
        },
    }

    const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

    /// Rows and bytes of a run of `duration` [s] sampled at `rate` [Hz] with `columns`
    /// values per row, or why it is refused.
    pub fn check(duration: f64, rate: f64, columns: usize) -> Result<(f64, f64), BudgetError> {
        let rows = (duration * rate).round() + 1.0;
        // A row is its values plus the time and the Vec's own header.
        let bytes = rows * (8.0 * (columns as f64 + 1.0) + 24.0);
        if !rows.is_finite() || rows > MAX_ROWS {
            return Err(BudgetError::TooManyRows {
                duration,
                rate,
                rows,
            });
        }
        if bytes > MAX_BYTES {
            return Err(BudgetError::TooManyBytes {
                rows,
                columns,
                bytes,
            });
        }
        Ok((rows, bytes))
    }
}

/// The table as Markdown (for `docs/reliability.md`).
pub fn markdown_table() -> String {
    let mut s = String::from(
        "| quantity | keys (endings or names) | unit | smallest non-zero magnitude | largest magnitude | why |\n| --- | --- | --- | --- | --- | --- |\n",
    );
    for b in BOUNDS {
        let keys = if b.keys.is_empty() {
            "any other".to_string()
        } else {
            b.keys
                .iter()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let min = if b.min > 0.0 {
            format!("{:e}", b.min)
        } else {
            "-".into()
        };
        s.push_str(&format!(
            "| {} | {keys} | {} | {min} | {:e} | {} |\n",
            b.quantity, b.unit, b.max, b.why
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn longest_ending_wins() {
        assert_eq!(for_key("stiffness_n_m").quantity, "translational stiffness");
        assert_eq!(for_key("max_torque_n_m").quantity, "torque");
        assert_eq!(for_key("inertia_kg_m2").quantity, "moment of inertia");
        assert_eq!(for_key("area_m2").quantity, "section area");
        assert_eq!(for_key("position_m").quantity, "length, position");
        assert_eq!(for_key("dt_s").quantity, "output interval");
        assert_eq!(for_key("end_time_s").quantity, "time, duration");
        assert_eq!(for_key("damping_n_m_s_rad").quantity, "rotational damping");
        assert_eq!(for_key("gain").quantity, "number (any other key)");
        assert_eq!(for_key("BELT_MASS").quantity, "mass");
        assert_eq!(for_key("x_axis").quantity, "direction component");
    }

    #[test]
    fn zero_and_range() {
        let m = for_key("mass_kg");
        assert!(m.accepts(0.0) && m.accepts(1200.0));
        assert!(!m.accepts(1e300) && !m.accepts(1e-300) && !m.accepts(f64::NAN));
        assert!(budget::check(3.0, 1000.0, 40).is_ok());
        assert!(budget::check(3600.0, 1e6, 40).is_err());
    }
}
